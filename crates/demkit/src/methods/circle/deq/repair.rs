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
use crate::methods::iteration::{Flow, Measured, Moved, count_down};
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
/// `progress`. The rounds run on the density-equalizing iteration ([`count_down`]) as the flow
/// [`Rounds`], at most [`ROUNDS`] of them. Returns the Newton iterations done and their
/// history.
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
    let mut flow = Rounds {
        mesh,
        population,
        outer: &layout.outer,
        neighbours: vertex_neighbours(n, &mesh.faces),
        holes: layout.holes.iter().map(|h| h.boundary.clone()).collect(),
        total_population: population.iter().sum(),
        alpha,
        tolerance,
        progress,
        done: Outcome {
            iterations: 0,
            history: Vec::new(),
            converged: true,
        },
    };
    count_down(&mut flow, x, ROUNDS)?;
    Ok(flow.done)
}

/// The local repair as a flow of the density-equalizing iteration ([`count_down`]: `Step::Own`,
/// `Keep::Last`): the map is the positions; the stopping quantity (and merit) is the number
/// of far-off faces, below 1 when there are none; one advance is one round,
/// the energy minimised by Newton's method ([`newton::minimize`]) on the faces within
/// [`RINGS`] rings of the far-off ones, the region's outer vertices held. The rounds' Newton
/// iterations and histories are summed in `done`, and every Newton iteration is reported to
/// `progress`, numbered after the rounds' so far.
struct Rounds<'a, 'p> {
    mesh: &'a TriMesh,
    population: &'a [f64],
    outer: &'a [u32],
    neighbours: Vec<Vec<u32>>,
    holes: Vec<Vec<u32>>,
    total_population: f64,
    alpha: f64,
    tolerance: f64,
    progress: ProgressFn<'p>,
    /// The rounds' Newton iterations and histories so far.
    done: Outcome,
}

impl Flow for Rounds<'_, '_> {
    type Map = Vec<[f64; 3]>;
    /// The corners of the far-off faces.
    type Data = Vec<u32>;

    /// The far-off faces of `x`: their number, and their corners.
    fn measure(&mut self, x: &Self::Map) -> Result<Measured<Vec<u32>>> {
        let areas = face_areas(x, &self.mesh.faces);
        let total_area: f64 = areas.iter().sum();
        let total_population = self.total_population;
        let far: Vec<&[u32; 3]> = self
            .mesh
            .faces
            .iter()
            .zip(areas.iter().zip(self.population))
            .filter(|(_, (a, p))| {
                let rho = (*p / total_population) / (*a / total_area);
                !(rho < FAR_OFF && rho > 1.0 / FAR_OFF)
            })
            .map(|(f, _)| f)
            .collect();
        Ok(Measured {
            error: far.len() as f64,
            merit: far.len() as f64,
            data: far.into_iter().flatten().copied().collect(),
        })
    }

    /// One round from `x`, whose far-off faces' corners are `m.data`; `fraction` 1 (the
    /// minimisation keeps the map it reaches).
    fn advance(
        &mut self,
        x: &Self::Map,
        m: &Measured<Vec<u32>>,
        _h: f64,
    ) -> Result<Moved<Self::Map>> {
        let mesh = self.mesh;
        let n = mesh.n_vertices();
        let distance = ring_distances(&self.neighbours, m.data.iter().copied(), RINGS);
        let inside = |v: u32| distance[v as usize] != usize::MAX;
        let (faces, region_population): (Vec<[u32; 3]>, Vec<f64>) = mesh
            .faces
            .iter()
            .zip(self.population)
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
            outer: self.outer,
            holes: &self.holes,
            pinned: &pinned,
            fixed_holes: true,
            alpha: self.alpha,
            misfit: Misfit::Square,
            max_iterations: ITERATIONS,
            tolerance: self.tolerance,
        };
        let done_before = self.done.history.len();
        let progress = &mut *self.progress;
        let mut moved = x.clone();
        let outcome = newton::minimize(&problem, &mut moved, &mut |p: Progress| {
            progress(Progress {
                iteration: done_before + p.iteration,
                ..p
            })
        })?;
        self.done.iterations += outcome.iterations;
        self.done.history.extend(outcome.history);
        Ok(Moved {
            map: moved,
            fraction: 1.0,
        })
    }
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
