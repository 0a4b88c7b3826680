//! The linkage's operating envelope (issue 33, item 3): a speed band and link-mass intervals,
//! so that every objective and limit means "the worst case over them".
//!
//! A link's mass interval scales its inertial parameters p = (m, m c_x, m c_y, I_P) together
//! (a denser or a larger casting of the same shape: the centroid stays, the inertia scales
//! with the mass). The shaking force F, the shaking moment M_O, the input torque T and the
//! joint loads are linear in every link's p, and ω² multiplies their inertial part (the
//! weights and process loads do not depend on it), so at a fixed design and angle each is
//! affine in every parameter separately; its magnitude — and ΔE, a max minus a min of affine
//! functions — is convex in each, and its maximum over the box is at a vertex
//! (`crate::synth::envelope`). "Minimise the worst case" is then one cone program over
//! angle × vertices, certified exactly.
//!
//! Named load cases (`[[mechanism.load_cases]]`, each its own set of process loads in place
//! of the file's) are a finite list: every vertex is solved in every case, the nominal loads
//! first, so the worst case over them is exact. Process loads enter the input torque, ΔE
//! and the joint loads only (the frame reacts them): the shaking force and moment are the
//! same in every case.
//!
//! A link's length tolerance (its distance to its tip, [`Linkage::with_length`]) enters the
//! kinematics non-linearly: its ends are among the scenarios, but the worst case over its
//! band is not proven there ([`LinkageEnvelope::certified`]), and the claim is `best_found`
//! with the quasi-Monte Carlo check as its evidence.

use crate::families::linkage::model::{Inertia, Linkage, LinkageError, ProcessLoad};
pub use crate::problem::envelope::NOMINAL;

/// A named load case: process loads in place of the file's `[[mechanism.loads]]`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinkageLoadCase {
    /// Its name.
    pub name: String,
    /// Its loads (none: the machine running idle).
    #[serde(skip)]
    pub loads: Vec<ProcessLoad>,
}

/// One scenario: a load case (0: the file's own loads, c ≥ 1: `cases[c − 1]`), the box's
/// vertex and the parameters' values.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The load case.
    pub case: usize,
    /// The vertex ([`crate::synth::envelope::vertices`]' index); `None`: the nominal scene.
    pub vertex: Option<usize>,
    /// The parameters' values ([`LinkageEnvelope::names`]' order).
    pub values: Vec<f64>,
}

/// A link's mass interval.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinkMassRange {
    /// The link's name.
    pub name: String,
    /// The link's index.
    pub link: usize,
    /// Its mass at the interval's ends (kg); the nominal mass is positive.
    pub mass: (f64, f64),
}

/// A link's length tolerance.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinkLengthRange {
    /// The link's name.
    pub name: String,
    /// The link's index.
    pub link: usize,
    /// Its nominal length: the distance to its tip (m).
    pub nominal: f64,
    /// The change of length at the interval's ends (m), (−t, t).
    pub delta: (f64, f64),
    /// A uniform bar: its centroid and inertia follow the length.
    pub bar: bool,
}

/// The envelope of a linkage scene: empty for a nominal scene.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct LinkageEnvelope {
    /// ω ∈ [ω_min, ω_max] (rad/s).
    pub speed: Option<(f64, f64)>,
    /// Link-mass intervals.
    pub masses: Vec<LinkMassRange>,
    /// Link-length tolerances (their worst case is sampled, not proven).
    pub lengths: Vec<LinkLengthRange>,
    /// Monte Carlo samples of the check (0: none).
    pub monte_carlo: usize,
    /// The sensitivity table: dV*/d(end) of the optimised worst case for every interval end,
    /// from the optimum's multipliers.
    pub sensitivities: bool,
    /// Named load cases after the nominal one (the file's own loads).
    pub cases: Vec<LinkageLoadCase>,
}

impl LinkageEnvelope {
    /// True for a nominal scene (no interval).
    pub fn is_empty(&self) -> bool {
        self.speed.is_none()
            && self.masses.is_empty()
            && self.lengths.is_empty()
            && self.cases.is_empty()
    }

    /// The load case c's name: [`NOMINAL`] for 0.
    pub fn case_name(&self, c: usize) -> &str {
        match c {
            0 => NOMINAL,
            c => &self.cases[c - 1].name,
        }
    }

