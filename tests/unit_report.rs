//! `report` (`src/report/`): drawings as SVG and DXF (`drawing.rs`), tick labels and plots
//! (`plot.rs`), result structs as number maps (`numbers.rs`), Markdown as an HTML page
//! (`page.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/report/drawing.rs`.
mod drawing {
    use cwsynth::geom::P2;
    use cwsynth::report::drawing::{readable, Drawing, DrawingError, Layer, Shape, Sheet};
    use std::f64::consts::PI;

    fn plate() -> Drawing {
        let mut d = Drawing::new("test plate");
        let c = P2::zeros();
        d.add(
            Layer::Outline,
            Shape::Arc {
                centre: c,
                radius: 0.2,
                start_rad: 0.5,
                end_rad: 2.5,
            },
        )
        .add(Layer::Centre, Shape::CentreMark { at: c })
        .add(
            Layer::Dim,
            Shape::Radius {
                centre: c,
                radius: 0.2,
                angle_rad: 1.0,
                label: "R".into(),
            },
        )
        .add(
            Layer::Dim,
            Shape::Linear {
                a: P2::new(-0.1, -0.05),
                b: P2::new(0.1, -0.05),
                offset: -0.03,
                label: "a".into(),
            },
        )
        .add(
            Layer::Dim,
            Shape::Angle {
                centre: c,
                from: 0.21,
                radius: 0.25,
                start_rad: 0.5,
                end_rad: 2.5,
                label: "θ".into(),
            },
        );
        d.note("thickness 10 mm");
        d
    }

    #[test]
    fn svg_has_equal_scales_and_the_texts() {
        let s = plate().svg().unwrap();
        let attr = |name: &str| -> String {
            let i = s.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            s[i..i + s[i..].find('"').unwrap()].to_string()
        };
        let (w, h): (f64, f64) = (
            attr("width").parse().unwrap(),
            attr("height").parse().unwrap(),
        );
        let vb: Vec<f64> = attr("viewBox")
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        assert!(((w / vb[2]) / (h / vb[3]) - 1.0).abs() < 1e-12, "{s}");
        assert!(s.contains("R = 200.00"), "{s}");
        assert!(s.contains("a = 200.00"), "{s}");
        assert!(s.contains("θ = 114.59°"), "{s}");
        assert!(s.contains("thickness 10 mm"));
    }

    #[test]
    fn dxf_is_millimetres_and_repeatable() {
        let a = plate().dxf().unwrap();
        let b = plate().dxf().unwrap();
        assert_eq!(a, b);
        let d = dxf::Drawing::load(&mut a.as_slice()).unwrap();
        assert_eq!(
            d.header.default_drawing_units,
            dxf::enums::Units::Millimeters
        );
        let arcs: Vec<f64> = d
            .entities()
            .filter(|e| e.common.layer == "OUTLINE")
            .filter_map(|e| match &e.specific {
                dxf::entities::EntityType::Arc(a) => Some(a.radius),
                _ => None,
            })
            .collect();
        assert_eq!(arcs, vec![200.0]);
    }

    #[test]
    fn nothing_to_draw_is_an_error_and_the_files_say_why() {
        let d = Drawing::new("empty");
        assert!(matches!(d.svg(), Err(DrawingError::Data(_))));
        let sheet = Sheet::new("drawing", "empty", || Ok(Drawing::new("empty")));
        let (dxf, svg) = sheet.files();
        assert!(String::from_utf8(svg).unwrap().contains("drawing not made"));
        assert!(String::from_utf8(dxf).unwrap().contains("drawing not made"));
    }

    #[test]
    fn readable_angles() {
        assert!((readable(PI) - 0.0).abs() < 1e-12);
        assert!((readable(0.75 * PI) + 0.25 * PI).abs() < 1e-12);
        assert!((readable(-0.5 * PI) - 0.5 * PI).abs() < 1e-12);
    }
}

/// The former unit tests of `src/report/plot.rs`.
mod plot {
    use cwsynth::report::plot::{
        heat_map, panels, peak_label_box, tick, tick_on, Figure, Grid, Panel, Series,
    };

