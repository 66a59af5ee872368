//! Every kind of invalid scenario is refused with a typed error that names the
//! polygon or entry; no input makes the library panic.

use kss::{
    run, CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, RunError, RunOptions,
    Scenario, ScenarioError, StructureKind,
};
use proptest::prelude::*;

fn sq(id: &str, x: f64, y: f64) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        position: [x, y],
        velocity: [0.0, 0.0],
        fixed: false,
    }
}

fn base() -> Scenario {
    Scenario {
        until: 10.0,
        on_collision: CollisionMode::Stop,
        polygons: vec![sq("a", 0.0, 0.0), sq("b", 3.0, 0.0)],
        flight_plan_changes: vec![],
        ..Default::default()
    }
}

fn change(id: &str, time: f64) -> FlightPlanChange {
    FlightPlanChange {
        time,
        id: id.into(),
        velocity: [1.0, 0.0],
    }
}

fn err(s: &Scenario) -> ScenarioError {
    let e = s.validate().expect_err("scenario should be invalid");
    // `run` refuses it the same way, before simulating.
    let r = run(
        s,
        &RunOptions {
            structure: StructureKind::Brute,
            ..Default::default()
        },
        &mut |_| panic!("no event may be reported for an invalid scenario"),
    );
    // (compared as text: NaN payloads are not equal to themselves)
    assert!(matches!(r, Err(kss::RunError::Invalid(ref e2)) if e2.to_string() == e.to_string()));
    e
}

#[test]
fn valid_base_scenario() {
    assert_eq!(base().validate(), Ok(()));
    let empty = Scenario {
        polygons: vec![],
        ..base()
    };
    assert_eq!(empty.validate(), Ok(()));
}

#[test]
fn bad_until() {
    for u in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let s = Scenario { until: u, ..base() };
        assert!(matches!(err(&s), ScenarioError::BadUntil(_)));
    }
}

#[test]
fn non_finite_numbers_name_the_entry() {
    let mut s = base();
    s.polygons[1].vertices[2][0] = f64::NAN;
    let e = err(&s);
    assert!(e.to_string().contains("\"b\" vertex 2"), "{e}");
    let mut s = base();
    s.polygons[0].position[1] = f64::INFINITY;
    assert!(err(&s).to_string().contains("\"a\" position"));
    let mut s = base();
    s.polygons[0].velocity[0] = f64::NEG_INFINITY;
    assert!(err(&s).to_string().contains("\"a\" velocity"));
    let mut s = base();
    s.flight_plan_changes.push(change("a", f64::NAN));
    assert!(err(&s).to_string().contains("flight_plan_changes[0] time"));
    let mut s = base();
    let mut c = change("a", 1.0);
    c.velocity = [0.0, f64::INFINITY];
    s.flight_plan_changes.push(c);
    assert!(err(&s)
        .to_string()
        .contains("flight_plan_changes[0] velocity"));
}

#[test]
fn ids() {
    let mut s = base();
    s.polygons[1].id = String::new();
    assert_eq!(err(&s), ScenarioError::EmptyId { index: 1 });
    let mut s = base();
    s.polygons[1].id = "a".into();
    assert_eq!(err(&s), ScenarioError::DuplicateId { id: "a".into() });
}

#[test]
fn polygon_shapes() {
    let with = |v: Vec<[f64; 2]>| {
        let mut s = base();
        s.polygons[1].vertices = v;
        err(&s)
    };
    assert_eq!(
        with(vec![[0.0, 0.0], [1.0, 0.0]]),
        ScenarioError::TooFewVertices {
            id: "b".into(),
            count: 2
        }
    );
    assert_eq!(
        with(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        ScenarioError::RepeatedVertex {
            id: "b".into(),
            index: 1
        }
    );
    assert_eq!(
        with(vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.0]
        ]),
        ScenarioError::RepeatedVertex {
            id: "b".into(),
            index: 4
        }
    );
    assert_eq!(
        with(vec![[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        ScenarioError::CollinearVertices {
            id: "b".into(),
            index: 1
        }
    );
    assert_eq!(
        with(vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]),
        ScenarioError::Clockwise { id: "b".into() }
    );
    assert!(matches!(
        with(vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.25], [2.0, 2.0], [0.0, 2.0]]),
        ScenarioError::NotConvex { ref id, .. } if id == "b"
    ));
    // a pentagram turns left everywhere but winds twice
    let star = (0..5)
        .map(|k| {
            let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
            [a.cos(), a.sin()]
        })
        .collect();
    assert!(matches!(with(star), ScenarioError::NotConvex { .. }));
    // collinear by exact arithmetic even though 0.1 + 0.2 != 0.3 in doubles:
    // (0,0), (0.1, 0.1), (0.3, 0.3) are exactly collinear as dyadics
    assert!(matches!(
        with(vec![[0.0, 0.0], [0.1, 0.1], [0.3, 0.3], [0.0, 1.0]]),
        ScenarioError::CollinearVertices { index: 1, .. }
    ));
}

