//! Tests of the generators: validity per the contract (checked in doubles
//! and exact predicates), determinism, planned contacts and gaps.

use std::f64::consts::TAU;

use super::*;
use crate::geom::{orient, Point};
use crate::num::Rational;
use crate::scenario::{FlightPlanChange, PolygonSpec};

/// Contract checks in doubles and exact predicates; `Err` says what broke.
pub(super) fn check_valid(sc: &Scenario) -> Result<(), String> {
    if !(sc.until.is_finite() && sc.until > 0.0) {
        return Err(format!("until {}", sc.until));
    }
    let mut ids = std::collections::HashSet::new();
    for p in &sc.polygons {
        if p.id.is_empty() || !ids.insert(p.id.clone()) {
            return Err(format!("bad or duplicate id {:?}", p.id));
        }
        check_polygon(&p.vertices).map_err(|e| format!("polygon {:?}: {e}", p.id))?;
        let nums = p
            .vertices
            .iter()
            .flatten()
            .chain(&p.position)
            .chain(&p.velocity);
        if nums.clone().any(|x| !x.is_finite()) {
            return Err(format!("polygon {:?}: non-finite number", p.id));
        }
        if p.fixed && p.velocity != [0.0, 0.0] {
            return Err(format!("fixed polygon {:?} moves", p.id));
        }
    }
    let mut seen = std::collections::HashSet::new();
    for c in &sc.flight_plan_changes {
        let Some(p) = sc.polygons.iter().find(|p| p.id == c.id) else {
            return Err(format!("change for unknown {:?}", c.id));
        };
        if p.fixed {
            return Err(format!("change for fixed {:?}", c.id));
        }
        if !(c.time > 0.0 && c.time <= sc.until) {
            return Err(format!("change time {} out of range", c.time));
        }
        if !seen.insert((c.id.clone(), c.time.to_bits())) {
            return Err(format!("duplicate change {:?} at {}", c.id, c.time));
        }
    }
    for i in 0..sc.polygons.len() {
        for j in i + 1..sc.polygons.len() {
            let (a, b) = (&sc.polygons[i], &sc.polygons[j]);
            if relation_at(a, b, &[], &[], 0.0) != Relation::Apart {
                return Err(format!("{:?} and {:?} not disjoint at 0", a.id, b.id));
            }
        }
    }
    Ok(())
}

fn check_polygon(v: &[[f64; 2]]) -> Result<(), String> {
    let n = v.len();
    if n < 3 {
        return Err(format!("{n} vertices"));
    }
    let mut turning = 0.0;
    for i in 0..n {
        let (a, b, c) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
        if a == b {
            return Err(format!("repeated vertex {i}"));
        }
        if orient_exact(a, b, c) <= 0 {
            return Err(format!("not strictly convex CCW at vertex {i}"));
        }
        let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
        turning += (e1[0] * e2[1] - e1[1] * e2[0]).atan2(e1[0] * e2[0] + e1[1] * e2[1]);
    }
    if (turning - TAU).abs() > 1e-6 {
        return Err(format!("winds {} turns", turning / TAU));
    }
    Ok(())
}

#[derive(Debug, PartialEq, Eq)]
pub(super) enum Relation {
    Apart,
    Touching,
    Overlapping,
}

/// The exact value of a finite double.
fn exact(x: f64) -> Rational {
    Rational::from_f64(x).expect("exact arithmetic on a non-finite number")
}

/// The exact point of two finite doubles.
fn exact_point(p: [f64; 2]) -> Point {
    Point::from_f64(p).expect("exact arithmetic on a non-finite number")
}

/// Position of `p` at time `t` (exact dyadic), given its changes.
fn position_at(p: &PolygonSpec, changes: &[FlightPlanChange], t: f64) -> Point {
    let mut ch: Vec<&FlightPlanChange> = changes.iter().filter(|c| c.id == p.id).collect();
    ch.sort_by(|a, b| a.time.total_cmp(&b.time));
    let mut pos = exact_point(p.position);
    let mut v = p.velocity;
    let mut now = Rational::zero();
    for c in ch {
        if c.time >= t {
            break;
        }
        let ct = exact(c.time);
        pos = pos.add(&exact_point(v).scale(&ct.sub(&now)));
        now = ct;
        v = c.velocity;
    }
    pos.add(&exact_point(v).scale(&exact(t).sub(&now)))
}

