//! The exact disc path: the peak of a turning counterweight's force solved as the smallest
//! enclosing disc of the curve p(θ) (the shared [`crate::synth::exchange::DiscForm`]),
//! without clarabel, with its own Lagrangian certificate. Several goal fields of one scale
//! (an operating envelope's scenarios at one speed) are one disc over the union of their
//! curves; the goal's other fields are only scanned for the certificate.

use super::grid::GridValue;
use super::{
    var_i, var_m, var_u, AffineValue, Engine, Goal, MinimaxError, Multiplier, Solution, Stop,
    DISC_SOLVER,
};
use crate::geom::{Disc, P2};
use crate::numeric::PeriodicPeak;
use crate::synth::exchange::{
    angle_dist, nearest_maximum, uniform_angles, Affine, DiscForm, DiscSamples, Status,
};

/// A sample of the disc path: (member k of the [`DiscGroup`], θ).
pub(super) type Tag = (usize, f64);

/// The end of a disc path that met the tolerance: (support samples with weights, design,
/// the refined peak of every goal field in the goal's order, V, L, round).
type DiscEnd<'m> = (
    &'m [(Tag, f64)],
    Vec<f64>,
    Vec<PeriodicPeak>,
    f64,
    f64,
    usize,
);

/// A disc round's design x and the weights (sample, λ) on its disc's support.
type DiscDesign = (Vec<f64>, Vec<(Tag, f64)>);

/// The goal's fields the disc path solves as one disc: each a turning counterweight's force
/// w·c·|u − p(θ)| with the same scale w·c, the largest of the goal's.
pub(super) struct DiscGroup {
    /// Each member's index in the goal's list.
    pub members: Vec<usize>,
    /// Each member's form (its c).
    forms: Vec<DiscForm>,
}

