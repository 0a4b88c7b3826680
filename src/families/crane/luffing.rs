//! The crane's luffing drive (issue 33): what sizes the luffing motor, from the quasi-static
//! drive torque T(φ) of [`super::balance`] over the luffing stroke [φ_min, φ_max], per load
//! case, without and with the boom counterweight.
//!
//! Luffing is a stroke, not a cycle: the boom goes from maximum to minimum reach and back,
//! so a flywheel and a coefficient of speed fluctuation do not apply. What the designer needs:
//! * the luffing work W = ∫_{φ_min}^{φ_max} T dφ, the energy the drive puts in to luff in
//!   (maximum → minimum reach; luffing out it brakes the same W back), which is the change of
//!   potential energy ΔV = Σ m g Δy of boom, jib, tie, load and counterweight between the end
//!   poses (checked, [`WorkCheck`]);
//! * the mean torque T̄ = W/(φ_max − φ_min);
//! * with a luffing time t_l at a constant boom speed φ̇ = (φ_max − φ_min)/t_l, the peak power
//!   P = max |T|·φ̇ and the mean power W/t_l.
//!
//! W is computed on the luffing range's periodic parameter φ(θ) = φ_mid − ½Δφ cos θ (as the
//! counterweight's minimax, [`super::balance`]): W = ∫₀^π T(φ(θ)) φ′(θ) dθ with
//! φ′ = ½Δφ sin θ, and f(θ) = T(φ(θ)) φ′(θ) is smooth, odd and 2π-periodic, so its
//! antiderivative E from [`crate::dynamics::antiderivatives`] (trapezoidal rule on a grid
//! doubled until settled, spectrally accurate) gives W = E(π) − E(0) + π f̄ with E's stated
//! error twice, plus the torque's own stated error × Δφ.
//!
//! Quasi-static: the inertia of the boom system is neglected. At constant φ̇ it would add
//! T_i = ½ J′(φ) φ̇², J(φ) = Σ m |r_G′|² + I_G ψ′² the generalised inertia (Lagrange; J φ̈ of the
//! starts and stops is not covered). It is bounded, not modelled: point masses at the
//! centroids of boom, jib, tie and at the load (hanging from the head, its swing neglected),
//! and the unknown spin inertias of jib and tie at most m L²/4 (Popoviciu: a body whose mass
//! lies on its pin-to-pin line of length L), so |T_i| ≤ φ̇² (|Σ m r_G′·r_G″| + Σ (m L²/4)
//! |ψ′ ψ″|); the boom and the counterweight turn with φ and add nothing to J′.

use super::balance::{phi_of, Balance, BalanceError, CasePeak, Cases};
use super::statics::potential;
use crate::dynamics::{antiderivatives, DriveSettings};
use crate::geom::{turn, P2};
use crate::numeric::interval_peak;
use crate::units::STANDARD_GRAVITY as G;
use std::f64::consts::PI;

/// What the report says of the luffing drive, in one sentence each.
pub const NOTE: &str = "luffing is a stroke from maximum to minimum reach, not a cycle: a flywheel and a coefficient of speed fluctuation do not apply";

/// The quasi-static assumption, stated.
pub const ASSUMPTION: &str = "quasi-static: the boom system's inertia is neglected (at constant boom speed it adds ½J′(φ)φ̇², bounded by inertia_torque_bound_nm; the acceleration at the start and end of the stroke is not covered); W > 0 is the work to luff in, luffing out the drive brakes it back";

/// The luffing drive of one load case, without or with the counterweight.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LuffingCase {
    /// `empty` or `loaded`.
    pub case: String,
    /// Whether the designed counterweight is on the boom.
    pub with_counterweight: bool,
    /// W = ∫ T dφ from φ_min to φ_max (J).
    pub work_j: f64,
    /// Bound on its error (J): quadrature + the torque's stated error × Δφ.
    pub work_error_j: f64,
    /// ΔV = V(φ_max) − V(φ_min), the change of the weights' potential energy (J).
    pub potential_energy_change_j: f64,
    /// T̄ = W/(φ_max − φ_min) (N·m).
    pub mean_torque_nm: f64,
    /// Bound on its error (N·m).
    pub mean_torque_error_nm: f64,
    /// max |T| over the stroke (N·m), as in `balance`.
    pub peak_torque_nm: f64,
    /// Bound on its error (N·m).
    pub peak_torque_error_nm: f64,
    /// With a luffing time: max |T|·φ̇ (W).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_power_w: Option<f64>,
    /// Bound on its numerical error (W).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_power_error_w: Option<f64>,
    /// With a luffing time: W/t_l (W).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_power_w: Option<f64>,
    /// With a luffing time: the bound on the neglected inertial torque ½|J′|φ̇² (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inertia_torque_bound_nm: Option<f64>,
}

