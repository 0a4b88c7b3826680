//! The full-cycle analysis of one gear design turned into its outcome: objectives with
//! their errors, derived figures, warnings, the consistency of the stated data with the
//! paper's, the contact series, the pitch curves and the tooth-level outputs.

use super::GearScene;
use super::{
    Analysis, Derived, Design, Objectives, Outcome, PaperCheck, PitchCurves, Series, Settings,
    SolveError, Status, TeethOptions, TeethOutcome, ZeroOut,
};
use crate::families::gear::model::{
    closure_integral, periodic_integral, Alpha2Map, GearPair, Which, Zero, ZeroKind,
};
use crate::families::gear::stress::{flank_stress, FlankStress};
use crate::families::gear::teeth::{
    balanced_shift, certified_pole_arches, circular_cycloidal_mu, contact_kinematics, flank_wear,
    involute, involute_shifted, profiles,
};
use crate::geom::P2;
use crate::report::numbers::key;
use std::f64::consts::{PI, TAU};

/// What the sections of an outcome share: the design's pair and its figures.
struct Ctx<'a> {
    scene: &'a GearScene,
    an: &'a Analysis,
    pair: &'a GearPair,
    /// Pitch radius R, eccentricity e, generating radius r.
    r: f64,
    e: f64,
    rg: f64,
    /// Turns of gear 1 and 2 per cycle, and n1/n2.
    n1: u32,
    n2: u32,
    ratio: f64,
    /// Teeth of gear 1 and gear 2.
    z1: usize,
    z2: f64,
    /// Perimeters of the pitch curves (m).
    perim1: f64,
    perim2: f64,
    /// Smallest distance between a µ1 and a µ2 pole (rad; ∞ without both).
    min_sep: f64,
    /// Largest obliquity |ψ| at the zeros of µ (rad).
    psi_at_zeros: f64,
    /// Cusps where ψ = 0 (µ is 0/0 there).
    indet: Vec<&'a Zero>,
}

/// Assemble the outcome (objectives, errors, derived values, checks, series) of an analysis.
pub fn report(
    scene: &GearScene,
    an: &Analysis,
    settings: &Settings,
) -> Result<Outcome, SolveError> {
    let pair = &an.pair;
    let a2map = Alpha2Map::new(&pair.c, pair.a);
    let (ctx, perim2_error) = context(scene, an);
    let (design, objectives, errors) = figures(&ctx);
    let mut derived = derived(&ctx, &a2map, perim2_error);
    let mut warnings = warnings(&ctx);
    let mut paper = Vec::new();
    stated_teeth(&ctx, &mut warnings, &mut paper);
    stated_lengths(&ctx, &mut warnings, &mut paper);
    stated_center_distance(&ctx, &mut derived, &mut warnings, &mut paper);
    mu_checks(&ctx, &mut paper);
    let ns = settings.series_points;
    let series = series(&ctx, ns);
    let pitch_curves = pitch_curves(pair, &a2map, ctx.ratio, settings.curve_points);
    let teeth = scene
        .tooth_outputs
        .map(|t| teeth(&ctx, &a2map, &t, ns, &mut derived))
        .transpose()?;
    let poles = an.sing.poles.clone();
    let zeros = an
        .sing
        .zeros
        .iter()
        .map(|z| ZeroOut {
            alpha1_rad: z.alpha1_rad,
            kind: z.kind,
        })
        .collect();
    Ok(Outcome {
        status: Status::Analysed,
        design,
        objectives,
        errors,
        derived,
        warnings,
        paper,
        method: String::new(),
        poles,
        zeros,
        series,
        pitch_curves,
        sweep: Vec::new(),
        search: None,
        teeth,
    })
}

