//! The workloads: scenarios made by `kss::gen` (and two small generators
//! here built on its parts) from fixed seeds, named so that a child process
//! can rebuild exactly the same scenario from the name.
//!
//! - `flypast-n<N>-r<R>`: two regular N-gons of diameter D = 1, B passing A at
//!   the gap s = D/R (a near miss: no collision), `stop` mode; with a suffix
//!   `-s<SEED>` the generator's seed (the polygons' rotations and the
//!   direction of the pass) is SEED instead of [`SEED`];
//! - `gas-k<K>-n<N>-c<C>`: K random convex N-gons with random velocities in a
//!   box of four fixed walls, `bounce` mode, `until` chosen so that about C
//!   collisions happen (measured rate: 0.7 collisions per polygon and unit
//!   of time; the table reports the actual count);
//! - `cluster-k<K>`: a dense cluster: K octagons on a unit grid with gaps of
//!   1/1000 of their size, slow random velocities, `remove` mode;
//! - `swarm-k<K>`: a sparse swarm: a gas of K octagons spread 64 times wider
//!   (positions scaled by 64, velocities by 8), `remove` mode;
//! - beyond the issue's list, three families where exactness matters, all
//!   in `remove` mode: `grazing-p<P>` (P pairs with tangential contacts:
//!   vertices sliding along edge lines, vertex-vertex grazes),
//!   `parallel-p<P>` (P pairs moving parallel to edges, touching flush) and
//!   `far-k<K>` (a gas of K octagons around coordinates 10^6, slowed down);
//! - `walls-k<K>-n<N>-bounce`, `walls-k<K>-n<N>-remove`: K regular N-gons in
//!   a box of walls, velocities in [-1, 1]², `until` calibrated for about 12
//!   collisions per polygon in `bounce` mode (`kss::gen::swarm`, the issue's
//!   "swarm"; the same motions in both modes);
//! - `gasmix-k<K>-n<MIN>to<MAX>`: K random convex polygons of MIN to MAX
//!   vertices in a box of walls, `remove` mode, until 10 (`kss gen gas
//!   --walls --mode remove`).
//!
//! Named sets of workloads ([`Workload::set`], [`SETS`]): `cost` (the four workloads
//! of the cost per event: two bounce swarms, a remove swarm and a gas of
//! mixed polygons) and `perf` (those and the 10⁴-octagon gas and the
//! 2¹⁶-gon flypast).

use std::f64::consts::TAU;

use kss::gen::{self, FlypastParams, GasParams, SwarmParams};
use kss::rng::Rng;
use kss::{CollisionMode, PolygonSpec, Scenario};

/// The seed of every workload.
pub const SEED: u64 = 1;

/// Collisions per polygon of the `walls` workloads in `bounce` mode (their
/// `until`; the `remove` ones use the same).
const WALLS_COLLISIONS_PER_POLYGON: f64 = 12.0;

/// How much slower the `far` workload moves.
const FAR_SLOWDOWN: f64 = 1024.0;

/// Collisions per polygon up to time `t` in the gas, measured (kinetic
/// sort-and-sweep, k = 10^2..10^4, 8- and 64-gons): none until the first
/// gaps close, then about 0.7 per polygon and unit of time.
const GAS_CURVE: [(f64, f64); 8] = [
    (0.15, 0.0),
    (0.25, 0.015),
    (0.5, 0.13),
    (0.75, 0.30),
    (1.0, 0.50),
    (1.5, 0.86),
    (2.0, 1.2),
    (4.0, 2.6),
];

/// The `until` at which about `per_polygon` collisions per polygon have happened.
fn gas_until(per_polygon: f64) -> f64 {
    for w in GAS_CURVE.windows(2) {
        let ((t0, n0), (t1, n1)) = (w[0], w[1]);
        if per_polygon <= n1 {
            return t0 + (t1 - t0) * ((per_polygon - n0) / (n1 - n0)).max(0.0);
        }
    }
    let (t, n) = GAS_CURVE[GAS_CURVE.len() - 1];
    t + (per_polygon - n) / 0.7
}

