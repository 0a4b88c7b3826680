//! The JSON Schema branch of the slider_crank problem file, written from its raw structs in `file`
//! with the shared builders of [`crate::problem::schema`].

use super::file::{MAX_MASS_ITEMS, MAX_TABLE_POINTS};
use crate::problem::schema::*;
use crate::units::Dim;
use serde_json::Value;

/// The branch of this family's problem file (its raw structs in `file`).
pub fn schema() -> Value {
    use Dim::*;
    let mechanism = obj(
        &[
            ("crank_radius", qty(Length, "R")),
            ("rod_length", qty(Length, "L")),
            ("offset", qty(Length, "e, slider offset (default 0)")),
            ("speed", qty(AngularSpeed, "n or ω")),
            ("crank_mass", qty(Mass, "m2 (or from mass_items)")),
            ("crank_centroid", qty(Length, "r2 (default R/2)")),
            ("rod_mass", qty(Mass, "m3")),
            ("slider_mass", qty(Mass, "m4 (or from mass_items)")),
            (
                "mass_items",
                limited(
                    array(
                        obj(
                            &[
                                ("name", string("label")),
                                ("mass", qty(Mass, "mass")),
                                ("at", one_of(&["slider", "crank-pin"], "reduced to")),
                                ("fraction", num("fraction reduced there (default 1)")),
                            ],
                            &["name", "mass", "at"],
                            "an itemised mass",
                        ),
                        "itemised masses (replace crank_mass and slider_mass)",
                    ),
                    "maxItems",
                    MAX_MASS_ITEMS,
                ),
            ),
            (
                "slider_axis_angle",
                qty(Angle, "slider axis above the horizontal"),
            ),
            (
                "process_force",
                qty(Force, "constant process force on the slider"),
            ),
            (
                "process_force_table",
                obj(
                    &[
                        (
                            "angle",
                            limited(
                                array(qty(Angle, "crank angle"), "crank angles"),
                                "maxItems",
                                MAX_TABLE_POINTS,
                            ),
                        ),
                        (
                            "force",
                            limited(
                                array(qty(Force, "force"), "forces"),
                                "maxItems",
                                MAX_TABLE_POINTS,
                            ),
                        ),
                    ],
                    &["angle", "force"],
                    "process force against crank angle",
                ),
            ),
        ],
        &["crank_radius", "rod_length", "speed", "rod_mass"],
        "the slider-crank",
    );
    let model = obj(
        &[
            (
                "kinematics",
                one_of(&["exact", "two-harmonic"], "slider kinematics"),
            ),
            ("masses", one_of(&["lumped", "rigid"], "rod model")),
            (
                "rod_split",
                num("lumped: rod mass fraction at the crank pin"),
            ),
            (
                "rod_centroid",
                qty(Length, "rigid: rod centre of mass from the crank pin"),
            ),
            ("rod_inertia", qty(Inertia, "rigid: rod moment of inertia")),
            ("gravity", boolean("model the weights")),
            ("gravity_acceleration", qty(Acceleration, "g")),
        ],
        &[],
        "model fidelity",
    );
    let design = obj(
        &[
            ("unbalance", var(Unbalance, "|U| = m r")),
            ("angle", var(Angle, "β from the crank line")),
            ("mass", var(Mass, "counterweight mass")),
            ("radius", var(Length, "counterweight centroid radius")),
            (
                "prefer",
                one_of(&["smallest-radius", "lightest"], "split preference"),
            ),
            (
                "paper",
                obj(
                    &[
                        ("rotating_mass", qty(Mass, "printed m_r")),
                        ("reciprocating_mass", qty(Mass, "printed m_s")),
                        ("counterweight_mass", qty(Mass, "printed m_pr")),
                    ],
                    &[],
                    "the paper's classical counterweight as printed",
                ),
            ),
            (
                "shape",
                obj(
                    &[
                        ("density", qty(Density, "material density")),
                        ("thickness", qty(Length, "plate thickness")),
                        ("inner_radius_min", qty(Length, "smallest inner radius")),
                        ("outer_radius_max", qty(Length, "largest outer radius")),
                        ("max_angle", qty(Angle, "largest sector angle")),
                        ("minimize", one_of(&["mass", "outer-radius"], "plate goal")),
                    ],
                    &[
                        "density",
                        "thickness",
                        "inner_radius_min",
                        "outer_radius_max",
                    ],
                    "an annular-sector plate realising the counterweight",
                ),
            ),
        ],
        &[],
        "the counterweight",
    );
    let objective = obj(
        &[
            (
                "minimize",
                one_of(
                    &["peak-force", "rms-force", "mass", "radius", "peak-torque"],
                    "what to minimise",
                ),
            ),
            ("max_peak_force", qty(Force, "peak shaking-force limit")),
            ("max_peak_torque", qty(Torque, "peak drive-torque limit")),
            (
                "pareto_points",
                uint("points of the torque–force Pareto front"),
            ),
            (
                "speed_sweep",
                obj(
                    &[
                        ("min", qty(AngularSpeed, "lowest speed")),
                        ("max", qty(AngularSpeed, "highest speed")),
                        ("points", uint("number of speeds (2–200)")),
                    ],
                    &["min", "max", "points"],
                    "the scene re-optimised at evenly spaced speeds",
                ),
            ),
        ],
        &["minimize"],
        "objective and constraints",
    );
    let accuracy = obj(
        &[
            ("rel_tol", num("relative optimality gap")),
            ("initial_samples", uint("first SOCP's angles")),
            ("scan_samples", uint("scan density of the peak search")),
            ("max_rounds", uint("exchange rounds at most")),
            (
                "peak_xtol",
                qty(Dim::Angle, "angle tolerance of the peak refinement"),
            ),
            ("rms_samples", uint("RMS quadrature points")),
            ("keep_band", num("near-active band kept between rounds")),
            (
                "warm_start",
                boolean("start the first SOCP at the maxima of the least-squares counterweight"),
            ),
            (
                "presolve",
                boolean("choose the first SOCP's angles by the smallest enclosing disc"),
            ),
            (
                "exact_disc",
                boolean("solve the sampled minimax exactly as a smallest enclosing disc where it is one (else clarabel)"),
            ),
        ],
        &[],
        "accuracy targets",
    );
    family(
        "slider-crank",
        mechanism,
        model,
        design,
        objective,
        accuracy,
    )
}
