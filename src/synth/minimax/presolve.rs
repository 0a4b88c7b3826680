//! The exact disc path: the peak of a turning counterweight's force solved as the smallest
//! enclosing disc of the curve p(θ) (the shared [`crate::synth::exchange::DiscForm`]),
//! without clarabel, with its own Lagrangian certificate.

use super::{
    var_i, var_m, var_u, AffineValue, Engine, Goal, MinimaxError, Solution, Stop, DISC_SOLVER,
};
use crate::geom::{Disc, P2};
use crate::numeric::PeriodicPeak;
use crate::synth::exchange::{
    angle_dist, nearest_maximum, uniform_angles, Affine, DiscForm, DiscSamples, Status,
};

/// The end of a disc path that met the tolerance: (field, support angles with weights,
/// design, its refined peak, V, L, round).
type DiscEnd<'m> = (
    usize,
    &'m [(f64, f64)],
    Vec<f64>,
    PeriodicPeak,
    f64,
    f64,
    usize,
);

/// A disc round's design x and the weights (angle, λ) on its disc's support.
type DiscDesign = (Vec<f64>, Vec<(f64, f64)>);

/// The u block of counterweight 0 in a field's value: the 2×2 map u ↦ A_u u + b.
fn u_block(v: &AffineValue) -> Affine {
    let ux = var_u(0);
    Affine {
        a: [
            [v.row(0)[ux], v.row(0)[ux + 1]],
            [v.row(1)[ux], v.row(1)[ux + 1]],
        ],
        b: v.b,
    }
}