/// A workload.
#[derive(Clone, Debug, PartialEq)]
pub enum Workload {
    /// Two n-gons passing at gap `D / ratio`.
    Flypast {
        /// Vertices of each polygon.
        n: usize,
        /// D/s.
        ratio: f64,
        /// The generator's seed ([`SEED`] unless another is asked for).
        seed: u64,
    },
    /// A bouncing gas in a box.
    Gas {
        /// Moving polygons.
        k: usize,
        /// Vertices of each.
        n: usize,
        /// About this many collisions.
        collisions: u64,
    },
    /// A dense cluster (small gaps), `remove` mode.
    Cluster {
        /// Polygons.
        k: usize,
    },
    /// A sparse far-apart swarm, `remove` mode.
    Swarm {
        /// Polygons.
        k: usize,
    },
    /// Tangential grazing contacts (`kss::gen::grazing`), `remove` mode.
    Grazing {
        /// Pairs.
        pairs: usize,
    },
    /// Edges flush, motion parallel to edges (`kss::gen::parallel`), `remove` mode.
    Parallel {
        /// Pairs.
        pairs: usize,
    },
    /// A gas far from the origin (`kss::gen::far`), `remove` mode.
    Far {
        /// Polygons.
        k: usize,
    },
    /// Regular n-gons in a box of walls (`kss::gen::swarm`), about 12
    /// collisions per polygon in `bounce` mode.
    Walls {
        /// Moving polygons.
        k: usize,
        /// Vertices of each.
        n: usize,
        /// `bounce` or `remove` (the same motions and `until` in both).
        mode: CollisionMode,
    },
    /// Random convex polygons of `min_n` to `max_n` vertices in a box of
    /// walls (`kss::gen::gas`), `remove` mode, until 10.
    GasMix {
        /// Moving polygons.
        k: usize,
        /// Fewest vertices of a polygon.
        min_n: usize,
        /// Most vertices of a polygon.
        max_n: usize,
    },
}

/// The names of the workload sets of [`Workload::set`].
pub const SETS: [&str; 2] = ["cost", "perf"];

/// The name of a collision mode in workload names.
fn mode_name(mode: CollisionMode) -> &'static str {
    match mode {
        CollisionMode::Stop => "stop",
        CollisionMode::Remove => "remove",
        CollisionMode::Bounce => "bounce",
    }
}

fn ratio_name(r: f64) -> String {
    let e = r.log10();
    if (e - e.round()).abs() < 1e-9 && e >= 1.0 {
        format!("1e{}", e.round() as i64)
    } else {
        format!("{r}")
    }
}

/// The name suffix of a flypast's seed: none for the default [`SEED`].
fn seed_suffix(seed: u64) -> String {
    if seed == SEED {
        String::new()
    } else {
        format!("-s{seed}")
    }
}

impl Workload {
    /// The name (parsed back by [`Workload::parse`]).
    pub fn name(&self) -> String {
        match self {
            Workload::Flypast { n, ratio, seed } => {
                format!("flypast-n{n}-r{}{}", ratio_name(*ratio), seed_suffix(*seed))
            }
            Workload::Gas { k, n, collisions } => format!("gas-k{k}-n{n}-c{collisions}"),
            Workload::Cluster { k } => format!("cluster-k{k}"),
            Workload::Swarm { k } => format!("swarm-k{k}"),
            Workload::Grazing { pairs } => format!("grazing-p{pairs}"),
            Workload::Parallel { pairs } => format!("parallel-p{pairs}"),
            Workload::Far { k } => format!("far-k{k}"),
            Workload::Walls { k, n, mode } => format!("walls-k{k}-n{n}-{}", mode_name(*mode)),
            Workload::GasMix { k, min_n, max_n } => format!("gasmix-k{k}-n{min_n}to{max_n}"),
        }
    }

