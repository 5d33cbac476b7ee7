//! The issues' time budgets on the papers' real meshes, one criterion case each, on the mesh
//! and settings of the real-mesh test that used to assert it (`tests/real_*.rs`, which now only
//! print their times). Each case's name carries its budget, printed beside the measured time;
//! a budget is a figure for an idle 2-core machine, not a pass/fail check.
//!
//! The meshes come from `DEMKIT_DATA` (default `../shared/data` beside the checkout); without
//! them every case is skipped with a message. Run one case with, e.g.,
//! `cargo bench -p demkit --bench real_meshes -- human_face`.

use demkit::methods::MethodConfig;
mod budget;

use budget::cut::{cut_holes, random_holes};
use budget::{case, data_root, ldeq_landmarks, load, population, run_deq, slow_group};
use criterion::{Criterion, criterion_group, criterion_main};
use demkit::geometry::torus::Torus;
use demkit::init::circle_domain::circle_domain_map_with_report;
use demkit::init::genus_one::flat_torus_map_with_report;
use demkit::methods::{dem, dem_shape, ldeq, lsdem, sdem, tdem};
use demkit::shape::Shape;
use std::path::Path;

/// The radii of `genus1/NAME.torus.txt` (lines `R value` and `r value`).
fn radii(root: &Path, name: &str) -> Torus {
    let text = std::fs::read_to_string(root.join(format!("genus1/{name}.torus.txt"))).unwrap();
    let value = |key: &str| -> f64 {
        text.lines()
            .filter_map(|l| l.split_once(' '))
            .find(|(k, _)| k.trim() == key)
            .map(|(_, v)| v.trim().parse().unwrap())
            .unwrap()
    };
    Torus::new(value("R"), value("r")).unwrap()
}

/// The path of a data file as a population spec.
fn file_spec(root: &Path, rel: &str) -> String {
    root.join(rel).to_str().unwrap().to_string()
}

/// Parsing the hand scan's OBJ (105 860 faces): 0.3 s.
fn reading(c: &mut Criterion) {
    let Some(root) = data_root("OBJ reading") else {
        return;
    };
    let mut g = slow_group(c, "read");
    case(
        &mut g,
        "open/hand.obj parsed",
        0.3,
        || std::fs::read(root.join("open/hand.obj")).unwrap(),
        |data| demkit::io::obj::parse_obj(data, "hand.obj").unwrap(),
    );
    g.finish();
}

/// DEM with population = area (tests/real_meshes.rs): the face and the lion 3 s, the hand and
/// the brain 15 s; shape-prescribed DEM of the face onto a disk, a 3 × 2 rectangle and a 2:1
/// ellipse, 3 s each.
fn dem_budgets(c: &mut Criterion) {
    let Some(root) = data_root("DEM") else {
        return;
    };
    let mut g = slow_group(c, "dem");
    for (rel, budget) in [
        ("open/human_face.obj", 3.0),
        ("open/chinese_lion.obj", 3.0),
        ("open/hand.obj", 15.0),
        ("open/human_brain.obj", 15.0),
    ] {
        let setup = || {
            let mesh = load(&root, rel);
            let pop = population(&mesh, "area");
            (mesh, pop)
        };
        case(&mut g, rel, budget, setup, |(mesh, pop)| {
            dem::Config::default().run(mesh, pop, &mut |_| {}).unwrap()
        });
    }
    let shapes = [
        ("disk", Shape::Disk),
        (
            "rectangle 3x2",
            Shape::Rectangle {
                width: 3.0,
                height: 2.0,
            },
        ),
        ("ellipse 2:1", Shape::Ellipse { a: 2.0, b: 1.0 }),
    ];
    for (label, shape) in shapes {
        let setup = || {
            let mesh = load(&root, "open/human_face.obj");
            let pop = population(&mesh, "area");
            (mesh, pop)
        };
        let name = format!("open/human_face.obj onto a {label}");
        case(&mut g, &name, 3.0, setup, |(mesh, pop)| {
            let config = dem_shape::Config {
                shape,
                ..Default::default()
            };
            config.run(mesh, pop, &mut |_| {}).unwrap()
        });
    }
    g.finish();
}

