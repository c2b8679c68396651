//! Pairs of triangles that must never be contact couples: triangles of one connected mesh
//! that share a node, and pairs the caller declares bonded (the intact joints of the fracture
//! crate; the caller sets the list again when joints break).

/// Bonded triangle pairs in compressed rows (both directions), rebuilt by [`Self::set_bonded`]
/// without allocating once its buffers are large enough.
#[derive(Clone, Debug, Default)]
pub struct Exclusions {
    offsets: Vec<u32>,
    nbrs: Vec<u32>,
}

impl Exclusions {
    /// No bonded pairs.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the bonded pairs (any order, any orientation; duplicates are harmless) for a mesh
    /// of `n_tris` triangles. Pairs naming a triangle `>= n_tris` are ignored.
    pub fn set_bonded(&mut self, n_tris: usize, pairs: &[[u32; 2]]) {
        self.offsets.clear();
        self.offsets.resize(n_tris + 1, 0);
        let ok = |p: &[u32; 2]| (p[0] as usize) < n_tris && (p[1] as usize) < n_tris;
        for p in pairs.iter().filter(|p| ok(p)) {
            self.offsets[p[0] as usize + 1] += 1;
            self.offsets[p[1] as usize + 1] += 1;
        }
        for i in 0..n_tris {
            self.offsets[i + 1] += self.offsets[i];
        }
        self.nbrs.clear();
        self.nbrs.resize(self.offsets[n_tris] as usize, 0);
        // Fill using offsets[i] as a cursor, then shift back.
        for p in pairs.iter().filter(|p| ok(p)) {
            for (a, b) in [(p[0], p[1]), (p[1], p[0])] {
                let c = &mut self.offsets[a as usize];
                self.nbrs[*c as usize] = b;
                *c += 1;
            }
        }
        for i in (1..=n_tris).rev() {
            self.offsets[i] = self.offsets[i - 1];
        }
        if n_tris > 0 {
            self.offsets[0] = 0;
        }
    }

    /// Number of bonded pairs stored (each counted once).
    pub fn len(&self) -> usize {
        self.nbrs.len() / 2
    }

    /// True when no pair is bonded.
    pub fn is_empty(&self) -> bool {
        self.nbrs.is_empty()
    }

    /// True when triangles `i` and `j` are bonded.
    #[inline]
    pub fn is_bonded(&self, i: u32, j: u32) -> bool {
        let i = i as usize;
        if i + 1 >= self.offsets.len() {
            return false;
        }
        let (a, b) = (self.offsets[i] as usize, self.offsets[i + 1] as usize);
        self.nbrs[a..b].contains(&j)
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
