//! The operating envelope's box, shared by the families that have one (issue 33, item 3):
//! its vertices, its quasi-Monte Carlo points and the worst case of a figure over scenarios.
//! Which parameters a box has, and what they change in a machine, is the family's.
//!
//! A figure affine in each parameter separately (masses; ω² with the weights fixed) has a
//! magnitude — and ΔE, a max minus a min of affine functions — convex in each, so its
//! maximum over the box is at a vertex: the vertices are the scenarios a certified worst case
//! needs. The Halton points check it (they never certify it). What each interval end costs
//! comes from the optimum's multipliers ([`sensitivities`]).

use crate::synth::minimax::{AffineField, AffineValue, Multiplier, Solution};
use crate::synth::search::starts::{halton, HALTON_PRIMES};

/// Most interval parameters of an envelope: 2^10 = 1024 vertices (and the Halton bases).
pub const MAX_PARAMETERS: usize = 10;

/// Every vertex of the box `ranges` (2^k, in binary order of the parameters' ends: bit i set
/// = parameter i at its upper end).
pub fn vertices(ranges: &[(f64, f64)]) -> Vec<Vec<f64>> {
    let k = ranges.len();
    (0..(1usize << k))
        .map(|bits| {
            (0..k)
                .map(|i| match bits >> i & 1 {
                    1 => ranges[i].1,
                    _ => ranges[i].0,
                })
                .collect()
        })
        .collect()
}

/// The scenarios [nominal, vertices…] ([`vertices`]' order) that a worst case needs: the
/// others are dominated exactly, at every angle and every design, so leaving them out of a
/// minimax changes neither its optimum nor its certificate (their figures are still
/// evaluated for the report).
///
/// - **The nominal scene**, when every parameter is multi-affine (none from `first_general`
///   on: no lengths) and the nominal values `nominal` lie in the box: a field affine in each
///   parameter separately (masses; ω² — a speed v enters as v², and v ∈ [lo, hi] with
///   0 ≤ lo puts v² in [lo², hi²]) is at any point of the box the multilinear interpolation
///   of its vertex values, g(p) = Σ_v w_v(p) g(v) with w_v ≥ 0, Σ w_v = 1 independent of the
///   angle and the design; so |g(p)| ≤ max_v |g(v)|, and for ΔE, a max minus a min of an
///   affine curve, ΔE(p) ≤ Σ w_v ΔE(v) ≤ max_v ΔE(v).
/// - **A vertex with the speed (parameter 0, `speed`) at its lower end**, when every field
///   the problem names is homogeneous in ω² (`homogeneous`: g = ω² h(φ; x, masses), the
///   inertial figures — shaking force and moment — with no weight or process load in them):
///   there g = (lo/hi)² × the value at the vertex with the speed at its upper end and every
///   other parameter the same.
pub fn needed_scenarios(
    ranges: &[(f64, f64)],
    nominal: &[f64],
    first_general: usize,
    speed: bool,
    homogeneous: bool,
) -> Vec<usize> {
    let inside = ranges
        .iter()
        .zip(nominal)
        .all(|(&(lo, hi), &v)| lo.min(hi) <= v && v <= lo.max(hi));
    let speed_ok = !speed || ranges[0].0 >= 0.0 && ranges[0].0 <= ranges[0].1;
    let nominal_needed = ranges.is_empty() || first_general < ranges.len() || !inside || !speed_ok;
    let low_speed_out = speed && homogeneous && speed_ok;
    let vertices = (0..(1usize << ranges.len())).filter(|v| !(low_speed_out && v & 1 == 0));
    nominal_needed
        .then_some(0)
        .into_iter()
        .chain(vertices.map(|v| v + 1))
        .collect()
}

/// Halton point `i` (≥ 1) of the box `ranges`: coordinate d in base `HALTON_PRIMES[d]`,
/// deterministic whatever the threads.
pub fn halton_point(ranges: &[(f64, f64)], i: usize) -> Vec<f64> {
    ranges
        .iter()
        .enumerate()
        .map(|(d, r)| r.0 + (r.1 - r.0) * halton(i, HALTON_PRIMES[d]))
        .collect()
}

