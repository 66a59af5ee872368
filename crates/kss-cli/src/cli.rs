//! The command-line grammar of `kss` (clap).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Exact kinetic collision detection for moving convex polygons.
///
/// Scenario files and the event output follow the contract in
/// docs/scenario-format.md: events go to standard output as JSON lines,
/// everything else to standard error.
#[derive(Debug, Parser)]
#[command(name = "kss", version)]
#[command(
    after_help = "Exit status: 0 complete run, 1 invalid input, 2 bad command line, \
3 structure not implemented, 4 internal error, 5 input/output error."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scenario; print its collisions as JSON lines on stdout.
    Run(RunArgs),
    /// Generate a scenario file (JSON) from a family of generators.
    Gen(GenArgs),
    /// Draw the scene at one instant as an SVG picture.
    Render(RenderArgs),
    /// Run a built-in scene, print its collisions and draw it.
    Demo(DemoArgs),
}

/// The kinetic structure (`--structure`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StructureArg {
    /// The separation-sensitive hierarchical structure (default).
    Hierarchical,
    /// The kinetic separation structure without the hierarchy.
    Plain,
    /// All-pairs exact time of impact (the reference).
    Brute,
}

impl From<StructureArg> for kss::StructureKind {
    fn from(s: StructureArg) -> Self {
        match s {
            StructureArg::Hierarchical => kss::StructureKind::Hierarchical,
            StructureArg::Plain => kss::StructureKind::Plain,
            StructureArg::Brute => kss::StructureKind::Brute,
        }
    }
}

/// The collision mode of a generated scenario (`--mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Report the earliest collisions, then end.
    Stop,
    /// Colliding polygons leave the scene.
    Remove,
    /// Elastic collisions.
    Bounce,
}

impl From<ModeArg> for kss::CollisionMode {
    fn from(m: ModeArg) -> Self {
        match m {
            ModeArg::Stop => kss::CollisionMode::Stop,
            ModeArg::Remove => kss::CollisionMode::Remove,
            ModeArg::Bounce => kss::CollisionMode::Bounce,
        }
    }
}

/// A finite number.
pub fn parse_finite(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("{s} is not a finite number"))
    }
}

/// A finite number greater than 0.
pub fn parse_positive(s: &str) -> Result<f64, String> {
    let x = parse_finite(s)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{s} must be greater than 0"))
    }
}

/// A finite number at least 0.
pub fn parse_non_negative(s: &str) -> Result<f64, String> {
    let x = parse_finite(s)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("{s} must be at least 0"))
    }
}

/// A world rectangle `x_min,y_min,x_max,y_max`.
pub fn parse_view(s: &str) -> Result<[f64; 4], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 4 {
        return Err(format!(
            "{s:?}: expected four numbers x_min,y_min,x_max,y_max"
        ));
    }
    let mut v = [0.0; 4];
    for (slot, part) in v.iter_mut().zip(parts) {
        *slot = parse_finite(part)?;
    }
    if v[2] <= v[0] || v[3] <= v[1] {
        return Err(format!("{s:?}: x_max must exceed x_min and y_max y_min"));
    }
    Ok(v)
}

/// `kss run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scenario file (JSON); `-` reads standard input.
    pub scenario: String,
    /// The kinetic structure.
    #[arg(long, value_enum, default_value_t = StructureArg::Hierarchical)]
    pub structure: StructureArg,
    /// With the hierarchical structure: polygons of at most N vertices take
    /// part as they are, only larger ones through outer approximations (0
    /// approximates every polygon). The collisions do not depend on it.
    #[arg(long, value_name = "N", default_value_t = kss::DEFAULT_APPROXIMATE_ABOVE)]
    pub approximate_above: usize,
    /// Replace the scenario's `until` (flight-plan changes after it are ignored).
    #[arg(long, value_name = "T", value_parser = parse_positive)]
    pub until: Option<f64>,
    /// Write the run's statistics (JSON) to FILE.
    #[arg(long, value_name = "FILE")]
    pub stats: Option<PathBuf>,
    /// Audit the structure after every event (slow; for debugging).
    #[arg(long)]
    pub audit: bool,
    /// No progress or summary on standard error (errors are still printed).
    #[arg(long, short)]
    pub quiet: bool,
}

