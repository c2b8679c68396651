//! The contact stage in a distributed run (`crate::distributed`): each rank evaluates only
//! the couples and plane pairs that bring a force to one of its nodes, so each of its nodes
//! sums its contact forces in the serial couple order, bit for bit.
//!
//! - **Detection** stays whole: before each force pass every rank judges the motion of its
//!   own nodes since the last detection, and when any rank's moved half the buffer the whole
//!   positions are gathered and every rank detects the same couples (the serial list).
//! - **Ghosts**: the nodes of the couples a rank evaluates come from their owners before each
//!   pass ([`Ghosts`], remade at each detection and release).
//! - **Books**: what sums over all couples (the statistics and slip dissipation, the plane
//!   reactions, the damping power, the work of the contact forces on the nodes, the potential
//!   brought in by releases, the active bound) is made of per-item terms; each rank hands out
//!   the terms of the items it leads, and at the end of the step every rank folds all of them
//!   in the serial order ([`Entries`]). The books are therefore the serial run's on
//!   every rank.
//! - **Observers and checkpoints** read the whole force pass and friction history, made
//!   current on every rank at the steps they read ([`ContactStage::share_part`]).

use fdem_contact::{COUPLE_SHARE, ContactStats, LEAD, LOCAL, TALLY, Tally, WALL_SHARE, react};

use super::ContactStage;
use crate::distributed::{Comm, Entries, Ghosts, Layout, share_nodes};
use crate::stages::system::{ForceTerm, StageDistribution, StepEvents};

/// The key of an entry of the `p`-th pass (or release) of a step: `p 2^32 + index`.
const PASS: f64 = 4294967296.0;

/// The sections of the end-of-step message and their widths (the key first).
const TALLIES: usize = 0;
const SWITCH: usize = 1;
const POWER0: usize = 2;
const WORK: usize = 3;
const POWER: usize = 4;
const WALLS: usize = 5;
const BOUND: usize = 6;
const WIDTHS: [usize; 7] = [1 + TALLY, 2, 7, 2, 7, 8, 2];

/// One rank's part of the contact.
pub(super) struct ContactPart {
    rank: usize,
    node_owner: Vec<u32>,
    owned_by: Vec<Vec<u32>>,
    ghosts: Ghosts,
    ghosts_stale: bool,
    /// The force passes since the last end of step: time and couple count.
    passes: Vec<(f64, usize)>,
    /// The releases since the last end of step.
    releases: usize,
    /// The time of the first evaluation while its damping power is pending.
    power0: Option<f64>,
    /// This rank's entries of the end-of-step message, per section.
    mine: Vec<Vec<f64>>,
    merged: Vec<Vec<f64>>,
    items: Vec<u32>,
    flat: Vec<f64>,
    all: Vec<f64>,
    entries: Entries,
    /// Every rank's verdict on its nodes' motion, and one value per rank (the counts).
    moved: Vec<f64>,
    ones: Vec<usize>,
}

impl ContactPart {
    fn new(layout: &Layout) -> ContactPart {
        ContactPart {
            rank: layout.rank,
            node_owner: layout.node_owner.clone(),
            owned_by: layout.owned_by.clone(),
            ghosts: Ghosts::default(),
            ghosts_stale: true,
            passes: Vec::new(),
            releases: 0,
            power0: None,
            mine: vec![Vec::new(); WIDTHS.len()],
            merged: vec![Vec::new(); WIDTHS.len()],
            items: Vec::new(),
            flat: Vec::new(),
            all: Vec::new(),
            entries: Entries::default(),
            moved: vec![0.0; layout.size],
            ones: vec![1; layout.size],
        }
    }
}

impl ContactStage {
    /// Takes this rank's part of `layout`: the triangles with a node of its own are local,
    /// those whose first node is its own it leads; the active bound counts its own nodes.
    fn distribute_part(&mut self, layout: &Layout) {
        let mine = |k: u32| layout.node_owner[k as usize] as usize == layout.rank;
        let roles = self
            .tris
            .iter()
            .map(|t| (t.iter().any(|&k| mine(k)) as u8 * LOCAL) | (mine(t[0]) as u8 * LEAD))
            .collect();
        self.contact.set_part(roles);
        let n = layout.node_owner.len();
        self.active.set_counted((0..n as u32).map(mine).collect());
        self.part = Some(Box::new(ContactPart::new(layout)));
    }

