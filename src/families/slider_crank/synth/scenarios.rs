//! The operating envelope's scenarios and the design over them (issue 33, item 3): the
//! scene at every vertex of the envelope's box ([`Envelope::scenarios`]), a design's figures
//! there, the worst cases and the quasi-Monte Carlo check over the whole box
//! ([`Envelope::evaluate`]). The envelope's data and result types are in `envelope.rs`.

use super::drive::energy_fluctuation;
use super::envelope::{
    Envelope, EnvelopeOutcome, LengthOf, MassOf, MonteCarlo, VertexFigures, WorstCase,
};
use super::metrics::metrics;
use super::scene::{Objective, Scene, SolveError};
use crate::geom::P2;
use crate::numeric::ordered;
use crate::synth::envelope::{halton_point, vertices};
use rayon::prelude::*;

/// One scenario: the parameters' values and the scene they make.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The parameters' values, in [`Envelope::names`]' order (ω in rad/s, Δm in kg, ΔL in m).
    pub values: Vec<f64>,
    /// The scene at those values (nominal otherwise; without an envelope of its own).
    pub scene: Scene,
}

impl Envelope {
    /// The nominal scenario first, then every vertex of the box (2^k, in binary order of the
    /// parameters' ends: bit i set = parameter i at its upper end).
    pub fn scenarios(&self, nominal: &Scene) -> Vec<Scenario> {
        // The nominal values: the scene's ω, no change of mass or length.
        let mut at_nominal = vec![0.0; self.ranges().len()];
        if self.speed.is_some() {
            at_nominal[0] = nominal.omega;
        }
        // The nominal scene without its envelope, cloned once: each scenario clones that.
        let bare = bare(nominal);
        std::iter::once(at_nominal)
            .chain(vertices(&self.ranges()))
            .map(|v| self.at_bare(&bare, v))
            .collect()
    }

    /// The scenario at `values` (in [`Self::names`]' order).
    pub fn at(&self, nominal: &Scene, values: Vec<f64>) -> Scenario {
        self.at_bare(&bare(nominal), values)
    }

    /// [`Self::at`] from the nominal scene without its envelope ([`bare`]).
    fn at_bare(&self, bare: &Scene, values: Vec<f64>) -> Scenario {
        let mut s = bare.clone();
        let mut v = values.iter();
        if self.speed.is_some() {
            s.omega = *v.next().expect("one value per parameter");
        }
        for m in &self.masses {
            add_mass(&mut s, m.of, *v.next().expect("one value per parameter"));
        }
        for l in &self.lengths {
            add_length(&mut s, l.of, *v.next().expect("one value per parameter"));
        }
        Scenario { values, scene: s }
    }
}

/// The scene without its envelope (a scenario is a single scene).
fn bare(scene: &Scene) -> Scene {
    Scene {
        envelope: Envelope::default(),
        ..scene.clone()
    }
}

/// Adds Δm to what `of` names in `s`.
fn add_mass(s: &mut Scene, of: MassOf, dm: f64) {
    let m = &mut s.mech;
    match of {
        MassOf::Slider => m.slider_mass += dm,
        MassOf::CrankPin => {
            let total = m.crank.mass + dm;
            if total > 0.0 {
                m.crank.centroid = (m.crank.mass * m.crank.centroid + dm * m.r) / total;
            }
            m.crank.mass = total;
        }
        MassOf::Crank => m.crank.mass += dm,
        MassOf::Rod => {
            let f = (m.rod.mass + dm) / m.rod.mass;
            m.rod.mass += dm;
            m.rod.inertia *= f;
        }
    }
}

/// Adds ΔL to what `of` names in `s`, keeping the centroids at their fractions.
fn add_length(s: &mut Scene, of: LengthOf, dl: f64) {
    let m = &mut s.mech;
    match of {
        LengthOf::CrankRadius => {
            let f = (m.r + dl) / m.r;
            m.crank.centroid *= f;
            m.r += dl;
        }
        LengthOf::RodLength => {
            let f = (m.l + dl) / m.l;
            m.rod.centroid *= f;
            m.l += dl;
        }
    }
}

/// The design U = `u` with the balancers `b` in one scenario: (force, its error, torque, its
/// error, ΔE and its error where `energy`).
fn figures(s: &Scene, u: P2, b: &[[f64; 2]], energy: bool) -> Result<[f64; 6], SolveError> {
    let s = s.with_balancers(b);
    let m = metrics(&s, u)?;
    let [e, ee] = if energy {
        energy_fluctuation(&s, u)?
    } else {
        [f64::NAN; 2]
    };
    Ok([
        m.peak,
        m.peak_error,
        m.peak_torque,
        m.peak_torque_error,
        e,
        ee,
    ])
}

