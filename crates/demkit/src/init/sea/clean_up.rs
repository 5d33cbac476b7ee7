//! Cleaning the disk glued to its reflection into one manifold disk (DEM paper Algorithm 4,
//! step 6), and the final check of the result.

use crate::{Error, Result};

/// Twice the signed area of (a, b, c).
pub(super) fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

pub(super) fn orient(pos: &[[f64; 2]], f: [u32; 3]) -> f64 {
    orient2(pos[f[0] as usize], pos[f[1] as usize], pos[f[2] as usize])
}

/// One corner of a face at a vertex v: the face and the vertices after and before v in it.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Corner {
    pub(super) face: u32,
    pub(super) next: u32,
    pub(super) prev: u32,
}

/// Vertex → corners incidence of a face list, in compressed form. The half-edges leaving v
/// are v → `next` of its corners, so twins are found by a scan of one short contiguous list.
/// Queries take the faces' `alive` flags, so faces can be dropped without a rebuild.
pub(super) struct Incidence {
    pub(super) start: Vec<usize>,
    pub(super) corners: Vec<Corner>,
}

impl Incidence {
    pub(super) fn new(faces: &[[u32; 3]], nv: usize) -> Self {
        let (start, corners) = crate::mesh::topology::vertex_corners(nv, faces, |k, e| {
            let f = faces[k];
            Some(Corner {
                face: k as u32,
                next: f[(e + 1) % 3],
                prev: f[(e + 2) % 3],
            })
        });
        Incidence { start, corners }
    }

    /// The corners of alive faces at `v`.
    pub(super) fn of<'a>(
        &'a self,
        v: u32,
        alive: &'a [bool],
    ) -> impl Iterator<Item = &'a Corner> + 'a {
        self.corners[self.start[v as usize]..self.start[v as usize + 1]]
            .iter()
            .filter(move |c| alive[c.face as usize])
    }

    /// Whether some alive face holds the half-edge b → a (the twin of a → b).
    pub(super) fn has_twin(&self, a: u32, b: u32, alive: &[bool]) -> bool {
        self.of(b, alive).any(|c| c.next == a)
    }
}

/// Drops (marks not alive) the faces that are not edge-connected to the first `n_dt` faces
/// (the triangulated unit disk D_T, never dropped) and, at every vertex whose faces form more
/// than one fan (two or more outgoing boundary half-edges), the faces of the fans other than
/// the one holding a D_T face (or the largest), until nothing changes. Vertices below
/// `n_circle` are inner vertices of D_T (all their faces are D_T faces); the circle vertices
/// are `n_circle..n_disk`. A vertex with `full[v]` alive faces has its complete fan.
pub(super) fn clean_up(
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
    let mut sets = crate::mesh::union_find::UnionFind::default();
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
            sets.reset(list.len());
            for i in 0..list.len() {
                for j in 0..list.len() {
                    if list[j].next == list[i].prev {
                        sets.union(i as u32, j as u32);
                    }
                }
            }
            let roots: Vec<usize> = (0..list.len() as u32)
                .map(|i| sets.find(i) as usize)
                .collect();
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

/// The directed boundary half-edges a → b of the alive faces (no alive face has b → a), as
/// `next[a] = b`; `None` if a vertex has two outgoing boundary edges (not a manifold).
/// Vertices with `full[v]` alive faces (a complete fan) are skipped.
pub(super) fn boundary_next(
    inc: &Incidence,
    alive: &[bool],
    full: Option<&[u32]>,
) -> Option<Vec<u32>> {
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
pub(super) fn loops(next: &[u32]) -> Vec<Vec<u32>> {
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

pub(super) fn loop_area(pos: &[[f64; 2]], lp: &[u32]) -> f64 {
    let k = lp.len();
    (0..k)
        .map(|i| {
            let (a, b) = (pos[lp[i] as usize], pos[lp[(i + 1) % k] as usize]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0
}

/// Final check of the extended mesh: counter-clockwise sea faces, every edge in at most two
/// faces, one boundary loop and Euler characteristic 1 (a disk).
pub(super) fn check_disk(pos: &[[f64; 2]], faces: &[[u32; 3]], n_roi_faces: usize) -> Result<()> {
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
        let list = &inc.corners[inc.start[v as usize]..inc.start[v as usize + 1]];
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
