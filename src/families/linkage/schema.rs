//! The JSON Schema branch of the linkage problem file, written from its raw structs in `file`
//! with the shared builders of [`crate::problem::schema`].

use super::file::{MAX_COUNTERWEIGHTS, MAX_DYADS};
use crate::problem::schema::*;
use crate::units::Dim;
use serde_json::{json, Value};

/// A point in the plane: two lengths.
fn xy(desc: &str) -> Value {
    let mut v = array(qty(Dim::Length, "coordinate"), desc);
    v["minItems"] = json!(2);
    v["maxItems"] = json!(2);
    v
}

/// A point reference: a frame point, `"NAME.pivot"`/`"NAME.tip"`, or `{ link, at }`.
fn point(desc: &str) -> Value {
    json!({
        "description": format!("{desc}: a frame point [\"x mm\", \"y mm\"], \"NAME.pivot\", \"NAME.tip\" or {{ link = \"NAME\", at = [\"x mm\", \"y mm\"] }}"),
        "anyOf": [
            xy("a frame point"),
            { "type": "string", "pattern": "^[A-Za-z0-9_-]+\\.(pivot|tip)$", "maxLength": 80 },
            obj(&[("link", string("link name")), ("at", xy("in the link's frame"))], &["link", "at"], "a point fixed to a link")
        ]
    })
}

/// The branch of this family's problem file (its raw structs in `file`).
pub fn schema() -> Value {
    use Dim::*;
    let dyad = obj(
        &[
            ("kind", one_of(&["RRR", "RRP", "RPR"], "the dyad's joints")),
            (
                "links",
                limited(
                    limited(
                        array(string("link name"), "the two new links"),
                        "minItems",
                        2,
                    ),
                    "maxItems",
                    2,
                ),
            ),
            ("p", point("P")),
            ("q", point("Q (RRR, RPR)")),
            ("length1", qty(Length, "RRR: |PB|")),
            ("length2", qty(Length, "RRR: |QB|")),
            ("length", qty(Length, "RRP: the rod's |PB|")),
            ("line_point", xy("RRP: a point of the slider's line")),
            ("line_angle", qty(Angle, "RRP: the line's direction")),
            ("offset", qty(Length, "RPR: the slide line's offset from P")),
            ("branch", one_of(&["left", "right"], "the assembly branch")),
        ],
        &["kind", "links", "p", "branch"],
        "an Assur dyad",
    );
    let link = obj(
        &[
            ("mass", qty(Mass, "m")),
            ("centroid", xy("the centre of mass in the link's frame")),
            ("inertia", qty(Inertia, "J about the centre of mass")),
            (
                "uniform_bar",
                boolean("a uniform bar along the link (centroid and J from its length)"),
            ),
        ],
        &["mass"],
        "a link's mass data",
    );
    let mechanism = obj(
        &[
            ("speed", qty(AngularSpeed, "ω, constant")),
            ("crank_length", qty(Length, "|A0 A|")),
            ("crank_pivot", xy("A0")),
            (
                "gravity",
                qty(Acceleration, "g, acting in −y (input torque only)"),
            ),
            (
                "dyads",
                limited(array(dyad, "the dyads, in order"), "maxItems", MAX_DYADS),
            ),
            (
                "links",
                json!({
                    "type": "object",
                    "description": "mass data of every link, by name (crank and the dyads' links)",
                    "additionalProperties": link
                }),
            ),
        ],
        &["speed", "crank_length"],
        "the linkage",
    );
    let model = obj(
        &[("moment_about", xy("O, the shaking moment's frame point"))],
        &[],
        "model",
    );
    let counterweight = obj(
        &[
            ("link", string("the link it is fixed to")),
            ("mass", var(Mass, "m")),
            (
                "radius",
                qty(Length, "envelope radius about the link's joint"),
            ),
            ("sector", var(Angle, "directions of its centroid (≤ 180°)")),
        ],
        &["link", "mass", "radius"],
        "a counterweight to size",
    );
    let design = obj(
        &[(
            "counterweights",
            limited(
                array(counterweight, "the counterweights (one per link)"),
                "maxItems",
                MAX_COUNTERWEIGHTS,
            ),
        )],
        &[],
        "design variables",
    );
    let objective = obj(
        &[
            (
                "minimize",
                one_of(
                    &[
                        "peak-force",
                        "peak-moment",
                        "peak-torque",
                        "rms-force",
                        "rms-moment",
                        "rms-torque",
                        "counterweight-mass",
                    ],
                    "what the counterweights minimise",
                ),
            ),
            (
                "max_peak_force",
                qty(Force, "limit on the peak shaking force"),
            ),
            (
                "max_peak_moment",
                qty(Torque, "limit on the peak shaking moment"),
            ),
            (
                "max_peak_torque",
                qty(Torque, "limit on the peak input torque"),
            ),
            (
                "full_force_balance",
                boolean("the total centre of mass stationary (F ≡ 0)"),
            ),
            (
                "pareto_points",
                uint("points of the force–moment front (0 or 2–200)"),
            ),
        ],
        &["minimize"],
        "objective and constraints",
    );
    let accuracy = obj(
        &[
            ("rel_tol", num("relative gap of the certificate")),
            (
                "abs_floor",
                num("below this fraction of the unbalanced peak the tolerance is absolute"),
            ),
            ("initial_samples", uint("angles of the first SOCP")),
            ("scan_samples", uint("angles of the peak scan")),
            ("max_rounds", uint("exchange rounds at most")),
            (
                "peak_xtol",
                qty(Angle, "angle tolerance of the peak refinement"),
            ),
            ("rms_samples", uint("uniform angles of RMS values (even)")),
            (
                "exact_disc",
                boolean("solve a turning counterweight's peak force as a smallest enclosing disc"),
            ),
        ],
        &[],
        "solver and sampling settings",
    );
    family("linkage", mechanism, model, design, objective, accuracy)
}
