//! Construction of the sea around a planar region of interest by reflection
//! (DEM paper, section 4.2, Algorithm 4, eqs. (4.18)–(4.21)).
//!
//! The region of interest (ROI, the initial flattening map r₀) is shrunk into the unit disk,
//! the gap up to the unit circle is filled with lattice points, at the ROI's mean edge length
//! next to the ROI and coarsening geometrically away from it, and triangulated by a constrained Delaunay triangulation that keeps the ROI's own
//! triangles; the triangulated unit disk D_T is then glued to its image under the reflection
//! g(z) = 1/z̄ (4.18) along the unit circle (4.19)–(4.21), truncated at |z| ≤ η, and scaled back.

use crate::geometry::segment::segment_distance;
use crate::mesh::triangulate::constrained_delaunay;

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

/// The similarity z = s (p − c) of Algorithm 4, step 1, and its inverse (step 7).
struct Similarity {
    center: [f64; 2],
    scale: f64,
}

impl Similarity {
    /// Area centroid of the ROI to the origin, farthest vertex to radius 0.5.
    fn fit(p: &[[f64; 2]], faces: &[[u32; 3]], roi_radius: f64) -> Result<Self> {
        let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for f in faces {
            let [a, b, c] = f.map(|v| p[v as usize]);
            let ar = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
            area += ar;
            cx += ar * (a[0] + b[0] + c[0]) / 3.0;
            cy += ar * (a[1] + b[1] + c[1]) / 3.0;
        }
        if !(area > 0.0 && area.is_finite()) {
            return Err(Error::InvalidMesh(format!(
                "the region of interest has total signed area {area}: it must be a \
                 counter-clockwise planar disk"
            )));
        }
        let center = [cx / area, cy / area];
        let radius = p
            .iter()
            .map(|q| (q[0] - center[0]).hypot(q[1] - center[1]))
            .fold(0.0, f64::max);
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(Error::InvalidMesh(
                "the region of interest has no extent".into(),
            ));
        }
        Ok(Similarity {
            center,
            scale: roi_radius / radius,
        })
    }

    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.scale * (p[0] - self.center[0]),
            self.scale * (p[1] - self.center[1]),
        ]
    }

    fn invert(&self, z: [f64; 2]) -> [f64; 2] {
        [
            z[0] / self.scale + self.center[0],
            z[1] / self.scale + self.center[1],
        ]
    }
}

fn validate(p: &[[f64; 2]], faces: &[[u32; 3]], boundary: &[u32], eta: f64) -> Result<()> {
    if !(eta.is_finite() && eta > 1.0) {
        return Err(Error::Argument(format!(
            "sea truncation radius eta must be a finite number > 1, got {eta}"
        )));
    }
    let n = p.len();
    if let Some(v) = p
        .iter()
        .position(|q| !(q[0].is_finite() && q[1].is_finite()))
    {
        return Err(Error::InvalidMesh(format!(
            "vertex {v} of the region of interest has a non-finite position"
        )));
    }
    for (k, f) in faces.iter().enumerate() {
        if f.iter().any(|&v| v as usize >= n) {
            return Err(Error::InvalidMesh(format!(
                "face {k} {f:?} refers to a vertex beyond the {n} vertices"
            )));
        }
        if f[0] == f[1] || f[1] == f[2] || f[2] == f[0] {
            return Err(Error::InvalidMesh(format!(
                "face {k} {f:?} repeats a vertex"
            )));
        }
    }
    if boundary.len() < 3 {
        return Err(Error::InvalidMesh(format!(
            "the boundary loop has {} vertices, at least 3 are needed",
            boundary.len()
        )));
    }
    let mut seen = vec![false; n];
    for (k, &v) in boundary.iter().enumerate() {
        let Some(s) = seen.get_mut(v as usize) else {
            return Err(Error::InvalidMesh(format!(
                "boundary loop entry {k} is vertex {v}, beyond the {n} vertices"
            )));
        };
        if *s {
            return Err(Error::InvalidMesh(format!(
                "vertex {v} appears twice in the boundary loop"
            )));
        }
        *s = true;
    }
    let b = boundary.len();
    let area: f64 = (0..b)
        .map(|k| {
            let (a, c) = (p[boundary[k] as usize], p[boundary[(k + 1) % b] as usize]);
            a[0] * c[1] - a[1] * c[0]
        })
        .sum();
    if area <= 0.0 {
        return Err(Error::InvalidMesh(
            "the boundary loop of the region of interest must be counter-clockwise".into(),
        ));
    }
    Ok(())
}

/// Mean length of the ROI's (undirected) edges: every interior edge appears in two faces and
/// every boundary edge in one, so Σ_edges = (Σ_half-edges + Σ_boundary) / 2.
fn mean_edge_length(z: &[[f64; 2]], faces: &[[u32; 3]], boundary: &[u32]) -> f64 {
    let d = |a: u32, b: u32| {
        let (p, q) = (z[a as usize], z[b as usize]);
        (q[0] - p[0]).hypot(q[1] - p[1])
    };
    let half: f64 = faces
        .iter()
        .map(|f| d(f[0], f[1]) + d(f[1], f[2]) + d(f[2], f[0]))
        .sum();
    let b = boundary.len();
    let bsum: f64 = (0..b).map(|k| d(boundary[k], boundary[(k + 1) % b])).sum();
    (half + bsum) / (3 * faces.len() + b) as f64
}

/// Most lattice points allowed in the unit disk; beyond that the lattice is coarsened.
const MAX_FILL_POINTS: f64 = 4.0e6;

/// The lattice spacing: the mean edge length l, but not so small that the hexagonal lattice
/// (2/(√3 l²) points per unit area) would exceed [`MAX_FILL_POINTS`] in the unit disk, and not
/// larger than a quarter of the disk's radius.
fn fill_spacing(l: f64) -> f64 {
    let min = (2.0 * std::f64::consts::PI / (3f64.sqrt() * MAX_FILL_POINTS)).sqrt();
    if l.is_finite() {
        l.clamp(min, 0.25)
    } else {
        0.25
    }
}

