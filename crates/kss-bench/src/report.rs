//! The results folder: `bench.md` (machine, ratio table, accuracy, every
//! cell), `bench.json` (the raw run) and SVG plots (hand-written SVG, log-log).

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::harness::{BenchRun, CellOutcome, CellResult, Status};
use crate::workload::Workload;
use crate::Method;

/// The machine a run was measured on.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Machine {
    /// CPU model (`/proc/cpuinfo`).
    pub cpu: String,
    /// Logical cores available.
    pub cores: usize,
    /// Total memory, GiB (`/proc/meminfo`).
    pub memory_gib: f64,
    /// Operating system and kernel.
    pub os: String,
    /// The compiler that built the benchmark.
    pub rustc: String,
    /// `release` or `debug`.
    pub profile: String,
    /// Date of the run (UTC).
    pub date: String,
    /// A fingerprint of the executable that ran the benchmark (64-bit
    /// FNV-1a of its bytes, hex; empty in older results): a resumed run
    /// must be run by the same binary.
    #[serde(default)]
    pub binary: String,
}

/// Describes this machine.
pub fn machine() -> Machine {
    let cpuinfo = fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let cpu = cpuinfo
        .lines()
        .find_map(|l| l.strip_prefix("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    let meminfo = fs::read_to_string("/proc/meminfo").unwrap_or_default();
    let memory_gib = meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kib| kib / (1024.0 * 1024.0));
    let kernel = fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default();
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    Machine {
        cpu,
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        memory_gib,
        os: format!("{} {}", std::env::consts::OS, kernel.trim()),
        rustc: env!("KSS_BENCH_RUSTC").to_string(),
        profile: if cfg!(debug_assertions) {
            "debug".into()
        } else {
            "release".into()
        },
        date: civil_date(secs),
        binary: std::env::current_exe()
            .and_then(fs::read)
            .map(|bytes| {
                let h = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
                    (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
                });
                format!("{h:016x}")
            })
            .unwrap_or_default(),
    }
}

/// `YYYY-MM-DD HH:MM` (UTC) of a Unix time.
fn civil_date(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // days since 1970-01-01 to a civil date (proleptic Gregorian)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}",
        rem / 3600,
        (rem % 3600) / 60
    )
}

/// A ratio with two significant digits (at least two decimals).
pub fn format_ratio(r: f64) -> String {
    if !(r.is_finite() && r > 0.0) || r >= 0.1 {
        format!("{r:.2}")
    } else {
        let decimals = (1.0 - r.log10().floor()) as usize;
        format!("{r:.decimals$}")
    }
}

/// `hierarchical`'s wall time over each other method's, per workload (the
/// headline ratios): below 1 (bold) the library's default structure is
/// faster. Empty when the run has no `hierarchical` cell.
fn against_section(s: &mut String, run: &BenchRun, workloads: &[(String, Option<Workload>)]) {
    const H: &str = "hierarchical";
    if !run.cells.iter().any(|c| c.method == H) {
        return;
    }
    let others: Vec<&String> = run.methods.iter().filter(|m| *m != H).collect();
    let _ = writeln!(s, "\n## `hierarchical` against each method\n");
    let _ = writeln!(
        s,
        "Each cell: `hierarchical`'s wall time divided by the method's on the same \
         workload; below 1 (bold) `hierarchical` is faster. `(m/w)` after a ratio: \
         the method missed m of the reference's collisions and reported w at a wrong \
         time (in bounce mode, where trajectories diverge after the first \
         difference, `(≠)` instead). Last column: `hierarchical`'s own wall time \
         (marked if its collisions differ from the reference's, a bug).\n"
    );
    let _ = write!(s, "| workload |");
    for me in &others {
        let _ = write!(s, " {} |", method_label(me));
    }
    let _ = writeln!(s, " hierarchical |");
    let _ = write!(s, "| --- |");
    for _ in 0..=others.len() {
        let _ = write!(s, " ---: |");
    }
    s.push('\n');
    for (w, wl) in workloads {
        let bounce = wl
            .as_ref()
            .is_some_and(|w| w.mode() == kss::CollisionMode::Bounce);
        let h = run
            .cell(w, H)
            .filter(|c| c.outcome.status == Status::Ok)
            .map(|c| c.outcome.wall_seconds);
        let _ = write!(s, "| {w} |");
        for me in &others {
            let text = match (run.cell(w, me), h) {
                (Some(c), Some(ht)) if c.outcome.status == Status::Ok => {
                    let r = ht / c.outcome.wall_seconds;
                    let ratio = if r < 1.0 {
                        format!("**{}**", format_ratio(r))
                    } else {
                        format_ratio(r)
                    };
                    let wrong = c.comparison.as_ref().filter(|x| !x.identical);
                    match wrong {
                        Some(_) if bounce => format!("{ratio} (≠)"),
                        Some(x) => format!("{ratio} ({}/{})", x.missed, x.wrong_time),
                        None => ratio,
                    }
                }
                (Some(c), _) if c.outcome.status == Status::Ok => {
                    human_seconds(c.outcome.wall_seconds)
                }
                (Some(c), _) => status_short(c),
                (None, _) => String::new(),
            };
            let _ = write!(s, " {text} |");
        }
        let own = match run.cell(w, H) {
            Some(c) if exact_differs(c) => format!(
                "{} **DIFFERS (bug)**",
                human_seconds(c.outcome.wall_seconds)
            ),
            Some(c) if c.outcome.status == Status::Ok => human_seconds(c.outcome.wall_seconds),
            Some(c) => status_short(c),
            None => String::new(),
        };
        let _ = writeln!(s, " {own} |");
    }
}

/// A duration for people.
pub fn human_seconds(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.0} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

/// A positive quantity with about three significant digits (integers from
/// 100 up).
pub fn format_sig(x: f64) -> String {
    if !x.is_finite() {
        return String::new();
    }
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else if x >= 1.0 || x == 0.0 {
        format!("{x:.2}")
    } else {
        let decimals = (2.0 - x.log10().floor()) as usize;
        format!("{x:.decimals$}")
    }
}

/// Events processed per simulated second of a completed cell.
pub fn events_per_sim_second(o: &CellOutcome) -> Option<f64> {
    (o.status == Status::Ok && o.sim_seconds > 0.0)
        .then(|| o.counters.events as f64 / o.sim_seconds)
}

/// Wall-clock nanoseconds per processed event of a completed cell.
pub fn ns_per_event(o: &CellOutcome) -> Option<f64> {
    (o.status == Status::Ok && o.counters.events > 0)
        .then(|| o.wall_seconds * 1e9 / o.counters.events as f64)
}

/// The peak heap of a completed cell in MiB ([`CellOutcome::peak_heap_bytes`]).
pub fn peak_heap_mib(o: &CellOutcome) -> Option<f64> {
    o.peak_heap_bytes
        .filter(|_| o.status == Status::Ok)
        .map(|b| b as f64 / (1024.0 * 1024.0))
}

/// Allocations per processed event of a completed cell
/// ([`CellOutcome::allocations`]).
pub fn allocations_per_event(o: &CellOutcome) -> Option<f64> {
    o.allocations
        .filter(|_| o.status == Status::Ok && o.counters.events > 0)
        .map(|a| a as f64 / o.counters.events as f64)
}

