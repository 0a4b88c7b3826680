//! The flywheel of several load cases (issue 33, item 3), written once for every family
//! with named load cases: each case's Cs_k(I_f) does not increase with I_f (the premise of
//! the least-flywheel search itself, [`super::least_flywheel`]), so the flywheels that meet
//! `cs` in case k are [I_k, ∞) and those that meet it in every case [max_k I_k, ∞): the
//! flywheel of all the cases is the largest least flywheel, exactly, with the largest of
//! their errors. Over a speed band it is found at the band's ends, and [`BandCheck::prove`]
//! proves that it meets `cs` at every speed between them (or says where it does not).

use super::{Drive, DriveFigures};

/// The flywheel of all the cases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CasesFlywheel {
    /// I* (kg·m²).
    pub inertia: f64,
    /// Bound on its error (kg·m²): max_k δI_k, 0 for a given flywheel.
    pub error: f64,
    /// The case whose least flywheel it is; `None`: the file's `flywheel`.
    pub governing: Option<usize>,
}

/// One case's own drive, as the flywheel of all the cases reads it: its name and its drive
/// (`None`: not computed; `Err`: why it failed).
pub type CaseDrive<'a> = (&'a str, Option<&'a Result<DriveFigures, String>>);

/// I*: the file's `flywheel`, else with `cs` the largest of the cases' least flywheels (the
/// module's doc), else none. A case whose drive failed leaves it unknown (a warning).
pub fn cases_flywheel(
    d: &Drive,
    cases: &[CaseDrive],
    warnings: &mut Vec<String>,
) -> Option<CasesFlywheel> {
    if let Some(f) = d.flywheel {
        return Some(CasesFlywheel {
            inertia: f,
            error: 0.0,
            governing: None,
        });
    }
    d.cs?;
    let mut least = Vec::with_capacity(cases.len());
    for (name, drive) in cases {
        match drive {
            Some(Ok(DriveFigures {
                flywheel: Some(f), ..
            })) => least.push((f.inertia, f.inertia_error)),
            Some(Err(why)) => {
                warnings.push(format!(
                    "no flywheel for all the load cases: the drive of load case {name} failed: {why}"
                ));
                return None;
            }
            _ => return None,
        }
    }
    let k = argmax(least.iter().map(|l| l.0))?;
    Some(CasesFlywheel {
        inertia: least[k].0,
        error: least.iter().map(|l| l.1).fold(0.0, f64::max),
        governing: Some(k),
    })
}

/// The drive `d` with the flywheel `inertia` given instead of a Cs to meet: each case's
/// steady state at the flywheel of all the cases.
pub fn with_flywheel(d: &Drive, inertia: f64) -> Drive {
    Drive {
        cs: None,
        flywheel: Some(inertia),
        motor: d.motor.clone(),
    }
}

/// Whether the steady state `st` swings more than `cs` beyond its error.
fn swings_beyond(st: &super::SteadyState, cs: f64) -> bool {
    st.cs > cs + st.cs_error
}

/// A warning for every case (name, its drive at the flywheel of all the cases) whose steady
/// state swings more than `cs` beyond its error.
pub fn check_cs(cs: Option<f64>, cases: &[CaseDrive], warnings: &mut Vec<String>) {
    let Some(cs) = cs else { return };
    for (name, drive) in cases {
        if let Some(Ok(f)) = drive {
            let st = &f.steady;
            if swings_beyond(st, cs) {
                warnings.push(format!(
                    "load case {name}: Cs = {:.6} ± {:.1e} with the flywheel {:.6} kg·m² is above mechanism.drive.cs = {cs}",
                    st.cs, st.cs_error, st.flywheel
                ));
            }
        }
    }
}

/// The index of the largest value (the first of equal ones); `None` for no values or NaN.
pub fn argmax(v: impl Iterator<Item = f64>) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, x) in v.enumerate() {
        if x.is_nan() {
            return None;
        }
        if best.is_none_or(|b| x > b.1) {
            best = Some((i, x));
        }
    }
    best.map(|b| b.0)
}

