//! The crane's stability against tipping (issue 38: a 53 t boom counterweight was designed
//! without one): the moments of every weight of the crane about its two tipping lines, empty
//! and loaded, over the luffing range, against a stated stability factor.
//!
//! The crane stands on a support (the portal's rails or wheels) whose edges are the tipping
//! lines. The boom's plane is taken perpendicular to them (the worst slewing position for
//! lines parallel to the boom's plane's normal): the forward line at the distance b in front
//! of the slewing axis (on the boom's side), the backward line at b behind it. In the frame
//! of A (reach along −x) the slewing axis is at x = r, so the lines are x_f = r − b and
//! x_r = r + b. A weight m g at x has about the line x_t, tipping outwards (direction s = −1
//! forward, +1 backward), the arm a = s (x − x_t): it overturns the crane when a > 0 and
//! stabilises it when a < 0, so
//!
//! O(φ) = g Σ m_i max(a_i, 0),  S(φ) = g Σ m_i max(−a_i, 0),  K(φ) = S/O,
//!
//! the classic stability factor (stabilising over overturning moment), over the weights: the
//! slewing part (mass M_s at x_s behind the slewing axis, with the A-frame, machinery and tie
//! pin), the non-slewing base (on the axis), boom, jib and tie at their centroids
//! ([`super::statics::centroids`]), the load at the jib head and the boom counterweight (mass
//! m, first moment u: at x = U_x/m, U_x = −u_s cos φ − u_n sin φ; on a lever, at the lever's
//! pivot plus its first moment's x over m). The worst pose is the
//! smallest K over [φ_min, φ_max]: the largest 1/K = O/S, refined by Brent.
//!
//! Static: wind, the inertia forces of slewing, hoisting and luffing, and the elastic
//! deflections are not modelled; the required factor is where a code's allowances for them go.

use super::balance::{Balance, BalanceError, BalanceScene, Cases};
use super::model::Linkage;
use super::statics::{centroids, tie_pin};
use crate::numeric::interval_peak;
use crate::units::STANDARD_GRAVITY as G;

/// The assumption, stated in the result.
pub const ASSUMPTION: &str = "static: every body a point mass at its centroid (the load at the jib head), the boom's plane perpendicular to the tipping lines; wind, the inertia forces of slewing, hoisting and luffing and elastic deflections are not modelled (the required factor carries them)";

/// What the problem file states of the crane's stability (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StabilitySpec {
    /// M_s, the slewing part's mass without the boom system, load and boom counterweight (kg).
    #[serde(rename = "slewing_mass_kg")]
    pub slewing_mass: f64,
    /// x_s, its centroid's distance behind the slewing axis (m; negative: in front).
    #[serde(rename = "slewing_centroid_m")]
    pub slewing_centroid: f64,
    /// The non-slewing base's mass (portal), its centroid on the slewing axis (kg).
    #[serde(rename = "base_mass_kg")]
    pub base_mass: f64,
    /// b, the distance of each tipping line from the slewing axis (m).
    #[serde(rename = "tipping_distance_m")]
    pub tipping_distance: f64,
    /// K_min, the required stability factor S/O.
    pub min_factor: f64,
}

/// The smallest stability factor of one load case about one tipping line.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LineCase {
    /// `empty` or `loaded`.
    pub case: String,
    /// `forward` (on the boom's side) or `backward`.
    pub line: String,
    /// The smallest K = S/O over the range; `None`: nothing overturns about this line.
    pub factor: Option<f64>,
    /// Bound on its error.
    pub factor_error: f64,
    /// The boom angle of the smallest K (rad).
    pub phi_rad: f64,
    /// The jib head's reach from the slewing axis there (m).
    pub reach_m: f64,
    /// S there (N·m).
    pub stabilising_moment_nm: f64,
    /// O there (N·m).
    pub overturning_moment_nm: f64,
    /// Whether K ≥ K_min.
    pub pass: bool,
}

/// The crane's stability.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Stability {
    /// [`ASSUMPTION`].
    pub assumption: String,
    /// How it was computed.
    pub method: String,
    /// The stated data.
    pub spec: StabilitySpec,
    /// Whether the designed boom counterweight is on the boom.
    pub with_counterweight: bool,
    /// Per load case and tipping line.
    pub cases: Vec<LineCase>,
    /// The smallest factor of all rows (`None`: nothing overturns).
    pub min_factor: Option<f64>,
    /// Whether every row meets K_min.
    pub pass: bool,
    /// The finding in plain words.
    pub verdict: String,
}

/// The weights (mass kg, x m in the frame of A; the slewing axis at x = r) at φ with load q and the counterweight (m, u):
/// slewing part, base, boom, jib, tie, load, counterweight.
pub(super) fn weights(
    c: &Cases,
    spec: &StabilitySpec,
    r: f64,
    phi: f64,
    q: f64,
    m: f64,
    u: [f64; 2],
) -> Result<[(f64, f64); 7], BalanceError> {
    let pose = c.link.pose(phi).ok_or(BalanceError::NoPose { phi })?;
    let b = tie_pin(c.link).ok_or(BalanceError::StraightGuide)?;
    let [g_b, g_j, g_t] = centroids(&pose, b, &c.w);
    let u_x = c.cw_moment(phi, u).ok_or(BalanceError::NoPose { phi })?.x;
    let x_cw = if m > 0.0 {
        c.cw_pivot().x + u_x / m
    } else {
        0.0
    };
    Ok([
        (spec.slewing_mass, r + spec.slewing_centroid),
        (spec.base_mass, r),
        (c.w.boom_mass, g_b.x),
        (c.w.jib_mass, g_j.x),
        (c.w.tie_mass, g_t.x),
        (q, pose.c.x),
        (m, x_cw),
    ])
}