fn method_label(name: &str) -> String {
    Method::parse(name).map_or_else(|_| name.to_string(), |m| m.label())
}

/// The wall time of the ratio's base for a workload: brute's, else the
/// reference's (marked with `*`).
fn base_time(run: &BenchRun, workload: &str) -> Option<(f64, bool)> {
    let ok = |m: &str| {
        run.cell(workload, m)
            .filter(|c| c.outcome.status == Status::Ok)
            .map(|c| c.outcome.wall_seconds)
    };
    if let Some(t) = ok("brute") {
        return Some((t, false));
    }
    let r = run.references.get(workload)?;
    ok(r).map(|t| (t, true))
}

fn status_short(c: &CellResult) -> String {
    match &c.outcome.status {
        Status::Ok => String::new(),
        Status::NotImplemented => "n/i".into(),
        Status::Unsupported(_) => "unsupported".into(),
        Status::Budget => "over budget".into(),
        Status::SkippedBudget => "skipped (budget)".into(),
        Status::SkippedMemory => "skipped (memory)".into(),
        Status::Error(_) => "error".into(),
    }
}

/// Whether an exact method's events differ from the reference (a bug).
fn exact_differs(c: &CellResult) -> bool {
    Method::parse(&c.method).is_ok_and(|m| m.is_exact())
        && c.comparison.as_ref().is_some_and(|x| !x.identical)
}

fn accuracy_text(c: &CellResult, bounce: bool) -> String {
    match &c.comparison {
        None => String::new(),
        Some(x) if x.identical => "exact".into(),
        Some(x) if bounce => format!("first {} of {} agree", x.agreeing_prefix, x.reference),
        Some(x) => {
            let mut parts = Vec::new();
            if x.missed > 0 {
                parts.push(format!("{} missed", x.missed));
            }
            if x.wrong_time > 0 {
                parts.push(format!("{} wrong time", x.wrong_time));
            }
            if x.extra > 0 {
                parts.push(format!("{} extra", x.extra));
            }
            if parts.is_empty() {
                "within 1e-12".into()
            } else {
                parts.join(", ")
            }
        }
    }
}

/// The Markdown report.
pub fn markdown(run: &BenchRun, m: &Machine) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# kss-bench results\n");
    let _ = writeln!(
        s,
        "Machine: {} ({} logical cores), {:.1} GiB memory, {}; built with {} ({} profile); run on {} UTC.\n",
        m.cpu, m.cores, m.memory_gib, m.os, m.rustc, m.profile, m.date
    );
    let _ = writeln!(
        s,
        "Mode: {}; time budget {} per cell; whole run {}{}. Every method ran on the same \
         machine in this one run; each cell in its own process, one at a time{}.\n",
        if run.quick {
            "quick (tiny workloads; CI checks only that it runs)"
        } else {
            "full"
        },
        human_seconds(run.budget_seconds),
        human_seconds(run.total_seconds),
        match run.resumes {
            0 => String::new(),
            n => format!(
                " (interrupted and resumed {n} time{} with `--resume`, by the same binary on the same machine: \
                 the workloads finished before were kept, the one interrupted ran again \
                 from its first cell)",
                if n == 1 { "" } else { "s" }
            ),
        },
        match run.repeat {
            1 => String::new(),
            n => format!(
                "; each cell {n} times, the methods of a workload taking turns round after \
                 round, reporting its run of median wall time (every run: \
                 [Repeated runs](#repeated-runs))"
            ),
        }
    );
    let methods: Vec<String> = run.methods.clone();
    let workloads: Vec<(String, Option<Workload>)> = run
        .workloads
        .iter()
        .map(|w| (w.clone(), Workload::parse(w).ok()))
        .collect();

    // 1. ratios
    let _ = writeln!(s, "## Wall time relative to brute (lower is faster)\n");
    let _ = writeln!(
        s,
        "Each cell: wall time divided by brute's on the same workload (`*`: by the \
         exact reference's, brute did not finish), then the wall time. `n/i`: not \
         implemented in the library yet.\n"
    );
    let _ = write!(s, "| workload |");
    for me in &methods {
        let _ = write!(s, " {} |", method_label(me));
    }
    let _ = write!(s, "\n| --- |");
    for _ in &methods {
        let _ = write!(s, " ---: |");
    }
    s.push('\n');
    for (w, _) in &workloads {
        let base = base_time(run, w);
        let _ = write!(s, "| {w} |");
        for me in &methods {
            let text = match run.cell(w, me) {
                Some(c) if c.outcome.status == Status::Ok => {
                    let t = c.outcome.wall_seconds;
                    match base {
                        Some((b, star)) if b > 0.0 => format!(
                            "{}{} ({})",
                            format_ratio(t / b),
                            if star { "*" } else { "" },
                            human_seconds(t)
                        ),
                        _ => human_seconds(t),
                    }
                }
                Some(c) => status_short(c),
                None => String::new(),
            };
            let _ = write!(s, " {text} |");
        }
        s.push('\n');
    }

    // 1b. the library's default structure against each method
    against_section(&mut s, run, &workloads);

    // 2. accuracy
    let _ = writeln!(s, "\n## Collisions found against the exact reference\n");
    let _ = writeln!(
        s,
        "`exact`: the same events as the reference (brute, or the first exact method \
         that finished), times within the contract's 1e-12. Otherwise the counts of \
         reference collisions missed, reported at a wrong time (relative error above \
         1e-12) and reported but not in the reference. In bounce mode (gas) \
         trajectories diverge after the first difference, so the count of leading \
         events that agree is shown instead.\n"
    );
    let _ = write!(s, "| workload | reference collisions |");
    for me in &methods {
        let _ = write!(s, " {} |", method_label(me));
    }
    let _ = write!(s, "\n| --- | ---: |");
    for _ in &methods {
        let _ = write!(s, " --- |");
    }
    s.push('\n');
    for (w, wl) in &workloads {
        let bounce = wl
            .as_ref()
            .is_some_and(|w| w.mode() == kss::CollisionMode::Bounce);
        let refc = run
            .references
            .get(w)
            .and_then(|r| run.cell(w, r))
            .map_or("—".to_string(), |c| {
                c.outcome.counters.collisions.to_string()
            });
        let _ = write!(s, "| {w} | {refc} |");
        for me in &methods {
            let text = run.cell(w, me).map_or(String::new(), |c| {
                if exact_differs(c) {
                    format!("**DIFFERS (bug)**: {}", accuracy_text(c, false))
                } else if c.outcome.status == Status::Ok {
                    accuracy_text(c, bounce)
                } else {
                    status_short(c)
                }
            });
            let _ = write!(s, " {text} |");
        }
        s.push('\n');
    }

    // 3. the cost per event of the issue's workloads, then the events of
    // the exact methods
    cost_section(&mut s, run, &workloads);
    events_section(&mut s, run, &workloads);
    flypast_section(&mut s, run, &workloads);

    // 4. every cell
    let _ = writeln!(s, "\n## Every cell\n");
    let _ = writeln!(
        s,
        "`events`: certificate failures, collisions and flight-plan changes \
         processed (fixed step: steps and TOI sub-steps); `certificates`: largest \
         number scheduled at once (pair times, swap certificates); `pair tests`: \
         narrow-phase time-of-impact computations (not reported by the library's \
         structures); `peak RSS`: the largest resident memory of the cell's process \
         while the method ran, the scene itself included (reset after building the \
         scene, read from `VmHWM`); `peak heap`: the largest number of live heap bytes \
         the method added over those live when it started (the scene excluded; \
         counted by `kss-bench`'s allocator, independent of the binary's layout); \
         `allocs / event`: allocations (including reallocations) per event; `sim time`: the simulated time covered (the \
         scenario's `until`, or the first collision in `stop` mode); `events / sim s` \
         and `ns / event`: events per simulated second, and wall time per event.\n"
    );
    let _ = writeln!(
        s,
        "| workload | method | status | wall | setup | collisions | events | certificates | pair tests | peak RSS (MiB) | peak heap (MiB) | allocs / event | sim time | events / sim s | ns / event |"
    );
    let _ = writeln!(
        s,
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for (w, _) in &workloads {
        for me in &methods {
            let Some(c) = run.cell(w, me) else { continue };
            let o = &c.outcome;
            let ok = o.status == Status::Ok;
            let num = |x: u64| if ok { x.to_string() } else { String::new() };
            let _ = writeln!(
                s,
                "| {w} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                method_label(me),
                o.status.text(),
                if ok {
                    human_seconds(o.wall_seconds)
                } else if o.status == Status::Budget {
                    format!("> {}", human_seconds(run.budget_seconds))
                } else {
                    String::new()
                },
                if ok {
                    human_seconds(o.setup_seconds)
                } else {
                    String::new()
                },
                num(o.counters.collisions),
                num(o.counters.events),
                num(o.counters.certificates_max),
                if ok && o.counters.pair_tests > 0 {
                    o.counters.pair_tests.to_string()
                } else {
                    String::new()
                },
                o.peak_rss_kib
                    .filter(|_| ok)
                    .map_or(String::new(), |k| format!("{:.1}", k as f64 / 1024.0)),
                peak_heap_mib(o).map_or(String::new(), |m| format!("{m:.1}")),
                allocations_per_event(o).map_or(String::new(), |x| format!("{x:.1}")),
                if ok && o.sim_seconds > 0.0 {
                    format_sig(o.sim_seconds)
                } else {
                    String::new()
                },
                events_per_sim_second(o).map_or(String::new(), format_sig),
                ns_per_event(o).map_or(String::new(), |x| format!("{x:.0}")),
            );
        }
    }
    repeated_section(&mut s, run);
    let _ = writeln!(s, "\n## Workloads and methods\n");
    let _ = writeln!(
        s,
        "- flypast-n<N>-r<R>: two regular N-gons of diameter D = 1, one passing the \
         other at the gap s = D/R (a near miss: no collision), `stop` mode.\n\
         - gas-k<K>-n<N>-c<C>: K random convex N-gons in a box of four fixed walls, \
         random velocities, `bounce` mode, simulated long enough for about C collisions.\n\
         - cluster-k<K>: K octagons on a unit grid, gaps down to 1/1000 of their size, \
         slow random velocities, `remove` mode.\n\
         - swarm-k<K>: K octagons spread 64 times wider than the gas, `remove` mode.\n\
         - grazing-p<P>, parallel-p<P>, far-k<K> (beyond the issue's list): P pairs with \
         tangential grazing contacts, P pairs touching flush while moving parallel to \
         edges, a gas of K octagons around coordinates 10^6; `remove` mode.\n\
         - walls-k<K>-n<N>-bounce / -remove: K regular N-gons of circumradius 0.4 in a \
         box of walls (`kss gen swarm`), velocities in [-1, 1]², simulated long enough \
         for about 12 collisions per polygon in `bounce` mode (the same motions and \
         `until` in `remove` mode).\n\
         - gasmix-k<K>-n<MIN>to<MAX>: K random convex polygons of MIN to MAX vertices \
         in a box of walls, `remove` mode, until 10 (`kss gen gas --walls --mode remove`).\n\
         - brute / plain / hierarchical: the kss library (`kss::run`); sweep: kinetic \
         sort-and-sweep of bounding-box endpoints with exact swap times and the \
         library's exact pair times; parry-toi: parry2d-f64 `cast_shapes` for all \
         pairs, event-driven; parry-step dt=1/N: fixed time step with swept-box sort \
         and sweep and `cast_shapes` per candidate pair, up to 8 TOI sub-steps per step; dt is in \
         the workload's time unit (in which polygons move about their own size: 1, \
         and 1024 for far).\n\
         - Wall time is the method's run on a built scene: for the kss library and \
         sweep it includes building the exact world (with the contract's validation that \
         no two polygons touch at time 0); the parry baselines build their own \
         floating-point scene and validate nothing.\n\
         - Plots: `*.svg` beside this file."
    );
    s
}