/// The work against the potential energy: |W − ΔV| within W's stated error.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WorkCheck {
    /// max |W − ΔV| over the cases (J).
    pub max_difference_j: f64,
    /// The largest stated error there (J): W's, plus 1e-12 |ΔV| for the potential's rounding.
    pub max_stated_error_j: f64,
    /// Whether every difference is within its stated error.
    pub pass: bool,
}

/// The luffing drive.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LuffingDrive {
    /// [`NOTE`].
    pub note: String,
    /// [`ASSUMPTION`].
    pub assumption: String,
    /// How it was computed.
    pub method: String,
    /// [φ_min, φ_max] (rad).
    pub phi_range_rad: [f64; 2],
    /// t_l (s), with `mechanism.drive.luffing_time`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub luffing_time_s: Option<f64>,
    /// φ̇ = (φ_max − φ_min)/t_l (rad/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boom_speed_rad_s: Option<f64>,
    /// Per load case, without and (designed) with the counterweight.
    pub cases: Vec<LuffingCase>,
    /// W against ΔV.
    pub work_check: WorkCheck,
}

impl LuffingDrive {
    /// The rows of the design: with its counterweight if one is designed, else without.
    fn design_rows(&self) -> impl Iterator<Item = &LuffingCase> {
        let designed = self.cases.iter().any(|c| c.with_counterweight);
        self.cases
            .iter()
            .filter(move |c| c.with_counterweight == designed)
    }

    /// The drive that sizes the motor, with a luffing time: the largest peak power over the
    /// load cases of the design, with its error, and the most the neglected inertia could add
    /// to it, max of `inertia_torque_bound_nm`·φ̇ (W).
    pub fn design_peak_power(&self) -> Option<(f64, f64, f64)> {
        let speed = self.boom_speed_rad_s?;
        let (p, e) = self
            .design_rows()
            .filter_map(|c| Some((c.peak_power_w?, c.peak_power_error_w?)))
            .max_by(|a, b| a.0.total_cmp(&b.0))?;
        let inertia = self
            .design_rows()
            .filter_map(|c| c.inertia_torque_bound_nm)
            .fold(0.0, f64::max);
        Some((p, e, inertia * speed))
    }
}

/// Step of the inertia bound's central differences (rad).
const FD_STEP: f64 = 1e-3;

