//! The commands of `kss`.

use std::fs;
use std::io::{self, BufWriter, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kss::gen;
use kss::{CollisionEvent, RunError, RunOptions, RunStats, Scenario, StructureKind};

use crate::cli::{
    BenchArgs, Cli, Command, DemoArgs, GasArgs, GenArgs, GenFamily, RenderArgs, RunArgs,
};
use crate::json::{self, json_f64, json_str};

/// Why a command failed; the kind gives the exit status.
#[derive(Debug)]
pub struct CliError {
    /// The exit status (see [`CliError::exit_code`]).
    pub kind: ErrorKind,
    /// The message (printed after `kss: error: `).
    pub message: String,
}

/// Kinds of failure, one exit status each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// Invalid input: malformed or invalid scenario, bad generator parameters (1).
    Invalid,
    /// Bad command line (2, as clap's own errors).
    Usage,
    /// The requested structure is not implemented (3).
    NotImplemented,
    /// A bug in kss (4).
    Internal,
    /// A file could not be read or written (5).
    Io,
}

impl CliError {
    fn new(kind: ErrorKind, message: impl Into<String>) -> CliError {
        CliError {
            kind,
            message: message.into(),
        }
    }

    /// The process exit status for this error.
    pub fn exit_code(&self) -> i32 {
        match self.kind {
            ErrorKind::Invalid => 1,
            ErrorKind::Usage => 2,
            ErrorKind::NotImplemented => 3,
            ErrorKind::Internal => 4,
            ErrorKind::Io => 5,
        }
    }

    fn from_run(source: &str, e: RunError) -> CliError {
        match e {
            RunError::Invalid(e) => CliError::new(
                ErrorKind::Invalid,
                format!("{source}: invalid scenario: {e}"),
            ),
            e @ RunError::NotImplemented(_) => {
                CliError::new(ErrorKind::NotImplemented, e.to_string())
            }
            e @ RunError::InsertionTouches { .. } => {
                CliError::new(ErrorKind::Invalid, format!("{source}: {e}"))
            }
            e @ (RunError::Internal(_) | RunError::Aborted(_)) => {
                CliError::new(ErrorKind::Internal, e.to_string())
            }
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CliError {}

/// Runs the parsed command line.
pub fn execute(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Run(a) => run(&a),
        Command::Gen(a) => gen_command(&a),
        Command::Render(a) => render(&a),
        Command::Demo(a) => demo(&a),
        Command::Bench(a) => bench(&a),
    }
}

/// Reads and parses a scenario file (`-`: standard input).
pub fn load_scenario(source: &str) -> Result<Scenario, CliError> {
    let text = if source == "-" {
        let mut s = String::new();
        io::stdin().read_to_string(&mut s).map_err(|e| {
            CliError::new(ErrorKind::Io, format!("cannot read standard input: {e}"))
        })?;
        s
    } else {
        fs::read_to_string(source)
            .map_err(|e| CliError::new(ErrorKind::Io, format!("cannot read {source}: {e}")))?
    };
    json::parse_scenario(&text)
        .map_err(|e| CliError::new(ErrorKind::Invalid, format!("{source}: {e}")))
}

/// One event as a JSON line (without the newline).
pub fn event_line(e: &CollisionEvent) -> String {
    let mut s = format!(
        "{{\"time\": {}, \"a\": {}, \"b\": {}",
        json_f64(e.time.to_f64()),
        json_str(&e.a),
        json_str(&e.b)
    );
    if e.point.iter().all(|x| x.is_finite()) {
        s.push_str(&format!(
            ", \"point\": [{}, {}]",
            json_f64(e.point[0]),
            json_f64(e.point[1])
        ));
    }
    s.push('}');
    s
}

/// The `--stats` object of the contract.
pub fn stats_json(stats: &RunStats, wall_seconds: f64) -> String {
    let by_kind: serde_json::Map<String, serde_json::Value> = stats
        .events_by_kind
        .iter()
        .map(|(k, v)| (k.clone(), serde_json::Value::from(*v)))
        .collect();
    let v = serde_json::json!({
        "structure": stats.structure,
        "polygons": stats.polygons,
        "vertices": stats.vertices,
        "events_processed": stats.events_processed,
        "events_by_kind": by_kind,
        "certificates_max": stats.certificates_max,
        "certificates_final": stats.certificates_final,
        "collisions": stats.collisions,
        "max_number_bits": stats.max_number_bits,
        "rebuilds": stats.rebuilds,
        "degenerate_rebuilds": stats.degenerate_rebuilds,
        "refine_rebuilds": stats.refine_rebuilds,
        "insert_rebuilds": stats.insert_rebuilds,
        "merges": stats.merges,
        "local_removals": stats.local_removals,
        "local_insertions": stats.local_insertions,
        "local_repairs": stats.local_repairs,
        "stand_ins": stats.stand_ins,
        "stand_in_ends": stats.stand_in_ends,
        "work": stats.work,
        "build_seconds": stats.build_seconds,
        "wall_seconds": wall_seconds,
    });
    let mut s = serde_json::to_string_pretty(&v).expect("stats serialize");
    s.push('\n');
    s
}

fn write_file(path: &Path, text: &str) -> Result<(), CliError> {
    fs::write(path, text).map_err(|e| {
        CliError::new(
            ErrorKind::Io,
            format!("cannot write {}: {e}", path.display()),
        )
    })
}

/// Writes `text` to `path`, or to standard output when `path` is `None` or `-`.
fn write_output(path: Option<&PathBuf>, text: &str) -> Result<(), CliError> {
    match path {
        Some(p) if p.as_os_str() != "-" => write_file(p, text),
        _ => {
            let mut out = io::stdout().lock();
            match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
                Ok(()) => Ok(()),
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(CliError::new(
                    ErrorKind::Io,
                    format!("cannot write to standard output: {e}"),
                )),
            }
        }
    }
}

/// Event lines to standard output, buffered; a closed pipe ends the program
/// quietly (or, with `keep_going`, just stops the output).
struct EventSink {
    out: BufWriter<io::StdoutLock<'static>>,
    closed: bool,
    error: Option<io::Error>,
    keep_going: bool,
}

impl EventSink {
    fn new(keep_going: bool) -> EventSink {
        EventSink {
            out: BufWriter::with_capacity(1 << 16, io::stdout().lock()),
            closed: false,
            error: None,
            keep_going,
        }
    }

