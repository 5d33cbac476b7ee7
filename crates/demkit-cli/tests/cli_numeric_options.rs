//! Every numeric option of every command at 0, −1, NaN, ±∞ and 1e300: each run either works
//! (exit 0, or 3 when not converged) or is refused before any work with exit 2 and one
//! `error:` line naming the option; never exit 1, a panic or a hang. NaN and ±∞ are refused
//! everywhere.

mod common;

use common::Scratch;

/// The values every option is tried at.
const VALUES: [&str; 6] = ["0", "-1", "NaN", "inf", "-inf", "1e300"];

/// The inputs the command lines read.
fn scratch(label: &str) -> Scratch {
    let s = Scratch::new(label);
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
    s.write("lm.txt", "0\n5\n9\n");
    s.write("targets.txt", "0 1 0 0\n5 0 1 0\n9 0 0 1\n");
    s.write(
        "two.geojson",
        r#"{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{"name":"A","v":1},"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,1],[0,0]]]}},
{"type":"Feature","properties":{"name":"B","v":3},"geometry":{"type":"Polygon","coordinates":[[[1,0],[2,0],[2,1],[1,1],[1,0]]]}}]}"#,
    );
    s
}

/// Runs every template (its words; `V` marks where the value goes, alone or inside a word
/// such as `V:1`) at every value and checks the outcome. `flag` of each template is what the
/// error must name.
fn sweep(s: &Scratch, templates: &[(&str, &str)]) {
    for (template, flag) in templates {
        for value in VALUES {
            let words: Vec<String> = template
                .split_whitespace()
                .map(|w| w.replace('V', value))
                .collect();
            let args: Vec<&str> = words.iter().map(String::as_str).collect();
            let out = s.run(&args);
            let refused_everywhere = matches!(value, "NaN" | "inf" | "-inf");
            match out.code {
                Some(0 | 3) if !refused_everywhere => {}
                _ => {
                    out.input_error_naming(&[flag]);
                }
            }
        }
    }
}

#[test]
fn map_options() {
    let s = scratch("numeric-map");
    let lsdem = "map sphere.obj --method lsdem --landmarks targets.txt --out o.obj --quiet";
    let templates: Vec<(String, &str)> = vec![
        (
            "map disk.obj --out o.obj --quiet --alpha V".into(),
            "--alpha",
        ),
        (
            "map annulus.obj --out o.obj --quiet --alpha V".into(),
            "--alpha",
        ),
        (
            "map annulus.obj --out o.obj --quiet --beta V".into(),
            "--beta",
        ),
        (format!("{lsdem} --alpha V"), "--alpha"),
        (format!("{lsdem} --beta V"), "--beta"),
        (format!("{lsdem} --gamma V"), "--gamma"),
        ("map disk.obj --out o.obj --quiet --dt V".into(), "--dt"),
        ("map sphere.obj --out o.obj --quiet --dt V".into(), "--dt"),
        ("map annulus.obj --out o.obj --quiet --dt V".into(), "--dt"),
        (
            "map torus.obj --torus 3:1 --out o.obj --quiet --dt V".into(),
            "--dt",
        ),
        (
            "map disk.obj --method dem-shape --shape square --out o.obj --quiet --dt V".into(),
            "--dt",
        ),
        (
            "map disk.obj --out o.obj --quiet --epsilon V".into(),
            "--epsilon",
        ),
        (
            "map sphere.obj --out o.obj --quiet --epsilon V".into(),
            "--epsilon",
        ),
        (
            "map annulus.obj --out o.obj --quiet --epsilon V".into(),
            "--epsilon",
        ),
        (
            "map torus.obj --torus 3:1 --out o.obj --quiet --epsilon V".into(),
            "--epsilon",
        ),
        (
            "map disk.obj --out o.obj --quiet --max-iter V".into(),
            "--max-iter",
        ),
        (
            "map sphere.obj --out o.obj --quiet --max-iter V".into(),
            "--max-iter",
        ),
        (
            "map annulus.obj --out o.obj --quiet --max-iter V".into(),
            "--max-iter",
        ),
        (
            "map torus.obj --torus 3:1 --out o.obj --quiet --max-iter V".into(),
            "--max-iter",
        ),
        (
            "map torus.obj --out o.obj --quiet --torus V:1".into(),
            "--torus",
        ),
        (
            "map torus.obj --out o.obj --quiet --torus 3:V".into(),
            "--torus",
        ),
        (
            "map disk.obj --method dem-shape --out o.obj --quiet --shape rectangle:V:1".into(),
            "--shape",
        ),
        (
            "map disk.obj --method dem-shape --out o.obj --quiet --shape rectangle:1:V".into(),
            "--shape",
        ),
        (
            "map disk.obj --method dem-shape --out o.obj --quiet --shape ellipse:V:1".into(),
            "--shape",
        ),
        (
            "map disk.obj --method dem-shape --out o.obj --quiet --shape ellipse:1:V".into(),
            "--shape",
        ),
        (
            "map disk.obj --out o.obj --quiet --render p.png --size V".into(),
            "--size",
        ),
        (
            "map disk.obj --out o.obj --quiet --histogram h.png --size V".into(),
            "--size",
        ),
        // Checked without a picture to draw, too.
        ("map disk.obj --out o.obj --quiet --size V".into(), "--size"),
        (
            "map disk.obj --out o.obj --quiet --view V:30".into(),
            "--view",
        ),
        (
            "map sphere.obj --out o.obj --quiet --render p.png --size 64 --view V:30".into(),
            "--view",
        ),
        (
            "map sphere.obj --out o.obj --quiet --render p.png --size 64 --view 30:V".into(),
            "--view",
        ),
    ];
    let t: Vec<(&str, &str)> = templates.iter().map(|(a, b)| (a.as_str(), *b)).collect();
    sweep(&s, &t);
}

