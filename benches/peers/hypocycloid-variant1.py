"""Peer of the hypocycloid zero curve (`benches/peers/problems/hypocycloid-variant1-zero-curve.toml`:
hypocycloid-variant1 plus its zero search): the curve a4(λ, θ) = 0 of the paper's C4, traced
at 100 equally spaced λ in [0.02, 0.5] by scipy.optimize.brentq in θ ∈ [0, 0.9] to 1e-12.

Physics (shared/domain/hypocycloid.md), variant 1 (α0 = 0):
    y = sin φ − θ sin 2φ,  x = cos φ + θ cos 2φ,  w = sqrt(1 − λ² y²),
    S/R − 1/λ = x − λ y² / (1 + w)            (the stable form: no 1/λ cancellation),
    a4(λ, θ) = (1/π) ∫₀^{2π} (S/R) cos 4φ dφ  (trapezoid rule on M points: spectrally exact
                                               for a smooth periodic integrand).
x has orders 1 and 2 only, so for order ≥ 3 the zeros of a4 are those of
    a4/λ = −(1/π) ∫ y²/(1 + w) cos 4φ dφ,
which is evaluated instead: summing x's O(1) terms only to cancel them costs ~1e-16 of
absolute rounding, i.e. ~2e-12 in θ at λ = 0.02 where ∂a4/∂θ ≈ λθ/2 ≈ 5e-5 (`--naive`
keeps the full S/R to show it).
Each λ: the sign of a4 at the ends of the θ box; if it differs, brentq; otherwise a
46-point scan brackets the first sign change (never needed on this box).
The printed value is θ*(λ = 0.5); the whole curve is in `extra.curve` for run.py.
"""
import _common as c

A = c.args("benches/peers/problems/hypocycloid-variant1-zero-curve.toml", lambda p: (
    p.add_argument("--quadrature", type=int, default=256, help="trapezoid points M"),
    p.add_argument("--xtol", type=float, default=1e-12),
    p.add_argument("--naive", action="store_true", help="integrate the full S/R")))

import numpy as np  # noqa: E402
from scipy import optimize  # noqa: E402
import_s = c.imports_done()

P = c.load(A.problem)
zs = P["objective"]["zero_search"]
order = zs["order"]
lam_lo, lam_hi = zs["lambda"]["min"], zs["lambda"]["max"]
th_lo, th_hi = zs["theta"]["min"], zs["theta"]["max"]
assert P["mechanism"]["variant"] == 1
M = A.quadrature
phi = np.linspace(0, 2 * np.pi, M, endpoint=False)
s1, s2, c1, c2 = np.sin(phi), np.sin(2 * phi), np.cos(phi), np.cos(2 * phi)
ck = np.cos(order * phi) * (2.0 / M)


def a_k(lam, th):
    y = s1 - th * s2
    if A.naive or order < 3:
        x = c1 + th * c2
        return float((x - lam * y * y / (1 + np.sqrt(1 - (lam * y) ** 2))) @ ck)
    z = y * y
    return -float((z / (1 + np.sqrt(1 - lam * lam * z))) @ ck)  # a_k / λ


def curve():
    out = []
    for lam in np.linspace(lam_lo, lam_hi, 100):
        f = lambda th: a_k(lam, th)  # noqa: E731
        lo, hi = th_lo, th_hi
        if f(lo) * f(hi) > 0:
            g = np.linspace(th_lo, th_hi, 46)
            v = np.array([f(t) for t in g])
            i = np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:]))
            if len(i) == 0:
                continue
            lo, hi = g[i[0]], g[i[0] + 1]
        out.append((float(lam), optimize.brentq(f, lo, hi, xtol=A.xtol, rtol=4 * np.finfo(float).eps)))
    return out


pts, solve_s, ts = c.timed(curve, A.repeats)
c.emit(scene=P["name"], value=pts[-1][1], unit="1", key="zero_curve[-1].theta",
       solve_s=solve_s, import_s=import_s,
       method="brentq in θ per λ on the exact a4 (trapezoid rule, stable root form)",
       settings={"points": 100, "xtol": A.xtol, "quadrature": M, "naive": A.naive,
                 "repeats": A.repeats},
       extra={"roots": len(pts), "curve": pts})
