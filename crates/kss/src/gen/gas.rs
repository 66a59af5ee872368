//! [`gas`] (random convex polygons in random motion, optionally in a box of
//! walls) and [`far`] (a gas scene far from the origin), with the walls and
//! the random polygons that other families share.

use super::InvalidParams;
use std::f64::consts::TAU;

use super::flypast::regular_polygon;
use super::hull::strict_convex_hull;
use super::{check_mode_until, check_or_panic, digits};
use crate::rng::Rng;
use crate::scenario::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario};

/// Parameters of [`gas`].
#[derive(Clone, Debug, PartialEq)]
pub struct GasParams {
    /// Number of moving polygons (walls not counted).
    pub k: usize,
    /// Fewest vertices of a polygon (at least 3).
    pub min_n: usize,
    /// Most vertices of a polygon.
    pub max_n: usize,
    /// Four fixed walls around the scene (thin rectangles with gaps at the
    /// corners, so that they do not touch each other).
    pub walls: bool,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the simulated interval.
    pub until: f64,
    /// Largest speed of a polygon.
    pub max_speed: f64,
    /// Number of random flight-plan changes.
    pub changes: usize,
    /// The seed.
    pub seed: u64,
}

impl Default for GasParams {
    fn default() -> Self {
        GasParams {
            k: 16,
            min_n: 3,
            max_n: 8,
            walls: false,
            mode: CollisionMode::Bounce,
            until: 10.0,
            max_speed: 1.0,
            changes: 0,
            seed: 0,
        }
    }
}

impl GasParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.k > 1 << 22 {
            return Err(InvalidParams(format!(
                "k is {}: at most 2^22 polygons",
                self.k
            )));
        }
        if self.min_n < 3 {
            return Err(InvalidParams(format!(
                "min_n is {}: a polygon needs 3 vertices",
                self.min_n
            )));
        }
        if self.max_n < self.min_n || self.max_n > 1 << 16 {
            return Err(InvalidParams(format!(
                "max_n is {}: it must be between min_n = {} and 65536",
                self.max_n, self.min_n
            )));
        }
        check_mode_until(Some(self.until))?;
        if !(self.max_speed.is_finite() && self.max_speed >= 0.0 && self.max_speed < 1e100) {
            return Err(InvalidParams(format!(
                "max_speed is {}: it must be a finite number >= 0",
                self.max_speed
            )));
        }
        if self.k == 0 && !self.walls {
            return Err(InvalidParams(
                "k is 0 and there are no walls: nothing to generate".to_string(),
            ));
        }
        Ok(())
    }
}

/// Random convex polygons with random velocities, each placed inside its own
/// cell of a unit grid (so they are disjoint at time 0), optionally inside a
/// box of four fixed walls.
///
/// Polygon `i` is called `g<i>` (zero-padded), the walls `wall-bottom`,
/// `wall-left`, `wall-right`, `wall-top`.
///
/// # Panics
///
/// If [`GasParams::check`] fails.
pub fn gas(params: &GasParams) -> Scenario {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 2);
    let k = params.k;
    let cols = ((k as f64).sqrt().ceil() as usize).max(1);
    let rows = k.div_ceil(cols).max(1);
    let cell = 1.0;
    let width = digits(k.saturating_sub(1));
    let mut polygons = Vec::with_capacity(k + 4);
    for i in 0..k {
        let (cx, cy) = ((i % cols) as f64 + 0.5, (i / cols) as f64 + 0.5);
        let radius = rng.range_f64(0.2, 0.4) * cell;
        let slack = 0.5 * cell - radius - 0.02 * cell;
        let centre = [
            cx * cell + rng.range_f64(-slack, slack),
            cy * cell + rng.range_f64(-slack, slack),
        ];
        let n = rng.range_usize(params.min_n, params.max_n);
        let vertices = random_convex_polygon(&mut rng, n, radius);
        let angle = rng.range_f64(0.0, TAU);
        let speed = params.max_speed * rng.range_f64(0.2, 1.0);
        polygons.push(PolygonSpec {
            id: format!("g{i:0width$}"),
            vertices,
            position: centre,
            velocity: [speed * angle.cos(), speed * angle.sin()],
            fixed: false,
        });
    }
    let mut changes = Vec::new();
    if k > 0 {
        for _ in 0..params.changes {
            let index = rng.below(k as u64) as usize;
            let mut time = rng.range_f64(0.0, params.until);
            if time <= 0.0 {
                time = params.until / 2.0;
            }
            let id = polygons[index].id.clone();
            if changes
                .iter()
                .any(|c: &FlightPlanChange| c.id == id && c.time == time)
            {
                continue;
            }
            let angle = rng.range_f64(0.0, TAU);
            let speed = params.max_speed * rng.range_f64(0.2, 1.0);
            changes.push(FlightPlanChange {
                time,
                id,
                velocity: [speed * angle.cos(), speed * angle.sin()],
            });
        }
    }
    if params.walls {
        polygons.extend(box_walls(cols as f64 * cell, rows as f64 * cell, cell));
    }
    Scenario {
        until: params.until,
        on_collision: params.mode,
        polygons,
        flight_plan_changes: changes,
        ..Default::default()
    }
}

