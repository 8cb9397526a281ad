#!/usr/bin/env python3
"""Mutation fuzzing of the bundled scenarios: bounded work, no panic, nothing infinite with exit 0.

Each mutation replaces one number of one bundled scenario (a key's value or a list entry,
never a comment) with an extreme: huge, tiny, negative, zero, a whole number of 19 digits;
or one number of an attribute of the machine model (URDF) the scenario loads (an origin, an
axis, a limit, a body's size); or a mesh the scenario probes (its STL as written, or turned
into binary STL or OBJ, then a number made extreme, a line deleted or doubled, the file cut,
bytes flipped, a binary triangle count or an OBJ face index made absurd). A mutated model or
mesh is a copy beside the original, which the mutated scenario loads instead; all of it in
a copy of scenarios/ and models/ under a temporary folder, never in the repository.
For every mutation, `mtwin check` must end within --timeout seconds without a panic; when
check accepts it, `mtwin run` must too, and a run that exits 0 must have written no table
holding `inf` or `NaN`. The bound is stated, not measured: the limits the scenarios enforce
(ten turns of a continuous axis, a million grid points, four million spindle samples, …)
keep the largest accepted scenario to about ten seconds on a 2-core machine in a release
build, so --timeout (default 30 s) only trips on a missing limit.

    python3 tools/fuzz_scenarios.py --mtwin target/release/mtwin --count 200 --seed 1
    python3 tools/fuzz_scenarios.py --mtwin target/release/mtwin --kinds mesh --count 100

Exit 0 when every mutation behaved, 1 with a line per failure otherwise. Standard library only.
"""
import argparse
import pathlib
import random
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

EXTREMES = ["1e9", "-1e9", "1e300", "-1e300", "0", "0.0", "1e-300", "350000", "-1",
            "9223372036854775807", "-9223372036854775808", "1.7976931348623157e308"]
# A number in TOML outside strings and comments: after `=`, `[`, `,` or `{` (and spaces).
NUMBER = re.compile(r"(?<=[=\[,{]) *(-?\d[\d_]*(?:\.\d+)?(?:[eE][+-]?\d+)?)(?=\s*[,\]}\n#]|\s*$)")
# A number inside a URDF attribute value (`xyz="0 -0.2 0.35"`, `lower="-3.1416"`).
URDF_NUMBER = re.compile(r'(?<=["\s])(-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?)(?=["\s])')
MACHINE = re.compile(r'^machine = "\.\./models/([^"]+)"', re.M)
MESH = re.compile(r'^file = "(data/[^"]+\.stl)"', re.M)
BAD_TEXT = re.compile(r"(?<![A-Za-z_])(inf|-inf|NaN|nan)(?![A-Za-z_])")


def numbers(text):
    """(start, end) of every number literal outside comments and strings."""
    spans = []
    offset = 0
    for line in text.splitlines(keepends=True):
        code = line.split("#", 1)[0]
        if code.count('"') % 2 == 0:  # not inside a multi-line string
            for m in NUMBER.finditer(code):
                spans.append((offset + m.start(1), offset + m.end(1)))
        offset += len(line)
    return spans


def urdf_numbers(text):
    """(start, end) of every number inside an attribute value of the URDF, outside comments."""
    spans = []
    for tag in re.finditer(r"<[a-z_]+\s[^<>]*>", text):
        for value in re.finditer(r'="([^"]*)"', tag.group(0)):
            base = tag.start() + value.start(1)
            for m in URDF_NUMBER.finditer(" " + value.group(1) + " "):
                spans.append((base + m.start(1) - 1, base + m.end(1) - 1))
    return spans


def ascii_triangles(text):
    """The triangles of an ASCII STL, as lists of three (x, y, z)."""
    vertices = [tuple(float(v) for v in line.split()[1:4])
                for line in text.splitlines() if line.strip().startswith("vertex")]
    return [vertices[i:i + 3] for i in range(0, len(vertices) - 2, 3)]


def binary_stl(triangles):
    out = bytearray(b"mtwin fuzz".ljust(80, b" "))
    out += struct.pack("<I", len(triangles))
    for tri in triangles:
        out += struct.pack("<3f", 0.0, 0.0, 0.0)
        for vertex in tri:
            out += struct.pack("<3f", *vertex)
        out += struct.pack("<H", 0)
    return bytes(out)


