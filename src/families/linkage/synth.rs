//! The linkage's counterweight synthesis: the shaking force F, the shaking moment M_O and the
//! input torque T of the linkage as fields affine in the counterweights' (m, u, I), handed to
//! the certified minimax engine ([`crate::synth::minimax`]).
//!
//! Counterweight j on link L_j adds x_j = (m_j, u_j, I_j) to that link's inertial parameters
//! p = (m, m c_x, m c_y, I_P) (the same order), so at every θ
//! F(θ; x) = F₀(θ) + Σ_j A_Lj(θ) x_j, M_O = M₀ + Σ_j m_Lj(θ)·x_j, T = T₀ + Σ_j t_Lj(θ)·x_j
//! with the blocks of [`Linkage::balance_map`]. Full force balance (F ≡ 0, Berkof–Lowen) is a
//! set of linear equalities on x: the range of the stacked force blocks at
//! [`BALANCE_ANGLES`] angles, from their SVD (well-conditioned rows, a consistent right-hand
//! side); when the counterweights cannot supply it, the least-squares residual says by how much.

use crate::dynamics::{DriveSettings, SteadyState};
use crate::families::linkage::file::{CounterweightSpec, Goal, LinkageScene, Objective};
use crate::families::linkage::model::{
    BalanceMap, Body, Joint, JointKind, Linkage, Params, Pose, ReactionMap,
};
use crate::geom::plate::Realised;
use crate::geom::P2;
use crate::numeric::{ordered, periodic_peak_sampled, AngleMemo, Refine};
use crate::synth::energy::EnergyField;
use crate::synth::minimax::{
    self as mm, AffineValue, CounterweightLimits, Engine, FnField, LinearConstraint, Problem,
    Relation, Settings, Solution,
};
use crate::synth::Var;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::sync::Mutex;

/// Field indices of the problem: shaking force (2-D), shaking moment about O, input torque.
pub const FORCE: usize = 0;
/// See [`FORCE`].
pub const MOMENT: usize = 1;
/// See [`FORCE`].
pub const TORQUE: usize = 2;
/// The first joint's field, with `objective.max_joint_force` (joint k is `JOINT0 + k`).
pub const JOINT0: usize = 3;

/// Uniform crank angles whose force equations define full force balance.
pub const BALANCE_ANGLES: usize = 64;

/// Relative least-squares residual of the balance equations above which full force balance is
/// out of the counterweights' reach.
pub const BALANCE_RESIDUAL_TOL: f64 = 1e-8;

/// Why a linkage cannot be solved (beyond an engine error).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinkageSolveError {
    /// The engine refused the problem or its settings.
    #[error(transparent)]
    Engine(#[from] mm::MinimaxError),
    /// The linkage did not assemble at an angle the solve needed (a narrow unreachable range
    /// the file's check missed).
    #[error("the linkage does not assemble at crank angle {0:.6}° (dyad {1})")]
    NoAssembly(f64, usize),
    /// The joint-force equations are singular at this crank angle (°): a toggle.
    #[error("the joint-force equations are singular at crank angle {0:.6}° (a toggle: the joint loads are unbounded there)")]
    SingularReactions(f64),
}

/// The three fields of a scene, with the first assembly failure met while evaluating them and
/// the largest dyad conditioning κ seen (over the engine's scan and every refined angle).
pub struct SceneFields<'s> {
    scene: &'s LinkageScene,
    /// The first failure met: an angle where the linkage does not assemble or its
    /// joint-force equations are singular.
    failure: Mutex<Option<LinkageSolveError>>,
    /// max κ ≥ 1 as f64 bits (positive floats order as their bits).
    kappa: AtomicU64,
    /// The joints ([`crate::families::linkage::model::Linkage::joints`]).
    joints: Vec<Joint>,
    /// Reaction maps by θ's bits: every joint field at an angle shares one.
    reaction_maps: AngleMemo<Arc<ReactionMap>>,
    /// Balance maps by θ's bits: the three fields at an angle share one.
    balance_maps: AngleMemo<Arc<BalanceMap>>,
}

impl<'s> SceneFields<'s> {
    /// The fields of `scene`.
    pub fn new(scene: &'s LinkageScene) -> Self {
        SceneFields {
            scene,
            failure: Mutex::new(None),
            kappa: AtomicU64::new(1f64.to_bits()),
            joints: scene.linkage.joints(),
            reaction_maps: AngleMemo::default(),
            balance_maps: AngleMemo::default(),
        }
    }

    /// Records the first failure of a solve (later ones are consequences).
    fn fail(&self, e: LinkageSolveError) {
        self.failure
            .lock()
            .expect("no panic holds it")
            .get_or_insert(e);
    }

    /// The pose at θ without its angles ([`Linkage::pose_for_fields`]: the balance and
    /// reaction maps read none), or `None` where the linkage does not assemble (recorded).
    ///
    /// [`Linkage::pose_for_fields`]: super::model::Linkage::pose_for_fields
    fn pose(&self, theta: f64) -> Option<Pose> {
        self.scene
            .linkage
            .pose_for_fields(theta)
            .map_err(|e| self.fail(LinkageSolveError::NoAssembly(theta.to_degrees(), e.dyad)))
            .ok()
    }

    /// The reaction map at θ, or `None` where the linkage does not assemble or the
    /// joint-force equations are singular (recorded as a failure).
    fn reaction_map(&self, theta: f64) -> Option<Arc<ReactionMap>> {
        self.reaction_maps.try_get_or(theta, || {
            let pose = self.pose(theta)?;
            self.scene
                .linkage
                .reaction_map(&pose)
                .map_err(|_| self.fail(LinkageSolveError::SingularReactions(theta.to_degrees())))
                .ok()
                .map(Arc::new)
        })
    }

