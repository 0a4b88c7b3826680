"""A fleet solved on a local Dask cluster of 2 workers gives the CLI's `cwsynth batch`
summary, byte for byte apart from the timing column, and the same fleet table."""

import csv
import io
import subprocess
import sys

import pytest

distributed = pytest.importorskip("distributed")

from cwsynth.dask import solve_fleet  # noqa: E402
from conftest import REPO  # noqa: E402

TEMPLATE = REPO / "problems" / "piston-1000rpm.toml"


def rows_without_time(text):
    rows = list(csv.reader(io.StringIO(text)))
    t = rows[0].index("time_s")
    return [r[:t] + r[t + 1 :] for r in rows]


def unparse(rows):
    s = io.StringIO()
    csv.writer(s, lineterminator="\n").writerows(rows)
    return s.getvalue()


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as c:
        yield c


@pytest.mark.parametrize("partitions", [None, 3])
def test_fleet_on_dask_equals_cli_batch(cli, client, tmp_path, partitions):
    fleet = tmp_path / "fleet.csv"
    subprocess.run(
        [sys.executable, REPO / "scripts" / "make_fleet.py", "200", "--broken", "0.05",
         "-o", fleet],
        check=True,
    )
    want = tmp_path / "cli"
    r = cli("batch", f"{TEMPLATE}:{fleet}", "--out", want, "--summary-only", "--quiet")
    assert r.returncode == 1, r.stderr  # the broken rows fail
    got = solve_fleet(TEMPLATE, fleet, client, partitions, out=tmp_path / "dask")
    assert got["total"] == 200 and 0 < got["failed"] < 30
    assert got["ok"] + got["failed"] == 200
    a = (want / "summary.csv").read_text()
    b = got["summary"].read_text()
    assert a.count("\n") == b.count("\n") == 201
    assert rows_without_time(a) == rows_without_time(b)
    # Byte for byte apart from the timing cells: each file is its rows written back (so its
    # bytes are its cells'), and the rows are equal but for time_s.
    for text in (a, b):
        assert unparse(list(csv.reader(io.StringIO(text)))) == text
    assert (want / "fleet-fleet.csv").read_bytes() == (tmp_path / "dask" / "fleet-fleet.csv").read_bytes()
    assert (tmp_path / "dask" / "index.html").exists()
    assert (tmp_path / "dask" / "summary.md").exists()
    assert not list((tmp_path / "dask").glob("summary-shard-*"))