    /// Before a force pass: the releases, the walls' places, the detection when any rank's
    /// nodes moved half the buffer (on the whole positions, gathered into `x`), and the
    /// couples' nodes from their owners.
    fn prepare_part(
        &mut self,
        t: f64,
        x: &mut [[f64; 2]],
        v: &mut [[f64; 2]],
        events: &mut StepEvents,
        comm: &mut dyn Comm,
    ) {
        let added = self.take_releases(events);
        self.place_walls(t);
        let with_v = self.reads_velocities();
        let Some(p) = self.part.as_deref_mut() else {
            return;
        };
        let moved = self.contact.moved_since_detection(x, &p.owned_by[p.rank]);
        let size = p.owned_by.len();
        comm.all_gather(&[moved as u8 as f64], &p.ones, &mut p.moved);
        if p.moved.iter().any(|m| *m != 0.0) {
            p.flat.clear();
            for &k in &p.owned_by[p.rank] {
                p.flat.extend_from_slice(&x[k as usize]);
            }
            share_nodes(comm, &p.owned_by, 2, &p.flat, &mut p.all, |k, c| {
                x[k] = [c[0], c[1]];
            });
            self.contact.detect(x, &self.tris);
            p.ghosts_stale = true;
        }
        if added || p.ghosts_stale {
            // every couple's and plane pair's nodes (a plane pair's triangle twice)
            p.items.clear();
            for c in self.contact.couples() {
                let (a, b) = (self.tris[c[0] as usize], self.tris[c[1] as usize]);
                p.items.extend_from_slice(&a);
                p.items.extend_from_slice(&b);
            }
            for w in self.contact.wall_pairs() {
                let a = self.tris[w[1] as usize];
                p.items.extend_from_slice(&a);
                p.items.extend_from_slice(&a);
            }
            p.ghosts = Ghosts::new(p.rank, size, &p.node_owner, p.items.chunks_exact(6));
            p.ghosts_stale = false;
        }
        p.ghosts.exchange(comm, x, v, with_v);
        if added {
            // the contact potential the new couples bring in (the switch jump), per couple
            // this rank leads
            let key = p.releases as f64 * PASS;
            let c = &self.contact;
            for (k, pair) in c.added_couples().iter().enumerate() {
                if c.tri_lead(pair[0]) {
                    let e = c.pair_potential(pair, x, &self.tris, &self.labels);
                    p.mine[SWITCH].extend_from_slice(&[key + k as f64, e]);
                }
            }
            p.releases += 1;
        }
    }

    /// The couples' nodes (and velocities, when the laws read them) from their owners, at
    /// the end of a step.
    fn exchange_part(&mut self, x: &mut [[f64; 2]], v: &mut [[f64; 2]], comm: &mut dyn Comm) {
        let with_v = self.reads_velocities();
        if let Some(p) = self.part.as_deref_mut() {
            p.ghosts.exchange(comm, x, v, with_v);
        }
    }

    /// The force pass of this rank's couples; its statistics wait for the end of the step.
    pub(super) fn add_forces_part(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
    ) {
        self.contact
            .compute_forces(x, v, &self.tris, &self.labels, self.dt);
        self.contact.add_forces(&self.tris, f);
        // the first evaluation detects, on the whole positions
        self.start_books(t, x, v);
        let Some(p) = self.part.as_deref_mut() else {
            return;
        };
        if self.damped && self.damping_power.is_none() && p.power0.is_none() {
            p.power0 = Some(t);
            let out = &mut p.mine[POWER0];
            self.contact
                .damping_terms(&self.tris, v, |k, d| push_terms(out, k as f64, d));
        }
        let key = p.passes.len() as f64 * PASS;
        p.passes.push((t, self.contact.couples().len()));
        let out = &mut p.mine[TALLIES];
        for tally in self.contact.tallies() {
            out.push(key + tally.index as f64);
            tally.encode(out);
        }
    }

