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
