//! Disjoint sets of `0..n` (union–find with path halving), shared by the connectivity checks:
//! the components of a mesh, the fans around a vertex, the fans of the sea's clean-up.

/// Disjoint sets of `0..n`; each set is represented by its smallest member.
#[derive(Debug, Clone, Default)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> Self {
        let mut sets = Self::default();
        sets.reset(n);
        sets
    }

    /// Back to `n` singletons, reusing the storage.
    pub fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }

    /// The smallest member of `x`'s set.
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let up = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = up;
            x = up;
        }
        x
    }

    /// Joins the sets of `a` and `b`; false if they were already one.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        // The smaller root stays the representative.
        self.parent[ra.max(rb) as usize] = ra.min(rb);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_join_and_keep_their_smallest_member() {
        let mut s = UnionFind::new(6);
        assert!(s.union(4, 2));
        assert!(s.union(5, 4));
        assert!(!s.union(2, 5));
        assert!(s.union(3, 1));
        assert_eq!(
            (0..6).map(|x| s.find(x)).collect::<Vec<_>>(),
            [0, 1, 2, 1, 2, 2]
        );
        assert!(s.union(3, 5));
        assert_eq!(
            (0..6).map(|x| s.find(x)).collect::<Vec<_>>(),
            [0, 1, 1, 1, 1, 1]
        );
        s.reset(3);
        assert_eq!((0..3).map(|x| s.find(x)).collect::<Vec<_>>(), [0, 1, 2]);
    }

    #[test]
    fn a_long_chain_is_found_from_its_far_end() {
        let n = 100_000u32;
        let mut s = UnionFind::new(n as usize);
        for x in 1..n {
            s.union(x, x - 1);
        }
        assert_eq!(s.find(n - 1), 0);
    }
}
