/* pgt: mesh file reading and writing (OBJ, OFF, PLY).
 *
 * Readers validate everything: a malformed file returns a pgt_result code and an error message
 * naming the file and the line (text formats) or byte offset (binary PLY); nothing aborts, and
 * declared counts are checked against the file size before anything is allocated. A UTF-8
 * byte order mark before an OBJ or OFF (Windows editors write one) is read past; before a PLY's
 * "ply" magic it is an error that names it.
 * Writers write to a temporary file beside the target and rename it into place, so an existing
 * file is never left half-written. */
#ifndef PGT_MESH_IO_H
#define PGT_MESH_IO_H

#include <stddef.h>

#include "mesh.h"

/* Bytes read at most from an input that is not a regular file (a pipe, a device): a regular
 * file is read in one piece of its size; a stream's size is known only at its end, and one that
 * does not end (/dev/zero) grew the buffer until memory ran out. 1 GiB is a mesh of some 20
 * million triangles as OBJ text. */
#define PGT_MESH_MAX_STREAM_BYTES (1ull << 30)

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pgt_mesh_format {
    PGT_FORMAT_AUTO = 0, /* from the file name's extension (.obj .off .ply, any case) */
    PGT_FORMAT_OBJ = 1,
    PGT_FORMAT_OFF = 2,
    PGT_FORMAT_PLY = 3  /* reading: ascii and binary_little_endian; writing: binary_little_endian */
} pgt_mesh_format;

/* Where the triangles and vertices of a mesh read from a file come from: the face record (OBJ
 * `f` line, OFF face line, PLY face element) each triangle was fan-triangulated from and each
 * vertex's record (OBJ `v` line, OFF vertex line, PLY vertex element), so that an error found
 * later about a face (a non-manifold edge or vertex, a degenerate face) or a vertex (a
 * coordinate beyond a limit) can name the place in the file. */
typedef struct pgt_mesh_origin {
    uint64_t *face;        /* face_count entries: the record's 1-based line, or in binary PLY
                              data the byte offset where the record starts */
    uint32_t face_count;   /* the mesh's face_count */
    int offsets;           /* nonzero: face[] and vertex[] hold byte offsets (binary PLY) */
    uint64_t *vertex;      /* vertex_count entries, as face[] */
    uint32_t vertex_count; /* the mesh's vertex_count */
    /* Where each corner's UV comes from (pgt_mesh_origin_uv_where): an OBJ `vt` line (uv[] has
     * one line per vt record, uv_index[] 3 per face: the corner's vt record), a PLY vertex's
     * `u v` (uv_of_vertex: its vertex's record), or else the face's record (a PLY texcoord
     * list). */
    uint64_t *uv;       /* uv_count entries, or NULL */
    uint32_t uv_count;  /* the OBJ's vt records */
    uint32_t *uv_index; /* 3 * face_count entries when uv is not NULL */
    int uv_of_vertex;   /* nonzero: a corner's UV is its vertex's (PLY u v) */
} pgt_mesh_origin;

typedef struct pgt_mesh_read_options {
    pgt_mesh_format format;  /* 0: from the extension */
    int quiet;               /* nonzero: no notes on stderr (e.g. "fan-triangulated N polygons") */
    pgt_mesh_origin *origin; /* not NULL: filled on success (free with pgt_mesh_origin_destroy),
                                zeroed on failure */
} pgt_mesh_read_options;

/* Frees the arrays and zeroes the struct; NULL or a zeroed origin is a no-op. */
void pgt_mesh_origin_destroy(pgt_mesh_origin *origin);

/* Frees the faces' and UVs' places and keeps the vertices': for a caller that has checked the
 * faces and holds the origin through a long build only to name a vertex (atlas, ivy). Face and
 * UV places are then named by the file name alone. NULL is a no-op. */
void pgt_mesh_origin_keep_vertices(pgt_mesh_origin *origin);

/* Writes where face `face` comes from as the readers' messages name places: "NAME:LINE" or
 * "NAME: byte offset N", or NAME alone when origin is NULL or does not cover the face. Returns
 * buf. */
const char *pgt_mesh_origin_where(const pgt_mesh_origin *origin, const char *name, uint32_t face,
                                  char *buf, size_t size);

/* pgt_mesh_origin_where of vertex `vertex`'s record. */
const char *pgt_mesh_origin_vertex_where(const pgt_mesh_origin *origin, const char *name,
                                         uint32_t vertex, char *buf, size_t size);

