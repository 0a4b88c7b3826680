//! The fields on the scan grid, stored flat: per field one vector of every angle's b and
//! one of both rows of A, so the scans, the disc path and the scales read contiguous
//! memory and the grid allocates twice per field. An [`AffineValue`] per angle (inline room
//! for 16 coefficients whatever n, 152 bytes) made the grid a copy and a zeroing of 152
//! bytes per value; on the envelope bench (`examples/envelope_ratio.rs`, 4 fields × 360
//! angles) the flat grid took the solve from about 132 µs to about 120 µs (paired runs,
//! session 33: docs/performance.md).

use super::validate::check_finite;
use super::{magnitude, AffineField, AffineValue, MinimaxError};

/// One field's values g(θ_k; x) = b_k + A_k x at the scan angles θ_k, k = 0…N−1.
pub(super) struct FieldGrid {
    /// n, the design's variables (each row of A has n entries).
    n: usize,
    /// b_k.
    b: Vec<[f64; 2]>,
    /// A_k's rows 0 and 1, 2n entries per angle (row r at r·n), angles in order.
    a: Vec<f64>,
}

/// One value of a [`FieldGrid`], borrowed: b and A's rows (the numbers of the
/// [`AffineValue`] the field wrote).
#[derive(Clone, Copy)]
pub(super) struct GridValue<'g> {
    pub(super) b: [f64; 2],
    a: &'g [f64],
}

impl<'g> GridValue<'g> {
    /// Row r of A.
    pub(super) fn row(&self, r: usize) -> &'g [f64] {
        let n = self.a.len() / 2;
        &self.a[r * n..(r + 1) * n]
    }

    /// |b + A x| ([`AffineValue::magnitude`]'s numbers, bit for bit).
    pub(super) fn magnitude(&self, dim: usize, x: &[f64]) -> f64 {
        magnitude(&self.b, self.a, dim, x)
    }

    /// The value as an [`AffineValue`] (n = its rows' length).
    pub(super) fn to_value(self) -> AffineValue {
        let mut v = AffineValue::zeros(self.a.len() / 2);
        v.b = self.b;
        v.a.copy_from_slice(self.a);
        v
    }
}

impl AffineValue {
    /// The value borrowed as a [`GridValue`] (what the disc path reads of either).
    pub(super) fn view(&self) -> GridValue<'_> {
        GridValue {
            b: self.b,
            a: &self.a,
        }
    }
}

impl FieldGrid {
    /// `field` at each of `angles` for n variables, each value checked finite.
    pub(super) fn eval(
        field: &dyn AffineField,
        angles: &[f64],
        n: usize,
    ) -> Result<FieldGrid, MinimaxError> {
        let w = 2 * n;
        let mut b = Vec::with_capacity(angles.len());
        // Extended value by value, not zeroed first and then written (the zeroing cost
        // ~2.5 % of the envelope bench's instructions; element-wise pushes cost more).
        let mut a = Vec::with_capacity(w * angles.len());
        let mut v = AffineValue::zeros(n);
        for &theta in angles {
            v.clear();
            field.eval(theta, &mut v);
            check_finite(field, theta, &v)?;
            b.push(v.b);
            a.extend_from_slice(&v.a);
        }
        Ok(FieldGrid { n, b, a })
    }

    /// N, the angles.
    pub(super) fn len(&self) -> usize {
        self.b.len()
    }

    /// The value at the first angle (θ = 0), if any.
    pub(super) fn first(&self) -> Option<GridValue<'_>> {
        self.iter().next()
    }

    /// The values in the order of the angles.
    pub(super) fn iter(&self) -> impl Iterator<Item = GridValue<'_>> + '_ {
        let w = (2 * self.n).max(1);
        (self.b.iter())
            .zip(self.a.chunks_exact(w))
            .map(|(&b, a)| GridValue { b, a })
    }

    /// Every value as an [`AffineValue`] (the RMS grid starts from them).
    pub(super) fn to_values(&self) -> Vec<AffineValue> {
        self.iter().map(GridValue::to_value).collect()
    }
}
