//! Broad phases against the O(N^2) brute force, exclusions, and the refresh criterion.

use crate::common;
use common::{Rng, random_triangle};
use fdem_contact::broad_parry::ParryBroadPhase;
use fdem_contact::narrow::separated;
use fdem_contact::nbs::Nbs;
use fdem_contact::{
    BoundingCircles, Contact, ContactLaw, ContactLaws, ContactSettings, Exclusions,
    brute_force_couples,
};
use proptest::prelude::*;

/// Positions, triangles and bonded pairs.
type Cloud = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[u32; 2]>);

/// A random cloud: triangles of random size (ratio up to `spread`), orientation and place in a
/// box of side `box_side`; with probability `p_share` a triangle reuses a node of the previous
/// one (a connected pair); `n_bond` random bonded pairs.
fn cloud(seed: u64, n: usize, box_side: f64, spread: f64, p_share: f64, n_bond: usize) -> Cloud {
    let mut rng = Rng(seed);
    let mut x = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    for i in 0..n {
        let c = [rng.range(0.0, box_side), rng.range(0.0, box_side)];
        let s = rng.range(1.0 / spread, 1.0);
        let v = random_triangle(&mut rng, c, s);
        let base = x.len() as u32;
        x.extend_from_slice(&v);
        let mut t = [base, base + 1, base + 2];
        if i > 0 && rng.f() < p_share {
            // Reuse a node of the previous triangle (positions need not match for detection).
            t[0] = tris[i - 1][(rng.next_u64() % 3) as usize];
        }
        tris.push(t);
    }
    let mut bonded = Vec::new();
    for _ in 0..n_bond {
        let a = (rng.next_u64() % n as u64) as u32;
        let b = (rng.next_u64() % n as u64) as u32;
        if a != b {
            bonded.push([a, b]);
        }
    }
    (x, tris, bonded)
}

fn check_all(x: &[[f64; 2]], tris: &[[u32; 3]], bonded: &[[u32; 2]], b: f64) -> usize {
    let mut circles = BoundingCircles::default();
    circles.update(x, tris);
    let mut excl = Exclusions::new();
    excl.set_bonded(tris.len(), bonded);
    let brute = brute_force_couples(&circles, b, |i, j| excl.excluded(tris, i, j));
    let mut nbs_out = Vec::new();
    Nbs::new().find_couples(&circles, b, tris, &excl, &mut nbs_out);
    assert_eq!(nbs_out, brute, "NBS differs from brute force");
    let mut parry_out = Vec::new();
    ParryBroadPhase::new().find_couples(&circles, b, tris, &excl, &mut parry_out);
    assert_eq!(parry_out, brute, "parry differs from brute force");
    brute.len()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn nbs_and_parry_find_exactly_the_brute_force_couples(
        seed in any::<u64>(),
        n in 2usize..400,
        box_side in 1.0f64..40.0,
        spread in 1.0f64..4.0,
        b in 0.0f64..0.5,
        p_share in 0.0f64..0.5,
        n_bond in 0usize..50,
    ) {
        let (x, tris, bonded) = cloud(seed, n, box_side, spread, p_share, n_bond);
        check_all(&x, &tris, &bonded, b);
    }
}

#[test]
fn dense_cloud_has_many_couples_and_matches_brute_force() {
    // A guard that the property test is not vacuous: a dense cloud gives thousands of couples.
    let (x, tris, bonded) = cloud(7, 2000, 20.0, 3.0, 0.3, 200);
    let k = check_all(&x, &tris, &bonded, 0.1);
    assert!(k > 3000, "only {k} couples");
}

#[test]
fn exclusions_remove_shared_node_and_bonded_pairs() {
    // Two overlapping triangles sharing node 0, and two bonded ones: no couples; unbonding
    // restores the pair.
    let x = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [0.0, 0.5],
        [2.0, 2.0],
        [3.0, 2.0],
        [2.0, 3.0],
        [2.1, 2.1],
        [3.1, 2.1],
        [2.1, 3.1],
    ];
    let tris = vec![[0, 1, 2], [0, 3, 4], [5, 6, 7], [8, 9, 10]];
    let mut c = Contact::new(
        ContactSettings {
            buffer: 0.01,
            ..Default::default()
        },
        ContactLaws::uniform(1, ContactLaw::with_penalty(1.0)),
    );
    c.set_bonded(4, &[[3, 2]]);
    c.update_detection(&x, &tris);
    assert!(c.couples().is_empty(), "{:?}", c.couples());
    c.set_bonded(4, &[]);
    assert!(c.update_detection(&x, &tris));
    assert_eq!(c.couples(), &[[2, 3]]);
}

#[test]
fn far_outlier_does_not_blow_up_memory_and_stays_exact() {
    // One triangle 1e12 m away: the cell count is capped, the result is still exact.
    let (mut x, tris, _) = cloud(9, 300, 10.0, 2.0, 0.0, 0);
    for k in 0..3 {
        x[k][0] += 1e12;
    }
    check_all(&x, &tris, &[], 0.05);
}