/// The worst case of one figure over the scenarios.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WorstCase {
    /// Its value (the figure's unit).
    pub value: f64,
    /// Its error bound: the binding scenario's evaluation error (the optimisation gap is
    /// added by the caller for the objective).
    pub error: f64,
    /// The binding scenario's index (0: the nominal scene).
    pub vertex: usize,
}

/// The worst (largest) of `(value, error)` over the scenarios, the first of equal ones
/// (load cases that do not change a figure tie exactly), `None` for none.
pub fn worst(rows: impl IntoIterator<Item = (f64, f64)>) -> Option<WorstCase> {
    rows.into_iter()
        .enumerate()
        .reduce(|a, b| match b.1 .0.total_cmp(&a.1 .0) {
            std::cmp::Ordering::Greater => b,
            _ => a,
        })
        .map(|(vertex, (value, error))| WorstCase {
            value,
            error,
            vertex,
        })
}

/// Which end of an interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum End {
    /// The lower end.
    Min,
    /// The upper end.
    Max,
}

/// One row of a sensitivity table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    /// The parameter (the family's name for it).
    pub parameter: String,
    /// Which end moves.
    pub end: End,
    /// The end's value (the parameter's SI unit).
    pub at: f64,
    /// dV*/d(end): the optimised worst case's change per unit of the end (the objective's
    /// unit per the parameter's SI unit).
    pub derivative: f64,
    /// Bound on its error (same unit).
    pub error: f64,
}

/// ∂|g|/∂v of one active maximum with the design and its angle held, and its error: what a
/// family computes for [`sensitivities`] by moving one parameter of one scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slope {
    /// The derivative (the field's unit per the parameter's).
    pub value: f64,
    /// A bound on its error.
    pub error: f64,
}

/// How a figure depends on a parameter, for [`central_slopes`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dependence {
    /// The field g (not its magnitude) affine or quadratic in it (a mass; ω, where the
    /// inertial parts scale with ω²): its central difference is exact but for the
    /// evaluations' errors, whatever the step.
    Quadratic,
    /// Anything else (a length): the magnitude's truncation is estimated from a second step.
    General,
}

/// One field's value at an angle and the design: g (a scalar in component 0) and a bound on
/// its evaluation error.
pub type FieldValue = ([f64; 2], f64);

/// ∂|g|/∂v at `v` of the fields `f(v)` by central differences with step `h`. For a
/// [`Dependence::Quadratic`] field, ∂g/∂v = (g(v + h) − g(v − h))/2h exactly but for the
/// evaluations, and ∂|g|/∂v = ĝ·∂g/∂v with ĝ = g(v)/|g(v)|: the error is the evaluations'
/// (e₊ + e₋)/2h, ĝ's (e₀/|g|)·|∂g/∂v| and the round-off 4ε·max|g|/h. Otherwise |g| at ±h
/// and ±2h: d_h with |d_h − d_2h| (d_2h's truncation is four times d_h's, so this
/// over-covers d_h's) and the evaluations' errors over the steps.
pub fn central_slopes<E>(
    v: f64,
    h: f64,
    dependence: Dependence,
    mut f: impl FnMut(f64) -> Result<Vec<FieldValue>, E>,
) -> Result<Vec<Slope>, E> {
    let norm = |g: &[f64; 2]| g[0].hypot(g[1]);
    let (p1, m1) = (f(v + h)?, f(v - h)?);
    let size = |a: &FieldValue, b: &FieldValue| norm(&a.0).max(norm(&b.0));
    let round_off = |size: f64, h: f64| 4.0 * f64::EPSILON * size / h;
    let slopes = match dependence {
        Dependence::Quadratic => {
            let at = f(v)?;
            (0..p1.len())
                .map(|k| {
                    let dg = [0, 1].map(|r| (p1[k].0[r] - m1[k].0[r]) / (2.0 * h));
                    let (g, e0) = at[k];
                    let n = norm(&g);
                    let (value, dir_error) = match n > 0.0 {
                        true => ((g[0] * dg[0] + g[1] * dg[1]) / n, e0 / n * norm(&dg)),
                        false => (norm(&dg), 0.0),
                    };
                    let eval = (p1[k].1 + m1[k].1) / (2.0 * h);
                    Slope {
                        value,
                        error: eval + dir_error + round_off(size(&p1[k], &m1[k]), h),
                    }
                })
                .collect()
        }
        Dependence::General => {
            let (p2, m2) = (f(v + 2.0 * h)?, f(v - 2.0 * h)?);
            (0..p1.len())
                .map(|k| {
                    let d1 = (norm(&p1[k].0) - norm(&m1[k].0)) / (2.0 * h);
                    let d2 = (norm(&p2[k].0) - norm(&m2[k].0)) / (4.0 * h);
                    let eval = (p1[k].1 + m1[k].1) / (2.0 * h) + (p2[k].1 + m2[k].1) / (4.0 * h);
                    Slope {
                        value: d1,
                        error: (d1 - d2).abs() + eval + round_off(size(&p2[k], &m2[k]), h),
                    }
                })
                .collect()
        }
    };
    Ok(slopes)
}

