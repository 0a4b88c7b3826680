//! The multi-cylinder's whole solve: the shaking force and couple as fields affine in the
//! designed unbalances ([`Fields`]), their certified minimax by the engine of
//! [`crate::synth::minimax`] (the crank-web counterweights and the balance shafts are its
//! counterweights: mass, first moment, inertia, of which only the first moment enters the
//! fields), the peaks of the bare layout, the harmonics of every order by FFT with and without
//! the design, the textbook's primary and secondary sums, and a peak-force against
//! peak-couple front — every number the result reports.

use super::file::{Goal, MultiCylinderProblem, RotorSpec};
use super::model::{self, Harmonic};
use super::mounts::{self, Frame};
use super::phases;
use crate::families::driver::Claim;
use crate::families::family::cw_status;
use crate::geom::P2;
use crate::report::Status;
use crate::synth::minimax::{
    self, var_u, AffineField, AffineValue, CounterweightLimits, Engine, FieldPeak, ParetoFront,
    Problem,
};
use crate::synth::Shortfall;
use nalgebra::SMatrix;
use rustfft::num_complex::Complex64;

/// Field 0: the shaking force (N); field 1: the couple about z₀ (N·m); fields from
/// [`MOUNTS`] on: each mount's transmitted force normal to the shaft (N).
pub const FORCE: usize = 0;
/// See [`FORCE`].
pub const COUPLE: usize = 1;
/// See [`FORCE`].
pub const MOUNTS: usize = 2;

/// The engine's fields of the mounts' forces normal to the shaft (empty without a frame).
pub fn normal_mounts(p: &MultiCylinderProblem) -> std::ops::Range<usize> {
    let n = p.frame.as_ref().map_or(0, |f| f.mounts.len());
    MOUNTS..MOUNTS + n
}

/// The engine's fields of the mounts' forces along the shaft (reported, not designed for).
pub fn axial_mounts(p: &MultiCylinderProblem) -> std::ops::Range<usize> {
    let r = normal_mounts(p);
    r.end..r.end + r.len()
}

/// The engine's field of the roll moment (after the mounts' axial fields).
pub fn roll_index(p: &MultiCylinderProblem) -> usize {
    axial_mounts(p).end
}

/// The links' shaking moment about the shaft (roll, N·m) as a scalar field:
/// ω²·Σ [`model::Cylinder::roll0`]. Free of the design: a crank-web counterweight or a
/// balance shaft turning at constant speed about the shaft's axis exerts none (a shaft's own
/// axis off the crankshaft's is not modelled: its roll is left out, and said so).
pub struct RollField<'a> {
    /// The scene.
    pub p: &'a MultiCylinderProblem,
}

impl AffineField for RollField<'_> {
    fn name(&self) -> &str {
        "roll moment"
    }
    fn dim(&self) -> usize {
        1
    }
    fn eval(&self, phi: f64, out: &mut AffineValue) {
        let w2 = self.p.omega * self.p.omega;
        let m = self.p.layout.roll0(phi).unwrap_or(f64::NAN);
        out.b = [w2 * m, 0.0];
        out.row_mut(0).fill(0.0);
    }
    fn error(&self, _: f64, _: &[f64]) -> f64 {
        let w2 = self.p.omega * self.p.omega;
        w2 * (self.p.layout.cylinders.iter())
            .map(model::Cylinder::roll_error0)
            .sum::<f64>()
    }
}

/// Samples of a turn for the harmonics' FFT (a power of two).
pub const FFT_SAMPLES: usize = 256;

/// The shaking force or couple of the layout with its designed unbalances, at real speed:
/// g(φ; x) = ω²·[f(φ) + Σⱼ nⱼ² Rot(βⱼ) uⱼ] (force) or its moment about z₀ (couple), uⱼ the
/// first moment of the engine's counterweight j.
pub struct Fields<'a> {
    /// The scene.
    pub p: &'a MultiCylinderProblem,
    /// [`FORCE`] or [`COUPLE`].
    pub which: usize,
}

impl Fields<'_> {
    /// The round-off of the links' part at any φ (N or N·m): per cylinder
    /// [`model::Cylinder::force_error0`], scaled by ω² (and |zᵢ − z₀| for the couple).
    fn links_error(&self) -> f64 {
        let l = &self.p.layout;
        let w2 = self.p.omega * self.p.omega;
        l.cylinders
            .iter()
            .map(|c| {
                let e = c.force_error0();
                let arm = if self.which == COUPLE {
                    (c.z - l.z0).abs()
                } else {
                    1.0
                };
                w2 * e * arm
            })
            .sum()
    }
}

