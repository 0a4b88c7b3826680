"""One paired run of cwsynth against its SciPy/cvxpy peers (issue 21).

For each scene and each round (A B A B …): A = `cwsynth solve FILE --json` as a whole
process (its in-process `timing.solve_s` read from the JSON: the one solve the process does,
cold), B = each peer script as a whole process, with BLAS/OpenMP pinned to one thread; its
in-process `solve_s` is the median of `--repeats` warm solves (one warm-up solve first, not
counted; imports excluded). Reports min/median/max over the rounds of whole-process wall
time, process CPU (user + sys), in-process solve time, the speed ratios peer/cwsynth (of the
medians), and the peer's headline value against cwsynth's with cwsynth's stated error bound.
A peer's whole-process wall and CPU times are counted less its warm repeats: start-up,
imports, parsing and one (the first) solve, as a cwsynth process does.
/proc/loadavg is recorded at start and end: the machine may be shared, so read the ratios,
not the absolute times.

    python benches/peers/run.py --cli target/release/cwsynth [--rounds 7] [--repeats 7] [--quick]

Writes benches/peers/results.csv and prints a markdown table.
"""
import argparse
import csv
import json
import os
import resource
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def dig(d, path):
    for part in path.split("."):
        d = d[int(part)] if isinstance(d, list) else d[part]
    return d


# scene: problem file, cwsynth's headline key, its error key (absolute) or a fixed bound,
# `evaluate` = (peer, design keys) to have the peer's model evaluate cwsynth's design, peers
SCENES = [
    dict(scene="piston-1000rpm", problem="problems/piston-1000rpm.toml",
         key="objectives.peak_shaking_force_n", err="errors.peak_shaking_force_n",
         evaluate=("piston-1000rpm.py", "design.counterweight_unbalance_x_kgm",
                   "design.counterweight_unbalance_y_kgm"),
         peers=[["piston-1000rpm.py", "--method", "cvxpy"],
                ["piston-1000rpm.py", "--method", "slsqp"]]),
    dict(scene="crane-thesis-optimise", problem="problems/crane-thesis-optimise.toml",
         key="objectives.delta_h_m", err="errors.delta_h_m",
         evaluate=("crane-thesis-optimise.py", "design.k1", "design.k2"),
         peers=[["crane-thesis-optimise.py", "--method", "slsqp"],
                ["crane-thesis-optimise.py", "--method", "de"]]),
    dict(scene="hypocycloid-variant1 zero curve",
         problem="benches/peers/problems/hypocycloid-variant1-zero-curve.toml",
         key="zero_curve.99.theta", err=None, bound=1e-12, curve=True,
         peers=[["hypocycloid-variant1.py"]]),
    dict(scene="gear-paper-table1", problem="problems/gear-paper-table1.toml",
         key="objectives.peak_sliding_coefficient", err="errors.peak_sliding_coefficient",
         peers=[["gear-paper-table1.py"]]),
]


