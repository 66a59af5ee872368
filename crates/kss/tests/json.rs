//! The scenario files' JSON (`kss::json`, the contract of
//! `docs/scenario-format.md`): the reader's values, defaults and correctly
//! rounded numbers, its errors (each naming the entry it is about), and the
//! writer, whose text reads back to the identical scenario.

use kss::gen::Family;
use kss::json::{parse_scenario, write_scenario, ScenarioJsonError};
use kss::Scenario;

/// The error `parse_scenario` gives for `text` (which it must refuse).
fn err(text: &str) -> ScenarioJsonError {
    match parse_scenario(text) {
        Ok(sc) => panic!("accepted {text}: {sc:?}"),
        Err(e) => e,
    }
}

/// Bit-exact equality of two polygons (`-0.0` differs from `0.0`).
fn assert_identical_polygon(p: &kss::PolygonSpec, q: &kss::PolygonSpec) {
    let bits = |x: &[f64; 2]| [x[0].to_bits(), x[1].to_bits()];
    assert_eq!(p.id, q.id);
    assert_eq!(p.fixed, q.fixed);
    assert_eq!(bits(&p.position), bits(&q.position), "{}", p.id);
    assert_eq!(bits(&p.velocity), bits(&q.velocity), "{}", p.id);
    assert_eq!(p.vertices.len(), q.vertices.len());
    for (u, v) in p.vertices.iter().zip(&q.vertices) {
        assert_eq!(bits(u), bits(v), "{}", p.id);
    }
}

/// Bit-exact equality of two scenarios (`-0.0` differs from `0.0`).
fn assert_identical(a: &Scenario, b: &Scenario) {
    let bits = |x: &[f64; 2]| [x[0].to_bits(), x[1].to_bits()];
    assert_eq!(a.until.to_bits(), b.until.to_bits());
    assert_eq!(a.on_collision, b.on_collision);
    assert_eq!(a.polygons.len(), b.polygons.len());
    for (p, q) in a.polygons.iter().zip(&b.polygons) {
        assert_identical_polygon(p, q);
    }
    assert_eq!(a.flight_plan_changes.len(), b.flight_plan_changes.len());
    for (c, d) in a.flight_plan_changes.iter().zip(&b.flight_plan_changes) {
        assert_eq!(c.id, d.id);
        assert_eq!(c.time.to_bits(), d.time.to_bits());
        assert_eq!(bits(&c.velocity), bits(&d.velocity));
    }
    assert_eq!(a.insertions.len(), b.insertions.len());
    for (i, j) in a.insertions.iter().zip(&b.insertions) {
        assert_eq!(i.time.to_bits(), j.time.to_bits(), "{}", i.polygon.id);
        assert_identical_polygon(&i.polygon, &j.polygon);
    }
    assert_eq!(a.removals.len(), b.removals.len());
    for (r, q) in a.removals.iter().zip(&b.removals) {
        assert_eq!(r.id, q.id);
        assert_eq!(r.time.to_bits(), q.time.to_bits(), "{}", r.id);
    }
}

/// A counter-clockwise triangle.
const TRIANGLE: &str = r#"[[-1.0, 0.0], [1.0, 0.0], [0.0, 1.5]]"#;

#[test]
fn the_contract_example_parses() {
    let sc = parse_scenario(
        r#"{
  "version": 1,
  "until": 50.0,
  "on_collision": "remove",
  "polygons": [
    {
      "id": "a",
      "vertices": [[-1.0, 0.0], [1.0, 0.0], [0.0, 1.5]],
      "position": [0.0, 0.0],
      "velocity": [1.0, 0.25]
    },
    {
      "id": "wall",
      "vertices": [[0, 0], [1, 0], [1, 20], [0, 20]],
      "position": [30.0, -10.0],
      "fixed": true
    }
  ],
  "flight_plan_changes": [
    { "time": 10.0, "id": "a", "velocity": [0.0, -1.0] }
  ]
}"#,
    )
    .unwrap();
    assert_eq!(sc.until, 50.0);
    assert_eq!(sc.on_collision, kss::CollisionMode::Remove);
    assert_eq!(sc.polygons.len(), 2);
    assert_eq!(sc.polygons[1].velocity, [0.0, 0.0]);
    assert!(sc.polygons[1].fixed);
    assert_eq!(sc.polygons[1].vertices[2], [1.0, 20.0]);
    assert_eq!(sc.flight_plan_changes[0].velocity, [0.0, -1.0]);
}