/// The shared figures of an analysis, and the error bound of gear 2's perimeter (m).
fn context<'a>(scene: &'a GearScene, an: &'a Analysis) -> (Ctx<'a>, f64) {
    let pair = &an.pair;
    let (r, e, rg) = (pair.c.r_pitch, pair.c.e, pair.r_gen);
    let (n1, n2) = (scene.turns_gear1, scene.turns_gear2);
    let ratio = n1 as f64 / n2 as f64;
    let n_arch = pair.n_arches;
    // Gear 2's perimeter from its own polar description: ∫ sqrt(ρ2² + ρ̇2²) dα2.
    let perim2_turn = periodic_integral(
        |al| {
            let r1 = pair.c.rho1(al);
            let r2 = pair.a - r1;
            let q = r2 / r1;
            let r2d = -pair.c.rho1_d1(al) * q;
            (r2 * r2 + r2d * r2d).sqrt() / q
        },
        1e-14,
    );
    // Smallest distance between a µ1 pole and a µ2 pole.
    let mut min_sep = f64::INFINITY;
    for p in an.sing.poles.iter().filter(|p| p.which == Which::Mu1) {
        for q in an.sing.poles.iter().filter(|p| p.which == Which::Mu2) {
            let d = (p.alpha1_rad - q.alpha1_rad).rem_euclid(TAU);
            min_sep = min_sep.min(d.min(TAU - d));
        }
    }
    let psi_at_zeros = an
        .sing
        .zeros
        .iter()
        .map(|z| pair.c.psi_sin_cos(z.alpha1_rad).0.abs().asin())
        .fold(0.0, f64::max);
    let ctx = Ctx {
        scene,
        an,
        pair,
        r,
        e,
        rg,
        n1,
        n2,
        ratio,
        z1: n_arch / 2,
        z2: (n_arch as f64 * ratio / 2.0).round(),
        perim1: TAU * r,
        perim2: perim2_turn.value * ratio,
        min_sep,
        psi_at_zeros,
        indet: an
            .sing
            .zeros
            .iter()
            .filter(|z| z.kind == ZeroKind::Indeterminate)
            .collect(),
    };
    (ctx, perim2_turn.error * ratio + an.closure.a_error * TAU)
}

/// The ratio range's errors through the centre distance a: d i/da = 1/ρ1.
fn ratio_errors(ctx: &Ctx) -> (f64, f64) {
    let a_error = ctx.an.closure.a_error;
    (a_error / (ctx.r + ctx.e), a_error / (ctx.r - ctx.e))
}

/// The design, the objectives and their errors.
fn figures(ctx: &Ctx) -> (Design, Objectives, Objectives) {
    let (an, r, e) = (ctx.an, ctx.r, ctx.e);
    let (imin, imax) = ctx.pair.ratio_range();
    let (di_min, di_max) = ratio_errors(ctx);
    let var = imax / imin;
    let var_err = var * (di_min / imin + di_max / imax) + 4.0 * f64::EPSILON * var;
    let design = Design {
        eccentricity_m: e,
        pitch_radius_m: r,
        generating_radius_m: ctx.rg,
    };
    let psi_max = (e / r).asin();
    let objectives = Objectives {
        peak_sliding_coefficient: an.peak.value,
        ratio_variation: var,
        max_pitch_pressure_angle_rad: psi_max,
        min_gear2_curvature_per_m: an.curvature.0,
    };
    let errors = Objectives {
        peak_sliding_coefficient: an.peak.error,
        ratio_variation: var_err,
        max_pitch_pressure_angle_rad: 4.0 * f64::EPSILON * psi_max.max(f64::MIN_POSITIVE),
        min_gear2_curvature_per_m: an.curvature.2,
    };
    (design, objectives, errors)
}

