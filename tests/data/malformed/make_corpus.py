#!/usr/bin/env python3
"""Writes the malformed-mesh corpus and its MANIFEST (tests/test_mesh_io.c reads both).

Each entry is (file name, expected pgt_result_name, bytes). Run from anywhere:
    python3 tests/data/malformed/make_corpus.py
The files are committed; this script documents how the binary ones were made."""
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
OFF_HEAD = "OFF\n3 1 0\n"
OFF_VERTS = "0 0 0\n1 0 0\n0 1 0\n"


def off(face="3 0 1 2\n", verts=OFF_VERTS, head=OFF_HEAD):
    return head + verts + face


def ply_ascii(x_type="float", idx="property list uchar int vertex_indices\n", extra_face="",
              vertex_count=3, face_count=1, fmt="format ascii 1.0\n"):
    return ("ply\n" + fmt + "comment pgt malformed corpus\n"
            "element vertex %d\nproperty %s x\nproperty %s y\nproperty %s z\n"
            "element face %d\n%s%send_header\n" % (vertex_count, x_type, x_type, x_type,
                                                   face_count, idx, extra_face))


PLY_A_VERTS = "0 0 0\n1 0 0\n0 1 0\n"


def ply_bin_header(vertex_count=3, face_count=1, x_type="float", count_type="uchar",
                   index_type="int", fmt="binary_little_endian"):
    return ("ply\nformat %s 1.0\nelement vertex %d\nproperty %s x\nproperty %s y\n"
            "property %s z\nelement face %d\nproperty list %s %s vertex_indices\nend_header\n"
            % (fmt, vertex_count, x_type, x_type, x_type, face_count, count_type,
               index_type)).encode()


def verts_f32(vs=((0, 0, 0), (1, 0, 0), (0, 1, 0)), fmt="<3f"):
    return b"".join(struct.pack(fmt, *v) for v in vs)


def face(idx, count_fmt="<B", index_fmt="<i"):
    return struct.pack(count_fmt, len(idx)) + b"".join(struct.pack(index_fmt, i) for i in idx)


GOOD_FACE = face((0, 1, 2))
rng = random.Random(20240611)
# Garbage that starts with a non-text byte, so no reader mistakes it for a statement or header.
GARBAGE = bytes([0x89, 0x01]) + bytes(rng.randrange(256) for _ in range(510))