/// The column of [`figures`] an objective is judged on over an envelope: the peak torque
/// (2), ΔE (4), else the peak force (0).
fn column(objective: Objective) -> usize {
    match objective {
        Objective::MinPeakTorque => 2,
        Objective::MinEnergyFluctuation => 4,
        _ => 0,
    }
}

impl EnvelopeOutcome {
    /// The worst case of the figure `objective` is judged on ([`column`]); `None` for ΔE
    /// where it was not evaluated.
    pub fn worst_for(&self, objective: Objective) -> Option<WorstCase> {
        match column(objective) {
            2 => Some(self.worst_peak_drive_torque),
            4 => self.worst_energy_fluctuation,
            _ => Some(self.worst_peak_shaking_force),
        }
    }
}

/// The worst of column `c` (error in column `c + 1`) over the vertices.
fn worst(rows: &[[f64; 6]], c: usize) -> WorstCase {
    crate::synth::envelope::worst(rows.iter().map(|r| (r[c], r[c + 1])))
        .expect("the nominal scenario at least")
}

impl Envelope {
    /// The worst case over the vertices of the figure `objective` minimises (the peak force,
    /// the peak torque or ΔE) for the design U = `u` without balancers: how a baseline fares
    /// over the envelope.
    pub fn worst_of(
        &self,
        nominal: &Scene,
        u: P2,
        objective: Objective,
    ) -> Result<f64, SolveError> {
        let energy = objective == Objective::MinEnergyFluctuation;
        let c = column(objective);
        self.scenarios(nominal).iter().try_fold(0.0_f64, |w, s| {
            Ok(w.max(figures(&s.scene, u, &[], energy)?[c]))
        })
    }

    /// The design U = `u` (balancers `b`) over the envelope of `nominal`: every vertex, the
    /// worst cases, and the quasi-Monte Carlo check on `monte_carlo` Halton points of the box
    /// (in parallel; each sample's figures depend only on its index).
    pub fn evaluate(
        &self,
        nominal: &Scene,
        u: P2,
        b: &[[f64; 2]],
        energy: bool,
    ) -> Result<EnvelopeOutcome, SolveError> {
        let scen = self.scenarios(nominal);
        let rows = scen
            .iter()
            .map(|s| figures(&s.scene, u, b, energy))
            .collect::<Result<Vec<_>, _>>()?;
        let vertices = scen
            .iter()
            .zip(&rows)
            .map(|(s, r)| VertexFigures {
                values: s.values.clone(),
                peak_shaking_force_n: r[0],
                peak_shaking_force_error_n: r[1],
                peak_drive_torque_nm: r[2],
                peak_drive_torque_error_nm: r[3],
                energy_fluctuation_j: energy.then_some(r[4]),
                energy_fluctuation_error_j: energy.then_some(r[5]),
            })
            .collect();
        let (wf, wt) = (worst(&rows, 0), worst(&rows, 2));
        let we = energy.then(|| worst(&rows, 4));
        let monte_carlo = (self.monte_carlo > 0)
            .then(|| self.monte_carlo_check(nominal, u, b, [Some(wf), Some(wt), we]))
            .transpose()?;
        Ok(EnvelopeOutcome {
            parameters: self.names(),
            vertices,
            worst_peak_shaking_force: wf,
            worst_peak_drive_torque: wt,
            worst_energy_fluctuation: we,
            monte_carlo,
            certified: self.certified(),
        })
    }

    /// The Halton points 1..=N of the box, each a scenario: the largest figures and how many
    /// exceed the vertices' worst cases `w` (force, torque, ΔE) beyond their errors.
    fn monte_carlo_check(
        &self,
        nominal: &Scene,
        u: P2,
        b: &[[f64; 2]],
        w: [Option<WorstCase>; 3],
    ) -> Result<MonteCarlo, SolveError> {
        let ranges = self.ranges();
        let energy = w[2].is_some();
        let point = |i: usize| halton_point(&ranges, i);
        let rows = ordered(
            (1..=self.monte_carlo)
                .into_par_iter()
                .map(|i| figures(&self.at(nominal, point(i)).scene, u, b, energy)),
        )?;
        let beyond = |r: &[f64; 6]| {
            [0, 2, 4]
                .iter()
                .zip(&w)
                .any(|(&c, wc)| wc.is_some_and(|wc| r[c] > wc.value + wc.error + r[c + 1]))
        };
        let (kf, rf) = rows
            .iter()
            .enumerate()
            .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
            .expect("at least one sample");
        let max_of = |c: usize| rows.iter().map(|r| r[c]).fold(f64::NEG_INFINITY, f64::max);
        Ok(MonteCarlo {
            samples: rows.len(),
            max_peak_shaking_force_n: rf[0],
            max_force_values: point(kf + 1),
            max_peak_drive_torque_nm: max_of(2),
            max_energy_fluctuation_j: energy.then(|| max_of(4)),
            beyond_worst_case: rows.iter().filter(|r| beyond(r)).count(),
        })
    }
}
