//! The machine as it runs (issue 33): a one-degree-of-freedom machine driven through its input
//! angle φ, at constant speed (mean drive torque, energy curve, energy fluctuation ΔE, the
//! textbook flywheel) and at real speed (the periodic steady state with a flywheel and a
//! motor, the least flywheel that meets a coefficient of speed fluctuation).
//!
//! A family describes its machine by three functions of φ ([`OneDof`]): the generalised
//! inertia J(φ) = Σ (mᵢ |r_Gᵢ′|² + I_Gᵢ φᵢ′²) (′ = d/dφ), its derivative J′(φ), and G(φ) =
//! V′(φ) + Q(φ), the torque of the weights and the process load. Then (`../shared/domain/
//! machine-as-it-runs.md`):
//! - at constant ω̄ the drive torque is T(φ) = ½ J′(φ) ω̄² + G(φ), its mean T̄ = Ḡ, the energy
//!   curve E(φ) = ∫₀^φ (T − T̄) dφ and ΔE = max E − min E; the textbook flywheel for a
//!   coefficient Cs is I_f = ΔE / (Cs ω̄²);
//! - at real speed, with a flywheel I_f on the input shaft and a motor torque T_m(ω), the
//!   energy equation d/dφ [½ (J + I_f) ω²] = T_m(ω) − G(φ) has one periodic solution ω(φ),
//!   and α = ω dω/dφ = (T_m − G − ½ J′ ω²)/(J + I_f).
//!
//! J, J′ and G are smooth and 2π-periodic, so everything is computed from their samples on a
//! uniform grid and their trigonometric interpolants (rustfft): integrals of a period by the
//! trapezoidal rule and antiderivatives term by term are then spectrally accurate, and every
//! figure's truncation error is measured by halving the grid. Hand-written on rustfft because
//! no crate integrates periodic energy equations: ODE crates (e.g. `ode_solvers`) integrate in
//! time and would need the shooting, the grid alignment and the error bookkeeping around them.

pub mod cases;
mod motor;
use crate::numeric::{brent_max, brent_root, ordered, refine_sampled_max};
pub use motor::Motor;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use std::f64::consts::TAU;

/// A one-degree-of-freedom machine over one turn of its input angle φ: `eval(φ)` returns
/// (J(φ) in kg·m², J′(φ) in kg·m², G(φ) in N·m).
pub trait OneDof: Sync {
    /// (J, J′, G) at φ.
    fn eval(&self, phi: f64) -> [f64; 3];
}

impl<F: Fn(f64) -> [f64; 3] + Sync> OneDof for F {
    fn eval(&self, phi: f64) -> [f64; 3] {
        self(phi)
    }
}

/// Why a drive could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriveError {
    /// J, J′ or G is not finite at this angle (rad).
    #[error("the machine's inertia or load torque is not finite at φ = {0} rad")]
    NotFinite(f64),
    /// J + I_f is not positive at this angle (rad).
    #[error("the generalised inertia J + I_f is not positive at φ = {0} rad")]
    NoInertia(f64),
    /// The motor cannot keep the machine turning (its torque line never meets the load).
    #[error("the motor stalls: {0}")]
    Stalls(String),
    /// No flywheel up to this inertia (kg·m²) meets the coefficient of fluctuation.
    #[error("no flywheel up to {0:.3e} kg·m² meets the coefficient of speed fluctuation")]
    NoFlywheel(f64),
}

/// Accuracy of the drive's figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveSettings {
    /// Grid samples to start with (a power of two ≥ 16).
    pub min_samples: usize,
    /// Grid samples at most (a power of two).
    pub max_samples: usize,
    /// Relative truncation error of ΔE at which the grid stops doubling.
    pub rel_tol: f64,
    /// Relative truncation error of the steady state's Cs at which its grid stops doubling
    /// (the motor line's RK4 and Hermite extremes converge as h⁴, not spectrally).
    pub steady_rel_tol: f64,
}

impl DriveSettings {
    /// For a load with kinks (a compressor's valve events, a load table's corners): its
    /// grids converge as h², not spectrally, so past 4096 nodes a halving costs far more than
    /// it gains; the grid stops there, unsettled, and every error adds the last two halvings'
    /// changes ([`Doubled::change`]). Measured on `hypocycloid-compressor` against 65,536
    /// nodes: ΔE off by 8.3e-6 J with a stated 1.4e-4 J, T̄ by 2.4e-6 N·m with 4.1e-5; the
    /// finer grid took 0.57 s instead of 38 ms.
    pub fn for_kinks() -> Self {
        DriveSettings {
            max_samples: 1 << 12,
            ..Default::default()
        }
    }
}

impl Default for DriveSettings {
    fn default() -> Self {
        DriveSettings {
            min_samples: 256,
            max_samples: 1 << 16,
            rel_tol: 1e-11,
            steady_rel_tol: 1e-9,
        }
    }
}

/// A 2π-periodic function's trigonometric interpolant on n uniform samples: c_k, k < n/2
/// (the Nyquist term dropped: the functions are smooth, and its coefficient is measured by
/// the grid doubling).
#[derive(Debug, Clone)]
struct Trig {
    c: Vec<Complex<f64>>,
}

thread_local! {
    /// One FFT planner per thread: it keeps every plan it has made, so the grid doublings of
    /// [`antiderivatives`] (four transforms per column and doubling) do not build and drop
    /// the same twiddle tables again (that churn was most of the linkage's ΔE solve).
    static PLANNER: std::cell::RefCell<FftPlanner<f64>> = std::cell::RefCell::new(FftPlanner::new());
}

/// The FFT of length n (forward or inverse) from this thread's planner.
fn fft(n: usize, forward: bool) -> std::sync::Arc<dyn rustfft::Fft<f64>> {
    PLANNER.with(|p| {
        let mut p = p.borrow_mut();
        if forward {
            p.plan_fft_forward(n)
        } else {
            p.plan_fft_inverse(n)
        }
    })
}

impl Trig {
    fn new(samples: &[f64]) -> Trig {
        let n = samples.len();
        let mut buf: Vec<Complex<f64>> = samples.iter().map(|&x| Complex::new(x, 0.0)).collect();
        fft(n, true).process(&mut buf);
        let c = buf[..n / 2].iter().map(|z| z / n as f64).collect();
        Trig { c }
    }

    fn mean(&self) -> f64 {
        self.c[0].re
    }

