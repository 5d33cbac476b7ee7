use super::*;

fn shapes() -> Vec<Shape> {
    vec![
        Shape::Disk,
        Shape::Square,
        Shape::Rectangle {
            width: 3.0,
            height: 0.5,
        },
        Shape::Ellipse { a: 2.0, b: 1.0 },
        Shape::Ellipse { a: 0.3, b: 1.7 },
        Shape::Ellipse { a: 1.0, b: 1.0 },
    ]
}

/// Distance of `p` from the shape's curve, measured by its implicit equation.
fn off_curve(shape: &Shape, p: [f64; 2]) -> f64 {
    match *shape {
        Shape::Disk => (p[0].hypot(p[1]) - 1.0).abs(),
        Shape::Square => ((p[0].abs().max(p[1].abs())) - 1.0).abs(),
        Shape::Rectangle { width, height } => {
            let (hx, hy) = (width / 2.0, height / 2.0);
            let inside = p[0].abs() <= hx + 1e-15 && p[1].abs() <= hy + 1e-15;
            let on_side = (p[0].abs() - hx).abs().min((p[1].abs() - hy).abs());
            if inside { on_side } else { f64::INFINITY }
        }
        Shape::Ellipse { a, b } => ((p[0] / a).powi(2) + (p[1] / b).powi(2) - 1.0).abs(),
    }
}

fn test_points() -> Vec<[f64; 2]> {
    let mut pts = vec![
        [0.0, 0.0],
        [1e-9, 0.0],
        [0.0, -1e-9],
        [5.0, 0.0],
        [0.0, 5.0],
        [-0.1, 0.0],
        [0.0, 0.2],
        [3.0, 3.0],
        [-1.0, 1.0],
        [1.0, -1.0],
    ];
    for k in 0..97 {
        let t = 0.37 + k as f64 * 0.731;
        let r = 0.05 + 0.04 * k as f64;
        pts.push([r * t.cos(), 0.8 * r * t.sin()]);
    }
    pts
}

#[test]
fn parse_accepts_the_documented_forms() {
    assert_eq!(Shape::parse("disk").unwrap(), Shape::Disk);
    assert_eq!(Shape::parse("Square").unwrap(), Shape::Square);
    assert_eq!(
        Shape::parse("rectangle:2:1.5").unwrap(),
        Shape::Rectangle {
            width: 2.0,
            height: 1.5
        }
    );
    assert_eq!(
        Shape::parse("ellipse:2:1").unwrap(),
        Shape::Ellipse { a: 2.0, b: 1.0 }
    );
}

#[test]
fn parse_rejects_slivers() {
    for bad in ["ellipse:1e300:1", "rectangle:1:2e3", "ellipse:1e-300:1"] {
        let e = Shape::parse(bad).unwrap_err().to_string();
        assert!(e.contains("too thin"), "{bad}: {e}");
    }
    assert!(Shape::parse("ellipse:1000:1").is_ok());
}

#[test]
fn parse_rejects_bad_input_with_clear_messages() {
    for bad in [
        "circle",
        "",
        "rectangle",
        "rectangle:1",
        "rectangle:1:2:3",
        "rectangle:0:1",
        "rectangle:-1:1",
        "ellipse:1:x",
        "ellipse:inf:1",
        "ellipse:NaN:1",
        "disk:1",
    ] {
        match Shape::parse(bad) {
            Err(Error::Argument(msg)) => {
                assert!(
                    msg.contains("disk, square, rectangle:W:H, ellipse:A:B"),
                    "{msg}"
                )
            }
            other => panic!("{bad:?} gave {other:?}"),
        }
    }
    let Err(Error::Argument(msg)) = Shape::parse("circle") else {
        panic!()
    };
    assert!(msg.contains("unknown shape 'circle'"));
    let Err(Error::Argument(msg)) = Shape::parse("rectangle:0:1") else {
        panic!()
    };
    assert!(msg.contains("W must be positive"), "{msg}");
}