    /// The workloads of the set called `name` (one of [`SETS`]), if it is one.
    pub fn set(name: &str) -> Option<Vec<Workload>> {
        let cost = || {
            vec![
                Workload::Walls {
                    k: 1000,
                    n: 16,
                    mode: CollisionMode::Bounce,
                },
                Workload::Walls {
                    k: 300,
                    n: 256,
                    mode: CollisionMode::Bounce,
                },
                Workload::Walls {
                    k: 2000,
                    n: 64,
                    mode: CollisionMode::Remove,
                },
                Workload::GasMix {
                    k: 1000,
                    min_n: 3,
                    max_n: 16,
                },
            ]
        };
        match name {
            "cost" => Some(cost()),
            "perf" => {
                let mut w = cost();
                w.push(Workload::Gas {
                    k: 10_000,
                    n: 8,
                    collisions: 1000,
                });
                w.push(Workload::Flypast {
                    n: 1 << 16,
                    ratio: 1e3,
                    seed: SEED,
                });
                Some(w)
            }
            _ => None,
        }
    }

    /// Parses [`Workload::name`].
    pub fn parse(s: &str) -> Result<Workload, String> {
        let bad = || {
            format!(
                "bad workload name {s:?}: expected flypast-n<N>-r<D/s>[-s<SEED>], gas-k<K>-n<N>-c<C>, cluster-k<K>, swarm-k<K>, grazing-p<P>, parallel-p<P>, far-k<K>, walls-k<K>-n<N>-<bounce|remove> or gasmix-k<K>-n<MIN>to<MAX>"
            )
        };
        let parts: Vec<&str> = s.split('-').collect();
        let num = |p: &str, prefix: &str| -> Result<f64, String> {
            p.strip_prefix(prefix)
                .and_then(|x| x.parse::<f64>().ok())
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(bad)
        };
        let int = |p: &str, prefix: &str| -> Result<usize, String> {
            p.strip_prefix(prefix)
                .and_then(|x| x.parse::<usize>().ok())
                .ok_or_else(bad)
        };
        let w = match parts.as_slice() {
            ["flypast", n, r] => Workload::Flypast {
                n: int(n, "n")?,
                ratio: num(r, "r")?,
                seed: SEED,
            },
            ["flypast", n, r, seed] => Workload::Flypast {
                n: int(n, "n")?,
                ratio: num(r, "r")?,
                seed: seed
                    .strip_prefix('s')
                    .and_then(|x| x.parse::<u64>().ok())
                    .ok_or_else(bad)?,
            },
            ["gas", k, n, c] => Workload::Gas {
                k: int(k, "k")?,
                n: int(n, "n")?,
                collisions: int(c, "c")? as u64,
            },
            ["cluster", k] => Workload::Cluster { k: int(k, "k")? },
            ["swarm", k] => Workload::Swarm { k: int(k, "k")? },
            ["grazing", p] => Workload::Grazing {
                pairs: int(p, "p")?,
            },
            ["parallel", p] => Workload::Parallel {
                pairs: int(p, "p")?,
            },
            ["far", k] => Workload::Far { k: int(k, "k")? },
            ["walls", k, n, mode] => Workload::Walls {
                k: int(k, "k")?,
                n: int(n, "n")?,
                mode: match *mode {
                    "bounce" => CollisionMode::Bounce,
                    "remove" => CollisionMode::Remove,
                    _ => return Err(bad()),
                },
            },
            ["gasmix", k, n] => {
                let (min_n, max_n) = n
                    .strip_prefix('n')
                    .and_then(|x| x.split_once("to"))
                    .ok_or_else(bad)?;
                Workload::GasMix {
                    k: int(k, "k")?,
                    min_n: int(min_n, "")?,
                    max_n: int(max_n, "")?,
                }
            }
            _ => return Err(bad()),
        };
        w.check()?;
        Ok(w)
    }

