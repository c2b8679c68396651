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
//! Parallel form (same couples, same order): the elements are sorted into rows (counting
//! sort, index order within a row), the rows are cut into bands of about equal element
//! counts (the cut depends on the data only, never on the thread count), and each band runs
//! the sweep above over its rows in parallel, with its own column heads and lists, starting
//! from the column lists of the row below its first one (the pairs between that row and the
//! band's first row are the first row's mask entries `(., iy - 1)`). Every pair is tested in
//! exactly one band, by the same criterion as the serial sweep; the bands' couples are
//! concatenated in band order and sorted, so the list is the serial one whatever the number
//! of threads ([`Nbs::find_couples_serial`] is the one-band sweep, kept as the reference).
//!
//! Cost O(N) time and O(N + n_x + n_y) memory. If the domain is so sparse that `n_x` or `n_y`
//! would exceed `4 N + 1024`, `d` is enlarged to cap them (still correct: any `d` at least
//! `2 max r + b` is). Triangles with non-finite vertices are skipped.

use rayon::prelude::*;

use crate::bounding::{BoundingCircles, sort_couples};
use crate::exclusions::Exclusions;

const NIL: u32 = u32::MAX;

/// Below this many elements the sweep runs as one band on the calling thread.
const PAR_MIN_ELEMS: usize = 8192;
/// Elements per band (about) above [`PAR_MIN_ELEMS`].
const BAND_ELEMS: usize = 4096;
/// Most bands (each holds two column-head arrays of `n_x + 2` entries).
const MAX_BANDS: usize = 64;

/// Scratch of one band of rows.
#[derive(Clone, Debug, Default)]
struct Band {
    /// Rows `rows[0]..rows[1]` are swept by this band.
    rows: [usize; 2],
    col_cur: Vec<u32>,
    col_prev: Vec<u32>,
    /// Per row slot (from the first slot of the row below the band): next slot in its
    /// column list.
    next: Vec<u32>,
    out: Vec<[u32; 2]>,
}

/// Scratch memory of the NBS search (kept between detections: no allocation once warm).
#[derive(Clone, Debug, Default)]
pub struct Nbs {
    /// Per element: column + 1 (so that `ix - 1` and `ix + 1` are valid) and row; `NIL` row
    /// for a non-finite element.
    cell: Vec<[u32; 2]>,
    /// Row `iy` holds slots `row_start[iy]..row_start[iy + 1]` of `slot_elem`/`slot_col`.
    row_start: Vec<u32>,
    slot_elem: Vec<u32>,
    slot_col: Vec<u32>,
    bands: Vec<Band>,
    count: Vec<u32>,
    tmp: Vec<[u32; 2]>,
}

/// The elements sorted into rows (read by every band).
struct Slots<'a> {
    row_start: &'a [u32],
    elem: &'a [u32],
    col: &'a [u32],
    circles: &'a BoundingCircles,
}

/// The grid of one search: origin, inverse cell size and cell counts.
#[derive(Clone, Copy)]
struct Grid {
    xmin: f64,
    ymin: f64,
    inv_d: f64,
    nx: usize,
    ny: usize,
}

impl Nbs {
    /// Empty scratch.
    pub fn new() -> Self {
        Self::default()
    }

    /// Finds all couples `(i < j)` with `|c_i - c_j| <= r_i + r_j + b` that are not excluded,
    /// sorted lexicographically, into `out` (cleared first). Bands of rows in parallel above
    /// 8 192 elements (module docs): the same list as [`Self::find_couples_serial`] for any
    /// number of threads.
    pub fn find_couples(
        &mut self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        out: &mut Vec<[u32; 2]>,
    ) {
        let n_bands = if circles.len() < PAR_MIN_ELEMS {
            1
        } else {
            (circles.len() / BAND_ELEMS).clamp(1, MAX_BANDS)
        };
        self.search(circles, b, tris, excl, out, n_bands);
    }