/// SDEM and LSDEM, initial map included (tests/real_spheres.rs).
fn sphere_budgets(c: &mut Criterion) {
    let Some(root) = data_root("SDEM") else {
        return;
    };
    let mut g = slow_group(c, "sdem");
    for (name, population_file, budget) in [
        ("david1", true, 1.5),
        ("david2", true, 1.5),
        ("twistedball", false, 2.5),
        ("maxplanck", false, 2.5),
        ("duck", false, 2.5),
        ("brain", false, 15.0),
        ("lion", false, 15.0),
        ("sphere", true, 2.5),
    ] {
        let setup = || {
            let mesh = load(&root, &format!("genus0/{name}.obj"));
            let spec = if population_file {
                file_spec(&root, &format!("genus0/{name}.population.txt"))
            } else {
                "area".to_string()
            };
            let pop = population(&mesh, &spec);
            (mesh, pop)
        };
        case(&mut g, name, budget, setup, |(mesh, pop)| {
            sdem::Config::default().run(mesh, pop, &mut |_| {}).unwrap()
        });
    }
    for (name, budget) in [("sphere_with_landmark", 5.0), ("brain_with_landmark", 15.0)] {
        let setup = || {
            let mesh = load(&root, &format!("genus0/{name}.obj"));
            let spec = file_spec(&root, &format!("genus0/{name}.population.txt"));
            let pop = population(&mesh, &spec);
            let landmarks = demkit::io::read_landmarks(
                &root.join(format!("genus0/{name}.landmarks.txt")),
                mesh.n_vertices(),
            )
            .unwrap();
            let landmarks: Vec<(usize, [f64; 3])> = landmarks
                .into_iter()
                .map(|l| (l.vertex, l.target))
                .collect();
            (mesh, pop, landmarks)
        };
        let label = format!("{name}, lsdem");
        case(&mut g, &label, budget, setup, |(mesh, pop, l)| {
            lsdem::run(mesh, pop, l, &lsdem::Config::default(), &mut |_| {}).unwrap()
        });
    }
    g.finish();
}

/// TDEM (tests/real_tori.rs): the example tori with their populations, 1 s; the genus-one
/// models with population = area, 5 s; and the initial flat-torus map alone
/// (tests/real_genus_one.rs), 1 s.
fn torus_budgets(c: &mut Criterion) {
    let Some(root) = data_root("TDEM") else {
        return;
    };
    let mut g = slow_group(c, "tdem");
    let tori = [
        "torus_1",
        "torus_2",
        "torus_3",
        "torus_4",
        "torus_5_1",
        "torus_R2",
        "torus_R10",
    ];
    let models = ["bob", "bracelet", "rocker_arm", "twisted", "vertebra"];
    let cases = tori
        .iter()
        .map(|t| (*t, 1.0, true))
        .chain(models.iter().map(|m| (*m, 5.0, false)));
    for (name, budget, population_file) in cases {
        let setup = || {
            let mesh = load(&root, &format!("genus1/{name}.obj"));
            let spec = if population_file {
                file_spec(&root, &format!("genus1/{name}.population.txt"))
            } else {
                "area".to_string()
            };
            let pop = population(&mesh, &spec);
            (mesh, pop, radii(&root, name))
        };
        case(&mut g, name, budget, setup, |(mesh, pop, torus)| {
            tdem::run(mesh, pop, torus, &tdem::Config::default(), &mut |_| {}).unwrap()
        });
    }
    g.finish();
    let mut g = slow_group(c, "flat torus map");
    for name in models {
        let setup = || {
            (
                load(&root, &format!("genus1/{name}.obj")),
                radii(&root, name),
            )
        };
        case(&mut g, name, 1.0, setup, |(mesh, torus)| {
            flat_torus_map_with_report(mesh, torus).unwrap()
        });
    }
    g.finish();
}

/// The circle domain map (tests/real_circle_domain.rs), 1 s each.
fn circle_domain_budgets(c: &mut Criterion) {
    let Some(root) = data_root("circle domain") else {
        return;
    };
    let mut g = slow_group(c, "circle domain map");
    for rel in [
        "multiply-connected/alex_3.obj",
        "multiply-connected/lion_5.obj",
        "multiply-connected/peaks_7.obj",
        "multiply-connected/sophie.obj",
        "multiply-connected/amoeba1.obj",
        "open/human_face.obj",
    ] {
        let setup = || {
            let mesh = load(&root, rel);
            let loops = demkit::mesh::topology::topology(&mesh).boundary_loops;
            (mesh, loops)
        };
        case(&mut g, rel, 1.0, setup, |(mesh, loops)| {
            circle_domain_map_with_report(mesh, loops).unwrap()
        });
    }
    g.finish();
}