#[test]
fn absent_optional_fields_take_their_defaults_and_unknown_ones_are_ignored() {
    let sc = parse_scenario(
        r#"{"version": 1, "until": 1, "comment": "hi", "polygons": [
            {"id": "a", "vertices": [[0,0],[1,0],[0,1]], "position": [0,0], "colour": "red"}]}"#,
    )
    .unwrap();
    assert_eq!(sc.on_collision, kss::CollisionMode::Stop);
    assert_eq!(sc.polygons[0].velocity, [0.0, 0.0]);
    assert!(!sc.polygons[0].fixed);
    assert!(sc.flight_plan_changes.is_empty());
    let empty = parse_scenario(r#"{"version": 1, "until": 1, "polygons": []}"#).unwrap();
    assert!(empty.polygons.is_empty());
}

#[test]
fn numbers_are_correctly_rounded() {
    let literal = |lit: &str| -> f64 {
        let sc = parse_scenario(&format!(
            r#"{{"version": 1, "until": {lit}, "polygons": []}}"#
        ))
        .unwrap();
        sc.until
    };
    for lit in [
        "0.1",
        "2.2250738585072011e-308",
        "1.7976931348623157e308",
        "4.9e-324",
        "9007199254740993",
        "123456789012345678901234567890",
        "0.30000000000000004",
        "1.00000000000000011102230246251565404236316680908203125",
        "1.000000000000000111022302462515654042363166809082031251",
        "18446744073709551615",
        "-9223372036854775809",
    ] {
        let want: f64 = lit.parse().unwrap();
        assert_eq!(literal(lit).to_bits(), want.to_bits(), "{lit}");
    }
    assert_eq!(
        literal("1.00000000000000011102230246251565404236316680908203125"),
        1.0
    );
    assert!(literal("1.000000000000000111022302462515654042363166809082031251") > 1.0);
}

#[test]
fn malformed_json_is_refused_with_its_line_and_column() {
    let e = err("{\n  \"version\": 1,\n  \"until\": 5,\n  \"polygons\": [ }\n");
    match &e {
        ScenarioJsonError::Syntax { line, column, .. } => {
            assert_eq!(*line, 4);
            assert!(*column > 0);
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("line 4"), "{e}");
    assert!(matches!(err(""), ScenarioJsonError::Syntax { .. }));
    assert!(matches!(
        err("{\"version\": 1"),
        ScenarioJsonError::Syntax { .. }
    ));
    assert!(matches!(err("[1, 2] x"), ScenarioJsonError::Syntax { .. }));
}

#[test]
fn numbers_beyond_the_largest_double_are_refused_and_below_the_smallest_read_as_zero() {
    for lit in [
        "1e999",
        "-1e999",
        "1.5e309",
        &format!("1{}", "0".repeat(400)),
    ] {
        let e = err(&format!(
            r#"{{"version": 1, "until": 5, "polygons": [
                {{"id": "a", "vertices": [[0,0],[{lit},0],[0,1]], "position": [0,0]}}]}}"#
        ));
        match &e {
            ScenarioJsonError::NumberOutOfRange { line, .. } => assert_eq!(*line, 2),
            other => panic!("{lit}: {other:?}"),
        }
        assert!(e.to_string().contains("out of range"), "{e}");
    }
    // Underflow is not an error: the literal means the nearest double, 0.
    let sc = parse_scenario(r#"{"version": 1, "until": 1e-999, "polygons": []}"#).unwrap();
    assert_eq!(sc.until, 0.0);
}