    /// The serial sweep (one band on the calling thread): the reference of
    /// [`Self::find_couples`], same arguments and result.
    pub fn find_couples_serial(
        &mut self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        out: &mut Vec<[u32; 2]>,
    ) {
        self.search(circles, b, tris, excl, out, 1);
    }

    fn search(
        &mut self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        out: &mut Vec<[u32; 2]>,
        n_bands: usize,
    ) {
        out.clear();
        let n = circles.len();
        if n < 2 {
            return;
        }
        let b = if b.is_finite() { b.max(0.0) } else { 0.0 };
        let Some(g) = grid(circles, b) else {
            return;
        };
        self.sort_into_rows(circles, g);

        // Bands of about equal element counts (cut by the data only).
        let per_band = n.div_ceil(n_bands).max(1);
        self.bands
            .resize_with(n_bands.max(self.bands.len()), Band::default);
        let mut r0 = 0usize;
        for (k, band) in self.bands.iter_mut().take(n_bands).enumerate() {
            let target = (k + 1) * per_band;
            let mut r1 = r0;
            while r1 < g.ny && (self.row_start[r1] as usize) < target {
                r1 += 1;
            }
            if k + 1 == n_bands {
                r1 = g.ny;
            }
            band.rows = [r0, r1];
            r0 = r1;
        }
        let slots = Slots {
            row_start: &self.row_start,
            elem: &self.slot_elem,
            col: &self.slot_col,
            circles,
        };
        let sweep = |band: &mut Band| sweep_band(band, g, &slots, b, tris, excl);
        let bands = &mut self.bands[..n_bands];
        if n_bands == 1 {
            sweep(&mut bands[0]);
        } else {
            bands.par_iter_mut().for_each(sweep);
        }
        for band in bands.iter() {
            out.extend_from_slice(&band.out);
        }
        sort_couples(n, out, &mut self.count, &mut self.tmp);
    }

    /// Cells of the elements, then the elements by row (counting sort: index order within a
    /// row), with their columns alongside.
    fn sort_into_rows(&mut self, circles: &BoundingCircles, g: Grid) {
        let n = circles.len();
        self.cell.resize(n, [0, NIL]);
        let cell_of = |(e, cell): (usize, &mut [u32; 2])| {
            *cell = if circles.r[e].is_nan() {
                [0, NIL]
            } else {
                let c = circles.c[e];
                let ix = (((c[0] - g.xmin) * g.inv_d) as usize).min(g.nx - 1);
                let iy = (((c[1] - g.ymin) * g.inv_d) as usize).min(g.ny - 1);
                [(ix + 1) as u32, iy as u32]
            };
        };
        if n < PAR_MIN_ELEMS {
            self.cell.iter_mut().enumerate().for_each(cell_of);
        } else {
            self.cell
                .par_iter_mut()
                .enumerate()
                .with_min_len(4096)
                .for_each(cell_of);
        }
        self.row_start.clear();
        self.row_start.resize(g.ny + 1, 0);
        for c in &self.cell {
            if c[1] != NIL {
                self.row_start[c[1] as usize + 1] += 1;
            }
        }
        for iy in 0..g.ny {
            self.row_start[iy + 1] += self.row_start[iy];
        }
        let placed = self.row_start[g.ny] as usize;
        self.slot_elem.resize(placed, 0);
        self.slot_col.resize(placed, 0);
        // row_start[iy] is the cursor of row iy while filling; shifted back afterwards.
        for (e, c) in self.cell.iter().enumerate() {
            if c[1] != NIL {
                let s = &mut self.row_start[c[1] as usize];
                self.slot_elem[*s as usize] = e as u32;
                self.slot_col[*s as usize] = c[0];
                *s += 1;
            }
        }
        for iy in (1..=g.ny).rev() {
            self.row_start[iy] = self.row_start[iy - 1];
        }
        self.row_start[0] = 0;
    }
}

