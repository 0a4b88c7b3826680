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
All 100 λ are solved at once, as NumPy arrays: a4 is evaluated for a vector of (λ, θ) pairs
(one (n, M) array and a matrix–vector product), the sign of a4 at the ends of the θ box
brackets each root (where it does not, a 46-point scan brackets the first sign change; never
needed on this box), and regula falsi with the Illinois modification narrows every bracket
together until its width is ≤ xtol + 4ε|θ| (brentq's tolerance), each λ leaving the iteration
when it is done with the secant of its last bracket as its root. `--brentq` solves λ by λ with scipy.optimize.brentq instead (the scalar loop
the peer first had; the same roots within xtol).
The printed value is θ*(λ = 0.5); the whole curve is in `extra.curve` for run.py.
"""
import _common as c

A = c.args("benches/peers/problems/hypocycloid-variant1-zero-curve.toml", lambda p: (
    p.add_argument("--quadrature", type=int, default=256, help="trapezoid points M"),
    p.add_argument("--xtol", type=float, default=1e-12),
    p.add_argument("--naive", action="store_true", help="integrate the full S/R"),
    p.add_argument("--brentq", action="store_true", help="brentq per λ (scalar loop)")))

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
    """a_k(λ, θ) (or a_k/λ, see above) for scalars or broadcastable arrays λ, θ."""
    lam, th = np.broadcast_arrays(np.asarray(lam, float), np.asarray(th, float))
    y = s1 - th[..., None] * s2
    if A.naive or order < 3:
        x = c1 + th[..., None] * c2
        return (x - lam[..., None] * y * y / (1 + np.sqrt(1 - (lam[..., None] * y) ** 2))) @ ck
    z = y * y
    return -((z / (1 + np.sqrt(1 - (lam * lam)[..., None] * z))) @ ck)  # a_k / λ


RTOL = 4 * np.finfo(float).eps


def curve_brentq():
    out = []
    for lam in np.linspace(lam_lo, lam_hi, 100):
        f = lambda th: float(a_k(lam, th))  # noqa: E731
        lo, hi = th_lo, th_hi
        if f(lo) * f(hi) > 0:
            g = np.linspace(th_lo, th_hi, 46)
            v = a_k(lam, g)
            i = np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:]))
            if len(i) == 0:
                continue
            lo, hi = g[i[0]], g[i[0] + 1]
        out.append((float(lam), optimize.brentq(f, lo, hi, xtol=A.xtol, rtol=RTOL)))
    return out


def illinois(lam, x0, x1, f0, f1, maxiter=100):
    """Roots θ of a_k(λ, θ) for every λ at once, each bracketed by [x0, x1] (f0·f1 ≤ 0):
    x2 = x1 − f1 (x1 − x0)/(f1 − f0); if f2 changes sign against f1 the bracket becomes
    [x1, x2], else [x0, x2] with f0 halved (Illinois). A λ is done where f = 0 or the bracket
    is ≤ xtol + 4ε|θ| wide; its root is then the secant of the bracket's ends (their true
    values), inside the bracket."""
    x0, x1, f0, f1 = (np.array(v, float) for v in (x0, x1, f0, f1))
    t0 = f0.copy()                       # a4 at x0 (f0 is halved by Illinois steps)
    root = np.where(f0 == 0, x0, x1)
    act = np.flatnonzero((f0 != 0) & (f1 != 0))
    for _ in range(maxiter):
        if act.size == 0:
            break
        a0, a1, g0, g1 = x0[act], x1[act], f0[act], f1[act]
        x2 = a1 - g1 * (a1 - a0) / (g1 - g0)
        # a step that rounding puts on or outside the bracket: bisect instead
        out = ~((np.minimum(a0, a1) < x2) & (x2 < np.maximum(a0, a1)))
        x2[out] = 0.5 * (a0[out] + a1[out])
        g2 = a_k(lam[act], x2)
        flip = g2 * g1 < 0
        x0[act] = np.where(flip, a1, a0)
        f0[act] = np.where(flip, g1, 0.5 * g0)
        t0[act] = np.where(flip, g1, t0[act])
        x1[act], f1[act] = x2, g2
        b0 = x0[act]
        done = (g2 == 0) | (np.abs(x2 - b0) <= A.xtol + RTOL * np.abs(x2))
        with np.errstate(invalid="ignore", divide="ignore"):
            sec = x2 - g2 * (x2 - b0) / (g2 - t0[act])
        inside = (np.minimum(x2, b0) <= sec) & (sec <= np.maximum(x2, b0))
        root[act] = np.where((g2 != 0) & inside, sec, x2)
        act = act[~done]
    if act.size:
        raise RuntimeError(f"Illinois: {act.size} roots not converged in {maxiter} steps")
    return root


def curve_vec():
    lam = np.linspace(lam_lo, lam_hi, 100)
    lo, hi = np.full_like(lam, th_lo), np.full_like(lam, th_hi)
    flo, fhi = a_k(lam, lo), a_k(lam, hi)
    no = np.flatnonzero(flo * fhi > 0)
    if no.size:  # no sign change at the ends: bracket the first one on a 46-point scan
        g = np.linspace(th_lo, th_hi, 46)
        v = a_k(lam[no, None], g)                              # (len(no), 46)
        ch = np.sign(v[:, :-1]) != np.sign(v[:, 1:])
        i = ch.argmax(1)
        lo[no], hi[no] = g[i], g[i + 1]
        flo[no], fhi[no] = v[np.arange(no.size), i], v[np.arange(no.size), i + 1]
        keep = np.ones(lam.size, bool)
        keep[no[~ch.any(1)]] = False                           # no root on this λ
        lam, lo, hi, flo, fhi = lam[keep], lo[keep], hi[keep], flo[keep], fhi[keep]
    th = illinois(lam, lo, hi, flo, fhi)
    return [(float(x), float(t)) for x, t in zip(lam, th)]


curve = curve_brentq if A.brentq else curve_vec


pts, solve_s, ts, first_s = c.timed(curve, A.repeats)
c.emit(scene=P["name"], value=pts[-1][1], unit="1", key="zero_curve[-1].theta",
       solve_s=solve_s, first_call_s=first_s, warm_s=ts, import_s=import_s,
       method=("brentq in θ per λ" if A.brentq else "Illinois regula falsi on all λ at once (NumPy)")
       + " on the exact a4 (trapezoid rule, stable root form)",
       settings={"points": 100, "xtol": A.xtol, "quadrature": M, "naive": A.naive,
                 "root": "brentq" if A.brentq else "illinois", "repeats": A.repeats},
       extra={"roots": len(pts), "curve": pts})
