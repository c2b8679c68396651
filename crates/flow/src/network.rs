//! The network, its state, its geometry at given positions, the faces' forces and the
//! explicit flow update (see the crate docs).

use thiserror::Error;

/// No cavity: a node on no joint.
pub const NONE: u32 = u32::MAX;

/// The fluid's properties and the apertures' bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fluid {
    /// Dynamic viscosity `mu` [Pa s], > 0.
    pub viscosity: f64,
    /// Bulk modulus `K` [Pa], > 0.
    pub bulk_modulus: f64,
    /// Density [kg/m^3], > 0 (the books' mass; the flow itself is by volume).
    pub density: f64,
    /// Residual aperture [m], > 0: a channel whose faces touch still conducts and stores
    /// this much ([`aperture`]).
    pub residual_aperture: f64,
    /// Maximum aperture [m], >= the residual one: the conductance's aperture at most.
    pub max_aperture: f64,
    /// Carter's leak-off coefficient `C_L` [m/s^0.5], >= 0.
    pub leak_off: f64,
}

impl Fluid {
    /// Checks every property (the first bad one, by name).
    pub fn check(&self) -> Result<(), FlowError> {
        let pos = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(FlowError::Property { name, value: v })
            }
        };
        pos("viscosity", self.viscosity)?;
        pos("bulk_modulus", self.bulk_modulus)?;
        pos("density", self.density)?;
        pos("residual_aperture", self.residual_aperture)?;
        if !(self.max_aperture.is_finite() && self.max_aperture >= self.residual_aperture) {
            return Err(FlowError::Property {
                name: "max_aperture",
                value: self.max_aperture,
            });
        }
        if !(self.leak_off.is_finite() && self.leak_off >= 0.0) {
            return Err(FlowError::Property {
                name: "leak_off",
                value: self.leak_off,
            });
        }
        Ok(())
    }
}

/// What the network refuses.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlowError {
    /// A fluid property out of its range.
    #[error("fluid property {name} = {value} is out of range")]
    Property {
        /// The property.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A node id beyond the positions.
    #[error("joint {joint} refers to node {node}, but there are {n_nodes} nodes")]
    Node {
        /// The joint.
        joint: u32,
        /// Its node id.
        node: u32,
        /// The number of nodes.
        n_nodes: usize,
    },
}

/// One channel's geometry at the positions of the last [`Network::geometry`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChannelGeometry {
    /// Length `l` of the joint's mid-line [m].
    pub length: f64,
    /// Unit normal of the mid-line, from the first face (P, Q) to the second (R, S).
    pub normal: [f64; 2],
    /// Apertures at the two ends ([`aperture`]) [m]; the conductance takes them at most at
    /// the maximum aperture.
    pub aperture: [f64; 2],
    /// `da/do` at the two ends (1 where open).
    pub slope: [f64; 2],
    /// Cubic-law conductance `t a^3 / (12 mu l)` [m^3 / (Pa s)].
    pub conductance: f64,
    /// Volume flow from end 0 to end 1 over the last sub-step [m^3/s].
    pub flow: f64,
}

/// The volume books of the fluid since the start [m^3], and its energies [J].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Books {
    /// Volume in the network at the start (cavities filled before the run, [`Network::fill`]).
    pub initial: f64,
    /// Volume injected by the sources.
    pub injected: f64,
    /// Net volume that entered through the prescribed pressures (negative: drained).
    pub boundary: f64,
    /// Volume leaked off into the rock.
    pub leaked: f64,
    /// Energy the sources put in, `int p Q dt`.
    pub injected_energy: f64,
    /// Energy that came in with the volume through the prescribed pressures, `sum p dm`.
    pub boundary_energy: f64,
    /// Energy dissipated by the viscous flow in the channels, `int sum q dp dt`.
    pub viscous: f64,
}

impl Books {
    /// The books in field order (a checkpoint's record).
    pub fn to_array(&self) -> [f64; 7] {
        [
            self.initial,
            self.injected,
            self.boundary,
            self.leaked,
            self.injected_energy,
            self.viscous,
            self.boundary_energy,
        ]
    }

    /// The books from [`Books::to_array`]'s record.
    pub fn from_array(a: [f64; 7]) -> Self {
        let [
            initial,
            injected,
            boundary,
            leaked,
            injected_energy,
            viscous,
            boundary_energy,
        ] = a;
        Self {
            initial,
            injected,
            boundary,
            leaked,
            injected_energy,
            viscous,
            boundary_energy,
        }
    }
}