    /// A peak's label: right of its point where it fits, else left, else as far right as the
    /// area lets it start; below a point in the upper half, above one in the lower half; a
    /// line further where it would cover a placed box, never out of the area.
    #[test]
    fn a_peak_label_sits_beside_its_point_inside_the_area_and_clear_of_others() {
        let area = [0.0, 0.0, 400.0, 300.0];
        let (size, gap) = ((100.0, 15.0), 9.0);
        let inside = |b: [f64; 4]| b[0] >= 0.0 && b[1] >= 0.0 && b[2] <= 400.0 && b[3] <= 300.0;
        // Room on the right, in the lower half: right of it and above.
        let b = peak_label_box((50.0, 200.0), size, area, &[], gap);
        assert_eq!(b, [59.0, 176.0, 159.0, 191.0]);
        // At the right edge, in the upper half: left of it and below.
        let b = peak_label_box((390.0, 20.0), size, area, &[], gap);
        assert_eq!(b, [281.0, 29.0, 381.0, 44.0]);
        // Too wide for either side: as far right as it can start, inside.
        let b = peak_label_box((200.0, 250.0), (350.0, 15.0), area, &[], gap);
        assert_eq!((b[0], b[2]), (50.0, 400.0));
        assert!(inside(b));
        // A placed box where it would go: a line further down (below a high point).
        let first = peak_label_box((390.0, 20.0), size, area, &[], gap);
        let second = peak_label_box((390.0, 25.0), size, area, &[first], gap);
        assert!(second[1] >= first[3], "{first:?} {second:?}");
        // Never out of the area, even when every line is taken.
        let taken: Vec<[f64; 4]> = (0..30)
            .map(|k| [0.0, 10.0 * k as f64, 400.0, 10.0 * k as f64 + 10.0])
            .collect();
        assert!(inside(peak_label_box(
            (390.0, 290.0),
            size,
            area,
            &taken,
            gap
        )));
    }

    /// A panel as `/api/report` sends it: a non-finite coordinate as null, each style by
    /// name, an x axis in degrees marked as the mechanism's angle.
    #[test]
    fn a_panel_is_its_json() {
        let p = Panel {
            title: "t".into(),
            x_label: "crank angle θ (deg)".into(),
            y_label: "|F| (N)".into(),
            series: vec![
                Series::line(
                    "bare",
                    vec![(0.0, 1.5), (f64::NAN, 2.0), (360.0, f64::INFINITY)],
                ),
                Series::peak("peak 2 N", vec![(90.0, 2.0)]),
            ],
            equal_aspect: false,
        };
        let v = p.to_json();
        assert_eq!(v["angle_x"], true);
        assert_eq!(v["series"][0]["x"], serde_json::json!([0.0, null, 360.0]));
        assert_eq!(v["series"][0]["y"], serde_json::json!([1.5, 2.0, null]));
        assert_eq!(v["series"][1]["style"], "peak");
        for (label, angle) in [
            ("α1, angle of gear 1 (deg)", true),
            ("φ (°)", true),
            ("x (mm)", false),
            ("speed (rpm)", false),
        ] {
            let q = Panel {
                x_label: label.into(),
                ..p.clone()
            };
            assert_eq!(q.x_is_angle(), angle, "{label}");
        }
        // A figure's labels name their units, as its SVG's must.
        let bare = Panel {
            y_label: "|F|".into(),
            ..p.clone()
        };
        assert!(Figure::new(vec![bare], 400, 300).is_err());
        let f = Figure::new(vec![p], 400, 300).unwrap();
        assert_eq!(f.to_json()["width"], 400);
        assert_eq!(f.svg().unwrap(), panels(&f.panels, 400, 300).unwrap());
    }

