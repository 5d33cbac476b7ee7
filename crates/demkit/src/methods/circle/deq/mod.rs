//! DEQ and LDEQ: bijective density-equalizing maps of multiply connected open surfaces (and
//! disks) onto circle domains — the unit disk minus round holes whose centres and radii the
//! method chooses — with low quasi-conformal distortion (Lyu, Choi & Lui 2024, models (4.2)
//! and (4.7)). The algorithm departs from the paper's Algorithms 5.1–5.4 where measurements
//! showed it had to (README, *Deviations*):
//!
//! 1. **Chords** ([`chords`]): an edge joining two vertices of the same hole (the ears and
//!    peninsulas of a jagged rim), which no circle domain can hold outside the hole's circle,
//!    is split at its midpoint.
//! 2. **Initial map** ([`initial`], [`rounding`]): the holes filled with fans, the filled disk
//!    embedded with positive weights and the outer loop on the unit circle, then every hole
//!    made round without folding the map.
//! 3. **Density-equalizing iteration** ([`equalize`]): each hole is filled with a triangulated
//!    disk carrying the hole's share of the population ([`patch`]), and the DEM paper's
//!    diffusion iteration runs on the filled disk (`planar_diffusion`), the outer loop sliding
//!    on the unit circle, each hole moving as a circle — translated, scaled, its vertices
//!    sliding along it: the GM step's domain alteration — ([`circles`]), a Beltrami relaxation
//!    after every move ([`beltrami`]), every step short enough that no triangle flips. It stops
//!    once the density is roughly equal.
//! 4. **DEQ energy** ([`energy`], [`newton`]): the energy (4.2) in its per-face form, density
//!    misfit plus α times the Beltrami coefficient, minimised by projected Newton over circle
//!    domain maps ([`parameters`]), every step bijective; it stops when an iteration lowers
//!    the energy by less than ε.
//! 5. **Large surfaces** ([`multilevel`]): steps 3–4 run on a coarse copy of the surface; the
//!    fine map follows it, its few folded triangles untangled ([`untangle`]), the energy
//!    minimised first around the faces still far off ([`repair`]), then on the whole surface.
//! 6. **LDEQ** ([`landmarks`]): from DEQ's map the landmarks are led to their targets without
//!    folding the map, then the energy is minimised with them pinned.

use crate::methods::MethodConfig;
mod beltrami;
mod chords;
mod circle;
mod circles;
mod energy;
mod equalize;
mod initial;
mod landmarks;
mod layout;
mod multilevel;
mod newton;
mod parameters;
mod patch;
mod repair;
mod rounding;
mod untangle;

use super::refusal::{PLANAR_STAND_IN, numerical, planar_stand_in, refused};
use crate::mesh::topology::topology;
use crate::methods::{MapResult, Progress, ProgressFn, StopReason};
use crate::{Error, Result, TriMesh};
use equalize::{Stage, energy_problem};
use layout::Layout;
use std::time::Instant;

/// LDEQ: each leg of the landmarks' way ([`landmarks::lead`]) is followed by at most this many
/// Newton iterations with the landmarks pinned.
const LEG_ITERATIONS: usize = 3;

/// DEQ parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Weight α of the mean |μ| against the density misfit in the DEQ energy.
    pub alpha: f64,
    /// A fixed time step of the density-equalizing iteration; `None` recomputes it from the
    /// density (DEM paper (4.39)).
    pub dt: Option<f64>,
    /// Stop when a Newton iteration lowers the DEQ energy by less than this fraction of it.
    pub epsilon: f64,
    /// Newton iterations at most.
    pub max_iter: usize,
    /// Let the holes move and change size (false: every hole keeps the circle of the initial
    /// map, the shape-preserving DEQ of §5.1.4).
    pub geometry_update: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            alpha: 2.0,
            dt: None,
            epsilon: 5e-3,
            max_iter: 200,
            geometry_update: true,
        }
    }
}