/// Four fixed walls around `[0, w] x [0, h]`, `cell / 16` away from it, `cell /
/// 8` thick, leaving gaps at the corners.
pub(super) fn box_walls(w: f64, h: f64, cell: f64) -> Vec<PolygonSpec> {
    let g = cell / 16.0;
    let t = cell / 8.0;
    let rect = |id: &str, x: f64, y: f64, rw: f64, rh: f64| PolygonSpec {
        id: id.to_string(),
        vertices: vec![[0.0, 0.0], [rw, 0.0], [rw, rh], [0.0, rh]],
        position: [x, y],
        velocity: [0.0, 0.0],
        fixed: true,
    };
    vec![
        rect("wall-bottom", 0.0, -g - t, w, t),
        rect("wall-left", -g - t, 0.0, t, h),
        rect("wall-right", w + g, 0.0, t, h),
        rect("wall-top", 0.0, h + g, w, t),
    ]
}

/// A random convex polygon with at most `n` vertices (exactly `n` but for a
/// rare rounding casualty) inscribed in an ellipse of major radius `radius`
/// centred at the origin.
pub(super) fn random_convex_polygon(rng: &mut Rng, n: usize, radius: f64) -> Vec<[f64; 2]> {
    let aspect = rng.range_f64(0.6, 1.0);
    let rot = rng.range_f64(0.0, TAU);
    let (rs, rc) = rot.sin_cos();
    let phase = rng.range_f64(0.0, TAU);
    let step = TAU / n as f64;
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = phase + (i as f64 + 0.1 + 0.8 * rng.next_f64()) * step;
            let (s, c) = a.sin_cos();
            let (x, y) = (radius * c, radius * aspect * s);
            [rc * x - rs * y, rs * x + rc * y]
        })
        .collect();
    let hull = strict_convex_hull(&pts);
    if hull.len() >= 3 {
        hull
    } else {
        regular_polygon(n.max(3), radius, phase)
    }
}

// ---------------------------------------------------------------------------
// Far
// ---------------------------------------------------------------------------

/// Parameters of [`far`].
#[derive(Clone, Debug, PartialEq)]
pub struct FarParams {
    /// The gas scene before translation and slowing down.
    pub gas: GasParams,
    /// About how far the scene is moved (along x; y gets three quarters).
    pub offset: f64,
    /// Velocities are divided by this power of two and `until` (and the
    /// flight-plan change times) multiplied by it.
    pub slowdown: f64,
}

impl Default for FarParams {
    fn default() -> Self {
        FarParams {
            gas: GasParams::default(),
            offset: 1.0e6,
            slowdown: 1024.0,
        }
    }
}

impl FarParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        self.gas.check()?;
        if !(self.offset.is_finite() && self.offset.abs() <= 1e12) {
            return Err(InvalidParams(format!(
                "offset is {}: at most 1e12 in size",
                self.offset
            )));
        }
        let s = self.slowdown;
        if !((1.0..=1e9).contains(&s) && s.log2().fract() == 0.0) {
            return Err(InvalidParams(format!(
                "slowdown is {s}: it must be a power of two between 1 and 2^29"
            )));
        }
        if !(self.gas.until * s).is_finite() {
            return Err(InvalidParams("until times slowdown overflows".to_string()));
        }
        Ok(())
    }
}

/// A [`gas`] scene translated to coordinates around `offset` (plus a random
/// integer), its velocities slowed down by `slowdown` and its times stretched
/// accordingly. The translation goes into the positions of some polygons and
/// into the body-frame vertices of others (which are then rounded, and
/// re-hulled exactly so that they stay strictly convex).
///
/// # Panics
///
/// If [`FarParams::check`] fails.
pub fn far(params: &FarParams) -> Scenario {
    check_or_panic(params.check());
    let mut sc = gas(&params.gas);
    let mut rng = Rng::with_stream(params.gas.seed, 3);
    let off = [
        params.offset + rng.range_i64(0, 1000) as f64,
        0.75 * params.offset + rng.range_i64(0, 1000) as f64,
    ];
    let s = params.slowdown;
    for p in &mut sc.polygons {
        if rng.chance(0.5) {
            p.position = [p.position[0] + off[0], p.position[1] + off[1]];
        } else {
            let moved: Vec<[f64; 2]> = p
                .vertices
                .iter()
                .map(|v| [v[0] + off[0], v[1] + off[1]])
                .collect();
            let hull = strict_convex_hull(&moved);
            if hull.len() >= 3 {
                p.vertices = hull;
            } else {
                p.position = [p.position[0] + off[0], p.position[1] + off[1]];
            }
        }
        p.velocity = [p.velocity[0] / s, p.velocity[1] / s];
    }
    for c in &mut sc.flight_plan_changes {
        c.time *= s;
        c.velocity = [c.velocity[0] / s, c.velocity[1] / s];
    }
    sc.until *= s;
    sc
}