/// `kss gen`.
#[derive(Debug, Args)]
pub struct GenArgs {
    /// The family of scenarios.
    #[command(subcommand)]
    pub family: GenFamily,
    /// Output file (default: standard output).
    #[arg(short, long, global = true, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Seed of the generator (same seed, same scenario, forever).
    #[arg(long, global = true, default_value_t = 0)]
    pub seed: u64,
    /// Collision mode (default: bounce for gas, far and swarm, remove for
    /// churn, stop for the others).
    #[arg(long, global = true, value_enum)]
    pub mode: Option<ModeArg>,
    /// Make the small random instance of the test sweeps for this seed
    /// (2-8 polygons, random mode); takes no other family option.
    #[arg(long, global = true)]
    pub small: bool,
}

/// The families of `kss gen`.
#[derive(Debug, Subcommand)]
pub enum GenFamily {
    /// Two congruent regular n-gons passing each other at a chosen gap.
    Flypast(FlypastArgs),
    /// Random convex polygons with random velocities, optionally in a box.
    Gas(GasArgs),
    /// Pairs first touching at one exact instant; three polygons meeting at a point.
    Simultaneous(SimultaneousArgs),
    /// Tangential contacts: vertex sliding along an edge's line, vertex-vertex grazes.
    Grazing(DegenerateArgs),
    /// Motion parallel to edges: edges flush, sliding along a common line.
    Parallel(DegenerateArgs),
    /// A gas scene translated to coordinates around 1e6, slowed down.
    Far(FarArgs),
    /// Regular n-gons in a box of walls, velocities in [-1, 1]², about 12
    /// collisions per polygon (bounce mode by default).
    Swarm(SwarmArgs),
    /// Polygons entering and leaving during the run: clusters inserted at
    /// free places, removals (one at the instant of a collision), fixed
    /// polygons inserted and removed, flight-plan changes (remove mode by
    /// default).
    Churn(ChurnArgs),
}

/// Options of `kss gen flypast`.
#[derive(Debug, Args)]
pub struct FlypastArgs {
    /// Vertices of each polygon (3 to 2^24).
    #[arg(long)]
    pub n: Option<usize>,
    /// Diameter D of each polygon (circumscribed circle).
    #[arg(long, value_parser = parse_positive)]
    pub diameter: Option<f64>,
    /// Minimum distance s during the motion; 0 or negative: they collide
    /// (default D/10).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, conflicts_with = "ratio")]
    pub gap: Option<f64>,
    /// The ratio D/s instead of --gap.
    #[arg(long, value_parser = parse_positive)]
    pub ratio: Option<f64>,
    /// A moves too (A and B at half the relative speed each); default: A fixed.
    #[arg(long)]
    pub a_moving: bool,
    /// Relative speed.
    #[arg(long, value_parser = parse_positive)]
    pub speed: Option<f64>,
}

/// Options shared by `kss gen gas` and `kss gen far`.
#[derive(Debug, Args)]
pub struct GasArgs {
    /// Number of moving polygons.
    #[arg(long)]
    pub k: Option<usize>,
    /// Vertices of every polygon (sets --min-n and --max-n).
    #[arg(long, conflicts_with_all = ["min_n", "max_n"])]
    pub n: Option<usize>,
    /// Fewest vertices of a polygon.
    #[arg(long)]
    pub min_n: Option<usize>,
    /// Most vertices of a polygon.
    #[arg(long)]
    pub max_n: Option<usize>,
    /// Four fixed walls around the scene (gaps at the corners).
    #[arg(long)]
    pub walls: bool,
    /// End of the simulated interval.
    #[arg(long, value_parser = parse_positive)]
    pub until: Option<f64>,
    /// Largest speed of a polygon.
    #[arg(long, value_parser = parse_non_negative)]
    pub max_speed: Option<f64>,
    /// Number of random flight-plan changes.
    #[arg(long)]
    pub changes: Option<usize>,
}

/// Options of `kss gen far`.
#[derive(Debug, Args)]
pub struct FarArgs {
    /// The gas scene.
    #[command(flatten)]
    pub gas: GasArgs,
    /// How far the scene is moved (x; y gets three quarters of it).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub offset: Option<f64>,
    /// Velocities divided (and times multiplied) by this power of two.
    #[arg(long, value_parser = parse_positive)]
    pub slowdown: Option<f64>,
}

/// Options of `kss gen swarm`.
#[derive(Debug, Args)]
pub struct SwarmArgs {
    /// Number of moving polygons.
    #[arg(long)]
    pub k: Option<usize>,
    /// Vertices of every polygon.
    #[arg(long)]
    pub n: Option<usize>,
    /// About this many collisions per polygon in bounce mode: sets the
    /// calibrated `until` (default 12).
    #[arg(long, value_name = "C", value_parser = parse_positive, conflicts_with = "until")]
    pub collisions: Option<f64>,
    /// End of the simulated interval instead of the calibrated one.
    #[arg(long, value_parser = parse_positive)]
    pub until: Option<f64>,
}

