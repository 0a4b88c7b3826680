//! The boom counterweight of the luffing crane (thesis `003`, ch. 1, Fig 1.5: the boom's
//! self-weight balanced by a counterweight on the boom, hung from it, or stacked): its static
//! moment chosen to minimise the peak luffing drive torque over the luffing range, empty and
//! loaded, and the forces of the boom system over the range.
//!
//! The drive torque is affine in the counterweight's first moment u about A in the boom
//! frame (see [`super::statics`]): T(φ) = T₀(φ) + g (u_s cos φ + u_n sin φ). So
//!
//! min over u of max over φ ∈ [φ_min, φ_max] and over the load cases of |T(φ; u)|
//!
//! is convex, the same problem as the torque-optimal crank counterweight: it is solved by
//! the shared certified minimax engine ([`crate::synth::minimax`]), a clarabel SOCP with an
//! exchange loop, whose status is `optimal` only with its certificate (the refined true
//! peak within `rel_tol` of a rigorous lower bound). The engine works over a periodic
//! parameter θ; the luffing range is mapped onto it by φ(θ) = φ_mid − ½Δφ cos θ, which
//! visits every φ of the range twice and keeps each field smooth and periodic (the ends of
//! the range become smooth extrema in θ, where the refinement finds them).
//!
//! The counterweight's limits: mass m ≤ m_max, its centroid (or, hung, its suspension
//! point) within the lever ℓ of A, |u| ≤ ℓ m, and optionally a sector of directions in the
//! boom frame (180° is the boom's extension behind A). A hung counterweight acts as a point
//! mass at its suspension point for the quasi-static drive torque, so the same u describes
//! it. Only u enters the torque: the lightest counterweight with it sits at the full lever,
//! m = |u|/ℓ, which is what is reported.

use super::lever::LeverLinkage;
use super::model::Linkage;
use super::statics::{
    counterweight_torque_row, statics, virtual_work_torque, HoistRope, Loads, SelfWeight, Statics,
};
use crate::numeric::interval_peak;
use crate::synth::counterweight::Status;
use crate::synth::minimax::{
    self as mm, AffineValue, CounterweightLimits, Engine, FieldPeak, FnField, Goal, Problem,
};

/// What the problem file asks of the counterweight (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CounterweightSpec {
    /// m_max (kg).
    pub max_mass: f64,
    /// ℓ, the largest distance of its centroid (or suspension point) from A (m).
    pub lever: f64,
    /// Allowed directions of u in the boom frame (rad, hi − lo ≤ π), if restricted.
    pub directions: Option<(f64, f64)>,
    /// Where it is and how it moves (thesis Fig 1.5 a, b, c).
    pub kind: CounterweightKind,
}

/// The counterweight's type (thesis Fig 1.5).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CounterweightKind {
    /// Fig 1.5a, on the boom ("đặt trực tiếp lên cần"): u = m·(centroid) in the boom frame.
    Boom,
    /// Fig 1.5b, hung ("treo") from a point of the boom by a rope of this length (m): it acts
    /// vertically below its suspension point, so quasi-statically as a mass at that point,
    /// u = m·(suspension point) in the boom frame; its own path is the suspension point's
    /// less the rope.
    Hanging {
        /// L_h, the rope from the suspension point to the counterweight's centroid (m).
        hang_length_m: f64,
    },
    /// Fig 1.5c, on a lever ("xếp") pivoted on the A-frame and linked to the boom by a rod:
    /// u = w, its first moment about the lever's pivot in the lever frame
    /// ([`super::lever`]).
    Lever(LeverSpec),
}

/// The lever's four-bar as the file states it (SI); the rod's length follows from the lever's
/// angle at maximum reach ([`LeverLinkage::new`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LeverSpec {
    /// O, the pivot on the A-frame (m, frame of A).
    pub pivot_m: [f64; 2],
    /// ρ, the pivot to the rod's lever pin (m).
    pub arm_m: f64,
    /// ψ₁, the lever's direction O → rod pin at maximum reach (rad, from +x anticlockwise).
    pub angle_at_max_reach_rad: f64,
    /// K = (s, n), the rod's pin on the boom (m, boom frame).
    pub rod_boom_point_m: [f64; 2],
}

impl LeverSpec {
    /// The four-bar for a boom whose range starts at φ_min.
    pub fn linkage(&self, phi_min: f64) -> Option<LeverLinkage> {
        let [x, y] = self.pivot_m;
        LeverLinkage::new(
            crate::geom::P2::new(x, y),
            self.arm_m,
            self.angle_at_max_reach_rad,
            self.rod_boom_point_m,
            phi_min,
        )
    }
}

