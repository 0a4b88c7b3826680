//! Dimensional synthesis with the certified balancing in the loop (issue 36): the linkage's
//! own geometry — link lengths, frame pivots, a tracer point — chosen so that the tracer
//! passes through precision points, each candidate balanced by the family's certified cone
//! program ([`super::synth::optimum`]). The search is the shared one
//! ([`crate::synth::search::constrained`]); this module supplies the geometry
//! ([`Synthesis::scene_at`]), the path error ([`path_error`]) and the front's driver
//! ([`synthesise`]).

use super::file::{Goal, LinkageProblem, LinkageScene};
use super::model::{tip_of, Linkage, LinkageError, Point};
use super::synth::{optimum, FORCE, MOMENT, TORQUE};
use crate::families::family::Scene;
use crate::geom::P2;
use crate::report::SolveResult;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::minimax::Settings;
use crate::synth::search::constrained::{self, Found, Shape};
use crate::synth::search::SearchEvidence;

/// What a geometry parameter moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A link's length ([`tip_of`]); a uniform bar's mass properties follow it.
    Length {
        /// The link.
        link: usize,
        /// Whether it is a uniform bar.
        bar: bool,
    },
    /// The x of a link's frame pivot ([`super::file_synthesis::frame_pivot`]).
    PivotX {
        /// The link.
        link: usize,
    },
    /// The y of a link's frame pivot.
    PivotY {
        /// The link.
        link: usize,
    },
    /// The tracer point's x in its link's frame.
    TracerX,
    /// The tracer point's y in its link's frame.
    TracerY,
}

/// One free geometry parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct GeometryParam {
    /// What it is, as the result names it ("length of coupler", "pivot of rocker x").
    pub name: String,
    /// What it moves.
    pub kind: Kind,
    /// Its bounds (m).
    pub bounds: (f64, f64),
}

/// `[objective.path]` resolved: the tracer point and its precision points.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSpec {
    /// The tracer's link.
    pub link: usize,
    /// The tracer in its link's frame (m): the file's, the search's reference.
    pub at: P2,
    /// The precision points (m, world).
    pub points: Vec<P2>,
    /// The crank angle of each point (rad), with timing.
    pub angles: Option<Vec<f64>>,
    /// The path error to meet (m).
    pub max_error: f64,
}

/// `[design.synthesis]` resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Synthesis {
    /// The free parameters, in the order of the search's x.
    pub params: Vec<GeometryParam>,
    /// The multistart's settings.
    pub search: constrained::Settings,
    /// Front points below `max_error`.
    pub front_points: usize,
}

/// Crank angles sampled for the path error before refining each point's nearest one.
pub const PATH_SAMPLES: usize = 360;

/// The scan grid of a candidate's inner program during the search (at most; the file's
/// `accuracy.scan_samples` where smaller): every candidate's optimum is still certified (its
/// peaks refined from the scan, its Lagrangian bound), on a coarser first look for the
/// local maxima; the design found is solved again at the file's settings.
pub const SEARCH_SCAN_SAMPLES: usize = 120;

/// The path error's refinement tolerance in the crank angle (rad).
const ANGLE_TOL: f64 = 1e-10;

impl Synthesis {
    /// The parameters' values in the scene `sc` with the tracer at `at` (the search's
    /// reference, inside the bounds).
    pub fn nominal(&self, sc: &LinkageScene, at: P2) -> Vec<f64> {
        self.params
            .iter()
            .map(|p| match p.kind {
                Kind::Length { link, .. } => {
                    tip_of(sc.linkage.dyads(), sc.crank_length, link).map_or(f64::NAN, |t| t.x)
                }
                Kind::PivotX { link } => {
                    super::file_synthesis::frame_pivot(sc, link).map_or(f64::NAN, |p| p.x)
                }
                Kind::PivotY { link } => {
                    super::file_synthesis::frame_pivot(sc, link).map_or(f64::NAN, |p| p.y)
                }
                Kind::TracerX => at.x,
                Kind::TracerY => at.y,
            })
            .collect()
    }