impl AffineField for Fields<'_> {
    fn name(&self) -> &str {
        if self.which == FORCE {
            "shaking force"
        } else {
            "couple"
        }
    }
    fn dim(&self) -> usize {
        2
    }
    fn eval(&self, phi: f64, out: &mut AffineValue) {
        let (p, w2) = (self.p, self.p.omega * self.p.omega);
        let s = p.layout.shaking0(phi).unwrap_or(model::Shaking {
            force: P2::new(f64::NAN, f64::NAN),
            couple: P2::zeros(),
        });
        let b = if self.which == FORCE {
            s.force
        } else {
            s.couple
        };
        out.b = [w2 * b.x, w2 * b.y];
        for (j, r) in p.rotors.iter().enumerate() {
            let k = w2 * r.rotor.speed2();
            let (sb, cb) = r.rotor.angle(phi).sin_cos();
            // Force columns: k·Rot(β) on (u_x, u_y).
            let mut rows = [[k * cb, -k * sb], [k * sb, k * cb]];
            if self.which == COUPLE {
                let arm = r.rotor.z - p.layout.z0;
                let f = rows;
                rows = [
                    [-arm * f[1][0], -arm * f[1][1]],
                    [arm * f[0][0], arm * f[0][1]],
                ];
            }
            for (row, v) in rows.iter().enumerate() {
                let a = out.row_mut(row);
                a[var_u(j)] = v[0];
                a[var_u(j) + 1] = v[1];
            }
        }
    }
    fn error(&self, _: f64, _: &[f64]) -> f64 {
        self.links_error()
    }
}

/// Orders of the bare force and couple the mount fields sum (the rest is in their error).
pub const MOUNT_ORDERS: usize = 64;

/// The force mount k transmits to the ground as a field: normal to the shaft (N, x and y;
/// [`MOUNTS`] on) or along it (N, z; after the normal ones, reported only), each component
/// Re Σₙ H_k(nω)·ŝₙ e^{inφ} with ŝₙ the order's (F̂_x, F̂_y, M̂_x, M̂_y, M̂_z) — the bare layout's from
/// its FFT (orders 1..=[`MOUNT_ORDERS`]), each unbalance's exactly (its one order).
pub struct MountField {
    name: String,
    /// The rows of H_k the field reports: [0, 1] (x, y) or [2] (z).
    rows: &'static [usize],
    /// H_k(nω)·ŝₙ of the bare layout, n = 1.. (x, y, z).
    bare: Vec<[Complex64; 3]>,
    /// Per rotor: its order and the columns of u_x and u_y.
    cols: Vec<(u32, [Complex64; 3], [Complex64; 3])>,
    /// The evaluation error bound (N).
    err: f64,
}

impl AffineField for MountField {
    fn name(&self) -> &str {
        &self.name
    }
    fn dim(&self) -> usize {
        self.rows.len()
    }
    fn eval(&self, phi: f64, out: &mut AffineValue) {
        let mut b = [0.0; 2];
        for (n, c) in self.bare.iter().enumerate() {
            let e = Complex64::from_polar(1.0, (n + 1) as f64 * phi);
            for (i, &row) in self.rows.iter().enumerate() {
                b[i] += (c[row] * e).re;
            }
        }
        out.b = b;
        for (j, (n, cx, cy)) in self.cols.iter().enumerate() {
            let e = Complex64::from_polar(1.0, *n as f64 * phi);
            for (i, &row) in self.rows.iter().enumerate() {
                let a = out.row_mut(i);
                a[var_u(j)] = (cx[row] * e).re;
                a[var_u(j) + 1] = (cy[row] * e).re;
            }
        }
    }
    fn error(&self, _: f64, _: &[f64]) -> f64 {
        self.err
    }
}

/// (F̂_x, F̂_y, M̂_x, M̂_y, M̂_z) of one order from its force, couple and roll coefficients
/// (forward, backward; the roll a real signal sampled as x + 0i, so its amplitude is the
/// x component's).
fn excitation(
    f: [Complex64; 2],
    m: [Complex64; 2],
    roll: [Complex64; 2],
) -> SMatrix<Complex64, 5, 1> {
    let [fx, fy] = mounts::components(f[0], f[1]);
    let [mx, my] = mounts::components(m[0], m[1]);
    let [mz, _] = mounts::components(roll[0], roll[1]);
    SMatrix::<Complex64, 5, 1>::from_column_slice(&[fx, fy, mx, my, mz])
}

