//! Bonded triangle pairs of an exploded mesh: the edge neighbours of an intact joint, and every
//! pair of triangles around an original (pre-explode) mesh node whose star is intact.
//!
//! The original nodes are recovered from the joints alone: joint `j` with nodes `[P, Q, R, S]`
//! (`P = S`, `Q = R` in the reference) joins `P ~ S` and `Q ~ R`; the classes of this relation
//! (union-find over the model's nodes) are the original nodes inside the fracturing regions
//! (a node on a region's border also collects the shared node of the unexploded triangles).
//! The star of class `c` is the set of triangles with a node in `c`; its joints are the joints
//! with an end node in `c`. A star is intact while all its joints are; a star on the border of
//! the body or of a fracturing region is intact when all the joints it has are.
//!
//! Bonded set `B = { (T1, T2) of intact joints } U { (a, b) : a, b in star(c), c intact }`.
//! A joint's first softening (damage > 0, as the fracture stage calls it) or break marks the
//! stars of its two end nodes released, for good ([`StarBonds::release_stars`]); a break also
//! removes the joint's own pair ([`StarBonds::break_joint`]); pairs still held by an intact
//! joint or another intact star stay bonded. Both calls append exactly the pairs that leave
//! `B` (each pair once over the run), in `O(pairs of the released stars)`: the solver lists
//! `B` once at set-up ([`StarBonds::pairs`], `O(joints + vertex pairs)`, no sorting) and then
//! hands only released pairs to the contact crate (`Contact::release_pairs`, no
//! re-detection). Releasing at the first softening keeps triangles from sliding along fully
//! damaged, unbroken joints into vertex neighbours that are not contact couples
//! (docs/fracture.md section 13).
//!
//! Physics caveat: two non-adjacent triangles of an intact star could only overlap after the
//! joints between them and their edge neighbours are crushed by more than the joint penalty
//! allows (the joints carry compression there), so the contact couples they would make are
//! dropped while the star is intact. Stars that are split in two by a non-manifold node
//! (triangles touching at a node without a chain of joints between them) are two classes here,
//! which only keeps more couples in contact (conservative).

use rayon::prelude::*;

/// The star structure of a joint set (reference topology, fixed at set-up) and which bonds
/// still hold.
#[derive(Debug, Clone)]
pub struct StarBonds {
    /// Per joint: its two triangles.
    joint_tris: Vec<[u32; 2]>,
    /// Per joint: the stars of its two end nodes.
    joint_stars: Vec<[u32; 2]>,
    /// Vertex-neighbour pairs (sharing a star, no joint between them) and their star, grouped
    /// by star, in chunks of [`STAR_CHUNK`] stars (as the set-up builds them, in parallel):
    /// star `s = c STAR_CHUNK + k` owns `vertex_pairs[c][star_off[c][k]..star_off[c][k + 1]]`.
    vertex_pairs: Vec<Vec<VertexPair>>,
    star_off: Vec<Vec<u32>>,
    /// Per triangle: the stars of its vertices (`u32::MAX` where none).
    tri_stars: Vec<[u32; 3]>,
    /// Per star: still intact.
    star_intact: Vec<bool>,
    /// Per joint: its own pair released (the joint broke).
    joint_released: Vec<bool>,
    /// Pairs in the bonded set now.
    n_bonded: usize,
}

const NONE: u32 = u32::MAX;

/// A vertex-neighbour pair and its star.
type VertexPair = ([u32; 2], u32);

/// Stars per parallel task of the set-up (fixed: the lists do not depend on the threads).
const STAR_CHUNK: usize = 2048;

/// The vertex pairs of star `s` with joints `js`: every pair `[a, b]` (`a < b`) of its
/// triangles with no joint of the star between them, appended to `out` with `s`, in the
/// order of the sorted triangle list. `star_tris` is scratch.
fn vertex_pairs_of_star(
    s: u32,
    js: &[u32],
    tris: &[[u32; 2]],
    star_tris: &mut Vec<u32>,
    out: &mut Vec<([u32; 2], u32)>,
) {
    star_tris.clear();
    for &j in js {
        for t in tris[j as usize] {
            if !star_tris.contains(&t) {
                star_tris.push(t);
            }
        }
    }
    star_tris.sort_unstable();
    for (ia, &a) in star_tris.iter().enumerate() {
        for &b in &star_tris[ia + 1..] {
            let by_joint = js.iter().any(|&j| {
                let p = tris[j as usize];
                (p[0] == a && p[1] == b) || (p[0] == b && p[1] == a)
            });
            if !by_joint {
                out.push(([a, b], s));
            }
        }
    }
}

