//! Running every method on every workload under a time budget.
//!
//! A *cell* is one method on one workload. With [`Executor::Subprocess`] each
//! cell runs in a child process (the `kss` binary re-invoked with `bench
//! --cell`), which is killed when it runs past the budget and which measures
//! its own peak resident memory: the child builds the scenario, resets the
//! kernel's peak-RSS counter (`/proc/self/clear_refs`), runs the method and
//! reads `VmHWM` from `/proc/self/status`. So the figure is the largest
//! resident size of the process during the method's run, the scenario
//! (held by every method alike) included. The child also counts its heap
//! ([`crate::heap`]): the largest number of live heap bytes the method
//! added over those live when it started (so the scene excluded), and its
//! allocations; these depend on the code run, not on the binary's layout
//! or the system allocator's mappings. With [`Executor::InProcess`]
//! (tests) the budget is only checked cooperatively by the baselines and no
//! memory is reported.
//!
//! With [`Config::build_time`], each cell of the library's structures first
//! runs the structure up to an instant just after 0
//! ([`crate::method::BUILD_UNTIL`]) and reports that wall time as the
//! construction time ([`CellOutcome::build_seconds`]), then the full run.
//!
//! Cells a method cannot finish are shown, never waited for: a method that
//! ran out of budget at one size of a series is not run at larger sizes,
//! nor where its wall time at the previous size, scaled by the growth of the
//! work, predicts more than twice the budget. The work of the all-pairs
//! methods (brute, parry-toi) on many polygons is their number of pair
//! computations ([`Workload::all_pairs_work`]: quadratic in the number of
//! polygons at the start, linear per collision); every other method's is
//! linear in the series' size.

use std::collections::HashMap;
use std::fs;
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::compare::{compare, Comparison};
use crate::workload::Workload;
use crate::{Counters, Deadline, Event, Failure, Method};

/// How a cell ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", content = "detail", rename_all = "snake_case")]
pub enum Status {
    /// Completed.
    Ok,
    /// The library does not implement the structure yet.
    NotImplemented,
    /// The method cannot run this scenario.
    Unsupported(String),
    /// Ran out of the time budget (killed or stopped).
    Budget,
    /// Not run: predicted over budget from smaller sizes.
    SkippedBudget,
    /// Not run: the scene is too large for the memory guard.
    SkippedMemory,
    /// Failed (a bug); the message says how.
    Error(String),
}

impl Status {
    /// Short text for the table.
    pub fn text(&self) -> String {
        match self {
            Status::Ok => "ok".into(),
            Status::NotImplemented => "not implemented yet".into(),
            Status::Unsupported(m) => format!("unsupported ({m})"),
            Status::Budget => "over budget".into(),
            Status::SkippedBudget => "skipped (budget)".into(),
            Status::SkippedMemory => "skipped (memory)".into(),
            Status::Error(m) => format!("error: {m}"),
        }
    }
}

/// What a cell reports (the child's one line of JSON on stdout).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellOutcome {
    /// How it ended.
    pub status: Status,
    /// Wall time of the method's run (scenario generation excluded).
    pub wall_seconds: f64,
    /// Scenario generation time.
    pub setup_seconds: f64,
    /// Simulated time covered by the run: the scenario's `until`, or in
    /// `stop` mode the instant of the first collision, where the run ends
    /// (0 for cells that did not complete).
    #[serde(default)]
    pub sim_seconds: f64,
    /// The method's counters.
    pub counters: Counters,
    /// Peak resident memory during the run, KiB (child processes only).
    pub peak_rss_kib: Option<u64>,
    /// The largest number of live heap bytes the run added over those live
    /// when it started (child processes of `kss-bench` only: see
    /// [`crate::heap`]).
    #[serde(default)]
    pub peak_heap_bytes: Option<u64>,
    /// Allocations during the run (`alloc`, `alloc_zeroed` and `realloc`
    /// calls; where [`CellOutcome::peak_heap_bytes`] is measured).
    #[serde(default)]
    pub allocations: Option<u64>,
    /// With [`Config::build_time`], for the library's structures: wall time
    /// of a separate run up to [`crate::method::BUILD_UNTIL`] (world,
    /// validation, structure and its certificates; no events), made before
    /// the measured run in the same process.
    #[serde(default)]
    pub build_seconds: Option<f64>,
    /// With [`Config::repeat`] above 1: the wall time of every run of the
    /// cell, in the order they ran (the outcome is the run of median wall
    /// time, [`median_run`]); empty for a cell run once.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wall_runs: Vec<f64>,
}

