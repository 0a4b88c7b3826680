"""cwsynth from Python: the CLI's results, to the bit, as dicts with NumPy curves.

    >>> import cwsynth
    >>> r = cwsynth.solve("problems/piston-1000rpm.toml")
    >>> r["status"], r["objectives"]
    >>> r["curves"]["<table>"]["<column>"]          # a numpy array

Every function calls the Rust library the `cwsynth` CLI calls (``cwsynth._cwsynth``);
the API is documented in ``docs/python.md``.
"""

from __future__ import annotations

import csv
import io
import json
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _cwsynth
from ._cwsynth import BatchError, ProblemError

__all__ = [
    "solve",
    "check",
    "schema",
    "batch",
    "merge",
    "ProblemError",
    "BatchError",
    "parse_table",
    "to_toml",
]
__version__ = _cwsynth.__version__

# The attributes of a ProblemError (set on every raised one; None where not known).
for _a in ("file", "line", "field", "message"):
    setattr(ProblemError, _a, None)

Problem = Union[str, "os.PathLike[str]", Mapping[str, Any]]


def _is_toml_text(s: str) -> bool:
    # A problem file's text always has `key = value`; a path to one has neither '=' nor a
    # newline (name such a path with pathlib.Path).
    return "\n" in s or "=" in s


def _source_kwargs(problem: Problem, source: Optional[str]) -> Dict[str, Any]:
    """The keyword arguments of the extension's solve/check for `problem`."""
    if isinstance(problem, Mapping):
        text = to_toml(problem)
        return {"text": text, "source": source or "<dict>"}
    if isinstance(problem, os.PathLike):
        return {"path": os.fspath(problem)}
    if isinstance(problem, str):
        if _is_toml_text(problem):
            return {"text": problem, "source": source or "<string>"}
        return {"path": problem}
    raise TypeError(
        f"problem: a TOML string, a path or a dict, not {type(problem).__name__}"
    )


def to_toml(problem: Mapping[str, Any]) -> str:
    """The TOML text a dict problem is solved as (written by the Rust toml crate; ``None``
    values left out). A dict's :class:`ProblemError` has its ``line`` in this text."""
    return _cwsynth.dict_to_toml(dict(problem))


def parse_table(text: str) -> Dict[str, np.ndarray]:
    """A result's CSV table as ``{column: numpy array}``: float64 where every cell is a
    number (an empty cell is NaN), else an array of str."""
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    out: Dict[str, np.ndarray] = {}
    for j, name in enumerate(header):
        cells = [r[j] if j < len(r) else "" for r in body]
        try:
            out[name] = np.array(
                [float(c) if c.strip() else np.nan for c in cells], dtype=np.float64
            )
        except ValueError:
            out[name] = np.array(cells, dtype=str)
    return out


def solve(
    problem: Problem,
    *,
    source: Optional[str] = None,
    complete: bool = False,
    curves: bool = True,
) -> Dict[str, Any]:
    """Solves one problem and returns its result.

    ``problem``: TOML text (a ``str`` holding ``=`` or a newline), a path (``str`` or
    ``pathlib.Path``) or a dict of the file's tables (``None`` values are left out). The dict
    is the JSON ``cwsynth solve --json`` prints for the same file (``json.loads`` of the
    library's own text, so every number is the CLI's), plus, with ``curves`` (default), the
    key ``"curves"``: ``{table suffix: {column: numpy array}}`` from the result's CSV tables
    (the ``<name>-<suffix>.csv`` files ``cwsynth solve --out`` writes). ``complete`` also
    computes the tables only written reports carry (a crane's landscape, say); the JSON keys
    are unchanged by it. ``source`` names text or a dict in messages and in ``source``
    (default ``<string>``, ``<dict>``). Raises :class:`ProblemError` for a bad problem.
    """
    text, tables = _cwsynth.solve(complete=complete, **_source_kwargs(problem, source))
    result = json.loads(text)
    if curves:
        result["curves"] = {suffix: parse_table(csv_text) for suffix, _, csv_text in tables}
    return result


def check(problem: Problem, *, source: Optional[str] = None) -> None:
    """Validates one problem without solving (``cwsynth check``): returns None or raises
    :class:`ProblemError` naming the file, line and field."""
    _cwsynth.check(**_source_kwargs(problem, source))


def schema() -> Dict[str, Any]:
    """The JSON Schema (draft 2020-12) of the problem file, every family: what
    ``cwsynth schema`` prints, as a dict."""
    return json.loads(_cwsynth.schema())


def _inputs(inputs: Union[str, "os.PathLike[str]", Iterable[Any]]) -> List[str]:
    """Batch inputs as the CLI's arguments: a file, a directory, ``TEMPLATE.toml:FLEET.csv``
    or a ``(template, csv)`` pair; one of them or a list."""
    if isinstance(inputs, (str, os.PathLike)) or (
        isinstance(inputs, tuple) and len(inputs) == 2 and all(isinstance(x, (str, os.PathLike)) for x in inputs)
        and str(inputs[1]).endswith(".csv")
    ):
        inputs = [inputs]
    out = []
    for i in inputs:
        if isinstance(i, tuple):
            template, fleet = i
            out.append(f"{os.fspath(template)}:{os.fspath(fleet)}")
        else:
            out.append(os.fspath(i))
    return out


def batch(
    inputs: Union[str, "os.PathLike[str]", Sequence[Any]],
    out: Union[str, "os.PathLike[str]"],
    *,
    threads: Optional[int] = None,
    shard: Optional[str] = None,
    quiet: bool = True,
    summary_only: bool = False,
    units: str = "workshop",
) -> Dict[str, int]:
    """``cwsynth batch INPUTS --out OUT``: the library's batch run, the same files as the
    CLI's. Returns the counts ``{"total", "ok", "failed", "skipped"}`` (the CLI exits 1 when
    ``failed > 0``). Raises :class:`BatchError` for what makes the CLI exit 2."""
    return _cwsynth.run_batch(
        _inputs(inputs),
        os.fspath(out),
        threads=threads,
        shard=shard,
        quiet=quiet,
        summary_only=summary_only,
        units=units,
    )


def merge(
    dirs: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]],
    out: Union[str, "os.PathLike[str]"],
) -> Dict[str, int]:
    """``cwsynth merge DIRS --out OUT``: joins shard summaries into ``OUT/summary.csv`` and
    its reports. Returns the counts."""
    if isinstance(dirs, (str, os.PathLike)):
        dirs = [dirs]
    return _cwsynth.merge([os.fspath(d) for d in dirs], os.fspath(out))
