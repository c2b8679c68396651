//! Recovered nodal stresses (`nodal_stress`, `nodal_principal_stress`, `nodal_von_mises`): a
//! continuous stress field from the constant stresses of the triangles, one value per node.
//!
//! **Patches.** The patch of a node is the set of triangles around its original vertex that
//! are of its material and connected to it without crossing a broken joint: the nodes are
//! joined in classes (an unexploded node is its own class; a joint `[P, Q, R, S]` that is
//! intact joins `P ~ S` and `Q ~ R`), and the patch of class `c` in material `m` is every
//! triangle of material `m` with a corner in `c`. A broken joint (and so a pre-existing
//! crack) joins nothing, so the two faces of a crack are separate patches down to the crack
//! tip; a material interface bounds every patch. A node where triangles of several materials
//! meet (an unexploded mesh with a material interface) takes the patch of the material with
//! the largest area around it: its value is that material's, never a mix.
//!
//! **Superconvergent patch recovery** ([`Method::Patch`], the default; Zienkiewicz and Zhu,
//! 1992): over the patch of an interior node, the least-squares linear fit
//! `s(x) = a + b . x` to the triangles' stresses at their centroids, evaluated at the node
//! (each of the four components fitted alike). A node on a boundary (of the body, of a
//! material region, or a crack face) takes the mean, at its position, of the fits of the
//! interior nodes of its patch (same class connectivity and material); where it has none (a
//! corner), the fit over its patch and its neighbours' patches, and where that is degenerate
//! (fewer than three triangles or centroids on a line) the area-weighted mean of its patch.
//!
//! **Lumped L2 projection** ([`Method::Average`]): the area-weighted mean of the patch.
//!
//! The fit is in the reference configuration (the triangles' reference centroids). One pass
//! per frame, parallel over the nodes, each node's value computed on its own in a fixed
//! order, so the result does not depend on the number of threads.

use rayon::prelude::*;

/// The joints of a fracturing scene: node ids `[P, Q, R, S]` and whether each is intact.
#[derive(Debug, Clone, Copy)]
pub struct Links<'a> {
    /// Node ids per joint.
    pub nodes: &'a [[u32; 4]],
    /// Per joint: not broken.
    pub intact: &'a [bool],
}

/// How the nodal values are recovered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Superconvergent patch recovery (linear least-squares fit over the patch).
    #[default]
    Patch,
    /// Lumped L2 projection: the area-weighted mean over the patch.
    Average,
    /// The linear fit of each node's own patch, boundary nodes included (for comparison).
    OwnPatch,
}

/// Neighbour classes a boundary node looks at, at most.
const MAX_NEIGHBOURS: usize = 64;

/// The patch structure of one frame.
struct Patches<'a> {
    /// Class (representative node) of each node.
    class: Vec<u32>,
    /// Triangles with a corner in class `c`: `tris[offsets[c]..offsets[c + 1]]`.
    offsets: Vec<u32>,
    tris: Vec<u32>,
    /// Material region per triangle.
    material: &'a [u32],
    /// Reference centroid and area per triangle.
    centroid: Vec<[f64; 2]>,
    area: Vec<f64>,
    x0: &'a [[f64; 2]],
    triangles: &'a [[u32; 3]],
    stress: &'a [[f64; 4]],
}

fn find(parent: &mut [u32], mut a: u32) -> u32 {
    while parent[a as usize] != a {
        let p = parent[a as usize];
        parent[a as usize] = parent[p as usize];
        a = p;
    }
    a
}

