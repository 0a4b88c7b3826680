//! The joint design of the crank counterweight and the balancers (or a moment or a
//! main-bearing limit) by the certified affine minimax of [`crate::synth::minimax`].

use super::fields::{force0, force0_at, moment0, torque0};
use super::outcome::Optimum;
use super::realise::unbalance_bounds;
use super::round_off::{joint_load_round_off, round_off_bounds};
use super::scene::{Objective, Scene, SolveError};
use crate::dynamics::DriveSettings;
use crate::families::slider_crank::model::{weight_torque_cs, State};
use crate::geom::P2;
use crate::synth::counterweight::Status;
use crate::synth::energy::EnergyField;
use crate::synth::envelope::{
    field_values, multipliers_with, needed_scenarios, scenario_sensitivities, Sensitivity,
};
use crate::synth::minimax::{
    self as mm, AffineField, AffineValue, FnField, UNUSED_PLANAR, UNUSED_SCALAR,
};
use crate::synth::Var;

/// The joint design of the crank counterweight U and the balancers' unbalances B_n by the
/// certified affine minimax of [`crate::synth::minimax`]: every figure is affine in
/// x = (U; B_1; …), so the columns of the balancers are added to those of U and the same
/// cone program and exchange loop certify the joint optimum.
///
/// Variables: each unbalance is a 2-vector held as the first moment of one of the engine's
/// counterweights (m, u, I) with m_max = 1 and r_max = ρ = its bound, so |u| ≤ bound is the
/// engine's own cone (m and I enter no field). Fields (SI): 0 the shaking force (N),
/// 1 the shaking moment about O (N·m), 2 the drive torque (N·m), 3 the main bearing load
/// without the counterweight's weight (N).
///
/// Bounds: where the scene leaves |U| or |B_n| unbounded, the Fourier coefficients of the
/// force z = F_x + iF_y bound them at any design whose peak (or RMS) force is at most K:
/// z = z₀ + U e^{iφ} + Σ n²(B_n e^{inφ} + B̄_n e^{−inφ})/2, and |c_k(z)| ≤ max|z| (≤ RMS for
/// the RMS), so n²|B_n|/2 ≤ K + P₀ and |U| ≤ 2(K + P₀), P₀ the peak of z₀ (taken as 1.5 ×
/// its sampled maximum). K is the force limit, or P₀ for a force objective (reached by the
/// design 0). Where the other limits exclude the design 0 the optimum's force may exceed P₀,
/// so a design on an automatic bound is reported `inaccurate`; one inside them all is the
/// unbounded problem's optimum too (a convex problem: a local optimum is global).
///
/// With an operating envelope (`scene.envelope`) every figure is a field per scenario (the
/// nominal scene and each vertex of the envelope's box), the objective their weighted
/// minimax and every limit imposed on each: the worst case over the vertices, one cone
/// program ([`super::envelope`]).
pub(super) fn optimise_joint(
    scene: &Scene,
    objective: Objective,
    max_force: Option<f64>,
    max_torque: Option<f64>,
) -> Result<Optimum, SolveError> {
    let nb = scene.balancers.len();
    // The fields the goal or a limit names; only these reach the engine (it scans every
    // field on its grid: the main bearing's Newton–Euler loads are not free).
    let used = [
        matches!(objective, Objective::MinPeakForce | Objective::MinRmsForce)
            || max_force.is_some(),
        objective == Objective::MinPeakMoment || scene.max_shaking_moment.is_some(),
        objective == Objective::MinPeakTorque || max_torque.is_some(),
        scene.load_limits.main_bearing.is_some(),
    ];
    let energy = objective == Objective::MinEnergyFluctuation;
    let (scenes, _, keep) = scenarios(scene, used, energy);
    let zeros_owned = balancer_free(&scenes, nb);
    let zeros: &[Scene] = if nb == 0 { &scenes } else { &zeros_owned };
    let (grids, grid_of) = StateGrid::shared(&scenes, &keep, minimax_settings(scene).scan_samples);
    let jss: Vec<JointScene> = scenes
        .iter()
        .zip(zeros)
        .zip(&grid_of)
        .map(|((s, z), g)| JointScene::new(s, z, nb).with_grid(g.map(|g| &grids[g])))
        .collect();
    let p0 = || jss.iter().map(JointScene::p0).fold(0.0, f64::max);
    let bounds = jss[0].bounds(objective, max_force, p0)?;
    // ΔE = 2 min_c max|E − c|: one offset c per scenario the engine sees, the extra
    // variables (`synth::energy`).
    let offset0 = mm::PER_COUNTERWEIGHT * (1 + nb);
    let n = offset0 + if energy { keep.len() } else { 0 };
    let sets = keep
        .iter()
        .enumerate()
        .map(|(i, &k)| jss[k].fields(used, energy.then_some((n, offset0 + i))))
        .collect::<Result<Vec<_>, _>>()?;
    let extra = sets
        .iter()
        .filter_map(|f| f.energy.as_ref())
        .map(|e| {
            let c = e.offset_bound(|j| bounds.var_bound(j));
            (-c, c)
        })
        .collect();
    // Only the fields the goal or a limit names go to the engine (its scan grids and the
    // certificate's scans are most of an envelope's cost): `kinds` per scenario, in order.
    let kinds: Vec<usize> = [FORCE, MOMENT, TORQUE, BEARING]
        .into_iter()
        .filter(|&k| used[k])
        .chain(energy.then_some(ENERGY))
        .collect();
    let stride = kinds.len();
    let at = |kind: usize| {
        kinds
            .iter()
            .position(|&k| k == kind)
            .expect("a named field")
    };
    let every = |kind: usize, w: f64| {
        let p = at(kind);
        (0..sets.len()).map(move |k| (k * stride + p, w))
    };
    let goal = match objective {
        Objective::MinEnergyFluctuation => mm::Goal::MinPeak(every(ENERGY, 2.0).collect()),
        Objective::MinPeakForce => mm::Goal::MinPeak(every(FORCE, 1.0).collect()),
        Objective::MinRmsForce if jss.len() == 1 => mm::Goal::MinRms(at(FORCE)),
        Objective::MinPeakTorque => mm::Goal::MinPeak(every(TORQUE, 1.0).collect()),
        Objective::MinPeakMoment => mm::Goal::MinPeak(every(MOMENT, 1.0).collect()),
        Objective::MinRmsForce | Objective::MinMass | Objective::MinRadius => {
            return Err(SolveError::Numeric(
                "minimising the RMS force, or the counterweight's mass or radius, is not available with balancers, moment or main-bearing limits (or the RMS over an operating envelope)".into(),
            ))
        }
    };
    let mut limits = Vec::new();
    for (f, lim) in [
        (FORCE, max_force),
        (TORQUE, max_torque),
        (MOMENT, scene.max_shaking_moment),
        (BEARING, scene.load_limits.main_bearing),
    ] {
        if let Some(l) = lim {
            limits.extend(every(f, l));
        }
    }
    let pb = mm::Problem {
        fields: sets.iter().flat_map(|s| s.select(&kinds)).collect(),
        counterweights: bounds.limits(),
        extra,
        linear: Vec::new(),
        goal,
        limits,
    };
    let num = |e: mm::MinimaxError| SolveError::Numeric(e.to_string());
    let engine = mm::Engine::new(&pb, &minimax_settings(scene)).map_err(num)?;
    let mut sol = engine.solve().map_err(num)?;
    // The multipliers' fields renumbered as every scenario's block (the sensitivity table's).
    for m in &mut sol.multipliers {
        m.field = keep[m.field / stride] * stride + m.field % stride;
    }
    let mut optimum = jss[0].optimum(&sol, &bounds)?;
    if jss.len() > 1 {
        optimum.duals = Some(EnvelopeDuals {
            multipliers: sol.multipliers.clone(),
            status: sol.status,
            x: sol.x.clone(),
            kinds: kinds.clone(),
            energy: energy.then_some((n, offset0)),
            used,
        });
    }
    if let Some(e) = sets[0].energy.as_ref() {
        optimum.method = format!(
            "least energy fluctuation ΔE = 2 min_c max_φ |E(φ) − c|, E = ∫₀^φ (T − T̄) dφ affine in the design (per-column trigonometric interpolants on {} samples, synth::energy); {}",
            e.samples(),
            optimum.method
        );
    }
    if jss.len() > 1 {
        optimum.method = format!(
            "worst case over the operating envelope: the nominal scene and the {} vertices of its box, every figure a field per scenario ({} of them in the program, the others dominated exactly: synth::envelope::needed_scenarios); {}",
            jss.len() - 1,
            keep.len(),
            optimum.method
        );
    }
    Ok(optimum)
}