impl CellOutcome {
    /// An outcome of `status` with nothing measured: every time and count
    /// zero, every optional figure absent.
    pub fn not_run(status: Status) -> CellOutcome {
        CellOutcome {
            status,
            wall_seconds: 0.0,
            setup_seconds: 0.0,
            sim_seconds: 0.0,
            counters: Counters::default(),
            peak_rss_kib: None,
            peak_heap_bytes: None,
            allocations: None,
            build_seconds: None,
            wall_runs: Vec::new(),
        }
    }
}

/// The outcome that a cell run several times ([`Config::repeat`]) reports:
/// the first run that did not finish (a cell that fails or goes over
/// budget once is not run again), else the run of median wall time (the
/// lower of the two middle ones for an even count) with every run's wall
/// time in [`CellOutcome::wall_runs`]. A single run as it is.
pub fn median_run(runs: &[CellOutcome]) -> CellOutcome {
    if let Some(bad) = runs.iter().find(|o| o.status != Status::Ok) {
        return bad.clone();
    }
    match runs {
        [] => CellOutcome::not_run(Status::Error("no run".into())),
        [one] => one.clone(),
        _ => {
            let mut order: Vec<&CellOutcome> = runs.iter().collect();
            order.sort_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds));
            let mut median = order[(runs.len() - 1) / 2].clone();
            median.wall_runs = runs.iter().map(|o| o.wall_seconds).collect();
            median
        }
    }
}

/// One cell's result, compared with the reference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CellResult {
    /// Workload name.
    pub workload: String,
    /// Method name.
    pub method: String,
    /// What the cell reported.
    pub outcome: CellOutcome,
    /// Against the reference's events (if both ran).
    pub comparison: Option<Comparison>,
}

/// The whole run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchRun {
    /// Quick mode.
    pub quick: bool,
    /// Time budget per cell, seconds.
    pub budget_seconds: f64,
    /// Workload names, in order.
    pub workloads: Vec<String>,
    /// Method names, in order.
    pub methods: Vec<String>,
    /// Which method's events each workload was compared against.
    pub references: HashMap<String, String>,
    /// Every cell.
    pub cells: Vec<CellResult>,
    /// Wall time of the whole run, seconds (over every process, when it
    /// was resumed).
    pub total_seconds: f64,
    /// How many times the run was resumed after an interruption
    /// ([`Config::resume`]); the workloads interrupted were run again from
    /// their first cell.
    #[serde(default)]
    pub resumes: u32,
    /// How many times each cell ran ([`Config::repeat`]; the largest of
    /// the runs merged into a report).
    #[serde(default = "one")]
    pub repeat: u32,
}

fn one() -> u32 {
    1
}

impl BenchRun {
    /// The cell of `workload` and `method`.
    pub fn cell(&self, workload: &str, method: &str) -> Option<&CellResult> {
        self.cells
            .iter()
            .find(|c| c.workload == workload && c.method == method)
    }
}

/// The configuration of a run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Quick mode (tiny workloads, short budget).
    pub quick: bool,
    /// Time budget per cell, seconds.
    pub budget_seconds: f64,
    /// Largest total number of vertices of a scene run.
    pub max_vertices: usize,
    /// Workloads, in order.
    pub workloads: Vec<Workload>,
    /// Methods, in order.
    pub methods: Vec<Method>,
    /// Where events files go (`<dir>/<workload>__<method>.jsonl`).
    pub events_dir: PathBuf,
    /// Also measure the construction time of the library's structures
    /// ([`CellOutcome::build_seconds`]).
    pub build_time: bool,
    /// An interrupted run to go on with (its checkpoint,
    /// [`Progress::WorkloadDone`]): the workloads it finished with every
    /// method are taken from it as they are, the others run.
    pub resume: Option<BenchRun>,
    /// How many times each cell runs (at least 1): the methods of a
    /// workload take turns, round after round, and each cell reports its
    /// run of median wall time ([`median_run`]).
    pub repeat: u32,
}

