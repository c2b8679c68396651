//! Contact laws per pair of materials and the contact settings.

/// The contact law of one pair of materials (per unit thickness forces).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Normal penalty `p` \[Pa\]. Default when built from a Young's modulus: `10 E`
    /// (see [`ContactLaw::from_young`]); typical range 10..100 E.
    pub penalty: f64,
    /// Coulomb friction coefficient `mu` \[-\] (0 = frictionless).
    pub mu: f64,
    /// Tangential penalty `k_t` \[Pa\] (N/m per unit thickness per m of slip). Default `p`.
    pub kt: f64,
    /// Normal contact damping `c` \[Pa s/m\]: a dashpot per unit length of edge inside the other
    /// triangle, acting on the normal relative velocity, bounded by the edge's normal force
    /// (`|f_d| <= p Q`: never tensile in total, no ploughing by a barely touching edge).
    /// Friction is bounded by `mu (p Q + f_d)`, the whole normal force.
    /// 0 = none. [`ContactLaw::damping_for_ratio`] gives a value from a damping ratio.
    pub damping: f64,
    /// Contact switched on for this pair of materials.
    pub enabled: bool,
}

impl ContactLaw {
    /// Default penalty factor: `p = 10 E`.
    pub const DEFAULT_PENALTY_FACTOR: f64 = 10.0;

    /// A frictionless law with penalty `p` \[Pa\], `k_t = p`, no damping.
    pub fn with_penalty(p: f64) -> Self {
        ContactLaw {
            penalty: p,
            mu: 0.0,
            kt: p,
            damping: 0.0,
            enabled: true,
        }
    }

    /// The documented default for a material of Young's modulus `e` \[Pa\]: `p = 10 E`,
    /// friction `mu`, `k_t = p`, no damping.
    pub fn from_young(e: f64, mu: f64) -> Self {
        ContactLaw {
            mu,
            ..Self::with_penalty(Self::DEFAULT_PENALTY_FACTOR * e)
        }
    }

    /// Dashpot coefficient \[Pa s/m\] giving damping ratio `xi` to a boundary layer of density
    /// `rho` \[kg/m^3\] on this penalty, estimated for equal altitudes H on both sides
    /// (contact stiffness `6 p L/H`, mass `rho H L`): `c = 2 xi sqrt(6 p rho)`.
    pub fn damping_for_ratio(&self, xi: f64, rho: f64) -> f64 {
        2.0 * xi * (6.0 * self.penalty * rho).sqrt()
    }

    /// A disabled law (the pair of materials does not interact).
    pub fn disabled() -> Self {
        ContactLaw {
            enabled: false,
            ..Self::with_penalty(0.0)
        }
    }
}

/// Symmetric table of contact laws indexed by the materials of the two triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactLaws {
    n: usize,
    table: Vec<ContactLaw>,
}

impl ContactLaws {
    /// `n` materials, every pair with `law`.
    pub fn uniform(n: usize, law: ContactLaw) -> Self {
        let n = n.max(1);
        ContactLaws {
            n,
            table: vec![law; n * n],
        }
    }

    /// Number of materials.
    pub fn n_materials(&self) -> usize {
        self.n
    }

    /// Sets the law between materials `i` and `j` (both orders). Out-of-range ids are ignored.
    pub fn set(&mut self, i: usize, j: usize, law: ContactLaw) {
        if i < self.n && j < self.n {
            self.table[i * self.n + j] = law;
            self.table[j * self.n + i] = law;
        }
    }

    /// The law between materials `i` and `j`; out-of-range ids fall back to material 0.
    #[inline(always)]
    pub fn get(&self, i: u32, j: u32) -> &ContactLaw {
        let i = if (i as usize) < self.n { i as usize } else { 0 };
        let j = if (j as usize) < self.n { j as usize } else { 0 };
        &self.table[i * self.n + j]
    }
}

/// Which broad phase finds the couples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BroadPhase {
    /// NBS binned search (the default: faster by measurement, docs/contact.md).
    #[default]
    Nbs,
    /// parry2d-f64's BVH (kept for comparison).
    ParryBvh,
}

/// Settings of contact detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSettings {
    /// Detection buffer `b` \[m\]: couples whose bounding circles are closer than `b` are kept;
    /// detection is redone when a node (or a wall) has moved `b/2` since the last one.
    /// Default: 0 means "choose `0.2 *` the mean triangle radius at the first detection".
    pub buffer: f64,
    /// Broad phase (default NBS).
    pub broad_phase: BroadPhase,
    /// Narrow filter at detection (default true): drop candidate couples that an edge line of
    /// one triangle separates from the other by more than `b` ([`crate::narrow`]). Off: every
    /// pair of bounding circles within `b` is a couple.
    pub narrow: bool,
    /// Largest `phi` reached on any contacting edge before [`crate::ContactStats::check`]
    /// reports too deep a penetration (0..1; `phi = 3 d/H`). Default 0.5 (d = H/6).
    pub max_phi: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            buffer: 0.0,
            broad_phase: BroadPhase::Nbs,
            narrow: true,
            max_phi: 0.5,
        }
    }
}
