"""``python -m mtwin_ray SCENARIO --count N --shards S --out DIR [--address …]``."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from typing import List, Optional


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m mtwin_ray",
        usage="%(prog)s SCENARIO --count N --shards S --out DIR [options] [-- MTWIN_ARGS…]",
        description=(
            "Make an `mtwin dataset` on a Ray cluster: one task per shard "
            "(`mtwin dataset … --shard I/S`), skipping shards already complete."
        ),
        epilog=(
            "Arguments after `--` go to every `mtwin dataset` process. Paths are made "
            "absolute: on a real cluster SCENARIO, its machine model and DIR must be on a "
            "filesystem every node mounts at the same path."
        ),
    )
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario .toml")
    parser.add_argument(
        "--count", "-n", type=int, required=True, metavar="N", help="number of cases"
    )
    parser.add_argument(
        "--shards", "-s", type=int, required=True, metavar="S", help="number of shards (tasks)"
    )
    parser.add_argument("--out", "-o", required=True, metavar="DIR", help="dataset folder")
    parser.add_argument(
        "--address",
        metavar="ADDR",
        help="Ray cluster: `auto` (a `ray start` on this node), `ray://host:10001` (Ray "
        "Client), host:port; default RAY_ADDRESS, else a local cluster",
    )
    parser.add_argument(
        "--mtwin",
        default=os.environ.get("MTWIN_BIN", "mtwin"),
        metavar="PATH",
        help="the mtwin binary: a path, or a name on every worker's PATH "
        "(default $MTWIN_BIN, else mtwin)",
    )
    parser.add_argument(
        "--ship-mtwin",
        action="store_true",
        help="send this machine's mtwin binary to the nodes through Ray's object store "
        "(written once per node to its temp folder) instead of expecting it there",
    )
    parser.add_argument(
        "--threads-per-task",
        type=int,
        default=1,
        metavar="T",
        help="CPUs per task, passed as --threads (default 1)",
    )
    parser.add_argument(
        "--max-retries",
        type=int,
        default=2,
        metavar="R",
        help="retries of a failed shard (default 2)",
    )
    parser.add_argument(
        "--check",
        action="store_true",
        help="start nothing: tell which shards are not complete and whether manifest.json "
        "lists every shard's files; exit 1 if anything is missing (e.g. after a Slurm array)",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log why each shard runs")
    argv = list(sys.argv[1:] if argv is None else argv)
    extra: List[str] = []
    if "--" in argv:  # everything after `--` goes to `mtwin dataset` as it is
        extra = argv[argv.index("--") + 1 :]
        argv = argv[: argv.index("--")]
    args = parser.parse_args(argv)

    logging.basicConfig(
        level=logging.DEBUG if args.verbose else logging.INFO,
        format="%(asctime)s %(levelname)s %(message)s",
        datefmt="%H:%M:%S",
    )
    from . import DatasetError, generate

    if args.check:
        return check(args.out, args.count, args.shards)
    if args.address is not None:
        import ray

        ray.init(address=args.address)
    try:
        summary = generate(
            args.scenario,
            args.out,
            args.count,
            args.shards,
            mtwin=args.mtwin,
            threads_per_task=args.threads_per_task,
            max_retries=args.max_retries,
            extra_args=extra,
            ship_binary=args.ship_mtwin,
        )
    except (DatasetError, FileNotFoundError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(
            "interrupted: shards already published are kept; the same command resumes",
            file=sys.stderr,
        )
        return 130
    print(summary)
    return 0


def check(out: str, count: int, shards: int) -> int:
    """``--check``: every shard complete and the manifest in agreement, or exit 1."""
    from pathlib import Path

    from .layout import layout_problem, manifest_problem, shard_problem

    out_path = Path(out).expanduser().resolve()
    problem = layout_problem(out_path, shards, count)
    if problem is not None:
        print(f"error: {problem}")
        return 1
    bad = 0
    for shard in range(shards):
        problem = shard_problem(out_path, shard, shards, count)
        if problem is not None:
            bad += 1
            print(f"shard {shard}/{shards}: {problem}")
    problem = manifest_problem(out_path, shards, count)
    if problem is not None:
        print(f"manifest: {problem}")
    complete = shards - bad
    print(
        f"{out_path}: {complete} of {shards} shard(s) complete, manifest "
        f"{'ok' if problem is None else 'not ok'}"
    )
    return 0 if bad == 0 and problem is None else 1


if __name__ == "__main__":
    sys.exit(main())
