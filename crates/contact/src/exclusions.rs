//! Pairs of triangles that must never be contact couples: triangles of one connected mesh
//! that share a node, and pairs the caller declares bonded (the intact joints of the fracture
//! crate; the caller releases pairs one by one as joints break, or sets the list again).

/// Bonded triangle pairs in compressed rows (both directions), rebuilt by [`Self::set_bonded`]
/// without allocating once its buffers are large enough, and thinned pair by pair by
/// [`Self::unbond`] (a released pair is swapped to the end of the live part of its two rows:
/// `O(row length)`, no allocation).
#[derive(Clone, Debug, Default)]
pub struct Exclusions {
    /// Per triangle: `[start, live length]` of its row in `nbrs`.
    rows: Vec<[u32; 2]>,
    nbrs: Vec<u32>,
    /// Live entries in `nbrs` (each pair counts twice).
    live: usize,
}

impl Exclusions {
    /// No bonded pairs.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the bonded pairs (any order, any orientation; duplicates are harmless) for a mesh
    /// of `n_tris` triangles. Pairs naming a triangle `>= n_tris` are ignored.
    pub fn set_bonded(&mut self, n_tris: usize, pairs: &[[u32; 2]]) {
        self.rows.clear();
        self.rows.resize(n_tris + 1, [0, 0]);
        let ok = |p: &[u32; 2]| (p[0] as usize) < n_tris && (p[1] as usize) < n_tris;
        // Row lengths into rows[i + 1][0], prefix sums, then fill with rows[i][1] as cursor.
        for p in pairs.iter().filter(|p| ok(p)) {
            self.rows[p[0] as usize + 1][0] += 1;
            self.rows[p[1] as usize + 1][0] += 1;
        }
        for i in 0..n_tris {
            self.rows[i + 1][0] += self.rows[i][0];
        }
        self.nbrs.clear();
        self.nbrs.resize(self.rows[n_tris][0] as usize, 0);
        for p in pairs.iter().filter(|p| ok(p)) {
            for (a, b) in [(p[0], p[1]), (p[1], p[0])] {
                let [start, len] = &mut self.rows[a as usize];
                self.nbrs[(*start + *len) as usize] = b;
                *len += 1;
            }
        }
        self.rows.pop();
        self.live = self.nbrs.len();
    }

    /// Releases the pair `(i, j)` (either orientation; every copy of it): from now on it is
    /// not excluded unless the two triangles share a node. Returns true when it was bonded.
    pub fn unbond(&mut self, i: u32, j: u32) -> bool {
        let removed = self.remove_from_row(i, j);
        if removed > 0 {
            self.remove_from_row(j, i);
        }
        self.live -= 2 * removed;
        removed > 0
    }

    /// Removes every `j` from the live part of row `i`; returns how many there were.
    fn remove_from_row(&mut self, i: u32, j: u32) -> usize {
        let Some([start, len]) = self.rows.get_mut(i as usize) else {
            return 0;
        };
        let (start, mut k, mut removed) = (*start as usize, 0usize, 0usize);
        while k < *len as usize {
            if self.nbrs[start + k] == j {
                *len -= 1;
                self.nbrs.swap(start + k, start + *len as usize);
                removed += 1;
            } else {
                k += 1;
            }
        }
        removed
    }

    /// Number of bonded pairs stored (each counted once).
    pub fn len(&self) -> usize {
        self.live / 2
    }

    /// True when no pair is bonded.
    pub fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// True when triangles `i` and `j` are bonded.
    #[inline]
    pub fn is_bonded(&self, i: u32, j: u32) -> bool {
        let Some(&[start, len]) = self.rows.get(i as usize) else {
            return false;
        };
        self.nbrs[start as usize..(start + len) as usize].contains(&j)
    }

    /// True when the couple (i, j) must not be a contact pair: they share a node or are bonded.
    #[inline]
    pub fn excluded(&self, tris: &[[u32; 3]], i: u32, j: u32) -> bool {
        share_node(&tris[i as usize], &tris[j as usize]) || self.is_bonded(i, j)
    }
}

/// True when two triangles share at least one node.
#[inline(always)]
pub fn share_node(a: &[u32; 3], b: &[u32; 3]) -> bool {
    a.iter().any(|n| b.contains(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unbond_releases_both_directions_and_every_copy() {
        let mut e = Exclusions::new();
        // (0, 1) twice (once reversed), (1, 2), (0, 3); a pair out of range is ignored.
        e.set_bonded(4, &[[0, 1], [1, 2], [1, 0], [0, 3], [2, 9]]);
        assert_eq!(e.len(), 4);
        assert!(e.is_bonded(0, 1) && e.is_bonded(1, 0) && e.is_bonded(2, 1));
        assert!(!e.is_bonded(2, 9) && !e.is_bonded(9, 2));
        assert!(e.unbond(1, 0), "was bonded");
        assert!(
            !e.is_bonded(0, 1) && !e.is_bonded(1, 0),
            "both copies released"
        );
        assert!(!e.unbond(0, 1), "already released");
        assert!(!e.unbond(7, 1), "out of range");
        assert_eq!(e.len(), 2);
        assert!(e.is_bonded(1, 2) && e.is_bonded(0, 3) && e.is_bonded(3, 0));
        assert!(e.unbond(3, 0) && e.unbond(2, 1));
        assert!(e.is_empty());
        // set_bonded again restores a full list.
        e.set_bonded(4, &[[2, 3]]);
        assert!(e.is_bonded(3, 2) && e.len() == 1);
    }
}
