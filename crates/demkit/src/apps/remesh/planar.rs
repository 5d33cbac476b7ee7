//! Remeshing through a planar map (DEM paper §6.2; DEQ paper §7.1 for circle domains): a
//! hexagonal lattice inside the region the map covers, each boundary loop resampled at the
//! lattice spacing, their constrained Delaunay triangulation (boundaries and holes kept as
//! edges), and every point pulled back onto the input surface through the inverse map.

use super::Layout;
use super::adaptive::Candidates;
use super::region::Region;
use super::sampling::{self, OnPolyline, hex_spacing, resample_closed};
use crate::geometry::locate::PlanarLocator;
use crate::mesh::triangulate::{constrained_delaunay, faces_inside};
use crate::{Error, Result, TriMesh};
use std::collections::HashMap;

/// Lattice points closer than this many spacings to the boundary are left out: the resampled
/// boundary takes their place.
const MARGIN: f64 = 0.6;

/// Above this density error of the map, the interior points follow the map's residual density
/// (see [`super::adaptive`]) instead of a uniform lattice.
const ADAPT_ABOVE: f64 = 0.25;

/// A Poisson-disk layout chooses among at most about this many candidates per point asked for.
const MAX_CANDIDATES_PER_POINT: usize = 100;

/// Where the points go for one spacing: the resampled boundary loops and the interior lattice.
struct Placement {
    h: f64,
    boundary: Vec<Vec<OnPolyline>>,
    interior: Vec<[f64; 2]>,
}

impl Placement {
    fn len(&self) -> usize {
        self.boundary.iter().map(Vec::len).sum::<usize>() + self.interior.len()
    }
}

/// About `n` points laid out uniformly on the planar map `mapped` (z ignored) of `input`, whose
/// boundary is `loops` (the input's boundary loops as vertex indices), and their triangulation
/// with as many boundary loops, faces oriented like the input's. Boundary points are fixed at
/// their place on the input's boundary edges, spaced along the input's boundary as the
/// population asks (`density`: population per unit area of every input face), so that a map
/// that stretches its boundary does not crowd or thin the points there.
pub fn layout_planar(
    input: &TriMesh,
    density: &[f64],
    mapped: &[[f64; 3]],
    loops: &[Vec<u32>],
    n: usize,
) -> Result<Layout> {
    let signed: f64 = input
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| mapped[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .sum();
    let area = signed.abs();
    if !(area > 0.0 && area.is_finite()) {
        return Err(Error::Numerical(
            "the planar map has no area to lay points on".into(),
        ));
    }
    let polylines: Vec<Vec<[f64; 2]>> = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|&v| [mapped[v as usize][0], mapped[v as usize][1]])
                .collect()
        })
        .collect();

    let surface_area: f64 = crate::geometry::face_areas(&input.positions, &input.faces)
        .iter()
        .sum();
    let measured = boundary_lengths(input, density, loops, area / surface_area);
    let relative = residual_density(input, density, mapped);
    let h0 = hex_spacing(area, n);
    let adaptive = if relative.error > ADAPT_ABOVE {
        let locator = PlanarLocator::new(mapped, &input.faces);
        let field = |p: [f64; 2]| {
            locator.locate(p).map(|l| {
                let f = input.faces[l.face];
                (0..3)
                    .map(|k| l.weights[k] * relative.vertex[f[k] as usize])
                    .sum()
            })
        };
        let region = Region::new(&polylines, h0);
        Some(Candidates::new(
            &region,
            area,
            h0,
            &field,
            MAX_CANDIDATES_PER_POINT * n,
        ))
    } else {
        None
    };
    let layout = fit_spacing(&polylines, &measured, adaptive.as_ref(), area, n);

    // Boundary points first (loop by loop), then the lattice.
    let mut points: Vec<[f64; 2]> = Vec::with_capacity(layout.len());
    let mut segments = Vec::new();
    let mut point_loops = Vec::new();
    for b in &layout.boundary {
        let first = points.len();
        points.extend(b.iter().map(|p| p.point));
        segments.extend((0..b.len()).map(|k| [first + k, first + (k + 1) % b.len()]));
        point_loops.push((first..first + b.len()).collect::<Vec<usize>>());
    }
    points.extend_from_slice(&layout.interior);
    let cdt = constrained_delaunay(&points, &segments)?;
    // Consecutive boundary points on a straight stretch of the boundary can close a sliver
    // of rounding size on either side of it: never a face of the region.
    let sliver = 1e-9 * layout.h * layout.h;
    let mut faces: Vec<[u32; 3]> = faces_inside(&cdt.points, &cdt.faces, &point_loops)
        .into_iter()
        .filter(|f| {
            let [a, b, c] = f.map(|v| cdt.points[v as usize]);
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs() > sliver
        })
        .collect();
    if signed < 0.0 {
        for f in &mut faces {
            f.swap(1, 2);
        }
    }

    // Boundary points sit on their input boundary edge.
    let mut fixed = Vec::with_capacity(points.len());
    for (l, b) in loops.iter().zip(&layout.boundary) {
        for p in b {
            let (u, v) = (l[p.edge] as usize, l[(p.edge + 1) % l.len()] as usize);
            fixed.push(Some(lerp(input.positions[u], input.positions[v], p.t)));
        }
    }
    fixed.resize(points.len(), None);
    Ok(Layout {
        domain: points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
        fixed,
        faces,
    })
}

