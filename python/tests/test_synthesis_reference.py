"""Issue 36's independent reference for the shape search of
`problems/linkage-fourbar-path-synthesis.toml`: the four-bar's loop closure written again with
NumPy, the path error of cwsynth's geometries recomputed from it (a dense scan refined by
SciPy's bounded Brent), and the five-point path fitted from six random starts by SciPy's
least-squares (the loop-closure fit with each point's crank angle a variable): the least path
error cwsynth's multistart finds agrees with SciPy's within 1e-6 m."""

import numpy as np
import pytest

scipy_optimize = pytest.importorskip("scipy.optimize")

from conftest import cli_json  # noqa: E402

FILE = "problems/linkage-fourbar-path-synthesis.toml"
POINTS = np.array(
    [[78.694, 66.693], [54.420, 86.786], [4.959, 74.146], [-11.127, 34.836], [25.219, 36.438]]
) * 1e-3


def tracer(x, theta):
    """The coupler point of the four-bar x = (crank a, coupler b, rocker c, pivot qx, qy,
    tracer u, v) at crank angles theta (crank pivot at the origin; B on the left of A→Q, as
    cwsynth's branch "left"). NaN where it does not assemble."""
    a, b, c, qx, qy, u, v = x
    theta = np.asarray(theta, dtype=float)
    ax, ay = a * np.cos(theta), a * np.sin(theta)
    dx, dy = qx - ax, qy - ay
    d = np.hypot(dx, dy)
    s = (b * b - c * c + d * d) / (2 * d)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(b * b - s * s)
    ux, uy = dx / d, dy / d
    bx, by = ax + s * ux - h * uy, ay + s * uy + h * ux
    ex, ey = (bx - ax) / b, (by - ay) / b
    return np.stack([ax + ex * u - ey * v, ay + ey * u + ex * v], axis=-1)


def path_error(x, points=POINTS, n=20000):
    """max over the points of the least distance to the path: a scan of n angles, each
    point's nearest refined by SciPy's bounded Brent."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    xy = tracer(x, t)
    out = []
    for q in points:
        d = np.hypot(*(xy - q).T)
        k = int(np.nanargmin(d))
        h = 2 * np.pi / n
        r = scipy_optimize.minimize_scalar(
            lambda th: np.hypot(*(tracer(x, th) - q)),
            bounds=(t[k] - h, t[k] + h),
            method="bounded",
            options={"xatol": 1e-13},
        )
        out.append(min(r.fun, d[k]))
    return max(out)


@pytest.fixture(scope="module")
def result(cli):
    return cli_json(cli, FILE)


def test_cwsynth_path_errors_are_the_loop_closure_s(result):
    s = result["synthesis"]
    for pt in [s["kinematic_first"], *s["front"]]:
        e = path_error(np.array(pt["x"]))
        assert abs(e - pt["path_error_m"]) <= 1e-9, (pt["max_error_m"], e, pt["path_error_m"])


def test_the_least_path_error_is_scipy_s_from_many_starts(result):
    lo = np.array([0.032, 0.100, 0.064, 0.085, -0.015, 0.045, 0.015])
    hi = np.array([0.048, 0.140, 0.096, 0.115, 0.015, 0.075, 0.045])
    rng = np.random.default_rng(36)

    def residuals(z):
        x, th = z[:7], z[7:]
        r = tracer(x, th) - POINTS
        return np.nan_to_num(r.ravel(), nan=1.0)

    fits = []
    for _ in range(6):
        x0 = lo + (hi - lo) * rng.random(7)
        th0 = rng.random(5) * 2 * np.pi
        fit = scipy_optimize.least_squares(
            residuals,
            np.concatenate([x0, th0]),
            bounds=(np.concatenate([lo, np.full(5, -10.0)]), np.concatenate([hi, np.full(5, 20.0)])),
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
        )
        x = fit.x[:7]
        if np.all(np.isfinite(tracer(x, np.linspace(0, 2 * np.pi, 720)))):
            fits.append((fit.cost, x))
    # The path error of the best fit that turns fully (its residuals' least squares).
    best = path_error(min(fits, key=lambda f: f[0])[1])
    ours = result["synthesis"]["kinematic_first"]["path_error_m"]
    assert best <= 1e-6, best
    assert abs(ours - best) <= 1e-6, (ours, best)
