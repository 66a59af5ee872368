//! Compactness of the plain kinetic separation structure: how many
//! certificates it holds for `k` polygons of `n` vertices each, for a grid of
//! `k` and `n`. A measurement, not a test: it prints a Markdown table.
//!
//! ```sh
//! cargo run --release -p kss-bench --example compactness
//! cargo run --release -p kss-bench --example compactness -- --k 2,10,100 --n 4,16 --family regular
//! ```
//!
//! Options: `--k LIST` (default 2,10,100,1000,10000), `--n LIST` (default
//! 4,16,256,4096,100000), `--family gas|regular|both` (default both),
//! `--max-vertices V` (default 2e7; larger combinations are listed as
//! skipped), `--seed S` (default 1).
//!
//! Scenes: `regular`: `k` regular `n`-gons of circumradius 0.25–0.45 with
//! random phases, one per cell of a unit grid, jittered inside their cells,
//! with random velocities (speed 0.2–1); `gas`: `kss::gen::gas` without
//! walls (random convex `n`-gons in the same kind of grid; `n` at most 2^16).
//! For each scene the structure is built at time 0
//! (`kss::structure::kinetic::Kinetic::new`) and the table gives its
//! certificates: all of them (`all`: every certificate the structure keeps,
//! scheduled or not; by kind from the from-scratch certificate set), the
//! scheduled ones (`sched`: those with a failure time on the current motions,
//! the set `certificates_max` of `kss run --stats` measures), both per
//! polygon, and the analytic bound `26(k − 1) − 7·t_ω` (ARCHITECTURE.md,
//! "Compactness"; `t_ω` is the number of partition triangles with a corner
//! at infinity). `build` is the time of `Kinetic::new` and `peak RSS` the
//! process's peak resident memory while the scene and the structure were
//! made (reset before each scene).

use std::f64::consts::TAU;
use std::io::Write as _;
use std::time::Instant;

use kss::gen::{self, GasParams};
use kss::num::{Rational, Time};
use kss::rng::Rng;
use kss::structure::certs::CertKind;
use kss::structure::kinetic::Kinetic;
use kss::world::World;
use kss::{CollisionMode, PolygonSpec, Scenario};

/// `k` regular `n`-gons on a jittered unit grid with random velocities.
fn regular_scene(k: usize, n: usize, seed: u64) -> Scenario {
    let mut rng = Rng::with_stream(seed, 0x5e9);
    let cols = ((k as f64).sqrt().ceil() as usize).max(1);
    let width = k.saturating_sub(1).to_string().len();
    let polygons = (0..k)
        .map(|i| {
            let radius = rng.range_f64(0.25, 0.45);
            let slack = 0.5 - radius - 0.02;
            let centre = [
                (i % cols) as f64 + 0.5 + rng.range_f64(-slack, slack),
                (i / cols) as f64 + 0.5 + rng.range_f64(-slack, slack),
            ];
            let phase = rng.range_f64(0.0, TAU);
            let angle = rng.range_f64(0.0, TAU);
            let speed = rng.range_f64(0.2, 1.0);
            PolygonSpec {
                id: format!("r{i:0width$}"),
                vertices: gen::regular_polygon(n, radius, phase),
                position: centre,
                velocity: [speed * angle.cos(), speed * angle.sin()],
                fixed: false,
            }
        })
        .collect();
    Scenario {
        until: 1.0,
        on_collision: CollisionMode::Bounce,
        polygons,
        flight_plan_changes: Vec::new(),
        ..Default::default()
    }
}

fn gas_scene(k: usize, n: usize, seed: u64) -> Scenario {
    gen::gas(&GasParams {
        k,
        min_n: n,
        max_n: n,
        walls: false,
        mode: CollisionMode::Bounce,
        until: 1.0,
        max_speed: 1.0,
        changes: 0,
        seed,
    })
}

fn peak_rss_mib() -> f64 {
    kss_bench::harness::peak_rss_kib().map_or(0.0, |k| k as f64 / 1024.0)
}

