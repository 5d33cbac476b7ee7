//! DEQ's initial map, first step: every hole filled with a fan (a centre joined to the hole's
//! loop on the surface) and the filled disk — a topological disk — embedded with Floater's
//! mean value weights (the DEM paper's Tutte embedding (4.11)–(4.13) with positive weights),
//! the outer loop on the unit circle at angles proportional to its length weighted by `√(ρ/ρ̄)`
//! per edge (ρ the population per surface area, ρ̄ its overall value). Positive weights and a
//! convex boundary make this a bijection (Tutte; Floater 2003) in which every hole is
//! star-shaped around its fan's centre. It stands in for §5.1.1's conformal map, which shrinks
//! the narrow parts of a surface by orders of magnitude; the holes are then made round
//! ([`super::rounding`]).

use super::layout::Layout;
use super::rounding;
use super::untangle::untangle_within_loops;
use crate::geometry::{count_nonpositive, face_areas, norm, sub};
use crate::init::tutte::{InteriorWeights, fixed_boundary_map};
use crate::{Error, Result, TriMesh};
use std::collections::HashMap;
use std::f64::consts::TAU;

/// [`round_and_untangle`]: the untangled region's radius in edges around the folds, tried in
/// turn (the last takes in any mesh whole).
const UNTANGLE_RINGS: [usize; 3] = [4, 16, usize::MAX];

/// Face densities on the surface, for spacing loops by weighted length.
struct Density {
    areas: Vec<f64>,
    density: Vec<f64>,
    mean: f64,
}

impl Density {
    fn new(mesh: &TriMesh, population: &[f64]) -> Self {
        let areas = face_areas(&mesh.positions, &mesh.faces);
        let mean = population.iter().sum::<f64>() / areas.iter().sum::<f64>();
        let density = population.iter().zip(&areas).map(|(p, a)| p / a).collect();
        Self {
            areas,
            density,
            mean,
        }
    }

    /// Angles of the vertices of `lp` (following the face orientation) in proportion to the
    /// weighted length of its edges, from 0 in the direction `sign` (+1 counter-clockwise).
    fn loop_angles(&self, mesh: &TriMesh, lp: &[u32], sign: f64) -> Vec<f64> {
        let input = lp;
        let m = input.len();
        let mut edge_face: HashMap<(u32, u32), usize> = HashMap::with_capacity(m);
        for k in 0..m {
            edge_face.insert((input[k], input[(k + 1) % m]), usize::MAX);
        }
        for (f, face) in mesh.faces.iter().enumerate() {
            for c in 0..3 {
                if let Some(slot) = edge_face.get_mut(&(face[c], face[(c + 1) % 3])) {
                    *slot = f;
                }
            }
        }
        let lengths: Vec<f64> = (0..m)
            .map(|k| {
                let (a, b) = (input[k], input[(k + 1) % m]);
                let l = norm(sub(mesh.positions[b as usize], mesh.positions[a as usize]));
                let weight = match edge_face.get(&(a, b)) {
                    Some(&f) if f != usize::MAX && self.areas[f] > 0.0 => {
                        (self.density[f] / self.mean).sqrt()
                    }
                    _ => 1.0,
                };
                let lw = l * weight;
                if lw.is_finite() && lw > 0.0 {
                    lw
                } else {
                    l.max(f64::MIN_POSITIVE)
                }
            })
            .collect();
        let total: f64 = lengths.iter().sum();
        let mut acc = 0.0;
        lengths
            .iter()
            .map(|l| {
                let t = sign * TAU * acc / total;
                acc += l;
                t
            })
            .collect()
    }
}

/// The fan-filled disk's embedding: the planar position of every surface vertex and of each
/// hole's fan centre.
pub(crate) struct FilledEmbedding {
    pub positions: Vec<[f64; 3]>,
    pub centres: Vec<[f64; 2]>,
}

