//! The cartogram on the globe (SDEM paper §5.3): longitude/latitude regions on the unit
//! sphere, the rest of the globe as their sea, one genus-0 mesh mapped by SDEM (Algorithm 3.1)
//! from the globe itself, and the regions' vertices carried back to longitude/latitude.
//!
//! The mesh: region edges are split along their great circles into pieces no longer than the
//! mesh spacing, a Fibonacci lattice covers the rest of the globe, and the whole is
//! triangulated by a constrained Delaunay triangulation in the stereographic projection from a
//! lattice point far from every region (the "far point"), whose cap is closed by a fan.
//!
//! Limitation (measured): SDEM diffuses the density over a fixed time (δt = 0.1 on the unit
//! sphere, a length of about 18°) and stops when the whole globe's density stops improving, so
//! regions much smaller than that are equalized poorly: a 5 × 5 grid of 10° cells comes within
//! a few percent, the same grid of 4° cells is up to 78% off; and the outcome changes with the
//! mesh size (a finer globe mesh is not reliably better).

use super::planar::face_population;
use super::regions::RegionSet;
use super::triangulate::assign_faces;
use super::{Cartogram, Config, MIN_CORRECTION, Polygon, Run, figures};
use crate::geometry::face_areas;
use crate::geometry::sphere::{
    fibonacci_sphere, mat_vec, normalize, project_from_north, rotation_to_north,
};
use crate::init::spherical_conformal::count_spherical_flips;
use crate::mesh::triangulate::{inside_loops, spherical_constrained_delaunay};
use crate::methods::{ProgressFn, StopReason, sdem};
use crate::{Error, Result, TriMesh};
use std::collections::HashMap;
use std::time::Instant;

/// Lattice points closer than this fraction of the spacing to a region edge are left out.
const CLEARANCE: f64 = 0.5;

/// Longitude/latitude degrees → unit vector.
pub fn to_unit(p: [f64; 2]) -> [f64; 3] {
    let (lon, lat) = (p[0].to_radians(), p[1].to_radians());
    [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()]
}

/// Unit vector → longitude/latitude degrees, the longitude in (−180, 180].
pub fn to_lon_lat(p: [f64; 3]) -> [f64; 2] {
    let q = normalize(p);
    [
        q[1].atan2(q[0]).to_degrees(),
        q[2].clamp(-1.0, 1.0).asin().to_degrees(),
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    dot(c, c).sqrt().atan2(dot(a, b))
}

/// Angular distance from `p` to the great-circle arc `a`–`b` (shorter than π).
fn arc_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let n = normalize([
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]);
    let off = dot(p, n);
    let q = [p[0] - off * n[0], p[1] - off * n[1], p[2] - off * n[2]];
    let ab = angle(a, b);
    if (angle(a, q) + angle(q, b) - ab).abs() < 1e-9 {
        off.abs().clamp(0.0, 1.0).asin()
    } else {
        angle(p, a).min(angle(p, b))
    }
}

/// The globe's mesh.
struct GlobeMesh {
    points: Vec<[f64; 3]>,
    faces: Vec<[u32; 3]>,
    face_region: Vec<Option<usize>>,
    /// Every region's rings as mesh vertices (each input vertex followed by the vertices added
    /// on its edge), per region, polygon, ring.
    rings: Vec<Vec<Vec<Vec<usize>>>>,
}

