//! The exchange (Remez-like) loop's vocabulary, shared by both convex engines — the 2-D
//! counterweight engine ([`crate::synth::counterweight`]) and the general affine minimax
//! ([`crate::synth::minimax`]) — so that the two say and test the same things the same way:
//! how a solve ended ([`Status`]), which angles are new, the uniform first angles, the
//! settings every loop shares, the clarabel tolerance of the next round, the nearest refined
//! maximum, and the smallest-disc form of a turning counterweight's force ([`DiscForm`],
//! [`DiscSamples`]) that both engines solve exactly instead of by clarabel.
//!
//! A loop samples each field g(θ; x) at angles θ_k, solves the sampled problem (a
//! relaxation: its optimum L bounds the true optimum from below), refines the true peak V of
//! the design found over the whole period, and adds the local maxima above L until
//! V − L ≤ `rel_tol`·V (or the engine's own scale).

use crate::geom::{Disc, P2};
use crate::numeric::Extremum;

/// How the solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Converged to the tolerance.
    Optimal,
    /// Stopped with a larger gap than asked (rounds exhausted, stalled, or clarabel only
    /// reached reduced accuracy); the gap is reported.
    Inaccurate,
    /// The constraints cannot be met (e.g. a force limit below the minimax optimum).
    Infeasible,
    /// clarabel failed (numerical error) before any usable iterate.
    Failed,
}

/// The settings every exchange loop shares (`synth::counterweight::Settings`, the minimax
/// engine's `synth::minimax::Settings`), checked in one place: `rel_tol` in (0, 1), at
/// least 3 initial and 16 scan samples, at least one round, `peak_xtol` in (0, 0.01) rad.
/// The error names the setting as in `[accuracy]`.
/// The finest `rel_tol` accepted: a gap V − L below 1e-14 of the peak is below the rounding
/// of the peaks themselves (a few ε times the field's conditioning), so no round can meet it
/// (`rel_tol = 1e-308` ran 30 rounds and 798 interior-point iterations to `inaccurate`).
pub const MIN_REL_TOL: f64 = 1e-14;

pub(crate) fn check_exchange(
    rel_tol: f64,
    initial_samples: usize,
    scan_samples: usize,
    max_rounds: usize,
    peak_xtol: f64,
) -> Result<(), (&'static str, String)> {
    if !(rel_tol >= MIN_REL_TOL && rel_tol < 1.0) {
        return Err((
            "rel_tol",
            format!("must be in [{MIN_REL_TOL:e}, 1) (a finer gap than 1e-14 of the peak is below what its double-precision evaluation resolves: the exchange loop would run out of rounds), got {rel_tol}"),
        ));
    }
    if initial_samples < 3 {
        return Err((
            "initial_samples",
            format!("must be at least 3, got {initial_samples}"),
        ));
    }
    if scan_samples < 16 {
        return Err((
            "scan_samples",
            format!("must be at least 16, got {scan_samples}"),
        ));
    }
    if max_rounds == 0 {
        return Err(("max_rounds", "must be at least 1".into()));
    }
    if !(peak_xtol > 0.0 && peak_xtol < 1e-2) {
        return Err((
            "peak_xtol",
            format!("must be in (0, 0.01) rad, got {peak_xtol}"),
        ));
    }
    Ok(())
}

/// Equally spaced angles θ_k = 2πk/n, k = 0…n−1.
pub fn uniform_angles(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| k as f64 * std::f64::consts::TAU / n as f64)
        .collect()
}

/// Whether `phi` is not yet among the sampled angles (none within 1e-9 rad).
pub(crate) fn is_new(samples: &[f64], phi: f64) -> bool {
    samples.iter().all(|&q| angle_dist(q, phi) > 1e-9)
}

/// Distance between two angles on the circle.
pub fn angle_dist(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// The refined local maximum nearest to θ within `within` rad (the first of equals), else
/// θ itself: where a sampled angle's maximum lies now.
pub(crate) fn nearest_maximum(maxima: &[Extremum], theta: f64, within: f64) -> f64 {
    maxima
        .iter()
        .map(|m| (angle_dist(m.x, theta), m.x))
        .filter(|m| m.0 <= within)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(theta, |m| m.1)
}

/// clarabel's tolerance of the first round: a round far from convergence only needs to
/// locate the next angles, so 1e-6 (or the target, if looser).
pub(crate) fn first_round_tol(rel_tol: f64) -> f64 {
    1e-6_f64.max(rel_tol)
}

/// clarabel's tolerance of the next round after one solved at `round_tol` left the relative
/// gap `rel_gap`: two orders below the gap and below the last round's, between the target
/// `rel_tol` and 1e-6 (a target looser than 1e-6 is its own next tolerance); once at the
/// target it stays there.
pub(crate) fn next_round_tol(round_tol: f64, rel_gap: f64, rel_tol: f64) -> f64 {
    let next_tol = (0.01 * rel_gap).min(1e-6).max(rel_tol);
    if round_tol > rel_tol {
        next_tol.min(round_tol * 0.01).max(rel_tol)
    } else {
        rel_tol
    }
}

/// The note of a loop that stalled: every local maximum above the bound is sampled, so the
/// gap left is the accuracy of `what` (clarabel, or the peak refinement).
pub(crate) fn stalled_note(round: usize, what: &str) -> String {
    format!(
        "exchange stalled after {round} rounds: every local maximum is already sampled; the remaining gap is {what}"
    )
}

/// The note of a loop that ran out of rounds.
pub(crate) fn max_rounds_note(max_rounds: usize) -> String {
    format!("stopped after max_rounds = {max_rounds} exchange rounds")
}

/// An affine map u ↦ A u + b at one angle; a scalar field uses only the first row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// Rows of A (2×2).
    pub a: [[f64; 2]; 2],
    /// b.
    pub b: [f64; 2],
}