#[test]
fn perimeters() {
    assert!((Shape::Disk.perimeter() - 2.0 * PI).abs() < 1e-15);
    assert_eq!(Shape::Square.perimeter(), 8.0);
    let r = Shape::Rectangle {
        width: 3.0,
        height: 0.5,
    };
    assert_eq!(r.perimeter(), 7.0);
    let e = Shape::Ellipse { a: 2.0, b: 1.0 };
    assert!((e.perimeter() - 9.688448220547675).abs() < 1e-13);
    let c = Shape::Ellipse { a: 1.5, b: 1.5 };
    assert!((c.perimeter() - 3.0 * PI).abs() < 1e-13);
}

#[test]
fn point_at_disk_and_rectangle() {
    let d = Shape::Disk;
    let p = d.point_at(0.0);
    assert!((p[0] - 1.0).abs() < 1e-15 && p[1].abs() < 1e-15);
    let p = d.point_at(0.25);
    assert!(p[0].abs() < 1e-15 && (p[1] - 1.0).abs() < 1e-15);
    let p = d.point_at(1.25);
    assert!(p[0].abs() < 1e-15 && (p[1] - 1.0).abs() < 1e-15);

    // Rectangle 4 x 2, perimeter 12: corners at fractions 1/12, 5/12, 7/12, 11/12.
    let r = Shape::Rectangle {
        width: 4.0,
        height: 2.0,
    };
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() + (p[1] - q[1]).abs() < 1e-12;
    assert!(close(r.point_at(0.0), [2.0, 0.0]));
    assert!(close(r.point_at(1.0 / 12.0), [2.0, 1.0]));
    assert!(close(r.point_at(5.0 / 12.0), [-2.0, 1.0]));
    assert!(close(r.point_at(7.0 / 12.0), [-2.0, -1.0]));
    assert!(close(r.point_at(11.0 / 12.0), [2.0, -1.0]));
    assert!(close(r.point_at(0.5), [-2.0, 0.0]));
    assert!(close(r.point_at(0.25), [0.0, 1.0]));
    assert!(close(Shape::Square.point_at(0.125), [1.0, 1.0]));
    assert!(close(r.point_at(1.0 - 1e-17), [2.0, 0.0]));
}

