//! The cost of the online operations of [`kss::Simulation`] against the
//! scene's size: microseconds per velocity change, per removal, per
//! insertion (and per refused insertion), and per event of the advances in
//! between, for each structure. A measurement, not a test: it prints a
//! Markdown table (and writes it to a file with `--out`).
//!
//! ```sh
//! cargo run --release -p kss-bench --example online_ops
//! cargo run --release -p kss-bench --example online_ops -- --k 1000,3000,10000 \
//!     --out crates/kss-bench/results/online-ops.md
//! ```
//!
//! Options: `--k LIST` (default 1000,3000,10000), `--structures LIST`
//! (default hierarchical,plain,brute), `--ops N` (velocity changes per
//! scene, and the most removals and insertions; default 10000),
//! `--insert-seconds S` (the time the insertions of one scene may take
//! about; default 20), `--brute-max-k K` (brute runs only up to this
//! size; default 1000), `--horizon T` (simulated time over the whole run
//! of one scene; default 1), `--seed S` (default 1), `--out FILE`.
//!
//! Scene: `k` regular octagons of circumradius 0.25 with random phases, one
//! per cell of a unit grid (jittered inside its cell), random headings and
//! speeds 0.2–1, in a box of four fixed walls that leave narrow gaps at the
//! corners. Collisions are answered with [`kss::Simulation::bounce`].
//!
//! The run of one scene is `ops / 4` rounds. Each round advances the
//! simulation by a random time (uniform in `[0, 2·horizon/rounds]`; the
//! advances, with the bounces that answer their collisions, are timed
//! together and divided by the events processed meanwhile: certificate
//! failures and collisions), then changes the velocities of 4 random
//! polygons (one `set_velocity` each, timed one by one), then makes the
//! removals and insertions due in that round (spread evenly over the
//! rounds; a removal takes a random moving polygon out; an insertion puts
//! an octagon at a random place in the box, trying other places while
//! `insert` refuses with [`kss::SimError::Touches`]: refused tries are
//! timed and counted apart). Where insertions are slow (brute's are
//! `O(k)` pair computations each; a kinetic insertion that falls back to a
//! rebuild is `O(k log k)`), the number of insertions is what
//! `--insert-seconds` allows (estimated from the first 5), at most `ops`; the number of removals is at most the
//! insertions plus `k/10`, so that the scene keeps at least 90% of its
//! size. Brute's operations compute `O(k)` pair contact times each and its
//! construction `O(k²)`: above `--brute-max-k` it is skipped with a note.

use std::io::Write as _;
use std::time::Instant;

use kss::rng::Rng;
use kss::{PolygonSpec, SimError, SimOptions, Simulation, StructureKind};

/// Velocity changes per round.
const BATCH: usize = 4;
/// Circumradius of the octagons.
const RADIUS: f64 = 0.25;
/// Insertions timed before the number of insertions is chosen.
const PROBE: usize = 5;

/// Command-line options (module docs).
struct Args {
    ks: Vec<usize>,
    structures: Vec<StructureKind>,
    ops: usize,
    insert_seconds: f64,
    brute_max_k: usize,
    horizon: f64,
    seed: u64,
    out: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        ks: vec![1000, 3000, 10000],
        structures: vec![
            StructureKind::Hierarchical,
            StructureKind::Plain,
            StructureKind::Brute,
        ],
        ops: 10_000,
        insert_seconds: 20.0,
        brute_max_k: 1000,
        horizon: 1.0,
        seed: 1,
        out: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        let num = |s: String| s.parse::<f64>().map_err(|e| format!("{s:?}: {e}"));
        match flag.as_str() {
            "--k" => {
                a.ks = value()?
                    .split(',')
                    .map(|s| s.trim().parse().map_err(|e| format!("{s:?}: {e}")))
                    .collect::<Result<_, _>>()?
            }
            "--structures" => {
                a.structures = value()?
                    .split(',')
                    .map(|s| match s.trim() {
                        "hierarchical" => Ok(StructureKind::Hierarchical),
                        "plain" => Ok(StructureKind::Plain),
                        "brute" => Ok(StructureKind::Brute),
                        other => Err(format!("unknown structure {other:?}")),
                    })
                    .collect::<Result<_, _>>()?
            }
            "--ops" => a.ops = num(value()?)? as usize,
            "--insert-seconds" => a.insert_seconds = num(value()?)?,
            "--brute-max-k" => a.brute_max_k = num(value()?)? as usize,
            "--horizon" => a.horizon = num(value()?)?,
            "--seed" => a.seed = num(value()?)? as u64,
            "--out" => a.out = Some(value()?),
            other => return Err(format!("unknown option {other:?} (see the module docs)")),
        }
    }
    if a.ops < BATCH {
        return Err(format!("--ops must be at least {BATCH}"));
    }
    Ok(a)
}