/// Checks that `mesh` is a connected open surface of genus 0 (a disk or a disk with holes)
/// and `population` has one positive value per face; returns its boundary loops, the outer
/// one first (the loop spanning the largest area).
pub(crate) fn circle_input(
    mesh: &TriMesh,
    population: &[f64],
    method: &str,
) -> Result<Vec<Vec<u32>>> {
    crate::methods::require_valid_mesh(mesh, method)?;
    let topo = topology(mesh);
    if topo.components != 1 || topo.boundary_loops.is_empty() || topo.genus != 0 {
        let what = if topo.boundary_loops.is_empty() {
            format!("a closed surface of genus {}", topo.genus)
        } else if topo.components != 1 {
            format!("a mesh of {} separate pieces", topo.components)
        } else {
            format!(
                "a surface of genus {} with {} boundary loops",
                topo.genus,
                topo.boundary_loops.len()
            )
        };
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!(
                "{method} needs a connected open surface of genus 0 (a disk, possibly with holes), but this is {what}"
            ),
        });
    }
    crate::population::check_population(population, mesh.n_faces())?;
    let mut used = vec![false; mesh.n_vertices()];
    for &v in mesh.faces.iter().flatten() {
        used[v as usize] = true;
    }
    if let Some(v) = used.iter().position(|u| !u) {
        return Err(Error::InvalidMesh(format!(
            "{method}: vertex {v} belongs to no face (drop unused vertices first: \
             mesh::validate::validate does)"
        )));
    }
    crate::init::circle_domain::ordered_loops(mesh, &topo.boundary_loops)
}

/// DEQ's initial map of `mesh` (boundary loops `loops`, the outer one first): a bijective map
/// onto a circle domain, not conformal ([`initial::initial_map`]).
pub(crate) fn initial_circle_domain(
    mesh: &TriMesh,
    population: &[f64],
    loops: &[Vec<u32>],
) -> Result<Vec<[f64; 3]>> {
    initial::initial_map(mesh, population, &Layout::new(mesh, loops))
}

/// The circle (centre, radius) fitted to the loop `lp` of the map `x`.
pub(crate) fn fit_circle(x: &[[f64; 3]], lp: &[u32]) -> ([f64; 2], f64) {
    let c = circles::Circle::fit(x, lp);
    (c.center, c.radius)
}

pub(crate) fn check_config(c: &Config) -> Result<()> {
    crate::methods::iteration::check_parameters(c.epsilon, c.dt, c.max_iter)?;
    if !(c.alpha >= 0.0 && c.alpha.is_finite()) {
        return Err(Error::Argument(format!(
            "alpha must be zero or positive, got {}",
            c.alpha
        )));
    }
    Ok(())
}

impl MethodConfig for Config {
    /// Computes the DEQ map of `mesh` (a connected open genus-0 surface) with one `population`
    /// value per face. The result lies in the unit disk (z = 0), in input vertex order.
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        check_config(self)?;
        let loops = circle_input(mesh, population, "deq")?;
        let request = Request {
            loops: &loops,
            landmarks: &[],
            config: self,
            method: "deq",
        };
        circle_domain_map(mesh, population, &request, progress)
    }
}

/// What DEQ (models (4.2), Algorithms 5.1–5.4) or LDEQ (model (4.7)) is asked to do with a
/// mesh and its population.
pub(crate) struct Request<'a> {
    /// The boundary loops, the outer one first ([`circle_input`]).
    pub loops: &'a [Vec<u32>],
    /// LDEQ's landmarks: interior vertices and their planar targets inside the unit disk
    /// (checked by the caller); none for DEQ.
    pub landmarks: &'a [(usize, [f64; 2])],
    /// The parameters (α, ε, the iteration limit, the geometry update of §5.1.4).
    pub config: &'a Config,
    /// The method's name in the report.
    pub method: &'static str,
}

