//! Shared by the property tests: mesh writers for every format, file mutations, small meshes
//! of every topology, and one call of the method each topology is mapped with.

#![allow(dead_code)]

pub mod formats;
pub mod mutate;

use demkit::methods::{self, MapResult};
use demkit::{Result, TriMesh};

/// Small generated meshes of every topology the methods take: disks (flat and curved),
/// surfaces with one and two holes, spheres and a torus. All of them pass validation.
pub fn small_meshes() -> Vec<TriMesh> {
    use demkit::generate::*;
    vec![
        square_grid(2, 2, 1.0, 1.0).unwrap(),
        square_grid(3, 2, 2.0, 1.0).unwrap(),
        regular_polygon(5, 2).unwrap(),
        peaks(3).unwrap(),
        annulus(0.4, 1.0, 2, 8).unwrap(),
        rectangle_with_holes(2.0, 1.0, &[(-0.5, 0.0, 0.2), (0.5, 0.0, 0.2)], 6).unwrap(),
        icosphere(0).unwrap(),
        uv_sphere(4, 6).unwrap(),
        torus(3.0, 1.0, 8, 5).unwrap(),
    ]
}

/// The iteration limit the property tests run every method with: enough to go through the
/// whole pipeline (initial map, iteration, best map), not to converge.
pub const MAX_ITER: usize = 3;

/// Maps `mesh` with the method its topology calls for (as `--method auto` picks), or with a
/// sibling of it chosen by `variant` (a prescribed shape, a conformal map, landmarks), with
/// few iterations. A mesh no method takes goes to DEM, which must refuse it.
pub fn run_for_topology(
    mesh: &TriMesh,
    population: &[f64],
    landmarks: Option<&[(usize, [f64; 3])]>,
    variant: u8,
) -> Result<MapResult> {
    use methods::*;
    let top = demkit::mesh::topology(mesh);
    let mut quiet = |_| {};
    let loops = top.boundary_loops.len();
    let dem_config = dem::Config {
        max_iter: MAX_ITER,
        ..Default::default()
    };
    let deq_config = deq::Config {
        max_iter: MAX_ITER,
        ..Default::default()
    };
    match (top.components, top.genus, loops) {
        (1, 0, 1..) if landmarks.is_some() => {
            let c = ldeq::Config { deq: deq_config };
            ldeq::run(mesh, population, landmarks.unwrap_or(&[]), &c, &mut quiet)
        }
        (1, 0, 1) => match variant % 4 {
            0 => dem_config.run(mesh, population, &mut quiet),
            1 => {
                let shape = match variant / 4 % 3 {
                    0 => demkit::shape::Shape::Disk,
                    1 => demkit::shape::Shape::Square,
                    _ => demkit::shape::Shape::Rectangle {
                        width: 3.0,
                        height: 2.0,
                    },
                };
                let c = dem_shape::Config {
                    shape,
                    max_iter: MAX_ITER,
                    ..Default::default()
                };
                c.run(mesh, population, &mut quiet)
            }
            2 => circle_conformal::run(mesh, population),
            _ => deq_config.run(mesh, population, &mut quiet),
        },
        (1, 0, 2..) => match variant % 2 {
            0 => deq_config.run(mesh, population, &mut quiet),
            _ => circle_conformal::run(mesh, population),
        },
        (1, 0, 0) => match (landmarks, variant % 2) {
            (Some(l), _) => {
                let c = lsdem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                };
                lsdem::run(mesh, population, l, &c, &mut quiet)
            }
            (None, 0) => {
                let c = sdem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                };
                c.run(mesh, population, &mut quiet)
            }
            (None, _) => spherical_conformal::run(mesh, population),
        },
        (1, 1, 0) => {
            let torus = demkit::geometry::torus::Torus::new(3.0, 1.0)?;
            let c = tdem::Config {
                max_iter: MAX_ITER,
                ..Default::default()
            };
            tdem::run(mesh, population, &torus, &c, &mut quiet)
        }
        _ => dem_config.run(mesh, population, &mut quiet),
    }
}

/// Every public method on `mesh`, each with few iterations (`landmarks` for the landmark
/// methods): the results in a fixed order.
pub fn run_every_method(
    mesh: &TriMesh,
    population: &[f64],
    landmarks: &[(usize, [f64; 3])],
) -> Vec<(&'static str, Result<MapResult>)> {
    use methods::*;
    let mut quiet = |_| {};
    let deq_config = deq::Config {
        max_iter: MAX_ITER,
        ..Default::default()
    };
    let torus = demkit::geometry::torus::Torus::new(3.0, 1.0).unwrap();
    vec![
        (
            "dem",
            demkit::methods::MethodConfig::run(
                &dem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                },
                mesh,
                population,
                &mut quiet,
            ),
        ),
        (
            "dem-shape",
            demkit::methods::MethodConfig::run(
                &dem_shape::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                },
                mesh,
                population,
                &mut quiet,
            ),
        ),
        (
            "sdem",
            demkit::methods::MethodConfig::run(
                &sdem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                },
                mesh,
                population,
                &mut quiet,
            ),
        ),
        (
            "lsdem",
            lsdem::run(
                mesh,
                population,
                landmarks,
                &lsdem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                },
                &mut quiet,
            ),
        ),
        ("deq", deq_config.run(mesh, population, &mut quiet)),
        (
            "ldeq",
            ldeq::run(
                mesh,
                population,
                landmarks,
                &ldeq::Config {
                    deq: deq_config.clone(),
                },
                &mut quiet,
            ),
        ),
        (
            "tdem",
            tdem::run(
                mesh,
                population,
                &torus,
                &tdem::Config {
                    max_iter: MAX_ITER,
                    ..Default::default()
                },
                &mut quiet,
            ),
        ),
        (
            "spherical-conformal",
            spherical_conformal::run(mesh, population),
        ),
        ("circle-conformal", circle_conformal::run(mesh, population)),
    ]
}

/// Checks what every successful map promises: one finite position per input vertex, or, when
/// the method mapped a refinement of the input (DEQ splits the chords of holes), one per vertex
/// of the refinement, which starts with the input's vertices in their order and whose every
/// face is part of an input face.
pub fn check_map(mesh: &TriMesh, result: &MapResult) -> std::result::Result<(), String> {
    let method = result.method;
    let n = match &result.refined {
        None => mesh.n_vertices(),
        Some(r) => {
            let m = &r.mesh;
            if m.n_vertices() < mesh.n_vertices()
                || m.positions[..mesh.n_vertices()] != mesh.positions[..]
            {
                return Err(format!(
                    "{method}: the refined surface does not start with the input's vertices"
                ));
            }
            if r.parent_face.len() != m.n_faces() || r.population.len() != m.n_faces() {
                return Err(format!(
                    "{method}: {} faces, {} parents, {} populations",
                    m.n_faces(),
                    r.parent_face.len(),
                    r.population.len()
                ));
            }
            if r.parent_face.iter().any(|&f| f >= mesh.n_faces()) {
                return Err(format!("{method}: a refined face has no parent"));
            }
            m.n_vertices()
        }
    };
    if result.positions.len() != n {
        return Err(format!(
            "{method}: {} positions for {n} vertices",
            result.positions.len()
        ));
    }
    if let Some(v) = result
        .positions
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(format!(
            "{method}: vertex {v} is mapped to {:?}",
            result.positions[v]
        ));
    }
    Ok(())
}