/// How many lattice spacings each band of the graded fill is wide before the spacing doubles.
const BAND_WIDTH: f64 = 3.0;

/// The distance bands of the graded fill: level `k` has lattice spacing `s·2^k` and covers the
/// points whose distance to the ROI boundary lies in `[lo_k, hi_k)`, with `lo_0 = s/2`,
/// `hi_k = lo_k + BAND_WIDTH·s·2^k` and a gap of a quarter spacing between bands (no two points
/// of neighbouring levels come closer than that). The last level, the first whose spacing
/// reaches 0.25, has no upper limit. Near the ROI the sea is as fine as the ROI's own mesh; far
/// from it, where the density is uniform, it coarsens geometrically — the sea then costs a
/// multiple of the ROI's boundary length instead of a multiple of the disk's area.
struct Bands<'a> {
    /// Per level: spacing, index answering "distance ≥ lo", index answering "distance ≥ hi"
    /// (`None` for the last level).
    levels: Vec<(f64, BoundaryIndex<'a>, Option<BoundaryIndex<'a>>)>,
}

impl<'a> Bands<'a> {
    fn new(poly: &'a [[f64; 2]], s: f64) -> Self {
        let mut levels = Vec::new();
        let (mut spacing, mut lo) = (s, 0.5 * s);
        loop {
            let last = spacing >= 0.25 || levels.len() >= 16;
            let hi = lo + BAND_WIDTH * spacing;
            let upper = (!last).then(|| BoundaryIndex::new(poly, hi));
            levels.push((spacing, BoundaryIndex::new(poly, lo), upper));
            if last {
                break;
            }
            spacing *= 2.0;
            lo = hi + 0.25 * spacing;
        }
        Self { levels }
    }

    /// The spacing wanted at `p` (outside the ROI): that of the finest level whose band
    /// reaches `p`.
    fn spacing_at(&self, p: [f64; 2]) -> f64 {
        for (spacing, _, upper) in &self.levels {
            match upper {
                Some(u) if u.far_from_boundary(p) => continue,
                _ => return *spacing,
            }
        }
        self.levels.last().map_or(0.25, |l| l.0)
    }
}

/// Points on the unit circle, counter-clockwise from (1, 0), each at the local spacing of the
/// graded fill ([`Bands::spacing_at`]) from the previous one.
fn circle_points(bands: &Bands) -> Vec<[f64; 2]> {
    let tau = 2.0 * std::f64::consts::PI;
    let mut angles: Vec<f64> = vec![0.0];
    loop {
        let t = *angles.last().unwrap_or(&0.0);
        let step = bands.spacing_at([t.cos(), t.sin()]).min(tau / 8.0);
        if t + 1.5 * step > tau {
            break;
        }
        angles.push(t + step);
    }
    angles.iter().map(|t| [t.cos(), t.sin()]).collect()
}

/// The graded fill of the gap between the ROI and the unit circle: for every level of
/// `bands`, the hexagonal lattice points of its spacing `s` in |z| ≤ 1 − s/2 that lie outside
/// the ROI polygon and in the level's distance band.
fn graded_fill(index: &BoundaryIndex, bands: &Bands) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for (s, lower, upper) in &bands.levels {
        lattice_points(*s, |p| {
            if lower.far_from_boundary(p)
                && upper.as_ref().is_none_or(|u| !u.far_from_boundary(p))
                && !index.contains(p)
            {
                out.push(p);
            }
        });
    }
    out
}

/// Calls `keep` with every point of the hexagonal lattice of spacing `s` in |z| ≤ 1 − s/2.
fn lattice_points(s: f64, mut keep: impl FnMut([f64; 2])) {
    let dy = s * 3f64.sqrt() / 2.0;
    let rmax = 1.0 - 0.5 * s;
    let rows = (rmax / dy).floor() as i64;
    let cols = (rmax / s).ceil() as i64 + 1;
    for j in -rows..=rows {
        let y = j as f64 * dy;
        let shift = if j.rem_euclid(2) == 1 { 0.5 * s } else { 0.0 };
        for i in -cols..=cols {
            let x = i as f64 * s + shift;
            if x * x + y * y <= rmax * rmax {
                keep([x, y]);
            }
        }
    }
}

/// The constrained Delaunay triangulation of the ROI boundary, the lattice and the circle
/// points, constrained by the ROI boundary edges (Algorithm 4, step 3); returns the faces
/// outside the ROI polygon, with ROI boundary vertices by their ROI indices and the others at
/// `n + k` (fill point k) and `n + fill.len() + k` (circle point k).
fn triangulate_ring(
    bpoly: &[[f64; 2]],
    boundary: &[u32],
    fill: &[[f64; 2]],
    circle: &[[f64; 2]],
    n: usize,
    index: &BoundaryIndex,
) -> Result<Vec<[u32; 3]>> {
    let b = bpoly.len();
    let m = fill.len();
    let points: Vec<[f64; 2]> = bpoly.iter().chain(fill).chain(circle).copied().collect();
    let edges: Vec<[usize; 2]> = (0..b).map(|k| [k, (k + 1) % b]).collect();
    // Fill and circle points keep away from the boundary by construction, so any coincidence
    // or crossing is the boundary loop's own.
    if let Some((i, j)) = crate::mesh::triangulate::coincident_pair(bpoly) {
        return Err(Error::InvalidMesh(format!(
            "boundary vertices {} and {} are at the same position in the initial map (is one a \
             duplicate of the other?)",
            boundary[i], boundary[j]
        )));
    }
    let cdt = constrained_delaunay(&points, &edges).map_err(|e| {
        let detail = match e {
            Error::InvalidMesh(m) => m,
            other => other.to_string(),
        };
        Error::InvalidMesh(format!(
            "the boundary loop of the region of interest is not a simple polygon \
             (it touches, crosses or repeats itself): {detail}"
        ))
    })?;
    let next = |k: usize| if k + 1 == b { 0 } else { k + 1 };
    let global = |k: usize| -> u32 {
        if k < b {
            boundary[k]
        } else {
            (n + k - b) as u32
        }
    };
    let mut out = Vec::with_capacity(cdt.faces.len());
    for f in &cdt.faces {
        let v = f.map(|i| i as usize);
        if v.iter().all(|&k| k >= b + m) {
            // Three circle points: its reflection is itself; leave the cap out.
            continue;
        }
        let outside = if v.iter().any(|&k| k >= b) {
            // A lattice or circle vertex is strictly outside the ROI, and no triangle crosses
            // a constraint edge.
            true
        } else {
            // All three on the ROI boundary: a constraint edge decides combinatorially (the ROI
            // is on its left); otherwise the centroid does.
            let mut side = None;
            for e in 0..3 {
                let (p, q) = (v[e], v[(e + 1) % 3]);
                if next(p) == q {
                    side = Some(false);
                } else if next(q) == p {
                    side = Some(true);
                }
            }
            side.unwrap_or_else(|| {
                let c = [
                    (bpoly[v[0]][0] + bpoly[v[1]][0] + bpoly[v[2]][0]) / 3.0,
                    (bpoly[v[0]][1] + bpoly[v[1]][1] + bpoly[v[2]][1]) / 3.0,
                ];
                !index.contains(c)
            })
        };
        if outside {
            out.push(v.map(global));
        }
    }
    Ok(out)
}