/// Exact relation of two polygons (no collision response) at time `t`.
pub(super) fn relation_at(
    a: &PolygonSpec,
    b: &PolygonSpec,
    ca: &[FlightPlanChange],
    cb: &[FlightPlanChange],
    t: f64,
) -> Relation {
    let pa = position_at(a, ca, t);
    let pb = position_at(b, cb, t);
    let world = |p: &Point, vs: &[[f64; 2]]| -> Vec<Point> {
        vs.iter().map(|&v| p.add(&exact_point(v))).collect()
    };
    let wa = world(&pa, &a.vertices);
    let wb = world(&pb, &b.vertices);
    // Quick filter in doubles: bounding boxes far apart.
    let bbox = |w: &[Point]| {
        let xs: Vec<f64> = w.iter().map(|p| p.x.to_f64()).collect();
        let ys: Vec<f64> = w.iter().map(|p| p.y.to_f64()).collect();
        let f = |v: &Vec<f64>, mx: bool| {
            v.iter()
                .cloned()
                .fold(if mx { f64::MIN } else { f64::MAX }, |x, y| {
                    if mx {
                        x.max(y)
                    } else {
                        x.min(y)
                    }
                })
        };
        [f(&xs, false), f(&ys, false), f(&xs, true), f(&ys, true)]
    };
    let (ba, bb) = (bbox(&wa), bbox(&wb));
    let slack = 1e-6 * (1.0 + ba.iter().chain(&bb).fold(0.0f64, |m, x| m.max(x.abs())));
    if ba[2] + slack < bb[0]
        || bb[2] + slack < ba[0]
        || ba[3] + slack < bb[1]
        || bb[3] + slack < ba[1]
    {
        return Relation::Apart;
    }
    let mut weak = false;
    for (p, q) in [(&wa, &wb), (&wb, &wa)] {
        let n = p.len();
        for i in 0..n {
            let (s, e) = (&p[i], &p[(i + 1) % n]);
            let mut max_side = -2;
            for r in q.iter() {
                let side = orient(s, e, r).as_i32();
                max_side = max_side.max(side);
                if max_side > 0 {
                    break;
                }
            }
            if max_side < 0 {
                return Relation::Apart;
            }
            if max_side == 0 {
                weak = true;
            }
        }
    }
    if weak {
        Relation::Touching
    } else {
        Relation::Overlapping
    }
}

fn check_family_seed(f: Family, seed: u64) {
    let sc = generate_small(f, seed);
    if let Err(e) = check_valid(&sc) {
        panic!("{} seed {seed}: {e}\n{sc:#?}", f.name());
    }
    let n = sc.polygons.len();
    assert!(
        (2..=8).contains(&n),
        "{} seed {seed}: {n} polygons",
        f.name()
    );
    for p in &sc.polygons {
        assert!(
            (3..=14).contains(&p.vertices.len()),
            "{} seed {seed}: {} vertices",
            f.name(),
            p.vertices.len()
        );
    }
}

#[test]
fn names_round_trip() {
    for f in Family::ALL {
        assert_eq!(Family::from_name(f.name()), Some(f));
        assert!(!f.description().is_empty());
    }
    assert_eq!(Family::from_name("nope"), None);
}

#[test]
fn small_instances_are_valid() {
    for f in Family::ALL {
        for seed in 0..300 {
            check_family_seed(f, seed);
        }
    }
}

#[test]
fn small_instances_are_deterministic() {
    for f in Family::ALL {
        for seed in [0, 1, 17, u64::MAX] {
            assert_eq!(generate_small(f, seed), generate_small(f, seed));
        }
        assert_ne!(generate_small(f, 1), generate_small(f, 2));
    }
}

#[test]
fn small_instances_use_every_mode() {
    for f in Family::ALL {
        let modes: std::collections::HashSet<_> =
            (0..60).map(|s| generate_small(f, s).on_collision).collect();
        assert_eq!(modes.len(), 3, "{}", f.name());
    }
}

