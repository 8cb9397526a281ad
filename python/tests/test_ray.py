"""The Ray driver against the real `mtwin dataset`, on a local Ray cluster the test starts.

Needs ``MTWIN_BIN``: the release binary (``python/ci.sh`` sets it). Uses no network.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

MTWIN_BIN = os.environ.get("MTWIN_BIN")
pytestmark = pytest.mark.skipif(
    not MTWIN_BIN,
    reason="MTWIN_BIN is not set: `cargo build --release`, then "
    "MTWIN_BIN=$CARGO_TARGET_DIR/release/mtwin pytest (python/ci.sh does both)",
)

# Before Ray is imported anywhere: no usage report (no network), and no token auth (recent Ray,
# 2.60 but not 2.40, turns it on for a new local cluster and writes ~/.ray/auth_token).
os.environ["RAY_USAGE_STATS_ENABLED"] = "0"
os.environ.setdefault("RAY_AUTH_MODE", "disabled")

import pyarrow as pa  # noqa: E402
import pyarrow.parquet as pq  # noqa: E402

import mtwin_ray  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SCENARIO = REPO / "scenarios" / "vmc3_dataset_volumetric.toml"
BALLBAR = REPO / "scenarios" / "vmc3_dataset_ballbar.toml"
EXAMPLE = REPO / "python" / "examples" / "join_cases.py"
SBATCH = REPO / "python" / "slurm" / "mtwin_dataset.sbatch"
COUNT = 24
SHARDS = 4
PARTITIONS = {"machine", "split", "shard"}


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def snapshot(root: Path) -> dict:
    """Every file under root (relative path → (mtime_ns, sha256))."""
    return {
        p.relative_to(root).as_posix(): (p.stat().st_mtime_ns, sha256(p))
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


def manifest_files(root: Path) -> list:
    manifest = json.loads((root / "manifest.json").read_text())
    return sorted((f["path"], f["rows"], f["sha256"]) for f in manifest["files"])


@pytest.fixture(scope="module")
def ray_cluster():
    import ray

    if not Path(MTWIN_BIN).is_file():
        pytest.fail(f"MTWIN_BIN={MTWIN_BIN} does not exist")
    if not SCENARIO.is_file():
        pytest.fail(f"{SCENARIO} does not exist")
    ray.init(num_cpus=2, include_dashboard=False, logging_level="warning")
    yield ray
    ray.shutdown()


@pytest.fixture(scope="module")
def single(tmp_path_factory) -> Path:
    """The dataset made by one `mtwin dataset` process (every shard)."""
    out = tmp_path_factory.mktemp("single") / "A"
    subprocess.run(
        [
            MTWIN_BIN,
            "dataset",
            str(SCENARIO),
            "--count",
            str(COUNT),
            "--shards",
            str(SHARDS),
            "--out",
            str(out),
        ],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return out


@pytest.fixture(scope="module")
def driven(ray_cluster, tmp_path_factory) -> Path:
    """The dataset made by the Ray driver, one task per shard."""
    out = tmp_path_factory.mktemp("ray") / "B"
    summary = mtwin_ray.generate(SCENARIO, out, COUNT, SHARDS, mtwin=MTWIN_BIN)
    assert summary.shards_run == list(range(SHARDS))
    assert summary.shards_skipped == []
    assert summary.manifest == out / "manifest.json"
    return out


def test_manifests_list_the_same_files(single, driven):
    a = json.loads((single / "manifest.json").read_text())
    b = json.loads((driven / "manifest.json").read_text())
    assert a["dataset"] == b["dataset"]
    assert a["dataset"]["count"] == COUNT and a["dataset"]["shards"] == SHARDS
    assert manifest_files(single) == manifest_files(driven)
    paths = [f["path"] for f in b["files"]]
    assert paths == sorted(paths), "manifest files are sorted by path"
    for root in (single, driven):
        assert (root / "README.md").is_file()
        for shard in range(SHARDS):
            record = json.loads(mtwin_ray.record_path(root, shard, SHARDS).read_text())
            assert record["shard"] == shard
            assert (record["first_case"], record["end_case"]) == mtwin_ray.shard_range(
                shard, SHARDS, COUNT
            )
        for path, rows, digest in manifest_files(root):
            assert sha256(root / path) == digest, path
            assert pq.ParquetFile(root / path).metadata.num_rows == rows, path
    # Byte-identical shards: the same file names and contents in both folders.
    tables = lambda r: {  # noqa: E731
        p.relative_to(r).as_posix(): sha256(p)
        for p in r.rglob("*.parquet")
        if ".tmp" not in p.parts
    }
    assert tables(single) == tables(driven)
    # …and so is everything else: the manifest and the dataset card.
    for name in ("manifest.json", "README.md"):
        assert (single / name).read_bytes() == (driven / name).read_bytes(), name


def test_tables_read_equal_with_the_documented_schema(single, driven):
    names = mtwin_ray.tables(driven)
    assert names == mtwin_ray.tables(single)
    assert "cases" in names and len(names) >= 2, names
    cases = mtwin_ray.read(driven, "cases")
    assert cases.num_rows == COUNT
    assert cases.column("case_id").to_pylist() == list(range(COUNT))
    split_of = dict(zip(cases.column("case_id").to_pylist(), cases.column("split").to_pylist()))
    assert set(split_of.values()) <= {"train", "test"}
    for name in names:
        a = mtwin_ray.read(single, name)
        b = mtwin_ray.read(driven, name)
        assert a.equals(b), name
        schema = b.schema
        assert schema.field("case_id").type == pa.int64(), name
        assert schema.field("machine").type == pa.string()
        assert schema.field("split").type == pa.string()
        for f in schema:
            if f.name in PARTITIONS or f.name == "case_id":
                continue
            if name == "cases":
                # case_seed (u64 bits as int64), then one double per sampled parameter.
                expected = pa.int64() if f.name == "case_seed" else pa.float64()
                assert f.type == expected, (name, f)
            else:
                assert f.type in (pa.float64(), pa.string(), pa.large_string()), (name, f)
        # The Parquet files themselves carry case_id as int64 and no split column.
        first = next((driven / name).rglob("*.parquet"))
        file_schema = pq.read_schema(first)
        assert file_schema.field("case_id").type == pa.int64()
        assert "split" not in file_schema.names
        if name == "cases":
            assert file_schema.field("case_seed").type == pa.int64()
            assert len(file_schema.names) > 2, "no sampled parameter column"
        else:
            # A measurement table: every case has rows, each in the split of its case.
            ids = b.column("case_id").to_pylist()
            assert set(ids) == set(range(COUNT)), name
            for case_id, split in zip(ids, b.column("split").to_pylist()):
                assert split_of[case_id] == split, (name, case_id)
            if name == "volumetric":
                per_case = {k: ids.count(k) for k in set(ids)}
                assert set(per_case.values()) == {225}, "the scenario maps 225 points per case"


def test_rerun_skips_every_shard_and_touches_nothing(driven):
    before = snapshot(driven)
    summary = mtwin_ray.generate(SCENARIO, driven, COUNT, SHARDS, mtwin=MTWIN_BIN)
    assert summary.shards_run == []
    assert summary.shards_skipped == list(range(SHARDS))
    assert snapshot(driven) == before


def _record(root: Path, shard: int) -> tuple:
    path = mtwin_ray.record_path(root, shard, SHARDS)
    return path, json.loads(path.read_text())


def test_a_damaged_shard_and_only_it_runs_again(single, driven, tmp_path):
    out = tmp_path / "C"
    shutil.copytree(driven, out)

    # 1. A wrong sha256 in shard 1's record.
    path, record = _record(out, 1)
    record["files"][0]["sha256"] = "0" * 64
    path.write_text(json.dumps(record))
    assert "sha256" in mtwin_ray.shard_problem(out, 1, SHARDS, COUNT)
    before = snapshot(out)
    summary = mtwin_ray.generate(SCENARIO, out, COUNT, SHARDS, mtwin=MTWIN_BIN)
    assert summary.shards_run == [1]
    assert summary.shards_skipped == [0, 2, 3]
    after = snapshot(out)
    untouched = [
        p
        for p in before
        if "/shard=1/" not in p
        and "shard-00001" not in p
        and p not in ("manifest.json", "README.md")
    ]
    assert untouched and all(after[p] == before[p] for p in untouched)
    assert manifest_files(out) == manifest_files(single)
    assert mtwin_ray.shard_problem(out, 1, SHARDS, COUNT) is None

    # 2. A file of shard 2 deleted.
    _, record = _record(out, 2)
    victim = out / record["files"][-1]["path"]
    victim.unlink()
    before = snapshot(out)
    summary = mtwin_ray.generate(SCENARIO, out, COUNT, SHARDS, mtwin=MTWIN_BIN)
    assert summary.shards_run == [2]
    assert "missing" in summary.reasons[2]
    after = snapshot(out)
    untouched = [
        p
        for p in before
        if "/shard=2/" not in p
        and "shard-00002" not in p
        and p not in ("manifest.json", "README.md")
    ]
    assert all(after[p] == before[p] for p in untouched)
    assert sha256(victim) == sha256(single / victim.relative_to(out))
    assert manifest_files(out) == manifest_files(single)


def test_shipped_binary(ray_cluster, single, tmp_path):
    """ship_binary: the tasks run a copy sent through the object store (/tmp/mtwin-<sha>)."""
    out = tmp_path / "H"
    summary = mtwin_ray.generate(SCENARIO, out, COUNT, SHARDS, mtwin=MTWIN_BIN, ship_binary=True)
    assert summary.shards_run == list(range(SHARDS))
    assert (out / "manifest.json").read_bytes() == (single / "manifest.json").read_bytes()


def test_a_process_that_fails_once_is_retried(ray_cluster, single, tmp_path):
    flaky = tmp_path / "flaky-mtwin"
    flaky.write_text(
        "#!/bin/bash\n"
        "# Fails the first attempt of every shard, then runs the real mtwin.\n"
        'shard=$(printf "%s\\n" "$@" | grep -A1 -x -- --shard | tail -n1 | cut -d/ -f1)\n'
        'if [ ! -e "$MARKERS/$shard" ]; then touch "$MARKERS/$shard"; '
        'echo "flaky: first attempt of shard $shard" >&2; exit 3; fi\n'
        'exec "$REAL_MTWIN" "$@"\n'
    )
    flaky.chmod(0o755)
    markers = tmp_path / "markers"
    markers.mkdir()
    out = tmp_path / "R"
    summary = mtwin_ray.generate(
        SCENARIO,
        out,
        COUNT,
        SHARDS,
        mtwin=flaky,
        max_retries=1,
        env={"MARKERS": str(markers), "REAL_MTWIN": MTWIN_BIN},
    )
    assert summary.shards_run == list(range(SHARDS))
    assert sorted(p.name for p in markers.iterdir()) == [str(i) for i in range(SHARDS)]
    assert manifest_files(out) == manifest_files(single)


def test_a_failing_process_raises_with_its_stderr(ray_cluster, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('schema = 1\nmachine = "no-such-machine.urdf"\n')
    with pytest.raises(mtwin_ray.DatasetError) as caught:
        mtwin_ray.generate(bad, tmp_path / "D", 4, 2, mtwin=MTWIN_BIN, max_retries=0)
    message = str(caught.value)
    assert "2 of 2 shard(s) failed" in message
    assert "exit code" in message and "stderr:" in message
    assert "(empty)" not in message, "mtwin said nothing on stderr"


def test_join_example_prints_one_line_per_case(driven):
    result = subprocess.run(
        [sys.executable, str(EXAMPLE), str(driven)], check=True, capture_output=True, text=True
    )
    lines = [line for line in result.stdout.splitlines() if line.strip()]
    assert len(lines) == COUNT + 1, result.stdout  # a header, then one line per case


def test_a_missing_manifest_is_written_again(single, driven, tmp_path):
    out = tmp_path / "E"
    shutil.copytree(driven, out)
    (out / "manifest.json").unlink()
    summary = mtwin_ray.generate(SCENARIO, out, COUNT, SHARDS, mtwin=MTWIN_BIN)
    # Every shard was complete: the last one runs (and skips its work) to write the manifest.
    assert summary.shards_run == [SHARDS - 1]
    assert (out / "manifest.json").read_bytes() == (single / "manifest.json").read_bytes()
    assert snapshot(out).keys() == snapshot(driven).keys()


def test_a_folder_of_another_layout_is_refused_before_running(driven):
    before = snapshot(driven)
    with pytest.raises(mtwin_ray.DatasetError, match="not 25 in 4"):
        mtwin_ray.generate(SCENARIO, driven, COUNT + 1, SHARDS, mtwin=MTWIN_BIN)
    with pytest.raises(ValueError, match="at most one shard per case"):
        mtwin_ray.generate(SCENARIO, driven, 3, SHARDS, mtwin=MTWIN_BIN)
    assert snapshot(driven) == before


def test_command_line_on_the_running_cluster(ray_cluster, single, driven, tmp_path):
    address = ray_cluster.get_runtime_context().gcs_address
    out = tmp_path / "F"
    base = [
        sys.executable,
        "-m",
        "mtwin_ray",
        str(SCENARIO),
        "--count",
        str(COUNT),
        "--shards",
        str(SHARDS),
        "--out",
        str(out),
        "--mtwin",
        MTWIN_BIN,
    ]
    run = subprocess.run([*base, "--address", address], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert f"{SHARDS} shard(s) run, 0 skipped" in run.stdout
    assert manifest_files(out) == manifest_files(single)
    check = subprocess.run([*base, "--check"], capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    assert f"{SHARDS} of {SHARDS} shard(s) complete, manifest ok" in check.stdout
    mtwin_ray.record_path(out, 0, SHARDS).unlink()
    check = subprocess.run([*base, "--check"], capture_output=True, text=True)
    assert check.returncode == 1 and "shard 0/4: no record" in check.stdout, check.stdout


def test_slurm_array_script_without_slurm(single, tmp_path):
    """The sbatch script as Slurm would run it: two arrays of 2 tasks (OFFSET 0 and 2), the
    four tasks at once, and an index beyond the last shard."""
    out = tmp_path / "G"
    env = dict(
        os.environ,
        SCENARIO=str(SCENARIO),
        COUNT=str(COUNT),
        SHARDS=str(SHARDS),
        OUT=str(out),
        MTWIN=MTWIN_BIN,
        SLURM_CPUS_PER_TASK="1",
    )
    tasks = [
        subprocess.Popen(
            ["bash", str(SBATCH)],
            env=dict(env, SLURM_ARRAY_TASK_ID=str(i), OFFSET=str(offset)),
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
        )
        for offset in (0, 2)
        for i in (0, 1)
    ]
    for task in tasks:
        output = task.communicate()[0].decode()
        assert task.returncode == 0, output
    beyond = subprocess.run(
        ["bash", str(SBATCH)],
        env=dict(env, SLURM_ARRAY_TASK_ID="2", OFFSET="2"),
        capture_output=True,
        text=True,
    )
    assert beyond.returncode == 0 and "nothing to do" in beyond.stdout
    assert (out / "manifest.json").read_bytes() == (single / "manifest.json").read_bytes()
    assert manifest_files(out) == manifest_files(single)


@pytest.mark.skipif(not BALLBAR.is_file(), reason=f"no {BALLBAR.name}")
def test_text_columns_and_a_csv_column_named_like_a_partition(ray_cluster, tmp_path):
    """The ball-bar table has text columns, and its CSV's preamble has a `machine` line, the
    name of a partition key: it is the column `meta_machine`, so no reader sees two `machine`
    fields."""
    a, b = tmp_path / "bA", tmp_path / "bB"
    subprocess.run(
        [MTWIN_BIN, "dataset", str(BALLBAR), "--count", "4", "--shards", "2", "--out", str(a)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    mtwin_ray.generate(BALLBAR, b, 4, 2, mtwin=MTWIN_BIN)
    assert manifest_files(a) == manifest_files(b)
    for name in mtwin_ray.tables(b):
        ta, tb = mtwin_ray.read(a, name), mtwin_ray.read(b, name)
        assert ta.equals(tb), name
        assert tb.schema.field("case_id").type == pa.int64()
        for f in tb.schema:
            if f.name not in PARTITIONS | {"case_id", "case_seed"}:
                assert f.type in (pa.float64(), pa.string()), (name, f)
    ballbar = mtwin_ray.read(b, "ballbar_xy")
    assert ballbar.schema.field("plane").type == pa.string()
    assert set(ballbar.column("meta_machine").to_pylist()) == {"vmc3"}
    assert set(ballbar.column("machine").to_pylist()) == {"vmc3"}  # the partition key
