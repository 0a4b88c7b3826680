//! Calibration (`cwsynth calibrate`): the unknown data a problem file names in its
//! `[calibrate]` section (a length the paper lost, a mass nobody weighed) fitted so that the
//! result reproduces measured or printed values, by weighted least squares
//! χ²(p) = Σ ((y_k(p) − ŷ_k)/σ_k)², then the design solved with the fitted values.
//!
//! Every evaluation is the problem text with the parameters written back (`toml_edit`, in the
//! SI unit of each parameter's dimension) and solved as a file would be, so any family and
//! any result key can be calibrated. One parameter against one value is a root of
//! y(p) − ŷ (bracketed on a scan of the bounds, then Brent); otherwise argmin's Nelder–Mead
//! minimises χ² on the box (Nelder & Mead 1965). The uncertainty is the linearised
//! covariance C = (JᵀWJ)⁻¹, W = diag(1/σ_k²) with σ_k² the data's uncertainty plus the
//! solve's own error of y_k, J by central differences; a parameter the data cannot fix
//! (a zero or nearly dependent column of J, fewer values than parameters) is said to be
//! non-identifiable instead of given a number.

use crate::families::{parse_str, solve_scene};
use crate::numeric::{brent_root, minimize_1d};
use crate::problem::calibrate::{resolve_calibration, CalibrateRaw, Calibration};
use crate::problem::ProblemError;
use crate::report::SolveResult;
use crate::synth::search::{nelder_mead, NelderMead};
use crate::units::Dim;
use std::path::Path;

/// Why a calibration could not run.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// The problem file does not resolve.
    #[error("{0}")]
    Problem(ProblemError),
    /// The file has no `[calibrate]` section.
    #[error("{0}: no [calibrate] section: name the unknown parameters ([[calibrate.parameter]]) and the values to match ([[calibrate.match]])")]
    NoSection(String),
    /// A parameter value could not be written back or read.
    #[error("calibrate.parameter `{key}`: {why}")]
    Parameter {
        /// The parameter's key.
        key: String,
        /// Why.
        why: String,
    },
    /// The result has no value at a match's key.
    #[error("calibrate.match `{0}`: the result has no number at this key")]
    NoValue(String),
}

impl From<ProblemError> for CalibrateError {
    fn from(e: ProblemError) -> CalibrateError {
        CalibrateError::Problem(e)
    }
}

/// A fitted parameter.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FittedParameter {
    /// Dotted key of the problem file.
    pub key: String,
    /// Fitted value (SI).
    pub value: f64,
    /// Its standard uncertainty (SI), from the linearised covariance; absent when the data
    /// cannot identify it.
    pub uncertainty: Option<f64>,
    /// The SI unit of value and uncertainty.
    pub unit: String,
    /// The bounds searched (SI).
    pub min: f64,
    /// See `min`.
    pub max: f64,
    /// On a bound: the bound, not the data, decides it.
    pub at_bound: bool,
    /// ∂y_k/∂p for each match (SI per SI).
    pub sensitivity: Vec<f64>,
}

/// A value matched.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MatchedValue {
    /// Dotted result key.
    pub key: String,
    /// The target (SI).
    pub target: f64,
    /// The result at the fitted parameters (SI).
    pub fitted: f64,
    /// fitted − target.
    pub residual: f64,
    /// σ used in the fit: the data's uncertainty and the solve's error, combined (SI).
    pub sigma: f64,
    /// Source note.
    pub note: String,
}

/// The fit.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Fit {
    /// The parameters.
    pub parameters: Vec<FittedParameter>,
    /// The values matched.
    pub matches: Vec<MatchedValue>,
    /// χ² at the fit.
    pub chi2: f64,
    /// Every parameter identified by the data.
    pub identifiable: bool,
    /// Solves spent.
    pub evaluations: usize,
    /// How the fit was found.
    pub method: String,
    /// What to know about the fit (non-identifiability, bounds, no exact fit).
    pub notes: Vec<String>,
}