    /// The balance map at θ, or `None` where the linkage does not assemble (recorded).
    fn balance_map(&self, theta: f64) -> Option<Arc<BalanceMap>> {
        self.balance_maps.try_get_or(theta, || {
            let pose = self.pose(theta)?;
            let map = self
                .scene
                .linkage
                .balance_map(&pose, self.scene.moment_about);
            self.kappa.fetch_max(map.kappa.to_bits(), Ordering::Relaxed);
            Some(Arc::new(map))
        })
    }

    /// Fills `out` with joint k's load at θ: (R_x, R_y) of a revolute joint, (N, 0) of a
    /// prismatic one, affine in the counterweights through the reaction map's blocks.
    fn eval_joint(&self, k: usize, theta: f64, out: &mut AffineValue) {
        let Some(map) = self.reaction_map(theta) else {
            return; // zeros: the solve is reported failed
        };
        let rows: &[usize] = match self.joints[k].kind {
            JointKind::Revolute => &[2 * k, 2 * k + 1],
            JointKind::Prismatic => &[2 * k],
        };
        let n = out.n();
        for (r, &row) in rows.iter().enumerate() {
            out.b[r] = map.base[row];
            for (j, cw) in self.scene.counterweights.iter().enumerate() {
                let blk = &map.blocks[cw.link];
                for c in 0..4 {
                    out.a[r * n + mm::var_m(j) + c] = blk[(row, c)];
                }
            }
        }
    }

    /// Fills `out` with field `which` at θ: b the bare linkage, A the counterweights' blocks.
    fn eval(&self, which: usize, theta: f64, out: &mut AffineValue) {
        if which >= JOINT0 {
            return self.eval_joint(which - JOINT0, theta, out);
        }
        let Some(map) = self.balance_map(theta) else {
            return; // zeros: the solve is reported failed
        };
        let n = out.n();
        match which {
            FORCE => {
                out.b = [map.base.force.x, map.base.force.y];
                for (j, cw) in self.scene.counterweights.iter().enumerate() {
                    let blk = &map.blocks[cw.link].force;
                    for c in 0..4 {
                        out.a[mm::var_m(j) + c] = blk[(0, c)];
                        out.a[n + mm::var_m(j) + c] = blk[(1, c)];
                    }
                }
            }
            MOMENT | TORQUE => {
                out.b[0] = if which == MOMENT {
                    map.base.moment
                } else {
                    map.base.torque
                };
                for (j, cw) in self.scene.counterweights.iter().enumerate() {
                    let b = &map.blocks[cw.link];
                    let row = if which == MOMENT { b.moment } else { b.torque };
                    for c in 0..4 {
                        out.a[mm::var_m(j) + c] = row[c];
                    }
                }
            }
            _ => unreachable!("three fields"),
        }
    }

    /// The model's round-off bound on field `which` at (θ, x): ρ·Σ‖block‖‖p‖
    /// ([`crate::families::linkage::model::BalanceMap::error`]).
    fn error(&self, which: usize, theta: f64, x: &[f64]) -> f64 {
        let l = &self.scene.linkage;
        if which >= JOINT0 {
            let Ok(pose) = l.pose(theta) else {
                return f64::INFINITY;
            };
            return l
                .reactions_with_error(&pose, &params_with(self.scene, x))
                .map_or(f64::INFINITY, |(_, e)| e);
        }
        let Some(map) = self.balance_map(theta) else {
            return f64::INFINITY;
        };
        let extra = extras(&self.scene.counterweights, x);
        let (ef, em, et) = map.error(&l.params(), &extra);
        [ef, em, et][which]
    }

    /// The largest dyad conditioning κ met so far.
    pub fn kappa_max(&self) -> f64 {
        f64::from_bits(self.kappa.load(Ordering::Relaxed))
    }

    /// The first failure met, if any.
    pub fn failure(&self) -> Option<LinkageSolveError> {
        self.failure.lock().expect("no panic holds it").clone()
    }
}

/// The counterweights of x as parameter additions (link, p).
pub fn extras(cws: &[CounterweightSpec], x: &[f64]) -> Vec<(usize, Params)> {
    cws.iter()
        .enumerate()
        .map(|(j, cw)| {
            let b = mm::var_m(j);
            (cw.link, Params::new(x[b], x[b + 1], x[b + 2], x[b + 3]))
        })
        .collect()
}

/// A joint's name: the two bodies it joins (`frame–crank`, `crank–coupler`).
pub fn joint_label(j: &Joint, names: &[String]) -> String {
    let first = match j.first {
        Body::Frame => "frame",
        Body::Link(i) => names[i].as_str(),
    };
    format!("{first}–{}", names[j.second])
}

/// The links' parameters with the counterweights of x added.
pub fn params_with(scene: &LinkageScene, x: &[f64]) -> Vec<Params> {
    let mut p = scene.linkage.params();
    if x.len() >= mm::PER_COUNTERWEIGHT * scene.counterweights.len() {
        for (link, q) in extras(&scene.counterweights, x) {
            p[link] += q;
        }
    }
    p
}

/// A joint's load magnitude: |R| of a revolute joint, |N| (the force normal to the slide)
/// of a prismatic one (N).
pub fn joint_load(kind: JointKind, load: [f64; 2]) -> f64 {
    match kind {
        JointKind::Revolute => load[0].hypot(load[1]),
        JointKind::Prismatic => load[0].abs(),
    }
}

/// One joint's peak load over the cycle: a bearing's design load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointPeak {
    /// The peak load (N).
    pub peak: f64,
    /// The crank angle of the peak (rad).
    pub angle: f64,
    /// Bound on |true peak − `peak`| (N): the refinement's bound plus the largest
    /// Newton–Euler round-off bound at the refined maxima
    /// ([`crate::families::linkage::model::Linkage::reactions_with_error`]).
    pub error: f64,
}