    /// The value at φ: c₀ + Σ 2 Re(c_k e^{ikφ}).
    fn eval(&self, phi: f64) -> f64 {
        let step = Complex::from_polar(1.0, phi);
        let mut e = step;
        let mut s = self.c[0].re;
        for c in &self.c[1..] {
            s += 2.0 * (c * e).re;
            e *= step;
        }
        s
    }

    /// The antiderivative of the zero-mean part, 0 at φ = 0.
    fn antiderivative(&self) -> Trig {
        let mut c: Vec<Complex<f64>> = self
            .c
            .iter()
            .enumerate()
            .map(|(k, c)| {
                if k == 0 {
                    Complex::new(0.0, 0.0)
                } else {
                    c / Complex::new(0.0, k as f64)
                }
            })
            .collect();
        let at0: f64 = c[1..].iter().map(|c| 2.0 * c.re).sum();
        c[0] = Complex::new(-at0, 0.0);
        Trig { c }
    }

    /// The interpolant without its trailing terms whose bound Σ 2|c_k| is at most `tol`, and
    /// that bound.
    fn trimmed(mut self, tol: f64) -> (Trig, f64) {
        let mut dropped = 0.0;
        while self.c.len() > 1 {
            let t = 2.0 * self.c[self.c.len() - 1].norm();
            if dropped + t > tol {
                break;
            }
            dropped += t;
            self.c.pop();
        }
        (self, dropped)
    }

    /// The values on the n-point grid.
    fn grid(&self, n: usize) -> Vec<f64> {
        let mut buf = vec![Complex::new(0.0, 0.0); n];
        buf[0] = self.c[0];
        for (k, c) in self.c.iter().enumerate().skip(1).take(n / 2 - 1) {
            buf[k] = *c;
            buf[n - k] = c.conj();
        }
        fft(n, false).process(&mut buf);
        buf.iter().map(|z| z.re).collect()
    }
}

/// The zero-mean antiderivative E(φ) = ∫₀^φ (f − f̄) dφ of a smooth 2π-periodic f (an energy
/// curve from a torque), as a trigonometric interpolant with a bound on its error: what the
/// design for the drive needs at any φ, column by column of a torque affine in the design
/// ([`antiderivatives`]).
#[derive(Debug, Clone)]
pub struct Antiderivative {
    e: Trig,
    /// f̄, the mean of f over the turn.
    pub mean: f64,
    /// Bound on |E_computed(φ) − E(φ)| over the turn: the change from half the grid, the
    /// terms dropped as negligible, and round-off.
    pub error: f64,
    /// max |E| on the grid.
    pub sup: f64,
    /// Grid samples used.
    pub samples: usize,
}

impl Antiderivative {
    /// E(φ).
    pub fn eval(&self, phi: f64) -> f64 {
        self.e.eval(phi)
    }

    /// True when f is zero at every sample (a column the function does not depend on).
    pub fn is_zero(&self) -> bool {
        self.sup == 0.0 && self.mean == 0.0
    }
}

/// The [`Antiderivative`]s of `cols` periodic functions sampled together (`f(φ, out)` writes
/// their values at φ into `out`), on one grid doubled from `s.min_samples` until every
/// column's E changes by at most `s.rel_tol` of its scale (max |E| + |f̄|·2π) from half the
/// grid, or `s.max_samples`. Each interpolant then drops the trailing terms whose sum is
/// below 10⁻¹⁶ of its scale (counted in its error), so that evaluating E costs only the
/// harmonics f has.
pub fn antiderivatives(
    mut f: impl FnMut(f64, &mut [f64]),
    cols: usize,
    s: &DriveSettings,
) -> Result<Vec<Antiderivative>, DriveError> {
    // The columns at φ_k = 2πk/n for k = first, first + step, … < n.
    let mut sample = |n: usize, first: usize, step: usize| -> Result<Vec<Vec<f64>>, DriveError> {
        let mut by_col = vec![Vec::with_capacity(n / step); cols];
        let mut row = vec![0.0; cols];
        for k in (first..n).step_by(step) {
            let phi = TAU * k as f64 / n as f64;
            row.iter_mut().for_each(|v| *v = 0.0);
            f(phi, &mut row);
            for (c, &v) in by_col.iter_mut().zip(&row) {
                if !v.is_finite() {
                    return Err(DriveError::NotFinite(phi));
                }
                c.push(v);
            }
        }
        Ok(by_col)
    };
    let mut n = s.min_samples.next_power_of_two().max(16);
    let mut by_col = sample(n, 0, 1)?;
    loop {
        let done: Vec<(Antiderivative, bool)> = by_col
            .iter()
            .map(|v| antiderivative_on(v, s.rel_tol))
            .collect();
        if done.iter().all(|d| d.1) || 2 * n > s.max_samples {
            return Ok(done.into_iter().map(|d| d.0).collect());
        }
        // Doubling keeps the samples taken (φ = 2π(2k)/(2n) is 2πk/n to the bit) and adds
        // the odd ones between them.
        let odd = sample(2 * n, 1, 2)?;
        for (c, o) in by_col.iter_mut().zip(odd) {
            *c = c.iter().zip(&o).flat_map(|(&e, &o)| [e, o]).collect();
        }
        n *= 2;
    }
}

/// One column's [`Antiderivative`] on the grid of `v`, and whether it has settled: its change
/// from every other sample is within `rel_tol` of its scale.
fn antiderivative_on(v: &[f64], rel_tol: f64) -> (Antiderivative, bool) {
    let n = v.len();
    if v.iter().all(|&x| x == 0.0) {
        // A column the function does not depend on: what the transforms below would give
        // (every coefficient 0, trimmed to c₀), without their four FFTs.
        let zero = Antiderivative {
            e: Trig {
                c: vec![Complex::new(0.0, 0.0)],
            },
            mean: 0.0,
            error: 0.0,
            sup: 0.0,
            samples: n,
        };
        return (zero, true);
    }
    let full = Trig::new(v);
    let half: Vec<f64> = v.iter().step_by(2).copied().collect();
    let (e, e_half) = (full.antiderivative(), Trig::new(&half).antiderivative());
    let (eg, eg_half) = (e.grid(n), e_half.grid(n / 2));
    let change = eg_half
        .iter()
        .zip(eg.iter().step_by(2))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let sup = eg.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let mean = full.mean();
    let scale = sup + mean.abs() * TAU;
    let (e, dropped) = e.trimmed(1e-16 * scale);
    let error = change + dropped + 1e-15 * n as f64 * scale;
    let settled = change <= rel_tol * scale;
    (
        Antiderivative {
            e,
            mean,
            error,
            sup,
            samples: n,
        },
        settled,
    )
}

