//! `[mechanism.drive]`, shared by every family with a drive torque (issue 33): the motor, a
//! flywheel and the coefficient of speed fluctuation to meet, read and checked once into a
//! [`crate::dynamics::Drive`]. The section's keys are documented in `docs/problem-files.md`
//! ("The drive").

use crate::dynamics::{Drive, Motor};
use crate::problem::FieldError;
use crate::units::{AngularSpeed, Inertia, Qty, Torque};
use serde::Deserialize;

/// `[mechanism.drive]`: the machine at real speed (`crate::dynamics`).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveRaw {
    /// The coefficient of speed fluctuation Cs = (ω_max − ω_min)/ω̄ to meet (dimensionless):
    /// the least flywheel that meets it is computed, beside the textbook one.
    pub cs: Option<f64>,
    /// A flywheel on the input shaft (kg·m²) for the steady state; without it, the least that
    /// meets `cs` (or none).
    pub flywheel: Option<Qty<Inertia>>,
    /// The motor: `"constant-torque"` (default) or a torque–speed line.
    pub motor: Option<MotorRaw>,
}

/// The motor of `[mechanism.drive]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum MotorRaw {
    /// `"constant-torque"`: the mean load, the speed at the nominal `speed`.
    Kind(MotorKind),
    /// `{ rated_torque, rated_speed, no_load_speed }`: T_m(ω) = T_r (ω₀ − ω)/(ω₀ − ω_r).
    Line {
        /// T_r.
        rated_torque: Qty<Torque>,
        /// ω_r.
        rated_speed: Qty<AngularSpeed>,
        /// ω₀ (> ω_r).
        no_load_speed: Qty<AngularSpeed>,
    },
    /// `{ speed = [..], torque = [..] }`: a measured torque–speed characteristic, linear
    /// between the points (2 to 64, speeds strictly increasing, torques strictly decreasing).
    Table {
        /// Speeds ω, strictly increasing.
        #[schemars(length(min = 2, max = MAX_MOTOR_POINTS))]
        speed: Vec<Qty<AngularSpeed>>,
        /// Torques T_m at those speeds, strictly decreasing.
        #[schemars(length(min = 2, max = MAX_MOTOR_POINTS))]
        torque: Vec<Qty<Torque>>,
    },
}

/// Most points of a motor table.
pub const MAX_MOTOR_POINTS: usize = 64;

/// A motor named by its kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum MotorKind {
    /// A constant torque.
    ConstantTorque,
}

/// `[mechanism.drive]` checked: 0 < cs < 2, a flywheel ≥ 0, a motor line with ω₀ > ω_r > 0
/// and T_r > 0.
pub fn resolve(d: &DriveRaw) -> Result<Drive, FieldError> {
    if let Some(cs) = d.cs {
        if !(cs > 0.0 && cs < 2.0) {
            return Err(FieldError::new(
                "mechanism.drive.cs",
                format!("{cs} is out of range; allowed: 0 < cs < 2 (e.g. 0.02 for a compressor)"),
            ));
        }
    }
    let flywheel = match d.flywheel {
        Some(q) if !(q.si() >= 0.0) => {
            return Err(FieldError::new(
                "mechanism.drive.flywheel",
                "allowed: ≥ 0 kg·m²",
            ))
        }
        q => q.map(Qty::si),
    };
    Ok(Drive {
        cs: d.cs,
        flywheel,
        motor: motor(d.motor.as_ref())?,
    })
}

/// The motor: a constant torque by default.
fn motor(m: Option<&MotorRaw>) -> Result<Motor, FieldError> {
    let (rated_torque, rated_speed, no_load_speed) = match m {
        None | Some(MotorRaw::Kind(MotorKind::ConstantTorque)) => return Ok(Motor::ConstantTorque),
        Some(MotorRaw::Table { speed, torque }) => return motor_table(speed, torque),
        Some(MotorRaw::Line {
            rated_torque,
            rated_speed,
            no_load_speed,
        }) => (rated_torque, rated_speed, no_load_speed),
    };
    let (t, wr, w0) = (rated_torque.si(), rated_speed.si(), no_load_speed.si());
    if !(t > 0.0 && wr > 0.0 && w0 > wr) {
        return Err(FieldError::new(
            "mechanism.drive.motor",
            "allowed: rated_torque > 0, 0 < rated_speed < no_load_speed",
        ));
    }
    Ok(Motor::Line {
        rated_torque: t,
        rated_speed: wr,
        no_load_speed: w0,
    })
}

/// A motor table: 2 to [`MAX_MOTOR_POINTS`] points, as many torques as speeds, the speeds
/// positive and strictly increasing, the torques strictly decreasing.
fn motor_table(speed: &[Qty<AngularSpeed>], torque: &[Qty<Torque>]) -> Result<Motor, FieldError> {
    const F: &str = "mechanism.drive.motor";
    let speeds: Vec<f64> = speed.iter().map(|q| q.si()).collect();
    let torques: Vec<f64> = torque.iter().map(|q| q.si()).collect();
    let n = speeds.len();
    if n != torques.len() || !(2..=MAX_MOTOR_POINTS).contains(&n) {
        return Err(FieldError::new(
            F,
            format!(
                "{n} speeds and {} torques; allowed: equal lists of 2 to {MAX_MOTOR_POINTS} points",
                torques.len()
            ),
        ));
    }
    let rising = speeds.windows(2).all(|w| w[1] > w[0]) && speeds[0] >= 0.0;
    let falling = torques.windows(2).all(|w| w[1] < w[0]);
    if !(rising && falling && torques.iter().all(|t| t.is_finite())) {
        return Err(FieldError::new(
            F,
            "allowed: speeds ≥ 0 strictly increasing, torques strictly decreasing (a stable characteristic: one speed for every load)",
        ));
    }
    Ok(Motor::Table { speeds, torques })
}
