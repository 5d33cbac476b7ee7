//! Remeshing the papers' example surfaces through their density-equalizing maps (DEM paper
//! §6.2, SDEM paper §5.2, DEQ paper §7.1, TDEM paper §5), from `DEMKIT_DATA` (default
//! `../shared/data` beside the checkout). Ignored by default: run with
//! `cargo test --release --test real_remesh -- --ignored`.
//!
//! Each remesh asserts the remeshing issue's acceptance figures for 5000 requested vertices:
//! 4500–5500 vertices, the input's number of boundary loops and genus, every vertex within
//! 1e-6 × the bounding-box diagonal of the input surface, triangle areas with coefficient of
//! variation ≤ 0.5 and a median smallest angle ≥ 35°; with the population `area·(1 + 3·[x > 0])`
//! at least 2.5 times more vertices per unit area where x > 0.

use demkit::TriMesh;
use demkit::apps::remesh::quality::{max_distance_to_surface, quality};
use demkit::apps::remesh::{Target, remesh};
use demkit::geometry::face_areas;
use demkit::geometry::torus::Torus;
use demkit::mesh::topology::topology;
use demkit::methods::MethodConfig;
use demkit::methods::{dem, deq, sdem, tdem};
use demkit::population::{PopulationSpec, face_populations};

mod common;
use common::data;

/// The map a surface is remeshed through.
#[derive(Clone, Copy)]
enum Map {
    Dem,
    Deq,
    Sdem,
    Tdem(f64, f64),
}

/// Reads `rel`, maps it with `population`, remeshes it to about `n` vertices; returns the input
/// and the new mesh.
fn remeshed(rel: &str, map: Map, population: &str, n: usize) -> (TriMesh, TriMesh) {
    let mesh = demkit::io::read_mesh(&data(rel)).unwrap();
    let (mesh, _) = demkit::mesh::validate::validate(mesh).unwrap();
    let pop = face_populations(&PopulationSpec::parse(population), &mesh).unwrap();
    let quiet = &mut |_| {};
    let torus = match map {
        Map::Tdem(big, small) => Some(Torus::new(big, small).unwrap()),
        _ => None,
    };
    let r = match map {
        Map::Dem => dem::Config::default().run(&mesh, &pop, quiet),
        // Remeshing maps with DEQ's density-first α, as `demkit remesh` does.
        Map::Deq => {
            let c = deq::Config {
                alpha: demkit::apps::remesh::DEQ_ALPHA,
                ..Default::default()
            };
            c.run(&mesh, &pop, quiet)
        }
        Map::Sdem => sdem::Config::default().run(&mesh, &pop, quiet),
        Map::Tdem(..) => {
            let t = torus.as_ref().unwrap();
            tdem::run(&mesh, &pop, t, &tdem::Config::default(), quiet)
        }
    }
    .unwrap();
    let target = match (map, &r.flat_torus, &torus) {
        (_, Some(flat), Some(t)) => Target::Torus {
            map: flat,
            torus: t,
        },
        (Map::Sdem, _, _) => Target::Sphere,
        _ => Target::Plane,
    };
    let out = remesh(&mesh, &pop, &r.positions, target, n).unwrap();
    (mesh, out)
}

/// Asserts every acceptance figure of a 5000-vertex remesh with population `area`.
fn acceptance(rel: &str, map: Map, boundaries: usize, genus: i64) {
    let _serial = common::SERIAL.lock();
    let (input, out) = remeshed(rel, map, "area", 5000);
    let t = topology(&out);
    let q = quality(&out);
    let diag = demkit::geometry::bounding_box_diagonal(&input.positions);
    let dist = max_distance_to_surface(&out.positions, &input, 1e-6 * diag) / diag;
    eprintln!(
        "{rel}: {} vertices, {} loops, genus {}, distance/diagonal {dist:.1e}, area CV {:.3}, median smallest angle {:.1}°",
        out.n_vertices(),
        t.boundary_loops.len(),
        t.genus,
        q.area_cv,
        q.median_min_angle_deg
    );
    assert!((4500..=5500).contains(&out.n_vertices()), "{rel}");
    assert_eq!(t.n_vertices, out.n_vertices(), "{rel}: unused vertices");
    assert_eq!(
        (t.boundary_loops.len(), t.genus, t.components),
        (boundaries, genus, 1)
    );
    assert!(demkit::mesh::check(&out).is_valid(), "{rel}");
    assert!(dist <= 1e-6, "{rel}: {dist}");
    assert!(q.area_cv <= 0.5, "{rel}: {q:?}");
    assert!(q.median_min_angle_deg >= 35.0, "{rel}: {q:?}");
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_face_remeshes_into_an_even_disk() {
    acceptance("open/human_face.obj", Map::Dem, 1, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn chinese_lion_remeshes_into_an_even_disk() {
    acceptance("open/chinese_lion.obj", Map::Dem, 1, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn max_planck_remeshes_into_an_even_sphere() {
    acceptance("genus0/maxplanck.obj", Map::Sdem, 0, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn buddha_remeshes_into_an_even_sphere() {
    acceptance("genus0/buddha.obj", Map::Sdem, 0, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn bob_remeshes_into_an_even_torus() {
    acceptance("genus1/bob.obj", Map::Tdem(2.0, 1.0), 0, 1);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn vertebra_remeshes_into_an_even_torus() {
    acceptance("genus1/vertebra.obj", Map::Tdem(2.0, 1.0), 0, 1);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn alex_remeshes_with_its_four_boundaries() {
    acceptance("multiply-connected/alex_3.obj", Map::Deq, 4, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn sophie_remeshes_with_its_two_boundaries() {
    acceptance("multiply-connected/sophie.obj", Map::Deq, 2, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_brain_remeshes_evenly_although_its_map_is_rough() {
    acceptance("open/human_brain.obj", Map::Dem, 1, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn lion_remeshes_evenly_with_its_six_boundaries_although_its_map_is_rough() {
    acceptance("multiply-connected/lion_5.obj", Map::Deq, 6, 0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn more_population_on_one_side_of_the_face_puts_more_vertices_there() {
    let _serial = common::SERIAL.lock();
    let (_, out) = remeshed("open/human_face.obj", Map::Dem, "area*(1+3*(x>0))", 5000);
    let areas = face_areas(&out.positions, &out.faces);
    let (mut area_pos, mut area_neg) = (0.0, 0.0);
    for (f, a) in out.faces.iter().zip(&areas) {
        let x: f64 = f.iter().map(|&v| out.positions[v as usize][0]).sum::<f64>() / 3.0;
        if x > 0.0 {
            area_pos += a;
        } else {
            area_neg += a;
        }
    }
    let pos = out.positions.iter().filter(|p| p[0] > 0.0).count() as f64;
    let neg = out.n_vertices() as f64 - pos;
    let ratio = (pos / area_pos) / (neg / area_neg);
    eprintln!("human_face, population area·(1 + 3·[x > 0]): density ratio {ratio:.2}");
    assert!(ratio >= 2.5, "{ratio}");
    assert!((4500..=5500).contains(&out.n_vertices()));
}