/// Random walk of a cloud; couples are only redetected when a node moved b/2. At every step
/// every pair whose bounding circles touch now (b = 0) must be among the couples, and with the
/// narrow filter every pair whose triangles are not separated now.
fn refresh_never_misses(narrow: bool) {
    let (mut x, tris, _) = cloud(11, 600, 15.0, 2.0, 0.0, 0);
    let mut rng = Rng(12);
    let vel: Vec<[f64; 2]> = (0..x.len() / 3)
        .map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)])
        .collect();
    let mut c = Contact::new(
        ContactSettings {
            buffer: 0.2,
            narrow,
            ..Default::default()
        },
        ContactLaws::uniform(1, ContactLaw::with_penalty(1.0)),
    );
    let mut circles = BoundingCircles::default();
    let (mut redetections, mut overlapping) = (0, 0);
    for _step in 0..200 {
        for (t, v) in vel.iter().enumerate() {
            for k in 0..3 {
                x[3 * t + k][0] += 0.013 * v[0];
                x[3 * t + k][1] += 0.013 * v[1];
            }
        }
        redetections += c.update_detection(&x, &tris) as usize;
        circles.update(&x, &tris);
        let now = brute_force_couples(&circles, 0.0, |_, _| false);
        for p in &now {
            let v = |t: u32| tris[t as usize].map(|n| x[n as usize]);
            let touch = !separated(&v(p[0]), &v(p[1]), 0.0);
            overlapping += touch as usize;
            if !narrow || touch {
                assert!(c.couples().binary_search(p).is_ok(), "missed {p:?}");
            }
        }
    }
    // Max speed sqrt(2) * 0.013 per step: refresh about every 0.1/0.018 = 5 steps.
    assert!(redetections > 20 && redetections < 100, "{redetections}");
    assert!(
        overlapping > 1000,
        "only {overlapping} overlapping pair-steps"
    );
}

#[test]
fn refresh_criterion_never_misses_a_contact() {
    refresh_never_misses(false);
}

#[test]
fn refresh_criterion_never_misses_a_contact_with_the_narrow_filter() {
    refresh_never_misses(true);
}

#[test]
fn narrow_filter_drops_only_separated_candidates() {
    // The detection with the filter lists exactly the circle candidates that no edge line
    // separates by more than b, on a dense cloud where it drops a good share of them.
    let (x, tris, bonded) = cloud(5, 1500, 20.0, 3.0, 0.2, 100);
    let b = 0.1;
    let run = |narrow: bool| {
        let mut c = Contact::new(
            ContactSettings {
                buffer: b,
                narrow,
                ..Default::default()
            },
            ContactLaws::uniform(1, ContactLaw::with_penalty(1.0)),
        );
        c.set_bonded(tris.len(), &bonded);
        c.detect(&x, &tris);
        c.couples().to_vec()
    };
    let (all, kept) = (run(false), run(true));
    let v = |t: u32| tris[t as usize].map(|n| x[n as usize]);
    let want: Vec<[u32; 2]> = all
        .iter()
        .copied()
        .filter(|p| !separated(&v(p[0]), &v(p[1]), b))
        .collect();
    assert_eq!(kept, want);
    // Not vacuous: this cloud has 2 000+ candidates and the filter drops a fifth or more.
    assert!(all.len() > 2000, "{}", all.len());
    assert!(
        5 * (all.len() - kept.len()) > all.len(),
        "{} of {}",
        kept.len(),
        all.len()
    );
}

/// The parallel broad phase (bands of rows) on 1- and 2-thread pools against the serial
/// sweep and the brute force: the same sorted list, element for element.
#[test]
fn parallel_nbs_matches_serial_and_brute_force_on_1_and_2_threads() {
    for (seed, n, side, brute) in [(11, 12_000, 50.0, true), (12, 40_000, 90.0, false)] {
        // no shared nodes here: a shared node is placed with the other triangle, so with
        // p_share > 0 long triangles make the cloud nearly all-pairs (the property test
        // covers shared nodes)
        let (x, tris, bonded) = cloud(seed, n, side, 3.0, 0.0, n / 10);
        let mut circles = BoundingCircles::default();
        circles.update(&x, &tris);
        let mut excl = Exclusions::new();
        excl.set_bonded(tris.len(), &bonded);
        let b = 0.1;
        let mut serial = Vec::new();
        Nbs::new().find_couples_serial(&circles, b, &tris, &excl, &mut serial);
        // Not vacuous: about 1 couple per triangle or more at this density.
        assert!(serial.len() > n / 2, "only {} couples", serial.len());
        if brute {
            let want = brute_force_couples(&circles, b, |i, j| excl.excluded(&tris, i, j));
            assert_eq!(serial, want, "serial NBS differs from brute force");
        }
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut nbs = Nbs::new();
            let mut out = Vec::new();
            // twice with the same scratch: the warm search gives the same list
            for _ in 0..2 {
                pool.install(|| nbs.find_couples(&circles, b, &tris, &excl, &mut out));
                assert_eq!(out, serial, "{threads} threads, {n} triangles");
            }
        }
    }
}

