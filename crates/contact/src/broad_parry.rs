//! Broad phase with parry2d-f64's bounding volume hierarchy, kept for comparison with NBS.
//!
//! Each triangle's leaf is the box around its bounding circle grown by `b/2`; the tree is
//! rebuilt at each detection (binned SAH build) and traversed against itself; box overlaps
//! are then filtered with the same circle criterion as NBS, so both give the same couples.
//! Measured slower than NBS (docs/contact.md), so NBS is the default.

use crate::bounding::{BoundingCircles, sort_couples};
use crate::exclusions::Exclusions;
use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::Vector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

/// Scratch memory of the parry broad phase.
#[derive(Default)]
pub struct ParryBroadPhase {
    leaves: Vec<Aabb>,
    index: Vec<u32>,
    ws: BvhWorkspace,
    count: Vec<u32>,
    tmp: Vec<[u32; 2]>,
}

impl ParryBroadPhase {
    /// Empty scratch.
    pub fn new() -> Self {
        Self::default()
    }

    /// Same contract as [`crate::nbs::Nbs::find_couples`].
    pub fn find_couples(
        &mut self,
        circles: &BoundingCircles,
        b: f64,
        tris: &[[u32; 3]],
        excl: &Exclusions,
        out: &mut Vec<[u32; 2]>,
    ) {
        out.clear();
        let b = if b.is_finite() { b.max(0.0) } else { 0.0 };
        self.leaves.clear();
        self.index.clear();
        for e in 0..circles.len() {
            let r = circles.r[e];
            if r.is_nan() {
                continue;
            }
            let c = circles.c[e];
            let h = r + 0.5 * b;
            self.leaves.push(Aabb::new(
                Vector::new(c[0] - h, c[1] - h),
                Vector::new(c[0] + h, c[1] + h),
            ));
            self.index.push(e as u32);
        }
        if self.leaves.len() < 2 {
            return;
        }
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.leaves);
        let index = &self.index;
        bvh.traverse_bvtt_single_tree::<false>(&mut self.ws, &mut |a, bb| {
            let (i, j) = (index[a as usize], index[bb as usize]);
            if circles.near(i as usize, j as usize, b) && !excl.excluded(tris, i, j) {
                out.push(if i < j { [i, j] } else { [j, i] });
            }
        });
        sort_couples(circles.len(), out, &mut self.count, &mut self.tmp);
    }
}
