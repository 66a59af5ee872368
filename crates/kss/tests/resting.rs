//! Resting contacts: where two polygons stay in contact at an instant at
//! which the structure has to be built afresh, no pseudo-triangulation of
//! the pinched free space exists; the reference stands in until no pair
//! rests in contact, and the structure takes over again (see
//! ARCHITECTURE.md, "Resting contacts").

use kss::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario, StructureKind};

mod common;

use common::events;

/// Three polygons meet at the origin at t = 3 (gen_small simultaneous seed
/// 972, which stopped with "no rebuild just after t = 3 found"); `t1`
/// stops there, resting on the fixed `t2` vertex to vertex; at t = 4 it
/// backs off, at t = 5 it comes back and hits `t2` again at t = 6.
fn resting_then_apart() -> Scenario {
    let polygon = |id: &str, vertices: &[[f64; 2]], position, velocity, fixed| PolygonSpec {
        id: id.into(),
        vertices: vertices.to_vec(),
        position,
        velocity,
        fixed,
    };
    let change = |time, id: &str, velocity| FlightPlanChange {
        time,
        id: id.into(),
        velocity,
    };
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
    }
}

#[test]
fn the_reference_stands_in_while_two_polygons_rest_in_contact() {
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
    for structure in [StructureKind::Plain, StructureKind::Hierarchical] {
        let (got, stats) = events(&s, structure, true).expect("runs");
        assert_eq!(got, want, "{}", structure.name());
        // stood in at t = 3, and the structure took over at t = 4 (the
        // collision at t = 6 and the internal events come from it)
        assert_eq!(stats.stand_ins, 1, "{}", structure.name());
        assert_eq!(stats.stand_in_ends, 1, "{}", structure.name());
        assert!(stats.events_by_kind.len() > 2, "{}", structure.name());
    }
}

/// Without the last two flight-plan changes `t1` rests on `t2` until the
/// end: the reference stands in for the rest of the run.
#[test]
fn a_contact_that_rests_for_ever_keeps_the_reference() {
    let mut s = resting_then_apart();
    s.flight_plan_changes.truncate(1);
    let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
    for structure in [StructureKind::Plain, StructureKind::Hierarchical] {
        let (got, stats) = events(&s, structure, true).expect("runs");
        assert_eq!(got, want, "{}", structure.name());
        assert_eq!(stats.stand_ins, 1, "{}", structure.name());
        assert_eq!(stats.stand_in_ends, 0, "{}", structure.name());
    }
}
