#!/usr/bin/env python3
"""cwsynth from Python in a few lines (after `pip install ./python`; docs/python.md).

    python examples/python_quickstart.py

Solves the paper's piston from its file, then a variant edited as a dict, prints the
optimum with its error bound, and reads a curve as NumPy arrays; a bad value shows the
exception naming file, line and field.
"""
import tomllib  # Python ≥ 3.11; on 3.9/3.10 `pip install tomli` and `import tomli as tomllib`
from pathlib import Path

import cwsynth

repo = Path(__file__).resolve().parents[1]
piston = repo / "problems" / "piston-1000rpm.toml"

# 1. A problem file: the result is the CLI's `cwsynth solve --json` as a dict.
r = cwsynth.solve(piston)
key = r["objective"]
print(f"{r['name']}: {r['status']}, {key} = {r['objectives'][key]:.6g} ± {r['errors'][key]:.1e}")

# 2. The same machine edited as a dict: twice the speed.
problem = tomllib.loads(piston.read_text())
problem["name"] = "piston-2x"
problem["mechanism"]["speed"] = "2000 rpm"
r2 = cwsynth.solve(problem)
print(f"{r2['name']}: {key} = {r2['objectives'][key]:.6g} N at 2000 rpm")

# 3. Curves: every CSV table of a result as {column: numpy array}.
gear = cwsynth.solve(repo / "problems" / "gear-paper-table1.toml")
for suffix, table in gear["curves"].items():
    cols = ", ".join(f"{c} ({len(a)})" for c, a in list(table.items())[:3])
    print(f"  curve {suffix}: {cols}, …")

# 4. A bad value: a clear error with file, line and field.
problem["mechanism"]["speed"] = 2000  # no unit: units are never guessed
try:
    cwsynth.check(problem, source="my-piston.toml")
except cwsynth.ProblemError as e:
    print(f"rejected: file {e.file}, line {e.line}, field {e.field}: {e.message[:60]}…")