/// What an envelope solve's sensitivity table is computed from ([`sensitivity_table`]):
/// the optimum's multipliers, each on its field in every scenario's block, the design, and
/// how the program was built.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvelopeDuals {
    multipliers: Vec<mm::Multiplier>,
    status: Status,
    x: Vec<f64>,
    /// The engine's fields per scenario ([`FORCE`] … [`ENERGY`]), in order.
    kinds: Vec<usize>,
    /// For a ΔE design: (the variables, the first energy offset's index).
    energy: Option<(usize, usize)>,
    /// The fields the problem names (the multipliers are on no others).
    used: [bool; 4],
}

/// The scenes with their balancers at 0 (empty without balancers: each scene is then its
/// own balancer-free copy, not cloned).
fn balancer_free(scenes: &[Scene], nb: usize) -> Vec<Scene> {
    match nb {
        0 => Vec::new(),
        _ => scenes
            .iter()
            .map(|s| s.with_balancers(&vec![[0.0; 2]; nb]))
            .collect(),
    }
}

/// The scenes of a joint design — the scene alone, or the nominal scene and every vertex of
/// its envelope — with their parameters' values and the indices of those the program needs
/// ([`needed_scenarios`]: the shaking force and moment are homogeneous in ω², the torque,
/// the bearing load and the energy curve carry weights and process loads).
fn scenarios(
    scene: &Scene,
    used: [bool; 4],
    energy: bool,
) -> (Vec<Scene>, Vec<Vec<f64>>, Vec<usize>) {
    if scene.envelope.is_empty() {
        return (vec![scene.clone()], vec![Vec::new()], vec![0]);
    }
    let env = &scene.envelope;
    let all = env.scenarios(scene);
    let homogeneous = !(used[TORQUE] || used[BEARING] || energy);
    let keep = needed_scenarios(
        &env.ranges(),
        &all[0].values,
        env.first_length(),
        env.speed.is_some(),
        homogeneous,
    );
    let (values, scenes) = all.into_iter().map(|s| (s.values, s.scene)).unzip();
    (scenes, values, keep)
}

