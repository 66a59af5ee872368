//! The commands of `kss`.

use std::fs;
use std::io::{self, BufWriter, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kss::gen;
use kss::json::{self, json_f64, json_str};
use kss::{CollisionEvent, RunError, RunOptions, RunStats, Scenario, StructureKind};

use crate::cli::{Cli, Command, DemoArgs, GasArgs, GenArgs, GenFamily, RenderArgs, RunArgs};

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
            // an internal error, an aborted finder, and any kind of error a
            // later version of the library adds
            e => CliError::new(ErrorKind::Internal, e.to_string()),
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
        "events_seconds": stats.events_seconds,
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
        approximate_above: args.approximate_above,
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
    p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
            p.check().map_err(|e| invalid(e.0))?;
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
        approximate_above: args.approximate_above,
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
        approximate_above: args.approximate_above,
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
        approximate_above: args.approximate_above,
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
