//! The regions of a cartogram as one planar straight-line graph: every vertex stored once
//! (positions closer than a tolerance are merged, so a border shared by two regions is made of
//! the same vertices and edges on both sides), a vertex of one region lying on an edge of
//! another splits that edge (no T-junctions), and no two edges cross.
//!
//! The graph is held in a normalised frame ([`Frame`]): the input's bounding box centred at
//! the origin with its larger half-side 1, so that squares of side 1e300 or 1e-300 are
//! computed on the same numbers as unit squares and only the output is scaled back.

use super::Polygon;
use super::cleaning::{Snapper, remove_spikes};
pub use super::frame::Frame;
use super::geojson::RawRegion;
use super::rings::map_polygons;
pub(crate) use super::rings::{bbox, inside_ring, segment_distance};
pub use super::rings::{polygon_area, ring_area, ring_orientation};
use crate::{Error, Result};
use std::collections::HashMap;

/// One feature's geometry as rings of indices into [`RegionSet::points`].
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// How messages name the feature (see [`super::geojson::feature_label`]).
    pub label: String,
    /// The region's value (> 0).
    pub value: f64,
    /// Whether the feature is a MultiPolygon.
    pub multi: bool,
    /// Polygons → rings (exterior first) → vertex indices, without closing vertex.
    pub polygons: Vec<Vec<Vec<usize>>>,
}

/// All regions over one shared vertex list.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionSet {
    /// The distinct vertices, in the normalised frame (see [`RegionSet::frame`]).
    pub points: Vec<[f64; 2]>,
    /// The regions, in feature order.
    pub regions: Vec<Region>,
    /// The similarity from input coordinates to those of [`RegionSet::points`].
    pub frame: Frame,
    /// What was done on reading: values completed (see [`super::load`]), and one line per
    /// region cleaned (degenerate parts dropped, zero-width spikes removed).
    pub warnings: Vec<String>,
}

/// Relative tolerance (of the bounding box diagonal) below which a vertex lies on an edge of
/// its own region, or a ring has no area (as a fraction of the diagonal squared).
pub(super) const SNAP: f64 = 1e-9;

/// Relative tolerance (of the bounding box diagonal) within which two positions are merged
/// into one vertex, and a vertex of one region near another region's edge is taken to lie on
/// it (a border not shared exactly): a thousandth of the flow's cell at the default grid, and
/// well above the rounding of map files' coordinates, whose clusters of points a metre apart
/// would otherwise cross themselves once projected.
const NEAR: f64 = 1e-6;