    /// The scene with the parameters at `x` (lengths first, then pivots) and the tracer
    /// point (the file's `at` where it is not free). Errors where a length or a pivot
    /// leaves no linkage (a length ≤ 0).
    pub fn scene_at(
        &self,
        base: &LinkageScene,
        at: P2,
        x: &[f64],
    ) -> Result<(LinkageScene, P2), LinkageError> {
        let mut sc = base.clone();
        let mut tracer = at;
        let mut pivots: Vec<(usize, P2)> = Vec::new();
        for (p, &v) in self.params.iter().zip(x) {
            match p.kind {
                Kind::Length { link, bar } => {
                    let old = tip_of(sc.linkage.dyads(), sc.crank_length, link)
                        .ok_or(LinkageError::NoLength { link })?
                        .x;
                    sc.linkage = sc.linkage.with_length(link, old, v, bar)?;
                    if link == 0 {
                        sc.crank_length = v;
                    }
                }
                Kind::PivotX { link } | Kind::PivotY { link } => {
                    let i = match pivots.iter().position(|q| q.0 == link) {
                        Some(i) => i,
                        None => {
                            let at = super::file_synthesis::frame_pivot(&sc, link)
                                .unwrap_or_else(P2::zeros);
                            pivots.push((link, at));
                            pivots.len() - 1
                        }
                    };
                    match p.kind {
                        Kind::PivotX { .. } => pivots[i].1.x = v,
                        _ => pivots[i].1.y = v,
                    }
                }
                Kind::TracerX => tracer.x = v,
                Kind::TracerY => tracer.y = v,
            }
        }
        if !pivots.is_empty() {
            sc.linkage = with_pivots(&sc.linkage, &pivots)?;
        }
        Ok((sc, tracer))
    }
}

/// The linkage with the frame pivots of the links `pivots` moved: A0 for the crank, a dyad
/// link's frame point for the others.
fn with_pivots(l: &Linkage, pivots: &[(usize, P2)]) -> Result<Linkage, LinkageError> {
    let at = |link: usize, old: Point| match pivots.iter().find(|p| p.0 == link) {
        Some(&(_, x)) => Point::Frame(x),
        None => old,
    };
    let dyads = l
        .dyads()
        .iter()
        .enumerate()
        .map(|(k, d)| d.remapped(Linkage::dyad_links(k), at, |_, l| l))
        .collect();
    let pivot = pivots.iter().find(|p| p.0 == 0).map_or(l.pivot(), |p| p.1);
    Linkage::new(pivot, dyads, l.inertia().to_vec(), l.omega(), l.gravity())?
        .with_loads(l.loads().to_vec())
}

/// The path error of the tracer at `at` on link `path.link` of `l`: the largest distance
/// from a precision point to the tracer's path, max_i min_θ |X(θ) − Q_i| (with timing,
/// max_i |X(θ_i) − Q_i|), and each point's distance. Without timing each point's nearest
/// sample of [`PATH_SAMPLES`] is refined by Brent's method in the two intervals beside it
/// (to [`ANGLE_TOL`] in θ: the distance's error is second order in it). `None` where the
/// linkage does not assemble at a sampled angle (the crank must turn fully).
pub fn path_error(l: &Linkage, path: &PathSpec, at: P2) -> Option<(f64, Vec<f64>)> {
    let x = |theta: f64| -> Option<P2> {
        let pose = l.pose(theta).ok()?;
        Some(pose.links[path.link].point(at)[0])
    };
    let d: Vec<f64> = match &path.angles {
        Some(angles) => (path.points.iter().zip(angles))
            .map(|(q, &t)| x(t).map(|p| (p - q).norm()))
            .collect::<Option<_>>()?,
        None => {
            let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
            let curve: Vec<P2> = (0..PATH_SAMPLES)
                .map(|k| x(k as f64 * h))
                .collect::<Option<_>>()?;
            path.points
                .iter()
                .map(|q| nearest(&curve, h, *q, &x))
                .collect::<Option<_>>()?
        }
    };
    Some((d.iter().copied().fold(0.0, f64::max), d))
}

