//! A machine's drive in its result (`[mechanism.drive]`, issue 33), for every family with a
//! drive torque: the figures of [`DriveFigures`] in `derived`, the tables of the turn
//! (`<name>-drive.csv`, `<name>-steady-state.csv`) and the turning-moment and speed plot. It
//! draws; the family's solve computed every number.

use crate::dynamics::{ConstantSpeed, DriveFigures, Flywheel, RealSpeed, SteadyState};
use crate::report::plot::{self, Panel, Series};
use crate::report::{number_map, Plot, SolveResult, Table};

/// The drive's figures (`[mechanism.drive]`, `docs/results.md`), in `derived` (and in each
/// row of a family's load cases).
#[derive(Debug, serde::Serialize)]
pub struct DriveNumbers {
    /// T̄, the mean drive torque at the nominal speed (N·m).
    pub drive_mean_torque_nm: f64,
    /// Bound on its error (N·m).
    pub drive_mean_torque_error_nm: f64,
    /// ΔE = max E − min E of the energy curve E = ∫ (T − T̄) dφ at the nominal speed (J).
    pub energy_fluctuation_j: f64,
    /// Bound on the error of ΔE (J).
    pub energy_fluctuation_error_j: f64,
    /// With `cs`: the textbook flywheel ΔE / (Cs ω̄²) (kg·m²).
    pub flywheel_textbook_kgm2: Option<f64>,
    /// With `cs`: the least flywheel whose periodic steady state meets Cs (kg·m²).
    pub flywheel_least_kgm2: Option<f64>,
    /// Bound on its error (kg·m²).
    pub flywheel_least_error_kgm2: Option<f64>,
    /// The flywheel of the steady state below (kg·m²).
    pub steady_flywheel_kgm2: f64,
    /// The steady state's ω_min (rad/s).
    pub steady_omega_min_rad_s: f64,
    /// Its ω_max (rad/s).
    pub steady_omega_max_rad_s: f64,
    /// Its time-mean speed 2π/period (rad/s).
    pub steady_omega_mean_rad_s: f64,
    /// Bound on the error of the three speeds (rad/s).
    pub steady_omega_error_rad_s: f64,
    /// Its Cs = (ω_max − ω_min)/ω_mean.
    pub steady_cs: f64,
    /// Bound on the error of Cs.
    pub steady_cs_error: f64,
    /// Its peak angular acceleration |α| of the crank (rad/s²).
    pub steady_peak_angular_acceleration_rad_s2: f64,
    /// Bound on its error (rad/s²).
    pub steady_peak_angular_acceleration_error_rad_s2: f64,
    /// The peak shaking force at real speed (N), without balancers.
    pub steady_peak_shaking_force_n: Option<f64>,
    /// Its error bound (N).
    pub steady_peak_shaking_force_error_n: Option<f64>,
    /// Its difference from the constant-speed peak, relative (%).
    pub steady_peak_shaking_force_change_pct: Option<f64>,
    /// The peak torque in the crank shaft between flywheel and mechanism at real speed (N·m).
    pub steady_peak_shaft_torque_nm: Option<f64>,
    /// Bound on its error (N·m).
    pub steady_peak_shaft_torque_error_nm: Option<f64>,
}

/// The drive's numbers in `derived`, or its error as a warning; `peak_force` is the
/// design's peak shaking force at constant speed (N), which the real-speed peak is compared
/// with.
pub fn drive_numbers(
    r: &mut SolveResult,
    drive: Option<&Result<DriveFigures, String>>,
    peak_force: Option<f64>,
) {
    let d = match drive {
        None => return,
        Some(Err(why)) => {
            r.warnings
                .push(format!("the drive could not be computed: {why}"));
            return;
        }
        Some(Ok(d)) => d,
    };
    r.derived.extend(number_map(&DriveNumbers::of(
        &d.constant,
        d.flywheel.as_ref(),
        &d.steady,
        d.real,
        peak_force,
    )));
}

