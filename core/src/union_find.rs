//! [`Uf`]: the union-find of proved equalities (detections proved to see
//! one landmark), with the smallest index as the root of each group, so
//! that groups come out sorted and in the same order whatever the order
//! of the unions. The one union-find of core: the SLAM side (the
//! matching, the shapes round, the distinct pairs) and the groups of the
//! atmost_nvector fixpoint (`nvector::Groups` wraps it with a union count).
//!
//! Complexity: near-constant amortized per operation (path compression);
//! O(k) memory.

/// Union-find over detections with the smallest index as root.
#[derive(Debug, Clone)]
pub struct Uf(Vec<usize>);

impl Uf {
    /// k singletons.
    pub fn new(k: usize) -> Uf {
        Uf((0..k).collect())
    }

    /// The root (smallest member) of `i`'s group.
    pub fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut j = i;
        while self.0[j] != r {
            let n = self.0[j];
            self.0[j] = r;
            j = n;
        }
        r
    }

    /// Merges; returns the new root.
    pub fn union(&mut self, a: usize, b: usize) -> usize {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.0[hi] = lo;
        lo
    }

    /// Number of detections.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are no detections.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Groups of size >= 2, members sorted, by smallest member.
    pub fn groups(&mut self) -> Vec<Vec<usize>> {
        let k = self.0.len();
        let mut by: Vec<Vec<usize>> = vec![Vec::new(); k];
        for i in 0..k {
            let r = self.find(i);
            by[r].push(i);
        }
        by.into_iter().filter(|g| g.len() >= 2).collect()
    }
}