/// Spatial index of the ROI boundary polygon: horizontal slabs for point-in-polygon by ray
/// casting, and a uniform grid for "farther than `dist` from every edge".
struct BoundaryIndex<'a> {
    poly: &'a [[f64; 2]],
    ymin: f64,
    slab_h: f64,
    slab_start: Vec<u32>,
    slab_edges: Vec<u32>,
    dist: f64,
    gx: f64,
    gy: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    cell_start: Vec<u32>,
    cell_edges: Vec<u32>,
}

impl<'a> BoundaryIndex<'a> {
    fn new(poly: &'a [[f64; 2]], dist: f64) -> Self {
        let b = poly.len();
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in poly {
            xmin = xmin.min(p[0]);
            xmax = xmax.max(p[0]);
            ymin = ymin.min(p[1]);
            ymax = ymax.max(p[1]);
        }
        let edge = |k: usize| (poly[k], poly[(k + 1) % b]);

        // Slabs.
        let n_slabs = b.clamp(1, 1 << 16);
        let slab_h = ((ymax - ymin) / n_slabs as f64).max(f64::MIN_POSITIVE);
        let slab_of = |y: f64| (((y - ymin) / slab_h).floor().max(0.0) as usize).min(n_slabs - 1);
        let (slab_start, slab_edges) = bucket(n_slabs, b, |k, push| {
            let (p, q) = edge(k);
            for s in slab_of(p[1].min(q[1]))..=slab_of(p[1].max(q[1])) {
                push(s);
            }
        });

        // Grid of cells of side >= dist, at most 512 per axis.
        let (gx, gy) = (xmin - dist, ymin - dist);
        let extent = (xmax - xmin).max(ymax - ymin) + 2.0 * dist;
        let cell = (2.0 * dist).max(extent / 512.0).max(f64::MIN_POSITIVE);
        let nx = ((xmax + dist - gx) / cell).floor() as usize + 1;
        let ny = ((ymax + dist - gy) / cell).floor() as usize + 1;
        let cell_of = |x: f64, y: f64| {
            (
                (((x - gx) / cell).floor().max(0.0) as usize).min(nx - 1),
                (((y - gy) / cell).floor().max(0.0) as usize).min(ny - 1),
            )
        };
        let (cell_start, cell_edges) = bucket(nx * ny, b, |k, push| {
            let (p, q) = edge(k);
            let (i0, j0) = cell_of(p[0].min(q[0]) - dist, p[1].min(q[1]) - dist);
            let (i1, j1) = cell_of(p[0].max(q[0]) + dist, p[1].max(q[1]) + dist);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    push(j * nx + i);
                }
            }
        });
        BoundaryIndex {
            poly,
            ymin,
            slab_h,
            slab_start,
            slab_edges,
            dist,
            gx,
            gy,
            cell,
            nx,
            ny,
            cell_start,
            cell_edges,
        }
    }

    /// Point in polygon by ray casting towards +x, with the half-open rule on y.
    fn contains(&self, p: [f64; 2]) -> bool {
        let n_slabs = self.slab_start.len() - 1;
        let s = (p[1] - self.ymin) / self.slab_h;
        if !(s >= 0.0 && s < n_slabs as f64 + 1.0) {
            return false;
        }
        let s = (s.floor() as usize).min(n_slabs - 1);
        let b = self.poly.len();
        let mut inside = false;
        for &e in &self.slab_edges[self.slab_start[s] as usize..self.slab_start[s + 1] as usize] {
            let (a, c) = (self.poly[e as usize], self.poly[(e as usize + 1) % b]);
            if (a[1] > p[1]) != (c[1] > p[1]) {
                let o = orient2(a, c, p);
                if (c[1] > a[1] && o > 0.0) || (c[1] < a[1] && o < 0.0) {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// True if `p` is at distance ≥ `dist` from every boundary edge.
    fn far_from_boundary(&self, p: [f64; 2]) -> bool {
        let (fx, fy) = ((p[0] - self.gx) / self.cell, (p[1] - self.gy) / self.cell);
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.nx as f64 && fy < self.ny as f64) {
            return true;
        }
        let c = fy as usize * self.nx + fx as usize;
        let b = self.poly.len();
        let d2 = self.dist * self.dist;
        self.cell_edges[self.cell_start[c] as usize..self.cell_start[c + 1] as usize]
            .iter()
            .all(|&e| {
                let (a, q) = (self.poly[e as usize], self.poly[(e as usize + 1) % b]);
                segment_distance(p, a, q).0.powi(2) >= d2
            })
    }
}

/// Compressed buckets: `items(k, push)` pushes the buckets of item k; returns (start, items).
fn bucket(
    n_buckets: usize,
    n_items: usize,
    items: impl Fn(usize, &mut dyn FnMut(usize)),
) -> (Vec<u32>, Vec<u32>) {
    let mut count = vec![0u32; n_buckets + 1];
    for k in 0..n_items {
        items(k, &mut |s| count[s + 1] += 1);
    }
    for s in 0..n_buckets {
        count[s + 1] += count[s];
    }
    let mut fill = count.clone();
    let mut out = vec![0u32; count[n_buckets] as usize];
    for k in 0..n_items {
        items(k, &mut |s| {
            out[fill[s] as usize] = k as u32;
            fill[s] += 1;
        });
    }
    (count, out)
}

/// Twice the signed area of (a, b, c).
fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn orient(pos: &[[f64; 2]], f: [u32; 3]) -> f64 {
    orient2(pos[f[0] as usize], pos[f[1] as usize], pos[f[2] as usize])
}

/// One corner of a face at a vertex v: the face and the vertices after and before v in it.
#[derive(Debug, Clone, Copy, Default)]
struct Corner {
    face: u32,
    next: u32,
    prev: u32,
}

/// Vertex → corners incidence of a face list, in compressed form. The half-edges leaving v
/// are v → `next` of its corners, so twins are found by a scan of one short contiguous list.
/// Queries take the faces' `alive` flags, so faces can be dropped without a rebuild.
struct Incidence {
    start: Vec<u32>,
    corners: Vec<Corner>,
}

impl Incidence {
    fn new(faces: &[[u32; 3]], nv: usize) -> Self {
        let mut start = vec![0u32; nv + 1];
        for f in faces {
            for &v in f {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut corners = vec![Corner::default(); start[nv] as usize];
        for (k, f) in faces.iter().enumerate() {
            for e in 0..3 {
                let v = f[e] as usize;
                corners[fill[v] as usize] = Corner {
                    face: k as u32,
                    next: f[(e + 1) % 3],
                    prev: f[(e + 2) % 3],
                };
                fill[v] += 1;
            }
        }
        Incidence { start, corners }
    }

    /// The corners of alive faces at `v`.
    fn of<'a>(&'a self, v: u32, alive: &'a [bool]) -> impl Iterator<Item = &'a Corner> + 'a {
        self.corners[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
            .iter()
            .filter(move |c| alive[c.face as usize])
    }

    /// Whether some alive face holds the half-edge b → a (the twin of a → b).
    fn has_twin(&self, a: u32, b: u32, alive: &[bool]) -> bool {
        self.of(b, alive).any(|c| c.next == a)
    }
}

/// Drops (marks not alive) the faces that are not edge-connected to the first `n_dt` faces
/// (the triangulated unit disk D_T, never dropped) and, at every vertex whose faces form more
/// than one fan (two or more outgoing boundary half-edges), the faces of the fans other than
/// the one holding a D_T face (or the largest), until nothing changes. Vertices below
/// `n_circle` are inner vertices of D_T (all their faces are D_T faces); the circle vertices
/// are `n_circle..n_disk`. A vertex with `full[v]` alive faces has its complete fan.
fn clean_up(
    faces: &[[u32; 3]],
    n_dt: usize,
    alive: &mut [bool],
    inc: &Incidence,
    full: &[u32],
    n_circle: usize,
    n_disk: usize,
) {
    let nv = inc.start.len() - 1;
    let on_circle = |v: u32| (n_circle..n_disk).contains(&(v as usize));
    let mut list: Vec<Corner> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    loop {
        let mut changed = false;

        // Edge-connected component of D_T: D_T is connected, so search the reflected faces
        // from those glued to D_T along a circle edge (two circle vertices).
        let mut reached = vec![false; faces.len()];
        reached[..n_dt].fill(true);
        let mut stack: Vec<u32> = (n_dt..faces.len())
            .filter(|&f| alive[f] && faces[f].iter().filter(|&&v| on_circle(v)).count() >= 2)
            .map(|f| f as u32)
            .collect();
        for &f in &stack {
            reached[f as usize] = true;
        }
        while let Some(f) = stack.pop() {
            let fv = faces[f as usize];
            for e in 0..3 {
                let (a, b) = (fv[e], fv[(e + 1) % 3]);
                for c in inc.of(b, alive) {
                    if c.next == a && !reached[c.face as usize] {
                        reached[c.face as usize] = true;
                        stack.push(c.face);
                    }
                }
            }
        }
        for (a, r) in alive.iter_mut().zip(&reached) {
            if *a && !r {
                *a = false;
                changed = true;
            }
        }
        if changed {
            continue;
        }

        // One fan per vertex. Every open fan has one outgoing boundary half-edge (the faces of
        // a vertex are a subset of one fan of D_T or of its mirror, so no second closed fan).
        for v in n_circle as u32..nv as u32 {
            if inc.of(v, alive).count() == full[v as usize] as usize {
                continue;
            }
            let open = inc
                .of(v, alive)
                .filter(|c| !inc.has_twin(v, c.next, alive))
                .count();
            if open < 2 {
                continue;
            }
            list.clear();
            list.extend(inc.of(v, alive).copied());
            // Corner j follows corner i around v when j's face holds v → prev(i).
            parent.clear();
            parent.extend(0..list.len());
            for i in 0..list.len() {
                for j in 0..list.len() {
                    if list[j].next == list[i].prev {
                        let (x, y) = (find(&mut parent, i), find(&mut parent, j));
                        if x != y {
                            parent[x.max(y)] = x.min(y);
                        }
                    }
                }
            }
            let roots: Vec<usize> = (0..list.len()).map(|i| find(&mut parent, i)).collect();
            let mut size = vec![0usize; list.len()];
            let mut has_dt = vec![false; list.len()];
            for (i, &r) in roots.iter().enumerate() {
                size[r] += 1;
                has_dt[r] |= (list[i].face as usize) < n_dt;
            }
            let any_dt = has_dt.iter().any(|&d| d);
            let best = (0..list.len()).max_by_key(|&k| (size[k], usize::MAX - k));
            for (i, &r) in roots.iter().enumerate() {
                let keep = if any_dt { has_dt[r] } else { Some(r) == best };
                if !keep {
                    alive[list[i].face as usize] = false;
                    changed = true;
                }
            }
        }
        if !changed {
            return;
        }
    }
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The directed boundary half-edges a → b of the alive faces (no alive face has b → a), as
/// `next[a] = b`; `None` if a vertex has two outgoing boundary edges (not a manifold).
/// Vertices with `full[v]` alive faces (a complete fan) are skipped.
fn boundary_next(inc: &Incidence, alive: &[bool], full: Option<&[u32]>) -> Option<Vec<u32>> {
    let mut next = vec![u32::MAX; inc.start.len() - 1];
    for (v, slot) in next.iter_mut().enumerate() {
        if full.is_some_and(|full| inc.of(v as u32, alive).count() == full[v] as usize) {
            continue;
        }
        for c in inc.of(v as u32, alive) {
            if !inc.has_twin(v as u32, c.next, alive) {
                if *slot != u32::MAX {
                    return None;
                }
                *slot = c.next;
            }
        }
    }
    Some(next)
}

/// The boundary loops given by `next`, in order of their smallest vertex.
fn loops(next: &[u32]) -> Vec<Vec<u32>> {
    let mut seen = vec![false; next.len()];
    let mut out = Vec::new();
    for v in 0..next.len() {
        if next[v] == u32::MAX || seen[v] {
            continue;
        }
        let mut lp = Vec::new();
        let mut w = v as u32;
        while !seen[w as usize] && next[w as usize] != u32::MAX {
            seen[w as usize] = true;
            lp.push(w);
            w = next[w as usize];
        }
        out.push(lp);
    }
    out
}

fn loop_area(pos: &[[f64; 2]], lp: &[u32]) -> f64 {
    let k = lp.len();
    (0..k)
        .map(|i| {
            let (a, b) = (pos[lp[i] as usize], pos[lp[(i + 1) % k] as usize]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0
}

/// Fills every hole (a clockwise boundary loop) of the alive faces by ear clipping. On failure
/// returns the reflected vertices (index ≥ `n_disk`) of the offending loop, to be removed
/// so that the hole grows and gets another chance.
fn fill_holes(
    pos: &[[f64; 2]],
    inc: &Incidence,
    alive: &[bool],
    full: &[u32],
    n_disk: usize,
) -> std::result::Result<Vec<[u32; 3]>, Vec<u32>> {
    let reflected = |lp: &[u32]| -> Vec<u32> {
        lp.iter()
            .copied()
            .filter(|&v| v as usize >= n_disk)
            .collect()
    };
    let Some(next) = boundary_next(inc, alive, Some(full)) else {
        // Not a manifold: remove the reflected vertices on every boundary.
        let nv = inc.start.len() - 1;
        let on_boundary = (n_disk..nv)
            .map(|v| v as u32)
            .filter(|&v| inc.of(v, alive).any(|c| !inc.has_twin(v, c.next, alive)));
        return Err(on_boundary.collect());
    };
    let mut new_faces = Vec::new();
    for lp in loops(&next) {
        if loop_area(pos, &lp) > 0.0 {
            continue; // the outer boundary
        }
        let mut poly = lp.clone();
        poly.reverse();
        match ear_clip(pos, &poly) {
            Some(tris) => new_faces.extend(tris),
            None => return Err(reflected(&lp)),
        }
    }
    Ok(new_faces)
}

/// Triangulates a simple counter-clockwise polygon (vertex indices into `pos`) by ear clipping,
/// choosing the best-shaped ear; `None` if the polygon is not simple or an ear cannot be found.
fn ear_clip(pos: &[[f64; 2]], poly: &[u32]) -> Option<Vec<[u32; 3]>> {
    let k = poly.len();
    if !(3..=4096).contains(&k) || !is_simple(pos, poly) {
        return None;
    }
    let p = |v: u32| pos[v as usize];
    let mut idx: Vec<u32> = poly.to_vec();
    let mut out = Vec::with_capacity(k - 2);
    while idx.len() > 3 {
        let m = idx.len();
        let mut best: Option<(f64, usize)> = None;
        for i in 0..m {
            let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            let area = orient2(p(a), p(b), p(c));
            if area <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&o| {
                o != a && o != b && o != c && {
                    let q = p(o);
                    orient2(p(a), p(b), q) >= 0.0
                        && orient2(p(b), p(c), q) >= 0.0
                        && orient2(p(c), p(a), q) >= 0.0
                }
            });
            if blocked {
                continue;
            }
            let d2 = |u: [f64; 2], w: [f64; 2]| (u[0] - w[0]).powi(2) + (u[1] - w[1]).powi(2);
            let quality = area / (d2(p(a), p(b)) + d2(p(b), p(c)) + d2(p(c), p(a)));
            if best.is_none_or(|(q, _)| quality > q) {
                best = Some((quality, i));
            }
        }
        let (_, i) = best?;
        let m = idx.len();
        out.push([idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]]);
        idx.remove(i);
    }
    if orient2(p(idx[0]), p(idx[1]), p(idx[2])) <= 0.0 {
        return None;
    }
    out.push([idx[0], idx[1], idx[2]]);
    Some(out)
}

/// No two non-adjacent edges of the closed polygon touch or cross, and no vertex repeats.
fn is_simple(pos: &[[f64; 2]], poly: &[u32]) -> bool {
    let k = poly.len();
    let p = |i: usize| pos[poly[i % k] as usize];
    for i in 0..k {
        for j in i + 1..k {
            if poly[i] == poly[j] {
                return false;
            }
            if j == i + 1 || (i == 0 && j == k - 1) {
                continue;
            }
            if segments_meet(p(i), p(i + 1), p(j), p(j + 1)) {
                return false;
            }
        }
    }
    true
}

fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient2(a, b, c), orient2(a, b, d));
    let (o3, o4) = (orient2(c, d, a), orient2(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2], o: f64| {
        o == 0.0
            && r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4)
}

/// Final check of the extended mesh: counter-clockwise sea faces, every edge in at most two
/// faces, one boundary loop and Euler characteristic 1 (a disk).
fn check_disk(pos: &[[f64; 2]], faces: &[[u32; 3]], n_roi_faces: usize) -> Result<()> {
    let nv = pos.len();
    if let Some(k) = (n_roi_faces..faces.len()).find(|&k| orient(pos, faces[k]) <= 0.0) {
        return Err(Error::Numerical(format!(
            "sea construction produced an inverted sea face {k}"
        )));
    }
    let alive = vec![true; faces.len()];
    let inc = Incidence::new(faces, nv);
    let fail = |what: &str| Err(Error::Numerical(format!("sea construction: {what}")));
    for v in 0..nv as u32 {
        let list = &inc.corners[inc.start[v as usize] as usize..inc.start[v as usize + 1] as usize];
        for (i, c) in list.iter().enumerate() {
            if list[i + 1..].iter().any(|d| d.next == c.next) {
                return fail("an edge is used twice in the same direction");
            }
        }
    }
    let Some(next) = boundary_next(&inc, &alive, None) else {
        return fail("the extended mesh has a non-manifold boundary vertex");
    };
    let lps = loops(&next);
    let n_boundary: usize = lps.iter().map(Vec::len).sum();
    let used = (0..nv).filter(|&v| inc.start[v] < inc.start[v + 1]).count();
    let edges = (3 * faces.len() + n_boundary) / 2;
    let chi = used as i64 - edges as i64 + faces.len() as i64;
    if lps.len() != 1 || chi != 1 {
        return fail(&format!(
            "the extended mesh is not a disk ({} boundary loops, Euler characteristic {chi})",
            lps.len()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::f64::consts::PI;

    /// A disk of `k` concentric rings (6j points on ring j, interior radii jittered),
    /// triangulated ring by ring: 6k² faces. Returns positions, faces and the boundary loop
    /// (the outer ring, CCW).
    fn disk(k: usize, center: [f64; 2], radius: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
        let mut pos = vec![center];
        let mut rings: Vec<Vec<u32>> = vec![vec![0]];
        for j in 1..=k {
            let count = 6 * j;
            let mut ring = Vec::new();
            for i in 0..count {
                let t = 2.0 * PI * i as f64 / count as f64;
                let jitter = if j < k {
                    0.2 * (7.0 * i as f64 + j as f64).sin()
                } else {
                    0.0
                };
                let r = radius * (j as f64 + jitter) / k as f64;
                ring.push(pos.len() as u32);
                pos.push([center[0] + r * t.cos(), center[1] + r * t.sin()]);
            }
            rings.push(ring);
        }
        let mut faces = Vec::new();
        for j in 1..=k {
            let (inner, outer) = (&rings[j - 1], &rings[j]);
            let (ni, no) = (inner.len(), outer.len());
            if ni == 1 {
                for o in 0..no {
                    faces.push([inner[0], outer[o], outer[(o + 1) % no]]);
                }
                continue;
            }
            // Merge the two rings by angle; both start at angle 0.
            let (mut i, mut o) = (0usize, 0usize);
            while i < ni || o < no {
                let next_in = (i + 1) as f64 / ni as f64;
                let next_out = (o + 1) as f64 / no as f64;
                if o < no && (i == ni || next_out <= next_in) {
                    faces.push([inner[i % ni], outer[o], outer[(o + 1) % no]]);
                    o += 1;
                } else {
                    faces.push([inner[i], outer[o % no], inner[(i + 1) % ni]]);
                    i += 1;
                }
            }
        }
        let boundary = rings[k].clone();
        (pos, faces, boundary)
    }

    /// A grid ROI from a mask of unit cells (row-major, `w` wide), each cell split in two.
    fn grid_roi(mask: &[&str], cell: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
        let h = mask.len();
        let w = mask[0].len();
        let mut id: HashMap<(usize, usize), u32> = HashMap::new();
        let mut pos = Vec::new();
        let mut vid = |x: usize, y: usize, pos: &mut Vec<[f64; 2]>| -> u32 {
            *id.entry((x, y)).or_insert_with(|| {
                pos.push([x as f64 * cell + 0.3, y as f64 * cell - 1.1]);
                (pos.len() - 1) as u32
            })
        };
        let mut faces = Vec::new();
        for (row, line) in mask.iter().enumerate() {
            let y = h - 1 - row;
            for (x, ch) in line.chars().enumerate().take(w) {
                if ch == '#' {
                    let a = vid(x, y, &mut pos);
                    let b = vid(x + 1, y, &mut pos);
                    let c = vid(x + 1, y + 1, &mut pos);
                    let d = vid(x, y + 1, &mut pos);
                    faces.push([a, b, c]);
                    faces.push([a, c, d]);
                }
            }
        }
        let boundary = boundary_of(&faces, pos.len());
        (pos, faces, boundary)
    }

    /// The single boundary loop of a disk mesh, in face orientation (CCW).
    fn boundary_of(faces: &[[u32; 3]], nv: usize) -> Vec<u32> {
        let alive = vec![true; faces.len()];
        let inc = Incidence::new(faces, nv);
        let next = boundary_next(&inc, &alive, None).unwrap();
        let lps = loops(&next);
        assert_eq!(lps.len(), 1);
        lps[0].clone()
    }

    fn area(p: &[[f64; 2]], f: [u32; 3]) -> f64 {
        0.5 * orient(p, f)
    }

    /// The checks every sea must pass.
    fn check_sea(pos: &[[f64; 2]], faces: &[[u32; 3]], boundary: &[u32], eta: f64) -> SeaMesh {
        let sea = build_sea(pos, faces, boundary, eta).unwrap();
        let n = pos.len();
        assert_eq!(sea.n_roi_vertices, n);
        assert_eq!(sea.n_roi_faces, faces.len());
        assert_eq!(&sea.positions[..n], pos);
        assert_eq!(&sea.faces[..faces.len()], faces);
        assert!(sea.faces.len() > 2 * faces.len());

        // Positive areas.
        for (k, f) in sea.faces.iter().enumerate() {
            assert!(area(&sea.positions, *f) > 0.0, "face {k} {f:?}");
        }
        // Edge use counts.
        let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
        for f in &sea.faces {
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        assert!(uses.values().all(|&u| u <= 2));
        let b = boundary.len();
        for k in 0..b {
            let (a, c) = (boundary[k], boundary[(k + 1) % b]);
            assert_eq!(uses[&(a.min(c), a.max(c))], 2, "ROI boundary edge {a}-{c}");
        }
        // Euler characteristic of a disk; every vertex used.
        let mut used = vec![false; sea.positions.len()];
        for f in &sea.faces {
            for &v in f {
                used[v as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u));
        let chi = sea.positions.len() as i64 - uses.len() as i64 + sea.faces.len() as i64;
        assert_eq!(chi, 1);

        // The scaled frame: area centroid at 0, farthest ROI vertex at 0.5.
        let frame = Similarity::fit(pos, faces, 0.5).unwrap();
        let z: Vec<[f64; 2]> = sea.positions.iter().map(|&p| frame.apply(p)).collect();
        let rmax = z.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
        assert!(rmax <= eta * (1.0 + 1e-12), "{rmax}");
        assert!(rmax >= 0.8 * eta.min(2.0), "{rmax}");

        // Sea faces around the ROI boundary have areas comparable to l².
        let l = mean_edge_length(&z[..n], faces, boundary);
        let on_boundary: std::collections::HashSet<u32> = boundary.iter().copied().collect();
        let mut count = 0;
        for f in &sea.faces[faces.len()..] {
            if f.iter().any(|v| on_boundary.contains(v)) {
                let a = area(&z, *f);
                assert!(
                    a > l * l / 10.0 && a < 10.0 * l * l,
                    "{a} vs l² = {}",
                    l * l
                );
                count += 1;
            }
        }
        assert!(count >= b);
        sea
    }

    #[test]
    fn disk_roi_gets_a_sea() {
        let (pos, faces, boundary) = disk(6, [3.0, -2.0], 2.5);
        assert_eq!(faces.len(), 6 * 36);
        let sea = check_sea(&pos, &faces, &boundary, 5.0);
        // The sea extends well beyond the unit circle (reflection), up to eta.
        assert!(sea.positions.len() > 4 * pos.len());
    }

    #[test]
    fn disk_roi_with_other_eta() {
        let (pos, faces, boundary) = disk(8, [0.0, 0.0], 1.0);
        check_sea(&pos, &faces, &boundary, 2.0);
        check_sea(&pos, &faces, &boundary, 1.3);
        check_sea(&pos, &faces, &boundary, 20.0);
    }

    #[test]
    fn square_grid_roi() {
        let mask = ["########"; 8];
        let (pos, faces, boundary) = grid_roi(&mask, 0.25);
        check_sea(&pos, &faces, &boundary, 5.0);
    }

    #[test]
    fn nonconvex_roi_with_centroid_outside() {
        // A U shape: the area centroid is in the notch, outside the ROI.
        let mask = [
            "###....###",
            "###....###",
            "###....###",
            "###....###",
            "##########",
            "##########",
        ];
        let (pos, faces, boundary) = grid_roi(&mask, 0.1);
        check_sea(&pos, &faces, &boundary, 5.0);
        // A spiral-ish shape with pockets.
        let mask = [
            "##########",
            "#........#",
            "#.######.#",
            "#.#....#.#",
            "#.#.##.#.#",
            "#.#..#.#.#",
            "#.####.#.#",
            "#......#.#",
            "########.#",
        ];
        let (pos, faces, boundary) = grid_roi(&mask, 1.0);
        check_sea(&pos, &faces, &boundary, 5.0);
    }

    #[test]
    fn inverted_reflections_are_repaired() {
        // A regular hexagon fan-triangulated from one corner: every triangle's circumcircle is
        // the hexagon's, which contains the origin, so every reflected ROI face is inverted.
        let pos: Vec<[f64; 2]> = (0..6)
            .map(|k| {
                let t = PI / 3.0 * k as f64;
                [t.cos(), t.sin()]
            })
            .collect();
        let faces = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]];
        let boundary = vec![0, 1, 2, 3, 4, 5];
        let sea = build_sea(&pos, &faces, &boundary, 5.0).unwrap();
        for f in &sea.faces {
            assert!(area(&sea.positions, *f) > 0.0);
        }
        assert_eq!(&sea.positions[..6], &pos[..]);
        // Also with a fan of thin triangles (a 40-gon fanned from one corner).
        let pos: Vec<[f64; 2]> = (0..40)
            .map(|k| {
                let t = PI / 20.0 * k as f64;
                [2.0 * t.cos(), 1.5 * t.sin()]
            })
            .collect();
        let faces: Vec<[u32; 3]> = (1..39).map(|k| [0, k, k + 1]).collect();
        let boundary: Vec<u32> = (0..40).collect();
        let sea = build_sea(&pos, &faces, &boundary, 5.0).unwrap();
        for f in &sea.faces {
            assert!(area(&sea.positions, *f) > 0.0);
        }
    }

    #[test]
    fn bad_input_is_rejected() {
        let (pos, faces, boundary) = disk(3, [0.0, 0.0], 1.0);
        for eta in [1.0, 0.5, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                build_sea(&pos, &faces, &boundary, eta),
                Err(Error::Argument(_))
            ));
        }
        let rev: Vec<u32> = boundary.iter().rev().copied().collect();
        assert!(matches!(
            build_sea(&pos, &faces, &rev, 5.0),
            Err(Error::InvalidMesh(_))
        ));
        assert!(matches!(
            build_sea(&pos, &faces, &boundary[..2], 5.0),
            Err(Error::InvalidMesh(_))
        ));
        let mut bad = faces.clone();
        bad[3][1] = 10_000;
        assert!(matches!(
            build_sea(&pos, &bad, &boundary, 5.0),
            Err(Error::InvalidMesh(_))
        ));
        let mut p2 = pos.clone();
        p2[4][0] = f64::NAN;
        assert!(matches!(
            build_sea(&p2, &faces, &boundary, 5.0),
            Err(Error::InvalidMesh(_))
        ));
    }

    #[test]
    fn ear_clipping_and_simplicity() {
        let pos = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.5], [0.0, 2.0]];
        let tris = ear_clip(&pos, &[0, 1, 2, 3, 4]).unwrap();
        assert_eq!(tris.len(), 3);
        let total: f64 = tris.iter().map(|t| area(&pos, *t)).sum();
        assert!((total - (4.0 - 1.5)).abs() < 1e-12);
        assert!(tris.iter().all(|t| area(&pos, *t) > 0.0));
        // A bow tie is not simple.
        let pos = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(ear_clip(&pos, &[0, 1, 2, 3]).is_none());
        // Clockwise is refused.
        let pos = vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
        assert!(ear_clip(&pos, &[0, 1, 2]).is_none());
    }

    #[test]
    fn point_in_polygon_index() {
        let poly: Vec<[f64; 2]> = vec![
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [2.0, 3.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        let idx = BoundaryIndex::new(&poly, 0.2);
        assert!(idx.contains([0.5, 2.0]));
        assert!(idx.contains([1.5, 0.5]));
        assert!(!idx.contains([1.5, 2.0]));
        assert!(!idx.contains([-1.0, 1.0]));
        assert!(!idx.contains([1.0, 5.0]));
        assert!(idx.far_from_boundary([1.5, 2.0]));
        assert!(!idx.far_from_boundary([1.5, 1.1]));
        assert!(!idx.far_from_boundary([3.1, 1.5]));
        assert!(idx.far_from_boundary([3.3, 1.5]));
        assert!(idx.far_from_boundary([30.0, 1.5]));
    }

    /// A small deterministic generator (64-bit LCG), uniform in [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A random ROI: a noisy star-shaped polygon of `nb` vertices (stretched by `aspect`) with
    /// `ni` random interior points, triangulated by a constrained Delaunay triangulation.
    /// `noise` < 1 keeps the radius positive, so the polygon is simple.
    fn random_roi(
        seed: u64,
        nb: usize,
        ni: usize,
        aspect: f64,
        noise: f64,
    ) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
        let mut rng = Lcg(seed);
        let harmonics: Vec<(f64, f64)> =
            (1..6).map(|k| (k as f64, rng.next() * 2.0 * PI)).collect();
        let mut pos: Vec<[f64; 2]> = (0..nb)
            .map(|k| {
                let t = 2.0 * PI * (k as f64 + 0.4 * rng.next()) / nb as f64;
                let wave: f64 = harmonics.iter().map(|(h, ph)| (h * t + ph).sin() / h).sum();
                let r = 1.0 + noise * wave / 2.3;
                [aspect * r * t.cos() + 7.0, r * t.sin() - 3.0]
            })
            .collect();
        let bpoly = pos.clone();
        let index = BoundaryIndex::new(&bpoly, 0.02);
        while pos.len() < nb + ni {
            let p = [
                7.0 + aspect * 3.0 * (2.0 * rng.next() - 1.0),
                -3.0 + 3.0 * (2.0 * rng.next() - 1.0),
            ];
            if index.contains(p) && index.far_from_boundary(p) {
                pos.push(p);
            }
        }
        let edges: Vec<[usize; 2]> = (0..nb).map(|k| [k, (k + 1) % nb]).collect();
        let cdt = constrained_delaunay(&pos, &edges).unwrap();
        let faces: Vec<[u32; 3]> = cdt
            .faces
            .into_iter()
            .filter(|f| {
                let c = [0, 1].map(|d| f.iter().map(|&v| pos[v as usize][d]).sum::<f64>() / 3.0);
                index.contains(c)
            })
            .collect();
        (pos, faces, (0..nb as u32).collect())
    }

    #[test]
    fn random_rois_give_valid_seas() {
        let mut seed = 1;
        for (nb, ni, aspect, noise) in [
            (40, 100, 1.0, 0.3),
            (60, 0, 1.0, 0.2),
            (25, 10, 3.0, 0.9),
            (120, 400, 1.0, 0.95),
            (80, 50, 8.0, 0.1),
            (200, 30, 1.5, 0.7),
            (12, 0, 1.0, 0.0),
            (30, 300, 0.2, 0.3),
        ] {
            for _ in 0..4 {
                seed += 1;
                let (pos, faces, boundary) = random_roi(seed, nb, ni, aspect, noise);
                for eta in [5.0, 1.5, 30.0] {
                    let sea = build_sea(&pos, &faces, &boundary, eta)
                        .unwrap_or_else(|e| panic!("seed {seed} eta {eta}: {e}"));
                    assert_eq!(&sea.positions[..pos.len()], &pos[..]);
                    assert_eq!(&sea.faces[..faces.len()], &faces[..]);
                    for f in &sea.faces {
                        assert!(area(&sea.positions, *f) > 0.0, "seed {seed}");
                    }
                }
            }
        }
    }

    /// CPU time of this thread in seconds (Linux), to time on a busy machine.
    fn thread_cpu_seconds() -> Option<f64> {
        let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
        Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
    }

    /// Run with `cargo test --release -p demkit --lib init::sea -- --ignored --nocapture`.
    #[test]
    #[ignore = "timing; run in release"]
    fn timing_35k_faces() {
        for k in [76, 130] {
            let (pos, faces, boundary) = disk(k, [0.0, 0.0], 1.0);
            let mut best = (f64::INFINITY, f64::INFINITY);
            let mut sea = None;
            for _ in 0..5 {
                let (t, c) = (std::time::Instant::now(), thread_cpu_seconds());
                sea = Some(build_sea(&pos, &faces, &boundary, 5.0).unwrap());
                let wall = t.elapsed().as_secs_f64();
                let cpu = c
                    .and_then(|c| Some(thread_cpu_seconds()? - c))
                    .unwrap_or(wall);
                best = (best.0.min(wall), best.1.min(cpu));
            }
            let sea = sea.unwrap();
            println!(
                "build_sea: ROI {} faces / {} vertices -> {} faces / {} vertices: \
                 best of 5 {:.3} s wall, {:.3} s CPU",
                faces.len(),
                pos.len(),
                sea.faces.len(),
                sea.positions.len(),
                best.0,
                best.1
            );
        }
    }
}