/// The boom system's masses and the counterweight to design (`None`: forces only).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BalanceScene {
    /// Masses and centroids; the jib's centroid is `jib_centroid`.
    pub self_weight: SelfWeight,
    /// The jib's centroid fraction f_j if given; `None`: the middle of the jib E–C,
    /// (1 − k2)/2, which depends on the design's k2 (see [`BalanceScene::self_weight_at`]).
    pub jib_centroid: Option<f64>,
    /// The counterweight asked for.
    pub counterweight: Option<CounterweightSpec>,
    /// Q, the rated load (kg): a second, loaded case.
    pub load_mass: Option<f64>,
    /// The hoist rope, if inclined (`mechanism.hoist_rope`).
    pub rope: Option<HoistRope>,
    /// Whether masses were given (`mechanism.self_weight`): without them only the load's
    /// path with the rope is analysed.
    pub masses: bool,
}

impl BalanceScene {
    /// The masses with the jib's centroid resolved for a jib tail ratio k2.
    pub fn self_weight_at(&self, k2: f64) -> SelfWeight {
        SelfWeight {
            jib_centroid: self.jib_centroid.unwrap_or(0.5 * (1.0 - k2)),
            ..self.self_weight
        }
    }
}

/// The peak drive torque of one load case.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CasePeak {
    /// `empty` or `loaded`.
    pub case: String,
    /// max over the range of |T| (N·m).
    pub peak_nm: f64,
    /// Its boom angle φ (rad).
    pub phi_rad: f64,
    /// Bound on |peak − true peak| (N·m): refinement and evaluation.
    pub error_nm: f64,
}

/// The designed counterweight.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Counterweight {
    /// `optimal` (certified), `inaccurate` (gap stated), `infeasible` or `failed`.
    pub status: Status,
    /// Why not optimal, if not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// u = (u_s, u_n), its first moment about A in the boom frame (kg·m).
    pub static_moment_kgm: [f64; 2],
    /// |u| (kg·m).
    pub static_moment_magnitude_kgm: f64,
    /// Direction of u in the boom frame (rad; 180° = on the boom's extension behind A), in
    /// [0, 2π) or, with `directions`, from its first angle on.
    pub direction_rad: f64,
    /// The lightest counterweight with this u: at the full lever, m = |u|/ℓ (kg).
    pub mass_kg: f64,
    /// ℓ, its centroid's distance from A (m).
    pub lever_m: f64,
    /// V: the peak |T| over the range and both cases with it (N·m), an upper bound of the
    /// optimum.
    pub peak_drive_torque_nm: f64,
    /// L: the certified lower bound of the optimum (N·m).
    pub lower_bound_nm: f64,
    /// Bound on |V − optimum| (N·m): sampling certificate + evaluation + refinement.
    pub error_nm: f64,
    /// Exchange rounds (SOCP solves).
    pub rounds: usize,
}

/// The refined largest value of one member force over the range, in one load case (with
/// the counterweight, if designed).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ForcePeak {
    /// `empty` or `loaded`.
    pub case: String,
    /// Which force: `tie tension max`, `tie tension min` (negative: compression),
    /// `boom compression max`, `boom shear max` (across the boom at D), `pin A max`,
    /// `pin B max`, `pin D max`, `pin E max` (pin load magnitudes), `head force N max`
    /// (thesis §2.2: the jib's force on the boom head).
    pub force: String,
    /// The value (N).
    pub value_n: f64,
    /// Its boom angle φ (rad).
    pub phi_rad: f64,
    /// Bound on |value − true extreme value| (N): refinement and evaluation.
    pub error_n: f64,
    /// For `head force N max`: α, the angle between N and the boom axis there (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha_rad: Option<f64>,
}

/// The independent check of the drive torque: statics against virtual work.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct VirtualWorkCheck {
    /// Boom angles checked (equally spaced over the range, both ends included).
    pub positions: usize,
    /// max |T_statics − dV/dφ| over them and both cases (N·m).
    pub max_difference_nm: f64,
    /// The largest stated error there (statics bound + difference estimate) (N·m).
    pub max_stated_error_nm: f64,
    /// Whether every difference is within its stated error.
    pub pass: bool,
}

/// One sample of the series over the range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// φ (rad).
    pub phi: f64,
    /// Reach of the jib head from the slewing axis (m).
    pub reach: f64,
    /// T without counterweight: empty, loaded (N·m; loaded = empty without a load).
    pub bare: [f64; 2],
    /// T with the counterweight: empty, loaded (N·m).
    pub balanced: [f64; 2],
    /// Statics of the loaded (or only) case with the counterweight.
    pub loaded: super::statics::Statics,
}

