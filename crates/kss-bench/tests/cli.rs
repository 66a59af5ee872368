//! Tests of the `kss-bench` binary: workload selection, a closed pipe,
//! reports of earlier runs, checkpoints and resuming.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

fn kss_bench() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kss-bench"))
}

fn run_bench(args: &[&str]) -> Output {
    kss_bench()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run kss-bench")
}

/// A quick run of `plain` and `parry-toi` on the smallest pass, with
/// `args` after.
fn run_pair(args: &[&str]) -> Output {
    let mut all = vec![
        "--quick",
        "--methods",
        "plain,parry-toi",
        "--workload",
        "flypast-n16-r1e1",
    ];
    all.extend_from_slice(args);
    run_bench(&all)
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
        "kss-bench-cli-test-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

#[test]
fn bench_list_expands_the_workload_sets() {
    let o = run_bench(&["--list", "--workload", "cost"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let workloads: Vec<String> = stdout(&o)
        .lines()
        .filter_map(|l| l.strip_prefix("workload "))
        .map(String::from)
        .collect();
    assert_eq!(
        workloads,
        [
            "walls-k1000-n16-bounce",
            "walls-k300-n256-bounce",
            "walls-k2000-n64-remove",
            "gasmix-k1000-n3to16",
        ]
    );
    let o = run_bench(&["--list", "--workload", "perf", "walls-k30-n16-remove"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = stdout(&o);
    assert_eq!(
        out.lines().filter(|l| l.starts_with("workload ")).count(),
        7
    );
    assert!(out.contains("workload gas-k10000-n8-c1000\n"));
    assert!(out.contains("workload flypast-n65536-r1e3\n"));
    assert!(out.contains("workload walls-k30-n16-remove\n"));
    // families pick among the defaults of the mode
    let o = run_bench(&["--list", "--quick", "--workload", "walls", "gasmix"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("workload walls-k30-n16-bounce\nworkload gasmix-k50-n3to16\n"));
    let o = run_bench(&["--list", "--workload", "walls-k30-n16-stop"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn bench_list_survives_a_closed_pipe() {
    // `kss-bench --list | head -1`: the reader is gone before the list is
    // written (the process takes longer to start than the drop below)
    let mut child = kss_bench()
        .args(["--list"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert_eq!(o.status.code(), Some(0));
}

#[test]
fn child_cells_report_their_heap_and_allocations() {
    let dir = temp_dir();
    let out = dir.join("run");
    let o = run_pair(&["--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (run, _) = kss_bench::report::read_runs(&[out.join("bench.json")]).unwrap();
    for m in ["plain", "parry-toi"] {
        let c = run.cell("flypast-n16-r1e1", m).expect("the cell");
        let heap = c.outcome.peak_heap_bytes.expect("a peak heap");
        let allocations = c.outcome.allocations.expect("an allocation count");
        // (each method builds something on the heap: the structure, the
        // shapes)
        assert!(heap > 0 && allocations > 0, "{m}: {heap} B, {allocations}");
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("| peak heap (MiB) | allocs / event |"), "{md}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn repeated_cells_report_their_median_run_and_every_run() {
    let dir = temp_dir();
    let out = dir.join("run");
    let o = run_pair(&["--repeat", "3", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // (each method ran three times, taking turns)
    let err = stderr(&o);
    assert_eq!(err.matches("flypast-n16-r1e1 plain:").count(), 3, "{err}");
    assert_eq!(
        err.matches("flypast-n16-r1e1 parry-toi:").count(),
        3,
        "{err}"
    );
    let (run, _) = kss_bench::report::read_runs(&[out.join("bench.json")]).unwrap();
    assert_eq!(run.repeat, 3);
    for m in ["plain", "parry-toi"] {
        let c = run.cell("flypast-n16-r1e1", m).expect("the cell");
        let runs = &c.outcome.wall_runs;
        assert_eq!(runs.len(), 3, "{m}: {runs:?}");
        let mut sorted = runs.clone();
        sorted.sort_by(f64::total_cmp);
        assert_eq!(
            c.outcome.wall_seconds, sorted[1],
            "{m}: the median of {runs:?}"
        );
        // the exact method's events are still compared with the reference
        assert!(c.comparison.is_some(), "{m}");
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("each cell 3 times"), "{md}");
    assert!(md.contains("## Repeated runs"), "{md}");
    // a checkpoint of a run repeated three times is not resumed once
    let o = run_pair(&[
        "--resume",
        out.join("checkpoint.json").to_str().unwrap(),
        "--out",
        dir.join("other").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--repeat"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bench_report_from_keeps_only_the_workloads_named() {
    // two tiny workloads with the reference alone, then a report of one
    let dir = temp_dir();
    let run = dir.join("run");
    let o = run_bench(&[
        "--quick",
        "--methods",
        "brute",
        "--workload",
        "flypast-n16-r1e1",
        "flypast-n16-r1e6",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // `kss-bench --report-from` of that run, keeping `workload`, into `out`
    let report_of = |workload: &str, out: &std::path::Path| {
        run_bench(&[
            "--report-from",
            run.join("bench.json").to_str().unwrap(),
            "--workload",
            workload,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let report = dir.join("report");
    let o = report_of("flypast-n16-r1e6", &report);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let md = std::fs::read_to_string(report.join("bench.md")).unwrap();
    assert!(md.contains("flypast-n16-r1e6"), "{md}");
    assert!(!md.contains("flypast-n16-r1e1"), "{md}");
    // a name that the runs do not hold is an error, not an empty report
    let o = report_of("gas-k30-n8-c100", &dir.join("none"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn bench_writes_a_checkpoint_and_resumes_from_it() {
    let dir = temp_dir();
    let out = dir.join("run");
    let bench = |extra: &[&str]| {
        let mut args = vec![
            "--quick",
            "--methods",
            "brute,sweep",
            "--workload",
            "flypast-n16-r1e1",
            "flypast-n16-r1e6",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        run_bench(&args)
    };
    let o = bench(&[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let checkpoint = out.join("checkpoint.json");
    let text = std::fs::read_to_string(&checkpoint).unwrap();
    assert!(text.contains("flypast-n16-r1e6"), "{text}");
    // resumed from the finished run's checkpoint: nothing runs again
    let o = bench(&["--resume", checkpoint.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.matches("kept from the run resumed").count(), 2, "{err}");
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("resumed 1 time"), "{md}");
    // a checkpoint of other methods is refused
    let o = run_bench(&[
        "--quick",
        "--methods",
        "brute",
        "--workload",
        "flypast-n16-r1e1",
        "--resume",
        checkpoint.to_str().unwrap(),
        "--out",
        dir.join("other").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("same methods"), "{}", stderr(&o));
    // and so is one of other workloads (its cells would be dropped)
    let o = run_bench(&[
        "--quick",
        "--methods",
        "brute,sweep",
        "--workload",
        "flypast-n16-r1e1",
        "--resume",
        checkpoint.to_str().unwrap(),
        "--out",
        dir.join("other").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("same methods, workloads"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn docs_writes_the_page_from_the_results_and_checks_it() {
    let dir = temp_dir();
    let results = dir.join("results");
    std::fs::create_dir_all(results.join("page")).expect("create results/page");
    std::fs::write(
        results.join("run.md"),
        "# A run\n\nOn 2026-01-02 with commit abc1234:\n\n```sh\nkss-bench --quick\n```\n\n\
         ## Numbers\n\n| workload | method | wall |\n| --- | --- | ---: |\n\
         | a | plain | 1 s |\n| b | plain | 2 s |\n",
    )
    .expect("write run.md");
    std::fs::write(
        results.join("page").join("00.md"),
        "# Page\n\n## Section\n\n::: run\nfile: run.md\ndate: 2026-01-02\ncommit: abc1234\n\
         command: block 1\n:::\n\n::: table\nfile: run.md\nunder: Numbers\nrows: b\n\
         columns: workload | wall\n:::\n\nSee [the run]({results}/run.md).\n",
    )
    .expect("write the page source");
    let docs = dir.join("docs");
    std::fs::create_dir_all(&docs).expect("create docs");
    let page = docs.join("page.md");
    let (r, p) = (
        results.to_str().expect("utf-8"),
        page.to_str().expect("utf-8"),
    );
    let o = run_bench(&["docs", "--results", r, "--out", p]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&page).expect("the page");
    assert!(
        text.contains("**Run:** 2026-01-02, binary of commit abc1234. Results: [`run.md`](../results/run.md).\n\n```sh\nkss-bench --quick\n```"),
        "{text}"
    );
    assert!(text.contains("| workload | wall |\n| --- | ---: |\n| b | 2 s |\n\n*From [`run.md`](../results/run.md), “Numbers”; run of 2026-01-02, commit abc1234.*"), "{text}");
    assert!(text.contains("See [the run](../results/run.md)."), "{text}");
    let o = run_bench(&["docs", "--results", r, "--out", p, "--check"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));

    // a page edited by hand is refused, and the message says how to write it
    std::fs::write(&page, text.replace("2 s", "3 s")).expect("edit the page");
    let o = run_bench(&["docs", "--results", r, "--out", p, "--check"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cargo run -p kss-bench -- docs"),
        "{}",
        stderr(&o)
    );

    // a run whose results file does not record its commit is refused
    let source = results.join("page").join("00.md");
    let s = std::fs::read_to_string(&source).expect("read the source");
    std::fs::write(&source, s.replace("commit: abc1234", "commit: def5678")).expect("edit");
    let o = run_bench(&["docs", "--results", r, "--out", p]);
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("does not record the commit def5678"),
        "{}",
        stderr(&o)
    );

    // so is a results file that the page does not name
    std::fs::write(&source, s).expect("restore");
    std::fs::write(results.join("other.md"), "# Other\n").expect("write other.md");
    let o = run_bench(&["docs", "--results", r, "--out", p]);
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(stderr(&o).contains("other.md"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}