/// One scenario's fields, in the engine's order within its stride: the force, the moment,
/// the torque, the main bearing load and, for a ΔE design, the energy curve.
struct FieldSet<'a> {
    force: Option<Box<dyn AffineField + 'a>>,
    moment: Option<Box<dyn AffineField + 'a>>,
    torque: Option<Box<dyn AffineField + 'a>>,
    bearing: Option<Box<dyn AffineField + 'a>>,
    energy: Option<EnergyField>,
}

impl FieldSet<'_> {
    /// The fields in order.
    fn all(&self) -> Vec<&dyn AffineField> {
        let mut v: Vec<&dyn AffineField> = vec![
            self.force.as_deref().unwrap_or(&UNUSED_PLANAR),
            self.moment.as_deref().unwrap_or(&UNUSED_SCALAR),
            self.torque.as_deref().unwrap_or(&UNUSED_SCALAR),
            self.bearing.as_deref().unwrap_or(&UNUSED_PLANAR),
        ];
        if let Some(e) = &self.energy {
            v.push(e);
        }
        v
    }

    /// The fields of `kinds` (indices into [`FieldSet::all`]), in that order.
    fn select(&self, kinds: &[usize]) -> Vec<&dyn AffineField> {
        let all = self.all();
        kinds.iter().map(|&k| all[k]).collect()
    }
}

/// The minimax engine's fields, by index: the shaking force (N).
const FORCE: usize = 0;
/// The shaking moment about O (N·m).
const MOMENT: usize = 1;
/// The drive torque (N·m).
const TORQUE: usize = 2;
/// The main bearing load without the counterweight's weight (N).
const BEARING: usize = 3;
/// The energy curve less its offset, E(φ) − c (J; with the energy-fluctuation objective).
const ENERGY: usize = 4;

/// The scene of a joint design with what its fields share: the scene with the balancers at
/// 0 (`zero`: the design-independent parts b(φ)), ω², the gravity g, the balancer count and
/// the mechanism's states on the engine's scan grid (shared by the scenarios of the same
/// kinematics).
struct JointScene<'a> {
    scene: &'a Scene,
    zero: &'a Scene,
    w2: f64,
    g: P2,
    nb: usize,
    grid: Option<&'a StateGrid>,
    /// The last design's [`round_off_bounds`] (the design, the bounds): the fields' error
    /// callbacks ask for them at every maximum and sampled angle of one design, and they
    /// do not depend on the angle.
    round_off_memo: std::sync::Mutex<Option<(Vec<f64>, [f64; 3])>>,
}

