//! End-to-end tests of `demkit map --uv-out` (DEQ paper §7.2, TDEM paper §5.2): texture
//! coordinates from planar and toroidal maps, and the refusals.

mod common;

use common::{Scratch, parse_obj};

/// `demkit generate torus` with radii 3 and 1 into `t.obj`.
fn torus(s: &Scratch) {
    s.generate(&[
        "torus", "--R", "3", "--r", "1", "--major", "48", "--minor", "16", "--out", "t.obj",
    ]);
}

/// The `vt` lines and the face lines of an OBJ text.
fn texture_lines(text: &str) -> (Vec<[f64; 2]>, Vec<String>) {
    let vt = text
        .lines()
        .filter_map(|l| l.strip_prefix("vt "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[0], v[1]]
        })
        .collect();
    let faces = text
        .lines()
        .filter(|l| l.starts_with("f "))
        .map(String::from)
        .collect();
    (vt, faces)
}

#[test]
fn uv_out_of_a_disk_map_has_one_vt_per_vertex_in_the_unit_square() {
    let s = Scratch::new("uv_disk");
    s.generate(&["peaks", "--n", "10", "--out", "p.obj"]);
    s.ok(&[
        "map", "p.obj", "--out", "o.obj", "--uv-out", "uv.obj", "--quiet",
    ]);
    let text = s.read("uv.obj");
    let (input, in_faces) = parse_obj(&s.read("p.obj"));
    let (uv_mesh, _) = parse_obj(&text);
    // The input surface, with its own positions.
    assert_eq!(uv_mesh.positions, input.positions);
    let (vt, faces) = texture_lines(&text);
    assert_eq!(vt.len(), input.positions.len());
    assert!(
        vt.iter()
            .all(|p| (0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1]))
    );
    assert_eq!(faces.len(), in_faces.len());
    for f in &faces {
        for c in f.split_whitespace().skip(1) {
            let (a, b) = c.split_once('/').unwrap();
            assert_eq!(a, b, "{f}");
        }
    }
}

#[test]
fn uv_out_of_a_torus_map_is_a_periodic_atlas() {
    let s = Scratch::new("uv_torus");
    torus(&s);
    s.ok(&[
        "map", "t.obj", "--out", "o.obj", "--torus", "3:1", "--uv-out", "uv.obj", "--quiet",
    ]);
    let (vt, faces) = texture_lines(&s.read("uv.obj"));
    let (input, _) = parse_obj(&s.read("t.obj"));
    // One vt per vertex plus the copies along the two seams.
    assert!(vt.len() > input.positions.len() && vt.len() < input.positions.len() + 48 + 16 + 2);
    let mut area = 0.0;
    for f in &faces {
        let p: Vec<[f64; 2]> = f
            .split_whitespace()
            .skip(1)
            .map(|c| vt[c.split_once('/').unwrap().1.parse::<usize>().unwrap() - 1])
            .collect();
        let a = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
        assert!(a > 0.0);
        area += a;
    }
    assert!((area - 1.0).abs() < 1e-9, "{area}");
}

#[test]
fn uv_out_is_refused_for_spherical_maps_and_other_formats() {
    let s = Scratch::new("uv_bad");
    s.generate(&["icosphere", "--out", "s.obj"]);
    s.run(&["map", "s.obj", "--out", "o.obj", "--uv-out", "uv.obj"])
        .input_error_naming(&["--uv-out", "sphere"]);
    s.generate(&["peaks", "--n", "8", "--out", "p.obj"]);
    s.run(&["map", "p.obj", "--out", "o.obj", "--uv-out", "uv.ply"])
        .input_error_naming(&["uv.ply", ".obj"]);
}
