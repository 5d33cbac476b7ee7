//! Adaptive remeshing through a density-equalizing map (DEM paper §6.2, SDEM paper §5.2, DEQ
//! paper §7.1, TDEM paper §5): near-uniform points on the map's target domain are triangulated
//! there and pulled back onto the input surface through the inverse map (point location in the
//! mapped mesh and barycentric interpolation of the input positions). Since the map gives every
//! region an area proportional to its population, the new mesh's vertex density follows the
//! population: uniform triangles for the population `area`, more vertices where the population
//! per unit area is higher.
//!
//! - [`planar`]: disk and circle-domain maps (boundaries and holes kept);
//! - [`sphere`]: maps onto the unit sphere or an ellipsoid;
//! - [`torus`]: maps onto the flat torus;
//! - `adaptive`: a Poisson-disk layout for planar maps that equalize the density only roughly;
//! - `relax`: flips and smoothing in the domain that improve the triangles' shapes on the
//!   surface without taking any vertex off it.

mod adaptive;
mod chart;
/// The weight α of the distortion in the DEQ energy with which a surface with holes is mapped
/// for remeshing when none is asked for: the density first (DEQ's own default, 2, weighs
/// conformality more), since the new mesh's vertex spacing follows the map's density
/// (lion_5 with 5000 vertices: area CV 0.27 at α = 0.3, 0.87 at α = 2).
pub const DEQ_ALPHA: f64 = 0.3;

pub mod planar;
pub mod quality;
mod region;
mod relax;
pub mod sampling;
pub mod sphere;
pub mod torus;

use chart::{Chart, ChartPoint};

use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::mesh::topology::topology;
use crate::{Error, Result, TriMesh};

/// Where the map lies.
#[derive(Debug, Clone, Copy)]
pub enum Target<'a> {
    /// A planar map (z = 0): disk, prescribed shape or circle domain.
    Plane,
    /// A map onto the unit sphere.
    Sphere,
    /// A map onto an ellipsoid (its positions on the ellipsoid).
    Ellipsoid(Ellipsoid),
    /// A map onto the flat torus of `torus`.
    Torus {
        /// The map (points and lattice offsets).
        map: &'a FlatTorusMap,
        /// The target torus.
        torus: &'a Torus,
    },
}

/// Points in a map's domain and their triangulation, before they are pulled back: z = 0 in the
/// plane and on the flat torus, unit vectors on the sphere (for an ellipsoid, the points'
/// images on the unit sphere).
#[derive(Debug, Clone)]
pub struct Layout {
    /// The points in the domain.
    pub domain: Vec<[f64; 3]>,
    /// For points that must stay where they are (boundary points), their place on the input
    /// surface; `None` for points pulled back through the map.
    pub fixed: Vec<Option<[f64; 3]>>,
    /// The faces, oriented like the input's.
    pub faces: Vec<[u32; 3]>,
}

/// Rounds of flips and smoothing after the layout is pulled back.
pub const RELAX_ROUNDS: usize = 10;

/// The most vertices a remesh may ask for ...
pub const MAX_VERTICES: usize = 20_000_000;

/// ... at about this many bytes of working memory each (candidates, triangulation, chart).
pub const BYTES_PER_VERTEX: usize = 2000;

/// Refuses a vertex count beyond [`MAX_VERTICES`], with the memory it would take.
pub fn check_vertex_count(n: usize) -> Result<()> {
    if n > MAX_VERTICES {
        let gb = n as f64 * BYTES_PER_VERTEX as f64 / 1e9;
        return Err(Error::Argument(format!(
            "vertices {n} would need about {gb:.0} GB of memory; at most {MAX_VERTICES} vertices"
        )));
    }
    Ok(())
}

/// The fewest vertices asked for that can keep a surface's topology: 16 for a closed genus-one
/// surface, otherwise 4, and 4 per boundary loop with holes.
pub fn min_vertices(boundary_loops: usize, genus: i64) -> usize {
    if boundary_loops == 0 && genus == 1 {
        16
    } else {
        (4 * boundary_loops).max(4)
    }
}

/// A new triangulation of `input` with about `n` vertices laid out uniformly on its map
/// `mapped` (the positions of a planar or spherical map; for the torus, `target` holds the
/// map), followed by [`RELAX_ROUNDS`] rounds of shape improvement in the domain that keep the
/// vertex density following `population` (one value per input face). Every new vertex lies on
/// the input surface; the result has the input's genus and number of boundary loops (checked),
/// and its faces are oriented like the input's.
///
/// Errors: [`Error::Argument`] when `n` is below [`min_vertices`] or the population does not
/// fit; [`Error::Numerical`] when the new triangulation is not a valid surface of the input's
/// topology (a map that is not bijective can cause this).
pub fn remesh(
    input: &TriMesh,
    population: &[f64],
    mapped: &[[f64; 3]],
    target: Target,
    n: usize,
) -> Result<TriMesh> {
    remesh_with(input, population, mapped, target, n, RELAX_ROUNDS)
}