/// The refresh check (single-precision filter, then the exact test on the chunks it cannot
/// clear) answers exactly the double-precision criterion `|x - x_det|^2 >= (b/2)^2` (or NaN)
/// on every trial: nodes moved up to just below, at and just above `b/2`, far from the
/// origin (larger rounding of the copy) and near it, and a NaN; on 1 and 2 threads.
#[test]
fn refresh_check_answers_the_exact_criterion_on_1_and_2_threads() {
    // 9 000 triangles, 27 000 nodes: four chunks of the check.
    let (x0, tris, _) = cloud(21, 9_000, 90.0, 3.0, 0.0, 0);
    let b = 0.1;
    let half = 0.5 * b;
    let exact = |x: &[[f64; 2]], xd: &[[f64; 2]]| {
        x.iter().zip(xd).any(|(a, d)| {
            let v = [a[0] - d[0], a[1] - d[1]];
            let d2 = v[0] * v[0] + v[1] * v[1];
            d2 >= half * half || d2.is_nan()
        })
    };
    for offset in [0.0, 1.0e3] {
        let xd: Vec<[f64; 2]> = x0.iter().map(|p| [p[0] + offset, p[1] + offset]).collect();
        let mut rng = Rng(5);
        // (node, factor of b/2, direction): one node moved by that much, every other node
        // jiggled by up to 0.4 b/2
        let mut trials = Vec::new();
        for k in 0..36 {
            let f = match k % 6 {
                0 => 0.5,
                1 => 1.0 - 1e-7,
                2 => 1.0 - 1e-13,
                3 => 1.0,
                4 => 1.0 + 1e-13,
                _ => 1.5,
            };
            let node = (rng.next_u64() % xd.len() as u64) as usize;
            trials.push((node, f, rng.range(0.0, std::f64::consts::TAU)));
        }
        let mut answers = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut c = Contact::new(
                ContactSettings {
                    buffer: b,
                    ..Default::default()
                },
                ContactLaws::uniform(1, ContactLaw::with_penalty(1.0)),
            );
            let mut rng = Rng(9);
            let mut got = Vec::new();
            let (mut n_true, mut n_false) = (0, 0);
            let mut at_xd = false;
            for (t, &(node, f, a)) in trials.iter().enumerate() {
                // back to a detection at xd after a trial that redetected
                if !at_xd {
                    c.invalidate();
                    assert!(pool.install(|| c.update_detection(&xd, &tris)));
                }
                let mut x: Vec<[f64; 2]> = xd
                    .iter()
                    .map(|p| {
                        let (r, s) = (rng.range(0.0, 0.4 * half), rng.range(0.0, 6.3));
                        [p[0] + r * s.cos(), p[1] + r * s.sin()]
                    })
                    .collect();
                x[node] = [
                    xd[node][0] + f * half * a.cos(),
                    xd[node][1] + f * half * a.sin(),
                ];
                if t == 7 {
                    x[node][1] = f64::NAN;
                }
                let want = exact(&x, &xd);
                let moved = pool.install(|| c.update_detection(&x, &tris));
                assert_eq!(moved, want, "trial {t}: factor {f}, offset {offset}");
                at_xd = !moved;
                if want {
                    n_true += 1;
                } else {
                    n_false += 1;
                }
                got.push(moved);
            }
            // Both answers occur (not vacuous).
            assert!(
                n_true >= 10 && n_false >= 10,
                "{n_true} moved, {n_false} not"
            );
            answers.push(got);
        }
        assert_eq!(answers[0], answers[1], "1 and 2 threads answer differently");
    }
}

/// Bounding circles of 20 000 triangles (the parallel path) on 1- and 2-thread pools equal,
/// bit for bit, those computed serially (blocks of 4 000 triangles, below the parallel
/// threshold), including a triangle with a NaN vertex.
#[test]
fn parallel_bounding_circles_match_the_serial_ones_on_1_and_2_threads() {
    let (mut x, tris, _) = cloud(31, 20_000, 120.0, 3.0, 0.0, 0);
    x[3 * 777][0] = f64::NAN;
    let bits = |c: &BoundingCircles| -> Vec<u64> {
        c.c.iter()
            .flat_map(|p| [p[0].to_bits(), p[1].to_bits()])
            .chain(c.r.iter().map(|r| r.to_bits()))
            .collect()
    };
    let mut serial = BoundingCircles::default();
    let mut block = BoundingCircles::default();
    for part in tris.chunks(4000) {
        block.update(&x, part);
        serial.c.extend_from_slice(&block.c);
        serial.r.extend_from_slice(&block.r);
    }
    assert!(serial.r[777].is_nan() && serial.r[778].is_finite());
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut c = BoundingCircles::default();
        pool.install(|| c.update(&x, &tris));
        assert_eq!(bits(&c), bits(&serial), "{threads} threads");
    }
}