/// A regular octagon of circumradius [`RADIUS`], counter-clockwise.
fn octagon(phase: f64) -> Vec<[f64; 2]> {
    (0..8)
        .map(|i| {
            let a = phase + std::f64::consts::TAU * i as f64 / 8.0;
            [RADIUS * a.cos(), RADIUS * a.sin()]
        })
        .collect()
}

/// A random velocity: uniform heading, speed 0.2–1.
fn velocity(rng: &mut Rng) -> [f64; 2] {
    let a = rng.range_f64(0.0, std::f64::consts::TAU);
    let s = rng.range_f64(0.2, 1.0);
    [s * a.cos(), s * a.sin()]
}

/// A fixed rectangle `[x0, x1] × [y0, y1]`.
fn wall(id: &str, x0: f64, y0: f64, x1: f64, y1: f64) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
        position: [0.0, 0.0],
        velocity: [0.0, 0.0],
        fixed: true,
    }
}

/// The scene of `k` octagons and its box `[0, w] × [0, h]`.
fn scene(k: usize, rng: &mut Rng) -> (Vec<PolygonSpec>, f64, f64) {
    let cols = (k as f64).sqrt().ceil() as usize;
    let rows = k.div_ceil(cols);
    let (w, h) = (cols as f64, rows as f64);
    let gap = 0.05;
    let mut polygons = vec![
        wall("#s", gap, -1.0, w - gap, 0.0),
        wall("#n", gap, h, w - gap, h + 1.0),
        wall("#w", -1.0, gap, 0.0, h - gap),
        wall("#e", w, gap, w + 1.0, h - gap),
    ];
    let slack = 0.5 - RADIUS - 0.02;
    for i in 0..k {
        polygons.push(PolygonSpec {
            id: format!("m{i}"),
            vertices: octagon(rng.range_f64(0.0, std::f64::consts::TAU)),
            position: [
                (i % cols) as f64 + 0.5 + rng.range_f64(-slack, slack),
                (i / cols) as f64 + 0.5 + rng.range_f64(-slack, slack),
            ],
            velocity: velocity(rng),
            fixed: false,
        });
    }
    (polygons, w, h)
}

/// Durations of one kind of operation, in microseconds.
#[derive(Default)]
struct Timings(Vec<f64>);

impl Timings {
    fn time<T>(&mut self, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let r = f();
        self.0.push(start.elapsed().as_secs_f64() * 1e6);
        r
    }

    fn mean(&self) -> f64 {
        self.0.iter().sum::<f64>() / self.0.len().max(1) as f64
    }

    fn median(&self) -> f64 {
        let mut v = self.0.clone();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    }

    /// `n: mean (median)` in µs, or a dash.
    fn cell(&self) -> String {
        if self.0.is_empty() {
            "0: –".into()
        } else {
            format!(
                "{}: {} ({})",
                self.0.len(),
                fmt_us(self.mean()),
                fmt_us(self.median())
            )
        }
    }
}

fn fmt_us(us: f64) -> String {
    if us >= 100.0 {
        format!("{us:.0}")
    } else {
        format!("{us:.1}")
    }
}

/// What one run of one scene with one structure measured.
struct Cell {
    k: usize,
    structure: &'static str,
    build_ms: f64,
    velocity: Timings,
    removal: Timings,
    insertion: Timings,
    refused: Timings,
    advance_seconds: f64,
    events: u64,
    collisions: u64,
    final_polygons: usize,
    wall_seconds: f64,
}

