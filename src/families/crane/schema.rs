//! The JSON Schema branch of the crane problem file, written from its raw structs in `file`
//! with the shared builders of [`crate::problem::schema`].

use crate::problem::schema::*;
use crate::units::Dim;
use serde_json::{json, Value};

/// The branch of this family's problem file (its raw structs in `file`).
pub fn schema() -> Value {
    use Dim::*;
    let range = |d: &str| {
        json!({
            "type": "array", "items": qty(Length, d), "minItems": 2, "maxItems": 2,
            "description": format!("{d}: [min, max]")
        })
    };
    let mechanism = obj(
        &[
            ("reach_max", qty(Length, "R_max")),
            ("reach_min", qty(Length, "R_min")),
            (
                "foot_offset",
                qty(Length, "r, slewing axis to the boom foot"),
            ),
            ("lift_height", qty(Length, "H")),
            ("foot_height", qty(Length, "h")),
            ("load_mass", qty(Mass, "Q, rated load")),
        ],
        &[
            "reach_max",
            "reach_min",
            "foot_offset",
            "lift_height",
            "foot_height",
        ],
        "the crane's requirements",
    );
    let model = obj(
        &[(
            "sizing",
            one_of(&["min-reach", "max-reach"], "boom-length rule"),
        )],
        &[],
        "model",
    );
    let design = obj(
        &[
            ("k1", var(Dimensionless, "k1 = C1C2/C1C3")),
            ("k2", var(Dimensionless, "k2 = a/L_v")),
            ("phi_min", var(Angle, "φ_min")),
            ("gamma1", var(Angle, "γ1")),
            ("gamma2", var(Angle, "γ2")),
            ("gamma3", var(Angle, "γ3")),
            ("boom_length", qty(Length, "L_c")),
        ],
        &[],
        "design variables",
    );
    let objective = obj(
        &[
            ("minimize", one_of(&["delta-h"], "what to minimise")),
            ("max_delta_h", qty(Length, "allowed Δh")),
            (
                "tie_pin",
                obj(
                    &[
                        ("max_distance", qty(Length, "|AB| limit")),
                        ("x_range", range("x_B")),
                        ("y_range", range("y_B")),
                    ],
                    &[],
                    "where the tie pin may be",
                ),
            ),
        ],
        &["minimize"],
        "objective and constraints",
    );
    let accuracy = obj(
        &[
            ("path_samples", uint("luffing-range samples")),
            ("xtol", qty(Dim::Angle, "extremum refinement tolerance")),
            (
                "refine_peaks",
                boolean("refine the sampled extrema of the head height (default true)"),
            ),
            ("plot_points", uint("path points written")),
            ("global_samples", uint("Halton points per free variable")),
            ("local_starts", uint("SQP local searches")),
            ("local_max_iters", uint("SQP iterations per local search")),
            ("local_tol", num("SQP stop: relative predicted gain")),
            ("landscape_k1", uint("landscape grid along k1")),
            ("landscape_k2", uint("landscape grid along k2")),
            ("penalty", num("penalty weight")),
            ("constraint_tol", num("accepted constraint violation")),
            ("moment_step", qty(Dim::Angle, "finite-difference step")),
        ],
        &[],
        "solver and sampling settings",
    );
    family(
        "luffing-crane",
        mechanism,
        model,
        design,
        objective,
        accuracy,
    )
}
