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

/// The left end of the map panel in a `map --render` figure: the input panel (an N × N
/// picture and its legend strip) fills the left half, the map panel the right half; N is the
/// figure's height.
fn map_x(r: &Pixmap) -> u32 {
    r.width() / 2
}

/// The distinct colours of the pixels in the rectangle [x0, x1) × [y0, y1).
fn colours_in(p: &Pixmap, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> HashSet<(u8, u8, u8)> {
    (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| rgb(p, x, y))
        .collect()
}

/// The mean colour of the rectangle [x0, x1) × [y0, y1).
fn mean_in(p: &Pixmap, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for y in y0..y1 {
        for x in x0..x1 {
            let c = rgb(p, x, y);
            sum[0] += f64::from(c.0);
            sum[1] += f64::from(c.1);
            sum[2] += f64::from(c.2);
        }
    }
    sum.map(|v| v / f64::from((x1 - x0) * (y1 - y0)))
}

/// The largest difference of one channel between two colours.
fn colour_gap(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

/// Checks the map panel's legend strip (right of its N × N picture): a colour bar running
/// from red (ratios above 1) to blue (below 1), and dark label ink.
fn assert_residual_bar(r: &Pixmap) {
    let n = r.height();
    let strip = colours_in(r, (map_x(r) + n, r.width()), (0, n));
    let red = strip
        .iter()
        .filter(|c| i32::from(c.0) > i32::from(c.2) + 80)
        .count();
    let blue = strip
        .iter()
        .filter(|c| i32::from(c.2) > i32::from(c.0) + 80)
        .count();
    let ink = strip
        .iter()
        .filter(|c| c.0 < 60 && c.1 < 60 && c.2 < 60)
        .count();
    assert!(red > 3 && blue > 3 && ink > 0, "{red} {blue} {ink}");
}

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
    // The default sizes: two 1024 × 1024 pictures, each with a legend strip of at most a
    // quarter of their width; histograms 1.5 times as wide as high.
    assert_eq!(r.height(), 1024);
    assert!(r.width() % 2 == 0 && r.width() > 2048 && r.width() <= 2560);
    assert_eq!((h.width(), h.height()), (1536, 1024));
    assert_residual_bar(&r);
    (r, h)
}

#[test]
fn a_disk_map_is_drawn_flat_with_both_densities() {
    let s = Scratch::new("render_disk");
    s.generate(&["polygon", "--sides", "6", "--rings", "12", "--out", "d.obj"]);
    let (r, h) = map_pictures(&s, "d.obj", &["--population", "1+3*(x>0)"]);
    // In both panels corners are background and the middle is mesh.
    for x0 in [0, map_x(&r)] {
        assert_eq!(rgb(&r, x0 + 2, 2), WHITE);
        assert_eq!(rgb(&r, x0 + 1021, 1021), WHITE);
        assert_ne!(rgb(&r, x0 + 512, 512), WHITE);
    }
    // Two population densities on the input: the dense half (x > 0, right) and the sparse
    // one differ, beyond the checkerboard's shading.
    let (sparse, dense) = (
        mean_in(&r, (150, 350), (412, 612)),
        mean_in(&r, (674, 874), (412, 612)),
    );
    assert!(colour_gap(sparse, dense) > 60.0, "{sparse:?} {dense:?}");
    // The map is coloured by the density left after it: neither half is the input's colour.
    let m = map_x(&r);
    let left = mean_in(&r, (m + 150, m + 350), (412, 612));
    let right = mean_in(&r, (m + 674, m + 874), (412, 612));
    assert!(
        colour_gap(left, sparse) > 60.0 && colour_gap(right, dense) > 60.0,
        "{left:?} {right:?}"
    );
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
    // The hole in the middle of the map is background, the ring around it is not.
    let m = map_x(&r);
    assert_eq!(rgb(&r, m + 512, 512), WHITE);
    assert_ne!(rgb(&r, m + 512, 60), WHITE);
}

#[test]
fn a_sphere_map_is_drawn_lit() {
    let s = Scratch::new("render_sphere");
    s.generate(&["icosphere", "--subdivisions", "3", "--out", "s.obj"]);
    let (r, _) = map_pictures(&s, "s.obj", &["--population", "area*(1+4*(z>0.3))"]);
    // Input and map are both the sphere, each a disk filling the middle of its picture:
    // 4 % margins, radius ≈ 471 pixels.
    for x0 in [0, map_x(&r)] {
        assert_eq!(rgb(&r, x0 + 2, 2), WHITE);
        assert_ne!(rgb(&r, x0 + 512, 512), WHITE);
        assert_ne!(rgb(&r, x0 + 512, 60), WHITE);
        assert_ne!(rgb(&r, x0 + 60, 512), WHITE);
    }
}

#[test]
fn a_torus_map_is_drawn_from_the_chosen_view() {
    let s = Scratch::new("render_torus");
    s.generate(&[
        "torus", "--R", "2", "--r", "1", "--major", "32", "--minor", "16", "--out", "t.obj",
    ]);
    let population = "area*(1+3*(x>0))";
    let (r, _) = map_pictures(&s, "t.obj", &["--torus", "2:1", "--population", population]);
    // The default view looks down at 60°: the hole is in the middle of both pictures.
    assert_eq!(rgb(&r, 512, 512), WHITE);
    assert_eq!(rgb(&r, map_x(&r) + 512, 512), WHITE);
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
    assert_eq!(side.height(), 600);
    assert_ne!(rgb(&side, 300, 300), WHITE);
    assert_ne!(rgb(&side, map_x(&side) + 300, 300), WHITE);
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

/// The share of the commonest and of the second commonest colour among `colours`.
fn two_commonest(p: &Pixmap, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> (f64, f64) {
    let mut count = std::collections::HashMap::new();
    for y in y0..y1 {
        for x in x0..x1 {
            *count.entry(rgb(p, x, y)).or_insert(0usize) += 1;
        }
    }
    let mut c: Vec<usize> = count.into_values().collect();
    c.sort_unstable_by(|a, b| b.cmp(a));
    let n = f64::from((x1 - x0) * (y1 - y0));
    (c[0] as f64 / n, c.get(1).map_or(0.0, |&v| v as f64 / n))
}

#[test]
fn a_map_by_area_shows_the_checkerboard_and_the_density_left() {
    let s = Scratch::new("render_area");
    // A planar disk by area: nothing to equalize, the map is the input. Both panels are one
    // colour each, but both show the checkerboard: two colours, each on a good share of the
    // middle of the disk.
    s.generate(&["polygon", "--sides", "6", "--rings", "40", "--out", "d.obj"]);
    s.ok(&[
        "map", "d.obj", "--out", "o.obj", "--render", "d.png", "--size", "512", "--quiet",
    ]);
    let d = picture(&s, "d.png");
    assert_eq!(d.height(), 512);
    assert_residual_bar(&d);
    for x0 in [0, map_x(&d)] {
        let (first, second) = two_commonest(&d, (x0 + 156, x0 + 356), (156, 356));
        assert!(second > 0.3 && first < 0.7, "{x0}: {first} {second}");
    }
    // A surface by area: the map (a disk) is coloured by the density left after it: besides
    // the checkerboard's two shades, many colours over its middle.
    s.generate(&["peaks", "--n", "40", "--out", "p.obj"]);
    s.ok(&[
        "map", "p.obj", "--out", "o.obj", "--render", "r.png", "--size", "512", "--quiet",
    ]);
    let r = picture(&s, "r.png");
    assert_residual_bar(&r);
    let m = map_x(&r);
    let region = ((m + 156, m + 356), (156, 356));
    let colours = colours_in(&r, region.0, region.1).len();
    assert!(colours > 20, "the map has {colours} colours");
    let (first, _) = two_commonest(&r, region.0, region.1);
    assert!(first < 0.5, "map: one colour covers {first}");
}

/// The number of places along row `y` from `x0` to `x1` where the brightness jumps by more
/// than 6 % from one pixel to the next (neighbouring jumps count once): checkerboard edges.
fn brightness_jumps(p: &Pixmap, y: u32, (x0, x1): (u32, u32)) -> usize {
    let luma = |x: u32| {
        let (r, g, b) = rgb(p, x, y);
        0.3 * f64::from(r) + 0.59 * f64::from(g) + 0.11 * f64::from(b) + 1.0
    };
    let mut jumps = 0;
    let mut previous = false;
    for x in x0..x1 {
        let jump = (luma(x + 1) / luma(x)).ln().abs() > 0.06;
        if jump && !previous {
            jumps += 1;
        }
        previous = jump;
    }
    jumps
}

#[test]
fn the_checkerboard_grows_where_the_population_is_dense() {
    let s = Scratch::new("render_cells");
    s.generate(&["polygon", "--sides", "6", "--rings", "40", "--out", "d.obj"]);
    s.ok(&[
        "map",
        "d.obj",
        "--out",
        "o.obj",
        "--population",
        "1+3*(x>0)",
        "--render",
        "r.png",
        "--size",
        "512",
        "--quiet",
    ]);
    let r = picture(&s, "r.png");
    // The input (its own initial map) has cells of one size: as many edges either side of
    // the middle along the middle row.
    let (left, right) = (
        brightness_jumps(&r, 250, (40, 236)),
        brightness_jumps(&r, 250, (276, 472)),
    );
    assert!(
        left >= 4 && left.abs_diff(right) <= 1,
        "input: {left} {right}"
    );
    // On the map the dense half (x > 0, right) has grown: its cells are larger, so fewer
    // edges cross the row there.
    let m = map_x(&r);
    let (left, right) = (
        brightness_jumps(&r, 250, (m + 40, m + 236)),
        brightness_jumps(&r, 250, (m + 276, m + 472)),
    );
    assert!(right >= 2 && 3 * right <= 2 * left, "map: {left} {right}");
    // The two panels differ: the input is coloured by its two densities, the map by what
    // is left of them.
    let input = mean_in(&r, (60, 452), (200, 300));
    let map = mean_in(&r, (m + 60, m + 452), (200, 300));
    assert!(colour_gap(input, map) > 40.0, "{input:?} {map:?}");
}
