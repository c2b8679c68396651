//! Small 2D vector helpers and convex polygon clipping used by the contact kernels.

/// A 2D point or vector `[x, y]`.
pub type V2 = [f64; 2];

#[inline(always)]
pub(crate) fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline(always)]
pub(crate) fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}

#[inline(always)]
pub(crate) fn scale(a: V2, s: f64) -> V2 {
    [a[0] * s, a[1] * s]
}

#[inline(always)]
pub(crate) fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// `cross(a, b) = a_x b_y - a_y b_x`.
#[inline(always)]
pub(crate) fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// `rot(a) = (-a_y, a_x)`, a rotation by +90 degrees.
#[inline(always)]
pub(crate) fn rot(a: V2) -> V2 {
    [-a[1], a[0]]
}

/// Euclidean length (plain square root: `hypot` is several times slower and its overflow
/// protection is irrelevant at physical scales).
#[inline(always)]
pub(crate) fn norm(a: V2) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

#[inline(always)]
pub(crate) fn finite(a: V2) -> bool {
    a[0].is_finite() && a[1].is_finite()
}

/// Centroid of a triangle.
#[inline(always)]
pub(crate) fn centroid(x: &[V2; 3]) -> V2 {
    [
        (x[0][0] + x[1][0] + x[2][0]) / 3.0,
        (x[0][1] + x[1][1] + x[2][1]) / 3.0,
    ]
}

/// A convex polygon with at most `POLY_MAX` vertices, stored inline (no allocation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Poly {
    pub(crate) p: [V2; POLY_MAX],
    pub(crate) n: usize,
}

/// Capacity of [`Poly`]: clipping a triangle by three half-planes, then by three more,
/// gives at most 3 + 6 vertices.
pub(crate) const POLY_MAX: usize = 12;

impl Poly {
    pub(crate) fn tri(x: [V2; 3]) -> Self {
        let mut p = [[0.0; 2]; POLY_MAX];
        p[..3].copy_from_slice(&x);
        Poly { p, n: 3 }
    }

    /// Keeps the part where `dot(q - o, m) >= 0` (Sutherland-Hodgman, one half-plane).
    pub(crate) fn clip_halfplane(&self, o: V2, m: V2) -> Self {
        let mut out = Poly {
            p: [[0.0; 2]; POLY_MAX],
            n: 0,
        };
        if self.n == 0 {
            return out;
        }
        for i in 0..self.n {
            let a = self.p[i];
            let b = self.p[(i + 1) % self.n];
            let da = dot(sub(a, o), m);
            let db = dot(sub(b, o), m);
            if da >= 0.0 && out.n < POLY_MAX {
                out.p[out.n] = a;
                out.n += 1;
            }
            if ((da >= 0.0) != (db >= 0.0)) && out.n < POLY_MAX {
                let t = da / (da - db);
                out.p[out.n] = add(a, scale(sub(b, a), t));
                out.n += 1;
            }
        }
        out
    }

    /// Clips by a CCW triangle (its three inner half-planes).
    pub(crate) fn clip_tri(&self, t: &[V2; 3]) -> Self {
        let mut q = *self;
        for k in 0..3 {
            let a = t[k];
            let b = t[(k + 1) % 3];
            // Inner normal of CCW edge a->b is rot(b - a).
            q = q.clip_halfplane(a, rot(sub(b, a)));
            if q.n < 3 {
                q.n = 0;
                return q;
            }
        }
        q
    }

    /// Area and area centroid.
    pub(crate) fn area_centroid(&self) -> (f64, V2) {
        if self.n < 3 {
            return (0.0, [0.0; 2]);
        }
        let o = self.p[0];
        let mut a2 = 0.0;
        let mut c = [0.0; 2];
        for i in 1..self.n - 1 {
            let u = sub(self.p[i], o);
            let w = sub(self.p[i + 1], o);
            let d = cross(u, w);
            a2 += d;
            c[0] += d * (u[0] + w[0]);
            c[1] += d * (u[1] + w[1]);
        }
        if a2 <= 0.0 {
            return (0.0, o);
        }
        let area = 0.5 * a2;
        (area, [o[0] + c[0] / (3.0 * a2), o[1] + c[1] / (3.0 * a2)])
    }
}
