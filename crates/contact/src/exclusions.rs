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

    /// The live rows: per triangle the number of its bonded partners, and the partners row
    /// after row (each pair appears in both of its rows; copies of a pair set twice stay).
    /// Empty when no list was ever set. [`Self::from_rows`] rebuilds the same exclusions.
    pub fn rows(&self) -> (Vec<u32>, Vec<u32>) {
        let lens = self.rows.iter().map(|r| r[1]).collect();
        let mut nbrs = Vec::with_capacity(self.live);
        for &[start, len] in &self.rows {
            nbrs.extend_from_slice(&self.nbrs[start as usize..(start + len) as usize]);
        }
        (lens, nbrs)
    }

    /// The exclusions whose live rows are `lens` and `nbrs` ([`Self::rows`]); an error when
    /// they do not fit together (the lengths do not add up to the partners, a partner is not
    /// a triangle, or a pair is missing from its partner's row as often as it is in its own).
    pub fn from_rows(lens: &[u32], nbrs: &[u32]) -> Result<Self, String> {
        let total: u64 = lens.iter().map(|&l| u64::from(l)).sum();
        if total != nbrs.len() as u64 {
            return Err(format!(
                "bonded pairs: the rows hold {total} partners, the list {}",
                nbrs.len()
            ));
        }
        if total > u64::from(u32::MAX) {
            return Err(format!("bonded pairs: {total} partners"));
        }
        let n = lens.len();
        if let Some(j) = nbrs.iter().find(|&&j| j as usize >= n) {
            return Err(format!(
                "bonded pairs: partner {j} of a mesh of {n} triangles"
            ));
        }
        let mut rows = Vec::with_capacity(n);
        let mut start = 0u32;
        for &l in lens {
            rows.push([start, l]);
            start += l;
        }
        let e = Exclusions {
            rows,
            nbrs: nbrs.to_vec(),
            live: nbrs.len(),
        };
        // Each pair in both of its rows, as often: the count of (i, j) in row i equals that
        // of (j, i) in row j (a pair (i, i) lies twice in row i per copy).
        let mut keys: Vec<(u32, u32)> = Vec::with_capacity(nbrs.len());
        for (i, &[s, l]) in e.rows.iter().enumerate() {
            for &j in &e.nbrs[s as usize..(s + l) as usize] {
                keys.push((i as u32, j));
            }
        }
        let mut swapped: Vec<(u32, u32)> = keys.iter().map(|&(i, j)| (j, i)).collect();
        keys.sort_unstable();
        swapped.sort_unstable();
        if keys != swapped {
            return Err("bonded pairs: a pair is not in both of its rows".into());
        }
        Ok(e)
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
        // The live rows rebuild the same exclusions (a checkpoint's copy).
        let (lens, nbrs) = e.rows();
        let r = Exclusions::from_rows(&lens, &nbrs).unwrap();
        assert_eq!((r.len(), r.rows()), (e.len(), (lens.clone(), nbrs.clone())));
        for (i, j) in [(0, 1), (1, 2), (0, 3), (2, 3)] {
            assert_eq!(r.is_bonded(i, j), e.is_bonded(i, j), "({i}, {j})");
        }
        assert!(Exclusions::from_rows(&lens, &nbrs[1..]).is_err(), "lengths");
        assert!(
            Exclusions::from_rows(&[1, 0, 0, 1], &[3, 2]).is_err(),
            "one-sided"
        );
        assert!(e.is_bonded(1, 2) && e.is_bonded(0, 3) && e.is_bonded(3, 0));
        assert!(e.unbond(3, 0) && e.unbond(2, 1));
        assert!(e.is_empty());
        // set_bonded again restores a full list.
        e.set_bonded(4, &[[2, 3]]);
        assert!(e.is_bonded(3, 2) && e.len() == 1);
    }
}
