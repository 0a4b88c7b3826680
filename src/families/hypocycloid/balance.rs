//! The machine beyond the reciprocating orders of paper 004: the counterweights of its
//! rotating masses (closed form, and the certified minimax of the whole shaking force with
//! the shared engine `synth::minimax`), the drive torque of a compressor cycle with the
//! inertia torque of the mechanism, and the couples of offset Lanchester shafts. Physics in
//! `dynamics.rs` and `gas.rs`; this module turns a resolved design into figures with error
//! bounds for the report.

use crate::dynamics::{self, Drive, DriveFigures};
use crate::families::hypocycloid::dynamics::{
    cancelling_counterweights, carrier_from_effective, harmonic_force, harmonic_force_at,
    kinematics, Counterweight, Geometry, MovingMasses, RotatingMasses, ShaftLayout,
};
use crate::families::hypocycloid::gas::{Cycle, GasCycle, LoadCase};
use crate::families::hypocycloid::model::{Coefficients, Hypocycloid, LanchesterPair};
use crate::families::hypocycloid::synth::{residual_rate, residual_rel};
use crate::geom::P2;
use crate::numeric::periodic_peak;
use crate::synth::counterweight::Status as EngineStatus;
use crate::synth::minimax::{self as mm, AffineValue, FnField, Problem};
use serde::Serialize;
use std::f64::consts::TAU;

/// What the rotating counterweights minimise.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum RotatingGoal {
    /// Cancel the rotating parts' force exactly (closed form); the reciprocating force is
    /// left to the Lanchester pairs.
    #[default]
    RotatingForce,
    /// Also minimise the peak of the whole shaking force (rotating + the reciprocating force
    /// left after the Lanchester pairs) over the two counterweights: a convex minimax,
    /// solved and certified by the shared engine.
    PeakShakingForce,
}

/// The counterweight design asked for (`[design.rotating]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RotatingDesign {
    /// ρ1, the centroid radius of the carrier counterweight from O (m).
    pub carrier_radius: f64,
    /// ρ2, the centroid radius of the planet counterweight from O1 (m).
    pub planet_radius: f64,
    /// The goal.
    pub minimize: RotatingGoal,
}

/// Everything beyond the paper's reciprocating orders a file may ask for.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct DynamicsSpec {
    /// The rotating masses (`[mechanism.carrier]`, `[mechanism.planet]`, `[mechanism.rod]`).
    pub masses: Option<RotatingMasses>,
    /// The counterweights (`[design.rotating]`, needs the masses).
    pub design: Option<RotatingDesign>,
    /// The compressor cycle (`[mechanism.gas]`).
    pub gas: Option<GasCycle>,
    /// The Lanchester shafts' position (`[mechanism.lanchester]`).
    pub shafts: Option<ShaftLayout>,
    /// The drive at real speed (`[mechanism.drive]`).
    pub drive: Option<Drive>,
    /// The named load cases beside the nominal `gas` (`[[mechanism.load_cases]]`).
    pub load_cases: Vec<LoadCase>,
    /// The speed band (ω_min, ω_max) in rad/s (`[mechanism.envelope] speed`): every case at
    /// both its ends too (`load_cases.rs`).
    pub speed_band: Option<(f64, f64)>,
}

impl DynamicsSpec {
    /// Whether anything is asked.
    pub fn any(&self) -> bool {
        self.masses.is_some() || self.gas.is_some() || self.shafts.is_some() || self.drive.is_some()
    }
}

/// The certified minimax of the whole shaking force.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MinimaxCounterweights {
    /// The carrier counterweight.
    pub carrier: Counterweight,
    /// The planet counterweight.
    pub planet: Counterweight,
    /// V: the peak of the whole shaking force with them (N).
    pub peak: f64,
    /// L: the certified lower bound of the optimum (N).
    pub lower_bound: f64,
    /// |V − optimum| ≤ this (N).
    pub error: f64,
    /// `optimal` only with the engine's certificate.
    pub status: EngineStatus,
    /// Exchange rounds.
    pub rounds: usize,
    /// Why not optimal, if not.
    pub note: Option<String>,
}