/// DEQ and LDEQ on the real meshes and on holes cut into them (tests/real_deq.rs), 15 s each.
fn deq_budgets(c: &mut Criterion) {
    let Some(root) = data_root("DEQ") else {
        return;
    };
    let mut g = slow_group(c, "deq");
    for rel in [
        "multiply-connected/alex_3.obj",
        "multiply-connected/sophie.obj",
        "multiply-connected/amoeba1.obj",
        "multiply-connected/lion_5.obj",
        "multiply-connected/peaks_7.obj",
        "multiply-connected/amoeba2.obj",
        "open/human_face.obj",
    ] {
        let setup = || {
            let mesh = load(&root, rel);
            let pop = population(&mesh, "area");
            (mesh, pop)
        };
        case(&mut g, rel, 15.0, setup, |(mesh, pop)| run_deq(mesh, pop));
    }
    let face_with_eye_holes = || {
        let face = load(&root, "open/human_face.obj");
        let eyes = [([0.028, 0.265, 0.0], 0.012), ([-0.028, 0.265, 0.0], 0.012)];
        cut_holes(&face, &eyes, true)
    };
    let balls = [
        ([0.003108, 0.240116, 0.100035], 0.006274),
        ([-0.052453, 0.281069, 0.071058], 0.006089),
        ([0.038877, 0.264829, 0.082188], 0.008868),
    ];
    type Make<'a> = Box<dyn Fn() -> (demkit::TriMesh, &'static str) + 'a>;
    let made: Vec<(&str, Make)> = vec![
        (
            "face with eye holes",
            Box::new(|| (face_with_eye_holes(), "area")),
        ),
        (
            "face with eye holes, bump",
            Box::new(|| {
                let bump = "area*(1+4*exp(-((x-0.02)^2+(y-0.2)^2)/0.0005))";
                (face_with_eye_holes(), bump)
            }),
        ),
        (
            "chinese lion, 3 holes",
            Box::new(|| {
                let lion = load(&root, "open/chinese_lion.obj");
                (
                    cut_holes(&lion, &random_holes(&lion, 3, 1, 0.04), false),
                    "area",
                )
            }),
        ),
        (
            "face, three ball cuts",
            Box::new(|| {
                let face = load(&root, "open/human_face.obj");
                (cut_holes(&face, &balls, false), "area")
            }),
        ),
        (
            "hand, 3 holes",
            Box::new(|| {
                let hand = load(&root, "open/hand.obj");
                (
                    cut_holes(&hand, &random_holes(&hand, 3, 2, 0.03), false),
                    "area",
                )
            }),
        ),
        (
            "human brain, 4 holes",
            Box::new(|| {
                let brain = load(&root, "open/human_brain.obj");
                let holes = random_holes(&brain, 4, 9, 0.03);
                (
                    cut_holes(&brain, &holes, false),
                    "area*(1+exp(-(x^2+y^2)/2000))",
                )
            }),
        ),
    ];
    for (name, make) in &made {
        let setup = || {
            let (mesh, spec) = make();
            let pop = population(&mesh, spec);
            (mesh, pop)
        };
        case(&mut g, name, 15.0, setup, |(mesh, pop)| run_deq(mesh, pop));
    }
    let setup = || {
        let mesh = face_with_eye_holes();
        let pop = population(&mesh, "area");
        let landmarks = ldeq_landmarks(&mesh, &pop, 5, 0.05);
        (mesh, pop, landmarks)
    };
    case(
        &mut g,
        "LDEQ face with eye holes",
        15.0,
        setup,
        |(mesh, pop, l)| ldeq::run(mesh, pop, l, &ldeq::Config::default(), &mut |_| {}).unwrap(),
    );
    g.finish();
}

criterion_group!(
    benches,
    reading,
    dem_budgets,
    sphere_budgets,
    torus_budgets,
    circle_domain_budgets,
    deq_budgets
);
criterion_main!(benches);
