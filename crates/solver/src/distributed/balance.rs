//! Repartitioning when the work becomes unbalanced: the cost of each triangle (its element,
//! the joints and contact couples it leads) summed per part; when the largest part costs more
//! than [`DEFAULT_THRESHOLD`] (or the run's threshold) times the mean, the triangles are cut
//! again by recursive coordinate bisection of their current centroids, weighted by their cost
//! ([`repartition`]). Every rank computes the same costs from the same whole state, so every
//! rank takes the same decision; the results do not depend on the partition.

use fdem_mesh::Elements;

use super::layout::centroids;
use super::partition::rcb;

/// The imbalance (largest part's cost over the mean) above which a distributed run
/// repartitions, unless the run gives its own.
pub const DEFAULT_THRESHOLD: f64 = 1.25;

/// Cost of a triangle's element pass per step, the unit of the costs.
pub const TRIANGLE: f64 = 1.0;
/// Cost of a joint per step in triangles: the joint pass of the fracturing disc on 13 824
/// triangles and 20 592 joints took 8.5 times the element pass on one thread, 5.7 triangles
/// per joint.
pub const JOINT: f64 = 5.7;
/// Cost of a contact couple or plane pair per step, in triangles: the contact force pass
/// runs 7.3 M couples/s on one thread, the element kernel 114 M triangles/s
/// (docs/performance.md), 15.6 triangles per couple. A detected couple whose triangles'
/// boxes are apart costs less; one that carries a load costs that.
pub const COUPLE: f64 = 15.0;

/// The largest part's cost over the mean, with `tri_part[t]` the part of triangle `t` out of
/// `size` and `cost[t]` its cost.
pub fn imbalance(tri_part: &[u32], cost: &[f64], size: usize) -> f64 {
    let mut per = vec![0.0; size];
    for (&p, &c) in tri_part.iter().zip(cost) {
        per[p as usize] += c;
    }
    let total: f64 = per.iter().sum();
    let max = per.iter().copied().fold(0.0, f64::max);
    if total > 0.0 {
        max * size as f64 / total
    } else {
        1.0
    }
}

/// A new part for each triangle when the current `tri_part` is more unbalanced than
/// `threshold`: the triangles cut by recursive coordinate bisection of their centroids at `x`,
/// weighted by `cost`; `None` when the current parts are balanced enough, when the new ones
/// would not be better, or when a centroid is not finite or a part would be empty.
pub fn repartition(
    elements: &Elements,
    x: &[[f64; 2]],
    tri_part: &[u32],
    cost: &[f64],
    size: usize,
    threshold: f64,
) -> Option<Vec<u32>> {
    let now = imbalance(tri_part, cost, size);
    if now.is_nan() || now <= threshold {
        return None;
    }
    let c = centroids(elements, x);
    if c.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return None;
    }
    let parts = rcb(&c, cost, size);
    let mut n = vec![0usize; size];
    for &p in &parts {
        n[p as usize] += 1;
    }
    (n.iter().all(|&k| k > 0) && imbalance(&parts, cost, size) < now).then_some(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_imbalance_is_the_largest_part_over_the_mean() {
        assert_eq!(imbalance(&[0, 0, 1, 1], &[1.0; 4], 2), 1.0);
        assert_eq!(imbalance(&[0, 0, 0, 1], &[1.0; 4], 2), 1.5);
        // one heavy triangle on part 1: 1 + 1 against 1 + 9
        assert_eq!(
            imbalance(&[0, 0, 1, 1], &[1.0, 1.0, 1.0, 9.0], 2),
            10.0 / 6.0
        );
        assert_eq!(imbalance(&[0, 1], &[0.0, 0.0], 2), 1.0);
    }
}
