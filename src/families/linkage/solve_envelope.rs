//! The linkage design over its operating envelope (issue 33, item 3): its figures in the
//! nominal scene and at every vertex (the engine's certified peaks, read per scenario block),
//! the worst cases with the scenario that binds, and the quasi-Monte Carlo check — Halton
//! points of the whole box, each a separate scan and refinement of the design's fields (not
//! the engine), none of which may exceed a worst case beyond both errors.

use super::drive::delta_e;
use super::file::{Goal, LinkageScene};
use super::model::{Linkage, Pose};
use super::synth::{self as ls, Outcome, FORCE, MOMENT, TORQUE};
use crate::numeric::{ordered, periodic_peak_sampled, Refine};
use crate::synth::envelope::{self, halton_point, worst, Sensitivity, WorstCase};
use crate::synth::minimax::{FieldPeak, Multiplier, Settings, Solution, PER_COUNTERWEIGHT};
use rayon::prelude::*;

/// A design's figures in one scenario: (value, error bound) of the peak shaking force (N),
/// moment (N·m) and input torque (N·m), and ΔE (J) with the energy-fluctuation objective.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ScenarioFigures {
    /// The load case's name, with `[[mechanism.load_cases]]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub case: Option<String>,
    /// The parameters' values ([`EnvelopeOutcome::parameters`]' order).
    pub values: Vec<f64>,
    /// max |F| and its error (N).
    pub peak_shaking_force_n: (f64, f64),
    /// max |M_O| and its error (N·m).
    pub peak_shaking_moment_nm: (f64, f64),
    /// max |T| and its error (N·m).
    pub peak_input_torque_nm: (f64, f64),
    /// ΔE and its error (J), by the drive's quadrature.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_j: Option<(f64, f64)>,
}

impl ScenarioFigures {
    /// The four figures as (value, error), ΔE NaN where absent.
    fn all(&self) -> [(f64, f64); 4] {
        [
            self.peak_shaking_force_n,
            self.peak_shaking_moment_nm,
            self.peak_input_torque_nm,
            self.energy_fluctuation_j.unwrap_or((f64::NAN, 0.0)),
        ]
    }
}

/// The Monte Carlo check over the whole box.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MonteCarlo {
    /// Scenes evaluated: the Halton points 1..=N of the box, each in every load case.
    pub samples: usize,
    /// The largest of each figure over them: force, moment, torque, ΔE (NaN without ΔE).
    pub max: [f64; 4],
    /// Samples whose figure exceeds the worst case beyond both errors (any figure).
    pub beyond_worst_case: usize,
}

/// The design over the envelope.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EnvelopeOutcome {
    /// The parameters ([`crate::families::linkage::envelope::LinkageEnvelope::names`]).
    pub parameters: Vec<String>,
    /// The nominal scene first, then the vertices, in every load case (the nominal loads
    /// first).
    pub scenarios: Vec<ScenarioFigures>,
    /// The worst of each figure over the scenarios: force, moment, torque, ΔE (absent
    /// without the energy objective).
    pub worst: [Option<WorstCase>; 4],
    /// The check (absent with `monte_carlo = 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarlo>,
    /// What each interval end costs (`sensitivities = true`), from the optimum's
    /// multipliers ([`sensitivities`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivities: Option<Vec<Sensitivity>>,
    /// Why the sensitivities asked for could not be computed.
    #[serde(skip)]
    pub sensitivity_error: Option<String>,
}