    /// The end of a step: every rank's terms folded in the serial order, then the single
    /// process's books.
    fn end_of_step_part(&mut self, t: f64, x: &[[f64; 2]], v: &[[f64; 2]], comm: &mut dyn Comm) {
        let Some(mut p) = self.part.take() else {
            return;
        };
        // this rank's terms
        if !self.node_x.is_empty() {
            self.node_force_now.fill([0.0; 2]);
            self.contact
                .add_forces(&self.tris, &mut self.node_force_now);
            for &k in &p.owned_by[p.rank] {
                let k = k as usize;
                let (f0, f1, x0, x1) = (
                    self.node_force[k],
                    self.node_force_now[k],
                    self.node_x[k],
                    x[k],
                );
                let w =
                    0.5 * ((f0[0] + f1[0]) * (x1[0] - x0[0]) + (f0[1] + f1[1]) * (x1[1] - x0[1]));
                if w != 0.0 {
                    p.mine[WORK].extend_from_slice(&[k as f64, w]);
                }
                self.node_x[k] = x1;
            }
            std::mem::swap(&mut self.node_force, &mut self.node_force_now);
        }
        if self.damped {
            let out = &mut p.mine[POWER];
            self.contact
                .damping_terms(&self.tris, v, |k, d| push_terms(out, k as f64, d));
        }
        let out = &mut p.mine[WALLS];
        self.contact.wall_forces(|k, plane, g| {
            out.extend_from_slice(&[k as f64, plane as f64]);
            for gk in g {
                out.extend_from_slice(&gk);
            }
        });
        if self.active_every > 0 && (self.steps + 1).is_multiple_of(self.active_every) {
            let w2 = self.active.omega_sq(
                &self.contact,
                x,
                &self.tris,
                &self.labels,
                &self.inv_sqrt_mass,
            );
            p.mine[BOUND].extend_from_slice(&[p.rank as f64, w2]);
        }
        let ContactPart {
            mine,
            merged,
            entries,
            ..
        } = &mut *p;
        entries.gather(comm, mine, &WIDTHS, merged);
        mine.iter_mut().for_each(Vec::clear);
        // the statistics of each pass, in order
        let mut last = None;
        for (n, &(tp, nc)) in p.passes.iter().enumerate() {
            let tallies =
                of_pass(&p.merged[TALLIES], WIDTHS[TALLIES], n).map(|e| Tally::decode(&e[1..]));
            let s = ContactStats::tally(nc, tallies);
            self.book_pass(tp, &s, true);
            last = Some(s);
        }
        p.passes.clear();
        if let Some(s) = last {
            self.contact.set_stats(s);
        }
        self.contact.commit();
        self.steps += 1;
        for n in 0..p.releases {
            let e: f64 = of_pass(&p.merged[SWITCH], 2, n).map(|e| e[1]).sum();
            self.switch_jump += e;
        }
        p.releases = 0;
        if let Some(t0) = p.power0.take() {
            self.damping_power = Some((t0, power(&p.merged[POWER0])));
        }
        if !self.node_x.is_empty() {
            let mut w = 0.0;
            for e in p.merged[WORK].chunks_exact(2) {
                w += e[1];
            }
            self.node_work += w;
        }
        let pw = self.damped.then(|| power(&p.merged[POWER]));
        self.reactions.iter_mut().for_each(|r| *r = [0.0; 2]);
        for e in p.merged[WALLS].chunks_exact(8) {
            let g = [[e[2], e[3]], [e[4], e[5]], [e[6], e[7]]];
            react(&mut self.reactions, e[1] as u32, &g);
        }
        let w2 = if self.active_due() {
            p.merged[BOUND]
                .chunks_exact(2)
                .fold(0.0, |m, e| e[1].max(m))
        } else {
            0.0
        };
        self.part = Some(p);
        self.book_step(t, pw, w2);
    }