/// The machine sampled on the uniform grid φ_k = 2πk/n.
#[derive(Debug, Clone)]
struct Grid {
    j: Vec<f64>,
    dj: Vec<f64>,
    g: Vec<f64>,
    /// What every steady state on the grid shares whatever the flywheel, made once
    /// ([`Grid::series`]).
    series: std::cell::OnceCell<Series>,
}

/// The interpolants of J and of W = ∫₀^φ (Ḡ − G) dφ, and W on the grid.
#[derive(Debug, Clone)]
struct Series {
    j: Trig,
    w_trig: Trig,
    w: Vec<f64>,
}

impl Grid {
    /// The machine sampled at φ_k = 2πk/n, k = 0…n−1, the samples in parallel (each a
    /// mechanism's pose; collected in order, so the same grid whatever the threads). Where
    /// the grid of n/2 is `half`, its samples are the even ones (the same angles to the bit:
    /// 2πk/n with k = 2i is 2πi/(n/2), both scaled by 2 exactly) and only the odd ones are
    /// evaluated. The first angle (in order) where J, J′ or G is not finite is the error.
    fn new(m: &dyn OneDof, n: usize, half: Option<&Grid>) -> Result<Grid, DriveError> {
        use rayon::prelude::*;
        let at = |k: usize| -> Result<[f64; 3], DriveError> {
            let phi = TAU * k as f64 / n as f64;
            let v = m.eval(phi);
            match v.iter().all(|x| x.is_finite()) {
                true => Ok(v),
                false => Err(DriveError::NotFinite(phi)),
            }
        };
        let (j, dj, g) = match half {
            Some(h) => {
                let odd = ordered(
                    (0..n / 2)
                        .into_par_iter()
                        .with_min_len(64)
                        .map(|i| at(2 * i + 1)),
                )?;
                let weave = |even: &[f64], c: usize| -> Vec<f64> {
                    even.iter()
                        .zip(&odd)
                        .flat_map(|(&e, o)| [e, o[c]])
                        .collect()
                };
                (weave(&h.j, 0), weave(&h.dj, 1), weave(&h.g, 2))
            }
            None => {
                let all = ordered((0..n).into_par_iter().with_min_len(64).map(at))?;
                let col = |c: usize| all.iter().map(|v| v[c]).collect();
                (col(0), col(1), col(2))
            }
        };
        Ok(Grid::of(j, dj, g))
    }

    fn of(j: Vec<f64>, dj: Vec<f64>, g: Vec<f64>) -> Grid {
        Grid {
            j,
            dj,
            g,
            series: std::cell::OnceCell::new(),
        }
    }

    /// The grid's [`Series`].
    fn series(&self) -> &Series {
        self.series.get_or_init(|| {
            let gbar = self.gbar();
            let neg: Vec<f64> = self.g.iter().map(|g| gbar - g).collect();
            let w_trig = Trig::new(&neg).antiderivative();
            Series {
                j: Trig::new(&self.j),
                w: w_trig.grid(self.n()),
                w_trig,
            }
        })
    }

    fn n(&self) -> usize {
        self.j.len()
    }

    /// Ḡ, the mean of G: the trapezoidal rule on the periodic grid (its interpolant's c₀).
    fn gbar(&self) -> f64 {
        self.g.iter().sum::<f64>() / self.n() as f64
    }

    /// Every other sample: the grid of n/2.
    fn halved(&self) -> Grid {
        let h = |v: &Vec<f64>| v.iter().step_by(2).copied().collect();
        Grid::of(h(&self.j), h(&self.dj), h(&self.g))
    }
}

/// The drive at constant speed ω̄.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ConstantSpeed {
    /// ω̄ (rad/s).
    pub omega: f64,
    /// T̄, the mean drive torque (N·m): the mean load, the motor's mean torque.
    pub mean_torque: f64,
    /// Bound on the error of T̄ (N·m): its change from half the grid, round-off.
    pub mean_torque_error: f64,
    /// ΔE = max E − min E (J).
    pub energy_fluctuation: f64,
    /// Bound on the error of ΔE (J): the grid's truncation (measured by halving it), the
    /// refinement of the extremes and round-off.
    pub energy_fluctuation_error: f64,
    /// φ at max E and at min E (rad).
    pub extreme_angles: [f64; 2],
    /// max E and min E (J): E(0) = 0.
    pub extreme_energies: [f64; 2],
    /// Grid samples used.
    pub samples: usize,
    /// (φ, T(φ), E(φ)) on the grid's points over the turn (0 and 2π both), for the
    /// turning-moment diagram.
    #[serde(skip)]
    pub curve: Vec<[f64; 3]>,
}

impl ConstantSpeed {
    /// The textbook flywheel for the coefficient of fluctuation `cs`: I_f = ΔE / (Cs ω̄²)
    /// (kg·m²), which neglects the variation of J and the definition of the mean speed.
    pub fn textbook_flywheel(&self, cs: f64) -> f64 {
        self.energy_fluctuation / (cs * self.omega * self.omega)
    }
}

/// The index of the largest of `sign`·v (the max for +1, the min for −1).
fn extreme_node(v: &[f64], sign: f64) -> usize {
    v.iter()
        .enumerate()
        .max_by(|a, b| (sign * a.1).total_cmp(&(sign * b.1)))
        .map_or(0, |(k, _)| k)
}

/// The extreme (max for `sign` +1, min for −1) of a smooth periodic `f` sampled as `v` at
/// spacing `h`: the extreme sample, refined on `f` within a sample either side — from `f`'s
/// own values at the sample and its neighbours by safeguarded parabolic steps
/// ([`refine_sampled_max`]: about five evaluations where Brent from scratch takes about
/// fifteen; `f` is a long trigonometric sum here, each evaluation O(n)), or by Brent where
/// those three values do not bracket a maximum (`v` is the grid's values by FFT, `f`'s may
/// differ in the last digits). (value, angle in [0, 2π)).
fn refined_extreme(v: &[f64], h: f64, sign: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let k = extreme_node(v, sign);
    let at = k as f64 * h;
    let g = |p: f64| sign * f(p);
    let ys = [g(at - h), g(at), g(at + h)];
    let refined = if ys[1] >= ys[0] && ys[1] >= ys[2] {
        refine_sampled_max(g, at, h, ys, 1e-13).map(|(x, _)| x)
    } else {
        brent_max(g, at - h, at + h, 1e-13)
    };
    refined
        .map(|x| (sign * x.fx, x.x.rem_euclid(TAU)))
        .unwrap_or((v[k], at))
}

