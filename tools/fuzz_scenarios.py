#!/usr/bin/env python3
"""Mutation fuzzing of the bundled scenarios: bounded work, no panic, nothing infinite with exit 0.

Each mutation replaces one number of one bundled scenario (a key's value or a list entry,
never a comment) with an extreme: huge, tiny, negative, zero, a whole number of 19 digits.
For every mutation, `mtwin check` must end within --timeout seconds without a panic; when
check accepts it, `mtwin run` must too, and a run that exits 0 must have written no table
holding `inf` or `NaN`. The bound is stated, not measured: the limits the scenarios enforce
(ten turns of a continuous axis, a million grid points, four million spindle samples, …)
keep the largest accepted scenario to about ten seconds on a 2-core machine in a release
build, so --timeout (default 30 s) only trips on a missing limit.

    python3 tools/fuzz_scenarios.py --mtwin target/release/mtwin --count 200 --seed 1

Exit 0 when every mutation behaved, 1 with a line per failure otherwise. Standard library only.
"""
import argparse
import pathlib
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

EXTREMES = ["1e9", "-1e9", "1e300", "-1e300", "0", "0.0", "1e-300", "350000", "-1",
            "9223372036854775807", "-9223372036854775808", "1.7976931348623157e308"]
# A number in TOML outside strings and comments: after `=`, `[`, `,` or `{` (and spaces).
NUMBER = re.compile(r"(?<=[=\[,{]) *(-?\d[\d_]*(?:\.\d+)?(?:[eE][+-]?\d+)?)(?=\s*[,\]}\n#]|\s*$)")
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


def run(cmd, timeout):
    started = time.monotonic()
    try:
        done = subprocess.run(cmd, capture_output=True, timeout=timeout)
        return done.returncode, time.monotonic() - started, done.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return None, time.monotonic() - started, "timed out"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mtwin", required=True, help="the mtwin binary (a release build)")
    parser.add_argument("--count", type=int, default=200, help="mutations to try")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per command")
    args = parser.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    rng = random.Random(args.seed)
    scenarios = sorted((root / "scenarios").glob("*.toml"))
    candidates = []
    for path in scenarios:
        text = path.read_text()
        for span in numbers(text):
            for value in EXTREMES:
                candidates.append((path, span, value))
    picks = rng.sample(candidates, min(args.count, len(candidates)))
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        for k, (path, (start, end), value) in enumerate(picks):
            text = path.read_text()
            mutated = text[:start] + value + text[end:]
            line = text.count("\n", 0, start) + 1
            what = f"{path.name}:{line}: {text[start:end]} -> {value}"
            # Beside the original, so that its relative paths (machine, extends) still resolve.
            target = path.with_name(f".fuzz-{k}-{path.name}")
            target.write_text(mutated)
            try:
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
                    for table in sorted(out.glob("*.csv")):
                        if BAD_TEXT.search(table.read_text(errors="replace")):
                            failures.append(f"{what}: run exit 0 with a non-finite number in {table.name}")
                shutil.rmtree(out, ignore_errors=True)
            finally:
                target.unlink(missing_ok=True)
    for failure in failures:
        print(failure)
    print(f"fuzz_scenarios: {len(picks)} mutations of {len(scenarios)} scenarios, "
          f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
