//! The harness end to end, in process, on tiny workloads: every cell runs,
//! the exact methods agree with brute, and the report files are written.

use kss_bench::harness::{self, Config, Executor, Progress, Status};
use kss_bench::workload::Workload;
use kss_bench::Method;

#[test]
fn tiny_run_writes_a_report() {
    let out = std::env::temp_dir().join(format!("kss-bench-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut config = Config::new(true, &out);
    config.workloads = vec![
        Workload::Flypast {
            n: 16,
            ratio: 1e3,
            seed: 1,
        },
        Workload::Flypast {
            n: 16,
            ratio: 1e3,
            seed: 2,
        },
        Workload::Gas {
            k: 8,
            n: 6,
            collisions: 10,
        },
        Workload::Cluster { k: 16 },
        Workload::Swarm { k: 20 },
    ];
    config.methods = Method::defaults();
    config.build_time = true;
    let mut cells = 0;
    let mut done = 0;
    let run = harness::run(&config, &Executor::InProcess, &mut |p| match p {
        Progress::Start { cells: c } => cells = c,
        Progress::CellStart { .. } => {}
        Progress::CellDone(_) => done += 1,
        Progress::WorkloadDone(_) | Progress::Resumed { .. } => {}
    })
    .unwrap();
    assert_eq!(cells, 5 * config.methods.len());
    assert_eq!(done, cells);
    for w in &run.workloads {
        assert_eq!(run.references.get(w).map(String::as_str), Some("brute"));
        for m in ["brute", "sweep"] {
            let c = run.cell(w, m).unwrap();
            assert_eq!(c.outcome.status, Status::Ok, "{w} {m}");
            assert!(c.comparison.as_ref().unwrap().identical, "{w} {m}");
            assert!(c.outcome.sim_seconds > 0.0, "{w} {m}");
        }
        for m in ["parry-toi", "parry-step:30", "parry-step:240"] {
            let c = run.cell(w, m).unwrap();
            assert_eq!(c.outcome.status, Status::Ok, "{w} {m}");
            assert!(c.comparison.is_some(), "{w} {m}");
        }
        for m in ["plain", "hierarchical"] {
            let c = run.cell(w, m).unwrap();
            assert!(
                matches!(c.outcome.status, Status::Ok | Status::NotImplemented),
                "{w} {m}: {:?}",
                c.outcome.status
            );
        }
    }
    let machine = kss_bench::report::machine();
    let files = kss_bench::report::write(&out, &run, &machine).unwrap();
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("| cluster-k16 |"));
    assert!(md.contains("## Events, certificates and time per event"));
    assert!(md.contains("## `hierarchical` against each method"));
    assert!(md.contains("### gas") && md.contains("| sweep ns/ev |"));
    assert!(md.contains("| events / sim s | ns / event |"));
    assert!(md.contains("parry-step dt=1/240"));
    assert!(md.contains("## Flypast: events, pops and construction"));
    assert!(md.contains("### Flypast over seeds"));
    for w in ["flypast-n16-r1e3", "flypast-n16-r1e3-s2"] {
        let c = run.cell(w, "brute").unwrap();
        assert!(c.outcome.build_seconds.is_some(), "{w}");
        assert!(run
            .cell(w, "sweep")
            .unwrap()
            .outcome
            .build_seconds
            .is_none());
    }
    assert!(files
        .iter()
        .any(|f| f.extension().is_some_and(|e| e == "svg")));
    for f in &files {
        if f.extension().is_some_and(|e| e == "svg") {
            let svg = std::fs::read_to_string(f).unwrap();
            assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn names_round_trip() {
    for w in Workload::full().into_iter().chain(Workload::quick()) {
        assert_eq!(Workload::parse(&w.name()).unwrap(), w);
    }
    for m in Method::defaults() {
        assert_eq!(Method::parse(&m.name()).unwrap(), m);
    }
    assert!(Method::parse("parry-step:0").is_err());
    assert!(Workload::parse("gas-k10").is_err());
    let seeded = Workload::Flypast {
        n: 64,
        ratio: 1e3,
        seed: 7,
    };
    assert_eq!(seeded.name(), "flypast-n64-r1e3-s7");
    assert_eq!(Workload::parse("flypast-n64-r1e3-s7").unwrap(), seeded);
    assert_eq!(
        Workload::parse("flypast-n64-r1e3").unwrap(),
        Workload::Flypast {
            n: 64,
            ratio: 1e3,
            seed: kss_bench::workload::SEED,
        }
    );
    assert!(Workload::parse("flypast-n64-r1e3-x7").is_err());
}

#[test]
fn all_pairs_work_grows_with_collisions_and_pairs() {
    let gas = |k| Workload::Gas {
        k,
        n: 8,
        collisions: 1000,
    };
    // 104 bodies: 5356 pairs at the start, 2 * 1000 * 104 recomputed
    assert_eq!(gas(100).all_pairs_work(), 5356.0 + 208_000.0);
    let growth = gas(1000).all_pairs_work() / gas(100).all_pairs_work();
    assert!(growth > 10.0 && growth < 15.0, "{growth}");
    assert_eq!(Workload::Cluster { k: 10 }.all_pairs_work(), 45.0);
}

#[test]
fn workloads_are_valid_scenarios() {
    for w in Workload::quick() {
        w.scenario().validate().unwrap();
    }
    for w in [
        Workload::Cluster { k: 1000 },
        Workload::Swarm { k: 1000 },
        Workload::Gas {
            k: 1000,
            n: 64,
            collisions: 1000,
        },
        Workload::Flypast {
            n: 4096,
            ratio: 1e6,
            seed: 1,
        },
    ] {
        w.scenario().validate().unwrap();
    }
}

#[test]
fn merged_runs_keep_the_later_cell() {
    use kss_bench::harness::{BenchRun, CellResult};
    let cell = |w: &str, m: &str, events: u64| CellResult {
        workload: w.into(),
        method: m.into(),
        outcome: outcome(Status::Ok, 1.0, events),
        comparison: None,
    };
    let run = |workloads: &[&str], methods: &[&str], cells| BenchRun {
        quick: false,
        budget_seconds: 10.0,
        workloads: workloads.iter().map(|w| w.to_string()).collect(),
        methods: methods.iter().map(|m| m.to_string()).collect(),
        references: Default::default(),
        cells,
        total_seconds: 2.0,
        resumes: 0,
        repeat: 1,
    };
    let a = run(
        &["flypast-n16-r1e3", "flypast-n64-r1e3"],
        &["plain"],
        vec![
            cell("flypast-n16-r1e3", "plain", 1),
            cell("flypast-n64-r1e3", "plain", 2),
        ],
    );
    let b = run(
        &["flypast-n64-r1e3", "flypast-n64-r1e8"],
        &["hierarchical", "plain"],
        vec![
            cell("flypast-n64-r1e3", "plain", 3),
            cell("flypast-n64-r1e8", "hierarchical", 4),
        ],
    );
    let m = kss_bench::report::merge(vec![a, b]).unwrap();
    assert_eq!(
        m.workloads,
        ["flypast-n16-r1e3", "flypast-n64-r1e3", "flypast-n64-r1e8"]
    );
    assert_eq!(m.methods, ["plain", "hierarchical"]);
    assert_eq!(m.cells.len(), 3);
    let events = |w, me| m.cell(w, me).unwrap().outcome.counters.events;
    assert_eq!(events("flypast-n16-r1e3", "plain"), 1);
    assert_eq!(events("flypast-n64-r1e3", "plain"), 3);
    assert_eq!(events("flypast-n64-r1e8", "hierarchical"), 4);
    assert_eq!(m.total_seconds, 4.0);
    assert!(kss_bench::report::merge(Vec::new()).is_none());
}

#[test]
fn an_interrupted_run_resumes_from_its_checkpoint() {
    let out = std::env::temp_dir().join(format!("kss-bench-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut config = Config::new(true, &out);
    config.workloads = vec![
        Workload::Flypast {
            n: 16,
            ratio: 1e3,
            seed: 1,
        },
        Workload::Cluster { k: 16 },
        Workload::Swarm { k: 20 },
    ];
    config.methods = vec![Method::Brute, Method::Sweep];
    // the checkpoints of a whole run, one per workload, each the run so far
    let mut checkpoints: Vec<harness::BenchRun> = Vec::new();
    let whole = harness::run(&config, &Executor::InProcess, &mut |p| {
        if let Progress::WorkloadDone(r) = p {
            checkpoints.push(r.clone());
        }
    })
    .unwrap();
    assert_eq!(checkpoints.len(), 3);
    for (i, c) in checkpoints.iter().enumerate() {
        assert_eq!(c.cells.len(), 2 * (i + 1));
        assert!(c.total_seconds <= whole.total_seconds);
    }
    // interrupted after its first workload: the resumed run keeps that one
    // and runs the other two
    let first = checkpoints[0].clone();
    config.resume = Some(first.clone());
    let (mut resumed, mut ran) = (Vec::new(), 0);
    let again = harness::run(&config, &Executor::InProcess, &mut |p| match p {
        Progress::Resumed { workload } => resumed.push(workload.to_string()),
        Progress::CellDone(_) => ran += 1,
        _ => {}
    })
    .unwrap();
    assert_eq!(resumed, [first.cells[0].workload.clone()]);
    assert_eq!(ran, 4);
    assert_eq!(again.resumes, 1);
    assert_eq!(again.cells.len(), 6);
    assert!(again.total_seconds >= first.total_seconds);
    // the kept cells are the checkpoint's, the others compare like the
    // whole run's
    for c in &first.cells {
        let kept = again.cell(&c.workload, &c.method).unwrap();
        assert_eq!(kept.outcome.wall_seconds, c.outcome.wall_seconds);
    }
    for c in &whole.cells {
        let r = again.cell(&c.workload, &c.method).unwrap();
        assert_eq!(r.outcome.counters.collisions, c.outcome.counters.collisions);
        assert_eq!(
            r.comparison.as_ref().map(|x| x.identical),
            c.comparison.as_ref().map(|x| x.identical)
        );
    }
    let md = kss_bench::report::markdown(&again, &kss_bench::report::machine());
    assert!(md.contains("resumed 1 time "), "{md}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_cell_run_several_times_reports_its_median_run() {
    use kss_bench::harness::median_run;
    // (each run's heap is its event count: the median's is its own)
    let run = |status: Status, wall: f64, events: u64| {
        let mut o = outcome(status, wall, events);
        o.peak_heap_bytes = Some(events);
        o
    };
    // one run: as it is
    let one = median_run(&[run(Status::Ok, 2.0, 7)]);
    assert_eq!((one.wall_seconds, one.wall_runs.len()), (2.0, 0));
    // three: the middle one, whole (its counters and heap), with every wall
    let m = median_run(&[
        run(Status::Ok, 3.0, 1),
        run(Status::Ok, 1.0, 2),
        run(Status::Ok, 2.0, 3),
    ]);
    assert_eq!(m.wall_seconds, 2.0);
    assert_eq!((m.counters.events, m.peak_heap_bytes), (3, Some(3)));
    assert_eq!(m.wall_runs, vec![3.0, 1.0, 2.0]);
    // four: the lower middle one
    let m = median_run(&[
        run(Status::Ok, 4.0, 1),
        run(Status::Ok, 1.0, 2),
        run(Status::Ok, 3.0, 3),
        run(Status::Ok, 2.0, 4),
    ]);
    assert_eq!(m.wall_seconds, 2.0);
    // a run that did not finish is what the cell reports
    let m = median_run(&[run(Status::Ok, 1.0, 1), run(Status::Budget, 9.0, 0)]);
    assert_eq!(m.status, Status::Budget);
}

/// An outcome of `status` with its wall time and event count, the rest
/// zero or absent.
fn outcome(status: Status, wall: f64, events: u64) -> harness::CellOutcome {
    harness::CellOutcome {
        wall_seconds: wall,
        sim_seconds: 1.0,
        counters: kss_bench::Counters {
            events,
            ..Default::default()
        },
        ..harness::CellOutcome::not_run(status)
    }
}