impl<'a> Patches<'a> {
    fn new(mesh: Mesh<'a>, stress: &'a [[f64; 4]], links: Option<Links>) -> Self {
        let Mesh {
            x0,
            triangles,
            material,
        } = mesh;
        let n = x0.len();
        let mut class: Vec<u32> = (0..n as u32).collect();
        if let Some(l) = links {
            for (j, nodes) in l.nodes.iter().enumerate() {
                if !l.intact.get(j).copied().unwrap_or(false) {
                    continue;
                }
                for (a, b) in [(nodes[0], nodes[3]), (nodes[1], nodes[2])] {
                    if (a as usize) >= n || (b as usize) >= n {
                        continue;
                    }
                    let (ra, rb) = (find(&mut class, a), find(&mut class, b));
                    if ra != rb {
                        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
                        class[hi as usize] = lo;
                    }
                }
            }
            for i in 0..n as u32 {
                let r = find(&mut class, i);
                class[i as usize] = r;
            }
        }
        // the triangles of each class (a triangle once per class), in increasing order
        let tri_classes = |t: &[u32; 3]| {
            let c = t.map(|k| class[k as usize]);
            [Some(c[0]), (c[1] != c[0]).then_some(c[1])]
                .into_iter()
                .chain([(c[2] != c[0] && c[2] != c[1]).then_some(c[2])])
                .flatten()
        };
        let mut offsets = vec![0u32; n + 1];
        for t in triangles {
            for c in tri_classes(t) {
                offsets[c as usize + 1] += 1;
            }
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut tris = vec![0u32; offsets[n] as usize];
        for (ti, t) in triangles.iter().enumerate() {
            for c in tri_classes(t) {
                tris[fill[c as usize] as usize] = ti as u32;
                fill[c as usize] += 1;
            }
        }
        let (centroid, area) = triangles
            .par_iter()
            .with_min_len(4096)
            .map(|t| {
                let [a, b, c] = t.map(|i| x0[i as usize]);
                let cen = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
                let ar = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
                (cen, ar.abs())
            })
            .unzip();
        Self {
            class,
            offsets,
            tris,
            material,
            centroid,
            area,
            x0,
            triangles,
            stress,
        }
    }

    /// The triangles of class `c` in material `m`.
    fn patch(&self, c: u32, m: u32) -> impl Iterator<Item = u32> + Clone + '_ {
        let (s, e) = (self.offsets[c as usize], self.offsets[c as usize + 1]);
        self.tris[s as usize..e as usize]
            .iter()
            .copied()
            .filter(move |&t| self.material[t as usize] == m)
    }

    /// The material of node `i`: that of the largest area among the triangles that have the
    /// node as a corner (the lowest id on a tie); `None` for a node of no triangle.
    fn node_material(&self, i: u32) -> Option<u32> {
        let c = self.class[i as usize];
        let (s, e) = (self.offsets[c as usize], self.offsets[c as usize + 1]);
        let own = &self.tris[s as usize..e as usize];
        let has = |t: u32| self.triangles[t as usize].contains(&i);
        let mut best: Option<(f64, u32)> = None;
        for &t in own.iter().filter(|&&t| has(t)) {
            let m = self.material[t as usize];
            let a: f64 = own
                .iter()
                .filter(|&&u| has(u) && self.material[u as usize] == m)
                .map(|&u| self.area[u as usize])
                .sum();
            best = match best {
                Some((ba, bm)) if ba > a || (ba == a && bm <= m) => Some((ba, bm)),
                _ => Some((a, m)),
            };
        }
        best.map(|(_, m)| m)
    }

    /// The area-weighted mean stress of `tris` (zero for none).
    fn average(&self, tris: impl Iterator<Item = u32>) -> [f64; 4] {
        let (mut sum, mut w) = ([0.0; 4], 0.0);
        for t in tris {
            let a = self.area[t as usize];
            for (s, v) in sum.iter_mut().zip(self.stress[t as usize]) {
                *s += a * v;
            }
            w += a;
        }
        if w > 0.0 { sum.map(|s| s / w) } else { sum }
    }

    /// The least-squares linear fit of the stresses at the centroids of `tris`, evaluated
    /// at `q`; `None` for fewer than three triangles or centroids (nearly) on a line.
    fn fit_at(&self, tris: impl Iterator<Item = u32> + Clone, q: [f64; 2]) -> Option<[f64; 4]> {
        let (mut n, mut mx, mut my, mut ms) = (0.0, 0.0, 0.0, [0.0; 4]);
        for t in tris.clone() {
            let c = self.centroid[t as usize];
            n += 1.0;
            mx += c[0] - q[0];
            my += c[1] - q[1];
            for (m, v) in ms.iter_mut().zip(self.stress[t as usize]) {
                *m += v;
            }
        }
        if n < 3.0 {
            return None;
        }
        let (mx, my, ms) = (mx / n, my / n, ms.map(|m| m / n));
        let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
        let (mut rx, mut ry) = ([0.0; 4], [0.0; 4]);
        for t in tris {
            let c = self.centroid[t as usize];
            let (dx, dy) = (c[0] - q[0] - mx, c[1] - q[1] - my);
            cxx += dx * dx;
            cxy += dx * dy;
            cyy += dy * dy;
            for k in 0..4 {
                let ds = self.stress[t as usize][k] - ms[k];
                rx[k] += dx * ds;
                ry[k] += dy * ds;
            }
        }
        let det = cxx * cyy - cxy * cxy;
        let tr = cxx + cyy;
        if det.is_nan() || det <= 1e-6 * tr * tr {
            return None;
        }
        // value at q: mean + gradient . (q - mean position), q - mean = (-mx, -my)
        let mut out = [0.0; 4];
        for k in 0..4 {
            let gx = (cyy * rx[k] - cxy * ry[k]) / det;
            let gy = (cxx * ry[k] - cxy * rx[k]) / det;
            out[k] = ms[k] - gx * mx - gy * my;
        }
        Some(out)
    }