#[test]
fn library_validate_accepts_every_family() {
    let defaults = [
        flypast(&FlypastParams::default()),
        gas(&GasParams {
            walls: true,
            changes: 4,
            ..Default::default()
        }),
        far(&FarParams::default()),
        simultaneous(&SimultaneousParams::default()),
        grazing(&DegenerateParams::default()),
        parallel(&DegenerateParams::default()),
        demo(),
    ];
    for sc in &defaults {
        sc.validate().unwrap();
    }
    for f in Family::ALL {
        for seed in 0..200 {
            let sc = generate_small(f, seed);
            if let Err(e) = crate::scenario::Scenario::validate(&sc) {
                panic!("{} seed {seed}: {e}", f.name());
            }
        }
    }
}

#[test]
fn brute_reports_the_planned_contacts() {
    // In stop mode the reference reports exactly the planned contacts at
    // the earliest planned instant.
    let options = crate::RunOptions {
        structure: crate::StructureKind::Brute,
        ..Default::default()
    };
    for seed in 0..40 {
        let p = DegenerateParams {
            pairs: 3,
            seed,
            small: seed % 2 == 0,
            ..Default::default()
        };
        let s = SimultaneousParams {
            pairs: 2,
            triple: true,
            seed,
            small: seed % 2 == 1,
            ..Default::default()
        };
        for (name, (sc, planned)) in [
            ("simultaneous", simultaneous_with_contacts(&s)),
            ("grazing", grazing_with_contacts(&p)),
            ("parallel", parallel_with_contacts(&p)),
        ] {
            let first = planned.iter().map(|c| c.time).fold(f64::MAX, f64::min);
            let mut want: Vec<(String, String, f64)> = planned
                .iter()
                .filter(|c| c.time == first)
                .map(|c| (c.a.clone(), c.b.clone(), c.time))
                .collect();
            want.sort_by(|x, y| {
                (x.0.as_bytes(), x.1.as_bytes()).cmp(&(y.0.as_bytes(), y.1.as_bytes()))
            });
            let mut got = Vec::new();
            crate::run(&sc, &options, &mut |e| {
                got.push((e.a.clone(), e.b.clone(), e.time.to_f64()))
            })
            .unwrap_or_else(|e| panic!("{name} seed {seed}: {e}"));
            assert_eq!(got, want, "{name} seed {seed}");
        }
    }
}

#[test]
fn brute_agrees_with_flypast_gaps() {
    for method in [
        crate::brute::PairMethod::Simple,
        crate::brute::PairMethod::Fast,
    ] {
        let options = crate::RunOptions {
            structure: crate::StructureKind::Brute,
            pair_method: method,
            ..Default::default()
        };
        for seed in 0..12 {
            for (n, gap) in [
                (3, 0.0),
                (8, 1e-12),
                (8, -1e-12),
                (33, 0.0),
                (64, 0.05),
                (64, -0.05),
            ] {
                let p = FlypastParams {
                    n,
                    gap,
                    a_moving: seed % 2 == 0,
                    seed,
                    ..Default::default()
                };
                let sc = flypast(&p);
                let mut events = 0;
                crate::run(&sc, &options, &mut |_| events += 1).unwrap();
                assert_eq!(events, usize::from(gap <= 0.0), "{p:?}");
            }
        }
    }
}

fn check_planned(sc: &Scenario, contacts: &[PlannedContact]) {
    assert!(!contacts.is_empty());
    for c in contacts {
        let a = sc.polygons.iter().find(|p| p.id == c.a).expect("a");
        let b = sc.polygons.iter().find(|p| p.id == c.b).expect("b");
        assert!(c.a.as_bytes() < c.b.as_bytes());
        let ch = &sc.flight_plan_changes;
        assert_eq!(
            relation_at(a, b, ch, ch, c.time),
            Relation::Touching,
            "{} {} at {}",
            c.a,
            c.b,
            c.time
        );
        for k in [1, 3, 10, 30] {
            let t = c.time - 0.5f64.powi(k);
            if t >= 0.0 {
                assert_eq!(
                    relation_at(a, b, ch, ch, t),
                    Relation::Apart,
                    "{} {} at {t}",
                    c.a,
                    c.b
                );
            }
        }
    }
}