/// A calibration: the fit and the scene solved with the fitted values (its name
/// `<name>-calibrated`, the fit in its section `calibration`).
pub struct Calibrated {
    /// The fit.
    pub fit: Fit,
    /// The result with the fitted values.
    pub result: SolveResult,
}

/// The problem text with the parameters set (each in its dimension's SI unit).
fn with_values(text: &str, cal: &Calibration, p: &[f64]) -> Result<String, CalibrateError> {
    let mut doc: toml_edit::DocumentMut =
        text.parse()
            .map_err(|e: toml_edit::TomlError| CalibrateError::Parameter {
                key: String::new(),
                why: e.to_string(),
            })?;
    for (par, &v) in cal.parameters.iter().zip(p) {
        let value = match par.dim {
            Dim::Dimensionless => toml_edit::value(v),
            d => toml_edit::value(format!("{v:e} {}", d.si())),
        };
        let parts: Vec<&str> = par.key.split('.').map(str::trim).collect();
        let (last, path) = parts.split_last().expect("checked: dotted");
        let mut item = doc.as_item_mut();
        for part in path {
            item = item
                .get_mut(part)
                .filter(|i| i.is_table_like())
                .ok_or_else(|| CalibrateError::Parameter {
                    key: par.key.clone(),
                    why: format!("no table `{part}` in the file"),
                })?;
        }
        let t = item.as_table_like_mut().expect("checked");
        if t.get(last).is_none() {
            return Err(CalibrateError::Parameter {
                key: par.key.clone(),
                why: "not a key of the file: give it a starting value (it is overwritten)".into(),
            });
        }
        t.insert(last, value);
    }
    Ok(doc.to_string())
}

/// The result at parameters `p`, and the values at the match keys with the solve's own error
/// of each (0 where the result states none).
fn evaluate(
    text: &str,
    path: &Path,
    cal: &Calibration,
    p: &[f64],
) -> Result<(SolveResult, Vec<(f64, f64)>), CalibrateError> {
    let scene = parse_str(&with_values(text, cal, p)?, path)?;
    let r = solve_scene(&scene);
    let ys = cal
        .matches
        .iter()
        .map(|m| {
            let y = r
                .lookup(&m.key)
                .ok_or_else(|| CalibrateError::NoValue(m.key.clone()))?;
            // An objective's stated error (other keys state none).
            let err = m
                .key
                .strip_prefix("objectives.")
                .and_then(|k| r.errors.get(k).copied())
                .unwrap_or(0.0);
            Ok((y, err))
        })
        .collect::<Result<Vec<_>, CalibrateError>>()?;
    Ok((r, ys))
}

/// The problem file's table and its resolved `[calibrate]` section.
fn section(text: &str, path: &Path) -> Result<(toml::Table, Calibration), CalibrateError> {
    // The file must be valid as it stands (its own values are the starting point).
    parse_str(text, path)?;
    let table: toml::Table = toml::from_str(text).map_err(|e| CalibrateError::Parameter {
        key: String::new(),
        why: e.to_string(),
    })?;
    let raw: CalibrateRaw = match table.get("calibrate") {
        Some(v) => {
            v.clone()
                .try_into()
                .map_err(|e: toml::de::Error| CalibrateError::Parameter {
                    key: String::new(),
                    why: e.to_string(),
                })?
        }
        None => return Err(CalibrateError::NoSection(path.display().to_string())),
    };
    let cal = resolve_calibration(&raw).map_err(|e| CalibrateError::Parameter {
        key: String::new(),
        why: e.to_string(),
    })?;
    Ok((table, cal))
}

/// One calibration's problem: the text, its section and the solves counted.
struct Problem<'a> {
    text: &'a str,
    path: &'a Path,
    table: toml::Table,
    cal: Calibration,
    lo: Vec<f64>,
    hi: Vec<f64>,
    evals: std::cell::Cell<usize>,
}