/// The balance of the boom system.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Balance {
    /// How it was computed.
    pub method: String,
    /// The masses used.
    pub self_weight: SelfWeight,
    /// Q (kg), if a loaded case is included.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_mass_kg: Option<f64>,
    /// Peak drive torque without counterweight, per case.
    pub unbalanced: Vec<CasePeak>,
    /// The designed counterweight (with `design.counterweight`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counterweight: Option<Counterweight>,
    /// Peak drive torque with it, per case.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub balanced: Vec<CasePeak>,
    /// Member forces over the range (with the counterweight if designed).
    pub forces: Vec<ForcePeak>,
    /// Statics against virtual work.
    pub virtual_work_check: VirtualWorkCheck,
    /// A hung or lever counterweight's own motion over the range (not for one on the boom).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counterweight_path: Option<CounterweightPath>,
    /// Series over the range (CSV and plot; not in the JSON).
    #[serde(skip)]
    pub series: Vec<Sample>,
}

/// A hung or lever counterweight's own kinematics over the luffing range, with the designed
/// counterweight.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CounterweightPath {
    /// `hanging` or `lever`.
    pub kind: String,
    /// What the design is, in plain words: how the counterweight acts, that the program is
    /// convex, and its status.
    pub note: String,
    /// The counterweight's lowest centroid height over the range (m above A) and its boom
    /// angle (rad).
    pub lowest_y_m: f64,
    /// See `lowest_y_m`.
    pub phi_at_lowest_rad: f64,
    /// Its highest centroid height (m above A).
    pub highest_y_m: f64,
    /// The horizontal range of its centroid [min x, max x] (m, frame of A).
    pub x_range_m: [f64; 2],
    /// Bound on the error of these (m): refinement (Brent to 1e-9 rad) plus rounding.
    pub error_m: f64,
    /// The centroid at φ_min and at φ_max (m, frame of A): what the drawing places.
    pub centroid_m: [[f64; 2]; 2],
    /// Hanging: the suspension point at φ_min and at φ_max (m, frame of A).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub suspension_point_m: Option<[[f64; 2]; 2]>,
    /// Hanging: the hanger's tension m g (N), constant quasi-statically.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hanger_tension_n: Option<f64>,
    /// Lever: its four-bar (pivot, arm, rod, boom point).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lever: Option<LeverLinkage>,
    /// Lever: ψ at φ_min (in [0, 2π)) and at φ_max, followed continuously (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lever_angle_rad: Option<[f64; 2]>,
    /// Lever: the rod's pins at φ_min and at φ_max, [lever pin L, boom pin K] each (m, frame
    /// of A): what the drawing places.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rod_pins_m: Option<[[[f64; 2]; 2]; 2]>,
    /// Lever: the largest |rod force| over the range (N; the counterweight's torque over the
    /// rod's arm about A, the same empty and loaded), and its error (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rod_force_max_n: Option<f64>,
    /// See `rod_force_max_n`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rod_force_error_n: Option<f64>,
}

/// Why the balance cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BalanceError {
    /// The tie is a straight guide (B at infinity): no pin B to carry a force.
    #[error("the tie is a straight guide (tie pin at infinity): member forces need a finite tie")]
    StraightGuide,
    /// The linkage does not assemble, or is singular, at a boom angle of the range.
    #[error("no statics at phi = {phi} rad (the linkage does not assemble or the tie and jib tail align)")]
    NoPose {
        /// The boom angle.
        phi: f64,
    },
    /// The lever counterweight's data give no four-bar (a zero rod, or the rod through the
    /// pivot at maximum reach).
    #[error("the lever counterweight's rod and lever give no four-bar at maximum reach: move the pivot, the arm or the lever angle")]
    NoLever,
    /// A luffing actuator passes its dead centre (its lever arm about A vanishes) in the range.
    #[error("the luffing actuator passes its dead centre (no lever arm about the boom foot) at phi = {phi} rad: move its attachment points")]
    DeadCentre {
        /// The boom angle.
        phi: f64,
    },
    /// The engine refused the problem.
    #[error("counterweight solve: {0}")]
    Engine(#[from] mm::MinimaxError),
}

/// φ(θ) = φ_mid − ½Δφ cos θ, the luffing range as a periodic parameter.
pub(super) fn phi_of(link: &Linkage, theta: f64) -> f64 {
    let [p0, p1] = link.phi_range;
    0.5 * (p0 + p1) - 0.5 * (p1 - p0) * theta.cos()
}

/// Step of the virtual-work check (rad): its truncation h⁴|V⁽⁵⁾| and rounding ε|V|/h are
/// both ~1e-12 of the torque.
const VW_STEP: f64 = 1e-3;

/// Angle tolerance of the force peaks' refinement (rad): ½|f''|·xtol² is ~1e-18 of a force.
const PEAK_XTOL: f64 = 1e-9;

