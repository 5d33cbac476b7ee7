//! Construction of the sea around a planar region of interest by reflection
//! (DEM paper, section 4.2, Algorithm 4, eqs. (4.18)–(4.21)).
//!
//! The region of interest (ROI, the initial flattening map r₀) is shrunk into the unit disk,
//! the gap up to the unit circle is filled with lattice points, at the ROI's mean edge length
//! next to the ROI and coarsening geometrically away from it ([`fill`]), and triangulated by a
//! constrained Delaunay triangulation that keeps the ROI's own triangles ([`ring`]); the
//! triangulated unit disk D_T is then glued to its image under the reflection g(z) = 1/z̄
//! (4.18) along the unit circle (4.19)–(4.21), truncated at |z| ≤ η, cleaned into one disk
//! ([`clean_up`], [`holes`]) and scaled back ([`roi`]).

mod boundary_index;
mod clean_up;
mod fill;
mod holes;
mod ring;
mod roi;
#[cfg(test)]
mod tests;

use boundary_index::BoundaryIndex;
use clean_up::{Incidence, check_disk, clean_up, orient};
use fill::{Bands, circle_points, fill_spacing, graded_fill};
use holes::fill_holes;
use ring::triangulate_ring;
use roi::{Similarity, mean_edge_length, validate};

use crate::{Error, Result};

/// A region of interest extended by a sea (output of [`build_sea`], DEM paper Algorithm 4).
///
/// The first `n_roi_vertices` positions are the ROI's vertices, in their order and at their
/// input positions; the first `n_roi_faces` faces are the ROI's faces, unchanged. The sea's
/// vertices and faces follow. All faces are counter-clockwise and the whole mesh is a
/// triangulated disk in which the ROI boundary is interior.
#[derive(Debug, Clone, PartialEq)]
pub struct SeaMesh {
    /// Vertex positions: ROI vertices first, then the sea's.
    pub positions: Vec<[f64; 2]>,
    /// Counter-clockwise faces: ROI faces first, then the sea's.
    pub faces: Vec<[u32; 3]>,
    /// Number of ROI vertices (a prefix of `positions`).
    pub n_roi_vertices: usize,
    /// Number of ROI faces (a prefix of `faces`).
    pub n_roi_faces: usize,
}

/// Builds the sea around a planar region of interest: DEM paper, Algorithm 4 (construction of
/// the sea via reflection), with the reflection g(z) = 1/z̄ of eq. (4.18) and the gluing
/// (4.19)–(4.21).
///
/// `roi_positions`/`roi_faces` must be a planar, counter-clockwise, flip-free triangulated disk
/// and `boundary` its boundary loop, counter-clockwise; `eta` > 1 is the truncation radius (the
/// paper uses η = 5), measured in the frame where the ROI fits in the disk of radius 0.5.
///
/// Steps, in that frame:
/// 1. the ROI is translated to its area centroid and scaled so that its farthest vertex is at
///    radius 0.5 (Algorithm 4, step 1);
/// 2. with `l` the ROI's mean edge length, the gap up to the unit circle is filled with
///    hexagonal lattice points graded by distance to the ROI boundary: spacing `l` up to
///    distance ≈ 3.5 l, then doubling band by band (points at distance ≥ l/2 from the boundary,
///    outside the ROI, with |z| ≤ 1 − spacing/2), and points on the unit circle at the local
///    spacing (step 2; the paper fills at the mean edge length everywhere, which on fine meshes
///    makes the sea several times larger than the ROI for no gain in accuracy);
///    the finest spacing is clamped to at most 0.25 (a coarse ROI still gets a usable sea) and
///    to at least the value giving 4·10⁶ lattice points in the unit disk (a bound on memory);
/// 3. a constrained Delaunay triangulation of the ROI boundary, the lattice and the circle points,
///    constrained by the ROI boundary edges, gives the ring between the ROI and the circle; the
///    ROI's own faces are kept (step 3);
/// 4. the triangulated disk D_T (ROI + ring) is reflected by g(z) = 1/z̄; the circle vertices
///    are shared and the reflected faces are reversed to stay counter-clockwise (steps 4–5);
/// 5. reflected vertices with |z| > η are removed with their faces (step 6), and what remains is
///    cleaned into one manifold disk: face components not edge-connected to the ROI and faces
///    making a vertex non-manifold are dropped; reflected faces that would be inverted (the
///    reflection of a triangle whose circumcircle contains the origin keeps its orientation)
///    are removed with their reflected vertices and the resulting holes, if any, are
///    re-triangulated by ear clipping;
/// 6. everything is mapped back by the inverse similarity (step 7); the ROI vertices are copied
///    from the input, not recomputed.
///
/// Errors: [`Error::Argument`] for a bad `eta`; [`Error::InvalidMesh`] for a ROI that is not a
/// counter-clockwise disk with a simple boundary (bad indices, non-finite positions, repeated
/// or self-intersecting boundary); [`Error::Numerical`] if the result fails its final check
/// (a manifold disk with counter-clockwise faces).
pub fn build_sea(
    roi_positions: &[[f64; 2]],
    roi_faces: &[[u32; 3]],
    boundary: &[u32],
    eta: f64,
) -> Result<SeaMesh> {
    build_sea_with_radius(roi_positions, roi_faces, boundary, eta, 0.5)
}