/// The u block of counterweight 0 in a field's value: the 2×2 map u ↦ A_u u + b.
fn u_block(v: GridValue) -> Affine {
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
    /// the points p(θ_k) of every member of the group (Welzl,
    /// [`crate::geom::enclosing_disc`], first on the scan grids), its support angles
    /// polished on the continuous curves by Newton (`polish_support`).
    ///
    /// The certificate is the engine's own: V is the largest refined peak of every goal
    /// field at the design (the scan of [`Engine::scan`], the group's members and the
    /// others alike), L the Lagrangian bound of [`Engine::disc_bound`] at the disc's
    /// support, with its weights (the barycentric coordinates of the centre) moved to the
    /// nearby refined maxima — a bound on the whole goal, since it weighs some of its
    /// maxima; both rest on no structure (the form only chooses the design). The maxima
    /// above L are added until V − L ≤ `rel_tol`·max(V, `abs_floor`·U₀); `None` (clarabel's
    /// loop runs instead) when the problem is not of this form, the centre is out of the
    /// counterweight's reach ([`Engine::disc_design`]) or the gap does not close in a few
    /// rounds (a field outside the group binds).
    pub(super) fn disc_path(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
    ) -> Result<Option<Solution>, MinimaxError> {
        let (Some(group), Goal::MinPeak(list)) = (self.disc_goal(goal, limits), goal) else {
            return Ok(None);
        };
        let point = |k: usize, t: f64| {
            let mut v = AffineValue::zeros(self.n);
            self.pb.fields[list[group.members[k]].0].eval(t, &mut v);
            group.forms[k].point_of(&u_block(v.view()))
        };
        // The sampled points: the scan grids' (already evaluated), then the angles added.
        let mut pts = Vec::with_capacity(group.members.len());
        for (k, &i) in group.members.iter().enumerate() {
            let grid = &self.grid[list[i].0];
            // Room for the grid and the angles a few rounds add.
            let mut s = DiscSamples::with_capacity(grid.len() + 16);
            for (t, v) in uniform_angles(grid.len()).into_iter().zip(grid.iter()) {
                match group.forms[k].point_of(&u_block(v)) {
                    Some(p) => s.push(t, p),
                    None => return Ok(None),
                }
            }
            pts.push(s);
        }
        let scale = |k: usize| list[group.members[k]].1;
        let floor = list
            .iter()
            .map(|&(f, w)| self.s.abs_floor * w * self.g0[f])
            .fold(0.0, f64::max);
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        const ROUNDS: usize = 6;
        for round in 1..=ROUNDS {
            let (tags, points) = union(&pts);
            let Some(disc) = crate::geom::enclosing_disc(&points) else {
                return Ok(None);
            };
            let Some((x, weights)) = self.disc_design(&tags, &points, &disc, &point) else {
                return Ok(None);
            };
            let pks = list
                .iter()
                .map(|&(f, _)| self.scan(f, &x))
                .collect::<Result<Vec<_>, _>>()?;
            let value = list
                .iter()
                .zip(&pks)
                .map(|(&(_, w), p)| w * p.peak.fx)
                .fold(0.0, f64::max);
            let maxima = |k: usize| &pks[group.members[k]].maxima;
            let moved: Vec<(Tag, f64)> = weights
                .iter()
                .map(|&((k, t), l)| ((k, nearest_maximum(maxima(k), t, 2.0 * h)), l))
                .collect();
            let lower = self
                .disc_bound(list, &group, &weights)?
                .max(self.disc_bound(list, &group, &moved)?);
            let gap_scale = value.max(floor);
            if value - lower <= self.s.rel_tol * gap_scale {
                let disc = (&moved[..], x, pks, value, lower, round);
                return self.disc_solution(goal, limits, &group, disc).map(Some);
            }
            let before: usize = pts.iter().map(DiscSamples::len).sum();
            for &((k, t), _) in &weights {
                pts[k].add_new(t, |t| point(k, t));
            }
            for (k, s) in pts.iter_mut().enumerate() {
                for e in maxima(k) {
                    if scale(k) * e.fx > lower + 0.5 * self.s.rel_tol * gap_scale {
                        s.add_new(e.x, |t| point(k, t));
                    }
                }
            }
            if pts.iter().map(DiscSamples::len).sum::<usize>() == before {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// The group of the goal's fields the disc path solves, when the problem is a turning
    /// counterweight's peak force: the goal is the peak of 2-D fields w·|g|, with no
    /// limit, no extra variable, no linear row, one counterweight without a sector, and at
    /// every scan angle each field's A(θ) has zero m and I columns (its u block c·Q(θ), Q
    /// orthogonal, one constant c > 0, is [`DiscForm`]'s test: a counterweight on a frame
    /// pivot turning with the crank, F = b + c·Rot(θ)·u). The group is the fields of the
    /// largest scale w·c (to 1e-12): one disc. `None` otherwise (and with
    /// `exact_disc = false`).
    pub(super) fn disc_goal(&self, goal: &Goal, limits: &[(usize, f64)]) -> Option<DiscGroup> {
        let pb = self.pb;
        let Goal::MinPeak(list) = goal else {
            return None;
        };
        if !(self.s.exact_disc
            && !list.is_empty()
            && limits.is_empty()
            && pb.extra.is_empty()
            && pb.linear.is_empty()
            && pb.counterweights.len() == 1
            && pb.counterweights[0].sector.is_none()
            && pb.counterweights[0].plate.is_none())
        {
            return None;
        }
        let (m, ii) = (var_m(0), var_i(0));
        let only_u = |v: GridValue| (0..2).all(|r| v.row(r)[m] == 0.0 && v.row(r)[ii] == 0.0);
        let mut forms = Vec::with_capacity(list.len());
        for &(f, w) in list {
            if pb.fields[f].dim() != 2 || !self.grid[f].iter().all(only_u) {
                return None;
            }
            // c from the scan grid's first value (θ = 0), already evaluated.
            let form = DiscForm::scaled_by(&u_block(self.grid[f].first()?))?;
            forms.push((form, w * form.c()));
        }
        let top = forms.iter().map(|f| f.1).fold(0.0, f64::max);
        let (members, forms) = forms
            .into_iter()
            .enumerate()
            .filter(|(_, f)| (f.1 - top).abs() <= 1e-12 * top)
            .map(|(i, f)| (i, f.0))
            .unzip();
        Some(DiscGroup { members, forms })
    }

    /// The design of a round of the disc path and the weights of its support: the disc's
    /// centre u, its support angles polished to the continuous curves' (Newton,
    /// `polish_support`, so the design does not creep towards a maximum that moves with
    /// it; kept only if the centre is inside the polished points' hull, all weights > 0:
    /// still a disc's support). Of all the counterweights with this u the design is the
    /// lightest: m = max(|u|/r_max, |u|/ρ, |u|²/I_max), a point mass (I = |u|²/m); the
    /// field does not depend on m or I. `None` when u is out of the counterweight's reach
    /// (|u| ≤ m_max·min(r_max, ρ), |u|² ≤ I_max·m_max).
    pub(super) fn disc_design(
        &self,
        tags: &[Tag],
        points: &[P2],
        disc: &Disc,
        point: &dyn Fn(usize, f64) -> Option<P2>,
    ) -> Option<DiscDesign> {
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        let mut weights = support_weights(tags, points, disc);
        let mut u = disc.centre;
        if let Some((t, c)) = polish_support(point, &weights, h) {
            let ps: Vec<(Tag, P2)> = t
                .iter()
                .filter_map(|&(k, a)| point(k, a).map(|p| ((k, a), p)))
                .collect();
            let d = Disc {
                centre: c,
                radius: ps.iter().map(|q| (q.1 - c).norm()).fold(0.0, f64::max),
            };
            let (pt, pp): (Vec<Tag>, Vec<P2>) = ps.iter().copied().unzip();
            let wt = support_weights(&pt, &pp, &d);
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

    /// The certified solution of the disc path: the design x with the refined peaks `pks`
    /// of the goal's fields (value V), the bound L, the support angles `moved` as the
    /// sampled set, and their weights as the optimum's multipliers (the envelope theorem's:
    /// the centre of the smallest enclosing disc is their weighted mean, the KKT condition
    /// of min_u max_k |u − p_k|), each with the change of the centre's barycentric
    /// coordinates between the disc's support and the refined maxima as its error.
    pub(super) fn disc_solution(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        group: &DiscGroup,
        (moved, x, pks, value, lower, round): DiscEnd,
    ) -> Result<Solution, MinimaxError> {
        let Goal::MinPeak(list) = goal else {
            unreachable!("the disc path's goal is a peak");
        };
        let field = |k: usize| list[group.members[k]];
        let nf = self.pb.fields.len();
        let mut sets: Vec<Vec<(f64, AffineValue)>> = vec![Vec::new(); nf];
        for &((k, t), _) in moved {
            let f = field(k).0;
            self.insert(&mut sets[f], f, t)?;
        }
        let mut peaks = vec![None; nf];
        for (&(f, _), pk) in list.iter().zip(pks) {
            peaks[f] = Some(pk);
        }
        let mut sol = self.finish(
            goal,
            limits,
            &sets,
            &x,
            peaks,
            value,
            (lower, 0.0, true),
            Status::Optimal,
            Stop::Converged,
            None,
            round,
            0,
            DISC_SOLVER.into(),
        )?;
        if sol.status == Status::Optimal {
            sol.multipliers = self.disc_multipliers(group, moved, &x, &field);
        }
        Ok(sol)
    }

    /// The disc's weights as [`Multiplier`]s at the support moved to the design's refined
    /// maxima: weight w·λ', λ' the design's u in barycentric coordinates of those maxima's
    /// points (located by the peak scan, not by the disc). Its error is |λ − λ'| (λ the
    /// disc's own weights) plus the conditioning of the barycentric solve: the change of λ'
    /// when each support angle moves by τ = max(`peak_xtol`, 1e-8) either way (a maximum's
    /// angle is known to about √ε from values), summed over the points, plus 1e-12. Where
    /// the maxima do not hold u: w·λ with all of it as its error.
    fn disc_multipliers(
        &self,
        group: &DiscGroup,
        moved: &[(Tag, f64)],
        x: &[f64],
        field: &dyn Fn(usize) -> (usize, f64),
    ) -> Vec<Multiplier> {
        let ux = var_u(0);
        let u = P2::new(x[ux], x[ux + 1]);
        let point = |k: usize, t: f64| {
            let mut v = AffineValue::zeros(self.n);
            self.pb.fields[field(k).0].eval(t, &mut v);
            group.forms[k].point_of(&u_block(v.view()))
        };
        let at = |on: &[(Tag, P2)]| -> Option<Vec<f64>> {
            let b = barycentric(u, on);
            let same = b.len() == on.len() && b.iter().zip(on).all(|(b, t)| b.0 == t.0);
            same.then(|| b.iter().map(|b| b.1).collect())
        };
        // The support's points, evaluated once; a moved angle re-evaluates its own alone.
        let on: Option<Vec<(Tag, P2)>> = moved
            .iter()
            .map(|&((k, t), _)| point(k, t).map(|p| ((k, t), p)))
            .collect();
        let tags: Vec<Tag> = moved.iter().map(|m| m.0).collect();
        let tau = self.s.peak_xtol.max(1e-8);
        let weights = on.as_deref().and_then(at).and_then(|l2| {
            let on = on.as_deref()?;
            let mut err = vec![1e-12; tags.len()];
            for i in 0..tags.len() {
                for s in [-tau, tau] {
                    let mut t = on.to_vec();
                    let (k, a) = (tags[i].0, tags[i].1 + s);
                    t[i] = ((k, a), point(k, a)?);
                    let l3 = at(&t)?;
                    let mut worst = vec![0.0_f64; tags.len()];
                    for (w, (a, b)) in worst.iter_mut().zip(l3.iter().zip(&l2)) {
                        *w = w.max((a - b).abs());
                    }
                    err.iter_mut().zip(worst).for_each(|(e, w)| *e += w);
                }
            }
            Some((l2, err))
        });
        moved
            .iter()
            .enumerate()
            .map(|(i, &((k, t), l))| {
                let (f, w) = field(k);
                let (l2, e) = match &weights {
                    Some((l2, err)) => (l2[i], (l - l2[i]).abs() + err[i]),
                    None => (l, l),
                };
                Multiplier {
                    field: f,
                    angle: t,
                    weight: w * l2,
                    weight_error: w * e,
                    limit: false,
                }
            })
            .collect()
    }

    /// A Lagrangian lower bound of min_u max_{f,θ} w_f|g_f(θ; u)| over the goal's fields
    /// (`list`) that depend on counterweight 0's u only, from samples of the group's
    /// members: for weights λ_k ≥ 0, Σλ_k = 1 at any samples (f_k, θ_k),
    /// max w²|g|² ≥ Σ_k λ_k w_k²|b_k + A_k u|² =: q(u) ≥ min q, so √(min q) is a lower
    /// bound (scaled back by the first member's w₀).
    /// min q is computed as q(u*) − ¼∇qᵀQ⁻¹∇q at the computed minimiser u* = −Q⁻¹r
    /// (q = uᵀQu + 2rᵀu + c: exact for a quadratic, whatever the error of u*), less the
    /// round-off of q(u*) (16(n + 3)ε of its absolute terms). 0 when Q is singular.
    pub(super) fn disc_bound(
        &self,
        list: &[(usize, f64)],
        group: &DiscGroup,
        terms: &[(Tag, f64)],
    ) -> Result<f64, MinimaxError> {
        let ux = var_u(0);
        let (mut q, mut r) = ([[0.0; 2]; 2], [0.0; 2]);
        let mut vals = Vec::with_capacity(terms.len());
        let w0 = list[group.members[0]].1;
        for &((k, t), l) in terms {
            let (f, w) = list[group.members[k]];
            let mut v = self.eval(f, t)?;
            // Each member's weight relative to the first (1 where they are equal).
            let s = w / w0;
            v.b = v.b.map(|b| s * b);
            let a = [
                [s * v.row(0)[ux], s * v.row(0)[ux + 1]],
                [s * v.row(1)[ux], s * v.row(1)[ux + 1]],
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
        Ok(w0 * l2.max(0.0).sqrt())
    }
}

/// The samples of every member in one list, members in order: (tags, points).
fn union(pts: &[DiscSamples]) -> (Vec<Tag>, Vec<P2>) {
    let len = pts.iter().map(DiscSamples::len).sum();
    let (mut tags, mut points) = (Vec::with_capacity(len), Vec::with_capacity(len));
    for (k, s) in pts.iter().enumerate() {
        tags.extend(s.angles.iter().map(|&t| (k, t)));
        points.extend_from_slice(&s.points);
    }
    (tags, points)
}

/// Weights λ ≥ 0, Σλ = 1, on the support of a smallest enclosing disc of the points
/// (sample, p): the points within 1e-9 of the radius from the centre, weighted by
/// [`barycentric`]. Any weights give a valid bound ([`Engine::disc_bound`]); these make it
/// the disc's radius.
pub(super) fn support_weights(tags: &[Tag], points: &[P2], disc: &Disc) -> Vec<(Tag, f64)> {
    let on: Vec<(Tag, P2)> = tags
        .iter()
        .zip(points)
        .filter(|(_, p)| (**p - disc.centre).norm() >= disc.radius * (1.0 - 1e-9))
        .map(|(&t, &p)| (t, p))
        .collect();
    barycentric(disc.centre, &on)
}

/// The point c's barycentric coordinates in the first triangle of the points `on` that
/// contains it, else in their farthest pair (c projected onto it), else the first point.
fn barycentric(c: P2, on: &[(Tag, P2)]) -> Vec<(Tag, f64)> {
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

/// Newton on the support angles θ_i of a smallest enclosing disc of curves p_k(θ) (2 or 3
/// points, each on its member's curve): each must be a stationary point of |p(θ) − v| with
/// v the centre of the disc through the points (their midpoint, or circumcentre),
/// F_i = (p(θ_i) − v)·p'(θ_i) = 0. Each point is evaluated at θ_i and θ_i ± η (η = 1e-5),
/// which give p' and p'' by central differences, and the Jacobian is formed from them
/// (`support_jacobian`): ∂F_i/∂θ_j = δ_ij(|p'_i|² + (p_i − v)·p''_i) − (∂v/∂θ_j)·p'_i.
/// Where a maximum moves with the design (a disc on two points, free to slide across
/// their diameter), the exchange alone creeps towards it; this locates it in a few steps.
/// The Jacobian only steers the steps: the angles are those where F vanishes, whatever its
/// accuracy. `None` if a step leaves the scan spacing `h` or the iteration does not settle.
pub(super) fn polish_support(
    point: &dyn Fn(usize, f64) -> Option<P2>,
    weights: &[(Tag, f64)],
    h: f64,
) -> Option<(Vec<Tag>, P2)> {
    let eta = 1e-5;
    let merged = merge_support(weights, h);
    let k = merged.len();
    if !(k == 2 || k == 3) {
        return None;
    }
    let curve: Vec<usize> = merged.iter().map(|w| w.0 .0).collect();
    // One support point: p, p' and p'' by central differences.
    let at = |c: usize, t: f64| -> Option<Jet> {
        let (lo, mid, hi) = (point(c, t - eta)?, point(c, t)?, point(c, t + eta)?);
        Some(Jet {
            p: mid,
            d: (hi - lo) / (2.0 * eta),
            dd: (hi - 2.0 * mid + lo) / (eta * eta),
        })
    };
    let points_at = |th: &[f64]| -> Option<Vec<Jet>> {
        th.iter().zip(&curve).map(|(&t, &c)| at(c, t)).collect()
    };
    let mut th: Vec<f64> = merged.iter().map(|w| w.0 .1).collect();
    let start = th.clone();
    let mut last_step = f64::INFINITY;
    let mut pd = points_at(&th)?;
    for _ in 0..10 {
        let (f, jac) = support_jacobian(&pd)?;
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
        // shrink is the differences' noise. The last points need no derivatives.
        if big <= 1e-9 || big >= last_step {
            let ps: Option<Vec<P2>> = th.iter().zip(&curve).map(|(&t, &c)| point(c, t)).collect();
            return polished(&th, &curve, &ps?);
        }
        pd = points_at(&th)?;
        last_step = big;
    }
    let ps: Vec<P2> = pd.iter().map(|q| q.p).collect();
    polished(&th, &curve, &ps)
}

/// [`polish_support`]'s result: the support (each curve with its angle in [0, 2π)) and
/// the centre of its points `ps` (at the angles `th`).
fn polished(th: &[f64], curve: &[usize], ps: &[P2]) -> Option<(Vec<Tag>, P2)> {
    let v = support_centre(ps)?;
    let tags = th.iter().zip(curve);
    Some((
        tags.map(|(t, &c)| (c, t.rem_euclid(std::f64::consts::TAU)))
            .collect(),
        v,
    ))
}

/// A support point of [`polish_support`]: p(θ) with its first and second derivatives.
#[derive(Clone, Copy)]
struct Jet {
    p: P2,
    d: P2,
    dd: P2,
}

/// Support points around one maximum of a curve (neighbouring samples, within 2h) are
/// one, at the angle of the heavier and with their summed weight.
fn merge_support(weights: &[(Tag, f64)], h: f64) -> Vec<(Tag, f64)> {
    let mut merged: Vec<(Tag, f64)> = Vec::new();
    for &((c, t), l) in weights {
        match merged
            .iter_mut()
            .find(|m| m.0 .0 == c && angle_dist(m.0 .1, t) <= 2.0 * h)
        {
            Some(m) if l > m.1 => *m = ((c, t), m.1 + l),
            Some(m) => m.1 += l,
            None => merged.push(((c, t), l)),
        }
    }
    merged
}

/// The centre of the disc through 2 points (their midpoint) or 3 (their circumcentre).
fn support_centre(ps: &[P2]) -> Option<P2> {
    if ps.len() == 2 {
        Some(0.5 * (ps[0] + ps[1]))
    } else {
        crate::geom::circumcentre(ps[0], ps[1], ps[2]).map(|c| c.0)
    }
}

/// [`polish_support`]'s residuals F_i = (p_i − v)·p'_i and their Jacobian in the angles,
/// from the points' derivatives: ∂F_i/∂θ_j = δ_ij(|p'_i|² + (p_i − v)·p''_i) − v_j·p'_i,
/// v_j = ∂v/∂θ_j the centre's motion, ½p'_j for a midpoint; for a circumcentre, from
/// differentiating 2(p_i − p_1)·v = |p_i|² − |p_1|² (i = 2, 3):
/// (p_i − p_1)·v_j = δ_ij F_i − δ_1j F_1. `None` for collinear points.
fn support_jacobian(pd: &[Jet]) -> Option<(Vec<f64>, nalgebra::DMatrix<f64>)> {
    let k = pd.len();
    let ps: Vec<P2> = pd.iter().map(|q| q.p).collect();
    let v = support_centre(&ps)?;
    let f: Vec<f64> = pd.iter().map(|q| (q.p - v).dot(&q.d)).collect();
    let moves: Vec<P2> = if k == 2 {
        pd.iter().map(|q| 0.5 * q.d).collect()
    } else {
        let (r1, r2) = (ps[1] - ps[0], ps[2] - ps[0]);
        let det = crate::geom::cross(r1, r2);
        if det == 0.0 {
            return None;
        }
        // Solve [r1; r2]·v_j = (b1, b2) by Cramer's rule.
        let solve = |b1: f64, b2: f64| {
            P2::new((b1 * r2.y - b2 * r1.y) / det, (r1.x * b2 - r2.x * b1) / det)
        };
        vec![solve(-f[0], -f[0]), solve(f[1], 0.0), solve(0.0, f[2])]
    };
    let mut jac = nalgebra::DMatrix::<f64>::zeros(k, k);
    for i in 0..k {
        for j in 0..k {
            jac[(i, j)] = -moves[j].dot(&pd[i].d);
        }
        jac[(i, i)] += pd[i].d.dot(&pd[i].d) + (pd[i].p - v).dot(&pd[i].dd);
    }
    Some((f, jac))
}