/// Interior speeds of a speed band at which every case's steady state is solved first
/// (beside the band's ends); [`BandCheck::prove`] then halves the intervals it cannot close.
pub const BAND_CHECK_SPEEDS: usize = 7;

/// Steady states per case [`BandCheck::prove`] may solve at most, the first
/// [`BAND_CHECK_SPEEDS`] + 2 included.
pub const BAND_MAX_SPEEDS: usize = 73;

/// The [`BAND_CHECK_SPEEDS`] + 2 evenly spaced speeds of the band `(lo, hi)` (rad/s), its
/// ends included.
pub fn band_speeds(band: (f64, f64)) -> impl Iterator<Item = f64> {
    let n = BAND_CHECK_SPEEDS + 1;
    (0..=n).map(move |j| match j {
        0 => band.0,
        j if j == n => band.1,
        j => band.0 + (band.1 - band.0) * j as f64 / n as f64,
    })
}

/// A case's name at an end of a speed band: `"<case> at <n> rpm"`, n from ω (rad/s) to
/// 10⁻⁹ rpm (so that 110 rpm, through rad/s and back, reads 110).
pub fn at_rpm(case: &str, omega: f64) -> String {
    let rpm = (omega * 60.0 / std::f64::consts::TAU * 1e9).round() / 1e9;
    format!("{case} at {rpm} rpm")
}

/// The steady states over a speed band, at the flywheel of all the cases, proven to swing
/// no more than `cs` at every speed of the band — not only at the speeds solved.
///
/// Why a proof is possible: with a constant-torque drive (the band is the speed the machine
/// is driven at) and J, G that do not depend on the speed, every steady state of one case is
/// y(φ) = ½ (J(φ) + I_f) ω(φ)² = y₀ + W(φ), W = ∫₀^φ (Ḡ − G) dφ the same at every speed: the
/// speed's level is y₀ alone, and the time-mean speed rises with it. The normalised speed
/// g(φ) = ω(φ)/ω(0) has g² = (1 + s W(φ)) (J(0) + I_f)/(J(φ) + I_f), s = 1/y₀: affine in s at
/// every φ, so between two solved speeds ω̄_a < ω̄_b every g(φ) lies between its values at
/// the two ends; and the period of g, ∫ dφ/g ∝ ∫ √(J + I_f) (1 + s W)^(−½) dφ, is convex in
/// s, so no larger than at an end. Cs = (g_max − g_min)/ḡ (scale-free) is therefore bounded
/// on [ω̄_a, ω̄_b] by
///
///   Cs ≤ (max(g_max,a, g_max,b) − min(g_min,a, g_min,b)) / min(ḡ_a, ḡ_b)
///
/// ([`interval_bound`], with every speed moved by its error bound against the claim). The
/// bound tends to Cs as the interval shrinks, so the intervals whose bound is above `cs` are
/// halved until it is below (proven), or a solved speed swings more than `cs` beyond its
/// error (the band's inside needs more flywheel than its ends: a warning), or
/// [`BAND_MAX_SPEEDS`] are solved (open).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BandCheck {
    /// Steady states solved per case, at most (the band's ends included).
    pub speeds: usize,
    /// The largest Cs among them.
    pub max_cs: f64,
    /// Its error bound.
    pub max_cs_error: f64,
    /// Where: ω (rad/s).
    pub max_cs_speed_rad_s: f64,
    /// Where: the case's name.
    pub max_cs_case: String,
    /// Solved steady states whose Cs is above `cs` beyond its error (0: the band's ends
    /// govern).
    pub beyond: usize,
    /// An upper bound on Cs at every speed of the band in every case: the largest
    /// [`interval_bound`] over the final intervals.
    pub cs_bound: f64,
    /// Its error bound (from the solved speeds' errors).
    pub cs_bound_error: f64,
    /// Every interval's bound is at most `cs` within its error — the standard every solved
    /// Cs is held to (the band's governing end meets `cs` only within its own error): the
    /// flywheel of all the cases meets `cs` over the whole band, so it is the band's least
    /// flywheel, exactly (its ends need it).
    pub proven: bool,
    /// Intervals left with a bound above `cs` and no solved speed beyond it, when the
    /// speeds ran out.
    pub open_intervals: usize,
}

