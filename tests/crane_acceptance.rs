//! Acceptance tests of issue 14 for the crane: (1) every stated Δh error covers the truth,
//! computed independently in double-double arithmetic (`twofloat`, ~32 digits: the thesis's
//! construction written out again here, textbook formulas, dense sampling and golden-section
//! refinement), on random and near-degenerate designs (k1 near 0 and 1, nearly collinear
//! tail points, tiny and huge scale); (2) the multistart's `best_found` is not beaten by an
//! independent search (precomputed reference optima and an in-test compass search).

use crate::common;

use common::Dd as T;
use cwsynth::families::crane::synth::*;

fn t(x: f64) -> T {
    T::from(x)
}

#[derive(Clone, Copy)]
struct V(T, T);
impl V {
    fn sub(self, o: V) -> V {
        V(self.0 - o.0, self.1 - o.1)
    }
    fn add(self, o: V) -> V {
        V(self.0 + o.0, self.1 + o.1)
    }
    fn mul(self, s: T) -> V {
        V(self.0 * s, self.1 * s)
    }
    fn dot(self, o: V) -> T {
        self.0 * o.0 + self.1 * o.1
    }
    fn cross(self, o: V) -> T {
        self.0 * o.1 - self.1 * o.0
    }
    fn norm(self) -> T {
        self.dot(self).sqrt()
    }
}

/// Intersection of circle (c0, r0) with circle (c1, r1), on the side `s` (+1 left of c0→c1).
fn cc(c0: V, r0: T, c1: V, r1: T, s: f64) -> Option<V> {
    let dv = c1.sub(c0);
    let d = dv.norm();
    let a = (d * d + r0 * r0 - r1 * r1) / (t(2.0) * d);
    let h2 = r0 * r0 - a * a;
    if h2 < t(0.0) {
        return None;
    }
    let u = dv.mul(t(1.0) / d);
    let n = V(-u.1, u.0);
    Some(c0.add(u.mul(a)).add(n.mul(h2.sqrt() * t(s))))
}