#[test]
fn planned_contacts_are_exact() {
    for seed in 0..150 {
        for small in [true, false] {
            let (sc, c) = simultaneous_with_contacts(&SimultaneousParams {
                pairs: 3,
                triple: true,
                small,
                seed,
                ..Default::default()
            });
            check_valid(&sc).unwrap();
            check_planned(&sc, &c);
            assert!(c.iter().all(|x| x.time == c[0].time));
            assert_eq!(c.len(), 6);
            let p = DegenerateParams {
                pairs: 3,
                small,
                seed,
                ..Default::default()
            };
            let (sc, c) = grazing_with_contacts(&p);
            check_valid(&sc).unwrap();
            check_planned(&sc, &c);
            let (sc, c) = parallel_with_contacts(&p);
            check_valid(&sc).unwrap();
            check_planned(&sc, &c);
        }
    }
}

#[test]
fn grazing_contacts_are_tangential() {
    // Just after a grazing contact the pair is never overlapping.
    for seed in 0..100 {
        let (sc, contacts) = grazing_with_contacts(&DegenerateParams {
            pairs: 2,
            seed,
            ..Default::default()
        });
        for c in &contacts {
            let a = sc.polygons.iter().find(|p| p.id == c.a).unwrap();
            let b = sc.polygons.iter().find(|p| p.id == c.b).unwrap();
            let t = c.time + 0.5f64.powi(20);
            assert_ne!(relation_at(a, b, &[], &[], t), Relation::Overlapping);
        }
    }
}

#[test]
fn gas_and_far_defaults_are_valid() {
    for seed in 0..10 {
        let g = GasParams {
            seed,
            walls: true,
            changes: 5,
            ..Default::default()
        };
        let sc = gas(&g);
        check_valid(&sc).unwrap();
        assert_eq!(sc.polygons.len(), 20);
        let f = far(&FarParams {
            gas: g,
            ..Default::default()
        });
        check_valid(&f).unwrap();
        assert!(f
            .polygons
            .iter()
            .all(|p| p.position[0] + p.vertices[0][0] > 9e5));
    }
    let sc = gas(&GasParams {
        k: 100,
        min_n: 3,
        max_n: 40,
        walls: false,
        ..Default::default()
    });
    check_valid(&sc).unwrap();
}

#[test]
fn swarm_is_valid_and_deterministic() {
    for (k, n, seed) in [(1, 3, 0), (7, 16, 1), (30, 8, 2), (12, 256, 3)] {
        let p = SwarmParams {
            k,
            n,
            seed,
            ..Default::default()
        };
        let sc = swarm(&p);
        check_valid(&sc).unwrap_or_else(|e| panic!("{p:?}: {e}"));
        sc.validate().unwrap();
        assert_eq!(sc, swarm(&p));
        assert_eq!(sc.polygons.len(), k + 4);
        assert_eq!(sc.on_collision, CollisionMode::Bounce);
        let moving: Vec<&PolygonSpec> = sc.polygons.iter().filter(|p| !p.fixed).collect();
        let square: f64 = moving
            .iter()
            .map(|p| p.velocity[0] * p.velocity[0] + p.velocity[1] * p.velocity[1])
            .sum();
        let rms = (square / k as f64).sqrt();
        assert_eq!(sc.until, swarm_until(k, n, rms, 12.0));
        assert_eq!(moving.len(), k);
        for (i, m) in moving.iter().enumerate() {
            assert_eq!(m.vertices.len(), n);
            assert!(m.velocity.iter().all(|v| (-1.0..=1.0).contains(v)));
            assert_eq!(m.id.trim_start_matches('s').parse::<usize>(), Ok(i));
            assert_eq!(m.id.len(), 1 + digits(k - 1));
        }
        let walls: Vec<&str> = sc
            .polygons
            .iter()
            .filter(|p| p.fixed)
            .map(|p| p.id.as_str())
            .collect();
        assert_eq!(
            walls,
            ["wall-bottom", "wall-left", "wall-right", "wall-top"]
        );
    }
    let a = swarm(&SwarmParams::default());
    let b = swarm(&SwarmParams {
        seed: 1,
        ..Default::default()
    });
    assert_ne!(a, b);
    // remove mode: the same motions and until
    let r = swarm(&SwarmParams {
        mode: CollisionMode::Remove,
        ..Default::default()
    });
    assert_eq!((r.polygons, r.until), (a.polygons, a.until));
    let given = swarm(&SwarmParams {
        until: Some(2.5),
        ..Default::default()
    });
    assert_eq!(given.until, 2.5);
}

