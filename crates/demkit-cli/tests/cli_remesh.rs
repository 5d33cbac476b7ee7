//! End-to-end tests of `demkit remesh` (DEM paper §6.2, SDEM paper §5.2, DEQ paper §7.1, TDEM
//! paper §5) on generated surfaces of every kind: the vertex count, the topology, the new
//! vertices on the input surface, the triangles' shapes, the density driven by the population,
//! the report, and the refusals.

mod common;

use common::{Scratch, parse_obj};
use demkit::TriMesh;
use demkit::apps::remesh::quality::{max_distance_to_surface, quality};
use demkit::mesh::topology::topology;

fn read(s: &Scratch, name: &str) -> TriMesh {
    let (m, _) = parse_obj(&s.read(name));
    TriMesh::new(
        m.positions,
        m.faces.iter().map(|f| f.map(|v| v as u32)).collect(),
    )
}

/// Remeshes `input` (in the scratch directory) with `extra` arguments to about `n` vertices
/// and checks the count (±10 %), the topology, the distance to the input surface (≤ 1e-6 of
/// its diagonal), area CV ≤ 0.5 and median smallest angle ≥ 35°; returns the new mesh.
fn check_remesh(
    s: &Scratch,
    input: &str,
    n: usize,
    extra: &[&str],
    boundaries: usize,
    genus: i64,
) -> TriMesh {
    let ns = n.to_string();
    let mut args = vec![
        "remesh",
        input,
        "--out",
        "r.obj",
        "--vertices",
        &ns,
        "--quiet",
    ];
    args.extend_from_slice(extra);
    s.ok(&args);
    let before = read(s, input);
    let out = read(s, "r.obj");
    let off = (out.n_vertices() as f64 - n as f64).abs() / n as f64;
    assert!(off <= 0.1, "{input}: {} vertices for {n}", out.n_vertices());
    let t = topology(&out);
    assert_eq!(t.n_vertices, out.n_vertices(), "{input}: unused vertices");
    assert_eq!(
        (t.boundary_loops.len(), t.genus, t.components),
        (boundaries, genus, 1),
        "{input}"
    );
    assert!(demkit::mesh::check(&out).is_valid(), "{input}");
    let diag = demkit::geometry::bounding_box_diagonal(&before.positions);
    let dist = max_distance_to_surface(&out.positions, &before, 1e-6 * diag);
    assert!(dist <= 1e-6 * diag, "{input}: {dist}");
    let q = quality(&out);
    assert!(q.area_cv <= 0.5, "{input}: {q:?}");
    assert!(q.median_min_angle_deg >= 35.0, "{input}: {q:?}");
    out
}

#[test]
fn a_polygon_becomes_an_even_disk() {
    let s = Scratch::new("remesh_polygon");
    s.generate(&["polygon", "--sides", "6", "--rings", "16", "--out", "p.obj"]);
    let out = check_remesh(&s, "p.obj", 600, &[], 1, 0);
    // Flat input, flat output.
    assert!(out.positions.iter().all(|p| p[2].abs() < 1e-12));
}

#[test]
fn a_height_field_becomes_an_even_disk_on_its_surface() {
    let s = Scratch::new("remesh_peaks");
    s.generate(&["peaks", "--n", "30", "--out", "p.obj"]);
    check_remesh(&s, "p.obj", 1500, &[], 1, 0);
}

#[test]
fn holes_stay_holes() {
    let s = Scratch::new("remesh_holes");
    s.generate(&[
        "disk-holes",
        "--hole",
        "0.4:0:0.2",
        "--hole",
        "-0.4:0.1:0.15",
        "--resolution",
        "40",
        "--out",
        "h.obj",
    ]);
    check_remesh(&s, "h.obj", 1000, &[], 3, 0);
}

#[test]
fn an_icosphere_becomes_an_even_sphere() {
    let s = Scratch::new("remesh_sphere");
    s.generate(&["icosphere", "--subdivisions", "3", "--out", "s.obj"]);
    check_remesh(&s, "s.obj", 800, &[], 0, 0);
}

#[test]
fn a_torus_becomes_an_even_torus() {
    let s = Scratch::new("remesh_torus");
    s.generate(&[
        "torus", "--R", "3", "--r", "1", "--major", "48", "--minor", "16", "--out", "t.obj",
    ]);
    check_remesh(&s, "t.obj", 1200, &["--torus", "2:1"], 0, 1);
}

