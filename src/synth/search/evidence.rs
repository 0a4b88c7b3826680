//! The evidence of a heuristic search (JSON key `search`): what a multistart did and how
//! consistent its ends were. A multistart is not a proof of global optimality, so a family
//! reports its best design as `best_found` with this evidence.

/// The evidence behind a `best_found` status: what a heuristic global search did and how
/// consistent its best results were (JSON key `search`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, Default)]
pub struct SearchEvidence {
    /// The search, with its reference (e.g. "Halton 256 + Nelder–Mead (Lagarias 1998) from 8 starts").
    pub method: String,
    /// Local searches started.
    pub starts: usize,
    /// Distinct local optima (basins) the starts ended in.
    pub distinct_basins: usize,
    /// Objective evaluations in all.
    pub evaluations: usize,
    /// The best few distinct local optima's objective values, best first (SI, the objective's unit).
    pub best_values: Vec<f64>,
    /// How many starts ended within `rel_tol` of the best value.
    pub starts_at_best: usize,
    /// (second best − best)/|best| over distinct basins; absent with one basin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spread_rel: Option<f64>,
}

/// When two ends of local searches are one basin: values v, w within `rel` of each other
/// (|v − w| ≤ rel·|w|), or — with `point` = (spans, tol) — points p, q within `tol` of each
/// other in every coordinate relative to its span (max_i |p_i − q_i|/span_i ≤ tol).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SameBasin<'a> {
    /// Relative tolerance on the values.
    pub rel: f64,
    /// The spans of the coordinates and the tolerance relative to them, if points count.
    pub point: Option<(&'a [f64], f64)>,
}

impl SameBasin<'_> {
    /// Whether the end `(p, v)` lies in the basin of the end `(q, w)`.
    fn same(&self, (p, v): (&[f64], f64), (q, w): (&[f64], f64)) -> bool {
        let near = self.point.is_some_and(|(spans, tol)| {
            let d = p.iter().zip(q).zip(spans).fold(0.0f64, |m, ((a, b), s)| {
                m.max((a - b).abs() / s.max(f64::MIN_POSITIVE))
            });
            d <= tol
        });
        near || (v - w).abs() <= self.rel * w.abs()
    }
}

impl SearchEvidence {
    /// The evidence of a minimising multistart from the objective values its starts ended
    /// at (feasible ends only) out of `starts` starts: ends within `same_rel` (relative) of
    /// each other are one basin; the best five distinct values are kept, best first.
    pub fn of_minima(
        method: String,
        ends: Vec<f64>,
        starts: usize,
        evaluations: usize,
        same_rel: f64,
    ) -> SearchEvidence {
        let same = SameBasin {
            rel: same_rel,
            point: None,
        };
        let ends = ends.into_iter().map(|v| (Vec::new(), v)).collect();
        SearchEvidence::of_ends(method, ends, starts, evaluations, &same, 1.0)
    }

    /// The evidence of a minimising multistart from the points and values `(x, v)` its
    /// starts ended at, out of `starts` starts and `evaluations` cost evaluations.
    ///
    /// The ends are ranked by value; each joins the first basin (in rank order) it is the
    /// same as ([`SameBasin`]), else opens one. With v₀ the best value, the starts at best
    /// are those with v ≤ v₀ + rel·|v₀|, the spread is (w₁ − v₀)/|v₀| (w₁ the second basin's
    /// best), and the best five basins' values are kept, times `scale` (the cost's unit
    /// into the objective's; the spread is taken before scaling).
    pub fn of_ends(
        method: String,
        mut ends: Vec<(Vec<f64>, f64)>,
        starts: usize,
        evaluations: usize,
        same: &SameBasin,
        scale: f64,
    ) -> SearchEvidence {
        ends.sort_by(|a, b| a.1.total_cmp(&b.1));
        let best = ends.first().map(|e| e.1);
        let at_best = best.map_or(0, |b| {
            ends.iter()
                .filter(|e| e.1 <= b + same.rel * b.abs())
                .count()
        });
        let mut basins: Vec<(&[f64], f64)> = Vec::new();
        for (p, v) in &ends {
            if !basins.iter().any(|&q| same.same((p, *v), q)) {
                basins.push((p, *v));
            }
        }
        let spread_rel =
            (basins.len() > 1).then(|| (basins[1].1 - basins[0].1) / basins[0].1.abs().max(1e-300));
        SearchEvidence {
            method,
            starts,
            distinct_basins: basins.len(),
            evaluations,
            starts_at_best: at_best,
            spread_rel,
            best_values: basins.iter().take(5).map(|b| b.1 * scale).collect(),
        }
    }
}