/// One solved speed of the band: (ω̄ in rad/s, its steady state).
type BandPoint = (f64, super::SteadyState);

/// g_max, g_min and ḡ of the steady state `st`, normalised by ω(0) (its first node), each
/// moved by `k` times the speeds' error bound against the bound's claim (k = 0: as solved);
/// `None` where ω(0) is within its error of 0.
fn normalised(st: &super::SteadyState, k: f64) -> Option<[f64; 3]> {
    let w0 = st.curve.first()?[1];
    let e = st.omega_error + 4.0 * f64::EPSILON * st.omega_max;
    (w0 > e).then(|| {
        let e = k * e;
        [
            (st.omega_max + e) / (w0 - e),
            (st.omega_min - e) / (w0 + e),
            (st.omega_mean - e) / (w0 + e),
        ]
    })
}

/// The bound on Cs at every speed between two solved speeds ([`BandCheck`]'s doc) and its
/// error bound (the bound with every speed moved by its error against it, less the bound);
/// +∞ where a speed's ω(0) is not known to be positive.
pub fn interval_bound(a: &super::SteadyState, b: &super::SteadyState) -> (f64, f64) {
    let at = |k: f64| match (normalised(a, k), normalised(b, k)) {
        (Some(a), Some(b)) if a[2].min(b[2]) > 0.0 => {
            (a[0].max(b[0]) - a[1].min(b[1])) / a[2].min(b[2])
        }
        _ => f64::INFINITY,
    };
    let (bound, moved) = (at(0.0), at(1.0));
    (bound, (moved - bound) + 4.0 * f64::EPSILON * bound)
}

/// The state of one interval between two solved speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Interval {
    /// Its bound is at most `cs` within the bound's error.
    Proven,
    /// An end swings more than `cs` beyond its error.
    Beyond,
    /// Neither: to be halved.
    Open,
}

/// The interval between `a` and `b`, its bound and the bound's error.
fn interval(cs: f64, a: &BandPoint, b: &BandPoint) -> (Interval, f64, f64) {
    let (bound, error) = interval_bound(&a.1, &b.1);
    let state = match () {
        _ if bound <= cs + error => Interval::Proven,
        _ if swings_beyond(&a.1, cs) || swings_beyond(&b.1, cs) => Interval::Beyond,
        _ => Interval::Open,
    };
    (state, bound, error)
}

