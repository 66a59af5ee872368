//! [`swarm`]: the benchmarks' swarms of regular n-gons in a box of walls,
//! and [`swarm_until`], their calibrated end of the interval.

use super::InvalidParams;
use std::f64::consts::{PI, TAU};

use super::flypast::regular_polygon;
use super::gas::box_walls;
use super::{check_mode_until, check_or_panic, digits};
use crate::rng::Rng;
use crate::scenario::{CollisionMode, PolygonSpec, Scenario};

/// Parameters of [`swarm`].
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmParams {
    /// Number of moving polygons (walls not counted).
    pub k: usize,
    /// Vertices of every polygon (regular n-gons).
    pub n: usize,
    /// Collision mode.
    pub mode: CollisionMode,
    /// About how many collisions per polygon happen in `bounce` mode when
    /// `until` is not given (see [`swarm_until`]).
    pub collisions_per_polygon: f64,
    /// End of the simulated interval; `None`: calibrated from
    /// `collisions_per_polygon` and the generated velocities
    /// ([`swarm_until`]).
    pub until: Option<f64>,
    /// The seed.
    pub seed: u64,
}

impl Default for SwarmParams {
    fn default() -> Self {
        SwarmParams {
            k: 100,
            n: 16,
            mode: CollisionMode::Bounce,
            collisions_per_polygon: 12.0,
            until: None,
            seed: 0,
        }
    }
}

impl SwarmParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.k == 0 || self.k > 1 << 22 {
            return Err(InvalidParams(format!(
                "k is {}: it must be between 1 and 2^22",
                self.k
            )));
        }
        if self.n < 3 || self.n > 1 << 16 {
            return Err(InvalidParams(format!(
                "n is {}: it must be between 3 and 65536",
                self.n
            )));
        }
        let c = self.collisions_per_polygon;
        if !(c.is_finite() && c > 0.0 && c <= 1e6) {
            return Err(InvalidParams(format!(
                "collisions_per_polygon is {c}: it must be a number > 0 and at most 1e6"
            )));
        }
        check_mode_until(self.until)
    }
}

/// Collisions per polygon up to time `t` in the reference swarm: regular
/// polygons as round as disks (area fraction π·0.4²), no walls (k → ∞),
/// root-mean-square speed √(2/3) (the expected one of velocities uniform in
/// [-1, 1]²). Measured with `kss run` in `bounce` mode on the seed-1 swarms
/// of 300 16-, 64- and 256-gons, 1000 8- and 16-gons and 2000 64-gons, each
/// run's counts brought to the reference by [`swarm_until`]'s factors and
/// averaged: no collision until the gaps close, then about 2.4 per polygon
/// and unit of time.
const SWARM_CURVE: [(f64, f64); 15] = [
    (0.0, 0.0),
    (0.125, 0.041),
    (0.25, 0.32),
    (0.375, 0.65),
    (0.5, 0.99),
    (0.75, 1.64),
    (1.0, 2.27),
    (1.5, 3.52),
    (2.0, 4.75),
    (3.0, 7.18),
    (4.0, 9.60),
    (5.0, 12.03),
    (6.0, 14.39),
    (8.0, 19.19),
    (10.0, 23.98),
];

/// The walls' share of a swarm's collisions: a swarm of `k` polygons has
/// `1 + SWARM_WALLS / √k` times the collisions per polygon of an unbounded
/// one (fitted on k = 30 to 2000).
const SWARM_WALLS: f64 = 1.8;

/// The contact value of the pair correlation of hard disks at area
/// fraction `eta` (Henderson's formula): how much more often the polygons of
/// a dense swarm collide than those of a dilute one.
fn contact_factor(eta: f64) -> f64 {
    (1.0 - 7.0 * eta / 16.0) / ((1.0 - eta) * (1.0 - eta))
}

