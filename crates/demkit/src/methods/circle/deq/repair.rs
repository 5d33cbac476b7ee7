//! Local repair: the DEQ energy minimised around the faces whose density is far off, the rest
//! of the map held.
//!
//! A map carried from a coarse copy of the surface ([`super::multilevel`]) is right at the
//! coarse scale and wrong at a few hundred faces, where the coarse map bends sharply. Newton's
//! method on the whole surface would spend most of its iterations on them, each costing a
//! factorization of the whole Hessian; on their neighbourhoods alone an iteration costs a few
//! milliseconds. The region's outer vertices and the loops' circles stay put, so the region
//! keeps its area and the map outside it is untouched.

use super::energy::Misfit;
use super::layout::Layout;
use super::newton::{self, Outcome};
use crate::Result;
use crate::TriMesh;
use crate::geometry::face_areas;
use crate::mesh::topology::{ring_distances, vertex_neighbours};
use crate::methods::{Progress, ProgressFn};

/// A face whose relative density `ρ̃ = (P/ΣP) / (A/ΣA)` lies outside `[1/FAR_OFF, FAR_OFF]` is
/// far off.
const FAR_OFF: f64 = 4.0;

/// The neighbourhood minimised around the far-off faces, in rings of vertices.
const RINGS: usize = 3;

/// Rounds (find the far-off faces, minimise around them) at most, and Newton iterations per
/// round.
const ROUNDS: usize = 3;
const ITERATIONS: usize = 20;

/// Minimises the DEQ energy (weight `alpha`, Newton tolerance `tolerance`) of the circle
/// domain map `x` of `mesh` around its far-off faces, reporting every Newton iteration to
/// `progress`. Returns the Newton iterations done and their history.
pub(crate) fn repair(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    x: &mut [[f64; 3]],
    alpha: f64,
    tolerance: f64,
    progress: ProgressFn,
) -> Result<Outcome> {
    let n = mesh.n_vertices();
    let neighbours = vertex_neighbours(n, &mesh.faces);
    let holes: Vec<Vec<u32>> = layout.holes.iter().map(|h| h.boundary.clone()).collect();
    let total_population: f64 = population.iter().sum();
    let mut done = Outcome {
        iterations: 0,
        history: Vec::new(),
        converged: true,
    };
    for _ in 0..ROUNDS {
        let areas = face_areas(x, &mesh.faces);
        let total_area: f64 = areas.iter().sum();
        let far_off: Vec<u32> = mesh
            .faces
            .iter()
            .zip(areas.iter().zip(population))
            .filter(|(_, (a, p))| {
                let rho = (*p / total_population) / (*a / total_area);
                !(rho < FAR_OFF && rho > 1.0 / FAR_OFF)
            })
            .flat_map(|(f, _)| *f)
            .collect();
        if far_off.is_empty() {
            break;
        }
        let distance = ring_distances(&neighbours, far_off, RINGS);
        let inside = |v: u32| distance[v as usize] != usize::MAX;
        let (faces, region_population): (Vec<[u32; 3]>, Vec<f64>) = mesh
            .faces
            .iter()
            .zip(population)
            .filter(|(f, _)| f.iter().any(|&v| inside(v)))
            .map(|(f, p)| (*f, *p))
            .unzip();
        // The region's outer vertices are held.
        let mut rim = vec![false; n];
        for f in &faces {
            for &v in f {
                rim[v as usize] = !inside(v);
            }
        }
        let pinned: Vec<u32> = (0..n as u32).filter(|&v| rim[v as usize]).collect();
        let problem = newton::Problem {
            surface: &mesh.positions,
            faces: &faces,
            population: &region_population,
            outer: &layout.outer,
            holes: &holes,
            pinned: &pinned,
            fixed_holes: true,
            alpha,
            misfit: Misfit::Square,
            max_iterations: ITERATIONS,
            tolerance,
        };
        let done_before = done.history.len();
        let outcome = newton::minimize(&problem, x, &mut |p: Progress| {
            progress(Progress {
                iteration: done_before + p.iteration,
                ..p
            })
        })?;
        done.iterations += outcome.iterations;
        done.history.extend(outcome.history);
    }
    Ok(done)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;
    use crate::geometry::count_nonpositive;
    use crate::init::circle_domain::ordered_loops;
    use crate::mesh::topology::topology;

    #[test]
    fn faces_squeezed_far_off_are_reopened_and_the_rest_of_the_map_stays() {
        // The annulus as its own circle domain map (area population: every face at density 1),
        // then one interior vertex pushed most of the way towards a neighbour.
        let mesh = annulus(0.4, 1.0, 10, 60).unwrap();
        let population = face_areas(&mesh.positions, &mesh.faces);
        let loops = ordered_loops(&mesh, &topology(&mesh).boundary_loops).unwrap();
        let layout = Layout::new(&mesh, &loops);
        let mut x = mesh.positions.clone();
        let v = (0..mesh.n_vertices())
            .find(|&v| (mesh.positions[v][0].hypot(mesh.positions[v][1]) - 0.7).abs() < 0.02)
            .unwrap();
        let w = vertex_neighbours(mesh.n_vertices(), &mesh.faces)[v][0] as usize;
        let target = x[w];
        for (p, q) in x[v].iter_mut().zip(target).take(2) {
            *p += 0.85 * (q - *p);
        }
        assert_eq!(count_nonpositive(&x, &mesh.faces), 0);
        let far_off = |x: &[[f64; 3]]| {
            let a = face_areas(x, &mesh.faces);
            a.iter()
                .zip(&population)
                .filter(|(a, p)| !((*p / *a) < FAR_OFF && (*p / *a) > 1.0 / FAR_OFF))
                .count()
        };
        assert!(far_off(&x) > 0);
        let before = x.clone();
        repair(&mesh, &population, &layout, &mut x, 0.0, 1e-6, &mut |_| {}).unwrap();
        assert_eq!(count_nonpositive(&x, &mesh.faces), 0);
        assert_eq!(far_off(&x), 0);
        // Vertices beyond the neighbourhood did not move.
        let nb = vertex_neighbours(mesh.n_vertices(), &mesh.faces);
        let near = ring_distances(&nb, [v as u32, w as u32], RINGS + 2);
        for u in 0..mesh.n_vertices() {
            if near[u] == usize::MAX {
                assert_eq!(x[u], before[u]);
            }
        }
    }
}
