"""Run `mtwin dataset` on a Ray cluster, one task per shard, and read the Parquet dataset.

>>> import mtwin_ray
>>> summary = mtwin_ray.generate("scenarios/vmc3_dataset_volumetric.toml", "/shared/ds",
...                              count=10_000, shards=40, mtwin="/opt/mtwin/bin/mtwin")
>>> cases = mtwin_ray.read("/shared/ds", "cases")
"""

from .driver import GenerateSummary, generate
from .layout import (
    DatasetError,
    layout_problem,
    manifest_problem,
    record_path,
    shard_problem,
    shard_range,
)
from .read import PARTITIONING, dataset, read, tables

__version__ = "0.1.0"

__all__ = [
    "PARTITIONING",
    "DatasetError",
    "GenerateSummary",
    "dataset",
    "generate",
    "layout_problem",
    "manifest_problem",
    "read",
    "record_path",
    "shard_problem",
    "shard_range",
    "tables",
]
