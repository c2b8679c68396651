//! The joint stage in a distributed run (`crate::distributed`): each rank evaluates and
//! commits the joints with a node of its own ([`LocalJoints`]: a subset of the joint set, on
//! the same global nodes, so each of its nodes sums its joint forces in the serial order).
//! After each commit the ranks share what every rank must know at once: the joints that
//! softened and the joints that broke, from the rank that owns each joint (the owner of its
//! first node), merged in joint order, so that the star bonds, the pairs handed to the
//! contact stage, `fractures.csv` and the energy released at breaks are booked exactly as
//! by one process. The joints' histories reach every rank only at the steps that read them
//! ([`LocalJoints::share_histories`]).

use fdem_fracture::{
    FractureEvent, FractureMode, Histories, JointId, JointScratch, JointSet, JointState,
};

use crate::distributed::{Comm, Ghosts, Layout};
use crate::stages::system::{StageDistribution, StepEvents};

/// Values per joint history in a message.
const HISTORY: usize = 14;
/// Values per event in a message (the joint id first).
const EVENT: usize = 9;

/// One rank's joints.
pub struct LocalJoints {
    /// Global ids of the joints this rank evaluates (those with a node of its own).
    pub ids: Vec<u32>,
    /// Those joints.
    pub set: JointSet,
    /// Their committed state.
    pub state: JointState,
    /// The pass's scratch.
    pub scratch: JointScratch,
    /// The nodes of this rank's joints that other ranks own, from their owners.
    pub ghosts: Ghosts,
    /// Per rank, the global ids of the joints it owns (shares), increasing.
    owned_by: Vec<Vec<u32>>,
    /// Per local joint: whether this rank owns it.
    owns: Vec<bool>,
    rank: usize,
    events: Vec<FractureEvent>,
    mine: Vec<f64>,
    all: Vec<f64>,
}

impl LocalJoints {
    /// The joints of `layout`'s rank out of `set` in the state `state`.
    pub fn new(set: &JointSet, state: &JointState, layout: &Layout) -> LocalJoints {
        let owner = |j: usize| layout.node_owner[set.nodes[j][0] as usize] as usize;
        let mut owned_by = vec![Vec::new(); layout.size];
        let mut ids = Vec::new();
        for (j, nodes) in set.nodes.iter().enumerate() {
            owned_by[owner(j)].push(j as u32);
            if nodes
                .iter()
                .any(|&k| layout.node_owner[k as usize] as usize == layout.rank)
            {
                ids.push(j as u32);
            }
        }
        let owns = ids
            .iter()
            .map(|&j| owner(j as usize) == layout.rank)
            .collect();
        let local = set.subset(&ids);
        let ghosts = Ghosts::new(
            layout.rank,
            layout.size,
            &layout.node_owner,
            set.nodes.iter().map(|n| n.as_slice()),
        );
        LocalJoints {
            ghosts,
            scratch: JointScratch::new(ids.len()),
            state: state.subset(&ids),
            set: local,
            ids,
            owned_by,
            owns,
            rank: layout.rank,
            events: Vec::new(),
            mine: Vec::new(),
            all: Vec::new(),
        }
    }

    /// Commits this rank's joints at `(t, x)` and shares the step's news: returns the joints
    /// newly softened (global ids, increasing) into `softened` and their breaks into `events`
    /// (global ids, in joint order), merged from every rank; `global` gets the breaks (intact
    /// flags, break times, the energy released at breaks, the broken count) in joint order.
    pub fn commit_and_share(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        at_last_pass: bool,
        comm: &mut dyn Comm,
        global: &mut JointState,
        softened: &mut Vec<u32>,
        events: &mut Vec<FractureEvent>,
    ) {
        self.events.clear();
        let commit = if at_last_pass {
            fdem_fracture::commit_joints_at_last_pass
        } else {
            fdem_fracture::commit_joints
        };
        commit(
            &self.set,
            &mut self.state,
            x,
            t,
            &mut self.scratch,
            &mut self.events,
        );
        // this rank's news: [softened ids..., then per event EVENT values], owned joints only
        self.mine.clear();
        let soft: Vec<u32> = self
            .scratch
            .newly_softened()
            .iter()
            .filter(|&&l| self.owns[l as usize])
            .map(|&l| self.ids[l as usize])
            .collect();
        self.mine.extend(soft.iter().map(|&j| j as f64));
        let n_soft = soft.len();
        for e in &self.events {
            let l = e.joint.0 as usize;
            if !self.owns[l] {
                continue;
            }
            self.mine.extend_from_slice(&[
                self.ids[l] as f64,
                e.time,
                e.position[0],
                e.position[1],
                e.mode_mix,
                e.energy_released,
                e.stored_at_break,
                e.triangles[0] as f64,
                e.triangles[1] as f64,
            ]);
        }
        // the lengths first, then the news
        let size = self.owned_by.len();
        let mut lens = vec![0.0; 2 * size];
        let head = [n_soft as f64, ((self.mine.len() - n_soft) / EVENT) as f64];
        comm.all_gather(&head, &vec![2; size], &mut lens);
        let counts: Vec<usize> = lens
            .chunks_exact(2)
            .map(|c| c[0] as usize + EVENT * c[1] as usize)
            .collect();
        self.all.resize(counts.iter().sum(), 0.0);
        comm.all_gather(&self.mine, &counts, &mut self.all);
        softened.clear();
        events.clear();
        let mut at = 0;
        for (c, &n) in lens.chunks_exact(2).zip(&counts) {
            let part = &self.all[at..at + n];
            let (s, ev) = part.split_at(c[0] as usize);
            softened.extend(s.iter().map(|&j| j as u32));
            for v in ev.chunks_exact(EVENT) {
                events.push(FractureEvent {
                    joint: JointId(v[0] as u32),
                    triangles: [v[7] as u32, v[8] as u32],
                    time: v[1],
                    position: [v[2], v[3]],
                    mode: FractureMode::from_mix(v[4]),
                    mode_mix: v[4],
                    energy_released: v[5],
                    stored_at_break: v[6],
                });
            }
            at += n;
        }
        softened.sort_unstable();
        events.sort_by_key(|e| e.joint.0);
        for e in events.iter() {
            global.record_break(e.joint.0 as usize, e.time, e.stored_at_break);
        }
    }