/// The peak load of every joint ([`crate::families::linkage::model::Linkage::joints`]) at
/// design x (all zeros: the bare linkage): the Newton–Euler loads on `scan_samples` angles,
/// every local maximum that can be the peak refined to `peak_xtol`.
pub fn joint_peaks(
    scene: &LinkageScene,
    x: &[f64],
    s: &Settings,
) -> Result<Vec<JointPeak>, LinkageSolveError> {
    let l = &scene.linkage;
    let joints = l.joints();
    let p = params_with(scene, x);
    let w = l.omega();
    let loads = |theta: f64| loads_at(l, &joints, &p, [theta, w, 0.0]);
    let n = s.scan_samples;
    let h = std::f64::consts::TAU / n as f64;
    let mut ys = vec![Vec::with_capacity(n); joints.len()];
    for theta in (0..n).map(|k| k as f64 * h) {
        for (y, v) in ys.iter_mut().zip(loads(theta)?) {
            y.push(v);
        }
    }
    let mut out = Vec::with_capacity(joints.len());
    for (k, y) in ys.iter().enumerate() {
        let f = |theta: f64| loads(theta).map_or(f64::NAN, |v| v[k]);
        let pk = periodic_peak_sampled(y, f, Some(s.peak_xtol), Refine::PeakOnly)
            .map_err(|_| LinkageSolveError::SingularReactions(f64::NAN))?;
        let mut roundoff: f64 = 0.0;
        for m in &pk.maxima {
            roundoff = roundoff.max(roundoff_at(l, &p, [m.x, w, 0.0])?);
        }
        if !pk.peak.fx.is_finite() {
            return Err(LinkageSolveError::SingularReactions(pk.peak.x.to_degrees()));
        }
        out.push(JointPeak {
            peak: pk.peak.fx,
            angle: pk.peak.x,
            error: pk.error + roundoff,
        });
    }
    Ok(out)
}

/// The peak load of every joint at design x in a periodic steady state at real speed: the
/// Newton–Euler loads at the steady state's nodes with each node's ω and α
/// ([`crate::families::linkage::model::Linkage::reactions_at`]), each joint's peak with the
/// steady state's bound ([`SteadyState::inertial_peak`]: the peak node's neighbour difference
/// and the speeds' error) plus the round-off bound of the reactions at the peak node.
pub fn steady_joint_peaks(
    scene: &LinkageScene,
    x: &[f64],
    st: &SteadyState,
) -> Result<Vec<JointPeak>, LinkageSolveError> {
    let l = &scene.linkage;
    let joints = l.joints();
    let p = params_with(scene, x);
    // The nodes in parallel (a pose and a Newton–Euler solve each), collected in order: the
    // same loads, and the first failing node's error, whatever the threads.
    let rows = ordered(
        st.curve
            .par_iter()
            .with_min_len(64)
            .map(|&node| loads_at(l, &joints, &p, node)),
    )?;
    let mut ys = vec![Vec::with_capacity(st.curve.len()); joints.len()];
    for row in rows {
        for (y, v) in ys.iter_mut().zip(row) {
            y.push(v);
        }
    }
    ys.iter()
        .map(|y| {
            let pk = st.inertial_peak(y);
            Ok(JointPeak {
                peak: pk.peak,
                angle: pk.angle,
                error: pk.error + roundoff_at(l, &p, st.curve[pk.node])?,
            })
        })
        .collect()
}

/// Every joint's load ([`joint_load`]) at crank angle θ with the crank at speed ω and
/// acceleration α, `[θ, ω, α]` (the nominal speed and α = 0 at constant speed).
fn loads_at(
    l: &Linkage,
    joints: &[Joint],
    p: &[Params],
    [theta, w, a]: [f64; 3],
) -> Result<Vec<f64>, LinkageSolveError> {
    let r = l
        .reactions_at(&pose_at(l, theta)?, p, w, a)
        .map_err(|_| LinkageSolveError::SingularReactions(theta.to_degrees()))?;
    Ok(joints
        .iter()
        .zip(&r.loads)
        .map(|(j, ld)| joint_load(j.kind, *ld))
        .collect())
}

/// The round-off bound of the Newton–Euler solve at `[θ, ω, α]`
/// ([`crate::families::linkage::model::Linkage::reactions_with_error_at`]).
fn roundoff_at(
    l: &Linkage,
    p: &[Params],
    [theta, w, a]: [f64; 3],
) -> Result<f64, LinkageSolveError> {
    let (_, e) = l
        .reactions_with_error_at(&pose_at(l, theta)?, p, w, a)
        .map_err(|_| LinkageSolveError::SingularReactions(theta.to_degrees()))?;
    Ok(e)
}

/// The linkage's pose at θ, or where it does not assemble.
fn pose_at(l: &Linkage, theta: f64) -> Result<Pose, LinkageSolveError> {
    l.pose(theta)
        .map_err(|e| LinkageSolveError::NoAssembly(theta.to_degrees(), e.dyad))
}

/// The engine's limits of one counterweight: mass up to its maximum, the body within
/// `radius` of the joint (|u| ≤ m r, I ≤ m r²), the sector.
pub fn limits_of(cw: &CounterweightSpec) -> CounterweightLimits {
    let (_, hi) = cw.mass.bounds();
    let plate = cw.areal_density();
    // A plate holds at most σπr², the whole disc.
    let hi = plate.map_or(hi, |s| {
        hi.min(s * std::f64::consts::PI * cw.radius * cw.radius)
    });
    CounterweightLimits {
        sector: cw.sector,
        plate,
        ..CounterweightLimits::new(hi, cw.radius)
    }
}

