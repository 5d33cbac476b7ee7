//! The region of interest in the unit disk: its checks, the similarity that puts it there
//! (DEM paper Algorithm 4, steps 1 and 7) and its mean edge length.

use crate::{Error, Result};

/// The similarity z = s (p − c) of Algorithm 4, step 1, and its inverse (step 7).
pub(super) struct Similarity {
    center: [f64; 2],
    scale: f64,
}

impl Similarity {
    /// Area centroid of the ROI to the origin, farthest vertex to radius 0.5.
    pub(super) fn fit(p: &[[f64; 2]], faces: &[[u32; 3]], roi_radius: f64) -> Result<Self> {
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

    pub(super) fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.scale * (p[0] - self.center[0]),
            self.scale * (p[1] - self.center[1]),
        ]
    }

    pub(super) fn invert(&self, z: [f64; 2]) -> [f64; 2] {
        [
            z[0] / self.scale + self.center[0],
            z[1] / self.scale + self.center[1],
        ]
    }
}

pub(super) fn validate(
    p: &[[f64; 2]],
    faces: &[[u32; 3]],
    boundary: &[u32],
    eta: f64,
) -> Result<()> {
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
pub(super) fn mean_edge_length(z: &[[f64; 2]], faces: &[[u32; 3]], boundary: &[u32]) -> f64 {
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