impl BandCheck {
    /// The check of `cases` (their names) over the band `band` (rad/s) against `cs`:
    /// `solve(ω̄, case)` is the case's steady state at the mean speed ω̄ with the flywheel of
    /// all the cases. Every case is solved at [`band_speeds`], then at the midpoints of its
    /// open intervals, all of a round in parallel and read in order (the same result
    /// whatever the threads). `None` (a warning) where a steady state failed.
    pub fn prove(
        cs: f64,
        band: (f64, f64),
        cases: &[&str],
        solve: impl Fn(f64, usize) -> Result<super::SteadyState, String> + Sync,
        warnings: &mut Vec<String>,
    ) -> Option<BandCheck> {
        use rayon::prelude::*;
        let mut points: Vec<Vec<BandPoint>> = vec![Vec::new(); cases.len()];
        let mut jobs: Vec<(f64, usize)> = band_speeds(band)
            .flat_map(|w| (0..cases.len()).map(move |c| (w, c)))
            .collect();
        while !jobs.is_empty() {
            let solved: Vec<_> = jobs.par_iter().map(|&(w, c)| solve(w, c)).collect();
            for (&(w, c), st) in jobs.iter().zip(solved) {
                match st {
                    Ok(st) => points[c].push((w, st)),
                    Err(why) => {
                        warnings.push(format!(
                            "the speed band's check: load case {} at {w} rad/s failed: {why}",
                            cases[c]
                        ));
                        return None;
                    }
                }
            }
            jobs = Vec::new();
            for (c, p) in points.iter_mut().enumerate() {
                p.sort_by(|a, b| a.0.total_cmp(&b.0));
                if p.len() >= BAND_MAX_SPEEDS {
                    continue;
                }
                let open = p
                    .windows(2)
                    .filter(|w| interval(cs, &w[0], &w[1]).0 == Interval::Open);
                let mids = open.map(|w| 0.5 * (w[0].0 + w[1].0)).filter(|&m| {
                    // Halve no further than the speeds' resolution.
                    p.iter().all(|q| q.0 != m)
                });
                let room = BAND_MAX_SPEEDS - p.len();
                jobs.extend(mids.take(room).map(|m| (m, c)));
            }
        }
        Self::of(cs, cases, &points, warnings)
    }

    /// The figures of the solved speeds `points` (per case, sorted by speed).
    fn of(
        cs: f64,
        cases: &[&str],
        points: &[Vec<BandPoint>],
        warnings: &mut Vec<String>,
    ) -> Option<BandCheck> {
        let all = points
            .iter()
            .enumerate()
            .flat_map(|(c, p)| p.iter().map(move |q| (c, q)));
        let (c, top) = all.clone().reduce(|a, b| match b.1 .1.cs > a.1 .1.cs {
            true => b,
            false => a,
        })?;
        let beyond = all.filter(|(_, q)| swings_beyond(&q.1, cs)).count();
        let intervals: Vec<(Interval, f64, f64)> = points
            .iter()
            .flat_map(|p| p.windows(2).map(|w| interval(cs, &w[0], &w[1])))
            .collect();
        // The largest bound, and the error of that one.
        let (cs_bound, cs_bound_error) =
            intervals
                .iter()
                .map(|i| (i.1, i.2))
                .fold((top.1.cs, top.1.cs_error), |a, b| match b.0 > a.0 {
                    true => b,
                    false => a,
                });
        let open_intervals = intervals.iter().filter(|i| i.0 == Interval::Open).count();
        let out = BandCheck {
            speeds: points.iter().map(Vec::len).max().unwrap_or(0),
            max_cs: top.1.cs,
            max_cs_error: top.1.cs_error,
            max_cs_speed_rad_s: top.0,
            max_cs_case: cases[c].to_string(),
            beyond,
            cs_bound,
            cs_bound_error,
            proven: intervals.iter().all(|i| i.0 == Interval::Proven),
            open_intervals,
        };
        out.warn(cs, warnings);
        Some(out)
    }

    fn warn(&self, cs: f64, warnings: &mut Vec<String>) {
        if self.beyond > 0 {
            warnings.push(format!(
                "the speed band's check: {} steady states inside the band swing more than mechanism.drive.cs = {cs} with the flywheel of all the cases (up to Cs = {:.6} in case {} at {:.6} rad/s): the band's interior needs more flywheel than its ends",
                self.beyond, self.max_cs, self.max_cs_case, self.max_cs_speed_rad_s
            ));
        } else if !self.proven {
            warnings.push(format!(
                "the speed band's check: Cs is proven only up to {:.6} ± {:.1e} over the band (mechanism.drive.cs = {cs}; {} intervals left open after {} speeds per case); the largest solved Cs is {:.6}",
                self.cs_bound, self.cs_bound_error, self.open_intervals, self.speeds, self.max_cs
            ));
        }
    }
}