/// The mount fields of the scene's frame — each mount's force normal to the shaft, then each
/// mount's along it: the transfer of every order up to 2·[`MOUNT_ORDERS`] (for the error's
/// largest gain), the bare layout's orders by FFT, the unbalances' columns.
pub fn mount_fields(p: &MultiCylinderProblem, frame: &Frame) -> Result<Vec<MountField>, String> {
    let c = |v: [f64; 2]| Complex64::new(v[0], v[1]);
    let n_fft = 4 * MOUNT_ORDERS;
    let x0 = vec![0.0; n_engine(p)];
    let (fb, mb) = (Fields { p, which: FORCE }, Fields { p, which: COUPLE });
    let (zf, zm) = (
        model::samples(n_fft, |phi| value_at(&fb, phi, &x0)),
        model::samples(n_fft, |phi| value_at(&mb, phi, &x0)),
    );
    let rb = RollField { p };
    let zr = model::samples(n_fft, |phi| value_at(&rb, phi, &x0));
    let (hf, hm, hr) = (
        model::harmonics(&zf, MOUNT_ORDERS as u32),
        model::harmonics(&zm, MOUNT_ORDERS as u32),
        model::harmonics(&zr, MOUNT_ORDERS as u32),
    );
    let transfer = |n: usize| {
        let w = n as f64 * p.omega;
        frame.transfer(p.layout.z0, w).ok_or_else(|| {
            format!("the frame on its mounts has an undamped resonance at order {n} ({w:.6} rad/s): its steady state does not exist")
        })
    };
    let table: Vec<_> = (1..=2 * MOUNT_ORDERS)
        .map(transfer)
        .collect::<Result<_, _>>()?;
    let alias = model::alias_bound(&zf) + model::alias_bound(&zm) + model::alias_bound(&zr);
    let tail = 2.0 * MOUNT_ORDERS as f64 * alias
        + fb.links_error()
        + mb.links_error()
        + rb.error(0.0, &x0);
    let axis = |k: usize| (k % frame.mounts.len(), k >= frame.mounts.len());
    Ok((0..2 * frame.mounts.len())
        .map(axis)
        .map(|(k, axial)| {
            let bare = (0..MOUNT_ORDERS)
                .map(|n| {
                    let s = excitation(
                        [c(hf[n].forward), c(hf[n].backward)],
                        [c(hm[n].forward), c(hm[n].backward)],
                        [c(hr[n].forward), c(hr[n].backward)],
                    );
                    let v = table[n][k] * s;
                    [v[0], v[1], v[2]]
                })
                .collect();
            let cols = (p.rotors.iter())
                .map(|r| rotor_columns(p, r, &table[r.rotor.order as usize - 1][k]))
                .collect();
            MountField {
                name: if axial {
                    format!("mount {} axial force", k + 1)
                } else {
                    format!("mount {} force", k + 1)
                },
                rows: if axial { &[2] } else { &[0, 1] },
                bare,
                cols,
                err: gain(&table, k) * tail,
            }
        })
        .collect())
}

