#!/usr/bin/env python3
"""Mutated inputs through the pgt program (DEVELOPERS.md: no input may crash the program; bad
input gets one error line naming the file, exit 2).

  fuzz_inputs.py PGT PGT_DATASETS SOURCE_DIR WORK_DIR [--runs N] [--seed S]

Starts from valid files (generated meshes in OBJ, PLY and OFF, the shipped grammars, a generated
city scene, a quad tower OBJ, ivy seed and stroke files, an atlas EXR, a PNG mask, a
protected-face list), applies 1-10 random edits to each copy (byte changes, inserted tokens such
as nan, -1, 1e39 or 4294967295, deleted, duplicated or truncated spans, duplicated lines, a
leading UTF-8 byte order mark) and runs the verb that reads it: pgt atlas and pgt subdiv (meshes),
pgt ivy (grammars, seed and stroke files, the atlas, the mask), pgt facade (facade grammars,
scenes, the tower with --mesh and --embree-check), pgt march (the atlas, the mask) and pgt subdiv
--protect (the face list). Every run must end with exit 0, 1 or 2 within the time limit and
without a sanitizer report (the Sanitize build runs this test too); an exit 2 must print exactly
one error line on stderr, naming the input file, after any notes the readers print (such as "note:
FILE: fan-triangulated 1 polygons").
The edits come from Python's random with a fixed seed: the same inputs every run. A failing
input is kept in WORK_DIR/failed/ with its command and stderr. Exit 0 when every run passes,
1 otherwise, 2 on bad arguments.
"""
import os
import random
import shutil
import struct
import subprocess
import sys
import zlib

# Mutated inputs per run of the test: about 20 s under ASan+UBSan on the 2-core machine.
DEFAULT_RUNS = 400
# A run longer than this is a failure (a hang): the slowest valid input here takes under 2 s
# under the sanitizers.
TIMEOUT_S = 60
TOKENS = [b"-1", b"0", b"1e39", b"nan", b"inf", b"-inf", b"4294967295", b"2147483648",
          b"-2147483649", b"1e-45", b"/", b"//", b" ", b"\n", b"\x00", b"{", b"}", b"(", b")",
          b",", b":", b"*", b"'", b"~", b"|", b"9999999999999999999999", b"-0", b"0x10", b".",
          b"..", b"e", b"#", b'"', b"\t", b"\r", b"\xef\xbb\xbf"]


def is_note(line):
    """A note on stderr: 'note: ...' (the mesh readers) or 'pgt VERB: note: ...'."""
    return line.startswith("note: ") or (line.startswith("pgt ") and ": note: " in line)