CASES = [
    # ---- OBJ ----
    ("obj_empty.obj", "empty", ""),
    ("obj_only_comments.obj", "empty", "# just a comment\n\n   # another one\n"),
    ("obj_no_faces.obj", "empty", OBJ),
    ("obj_zero_index.obj", "index_range", OBJ + "f 0 1 2\n"),
    ("obj_index_out_of_range.obj", "index_range", OBJ + "f 1 2 4\n"),
    ("obj_negative_before_start.obj", "index_range", OBJ + "f -1 -2 -4\n"),
    ("obj_negative_before_defined.obj", "index_range", "v 0 0 0\nf -1 -2 -3\n" + OBJ),
    ("obj_index_overflow.obj", "index_range", OBJ + "f 1 2 99999999999999999999999\n"),
    ("obj_nan.obj", "not_finite", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_inf.obj", "not_finite", "v 0 0 0\nv 1 -inf 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_overflow_1e999.obj", "not_finite", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_float_overflow_1e39.obj", "not_finite", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_nan_uv.obj", "not_finite", OBJ + "vt 0 0\nvt nan 0\nvt 0 1\nf 1/1 2/2 3/3\n"),
    ("obj_face_two_vertices.obj", "parse", OBJ + "f 1 2\n"),
    ("obj_bad_number.obj", "parse", "v 0 0 abc\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_vertex_two_coords.obj", "parse", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_unknown_statement.obj", "parse", OBJ + "foo 1 2 3\nf 1 2 3\n"),
    ("obj_line_element.obj", "unsupported", OBJ + "l 1 2\nf 1 2 3\n"),
    ("obj_bad_face_token.obj", "parse", OBJ + "f 1/1/1/1 2/2/2/2 3/3/3/3\n"),
    ("obj_face_trailing_slash.obj", "parse", OBJ + "vt 0 0\nf 1/ 2/ 3/\n"),
    ("obj_face_not_integer.obj", "parse", OBJ + "f 1 2 3.0\n"),
    ("obj_vt_index_range.obj", "index_range", OBJ + "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/5\n"),
    ("obj_vn_index_range.obj", "index_range", OBJ + "vn 0 0 1\nf 1//1 2//1 3//2\n"),
    ("obj_nul_byte.obj", "parse", "v 0 0 0\x00\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("obj_binary_garbage.obj", "parse", GARBAGE),
    # ---- OFF ----
    ("off_empty.off", "empty", ""),
    ("off_only_comments.off", "empty", "# nothing here\n#\n\n"),
    ("off_no_faces.off", "empty", "OFF\n3 0 0\n" + OFF_VERTS),
    ("off_bad_header.off", "parse", off(head="OFX\n3 1 0\n")),
    ("off_coff.off", "unsupported", "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n"
                                    "0 1 0 1 1 1 1\n3 0 1 2\n"),
    ("off_binary.off", "unsupported", "OFF BINARY\n"),
    ("off_bad_counts.off", "parse", off(head="OFF\nthree 1 0\n")),
    ("off_counts_one_value.off", "parse", off(head="OFF\n3\n")),
    ("off_counts_missing.off", "truncated", "OFF\n"),
    ("off_huge_counts.off", "limit", "OFF\n4000000000 4000000000 0\n"),
    ("off_counts_exceed_file.off", "truncated", "OFF\n100000000 100000000 0\n0 0 0\n"),
    ("off_truncated_vertices.off", "truncated", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
    ("off_truncated_mid_line.off", "truncated", off(face="3 0 1")),
    ("off_fewer_vertex_lines.off", "truncated", off(head="OFF\n4 1 0\n")),
    ("off_extra_data.off", "count_mismatch", off() + "3 0 2 1\n"),
    ("off_vertex_count_too_small.off", "count_mismatch", off(head="OFF\n2 1 0\n")),
    ("off_index_out_of_range.off", "index_range", off(face="3 0 1 3\n")),
    ("off_negative_index.off", "index_range", off(face="3 0 -1 2\n")),
    ("off_nan.off", "not_finite", off(verts="nan 0 0\n1 0 0\n0 1 0\n")),
    ("off_inf.off", "not_finite", off(verts="0 0 0\n1 -inf 0\n0 1 0\n")),
    ("off_overflow_1e999.off", "not_finite", off(verts="0 0 0\n1 0 0\n0 1 1e999\n")),
    ("off_face_two_vertices.off", "parse", off(face="2 0 1\n")),
    ("off_face_short_line.off", "parse", off(face="4 0 1 2\n")),
    ("off_face_too_many_values.off", "parse", off(face="3 0 1 2 1 1 1 1 1\n")),
    ("off_vertex_bad_number.off", "parse", off(verts="0 0 0\n1 x 0\n0 1 0\n")),
    ("off_vertex_four_values.off", "parse", off(verts="0 0 0\n1 0 0 0\n0 1 0\n")),
    ("off_binary_garbage.off", "parse", GARBAGE),
    # ---- PLY header (ascii) ----
    ("ply_empty.ply", "empty", ""),
    ("ply_bad_magic.ply", "parse", "plx\n" + ply_ascii()[4:] + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_bad_format.ply", "parse", ply_ascii(fmt="format foo 1.0\n") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_version_2.ply", "unsupported",
     ply_ascii(fmt="format ascii 2.0\n") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_big_endian.ply", "unsupported",
     ply_bin_header(fmt="binary_big_endian") + verts_f32(fmt=">3f") + face((0, 1, 2), ">B", ">i")),
    ("ply_bad_keyword.ply", "parse",
     ply_ascii().replace("element vertex", "elemnt vertex") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_bad_type.ply", "parse",
     ply_ascii().replace("property float x", "property flaot x") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_property_before_element.ply", "parse",
     "ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
    ("ply_missing_vertex_indices.ply", "parse",
     ply_ascii(idx="property list uchar int verts\n") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_indices_not_list.ply", "parse",
     ply_ascii(idx="property int vertex_indices\n") + PLY_A_VERTS + "0\n"),
    ("ply_missing_end_header.ply", "truncated", ply_ascii().replace("end_header\n", "")),
    ("ply_huge_count.ply", "limit",
     ply_ascii(vertex_count=3000000000) + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_count_exceeds_file.ply", "truncated",
     ply_ascii(vertex_count=100000000) + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_int_coordinates.ply", "unsupported", ply_ascii(x_type="int") + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_float_group.ply", "parse",
     ply_ascii(extra_face="property float group\n") + PLY_A_VERTS + "3 0 1 2 1.5\n"),
    ("ply_no_face_element.ply", "empty",
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
     "property float z\nend_header\n" + PLY_A_VERTS),
    # ---- PLY ascii data ----
    ("ply_ascii_no_faces.ply", "empty", ply_ascii(face_count=0) + PLY_A_VERTS),
    ("ply_ascii_truncated.ply", "truncated", ply_ascii(face_count=2) + PLY_A_VERTS + "3 0 1 2\n"),
    ("ply_ascii_mid_line.ply", "truncated", ply_ascii() + PLY_A_VERTS + "3 0 1"),
    ("ply_ascii_extra_data.ply", "count_mismatch", ply_ascii() + PLY_A_VERTS + "3 0 1 2\n3 0 2 1\n"),
    ("ply_ascii_index_range.ply", "index_range", ply_ascii() + PLY_A_VERTS + "3 0 1 3\n"),
    ("ply_ascii_negative_index.ply", "index_range", ply_ascii() + PLY_A_VERTS + "3 0 -1 2\n"),
    ("ply_ascii_nan.ply", "not_finite", ply_ascii() + "nan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
    ("ply_ascii_1e999.ply", "not_finite",
     ply_ascii(x_type="double") + "0 0 0\n1 0 1e999\n0 1 0\n3 0 1 2\n"),
    ("ply_ascii_face_two_vertices.ply", "parse", ply_ascii() + PLY_A_VERTS + "2 0 1\n"),
    ("ply_ascii_list_count_past_line.ply", "parse", ply_ascii() + PLY_A_VERTS + "255 0 1 2\n"),
    ("ply_ascii_bad_number.ply", "parse", ply_ascii() + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n"),
    ("ply_ascii_extra_value.ply", "parse", ply_ascii() + PLY_A_VERTS + "3 0 1 2 7\n"),
    ("ply_ascii_texcoord_count.ply", "count_mismatch",
     ply_ascii(extra_face="property list uchar float texcoord\n") + PLY_A_VERTS +
     "3 0 1 2 4 0 0 1 0\n"),
    # ---- PLY binary data ----
    ("plyb_truncated_vertex.ply", "truncated", ply_bin_header() + verts_f32()[:20]),
    ("plyb_truncated_face.ply", "truncated", ply_bin_header() + verts_f32() + GOOD_FACE[:7]),
    ("plyb_list_count_255.ply", "truncated",
     ply_bin_header() + verts_f32() + struct.pack("<B3i", 255, 0, 1, 2)),
    ("plyb_huge_list_count.ply", "truncated",
     ply_bin_header(count_type="uint") + verts_f32() + struct.pack("<I3i", 4000000000, 0, 1, 2)),
    ("plyb_index_range.ply", "index_range", ply_bin_header() + verts_f32() + face((0, 1, 3))),
    ("plyb_negative_index.ply", "index_range", ply_bin_header() + verts_f32() + face((0, -1, 2))),
    ("plyb_uint_index_range.ply", "index_range",
     ply_bin_header(index_type="uint") + verts_f32() + face((0, 1, 4294967295), index_fmt="<I")),
    ("plyb_nan.ply", "not_finite",
     ply_bin_header() + verts_f32(((0, 0, 0), (1, float("nan"), 0), (0, 1, 0))) + GOOD_FACE),
    ("plyb_inf.ply", "not_finite",
     ply_bin_header() + verts_f32(((0, 0, 0), (1, 0, 0), (0, 1, float("-inf")))) + GOOD_FACE),
    ("plyb_double_overflow.ply", "not_finite",
     ply_bin_header(x_type="double") + verts_f32(((0, 0, 0), (1, 0, 1e300), (0, 1, 0)), "<3d")
     + GOOD_FACE),
    ("plyb_trailing_bytes.ply", "count_mismatch",
     ply_bin_header() + verts_f32() + GOOD_FACE + b"\n\x00\x00\x00\x00"),
    ("plyb_face_two_vertices.ply", "parse",
     ply_bin_header() + verts_f32() + face((0, 1))),
    ("plyb_negative_list_count.ply", "parse",
     ply_bin_header(count_type="char") + verts_f32() + struct.pack("<b", -1)),
    ("plyb_garbage.ply", "parse", GARBAGE),
    ("plyb_garbage_header.ply", "parse", b"ply\n" + GARBAGE),
]


def main():
    names = set()
    with open(os.path.join(HERE, "MANIFEST"), "w") as manifest:
        for name, code, content in CASES:
            assert name not in names, name
            names.add(name)
            data = content.encode() if isinstance(content, str) else content
            with open(os.path.join(HERE, name), "wb") as f:
                f.write(data)
            manifest.write("%s %s\n" % (name, code))


if __name__ == "__main__":
    main()