#[test]
fn a_missing_top_level_field_is_named() {
    for (text, field) in [
        (r#"{"until": 5, "polygons": []}"#, "version"),
        (r#"{"version": 1, "polygons": []}"#, "until"),
        (r#"{"version": 1, "until": 5}"#, "polygons"),
    ] {
        let e = err(text);
        assert_eq!(
            e,
            ScenarioJsonError::MissingField {
                entry: "scenario".into(),
                field
            }
        );
        assert!(e.to_string().contains(field), "{e}");
    }
}

#[test]
fn a_missing_polygon_field_names_the_polygon() {
    let e =
        err(r#"{"version": 1, "until": 5, "polygons": [{"vertices": [], "position": [0, 0]}]}"#);
    assert_eq!(
        e,
        ScenarioJsonError::MissingField {
            entry: "polygons[0]".into(),
            field: "id"
        }
    );
    let e = err(r#"{"version": 1, "until": 5, "polygons": [{"id": "rock", "position": [0, 0]}]}"#);
    assert!(matches!(
        &e,
        ScenarioJsonError::MissingField {
            field: "vertices",
            ..
        }
    ));
    assert!(
        e.to_string().contains("\"rock\"") && e.to_string().contains("vertices"),
        "{e}"
    );
    let e = err(&format!(
        r#"{{"version": 1, "until": 5, "polygons": [
            {{"id": "ok", "vertices": {TRIANGLE}, "position": [0, 0]}},
            {{"id": "lost", "vertices": {TRIANGLE}}}]}}"#
    ));
    assert!(matches!(
        &e,
        ScenarioJsonError::MissingField {
            field: "position",
            ..
        }
    ));
    let msg = e.to_string();
    assert!(
        msg.contains("polygons[1]") && msg.contains("\"lost\"") && msg.contains("position"),
        "{msg}"
    );
}

#[test]
fn a_missing_change_field_names_the_change() {
    for (change, field) in [
        (r#"{"id": "a", "velocity": [0, 1]}"#, "time"),
        (r#"{"time": 1, "velocity": [0, 1]}"#, "id"),
        (r#"{"time": 1, "id": "a"}"#, "velocity"),
    ] {
        let e = err(&format!(
            r#"{{"version": 1, "until": 5, "polygons": [], "flight_plan_changes": [
                {{"time": 0.5, "id": "a", "velocity": [1, 0]}}, {change}]}}"#
        ));
        assert_eq!(
            e,
            ScenarioJsonError::MissingField {
                entry: "flight_plan_changes[1]".into(),
                field
            },
            "{change}"
        );
        assert!(e.to_string().contains("flight_plan_changes[1]"));
    }
}

#[test]
fn a_field_of_the_wrong_type_is_named() {
    let e = err(&format!(
        r#"{{"version": 1, "until": 5, "polygons": [
            {{"id": "jet", "vertices": {TRIANGLE}, "position": [0, 0], "velocity": "fast"}}]}}"#
    ));
    match &e {
        ScenarioJsonError::WrongType { entry, field, .. } => {
            assert!(entry.contains("\"jet\""));
            assert_eq!(field, "velocity");
        }
        other => panic!("{other:?}"),
    }
    let msg = e.to_string();
    assert!(
        msg.contains("jet") && msg.contains("velocity") && msg.contains("\"fast\""),
        "{msg}"
    );

    let cases = [
        (
            r#"{"version": 1, "until": "soon", "polygons": []}"#,
            "until",
        ),
        (r#"{"version": 1, "until": 5, "polygons": {}}"#, "polygons"),
        (
            r#"{"version": 1, "until": 5, "polygons": [], "on_collision": 3}"#,
            "on_collision",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [], "flight_plan_changes": 3}"#,
            "flight_plan_changes",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [{"id": 7, "vertices": [], "position": [0,0]}]}"#,
            "id",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [{"id": "f", "vertices": [], "position": [0,0], "fixed": "yes"}]}"#,
            "fixed",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [{"id": "v", "vertices": 3, "position": [0,0]}]}"#,
            "vertices",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [{"id": "p", "vertices": [], "position": null}]}"#,
            "position",
        ),
        (
            r#"{"version": 1, "until": 5, "polygons": [], "flight_plan_changes": [{"time": "1", "id": "a", "velocity": [0, 0]}]}"#,
            "time",
        ),
    ];
    for (text, want) in cases {
        match err(text) {
            ScenarioJsonError::WrongType { field, .. } => assert_eq!(field, want, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
    }
    assert!(matches!(err("[1, 2]"), ScenarioJsonError::WrongType { .. }));
    assert!(matches!(
        err(r#"{"version": 1, "until": 5, "polygons": [3]}"#),
        ScenarioJsonError::WrongType { entry, .. } if entry == "polygons[0]"
    ));
}

#[test]
fn an_unknown_collision_mode_is_refused() {
    let e = err(r#"{"version": 1, "until": 5, "on_collision": "explode", "polygons": []}"#);
    assert_eq!(
        e,
        ScenarioJsonError::UnknownMode {
            value: "explode".into()
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("on_collision") && msg.contains("explode") && msg.contains("bounce"),
        "{msg}"
    );
}

#[test]
fn versions_other_than_1_are_refused() {
    for (v, shown) in [("2", "2"), ("0", "0"), ("1.5", "1.5"), ("\"1\"", "string")] {
        let e = err(&format!(
            r#"{{"version": {v}, "until": 5, "polygons": []}}"#
        ));
        assert!(matches!(e, ScenarioJsonError::BadVersion { .. }), "{v}");
        let msg = e.to_string();
        assert!(msg.contains("version") && msg.contains(shown), "{msg}");
    }
    // 1.0 is the number 1.
    assert!(parse_scenario(r#"{"version": 1.0, "until": 5, "polygons": []}"#).is_ok());
}

#[test]
fn a_point_that_is_not_two_numbers_is_refused() {
    for (bad, field) in [
        ("[[0,0],[1,0,0],[0,1]]", "vertices[1]"),
        ("[[0,0],[1,0],[0]]", "vertices[2]"),
        ("[[0,0],[1,0],[0,\"1\"]]", "vertices[2]"),
        ("[[0,0],3,[0,1]]", "vertices[1]"),
        ("[[0,0],[],[0,1]]", "vertices[1]"),
    ] {
        let e = err(&format!(
            r#"{{"version": 1, "until": 5, "polygons": [{{"id": "tri", "vertices": {bad}, "position": [0,0]}}]}}"#
        ));
        match &e {
            ScenarioJsonError::BadPoint {
                entry, field: f, ..
            } => {
                assert!(entry.contains("\"tri\""), "{entry}");
                assert_eq!(f, field);
            }
            other => panic!("{bad}: {other:?}"),
        }
        assert!(e.to_string().contains(field));
    }
    for bad in ["[1, 2, 3]", "[1]", "[true, 2]"] {
        let e = err(&format!(
            r#"{{"version": 1, "until": 5, "polygons": [{{"id": "p", "vertices": {TRIANGLE}, "position": {bad}}}]}}"#
        ));
        assert!(
            matches!(&e, ScenarioJsonError::BadPoint { field, .. } if field == "position"),
            "{bad}: {e:?}"
        );
    }
}

#[test]
fn written_scenarios_read_back_identically() {
    for f in Family::ALL {
        for seed in 0..25 {
            let sc = kss::gen::generate_small(f, seed);
            let text = write_scenario(&sc).unwrap();
            let back = parse_scenario(&text).unwrap();
            assert_identical(&sc, &back);
        }
    }
    // Awkward doubles, negative zero, an empty scenario, escaped ids.
    let mut sc = kss::gen::demo();
    sc.polygons[0].position = [-0.0, 5e-324];
    sc.polygons[0].velocity = [0.1 + 0.2, 1.7976931348623157e308];
    sc.polygons[1].id = "quote\" back\\ slash \u{1} ünï".into();
    let back = parse_scenario(&write_scenario(&sc).unwrap()).unwrap();
    assert_identical(&sc, &back);
    let empty = Scenario {
        until: 1.0,
        on_collision: kss::CollisionMode::Bounce,
        polygons: vec![],
        flight_plan_changes: vec![],
        ..Default::default()
    };
    assert_identical(
        &empty,
        &parse_scenario(&write_scenario(&empty).unwrap()).unwrap(),
    );
    let mut bad = kss::gen::demo();
    bad.polygons[2].vertices[1][0] = f64::NAN;
    let e = write_scenario(&bad).unwrap_err();
    assert!(e.to_string().contains(&bad.polygons[2].id));
}

/// A scenario with insertions and removals of awkward numbers and ids.
fn churned_demo() -> Scenario {
    let mut sc = kss::gen::demo();
    let mut late = sc.polygons[0].clone();
    late.id = "late \"one\" ü".into();
    late.position = [-0.0, 0.1 + 0.2];
    late.velocity = [5e-324, -1.7976931348623157e308];
    let mut wall = sc.polygons[1].clone();
    wall.id = "late wall".into();
    wall.velocity = [0.0, 0.0];
    wall.fixed = true;
    sc.insertions = vec![
        kss::Insertion {
            time: 1.0 / 3.0,
            polygon: late,
        },
        kss::Insertion {
            time: 2.5,
            polygon: wall,
        },
    ];
    sc.removals = vec![
        kss::Removal {
            time: 0.1,
            id: sc.polygons[2].id.clone(),
        },
        kss::Removal {
            time: 2.5f64.next_up(),
            id: "late wall".into(),
        },
    ];
    sc
}

#[test]
fn insertions_and_removals_are_written_one_per_line_and_read_back_identically() {
    let sc = churned_demo();
    let text = write_scenario(&sc).unwrap();
    let back = parse_scenario(&text).unwrap();
    assert_identical(&sc, &back);
    assert_eq!(back, sc);
    // one entry per line
    let lines: Vec<&str> = text.lines().collect();
    let entries = |polygon: bool| {
        lines
            .iter()
            .filter(|l| l.trim_start().starts_with("{\"time\":"))
            .filter(|l| l.contains("\"polygon\":{") == polygon && l.contains("velocity") == polygon)
            .count()
    };
    assert_eq!(entries(true), 2, "{text}");
    assert_eq!(entries(false), 2, "{text}");
    assert!(
        lines.iter().any(|l| l.trim() == "\"insertions\": ["),
        "{text}"
    );
    assert!(
        lines.iter().any(|l| l.trim() == "\"removals\": ["),
        "{text}"
    );
    // only one of the two arrays
    for (insertions, removals) in [(true, false), (false, true)] {
        let mut one = sc.clone();
        if !insertions {
            one.insertions.clear();
        }
        if !removals {
            one.removals.clear();
        }
        let text = write_scenario(&one).unwrap();
        assert_eq!(text.contains("\"insertions\""), insertions, "{text}");
        assert_eq!(text.contains("\"removals\""), removals, "{text}");
        assert_identical(&one, &parse_scenario(&text).unwrap());
    }
    // generated scenes
    for seed in 0..10 {
        for mode in [
            kss::CollisionMode::Stop,
            kss::CollisionMode::Remove,
            kss::CollisionMode::Bounce,
        ] {
            let sc = kss::gen::churn(&kss::gen::ChurnParams {
                mode,
                seed,
                ..Default::default()
            });
            assert!(!sc.insertions.is_empty() && !sc.removals.is_empty());
            let back = parse_scenario(&write_scenario(&sc).unwrap()).unwrap();
            assert_identical(&sc, &back);
        }
    }
    // non-finite numbers name the entry
    let mut bad = churned_demo();
    bad.insertions[1].polygon.vertices[0][1] = f64::INFINITY;
    let e = write_scenario(&bad).unwrap_err().to_string();
    assert!(
        e.contains("insertions[1]") && e.contains("late wall"),
        "{e}"
    );
    let mut bad = churned_demo();
    bad.removals[0].time = f64::NAN;
    let e = write_scenario(&bad).unwrap_err().to_string();
    assert!(e.contains("removals[0]"), "{e}");
}

#[test]
fn empty_insertions_and_removals_are_left_out() {
    // a scenario without them is written exactly as the contract's older
    // files: the two arrays are absent
    let sc = kss::gen::generate_small(Family::Gas, 4);
    let text = write_scenario(&sc).unwrap();
    assert!(
        !text.contains("insertions") && !text.contains("removals"),
        "{text}"
    );
    assert!(
        text.ends_with("  ]\n}\n") || text.ends_with("[]\n}\n"),
        "{text}"
    );
    let empty = Scenario {
        until: 2.0,
        ..Default::default()
    };
    assert_eq!(
        write_scenario(&empty).unwrap(),
        "{\n  \"version\": 1,\n  \"until\": 2.0,\n  \"on_collision\": \"stop\",\n  \"polygons\": [],\n  \"flight_plan_changes\": []\n}\n"
    );
}