    /// The scenarios of the engine's blocks, in order: the nominal scene, then the box's
    /// vertices ([`crate::synth::envelope::vertices`]' order) in the nominal load case, then
    /// the same vertices in each named case: block 1 + c·2ⁿ + v is vertex v in case c.
    pub fn scenarios(&self, l: &Linkage) -> Vec<Scenario> {
        let vs = crate::synth::envelope::vertices(&self.ranges());
        let nominal = Scenario {
            case: 0,
            vertex: None,
            values: self.nominal(l),
        };
        let all = (0..=self.cases.len()).flat_map(|case| {
            vs.iter().enumerate().map(move |(v, values)| Scenario {
                case,
                vertex: Some(v),
                values: values.clone(),
            })
        });
        std::iter::once(nominal).chain(all).collect()
    }

    /// How a scenario's fields are named in messages: `""` for the nominal scene, else
    /// `" at vertex N"` (1-based), with its load case where the file has them.
    pub fn label(&self, s: &Scenario) -> String {
        match (s.vertex, self.cases.is_empty()) {
            (None, _) => String::new(),
            (Some(v), true) => format!(" at vertex {}", v + 1),
            (Some(v), false) => format!(
                " at vertex {} in load case \"{}\"",
                v + 1,
                self.case_name(s.case)
            ),
        }
    }

    /// The linkage `l` in load case `case` (its loads in place of `l`'s) at the parameters'
    /// `values` ([`Self::at`]).
    pub fn at_case(
        &self,
        l: &Linkage,
        case: usize,
        values: &[f64],
    ) -> Result<Linkage, LinkageError> {
        match case {
            0 => self.at(l, values),
            c => self.at(
                &l.clone().with_loads(self.cases[c - 1].loads.clone())?,
                values,
            ),
        }
    }

    /// True where the worst case over the box is proven at its vertices: no length
    /// tolerance (lengths enter the kinematics non-linearly).
    pub fn certified(&self) -> bool {
        self.lengths.is_empty()
    }

    /// The index of the first length parameter in [`Self::names`]' order.
    pub fn first_length(&self) -> usize {
        usize::from(self.speed.is_some()) + self.masses.len()
    }

    /// The parameters' names with their units, in order: `speed_rad_s`, then
    /// `<link>_mass_kg` for each mass interval, then `<link>_length_delta_m` for each length
    /// tolerance.
    pub fn names(&self) -> Vec<String> {
        let speed = self.speed.map(|_| "speed_rad_s".to_string());
        speed
            .into_iter()
            .chain(self.masses.iter().map(|m| format!("{}_mass_kg", m.name)))
            .chain(
                self.lengths
                    .iter()
                    .map(|l| format!("{}_length_delta_m", l.name)),
            )
            .collect()
    }

    /// Each parameter's interval, in [`Self::names`]' order.
    pub fn ranges(&self) -> Vec<(f64, f64)> {
        self.speed
            .into_iter()
            .chain(self.masses.iter().map(|m| m.mass))
            .chain(self.lengths.iter().map(|l| l.delta))
            .collect()
    }

    /// The parameters' values of the nominal linkage `l`.
    pub fn nominal(&self, l: &Linkage) -> Vec<f64> {
        self.speed
            .map(|_| l.omega())
            .into_iter()
            .chain(self.masses.iter().map(|m| l.inertia()[m.link].mass))
            .chain(self.lengths.iter().map(|_| 0.0))
            .collect()
    }

    /// The linkage `l` at the parameters' `values` ([`Self::names`]' order): its speed set,
    /// each named link's inertial parameters scaled by m / m_nominal.
    pub fn at(&self, l: &Linkage, values: &[f64]) -> Result<Linkage, LinkageError> {
        let mut out = l.clone();
        let mut v = values.iter().copied();
        if self.speed.is_some() {
            out.set_omega(v.next().expect("one value per parameter"))?;
        }
        for m in &self.masses {
            let new = v.next().expect("one value per parameter");
            let old = l.inertia()[m.link];
            let f = new / old.mass;
            out.set_inertia(
                m.link,
                Inertia {
                    mass: new,
                    centroid: old.centroid,
                    j: old.j * f,
                },
            )?;
        }
        for r in &self.lengths {
            let d = v.next().expect("one value per parameter");
            out = out.with_length(r.link, r.nominal, r.nominal + d, r.bar)?;
        }
        Ok(out)
    }
}
