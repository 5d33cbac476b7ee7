//! End-to-end tests of `demkit map --method edem|edeq` (Lyu, Lui & Choi 2026) on surfaces the
//! tests make themselves: icospheres stretched into ellipsoids, with and without populations,
//! onto their own ellipsoid and onto others; the report's domain and radii; the refusals of
//! bad radii and of surfaces that are not genus-0 closed; remesh and render of the maps.

mod common;

use common::{Scratch, json_file, parse_obj};

/// `demkit generate icosphere` with `subdivisions`, its points scaled by `radii` per axis,
/// written to `name`.
fn stretched_icosphere(s: &Scratch, name: &str, subdivisions: &str, radii: [f64; 3]) {
    s.generate(&[
        "icosphere",
        "--subdivisions",
        subdivisions,
        "--out",
        "unit.obj",
    ]);
    let (mesh, _) = parse_obj(&s.read("unit.obj"));
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!(
            "v {} {} {}\n",
            p[0] * radii[0],
            p[1] * radii[1],
            p[2] * radii[2]
        );
    }
    for f in &mesh.faces {
        text += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    s.write(name, text);
}

/// The largest relative residual |x²/a² + y²/b² + z²/c² − 1| of the points of `obj`.
fn residual(s: &Scratch, obj: &str, r: [f64; 3]) -> f64 {
    let (mesh, _) = parse_obj(&s.read(obj));
    mesh.positions
        .iter()
        .map(|p| {
            ((p[0] / r[0]).powi(2) + (p[1] / r[1]).powi(2) + (p[2] / r[2]).powi(2) - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

fn radii_of(report: &serde_json::Value) -> [f64; 3] {
    let r = report["radii"].as_array().expect("radii in the report");
    [0, 1, 2].map(|i| r[i].as_f64().unwrap())
}

#[test]
fn edem_equalizes_a_population_on_the_surfaces_own_ellipsoid() {
    // An ellipsoid 1:1.5:2.5 with a population growing towards its ends: it is its own initial
    // map, and EDEM moves it on the ellipsoid until the density is flat.
    let s = Scratch::new("edem_own");
    stretched_icosphere(&s, "e.obj", "4", [1.0, 1.5, 2.5]);
    s.ok(&[
        "map",
        "e.obj",
        "--method",
        "edem",
        "--ellipsoid",
        "1:1.5:2.5",
        "--population",
        "area*(1+z*z)",
        "--out",
        "o.obj",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let r = json_file(&s.path("r.json"));
    assert_eq!(r["method"], "edem");
    assert_eq!(r["domain"], "ellipsoid");
    assert_eq!(r["converged"], true);
    assert_eq!(radii_of(&r), [1.0, 1.5, 2.5]);
    let m = &r["metrics"];
    assert_eq!(m["flipped_triangles"], 0);
    let (initial, last) = (
        m["face_density_var_initial"].as_f64().unwrap(),
        m["face_density_var_final"].as_f64().unwrap(),
    );
    assert!(
        initial > 0.1 && last < 0.01 * initial,
        "{initial} -> {last}"
    );
    assert!(m["density_error_mean"].as_f64().unwrap() < 0.02, "{m}");
    assert!(residual(&s, "o.obj", [1.0, 1.5, 2.5]) <= 1e-9);
    let (_, in_faces) = parse_obj(&s.read("e.obj"));
    let (_, out_faces) = parse_obj(&s.read("o.obj"));
    assert_eq!(in_faces, out_faces);
}

#[test]
fn edem_maps_a_surface_onto_an_ellipsoid_of_other_proportions() {
    // A sphere onto 2:1:3 and an ellipsoid onto a sphere-like 1:1.2:0.8, both by area: the
    // ellipsoidal conformal map first, then the flow; every point on the target.
    let s = Scratch::new("edem_other");
    stretched_icosphere(&s, "a.obj", "4", [1.0, 1.0, 1.0]);
    stretched_icosphere(&s, "b.obj", "4", [1.0, 1.0, 2.0]);
    for (mesh, radii, r3) in [
        ("a.obj", "2:1:3", [2.0, 1.0, 3.0]),
        ("b.obj", "1:1.2:0.8", [1.0, 1.2, 0.8]),
    ] {
        let (out, report) = (format!("o-{mesh}"), format!("{mesh}.json"));
        s.ok(&[
            "map",
            mesh,
            "--method",
            "edem",
            "--ellipsoid",
            radii,
            "--out",
            &out,
            "--report",
            &report,
            "--quiet",
        ]);
        let r = json_file(&s.path(&report));
        let m = &r["metrics"];
        assert_eq!(m["flipped_triangles"], 0, "{mesh} onto {radii}");
        assert!(
            m["density_error_mean"].as_f64().unwrap() < 0.05,
            "{mesh}: {m}"
        );
        assert!(residual(&s, &out, r3) <= 1e-9);
    }
}

#[test]
fn a_unit_sphere_as_ellipsoid_gives_sdems_accuracy() {
    let s = Scratch::new("edem_sphere");
    stretched_icosphere(&s, "e.obj", "4", [1.0, 1.3, 1.7]);
    let error = |method: &str, extra: &[&str]| -> f64 {
        let mut args = vec![
            "map",
            "e.obj",
            "--method",
            method,
            "--population",
            "area*(2+x)",
            "--out",
        ];
        let out = format!("{method}.obj");
        let report = format!("{method}.json");
        args.extend_from_slice(&[&out, "--report", &report, "--quiet"]);
        args.extend_from_slice(extra);
        s.ok(&args);
        let r = json_file(&s.path(&report));
        assert_eq!(r["metrics"]["flipped_triangles"], 0);
        r["metrics"]["density_error_mean"].as_f64().unwrap()
    };
    let sdem = error("sdem", &[]);
    let edem = error("edem", &["--ellipsoid", "1:1:1"]);
    assert!(
        edem <= 1.05 * sdem + 1e-4,
        "edem {edem} against sdem {sdem}"
    );
    assert!(residual(&s, "edem.obj", [1.0; 3]) <= 1e-9);
}

#[test]
fn edeq_chooses_radii_near_a_stretched_spheres_own() {
    // By area from the guess 1:1:1, the least distorted ellipsoid is the surface's own shape.
    let s = Scratch::new("edeq_stretched");
    stretched_icosphere(&s, "e.obj", "4", [1.0, 1.3, 1.8]);
    s.ok(&[
        "map",
        "e.obj",
        "--method",
        "edeq",
        "--ellipsoid",
        "1:1:1",
        "--out",
        "o.obj",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let r = json_file(&s.path("r.json"));
    assert_eq!(r["method"], "edeq");
    assert_eq!(r["domain"], "ellipsoid");
    let [a, b, c] = radii_of(&r);
    assert_eq!(a, 1.0);
    assert!(
        (b - 1.3).abs() < 0.1 && (c - 1.8).abs() < 0.15,
        "{a}:{b}:{c}"
    );
    assert_eq!(r["metrics"]["flipped_triangles"], 0);
    assert!(residual(&s, "o.obj", [a, b, c]) <= 1e-9);
    // Without a guess the enclosed solid's proportions are the start.
    s.ok(&[
        "map", "e.obj", "--method", "edeq", "--out", "p.obj", "--report", "p.json", "--quiet",
    ]);
    let [_, b, c] = radii_of(&json_file(&s.path("p.json")));
    assert!((b - 1.3).abs() < 0.1 && (c - 1.8).abs() < 0.15, "1:{b}:{c}");
}

#[test]
fn bad_radii_are_refused_before_any_work() {
    let s = Scratch::new("edem_radii");
    stretched_icosphere(&s, "e.obj", "2", [1.0, 1.0, 1.0]);
    for bad in [
        "0:1:1",
        "-1:1:1",
        "1:nan:1",
        "1:1:inf",
        "1:1",
        "1:2:3:4",
        "a:b:c",
        "1:1:1e300",
        "1e-300:1:1",
    ] {
        for method in ["edem", "edeq"] {
            s.run(&[
                "map",
                "e.obj",
                "--method",
                method,
                "--ellipsoid",
                bad,
                "--out",
                "o.obj",
            ])
            .input_error_naming(&["--ellipsoid"]);
        }
    }
    s.run(&["map", "e.obj", "--method", "edem", "--out", "o.obj"])
        .input_error_naming(&["--ellipsoid"]);
    s.run(&[
        "map", "e.obj", "--method", "edeq", "--alpha", "-1", "--out", "o.obj",
    ])
    .input_error_naming(&["alpha"]);
    assert!(!s.path("o.obj").exists());
}

#[test]
fn only_genus_0_closed_surfaces_are_mapped_onto_an_ellipsoid() {
    let s = Scratch::new("edem_topology");
    s.generate(&["torus", "--R", "3", "--r", "1", "--out", "t.obj"]);
    s.generate(&["peaks", "--n", "8", "--out", "p.obj"]);
    for mesh in ["t.obj", "p.obj"] {
        for method in ["edem", "edeq"] {
            s.run(&[
                "map",
                mesh,
                "--method",
                method,
                "--ellipsoid",
                "1:1:2",
                "--out",
                "o.obj",
            ])
            .input_error_naming(&[method, "genus-0"]);
        }
    }
}

#[test]
fn an_ellipsoidal_map_is_remeshed_and_rendered() {
    let s = Scratch::new("edem_remesh");
    stretched_icosphere(&s, "e.obj", "3", [1.0, 1.0, 2.0]);
    s.ok(&[
        "remesh",
        "e.obj",
        "--method",
        "edem",
        "--ellipsoid",
        "1:1:2",
        "--vertices",
        "300",
        "--out",
        "n.obj",
        "--quiet",
    ]);
    let (mesh, _) = parse_obj(&s.read("n.obj"));
    assert!(mesh.positions.len() > 200 && mesh.faces.len() > 400);
    s.ok(&[
        "map",
        "e.obj",
        "--method",
        "edem",
        "--ellipsoid",
        "1:1:2",
        "--out",
        "o.obj",
        "--quiet",
    ]);
    s.ok(&["render", "o.obj", "--out", "o.png", "--size", "128"]);
    assert!(s.read_bytes("o.png").starts_with(b"\x89PNG"));
    // The ellipsoid is no plane: a uv output is refused.
    s.run(&[
        "map",
        "e.obj",
        "--method",
        "edem",
        "--ellipsoid",
        "1:1:2",
        "--out",
        "u.obj",
        "--uv-out",
        "u2.obj",
    ])
    .input_error();
}
