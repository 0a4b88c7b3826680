"""The package's results equal the CLI's `solve --json` for every shipped problem, and its
curves are the CSV tables `solve --out` writes."""

import numpy as np
import pytest

import cwsynth
from conftest import PROBLEMS, REPO, cli_json, without


@pytest.mark.parametrize("path", PROBLEMS, ids=[p.stem for p in PROBLEMS])
def test_equals_cli_json(cli, in_repo, path):
    rel = path.relative_to(REPO).as_posix()
    want = cli_json(cli, rel)
    got = cwsynth.solve(rel)
    assert "curves" in got
    # json.loads of the library's own JSON text on both sides: equal dicts are equal bits.
    assert without(got, "curves", "timing", "batch") == without(want, "timing", "batch")
    assert set(got["timing"]) == set(want["timing"])


@pytest.mark.parametrize(
    "name", ["crane-thesis-example", "gear-tooth-profiles", "linkage-fourbar-pareto"]
)
def test_curves_are_the_written_tables(cli, in_repo, tmp_path, name):
    rel = f"problems/{name}.toml"
    cli("solve", rel, "--out", tmp_path, check=True)
    got = cwsynth.solve(rel, complete=True)
    files = sorted(tmp_path.glob(f"{got['name']}-*.csv"))
    assert files
    assert {f.name[len(got["name"]) + 1 : -4] for f in files} == set(got["curves"])
    for f in files:
        want = cwsynth.parse_table(f.read_text())
        table = got["curves"][f.name[len(got["name"]) + 1 : -4]]
        assert list(table) == list(want)
        for col, arr in table.items():
            assert isinstance(arr, np.ndarray)
            if arr.dtype.kind == "f":
                assert np.array_equal(arr, want[col], equal_nan=True), (f.name, col)
            else:
                assert list(arr) == list(want[col]), (f.name, col)


def test_curves_without_complete_are_a_subset(in_repo):
    base = cwsynth.solve("problems/crane-thesis-example.toml")
    full = cwsynth.solve("problems/crane-thesis-example.toml", complete=True)
    assert set(base["curves"]) < set(full["curves"])
    assert without(base, "curves", "timing") == without(full, "curves", "timing")
    assert np.issubdtype(base["curves"]["path"][next(iter(base["curves"]["path"]))].dtype, np.floating)
