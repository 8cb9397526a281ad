"""The on-disk layout of an `mtwin dataset` folder (standard library only).

A dataset folder ``DIR`` holds, per shard ``I`` of ``S``, a record
``DIR/_shards/shard-IIIII-of-SSSSS.json`` written (temp + rename) after the shard's Parquet
files were renamed into place, and, once every shard has its record, ``DIR/manifest.json`` and
``DIR/README.md``. This module reads those records and tells whether a shard is complete; it
never writes anything.
"""

from __future__ import annotations

import hashlib
import json
import os
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

#: Folder of the shard records, relative to the dataset folder.
SHARDS_DIR = "_shards"
#: The merged record written by the process that wrote the last shard record.
MANIFEST = "manifest.json"


class DatasetError(RuntimeError):
    """A dataset folder is not what the command promised (missing or inconsistent records)."""


def shard_range(shard: int, shards: int, count: int) -> Tuple[int, int]:
    """Cases ``[first, end)`` of shard ``shard`` of ``shards`` for ``count`` cases."""
    if not 0 <= shard < shards:
        raise ValueError(f"shard {shard} is not in 0..{shards}")
    return shard * count // shards, (shard + 1) * count // shards


def record_path(out: os.PathLike, shard: int, shards: int) -> Path:
    """``DIR/_shards/shard-IIIII-of-SSSSS.json``."""
    return Path(out) / SHARDS_DIR / f"shard-{shard:05d}-of-{shards:05d}.json"


def load_json(path: os.PathLike) -> Optional[Dict[str, Any]]:
    """The JSON object in ``path``, or None when the file is missing or not a JSON object."""
    try:
        with open(path, "rb") as f:
            value = json.load(f)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except (OSError, ValueError):
        return None
    return value if isinstance(value, dict) else None


