//! A family written outside the crate (issue 32, "adding a family"): the Scotch yoke with a
//! crank counterweight, in the files a new family writes — `model` (physics), `file` (its
//! problem file), `solve` (every number), `numbers` (the numbers shaped), `report` (the documents drawn),
//! `study` (its ladder) — one `cwsynth::family_folder!` line and one `register` call. It
//! then loads, solves, batches and studies through the library unchanged.
//!
//! The physics, independent of every shipped family: crank radius R at speed ω, the yoke of
//! mass m_s at x = R cos φ (exactly), the rotating mass m_r at the crank pin, a counterweight
//! of unbalance u opposite the pin. The shaking force is
//! F(φ) = ω² ((a − u) cos φ, (b − u) sin φ), a = (m_r + m_s) R, b = m_r R,
//! so |F| peaks at ω² max(|a − u|, |b − u|): convex in u, least at u* = (a + b)/2 — half the
//! yoke balanced — where it is ω² m_s R / 2.

use cwsynth::families::{parse_str, register, solve_scene};
use cwsynth::report::Status;
use std::path::Path;

mod yoke {
    pub mod model {
        /// A Scotch yoke: R (m), m_s, m_r (kg), ω (rad/s).
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct Yoke {
            pub r: f64,
            pub m_s: f64,
            pub m_r: f64,
            pub omega: f64,
        }

        impl Yoke {
            /// |F(φ)| with the counterweight u (kg·m) opposite the pin.
            pub fn force(&self, u: f64, phi: f64) -> f64 {
                let w2 = self.omega * self.omega;
                let (a, b) = ((self.m_r + self.m_s) * self.r, self.m_r * self.r);
                w2 * ((a - u) * phi.cos()).hypot((b - u) * phi.sin())
            }
            /// The peak of |F| over n equally spaced angles (n a multiple of 4 holds both
            /// maxima, φ = 0 and π/2, exactly).
            pub fn peak(&self, u: f64, n: usize) -> f64 {
                (0..n)
                    .map(|k| self.force(u, std::f64::consts::TAU * k as f64 / n as f64))
                    .fold(0.0, f64::max)
            }
            /// u* = (a + b)/2, the least peak.
            pub fn best_unbalance(&self) -> f64 {
                (self.m_r + 0.5 * self.m_s) * self.r
            }
        }
    }

    pub mod file {
        use super::model::Yoke;
        use cwsynth::problem::limits::{c, Count};
        use cwsynth::problem::{positive, Ctx, FieldError, Input, ProblemError, RawFile, Resolved};
        use cwsynth::units::{AngularSpeed, Length, Mass, Qty, Unbalance};
        use serde::Deserialize;

        pub const FAMILY: &str = "scotch-yoke";
        pub const TEMPLATE: &str = "name = \"yoke\"\nfamily = \"scotch-yoke\"\n\
            [mechanism]\ncrank_radius = \"40 mm\"\nyoke_mass = \"2 kg\"\n\
            rotating_mass = \"0.5 kg\"\nspeed = \"1500 rpm\"\n\
            [design]\nmax_unbalance = \"1 kg*m\"\n[objective]\nminimize = \"peak\"\n";
        pub const COUNTS: &[Count] = &[c("accuracy.samples", 4, 100_000)];

