//! The fields at a design: evaluated at one angle, their refined true peaks over the
//! period (scan grid + refinement) with error bounds (their RMS: `rms`).

use super::validate::{bad, check_finite};
use super::{AffineValue, Engine, FieldPeak, MinimaxError};
use crate::numeric::{periodic_peak_sampled, PeriodicPeak, Refine};
use std::cell::RefCell;

impl<'p, 'a> Engine<'p, 'a> {
    /// The refined peaks of every field at a given design (an analysis, e.g. without
    /// counterweights), with their error bounds; `limits` only mark violations.
    pub fn peaks(&self, x: &[f64]) -> Result<Vec<FieldPeak>, MinimaxError> {
        if x.len() != self.n {
            return Err(bad(
                "x",
                format!("has {} values, the problem {}", x.len(), self.n),
            ));
        }
        (0..self.pb.fields.len())
            .map(|f| {
                let p = self.scan(f, x)?;
                self.field_peak(f, x, &p, &self.pb.limits)
            })
            .collect()
    }

    pub(super) fn eval(&self, f: usize, theta: f64) -> Result<AffineValue, MinimaxError> {
        let mut v = AffineValue::zeros(self.n);
        self.pb.fields[f].eval(theta, &mut v);
        check_finite(self.pb.fields[f], theta, &v)?;
        Ok(v)
    }

    /// The refined peak of field f at x (grid scan + refinement of every local maximum).
    pub(super) fn scan(&self, f: usize, x: &[f64]) -> Result<PeriodicPeak, MinimaxError> {
        let field = self.pb.fields[f];
        let d = field.dim();
        let ys: Vec<f64> = self.grid[f].iter().map(|v| v.magnitude(d, x)).collect();
        let buf = RefCell::new(AffineValue::zeros(self.n));
        periodic_peak_sampled(
            &ys,
            |theta| {
                let mut v = buf.borrow_mut();
                v.clear();
                field.eval(theta, &mut v);
                v.magnitude(d, x)
            },
            Some(self.s.peak_xtol),
            Refine::All,
        )
        .map_err(|e| match e {
            crate::numeric::SearchError::NotFinite { x } => MinimaxError::NotFinite {
                field: field.name().to_string(),
                theta: x,
            },
            other => bad(format!("fields[{f}]"), other.to_string()),
        })
    }

    /// The evaluation error bound of field f at θ for x: callback + engine round-off.
    pub(super) fn eval_error(&self, f: usize, v: &AffineValue, theta: f64, x: &[f64]) -> f64 {
        let field = self.pb.fields[f];
        let gamma = (self.n as f64 + 3.0) * f64::EPSILON;
        field.error(theta, x) + gamma * v.size(field.dim(), x)
    }

    pub(super) fn field_peak(
        &self,
        f: usize,
        x: &[f64],
        p: &PeriodicPeak,
        limits: &[(usize, f64)],
    ) -> Result<FieldPeak, MinimaxError> {
        let mut e_eval: f64 = 0.0;
        for m in &p.maxima {
            let v = self.eval(f, m.x)?;
            e_eval = e_eval.max(self.eval_error(f, &v, m.x, x));
        }
        let limit = limits
            .iter()
            .filter(|l| l.0 == f)
            .map(|l| l.1)
            .fold(None, |a: Option<f64>, e| Some(a.map_or(e, |a| a.min(e))));
        Ok(FieldPeak {
            name: self.pb.fields[f].name().to_string(),
            peak: p.peak.fx,
            angle: p.peak.x,
            error: p.error + e_eval,
            maxima: p.maxima.clone(),
            limit,
            violation: limit.map_or(0.0, |e| (p.peak.fx - e).max(0.0)),
        })
    }
}