/// The largest gain over the table's orders of mount k: max over its rows of Σ|H_ij|.
fn gain(table: &[Vec<SMatrix<Complex64, 3, 5>>], k: usize) -> f64 {
    let row =
        |h: &SMatrix<Complex64, 3, 5>, i: usize| (0..5).map(|j| h[(i, j)].norm()).sum::<f64>();
    table
        .iter()
        .map(|h| (0..3).map(|i| row(&h[k], i)).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

/// The columns of a rotor's u_x and u_y in a mount's force: its force ω²n²(1 or i) turning
/// with (forward) or against (backward) the crank at order n, its couple i(z − z₀) times that.
fn rotor_columns(
    p: &MultiCylinderProblem,
    r: &RotorSpec,
    h: &SMatrix<Complex64, 3, 5>,
) -> (u32, [Complex64; 3], [Complex64; 3]) {
    let k = p.omega * p.omega * r.rotor.speed2();
    let arm = Complex64::new(0.0, r.rotor.z - p.layout.z0);
    let col = |c: Complex64| {
        let zero = Complex64::new(0.0, 0.0);
        let (f, b) = if r.rotor.sense > 0.0 {
            (c, zero)
        } else {
            (zero, c)
        };
        let zero = Complex64::new(0.0, 0.0);
        let v = h * excitation([f, b], [arm * f, arm * b], [zero, zero]);
        [v[0], v[1], v[2]]
    };
    (
        r.rotor.order,
        col(Complex64::new(k, 0.0)),
        col(Complex64::new(0.0, k)),
    )
}

/// g(φ; x) of a planar field as a vector.
pub fn value_at(f: &dyn AffineField, phi: f64, x: &[f64]) -> P2 {
    let mut v = AffineValue::zeros(x.len());
    f.eval(phi, &mut v);
    let g = v.at(2, x);
    P2::new(g[0], g[1])
}

/// The harmonics of one state of the machine (bare, or with the design).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Spectrum {
    /// The force's orders 1..=orders (N).
    pub force: Vec<Harmonic>,
    /// The couple's (N·m).
    pub couple: Vec<Harmonic>,
    /// A bound on every force coefficient's aliasing and round-off (N).
    pub force_error: f64,
    /// The same for the couple (N·m).
    pub couple_error: f64,
}

/// Every number of a solved multi-cylinder scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The claim: `optimal` with the engine's certificate, `analysed` without a design.
    pub claim: Claim,
    /// The bare layout's peaks (force, couple), refined.
    pub bare: Vec<FieldPeak>,
    /// The certified design, when the scene has unbalances to design.
    pub design: Option<minimax::Solution>,
    /// The harmonics of the bare layout.
    pub bare_spectrum: Spectrum,
    /// The harmonics with the design's unbalances.
    pub spectrum: Option<Spectrum>,
    /// The textbook's primary and secondary force and couple (N, N·m; the model's λ).
    pub textbook: [Harmonic; 4],
    /// The peak-force against peak-couple front, if asked for.
    pub front: Option<ParetoFront>,
    /// With `[design.phases]`: every layout tried.
    pub phases: Option<phases::PhaseSearch>,
    /// With `[design.phases]`: the scene with the chosen phases (what the numbers, documents
    /// and motion describe).
    pub chosen: Option<Box<MultiCylinderProblem>>,
}

impl Solution {
    /// The scene the solution describes: the chosen layout's, or `p` itself.
    pub fn scene<'a>(&'a self, p: &'a MultiCylinderProblem) -> &'a MultiCylinderProblem {
        self.chosen.as_deref().unwrap_or(p)
    }
}

impl Solution {
    /// The design vector (zeros for an analysis).
    pub fn x(&self, p: &MultiCylinderProblem) -> Vec<f64> {
        self.design
            .as_ref()
            .map_or_else(|| vec![0.0; n_engine(p)], |d| d.x.clone())
    }
}

/// The engine's vector length: four per rotor, or one inert extra for an analysis.
pub fn n_engine(p: &MultiCylinderProblem) -> usize {
    if p.rotors.is_empty() {
        1
    } else {
        minimax::PER_COUNTERWEIGHT * p.rotors.len()
    }
}

/// The engine's problem: the two fields, a counterweight per rotor (or one inert extra for
/// an analysis), the goal and the limits.
pub fn problem<'a>(p: &MultiCylinderProblem, fields: Vec<&'a dyn AffineField>) -> Problem<'a> {
    let mounts = normal_mounts(p);
    let goal = match p.goal {
        Goal::PeakForce => minimax::Goal::MinPeak(vec![(FORCE, 1.0)]),
        Goal::PeakCouple => minimax::Goal::MinPeak(vec![(COUPLE, 1.0)]),
        Goal::CounterweightMass => minimax::Goal::MinMass,
        Goal::PeakMountForce => minimax::Goal::MinPeak(mounts.clone().map(|k| (k, 1.0)).collect()),
    };
    let mut limits = Vec::new();
    if let Some(e) = p.max_peak_force {
        limits.push((FORCE, e));
    }
    if let Some(e) = p.max_peak_couple {
        limits.push((COUPLE, e));
    }
    if let Some(e) = p.max_mount_force {
        limits.extend(mounts.map(|k| (k, e)));
    }
    Problem {
        fields,
        counterweights: (p.rotors.iter())
            .map(|r| CounterweightLimits::new(r.mass_max, r.radius_max))
            .collect(),
        extra: if p.rotors.is_empty() {
            vec![(0.0, 0.0)]
        } else {
            Vec::new()
        },
        linear: Vec::new(),
        goal,
        limits,
    }
}