/// The wall time of every run of the cells run more than once
/// ([`crate::harness::Config::repeat`]): the median reported, the fastest
/// and slowest, and each run in the order they ran. Nothing when no cell
/// ran twice.
fn repeated_section(s: &mut String, run: &BenchRun) {
    let cells: Vec<&CellResult> = run
        .cells
        .iter()
        .filter(|c| c.outcome.wall_runs.len() > 1)
        .collect();
    if cells.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n## Repeated runs\n");
    let _ = writeln!(
        s,
        "The wall time of each run of a cell, in the order they ran; a cell reports \
         its run of median wall time (the lower middle one of an even count).\n"
    );
    let _ = writeln!(
        s,
        "| workload | method | median | fastest | slowest | runs |\n| --- | --- | ---: | ---: | ---: | --- |"
    );
    for c in cells {
        let runs = &c.outcome.wall_runs;
        let lo = runs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = runs.iter().copied().fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            c.workload,
            method_label(&c.method),
            human_seconds(c.outcome.wall_seconds),
            human_seconds(lo),
            human_seconds(hi),
            runs.iter()
                .map(|&w| human_seconds(w))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
}

/// The size a workload's series grows with, and its letter (`n` for
/// flypast, `k` for the polygon counts, `p` for pairs).
fn size_of(w: &Workload) -> (f64, &'static str) {
    let (_, size) = w.series();
    let letter = match w {
        Workload::Flypast { .. } => "n",
        Workload::Grazing { .. } | Workload::Parallel { .. } => "p",
        _ => "k",
    };
    (size, letter)
}

/// Per family, for the exact methods that completed a cell of it: events,
/// events per unit of size, events per simulated second, certificates (the
/// largest number scheduled at once) and wall time per event, and the wall
/// time against brute's.
fn events_section(s: &mut String, run: &BenchRun, workloads: &[(String, Option<Workload>)]) {
    let mut families: Vec<&'static str> = Vec::new();
    for w in workloads.iter().filter_map(|(_, w)| w.as_ref()) {
        if !families.contains(&w.family()) {
            families.push(w.family());
        }
    }
    let ok = |w: &str, me: &str| {
        run.cell(w, me)
            .filter(|c| c.outcome.status == Status::Ok)
            .map(|c| &c.outcome)
    };
    let mut header = false;
    for family in families {
        let rows: Vec<(&String, &Workload)> = workloads
            .iter()
            .filter_map(|(name, w)| w.as_ref().map(|w| (name, w)))
            .filter(|(_, w)| w.family() == family)
            .collect();
        let methods: Vec<&String> = run
            .methods
            .iter()
            .filter(|me| Method::parse(me).is_ok_and(|m| m.is_exact()))
            .filter(|me| rows.iter().any(|(w, _)| ok(w, me).is_some()))
            .collect();
        if methods.is_empty() {
            continue;
        }
        if !header {
            header = true;
            let _ = writeln!(s, "\n## Events, certificates and time per event\n");
            let _ = writeln!(
                s,
                "The exact methods only. `events`: what the method processed (the kinetic \
                 structures: every certificate failure, collision and flight-plan change; \
                 brute: only its collisions and flight-plan changes, which in `bounce` \
                 mode include the end of each bounced body's short bridge, while its \
                 pair-time computations are not events; sweep: swaps of box endpoints \
                 too); \
                 `/n`, `/k`, `/p`: per vertex of one polygon, per polygon, per pair; \
                 `per sim s`: per simulated second; `certs`: the largest number of \
                 certificates scheduled at once (brute: pair times queued); `ns/ev`: \
                 wall time per event; `× brute`: wall time over brute's. Blank: the \
                 cell did not complete (see the tables around).\n"
            );
        }
        let letter = rows.first().map_or("k", |(_, w)| size_of(w).1);
        let _ = writeln!(s, "### {family}\n");
        let _ = write!(s, "| workload |");
        let mut align = String::from("| --- |");
        for me in &methods {
            let l = method_label(me);
            let _ = write!(
                s,
                " {l} events | {l} /{letter} | {l} per sim s | {l} certs | {l} ns/ev |"
            );
            align.push_str(" ---: | ---: | ---: | ---: | ---: |");
            if me.as_str() != "brute" && run.methods.iter().any(|m| m == "brute") {
                let _ = write!(s, " {l} × brute |");
                align.push_str(" ---: |");
            }
        }
        let _ = writeln!(s, "\n{align}");
        for (w, wl) in &rows {
            let (size, _) = size_of(wl);
            let _ = write!(s, "| {w} |");
            let brute = ok(w, "brute");
            for me in &methods {
                match ok(w, me) {
                    Some(o) => {
                        let _ = write!(
                            s,
                            " {} | {} | {} | {} | {} |",
                            o.counters.events,
                            format_sig(o.counters.events as f64 / size),
                            events_per_sim_second(o).map_or(String::new(), format_sig),
                            o.counters.certificates_max,
                            ns_per_event(o).map_or(String::new(), |x| format!("{x:.0}")),
                        );
                    }
                    None => {
                        let text = run.cell(w, me).map_or(String::new(), status_short);
                        let _ = write!(s, " {text} | | | | |");
                    }
                }
                if me.as_str() != "brute" && run.methods.iter().any(|m| m == "brute") {
                    let ratio = match (ok(w, me), brute) {
                        (Some(o), Some(b)) if b.wall_seconds > 0.0 => {
                            format_ratio(o.wall_seconds / b.wall_seconds)
                        }
                        _ => String::new(),
                    };
                    let _ = write!(s, " {ratio} |");
                }
            }
            s.push('\n');
        }
        s.push('\n');
    }
}

/// Whether a workload belongs in the cost-per-event section: one of the
/// `perf` set (which holds the `cost` set) or of the families made for it
/// (`walls`, `gasmix`), at any size.
fn is_cost_workload(w: &Workload) -> bool {
    matches!(w, Workload::Walls { .. } | Workload::GasMix { .. })
        || Workload::set("perf").is_some_and(|set| set.contains(w))
}

/// Microseconds with three significant digits, or `—` when there is
/// nothing to divide by.
fn micros_per(wall_seconds: f64, count: u64) -> String {
    if count == 0 {
        "—".into()
    } else {
        format_sig(wall_seconds * 1e6 / count as f64)
    }
}

/// The cost per event and per collision of every method, side by side, on
/// the workloads of the `cost` and `perf` sets (and the small `walls` and
/// `gasmix` ones of a quick run): wall time, events, collisions, events per
/// collision, µs per event and per collision. Empty when the run has none
/// of them.
fn cost_section(s: &mut String, run: &BenchRun, workloads: &[(String, Option<Workload>)]) {
    let rows: Vec<&String> = workloads
        .iter()
        .filter(|(_, w)| w.as_ref().is_some_and(is_cost_workload))
        .map(|(name, _)| name)
        .filter(|name| run.methods.iter().any(|me| run.cell(name, me).is_some()))
        .collect();
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n## Cost per event\n");
    let _ = writeln!(
        s,
        "Every method on the workloads of the cost per event, side by side. `wall`: \
         the whole run of the method on the built scene (for the kss library and sweep, \
         building the exact world and the structure included); `events` is what each \
         method counts as one, so `µs / event` compares like with like only between \
         the kinetic structures: \
         `plain` / `hierarchical`: every certificate failure (the hierarchy's pops \
         and merges included), collision and flight-plan change the structure \
         processed (`kss run --stats`' `events_processed`); \
         `brute`: only collisions and flight-plan changes (and in `bounce` mode the \
         end of each bounced body's short bridge), its pair-time computations are \
         not events; \
         `sweep`: swaps of bounding-box endpoints, collisions and flight-plan changes; \
         `parry-toi`: collisions and flight-plan changes only (its time-of-impact \
         queries are not counted as events), so its `events / collision` is about 1; \
         `parry-step`: time steps and time-of-impact sub-steps. \
         `µs / collision` (wall over collisions) compares every method. `—`: \
         nothing counted to divide by. A method that did not complete shows its \
         status.\n"
    );
    let _ = writeln!(
        s,
        "| workload | method | wall | events | collisions | events / collision | µs / event | µs / collision |"
    );
    let _ = writeln!(s, "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    for w in rows {
        for me in &run.methods {
            let Some(c) = run.cell(w, me) else { continue };
            let o = &c.outcome;
            let label = method_label(me);
            if o.status != Status::Ok {
                let status = if o.status == Status::Budget {
                    format!("> {}", human_seconds(run.budget_seconds))
                } else {
                    status_short(c)
                };
                let _ = writeln!(s, "| {w} | {label} | {status} | | | | | |");
                continue;
            }
            let (events, collisions) = (o.counters.events, o.counters.collisions);
            let per_collision = if collisions == 0 || events == 0 {
                "—".to_string()
            } else {
                format_sig(events as f64 / collisions as f64)
            };
            let _ = writeln!(
                s,
                "| {w} | {label} | {} | {} | {collisions} | {per_collision} | {} | {} |",
                human_seconds(o.wall_seconds),
                if events == 0 {
                    "—".to_string()
                } else {
                    events.to_string()
                },
                micros_per(o.wall_seconds, events),
                micros_per(o.wall_seconds, collisions),
            );
        }
    }
}

/// Whether `method` is one of the library's structures (through `kss::run`).
fn is_library(method: &str) -> bool {
    Method::parse(method).is_ok_and(|m| m.is_library())
}

/// `mean (min–max)` of integers, or the value if all are equal.
fn mean_range(v: &[u64]) -> String {
    let (lo, hi) = (v.iter().min(), v.iter().max());
    match (lo, hi) {
        (Some(lo), Some(hi)) if lo == hi => lo.to_string(),
        (Some(lo), Some(hi)) => {
            let mean = v.iter().sum::<u64>() as f64 / v.len() as f64;
            format!("{} ({lo}–{hi})", format_sig(mean))
        }
        _ => String::new(),
    }
}

/// The flypast cells of the library's structures: events, the hierarchy's
/// pops, collisions, certificates, wall and construction time, time per
/// event, the other event kinds; and with several seeds, their summary.
fn flypast_section(s: &mut String, run: &BenchRun, workloads: &[(String, Option<Workload>)]) {
    let mut rows: Vec<(&String, usize, f64, u64)> = workloads
        .iter()
        .filter_map(|(name, w)| match w {
            Some(Workload::Flypast { n, ratio, seed }) => Some((name, *n, *ratio, *seed)),
            _ => None,
        })
        .collect();
    let methods: Vec<&String> = run.methods.iter().filter(|m| is_library(m)).collect();
    if rows.is_empty() || methods.is_empty() {
        return;
    }
    rows.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.1.cmp(&b.1)).then(a.3.cmp(&b.3)));
    let _ = writeln!(s, "\n## Flypast: events, pops and construction\n");
    let _ = writeln!(
        s,
        "The library's structures on the flypast (two regular n-gons of diameter \
         D = 1 passing at gap s = D/R; no collision). `events`: `events_processed` of \
         `kss run --stats` (every certificate failure, pop, collision and flight-plan \
         change); `pops`: the hierarchy's refined approximation vertices (`pop` while \
         running plus `initial_pop` before the start; part of `events`); `certs`: \
         `certificates_max`; `wall`: the whole run (world with validation, \
         construction, events, freeing the structure); `build`: with `--build-time`, \
         a separate run of the same structure up to the smallest positive double \
         (world, validation, structure and certificates, no events); `ns/ev`: wall / \
         events; `ns/ev after build`: the wall time of the run's events (timed inside \
         the run, from the end of its construction to the end of its last event; \
         freeing the structure afterwards is not in it) over events; for runs \
         recorded without that time, the run's wall time less its own construction, \
         or else (wall − build), over events, `—` where the run was not slower than \
         the separate construction; `other kinds`: the rest of `events_by_kind`.\n"
    );
    let _ = writeln!(
        s,
        "| n | D/s | seed | method | status | events | pops | collisions | certs | wall | build | ns/ev | ns/ev after build | other kinds |"
    );
    let _ = writeln!(
        s,
        "| ---: | ---: | ---: | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"
    );
    for &(w, n, ratio, seed) in &rows {
        for me in &methods {
            let Some(c) = run.cell(w, me) else { continue };
            let o = &c.outcome;
            let build = o.build_seconds.map_or(String::new(), human_seconds);
            if o.status != Status::Ok {
                let status = if o.status == Status::Budget {
                    format!("over budget (> {})", human_seconds(run.budget_seconds))
                } else {
                    o.status.text()
                };
                let _ = writeln!(
                    s,
                    "| {n} | {ratio:e} | {seed} | {} | {status} | | | | | | {build} | | | |",
                    method_label(me)
                );
                continue;
            }
            let k = &o.counters;
            let after = match o.build_seconds {
                _ if k.build_seconds.is_some() => k
                    .ns_per_event_after_build(o.wall_seconds)
                    .map_or(String::new(), |ns| format!("{ns:.0}")),
                Some(b) if k.events > 0 && o.wall_seconds > b => {
                    format!("{:.0}", (o.wall_seconds - b) * 1e9 / k.events as f64)
                }
                Some(_) if k.events > 0 => "—".into(),
                _ => String::new(),
            };
            let others: Vec<String> = k
                .events_by_kind
                .iter()
                .filter(|(kind, v)| {
                    **v > 0
                        && !matches!(
                            kind.as_str(),
                            "pop" | "initial_pop" | "collision" | "flight_plan_change"
                        )
                })
                .map(|(kind, v)| format!("{kind} {v}"))
                .collect();
            let _ = writeln!(
                s,
                "| {n} | {ratio:e} | {seed} | {} | ok | {} | {} | {} | {} | {} | {build} | {} | {after} | {} |",
                method_label(me),
                k.events,
                k.pops(),
                k.collisions,
                k.certificates_max,
                human_seconds(o.wall_seconds),
                ns_per_event(o).map_or(String::new(), |x| format!("{x:.0}")),
                others.join(", "),
            );
        }
    }
    flypast_fits(s, run, &rows, &methods);
    // several seeds at one (n, D/s): their summary
    let mut keys: Vec<(usize, f64)> = rows.iter().map(|r| (r.1, r.2)).collect();
    keys.dedup();
    let seeded = keys
        .iter()
        .any(|k| rows.iter().filter(|r| (r.1, r.2) == *k).count() > 1);
    if !seeded {
        return;
    }
    let _ = writeln!(s, "\n### Flypast over seeds\n");
    let _ = writeln!(
        s,
        "Per n and D/s, the completed runs over the seeds: mean (min–max) of events \
         and pops, mean wall and construction time.\n"
    );
    let _ = writeln!(
        s,
        "| n | D/s | method | seeds completed | events | pops | certs | wall | build |"
    );
    let _ = writeln!(
        s,
        "| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for &(n, ratio) in &keys {
        let names: Vec<&String> = rows
            .iter()
            .filter(|r| (r.1, r.2) == (n, ratio))
            .map(|r| r.0)
            .collect();
        for me in &methods {
            let done: Vec<&CellOutcome> = names
                .iter()
                .filter_map(|w| run.cell(w, me))
                .map(|c| &c.outcome)
                .filter(|o| o.status == Status::Ok)
                .collect();
            let mean = |f: &dyn Fn(&CellOutcome) -> Option<f64>| {
                let v: Vec<f64> = done.iter().filter_map(|o| f(o)).collect();
                if v.is_empty() {
                    String::new()
                } else {
                    human_seconds(v.iter().sum::<f64>() / v.len() as f64)
                }
            };
            let ints = |f: &dyn Fn(&CellOutcome) -> u64| {
                mean_range(&done.iter().map(|o| f(o)).collect::<Vec<_>>())
            };
            let _ = writeln!(
                s,
                "| {n} | {ratio:e} | {} | {} of {} | {} | {} | {} | {} | {} |",
                method_label(me),
                done.len(),
                names.len(),
                ints(&|o| o.counters.events),
                ints(&|o| o.counters.pops()),
                ints(&|o| o.counters.certificates_max),
                mean(&|o| Some(o.wall_seconds)),
                mean(&|o| o.build_seconds),
            );
        }
    }
}

