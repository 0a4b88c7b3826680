//! Problem assembly: the engine's scales and scan grid (`Engine::new`), and the cone
//! programs built from the fields, the sampled angles and the limits — each round's SOCP
//! (`solve_round`) and the design constraints every program shares (`design_rows`, and the
//! same constraints as smooth functions for the Newton polish, `design_constraints`).

use super::constraints::Design;
use super::grid::FieldGrid;
use super::plate::{body_rows, Cuts};
use super::validate::{bad, validate_structure};
use super::{
    var_i, var_m, var_u, AffineValue, Engine, Goal, LinearConstraint, MinimaxError, Problem,
    Relation, Settings, PER_COUNTERWEIGHT,
};
use crate::synth::conic::{run_clarabel_with, Built, ConicResult, Rows};
use crate::synth::exchange::uniform_angles;
use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;

/// The SOCP solved on one round.
pub(super) struct Round {
    pub(super) res: ConicResult,
    /// T: objective scale (L = T·min(p, d)).
    pub(super) t_scale: f64,
    /// The sampled cones, for the dual bound.
    pub(super) tags: Vec<ConeTag>,
    /// The program solved.
    pub(super) built: Built,
}

/// One sampled cone ‖c·g_f(θ; x)‖ ≤ t̂ (objective) or ≤ ε̂ (limit) of a round's SOCP.
pub(super) struct ConeTag {
    /// Its first row (the t̂ or ε̂ row; its dual is the cone's multiplier).
    pub(super) row: usize,
    pub(super) field: usize,
    pub(super) theta: f64,
    /// The factor c of the field's rows.
    pub(super) c: f64,
    /// ε̂ for a limit, `None` for an objective cone.
    pub(super) eps: Option<f64>,
}

impl Round {
    /// Σ z₀ over the objective cones: the objective's total dual weight, by which the
    /// cones' multipliers are normalised.
    pub(super) fn objective_weight(&self) -> f64 {
        let z = &self.res.z;
        self.tags
            .iter()
            .filter(|t| t.eps.is_none())
            .map(|t| z[t.row].max(0.0))
            .sum()
    }
}

impl<'p, 'a> Engine<'p, 'a> {
    /// Validates `pb` and `s`, evaluates the fields on the scan grid and fixes the scales
    /// (module doc of [`super`]: "Scaling").
    pub fn new(pb: &'p Problem<'a>, s: &Settings) -> Result<Self, MinimaxError> {
        s.validate()
            .map_err(|(field, message)| MinimaxError::Settings { field, message })?;
        validate_structure(pb)?;
        let n = pb.n();
        let grid = scan_grid(pb, s, n)?;
        let g0: Vec<f64> = (0..pb.fields.len())
            .map(|f| {
                let d = pb.fields[f].dim();
                grid[f]
                    .iter()
                    .map(|v| v.b[..d].iter().map(|b| b * b).sum::<f64>().sqrt())
                    .fold(0.0, f64::max)
            })
            .collect();
        let scale = variable_scales(pb, &grid, &g0);
        let xbound = design_bounds(pb, &scale);
        Ok(Engine {
            pb,
            s: *s,
            n,
            scale,
            g_ref: std::sync::OnceLock::new(),
            g0,
            grid,
            xbound,
            rms_grids: (0..pb.fields.len())
                .map(|_| std::sync::OnceLock::new())
                .collect(),
            cuts: std::sync::Mutex::new(pb.counterweights.iter().map(Cuts::seed).collect()),
        })
    }

    /// G_f, each field's size over the design box (`field_sizes`), computed on first use:
    /// the cone programs' scales, which the exact disc path does not build.
    pub(super) fn g_ref(&self) -> &[f64] {
        self.g_ref
            .get_or_init(|| field_sizes(self.pb, &self.grid, &self.scale))
    }

