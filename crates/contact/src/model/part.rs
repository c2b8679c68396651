//! One rank's part of the contact in a distributed run: the model on every rank holds the
//! whole couple list (every rank detects on the whole positions), but evaluates only the
//! couples and plane pairs that touch a triangle it marks [`LOCAL`]: those that bring a force
//! to one of its nodes. A node's couples are then all evaluated on its rank and scattered in
//! couple order, so its contact force is the whole model's, bit for bit.
//!
//! What sums over all couples (the statistics, the slip dissipation, the plane reactions, the
//! damping power) is made of per-item terms: each rank hands out the terms of the items it
//! leads ([`LEAD`]: the first node of the couple's first triangle is its own), and the whole
//! sum is the serial fold of every rank's terms merged by item index ([`Tally`],
//! [`Contact::wall_forces`], [`Contact::damping_terms`]). [`Contact::share_out`] and
//! [`Contact::share_in`] make the whole force pass and friction history current on every rank
//! (for the observers and checkpoints).

use super::{Contact, ContactStats};
use crate::couple::{CoupleForce, WallForce};
use crate::geom::{V2, add, dot, sub};

/// The rank evaluates the couples and plane pairs of the triangle (it owns one of its nodes).
pub const LOCAL: u8 = 1;
/// The rank leads the couples whose first triangle this is, and the triangle's plane pairs
/// (it owns the triangle's first node).
pub const LEAD: u8 = 2;

/// Values per [`Tally`] in [`Tally::encode`].
pub const TALLY: usize = 9;
/// Values per couple in [`Contact::share_out`].
pub const COUPLE_SHARE: usize = 68;
/// Values per plane pair in [`Contact::share_out`].
pub const WALL_SHARE: usize = 25;

/// One couple's or plane pair's part of a force pass's statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Its place in the pass: the couple's index, or the couple count plus the plane pair's.
    pub index: usize,
    /// The couple's triangles, or `[plane, triangle]`.
    pub pair: [u32; 2],
    /// A plane pair.
    pub wall: bool,
    /// A triangle of the couple was degenerate, inverted or not finite.
    pub invalid: bool,
    /// The normal force is positive.
    pub loaded: bool,
    /// Edges slipping.
    pub slipping: usize,
    /// Trial slip dissipation \[J/m\].
    pub dissipation: f64,
    /// Largest `phi`.
    pub phi_max: f64,
}

impl Tally {
    /// Appends the tally as [`TALLY`] values (the index first).
    pub fn encode(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&[
            self.index as f64,
            self.pair[0] as f64,
            self.pair[1] as f64,
            self.wall as u8 as f64,
            self.invalid as u8 as f64,
            self.loaded as u8 as f64,
            self.slipping as f64,
            self.dissipation,
            self.phi_max,
        ]);
    }

    /// The tally of [`Tally::encode`]'s values.
    pub fn decode(v: &[f64]) -> Tally {
        Tally {
            index: v[0] as usize,
            pair: [v[1] as u32, v[2] as u32],
            wall: v[3] != 0.0,
            invalid: v[4] != 0.0,
            loaded: v[5] != 0.0,
            slipping: v[6] as usize,
            dissipation: v[7],
            phi_max: v[8],
        }
    }
}

impl ContactStats {
    /// The statistics of a pass over `n_couples` couples from the tallies of its couples and
    /// plane pairs, in pass order (a fixed-order fold: the same bits for the same tallies).
    pub fn tally(n_couples: usize, items: impl IntoIterator<Item = Tally>) -> ContactStats {
        let mut s = ContactStats {
            n_couples,
            ..Default::default()
        };
        for t in items {
            if t.invalid {
                if s.n_invalid == 0 {
                    s.first_invalid = t.pair;
                }
                s.n_invalid += 1;
            }
            if t.wall {
                s.n_wall_active += t.loaded as usize;
            } else {
                s.n_active += t.loaded as usize;
            }
            s.n_slipping += t.slipping;
            s.trial_dissipation += t.dissipation;
            if t.loaded {
                s.sum_phi_loaded += t.phi_max;
            }
            if t.phi_max > s.max_phi {
                s.max_phi = t.phi_max;
                s.max_phi_couple = if t.wall {
                    [u32::MAX, t.pair[1]]
                } else {
                    t.pair
                };
            }
        }
        s
    }
}

