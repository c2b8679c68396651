//! NBS (no binary search) contact detection (Munjiza & Andrews 1998; Munjiza 2004 ch. 3).
//!
//! 1. Bounding circle per triangle (centroid `c_e`, radius `r_e`), see [`BoundingCircles`].
//! 2. Cell size `d = 2 max r_e + b` (buffer `b >= 0`), recomputed at each detection.
//! 3. Each triangle lies in exactly one cell `(floor((x_c - x_min)/d), floor((y_c - y_min)/d))`.
//! 4. Singly linked lists: one head per row and a `next` array over elements.
//! 5. Sweep the rows keeping column lists only for rows `iy` and `iy - 1`; test each element
//!    against the mask `(ix,iy) (ix-1,iy) (ix-1,iy-1) (ix,iy-1) (ix+1,iy-1)`, in its own cell
//!    only against the elements after it in the list. Every pair is found once; only the
//!    column heads that were used are reset.
//! 6. Keep `(i, j)` if `|c_i - c_j| <= r_i + r_j + b` and the pair is not excluded.
//!
//! Cost O(N) time and O(N + n_x + n_y) memory. If the domain is so sparse that `n_x` or `n_y`
//! would exceed `4 N + 1024`, `d` is enlarged to cap them (still correct: any `d` at least
//! `2 max r + b` is). Triangles with non-finite vertices are skipped.

use crate::bounding::{BoundingCircles, sort_couples};
use crate::exclusions::Exclusions;

const NIL: u32 = u32::MAX;

/// Scratch memory of the NBS search (kept between detections: no allocation once warm).
#[derive(Clone, Debug, Default)]
pub struct Nbs {
    row_head: Vec<u32>,
    next_row: Vec<u32>,
    next_col: Vec<u32>,
    col_cur: Vec<u32>,
    col_prev: Vec<u32>,
    cell_x: Vec<u32>,
    cell_y: Vec<u32>,
    count: Vec<u32>,
    tmp: Vec<[u32; 2]>,
}

impl Nbs {
    /// Empty scratch.
    pub fn new() -> Self {
        Self::default()
    }

    /// Finds all couples `(i < j)` with `|c_i - c_j| <= r_i + r_j + b` that are not excluded,
    /// sorted lexicographically, into `out` (cleared first).
    pub fn find_couples(
        &mut self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        out: &mut Vec<[u32; 2]>,
    ) {
        out.clear();
        let n = circles.len();
        if n < 2 {
            return;
        }
        let b = if b.is_finite() { b.max(0.0) } else { 0.0 };
        // Bounds and largest radius over the finite elements.
        let (mut xmin, mut ymin, mut xmax, mut ymax, mut rmax) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
            0.0f64,
        );
        for e in 0..n {
            let r = circles.r[e];
            if r.is_nan() {
                continue;
            }
            let c = circles.c[e];
            xmin = xmin.min(c[0]);
            xmax = xmax.max(c[0]);
            ymin = ymin.min(c[1]);
            ymax = ymax.max(c[1]);
            rmax = rmax.max(r);
        }
        if xmin > xmax {
            return;
        }
        let mut d = 2.0 * rmax + b;
        if !(d > 0.0 && d.is_finite()) {
            d = 1.0;
        }
        let cap = (4 * n + 1024) as f64;
        let span = (xmax - xmin).max(ymax - ymin);
        if span / d > cap - 1.0 {
            d = span / (cap - 1.0);
        }
        let inv_d = 1.0 / d;
        let nx = ((xmax - xmin) * inv_d) as usize + 1;
        let ny = ((ymax - ymin) * inv_d) as usize + 1;

        self.row_head.clear();
        self.row_head.resize(ny, NIL);
        self.next_row.resize(n, NIL);
        self.next_col.resize(n, NIL);
        self.cell_x.resize(n, 0);
        self.cell_y.resize(n, 0);
        self.col_cur.clear();
        self.col_cur.resize(nx + 2, NIL);
        self.col_prev.clear();
        self.col_prev.resize(nx + 2, NIL);

        // Row lists (elements pushed in reverse order so each list runs in index order).
        for e in (0..n).rev() {
            if circles.r[e].is_nan() {
                continue;
            }
            let c = circles.c[e];
            let ix = (((c[0] - xmin) * inv_d) as usize).min(nx - 1);
            let iy = (((c[1] - ymin) * inv_d) as usize).min(ny - 1);
            // Column index shifted by one so that ix-1 and ix+1 are always valid.
            self.cell_x[e] = (ix + 1) as u32;
            self.cell_y[e] = iy as u32;
            self.next_row[e] = self.row_head[iy];
            self.row_head[iy] = e as u32;
        }

        let mut prev_head = NIL;
        for iy in 0..ny {
            let head = self.row_head[iy];
            if head == NIL && prev_head == NIL {
                continue;
            }
            // Column lists of this row (reverse push keeps index order not needed; any order).
            let mut e = head;
            while e != NIL {
                let ix = self.cell_x[e as usize] as usize;
                self.next_col[e as usize] = self.col_cur[ix];
                self.col_cur[ix] = e;
                e = self.next_row[e as usize];
            }
            let mut e = head;
            while e != NIL {
                let eu = e as usize;
                let ix = self.cell_x[eu] as usize;
                // Own cell: only later elements of the list.
                let mut j = self.next_col[eu];
                while j != NIL {
                    self.test(circles, b, tris, excl, e, j, out);
                    j = self.next_col[j as usize];
                }
                let mut j = self.col_cur[ix - 1];
                while j != NIL {
                    self.test(circles, b, tris, excl, e, j, out);
                    j = self.next_col[j as usize];
                }
                if prev_head != NIL {
                    for cx in [ix - 1, ix, ix + 1] {
                        let mut j = self.col_prev[cx];
                        while j != NIL {
                            self.test(circles, b, tris, excl, e, j, out);
                            j = self.next_col[j as usize];
                        }
                    }
                }
                e = self.next_row[eu];
            }
            // Reset the previous row's heads, then this row becomes the previous one.
            let mut e = prev_head;
            while e != NIL {
                self.col_prev[self.cell_x[e as usize] as usize] = NIL;
                e = self.next_row[e as usize];
            }
            std::mem::swap(&mut self.col_cur, &mut self.col_prev);
            prev_head = head;
        }
        // Leave the column heads clean for the next call.
        let mut e = prev_head;
        while e != NIL {
            self.col_prev[self.cell_x[e as usize] as usize] = NIL;
            e = self.next_row[e as usize];
        }
        sort_couples(n, out, &mut self.count, &mut self.tmp);
    }

    #[inline(always)]
    fn test(
        &self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        i: u32,
        j: u32,
        out: &mut Vec<[u32; 2]>,
    ) {
        if circles.near(i as usize, j as usize, b) && !excl.excluded(tris, i, j) {
            out.push(if i < j { [i, j] } else { [j, i] });
        }
    }
}