/// The rotating masses and their counterweights.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RotatingOutcome {
    /// U1 (kg·m), carrier frame.
    pub u1: [f64; 2],
    /// U2 (kg·m), planet frame.
    pub u2: [f64; 2],
    /// Peak of the rotating parts' force without counterweights (N).
    pub rotating_peak: f64,
    /// The closed-form cancelling counterweights.
    pub closed: Option<(Counterweight, Counterweight)>,
    /// Peak of the rotating force left with them (N): round-off only.
    pub closed_rotating_residual: Option<f64>,
    /// Peak of the whole shaking force with them (rotating + reciprocating residual) (N).
    pub closed_total_peak: Option<f64>,
    /// Peak of the whole shaking force without any rotating counterweight (N).
    pub bare_total_peak: f64,
    /// Error bound of the force peaks (N): refinement + the coefficients' error.
    pub peak_error: f64,
    /// The minimax, with `minimize = "peak-shaking-force"`.
    pub minimax: Option<MinimaxCounterweights>,
}

impl RotatingOutcome {
    /// The peak of the whole shaking force at constant speed with the counterweights the
    /// design builds ([`RotatingOutcome::design_pair`]), without any where there are none.
    pub fn design_peak(&self) -> f64 {
        match (&self.minimax, self.closed_total_peak) {
            (Some(m), _) => m.peak,
            (None, Some(p)) => p,
            (None, None) => self.bare_total_peak,
        }
    }

    /// The (carrier, planet) counterweights the design builds: the minimax pair where it was
    /// asked for, else the closed-form pair; none without `[design.rotating]`.
    pub fn design_pair(&self) -> Option<(Counterweight, Counterweight)> {
        self.minimax
            .as_ref()
            .map(|m| (m.carrier, m.planet))
            .or(self.closed)
    }
}

/// The drive torque over a turn.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TorqueOutcome {
    /// Peak |T| (N·m).
    pub peak: f64,
    /// Its angle (rad).
    pub peak_angle: f64,
    /// Error bound of the peak (N·m).
    pub peak_error: f64,
    /// Mean T over a turn (N·m).
    pub mean: f64,
    /// Mean of the gas torque (N·m), 0 without a gas cycle.
    pub gas_mean: f64,
    /// Error bound of the means (quadrature change) (N·m).
    pub mean_error: f64,
    /// Mean of the inertia torque (N·m): 0 in exact arithmetic (E is periodic).
    pub inertia_mean: f64,
    /// Indicated work −∮p dV per turn (J), with a gas cycle.
    pub indicated_work: Option<f64>,
    /// Peak gas force on the piston (N), with a gas cycle.
    pub gas_force_peak: Option<f64>,
    /// Whether the cycle delivers (the compression reaches p_d).
    pub delivers: Option<bool>,
    /// Curves for the plot and the CSV: φ, T_gas, T_inertia, T (N·m), p (Pa).
    pub phi: Vec<f64>,
    /// T_gas(φ).
    pub gas: Vec<f64>,
    /// T_in(φ).
    pub inertia: Vec<f64>,
    /// T(φ).
    pub total: Vec<f64>,
    /// p(φ) (Pa), empty without a gas cycle.
    pub pressure: Vec<f64>,
}

/// One order's Lanchester couple.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoupleRow {
    /// Order i.
    pub order: usize,
    /// Amplitude F_i sqrt(e² + d²/4) (N·m).
    pub amplitude: f64,
}

/// The couples of offset Lanchester shafts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoupleOutcome {
    /// The layout.
    pub layout: ShaftLayout,
    /// Per balanced order.
    pub rows: Vec<CoupleRow>,
    /// Peak over φ of the sum of all pairs' couples (N·m).
    pub peak: f64,
    /// Its error bound (N·m).
    pub peak_error: f64,
}

/// Everything of this module for one design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DynamicsOutcome {
    /// The rotating masses and counterweights.
    pub rotating: Option<RotatingOutcome>,
    /// The drive torque.
    pub torque: Option<TorqueOutcome>,
    /// The couples.
    pub couples: Option<CoupleOutcome>,
    /// The drive at constant and at real speed (`[mechanism.drive]`; `Err`: why it could not
    /// be computed).
    #[serde(skip)]
    pub drive: Option<Result<DriveFigures, String>>,
    /// Things the user should know.
    pub warnings: Vec<String>,
}

