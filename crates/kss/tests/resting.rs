//! Resting contacts: two polygons that stay in contact over an interval
//! pinch the free space. A vertex resting on a vertex is a bridge of
//! length zero (inside a corridor, or a side of a partition triangle that
//! stays flat while they rest); where no pseudo-triangulation follows, as
//! with an edge resting on an identical edge, the reference stands in until
//! no pair rests in contact, and the structure takes over again (see
//! ARCHITECTURE.md, "Resting contacts").

use kss::{CollisionMode, FlightPlanChange, PolygonSpec, RunStats, Scenario, StructureKind};

mod common;

use common::events;

fn polygon(
    id: &str,
    vertices: &[[f64; 2]],
    position: [f64; 2],
    velocity: [f64; 2],
    fixed: bool,
) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vertices.to_vec(),
        position,
        velocity,
        fixed,
    }
}

fn change(time: f64, id: &str, velocity: [f64; 2]) -> FlightPlanChange {
    FlightPlanChange {
        time,
        id: id.into(),
        velocity,
    }
}

/// Both structures on `s` with the audit after every event: the same
/// events as `want` (the reference's), and each one's statistics.
fn structures_follow(
    s: &Scenario,
    want: &common::Events,
    case: &str,
) -> Vec<(&'static str, RunStats)> {
    [StructureKind::Plain, StructureKind::Hierarchical]
        .into_iter()
        .map(|structure| {
            let name = structure.name();
            let (got, stats) =
                events(s, structure, true).unwrap_or_else(|e| panic!("{case} {name}: {e}"));
            assert_eq!(&got, want, "{case} {name}");
            (name, stats)
        })
        .collect()
}

/// Three polygons meet at the origin at t = 3 (gen_small simultaneous seed
/// 972, which stopped with "no rebuild just after t = 3 found"); `t1`
/// stops there, resting on the fixed `t2` vertex to vertex; at t = 4 it
/// backs off, at t = 5 it comes back and hits `t2` again at t = 6.
fn resting_then_apart() -> Scenario {
    Scenario {
        until: 8.0,
        on_collision: CollisionMode::Bounce,
        polygons: vec![
            polygon(
                "t0",
                &[[0.0, 0.0], [-0.5, 3.0], [-2.5, 7.5], [-2.0, 4.5]],
                [-1.5, 4.5],
                [0.5, -1.5],
                false,
            ),
            polygon(
                "t1",
                &[[0.0, 0.0], [-2.0, 3.5], [-2.5, 2.5], [-0.5, -1.0]],
                [-3.0, 3.0],
                [1.0, -1.0],
                false,
            ),
            polygon(
                "t2",
                &[[0.0, 0.0], [1.5, -3.5], [2.0, -4.0], [1.5, -2.5]],
                [0.0, 0.0],
                [0.0, 0.0],
                true,
            ),
        ],
        flight_plan_changes: vec![
            change(3.0, "t1", [0.0, 0.0]),
            change(4.0, "t1", [-1.0, 0.5]),
            change(5.0, "t1", [1.0, -0.5]),
        ],
        ..Default::default()
    }
}

/// The structure follows the three polygons through the instant where
/// they meet and `t1` rests on `t2`: the side between the two resting
/// vertices has length zero, in a partition triangle that stays flat while
/// they rest; the reference never stands in.
#[test]
fn three_polygons_meet_and_one_rests_without_the_reference() {
    let s = resting_then_apart();
    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
    let pairs: Vec<(f64, &str, &str)> = want
        .iter()
        .map(|(t, a, b)| (t.to_f64(), a.as_str(), b.as_str()))
        .collect();
    assert_eq!(
        pairs,
        [
            (3.0, "t0", "t1"),
            (3.0, "t0", "t2"),
            (3.0, "t1", "t2"),
            (6.0, "t1", "t2")
        ]
    );
    for (name, stats) in structures_follow(&s, &want, "parting") {
        assert_eq!(stats.stand_ins, 0, "{name}");
        assert_eq!(stats.degenerate_rebuilds, 0, "{name}");
    }
    // resting there until the end
    let mut s = s;
    s.flight_plan_changes.truncate(1);
    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
    for (name, stats) in structures_follow(&s, &want, "resting") {
        assert_eq!(stats.stand_ins, 0, "{name}");
    }
}

