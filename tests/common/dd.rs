//! Double-double numbers for the independent references, with a division that keeps its
//! digits. `twofloat` 0.8.4 (the newest) divides by a `TwoFloat` with Joldes et al.'s
//! Algorithm 18 but computes its residual `1 − b_hi·(1/b_hi)` without a fused multiply-add,
//! so `T / T` and `f64 / T` are only ~1e-17 relative (3·(1/3) − 1 = −5.6e-17): a reference
//! built on them drifts wherever a division is amplified (the crane's circle through E1 E2 E3
//! as k1 → 1 moved by 3.8e-16/(1 − k1) m). Every other operation is twofloat's (products by
//! FMA, sums by two-sum, `T / f64` by Algorithm 15, sqrt: all ~1e-32, checked below).
//! `Dd` wraps it so that a reference cannot reach the faulty division by accident.

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use twofloat::TwoFloat;

/// A double-double number (≈ 32 significant digits).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd(pub TwoFloat);

impl Dd {
    /// π/2, 2π as double-double constants.
    pub const FRAC_PI_2: Dd = Dd(twofloat::consts::FRAC_PI_2);
    pub const PI: Dd = Dd(twofloat::consts::PI);
    pub const TAU: Dd = Dd(twofloat::consts::TAU);

    /// The exact sum a + b of two f64.
    pub fn new_add(a: f64, b: f64) -> Dd {
        Dd(TwoFloat::new_add(a, b))
    }
    pub fn hi(self) -> f64 {
        self.0.hi()
    }
    pub fn lo(self) -> f64 {
        self.0.lo()
    }
    pub fn sqrt(self) -> Dd {
        Dd(self.0.sqrt())
    }
    pub fn abs(self) -> Dd {
        Dd(self.0.abs())
    }
    /// atan2 to ~f64 accuracy only (twofloat's); callers refine it by Newton on sin/cos.
    pub fn atan2(self, x: Dd) -> Dd {
        Dd(self.0.atan2(x.0))
    }
    /// a / b to ~1e-32 relative: three quotient digits, each from the exact residual
    /// r = a − b·q (Bailey's QD "accurate" division).
    fn quotient(a: TwoFloat, b: TwoFloat) -> TwoFloat {
        let q1 = a.hi() / b.hi();
        let r = a - b * q1;
        let q2 = r.hi() / b.hi();
        let r = r - b * q2;
        let q3 = r.hi() / b.hi();
        TwoFloat::new_add(q1, q2) + q3
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Dd {
        Dd(TwoFloat::from(x))
    }
}
impl From<Dd> for f64 {
    fn from(x: Dd) -> f64 {
        f64::from(x.0)
    }
}
impl PartialOrd for Dd {
    fn partial_cmp(&self, o: &Dd) -> Option<Ordering> {
        self.0.partial_cmp(&o.0)
    }
}
impl PartialEq<f64> for Dd {
    fn eq(&self, o: &f64) -> bool {
        self.0 == *o
    }
}
impl PartialOrd<f64> for Dd {
    fn partial_cmp(&self, o: &f64) -> Option<Ordering> {
        self.0.partial_cmp(o)
    }
}
impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd(-self.0)
    }
}

macro_rules! ops {
    ($($tr:ident $f:ident $atr:ident $af:ident;)*) => {$(
        impl $tr<Dd> for Dd {
            type Output = Dd;
            fn $f(self, o: Dd) -> Dd {
                Dd($tr::$f(self.0, o.0))
            }
        }
        impl $tr<f64> for Dd {
            type Output = Dd;
            fn $f(self, o: f64) -> Dd {
                Dd($tr::$f(self.0, o))
            }
        }
        impl $tr<Dd> for f64 {
            type Output = Dd;
            fn $f(self, o: Dd) -> Dd {
                Dd($tr::$f(self, o.0))
            }
        }
        impl $atr<Dd> for Dd {
            fn $af(&mut self, o: Dd) {
                *self = $tr::$f(*self, o);
            }
        }
        impl $atr<f64> for Dd {
            fn $af(&mut self, o: f64) {
                *self = $tr::$f(*self, o);
            }
        }
    )*};
}
ops! {
    Add add AddAssign add_assign;
    Sub sub SubAssign sub_assign;
    Mul mul MulAssign mul_assign;
}

impl Div<Dd> for Dd {
    type Output = Dd;
    fn div(self, o: Dd) -> Dd {
        Dd(Dd::quotient(self.0, o.0))
    }
}
impl Div<f64> for Dd {
    type Output = Dd;
    /// twofloat's `T / f64` (Algorithm 15) is exact to ~1e-32.
    fn div(self, o: f64) -> Dd {
        Dd(self.0 / o)
    }
}
impl Div<Dd> for f64 {
    type Output = Dd;
    fn div(self, o: Dd) -> Dd {
        Dd(Dd::quotient(TwoFloat::from(self), o.0))
    }
}
impl DivAssign<Dd> for Dd {
    fn div_assign(&mut self, o: Dd) {
        *self = *self / o;
    }
}
impl DivAssign<f64> for Dd {
    fn div_assign(&mut self, o: f64) {
        *self = *self / o;
    }
}

/// sin and cos of a double-double x (|x| ≲ 100): reduction by the double-double π/2 and
/// Taylor series to y²⁰ on |y| ≤ π/4 (term < 1e-33).
pub fn dd_sin_cos(x: Dd) -> (Dd, Dd) {
    let k = (x.hi() / std::f64::consts::FRAC_PI_2).round();
    let y = x - Dd::FRAC_PI_2 * k;
    let y2 = y * y;
    let (mut s, mut c) = (y, Dd::from(1.0));
    let (mut ts, mut tc) = (y, Dd::from(1.0));
    for n in 1..=14 {
        let nf = n as f64;
        ts = -ts * y2 / ((2.0 * nf) * (2.0 * nf + 1.0));
        tc = -tc * y2 / ((2.0 * nf - 1.0) * (2.0 * nf));
        s += ts;
        c += tc;
    }
    match (k as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}