/// Solves the scene: its layout, or with `[design.phases]` the best of every admissible
/// layout ([`phases::search`], which keeps the best's whole solution).
pub fn solve(p: &MultiCylinderProblem) -> Result<Solution, String> {
    let Some(step) = p.phase_step else {
        return solve_layout(p);
    };
    let (search, mut sol) = phases::search(p, step, |q| {
        let sol = solve_layout(q)?;
        let (v, e) = headline(q, &sol);
        Ok((v, e, sol.claim.status, sol))
    })?;
    let mut q = p.clone();
    q.phase_step = None;
    let best = &search.candidates[search.best];
    for (c, a) in q.layout.cylinders.iter_mut().zip(&best.phases) {
        c.phase = *a;
    }
    let certified =
        (search.candidates.iter()).all(|c| matches!(c.status, Status::Optimal | Status::Analysed));
    let n = search.candidates.len();
    let firing = p.admissible.as_ref().map_or(String::new(), |a| {
        let order = (a.order.as_deref()).map_or(String::new(), |o| {
            format!(" in the order {}", super::firing::order_text(o))
        });
        format!(", firing evenly{order} in a {} cycle", a.cycle.as_str())
    });
    sol.claim.method = format!(
        "crank phases: the best of {n} layouts (every throw but the first at a multiple of {:.4}°{firing}), each solved: {}",
        step.to_degrees(),
        sol.claim.method
    );
    sol.claim.status = if certified && sol.claim.status != Status::Infeasible {
        Status::Optimal
    } else {
        sol.claim.warnings.push(format!(
            "{} of the {n} layouts were not certified: the best of the others is kept",
            search
                .candidates
                .iter()
                .filter(|c| !matches!(c.status, Status::Optimal | Status::Analysed))
                .count()
        ));
        Status::BestFound
    };
    let ties = (search.candidates.iter())
        .filter(|c| c.value - c.error <= best.value + best.error)
        .count();
    if ties > 1 {
        sol.claim.warnings.push(format!(
            "{ties} layouts are within their errors of the best (mirror images, the same throws in another order along the shaft, or true ties): the first in the search's order is kept; the `phases` table lists them all, with their other figures in each layout's own solve"
        ));
    }
    sol.chosen = Some(Box::new(q));
    sol.phases = Some(search);
    Ok(sol)
}

/// The headline value of a solved layout and its error: the design's objective, or the bare
/// peak the goal names.
pub fn headline(p: &MultiCylinderProblem, sol: &Solution) -> (f64, f64) {
    if let Some(d) = &sol.design {
        return (d.objective, d.error.total);
    }
    let field = match p.goal {
        Goal::PeakCouple => COUPLE,
        Goal::PeakMountForce => normal_mounts(p)
            .max_by(|a, b| sol.bare[*a].peak.total_cmp(&sol.bare[*b].peak))
            .unwrap_or(FORCE),
        Goal::PeakForce | Goal::CounterweightMass => FORCE,
    };
    (sol.bare[field].peak, sol.bare[field].error)
}

/// Solves the scene's one layout.
pub fn solve_layout(p: &MultiCylinderProblem) -> Result<Solution, String> {
    if !p.layout.assembles() {
        return Err("a cylinder does not assemble: (R + |e|)/L ≥ 1".into());
    }
    let (f, m) = (Fields { p, which: FORCE }, Fields { p, which: COUPLE });
    let mounts = match &p.frame {
        Some(frame) => mount_fields(p, frame)?,
        None => Vec::new(),
    };
    let roll = RollField { p };
    let mut fields: Vec<&dyn AffineField> = vec![&f, &m];
    fields.extend(mounts.iter().map(|k| k as &dyn AffineField));
    fields.push(&roll);
    let pb = problem(p, fields);
    let engine = Engine::new(&pb, &p.settings).map_err(|e| e.to_string())?;
    let bare = engine
        .peaks(&vec![0.0; pb.n()])
        .map_err(|e| e.to_string())?;
    let design = if p.rotors.is_empty() {
        None
    } else {
        Some(engine.solve().map_err(|e| e.to_string())?)
    };
    let front = front(p, &engine, design.as_ref())?;
    let bare_spectrum = spectrum(p, &vec![0.0; pb.n()]);
    let spectrum = (design.as_ref())
        .filter(|d| d.x.iter().all(|v| v.is_finite()))
        .map(|d| spectrum(p, &d.x));
    let w2 = p.omega * p.omega;
    let textbook = model::textbook(&p.layout).map(|h| scaled(h, w2));
    let mut claim = claim(p, design.as_ref());
    if claim.status == Status::Infeasible {
        let sf = shortfalls(p, &engine);
        if !sf.is_empty() {
            claim.status_detail = None;
        }
        claim.infeasible(sf);
    }
    Ok(Solution {
        claim,
        bare,
        design,
        bare_spectrum,
        spectrum,
        textbook,
        front,
        phases: None,
        chosen: None,
    })
}

