//! The paper's closed-form coefficients C_i(λ, θ) (paper 004, eqs. (6) and (19)–(21)), lost
//! in the extraction of the seed and re-derived here symbolically, so that the program can
//! print them beside the exact (FFT) coefficients and show where the truncation misleads.
//!
//! The paper expands the root of S/R binomially to the sixth power of y,
//!
//!   S/R ≈ x + 1/λ − (λ/2) y² − (λ³/8) y⁴ − (λ⁵/16) y⁶,
//!
//! writes every power of sin/cos as harmonics and collects them up to the sixth order
//! (harmonics 7–12 of y⁴ and y⁶ are dropped). With y and x of
//! [`crate::families::hypocycloid::model`] (variant 1: y = sin φ − θ sin 2φ,
//! x = cos φ + θ cos 2φ; variant 2: y = sin φ − θ cos 2φ, x = cos φ − θ sin 2φ) the
//! coefficients below are exact polynomials in λ and θ (derived with sympy from the
//! expansion above; the test suite checks them against the numerical convolution of
//! `Hypocycloid::series_coefficients` at power 3, against the FFT coefficients as λ → 0
//! — the difference is O(λ⁷) — and against the slider-crank's textbook series at θ = 0).
//!
//! The constant 1/λ of C0 is left out of every formula here (it is the rod length over R).

/// The paper's closed-form coefficients of one design: S/R ≈ 1/λ + C0 + Σ_{i=1..6}
/// (a_i cos iφ + b_i sin iφ). In variant 1 the b_i are 0 (the paper's C_i = a_i); in
/// variant 2 a_i = C^I_i (orders 0, 1, 2, 4, 6; a_3 = a_5 = 0) and b_i = C^II_i (the paper's
/// S^II written with cos(iφ − π/2) = sin iφ; b_4 = b_6 = 0).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PaperCoefficients {
    /// 1 or 2.
    pub variant: u8,
    /// a_0 … a_6 (a_0 without 1/λ).
    pub a: [f64; 7],
    /// b_0 (= 0) … b_6.
    pub b: [f64; 7],
}

/// Variant 1 (α0 = 0), the paper's eq. (6): S/R ≈ 1/λ + C0 + Σ C_i cos iφ with
///
/// - C0 = −λ(1 + θ²)/4 − 3λ³(1 + 4θ² + θ⁴)/64 − λ⁵(10 + 75θ² + 90θ⁴ + 10θ⁶)/512
/// - C1 = 1 + λθ/2 + λ³(θ/8 + 3θ³/16) + λ⁵(15θ/256 + 15θ³/64 + 15θ⁵/128)
/// - C2 = θ + λ/4 + λ³(1/16 + 3θ²/32) + λ⁵(15/512 + 15θ²/128 + 15θ⁴/256)
/// - C3 = −λθ/2 − λ³(3θ/16 + 3θ³/16) − λ⁵(27θ/256 + 5θ³/16 + 15θ⁵/128)
/// - C4 = λθ²/4 + λ³(−1/64 + 3θ²/16 + θ⁴/16) + λ⁵(−3/256 + 15θ²/128 + 15θ⁴/64 + 15θ⁶/512)
/// - C5 = λ³(θ − θ³)/16 + 15λ⁵(θ − θ⁵)/256
/// - C6 = −3λ³θ²/32 + λ⁵(1/512 − 15θ²/128 − 45θ⁴/512)
///
/// At θ = 0: C2 = λ/4 + λ³/16 + 15λ⁵/512, C4 = −(λ³/64 + 3λ⁵/256), C6 = λ⁵/512 — the
/// slider-crank's textbook A2 = 4C2, A4 = −16C4, A6 = 36C6.
pub fn variant1(lambda: f64, theta: f64) -> PaperCoefficients {
    let (l, t) = (lambda, theta);
    let (l3, l5) = (l.powi(3), l.powi(5));
    let (t2, t3, t4, t5, t6) = (t * t, t.powi(3), t.powi(4), t.powi(5), t.powi(6));
    let a = [
        -l * (1.0 + t2) / 4.0
            - 3.0 * l3 * (1.0 + 4.0 * t2 + t4) / 64.0
            - l5 * (10.0 + 75.0 * t2 + 90.0 * t4 + 10.0 * t6) / 512.0,
        1.0 + l * t / 2.0
            + l3 * (t / 8.0 + 3.0 * t3 / 16.0)
            + l5 * (15.0 * t / 256.0 + 15.0 * t3 / 64.0 + 15.0 * t5 / 128.0),
        t + l / 4.0
            + l3 * (1.0 / 16.0 + 3.0 * t2 / 32.0)
            + l5 * (15.0 / 512.0 + 15.0 * t2 / 128.0 + 15.0 * t4 / 256.0),
        -l * t / 2.0
            - l3 * (3.0 * t / 16.0 + 3.0 * t3 / 16.0)
            - l5 * (27.0 * t / 256.0 + 5.0 * t3 / 16.0 + 15.0 * t5 / 128.0),
        l * t2 / 4.0
            + l3 * (-1.0 / 64.0 + 3.0 * t2 / 16.0 + t4 / 16.0)
            + l5 * (-3.0 / 256.0 + 15.0 * t2 / 128.0 + 15.0 * t4 / 64.0 + 15.0 * t6 / 512.0),
        l3 * (t - t3) / 16.0 + 15.0 * l5 * (t - t5) / 256.0,
        -3.0 * l3 * t2 / 32.0 + l5 * (1.0 / 512.0 - 15.0 * t2 / 128.0 - 45.0 * t4 / 512.0),
    ];
    PaperCoefficients {
        variant: 1,
        a,
        b: [0.0; 7],
    }
}