    fn line(&mut self, line: &str) {
        if self.closed {
            return;
        }
        if let Err(e) = writeln!(self.out, "{line}") {
            self.fail(e);
        }
    }

    fn fail(&mut self, e: io::Error) {
        self.closed = true;
        if e.kind() == io::ErrorKind::BrokenPipe {
            if !self.keep_going {
                // The reader went away (`kss run ... | head`): nothing more
                // to say to anybody.
                std::process::exit(0);
            }
        } else {
            self.error = Some(e);
        }
    }

    fn finish(mut self) -> Result<(), CliError> {
        if !self.closed {
            if let Err(e) = self.out.flush() {
                self.fail(e);
            }
        }
        match self.error {
            Some(e) => Err(CliError::new(
                ErrorKind::Io,
                format!("cannot write to standard output: {e}"),
            )),
            None => Ok(()),
        }
    }
}

/// A progress line on standard error, only when it is a terminal.
struct Progress {
    enabled: bool,
    last: Instant,
    shown: bool,
}

impl Progress {
    fn new(quiet: bool) -> Progress {
        Progress {
            enabled: !quiet && io::stderr().is_terminal(),
            last: Instant::now(),
            shown: false,
        }
    }

    fn tick(&mut self, collisions: u64, time: f64) {
        if self.enabled && self.last.elapsed() >= Duration::from_millis(200) {
            self.last = Instant::now();
            self.shown = true;
            eprint!("\rkss: {collisions} collisions, t = {time:<24}");
        }
    }

