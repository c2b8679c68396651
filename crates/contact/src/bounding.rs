//! Bounding circles of triangles (about the centroid) and the couple criterion shared by all
//! broad phases: keep (i, j) if `|c_i - c_j| <= r_i + r_j + b`.

use rayon::prelude::*;

use crate::geom::{V2, centroid, finite, norm, sub};

/// Bounding circle of every triangle: centroid `c` and radius `r = max |x_vertex - c|`.
/// Triangles with a non-finite vertex get `r = NaN` and are never paired.
#[derive(Clone, Debug, Default)]
pub struct BoundingCircles {
    /// Centroids.
    pub c: Vec<V2>,
    /// Radii.
    pub r: Vec<f64>,
}

impl BoundingCircles {
    /// Recomputes the circles for positions `x` and triangles `tris` (no allocation once
    /// warm; in parallel above 8 192 triangles, each circle from its own triangle only: the
    /// same values for any number of threads).
    pub fn update(&mut self, x: &[V2], tris: &[[u32; 3]]) {
        let circle = |((c, r), t): ((&mut V2, &mut f64), &[u32; 3])| {
            let v = [x[t[0] as usize], x[t[1] as usize], x[t[2] as usize]];
            let cc = centroid(&v);
            let rr = norm(sub(v[0], cc))
                .max(norm(sub(v[1], cc)))
                .max(norm(sub(v[2], cc)));
            let ok = finite(cc) && rr.is_finite();
            *c = cc;
            *r = if ok { rr } else { f64::NAN };
        };
        self.c.resize(tris.len(), [0.0; 2]);
        self.r.resize(tris.len(), 0.0);
        if tris.len() < 8192 {
            self.c
                .iter_mut()
                .zip(self.r.iter_mut())
                .zip(tris)
                .for_each(circle);
        } else {
            self.c
                .par_iter_mut()
                .zip(self.r.par_iter_mut())
                .zip(tris.par_iter())
                .with_min_len(2048)
                .for_each(circle);
        }
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.c.len()
    }

    /// True when there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.c.is_empty()
    }

    /// Whether triangles i and j are a candidate couple with buffer `b`
    /// (false if either is non-finite).
    #[inline(always)]
    pub fn near(&self, i: usize, j: usize, b: f64) -> bool {
        let d = sub(self.c[i], self.c[j]);
        let s = self.r[i] + self.r[j] + b;
        d[0] * d[0] + d[1] * d[1] <= s * s
    }
}

/// Sorts couples `(i < j)` lexicographically in O(N + K) (counting sort on `i`, then the short
/// runs on `j`), reusing `count` and `tmp` as scratch.
pub(crate) fn sort_couples(
    n: usize,
    out: &mut [[u32; 2]],
    count: &mut Vec<u32>,
    tmp: &mut Vec<[u32; 2]>,
) {
    count.clear();
    count.resize(n + 1, 0);
    for p in out.iter() {
        count[p[0] as usize + 1] += 1;
    }
    for i in 0..n {
        count[i + 1] += count[i];
    }
    tmp.clear();
    tmp.resize(out.len(), [0, 0]);
    for p in out.iter() {
        let c = &mut count[p[0] as usize];
        tmp[*c as usize] = *p;
        *c += 1;
    }
    // count[i] is now the end of run i; runs are short: insertion sort each by j.
    let mut start = 0usize;
    for i in 0..n {
        let end = count[i] as usize;
        let run = &mut tmp[start..end];
        for a in 1..run.len() {
            let mut b = a;
            while b > 0 && run[b - 1][1] > run[b][1] {
                run.swap(b - 1, b);
                b -= 1;
            }
        }
        start = end;
    }
    out.copy_from_slice(tmp);
}

/// All couples by the O(N^2) test (the reference for the broad phases), sorted, excluding
/// pairs for which `excluded(i, j)` is true.
pub fn brute_force_couples(
    circles: &BoundingCircles,
    b: f64,
    mut excluded: impl FnMut(u32, u32) -> bool,
) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    let n = circles.len();
    for i in 0..n {
        for j in i + 1..n {
            if circles.near(i, j, b) && !excluded(i as u32, j as u32) {
                out.push([i as u32, j as u32]);
            }
        }
    }
    out
}