/// Two pairs meet at t = 1 (gen_small parallel seed 8952, minimized); at
/// t = 2 a plan change of `b1` leaves a pair in contact, one polygon's
/// vertex on the other's edge, where the free space has no triangulation:
/// the structure is built from the infinitesimally shrunk copy; at t = 3
/// `b1` moves away.
fn contact_at_a_plan_change_then_apart() -> Scenario {
    Scenario {
        until: 5.0,
        on_collision: CollisionMode::Bounce,
        polygons: vec![
            polygon(
                "a0",
                &[
                    [0.25, 0.125],
                    [0.0, 0.25],
                    [-0.25, -0.25],
                    [-0.25, -0.5],
                    [-0.125, -0.375],
                ],
                [0.0, 0.0],
                [0.0, 0.0],
                true,
            ),
            polygon(
                "b0",
                &[
                    [0.5, 1.125],
                    [0.25, 0.875],
                    [-0.25, 0.125],
                    [-0.375, -0.125],
                    [-0.5, -0.75],
                    [-0.25, -0.75],
                    [0.0, -0.5],
                    [0.375, 0.125],
                    [0.5, 0.375],
                ],
                [-0.5, -1.625],
                [0.0, 0.25],
                false,
            ),
            polygon(
                "a1",
                &[
                    [0.375, 0.25],
                    [-0.25, 0.0],
                    [-0.25, -0.75],
                    [-0.125, -0.625],
                ],
                [-19.875, -19.875],
                [-0.125, -0.125],
                false,
            ),
            polygon(
                "b1",
                &[
                    [0.5, 1.125],
                    [0.25, 0.875],
                    [-0.125, 0.375],
                    [-0.25, -0.75],
                    [0.5, 0.375],
                ],
                [-19.875, -21.0],
                [-0.5, -0.5],
                false,
            ),
        ],
        flight_plan_changes: vec![
            change(2.0, "b1", [-0.125, 0.0]),
            change(3.0, "b1", [-1.0, -1.0]),
        ],
        ..Default::default()
    }
}

#[test]
fn the_structure_follows_two_polygons_resting_in_contact_after_a_plan_change() {
    let s = contact_at_a_plan_change_then_apart();
    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
    let pairs: Vec<(f64, &str, &str)> = want
        .iter()
        .map(|(t, a, b)| (t.to_f64(), a.as_str(), b.as_str()))
        .collect();
    assert_eq!(pairs, [(1.0, "a0", "b0"), (1.0, "a1", "b1")]);
    for (name, stats) in structures_follow(&s, &want, "apart") {
        // no stand-in and no global rebuild: the structure itself follows
        assert_eq!(stats.stand_ins, 0, "{name}");
        assert_eq!(stats.degenerate_rebuilds, 0, "{name}");
        assert!(stats.events_by_kind.len() > 2, "{name}");
    }
}

/// Without the last flight-plan change the contact lasts until the end:
/// the structure follows it to the end.
#[test]
fn the_structure_follows_a_contact_that_rests_for_ever() {
    let mut s = contact_at_a_plan_change_then_apart();
    s.flight_plan_changes.truncate(1);
    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
    for (name, stats) in structures_follow(&s, &want, "for ever") {
        assert_eq!(stats.stand_ins, 0, "{name}");
        assert_eq!(stats.degenerate_rebuilds, 0, "{name}");
    }
}