#[test]
fn fixed_polygons() {
    let mut s = base();
    s.polygons[0].fixed = true;
    s.polygons[0].velocity = [0.0, 1e-300];
    assert_eq!(err(&s), ScenarioError::FixedWithVelocity { id: "a".into() });
    let mut s = base();
    s.polygons[0].fixed = true;
    s.flight_plan_changes.push(change("a", 1.0));
    assert_eq!(
        err(&s),
        ScenarioError::FixedWithChange {
            index: 0,
            id: "a".into()
        }
    );
}

#[test]
fn flight_plan_changes() {
    let mut s = base();
    s.flight_plan_changes = vec![change("a", 1.0), change("zz", 1.0)];
    assert_eq!(
        err(&s),
        ScenarioError::UnknownChangeId {
            index: 1,
            id: "zz".into()
        }
    );
    for t in [0.0, -1.0, 10.5] {
        let mut s = base();
        s.flight_plan_changes = vec![change("b", t)];
        assert!(matches!(
            err(&s),
            ScenarioError::ChangeTimeOutOfRange { index: 0, .. }
        ));
    }
    let mut s = base();
    s.flight_plan_changes = vec![change("b", 10.0)]; // at `until` is allowed
    assert_eq!(s.validate(), Ok(()));
    let mut s = base();
    s.flight_plan_changes = vec![change("b", 2.0), change("a", 2.0), change("b", 2.0)];
    assert_eq!(
        err(&s),
        ScenarioError::DuplicateChange {
            first: 0,
            second: 2,
            id: "b".into(),
            time: 2.0
        }
    );
}

#[test]
fn overlap_at_time_zero_names_the_pair() {
    // overlapping
    let mut s = base();
    s.polygons.push(sq("c", 2.5, 0.5));
    let e = err(&s);
    assert_eq!(
        e,
        ScenarioError::Overlap {
            a: "b".into(),
            b: "c".into()
        }
    );
    assert!(e.to_string().contains("\"b\" and \"c\""));
    // touching along an edge (closed sets)
    let mut s = base();
    s.polygons[1].position = [1.0, 0.0];
    assert_eq!(
        err(&s),
        ScenarioError::Overlap {
            a: "a".into(),
            b: "b".into()
        }
    );
    // touching at a corner only
    let mut s = base();
    s.polygons[1].position = [1.0, 1.0];
    assert_eq!(
        err(&s),
        ScenarioError::Overlap {
            a: "a".into(),
            b: "b".into()
        }
    );
    // fixed walls that touch at a corner are refused as well
    let mut s = base();
    s.polygons[0].fixed = true;
    s.polygons[1].fixed = true;
    s.polygons[1].position = [1.0, 1.0];
    assert!(matches!(err(&s), ScenarioError::Overlap { .. }));
    // a gap of one unit in the last place is fine
    let mut s = base();
    s.polygons[1].position = [1.0f64.next_up(), 0.0];
    assert_eq!(s.validate(), Ok(()));
}

fn insertion(id: &str, time: f64, x: f64) -> Insertion {
    Insertion {
        time,
        polygon: sq(id, x, 5.0),
    }
}

fn removal(id: &str, time: f64) -> Removal {
    Removal {
        time,
        id: id.into(),
    }
}

