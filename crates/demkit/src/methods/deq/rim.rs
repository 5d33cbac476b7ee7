//! The parts of a hole's rim that no circle domain can hold outside its circle.
//!
//! An *ear* is a triangle with two edges on a hole's boundary loop: its three corners are
//! boundary vertices of that hole, so on the hole's circle they span a triangle inside the
//! circle, which is inside the hole. More generally, a *peninsula* is a part of the surface
//! joined to the rest by a single edge whose two ends lie on the same hole (an ear is a
//! peninsula of one triangle): that edge would be a chord of the circle, inside the hole. Holes
//! cut out of a scan by removing faces typically leave such ears along their jagged rims.
//!
//! [`peel`] removes them, repeatedly, from the region that must lie outside the holes: the
//! remaining *peeled* loop of each hole has no ear and no chord, and a peeled-off face becomes
//! part of its hole (the map lays it inside the hole's circle).

use crate::{Error, Result};

/// What [`peel`] found on the rims of the holes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rims {
    /// The boundary loops after peeling, in the order given (the outer loop first, unchanged).
    pub loops: Vec<Vec<u32>>,
    /// For every face, the hole (index into `loops`) it was peeled into, or `None` if it stays
    /// in the region outside the holes.
    pub hole_of_face: Vec<Option<usize>>,
}

impl Rims {
    /// Number of faces peeled into holes.
    pub fn n_peeled(&self) -> usize {
        self.hole_of_face.iter().filter(|h| h.is_some()).count()
    }
}

/// Peels ears and peninsulas off every hole loop (`loops[1..]`; `loops[0]` is the outer loop,
/// where chords are harmless). The loops follow the face orientation (as
/// [`crate::mesh::topology::topology`] gives them) and the mesh is a valid connected surface.
///
/// Errors ([`Error::Topology`]): a hole whose rim is nothing but peninsulas (fewer than three
/// vertices remain), or a hole joined by a single edge to a part of the surface that holds
/// another boundary, which no circle domain can represent.
pub(crate) fn peel(n_vertices: usize, faces: &[[u32; 3]], loops: &[Vec<u32>]) -> Result<Rims> {
    let mut state = State::new(n_vertices, faces);
    let mut loop_of = vec![usize::MAX; n_vertices];
    for (l, lp) in loops.iter().enumerate() {
        for &v in lp {
            loop_of[v as usize] = l;
        }
    }
    let mut out = vec![loops[0].clone()];
    for (h, lp) in loops.iter().enumerate().skip(1) {
        let mut lp = lp.clone();
        loop {
            let before = lp.len();
            state.clip_ears(&mut lp, h);
            if let Some(chord) = state.find_chord(&lp) {
                state.remove_peninsula(&mut lp, chord, h, &loop_of)?;
            }
            if lp.len() == before {
                break;
            }
        }
        if lp.len() < 3 {
            return Err(Error::Topology {
                method: "deq".into(),
                msg: format!(
                    "the rim of hole {h} is a strip of triangles with no room for a circle \
                     (fewer than three of its boundary vertices remain outside it)"
                ),
            });
        }
        out.push(lp);
    }
    Ok(Rims {
        loops: out,
        hole_of_face: state.hole_of_face,
    })
}

/// The faces still outside the holes, with their incidence.
struct State<'a> {
    faces: &'a [[u32; 3]],
    hole_of_face: Vec<Option<usize>>,
    /// Faces around every vertex (all faces; peeled ones are skipped by the readers).
    offsets: Vec<usize>,
    incident: Vec<u32>,
    /// Number of unpeeled faces at every vertex.
    alive: Vec<u32>,
}

impl<'a> State<'a> {
    fn new(n: usize, faces: &'a [[u32; 3]]) -> Self {
        let (offsets, incident) = crate::mesh::topology::vertex_faces(n, faces);
        let mut alive = vec![0u32; n];
        for f in faces {
            for &v in f {
                alive[v as usize] += 1;
            }
        }
        Self {
            faces,
            hole_of_face: vec![None; faces.len()],
            offsets,
            incident,
            alive,
        }
    }