/// Least-squares line `y = a + b·x` through `points`: `(a, b, R²)`.
pub fn fit_line(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let m = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / m;
    let my = points.iter().map(|p| p.1).sum::<f64>() / m;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = points.iter().map(|p| (p.1 - my) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let b = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Some((my - b * mx, b, r2))
}

/// Per n with at least three ratios, per method: the line through events
/// (and pops) against log2(D/s), every completed seed a point.
fn flypast_fits(
    s: &mut String,
    run: &BenchRun,
    rows: &[(&String, usize, f64, u64)],
    methods: &[&String],
) {
    let mut ns: Vec<usize> = rows.iter().map(|r| r.1).collect();
    ns.sort_unstable();
    ns.dedup();
    let mut lines = Vec::new();
    for n in ns {
        let mut ratios: Vec<f64> = rows.iter().filter(|r| r.1 == n).map(|r| r.2).collect();
        ratios.sort_by(f64::total_cmp);
        ratios.dedup();
        if ratios.len() < 3 {
            continue;
        }
        for me in methods {
            let done: Vec<(f64, &CellOutcome)> = rows
                .iter()
                .filter(|r| r.1 == n)
                .filter_map(|r| run.cell(r.0, me).map(|c| (r.2, &c.outcome)))
                .filter(|(_, o)| o.status == Status::Ok)
                .collect();
            let pts = |f: &dyn Fn(&CellOutcome) -> u64| -> Vec<(f64, f64)> {
                done.iter().map(|(r, o)| (r.log2(), f(o) as f64)).collect()
            };
            let ev = fit_line(&pts(&|o| o.counters.events));
            let pop_points = pts(&|o| o.counters.pops());
            let po = if pop_points.iter().any(|p| p.1 > 0.0) {
                fit_line(&pop_points)
            } else {
                None
            };
            if let Some((a, b, r2)) = ev {
                let pops = po.map_or(String::new(), |(a, b, r2)| {
                    format!("{} (R² {r2:.3})", format_affine(a, b))
                });
                let mut used: Vec<f64> = done.iter().map(|(r, _)| *r).collect();
                used.sort_by(f64::total_cmp);
                used.dedup();
                lines.push(format!(
                    "| {n} | {} | {} | {} | {} (R² {r2:.3}) | {pops} |",
                    method_label(me),
                    used.len(),
                    done.len(),
                    format_affine(a, b),
                ));
            }
        }
    }
    if lines.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n### Flypast: events against log2(D/s)\n");
    let _ = writeln!(
        s,
        "Least-squares lines through every completed run (each seed a point) at one \
         n, over the D/s of the run.\n"
    );
    let _ = writeln!(s, "| n | method | D/s values | runs | events | pops |");
    let _ = writeln!(s, "| ---: | --- | ---: | ---: | --- | --- |");
    for l in lines {
        let _ = writeln!(s, "{l}");
    }
}

/// `a + b·log2(D/s)` with three significant digits.
fn format_affine(a: f64, b: f64) -> String {
    let a = if a < 0.0 {
        format!("−{}", format_sig(-a))
    } else {
        format_sig(a)
    };
    let (sign, b) = if b < 0.0 { ("−", -b) } else { ("+", b) };
    format!("{a} {sign} {}·log2(D/s)", format_sig(b))
}

/// One line of a plot.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` points, both positive (joined by the line; with several
    /// runs at one `x`, their mean).
    pub points: Vec<(f64, f64)>,
    /// Individual runs (e.g. one per seed) drawn as small open circles in
    /// the line's colour; empty if every `x` has one run.
    pub scatter: Vec<(f64, f64)>,
    /// Draw the line dashed (a secondary quantity of the same method).
    pub dashed: bool,
    /// Index of the colour (default: the series' position).
    pub colour: Option<usize>,
}