    fn check(&self) -> Result<(), String> {
        let ok = match self {
            Workload::Flypast { n, ratio, .. } => (3..=1 << 24).contains(n) && *ratio >= 2.0,
            Workload::Gas { k, n, collisions } => {
                (1..=1 << 20).contains(k) && (3..=1 << 16).contains(n) && *collisions > 0
            }
            Workload::Cluster { k } | Workload::Swarm { k } | Workload::Far { k } => {
                (1..=1 << 20).contains(k)
            }
            Workload::Grazing { pairs } | Workload::Parallel { pairs } => {
                (1..=100_000).contains(pairs)
            }
            Workload::Walls { k, n, mode } => {
                (1..=1 << 20).contains(k)
                    && (3..=1 << 16).contains(n)
                    && *mode != CollisionMode::Stop
            }
            Workload::GasMix { k, min_n, max_n } => {
                (1..=1 << 20).contains(k) && *min_n >= 3 && (*min_n..=1 << 16).contains(max_n)
            }
        };
        if ok {
            Ok(())
        } else {
            Err(format!("workload {} is out of range", self.name()))
        }
    }

    /// The family (`flypast`, `gas`, `cluster`, `swarm`, `grazing`,
    /// `parallel`, `far`, `walls`, `gasmix`).
    pub fn family(&self) -> &'static str {
        match self {
            Workload::Flypast { .. } => "flypast",
            Workload::Gas { .. } => "gas",
            Workload::Cluster { .. } => "cluster",
            Workload::Swarm { .. } => "swarm",
            Workload::Grazing { .. } => "grazing",
            Workload::Parallel { .. } => "parallel",
            Workload::Far { .. } => "far",
            Workload::Walls { .. } => "walls",
            Workload::GasMix { .. } => "gasmix",
        }
    }

    /// The series this workload belongs to (all parameters but the size)
    /// and its size: methods that ran out of budget at one size are not run
    /// at larger sizes of the same series.
    pub fn series(&self) -> (String, f64) {
        match self {
            Workload::Flypast { n, ratio, seed } => (
                format!("flypast D/s={}{}", ratio_name(*ratio), seed_suffix(*seed)),
                *n as f64,
            ),
            Workload::Gas { k, n, collisions } => (format!("gas n={n} c={collisions}"), *k as f64),
            Workload::Cluster { k } => ("cluster".into(), *k as f64),
            Workload::Swarm { k } => ("swarm".into(), *k as f64),
            Workload::Grazing { pairs } => ("grazing".into(), *pairs as f64),
            Workload::Parallel { pairs } => ("parallel".into(), *pairs as f64),
            Workload::Far { k } => ("far".into(), *k as f64),
            Workload::Walls { k, n, mode } => {
                (format!("walls n={n} {}", mode_name(*mode)), *k as f64)
            }
            Workload::GasMix { k, min_n, max_n } => {
                (format!("gasmix n={min_n}..{max_n}"), *k as f64)
            }
        }
    }

    /// Total number of vertices (for the memory guard).
    pub fn vertices(&self) -> usize {
        match self {
            Workload::Flypast { n, .. } => 2 * n,
            Workload::Gas { k, n, .. } => k * n + 16,
            Workload::Cluster { k } | Workload::Swarm { k } | Workload::Far { k } => 8 * k,
            Workload::Grazing { pairs } | Workload::Parallel { pairs } => 16 * pairs,
            Workload::Walls { k, n, .. } => k * n + 16,
            Workload::GasMix { k, max_n, .. } => k * max_n + 16,
        }
    }

    /// The pair computations of an all-pairs method on this workload, as a
    /// cost model for predicting its growth: every pair of bodies once at
    /// the start, and in `bounce` mode (the gas, with about as many
    /// collisions as the name says; the bouncing walls swarm, with about 12
    /// per polygon) both bodies of a collision against all others again.
    /// Flypast: one pair, however large the polygons.
    pub fn all_pairs_work(&self) -> f64 {
        let pairs = |bodies: usize| bodies as f64 * (bodies as f64 - 1.0) / 2.0;
        match *self {
            Workload::Flypast { .. } => 1.0,
            Workload::Gas { k, collisions, .. } => {
                let bodies = k + 4;
                pairs(bodies) + 2.0 * collisions as f64 * bodies as f64
            }
            Workload::Cluster { k } | Workload::Swarm { k } | Workload::Far { k } => pairs(k),
            Workload::Grazing { pairs: p } | Workload::Parallel { pairs: p } => pairs(2 * p),
            Workload::Walls { k, mode, .. } => {
                let bodies = k + 4;
                let bounces = if mode == CollisionMode::Bounce {
                    WALLS_COLLISIONS_PER_POLYGON * k as f64
                } else {
                    0.0
                };
                pairs(bodies) + 2.0 * bounces * bodies as f64
            }
            Workload::GasMix { k, .. } => pairs(k + 4),
        }
    }

    /// Whether the run's size grows with the number of polygons (all-pairs
    /// methods then grow as [`Workload::all_pairs_work`]).
    pub fn is_many_body(&self) -> bool {
        !matches!(self, Workload::Flypast { .. })
    }

    /// The time unit of the motions: polygons move about their own size in
    /// this time (1, but 1024 for `far`, which is slowed down). The fixed
    /// time step method's `dt = 1/N` is in this unit.
    pub fn time_scale(&self) -> f64 {
        match self {
            Workload::Far { .. } => FAR_SLOWDOWN,
            _ => 1.0,
        }
    }

    /// The collision mode of the scenario.
    pub fn mode(&self) -> CollisionMode {
        match self {
            Workload::Flypast { .. } => CollisionMode::Stop,
            Workload::Gas { .. } => CollisionMode::Bounce,
            Workload::Walls { mode, .. } => *mode,
            _ => CollisionMode::Remove,
        }
    }

    /// Builds the scenario.
    pub fn scenario(&self) -> Scenario {
        match *self {
            Workload::Flypast { n, ratio, seed } => gen::flypast(&FlypastParams {
                n,
                diameter: 1.0,
                gap: 1.0 / ratio,
                a_moving: false,
                speed: 1.0,
                mode: CollisionMode::Stop,
                seed,
            }),
            Workload::Gas { k, n, collisions } => gen::gas(&GasParams {
                k,
                min_n: n,
                max_n: n,
                walls: true,
                mode: CollisionMode::Bounce,
                until: gas_until(collisions as f64 / k as f64),
                max_speed: 1.0,
                changes: 0,
                seed: SEED,
            }),
            Workload::Cluster { k } => cluster(k),
            Workload::Swarm { k } => {
                let mut s = gen::gas(&GasParams {
                    k,
                    min_n: 8,
                    max_n: 8,
                    walls: false,
                    mode: CollisionMode::Remove,
                    until: 16.0,
                    max_speed: 1.0,
                    changes: 0,
                    seed: SEED,
                });
                for p in &mut s.polygons {
                    p.position = [p.position[0] * 64.0, p.position[1] * 64.0];
                    p.velocity = [p.velocity[0] * 8.0, p.velocity[1] * 8.0];
                }
                s
            }
            Workload::Grazing { pairs } => gen::grazing(&gen::DegenerateParams {
                pairs,
                mode: CollisionMode::Remove,
                until: None,
                small: false,
                seed: SEED,
            }),
            Workload::Parallel { pairs } => gen::parallel(&gen::DegenerateParams {
                pairs,
                mode: CollisionMode::Remove,
                until: None,
                small: false,
                seed: SEED,
            }),
            Workload::Far { k } => gen::far(&gen::FarParams {
                gas: GasParams {
                    k,
                    min_n: 8,
                    max_n: 8,
                    walls: false,
                    mode: CollisionMode::Remove,
                    until: 4.0,
                    max_speed: 1.0,
                    changes: 0,
                    seed: SEED,
                },
                offset: 1.0e6,
                slowdown: FAR_SLOWDOWN,
            }),
            Workload::Walls { k, n, mode } => gen::swarm(&SwarmParams {
                k,
                n,
                mode,
                collisions_per_polygon: WALLS_COLLISIONS_PER_POLYGON,
                until: None,
                seed: SEED,
            }),
            Workload::GasMix { k, min_n, max_n } => gen::gas(&GasParams {
                k,
                min_n,
                max_n,
                walls: true,
                mode: CollisionMode::Remove,
                until: 10.0,
                max_speed: 1.0,
                changes: 0,
                seed: SEED,
            }),
        }
    }

    /// The workloads of `kss-bench --quick`: tiny sizes.
    pub fn quick() -> Vec<Workload> {
        let mut w = Vec::new();
        for ratio in [10.0, 1e6] {
            for n in [16, 1024, 65536] {
                w.push(Workload::Flypast {
                    n,
                    ratio,
                    seed: SEED,
                });
            }
        }
        for k in [30, 100] {
            w.push(Workload::Gas {
                k,
                n: 8,
                collisions: 100,
            });
        }
        w.push(Workload::Cluster { k: 100 });
        w.push(Workload::Cluster { k: 256 });
        w.push(Workload::Swarm { k: 100 });
        w.push(Workload::Swarm { k: 300 });
        w.push(Workload::Grazing { pairs: 50 });
        w.push(Workload::Parallel { pairs: 50 });
        w.push(Workload::Far { k: 100 });
        w.push(Workload::Walls {
            k: 30,
            n: 16,
            mode: CollisionMode::Bounce,
        });
        w.push(Workload::GasMix {
            k: 50,
            min_n: 3,
            max_n: 16,
        });
        w
    }

    /// The workloads of a full `kss-bench` run (the issue's matrix).
    pub fn full() -> Vec<Workload> {
        let mut w = Vec::new();
        for ratio in [10.0, 1e2, 1e3, 1e4, 1e5, 1e6] {
            for e in (4..=20).step_by(2) {
                w.push(Workload::Flypast {
                    n: 1 << e,
                    ratio,
                    seed: SEED,
                });
            }
        }
        for n in [8, 64, 1024] {
            for k in [100, 1000, 10_000, 100_000] {
                w.push(Workload::Gas {
                    k,
                    n,
                    collisions: 1000,
                });
            }
        }
        for k in [100, 1000, 10_000] {
            w.push(Workload::Cluster { k });
        }
        for k in [1000, 10_000, 100_000] {
            w.push(Workload::Swarm { k });
        }
        for pairs in [100, 1000] {
            w.push(Workload::Grazing { pairs });
            w.push(Workload::Parallel { pairs });
        }
        for k in [100, 1000, 10_000] {
            w.push(Workload::Far { k });
        }
        w.extend(Workload::set("cost").expect("the cost set"));
        w
    }
}