impl DriveNumbers {
    /// The figures of a drive's parts ([`DriveFigures`]): the constant-speed figures `c`, the
    /// least flywheel `f`, a steady state `st` with its real-speed peaks `real`; `peak_force`
    /// the constant-speed peak shaking force the real-speed one is compared with (N).
    pub fn of(
        c: &ConstantSpeed,
        f: Option<&Flywheel>,
        st: &SteadyState,
        real: Option<RealSpeed>,
        peak_force: Option<f64>,
    ) -> DriveNumbers {
        DriveNumbers {
            drive_mean_torque_nm: c.mean_torque,
            drive_mean_torque_error_nm: c.mean_torque_error,
            energy_fluctuation_j: c.energy_fluctuation,
            energy_fluctuation_error_j: c.energy_fluctuation_error,
            flywheel_textbook_kgm2: f.map(|f| f.textbook),
            flywheel_least_kgm2: f.map(|f| f.inertia),
            flywheel_least_error_kgm2: f.map(|f| f.inertia_error),
            steady_flywheel_kgm2: st.flywheel,
            steady_omega_min_rad_s: st.omega_min,
            steady_omega_max_rad_s: st.omega_max,
            steady_omega_mean_rad_s: st.omega_mean,
            steady_omega_error_rad_s: st.omega_error,
            steady_cs: st.cs,
            steady_cs_error: st.cs_error,
            steady_peak_angular_acceleration_rad_s2: st.peak_alpha,
            steady_peak_angular_acceleration_error_rad_s2: st.peak_alpha_error,
            steady_peak_shaking_force_n: real.map(|x| x.peak_force),
            steady_peak_shaking_force_error_n: real.map(|x| x.peak_force_error),
            steady_peak_shaking_force_change_pct: real
                .zip(peak_force)
                .map(|(x, p)| 100.0 * (x.peak_force - p) / p),
            steady_peak_shaft_torque_nm: real.map(|x| x.peak_shaft_torque),
            steady_peak_shaft_torque_error_nm: real.map(|x| x.peak_shaft_torque_error),
        }
    }
}

/// The `load_cases` section of a family with named load cases: the keys every family
/// writes alike — `count`, the flywheel of all the cases (`flywheel_kgm2`,
/// `flywheel_error_kgm2`, `flywheel_rule`, `flywheel_case`, `case_of(k)` naming case k) —
/// and the family's own keys `own` (a JSON object: its governing cases and its rows).
pub fn load_cases_section<'a>(
    count: usize,
    flywheel: Option<crate::dynamics::cases::CasesFlywheel>,
    case_of: impl Fn(usize) -> &'a str,
    own: serde_json::Value,
) -> serde_json::Value {
    let mut v = serde_json::json!({
        "count": count,
        "flywheel_kgm2": flywheel.map(|f| f.inertia),
        "flywheel_error_kgm2": flywheel.map(|f| f.error),
        "flywheel_rule": flywheel.map(|f| match f.governing {
            Some(_) => "the largest least flywheel over the cases (mechanism.drive.cs)",
            None => "the given flywheel (mechanism.drive.flywheel)",
        }),
        "flywheel_case": flywheel.and_then(|f| f.governing).map(case_of),
    });
    if let (Some(v), serde_json::Value::Object(own)) = (v.as_object_mut(), own) {
        v.extend(own);
    }
    v
}

/// One load case's drive keys ([`DriveNumbers`]) from its own drive `own` (its constant-speed
/// figures and least flywheel) and its steady state `at` with the flywheel of all the cases,
/// and why not where either failed; `peak_force` the design's constant-speed peak shaking
/// force (N).
pub fn case_numbers<'a>(
    own: Option<&'a Result<DriveFigures, String>>,
    at: Option<&'a Result<DriveFigures, String>>,
    peak_force: Option<f64>,
) -> (Option<DriveNumbers>, Option<&'a str>) {
    let why = [own, at]
        .into_iter()
        .find_map(|d| d.and_then(|d| d.as_ref().err()));
    let ok = |d: Option<&'a Result<DriveFigures, String>>| d.and_then(|d| d.as_ref().ok());
    let numbers = ok(own).zip(ok(at)).map(|(own, at)| {
        let f = own.flywheel.as_ref();
        DriveNumbers::of(&own.constant, f, &at.steady, at.real, peak_force)
    });
    (numbers, why.map(String::as_str))
}