    fn clear(&mut self) {
        if self.shown {
            eprint!("\r{:60}\r", "");
            self.shown = false;
        }
    }
}

fn summary(stats: &RunStats, wall: f64) -> String {
    format!(
        "kss: {} collision{} ({} structure, {} polygons, {} vertices, {} events processed, at most {} certificates) in {:.3} s",
        stats.collisions,
        if stats.collisions == 1 { "" } else { "s" },
        stats.structure,
        stats.polygons,
        stats.vertices,
        stats.events_processed,
        stats.certificates_max,
        wall
    )
}

/// `kss run`.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let scenario = load_scenario(&args.scenario)?;
    let options = RunOptions {
        structure: StructureKind::from(args.structure),
        until: args.until,
        audit: args.audit,
        ..Default::default()
    };
    let mut sink = EventSink::new(args.stats.is_some());
    let mut progress = Progress::new(args.quiet);
    let mut count = 0u64;
    let start = Instant::now();
    let result = kss::run(&scenario, &options, &mut |e| {
        count += 1;
        sink.line(&event_line(e));
        progress.tick(count, e.time.to_f64());
    });
    let wall = start.elapsed().as_secs_f64();
    progress.clear();
    let flushed = sink.finish();
    let stats = result.map_err(|e| CliError::from_run(&args.scenario, e))?;
    flushed?;
    if let Some(path) = &args.stats {
        write_file(path, &stats_json(&stats, wall))?;
    }
    if !args.quiet {
        eprintln!("{}", summary(&stats, wall));
    }
    Ok(())
}

fn mode_or(args: &GenArgs, default: kss::CollisionMode) -> kss::CollisionMode {
    args.mode.map(Into::into).unwrap_or(default)
}

fn invalid(msg: String) -> CliError {
    CliError::new(ErrorKind::Invalid, msg)
}

fn gas_params(a: &GasArgs, g: &GenArgs) -> Result<gen::GasParams, CliError> {
    let d = gen::GasParams::default();
    let (min_n, max_n) = match a.n {
        Some(n) => (n, n),
        None => {
            let min_n = a.min_n.unwrap_or(d.min_n);
            (min_n, a.max_n.unwrap_or(d.max_n.max(min_n)))
        }
    };
    let p = gen::GasParams {
        k: a.k.unwrap_or(d.k),
        min_n,
        max_n,
        walls: a.walls,
        mode: mode_or(g, d.mode),
        until: a.until.unwrap_or(d.until),
        max_speed: a.max_speed.unwrap_or(d.max_speed),
        changes: a.changes.unwrap_or(d.changes),
        seed: g.seed,
    };
    p.check().map_err(invalid)?;
    Ok(p)
}

fn gas_args_given(a: &GasArgs) -> bool {
    a.k.is_some()
        || a.n.is_some()
        || a.min_n.is_some()
        || a.max_n.is_some()
        || a.walls
        || a.until.is_some()
        || a.max_speed.is_some()
        || a.changes.is_some()
}