/// The mechanism's states at the engine's scan angles θ_k = 2πk/N
/// ([`crate::synth::exchange::uniform_angles`]): every field of a scenario, and every
/// scenario of an envelope whose speed and masses alone differ, is scanned at those angles,
/// and the kinematics ([`crate::families::slider_crank::model::SliderCrank::state`], a loop
/// closure with its square root and sine) are the same for all of them.
struct StateGrid {
    states: Vec<State>,
    /// N/(2π): a grid angle's index per radian (a product, not a division, per lookup:
    /// every field of every scenario looks its states up here).
    per_radian: f64,
}

impl StateGrid {
    /// The grids of the scenes `keep` names, one per distinct kinematics
    /// ([`SliderCrank::same_kinematics`]), and each scene's grid (`None`: not kept).
    ///
    /// [`SliderCrank::same_kinematics`]: crate::families::slider_crank::model::SliderCrank::same_kinematics
    fn shared(scenes: &[Scene], keep: &[usize], n: usize) -> (Vec<StateGrid>, Vec<Option<usize>>) {
        let mut owners: Vec<usize> = Vec::new();
        let mut grid_of = vec![None; scenes.len()];
        for &k in keep {
            let mech = &scenes[k].mech;
            let same = owners
                .iter()
                .position(|&o| scenes[o].mech.same_kinematics(mech));
            grid_of[k] = Some(same.unwrap_or_else(|| {
                owners.push(k);
                owners.len() - 1
            }));
        }
        let grids = owners
            .iter()
            .map(|&o| StateGrid {
                states: crate::synth::exchange::uniform_angles(n)
                    .into_iter()
                    .map(|phi| scenes[o].mech.state(phi).expect("assembly checked"))
                    .collect(),
                per_radian: n as f64 / std::f64::consts::TAU,
            })
            .collect();
        (grids, grid_of)
    }

    /// The state at φ when φ is one of the grid's angles (bit for bit): the nearest grid
    /// index by a truncating cast (a negative φ casts to 0, whose angle then differs), the
    /// angle's bits checked.
    fn get(&self, phi: f64) -> Option<&State> {
        let k = (phi * self.per_radian + 0.5) as usize;
        let s = self.states.get(k)?;
        (s.phi.to_bits() == phi.to_bits()).then_some(s)
    }
}

/// The bounds on the design's unbalances (kg·m): the scene's |U| range, the automatic
/// Fourier bound on |U| and the bound on |U| and each |B_n| used, with the peak-force
/// scale K + P₀ the automatic bounds come from.
struct JointBounds {
    u_lo: f64,
    u_hi: f64,
    u_auto: f64,
    u_max: f64,
    b_max: Vec<f64>,
    /// K + P₀ (N): the force scale of the automatic bounds.
    k_p0: f64,
    /// ω² (rad²/s²).
    w2: f64,
    /// U's angle range when not the full circle.
    sector: Option<(f64, f64)>,
}

impl JointBounds {
    /// The automatic bound on |B_n| of order `n`: 2(K + P₀)/(ω² n²).
    fn auto(&self, n: f64) -> f64 {
        2.0 * self.k_p0 / (self.w2 * n * n)
    }

    /// The bound on |x_j| of the engine's variable `j`: |U| or |B_n| for their components,
    /// 0 for the masses and inertias (they enter no field).
    fn var_bound(&self, j: usize) -> f64 {
        let (cw, k) = (j / mm::PER_COUNTERWEIGHT, j % mm::PER_COUNTERWEIGHT);
        match (cw, k) {
            (_, 0 | 3) => 0.0,
            (0, _) => self.u_max,
            (c, _) => self.b_max.get(c - 1).copied().unwrap_or(f64::INFINITY),
        }
    }

    /// The engine's counterweights: U (in its sector) and the balancers, each with
    /// m_max = 1 and r_max = its bound.
    fn limits(&self) -> Vec<mm::CounterweightLimits> {
        let limits_of = |bound: f64| mm::CounterweightLimits {
            sector: None,
            ..mm::CounterweightLimits::new(1.0, bound)
        };
        let mut cws = vec![mm::CounterweightLimits {
            sector: self.sector,
            ..limits_of(self.u_max)
        }];
        cws.extend(self.b_max.iter().map(|&b| limits_of(b)));
        cws
    }
}