/// The drive's table and plot: the turn at constant speed (T, E) and at real speed (ω, α).
/// `angle` names the input angle in the CSV columns and the plot (e.g. `"crank"`).
pub fn drive_documents(
    r: &mut SolveResult,
    drive: Option<&Result<DriveFigures, String>>,
    angle: &'static str,
) {
    drive_documents_of(r, drive, angle, None)
}

/// [`drive_documents`] of another case beside the scene's own, `case` = (suffix, name): the
/// load case that governs the flywheel, say. Its tables and plot are `drive-<suffix>` and
/// `steady-state-<suffix>`, their captions naming the case.
pub fn drive_documents_of(
    r: &mut SolveResult,
    drive: Option<&Result<DriveFigures, String>>,
    angle: &'static str,
    case: Option<(&str, &str)>,
) {
    let Some(Ok(d)) = drive else { return };
    let suffix = |s: &str| case.map_or(s.to_string(), |c| format!("{s}-{}", c.0));
    let of = case.map_or(String::new(), |c| format!(" (load case {})", c.1));
    let mut d = d.clone();
    d.constant.curve = thin(&d.constant.curve);
    d.steady.curve = thin(&d.steady.curve);
    let mut csv = format!("{angle}_angle_deg,drive_torque_nm,energy_j\n");
    for [p, t, e] in &d.constant.curve {
        csv += &format!("{},{},{}\n", p.to_degrees(), t, e);
    }
    r.tables.push(Table {
        suffix: suffix("drive"),
        caption: format!(
            "The turn at constant speed{of}: drive torque T and energy curve E = ∫ (T − T̄) dφ"
        ),
        csv,
    });
    let mut csv = format!("{angle}_angle_deg,speed_rad_s,angular_acceleration_rad_s2\n");
    for [p, w, a] in &d.steady.curve {
        csv += &format!("{},{},{}\n", p.to_degrees(), w, a);
    }
    r.tables.push(Table {
        suffix: suffix("steady-state"),
        caption: format!(
            "The periodic steady state at real speed{of}: {angle} speed ω and acceleration α"
        ),
        csv,
    });
    r.plots.push(Plot::of_panels(
        suffix("drive"),
        format!("Turning-moment diagram, energy fluctuation and the speed over a turn{of}"),
        480,
        420,
        move || Ok(drive_panels(&d, angle)),
    ));
}