/// Two triangles meet vertex to vertex at the top of the convex hull (`B`
/// comes down onto `A`'s apex at t = 1, a collision with no impulse, and
/// stops there), rest until t = 2, and a plan change then moves one of
/// them in one of 25 directions, with or without a third polygon below.
/// While they rest, the hull edge between them and the corridor junction
/// at the touching point are turns through two resting points, which have
/// no certificate; the motion change must give both corridors theirs
/// back, or the audit finds a corridor between them with two convex
/// vertices. A hand-made case that no generated family produces.
#[test]
fn a_vertex_resting_on_a_vertex_on_the_hull_then_parted_in_any_direction() {
    let speeds = [-1.0, -0.5, 0.0, 0.5, 1.0];
    for vx in speeds {
        for vy in speeds {
            for who in ["A", "B"] {
                for third in [false, true] {
                    let mut polygons = vec![
                        polygon(
                            "A",
                            &[[0.0, 0.0], [-2.0, -1.0], [-1.0, -2.0]],
                            [0.0, 0.0],
                            [0.0, 0.0],
                            false,
                        ),
                        polygon(
                            "B",
                            &[[0.0, 0.0], [1.0, -2.0], [2.0, -1.0]],
                            [0.0, 1.0],
                            [0.0, -1.0],
                            false,
                        ),
                    ];
                    if third {
                        polygons.push(polygon(
                            "C",
                            &[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]],
                            [0.0, -6.0],
                            [0.0, 0.0],
                            false,
                        ));
                    }
                    let s = Scenario {
                        until: 3.0,
                        on_collision: CollisionMode::Bounce,
                        polygons,
                        flight_plan_changes: vec![
                            change(1.0, "B", [0.0, 0.0]),
                            change(2.0, who, [vx, vy]),
                        ],
                        ..Default::default()
                    };
                    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
                    let case = format!("{who} moves ({vx}, {vy}), third {third}");
                    for (name, stats) in structures_follow(&s, &want, &case) {
                        assert_eq!(stats.stand_ins, 0, "{case} {name}");
                        assert_eq!(stats.degenerate_rebuilds, 0, "{case} {name}");
                    }
                }
            }
        }
    }
}

/// The scenario as the contract's JSON (for a failure message: the run can
/// be repeated with `kss run`).
fn scenario_json(s: &Scenario) -> String {
    let v = |p: [f64; 2]| format!("[{:?},{:?}]", p[0], p[1]);
    let polys: Vec<String> = s
        .polygons
        .iter()
        .map(|p| {
            let vs: Vec<String> = p.vertices.iter().map(|&x| v(x)).collect();
            format!(
                "{{\"id\":\"{}\",\"vertices\":[{}],\"position\":{},\"velocity\":{},\"fixed\":{}}}",
                p.id,
                vs.join(","),
                v(p.position),
                v(p.velocity),
                p.fixed
            )
        })
        .collect();
    let changes: Vec<String> = s
        .flight_plan_changes
        .iter()
        .map(|c| {
            format!(
                "{{\"time\":{:?},\"id\":\"{}\",\"velocity\":{}}}",
                c.time,
                c.id,
                v(c.velocity)
            )
        })
        .collect();
    let mode = match s.on_collision {
        CollisionMode::Stop => "stop",
        CollisionMode::Remove => "remove",
        CollisionMode::Bounce => "bounce",
    };
    format!(
        "{{\"version\":1,\"until\":{:?},\"on_collision\":\"{mode}\",\"polygons\":[{}],\"flight_plan_changes\":[{}]}}",
        s.until,
        polys.join(","),
        changes.join(",")
    )
}