    /// Builds and solves the SOCP on the sampled angles.
    pub(super) fn solve_round(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        sets: &[Vec<(f64, AffineValue)>],
        rms_r: Option<&nalgebra::DMatrix<f64>>,
        tol: f64,
        level: f64,
    ) -> Result<Round, MinimaxError> {
        let n = self.n;
        let has_t = !matches!(goal, Goal::MinMass);
        let nv = n + has_t as usize;
        let mut rows = Rows::default();
        let mut q = vec![0.0; nv];
        let sc = &self.scale;
        // ‖(c/…)(b + A S x̂)‖ ≤ t̂ (t = Some) or ≤ bound.
        let mut tags = Vec::new();
        let t_scale = match goal {
            Goal::MinPeak(list) => {
                let _ = level;
                let t = self.peak_scale(list);
                q[n] = 1.0;
                for &(f, w) in list {
                    let d = self.pb.fields[f].dim();
                    for (theta, v) in &sets[f] {
                        tags.push(ConeTag {
                            row: rows.b.len(),
                            field: f,
                            theta: *theta,
                            c: w / t,
                            eps: None,
                        });
                        self.field_cone(&mut rows, v, d, w / t, Some(n), 0.0);
                    }
                }
                t
            }
            Goal::MinRms(f) => {
                q[n] = 1.0;
                let r = rms_r.expect("factor computed");
                rows.row(&[(n, -1.0)], 0.0);
                for i in 0..r.nrows() {
                    let coeffs: Vec<(usize, f64)> = (0..n).map(|j| (j, -r[(i, j)])).collect();
                    rows.row(&coeffs, r[(i, n)]);
                }
                rows.cones
                    .push(SupportedConeT::SecondOrderConeT(r.nrows() + 1));
                self.g_ref()[*f]
            }
            Goal::MinMass => {
                let t: f64 = self.pb.counterweights.iter().map(|c| c.m_max).sum();
                for j in 0..self.pb.counterweights.len() {
                    q[var_m(j)] = sc[var_m(j)] / t;
                }
                t
            }
        };
        for &(f, e) in limits {
            let d = self.pb.fields[f].dim();
            let g = self.g_ref()[f];
            for (theta, v) in &sets[f] {
                tags.push(ConeTag {
                    row: rows.b.len(),
                    field: f,
                    theta: *theta,
                    c: 1.0 / g,
                    eps: Some(e / g),
                });
                self.field_cone(&mut rows, v, d, 1.0 / g, None, e / g);
            }
        }
        self.design_rows(&mut rows);
        let p = CscMatrix::zeros((nv, nv));
        let built = rows.build(nv, p, q);
        // Feasibility as tight as the gap: a design infeasible by r moves the true peak at
        // the projected design by about r, which the certificate then has to absorb.
        let gap_tol = (0.01 * tol).clamp(1e-12, 1e-8);
        let res = run_clarabel_with(&built, gap_tol, |g| g.clamp(1e-12, 1e-8), false)
            .map_err(|e| bad("clarabel", e))?;
        Ok(Round {
            res,
            t_scale,
            tags,
            built,
        })
    }

    /// One sampled cone ‖c·(b + A S x̂)‖ ≤ x̂_t (the variable `t`, `Some`) or ≤ `bound`, of
    /// a field's value v (dimension d) scaled by c.
    pub(super) fn field_cone(
        &self,
        rows: &mut Rows,
        v: &AffineValue,
        d: usize,
        c: f64,
        t: Option<usize>,
        bound: f64,
    ) {
        let sc = &self.scale;
        match t {
            Some(tj) => rows.row(&[(tj, -1.0)], 0.0),
            None => rows.row(&[], bound),
        }
        for r in 0..d {
            let coeffs: Vec<(usize, f64)> = v
                .row(r)
                .iter()
                .enumerate()
                .map(|(j, a)| (j, -c * a * sc[j]))
                .collect();
            rows.row(&coeffs, c * v.b[r]);
        }
        rows.cones.push(SupportedConeT::SecondOrderConeT(d + 1));
    }

    /// A linear constraint's scale: its largest coefficient in the scaled variables.
    fn linear_scale(&self, lc: &LinearConstraint) -> f64 {
        lc.coeffs
            .iter()
            .map(|&(j, c)| (c * self.scale[j]).abs())
            .fold(0.0, f64::max)
    }