/// Boom angles of the virtual-work check.
pub const VW_POSITIONS: usize = 10;

/// The balance of the linkage `link` for `scene`: the drive torque without counterweight, the
/// optimal counterweight when asked for, the forces over the range, the check by virtual
/// work. `foot_offset` r places the reach; `samples` is the number of series points.
pub fn solve(
    link: &Linkage,
    scene: &BalanceScene,
    foot_offset: f64,
    settings: &mm::Settings,
    samples: usize,
) -> Result<Balance, BalanceError> {
    if !matches!(link.guide, super::model::Guide::Circle { .. }) {
        return Err(BalanceError::StraightGuide);
    }
    let c = Cases::new(link, scene);
    if let Some(CounterweightKind::Lever(_)) = scene.counterweight.map(|c| c.kind) {
        if c.lever.is_none() {
            return Err(BalanceError::NoLever);
        }
    }
    // Every field must evaluate over the range; a failing pose is an error, not a NaN.
    let [p0, p1] = link.phi_range;
    for k in 0..=64 {
        let phi = p0 + (p1 - p0) * k as f64 / 64.0;
        for &(_, q) in &c.cases {
            c.at(phi, q, 0.0, [0.0; 2])?;
        }
    }
    let d = c.design(settings)?;
    let forces = c.force_peaks(d.m, d.u)?;
    let series = c.series(d.m, d.u, foot_offset, samples)?;
    let vw = c.virtual_work_check()?;
    let counterweight_path = c.counterweight_path(d.m, d.u)?;
    Ok(Balance {
        method: "quasi-static equilibrium of boom, jib and tie (2×2 tie–jib system per pose); counterweight: certified minimax of |T| over the luffing range and both load cases (clarabel SOCP + exchange loop, synth::minimax)".into(),
        self_weight: c.w,
        load_mass_kg: scene.load_mass,
        unbalanced: d.unbalanced,
        counterweight: d.counterweight,
        balanced: d.balanced,
        forces,
        virtual_work_check: vw,
        counterweight_path,
        series,
    })
}

/// The linkage under its self weight `w` and the load cases (name, load mass q): what
/// every figure of the balance, and of the luffing drive ([`super::luffing`]), evaluates.
pub(super) struct Cases<'a> {
    pub(super) link: &'a Linkage,
    pub(super) scene: &'a BalanceScene,
    pub(super) w: SelfWeight,
    pub(super) cases: Vec<(&'static str, f64)>,
    /// A lever counterweight's four-bar (`None`: the counterweight is on the boom or hung,
    /// or the lever's data give no four-bar, which [`solve`] refuses).
    pub(super) lever: Option<LeverLinkage>,
}

/// The drive-torque peaks without and with the counterweight, and the counterweight
/// (mass m, first moment u) found, zero without one to design.
struct Designed {
    unbalanced: Vec<CasePeak>,
    counterweight: Option<Counterweight>,
    balanced: Vec<CasePeak>,
    m: f64,
    u: [f64; 2],
}

impl<'a> Cases<'a> {
    /// The cases of `scene` on `link`: `empty`, and `loaded` with the scene's load mass.
    pub(super) fn new(link: &'a Linkage, scene: &'a BalanceScene) -> Self {
        Cases {
            link,
            scene,
            w: scene.self_weight_at(link.k2),
            cases: match scene.load_mass {
                Some(q) => vec![("empty", 0.0), ("loaded", q)],
                None => vec![("empty", 0.0)],
            },
            lever: match scene.counterweight.map(|c| c.kind) {
                Some(CounterweightKind::Lever(l)) => l.linkage(link.phi_range[0]),
                _ => None,
            },
        }
    }

    /// The statics at φ with load mass q and the counterweight of mass m and first moment u.
    pub(super) fn at(
        &self,
        phi: f64,
        q: f64,
        m: f64,
        u: [f64; 2],
    ) -> Result<Statics, BalanceError> {
        let pose = self.link.pose(phi).ok_or(BalanceError::NoPose { phi })?;
        let lever = self.lever;
        // A lever's counterweight weighs on the A-frame, not on the boom: its torque comes
        // through the rod.
        let loads = Loads {
            load_mass: q,
            counterweight_mass: if lever.is_some() { 0.0 } else { m },
            counterweight_moment: if lever.is_some() { [0.0; 2] } else { u },
            rope: self.scene.rope,
        };
        let mut st =
            statics(self.link, phi, &pose, &self.w, &loads).ok_or(BalanceError::NoPose { phi })?;
        if let Some(lk) = lever {
            let lp = lk.pose(phi).ok_or(BalanceError::NoPose { phi })?;
            let row = LeverLinkage::torque_row(&lp);
            let t_cw = row[0] * u[0] + row[1] * u[1];
            // The rod's pull f along d = (L − K)/|L − K| on the boom at K gives K × f d = T_cw.
            let d = (lp.l - lp.k) / (lp.l - lp.k).norm();
            let f = t_cw / crate::geom::cross(lp.k, d);
            st.drive_torque += t_cw;
            st.drive_torque_error += 64.0 * f64::EPSILON * t_cw.abs() * lp.condition;
            st.pin_a -= d * f;
            st.force_error += 64.0 * f64::EPSILON * f.abs() * lp.condition;
        }
        Ok(st)
    }