        #[derive(Debug, Deserialize, schemars::JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct MechanismRaw {
            pub crank_radius: Qty<Length>,
            pub yoke_mass: Qty<Mass>,
            pub rotating_mass: Qty<Mass>,
            pub speed: Qty<AngularSpeed>,
        }
        #[derive(Debug, Default, Deserialize, schemars::JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct DesignRaw {
            /// The counterweight's unbalance: fixed (an analysis) …
            pub unbalance: Option<Qty<Unbalance>>,
            /// … or free up to this.
            pub max_unbalance: Option<Qty<Unbalance>>,
        }
        #[derive(Debug, Deserialize, schemars::JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct ObjectiveRaw {
            pub minimize: String,
        }
        #[derive(Debug, Default, Deserialize, schemars::JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct AccuracyRaw {
            pub samples: Option<u32>,
        }
        pub type File = RawFile<MechanismRaw, (), DesignRaw, ObjectiveRaw, AccuracyRaw>;

        #[derive(Debug, Clone)]
        pub struct YokeProblem {
            pub yoke: Yoke,
            /// Fixed u, or the range [0, max].
            pub unbalance: Result<f64, f64>,
            pub samples: usize,
        }

        pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<YokeProblem>, ProblemError> {
            File::resolve(ctx, input, |raw: &File| {
                let m = &raw.mechanism;
                let yoke = Yoke {
                    r: positive("mechanism.crank_radius", m.crank_radius.si())?,
                    m_s: positive("mechanism.yoke_mass", m.yoke_mass.si())?,
                    m_r: m.rotating_mass.si(),
                    omega: positive("mechanism.speed", m.speed.si())?,
                };
                let unbalance = match (raw.design.unbalance, raw.design.max_unbalance) {
                    (Some(u), None) => Ok(u.si()),
                    (None, Some(max)) => Err(positive("design.max_unbalance", max.si())?),
                    _ => return Err(FieldError::new("design", "give unbalance or max_unbalance")),
                };
                if raw.objective.minimize != "peak" {
                    return Err(FieldError::new("objective.minimize", "allowed: \"peak\""));
                }
                let samples = raw.accuracy.samples.unwrap_or(360);
                cwsynth::problem::limits::check(COUNTS, "accuracy.samples", samples.into())?;
                Ok(YokeProblem {
                    yoke,
                    unbalance,
                    samples: samples as usize,
                })
            })
        }
    }

    pub mod solve {
        use super::file::YokeProblem;
        use cwsynth::families::Claim;
        use cwsynth::report::Status;

        /// Every number: the design u, its sampled peak and the closed-form optimum.
        #[derive(Debug, Clone)]
        pub struct Solution {
            pub claim: Claim,
            pub u: f64,
            pub peak: f64,
            pub unbalanced_peak: f64,
        }

        pub fn solve(p: &YokeProblem) -> Result<Solution, String> {
            let (u, free, on_bound) = match p.unbalance {
                Ok(u) => (u, false, false),
                Err(max) => {
                    let best = p.yoke.best_unbalance();
                    (best.min(max), true, best > max)
                }
            };
            // The peak is convex piecewise linear in u: its least value is proven.
            let mut claim = Claim::new(
                if free {
                    Status::Optimal
                } else {
                    Status::Analysed
                },
                "closed form u* = (m_r + m_s/2) R; peak sampled where it lies",
            );
            if on_bound {
                claim
                    .warnings
                    .push("the counterweight is at max_unbalance".into());
            }
            Ok(Solution {
                claim,
                u,
                peak: p.yoke.peak(u, p.samples),
                unbalanced_peak: p.yoke.peak(0.0, p.samples),
            })
        }
        pub type Analyses = ();
        pub fn analyse(_: &YokeProblem, _: &Solution) -> Analyses {}
    }

    pub mod numbers {
        use super::file::YokeProblem;
        use super::solve::Solution;
        use cwsynth::families::Scene;
        use cwsynth::report::SolveResult;
        use std::collections::BTreeMap;

        pub fn model(_: &YokeProblem, _: Option<&Solution>) -> BTreeMap<String, serde_json::Value> {
            BTreeMap::from([("kinematics".into(), serde_json::json!("exact: x = R cos φ"))])
        }
        pub fn numbers(_: &Scene, p: &YokeProblem, s: &Solution, r: &mut SolveResult) {
            r.design.insert("unbalance_kgm".into(), s.u);
            r.objectives.insert("peak_shaking_force_n".into(), s.peak);
            r.errors
                .insert("peak_shaking_force_n".into(), 1e-12 * s.peak);
            r.baselines.insert(
                "none".into(),
                BTreeMap::from([("peak_shaking_force_n".into(), s.unbalanced_peak)]),
            );
            r.derived.insert("samples".into(), p.samples as f64);
        }
    }

    pub mod report {
        use super::file::YokeProblem;
        use super::solve::{Analyses, Solution};
        use cwsynth::families::Scene;
        use cwsynth::report::{SolveResult, Table};

        pub fn documents(_: &Scene, p: &YokeProblem, s: &Solution, r: &mut SolveResult) {
            let mut csv = String::from("phi_rad,force_n\n");
            for k in 0..=8 {
                let phi = std::f64::consts::TAU * k as f64 / 8.0;
                csv += &format!("{phi},{}\n", p.yoke.force(s.u, phi));
            }
            r.tables.push(Table {
                suffix: "force".into(),
                caption: "|F|".into(),
                csv,
            });
        }
        pub fn analysis_documents(
            _: &Scene,
            _: &YokeProblem,
            _: &Solution,
            _: &Analyses,
            _: &mut SolveResult,
        ) {
        }
    }

    pub mod study {
        use super::file::YokeProblem;
        use cwsynth::families::{Effect, Ladder, Rung};
        use cwsynth::problem::edit::{v_int, Edit};
        use cwsynth::report::SolveResult;

        pub fn headline(_: &YokeProblem) -> String {
            "objectives.peak_shaking_force_n".into()
        }
        pub fn ladder(_: &YokeProblem) -> Ladder {
            let samples = |n| vec![Edit::Set("accuracy.samples", v_int(n))];
            Ladder {
                reference: samples(4096),
                rungs: vec![Rung::new("6 samples", "accuracy", samples(6))],
            }
        }
        pub fn effects(_: &YokeProblem, _: &SolveResult, _: f64) -> Vec<Effect> {
            vec![("friction".into(), "not modelled".into())]
        }
    }

    cwsynth::family_folder!(
        /// The Scotch yoke with a crank counterweight (a test family).
        ScotchYoke,
        file::YokeProblem
    );
}