/// The energy figures on one grid.
struct Energy {
    /// ΔE (J).
    delta: f64,
    /// (max E, its φ) and (min E, its φ).
    max: (f64, f64),
    min: (f64, f64),
    /// T̄ (N·m).
    mean: f64,
    /// T's and E's interpolants.
    torque: Trig,
    energy: Trig,
}

/// ΔE on one grid: T = ½ J′ ω² + G, E its zero-mean antiderivative, the extremes refined on E.
fn energy_on(grid: &Grid, omega: f64) -> Energy {
    let n = grid.n();
    let w2 = omega * omega;
    let t: Vec<f64> = (0..n).map(|k| 0.5 * grid.dj[k] * w2 + grid.g[k]).collect();
    let torque = Trig::new(&t);
    let energy = torque.antiderivative();
    let eg = energy.grid(n);
    let h = TAU / n as f64;
    let max = refined_extreme(&eg, h, 1.0, |p| energy.eval(p));
    let min = refined_extreme(&eg, h, -1.0, |p| energy.eval(p));
    Energy {
        delta: max.0 - min.0,
        max,
        min,
        mean: torque.mean(),
        torque,
        energy,
    }
}

/// What [`doubled`] ends on: the figures on the last grid, on its half, and — where the grid
/// stopped at `max_samples` before the figures settled — on its quarter.
struct Doubled<T> {
    cur: T,
    prev: T,
    /// On a quarter of the grid, where the doubling stopped unsettled (`None` otherwise).
    unsettled: Option<T>,
    grid: Grid,
}

impl<T> Doubled<T> {
    /// The error bound of the figure `f`: its change from half the grid — the whole error of
    /// a spectrally converging figure — plus, where the doubling stopped unsettled, its
    /// change before that. A load with kinks (a compressor's valve events) converges as h²
    /// with a constant that swings with the kinks' places on the grid, so one change can be
    /// small by chance; two in a row cover it.
    fn change(&self, f: impl Fn(&T) -> f64) -> f64 {
        self.change_by(|a, b| (f(a) - f(b)).abs())
    }

    /// [`Doubled::change`] with the change between two grids' figures measured by `diff`.
    fn change_by(&self, diff: impl Fn(&T, &T) -> f64) -> f64 {
        diff(&self.cur, &self.prev) + self.unsettled.as_ref().map_or(0.0, |e| diff(&self.prev, e))
    }
}

/// The figures `on` a grid of the machine, the grid doubled from `s.min_samples` until
/// `settled(current, on half the grid)` (or `s.max_samples`). The one refinement loop of
/// the drive: every figure's error is its change from half the grid ([`Doubled::change`]).
fn doubled<T>(
    grids: &Grids,
    s: &DriveSettings,
    on: impl Fn(&Grid) -> Result<T, DriveError>,
    settled: impl Fn(&T, &T) -> bool,
) -> Result<Doubled<T>, DriveError> {
    let mut n = s.min_samples.next_power_of_two().max(16);
    let mut grid = grids.get(n)?;
    let mut prev = on(&grid.halved())?;
    let mut before = None;
    loop {
        let cur = on(&grid)?;
        if settled(&cur, &prev) {
            return Ok(Doubled {
                cur,
                prev,
                unsettled: None,
                grid,
            });
        }
        if 2 * n > s.max_samples {
            return Ok(Doubled {
                cur,
                prev,
                unsettled: before,
                grid,
            });
        }
        before = Some(std::mem::replace(&mut prev, cur));
        n *= 2;
        grid = grids.get(n)?;
    }
}

/// The machine's grids by size, each sampled once: the least flywheel's search converges a
/// steady state at both ends of its bracket (and, for a machine that stalls, at the halvings
/// of its top), each doubling the same uniform grids of the same machine.
struct Grids<'m> {
    m: &'m dyn OneDof,
    made: std::cell::RefCell<Vec<Grid>>,
}

impl<'m> Grids<'m> {
    /// None made yet.
    fn of(m: &'m dyn OneDof) -> Self {
        Grids {
            m,
            made: Default::default(),
        }
    }

    /// The machine on the grid of `n` samples ([`Grid::new`]), made once.
    fn get(&self, n: usize) -> Result<Grid, DriveError> {
        if let Some(g) = self.made.borrow().iter().find(|g| g.n() == n) {
            return Ok(g.clone());
        }
        let half = self.made.borrow().iter().find(|g| 2 * g.n() == n).cloned();
        let g = Grid::new(self.m, n, half.as_ref())?;
        self.made.borrow_mut().push(g.clone());
        Ok(g)
    }
}

/// The drive at constant speed ω̄: T̄, the energy curve and ΔE, the grid doubled until ΔE
/// changes by less than `rel_tol` of itself (or of T's scale over a radian).
pub fn constant_speed(
    m: &dyn OneDof,
    omega: f64,
    s: &DriveSettings,
) -> Result<ConstantSpeed, DriveError> {
    let scale = |e: &Energy| e.delta.abs().max(e.mean.abs() * TAU).max(f64::MIN_POSITIVE);
    let on = |g: &Grid| Ok(energy_on(g, omega));
    let settled =
        |cur: &Energy, prev: &Energy| (cur.delta - prev.delta).abs() <= s.rel_tol * scale(cur);
    let d = doubled(&Grids::of(m), s, on, settled)?;
    let (cur, n) = (&d.cur, d.grid.n());
    let round_off = 1e-15 * n as f64 * scale(cur);
    let (tg, eg) = (cur.torque.grid(n), cur.energy.grid(n));
    let curve = (0..=n)
        .map(|k| [TAU * k as f64 / n as f64, tg[k % n], eg[k % n]])
        .collect();
    Ok(ConstantSpeed {
        omega,
        mean_torque: cur.mean,
        mean_torque_error: d.change(|e| e.mean) + round_off / TAU,
        energy_fluctuation: cur.delta,
        energy_fluctuation_error: d.change(|e| e.delta) + round_off + 1e-13 * cur.delta,
        extreme_angles: [cur.max.1, cur.min.1],
        extreme_energies: [cur.max.0, cur.min.0],
        samples: n,
        curve,
    })
}

