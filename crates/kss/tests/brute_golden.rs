//! Hand-computed golden scenarios for the brute-force reference, times exact.

use kss::num::{Int, Rational};
use kss::{run, CollisionMode, FlightPlanChange, PolygonSpec, RunOptions, Scenario, StructureKind};

fn square(id: &str, x: f64, y: f64, vx: f64, vy: f64) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        position: [x, y],
        velocity: [vx, vy],
        fixed: false,
    }
}

fn events(s: &Scenario) -> Vec<(Rational, String, String)> {
    let mut out = Vec::new();
    let opts = RunOptions {
        structure: StructureKind::Brute,
        audit: true,
        ..Default::default()
    };
    run(s, &opts, &mut |e| {
        out.push((
            e.time.as_rational().unwrap().clone(),
            e.a.clone(),
            e.b.clone(),
        ))
    })
    .unwrap();
    out
}

fn q(n: i64, d: i64) -> Rational {
    Rational::new(Int::from(n), Int::from(d))
}

fn scenario(mode: CollisionMode, until: f64, polygons: Vec<PolygonSpec>) -> Scenario {
    Scenario {
        until,
        on_collision: mode,
        polygons,
        flight_plan_changes: vec![],
        ..Default::default()
    }
}

#[test]
fn head_on_squares() {
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            square("a", 0.0, 0.0, 1.0, 0.0),
            square("b", 3.0, 0.0, -1.0, 0.0),
        ],
    );
    assert_eq!(events(&s), vec![(q(1, 1), "a".into(), "b".into())]);
}

#[test]
fn head_on_thirds() {
    // closing speed 3, gap 1: contact at exactly 1/3 (not a double)
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            square("a", 0.0, 0.0, 2.0, 0.0),
            square("b", 2.0, 0.5, -1.0, 0.0),
        ],
    );
    assert_eq!(events(&s), vec![(q(1, 3), "a".into(), "b".into())]);
}

fn poly(id: &str, vertices: &[[f64; 2]], at: [f64; 2], v: [f64; 2]) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vertices.to_vec(),
        position: at,
        velocity: v,
        fixed: false,
    }
}

fn wall(id: &str, at: [f64; 2]) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vec![[0.0, -5.0], [1.0, -5.0], [1.0, 5.0], [0.0, 5.0]],
        position: at,
        velocity: [0.0, 0.0],
        fixed: true,
    }
}

fn ev(n: i64, d: i64, a: &str, b: &str) -> (Rational, String, String) {
    (q(n, d), a.into(), b.into())
}

#[test]
fn vertex_against_vertex() {
    let diamond = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            poly("a", &diamond, [0.0, 0.0], [1.0, 0.0]),
            poly("b", &diamond, [5.0, 0.0], [-1.0, 0.0]),
        ],
    );
    assert_eq!(events(&s), vec![ev(3, 2, "a", "b")]);
}

#[test]
fn grazing_contact() {
    // b slides along the line y = 1 of a's top edge and first touches a's
    // corner (0, 1) at t = 2: closed sets share a point, so it is a collision.
    let mut a = square("a", 0.0, 0.0, 0.0, 0.0);
    a.fixed = true;
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![a, square("b", -3.0, 1.0, 1.0, 0.0)],
    );
    assert_eq!(events(&s), vec![ev(2, 1, "a", "b")]);
}

#[test]
fn grazing_then_sliding_in_bounce_mode() {
    // The graze has no normal approach, so no impulse: b slides along a and
    // leaves; nothing else happens.
    let mut a = square("a", 0.0, 0.0, 0.0, 0.0);
    a.fixed = true;
    let s = scenario(
        CollisionMode::Bounce,
        10.0,
        vec![a, square("b", -3.0, 1.0, 1.0, 0.0)],
    );
    assert_eq!(events(&s), vec![ev(2, 1, "a", "b")]);
}

#[test]
fn three_polygons_meet_at_one_point() {
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            poly(
                "a",
                &[[0.0, 0.0], [-2.0, 1.0], [-2.0, -1.0]],
                [-1.0, 0.0],
                [1.0, 0.0],
            ),
            poly(
                "b",
                &[[0.0, 0.0], [2.0, -1.0], [2.0, 1.0]],
                [1.0, 0.0],
                [-1.0, 0.0],
            ),
            poly(
                "c",
                &[[0.0, 0.0], [1.0, 2.0], [-1.0, 2.0]],
                [0.0, 1.0],
                [0.0, -1.0],
            ),
        ],
    );
    assert_eq!(
        events(&s),
        vec![ev(1, 1, "a", "b"), ev(1, 1, "a", "c"), ev(1, 1, "b", "c")]
    );
}

