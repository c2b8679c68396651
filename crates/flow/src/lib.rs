//! Fluid flow in the crack network of fdem.
//!
//! The network lives on the joints of the exploded mesh, given as plain arrays (node ids
//! P, Q, R, S per joint: edge P->Q of one triangle bonded to edge R->S of the other, P = S
//! and Q = R in the reference state); this crate knows nothing of the fracture crate.
//!
//! - **Cavities** sit at the original (pre-explode) vertices: the copies of a vertex are
//!   found by joining P with S and Q with R over every joint ([`Network::new`]). A cavity
//!   holds fluid once a wetted joint touches it.
//! - **Channels** are the wetted joints (pre-existing cracks, broken joints, the joints at a
//!   source): each links the cavities of its two ends. Its aperture at each end is the
//!   residual aperture plus the joint's opening `o = (x_S - x_P) . n` (and `(x_R - x_Q) . n`),
//!   smoothly down to the residual aperture times `exp(o / r)` where the faces press
//!   together ([`aperture`]); its conductance is the cubic law `C = t a^3 / (12 mu l)` with
//!   `a` the mean of the two end apertures, each at most the maximum aperture, `l` its
//!   length and `t` the model's thickness. Each cavity's volume is the channel volume nearer to it (the
//!   trapezoid of the apertures over the channel's half length, `t l (3 a_0 + a_1) / 8`).
//! - **Storage**: a cavity stores the fluid volume `m` (measured at zero pressure); its
//!   pressure is `p = K max(0, m / V - 1)` with `K` the fluid's bulk modulus and `V` the
//!   cavity's volume: an unfilled cavity has no pressure.
//! - **Pressure on the faces**: a channel's end pressures push its two faces apart along
//!   the normal, with the forces that are the gradient of the stored fluid's energy in the
//!   nodes' openings (`p l t / 2` per node under a uniform pressure,
//!   [`Network::add_face_forces`]): within a step the fluid is a conservative spring.
//! - **Time**: [`Network::advance`] moves the fluid over a mechanical step with the
//!   apertures of its end, in explicit sub-steps below the flow's own stable step
//!   ([`Network::stable_step`]).
//! - **Books** ([`Books`]): injected volume, the net inflow through prescribed pressures,
//!   leak-off (Carter: `u = C_L / sqrt(t - t_wet)` on each face) and the viscous
//!   dissipation; the volume in the network and its compression come from the state, and
//!   `initial + injected + boundary = network + compression + leaked` to round-off.

mod network;

pub use network::{
    Books, ChannelGeometry, FlowError, Fluid, NONE, Network, aperture, aperture_slope,
};