fn build(set: &RegionSet, target_faces: usize, path: &str) -> Result<GlobeMesh> {
    let fmt = |msg: String| Error::Format {
        path: path.to_string(),
        msg,
    };
    // Region vertices on the sphere; positions that meet there (a pole, ±180°) merged.
    let lon_lat = set.input_points();
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut merged = Vec::with_capacity(set.points.len());
    let mut seen: HashMap<[i64; 3], usize> = HashMap::new();
    for &p in &lon_lat {
        let u = to_unit(p);
        let key = u.map(|c| (c * 1e10).round() as i64);
        let v = *seen.entry(key).or_insert_with(|| {
            points.push(u);
            points.len() - 1
        });
        merged.push(v);
    }
    // A uniform spacing over the globe: SDEM's fixed time step is a fraction of the sphere,
    // and triangles much smaller than the globe's average make its steps stall on the overlap
    // correction (measured: a cap around the regions twice as fine gave worse areas).
    let sphere_area = 4.0 * std::f64::consts::PI;
    let h = (4.0 * sphere_area / (3f64.sqrt() * target_faces.max(64) as f64)).sqrt();
    // Region edges split along their great circles.
    let mut segments: Vec<[usize; 2]> = Vec::new();
    let mut chains: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    let mut arcs: Vec<[usize; 2]> = Vec::new();
    for ([a, b], _) in set.edges() {
        let (a, b) = (merged[a], merged[b]);
        if a == b || chains.contains_key(&[a.min(b), a.max(b)]) {
            continue;
        }
        let (a, b) = (a.min(b), a.max(b));
        let (pa, pb) = (points[a], points[b]);
        let theta = angle(pa, pb);
        if theta > std::f64::consts::PI - 1e-6 {
            return Err(fmt(format!(
                "an edge from {:?} to {:?} joins antipodal points (no unique great circle)",
                to_lon_lat(pa),
                to_lon_lat(pb)
            )));
        }
        let n = ((theta / h).ceil() as usize).max(1);
        let mut chain = Vec::with_capacity(n - 1);
        let mut prev = a;
        for k in 1..n {
            let t = k as f64 / n as f64;
            let (sa, sb) = (((1.0 - t) * theta).sin(), (t * theta).sin());
            let q = normalize([
                sa * pa[0] + sb * pb[0],
                sa * pa[1] + sb * pb[1],
                sa * pa[2] + sb * pb[2],
            ]);
            points.push(q);
            let v = points.len() - 1;
            segments.push([prev, v]);
            chain.push(v);
            prev = v;
        }
        segments.push([prev, b]);
        chains.insert([a, b], chain);
        arcs.push([a, b]);
    }
    let n_boundary = points.len();
    // A lattice of spacing h: 2/(√3 h²) points per unit area.
    let lattice =
        fibonacci_sphere(((2.0 * sphere_area / (3f64.sqrt() * h * h)).ceil() as usize).max(32));
    // The far point: the lattice point farthest from every region vertex, outside every region.
    let mut order: Vec<(f64, usize)> = lattice
        .iter()
        .enumerate()
        .map(|(i, &q)| {
            let d = points[..n_boundary]
                .iter()
                .map(|&p| dot(p, q))
                .fold(f64::NEG_INFINITY, f64::max);
            (d, i)
        })
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0));
    let far = order
        .iter()
        .map(|&(_, i)| lattice[i])
        .take(64)
        .find(|&q| {
            let ll = to_lon_lat(q);
            !set.regions.iter().any(|r| {
                r.polygons
                    .iter()
                    .any(|rings| inside_loops(&lon_lat, rings, ll))
            })
        })
        .ok_or_else(|| fmt("the regions cover the whole globe: no sea is left".into()))?;
    // The lattice, clear of the region edges and the far point.
    let clear = CLEARANCE * h;
    let near_arc = |q: [f64; 3]| {
        arcs.iter().any(|&[a, b]| {
            let (pa, pb) = (points[a], points[b]);
            let m = normalize([pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]]);
            angle(q, m) <= 0.5 * angle(pa, pb) + clear && arc_distance(q, pa, pb) < clear
        })
    };
    let kept: Vec<[f64; 3]> = lattice
        .iter()
        .copied()
        .filter(|&q| angle(q, far) >= clear && (arcs.is_empty() || !near_arc(q)))
        .collect();
    points.extend(kept);

    // The triangulation seen from the far point (the last vertex): in its stereographic
    // projection, the cap closed by a fan around it. Regions are assigned in that projection.
    let rot = rotation_to_north(far);
    let plane: Vec<[f64; 2]> = points
        .iter()
        .map(|&p| {
            let w = project_from_north(mat_vec(&rot, p));
            [w[0], w[1]]
        })
        .collect();
    let far_index = points.len();
    points.push(far);
    let faces = spherical_constrained_delaunay(&points, &segments, far_index)?;

    // Rings through the mesh, and every face's region (decided in the projection).
    let dense = |ring: &[usize]| -> Vec<usize> {
        let mut out = Vec::with_capacity(ring.len());
        for i in 0..ring.len() {
            let (a, b) = (merged[ring[i]], merged[ring[(i + 1) % ring.len()]]);
            if a == b {
                continue;
            }
            out.push(a);
            if let Some(mid) = chains.get(&[a.min(b), a.max(b)]) {
                if a < b {
                    out.extend(mid.iter().copied());
                } else {
                    out.extend(mid.iter().rev().copied());
                }
            }
        }
        out
    };
    let rings: Vec<Vec<Vec<Vec<usize>>>> = set
        .regions
        .iter()
        .map(|r| {
            r.polygons
                .iter()
                .map(|p| p.iter().map(|ring| dense(ring)).collect())
                .collect()
        })
        .collect();
    let polygons: Vec<(usize, Vec<Vec<usize>>)> = rings
        .iter()
        .enumerate()
        .flat_map(|(r, polys)| polys.iter().map(move |p| (r, p.clone())))
        .collect();
    // Faces at the far point are sea; the others are decided in the projection.
    let projected: Vec<usize> = (0..faces.len())
        .filter(|&f| !faces[f].contains(&(far_index as u32)))
        .collect();
    let projected_faces: Vec<[u32; 3]> = projected.iter().map(|&f| faces[f]).collect();
    let assigned = assign_faces(set, &polygons, &plane, &plane, &projected_faces, path)?;
    let mut face_region = vec![None; faces.len()];
    for (&f, r) in projected.iter().zip(assigned) {
        face_region[f] = r;
    }
    Ok(GlobeMesh {
        points,
        faces,
        face_region,
        rings,
    })
}