/// A harmonic's coefficients times `k`.
fn scaled(mut h: Harmonic, k: f64) -> Harmonic {
    h.forward = h.forward.map(|v| v * k);
    h.backward = h.backward.map(|v| v * k);
    h
}

/// The front, when asked for: min peak force subject to peak couple ≤ ε, ε spread evenly
/// between the couple's least and its value at the least force.
fn front(
    p: &MultiCylinderProblem,
    engine: &Engine,
    design: Option<&minimax::Solution>,
) -> Result<Option<ParetoFront>, String> {
    let usable = design.is_some_and(|d| d.x.iter().all(|v| v.is_finite()));
    if p.pareto_points == 0 || !usable {
        return Ok(None);
    }
    engine
        .pareto_front(FORCE, COUPLE, p.pareto_points as usize)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// The harmonics of the machine with the unbalances x (FFT of [`FFT_SAMPLES`] samples).
pub fn spectrum(p: &MultiCylinderProblem, x: &[f64]) -> Spectrum {
    let (f, m) = (Fields { p, which: FORCE }, Fields { p, which: COUPLE });
    let n = FFT_SAMPLES.max(4 * p.orders as usize).next_power_of_two();
    let zf = model::samples(n, |phi| value_at(&f, phi, x));
    let zm = model::samples(n, |phi| value_at(&m, phi, x));
    Spectrum {
        force: model::harmonics(&zf, p.orders),
        couple: model::harmonics(&zm, p.orders),
        force_error: model::alias_bound(&zf) + f.links_error(),
        couple_error: model::alias_bound(&zm) + m.links_error(),
    }
}

/// What the solve claims of its design.
fn claim(p: &MultiCylinderProblem, d: Option<&minimax::Solution>) -> Claim {
    let Some(d) = d else {
        return Claim::new(
            Status::Analysed,
            "the slider-crank family's kinematics per cylinder; every peak refined from a scan; harmonics by FFT (rustfft)",
        );
    };
    if d.status == minimax::Status::Infeasible {
        let mut c = Claim::new(
            Status::Infeasible,
            format!(
                "clarabel SOCP + exchange loop: infeasible on {} sampled angles, so on all angles",
                d.angles
            ),
        );
        c.status_detail = d.note.clone();
        return c;
    }
    let n = p.rotors.len();
    let what = format!("{n} unbalance{}", if n == 1 { "" } else { "s" });
    let method = if d.solver_status == minimax::DISC_SOLVER {
        format!("exact smallest enclosing disc (Welzl, support polished by Newton) of {what}")
    } else {
        format!(
            "clarabel SOCP + exchange loop over {what} ({} rounds, {} angles, {})",
            d.rounds, d.angles, d.solver_status
        )
    };
    let mut c = Claim::new(
        cw_status(d.status),
        format!(
            "{method}; certificate |V − L| ≤ {:.1e}·V",
            p.settings.rel_tol
        ),
    );
    c.warnings.extend(d.note.clone());
    c
}

/// How far off each limit of an infeasible scene is: the limited peak minimised alone.
fn shortfalls(p: &MultiCylinderProblem, engine: &Engine) -> Vec<Shortfall> {
    let mut out = Vec::new();
    for (limit, field, key, quantity, unit) in [
        (
            p.max_peak_force,
            FORCE,
            "max_peak_force",
            "peak shaking force",
            "N",
        ),
        (
            p.max_peak_couple,
            COUPLE,
            "max_peak_couple",
            "peak couple",
            "N·m",
        ),
    ] {
        let Some(limit) = limit else { continue };
        let alone = engine.solve_goal(&minimax::Goal::MinPeak(vec![(field, 1.0)]), &[], None);
        if let Some(s) = alone.ok().filter(|s| s.status == minimax::Status::Optimal) {
            out.push(Shortfall::at_most(
                &format!("objective.{key}"),
                quantity,
                limit,
                s.objective,
                s.error.total,
                unit,
            ));
        }
    }
    out
}

/// The file-only analyses: none.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &MultiCylinderProblem, _: &Solution) -> Analyses {}