/// The derived figures of the analysis (those of the stated data, the teeth and the design
/// search left empty).
fn derived(ctx: &Ctx, a2map: &Alpha2Map, perim2_error: f64) -> Derived {
    let (an, pair, r, e, rg) = (ctx.an, ctx.pair, ctx.r, ctx.e, ctx.rg);
    let (imin, imax) = pair.ratio_range();
    let (di_min, di_max) = ratio_errors(ctx);
    let n_mu1 = an
        .sing
        .poles
        .iter()
        .filter(|p| p.which == Which::Mu1)
        .count();
    let n_mu2 = an.sing.poles.len() - n_mu1;
    let max_pole_err = an
        .sing
        .poles
        .iter()
        .map(|p| p.error_rad)
        .fold(0.0, f64::max);
    let min_sep = ctx.min_sep;
    Derived {
        center_distance_m: pair.a,
        center_distance_error_m: an.closure.a_error,
        ratio_min: imin,
        ratio_max: imax,
        ratio_min_error: di_min,
        ratio_max_error: di_max,
        gear2_turn_per_gear1_turn_rad: a2map.per_turn(),
        gear2_turn_per_gear1_turn_error_rad: a2map.error,
        gear1_perimeter_m: ctx.perim1,
        gear2_perimeter_m: ctx.perim2,
        gear2_perimeter_error_m: perim2_error,
        arches_gear1: pair.n_arches as f64,
        teeth_gear1: ctx.z1 as f64,
        teeth_gear2: ctx.z2,
        pitch_m: 4.0 * PI * rg,
        arch_length_m: TAU * rg,
        arch_span_rad: TAU * rg / r,
        poles_mu1_per_turn: n_mu1 as f64,
        poles_mu2_per_turn: n_mu2 as f64,
        pole_window_rad: ctx.scene.pole_window,
        peak_sliding_alpha1_rad: an.peak.alpha1,
        max_mu_asymmetry: an.peak.max_asymmetry,
        min_gear2_curvature_alpha1_rad: an.curvature.1,
        rho1_min_m: r - e,
        rho1_max_m: r + e,
        max_pole_error_rad: max_pole_err,
        min_mu1_mu2_pole_separation_rad: min_sep.is_finite().then_some(min_sep),
        ratio_at_stated_center_distance: None,
        max_obliquity_at_pitch_point_contact_rad: ctx.psi_at_zeros,
        ..Derived::default()
    }
}

/// What the user should know about the analysed pair: a degenerating e, unbounded |µ|, a
/// concave gear 2, cusps where µ is 0/0, overlapping pole windows, a peak set by the window.
fn warnings(ctx: &Ctx) -> Vec<String> {
    let (scene, an, r, e, rg, min_sep) = (ctx.scene, ctx.an, ctx.r, ctx.e, ctx.rg, ctx.min_sep);
    let imax = ctx.pair.ratio_range().1;
    let indet = &ctx.indet;
    let mut warnings = Vec::new();
    if e / r > 0.9 {
        warnings.push(format!(
            "design.eccentricity: e/R = {:.4} is close to 1: ρ1 min = {:.3e} m, i12 max = {:.4}; the pair degenerates as e → R",
            e / r,
            r - e,
            imax
        ));
    }
    if r - e <= 2.0 * rg {
        warnings.push(format!(
            "design.eccentricity: ρ1 min = R − e = {:.3e} m ≤ 2r = {:.3e} m: the generating circle is as large as gear 1's radius there, hypocycloid flanks run through the pivot and µ1 poles spread over whole arches",
            r - e,
            2.0 * rg
        ));
    }
    if !an.peak.value.is_finite() {
        warnings.push(format!(
            "model.pole_window = 0: no window is left out, and |µ| is unbounded at the {} poles of µ1, µ2 (the first at α1 = {:.6} rad); objectives.peak_sliding_coefficient has no finite value (null)",
            an.sing.poles.len(),
            an.peak.alpha1
        ));
    }
    if an.curvature.0 <= 0.0 {
        warnings.push(format!(
            "gear 2's pitch curve is not convex (min curvature {:.4e} 1/m at α1 = {:.4} rad): it cannot be cut as an external gear there",
            an.curvature.0, an.curvature.1
        ));
    }
    if !indet.is_empty() {
        warnings.push(format!(
            "{} cusp(s) fall where ψ = 0 (α1 = {}): µ is 0/0 there (a pole merged with the zero, one-sided limits differ); excluded by the pole window",
            indet.len(),
            indet.iter().map(|z| format!("{:.6}", z.alpha1_rad)).collect::<Vec<_>>().join(", ")
        ));
    }
    if min_sep.is_finite() && min_sep < 2.0 * scene.pole_window {
        warnings.push(format!(
            "µ1 and µ2 poles are as close as {min_sep:.3e} rad (< twice the pole window {:.3e} rad): their windows overlap",
            scene.pole_window
        ));
    }
    let at_edge = an.sing.poles.iter().any(|p| {
        let d = (p.alpha1_rad - an.peak.alpha1).rem_euclid(TAU);
        (d.min(TAU - d) - scene.pole_window).abs() < 1e-6
    });
    if at_edge {
        warnings.push(format!(
            "the peak |µ| = {:.4} is attained at the edge of a pole window: it is set by model.pole_window (|µ| grows like 1/distance to the pole)",
            an.peak.value
        ));
    }

    warnings
}