/// Random convex polygons, exact on a grid of eighths.
fn random_convex(rng: &mut kss::rng::Rng) -> Vec<[f64; 2]> {
    loop {
        let n = rng.range_usize(3, 7);
        let mut pts: Vec<[f64; 2]> = (0..n)
            .map(|_| {
                [
                    rng.range_i64(-16, 16) as f64 / 8.0,
                    rng.range_i64(-16, 16) as f64 / 8.0,
                ]
            })
            .collect();
        pts.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
        pts.dedup();
        // Andrew's monotone chain, counter-clockwise, no collinear points
        let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
            (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
        };
        let mut hull: Vec<[f64; 2]> = Vec::new();
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
                Box::new(pts.iter())
            } else {
                Box::new(pts.iter().rev())
            };
            for &p in iter {
                while hull.len() >= start + 2
                    && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
                {
                    hull.pop();
                }
                hull.push(p);
            }
            hull.pop();
        }
        if hull.len() >= 3 {
            return hull;
        }
    }
}

/// Whether two convex polygons (counter-clockwise) share interior points
/// (touching is not overlapping): no edge normal of either separates them.
fn interiors_overlap(p: &[[f64; 2]], q: &[[f64; 2]]) -> bool {
    for (poly, other) in [(p, q), (q, p)] {
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let n = [b[1] - a[1], a[0] - b[0]];
            let dot = |x: &[f64; 2]| n[0] * x[0] + n[1] * x[1];
            let hi = poly.iter().map(dot).fold(f64::MIN, f64::max);
            let lo = other.iter().map(dot).fold(f64::MAX, f64::min);
            if lo >= hi {
                return false;
            }
        }
    }
    true
}

fn shifted(p: &[[f64; 2]], d: [f64; 2], s: f64) -> Vec<[f64; 2]> {
    p.iter()
        .map(|v| [v[0] + d[0] * s, v[1] + d[1] * s])
        .collect()
}

