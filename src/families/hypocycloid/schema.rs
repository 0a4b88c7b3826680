//! The JSON Schema branch of the hypocycloid problem file, written from its raw structs in `file`
//! with the shared builders of [`crate::problem::schema`].

use crate::problem::schema::*;
use crate::units::Dim;
use serde_json::{json, Value};

/// The branch of this family's problem file (its raw structs in `file`).
pub fn schema() -> Value {
    use Dim::*;
    let range = |d: &str| {
        obj(
            &[
                ("min", qty(Dimensionless, "lower end")),
                ("max", qty(Dimensionless, "upper end")),
            ],
            &["min", "max"],
            d,
        )
    };
    let mechanism = obj(
        &[
            (
                "variant",
                json!({ "type": "integer", "description": "the paper's variant: 1 or 2" }),
            ),
            ("orientation", qty(Angle, "α0 instead of variant")),
            ("carrier_radius", qty(Length, "R = OO1")),
            ("reciprocating_mass", qty(Mass, "m_B")),
            ("speed", qty(AngularSpeed, "carrier n or ω")),
        ],
        &["carrier_radius", "reciprocating_mass", "speed"],
        "the hypocycloid machine",
    );
    let model = obj(
        &[
            ("orders", uint("highest order in the tables")),
            ("series_power", uint("power of z = λ²y² of the series")),
            (
                "coefficients",
                one_of(
                    &["exact", "series"],
                    "coefficients for balancing and objectives (default exact)",
                ),
            ),
        ],
        &[],
        "model",
    );
    let design = obj(
        &[
            ("lambda", var(Dimensionless, "λ = R/L")),
            ("theta", var(Dimensionless, "θ = r/R")),
        ],
        &[],
        "design variables",
    );
    let objective = obj(
        &[
            (
                "minimize",
                one_of(&["peak-residual-force"], "what to minimise"),
            ),
            (
                "balance_orders",
                array(uint("order"), "orders cancelled by Lanchester pairs"),
            ),
            ("assembly_margin", num("required 1 − λ·max|y_A/R|")),
            ("min_stroke", qty(Length, "minimum stroke")),
            ("min_suction_gain", num("minimum suction-phase gain")),
            (
                "zero_search",
                obj(
                    &[
                        ("order", uint("order of the searched coefficient")),
                        ("lambda", range("λ range")),
                        ("theta", range("θ range")),
                    ],
                    &["lambda", "theta"],
                    "the zero search",
                ),
            ),
        ],
        &["minimize"],
        "objective and constraints",
    );
    let accuracy = obj(
        &[
            ("n_fft_min", uint("smallest FFT size")),
            ("n_fft_max", uint("largest FFT size")),
            ("root_tol", num("root tolerance in θ = r/R (dimensionless)")),
            ("curve_points", uint("λ columns of the zero search")),
            ("theta_scan", uint("θ samples per column")),
            ("peak_samples", uint("φ samples of the peak scans")),
            (
                "peak_xtol",
                qty(Dim::Angle, "φ tolerance of the peak refinement"),
            ),
            (
                "refine_peaks",
                boolean("refine the sampled peaks by Brent (default true)"),
            ),
            (
                "fft_adaptive",
                boolean(
                    "double the FFT size until converged (default true; false: n_fft_min only)",
                ),
            ),
            ("opt_grid", uint("start grid per free variable")),
            (
                "opt_starts",
                uint("Nelder–Mead runs from the best distant grid points"),
            ),
            ("nm_max_iters", uint("Nelder–Mead iteration limit")),
            ("nm_sd_tol", num("Nelder–Mead simplex tolerance")),
            ("plot_samples", uint("samples per turn of the force curves")),
        ],
        &[],
        "numerical settings",
    );
    family("hypocycloid", mechanism, model, design, objective, accuracy)
}