/// The module and the teeth the paper states against those of the pitch circle.
fn stated_teeth(ctx: &Ctx, warnings: &mut Vec<String>, paper: &mut Vec<PaperCheck>) {
    let (scene, r, rg, z1, z2, perim1, perim2, ratio) = (
        ctx.scene, ctx.r, ctx.rg, ctx.z1, ctx.z2, ctx.perim1, ctx.perim2, ctx.ratio,
    );
    let pitch = 4.0 * PI * rg;
    if let Some(m) = scene.module {
        if ((PI * m) - pitch).abs() > 1e-6 * pitch {
            warnings.push(format!("mechanism.module: πm = {:.4e} m but the teeth (arch 2πr, tooth = space) give a pitch 4πr = {pitch:.4e} m", PI * m));
        }
    }
    if let Some((tz1, tz2)) = scene.teeth {
        if tz1 as usize != z1 {
            warnings.push(format!(
                "mechanism.teeth_gear1: stated z1 = {tz1}, but the pitch circle (2πR = {:.4} mm) holds R/(2r) = {z1} teeth of pitch 4πr = {:.4} mm; z1 = {tz1} would need R = {:.4} mm or r = {:.4} mm. The model uses {z1} teeth",
                perim1 * 1e3,
                pitch * 1e3,
                2.0 * tz1 as f64 * rg * 1e3,
                r / (2.0 * tz1 as f64) * 1e3
            ));
            paper.push(PaperCheck::new(
                "teeth of gear 1, z1",
                key!("derived", Derived, teeth_gear1),
                tz1 as f64,
                z1 as f64,
                format!(
                    "2πR/(4πr) = R/(2r); with the stated module, 2πR/(πm) = {:.4}",
                    scene.module.map_or(f64::NAN, |m| 2.0 * r / m)
                ),
            ));
            paper.push(PaperCheck::new(
                "arch span of eq. (2), π/z1 (rad of the pitch circle)",
                key!("derived", Derived, arch_span_rad),
                PI / tz1 as f64,
                TAU * rg / r,
                "eq. (2) spans each arch over π/z1 of the pitch circle, but one turn of the r = 1.25 mm generating circle covers 2πr/R; with z1 = 12 the arches would not end in cusps",
            ));
        }
        if tz2 as f64 != z2 {
            warnings.push(format!(
                "mechanism.teeth_gear2: stated z2 = {tz2}, closure gives (n1/n2)·z1 = {z2}"
            ));
            paper.push(PaperCheck::new(
                "teeth of gear 2, z2",
                key!("derived", Derived, teeth_gear2),
                tz2 as f64,
                z2,
                "z2 = (n1/n2)·z1 with z1 from the pitch circle; the stated 36 = 3 × 12 keeps the ratio but inherits the wrong z1",
            ));
        }
        if let Some(p) = scene.tooth_pitch {
            let stated_perim2 = tz2 as f64 * p;
            paper.push(PaperCheck::new(
                "perimeter of gear 2's pitch curve (z2 × pitch)",
                key!("derived", Derived, gear2_perimeter_m),
                stated_perim2,
                perim2,
                format!("paper value = z2 × pitch; computed from gear 2's polar curve ∫sqrt(ρ2² + ρ2'²)dα2; must equal (n1/n2)·2πR = {:.4} mm", ratio * perim1 * 1e3),
            ));
        }
    }
}

