use std::collections::{BTreeSet, HashSet, VecDeque};
use std::f64::consts::TAU;

use proptest::prelude::*;

use super::array::Entry;
use super::levels::{gap, is_dyadic, is_sibling_merge, level, top};
use super::*;
use crate::gen::{gas, regular_polygon, strict_convex_hull, GasParams};
use crate::geom::{orient, BodyPolygon, Point};
use crate::motion::{orient_poly, Frame, Trajectory};
use crate::num::{Int, Rational, Sign, Time};
use crate::rng::Rng;

// ---------------------------------------------------------------------------
// levels and top
// ---------------------------------------------------------------------------

fn top_brute(i: usize, j: usize, h: u32) -> Option<usize> {
    let m = 1usize << h;
    let g = gap(i, j, h);
    let mut best: Option<usize> = None;
    for d in 1..g {
        let k = (i + d) % m;
        match best {
            Some(b) if level(b, h) >= level(k, h) => {
                assert_ne!(level(b, h), level(k, h), "the maximum level is unique");
            }
            _ => best = Some(k),
        }
    }
    best
}

#[test]
fn hier_top_note_examples() {
    assert_eq!(top(0, 8, 4), Some(4));
    assert_eq!(top(3, 6, 4), Some(4));
    assert_eq!(top(7, 13, 4), Some(8));
    assert_eq!(top(4, 7, 4), Some(6));
    assert_eq!(top(4, 5, 4), None);
    assert_eq!(top(15, 0, 4), None);
    // wrapping and the whole cycle
    assert_eq!(top(12, 4, 4), Some(0));
    assert_eq!(top(0, 0, 4), Some(8));
    assert_eq!(top(3, 3, 4), Some(0));
    assert_eq!(level(0, 4), 4);
    assert_eq!(level(12, 4), 2);
}

#[test]
fn hier_top_all_pairs_16() {
    for h in 1..=4 {
        let m = 1usize << h;
        for i in 0..m {
            for j in 0..m {
                assert_eq!(top(i, j, h), top_brute(i, j, h), "({i}, {j}) in M = {m}");
            }
        }
    }
}

#[test]
fn hier_top_random_pairs_2_pow_20() {
    let h = 20;
    let m = 1usize << h;
    let mut rng = Rng::new(7);
    for round in 0..200 {
        let i = rng.below(m as u64) as usize;
        let j = match round % 4 {
            0 => (i + 1 + rng.below(64) as usize) % m, // short intervals
            1 => i,                                    // whole cycle
            _ => rng.below(m as u64) as usize,
        };
        assert_eq!(top(i, j, h), top_brute(i, j, h), "({i}, {j})");
    }
}

/// Exposed sets over M = 16 as bit masks: pure index logic.
fn mask_pred(s: u32, k: usize, m: usize) -> usize {
    (1..=m)
        .map(|d| (k + m - d) % m)
        .find(|&x| s >> x & 1 == 1)
        .unwrap()
}

fn mask_succ(s: u32, k: usize, m: usize) -> usize {
    (1..=m)
        .map(|d| (k + d) % m)
        .find(|&x| s >> x & 1 == 1)
        .unwrap()
}

fn mask_dyadic(s: u32, h: u32) -> bool {
    let m = 1usize << h;
    s != 0
        && (0..m)
            .filter(|&k| s >> k & 1 == 1)
            .all(|k| is_dyadic(k, mask_succ(s, k, m), h))
}

