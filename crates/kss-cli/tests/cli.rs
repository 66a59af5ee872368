//! Tests of the `kss` command line: the event lines and statistics it
//! prints, and the binary's subcommands, messages and exit statuses. (The
//! JSON reader and writer are `kss::json`'s, tested in `crates/kss/tests/json.rs`.)

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

use kss::gen::Family;
use kss::json::{parse_scenario, write_scenario};
use kss::Scenario;

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

fn kss() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kss"))
}

fn run_kss(args: &[&str], stdin: Option<&str>) -> Output {
    let mut cmd = kss();
    cmd.args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("start kss");
    {
        use std::io::Write;
        let mut input = child.stdin.take().expect("stdin");
        if let Some(text) = stdin {
            // kss may exit before reading its input (a bad command line)
            if let Err(e) = input.write_all(text.as_bytes()) {
                assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "write stdin: {e}");
            }
        }
    }
    child.wait_with_output().expect("wait for kss")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

/// A fresh directory for one test's files.
fn temp_dir() -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "kss-cli-test-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
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

const TRIANGLE: &str = r#"[[-1.0, 0.0], [1.0, 0.0], [0.0, 1.5]]"#;

/// A valid scenario: two triangles approaching head-on (they touch at t = 1).
fn two_triangles(mode: &str) -> String {
    format!(
        r#"{{"version": 1, "until": 5, "on_collision": "{mode}", "polygons": [
            {{"id": "a", "vertices": {TRIANGLE}, "position": [0, 0], "velocity": [1, 0]}},
            {{"id": "b", "vertices": {TRIANGLE}, "position": [4, 0], "velocity": [-1, 0]}}
        ]}}"#
    )
}

// ---------------------------------------------------------------------------
// Event lines and statistics
// ---------------------------------------------------------------------------

#[test]
fn event_lines_and_stats_are_json() {
    let e = kss::CollisionEvent {
        time: kss_time(2.5),
        a: "p\"1".into(),
        b: "p2".into(),
        point: [1.0, -0.5],
        again: false,
    };
    let line = kss_cli::commands::event_line(&e);
    let v: serde_json::Value = serde_json::from_str(&line).unwrap();
    assert_eq!(v["time"], 2.5);
    assert_eq!(v["a"], "p\"1");
    assert_eq!(v["b"], "p2");
    assert!(line.starts_with("{\"time\": 2.5, \"a\": "), "{line}");
    let mut stats = kss::RunStats {
        structure: "brute",
        polygons: 2,
        vertices: 6,
        events_processed: 3,
        collisions: 1,
        ..Default::default()
    };
    stats.events_by_kind.insert("collision".into(), 1);
    let v: serde_json::Value =
        serde_json::from_str(&kss_cli::commands::stats_json(&stats, 0.25)).unwrap();
    for key in [
        "structure",
        "polygons",
        "vertices",
        "events_processed",
        "events_by_kind",
        "certificates_max",
        "certificates_final",
        "collisions",
        "wall_seconds",
    ] {
        assert!(v.get(key).is_some(), "{key}");
    }
    assert_eq!(v["events_by_kind"]["collision"], 1);
    assert_eq!(v["wall_seconds"], 0.25);
}

/// The event time type of the library, built from a double.
fn kss_time(t: f64) -> kss::num::Time {
    kss::num::Time::from_f64(t).expect("a finite time")
}

#[test]
fn an_event_line_leaves_out_a_point_that_is_not_finite() {
    for point in [
        [f64::INFINITY, 0.0],
        [f64::NAN, 1.0],
        [0.5, f64::NEG_INFINITY],
    ] {
        let e = kss::CollisionEvent {
            time: kss_time(0.5),
            a: "a".into(),
            b: "b".into(),
            point,
            again: false,
        };
        let line = kss_cli::commands::event_line(&e);
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert_eq!(v["time"], 0.5, "{line}");
        assert!(v.get("point").is_none(), "{line}");
    }
}

// ---------------------------------------------------------------------------
// The binary
// ---------------------------------------------------------------------------