impl Affine {
    /// Value at u.
    pub fn at(&self, u: P2) -> P2 {
        P2::new(
            self.a[0][0] * u.x + self.a[0][1] * u.y + self.b[0],
            self.a[1][0] * u.x + self.a[1][1] * u.y + self.b[1],
        )
    }
}

/// A minimax force `max_θ ‖A(θ)u + b(θ)‖` whose every A(θ) is c·Q(θ), Q orthogonal, one
/// constant c > 0 (a counterweight turning with the crank): ‖A u + b‖ = c‖u − p(θ)‖ with
/// p(θ) = −Aᵀb/c², the unbalance that would cancel the force at θ. The minimax over sampled
/// angles is then the smallest disc enclosing the points p(θ_k) ([`DiscSamples`]): its
/// centre is the optimal u and c times its radius the optimal sampled peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DiscForm {
    /// c².
    c2: f64,
}

impl DiscForm {
    /// The form with c taken from one value of the field (the first column of A at a
    /// reference angle); `None` when that column is zero.
    pub(crate) fn scaled_by(aff: &Affine) -> Option<DiscForm> {
        let [[a00, _], [a10, _]] = aff.a;
        let c2 = a00 * a00 + a10 * a10;
        (c2 > 0.0).then_some(DiscForm { c2 })
    }

    /// c.
    pub(crate) fn c(&self) -> f64 {
        self.c2.sqrt()
    }

    /// p of one affine value (`None` when its A is not c·orthogonal to 1e-12).
    pub(crate) fn point_of(&self, aff: &Affine) -> Option<P2> {
        let tol = 1e-12 * self.c2;
        let [[a00, a01], [a10, a11]] = aff.a;
        let (n0, n1) = (a00 * a00 + a10 * a10, a01 * a01 + a11 * a11);
        let dot = a00 * a01 + a10 * a11;
        if (n0 - self.c2).abs() > tol || (n1 - self.c2).abs() > tol || dot.abs() > tol {
            return None;
        }
        let [b0, b1] = aff.b;
        Some(-P2::new(a00 * b0 + a10 * b1, a01 * b0 + a11 * b1) / self.c2)
    }
}

/// The sampled angles θ_k of a disc exchange with their points p(θ_k) ([`DiscForm`]), in
/// the order sampled: each round solves the sampled minimax as their smallest enclosing
/// disc (Welzl, [`crate::geom::enclosing_disc`]) and adds the angles its design lacks.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct DiscSamples {
    /// θ_k (rad).
    pub angles: Vec<f64>,
    /// p(θ_k).
    pub points: Vec<P2>,
}

impl DiscSamples {
    /// From (θ, p) pairs.
    pub(crate) fn of(pairs: &[(f64, P2)]) -> DiscSamples {
        let (angles, points) = pairs.iter().copied().unzip();
        DiscSamples { angles, points }
    }

    /// None yet, with room for `n` without growing.
    pub(crate) fn with_capacity(n: usize) -> DiscSamples {
        DiscSamples {
            angles: Vec::with_capacity(n),
            points: Vec::with_capacity(n),
        }
    }

    /// The number of samples.
    pub(crate) fn len(&self) -> usize {
        self.angles.len()
    }

    /// The smallest disc enclosing the points: the sampled minimax's solution.
    pub(crate) fn disc(&self) -> Option<Disc> {
        crate::geom::enclosing_disc(&self.points)
    }

    /// Whether θ is not yet sampled ([`is_new`]).
    pub(crate) fn is_new(&self, theta: f64) -> bool {
        is_new(&self.angles, theta)
    }

    /// Appends θ with its point.
    pub(crate) fn push(&mut self, theta: f64, p: P2) {
        self.angles.push(theta);
        self.points.push(p);
    }

    /// Appends θ if it is new and has a point (`point(θ)`); true if appended.
    pub(crate) fn add_new(&mut self, theta: f64, point: impl FnOnce(f64) -> Option<P2>) -> bool {
        if !self.is_new(theta) {
            return false;
        }
        match point(theta) {
            Some(p) => {
                self.push(theta, p);
                true
            }
            None => false,
        }
    }
}