/// Bounds of the finite elements and the cell size `d = 2 max r + b` (capped cell counts),
/// or `None` when no element is finite.
fn grid(circles: &BoundingCircles, b: f64) -> Option<Grid> {
    let (mut xmin, mut ymin, mut xmax, mut ymax, mut rmax) = (
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
        0.0f64,
    );
    for e in 0..circles.len() {
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
        return None;
    }
    let mut d = 2.0 * rmax + b;
    if !(d > 0.0 && d.is_finite()) {
        d = 1.0;
    }
    let cap = (4 * circles.len() + 1024) as f64;
    let span = (xmax - xmin).max(ymax - ymin);
    if span / d > cap - 1.0 {
        d = span / (cap - 1.0);
    }
    let inv_d = 1.0 / d;
    Some(Grid {
        xmin,
        ymin,
        inv_d,
        nx: ((xmax - xmin) * inv_d) as usize + 1,
        ny: ((ymax - ymin) * inv_d) as usize + 1,
    })
}

/// The sweep of module docs step 5 over the rows of one band, its couples into `band.out`.
fn sweep_band(
    band: &mut Band,
    g: Grid,
    slots: &Slots,
    b: f64,
    tris: &[[u32; 3]],
    excl: &Exclusions,
) {
    let Band {
        rows: [r0, r1],
        col_cur,
        col_prev,
        next,
        out,
    } = band;
    let (r0, r1) = (*r0, *r1);
    out.clear();
    if r0 >= r1 {
        return;
    }
    let Slots {
        row_start,
        elem: slot_elem,
        col: slot_col,
        circles,
    } = *slots;
    // Slots from the row below the band (its column lists are the first row's mask).
    let first = r0.saturating_sub(1);
    let base = row_start[first] as usize;
    next.clear();
    next.resize(row_start[r1] as usize - base, NIL);
    col_cur.clear();
    col_cur.resize(g.nx + 2, NIL);
    col_prev.clear();
    col_prev.resize(g.nx + 2, NIL);
    let row = |iy: usize| row_start[iy] as usize..row_start[iy + 1] as usize;
    // Column lists of row iy into `heads` (slots pushed in order: each list runs backwards).
    let build = |heads: &mut [u32], next: &mut [u32], iy: usize| {
        for s in row(iy) {
            let cx = slot_col[s] as usize;
            next[s - base] = heads[cx];
            heads[cx] = s as u32;
        }
    };
    let test = |out: &mut Vec<[u32; 2]>, i: u32, j: u32| {
        if circles.near(i as usize, j as usize, b) && !excl.excluded(tris, i, j) {
            out.push(if i < j { [i, j] } else { [j, i] });
        }
    };
    let mut prev_row = None;
    if r0 > 0 && !row(r0 - 1).is_empty() {
        build(col_prev, next, r0 - 1);
        prev_row = Some(r0 - 1);
    }
    for iy in r0..r1 {
        let slots = row(iy);
        if !slots.is_empty() {
            build(col_cur, next, iy);
            for s in slots.clone() {
                let e = slot_elem[s];
                let cx = slot_col[s] as usize;
                // Own cell: only later slots of its list.
                let mut j = next[s - base];
                while j != NIL {
                    let k = j as usize;
                    test(out, e, slot_elem[k]);
                    j = next[k - base];
                }
                let mut j = col_cur[cx - 1];
                while j != NIL {
                    let k = j as usize;
                    test(out, e, slot_elem[k]);
                    j = next[k - base];
                }
                if prev_row.is_some() {
                    for c in [cx - 1, cx, cx + 1] {
                        let mut j = col_prev[c];
                        while j != NIL {
                            let k = j as usize;
                            test(out, e, slot_elem[k]);
                            j = next[k - base];
                        }
                    }
                }
            }
        }
        // Reset the previous row's heads, then this row becomes the previous one.
        if let Some(p) = prev_row {
            for s in row(p) {
                col_prev[slot_col[s] as usize] = NIL;
            }
        }
        std::mem::swap(col_cur, col_prev);
        prev_row = (!slots.is_empty()).then_some(iy);
    }
}
