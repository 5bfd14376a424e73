"""Small mesh readers for the figure scripts: OFF and PLY (ascii, binary little/big endian).

read_mesh(path) -> (V, F): V float64 (n, 3), F int64 (m, 3). Polygons are fan-triangulated.
Malformed input raises MeshError with the file name and the line (OFF, ascii PLY) or the byte
offset (binary PLY); nothing here asserts on user data.

PLY as written by pgt_mesh_write: vertex float x y z; face `list uchar uint vertex_indices`,
optional `int group`, optional `list uchar float texcoord` (6 wedge UVs). Other properties of
any type are skipped, so files from other tools read too.
"""

import io
import os

import numpy as np


class MeshError(Exception):
    pass


# PLY scalar type names (both spellings) -> numpy dtype character
_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def _fan(polys, name):
    """Fan-triangulates a list of index lists into an (m, 3) array."""
    tris = []
    for i, p in enumerate(polys):
        if len(p) < 3:
            raise MeshError(f"{name}: face {i} has {len(p)} vertices (need >= 3)")
        for j in range(1, len(p) - 1):
            tris.append((p[0], p[j], p[j + 1]))
    return np.asarray(tris, dtype=np.int64).reshape(-1, 3)


def _check_indices(F, nv, name):
    if F.size and (F.min() < 0 or F.max() >= nv):
        bad = int(np.argmax((F < 0).any(axis=1) | (F >= nv).any(axis=1)))
        raise MeshError(f"{name}: face {bad} has a vertex index outside [0, {nv})")


def read_off(path):
    name = os.path.basename(path)
    with open(path, "r", encoding="ascii", errors="replace") as fh:
        # (line number, tokens) with comments and blank lines dropped
        toks = []
        for ln, line in enumerate(fh, 1):
            line = line.split("#", 1)[0].split()
            if line:
                toks.append((ln, line))
    if not toks or not toks[0][1][0].endswith("OFF"):
        raise MeshError(f"{name}: line 1: missing OFF header")
    # colour/normal variants only add columns after x y z, which are ignored
    if toks[0][1][0] not in ("OFF", "COFF", "NOFF", "CNOFF"):
        raise MeshError(f"{name}: line {toks[0][0]}: unsupported OFF variant {toks[0][1][0]!r}")
    # counts may share the header line ("OFF 8 12 0")
    rest = toks[0][1][1:]
    lines = toks[1:]
    if rest:
        lines = [(toks[0][0], rest)] + lines
    if not lines or len(lines[0][1]) < 2:
        raise MeshError(f"{name}: missing vertex/face counts after the OFF header")
    ln, c = lines[0]
    try:
        nv, nf = int(c[0]), int(c[1])
    except ValueError:
        raise MeshError(f"{name}: line {ln}: bad counts {' '.join(c)!r}") from None
    if nv < 0 or nf < 0:
        raise MeshError(f"{name}: line {ln}: negative counts")
    body = lines[1:]
    if len(body) < nv + nf:
        raise MeshError(f"{name}: file ends after {len(body)} data lines; "
                        f"header promises {nv} vertices + {nf} faces")
    V = np.empty((nv, 3))
    for i in range(nv):
        ln, t = body[i]
        try:
            V[i] = [float(t[0]), float(t[1]), float(t[2])]
        except (ValueError, IndexError):
            raise MeshError(f"{name}: line {ln}: bad vertex {' '.join(t)!r}") from None
    polys = []
    for i in range(nf):
        ln, t = body[nv + i]
        try:
            k = int(t[0])
            if k < 3 or len(t) < k + 1:
                raise ValueError
            polys.append([int(x) for x in t[1:k + 1]])
        except (ValueError, IndexError):
            raise MeshError(f"{name}: line {ln}: bad face {' '.join(t)!r}") from None
    F = _fan(polys, name)
    _check_indices(F, nv, name)
    return V, F


