"""Peer of `crane-thesis-optimise`: the level-luffing four-bar jib crane of the thesis
(shared/domain/luffing-crane.md), k1 and k2 optimised for the least jib-head height
variation Δh with the tie pin B confined (|AB| ≤ 15 m, 0 ≤ x_B ≤ 15 m), in NumPy/SciPy.

Geometry (A = (0, 0), reach along −x): D(φ) = L_c(−cos φ, sin φ); k = L_v/L_c =
(cos γ1 − sin φ_min)/(cos γ2 − sin γ3); C1 = D1 + L_v(−cos γ3, −sin γ3) at φ_min,
C3 = D3 + L_v(−sin γ2, −cos γ2) at φ_max = 90° − γ1; C2 = (x_C1 + k1(x_C3 − x_C1), y_C1);
D2 = circle(A, L_c) ∩ circle(C2, L_v) on the side of the line A→C where D1 and D3 are (and
φ_min ≤ φ2 ≤ φ_max); E_i = D_i + k2(D_i − C_i); B = circumcentre of E1 E2 E3, b = |BE1|.
Path: E(φ) = circle(D, a = k2 L_v) ∩ circle(B, b) on the side of the line D→B where the three
design positions are (all three must agree), C = D + (D − E)/k2, Δh = max y_C − min y_C.

Method (`--method slsqp`, the default): Δh on a sampled path (N boom angles, vectorised) is
the objective; a 12×12 grid of (k1, k2) gives the starts, SLSQP runs from the 4 best
feasible ones with the tie-pin limits as inequality constraints (finite-difference
gradients); the best end point's Δh is then re-evaluated with each sampled extremum refined
by minimize_scalar (bounded, xatol 1e-10 rad). `--method de`: differential_evolution with
the same constraints (NonlinearConstraint), then the same refinement.
"""
import _common as c

A = c.args("problems/crane-thesis-optimise.toml", lambda p: (
    p.add_argument("--method", default="slsqp", choices=["slsqp", "de"]),
    p.add_argument("--path-samples", type=int, default=201),
    p.add_argument("--grid", type=int, default=12),
    p.add_argument("--starts", type=int, default=4),
    p.add_argument("--evaluate", metavar="K1,K2", help="only the refined Δh of this design")))

import numpy as np  # noqa: E402
from scipy import optimize  # noqa: E402
import_s = c.imports_done()

P = c.load(A.problem)
d = P["design"]
L_c = c.q(d["boom_length"])
phi_min, g1, g2, g3 = (c.q(d[k]) for k in ("phi_min", "gamma1", "gamma2", "gamma3"))
phi_max = np.pi / 2 - g1
(k1_lo, k1_hi), (k2_lo, k2_hi) = ((d[k]["min"], d[k]["max"]) for k in ("k1", "k2"))
tp = P["objective"]["tie_pin"]
B_max = c.q(tp["max_distance"])
xB_lo, xB_hi = (c.q(v) for v in tp["x_range"])
k = (np.cos(g1) - np.sin(phi_min)) / (np.cos(g2) - np.sin(g3))
L_v = k * L_c
N = A.path_samples
PHI = np.linspace(phi_min, phi_max, N)
BAD = 10.0  # Δh of an infeasible geometry (m), far above any valid one (~0.5 m)


def head(phi):
    return np.stack([-L_c * np.cos(phi), L_c * np.sin(phi)])


def cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def circles(p0, r0, p1, r1, side):
    """Intersection of circle(p0, r0) and circle(p1, r1) with sign(cross(p1 − p0, X − p0)) =
    side; p0 may be a (2, n) array. NaN where the circles miss."""
    dv = p1[:, None] - p0 if np.ndim(p0) == 2 else p1 - p0
    dd = np.hypot(dv[0], dv[1])
    a = (dd**2 + r0**2 - r1**2) / (2 * dd)
    h = np.sqrt(r0**2 - a**2)  # NaN if no intersection
    u = dv / dd
    return p0 + u * a + side * h * np.stack([-u[1], u[0]])


D1, D3 = head(phi_min), head(phi_max)
C1 = D1 + L_v * np.array([-np.cos(g3), -np.sin(g3)])
C3 = D3 + L_v * np.array([-np.sin(g2), -np.cos(g2)])
s13 = np.sign(cross(C1, D1))