impl<'p, 'a> Engine<'p, 'a> {
    /// The peak of a turning counterweight's force solved exactly, without clarabel, when
    /// the problem is one ([`Engine::disc_goal`]): then |g| = c|u − p(θ)| with p = −Qᵀb/c
    /// ([`DiscForm`]), and the minimax over sampled angles is the smallest disc enclosing
    /// the points p(θ_k) (Welzl, [`crate::geom::enclosing_disc`], first on the scan grid),
    /// its support angles polished on the continuous curve by Newton (`polish_support`).
    ///
    /// The certificate is the engine's own: V is the refined peak at the design (the scan of
    /// [`Engine::scan`]), L the Lagrangian bound of [`Engine::disc_bound`] at the disc's
    /// support, with its weights (the barycentric coordinates of the centre) moved to the
    /// nearby refined maxima; both rest on no structure (the form only chooses the design).
    /// The maxima above L are added until V − L ≤ `rel_tol`·max(V, `abs_floor`·U₀); `None`
    /// (clarabel's loop runs instead) when the problem is not of this form, the centre is
    /// out of the counterweight's reach ([`Engine::disc_design`]) or the gap does not close
    /// in a few rounds.
    pub(super) fn disc_path(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
    ) -> Result<Option<Solution>, MinimaxError> {
        let Some((f, w)) = self.disc_goal(goal, limits) else {
            return Ok(None);
        };
        let grid: Vec<Affine> = self.grid[f].iter().map(u_block).collect();
        let field = self.pb.fields[f];
        let eval = |phi: f64| {
            let mut v = AffineValue::zeros(self.n);
            field.eval(phi, &mut v);
            u_block(&v)
        };
        let Some(form) = DiscForm::scaled_by(&eval(0.0)) else {
            return Ok(None);
        };
        // The sampled points: the scan grid's (already evaluated), then the angles added.
        let mut pts = DiscSamples::default();
        for (t, a) in uniform_angles(grid.len()).into_iter().zip(&grid) {
            match form.point_of(a) {
                Some(p) => pts.push(t, p),
                None => return Ok(None),
            }
        }
        let point = |t: f64| form.point_of(&eval(t));
        let floor = self.s.abs_floor * w * self.g0[f];
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        const ROUNDS: usize = 6;
        for round in 1..=ROUNDS {
            let Some(disc) = pts.disc() else {
                return Ok(None);
            };
            let Some((x, weights)) = self.disc_design(&pts, &disc, &point) else {
                return Ok(None);
            };
            let pk = self.scan(f, &x)?;
            let value = w * pk.peak.fx;
            let moved: Vec<(f64, f64)> = weights
                .iter()
                .map(|&(t, l)| (nearest_maximum(&pk.maxima, t, 2.0 * h), l))
                .collect();
            let lower = w * self
                .disc_bound(f, &weights)?
                .max(self.disc_bound(f, &moved)?);
            let gap_scale = value.max(floor);
            if value - lower <= self.s.rel_tol * gap_scale {
                let disc = (f, &moved[..], x, pk, value, lower, round);
                return self.disc_solution(goal, limits, disc).map(Some);
            }
            let before = pts.len();
            for &(t, _) in &weights {
                pts.add_new(t, point);
            }
            for e in &pk.maxima {
                if w * e.fx > lower + 0.5 * self.s.rel_tol * gap_scale {
                    pts.add_new(e.x, point);
                }
            }
            if pts.len() == before {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// The objective (field, weight) when the problem is a turning counterweight's peak
    /// force: the goal is the peak of one 2-D field w·|g|, with no limit, no extra variable,
    /// no linear row, one counterweight without a sector, and at every scan angle A(θ) has
    /// zero m and I columns (its u block c·Q(θ), Q orthogonal, one constant c > 0, is
    /// [`DiscForm`]'s test: a counterweight on a frame pivot turning with the crank,
    /// F = b + c·Rot(θ)·u). `None` otherwise (and with `exact_disc = false`).
    pub(super) fn disc_goal(&self, goal: &Goal, limits: &[(usize, f64)]) -> Option<(usize, f64)> {
        let pb = self.pb;
        let Goal::MinPeak(list) = goal else {
            return None;
        };
        let &[(f, w)] = list.as_slice() else {
            return None;
        };
        if !(self.s.exact_disc
            && limits.is_empty()
            && pb.extra.is_empty()
            && pb.linear.is_empty()
            && pb.counterweights.len() == 1
            && pb.counterweights[0].sector.is_none()
            && pb.counterweights[0].plate.is_none()
            && pb.fields[f].dim() == 2)
        {
            return None;
        }
        let (m, ii) = (var_m(0), var_i(0));
        let only_u = |v: &AffineValue| (0..2).all(|r| v.row(r)[m] == 0.0 && v.row(r)[ii] == 0.0);
        self.grid[f].iter().all(only_u).then_some((f, w))
    }

    /// The design of a round of the disc path and the weights of its support: the disc's
    /// centre u, its support angles polished to the continuous curve's (Newton,
    /// `polish_support`, so the design does not creep towards a maximum that moves with
    /// it; kept only if the centre is inside the polished points' hull, all weights > 0:
    /// still a disc's support). Of all the counterweights with this u the design is the
    /// lightest: m = max(|u|/r_max, |u|/ρ, |u|²/I_max), a point mass (I = |u|²/m); the
    /// field does not depend on m or I. `None` when u is out of the counterweight's reach
    /// (|u| ≤ m_max·min(r_max, ρ), |u|² ≤ I_max·m_max).
    pub(super) fn disc_design(
        &self,
        pts: &DiscSamples,
        disc: &Disc,
        point: &dyn Fn(f64) -> Option<P2>,
    ) -> Option<DiscDesign> {
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        let mut weights = support_weights(pts, disc);
        let mut u = disc.centre;
        if let Some((t, c)) = polish_support(point, &weights, h) {
            let ps: Vec<(f64, P2)> = t.iter().filter_map(|&a| point(a).map(|p| (a, p))).collect();
            let d = Disc {
                centre: c,
                radius: ps.iter().map(|q| (q.1 - c).norm()).fold(0.0, f64::max),
            };
            let wt = support_weights(&DiscSamples::of(&ps), &d);
            if wt.len() == ps.len() {
                weights = wt;
                u = c;
            }
        }
        let c = &self.pb.counterweights[0];
        let reach = (c.m_max * c.r_max.min(c.envelope)).min((c.inertia_max * c.m_max).sqrt());
        let un = u.norm();
        if !(un <= reach) {
            return None;
        }
        // The lightest counterweight with this u.
        let mass = [un / c.r_max, un / c.envelope, un * un / c.inertia_max]
            .into_iter()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
            .min(c.m_max);
        let (m, ux, ii) = (var_m(0), var_u(0), var_i(0));
        let mut x = vec![0.0; self.n];
        x[m] = mass;
        x[ux] = u.x;
        x[ux + 1] = u.y;
        x[ii] = if mass > 0.0 { un * un / mass } else { 0.0 };
        Some((self.project(&x), weights))
    }

    /// The certified solution of the disc path: the design x with its refined peak `pk` of
    /// field f (value V), the bound L, the support angles `moved` as the sampled set.
    pub(super) fn disc_solution(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        (f, moved, x, pk, value, lower, round): DiscEnd,
    ) -> Result<Solution, MinimaxError> {
        let nf = self.pb.fields.len();
        let mut sets: Vec<Vec<(f64, AffineValue)>> = vec![Vec::new(); nf];
        for &(t, _) in moved {
            self.insert(&mut sets[f], f, t)?;
        }
        let mut pks = vec![None; nf];
        pks[f] = Some(pk);
        self.finish(
            goal,
            limits,
            &sets,
            &x,
            pks,
            value,
            (lower, 0.0, true),
            Status::Optimal,
            Stop::Converged,
            None,
            round,
            0,
            DISC_SOLVER.into(),
        )
    }

    /// A Lagrangian lower bound of min_u max_θ |g_f(θ; u)| for a field that depends on
    /// counterweight 0's u only: for weights λ_k ≥ 0, Σλ_k = 1 at any angles θ_k,
    /// max_θ |g|² ≥ Σ_k λ_k |b_k + A_k u|² =: q(u) ≥ min q, so √(min q) is a lower bound.
    /// min q is computed as q(u*) − ¼∇qᵀQ⁻¹∇q at the computed minimiser u* = −Q⁻¹r
    /// (q = uᵀQu + 2rᵀu + c: exact for a quadratic, whatever the error of u*), less the
    /// round-off of q(u*) (16(n + 3)ε of its absolute terms). 0 when Q is singular.
    pub(super) fn disc_bound(&self, f: usize, terms: &[(f64, f64)]) -> Result<f64, MinimaxError> {
        let ux = var_u(0);
        let (mut q, mut r) = ([[0.0; 2]; 2], [0.0; 2]);
        let mut vals = Vec::with_capacity(terms.len());
        for &(t, l) in terms {
            let v = self.eval(f, t)?;
            let a = [
                [v.row(0)[ux], v.row(0)[ux + 1]],
                [v.row(1)[ux], v.row(1)[ux + 1]],
            ];
            for i in 0..2 {
                for j in 0..2 {
                    q[i][j] += l * (a[0][i] * a[0][j] + a[1][i] * a[1][j]);
                }
                r[i] += l * (a[0][i] * v.b[0] + a[1][i] * v.b[1]);
            }
            vals.push((l, a, v.b));
        }
        let det = q[0][0] * q[1][1] - q[0][1] * q[1][0];
        if !(det > 0.0) || terms.is_empty() {
            return Ok(0.0);
        }
        let inv = [
            [q[1][1] / det, -q[0][1] / det],
            [-q[1][0] / det, q[0][0] / det],
        ];
        let u = [
            -(inv[0][0] * r[0] + inv[0][1] * r[1]),
            -(inv[1][0] * r[0] + inv[1][1] * r[1]),
        ];
        let (mut val, mut size) = (0.0, 0.0);
        let mut grad = [0.0; 2];
        for (l, a, b) in &vals {
            let mut s2 = 0.0;
            for k in 0..2 {
                let g = b[k] + a[k][0] * u[0] + a[k][1] * u[1];
                val += l * g * g;
                let abs = b[k].abs() + (a[k][0] * u[0]).abs() + (a[k][1] * u[1]).abs();
                s2 += abs * abs;
                for (i, gi) in grad.iter_mut().enumerate() {
                    *gi += 2.0 * l * a[k][i] * g;
                }
            }
            size += l * s2;
        }
        let gamma = 16.0 * (self.n as f64 + 3.0) * f64::EPSILON;
        // ¼∇ᵀQ⁻¹∇ ≤ ¼|∇|²/λ_min(Q), with |∇| raised by its own round-off.
        let tr = q[0][0] + q[1][1];
        let lmin = 0.5 * (tr - ((q[0][0] - q[1][1]).powi(2) + 4.0 * q[0][1] * q[1][0]).sqrt());
        let gn = grad[0].hypot(grad[1]) + 2.0 * gamma * size.sqrt() * tr.sqrt();
        if !(lmin > 0.0) {
            return Ok(0.0);
        }
        let l2 = val - 0.25 * gn * gn / (lmin * (1.0 - 1e-12)) - gamma * size;
        Ok(l2.max(0.0).sqrt())
    }
}

/// Weights λ ≥ 0, Σλ = 1, on the support of a smallest enclosing disc of the points
/// (angle, p): the points within 1e-9 of the radius from the centre; the centre's
/// barycentric coordinates in a triangle of them that contains it, else in their farthest
/// pair (projected onto it). Any weights give a valid bound ([`Engine::disc_bound`]); these
/// make it the disc's radius.
pub(super) fn support_weights(pts: &DiscSamples, disc: &Disc) -> Vec<(f64, f64)> {
    let on: Vec<(f64, P2)> = pts
        .angles
        .iter()
        .zip(&pts.points)
        .filter(|(_, p)| (*p - disc.centre).norm() >= disc.radius * (1.0 - 1e-9))
        .map(|(&t, &p)| (t, p))
        .collect();
    let c = disc.centre;
    for i in 0..on.len() {
        for j in i + 1..on.len() {
            for k in j + 1..on.len() {
                let (a, b, d) = (on[i].1, on[j].1, on[k].1);
                let det = crate::geom::cross(b - a, d - a);
                if det == 0.0 {
                    continue;
                }
                let lb = crate::geom::cross(c - a, d - a) / det;
                let ld = crate::geom::cross(b - a, c - a) / det;
                let la = 1.0 - lb - ld;
                if la >= 0.0 && lb >= 0.0 && ld >= 0.0 {
                    return vec![(on[i].0, la), (on[j].0, lb), (on[k].0, ld)];
                }
            }
        }
    }
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..on.len() {
        for j in i + 1..on.len() {
            let d = (on[i].1 - on[j].1).norm();
            if best.is_none_or(|b| d > b.0) {
                best = Some((d, i, j));
            }
        }
    }
    match best {
        Some((d, i, j)) if d > 0.0 => {
            let (a, b) = (on[i].1, on[j].1);
            let t = ((c - a).dot(&(b - a)) / (d * d)).clamp(0.0, 1.0);
            vec![(on[i].0, 1.0 - t), (on[j].0, t)]
        }
        _ => on.first().map_or(Vec::new(), |p| vec![(p.0, 1.0)]),
    }
}

/// Newton on the support angles θ_i of a smallest enclosing disc of a curve p(θ) (2 or 3
/// points): each must be a stationary point of |p(θ) − v| with v the centre of the disc
/// through the points (their midpoint, or circumcentre), F_i = (p(θ_i) − v)·p'(θ_i) = 0,
/// p' by central differences (step 1e-5), the Jacobian by forward differences of F. Where
/// a maximum moves with the design (a disc on two points, free to slide across their
/// diameter), the exchange alone creeps towards it; this locates it in a few steps.
/// `None` if a step leaves the scan spacing `h` or the iteration does not settle.
pub(super) fn polish_support(
    point: &dyn Fn(f64) -> Option<P2>,
    weights: &[(f64, f64)],
    h: f64,
) -> Option<(Vec<f64>, P2)> {
    use P2;
    let centre = |ps: &[P2]| -> Option<P2> {
        if ps.len() == 2 {
            Some(0.5 * (ps[0] + ps[1]))
        } else {
            crate::geom::circumcentre(ps[0], ps[1], ps[2]).map(|c| c.0)
        }
    };
    let eta = 1e-5;
    let resid = |th: &[f64]| -> Option<(Vec<f64>, P2)> {
        let ps: Vec<P2> = th.iter().map(|&t| point(t)).collect::<Option<_>>()?;
        let v = centre(&ps)?;
        let mut f = Vec::with_capacity(th.len());
        for (i, &t) in th.iter().enumerate() {
            let d = (point(t + eta)? - point(t - eta)?) / (2.0 * eta);
            f.push((ps[i] - v).dot(&d));
        }
        Some((f, v))
    };
    // Support points around one maximum of the curve (neighbouring samples) are one.
    let mut merged: Vec<(f64, f64)> = Vec::new();
    for &(t, l) in weights {
        match merged.iter_mut().find(|m| angle_dist(m.0, t) <= 2.0 * h) {
            Some(m) if l > m.1 => *m = (t, m.1 + l),
            Some(m) => m.1 += l,
            None => merged.push((t, l)),
        }
    }
    let k = merged.len();
    if !(k == 2 || k == 3) {
        return None;
    }
    let mut th: Vec<f64> = merged.iter().map(|w| w.0).collect();
    let start = th.clone();
    let eta2 = 1e-6;
    let mut last_step = f64::INFINITY;
    for _ in 0..10 {
        let (f, _) = resid(&th)?;
        let mut jac = nalgebra::DMatrix::<f64>::zeros(k, k);
        for j in 0..k {
            let mut t2 = th.clone();
            t2[j] += eta2;
            let (f2, _) = resid(&t2)?;
            for i in 0..k {
                jac[(i, j)] = (f2[i] - f[i]) / eta2;
            }
        }
        let step = jac.lu().solve(&nalgebra::DVector::from_vec(f))?;
        let mut big: f64 = 0.0;
        for j in 0..k {
            th[j] -= step[j];
            big = big.max(step[j].abs());
        }
        if th.iter().zip(&start).any(|(a, b)| angle_dist(*a, *b) > h) {
            return None;
        }
        // Quadratic convergence: the next step would be below 1e-16; a step that does not
        // shrink is the differences' noise.
        if big <= 1e-9 || big >= last_step {
            break;
        }
        last_step = big;
    }
    let (_, v) = resid(&th)?;
    Some((
        th.iter()
            .map(|t| t.rem_euclid(std::f64::consts::TAU))
            .collect(),
        v,
    ))
}