    /// T, the objective scale of a peak goal: max w·G_f over its fields.
    pub(super) fn peak_scale(&self, list: &[(usize, f64)]) -> f64 {
        list.iter()
            .map(|&(f, w)| w * self.g_ref()[f])
            .fold(0.0, f64::max)
    }

    /// The design constraints in scaled variables.
    pub(super) fn design_rows(&self, rows: &mut Rows) {
        let sc = &self.scale;
        let nonneg =
            |rows: &mut Rows, k: usize| rows.cones.push(SupportedConeT::NonnegativeConeT(k));
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, ux, uy, i) = (var_m(j), var_u(j), var_u(j) + 1, var_i(j));
            let l = c.length();
            // 0 ≤ m̂ ≤ 1 (s_m = m_max), Î ≥ 0.
            rows.row(&[(m, -1.0)], 0.0);
            rows.row(&[(m, 1.0)], 1.0);
            rows.row(&[(i, -1.0)], 0.0);
            nonneg(rows, 3);
            if c.inertia_max.is_finite() {
                rows.row(&[(i, 1.0)], c.inertia_max / sc[i]);
                nonneg(rows, 1);
            }
            if c.envelope.is_finite() {
                // ρ² m − I ≥ 0 → (ρ/ℓ)² m̂ − Î ≥ 0.
                let k = (c.envelope / l).powi(2);
                rows.row(&[(m, -k), (i, 1.0)], 0.0);
                nonneg(rows, 1);
            }
            if c.r_max.is_finite() {
                // ‖û‖ ≤ (r_max/ℓ) m̂.
                rows.row(&[(m, -c.r_max / l)], 0.0);
                rows.row(&[(ux, -1.0)], 0.0);
                rows.row(&[(uy, -1.0)], 0.0);
                rows.cones.push(SupportedConeT::SecondOrderConeT(3));
            }
            // Î m̂ ≥ |û|²: ‖(2û, Î − m̂)‖ ≤ Î + m̂.
            body_rows(rows, m, ux, i, 0.0, 0.0);
            if let Some((lo, hi)) = c.sector {
                for (ax, ay) in sector_rows(lo, hi) {
                    rows.row(&[(ux, ax), (uy, ay)], 0.0);
                }
                nonneg(rows, 3);
            }
            self.plate_rows(j, rows);
        }
        let n_cw = PER_COUNTERWEIGHT * self.pb.counterweights.len();
        for (e, &(lo, hi)) in self.pb.extra.iter().enumerate() {
            let j = n_cw + e;
            if lo.is_finite() {
                rows.row(&[(j, -1.0)], -lo / sc[j]);
                nonneg(rows, 1);
            }
            if hi.is_finite() {
                rows.row(&[(j, 1.0)], hi / sc[j]);
                nonneg(rows, 1);
            }
        }
        for lc in &self.pb.linear {
            let big = self.linear_scale(lc);
            let coeffs: Vec<(usize, f64)> = lc
                .coeffs
                .iter()
                .map(|&(j, c)| (j, c * sc[j] / big))
                .collect();
            rows.row(&coeffs, lc.rhs / big);
            rows.cones.push(match lc.relation {
                Relation::Eq => SupportedConeT::ZeroConeT(1),
                Relation::Le => SupportedConeT::NonnegativeConeT(1),
            });
        }
    }

    /// Makes a solver iterate a real body: m and I clamped to ≥ 0 and ≤ their bounds, and
    /// where I·m < |u|² by the solver's tolerance, I raised to |u|²/m (u = 0 at m = 0). The
    /// peaks are then computed at this x, so the certificate is of the design returned.
    pub(super) fn project(&self, x: &[f64]) -> Vec<f64> {
        let mut x = x.to_vec();
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, ux, i) = (var_m(j), var_u(j), var_i(j));
            x[m] = x[m].clamp(0.0, c.m_max);
            x[i] = x[i].max(0.0);
            let u2 = x[ux] * x[ux] + x[ux + 1] * x[ux + 1];
            if x[i] * x[m] < u2 {
                if x[m] > 0.0 {
                    x[i] = u2 / x[m] * (1.0 + 4.0 * f64::EPSILON);
                } else {
                    x[ux] = 0.0;
                    x[ux + 1] = 0.0;
                }
            }
            self.project_plate(j, &mut x);
        }
        x
    }

    /// The design constraints in scaled variables as smooth functions d(x̂) ≤ 0 (or = 0),
    /// each relative to its scale (the same constraints as [`Engine::design_rows`]'s cones).
    pub(super) fn design_constraints(&self) -> Vec<Design> {
        let sc = &self.scale;
        let lin = |a: Vec<(usize, f64)>, r: f64| Design::Linear { a, r, eq: false };
        let mut out = Vec::new();
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, u, i) = (var_m(j), var_u(j), var_i(j));
            let l = c.length();
            out.push(lin(vec![(m, -1.0)], 0.0));
            out.push(lin(vec![(m, 1.0)], 1.0));
            out.push(lin(vec![(i, -1.0)], 0.0));
            if c.inertia_max.is_finite() {
                out.push(lin(vec![(i, 1.0)], c.inertia_max / sc[i]));
            }
            if c.envelope.is_finite() {
                out.push(lin(vec![(i, 1.0), (m, -(c.envelope / l).powi(2))], 0.0));
            }
            if c.r_max.is_finite() {
                out.push(Design::Radius {
                    m,
                    u,
                    k: c.r_max / l,
                    c: 0.0,
                });
            }
            out.push(Design::Body {
                m,
                u,
                i,
                p: 0.0,
                q: 0.0,
            });
            if let Some((lo, hi)) = c.sector {
                for (ax, ay) in sector_rows(lo, hi) {
                    out.push(lin(vec![(u, ax), (u + 1, ay)], 0.0));
                }
            }
            self.plate_constraints(j, &mut out);
        }
        let n_cw = PER_COUNTERWEIGHT * self.pb.counterweights.len();
        for (e, &(lo, hi)) in self.pb.extra.iter().enumerate() {
            let j = n_cw + e;
            if lo.is_finite() {
                out.push(lin(vec![(j, -1.0)], -lo / sc[j]));
            }
            if hi.is_finite() {
                out.push(lin(vec![(j, 1.0)], hi / sc[j]));
            }
        }
        for lc in &self.pb.linear {
            let big = self.linear_scale(lc);
            out.push(Design::Linear {
                a: lc
                    .coeffs
                    .iter()
                    .map(|&(j, c)| (j, c * sc[j] / big))
                    .collect(),
                r: lc.rhs / big,
                eq: lc.relation == Relation::Eq,
            });
        }
        out
    }

    /// Largest relative violation of the design constraints at x.
    pub(super) fn design_violation(&self, x: &[f64]) -> f64 {
        let xh: Vec<f64> = x.iter().zip(&self.scale).map(|(v, s)| v / s).collect();
        self.design_constraints()
            .iter()
            .map(|d| {
                let v = d.value(&xh);
                if d.is_eq() {
                    v.abs()
                } else {
                    v
                }
            })
            .fold(0.0, f64::max)
    }
}