/// [`remesh`] with `rounds` rounds of shape improvement (0: the plain pulled-back layout).
pub fn remesh_with(
    input: &TriMesh,
    population: &[f64],
    mapped: &[[f64; 3]],
    target: Target,
    n: usize,
    rounds: usize,
) -> Result<TriMesh> {
    check_vertex_count(n)?;
    let topo = topology(input);
    let least = min_vertices(topo.boundary_loops.len(), topo.genus);
    if n < least {
        return Err(Error::Argument(format!(
            "vertices must be at least {least} to keep the surface's topology, got {n}"
        )));
    }
    if mapped.len() != input.n_vertices() {
        return Err(Error::Argument(format!(
            "the map has {} points for {} vertices",
            mapped.len(),
            input.n_vertices()
        )));
    }
    if population.len() != input.n_faces() {
        return Err(Error::Argument(format!(
            "the population has {} values for {} faces",
            population.len(),
            input.n_faces()
        )));
    }
    let areas = crate::geometry::face_areas(&input.positions, &input.faces);
    let density: Vec<f64> = population
        .iter()
        .zip(&areas)
        .map(|(p, a)| if *a > 0.0 { p / a } else { 1.0 })
        .collect();
    let layout = match target {
        Target::Plane => planar::layout_planar(input, &density, mapped, &topo.boundary_loops, n)?,
        Target::Sphere => sphere::layout_ellipsoid(&Ellipsoid::UNIT_SPHERE, n)?,
        Target::Ellipsoid(e) => sphere::layout_ellipsoid(&e, n)?,
        Target::Torus { torus, .. } => torus::layout_torus(torus, n),
    };
    let chart = Chart::new(input, mapped, target);
    let points: Vec<ChartPoint> = layout
        .domain
        .iter()
        .zip(&layout.fixed)
        .map(|(&p, fixed)| match fixed {
            Some(x) => ChartPoint {
                domain: p,
                face: usize::MAX,
                position: *x,
            },
            None => chart.pull_or_nearest(p),
        })
        .collect();
    let mut draft = relax::Draft {
        fixed: points.iter().map(|p| p.face == usize::MAX).collect(),
        points,
        faces: layout.faces,
    };
    if rounds > 0 {
        relax::relax(&mut draft, &chart, &density, rounds);
    }
    let out = TriMesh::new(
        draft.points.iter().map(|p| p.position).collect(),
        draft.faces,
    );
    let (out, _) = crate::mesh::validate(out)
        .map_err(|e| Error::Numerical(format!("the new mesh is not a valid surface: {e}")))?;
    let t = topology(&out);
    if t.boundary_loops.len() != topo.boundary_loops.len() || t.genus != topo.genus {
        return Err(Error::Numerical(format!(
            "the new mesh has {} boundary loops and genus {}, the input {} and {}",
            t.boundary_loops.len(),
            t.genus,
            topo.boundary_loops.len(),
            topo.genus
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn too_few_vertices_are_refused() {
        let input = crate::generate::regular_polygon(6, 3).unwrap();
        let pop = vec![1.0; input.n_faces()];
        let err = remesh(&input, &pop, &input.positions, Target::Plane, 3).unwrap_err();
        assert!(err.is_input_error(), "{err}");
        let out = remesh(&input, &pop, &input.positions, Target::Plane, 4).unwrap();
        assert_eq!(topology(&out).boundary_loops.len(), 1);
    }

    #[test]
    fn holes_survive_in_a_circle_domain() {
        let input =
            crate::generate::disk_with_holes(&[(0.4, 0.0, 0.2), (-0.4, 0.1, 0.15)], 24).unwrap();
        let pop = crate::geometry::face_areas(&input.positions, &input.faces);
        let out = remesh(&input, &pop, &input.positions, Target::Plane, 600).unwrap();
        let t = topology(&out);
        assert_eq!((t.boundary_loops.len(), t.genus), (3, 0));
        assert!((out.n_vertices() as f64 - 600.0).abs() <= 60.0);
        let q = quality::quality(&out);
        assert!(q.median_min_angle_deg > 45.0, "{q:?}");
        assert!(q.area_cv < 0.5, "{q:?}");
        assert!(remesh(&input, &pop, &input.positions, Target::Plane, 11).is_err());
    }
}
