//! The `kss-bench` command: runs the benchmark (every cell in a child
//! process of the same executable), resumes an interrupted run, or writes
//! the report of earlier runs.

use std::io::{self, IsTerminal, Write};
use std::path::{Path, PathBuf};

use crate::cli::{BenchArgs, DocsArgs, Sub};
use crate::harness::{self, BenchRun, CellResult, Config, Executor, Progress, Status};
use crate::report::{self, Machine};
use crate::workload::Workload;
use crate::Method;

/// Why the command failed; the kind gives the exit status.
#[derive(Debug)]
pub struct Error {
    /// The exit status (see [`Error::exit_code`]).
    pub kind: ErrorKind,
    /// The message (printed after `kss-bench: error: `).
    pub message: String,
}

/// Kinds of failure, one exit status each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// `docs --check`: the page differs from what the results make (1).
    Stale,
    /// Bad command line (2, as clap's own errors).
    Usage,
    /// A cell failed or an exact method differs from the reference (4).
    Internal,
    /// A file could not be read or written (5).
    Io,
}

impl Error {
    fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            message: message.into(),
        }
    }

    /// The process exit status for this error.
    pub fn exit_code(&self) -> i32 {
        match self.kind {
            ErrorKind::Stale => 1,
            ErrorKind::Usage => 2,
            ErrorKind::Internal => 4,
            ErrorKind::Io => 5,
        }
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// Writes `text` to standard output; a reader that is gone (a closed pipe,
/// as with `kss-bench --list | head -1`) is not an error.
fn print(text: &str) -> Result<(), Error> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => Err(Error::new(
            ErrorKind::Io,
            format!("cannot write to standard output: {e}"),
        )),
        _ => Ok(()),
    }
}

/// The workloads selected by `--workload`: full names, named sets (`cost`,
/// `perf`: the same workloads in quick and full mode) or families (the
/// family's workloads among the defaults of the mode).
fn bench_workloads(args: &BenchArgs) -> Result<Vec<Workload>, Error> {
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
            vec![Workload::parse(name).map_err(|e| Error::new(ErrorKind::Usage, e))?]
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
fn write_report(out: &Path, run: &BenchRun, machine: &Machine) -> Result<(), Error> {
    let files = report::write(out, run, machine).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("cannot write results to {}: {e}", out.display()),
        )
    })?;
    print(&report::markdown(run, machine))?;
    for f in &files {
        eprintln!("kss-bench: wrote {}", f.display());
    }
    Ok(())
}

/// `kss-bench docs`: writes the benchmark page from the results files, or
/// with `--check` compares it with the page there.
pub fn docs(args: &DocsArgs) -> Result<(), Error> {
    let page = crate::docs::generate(&args.results, &args.out)
        .map_err(|e| Error::new(ErrorKind::Io, format!("docs: {e}")))?;
    if args.check {
        let now = std::fs::read_to_string(&args.out).map_err(|e| {
            Error::new(
                ErrorKind::Io,
                format!("docs: cannot read {}: {e}", args.out.display()),
            )
        })?;
        return match crate::docs::first_difference(&now, &page) {
            None => Ok(()),
            Some(d) => Err(Error::new(
                ErrorKind::Stale,
                format!(
                    "docs: {} is not what the results make ({d}); write it with `{}`",
                    args.out.display(),
                    crate::docs::COMMAND
                ),
            )),
        };
    }
    std::fs::write(&args.out, &page).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("docs: cannot write {}: {e}", args.out.display()),
        )
    })?;
    eprintln!("kss-bench: wrote {}", args.out.display());
    Ok(())
}