impl Config {
    /// The defaults: quick (tiny sizes, 5 s per cell) or full (the issue's
    /// matrix, 600 s per cell).
    pub fn new(quick: bool, out: &Path) -> Config {
        Config {
            quick,
            budget_seconds: if quick { 5.0 } else { 600.0 },
            max_vertices: 1 << 24,
            workloads: if quick {
                Workload::quick()
            } else {
                Workload::full()
            },
            methods: Method::defaults(),
            events_dir: out.join("events"),
            build_time: false,
            resume: None,
            repeat: 1,
        }
    }
}

/// Where cells run.
#[derive(Clone, Debug)]
pub enum Executor {
    /// In this process; the budget is checked cooperatively.
    InProcess,
    /// In a child process: `exe args.. --cell WORKLOAD/METHOD --cell-events
    /// FILE --budget SECONDS [--build-time]` must call [`cell_main`] and
    /// print its result.
    Subprocess {
        /// The executable.
        exe: PathBuf,
        /// Arguments before the cell arguments (none for `kss-bench`).
        args: Vec<String>,
    },
}

/// Progress notifications.
#[derive(Clone, Debug)]
pub enum Progress<'a> {
    /// The run starts with this many cells.
    Start {
        /// Number of cells.
        cells: usize,
    },
    /// A cell starts.
    CellStart {
        /// Workload name.
        workload: &'a str,
        /// Method name.
        method: &'a str,
    },
    /// A cell ended.
    CellDone(&'a CellResult),
    /// A workload ended with every method: the run so far (every finished
    /// workload's cells, and the wall time so far), a checkpoint from which
    /// an interrupted run can be resumed.
    WorkloadDone(&'a BenchRun),
    /// A workload was taken from the run resumed, not run again.
    Resumed {
        /// Workload name.
        workload: &'a str,
    },
}

fn events_path(dir: &Path, workload: &str, method: &str) -> PathBuf {
    dir.join(format!("{workload}__{}.jsonl", method.replace(':', "-")))
}

/// Writes events as JSON lines.
pub fn write_events(path: &Path, events: &[Event]) -> std::io::Result<()> {
    let mut w = BufWriter::new(fs::File::create(path)?);
    for e in events {
        serde_json::to_writer(&mut w, e)?;
        w.write_all(b"\n")?;
    }
    w.flush()
}

/// Reads events written by [`write_events`].
pub fn read_events(path: &Path) -> std::io::Result<Vec<Event>> {
    let r = BufReader::new(fs::File::open(path)?);
    let mut out = Vec::new();
    for line in r.lines() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        out.push(serde_json::from_str(&line).map_err(std::io::Error::other)?);
    }
    Ok(out)
}

/// Peak resident set size of this process, KiB (`VmHWM`).
pub fn peak_rss_kib() -> Option<u64> {
    let status = fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}

