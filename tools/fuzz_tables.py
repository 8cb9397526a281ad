#!/usr/bin/env python3
"""Mutation fuzzing of the table readers: no panic, no hang, nothing infinite with exit 0.

The tables come from the bundled scenarios (one `mtwin run` each, once). Each mutation changes
one thing in one table, the way an export or an editor goes wrong:

* a number (a cell or a preamble value) replaced with an extreme (huge, tiny, negative,
  zero, 19 digits, `inf`, `NaN`, text);
* a row deleted, duplicated or cut short; two rows swapped;
* a column's name changed, or a column removed from the header only;
* a preamble line deleted or given twice.

The JSON readers are fuzzed the same way: `mtwin identify` makes an estimate.json from the
R-test table once, and a mutation changes a number of it or of the run's truth.json (or
deletes or doubles a line), then `mtwin score` (text and `--json`) is held to the same rules.

For every mutation, `mtwin analyze <kind>` (text and `--json`) must end within --timeout
seconds and exit 0 or 1 (never 101, a panic), and a report that exits 0 must hold no `inf` or
`NaN`. The bound is stated, not measured: the bundled tables are analysed in well under a
second each in a release build, and no mutation here makes a table larger than twice its
size, so --timeout (default 30 s) only trips on work that grows faster than its input.

    python3 tools/fuzz_tables.py --mtwin target/release/mtwin --count 300 --seed 1

Exit 0 when every mutation behaved, 1 with a line per failure otherwise. Standard library only.
"""
import argparse
import pathlib
import random
import re
import subprocess
import sys
import tempfile
import time

EXTREMES = ["1e9", "-1e9", "1e300", "-1e300", "0", "-0", "1e-300", "-1",
            "9223372036854775807", "1.7976931348623157e308", "inf", "-inf", "NaN", "x", ""]
NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?")
BAD_TEXT = re.compile(r"(?<![A-Za-z_])(inf|-inf|NaN|nan)(?![A-Za-z_])")
# The scenarios whose tables are fuzzed, and the kind that analyses each table (by file name).
SCENARIOS = ["vmc3_iso230_2", "teach_warmup", "vmc3_iso230_3_etve", "vmc3_iso230_3_spindle",
             "vmc3_ballbar_xy", "trunnion5_rtest", "teach_spindle", "vmc3_spindle_reversal",
             "teach_probe"]
KINDS = {"positioning.csv": "positioning", "drift.csv": "drift", "rtest.csv": "rtest",
         "spindle.csv": "spindle", "probe.csv": "probe"}


def kind_of(name):
    if name.startswith("ballbar_"):
        return "ballbar"
    return KINDS.get(name)


def mutate(text, rng):
    """One mutation of `text` and what it was."""
    lines = text.split("\n")
    header = next(i for i, l in enumerate(lines) if l and not l.startswith("#"))
    rows = [i for i in range(header + 1, len(lines)) if lines[i]]
    preamble = [i for i in range(header) if "=" in lines[i]]
    choice = rng.choice(["number", "number", "number", "delete", "duplicate", "cut", "swap",
                         "rename", "drop_column", "preamble_delete", "preamble_twice"])
    if choice == "number":
        i = rng.choice(rows + preamble)
        spans = [m.span() for m in NUMBER.finditer(lines[i])]
        if not spans:
            return None
        start, end = rng.choice(spans)
        value = rng.choice(EXTREMES)
        what = f"line {i + 1}: {lines[i][start:end]} -> {value!r}"
        lines[i] = lines[i][:start] + value + lines[i][end:]
    elif choice == "delete":
        i = rng.choice(rows)
        what = f"line {i + 1} deleted"
        del lines[i]
    elif choice == "duplicate":
        i = rng.choice(rows)
        what = f"line {i + 1} twice"
        lines.insert(i, lines[i])
    elif choice == "cut":
        i = rng.choice(rows)
        keep = rng.randrange(len(lines[i]))
        what = f"line {i + 1} cut after {keep} characters"
        lines[i] = lines[i][:keep]
    elif choice == "swap":
        i, j = rng.sample(rows, 2)
        what = f"lines {i + 1} and {j + 1} swapped"
        lines[i], lines[j] = lines[j], lines[i]
    elif choice == "rename":
        names = lines[header].split(",")
        k = rng.randrange(len(names))
        new = rng.choice(["x", names[k].upper(), names[k] + "_mm", names[(k + 1) % len(names)]])
        what = f"column {names[k]} renamed {new}"
        names[k] = new
        lines[header] = ",".join(names)
    elif choice == "drop_column":
        names = lines[header].split(",")
        k = rng.randrange(len(names))
        what = f"column {names[k]} removed from the header only"
        del names[k]
        lines[header] = ",".join(names)
    elif not preamble:
        return None
    elif choice == "preamble_delete":
        i = rng.choice(preamble)
        what = f"preamble line {i + 1} deleted"
        del lines[i]
    else:
        i = rng.choice(preamble)
        what = f"preamble line {i + 1} twice"
        lines.insert(i, lines[i])
    return "\n".join(lines), what