/// The distance from `q` to the closed curve X(θ) sampled as `curve` at spacing `h`: each
/// local minimum of the sampled distance refined by Brent's method on [θ_k − h, θ_k + h],
/// the least of them (a curve passing near `q` twice has two).
fn nearest(curve: &[P2], h: f64, q: P2, x: &dyn Fn(f64) -> Option<P2>) -> Option<f64> {
    let n = curve.len();
    let d2: Vec<f64> = curve.iter().map(|p| (p - q).norm_squared()).collect();
    let f = |th: f64| x(th).map_or(f64::NEG_INFINITY, |p| -(p - q).norm_squared());
    let mut best = f64::INFINITY;
    for k in 0..n {
        let (prev, next) = (d2[(k + n - 1) % n], d2[(k + 1) % n]);
        if d2[k] > prev || d2[k] > next {
            continue;
        }
        let t = k as f64 * h;
        let m = crate::numeric::brent_max(f, t - h, t + h, ANGLE_TOL).ok()?;
        best = best.min((-m.fx).max(0.0).min(d2[k]));
    }
    best.is_finite().then(|| best.sqrt())
}

/// The error bound of a path error from [`path_error`]: the refinement's tolerance in θ
/// times the tracer's largest speed |X'| over the samples (a first-order bound, though at a
/// nearest point the distance moves only to second order), plus the poses' round-off,
/// 1e-15 of the mechanism's size times its largest dyad conditioning.
pub fn path_error_bound(l: &Linkage, path: &PathSpec, at: P2) -> f64 {
    let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
    let (mut v, mut size, mut kappa) = (0.0f64, 0.0f64, 1.0f64);
    for k in 0..PATH_SAMPLES {
        if let Ok(pose) = l.pose(k as f64 * h) {
            let x = pose.links[path.link].point(at);
            v = v.max(x[1].norm());
            size = size.max(x[0].norm());
            kappa = kappa.max(pose.kappa());
        }
    }
    let size = path.points.iter().map(|p| p.norm()).fold(size, f64::max);
    v * ANGLE_TOL + 1e-15 * size * kappa
}

/// The field index of the objective's peak, for the goals a shape search can minimise.
pub fn goal_field(g: Goal) -> Option<usize> {
    match g {
        Goal::PeakForce => Some(FORCE),
        Goal::PeakMoment => Some(MOMENT),
        Goal::PeakTorque => Some(TORQUE),
        _ => None,
    }
}

/// The linkage scene as a [`Shape`]: its geometry parameters, its path error and its
/// certified optimum's objective.
pub struct LinkageShape<'a> {
    /// The file's scene.
    pub base: &'a LinkageScene,
    /// The free geometry.
    pub syn: &'a Synthesis,
    /// The path.
    pub path: &'a PathSpec,
    /// The inner program's settings.
    pub settings: Settings,
    bounds: Vec<(f64, f64)>,
}

impl<'a> LinkageShape<'a> {
    /// The shape of the scene `base` with the free geometry `syn`, the path `path` and the
    /// inner program's settings.
    pub fn new(
        base: &'a LinkageScene,
        syn: &'a Synthesis,
        path: &'a PathSpec,
        settings: Settings,
    ) -> Self {
        LinkageShape {
            base,
            syn,
            path,
            settings,
            bounds: syn.params.iter().map(|p| p.bounds).collect(),
        }
    }

    /// The certified optimum of the geometry `x`: its objective and design, `None` unless
    /// the engine certified it (`optimal`).
    pub fn balanced(&self, x: &[f64]) -> Option<(f64, crate::synth::minimax::Solution)> {
        let (sc, _) = self.syn.scene_at(self.base, self.path.at, x).ok()?;
        let field = goal_field(sc.objective.minimize)?;
        let sol = optimum(&sc, &self.settings).ok()??;
        (sol.status == CwStatus::Optimal).then(|| (sol.peaks[field].peak, sol))
    }
}