/// The design the dynamics are computed for.
pub struct At<'a> {
    /// The dimensionless model.
    pub model: &'a Hypocycloid,
    /// Its coefficients.
    pub coef: &'a Coefficients,
    /// The balanced orders.
    pub orders: &'a [usize],
    /// The Lanchester pairs.
    pub pairs: &'a [LanchesterPair],
    /// R (m).
    pub r_carrier: f64,
    /// m_B (kg).
    pub m_b: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// φ samples of the curves.
    pub plot_samples: usize,
}

impl At<'_> {
    /// The same design at the speed ω (rad/s).
    pub(super) fn at_speed(&self, omega: f64) -> Self {
        At {
            model: self.model,
            coef: self.coef,
            orders: self.orders,
            pairs: self.pairs,
            r_carrier: self.r_carrier,
            m_b: self.m_b,
            omega,
            plot_samples: self.plot_samples,
        }
    }

    /// The design's lengths and speed.
    pub(super) fn geometry(&self) -> Geometry {
        Geometry {
            r_carrier: self.r_carrier,
            r_crank: self.model.theta * self.r_carrier,
            l_rod: self.r_carrier / self.model.lambda,
            alpha0: self.model.alpha0,
            omega: self.omega,
        }
    }
    fn fscale(&self) -> f64 {
        self.m_b * self.r_carrier * self.omega * self.omega
    }
    /// The reciprocating force left after the pairs (N, along x).
    fn recip(&self, phi: f64) -> f64 {
        self.fscale() * residual_rel(self.model, self.coef, self.orders, phi)
    }
    /// The reciprocating force left after the pairs at real speed ω and acceleration α (N,
    /// along x): m_B R (ω² residual − α s_res′) ([`residual_rate`]).
    fn recip_at(&self, phi: f64, omega: f64, alpha: f64) -> f64 {
        let (m, c, o) = (self.model, self.coef, self.orders);
        self.m_b
            * self.r_carrier
            * (omega * omega * residual_rel(m, c, o, phi) - alpha * residual_rate(m, c, o, phi))
    }
    /// Its error from the coefficients of the cancelled orders (N).
    fn recip_error(&self) -> f64 {
        self.fscale()
            * self
                .orders
                .iter()
                .map(|&i| (i * i) as f64 * self.coef.err[i])
                .sum::<f64>()
    }
}

