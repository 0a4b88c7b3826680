"""Shared plumbing of the SciPy/cvxpy peers: read a problem file's values with their units,
time a solve in-process (median of k repeats), print the one JSON line run.py reads.

Kept deliberately small: the physics of each scene lives in its own script and does not
reuse cwsynth's code (the peers are an independent computation).
"""
import argparse
import json
import math
import re
import statistics
import time
import tomllib

_T0 = time.perf_counter()  # set when a peer imports this module, before numpy/scipy

# Units that occur in the four scenes' problem files (SI factor).
_UNITS = {
    "m": 1.0, "mm": 1e-3, "cm": 1e-2,
    "kg": 1.0, "g": 1e-3,
    "kg*m": 1.0, "kg m": 1.0, "kg·m": 1.0,
    "rad": 1.0, "deg": math.pi / 180.0,
    "rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0,
}


def q(text):
    """'35 mm' -> 0.035 (SI). A bare number is refused, as in cwsynth's files."""
    if not isinstance(text, str):
        raise ValueError(f"dimensional value without unit: {text!r}")
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*(.+?)\s*", text)
    if not m or m.group(2) not in _UNITS:
        raise ValueError(f"cannot read {text!r}")
    return float(m.group(1)) * _UNITS[m.group(2)]


def load(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def args(default_problem, extra=None):
    p = argparse.ArgumentParser()
    p.add_argument("problem", nargs="?", default=default_problem)
    p.add_argument("--repeats", type=int, default=5, help="in-process repeats (median reported)")
    if extra:
        extra(p)
    return p.parse_args()


def imports_done():
    """Seconds spent importing numpy/scipy/cvxpy (call right after the imports)."""
    return time.perf_counter() - _T0


def timed(fn, repeats):
    """Run fn() `repeats` times; return (last result, median seconds, all seconds)."""
    ts, out = [], None
    for _ in range(max(1, repeats)):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return out, statistics.median(ts), ts


def emit(**kw):
    print(json.dumps(kw, sort_keys=False))
