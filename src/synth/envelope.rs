//! The operating envelope's box, shared by the families that have one (issue 33, item 3):
//! its vertices, its quasi-Monte Carlo points and the worst case of a figure over scenarios.
//! Which parameters a box has, and what they change in a machine, is the family's.
//!
//! A figure affine in each parameter separately (masses; ω² with the weights fixed) has a
//! magnitude — and ΔE, a max minus a min of affine functions — convex in each, so its
//! maximum over the box is at a vertex: the vertices are the scenarios a certified worst case
//! needs. The Halton points check it (they never certify it).

use crate::synth::search::starts::{halton, HALTON_PRIMES};

/// Most interval parameters of an envelope: 2^10 = 1024 vertices (and the Halton bases).
pub const MAX_PARAMETERS: usize = 10;

/// Every vertex of the box `ranges` (2^k, in binary order of the parameters' ends: bit i set
/// = parameter i at its upper end).
pub fn vertices(ranges: &[(f64, f64)]) -> Vec<Vec<f64>> {
    let k = ranges.len();
    (0..(1usize << k))
        .map(|bits| {
            (0..k)
                .map(|i| match bits >> i & 1 {
                    1 => ranges[i].1,
                    _ => ranges[i].0,
                })
                .collect()
        })
        .collect()
}

/// Halton point `i` (≥ 1) of the box `ranges`: coordinate d in base `HALTON_PRIMES[d]`,
/// deterministic whatever the threads.
pub fn halton_point(ranges: &[(f64, f64)], i: usize) -> Vec<f64> {
    ranges
        .iter()
        .enumerate()
        .map(|(d, r)| r.0 + (r.1 - r.0) * halton(i, HALTON_PRIMES[d]))
        .collect()
}

/// The worst case of one figure over the scenarios.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WorstCase {
    /// Its value (the figure's unit).
    pub value: f64,
    /// Its error bound: the binding scenario's evaluation error (the optimisation gap is
    /// added by the caller for the objective).
    pub error: f64,
    /// The binding scenario's index (0: the nominal scene).
    pub vertex: usize,
}

/// The worst (largest) of `(value, error)` over the scenarios, `None` for none.
pub fn worst(rows: impl IntoIterator<Item = (f64, f64)>) -> Option<WorstCase> {
    rows.into_iter()
        .enumerate()
        .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
        .map(|(vertex, (value, error))| WorstCase {
            value,
            error,
            vertex,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_are_in_binary_order() {
        let v = vertices(&[(0.0, 1.0), (2.0, 3.0)]);
        assert_eq!(
            v,
            vec![vec![0., 2.], vec![1., 2.], vec![0., 3.], vec![1., 3.]]
        );
        assert_eq!(vertices(&[]), vec![Vec::<f64>::new()]);
    }

    #[test]
    fn the_worst_is_the_last_largest() {
        let w = worst([(1.0, 0.1), (3.0, 0.2), (3.0, 0.3)]).unwrap();
        assert_eq!((w.value, w.error, w.vertex), (3.0, 0.3, 2));
    }
}