    /// The counterweight's drive torque per unit u at φ (N·m per kg·m): on the boom or hung,
    /// g (cos φ, sin φ); on a lever, g ψ′ (cos ψ, −sin ψ). `None` where the lever's pose fails.
    pub(super) fn cw_row(&self, phi: f64) -> Option<[f64; 2]> {
        match &self.lever {
            Some(lk) => Some(LeverLinkage::torque_row(&lk.pose(phi)?)),
            None => Some(counterweight_torque_row(phi)),
        }
    }

    /// The counterweight's first moment m·(centroid − its pivot) in the world at φ (kg·m): on
    /// the boom u_s e_b + u_n e_n about A (hung: its suspension point's), on a lever the
    /// lever frame's w about the lever's pivot O.
    pub(super) fn cw_moment(&self, phi: f64, u: [f64; 2]) -> Option<crate::geom::P2> {
        match &self.lever {
            Some(lk) => Some(LeverLinkage::world_moment(&lk.pose(phi)?, u)),
            None => Some(super::lever::boom_point_at(u, phi)),
        }
    }

    /// The pivot the counterweight's first moment is taken about: A, or the lever's O.
    pub(super) fn cw_pivot(&self) -> crate::geom::P2 {
        self.lever.map_or(crate::geom::P2::zeros(), |lk| lk.pivot)
    }

    /// The minimax of the drive torque over the luffing range and the load cases: field k
    /// is T_k(φ; u) = T_k(φ; 0) + row(φ)·u, u the counterweight's first moment with
    /// |u| ≤ ℓ m_max (in its sector when given). The peaks at u = 0 always; the optimum
    /// when the scene asks for a counterweight.
    fn design(&self, settings: &mm::Settings) -> Result<Designed, BalanceError> {
        let link = self.link;
        let fields: Vec<_> = self
            .cases
            .iter()
            .map(|&(name, q)| {
                FnField::new(
                    format!("drive torque, {name}"),
                    1,
                    move |theta: f64, out: &mut AffineValue| {
                        let phi = phi_of(link, theta);
                        let s = self.at(phi, q, 0.0, [0.0; 2]);
                        out.b[0] = s.map_or(f64::NAN, |s| s.drive_torque);
                        let row = self.cw_row(phi).unwrap_or([f64::NAN; 2]);
                        let r = out.row_mut(0);
                        r[mm::var_u(0)] = row[0];
                        r[mm::var_u(0) + 1] = row[1];
                    },
                )
                .with_error(move |theta: f64, _x: &[f64]| {
                    self.at(phi_of(link, theta), q, 0.0, [0.0; 2])
                        .map_or(f64::INFINITY, |s| s.drive_torque_error)
                })
            })
            .collect();
        let field_refs: Vec<&dyn mm::AffineField> =
            fields.iter().map(|f| f as &dyn mm::AffineField).collect();
        // Without a counterweight to design the engine still computes the peaks (at u = 0): a
        // counterweight of zero mass.
        let spec = self.scene.counterweight.unwrap_or(CounterweightSpec {
            max_mass: 1.0,
            lever: 1.0,
            directions: None,
            kind: CounterweightKind::Boom,
        });
        let mut limits = CounterweightLimits::new(spec.max_mass, spec.lever);
        limits.sector = spec.directions;
        let pb = Problem {
            fields: field_refs,
            counterweights: vec![limits],
            extra: vec![],
            linear: vec![],
            goal: Goal::MinPeak((0..self.cases.len()).map(|f| (f, 1.0)).collect()),
            limits: vec![],
        };
        let engine = Engine::new(&pb, settings)?;
        let x0 = vec![0.0; pb.n()];
        let unbalanced = self.case_peaks(&engine.peaks(&x0)?);
        Ok(match self.scene.counterweight {
            None => Designed {
                unbalanced,
                counterweight: None,
                balanced: Vec::new(),
                m: 0.0,
                u: [0.0; 2],
            },
            Some(spec) => {
                let sol = engine.solve()?;
                let c = counterweight_of(&sol, &spec);
                let (m, u) = (c.mass_kg, c.static_moment_kgm);
                Designed {
                    unbalanced,
                    counterweight: Some(c),
                    balanced: self.case_peaks(&sol.peaks),
                    m,
                    u,
                }
            }
        })
    }