/// The tooth pitch, thickness and space width the paper states against one arch.
fn stated_lengths(ctx: &Ctx, warnings: &mut Vec<String>, paper: &mut Vec<PaperCheck>) {
    let (scene, rg) = (ctx.scene, ctx.rg);
    let pitch = 4.0 * PI * rg;
    if let Some(p) = scene.tooth_pitch {
        if (p - pitch).abs() > 0.005 * pitch {
            warnings.push(format!(
                "mechanism.tooth_pitch: stated {:.4} mm, teeth give 4πr = {:.4} mm",
                p * 1e3,
                pitch * 1e3
            ));
        }
        paper.push(PaperCheck::new(
                "pitch on the pitch curve",
                key!("derived", Derived, pitch_m),
                p,
                pitch,
                "4πr (= πm for m = 4r); agrees to the printed rounding. The pitch 2πR/z1 with the stated z1 would be different",
            ));
    }
    for (k, v) in [
        ("mechanism.tooth_thickness", scene.tooth_thickness),
        ("mechanism.space_width", scene.space_width),
    ] {
        if let Some(t) = v {
            let arch = TAU * rg;
            if (t - arch).abs() > 0.005 * arch {
                warnings.push(format!(
                    "{k}: stated {:.4} mm, one arch 2πr = {:.4} mm",
                    t * 1e3,
                    arch * 1e3
                ));
            }
            paper.push(PaperCheck::new(
                format!("{} on the pitch curve", if k.ends_with("thickness") { "tooth thickness" } else { "space width" }),
                key!("derived", Derived, arch_length_m),
                t,
                arch,
                "one cycloid arch = one turn of the generating circle, 2πr; agrees to the printed rounding",
            ));
        }
    }
}

/// The centre distance the paper states against the closing one.
fn stated_center_distance(
    ctx: &Ctx,
    derived: &mut Derived,
    warnings: &mut Vec<String>,
    paper: &mut Vec<PaperCheck>,
) {
    let (scene, an, pair, r, e, n1, n2) =
        (ctx.scene, ctx.an, ctx.pair, ctx.r, ctx.e, ctx.n1, ctx.n2);
    if let Some(a_st) = scene.center_distance {
        let j = closure_integral(&pair.c, a_st, 1e-15);
        if a_st > r + e && j.value.is_finite() {
            let ratio_st = TAU / j.value;
            let miss = (n1 as f64 * j.value - TAU * n2 as f64).to_degrees();
            derived.ratio_at_stated_center_distance = Some(ratio_st);
            paper.push(PaperCheck::new(
                "centre distance a12",
                key!("derived", Derived, center_distance_m),
                a_st,
                pair.a,
                format!(
                    "closing centre distance for n1/n2 = {n1}/{n2} (±{:.1e} mm); the stated value gives n1/n2 = {ratio_st:.6}, gear 2 missing closure by {miss:.4}° per cycle{}",
                    an.closure.a_error * 1e3,
                    if (a_st - pair.a).abs() <= 0.05e-3 { " — the stated value is the closing one rounded to 0.1 mm" } else { " — the stated value belongs to a different design" }
                ),
            ));
            if (a_st - pair.a).abs() > 1e-9 * pair.a {
                warnings.push(format!(
                    "mechanism.center_distance: stated {:.4} mm, closure gives {:.6} mm; the stated value would give n1/n2 = {ratio_st:.6}",
                    a_st * 1e3,
                    pair.a * 1e3
                ));
            }
        } else {
            warnings.push(format!("mechanism.center_distance: stated {:.4} mm is not above R + e: the pair cannot mesh there", a_st * 1e3));
        }
    }
}