#[test]
fn flight_plan_change_before_contact() {
    let mut s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            square("a", 0.0, 0.0, 1.0, 0.0),
            square("b", 3.0, 0.0, -1.0, 0.0),
        ],
    );
    s.flight_plan_changes.push(FlightPlanChange {
        time: 0.5,
        id: "a".into(),
        velocity: [0.0, 0.0],
    });
    assert_eq!(events(&s), vec![ev(3, 2, "a", "b")]);
}

#[test]
fn fixed_wall() {
    let s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![square("a", 0.0, 0.0, 1.0, 0.0), wall("w", [5.0, 0.0])],
    );
    assert_eq!(events(&s), vec![ev(4, 1, "a", "w")]);
}

#[test]
fn bounce_between_walls() {
    let s = scenario(
        CollisionMode::Bounce,
        20.0,
        vec![
            square("a", 0.0, 0.0, 1.0, 0.0),
            wall("wall_r", [5.0, 0.0]),
            wall("wall_l", [-6.0, 0.0]),
        ],
    );
    assert_eq!(
        events(&s),
        vec![ev(4, 1, "a", "wall_r"), ev(13, 1, "a", "wall_l")]
    );
}

#[test]
fn remove_cascade() {
    // a removes b at t = 1; c, which would have hit b at t = 2, passes
    // through b's old place and hits d at t = 5.
    let s = scenario(
        CollisionMode::Remove,
        10.0,
        vec![
            square("a", 0.0, 0.0, 2.0, 0.0),
            square("b", 3.0, 0.0, 0.0, 0.0),
            square("c", 3.0, 3.0, 0.0, -1.0),
            square("d", 3.0, -3.0, 0.0, 0.0),
        ],
    );
    assert_eq!(events(&s), vec![ev(1, 1, "a", "b"), ev(5, 1, "c", "d")]);
}

#[test]
fn contact_at_exactly_until() {
    let pair = vec![
        square("a", 0.0, 0.0, 1.0, 0.0),
        square("b", 3.0, 0.0, -1.0, 0.0),
    ];
    let at = scenario(CollisionMode::Stop, 1.0, pair.clone());
    assert_eq!(events(&at), vec![ev(1, 1, "a", "b")]);
    let before = scenario(CollisionMode::Stop, 0.999, pair);
    assert_eq!(events(&before), vec![]);
}

#[test]
fn change_at_collision_instant_takes_effect_after() {
    // b would reverse at t = 1, the very instant of contact: the collision
    // is still reported.
    let mut s = scenario(
        CollisionMode::Stop,
        10.0,
        vec![
            square("a", 0.0, 0.0, 1.0, 0.0),
            square("b", 3.0, 0.0, -1.0, 0.0),
        ],
    );
    s.flight_plan_changes.push(FlightPlanChange {
        time: 1.0,
        id: "b".into(),
        velocity: [5.0, 0.0],
    });
    assert_eq!(events(&s), vec![ev(1, 1, "a", "b")]);
}

/// In bounce mode the bridges keep every exact number's size bounded: the
/// largest bit length seen over a run of thousands of collisions is the same
/// as over its first few hundred.
#[test]
fn bounce_numbers_stay_bounded() {
    let stats = |until: f64| {
        let s = kss::gen::gas(&kss::gen::GasParams {
            k: 8,
            min_n: 6,
            max_n: 6,
            walls: true,
            mode: CollisionMode::Bounce,
            until,
            seed: 3,
            ..Default::default()
        });
        let opts = RunOptions {
            structure: StructureKind::Brute,
            ..Default::default()
        };
        run(&s, &opts, &mut |_| {}).unwrap()
    };
    let short = stats(20.0);
    let long = stats(400.0);
    assert!(short.collisions > 100, "{}", short.collisions);
    assert!(long.collisions > 3000, "{}", long.collisions);
    assert!(long.max_number_bits <= 256, "{}", long.max_number_bits);
    assert!(
        long.max_number_bits <= short.max_number_bits + 16,
        "grew from {} to {} bits",
        short.max_number_bits,
        long.max_number_bits
    );
}