#[test]
fn hier_dyadic_sets_are_exactly_the_pop_closure() {
    let h = 4;
    let m = 1usize << h;
    // every set reachable from {0} by pops (ignoring geometry)
    let mut seen: HashSet<u32> = HashSet::new();
    let mut queue = VecDeque::from([1u32]);
    seen.insert(1);
    while let Some(s) = queue.pop_front() {
        for k in (0..m).filter(|&k| s >> k & 1 == 1) {
            let i = mask_pred(s, k, m);
            if let Some(t) = top(i, k, h) {
                let t2 = s | 1 << t;
                if seen.insert(t2) {
                    queue.push_back(t2);
                }
            }
        }
    }
    // leaf sets of binary trees of depth <= 4: 1, 2, 5, 26, 677
    assert_eq!(seen.len(), 677);
    for s in 1u32..(1 << m) {
        assert_eq!(mask_dyadic(s, h), seen.contains(&s), "set {s:#06x}");
    }
    // sibling merges stay in the family, and some merge exists until {0}
    for &s in &seen {
        let mut any = false;
        for k in (0..m).filter(|&k| s >> k & 1 == 1) {
            let (p, q) = (mask_pred(s, k, m), mask_succ(s, k, m));
            if is_sibling_merge(p, k, q, h) {
                any = true;
                assert!(seen.contains(&(s & !(1 << k))));
                assert_eq!(top(p, q, h), Some(k));
            }
        }
        assert!(any || s == 1 || s == (1 | 1 << 8), "{s:#06x}");
    }
    // the note's rule k == top(p, q) alone leaves the family: {0,2,4,8,12} − 4
    let s: u32 = 1 | 1 << 2 | 1 << 4 | 1 << 8 | 1 << 12;
    assert!(seen.contains(&s));
    assert_eq!(top(2, 8, h), Some(4));
    assert!(!is_sibling_merge(2, 4, 8, h));
    assert!(!seen.contains(&(s & !(1 << 4))));
}

// ---------------------------------------------------------------------------
// Exposed
// ---------------------------------------------------------------------------

fn exposed_against_btree(m: usize, ops: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut s = Exposed::new(m);
    let mut b: BTreeSet<usize> = BTreeSet::new();
    for step in 0..ops {
        // keep a range of densities: clustered and spread indices
        let k = if rng.chance(0.5) {
            rng.below(m as u64) as usize
        } else {
            (m / 3 + rng.below(200) as usize) % m
        };
        let ins = rng.chance(if step < ops / 2 { 0.7 } else { 0.35 });
        if ins {
            assert_eq!(s.insert(k), b.insert(k));
        } else {
            assert_eq!(s.remove(k), b.remove(&k));
        }
        assert_eq!(s.len(), b.len());
        let q = rng.below(m as u64) as usize;
        assert_eq!(s.contains(q), b.contains(&q));
        let succ = b.range(q + 1..).next().or_else(|| b.iter().next()).copied();
        let pred = b
            .range(..q)
            .next_back()
            .or_else(|| b.iter().next_back())
            .copied();
        assert_eq!(s.succ(q), succ);
        assert_eq!(s.pred(q), pred);
        assert_eq!(s.prev_at_or_before(q), b.range(..=q).next_back().copied());
        assert_eq!(s.rank(q), b.range(..q).count());
        if !b.is_empty() {
            let r = rng.below(b.len() as u64) as usize;
            assert_eq!(s.select(r), b.iter().nth(r).copied());
        }
        assert_eq!(s.select(b.len()), None);
    }
    assert!(s.iter().eq(b.iter().copied()));
    assert_eq!(s.rank(m), b.len());
}

#[test]
fn hier_exposed_matches_btreeset() {
    exposed_against_btree(4, 300, 1);
    exposed_against_btree(64, 1000, 2);
    exposed_against_btree(128, 1000, 3);
    exposed_against_btree(4096, 3000, 4);
    exposed_against_btree(1 << 18, 3000, 5);
    let full = Exposed::full(256);
    assert_eq!(full.len(), 256);
    assert_eq!(full.pred(0), Some(255));
    assert_eq!(full.succ(255), Some(0));
    assert_eq!(full.select(200), Some(200));
    let one = Exposed::from_indices(1 << 12, [77]);
    assert_eq!((one.succ(77), one.pred(77)), (Some(77), Some(77)));
    assert_eq!(Exposed::new(64).succ(3), None);
}

// ---------------------------------------------------------------------------
// Edge arrays on polygons
// ---------------------------------------------------------------------------

fn unit(x: &Int, y: &Int) -> (f64, f64) {
    use dashu_base::{BitTest, UnsignedAbs};
    let bits = |v: &Int| v.clone().unsigned_abs().bit_len();
    let s = bits(x).max(bits(y)).saturating_sub(60);
    let (fx, fy) = ((x >> s).to_f64().value(), (y >> s).to_f64().value());
    let r = fx.hypot(fy);
    (fx / r, fy / r)
}