    /// A hung or lever counterweight's path with mass m and first moment u (`None` on the
    /// boom or without a counterweight): its centroid's extremes refined over the range, the
    /// hanger's tension or the lever's angles and rod force.
    fn counterweight_path(
        &self,
        m: f64,
        u: [f64; 2],
    ) -> Result<Option<CounterweightPath>, BalanceError> {
        let Some(spec) = self.scene.counterweight else {
            return Ok(None);
        };
        let hang = match spec.kind {
            CounterweightKind::Boom => return Ok(None),
            CounterweightKind::Hanging { hang_length_m } => hang_length_m,
            CounterweightKind::Lever(_) => 0.0,
        };
        if !(m > 0.0) {
            return Ok(None);
        }
        let [p0, p1] = self.link.phi_range;
        let nan = crate::geom::P2::new(f64::NAN, f64::NAN);
        let at = |phi: f64| {
            self.cw_moment(phi, u).map_or(nan, |w| {
                self.cw_pivot() + w / m - crate::geom::P2::new(0.0, hang)
            })
        };
        let peak = |f: &dyn Fn(f64) -> f64| {
            interval_peak(f, p0, p1, 64, PEAK_XTOL).map_err(|_| BalanceError::NoPose { phi: p0 })
        };
        let (lo, hi) = (peak(&|p| -at(p).y)?, peak(&|p| at(p).y)?);
        let (xl, xh) = (peak(&|p| -at(p).x)?, peak(&|p| at(p).x)?);
        let error = lo.error.max(hi.error).max(xl.error).max(xh.error)
            + 64.0 * f64::EPSILON * (self.link.length_scale() + self.cw_pivot().norm() + hang);
        let mut path = CounterweightPath {
            kind: String::new(),
            note: String::new(),
            lowest_y_m: -lo.peak.fx,
            phi_at_lowest_rad: lo.peak.x,
            highest_y_m: hi.peak.fx,
            x_range_m: [-xl.peak.fx, xh.peak.fx],
            error_m: error,
            centroid_m: [p0, p1].map(|p| {
                let c = at(p);
                [c.x, c.y]
            }),
            suspension_point_m: None,
            hanger_tension_n: None,
            lever: None,
            lever_angle_rad: None,
            rod_pins_m: None,
            rod_force_max_n: None,
            rod_force_error_n: None,
        };
        match self.lever {
            None => {
                let s = |p: f64| {
                    let h = at(p) + crate::geom::P2::new(0.0, hang);
                    [h.x, h.y]
                };
                path.kind = "hanging".into();
                path.note = "hung from the boom (thesis Fig 1.5b), the counterweight acts vertically below its suspension point, quasi-statically as a mass there: its torque g (u_s cos φ + u_n sin φ) is affine in u = m·(suspension point), so the minimax of the drive torque is convex, the same program as on the boom; its status is the certificate's".into();
                path.suspension_point_m = Some([s(p0), s(p1)]);
                path.hanger_tension_n = Some(m * crate::units::STANDARD_GRAVITY);
            }
            Some(lk) => {
                let psi = |p: f64| {
                    lk.pose(p)
                        .map(|lp| lp.psi)
                        .ok_or(BalanceError::NoPose { phi: p })
                };
                let rod = |p: f64| {
                    lk.pose(p).map_or(f64::NAN, |lp| {
                        let row = LeverLinkage::torque_row(&lp);
                        let d = (lp.l - lp.k) / (lp.l - lp.k).norm();
                        ((row[0] * u[0] + row[1] * u[1]) / crate::geom::cross(lp.k, d)).abs()
                    })
                };
                let r = peak(&rod)?;
                let cond = lk.pose(r.peak.x).map_or(f64::INFINITY, |lp| lp.condition);
                path.kind = "lever".into();
                path.note = "on a lever linked to the boom by a rod (thesis Fig 1.5c), the counterweight's torque at the boom foot is g ψ′(φ) (w_s cos ψ − w_n sin ψ), affine in its first moment w about the lever's pivot, so the minimax of the drive torque is convex (clarabel SOCP + exchange loop); its status is the certificate's; the lever and the rod are weightless".into();
                path.lever = Some(lk);
                // ψ followed continuously from its value in [0, 2π) at φ_min.
                let start = psi(p0)?.rem_euclid(std::f64::consts::TAU);
                let (mut end, mut prev) = (start, start);
                for i in 1..=64 {
                    let now = psi(p0 + (p1 - p0) * i as f64 / 64.0)?;
                    let step = (now - prev + std::f64::consts::PI)
                        .rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI;
                    end += step;
                    prev = now;
                }
                path.lever_angle_rad = Some([start, end]);
                let pins = |p: f64| {
                    lk.pose(p)
                        .map(|lp| [[lp.l.x, lp.l.y], [lp.k.x, lp.k.y]])
                        .ok_or(BalanceError::NoPose { phi: p })
                };
                path.rod_pins_m = Some([pins(p0)?, pins(p1)?]);
                path.rod_force_max_n = Some(r.peak.fx);
                path.rod_force_error_n = Some(r.error + 64.0 * f64::EPSILON * r.peak.fx * cond);
            }
        }
        Ok(Some(path))
    }