fn list(s: &str) -> Vec<usize> {
    s.split(',')
        .map(|x| {
            let v: f64 = x
                .trim()
                .parse()
                .unwrap_or_else(|_| panic!("bad number {x:?}"));
            v as usize
        })
        .collect()
}

fn main() {
    let mut ks = vec![2, 10, 100, 1000, 10_000];
    let mut ns = vec![4, 16, 256, 4096, 100_000];
    let mut families = vec!["regular", "gas"];
    let mut max_vertices = 2e7 as usize;
    let mut seed = 1u64;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).map(String::as_str).unwrap_or("");
        match args[i].as_str() {
            "--k" => ks = list(value),
            "--n" => ns = list(value),
            "--family" => {
                families = match value {
                    "both" => vec!["regular", "gas"],
                    "gas" => vec!["gas"],
                    "regular" => vec!["regular"],
                    _ => panic!("--family gas|regular|both"),
                }
            }
            "--max-vertices" => max_vertices = value.parse::<f64>().expect("a number") as usize,
            "--seed" => seed = value.parse().expect("an integer"),
            other => panic!("unknown argument {other:?} (see the file's doc comment)"),
        }
        i += 2;
    }
    println!(
        "| scene | k | n | vertices | all | all / k | sched | sched / k | triangle | junction | hull turn | order | bound 26(k−1)−7t_ω | build (s) | peak RSS (MiB) |"
    );
    println!(
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    let mut worst_all: f64 = 0.0;
    let mut worst_sched: f64 = 0.0;
    let mut skipped = Vec::new();
    for family in &families {
        for &k in &ks {
            for &n in &ns {
                if k * n > max_vertices {
                    skipped.push(format!("{family} k={k} n={n} ({} vertices)", k * n));
                    continue;
                }
                if *family == "gas" && n > 1 << 16 {
                    skipped.push(format!("gas k={k} n={n} (the gas generator stops at 2^16)"));
                    continue;
                }
                kss_bench::harness::reset_peak_rss();
                let scenario = match *family {
                    "gas" => gas_scene(k, n, seed),
                    _ => regular_scene(k, n, seed),
                };
                let world = World::new(&scenario, None).expect("a valid scene");
                let world = kss::structure::geo::Geo::plain(&world);
                let vertices: usize = world.bodies().iter().map(|b| b.shape.len()).sum();
                let start = Instant::now();
                let kinetic = Kinetic::new(&world, &Rational::zero()).expect("the structure");
                let build = start.elapsed().as_secs_f64();
                let all = kinetic.certificate_count();
                let (sched, _) = kinetic.active();
                let by_kind = kinetic
                    .kss
                    .certificates(&world, &Time::zero())
                    .expect("the certificate set");
                let count = |kind: CertKind| by_kind.iter().filter(|c| c.kind == kind).count();
                let t_omega = kinetic
                    .kss
                    .tris
                    .iter()
                    .filter(|t| t.c.iter().any(|c| c.is_omega()))
                    .count();
                let bodies = world.len();
                let bound = 26 * (bodies - 1) - 7 * t_omega;
                assert!(all <= bound, "{all} certificates above the bound {bound}");
                worst_all = worst_all.max(all as f64 / bodies as f64);
                worst_sched = worst_sched.max(sched as f64 / bodies as f64);
                println!(
                    "| {family} | {bodies} | {n} | {vertices} | {all} | {:.2} | {sched} | {:.2} | {} | {} | {} | {} | {bound} | {build:.2} | {:.0} |",
                    all as f64 / bodies as f64,
                    sched as f64 / bodies as f64,
                    count(CertKind::Triangle),
                    count(CertKind::Junction),
                    count(CertKind::HullTurn),
                    count(CertKind::Order),
                    peak_rss_mib(),
                );
                let _ = std::io::stdout().flush();
            }
        }
    }
    println!();
    println!("Largest certificates per polygon: all {worst_all:.2}, scheduled {worst_sched:.2}.");
    if !skipped.is_empty() {
        println!("Skipped: {}.", skipped.join("; "));
    }
}