fn turn_f64(a: &Entry, b: &Entry) -> f64 {
    let ((ax, ay), (bx, by)) = (unit(&a.nx, &a.ny), unit(&b.nx, &b.ny));
    (ax * by - ay * bx).atan2(ax * bx + ay * by)
}

/// Whether a homogeneous point is strictly outside the polygon.
fn strictly_outside(arr: &EdgeArray, p: &HomPoint) -> bool {
    (0..arr.vertex_count()).any(|i| arr.entry(arr.edge_entry(i)).side_hom(p) == Sign::Positive)
}

/// Everything about the array itself; `deep` adds O(n·M) global checks.
fn check_array(body: &BodyPolygon, deep: bool) -> EdgeArray {
    let arr = EdgeArray::new(body);
    let n = body.len();
    let m = arr.m();
    arr.check(body).unwrap();
    assert!(
        m.is_power_of_two() && m >= n && m <= 4 * n,
        "M = {m}, n = {n}"
    );
    assert_eq!(1usize << arr.h(), m);
    // real edges once, in order
    let reals: Vec<usize> = (0..m).filter(|&k| !arr.entry(k).is_zero_length()).collect();
    assert_eq!(reals.len(), n);
    for (i, &k) in reals.iter().enumerate() {
        assert_eq!(arr.edge_entry(i), k);
        assert_eq!(arr.base_vertex_of_entry_start(k), i);
        assert_eq!(arr.base_vertex_of_entry_end(k), (i + 1) % n);
    }
    // turns: positive, below 2π/max(n, 5) up to rounding, summing to 2π
    let bound = TAU / n.max(5) as f64 * 1.0102 + 1e-12;
    let mut total = 0.0;
    for k in 0..m {
        let t = turn_f64(arr.entry(k), arr.entry((k + 1) % m));
        assert!(t > 0.0, "turn {t} after entry {k}");
        assert!(
            t <= bound,
            "turn {t} after entry {k} > {bound} (n = {n}, M = {m})"
        );
        total += t;
    }
    assert!((total - TAU).abs() < 1e-6, "total turn {total}");
    // adjacent entries meet at the real vertex
    for k in 0..m {
        let j = (k + 1) % m;
        let v = arr.base_vertex_of_entry_start(j);
        assert_eq!(arr.av_is_real(k, j), Some(v));
        assert!(arr.av(k, j).unwrap().is_vertex(body, v));
    }
    // adjacent real edges meet at their vertex
    for v in 0..n {
        let (a, b) = (arr.edge_entry((v + n - 1) % n), arr.edge_entry(v));
        assert_eq!(arr.av_is_real(a, b), Some(v));
        assert!(arr.av(a, b).unwrap().is_vertex(body, v));
        if n > 3 {
            let c = arr.edge_entry((v + 1) % n);
            assert_eq!(arr.av_is_real(a, c), None);
        }
    }
    if deep {
        arr.check_containment_brute(body, &Exposed::full(m))
            .unwrap();
    }
    arr
}