/// Events processed by the advances (not the velocity changes).
fn advance_events(sim: &Simulation) -> u64 {
    let stats = sim.stats();
    stats.events_processed
        - stats
            .events_by_kind
            .get("flight_plan_change")
            .copied()
            .unwrap_or(0)
}

/// Advance to `target`, bouncing every collision on the way; the number
/// of collisions.
fn advance(sim: &mut Simulation, target: f64) -> Result<u64, SimError> {
    let mut collisions = 0;
    loop {
        let events = sim.advance(target)?;
        if events.is_empty() {
            return Ok(collisions);
        }
        collisions += events.iter().filter(|e| !e.again).count() as u64;
        sim.bounce(&events)?;
    }
}

fn measure(k: usize, structure: StructureKind, args: &Args) -> Result<Cell, SimError> {
    let wall_start = Instant::now();
    let mut rng = Rng::with_stream(args.seed, k as u64);
    let (polygons, w, h) = scene(k, &mut rng);
    let options = SimOptions {
        structure,
        ..SimOptions::default()
    };
    let start = Instant::now();
    let mut sim = Simulation::new(&polygons, &options)?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut moving: Vec<String> = polygons
        .iter()
        .filter(|p| !p.fixed)
        .map(|p| p.id.clone())
        .collect();

    let rounds = args.ops / BATCH;
    let dt = args.horizon / rounds as f64;
    let (mut changes, mut removal) = (Timings::default(), Timings::default());
    let (mut insertion, mut refused) = (Timings::default(), Timings::default());
    let (mut advance_seconds, mut collisions) = (0.0, 0);
    let events_before = advance_events(&sim);
    let mut next_id = 0usize;
    // planned after the probe insertions
    let (mut n_ins, mut n_rem) = (PROBE.min(args.ops), 0);
    let mut insert_one = |sim: &mut Simulation,
                          rng: &mut Rng,
                          moving: &mut Vec<String>,
                          insertion: &mut Timings,
                          refused: &mut Timings|
     -> Result<(), SimError> {
        loop {
            let spec = PolygonSpec {
                id: format!("i{next_id}"),
                vertices: octagon(rng.range_f64(0.0, std::f64::consts::TAU)),
                position: [
                    rng.range_f64(RADIUS + 0.01, w - RADIUS - 0.01),
                    rng.range_f64(RADIUS + 0.01, h - RADIUS - 0.01),
                ],
                velocity: velocity(rng),
                fixed: false,
            };
            let start = Instant::now();
            match sim.insert(&spec) {
                Ok(()) => {
                    insertion.0.push(start.elapsed().as_secs_f64() * 1e6);
                    next_id += 1;
                    moving.push(spec.id);
                    return Ok(());
                }
                Err(SimError::Touches { .. }) => {
                    refused.0.push(start.elapsed().as_secs_f64() * 1e6)
                }
                Err(e) => return Err(e),
            }
        }
    };
    // `n` operations spread evenly over the rounds `from..rounds`
    let due = |r: usize, n: usize, from: usize| {
        let m = rounds - from;
        (r + 1 - from) * n / m - (r - from) * n / m
    };
    for r in 0..rounds {
        let target = sim.now().to_f64() + rng.range_f64(0.0, 2.0 * dt);
        let start = Instant::now();
        collisions += advance(&mut sim, target)?;
        advance_seconds += start.elapsed().as_secs_f64();

        for _ in 0..BATCH {
            let id = &moving[rng.below(moving.len() as u64) as usize];
            let v = velocity(&mut rng);
            changes.time(|| sim.set_velocity(id, v))?;
        }
        if r == 0 {
            for _ in 0..n_ins {
                insert_one(
                    &mut sim,
                    &mut rng,
                    &mut moving,
                    &mut insertion,
                    &mut refused,
                )?;
            }
            let per_insert = insertion.mean() * 1e-6;
            n_ins = ((args.insert_seconds / per_insert) as usize).clamp(n_ins, args.ops);
            n_rem = (n_ins + k / 10).min(args.ops);
        } else {
            for _ in 0..due(r, n_ins - PROBE.min(args.ops), 1) {
                insert_one(
                    &mut sim,
                    &mut rng,
                    &mut moving,
                    &mut insertion,
                    &mut refused,
                )?;
            }
        }
        for _ in 0..due(r, n_rem, 0) {
            let i = rng.below(moving.len() as u64) as usize;
            let id = moving.swap_remove(i);
            removal.time(|| sim.remove(&id))?;
        }
    }
    let events = advance_events(&sim) - events_before;
    Ok(Cell {
        k,
        structure: structure.name(),
        build_ms,
        velocity: changes,
        removal,
        insertion,
        refused,
        advance_seconds,
        events,
        collisions,
        final_polygons: sim.polygons().count() - 4,
        wall_seconds: wall_start.elapsed().as_secs_f64(),
    })
}