    /// The engine's field peaks as the load cases' torque peaks (θ mapped back to φ).
    fn case_peaks(&self, peaks: &[FieldPeak]) -> Vec<CasePeak> {
        peaks
            .iter()
            .zip(&self.cases)
            .map(|(p, &(name, _))| CasePeak {
                case: name.into(),
                peak_nm: p.peak,
                phi_rad: phi_of(self.link, p.angle),
                error_nm: p.error,
            })
            .collect()
    }

    /// The force peaks with the counterweight (m, u) in each load case, each refined over
    /// the range from a 64-point scan, with its error (refinement + the statics' bound).
    fn force_peaks(&self, m: f64, u: [f64; 2]) -> Result<Vec<ForcePeak>, BalanceError> {
        let [p0, p1] = self.link.phi_range;
        let scan = 64;
        let mut forces = Vec::new();
        type Get = fn(&Statics) -> f64;
        let which: [(&str, f64, Get); 9] = [
            ("tie tension max", 1.0, |s| s.tie_tension),
            ("tie tension min", -1.0, |s| -s.tie_tension),
            ("boom compression max", 1.0, |s| s.boom_compression),
            ("boom shear max", 1.0, |s| s.boom_shear.abs()),
            ("pin A max", 1.0, |s| s.pin_a.norm()),
            ("pin B max", 1.0, |s| s.pin_b.norm()),
            ("pin D max", 1.0, |s| s.pin_d.norm()),
            ("pin E max", 1.0, |s| s.pin_e.norm()),
            ("head force N max", 1.0, |s| s.head_force),
        ];
        for &(name, q) in &self.cases {
            for &(force, sign, g) in &which {
                let f = |phi: f64| self.at(phi, q, m, u).map_or(f64::NAN, |s| g(&s));
                let p = interval_peak(f, p0, p1, scan, PEAK_XTOL)
                    .map_err(|_| BalanceError::NoPose { phi: p0 })?;
                let s = self.at(p.peak.x, q, m, u)?;
                forces.push(ForcePeak {
                    case: name.into(),
                    force: force.into(),
                    value_n: sign * p.peak.fx,
                    phi_rad: p.peak.x,
                    error_n: p.error + s.force_error,
                    alpha_rad: (force == "head force N max").then_some(s.head_force_angle),
                });
            }
        }
        Ok(forces)
    }

    /// The series over the range for the table and the plots: at `samples` + 1 angles the
    /// reach r − C_x, the drive torque without and with the counterweight in each case (the
    /// one case twice without a load), and the statics of the last case.
    fn series(
        &self,
        m: f64,
        u: [f64; 2],
        foot_offset: f64,
        samples: usize,
    ) -> Result<Vec<Sample>, BalanceError> {
        let [p0, p1] = self.link.phi_range;
        let n = samples.max(2);
        let mut series = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let phi = p0 + (p1 - p0) * i as f64 / n as f64;
            let mut bare = [0.0; 2];
            let mut bal = [0.0; 2];
            let mut last = None;
            for (k, &(_, q)) in self.cases.iter().enumerate() {
                bare[k] = self.at(phi, q, 0.0, [0.0; 2])?.drive_torque;
                let s = self.at(phi, q, m, u)?;
                bal[k] = s.drive_torque;
                last = Some(s);
            }
            if self.cases.len() == 1 {
                bare[1] = bare[0];
                bal[1] = bal[0];
            }
            let c = self.link.pose(phi).ok_or(BalanceError::NoPose { phi })?.c;
            series.push(Sample {
                phi,
                reach: foot_offset - c.x,
                bare,
                balanced: bal,
                loaded: last.expect("at least one case"),
            });
        }
        Ok(series)
    }

    /// The check: the statics' drive torque against virtual work at [`VW_POSITIONS`]
    /// equally spaced angles, ends included; it passes where |T − T_vw| is within the stated
    /// errors (the statics', the stencil's and 1e-12 |T_vw|) everywhere.
    fn virtual_work_check(&self) -> Result<VirtualWorkCheck, BalanceError> {
        let [p0, p1] = self.link.phi_range;
        let mut vw = VirtualWorkCheck {
            positions: VW_POSITIONS,
            max_difference_nm: 0.0,
            max_stated_error_nm: 0.0,
            pass: true,
        };
        for i in 0..VW_POSITIONS {
            let phi = p0 + (p1 - p0) * i as f64 / (VW_POSITIONS - 1) as f64;
            // Inside the range by the stencil's reach, so every pose assembles.
            let phi = phi.clamp(p0 + VW_STEP, p1 - VW_STEP);
            for &(_, q) in &self.cases {
                let s = self.at(phi, q, 0.0, [0.0; 2])?;
                let (t_vw, e_vw) = virtual_work_torque(
                    self.link,
                    phi,
                    VW_STEP,
                    &self.w,
                    q,
                    self.scene.rope.as_ref(),
                )
                .ok_or(BalanceError::NoPose { phi })?;
                let diff = (s.drive_torque - t_vw).abs();
                let stated = s.drive_torque_error + e_vw + 1e-12 * t_vw.abs();
                vw.max_difference_nm = vw.max_difference_nm.max(diff);
                vw.max_stated_error_nm = vw.max_stated_error_nm.max(stated);
                vw.pass &= diff <= stated;
            }
        }
        Ok(vw)
    }
}