/// A generated family of the hand-made case above: random convex `B`
/// comes onto random convex `A` (fixed or not) so that a vertex of `B`
/// touches a vertex or an edge point of `A` at t = 1, stops there (a plan
/// change), rests until t = 2, and a plan change then moves `A` or `B` in
/// one of 17 directions; half of them with a third polygon somewhere,
/// `bounce` or `remove`. All coordinates are exact eighths. The same events
/// as `brute`, with the audit after every event; the reference's stand-in
/// and the global rebuild stay rare (at most 1 scenario in 50; all those
/// measured were a vertex resting on a vertex). A
/// first version of this family found two more missed certificates at a
/// motion change (a hull turn whose corridor owned no certificate of the
/// moving body, and a corridor reached only through an empty one); with
/// the binary of 350872f 14 of 213 such scenarios (a Python version of the
/// family) failed the audit. `KSS_SLOW=1` runs 20 times as many.
#[test]
fn random_contacts_that_rest_then_part() {
    const DIRS: [[f64; 2]; 17] = [
        [1.0, 0.0],
        [0.0, 1.0],
        [-1.0, 0.0],
        [0.0, -1.0],
        [1.0, 1.0],
        [-1.0, 1.0],
        [1.0, -1.0],
        [-1.0, -1.0],
        [2.0, 1.0],
        [1.0, 2.0],
        [-2.0, 1.0],
        [-1.0, 2.0],
        [2.0, -1.0],
        [1.0, -2.0],
        [-2.0, -1.0],
        [-1.0, -2.0],
        [0.0, 0.0],
    ];
    let want_runs = if std::env::var_os("KSS_SLOW").is_some() {
        4000
    } else {
        200
    };
    let mut runs = 0;
    let mut seed = 0u64;
    let mut fallbacks = [0u64; 2];
    while runs < want_runs {
        seed += 1;
        let mut rng = kss::rng::Rng::new(seed);
        let a = random_convex(&mut rng);
        let b = random_convex(&mut rng);
        let mut touch = a[rng.range_usize(0, a.len() - 1)];
        let on_edge = rng.chance(0.4);
        if on_edge {
            // a point inside one of A's edges
            let i = a.iter().position(|&v| v == touch).expect("a vertex");
            let next = a[(i + 1) % a.len()];
            let f = rng.range_i64(1, 7) as f64 / 8.0;
            touch = [
                touch[0] + (next[0] - touch[0]) * f,
                touch[1] + (next[1] - touch[1]) * f,
            ];
        }
        let bv = b[rng.range_usize(0, b.len() - 1)];
        let off = [touch[0] - bv[0], touch[1] - bv[1]];
        let b1 = shifted(&b, off, 1.0);
        if interiors_overlap(&a, &b1) {
            continue;
        }
        let d = DIRS[rng.range_usize(0, 15)];
        // B comes from `off + d` at t = 0 along −d, apart until t = 1
        if (0..8).any(|k| interiors_overlap(&a, &shifted(&b1, d, 1.0 - k as f64 / 8.0)))
            || shifted(&b1, d, 1.0)
                .iter()
                .any(|p| a.iter().any(|q| p == q))
        {
            continue;
        }
        let a_fixed = rng.chance(0.3);
        let mut polygons = vec![
            polygon("A", &a, [0.0, 0.0], [0.0, 0.0], a_fixed),
            polygon(
                "B",
                &b,
                [off[0] + d[0], off[1] + d[1]],
                [-d[0], -d[1]],
                false,
            ),
        ];
        if rng.chance(0.5) {
            let c = random_convex(&mut rng);
            let at = [
                rng.range_i64(-40, 40) as f64 / 4.0,
                rng.range_i64(-40, 40) as f64 / 4.0,
            ];
            let cs = shifted(&c, at, 1.0);
            if interiors_overlap(&a, &cs)
                || (0..=8).any(|k| interiors_overlap(&cs, &shifted(&b1, d, k as f64 / 8.0)))
            {
                continue;
            }
            polygons.push(polygon("C", &c, at, [0.0, 0.0], false));
        }
        let who = if a_fixed || rng.chance(0.5) { "B" } else { "A" };
        let v = DIRS[rng.range_usize(0, 16)];
        let speed = [0.25, 0.5, 1.0][rng.range_usize(0, 2)];
        let mode = if rng.chance(0.3) {
            CollisionMode::Remove
        } else {
            CollisionMode::Bounce
        };
        let s = Scenario {
            until: 3.0,
            on_collision: mode,
            polygons,
            flight_plan_changes: vec![
                change(1.0, "B", [0.0, 0.0]),
                change(2.0, who, [v[0] * speed, v[1] * speed]),
            ],
            ..Default::default()
        };
        let Ok((want, _)) = events(&s, StructureKind::Brute, false) else {
            continue; // (touching at the start: not a scenario)
        };
        runs += 1;
        let json = scenario_json(&s);
        let case = format!("seed {seed}\n{json}");
        for (si, (name, stats)) in structures_follow(&s, &want, &case).into_iter().enumerate() {
            if stats.stand_ins + stats.degenerate_rebuilds > 0 {
                eprintln!(
                    "fallback: seed {seed} {name} (touch inside an edge: {on_edge}): {} stand-ins, {} rebuilds",
                    stats.stand_ins, stats.degenerate_rebuilds
                );
                eprintln!("{json}");
            }
            fallbacks[si] += stats.stand_ins + stats.degenerate_rebuilds;
        }
    }
    eprintln!(
        "{runs} scenarios; fallbacks (stand-ins and rebuilds): plain {}, hierarchical {}",
        fallbacks[0], fallbacks[1]
    );
    // (with `KSS_SLOW=1`, 4000 scenarios, at commit 2419cf7: plain 28
    // stand-ins and 7 rebuilds, the hierarchy 29 and 7, every one where a
    // vertex touches a vertex; not traced yet)
    for (name, f) in ["plain", "hierarchical"].iter().zip(fallbacks) {
        assert!(
            f * 50 <= runs,
            "{name}: {f} stand-ins and rebuilds in {runs} scenarios"
        );
    }
}