impl Shape for LinkageShape<'_> {
    fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    fn error(&self, x: &[f64]) -> Option<f64> {
        let (sc, at) = self.syn.scene_at(self.base, self.path.at, x).ok()?;
        path_error(&sc.linkage, self.path, at).map(|e| e.0)
    }

    fn objective(&self, x: &[f64]) -> Option<f64> {
        self.balanced(x).map(|b| b.0)
    }
}

/// A geometry of the front: its parameters, path error and certified objective.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapePoint {
    /// The path error the search was held to (m; `None` for the least-error geometry).
    pub max_error_m: Option<f64>,
    /// The parameters (m), in the order of `parameters`.
    pub x: Vec<f64>,
    /// Its path error (m).
    pub path_error_m: f64,
    /// Its certified optimum's objective (SI), `None` where the balancing is not `optimal`.
    pub objective: Option<f64>,
    /// The search's evidence.
    pub search: SearchEvidence,
}

impl ShapePoint {
    fn of(found: Found, eps: Option<f64>, objective: Option<f64>) -> Self {
        ShapePoint {
            max_error_m: eps,
            path_error_m: found.error,
            objective: found.objective.or(objective),
            x: found.x,
            search: found.evidence,
        }
    }
}

/// What a shape search found: "synthesise first, balance afterwards" (the least path error,
/// then its certified balancing) and the front of path error against the certified
/// objective, the last point at `max_error` the design.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapeOutcome {
    /// The parameters' names.
    pub parameters: Vec<String>,
    /// The file's geometry where it lies in the box: its parameters, path error and
    /// objective (a seed of the searches).
    pub nominal: Option<ShapePoint>,
    /// The least path error, balanced afterwards.
    pub kinematic_first: ShapePoint,
    /// The front, ascending in the path error held to; the last at `max_error`.
    pub front: Vec<ShapePoint>,
}

impl ShapeOutcome {
    /// The design: the front's point at `max_error`.
    pub fn chosen(&self) -> Option<&ShapePoint> {
        self.front.last()
    }
}

/// The shape search of the scene `sc`: the least path error (its geometry then balanced:
/// synthesise first, balance afterwards), then for each ε of the front — `front_points`
/// evenly spaced values below `max_error`, and `max_error` — the least certified objective
/// with the path error ≤ ε, each searched from the Halton points and the previous geometry.
/// `Err` when no geometry of the box meets the path or none balances.
pub fn synthesise(
    sc: &LinkageScene,
    syn: &Synthesis,
    path: &PathSpec,
    settings: &Settings,
) -> Result<ShapeOutcome, String> {
    if goal_field(sc.objective.minimize).is_none() || sc.counterweights.is_empty() {
        return Err("a shape search minimises a peak (force, moment or torque) with counterweights to design".into());
    }
    let inner = Settings {
        scan_samples: settings.scan_samples.min(SEARCH_SCAN_SAMPLES),
        ..*settings
    };
    let shape = LinkageShape::new(sc, syn, path, inner);
    let x0 = syn.nominal(sc, path.at);
    let inside = x0
        .iter()
        .zip(&shape.bounds)
        .all(|(v, b)| (b.0..=b.1).contains(v));
    let nominal = shape.error(&x0).filter(|_| inside).map(|e| ShapePoint {
        max_error_m: None,
        x: x0.clone(),
        path_error_m: e,
        objective: shape.objective(&x0),
        search: SearchEvidence::default(),
    });
    let seeds: Vec<Vec<f64>> = nominal.iter().map(|n| n.x.clone()).collect();
    let kin = constrained::least_error(&shape, &seeds, &syn.search)
        .ok_or("no geometry of the box assembles over the whole turn")?;
    let f_kin = shape.objective(&kin.x);
    let kinematic_first = ShapePoint::of(kin, None, f_kin);
    let e_min = kinematic_first.path_error_m;
    if e_min > path.max_error {
        return Err(format!(
            "the least path error found, {e_min:e} m, exceeds objective.path.max_error = {:e} m",
            path.max_error
        ));
    }
    let f_ref = f_kin
        .or(nominal.as_ref().and_then(|n| n.objective))
        .ok_or("the least-error geometry's balancing is not certified")?;
    let n = syn.front_points;
    let mut front: Vec<ShapePoint> = Vec::new();
    let mut seeds = vec![kinematic_first.x.clone()];
    for j in 1..=n + 1 {
        let eps = e_min + (path.max_error - e_min) * j as f64 / (n + 1) as f64;
        let found = constrained::least_objective(&shape, eps, f_ref, &seeds, &syn.search)
            .ok_or_else(|| format!("no balanced geometry within the path error {eps:e} m"))?;
        seeds.push(found.x.clone());
        front.push(ShapePoint::of(found, Some(eps), None));
    }
    Ok(ShapeOutcome {
        parameters: syn.params.iter().map(|p| p.name.clone()).collect(),
        nominal,
        kinematic_first,
        front,
    })
}

