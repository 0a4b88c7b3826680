"""Peer of `piston-1000rpm`: the minimax crank counterweight of a slider-crank, as a
SciPy/cvxpy user would write it from the physics (shared/domain/slider-crank.md).

Shaking force with a counterweight unbalance U = (Ux, Uy) (kg·m) fixed in the crank frame:
    F(φ)/ω² = Rot(φ)(m_tq R e_x + U) − m_ct x''(φ) e_x,
    x''(φ) = −R cos φ − Rλ[(cos²φ − sin²φ)/k + λ² sin²φ cos²φ/k³],  k = sqrt(1 − λ² sin²φ),
m_tq = m_crank/2 + m_rod/2 (uniform crank and rod), m_ct = m_slider + m_rod/2.
minimise over |U| ≤ U_max the max over φ of |F(φ)|, on N equally spaced angles:
  --method cvxpy        SOCP  min t s.t. ‖A_k U + b_k‖ ≤ t (CLARABEL)
  --method slsqp        scipy.optimize.minimize(SLSQP) on the epigraph (U, t), exact Jacobians
  --method nelder-mead  scipy.optimize.minimize(Nelder-Mead) on max_k |F_k| (U only)
The reported value is the true peak of |F| for the U found: a 10×N scan and every sampled
local maximum refined by scipy.optimize.minimize_scalar (bounded, xatol 1e-12).
"""
import _common as c

A = c.args("problems/piston-1000rpm.toml", lambda p: (
    p.add_argument("--method", default="cvxpy", choices=["cvxpy", "slsqp", "nelder-mead"]),
    p.add_argument("--samples", type=int, default=360),
    p.add_argument("--evaluate", metavar="UX,UY", help="only the refined peak of this U (kg·m)")))

import numpy as np  # noqa: E402
from scipy import optimize  # noqa: E402
if A.method == "cvxpy":
    import cvxpy as cp  # noqa: E402
import_s = c.imports_done()

P = c.load(A.problem)
mech = P["mechanism"]
R, L = c.q(mech["crank_radius"]), c.q(mech["rod_length"])
w = c.q(mech["speed"])
m2, m3, m4 = c.q(mech["crank_mass"]), c.q(mech["rod_mass"]), c.q(mech["slider_mass"])
m_tq, m_ct = m2 / 2 + m3 / 2, m4 + m3 / 2
u_max = c.q(P["design"]["unbalance"]["max"])
lam = R / L
N = A.samples


def xpp(phi):
    s, co = np.sin(phi), np.cos(phi)
    k = np.sqrt(1 - lam**2 * s**2)
    return -R * co - R * lam * ((co**2 - s**2) / k + lam**2 * s**2 * co**2 / k**3)


def force(u, phi):
    """F(φ)/ω² (N / (rad/s)²), shape (2, n)."""
    s, co = np.sin(phi), np.cos(phi)
    bx = m_tq * R + u[0]
    return np.array([co * bx - s * u[1] - m_ct * xpp(phi), s * bx + co * u[1]])


def peak(u):
    """True max of |F| (N) for a given U: dense scan + bounded Brent on each local max."""
    n = 10 * N
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    f = np.hypot(*force(u, phi))
    h = 2 * np.pi / n
    best = f.max()
    for i in np.flatnonzero((f >= np.roll(f, 1)) & (f >= np.roll(f, -1))):
        r = optimize.minimize_scalar(lambda p: -np.hypot(*force(u, np.array([p])))[0],
                                     bounds=(phi[i] - h, phi[i] + h), method="bounded",
                                     options={"xatol": 1e-12})
        best = max(best, -r.fun)
    return w**2 * best


phi = np.linspace(0, 2 * np.pi, N, endpoint=False)
S, C = np.sin(phi), np.cos(phi)
# F_k = M_k U + b_k with M_k = Rot(φ_k), b_k = Rot(φ_k) m_tq R e_x − m_ct x''_k e_x
bx = C * m_tq * R - m_ct * xpp(phi)
by = S * m_tq * R


def solve_cvxpy():
    u, t = cp.Variable(2), cp.Variable()
    fx = cp.multiply(C, u[0]) - cp.multiply(S, u[1]) + bx
    fy = cp.multiply(S, u[0]) + cp.multiply(C, u[1]) + by
    prob = cp.Problem(cp.Minimize(t), [cp.norm(cp.vstack([fx, fy]), 2, axis=0) <= t,
                                       cp.norm(u, 2) <= u_max])
    prob.solve(solver=cp.CLARABEL)
    return np.array(u.value)


def solve_slsqp():
    def fk(z):
        return np.array([C * z[0] - S * z[1] + bx, S * z[0] + C * z[1] + by])

    def cons(z):  # t² − |F_k|² ≥ 0 (scaled), U_max² − |U|² ≥ 0
        f = fk(z)
        return np.concatenate([z[2]**2 - (f**2).sum(0), [u_max**2 - z[0]**2 - z[1]**2]])

    def jac(z):
        f = fk(z)
        j = np.empty((N + 1, 3))
        j[:N, 0] = -2 * (f[0] * C + f[1] * S)
        j[:N, 1] = -2 * (-f[0] * S + f[1] * C)
        j[:N, 2] = 2 * z[2]
        j[N] = [-2 * z[0], -2 * z[1], 0]
        return j

    z0 = np.array([0.0, 0.0, np.hypot(bx, by).max()])
    r = optimize.minimize(lambda z: z[2], z0, jac=lambda z: np.array([0, 0, 1.0]),
                          constraints=[{"type": "ineq", "fun": cons, "jac": jac}],
                          method="SLSQP", options={"ftol": 1e-12, "maxiter": 500})
    return r.x[:2]


def solve_nm():
    def g(u):
        if u[0]**2 + u[1]**2 > u_max**2:
            return 1e9
        return np.hypot(C * u[0] - S * u[1] + bx, S * u[0] + C * u[1] + by).max()

    r = optimize.minimize(g, np.array([-m_tq * R, 0.0]), method="Nelder-Mead",
                          options={"xatol": 1e-12, "fatol": 1e-12, "maxiter": 4000})
    return r.x


if A.evaluate:
    u = np.array([float(v) for v in A.evaluate.split(",")])
    c.emit(scene=P["name"], value=peak(u), unit="N", key="objectives.peak_shaking_force_n",
           solve_s=0.0, import_s=import_s, method="refined peak of the given U",
           settings={"scan": 10 * N, "peak_xatol_rad": 1e-12}, extra={"unbalance_kgm": list(u)})
    raise SystemExit

solver = {"cvxpy": solve_cvxpy, "slsqp": solve_slsqp, "nelder-mead": solve_nm}[A.method]
(u, value), solve_s, ts, first_s = c.timed(lambda: (lambda u: (u, peak(u)))(solver()), A.repeats)
c.emit(scene=P["name"], value=value, unit="N", key="objectives.peak_shaking_force_n",
       solve_s=solve_s, first_call_s=first_s, warm_s=ts, import_s=import_s,
       method=f"{A.method} minimax on sampled angles + refined peak of the result",
       settings={"samples": N, "scan": 10 * N, "peak_xatol_rad": 1e-12, "repeats": A.repeats},
       extra={"unbalance_kgm": float(np.hypot(*u)),
              "unbalance_angle_rad": float(np.arctan2(u[1], u[0]) % (2 * np.pi))})