/// `k` octagons on a unit grid, circumradius `0.4995`, so neighbours are
/// `1/1000` apart at their closest, with slow random velocities.
fn cluster(k: usize) -> Scenario {
    let mut rng = Rng::with_stream(SEED, 0xc1u64);
    let cols = ((k as f64).sqrt().ceil() as usize).max(1);
    let width = (k.saturating_sub(1)).to_string().len();
    let polygons = (0..k)
        .map(|i| {
            let phase = rng.range_f64(0.0, TAU);
            let angle = rng.range_f64(0.0, TAU);
            let speed = rng.range_f64(0.005, 0.05);
            PolygonSpec {
                id: format!("c{i:0width$}"),
                vertices: gen::regular_polygon(8, 0.4995, phase),
                position: [(i % cols) as f64, (i / cols) as f64],
                velocity: [speed * angle.cos(), speed * angle.sin()],
                fixed: false,
            }
        })
        .collect();
    Scenario {
        until: 1.0,
        on_collision: CollisionMode::Remove,
        polygons,
        flight_plan_changes: Vec::new(),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_name_the_cost_workloads() {
        let names = |set: &str| -> Vec<String> {
            Workload::set(set)
                .unwrap()
                .iter()
                .map(Workload::name)
                .collect()
        };
        assert_eq!(
            names("cost"),
            [
                "walls-k1000-n16-bounce",
                "walls-k300-n256-bounce",
                "walls-k2000-n64-remove",
                "gasmix-k1000-n3to16",
            ]
        );
        let perf = names("perf");
        assert_eq!(perf[..4], names("cost")[..]);
        assert_eq!(perf[4..], ["gas-k10000-n8-c1000", "flypast-n65536-r1e3"]);
        for set in SETS {
            for w in Workload::set(set).unwrap() {
                assert_eq!(Workload::parse(&w.name()), Ok(w.clone()));
            }
        }
        assert!(Workload::set("walls").is_none());
        let full = Workload::full();
        assert!(Workload::set("cost")
            .unwrap()
            .iter()
            .all(|w| full.contains(w)));
    }

    #[test]
    fn walls_and_gasmix_parse_and_describe_themselves() {
        let w = Workload::parse("walls-k300-n256-bounce").unwrap();
        assert_eq!(
            w,
            Workload::Walls {
                k: 300,
                n: 256,
                mode: CollisionMode::Bounce
            }
        );
        assert_eq!(w.family(), "walls");
        assert_eq!(w.mode(), CollisionMode::Bounce);
        assert_eq!(w.series(), ("walls n=256 bounce".to_string(), 300.0));
        assert_eq!(w.vertices(), 300 * 256 + 16);
        assert_eq!(w.time_scale(), 1.0);
        let remove = Workload::parse("walls-k300-n256-remove").unwrap();
        assert_eq!(remove.mode(), CollisionMode::Remove);
        assert!(remove.all_pairs_work() < w.all_pairs_work());
        let g = Workload::parse("gasmix-k1000-n3to16").unwrap();
        assert_eq!(
            g,
            Workload::GasMix {
                k: 1000,
                min_n: 3,
                max_n: 16
            }
        );
        assert_eq!(g.family(), "gasmix");
        assert_eq!(g.mode(), CollisionMode::Remove);
        assert_eq!(g.all_pairs_work(), 1004.0 * 1003.0 / 2.0);
        // the old sparse octagon swarm keeps its name
        assert_eq!(
            Workload::parse("swarm-k1000").unwrap(),
            Workload::Swarm { k: 1000 }
        );
        for bad in [
            "walls-k10-n8-stop",
            "walls-k10-n8",
            "walls-k0-n8-bounce",
            "walls-k10-n2-remove",
            "gasmix-k10-n5to3",
            "gasmix-k10-n2to8",
            "gasmix-k10-n3-16",
            "gasmix-k10-n3",
        ] {
            assert!(Workload::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn walls_and_gasmix_build_their_scenarios() {
        let bounce = Workload::parse("walls-k30-n16-bounce").unwrap().scenario();
        let remove = Workload::parse("walls-k30-n16-remove").unwrap().scenario();
        assert_eq!(bounce.on_collision, CollisionMode::Bounce);
        assert_eq!(remove.on_collision, CollisionMode::Remove);
        assert_eq!(bounce.polygons, remove.polygons);
        assert_eq!(bounce.until, remove.until);
        assert_eq!(
            bounce,
            gen::swarm(&SwarmParams {
                k: 30,
                n: 16,
                seed: SEED,
                ..Default::default()
            })
        );
        bounce.validate().unwrap();
        let g = Workload::parse("gasmix-k50-n3to16").unwrap().scenario();
        assert_eq!(g.on_collision, CollisionMode::Remove);
        assert_eq!(g.until, 10.0);
        assert_eq!(g.polygons.len(), 54);
        assert!(g
            .polygons
            .iter()
            .filter(|p| !p.fixed)
            .all(|p| (3..=16).contains(&p.vertices.len())));
        g.validate().unwrap();
    }
}
