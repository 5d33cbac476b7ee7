//! DEQ's density-equalizing map from its initial map: the density-equalizing iteration with
//! the holes filled, then the DEQ energy minimised — directly, or for a large surface through a
//! coarse copy of it ([`super::multilevel`]).

use super::beltrami::Relaxation;
use super::circles::{Circle, CircleBoundary};
use super::energy::Misfit;
use super::layout::Layout;
use super::multilevel::{self, Coarse};
use super::patch::Patch;
use super::{Config, newton, repair};
use crate::fem::DirichletSystem;
use crate::geometry::face_areas;
use crate::methods::disk::planar_diffusion::{self, Problem};
use crate::methods::{Progress, ProgressFn};
use crate::{Result, TriMesh};

/// The density-equalizing iteration stops once sd/mean of the vertex density is below this;
/// the DEQ energy's minimisation does the rest.
const COARSE_EPSILON: f64 = 0.1;

/// The density-equalizing iteration's own iteration limit.
const COARSE_MAX_ITER: usize = 300;

/// Newton iterations at most on the density alone, and their tolerance (see [`direct`]).
const LOG_STAGE_ITERATIONS: usize = 30;
const LOG_STAGE_TOLERANCE: f64 = 1e-2;

/// A density-equalizing circle domain map and how it was reached.
pub(super) struct Equalized {
    /// The surface's vertices in the circle domain.
    pub positions: Vec<[f64; 3]>,
    pub iterations: usize,
    pub history: Vec<f64>,
    /// The DEQ energy's minimisation met its tolerance.
    pub converged: bool,
}

/// One minimisation of the DEQ energy: its density misfit, the weight of the distortion, and
/// when it stops.
#[derive(Debug, Clone, Copy)]
pub(super) struct Stage {
    pub misfit: Misfit,
    pub alpha: f64,
    pub max_iterations: usize,
    pub tolerance: f64,
}

impl Stage {
    /// The DEQ energy as configured: `(ρ̃ − 1)²` with the configured α, iterations and ε.
    pub fn configured(config: &Config) -> Self {
        Self {
            misfit: Misfit::Square,
            alpha: config.alpha,
            max_iterations: config.max_iter,
            tolerance: config.epsilon,
        }
    }
}

/// The DEQ energy of `mesh`'s circle domain maps (loops `layout`, hole loops `holes`) as a
/// Newton problem, with the vertices `pinned` held and the holes kept on their circles when
/// `fixed_holes`.
pub(super) fn energy_problem<'a>(
    mesh: &'a TriMesh,
    population: &'a [f64],
    layout: &'a Layout,
    holes: &'a [Vec<u32>],
    pinned: &'a [u32],
    fixed_holes: bool,
    stage: Stage,
) -> newton::Problem<'a> {
    newton::Problem {
        surface: &mesh.positions,
        faces: &mesh.faces,
        population,
        outer: &layout.outer,
        holes,
        pinned,
        fixed_holes,
        alpha: stage.alpha,
        misfit: stage.misfit,
        max_iterations: stage.max_iterations,
        tolerance: stage.tolerance,
    }
}

/// DEQ's map of `mesh` from its initial map `x` (every hole round, the vertices `keep` to be
/// kept by a coarse copy): for a surface of [`multilevel::MIN_FACES`] faces or more through a
/// coarse copy ([`through_coarse`]) when that works, [`direct`] otherwise.
pub(super) fn equalize(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    x: Vec<[f64; 3]>,
    keep: &[u32],
    config: &Config,
    progress: ProgressFn,
) -> Result<Equalized> {
    let mean = mean_density(mesh, population);
    if mesh.n_faces() >= multilevel::MIN_FACES
        && let Some(e) = through_coarse(mesh, population, layout, &x, keep, config, progress)?
    {
        return Ok(e);
    }
    direct(mesh, population, layout, x, mean, config, progress)
}

/// The map through a coarse copy of the surface: the coarse map ([`direct`]), carried to the
/// surface ([`Coarse::prolong`]), repaired where the density is far off ([`repair`]), then
/// the DEQ energy minimised on the whole surface. `None` when no coarse copy can be built or
/// carried back.
fn through_coarse(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    x: &[[f64; 3]],
    keep: &[u32],
    config: &Config,
    progress: ProgressFn,
) -> Result<Option<Equalized>> {
    let loops: Vec<Vec<u32>> = std::iter::once(layout.outer.clone())
        .chain(layout.holes.iter().map(|h| h.boundary.clone()))
        .collect();
    let Some(coarse) = Coarse::build(mesh, population, &loops, keep, x)? else {
        return Ok(None);
    };
    let coarse_layout = Layout::new(&coarse.mesh, &coarse.loops);
    let g = direct(
        &coarse.mesh,
        &coarse.population,
        &coarse_layout,
        coarse.initial.clone(),
        mean_density(mesh, population),
        config,
        progress,
    )?;
    let Some(mut y) = coarse.prolong(&g.positions, mesh, population, layout)? else {
        return Ok(None);
    };
    let mut history = g.history;
    let local = repair::repair(
        mesh,
        population,
        layout,
        &mut y,
        config.alpha,
        config.epsilon,
        &mut after(progress, history.len(), config.max_iter),
    )?;
    history.extend(&local.history);
    let holes = &loops[1..];
    let fine = newton::minimize(
        &energy_problem(
            mesh,
            population,
            layout,
            holes,
            &[],
            !config.geometry_update,
            Stage::configured(config),
        ),
        &mut y,
        &mut after(progress, history.len(), config.max_iter),
    )?;
    history.extend(&fine.history);
    Ok(Some(Equalized {
        positions: y,
        iterations: g.iterations + local.iterations + fine.iterations,
        history,
        converged: fine.converged,
    }))
}

