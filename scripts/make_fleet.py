#!/usr/bin/env python3
"""Writes a fleet CSV of N slider-crank machines for `problems/piston-1000rpm.toml`.

    scripts/make_fleet.py N [--seed S] [--broken FRACTION] > fleet.csv
    cwsynth batch problems/piston-1000rpm.toml:fleet.csv --out out/

The first column names each machine by its speed and row (`piston-1834rpm-00017`), the others
are dotted keys of the template, each header with its unit (`mechanism.speed [rpm]`):
cells are bare numbers in that unit (units are never guessed: a dimensional column needs a
unit in its header or in each cell). Values vary deterministically
(a seeded PRNG) around the paper's piston: crank radius 25–45 mm, rod/crank ratio 3–5,
crank 0.2–0.5 kg, rod 0.2–0.45 kg, slider 0.6–1.5 kg, speed 600–3000 rpm. With
--broken F, about F of the rows are broken on purpose, each in one of several ways (a
negative length, a rod shorter than the crank, an unknown unit, a bad number, an unknown
column value); the batch must report each with its reason and solve the others.
"""
import argparse
import random
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int, help="number of machines (rows)")
    ap.add_argument("--seed", type=int, default=1, help="PRNG seed (default 1)")
    ap.add_argument("--broken", type=float, default=0.0, help="fraction of broken rows, e.g. 0.05")
    ap.add_argument("-o", "--output", help="output file (default: stdout)")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    out = open(a.output, "w", newline="") if a.output else sys.stdout
    out.write("name,mechanism.crank_radius [mm],mechanism.rod_length [mm],mechanism.crank_mass [kg],"
              "mechanism.rod_mass [kg],mechanism.slider_mass [kg],mechanism.speed [rpm]\n")
    for i in range(a.n):
        r = rng.uniform(25.0, 45.0)
        l = r * rng.uniform(3.0, 5.0)
        cells = [f"{r:.3f}", f"{l:.3f}", f"{rng.uniform(0.2, 0.5):.4f}",
                 f"{rng.uniform(0.2, 0.45):.4f}", f"{rng.uniform(0.6, 1.5):.4f}",
                 f"{rng.uniform(600, 3000):.1f}"]
        name = f"piston-{float(cells[5]):.0f}rpm-{i + 1:05d}"
        if a.broken > 0 and rng.random() < a.broken:
            kind = rng.randrange(5)
            if kind == 0:
                cells[0] = f"-{r:.3f}"             # negative crank radius
            elif kind == 1:
                cells[1] = f"{0.5 * r:.3f}"        # rod shorter than the crank
            elif kind == 2:
                cells[2] = "0.3 furlong"           # unknown unit
            elif kind == 3:
                cells[5] = "fast"                  # not a quantity
            else:
                cells[4] = "-1"                    # negative mass
        out.write(",".join([name] + cells) + "\n")


if __name__ == "__main__":
    main()