/// `word` with its first letter in upper case ("crank" → "Crank").
fn capitalised(word: &str) -> String {
    let mut c = word.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// Most rows of a curve in the tables and plots: a grid that had to be finer (a load with
/// kinks, such as a compressor's valve events) is shown at every 2ᵏ-th node.
const MAX_ROWS: usize = 4096;

/// Every 2ᵏ-th point of `v`, the least k that leaves at most `MAX_ROWS` + 1 (a closed curve's
/// last point, at 2π, is kept).
fn thin(v: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let k = v.len().div_ceil(MAX_ROWS + 1).next_power_of_two();
    v.iter().step_by(k).copied().collect()
}

/// Three panels over the input angle: T with T̄; E with its extremes marked (ΔE between them);
/// ω at real speed with ω_min, ω_max and the mean.
fn drive_panels(d: &DriveFigures, angle: &str) -> Vec<Panel> {
    let (c, st) = (&d.constant, &d.steady);
    let deg = |p: f64| p.to_degrees();
    let curve = |k: usize| {
        c.curve
            .iter()
            .map(|v| (deg(v[0]), v[k]))
            .collect::<Vec<_>>()
    };
    let flat = |y: f64| vec![(0.0, y), (360.0, y)];
    let ([p_hi, p_lo], [e_hi, e_lo]) = (c.extreme_angles, c.extreme_energies);
    // The nodes of one turn, closed at 360°.
    let speed: Vec<(f64, f64)> = st
        .curve
        .iter()
        .map(|v| (deg(v[0]), v[1]))
        .chain(st.curve.first().map(|v| (360.0, v[1])))
        .collect();
    // T̄ at round-off level (a machine that does no net work) is shown as 0.
    let t_scale = c.curve.iter().fold(0.0_f64, |m, v| m.max(v[1].abs()));
    let t_bar = if c.mean_torque.abs() < 1e-12 * t_scale {
        0.0
    } else {
        c.mean_torque
    };
    vec![
        Panel {
            title: format!(
                "Drive torque at constant speed, T̄ = {} N·m",
                plot::tick(&t_bar)
            ),
            x_label: format!("{angle} angle φ (°)"),
            y_label: "T (N·m)".into(),
            series: vec![
                Series::line("T(φ)", curve(1)),
                Series::line("T̄", flat(t_bar)),
            ],
            equal_aspect: false,
        },
        Panel {
            title: format!("Energy curve: ΔE = {} J", plot::tick(&c.energy_fluctuation)),
            x_label: format!("{angle} angle φ (°)"),
            y_label: "E (J)".into(),
            series: vec![
                Series::line("E(φ) = ∫ (T − T̄) dφ", curve(2)),
                Series::peak("max E", vec![(deg(p_hi), e_hi)]),
                Series::peak("min E", vec![(deg(p_lo), e_lo)]),
            ],
            equal_aspect: false,
        },
        Panel {
            title: format!(
                "{} speed at real speed, flywheel {} kg·m²: Cs = {}",
                capitalised(angle),
                plot::tick(&st.flywheel),
                plot::tick(&st.cs)
            ),
            x_label: format!("{angle} angle φ (°)"),
            y_label: "ω (rad/s)".into(),
            series: vec![
                Series::line("ω(φ)", speed),
                Series::line("time-mean speed", flat(st.omega_mean)),
            ],
            equal_aspect: false,
        },
    ]
}

/// Every load case's turn on one plot (`drive-cases`): each case's drive torque at constant
/// speed, and its speed at real speed with the flywheel of all the cases — the cases that do
/// not govern beside the one that does. `cases` = (legend, the case's drive at that
/// flywheel); nothing with fewer than two.
pub fn cases_plot(r: &mut SolveResult, cases: Vec<(String, DriveFigures)>, angle: &'static str) {
    if cases.len() < 2 {
        return;
    }
    let cases: Vec<(String, DriveFigures)> = cases
        .into_iter()
        .map(|(name, mut d)| {
            d.constant.curve = thin(&d.constant.curve);
            d.steady.curve = thin(&d.steady.curve);
            (name, d)
        })
        .collect();
    r.plots.push(Plot::of_panels(
        "drive-cases",
        "Every load case: the drive torque at constant speed, and the speed over a turn with the flywheel of all the cases",
        480,
        420,
        move || Ok(cases_panels(&cases, angle)),
    ));
}

/// The two panels of [`cases_plot`]: T(φ) and ω(φ) of every case.
fn cases_panels(cases: &[(String, DriveFigures)], angle: &str) -> Vec<Panel> {
    let deg = |p: f64| p.to_degrees();
    let line = |name: &str, curve: &[[f64; 3]], k: usize| {
        let mut pts: Vec<(f64, f64)> = curve.iter().map(|v| (deg(v[0]), v[k])).collect();
        // A steady state's nodes close at 360° (the constant-speed curve already does).
        if let (Some(first), Some(last)) = (curve.first(), curve.last()) {
            if deg(last[0]) < 359.999 {
                pts.push((360.0, first[k]));
            }
        }
        Series::line(name, pts)
    };
    let flywheel = cases.first().map_or(0.0, |c| c.1.steady.flywheel);
    // One panel of every case's curve: the constant-speed turn's T or the steady state's ω.
    let panel = |title: String, y_label: &str, steady: bool| Panel {
        title,
        x_label: format!("{angle} angle φ (°)"),
        y_label: y_label.into(),
        series: cases
            .iter()
            .map(|(n, d)| match steady {
                true => line(n, &d.steady.curve, 1),
                false => line(n, &d.constant.curve, 1),
            })
            .collect(),
        equal_aspect: false,
    };
    let speed = format!(
        "{} speed at real speed, flywheel {} kg·m²",
        capitalised(angle),
        plot::tick(&flywheel)
    );
    vec![
        panel(
            "Drive torque at constant speed, every load case".into(),
            "T (N·m)",
            false,
        ),
        panel(speed, "ω (rad/s)", true),
    ]
}