fn find(parent: &mut [u32], mut a: u32) -> u32 {
    while parent[a as usize] != a {
        let p = parent[a as usize];
        parent[a as usize] = parent[p as usize];
        a = p;
    }
    a
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

impl StarBonds {
    /// Builds the stars of joints `nodes[j] = [P, Q, R, S]` between `tris[j] = [T1, T2]`
    /// (`P -> Q` in `T1`, `R -> S` in `T2`) over a model of `n_nodes` nodes. All stars start
    /// intact.
    pub fn new(nodes: &[[u32; 4]], tris: &[[u32; 2]], n_nodes: usize) -> Self {
        let mut sb = Self::build(nodes, tris, n_nodes);
        sb.n_bonded = sb.bonded().count();
        sb
    }

    /// [`Self::new`] that also writes the bonded set into `out` (what [`Self::pairs`] writes
    /// then), listing it once: the count of bonded pairs is the list's length.
    pub fn with_pairs(
        nodes: &[[u32; 4]],
        tris: &[[u32; 2]],
        n_nodes: usize,
        out: &mut Vec<[u32; 2]>,
    ) -> Self {
        let mut sb = Self::build(nodes, tris, n_nodes);
        sb.pairs(out);
        sb.n_bonded = out.len();
        sb
    }

    /// The stars, all intact, with `n_bonded` still to be set.
    fn build(nodes: &[[u32; 4]], tris: &[[u32; 2]], n_nodes: usize) -> Self {
        let mut parent: Vec<u32> = (0..n_nodes as u32).collect();
        for n in nodes {
            union(&mut parent, n[0], n[3]);
            union(&mut parent, n[1], n[2]);
        }
        // Dense star ids for the roots that appear in a joint.
        let mut star_of_root = vec![NONE; n_nodes];
        let mut n_stars = 0u32;
        let mut joint_stars = Vec::with_capacity(nodes.len());
        for n in nodes {
            let mut s = [0u32; 2];
            for (k, &node) in [n[0], n[1]].iter().enumerate() {
                let r = find(&mut parent, node) as usize;
                if star_of_root[r] == NONE {
                    star_of_root[r] = n_stars;
                    n_stars += 1;
                }
                s[k] = star_of_root[r];
            }
            joint_stars.push(s);
        }
        // Per triangle: its stars (the two end stars of each of its joints; at most three).
        let n_tris = tris.iter().flatten().max().map_or(0, |m| *m as usize + 1);
        let mut tri_stars = vec![[NONE; 3]; n_tris];
        for (t, s) in tris.iter().zip(&joint_stars) {
            for &tri in t {
                for &si in s {
                    let ts = &mut tri_stars[tri as usize];
                    if !ts.contains(&si)
                        && let Some(slot) = ts.iter_mut().find(|x| **x == NONE)
                    {
                        *slot = si;
                    }
                }
            }
        }
        // Per star: its triangles and its joints (compressed rows).
        let ns = n_stars as usize;
        let mut off = vec![0u32; ns + 1];
        for s in &joint_stars {
            off[s[0] as usize + 1] += 1;
            off[s[1] as usize + 1] += 1;
        }
        for i in 0..ns {
            off[i + 1] += off[i];
        }
        let mut cur = off.clone();
        let mut star_joints = vec![0u32; off[ns] as usize];
        for (j, s) in joint_stars.iter().enumerate() {
            for &si in s {
                star_joints[cur[si as usize] as usize] = j as u32;
                cur[si as usize] += 1;
            }
        }
        // Vertex pairs star by star, in parallel over fixed chunks of stars, concatenated in
        // star order (the list does not depend on the thread count).
        let (vertex_pairs, star_off): (Vec<Vec<VertexPair>>, Vec<Vec<u32>>) = (0..ns
            .div_ceil(STAR_CHUNK))
            .into_par_iter()
            .map(|c| {
                let (s0, s1) = (c * STAR_CHUNK, ((c + 1) * STAR_CHUNK).min(ns));
                // at most k(k+1)/2 - k pairs for a star of k joints (k + 1 triangles at most,
                // less the joints' own pairs): reserved, so the list is not reallocated
                let bound: usize = (s0..s1)
                    .map(|s| {
                        let k = (off[s + 1] - off[s]) as usize;
                        k * k.saturating_sub(1) / 2
                    })
                    .sum();
                let mut pairs = Vec::with_capacity(bound);
                let mut offs = Vec::with_capacity(s1 - s0 + 1);
                let mut star_tris: Vec<u32> = Vec::new();
                for s in s0..s1 {
                    offs.push(pairs.len() as u32);
                    let js = &star_joints[off[s] as usize..off[s + 1] as usize];
                    vertex_pairs_of_star(s as u32, js, tris, &mut star_tris, &mut pairs);
                }
                offs.push(pairs.len() as u32);
                (pairs, offs)
            })
            .unzip();
        Self {
            joint_tris: tris.to_vec(),
            joint_stars,
            vertex_pairs,
            star_off,
            tri_stars,
            star_intact: vec![true; ns],
            joint_released: vec![false; tris.len()],
            n_bonded: 0,
        }
    }

    /// Number of stars (original nodes touched by a joint).
    pub fn n_stars(&self) -> usize {
        self.star_intact.len()
    }

    /// Number of vertex-neighbour pairs (bonded while their star is intact).
    pub fn n_vertex_pairs(&self) -> usize {
        self.vertex_pairs.iter().map(Vec::len).sum()
    }

    /// Number of pairs in the bonded set now.
    pub fn n_bonded(&self) -> usize {
        self.n_bonded
    }

    /// What a run changes (a checkpoint saves it): per star, still intact; per joint, its own
    /// pair released; the number of bonded pairs. The rest is the reference topology, rebuilt
    /// from the joints.
    pub fn bond_flags(&self) -> (&[bool], &[bool], usize) {
        (&self.star_intact, &self.joint_released, self.n_bonded)
    }

    /// Sets what [`Self::bond_flags`] gave (a checkpoint's) on stars built from the same
    /// joints. Refused (nothing changed): flags of another length, a broken joint with an
    /// intact end star, or a count that is not that of the bonded set the flags give.
    pub fn set_bond_flags(
        &mut self,
        star_intact: Vec<bool>,
        joint_released: Vec<bool>,
        n_bonded: usize,
    ) -> Result<(), String> {
        let (ns, nj) = (self.star_intact.len(), self.joint_released.len());
        if star_intact.len() != ns || joint_released.len() != nj {
            return Err(format!(
                "{} stars and {} joints where the scene has {ns} and {nj}",
                star_intact.len(),
                joint_released.len()
            ));
        }
        if let Some(j) = (0..nj).find(|&j| {
            joint_released[j] && self.joint_stars[j].iter().any(|&s| star_intact[s as usize])
        }) {
            return Err(format!(
                "joint {j} is released but one of its stars is intact"
            ));
        }
        let old = (
            std::mem::replace(&mut self.star_intact, star_intact),
            std::mem::replace(&mut self.joint_released, joint_released),
        );
        let count = self.bonded().count();
        if count != n_bonded {
            (self.star_intact, self.joint_released) = old;
            return Err(format!(
                "{n_bonded} bonded pairs recorded, the flags give {count}"
            ));
        }
        self.n_bonded = n_bonded;
        Ok(())
    }

    /// True when an intact star other than `except` holds both triangles `a` and `b`.
    fn held_by_star(&self, a: u32, b: u32, except: u32) -> bool {
        let sb = &self.tri_stars[b as usize];
        self.tri_stars[a as usize]
            .iter()
            .any(|&s| s != NONE && s != except && sb.contains(&s) && self.star_intact[s as usize])
    }

    /// Joint `j` softened or broke (as the fracture stage uses it: damage > 0 at a point): the
    /// stars of its two end nodes stop bonding, for good. Appends to `released` the pairs
    /// that thereby leave the bonded set (each pair exactly once over the run: a vertex pair
    /// shared by another intact star stays until that one goes too) and returns true when a
    /// star was still bonding.
    pub fn release_stars(&mut self, j: usize, released: &mut Vec<[u32; 2]>) -> bool {
        let mut changed = false;
        for s in self.joint_stars[j] {
            if !std::mem::replace(&mut self.star_intact[s as usize], false) {
                continue;
            }
            changed = true;
            let (c, k) = (s as usize / STAR_CHUNK, s as usize % STAR_CHUNK);
            let (lo, hi) = (self.star_off[c][k], self.star_off[c][k + 1]);
            for i in lo as usize..hi as usize {
                let [a, b] = self.vertex_pairs[c][i].0;
                if !self.held_by_star(a, b, s) {
                    released.push([a, b]);
                    self.n_bonded -= 1;
                }
            }
        }
        changed
    }

    /// Joint `j` broke: its stars are released ([`Self::release_stars`]), and its own pair
    /// leaves the bonded set (appended to `released`, once; no intact star can hold it, its
    /// two common stars being the joint's own). Returns true when something was still
    /// bonding.
    pub fn break_joint(&mut self, j: usize, released: &mut Vec<[u32; 2]>) -> bool {
        let mut changed = self.release_stars(j, released);
        if !std::mem::replace(&mut self.joint_released[j], true) {
            changed = true;
            let [a, b] = self.joint_tris[j];
            if !self.held_by_star(a, b, NONE) {
                released.push([a.min(b), a.max(b)]);
                self.n_bonded -= 1;
            }
        }
        changed
    }

    /// Writes the bonded set into `out` (cleared first): the pairs of the joints not broken,
    /// then the vertex pairs of the intact stars. No pair appears twice. `O(joints + vertex
    /// pairs)`; the solver lists it once at set-up and then only releases pairs.
    pub fn pairs(&self, out: &mut Vec<[u32; 2]>) {
        out.clear();
        out.extend(self.bonded_joints());
        // The vertex pairs in parallel, in list order (rayon's extend keeps it).
        out.par_extend(
            self.vertex_pairs
                .par_iter()
                .flat_map_iter(|c| c.iter().filter_map(|vp| self.listed_vertex_pair(vp))),
        );
    }

    /// The pairs of the joints not broken.
    fn bonded_joints(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        self.joint_tris
            .iter()
            .zip(&self.joint_released)
            .filter(|(_, r)| !**r)
            .map(|(p, _)| *p)
    }

    /// A vertex pair of star `s` is listed once: by the first intact star that holds it.
    fn listed_vertex_pair(&self, &([a, b], s): &([u32; 2], u32)) -> Option<[u32; 2]> {
        let first = self.tri_stars[a as usize]
            .iter()
            .filter(|&&t| t != NONE && self.tri_stars[b as usize].contains(&t))
            .filter(|&&t| self.star_intact[t as usize])
            .min();
        (first == Some(&s)).then_some([a, b])
    }

    /// The bonded set, each pair once (see [`Self::pairs`]).
    fn bonded(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        self.bonded_joints().chain(
            self.vertex_pairs
                .iter()
                .flatten()
                .filter_map(|vp| self.listed_vertex_pair(vp)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings};
    use fdem_mesh::{Exploded, Mesh, explode};
    use std::collections::BTreeSet;

    /// A structured `n x n` square mesh of side 1 (two triangles per cell, diagonals alternating).
    fn square(n: usize) -> Mesh {
        let mut nodes = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                nodes.push([i as f64 / n as f64, j as f64 / n as f64]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 2 == 0 {
                    tris.push([a, b, c]);
                    tris.push([a, c, d]);
                } else {
                    tris.push([a, b, d]);
                    tris.push([b, c, d]);
                }
            }
        }
        Mesh::from_nodes_triangles(nodes, tris).expect("valid mesh")
    }

    /// The bonded set from its definition, with the explode's map to the original nodes:
    /// the pairs of the joints not `broken`, and every pair around an original node none of
    /// whose joints is `broken` or `softened`.
    fn brute_force(
        tris: &[[u32; 3]],
        original: &[u32],
        jn: &[[u32; 4]],
        jt: &[[u32; 2]],
        broken: &[bool],
        softened: &[bool],
    ) -> BTreeSet<[u32; 2]> {
        let n_orig = original.iter().max().map_or(0, |m| *m as usize + 1);
        let mut star_ok = vec![true; n_orig];
        for (j, n) in jn.iter().enumerate() {
            if broken[j] || softened[j] {
                star_ok[original[n[0] as usize] as usize] = false;
                star_ok[original[n[1] as usize] as usize] = false;
            }
        }
        let mut out = BTreeSet::new();
        for (j, p) in jt.iter().enumerate() {
            if !broken[j] {
                out.insert([p[0].min(p[1]), p[0].max(p[1])]);
            }
        }
        for a in 0..tris.len() {
            for b in a + 1..tris.len() {
                let shared = tris[a].iter().any(|&na| {
                    let oa = original[na as usize];
                    star_ok[oa as usize] && tris[b].iter().any(|&nb| original[nb as usize] == oa)
                });
                if shared {
                    out.insert([a as u32, b as u32]);
                }
            }
        }
        out
    }

    /// The joints' node quadruples and triangle pairs of an exploded mesh, as plain ids.
    fn joint_arrays(ex: &Exploded) -> (Vec<[u32; 4]>, Vec<[u32; 2]>) {
        let jn = ex
            .internal_edges
            .iter()
            .map(|e| e.nodes.map(|n| n.0))
            .collect();
        let jt = ex
            .internal_edges
            .iter()
            .map(|e| e.tris.map(|t| t.0))
            .collect();
        (jn, jt)
    }

    fn as_set(pairs: &[[u32; 2]]) -> BTreeSet<[u32; 2]> {
        pairs
            .iter()
            .map(|p| [p[0].min(p[1]), p[0].max(p[1])])
            .collect()
    }

    #[test]
    fn released_pairs_keep_the_bonded_set_equal_to_brute_force() {
        let mesh = square(5);
        let ex = explode(&mesh, None).expect("explode");
        let (jn, jt) = joint_arrays(&ex);
        let original: Vec<u32> = ex.original_node.iter().map(|n| n.0).collect();
        let tris = &ex.mesh.triangles;
        let mut sb = StarBonds::new(&jn, &jt, ex.mesh.nodes.len());
        // One star per original node touched by a joint (all but the two corners (1, 0) and
        // (0, 1), whose single triangle has no diagonal there).
        let touched: BTreeSet<u32> = jn
            .iter()
            .flat_map(|n| [original[n[0] as usize], original[n[1] as usize]])
            .collect();
        assert_eq!(touched.len(), mesh.nodes.len() - 2);
        assert_eq!(sb.n_stars(), touched.len(), "one star per original node");
        let (mut broken, mut softened) = (vec![false; jn.len()], vec![false; jn.len()]);
        let mut out = Vec::new();
        sb.pairs(&mut out);
        // The set the contact stage holds: the initial list minus every released pair.
        let mut held = as_set(&out);
        assert_eq!(held.len(), out.len(), "a pair listed twice");
        assert_eq!(sb.n_bonded(), out.len());
        // The set-up's one-pass constructor lists the same pairs in the same order.
        let mut listed = Vec::new();
        let sb2 = StarBonds::with_pairs(&jn, &jt, ex.mesh.nodes.len(), &mut listed);
        assert_eq!(listed, out);
        assert_eq!(sb2.n_bonded(), sb.n_bonded());
        // Events in a fixed scrambled order, checked after each batch of 1, 2, 3, ... events;
        // every third event breaks its joint, the others soften it (a softened joint may
        // break later: the order visits each joint twice).
        let n = jn.len();
        let order: Vec<usize> = (0..2 * n).map(|k| (k * 37 + 11) % n).collect();
        let (mut k, mut batch, mut checked, mut n_released) = (0, 1, 0, 0);
        let mut released = Vec::new();
        while k < order.len() {
            released.clear();
            for (e, &j) in order[k..(k + batch).min(order.len())].iter().enumerate() {
                if (k + e) % 3 == 0 {
                    broken[j] = true;
                    let _ = sb.break_joint(j, &mut released);
                } else {
                    softened[j] = true;
                    let _ = sb.release_stars(j, &mut released);
                }
            }
            for p in &released {
                assert!(p[0] < p[1], "{p:?} not ordered");
                assert!(held.remove(p), "{p:?} released but not bonded (or twice)");
            }
            n_released += released.len();
            let want = brute_force(tris, &original, &jn, &jt, &broken, &softened);
            assert_eq!(held, want, "incremental set after {k} events");
            sb.pairs(&mut out);
            assert_eq!(as_set(&out), want, "full listing after {k} events");
            assert_eq!(out.len(), want.len(), "a pair listed twice");
            assert_eq!(sb.n_bonded(), want.len());
            checked += 1;
            k += batch;
            batch += 1;
        }
        for j in 0..n {
            released.clear();
            let _ = sb.break_joint(j, &mut released);
            for p in &released {
                assert!(held.remove(p), "{p:?} released but not bonded (or twice)");
            }
            n_released += released.len();
        }
        sb.pairs(&mut out);
        assert!(out.is_empty(), "all joints broken: nothing bonded");
        assert!(held.is_empty() && sb.n_bonded() == 0);
        assert!(checked >= 12, "only {checked} states checked");
        assert!(n_released > 150, "only {n_released} pairs released");
    }

    /// The flags of stars part-way through a run, set on stars built afresh from the same
    /// joints, give the same bonded set and count, and the same released pairs in the same
    /// order for every later event; flags that do not fit are refused and change nothing.
    #[test]
    fn bond_flags_set_on_fresh_stars_continue_the_releases_identically() {
        let mesh = square(6);
        let ex = explode(&mesh, None).expect("explode");
        let (jn, jt) = joint_arrays(&ex);
        let n_nodes = ex.mesh.nodes.len();
        let mut sb = StarBonds::new(&jn, &jt, n_nodes);
        let n = jn.len();
        let mut released = Vec::new();
        for k in 0..n / 4 {
            let j = (k * 29 + 5) % n;
            if k % 3 == 0 {
                sb.break_joint(j, &mut released);
            } else {
                sb.release_stars(j, &mut released);
            }
        }
        let (si, jr, nb) = sb.bond_flags();
        let (si, jr) = (si.to_vec(), jr.to_vec());
        assert!(nb > 0 && !released.is_empty());
        let mut fresh = StarBonds::new(&jn, &jt, n_nodes);
        let before = fresh.n_bonded();
        let mut bad = jr.clone();
        bad.pop();
        assert!(fresh.set_bond_flags(si.clone(), bad, nb).is_err());
        let e = fresh
            .set_bond_flags(si.clone(), jr.clone(), nb + 1)
            .unwrap_err();
        assert!(e.contains("bonded pairs recorded"), "{e}");
        let (si0, jr0, nb0) = fresh.bond_flags();
        assert!(si0.iter().all(|&b| b) && !jr0.iter().any(|&b| b) && nb0 == before);
        fresh.set_bond_flags(si, jr, nb).unwrap();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        sb.pairs(&mut a);
        fresh.pairs(&mut b);
        assert_eq!(a, b);
        assert_eq!(fresh.n_bonded(), sb.n_bonded());
        let (mut ra, mut rb) = (Vec::new(), Vec::new());
        for k in 0..n {
            let j = (k * 17 + 3) % n;
            if k % 2 == 0 {
                sb.break_joint(j, &mut ra);
                fresh.break_joint(j, &mut rb);
            } else {
                sb.release_stars(j, &mut ra);
                fresh.release_stars(j, &mut rb);
            }
        }
        // 75 pairs measured
        assert!(ra.len() > 50, "only {} pairs released", ra.len());
        assert_eq!(ra, rb, "released pairs or their order differ");
        assert_eq!(fresh.n_bonded(), sb.n_bonded());
    }

    #[test]
    fn parallel_set_up_lists_the_serial_pairs_on_1_and_2_threads() {
        // 60 x 60 cells: 7 200 triangles, about 3 600 stars (two chunks of stars) and tens of
        // thousands of vertex pairs (several listing chunks).
        let mesh = square(60);
        let ex = explode(&mesh, None).expect("explode");
        let (jn, jt) = joint_arrays(&ex);
        let n_nodes = ex.mesh.nodes.len();
        let mut lists = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = Vec::new();
            let sb = pool.install(|| StarBonds::with_pairs(&jn, &jt, n_nodes, &mut out));
            lists.push((sb, out));
        }
        let (sb, out) = &lists[0];
        assert!(
            sb.n_stars() > STAR_CHUNK,
            "{} stars: one chunk",
            sb.n_stars()
        );
        assert!(out.len() > 20_000, "{} pairs", out.len());
        assert_eq!(lists[1].1, *out, "1 and 2 threads list different pairs");
        assert_eq!(lists[1].0.vertex_pairs, sb.vertex_pairs);
        assert_eq!(lists[1].0.star_off, sb.star_off);
        // The serial algorithm: stars one after the other, then the serial listing.
        let mut want = Vec::new();
        let mut star_off = Vec::new();
        let mut scratch = Vec::new();
        let joints_of = |s: usize| -> Vec<u32> {
            (0..jn.len() as u32)
                .filter(|&j| sb.joint_stars[j as usize].contains(&(s as u32)))
                .collect()
        };
        for s in 0..sb.n_stars() {
            star_off.push(want.len() as u32);
            vertex_pairs_of_star(s as u32, &joints_of(s), &jt, &mut scratch, &mut want);
        }
        star_off.push(want.len() as u32);
        let global_off = |sb: &StarBonds| -> Vec<u32> {
            let mut off = Vec::new();
            let mut base = 0;
            for (c, o) in sb.star_off.iter().enumerate() {
                off.extend(o[..o.len() - 1].iter().map(|x| base + x));
                base += sb.vertex_pairs[c].len() as u32;
            }
            off.push(base);
            off
        };
        assert_eq!(
            sb.vertex_pairs.concat(),
            want,
            "vertex pairs differ from the serial build"
        );
        assert_eq!(global_off(sb), star_off);
        let serial: Vec<[u32; 2]> = sb.bonded().collect();
        assert_eq!(*out, serial, "parallel listing differs from the serial one");
        // and the set is the definition's
        let original: Vec<u32> = ex.original_node.iter().map(|n| n.0).collect();
        let none = vec![false; jn.len()];
        let brute = brute_force(&ex.mesh.triangles, &original, &jn, &jt, &none, &none);
        assert_eq!(as_set(out), brute);
        assert_eq!(out.len(), brute.len(), "a pair listed twice");
    }

    #[test]
    fn vertex_neighbours_at_a_star_with_a_broken_joint_are_detected() {
        // Two triangles sharing only original node 4 (the centre of a 2 x 2 square): T(a) in the
        // lower-left cell and T(b) in the upper-right cell; pushed through each other they
        // overlap. Bonded while the centre's star is intact: no couple; after one joint of that
        // star breaks (any of its 8 joints; not between a and b): a couple.
        let mesh = square(2);
        let ex = explode(&mesh, None).expect("explode");
        let (jn, jt) = joint_arrays(&ex);
        let tris = ex.mesh.triangles.clone();
        let orig = |n: u32| ex.original_node[n as usize].0;
        // Triangles 0..2 are cell (0,0), 6..8 cell (1,1); both have a vertex at node 4.
        let a = (0..2u32)
            .find(|&t| tris[t as usize].iter().any(|&n| orig(n) == 4))
            .expect("lower-left triangle at the centre");
        let b = (6..8u32)
            .find(|&t| tris[t as usize].iter().any(|&n| orig(n) == 4))
            .expect("upper-right triangle at the centre");
        let mut x = ex.mesh.nodes.clone();
        for &n in &tris[b as usize] {
            x[n as usize][0] -= 0.3;
            x[n as usize][1] -= 0.3;
        }
        let mut sb = StarBonds::new(&jn, &jt, x.len());
        let mut out = Vec::new();
        sb.pairs(&mut out);
        let mut c = Contact::new(
            ContactSettings::default(),
            ContactLaws::uniform(1, ContactLaw::with_penalty(1e9)),
        );
        c.set_bonded(tris.len(), &out);
        c.detect(&x, &tris);
        let has = |c: &Contact| {
            c.couples()
                .iter()
                .any(|p| (p[0] == a && p[1] == b) || (p[0] == b && p[1] == a))
        };
        assert!(!has(&c), "intact star: (a, b) bonded");
        let j = (0..jn.len())
            .find(|&j| orig(jn[j][0]) == 4 && !jt[j].contains(&a) && !jt[j].contains(&b))
            .expect("a joint of the centre's star away from a and b");
        let mut released = Vec::new();
        assert!(
            sb.break_joint(j, &mut released),
            "the centre's star was bonding"
        );
        assert!(released.contains(&[a.min(b), a.max(b)]), "(a, b) released");
        // Released without a re-detection: (a, b) overlaps, so it is a couple at once.
        let n_det = c.n_detections();
        c.release_pairs(&released, &tris);
        assert!(has(&c), "broken star: (a, b) must be a contact couple");
        assert_eq!(c.n_detections(), n_det, "no re-detection");
        // A full detection with the full list of the new bonded set agrees.
        sb.pairs(&mut out);
        c.set_bonded(tris.len(), &out);
        c.detect(&x, &tris);
        assert!(has(&c), "broken star: (a, b) must be a contact couple");
    }
}