/// Builds the scenario `kss gen` asks for (also used by tests).
pub fn generate(args: &GenArgs) -> Result<Scenario, CliError> {
    let family = match &args.family {
        GenFamily::Flypast(_) => Some(gen::Family::Flypast),
        GenFamily::Gas(_) => Some(gen::Family::Gas),
        GenFamily::Simultaneous(_) => Some(gen::Family::Simultaneous),
        GenFamily::Grazing(_) => Some(gen::Family::Grazing),
        GenFamily::Parallel(_) => Some(gen::Family::Parallel),
        GenFamily::Far(_) => Some(gen::Family::Far),
        GenFamily::Swarm(_) | GenFamily::Churn(_) => None,
    };
    if args.small {
        let Some(family) = family else {
            let name = match args.family {
                GenFamily::Churn(_) => "churn",
                _ => "swarm",
            };
            return Err(CliError::new(
                ErrorKind::Usage,
                format!(
                    "--small: {name} has no small instance of the test sweeps; give its options"
                ),
            ));
        };
        let other = args.mode.is_some()
            || match &args.family {
                GenFamily::Flypast(a) => {
                    a.n.is_some()
                        || a.diameter.is_some()
                        || a.gap.is_some()
                        || a.ratio.is_some()
                        || a.a_moving
                        || a.speed.is_some()
                }
                GenFamily::Gas(a) => gas_args_given(a),
                GenFamily::Far(a) => {
                    gas_args_given(&a.gas) || a.offset.is_some() || a.slowdown.is_some()
                }
                GenFamily::Simultaneous(a) => a.pairs.is_some() || a.no_triple || a.until.is_some(),
                GenFamily::Grazing(a) | GenFamily::Parallel(a) => {
                    a.pairs.is_some() || a.until.is_some()
                }
                GenFamily::Swarm(_) | GenFamily::Churn(_) => {
                    unreachable!("swarm and churn have no small instance")
                }
            };
        if other {
            return Err(CliError::new(
                ErrorKind::Usage,
                "--small takes only --seed (and -o): the small instance chooses everything else",
            ));
        }
        return Ok(gen::generate_small(family, args.seed));
    }
    let scenario = match &args.family {
        GenFamily::Flypast(a) => {
            let d = gen::FlypastParams::default();
            let diameter = a.diameter.unwrap_or(d.diameter);
            let gap = match (a.gap, a.ratio) {
                (Some(g), _) => g,
                (None, Some(r)) => diameter / r,
                (None, None) => diameter / 10.0,
            };
            let p = gen::FlypastParams {
                n: a.n.unwrap_or(d.n),
                diameter,
                gap,
                a_moving: a.a_moving,
                speed: a.speed.unwrap_or(d.speed),
                mode: mode_or(args, d.mode),
                seed: args.seed,
            };
            p.check().map_err(invalid)?;
            let (sc, info) = gen::flypast_with_info(&p);
            eprintln!(
                "kss gen flypast: n = {}, diameter = {}, requested gap {}, achieved gap {:e}{}",
                p.n,
                p.diameter,
                p.gap,
                info.achieved_gap,
                if info.achieved_gap <= 0.0 {
                    " (they collide)"
                } else {
                    ""
                }
            );
            sc
        }
        GenFamily::Gas(a) => gen::gas(&gas_params(a, args)?),
        GenFamily::Far(a) => {
            let d = gen::FarParams::default();
            let p = gen::FarParams {
                gas: gas_params(&a.gas, args)?,
                offset: a.offset.unwrap_or(d.offset),
                slowdown: a.slowdown.unwrap_or(d.slowdown),
            };
            p.check().map_err(invalid)?;
            gen::far(&p)
        }
        GenFamily::Simultaneous(a) => {
            let d = gen::SimultaneousParams::default();
            let p = gen::SimultaneousParams {
                pairs: a.pairs.unwrap_or(d.pairs),
                triple: !a.no_triple,
                mode: mode_or(args, d.mode),
                until: a.until,
                small: false,
                seed: args.seed,
            };
            p.check().map_err(invalid)?;
            gen::simultaneous(&p)
        }
        GenFamily::Grazing(a) | GenFamily::Parallel(a) => {
            let d = gen::DegenerateParams::default();
            let p = gen::DegenerateParams {
                pairs: a.pairs.unwrap_or(d.pairs),
                mode: mode_or(args, d.mode),
                until: a.until,
                small: false,
                seed: args.seed,
            };
            p.check().map_err(invalid)?;
            if family == Some(gen::Family::Grazing) {
                gen::grazing(&p)
            } else {
                gen::parallel(&p)
            }
        }
        GenFamily::Swarm(a) => {
            let d = gen::SwarmParams::default();
            let p = gen::SwarmParams {
                k: a.k.unwrap_or(d.k),
                n: a.n.unwrap_or(d.n),
                mode: mode_or(args, d.mode),
                collisions_per_polygon: a.collisions.unwrap_or(d.collisions_per_polygon),
                until: a.until,
                seed: args.seed,
            };
            p.check().map_err(invalid)?;
            let sc = gen::swarm(&p);
            eprintln!(
                "kss gen swarm: {} regular {}-gons, until {}{}",
                p.k,
                p.n,
                sc.until,
                if p.until.is_none() {
                    format!(
                        " (calibrated for about {} collisions per polygon in bounce mode)",
                        p.collisions_per_polygon
                    )
                } else {
                    String::new()
                }
            );
            sc
        }
        GenFamily::Churn(a) => {
            let d = gen::ChurnParams::default();
            let p = gen::ChurnParams {
                k: a.k.unwrap_or(d.k),
                clusters: a.clusters.unwrap_or(d.clusters),
                mode: mode_or(args, d.mode),
                until: a.until.unwrap_or(d.until),
                seed: args.seed,
            };
            p.check().map_err(invalid)?;
            let sc = gen::churn(&p);
            eprintln!(
                "kss gen churn: {} polygons at the start, {} insertions, {} removals, {} flight-plan changes, until {}",
                sc.polygons.len(),
                sc.insertions.len(),
                sc.removals.len(),
                sc.flight_plan_changes.len(),
                sc.until
            );
            sc
        }
    };
    Ok(scenario)
}