#[test]
fn point_at_ellipse_uses_true_arclength() {
    let e = Shape::Ellipse { a: 2.0, b: 1.0 };
    let p = e.point_at(0.0);
    assert!((p[0] - 2.0).abs() < 1e-14 && p[1].abs() < 1e-14);
    // Quarter points by symmetry.
    for (t, q) in [(0.25, [0.0, 1.0]), (0.5, [-2.0, 0.0]), (0.75, [0.0, -1.0])] {
        let p = e.point_at(t);
        assert!(
            (p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12,
            "{t}: {p:?}"
        );
    }
    // Equal arclength steps: consecutive chords are nearly equal (they differ from the arc
    // by at most arc³κ²/24, κ ≤ a/b² = 2).
    let n = 1000;
    let pts: Vec<[f64; 2]> = (0..n).map(|k| e.point_at(k as f64 / n as f64)).collect();
    let step = e.perimeter() / n as f64;
    for k in 0..n {
        let (p, q) = (pts[k], pts[(k + 1) % n]);
        let chord = (q[0] - p[0]).hypot(q[1] - p[1]);
        assert!(chord <= step && chord > step - step.powi(3) * 4.0 / 24.0 * 1.01);
    }
    for p in &pts {
        assert!(off_curve(&e, *p) < 1e-14);
    }
    // The arclength up to point_at(t), by a fine independent Simpson rule, is t·perimeter.
    let speed = |tau: f64| (2.0 * tau.sin()).hypot(tau.cos());
    for t in [0.01, 0.1, 0.2, 0.3, 0.37, 0.6, 0.9] {
        let p = e.point_at(t);
        let tau = (p[1] / 1.0).atan2(p[0] / 2.0).rem_euclid(2.0 * PI);
        let m = 20000;
        let h = tau / m as f64;
        let mut s = speed(0.0) + speed(tau);
        for i in 1..m {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * speed(i as f64 * h);
        }
        s *= h / 3.0;
        assert!((s - t * e.perimeter()).abs() < 1e-11, "{t}: {s}");
    }
}

#[test]
fn boundary_positions_follow_cumulative_length() {
    let lengths = [1.0, 2.0, 1.0, 4.0];
    for shape in shapes() {
        let pos = shape.boundary_positions(&lengths);
        assert_eq!(pos.len(), 4);
        for (p, t) in pos.iter().zip([0.0, 0.125, 0.375, 0.5]) {
            let q = shape.point_at(t);
            assert!((p[0] - q[0]).abs() < 1e-14 && (p[1] - q[1]).abs() < 1e-14);
        }
    }
    let pos = Shape::Disk.boundary_positions(&[0.0; 4]);
    assert!((pos[1][0]).abs() < 1e-15 && (pos[1][1] - 1.0).abs() < 1e-15);
    assert!(Shape::Disk.boundary_positions(&[]).is_empty());
}

#[test]
fn projection_lands_on_the_curve_and_is_idempotent() {
    for shape in shapes() {
        for p in test_points() {
            let q = shape.project(p);
            assert!(off_curve(&shape, q) < 1e-12, "{shape:?} {p:?} -> {q:?}");
            let qq = shape.project(q);
            assert!(
                (qq[0] - q[0]).abs() < 1e-12 && (qq[1] - q[1]).abs() < 1e-12,
                "{shape:?}: {q:?} -> {qq:?}"
            );
        }
        for k in 0..50 {
            let q = shape.point_at(k as f64 / 50.0);
            let qq = shape.project(q);
            assert!((qq[0] - q[0]).abs() < 1e-12 && (qq[1] - q[1]).abs() < 1e-12);
        }
    }
}

#[test]
fn projection_is_the_nearest_point() {
    // Compare against a dense sampling of the curve.
    for shape in shapes() {
        let samples: Vec<[f64; 2]> = (0..20000)
            .map(|k| shape.point_at(k as f64 / 20000.0))
            .collect();
        for p in test_points() {
            let q = shape.project(p);
            let d = (q[0] - p[0]).hypot(q[1] - p[1]);
            let dmin = samples
                .iter()
                .map(|s| (s[0] - p[0]).hypot(s[1] - p[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= dmin + 1e-12, "{shape:?} {p:?}: {d} > {dmin}");
            assert!(d >= dmin - 1e-3, "{shape:?} {p:?}: {d} << {dmin}");
        }
    }
}

#[test]
fn projection_special_cases() {
    assert_eq!(Shape::Disk.project([0.0, 0.0]), [1.0, 0.0]);
    assert_eq!(Shape::Disk.project([0.0, -3.0]), [0.0, -1.0]);
    let r = Shape::Rectangle {
        width: 4.0,
        height: 2.0,
    };
    assert_eq!(r.project([5.0, 7.0]), [2.0, 1.0]);
    assert_eq!(r.project([-5.0, 0.3]), [-2.0, 0.3]);
    assert_eq!(r.project([0.5, 0.2]), [0.5, 1.0]);
    assert_eq!(r.project([1.9, -0.5]), [2.0, -0.5]);
    assert_eq!(r.project([2.0, 1.0]), [2.0, 1.0]);
    let e = Shape::Ellipse { a: 2.0, b: 1.0 };
    assert_eq!(e.project([5.0, 0.0]), [2.0, 0.0]);
    assert_eq!(e.project([0.0, -0.5]), [0.0, -1.0]);
    // Inside on the major axis near the centre: the nearest points are at the top/bottom.
    let q = e.project([0.1, 0.0]);
    assert!((q[0] - 2.0 * 0.1 * 2.0 / 3.0).abs() < 1e-14, "{q:?}");
}