/// Subtracts a plane pair's forces on its triangle `g` from the reaction of plane `plane`.
pub fn react(out: &mut [V2], plane: u32, g: &[V2; 3]) {
    if let Some(o) = out.get_mut(plane as usize) {
        for gk in g {
            *o = sub(*o, *gk);
        }
    }
}

impl Contact {
    /// Makes this model one rank's part (`part[t]`: [`LOCAL`] and [`LEAD`] bits per triangle;
    /// empty: the whole model). The force pass then evaluates only the couples and plane
    /// pairs with a local triangle (the others get no force: flag 0, a plane pair's result
    /// zero); the next detection marks only their triangles for the pass.
    pub fn set_part(&mut self, part: Vec<u8>) {
        self.part = part;
        self.held_part.clear();
        // the marks of the triangles the pass reads, for this part
        self.tri_used.iter_mut().for_each(|u| *u &= 1);
        for k in 0..self.couples.len() {
            let c = self.couples[k];
            if self.couple_local(&c) {
                for t in c {
                    if let Some(u) = self.tri_used.get_mut(t as usize) {
                        *u |= 2;
                    }
                }
            }
        }
        for k in 0..self.wall_pairs.len() {
            let t = self.wall_pairs[k][1];
            if self.tri_local(t)
                && let Some(u) = self.tri_used.get_mut(t as usize)
            {
                *u |= 2;
            }
        }
    }

    /// With `on`, the passes evaluate and count every couple and plane pair, on the whole
    /// positions (an observer's look at the whole state in a distributed run); off, this
    /// rank's part again.
    pub fn set_whole(&mut self, on: bool) {
        if on && self.held_part.is_empty() {
            self.held_part = std::mem::take(&mut self.part);
        } else if !on && self.part.is_empty() {
            self.part = std::mem::take(&mut self.held_part);
        }
    }

    /// The rank evaluates couples of triangle `t`.
    pub fn tri_local(&self, t: u32) -> bool {
        self.part.get(t as usize).is_none_or(|r| r & LOCAL != 0)
    }

    /// The rank leads the couples whose first triangle is `t`, and `t`'s plane pairs.
    pub fn tri_lead(&self, t: u32) -> bool {
        self.part.get(t as usize).is_none_or(|r| r & LEAD != 0)
    }

    /// The rank evaluates couple `c`.
    pub fn couple_local(&self, c: &[u32; 2]) -> bool {
        self.tri_local(c[0]) || self.tri_local(c[1])
    }

    /// The statistics now (a distributed run sets the whole pass's, folded from every
    /// rank's [`Contact::tallies`]; [`Contact::commit`] books their slip dissipation).
    pub fn set_stats(&mut self, s: ContactStats) {
        self.stats = s;
    }