/// `kss gen`.
pub fn gen_command(args: &GenArgs) -> Result<(), CliError> {
    let scenario = generate(args)?;
    let text = json::write_scenario(&scenario)
        .map_err(|e| CliError::new(ErrorKind::Internal, e.to_string()))?;
    write_output(args.output.as_ref(), &text)?;
    if let Some(p) = &args.output {
        if p.as_os_str() != "-" {
            eprintln!(
                "kss: wrote {} ({} polygons, {} vertices)",
                p.display(),
                scenario.polygons.len(),
                scenario
                    .polygons
                    .iter()
                    .map(|p| p.vertices.len())
                    .sum::<usize>()
            );
        }
    }
    Ok(())
}

/// `kss render`.
pub fn render(args: &RenderArgs) -> Result<(), CliError> {
    let scenario = load_scenario(&args.scenario)?;
    let structure = StructureKind::from(args.structure);
    let options = RunOptions {
        structure,
        ..Default::default()
    };
    let with_structure = options.structure != StructureKind::Brute && !args.no_structure;
    let snapshot_at = |t: f64| {
        if with_structure {
            kss::runner::structure_snapshot_at(&scenario, &options, t, args.highlight)
        } else {
            kss::runner::snapshot_at(&scenario, &options, t)
        }
        .map_err(|e| CliError::from_run(&args.scenario, e))
    };
    let times: Vec<f64> = match (args.frames, args.to) {
        (Some(n), Some(to)) if n > 1 => (0..n)
            .map(|i| args.time + (to - args.time) * f64::from(i) / f64::from(n - 1))
            .collect(),
        _ => vec![args.time],
    };
    let mut snapshots = Vec::with_capacity(times.len());
    for &t in &times {
        let snapshot = snapshot_at(t)?;
        if let Some(note) = snapshot.structure.as_ref().and_then(|s| s.note.as_ref()) {
            eprintln!("kss render: t = {t}: {note}");
        }
        snapshots.push(snapshot);
    }
    // one view for every frame of an animation: the union of their scenes
    let view = args.view.or_else(|| {
        (snapshots.len() > 1).then(|| {
            let mut v = [
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ];
            for p in snapshots.iter().flat_map(|s| &s.polygons) {
                for q in &p.vertices {
                    v = [
                        v[0].min(q[0]),
                        v[1].min(q[1]),
                        v[2].max(q[0]),
                        v[3].max(q[1]),
                    ];
                }
            }
            let pad = 0.05 * (v[2] - v[0]).max(v[3] - v[1]);
            [v[0] - pad, v[1] - pad, v[2] + pad, v[3] + pad]
        })
    });
    for (i, snapshot) in snapshots.iter().enumerate() {
        let picture = kss::render::svg(
            snapshot,
            &kss::render::RenderOptions {
                width: args.width,
                height: args.height,
                show_ids: !args.no_ids,
                show_velocities: !args.no_velocities,
                view,
                show_structure: with_structure,
                show_legend: !args.no_legend,
                ..Default::default()
            },
        );
        let path = match (&args.output, snapshots.len()) {
            (Some(p), n) if n > 1 => {
                let stem = p.to_string_lossy();
                let stem = stem.strip_suffix(".svg").unwrap_or(&stem);
                Some(PathBuf::from(format!("{stem}-{i:03}.svg")))
            }
            (p, _) => p.clone(),
        };
        write_output(path.as_ref(), &picture)?;
        if let Some(p) = &path {
            if p.as_os_str() != "-" {
                eprintln!(
                    "kss: picture at t = {} written to {}",
                    times[i],
                    p.display()
                );
            }
        }
    }
    Ok(())
}