/// [`build_sea`] with the ROI scaled so that its farthest vertex is at `roi_radius` (in (0, 1))
/// inside the unit circle, instead of 0.5. A larger radius leaves a thinner ring to fill, so
/// the sea has fewer vertices, while still reaching η / roi_radius ROI radii beyond the ROI
/// after reflection.
pub fn build_sea_with_radius(
    roi_positions: &[[f64; 2]],
    roi_faces: &[[u32; 3]],
    boundary: &[u32],
    eta: f64,
    roi_radius: f64,
) -> Result<SeaMesh> {
    if !(roi_radius > 0.0 && roi_radius < 1.0) {
        return Err(Error::Argument(format!(
            "the ROI radius in the unit disk must lie in (0, 1), got {roi_radius}"
        )));
    }
    validate(roi_positions, roi_faces, boundary, eta)?;
    let n = roi_positions.len();

    // Step 1: the similarity that puts the ROI inside the disk of radius 0.5.
    let frame = Similarity::fit(roi_positions, roi_faces, roi_radius)?;
    let z: Vec<[f64; 2]> = roi_positions.iter().map(|&p| frame.apply(p)).collect();

    // Step 2: lattice and circle points at the ROI's mean edge length.
    let l = mean_edge_length(&z, roi_faces, boundary);
    let spacing = fill_spacing(l);
    let bpoly: Vec<[f64; 2]> = boundary.iter().map(|&v| z[v as usize]).collect();
    let index = BoundaryIndex::new(&bpoly, 0.5 * spacing);
    let bands = Bands::new(&bpoly, spacing);
    let fill = graded_fill(&index, &bands);
    let circle = circle_points(&bands);
    let (m, c) = (fill.len(), circle.len());

    let parts = SeaParts {
        roi: &z,
        roi_faces,
        boundary,
        bpoly: &bpoly,
        index: &index,
        fill: &fill,
        circle: &circle,
    };
    if let Some(sea) = graded_outer_sea(&parts, eta, &frame, roi_positions)? {
        return Ok(sea);
    }

    // Uncompacted vertex layout: ROI | fill | circle | reflections of ROI and fill.
    let n_disk = n + m + c;
    let nv = n_disk + n + m;
    if nv >= u32::MAX as usize {
        return Err(Error::Argument(format!(
            "the sea would need {nv} vertices, more than 32-bit indices allow"
        )));
    }
    let mut pos = Vec::with_capacity(nv);
    pos.extend_from_slice(&z);
    pos.extend_from_slice(&fill);
    pos.extend_from_slice(&circle);
    for i in 0..n + m {
        let [x, y] = pos[i];
        let r2 = x * x + y * y;
        // g(z) = 1/z̄ = z/|z|²; the origin goes to infinity (and is truncated below).
        pos.push(if r2 > 0.0 {
            [x / r2, y / r2]
        } else {
            [f64::INFINITY, f64::INFINITY]
        });
    }

    // Step 3: the ring between the ROI and the unit circle.
    let ring = triangulate_ring(&bpoly, boundary, &fill, &circle, n, &index)?;

    // D_T = ROI faces + ring faces.
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(2 * (roi_faces.len() + ring.len()));
    faces.extend_from_slice(roi_faces);
    faces.extend_from_slice(&ring);
    let n_dt = faces.len();

    // Step 4: reflection (4.18), shared circle vertices (4.19), reversed faces (4.20).
    let circle_range = (n + m) as u32..n_disk as u32;
    let reflect = |v: u32| -> u32 {
        if circle_range.contains(&v) {
            v
        } else {
            v + n_disk as u32
        }
    };
    // Step 6 (truncation): a reflected vertex survives if |1/z̄| ≤ η.
    let mut dead = vec![false; nv];
    for (i, d) in dead.iter_mut().enumerate().skip(n_disk) {
        let [x, y] = pos[i];
        let r = x.hypot(y);
        *d = r.is_nan() || r > eta;
    }
    // Inverted reflected faces: remove their reflected vertices (holes are filled below).
    for f in &faces[..n_dt] {
        let r = [reflect(f[0]), reflect(f[2]), reflect(f[1])];
        if r.iter().all(|&v| !dead[v as usize]) && orient(&pos, r) <= 0.0 {
            for v in r {
                if v as usize >= n_disk {
                    dead[v as usize] = true;
                }
            }
        }
    }

    // Size of each vertex's complete fan: its D_T faces, their mirrors, or both (circle).
    let mut full = vec![0u32; nv];
    for f in &faces[..n_dt] {
        for &v in f {
            full[v as usize] += 1;
            full[reflect(v) as usize] += 1;
        }
    }

    let mut attempts = 0;
    let (faces, alive) = loop {
        attempts += 1;
        let mut all = faces[..n_dt].to_vec();
        for f in &faces[..n_dt] {
            let r = [reflect(f[0]), reflect(f[2]), reflect(f[1])];
            if r.iter().all(|&v| !dead[v as usize]) {
                all.push(r);
            }
        }
        let mut alive = vec![true; all.len()];
        let inc = Incidence::new(&all, nv);
        clean_up(&all, n_dt, &mut alive, &inc, &full, n + m, n_disk);
        match fill_holes(&pos, &inc, &alive, &full, n_disk) {
            Ok(new_faces) => {
                all.extend(new_faces);
                alive.resize(all.len(), true);
                break (all, alive);
            }
            Err(grow) if !grow.is_empty() && attempts < 20 => {
                for v in grow {
                    dead[v as usize] = true;
                }
            }
            Err(_) => {
                return Err(Error::Numerical(
                    "sea construction: could not close a hole in the reflected sea".into(),
                ));
            }
        }
    };

    // Compact: ROI vertices keep their indices; referenced sea vertices follow in order.
    let mut new_index = vec![u32::MAX; nv];
    for (i, slot) in new_index.iter_mut().enumerate().take(n) {
        *slot = i as u32;
    }
    let mut next = n as u32;
    let mut out_faces = Vec::with_capacity(faces.len());
    let mut referenced = vec![false; nv];
    for (f, &a) in faces.iter().zip(&alive) {
        if a {
            for &v in f {
                referenced[v as usize] = true;
            }
        }
    }
    let mut positions = roi_positions.to_vec();
    for v in n..nv {
        if referenced[v] {
            new_index[v] = next;
            next += 1;
            positions.push(frame.invert(pos[v]));
        }
    }
    for (f, &a) in faces.iter().zip(&alive) {
        if a {
            out_faces.push(f.map(|v| new_index[v as usize]));
        }
    }
    debug_assert!(out_faces[..roi_faces.len()] == *roi_faces);
    check_disk(&positions, &out_faces, roi_faces.len())?;
    Ok(SeaMesh {
        positions,
        faces: out_faces,
        n_roi_vertices: n,
        n_roi_faces: roi_faces.len(),
    })
}

