//! Nelder–Mead on argmin: a [`Cost`] driven by argmin's `NelderMead` solver and `Executor`,
//! its evaluations counted here so that no caller counts them again.

use super::Cost;
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead as ArgminNelderMead;
use std::cell::Cell;

/// The settings of one Nelder–Mead run (Nelder & Mead 1965, argmin 0.11's `NelderMead`).
#[derive(Debug, Clone, PartialEq)]
pub struct NelderMead {
    /// The initial simplex: n + 1 vertices in n dimensions, the start first.
    pub simplex: Vec<Vec<f64>>,
    /// Stop when the standard deviation of the vertices' costs falls below this (> 0).
    pub sd_tolerance: f64,
    /// Stop after this many iterations.
    pub max_iters: u64,
}

/// Where a local search ended.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalEnd {
    /// The best point found (the start when the solver returned none).
    pub x: Vec<f64>,
    /// Iterations run.
    pub iterations: u64,
    /// Whether it stopped before its iteration limit.
    pub converged: bool,
    /// Cost evaluations spent.
    pub evaluations: usize,
}

/// A [`Cost`] as argmin's cost function, counting its evaluations.
struct Counted<'a, C: ?Sized> {
    cost: &'a C,
    count: Cell<usize>,
}

impl<C: Cost + ?Sized> CostFunction for Counted<'_, C> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        self.count.set(self.count.get() + 1);
        Ok(self.cost.cost(x))
    }
}

/// Minimise `cost` by argmin's Nelder–Mead from `settings.simplex`. `Err` (argmin's
/// message) when the solver fails; the best point, its iterations and the evaluations
/// otherwise.
///
/// # Panics
/// When `settings.sd_tolerance` is not positive (a caller's settings are checked first).
pub fn nelder_mead<C: Cost + ?Sized>(cost: &C, settings: &NelderMead) -> Result<LocalEnd, String> {
    let x0 = settings.simplex[0].clone();
    let solver = ArgminNelderMead::new(settings.simplex.clone())
        .with_sd_tolerance(settings.sd_tolerance)
        .expect("sd_tolerance > 0");
    let problem = Counted {
        cost,
        count: Cell::new(0),
    };
    let r = Executor::new(problem, solver)
        .configure(|s| s.max_iters(settings.max_iters))
        .run()
        .map_err(|e| e.to_string())?;
    let st = r.state();
    let iterations = st.get_iter();
    Ok(LocalEnd {
        x: st.get_best_param().cloned().unwrap_or(x0),
        iterations,
        converged: iterations < settings.max_iters,
        evaluations: r.problem().problem.as_ref().map_or(0, |p| p.count.get()),
    })
}
