//! Refusals before any work (exit 2, one `error:` line naming the problem) and warnings for
//! options the chosen method does not read: one table of command lines, each with what its
//! error must name, on meshes and maps small enough to keep the whole file fast.

mod common;

use common::Scratch;

/// The meshes and maps the table runs on.
fn scratch() -> Scratch {
    let s = Scratch::new("refusals");
    s.generate(&["grid", "--nx", "4", "--ny", "4", "--out", "disk.obj"]);
    s.generate(&[
        "annulus",
        "--radial",
        "3",
        "--angular",
        "16",
        "--out",
        "annulus.obj",
    ]);
    s.generate(&["icosphere", "--subdivisions", "1", "--out", "sphere.obj"]);
    s.generate(&[
        "torus",
        "--major",
        "12",
        "--minor",
        "6",
        "--out",
        "torus.obj",
    ]);
    let square = "[[0,0],[1,0],[1,1],[0,1],[0,0]]";
    s.write(
        "twice.geojson",
        format!(
            r#"{{"type":"FeatureCollection","features":[
{{"type":"Feature","properties":{{"name":"Left","v":1}},"geometry":{{"type":"Polygon","coordinates":[{square}]}}}},
{{"type":"Feature","properties":{{"name":"Again","v":2}},"geometry":{{"type":"Polygon","coordinates":[{square}]}}}},
{{"type":"Feature","properties":{{"name":"Right","v":3}},"geometry":{{"type":"Polygon","coordinates":[[[1,0],[2,0],[2,1],[1,1],[1,0]]]}}}}]}}"#
        ),
    );
    s.write("lm.txt", "0\n5\n9\n");
    s
}

#[test]
fn out_of_range_values_and_overlapping_regions_are_refused_naming_the_problem() {
    let s = scratch();
    let map = |mesh: &'static str, extra: &[&'static str]| {
        let mut a = vec!["map", mesh, "--out", "o.obj"];
        a.extend_from_slice(extra);
        a
    };
    let rows: Vec<(Vec<&str>, Vec<&str>)> = vec![
        // The issue's table.
        (
            vec![
                "cartogram",
                "twice.geojson",
                "--value",
                "v",
                "--out",
                "c.geojson",
            ],
            vec!["'Left'", "'Again'", "overlap"],
        ),
        (
            map("torus.obj", &["--method", "tdem", "--torus", "1e300:1e299"]),
            vec!["--torus", "out of range"],
        ),
        (map("annulus.obj", &["--beta", "-1"]), vec!["--beta", "-1"]),
        // Every weight, whichever method reads it.
        (map("disk.obj", &["--alpha", "NaN"]), vec!["--alpha"]),
        (map("sphere.obj", &["--gamma", "inf"]), vec!["--gamma"]),
        (
            map("sphere.obj", &["--beta", "1e300"]),
            vec!["--beta", "1e6"],
        ),
        // Tolerances, steps, tori relative to the mesh.
        (
            map("disk.obj", &["--epsilon", "1e300"]),
            vec!["--epsilon", "below 1"],
        ),
        (map("disk.obj", &["--dt", "NaN"]), vec!["--dt", "positive"]),
        (
            map("torus.obj", &["--torus", "3:1", "--dt", "1e300"]),
            vec!["--dt", "out of range"],
        ),
        (
            map("torus.obj", &["--torus", "1e-300:1e-301"]),
            vec!["--torus", "out of range"],
        ),
        (
            map("torus.obj", &["--torus", "1e12:1"]),
            vec!["--torus", "R / r"],
        ),
        (
            map("disk.obj", &["--render", "p.png", "--view", "1e300:30"]),
            vec!["--view", "azimuth"],
        ),
        (
            vec!["remesh", "disk.obj", "--out", "r.obj", "--beta", "-1"],
            vec!["--beta"],
        ),
        (
            vec![
                "register",
                "sphere.obj",
                "sphere.obj",
                "--landmarks-a",
                "lm.txt",
                "--landmarks-b",
                "lm.txt",
                "--out",
                "g.obj",
                "--alpha",
                "1e300",
            ],
            vec!["--alpha"],
        ),
        (
            vec![
                "cartogram",
                "twice.geojson",
                "--value",
                "v",
                "--out",
                "c.geojson",
                "--max-error",
                "1e300",
            ],
            vec!["--max-error", "at most 1"],
        ),
        (
            vec!["generate", "torus", "--R", "1e300", "--out", "t.obj"],
            vec!["--r ", "--R"],
        ),
    ];
    for (args, needles) in rows {
        s.run(&args).input_error_naming(&needles);
    }
    assert!(!s.path("o.obj").exists() && !s.path("c.geojson").exists());
}

#[test]
fn an_option_the_method_does_not_read_is_named_in_a_warning_and_the_run_goes_on() {
    let s = scratch();
    let out = s.ok(&[
        "map",
        "annulus.obj",
        "--out",
        "o.obj",
        "--beta",
        "1",
        "--gamma",
        "2",
    ]);
    assert!(
        out.stderr
            .contains("warning: --beta, --gamma not used by --method deq"),
        "{}",
        out.stderr
    );
    let out = s.ok(&[
        "map",
        "disk.obj",
        "--out",
        "o.obj",
        "--alpha",
        "1",
        "--no-geometry-update",
    ]);
    assert!(
        out.stderr
            .contains("warning: --alpha, --no-geometry-update not used by --method dem"),
        "{}",
        out.stderr
    );
    // Options it reads draw no warning.
    let out = s.ok(&["map", "annulus.obj", "--out", "o.obj", "--alpha", "0.5"]);
    assert!(!out.stderr.contains("warning"), "{}", out.stderr);
}

#[test]
fn no_subcommand_prints_the_usage_on_stderr_and_exits_2() {
    let s = Scratch::new("no-args");
    let out = s.run(&[]);
    let line = out.input_error();
    assert!(line.contains("subcommand"), "{line}");
    assert!(
        out.stderr.contains("Usage: demkit <COMMAND>"),
        "{}",
        out.stderr
    );
    assert!(out.stdout.is_empty(), "{}", out.stdout);
    // Asked for, the help is still on stdout with exit 0.
    let help = s.ok(&["--help"]);
    assert!(help.stdout.contains("Usage: demkit <COMMAND>"));
}