/// [`graded_outer_sea`] is used when the farthest reflected ROI boundary vertex lies within
/// the truncation radius divided by this.
const OUTER_MARGIN: f64 = 1.25;

/// The pieces of the sea inside the unit circle, in the frame of [`Similarity`].
struct SeaParts<'a> {
    roi: &'a [[f64; 2]],
    roi_faces: &'a [[u32; 3]],
    boundary: &'a [u32],
    bpoly: &'a [[f64; 2]],
    index: &'a BoundaryIndex<'a>,
    fill: &'a [[f64; 2]],
    circle: &'a [[f64; 2]],
}

/// The sea with the reflected ring but without the reflected ROI: beyond the reflection of
/// the ROI boundary, up to the circle of radius `eta` (or a little beyond the farthest
/// reflected boundary vertex), a graded fill triangulated like the ring. `None` when the
/// origin is not inside the ROI (the reflection of the ring would not be bounded) or a
/// reflected face would be inverted; the caller then reflects the whole disk.
fn graded_outer_sea(
    parts: &SeaParts,
    eta: f64,
    frame: &Similarity,
    roi_positions: &[[f64; 2]],
) -> Result<Option<SeaMesh>> {
    let SeaParts {
        roi,
        roi_faces,
        boundary,
        bpoly,
        index,
        fill,
        circle,
    } = *parts;
    let (n, m, c, b) = (roi.len(), fill.len(), circle.len(), boundary.len());
    if !index.contains([0.0, 0.0]) || !index.far_from_boundary([0.0, 0.0]) {
        return Ok(None);
    }
    let ring = ring::triangulate_ring(bpoly, boundary, fill, circle, n, index)?;
    let inv = |p: [f64; 2]| {
        let r2 = p[0] * p[0] + p[1] * p[1];
        [p[0] / r2, p[1] / r2]
    };
    // Reflected boundary (z ↦ 1/z̄ keeps every point's angle, so it still runs
    // counter-clockwise around the origin), scaled into the unit disk.
    let far = bpoly
        .iter()
        .map(|&p| {
            let q = inv(p);
            q[0].hypot(q[1])
        })
        .fold(0.0, f64::max);
    // The reflected ring must stay inside the truncation radius, with room for a band of fill.
    if !(OUTER_MARGIN * far <= eta) {
        return Ok(None);
    }
    let radius = eta;
    let outer_poly: Vec<[f64; 2]> = (0..b)
        .map(|k| {
            let q = inv(bpoly[k]);
            [q[0] / radius, q[1] / radius]
        })
        .collect();
    let lengths: f64 = (0..b)
        .map(|k| {
            let (p, q) = (outer_poly[k], outer_poly[(k + 1) % b]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .sum();
    let spacing = fill_spacing(lengths / b as f64);
    let outer_index = BoundaryIndex::new(&outer_poly, 0.5 * spacing);
    let outer_bands = Bands::new(&outer_poly, spacing);
    let outer_fill = graded_fill(&outer_index, &outer_bands);
    let outer_circle = circle_points(&outer_bands);

    // Vertex layout: ROI | fill | circle | reflected boundary | reflected fill | outer fill |
    // outer circle.
    let n_disk = n + m + c;
    let rb = n_disk; // reflected boundary vertex k (boundary order)
    let rf = rb + b; // reflected fill point k
    let of = rf + m; // outer fill and outer circle
    let nv = of + outer_fill.len() + outer_circle.len();
    if nv >= u32::MAX as usize {
        return Err(Error::Argument(format!(
            "the sea would need {nv} vertices, more than 32-bit indices allow"
        )));
    }
    let mut pos = Vec::with_capacity(nv);
    pos.extend_from_slice(roi);
    pos.extend_from_slice(fill);
    pos.extend_from_slice(circle);
    pos.extend(bpoly.iter().map(|&p| inv(p)));
    pos.extend(fill.iter().map(|&p| inv(p)));
    pos.extend(
        outer_fill
            .iter()
            .chain(&outer_circle)
            .map(|p| [p[0] * radius, p[1] * radius]),
    );
    let mut slot = vec![u32::MAX; n];
    for (k, &v) in boundary.iter().enumerate() {
        slot[v as usize] = (rb + k) as u32;
    }
    let reflect = |v: u32| -> u32 {
        let v = v as usize;
        if v < n {
            slot[v]
        } else if v < n + m {
            (rf + v - n) as u32
        } else {
            v as u32
        }
    };
    let outer_ids: Vec<u32> = (0..b).map(|k| (rb + k) as u32).collect();
    let outer = ring::triangulate_ring(
        &outer_poly,
        &outer_ids,
        &outer_fill,
        &outer_circle,
        of,
        &outer_index,
    )?;

    let mut faces = Vec::with_capacity(roi_faces.len() + 2 * ring.len() + outer.len());
    faces.extend_from_slice(roi_faces);
    faces.extend_from_slice(&ring);
    for f in &ring {
        let r = [reflect(f[0]), reflect(f[2]), reflect(f[1])];
        if r.contains(&u32::MAX) || orient(&pos, r) <= 0.0 {
            return Ok(None);
        }
        faces.push(r);
    }
    faces.extend_from_slice(&outer);

    // Compact: ROI vertices keep their indices; referenced sea vertices follow in order.
    let mut referenced = vec![false; nv];
    for f in &faces {
        for &v in f {
            referenced[v as usize] = true;
        }
    }
    let mut new_index = vec![u32::MAX; nv];
    let mut positions = roi_positions.to_vec();
    for (i, slot) in new_index.iter_mut().enumerate().take(n) {
        *slot = i as u32;
    }
    for v in n..nv {
        if referenced[v] {
            new_index[v] = positions.len() as u32;
            positions.push(frame.invert(pos[v]));
        }
    }
    let faces: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| f.map(|v| new_index[v as usize]))
        .collect();
    if check_disk(&positions, &faces, roi_faces.len()).is_err() {
        return Ok(None);
    }
    Ok(Some(SeaMesh {
        positions,
        faces,
        n_roi_vertices: n,
        n_roi_faces: roi_faces.len(),
    }))
}
