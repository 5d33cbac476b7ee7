//! `demkit subdivide`: V + E vertices and 4F faces per level, the input vertices first, the
//! topology and the area kept, populations split in equal parts; bad inputs exit 2 with one line.

mod common;

use common::{Scratch, json, parse_obj, parse_ply};

fn info(s: &Scratch, mesh: &str) -> serde_json::Value {
    json(&s.ok(&["info", mesh, "--json"]).stdout)
}

#[test]
fn a_torus_subdivided_twice_has_the_counts_and_topology_of_midpoint_subdivision() {
    let s = Scratch::new("subdivide-torus");
    s.generate(&["torus", "--major", "8", "--minor", "4", "--out", "t.obj"]);
    let out = s.ok(&["subdivide", "t.obj", "--levels", "2", "--out", "s.obj"]);
    assert!(
        out.stderr
            .contains("32 vertices, 64 faces -> 512 vertices, 1024 faces (2 levels in 2 parts)"),
        "{}",
        out.stderr
    );
    let (input, _) = parse_obj(&s.read("t.obj"));
    let (fine, _) = parse_obj(&s.read("s.obj"));
    // V' = V + E: 32 + 96 = 128, then 128 + (2·96 + 3·64) = 512; F'' = 16 F.
    assert_eq!(fine.positions.len(), 512);
    assert_eq!(fine.faces.len(), 1024);
    assert_eq!(fine.positions[..32], input.positions[..]);
    let i = info(&s, "s.obj");
    assert_eq!(i["euler_characteristic"], 0);
    assert_eq!(i["genus"], 1);
    assert_eq!(i["boundaries"], 0);
    assert_eq!(i["errors"].as_array().map(Vec::len), Some(0));
}

#[test]
fn a_torus_in_three_parts_has_the_lattice_counts_and_its_population_in_nine_parts() {
    let s = Scratch::new("subdivide-parts");
    s.generate(&["torus", "--major", "8", "--minor", "4", "--out", "t.obj"]);
    s.write("t.txt", "9\n".repeat(64));
    let out = s.ok(&[
        "subdivide",
        "t.obj",
        "--parts",
        "3",
        "--out",
        "s.obj",
        "--population",
        "t.txt",
        "--population-out",
        "s.txt",
    ]);
    // V + 2E + F = 32 + 192 + 64; 9 F faces.
    assert!(
        out.stderr
            .contains("32 vertices, 64 faces -> 288 vertices, 576 faces (1 level in 3 parts)"),
        "{}",
        out.stderr
    );
    let values: Vec<f64> = s
        .read("s.txt")
        .lines()
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(values.len(), 576);
    assert!(values.iter().all(|&v| (v - 1.0).abs() < 1e-15));
    assert_eq!(info(&s, "s.obj")["genus"], 1);
    let line = s
        .run(&["subdivide", "t.obj", "--parts", "0", "--out", "z.obj"])
        .input_error();
    assert!(line.contains("parts must be at least 1"), "{line}");
}

#[test]
fn a_planar_grid_keeps_its_area_exactly_and_its_boundary() {
    let s = Scratch::new("subdivide-grid");
    s.generate(&[
        "grid", "--nx", "3", "--ny", "2", "--width", "3", "--height", "2", "--out", "g.obj",
    ]);
    s.ok(&["subdivide", "g.obj", "--out", "s.ply", "--quiet"]);
    let ((nv, nf), mesh) = parse_ply(&s.read_bytes("s.ply"));
    // 12 vertices + 23 edges; 4 · 12 faces.
    assert_eq!((nv, nf), (35, 48));
    // Face f's parts are 4f .. 4f + 3; the first shares f's first corner.
    let (grid, _) = parse_obj(&s.read("g.obj"));
    for (f, face) in grid.faces.iter().enumerate() {
        assert_eq!(mesh.faces[4 * f][0], face[0]);
    }
    let i = info(&s, "s.ply");
    assert_eq!(i["area"].as_f64(), Some(6.0));
    assert_eq!(i["boundaries"], 1);
    assert_eq!(i["boundary_lengths"][0], 20);
}

#[test]
fn a_population_file_is_split_in_equal_parts_and_maps_with_the_finer_mesh() {
    let s = Scratch::new("subdivide-population");
    s.generate(&["grid", "--nx", "2", "--ny", "1", "--out", "g.obj"]);
    s.write("p.txt", "1\n2\n# a comment\n3\n4\n");
    s.ok(&[
        "subdivide",
        "g.obj",
        "--out",
        "s.obj",
        "--population",
        "p.txt",
        "--population-out",
        "q.txt",
        "--quiet",
    ]);
    let values: Vec<f64> = s
        .read("q.txt")
        .lines()
        .map(|l| l.parse().unwrap())
        .collect();
    let expected: Vec<f64> = [0.25, 0.5, 0.75, 1.0]
        .iter()
        .flat_map(|&v| [v; 4])
        .collect();
    assert_eq!(values, expected);
    // The split file fits the finer mesh (a map that stops at --max-iter still read it).
    let map = s.run(&[
        "map",
        "s.obj",
        "--out",
        "m.obj",
        "--population",
        "q.txt",
        "--quiet",
    ]);
    assert!(matches!(map.code, Some(0 | 3)), "{}", map.stderr);
}

#[test]
fn bad_requests_are_one_line_errors() {
    let s = Scratch::new("subdivide-errors");
    s.generate(&["grid", "--nx", "2", "--ny", "1", "--out", "g.obj"]);
    s.write("p.txt", "1\n2\n3\n");
    // 4 faces · 4^15 = 2^32 faces: one more than 32-bit indices hold.
    s.run(&["subdivide", "g.obj", "--levels", "15", "--out", "s.obj"])
        .input_error_naming(&["--levels must be at most 14 for 4 faces"]);
    s.run(&["subdivide", "g.obj", "--levels", "-1", "--out", "s.obj"])
        .input_error_naming(&["--levels"]);
    s.run(&[
        "subdivide",
        "g.obj",
        "--out",
        "s.obj",
        "--population",
        "p.txt",
    ])
    .input_error_naming(&["--population-out"]);
    s.run(&[
        "subdivide",
        "g.obj",
        "--out",
        "s.obj",
        "--population",
        "p.txt",
        "--population-out",
        "q.txt",
    ])
    .input_error_naming(&["p.txt has 3 values but the mesh has 4 faces"]);
    s.run(&["subdivide", "g.obj", "--out", "./g.obj"])
        .input_error_naming(&["--out", "would replace the input MESH"]);
    s.run(&["subdivide", "g.obj", "--out", "s.stl"])
        .input_error_naming(&[".obj or .ply"]);
    s.run(&["subdivide", "missing.obj", "--out", "s.obj"])
        .input_error_naming(&["missing.obj"]);
    assert!(!s.path("s.obj").exists() && !s.path("q.txt").exists());
}
