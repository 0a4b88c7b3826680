//! The JSON Schema branch of the gear problem file, written from its raw structs in `file`
//! with the shared builders of [`crate::problem::schema`].

use crate::problem::schema::*;
use crate::units::Dim;
use serde_json::Value;

/// The branch of this family's problem file (its raw structs in `file`).
pub fn schema() -> Value {
    use Dim::*;
    let mechanism = obj(
        &[
            ("pitch_radius", qty(Length, "R")),
            ("generating_radius", qty(Length, "r")),
            ("turns_gear1", uint("n1")),
            ("turns_gear2", uint("n2")),
            ("speed", qty(AngularSpeed, "ω1")),
            ("module", qty(Length, "stated module")),
            ("teeth_gear1", uint("stated z1")),
            ("teeth_gear2", uint("stated z2")),
            ("tooth_pitch", qty(Length, "stated pitch")),
            ("tooth_thickness", qty(Length, "stated tooth thickness")),
            ("space_width", qty(Length, "stated space width")),
            ("center_distance", qty(Length, "stated centre distance")),
        ],
        &[
            "pitch_radius",
            "generating_radius",
            "turns_gear1",
            "turns_gear2",
            "speed",
        ],
        "the gear pair",
    );
    let model = obj(
        &[(
            "pole_window",
            qty(Angle, "half-width left out around every pole"),
        )],
        &[],
        "model",
    );
    let design = obj(
        &[("eccentricity", var(Length, "e"))],
        &[],
        "design variables",
    );
    let objective = obj(
        &[
            ("maximize", one_of(&["ratio-variation"], "what to maximise")),
            ("max_sliding_coefficient", num("limit of the peak |µ|")),
            ("require_gear2_convex", boolean("gear 2 must stay convex")),
            (
                "max_pressure_angle",
                qty(Angle, "pitch pressure-angle limit"),
            ),
        ],
        &["maximize"],
        "objective and constraints",
    );
    let accuracy = obj(
        &[
            ("samples_per_arch", uint("pole-function samples per arch")),
            ("pole_tol", qty(Dim::Angle, "pole tolerance")),
            ("peak_xtol", qty(Dim::Angle, "maxima refinement tolerance")),
            (
                "peak_samples_per_arch",
                uint("samples per arch for peak |µ|"),
            ),
            (
                "refine_poles",
                boolean("refine each pole by Brent (default true; false: one false-position step)"),
            ),
            (
                "refine_peaks",
                boolean("refine each sampled maximum of |µ| (default true)"),
            ),
            ("curvature_samples", uint("curvature samples per turn")),
            ("series_points", uint("points of the α1 series")),
            ("curve_points", uint("points per pitch curve")),
            ("sweep_points", uint("points of the design sweep")),
            (
                "design_rtol",
                num("tolerance of the designed e (relative to R)"),
            ),
        ],
        &[],
        "solver and sampling settings",
    );
    family(
        "eccentric-gear",
        mechanism,
        model,
        design,
        objective,
        accuracy,
    )
}