/// Each field on the scan grid θ_k = 2πk/`scan_samples`, checked finite: each value
/// written in its place.
fn scan_grid(pb: &Problem, s: &Settings, n: usize) -> Result<Vec<FieldGrid>, MinimaxError> {
    let angles = uniform_angles(s.scan_samples);
    pb.fields
        .iter()
        .map(|f| FieldGrid::eval(*f, &angles, n))
        .collect()
}

/// The column scales s_j (x = s ⊙ x̂): a counterweight's s_m = m_max, s_u = s_m ℓ,
/// s_I = s_m ℓ²; an extra variable's largest finite bound, else the largest field size over
/// its sensitivity (G_f⁰ = `g0`, the unbalanced peak), else 1.
fn variable_scales(pb: &Problem, grid: &[FieldGrid], g0: &[f64]) -> Vec<f64> {
    let nf = pb.fields.len();
    let mut scale = vec![1.0; pb.n()];
    for (j, c) in pb.counterweights.iter().enumerate() {
        let (sm, l) = (c.m_max, c.length());
        scale[var_m(j)] = sm;
        scale[var_u(j)] = sm * l;
        scale[var_u(j) + 1] = sm * l;
        scale[var_i(j)] = sm * l * l;
    }
    // Extra variables: their largest finite bound, else field size / sensitivity.
    let n_cw = PER_COUNTERWEIGHT * pb.counterweights.len();
    for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
        let j = n_cw + e;
        let bound = [lo, hi]
            .into_iter()
            .filter(|v| v.is_finite())
            .fold(0.0, |a: f64, v| a.max(v.abs()));
        scale[j] = if bound > 0.0 {
            bound
        } else {
            let mut best: f64 = 0.0;
            for f in 0..nf {
                let d = pb.fields[f].dim();
                let sens = grid[f]
                    .iter()
                    .map(|v| (0..d).map(|r| v.row(r)[j].powi(2)).sum::<f64>().sqrt())
                    .fold(0.0, f64::max);
                if sens > 0.0 && g0[f] > 0.0 {
                    best = best.max(g0[f] / sens);
                }
            }
            if best > 0.0 {
                best
            } else {
                1.0
            }
        };
    }
    scale
}

