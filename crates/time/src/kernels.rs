//! The element-wise update loops that every scheme is made of.
//!
//! Each loop is element-wise (no reduction except the `max` of the finite-difference
//! gradient, which is exact), so
//! the results are bit for bit the same whatever the number of threads or the chunking.
//! Above [`PAR_MIN_DOFS`] the loops run on rayon in chunks of [`CHUNK`] DOFs.

use rayon::prelude::*;

/// Below this many DOFs the update loops run serially (rayon's overhead would dominate).
pub const PAR_MIN_DOFS: usize = 1 << 16;
/// DOFs per rayon task (128 KiB per array).
pub const CHUNK: usize = 1 << 14;

/// Runs `f` over matching chunks of one mutable and one shared array.
#[inline]
pub(crate) fn zip_mr<F>(m: &mut [f64], r: &[f64], f: F)
where
    F: Fn(&mut [f64], &[f64]) + Sync + Send,
{
    debug_assert_eq!(m.len(), r.len());
    if m.len() >= PAR_MIN_DOFS {
        m.par_chunks_mut(CHUNK)
            .zip(r.par_chunks(CHUNK))
            .for_each(|(m, r)| f(m, r));
    } else {
        f(m, r);
    }
}

/// Runs `f` over matching chunks of two mutable arrays and `k` shared ones (k = 1 or 2;
/// pass the same array twice if only one is needed).
#[inline]
pub(crate) fn zip_mmrr<F>(m1: &mut [f64], m2: &mut [f64], r1: &[f64], r2: &[f64], f: F)
where
    F: Fn(&mut [f64], &mut [f64], &[f64], &[f64]) + Sync + Send,
{
    debug_assert!(m1.len() == m2.len() && m1.len() == r1.len() && m1.len() == r2.len());
    if m1.len() >= PAR_MIN_DOFS {
        m1.par_chunks_mut(CHUNK)
            .zip(m2.par_chunks_mut(CHUNK))
            .zip(r1.par_chunks(CHUNK))
            .zip(r2.par_chunks(CHUNK))
            .for_each(|(((m1, m2), r1), r2)| f(m1, m2, r1, r2));
    } else {
        f(m1, m2, r1, r2);
    }
}

/// Largest absolute value (0 for an empty slice; NaN-propagating is not needed here: a NaN
/// entry gives a NaN or an entry-dependent result, and callers check finiteness).
pub(crate) fn max_abs(a: &[f64]) -> f64 {
    let serial = |a: &[f64]| a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if a.len() >= PAR_MIN_DOFS {
        a.par_chunks(CHUNK).map(serial).reduce(|| 0.0, f64::max)
    } else {
        serial(a)
    }
}

/// `out = x + c y`.
pub(crate) fn axpy_into(out: &mut [f64], x: &[f64], c: f64, y: &[f64]) {
    let n = out.len();
    // Chunk over out, x and y together through index ranges of equal length.
    if n >= PAR_MIN_DOFS {
        out.par_chunks_mut(CHUNK)
            .zip(x.par_chunks(CHUNK))
            .zip(y.par_chunks(CHUNK))
            .for_each(|((o, x), y)| {
                for ((o, x), y) in o.iter_mut().zip(x).zip(y) {
                    *o = x + c * y;
                }
            });
    } else {
        for ((o, x), y) in out.iter_mut().zip(x).zip(y) {
            *o = x + c * y;
        }
    }
}

/// `g = (g - b) s`.
pub(crate) fn sub_scale(g: &mut [f64], b: &[f64], s: f64) {
    zip_mr(g, b, |g, b| {
        for (g, b) in g.iter_mut().zip(b) {
            *g = (*g - b) * s;
        }
    });
}

/// Kick: `v += c a`.
pub(crate) fn kick(v: &mut [f64], a: &[f64], c: f64) {
    zip_mr(v, a, |v, a| {
        for (v, a) in v.iter_mut().zip(a) {
            *v += c * a;
        }
    });
}

/// Drift: `x += c v`.
pub(crate) fn drift(x: &mut [f64], v: &[f64], c: f64) {
    zip_mr(x, v, |x, v| {
        for (x, v) in x.iter_mut().zip(v) {
            *x += c * v;
        }
    });
}

/// Fused kick then drift: `v += ck a; x += cd v` (one pass over memory).
pub(crate) fn kick_drift(v: &mut [f64], x: &mut [f64], a: &[f64], ck: f64, cd: f64) {
    zip_mmrr(v, x, a, a, |v, x, a, _| {
        for ((v, x), a) in v.iter_mut().zip(x.iter_mut()).zip(a) {
            *v += ck * a;
            *x += cd * *v;
        }
    });
}

/// Fused drift then kick is not needed: OMF32 drifts first, then evaluates a force.
/// Fused gradient kick then drift: `v += ca a + cg g; x += cd v`.
pub(crate) fn kick2_drift(
    v: &mut [f64],
    x: &mut [f64],
    a: &[f64],
    g: &[f64],
    ca: f64,
    cg: f64,
    cd: f64,
) {
    zip_mmrr(v, x, a, g, |v, x, a, g| {
        for (((v, x), a), g) in v.iter_mut().zip(x.iter_mut()).zip(a).zip(g) {
            *v += ca * a + cg * g;
            *x += cd * *v;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_and_serial_kick_drift_agree_bit_for_bit() {
        let n = PAR_MIN_DOFS + 12345;
        let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut v: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
                let mut x = vec![0.5; n];
                kick_drift(&mut v, &mut x, &a, 0.1, 0.3);
                kick2_drift(&mut v, &mut x, &a, &a, 0.2, 1e-3, 0.7);
                (x, v, max_abs(&a))
            })
        };
        let (x1, v1, m1) = run(1);
        let (x2, v2, m2) = run(2);
        // Element-wise loops: identical to the last bit.
        assert!(x1.iter().zip(&x2).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(v1.iter().zip(&v2).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(m1.to_bits(), m2.to_bits());
        // And the serial reference (below the threshold, chunk by chunk) gives the same.
        let mut v: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let mut x = vec![0.5; n];
        for ((v, x), a) in v
            .chunks_mut(1000)
            .zip(x.chunks_mut(1000))
            .zip(a.chunks(1000))
        {
            kick_drift(v, x, a, 0.1, 0.3);
            kick2_drift(v, x, a, a, 0.2, 1e-3, 0.7);
        }
        assert!(x1.iter().zip(&x).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