/// The counterweight of the engine's solution: its first moment u, |u|, its direction (in
/// [0, 2π), or within the allowed sector), the mass m = |u|/ℓ at the full lever, the peak
/// drive torque with its lower bound and error.
fn counterweight_of(sol: &mm::Solution, spec: &CounterweightSpec) -> Counterweight {
    let cw = sol.counterweight(0);
    let u = cw.first_moment;
    let un = u[0].hypot(u[1]);
    let m = un / spec.lever;
    Counterweight {
        status: sol.status,
        note: sol.note.clone(),
        static_moment_kgm: u,
        static_moment_magnitude_kgm: un,
        // In [0, 2π), or within the allowed sector when one is given.
        direction_rad: if un > 0.0 {
            let a = u[1].atan2(u[0]).rem_euclid(std::f64::consts::TAU);
            match spec.directions {
                Some((lo, _)) => lo + (a - lo).rem_euclid(std::f64::consts::TAU),
                None => a,
            }
        } else {
            0.0
        },
        mass_kg: m,
        lever_m: spec.lever,
        peak_drive_torque_nm: sol.objective,
        lower_bound_nm: sol.lower_bound,
        error_nm: sol.error.total,
        rounds: sol.rounds,
    }
}

/// The load's path with an inclined hoist rope (thesis §2.2, Fig 2.3): the load hangs at
/// y_L = y_C + |S − C|/n (up to a constant), so a level head does not give a level load.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LoadPath {
    /// S (m, frame of A).
    pub sheave_m: [f64; 2],
    /// n, the falls.
    pub parts: f64,
    /// Δh_L = max − min of the load's height over the luffing range (m).
    pub load_delta_h_m: f64,
    /// Bound on its error (m): refinement of both extrema plus the pose's rounding.
    pub load_delta_h_error_m: f64,
    /// φ of the highest and of the lowest load position (rad).
    pub phi_at_max_rad: f64,
    /// See `phi_at_max_rad`.
    pub phi_at_min_rad: f64,
    /// The thesis's h3 = y_L1 − y_L3: how much higher the load hangs at maximum reach than at
    /// minimum reach for a level head, which the linkage would have to make up (m).
    pub h3_m: f64,
}

/// The load's path over the luffing range of `link` with the rope `rope`: every sampled
/// extremum of y_L refined by Brent to `xtol` ([`interval_peak`], `n` samples).
pub fn load_path(link: &Linkage, rope: &HoistRope, n: usize, xtol: f64) -> Option<LoadPath> {
    let [p0, p1] = link.phi_range;
    let y = |phi: f64| link.pose(phi).map_or(f64::NAN, |p| rope.load_height(p.c));
    let hi = interval_peak(y, p0, p1, n, xtol).ok()?;
    let lo = interval_peak(|phi| -y(phi), p0, p1, n, xtol).ok()?;
    // The head's rounding (64ε·scale/k2, as for Δh) and the rope length's.
    let rounding = 64.0 * f64::EPSILON * link.length_scale() * (1.0 + 1.0 / link.k2);
    Some(LoadPath {
        sheave_m: [rope.sheave.x, rope.sheave.y],
        parts: rope.parts,
        load_delta_h_m: hi.peak.fx + lo.peak.fx,
        load_delta_h_error_m: hi.error + lo.error + rounding,
        phi_at_max_rad: hi.peak.x,
        phi_at_min_rad: lo.peak.x,
        h3_m: y(p0) - y(p1),
    })
}