/* pgt_mesh_origin_where of the record corner `corner`'s UV was read from (the corner of face
 * corner / 3 at corner % 3 in mesh, the mesh the origin was read with). */
const char *pgt_mesh_origin_uv_where(const pgt_mesh_origin *origin, const pgt_mesh *mesh,
                                     const char *name, uint32_t corner, char *buf, size_t size);

typedef struct pgt_mesh_write_options {
    pgt_mesh_format format; /* 0: from the extension */
    int precise;            /* OFF/OBJ: 17 significant digits instead of 9 (float32 round-trips at 9) */
} pgt_mesh_write_options;

/* Reads a mesh. OBJ: v, vt, vn; faces v, v/vt, v//vn, v/vt/vn; negative (relative) indices;
 * polygons fan-triangulated with a note on stderr; o g s usemtl mtllib ignored. OFF: "OFF"
 * header, optional comments, polygons fan-triangulated. PLY: vertex x y z (float or double),
 * face vertex_indices (or vertex_index) list, optional int face property `group` stored as the
 * label, other properties skipped; optional per-face `texcoord` list of 6 floats as wedge UVs,
 * else per-vertex texture coordinates (`u v`, `s t` or `texture_u texture_v`, as pgt's soups
 * write them) copied to each corner. opts may be NULL. On failure *out is zeroed.
 *
 * Details of what is accepted:
 * - Every format: a polygon (v0 .. vn-1) becomes the fan (v0, vi, vi+1), i = 1 .. n-2, its UVs
 *   and label following the corners; one line "note: FILE: fan-triangulated N polygons" goes
 *   to stderr per file unless opts->quiet. A face repeating a vertex is accepted (the adjacency
 *   module reports it). Positions and UVs are stored as float: a value that is NaN, infinite or
 *   beyond the float range (1e39, 1e999) is PGT_ERROR_NOT_FINITE. Lines may end in "\r\n".
 * - OBJ: only v vt vn f are read and o g s usemtl mtllib ignored. Any other statement is an
 *   error: PGT_ERROR_UNSUPPORTED when the OBJ specification defines it (l, p, vp, curv, surf,
 *   cstype, ...: dropping it silently would change the geometry) and PGT_ERROR_PARSE otherwise
 *   (which is also how binary garbage fails). '#' starts a comment anywhere on a line. `v` takes
 *   3 to 7 numbers (x y z, then w or vertex colours, ignored); `vt` 1 to 3 (v defaults to 0);
 *   `vn` 3, which may be nan (normals are not read). Positive indices may refer forward to
 *   vertices defined later in the file; negative ones count back from the last vertex read.
 *   UVs are kept only when every face has a vt on every corner; when only some do, they are
 *   dropped with one note on stderr ("N of M faces have no texture coordinates; UVs dropped").
 * - OFF: plain "OFF" only (COFF, NOFF, STOFF, 4OFF, nOFF and "OFF BINARY" are
 *   PGT_ERROR_UNSUPPORTED); the counts "V F [E]" may follow on the header line; '#' comments
 *   and blank lines anywhere; one vertex ("x y z") or face ("n i0 .. in-1", then up to 4
 *   colour numbers, ignored) per line, and every such line must end with '\n'.
 * - PLY: ascii 1.0 and binary_little_endian 1.0 (binary_big_endian and other versions are
 *   PGT_ERROR_UNSUPPORTED). Types char uchar short ushort int uint float double and their
 *   int8 .. float64 names. x y z must be float or double (an integer type is UNSUPPORTED).
 *   `group` may be any integer type whose values fit int32; `texcoord` a float or double list
 *   of 2 values per corner; per-vertex texture coordinates float or double scalars (an integer
 *   type or a list is UNSUPPORTED), the first of the three pairs present, used only without a
 *   `texcoord` list (which can hold seams, as one UV per vertex cannot). Other elements, properties
 * and lists are skipped. Ascii PLY holds one element instance per line, each ending with '\n'. A
 * header whose `vertex` element is missing, or lacks x y z, or whose face element lacks the index
 * list, is PGT_ERROR_PARSE; no `face` element or zero faces is PGT_ERROR_EMPTY.
 *
 * Error codes (text messages are "FILE:LINE: ...", binary PLY data "FILE: byte offset N: ..."):
 * - PGT_ERROR_IO: the file cannot be opened or read (or is a directory).
 * - PGT_ERROR_UNSUPPORTED: unknown extension with PGT_FORMAT_AUTO, or a feature listed above.
 * - PGT_ERROR_EMPTY: an empty file, only comments, or no faces (checked once the header is
 *   read: OFF "3 0 0", PLY "element face 0").
 * - PGT_ERROR_LIMIT: a declared count (OFF V or F, any PLY element) or the number of triangles
 *   after fan triangulation above PGT_MESH_MAX_ELEMENTS.
 * - PGT_ERROR_TRUNCATED: the file ends before what its header promised. Checked in this order
 *   before anything is allocated: declared counts that need more bytes than the file holds
 *   (every OFF record and ascii PLY value at least 2 bytes, binary PLY the sizes of its scalars
 *   and list lengths); then, for OFF and ascii PLY, fewer record lines than the counts declare,
 *   whether the missing lines are vertices or faces (a short file and a too-large count look
 *   the same). Also: a header cut short (no OFF counts line, no PLY end_header), a last record
 *   line without its '\n', and binary PLY data that ends inside a value or list.
 * - PGT_ERROR_COUNT_MISMATCH: more OFF / ascii PLY record lines than the header declares, bytes
 *   after the last binary PLY element, or a PLY texcoord list whose length is not twice the
 *   face's vertex count.
 * - PGT_ERROR_INDEX_RANGE: an OBJ index 0, beyond the count, or negative reaching before the
 *   first element; an OFF/PLY index negative or >= V. (OBJ vt and vn indices are checked too.)
 * - PGT_ERROR_NOT_FINITE: see above.
 * - PGT_ERROR_PARSE: everything else that is not what the format allows where it is: a
 *   non-number, a face with fewer than 3 vertices, a record with too few or too many values,
 *   a bad header line or type, an unknown OBJ statement, binary garbage.
 * - PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_mesh_read(pgt_mesh *out, const char *path, const pgt_mesh_read_options *opts,
                         pgt_error *err);

/* The same from memory; `name` is used in messages in place of the path. format must not be AUTO
 * unless name has an extension. */