/// The periodic steady state at real speed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SteadyState {
    /// The flywheel I_f (kg·m²) on the input shaft.
    pub flywheel: f64,
    /// ω_min and ω_max over the turn (rad/s).
    pub omega_min: f64,
    /// See `omega_min`.
    pub omega_max: f64,
    /// Their angles (rad).
    pub extreme_angles: [f64; 2],
    /// The time-mean speed 2π/period (rad/s): the mean that Cs is taken about.
    pub omega_mean: f64,
    /// Cs = (ω_max − ω_min)/ω_mean.
    pub cs: f64,
    /// Bound on the error of Cs: the grid's truncation (the steady state on half the grid).
    pub cs_error: f64,
    /// Bound on the error of ω_min, ω_max and ω_mean (rad/s), likewise.
    pub omega_error: f64,
    /// The period of one turn (s).
    pub period: f64,
    /// max |α| over the turn (rad/s²).
    pub peak_alpha: f64,
    /// Bound on its error (rad/s²): the difference from the peak node's neighbours, plus its
    /// change from half the grid.
    pub peak_alpha_error: f64,
    /// Grid samples.
    pub samples: usize,
    /// (φ, ω, α) at the grid's nodes, for the tables and plots.
    #[serde(skip)]
    pub curve: Vec<[f64; 3]>,
}

/// The peak of a quantity over a steady state's nodes, with its error bound and angle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct NodePeak {
    /// max |v| over the nodes.
    pub peak: f64,
    /// Its error bound: how far the maximum between the nodes can rise ([`node_peak`]) plus
    /// the speeds' error (2 δω/ω_min of it, for a quantity that scales as ω²).
    pub error: f64,
    /// The input angle of the peak node (rad).
    pub angle: f64,
    /// The peak node's index in the steady state's curve.
    pub node: usize,
}

impl SteadyState {
    /// `v(φ, ω, α)` at every node of the curve; `None` where it is `None` at a node.
    pub fn at_nodes<T>(&self, v: impl Fn(f64, f64, f64) -> Option<T>) -> Option<Vec<T>> {
        self.curve.iter().map(|&[p, w, a]| v(p, w, a)).collect()
    }

    /// The peak of an inertial quantity (a force or a load, which scales as ω²) given at
    /// the nodes ([`Self::at_nodes`]), with its error and angle ([`NodePeak`]).
    pub fn inertial_peak(&self, values: &[f64]) -> NodePeak {
        let (peak, k, between) = node_peak(values);
        NodePeak {
            peak,
            error: between + 2.0 * self.omega_error / self.omega_min * peak,
            angle: self.curve[k][0],
            node: k,
        }
    }
}

/// max |v| over the nodes of one turn (periodic), its node, and a bound on how far the true
/// maximum between the nodes can lie above it: the larger difference from the two
/// neighbours. A peak at a kink (a load table's corner) is off by at most its slope times half
/// a step, a smooth one by far less; the neighbour difference covers both.
fn node_peak(v: &[f64]) -> (f64, usize, f64) {
    let (k, peak) = v
        .iter()
        .map(|x| x.abs())
        .enumerate()
        .fold((0, 0.0_f64), |b, (i, x)| if x > b.1 { (i, x) } else { b });
    let n = v.len();
    let near = |j: usize| (peak - v[j % n].abs()).abs();
    (peak, k, near(k + 1).max(near(k + n - 1)))
}

/// ω(φ) of a constant-torque steady state anywhere on the turn, exactly (up to the
/// interpolants' truncation): ω = sqrt(2 (y₀ + W(φ)) / (J(φ) + I_f)).
struct ExactSpeed<'g> {
    y0: f64,
    w: &'g Trig,
    j: &'g Trig,
    flywheel: f64,
}

impl ExactSpeed<'_> {
    fn at(&self, phi: f64) -> f64 {
        (2.0 * (self.y0 + self.w.eval(phi)).max(0.0) / (self.j.eval(phi) + self.flywheel)).sqrt()
    }
}

/// One steady state on one grid: (ω at the nodes, α at the nodes, node spacing, ω anywhere
/// where it is explicit) — the constant torque exactly at every grid point, the line by RK4
/// on every other point.
type OnGrid<'g> = (Vec<f64>, Vec<f64>, f64, Option<ExactSpeed<'g>>);

fn steady_on<'g>(
    grid: &'g Grid,
    motor: &Motor,
    flywheel: f64,
    omega_nominal: f64,
) -> Result<OnGrid<'g>, DriveError> {
    let n = grid.n();
    let h = TAU / n as f64;
    let gbar = grid.gbar();
    for (k, j) in grid.j.iter().enumerate() {
        if j + flywheel <= 0.0 {
            return Err(DriveError::NoInertia(k as f64 * h));
        }
    }
    let omega_of = |y: f64, k: usize| (2.0 * y.max(0.0) / (grid.j[k] + flywheel)).sqrt();
    let alpha_of = |w: f64, k: usize| {
        (motor.torque(w, gbar) - grid.g[k] - 0.5 * grid.dj[k] * w * w) / (grid.j[k] + flywheel)
    };
    let omegas = match motor {
        Motor::ConstantTorque => {
            // y = ½ (J + I_f) ω² = y₀ + W(φ), W = ∫ (Ḡ − G): y₀ sets the time-mean speed.
            let series = grid.series();
            let w = &series.w;
            let wmin = w.iter().cloned().fold(f64::INFINITY, f64::min);
            let mean_speed = |y0: f64| {
                let inv: f64 = (0..n).map(|k| 1.0 / omega_of(y0 + w[k], k)).sum();
                TAU / (h * inv)
            };
            let jmax = grid.j.iter().cloned().fold(0.0, f64::max) + flywheel;
            // From a positive start (ω̄² can underflow to 0 with W ≡ 0: a tiny speed), up by
            // fours until the mean speed is reached; a bracket beyond f64 is no steady state.
            let mut hi = (0.5 * jmax * omega_nominal * omega_nominal + wmin.abs() * 2.0)
                .max(f64::MIN_POSITIVE);
            while mean_speed(hi) < omega_nominal {
                hi *= 4.0;
                if !hi.is_finite() {
                    return Err(DriveError::Stalls(format!(
                        "no constant-torque steady state reaches the mean speed {omega_nominal:e} rad/s"
                    )));
                }
            }
            let lo = -wmin + 1e-300;
            let f = |y0: f64| mean_speed(y0) - omega_nominal;
            let y0 = brent_root(f, lo, hi, 1e-15 * hi)
                .map_err(|e| DriveError::Stalls(e.to_string()))?
                .x;
            let exact = ExactSpeed {
                y0,
                w: &series.w_trig,
                j: &series.j,
                flywheel,
            };
            (
                (0..n).map(|k| omega_of(y0 + w[k], k)).collect::<Vec<f64>>(),
                Some(exact),
            )
        }
        Motor::Line { .. } | Motor::Table { .. } => {
            (shoot_line(grid, motor, flywheel, gbar)?, None)
        }
    };
    let (omegas, exact) = omegas;
    let stride = n / omegas.len();
    let alphas = omegas
        .iter()
        .enumerate()
        .map(|(i, &w)| alpha_of(w, i * stride))
        .collect();
    Ok((omegas, alphas, h * stride as f64, exact))
}