/// The step of [`central_slopes`] for a parameter at `v` with interval `range`: 1 % of its
/// width for a quadratic dependence (exact at any step; a long step divides the evaluations'
/// errors), 10⁻⁴ of it otherwise; a point interval's magnitude (else 10⁻⁶) stands for the
/// width; at most half of |v| where v ≠ 0 (an absolute mass or speed stays positive).
pub fn step(v: f64, range: (f64, f64), dependence: Dependence) -> f64 {
    let w = range.1 - range.0;
    let width = if w > 0.0 {
        w
    } else if range.0 != 0.0 {
        range.0.abs()
    } else {
        1e-6
    };
    let h = width
        * match dependence {
            Dependence::Quadratic => 1e-2,
            Dependence::General => 1e-4,
        };
    if v != 0.0 {
        h.min(0.5 * v.abs())
    } else {
        h
    }
}

/// The optimum's multipliers for [`sensitivities`], or why there are none: the solve was not
/// certified by Newton's polish of its optimality conditions (its status says how it
/// ended), or its design was moved off the optimum (a plate cut to realise it).
pub fn multipliers_of(sol: &Solution) -> Result<&[Multiplier], String> {
    multipliers_with(&sol.multipliers, sol.status)
}

/// [`multipliers_of`] of an optimum kept as its multipliers and its status.
pub fn multipliers_with(
    multipliers: &[Multiplier],
    status: crate::synth::minimax::Status,
) -> Result<&[Multiplier], String> {
    if multipliers.is_empty() {
        return Err(format!(
            "the optimum has no multipliers: its status is {status:?}, and it was not certified by Newton's polish of the optimality conditions, or its design was moved to a plate that realises it"
        ));
    }
    Ok(multipliers)
}

/// How well a polished maximum's angle is known (rad): the disc path's weights are perturbed
/// by the same amount (`peak_xtol`'s floor), and [`sensitivities`] moves each slope's angle
/// by it.
pub const ANGLE_TOL: f64 = 1e-8;