/// The linkage's solve through the one driver: with a shape search not yet run, the search
/// first ([`synthesise`]), then the whole solve of its chosen geometry — the scene the
/// report draws — with the search's outcome in [`LinkageProblem::shape`]; the search's time
/// is added to the solve's. A search that finds no geometry leaves the file's geometry
/// solved, with the reason as a warning.
pub fn drive(scene: &Scene, p: &LinkageProblem) -> SolveResult {
    let (Some(syn), Some(path), None) = (&p.synthesis, &p.path, &p.shape) else {
        return crate::families::driver::drive(scene, p);
    };
    let t0 = std::time::Instant::now();
    let chosen = synthesise(&p.scene, syn, path, &p.settings).and_then(|out| {
        let x = &out.chosen().ok_or("the front is empty")?.x;
        let (sc, at) = syn
            .scene_at(&p.scene, path.at, x)
            .map_err(|e| e.to_string())?;
        super::file::check_full_turn(&sc.linkage).map_err(|e| e.message)?;
        Ok(LinkageProblem {
            scene: sc,
            path: Some(PathSpec { at, ..path.clone() }),
            shape: Some(out),
            ..p.clone()
        })
    });
    let searched = t0.elapsed().as_secs_f64();
    match chosen {
        Ok(q) => {
            let q = std::sync::Arc::new(q);
            let scene = Scene {
                machine: q.clone(),
                ..scene.clone()
            };
            let mut r = crate::families::driver::drive(&scene, q.as_ref());
            r.timing.solve_s += searched;
            r
        }
        Err(why) => {
            let mut r = crate::families::driver::drive(scene, p);
            r.warnings.push(format!(
                "the shape search found no design: {why}; the file's geometry is solved"
            ));
            r
        }
    }
}

/// The claim of a synthesised design: the geometry is a multistart's (`best_found`, the
/// evidence of the search at `max_error`), its counterweights the certified optimum of that
/// geometry (the inner claim's `optimal`, said in the detail). An inner claim other than
/// `optimal` stands as it is.
pub fn claim(shape: &ShapeOutcome, c: &mut crate::families::driver::Claim) {
    let Some(chosen) = shape.chosen() else { return };
    if c.status == crate::report::Status::Optimal {
        c.status = crate::report::Status::BestFound;
        c.status_detail = Some(format!(
            "the geometry ({} parameters) is the best a multistart found, not proven; the counterweights are the certified optimum (optimal) of that geometry",
            shape.parameters.len()
        ));
        c.search = Some(chosen.search.clone());
    }
    c.method = format!(
        "{}; for the geometry found: {}",
        chosen.search.method, c.method
    );
}