/// `kss demo`.
pub fn demo(args: &DemoArgs) -> Result<(), CliError> {
    let scenario = gen::demo();
    let structure = StructureKind::from(args.structure);
    let start = Instant::now();
    let mut events: Vec<CollisionEvent> = Vec::new();
    let options = RunOptions {
        structure,
        ..Default::default()
    };
    let stats = kss::run(&scenario, &options, &mut |e| events.push(e.clone()))
        .map_err(|e| CliError::from_run("demo", e))?;
    let wall = start.elapsed().as_secs_f64();
    let mut sink = EventSink::new(true);
    for e in &events {
        sink.line(&event_line(e));
    }
    sink.finish()?;

    let first = events.first().map(|e| e.time.to_f64());
    let moving = scenario.polygons.iter().filter(|p| !p.fixed).count();
    eprintln!(
        "kss demo: {} moving polygons in a box of {} walls, mode {}, until {}",
        moving,
        scenario.polygons.len() - moving,
        scenario.on_collision.name(),
        scenario.until
    );
    eprintln!("{}", summary(&stats, wall));
    let when = first.unwrap_or(0.0);
    match first {
        Some(t) => eprintln!("kss demo: first collision at t = {t}"),
        None => eprintln!("kss demo: no collision"),
    }
    let options = RunOptions {
        structure,
        ..Default::default()
    };
    let snapshot = kss::runner::snapshot_at(&scenario, &options, when)
        .map_err(|e| CliError::from_run("demo", e))?;
    let picture = kss::render::svg(&snapshot, &kss::render::RenderOptions::default());
    write_file(&args.output, &picture)?;
    eprintln!(
        "kss demo: picture of the scene at t = {when} written to {}",
        args.output.display()
    );
    Ok(())
}

/// The workloads selected by `--workload`: full names, named sets (`cost`,
/// `perf`: the same workloads in quick and full mode) or families (the
/// family's workloads among the defaults of the mode).
fn bench_workloads(args: &BenchArgs) -> Result<Vec<kss_bench::workload::Workload>, CliError> {
    use kss_bench::workload::Workload;
    let defaults = if args.quick {
        Workload::quick()
    } else {
        Workload::full()
    };
    if args.workload.is_empty() {
        return Ok(defaults);
    }
    let mut out: Vec<Workload> = Vec::new();
    for name in &args.workload {
        let picked: Vec<Workload> = if let Some(set) = Workload::set(name) {
            set
        } else if [
            "flypast", "gas", "cluster", "swarm", "grazing", "parallel", "far", "walls", "gasmix",
        ]
        .contains(&name.as_str())
        {
            defaults
                .iter()
                .filter(|w| w.family() == name)
                .cloned()
                .collect()
        } else {
            vec![Workload::parse(name).map_err(|e| CliError::new(ErrorKind::Usage, e))?]
        };
        for w in picked {
            if !out.contains(&w) {
                out.push(w);
            }
        }
    }
    Ok(out)
}

/// Write a benchmark run's Markdown table, JSON and plots into `out`, and
/// the table on standard output.
fn write_report(
    out: &Path,
    run: &kss_bench::harness::BenchRun,
    machine: &kss_bench::report::Machine,
) -> Result<(), CliError> {
    let files = kss_bench::report::write(out, run, machine).map_err(|e| {
        CliError::new(
            ErrorKind::Io,
            format!("cannot write results to {}: {e}", out.display()),
        )
    })?;
    write_output(None, &kss_bench::report::markdown(run, machine))?;
    for f in &files {
        eprintln!("kss bench: wrote {}", f.display());
    }
    Ok(())
}