/// The backward-Euler update's working arrays, one entry per cavity (kept between steps so
/// that a step allocates nothing).
#[derive(Debug, Clone, Default)]
struct Implicit {
    leak: Vec<f64>,
    filled: Vec<bool>,
    p: Vec<f64>,
    m: Vec<f64>,
    b: Vec<f64>,
    diag: Vec<f64>,
    x: Vec<f64>,
    ax: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    d: Vec<f64>,
}

impl Implicit {
    /// Every array at `n` zeros (no cavity filled).
    fn reset(&mut self, n: usize) {
        for v in [
            &mut self.leak,
            &mut self.p,
            &mut self.m,
            &mut self.b,
            &mut self.diag,
            &mut self.x,
            &mut self.ax,
            &mut self.r,
            &mut self.z,
            &mut self.d,
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.filled.clear();
        self.filled.resize(n, false);
    }
}

/// The fluid network on a joint set (see the crate docs).
#[derive(Debug, Clone)]
pub struct Network {
    /// Node ids P, Q, R, S of every joint.
    pub joints: Vec<[u32; 4]>,
    /// The cavity (original vertex) of each node; [`NONE`] for a node on no joint.
    pub vertex_of: Vec<u32>,
    /// Number of cavities.
    pub n_vertices: usize,
    /// Out-of-plane thickness `t` [m].
    pub thickness: f64,
    /// The fluid.
    pub fluid: Fluid,
    /// Per joint: wetted (a channel).
    pub wet: Vec<bool>,
    /// Per joint: the time it was wetted [s] (the leak-off clock).
    pub wet_since: Vec<f64>,
    /// The wetted joints, increasing.
    pub channels: Vec<u32>,
    /// Per channel (in [`Network::channels`] order): its geometry.
    pub geometry: Vec<ChannelGeometry>,
    /// Per cavity: the fluid volume it stores, measured at zero pressure [m^3].
    pub stored: Vec<f64>,
    /// Per cavity: its volume at the last geometry [m^3] (0 when no channel touches it).
    pub volume: Vec<f64>,
    /// Per cavity: its pressure [Pa].
    pub pressure: Vec<f64>,
    /// Per cavity: a prescribed pressure [Pa]; NaN where free.
    pub fixed: Vec<f64>,
    /// Per cavity: the injection rate at the current time [m^3/s] (set by the caller).
    pub rate: Vec<f64>,
    /// The books since the start.
    pub books: Books,
    /// Per cavity: the bulk modulus it stores the fluid with [Pa]: the fluid's, or less
    /// where the explicit mechanical step cannot carry the stiffness of a small filled cavity
    /// ([`Network::set_stiffness_cap`]).
    pub bulk: Vec<f64>,
    /// Per node `1 / m` and the largest frequency a cavity may add [rad/s]
    /// ([`Network::set_stiffness_cap`]); empty and infinite: no cap.
    inv_mass: Vec<f64>,
    omega_cap: f64,
    /// Per cavity: `sum a_i^2 / m_i` over the nodes of its faces (scratch of the cap).
    face_sum: Vec<f64>,
    /// Per cavity: the sum of its channels' conductances (scratch of the stable step).
    sum_c: Vec<f64>,
    /// Per cavity: the change of stored volume over a sub-step (scratch).
    change: Vec<f64>,
    /// The backward-Euler update's working arrays.
    implicit: Implicit,
    /// Sub-steps (explicit) or steps (implicit) taken so far.
    pub substeps: u64,
}

/// The aperture of a channel end at the opening `o` [m], `r` the residual aperture:
/// `r + o` when open, `r exp(o / r)` when the faces press into each other (`o < 0`): positive,
/// continuous with its slope at 0, so that a cavity's volume is a smooth function of the
/// positions (a volume held constant while the faces move would let the pressure do work on
/// the solid that no compression of the fluid pays for).
pub fn aperture(o: f64, r: f64) -> f64 {
    if o >= 0.0 { r + o } else { r * (o / r).exp() }
}

/// The terms `sum (dV/du_i)^2 / m_i` of the cavities at the two ends of a channel of face
/// area `lt`, end slopes `sl` and nodes `n` (P, Q, R, S): the end-0 cavity's volume
/// `lt (3 a_0 + a_1) / 8` moves with the end-0 nodes by `3 lt s_0 / 8` and with the end-1
/// nodes by `lt s_1 / 8`.
fn face_terms(lt: f64, sl: [f64; 2], im: &[f64], n: [u32; 4]) -> (f64, f64) {
    let m0 = im[n[0] as usize] + im[n[3] as usize];
    let m1 = im[n[1] as usize] + im[n[2] as usize];
    let (a0, a1) = (0.125 * lt * sl[0], 0.125 * lt * sl[1]);
    (
        9.0 * a0 * a0 * m0 + a1 * a1 * m1,
        a0 * a0 * m0 + 9.0 * a1 * a1 * m1,
    )
}

/// `da/do` of [`aperture`]: 1 when open, `exp(o / r)` when the faces press together.
pub fn aperture_slope(o: f64, r: f64) -> f64 {
    if o >= 0.0 { 1.0 } else { (o / r).exp() }
}

/// Union-find root of `i` with path halving.
fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let g = parent[parent[i as usize] as usize];
        parent[i as usize] = g;
        i = g;
    }
    i
}