#[test]
fn swarm_until_follows_the_curve() {
    let reference = (2.0f64 / 3.0).sqrt();
    for k in [1, 10, 300, 1000, 100_000] {
        for n in [3, 16, 256, 65536] {
            let mut last = 0.0;
            for c in [0.01, 0.1, 1.0, 3.0, 6.0, 12.0, 24.0, 100.0] {
                let t = swarm_until(k, n, reference, c);
                assert!(t.is_finite() && t > last, "k {k} c {c}: {t} after {last}");
                last = t;
                // twice as fast: half the time
                let fast = swarm_until(k, n, 2.0 * reference, c);
                assert!((fast - t / 2.0).abs() <= 1e-12 * t, "{fast} {t}");
            }
        }
        // rounder polygons and fewer walls collide more often
        assert!(swarm_until(k, 8, reference, 12.0) > swarm_until(k, 64, reference, 12.0));
    }
    assert!(swarm_until(100, 16, reference, 12.0) < swarm_until(1000, 16, reference, 12.0));
    // measured: 1000 16-gons, 12 per polygon about t = 4.9
    let t = swarm_until(1000, 16, reference, 12.0);
    assert!((4.6..5.2).contains(&t), "{t}");
    assert!(swarm_until(10, 16, 0.0, 12.0).is_finite());
}

#[test]
fn swarm_refuses_bad_parameters() {
    let ok = SwarmParams::default();
    assert!(ok.check().is_ok());
    for (bad, want) in [
        (SwarmParams { k: 0, ..ok.clone() }, "k is 0"),
        (SwarmParams { n: 2, ..ok.clone() }, "n is 2"),
        (
            SwarmParams {
                collisions_per_polygon: 0.0,
                ..ok.clone()
            },
            "collisions_per_polygon is 0",
        ),
        (
            SwarmParams {
                collisions_per_polygon: f64::NAN,
                ..ok.clone()
            },
            "collisions_per_polygon is NaN",
        ),
        (
            SwarmParams {
                until: Some(-1.0),
                ..ok.clone()
            },
            "until is -1",
        ),
    ] {
        let e = bad.check().unwrap_err();
        assert!(e.0.contains(want), "{e}");
    }
}

#[test]
fn flypast_gap_is_achieved() {
    for seed in 0..40 {
        for &(n, gap, a_moving) in &[
            (3usize, 0.1, false),
            (5, 0.0, true),
            (17, -0.2, false),
            (64, 1e-9, true),
            (100, 0.5, false),
            (1000, 0.0, false),
        ] {
            let p = FlypastParams {
                n,
                gap,
                a_moving,
                seed,
                ..Default::default()
            };
            let (sc, info) = flypast_with_info(&p);
            check_valid(&sc).unwrap();
            assert_eq!(sc.polygons[0].vertices.len(), n);
            if gap > 0.0 {
                assert!(info.achieved_gap > 0.0);
                assert!((info.achieved_gap - gap).abs() <= 1e-12, "{info:?}");
            } else {
                assert!(info.achieved_gap <= 0.0);
                assert!((info.achieved_gap - gap).abs() <= 1e-12, "{info:?}");
            }
            // B passes completely: disjoint again at `until`.
            let (a, b) = (&sc.polygons[0], &sc.polygons[1]);
            assert_eq!(relation_at(a, b, &[], &[], sc.until), Relation::Apart);
            let mid = relation_at(a, b, &[], &[], info.closest_time);
            if gap > 1e-6 {
                assert_eq!(mid, Relation::Apart);
            }
            if gap < -1e-6 {
                assert_ne!(mid, Relation::Apart);
            }
        }
    }
}

