//! Whether a cartogram's polygons are valid as written: every ring has finite positions, at
//! least 3 distinct points and an area; no two edges cross (a ring crossing itself, a hole
//! crossing its exterior, two regions overlapping at a border); every hole lies inside its
//! exterior; and no polygon lies inside another region's polygon. Shared vertices and edges
//! are compared by exact position, as written; positions closer to another region's boundary
//! than [`ROUNDING`] of the map's size are not counted as inside it.

use super::Polygon;
use super::buckets::Buckets;
use super::crossings::{crossing_point, proper_crossings};
use super::regions::{Frame, bbox, inside_ring, ring_area, segment_distance};
use super::rings::map_polygons;
use std::collections::HashSet;

/// Distances below this fraction of the map's larger half-side are rounding.
pub const ROUNDING: f64 = 1e-9;

/// One invalid polygon and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Invalid {
    /// The region (feature) index.
    pub region: usize,
    /// The polygon's index within the region.
    pub polygon: usize,
    /// What is wrong, naming the region by its label.
    pub reason: String,
}

/// One edge of a ring, for the crossing test.
struct Edge {
    region: usize,
    polygon: usize,
    a: [f64; 2],
    b: [f64; 2],
}

/// Every invalid polygon of `coordinates` (one entry per region, rings without closing
/// point), each once, with its first reason; `labels` name the regions in the reasons.
pub fn check(coordinates: &[Vec<Polygon>], labels: &[String]) -> Vec<Invalid> {
    let label = |r: usize| {
        labels
            .get(r)
            .cloned()
            .unwrap_or_else(|| format!("region {r}"))
    };
    let mut found: Vec<Invalid> = Vec::new();
    let mut flagged: HashSet<(usize, usize)> = HashSet::new();
    let mut flag = |found: &mut Vec<Invalid>, region: usize, polygon: usize, reason: String| {
        if flagged.insert((region, polygon)) {
            found.push(Invalid {
                region,
                polygon,
                reason,
            });
        }
    };
    let all = coordinates.iter().flatten().flatten().flatten();
    let finite = |p: &[f64; 2]| p[0].is_finite() && p[1].is_finite();
    if !all.clone().all(finite) {
        for (r, polys) in coordinates.iter().enumerate() {
            for (k, rings) in polys.iter().enumerate() {
                if !rings.iter().flatten().all(finite) {
                    flag(
                        &mut found,
                        r,
                        k,
                        format!(
                            "{}: polygon {k} has a position that is not finite",
                            label(r)
                        ),
                    );
                }
            }
        }
        return found;
    }
    let (lo, hi) = bbox(all.copied());
    let Some(frame) = Frame::of_box(lo, hi) else {
        for (r, polys) in coordinates.iter().enumerate() {
            for k in 0..polys.len() {
                flag(
                    &mut found,
                    r,
                    k,
                    format!("{}: polygon {k} has no extent", label(r)),
                );
            }
        }
        return found;
    };
    // In the normalised frame: no overflow in the orientation tests.
    let unit: Vec<Vec<Polygon>> = coordinates
        .iter()
        .map(|polys| map_polygons(polys, |p| frame.to_unit(p)))
        .collect();
    let mut edges = Vec::new();
    for (r, polys) in unit.iter().enumerate() {
        for (k, rings) in polys.iter().enumerate() {
            for (j, ring) in rings.iter().enumerate() {
                let mut distinct: Vec<(u64, u64)> = ring
                    .iter()
                    .map(|p| (p[0].to_bits(), p[1].to_bits()))
                    .collect();
                distinct.sort_unstable();
                distinct.dedup();
                if distinct.len() < 3 || ring_area(ring) == 0.0 {
                    flag(
                        &mut found,
                        r,
                        k,
                        format!("{}: ring {j} of polygon {k} has no area", label(r)),
                    );
                }
                for i in 0..ring.len() {
                    let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                    if a != b {
                        edges.push(Edge {
                            region: r,
                            polygon: k,
                            a,
                            b,
                        });
                    }
                }
            }
        }
    }
    for (e, f, at) in crossings(&edges) {
        let (e, f) = (&edges[e], &edges[f]);
        let at = frame.to_input(at);
        let reason = if e.region == f.region && e.polygon == f.polygon {
            format!(
                "{}: polygon {} crosses itself near ({}, {})",
                label(e.region),
                e.polygon,
                at[0],
                at[1]
            )
        } else {
            format!(
                "{}: polygon {} crosses {} near ({}, {})",
                label(e.region),
                e.polygon,
                label(f.region),
                at[0],
                at[1]
            )
        };
        flag(&mut found, e.region, e.polygon, reason.clone());
        flag(&mut found, f.region, f.polygon, reason);
    }
    for (r, polys) in unit.iter().enumerate() {
        for (k, rings) in polys.iter().enumerate() {
            for (j, hole) in rings.iter().enumerate().skip(1) {
                if hole.len() < 2 || rings[0].len() < 3 {
                    continue;
                }
                let (a, b) = (hole[0], hole[1]);
                let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
                if !inside_ring(mid, &rings[0]) {
                    flag(
                        &mut found,
                        r,
                        k,
                        format!(
                            "{}: ring {j} of polygon {k} (a hole) lies outside its exterior",
                            label(r)
                        ),
                    );
                }
            }
        }
    }
    for (r, k, other) in contained(&unit) {
        flag(
            &mut found,
            r,
            k,
            format!("{}: polygon {k} lies inside {}", label(r), label(other)),
        );
    }
    found
}

/// Pairs of edges that cross properly (see [`proper_crossings`]), with where they cross.
fn crossings(edges: &[Edge]) -> Vec<(usize, usize, [f64; 2])> {
    let segments: Vec<[[f64; 2]; 2]> = edges.iter().map(|e| [e.a, e.b]).collect();
    proper_crossings(&segments)
        .into_iter()
        .map(|(i, j)| (i, j, crossing_point(segments[i], segments[j])))
        .collect()
}