impl Series {
    /// A series from `(x, y)` samples: the line through the mean `y` at each
    /// `x`, and the samples themselves as [`Series::scatter`] when some `x`
    /// has more than one.
    pub fn from_samples(label: String, samples: &[(f64, f64)]) -> Series {
        let mut xs: Vec<f64> = samples.iter().map(|p| p.0).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        let points = xs
            .iter()
            .map(|&x| {
                let ys: Vec<f64> = samples.iter().filter(|p| p.0 == x).map(|p| p.1).collect();
                (x, ys.iter().sum::<f64>() / ys.len() as f64)
            })
            .collect();
        Series {
            label,
            points,
            scatter: if xs.len() < samples.len() {
                samples.to_vec()
            } else {
                Vec::new()
            },
            dashed: false,
            colour: None,
        }
    }
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

const COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf",
    "#7f7f7f", "#bcbd22",
];

/// A log-log line plot as an SVG document.
pub fn loglog_plot(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> String {
    let (w, h) = (760.0, 460.0);
    let (left, right, top, bottom) = (80.0, 210.0, 40.0, 55.0);
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter().chain(&s.scatter))
        .copied();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for (x, y) in pts.filter(|p| p.0 > 0.0 && p.1 > 0.0) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (1.0, 10.0, 1.0, 10.0);
    }
    let (lx0, mut lx1) = (x0.log10().floor(), x1.log10().ceil());
    let (ly0, mut ly1) = (y0.log10().floor(), y1.log10().ceil());
    if lx1 <= lx0 {
        lx1 = lx0 + 1.0;
    }
    if ly1 <= ly0 {
        ly1 = ly0 + 1.0;
    }
    let pw = w - left - right;
    let ph = h - top - bottom;
    let px = |x: f64| left + (x.log10() - lx0) / (lx1 - lx0) * pw;
    let py = |y: f64| top + ph - (y.log10() - ly0) / (ly1 - ly0) * ph;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" font-size="15" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        xml(title)
    );
    // grid and ticks at powers of ten
    let mut e = lx0;
    while e <= lx1 + 1e-9 {
        let x = px(10f64.powf(e));
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">1e{}</text>"##,
            top + ph,
            top + ph + 16.0,
            e as i64
        );
        e += 1.0;
    }
    let mut e = ly0;
    while e <= ly1 + 1e-9 {
        let y = py(10f64.powf(e));
        let _ = writeln!(
            s,
            r##"<line x1="{left}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">1e{}</text>"##,
            left + pw,
            left - 6.0,
            y + 4.0,
            e as i64
        );
        e += 1.0;
    }
    let _ = writeln!(
        s,
        r#"<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="black"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        h - 12.0,
        xml(x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        top + ph / 2.0,
        xml(y_label)
    );
    for (i, se) in series.iter().enumerate() {
        let c = COLOURS[se.colour.unwrap_or(i) % COLOURS.len()];
        let mut p: Vec<(f64, f64)> = se
            .points
            .iter()
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect();
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        let dash = if se.dashed {
            r#" stroke-dasharray="6 4""#
        } else {
            ""
        };
        if p.len() > 1 {
            let path: Vec<String> = p
                .iter()
                .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="2"{dash}/>"#,
                path.join(" ")
            );
        }
        for &(x, y) in se.scatter.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0) {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="none" stroke="{c}"/>"#,
                px(x),
                py(y)
            );
        }
        for &(x, y) in &p {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{c}"/>"#,
                px(x),
                py(y)
            );
        }
        let ly = top + 10.0 + 20.0 * i as f64;
        let lx = left + pw + 14.0;
        let _ = writeln!(
            s,
            r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{c}" stroke-width="2"{dash}/><text x="{}" y="{}">{}</text>"#,
            lx + 22.0,
            lx + 28.0,
            ly + 4.0,
            xml(&se.label)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// Wall-time series over the workloads selected by `pick` (which returns
/// the x value), one per method that finished at least one of them.
fn time_series(run: &BenchRun, pick: &dyn Fn(&Workload) -> Option<f64>) -> Vec<Series> {
    value_series(run, pick, &|o| Some(o.wall_seconds.max(1e-7)))
}

/// Series of `value` (positive, or the point is left out) over the
/// workloads selected by `pick`, one per method with at least one point.
fn value_series(
    run: &BenchRun,
    pick: &dyn Fn(&Workload) -> Option<f64>,
    value: &dyn Fn(&CellOutcome) -> Option<f64>,
) -> Vec<Series> {
    run.methods
        .iter()
        .filter_map(|me| method_series(run, me, pick, value))
        .collect()
}

/// The series of [`value_series`] for one method, if it has a point.
fn method_series(
    run: &BenchRun,
    method: &str,
    pick: &dyn Fn(&Workload) -> Option<f64>,
    value: &dyn Fn(&CellOutcome) -> Option<f64>,
) -> Option<Series> {
    let points: Vec<(f64, f64)> = run
        .workloads
        .iter()
        .filter_map(|w| {
            let x = pick(&Workload::parse(w).ok()?)?;
            let c = run.cell(w, method)?;
            if c.outcome.status != Status::Ok {
                return None;
            }
            value(&c.outcome).filter(|y| *y > 0.0).map(|y| (x, y))
        })
        .collect();
    (!points.is_empty()).then(|| Series::from_samples(method_label(method), &points))
}

/// Events against the workloads selected by `pick`, one series per method,
/// and dashed in the same colour the pops of the methods that have some.
fn events_and_pops(run: &BenchRun, pick: &dyn Fn(&Workload) -> Option<f64>) -> Vec<Series> {
    let mut series = value_series(run, pick, &|o| Some(o.counters.events as f64));
    for s in &mut series {
        s.label = format!("{} events", s.label);
    }
    for me in &run.methods {
        let pops = |o: &CellOutcome| Some(o.counters.pops() as f64);
        if let Some(mut p) = method_series(run, me, pick, &pops) {
            let label = format!("{} events", p.label);
            p.colour = series.iter().position(|s| s.label == label);
            p.label = format!("{} pops", p.label);
            p.dashed = true;
            series.push(p);
        }
    }
    series
}

/// The plots of a run: `(file name, SVG)`.
pub fn plots(run: &BenchRun) -> Vec<(String, String)> {
    let parsed: Vec<Workload> = run
        .workloads
        .iter()
        .filter_map(|w| Workload::parse(w).ok())
        .collect();
    let mut out = Vec::new();
    let flypasts: Vec<(usize, f64)> = parsed
        .iter()
        .filter_map(|w| match w {
            Workload::Flypast { n, ratio, .. } => Some((*n, *ratio)),
            _ => None,
        })
        .collect();
    // the sweep over n: at the D/s with the most sizes (ties: the largest)
    let count = |f: &dyn Fn(&(usize, f64)) -> bool, key: &dyn Fn(&(usize, f64)) -> u64| {
        let mut v: Vec<u64> = flypasts.iter().filter(|p| f(p)).map(key).collect();
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    let r_sweep = flypasts.iter().map(|p| p.1).max_by(|&a, &b| {
        let ca = count(&|p| p.1 == a, &|p| p.0 as u64);
        let cb = count(&|p| p.1 == b, &|p| p.0 as u64);
        ca.cmp(&cb).then(a.total_cmp(&b))
    });
    if let Some(r) = r_sweep {
        let pick = |w: &Workload| match w {
            Workload::Flypast { n, ratio, .. } if *ratio == r => Some(*n as f64),
            _ => None,
        };
        let series = time_series(run, &pick);
        out.push((
            "flypast-time-vs-n.svg".into(),
            loglog_plot(
                &format!("flypast, D/s = {r:e}: wall time against n"),
                "vertices per polygon n",
                "wall time (s)",
                &series,
            ),
        ));
        let series = events_and_pops(run, &pick);
        if !series.is_empty() {
            out.push((
                "flypast-events-vs-n.svg".into(),
                loglog_plot(
                    &format!("flypast, D/s = {r:e}: events processed against n"),
                    "vertices per polygon n",
                    "events",
                    &series,
                ),
            ));
        }
        let series = value_series(run, &pick, &|o| o.build_seconds);
        if !series.is_empty() {
            out.push((
                "flypast-build-vs-n.svg".into(),
                loglog_plot(
                    &format!("flypast, D/s = {r:e}: construction time against n"),
                    "vertices per polygon n",
                    "construction (s)",
                    &series,
                ),
            ));
        }
    }
    // the sweep over D/s: at the n with the most ratios (ties: nearest 1024)
    let dist = |n: usize| (n as f64 / 1024.0).log2().abs();
    let n_sweep = flypasts.iter().map(|p| p.0).min_by(|&a, &b| {
        let ca = count(&|p| p.0 == a, &|p| p.1.to_bits());
        let cb = count(&|p| p.0 == b, &|p| p.1.to_bits());
        cb.cmp(&ca).then(dist(a).total_cmp(&dist(b)))
    });
    if let Some(n0) = n_sweep {
        let pick = |w: &Workload| match w {
            Workload::Flypast { n, ratio, .. } if *n == n0 => Some(*ratio),
            _ => None,
        };
        let series = time_series(run, &pick);
        out.push((
            "flypast-time-vs-gap.svg".into(),
            loglog_plot(
                &format!("flypast, n = {n0}: wall time against D/s"),
                "D/s (diameter over gap)",
                "wall time (s)",
                &series,
            ),
        ));
        let mut ns: Vec<usize> = flypasts.iter().map(|p| p.0).collect();
        ns.sort_unstable();
        ns.dedup();
        ns.retain(|&n| count(&|p| p.0 == n, &|p| p.1.to_bits()) >= 3);
        if ns.len() >= 2 {
            // colour by n; the first method solid, the others dashed
            let mut series = Vec::new();
            for (m, me) in run.methods.iter().enumerate() {
                for (i, &n0) in ns.iter().enumerate() {
                    let pick = |w: &Workload| match w {
                        Workload::Flypast { n, ratio, .. } if *n == n0 => Some(*ratio),
                        _ => None,
                    };
                    let events = |o: &CellOutcome| Some(o.counters.events as f64);
                    if let Some(mut se) = method_series(run, me, &pick, &events) {
                        if se.points.len() < 3 {
                            continue;
                        }
                        se.label = format!("{} n = {n0}", se.label);
                        se.colour = Some(i);
                        se.dashed = m > 0;
                        series.push(se);
                    }
                }
            }
            out.push((
                "flypast-events-vs-gap-by-n.svg".into(),
                loglog_plot(
                    "flypast: events processed against D/s, per n",
                    "D/s (diameter over gap)",
                    "events",
                    &series,
                ),
            ));
        }
        let series = events_and_pops(run, &pick);
        if !series.is_empty() {
            out.push((
                "flypast-events-vs-gap.svg".into(),
                loglog_plot(
                    &format!("flypast, n = {n0}: events processed against D/s"),
                    "D/s (diameter over gap)",
                    "events",
                    &series,
                ),
            ));
        }
        // with sweeps over D/s at several n: each one on its own too
        for &n1 in ns.iter().filter(|_| ns.len() >= 2) {
            let pick = |w: &Workload| match w {
                Workload::Flypast { n, ratio, .. } if *n == n1 => Some(*ratio),
                _ => None,
            };
            let series = events_and_pops(run, &pick);
            if !series.is_empty() {
                out.push((
                    format!("flypast-events-vs-gap-n{n1}.svg"),
                    loglog_plot(
                        &format!("flypast, n = {n1}: events processed against D/s"),
                        "D/s (diameter over gap)",
                        "events",
                        &series,
                    ),
                ));
            }
        }
    }
    let gas_n: Option<usize> = parsed
        .iter()
        .filter_map(|w| match w {
            Workload::Gas { n, .. } => Some(*n),
            _ => None,
        })
        .min();
    if let Some(n0) = gas_n {
        let series = time_series(run, &|w| match w {
            Workload::Gas { k, n, .. } if *n == n0 => Some(*k as f64),
            _ => None,
        });
        out.push((
            "gas-time-vs-k.svg".into(),
            loglog_plot(
                &format!("gas (bounce), {n0}-gons: wall time against k"),
                "polygons k",
                "wall time (s)",
                &series,
            ),
        ));
    }
    for (family, file) in [
        ("cluster", "cluster-time-vs-k.svg"),
        ("swarm", "swarm-time-vs-k.svg"),
    ] {
        let series = time_series(run, &|w| match w {
            Workload::Cluster { k } if family == "cluster" => Some(*k as f64),
            Workload::Swarm { k } if family == "swarm" => Some(*k as f64),
            _ => None,
        });
        if !series.is_empty() {
            out.push((
                file.into(),
                loglog_plot(
                    &format!("{family} (remove): wall time against k"),
                    "polygons k",
                    "wall time (s)",
                    &series,
                ),
            ));
        }
    }
    out
}

/// Merges runs, in order: workloads and methods in the order first seen,
/// a later run's cell of the same workload and method replacing an earlier
/// one (and its reference), the largest budget, the total of the wall
/// times; quick only if every run was.
pub fn merge(runs: Vec<BenchRun>) -> Option<BenchRun> {
    let mut it = runs.into_iter();
    let mut out = it.next()?;
    for r in it {
        out.quick &= r.quick;
        out.budget_seconds = out.budget_seconds.max(r.budget_seconds);
        out.total_seconds += r.total_seconds;
        out.resumes += r.resumes;
        out.repeat = out.repeat.max(r.repeat);
        for w in r.workloads {
            if !out.workloads.contains(&w) {
                out.workloads.push(w);
            }
        }
        for m in r.methods {
            if !out.methods.contains(&m) {
                out.methods.push(m);
            }
        }
        out.references.extend(r.references);
        for c in r.cells {
            out.cells
                .retain(|x| !(x.workload == c.workload && x.method == c.method));
            out.cells.push(c);
        }
    }
    Some(out)
}

/// Reads the `bench.json` files written by [`write()`] and merges their runs
/// ([`merge`]); the machine is the first file's.
pub fn read_runs(paths: &[PathBuf]) -> std::io::Result<(BenchRun, Machine)> {
    #[derive(Deserialize)]
    struct Saved {
        machine: Machine,
        run: BenchRun,
    }
    let mut machine = None;
    let mut runs = Vec::new();
    for p in paths {
        let text = fs::read_to_string(p)?;
        let saved: Saved = serde_json::from_str(&text).map_err(|e| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("{}: {e}", p.display()),
            )
        })?;
        machine.get_or_insert(saved.machine);
        runs.push(saved.run);
    }
    match (merge(runs), machine) {
        (Some(run), Some(machine)) => Ok((run, machine)),
        _ => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "no bench.json given",
        )),
    }
}