def _parse_ply_header(fh, name):
    first = fh.readline()
    if first.strip() != b"ply":
        raise MeshError(f"{name}: line 1: missing 'ply' magic")
    fmt = None
    elements = []  # [name, count, [(prop, kind, type(s))]]
    ln = 1
    while True:
        raw = fh.readline()
        ln += 1
        if not raw:
            raise MeshError(f"{name}: header has no end_header")
        t = raw.decode("ascii", "replace").split()
        if not t or t[0] in ("comment", "obj_info"):
            continue
        if t[0] == "end_header":
            break
        if t[0] == "format":
            if len(t) < 2 or t[1] not in ("ascii", "binary_little_endian", "binary_big_endian"):
                raise MeshError(f"{name}: line {ln}: unknown format {' '.join(t[1:])!r}")
            fmt = t[1]
        elif t[0] == "element":
            try:
                elements.append([t[1], int(t[2]), []])
            except (IndexError, ValueError):
                raise MeshError(f"{name}: line {ln}: bad element line") from None
            if elements[-1][1] < 0:
                raise MeshError(f"{name}: line {ln}: negative element count")
        elif t[0] == "property":
            if not elements:
                raise MeshError(f"{name}: line {ln}: property before any element")
            if len(t) == 5 and t[1] == "list":
                if t[2] not in _PLY_TYPES or t[3] not in _PLY_TYPES:
                    raise MeshError(f"{name}: line {ln}: unknown list type")
                elements[-1][2].append((t[4], "list", (_PLY_TYPES[t[2]], _PLY_TYPES[t[3]])))
            elif len(t) == 3 and t[1] in _PLY_TYPES:
                elements[-1][2].append((t[2], "scalar", _PLY_TYPES[t[1]]))
            else:
                raise MeshError(f"{name}: line {ln}: bad property line {' '.join(t)!r}")
        else:
            raise MeshError(f"{name}: line {ln}: unknown header keyword {t[0]!r}")
    if fmt is None:
        raise MeshError(f"{name}: header has no format line")
    return fmt, elements, ln


def _ply_binary_element(buf, pos, count, props, endian, name, ename):
    """Reads `count` records of one element starting at byte `pos`.
    Returns ({prop: array or list of arrays}, new_pos)."""
    has_list = any(kind == "list" for _, kind, _ in props)
    if not has_list:
        dt = np.dtype([(p, endian + ty) for p, _, ty in props])
        need = dt.itemsize * count
        if pos + need > len(buf):
            raise MeshError(f"{name}: byte {pos}: file truncated in element {ename!r} "
                            f"(needs {need} bytes, {len(buf) - pos} left)")
        rec = np.frombuffer(buf, dtype=dt, count=count, offset=pos)
        return {p: rec[p] for p, _, _ in props}, pos + need

    # Fast path: guess every list has the length found in the first record, read the whole
    # element as one structured array and verify the counts; fall back to a record loop.
    if count > 0:
        fields, off, ok = [], pos, True
        for p, kind, ty in props:
            if kind == "scalar":
                fields.append((p, endian + ty))
                off += np.dtype(ty).itemsize
            else:
                cty, ity = ty
                if off + np.dtype(cty).itemsize > len(buf):
                    ok = False
                    break
                n = int(np.frombuffer(buf, dtype=endian + cty, count=1, offset=off)[0])
                fields.append((p + "#n", endian + cty))
                if n > 0:
                    fields.append((p, endian + ity, (n,)))
                off += np.dtype(cty).itemsize + n * np.dtype(ity).itemsize
        if ok:
            dt = np.dtype(fields)
            if pos + dt.itemsize * count <= len(buf):
                rec = np.frombuffer(buf, dtype=dt, count=count, offset=pos)
                lens = {p: rec[p + "#n"] for p, kind, _ in props if kind == "list"}
                if all((v == v[0]).all() for v in lens.values()):
                    out = {}
                    for p, kind, _ in props:
                        if kind == "list" and lens[p][0] == 0:
                            out[p] = np.zeros((count, 0))
                        else:
                            out[p] = rec[p]
                    return out, pos + dt.itemsize * count

    out = {p: [] for p, _, _ in props}
    for i in range(count):
        for p, kind, ty in props:
            if kind == "scalar":
                sz = np.dtype(ty).itemsize
                if pos + sz > len(buf):
                    raise MeshError(f"{name}: byte {pos}: file truncated in {ename} {i}")
                out[p].append(np.frombuffer(buf, endian + ty, 1, pos)[0])
                pos += sz
            else:
                cty, ity = ty
                csz, isz = np.dtype(cty).itemsize, np.dtype(ity).itemsize
                if pos + csz > len(buf):
                    raise MeshError(f"{name}: byte {pos}: file truncated in {ename} {i}")
                n = int(np.frombuffer(buf, endian + cty, 1, pos)[0])
                pos += csz
                if pos + n * isz > len(buf):
                    raise MeshError(f"{name}: byte {pos}: file truncated in {ename} {i} "
                                    f"list {p!r} of {n}")
                out[p].append(np.frombuffer(buf, endian + ity, n, pos))
                pos += n * isz
    return out, pos