/// A family that claims a shipped family's name.
#[derive(Debug)]
struct Impostor;

impl cwsynth::families::Family for Impostor {
    fn name(&self) -> &'static str {
        "slider-crank"
    }
    fn counts(&self) -> &'static [cwsynth::problem::limits::Count] {
        &[]
    }
    fn schema(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
    fn resolve(
        &self,
        ctx: &cwsynth::problem::Ctx,
        input: cwsynth::problem::Input,
    ) -> Result<
        cwsynth::problem::Resolved<std::sync::Arc<dyn cwsynth::families::Machine>>,
        cwsynth::problem::ProblemError,
    > {
        cwsynth::families::Family::resolve(&yoke::ScotchYoke, ctx, input)
    }
    fn template(&self) -> &'static str {
        ""
    }
}

fn registered() {
    register(&yoke::ScotchYoke).unwrap();
}

#[test]
fn a_family_from_outside_solves_against_its_closed_form() {
    registered();
    let s = parse_str(yoke::file::TEMPLATE, Path::new("yoke.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let (rr, ms, w) = (0.04, 2.0, 1500.0 * std::f64::consts::TAU / 60.0);
    let best = w * w * ms * rr / 2.0;
    assert!((r.objectives["peak_shaking_force_n"] - best).abs() <= 1e-9 * best);
    assert!((r.design["unbalance_kgm"] - (0.5 + 1.0) * rr).abs() < 1e-15);
    assert_eq!(r.objective.as_deref(), Some("peak_shaking_force_n"));
    // The same family again is a no-op; another family under a name taken is refused.
    registered();
    assert!(register(&cwsynth::families::slider_crank::SliderCrank).is_ok());
    assert!(register(&Impostor).is_err());
    // A bad file names its field.
    let bad = yoke::file::TEMPLATE.replace("\"2 kg\"", "2");
    let e = parse_str(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.toml") && e.contains("mechanism.yoke_mass"),
        "{e}"
    );
}

#[test]
fn a_family_from_outside_runs_through_batch_and_study() {
    registered();
    let dir = tempfile::tempdir().unwrap();
    let (inp, out) = (dir.path().join("in"), dir.path().join("out"));
    std::fs::create_dir_all(&inp).unwrap();
    std::fs::write(inp.join("yoke.toml"), yoke::file::TEMPLATE).unwrap();
    let analysis = yoke::file::TEMPLATE
        .replace("max_unbalance = \"1 kg*m\"", "unbalance = \"0.05 kg*m\"")
        .replace("name = \"yoke\"", "name = \"yoke-given\"");
    std::fs::write(inp.join("yoke-given.toml"), analysis).unwrap();
    let opts = cwsynth::batch::Options {
        out: out.clone(),
        threads: Some(2),
        shard: None,
        quiet: true,
        summary_only: false,
        units: Default::default(),
    };
    let inputs = cwsynth::batch::expand(&[inp.display().to_string()]).unwrap();
    cwsynth::batch::run(inputs, &opts).unwrap();
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(summary.contains("yoke,scotch-yoke,optimal"), "{summary}");
    assert!(
        summary.contains("yoke-given,scotch-yoke,analysed"),
        "{summary}"
    );
    assert!(out.join("yoke-force.csv").exists() && out.join("yoke.md").exists());
    let st = cwsynth::study::study(yoke::file::TEMPLATE, Path::new("yoke.toml"), 1).unwrap();
    assert_eq!(st.family, "scotch-yoke");
    assert_eq!(st.rungs.len(), 3, "default, one rung, reference");
}
