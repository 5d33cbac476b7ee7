//! Texture coordinates from a map (DEQ paper §7.2, TDEM paper §5.2): the input surface keeps its
//! geometry and gets `vt` coordinates in [0, 1]² from its planar, circle-domain or flat-torus
//! image.
//!
//! - A planar map (z = 0) is scaled uniformly into the unit square, centred: one `vt` per
//!   vertex, so `f a/a b/b c/c`.
//! - A toroidal map is a seamless periodic atlas: the flat torus divided by its periods, each
//!   vertex at its point modulo 1, and a face that crosses a side of the unit square given the
//!   translated copies of its corners (outside [0, 1]² by less than a triangle), so that with
//!   repeating textures there is no seam; a vertex gets one `vt` per side it is drawn on.

use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::io::obj::TextureCoordinates;
use crate::methods::MapResult;
use crate::{Error, Result};
use std::collections::HashMap;

/// The texture coordinates of `result` (a map of a mesh with faces `faces`); `torus` is the
/// target of a toroidal map. Spherical maps have no planar image and are refused.
pub fn texture_coordinates(
    result: &MapResult,
    faces: &[[u32; 3]],
    torus: Option<&Torus>,
) -> Result<TextureCoordinates> {
    if let (Some(flat), Some(t)) = (&result.flat_torus, torus) {
        return Ok(periodic_atlas(flat, faces, t.periods()));
    }
    if result.positions.iter().any(|p| p[2] != 0.0) {
        return Err(Error::Argument(format!(
            "texture coordinates need a planar, circle-domain or torus map, and {} maps onto a curved surface",
            result.method
        )));
    }
    Ok(planar_atlas(&result.positions, faces))
}

/// A planar map scaled uniformly into [0, 1]², centred; one point per vertex.
pub fn planar_atlas(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> TextureCoordinates {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in positions {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let scale = if size > 0.0 { 1.0 / size } else { 1.0 };
    let margin = [0, 1].map(|d| 0.5 * (1.0 - (hi[d] - lo[d]) * scale));
    let points = positions
        .iter()
        .map(|p| [0, 1].map(|d| ((p[d] - lo[d]) * scale + margin[d]).clamp(0.0, 1.0)))
        .collect();
    TextureCoordinates {
        points,
        corners: faces.to_vec(),
    }
}

/// The flat torus divided by its periods: every face drawn contiguously from its first corner,
/// which lies in [0, 1)²; one point per (vertex, translation) actually used.
pub fn periodic_atlas(
    map: &FlatTorusMap,
    faces: &[[u32; 3]],
    period: [f64; 2],
) -> TextureCoordinates {
    let unit = |p: [f64; 2]| [p[0] / period[0], p[1] / period[1]];
    let mut points = Vec::with_capacity(map.points.len());
    let mut index: HashMap<(u32, [i64; 2]), u32> = HashMap::with_capacity(map.points.len());
    let mut corners = Vec::with_capacity(faces.len());
    for (f, face) in faces.iter().enumerate() {
        let c = map.corners(faces, f, period);
        let first = unit([c[0][0], c[0][1]]);
        let shift = first.map(f64::floor);
        let mut out = [0u32; 3];
        for k in 0..3 {
            let v = face[k];
            let q = unit([c[k][0], c[k][1]]);
            let uv = [q[0] - shift[0], q[1] - shift[1]];
            // Which copy of the vertex this is: its whole-period distance from the copy in
            // [0, 1)².
            let own = unit(map.points[v as usize]);
            let copy = [0, 1].map(|d| (uv[d] - (own[d] - own[d].floor())).round() as i64);
            out[k] = *index.entry((v, copy)).or_insert_with(|| {
                points.push(uv);
                (points.len() - 1) as u32
            });
        }
        corners.push(out);
    }
    TextureCoordinates { points, corners }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::torus;
    use crate::geometry::signed_area_2d;

    #[test]
    fn planar_maps_fill_the_unit_square_keeping_their_aspect() {
        let p = vec![[-2.0, 1.0, 0.0], [2.0, 1.0, 0.0], [0.0, 3.0, 0.0]];
        let t = planar_atlas(&p, &[[0, 1, 2]]);
        assert_eq!(t.corners, vec![[0, 1, 2]]);
        // Width 4, height 2: x spans [0, 1], y is centred in [0.25, 0.75].
        assert_eq!(t.points[0], [0.0, 0.25]);
        assert_eq!(t.points[1], [1.0, 0.25]);
        assert_eq!(t.points[2], [0.5, 0.75]);
    }

    #[test]
    fn the_torus_atlas_is_seamless_and_covers_the_unit_square_once() {
        let t = Torus::new(3.0, 1.0).unwrap();
        let mesh = torus(3.0, 1.0, 24, 12).unwrap();
        let map = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, &t);
        let atlas = periodic_atlas(&map, &mesh.faces, t.periods());
        // Every face keeps its orientation and its share of the square.
        let mut total = 0.0;
        for c in &atlas.corners {
            let p = c.map(|i| {
                let q = atlas.points[i as usize];
                [q[0], q[1], 0.0]
            });
            let a = signed_area_2d(p[0], p[1], p[2]);
            assert!(a > 0.0);
            total += a;
        }
        assert!((total - 1.0).abs() < 1e-12);
        // Extra copies only along the two seams; first corners in [0, 1)², the rest within a
        // triangle of it.
        assert!(atlas.points.len() > mesh.n_vertices());
        assert!(atlas.points.len() < mesh.n_vertices() + 24 + 12 + 2);
        for p in &atlas.points {
            assert!(
                p[0] > -0.1 && p[0] < 1.1 && p[1] > -0.1 && p[1] < 1.1,
                "{p:?}"
            );
        }
    }
}