/// The whole method for DEQ and LDEQ ([`Request`]). A mesh whose holes have chords
/// ([`chords`]) is mapped with them split; the result then carries the refined surface.
pub(crate) fn circle_domain_map(
    mesh: &TriMesh,
    population: &[f64],
    request: &Request,
    progress: ProgressFn,
) -> Result<MapResult> {
    with_chords_split(
        mesh,
        population,
        request.loops,
        |surface, surface_population| chordless_map(surface, surface_population, request, progress),
    )
}

/// `map` (a circle domain map of a mesh and its population) run on `mesh` with the chords of
/// its holes (`loops[1..]`, [`chords`]) split at their midpoints, or on `mesh` itself when
/// there are none; a result of the refined mesh carries it, and a note says so.
pub(crate) fn with_chords_split(
    mesh: &TriMesh,
    population: &[f64],
    loops: &[Vec<u32>],
    map: impl FnOnce(&TriMesh, &[f64]) -> Result<MapResult>,
) -> Result<MapResult> {
    let chords = chords::of_holes(mesh.n_vertices(), &mesh.faces, loops);
    if chords.is_empty() {
        return map(mesh, population);
    }
    let refinement = crate::mesh::split::split_edges(mesh, &chords);
    let refined_population = refinement.population(population);
    let mut result = map(&refinement.mesh, &refined_population)?;
    result.notes.insert(
        0,
        format!(
            "{} edges joined two vertices of the same hole (ears and peninsulas of its rim), \
             which no circle domain can hold outside the hole's circle: each was split at its \
             midpoint, so the map has {} more vertices and {} more faces than the input (the \
             input's come first, in their order)",
            chords.len(),
            refinement.mesh.n_vertices() - mesh.n_vertices(),
            refinement.mesh.n_faces() - mesh.n_faces()
        ),
    );
    result.refined = Some(crate::methods::RefinedSurface {
        mesh: refinement.mesh,
        population: refined_population,
        parent_face: refinement.parent_face,
    });
    Ok(result)
}