def mutate_json(text, rng):
    """One mutation of a JSON file's text and what it was."""
    lines = text.split("\n")
    choice = rng.choice(["number", "number", "number", "delete", "duplicate"])
    if choice == "number":
        spans = [(i, m.span()) for i, l in enumerate(lines) for m in NUMBER.finditer(l)]
        if not spans:
            return None
        i, (start, end) = rng.choice(spans)
        value = rng.choice(EXTREMES)
        what = f"line {i + 1}: {lines[i][start:end]} -> {value!r}"
        lines[i] = lines[i][:start] + value + lines[i][end:]
    elif choice == "delete":
        i = rng.randrange(len(lines))
        what = f"line {i + 1} deleted"
        del lines[i]
    else:
        i = rng.randrange(len(lines))
        what = f"line {i + 1} twice"
        lines.insert(i, lines[i])
    return "\n".join(lines), what


def run(cmd, timeout):
    started = time.monotonic()
    try:
        done = subprocess.run(cmd, capture_output=True, timeout=timeout)
        return (done.returncode, time.monotonic() - started,
                done.stdout.decode(errors="replace"), done.stderr.decode(errors="replace"))
    except subprocess.TimeoutExpired:
        return None, time.monotonic() - started, "", "timed out"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mtwin", required=True, help="the mtwin binary (a release build)")
    parser.add_argument("--count", type=int, default=300, help="mutations to try")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per command")
    args = parser.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    rng = random.Random(args.seed)
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        tables = []
        for name in SCENARIOS:
            out = scratch / name
            rc, _, _, err = run([args.mtwin, "run", str(root / "scenarios" / f"{name}.toml"),
                                 "--out", str(out)], 300)
            if rc != 0:
                print(f"{name}: run failed: {err[-300:]}")
                return 1
            tables += [(t, kind_of(t.name)) for t in sorted(out.glob("*.csv")) if kind_of(t.name)]
        # The estimate and truth of the R-test run, for `score`.
        rtest = scratch / "trunnion5_rtest"
        rc, _, _, err = run([args.mtwin, "identify", "--machine",
                             str(root / "models" / "trunnion5.urdf"), "--params", "location",
                             str(rtest / "rtest.csv"), "--out", str(scratch / "estimate")], 300)
        if rc != 0:
            print(f"identify failed: {err[-300:]}")
            return 1
        estimate, truth = scratch / "estimate" / "estimate.json", rtest / "truth.json"
        tables += [(estimate, "score-estimate"), (truth, "score-truth")]
        done = 0
        while done < args.count:
            path, kind = rng.choice(tables)
            scoring = kind.startswith("score")
            mutation = (mutate_json if scoring else mutate)(path.read_text(), rng)
            if mutation is None:
                continue
            text, what = mutation
            target = scratch / f"fuzz-{done}-{path.name}"
            target.write_text(text)
            done += 1
            for json in (False, True):
                if kind == "score-estimate":
                    cmd = [args.mtwin, "score", str(target), str(truth)]
                elif kind == "score-truth":
                    cmd = [args.mtwin, "score", str(estimate), str(target)]
                else:
                    cmd = [args.mtwin, "analyze", kind, str(target)]
                cmd += ["--json"] if json else []
                rc, seconds, out, err = run(cmd, args.timeout)
                verb = "score" if scoring else f"analyze {kind}"
                where = f"{path.parent.name}/{path.name} {what} ({verb}{' --json' if json else ''})"
                if rc is None or rc not in (0, 1):
                    failures.append(f"{where}: rc={rc} after {seconds:.1f} s: {err[-300:]}")
                    break
                if rc == 0 and BAD_TEXT.search(out):
                    failures.append(f"{where}: exit 0 with a non-finite number in the report")
                    break
            target.unlink()
    for failure in failures:
        print(failure)
    print(f"fuzz_tables: {args.count} mutations of {len(tables)} files (tables, estimate, truth), "
          f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