#[test]
fn insertions() {
    let mut s = base();
    s.insertions = vec![insertion("c", 1.0, 0.0), insertion("d", 10.0, 3.0)];
    s.removals = vec![removal("c", 2.0), removal("a", 10.0)];
    assert_eq!(s.validate(), Ok(())); // at `until` is allowed
    let mut s = base();
    s.insertions = vec![insertion("c", 1.0, 0.0), insertion("", 1.0, 3.0)];
    assert_eq!(err(&s), ScenarioError::EmptyInsertedId { index: 1 });
    for t in [0.0, -1.0, 10.5] {
        let mut s = base();
        s.insertions = vec![insertion("c", t, 0.0)];
        assert!(matches!(
            err(&s),
            ScenarioError::InsertionTimeOutOfRange { index: 0, ref id, .. } if id == "c"
        ));
    }
    // ids are unique across polygons and insertions
    let mut s = base();
    s.insertions = vec![insertion("b", 1.0, 0.0)];
    assert_eq!(err(&s), ScenarioError::DuplicateId { id: "b".into() });
    let mut s = base();
    s.insertions = vec![insertion("c", 1.0, 0.0), insertion("c", 2.0, 3.0)];
    assert_eq!(err(&s), ScenarioError::DuplicateId { id: "c".into() });
    // an inserted polygon follows the rules of `polygons`
    let mut s = base();
    let mut p = insertion("c", 1.0, 0.0);
    p.polygon.vertices.reverse();
    s.insertions = vec![p];
    assert_eq!(err(&s), ScenarioError::Clockwise { id: "c".into() });
    let mut s = base();
    let mut p = insertion("c", 1.0, 0.0);
    p.polygon.vertices.truncate(2);
    s.insertions = vec![p];
    assert_eq!(
        err(&s),
        ScenarioError::TooFewVertices {
            id: "c".into(),
            count: 2
        }
    );
    let mut s = base();
    let mut p = insertion("c", 1.0, 0.0);
    p.polygon.fixed = true;
    p.polygon.velocity = [1.0, 0.0];
    s.insertions = vec![p];
    assert_eq!(err(&s), ScenarioError::FixedWithVelocity { id: "c".into() });
    let mut s = base();
    let mut p = insertion("c", 1.0, 0.0);
    p.polygon.position[0] = f64::NAN;
    s.insertions = vec![p];
    assert!(err(&s).to_string().contains("\"c\" position"));
    // an insertion where a polygon is at time 0 is checked during the run
    let mut s = base();
    s.insertions = vec![Insertion {
        time: 1.0,
        polygon: sq("c", 0.0, 0.0),
    }];
    assert_eq!(s.validate(), Ok(()));
}

#[test]
fn removals() {
    for t in [0.0, -1.0, 10.5, f64::NAN] {
        let mut s = base();
        s.removals = vec![removal("a", t)];
        let e = err(&s);
        if t.is_nan() {
            assert!(e.to_string().contains("removals[0] time"), "{e}");
        } else {
            assert!(matches!(
                e,
                ScenarioError::RemovalTimeOutOfRange { index: 0, ref id, .. } if id == "a"
            ));
        }
    }
    let mut s = base();
    s.removals = vec![removal("a", 1.0), removal("zz", 1.0)];
    assert_eq!(
        err(&s),
        ScenarioError::UnknownRemovalId {
            index: 1,
            id: "zz".into()
        }
    );
    let mut s = base();
    s.removals = vec![removal("b", 1.0), removal("a", 1.0), removal("b", 2.0)];
    assert_eq!(
        err(&s),
        ScenarioError::DuplicateRemoval {
            first: 0,
            second: 2,
            id: "b".into()
        }
    );
    // an inserted polygon leaves strictly after it enters
    for t in [1.0, 2.0] {
        let mut s = base();
        s.insertions = vec![insertion("c", 2.0, 0.0)];
        s.removals = vec![removal("c", t)];
        assert_eq!(
            err(&s),
            ScenarioError::RemovalNotAfterInsertion {
                index: 0,
                id: "c".into(),
                time: t,
                inserted: 2.0
            }
        );
    }
    // fixed polygons may leave
    let mut s = base();
    s.polygons[0].fixed = true;
    s.removals = vec![removal("a", 1.0)];
    assert_eq!(s.validate(), Ok(()));
}