impl Network {
    /// A dry network over `joints` (node ids below `n_nodes`): the cavities found, no
    /// channel. Errors: a node id out of range, a fluid property out of range.
    pub fn new(
        joints: Vec<[u32; 4]>,
        n_nodes: usize,
        thickness: f64,
        fluid: Fluid,
    ) -> Result<Self, FlowError> {
        fluid.check()?;
        let mut parent: Vec<u32> = (0..n_nodes as u32).collect();
        for (j, n) in joints.iter().enumerate() {
            if let Some(&node) = n.iter().find(|&&k| k as usize >= n_nodes) {
                return Err(FlowError::Node {
                    joint: j as u32,
                    node,
                    n_nodes,
                });
            }
            for (a, b) in [(n[0], n[3]), (n[1], n[2])] {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                if ra != rb {
                    // the smaller id is the root: the cavities do not depend on joint order
                    parent[ra.max(rb) as usize] = ra.min(rb);
                }
            }
        }
        let mut on_joint = vec![false; n_nodes];
        for n in &joints {
            for &k in n {
                on_joint[k as usize] = true;
            }
        }
        // cavities numbered by their smallest node id
        let mut id_of_root = vec![NONE; n_nodes];
        let mut vertex_of = vec![NONE; n_nodes];
        let mut n_vertices = 0usize;
        for i in 0..n_nodes {
            if !on_joint[i] {
                continue;
            }
            let r = root(&mut parent, i as u32) as usize;
            if id_of_root[r] == NONE {
                id_of_root[r] = n_vertices as u32;
                n_vertices += 1;
            }
            vertex_of[i] = id_of_root[r];
        }
        let nj = joints.len();
        Ok(Self {
            joints,
            vertex_of,
            n_vertices,
            thickness,
            fluid,
            wet: vec![false; nj],
            wet_since: vec![0.0; nj],
            channels: Vec::new(),
            geometry: Vec::new(),
            stored: vec![0.0; n_vertices],
            volume: vec![0.0; n_vertices],
            pressure: vec![0.0; n_vertices],
            fixed: vec![f64::NAN; n_vertices],
            rate: vec![0.0; n_vertices],
            books: Books::default(),
            bulk: vec![fluid.bulk_modulus; n_vertices],
            inv_mass: Vec::new(),
            omega_cap: f64::INFINITY,
            face_sum: vec![0.0; n_vertices],
            sum_c: vec![0.0; n_vertices],
            change: vec![0.0; n_vertices],
            implicit: Implicit::default(),
            substeps: 0,
        })
    }

    /// Caps the fluid's stiffness on the solid at `omega` [rad/s] (`inv_mass`: `1 / m` per
    /// node): a filled cavity of volume `V` is a spring on the nodes of its faces whose
    /// frequency is `sqrt(K S / V)`, `S = sum g_i^2 / m_i` (`g_i = dV/du_i`); where that is
    /// above `omega`, the cavity stores the fluid with `K_v = omega^2 V / S` in place of `K`
    /// (the books stay exact: the cavity's pressure is `K_v (m / V - 1)`). A time step `h`
    /// of a scheme stable up to `h omega = c` carries springs up to `omega = c / h`.
    pub fn set_stiffness_cap(&mut self, inv_mass: Vec<f64>, omega: f64) {
        self.inv_mass = inv_mass;
        self.omega_cap = omega;
    }

    /// The cap's frequency [rad/s] (infinite: none).
    pub fn stiffness_cap(&self) -> f64 {
        self.omega_cap
    }

    /// The cavities at the two ends of joint `j` (of its nodes P and Q).
    pub fn ends(&self, j: usize) -> [usize; 2] {
        let n = self.joints[j];
        [
            self.vertex_of[n[0] as usize] as usize,
            self.vertex_of[n[1] as usize] as usize,
        ]
    }

