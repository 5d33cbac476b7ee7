//! A cartogram computed in a map projection, written in longitude/latitude degrees.
//!
//! The flow's polygons are valid in the projection's plane, where their edges are straight.
//! Written in degrees, each edge is the chord between its ends' images, whereas the edge's
//! true image is a curve; near a pole the inverse of a cylindrical projection stretches
//! latitude by 1/cos φ and bends that curve far from its chord (at 89° N a cell of the globe's
//! grid spans about 10° of latitude), so chords of neighbouring edges that do not cross in
//! the plane can cross in degrees (the world's Greenland, squeezed against the North Pole).
//! The images of the plane's edges never cross (the inverse is one-to-one), so every edge
//! whose chord crosses another in degrees is split in the plane, on itself (the cartogram's
//! areas in the plane are unchanged), until the chords follow the curves closely enough.

use super::Polygon;
use super::crossings::crossing_edges;
use super::densify::split_edges;
use super::raster::IndexRings;
use super::rings::map_polygons;
use rayon::prelude::*;
use std::collections::HashMap;

/// At most this many times are the crossing edges split.
const PASSES: usize = 12;

/// The parts each crossing edge is split into per pass.
const PARTS: usize = 4;

/// Every region's polygons, given over shared `points` in the projection's plane, in degrees
/// through `inverse`: edges whose chords cross in degrees but not in the plane are split in
/// the plane (the same vertices for both regions of a shared border) until none do, at most
/// [`PASSES`] times. Returns the coordinates and the number of vertices added.
pub(crate) fn to_degrees_indexed(
    mut points: Vec<[f64; 2]>,
    mut rings: Vec<IndexRings>,
    inverse: impl Fn([f64; 2]) -> [f64; 2] + Sync,
) -> (Vec<Vec<Polygon>>, usize) {
    let first = points.len();
    let mut images: Vec<[f64; 2]> = points.par_iter().map(|&p| inverse(p)).collect();
    for _ in 0..PASSES {
        let mut crossing = crossing_edges(&images, &rings);
        if crossing.is_empty() {
            break;
        }
        // Edges that cross in the plane already are not the writing's to mend.
        for e in crossing_edges(&points, &rings) {
            crossing.remove(&e);
        }
        if crossing.is_empty() {
            break;
        }
        let old = points.len();
        split_edges(&mut points, &mut rings, &crossing, PARTS);
        images.extend(
            points[old..]
                .par_iter()
                .map(|&p| inverse(p))
                .collect::<Vec<_>>(),
        );
    }
    let coordinates = rings
        .iter()
        .map(|polys| map_polygons(polys, |v| images[v]))
        .collect();
    (coordinates, points.len() - first)
}

/// [`to_degrees_indexed`] of polygons given as coordinates: positions that are equal (bit
/// for bit) are one shared vertex, as a cartogram's neighbours share their borders.
pub fn to_degrees(
    coordinates: &[Vec<Polygon>],
    inverse: impl Fn([f64; 2]) -> [f64; 2] + Sync,
) -> Vec<Vec<Polygon>> {
    let mut index: HashMap<(u64, u64), usize> = HashMap::new();
    let mut points = Vec::new();
    let rings: Vec<IndexRings> = coordinates
        .iter()
        .map(|polys| {
            map_polygons(polys, |p: [f64; 2]| {
                *index
                    .entry((p[0].to_bits(), p[1].to_bits()))
                    .or_insert_with(|| {
                        points.push(p);
                        points.len() - 1
                    })
            })
        })
        .collect();
    to_degrees_indexed(points, rings, inverse).0
}

#[cfg(test)]
mod tests {
    use super::super::sphere::{project, unproject};
    use super::super::validity;
    use super::*;

    /// In the globe's projection, below the North Pole: a triangle whose hypotenuse climbs
    /// from 66° N to the pole, and a small square just above that hypotenuse. Valid in the
    /// plane; with their vertices merely taken to degrees, the hypotenuse's chord (above its
    /// true, convex image) passes over the square.
    fn near_the_pole() -> Vec<Vec<Polygon>> {
        let pole = project([0.0, 90.0])[1];
        let (y0, y1) = (pole - 0.1, pole);
        let triangle = vec![vec![[0.0, y0], [1.0, y0], [1.0, y1]]];
        let c = y0 + 0.06;
        let square = vec![vec![[0.45, c], [0.5, c], [0.5, c + 0.01], [0.45, c + 0.01]]];
        vec![vec![triangle], vec![square]]
    }

    #[test]
    fn chords_that_cross_only_in_degrees_are_split_until_they_do_not() {
        let plane = near_the_pole();
        let labels = vec!["triangle".to_string(), "square".to_string()];
        assert!(validity::check(&plane, &labels).is_empty());
        let naive: Vec<Vec<Polygon>> = plane
            .iter()
            .map(|polys| map_polygons(polys, unproject))
            .collect();
        assert!(naive[0][0][0].iter().any(|p| p[1] > 85.0));
        assert!(!validity::check(&naive, &labels).is_empty());
        let written = to_degrees(&plane, unproject);
        assert_eq!(validity::check(&written, &labels), vec![]);
        // The vertices added lie on the plane's edges: the areas in the plane are unchanged.
        let back: Vec<Vec<Polygon>> = written
            .iter()
            .map(|polys| map_polygons(polys, project))
            .collect();
        let area = |c: &Vec<Polygon>| super::super::rings::polygon_area(&c[0]);
        for (a, b) in plane.iter().zip(&back) {
            assert!(
                (area(a) - area(b)).abs() < 1e-12 * area(a),
                "{} {}",
                area(a),
                area(b)
            );
        }
        // Both edges of a crossing pair are split: the hypotenuse and the square's side.
        assert!(written[0][0][0].len() > 3 && written[1][0][0].len() > 4);
    }
}