/// The exposed-set life cycle on one polygon: coarsest, random pops and
/// merges (checked after each), full refinement, full coarsening.
fn check_hierarchy(body: &BodyPolygon, arr: &EdgeArray, seed: u64, steps: usize, deep: bool) {
    let n = body.len();
    let mut s = arr.coarsest();
    assert!(s.len() >= 5 && s.len() <= 40, "|coarsest| = {}", s.len());
    let audit = |s: &Exposed| {
        arr.check_exposed(body, s).unwrap();
        if deep {
            arr.check_containment_brute(body, s).unwrap();
            for k in s.iter() {
                let i = s.pred(k).unwrap();
                let p = arr.av(i, k).unwrap();
                match arr.av_is_real(i, k) {
                    Some(v) => assert!(p.is_vertex(body, v)),
                    None => assert!(strictly_outside(arr, &p), "av({i}, {k}) not outside"),
                }
            }
        }
    };
    audit(&s);
    let mut rng = Rng::new(seed);
    for _ in 0..steps {
        let k = s.select(rng.below(s.len() as u64) as usize).unwrap();
        if rng.chance(0.6) {
            let i = s.pred(k).unwrap();
            let before = arr.av_is_real(i, k);
            match arr.pop(&mut s, k) {
                Some(t) => {
                    assert!(before.is_none());
                    assert_eq!(Some(t), arr.top(i, k));
                    assert_eq!((s.pred(t), s.pred(k)), (Some(i), Some(t)));
                    // the merge undoes the pop
                    assert!(arr.merge_ok(&s, t));
                }
                None => assert!(before.is_some()),
            }
        } else {
            let ok = arr.merge_ok(&s, k);
            assert_eq!(arr.merge(&mut s, k), ok);
            assert_eq!(s.contains(k), !ok);
        }
        audit(&s);
    }
    // pop everything: every vertex real, every base vertex present
    loop {
        let ks: Vec<usize> = s.iter().collect();
        let mut popped = false;
        for k in ks {
            popped |= arr.pop(&mut s, k).is_some();
        }
        if !popped {
            break;
        }
    }
    audit(&s);
    let mut reals = vec![false; n];
    for k in s.iter() {
        let i = s.pred(k).unwrap();
        let v = arr
            .av_is_real(i, k)
            .expect("fully popped: every vertex real");
        reals[v] = true;
        assert!(arr.vertex_of(body, &s, k).unwrap().is_vertex(body, v));
    }
    assert!(reals.iter().all(|&r| r), "every real vertex appears");
    // merge everything possible: stays valid, ends at most as fine as coarsest
    loop {
        let ks: Vec<usize> = s.iter().collect();
        let mut merged = false;
        for k in ks {
            merged |= arr.merge(&mut s, k);
        }
        if !merged {
            break;
        }
    }
    audit(&s);
    assert!(s.len() <= arr.coarsest().len());
}

#[test]
fn hier_regular_polygons() {
    for n in 3..=(1usize << 12) {
        let small = n <= 64;
        if !(small || n.is_power_of_two() || n % 97 == 0 || n == 4095) {
            // cheap checks only: every n up to 1024, then every 7th
            if n > 1024 && n % 7 != 0 {
                continue;
            }
            let body = BodyPolygon::new(&regular_polygon(n, 1.0, 0.1)).unwrap();
            let arr = EdgeArray::new(&body);
            arr.check(&body).unwrap();
            assert!(arr.m() <= 4 * n);
            arr.check_exposed(&body, &arr.coarsest()).unwrap();
            continue;
        }
        let body = BodyPolygon::new(&regular_polygon(n, 1.0 + n as f64, 0.1)).unwrap();
        let arr = check_array(&body, small);
        check_hierarchy(&body, &arr, n as u64, if small { 300 } else { 60 }, small);
        if n.is_power_of_two() && n >= 8 {
            assert_eq!(arr.m(), n, "regular 2^k-gon: no replication");
            // the plain structure is the case S = everything: id k is vertex k
            let all = Exposed::full(n);
            for (k, p) in arr.approx_polygon(&body, &all) {
                assert!(p.is_vertex(&body, k));
                assert!(arr.av(s_pred(&all, k), k).unwrap().is_vertex(&body, k));
            }
            assert_eq!(arr.coarsest().len(), 8);
        }
    }
}

fn s_pred(s: &Exposed, k: usize) -> usize {
    s.pred(k).unwrap()
}