impl Problem<'_> {
    /// The result and the values at the match keys at parameters `p` (not counted).
    fn evaluate(&self, p: &[f64]) -> Result<(SolveResult, Vec<(f64, f64)>), CalibrateError> {
        evaluate(self.text, self.path, &self.cal, p)
    }

    /// Count `n` solves.
    fn count(&self, n: usize) {
        self.evals.set(self.evals.get() + n);
    }

    /// χ² at `p` (∞ where the scene does not solve), counted.
    fn chi2(&self, p: &[f64]) -> f64 {
        self.count(1);
        match self.evaluate(p) {
            Ok((_, ys)) => ys
                .iter()
                .zip(&self.cal.matches)
                .map(|((y, _), m)| ((y - m.value) / m.uncertainty).powi(2))
                .sum(),
            Err(_) => f64::INFINITY,
        }
    }

    /// One parameter against one value: y(p) − ŷ bracketed on a 16-point scan of the bounds,
    /// then Brent's root (argmin's `BrentRoot`); without a sign change the least |y − ŷ| by
    /// argmin's `BrentOpt`. The parameter and the method; what to know into `notes`.
    fn fit_one(&self, notes: &mut Vec<String>) -> (Vec<f64>, String) {
        let (lo, hi, cal) = (&self.lo, &self.hi, &self.cal);
        let m = &cal.matches[0];
        let g = |x: f64| -> f64 {
            self.count(1);
            self.evaluate(&[x])
                .map(|(_, ys)| ys[0].0 - m.value)
                .unwrap_or(f64::NAN)
        };
        let xs: Vec<f64> = (0..=16)
            .map(|k| lo[0] + (hi[0] - lo[0]) * k as f64 / 16.0)
            .collect();
        let gs: Vec<f64> = xs.iter().map(|&x| g(x)).collect();
        let mut roots = Vec::new();
        for k in 0..16 {
            if gs[k].is_finite() && gs[k + 1].is_finite() && gs[k] * gs[k + 1] <= 0.0 {
                if let Ok(r) = brent_root(g, xs[k], xs[k + 1], 1e-13 * (hi[0] - lo[0])) {
                    roots.push(r.x);
                }
            }
        }
        match roots.len() {
            0 => {
                let best = minimize_1d(|x| g(x).abs(), lo[0], hi[0], 1e-12 * (hi[0] - lo[0]))
                    .map(|b| b.x)
                    .unwrap_or(0.5 * (lo[0] + hi[0]));
                notes.push(format!(
                    "no parameter in [{}, {}] reproduces the value exactly: the least residual is given",
                    lo[0], hi[0]
                ));
                (
                    vec![best],
                    "16-point scan, no sign change; argmin Brent on |y − ŷ|".to_string(),
                )
            }
            n => {
                if n > 1 {
                    notes.push(format!(
                        "{n} parameter values in the bounds reproduce the value ({}): the one nearest the file's own value is kept; narrow the bounds to choose",
                        roots.iter().map(|r| format!("{r:.6e}")).collect::<Vec<_>>().join(", ")
                    ));
                }
                let own = own_value(&self.table, &cal.parameters[0].key, cal.parameters[0].dim)
                    .unwrap_or(0.5 * (lo[0] + hi[0]));
                let best = roots
                    .iter()
                    .copied()
                    .min_by(|a, b| (a - own).abs().total_cmp(&(b - own).abs()))
                    .expect("n ≥ 1");
                (
                    vec![best],
                    "16-point scan of the bounds, then Brent on y(p) − ŷ to 1e-13 of the range"
                        .to_string(),
                )
            }
        }
    }

    /// The Jacobian ∂y_k/∂p_i at `p_fit` by central differences (1e-4 of each range, kept
    /// in the bounds).
    fn jacobian(&self, p_fit: &[f64]) -> Result<Vec<Vec<f64>>, CalibrateError> {
        let (np, nm) = (self.cal.parameters.len(), self.cal.matches.len());
        let (lo, hi) = (&self.lo, &self.hi);
        let mut jac = vec![vec![0.0; np]; nm];
        for i in 0..np {
            let h = 1e-4 * (hi[i] - lo[i]);
            let (mut a, mut b) = (p_fit.to_vec(), p_fit.to_vec());
            a[i] = (p_fit[i] - h).max(lo[i]);
            b[i] = (p_fit[i] + h).min(hi[i]);
            let (_, ya) = self.evaluate(&a)?;
            let (_, yb) = self.evaluate(&b)?;
            self.count(2);
            for k in 0..nm {
                jac[k][i] = (yb[k].0 - ya[k].0) / (b[i] - a[i]);
            }
        }
        Ok(jac)
    }
}