/// The design `x` (none: the bare linkage) over the envelope of `scene`, from the solve's
/// peaks `peaks` (every block's), and the check.
pub fn evaluate(
    scene: &LinkageScene,
    out: &Outcome,
    peaks: &[FieldPeak],
    x: Option<&[f64]>,
    s: &Settings,
) -> Result<EnvelopeOutcome, String> {
    let env = &scene.envelope;
    let energy = scene.objective.minimize == Goal::EnergyFluctuation;
    // ΔE by the drive's quadrature in each scenario's scene (the nominal values give the
    // nominal scene).
    let energy_at = |c: usize, v: &[f64]| {
        let sc = ls::scene_at_case(scene, c, v).map_err(|e| e.to_string())?;
        delta_e(&sc, x)
    };
    let named = !env.cases.is_empty();
    let scenarios = env
        .scenarios(&scene.linkage)
        .into_iter()
        .enumerate()
        .map(|(b, sn)| {
            let pk = |k: usize| {
                let p = &peaks[b * out.block_len + k];
                (p.peak, p.error)
            };
            Ok(ScenarioFigures {
                energy_fluctuation_j: energy.then(|| energy_at(sn.case, &sn.values)).transpose()?,
                case: named.then(|| env.case_name(sn.case).to_string()),
                values: sn.values,
                peak_shaking_force_n: pk(FORCE),
                peak_shaking_moment_nm: pk(MOMENT),
                peak_input_torque_nm: pk(TORQUE),
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let worst = [0, 1, 2, 3].map(|c| {
        (c < 3 || energy).then(|| worst(scenarios.iter().map(|f| f.all()[c])).expect("nominal"))
    });
    let monte_carlo = (env.monte_carlo > 0)
        .then(|| monte_carlo(scene, x, &worst, s))
        .transpose()?;
    let (sensitivities, sensitivity_error) = match (&out.design, env.sensitivities) {
        (Some(d), true) => match sensitivities(scene, d, out.block_len) {
            Ok(rows) => (Some(rows), None),
            Err(e) => (None, Some(e)),
        },
        _ => (None, None),
    };
    Ok(EnvelopeOutcome {
        parameters: env.names(),
        scenarios,
        worst,
        monte_carlo,
        sensitivities,
        sensitivity_error,
    })
}

/// The sensitivity table of the envelope design `sol` (`block_len` fields per scenario):
/// each active maximum's slope when one parameter of its scenario moves, the design and the
/// angle held (the scenario's scene rebuilt at the partner vertex or at θ ± h,
/// [`ls::block_field_values`]; every figure is affine in a link's mass and in ω², a length
/// is general), weighted by its multiplier
/// (`crate::synth::envelope::sensitivities`, the envelope theorem).
pub fn sensitivities(
    scene: &LinkageScene,
    sol: &Solution,
    block_len: usize,
) -> Result<Vec<Sensitivity>, String> {
    let multipliers = envelope::multipliers_of(sol)?;
    let env = &scene.envelope;
    let n_cw = PER_COUNTERWEIGHT * scene.counterweights.len();
    let scenarios = env.scenarios(&scene.linkage);
    let fields_at = |k: usize, values: &[f64], ms: &[&Multiplier]| {
        let at: Vec<(usize, f64)> = ms.iter().map(|m| (m.field % block_len, m.angle)).collect();
        let case = scenarios[k].case;
        let s = ls::scene_at_case(scene, case, values).map_err(|e| e.to_string())?;
        ls::block_field_values(&s, &at, n_cw + k, &sol.x).map_err(|e| e.to_string())
    };
    envelope::scenario_sensitivities(
        &env.names(),
        &env.ranges(),
        block_len,
        multipliers,
        env.first_length(),
        env.speed.is_some(),
        fields_at,
    )
}

/// The Halton points 1..=N of the box, each in every load case, each scene's figures
/// computed afresh: the largest and how many exceed the worst cases `w` beyond both errors.
fn monte_carlo(
    scene: &LinkageScene,
    x: Option<&[f64]>,
    w: &[Option<WorstCase>; 4],
    s: &Settings,
) -> Result<MonteCarlo, String> {
    let env = &scene.envelope;
    let ranges = env.ranges();
    let energy = w[3].is_some();
    let cases = 1 + env.cases.len();
    // Without a length tolerance every point of the box has the nominal geometry: the poses
    // on the scan grid are made once for all of them.
    let poses = (env.first_length() == ranges.len())
        .then(|| grid_poses(&scene.linkage, s.scan_samples))
        .transpose()?;
    let rows = ordered((0..env.monte_carlo * cases).into_par_iter().map(|j| {
        let (i, c) = (1 + j / cases, j % cases);
        let sc =
            ls::scene_at_case(scene, c, &halton_point(&ranges, i)).map_err(|e| e.to_string())?;
        let [f, m, t] = peaks_on(&sc, x, s, poses.as_deref())?;
        let e = energy.then(|| delta_e(&sc, x)).transpose()?;
        Ok::<_, String>([f, m, t, e.unwrap_or((f64::NAN, 0.0))])
    }))?;
    let beyond = |r: &[(f64, f64); 4]| {
        r.iter()
            .zip(w)
            .any(|(v, wc)| wc.is_some_and(|wc| v.0 > wc.value + wc.error + v.1))
    };
    let max = [0, 1, 2, 3].map(|c| rows.iter().map(|r| r[c].0).fold(f64::NAN, f64::max));
    Ok(MonteCarlo {
        samples: rows.len(),
        max,
        beyond_worst_case: rows.iter().filter(|r| beyond(r)).count(),
    })
}

/// The peaks of |F|, |M_O| and |T| of `sc` with the design `x` (none: bare), each with its
/// error: `scan_samples` angles, every maximum that can be the peak refined to `peak_xtol`,
/// plus the model's round-off bound at the refined peak.
pub fn peaks(
    sc: &LinkageScene,
    x: Option<&[f64]>,
    s: &Settings,
) -> Result<[(f64, f64); 3], String> {
    peaks_on(sc, x, s, None)
}

/// The linkage's poses at the scan angles 2πk/n, or where it does not assemble.
fn grid_poses(l: &Linkage, n: usize) -> Result<Vec<Pose>, String> {
    let h = std::f64::consts::TAU / n as f64;
    (0..n)
        .map(|k| l.pose(k as f64 * h))
        .collect::<Result<_, _>>()
        .map_err(|_| "the linkage does not assemble at a scanned angle".to_string())
}

/// [`peaks`], with the poses on the scan grid given where they are known (`poses`, n =
/// `scan_samples` of them: the scene's geometry, shared by every point of a box without a
/// length tolerance; the refinement between grid angles makes its own).
fn peaks_on(
    sc: &LinkageScene,
    x: Option<&[f64]>,
    s: &Settings,
    poses: Option<&[Pose]>,
) -> Result<[(f64, f64); 3], String> {
    let l: &Linkage = &sc.linkage;
    let extra = x
        .map(|x| ls::extras(&sc.counterweights, x))
        .unwrap_or_default();
    let params = l.params();
    let on = |pose: &Pose| -> ([f64; 3], [f64; 3]) {
        let map = l.balance_map(pose, sc.moment_about);
        let f = map.fields(&extra);
        let (ef, em, et) = map.error(&params, &extra);
        (
            [f.force.norm(), f.moment.abs(), f.torque.abs()],
            [ef, em, et],
        )
    };
    let at = |th: f64| l.pose(th).ok().map(|p| on(&p));
    let n = s.scan_samples;
    let own;
    let poses = match poses {
        Some(ps) if ps.len() == n => ps,
        _ => {
            own = grid_poses(l, n)?;
            &own
        }
    };
    let samples: Vec<_> = poses.iter().map(on).collect();
    let mut out = [(0.0, 0.0); 3];
    for (c, o) in out.iter_mut().enumerate() {
        let ys: Vec<f64> = samples.iter().map(|v| v.0[c]).collect();
        let f = |th: f64| at(th).map_or(f64::NAN, |v| v.0[c]);
        let pk = periodic_peak_sampled(&ys, f, Some(s.peak_xtol), Refine::PeakOnly)
            .map_err(|e| e.to_string())?;
        let round = at(pk.peak.x).map_or(f64::INFINITY, |v| v.1[c]);
        *o = (pk.peak.fx, pk.error + round);
    }
    Ok(out)
}