/// Options of `kss gen churn`.
#[derive(Debug, Args)]
pub struct ChurnArgs {
    /// Number of moving polygons present at time 0.
    #[arg(long)]
    pub k: Option<usize>,
    /// Number of clusters of polygons inserted during the run.
    #[arg(long)]
    pub clusters: Option<usize>,
    /// End of the simulated interval (at least 1).
    #[arg(long, value_parser = parse_positive)]
    pub until: Option<f64>,
}

/// Options of `kss gen simultaneous`.
#[derive(Debug, Args)]
pub struct SimultaneousArgs {
    /// Number of pairs touching at the common instant.
    #[arg(long)]
    pub pairs: Option<usize>,
    /// Leave out the three polygons meeting at one point.
    #[arg(long)]
    pub no_triple: bool,
    /// End of the simulated interval (default: a little after the contacts).
    #[arg(long, value_parser = parse_positive)]
    pub until: Option<f64>,
}

/// Options of `kss gen grazing` and `kss gen parallel`.
#[derive(Debug, Args)]
pub struct DegenerateArgs {
    /// Number of pairs.
    #[arg(long)]
    pub pairs: Option<usize>,
    /// End of the simulated interval (default: a little after the contacts).
    #[arg(long, value_parser = parse_positive)]
    pub until: Option<f64>,
}

/// `kss render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scenario file (JSON); `-` reads standard input.
    pub scenario: String,
    /// The instant drawn.
    #[arg(long, short, value_name = "T", value_parser = parse_non_negative, default_value_t = 0.0)]
    pub time: f64,
    /// Output SVG file (default: standard output).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The kinetic structure used to simulate up to the instant.
    #[arg(long, value_enum, default_value_t = StructureArg::Hierarchical)]
    pub structure: StructureArg,
    /// With the hierarchical structure: polygons of at most N vertices take
    /// part as they are, only larger ones through outer approximations (0
    /// approximates every polygon). The collisions do not depend on it.
    #[arg(long, value_name = "N", default_value_t = kss::DEFAULT_APPROXIMATE_ABOVE)]
    pub approximate_above: usize,
    /// Picture width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Picture height in pixels.
    #[arg(long, default_value_t = 600)]
    pub height: u32,
    /// World rectangle shown, x_min,y_min,x_max,y_max (default: fit all).
    #[arg(long, value_parser = parse_view, allow_hyphen_values = true)]
    pub view: Option<[f64; 4]>,
    /// Do not write the ids.
    #[arg(long)]
    pub no_ids: bool,
    /// Do not draw velocity arrows.
    #[arg(long)]
    pub no_velocities: bool,
    /// Do not draw the kinetic separation structure (drawn by default with
    /// the plain and hierarchical structures: partition triangles, corridor
    /// faces, bridges, the certificates that fail next and, for the
    /// hierarchy, the outer approximations).
    #[arg(long)]
    pub no_structure: bool,
    /// With the structure: highlight the N certificates that fail next.
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub highlight: usize,
    /// With the structure: no legend.
    #[arg(long)]
    pub no_legend: bool,
    /// An animation: this many frames from --time to --to, evenly spaced,
    /// written as OUTPUT-000.svg, OUTPUT-001.svg, ... (OUTPUT without its
    /// .svg; --output is required), all with the same view.
    #[arg(long, value_name = "N", requires = "to", requires = "output")]
    pub frames: Option<u32>,
    /// The last instant of an animation (with --frames).
    #[arg(long, value_name = "T", value_parser = parse_non_negative)]
    pub to: Option<f64>,
}

/// `kss demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Where to write the picture.
    #[arg(short, long, value_name = "FILE", default_value = "kss-demo.svg")]
    pub output: PathBuf,
    /// The kinetic structure.
    #[arg(long, value_enum, default_value_t = StructureArg::Hierarchical)]
    pub structure: StructureArg,
    /// With the hierarchical structure: polygons of at most N vertices take
    /// part as they are, only larger ones through outer approximations (0
    /// approximates every polygon). The collisions do not depend on it.
    #[arg(long, value_name = "N", default_value_t = kss::DEFAULT_APPROXIMATE_ABOVE)]
    pub approximate_above: usize,
}