/// Resets the peak resident set size (Linux: `5` into `/proc/self/clear_refs`).
pub fn reset_peak_rss() -> bool {
    fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Runs one cell in this process; returns the outcome and the events.
/// With `build_time`, the library's structures are first run up to
/// [`crate::method::BUILD_UNTIL`] to time their construction.
pub fn run_cell(
    workload: &Workload,
    method: Method,
    budget_seconds: f64,
    measure_memory: bool,
    build_time: bool,
) -> (CellOutcome, Vec<Event>) {
    let t0 = Instant::now();
    let scenario = workload.scenario();
    let setup_seconds = t0.elapsed().as_secs_f64();
    let mut build_seconds = None;
    if build_time {
        match method.build_seconds(&scenario) {
            Some(Ok((seconds, _))) => build_seconds = Some(seconds),
            Some(Err(f)) => {
                let mut o = CellOutcome::not_run(match f {
                    Failure::NotImplemented => Status::NotImplemented,
                    f => Status::Error(format!("construction: {f}")),
                });
                o.setup_seconds = setup_seconds;
                return (o, Vec::new());
            }
            None => {}
        }
    }
    let memory = measure_memory && reset_peak_rss();
    let heap_before = measure_memory
        .then(|| {
            crate::heap::reset();
            crate::heap::read()
        })
        .flatten();
    let start = Instant::now();
    let result = method.run_scaled(
        &scenario,
        workload.time_scale(),
        Deadline::after(budget_seconds),
    );
    let wall_seconds = start.elapsed().as_secs_f64();
    let heap = heap_before.zip(crate::heap::read());
    let peak_rss_kib = if memory { peak_rss_kib() } else { None };
    let sim_seconds = |events: &[Event]| match (scenario.on_collision, events.first()) {
        (kss::CollisionMode::Stop, Some(e)) => e.time,
        _ => scenario.until,
    };
    let (status, counters, events) = match result {
        Ok((events, counters)) => {
            // a library structure cannot be stopped from outside in-process
            let status = if wall_seconds > budget_seconds {
                Status::Budget
            } else {
                Status::Ok
            };
            (status, counters, events)
        }
        Err(f) => (
            match f {
                Failure::NotImplemented => Status::NotImplemented,
                Failure::Unsupported(m) => Status::Unsupported(m),
                Failure::Budget => Status::Budget,
                Failure::Error(m) => Status::Error(m),
            },
            Counters::default(),
            Vec::new(),
        ),
    };
    (
        CellOutcome {
            sim_seconds: if status == Status::Ok {
                sim_seconds(&events)
            } else {
                0.0
            },
            status,
            wall_seconds,
            setup_seconds,
            counters,
            peak_rss_kib,
            peak_heap_bytes: heap.map(|(b, a)| a.peak_bytes - b.live_bytes),
            allocations: heap.map(|(_, a)| a.allocations),
            build_seconds,
            wall_runs: Vec::new(),
        },
        events,
    )
}

/// The child side of [`Executor::Subprocess`]: runs `cell`
/// (`WORKLOAD/METHOD`), writes the events to `events_file` and returns the
/// line of JSON to print on standard output. `build_time`: see
/// [`Config::build_time`].
pub fn cell_main(
    cell: &str,
    events_file: &Path,
    budget_seconds: f64,
    build_time: bool,
) -> Result<String, String> {
    let (w, m) = cell
        .split_once('/')
        .ok_or_else(|| format!("--cell {cell:?}: expected WORKLOAD/METHOD"))?;
    let workload = Workload::parse(w)?;
    let method = Method::parse(m)?;
    let (outcome, events) = run_cell(&workload, method, budget_seconds, true, build_time);
    if outcome.status == Status::Ok {
        write_events(events_file, &events)
            .map_err(|e| format!("cannot write {}: {e}", events_file.display()))?;
    }
    serde_json::to_string(&outcome).map_err(|e| e.to_string())
}

/// Runs a cell in a child process, killing it past the budget.
fn run_child(
    exe: &Path,
    args: &[String],
    workload: &Workload,
    method: Method,
    budget_seconds: f64,
    events_file: &Path,
    build_time: bool,
) -> CellOutcome {
    let mut cmd = Command::new(exe);
    cmd.args(args)
        .arg("--cell")
        .arg(format!("{}/{}", workload.name(), method.name()))
        .arg("--cell-events")
        .arg(events_file)
        .arg("--budget")
        .arg(format!("{budget_seconds}"))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if build_time {
        cmd.arg("--build-time");
    }
    let mut child = match cmd.spawn() {
        Ok(c) => c,
        Err(e) => return CellOutcome::not_run(Status::Error(format!("cannot start: {e}"))),
    };
    // generous room for building large scenes before the method starts;
    // with `build_time` the child first runs the construction alone, which
    // can take as long as the measured run (brute's first all-pairs pass
    // is most of its run): room for both, or a cell that finishes within
    // its budget is killed (brute on 10^4 octagons)
    let limit = if build_time {
        Duration::from_secs_f64(budget_seconds * 2.4 + 20.0)
    } else {
        Duration::from_secs_f64(budget_seconds * 1.2 + 10.0)
    };
    let start = Instant::now();
    let exit = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => return CellOutcome::not_run(Status::Error(format!("wait: {e}"))),
        }
    };
    let Some(exit) = exit else {
        let mut o = CellOutcome::not_run(Status::Budget);
        o.wall_seconds = start.elapsed().as_secs_f64();
        return o;
    };
    let mut out = String::new();
    let mut err = String::new();
    if let Some(mut s) = child.stdout.take() {
        let _ = s.read_to_string(&mut out);
    }
    if let Some(mut s) = child.stderr.take() {
        let _ = s.read_to_string(&mut err);
    }
    match out
        .lines()
        .last()
        .and_then(|l| serde_json::from_str(l).ok())
    {
        Some(o) if exit.success() => o,
        _ => {
            let last = err
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("");
            CellOutcome::not_run(Status::Error(format!("child exited with {exit}: {last}")))
        }
    }
}