def grey_png(w, h, value):
    """An 8-bit grey PNG, value(x, y) in 0..255, written with the standard library."""
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    raw = b"".join(b"\0" + bytes(value(x, y) for x in range(w)) for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def mutate(rng, data):
    d = bytearray(data)
    for _ in range(rng.choice([1, 1, 2, 3, 5, 10])):
        if not d:
            d += b"x"
        i = rng.randrange(len(d))
        op = rng.randrange(8)
        if op == 0:
            d[i] = rng.randrange(256)
        elif op == 1:
            d[i:i] = rng.choice(TOKENS)
        elif op == 2:
            del d[i:i + rng.randrange(1, 64)]
        elif op == 3:
            j = rng.randrange(len(d))
            d[i:i] = d[j:j + rng.randrange(1, 200)]
        elif op == 4:
            del d[i:]
        elif op == 5:  # replace the token at i
            j = i
            while j < len(d) and d[j] not in b" \n":
                j += 1
            d[i:j] = rng.choice(TOKENS)
        elif op == 7:  # a UTF-8 byte order mark first, as Windows editors write one
            d[0:0] = b"\xef\xbb\xbf"
        else:
            lines = bytes(d).split(b"\n")
            k = rng.randrange(len(lines))
            lines.insert(rng.randrange(len(lines)), lines[k])
            d = bytearray(b"\n".join(lines))
    return bytes(d)


def main(argv):
    if len(argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    pgt, gen, src, work = argv[:4]
    runs, seed = DEFAULT_RUNS, 1
    rest = argv[4:]
    while rest:
        if rest[0] in ("--runs", "--seed") and len(rest) > 1 and rest[1].isdigit():
            if rest[0] == "--runs":
                runs = int(rest[1])
            else:
                seed = int(rest[1])
            rest = rest[2:]
        else:
            print(f"fuzz_inputs: bad argument {rest[0]!r}", file=sys.stderr)
            return 2
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "data"))
    data = os.path.join(work, "data")
    for fmt, name in (("obj", "cube_sphere_8"), ("ply", "cube_sphere_8"), ("off", "icosphere_l1")):
        subprocess.run([gen, data, "--only", name, "--format", fmt], check=True,
                       capture_output=True)
    scene = os.path.join(data, "city.scene")
    subprocess.run([gen, "city", "3", "1", "-o", scene, "--grammar",
                    os.path.join(src, "grammars", "facade.grammar")], check=True,
                   capture_output=True)
    tower = os.path.join(data, "tower.obj")
    subprocess.run([gen, "tower", "-o", tower, "10", "7", "20", "30", "8", "3"], check=True,
                   capture_output=True)
    atlas = os.path.join(data, "cs.exr")
    subprocess.run([pgt, "atlas", os.path.join(data, "cube_sphere_8.obj"), "-o", atlas,
                    "--res", "64"], check=True, capture_output=True)

    def read(path):
        with open(path, "rb") as f:
            return f.read()

    out = os.path.join(work, "out")
    ivy = [pgt, "ivy", atlas, "--seeds", "2", "-o", out + ".ply", "--threads", "1"]
    short = ["--param", "maxMainSteps=5"]
    facade = [pgt, "facade", "-o", out + ".exr", "--width", "40", "--height", "30",
              "--threads", "1"]
    # (name, valid content, file extension, commands with {} for the mutated file)
    cases = []
    for ext in ("obj", "ply", "off"):
        name = "icosphere_l1" if ext == "off" else "cube_sphere_8"
        cases.append((ext, read(os.path.join(data, f"{name}.{ext}")), "." + ext,
                      [[pgt, "atlas", "{}", "-o", out + ".exr", "--res", "48", "--threads", "1"],
                       [pgt, "subdiv", "{}", "--iters", "1", "-o", out + ".off",
                        "--threads", "1"]]))
    cases.append(("ivy_grammar", read(os.path.join(src, "grammars", "ivy.grammar")), ".grammar",
                  [ivy + ["--grammar", "{}", "--curves", out + ".csv"]]))
    for g in ("facade.grammar", "facade_rich.grammar"):
        cases.append((g, read(os.path.join(src, "grammars", g)), ".grammar",
                      [facade + ["--city", "2", "--grammar", "{}", "--explicit", out + ".ply"]]))
    cases.append(("scene", read(scene), ".scene", [facade + ["--scene", "{}"]]))
    cases.append(("tower", read(tower), ".obj", [facade + ["--mesh", "{}", "--embree-check"]]))
    cases.append(("seeds", b"texel 20.5 20.5 1 0\npoint 1 0 0\n# c\ntexel 30.5 40.5\n", ".txt",
                  [ivy + short + ["--seed-file", "{}"]]))
    cases.append(("strokes", b"stroke\npoint 1 0 0\npoint 0.9 0.43 0\npoint 0.7 0.71 0\n"
                  b"stroke\npoint 0 0 1\ntexel 20.5 20.5\n", ".txt",
                  [ivy + short + ["--paint", "{}"]]))

    # the atlas itself (ZIP chunks: most edits break a chunk's inflate or CRC-less data, the
    # rest reach the marcher's checks of the channels), a PNG mask of the atlas's size and a
    # protected-face list
    march = [pgt, "march", "{}", "--from", "10.5,10.5", "--dir", "1,0.3", "--step", "2",
             "--steps", "40", "-o", out + ".csv"]
    cases.append(("atlas", read(atlas), ".exr",
                  [march, ivy[:2] + ["{}"] + ivy[3:] + short]))
    march_mask = [a.replace("{}", atlas) for a in march] + ["--mask", "{}"]
    cases.append(("mask", grey_png(64, 64, lambda x, y: 255 if (x // 8 + y // 8) % 5 == 0 else 0),
                  ".png", [march_mask, ivy + short + ["--mask", "{}"]]))
    ico = os.path.join(data, "icosphere_l1.off")
    cases.append(("protect", b"# faces of icosphere_l1\n0 1, 2\n10\n79 # the last\n", ".txt",
                  [[pgt, "subdiv", ico, "--iters", "1", "-o", out + ".off", "--threads", "1",
                    "--protect", "{}"]]))

    env = dict(os.environ)
    env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
    env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
    # no progress lines (a slow run under the sanitizers may pass their first period): the
    # check below counts stderr lines
    env["PGT_PROGRESS_SECONDS"] = "0"
    rng = random.Random(seed)
    failed_dir = os.path.join(work, "failed")
    counts = {0: 0, 1: 0, 2: 0}
    failures = 0
    for run in range(runs):
        name, content, ext, commands = cases[run % len(cases)]
        path = os.path.join(work, f"in_{run}{ext}")
        with open(path, "wb") as f:
            f.write(mutate(rng, content))
        for cmd in commands:
            cmd = [path if a == "{}" else a for a in cmd]
            try:
                r = subprocess.run(cmd, env=env, capture_output=True, timeout=TIMEOUT_S)
                code, err = r.returncode, r.stderr.decode(errors="replace")
            except subprocess.TimeoutExpired:
                code, err = "timeout", ""
            problem = None
            if code not in (0, 1, 2):
                problem = f"exit {code}"
            elif "Sanitizer" in err or "runtime error" in err:
                problem = "sanitizer report"
            elif code == 2:
                lines = err.rstrip("\n").split("\n")
                # the reader's notes ("note: FILE: fan-triangulated 1 polygons") may come
                # before the error, which is one line, the last
                errors = [l for l in lines if not is_note(l)]
                if len(errors) != 1 or errors[0] != lines[-1]:
                    problem = f"exit 2 with {len(errors)} stderr lines besides notes"
                elif os.path.basename(path) not in errors[0]:
                    problem = "exit 2 without the file's name"
            if problem:
                failures += 1
                os.makedirs(failed_dir, exist_ok=True)
                kept = os.path.join(failed_dir, os.path.basename(path))
                shutil.copy(path, kept)
                with open(kept + ".log", "w") as f:
                    f.write(" ".join(cmd) + f"\n{problem}\n{err[-4000:]}")
                print(f"FAIL {name} run {run}: {problem}: {' '.join(cmd)}\n  {err[-600:]}")
            else:
                counts[code] += 1
        os.remove(path)
    print(f"fuzz_inputs: {runs} mutated inputs (seed {seed}), "
          f"{sum(counts.values()) + failures} runs: exit 0 {counts[0]}, exit 1 {counts[1]}, "
          f"exit 2 {counts[2]} (one line naming the file), {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
