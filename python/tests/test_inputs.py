"""A problem as a string, a path (str, pathlib.Path) or a dict gives the same result; check,
schema and batch are the CLI's."""

import csv
import io
import json
from pathlib import Path

import pytest

import cwsynth
from conftest import PROBLEMS, REPO, without

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

FILE = "problems/felling-head-150rpm.toml"


def comparable(r):
    """The result but its timing and source, as JSON text (curves' arrays as lists, NaN as
    NaN): equal text is equal values, bit for bit."""
    return json.dumps(without(r, "timing", "source"), default=lambda a: a.tolist(), sort_keys=True)


def test_str_path_dict_same_result(in_repo):
    by_str_path = cwsynth.solve(FILE)
    by_path = cwsynth.solve(Path(FILE))
    text = Path(FILE).read_text()
    by_text = cwsynth.solve(text)
    assert by_path["source"] == by_str_path["source"] == FILE
    assert by_text["source"] == "<string>"
    assert cwsynth.solve(text, source=FILE)["source"] == FILE
    ref = comparable(by_path)
    assert comparable(by_str_path) == ref
    assert comparable(by_text) == ref
    if tomllib is not None:
        by_dict = cwsynth.solve(tomllib.loads(text))
        assert by_dict["source"] == "<dict>"
        assert comparable(by_dict) == ref


def test_check(in_repo):
    assert cwsynth.check(FILE) is None
    assert cwsynth.check(Path(FILE).read_text()) is None


def test_schema_is_the_clis(cli):
    assert cwsynth.schema() == json.loads(cli("schema", check=True).stdout)


def test_batch_is_the_clis(cli, in_repo, tmp_path):
    inputs = ["problems/piston-1000rpm.toml", "problems/hypocycloid-variant1.toml"]
    cli("batch", *inputs, "--out", tmp_path / "cli", "--quiet", check=True)
    counts = cwsynth.batch(inputs, tmp_path / "py")
    assert counts == {"total": 2, "ok": 2, "failed": 0, "skipped": 0}
    for f in ["piston-1000rpm.json", "hypocycloid-variant1.md"]:
        assert (tmp_path / "py" / f).exists()
    a, b = (list(csv.DictReader(io.StringIO((tmp_path / d / "summary.csv").read_text())))
            for d in ("cli", "py"))
    assert [without(r, "time_s") for r in a] == [without(r, "time_s") for r in b]


def test_batch_errors(tmp_path):
    # A machine that fails is a row (the CLI exits 1); a usage error raises (the CLI's 2).
    assert cwsynth.batch(["no-such.toml"], tmp_path / "a")["failed"] == 1
    with pytest.raises(cwsynth.BatchError, match="need 0 ≤ i < n"):
        cwsynth.batch(["no-such.toml"], tmp_path / "b", shard="3/2")


@pytest.mark.skipif(tomllib is None, reason="tomllib needs Python ≥ 3.11")
@pytest.mark.parametrize("path", PROBLEMS, ids=[p.stem for p in PROBLEMS])
def test_dict_of_every_problem(in_repo, path):
    """Every shipped file read by tomllib and given as a dict (written back as TOML by the
    Rust toml crate) solves to the file's result, bit for bit. A dict has no folder: the
    drawings it reads (`outline.file`) are relative to the working directory, so the file's
    own paths (relative to its folder) are rewritten from the repository's root."""
    rel = path.relative_to(REPO).as_posix()
    problem = tomllib.loads(path.read_text())
    folder = path.parent.relative_to(REPO)

    def rebase(v):
        if isinstance(v, dict):
            if isinstance(v.get("outline"), dict) and "file" in v["outline"]:
                v["outline"]["file"] = (folder / v["outline"]["file"]).as_posix()
            for w in v.values():
                rebase(w)
        elif isinstance(v, list):
            for w in v:
                rebase(w)

    rebase(problem)
    assert comparable(cwsynth.solve(problem)) == comparable(cwsynth.solve(rel))