/// The periodic solution of d/dφ y = T_m(ω) − G with a motor line, y = ½ (J + I_f) ω²: RK4
/// with step 2h on the grid (its stages fall on grid points), shooting on y₀ until
/// y(2π) = y₀ (Brent on y(2π) − y₀, which falls through zero once: the line brakes a fast
/// machine and drives a slow one). ω at the nodes φ_{2i}.
fn shoot_line(
    grid: &Grid,
    motor: &Motor,
    flywheel: f64,
    gbar: f64,
) -> Result<Vec<f64>, DriveError> {
    let n = grid.n();
    let h2 = 2.0 * TAU / n as f64;
    let jf = |k: usize| grid.j[k % n] + flywheel;
    // 2/(J + I_f) and G at the nodes 0..=n (the last is the first again), once per call:
    // the runs below evaluate them 2n times each.
    let two_over_j: Vec<f64> = (0..=n).map(|k| 2.0 / jf(k)).collect();
    let g: Vec<f64> = (0..=n).map(|k| grid.g[k % n]).collect();
    let rate = |y: f64, k: usize| {
        let w = (y.max(0.0) * two_over_j[k]).sqrt();
        motor.torque(w, gbar) - g[k]
    };
    let run = |y0: f64, out: Option<&mut Vec<f64>>| {
        let mut y = y0;
        let mut ys = Vec::new();
        for i in 0..n / 2 {
            ys.push(y);
            let k = 2 * i;
            let k1 = rate(y, k);
            let k2 = rate(y + 0.5 * h2 * k1, k + 1);
            let k3 = rate(y + 0.5 * h2 * k2, k + 1);
            let k4 = rate(y + h2 * k3, k + 2);
            y += h2 / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        if let Some(o) = out {
            *o = ys;
        }
        y
    };
    // The speed where the motor's torque meets the mean load, then a bracket around it.
    let Some(wc) = motor.speed_at(gbar).filter(|&w| w > 0.0) else {
        return Err(DriveError::Stalls(format!(
            "the mean load {gbar:.6} N·m is above the motor's stall torque"
        )));
    };
    let jbar = grid.j.iter().sum::<f64>() / n as f64 + flywheel;
    let yc = 0.5 * jbar * wc * wc;
    let f = |y0: f64| run(y0, None) - y0;
    let y0 = match secant(&f, yc, 1.001 * yc) {
        Some(y0) => y0,
        None => {
            // The secant strayed: bracket the root and let Brent find it.
            let (mut lo, mut hi) = (0.5 * yc, 2.0 * yc);
            for _ in 0..60 {
                if f(lo) > 0.0 {
                    break;
                }
                lo *= 0.5;
            }
            for _ in 0..60 {
                if f(hi) < 0.0 {
                    break;
                }
                hi *= 2.0;
            }
            brent_root(f, lo, hi, 1e-15 * hi)
                .map_err(|e| DriveError::Stalls(format!("no periodic motion: {e}")))?
                .x
        }
    };
    let mut ys = Vec::new();
    run(y0, Some(&mut ys));
    if ys.iter().any(|&y| y <= 0.0) {
        return Err(DriveError::Stalls(
            "the speed falls to zero in the cycle".into(),
        ));
    }
    Ok(ys
        .iter()
        .enumerate()
        .map(|(i, &y)| (2.0 * y / jf(2 * i)).sqrt())
        .collect())
}

/// A root of `f` by the secant method from `a` and `b`, to 10⁻¹⁴ relative, if it converges
/// in 12 steps without leaving the positive axis: the periodicity defect y(2π) − y₀ of a
/// motor line is nearly affine in y₀, so this takes three or four runs where a bracketed
/// Brent takes a dozen.
fn secant(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> Option<f64> {
    let (mut x0, mut x1) = (a, b);
    let (mut f0, mut f1) = (f(x0), f(x1));
    for _ in 0..12 {
        if !(f0.is_finite() && f1.is_finite()) || f1 == f0 {
            return None;
        }
        let x2 = x1 - f1 * (x1 - x0) / (f1 - f0);
        if !(x2 > 0.0) {
            return None;
        }
        if (x2 - x1).abs() <= 1e-14 * x2 {
            return Some(x2);
        }
        (x0, f0, x1) = (x1, f1, x2);
        f1 = f(x1);
    }
    None
}

/// Extremes of ω on the nodes, refined on the cubic Hermite interpolant through (ω, ω′ = α/ω)
/// of the node's neighbours: ((ω_min, φ), (ω_max, φ)).
fn speed_extremes(om: &[f64], al: &[f64], h: f64) -> [(f64, f64); 2] {
    let m = om.len();
    let refine = |sign: f64| {
        let k = extreme_node(om, sign);
        let mut best = (sign * om[k], k as f64 * h);
        for (a, b) in [((k + m - 1) % m, k), (k, (k + 1) % m)] {
            let (y0, y1) = (om[a], om[b]);
            let (d0, d1) = (al[a] / om[a] * h, al[b] / om[b] * h);
            let herm = |t: f64| {
                let (t2, t3) = (t * t, t * t * t);
                (2.0 * t3 - 3.0 * t2 + 1.0) * y0
                    + (t3 - 2.0 * t2 + t) * d0
                    + (-2.0 * t3 + 3.0 * t2) * y1
                    + (t3 - t2) * d1
            };
            if let Ok(x) = brent_max(|t| sign * herm(t), 0.0, 1.0, 1e-12) {
                if x.fx > best.0 {
                    best = (x.fx, ((a as f64 + x.x) * h).rem_euclid(TAU));
                }
            }
        }
        (sign * best.0, best.1)
    };
    [refine(-1.0), refine(1.0)]
}

/// Extremes of an explicit ω(φ): Brent on it around the extreme nodes.
fn exact_extremes(om: &[f64], h: f64, e: &ExactSpeed) -> [(f64, f64); 2] {
    [
        refined_extreme(om, h, -1.0, |p| e.at(p)),
        refined_extreme(om, h, 1.0, |p| e.at(p)),
    ]
}

/// The figures of one steady state on one grid.
fn figures(
    grid: &Grid,
    motor: &Motor,
    flywheel: f64,
    omega_nominal: f64,
) -> Result<SteadyState, DriveError> {
    let (om, al, h, exact) = steady_on(grid, motor, flywheel, omega_nominal)?;
    let [(wmin, pmin), (wmax, pmax)] = match &exact {
        Some(e) => exact_extremes(&om, h, e),
        None => speed_extremes(&om, &al, h),
    };
    let (peak_alpha, _, peak_alpha_error) = node_peak(&al);
    // The period ∫ dφ/ω by the trapezoidal rule on the nodes (spectral for a smooth ω).
    let period: f64 = om.iter().map(|w| h / w).sum();
    let mean = TAU / period;
    Ok(SteadyState {
        flywheel,
        omega_min: wmin,
        omega_max: wmax,
        extreme_angles: [pmin, pmax],
        omega_mean: mean,
        cs: (wmax - wmin) / mean,
        cs_error: 0.0,
        omega_error: 0.0,
        period,
        peak_alpha,
        peak_alpha_error,
        samples: grid.n(),
        curve: om
            .iter()
            .zip(&al)
            .enumerate()
            .map(|(i, (&w, &a))| [i as f64 * h, w, a])
            .collect(),
    })
}

/// The periodic steady state with the flywheel `flywheel` and `motor`, the constant torque's
/// mean speed at `omega_nominal`: the grid doubled until Cs changes by less than `steady_rel_tol` (or
/// 10⁻¹³ absolutely); the errors are the last change.
pub fn steady_state(
    m: &dyn OneDof,
    motor: &Motor,
    flywheel: f64,
    omega_nominal: f64,
    s: &DriveSettings,
) -> Result<SteadyState, DriveError> {
    converged(&Grids::of(m), motor, flywheel, omega_nominal, s).map(|(st, _)| st)
}

/// [`steady_state`], and the grid it converged on (to solve again on it).
fn converged(
    grids: &Grids,
    motor: &Motor,
    flywheel: f64,
    omega_nominal: f64,
    s: &DriveSettings,
) -> Result<(SteadyState, Grid), DriveError> {
    let on = |g: &Grid| figures(g, motor, flywheel, omega_nominal);
    let settled = |cur: &SteadyState, prev: &SteadyState| {
        (cur.cs - prev.cs).abs() <= s.steady_rel_tol * cur.cs.abs() + 1e-13
    };
    Ok(with_errors(doubled(grids, s, on, settled)?))
}

/// The state on the last grid with its errors: the changes from half the grid (and from a
/// quarter where the grid stopped unsettled, [`Doubled::change`]) plus round-off; and the
/// grid.
fn with_errors(d: Doubled<SteadyState>) -> (SteadyState, Grid) {
    let speeds = |a: &SteadyState, b: &SteadyState| {
        [
            a.omega_min - b.omega_min,
            a.omega_max - b.omega_max,
            a.omega_mean - b.omega_mean,
        ]
        .iter()
        .fold(0.0, |m: f64, d| m.max(d.abs()))
    };
    let (dw, dcs, dpa) = (
        d.change_by(speeds),
        d.change(|s| s.cs),
        d.change(|s| s.peak_alpha),
    );
    let Doubled { mut cur, grid, .. } = d;
    let n = cur.samples as f64;
    cur.cs_error = dcs + 1e-14 * n * cur.cs.abs().max(1e-300);
    cur.peak_alpha_error += dpa;
    cur.omega_error = dw + 1e-14 * n * cur.omega_max;
    (cur, grid)
}

/// The least flywheel that meets a coefficient of fluctuation, exactly and by the textbook.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Flywheel {
    /// The requested Cs.
    pub cs: f64,
    /// The least I_f (kg·m²) whose periodic steady state has Cs ≤ the request (0 when the
    /// machine meets it without one).
    pub inertia: f64,
    /// Bound on its error (kg·m²): the root's tolerance plus Cs's error over |dCs/dI_f|.
    pub inertia_error: f64,
    /// The textbook I_f = ΔE / (Cs ω̄²) (kg·m²).
    pub textbook: f64,
    /// The steady state with the least I_f.
    pub steady: SteadyState,
}

/// The least flywheel for the coefficient of fluctuation `cs` (Brent on Cs(I_f) − cs, Cs
/// falling as I_f grows), beside the textbook one from `constant`.
pub fn least_flywheel(
    m: &dyn OneDof,
    motor: &Motor,
    constant: &ConstantSpeed,
    cs: f64,
    s: &DriveSettings,
) -> Result<Flywheel, DriveError> {
    let textbook = constant.textbook_flywheel(cs);
    let grids = Grids::of(m);
    let at = |i: f64| converged(&grids, motor, i, constant.omega, s);
    // Without a flywheel a machine on a motor line may stall (no periodic motion): then the
    // bracket's bottom is found below its top instead.
    let zero = match at(0.0) {
        Ok((zero, _)) if zero.cs <= cs => {
            return Ok(Flywheel {
                cs,
                inertia: 0.0,
                inertia_error: 0.0,
                textbook,
                steady: zero,
            });
        }
        Ok((_, g0)) => Some(g0),
        Err(DriveError::Stalls(_)) => None,
        Err(e) => return Err(e),
    };
    let mut hi = textbook.max(f64::MIN_POSITIVE) * 2.0;
    let mut top = at(hi)?;
    for _ in 0..30 {
        if top.0.cs <= cs {
            break;
        }
        hi *= 4.0;
        top = at(hi)?;
    }
    if top.0.cs > cs {
        return Err(DriveError::NoFlywheel(hi));
    }
    let (lo, g0) = match zero {
        Some(g0) => (0.0, g0),
        None => stall_floor(&at, hi, cs)?,
    };
    // Cs(I_f) on one grid, the finer of those that converged at the bracket's bottom and top
    // (the speed swings most at the bottom): the root's search evaluates the machine no more,
    // and the state at the root is checked on the grid and on its half.
    let g1 = top.1;
    let grid = if g0.n() >= g1.n() { g0 } else { g1 };
    let cs_on = |g: &Grid, i: f64| figures(g, motor, i, constant.omega);
    // The root of 1 − cs/Cs(I_f), the same as Cs(I_f) = cs's: Cs ≈ ΔE/((J̄ + I_f) ω̄²) is
    // nearly a hyperbola in I_f, so 1/Cs is nearly a line and Brent's interpolation settles
    // in a few evaluations instead of bisecting down from the bracket's wide top.
    let f = |i: f64| {
        cs_on(&grid, i)
            .map(|st| 1.0 - cs / st.cs)
            .unwrap_or(f64::NAN)
    };
    let tol = 1e-12 * hi;
    let root = brent_root(f, lo, hi, tol).map_err(|e| DriveError::Stalls(e.to_string()))?;
    // A grid at the cap may not have settled: then the quarter grid's change counts too.
    let unsettled = if 2 * grid.n() > s.max_samples {
        Some(cs_on(&grid.halved().halved(), root.x)?)
    } else {
        None
    };
    let (steady, grid) = with_errors(Doubled {
        cur: cs_on(&grid, root.x)?,
        prev: cs_on(&grid.halved(), root.x)?,
        unsettled,
        grid,
    });
    // |dCs/dI_f| by a central difference, for the error that Cs's own error makes in I_f.
    let d = 1e-4 * root.x.max(tol);
    let slope = ((cs_on(&grid, root.x + d)?.cs - cs_on(&grid, (root.x - d).max(0.0))?.cs)
        / (2.0 * d))
        .abs();
    Ok(Flywheel {
        cs,
        inertia: root.x,
        inertia_error: tol + steady.cs_error / slope.max(f64::MIN_POSITIVE),
        textbook,
        steady,
    })
}

/// The bottom of the least flywheel's bracket for a machine that stalls without one: halving
/// from the top `hi` (which meets `cs`), the first flywheel whose steady state exists and
/// swings more than `cs`, with its grid. A flywheel below which the machine stalls while it
/// still meets `cs` has no least one to find by Brent: an error.
fn stall_floor(
    at: &dyn Fn(f64) -> Result<(SteadyState, Grid), DriveError>,
    hi: f64,
    cs: f64,
) -> Result<(f64, Grid), DriveError> {
    let mut t = hi;
    for _ in 0..60 {
        t *= 0.5;
        match at(t) {
            Ok((st, g)) if st.cs > cs => return Ok((t, g)),
            Ok(_) => {}
            Err(e) => return Err(e),
        }
    }
    Err(DriveError::Stalls(format!(
        "no flywheel down to {t:e} kg·m² swings more than Cs = {cs}: the least one is not bracketed"
    )))
}

/// A problem file's `[mechanism.drive]`, checked (`crate::problem::drive`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Drive {
    /// Cs to meet, if any.
    pub cs: Option<f64>,
    /// The given flywheel (kg·m²), if any.
    pub flywheel: Option<f64>,
    /// The motor.
    pub motor: Motor,
}