/// The linearised covariance C = (JᵀWJ)⁻¹ through the SVD of W^½J (rows of J over `sigma`):
/// a singular value below 1e-10 of the largest is a direction the data do not fix. The
/// rank and C (absent when the rank is short).
fn covariance(
    jac: &[Vec<f64>],
    sigma: &[f64],
    np: usize,
) -> (usize, Option<nalgebra::DMatrix<f64>>) {
    let nm = jac.len();
    let a = nalgebra::DMatrix::from_fn(nm, np, |k, i| jac[k][i] / sigma[k]);
    let svd = a.clone().svd(true, true);
    let smax = svd.singular_values.max();
    let rank = svd
        .singular_values
        .iter()
        .filter(|&&s| s > 1e-10 * smax && s > 0.0)
        .count();
    let cov = (rank == np)
        .then(|| (a.transpose() * &a).try_inverse())
        .flatten();
    (rank, cov)
}

/// Fits the `[calibrate]` section of the problem text, then solves with the fitted values.
pub fn calibrate(text: &str, path: &Path) -> Result<Calibrated, CalibrateError> {
    let (table, cal) = section(text, path)?;
    let problem = Problem {
        text,
        path,
        lo: cal.parameters.iter().map(|p| p.min).collect(),
        hi: cal.parameters.iter().map(|p| p.max).collect(),
        table,
        cal,
        evals: std::cell::Cell::new(0),
    };
    let cal = &problem.cal;
    let (np, nm) = (cal.parameters.len(), cal.matches.len());
    let mut notes = Vec::new();
    let (p_fit, method) = if np == 1 && nm == 1 {
        problem.fit_one(&mut notes)
    } else {
        let p0: Vec<f64> = cal
            .parameters
            .iter()
            .map(|p| own_value(&problem.table, &p.key, p.dim).unwrap_or(0.5 * (p.min + p.max)))
            .collect();
        (
            nelder_mead_in_box(&|p: &[f64]| problem.chi2(p), &p0, &problem.lo, &problem.hi),
            "argmin Nelder–Mead (Nelder & Mead 1965) on χ² in the box".to_string(),
        )
    };
    // The fit's result, and the Jacobian by central differences.
    let (result, ys) = problem.evaluate(&p_fit)?;
    problem.count(1);
    let jac = problem.jacobian(&p_fit)?;
    let sigma: Vec<f64> = cal
        .matches
        .iter()
        .zip(&ys)
        .map(|(m, &(_, e))| m.uncertainty.hypot(e))
        .collect();
    let (rank, cov) = covariance(&jac, &sigma, np);
    let identifiable = rank == np;
    if !identifiable {
        notes.push(format!(
            "not identifiable: {} parameter(s) against {} value(s), rank {rank} — the data fix only {rank} combination(s) of the parameters; add values to match or fix a parameter",
            np, nm
        ));
    }
    let chi2: f64 = ys
        .iter()
        .zip(&cal.matches)
        .zip(&sigma)
        .map(|(((y, _), m), s)| ((y - m.value) / s).powi(2))
        .sum();
    let parameters = fitted_parameters(cal, &p_fit, &jac, cov.as_ref());
    notes.push(
        "the uncertainty propagates the stated σ of the matched values (and the solve's own error) only: a difference between this model and the source of the values (another model, a measurement) is not in it".into(),
    );
    for p in parameters.iter().filter(|p| p.at_bound) {
        notes.push(format!(
            "`{}` is on a bound: the bound, not the data, decides it",
            p.key
        ));
    }
    let matches = cal
        .matches
        .iter()
        .zip(&ys)
        .zip(&sigma)
        .map(|((m, &(y, _)), &s)| MatchedValue {
            key: m.key.clone(),
            target: m.value,
            fitted: y,
            residual: y - m.value,
            sigma: s,
            note: m.note.clone(),
        })
        .collect();
    let fit = Fit {
        parameters,
        matches,
        chi2,
        identifiable,
        evaluations: problem.evals.get(),
        method,
        notes,
    };
    let mut result = result;
    result.name = format!("{}-calibrated", result.name);
    result.warnings.extend(fit.notes.iter().cloned());
    result.extra.insert(
        "calibration".into(),
        serde_json::to_value(&fit).expect("plain data"),
    );
    Ok(Calibrated { fit, result })
}