/// The work a cell of `method` does on `workload`, by which its wall time
/// is extrapolated to the next size of the series: the number of pairs for
/// the all-pairs methods on many bodies, else the workload's size.
fn cell_work(workload: &Workload, method: Method) -> f64 {
    if workload.is_many_body() && matches!(method, Method::Brute | Method::ParryToi) {
        workload.all_pairs_work()
    } else {
        workload.series().1
    }
}

/// Runs the benchmark: every method on every workload.
pub fn run(
    config: &Config,
    executor: &Executor,
    on_progress: &mut dyn FnMut(Progress<'_>),
) -> std::io::Result<BenchRun> {
    let started = Instant::now();
    fs::create_dir_all(&config.events_dir)?;
    let repeat = config.repeat.max(1);
    on_progress(Progress::Start {
        cells: config.workloads.len() * config.methods.len() * repeat as usize,
    });
    // per (series, method): the work of the last size run and its wall time,
    // or over budget
    let mut history: HashMap<(String, String), (f64, f64, bool)> = HashMap::new();
    let mut run = BenchRun {
        quick: config.quick,
        budget_seconds: config.budget_seconds,
        workloads: config.workloads.iter().map(|w| w.name()).collect(),
        methods: config.methods.iter().map(|m| m.name()).collect(),
        references: HashMap::new(),
        cells: Vec::new(),
        total_seconds: 0.0,
        resumes: 0,
        repeat,
    };
    let earlier = config.resume.as_ref();
    let earlier_seconds = earlier.map_or(0.0, |r| r.total_seconds);
    if let Some(r) = earlier {
        run.resumes = r.resumes + 1;
    }
    // smaller sizes first within a series, so that budgets carry over
    let mut order: Vec<&Workload> = config.workloads.iter().collect();
    order.sort_by(|a, b| {
        let (sa, za) = a.series();
        let (sb, zb) = b.series();
        sa.cmp(&sb).then(za.total_cmp(&zb))
    });
    for workload in order {
        let wname = workload.name();
        let series = workload.series().0;
        // finished in the run resumed: taken as it is (its budgets carry
        // over as if it had run here)
        let done: Option<Vec<CellResult>> = earlier.and_then(|r| {
            config
                .methods
                .iter()
                .map(|m| r.cell(&wname, &m.name()).cloned())
                .collect()
        });
        if let Some(cells) = done {
            for (cell, method) in cells.iter().zip(&config.methods) {
                let work = cell_work(workload, *method);
                let key = (series.clone(), cell.method.clone());
                match cell.outcome.status {
                    Status::Ok => {
                        history.insert(key, (work, cell.outcome.wall_seconds, false));
                    }
                    Status::Budget | Status::SkippedBudget => {
                        history.insert(key, (work, f64::INFINITY, true));
                    }
                    _ => {}
                }
            }
            if let Some(r) = earlier.and_then(|r| r.references.get(&wname)) {
                run.references.insert(wname.clone(), r.clone());
            }
            run.cells.extend(cells);
            on_progress(Progress::Resumed { workload: &wname });
            continue;
        }
        let mut events: HashMap<String, Vec<Event>> = HashMap::new();
        // each method's runs, round after round (one round unless
        // `repeat`): a method whose run did not finish is not run again
        let mut runs: Vec<Vec<CellOutcome>> = vec![Vec::new(); config.methods.len()];
        for _round in 0..repeat {
            for (mi, &method) in config.methods.iter().enumerate() {
                if runs[mi].last().is_some_and(|o| o.status != Status::Ok) {
                    continue;
                }
                let mname = method.name();
                on_progress(Progress::CellStart {
                    workload: &wname,
                    method: &mname,
                });
                let key = (series.clone(), mname.clone());
                let work = cell_work(workload, method);
                let predicted_over = history.get(&key).is_some_and(|&(w0, wall, over)| {
                    over || wall * (work / w0) > 2.0 * config.budget_seconds
                });
                let outcome = if workload.vertices() > config.max_vertices {
                    CellOutcome::not_run(Status::SkippedMemory)
                } else if predicted_over && runs[mi].is_empty() {
                    CellOutcome::not_run(Status::SkippedBudget)
                } else {
                    let file = events_path(&config.events_dir, &wname, &mname);
                    let _ = fs::remove_file(&file);
                    match executor {
                        Executor::InProcess => {
                            let (o, ev) = run_cell(
                                workload,
                                method,
                                config.budget_seconds,
                                false,
                                config.build_time,
                            );
                            if o.status == Status::Ok {
                                write_events(&file, &ev)?;
                            }
                            o
                        }
                        Executor::Subprocess { exe, args } => run_child(
                            exe,
                            args,
                            workload,
                            method,
                            config.budget_seconds,
                            &file,
                            config.build_time,
                        ),
                    }
                };
                on_progress(Progress::CellDone(&CellResult {
                    workload: wname.clone(),
                    method: mname,
                    outcome: outcome.clone(),
                    comparison: None,
                }));
                runs[mi].push(outcome);
            }
        }
        let mut cells = Vec::new();
        for (mi, &method) in config.methods.iter().enumerate() {
            let mname = method.name();
            let outcome = median_run(&runs[mi]);
            let key = (series.clone(), mname.clone());
            let work = cell_work(workload, method);
            match outcome.status {
                Status::Ok => {
                    history.insert(key, (work, outcome.wall_seconds, false));
                    // (the events of the last run, read once: every run of
                    // a method reports the same, and a method runs again
                    // only while its runs finish)
                    let file = events_path(&config.events_dir, &wname, &mname);
                    events.insert(mname.clone(), read_events(&file)?);
                }
                Status::Budget | Status::SkippedBudget => {
                    history.insert(key, (work, f64::INFINITY, true));
                }
                _ => {}
            }
            cells.push(CellResult {
                workload: wname.clone(),
                method: mname,
                outcome,
                comparison: None,
            });
        }
        // the reference: brute if it ran, else the first exact method that did
        let reference = config
            .methods
            .iter()
            .filter(|m| m.is_exact())
            .map(|m| m.name())
            .find(|m| events.contains_key(m));
        if let Some(r) = &reference {
            let want = &events[r];
            for cell in &mut cells {
                if let Some(got) = events.get(&cell.method) {
                    cell.comparison = Some(compare(want, got));
                }
            }
            run.references.insert(wname.clone(), r.clone());
        }
        run.cells.extend(cells);
        run.total_seconds = earlier_seconds + started.elapsed().as_secs_f64();
        on_progress(Progress::WorkloadDone(&run));
    }
    run.total_seconds = earlier_seconds + started.elapsed().as_secs_f64();
    Ok(run)
}