/// A lower or fixed mass, and a given centroid and inertia, as linear rows.
fn mass_rows(cws: &[CounterweightSpec]) -> Vec<LinearConstraint> {
    let mut rows = Vec::new();
    for (j, cw) in cws.iter().enumerate() {
        match cw.mass {
            Var::Fixed(m) => rows.push(LinearConstraint {
                coeffs: vec![(mm::var_m(j), 1.0)],
                relation: Relation::Eq,
                rhs: m,
            }),
            Var::Free { min, .. } if min > 0.0 => rows.push(LinearConstraint {
                coeffs: vec![(mm::var_m(j), -1.0)],
                relation: Relation::Le,
                rhs: -min,
            }),
            Var::Free { .. } => {}
        }
        // A given centroid fixes u = m c; a given inertia I about the joint = I_c + m |c|².
        if let (Var::Fixed(m), Some((c, ic))) = (cw.mass, cw.given) {
            let eq = |var: usize, rhs: f64| LinearConstraint {
                coeffs: vec![(var, 1.0)],
                relation: Relation::Eq,
                rhs,
            };
            rows.push(eq(mm::PER_COUNTERWEIGHT * j + 1, m * c.x));
            rows.push(eq(mm::PER_COUNTERWEIGHT * j + 2, m * c.y));
            if let Some(ic) = ic {
                rows.push(eq(mm::PER_COUNTERWEIGHT * j + 3, ic + m * c.norm_squared()));
            }
        }
    }
    rows
}

/// Full force balance as linear equalities on x, or the relative residual by which the
/// counterweights miss it. Rows: the right singular vectors of the stacked force blocks at
/// [`BALANCE_ANGLES`] angles with σ > 1e-10·σ_max; right-hand side from the least-squares
/// solution (so the rows are consistent).
pub fn force_balance_rows(fields: &SceneFields, n: usize) -> Result<Vec<LinearConstraint>, f64> {
    let k = BALANCE_ANGLES;
    let mut a = DMatrix::<f64>::zeros(2 * k, n);
    let mut b = DVector::<f64>::zeros(2 * k);
    for i in 0..k {
        let theta = std::f64::consts::TAU * i as f64 / k as f64;
        let mut v = AffineValue::zeros(n);
        fields.eval(FORCE, theta, &mut v);
        for r in 0..2 {
            b[2 * i + r] = -v.b[r];
            for c in 0..n {
                a[(2 * i + r, c)] = v.row(r)[c];
            }
        }
    }
    // Column scaling (m, u and I differ by the machine's length scale).
    let scale: Vec<f64> = (0..n)
        .map(|c| a.column(c).norm().max(f64::MIN_POSITIVE))
        .collect();
    let mut a_s = a.clone();
    for (c, s) in scale.iter().enumerate() {
        a_s.column_mut(c).scale_mut(1.0 / s);
    }
    let svd = a_s.clone().svd(true, true);
    let smax = svd.singular_values.max();
    let tol = 1e-10 * smax;
    let y = svd
        .solve(&b, tol)
        .expect("the SVD was computed with U and V");
    let resid = (&a_s * &y - &b).norm() / b.norm().max(f64::MIN_POSITIVE);
    if b.norm() == 0.0 {
        return Ok(Vec::new());
    }
    if resid > BALANCE_RESIDUAL_TOL {
        return Err(resid);
    }
    let vt = svd.v_t.expect("computed");
    let mut rows = Vec::new();
    for (i, s) in svd.singular_values.iter().enumerate() {
        if *s <= tol {
            continue;
        }
        let row = vt.row(i);
        // Row in scaled variables y = scale ⊙ x (A x = A_s y): row·y = d, i.e.
        // Σ row_c s_c x_c = d.
        let rhs = row.dot(&y.transpose());
        rows.push(LinearConstraint {
            coeffs: (0..n)
                .filter(|&c| row[c] != 0.0)
                .map(|c| (c, row[c] * scale[c]))
                .collect(),
            relation: Relation::Eq,
            rhs,
        });
    }
    Ok(rows)
}

type Eval<'a> = Box<dyn Fn(f64, &mut AffineValue) + Sync + 'a>;
type Err<'a> = Box<dyn Fn(f64, &[f64]) -> f64 + Sync + 'a>;

/// The three engine fields of `fields`: force (2-D), moment, torque; `label` follows each
/// field's name (a scenario's, empty for the nominal scene).
pub fn field_objects<'a>(
    fields: &'a SceneFields<'a>,
    label: &str,
) -> (
    FnField<Eval<'a>, Err<'a>>,
    FnField<Eval<'a>, Err<'a>>,
    FnField<Eval<'a>, Err<'a>>,
) {
    let make = |which: usize, name: &str, dim: usize| {
        let e: Eval<'a> = Box::new(move |th, out| fields.eval(which, th, out));
        let r: Err<'a> = Box::new(move |th, x| fields.error(which, th, x));
        FnField::new(format!("{name}{label}"), dim, e).with_error(r)
    };
    (
        make(FORCE, "shaking_force", 2),
        make(MOMENT, "shaking_moment", 1),
        make(TORQUE, "input_torque", 1),
    )
}

/// The engine fields of the joint loads (field `JOINT0 + k` is joint k; dimension 2, a
/// prismatic joint's second row 0).
pub fn joint_field_objects<'a>(
    fields: &'a SceneFields<'a>,
    label: &str,
) -> Vec<FnField<Eval<'a>, Err<'a>>> {
    (0..fields.joints.len())
        .map(|k| {
            let which = JOINT0 + k;
            let e: Eval<'a> = Box::new(move |th, out| fields.eval(which, th, out));
            let r: Err<'a> = Box::new(move |th, x| fields.error(which, th, x));
            let name = format!(
                "load of joint {}{label}",
                joint_label(&fields.joints[k], &fields.scene.link_names)
            );
            FnField::new(name, 2, e).with_error(r)
        })
        .collect()
}