impl RegionSet {
    /// Builds the shared vertex graph of `raw` in its normalised frame ([`Frame::of_box`] of
    /// the regions' bounding box); `path` names the file in messages.
    ///
    /// Errors ([`Error::Format`], naming the feature and ring): all positions equal (the
    /// regions have no extent), a ring with fewer than three distinct points or zero area,
    /// edges that cross (within one region: the region's boundary crosses itself; between
    /// two: the regions overlap).
    pub fn build(raw: &[RawRegion], path: &str) -> Result<RegionSet> {
        let err = |msg: String| Error::Format {
            path: path.to_string(),
            msg,
        };
        let (lo, hi) = bbox(
            raw.iter()
                .flat_map(|r| r.polygons.iter().flatten().flatten().copied()),
        );
        let frame = Frame::of_box(lo, hi).ok_or_else(|| {
            err("the regions have no extent (all their positions are equal)".into())
        })?;
        // In the normalised frame the bounding box is [-1, 1] along its larger side.
        let (lo, hi) = (frame.to_unit(lo), frame.to_unit(hi));
        let diag = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
        let tol = SNAP * diag;
        let mut snap = Snapper::new(NEAR * diag);
        let mut regions = Vec::with_capacity(raw.len());
        let mut warnings = Vec::new();
        for r in raw {
            let mut polygons = Vec::with_capacity(r.polygons.len());
            let mut dropped: Vec<String> = Vec::new();
            let mut first_refusal: Option<String> = None;
            let mut spikes = 0;
            for (k, rings) in r.polygons.iter().enumerate() {
                let mut out = Vec::with_capacity(rings.len());
                for (j, ring) in rings.iter().enumerate() {
                    let mut idx: Vec<usize> = Vec::with_capacity(ring.len());
                    for &p in ring {
                        let v = snap.insert(frame.to_unit(p));
                        if idx.last() != Some(&v) {
                            idx.push(v);
                        }
                    }
                    while idx.len() > 1 && idx.first() == idx.last() {
                        idx.pop();
                    }
                    let ring_spikes = remove_spikes(&mut idx, &snap.points, tol);
                    spikes += ring_spikes;
                    let pts: Vec<[f64; 2]> = idx.iter().map(|&v| snap.points[v]).collect();
                    let mut distinct = idx.clone();
                    distinct.sort_unstable();
                    distinct.dedup();
                    let problem = if distinct.len() < 3 && ring_spikes > 0 {
                        // A ring that was all spike: a line.
                        Some("has zero area")
                    } else if distinct.len() < 3 {
                        Some("has fewer than 3 distinct points")
                    } else if ring_area(&pts).abs() <= tol * diag {
                        Some("has zero area")
                    } else {
                        None
                    };
                    if let Some(problem) = problem {
                        first_refusal.get_or_insert(format!(
                            "{}: ring {j} of polygon {k} {problem}",
                            r.label
                        ));
                        if j == 0 {
                            dropped.push(format!("polygon {k} ({problem})"));
                            out.clear();
                            break;
                        }
                        dropped.push(format!("ring {j} of polygon {k} ({problem})"));
                        continue;
                    }
                    out.push(idx);
                }
                if !out.is_empty() {
                    polygons.push(out);
                }
            }
            if polygons.is_empty() {
                return Err(err(
                    first_refusal.unwrap_or_else(|| format!("{}: has no polygon", r.label))
                ));
            }
            if !dropped.is_empty() {
                warnings.push(format!("{}: dropped {}", r.label, dropped.join(", ")));
            }
            if spikes > 0 {
                warnings.push(format!(
                    "{}: removed {spikes} zero-width spike vertices",
                    r.label
                ));
            }
            regions.push(Region {
                label: r.label.clone(),
                value: r.value,
                multi: r.multi,
                polygons,
            });
        }
        let mut set = RegionSet {
            points: snap.points,
            regions,
            frame,
            warnings,
        };
        set.split_t_junctions(tol, NEAR * diag);
        set.check_crossings(path, tol)?;
        set.check_holes_inside(path)?;
        set.check_sides(path)?;
        Ok(set)
    }

    /// The distinct undirected edges of all rings, each with the regions using it.
    pub fn edges(&self) -> Vec<([usize; 2], Vec<usize>)> {
        let mut map: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        let mut order = Vec::new();
        for (r, region) in self.regions.iter().enumerate() {
            for ring in region.polygons.iter().flatten() {
                for i in 0..ring.len() {
                    let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                    let key = [a.min(b), a.max(b)];
                    let owners = map.entry(key).or_insert_with(|| {
                        order.push(key);
                        Vec::new()
                    });
                    if !owners.contains(&r) {
                        owners.push(r);
                    }
                }
            }
        }
        order
            .into_iter()
            .map(|k| {
                let o = map.remove(&k).unwrap_or_default();
                (k, o)
            })
            .collect()
    }

    /// The vertices in input coordinates.
    pub fn input_points(&self) -> Vec<[f64; 2]> {
        self.points
            .iter()
            .map(|&p| self.frame.to_input(p))
            .collect()
    }

    /// The coordinates of every region's rings, in the normalised frame.
    pub fn coordinates(&self) -> Vec<Vec<Polygon>> {
        self.regions
            .iter()
            .map(|r| map_polygons(&r.polygons, |v| self.points[v]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(label: &str, polygons: Vec<Polygon>) -> RawRegion {
        RawRegion {
            label: label.into(),
            value: 1.0,
            multi: polygons.len() > 1,
            polygons,
        }
    }

    fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s], [x, y]]
    }