/// Computes the cartogram of `set` (longitude/latitude degrees) on the unit sphere by SDEM,
/// in rounds with corrected values as in [`super::planar::run`]; areas in the figures are
/// those of the mesh on the unit sphere (steradians).
pub fn run(
    set: &RegionSet,
    config: &Config,
    path: &str,
    progress: ProgressFn,
) -> Result<Cartogram> {
    let t0 = Instant::now();
    let mesh = build(set, config.target_faces, path)?;
    if count_spherical_flips(&mesh.points, &mesh.faces) > 0 {
        return Err(Error::Numerical(
            "the globe's triangulation has flipped faces".into(),
        ));
    }
    let values = super::unit_values(&set.regions.iter().map(|r| r.value).collect::<Vec<_>>());
    let areas0 = face_areas(&mesh.points, &mesh.faces);
    let region_areas = |areas: &[f64]| {
        let mut s = vec![0.0; values.len()];
        for (r, a) in mesh.face_region.iter().zip(areas) {
            if let Some(r) = r {
                s[*r] += a;
            }
        }
        s
    };
    let in_areas = region_areas(&areas0);
    let mut sdem_config = sdem::Config::default();
    if let Some(n) = config.max_iter {
        sdem_config.max_iter = n;
    }
    let mut effective = values.clone();
    let mut positions = mesh.points.clone();
    let (mut iterations, mut rounds) = (0, 0);
    let mut stop_reason = StopReason::Tolerance;
    let mut notes = Vec::new();
    // The best round so far: (worst error, positions, region areas).
    let mut best: Option<(f64, Vec<[f64; 3]>, Vec<f64>)> = None;
    let tri = TriMesh::new(mesh.points.clone(), mesh.faces.clone());
    for round in 0..config.rounds.max(1) {
        let population = face_population(&effective, &mesh.face_region, &areas0);
        let r = sdem::run_from(&tri, &population, positions.clone(), &sdem_config, progress)?;
        positions = r.positions;
        iterations += r.iterations;
        rounds = round + 1;
        stop_reason = r.stop_reason;
        for n in r.notes {
            if !notes.contains(&n) {
                notes.push(n);
            }
        }
        let out_areas = region_areas(&face_areas(&positions, &mesh.faces));
        let errors = super::ratio_errors_of_areas(&values, &out_areas);
        let worst = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        if best.as_ref().is_none_or(|b| worst < b.0) {
            best = Some((worst, positions.clone(), out_areas));
        }
        if worst <= config.tolerance || stop_reason == StopReason::MaxIter {
            break;
        }
        for (v, e) in effective.iter_mut().zip(&errors) {
            *v /= (1.0 + e).clamp(MIN_CORRECTION, 1.0 / MIN_CORRECTION);
        }
    }
    let (_, positions, out_areas) = best.unwrap_or_default();
    let coordinates = lon_lat_rings(set, &mesh, &positions);
    let run = Run {
        iterations,
        rounds,
        stop_reason,
        mesh_vertices: mesh.points.len(),
        mesh_faces: mesh.faces.len(),
        flipped_triangles: count_spherical_flips(&positions, &mesh.faces),
        notes,
        time_s: t0.elapsed().as_secs_f64(),
    };
    Ok(figures(
        set,
        coordinates,
        (&in_areas, &out_areas),
        &out_areas,
        run,
    ))
}

/// The mapped rings in longitude/latitude, each longitude unwrapped to stay within 180° of the
/// previous one (starting near the input's), so rings do not jump across the date line.
fn lon_lat_rings(set: &RegionSet, mesh: &GlobeMesh, positions: &[[f64; 3]]) -> Vec<Vec<Polygon>> {
    set.regions
        .iter()
        .zip(&mesh.rings)
        .map(|(region, polys)| {
            polys
                .iter()
                .zip(&region.polygons)
                .map(|(rings, input)| {
                    rings
                        .iter()
                        .zip(input)
                        .map(|(ring, inring)| {
                            let mut prev = set.frame.to_input(set.points[inring[0]])[0];
                            ring.iter()
                                .map(|&v| {
                                    let mut p = to_lon_lat(positions[v]);
                                    p[0] += 360.0 * ((prev - p[0]) / 360.0).round();
                                    prev = p[0];
                                    p
                                })
                                .collect()
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lon_lat_round_trip_and_arc_distance() {
        for p in [[0.0, 0.0], [135.0, -45.0], [-170.0, 89.0]] {
            let q = to_lon_lat(to_unit(p));
            assert!(
                (q[0] - p[0]).abs() < 1e-9 && (q[1] - p[1]).abs() < 1e-9,
                "{q:?}"
            );
        }
        // The equator from 0° to 90°: a point at 10° N above 45° E is 10° away; one beyond
        // the end is measured to the end point.
        let (a, b) = (to_unit([0.0, 0.0]), to_unit([90.0, 0.0]));
        let d = arc_distance(to_unit([45.0, 10.0]), a, b);
        assert!((d - 10f64.to_radians()).abs() < 1e-12);
        let d = arc_distance(to_unit([100.0, 0.0]), a, b);
        assert!((d - 10f64.to_radians()).abs() < 1e-12);
    }
}
