//! Regions that overlap along shared edges. In a map every edge has at most one region on
//! each side; once borders are shared vertex for vertex, two regions on the same side of an
//! edge overlap there (the same polygon given twice, or one region's part lying on
//! another's), which no crossing of edges reveals.

use super::regions::RegionSet;
use super::rings::ring_orientation;
use crate::{Error, Result};
use std::collections::HashMap;

impl RegionSet {
    /// Refuses two regions (or two polygons of one region) lying on the same side of a shared
    /// edge: every ring's edges are taken in the direction that has its region on the left
    /// (exteriors counter-clockwise, holes clockwise), and no directed edge may come twice.
    ///
    /// Errors: [`Error::Format`] naming both features and the edge.
    pub(super) fn check_sides(&self, path: &str) -> Result<()> {
        let mut left_of: HashMap<[usize; 2], (usize, usize)> = HashMap::new();
        for (r, region) in self.regions.iter().enumerate() {
            for (k, rings) in region.polygons.iter().enumerate() {
                for (j, ring) in rings.iter().enumerate() {
                    let pts: Vec<[f64; 2]> = ring.iter().map(|&v| self.points[v]).collect();
                    // The region lies left of a counter-clockwise exterior, right of a
                    // counter-clockwise hole.
                    let ccw = ring_orientation(&pts) > 0.0;
                    let forward = ccw == (j == 0);
                    for i in 0..ring.len() {
                        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                        let edge = if forward { [a, b] } else { [b, a] };
                        if let Some(&(r0, k0)) = left_of.get(&edge) {
                            let (p, q) = (
                                self.frame.to_input(self.points[edge[0]]),
                                self.frame.to_input(self.points[edge[1]]),
                            );
                            let first = &self.regions[r0].label;
                            let what = if r0 == r {
                                format!("{first}: polygons {k0} and {k} overlap")
                            } else {
                                format!("{first} and {} overlap", region.label)
                            };
                            return Err(Error::Format {
                                path: path.to_string(),
                                msg: format!(
                                    "{what}: both lie on the same side of the edge from ({}, {}) \
                                     to ({}, {}) (a region given twice?)",
                                    p[0], p[1], q[0], q[1]
                                ),
                            });
                        }
                        left_of.insert(edge, (r, k));
                    }
                }
            }
        }
        Ok(())
    }
}