    /// The tallies of the last pass's couples with a result and of its plane pairs that
    /// this rank leads, in pass order. A plane pair that adds nothing to the statistics (no
    /// load, slip, dissipation or `phi`) is left out.
    pub fn tallies(&self) -> impl Iterator<Item = Tally> + '_ {
        let nc = self.couples.len();
        let couples = self
            .results
            .iter()
            .zip(&self.couples)
            .zip(&self.flags)
            .enumerate()
            .filter(|(_, ((r, c), f))| **f != 0 && r.active && self.tri_lead(c[0]))
            .map(|(k, ((r, c), _))| Tally {
                index: k,
                pair: *c,
                wall: false,
                invalid: r.invalid,
                loaded: r.fn_total > 0.0,
                slipping: r.slipping as usize,
                dissipation: r.dissipation,
                phi_max: r.phi_max,
            });
        let walls = self
            .wall_results
            .iter()
            .zip(&self.wall_pairs)
            .enumerate()
            .filter(|(_, (r, c))| {
                self.tri_lead(c[1])
                    && (r.fn_total != 0.0
                        || r.slipping
                        || r.dissipation != 0.0
                        || r.phi_max > 0.0
                        || r.phi_max.is_nan())
            })
            .map(move |(k, (r, c))| Tally {
                index: nc + k,
                pair: *c,
                wall: true,
                invalid: false,
                loaded: r.fn_total > 0.0,
                slipping: r.slipping as usize,
                dissipation: r.dissipation,
                phi_max: r.phi_max,
            });
        couples.chain(walls)
    }

    /// Calls `put(k, plane, g)` for each plane pair `k` this rank leads, in order: `g` the
    /// last pass's forces (all families) on its triangle's nodes.
    pub fn wall_forces(&self, mut put: impl FnMut(usize, u32, [V2; 3])) {
        for (k, (r, c)) in self.wall_results.iter().zip(&self.wall_pairs).enumerate() {
            if self.tri_lead(c[1]) {
                let g = std::array::from_fn(|i| add(add(r.normal[i], r.friction[i]), r.damping[i]));
                put(k, c[0], g);
            }
        }
    }

    /// The terms of the damping power ([`Contact::damping_power`] subtracts them in order)
    /// of the couples with a load and the plane pairs this rank leads: `put(index, terms)`,
    /// index as for [`Tally::index`], terms `f_d,k . (v_k - v_plane)` per node. Nothing when
    /// no law (pair or plane) has damping.
    pub fn damping_terms(&self, tris: &[[u32; 3]], v: &[V2], mut put: impl FnMut(usize, &[f64])) {
        let n = self.laws.n_materials() as u32;
        let pairs = (0..n).any(|i| (0..n).any(|j| self.laws.get(i, j).damping > 0.0));
        let planes = self.walls.iter().any(|w| w.law.damping > 0.0);
        let nc = self.couples.len();
        let mut d = [0.0; 6];
        if pairs {
            for (k, ((r, c), f)) in self
                .results
                .iter()
                .zip(&self.couples)
                .zip(&self.flags)
                .enumerate()
            {
                if *f == 0 || !r.active || r.fn_total == 0.0 || !self.tri_lead(c[0]) {
                    continue;
                }
                let (ti, tj) = (&tris[c[0] as usize], &tris[c[1] as usize]);
                let nodes = [ti[0], ti[1], ti[2], tj[0], tj[1], tj[2]];
                for i in 0..6 {
                    d[i] = dot(r.damping[i], v[nodes[i] as usize]);
                }
                put(k, &d);
            }
        }
        if planes {
            for (k, (r, c)) in self.wall_results.iter().zip(&self.wall_pairs).enumerate() {
                let Some(plane) = self.walls.get(c[0] as usize) else {
                    continue;
                };
                if !self.tri_lead(c[1]) {
                    continue;
                }
                let t = &tris[c[1] as usize];
                for i in 0..3 {
                    d[i] = dot(r.damping[i], sub(v[t[i] as usize], plane.velocity));
                }
                put(nc + k, &d[..3]);
            }
        }
    }

    /// Whether the next pass must redetect, judged on `nodes` only (a rank's own nodes; the
    /// whole decision is true when any rank's is): the exact criterion of
    /// [`Contact::update_detection`].
    pub fn moved_since_detection(&self, x: &[V2], nodes: &[u32]) -> bool {
        if self.stale || x.len() != self.x_det.len() || self.walls.len() != self.wall_det.len() {
            return true;
        }
        let half = 0.5 * self.buffer;
        let h2 = half * half;
        nodes.iter().any(|&k| {
            let (a, b) = (x[k as usize], self.x_det[k as usize]);
            let d = [a[0] - b[0], a[1] - b[1]];
            let d2 = d[0] * d[0] + d[1] * d[1];
            d2 >= h2 || d2.is_nan()
        }) || self.walls.iter().zip(&self.wall_det).any(|(w, p0)| {
            let s = dot(sub(w.point, *p0), w.normal).abs();
            s >= half || s.is_nan()
        })
    }

    /// Appends the couples (with a result or a friction history) and the plane pairs this
    /// rank leads, [`COUPLE_SHARE`] and [`WALL_SHARE`] values each: the state that
    /// [`Contact::share_in`] makes current on every rank. Call after [`Contact::commit`].
    pub fn share_out(&self, couples: &mut Vec<f64>, walls: &mut Vec<f64>) {
        for (k, c) in self.couples.iter().enumerate() {
            let (f, ft) = (self.flags[k], &self.ft[k]);
            if !self.tri_lead(c[0]) || (f == 0 && ft.iter().all(|v| *v == 0.0)) {
                continue;
            }
            couples.push(k as f64);
            couples.push(f as f64);
            couples.extend_from_slice(ft);
            put_couple(couples, &self.results[k]);
        }
        for (k, c) in self.wall_pairs.iter().enumerate() {
            if self.tri_lead(c[1]) {
                walls.push(k as f64);
                walls.push(self.wall_ft[k]);
                put_wall(walls, &self.wall_results[k]);
            }
        }
    }

    /// Takes every rank's [`Contact::share_out`] (all of them, in any order): the couples
    /// and plane pairs not listed carry no result and no friction.
    pub fn share_in(&mut self, couples: &[f64], walls: &[f64]) {
        self.flags.fill(0);
        self.results.iter_mut().for_each(|r| r.active = false);
        self.ft.fill([0.0; 6]);
        for e in couples.chunks_exact(COUPLE_SHARE) {
            let k = e[0] as usize;
            self.flags[k] = e[1] as u8;
            self.ft[k].copy_from_slice(&e[2..8]);
            self.results[k] = get_couple(&e[8..]);
        }
        self.ft_trial.copy_from_slice(&self.ft);
        for e in walls.chunks_exact(WALL_SHARE) {
            let k = e[0] as usize;
            self.wall_ft[k] = e[1];
            self.wall_results[k] = get_wall(&e[2..]);
        }
        self.wall_ft_trial.copy_from_slice(&self.wall_ft);
    }
}