/// The progress of a stage that follows `done` iterations of the run (sd/mean of the vertex
/// density, the quantity of the density-equalizing iteration before it), passed on to
/// `progress` numbered after them; the limit shown is the iterations done plus `max_iter`.
pub(super) fn after<'p>(
    progress: &'p mut dyn FnMut(Progress),
    done: usize,
    max_iter: usize,
) -> impl FnMut(Progress) + 'p {
    move |p| {
        progress(Progress {
            iteration: done + p.iteration,
            max_iter: done + max_iter,
            error: p.error,
        })
    }
}

/// The population per unit area of the surface.
fn mean_density(mesh: &TriMesh, population: &[f64]) -> f64 {
    population.iter().sum::<f64>() / face_areas(&mesh.positions, &mesh.faces).iter().sum::<f64>()
}

/// DEQ's map of `mesh` from its initial map `x`, computed on the surface itself: the
/// density-equalizing iteration on the disk with every hole filled at `mean_density`
/// ([`Patch`]), until the density is roughly equal; then the DEQ energy minimised, first on
/// `(log ρ̃)²` — which Newton's method handles better far from equal densities (a few
/// triangles crushed by the iteration are reopened in a few steps) — then on `(ρ̃ − 1)²`,
/// what Var(ρ̃) measures, with the distortion term.
pub(super) fn direct(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    mut x: Vec<[f64; 3]>,
    mean_density: f64,
    config: &Config,
    progress: ProgressFn,
) -> Result<Equalized> {
    let holes: Vec<Vec<u32>> = layout.holes.iter().map(|h| h.boundary.clone()).collect();
    let n_surface = mesh.n_vertices();
    let mut held = layout.on_loops(x.len());
    // The hole fillings and the populations of the filled disk.
    let mut patches = Vec::with_capacity(layout.holes.len());
    for hole in &layout.holes {
        let circle = Circle::fit(&x, &hole.boundary);
        patches.push(Patch::build(&mut x, hole, circle)?);
    }
    let mut faces = mesh.faces.clone();
    let mut filled_population = population.to_vec();
    for (hole, p) in layout.holes.iter().zip(&patches) {
        // The hole carries the mean density over the area it spans on the surface.
        let total = mean_density * hole.surface_area;
        let areas = face_areas(&x, &p.faces);
        let sum: f64 = areas.iter().sum();
        filled_population.extend(areas.iter().map(|a| total * a / sum));
        faces.extend_from_slice(&p.faces);
    }

    // The density-equalizing iteration on the filled disk.
    held.resize(x.len(), true);
    let surface = {
        let mut s = mesh.positions.clone();
        s.resize(x.len(), [0.0; 3]);
        s
    };
    let constraint = CircleBoundary {
        outer: &layout.outer,
        holes: &holes,
        fixed_holes: !config.geometry_update,
        patches: &patches,
        region_faces: &mesh.faces,
        extension: DirichletSystem::new(x.len(), &mesh.faces, &held)?,
        relaxation: Relaxation::new(&surface, &mesh.faces, &held)?,
    };
    let problem = Problem {
        faces: &faces,
        population: filled_population,
        n_roi_vertices: n_surface,
        n_roi_faces: mesh.n_faces(),
        constraint: &constraint,
        dt: config.dt,
        epsilon: COARSE_EPSILON,
        max_iter: COARSE_MAX_ITER,
        patience: 5,
    };
    let flow = planar_diffusion::run(&problem, x, progress)?;
    let mut x = flow.positions;
    x.truncate(n_surface);

    let fixed_holes = !config.geometry_update;
    let log_stage = Stage {
        misfit: Misfit::Log,
        alpha: 0.0,
        max_iterations: LOG_STAGE_ITERATIONS,
        tolerance: LOG_STAGE_TOLERANCE,
    };
    let mut history = flow.history;
    let mut stages = Vec::with_capacity(2);
    for stage in [log_stage, Stage::configured(config)] {
        let problem = energy_problem(mesh, population, layout, &holes, &[], fixed_holes, stage);
        let out = newton::minimize(
            &problem,
            &mut x,
            &mut after(progress, history.len(), config.max_iter),
        )?;
        history.extend(&out.history);
        stages.push(out);
    }
    let [log, fine] = [&stages[0], &stages[1]];
    Ok(Equalized {
        positions: x,
        iterations: flow.iterations + log.iterations + fine.iterations,
        history,
        converged: fine.converged,
    })
}