/// The fitted parameters: value, uncertainty (from the covariance, if any), bounds, whether
/// on a bound, and the sensitivities.
fn fitted_parameters(
    cal: &Calibration,
    p_fit: &[f64],
    jac: &[Vec<f64>],
    cov: Option<&nalgebra::DMatrix<f64>>,
) -> Vec<FittedParameter> {
    cal.parameters
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let at_bound = (p_fit[i] - p.min).abs() <= 1e-9 * (p.max - p.min)
                || (p.max - p_fit[i]).abs() <= 1e-9 * (p.max - p.min);
            FittedParameter {
                key: p.key.clone(),
                value: p_fit[i],
                uncertainty: cov.map(|c| c[(i, i)].max(0.0).sqrt()),
                unit: p.dim.si().to_string(),
                min: p.min,
                max: p.max,
                at_bound,
                sensitivity: jac.iter().map(|row| row[i]).collect(),
            }
        })
        .collect()
}

/// The file's own value of a parameter (its starting point), in SI.
fn own_value(table: &toml::Table, key: &str, dim: Dim) -> Option<f64> {
    match crate::problem::edit::dotted_get(table, key)? {
        toml::Value::String(s) => crate::units::parse(s, dim).ok(),
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// Nelder–Mead on the box [lo, hi] (argmin's, through [`crate::synth::search::nelder_mead`]),
/// in coordinates scaled to [0, 1]: outside the box the cost is the value at the projection
/// plus 1e6 times the distance (a penalty). From the file's values `p0`, a simplex of steps
/// ±0.1 (towards the box's middle); 400 iterations at most, stop at a spread of 1e-12.
fn nelder_mead_in_box(f: &dyn Fn(&[f64]) -> f64, p0: &[f64], lo: &[f64], hi: &[f64]) -> Vec<f64> {
    let unscale = |z: &[f64]| -> Vec<f64> {
        z.iter()
            .enumerate()
            .map(|(i, &t)| lo[i] + (hi[i] - lo[i]) * t.clamp(0.0, 1.0))
            .collect()
    };
    let cost = |z: &[f64]| {
        let out: f64 = z.iter().map(|t| (t - t.clamp(0.0, 1.0)).abs()).sum();
        f(&unscale(z)) + 1e6 * out
    };
    let n = p0.len();
    let z0: Vec<f64> = (0..n).map(|i| (p0[i] - lo[i]) / (hi[i] - lo[i])).collect();
    let mut simplex = vec![z0.clone()];
    for i in 0..n {
        let mut z = z0.clone();
        z[i] += if z[i] < 0.5 { 0.1 } else { -0.1 };
        simplex.push(z);
    }
    let settings = NelderMead {
        simplex,
        sd_tolerance: 1e-12,
        max_iters: 400,
    };
    let best = nelder_mead(&cost, &settings).map_or(z0, |end| end.x);
    unscale(&best)
}