    /// Wets the joints `js` at time `t` (those already wet are left as they are). Returns
    /// whether any was new; the channel list stays increasing.
    pub fn wet_joints(&mut self, js: impl IntoIterator<Item = usize>, t: f64) -> bool {
        let mut new = false;
        for j in js {
            if !self.wet[j] {
                self.wet[j] = true;
                self.wet_since[j] = t;
                new = true;
            }
        }
        if new {
            self.channels = (0..self.joints.len() as u32)
                .filter(|&j| self.wet[j as usize])
                .collect();
            self.geometry
                .resize(self.channels.len(), ChannelGeometry::default());
        }
        new
    }

    /// Whether cavity `v` touches a channel.
    pub fn is_wetted(&self, v: usize) -> bool {
        self.volume[v] > 0.0
    }

    /// The channels' geometry and the cavities' volumes at positions `x`, then the
    /// pressures of the stored volumes in them.
    pub fn geometry(&mut self, x: &[[f64; 2]]) {
        let (t, f) = (self.thickness, self.fluid);
        self.volume.iter_mut().for_each(|v| *v = 0.0);
        self.sum_c.iter_mut().for_each(|v| *v = 0.0);
        self.face_sum.iter_mut().for_each(|v| *v = 0.0);
        let capped = !self.inv_mass.is_empty() && self.omega_cap.is_finite();
        for (c, &j) in self.channels.iter().enumerate() {
            let n = self.joints[j as usize];
            let [p, q, r, s] = n.map(|k| x[k as usize]);
            let m0 = [(p[0] + s[0]) * 0.5, (p[1] + s[1]) * 0.5];
            let m1 = [(q[0] + r[0]) * 0.5, (q[1] + r[1]) * 0.5];
            let d = [m1[0] - m0[0], m1[1] - m0[1]];
            let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
            let nn = [d[1] / l, -d[0] / l];
            let o0 = (s[0] - p[0]) * nn[0] + (s[1] - p[1]) * nn[1];
            let o1 = (r[0] - q[0]) * nn[0] + (r[1] - q[1]) * nn[1];
            let a = [o0, o1].map(|o| aperture(o, f.residual_aperture));
            let am = 0.5 * (a[0].min(f.max_aperture) + a[1].min(f.max_aperture));
            let g = &mut self.geometry[c];
            g.length = l;
            g.normal = nn;
            g.aperture = a;
            g.slope = [o0, o1].map(|o| aperture_slope(o, f.residual_aperture));
            g.conductance = t * am * am * am / (12.0 * f.viscosity * l);
            let [v0, v1] = [
                self.vertex_of[n[0] as usize] as usize,
                self.vertex_of[n[1] as usize] as usize,
            ];
            self.volume[v0] += t * l * (3.0 * a[0] + a[1]) * 0.125;
            self.volume[v1] += t * l * (a[0] + 3.0 * a[1]) * 0.125;
            self.sum_c[v0] += g.conductance;
            self.sum_c[v1] += g.conductance;
            if capped {
                let im = &self.inv_mass;
                let (e0, e1) = face_terms(l * t, g.slope, im, n);
                self.face_sum[v0] += e0;
                self.face_sum[v1] += e1;
            }
        }
        let (k, w2) = (f.bulk_modulus, self.omega_cap * self.omega_cap);
        for v in 0..self.n_vertices {
            self.bulk[v] = if capped && self.face_sum[v] > 0.0 {
                k.min(w2 * self.volume[v] / self.face_sum[v])
            } else {
                k
            };
        }
        self.update_pressures();
    }

    /// The pressures of the stored volumes in the current cavity volumes; prescribed
    /// pressures hold their value.
    fn update_pressures(&mut self) {
        for v in 0..self.n_vertices {
            let fixed = self.fixed[v];
            self.pressure[v] = if !fixed.is_nan() {
                fixed
            } else if self.volume[v] > 0.0 {
                self.bulk[v] * (self.stored[v] / self.volume[v] - 1.0).max(0.0)
            } else {
                0.0
            };
        }
    }

    /// The flow's stable step at the last geometry [s]: `min V_i / (K sum_c C_c)` over the
    /// free cavities (forward Euler on the pressures `dp_i/dt = (K / V_i) sum_c C_c (p_j -
    /// p_i)`; the bound of Gershgorin's circles). Infinite without channels.
    pub fn stable_step(&self) -> f64 {
        let mut h = f64::INFINITY;
        for v in 0..self.n_vertices {
            if self.fixed[v].is_nan() && self.sum_c[v] > 0.0 {
                h = h.min(self.volume[v] / (self.bulk[v] * self.sum_c[v]));
            }
        }
        h
    }