/// The paper's claims on µ1, µ2 and the contact at the pitch point against the computation.
fn mu_checks(ctx: &Ctx, paper: &mut Vec<PaperCheck>) {
    let (an, min_sep, psi_at_zeros) = (ctx.an, ctx.min_sep, ctx.psi_at_zeros);
    paper.push(PaperCheck::new(
                "max |µ1 + µ2| on the working window (paper: µ2 = −µ1, symmetric)",
                key!("derived", Derived, max_mu_asymmetry),
                0.0,
                an.peak.max_asymmetry,
                "by definition µ2 = −µ1/(1 − µ1) exactly, which is −µ1 only to first order; the curves are mirror images only where |µ| ≪ 1",
            ));
    if min_sep.is_finite() {
        paper.push(PaperCheck::new(
                "separation of µ1 and µ2 poles in α1 (paper: both at points 2, 4)",
                key!("derived", Derived, min_mu1_mu2_pole_separation_rad),
                0.0,
                min_sep,
                "µ1 is infinite where the common tangent passes through O1, µ2 where it passes through O2: distinct points (the paper's eq. 11 itself keeps cos β2 ≠ 0)",
            ));
    }
    paper.push(PaperCheck::new(
                "angle between the common tangent and O1O2 at K = P",
                key!("derived", Derived, max_obliquity_at_pitch_point_contact_rad),
                PI / 2.0,
                psi_at_zeros,
                "at K = P the contact is at a cusp, whose tangent is the pitch-curve normal: it deviates from O1O2 by the obliquity |ψ| (max shown), it is not perpendicular to it",
            ));
}

/// The contact series at `ns` angles of one turn of gear 1 (µ left out within a pole window).
fn series(ctx: &Ctx, ns: usize) -> Series {
    let (scene, an, pair, indet) = (ctx.scene, ctx.an, ctx.pair, &ctx.indet);
    let mut series = Series::default();
    let near_pole = |x: f64, w: Which| {
        an.sing.poles.iter().filter(|p| p.which == w).any(|p| {
            let d = (x - p.alpha1_rad).rem_euclid(TAU);
            d.min(TAU - d) <= scene.pole_window + p.error_rad
        }) || indet.iter().any(|z| {
            let d = (x - z.alpha1_rad).rem_euclid(TAU);
            d.min(TAU - d) <= scene.pole_window
        })
    };
    for k in 0..ns {
        let x = TAU * k as f64 / ns as f64;
        let ct = pair.contact(x);
        series.alpha1_rad.push(x);
        series.i12.push(pair.i12(x));
        series.mu1.push(if near_pole(x, Which::Mu1) {
            None
        } else {
            ct.mu1
        });
        series.mu2.push(if near_pole(x, Which::Mu2) {
            None
        } else {
            ct.mu2
        });
        series.sliding_velocity_m_per_s.push(ct.v_slide);
        series.pressure_angle_rad.push(ct.pressure_angle);
        series.contact_point_m.push([ct.k.x, ct.k.y]);
    }
    series
}

