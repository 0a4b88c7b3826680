//! When each cylinder fires (or, in a compressor, compresses): the crank angle of each
//! cylinder's outer dead centre and the firing orders a layout admits with even intervals —
//! what `[design.phases] even_firing` restricts the phase search to, and what the report lists.
//! No crate computes firing orders of an arbitrary layout; the matching below is a few lines.
//!
//! Convention: cylinder i is at its outer dead centre (top dead centre, TDC) where its throw
//! points along its cylinder axis, θᵢ = φ + αᵢ − γᵢ ≡ 0, i.e. at φᵢ = (γᵢ − αᵢ) mod 2π (for an
//! offset cylinder the true dead centre is a little off this angle; the firing is timed from
//! the throw). A two-stroke cycle (and a single-acting compressor) fires every cylinder once
//! a turn, at φᵢ; a four-stroke cycle once every two turns, at φᵢ or φᵢ + 2π. The layout fires
//! evenly in the order (c₁ = 1, c₂, …, c_N) when cylinder c_{j+1} fires at φ₁ + j·P/N,
//! P = 2π or 4π the cycle's period.

use super::model::{Cylinder, Layout};
use std::f64::consts::TAU;

/// Angles closer than this (rad) are the same angle: the file's phases and banks are exact
/// fractions of a turn read in degrees, equal to round-off far below it.
pub const ANGLE_TOL: f64 = 1e-9;

/// Most even firing orders listed (the count is always exact).
pub const MAX_LISTED: usize = 64;

/// The cycle of the machine's cylinders.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Cycle {
    /// Every cylinder fires once a turn (a two-stroke engine, a single-acting compressor).
    TwoStroke,
    /// Every cylinder fires once every two turns.
    FourStroke,
}

impl Cycle {
    /// P, the cycle's period in crank angle (rad).
    pub fn period(self) -> f64 {
        match self {
            Cycle::TwoStroke => TAU,
            Cycle::FourStroke => 2.0 * TAU,
        }
    }
    /// The name the problem file uses.
    pub fn as_str(self) -> &'static str {
        match self {
            Cycle::TwoStroke => "two-stroke",
            Cycle::FourStroke => "four-stroke",
        }
    }
}

/// φᵢ = (γᵢ − αᵢ) mod 2π, the crank angle of cylinder i's outer dead centre (rad, in [0, 2π)).
pub fn tdc(c: &Cylinder) -> f64 {
    (c.bank - c.phase).rem_euclid(TAU)
}

/// Is a − b a whole number of turns (within [`ANGLE_TOL`])?
fn same_mod_turn(a: f64, b: f64) -> bool {
    let d = (a - b).rem_euclid(TAU);
    d < ANGLE_TOL || TAU - d < ANGLE_TOL
}

/// The slots a cylinder can fire in: j with φ₁ + j·P/N ≡ φᵢ (mod 2π) — one slot in a
/// two-stroke cycle, at most two in a four-stroke one.
fn slots(layout: &Layout, cycle: Cycle) -> Vec<Vec<usize>> {
    let n = layout.cylinders.len();
    let phi1 = tdc(&layout.cylinders[0]);
    let dt = cycle.period() / n as f64;
    layout
        .cylinders
        .iter()
        .map(|c| {
            let p = tdc(c);
            (0..n)
                .filter(|&j| same_mod_turn(phi1 + j as f64 * dt, p))
                .collect()
        })
        .collect()
}