impl<'a> JointScene<'a> {
    /// The mechanism's state at φ (assembly was checked for the whole revolution).
    fn state(&self, phi: f64) -> State {
        match self.grid.and_then(|g| g.get(phi)) {
            Some(s) => *s,
            None => self.scene.mech.state(phi).expect("assembly checked"),
        }
    }

    /// (cos φ, sin φ) and [`force0`] at φ: from the shared state on the scan grid, else by
    /// the force-only evaluation ([`force0_at`], the same numbers at about two thirds of the
    /// cost of a whole state: the refinements, the polish and the certificate ask for
    /// angles off the grid).
    fn force0(&self, phi: f64) -> ([f64; 2], P2) {
        match self.grid.and_then(|g| g.get(phi)) {
            Some(s) => (s.cs, force0(self.zero, s)),
            None => force0_at(self.zero, phi),
        }
    }

    /// The scenario with the states `grid` (of its kinematics) on the scan grid.
    fn with_grid(self, grid: Option<&'a StateGrid>) -> Self {
        JointScene { grid, ..self }
    }

    /// The scenario of `scene` with its balancers at 0 in `zero`.
    fn new(scene: &'a Scene, zero: &'a Scene, nb: usize) -> Self {
        JointScene {
            scene,
            zero,
            w2: scene.omega * scene.omega,
            g: scene.loads.gravity,
            nb,
            grid: None,
            round_off_memo: std::sync::Mutex::new(None),
        }
    }

    /// P₀, the peak of the force without design: 1.5 × the largest of ω²|f₀(φₖ)| on 720
    /// angles (sampled, with margin).
    fn p0(&self) -> f64 {
        1.5 * (0..720)
            .map(|k| {
                let phi = k as f64 * std::f64::consts::TAU / 720.0;
                force0(self.zero, &self.state(phi)).norm() * self.w2
            })
            .fold(0.0, f64::max)
    }