/// G_f, each field's size over the design box: max over the grid of
/// ‖b_f‖ + Σ_j ‖A_f,j‖ s_j (1 for a field that is zero).
fn field_sizes(pb: &Problem, grid: &[FieldGrid], scale: &[f64]) -> Vec<f64> {
    let n = scale.len();
    (0..pb.fields.len())
        .map(|f| {
            let d = pb.fields[f].dim();
            let g = grid[f]
                .iter()
                .map(|v| {
                    let b = v.b[..d].iter().map(|b| b * b).sum::<f64>().sqrt();
                    b + (0..n)
                        .map(|j| (0..d).map(|r| v.row(r)[j].powi(2)).sum::<f64>().sqrt() * scale[j])
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            if g > 0.0 {
                g
            } else {
                1.0
            }
        })
        .collect()
}

/// Bounds on |x̂_j| implied by the design constraints (∞ for an unbounded extra): m̂ ≤ 1;
/// Î ≤ min(I_max/s_I, (ρ/ℓ)²); |û|² ≤ Î m̂ and |û| ≤ r_max/ℓ.
fn design_bounds(pb: &Problem, scale: &[f64]) -> Vec<f64> {
    let mut xbound = vec![f64::INFINITY; scale.len()];
    for (j, c) in pb.counterweights.iter().enumerate() {
        let l = c.length();
        let i_hat = (c.inertia_max / scale[var_i(j)]).min((c.envelope / l).powi(2));
        let u_hat = i_hat.sqrt().min(c.r_max / l);
        xbound[var_m(j)] = 1.0;
        xbound[var_u(j)] = u_hat;
        xbound[var_u(j) + 1] = u_hat;
        xbound[var_i(j)] = i_hat;
    }
    let n_cw = PER_COUNTERWEIGHT * pb.counterweights.len();
    for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
        let j = n_cw + e;
        xbound[j] = lo.abs().max(hi.abs()) / scale[j];
    }
    xbound
}

/// The sector lo ≤ direction of u ≤ hi (hi − lo ≤ π) as three rows a·u ≤ 0, each (a_x, a_y):
/// cos lo·u_y − sin lo·u_x ≥ 0, sin hi·u_x − cos hi·u_y ≥ 0 and u·bisector ≥ 0.
fn sector_rows(lo: f64, hi: f64) -> [(f64, f64); 3] {
    let (sl, cl) = lo.sin_cos();
    let (sh, ch) = hi.sin_cos();
    let (sm, cm) = (0.5 * (lo + hi)).sin_cos();
    [(sl, -cl), (-sh, ch), (-cm, -sm)]
}