/// The sensitivity of the optimised worst case V* to every interval end, free once the
/// program is solved: by the envelope theorem, dV*/d(end) = Σ_k w_k ∂|g_k(θ_k; x*)|/∂v over
/// the optimum's active maxima k ([`Multiplier`]) whose scenario has the parameter at that
/// end, the design x* and the angles θ_k held. Field f belongs to scenario f / `stride`:
/// 0 is the nominal scene (at no end), s ≥ 1 vertex (s − 1) mod 2ⁿ of [`vertices`] (bit i
/// set: parameter i at its upper end; the vertices repeat once per load case of a family
/// that has them). `slopes(s, i, maxima)` is ∂|g|/∂v_i of each of scenario
/// s's active maxima (the family's fields, moved once for all of them). The error is
/// Σ_k (|w_k|·slope error + w_k's error·|slope|), each slope's error including twice its
/// change when the maximum's angle moves by [`ANGLE_TOL`] (a polished maximum's angle is
/// known to that: the slope is evaluated there too; twice: the first order either way and
/// the second). It is V*'s derivative where V* is
/// differentiable; where the active set changes at the end (an end whose scenarios are all
/// inactive but tie the worst case) it is one of the one-sided derivatives.
pub fn sensitivities<E>(
    names: &[String],
    ranges: &[(f64, f64)],
    stride: usize,
    multipliers: &[Multiplier],
    mut slopes: impl FnMut(usize, usize, &[&Multiplier]) -> Result<Vec<Slope>, E>,
) -> Result<Vec<Sensitivity>, E> {
    let active: Vec<&Multiplier> = multipliers.iter().filter(|m| m.weight != 0.0).collect();
    let nv = 1usize << ranges.len();
    let mut scenarios: Vec<usize> = active.iter().map(|m| m.field / stride).collect();
    scenarios.sort_unstable();
    scenarios.dedup();
    let mut rows = Vec::new();
    for (i, (name, &(lo, hi))) in names.iter().zip(ranges).enumerate() {
        // (derivative, error) of the lower and the upper end.
        let mut ends = [(0.0, 0.0); 2];
        for &s in scenarios.iter().filter(|&&s| s >= 1) {
            let at: Vec<&Multiplier> = active
                .iter()
                .copied()
                .filter(|m| m.field / stride == s)
                .collect();
            let end = &mut ends[((s - 1) % nv) >> i & 1];
            let mut sls = slopes(s, i, &at)?;
            // A maximum's angle is known to about ANGLE_TOL: the slope there moves with it,
            // to first order (∂²|g|/∂v∂θ need not vanish at a maximum of |g| in θ), by at
            // most |Δ| of one step of ANGLE_TOL, doubled to cover the second order.
            let moved: Vec<Multiplier> = (at.iter())
                .map(|m| Multiplier {
                    angle: m.angle + ANGLE_TOL,
                    ..**m
                })
                .collect();
            let refs: Vec<&Multiplier> = moved.iter().collect();
            for (sl, o) in sls.iter_mut().zip(slopes(s, i, &refs)?) {
                sl.error += 2.0 * (o.value - sl.value).abs();
            }
            for (m, sl) in at.iter().zip(sls) {
                end.0 += m.weight * sl.value;
                end.1 += m.weight.abs() * sl.error + m.weight_error * sl.value.abs();
            }
        }
        for (end, at, (derivative, error)) in [(End::Min, lo, ends[0]), (End::Max, hi, ends[1])] {
            rows.push(Sensitivity {
                parameter: name.clone(),
                end,
                at,
                derivative,
                error,
            });
        }
    }
    Ok(rows)
}

