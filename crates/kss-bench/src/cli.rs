//! The command-line grammar of `kss-bench` (clap).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Benchmark kss against the baselines (parry2d, kinetic sort-and-sweep) on
/// fixed workloads; writes a Markdown table and SVG plots.
///
/// The table also goes to standard output; progress goes to standard error.
#[derive(Debug, Parser)]
#[command(name = "kss-bench", version)]
#[command(after_help = "Exit status: 0 complete run, 2 bad command line, \
4 a cell failed or an exact method differs from the reference, 5 input/output error.")]
#[command(args_conflicts_with_subcommands = true)]
pub struct BenchArgs {
    /// Instead of a benchmark: `docs` writes the benchmark page from the
    /// results files.
    #[command(subcommand)]
    pub command: Option<Sub>,
    /// Tiny workloads and a short budget (CI runs this; about a minute).
    #[arg(long)]
    pub quick: bool,
    /// Results folder (bench.md, bench.json, plots, events).
    #[arg(long, value_name = "DIR", default_value = "results")]
    pub out: PathBuf,
    /// Only these workloads: full names (e.g. gas-k1000-n8-c1000, see
    /// --list), sets (cost: the four workloads of the cost per event, two
    /// bounce swarms in a box, a remove swarm and a gas of 3-16-gons; perf:
    /// cost, the 10^4-octagon gas and the 2^16-gon flypast) or families
    /// (flypast, gas, cluster, swarm, grazing, parallel, far, walls, gasmix).
    #[arg(long, value_name = "NAME", num_args = 1..)]
    pub workload: Vec<String>,
    /// Methods, comma-separated: brute, plain, hierarchical,
    /// hierarchical-all (the hierarchy approximating every polygon, not
    /// only those of more than 32 vertices), sweep, parry-toi, parry-step:N
    /// (fixed time step 1/N). Default: all but hierarchical-all, with
    /// parry-step:30 and parry-step:240.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Time budget per cell in seconds (default 600, quick 5).
    #[arg(long, value_name = "SECONDS", value_parser = parse_budget)]
    pub budget: Option<f64>,
    /// Run each cell N times, the methods of a workload taking turns round
    /// after round (a drift of the machine's speed falls on all of them),
    /// and report each cell's run of median wall time; the report lists
    /// every run's wall time. A cell whose run fails or goes over budget
    /// is not run again and reports that run.
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeat: u32,
    /// Also time the construction of the library's structures: each of
    /// their cells first runs the structure up to the smallest positive
    /// double (world, validation, structure and certificates; no events),
    /// reported as `build`.
    #[arg(long)]
    pub build_time: bool,
    /// Run nothing: write the report (bench.md, bench.json, plots) into
    /// --out from the bench.json files of earlier runs, merged (a later
    /// file's cell of the same workload and method replaces an earlier one);
    /// with --workload, only those workloads.
    #[arg(long, value_name = "FILE", num_args = 1.., conflicts_with_all = ["list", "cell"])]
    pub report_from: Vec<PathBuf>,
    /// Go on with an interrupted run: FILE is the checkpoint it wrote
    /// (`<out>/checkpoint.json`, rewritten after every workload). Its
    /// finished workloads are kept as they are, the others run; the budget
    /// and the methods must be the same. Use the same --out to keep its
    /// events files. It must be the same binary on the same machine, with
    /// the same workloads, methods, budget, mode and --build-time.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["list", "cell", "report_from"])]
    pub resume: Option<PathBuf>,
    /// Print the workloads and methods that would run, and exit.
    #[arg(long)]
    pub list: bool,
    /// Internal: run one cell WORKLOAD/METHOD in this process (the parent
    /// re-invokes the binary so that it can time it out and measure memory).
    #[arg(long, hide = true, value_name = "WORKLOAD/METHOD")]
    pub cell: Option<String>,
    /// Internal: where the cell writes its events.
    #[arg(long, hide = true, value_name = "FILE", requires = "cell")]
    pub cell_events: Option<PathBuf>,
}

/// The subcommands (none runs the benchmark).
#[derive(Debug, Subcommand)]
pub enum Sub {
    /// Write docs/benchmarks.md from the results files: the page's text
    /// from DIR/page/*.md, every table from the results file it names
    /// (run it from the workspace root).
    #[command(after_help = "Exit status: 0 written (with --check: up to date), \
1 with --check: the page differs from what the results make, 2 bad command line, \
5 a file cannot be read or written, or the page's sources do not match the results files.")]
    Docs(DocsArgs),
}

/// `kss-bench docs`.
#[derive(Debug, Args)]
pub struct DocsArgs {
    /// The results folder (its `page/` holds the page's text).
    #[arg(long, value_name = "DIR", default_value = "crates/kss-bench/results")]
    pub results: PathBuf,
    /// The page to write.
    #[arg(long, value_name = "FILE", default_value = "docs/benchmarks.md")]
    pub out: PathBuf,
    /// Write nothing: fail if FILE differs from what the results make.
    #[arg(long)]
    pub check: bool,
}

/// A budget in seconds: a finite number greater than 0.
pub fn parse_budget(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if !x.is_finite() => Err(format!("{s} is not a finite number")),
        Ok(x) if x > 0.0 => Ok(x),
        Ok(_) => Err(format!("{s} must be greater than 0")),
        Err(_) => Err(format!("{s:?} is not a number")),
    }
}