#[test]
fn remesh_register_and_render_options() {
    let s = scratch("numeric-remesh");
    let register = "register sphere.obj sphere.obj --landmarks-a lm.txt --landmarks-b lm.txt \
                    --out g.obj --quiet";
    let templates: Vec<(String, &str)> = vec![
        (
            "remesh disk.obj --out r.obj --quiet --vertices V".into(),
            "--vertices",
        ),
        ("remesh disk.obj --out r.obj --quiet --dt V".into(), "--dt"),
        (
            "remesh sphere.obj --out r.obj --quiet --epsilon V".into(),
            "--epsilon",
        ),
        (
            "remesh disk.obj --out r.obj --quiet --max-iter V".into(),
            "--max-iter",
        ),
        (
            "remesh annulus.obj --out r.obj --quiet --alpha V".into(),
            "--alpha",
        ),
        (
            "remesh torus.obj --out r.obj --quiet --torus V:1".into(),
            "--torus",
        ),
        (format!("{register} --alpha V"), "--alpha"),
        (format!("{register} --beta V"), "--beta"),
        (format!("{register} --gamma V"), "--gamma"),
        (format!("{register} --epsilon V"), "--epsilon"),
        (format!("{register} --max-iter V"), "--max-iter"),
        (
            "render sphere.obj --out p.png --quiet --size V".into(),
            "--size",
        ),
        (
            "render sphere.obj --out p.png --quiet --size 64 --view V:30".into(),
            "--view",
        ),
        (
            "render sphere.obj --out p.png --quiet --size 64 --view 30:V".into(),
            "--view",
        ),
        (
            "subdivide disk.obj --out s.obj --quiet --levels V".into(),
            "--levels",
        ),
        (
            "subdivide disk.obj --out s.obj --quiet --parts V".into(),
            "--parts",
        ),
        (
            "bench --filter no-such-case --max-iter V".into(),
            "--max-iter",
        ),
    ];
    let t: Vec<(&str, &str)> = templates.iter().map(|(a, b)| (a.as_str(), *b)).collect();
    sweep(&s, &t);
}

#[test]
fn cartogram_options() {
    let s = scratch("numeric-cartogram");
    let c = "cartogram two.geojson --value v --out c.geojson --quiet";
    let templates: Vec<(String, &str)> = vec![
        (format!("{c} --max-error V"), "--max-error"),
        (format!("{c} --time-limit V"), "--time-limit"),
        (format!("{c} --grid V"), "--grid"),
        (format!("{c} --max-iter V"), "--max-iter"),
        (format!("{c} --png c.png --size V"), "--size"),
        // Checked without a picture to draw, too.
        (format!("{c} --svg c.svg --size V"), "--size"),
        (format!("{c} --size V"), "--size"),
    ];
    let t: Vec<(&str, &str)> = templates.iter().map(|(a, b)| (a.as_str(), *b)).collect();
    sweep(&s, &t);
}

#[test]
fn generate_options() {
    let s = scratch("numeric-generate");
    let g = "generate --out g.obj";
    let templates: Vec<(String, &str)> = [
        ("grid --nx V", "--nx"),
        ("grid --ny V", "--ny"),
        ("grid --nx 4 --ny 4 --width V", "--width"),
        ("grid --nx 4 --ny 4 --height V", "--height"),
        ("polygon --sides V --rings 4", "--sides"),
        ("polygon --rings V", "--rings"),
        ("peaks --n V", "--n"),
        ("gaussian --n V", "--n"),
        ("annulus --radial 3 --angular 16 --inner V", "--inner"),
        ("annulus --radial 3 --angular 16 --outer V", "--outer"),
        ("annulus --radial V --angular 16", "--radial"),
        ("annulus --radial 3 --angular V", "--angular"),
        ("disk-holes --resolution 16 --hole V:0:0.2", "hole 0"),
        ("disk-holes --resolution 16 --hole 0:V:0.2", "hole 0"),
        ("disk-holes --resolution 16 --hole 0:0:V", "hole 0"),
        ("disk-holes --resolution V --hole 0:0:0.2", "--resolution"),
        ("rect-holes --resolution 16 --width V", "--width"),
        ("rect-holes --resolution 16 --height V", "--height"),
        ("rect-holes --resolution 16 --hole V:0:0.2", "hole 0"),
        ("rect-holes --resolution 16 --hole 0:0:V", "hole 0"),
        ("rect-holes --resolution V", "--resolution"),
        ("icosphere --subdivisions V", "--subdivisions"),
        ("uv-sphere --lat V", "--lat"),
        ("uv-sphere --lon V", "--lon"),
        ("torus --major 12 --minor 6 --R V", "--R"),
        ("torus --major 12 --minor 6 --r V", "--r"),
        ("torus --major V", "--major"),
        ("torus --minor V", "--minor"),
    ]
    .iter()
    .map(|(rest, flag)| (format!("{g} {rest}"), *flag))
    .collect();
    let t: Vec<(&str, &str)> = templates.iter().map(|(a, b)| (a.as_str(), *b)).collect();
    sweep(&s, &t);
}
