//! No output may replace an input or another output, and nothing is written before the checks
//! pass: every such command ends with exit 2 naming the options, and leaves the files as they
//! were (DESIGN.md, "Command line"; `src/paths.rs`).

mod common;

use common::Scratch;

/// A square split into four triangles around its centre.
const FAN: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0\n\
                   f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";

/// Runs `args` in a scratch directory holding `in.obj` (and `pop.txt`), expects exit 2 with an
/// error naming `needles`, and checks that `in.obj` is unchanged and that no other file appeared.
fn refused(tag: &str, args: &[&str], needles: &[&str]) {
    let s = Scratch::new(tag);
    s.write("in.obj", FAN);
    s.write("pop.txt", "1\n2\n1\n2\n");
    let before: Vec<_> = std::fs::read_dir(s.path("."))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    s.run(args).input_error_naming(needles);
    assert_eq!(s.read("in.obj"), FAN, "{tag}: the input changed");
    let after: Vec<_> = std::fs::read_dir(s.path("."))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        before.len(),
        after.len(),
        "{tag}: files appeared: {after:?}"
    );
}

#[test]
fn the_output_mesh_may_not_replace_the_input() {
    refused(
        "out-in",
        &["map", "in.obj", "--out", "in.obj"],
        &["--out", "MESH"],
    );
    refused(
        "out-in-dot",
        &["map", "in.obj", "--out", "./in.obj", "--max-iter", "1"],
        &["--out"],
    );
    refused(
        "remesh-in",
        &["remesh", "in.obj", "--out", "in.obj"],
        &["--out", "MESH"],
    );
}

#[test]
fn a_report_may_not_replace_an_input() {
    refused(
        "report-mesh",
        &["map", "in.obj", "--out", "o.obj", "--report", "in.obj"],
        &["--report"],
    );
    refused(
        "report-pop",
        &[
            "map",
            "in.obj",
            "--out",
            "o.obj",
            "--population",
            "pop.txt",
            "--report",
            "pop.txt",
        ],
        &["--report", "--population"],
    );
}

#[test]
fn two_outputs_may_not_be_one_file() {
    refused(
        "out-report",
        &["map", "in.obj", "--out", "o.obj", "--report", "./o.obj"],
        &["--out", "--report"],
    );
    refused(
        "render-histogram",
        &[
            "map",
            "in.obj",
            "--out",
            "o.obj",
            "--render",
            "p.png",
            "--histogram",
            "p.png",
        ],
        &["--render", "--histogram"],
    );
    refused(
        "uv-out",
        &["map", "in.obj", "--out", "o.obj", "--uv-out", "o.obj"],
        &["--out", "--uv-out"],
    );
}

#[test]
fn a_missing_output_directory_is_found_before_anything_is_written() {
    refused(
        "nodir",
        &[
            "map",
            "in.obj",
            "--out",
            "in.obj",
            "--report",
            "nodir/r.json",
        ],
        &["nodir"],
    );
    refused(
        "nodir-out",
        &[
            "map",
            "in.obj",
            "--out",
            "o.obj",
            "--report",
            "nodir/r.json",
        ],
        &["--report", "nodir"],
    );
}

#[test]
fn a_link_to_the_input_is_the_input() {
    let s = Scratch::new("link");
    s.write("in.obj", FAN);
    std::os::unix::fs::symlink(s.path("in.obj"), s.path("link.obj")).unwrap();
    s.run(&["map", "in.obj", "--out", "link.obj"])
        .input_error_naming(&["--out", "MESH"]);
    assert_eq!(s.read("in.obj"), FAN);
}

#[test]
fn outputs_are_written_whole_with_no_temporary_left() {
    let s = Scratch::new("whole");
    s.write("in.obj", FAN);
    s.write("o.obj", "old");
    s.ok(&[
        "map", "in.obj", "--out", "o.obj", "--report", "r.json", "--quiet",
    ]);
    let written = s.read("o.obj");
    assert!(written != "old" && written.contains("\nf "), "{written}");
    let names: Vec<String> = std::fs::read_dir(s.path("."))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}
