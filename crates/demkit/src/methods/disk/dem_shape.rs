//! Shape-prescribed DEM (Choi & Rycroft 2018, Algorithm 6): Tutte's map onto the shape with an
//! arclength-parameterized boundary, no sea, and boundary vertices projected back onto the
//! shape after every step (they slide along it). Recoupling and the bijectivity safeguard as in
//! DEM. The result stays in the shape's own coordinates (no final rescale), so the boundary lies
//! exactly on the prescribed curve.

use super::input::disk_boundary;
use super::planar_diffusion::{self, Problem};
use crate::geometry::signed_areas_2d;
use crate::geometry::{norm, sub};
use crate::init::tutte::{InteriorWeights, fixed_boundary_map};
use crate::methods::MethodConfig;
use crate::methods::iteration::check_parameters;
use crate::methods::{MapResult, ProgressFn};
use crate::shape::Shape;
use crate::{Error, Result, TriMesh};
use std::time::Instant;

/// Shape-prescribed DEM parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The target boundary shape.
    pub shape: Shape,
    /// Stop when sd/mean of the (recoupled) vertex density is below ε.
    pub epsilon: f64,
    /// Iteration limit.
    pub max_iter: usize,
    /// Time step; `None` uses (4.39).
    pub dt: Option<f64>,
    /// Stop as stationary when the best density error has improved by less than 2% over this
    /// many iterations.
    pub patience: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            shape: Shape::Disk,
            epsilon: 1e-3,
            max_iter: 500,
            dt: None,
            patience: 5,
        }
    }
}

impl MethodConfig for Config {
    /// Computes the shape-prescribed DEM of `mesh` (a topological disk).
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        check_parameters(self.epsilon, self.dt, self.max_iter)?;
        let t0 = Instant::now();
        let boundary = disk_boundary(mesh, population, "dem-shape")?;
        let faces = &mesh.faces;
        let lengths: Vec<f64> = (0..boundary.len())
            .map(|k| {
                let a = mesh.positions[boundary[k] as usize];
                let b = mesh.positions[boundary[(k + 1) % boundary.len()] as usize];
                norm(sub(b, a))
            })
            .collect();
        let bp = shape_boundary(mesh, &boundary, &lengths, self.shape)?;
        let initial = fixed_boundary_map(
            &mesh.positions,
            faces,
            &boundary,
            &bp,
            InteriorWeights::Tutte,
        )?;
        if let Some(f) = signed_areas_2d(&initial, faces)
            .iter()
            .position(|&a| !(a > 0.0))
        {
            return Err(Error::Numerical(format!(
                "the initial map onto the shape is degenerate at face {f}; try the shape disk or ellipse"
            )));
        }
        let time_init = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let constraint = planar_diffusion::OnShape {
            boundary,
            shape: self.shape,
        };
        let problem = Problem {
            faces,
            population: population.to_vec(),
            n_roi_vertices: mesh.n_vertices(),
            n_roi_faces: mesh.n_faces(),
            constraint: &constraint,
            dt: self.dt,
            epsilon: self.epsilon,
            max_iter: self.max_iter,
            patience: self.patience,
        };
        let out = planar_diffusion::run(&problem, initial.clone(), progress)?;
        let mut result = MapResult::new(
            "dem-shape",
            out.positions,
            initial,
            out.stop_reason,
            out.iterations,
            out.history,
        );
        result.time_init = time_init;
        result.time_map = t1.elapsed().as_secs_f64();
        Ok(result)
    }
}

/// The corners of a shape with straight sides, counter-clockwise, starting after the positive
/// x axis (the start of [`Shape::point_at`]); `None` for smooth shapes.
fn corners(shape: Shape) -> Option<[[f64; 2]; 4]> {
    let (w, h) = match shape {
        Shape::Square => (2.0, 2.0),
        Shape::Rectangle { width, height } => (width, height),
        Shape::Disk | Shape::Ellipse { .. } => return None,
    };
    Some([
        [w / 2.0, h / 2.0],
        [-w / 2.0, h / 2.0],
        [-w / 2.0, -h / 2.0],
        [w / 2.0, -h / 2.0],
    ])
}