/// Polygons (region, polygon) lying inside another region's polygon (inside its exterior and
/// in none of its holes), with that region: a vertex of the polygon that is not a vertex of
/// the other lies inside it, farther than [`ROUNDING`] from its boundary.
fn contained(unit: &[Vec<Polygon>]) -> Vec<(usize, usize, usize)> {
    let mut boxes = Vec::new();
    for (r, polys) in unit.iter().enumerate() {
        for (k, rings) in polys.iter().enumerate() {
            if let Some(ext) = rings.first().filter(|e| !e.is_empty()) {
                let (lo, hi) = bbox(ext.iter().copied());
                boxes.push((r, k, lo, hi));
            }
        }
    }
    let mut out = Vec::new();
    if boxes.is_empty() {
        return out;
    }
    let (lo, hi) = bbox(boxes.iter().flat_map(|b| [b.2, b.3]));
    let extents: Vec<([f64; 2], [f64; 2])> = boxes.iter().map(|b| (b.2, b.3)).collect();
    let grid = Buckets::new(lo, hi, &extents);
    for &(r, k, plo, phi) in &boxes {
        let mut seen = HashSet::new();
        let mut inside_of = None;
        grid.visit(plo, phi, |j| {
            let (s, m, qlo, qhi) = boxes[j];
            if s == r || inside_of.is_some() || !seen.insert(j) {
                return;
            }
            let within =
                qlo[0] <= plo[0] && qlo[1] <= plo[1] && qhi[0] >= phi[0] && qhi[1] >= phi[1];
            if within && polygon_inside(&unit[r][k], &unit[s][m]) {
                inside_of = Some(s);
            }
        });
        if let Some(s) = inside_of {
            out.push((r, k, s));
        }
    }
    out
}

/// Whether polygon `p` lies inside polygon `q` (see [`contained`]).
fn polygon_inside(p: &Polygon, q: &Polygon) -> bool {
    let key = |v: &[f64; 2]| (v[0].to_bits(), v[1].to_bits());
    let q_vertices: HashSet<(u64, u64)> = q.iter().flatten().map(key).collect();
    let Some(v) = p[0].iter().find(|v| !q_vertices.contains(&key(v))) else {
        return false;
    };
    let inside = q.iter().filter(|ring| inside_ring(*v, ring)).count() % 2 == 1;
    if !inside {
        return false;
    }
    let distance = q
        .iter()
        .flat_map(|ring| (0..ring.len()).map(move |i| (ring[i], ring[(i + 1) % ring.len()])))
        .fold(f64::INFINITY, |d, (a, b)| d.min(segment_distance(*v, a, b)));
    distance > ROUNDING
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
    }

    fn labels(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("feature {i}")).collect()
    }

    #[test]
    fn touching_squares_and_a_lake_are_valid() {
        let mut hole = square(0.25, 0.25, 0.5);
        hole.reverse();
        let coords = vec![
            vec![vec![square(0.0, 0.0, 1.0), hole.clone()]],
            vec![vec![square(1.0, 0.0, 1.0)]],
            vec![vec![hole]],
        ];
        assert_eq!(check(&coords, &labels(3)), vec![]);
        // At any scale.
        let big: Vec<Vec<Polygon>> = coords
            .iter()
            .map(|p| {
                p.iter()
                    .map(|r| {
                        r.iter()
                            .map(|ring| ring.iter().map(|q| [q[0] * 1e300, q[1] * 1e300]).collect())
                            .collect()
                    })
                    .collect()
            })
            .collect();
        assert_eq!(check(&big, &labels(3)), vec![]);
    }

    #[test]
    fn a_bow_tie_is_invalid_and_named() {
        let bow = vec![[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
        let coords = vec![vec![vec![square(5.0, 5.0, 1.0)]], vec![vec![bow]]];
        let found = check(&coords, &labels(2));
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].region, found[0].polygon), (1, 0));
        assert!(
            found[0]
                .reason
                .starts_with("feature 1: polygon 0 crosses itself near ("),
            "{}",
            found[0].reason
        );
    }

    #[test]
    fn overlaps_holes_outside_and_degenerate_rings_are_invalid() {
        // Two squares overlapping at a corner: both polygons are invalid.
        let coords = vec![
            vec![vec![square(0.0, 0.0, 1.0)]],
            vec![vec![square(0.5, 0.5, 1.0)]],
        ];
        let found = check(&coords, &labels(2));
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found[0].reason.contains("crosses feature 1"), "{found:?}");
        // One square wholly inside another, sharing nothing.
        let coords = vec![
            vec![vec![square(0.0, 0.0, 4.0)]],
            vec![vec![square(1.0, 1.0, 1.0)]],
        ];
        let found = check(&coords, &labels(2));
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0]
                .reason
                .contains("feature 1: polygon 0 lies inside feature 0")
        );
        // A hole outside its exterior; a ring of two points.
        let coords = vec![
            vec![vec![square(0.0, 0.0, 1.0), square(3.0, 3.0, 1.0)]],
            vec![vec![vec![[5.0, 5.0], [6.0, 6.0]]]],
        ];
        let found = check(&coords, &labels(2));
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(
            found
                .iter()
                .any(|f| f.reason.contains("(a hole) lies outside"))
        );
        assert!(found.iter().any(|f| f.reason.contains("has no area")));
        // A position that is not finite.
        let coords = vec![vec![vec![vec![[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]]]]];
        let found = check(&coords, &labels(1));
        assert!(found[0].reason.contains("not finite"), "{found:?}");
    }
}