fn shell(cmd: &str, args: &[&str]) -> String {
    std::process::Command::new(cmd)
        .args(args)
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("online_ops: {e}");
            std::process::exit(2);
        }
    };
    let run_start = Instant::now();
    let mut cells = Vec::new();
    let mut notes = Vec::new();
    for &k in &args.ks {
        for &structure in &args.structures {
            if structure == StructureKind::Brute && k > args.brute_max_k {
                let note = format!(
                    "brute at k = {k} skipped (above --brute-max-k {}): its construction computes all k²/2 pair contact times and each operation k of them",
                    args.brute_max_k
                );
                eprintln!("{note}");
                notes.push(note);
                continue;
            }
            eprint!("k = {k}, {} ... ", structure.name());
            let _ = std::io::stderr().flush();
            match measure(k, structure, &args) {
                Ok(cell) => {
                    eprintln!("{:.1} s", cell.wall_seconds);
                    cells.push(cell);
                }
                Err(e) => {
                    eprintln!("failed: {e}");
                    notes.push(format!("k = {k}, {}: failed: {e}", structure.name()));
                }
            }
        }
    }
    let total = run_start.elapsed().as_secs_f64();

    let mut md = String::new();
    let command: Vec<String> = std::env::args().collect();
    md.push_str("# Online operations of `kss::Simulation`: µs per operation against k\n\n");
    md.push_str(&format!(
        "Measured on {} at commit `{}` ({} CPUs), release build:\n\n```sh\n{}\n```\n\n",
        shell("date", &["-u", "+%Y-%m-%d"]),
        shell("git", &["rev-parse", "--short", "HEAD"]),
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        command.join(" ")
    ));
    md.push_str(&format!(
        "Scene and procedure: `crates/kss-bench/examples/online_ops.rs` (module docs). {} velocity changes per scene; insertions as many as about {} s allow (at most {}); removals at most the insertions plus k/10. Operation cells: `count: mean (median)` µs per call. `advance`: the advances between the operations with the bounces that answer their collisions, µs per event (certificate failures and collisions). Simulated time {} per scene.\n\n",
        args.ops / BATCH * BATCH,
        args.insert_seconds,
        args.ops,
        args.horizon
    ));
    md.push_str("| k | structure | build ms | velocity change µs | removal µs | insertion µs | refused insertion µs | advance: events | collisions | µs / event | k at end | wall s |\n");
    md.push_str(
        "| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for c in &cells {
        md.push_str(&format!(
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1} |\n",
            c.k,
            c.structure,
            c.build_ms,
            c.velocity.cell(),
            c.removal.cell(),
            c.insertion.cell(),
            c.refused.cell(),
            c.events,
            c.collisions,
            fmt_us(c.advance_seconds * 1e6 / c.events.max(1) as f64),
            c.final_polygons,
            c.wall_seconds
        ));
    }
    md.push('\n');
    for n in &notes {
        md.push_str(&format!("- {n}\n"));
    }
    md.push_str(&format!("\nWall time of the whole run: {total:.0} s.\n"));
    print!("{md}");
    if let Some(path) = &args.out {
        if let Err(e) = std::fs::write(path, &md) {
            eprintln!("online_ops: cannot write {path}: {e}");
            std::process::exit(1);
        }
    }
}