def obj_text(triangles):
    lines, index = [], {}
    faces = []
    for tri in triangles:
        face = []
        for vertex in tri:
            if vertex not in index:
                index[vertex] = len(index) + 1
                lines.append("v %g %g %g" % vertex)
            face.append(index[vertex])
        faces.append("f %d %d %d" % tuple(face))
    return "\n".join(lines + faces) + "\n"


def mesh_mutation(original, rng):
    """(suffix, bytes, what) of one mutation of the ASCII STL `original`."""
    triangles = ascii_triangles(original)
    form = rng.choice(["stl", "binary", "obj"])
    if form == "binary":
        data = bytearray(binary_stl(triangles))
        how = rng.choice(["count", "cut", "flip"])
        if how == "count":
            value = rng.choice([0, 1, 0xFFFFFFFF, len(triangles) + 1, 2**31])
            data[80:84] = struct.pack("<I", value)
            return ".stl", bytes(data), f"binary STL with a triangle count of {value}"
        if how == "cut":
            at = rng.randrange(len(data))
            return ".stl", bytes(data[:at]), f"binary STL cut at byte {at}"
        at = rng.randrange(84, len(data))
        data[at] ^= 0xFF
        return ".stl", bytes(data), f"binary STL with byte {at} flipped"
    text = original if form == "stl" else obj_text(triangles)
    suffix = ".stl" if form == "stl" else ".obj"
    lines = text.splitlines(keepends=True)
    how = rng.choice(["number", "number", "delete", "double", "cut", "face"])
    if how == "face" and form == "obj":
        faces = [i for i, l in enumerate(lines) if l.startswith("f ")]
        i = rng.choice(faces)
        value = rng.choice(["0", "-100000", "99999", "1.5", "x"])
        lines[i] = "f %s %s\n" % (lines[i].split()[1], value)
        return suffix, "".join(lines).encode(), f"OBJ face {i + 1} with index {value}"
    if how in ("number", "face"):
        spans = [(m.start(1), m.end(1)) for m in
                 re.finditer(r"(?<=\s)(-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?)(?=\s)", text)]
        start, end = rng.choice(spans)
        value = rng.choice(EXTREMES + ["nan", "inf"])
        line = text.count("\n", 0, start) + 1
        return (suffix, (text[:start] + value + text[end:]).encode(),
                f"{form} line {line}: {text[start:end]} -> {value}")
    i = rng.randrange(len(lines))
    if how == "delete":
        return suffix, "".join(lines[:i] + lines[i + 1:]).encode(), f"{form} line {i + 1} deleted"
    if how == "double":
        return suffix, "".join(lines[:i + 1] + lines[i:]).encode(), f"{form} line {i + 1} doubled"
    at = rng.randrange(len(text))
    return suffix, text[:at].encode(), f"{form} cut at character {at}"


def run(cmd, timeout):
    started = time.monotonic()
    try:
        done = subprocess.run(cmd, capture_output=True, timeout=timeout)
        return done.returncode, time.monotonic() - started, done.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return None, time.monotonic() - started, "timed out"


