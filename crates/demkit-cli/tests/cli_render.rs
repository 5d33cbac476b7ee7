//! End-to-end tests of the pictures: `map --render` and `map --histogram` on planar, circle-
//! domain, sphere and torus maps (the figures of the DEM, DEQ, SDEM and TDEM papers), `demkit
//! render`, and the refusals.

mod common;

use common::{Scratch, parse_obj};
use std::collections::HashSet;
use tiny_skia::Pixmap;

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

/// Reads `name` as a PNG and checks what every picture must be: the PNG signature, at least
/// 512 × 512 pixels, and more than a few colours.
fn picture(s: &Scratch, name: &str) -> Pixmap {
    let bytes = s.read_bytes(name);
    assert_eq!(bytes[..8], PNG_SIGNATURE, "{name} is not a PNG");
    let p = Pixmap::decode_png(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        p.width() >= 512 && p.height() >= 512,
        "{name}: {} × {}",
        p.width(),
        p.height()
    );
    let colours = distinct_colours(&p);
    assert!(colours > 8, "{name} has only {colours} colours");
    p
}

fn distinct_colours(p: &Pixmap) -> usize {
    p.pixels()
        .iter()
        .map(|c| (c.red(), c.green(), c.blue(), c.alpha()))
        .collect::<HashSet<_>>()
        .len()
}

fn rgb(p: &Pixmap, x: u32, y: u32) -> (u8, u8, u8) {
    let c = p.pixel(x, y).expect("pixel inside the picture");
    (c.red(), c.green(), c.blue())
}

const WHITE: (u8, u8, u8) = (255, 255, 255);