def synth(k1, k2):
    """(B, b, side, a) or None."""
    C2 = np.array([C1[0] + k1 * (C3[0] - C1[0]), C1[1]])
    D2 = circles(np.zeros(2), L_c, C2, L_v, 1.0)
    if np.sign(cross(C2, D2)) != s13:
        D2 = circles(np.zeros(2), L_c, C2, L_v, -1.0)
    phi2 = np.arctan2(D2[1], -D2[0])
    if not (np.all(np.isfinite(D2)) and phi_min <= phi2 <= phi_max and D2[1] >= C1[1]):
        return None
    E = [Di + k2 * (Di - Ci) for Di, Ci in ((D1, C1), (D2, C2), (D3, C3))]
    (ax, ay), (bx, by), (cx, cy) = E
    den = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    if den == 0:
        return None
    B = np.array([((ax**2 + ay**2) * (by - cy) + (bx**2 + by**2) * (cy - ay) + (cx**2 + cy**2) * (ay - by)),
                  ((ax**2 + ay**2) * (cx - bx) + (bx**2 + by**2) * (ax - cx) + (cx**2 + cy**2) * (bx - ax))]) / den
    sides = {np.sign(cross(B - Di, Ei - Di)) for Di, Ei in zip((D1, D2, D3), E)}
    if len(sides) != 1:
        return None  # branch defect
    return B, np.hypot(*(B - E[0])), sides.pop(), k2 * L_v


def y_head(s, k2, phi):
    B, b, side, a = s
    D = head(np.atleast_1d(phi))
    E = circles(D, a, B, b, side)
    return (D + (D - E) / k2)[1]


def delta_h(x, refine=False):
    k1, k2 = x
    s = synth(k1, k2)
    if s is None:
        return BAD
    y = y_head(s, k2, PHI)
    if not np.all(np.isfinite(y)):
        return BAD
    if not refine:
        return y.max() - y.min()
    ext = []
    for sgn, i in ((1, int(np.argmax(y))), (-1, int(np.argmin(y)))):
        lo, hi = PHI[max(i - 1, 0)], PHI[min(i + 1, N - 1)]
        r = optimize.minimize_scalar(lambda p: -sgn * y_head(s, k2, p)[0], bounds=(lo, hi),
                                     method="bounded", options={"xatol": 1e-10})
        ext.append(max(sgn * y[i], -r.fun) * sgn)
    return ext[0] - ext[1]


def pin(x):
    s = synth(*x)
    return None if s is None else s[0]


def cons(x):
    """Tie-pin limits as g(x) ≥ 0 (m); −100 where the geometry fails."""
    B = pin(x)
    if B is None:
        return np.full(3, -100.0)
    return np.array([B_max - np.hypot(*B), B[0] - xB_lo, xB_hi - B[0]])


bounds = [(k1_lo, k1_hi), (k2_lo, k2_hi)]


def solve_slsqp():
    g = A.grid
    pts = [(a, b) for a in np.linspace(k1_lo, k1_hi, g) for b in np.linspace(k2_lo, k2_hi, g)]
    feas = [(delta_h(p), p) for p in pts if cons(p).min() >= 0]
    feas.sort()
    best = None
    for _, p in feas[: A.starts]:
        r = optimize.minimize(delta_h, np.array(p), method="SLSQP", bounds=bounds,
                              constraints=[{"type": "ineq", "fun": cons}],
                              options={"ftol": 1e-12, "maxiter": 200})
        if cons(r.x).min() >= -1e-9 and (best is None or r.fun < best.fun):
            best = r
    return best.x


def solve_de():
    r = optimize.differential_evolution(
        delta_h, bounds, constraints=[optimize.NonlinearConstraint(cons, 0, np.inf)],
        seed=1, tol=1e-10, polish=True)
    return r.x


if A.evaluate:
    x = np.array([float(v) for v in A.evaluate.split(",")])
    B = pin(x)
    c.emit(scene=P["name"], value=delta_h(x, refine=True), unit="m", key="objectives.delta_h_m",
           solve_s=0.0, import_s=import_s, method="refined Δh of the given design",
           settings={"path_samples": N, "extremum_xatol_rad": 1e-10},
           extra={"k1": x[0], "k2": x[1], "tie_pin": [B[0], B[1]], "tie_pin_distance_m": np.hypot(*B),
                  "tie_pin_ok": bool(cons(x).min() >= -1e-9)})
    raise SystemExit

solver = {"slsqp": solve_slsqp, "de": solve_de}[A.method]
(x, value), solve_s, ts, first_s = c.timed(lambda: (lambda x: (x, delta_h(x, refine=True)))(solver()), A.repeats)
B = pin(x)
c.emit(scene=P["name"], value=value, unit="m", key="objectives.delta_h_m", solve_s=solve_s,
       first_call_s=first_s, warm_s=ts, import_s=import_s,
       method=f"{A.method} on the sampled-path Δh + refined extrema at the end",
       settings={"path_samples": N, "grid": A.grid, "starts": A.starts, "ftol": 1e-12,
                 "extremum_xatol_rad": 1e-10, "repeats": A.repeats},
       extra={"k1": x[0], "k2": x[1], "tie_pin": [B[0], B[1]], "tie_pin_distance_m": np.hypot(*B)})
