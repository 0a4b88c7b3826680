//! The motor on a machine's input shaft (`[mechanism.drive] motor`): a constant torque, a
//! torque–speed line, or a measured table — its torque at a speed, the speed at which it
//! meets a load, and its steepest slope, for the steady state in [`super`].

/// The motor on the input shaft.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Motor {
    /// A constant torque, equal to the cycle's mean load T̄ (the only constant torque with a
    /// periodic motion); the mean speed is then the nominal one.
    ConstantTorque,
    /// A torque–speed line through (ω_r, T_r) and (ω₀, 0): T_m(ω) = T_r (ω₀ − ω)/(ω₀ − ω_r)
    /// (an induction motor's slip line, ω₀ its synchronous speed; or a hydraulic motor's
    /// characteristic). The mean speed is where the motor and the load agree.
    Line {
        /// Rated torque T_r (N·m).
        rated_torque: f64,
        /// Rated speed ω_r (rad/s).
        rated_speed: f64,
        /// No-load speed ω₀ (rad/s), above ω_r.
        no_load_speed: f64,
    },
    /// A measured torque–speed characteristic (a hydraulic motor's from its displacement, the
    /// pump's flow and the relief pressure; any motor's from its data sheet): T_m(ω) linear
    /// between the points, continued along the end segments beyond them. The torque falls
    /// strictly as the speed rises, so every load has one speed (a stable operating point).
    Table {
        /// Speeds ω (rad/s), strictly increasing, at least two.
        speeds: Vec<f64>,
        /// Torques T_m (N·m) at those speeds, strictly decreasing.
        torques: Vec<f64>,
    },
}

/// The segment k of the strictly increasing `xs` (at least two) to interpolate at `x` on:
/// xs[k] ≤ x < xs[k+1], or an end segment outside them.
fn segment(xs: &[f64], x: f64) -> usize {
    xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1
}

impl Motor {
    /// T_m(ω) (N·m); `mean` is the cycle's mean load T̄ (the constant torque's value).
    #[inline]
    pub fn torque(&self, omega: f64, mean: f64) -> f64 {
        match *self {
            Motor::ConstantTorque => mean,
            Motor::Line {
                rated_torque,
                rated_speed,
                no_load_speed,
            } => rated_torque * (no_load_speed - omega) / (no_load_speed - rated_speed),
            Motor::Table {
                ref speeds,
                ref torques,
            } => {
                let k = segment(speeds, omega);
                let t = (omega - speeds[k]) / (speeds[k + 1] - speeds[k]);
                torques[k] + t * (torques[k + 1] - torques[k])
            }
        }
    }

    /// The steepest |dT_m/dω| (N·m·s/rad) anywhere: a line's slope, a table's steepest
    /// segment's, 0 for a constant torque.
    pub fn max_slope(&self) -> f64 {
        match *self {
            Motor::ConstantTorque => 0.0,
            Motor::Line {
                rated_torque,
                rated_speed,
                no_load_speed,
            } => rated_torque / (no_load_speed - rated_speed),
            Motor::Table {
                ref speeds,
                ref torques,
            } => speeds
                .windows(2)
                .zip(torques.windows(2))
                .map(|(w, t)| ((t[1] - t[0]) / (w[1] - w[0])).abs())
                .fold(0.0, f64::max),
        }
    }

    /// The speed (rad/s) at which a line or a table gives the torque `load` (N·m); `None`
    /// for a constant torque, which gives it at any speed.
    pub fn speed_at(&self, load: f64) -> Option<f64> {
        match *self {
            Motor::ConstantTorque => None,
            Motor::Line {
                rated_torque,
                rated_speed,
                no_load_speed,
            } => Some(no_load_speed - load * (no_load_speed - rated_speed) / rated_torque),
            Motor::Table {
                ref speeds,
                ref torques,
            } => {
                // The torques fall: the segment whose torques bracket the load (or an end's).
                let n = torques.len();
                let k = (0..n - 1)
                    .find(|&k| torques[k + 1] <= load)
                    .unwrap_or(n - 2);
                let t = (load - torques[k]) / (torques[k + 1] - torques[k]);
                Some(speeds[k] + t * (speeds[k + 1] - speeds[k]))
            }
        }
    }
}
