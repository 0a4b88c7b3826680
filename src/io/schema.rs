//! A JSON Schema (draft 2020-12) of the problem file, for editors (`cwsynth schema`).
//!
//! Written by hand from the raw serde structs of each family (`io::<family>::*Raw`): one
//! branch per family under `oneOf`, selected by `family`, each closed with
//! `additionalProperties: false` like the structs' `deny_unknown_fields`. A dimensional
//! quantity is a `string` whose pattern is a number and one of the units of its dimension,
//! built from [`crate::units::UNITS`] (units are never guessed: no bare number); a pure
//! number (λ, k1) is a `number`. Every integer setting has the `minimum` and `maximum` of
//! [`super::limits`], and the input sizes have `maxLength`/`maxItems` (quantity strings,
//! `description`, `[[paper]]`, the slider-crank's arrays). The schema checks shape and spelling; other value ranges (λ < 1,
//! min ≤ max, …) stay with the resolvers, whose errors name the field.
//!
//! Keep it in step with the structs: `tests/schema.rs` validates every shipped problem file
//! against it and shows that unknown keys fail.

use super::limits::counts;
use super::problem::{Family, MAX_PAPER_ENTRIES, MAX_TEXT_CHARS};
use super::slider_crank::MAX_TABLE_POINTS;
use crate::units::{Dim, UNITS};
use serde_json::{json, Map, Value};

/// A number, then optional spaces and a unit of `dim` (`None`: any known unit, or none).
fn quantity_pattern(dim: Option<Dim>) -> String {
    let mut alts: Vec<String> = UNITS
        .iter()
        .filter(|u| dim.is_none_or(|d| u.dim == d))
        .map(|u| {
            let mut s = String::new();
            for c in u.symbol.chars() {
                match c {
                    // The reader treats `·`, `*`, `.`, `⋅`, `-` and spaces alike.
                    '·' | '*' => s.push_str("\\s*[·*.⋅-]?\\s*"),
                    '^' | '/' | '.' | '+' | '(' | ')' | '[' | ']' | '?' | '|' | '$' | '\\' => {
                        s.push('\\');
                        s.push(c);
                    }
                    c => s.push(c),
                }
            }
            s
        })
        .collect();
    // Longest first, so that `mm` is not read as `m` + rest.
    alts.sort_by_key(|a| std::cmp::Reverse(a.len()));
    let num = r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?";
    let optional = if dim.is_none() { "?" } else { "" };
    if alts.is_empty() {
        format!(r"^\s*{num}\s*$")
    } else {
        format!(r"^\s*{num}\s*({}){optional}\s*$", alts.join("|"))
    }
}

fn qty(dim: Dim, desc: &str) -> Value {
    let description = format!("{desc} — {}", dim.allowed());
    match dim {
        Dim::Dimensionless => json!({ "type": "number", "description": description }),
        _ => json!({
            "description": description,
            "type": "string",
            "maxLength": crate::units::MAX_QUANTITY_LEN,
            "pattern": quantity_pattern(Some(dim))
        }),
    }
}

fn var(dim: Dim, desc: &str) -> Value {
    json!({
        "description": format!("{desc}: fixed, or free within {{ min, max }}"),
        "anyOf": [
            qty(dim, desc),
            obj(&[("min", qty(dim, "lower bound")), ("max", qty(dim, "upper bound"))], &["min", "max"], "a free range")
        ]
    })
}

fn num(desc: &str) -> Value {
    json!({ "type": "number", "description": desc })
}

fn uint(desc: &str) -> Value {
    json!({ "type": "integer", "minimum": 0, "description": desc })
}

fn boolean(desc: &str) -> Value {
    json!({ "type": "boolean", "description": desc })
}

fn string(desc: &str) -> Value {
    json!({ "type": "string", "description": desc })
}

fn one_of(values: &[&str], desc: &str) -> Value {
    json!({ "type": "string", "enum": values, "description": desc })
}

fn array(items: Value, desc: &str) -> Value {
    json!({ "type": "array", "items": items, "description": desc })
}

fn obj(props: &[(&str, Value)], required: &[&str], desc: &str) -> Value {
    let mut p = Map::new();
    for (k, v) in props {
        p.insert((*k).to_string(), v.clone());
    }
    json!({
        "type": "object",
        "description": desc,
        "properties": p,
        "required": required,
        "additionalProperties": false
    })
}

/// `v` with the JSON Schema keyword `key` set to `n` (an input-size limit).
fn limited(mut v: Value, key: &str, n: usize) -> Value {
    v[key] = json!(n);
    v
}