/// Random convex polygons of many shapes: gas polygons, hulls of random
/// points in thin boxes, polygons with a few huge exterior angles, mixed
/// scales.
fn random_polygons(seed: u64) -> Vec<Vec<[f64; 2]>> {
    let mut out = Vec::new();
    let sc = gas(&GasParams {
        k: 12,
        min_n: 3,
        max_n: 60,
        seed,
        ..Default::default()
    });
    out.extend(sc.polygons.into_iter().map(|p| p.vertices));
    let mut rng = Rng::new(seed ^ 0xabcdef);
    for _ in 0..12 {
        let k = rng.range_usize(3, 200);
        let (sx, sy) = (
            10f64.powf(rng.range_f64(-6.0, 6.0)),
            10f64.powf(rng.range_f64(-3.0, 3.0)),
        );
        let pts: Vec<[f64; 2]> = (0..k)
            .map(|_| {
                let a = rng.range_f64(0.0, TAU);
                let r = if rng.chance(0.5) { 1.0 } else { rng.next_f64() };
                [sx * r * a.cos(), sy * r * a.sin()]
            })
            .collect();
        let hull = strict_convex_hull(&pts);
        if hull.len() >= 3 {
            out.push(hull);
        }
    }
    // a dense arc plus two far points: a few very large exterior angles
    let mut arc: Vec<[f64; 2]> = (0..100)
        .map(|i| {
            let a = 0.3 * i as f64 / 100.0;
            [a.cos(), a.sin()]
        })
        .collect();
    arc.push([-1e3, 1.0]);
    arc.push([-1.0, -1e-3]);
    out.push(strict_convex_hull(&arc));
    // extreme aspect ratio and mixed magnitudes
    out.push(vec![[0.0, 0.0], [1e9, 0.0], [1e9, 1e-9], [0.0, 1e-9]]);
    out.push(vec![[0.0, 0.0], [1e6, 1e-9], [0.5, 1e6]]);
    out.push(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    out.push(vec![[-1e300, -1e300], [1e300, -1e300], [0.0, 1e-300]]);
    out
}

#[test]
fn hier_random_polygons() {
    for seed in 0..6u64 {
        for (idx, verts) in random_polygons(seed).into_iter().enumerate() {
            let body = BodyPolygon::new(&verts).unwrap();
            let deep = body.len() <= 80;
            let arr = check_array(&body, deep);
            check_hierarchy(&body, &arr, seed * 1000 + idx as u64, 200, deep);
        }
    }
}

#[test]
fn hier_note_interpolation_is_uneven() {
    // A vertex between a long and a short edge: the note's (r−j)·a + j·b
    // puts almost the whole turn in the last step.
    let a = (Int::from(0), Int::from(-1_000_000)); // long edge along +x
    let b = (Int::from(1), Int::from(1)); // short edge
    let r = 8;
    let mut prev = a.clone();
    let mut steps = Vec::new();
    for j in 1..=r {
        let v = (
            Int::from(r - j) * &a.0 + Int::from(j) * &b.0,
            Int::from(r - j) * &a.1 + Int::from(j) * &b.1,
        );
        let e = |p: &(Int, Int)| Entry {
            nx: p.0.clone(),
            ny: p.1.clone(),
            c: Int::ZERO,
            start: 0,
            end: 0,
        };
        steps.push(turn_f64(&e(&prev), &e(&v)));
        prev = v;
    }
    let total: f64 = steps.iter().sum();
    assert!(steps[r - 1] > 0.99 * total, "{steps:?}");
}

#[test]
fn hier_check_rejects_corrupted_sets() {
    let body = BodyPolygon::new(&regular_polygon(100, 3.0, 0.2)).unwrap();
    let arr = EdgeArray::new(&body);
    let m = arr.m();
    let mut s = arr.coarsest();
    let mut rng = Rng::new(3);
    for _ in 0..50 {
        let k = s.select(rng.below(s.len() as u64) as usize).unwrap();
        arr.pop(&mut s, k);
    }
    arr.check_exposed(&body, &s).unwrap();
    // 0 missing: the gap across 0 is not dyadic
    let mut bad = s.clone();
    bad.remove(0);
    assert!(arr.check_exposed(&body, &bad).is_err());
    // an index that splits a gap off its midpoint
    let (i, j) = s
        .iter()
        .map(|i| (i, s.succ(i).unwrap()))
        .find(|&(i, j)| gap(i, j, arr.h()) >= 4)
        .unwrap();
    let mut bad = s.clone();
    bad.insert((i + 1) % m);
    assert!(arr.check_exposed(&body, &bad).is_err(), "({i}, {j})");
    // removing an element that is not a sibling merge leaves a gap that is
    // not dyadic (two dyadic blocks make one only as its two halves)
    let k = s
        .iter()
        .find(|&k| !is_sibling_merge(s.pred(k).unwrap(), k, s.succ(k).unwrap(), arr.h()))
        .unwrap();
    let mut bad = s.clone();
    bad.remove(k);
    assert!(arr.check_exposed(&body, &bad).is_err());
    // a sibling merge whose turn is too large is refused: the layer above
    // the coarsest has a non-acute gap, whose midpoint is exposed
    let step = 1usize << arr.coarsest_level();
    let c = arr.coarsest();
    let a = (0..m)
        .step_by(2 * step)
        .find(|&a| !arr.turn_is_acute(a, (a + 2 * step) % m))
        .unwrap();
    assert!(is_sibling_merge(a, a + step, (a + 2 * step) % m, arr.h()));
    assert!(!arr.merge_ok(&c, a + step));
    // dyadic but too coarse: the layer above the coarsest
    let l = arr.coarsest_level() + 1;
    let coarse = Exposed::from_indices(m, (0..m).step_by(1 << l));
    assert!(arr.check_exposed(&body, &coarse).is_err());
    // the empty set, a foreign universe
    assert!(arr.check_exposed(&body, &Exposed::new(m)).is_err());
    assert!(arr.check_exposed(&body, &Exposed::full(2 * m)).is_err());
}

#[test]
fn hier_check_rejects_corrupted_arrays() {
    let body = BodyPolygon::new(&regular_polygon(9, 1.0, 0.0)).unwrap();
    let arr = EdgeArray::new(&body);
    arr.check(&body).unwrap();
    let m = arr.m();
    let k = (0..m).find(|&k| arr.entry(k).is_zero_length()).unwrap();
    // a line pushed outwards no longer passes through its vertex
    let mut bad = arr.clone();
    bad.entry_mut(k).c += Int::ONE;
    assert!(bad.check(&body).is_err());
    // a normal outside the vertex's cone
    let mut bad = arr.clone();
    let e = bad.entry_mut(k);
    e.nx = -e.nx.clone();
    assert!(bad.check(&body).is_err());
    // a real edge with a wrong offset
    let mut bad = arr.clone();
    bad.entry_mut(0).c -= Int::ONE;
    assert!(bad.check(&body).is_err());
    // another polygon
    let other = BodyPolygon::new(&regular_polygon(9, 1.0, 0.01)).unwrap();
    assert!(arr.check(&other).is_err());
}

// ---------------------------------------------------------------------------
// Moving approximation vertices
// ---------------------------------------------------------------------------

#[test]
fn hier_frame_homogeneous() {
    let t0 = Rational::zero();
    let polys = [
        regular_polygon(37, 0.75, 0.3),
        vec![[0.0, 0.0], [1e6, 1e-9], [0.5, 1e6]],
        vec![[0.125, 0.0], [3.0, 0.5], [2.0, 2.0], [-1.0, 1.0]],
    ];
    let mut rng = Rng::new(11);
    for verts in &polys {
        let body = BodyPolygon::new(verts).unwrap();
        let arr = EdgeArray::new(&body);
        for _ in 0..4 {
            let pos =
                Point::from_f64([rng.range_f64(-5.0, 5.0), rng.range_f64(-5.0, 5.0)]).unwrap();
            let vel =
                Point::from_f64([rng.range_f64(-2.0, 2.0), rng.range_f64(-2.0, 2.0)]).unwrap();
            let tr = Trajectory::through(&t0, &pos, vel);
            let frame = Frame::new(&tr, &body);
            for i in 0..body.len() {
                assert_eq!(
                    HomPoint::vertex(&body, i).moving(&frame),
                    frame.vertex(&body, i)
                );
            }
            // approximation vertices of a refined set, and their static positions
            let mut s = arr.coarsest();
            for _ in 0..10 {
                let k = s.select(rng.below(s.len() as u64) as usize).unwrap();
                arr.pop(&mut s, k);
            }
            let pts: Vec<HomPoint> = arr
                .approx_polygon(&body, &s)
                .into_iter()
                .map(|p| p.1)
                .collect();
            let world = |p: &HomPoint| pos.add(&p.to_point(body.exp()));
            let tt = Rational::from_f64(rng.range_f64(-3.0, 3.0)).unwrap();
            for p in &pts {
                assert_eq!(p.moving(&frame).at(&t0), world(p));
                // the point translates with the body
                let shifted = world(p).add(&tr.velocity().scale(&tt));
                assert_eq!(p.moving(&frame).at(&tt), shifted);
            }
            for _ in 0..30 {
                let pick = |rng: &mut Rng| &pts[rng.below(pts.len() as u64) as usize];
                let (a, b, c) = (pick(&mut rng), pick(&mut rng), pick(&mut rng));
                let cert = orient_poly(&a.moving(&frame), &b.moving(&frame), &c.moving(&frame));
                assert_eq!(
                    cert.sign_at(&Time::zero()),
                    orient(&world(a), &world(b), &world(c))
                );
            }
            // the approximate polygon is convex and counter-clockwise
            for w in 0..pts.len() {
                let (a, b, c) = (
                    &pts[w],
                    &pts[(w + 1) % pts.len()],
                    &pts[(w + 2) % pts.len()],
                );
                assert_ne!(orient(&world(a), &world(b), &world(c)), Sign::Negative);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Property tests
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn hier_prop_random_hulls(
        pts in prop::collection::vec((-1e3f64..1e3, -1e3f64..1e3), 3..120),
        stretch in -4.0f64..4.0,
        seed in any::<u64>(),
    ) {
        let s = 10f64.powf(stretch);
        let pts: Vec<[f64; 2]> = pts.into_iter().map(|(x, y)| [x * s, y]).collect();
        let hull = strict_convex_hull(&pts);
        prop_assume!(hull.len() >= 3);
        let body = BodyPolygon::new(&hull).unwrap();
        let arr = check_array(&body, true);
        check_hierarchy(&body, &arr, seed, 150, true);
    }

    #[test]
    fn hier_prop_top(h in 1u32..=30, i in any::<u64>(), d in any::<u64>()) {
        let m = 1usize << h;
        let i = (i as usize) & (m - 1);
        let j = (i + (d as usize) % m) & (m - 1);
        if let Some(t) = top(i, j, h) {
            let (g, off) = (gap(i, j, h), (t + m - i) % m);
            prop_assert!(off >= 1 && off < g);
            // t is an odd multiple of 2^l (or 0): the nearest indices of level
            // >= l are t ± 2^l, and they are not strictly inside
            let span = 1usize << level(t, h);
            prop_assert!(off <= span && off + span >= g);
        } else {
            prop_assert_eq!(gap(i, j, h), 1);
        }
    }
}

#[test]
#[ignore = "large: run in release to see the linear build"]
fn hier_build_2_pow_20() {
    for n in [1 << 16, 1 << 18] {
        let body = BodyPolygon::new(&regular_polygon(n - 1, 1.0, 0.25)).unwrap();
        let start = std::time::Instant::now();
        let arr = EdgeArray::new(&body);
        eprintln!(
            "n = {}: M = {}, built in {:?}",
            n - 1,
            arr.m(),
            start.elapsed()
        );
    }
    let n = 1 << 20;
    let body = BodyPolygon::new(&regular_polygon(n, 1.0, 0.25)).unwrap();
    let start = std::time::Instant::now();
    let arr = EdgeArray::new(&body);
    eprintln!("n = {n}: M = {}, built in {:?}", arr.m(), start.elapsed());
    arr.check(&body).unwrap();
    assert_eq!(arr.m(), n);
    arr.check_exposed(&body, &arr.coarsest()).unwrap();
    let odd = BodyPolygon::new(&regular_polygon(n - 3, 1.0, 0.25)).unwrap();
    let start = std::time::Instant::now();
    let arr = EdgeArray::new(&odd);
    eprintln!(
        "n = {}: M = {}, built in {:?}",
        n - 3,
        arr.m(),
        start.elapsed()
    );
    arr.check(&odd).unwrap();
    assert_eq!(arr.m(), n);
}