def _ply_ascii_elements(lines, elements, name):
    """lines: (line number, text) pairs of the body, blank lines dropped."""
    data, li = {}, 0
    for ename, count, props in elements:
        cols = {p: [] for p, _, _ in props}
        for i in range(count):
            if li >= len(lines):
                raise MeshError(f"{name}: file ends in {ename} {i} of {count}")
            ln, t = lines[li][0], lines[li][1].split()
            li += 1
            k = 0
            try:
                for p, kind, ty in props:
                    if kind == "scalar":
                        cols[p].append(float(t[k]))
                        k += 1
                    else:
                        n = int(t[k])
                        cols[p].append([float(x) for x in t[k + 1:k + 1 + n]])
                        if len(cols[p][-1]) != n:
                            raise IndexError
                        k += 1 + n
            except (ValueError, IndexError):
                raise MeshError(f"{name}: line {ln}: bad {ename} record") from None
        data[ename] = cols
    return data


def read_ply(path):
    name = os.path.basename(path)
    with open(path, "rb") as fh:
        buf = fh.read()
    hdr = io.BytesIO(buf)
    fmt, elements, hdr_lines = _parse_ply_header(hdr, name)
    pos = hdr.tell()  # byte offsets in messages count from the start of the file
    if fmt == "ascii":
        text = buf[pos:].decode("ascii", "replace").splitlines()
        lines = [(hdr_lines + 1 + i, l) for i, l in enumerate(text) if l.strip()]
        data = _ply_ascii_elements(lines, elements, name)
    else:
        endian = "<" if fmt == "binary_little_endian" else ">"
        data = {}
        for ename, count, props in elements:
            data[ename], pos = _ply_binary_element(buf, pos, count, props, endian, name, ename)
    if "vertex" not in data:
        raise MeshError(f"{name}: no 'vertex' element")
    vx = data["vertex"]
    for c in "xyz":
        if c not in vx:
            raise MeshError(f"{name}: vertex element has no property {c!r}")
    V = np.column_stack([np.asarray(vx[c], dtype=np.float64) for c in "xyz"])
    if "face" not in data:
        raise MeshError(f"{name}: no 'face' element")
    fc = data["face"]
    key = "vertex_indices" if "vertex_indices" in fc else "vertex_index"
    if key not in fc:
        raise MeshError(f"{name}: face element has no vertex_indices list")
    idx = fc[key]
    if isinstance(idx, np.ndarray) and idx.ndim == 2 and idx.shape[1] == 3:
        F = idx.astype(np.int64)
    else:
        F = _fan([list(map(int, p)) for p in idx], name)
    _check_indices(F, len(V), name)
    return V, F


def read_mesh(path):
    """(V, F) from an .off or .ply file, chosen by extension (any case)."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".off":
        return read_off(path)
    if ext == ".ply":
        return read_ply(path)
    raise MeshError(f"{os.path.basename(path)}: unknown mesh extension {ext!r} "
                    f"(expected .off or .ply)")