#[test]
fn help_and_usage_errors() {
    let o = run_kss(&["--help"], None);
    assert!(o.status.success());
    let text = stdout(&o);
    for cmd in ["run", "gen", "render", "demo"] {
        assert!(text.contains(cmd), "{text}");
    }
    let o = run_kss(&["run"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["run", "x.json", "--until", "-1"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["run", "x.json", "--structure", "quantum"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["gen", "nebula"], None);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn gen_every_family_round_trips() {
    for f in Family::ALL {
        for seed in [0u64, 7] {
            let s = seed.to_string();
            let o = run_kss(&["gen", f.name(), "--small", "--seed", &s], None);
            assert!(o.status.success(), "{}: {}", f.name(), stderr(&o));
            let sc = parse_scenario(&stdout(&o)).unwrap();
            assert_identical(&sc, &kss::gen::generate_small(f, seed));
            // Default parameters too (and stdout carries nothing else).
            let o = run_kss(&["gen", f.name(), "--seed", &s], None);
            assert!(o.status.success(), "{}: {}", f.name(), stderr(&o));
            let sc = parse_scenario(&stdout(&o)).unwrap();
            assert!(sc.polygons.len() >= 2, "{}", f.name());
            let again = run_kss(&["gen", f.name(), "--seed", &s], None);
            assert_eq!(o.stdout, again.stdout, "{} is not deterministic", f.name());
        }
    }
}

#[test]
fn gen_options_and_output_file() {
    let dir = temp_dir();
    let path = dir.join("fly.json");
    let p = path.to_str().unwrap();
    let o = run_kss(
        &[
            "gen",
            "flypast",
            "--n",
            "1000",
            "--ratio",
            "100",
            "--a-moving",
            "-o",
            p,
            "--seed",
            "3",
        ],
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    assert!(stderr(&o).contains("achieved gap"));
    let sc = parse_scenario(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(sc.polygons.len(), 2);
    assert_eq!(sc.polygons[0].vertices.len(), 1000);
    assert!(!sc.polygons[0].fixed);
    let want = kss::gen::flypast(&kss::gen::FlypastParams {
        n: 1000,
        gap: 0.01,
        a_moving: true,
        seed: 3,
        ..Default::default()
    });
    assert_identical(&sc, &want);

    let o = run_kss(
        &["gen", "flypast", "--gap", "-0.1", "--mode", "remove"],
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sc = parse_scenario(&stdout(&o)).unwrap();
    assert_eq!(sc.on_collision, kss::CollisionMode::Remove);
    assert!(stderr(&o).contains("collide"));

    let o = run_kss(
        &[
            "gen",
            "gas",
            "--k",
            "9",
            "--n",
            "5",
            "--walls",
            "--changes",
            "3",
        ],
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sc = parse_scenario(&stdout(&o)).unwrap();
    assert_eq!(sc.polygons.len(), 13);
    assert_eq!(sc.on_collision, kss::CollisionMode::Bounce);
    assert!(sc.polygons.iter().filter(|p| p.fixed).count() == 4);

    let o = run_kss(
        &["gen", "simultaneous", "--pairs", "5", "--no-triple"],
        None,
    );
    let sc = parse_scenario(&stdout(&o)).unwrap();
    assert_eq!(sc.polygons.len(), 10);
    let o = run_kss(&["gen", "far", "--k", "4", "--offset", "2e6"], None);
    let sc = parse_scenario(&stdout(&o)).unwrap();
    assert!(sc
        .polygons
        .iter()
        .all(|p| p.position[0] + p.vertices[0][0] > 1.9e6));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn gen_swarm_generates_and_runs() {
    let dir = temp_dir();
    let path = dir.join("swarm.json");
    let p = path.to_str().unwrap();
    let gen = [
        "gen",
        "swarm",
        "--k",
        "9",
        "--n",
        "12",
        "--collisions",
        "3",
        "--seed",
        "2",
    ];
    let o = run_kss(&[&gen[..], &["-o", p]].concat(), None);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    assert!(stderr(&o).contains("calibrated"), "{}", stderr(&o));
    let sc = parse_scenario(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let want = kss::gen::swarm(&kss::gen::SwarmParams {
        k: 9,
        n: 12,
        collisions_per_polygon: 3.0,
        seed: 2,
        ..Default::default()
    });
    assert_identical(&sc, &want);
    assert_eq!(sc.on_collision, kss::CollisionMode::Bounce);
    assert_eq!(sc.polygons.len(), 13);
    assert_eq!(sc.polygons.iter().filter(|p| p.fixed).count(), 4);
    assert_eq!(sc.polygons[0].id, "s0");
    assert!(sc
        .polygons
        .iter()
        .filter(|p| !p.fixed)
        .all(|p| p.vertices.len() == 12));

    // the library's structure and the reference report the same collisions
    let mut outputs = Vec::new();
    for structure in ["hierarchical", "brute"] {
        let stats = dir.join(format!("{structure}.json"));
        let o = run_kss(
            &[
                "run",
                p,
                "--structure",
                structure,
                "--stats",
                stats.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(o.status.code(), Some(0), "{structure}: {}", stderr(&o));
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        assert_eq!(v["polygons"], 13);
        assert!(v["collisions"].as_u64().unwrap() > 0, "{structure}: {v}");
        outputs.push(o.stdout);
    }
    assert_eq!(outputs[0], outputs[1]);

    // remove mode: the same polygons and until
    let o = run_kss(&[&gen[..], &["--mode", "remove"]].concat(), None);
    assert!(o.status.success(), "{}", stderr(&o));
    let removed = parse_scenario(&stdout(&o)).unwrap();
    assert_eq!(removed.on_collision, kss::CollisionMode::Remove);
    assert_eq!(removed.until, sc.until);
    assert_eq!(removed.polygons, sc.polygons);
    let o = run_kss(
        &["run", "-", "--structure", "hierarchical"],
        Some(&stdout(&o)),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!o.stdout.is_empty());

    // refused parameters
    let o = run_kss(&["gen", "swarm", "--n", "2"], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("n is 2"), "{}", stderr(&o));
    let o = run_kss(&["gen", "swarm", "--k", "0"], None);
    assert_eq!(o.status.code(), Some(1));
    let o = run_kss(&["gen", "swarm", "--small"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["gen", "swarm", "--collisions", "3", "--until", "2"], None);
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn gen_refuses_bad_parameters() {
    let o = run_kss(&["gen", "flypast", "--n", "2"], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("n is 2"), "{}", stderr(&o));
    let o = run_kss(&["gen", "flypast", "--gap", "-5"], None);
    assert_eq!(o.status.code(), Some(1));
    let o = run_kss(&["gen", "gas", "--min-n", "2"], None);
    assert_eq!(o.status.code(), Some(1));
    let o = run_kss(&["gen", "gas", "--small", "--k", "3"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["gen", "flypast", "--gap", "1", "--ratio", "3"], None);
    assert_eq!(o.status.code(), Some(2));
    let o = run_kss(&["gen", "grazing", "--pairs", "0"], None);
    assert_eq!(o.status.code(), Some(1));
}

/// The `kss gen churn` command line of a seed and mode.
fn churn_args(seed: u64, mode: &str) -> Vec<String> {
    ["gen", "churn", "--seed", &seed.to_string(), "--mode", mode]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

#[test]
fn gen_churn_writes_the_library_scene() {
    for (seed, mode, want_mode) in [
        (3, "stop", kss::CollisionMode::Stop),
        (4, "remove", kss::CollisionMode::Remove),
        (5, "bounce", kss::CollisionMode::Bounce),
    ] {
        let args = churn_args(seed, mode);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run_kss(&args, None);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("insertions"), "{}", stderr(&o));
        let sc = parse_scenario(&stdout(&o)).unwrap();
        let want = kss::gen::churn(&kss::gen::ChurnParams {
            mode: want_mode,
            seed,
            ..Default::default()
        });
        assert_identical(&sc, &want);
        assert!(sc.insertions.iter().any(|i| i.polygon.fixed));
        assert!(sc.removals.len() >= 3);
    }
    // the scenes whose collisions kss's `plain_vs_brute` test compares
    // between the structures (`churn_scenes_give_identical_events_with_every_structure`)
    for (mode, want_mode) in [
        ("stop", kss::CollisionMode::Stop),
        ("remove", kss::CollisionMode::Remove),
        ("bounce", kss::CollisionMode::Bounce),
    ] {
        for seed in 0..8 {
            let args = churn_args(seed, mode);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = run_kss(&args, None);
            assert!(o.status.success(), "{}", stderr(&o));
            let want = kss::gen::churn(&kss::gen::ChurnParams {
                mode: want_mode,
                seed,
                ..Default::default()
            });
            assert_identical(&parse_scenario(&stdout(&o)).unwrap(), &want);
        }
    }
    // options and the default mode
    let o = run_kss(
        &[
            "gen",
            "churn",
            "--k",
            "5",
            "--clusters",
            "2",
            "--until",
            "3",
            "--seed",
            "9",
        ],
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sc = parse_scenario(&stdout(&o)).unwrap();
    let want = kss::gen::churn(&kss::gen::ChurnParams {
        k: 5,
        clusters: 2,
        until: 3.0,
        seed: 9,
        ..Default::default()
    });
    assert_identical(&sc, &want);
    assert_eq!(sc.on_collision, kss::CollisionMode::Remove);
    assert_eq!(sc.until, 3.0);
    // refused parameters
    let o = run_kss(&["gen", "churn", "--until", "0.5"], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("until is 0.5"), "{}", stderr(&o));
    let o = run_kss(&["gen", "churn", "--small"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("churn"), "{}", stderr(&o));
}

/// Runs a scenario text with a structure; exit status and stdout.
fn run_text(text: &str, structure: &str, extra: &[&str]) -> Output {
    let args = [
        &["run", "-", "--structure", structure, "--quiet"][..],
        extra,
    ]
    .concat();
    run_kss(&args, Some(text))
}

const SQUARE: &str = "[[0, 0], [1, 0], [1, 1], [0, 1]]";

/// Unit squares in `remove` mode: `a` and `b` collide at t = 1 (edges
/// 1 + t and 3 - t), `d` and `e` at t = 2.5 (edges 1 + t and 6 - t); `post`
/// is fixed at [6, 7] × [4, 5]; `extra` is appended to the top level.
fn squares_with(extra: &str) -> String {
    format!(
        r#"{{"version": 1, "until": 10, "on_collision": "remove", "polygons": [
            {{"id": "a", "vertices": {SQUARE}, "position": [0, 0], "velocity": [1, 0]}},
            {{"id": "b", "vertices": {SQUARE}, "position": [3, 0], "velocity": [-1, 0]}},
            {{"id": "d", "vertices": {SQUARE}, "position": [0, 8], "velocity": [1, 0]}},
            {{"id": "e", "vertices": {SQUARE}, "position": [6, 8], "velocity": [-1, 0]}},
            {{"id": "post", "vertices": {SQUARE}, "position": [6, 4], "fixed": true}}
        ]{extra}}}"#
    )
}

const EVENT_AB: &str = r#"{"time": 1.0, "a": "a", "b": "b""#;
const EVENT_DE: &str = r#"{"time": 2.5, "a": "d", "b": "e""#;

#[test]
fn insertion_touching_a_present_polygon_stops_the_run() {
    // late overlaps post at t = 2, after a and b collided, before d and e do
    let text = squares_with(
        r#", "insertions": [{"time": 2, "polygon": {"id": "late", "vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "position": [6.5, 4.5]}}]"#,
    );
    for structure in ["brute", "plain", "hierarchical"] {
        let o = run_text(&text, structure, &[]);
        assert_eq!(o.status.code(), Some(1), "{structure}: {}", stderr(&o));
        let out = stdout(&o);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 1, "{structure}: {out}");
        assert!(lines[0].starts_with(EVENT_AB), "{structure}: {out}");
        let err = stderr(&o);
        for name in ["\"late\"", "\"post\"", "t = 2"] {
            assert!(err.contains(name), "{structure}: {name} not in {err}");
        }
    }
    // touching (a shared edge) counts too; a polygon that left in a
    // collision at that very instant is no longer there
    let touching = squares_with(
        r#", "insertions": [{"time": 2, "polygon": {"id": "late", "vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "position": [7, 4]}}]"#,
    );
    let o = run_text(&touching, "hierarchical", &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("\"post\""), "{}", stderr(&o));
    // a and b (edges at 2 when they meet) are removed at t = 1: the same
    // place is free at t = 1
    let freed = squares_with(
        r#", "insertions": [{"time": 1, "polygon": {"id": "late", "vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "position": [1, 0]}}]"#,
    );
    for structure in ["brute", "plain", "hierarchical"] {
        let o = run_text(&freed, structure, &[]);
        assert_eq!(o.status.code(), Some(0), "{structure}: {}", stderr(&o));
        let out = stdout(&o);
        assert_eq!(out.lines().count(), 2, "{structure}: {out}");
        assert!(out.lines().nth(1).unwrap().starts_with(EVENT_DE), "{out}");
    }
}

#[test]
fn invalid_insertions_and_removals_are_refused_before_simulating() {
    let late = |time: &str, id: &str, position: &str| {
        format!(
            r#"{{"time": {time}, "polygon": {{"id": "{id}", "vertices": {SQUARE}, "position": {position}}}}}"#
        )
    };
    let cases = [
        (
            format!(r#", "insertions": [{}]"#, late("0", "late", "[20, 20]")),
            "insertions[0]",
        ),
        (
            format!(
                r#", "insertions": [{}, {}]"#,
                late("1", "late", "[20, 20]"),
                late("11", "later", "[30, 20]")
            ),
            "insertions[1]",
        ),
        (
            format!(r#", "insertions": [{}]"#, late("1", "post", "[20, 20]")),
            "\"post\"",
        ),
        (
            r#", "insertions": [{"time": 1, "polygon": {"id": "cw", "vertices": [[0, 0], [0, 1], [1, 0]], "position": [20, 20]}}]"#
                .to_string(),
            "\"cw\"",
        ),
        (
            r#", "removals": [{"time": 1, "id": "ghost"}]"#.to_string(),
            "removals[0]",
        ),
        (
            r#", "removals": [{"time": 12, "id": "a"}]"#.to_string(),
            "removals[0]",
        ),
        (
            r#", "removals": [{"time": 1, "id": "a"}, {"time": 2, "id": "a"}]"#.to_string(),
            "removals[0] and [1]",
        ),
        (
            format!(
                r#", "insertions": [{}], "removals": [{{"time": 3, "id": "late"}}]"#,
                late("3", "late", "[20, 20]")
            ),
            "removals[0]",
        ),
        (
            format!(
                r#", "insertions": [{}], "flight_plan_changes": [{{"time": 3, "id": "late", "velocity": [1, 0]}}]"#,
                late("3", "late", "[20, 20]")
            ),
            "flight_plan_changes[0]",
        ),
        (
            r#", "removals": [{"time": 3, "id": "d"}], "flight_plan_changes": [{"time": 3, "id": "d", "velocity": [1, 0]}]"#
                .to_string(),
            "flight_plan_changes[0]",
        ),
        (
            r#", "insertions": [{"time": 1}]"#.to_string(),
            "insertions[0]",
        ),
        (
            r#", "removals": [{"id": "a"}]"#.to_string(),
            "removals[0]",
        ),
    ];
    for (extra, entry) in &cases {
        let text = squares_with(extra);
        for structure in ["brute", "hierarchical"] {
            let o = run_text(&text, structure, &[]);
            assert_eq!(o.status.code(), Some(1), "{extra}: {}", stderr(&o));
            // a and b would collide at t = 1: nothing was simulated
            assert!(o.stdout.is_empty(), "{extra}: {}", stdout(&o));
            assert!(
                stderr(&o).contains(entry),
                "{extra}: {entry} not in {}",
                stderr(&o)
            );
        }
    }
}

#[test]
fn until_before_an_insertion_ignores_it() {
    // late overlaps post at t = 3; d and e collide at 2.5
    let text = squares_with(
        r#", "insertions": [{"time": 3, "polygon": {"id": "late", "vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "position": [6.5, 4.5], "velocity": [1, 0]}}], "removals": [{"time": 4, "id": "late"}], "flight_plan_changes": [{"time": 3.5, "id": "late", "velocity": [0, 1]}]"#,
    );
    for structure in ["brute", "plain", "hierarchical"] {
        let o = run_text(&text, structure, &[]);
        assert_eq!(o.status.code(), Some(1), "{structure}: {}", stderr(&o));
        assert_eq!(stdout(&o).lines().count(), 2, "{structure}");
        for until in ["2.75", "2.9999999999999996"] {
            let o = run_text(&text, structure, &["--until", until]);
            assert_eq!(o.status.code(), Some(0), "{structure}: {}", stderr(&o));
            let out = stdout(&o);
            let lines: Vec<&str> = out.lines().collect();
            assert_eq!(lines.len(), 2, "{structure}: {out}");
            assert!(lines[0].starts_with(EVENT_AB) && lines[1].starts_with(EVENT_DE));
        }
        // at exactly --until, the insertion still happens
        let o = run_text(&text, structure, &["--until", "3"]);
        assert_eq!(o.status.code(), Some(1), "{structure}: {}", stderr(&o));
        assert!(stderr(&o).contains("\"late\""), "{}", stderr(&o));
    }
}

#[test]
fn run_refuses_malformed_input() {
    let o = run_kss(&["run", "-"], Some("{\"version\": 1,\n \"until\": "));
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    let o = run_kss(
        &["run", "-", "--structure", "brute"],
        Some(
            r#"{"version": 1, "until": 5, "polygons": [{"id": "x", "vertices": [[0,0],[1,0],[0,1]], "position": [0, "y"]}]}"#,
        ),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("\"x\""), "{}", stderr(&o));
    let o = run_kss(
        &["run", "-"],
        Some(r#"{"version": 1, "until": 1e999, "polygons": []}"#),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("out of range"));
    let o = run_kss(&["run", "/nonexistent/kss/scenario.json"], None);
    assert_eq!(o.status.code(), Some(5));
    assert!(stderr(&o).contains("/nonexistent/kss/scenario.json"));
}

#[test]
fn run_exit_status_is_zero_or_not_implemented() {
    // Whatever the state of the structures, a valid scenario gives either a
    // complete run (0) or a clean "not implemented" (3), never a crash.
    for structure in ["hierarchical", "plain", "brute"] {
        let o = run_kss(
            &["run", "-", "--structure", structure],
            Some(&two_triangles("stop")),
        );
        let code = o.status.code();
        assert!(
            code == Some(0) || code == Some(3),
            "{structure}: {code:?} {}",
            stderr(&o)
        );
        if code == Some(3) {
            assert!(stderr(&o).contains("not implemented"));
            assert!(o.stdout.is_empty());
        }
    }
}

/// `kss run` prints the library's collisions, one line each, on a scene
/// whose contact point is `[inf, 0]` (coordinates near `f64::MAX`): that
/// line has no point. (kss's `regressions` test compares the structures'
/// collisions on this file.)
#[test]
fn run_prints_the_library_events_and_no_point_that_is_not_finite() {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/regressions/extreme_coordinates_and_velocity_near_1e308.json");
    let text = std::fs::read_to_string(&file).expect("the scenario");
    let mut want = String::new();
    let mut without_point = 0;
    let options = kss::RunOptions {
        structure: kss::StructureKind::Brute,
        ..Default::default()
    };
    kss::run(&parse_scenario(&text).unwrap(), &options, &mut |e| {
        want.push_str(&kss_cli::commands::event_line(e));
        want.push('\n');
        without_point += usize::from(!e.point.iter().all(|x| x.is_finite()));
    })
    .unwrap();
    assert!(
        without_point > 0,
        "the scene has a point that is not finite"
    );
    for structure in ["brute", "hierarchical"] {
        let o = run_kss(
            &[
                "run",
                file.to_str().unwrap(),
                "--structure",
                structure,
                "--quiet",
            ],
            None,
        );
        assert_eq!(o.status.code(), Some(0), "{structure}: {}", stderr(&o));
        assert_eq!(stdout(&o), want, "{structure}");
    }
}

#[test]
fn run_prints_events() {
    let o = run_kss(
        &["run", "-", "--structure", "brute"],
        Some(&two_triangles("stop")),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(lines[0]).unwrap();
    assert_eq!(v["time"], 1.0);
    assert_eq!(v["a"], "a");
    assert_eq!(v["b"], "b");
    assert!(stderr(&o).contains("1 collision"));
    // --until before the contact: no event, still a complete run.
    let o = run_kss(
        &["run", "-", "--structure", "brute", "--until", "0.5"],
        Some(&two_triangles("stop")),
    );
    assert_eq!(o.status.code(), Some(0));
    assert!(o.stdout.is_empty());
}

#[test]
fn run_writes_stats() {
    let dir = temp_dir();
    let scenario = dir.join("s.json");
    std::fs::write(&scenario, two_triangles("remove")).unwrap();
    let stats = dir.join("stats.json");
    let o = run_kss(
        &[
            "run",
            scenario.to_str().unwrap(),
            "--structure",
            "brute",
            "--stats",
            stats.to_str().unwrap(),
            "--audit",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(v["structure"], "brute");
    assert_eq!(v["polygons"], 2);
    assert_eq!(v["vertices"], 6);
    assert_eq!(v["collisions"], 1);
    assert!(v["wall_seconds"].as_f64().unwrap() >= 0.0);
    assert_eq!(
        v["work"],
        serde_json::json!({}),
        "brute has no structure work"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn stats_count_the_structures_work_by_path() {
    let dir = temp_dir();
    let scenario = dir.join("s.json");
    std::fs::write(&scenario, two_triangles("bounce")).unwrap();
    for structure in ["plain", "hierarchical"] {
        let stats = dir.join(format!("{structure}.json"));
        let o = run_kss(
            &[
                "run",
                scenario.to_str().unwrap(),
                "--structure",
                structure,
                "--stats",
                stats.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        let w = &v["work"];
        let n = |k: &str| {
            w[k].as_u64()
                .unwrap_or_else(|| panic!("work.{k} missing: {w}"))
        };
        // the construction and the events evaluate turns and failure times
        assert!(n("turns_filtered") > 0 && n("failure_times") > 0, "{w}");
        assert!(n("turns_undecided") <= n("turns_filtered"), "{w}");
        assert!(n("failure_times_exact") <= n("failure_times"), "{w}");
        assert!(
            n("failure_times_exact") + n("failure_times_memo") <= n("failure_times"),
            "{w}"
        );
        for k in [
            "turns_exact",
            "turns_memo",
            "failing_known",
            "normalizations",
            "walks",
            "trusted_checks",
        ] {
            n(k);
        }
        // the construction and the events are parts of the run, one after
        // the other
        let (build, events, wall) = (
            v["build_seconds"].as_f64().expect("build_seconds"),
            v["events_seconds"].as_f64().expect("events_seconds"),
            v["wall_seconds"].as_f64().expect("wall_seconds"),
        );
        assert!(
            build > 0.0 && events > 0.0 && build + events <= wall,
            "build {build} s, events {events} s, wall {wall} s"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn run_refuses_invalid_scenarios() {
    // Overlapping at time 0: the message names the pair.
    let text = format!(
        r#"{{"version": 1, "until": 5, "polygons": [
            {{"id": "left", "vertices": {TRIANGLE}, "position": [0, 0]}},
            {{"id": "right", "vertices": {TRIANGLE}, "position": [0.5, 0]}}]}}"#
    );
    let o = run_kss(&["run", "-", "--structure", "brute"], Some(&text));
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("left") && err.contains("right"), "{err}");
    assert!(o.stdout.is_empty());
}

#[test]
fn run_survives_a_closed_pipe() {
    // Thousands of events (four polygons bouncing in a box for a long time),
    // and a reader that goes away after the first line.
    let sc = kss::gen::gas(&kss::gen::GasParams {
        k: 4,
        walls: true,
        until: 300.0,
        max_speed: 2.0,
        mode: kss::CollisionMode::Bounce,
        ..Default::default()
    });
    let text = write_scenario(&sc).unwrap();
    let mut child = kss()
        .args(["run", "-", "--structure", "brute"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    {
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    {
        use std::io::BufRead;
        let mut out = std::io::BufReader::new(child.stdout.take().unwrap());
        let mut first = String::new();
        out.read_line(&mut first).unwrap();
        assert!(first.starts_with("{\"time\""));
        // Dropping the reader closes the pipe.
    }
    let o = child.wait_with_output().unwrap();
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert_eq!(o.status.code(), Some(0));
}

/// `kss render` of the two triangles (`stop` mode) at `time` with
/// `structure`: the process output and the SVG written.
fn render_two_triangles(time: &str, structure: &str) -> (std::process::Output, String) {
    let dir = temp_dir();
    let scenario = dir.join("s.json");
    std::fs::write(&scenario, two_triangles("stop")).unwrap();
    let svg = dir.join("out.svg");
    let o = run_kss(
        &[
            "render",
            scenario.to_str().unwrap(),
            "--time",
            time,
            "--structure",
            structure,
            "-o",
            svg.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    let _ = std::fs::remove_dir_all(dir);
    (o, text)
}

#[test]
fn render_writes_an_svg() {
    let (_, text) = render_two_triangles("0.5", "brute");
    assert!(text.starts_with("<svg") && text.contains("t = 0.5"));
    assert_eq!(text.matches("<polygon").count(), 2);
}

#[test]
fn render_refuses_bad_input() {
    let o = run_kss(&["render", "-", "--time", "1"], Some("not json"));
    assert_eq!(o.status.code(), Some(1));
    let o = run_kss(&["render", "-", "--time", "nan"], Some("{}"));
    assert_eq!(o.status.code(), Some(2));
}

/// Checks that `text` is well-formed XML as `kss render` writes it: every
/// element closed in order, no raw `<` or `&` outside markup and entities.
fn assert_well_formed(text: &str) {
    let mut stack: Vec<&str> = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find('<') {
        let between = &rest[..open];
        for (i, _) in between.match_indices('&') {
            let entity = &between[i..];
            assert!(
                ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                    .iter()
                    .any(|e| entity.starts_with(e)),
                "raw & in {between:?}"
            );
        }
        let close = rest[open..].find('>').expect("unclosed tag") + open;
        let tag = &rest[open + 1..close];
        assert!(!tag.contains('<'), "< inside tag {tag:?}");
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop(), Some(name.trim()), "closing {name}");
        } else if !tag.ends_with('/') {
            let name = tag.split_whitespace().next().expect("tag name");
            stack.push(name);
        }
        rest = &rest[close + 1..];
    }
    assert!(stack.is_empty(), "unclosed elements {stack:?}");
}

#[test]
fn render_plain_draws_the_structure() {
    let dir = temp_dir();
    let scenario = dir.join("gas.json");
    let o = run_kss(
        &[
            "gen",
            "gas",
            "--k",
            "6",
            "--seed",
            "3",
            "-o",
            scenario.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let render = |extra: &[&str]| -> String {
        let svg = dir.join("out.svg");
        let mut args = vec![
            "render",
            scenario.to_str().unwrap(),
            "--time",
            "1.5",
            "-o",
            svg.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = run_kss(&args, None);
        assert_eq!(o.status.code(), Some(0), "{extra:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"));
        std::fs::read_to_string(&svg).unwrap()
    };
    let text = render(&["--structure", "plain"]);
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    assert_well_formed(&text);
    assert_eq!(text.matches("<g id=\"structure\">").count(), 1);
    assert!(text.contains("id=\"legend\""));
    assert!(!text.contains("NaN") && !text.contains("inf"));
    let polygons = text.matches("<polygon points=").count();
    assert_eq!(polygons, 6);
    // the legend counts 2k − 2 partition triangles and 3k − 3 corridors
    let k = polygons;
    let legend = text.split("partition triangle (").nth(1).unwrap();
    let finite: usize = legend.split(' ').next().unwrap().parse().unwrap();
    let infinite: usize = legend
        .split("+ ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(finite + infinite, 2 * k - 2);
    assert_eq!(text.matches("class=\"partition-triangle\"").count(), finite);
    let faces = text.matches("class=\"corridor-face\"").count();
    assert!(text.contains(&format!(
        "corridor face ({faces} in {} corridors)",
        3 * k - 3
    )));
    assert!(faces >= 1);
    assert!(text.matches("class=\"certificate\"").count() <= 5);
    assert!(text.matches("class=\"end-edge\"").count() >= 3);

    let two = render(&["--structure", "plain", "--highlight", "2", "--no-legend"]);
    assert_well_formed(&two);
    assert!(two.matches("class=\"certificate\"").count() <= 2 && !two.contains("legend"));
    for off in [
        render(&["--structure", "plain", "--no-structure"]),
        render(&["--structure", "brute"]),
    ] {
        assert_well_formed(&off);
        assert!(!off.contains("id=\"structure\"") && !off.contains("corridor-face"));
        assert_eq!(off.matches("<polygon").count(), 6);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn render_plain_after_a_stop_explains_the_missing_structure() {
    // the triangles touch at t = 1 and the run stops there
    let (o, text) = render_two_triangles("3", "plain");
    assert!(stderr(&o).contains("structure not drawn"), "{}", stderr(&o));
    assert_well_formed(&text);
    assert!(text.contains("structure not drawn") && !text.contains("partition-triangle"));
}

#[test]
fn demo_runs_and_draws() {
    let dir = temp_dir();
    let svg = dir.join("demo.svg");
    let o = run_kss(&["demo", "-o", svg.to_str().unwrap()], None);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.lines().count() >= 2, "{out}");
    for line in out.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert!(v["time"].as_f64().unwrap() <= 12.0);
    }
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"));
    assert!(stderr(&o).contains("demo.svg"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn demo_fails_cleanly_or_runs() {
    let dir = temp_dir();
    let svg = dir.join("demo.svg");
    let o = run_kss(&["demo", "-o", svg.to_str().unwrap()], None);
    let code = o.status.code();
    assert!(
        code == Some(0) || code == Some(3),
        "{code:?}: {}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("panicked"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn render_hierarchical_draws_approximations_and_animation_frames() {
    let dir = temp_dir();
    let scenario = dir.join("flypast.json");
    let o = run_kss(
        &[
            "gen",
            "flypast",
            "--n",
            "64",
            "--ratio",
            "100",
            "-o",
            scenario.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = dir.join("fly.svg");
    let o = run_kss(
        &[
            "render",
            scenario.to_str().unwrap(),
            "--time",
            "0",
            "--to",
            "2",
            "--frames",
            "3",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!out.exists(), "frames are numbered files");
    let mut not_real = Vec::new();
    for i in 0..3 {
        let text = std::fs::read_to_string(dir.join(format!("fly-{i:03}.svg"))).unwrap();
        assert_well_formed(&text);
        assert_eq!(text.matches("<polygon points=").count(), 2);
        // both polygons are seen through an outer approximation
        assert_eq!(text.matches("class=\"approximation\"").count(), 2);
        let dots = text.matches("class=\"approximation-vertex\"").count();
        assert!(text.contains(&format!("approximation ({dots} vertices not real)")));
        not_real.push(dots);
        assert!(text.contains("<g id=\"structure\">"));
    }
    // 64-gons start from much coarser approximations
    assert!(not_real[0] > 0, "{not_real:?}");
    // --frames needs --to and --output
    let o = run_kss(
        &["render", scenario.to_str().unwrap(), "--frames", "3"],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(dir);
}