def sha256_file(path: os.PathLike, chunk: int = 1 << 20) -> str:
    """Hex SHA-256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while True:
            block = f.read(chunk)
            if not block:
                break
            h.update(block)
    return h.hexdigest()


def _file_problem(out: Path, entry: Any) -> Optional[str]:
    """Why one ``files`` entry of a record does not match the disk, or None when it does."""
    if not isinstance(entry, dict) or not isinstance(entry.get("path"), str):
        return f"malformed files entry {entry!r}"
    rel = entry["path"]
    if rel.startswith("/") or ".." in rel.split("/"):
        return f"file path {rel!r} is not inside the dataset folder"
    path = out.joinpath(*rel.split("/"))
    try:
        digest = sha256_file(path)
    except FileNotFoundError:
        return f"{rel} is missing"
    except OSError as e:
        return f"{rel} cannot be read: {e}"
    if digest != str(entry.get("sha256", "")).lower():
        return f"{rel} has sha256 {digest[:12]}…, the record says {str(entry.get('sha256'))[:12]}…"
    return None


def shard_problem(
    out: os.PathLike,
    shard: int,
    shards: int,
    count: Optional[int] = None,
    *,
    workers: int = 4,
) -> Optional[str]:
    """Why shard ``shard`` of ``shards`` in ``out`` is not complete, or None when it is.

    Complete means what `mtwin dataset` itself checks before skipping a shard: the record is
    there and every file it lists is there with the recorded SHA-256. With ``count``, the
    record must also be for that many cases (a folder made with another ``--count`` is never
    taken as done).
    """
    out = Path(out)
    path = record_path(out, shard, shards)
    record = load_json(path)
    if record is None:
        return (
            f"no record {path.relative_to(out).as_posix()}"
            if not path.exists()
            else (f"record {path.relative_to(out).as_posix()} is not a JSON object")
        )
    dataset = record.get("dataset") if isinstance(record.get("dataset"), dict) else {}
    if record.get("shard") != shard or dataset.get("shards") != shards:
        return f"record says shard {record.get('shard')} of {dataset.get('shards')}"
    if count is not None:
        if dataset.get("count") != count:
            return f"record is for {dataset.get('count')} cases, not {count}"
        first, end = shard_range(shard, shards, count)
        if (record.get("first_case"), record.get("end_case")) != (first, end):
            return (
                f"record holds cases [{record.get('first_case')}, {record.get('end_case')}),"
                f" not [{first}, {end})"
            )
    files = record.get("files")
    if not isinstance(files, list):
        return "record has no files list"
    if workers > 1 and len(files) > 1:
        with ThreadPoolExecutor(max_workers=min(workers, len(files))) as pool:
            problems = list(pool.map(lambda e: _file_problem(out, e), files))
    else:
        problems = [_file_problem(out, e) for e in files]
    problems = [p for p in problems if p]
    if problems:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        return problems[0] + more
    return None


def layout_problem(out: os.PathLike, shards: int, count: int) -> Optional[str]:
    """Why the records in ``out/_shards`` are not all of one dataset of ``count`` cases in
    ``shards`` shards, or None. `mtwin dataset` refuses such a folder ("holds shards of
    another dataset"); the driver says so before submitting anything. Unreadable records are
    ignored (their shards are redone)."""
    folder = Path(out) / SHARDS_DIR
    if not folder.is_dir():
        return None
    identities: Dict[str, Any] = {}
    for path in sorted(folder.glob("*.json")):
        record = load_json(path)
        if record is None:
            continue
        dataset = record.get("dataset")
        if not isinstance(dataset, dict):
            continue
        if dataset.get("count") != count or dataset.get("shards") != shards:
            return (
                f"{path} is a record of a dataset of {dataset.get('count')} cases in"
                f" {dataset.get('shards')} shards, not {count} in {shards}: give another"
                " output folder or remove this one"
            )
        identities.setdefault(json.dumps(dataset, sort_keys=True), path)
    if len(identities) > 1:
        paths = list(identities.values())
        return (
            f"{paths[0].name} and {paths[1].name} are records of different datasets (another"
            " scenario, machine model or seed): give another output folder or remove this one"
        )
    return None


def file_key(entry: Dict[str, Any]) -> Tuple[str, int, str]:
    """(path, rows, sha256) of one ``files`` entry, for comparing records and manifests."""
    return (
        str(entry.get("path")),
        int(entry.get("rows", -1)),
        str(entry.get("sha256", "")).lower(),
    )


def manifest_problem(out: os.PathLike, shards: int, count: Optional[int] = None) -> Optional[str]:
    """Why ``out/manifest.json`` does not list exactly the files of the ``shards`` records.

    Checks that the manifest exists, is for ``shards`` shards (and ``count`` cases when given),
    and that its ``files`` are the union of the shard records' ``files`` (path, rows, sha256).
    Files are not hashed again here: the records were checked (or just written).
    """
    out = Path(out)
    manifest = load_json(out / MANIFEST)
    if manifest is None:
        return f"{out / MANIFEST} is missing or not a JSON object"
    dataset = manifest.get("dataset") if isinstance(manifest.get("dataset"), dict) else {}
    if dataset.get("shards") != shards:
        return f"manifest is for {dataset.get('shards')} shards, not {shards}"
    if count is not None and dataset.get("count") != count:
        return f"manifest is for {dataset.get('count')} cases, not {count}"
    expected: List[Tuple[str, int, str]] = []
    for shard in range(shards):
        record = load_json(record_path(out, shard, shards))
        if record is None:
            return f"shard {shard} has no record"
        if isinstance(record.get("dataset"), dict) and record["dataset"] != dataset:
            return f"shard {shard}'s record is for another dataset than the manifest"
        expected.extend(file_key(e) for e in record.get("files", []))
    listed = [file_key(e) for e in manifest.get("files", []) if isinstance(e, dict)]
    if sorted(listed) != sorted(expected):
        missing = sorted(set(expected) - set(listed))
        extra = sorted(set(listed) - set(expected))
        detail = []
        if missing:
            detail.append(
                f"{len(missing)} record file(s) not in the manifest, e.g. {missing[0][0]}"
            )
        if extra:
            detail.append(f"{len(extra)} manifest file(s) in no record, e.g. {extra[0][0]}")
        return "manifest does not match the shard records: " + "; ".join(detail or ["duplicates"])
    return None


def manifest_tables(out: os.PathLike) -> List[str]:
    """The tables of a dataset (first path component of the manifest's files), sorted."""
    manifest = load_json(Path(out) / MANIFEST)
    if manifest is None:
        raise DatasetError(f"{Path(out) / MANIFEST} is missing or not a JSON object")
    return sorted({str(e["path"]).split("/", 1)[0] for e in manifest.get("files", [])})