    /// Sets the stored volume of each prescribed cavity to what its pressure needs in its
    /// volume, booking the difference as inflow through the boundary.
    fn hold_prescribed(&mut self) {
        for v in 0..self.n_vertices {
            let p = self.fixed[v];
            if p.is_nan() || self.volume[v] <= 0.0 {
                continue;
            }
            let m = self.volume[v] * (1.0 + p / self.bulk[v]);
            self.books.boundary += m - self.stored[v];
            self.books.boundary_energy += p * (m - self.stored[v]);
            self.stored[v] = m;
        }
    }

    /// Moves the fluid from time `t0` over `dt` at the last geometry: `n` explicit
    /// sub-steps, each at most `safety` times [`Network::stable_step`] (safety in (0, 1]);
    /// the injection [`Network::rate`]s, the leak-off and the prescribed pressures act in
    /// each. Returns the number of sub-steps.
    pub fn advance(&mut self, t0: f64, dt: f64, safety: f64) -> u64 {
        if self.channels.is_empty() || dt <= 0.0 {
            return 0;
        }
        self.hold_prescribed();
        self.update_pressures();
        let crit = safety * self.stable_step();
        let n = if crit.is_finite() && crit > 0.0 {
            (dt / crit).ceil().max(1.0) as u64
        } else {
            1
        };
        let h = dt / n as f64;
        for k in 0..n {
            let (ta, tb) = (t0 + k as f64 * h, t0 + (k + 1) as f64 * h);
            self.substep(ta, tb);
        }
        self.substeps += n;
        n
    }

    /// One explicit sub-step from `ta` to `tb`.
    fn substep(&mut self, ta: f64, tb: f64) {
        let h = tb - ta;
        self.change.iter_mut().for_each(|c| *c = 0.0);
        for (c, &j) in self.channels.iter().enumerate() {
            let n = self.joints[j as usize];
            let v0 = self.vertex_of[n[0] as usize] as usize;
            let v1 = self.vertex_of[n[1] as usize] as usize;
            let dp = self.pressure[v0] - self.pressure[v1];
            let g = &mut self.geometry[c];
            let q = g.conductance * dp;
            g.flow = q;
            self.change[v0] -= q * h;
            self.change[v1] += q * h;
            self.books.viscous += q * dp * h;
        }
        for v in 0..self.n_vertices {
            let r = self.rate[v];
            if r != 0.0 {
                self.change[v] += r * h;
                self.books.injected += r * h;
                self.books.injected_energy += self.pressure[v] * r * h;
            }
        }
        for (s, c) in self.stored.iter_mut().zip(&self.change) {
            *s += c;
        }
        if self.fluid.leak_off > 0.0 {
            self.leak(ta, tb);
        }
        self.hold_prescribed();
        self.update_pressures();
    }