    /// The scenario's fields; with `energy` = (n, the offset's index) also its energy curve
    /// over n variables.
    /// `used` says which of the force, moment, torque and bearing fields the problem names
    /// (the others are zero fields of the same dimension).
    fn fields(
        &self,
        used: [bool; 4],
        energy: Option<(usize, usize)>,
    ) -> Result<FieldSet<'_>, SolveError> {
        let energy = match energy {
            Some((n, offset)) => Some(
                EnergyField::new(&self.torque_field(), n, offset, &DriveSettings::default())
                    .map_err(|e| SolveError::Numeric(format!("the energy curve: {e}")))?,
            ),
            None => None,
        };
        fn keep<'b>(on: bool, f: impl AffineField + 'b) -> Option<Box<dyn AffineField + 'b>> {
            on.then(|| Box::new(f) as Box<dyn AffineField + 'b>)
        }
        Ok(FieldSet {
            force: keep(used[0], self.force_field()),
            moment: keep(used[1], self.moment_field()),
            torque: keep(used[2], self.torque_field()),
            bearing: keep(used[3], self.bearing_field()),
            energy,
        })
    }

    /// The bounds of the design (see [`optimise_joint`]) from P₀ (`p0`, the largest over the
    /// scenarios, sampled only where a bound needs it): K the force limit or P₀ (the least of
    /// them for a force objective),
    /// |U| ≤ 2(K + P₀)/ω² · 2 and n²|B_n| ≤ 2(K + P₀)/ω², each capped by the scene's own
    /// bound.
    fn bounds(
        &self,
        objective: Objective,
        max_force: Option<f64>,
        sample_p0: impl Fn() -> f64,
    ) -> Result<JointBounds, SolveError> {
        let (scene, w2) = (self.scene, self.w2);
        let once = std::cell::OnceCell::new();
        let p0 = || *once.get_or_init(&sample_p0);
        // No automatic bound is needed where the scene's own bounds are finite (P₀, 720
        // mechanism states per scenario, is then not sampled).
        let own = unbalance_bounds(&scene.counterweight).1.is_finite()
            && scene.balancers.iter().all(|b| b.max_unbalance.is_finite());
        let k_force = match (objective, max_force) {
            _ if own => f64::INFINITY,
            (Objective::MinPeakForce | Objective::MinRmsForce, Some(f)) => f.min(p0()),
            (Objective::MinPeakForce | Objective::MinRmsForce, None) => p0(),
            (_, Some(f)) => f,
            (_, None) => {
                return Err(SolveError::Numeric(
                    "a joint design (balancers, moment or main-bearing limits, or the energy fluctuation) minimising the torque, the moment or ΔE needs objective.max_peak_force (or, for ΔE, finite bounds on |U| and every |B_n|): the counterweight is otherwise unbounded".into(),
                ))
            }
        };
        // K + P₀, infinite (and P₀ not sampled) where the scene's own bounds suffice.
        let k_p0 = if k_force.is_finite() {
            k_force + p0()
        } else {
            f64::INFINITY
        };
        let auto = |n: f64| 2.0 * k_p0 / (w2 * n * n);
        let (u_lo, u_hi) = unbalance_bounds(&scene.counterweight);
        let u_auto = 2.0 * auto(1.0);
        let sector = match scene.counterweight.angle {
            Var::Fixed(b) => Some((b, b)),
            Var::Free { min, max } if max - min < std::f64::consts::TAU - 1e-9 => Some((min, max)),
            _ => None,
        };
        Ok(JointBounds {
            u_lo,
            u_hi,
            u_auto,
            u_max: u_hi.min(u_auto),
            b_max: scene
                .balancers
                .iter()
                .map(|b| b.max_unbalance.min(auto(b.pair.order as f64)))
                .collect(),
            k_p0,
            w2,
            sector,
        })
    }

    /// Writes the balancers' columns of field `which` (0 the force, 1 the moment, 2 the
    /// torque of their weights) at φ into row 0 of `out`: their coefficients times ω² (1 for
    /// the torque).
    fn fill_balancers(&self, out: &mut AffineValue, phi: f64, which: u8) {
        for (j, b) in self.scene.balancers.iter().enumerate() {
            let (c, scale) = match which {
                0 => (b.pair.force_coeffs(phi), self.w2),
                1 => (b.pair.moment_coeffs(phi), self.w2),
                _ => (b.pair.weight_torque_coeffs(phi, self.g), 1.0),
            };
            let row = out.row_mut(0);
            row[mm::var_u(j + 1)] = c[0] * scale;
            row[mm::var_u(j + 1) + 1] = c[1] * scale;
        }
    }

    /// U and the balancers' B_n from the engine's variables x.
    fn parts(&self, x: &[f64]) -> (P2, Vec<[f64; 2]>) {
        let ub = mm::var_u;
        (
            P2::new(x[ub(0)], x[ub(0) + 1]),
            (0..self.nb)
                .map(|j| [x[ub(j + 1)], x[ub(j + 1) + 1]])
                .collect(),
        )
    }

    /// [`round_off_bounds`] of the design x (force, torque, moment), remembered for the
    /// last design (the same bits of x: the same numbers).
    fn round_off(&self, x: &[f64]) -> [f64; 3] {
        let mut memo = self
            .round_off_memo
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        let same = |at: &[f64]| {
            at.len() == x.len() && at.iter().zip(x).all(|(a, b)| a.to_bits() == b.to_bits())
        };
        if let Some((_, r)) = memo.as_ref().filter(|m| same(&m.0)) {
            return *r;
        }
        let (u, b) = self.parts(x);
        let r = match self.nb {
            0 => round_off_bounds(self.zero, u),
            _ => round_off_bounds(&self.zero.with_balancers(&b), u),
        };
        *memo = Some((x.to_vec(), r));
        r
    }

    /// The shaking force F = ω²(f₀ + Rot(φ)U + Σ balancers) (N).
    fn force_field(&self) -> impl AffineField + '_ {
        let ub = mm::var_u;
        let w2 = self.w2;
        FnField::new(
            "shaking force",
            2,
            move |phi: f64, out: &mut AffineValue| {
                let ([c, sn], f0) = self.force0(phi);
                let f0 = f0 * w2;
                out.b = [f0.x, f0.y];
                // Both rows at once (row r at r·n): one look at the inline storage.
                let (n, u) = (out.n(), ub(0));
                let a = &mut out.a[..];
                a[u] = w2 * c;
                a[u + 1] = -w2 * sn;
                a[n + u] = w2 * sn;
                a[n + u + 1] = w2 * c;
                if self.nb > 0 {
                    self.fill_balancers(out, phi, 0);
                }
            },
        )
        .with_error(move |_, x: &[f64]| self.round_off(x)[0])
    }

    /// The shaking moment about O, ω²(M₀ + Σ balancers' couples) (N·m); U adds none.
    fn moment_field(&self) -> impl AffineField + '_ {
        FnField::new(
            "shaking moment",
            1,
            move |phi: f64, out: &mut AffineValue| {
                out.b = [moment0(self.zero, &self.state(phi)) * self.w2, 0.0];
                self.fill_balancers(out, phi, 1);
            },
        )
        .with_error(move |_, x: &[f64]| self.round_off(x)[2])
    }

    /// The drive torque T₀ − g·Rot'(φ)U + Σ balancers' weights (N·m).
    fn torque_field(&self) -> impl AffineField + '_ {
        let ub = mm::var_u;
        let g = self.g;
        FnField::new("drive torque", 1, move |phi: f64, out: &mut AffineValue| {
            let s = self.state(phi);
            out.b = [torque0(self.zero, &s), 0.0];
            out.row_mut(0)[ub(0)] = weight_torque_cs(s.cs, g, P2::new(1.0, 0.0));
            out.row_mut(0)[ub(0) + 1] = weight_torque_cs(s.cs, g, P2::new(0.0, 1.0));
            self.fill_balancers(out, phi, 2);
        })
        .with_error(move |_, x: &[f64]| self.round_off(x)[1])
    }

    /// The main bearing load without the counterweight's weight, F_main(φ; 0) − ω²Rot(φ)U (N).
    fn bearing_field(&self) -> impl AffineField + '_ {
        let ub = mm::var_u;
        let (scene, w2) = (self.scene, self.w2);
        FnField::new(
            "main bearing load",
            2,
            move |phi: f64, out: &mut AffineValue| {
                let s = self.state(phi);
                let f = scene
                    .mech
                    .joint_loads(&s, scene.omega, &scene.loads, P2::zeros(), 0.0)
                    .main;
                let [c, sn] = s.cs;
                out.b = [f.x, f.y];
                out.row_mut(0)[ub(0)] = -w2 * c;
                out.row_mut(0)[ub(0) + 1] = w2 * sn;
                out.row_mut(1)[ub(0)] = -w2 * sn;
                out.row_mut(1)[ub(0) + 1] = -w2 * c;
            },
        )
        .with_error(move |_, x: &[f64]| joint_load_round_off(scene, self.parts(x).0, 0.0))
    }

    /// The [`Optimum`] of the engine's solution: U and the B_n (0 where infeasible), the
    /// status (`inaccurate` on an automatic bound), the gap (sampling + solver error), the
    /// method with the bounds used, and the warnings. |U| below the scene's U_min is an
    /// error (that bound is not convex).
    fn optimum(&self, sol: &mm::Solution, bounds: &JointBounds) -> Result<Optimum, SolveError> {
        let (scene, nb) = (self.scene, self.nb);
        let mut warnings = Vec::new();
        if let Some(n) = &sol.note {
            warnings.push(n.clone());
        }
        let feasible = sol.x.iter().all(|v| v.is_finite());
        let (u, b) = if feasible {
            self.parts(&sol.x)
        } else {
            (P2::zeros(), vec![[0.0; 2]; nb])
        };
        // A design on a bound the scene did not set would be the bounds' optimum, not the
        // scene's: the Fourier bounds exclude it, so say so if it happens.
        let on = |v: f64, auto: f64, given: f64| auto < given && v >= auto * (1.0 - 1e-6);
        let mut status = sol.status;
        if feasible
            && (on(u.norm(), bounds.u_auto, bounds.u_hi)
                || b.iter().zip(&scene.balancers).any(|(bb, spec)| {
                    on(
                        bb[0].hypot(bb[1]),
                        bounds.auto(spec.pair.order as f64),
                        spec.max_unbalance,
                    )
                }))
        {
            status = Status::Inaccurate;
            warnings.push(
                "the joint design reached an automatic bound on |U| or |B_n| (see the method); the optimum may lie beyond it".into(),
            );
        }
        let u_lo = bounds.u_lo;
        if u_lo > 0.0 && u.norm() < u_lo * (1.0 - 1e-9) {
            return Err(SolveError::Numeric(format!(
                "|U| ≥ {u_lo} kg·m is not convex and not available with balancers, moment or main-bearing limits, or the energy-fluctuation objective"
            )));
        }
        let gap = if feasible {
            sol.error.sampling + sol.error.solver
        } else {
            0.0
        };
        Ok(Optimum {
            status,
            u,
            gap,
            method: format!(
                "joint design of the crank counterweight and {nb} balancer pair(s) (synth::minimax, bounds |U| ≤ {:.6e} kg·m{}): clarabel SOCP + exchange loop: {} rounds, {} angles, {} interior-point iterations, last status {}",
                bounds.u_max,
                bounds
                    .b_max
                    .iter()
                    .zip(&scene.balancers)
                    .map(|(m, s)| format!(", |B_{}| ≤ {m:.6e} kg·m", s.pair.order))
                    .collect::<String>(),
                sol.rounds,
                sol.angles,
                sol.ipm_iterations,
                sol.solver_status
            ),
            rounds: sol.rounds,
            warnings,
            balancers: b,
            duals: None,
        })
    }
}