/// The layout's even firing orders (cylinder numbers from 1, cylinder 1 first): at most
/// [`MAX_LISTED`] of them in lexicographic order, and how many there are. Each is a perfect
/// matching of cylinders to the cycle's N evenly spaced slots, cylinder 1 in slot 0 (every
/// cylinder has at most two slots, so the backtracking below meets a dead end at once).
pub fn even_orders(layout: &Layout, cycle: Cycle) -> (Vec<Vec<usize>>, usize) {
    let s = slots(layout, cycle);
    let n = s.len();
    if s.iter().any(Vec::is_empty) || !s[0].contains(&0) {
        return (Vec::new(), 0);
    }
    // Slot → cylinder, filled slot by slot so that the orders come out lexicographically.
    let mut by_slot = vec![usize::MAX; n];
    let mut used = vec![false; n];
    let (mut listed, mut count) = (Vec::new(), 0);
    fill(&s, 0, &mut by_slot, &mut used, &mut listed, &mut count);
    (listed, count)
}

/// Fills slot `j` and the ones after it with every unused cylinder that can fire there.
fn fill(
    s: &[Vec<usize>],
    j: usize,
    by_slot: &mut Vec<usize>,
    used: &mut Vec<bool>,
    listed: &mut Vec<Vec<usize>>,
    count: &mut usize,
) {
    let n = s.len();
    if j == n {
        *count += 1;
        if listed.len() < MAX_LISTED {
            listed.push(by_slot.iter().map(|c| c + 1).collect());
        }
        return;
    }
    for i in 0..n {
        if used[i] || !s[i].contains(&j) || (j == 0) != (i == 0) {
            continue;
        }
        used[i] = true;
        by_slot[j] = i;
        fill(s, j + 1, by_slot, used, listed, count);
        used[i] = false;
    }
}

/// Does the layout fire evenly in `order` (cylinder numbers from 1, cylinder 1 first)?
pub fn fires_evenly_in(layout: &Layout, cycle: Cycle, order: &[usize]) -> bool {
    let s = slots(layout, cycle);
    order.len() == s.len()
        && order.first() == Some(&1)
        && order
            .iter()
            .enumerate()
            .all(|(j, &c)| (1..=s.len()).contains(&c) && s[c - 1].contains(&j))
}

/// What the phase search admits: any layout, or only those that fire evenly (in the given
/// order, if one is given).
#[derive(Debug, Clone, PartialEq)]
pub struct Admissible {
    /// The cycle.
    pub cycle: Cycle,
    /// The firing order asked for (cylinder numbers from 1), if any.
    pub order: Option<Vec<usize>>,
}

impl Admissible {
    /// Is the layout admitted?
    pub fn admits(&self, layout: &Layout) -> bool {
        match &self.order {
            Some(o) => fires_evenly_in(layout, self.cycle, o),
            None => even_orders_exist(layout, self.cycle),
        }
    }
}

/// Is there an even firing order (without listing them all)?
fn even_orders_exist(layout: &Layout, cycle: Cycle) -> bool {
    // Counting is cheap here: at most 2^(N/2) matchings, each found without backtracking.
    even_orders(layout, cycle).1 > 0
}

/// The candidate layouts of a phase search: cylinder 1 at `first`, every other at a multiple
/// of `step` (candidate k's digits in base 2π/step, cylinder 2's fastest), those `admissible`
/// admits — in enumeration order.
pub fn candidate_layouts(
    layout: &Layout,
    step: f64,
    admissible: Option<&Admissible>,
) -> Vec<Vec<f64>> {
    let n = layout.cylinders.len();
    let m = (TAU / step).round() as usize;
    let total = m.pow(n as u32 - 1);
    let first = layout.cylinders[0].phase;
    let mut trial = layout.clone();
    (0..total)
        .map(|k| {
            let mut out = vec![first];
            let mut rest = k;
            for _ in 1..n {
                out.push((rest % m) as f64 * step);
                rest /= m;
            }
            out
        })
        .filter(|phases| {
            admissible.is_none_or(|a| {
                for (c, p) in trial.cylinders.iter_mut().zip(phases) {
                    c.phase = *p;
                }
                a.admits(&trial)
            })
        })
        .collect()
}

/// An order as the report writes it: `1-3-4-2`.
pub fn order_text(order: &[usize]) -> String {
    order
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("-")
}
