"""The Ray driver: one task per shard of `mtwin dataset`, skipping complete shards."""

from __future__ import annotations

import hashlib
import logging
import os
import shutil
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _task
from .layout import (
    MANIFEST,
    DatasetError,
    layout_problem,
    manifest_problem,
    record_path,
    shard_problem,
)

log = logging.getLogger("mtwin_ray")

PathLike = Union[str, os.PathLike]


@dataclass
class GenerateSummary:
    """What :func:`generate` did."""

    #: The dataset folder (absolute).
    out: Path
    #: ``out/manifest.json``, checked to list the files of every shard.
    manifest: Path
    #: Shards that ran as Ray tasks (sorted).
    shards_run: List[int]
    #: Shards found complete before submitting and not run again (sorted).
    shards_skipped: List[int]
    #: Why each run shard was not complete before (``"no record …"`` on a first run).
    reasons: Dict[int, str] = field(default_factory=dict)
    #: What each task returned (host, seconds, stderr tail), by shard.
    results: Dict[int, Dict[str, Any]] = field(default_factory=dict)
    #: Wall time of :func:`generate`, seconds.
    seconds: float = 0.0

    def __str__(self) -> str:
        return (
            f"{len(self.shards_run)} shard(s) run, {len(self.shards_skipped)} skipped"
            f" in {self.seconds:.1f} s; manifest {self.manifest}"
        )


def _resolve_binary(mtwin: PathLike, ship: bool) -> str:
    """An absolute path for a binary given as a path; a bare name stays as it is (looked up on
    PATH by each worker), unless it is shipped, when it must be found here."""
    text = os.fspath(mtwin)
    if os.sep not in text and (os.altsep is None or os.altsep not in text):
        found = shutil.which(text)
        if ship:
            if found is None:
                raise FileNotFoundError(f"{text!r} is not on PATH: cannot ship it")
            return str(Path(found).resolve())
        if found is None:
            log.warning("%r is not on this machine's PATH: every worker must have it", text)
        return text
    path = Path(text).expanduser().resolve()
    if not path.is_file():
        raise FileNotFoundError(f"mtwin binary {path} does not exist")
    return str(path)


def _ray():
    import ray  # imported here so that mtwin_ray.read works without starting anything

    return ray