/// [`sensitivities`] with each slope from the family's fields moved in one scenario:
/// `fields_at(s, values, maxima)` is g and its evaluation error ([`field_values`]) at each of
/// scenario s's active maxima with the parameters at `values`, the design held (s tells the
/// family scenario s's load case, if it has them, and its own design variables).
///
/// - A multi-affine parameter (before `first_general`: a mass, or the speed — parameter 0
///   when `speed` — entering as ω²) with an interval of positive width: the exact slope from
///   the scenario's vertex and its partner, the vertex with that parameter at its other end
///   ([`vertex_slopes`]); both are vertices of the box, so a family can evaluate them on the
///   scenes it already built.
/// - A length (from `first_general` on, [`Dependence::General`]), or a point interval
///   ([`Dependence::Quadratic`]): central differences ([`central_slopes`]) with [`step`]'s
///   step.
pub fn scenario_sensitivities<E>(
    names: &[String],
    ranges: &[(f64, f64)],
    stride: usize,
    multipliers: &[Multiplier],
    first_general: usize,
    speed: bool,
    mut fields_at: impl FnMut(usize, &[f64], &[&Multiplier]) -> Result<Vec<FieldValue>, E>,
) -> Result<Vec<Sensitivity>, E> {
    let vs = vertices(ranges);
    // Each scenario's own values at its vertex, evaluated once for all its parameters at
    // the same angles (the moved angles of `sensitivities` are another key: the slope
    // between the vertex and its partner is taken at one angle).
    type Own = (usize, Vec<f64>, Vec<FieldValue>);
    let mut own: Vec<Own> = Vec::new();
    sensitivities(names, ranges, stride, multipliers, |k, i, ms| {
        let v = (k - 1) % vs.len();
        let (lo, hi) = ranges[i];
        let square = speed && i == 0;
        let phi = |x: f64| if square { x * x } else { x };
        if i < first_general && phi(hi) != phi(lo) {
            let partner = &vs[v ^ (1 << i)];
            let angles: Vec<f64> = ms.iter().map(|m| m.angle).collect();
            let at = match own.iter().position(|o| o.0 == k && o.1 == angles) {
                Some(j) => j,
                None => {
                    own.push((k, angles, fields_at(k, &vs[v], ms)?));
                    own.len() - 1
                }
            };
            let other = fields_at(k, partner, ms)?;
            return Ok(vertex_slopes(
                vs[v][i], partner[i], square, &own[at].2, &other,
            ));
        }
        let dependence = match i >= first_general {
            true => Dependence::General,
            false => Dependence::Quadratic,
        };
        let mut values = vs[v].clone();
        let h = step(values[i], ranges[i], dependence);
        central_slopes(values[i], h, dependence, |x| {
            values[i] = x;
            fields_at(k, &values, ms)
        })
    })
}

/// ∂|g|/∂v at a vertex v = `at` of fields affine in φ(v) (φ(v) = v, or v² when `square`: a
/// speed), from their values `own` there and `other` at the partner vertex v' = `to` (the
/// same scenario with this parameter at its other end): ∂g/∂v = (g(v') − g(v))·φ′(v) /
/// (φ(v') − φ(v)), exact but for the evaluations, and ∂|g|/∂v = ĝ·∂g/∂v with ĝ = g(v)/|g(v)|.
/// The error is the evaluations' (e + e′)·φ′/|Δφ|, ĝ's (e/|g|)·|∂g/∂v| and the round-off
/// 4ε·max|g|·φ′/|Δφ| of the difference and the quotient.
pub fn vertex_slopes(
    at: f64,
    to: f64,
    square: bool,
    own: &[FieldValue],
    other: &[FieldValue],
) -> Vec<Slope> {
    let norm = |g: &[f64; 2]| g[0].hypot(g[1]);
    let (dphi, dv) = match square {
        true => (to * to - at * at, 2.0 * at),
        false => (to - at, 1.0),
    };
    let q = dv / dphi;
    own.iter()
        .zip(other)
        .map(|(&(g, e0), &(g1, e1))| {
            let dg = [0, 1].map(|r| (g1[r] - g[r]) * q);
            let n = norm(&g);
            let (value, dir_error) = match n > 0.0 {
                true => ((g[0] * dg[0] + g[1] * dg[1]) / n, e0 / n * norm(&dg)),
                false => (norm(&dg), 0.0),
            };
            let size = n.max(norm(&g1));
            Slope {
                value,
                error: (e0 + e1) * q.abs() + dir_error + 4.0 * f64::EPSILON * size * q.abs(),
            }
        })
        .collect()
}

/// g and its evaluation error at each (field, θ) of `at` at the design x: the values
/// [`scenario_sensitivities`] differences.
pub fn field_values(
    fields: &[&dyn AffineField],
    at: impl IntoIterator<Item = (usize, f64)>,
    x: &[f64],
) -> Vec<FieldValue> {
    let mut out = AffineValue::zeros(x.len());
    at.into_iter()
        .map(|(f, theta)| {
            out.clear();
            fields[f].eval(theta, &mut out);
            (out.at(fields[f].dim(), x), fields[f].error(theta, x))
        })
        .collect()
}
