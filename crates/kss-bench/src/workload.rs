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
//!   `far-k<K>` (a gas of K octagons around coordinates 10^6, slowed down).

use std::f64::consts::TAU;

use kss::gen::{self, FlypastParams, GasParams};
use kss::rng::Rng;
use kss::{CollisionMode, PolygonSpec, Scenario};

/// The seed of every workload.
pub const SEED: u64 = 1;

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
        }
    }

    /// Parses [`Workload::name`].
    pub fn parse(s: &str) -> Result<Workload, String> {
        let bad = || {
            format!(
                "bad workload name {s:?}: expected flypast-n<N>-r<D/s>[-s<SEED>], gas-k<K>-n<N>-c<C>, cluster-k<K>, swarm-k<K>, grazing-p<P>, parallel-p<P> or far-k<K>"
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
        };
        if ok {
            Ok(())
        } else {
            Err(format!("workload {} is out of range", self.name()))
        }
    }

    /// The family (`flypast`, `gas`, `cluster`, `swarm`).
    pub fn family(&self) -> &'static str {
        match self {
            Workload::Flypast { .. } => "flypast",
            Workload::Gas { .. } => "gas",
            Workload::Cluster { .. } => "cluster",
            Workload::Swarm { .. } => "swarm",
            Workload::Grazing { .. } => "grazing",
            Workload::Parallel { .. } => "parallel",
            Workload::Far { .. } => "far",
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
        }
    }

    /// Total number of vertices (for the memory guard).
    pub fn vertices(&self) -> usize {
        match self {
            Workload::Flypast { n, .. } => 2 * n,
            Workload::Gas { k, n, .. } => k * n + 16,
            Workload::Cluster { k } | Workload::Swarm { k } | Workload::Far { k } => 8 * k,
            Workload::Grazing { pairs } | Workload::Parallel { pairs } => 16 * pairs,
        }
    }

    /// The pair computations of an all-pairs method on this workload, as a
    /// cost model for predicting its growth: every pair of bodies once at
    /// the start, and in `bounce` mode (the gas, with about as many
    /// collisions as the name says) both bodies of a collision against all
    /// others again. Flypast: one pair, however large the polygons.
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
        }
    }

    /// The workloads of `kss bench --quick`: tiny sizes.
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
        w
    }

    /// The workloads of a full `kss bench` (the issue's matrix).
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
    }
}