/// Positions of the boundary loop on the prescribed shape, by arclength (Alg. 6 line 1).
/// On a shape with corners, a boundary "ear" (a vertex with a single triangle) must sit at a
/// corner — three consecutive boundary vertices on one straight side would make its triangle
/// flat — so ears are snapped to the nearest corners, the remaining corners take the boundary
/// vertices nearest to them by arclength, and each side is laid out by arclength between its
/// two corner vertices. More ears than corners cannot be mapped bijectively: an error.
fn shape_boundary(
    mesh: &TriMesh,
    boundary: &[u32],
    lengths: &[f64],
    shape: Shape,
) -> Result<Vec<[f64; 2]>> {
    let Some(corner_points) = corners(shape) else {
        return Ok(shape.boundary_positions(lengths));
    };
    let n = boundary.len();
    let total: f64 = lengths.iter().sum();
    let mut frac = Vec::with_capacity(n);
    let mut acc = 0.0;
    for l in lengths {
        frac.push(acc / total);
        acc += l;
    }
    let mut face_count = vec![0usize; mesh.n_vertices()];
    for f in &mesh.faces {
        for &v in f {
            face_count[v as usize] += 1;
        }
    }
    let ears: Vec<usize> = (0..n)
        .filter(|&k| face_count[boundary[k] as usize] == 1)
        .collect();
    if ears.len() > 4 || n < 8 {
        return Err(Error::Topology {
            method: "dem-shape".into(),
            msg: format!(
                "the boundary has {} vertices with a single triangle (ears); a shape with straight sides can host at most 4, one per corner: use the shape disk or ellipse",
                ears.len()
            ),
        });
    }
    // Arclength fraction of each corner along the shape, from the start of point_at.
    let perimeter = shape.perimeter();
    let mut corner_frac = [0.0; 4];
    let mut prev = shape.point_at(0.0);
    let mut s = 0.0;
    for (j, c) in corner_points.iter().enumerate() {
        s += (c[0] - prev[0]).hypot(c[1] - prev[1]);
        corner_frac[j] = s / perimeter;
        prev = *c;
    }
    let cyc = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(1.0);
        d.min(1.0 - d)
    };
    let mut chosen: [Option<usize>; 4] = [None; 4];
    for &k in &ears {
        let j = (0..4)
            .min_by(|&a, &b| cyc(frac[k], corner_frac[a]).total_cmp(&cyc(frac[k], corner_frac[b])))
            .unwrap_or(0);
        let j = (0..4)
            .map(|d| (j + d) % 4)
            .find(|&j| chosen[j].is_none())
            .unwrap_or(j);
        chosen[j] = Some(k);
    }
    for j in 0..4 {
        if chosen[j].is_none() {
            let k = (0..n)
                .filter(|k| !chosen.contains(&Some(*k)))
                .min_by(|&a, &b| {
                    cyc(frac[a], corner_frac[j]).total_cmp(&cyc(frac[b], corner_frac[j]))
                })
                .unwrap_or(0);
            chosen[j] = Some(k);
        }
    }
    let c: Vec<usize> = chosen.iter().map(|k| k.unwrap_or(0)).collect();
    // The corner vertices must follow the loop in the corners' cyclic order.
    let start = c[0];
    let rel: Vec<usize> = c.iter().map(|&k| (k + n - start) % n).collect();
    if !(rel[0] < rel[1] && rel[1] < rel[2] && rel[2] < rel[3]) {
        return Err(Error::Topology {
            method: "dem-shape".into(),
            msg: "the boundary's ears cannot be placed at the shape's corners in order: use the shape disk or ellipse".into(),
        });
    }
    let mut out = vec![[0.0; 2]; n];
    for j in 0..4 {
        let (a, b) = (corner_points[j], corner_points[(j + 1) % 4]);
        let (k0, steps) = (c[j], (c[(j + 1) % 4] + n - c[j]) % n);
        let side: f64 = (0..steps).map(|i| lengths[(k0 + i) % n]).sum();
        let mut acc = 0.0;
        for i in 0..steps {
            let t = if side > 0.0 {
                acc / side
            } else {
                i as f64 / steps as f64
            };
            out[(k0 + i) % n] = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            acc += lengths[(k0 + i) % n];
        }
    }
    Ok(out)
}