    /// Makes the whole force pass, friction history and work books current on every rank
    /// (for the observers and checkpoints).
    fn share_part(&mut self, comm: &mut dyn Comm) {
        let Some(mut p) = self.part.take() else {
            return;
        };
        let ContactPart {
            rank,
            owned_by,
            mine,
            merged,
            flat,
            all,
            entries,
            ..
        } = &mut *p;
        let (c, w) = mine.split_at_mut(1);
        self.contact.share_out(&mut c[0], &mut w[0]);
        entries.gather(
            comm,
            &mine[..2],
            &[COUPLE_SHARE, WALL_SHARE],
            &mut merged[..2],
        );
        self.contact.share_in(&merged[0], &merged[1]);
        mine.iter_mut().for_each(Vec::clear);
        if !self.node_x.is_empty() {
            flat.clear();
            for &k in &owned_by[*rank] {
                flat.extend_from_slice(&self.node_x[k as usize]);
                flat.extend_from_slice(&self.node_force[k as usize]);
            }
            let (nx, nf) = (&mut self.node_x, &mut self.node_force);
            share_nodes(comm, owned_by, 4, flat, all, |k, c| {
                nx[k] = [c[0], c[1]];
                nf[k] = [c[2], c[3]];
            });
        }
        self.part = Some(p);
    }
}

impl StageDistribution for ContactStage {
    /// Takes this rank's part ([`distributed`]).
    fn distribute(&mut self, layout: &Layout) {
        self.distribute_part(layout);
    }

    fn set_looking(&mut self, on: bool) {
        self.looking = on;
    }

    fn set_partial(&mut self, on: bool) {
        self.partial = on;
    }

    fn end_of_step_distributed(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        _at_last: bool,
        _events: &mut StepEvents,
        comm: &mut dyn Comm,
    ) {
        self.end_of_step_part(t, x, v, comm);
    }

    fn exchange_distributed(
        &mut self,
        t: f64,
        x: &mut [[f64; 2]],
        v: &mut [[f64; 2]],
        before_forces: bool,
        events: &mut StepEvents,
        comm: &mut dyn Comm,
    ) {
        if before_forces {
            self.prepare_part(t, x, v, events, comm);
        } else {
            self.exchange_part(x, v, comm);
        }
    }

    /// A couple of the last detection costs [`crate::distributed::balance::COUPLE`], to its
    /// first triangle, and so does a plane pair, to its triangle.
    fn add_costs(&self, tri_cost: &mut [f64]) {
        use crate::distributed::balance::COUPLE;
        for c in self.contact.couples() {
            tri_cost[c[0] as usize] += COUPLE;
        }
        for w in self.contact.wall_pairs() {
            tri_cost[w[1] as usize] += COUPLE;
        }
    }

    fn share(&mut self, comm: &mut dyn Comm) {
        self.share_part(comm);
    }
}

/// Appends an entry `[key, terms padded with +0 to 6]` (subtracting `+0` leaves any sum as
/// it is, so the padding does not change the fold).
fn push_terms(out: &mut Vec<f64>, key: f64, d: &[f64]) {
    out.push(key);
    out.extend_from_slice(d);
    out.extend(std::iter::repeat_n(0.0, 6 - d.len()));
}

/// The damping power of merged entries: minus every term, in order (as
/// `fdem_contact::Contact::damping_power` folds them).
fn power(merged: &[f64]) -> f64 {
    let mut p = 0.0;
    for e in merged.chunks_exact(7) {
        for d in &e[1..] {
            p -= d;
        }
    }
    p
}

/// The entries of the `n`-th pass (or release) among `merged` (`w` values each).
fn of_pass(merged: &[f64], w: usize, n: usize) -> impl Iterator<Item = &[f64]> {
    let (lo, hi) = (n as f64 * PASS, (n + 1) as f64 * PASS);
    merged
        .chunks_exact(w)
        .filter(move |e| e[0] >= lo && e[0] < hi)
}