/// The layout whose spacing puts closest to `n` points in the region: the spacing of a
/// hexagonal lattice of `n` points on `area`, corrected by the square root of the count ratio
/// until the count is within 1 % (or the steps run out).
fn fit_spacing(
    polylines: &[Vec<[f64; 2]>],
    lengths: &[Vec<f64>],
    adaptive: Option<&Candidates>,
    area: f64,
    n: usize,
) -> Placement {
    sampling::fit_spacing(
        hex_spacing(area, n),
        n,
        |h| lay_out(polylines, lengths, adaptive, h),
        Placement::len,
    )
}

/// The boundary loops resampled at spacing `h` and, inside the region, the hexagonal lattice of
/// spacing `h` at least [`MARGIN`]` · h` from its boundary, or with `adaptive` candidates, a
/// Poisson-disk set of local spacing `h / √r` as far from the boundary in proportion.
fn lay_out(
    polylines: &[Vec<[f64; 2]>],
    lengths: &[Vec<f64>],
    adaptive: Option<&Candidates>,
    h: f64,
) -> Placement {
    let boundary = polylines
        .iter()
        .zip(lengths)
        .map(|(p, l)| resample_closed(p, l, h))
        .collect();
    if let Some(c) = adaptive {
        let region = Region::new(polylines, MARGIN * h * c.max_factor());
        return Placement {
            h,
            boundary,
            interior: c.select(&region, h, MARGIN),
        };
    }
    let margin = MARGIN * h;
    let region = Region::new(polylines, margin);
    let interior = region
        .lattice_inside(h)
        .into_iter()
        .filter(|&p| !region.near_boundary(p, margin))
        .collect();
    Placement {
        h,
        boundary,
        interior,
    }
}

/// The density a map leaves to be made up by the point layout: per input vertex, the
/// population of its faces over their area on the map, relative to the whole (1 everywhere for
/// an exact density-equalizing map), and the map's density error (mean |log| of the per-face
/// ratio, the report's `density_error_mean`).
struct Residual {
    vertex: Vec<f64>,
    error: f64,
}

fn residual_density(input: &TriMesh, density: &[f64], mapped: &[[f64; 3]]) -> Residual {
    let areas = crate::geometry::face_areas(&input.positions, &input.faces);
    let on_map = crate::geometry::face_areas(mapped, &input.faces);
    let pop: Vec<f64> = density.iter().zip(&areas).map(|(d, a)| d * a).collect();
    let (total_pop, total_map) = (pop.iter().sum::<f64>(), on_map.iter().sum::<f64>());
    let mut sums = vec![(0.0, 0.0); input.n_vertices()];
    let mut error = 0.0;
    for (f, t) in input.faces.iter().enumerate() {
        for &v in t {
            sums[v as usize].0 += pop[f];
            sums[v as usize].1 += on_map[f];
        }
        let r = (pop[f] / total_pop) / (on_map[f] / total_map);
        if r.is_finite() && r > 0.0 {
            error += r.ln().abs();
        }
    }
    Residual {
        vertex: sums
            .iter()
            .map(|(p, a)| (p / total_pop) / (a / total_map))
            .collect(),
        error: error / input.n_faces().max(1) as f64,
    }
}