/// The engine goal of the file's objective.
pub fn goal(g: Goal, energy: usize) -> mm::Goal {
    match g {
        Goal::PeakForce => mm::Goal::MinPeak(vec![(FORCE, 1.0)]),
        Goal::PeakMoment => mm::Goal::MinPeak(vec![(MOMENT, 1.0)]),
        Goal::PeakTorque => mm::Goal::MinPeak(vec![(TORQUE, 1.0)]),
        Goal::RmsForce => mm::Goal::MinRms(FORCE),
        Goal::RmsMoment => mm::Goal::MinRms(MOMENT),
        Goal::RmsTorque => mm::Goal::MinRms(TORQUE),
        Goal::CounterweightMass => mm::Goal::MinMass,
        // Weighted by 2: ΔE = 2 min_c max|E − c| (`crate::synth::energy`), the field after
        // the joints' (`solve`).
        Goal::EnergyFluctuation => mm::Goal::MinPeak(vec![(energy, 2.0)]),
    }
}

/// What a linkage solve found.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The bare linkage (no counterweight): refined peaks of F, M_O, T with their errors.
    pub bare: Vec<mm::FieldPeak>,
    /// The bare linkage's RMS of F, M_O, T with their quadrature errors.
    pub bare_rms: [(f64, f64); 3],
    /// The design (None without counterweights, or when full balance is out of reach).
    pub design: Option<Solution>,
    /// The design's RMS of F, M_O, T with their quadrature errors.
    pub design_rms: Option<[(f64, f64); 3]>,
    /// With `full_force_balance`: the relative least-squares residual when the counterweights
    /// cannot balance the force.
    pub balance_residual: Option<f64>,
    /// The number of balance equalities used (the rank of the force blocks).
    pub balance_rows: usize,
    /// The Pareto front (peak force against peak moment, or ΔE against peak force), if
    /// asked.
    pub pareto: Option<mm::ParetoFront>,
    /// The front's fields (optimised, limited): engine field indices of `pareto`'s points'
    /// peaks (the energy field's peak is max|E − c| = ΔE/2).
    pub pareto_fields: (usize, usize),
    /// Fields per scenario: with an operating envelope the peaks of vertex v's field k are
    /// at `v * block_len + k` (v = 0 the nominal scene).
    pub block_len: usize,
    /// Largest dyad conditioning κ over the scan.
    pub kappa_max: f64,
    /// Why the objective cannot be moved by a counterweight the scene leaves free, if it
    /// cannot ([`idle_counterweights`]): the result is then `degenerate`.
    pub degenerate: Option<String>,
    /// The two masses where the optimum is not unique and the design is the lightest of the
    /// optimal set ([`Engine::lightest_of_optimum`]).
    pub lighter: Option<mm::Lighter>,
    /// Per counterweight, the plate that is the design's where it has a `thickness`
    /// ([`realise_plates`]).
    pub plates: Vec<Option<Realised>>,
}

/// The engine fields of one scenario, in the order every scenario keeps: force (2-D),
/// moment, torque ([`FORCE`], [`MOMENT`], [`TORQUE`]), the joints' with a joint-load limit
/// ([`JOINT0`]` + k`), then the energy curve with the ΔE goal (with the bound on its offset).
struct Block<'a> {
    fmt: [FnField<Eval<'a>, Err<'a>>; 3],
    joints: Vec<FnField<Eval<'a>, Err<'a>>>,
    energy: Option<(EnergyField, f64)>,
}

impl<'a> Block<'a> {
    /// The fields of `fields` (named with `label`), the energy curve's offset the design
    /// variable `offset` of `n` (`with_energy` false: without the energy curve, which costs
    /// its quadrature).
    fn new(
        fields: &'a SceneFields<'a>,
        label: &str,
        n: usize,
        offset: usize,
        with_energy: bool,
    ) -> Result<Self, LinkageSolveError> {
        let (f, m, t) = field_objects(fields, label);
        let joints = match fields.scene.objective.max_joint_force {
            Some(_) => joint_field_objects(fields, label),
            None => Vec::new(),
        };
        let energy = match with_energy {
            true => energy_field(fields.scene, &t, n, offset)?,
            false => None,
        };
        Ok(Block {
            fmt: [f, m, t],
            joints,
            energy,
        })
    }

    /// The fields, in the block's order; a force, moment or torque not `named` is a zero
    /// field of its dimension ([`mm::Unused`]: never evaluated).
    fn refs(&self, named: [bool; 3]) -> Vec<&dyn mm::AffineField> {
        let fmt = (self.fmt.iter().zip(named)).map(|(f, on)| match (on, f.dim) {
            (true, _) => f as &dyn mm::AffineField,
            (false, 2) => &mm::UNUSED_PLANAR,
            (false, _) => &mm::UNUSED_SCALAR,
        });
        let joints = self.joints.iter().map(|j| j as &dyn mm::AffineField);
        let energy = self.energy.iter().map(|(e, _)| e as &dyn mm::AffineField);
        fmt.chain(joints).chain(energy).collect()
    }
}

