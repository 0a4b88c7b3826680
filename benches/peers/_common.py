"""Shared plumbing of the SciPy/cvxpy peers: read a problem file's values with their units,
time a solve in-process (one warm-up call, then the median of k warm repeats), print the one
JSON line run.py reads. Importing it pins the BLAS/OpenMP thread pools to one thread (unless
the environment already sets them), before the peer imports NumPy.

Kept deliberately small: the physics of each scene lives in its own script and does not
reuse cwsynth's code (the peers are an independent computation).
"""
import argparse
import json
import math
import os
import re
import statistics
import time
import tomllib

_T0 = time.perf_counter()  # set when a peer imports this module, before numpy/scipy

# One thread for every BLAS/OpenMP pool (read by NumPy's OpenBLAS, MKL, Accelerate, numexpr
# when they load, i.e. at `import numpy`): the peers run single-threaded, like a benchmark
# that should not depend on how many cores happen to be idle. run.py sets the same values.
THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
               "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")
for _v in THREAD_VARS:
    os.environ.setdefault(_v, "1")

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
    p.add_argument("--repeats", type=int, default=7,
                   help="warm in-process repeats after one warm-up call (their median is reported)")
    if extra:
        extra(p)
    return p.parse_args()


def imports_done():
    """Seconds spent importing numpy/scipy/cvxpy (call right after the imports)."""
    return time.perf_counter() - _T0


def timed(fn, repeats):
    """Call fn() once to warm up (first-call costs: lazy imports inside SciPy/cvxpy, caches,
    page faults), then `repeats` more times. Return (last result, median seconds of the warm
    calls, the warm calls' seconds, the first call's seconds); the first call is not in the
    median."""
    t = time.perf_counter()
    out = fn()
    cold = time.perf_counter() - t
    ts = []
    for _ in range(max(1, repeats)):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return out, statistics.median(ts), ts, cold


def emit(**kw):
    """Print the JSON line run.py reads, with the thread settings the peer ran under."""
    kw["threads"] = {v: os.environ.get(v) for v in THREAD_VARS}
    print(json.dumps(kw, sort_keys=False))