/// (S, O) of the weights about the line x_t tipping towards `s` (−1 forward, +1 backward), N·m.
pub fn moments(weights: &[(f64, f64)], x_t: f64, s: f64) -> (f64, f64) {
    weights.iter().fold((0.0, 0.0), |(st, ov), &(m, x)| {
        let a = s * (x - x_t);
        (st + m * G * (-a).max(0.0), ov + m * G * a.max(0.0))
    })
}

/// The stability of `c` (its load cases) with the counterweight (m, u) against `spec`, the
/// slewing axis at x = r (`mechanism.foot_offset`).
pub(super) fn check(
    c: &Cases,
    spec: &StabilitySpec,
    r: f64,
    m: f64,
    u: [f64; 2],
) -> Result<Stability, BalanceError> {
    let b = spec.tipping_distance;
    let [p0, p1] = c.link.phi_range;
    let mut cases = Vec::new();
    for &(name, q) in &c.cases {
        for (line, x_t, s) in [("forward", r - b, -1.0), ("backward", r + b, 1.0)] {
            let at = |phi: f64| -> Result<(f64, f64), BalanceError> {
                Ok(moments(&weights(c, spec, r, phi, q, m, u)?, x_t, s))
            };
            at(p0)?;
            let inverse = |phi: f64| at(phi).map_or(f64::NAN, |(st, ov)| ov / st);
            let p = interval_peak(inverse, p0, p1, 64, 1e-9)
                .map_err(|_| BalanceError::NoPose { phi: p0 })?;
            let (st, ov) = at(p.peak.x)?;
            // The positions' rounding (as the head height's, 64ε·scale/k2) moves O/S by at
            // most Σ m g δx (1 + O/S)/S.
            let dx = 64.0 * f64::EPSILON * (c.link.length_scale() + r + b) / c.link.k2;
            let total: f64 = weights(c, spec, r, p.peak.x, q, m, u)?
                .iter()
                .map(|w| w.0)
                .sum();
            let q_err = p.error + total * G * dx * (1.0 + p.peak.fx) / st;
            let pose = c
                .link
                .pose(p.peak.x)
                .ok_or(BalanceError::NoPose { phi: p.peak.x })?;
            let factor = (p.peak.fx > 0.0).then(|| 1.0 / p.peak.fx);
            cases.push(LineCase {
                case: name.into(),
                line: line.into(),
                factor,
                factor_error: factor.map_or(0.0, |k| k * k * q_err + 4.0 * f64::EPSILON * k),
                phi_rad: p.peak.x,
                reach_m: r - pose.c.x,
                stabilising_moment_nm: st,
                overturning_moment_nm: ov,
                pass: factor.is_none_or(|k| k >= spec.min_factor),
            });
        }
    }
    let min_factor = cases.iter().filter_map(|l| l.factor).min_by(f64::total_cmp);
    let pass = cases.iter().all(|l| l.pass);
    Ok(Stability {
        assumption: ASSUMPTION.into(),
        method: "K = S/O, the moments of the point weights about each tipping line summed in closed form; the smallest K over the luffing range as the largest O/S, 64 samples refined by Brent to 1e-9 rad".into(),
        spec: *spec,
        with_counterweight: m > 0.0,
        verdict: verdict(&cases, spec, m > 0.0),
        cases,
        min_factor,
        pass,
    })
}

/// The finding in plain words: each row's factor against the required one, failures first.
fn verdict(cases: &[LineCase], spec: &StabilitySpec, with_cw: bool) -> String {
    let cw = if with_cw {
        "with the designed boom counterweight"
    } else {
        "without a boom counterweight"
    };
    let row = |l: &LineCase| match l.factor {
        None => format!(
            "{} about the {} line: nothing overturns the crane",
            l.case, l.line
        ),
        Some(k) => format!(
            "{} about the {} line: K = {:.3} at {:.2} m reach",
            l.case, l.line, k, l.reach_m
        ),
    };
    let failed: Vec<String> = cases.iter().filter(|l| !l.pass).map(row).collect();
    let held: Vec<String> = cases.iter().filter(|l| l.pass).map(row).collect();
    let mut s = if failed.is_empty() {
        format!(
            "Stable {cw}: every case meets the required factor {:.3} (tipping lines {:.3} m from the slewing axis)",
            spec.min_factor, spec.tipping_distance
        )
    } else {
        format!(
            "NOT STABLE ENOUGH {cw}: the required factor {:.3} is not met: {}",
            spec.min_factor,
            failed.join("; ")
        )
    };
    if !held.is_empty() {
        s += &format!(". Met: {}", held.join("; "));
    }
    s + "."
}

/// The stability of the linkage `link` under `scene` with the balance's designed counterweight
/// (none without one), the slewing axis at x = `foot_offset` (module doc).
pub fn stability(
    link: &Linkage,
    scene: &BalanceScene,
    spec: &StabilitySpec,
    foot_offset: f64,
    bal: &Balance,
) -> Result<Stability, BalanceError> {
    let (m, u) = bal
        .counterweight
        .as_ref()
        .map_or((0.0, [0.0; 2]), |cw| (cw.mass_kg, cw.static_moment_kgm));
    check(&Cases::new(link, scene), spec, foot_offset, m, u)
}