/// The luffing drive of `bal`, the balance of `link` under `scene`, with the luffing time
/// t_l = `luffing_time` (s) if given (module doc): per column (case, without or with the
/// counterweight) W, ΔV, T̄ = W/Δφ, and with t_l the powers max |T|·φ̇, W/t_l and the inertia
/// bound.
pub fn drive(
    link: &super::model::Linkage,
    scene: &super::balance::BalanceScene,
    bal: &Balance,
    luffing_time: Option<f64>,
) -> Result<LuffingDrive, BalanceError> {
    let c = Cases::new(link, scene);
    let [p0, p1] = link.phi_range;
    let span = p1 - p0;
    let speed = luffing_time.map(|t| span / t);
    let (m, u) = bal
        .counterweight
        .as_ref()
        .map_or((0.0, [0.0; 2]), |cw| (cw.mass_kg, cw.static_moment_kgm));
    // The columns: every case without, then (designed) with the counterweight.
    let mut cols: Vec<(usize, bool)> = (0..c.cases.len()).map(|k| (k, false)).collect();
    if bal.counterweight.is_some() {
        cols.extend((0..c.cases.len()).map(|k| (k, true)));
    }
    let works = works(&c, &cols, m, u)?;
    let mut cases = Vec::with_capacity(cols.len());
    let mut check = WorkCheck {
        max_difference_j: 0.0,
        max_stated_error_j: 0.0,
        pass: true,
    };
    for (&(k, with), &(w, w_err)) in cols.iter().zip(&works) {
        let (name, q) = c.cases[k];
        let dv = potential_change(&c, q, if with { u } else { [0.0; 2] })?;
        let diff = (w - dv).abs();
        let stated = w_err + 1e-12 * dv.abs();
        check.max_difference_j = check.max_difference_j.max(diff);
        check.max_stated_error_j = check.max_stated_error_j.max(stated);
        check.pass &= diff <= stated;
        let peak = peak_of(if with { &bal.balanced } else { &bal.unbalanced }, name);
        let inertia = match speed {
            Some(s) => Some(inertia_bound(
                &c,
                q,
                if with { (m, u) } else { (0.0, [0.0; 2]) },
                s,
            )?),
            None => None,
        };
        cases.push(LuffingCase {
            case: name.into(),
            with_counterweight: with,
            work_j: w,
            work_error_j: w_err,
            potential_energy_change_j: dv,
            mean_torque_nm: w / span,
            mean_torque_error_nm: w_err / span,
            peak_torque_nm: peak.peak_nm,
            peak_torque_error_nm: peak.error_nm,
            peak_power_w: speed.map(|s| peak.peak_nm * s),
            peak_power_error_w: speed.map(|s| peak.error_nm * s),
            mean_power_w: luffing_time.map(|t| w / t),
            inertia_torque_bound_nm: inertia,
        });
    }
    Ok(LuffingDrive {
        note: NOTE.into(),
        assumption: ASSUMPTION.into(),
        method: "W = ∫ T dφ on φ(θ) = φ_mid − ½Δφ cos θ: the antiderivative of T(φ(θ))·½Δφ sin θ by the trapezoidal rule, grid doubled until settled (dynamics::antiderivatives); ΔV in closed form from the end poses; the inertia bound by central differences of the poses (h = 1e-3 rad, inside the range by h), its peak refined by Brent".into(),
        phi_range_rad: link.phi_range,
        luffing_time_s: luffing_time,
        boom_speed_rad_s: speed,
        cases,
        work_check: check,
    })
}

/// The peak of case `name` in `peaks`.
fn peak_of<'p>(peaks: &'p [CasePeak], name: &str) -> &'p CasePeak {
    peaks
        .iter()
        .find(|p| p.case == name)
        .expect("a peak for every case")
}

/// W and its error for each column (case k, with the counterweight (m, u) or without): the
/// antiderivatives of f(θ) = T(φ(θ)) ½Δφ sin θ, W = E(π) − E(0) + π f̄, the error 2 E.error
/// plus Δφ × the largest stated torque error on the grid.
fn works(
    c: &Cases,
    cols: &[(usize, bool)],
    m: f64,
    u: [f64; 2],
) -> Result<Vec<(f64, f64)>, BalanceError> {
    let [p0, p1] = c.link.phi_range;
    let half = 0.5 * (p1 - p0);
    let mut t_err = vec![0.0_f64; cols.len()];
    let mut failed = None;
    let settings = DriveSettings {
        min_samples: 64,
        max_samples: 1 << 14,
        ..DriveSettings::default()
    };
    let e = antiderivatives(
        |theta, out| {
            let phi = phi_of(c.link, theta);
            for (i, &(k, with)) in cols.iter().enumerate() {
                let (mc, uc) = if with { (m, u) } else { (0.0, [0.0; 2]) };
                match c.at(phi, c.cases[k].1, mc, uc) {
                    Ok(s) => {
                        out[i] = s.drive_torque * half * theta.sin();
                        t_err[i] = t_err[i].max(s.drive_torque_error);
                    }
                    Err(e) => {
                        failed.get_or_insert(e);
                        out[i] = f64::NAN;
                    }
                }
            }
        },
        cols.len(),
        &settings,
    );
    if let Some(e) = failed {
        return Err(e);
    }
    let e = e.map_err(|_| BalanceError::NoPose { phi: p0 })?;
    Ok(e.iter()
        .zip(&t_err)
        .map(|(e, &te)| {
            let w = e.eval(PI) - e.eval(0.0) + PI * e.mean;
            (w, 2.0 * e.error + 2.0 * half * te)
        })
        .collect())
}