    fn faces_at(&self, v: u32) -> impl Iterator<Item = usize> + '_ {
        self.incident[self.offsets[v as usize]..self.offsets[v as usize + 1]]
            .iter()
            .map(|&f| f as usize)
            .filter(|&f| self.hole_of_face[f].is_none())
    }

    fn remove_face(&mut self, f: usize, hole: usize) {
        self.hole_of_face[f] = Some(hole);
        for &v in &self.faces[f] {
            self.alive[v as usize] -= 1;
        }
    }

    /// Removes ears (loop vertices with a single face) until none is left; the loop loses
    /// their apexes.
    fn clip_ears(&mut self, lp: &mut Vec<u32>, hole: usize) {
        loop {
            let Some(k) = (0..lp.len()).find(|&k| self.alive[lp[k] as usize] == 1) else {
                return;
            };
            if lp.len() <= 3 {
                return;
            }
            let v = lp[k];
            let face = self.faces_at(v).next();
            if let Some(f) = face {
                self.remove_face(f, hole);
            }
            lp.remove(k);
        }
    }

    /// An edge of an unpeeled face joining two vertices of `lp` that are not neighbours on it.
    fn find_chord(&self, lp: &[u32]) -> Option<[u32; 2]> {
        let n = lp.len();
        let mut position = std::collections::HashMap::with_capacity(n);
        for (k, &v) in lp.iter().enumerate() {
            position.insert(v, k);
        }
        for &a in lp {
            for f in self.faces_at(a) {
                for &b in &self.faces[f] {
                    if b == a {
                        continue;
                    }
                    if let Some(&kb) = position.get(&b) {
                        let d = (position[&a] + n - kb) % n;
                        if d != 1 && d != n - 1 {
                            return Some([a, b]);
                        }
                    }
                }
            }
        }
        None
    }

    /// Peels the side of `chord` that holds no other boundary: the faces reached from one of
    /// the chord's two faces without crossing the chord.
    fn remove_peninsula(
        &mut self,
        lp: &mut Vec<u32>,
        chord: [u32; 2],
        hole: usize,
        loop_of: &[usize],
    ) -> Result<()> {
        let sides: Vec<usize> = self
            .faces_at(chord[0])
            .filter(|&f| self.faces[f].contains(&chord[1]))
            .collect();
        for &start in &sides {
            let region = self.flood(start, chord);
            let foreign = region.iter().any(|&f| {
                self.faces[f]
                    .iter()
                    .any(|&v| loop_of[v as usize] != usize::MAX && loop_of[v as usize] != hole)
            });
            if !foreign {
                for f in region {
                    self.remove_face(f, hole);
                }
                lp.retain(|&v| self.alive[v as usize] > 0);
                return Ok(());
            }
        }
        Err(Error::Topology {
            method: "deq".into(),
            msg: format!(
                "the edge from vertex {} to vertex {} joins two points of one hole's boundary \
                 and separates it from another boundary; no circle domain can hold this surface",
                chord[0], chord[1]
            ),
        })
    }

    /// The unpeeled faces connected to `start` through edges other than `chord`.
    fn flood(&self, start: usize, chord: [u32; 2]) -> Vec<usize> {
        let mut seen = std::collections::HashSet::from([start]);
        let mut stack = vec![start];
        let mut out = Vec::new();
        while let Some(f) = stack.pop() {
            out.push(f);
            let face = self.faces[f];
            for k in 0..3 {
                let (a, b) = (face[k], face[(k + 1) % 3]);
                if (a == chord[0] && b == chord[1]) || (a == chord[1] && b == chord[0]) {
                    continue;
                }
                for g in self.faces_at(a) {
                    if g != f && self.faces[g].contains(&b) && seen.insert(g) {
                        stack.push(g);
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology::topology;

    /// A 4×4-square grid with the middle 2×2 squares removed, and one extra triangle (an ear)
    /// poking into the hole.
    fn grid_with_hole(ear: bool) -> (usize, Vec<[u32; 3]>) {
        let id = |i: u32, j: u32| j * 5 + i;
        let mut faces = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                if (1..3).contains(&i) && (1..3).contains(&j) {
                    continue;
                }
                faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        if ear {
            // Half of the hole's square (1,1): corners (1,1), (2,1), (2,2); the corner (2,2)
            // has no other face, so two of the triangle's edges are on the hole's loop.
            faces.push([id(1, 1), id(2, 1), id(2, 2)]);
        }
        (25, faces)
    }

    #[test]
    fn a_hole_without_ears_is_unchanged() {
        let (n, faces) = grid_with_hole(false);
        let mesh = crate::TriMesh::new(vec![[0.0; 3]; n], faces.clone());
        let loops = topology(&mesh).boundary_loops;
        let rims = peel(n, &faces, &loops).unwrap();
        assert_eq!(rims.loops, loops);
        assert_eq!(rims.n_peeled(), 0);
    }

    #[test]
    fn an_ear_is_peeled_into_its_hole() {
        let (n, faces) = grid_with_hole(true);
        let mesh = crate::TriMesh::new(vec![[0.0; 3]; n], faces.clone());
        let loops = topology(&mesh).boundary_loops;
        assert_eq!(loops.len(), 2);
        let rims = peel(n, &faces, &loops).unwrap();
        assert_eq!(rims.n_peeled(), 1);
        assert_eq!(rims.hole_of_face[faces.len() - 1], Some(1));
        // The ear's apex (2,2) = vertex 12 leaves the loop; its edge (1,1)–(2,1) closes it.
        assert!(loops[1].contains(&12) && !rims.loops[1].contains(&12));
        assert_eq!(rims.loops[1].len(), loops[1].len() - 1);
    }
}