pgt_result pgt_mesh_read_memory(pgt_mesh *out, const void *data, size_t size, const char *name,
                                const pgt_mesh_read_options *opts, pgt_error *err);

/* Writes OFF (positions and triangles), OBJ (v, vt per corner when uvs exist, f v/vt) or binary
 * little-endian PLY (float x y z; face uchar-uint vertex_indices; int group when labels exist;
 * uchar-float texcoord list of 6 when uvs exist). opts may be NULL.
 * OFF and OBJ print %.9g (enough for every float to read back bit-exact) or %.17g when precise;
 * OFF drops uvs and labels, OBJ drops labels. The file is written to PATH.tmp.PID and renamed
 * over PATH; on any failure the temporary file is removed and PGT_ERROR_IO names PATH. (No
 * fsync: the replacement is atomic for readers and against a crash of this process, not
 * durable across power loss; a replaced file gets default permissions.) An index >= vertex
 * count is PGT_ERROR_INVALID_ARGUMENT and an unknown extension PGT_ERROR_UNSUPPORTED, both
 * before anything is written. */
pgt_result pgt_mesh_write(const pgt_mesh *mesh, const char *path,
                          const pgt_mesh_write_options *opts, pgt_error *err);

/* A triangle mesh with per-vertex attributes (the terminal evaluator's output: positions,
 * normals and uvs per vertex, not per corner). normals and uvs may be NULL. */
typedef struct pgt_vertex_mesh {
    uint32_t vertex_count, triangle_count;
    const float *positions;    /* 3 * vertex_count */
    const float *normals;      /* 3 * vertex_count, or NULL */
    const float *uvs;          /* 2 * vertex_count, or NULL */
    const uint32_t *triangles; /* 3 * triangle_count */
} pgt_vertex_mesh;

/* Writes binary little-endian PLY: vertex float x y z, then float nx ny nz and float u v when
 * given (the property names MeshLab, Blender and Open3D read); face uchar-uint vertex_indices.
 * Written to PATH.tmp.PID and renamed, like pgt_mesh_write; an index >= vertex_count is
 * PGT_ERROR_INVALID_ARGUMENT before anything is written; a write failure PGT_ERROR_IO. */
pgt_result pgt_mesh_write_ply_soup(const pgt_vertex_mesh *soup, const char *path, pgt_error *err);

/* Format from a path's extension, or PGT_FORMAT_AUTO when unknown. */
pgt_mesh_format pgt_mesh_format_from_path(const char *path);

#ifdef __cplusplus
}
#endif

#endif