    #[test]
    fn ticks_are_the_shortest_decimal() {
        for (v, want) in [
            (600.0, "600"),
            (-0.0, "0"),
            (0.25, "0.25"),
            (-2.5, "-2.5"),
            (1.5e-7, "1.5e-7"),
            (123456789.0, "1.23457e8"),
            (0.1 + 0.2, "0.3"),
            (1e-5, "1e-5"),
            (2e-4, "0.0002"),
        ] {
            assert_eq!(tick(&v), want, "{v}");
        }
        assert_eq!(tick_on(5.551115123125783e-17, 1.0), "0");
    }

    #[test]
    fn writes_an_svg_with_every_series_name() {
        let p = Panel {
            title: "t".into(),
            x_label: "x (m)".into(),
            y_label: "y (m)".into(),
            series: vec![
                Series::line(
                    "curve",
                    vec![
                        (0.0, 0.0),
                        (1.0, 1.0),
                        (f64::NAN, 0.0),
                        (2.0, 0.0),
                        (3.0, 1.0),
                    ],
                ),
                Series::marker("optimum", vec![(1.0, 1.0)]),
            ],
            equal_aspect: true,
        };
        let svg = panels(std::slice::from_ref(&p), 400, 300).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("curve") && svg.contains("optimum"));
        let g = Grid {
            x: vec![0.0, 1.0, 2.0],
            y: vec![0.0, 1.0],
            values: vec![vec![1.0, f64::NAN, 3.0], vec![-1.0, 0.0, 2.0]],
        };
        let svg = heat_map(&p, &g, Some(1.0), 400, 300).unwrap();
        assert!(svg.contains("<rect") && svg.contains("optimum"));
    }
}

/// The former unit tests of `src/report/numbers.rs`.
mod numbers {
    use cwsynth::key;
    use cwsynth::report::numbers::{declared_keys, number_map, try_number_map};

    use serde::Serialize;

    #[derive(Serialize)]
    struct Inner {
        /// A length (m).
        c_m: f64,
    }

    #[derive(Serialize)]
    struct Outer {
        /// A force (N).
        a_n: f64,
        /// An optional count.
        #[serde(skip_serializing_if = "Option::is_none")]
        b: Option<usize>,
        /// Left out when `None`.
        d: Option<f64>,
        #[serde(flatten)]
        inner: Inner,
    }

    #[test]
    fn fields_become_keys_with_inf_and_nan_kept() {
        let v = Outer {
            a_n: f64::INFINITY,
            b: Some(3),
            d: None,
            inner: Inner { c_m: f64::NAN },
        };
        let m = number_map(&v);
        assert_eq!(m.keys().collect::<Vec<_>>(), ["a_n", "b", "c_m"]);
        assert!(m["a_n"].is_infinite() && m["c_m"].is_nan());
        assert_eq!(m["b"], 3.0);
        assert_eq!(declared_keys(&v), ["a_n", "b", "d", "c_m"]);
        assert_eq!(key!("derived", Inner, c_m), "derived.c_m");
        assert_eq!(key!(Outer, a_n), "a_n");
    }

    #[test]
    fn a_string_field_is_refused() {
        #[derive(Serialize)]
        struct S {
            s: &'static str,
        }
        assert!(try_number_map(&S { s: "x" }).is_err());
    }
}

/// The former unit tests of `src/report/page.rs`.
mod page {
    use cwsynth::report::page::{document, markdown_html};
    use maud::html;

    /// Markdown tables and images become HTML; raw HTML and entities stay text.
    #[test]
    fn markdown_becomes_html_and_raw_html_stays_text() {
        let h = markdown_html(
            "# T\n\n| a | b |\n|---|---|\n| 1 | &lt;b&gt; |\n\n<script>x</script>\n\n![c](p.svg)\n\ninline <i>i</i>\n",
        );
        assert!(
            h.contains("<table>") && h.contains("<td>&lt;b&gt;</td>"),
            "{h}"
        );
        assert!(h.contains("<img src=\"p.svg\" alt=\"c\""), "{h}");
        assert!(!h.contains("<script") && !h.contains("<i>"), "{h}");
        let page = document("a <b>", "", html! { p { "x < y" } });
        assert!(page.contains("<title>a &lt;b&gt;</title>") && page.contains("x &lt; y"));
    }
}
