//! The energy curve of a drive torque as a field of the certified minimax
//! ([`crate::synth::minimax`]), so that "the design that minimises the energy fluctuation ΔE"
//! is a cone program with the same exchange loop and certificate as every other objective
//! (issue 33; `../shared/domain/machine-as-it-runs.md`).
//!
//! A drive torque affine in the design, T(φ; x) = T₀(φ) + Σⱼ Tⱼ(φ) xⱼ, has the energy curve
//! E(φ; x) = ∫₀^φ (T − T̄) dφ = E₀(φ) + Σⱼ Eⱼ(φ) xⱼ, affine too, with each Eⱼ the zero-mean
//! antiderivative of its column ([`crate::dynamics::antiderivatives`]). Then
//!
//! ΔE(x) = max_φ E − min_φ E = 2 min_c max_φ |E(φ; x) − c|,
//!
//! the optimal offset c being the mid-range (max E + min E)/2. So min over x of ΔE is the
//! weighted minimax `min t s.t. 2|E(φ; x) − c| ≤ t` over (x, c), with c one extra variable of
//! the engine: a scalar field like any torque, with the exchange loop on its continuous
//! maximum and the engine's lower bound certifying ΔE. The offset is bounded by
//! [`EnergyField::offset_bound`] (the mid-range lies within the range of E, which the grid
//! bounds), so the engine's lower bound stays rigorous.

use crate::dynamics::{antiderivatives, Antiderivative, DriveError, DriveSettings};
use crate::synth::minimax::{AffineField, AffineValue};

/// E(φ; x) − c of a scalar torque field: b = E₀, the design's columns Eⱼ, and −1 in the
/// offset's column (see the module).
pub struct EnergyField {
    name: String,
    /// E₀, the design-independent part.
    b: Antiderivative,
    /// (j, Eⱼ) for the columns the torque depends on.
    cols: Vec<(usize, Antiderivative)>,
    /// The offset variable's index.
    offset: usize,
    /// E₀ and the columns' values by θ's bits: the exchange loop, the certificate and the
    /// peaks' error bounds evaluate the field at the same angles again, and each value is a
    /// trigonometric sum over up to half the grid (a process load's kink keeps every term).
    memo: crate::numeric::AngleMemo<Vec<f64>>,
}

impl EnergyField {
    /// The energy field of the scalar field `torque` (n design variables, one of which, at
    /// `offset`, is the offset c and must not enter the torque).
    pub fn new(
        torque: &dyn AffineField,
        n: usize,
        offset: usize,
        s: &DriveSettings,
    ) -> Result<EnergyField, DriveError> {
        let mut val = AffineValue::zeros(n);
        let mut all = antiderivatives(
            |phi, out| {
                val.b = [0.0; 2];
                val.a.iter_mut().for_each(|v| *v = 0.0);
                torque.eval(phi, &mut val);
                out[0] = val.b[0];
                out[1..].copy_from_slice(val.row(0));
            },
            n + 1,
            s,
        )?
        .into_iter();
        let b = all.next().expect("n + 1 columns");
        let cols = all
            .enumerate()
            .filter(|(j, e)| *j != offset && !e.is_zero())
            .collect();
        Ok(EnergyField {
            name: format!("energy curve of the {}", torque.name()),
            b,
            cols,
            offset,
            memo: Default::default(),
        })
    }

    /// A bound B on |c| at the optimum: the mid-range of E(·; x) lies within E's range, so
    /// within sup|E₀| + Σⱼ sup|Eⱼ|·|xⱼ|max (plus the errors), with |xⱼ| ≤ `x_max(j)`.
    pub fn offset_bound(&self, x_max: impl Fn(usize) -> f64) -> f64 {
        let b = self.b.sup + self.b.error;
        b + self
            .cols
            .iter()
            .map(|(j, e)| (e.sup + e.error) * x_max(*j))
            .sum::<f64>()
    }

    /// The largest grid any column needed.
    pub fn samples(&self) -> usize {
        self.cols
            .iter()
            .map(|c| c.1.samples)
            .fold(self.b.samples, usize::max)
    }
}

impl AffineField for EnergyField {
    fn name(&self) -> &str {
        &self.name
    }

    fn dim(&self) -> usize {
        1
    }

    /// E₀ and each column at θ (remembered by θ's bits: the same values again).
    fn eval(&self, theta: f64, out: &mut AffineValue) {
        let values = self.memo.get_or(theta, || {
            std::iter::once(self.b.eval(theta))
                .chain(self.cols.iter().map(|(_, e)| e.eval(theta)))
                .collect()
        });
        out.b = [values[0], 0.0];
        let row = out.row_mut(0);
        for ((j, _), v) in self.cols.iter().zip(&values[1..]) {
            row[*j] = *v;
        }
        row[self.offset] = -1.0;
    }

    /// The interpolants' error bounds, each column's times |xⱼ|.
    fn error(&self, _theta: f64, x: &[f64]) -> f64 {
        self.b.error
            + self
                .cols
                .iter()
                .map(|(j, e)| e.error * x[*j].abs())
                .sum::<f64>()
    }
}
