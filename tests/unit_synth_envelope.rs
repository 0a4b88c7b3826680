//! `synth::envelope` (`src/synth/envelope.rs`): the box's vertices, the worst case and the
//! sensitivity table's arithmetic. Moved from the source file's `#[cfg(test)]` module, which
//! never ran (the library has no unit-test harness: `lib test = false`).

use cwsynth::synth::envelope::{
    central_slopes, sensitivities, vertex_slopes, vertices, worst, Dependence, End, Slope,
};
use cwsynth::synth::minimax::Multiplier;

#[test]
fn vertices_are_in_binary_order() {
    let v = vertices(&[(0.0, 1.0), (2.0, 3.0)]);
    assert_eq!(
        v,
        vec![vec![0., 2.], vec![1., 2.], vec![0., 3.], vec![1., 3.]]
    );
    assert_eq!(vertices(&[]), vec![Vec::<f64>::new()]);
}

#[test]
fn the_worst_is_the_first_largest() {
    let w = worst([(1.0, 0.1), (3.0, 0.2), (3.0, 0.3), (2.0, 0.1)]).unwrap();
    assert_eq!((w.value, w.error, w.vertex), (3.0, 0.2, 1));
}

/// A quadratic field's slope is exact but for its evaluations' errors at any step (here the
/// 2-D field (3v² + v, v²): |g|′ = ĝ·g′); a cubic's truncation shows in the general error,
/// which covers it.
#[test]
fn central_slopes_are_exact_for_quadratics_and_cover_a_cubic() {
    let f = |v: f64| {
        Ok::<_, ()>(vec![
            ([3.0 * v * v + v, v * v], 1e-12),
            ([v * v * v, 0.0], 0.0),
        ])
    };
    let q = central_slopes(2.0, 0.5, Dependence::Quadratic, f).unwrap();
    let (g, dg) = ([14.0, 4.0], [13.0, 4.0]);
    let want = (g[0] * dg[0] + g[1] * dg[1]) / f64::hypot(g[0], g[1]);
    assert!(
        (q[0].value - want).abs() <= q[0].error && q[0].error < 1e-10,
        "{q:?}"
    );
    let c = central_slopes(2.0, 1e-4, Dependence::General, f).unwrap();
    assert!((c[1].value - 12.0).abs() <= c[1].error, "{c:?}");
    assert!(c[1].error < 1e-6, "{c:?}");
}

/// A figure affine in a mass m, g = (2 + 3m, 1 − m), and one affine in ω², g = (5 + ω², 2ω²):
/// the slope from a vertex and its partner equals the derivative at the vertex, at either
/// end, within its stated error, which is round-off sized.
#[test]
fn vertex_slopes_are_exact_for_figures_affine_in_a_mass_or_in_the_speeds_square() {
    let mass = |m: f64| ([2.0 + 3.0 * m, 1.0 - m], 1e-13);
    let speed = |w: f64| ([5.0 + w * w, 2.0 * w * w], 1e-12);
    let slope_of = |g: [f64; 2], dg: [f64; 2]| (g[0] * dg[0] + g[1] * dg[1]) / g[0].hypot(g[1]);
    for (at, to) in [(0.5, 0.7), (0.7, 0.5)] {
        let s = vertex_slopes(at, to, false, &[mass(at)], &[mass(to)]);
        let want = slope_of(mass(at).0, [3.0, -1.0]);
        assert!((s[0].value - want).abs() <= s[0].error, "{s:?} {want}");
        assert!(s[0].error < 1e-11, "{s:?}");
    }
    for (at, to) in [(80.0, 120.0), (120.0, 80.0)] {
        let s = vertex_slopes(at, to, true, &[speed(at)], &[speed(to)]);
        let want = slope_of(speed(at).0, [2.0 * at, 4.0 * at]);
        assert!((s[0].value - want).abs() <= s[0].error, "{s:?} {want}");
        assert!(s[0].error < 1e-9 * want.abs(), "{s:?}");
    }
}

/// Two parameters, stride 1 (one field per scenario): the nominal scene (field 0) is at no
/// end; vertex k − 1 = field k has parameter i at its upper end where bit i of k − 1 is set.
#[test]
fn each_end_sums_the_multipliers_of_the_vertices_at_it() {
    let m = |field, weight| Multiplier {
        field,
        angle: 0.0,
        weight,
        weight_error: 0.01 * weight,
        limit: false,
    };
    // Fields 1..=4: vertices (lo, lo), (hi, lo), (lo, hi), (hi, hi).
    let mults = [m(0, 0.5), m(2, 0.25), m(4, 0.25)];
    let names = ["a".to_string(), "b".to_string()];
    let rows = sensitivities::<()>(&names, &[(0.0, 1.0), (5.0, 6.0)], 1, &mults, |k, i, ms| {
        assert!(ms.iter().all(|m| m.field == k));
        Ok(ms
            .iter()
            .map(|m| Slope {
                value: (m.field * 10 + i) as f64,
                error: 1e-3,
            })
            .collect())
    })
    .unwrap();
    let d: Vec<(End, f64)> = rows.iter().map(|r| (r.end, r.derivative)).collect();
    assert_eq!(
        d,
        vec![
            (End::Min, 0.0),
            (End::Max, 0.25 * 20.0 + 0.25 * 40.0),
            (End::Min, 0.25 * 21.0),
            (End::Max, 0.25 * 41.0),
        ]
    );
    let want = 0.25 * 1e-3 + 0.0025 * 41.0;
    assert!((rows[3].error - want).abs() < 1e-15, "{}", rows[3].error);
    assert_eq!((rows[1].at, rows[2].at), (1.0, 5.0));
}

#[test]
fn the_scenarios_a_worst_case_needs_leave_out_only_dominated_ones() {
    use cwsynth::synth::envelope::needed_scenarios;
    // ω ∈ [80, 120], two masses: the nominal (100, 0, 0) is inside the box.
    let r = [(80.0, 120.0), (-0.1, 0.1), (-0.2, 0.2)];
    let nominal = [100.0, 0.0, 0.0];
    // Inertial fields (∝ ω²): the vertices at the top speed alone (bit 0 set).
    assert_eq!(
        needed_scenarios(&r, &nominal, 3, true, true),
        vec![2, 4, 6, 8]
    );
    // A weight or a process load in a field: every vertex, the nominal still dominated.
    assert_eq!(
        needed_scenarios(&r, &nominal, 3, true, false),
        (1..=8).collect::<Vec<_>>()
    );
    // A length (parameter 2 general): the nominal is needed too.
    assert_eq!(
        needed_scenarios(&r, &nominal, 2, true, true),
        vec![0, 2, 4, 6, 8]
    );
    // A nominal outside the box (a mass interval not containing 0) is needed.
    let off = [(80.0, 120.0), (0.1, 0.3)];
    assert_eq!(
        needed_scenarios(&off, &[100.0, 0.0], 2, true, true),
        vec![0, 2, 4]
    );
    // No speed interval: the masses' vertices, whatever the fields.
    assert_eq!(
        needed_scenarios(&r[1..], &nominal[1..], 2, false, true),
        vec![1, 2, 3, 4]
    );
}