/// The tooth-level outputs and their derived figures.
fn teeth(
    ctx: &Ctx,
    a2map: &Alpha2Map,
    t: &TeethOptions,
    ns: usize,
    derived: &mut Derived,
) -> Result<TeethOutcome, SolveError> {
    let (an, pair, n1, n2) = (ctx.an, ctx.pair, ctx.n1, ctx.n2);
    let out = teeth_outcome(pair, a2map, n1, n2, t, ns, ctx.scene.pole_window)?;
    let wear_ext = |v: &[(f64, f64)], max: bool| extreme(v.iter().map(|x| x.0), max);
    derived.tooth_profile_closure_gap_m = Some(out.profiles.gear2_closure_gap_m);
    derived.sliding_distance_max_gear1_m = Some(wear_ext(&out.wear.gear1, true));
    derived.sliding_distance_min_gear1_m = Some(wear_ext(&out.wear.gear1, false));
    derived.sliding_distance_max_gear2_m = Some(wear_ext(&out.wear.gear2, true));
    derived.sliding_distance_min_gear2_m = Some(wear_ext(&out.wear.gear2, false));
    derived.sliding_distance_error_m = Some(
        out.wear
            .gear1
            .iter()
            .chain(&out.wear.gear2)
            .map(|x| x.1)
            .fold(0.0, f64::max),
    );
    let inv = &out.involute;
    derived.involute_peak_sliding_coefficient = Some(inv.peak_mu());
    derived.involute_contact_ratio = Some(inv.contact_ratio);
    derived.involute_routine_shift_peak_sliding_coefficient = Some(out.routine_shift.peak_mu());
    if let Some(b) = &out.balanced_shift {
        derived.involute_balanced_shift_x1 = Some(b.pair.shift[0]);
        derived.involute_balanced_shift_peak_sliding_coefficient = Some(b.pair.peak_mu());
        derived.involute_balanced_shift_contact_ratio = Some(b.pair.contact_ratio);
    }
    derived.circular_cycloidal_sliding_coefficient = Some(
        out.circular
            .iter()
            .fold(0.0, |a: f64, b| a.max(b.0.abs()).max(b.1.abs())),
    );
    derived.arches_with_certified_pole = Some(out.certified_pole_arches.len() as f64);
    derived.pole_band_from_cusp_rad = Some(
        an.sing
            .poles
            .iter()
            .map(|p| p.phi_rad.min(TAU - p.phi_rad))
            .fold(0.0, f64::max),
    );
    derived.min_abs_cos_beta_sampled = Some(out.contact.iter().fold(f64::INFINITY, |a, c| {
        a.min(c.cos_beta1.abs()).min(c.cos_beta2.abs())
    }));
    if let Some(st) = &out.stress {
        stress_figures(st, derived);
    }
    Ok(out)
}

/// The largest (`max`) or smallest value of `v` (0 or ∞ when empty).
fn extreme(v: impl Iterator<Item = f64>, max: bool) -> f64 {
    if max {
        v.fold(0.0, f64::max)
    } else {
        v.fold(f64::INFINITY, f64::min)
    }
}

/// The derived figures of the contact stress and the Archard wear.
fn stress_figures(st: &FlankStress, derived: &mut Derived) {
    derived.driving_contact_fraction = Some(st.driving_fraction.0);
    derived.driving_contact_fraction_error = Some(st.driving_fraction.1);
    let peak = st
        .arches
        .iter()
        .filter_map(|a| a.peak.map(|p| (a.arch, p)))
        .max_by(|x, y| x.1.p0_pa.total_cmp(&y.1.p0_pa));
    if let Some((arch, p)) = peak {
        derived.hertz_peak_stress_pa = Some(p.p0_pa);
        derived.hertz_peak_stress_error_pa = Some(p.error_pa);
        derived.hertz_peak_alpha1_rad = Some(p.alpha1);
        derived.hertz_peak_arch = Some(arch as f64);
    }
    let least = || st.arches.iter().filter_map(|a| a.least);
    if least().next().is_some() {
        derived.hertz_least_stress_max_pa = Some(extreme(least().map(|l| l.p0_pa), true));
        derived.hertz_least_stress_min_pa = Some(extreme(least().map(|l| l.p0_pa), false));
        derived.hertz_least_stress_error_pa = Some(extreme(least().map(|l| l.error_pa), true));
    }
    let vals = |v: &[(f64, f64)], max| extreme(v.iter().map(|x| x.0), max);
    derived.archard_max_gear1_nm = Some(vals(&st.gear1, true));
    derived.archard_min_gear1_nm = Some(vals(&st.gear1, false));
    derived.archard_max_gear2_nm = Some(vals(&st.gear2, true));
    derived.archard_min_gear2_nm = Some(vals(&st.gear2, false));
    derived.archard_error_nm = Some(extreme(st.gear1.iter().chain(&st.gear2).map(|x| x.1), true));
}