    /// The classes of the other corners of the patch `(c, m)`, each once, in order of first
    /// appearance (at most [`MAX_NEIGHBOURS`]); and whether the patch closes around `c`
    /// (every such class is a corner of exactly two of its triangles).
    fn neighbours(&self, c: u32, m: u32, out: &mut [u32; MAX_NEIGHBOURS]) -> (usize, bool) {
        let mut k = 0;
        let mut interior = true;
        for t in self.patch(c, m) {
            for &node in &self.triangles[t as usize] {
                let nc = self.class[node as usize];
                if nc == c || out[..k].contains(&nc) {
                    continue;
                }
                let count = self
                    .patch(c, m)
                    .filter(|&u| {
                        (self.triangles[u as usize].iter()).any(|&x| self.class[x as usize] == nc)
                    })
                    .count();
                interior &= count == 2;
                if k < MAX_NEIGHBOURS {
                    out[k] = nc;
                    k += 1;
                }
            }
        }
        (k, interior && k > 0)
    }

    /// The recovered stress at node `i`, whose material is `material`
    /// ([`Patches::node_material`]).
    fn node_in(&self, i: u32, material: Option<u32>, method: Method) -> [f64; 4] {
        let Some(m) = material else {
            return [0.0; 4];
        };
        let c = self.class[i as usize];
        let q = self.x0[i as usize];
        let own = || {
            self.fit_at(self.patch(c, m), q)
                .unwrap_or_else(|| self.average(self.patch(c, m)))
        };
        match method {
            Method::Average => self.average(self.patch(c, m)),
            Method::OwnPatch => own(),
            Method::Patch => {
                let mut near = [0u32; MAX_NEIGHBOURS];
                let (k, interior) = self.neighbours(c, m, &mut near);
                if interior {
                    return own();
                }
                // the mean of the interior neighbours' fits, at q
                let mut scratch = [0u32; MAX_NEIGHBOURS];
                let (mut sum, mut count) = ([0.0; 4], 0.0);
                for &nc in &near[..k] {
                    if !self.neighbours(nc, m, &mut scratch).1 {
                        continue;
                    }
                    if let Some(v) = self.fit_at(self.patch(nc, m), q) {
                        for (s, x) in sum.iter_mut().zip(v) {
                            *s += x;
                        }
                        count += 1.0;
                    }
                }
                if count > 0.0 {
                    return sum.map(|s| s / count);
                }
                // no interior neighbour (a corner): the fit over the patches of the node and
                // of its neighbours, each triangle once
                let near = &near[..k];
                let touches = |t: u32, cs: &[u32]| {
                    (self.triangles[t as usize].iter())
                        .any(|&x| cs.contains(&self.class[x as usize]))
                };
                let wider =
                    self.patch(c, m)
                        .chain(near.iter().enumerate().flat_map(move |(ni, &nc)| {
                            self.patch(nc, m)
                                .filter(move |&t| !touches(t, &[c]) && !touches(t, &near[..ni]))
                        }));
                self.fit_at(wider, q).unwrap_or_else(own)
            }
        }
    }
}

/// The reference mesh the recovery works on.
#[derive(Debug, Clone, Copy)]
pub struct Mesh<'a> {
    /// Reference node positions.
    pub x0: &'a [[f64; 2]],
    /// Triangles (node ids).
    pub triangles: &'a [[u32; 3]],
    /// Material region per triangle (no patch holds two).
    pub material: &'a [u32],
}