/// Every hole filled with a fan (a centre joined to the hole's loop on the surface) and the
/// filled disk embedded with mean value weights, the outer loop on the unit circle: a
/// bijection (Floater) in which every hole is star-shaped around its fan's centre.
pub(crate) fn filled_disk_embedding(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
) -> Result<FilledEmbedding> {
    let n = mesh.n_vertices();
    let mut positions = mesh.positions.clone();
    let mut faces = mesh.faces.clone();
    for (h, hole) in layout.holes.iter().enumerate() {
        let centre = (n + h) as u32;
        positions.push(hole.surface_centroid);
        let lp = &hole.boundary;
        for k in 0..lp.len() {
            faces.push([lp[(k + 1) % lp.len()], lp[k], centre]);
        }
    }
    let density = Density::new(mesh, population);
    let angles = density.loop_angles(mesh, &layout.outer, 1.0);
    let circle: Vec<[f64; 2]> = angles.iter().map(|t| [t.cos(), t.sin()]).collect();
    let map = fixed_boundary_map(
        &positions,
        &faces,
        &layout.outer,
        &circle,
        InteriorWeights::MeanValue,
    )?;
    let mut map = map;
    let flipped = count_nonpositive(&map, &faces);
    if flipped > 0 {
        return Err(Error::Numerical(format!(
            "the initial embedding of the filled disk folds {flipped} triangles"
        )));
    }
    let centres = (0..layout.holes.len())
        .map(|h| [map[n + h][0], map[n + h][1]])
        .collect();
    map.truncate(n);
    Ok(FilledEmbedding {
        positions: map,
        centres,
    })
}

/// DEQ's initial map: the fan-filled disk's embedding ([`filled_disk_embedding`]), its holes
/// made round ([`round_holes`]). The surface's vertices only.
pub(crate) fn initial_map(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
) -> Result<Vec<[f64; 3]>> {
    let embedding = filled_disk_embedding(mesh, population, layout)?;
    let mut x = embedding.positions;
    if !round_holes(mesh, layout, &mut x, &embedding.centres)?
        && !round_and_untangle(mesh, population, layout, &mut x, &embedding.centres)?
    {
        return Err(Error::Numerical(
            "a hole of the initial map could not be made round without folding the map".into(),
        ));
    }
    Ok(x)
}

/// The fallback of [`round_holes`] for holes the embedding pressed too flat for harmonic moves
/// to open: every hole's loop put on its circle at once (inside its polygon, else of its
/// area), and the triangles this folds untangled ([`untangle`]) with every loop held, towards
/// areas in proportion to the population. Returns false, with `x` unchanged, when neither
/// untangles.
fn round_and_untangle(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    x: &mut [[f64; 3]],
    centres: &[[f64; 2]],
) -> Result<bool> {
    let before = x.to_vec();
    for size in [rounding::Size::Inside, rounding::Size::Area] {
        for (hole, &centre) in layout.holes.iter().zip(centres) {
            let (_, targets) = rounding::round_targets(&before, &hole.boundary, centre, size);
            for (v, [a, b]) in targets {
                x[v as usize] = [a, b, 0.0];
            }
        }
        if untangle_within_loops(mesh, population, layout, x, &UNTANGLE_RINGS)? {
            return Ok(true);
        }
        x.copy_from_slice(&before);
    }
    Ok(false)
}

/// Makes every hole of the bijective planar map `x` round without folding it
/// ([`rounding::move_vertices`]): each the circle of its area or, where one would reach
/// another hole or the outer loop, every hole a circle inside its polygon (`centres`: a point
/// each hole's polygon is star-shaped around). Returns false, with `x` unchanged, when
/// neither works.
pub(crate) fn round_holes(
    mesh: &TriMesh,
    layout: &Layout,
    x: &mut [[f64; 3]],
    centres: &[[f64; 2]],
) -> Result<bool> {
    let held = layout.on_loops(x.len());
    let before = x.to_vec();
    for size in [rounding::Size::Area, rounding::Size::Inside] {
        let mut movers = Vec::new();
        for (hole, &centre) in layout.holes.iter().zip(centres) {
            let (_, targets) = rounding::round_targets(x, &hole.boundary, centre, size);
            movers.extend(targets);
        }
        if rounding::move_vertices(&mesh.faces, x, &held, &movers)?
            && count_nonpositive(x, &mesh.faces) == 0
        {
            return Ok(true);
        }
        x.copy_from_slice(&before);
    }
    Ok(false)
}