#[test]
fn more_population_on_one_side_puts_more_vertices_there() {
    let s = Scratch::new("remesh_population");
    s.generate(&["polygon", "--sides", "8", "--rings", "24", "--out", "p.obj"]);
    s.ok(&[
        "remesh",
        "p.obj",
        "--out",
        "r.obj",
        "--vertices",
        "2000",
        "--population",
        "area*(1+3*(x>0))",
        "--quiet",
    ]);
    let out = read(&s, "r.obj");
    let (mut area_pos, mut area_neg) = (0.0, 0.0);
    for f in &out.faces {
        let [a, b, c] = f.map(|v| out.positions[v as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        if (a[0] + b[0] + c[0]) / 3.0 > 0.0 {
            area_pos += area;
        } else {
            area_neg += area;
        }
    }
    let pos = out.positions.iter().filter(|p| p[0] > 0.0).count() as f64;
    let neg = out.n_vertices() as f64 - pos;
    let ratio = (pos / area_pos) / (neg / area_neg);
    assert!(ratio >= 2.5, "density ratio {ratio}");
    assert!((out.n_vertices() as f64 - 2000.0).abs() <= 200.0);
}

#[test]
fn the_report_has_the_new_mesh_figures() {
    let s = Scratch::new("remesh_report");
    s.generate(&["icosphere", "--subdivisions", "2", "--out", "s.obj"]);
    s.ok(&[
        "remesh",
        "s.obj",
        "--out",
        "r.ply",
        "--vertices",
        "300",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let v: serde_json::Value = serde_json::from_str(&s.read("r.json")).unwrap();
    assert_eq!(v["method"], "sdem");
    assert_eq!(v["input"]["vertices"], 162);
    assert_eq!(v["output"]["vertices"], 300);
    assert_eq!(v["output"]["genus"], 0);
    assert_eq!(v["output"]["boundaries"], 0);
    assert_eq!(v["map"]["flipped_triangles"], 0);
    let q = &v["quality"];
    assert!(q["area_cv"].as_f64().unwrap() < 0.5);
    assert!(q["median_min_angle_deg"].as_f64().unwrap() > 35.0);
    assert!(q["max_distance_over_diagonal"].as_f64().unwrap() < 1e-9);
    assert!(v["time_s"]["total"].as_f64().unwrap() > 0.0);
    assert!(s.read_bytes("r.ply").starts_with(b"ply"));
}

#[test]
fn too_few_vertices_and_bad_arguments_are_refused() {
    let s = Scratch::new("remesh_refusals");
    s.generate(&["polygon", "--sides", "6", "--rings", "4", "--out", "p.obj"]);
    s.generate(&[
        "torus", "--R", "3", "--r", "1", "--major", "24", "--minor", "8", "--out", "t.obj",
    ]);
    s.generate(&[
        "disk-holes",
        "--hole",
        "0.4:0:0.2",
        "--hole",
        "-0.4:0.1:0.15",
        "--out",
        "h.obj",
    ]);
    let run = |args: &[&str]| s.run(args);
    run(&["remesh", "p.obj", "--out", "r.obj", "--vertices", "3"])
        .input_error_naming(&["--vertices", "4"]);
    run(&["remesh", "h.obj", "--out", "r.obj", "--vertices", "8"])
        .input_error_naming(&["--vertices", "3 boundary loops"]);
    run(&[
        "remesh",
        "t.obj",
        "--out",
        "r.obj",
        "--vertices",
        "10",
        "--torus",
        "2:1",
    ])
    .input_error_naming(&["--vertices", "16"]);
    run(&["remesh", "t.obj", "--out", "r.obj"]).input_error_naming(&["--torus"]);
    run(&["remesh", "p.obj", "--out", "r.stl"]).input_error_naming(&[".obj or .ply"]);
    run(&["remesh", "missing.obj", "--out", "r.obj"]).input_error();
    run(&["remesh", "p.obj", "--out", "r.obj", "--population", "x-5"])
        .input_error_naming(&["population"]);
    assert!(!s.path("r.obj").exists());
}