/// g and its evaluation error of each (field, θ) of `at` in one scenario block of the
/// scene `s` (its energy curve's offset the design variable `offset`), at the design x
/// (n = x.len()): active maxima's values when their scenario moves (the envelope's
/// sensitivity table). The energy curve, which costs its quadrature, only where asked.
pub fn block_field_values(
    s: &LinkageScene,
    at: &[(usize, f64)],
    offset: usize,
    x: &[f64],
) -> Result<Vec<([f64; 2], f64)>, LinkageSolveError> {
    let fields = SceneFields::new(s);
    let mut block = Block::new(&fields, "", x.len(), offset, false)?;
    if at.iter().any(|&(f, _)| f >= block.refs([true; 3]).len()) {
        block = Block::new(&fields, "", x.len(), offset, true)?;
    }
    let values =
        crate::synth::envelope::field_values(&block.refs([true; 3]), at.iter().copied(), x);
    match fields.failure() {
        Some(e) => Err(e),
        None => Ok(values),
    }
}

/// The scenes of the envelope's blocks after the nominal one (none without an envelope):
/// every vertex in every load case, in
/// [`crate::families::linkage::envelope::LinkageEnvelope::scenarios`]' order.
pub fn vertex_scenes(scene: &LinkageScene) -> Result<Vec<LinkageScene>, LinkageSolveError> {
    let env = &scene.envelope;
    if env.is_empty() {
        return Ok(Vec::new());
    }
    env.scenarios(&scene.linkage)
        .iter()
        .skip(1)
        .map(|s| scene_at_case(scene, s.case, &s.values))
        .collect()
}

/// The scene at the envelope's parameter `values` in the nominal load case, without an
/// envelope of its own.
pub fn scene_at(scene: &LinkageScene, values: &[f64]) -> Result<LinkageScene, LinkageSolveError> {
    scene_at_case(scene, 0, values)
}

/// The scene in load case `case` at the envelope's parameter `values`, without an envelope
/// of its own.
pub fn scene_at_case(
    scene: &LinkageScene,
    case: usize,
    values: &[f64],
) -> Result<LinkageScene, LinkageSolveError> {
    let linkage = scene
        .envelope
        .at_case(&scene.linkage, case, values)
        .map_err(|e| {
            LinkageSolveError::Engine(mm::MinimaxError::Problem {
                what: "the operating envelope".into(),
                message: e.to_string(),
            })
        })?;
    Ok(LinkageScene {
        linkage,
        envelope: Default::default(),
        ..scene.clone()
    })
}

/// The file's peak limits as (field, ε) of one block.
fn peak_limits(o: &Objective, joints: usize) -> Vec<(usize, f64)> {
    [
        (FORCE, o.max_peak_force),
        (MOMENT, o.max_peak_moment),
        (TORQUE, o.max_peak_torque),
    ]
    .into_iter()
    .chain((0..joints).map(|k| (JOINT0 + k, o.max_joint_force)))
    .filter_map(|(k, v)| v.map(|v| (k, v)))
    .collect()
}

/// The goal over `blocks` blocks of `len` fields: the nominal block's goal with every
/// peak's field repeated in each block (the worst case over the scenarios).
/// Whether the goal `g` names field `k`.
fn goal_names(g: &mm::Goal, k: usize) -> bool {
    match g {
        mm::Goal::MinPeak(v) => v.iter().any(|p| p.0 == k),
        mm::Goal::MinRms(f) => *f == k,
        mm::Goal::MinMass => false,
    }
}

fn block_goal(g: mm::Goal, blocks: usize, len: usize) -> mm::Goal {
    match g {
        mm::Goal::MinPeak(v) => mm::Goal::MinPeak(
            (0..blocks)
                .flat_map(|b| v.iter().map(move |&(k, w)| (b * len + k, w)))
                .collect(),
        ),
        other => other,
    }
}

/// What the engine's problem of a scene is built from besides its fields: the full force
/// balance's rows (or the residual that puts it out of reach) and a block's length.
struct Built {
    balance_residual: Option<f64>,
    balance_rows: usize,
    /// Fields per block.
    len: usize,
    /// The energy field's index in a block.
    energy_at: usize,
    /// Design variables.
    n: usize,
}

/// Builds the scene's engine — the nominal scene and every vertex of its envelope, each a
/// block of fields, the goal the worst case over the blocks, every limit in each ([`Block`])
/// — and hands it to `then` with the scene's fields (the nominal's, then the vertices').
/// With `named_only` the force, moment and torque that neither the goal nor a limit names
/// are zero fields ([`Block::refs`]).
fn with_engine<R>(
    scene: &LinkageScene,
    settings: &Settings,
    named_only: bool,
    then: impl FnOnce(&Engine, &Built, &[SceneFields]) -> Result<R, LinkageSolveError>,
) -> Result<R, LinkageSolveError> {
    let vertices = vertex_scenes(scene)?;
    let all: Vec<SceneFields> = std::iter::once(SceneFields::new(scene))
        .chain(vertices.iter().map(SceneFields::new))
        .collect();
    let fields = &all[0];
    let cws = &scene.counterweights;
    let n_cw = mm::PER_COUNTERWEIGHT * cws.len();
    let o = &scene.objective;
    // An analysis has no design variable: one fixed at 0 keeps the engine's problem whole;
    // the ΔE goal has one offset per scenario.
    let energy_goal = o.minimize == Goal::EnergyFluctuation && !cws.is_empty();
    let n = n_cw
        + if cws.is_empty() {
            1
        } else {
            usize::from(energy_goal) * all.len()
        };
    let mut blocks = vec![Block::new(fields, "", n, n_cw, true)?];
    let env = &scene.envelope;
    let scenarios = env.scenarios(&scene.linkage);
    for (k, (f, s)) in all[1..].iter().zip(&scenarios[1..]).enumerate() {
        blocks.push(Block::new(f, &env.label(s), n, n_cw + 1 + k, true)?);
    }
    let mut linear = mass_rows(cws);
    let mut built = Built {
        balance_residual: None,
        balance_rows: 0,
        len: blocks[0].refs([true; 3]).len(),
        energy_at: 3 + blocks[0].joints.len(),
        n: 0,
    };
    if o.full_force_balance && !cws.is_empty() {
        match force_balance_rows(fields, n_cw) {
            Ok(rows) => {
                built.balance_rows = rows.len();
                linear.extend(rows);
            }
            Err(resid) => built.balance_residual = Some(resid),
        }
    }
    let (len, energy_at) = (built.len, built.energy_at);
    let limits = peak_limits(o, blocks[0].joints.len());
    let goal_k = goal(o.minimize, energy_at);
    let named = [FORCE, MOMENT, TORQUE]
        .map(|k| !named_only || goal_names(&goal_k, k) || limits.iter().any(|l| l.0 == k));
    let mut extra = if cws.is_empty() {
        vec![(0.0, 0.0)]
    } else {
        Vec::new()
    };
    extra.extend(
        blocks
            .iter()
            .filter_map(|b| b.energy.as_ref())
            .map(|(_, c)| (-c, *c)),
    );
    let pb = Problem {
        fields: blocks.iter().flat_map(|b| b.refs(named)).collect(),
        counterweights: cws.iter().map(limits_of).collect(),
        extra,
        linear,
        goal: block_goal(goal_k, blocks.len(), len),
        limits: (0..blocks.len())
            .flat_map(|b| limits.iter().map(move |&(k, v)| (b * len + k, v)))
            .collect(),
    };
    built.n = pb.n();
    let engine = Engine::new(&pb, settings)?;
    then(&engine, &built, &all)
}