/// [`circle_domain_map`] of a mesh whose holes have no chords.
fn chordless_map(
    mesh: &TriMesh,
    population: &[f64],
    request: &Request,
    progress: ProgressFn,
) -> Result<MapResult> {
    let Request {
        loops,
        landmarks,
        config,
        method,
    } = *request;
    let t0 = Instant::now();
    let layout = Layout::new(mesh, loops);
    let holes: Vec<Vec<u32>> = layout.holes.iter().map(|h| h.boundary.clone()).collect();
    let x = match numerical(initial::initial_map(mesh, population, &layout))? {
        Ok(x) => x,
        Err(why) => {
            let x = planar_stand_in(mesh, &layout.outer);
            return Ok(refused(method, x, &why, PLANAR_STAND_IN));
        }
    };
    let initial = x.clone();
    let time_init = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let pinned: Vec<u32> = landmarks.iter().map(|&(v, _)| v as u32).collect();
    let equalized = equalize::equalize(mesh, population, &layout, x, &pinned, config, progress);
    let mut map = match numerical(equalized)? {
        Ok(map) => map,
        Err(why) => {
            let stand_in = "the initial map (bijective, its holes round, not equalized)";
            return Ok(refused(method, initial, &why, stand_in));
        }
    };
    let mut notes = Vec::new();
    // The DEQ energy of the initial map and of the density-equalizing map, before landmarks
    // constrain it: what the run's progress is judged on.
    let energy = energy_problem(
        mesh,
        population,
        &layout,
        &holes,
        &[],
        !config.geometry_update,
        Stage::configured(config),
    );
    let objective = newton::energy_at(&energy, &initial)
        .zip(newton::energy_at(&energy, &map.positions))
        .map(|(before, after)| [before, after]);

    // LDEQ: from DEQ's map the landmarks are led to their targets by short moves, each
    // followed by a few Newton steps with them pinned, which spread out the squeeze the move
    // made; once there, the energy is minimised with them pinned.
    if !landmarks.is_empty() {
        let fixed_holes = !config.geometry_update;
        let minimize = |stage, x: &mut [[f64; 3]], progress: ProgressFn| {
            let problem = energy_problem(
                mesh,
                population,
                &layout,
                &holes,
                &pinned,
                fixed_holes,
                stage,
            );
            newton::minimize(&problem, x, progress)
        };
        let held = layout.on_loops(mesh.n_vertices());
        let targets: Vec<[f64; 2]> = landmarks.iter().map(|l| l.1).collect();
        let leg = Stage {
            max_iterations: LEG_ITERATIONS,
            ..Stage::configured(config)
        };
        let deq_map = map.positions.clone();
        let refuse = |why: String| {
            let stand_in = "DEQ's map before the landmarks were moved (bijective, equalized)";
            Ok(refused(method, deq_map.clone(), &why, stand_in))
        };
        let x = &mut map.positions;
        let n = x.len();
        // Every leg's Newton iterations are numbered after the run's so far.
        let base = map.history.len();
        let mut done = base;
        let legs = landmarks::lead(&mesh.faces, x, &held, n, &pinned, &targets, |x| {
            let out = minimize(leg, x, &mut |p: Progress| {
                progress(Progress {
                    iteration: done + p.iteration,
                    max_iter: base + config.max_iter,
                    error: p.error,
                })
            })?;
            done += out.history.len();
            Ok(out)
        });
        let legs = match numerical(legs)? {
            Ok(legs) => legs,
            Err(why) => return refuse(why),
        };
        map.history.extend(&legs.history);
        let last = minimize(
            Stage::configured(config),
            x,
            &mut equalize::after(progress, map.history.len(), config.max_iter),
        );
        let last = match numerical(last)? {
            Ok(last) => last,
            Err(why) => return refuse(why),
        };
        map.iterations += legs.iterations + last.iterations;
        map.history.extend(&last.history);
        map.converged = last.converged;
        let missed: Vec<String> = landmarks
            .iter()
            .enumerate()
            .filter(|&(_, &(v, q))| x[v][0] != q[0] || x[v][1] != q[1])
            .map(|(k, &(v, _))| format!("{} (vertex {v})", k + 1))
            .collect();
        if !missed.is_empty() {
            map.converged = false;
            notes.push(format!(
                "landmarks {} could not reach their targets without folding the map",
                missed.join(", ")
            ));
        }
    }
    let stop_reason = if map.converged {
        StopReason::Tolerance
    } else {
        StopReason::MaxIter
    };
    let mut result = MapResult::new(
        method,
        map.positions,
        initial,
        stop_reason,
        map.iterations,
        map.history,
    );
    result.objective = objective;
    result.time_init = time_init;
    result.time_map = t1.elapsed().as_secs_f64();
    result.notes = notes;
    Ok(result)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::generate::annulus;
    use crate::geometry::face_areas;
    use crate::metrics::{Domain, compute};
    use circles::Circle;

    /// The four-quadrant population of the DEQ paper's Fig. 6: density 4, 1, 2, 3 by quadrant.
    pub(crate) fn quadrant_population(mesh: &TriMesh) -> Vec<f64> {
        let areas = face_areas(&mesh.positions, &mesh.faces);
        mesh.faces
            .iter()
            .zip(&areas)
            .map(|(f, a)| {
                let c = f.iter().fold([0.0; 2], |s, &v| {
                    let p = mesh.positions[v as usize];
                    [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]
                });
                a * match (c[0] > 0.0, c[1] > 0.0) {
                    (true, true) => 4.0,
                    (false, true) => 1.0,
                    (false, false) => 2.0,
                    (true, false) => 3.0,
                }
            })
            .collect()
    }

    #[test]
    fn annulus_with_four_quadrants_equalizes_bijectively() {
        let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
        let pop = quadrant_population(&mesh);
        let r = Config::default().run(&mesh, &pop, &mut |_| {}).unwrap();
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Plane, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(r.converged);
        // Below the DEQ paper's Table 1 on both (annulus: Var(ρ̃) 0.10, mean |μ| 0.17).
        assert!(
            m.face_density_var_final < 0.08,
            "{}",
            m.face_density_var_final
        );
        assert!(m.mean_abs_mu < 0.1, "{}", m.mean_abs_mu);
    }

    #[test]
    fn a_vertex_of_no_face_is_refused() {
        let mut mesh = annulus(0.4, 1.0, 4, 24).unwrap();
        mesh.positions.push([5.0, 5.0, 0.0]);
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let e = Config::default().run(&mesh, &pop, &mut |_| {}).unwrap_err();
        assert!(e.to_string().contains("belongs to no face"), "{e}");
    }

    #[test]
    fn an_ear_on_a_hole_is_split_and_every_hole_vertex_lies_on_its_circle() {
        // The annulus with an ear glued into its hole on one edge of the inner loop.
        let mut mesh = annulus(0.4, 1.0, 6, 48).unwrap();
        let topo = topology(&mesh);
        let loops = crate::init::circle_domain::ordered_loops(&mesh, &topo.boundary_loops).unwrap();
        let (a, b) = (loops[1][0], loops[1][1]);
        let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        mesh.positions
            .push([0.45 * (pa[0] + pb[0]), 0.45 * (pa[1] + pb[1]), 0.0]);
        let apex = (mesh.n_vertices() - 1) as u32;
        // The loop runs a → b along the face orientation, so the ear runs b → a.
        mesh.faces.push([b, a, apex]);
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let r = Config::default().run(&mesh, &pop, &mut |_| {}).unwrap();
        let refined = r.refined.as_ref().expect("the ear's chord is split");
        assert_eq!(refined.mesh.n_vertices(), mesh.n_vertices() + 1);
        assert_eq!(refined.mesh.n_faces(), mesh.n_faces() + 2);
        assert_eq!(r.positions.len(), refined.mesh.n_vertices());
        let m = compute(
            &refined.mesh,
            &refined.population,
            &r.initial,
            &r.positions,
            Domain::Plane,
            None,
        );
        assert_eq!(m.flipped_triangles, 0);
        let hole = topology(&refined.mesh)
            .boundary_loops
            .into_iter()
            .find(|lp| lp.contains(&apex))
            .unwrap();
        let c = Circle::fit(&r.positions, &hole);
        for &v in &hole {
            let p = r.positions[v as usize];
            let d = (p[0] - c.center[0]).hypot(p[1] - c.center[1]);
            assert!(
                (d - c.radius).abs() < 1e-9 * c.radius,
                "vertex {v}: {d} vs {}",
                c.radius
            );
        }
    }

    #[test]
    fn without_geometry_update_the_holes_keep_their_initial_circles() {
        let mesh =
            crate::generate::disk_with_holes(&[(0.3, 0.0, 0.25), (-0.4, 0.2, 0.15)], 40).unwrap();
        let pop: Vec<f64> = face_areas(&mesh.positions, &mesh.faces)
            .iter()
            .zip(&mesh.faces)
            .map(|(a, f)| a * (1.0 + (mesh.positions[f[0] as usize][1] > 0.0) as u8 as f64))
            .collect();
        let config = Config {
            geometry_update: false,
            ..Config::default()
        };
        let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
        let loops = circle_input(&mesh, &pop, "deq").unwrap();
        for lp in &loops[1..] {
            let (before, after) = (Circle::fit(&r.initial, lp), Circle::fit(&r.positions, lp));
            assert!((before.center[0] - after.center[0]).abs() < 1e-9);
            assert!((before.center[1] - after.center[1]).abs() < 1e-9);
            assert!((before.radius - after.radius).abs() < 1e-9);
        }
        // With the geometry update the holes move.
        let moved = Config::default().run(&mesh, &pop, &mut |_| {}).unwrap();
        let lp = &loops[1];
        let (a, b) = (
            Circle::fit(&moved.initial, lp),
            Circle::fit(&moved.positions, lp),
        );
        assert!(
            (a.center[0] - b.center[0]).hypot(a.center[1] - b.center[1])
                + (a.radius - b.radius).abs()
                > 1e-3
        );
    }
}
