"""Fleets on Dask: each partition of a fleet's rows is one Dask task running the Rust batch
code on a shard (``cwsynth batch --shard i/n --summary-only``); the driver joins the shard
summaries as ``cwsynth merge`` does. The summary equals the CLI's ``cwsynth batch`` summary
byte for byte apart from the ``time_s`` column.

The template and the CSV must be readable by every worker under the same path (a shared
file system; a relative path is taken from each worker's working directory), and are
written into the summary as given, as the CLI does.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Dict, Optional, Tuple, Union

from . import _cwsynth, batch, merge

PathLike = Union[str, "os.PathLike[str]"]


def _solve_shard(fleet: str, i: int, n: int, threads: int) -> Tuple[int, bytes]:
    """One Dask task: shard ``i/n`` of ``fleet`` solved into a temporary directory; returns
    the shard's summary CSV (bytes)."""
    tmp = tempfile.mkdtemp(prefix=f"cwsynth-shard-{i}-of-{n}-")
    try:
        batch([fleet], tmp, threads=threads, shard=f"{i}/{n}", quiet=True, summary_only=True)
        return i, (Path(tmp) / _cwsynth.summary_name((i, n))).read_bytes()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def solve_fleet(
    template: PathLike,
    fleet_csv: PathLike,
    client: Any,
    partitions: Optional[int] = None,
    *,
    out: Optional[PathLike] = None,
    threads_per_task: int = 1,
) -> Dict[str, Any]:
    """Solves the fleet ``template:fleet_csv`` on the Dask ``client``'s workers.

    ``partitions``: how many tasks (shards ``i/partitions``, rows ``index % partitions ==
    i``); default, the cluster's total worker threads. Each task solves its shard with
    ``threads_per_task`` Rust threads (default 1: Dask's threads are the parallelism).
    ``out``: where ``summary.csv``, ``summary.md``, ``index.html`` and the fleet's table
    ``fleet-<stem>.csv`` are written, as ``cwsynth batch --summary-only --out OUT`` writes
    them (default: a new temporary directory). Returns the counts ``{"total", "ok",
    "failed", "skipped"}`` and ``"summary"``, the path of ``summary.csv``.
    """
    fleet = f"{os.fspath(template)}:{os.fspath(fleet_csv)}"
    if partitions is None:
        partitions = max(1, sum(client.nthreads().values()))
    n = int(partitions)
    if n < 1:
        raise ValueError("partitions must be ≥ 1")
    out = Path(out) if out is not None else Path(tempfile.mkdtemp(prefix="cwsynth-fleet-"))
    out.mkdir(parents=True, exist_ok=True)
    futures = [
        client.submit(_solve_shard, fleet, i, n, threads_per_task, pure=False) for i in range(n)
    ]
    shards = tempfile.mkdtemp(prefix="cwsynth-shards-", dir=out)
    try:
        for i, data in client.gather(futures):
            (Path(shards) / _cwsynth.summary_name((i, n))).write_bytes(data)
        counts = merge([shards], out)
    finally:
        shutil.rmtree(shards, ignore_errors=True)
    _cwsynth.fleet_tables([fleet], os.fspath(out))
    counts["summary"] = out / "summary.csv"
    return counts