/// Δh of the design (fixed L_c) in double-double: None where it does not assemble.
fn reference_delta_h(l_c: f64, x: [f64; 6]) -> Option<f64> {
    let [k1, k2, phi_min, g1, g2, g3] = x.map(t);
    let l_c = t(l_c);
    let sn = |x: T| common::dd_sin_cos(x).0;
    let cs = |x: T| common::dd_sin_cos(x).1;
    let half_pi = T::new_add(std::f64::consts::FRAC_PI_2, 6.123233995736766e-17);
    let phi_max = half_pi - g1;
    let k = (cs(g1) - sn(phi_min)) / (cs(g2) - sn(g3));
    let l_v = k * l_c;
    let dph = |p: T| V(-l_c * cs(p), l_c * sn(p));
    let (d1, d3) = (dph(phi_min), dph(phi_max));
    let c1 = d1.add(V(-cs(g3), -sn(g3)).mul(l_v));
    let c3 = d3.add(V(-sn(g2), -cs(g2)).mul(l_v));
    let c2 = V(c1.0 + k1 * (c3.0 - c1.0), c1.1);
    let side = if c1.cross(d1) > t(0.0) { 1.0 } else { -1.0 };
    // D2 on circle(A, L_c) at |D2 − C2| = L_v: the textbook intersection, then Newton on
    // δ = φ2 − φ_a from the nearer extreme a in difference form (so that D2 − D_a keeps its
    // digits when k1 is near 0 or 1).
    let d2c = cc(V(t(0.0), t(0.0)), l_c, c2, l_v, side)?;
    let near1 = x[0] <= 0.5;
    let (pa, da) = if near1 { (phi_min, d1) } else { (phi_max, d3) };
    let w = if near1 {
        V(cs(g3), sn(g3)).mul(l_v)
    } else {
        V(sn(g2), cs(g2)).mul(l_v)
    };
    let dc = if near1 {
        V(k1 * (c3.0 - c1.0), t(0.0))
    } else {
        V((t(1.0) - k1) * (c1.0 - c3.0), t(0.0))
    };

    let ddf = |del: T| {
        let h = del / t(2.0);
        V(sn(pa + h), cs(pa + h)).mul(t(2.0) * l_c * sn(h))
    };
    let mut del = d2c.1.atan2(-d2c.0) - pa;
    for _ in 0..8 {
        let r = ddf(del).sub(dc);
        let f = t(2.0) * w.dot(r) + r.dot(r);
        let fp = t(2.0) * w.add(r).dot(V(sn(pa + del), cs(pa + del)).mul(l_c));
        del -= f / fp;
    }
    let d2 = da.add(ddf(del));
    let e = |d: V, c: V| d.add(d.sub(c).mul(k2));
    let (e1, e2, e3) = (e(d1, c1), e(d2, c2), e(d3, c3));
    let (b, c) = (e2.sub(e1), e3.sub(e1));
    let dd = t(2.0) * b.cross(c);
    let (bb, cq) = (b.dot(b), c.dot(c));
    let o = V((c.1 * bb - b.1 * cq) / dd, (b.0 * cq - c.0 * bb) / dd);
    let pin = e1.add(o);
    let rb = o.norm();
    let a = k2 * l_v;
    let s_e = if pin.sub(d1).cross(e1.sub(d1)) > t(0.0) {
        1.0
    } else {
        -1.0
    };
    let y = |p: T| -> Option<T> {
        let d = dph(p);
        let ee = cc(d, a, pin, rb, s_e)?;
        Some(d.1 + (d.1 - ee.1) / k2)
    };
    let n = 400;
    let ph = |i: usize| phi_min + (phi_max - phi_min) * t(i as f64 / n as f64);
    let ys: Vec<T> = (0..=n).map(|i| y(ph(i))).collect::<Option<_>>()?;
    // Every sampled local extreme is refined (golden section on its two neighbouring
    // intervals), not only the largest sample: an optimised tail path has near-equal ripple
    // extremes, and the largest sample need not lie next to the largest extreme.
    let ext = |sign: f64| -> Option<T> {
        let g = t(0.381_966_011_250_105_1);
        let f = |p: T| y(p).map(|v| v * t(sign));
        let mut best = ys[0] * t(sign);
        for i in 0..=n {
            let v = ys[i] * t(sign);
            let left = i == 0 || ys[i - 1] * t(sign) <= v;
            let right = i == n || ys[i + 1] * t(sign) <= v;
            if !(left && right) {
                continue;
            }
            let (mut lo, mut hi) = (ph(i.saturating_sub(1)), ph((i + 1).min(n)));
            if v > best {
                best = v;
            }
            for _ in 0..90 {
                let (m1, m2) = (lo + (hi - lo) * g, hi - (hi - lo) * g);
                let (f1, f2) = (f(m1)?, f(m2)?);
                if f1 > best {
                    best = f1;
                }
                if f2 > best {
                    best = f2;
                }
                if f1 > f2 {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
        }
        Some(best * t(sign))
    };
    let top = ext(1.0)?;
    let bottom = ext(-1.0)?;
    Some(f64::from(top - bottom))
}

fn scene(l_c: f64, x: [f64; 6]) -> CraneScene {
    CraneScene {
        k1: Var::Fixed(x[0]),
        k2: Var::Fixed(x[1]),
        phi_min: Var::Fixed(x[2]),
        gamma1: Var::Fixed(x[3]),
        gamma2: Var::Fixed(x[4]),
        gamma3: Var::Fixed(x[5]),
        sizing: SizingRule::Given(l_c),
        ..thesis_example()
    }
}

fn quick() -> Settings {
    Settings {
        landscape_k1: 0,
        landscape_k2: 0,
        plot_points: 2,
        ..Settings::default()
    }
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// k2 where E1 E2 E3 turn collinear (the tie pin at infinity) for the other variables, by
/// bisection on the orientation of the triangle: designs just beside it are nearly collinear.
fn collinear_k2(l_c: f64, x: [f64; 6]) -> Option<f64> {
    let orient = |k2: f64| {
        let mut y = x;
        y[1] = k2;
        let s = scene(l_c, y);
        let ev = evaluate(&s, &y, &quick()).ok()?;
        let [e1, e2, e3] = ev.synthesis.positions.e;
        Some(cwsynth::geom::cross(e2 - e1, e3 - e1))
    };
    let (mut a, mut b) = (0.05, 3.0);
    let (fa, fb) = (orient(a)?, orient(b)?);
    if fa * fb > 0.0 {
        return None;
    }
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        let fm = orient(m)?;
        if (fm > 0.0) == (fa > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    Some(0.5 * (a + b))
}

#[test]
fn stated_delta_h_error_covers_the_double_double_truth() {
    let d = f64::to_radians;
    let thesis = [0.2, 0.4, d(35.0), d(10.0), d(5.0), d(12.0)];
    let mut cases: Vec<(f64, [f64; 6])> = Vec::new();
    // Issue 14's cases: k1 near 0 (down to 1e-15) and near 1 (up to 1 − 1e-14) on the
    // thesis example. As k1 → 1 the circle through E1 E2 E3 is fixed by E2 − E3 ≈ (1 − k1)
    // of the scale, so a reference error η in E2 moves Δh by ~η/(1 − k1): the reference
    // needs its ~1e-32 everywhere, which `common::Dd` gives (twofloat's own division, ~1e-17,
    // made the reference drift by 3.8e-16/(1 − k1) m here before).
    for k1 in [
        1e-15,
        1e-12,
        1e-10,
        1e-8,
        1e-4,
        0.5,
        1.0 - 1e-3,
        1.0 - 1e-4,
        1.0 - 1e-6,
        1.0 - 1e-8,
        1.0 - 1e-10,
        1.0 - 1e-12,
        1.0 - 1e-14,
    ] {
        for l_c in [1e-3, 22.8, 1e4] {
            let mut x = thesis;
            x[0] = k1;
            cases.push((l_c, x));
        }
    }
    // Random designs in the recommended ranges, some at tiny and huge scale.
    let mut rng = Rng(14);
    for i in 0..40 {
        let x = [
            rng.range(0.02, 0.98),
            rng.range(0.2, 1.0),
            d(rng.range(30.0, 45.0)),
            d(rng.range(5.0, 15.0)),
            d(rng.range(5.0, 10.0)),
            d(rng.range(10.0, 25.0)),
        ];
        let l_c = [22.8, 1e-3, 1e5][i % 3];
        cases.push((l_c, x));
        // Nearly collinear tail points beside the k2 of the straight guide.
        if i % 4 == 0 {
            if let Some(k2) = collinear_k2(l_c, x) {
                for f in [1.0 + 1e-3, 1.0 - 1e-6, 1.0 + 1e-9] {
                    let mut y = x;
                    y[1] = k2 * f;
                    cases.push((l_c, y));
                }
            }
        }
    }
    let (mut checked, mut outside, mut worst) = (0, Vec::new(), 0.0f64);
    for (l_c, x) in &cases {
        let o = solve(&scene(*l_c, *x), &quick()).unwrap();
        let Some(dh) = o.objectives.delta_h_m else {
            continue;
        };
        let Some(truth) = reference_delta_h(*l_c, *x) else {
            continue;
        };
        if o.status == Status::Degenerate {
            continue;
        }
        checked += 1;
        let err = o.errors.delta_h_m.unwrap();
        worst = worst.max((dh - truth).abs() / err);
        if (dh - truth).abs() > err {
            outside.push(format!(
                "L_c {l_c:e} x {x:?}: dh {dh:e} truth {truth:e} diff {:e} stated {err:e}",
                dh - truth
            ));
        }
    }
    eprintln!("{checked} designs, worst |error| / stated {worst:.3}");
    assert!(checked >= 60, "only {checked} cases checked");
    assert!(
        outside.is_empty(),
        "{} of {checked} outside:\n{}",
        outside.len(),
        outside.join("\n")
    );
}
#[test]
fn k1_at_or_beyond_one_is_refused() {
    // k1 = C1C2/C1C3 ≥ 1 puts C2 at or beyond C3: not a design, a clear error naming k1.
    let d = f64::to_radians;
    for k1 in [1.0, 1.0 + 1e-12, 1.0 + 1e-6, 0.0, -1e-15] {
        let x = [k1, 0.4, d(35.0), d(10.0), d(5.0), d(12.0)];
        let e = solve(&scene(22.8, x), &quick()).unwrap_err();
        assert_eq!(e.field, "design.k1", "{e}");
    }
}

#[test]
fn k1_near_one_converges() {
    // As k1 → 1 the circle through E1 E2 E3 tends to the one through E1 tangent to the tail
    // path at E3: Δh converges. Each value must agree with the next within the stated
    // errors plus the first-order change in k1 (|dΔh/dk1| ≤ 200 m here: the secant slope
    // is 156.5 m from 1 − 1e-6 to 1 − 1e-8 and again to 1 − 1e-10, so a drift growing as
    // ε/(1 − k1) would fail; the double-double check of the same k1 is in
    // `stated_delta_h_error_covers_the_double_double_truth`).
    let d = f64::to_radians;
    let mut prev: Option<(f64, f64, f64)> = None;
    for e in [1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
        let x = [1.0 - e, 0.4, d(35.0), d(10.0), d(5.0), d(12.0)];
        let o = solve(&scene(22.8, x), &quick()).unwrap();
        let (dh, err) = (o.objectives.delta_h_m.unwrap(), o.errors.delta_h_m.unwrap());
        assert!(
            o.design.tie_pin_x_m.is_some(),
            "tie pin dropped at 1 - {e:e}"
        );
        if let Some((pd, pe, pk)) = prev {
            assert!(
                (dh - pd).abs() <= err + pe + 200.0 * pk,
                "1 - {e:e}: {dh} vs {pd}"
            );
        }
        prev = Some((dh, err, e));
    }
}

#[test]
fn best_found_reaches_the_reference_optima() {
    // Reference optima: the same scenes solved with 40 SQP starts from 400 Halton points per
    // variable (every default run below uses 6 from 64), which ended at these values from 33
    // to 40 of their 40 starts; the tester found 0.2799 m (|AB| <= 15 m), 0.3491 m
    // (<= 10 m) and 0.182866 m (Tukan) independently. Target: within 1e-4 relative.
    let mut cases: Vec<(CraneScene, f64)> = Vec::new();
    for (r, best) in [
        (10.0, 0.3490972644),
        (15.0, 0.2799236701),
        (20.0, 0.2169971526),
        (30.0, 0.1358823085),
    ] {
        let mut s = thesis_optimisation_with_angles();
        s.tie_pin = TiePinLimit {
            max_distance: Some(r),
            x_range: Some([0.0, r]),
            y_range: None,
        };
        cases.push((s, best));
    }
    cases.push((tukan_40t_optimisation(), 0.1828656412));
    cases.push((tukan_40t(), 0.1921091562));
    cases.push((thesis_optimisation(), 0.5029242597));
    for (s, best) in cases {
        let o = solve(&s, &quick()).unwrap();
        assert_eq!(o.status, Status::BestFound);
        assert!(o.checks.iter().all(|c| c.pass), "{:?}", o.checks);
        let dh = o.objectives.delta_h_m.unwrap();
        assert!(dh <= best * (1.0 + 1e-4), "{dh} vs reference {best}");
        let ev = o.search.unwrap();
        assert!(ev.starts_at_best >= 1 && ev.best_values[0] <= dh * (1.0 + 1e-9));
    }
}

// ---------------------------------------------------------------------------------------
// The 6-variable multistart against an independent search on random cranes.
//
// The reference below shares only the model with cwsynth (`evaluate` for Δh and the
// feasibility verdict, `synthesize` for the tie pin): its search is a different algorithm —
// uniform random sampling (not Halton) and, from the best distinct samples and from
// cwsynth's own answer, a derivative-free pattern search over random orthonormal bases,
// each poll direction projected on the tangent space of the near-active constraints and
// pulled back onto them by Gauss–Newton restoration (a projection/restoration pattern
// search, no SQP, no QP, no penalty).

/// Unit-box coordinates → design x (all six variables free).
fn unbox(s: &CraneScene, u: &[f64; 6]) -> [f64; 6] {
    let v = s.vars();
    std::array::from_fn(|i| {
        let (lo, hi) = v[i].bounds();
        lo + u[i].clamp(0.0, 1.0) * (hi - lo)
    })
}

/// Signed constraints (m, ≤ 0 met) of a design, from the public model pieces: the tie-pin
/// limits, the reach shortfall at R_max, the reach excess at R_min and the height shortfall.
/// `None` without a tie circle (no geometry, or the straight-guide limit).
fn ref_constraints(s: &CraneScene, x: &[f64; 6]) -> Option<Vec<f64>> {
    use cwsynth::families::crane::model::{synthesize, Angles, Boom, Guide};
    let ang = Angles {
        phi_min: x[2],
        gamma1: x[3],
        gamma2: x[4],
        gamma3: x[5],
    };
    let k = ang.k()?;
    let boom = Boom::new(s.boom_length(&ang, k), ang).ok()?;
    let syn = synthesize(&boom, x[0], x[1]).ok()?;
    let Guide::Circle { centre: b, .. } = syn.guide else {
        return None;
    };
    let t = s.tie_pin;
    let mut c = Vec::new();
    c.extend(t.max_distance.map(|r| b.x.hypot(b.y) - r));
    if let Some([lo, hi]) = t.x_range {
        c.extend([lo - b.x, b.x - hi]);
    }
    if let Some([lo, hi]) = t.y_range {
        c.extend([lo - b.y, b.y - hi]);
    }
    let reach = |phi: f64, g: f64| boom.l_c * phi.cos() + boom.l_v() * g;
    c.push(s.reach_max - s.foot_offset - reach(x[2], x[5].cos()));
    c.push(reach(std::f64::consts::FRAC_PI_2 - x[3], x[4].sin()) - (s.reach_min - s.foot_offset));
    c.push(s.lift_height - s.foot_height - boom.head_height());
    Some(c)
}

/// The reference's objective: Δh of a design that cwsynth's model calls feasible (the same
/// `constraint_tol` as the solver), else `None`.
struct RefProblem<'a> {
    s: &'a CraneScene,
    set: Settings,
    evals: std::cell::Cell<usize>,
}

impl RefProblem<'_> {
    fn tol(&self) -> f64 {
        self.set.constraint_tol * (self.s.reach_max - self.s.foot_offset)
    }
    fn f(&self, u: &[f64; 6]) -> Option<f64> {
        let x = unbox(self.s, u);
        if ref_constraints(self.s, &x)?.iter().any(|&c| c > self.tol()) {
            return None;
        }
        self.evals.set(self.evals.get() + 1);
        let ev = evaluate(self.s, &x, &self.set).ok()?;
        (ev.violation() <= self.tol() && ev.tie_pin_violation.is_finite())
            .then(|| ev.delta_h())
            .flatten()
    }
    fn c(&self, u: &[f64; 6]) -> Option<Vec<f64>> {
        ref_constraints(self.s, &unbox(self.s, u))
    }
    /// Jacobian of the constraints over the unit box by central differences.
    fn jac(&self, u: &[f64; 6]) -> Option<Vec<[f64; 6]>> {
        let h = 1e-7;
        let c0 = self.c(u)?;
        let mut j = vec![[0.0; 6]; c0.len()];
        for k in 0..6 {
            let (mut a, mut b) = (*u, *u);
            a[k] = (u[k] + h).min(1.0);
            b[k] = (u[k] - h).max(0.0);
            let (ca, cb) = (self.c(&a)?, self.c(&b)?);
            for (r, row) in j.iter_mut().enumerate() {
                row[k] = (ca[r] - cb[r]) / (a[k] - b[k]);
            }
        }
        Some(j)
    }
}

fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The least-norm δ with J_r·δ = rhs_r for the rows `rows` (normal equations, Gauss–Jordan).
fn least_norm(j: &[[f64; 6]], rows: &[usize], rhs: &[f64]) -> Option<[f64; 6]> {
    let m = rows.len();
    let mut a: Vec<Vec<f64>> = (0..m)
        .map(|p| {
            let mut r: Vec<f64> = (0..m).map(|q| dot6(&j[rows[p]], &j[rows[q]])).collect();
            r.push(rhs[p]);
            r
        })
        .collect();
    for col in 0..m {
        let piv = (col..m).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        a.swap(col, piv);
        if a[col][col].abs() < 1e-300 {
            return None;
        }
        let pivot = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot[col];
                for (x, p) in row.iter_mut().zip(&pivot).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    let mut d = [0.0; 6];
    for (p, &r) in rows.iter().enumerate() {
        let w = a[p][m] / a[p][p];
        for k in 0..6 {
            d[k] += w * j[r][k];
        }
    }
    Some(d)
}

/// Pattern search from a feasible u with value f: polls ±(a random orthonormal basis
/// projected on the tangent space of the constraints within two steps of their bound) and
/// the inward normals of those constraints; an infeasible trial point is pulled back by up
/// to four Gauss–Newton (chord) restoration steps. Step doubled on success, halved on
/// failure, stop below 1e-9 of the box or after `budget` Δh evaluations.
fn pattern_search(
    p: &RefProblem,
    rng: &mut Rng,
    mut u: [f64; 6],
    mut f: f64,
    budget: usize,
) -> f64 {
    let start = p.evals.get();
    let mut s: f64 = 0.05;
    let Some(mut jac) = p.jac(&u) else {
        return f;
    };
    while s > 1e-9 && p.evals.get() - start < budget {
        let c = p.c(&u).expect("feasible point has constraints");
        let near: Vec<usize> = (0..c.len())
            .filter(|&r| c[r] > -2.0 * s * dot6(&jac[r], &jac[r]).sqrt())
            .collect();
        // Random orthonormal basis (Gram–Schmidt of Gaussian vectors).
        let mut basis: Vec<[f64; 6]> = Vec::new();
        while basis.len() < 6 {
            let mut v: [f64; 6] = std::array::from_fn(|_| {
                let (a, b) = (rng.next().max(1e-300), rng.next());
                (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
            });
            for w in &basis {
                let d = dot6(&v, w);
                for k in 0..6 {
                    v[k] -= d * w[k];
                }
            }
            let n = dot6(&v, &v).sqrt();
            if n > 1e-6 {
                basis.push(v.map(|x| x / n));
            }
        }
        let mut dirs: Vec<[f64; 6]> = Vec::new();
        for v in &basis {
            let proj = match least_norm(
                &jac,
                &near,
                &near.iter().map(|&r| dot6(&jac[r], v)).collect::<Vec<_>>(),
            ) {
                Some(d) if !near.is_empty() => std::array::from_fn(|k| v[k] - d[k]),
                _ => *v,
            };
            let n = dot6(&proj, &proj).sqrt();
            if n > 1e-9 {
                dirs.push(proj.map(|x| x / n));
                dirs.push(proj.map(|x| -x / n));
            }
        }
        for &r in &near {
            let n = dot6(&jac[r], &jac[r]).sqrt();
            if n > 0.0 {
                dirs.push(jac[r].map(|x| -x / n));
            }
        }
        let mut moved = false;
        for d in dirs {
            let mut z: [f64; 6] = std::array::from_fn(|k| (u[k] + s * d[k]).clamp(0.0, 1.0));
            for _ in 0..4 {
                let Some(cz) = p.c(&z) else { break };
                let viol: Vec<usize> = (0..cz.len()).filter(|&r| cz[r] > 0.0).collect();
                if viol.is_empty() {
                    break;
                }
                // Aim a hair inside: −1e-3 of the tolerance.
                let rhs: Vec<f64> = viol.iter().map(|&r| -cz[r] - 1e-3 * p.tol()).collect();
                let Some(dz) = least_norm(&jac, &viol, &rhs) else {
                    break;
                };
                z = std::array::from_fn(|k| (z[k] + dz[k]).clamp(0.0, 1.0));
            }
            if let Some(fz) = p.f(&z) {
                if fz < f - 1e-15 * f.abs() {
                    (u, f, moved) = (z, fz, true);
                    break;
                }
            }
        }
        if moved {
            s = (2.0 * s).min(0.2);
            match p.jac(&u) {
                Some(j) => jac = j,
                None => break,
            }
        } else {
            s *= 0.5;
        }
    }
    f
}

/// A random level-luffing crane near the thesis example or the Tukan 40 t crane: the
/// requirements scaled by 0.92–1.08 each, all six variables free in the rule-of-thumb and
/// recommended ranges, a tie-pin limit of 8–25 m in one of three shapes.
fn random_crane(rng: &mut Rng, i: usize) -> CraneScene {
    let base = if i.is_multiple_of(2) {
        thesis_optimisation_with_angles()
    } else {
        tukan_40t_optimisation()
    };
    let mut f = || rng.range(0.92, 1.08);
    let mut s = CraneScene {
        reach_max: base.reach_max * f(),
        reach_min: base.reach_min * f(),
        foot_offset: base.foot_offset * f(),
        lift_height: base.lift_height * f(),
        foot_height: base.foot_height * f(),
        k1: Var::Free {
            min: 0.05,
            max: 0.95,
        },
        k2: Var::Free { min: 0.2, max: 1.0 },
        sizing: if i % 3 == 2 {
            SizingRule::MaxReach
        } else {
            SizingRule::MinReach
        },
        ..base
    };
    let r = rng.range(8.0, 25.0);
    s.tie_pin = match i % 3 {
        0 => TiePinLimit {
            max_distance: Some(r),
            x_range: Some([0.0, r]),
            y_range: None,
        },
        1 => TiePinLimit {
            max_distance: Some(r),
            x_range: None,
            y_range: None,
        },
        _ => TiePinLimit {
            max_distance: None,
            x_range: Some([0.0, r]),
            y_range: Some([-0.5 * r, r]),
        },
    };
    s
}

/// cwsynth's Δh and the reference's on random crane `i` (`None` where neither finds a
/// feasible design), with the reference's Δh evaluations.
fn compare_random_crane(
    i: usize,
    samples: usize,
    starts: usize,
    budget: usize,
) -> Option<(f64, f64, usize)> {
    let mut rng = Rng(1400 + i as u64);
    let s = random_crane(&mut rng, i);
    let o = solve(&s, &quick()).unwrap();
    let cw = o.objectives.delta_h_m;
    let feasible = o
        .checks
        .iter()
        .all(|c| c.pass || c.name == "delta_h_allowed");
    let p = RefProblem {
        s: &s,
        set: quick(),
        evals: std::cell::Cell::new(0),
    };
    // Global stage: uniform random points; local stage from the best distinct ones.
    let mut pts: Vec<([f64; 6], f64)> = (0..samples)
        .filter_map(|_| {
            let u: [f64; 6] = std::array::from_fn(|_| rng.next());
            p.f(&u).map(|f| (u, f))
        })
        .collect();
    pts.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut chosen: Vec<([f64; 6], f64)> = Vec::new();
    for &(u, f) in &pts {
        if chosen.len() < starts
            && chosen.iter().all(|(w, _)| {
                u.iter()
                    .zip(w)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
                    .sqrt()
                    > 0.25
            })
        {
            chosen.push((u, f));
        }
    }
    // cwsynth's own answer polished by the reference's local search (the local check).
    if let (Some(_), true) = (cw, feasible) {
        let x: [f64; 6] = [
            o.design.vars.k1,
            o.design.vars.k2,
            o.design.vars.phi_min_rad,
            o.design.vars.gamma1_rad,
            o.design.vars.gamma2_rad,
            o.design.vars.gamma3_rad,
        ];
        let v = s.vars();
        let u: [f64; 6] = std::array::from_fn(|k| {
            let (lo, hi) = v[k].bounds();
            (x[k] - lo) / (hi - lo)
        });
        if let Some(f) = p.f(&u) {
            chosen.push((u, f));
        }
    }
    let reference = chosen
        .into_iter()
        .map(|(u, f)| pattern_search(&p, &mut rng, u, f, budget))
        .fold(f64::INFINITY, f64::min);
    if !reference.is_finite() {
        assert!(
            !feasible || cw.is_none(),
            "crane {i}: only cwsynth found a feasible design: {cw:?}"
        );
        return None;
    }
    assert!(
        feasible && o.status == Status::BestFound,
        "crane {i}: the reference found a feasible design (dh {reference}), cwsynth says {:?} {:?}",
        o.status,
        o.checks
    );
    let cw = cw.unwrap();
    let ev = o.search.as_ref().unwrap();
    assert!(
        ev.starts_at_best >= 1 && ev.starts_at_best <= ev.starts,
        "crane {i}: {ev:?}"
    );
    assert!(
        ev.distinct_basins >= 1 && ev.distinct_basins <= ev.starts,
        "crane {i}: {ev:?}"
    );
    assert!(
        (ev.best_values[0] - cw).abs() <= 1e-9 * cw,
        "crane {i}: the evidence's best {} is not the reported {cw}",
        ev.best_values[0]
    );
    assert!(
        ev.best_values.windows(2).all(|w| w[0] <= w[1]),
        "crane {i}: {ev:?}"
    );
    Some((cw, reference, p.evals.get()))
}

/// Runs cranes `range` and asserts cwsynth within 1e-4 relative of the reference; prints
/// one line per crane (`--nocapture`). `CRANE_REF_SCALE` multiplies the reference's effort
/// (for a measurement run: `CRANE_REF_SCALE=10 CRANE_CASES=60 cargo test --release ...`).
fn random_cranes(range: std::ops::Range<usize>) {
    let scale = env_count("CRANE_REF_SCALE", 1);
    let (mut lost, mut compared) = (Vec::new(), 0);
    for i in range {
        let Some((cw, reference, evals)) =
            compare_random_crane(i, 600 * scale, 4 + scale, 1500 * scale)
        else {
            eprintln!("crane {i}: no feasible design (both agree)");
            continue;
        };
        compared += 1;
        let rel = (cw - reference) / reference;
        eprintln!("crane {i}: cwsynth {cw:.10} reference {reference:.10} rel {rel:+.3e} ({evals} reference evaluations)");
        if rel > 1e-4 {
            lost.push(format!(
                "crane {i}: cwsynth {cw} reference {reference} ({rel:+.2e})"
            ));
        }
    }
    assert!(compared >= 1);
    assert!(
        lost.is_empty(),
        "cwsynth beaten by more than 1e-4:\n{}",
        lost.join("\n")
    );
}

/// An environment setting (`CRANE_CASES`, `CRANE_REF_SCALE`) or its default.
fn env_count(key: &str, default: usize) -> usize {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn random_cranes_best_found_is_not_beaten_a() {
    random_cranes(0..env_count("CRANE_CASES", 12).div_ceil(2));
}

#[test]
fn random_cranes_best_found_is_not_beaten_b() {
    let n = env_count("CRANE_CASES", 12);
    random_cranes(n.div_ceil(2)..n);
}