/// A design's drive, at constant speed and at real speed: what every family's result reports
/// of `[mechanism.drive]`.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveFigures {
    /// T̄, the energy curve and ΔE at the nominal speed.
    pub constant: ConstantSpeed,
    /// The least flywheel for `cs`, with the textbook one (with `cs`).
    pub flywheel: Option<Flywheel>,
    /// The periodic steady state with the given flywheel, else the least one, else none.
    pub steady: SteadyState,
    /// The shaking force's and the shaft's peaks in that steady state, where the family
    /// computes the force at real speed.
    pub real: Option<RealSpeed>,
}

/// The peaks at real speed: the steady state's ω(φ) and α(φ) in the accelerations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RealSpeed {
    /// max |F| over the steady state's nodes (N).
    pub peak_force: f64,
    /// Its error bound (N): the larger difference from the peak node's neighbours (how far
    /// the maximum between nodes can rise), plus the speeds' error.
    pub peak_force_error: f64,
    /// Its input angle (rad).
    pub peak_force_angle: f64,
    /// max |T_m(ω) − I_f α|, the torque the input shaft carries between the flywheel and the
    /// mechanism (N·m).
    pub peak_shaft_torque: f64,
    /// Bound on its error (N·m): the difference from the peak node's neighbours, plus I_f
    /// times the error of α's peak and the motor's steepest slope times the speeds' error.
    pub peak_shaft_torque_error: f64,
}

