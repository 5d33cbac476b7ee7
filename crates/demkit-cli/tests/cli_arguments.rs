//! Readers and arguments: data after a header's declared elements, a population file that does
//! not exist, negative numbers given to options, missing arguments, a mesh too small for a
//! method, coincident vertices: each is exit 2 with one `error:` line that says what is wrong.

mod common;

use common::Scratch;

#[test]
fn faces_beyond_an_off_header_are_an_error_naming_the_line() {
    let s = Scratch::new("off-extra");
    s.write(
        "x.off",
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n",
    );
    s.run(&["map", "x.off", "--out", "o.obj"])
        .input_error_naming(&["x.off:7", "after the 1 faces"]);
}

#[test]
fn a_missing_population_file_is_named_as_such() {
    let s = Scratch::new("pop-typo");
    s.generate(&["grid", "--nx", "3", "--ny", "3", "--out", "g.obj"]);
    s.run(&[
        "map",
        "g.obj",
        "--out",
        "o.obj",
        "--population",
        "pop_typo.txt",
    ])
    .input_error_naming(&[
        "no such population file 'pop_typo.txt'",
        "not a valid expression",
    ]);
}

#[test]
fn negative_numbers_get_the_options_own_range_message() {
    let s = Scratch::new("negative");
    s.generate(&["torus", "--out", "t.obj"]);
    s.run(&["map", "t.obj", "--out", "o.obj", "--torus", "-1:1"])
        .input_error_naming(&["--torus", "R > r > 0"]);
    s.run(&["render", "t.obj", "--out", "p.png", "--size", "-5"])
        .input_error_naming(&["--size", "64 to 4096"]);
    s.run(&["generate", "grid", "--width", "-1", "--out", "w.obj"])
        .input_error_naming(&["width must be positive"]);
}

#[test]
fn the_librarys_parameters_are_named_by_their_flags() {
    let s = Scratch::new("flags");
    s.generate(&["grid", "--nx", "3", "--ny", "3", "--out", "g.obj"]);
    s.run(&["map", "g.obj", "--out", "o.obj", "--epsilon", "0"])
        .input_error_naming(&["--epsilon must be positive"]);
    s.run(&["map", "g.obj", "--out", "o.obj", "--dt", "0"])
        .input_error_naming(&["--dt must be positive"]);
    s.run(&["map", "g.obj", "--out", "o.obj", "--max-iter", "0"])
        .input_error_naming(&["--max-iter must be at least 1"]);
}

#[test]
fn missing_arguments_are_named_on_the_error_line() {
    let s = Scratch::new("missing");
    s.run(&["map"]).input_error_naming(&["--out", "<MESH>"]);
    s.run(&["map", "g.obj"]).input_error_naming(&["--out"]);
}

#[test]
fn a_tetrahedron_is_too_small_for_a_spherical_map() {
    let s = Scratch::new("tetra");
    s.write(
        "t.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
    );
    s.run(&["map", "t.obj", "--out", "o.obj"])
        .input_error_naming(&["too small", "4 faces"]);
}

#[test]
fn a_remesh_beyond_memory_is_refused_up_front_with_the_estimate() {
    let s = Scratch::new("huge-remesh");
    s.generate(&["grid", "--nx", "4", "--ny", "4", "--out", "g.obj"]);
    s.run(&[
        "remesh",
        "g.obj",
        "--out",
        "o.obj",
        "--vertices",
        "1000000000",
    ])
    .input_error_naming(&["--vertices 1000000000", "GB"]);
}

#[test]
fn a_geojson_hole_outside_its_exterior_is_refused_naming_the_feature() {
    let s = Scratch::new("geo-hole");
    s.write(
        "r.geojson",
        r#"{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{"v":1},"geometry":{"type":"Polygon","coordinates":[[[0,0],[4,0],[4,4],[0,4],[0,0]],[[10,10],[11,10],[11,11],[10,11],[10,10]]]}},
{"type":"Feature","properties":{"v":2},"geometry":{"type":"Polygon","coordinates":[[[4,0],[8,0],[8,4],[4,4],[4,0]]]}}]}"#,
    );
    s.run(&[
        "cartogram",
        "r.geojson",
        "--value",
        "v",
        "--out",
        "o.geojson",
    ])
    .input_error_naming(&["feature 0", "outside"]);
}