#[test]
fn changes_outside_a_lifetime() {
    // before and at the insertion
    for t in [1.0, 2.0] {
        let mut s = base();
        s.insertions = vec![insertion("c", 2.0, 0.0)];
        s.flight_plan_changes = vec![change("a", 1.0), change("c", t)];
        assert!(matches!(
            err(&s),
            ScenarioError::ChangeOutsideLifetime { index: 1, ref id, time, ref why }
                if id == "c" && time == t && why.contains("insertion")
        ));
    }
    // at and after the removal, of an initial and of an inserted polygon
    for (id, t) in [("a", 3.0), ("a", 4.0), ("c", 3.0), ("c", 4.0)] {
        let mut s = base();
        s.insertions = vec![insertion("c", 2.0, 0.0)];
        s.removals = vec![removal(id, 3.0)];
        s.flight_plan_changes = vec![change(id, 2.5), change(id, t)];
        assert!(matches!(
            err(&s),
            ScenarioError::ChangeOutsideLifetime { index: 1, id: ref got, time, ref why }
                if got == id && time == t && why.contains("removal")
        ));
    }
    // inside the lifetime
    let mut s = base();
    s.insertions = vec![insertion("c", 2.0, 0.0)];
    s.removals = vec![removal("c", 3.0)];
    s.flight_plan_changes = vec![change("c", 2.5)];
    assert_eq!(s.validate(), Ok(()));
}

/// `b` runs into `a` at t = 1 (reported), then `c` enters at t = 2 where
/// `a` is: the run stops with the insertion's error naming both polygons
/// and the time, after the collision was reported, with every structure.
#[test]
fn insertion_touching_a_present_polygon_stops_the_run() {
    let mut s = base();
    s.on_collision = CollisionMode::Bounce;
    s.polygons[0].fixed = true;
    s.polygons[1].velocity = [-2.0, 0.0];
    s.insertions = vec![
        insertion("c", 1.5, 0.0),
        Insertion {
            time: 2.0,
            polygon: sq("d", 0.5, 1.0),
        },
    ];
    for structure in [
        StructureKind::Brute,
        StructureKind::Plain,
        StructureKind::Hierarchical,
    ] {
        let mut events = Vec::new();
        let r = run(
            &s,
            &RunOptions {
                structure,
                audit: true,
                ..Default::default()
            },
            &mut |e| events.push((e.time.to_f64(), e.a.clone(), e.b.clone())),
        );
        assert_eq!(
            events,
            [(1.0, "a".to_string(), "b".to_string())],
            "{}",
            structure.name()
        );
        assert!(
            matches!(
                r,
                Err(RunError::InsertionTouches { ref inserted, ref present, time })
                    if inserted == "d" && present == "a" && time == 2.0
            ),
            "{}: {r:?}",
            structure.name()
        );
    }
}

fn arb_scenario() -> impl Strategy<Value = Scenario> {
    let num = prop_oneof![
        Just(0.0),
        Just(1.0),
        Just(-1.0),
        -10.0..10.0f64,
        any::<f64>(),
        Just(f64::NAN),
        Just(1e308),
        Just(-1e-320),
    ];
    let pt = [num.clone(), num.clone()];
    let poly = (
        "[a-c]{0,2}",
        prop::collection::vec(pt.clone(), 0..6),
        pt.clone(),
        pt.clone(),
        any::<bool>(),
    )
        .prop_map(|(id, vertices, position, velocity, fixed)| PolygonSpec {
            id,
            vertices,
            position,
            velocity,
            fixed,
        });
    let ch = (num.clone(), "[a-c]{1}", pt).prop_map(|(time, id, velocity)| FlightPlanChange {
        time,
        id,
        velocity,
    });
    (
        num,
        prop::sample::select(vec![
            CollisionMode::Stop,
            CollisionMode::Remove,
            CollisionMode::Bounce,
        ]),
        prop::collection::vec(poly, 0..4),
        prop::collection::vec(ch, 0..3),
    )
        .prop_map(
            |(until, on_collision, polygons, flight_plan_changes)| Scenario {
                until,
                on_collision,
                polygons,
                flight_plan_changes,
                ..Default::default()
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Arbitrary (mostly invalid) input: validation answers, running never panics.
    #[test]
    fn never_panics(s in arb_scenario()) {
        let opts = RunOptions { structure: StructureKind::Brute, until: Some(5.0), ..Default::default() };
        match s.validate() {
            Ok(()) => { run(&s, &opts, &mut |_| {}).expect("valid scenarios run"); }
            Err(e) => { prop_assert!(!e.to_string().is_empty()); }
        }
    }
}
