//! Closed surfaces: spheres (genus 0) and tori (genus 1), with outward normals.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use super::{at_least, fits, positive, smaller};
use crate::{Error, Result, TriMesh};

/// The unit sphere as a subdivided icosahedron: each of `subdivisions` rounds splits every face
/// into four at its edge midpoints and projects the new vertices onto the sphere.
/// 10·4^s + 2 vertices (the 12 icosahedron corners first, the rest in order of creation),
/// 20·4^s faces, all with outward normals. Faces are close to equilateral; edge lengths vary
/// by less than a factor 1.3.
///
/// Errors: a mesh too large for `u32` indices (`subdivisions` > 14).
pub fn icosphere(subdivisions: usize) -> Result<TriMesh> {
    let pow4 = u32::try_from(subdivisions)
        .ok()
        .and_then(|s| 4usize.checked_pow(s));
    let n_faces = pow4.and_then(|p| p.checked_mul(20));
    fits(
        pow4.and_then(|p| p.checked_mul(10)?.checked_add(2)),
        n_faces,
    )?;

    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let corners = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut positions: Vec<[f64; 3]> = corners.iter().map(normalized).collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        // The map is only looked up, never iterated: the output order stays deterministic.
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<[f64; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (positions[a as usize], positions[b as usize]);
                positions.push(normalized(&std::array::from_fn(|k| p[k] + q[k])));
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    Ok(TriMesh::new(positions, faces))
}

/// The unit sphere on a latitude–longitude grid: `n_lat` bands from pole to pole (polar angle
/// θ_i = πi/n_lat) and `n_lon` meridians (longitude φ_j = 2πj/n_lon), with the point
/// (sin θ cos φ, sin θ sin φ, cos θ). Vertex 0 is the north pole (0, 0, 1); then the n_lat − 1
/// circles of latitude from north to south, n_lon vertices each starting at φ = 0; the south
/// pole last. The polar caps are fans of triangles, the other bands quads split along one
/// diagonal: 2 + (n_lat − 1)·n_lon vertices, 2·n_lon·(n_lat − 1) faces, outward normals.
///
/// Errors: `n_lat` < 2, `n_lon` < 3.
pub fn uv_sphere(n_lat: usize, n_lon: usize) -> Result<TriMesh> {
    at_least("n_lat", n_lat, 2)?;
    at_least("n_lon", n_lon, 3)?;
    let n_vertices = (n_lat - 1)
        .checked_mul(n_lon)
        .and_then(|v| v.checked_add(2));
    let n_faces = (n_lat - 1)
        .checked_mul(n_lon)
        .and_then(|v| v.checked_mul(2));
    fits(n_vertices, n_faces)?;

    let mut positions = Vec::with_capacity(n_vertices.unwrap_or(0));
    positions.push([0.0, 0.0, 1.0]);
    for i in 1..n_lat {
        let theta = PI * i as f64 / n_lat as f64;
        for j in 0..n_lon {
            let phi = TAU * j as f64 / n_lon as f64;
            positions.push([
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]);
        }
    }
    let south = positions.len() as u32;
    positions.push([0.0, 0.0, -1.0]);

    // Vertex j of the i-th circle of latitude (1 ≤ i ≤ n_lat − 1).
    let ring = |i: usize, j: usize| (1 + (i - 1) * n_lon + j % n_lon) as u32;
    let mut faces = Vec::with_capacity(n_faces.unwrap_or(0));
    for j in 0..n_lon {
        faces.push([0, ring(1, j), ring(1, j + 1)]);
    }
    let band = (1..n_lat - 1).flat_map(|i| (0..n_lon).map(move |j| (i, j)));
    faces.extend(super::split_cells(band, ring, 0));
    for j in 0..n_lon {
        faces.push([ring(n_lat - 1, j), south, ring(n_lat - 1, j + 1)]);
    }
    Ok(TriMesh::new(positions, faces))
}

/// The thinnest tube [`torus`] makes, as a fraction of the ring's radius: R + r cos v keeps
/// r's digits to about 1e-4 of it.
pub const THINNEST_TUBE: f64 = 1e-12;

/// A torus of revolution about the z-axis: tube centre at distance `big_r` from the axis, tube
/// radius `small_r`. Vertex (i, j), with index `i*n_minor + j`, is at
/// ((R + r cos v) cos u, (R + r cos v) sin u, r sin v) for u = 2πi/n_major, v = 2πj/n_minor;
/// each (u, v) cell is split along the same diagonal into two faces.
/// n_major·n_minor vertices, 2·n_major·n_minor faces, outward normals; area close to 4π²Rr.
///
/// Errors: radii not finite with 0 < `small_r` < `big_r`, or `small_r` below
/// [`THINNEST_TUBE`] times `big_r`; `n_major` or `n_minor` < 3.
pub fn torus(big_r: f64, small_r: f64, n_major: usize, n_minor: usize) -> Result<TriMesh> {
    positive("big_r", big_r)?;
    positive("small_r", small_r)?;
    smaller(("small_r", small_r), ("big_r", big_r))?;
    if small_r < THINNEST_TUBE * big_r {
        return Err(Error::Argument(format!(
            "small_r must be at least {THINNEST_TUBE:e} times big_r (a thinner tube vanishes in \
             rounding beside the ring), got {small_r:?} and {big_r:?}"
        )));
    }
    at_least("n_major", n_major, 3)?;
    at_least("n_minor", n_minor, 3)?;
    let n_vertices = n_major.checked_mul(n_minor);
    fits(n_vertices, n_vertices.and_then(|v| v.checked_mul(2)))?;

    let mut positions = Vec::with_capacity(n_vertices.unwrap_or(0));
    for i in 0..n_major {
        let u = TAU * i as f64 / n_major as f64;
        for j in 0..n_minor {
            let v = TAU * j as f64 / n_minor as f64;
            let rho = big_r + small_r * v.cos();
            positions.push([rho * u.cos(), rho * u.sin(), small_r * v.sin()]);
        }
    }
    let index = |i: usize, j: usize| ((i % n_major) * n_minor + j % n_minor) as u32;
    let cells = (0..n_major).flat_map(|i| (0..n_minor).map(move |j| (i, j)));
    let faces = super::split_cells(cells, index, 2 * n_vertices.unwrap_or(0));
    Ok(TriMesh::new(positions, faces))
}

fn normalized(p: &[f64; 3]) -> [f64; 3] {
    let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    p.map(|c| c / n)
}

#[cfg(test)]
mod tests {
    use super::super::checks::*;
    use super::*;
    use crate::Error;

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Closed, consistently oriented, no duplicate vertices, outward (n · (centroid − centre(f)) > 0).
    fn check_closed(m: &TriMesh, chi: i64, centre: impl Fn([f64; 3]) -> [f64; 3]) {
        assert_eq!(check_oriented_manifold(m), 0, "boundary edges");
        check_no_duplicate_vertices(m);
        assert_eq!(euler_characteristic(m), chi);
        for f in 0..m.n_faces() {
            let (n, c) = normal_and_centroid(m, f);
            let o = centre(c);
            let out = dot(n, std::array::from_fn(|k| c[k] - o[k]));
            assert!(out > 0.0, "face {f} points inward: {out}");
        }
    }

    #[test]
    fn icosahedron_is_exact() {
        let m = icosphere(0).unwrap();
        assert_eq!((m.n_vertices(), m.n_faces()), (12, 20));
        check_closed(&m, 2, |_| [0.0; 3]);
        // Inscribed in the unit sphere: edge a = 4/sqrt(10 + 2√5), area 5√3·a².
        let a2 = 16.0 / (10.0 + 2.0 * 5f64.sqrt());
        assert_close(total_area(&m), 5.0 * 3f64.sqrt() * a2, 1e-14);
    }

    #[test]
    fn icosphere_counts_and_area() {
        for s in 1..=4 {
            let m = icosphere(s).unwrap();
            let p = 4usize.pow(s as u32);
            assert_eq!((m.n_vertices(), m.n_faces()), (10 * p + 2, 20 * p));
            check_closed(&m, 2, |_| [0.0; 3]);
            for p in &m.positions {
                assert_close(dot(*p, *p), 1.0, 1e-14);
            }
            let a = total_area(&m);
            assert!(a < 4.0 * PI);
            if s == 4 {
                assert_close(a, 4.0 * PI, 2e-3);
            }
        }
    }

    #[test]
    fn uv_sphere_counts_and_area() {
        for (n_lat, n_lon) in [(2, 3), (3, 4), (32, 64)] {
            let m = uv_sphere(n_lat, n_lon).unwrap();
            assert_eq!(m.n_vertices(), 2 + (n_lat - 1) * n_lon);
            assert_eq!(m.n_faces(), 2 * n_lon * (n_lat - 1));
            check_closed(&m, 2, |_| [0.0; 3]);
            assert_eq!(m.positions[0], [0.0, 0.0, 1.0]);
            assert_eq!(*m.positions.last().unwrap(), [0.0, 0.0, -1.0]);
        }
        // The octahedron: uv_sphere(2, 4) has 8 faces of side √2, area 8·(√3/4)·2 = 4√3.
        let octahedron = uv_sphere(2, 4).unwrap();
        assert_close(total_area(&octahedron), 4.0 * 3f64.sqrt(), 1e-14);
        let a = total_area(&uv_sphere(32, 64).unwrap());
        assert!(a < 4.0 * PI);
        assert_close(a, 4.0 * PI, 5e-3);
    }

    #[test]
    fn torus_counts_and_area() {
        let (big_r, small_r) = (3.0, 1.0);
        let m = torus(big_r, small_r, 64, 32).unwrap();
        assert_eq!((m.n_vertices(), m.n_faces()), (64 * 32, 2 * 64 * 32));
        assert_eq!(m.positions[0], [4.0, 0.0, 0.0]);
        check_closed(&m, 0, |c| {
            let u = c[1].atan2(c[0]);
            [big_r * u.cos(), big_r * u.sin(), 0.0]
        });
        assert_close(total_area(&m), 4.0 * PI * PI * big_r * small_r, 5e-3);
        assert!(matches!(torus(1.0, 1.0, 8, 8), Err(Error::Argument(_))));
        assert!(matches!(torus(2.0, 1.0, 2, 8), Err(Error::Argument(_))));
    }
}