/// Writes the run so far to `path` in `bench.json`'s format (through a
/// temporary file, so that an interruption leaves the previous checkpoint
/// whole): what `kss-bench --resume` reads.
pub fn write_checkpoint(path: &Path, run: &BenchRun, m: &Machine) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir)?;
    }
    let value = serde_json::json!({ "machine": m, "run": run });
    let tmp = path.with_extension("json.tmp");
    fs::write(
        &tmp,
        serde_json::to_string_pretty(&value).map_err(std::io::Error::other)? + "\n",
    )?;
    fs::rename(&tmp, path)
}

/// Writes `bench.md`, `bench.json` and the plots into `dir`; returns the
/// files written.
pub fn write(dir: &Path, run: &BenchRun, m: &Machine) -> std::io::Result<Vec<PathBuf>> {
    fs::create_dir_all(dir)?;
    let mut files = Vec::new();
    let md = dir.join("bench.md");
    fs::write(&md, markdown(run, m))?;
    files.push(md);
    let json = dir.join("bench.json");
    let value = serde_json::json!({ "machine": m, "run": run });
    fs::write(
        &json,
        serde_json::to_string_pretty(&value).map_err(std::io::Error::other)? + "\n",
    )?;
    files.push(json);
    for (name, svg) in plots(run) {
        let p = dir.join(name);
        fs::write(&p, svg)?;
        files.push(p);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::{CellOutcome, CellResult};
    use crate::Counters;

    fn cell(
        w: &str,
        m: &str,
        status: Status,
        wall: f64,
        events: u64,
        collisions: u64,
    ) -> CellResult {
        CellResult {
            workload: w.into(),
            method: m.into(),
            outcome: CellOutcome {
                wall_seconds: wall,
                sim_seconds: 1.0,
                counters: Counters {
                    events,
                    collisions,
                    ..Default::default()
                },
                ..CellOutcome::not_run(status)
            },
            comparison: None,
        }
    }

    #[test]
    fn cost_section_lists_every_method_of_the_cost_workloads() {
        let w = "walls-k30-n16-bounce";
        let run = BenchRun {
            quick: true,
            budget_seconds: 5.0,
            workloads: vec![w.into(), "cluster-k16".into()],
            methods: vec![
                "hierarchical".into(),
                "parry-toi".into(),
                "parry-step:30".into(),
            ],
            references: Default::default(),
            cells: vec![
                cell(w, "hierarchical", Status::Ok, 2.0, 40_000, 400),
                cell(w, "parry-toi", Status::Ok, 0.5, 0, 0),
                cell(w, "parry-step:30", Status::Budget, 0.0, 0, 0),
                cell("cluster-k16", "hierarchical", Status::Ok, 1.0, 10, 1),
            ],
            total_seconds: 8.0,
            resumes: 0,
            repeat: 1,
        };
        let md = markdown(&run, &machine());
        let section = &md[md.find("## Cost per event").expect("the section")..];
        let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
        // 2 s over 40000 events: 50 µs per event, 100 events and 5000 µs per collision
        assert!(
            section.contains("| walls-k30-n16-bounce | hierarchical | 2.00 s | 40000 | 400 | 100 | 50.0 | 5000 |"),
            "{section}"
        );
        assert!(
            section.contains("| walls-k30-n16-bounce | parry-toi | 500.0 ms | — | 0 | — | — | — |"),
            "{section}"
        );
        assert!(
            section.contains("| walls-k30-n16-bounce | parry-step dt=1/30 | > 5.00 s |"),
            "{section}"
        );
        assert!(!section.contains("cluster-k16"), "{section}");
        // a run without them has no such section
        let mut other = run.clone();
        other.workloads.remove(0);
        other.cells.retain(|c| c.workload != w);
        assert!(!markdown(&other, &machine()).contains("## Cost per event"));
    }
}