fn paper() -> Value {
    let text = |d| limited(string(d), "maxLength", MAX_TEXT_CHARS);
    let entries = array(
        obj(
            &[
                ("quantity", text("what the paper's number is")),
                (
                    "value",
                    json!({
                        "description": "the paper's value: a quantity string whose unit is of the dimension of the key's SI unit suffix (`_n`: \"900 N\"), or a plain number for a key without one (`_pct`, a ratio)",
                        "anyOf": [
                            { "type": "number" },
                            { "type": "string", "pattern": quantity_pattern(None) }
                        ]
                    }),
                ),
                ("key", text("dotted result key compared with")),
                ("note", text("how to read the comparison")),
            ],
            &["quantity", "value", "key"],
            "a value printed in the source paper",
        ),
        "printed values of the source paper to compare with",
    );
    limited(entries, "maxItems", MAX_PAPER_ENTRIES)
}

/// One family's branch: the common keys plus its sections.
fn family(
    name: &str,
    mechanism: Value,
    model: Value,
    design: Value,
    objective: Value,
    accuracy: Value,
) -> Value {
    obj(
        &[
            (
                "name",
                json!({
                    "type": "string",
                    "pattern": "^[A-Za-z0-9_-][A-Za-z0-9._-]{0,127}$",
                    "description": "scene name (also the result file's stem)"
                }),
            ),
            ("family", json!({ "type": "string", "enum": [name] })),
            (
                "description",
                limited(string("free text"), "maxLength", MAX_TEXT_CHARS),
            ),
            ("mechanism", mechanism),
            ("model", model),
            ("design", design),
            ("objective", objective),
            ("accuracy", accuracy),
            ("paper", paper()),
        ],
        &["name", "family", "mechanism", "objective"],
        &format!("a {name} scene"),
    )
}

fn slider_crank() -> Value {
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
                    super::slider_crank::MAX_MASS_ITEMS,
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
                num("angle tolerance of the peak refinement (rad)"),
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

fn luffing_crane() -> Value {
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
            ("xtol", num("extremum refinement tolerance (rad)")),
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
            ("moment_step", num("finite-difference step (rad)")),
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

fn eccentric_gear() -> Value {
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
            ("pole_tol", num("pole tolerance (rad)")),
            ("peak_xtol", num("maxima refinement tolerance (rad)")),
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

fn hypocycloid() -> Value {
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
            ("root_tol", num("root tolerance in θ")),
            ("curve_points", uint("λ columns of the zero search")),
            ("theta_scan", uint("θ samples per column")),
            ("peak_samples", uint("φ samples of the peak scans")),
            ("peak_xtol", num("φ tolerance of the peak refinement")),
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

/// The JSON Schema of a problem file, every family.
pub fn problem_schema() -> Value {
    let mut branches = [
        (Family::SliderCrank, slider_crank()),
        (Family::LuffingCrane, luffing_crane()),
        (Family::Hypocycloid, hypocycloid()),
        (Family::EccentricGear, eccentric_gear()),
    ];
    for (family, branch) in &mut branches {
        with_ranges(*family, branch);
    }
    let branches: Vec<Value> = branches.into_iter().map(|(_, b)| b).collect();
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://github.com/cwsynth/cwsynth/problem-file.schema.json",
        "title": "cwsynth problem file",
        "description": "One machine (scene) in TOML; see docs/problem-files.md. A dimensional quantity is a string with a unit (\"35 mm\"); a bare number is a pure number.",
        "type": "object",
        "required": ["name", "family", "mechanism", "objective"],
        "properties": {
            "family": {
                "type": "string",
                "enum": ["slider-crank", "luffing-crane", "hypocycloid", "eccentric-gear"]
            }
        },
        "oneOf": branches
    })
}

/// Sets `minimum` and `maximum` of every integer key of `family` ([`super::limits`]) in its
/// branch (for an array of integers, on its items).
fn with_ranges(family: Family, branch: &mut Value) {
    for c in counts(family) {
        let mut node = &mut *branch;
        for part in c.key.split('.') {
            node = &mut node["properties"][part];
        }
        if node.get("items").is_some() {
            node = &mut node["items"];
        }
        assert!(
            node["type"] == "integer",
            "schema: {} {} is no integer",
            family.as_str(),
            c.key
        );
        node["minimum"] = c.min.into();
        node["maximum"] = c.max.into();
    }
}