/// The engine's optimum of the scene's counterweights alone (no baselines, RMS, plates or
/// front): the inner program of a shape search (issue 36), whose candidate needs its
/// objective's peak only — of the force, moment and torque only those the goal and the
/// limits name are fields (the others' peaks are 0: their grids and refinements are not
/// paid). `None` without counterweights or with a full force balance out of reach.
pub fn optimum(
    scene: &LinkageScene,
    settings: &Settings,
) -> Result<Option<Solution>, LinkageSolveError> {
    if scene.counterweights.is_empty() {
        return Ok(None);
    }
    with_engine(scene, settings, true, |engine, built, _| {
        match built.balance_residual {
            Some(_) => Ok(None),
            None => Ok(Some(engine.solve()?)),
        }
    })
}

/// Solves the scene: the bare linkage's peaks, then the counterweights (if any) for the
/// objective under the limits, and the front if asked. With an operating envelope every
/// vertex's scene is a block of fields after the nominal one, the goal is the worst case over
/// the blocks and every limit holds in each ([`with_engine`]).
pub fn solve(scene: &LinkageScene, settings: &Settings) -> Result<Outcome, LinkageSolveError> {
    with_engine(scene, settings, false, |engine, built, all| {
        let cws = &scene.counterweights;
        let o = &scene.objective;
        let energy_at = built.energy_at;
        let zeros = vec![0.0; built.n];
        let bare = engine.peaks(&zeros)?;
        let bare_rms = [0, 1, 2].map(|k| engine.rms(k, &zeros));
        let mut out = Outcome {
            bare,
            bare_rms,
            design: None,
            design_rms: None,
            balance_residual: built.balance_residual,
            balance_rows: built.balance_rows,
            pareto: None,
            pareto_fields: match o.minimize {
                Goal::PeakMoment => (MOMENT, FORCE),
                Goal::EnergyFluctuation => (energy_at, FORCE),
                _ => (FORCE, MOMENT),
            },
            block_len: built.len,
            kappa_max: 1.0,
            degenerate: None,
            lighter: None,
            plates: Vec::new(),
        };
        if !cws.is_empty() && built.balance_residual.is_none() {
            let (first, lighter) = engine.lightest_of_optimum(engine.solve()?)?;
            out.lighter = lighter;
            let (sol, plates) = realise_plates(engine, cws, first)?;
            out.plates = plates;
            if sol.x.iter().all(|v| v.is_finite()) {
                out.design_rms = Some([0, 1, 2].map(|k| engine.rms(k, &sol.x)));
            }
            out.design = Some(sol);
            if o.pareto_points >= 2 {
                let (a, b) = out.pareto_fields;
                out.pareto = Some(engine.pareto_front(a, b, o.pareto_points)?);
            }
        }
        if out.design.is_some() {
            out.degenerate = idle_counterweights(&all[0], scene);
        }
        if let Some(e) = all.iter().find_map(SceneFields::failure) {
            return Err(e);
        }
        out.kappa_max = all.iter().map(SceneFields::kappa_max).fold(1.0, f64::max);
        Ok(out)
    })
}

/// Each plate counterweight (a `thickness`) cut as a concrete plate
/// ([`crate::geom::plate::realise`]: the ring at its centroid, else the lens of its area and
/// centroid). The engine's design meets the plate's necessary conditions; where the plate
/// found has another (m, u, I) the design becomes the plate's, re-certified against the
/// same lower bound ([`Engine::moved`]: `inaccurate` when it no longer meets the
/// tolerance).
fn realise_plates(
    engine: &Engine,
    cws: &[CounterweightSpec],
    sol: Solution,
) -> Result<(Solution, Vec<Option<Realised>>), LinkageSolveError> {
    if !sol.x.iter().all(|v| v.is_finite()) {
        return Ok((sol, vec![None; cws.len()]));
    }
    let mut x = sol.x.clone();
    let mut moved = Vec::new();
    let plates: Vec<Option<Realised>> = cws
        .iter()
        .enumerate()
        .map(|(j, cw)| {
            let sigma = cw.areal_density()?;
            let d = sol.counterweight(j);
            let u = P2::new(d.first_moment[0], d.first_moment[1]);
            let r = crate::geom::plate::realise(d.mass, u, d.inertia, sigma, cw.radius);
            let (m_s, u_s) = (sigma * std::f64::consts::PI * cw.radius.powi(2), cw.radius);
            let off = ((r.mass - d.mass) / m_s).abs()
                + (r.first_moment - u).norm() / (m_s * u_s)
                + ((r.inertia - d.inertia) / (m_s * u_s * u_s)).abs();
            if off > 1e-9 {
                let at = mm::var_m(j);
                x[at] = r.mass;
                x[at + 1] = r.first_moment.x;
                x[at + 2] = r.first_moment.y;
                x[at + 3] = r.inertia;
                moved.push(cw.link_name.clone());
            }
            Some(r)
        })
        .collect();
    if moved.is_empty() {
        return Ok((sol, plates));
    }
    let why = format!(
        "the plate cut for the counterweight on {} has another mass, first moment or inertia than the optimum of the plate's necessary conditions (no ring or lens has those)",
        moved.join(", ")
    );
    Ok((engine.moved(&sol, &x, &why)?, plates))
}