    /// Every joint's committed history from the rank that owns it into `global` (the steps
    /// whose checks, rows or frames read the joints).
    pub fn share_histories(&mut self, comm: &mut dyn Comm, global: &mut JointState) {
        self.mine.clear();
        for (l, &j) in self.ids.iter().enumerate() {
            if self.owns[l] {
                pack(&self.state.history, l, &mut self.mine);
                debug_assert!(self.owned_by[self.rank].binary_search(&j).is_ok());
            }
        }
        let counts: Vec<usize> = self.owned_by.iter().map(|o| HISTORY * o.len()).collect();
        self.all.resize(counts.iter().sum(), 0.0);
        comm.all_gather(&self.mine, &counts, &mut self.all);
        let mut at = 0;
        for ids in &self.owned_by {
            for &j in ids {
                unpack(&self.all[at..at + HISTORY], &mut global.history, j as usize);
                at += HISTORY;
            }
        }
    }
}

/// Joint `l`'s history, [`HISTORY`] values.
fn pack(h: &Histories, l: usize, out: &mut Vec<f64>) {
    out.extend_from_slice(&h.damage[l]);
    out.extend_from_slice(&h.shear_secant[l]);
    out.extend_from_slice(&h.mode_mix[l]);
    out.extend_from_slice(&h.local[l]);
    out.extend_from_slice(&h.normal[l]);
    out.push(h.stored[l]);
    out.push(h.dissipated[l]);
}

/// [`pack`]'s values into joint `j` of `h`.
fn unpack(v: &[f64], h: &mut Histories, j: usize) {
    h.damage[j] = [v[0], v[1]];
    h.shear_secant[j] = [v[2], v[3]];
    h.mode_mix[j] = [v[4], v[5]];
    h.local[j] = [v[6], v[7], v[8], v[9]];
    h.normal[j] = [v[10], v[11]];
    h.stored[j] = v[12];
    h.dissipated[j] = v[13];
}

impl StageDistribution for super::FractureStage {
    /// Takes this rank's joints: those with a node of its own.
    fn distribute(&mut self, layout: &Layout) {
        let mut l = LocalJoints::new(&self.set, &self.state, layout);
        // the time crate says when the commit is at the last pass's positions
        l.scratch.set_position_check(false);
        self.local = Some(l);
    }

    fn set_partial(&mut self, on: bool) {
        self.partial = on;
    }

    fn end_of_step_distributed(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        at_last: bool,
        events: &mut StepEvents,
        comm: &mut dyn Comm,
    ) {
        let Some(l) = &mut self.local else {
            return self.end_step(t, x, at_last, events);
        };
        let _ = v;
        l.commit_and_share(
            t,
            x,
            at_last,
            comm,
            &mut self.state,
            &mut self.softened,
            &mut events.fractures,
        );
        self.after_commit(events);
    }

    /// The nodes of this rank's joints from their owners (the joints read no velocities).
    fn exchange_distributed(
        &mut self,
        _t: f64,
        x: &mut [[f64; 2]],
        v: &mut [[f64; 2]],
        _before_forces: bool,
        _events: &mut StepEvents,
        comm: &mut dyn Comm,
    ) {
        if let Some(l) = &mut self.local {
            l.ghosts.exchange(comm, x, v, false);
        }
    }

    /// An intact joint costs [`crate::distributed::balance::JOINT`], to its first triangle.
    fn add_costs(&self, tri_cost: &mut [f64]) {
        for (t, intact) in self.set.triangles.iter().zip(&self.state.intact) {
            if *intact {
                tri_cost[t[0] as usize] += crate::distributed::balance::JOINT;
            }
        }
    }

    fn share(&mut self, comm: &mut dyn Comm) {
        if let Some(l) = &mut self.local {
            l.share_histories(comm, &mut self.state);
        }
    }
}