fn put_v2s(out: &mut Vec<f64>, v: &[V2]) {
    for p in v {
        out.extend_from_slice(p);
    }
}

fn get_v2s<const N: usize>(v: &[f64]) -> [V2; N] {
    std::array::from_fn(|i| [v[2 * i], v[2 * i + 1]])
}

fn put_couple(out: &mut Vec<f64>, r: &CoupleForce) {
    out.push(r.active as u8 as f64);
    put_v2s(out, &r.normal);
    put_v2s(out, &r.friction);
    put_v2s(out, &r.damping);
    put_v2s(out, &r.total);
    out.extend_from_slice(&r.ft);
    out.extend_from_slice(&[
        r.dissipation,
        r.fn_total,
        r.phi_max,
        r.slipping as f64,
        r.invalid as u8 as f64,
    ]);
}

fn get_couple(v: &[f64]) -> CoupleForce {
    CoupleForce {
        active: v[0] != 0.0,
        normal: get_v2s(&v[1..13]),
        friction: get_v2s(&v[13..25]),
        damping: get_v2s(&v[25..37]),
        total: get_v2s(&v[37..49]),
        ft: std::array::from_fn(|i| v[49 + i]),
        dissipation: v[55],
        fn_total: v[56],
        phi_max: v[57],
        slipping: v[58] as u8,
        invalid: v[59] != 0.0,
    }
}

fn put_wall(out: &mut Vec<f64>, r: &WallForce) {
    put_v2s(out, &r.normal);
    put_v2s(out, &r.friction);
    put_v2s(out, &r.damping);
    out.extend_from_slice(&[
        r.ft,
        r.dissipation,
        r.fn_total,
        r.phi_max,
        r.slipping as u8 as f64,
    ]);
}

fn get_wall(v: &[f64]) -> WallForce {
    WallForce {
        normal: get_v2s(&v[0..6]),
        friction: get_v2s(&v[6..12]),
        damping: get_v2s(&v[12..18]),
        ft: v[18],
        dissipation: v[19],
        fn_total: v[20],
        phi_max: v[21],
        slipping: v[22] != 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_results_come_back_bit_for_bit() {
        let mut r = CoupleForce {
            active: true,
            slipping: 3,
            invalid: false,
            dissipation: 1.5e-9,
            fn_total: -0.0,
            phi_max: f64::NAN,
            ..Default::default()
        };
        r.normal[4] = [1.0 / 3.0, -2.5e-300];
        r.total[5] = [7.0, 8.0];
        r.ft[2] = -4.0;
        let mut v = Vec::new();
        put_couple(&mut v, &r);
        assert_eq!(v.len(), COUPLE_SHARE - 8);
        let back = get_couple(&v);
        assert_eq!(back.normal, r.normal);
        assert_eq!(back.total, r.total);
        assert_eq!(back.ft, r.ft);
        assert_eq!(back.fn_total.to_bits(), r.fn_total.to_bits());
        assert!(back.phi_max.is_nan() && back.slipping == 3 && back.active && !back.invalid);
        let w = WallForce {
            slipping: true,
            ft: 2.0,
            phi_max: 0.25,
            normal: [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]],
            ..Default::default()
        };
        let mut v = Vec::new();
        put_wall(&mut v, &w);
        assert_eq!(v.len(), WALL_SHARE - 2);
        assert_eq!(get_wall(&v), w);
        let t = Tally {
            index: 12,
            pair: [3, 9],
            wall: true,
            invalid: false,
            loaded: true,
            slipping: 2,
            dissipation: 0.125,
            phi_max: 0.5,
        };
        let mut v = Vec::new();
        t.encode(&mut v);
        assert_eq!(v.len(), TALLY);
        assert_eq!(Tally::decode(&v), t);
    }
}
