"""A small OpenEXR reader for the figure scripts: what pgt_image_write_exr writes (single-part
scanline, FLOAT or HALF channels, NONE / ZIPS / ZIP compression); Debian's python3 has no
OpenEXR module. Errors raise ExrError naming the file.
"""

import struct
import zlib

import numpy as np


class ExrError(Exception):
    pass


def die(msg):
    raise ExrError(msg)


def read_exr(path):
    """{channel name: H x W float32} of a single-part scanline OpenEXR file."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as e:
        die(f"{path}: {e.strerror}")
    try:
        if data[:4] != b"\x76\x2f\x31\x01":
            die(f"{path}: not an OpenEXR file")
        if data[5] & 0x1A:  # tiled, deep or multi-part
            die(f"{path}: only single-part scanline files are read")
        pos, attrs = 8, {}
        while data[pos] != 0:
            end = data.index(b"\0", pos)
            name = data[pos:end].decode()
            end2 = data.index(b"\0", end + 1)
            typ = data[end + 1:end2].decode()
            (size,) = struct.unpack_from("<i", data, end2 + 1)
            attrs[name] = (typ, data[end2 + 5:end2 + 5 + size])
            pos = end2 + 5 + size
        pos += 1
        raw, p, chans = attrs["channels"][1], 0, []
        while raw[p] != 0:
            end = raw.index(b"\0", p)
            (ptype,) = struct.unpack_from("<i", raw, end + 1)
            chans.append((raw[p:end].decode(), ptype))
            p = end + 17
        comp = attrs["compression"][1][0]
        x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    except (KeyError, IndexError, ValueError, struct.error, UnicodeDecodeError) as e:
        die(f"{path}: malformed header ({e})")
    lines = {0: 1, 2: 1, 3: 16}.get(comp)
    if lines is None:
        die(f"{path}: compression {comp} is not read here (pgt writes ZIP)")
    if any(t not in (1, 2) for _, t in chans):
        die(f"{path}: only HALF and FLOAT channels are read")
    W, H = x1 - x0 + 1, y1 - y0 + 1
    if W <= 0 or H <= 0 or W * H > (1 << 26):
        die(f"{path}: unreasonable size {W}x{H}")
    sizes = [4 if t == 2 else 2 for _, t in chans]
    out = {n: np.zeros((H, W), np.float32) for n, _ in chans}
    nchunks = (H + lines - 1) // lines
    try:
        offsets = struct.unpack_from(f"<{nchunks}Q", data, pos)
        for off in offsets:
            y, n = struct.unpack_from("<ii", data, off)
            blob = data[off + 8:off + 8 + n]
            rows = min(lines, y1 + 1 - y)
            if n < rows * W * sum(sizes):  # compressed: zlib, then predictor, then interleave
                t = np.frombuffer(zlib.decompress(blob), np.uint8).astype(np.int32)
                t[1:] -= 128
                t = (np.cumsum(t) & 255).astype(np.uint8)
                half = (len(t) + 1) // 2
                b = np.empty(len(t), np.uint8)
                b[0::2], b[1::2] = t[:half], t[half:]
                blob = b.tobytes()
            q = 0
            for r in range(rows):
                for (name, typ), sz in zip(chans, sizes):
                    dt = "<f4" if typ == 2 else "<f2"
                    out[name][y - y0 + r] = np.frombuffer(blob, dt, W, q)
                    q += W * sz
    except (struct.error, zlib.error, ValueError, IndexError) as e:
        die(f"{path}: malformed pixel data ({e})")
    return out