/// The length of every boundary edge as the domain should see it: its length on the surface
/// times the square root of its face's density over the mean density (where the population is
/// denser, points are closer), scaled by `√scale` (`scale`: the map's area over the surface's).
fn boundary_lengths(
    input: &TriMesh,
    density: &[f64],
    loops: &[Vec<u32>],
    scale: f64,
) -> Vec<Vec<f64>> {
    let mut face_of: HashMap<(u32, u32), usize> = HashMap::new();
    for (f, t) in input.faces.iter().enumerate() {
        for k in 0..3 {
            face_of.insert((t[k], t[(k + 1) % 3]), f);
        }
    }
    let areas = crate::geometry::face_areas(&input.positions, &input.faces);
    let mean =
        density.iter().zip(&areas).map(|(d, a)| d * a).sum::<f64>() / areas.iter().sum::<f64>();
    loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|k| {
                    let (u, v) = (l[k], l[(k + 1) % l.len()]);
                    let rho = face_of
                        .get(&(u, v))
                        .map(|&f| density[f] / mean)
                        .filter(|r| r.is_finite() && *r > 0.0)
                        .unwrap_or(1.0);
                    let (a, b) = (input.positions[u as usize], input.positions[v as usize]);
                    let len = (0..3).map(|d| (a[d] - b[d]).powi(2)).sum::<f64>().sqrt();
                    len * (rho * scale).sqrt()
                })
                .collect()
        })
        .collect()
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|d| a[d] + t * (b[d] - a[d]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology::topology;

    /// A unit square of 2·k² triangles, lifted onto the paraboloid z = x² + y² (its map is the
    /// square itself).
    fn square(k: usize) -> (TriMesh, Vec<[f64; 3]>) {
        let mut flat = Vec::new();
        for j in 0..=k {
            for i in 0..=k {
                flat.push([i as f64 / k as f64, j as f64 / k as f64, 0.0]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..k {
            for i in 0..k {
                let v = (j * (k + 1) + i) as u32;
                let w = v + k as u32 + 1;
                faces.push([v, v + 1, w + 1]);
                faces.push([v, w + 1, w]);
            }
        }
        let lifted = flat
            .iter()
            .map(|p| [p[0], p[1], p[0] * p[0] + p[1] * p[1]])
            .collect();
        (TriMesh::new(lifted, faces), flat)
    }

    fn remesh_planar(
        input: &TriMesh,
        mapped: &[[f64; 3]],
        _loops: &[Vec<u32>],
        n: usize,
    ) -> Result<TriMesh> {
        let area = crate::geometry::face_areas(&input.positions, &input.faces);
        super::super::remesh(input, &area, mapped, super::super::Target::Plane, n)
    }

    #[test]
    fn a_square_map_gives_a_disk_with_the_asked_count_on_the_surface() {
        let (input, flat) = square(8);
        let loops = topology(&input).boundary_loops;
        let out = remesh_planar(&input, &flat, &loops, 400).unwrap();
        let t = topology(&out);
        assert_eq!(t.boundary_loops.len(), 1);
        assert_eq!(t.genus, 0);
        assert_eq!(t.n_vertices, out.n_vertices());
        assert!(
            (out.n_vertices() as f64 - 400.0).abs() <= 20.0,
            "{}",
            out.n_vertices()
        );
        // Every vertex is on the paraboloid patch (linear interpolation of a flat patch's
        // lift is exact along x and y; z lies between the chords, at most 1/(4·8²) above).
        for p in &out.positions {
            assert!(p[0] >= -1e-12 && p[0] <= 1.0 + 1e-12);
            assert!(p[2] >= p[0] * p[0] + p[1] * p[1] - 1e-12);
            assert!(p[2] <= p[0] * p[0] + p[1] * p[1] + 2.0 / 64.0);
        }
        // Oriented like the input: positive area in the (x, y) plane.
        for f in &out.faces {
            let [a, b, c] = f.map(|v| out.positions[v as usize]);
            assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
        }
    }

    #[test]
    fn a_mirrored_map_keeps_the_input_orientation() {
        let (input, flat) = square(6);
        let mirrored: Vec<[f64; 3]> = flat.iter().map(|p| [-p[0], p[1], 0.0]).collect();
        let loops = topology(&input).boundary_loops;
        let out = remesh_planar(&input, &mirrored, &loops, 200).unwrap();
        for f in &out.faces {
            let [a, b, c] = f.map(|v| out.positions[v as usize]);
            assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
        }
    }

    #[test]
    fn a_map_that_squeezes_half_the_surface_is_made_up_for() {
        // The left half of the square takes a quarter of the map: four times too little area.
        let (input, flat) = square(16);
        let squeezed: Vec<[f64; 3]> = flat
            .iter()
            .map(|p| {
                let x = if p[0] < 0.5 {
                    0.5 * p[0]
                } else {
                    1.5 * p[0] - 0.5
                };
                [x, p[1], 0.0]
            })
            .collect();
        let loops = topology(&input).boundary_loops;
        let out = remesh_planar(&input, &squeezed, &loops, 800).unwrap();
        let q = super::super::quality::quality(&out);
        assert!(q.area_cv < 0.35, "{q:?}");
        // As many vertices per unit area on both halves of the (curved) surface.
        let areas = crate::geometry::face_areas(&out.positions, &out.faces);
        let (mut area_left, mut area_right) = (0.0, 0.0);
        for (f, a) in out.faces.iter().zip(&areas) {
            if f.iter().map(|&v| out.positions[v as usize][0]).sum::<f64>() < 1.5 {
                area_left += a;
            } else {
                area_right += a;
            }
        }
        let left = out.positions.iter().filter(|p| p[0] < 0.5).count() as f64;
        let right = out.n_vertices() as f64 - left;
        let ratio = (left / area_left) / (right / area_right);
        assert!((ratio - 1.0).abs() < 0.15, "{ratio}");
    }
}