# The environment of every peer process: one thread for each BLAS/OpenMP pool, set before the
# peer starts (so before it imports NumPy). _common.py sets the same defaults when a peer
# runs alone.
PIN = {v: "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                         "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")}


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def run(cmd, env=None):
    """(stdout, wall s, CPU s of the child)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return p.stdout, wall, cpu


def stats(xs):
    return min(xs), statistics.median(xs), max(xs)


def fmt_t(s):
    return f"{s * 1e3:.3g} ms" if s < 1 else f"{s:.3g} s"


def fmt_r(x):
    return f"{x:.2f}×" if x < 10 else f"{x:.0f}×"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default="target/release/cwsynth")
    ap.add_argument("--python", default=sys.executable)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--repeats", type=int, default=7,
                    help="warm in-process solves per peer process (after one warm-up); median reported")
    ap.add_argument("--quick", action="store_true", help="one round")
    ap.add_argument("--only", help="run only scenes whose name contains this")
    ap.add_argument("--out", default=os.path.join(HERE, "results.csv"))
    a = ap.parse_args()
    rounds = 1 if a.quick else a.rounds
    cli = os.path.abspath(os.path.join(ROOT, a.cli)) if not os.path.isabs(a.cli) else a.cli
    scenes = [s for s in SCENES if not a.only or a.only in s["scene"]]
    peer_env = dict(os.environ, **PIN)
    pin_txt = " ".join(f"{k}={v}" for k, v in PIN.items())
    load0, t0 = loadavg(), time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())
    # samples[(scene, tool)] = list of (wall, cpu, inproc, peer's first call, peer's imports)
    samples, last = {}, {}
    for rnd in range(rounds):
        for s in scenes:
            cmds = [("cwsynth", [cli, "solve", s["problem"], "--json"], None)]
            cmds += [(" ".join(p[1:]) or "default",
                      [a.python, os.path.join(HERE, p[0]), *p[1:], s["problem"],
                       "--repeats", str(a.repeats)], peer_env)
                     for p in s["peers"]]
            for tool, cmd, env in cmds:
                out, wall, cpu = run(cmd, env)
                j = json.loads(out.strip().splitlines()[-1])
                if tool == "cwsynth":
                    sample = (wall, cpu, j["timing"]["solve_s"], None, None)
                else:
                    assert all(j["threads"][k] == v for k, v in PIN.items()), j["threads"]
                    # whole process as if it solved once, like cwsynth: less the warm repeats
                    # (single-threaded, so their CPU time is their wall time)
                    rep_s = sum(j["warm_s"])
                    sample = (wall - rep_s, cpu - rep_s, j["solve_s"], j["first_call_s"], j["import_s"])
                samples.setdefault((s["scene"], tool), []).append(sample)
                last[(s["scene"], tool)] = j
        print(f"round {rnd + 1}/{rounds} done, load {loadavg()}", file=sys.stderr)
    load1, t1 = loadavg(), time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())

    rows, checks = [], []
    for s in scenes:
        cw = last[(s["scene"], "cwsynth")]
        cw_val = dig(cw, s["key"])
        cw_abs = dig(cw, s["err"]) if s.get("err") else s["bound"]
        cw_rel = cw_abs / abs(cw_val)
        if s.get("evaluate"):
            # the peer's own model evaluates cwsynth's design: separates "the peer's optimiser
            # stops elsewhere" from "cwsynth's value of its design is wrong"
            script, *keys = s["evaluate"]
            design = ",".join(repr(float(dig(cw, k))) for k in keys)
            out, _, _ = run([a.python, os.path.join(HERE, script), s["problem"], f"--evaluate={design}"],
                            peer_env)
            ev = json.loads(out.strip().splitlines()[-1])["value"]
            checks.append((s["scene"], design, cw_val, ev, (ev - cw_val) / abs(cw_val), cw_rel))
        cws = samples[(s["scene"], "cwsynth")]
        for p in s["peers"]:
            tool = " ".join(p[1:]) or "default"
            pj = last[(s["scene"], tool)]
            ps = samples[(s["scene"], tool)]
            if s.get("curve"):
                # both curves are at the same λ grid: compare θ point by point
                diffs = [abs(q[1] - z["theta"]) for q, z in zip(pj["extra"]["curve"], cw["zero_curve"])]
                diff_abs = max(diffs) if len(diffs) == len(cw["zero_curve"]) else float("inf")
                cmp_what, rel, bound = "max |Δθ| over the 100 points", diff_abs, cw_abs
            else:
                diff_abs = pj["value"] - cw_val
                cmp_what, rel, bound = "relative difference", diff_abs / abs(cw_val), cw_rel
            row = dict(scene=s["scene"], peer=f"{p[0]} {tool}".strip(), peer_method=pj["method"],
                       peer_settings=json.dumps(pj["settings"]), rounds=rounds,
                       cwsynth_inproc_is="timing.solve_s: the one (cold) solve of its process",
                       peer_inproc_is=f"median of {a.repeats} warm solves after 1 warm-up",
                       peer_threads=pin_txt)
            for name, idx in (("wall", 0), ("cpu", 1), ("inproc", 2)):
                for who, xs in (("cwsynth", cws), ("peer", ps)):
                    lo, med, hi = stats([x[idx] for x in xs])
                    row.update({f"{who}_{name}_min_s": lo, f"{who}_{name}_median_s": med,
                                f"{who}_{name}_max_s": hi})
                row[f"ratio_{name}"] = row[f"peer_{name}_median_s"] / row[f"cwsynth_{name}_median_s"]
            row.update(peer_first_call_median_s=statistics.median([x[3] for x in ps]),
                       peer_import_median_s=statistics.median([x[4] for x in ps]),
                       cwsynth_value=cw_val, peer_value=pj["value"], unit=pj["unit"],
                       compare=cmp_what, difference=rel, cwsynth_stated_error=bound,
                       within_bound=abs(rel) <= bound,
                       load_start=load0, load_end=load1, started=t0, ended=t1)
            rows.append(row)

    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    print(f"Paired run: {rounds} rounds, A = `cwsynth solve FILE --json` (in-process: its one, cold "
          f"solve), B = peer (in-process: median of {a.repeats} warm solves after a warm-up; "
          f"{pin_txt}); {t0} → {t1}; load average {load0} at start, {load1} at end "
          f"({os.cpu_count()} CPUs).\n")
    print("| scene | peer | in-process: cwsynth | peer | ratio | whole process: cwsynth | peer | ratio "
          "| value: cwsynth | peer | difference | cwsynth's bound |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        def t3(who, name):
            return (f"{fmt_t(r[f'{who}_{name}_median_s'])} "
                    f"[{fmt_t(r[f'{who}_{name}_min_s'])}–{fmt_t(r[f'{who}_{name}_max_s'])}]")
        diff = (f"{r['difference']:.1e} (abs θ)" if r["compare"].startswith("max")
                else f"{r['difference']:+.1e}")
        print(f"| {r['scene']} | {r['peer']} | {t3('cwsynth', 'inproc')} | {t3('peer', 'inproc')} "
              f"| {fmt_r(r['ratio_inproc'])} | {t3('cwsynth', 'wall')} | {t3('peer', 'wall')} "
              f"| {fmt_r(r['ratio_wall'])} | {r['cwsynth_value']:.12g} | {r['peer_value']:.12g} "
              f"| {diff} | {r['cwsynth_stated_error']:.1e} |")
    print(f"\nmedian [min–max] of {rounds} rounds; ratio = peer median / cwsynth median; difference = "
          "(peer − cwsynth)/|cwsynth| (relative), except the zero curve (max |θ_peer − θ_cwsynth|); "
          "cwsynth's bound = its stated error (errors.* over the value; the zero curve: its 1e-12 "
          f"root tolerance in θ). CPU medians (user + sys), the peers' first (warm-up) solves and "
          f"import times are in {os.path.relpath(a.out, ROOT)}.")
    print("\nCold against cold (each peer's first solve in its process, the warm-up not in the "
          "median above, against cwsynth's): "
          + "; ".join(f"{r['scene']} / {r['peer']}: {fmt_t(r['peer_first_call_median_s'])}, "
                      f"{fmt_r(r['peer_first_call_median_s'] / r['cwsynth_inproc_median_s'])}"
                      for r in rows) + ".")
    if checks:
        print("\nThe peers' models evaluating cwsynth's optimum (no optimisation):\n")
        print("| scene | cwsynth's design | cwsynth's value | peer's evaluation | difference | cwsynth's bound |")
        print("|---|---|---:|---:|---:|---:|")
        for sc, d, v, ev, rel, b in checks:
            print(f"| {sc} | {d} | {v:.15g} | {ev:.15g} | {rel:+.1e} | {b:.1e} |")


if __name__ == "__main__":
    main()