/// ΔV = V(φ_max) − V(φ_min) of the weights with load q and the counterweight of first moment
/// u: [`potential`] plus the counterweight's g·(its world first moment)_y (on the boom
/// g (u_s sin φ − u_n cos φ); on a lever about its fixed pivot).
fn potential_change(c: &Cases, q: f64, u: [f64; 2]) -> Result<f64, BalanceError> {
    let v = |phi: f64| {
        let pose = c.link.pose(phi).ok_or(BalanceError::NoPose { phi })?;
        let v = potential(&pose, c.link, &c.w, q, c.scene.rope.as_ref())
            .ok_or(BalanceError::NoPose { phi })?;
        let cw = c.cw_moment(phi, u).ok_or(BalanceError::NoPose { phi })?;
        Ok::<f64, BalanceError>(v + G * cw.y)
    };
    let [p0, p1] = c.link.phi_range;
    Ok(v(p1)? - v(p0)?)
}

/// The bound on the neglected inertial torque at boom speed `speed` with load q (module doc):
/// the peak over the range of φ̇² (|Σ m r_G′·r_G″| + Σ (m L²/4) |ψ′ψ″|), plus its refinement
/// error.
fn inertia_bound(c: &Cases, q: f64, cw: (f64, [f64; 2]), speed: f64) -> Result<f64, BalanceError> {
    let [p0, p1] = c.link.phi_range;
    let (a, b) = (p0 + FD_STEP, p1 - FD_STEP);
    let f = |phi: f64| inertia_term(c, q, cw, phi).unwrap_or(f64::NAN);
    let p = interval_peak(f, a, b, 64, 1e-9).map_err(|_| BalanceError::NoPose { phi: a })?;
    Ok(speed * speed * (p.peak.fx + p.error))
}

/// |Σ m r_G′·r_G″| + Σ (m L²/4) |ψ′ψ″| at φ (kg·m²), by central differences of the poses; a
/// lever's counterweight (m, w) is a point mass at its centroid, moving with the lever (a
/// counterweight on the boom or hung turns or translates with the boom: nothing).
fn inertia_term(c: &Cases, q: f64, cw: (f64, [f64; 2]), phi: f64) -> Option<f64> {
    let h = FD_STEP;
    let super::model::Guide::Circle { centre: pin_b, .. } = c.link.guide else {
        return None;
    };
    let w = &c.w;
    // The points with mass, and the directions of jib and tie, at one angle.
    let at = |phi: f64| -> Option<([P2; 4], [P2; 2])> {
        let p = c.link.pose(phi)?;
        let load = match &c.scene.rope {
            Some(r) => P2::new(p.c.x, r.load_height(p.c)),
            None => p.c,
        };
        Some((
            [
                p.d * w.boom_centroid,
                p.d + (p.c - p.d) * w.jib_centroid,
                (p.e + pin_b) * 0.5,
                load,
            ],
            [p.c - p.e, p.e - pin_b],
        ))
    };
    let ((r_m, d_m), (r_0, d_0), (r_p, d_p)) = (at(phi - h)?, at(phi)?, at(phi + h)?);
    let masses = [w.boom_mass, w.jib_mass, w.tie_mass, q];
    let translation: f64 = (0..4)
        .map(|i| {
            let v = (r_p[i] - r_m[i]) / (2.0 * h);
            let acc = (r_p[i] - r_0[i] * 2.0 + r_m[i]) / (h * h);
            masses[i] * v.dot(&acc)
        })
        .sum();
    // ψ′ and ψ″ from the turns between the three poses.
    let spin: f64 = [(w.jib_mass, 0), (w.tie_mass, 1)]
        .iter()
        .map(|&(mass, j)| {
            let (back, fwd) = (turn(d_m[j], d_0[j]), turn(d_0[j], d_p[j]));
            let rate = (back + fwd) / (2.0 * h);
            let acc = (fwd - back) / (h * h);
            let len = d_0[j].norm();
            mass * len * len / 4.0 * (rate * acc).abs()
        })
        .sum();
    let lever = match c.lever {
        Some(_) if cw.0 > 0.0 => {
            let r = |p: f64| c.cw_moment(p, cw.1).map(|w| w / cw.0);
            let (r_m, r_0, r_p) = (r(phi - h)?, r(phi)?, r(phi + h)?);
            let v = (r_p - r_m) / (2.0 * h);
            let acc = (r_p - r_0 * 2.0 + r_m) / (h * h);
            cw.0 * v.dot(&acc)
        }
        _ => 0.0,
    };
    Some((translation + lever).abs() + spin)
}
