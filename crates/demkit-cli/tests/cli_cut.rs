//! `demkit cut`: holes cut around points give a surface with one more boundary loop per hole,
//! which DEQ maps onto a circle domain; bad holes exit 2 with one line.

mod common;

use common::{Scratch, json};

#[test]
fn two_holes_in_a_disk_give_three_loops_and_deq_maps_them() {
    let s = Scratch::new("cut-disk");
    s.generate(&["polygon", "--sides", "6", "--rings", "24", "--out", "d.obj"]);
    // The second centre lies 5 above the disk: a cylinder (`--planar`) cuts there, a ball
    // does not.
    const HOLES: [&str; 4] = ["--hole", "0.4,0,0,0.15", "--hole", "-0.4,0.1,5,0.2"];
    let cut = |out: &str, planar: bool| {
        let mut args = vec!["cut", "d.obj", "--out", out];
        args.extend(HOLES);
        if planar {
            args.push("--planar");
        }
        s.ok(&args)
    };
    let out = cut("h.obj", true);
    assert!(out.stderr.contains("3 boundary loops"), "{}", out.stderr);
    let info = json(&s.ok(&["info", "h.obj", "--json"]).stdout);
    assert_eq!(info["boundaries"], 3, "{info}");
    assert_eq!(info["errors"].as_array().map(Vec::len), Some(0), "{info}");
    s.ok(&[
        "map", "h.obj", "--method", "deq", "--out", "m.obj", "--report", "r.json",
    ]);
    let r = json(&s.read("r.json"));
    assert_eq!(r["metrics"]["flipped_triangles"], 0, "{r}");
    cut("b.obj", false);
    let info = json(&s.ok(&["info", "b.obj", "--json"]).stdout);
    assert_eq!(info["boundaries"], 2, "{info}");
}

#[test]
fn bad_holes_and_outputs_are_refused_with_one_line() {
    let s = Scratch::new("cut-refusals");
    s.generate(&["polygon", "--sides", "6", "--rings", "6", "--out", "d.obj"]);
    for (hole, needle) in [
        ("0,0,0", "four numbers"),
        ("0,0,0,x", "four numbers"),
        ("0,0,0,-1", "radius"),
        ("nan,0,0,0.1", "centre"),
        ("0,0,0,100", "no face"),
    ] {
        s.run(&["cut", "d.obj", "--hole", hole, "--out", "h.obj"])
            .input_error_naming(&[needle]);
    }
    s.run(&["cut", "d.obj", "--hole", "0,0,0,0.1", "--out", "d.obj"])
        .input_error();
    s.run(&["cut", "d.obj", "--out", "h.obj"]).assert_code(2);
    assert!(!s.path("h.obj").exists());
}