#[test]
fn flypast_sampled_distance_matches_gap() {
    // Sampling the motion finely: the smallest distance is close to the gap.
    let p = FlypastParams {
        n: 12,
        gap: 0.25,
        seed: 3,
        ..Default::default()
    };
    let sc = flypast(&p);
    let (a, b) = (&sc.polygons[0], &sc.polygons[1]);
    let mut best = f64::MAX;
    for i in 0..=20_000 {
        let t = sc.until * i as f64 / 20_000.0;
        let pa = [
            a.position[0] + t * a.velocity[0],
            a.position[1] + t * a.velocity[1],
        ];
        let pb = [
            b.position[0] + t * b.velocity[0],
            b.position[1] + t * b.velocity[1],
        ];
        for u in &a.vertices {
            for v in &b.vertices {
                let dx = pa[0] + u[0] - pb[0] - v[0];
                let dy = pa[1] + u[1] - pb[1] - v[1];
                best = best.min((dx * dx + dy * dy).sqrt());
            }
        }
    }
    // Vertex-vertex distances bound the true distance from above.
    assert!((0.25 - 1e-9..0.25 + 0.05).contains(&best), "{best}");
}

#[test]
fn flypast_huge_is_strictly_convex() {
    let p = FlypastParams {
        n: 1 << 20,
        gap: 0.01,
        ..Default::default()
    };
    let (sc, info) = flypast_with_info(&p);
    assert!(info.achieved_gap > 0.0);
    for poly in &sc.polygons {
        assert_eq!(poly.vertices.len(), 1 << 20);
        check_polygon(&poly.vertices).unwrap();
    }
}

#[test]
fn hull_is_strict() {
    let pts = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 2.0],
        [0.0, 2.0],
        [1.0, 1.0],
        [0.0, 0.0],
    ];
    assert_eq!(
        strict_convex_hull(&pts),
        vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    );
    // Collinear in exact arithmetic although doubles round the products.
    let a = [0.1, 0.1];
    let b = [0.2, 0.2];
    let c = [0.30000000000000004, 0.30000000000000004];
    assert_eq!(orient_exact(a, b, c), 0);
    assert_eq!(orient_exact([0.0, 0.0], [1.0, 0.0], [0.5, 1e-300]), 1);
}

#[test]
fn demo_is_valid() {
    check_valid(&demo()).unwrap();
}

#[test]
#[should_panic(expected = "invalid generator parameters")]
fn bad_params_panic() {
    flypast(&FlypastParams {
        n: 2,
        ..Default::default()
    });
}

const MODES: [CollisionMode; 3] = [
    CollisionMode::Stop,
    CollisionMode::Remove,
    CollisionMode::Bounce,
];

fn churn_of(seed: u64, mode: CollisionMode) -> Scenario {
    churn(&ChurnParams {
        mode,
        seed,
        ..Default::default()
    })
}

fn polygon_of<'a>(sc: &'a Scenario, id: &str) -> &'a PolygonSpec {
    sc.polygons
        .iter()
        .chain(sc.insertions.iter().map(|i| &i.polygon))
        .find(|p| p.id == id)
        .unwrap_or_else(|| panic!("no polygon {id}"))
}

fn removal_of(sc: &Scenario, id: &str) -> Option<f64> {
    sc.removals.iter().find(|r| r.id == id).map(|r| r.time)
}

#[test]
fn churn_is_valid_and_deterministic() {
    for seed in 0..40 {
        for mode in MODES {
            let sc = churn_of(seed, mode);
            sc.validate()
                .unwrap_or_else(|e| panic!("seed {seed} {mode:?}: {e}"));
            assert_eq!(sc, churn_of(seed, mode), "seed {seed}");
            assert_eq!(sc.on_collision, mode);
        }
    }
    for (k, clusters, until) in [(0, 0, 1.0), (1, 1, 1.0), (3, 2, 2.5), (40, 9, 20.0)] {
        let sc = churn(&ChurnParams {
            k,
            clusters,
            until,
            mode: CollisionMode::Bounce,
            seed: 5,
        });
        sc.validate()
            .unwrap_or_else(|e| panic!("k {k}, clusters {clusters}: {e}"));
        assert_eq!(sc.polygons.iter().filter(|p| !p.fixed).count(), k + 2);
    }
}

