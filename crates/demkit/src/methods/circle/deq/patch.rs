//! The filling of a round hole during the density-equalizing iteration: a triangulated disk
//! inside the hole's circle that carries the hole's share of the population at a uniform
//! density, so the density diffuses through the hole as through the sea of the DEM paper
//! (§4.3) and the hole grows or shrinks with it instead of standing as a wall.
//!
//! The filling is a constrained Delaunay triangulation of the hole's circle: its loop plus
//! rings of points whose spacing grows by a quarter per ring towards the centre. Its vertices
//! inside the circle are laid out again after every move by Tutte's embedding with the circle's vertices
//! fixed — a convex boundary, so the filling never folds, whatever the hole did.

use super::circle::Circle;
use super::layout::Hole;
use crate::Result;
use crate::fem::{DirichletSystem, uniform_weights};
use crate::geometry::segment::polygon_distance;
use crate::mesh::triangulate::{constrained_delaunay, faces_inside, inside_loops};
use std::f64::consts::TAU;

/// Ring spacing growth towards the centre.
const GROWTH: f64 = 1.25;

/// One hole's filling.
pub(crate) struct Patch {
    /// Vertices of the patch (the map's numbering): the circle's loop first, then the inside.
    vertices: Vec<u32>,
    n_boundary: usize,
    /// Faces in the map's numbering.
    pub faces: Vec<[u32; 3]>,
    /// The same faces in the patch's own numbering.
    local_faces: Vec<[u32; 3]>,
    system: DirichletSystem,
}

impl Patch {
    /// Fills the hole `hole`, whose loop lies on `circle` in the map `x`; the filling's points
    /// are appended to `x`.
    pub fn build(x: &mut Vec<[f64; 3]>, hole: &Hole, circle: Circle) -> Result<Self> {
        let lp = &hole.boundary;
        let m = lp.len();
        let mut points: Vec<[f64; 2]> = lp
            .iter()
            .map(|&v| [x[v as usize][0], x[v as usize][1]])
            .collect();
        let segments: Vec<[usize; 2]> = (0..m).map(|k| [k, (k + 1) % m]).collect();
        let polygon = vec![(0..m).collect::<Vec<usize>>()];
        let mut s = TAU * circle.radius / m as f64;
        let mut r = circle.radius - 0.9 * s;
        let mut ring = 0;
        while r > 0.6 * s {
            let count = ((TAU * r / s).round() as usize).max(5);
            let offset = if ring % 2 == 0 { 0.0 } else { 0.5 };
            for k in 0..count {
                let t = TAU * (k as f64 + offset) / count as f64;
                let q = [
                    circle.center[0] + r * t.cos(),
                    circle.center[1] + r * t.sin(),
                ];
                if inside_loops(&points, &polygon, q)
                    && polygon_distance(points[..m].iter().copied(), q) > 0.4 * s
                {
                    points.push(q);
                }
            }
            s *= GROWTH;
            r -= 0.87 * s;
            ring += 1;
        }
        if r > -0.3 * s {
            let q = circle.center;
            if inside_loops(&points, &polygon, q)
                && polygon_distance(points[..m].iter().copied(), q) > 0.3 * s
            {
                points.push(q);
            }
        }
        let cdt = constrained_delaunay(&points, &segments)?;
        let fill = faces_inside(&cdt.points, &cdt.faces, &polygon);
        let first_new = x.len() as u32;
        for q in &points[m..] {
            x.push([q[0], q[1], 0.0]);
        }
        let global = |k: u32| -> u32 {
            if (k as usize) < m {
                lp[k as usize]
            } else {
                first_new + k - m as u32
            }
        };
        let faces: Vec<[u32; 3]> = fill.iter().map(|f| f.map(global)).collect();
        // The patch's own numbering: circle loop, then every other vertex of its faces.
        let mut vertices = lp.clone();
        let n_boundary = vertices.len();
        let mut local = std::collections::HashMap::new();
        for (k, &v) in vertices.iter().enumerate() {
            local.insert(v, k as u32);
        }
        for f in &faces {
            for &v in f {
                local.entry(v).or_insert_with(|| {
                    vertices.push(v);
                    (vertices.len() - 1) as u32
                });
            }
        }
        let local_faces: Vec<[u32; 3]> = faces.iter().map(|f| f.map(|v| local[&v])).collect();
        let fixed: Vec<bool> = (0..vertices.len()).map(|k| k < n_boundary).collect();
        let system = DirichletSystem::new(vertices.len(), &local_faces, &fixed)?;
        let patch = Self {
            vertices,
            n_boundary,
            faces,
            local_faces,
            system,
        };
        patch.place(x);
        Ok(patch)
    }

    /// Lays out the inside of the patch by Tutte's embedding with the circle loop where `x`
    /// has it.
    pub fn place(&self, x: &mut [[f64; 3]]) {
        let values: Vec<[f64; 3]> = self.vertices.iter().map(|&v| x[v as usize]).collect();
        if let Ok(out) = self
            .system
            .solve(&uniform_weights(self.local_faces.len()), &values)
        {
            for (k, &v) in self.vertices.iter().enumerate().skip(self.n_boundary) {
                x[v as usize] = out[k];
            }
        }
    }

    /// Zeroes the displacement of the patch's inside (it is laid out, not moved).
    pub fn clear_interior(&self, step: &mut [[f64; 2]]) {
        for &v in &self.vertices[self.n_boundary..] {
            step[v as usize] = [0.0, 0.0];
        }
    }
}