/// The minimax engine's settings from the scene's accuracy (the RMS quadrature's count made
/// even).
fn minimax_settings(scene: &Scene) -> mm::Settings {
    let cs = &scene.resolved_settings();
    mm::Settings {
        rel_tol: cs.rel_tol,
        initial_samples: cs.initial_samples,
        scan_samples: cs.scan_samples,
        max_rounds: cs.max_rounds,
        peak_xtol: cs.peak_xtol,
        rms_samples: (cs.rms_samples + 1) & !1,
        exact_disc: cs.exact_disc,
        ..mm::Settings::default()
    }
}

/// What each interval of the operating envelope costs (issue 33, item 3): the sensitivity
/// table of an envelope solve of `scene` from its `duals`, dV*/d(end) for every interval
/// end, so a designer sees which tolerance or speed limit to tighten first. By the envelope
/// theorem from the optimum's multipliers (`synth::envelope::sensitivities`): no re-solve.
/// The part here is the family's: one active maximum's field evaluated with one parameter
/// of its scenario moved, the design and the angle held — on the scenario's vertex partner
/// where the values are a vertex's (a mass or the speed: every figure is affine in a mass
/// and in ω²), else on the scene rebuilt at θ ± h (a length). An error when the optimum
/// has no multipliers (not certified by Newton's polish). The tests check the table
/// against whole re-solves.
pub fn sensitivity_table(
    scene: &Scene,
    duals: &EnvelopeDuals,
) -> Result<Vec<Sensitivity>, SolveError> {
    let stride = duals.kinds.len();
    let multipliers =
        multipliers_with(&duals.multipliers, duals.status).map_err(SolveError::Numeric)?;
    let env = &scene.envelope;
    let nb = scene.balancers.len();
    let energy = duals.energy.is_some();
    let (scenes, values, keep) = scenarios(scene, duals.used, energy);
    let zeros_owned = balancer_free(&scenes, nb);
    let zeros: &[Scene] = if nb == 0 { &scenes } else { &zeros_owned };
    let built: Vec<JointScene> = (scenes.iter().zip(zeros))
        .map(|(s, z)| JointScene::new(s, z, nb))
        .collect();
    let fields_at = |k: usize, at_values: &[f64], ms: &[&mm::Multiplier]| {
        // Scenario k's energy offset is the engine's variable of its place among `keep`.
        let place = keep
            .iter()
            .position(|&j| j == k)
            .expect("an active scenario is kept");
        let energy = duals.energy.map(|(n, o)| (n, o + place));
        let at = ms.iter().map(|m| (duals.kinds[m.field % stride], m.angle));
        if let Some(j) = values.iter().position(|v| v == at_values) {
            let set = built[j].fields(duals.used, energy)?;
            return Ok(field_values(&set.all(), at, &duals.x));
        }
        let s = env.at(scene, at_values.to_vec()).scene;
        let zero = s.with_balancers(&vec![[0.0; 2]; nb]);
        let js = JointScene::new(&s, &zero, nb);
        let set = js.fields([true; 4], energy)?;
        Ok(field_values(&set.all(), at, &duals.x))
    };
    scenario_sensitivities(
        &env.names(),
        &env.ranges(),
        stride,
        multipliers,
        env.first_length(),
        env.speed.is_some(),
        fields_at,
    )
}