    /// Moves the fluid from time `t0` over `dt` at the last geometry in one backward-Euler
    /// step (unconditionally stable): the pressures of the filled free cavities solve
    /// `(V_i / K) p_i + dt sum_c C_c (p_i - p_j) = m_i - V_i + dt Q_i - L_i` (`L_i` the
    /// step's leak-off, Carter's integral), the unfilled ones have `p = 0`, the prescribed
    /// ones their pressure; a cavity that the step fills or empties changes set and the
    /// solve is repeated (at most [`MAX_SETS`] times). The stored volumes then move by the
    /// channels' flows at the new pressures, so the books close whatever the solve's
    /// tolerance. Returns the conjugate-gradient iterations.
    pub fn advance_implicit(&mut self, t0: f64, dt: f64) -> u64 {
        if self.channels.is_empty() || dt <= 0.0 {
            return 0;
        }
        self.hold_prescribed();
        let n = self.n_vertices;
        let mut s = std::mem::take(&mut self.implicit);
        s.reset(n);
        // the step's leak-off per cavity, at most what it stores
        if self.fluid.leak_off > 0.0 {
            self.leak_into(t0, t0 + dt, &mut s.leak);
        }
        for v in 0..n {
            s.filled[v] =
                self.fixed[v].is_nan() && self.volume[v] > 0.0 && self.stored[v] >= self.volume[v];
        }
        let mut iters = 0;
        s.p.copy_from_slice(&self.pressure);
        for _ in 0..MAX_SETS {
            iters += self.solve(&mut s, dt);
            // the stored volumes the flows at p give
            self.moved(&s.p, &s.leak, dt, &mut s.m);
            let mut changed = false;
            for v in 0..n {
                if !self.fixed[v].is_nan() || self.volume[v] <= 0.0 {
                    continue;
                }
                let now = if s.filled[v] {
                    s.p[v] >= 0.0
                } else {
                    s.m[v] > self.volume[v]
                };
                if now != s.filled[v] {
                    s.filled[v] = now;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let p = &mut s.p;
        for v in 0..n {
            if !s.filled[v] && self.fixed[v].is_nan() {
                p[v] = 0.0;
            }
        }
        // the flows at the new pressures move the fluid: exact books
        self.change.iter_mut().for_each(|c| *c = 0.0);
        for (c, &j) in self.channels.iter().enumerate() {
            let nn = self.joints[j as usize];
            let v0 = self.vertex_of[nn[0] as usize] as usize;
            let v1 = self.vertex_of[nn[1] as usize] as usize;
            let dp = p[v0] - p[v1];
            let g = &mut self.geometry[c];
            let q = g.conductance * dp;
            g.flow = q;
            self.change[v0] -= q * dt;
            self.change[v1] += q * dt;
            self.books.viscous += q * dp * dt;
        }
        for v in 0..n {
            let r = self.rate[v];
            if r != 0.0 {
                self.change[v] += r * dt;
                self.books.injected += r * dt;
                self.books.injected_energy += p[v] * r * dt;
            }
            self.change[v] -= s.leak[v];
            self.books.leaked += s.leak[v];
        }
        for (st, c) in self.stored.iter_mut().zip(&self.change) {
            *st += c;
        }
        self.implicit = s;
        self.hold_prescribed();
        self.update_pressures();
        self.substeps += 1;
        iters
    }

    /// The stored volumes after a step of `dt` with the flows at pressures `p`, the sources
    /// and the leak-off `leak`, into `m`.
    fn moved(&self, p: &[f64], leak: &[f64], dt: f64, m: &mut [f64]) {
        m.copy_from_slice(&self.stored);
        for (c, &j) in self.channels.iter().enumerate() {
            let nn = self.joints[j as usize];
            let v0 = self.vertex_of[nn[0] as usize] as usize;
            let v1 = self.vertex_of[nn[1] as usize] as usize;
            let q = self.geometry[c].conductance * (p[v0] - p[v1]) * dt;
            m[v0] -= q;
            m[v1] += q;
        }
        for v in 0..self.n_vertices {
            m[v] += self.rate[v] * dt - leak[v];
        }
    }

    /// `y = A x` on the filled cavities: `A = diag(V/K) + dt L` (L the channels' graph
    /// Laplacian; the other cavities' pressures are held at `x`'s values and not written).
    fn apply(&self, filled: &[bool], dt: f64, x: &[f64], y: &mut [f64]) {
        for v in 0..self.n_vertices {
            y[v] = if filled[v] {
                self.volume[v] / self.bulk[v] * x[v]
            } else {
                0.0
            };
        }
        for (c, &j) in self.channels.iter().enumerate() {
            let nn = self.joints[j as usize];
            let v0 = self.vertex_of[nn[0] as usize] as usize;
            let v1 = self.vertex_of[nn[1] as usize] as usize;
            let q = dt * self.geometry[c].conductance * (x[v0] - x[v1]);
            if filled[v0] {
                y[v0] += q;
            }
            if filled[v1] {
                y[v1] -= q;
            }
        }
    }

    /// Solves the backward-Euler system for the filled cavities' pressures in `s.p` (the
    /// others: 0 when free, their value when prescribed) by conjugate gradients with the
    /// diagonal as preconditioner, to a relative residual of 1e-13. Returns the iterations.
    fn solve(&self, s: &mut Implicit, dt: f64) -> u64 {
        let n = self.n_vertices;
        let Implicit {
            leak,
            filled,
            p,
            b,
            diag,
            x,
            ax,
            r,
            z,
            d,
            ..
        } = s;
        for v in 0..n {
            if !self.fixed[v].is_nan() {
                p[v] = self.fixed[v];
            } else if !filled[v] {
                p[v] = 0.0;
            }
        }
        // b = m - V + dt Q - L, less the known pressures' part of A p
        for v in 0..n {
            (b[v], diag[v]) = if filled[v] {
                (
                    self.stored[v] - self.volume[v] + dt * self.rate[v] - leak[v],
                    self.volume[v] / self.bulk[v],
                )
            } else {
                (0.0, 0.0)
            };
        }
        for (c, &j) in self.channels.iter().enumerate() {
            let nn = self.joints[j as usize];
            let v0 = self.vertex_of[nn[0] as usize] as usize;
            let v1 = self.vertex_of[nn[1] as usize] as usize;
            let g = dt * self.geometry[c].conductance;
            for (a, o) in [(v0, v1), (v1, v0)] {
                if filled[a] {
                    diag[a] += g;
                    if !filled[o] {
                        b[a] += g * p[o];
                    }
                }
            }
        }
        for v in 0..n {
            x[v] = if filled[v] { p[v] } else { 0.0 };
        }
        self.apply(filled, dt, x, ax);
        for v in 0..n {
            r[v] = if filled[v] { b[v] - ax[v] } else { 0.0 };
        }
        let norm_b = b.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm_b == 0.0 {
            for v in 0..n {
                if filled[v] {
                    p[v] = 0.0;
                }
            }
            return 0;
        }
        for v in 0..n {
            z[v] = if filled[v] { r[v] / diag[v] } else { 0.0 };
        }
        d.copy_from_slice(z);
        let mut rz: f64 = r.iter().zip(z.iter()).map(|(a, b)| a * b).sum();
        let mut it = 0;
        let limit = 10 * n as u64 + 100;
        while it < limit {
            let rn = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            if rn <= 1e-13 * norm_b {
                break;
            }
            self.apply(filled, dt, d, ax);
            for v in 0..n {
                if !filled[v] {
                    ax[v] = 0.0;
                }
            }
            let dad: f64 = d.iter().zip(ax.iter()).map(|(a, b)| a * b).sum();
            if dad <= 0.0 {
                break;
            }
            let alpha = rz / dad;
            for v in 0..n {
                x[v] += alpha * d[v];
                r[v] -= alpha * ax[v];
            }
            for v in 0..n {
                z[v] = if filled[v] { r[v] / diag[v] } else { 0.0 };
            }
            let rz_new: f64 = r.iter().zip(z.iter()).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for v in 0..n {
                d[v] = z[v] + beta * d[v];
            }
            it += 1;
        }
        for v in 0..n {
            if filled[v] {
                p[v] = x[v];
            }
        }
        it
    }

    /// Carter's leak-off from every channel's two faces over `[ta, tb]`, half of each
    /// channel's to each end cavity, at most what a cavity stores.
    fn leak(&mut self, ta: f64, tb: f64) {
        let mut out = std::mem::take(&mut self.change);
        out.iter_mut().for_each(|c| *c = 0.0);
        self.leak_into(ta, tb, &mut out);
        for (s, l) in self.stored.iter_mut().zip(&out) {
            *s -= l;
            self.books.leaked += l;
        }
        self.change = out;
    }

    /// Carter's leak-off volumes over `[ta, tb]` per cavity into `out` (zeroed by the
    /// caller): from each channel's two faces of area `l t`, `2 C_L (sqrt(tb - t_w) -
    /// sqrt(ta - t_w))` per unit area, half to each end (a prescribed cavity is refilled through
    /// the boundary); at most what a cavity stores.
    fn leak_into(&self, ta: f64, tb: f64, out: &mut [f64]) {
        let (t, cl) = (self.thickness, self.fluid.leak_off);
        for (c, &j) in self.channels.iter().enumerate() {
            let since = self.wet_since[j as usize];
            let root_gain = (tb - since).max(0.0).sqrt() - (ta - since).max(0.0).sqrt();
            let per_end = 2.0 * cl * self.geometry[c].length * t * root_gain;
            let n = self.joints[j as usize];
            for node in [n[0], n[1]] {
                out[self.vertex_of[node as usize] as usize] += per_end;
            }
        }
        for (o, &m) in out.iter_mut().zip(&self.stored) {
            *o = o.min(m.max(0.0));
        }
    }

    /// Fills cavity `v` at pressure `p` in its current volume (a crack filled before the
    /// run), booking the volume as initial.
    pub fn fill(&mut self, v: usize, p: f64) {
        let m = self.volume[v] * (1.0 + p / self.bulk[v]);
        self.books.initial += m - self.stored[v];
        self.stored[v] = m;
        self.update_pressures();
    }

    /// The fluid volume in the network, `sum min(m, V)`, and its compression,
    /// `sum max(m - V, 0)` [m^3].
    pub fn network_and_compression(&self) -> (f64, f64) {
        let (mut net, mut comp) = (0.0, 0.0);
        for (&m, &v) in self.stored.iter().zip(&self.volume) {
            net += m.min(v);
            comp += (m - v).max(0.0);
        }
        (net, comp)
    }

    /// The mass balance's residual, `initial + injected + boundary - (network + compression +
    /// leaked)`, relative to the largest of its terms (0 when all are 0).
    pub fn balance_error(&self) -> f64 {
        let (net, comp) = self.network_and_compression();
        let b = &self.books;
        let scale = [b.initial, b.injected, b.boundary.abs(), net, comp, b.leaked]
            .into_iter()
            .fold(0.0, f64::max);
        if scale == 0.0 {
            return 0.0;
        }
        (b.initial + b.injected + b.boundary - net - comp - b.leaked).abs() / scale
    }

    /// Adds the pressure's forces on the faces of every channel at positions `x` to `f` (the
    /// positions of the last [`Network::geometry`]), pushing the faces apart along the
    /// mid-line's normal: the forces are the gradient of the stored fluid's energy in the
    /// opening, `p_0 dV_0 + p_1 dV_1`, so `l t s_0 (3 p_0 + p_1) / 8` on each node of end 0
    /// and `l t s_1 (p_0 + 3 p_1) / 8` on each node of end 1 (`s_k = da/do` at end k, 1
    /// when open); under a uniform pressure, `p l t / 2` per node.
    pub fn add_face_forces(&self, x: &[[f64; 2]], f: &mut [[f64; 2]]) {
        let t = self.thickness;
        for (c, &j) in self.channels.iter().enumerate() {
            let n = self.joints[j as usize];
            let [p0, p1] = [n[0], n[1]].map(|k| self.pressure[self.vertex_of[k as usize] as usize]);
            if p0 == 0.0 && p1 == 0.0 {
                continue;
            }
            let sl = self.geometry[c].slope;
            let [p, q, r, s] = n.map(|k| x[k as usize]);
            // l nn = (d_y, -d_x) with d the mid-line
            let d = [
                (q[0] + r[0] - p[0] - s[0]) * 0.5,
                (q[1] + r[1] - p[1] - s[1]) * 0.5,
            ];
            let ln = [d[1], -d[0]];
            let w = [
                0.125 * t * sl[0] * (3.0 * p0 + p1),
                0.125 * t * sl[1] * (p0 + 3.0 * p1),
            ];
            for (end, (a, b)) in [(n[0], n[3]), (n[1], n[2])].into_iter().enumerate() {
                f[a as usize][0] -= w[end] * ln[0];
                f[a as usize][1] -= w[end] * ln[1];
                f[b as usize][0] += w[end] * ln[0];
                f[b as usize][1] += w[end] * ln[1];
            }
        }
    }

    /// The highest frequency the fluid's stiffness adds to the solid [rad/s]. The filled free
    /// cavities joined by channels form connected cavities (the flow evens their pressure out
    /// within a step when the fluid is not too viscous); one of volume `V` under the bulk
    /// modulus `K` couples the nodes of its faces by the stiffness `K g_i g_j / V` (`g_i =
    /// dV/du_i`), whose one non-zero eigenvalue over the lumped masses is
    /// `(K / V) sum_i g_i^2 / m_i`; the largest over the connected cavities.
    /// `inv_mass`: per node, `1 / m`. With each cavity's own bulk modulus `K_v`, a connected
    /// cavity's is `sum S / sum (V / K_v)`. A very viscous fluid keeps the cavities apart,
    /// each stiffer than their union: the bound is then too low, unless the stiffness cap
    /// holds each cavity ([`Network::set_stiffness_cap`]).
    pub fn frequency_bound(&self, inv_mass: &[f64]) -> f64 {
        let n = self.n_vertices;
        let filled = |v: usize| {
            self.fixed[v].is_nan() && self.volume[v] > 0.0 && self.stored[v] >= self.volume[v]
        };
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for &j in &self.channels {
            let [a, b] = self.ends(j as usize);
            if filled(a) && filled(b) {
                let (ra, rb) = (root(&mut parent, a as u32), root(&mut parent, b as u32));
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
        let (mut vol, mut sum) = (vec![0.0; n], vec![0.0; n]);
        for v in 0..n {
            if filled(v) {
                vol[root(&mut parent, v as u32) as usize] += self.volume[v] / self.bulk[v];
            }
        }
        for (c, &j) in self.channels.iter().enumerate() {
            let nn = self.joints[j as usize];
            let g = &self.geometry[c];
            let terms = face_terms(g.length * self.thickness, g.slope, inv_mass, nn);
            for (end, e) in [(0usize, terms.0), (1, terms.1)] {
                let v = self.vertex_of[nn[end] as usize] as usize;
                if filled(v) {
                    sum[root(&mut parent, v as u32) as usize] += e;
                }
            }
        }
        let mut w2: f64 = 0.0;
        for v in 0..n {
            if vol[v] > 0.0 {
                w2 = w2.max(sum[v] / vol[v]);
            }
        }
        w2.sqrt()
    }
}

/// The most times [`Network::advance_implicit`] repeats its solve when cavities fill or
/// empty.
pub const MAX_SETS: usize = 20;

#[cfg(test)]
mod tests;