def mutation(candidate, k, rng):
    """The mutated scenario's text, the copies it loads {path: bytes} and a description."""
    path, kind, where, value = candidate
    text = path.read_text()
    if kind == "scenario":
        start, end = where
        line = text.count("\n", 0, start) + 1
        return (text[:start] + value + text[end:], {},
                f"{path.name}:{line}: {text[start:end]} -> {value}")
    if kind == "model":
        model, (start, end) = where
        urdf = model.read_text()
        line = urdf.count("\n", 0, start) + 1
        copy = model.with_name(f".fuzz-{k}-{model.name}")
        mutated = text.replace(f'"../models/{model.name}"', f'"../models/{copy.name}"', 1)
        return (mutated, {copy: (urdf[:start] + value + urdf[end:]).encode()},
                f"{path.name} on {model.name}:{line}: {urdf[start:end]} -> {value}")
    mesh = where
    suffix, data, what = mesh_mutation(mesh.read_text(), rng)
    copy = mesh.with_name(f".fuzz-{k}-{mesh.stem}{suffix}")
    relative = mesh.relative_to(path.parent).as_posix()
    mutated = text.replace(f'"{relative}"', f'"{copy.relative_to(path.parent).as_posix()}"', 1)
    return mutated, {copy: data}, f"{path.name} on {mesh.name}: {what}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mtwin", required=True, help="the mtwin binary (a release build)")
    parser.add_argument("--count", type=int, default=200, help="mutations to try")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per command")
    parser.add_argument("--kinds", default="scenario,model,mesh",
                        help="what to mutate: scenario, model, mesh (comma-separated)")
    args = parser.parse_args()
    kinds = set(args.kinds.split(","))
    repo = pathlib.Path(__file__).resolve().parent.parent
    rng = random.Random(args.seed)
    # Everything happens in a copy of scenarios/ and models/ (relative paths intact), so the
    # repository never holds a mutated file, whatever runs beside the fuzzer or stops it.
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="mtwin-fuzz-"))
    root = scratch / "tree"
    for folder in ("scenarios", "models"):
        shutil.copytree(repo / folder, root / folder)
    scenarios = sorted(p for p in (root / "scenarios").glob("*.toml") if not p.name.startswith("."))
    candidates = []
    models = {}
    for path in scenarios:
        text = path.read_text()
        spans = numbers(text)
        for span in spans:
            for value in EXTREMES:
                candidates.append((path, "scenario", span, value))
        machine = MACHINE.search(text)
        if machine:
            model = root / "models" / machine.group(1)
            models.setdefault(model, urdf_numbers(model.read_text()))
            # A quarter as many model mutations as the scenario has numbers: a model is shared.
            for span in rng.sample(models[model], min(len(models[model]), len(spans) // 4 + 1)):
                for value in EXTREMES:
                    candidates.append((path, "model", (model, span), value))
        for mesh in MESH.finditer(text):
            # As many mesh mutations as the scenario has number mutations: a mesh is its own
            # reader, as exposed as the scenario's.
            for _ in range(len(spans) * len(EXTREMES)):
                candidates.append((path, "mesh", path.parent / mesh.group(1), None))
    candidates = [c for c in candidates if c[1] in kinds]
    picks = rng.sample(candidates, min(args.count, len(candidates)))
    failures = []
    try:
        for k, candidate in enumerate(picks):
            mutated, copies, what = mutation(candidate, k, rng)
            # Beside the original (in the copy), so its relative paths (machine, extends, meshes)
            # resolve.
            target = candidate[0].with_name(f".fuzz-{k}-{candidate[0].name}")
            try:
                for copy, data in copies.items():
                    copy.write_bytes(data)
                target.write_text(mutated)
                rc, seconds, err = run([args.mtwin, "check", str(target)], args.timeout)
                if rc is None or rc not in (0, 1):
                    failures.append(f"{what}: check rc={rc} after {seconds:.1f} s: {err[-300:]}")
                    continue
                if rc != 0:
                    continue
                out = scratch / f"run{k}"
                rc, seconds, err = run([args.mtwin, "run", str(target), "--out", str(out)],
                                       args.timeout)
                if rc is None or rc not in (0, 1):
                    failures.append(f"{what}: run rc={rc} after {seconds:.1f} s: {err[-300:]}")
                elif rc == 0:
                    for table in sorted(list(out.glob("*.csv")) + list(out.glob("*.json"))):
                        if BAD_TEXT.search(table.read_text(errors="replace")):
                            failures.append(f"{what}: run exit 0 with a non-finite number in {table.name}")
                shutil.rmtree(out, ignore_errors=True)
            finally:
                target.unlink(missing_ok=True)
                for copy in copies:
                    copy.unlink(missing_ok=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    for failure in failures:
        print(failure)
    made = {kind: sum(1 for c in picks if c[1] == kind) for kind in ("scenario", "model", "mesh")}
    print(f"fuzz_scenarios: {len(picks)} mutations of {len(scenarios)} scenarios "
          f"({made['scenario']} of scenarios, {made['model']} of models, {made['mesh']} of meshes), "
          f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