/// Variant 2 (α0 = 270°), the paper's eqs. (18)–(21): S = S^I + S^II,
/// S^I/R ≈ 1/λ + C0^I + Σ_{i=1,2,4,6} C^I_i cos iφ and S^II/R ≈ Σ_{i=1..6} C^II_i sin iφ with
///
/// - C0^I = −λ(1 + θ²)/4 − 3λ³(1 + 4θ² + θ⁴)/64 − λ⁵(10 + 105θ² + 90θ⁴ + 10θ⁶)/512
/// - C1^I = 1
/// - C2^I = λ/4 + λ³(1/16 + 9θ²/32) + λ⁵(15/512 + 45θ²/128 + 75θ⁴/256)
/// - C4^I = −λθ²/4 − λ³(1/64 + 3θ²/16 + θ⁴/16) − λ⁵(3/256 + 15θ²/64 + 15θ⁴/64 + 15θ⁶/512)
/// - C6^I = 3λ³θ²/32 + λ⁵(1/512 + 15θ²/128 + 75θ⁴/512)
/// - C1^II = −λθ/2 − λ³(θ/4 + 3θ³/16) − λ⁵(45θ/256 + 15θ³/32 + 15θ⁵/128)
/// - C2^II = −θ
/// - C3^II = λθ/2 + λ³(3θ/16 + 3θ³/16) + λ⁵(33θ/256 + 25θ³/64 + 15θ⁵/128)
/// - C5^II = −λ³(θ + θ³)/16 − λ⁵(15θ/256 + 15θ³/64 + 15θ⁵/256)
/// - C3^I = C5^I = C4^II = C6^II = 0.
///
/// Every term of C4^I has the same sign (all negative for λ, θ > 0): the truncated series
/// of variant 2 cannot vanish, whatever (λ, θ) — the paper's conjecture can only be settled
/// by the exact coefficient.
pub fn variant2(lambda: f64, theta: f64) -> PaperCoefficients {
    let (l, t) = (lambda, theta);
    let (l3, l5) = (l.powi(3), l.powi(5));
    let (t2, t3, t4, t5, t6) = (t * t, t.powi(3), t.powi(4), t.powi(5), t.powi(6));
    let a = [
        -l * (1.0 + t2) / 4.0
            - 3.0 * l3 * (1.0 + 4.0 * t2 + t4) / 64.0
            - l5 * (10.0 + 105.0 * t2 + 90.0 * t4 + 10.0 * t6) / 512.0,
        1.0,
        l / 4.0
            + l3 * (1.0 / 16.0 + 9.0 * t2 / 32.0)
            + l5 * (15.0 / 512.0 + 45.0 * t2 / 128.0 + 75.0 * t4 / 256.0),
        0.0,
        -l * t2 / 4.0
            - l3 * (1.0 / 64.0 + 3.0 * t2 / 16.0 + t4 / 16.0)
            - l5 * (3.0 / 256.0 + 15.0 * t2 / 64.0 + 15.0 * t4 / 64.0 + 15.0 * t6 / 512.0),
        0.0,
        3.0 * l3 * t2 / 32.0 + l5 * (1.0 / 512.0 + 15.0 * t2 / 128.0 + 75.0 * t4 / 512.0),
    ];
    let b = [
        0.0,
        -l * t / 2.0
            - l3 * (t / 4.0 + 3.0 * t3 / 16.0)
            - l5 * (45.0 * t / 256.0 + 15.0 * t3 / 32.0 + 15.0 * t5 / 128.0),
        -t,
        l * t / 2.0
            + l3 * (3.0 * t / 16.0 + 3.0 * t3 / 16.0)
            + l5 * (33.0 * t / 256.0 + 25.0 * t3 / 64.0 + 15.0 * t5 / 128.0),
        0.0,
        -l3 * (t + t3) / 16.0 - l5 * (15.0 * t / 256.0 + 15.0 * t3 / 64.0 + 15.0 * t5 / 256.0),
        0.0,
    ];
    PaperCoefficients { variant: 2, a, b }
}

/// The closed forms of the paper's variant `variant` (1 or 2); `None` for another
/// orientation (the paper gives none).
pub fn paper_coefficients(
    variant: Option<u8>,
    lambda: f64,
    theta: f64,
) -> Option<PaperCoefficients> {
    match variant {
        Some(1) => Some(variant1(lambda, theta)),
        Some(2) => Some(variant2(lambda, theta)),
        _ => None,
    }
}

/// How a closed-form coefficient compares with the exact one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Within 1 % of the exact value (or both below the exact value's error).
    Agrees,
    /// Off by more than 1 % but the same sign.
    Inaccurate,
    /// The opposite sign of the exact coefficient (beyond its error).
    WrongSign,
    /// The closed form is 0 (an order the series does not produce) where the exact value is
    /// not.
    Missing,
}

/// The verdict on one closed-form value `c` against the exact `e` with error `err`.
pub fn verdict(c: f64, e: f64, err: f64) -> Verdict {
    let tol = err.max(1e-15);
    if (c - e).abs() <= tol.max(0.01 * e.abs()) {
        Verdict::Agrees
    } else if c == 0.0 {
        Verdict::Missing
    } else if e.abs() > tol && c.signum() != e.signum() {
        Verdict::WrongSign
    } else {
        Verdict::Inaccurate
    }
}