/// The drive of the machine `m` at the nominal speed `omega` with `d`'s motor: ΔE, the least
/// flywheel for `d.cs`, the steady state with `d.flywheel` (or the least one, or none).
pub fn drive(
    m: &dyn OneDof,
    omega: f64,
    d: &Drive,
    s: &DriveSettings,
) -> Result<DriveFigures, DriveError> {
    let constant = constant_speed(m, omega, s)?;
    let flywheel =
        d.cs.map(|cs| least_flywheel(m, &d.motor, &constant, cs, s))
            .transpose()?;
    let steady = match (d.flywheel, &flywheel) {
        (None, Some(f)) => f.steady.clone(),
        (given, _) => steady_state(m, &d.motor, given.unwrap_or(0.0), omega, s)?,
    };
    Ok(DriveFigures {
        constant,
        flywheel,
        steady,
        real: None,
    })
}

impl DriveFigures {
    /// The peaks at real speed, with `force(φ, ω, α)` the shaking force's magnitude (N) at
    /// the steady state's nodes (`None` where it cannot be computed: then no peaks). A force
    /// of the accelerations scales as ω², so the speeds' error δω adds 2 δω/ω_min of it; the
    /// sampling error is the peak node's difference from its neighbours ([`node_peak`]).
    pub fn with_real_speed(
        mut self,
        motor: &Motor,
        force: impl Fn(f64, f64, f64) -> Option<f64>,
    ) -> DriveFigures {
        let st = &self.steady;
        let Some(forces) = st.at_nodes(force) else {
            return self;
        };
        let force = st.inertial_peak(&forces);
        let mean = self.constant.mean_torque;
        let shafts: Vec<f64> = st
            .curve
            .iter()
            .map(|&[_, w, a]| motor.torque(w, mean) - st.flywheel * a)
            .collect();
        let (shaft, _, shaft_between) = node_peak(&shafts);
        // The steepest |dT_m/dω| (0 for a constant torque), for the speeds' error.
        let slope = motor.max_slope();
        let shaft_error =
            shaft_between + st.flywheel * st.peak_alpha_error + slope * st.omega_error;
        self.real = Some(RealSpeed {
            peak_force: force.peak,
            peak_force_error: force.error,
            peak_force_angle: force.angle,
            peak_shaft_torque: shaft,
            peak_shaft_torque_error: shaft_error,
        });
        self
    }
}