/// `kss bench`.
pub fn bench(args: &BenchArgs) -> Result<(), CliError> {
    use kss_bench::harness::{self, Config, Executor, Progress, Status};

    if let Some(cell) = &args.cell {
        let events = args
            .cell_events
            .clone()
            .unwrap_or_else(|| PathBuf::from("cell-events.jsonl"));
        let budget = args.budget.unwrap_or(600.0);
        let line = harness::cell_main(cell, &events, budget, args.build_time)
            .map_err(|e| CliError::new(ErrorKind::Usage, e))?;
        println!("{line}");
        return Ok(());
    }
    if !args.report_from.is_empty() {
        let (mut run, machine) = kss_bench::report::read_runs(&args.report_from)
            .map_err(|e| CliError::new(ErrorKind::Io, format!("--report-from: {e}")))?;
        if !args.workload.is_empty() {
            // only the workloads named (full names or families)
            let keep: Vec<String> = bench_workloads(args)?.iter().map(|w| w.name()).collect();
            run.workloads.retain(|w| keep.contains(w));
            run.cells.retain(|c| keep.contains(&c.workload));
            run.references.retain(|w, _| keep.contains(w));
            if run.workloads.is_empty() {
                return Err(CliError::new(
                    ErrorKind::Usage,
                    "--report-from: none of the --workload names is in these runs",
                ));
            }
        }
        return write_report(&args.out, &run, &machine);
    }
    let mut config = Config::new(args.quick, &args.out);
    if let Some(b) = args.budget {
        config.budget_seconds = b;
    }
    config.workloads = bench_workloads(args)?;
    config.build_time = args.build_time;
    if !args.methods.is_empty() {
        config.methods = args
            .methods
            .iter()
            .map(|m| kss_bench::Method::parse(m.trim()))
            .collect::<Result<_, _>>()
            .map_err(|e| CliError::new(ErrorKind::Usage, e))?;
    }
    let machine = kss_bench::report::machine();
    let mut machine_of_run = machine.clone();
    if let Some(file) = &args.resume {
        let (earlier, m) = kss_bench::report::read_runs(std::slice::from_ref(file))
            .map_err(|e| CliError::new(ErrorKind::Io, format!("--resume: {e}")))?;
        let methods: Vec<String> = config.methods.iter().map(|m| m.name()).collect();
        let workloads: Vec<String> = config.workloads.iter().map(|w| w.name()).collect();
        // (a run with --build-time measured a build for its structure cells)
        let built = earlier
            .cells
            .iter()
            .any(|c| c.outcome.build_seconds.is_some());
        let timed_build = earlier.cells.iter().any(|c| {
            matches!(
                kss_bench::Method::parse(&c.method),
                Ok(kss_bench::Method::Brute
                    | kss_bench::Method::Plain
                    | kss_bench::Method::Hierarchical)
            ) && c.outcome.status == Status::Ok
        });
        if earlier.methods != methods
            || earlier.workloads != workloads
            || earlier.budget_seconds != config.budget_seconds
            || earlier.quick != config.quick
            || (timed_build && built != config.build_time)
        {
            return Err(CliError::new(
                ErrorKind::Usage,
                format!(
                    "--resume: {} was a run of {} on {} workloads ({} …) at {} s per cell{}{}; \
                     give the same methods, workloads, budget, mode and --build-time",
                    file.display(),
                    earlier.methods.join(","),
                    earlier.workloads.len(),
                    earlier.workloads.first().map_or("", String::as_str),
                    earlier.budget_seconds,
                    if earlier.quick { " (quick)" } else { "" },
                    if built { " with --build-time" } else { "" }
                ),
            ));
        }
        let here = &machine;
        if (
            m.cpu.as_str(),
            m.cores,
            m.rustc.as_str(),
            m.profile.as_str(),
            m.binary.as_str(),
        ) != (
            here.cpu.as_str(),
            here.cores,
            here.rustc.as_str(),
            here.profile.as_str(),
            here.binary.as_str(),
        ) {
            return Err(CliError::new(
                ErrorKind::Usage,
                format!(
                    "--resume: {} was run by another binary or on another machine \
                     ({}, {} cores, {}, {} profile, binary {}); resume it with the same one",
                    file.display(),
                    m.cpu,
                    m.cores,
                    m.rustc,
                    m.profile,
                    if m.binary.is_empty() {
                        "unknown"
                    } else {
                        &m.binary
                    }
                ),
            ));
        }
        // the report names the machine and the date of the run's start
        machine_of_run = m;
        config.resume = Some(earlier);
    }
    if args.list {
        let mut text = String::new();
        for w in &config.workloads {
            text.push_str(&format!("workload {}\n", w.name()));
        }
        for m in &config.methods {
            text.push_str(&format!("method {}\n", m.name()));
        }
        return write_output(None, &text);
    }
    let exe = std::env::current_exe().map_err(|e| {
        CliError::new(
            ErrorKind::Io,
            format!("cannot find the kss executable: {e}"),
        )
    })?;
    let executor = Executor::Subprocess {
        exe,
        args: vec!["bench".into()],
    };
    let terminal = io::stderr().is_terminal();
    let bar = indicatif::ProgressBar::hidden();
    if terminal {
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "kss bench {bar:30} {pos}/{len} cells, {elapsed} [{msg}]",
            )
            .expect("valid template"),
        );
    }
    let say = |line: String| {
        if terminal {
            bar.println(line);
        } else {
            eprintln!("{line}");
        }
    };
    let checkpoint = args.out.join("checkpoint.json");
    let mut done = 0usize;
    let mut total = 0usize;
    let mut on_progress = |p: Progress<'_>| match p {
        Progress::Start { cells } => {
            total = cells;
            bar.set_length(cells as u64);
            say(format!(
                "kss bench: {} workloads x {} methods, budget {} s per cell, results in {}",
                config.workloads.len(),
                config.methods.len(),
                config.budget_seconds,
                args.out.display()
            ));
        }
        Progress::CellStart { workload, method } => {
            bar.set_message(format!("{workload} {method}"));
        }
        Progress::Resumed { workload } => {
            let n = config.methods.len();
            done += n;
            bar.inc(n as u64);
            say(format!(
                "[{done}/{total}] {workload}: kept from the run resumed"
            ));
        }
        Progress::WorkloadDone(run) => {
            // a checkpoint to resume from if the run is interrupted
            if let Err(e) = kss_bench::report::write_checkpoint(&checkpoint, run, &machine_of_run) {
                say(format!(
                    "kss bench: warning: cannot write {}: {e}",
                    checkpoint.display()
                ));
            }
        }
        Progress::CellDone(cell) => {
            done += 1;
            bar.inc(1);
            let o = &cell.outcome;
            let what = match &o.status {
                Status::Ok => format!(
                    "{} collisions in {}",
                    o.counters.collisions,
                    kss_bench::report::human_seconds(o.wall_seconds)
                ),
                s => s.text(),
            };
            say(format!(
                "[{done}/{total}] {} {}: {what}",
                cell.workload, cell.method
            ));
        }
    };
    let run = harness::run(&config, &executor, &mut on_progress)
        .map_err(|e| CliError::new(ErrorKind::Io, format!("benchmark: {e}")))?;
    bar.finish_and_clear();
    write_report(&args.out, &run, &machine_of_run)?;
    eprintln!(
        "kss bench: {} cells in {:.1} s",
        run.cells.len(),
        run.total_seconds
    );
    let bad = |c: &&kss_bench::harness::CellResult| {
        matches!(c.outcome.status, Status::Error(_))
            || (kss_bench::Method::parse(&c.method).is_ok_and(|m| m.is_exact())
                && c.comparison.as_ref().is_some_and(|x| !x.identical))
    };
    let broken: Vec<String> = run
        .cells
        .iter()
        .filter(bad)
        .map(|c| format!("{} {}", c.workload, c.method))
        .collect();
    if broken.is_empty() {
        Ok(())
    } else {
        Err(CliError::new(
            ErrorKind::Internal,
            format!(
                "benchmark cells failed or an exact method differs from the reference: {}",
                broken.join(", ")
            ),
        ))
    }
}