/// With `minimize = "energy-fluctuation"` and counterweights: the energy curve of the input
/// torque field `t` as an engine field (`crate::synth::energy`) of `n` design variables whose
/// offset c is the variable `offset`, with the bound on |c|. Each column's
/// largest value is bounded by the counterweight's limits: m ≤ m_max, |u| ≤ m_max r,
/// I ≤ m_max r².
fn energy_field(
    scene: &LinkageScene,
    t: &dyn mm::AffineField,
    n: usize,
    offset: usize,
) -> Result<Option<(EnergyField, f64)>, LinkageSolveError> {
    let cws = &scene.counterweights;
    if scene.objective.minimize != Goal::EnergyFluctuation || cws.is_empty() {
        return Ok(None);
    }
    let e = EnergyField::new(t, n, offset, &DriveSettings::default()).map_err(|e| {
        LinkageSolveError::Engine(mm::MinimaxError::Problem {
            what: "the energy curve".into(),
            message: e.to_string(),
        })
    })?;
    let x_max = |j: usize| {
        let cw = &cws[j / mm::PER_COUNTERWEIGHT];
        let (m, r) = (cw.mass.bounds().1, cw.radius);
        match j % mm::PER_COUNTERWEIGHT {
            0 => m,
            3 => m * r * r,
            _ => m * r,
        }
    };
    let bound = e.offset_bound(x_max);
    Ok(Some((e, bound)))
}

/// Angles at which [`idle_counterweights`] looks at the blocks.
const IDLE_ANGLES: usize = 64;

/// The counterweights that cannot move the objective, in words, if any: counterweight j on
/// link L enters a field (F, M_O or T; their RMS alike) only through the block of L, A_L(θ)
/// (`Blocks`), so where that block is zero at every angle — relative to the largest block of
/// the field, 10⁻⁹ — for the objective's field and for every field a constraint limits (the
/// full balance limits the force; a joint-load limit every link), its (m, u, I) are arbitrary
/// at the optimum and the problem is degenerate as posed (a crank counterweight turning at
/// constant speed without gravity adds no drive torque, and none about its own pivot). The
/// lightest-counterweight goal depends on every free mass and is never idle.
fn idle_counterweights(fields: &SceneFields, scene: &LinkageScene) -> Option<String> {
    let o = &scene.objective;
    let (field, name) = match o.minimize {
        Goal::PeakForce | Goal::RmsForce => (FORCE, "shaking force"),
        Goal::PeakMoment | Goal::RmsMoment => (MOMENT, "shaking moment"),
        Goal::PeakTorque | Goal::RmsTorque => (TORQUE, "drive torque"),
        // ΔE moves only through the torque's blocks.
        Goal::EnergyFluctuation => (TORQUE, "energy fluctuation"),
        Goal::CounterweightMass => return None,
    };
    if o.max_joint_force.is_some() {
        return None;
    }
    let constrained = [
        (FORCE, o.max_peak_force.is_some() || o.full_force_balance),
        (MOMENT, o.max_peak_moment.is_some()),
        (TORQUE, o.max_peak_torque.is_some()),
    ];
    let entered: Vec<usize> = constrained
        .iter()
        .filter(|&&(f, on)| on || f == field)
        .map(|&(f, _)| f)
        .collect();
    let links = scene.link_names.len();
    // norms[f][link]: the largest block of field f over the angles.
    let mut norms = [vec![0.0_f64; links], vec![0.0; links], vec![0.0; links]];
    for k in 0..IDLE_ANGLES {
        let theta = std::f64::consts::TAU * k as f64 / IDLE_ANGLES as f64;
        let Some(map) = fields.balance_map(theta) else {
            continue;
        };
        for (i, b) in map.blocks.iter().enumerate() {
            let v = [b.force.norm(), b.moment.norm(), b.torque.norm()];
            for f in 0..3 {
                norms[f][i] = norms[f][i].max(v[f]);
            }
        }
    }
    let idle_in = |f: usize, link: usize| {
        let scale = norms[f].iter().cloned().fold(0.0, f64::max);
        norms[f][link] <= 1e-9 * scale
    };
    let idle: Vec<&str> = scene
        .counterweights
        .iter()
        .filter(|c| entered.iter().all(|&f| idle_in(f, c.link)))
        .map(|c| c.link_name.as_str())
        .collect();
    (!idle.is_empty()).then(|| {
        format!(
            "the objective, the {name}, does not depend on the counterweight on {}: at constant \
             speed its mass, first moment and inertia add nothing to the {name} at any angle, so \
             any value of it is equally 'optimal' and the one shown is arbitrary (remove it, or \
             minimise a field it enters)",
            idle.join(", ")
        )
    })
}