/// Runs `map MESH --out o.obj --render r.png --histogram h.png EXTRA --quiet` and checks both
/// pictures; returns them.
fn map_pictures(s: &Scratch, mesh: &str, extra: &[&str]) -> (Pixmap, Pixmap) {
    let mut args = vec![
        "map",
        mesh,
        "--out",
        "o.obj",
        "--render",
        "r.png",
        "--histogram",
        "h.png",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    s.ok(&args);
    let (r, h) = (picture(s, "r.png"), picture(s, "h.png"));
    // The default sizes: a square map picture, histograms 1.5 times as wide.
    assert_eq!((r.width(), r.height()), (1024, 1024));
    assert_eq!((h.width(), h.height()), (1536, 1024));
    (r, h)
}

#[test]
fn a_disk_map_is_drawn_flat_with_both_densities() {
    let s = Scratch::new("render_disk");
    s.generate(&["polygon", "--sides", "6", "--rings", "12", "--out", "d.obj"]);
    let (r, h) = map_pictures(&s, "d.obj", &["--population", "1+3*(x>0)"]);
    // Corners are background; the middle is mesh.
    assert_eq!(rgb(&r, 2, 2), WHITE);
    assert_eq!(rgb(&r, 1021, 1021), WHITE);
    assert_ne!(rgb(&r, 512, 512), WHITE);
    // Two population densities: the dense half (x > 0, right) and the sparse one differ.
    assert_ne!(rgb(&r, 800, 512), rgb(&r, 200, 512));
    // Both histogram panels have bars (the initial blue, the final orange).
    let bars = |c: (u8, u8, u8)| {
        h.pixels()
            .iter()
            .filter(|p| (p.red(), p.green(), p.blue()) == c)
            .count()
    };
    assert!(bars((76, 114, 176)) > 1000 && bars((221, 132, 82)) > 1000);
}

#[test]
fn a_circle_domain_map_is_drawn_with_its_hole() {
    let s = Scratch::new("render_annulus");
    s.generate(&[
        "annulus",
        "--radial",
        "6",
        "--angular",
        "48",
        "--out",
        "a.obj",
    ]);
    let (r, _) = map_pictures(&s, "a.obj", &["--population", "area*(1+3*(x>0))"]);
    // The hole in the middle is background, the ring around it is not.
    assert_eq!(rgb(&r, 512, 512), WHITE);
    assert_ne!(rgb(&r, 512, 60), WHITE);
}

#[test]
fn a_sphere_map_is_drawn_lit() {
    let s = Scratch::new("render_sphere");
    s.generate(&["icosphere", "--subdivisions", "3", "--out", "s.obj"]);
    let (r, _) = map_pictures(&s, "s.obj", &["--population", "area*(1+4*(z>0.3))"]);
    assert_eq!(rgb(&r, 2, 2), WHITE);
    assert_ne!(rgb(&r, 512, 512), WHITE);
    // A disk fills the middle of the picture: 4 % margins, radius ≈ 471 pixels.
    assert_ne!(rgb(&r, 512, 60), WHITE);
    assert_ne!(rgb(&r, 60, 512), WHITE);
}

#[test]
fn a_torus_map_is_drawn_from_the_chosen_view() {
    let s = Scratch::new("render_torus");
    s.generate(&[
        "torus", "--R", "2", "--r", "1", "--major", "32", "--minor", "16", "--out", "t.obj",
    ]);
    let population = "area*(1+3*(x>0))";
    let (r, _) = map_pictures(&s, "t.obj", &["--torus", "2:1", "--population", population]);
    // The default view looks down at 60°: the hole is in the middle.
    assert_eq!(rgb(&r, 512, 512), WHITE);
    // From the side the middle is the torus itself.
    s.ok(&[
        "map",
        "t.obj",
        "--out",
        "o.obj",
        "--torus",
        "2:1",
        "--population",
        population,
        "--render",
        "side.png",
        "--view",
        "0:0",
        "--size",
        "600",
        "--quiet",
    ]);
    let side = picture(&s, "side.png");
    assert_eq!((side.width(), side.height()), (600, 600));
    assert_ne!(rgb(&side, 300, 300), WHITE);
}

#[test]
fn render_draws_any_mesh_with_or_without_values() {
    let s = Scratch::new("render_cmd");
    s.generate(&["peaks", "--n", "12", "--out", "p.obj"]);
    s.ok(&["render", "p.obj", "--out", "plain.png"]);
    let plain = picture(&s, "plain.png");
    assert_eq!((plain.width(), plain.height()), (1024, 1024));
    let (mesh, _) = parse_obj(&s.read("p.obj"));
    let values: String = (0..mesh.faces.len())
        .map(|f| format!("{}\n", f % 7))
        .collect();
    s.write("v.txt", format!("# one value per face\n{values}"));
    s.ok(&[
        "render",
        "p.obj",
        "--out",
        "coloured.png",
        "--color",
        "v.txt",
    ]);
    let coloured = picture(&s, "coloured.png");
    assert!(distinct_colours(&coloured) > distinct_colours(&plain));
    assert_ne!(s.read_bytes("plain.png"), s.read_bytes("coloured.png"));
    // A planar mesh, flat from above: the grid fills the square picture but its margin.
    s.generate(&[
        "grid", "--nx", "4", "--ny", "4", "--width", "1", "--height", "1", "--out", "g.obj",
    ]);
    s.ok(&["render", "g.obj", "--out", "g.png", "--size", "512"]);
    let g = Pixmap::decode_png(&s.read_bytes("g.png")).unwrap();
    assert_eq!((g.width(), g.height()), (512, 512));
    assert_eq!(rgb(&g, 5, 5), WHITE);
    assert_ne!(rgb(&g, 30, 30), WHITE);
    assert_ne!(rgb(&g, 256, 256), WHITE);
}

#[test]
fn bad_pictures_are_refused() {
    let s = Scratch::new("render_refusals");
    s.generate(&["polygon", "--sides", "6", "--rings", "4", "--out", "d.obj"]);
    let (mesh, _) = parse_obj(&s.read("d.obj"));
    let n = mesh.faces.len();
    s.run(&["render", "d.obj", "--out", "a.jpg"])
        .input_error_naming(&["a.jpg", ".png"]);
    s.run(&["map", "d.obj", "--out", "o.obj", "--render", "a.jpg"])
        .input_error_naming(&["a.jpg", ".png"]);
    s.run(&["map", "d.obj", "--out", "o.obj", "--histogram", "h.gif"])
        .input_error_naming(&["h.gif", ".png"]);
    // Bad views and sizes are refused before the map is computed.
    s.run(&[
        "map", "d.obj", "--out", "o.obj", "--render", "r.png", "--view", "10",
    ])
    .input_error_naming(&["--view", "AZIMUTH:ELEVATION", "'10'"]);
    s.run(&[
        "map", "d.obj", "--out", "o.obj", "--render", "r.png", "--view", "0:95",
    ])
    .input_error_naming(&["--view", "'0:95'"]);
    s.run(&[
        "map",
        "d.obj",
        "--out",
        "o.obj",
        "--histogram",
        "h.png",
        "--size",
        "32",
    ])
    .input_error_naming(&["--size", "32"]);
    assert!(
        !s.path("o.obj").exists(),
        "nothing is computed after a refusal"
    );
    s.run(&["render", "d.obj", "--out", "r.png", "--size", "100000"])
        .input_error_naming(&["--size", "100000"]);
    // --color: wrong count, NaN, missing file, not a number.
    s.write("short.txt", "1\n2\n");
    s.run(&["render", "d.obj", "--out", "r.png", "--color", "short.txt"])
        .input_error_naming(&["short.txt", "2 values", &format!("{n} faces")]);
    let mut nan: Vec<String> = vec!["1".into(); n];
    nan[3] = "NaN".into();
    s.write("nan.txt", nan.join("\n"));
    s.run(&["render", "d.obj", "--out", "r.png", "--color", "nan.txt"])
        .input_error_naming(&["nan.txt", "face 3", "NaN"]);
    s.run(&[
        "render",
        "d.obj",
        "--out",
        "r.png",
        "--color",
        "missing.txt",
    ])
    .input_error_naming(&["missing.txt"]);
    s.write("word.txt", "1\nabc\n");
    s.run(&["render", "d.obj", "--out", "r.png", "--color", "word.txt"])
        .input_error_naming(&["word.txt", "abc"]);
    assert!(!s.path("r.png").exists());
    // An unwritable path is named.
    s.run(&["render", "d.obj", "--out", "no/such/dir/r.png"])
        .input_error_naming(&["no/such/dir/r.png"]);
}