/// The recovered stress `(sxx, syy, sxy, szz)` at every node of `mesh`, from the stresses
/// `stress` of its triangles, the patches cut by the broken joints of `links`; zeros when
/// the sizes disagree.
pub fn recover(
    mesh: Mesh,
    stress: &[[f64; 4]],
    links: Option<Links>,
    method: Method,
) -> Vec<[f64; 4]> {
    let n = mesh.x0.len();
    let n_tris = mesh.triangles.len();
    if stress.len() != n_tris
        || mesh.material.len() != n_tris
        || mesh.triangles.iter().flatten().any(|&k| k as usize >= n)
    {
        return vec![[0.0; 4]; n];
    }
    let p = Patches::new(mesh, stress, links);
    let material: Vec<Option<u32>> = (0..n as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| p.node_material(i))
        .collect();
    let leader = leaders(&p.class, &material, mesh.x0);
    let mut out: Vec<[f64; 4]> = (0..n as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            if leader[i as usize] == i {
                p.node_in(i, material[i as usize], method)
            } else {
                [0.0; 4]
            }
        })
        .collect();
    for i in 0..n {
        let l = leader[i] as usize;
        if l != i {
            out[i] = out[l];
        }
    }
    out
}

/// Per node, the first node of its class with the same material and the same reference
/// position (itself when there is none): such nodes (the copies of one vertex in an
/// exploded mesh, joined by intact joints) have the same patch and the same value, which is
/// then computed once.
fn leaders(class: &[u32], material: &[Option<u32>], x0: &[[f64; 2]]) -> Vec<u32> {
    let n = class.len();
    // the nodes of each class, in increasing order (CSR)
    let mut offsets = vec![0u32; n + 1];
    for &c in class {
        offsets[c as usize + 1] += 1;
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut members = vec![0u32; n];
    for (i, &c) in class.iter().enumerate() {
        members[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
    let same = |a: usize, b: usize| {
        material[a] == material[b]
            && x0[a][0].to_bits() == x0[b][0].to_bits()
            && x0[a][1].to_bits() == x0[b][1].to_bits()
    };
    let mut leader: Vec<u32> = (0..n as u32).collect();
    for c in 0..n {
        let m = &members[offsets[c] as usize..offsets[c + 1] as usize];
        for (k, &i) in m.iter().enumerate() {
            if let Some(&l) = m[..k].iter().find(|&&l| same(l as usize, i as usize)) {
                leader[i as usize] = leader[l as usize];
            }
        }
    }
    leader
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes, triangles and joints.
    type Grid = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[u32; 4]>);

    /// A structured `n` x `n` grid of the unit square, exploded (each triangle its own three
    /// nodes), with a joint on every interior edge: (nodes, triangles, joints).
    fn exploded_grid(n: usize) -> Grid {
        let v = |i: usize, j: usize| [i as f64 / n as f64, j as f64 / n as f64];
        let mut nodes = Vec::new();
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                for t in [
                    [v(i, j), v(i + 1, j), v(i + 1, j + 1)],
                    [v(i, j), v(i + 1, j + 1), v(i, j + 1)],
                ] {
                    let b = nodes.len() as u32;
                    nodes.extend(t);
                    tris.push([b, b + 1, b + 2]);
                }
            }
        }
        // joints: every pair of triangles sharing an edge (by position), P -> Q in T1 and
        // R -> S in T2 with P = S, Q = R
        let key = |p: [f64; 2]| {
            (
                (p[0] * n as f64).round() as i64,
                (p[1] * n as f64).round() as i64,
            )
        };
        let mut edges: std::collections::BTreeMap<_, (u32, u32)> = Default::default();
        let mut joints = Vec::new();
        for t in &tris {
            for k in 0..3 {
                let (p, q) = (t[k], t[(k + 1) % 3]);
                let (kp, kq) = (key(nodes[p as usize]), key(nodes[q as usize]));
                match edges.remove(&(kq, kp)) {
                    Some((r, s)) => joints.push([p, q, r, s]),
                    None => {
                        edges.insert((kp, kq), (p, q));
                    }
                }
            }
        }
        (nodes, tris, joints)
    }

    #[test]
    fn a_linear_stress_field_is_recovered_exactly_at_every_node() {
        // s = (1 + 2x - 3y, 4 - x + y, 0.5 x, 7): the fit is exact for it, interior,
        // boundary and corner nodes alike (to round-off: measured 8.9e-16); the area-weighted
        // mean is not (0.28 at a corner)
        let (nodes, tris, joints) = exploded_grid(6);
        let lin = |p: [f64; 2]| {
            [
                1.0 + 2.0 * p[0] - 3.0 * p[1],
                4.0 - p[0] + p[1],
                0.5 * p[0],
                7.0,
            ]
        };
        let stress: Vec<[f64; 4]> = tris
            .iter()
            .map(|t| {
                let c = t.iter().fold([0.0; 2], |a, &i| {
                    [
                        a[0] + nodes[i as usize][0] / 3.0,
                        a[1] + nodes[i as usize][1] / 3.0,
                    ]
                });
                lin(c)
            })
            .collect();
        let material = vec![0u32; tris.len()];
        let intact = vec![true; joints.len()];
        let mesh = Mesh {
            x0: &nodes,
            triangles: &tris,
            material: &material,
        };
        let links = Links {
            nodes: &joints,
            intact: &intact,
        };
        let worst = |m: Method| {
            let r = recover(mesh, &stress, Some(links), m);
            (r.iter().zip(&nodes))
                .flat_map(|(s, p)| (0..4).map(move |k| (s[k] - lin(*p)[k]).abs()))
                .fold(0.0, f64::max)
        };
        let (fit, mean) = (worst(Method::Patch), worst(Method::Average));
        eprintln!("linear field: largest nodal error {fit:.1e} (patch fit), {mean:.3} (mean)");
        assert!(fit < 1e-12, "{fit}");
        assert!(mean > 0.1, "{mean}");
        fdem_figures::record_part(
            100,
            1,
            format!(
                "{} (the area-weighted mean: {mean:.2})",
                fdem_figures::sci(fit, 1)
            ),
        );
    }

    #[test]
    fn no_patch_crosses_a_material_interface() {
        // an unexploded 8 x 8 grid, material 0 left of x = 1/2 with the stress A, material 1
        // right of it with B: every node reads A or B exactly, its own side's; the nodes on
        // the interface read the material with the larger area around them: material 0's A
        // inside (three triangles of each, a tie) and at the top end (two of material 0),
        // B at the bottom end (two of material 1)
        let n = 8;
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let nodes: Vec<[f64; 2]> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64 / n as f64, j as f64 / n as f64]))
            .collect();
        let mut tris = Vec::new();
        let mut material = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                material.extend([u32::from(i >= n / 2); 2]);
            }
        }
        let (a, b) = ([1.0, 2.0, 3.0, 4.0], [-5.0, 6.0, -7.0, 8.0]);
        let stress: Vec<[f64; 4]> = material
            .iter()
            .map(|&m| if m == 0 { a } else { b })
            .collect();
        let mesh = Mesh {
            x0: &nodes,
            triangles: &tris,
            material: &material,
        };
        let mut largest: f64 = 0.0;
        for method in [Method::Patch, Method::Average, Method::OwnPatch] {
            let r = recover(mesh, &stress, None, method);
            for (s, p) in r.iter().zip(&nodes) {
                let off = |w: [f64; 4]| (0..4).map(|k| (s[k] - w[k]).abs()).fold(0.0, f64::max);
                let worst = if p[0] < 0.5 {
                    off(a)
                } else if p[0] > 0.5 {
                    off(b)
                } else if p[1] == 0.0 {
                    // the bottom end: two triangles of material 1, one of material 0
                    off(b)
                } else {
                    off(a)
                };
                assert!(worst < 1e-12, "{method:?} at {p:?}: {s:?}");
                largest = largest.max(worst);
            }
        }
        let text = if largest == 0.0 {
            "exact".to_string()
        } else {
            fdem_figures::sci(largest, 1)
        };
        fdem_figures::record_part(100, 2, text);
    }

    #[test]
    fn the_recovery_is_the_same_bits_on_any_number_of_threads() {
        let (nodes, tris, joints) = exploded_grid(40);
        let stress: Vec<[f64; 4]> = (0..tris.len())
            .map(|t| {
                let x = t as f64;
                [
                    (x * 0.37).sin(),
                    (x * 0.11).cos(),
                    x.sqrt(),
                    1.0 / (1.0 + x),
                ]
            })
            .collect();
        let material: Vec<u32> = (0..tris.len() as u32)
            .map(|t| u32::from(t % 7 == 0))
            .collect();
        let intact: Vec<bool> = (0..joints.len()).map(|j| j % 5 != 0).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mesh = Mesh {
                    x0: &nodes,
                    triangles: &tris,
                    material: &material,
                };
                let links = Links {
                    nodes: &joints,
                    intact: &intact,
                };
                recover(mesh, &stress, Some(links), Method::Patch)
            })
        };
        let one = run(1);
        assert!(one.len() == nodes.len() && one.iter().flatten().all(|v| v.is_finite()));
        let bits =
            |r: &[[f64; 4]]| -> Vec<u64> { r.iter().flatten().map(|v| v.to_bits()).collect() };
        assert_eq!(bits(&one), bits(&run(2)));
        assert_eq!(bits(&one), bits(&run(3)));
        fdem_figures::record_part(100, 3, "identical on 1, 2 and 3 threads");
    }
}
