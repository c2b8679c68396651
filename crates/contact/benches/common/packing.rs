//! The benchmark packing shared by `benches/contact.rs` and `examples/force_pass.rs`: a square
//! grid of cells of size 1, each split into two triangles that own their nodes (as with
//! intrinsic joints), every node jittered by up to ±0.05 and given a random velocity.

/// Positions, velocities and triangles of a packing.
pub struct Packing {
    /// Node positions.
    pub x: Vec<[f64; 2]>,
    /// Node velocities.
    pub v: Vec<[f64; 2]>,
    /// Triangles (own nodes each).
    pub tris: Vec<[u32; 3]>,
}

/// The packing of `n_tris` triangles (deterministic).
pub fn packing(n_tris: usize) -> Packing {
    let side = ((n_tris / 2) as f64).sqrt().ceil() as usize;
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut x, mut v, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    'outer: for j in 0..side {
        for i in 0..side {
            let (a, b) = (i as f64, j as f64);
            let corners = [[a, b], [a + 1.0, b], [a + 1.0, b + 1.0], [a, b + 1.0]];
            for t in [[0, 1, 2], [0, 2, 3]] {
                if tris.len() == n_tris {
                    break 'outer;
                }
                let base = x.len() as u32;
                for k in t {
                    let c: [f64; 2] = corners[k];
                    x.push([c[0] + 0.1 * rnd(), c[1] + 0.1 * rnd()]);
                    v.push([rnd(), rnd()]);
                }
                tris.push([base, base + 1, base + 2]);
            }
        }
    }
    Packing { x, v, tris }
}
