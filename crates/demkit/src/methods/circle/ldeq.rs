//! LDEQ: landmark-matching DEQ (Lyu, Choi & Lui 2024, model (4.7)–(4.10)). As DEQ, with
//! interior landmarks `p_i` sent exactly to planar targets `q_i` inside the unit disk: the
//! landmarks travel to their targets during the density-equalizing iteration, each carrying a
//! smooth bump of the map so that nothing folds, then stay pinned through the energy's
//! minimisation (see `deq`). A landmark that cannot reach its target bijectively (for instance one whose
//! target lies in a hole) is reported, and the run does not count as converged.

use super::deq::{self, Request, circle_domain_map, circle_input};
use crate::methods::{MapResult, ProgressFn};
use crate::{Error, Result, TriMesh};

/// LDEQ parameters: those of DEQ.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Config {
    /// The DEQ parameters (α, time step, ε, iteration limit, hole motion).
    pub deq: deq::Config,
}

/// Checks the landmarks: at least one, interior vertices, each once, with planar targets
/// strictly inside the unit disk.
fn check_landmarks(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    landmarks: &[(usize, [f64; 3])],
) -> Result<Vec<(usize, [f64; 2])>> {
    crate::methods::check_landmark_vertices(landmarks, mesh.n_vertices(), "ldeq")?;
    let mut on_boundary = vec![false; mesh.n_vertices()];
    for &v in loops.iter().flatten() {
        on_boundary[v as usize] = true;
    }
    landmarks
        .iter()
        .enumerate()
        .map(|(i, &(v, q))| {
            let i = i + 1;
            if on_boundary[v] {
                return Err(Error::Landmarks(format!(
                    "landmark {i}: vertex {v} is on the boundary; ldeq landmarks must be interior vertices"
                )));
            }
            if !(q[0].hypot(q[1]) < 1.0) || q[2] != 0.0 {
                return Err(Error::Landmarks(format!(
                    "landmark {i}: the target ({}, {}, {}) of vertex {v} must be a point of the plane inside the unit disk",
                    q[0], q[1], q[2]
                )));
            }
            Ok((v, [q[0], q[1]]))
        })
        .collect()
}

/// Computes the LDEQ map of `mesh` (a connected open genus-0 surface) with one `population`
/// value per face and `landmarks` (vertex, planar target). The result lies in the unit disk.
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    landmarks: &[(usize, [f64; 3])],
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    deq::check_config(&config.deq)?;
    let loops = circle_input(mesh, population, "ldeq")?;
    let targets = check_landmarks(mesh, &loops, landmarks)?;
    let request = Request {
        loops: &loops,
        landmarks: &targets,
        config: &config.deq,
        method: "ldeq",
    };
    circle_domain_map(mesh, population, &request, progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;
    use crate::geometry::count_nonpositive;

    #[test]
    fn annulus_landmarks_reach_their_targets_bijectively() {
        let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
        let pop = crate::methods::deq::tests::quadrant_population(&mesh);
        // Four vertices on the middle circle (radius 0.7), their targets a little turned and
        // further out.
        let ring = 6 * 96;
        let landmarks: Vec<(usize, [f64; 3])> = (0..4)
            .map(|k| {
                let a = std::f64::consts::TAU * (0.125 + 0.25 * k as f64) - 0.05;
                (ring + 12 + 24 * k, [0.72 * a.cos(), 0.72 * a.sin(), 0.0])
            })
            .collect();
        let r = run(&mesh, &pop, &landmarks, &Config::default(), &mut |_| {}).unwrap();
        assert!(r.converged, "{:?}", r.notes);
        assert_eq!(count_nonpositive(&r.positions, &mesh.faces), 0);
        for &(v, q) in &landmarks {
            let p = r.positions[v];
            assert!((p[0] - q[0]).hypot(p[1] - q[1]) < 1e-12);
        }
        let m = crate::metrics::compute(
            &mesh,
            &pop,
            &r.initial,
            &r.positions,
            crate::metrics::Domain::Plane,
            None,
        );
        assert!(
            m.face_density_var_final < 0.2,
            "{}",
            m.face_density_var_final
        );
    }

    #[test]
    fn targets_outside_the_disk_and_boundary_landmarks_are_refused() {
        let mesh = annulus(0.4, 1.0, 6, 32).unwrap();
        let pop = vec![1.0; mesh.n_faces()];
        let c = Config::default();
        let outside = [(3 * 32, [1.2, 0.0, 0.0])];
        assert!(matches!(
            run(&mesh, &pop, &outside, &c, &mut |_| {}),
            Err(Error::Landmarks(_))
        ));
        let boundary = [(0, [0.5, 0.0, 0.0])];
        assert!(matches!(
            run(&mesh, &pop, &boundary, &c, &mut |_| {}),
            Err(Error::Landmarks(_))
        ));
    }
}
