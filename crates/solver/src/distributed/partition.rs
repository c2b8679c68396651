//! Recursive coordinate bisection: points with weights split into parts of about equal
//! weight, each a compact region (a part is cut across its longer side).

/// The part (`0..parts`) of each point: the points are cut across the longer side of their
/// bounding box at the weighted median, the two sides getting `floor(parts/2)` and
/// `ceil(parts/2)` parts with weight in that ratio, recursively. Deterministic: ties in the
/// coordinate are broken by the point's index. `parts` ≥ 1.
pub fn rcb(points: &[[f64; 2]], weights: &[f64], parts: usize) -> Vec<u32> {
    assert!(parts >= 1 && points.len() == weights.len());
    let mut part = vec![0u32; points.len()];
    let mut ids: Vec<u32> = (0..points.len() as u32).collect();
    split(points, weights, &mut ids, 0, parts, &mut part);
    part
}

fn split(
    points: &[[f64; 2]],
    weights: &[f64],
    ids: &mut [u32],
    first: usize,
    parts: usize,
    part: &mut [u32],
) {
    if parts == 1 || ids.len() <= 1 {
        for &i in ids.iter() {
            part[i as usize] = first as u32;
        }
        return;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in ids.iter() {
        let p = points[i as usize];
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
    ids.sort_by(|&a, &b| {
        points[a as usize][axis]
            .total_cmp(&points[b as usize][axis])
            .then(a.cmp(&b))
    });
    let left_parts = parts / 2;
    let total: f64 = ids.iter().map(|&i| weights[i as usize]).sum();
    let target = total * left_parts as f64 / parts as f64;
    let mut acc = 0.0;
    let mut cut = 0;
    while cut < ids.len() && acc + 0.5 * weights[ids[cut] as usize] <= target {
        acc += weights[ids[cut] as usize];
        cut += 1;
    }
    // each side keeps at least as many points as it has parts, where it can
    let (lo, hi) = (
        left_parts.min(ids.len()),
        ids.len().saturating_sub(parts - left_parts),
    );
    let cut = if lo <= hi {
        cut.clamp(lo, hi)
    } else {
        ids.len() * left_parts / parts
    };
    let (l, r) = ids.split_at_mut(cut);
    split(points, weights, l, first, left_parts, part);
    split(
        points,
        weights,
        r,
        first + left_parts,
        parts - left_parts,
        part,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_weights_split_into_equal_compact_parts() {
        // a 12 x 4 grid into 3 parts: cut across x into 4 + 8 columns' worth, then 4 + 4
        let pts: Vec<[f64; 2]> = (0..48)
            .map(|k| [(k % 12) as f64, (k / 12) as f64])
            .collect();
        let part = rcb(&pts, &vec![1.0; 48], 3);
        let mut count = [0; 3];
        for &p in &part {
            count[p as usize] += 1;
        }
        assert_eq!(count, [16, 16, 16]);
        // part 0 is the left third of the grid
        for (k, &p) in part.iter().enumerate() {
            assert_eq!(p == 0, k % 12 < 4, "point {k}");
        }
    }

    #[test]
    fn more_parts_than_points_leaves_no_point_unassigned() {
        let pts = [[0.0, 0.0], [1.0, 0.0]];
        let part = rcb(&pts, &[1.0, 1.0], 4);
        assert!(part.iter().all(|&p| p < 4));
        assert_ne!(part[0], part[1]);
    }
}