/// The `until` at which about `per_polygon` collisions per polygon have
/// happened in a `bounce`-mode [`swarm`] of `k` regular `n`-gons moving at
/// root-mean-square speed `rms_speed` (taken as at least 0.05).
///
/// The measured curve of collisions per polygon of a reference swarm
/// (interpolated, extrapolated linearly beyond its end) with three factors
/// on the rate of collisions: the swarm's speed over the reference's, the
/// walls (`1 + 1.8 / √k`), and the polygons' area fraction, through the
/// contact value of the pair correlation of hard disks (`(1 − 7η/16) / (1 −
/// η)²`, η the area of an n-gon of circumradius 0.4 in a unit cell: 8-gons
/// collide about 15 % less often than 64-gons). On the measured swarms (k =
/// 30 to 2000, seeds 1 to 4 at k = 30, 100 and 300) the count at this
/// `until` for 12 per polygon is within 4 % of 12 from k = 300 on, within
/// 10 % at k = 30 and 100.
pub fn swarm_until(k: usize, n: usize, rms_speed: f64, per_polygon: f64) -> f64 {
    let eta = |n: usize| {
        let n = n as f64;
        0.5 * n * SWARM_RADIUS * SWARM_RADIUS * (TAU / n).sin()
    };
    let density = contact_factor(eta(n.max(3))) / contact_factor(PI * SWARM_RADIUS * SWARM_RADIUS);
    let walls = 1.0 + SWARM_WALLS / (k.max(1) as f64).sqrt();
    let target = per_polygon / (density * walls);
    let speed = rms_speed.max(0.05) / (2.0f64 / 3.0).sqrt();
    let mut t = None;
    for w in SWARM_CURVE.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if target <= c1 {
            t = Some(t0 + (t1 - t0) * ((target - c0) / (c1 - c0)).max(0.0));
            break;
        }
    }
    let t = t.unwrap_or_else(|| {
        let [.., (ta, ca), (tb, cb)] = SWARM_CURVE;
        tb + (target - cb) * (tb - ta) / (cb - ca)
    });
    t / speed
}

/// Regular n-gons in a box of four fixed walls: polygon `i` sits in its own
/// cell of a unit grid `ceil(sqrt(k))` cells wide (circumradius 0.4, its
/// centre jittered by at most 0.05 from the cell's, so the polygons are
/// pairwise disjoint at time 0), turned by a random angle, with each
/// velocity component uniform in `[-1, 1]`. The walls are those of [`gas`](fn@super::gas)
/// (`cell / 16` outside the grid, gaps at the corners).
///
/// `until` is the given one, or calibrated for about
/// `collisions_per_polygon` collisions per polygon in `bounce` mode
/// ([`swarm_until`] of the generated velocities); other modes use the same
/// `until` and the same polygons, so a seed gives the same motions up to the
/// first collision in every mode.
///
/// Polygon `i` is called `s<i>` (zero-padded), the walls `wall-bottom`,
/// `wall-left`, `wall-right`, `wall-top`.
///
/// # Panics
///
/// If [`SwarmParams::check`] fails.
pub fn swarm(params: &SwarmParams) -> Scenario {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 7);
    let (k, n) = (params.k, params.n);
    let cols = ((k as f64).sqrt().ceil() as usize).max(1);
    let rows = k.div_ceil(cols).max(1);
    let width = digits(k - 1);
    let step = TAU / n as f64;
    let mut polygons = Vec::with_capacity(k + 4);
    for i in 0..k {
        let (cx, cy) = ((i % cols) as f64 + 0.5, (i / cols) as f64 + 0.5);
        let centre = [
            cx + rng.range_f64(-SWARM_JITTER, SWARM_JITTER),
            cy + rng.range_f64(-SWARM_JITTER, SWARM_JITTER),
        ];
        let phase = rng.range_f64(0.0, step);
        let velocity = [rng.range_f64(-1.0, 1.0), rng.range_f64(-1.0, 1.0)];
        polygons.push(PolygonSpec {
            id: format!("s{i:0width$}"),
            vertices: regular_polygon(n, SWARM_RADIUS, phase),
            position: centre,
            velocity,
            fixed: false,
        });
    }
    let until = params.until.unwrap_or_else(|| {
        let square: f64 = polygons
            .iter()
            .map(|p| p.velocity[0] * p.velocity[0] + p.velocity[1] * p.velocity[1])
            .sum();
        let rms_speed = (square / k as f64).sqrt();
        swarm_until(k, n, rms_speed, params.collisions_per_polygon)
    });
    polygons.extend(box_walls(cols as f64, rows as f64, 1.0));
    Scenario {
        until,
        on_collision: params.mode,
        polygons,
        flight_plan_changes: Vec::new(),
        ..Default::default()
    }
}

/// Circumradius of a [`swarm`]'s polygons, in grid cells.
const SWARM_RADIUS: f64 = 0.4;

/// Largest offset of a [`swarm`] polygon's centre from its cell's, per axis.
const SWARM_JITTER: f64 = 0.05;