/// Why the dynamics cannot be computed (the key named is the problem-file key).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key}: {message}")]
pub struct DynamicsError {
    /// The problem-file key.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

fn derr(key: &str, message: impl Into<String>) -> DynamicsError {
    DynamicsError {
        key: key.into(),
        message: message.into(),
    }
}

/// The peak of |f| over a turn with its error (scan of 720, Brent to 1e-10).
fn peak_of(f: impl Fn(f64) -> f64) -> (f64, f64, f64) {
    match periodic_peak(f, 720, 1e-10) {
        Ok(p) => (p.peak.fx, p.peak.x, p.error),
        Err(_) => (f64::NAN, f64::NAN, f64::NAN),
    }
}

/// The certified minimax of |F_rot(φ; U + x) + F_rec(φ) e_x| over the effective variables
/// x = (W1 + m2 R e_x, W2) (the force is affine in them; each harmonic's
/// variable is bounded by |U| + 2P0/(k²ω²), P0 the peak without counterweights, a bound no
/// optimum reaches: the k-th harmonic's amplitude is at most the peak). `recip(φ)` is the
/// reciprocating force along x (N) and `recip_err` its error bound.
pub fn minimax_counterweights(
    geo: &Geometry,
    u1: P2,
    u2: P2,
    recip: &(dyn Fn(f64) -> f64 + Sync),
    recip_err: f64,
    design: &RotatingDesign,
) -> Result<MinimaxCounterweights, DynamicsError> {
    let w2 = geo.omega * geo.omega;
    let b_of = |phi: f64| harmonic_force(geo, u1, u2, phi) + P2::new(recip(phi), 0.0);
    let (p0, _, _) = peak_of(|p| b_of(p).norm());
    let b1 = u1.norm() + 2.0 * p0 / w2 + f64::MIN_POSITIVE;
    let b2 = u2.norm() + 2.0 * p0 / (4.0 * w2) + f64::MIN_POSITIVE;
    let eval = |phi: f64, out: &mut AffineValue| {
        let b = b_of(phi);
        out.b = [b.x, b.y];
        let e1 = harmonic_force(geo, P2::new(1.0, 0.0), P2::zeros(), phi);
        let f1 = harmonic_force(geo, P2::new(0.0, 1.0), P2::zeros(), phi);
        let e2 = harmonic_force(geo, P2::zeros(), P2::new(1.0, 0.0), phi);
        let f2 = harmonic_force(geo, P2::zeros(), P2::new(0.0, 1.0), phi);
        out.row_mut(0).copy_from_slice(&[e1.x, f1.x, e2.x, f2.x]);
        out.row_mut(1).copy_from_slice(&[e1.y, f1.y, e2.y, f2.y]);
    };
    let field = FnField::new("shaking force", 2, eval).with_error(move |_, _| recip_err);
    let pb = Problem {
        fields: vec![&field],
        counterweights: Vec::new(),
        extra: vec![
            (-2.0 * b1, 2.0 * b1),
            (-2.0 * b1, 2.0 * b1),
            (-2.0 * b2, 2.0 * b2),
            (-2.0 * b2, 2.0 * b2),
        ],
        linear: Vec::new(),
        goal: mm::Goal::MinPeak(vec![(0, 1.0)]),
        limits: Vec::new(),
    };
    let sol = mm::solve(&pb, &mm::Settings::default())
        .map_err(|e| derr("design.rotating", e.to_string()))?;
    if !sol.x.iter().all(|v| v.is_finite()) {
        return Err(derr(
            "design.rotating",
            format!("the minimax failed: {}", sol.note.unwrap_or_default()),
        ));
    }
    // x = (W1 + m2 R e_x, W2): the planet counterweight first, then the carrier's own W1.
    let w_2 = P2::new(sol.x[2], sol.x[3]);
    let m2 = w_2.norm() / design.planet_radius;
    let w_1 = carrier_from_effective(P2::new(sol.x[0], sol.x[1]), m2, geo.r_carrier);
    Ok(MinimaxCounterweights {
        carrier: Counterweight::new(w_1, design.carrier_radius),
        planet: Counterweight::new(w_2, design.planet_radius),
        peak: sol.objective,
        lower_bound: sol.lower_bound,
        error: sol.error.total,
        status: sol.status,
        rounds: sol.rounds,
        note: sol.note.clone(),
    })
}

/// The whole shaking force (N) at φ of the rotating parts with the counterweights `cw`
/// (carrier, planet) and the reciprocating force `recip` (N, along x).
pub fn total_force(
    geo: &Geometry,
    u1: P2,
    u2: P2,
    cw: (&Counterweight, &Counterweight),
    recip: f64,
    phi: f64,
) -> P2 {
    let (v1, v2) = with_counterweights(geo, u1, u2, cw);
    harmonic_force(geo, v1, v2, phi) + P2::new(recip, 0.0)
}

/// The unbalances (V1, V2) turning with the carrier and the planet once the counterweights
/// `cw` (carrier, planet) are added: V1 = U1 + W1 + m2 R e_x (the planet counterweight's mass
/// rides on the carrier at R), V2 = U2 + W2.
fn with_counterweights(
    geo: &Geometry,
    u1: P2,
    u2: P2,
    cw: (&Counterweight, &Counterweight),
) -> (P2, P2) {
    (
        u1 + P2::from(cw.0.w) + P2::new(cw.1.mass * geo.r_carrier, 0.0),
        u2 + P2::from(cw.1.w),
    )
}

/// Computes what `spec` asks at the design `at`: the rotating masses' counterweights, the
/// drive torque (with a gas cycle or masses) and the Lanchester shafts' couples.
pub fn solve(spec: &DynamicsSpec, at: &At) -> Result<DynamicsOutcome, DynamicsError> {
    let geo = at.geometry();
    let mut warnings = Vec::new();
    let rotating = match &spec.masses {
        None => None,
        Some(ms) => Some(rotating_outcome(spec, ms, at, &geo, &mut warnings)?),
    };
    // The drive torque: with a gas cycle or masses.
    let torque = if spec.gas.is_some() || spec.masses.is_some() {
        Some(torque_outcome(
            spec,
            at,
            &geo,
            rotating.as_ref(),
            &mut warnings,
        )?)
    } else {
        None
    };
    let couples = spec.shafts.map(|layout| couple_outcome(layout, at));
    let drive = match &spec.drive {
        Some(d) => Some(drive_outcome(spec, d, at, &geo, rotating.as_ref())?),
        None => None,
    };
    Ok(DynamicsOutcome {
        rotating,
        torque,
        couples,
        drive,
        warnings,
    })
}

/// The drive of the machine (`[mechanism.drive]`) as a one-degree-of-freedom machine of the
/// carrier angle φ: J = 2 E/ω² + J₀ and J′ = 2 T_in/ω² of the moving masses
/// ([`MovingMasses::energy_and_torque`]), G = T_gas of the cycle (0 without one). J₀ adds
/// the carrier's and its counterweight's m |c|², constant; the bodies' own rotational
/// inertias (carrier, planet spin at its fixed ratio, Lanchester shafts) are constant too and
/// not in the file: they act as flywheel, so the flywheel found includes them.
pub(super) fn drive_outcome(
    spec: &DynamicsSpec,
    d: &Drive,
    at: &At,
    geo: &Geometry,
    rotating: Option<&RotatingOutcome>,
) -> Result<Result<DriveFigures, String>, DynamicsError> {
    let moving = moving_masses(spec, at, rotating);
    let cycle = cycle(spec, at)?;
    let carrier_cw = rotating
        .and_then(RotatingOutcome::design_pair)
        .map_or(0.0, |(c, _)| c.mass * c.radius * c.radius);
    let j0 = spec.masses.map_or(0.0, |m| {
        m.carrier_mass * P2::from(m.carrier_centroid).norm_squared()
    }) + carrier_cw;
    let machine = |p: f64| {
        let (e, t) = moving.energy_and_torque(&kinematics(at.model, geo, p), geo);
        let g = cycle
            .as_ref()
            .map_or(0.0, |c| c.torque(at.model, at.r_carrier, p));
        [2.0 * e + j0, 2.0 * t, g]
    };
    // The gas torque has kinks at the valve events.
    let set = dynamics::DriveSettings::for_kinks();
    let figures = match dynamics::drive(&machine, at.omega, d, &set) {
        Ok(f) => f,
        Err(e) => return Ok(Err(e.to_string())),
    };
    // The shaking force at real speed: the rotating unbalances with the design's
    // counterweights and the reciprocating residual, each with its ω² and α parts.
    let (v1, v2) = rotating.map_or((P2::zeros(), P2::zeros()), |r| {
        let (u1, u2) = (P2::from(r.u1), P2::from(r.u2));
        match r.design_pair() {
            Some((c1, c2)) => with_counterweights(geo, u1, u2, (&c1, &c2)),
            None => (u1, u2),
        }
    });
    Ok(Ok(figures.with_real_speed(&d.motor, |p, w, a| {
        let f = harmonic_force_at(geo, v1, v2, p, w, a) + P2::new(at.recip_at(p, w, a), 0.0);
        Some(f.norm())
    })))
}

/// The compressor cycle of `spec`, if it has one.
fn cycle(spec: &DynamicsSpec, at: &At) -> Result<Option<Cycle>, DynamicsError> {
    spec.gas
        .map(|g| {
            Cycle::new(at.model, at.r_carrier, g).map_err(|e| derr("mechanism.gas", e.to_string()))
        })
        .transpose()
}

/// The rotating masses `ms` and their counterweights: the unbalances U₁, U₂ (rod centroid
/// within the rod, m_B at least the rod's share at B), the peaks of the rotating and the
/// whole force without counterweights, and with `spec.design` the cancelling pair (closed
/// form) and, when asked, the certified minimax pair.
fn rotating_outcome(
    spec: &DynamicsSpec,
    ms: &RotatingMasses,
    at: &At,
    geo: &Geometry,
    warnings: &mut Vec<String>,
) -> Result<RotatingOutcome, DynamicsError> {
    let rerr = at.recip_error();
    if ms.rod_centroid > geo.l_rod {
        return Err(derr(
            "mechanism.rod.centroid",
            format!(
                "AG = {} m is longer than the rod L = R/λ = {} m",
                ms.rod_centroid, geo.l_rod
            ),
        ));
    }
    if ms.rod_at_b(geo) > at.m_b * (1.0 + 1e-12) {
        return Err(derr(
            "mechanism.reciprocating_mass",
            format!(
                "m_B = {} kg is less than the rod's share at B, m_r·AG/L = {} kg; m_B is the piston group plus that share",
                at.m_b,
                ms.rod_at_b(geo)
            ),
        ));
    }
    let (u1, u2) = ms.unbalances(geo);
    let (rot_peak, _, rot_err) = peak_of(|p| harmonic_force(geo, u1, u2, p).norm());
    let (bare, _, bare_err) =
        peak_of(|p| (harmonic_force(geo, u1, u2, p) + P2::new(at.recip(p), 0.0)).norm());
    let mut out = RotatingOutcome {
        u1: [u1.x, u1.y],
        u2: [u2.x, u2.y],
        rotating_peak: rot_peak,
        closed: None,
        closed_rotating_residual: None,
        closed_total_peak: None,
        bare_total_peak: bare,
        peak_error: rot_err.max(bare_err) + rerr,
        minimax: None,
    };
    if let Some(d) = &spec.design {
        let (c1, c2) =
            cancelling_counterweights(u1, u2, geo.r_carrier, d.carrier_radius, d.planet_radius);
        let (res, _, _) = peak_of(|p| total_force(geo, u1, u2, (&c1, &c2), 0.0, p).norm());
        let (tot, _, tot_err) =
            peak_of(|p| total_force(geo, u1, u2, (&c1, &c2), at.recip(p), p).norm());
        out.closed = Some((c1, c2));
        out.closed_rotating_residual = Some(res);
        out.closed_total_peak = Some(tot);
        out.peak_error = out.peak_error.max(tot_err + rerr);
        if d.minimize == RotatingGoal::PeakShakingForce {
            let recip = |p: f64| at.recip(p);
            let mm = minimax_counterweights(geo, u1, u2, &recip, rerr, d)?;
            if mm.status != EngineStatus::Optimal {
                warnings.push(format!(
                    "the rotating counterweights' minimax is {:?}: {}",
                    mm.status,
                    mm.note.clone().unwrap_or_default()
                ));
            }
            out.minimax = Some(mm);
        }
    }
    Ok(out)
}

/// The drive torque T = T_gas + T_in over a turn: T_in = ω²·dE/dφ of the moving masses
/// (with the planet's counterweight, the minimax one before the closed one), T_gas of the
/// compressor cycle; its mean (split into gas and inertia), its refined peak |T| and the
/// curves at `at.plot_samples` angles.
pub(super) fn torque_outcome(
    spec: &DynamicsSpec,
    at: &At,
    geo: &Geometry,
    rotating: Option<&RotatingOutcome>,
    warnings: &mut Vec<String>,
) -> Result<TorqueOutcome, DynamicsError> {
    let moving = moving_masses(spec, at, rotating);
    let w2 = at.omega * at.omega;
    let t_in = |p: f64| {
        w2 * moving
            .energy_and_torque(&kinematics(at.model, geo, p), geo)
            .1
    };
    let cycle = cycle(spec, at)?;
    let t_gas = |p: f64| {
        cycle
            .as_ref()
            .map_or(0.0, |c| c.torque(at.model, at.r_carrier, p))
    };
    let total = |p: f64| t_gas(p) + t_in(p);
    let (gas_mean, in_mean, mean, mean_err) = mean_torques(cycle.as_ref(), &t_gas, &t_in);
    if let Some(c) = &cycle {
        if !c.delivers {
            warnings.push(
                "the compression never reaches the discharge pressure (clearance too large for the pressure ratio): nothing is delivered"
                    .into(),
            );
        }
    }
    let (peak, peak_angle, mut peak_error) = peak_of(|p| total(p).abs());
    if cycle.is_some() {
        peak_error += kink_error(&total);
    }
    let np = at.plot_samples;
    let phi: Vec<f64> = (0..np).map(|j| TAU * j as f64 / (np - 1) as f64).collect();
    Ok(TorqueOutcome {
        peak,
        peak_angle,
        peak_error: peak_error + mean_err,
        mean,
        gas_mean,
        mean_error: mean_err,
        inertia_mean: in_mean,
        indicated_work: cycle.as_ref().map(|_| gas_mean * TAU),
        gas_force_peak: cycle.as_ref().map(|c| c.peak_force(at.model, at.r_carrier)),
        delivers: cycle.as_ref().map(|c| c.delivers),
        gas: phi.iter().map(|&p| t_gas(p)).collect(),
        inertia: phi.iter().map(|&p| t_in(p)).collect(),
        total: phi.iter().map(|&p| total(p)).collect(),
        pressure: cycle
            .as_ref()
            .map(|c| {
                phi.iter()
                    .map(|&p| c.pressure(at.model, at.r_carrier, p))
                    .collect()
            })
            .unwrap_or_default(),
        phi,
    })
}

/// The moving masses of the torque: the rotating masses (none without `[mechanism.*]`
/// masses), m_B, and the planet's counterweight (mass, first moment) of the design — the
/// minimax one, else the closed-form one, else none.
fn moving_masses(spec: &DynamicsSpec, at: &At, rotating: Option<&RotatingOutcome>) -> MovingMasses {
    let zero = RotatingMasses {
        carrier_mass: 0.0,
        carrier_centroid: [0.0; 2],
        planet_mass: 0.0,
        planet_centroid: [0.0; 2],
        rod_mass: 0.0,
        rod_centroid: 0.0,
        rod_inertia: None,
    };
    let planet_cw = rotating
        .and_then(RotatingOutcome::design_pair)
        .map_or((0.0, P2::zeros()), |(_, c)| (c.mass, P2::from(c.w)));
    MovingMasses {
        rotating: spec.masses.unwrap_or(zero),
        m_b: at.m_b,
        planet_cw,
    }
}

/// The means over a turn of T_gas and T_in, their sum and its error: with a cycle, Gauss
/// quadrature on its smooth pieces; without, the trapezoid rule on 1440 points
/// (spectrally accurate: T_in is smooth and periodic), its change from half the points as
/// the error.
fn mean_torques(
    cycle: Option<&Cycle>,
    t_gas: &dyn Fn(f64) -> f64,
    t_in: &dyn Fn(f64) -> f64,
) -> (f64, f64, f64, f64) {
    match cycle {
        Some(c) => {
            let (g, ge) = c.mean_over_pieces(t_gas, 8);
            let (i, ie) = c.mean_over_pieces(t_in, 8);
            (g, i, g + i, ge + ie)
        }
        None => {
            let n = 1440;
            let m1: f64 = (0..n).map(|k| t_in(TAU * k as f64 / n as f64)).sum::<f64>() / n as f64;
            let m2: f64 = (0..n / 2)
                .map(|k| t_in(TAU * k as f64 / (n / 2) as f64))
                .sum::<f64>()
                / (n / 2) as f64;
            (0.0, m1, m1, (m1 - m2).abs())
        }
    }
}

/// The extra error of the torque's peak with a gas cycle: T has kinks at the valve events,
/// where the curvature estimate of the peak's error does not hold, so add the slope bound
/// 2·max|T'|·xtol (xtol = 1e-10 rad), the slope from a 1440-point scan (doubled for the
/// scan's own error).
fn kink_error(total: &dyn Fn(f64) -> f64) -> f64 {
    let n = 1440;
    let h = TAU / n as f64;
    let ts: Vec<f64> = (0..=n).map(|k| total(k as f64 * h)).collect();
    let slope = ts
        .windows(2)
        .map(|w| (w[1] - w[0]).abs() / h)
        .fold(0.0, f64::max);
    2.0 * slope * 1e-10
}

/// The couples of the Lanchester shafts in `layout`: each pair's amplitude and the refined
/// peak of their sum over φ.
fn couple_outcome(layout: ShaftLayout, at: &At) -> CoupleOutcome {
    let rows: Vec<CoupleRow> = at
        .pairs
        .iter()
        .map(|p| CoupleRow {
            order: p.order,
            amplitude: layout.couple_amplitude(p),
        })
        .collect();
    let (peak, _, err) = peak_of(|phi| {
        at.pairs
            .iter()
            .map(|p| layout.couple_direct(p, phi))
            .sum::<f64>()
            .abs()
    });
    CoupleOutcome {
        layout,
        rows,
        peak,
        peak_error: err,
    }
}
