"""A bad problem raises cwsynth.ProblemError naming the file, the line and the field, as
the CLI's message does."""

from pathlib import Path

import pytest

import cwsynth
from conftest import REPO

BAD = "problems/errors/linkage-fourbar-not-grashof.toml"


def line_of(text, needle):
    return text[: text.index(needle)].count("\n") + 1


def test_shipped_error_file(cli, in_repo):
    with pytest.raises(cwsynth.ProblemError) as e:
        cwsynth.solve(BAD)
    err = e.value
    assert err.file == BAD
    assert err.field == "mechanism.dyads[0]"
    assert err.line == line_of(Path(BAD).read_text(), "[[mechanism.dyads]]")
    assert "the crank cannot turn fully" in err.message
    # The exception's text is the CLI's line.
    assert cli("check", BAD).stderr.strip() == f"error {err}"
    with pytest.raises(cwsynth.ProblemError):
        cwsynth.check(BAD)
    assert isinstance(err, ValueError)


def test_written_bad_file(tmp_path):
    text = (REPO / "problems/piston-1000rpm.toml").read_text()
    key = next(l for l in text.splitlines() if l.startswith("speed"))
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(key, "speed = 1000", 1))
    with pytest.raises(cwsynth.ProblemError) as e:
        cwsynth.solve(bad)
    assert e.value.file == str(bad)
    assert e.value.line == line_of(text, key)
    assert e.value.field == "mechanism.speed"
    assert "unit" in e.value.message


def test_text_and_dict_errors():
    with pytest.raises(cwsynth.ProblemError) as e:
        cwsynth.check('name = "x"\nfamily = "slider-crank"\n[mechanism\n', source="mine.toml")
    assert (e.value.file, e.value.line) == ("mine.toml", 3)
    with pytest.raises(cwsynth.ProblemError) as e:
        cwsynth.check({"name": "x", "family": "slider-crnk"})
    assert e.value.file == "<dict>" and e.value.field == "family"
    assert "did you mean `slider-crank`" in e.value.message


def test_missing_file():
    with pytest.raises(cwsynth.ProblemError) as e:
        cwsynth.solve(Path("no/such/file.toml"))
    assert e.value.file == "no/such/file.toml" and e.value.line is None and e.value.field is None


def test_hostile_dicts_raise_instead_of_crashing():
    """A dict that contains itself, or one nested 20,000 deep, raises; it used to overflow
    the stack and kill the interpreter."""
    selfish = {"name": "x", "family": "slider-crank"}
    selfish["mechanism"] = selfish
    deep = {}
    inner = deep
    for _ in range(20_000):
        inner["a"] = {}
        inner = inner["a"]
    listed = {"name": "x", "family": "slider-crank", "mechanism": {"crank_pivot": []}}
    listed["mechanism"]["crank_pivot"].append(listed["mechanism"]["crank_pivot"])
    for problem in (selfish, {"name": "x", "family": "slider-crank", "mechanism": deep}, listed):
        with pytest.raises(ValueError) as e:
            cwsynth.check(problem)
        assert "nested deeper than 64 levels" in str(e.value)