#[test]
fn churn_has_the_planned_coincidences() {
    for seed in 0..20 {
        let sc = churn_of(seed, CollisionMode::Bounce);
        // the head-on pair touches exactly when hx-b is removed
        let (a, b) = (polygon_of(&sc, "hx-a"), polygon_of(&sc, "hx-b"));
        let gap = (b.position[0] - 0.5) - (a.position[0] + 0.5);
        let closing = a.velocity[0] - b.velocity[0];
        assert!((a.position[1] - b.position[1]).abs() < 1.0);
        assert_eq!(a.velocity[1], 0.0);
        assert_eq!(b.velocity[1], 0.0);
        let contact = gap / closing;
        assert_eq!(contact * closing, gap, "seed {seed}: inexact contact");
        assert_eq!(removal_of(&sc, "hx-b"), Some(contact), "seed {seed}");
        // a fixed polygon inserted, then removed
        assert!(
            sc.insertions
                .iter()
                .any(|i| i.polygon.fixed
                    && removal_of(&sc, &i.polygon.id).is_some_and(|r| r > i.time)),
            "seed {seed}"
        );
        // a change at the next double after an insertion, of an inserted polygon
        assert!(
            sc.flight_plan_changes.iter().any(|c| sc
                .insertions
                .iter()
                .any(|i| i.polygon.id == c.id && c.time == i.time.next_up())),
            "seed {seed}"
        );
        // insertions at the instants of the collision, of f0's removal
        // (with its successor in its place) and of a change
        let inserted_at = |t: f64| sc.insertions.iter().any(|i| i.time == t);
        assert!(inserted_at(contact), "seed {seed}");
        let f0 = polygon_of(&sc, "f0");
        let gone = removal_of(&sc, "f0").expect("f0 leaves");
        let next = sc
            .insertions
            .iter()
            .find(|i| i.polygon.id == "f0-next")
            .expect("f0 has a successor");
        assert_eq!(next.time, gone);
        assert_eq!(
            (&next.polygon.vertices, next.polygon.position),
            (&f0.vertices, f0.position)
        );
        assert!(sc
            .insertions
            .iter()
            .any(|i| i.time == gone && i.polygon.id != "f0-next"));
        assert!(sc
            .flight_plan_changes
            .iter()
            .any(|c| c.id == "g00" && c.time == gone));
    }
}

#[test]
fn churn_runs_with_every_insertion_free_and_the_pair_touching_on_time() {
    for seed in 0..12 {
        for mode in MODES {
            let sc = churn_of(seed, mode);
            let contact = removal_of(&sc, "hx-b").expect("hx-b leaves");
            let mut events = Vec::new();
            crate::run(&sc, &crate::RunOptions::default(), &mut |e| {
                events.push((e.time.to_f64(), e.a.clone(), e.b.clone()));
            })
            .unwrap_or_else(|e| panic!("seed {seed} {mode:?}: {e}"));
            // nothing reaches the pair before it touches; in stop mode
            // only if nothing else collided first
            let pair = (contact, "hx-a".to_string(), "hx-b".to_string());
            let first = events.first().map(|e| e.0);
            if mode != CollisionMode::Stop || first == Some(contact) {
                assert!(events.contains(&pair), "seed {seed} {mode:?}: {events:?}");
            }
            assert!(
                events.iter().all(|e| e.0 >= contact
                    || !(["hx-a", "hx-b"].contains(&e.1.as_str())
                        || ["hx-a", "hx-b"].contains(&e.2.as_str()))),
                "seed {seed} {mode:?}: {events:?}"
            );
        }
    }
}

#[test]
fn churn_refuses_bad_parameters() {
    for p in [
        ChurnParams {
            until: 0.5,
            ..Default::default()
        },
        ChurnParams {
            until: f64::INFINITY,
            ..Default::default()
        },
        ChurnParams {
            k: 1 << 20,
            ..Default::default()
        },
        ChurnParams {
            clusters: 5000,
            ..Default::default()
        },
    ] {
        assert!(p.check().is_err(), "{p:?}");
    }
    assert!(ChurnParams::default().check().is_ok());
}

/// A speed so small that the fly-past would last beyond the doubles' range
/// is refused by the parameter check (the generator would divide by its
/// square), and a slow one within the range is built.
#[test]
fn flypast_refuses_speeds_too_small_for_its_sizes() {
    let slow = |speed: f64| FlypastParams {
        speed,
        diameter: 1.0,
        ..Default::default()
    };
    assert!(slow(1e-167).check().is_err());
    assert!(slow(1e-320).check().is_err());
    assert!(slow(1e-140).check().is_ok());
    let s = flypast(&slow(1e-140));
    assert_eq!(s.polygons.len(), 2);
}