/// Runs `kss-bench` with the parsed command line.
pub fn bench(args: &BenchArgs) -> Result<(), Error> {
    if let Some(Sub::Docs(d)) = &args.command {
        return docs(d);
    }
    if let Some(cell) = &args.cell {
        let events = args
            .cell_events
            .clone()
            .unwrap_or_else(|| PathBuf::from("cell-events.jsonl"));
        let budget = args.budget.unwrap_or(600.0);
        let line = harness::cell_main(cell, &events, budget, args.build_time)
            .map_err(|e| Error::new(ErrorKind::Usage, e))?;
        println!("{line}");
        return Ok(());
    }
    if !args.report_from.is_empty() {
        let (mut run, machine) = report::read_runs(&args.report_from)
            .map_err(|e| Error::new(ErrorKind::Io, format!("--report-from: {e}")))?;
        if !args.workload.is_empty() {
            // only the workloads named (full names or families)
            let keep: Vec<String> = bench_workloads(args)?.iter().map(|w| w.name()).collect();
            run.workloads.retain(|w| keep.contains(w));
            run.cells.retain(|c| keep.contains(&c.workload));
            run.references.retain(|w, _| keep.contains(w));
            if run.workloads.is_empty() {
                return Err(Error::new(
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
    config.repeat = args.repeat;
    if !args.methods.is_empty() {
        config.methods = args
            .methods
            .iter()
            .map(|m| Method::parse(m.trim()))
            .collect::<Result<_, _>>()
            .map_err(|e| Error::new(ErrorKind::Usage, e))?;
    }
    let machine = report::machine();
    let mut machine_of_run = machine.clone();
    if let Some(file) = &args.resume {
        let (earlier, m) = report::read_runs(std::slice::from_ref(file))
            .map_err(|e| Error::new(ErrorKind::Io, format!("--resume: {e}")))?;
        let methods: Vec<String> = config.methods.iter().map(|m| m.name()).collect();
        let workloads: Vec<String> = config.workloads.iter().map(|w| w.name()).collect();
        // (a run with --build-time measured a build for its structure cells)
        let built = earlier
            .cells
            .iter()
            .any(|c| c.outcome.build_seconds.is_some());
        let timed_build = earlier.cells.iter().any(|c| {
            Method::parse(&c.method).is_ok_and(|m| m.is_library()) && c.outcome.status == Status::Ok
        });
        if earlier.methods != methods
            || earlier.workloads != workloads
            || earlier.budget_seconds != config.budget_seconds
            || earlier.quick != config.quick
            || earlier.repeat != config.repeat
            || (timed_build && built != config.build_time)
        {
            return Err(Error::new(
                ErrorKind::Usage,
                format!(
                    "--resume: {} was a run of {} on {} workloads ({} …) at {} s per cell{}{}{}; \
                     give the same methods, workloads, budget, mode, --repeat and --build-time",
                    file.display(),
                    earlier.methods.join(","),
                    earlier.workloads.len(),
                    earlier.workloads.first().map_or("", String::as_str),
                    earlier.budget_seconds,
                    if earlier.quick { " (quick)" } else { "" },
                    if built { " with --build-time" } else { "" },
                    match earlier.repeat {
                        1 => String::new(),
                        n => format!(", each cell {n} times"),
                    }
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
            return Err(Error::new(
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
        return print(&text);
    }
    let exe = std::env::current_exe().map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("cannot find the kss-bench executable: {e}"),
        )
    })?;
    let executor = Executor::Subprocess {
        exe,
        args: Vec::new(),
    };
    let terminal = io::stderr().is_terminal();
    let bar = indicatif::ProgressBar::hidden();
    if terminal {
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "kss-bench {bar:30} {pos}/{len} cells, {elapsed} [{msg}]",
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
                "kss-bench: {} workloads x {} methods{}, budget {} s per cell, results in {}",
                config.workloads.len(),
                config.methods.len(),
                match config.repeat {
                    1 => String::new(),
                    n => format!(" x {n} runs"),
                },
                config.budget_seconds,
                args.out.display()
            ));
        }
        Progress::CellStart { workload, method } => {
            bar.set_message(format!("{workload} {method}"));
        }
        Progress::Resumed { workload } => {
            let n = config.methods.len() * config.repeat as usize;
            done += n;
            bar.inc(n as u64);
            say(format!(
                "[{done}/{total}] {workload}: kept from the run resumed"
            ));
        }
        Progress::WorkloadDone(run) => {
            // a checkpoint to resume from if the run is interrupted
            if let Err(e) = report::write_checkpoint(&checkpoint, run, &machine_of_run) {
                say(format!(
                    "kss-bench: warning: cannot write {}: {e}",
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
                    report::human_seconds(o.wall_seconds)
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
        .map_err(|e| Error::new(ErrorKind::Io, format!("benchmark: {e}")))?;
    bar.finish_and_clear();
    write_report(&args.out, &run, &machine_of_run)?;
    eprintln!(
        "kss-bench: {} cells in {:.1} s",
        run.cells.len(),
        run.total_seconds
    );
    let bad = |c: &&CellResult| {
        matches!(c.outcome.status, Status::Error(_))
            || (Method::parse(&c.method).is_ok_and(|m| m.is_exact())
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
        Err(Error::new(
            ErrorKind::Internal,
            format!(
                "benchmark cells failed or an exact method differs from the reference: {}",
                broken.join(", ")
            ),
        ))
    }
}
