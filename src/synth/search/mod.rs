//! The outer searches of a design, written once behind one interface.
//!
//! A design problem is data that implements a cost trait: [`Cost`] (a value at a point, for
//! the derivative-free searches) or [`Minimax`] (the pieces and constraints of a minimax
//! objective, for the constrained SQP). The caller chooses the method and its settings:
//!
//! * [`nelder_mead`] — argmin's `NelderMead` (Nelder & Mead 1965) driven by argmin's
//!   `Executor`; the cost evaluations are counted here, once.
//! * [`sqp`] — a trust-region Sℓ1QP (Fletcher 1987, §14.5) for a minimax of smooth pieces
//!   under constraints; hand-written, see its module for why no crate serves. Its steps
//!   are small dense QPs, solved by the primal active-set method of [`qp`].
//! * 1-D: argmin's `BrentOpt` and `BrentRoot` through [`crate::numeric::minimize_1d`] and
//!   [`crate::numeric::brent_root`]; the innermost peak loops use the hand-written
//!   [`crate::numeric::brent_max`] (Brent's fmin) for speed.
//!
//! Around a local method sit the parts of a multistart, also written once: the starts
//! (Halton points or a grid, then the best distinct ones: [`starts`]) and the evidence of a
//! heuristic search — how many basins its ends fell in, how consistent the best ones are
//! ([`SearchEvidence`]).
//!
//! A shape search — the least kinematic error, and the least balanced objective within a
//! kinematic error — is written once over a [`constrained::Shape`].

pub mod constrained;
mod evidence;
mod nelder_mead;
pub mod qp;
pub mod sqp;
pub mod starts;

pub use evidence::{SameBasin, SearchEvidence};
pub use nelder_mead::{nelder_mead, LocalEnd, NelderMead};
pub use sqp::{sqp, LocalRun, Minimax, Probe, Sqp};

/// A design problem's cost at a point `x` of its search space (lower is better); the
/// derivative-free searches need nothing more. A closure `Fn(&[f64]) -> f64` is one.
pub trait Cost {
    /// The cost at `x`.
    fn cost(&self, x: &[f64]) -> f64;
}

impl<F: Fn(&[f64]) -> f64 + ?Sized> Cost for F {
    fn cost(&self, x: &[f64]) -> f64 {
        self(x)
    }
}