def generate(
    scenario: PathLike,
    out: PathLike,
    count: int,
    shards: int,
    *,
    mtwin: PathLike = "mtwin",
    threads_per_task: int = 1,
    max_retries: int = 2,
    extra_args: Sequence[str] = (),
    runtime_env: Optional[Mapping[str, Any]] = None,
    env: Optional[Mapping[str, str]] = None,
    ship_binary: bool = False,
) -> GenerateSummary:
    """Makes the dataset ``out`` of ``count`` cases of ``scenario`` in ``shards`` shards, one
    Ray task per shard that is not already complete.

    Each task runs ``mtwin dataset SCENARIO --count N --out DIR --shard I/S --threads T
    [extra_args…]``. Paths are made absolute here: on a real cluster, ``scenario`` (with the
    machine model it names) and ``out`` must be on a filesystem every node mounts at the same
    path. ``mtwin`` is a path (made absolute) or a name looked up on each worker's PATH.

    A shard whose record exists and whose files all exist with the recorded SHA-256 is skipped
    before submitting, so running the same call again does nothing but check. A task whose
    process fails is retried up to ``max_retries`` times (Ray's ``retry_exceptions``); a retry
    redoes the shard from its start (nothing of it is published before the final renames).

    If Ray is not initialised, calls ``ray.init()`` (which honours ``RAY_ADDRESS``); otherwise
    uses the connection the caller made. ``ship_binary`` sends the driver's ``mtwin`` through
    Ray's object store, written once per node to its temp folder (the nodes must be able to
    run it: same OS, architecture, a glibc as new). ``runtime_env`` goes to every task
    (``env_vars``, a ``container``, …), ``env`` is added to the process's environment.

    Raises :class:`DatasetError` when some shard failed for good (after the others finished)
    or when ``out/manifest.json`` is missing or does not list the files of every shard.
    """
    started = time.monotonic()
    if count < 1:
        raise ValueError(f"count must be at least 1, not {count}")
    if shards < 1:
        raise ValueError(f"shards must be at least 1, not {shards}")
    if shards > count:
        raise ValueError(f"{shards} shards for {count} cases: at most one shard per case")
    if threads_per_task < 1:
        raise ValueError(f"threads_per_task must be at least 1, not {threads_per_task}")
    scenario_path = Path(scenario).expanduser().resolve()
    if not scenario_path.is_file():
        raise FileNotFoundError(f"scenario {scenario_path} does not exist")
    out_path = Path(out).expanduser().resolve()
    binary = _resolve_binary(mtwin, ship_binary)

    problem = layout_problem(out_path, shards, count)
    if problem is not None:
        raise DatasetError(f"{out_path}: {problem}")
    todo: Dict[int, str] = {}
    skipped: List[int] = []
    # Hashing is I/O bound (and hashlib lets go of the GIL): a few shards at a time.
    with ThreadPoolExecutor(max_workers=min(8, shards)) as pool:
        problems = pool.map(
            lambda shard: shard_problem(out_path, shard, shards, count, workers=1), range(shards)
        )
        for shard, problem in enumerate(problems):
            if problem is None:
                skipped.append(shard)
            else:
                todo[shard] = problem
    log.info("%s: %d shard(s) to run, %d complete", out_path, len(todo), len(skipped))
    for shard, reason in todo.items():
        log.debug("shard %d: %s", shard, reason)

    # Every shard complete but the manifest missing or stale (say, deleted by hand): run the
    # last shard again, which finds its files complete and writes the manifest, as the last
    # record's writer does.
    if not todo and manifest_problem(out_path, shards, count) is not None:
        todo[shards - 1] = "manifest.json missing or stale"
        skipped.remove(shards - 1)

    results: Dict[int, Dict[str, Any]] = {}
    if todo:
        ray = _ray()
        if not ray.is_initialized():
            ray.init()
        # Ship the task body by value: workers need Ray, not this package.
        ray.cloudpickle.register_pickle_by_value(_task)
        remote = ray.remote(_task.run_shard).options(
            num_cpus=threads_per_task,
            max_retries=max_retries,
            retry_exceptions=True,
            runtime_env=dict(runtime_env) if runtime_env else None,
            name="mtwin-dataset-shard",
        )
        shipped: tuple = ()
        if ship_binary:
            blob = Path(binary).read_bytes()
            shipped = (ray.put(blob), hashlib.sha256(blob).hexdigest())
            binary = Path(binary).name
        refs = {}
        for shard in todo:
            argv = [
                binary,
                "dataset",
                str(scenario_path),
                "--count",
                str(count),
                "--out",
                str(out_path),
                "--shard",
                f"{shard}/{shards}",
                "--threads",
                str(threads_per_task),
                *map(str, extra_args),
            ]
            refs[remote.remote(argv, shard, dict(env) if env else None, *shipped)] = shard
        failures: Dict[int, str] = {}
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                shard = refs[ref]
                try:
                    results[shard] = ray.get(ref)
                    log.info(
                        "shard %d/%d done on %s in %.2f s (%d left)",
                        shard,
                        shards,
                        results[shard]["host"],
                        results[shard]["seconds"],
                        len(pending),
                    )
                except Exception as e:  # RayTaskError wrapping ShardFailed, worker death, …
                    failures[shard] = str(e)
                    log.error("shard %d/%d failed for good: %s", shard, shards, e)
        if failures:
            first = min(failures)
            kept = "the others are published; " if len(failures) < len(todo) else ""
            raise DatasetError(
                f"{len(failures)} of {len(todo)} shard(s) failed after {max_retries} retr"
                f"{'y' if max_retries == 1 else 'ies'}: {sorted(failures)}; {kept}the same"
                f" call again redoes only what is missing. Shard {first}:\n{failures[first]}"
            )

    # Every shard must now be complete (records written by the tasks), and the manifest must
    # merge them.
    for shard in todo:
        if not record_path(out_path, shard, shards).is_file():
            raise DatasetError(
                f"shard {shard}: the process exited 0 but wrote no record"
                f" {record_path(out_path, shard, shards)}"
            )
    problem = manifest_problem(out_path, shards, count)
    if problem is not None:
        raise DatasetError(f"{out_path}: {problem}")
    return GenerateSummary(
        out=out_path,
        manifest=out_path / MANIFEST,
        shards_run=sorted(todo),
        shards_skipped=sorted(skipped),
        reasons=dict(sorted(todo.items())),
        results=dict(sorted(results.items())),
        seconds=time.monotonic() - started,
    )
