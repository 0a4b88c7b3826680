//! The operating envelope (issue 33, item 3; `../shared/domain/machine-as-it-runs.md`): the
//! speed, masses and lengths as intervals, so that every objective and limit means "over the
//! whole envelope".
//!
//! Masses enter the shaking force, the drive torque and the energy curve affinely, and ω²
//! multiplies the inertial parts (the weights do not depend on it): at a fixed design and
//! angle each figure is affine in every one of these parameters separately, so its magnitude
//! (and ΔE, a max minus a min of affine functions) is convex in each, and its maximum over a
//! box of them is reached at a vertex of the box. "Minimise the worst case" is then the
//! minimax over angle × vertices: one cone program, certified exactly (`optimal`).
//!
//! Lengths (a crank radius or rod length tolerance) enter the kinematics non-linearly: their
//! vertices are added to the scenarios the design is optimised over, but nothing proves the
//! worst case is at one of them, so a scene with length tolerances claims `best_found`, with
//! the Monte Carlo check over the whole box as its evidence.

pub use crate::synth::envelope::{WorstCase, MAX_PARAMETERS};

/// What a mass interval changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MassOf {
    /// The slider's mass m4 (a mass item reduced to the slider, or `slider_mass`).
    Slider,
    /// A mass at the crank pin (a mass item reduced there): the crank's mass and centroid.
    CrankPin,
    /// The crank's own mass m2 at its centroid (`crank_mass`).
    Crank,
    /// The rod's mass m3, its moment of inertia scaled with it (a casting tolerance).
    Rod,
}

/// A mass interval: Δm ∈ [lo, hi] (kg) added to the nominal.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MassRange {
    /// The key or item it comes from (`slider_mass`, a mass item's name, …).
    pub name: String,
    /// What it changes.
    pub of: MassOf,
    /// Δm at the interval's ends (kg), lo ≤ 0 ≤ hi not required.
    pub delta: (f64, f64),
}

/// What a length tolerance changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthOf {
    /// R (the crank's centroid kept at the same fraction of R).
    CrankRadius,
    /// L (the rod's centroid kept at the same fraction of L).
    RodLength,
}

/// A length interval: ΔL ∈ [lo, hi] (m) added to the nominal.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LengthRange {
    /// `crank_radius` or `rod_length`.
    pub name: String,
    /// What it changes.
    pub of: LengthOf,
    /// ΔL at the interval's ends (m).
    pub delta: (f64, f64),
}

/// The envelope of a scene: empty for a nominal scene.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct Envelope {
    /// ω ∈ [ω_min, ω_max] (rad/s).
    pub speed: Option<(f64, f64)>,
    /// Mass intervals.
    pub masses: Vec<MassRange>,
    /// Length tolerances.
    pub lengths: Vec<LengthRange>,
    /// Monte Carlo samples of the check (0: none).
    pub monte_carlo: usize,
    /// Whether the result carries the sensitivity table (`super::sensitivity`).
    pub sensitivities: bool,
}

impl Envelope {
    /// True for a nominal scene (no interval).
    pub fn is_empty(&self) -> bool {
        self.speed.is_none() && self.masses.is_empty() && self.lengths.is_empty()
    }

    /// True when the worst case over the box is proven at its vertices (no length tolerance).
    pub fn certified(&self) -> bool {
        self.lengths.is_empty()
    }

    /// The index of the first length parameter in [`Self::names`]' order.
    pub fn first_length(&self) -> usize {
        usize::from(self.speed.is_some()) + self.masses.len()
    }

    /// The parameters' names with their units, in order: `speed_rad_s`, then `<mass>_delta_kg`
    /// for each mass, then `<length>_delta_m`.
    pub fn names(&self) -> Vec<String> {
        let speed = self.speed.map(|_| "speed_rad_s".to_string());
        speed
            .into_iter()
            .chain(self.masses.iter().map(|m| format!("{}_delta_kg", m.name)))
            .chain(self.lengths.iter().map(|l| format!("{}_delta_m", l.name)))
            .collect()
    }

    /// Parameter `i`'s interval (in [`Self::names`]' order), to change it.
    pub fn range_mut(&mut self, i: usize) -> &mut (f64, f64) {
        let speeds = usize::from(self.speed.is_some());
        match self.speed.as_mut() {
            Some(s) if i == 0 => s,
            _ if i - speeds < self.masses.len() => &mut self.masses[i - speeds].delta,
            _ => &mut self.lengths[i - speeds - self.masses.len()].delta,
        }
    }

    /// Each parameter's interval, in [`Self::names`]' order.
    pub fn ranges(&self) -> Vec<(f64, f64)> {
        self.speed
            .into_iter()
            .chain(self.masses.iter().map(|m| m.delta))
            .chain(self.lengths.iter().map(|l| l.delta))
            .collect()
    }
}

/// A design's figures in one scenario (N, N·m, J).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct VertexFigures {
    /// The parameters' values ([`EnvelopeOutcome::parameters`]' order).
    pub values: Vec<f64>,
    /// max |F| (N).
    pub peak_shaking_force_n: f64,
    /// Its error bound (N).
    pub peak_shaking_force_error_n: f64,
    /// max |T| (N·m).
    pub peak_drive_torque_nm: f64,
    /// Its error bound (N·m).
    pub peak_drive_torque_error_nm: f64,
    /// ΔE (J; with the energy-fluctuation objective).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_j: Option<f64>,
    /// Its error bound (J).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_error_j: Option<f64>,
}

/// The quasi-Monte Carlo check of the worst case over the whole box.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MonteCarlo {
    /// Samples: the Halton points 1..=N of the box (deterministic, whatever the threads).
    pub samples: usize,
    /// The largest peak force over them (N) and its sample's values.
    pub max_peak_shaking_force_n: f64,
    /// The parameters' values where it was reached.
    pub max_force_values: Vec<f64>,
    /// The largest peak torque (N·m).
    pub max_peak_drive_torque_nm: f64,
    /// The largest ΔE (J; with the energy-fluctuation objective).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_energy_fluctuation_j: Option<f64>,
    /// Samples whose figure exceeds the vertices' worst case beyond its error (any figure):
    /// 0 wherever the worst case is proven.
    pub beyond_worst_case: usize,
}

/// The design over the envelope: its figures at every vertex, the worst cases and the check.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EnvelopeOutcome {
    /// The parameters ([`Envelope::names`]).
    pub parameters: Vec<String>,
    /// The nominal scene first, then the vertices.
    pub vertices: Vec<VertexFigures>,
    /// The worst peak force over the vertices.
    pub worst_peak_shaking_force: WorstCase,
    /// The worst peak torque.
    pub worst_peak_drive_torque: WorstCase,
    /// The worst ΔE (with the energy-fluctuation objective).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worst_energy_fluctuation: Option<WorstCase>,
    /// The check over the whole box (absent with `monte_carlo = 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarlo>,
    /// True when the worst case over the box is proven at the vertices (no length tolerance).
    pub certified: bool,
}
