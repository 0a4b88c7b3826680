//! The crank phases as a design choice (`[design.phases]`): every layout whose throws sit at
//! multiples of `step` (the first throw held at its file's phase: turning every throw by one
//! angle changes no peak) and that fires as asked (`even_firing`, [`super::firing`]) is solved — each its own certified cone program, or for an analysis
//! its refined peaks — and the best kept. An exhaustive search of a finite set whose members
//! are each certified within their errors certifies the best within the largest error of the
//! candidates that could be it, so the claim stays `optimal` when every candidate's is.
//! Candidates run in parallel (rayon) and are collected in order, so the choice does not depend
//! on the thread count; ties go to the first in order.

use super::file::MultiCylinderProblem;
use super::firing::candidate_layouts;
use crate::numeric::ordered;
use crate::report::Status;
use rayon::prelude::*;
use std::sync::Mutex;

/// One candidate layout's outcome.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Candidate {
    /// Each throw's phase (rad).
    pub phases: Vec<f64>,
    /// The headline value (the objective, or the bare peak of an analysis).
    pub value: f64,
    /// Its error bound.
    pub error: f64,
    /// Its status.
    pub status: Status,
}

/// The search's outcome: every candidate in order, and which is best.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseSearch {
    /// The candidates, in enumeration order (cylinder 2's phase fastest).
    pub candidates: Vec<Candidate>,
    /// The index of the best.
    pub best: usize,
    /// The error the best's value carries as the optimum over the set: the largest error of
    /// the candidates within their errors of it.
    pub error: f64,
}

/// Solves every layout of the search with `solve_layout` (its headline value, error, status
/// and whole solution) and picks the best; the best's solution is kept as it finishes (the
/// least value, ties to the first in order: the same whatever the thread count), the others
/// dropped, so the chosen layout is not solved twice.
pub fn search<T: Send>(
    p: &MultiCylinderProblem,
    step: f64,
    solve_layout: impl Fn(&MultiCylinderProblem) -> Result<(f64, f64, Status, T), String> + Sync,
) -> Result<(PhaseSearch, T), String> {
    let layouts = candidate_layouts(&p.layout, step, p.admissible.as_ref());
    let kept: Mutex<Option<(f64, usize, T)>> = Mutex::new(None);
    let candidates = ordered(layouts.into_par_iter().enumerate().map(|(k, phases)| {
        let mut q = p.clone();
        for (c, a) in q.layout.cylinders.iter_mut().zip(&phases) {
            c.phase = *a;
        }
        let (value, error, status, sol) = solve_layout(&q)?;
        // A candidate without a design (infeasible, failed) is never the best.
        let value = if value.is_finite() {
            value
        } else {
            f64::INFINITY
        };
        let mut best = kept.lock().unwrap_or_else(|e| e.into_inner());
        let better = best
            .as_ref()
            .is_none_or(|(v, i, _)| value.total_cmp(v).then(k.cmp(i)).is_lt());
        if better {
            *best = Some((value, k, sol));
        }
        Ok::<_, String>(Candidate {
            phases,
            value,
            error,
            status,
        })
    }))?;
    let (_, best, sol) = (kept.into_inner().unwrap_or_else(|e| e.into_inner()))
        .ok_or("no layout to search: the admissible set is empty")?;
    let b = &candidates[best];
    let error = candidates
        .iter()
        .filter(|c| c.value - c.error <= b.value + b.error)
        .map(|c| c.error)
        .fold(b.error, f64::max);
    Ok((
        PhaseSearch {
            candidates,
            best,
            error,
        },
        sol,
    ))
}