/// The tooth-level outputs of one analysed pair: outlines (`t.points_per_arch` per arch),
/// the contact series at `ns` points of one turn of gear 1, the sliding distance per flank
/// (Simpson to 1e-12 relative), the circular cycloidal and the involute equivalents (module
/// 4r, z1 = N/2, z2 = z1·n1/n2, standard addendum 1·m: unshifted, with the routine shift
/// x₁ = −x₂ = [`ROUTINE_SHIFT`] and with the balanced shift) and the pole certificate.
/// The routine profile shift of a small pinion, x₁ = +0.5 (x₂ = −0.5), compared beside the
/// balanced one.
pub const ROUTINE_SHIFT: f64 = 0.5;

pub fn teeth_outcome(
    pair: &GearPair,
    a2map: &Alpha2Map,
    n1: u32,
    n2: u32,
    t: &TeethOptions,
    ns: usize,
    window: f64,
) -> Result<TeethOutcome, SolveError> {
    let ratio = n1 as f64 / n2 as f64;
    let z1 = (pair.n_arches / 2) as f64;
    let stress = t
        .load
        .map(|load| flank_stress(pair, n1, n2, &load, window))
        .transpose()?;
    Ok(TeethOutcome {
        profiles: profiles(pair, a2map, n1, n2, t.points_per_arch),
        contact: (0..ns)
            .map(|k| contact_kinematics(pair, TAU * k as f64 / ns as f64))
            .collect(),
        wear: flank_wear(pair, n1, n2, 1e-12),
        involute: involute(
            4.0 * pair.r_gen,
            z1,
            z1 * ratio,
            t.involute_pressure_angle,
            1.0,
        ),
        routine_shift: involute_shifted(
            4.0 * pair.r_gen,
            z1,
            z1 * ratio,
            t.involute_pressure_angle,
            1.0,
            ROUTINE_SHIFT,
        ),
        balanced_shift: balanced_shift(
            4.0 * pair.r_gen,
            z1,
            z1 * ratio,
            t.involute_pressure_angle,
            1.0,
        ),
        circular: circular_cycloidal_mu(pair.c.r_pitch, pair.r_gen, ratio),
        certified_pole_arches: certified_pole_arches(pair),
        stress,
    })
}

/// Both pitch curves in the fixed frame at α1 = 0: gear 1's points ρ1(α)(cos α, sin α);
/// gear 2's points O2 + ρ2 (cos(π − α2), sin(π − α2)) over α1 ∈ [0, 2π n1/n2), which is one
/// full turn of gear 2.
pub fn pitch_curves(pair: &GearPair, a2: &Alpha2Map, ratio: f64, n: usize) -> PitchCurves {
    let o2 = P2::new(pair.a, 0.0);
    let gear1_m = (0..n)
        .map(|k| {
            let p = pair.c.point(TAU * k as f64 / n as f64);
            [p.x, p.y]
        })
        .collect();
    let m = ((n as f64) * ratio).ceil() as usize;
    let gear2_m = (0..m)
        .map(|k| {
            let al = TAU * ratio * k as f64 / m as f64;
            let r2 = pair.a - pair.c.rho1(al);
            let ang = PI - a2.alpha2(al);
            let p = o2 + P2::new(ang.cos(), ang.sin()) * r2;
            [p.x, p.y]
        })
        .collect();
    PitchCurves {
        center1_m: [0.0, 0.0],
        center2_m: [pair.a, 0.0],
        gear1_m,
        gear2_m,
    }
}