    #[test]
    fn shared_borders_share_vertices_and_t_junctions_are_split() {
        // A 2×1 block on the left of two unit squares: its right edge (2 units long) carries
        // the squares' common corner (1, 1) as a T-junction.
        let left = vec![vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 0.0],
        ]];
        let a = vec![square(1.0, 0.0, 1.0)];
        let b = vec![square(1.0, 1.0, 1.0)];
        let set = RegionSet::build(
            &[raw("L", vec![left]), raw("A", vec![a]), raw("B", vec![b])],
            "t",
        )
        .unwrap();
        // Distinct positions only: 4 (left) + 2 + 2 (the squares' right corners) + (1,1).
        assert_eq!(set.points.len(), 8);
        assert_eq!(
            set.regions[0].polygons[0][0].len(),
            5,
            "(1,1) inserted in the left ring"
        );
        let edges = set.edges();
        let shared = edges.iter().filter(|(_, o)| o.len() == 2).count();
        assert_eq!(shared, 3);
        let coords = set.coordinates();
        let total: f64 = coords.iter().flatten().map(|p| polygon_area(p)).sum();
        assert!((total - 4.0).abs() < 1e-12);
    }

    /// Whether any two edges of `set` cross properly.
    fn any_crossing(set: &RegionSet) -> bool {
        let segments: Vec<[[f64; 2]; 2]> = set
            .edges()
            .iter()
            .map(|([a, b], _)| [set.points[*a], set.points[*b]])
            .collect();
        !super::super::crossings::proper_crossings(&segments).is_empty()
    }

    #[test]
    fn a_slight_overlap_of_two_borders_is_snapped_onto_one_with_a_warning() {
        // B's left border wanders 1e-4 either side of A's right edge: into A at (0.9999,
        // 0.5), out at (1.0001, 0.2), so that their edges cross.
        let a = vec![square(0.0, 0.0, 1.0)];
        let b = vec![vec![
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [0.9999, 0.5],
            [1.0001, 0.2],
            [1.0, 0.0],
        ]];
        let raw_set = [raw("A", vec![a]), raw("B", vec![b])];
        let set = RegionSet::build(&raw_set, "t").unwrap();
        assert!(!any_crossing(&set));
        assert!(
            set.warnings
                .iter()
                .any(|w| w.contains("A and B") && w.contains("moved onto")),
            "{:?}",
            set.warnings
        );
        // B's vertex inside A went onto A's edge, which now carries it: A keeps its area, B
        // loses the sliver that overlapped A.
        let coords = set.coordinates();
        let area = |r: usize| -> f64 { coords[r].iter().map(|p| polygon_area(p)).sum() };
        let unit = area(0);
        assert_eq!(set.regions[0].polygons[0][0].len(), 5);
        let sliver = 0.5 * 0.5 * 1e-4 * unit;
        assert!(
            (area(1) - (unit - sliver)).abs() < 1e-3 * sliver,
            "{} {unit}",
            area(1)
        );
    }

    #[test]
    fn near_misses_of_a_border_and_clusters_of_points_are_joined() {
        // B's vertex (1 + 1e-7, 0.5) lies off A's right edge by 5e-8 of the diagonal; A's
        // corner (0, 1) comes as a cluster of three points a millionth apart.
        let a = vec![vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [1e-7, 1.0 - 1e-7],
            [0.0, 1.0 - 2e-7],
            [0.0, 0.0],
        ]];
        let b = vec![vec![
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0 + 1e-7, 0.5],
            [1.0, 0.0],
        ]];
        let set = RegionSet::build(&[raw("A", vec![a]), raw("B", vec![b])], "t").unwrap();
        // A's ring: its four corners and B's vertex, now shared.
        assert_eq!(set.regions[0].polygons[0][0].len(), 5);
        let shared = set.edges().iter().filter(|(_, o)| o.len() == 2).count();
        assert_eq!(shared, 2);
        assert!(
            set.warnings
                .iter()
                .any(|w| w.starts_with("A: its border and its neighbours'")),
            "{:?}",
            set.warnings
        );
    }

    #[test]
    fn a_hole_outside_its_exterior_ring_is_refused() {
        let outer = square(0.0, 0.0, 4.0)[..4].to_vec();
        let away = square(10.0, 10.0, 1.0)[..4].to_vec();
        let e = RegionSet::build(&[raw("feature 3", vec![vec![outer.clone(), away]])], "t")
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("feature 3: ring 1 of polygon 0 (a hole) lies outside"),
            "{e}"
        );
        let inner = square(1.0, 1.0, 1.0)[..4].to_vec();
        assert!(RegionSet::build(&[raw("feature 3", vec![vec![outer, inner]])], "t").is_ok());
    }

    #[test]
    fn crossings_and_degenerate_rings_are_refused() {
        let bow = vec![vec![[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 1.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![bow])], "t").unwrap_err();
        assert!(
            e.to_string()
                .contains("feature 0: its boundary crosses itself"),
            "{e}"
        );
        let a = vec![square(0.0, 0.0, 1.0)];
        let b = vec![square(0.5, 0.5, 1.0)];
        let e = RegionSet::build(&[raw("feature 0", vec![a]), raw("feature 1", vec![b])], "t")
            .unwrap_err();
        assert!(
            e.to_string().contains("feature 0 overlaps feature 1"),
            "{e}"
        );
        let line = vec![vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 0.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![line])], "t").unwrap_err();
        assert!(e.to_string().contains("zero area"), "{e}");
        let two = vec![vec![[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]];
        let e = RegionSet::build(&[raw("feature 0", vec![two])], "t").unwrap_err();
        assert!(
            e.to_string().contains("fewer than 3 distinct points"),
            "{e}"
        );
    }

    #[test]
    fn extreme_scales_are_normalised_and_orientations_kept() {
        for k in [1e300, 1e-300, 1e-310] {
            let sq: Vec<[f64; 2]> = square(3.0 * k, -2.0 * k, k)[..4].to_vec();
            let set = RegionSet::build(&[raw("feature 0", vec![vec![sq.clone()]])], "t").unwrap();
            // The box [-1, 1]², and back to the input, within rounding.
            let (lo, hi) = bbox(set.points.iter().copied());
            let near = |a: [f64; 2], b: f64| (a[0] - b).abs() < 1e-12 && (a[1] - b).abs() < 1e-12;
            assert!(near(lo, -1.0) && near(hi, 1.0), "{k:e}: {lo:?} {hi:?}");
            for (p, q) in set.input_points().iter().zip(&sq) {
                let tol = 1e-14 * k + 4.0 * f64::from_bits(1); // a few units of the last place
                assert!(
                    (p[0] - q[0]).abs() <= tol && (p[1] - q[1]).abs() <= tol,
                    "{p:?} {q:?}"
                );
            }
            assert_eq!(ring_orientation(&sq), 1.0, "{k:e}");
            let mut cw = sq.clone();
            cw.reverse();
            assert_eq!(ring_orientation(&cw), -1.0, "{k:e}");
        }
        // Coordinates near the largest f64: the frame's centre and scale stay finite.
        let f = Frame::of_box([-1.7e308, -1.0], [1.7e308, 1.0]).unwrap();
        assert_eq!(f.to_unit([1.7e308, 0.0]), [1.0, 0.0]);
        assert!(Frame::of_box([1.0, 1.0], [1.0, 1.0]).is_none());
        let e = RegionSet::build(&[raw("feature 0", vec![vec![vec![[2.0, 2.0]; 4]]])], "t");
        assert!(e.unwrap_err().to_string().contains("no extent"));
    }
}
