//! Scenario generators, shared by the `kss gen` command, the tests and the
//! benchmarks.
//!
//! Every generator is a pure function of its parameters (seeded through the
//! hand-written [`Rng`], so a seed gives the same scenario forever) and returns
//! a [`Scenario`] that is valid per the contract: counter-clockwise strictly
//! convex polygons, unique ids, pairwise disjoint closed polygons at time 0,
//! flight-plan changes in `(0, until]`.
//!
//! The families ([`Family`]):
//!
//! - [`flypast`]: two congruent regular n-gons passing each other at a chosen
//!   minimum distance (or colliding);
//! - [`gas`]: many random convex polygons with random velocities, optionally in
//!   a box of four fixed walls;
//! - [`simultaneous`], [`grazing`], [`parallel`]: exact degeneracies (several
//!   pairs first touching at one instant, three polygons meeting at one point,
//!   tangential grazing contacts, edges sliding flush along a common line),
//!   built on small integers and dyadic numbers so that the degeneracies hold
//!   exactly in double arithmetic, not just approximately;
//! - [`far`]: a gas scene translated to coordinates around 10^6, slowed down.
//!
//! Beside the families, [`swarm`] makes the benchmarks' swarms: regular
//! n-gons in a box of walls, velocities in [-1, 1]², simulated long enough
//! for about 12 collisions per polygon ([`swarm_until`]), and [`churn`]
//! makes scenes whose polygons enter and leave while they run (the
//! contract's `insertions` and `removals`); neither has a small instance for
//! the test sweeps.
//!
//! [`generate_small`] makes a small random instance of any family, for
//! differential test sweeps over thousands of seeds. [`demo`] is the built-in
//! scene of `kss demo`.

use std::f64::consts::{PI, TAU};

use dashu_int::IBig;

use crate::rng::Rng;
use crate::scenario::{CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, Scenario};

// ---------------------------------------------------------------------------
// Families
// ---------------------------------------------------------------------------

/// The generator families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Two congruent regular n-gons passing each other ([`flypast`]).
    Flypast,
    /// Random convex polygons in random motion ([`gas`]).
    Gas,
    /// Pairs first touching at exactly one common instant, and three polygons
    /// meeting at one point ([`simultaneous`]).
    Simultaneous,
    /// Tangential grazing contacts ([`grazing`]).
    Grazing,
    /// Motion parallel to edges, edges flush ([`parallel`]).
    Parallel,
    /// A gas scene far from the origin ([`far`]).
    Far,
}

impl Family {
    /// Every family, in a fixed order.
    pub const ALL: [Family; 6] = [
        Family::Flypast,
        Family::Gas,
        Family::Simultaneous,
        Family::Grazing,
        Family::Parallel,
        Family::Far,
    ];

    /// The family's name on the command line (`"flypast"`, `"gas"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Family::Flypast => "flypast",
            Family::Gas => "gas",
            Family::Simultaneous => "simultaneous",
            Family::Grazing => "grazing",
            Family::Parallel => "parallel",
            Family::Far => "far",
        }
    }

    /// The family called `name` (as given by [`Family::name`]), if any.
    pub fn from_name(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == name)
    }

    /// A one-line description of the family.
    pub fn description(self) -> &'static str {
        match self {
            Family::Flypast => "two congruent regular n-gons passing each other at a chosen gap",
            Family::Gas => "random convex polygons with random velocities, optionally in a box",
            Family::Simultaneous => {
                "pairs first touching at one exact instant; three polygons meeting at a point"
            }
            Family::Grazing => {
                "tangential contacts: a vertex sliding along an edge's line, vertex-vertex grazes"
            }
            Family::Parallel => {
                "motion parallel to edges: edges flush, sliding along a common line"
            }
            Family::Far => "a gas scene translated to coordinates around 1e6, slowed down",
        }
    }
}

/// A collision mode drawn uniformly among stop, remove and bounce.
fn random_mode(rng: &mut Rng) -> CollisionMode {
    match rng.below(3) {
        0 => CollisionMode::Stop,
        1 => CollisionMode::Remove,
        _ => CollisionMode::Bounce,
    }
}

/// A small random instance of `family` for differential test sweeps: 2 to 8
/// polygons of 3 to about 12 vertices, a short `until`, a collision mode drawn
/// among stop, remove and bounce. The same `(family, seed)` always gives the
/// same scenario.
pub fn generate_small(family: Family, seed: u64) -> Scenario {
    let mut rng = Rng::with_stream(seed, 0x5ca1_ab1e ^ family as u64);
    let mode = random_mode(&mut rng);
    let sub_seed = rng.next_u64();
    match family {
        Family::Flypast => {
            let diameter = rng.range_f64(0.5, 2.0);
            let gap = match rng.below(4) {
                0 => 0.0,
                1 => -rng.range_f64(0.01, 0.3) * diameter,
                _ => rng.range_f64(0.001, 0.3) * diameter,
            };
            flypast(&FlypastParams {
                n: rng.range_usize(3, 12),
                diameter,
                gap,
                a_moving: rng.chance(0.5),
                speed: rng.range_f64(0.5, 2.0),
                mode,
                seed: sub_seed,
            })
        }
        Family::Gas | Family::Far => {
            let walls = rng.chance(0.4);
            let k = if walls {
                rng.range_usize(1, 4)
            } else {
                rng.range_usize(2, 8)
            };
            let min_n = rng.range_usize(3, 8);
            let gas_params = GasParams {
                k,
                min_n,
                max_n: rng.range_usize(min_n, 12),
                walls,
                mode,
                until: rng.range_f64(1.0, 4.0),
                max_speed: rng.range_f64(0.3, 2.0),
                changes: rng.range_usize(0, 3),
                seed: sub_seed,
            };
            if family == Family::Gas {
                gas(&gas_params)
            } else {
                far(&FarParams {
                    gas: gas_params,
                    offset: 1.0e6,
                    slowdown: 1024.0,
                })
            }
        }
        Family::Simultaneous => {
            let triple = rng.chance(0.5);
            let pairs = if triple {
                rng.range_usize(0, 2)
            } else {
                rng.range_usize(1, 3)
            };
            simultaneous(&SimultaneousParams {
                pairs,
                triple,
                mode,
                until: None,
                small: true,
                seed: sub_seed,
            })
        }
        Family::Grazing => grazing(&DegenerateParams {
            pairs: rng.range_usize(1, 4),
            mode,
            until: None,
            small: true,
            seed: sub_seed,
        }),
        Family::Parallel => parallel(&DegenerateParams {
            pairs: rng.range_usize(1, 4),
            mode,
            until: None,
            small: true,
            seed: sub_seed,
        }),
    }
}

/// Panics with the message of a failed parameter check.
fn check_or_panic(check: Result<(), String>) {
    if let Err(msg) = check {
        panic!("invalid generator parameters: {msg}");
    }
}

fn check_mode_until(until: Option<f64>) -> Result<(), String> {
    match until {
        Some(u) if !(u.is_finite() && u > 0.0) => {
            Err(format!("until is {u}: it must be a finite number > 0"))
        }
        _ => Ok(()),
    }
}

// ---------------------------------------------------------------------------
// Flypast
// ---------------------------------------------------------------------------

/// Parameters of [`flypast`].
#[derive(Clone, Debug, PartialEq)]
pub struct FlypastParams {
    /// Vertices of each polygon (3 to 2^24).
    pub n: usize,
    /// Diameter of the circumscribed circle of each polygon.
    pub diameter: f64,
    /// The minimum distance between the polygons during the motion; zero or
    /// negative: they collide (a negative gap is a penetration depth of the
    /// relative path into the Minkowski difference, at least `-diameter / 2`).
    pub gap: f64,
    /// Whether A moves too (A and B then move in opposite directions at half
    /// the speed each); otherwise A is fixed.
    pub a_moving: bool,
    /// The speed of B relative to A.
    pub speed: f64,
    /// Collision mode of the scenario.
    pub mode: CollisionMode,
    /// Seed of the rotations and the direction of motion.
    pub seed: u64,
}

impl Default for FlypastParams {
    fn default() -> Self {
        FlypastParams {
            n: 64,
            diameter: 1.0,
            gap: 0.1,
            a_moving: false,
            speed: 1.0,
            mode: CollisionMode::Stop,
            seed: 0,
        }
    }
}

impl FlypastParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), String> {
        if self.n < 3 || self.n > 1 << 24 {
            return Err(format!("n is {}: it must be between 3 and 2^24", self.n));
        }
        if !(self.diameter.is_finite() && self.diameter > 0.0 && self.diameter < 1e100) {
            return Err(format!(
                "diameter is {}: it must be a finite number > 0",
                self.diameter
            ));
        }
        if !(self.gap.is_finite() && self.gap >= -self.diameter / 2.0 && self.gap < 1e100) {
            return Err(format!(
                "gap is {}: it must be finite and at least -diameter/2 = {}",
                self.gap,
                -self.diameter / 2.0
            ));
        }
        if !(self.speed.is_finite() && self.speed > 0.0 && self.speed < 1e100) {
            return Err(format!(
                "speed is {}: it must be a finite number > 0",
                self.speed
            ));
        }
        Ok(())
    }
}

/// What [`flypast_with_info`] achieved.
#[derive(Clone, Debug, PartialEq)]
pub struct FlypastInfo {
    /// The minimum distance between the two polygons over the motion, computed
    /// from the exact values of the generated doubles (the sign is exact, the
    /// magnitude rounded); negative: the relative path enters the Minkowski
    /// difference that deep, so the polygons collide.
    pub achieved_gap: f64,
    /// About when the polygons are closest.
    pub closest_time: f64,
}

/// The vertices of a regular `n`-gon of circumradius `radius` centred at the
/// origin, counter-clockwise, vertex `k` at angle `phase + 2πk/n` (computed
/// with `sin_cos` and rounded to doubles; such polygons stay strictly convex
/// in double precision far beyond `n = 2^20`).
pub fn regular_polygon(n: usize, radius: f64, phase: f64) -> Vec<[f64; 2]> {
    let step = TAU / n as f64;
    (0..n)
        .map(|k| {
            let (s, c) = (phase + step * k as f64).sin_cos();
            [radius * c, radius * s]
        })
        .collect()
}

/// Two congruent regular n-gons `A` and `B`: `B` passes `A` along a straight
/// line at minimum distance `gap` (see [`FlypastParams`]).
///
/// # Panics
///
/// If [`FlypastParams::check`] fails.
pub fn flypast(params: &FlypastParams) -> Scenario {
    flypast_with_info(params).0
}

/// [`flypast`], also returning the achieved minimum distance.
///
/// The distance from the relative path `r0 + t·w` (a line) to the Minkowski
/// difference `M = A ⊕ (−B)` is `(cross(w, r0) − max_{m∈M} cross(w, m)) / |w|`
/// when the line passes on the far side of `M`, and the maximum over `M` is
/// the sum of the support values of `A` and `−B` (O(n), no Minkowski sum is
/// built). It is evaluated exactly on the generated doubles, and `B` is nudged
/// by a few ulps if rounding made a requested miss touch or a requested
/// collision miss.
///
/// # Panics
///
/// If [`FlypastParams::check`] fails.
pub fn flypast_with_info(params: &FlypastParams) -> (Scenario, FlypastInfo) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 1);
    let n = params.n;
    let d = params.diameter;
    let step = TAU / n as f64;
    let phase_a = rng.range_f64(0.05, 0.95) * step + 0.011_235_813;
    let theta = rng.range_f64(0.2, 0.8) * step;
    let a_body = regular_polygon(n, d / 2.0, phase_a);
    let b_body = regular_polygon(n, d / 2.0, phase_a + theta);
    let psi = rng.range_f64(0.15, PI / 2.0 - 0.15) + (rng.below(4) as f64) * (PI / 2.0);
    let w0 = [params.speed * psi.cos(), params.speed * psi.sin()];
    let (va, vb) = if params.a_moving {
        ([-w0[0] / 2.0, -w0[1] / 2.0], [w0[0] / 2.0, w0[1] / 2.0])
    } else {
        ([0.0, 0.0], w0)
    };
    // The exact relative velocity and its double approximation.
    let wr = [
        Dy::from_f64(vb[0]).sub(&Dy::from_f64(va[0])),
        Dy::from_f64(vb[1]).sub(&Dy::from_f64(va[1])),
    ];
    let w = [wr[0].to_f64(), wr[1].to_f64()];
    let wl2 = w[0] * w[0] + w[1] * w[1];
    let wl = wl2.sqrt();

    // max over M of cross(w, m) = max_a cross(w, a) - min_b cross(w, b).
    let max_m = exact_max_cross(&wr, w, &a_body, 1.0).add(&exact_max_cross(&wr, w, &b_body, -1.0));
    let max_m_f = max_m.to_f64();

    let tau = 1.5 * d / wl;
    let until = 2.0 * tau;
    let mut lambda = (max_m_f + params.gap * wl) / wl2;
    let place =
        |lambda: f64| -> [f64; 2] { [-tau * w[0] - lambda * w[1], -tau * w[1] + lambda * w[0]] };
    let want_hit = params.gap <= 0.0;
    let mut r0 = place(lambda);
    let mut delta = d * f64::EPSILON / wl.max(1e-300) * 0.25;
    let mut numerator = cross_dy(&wr, &r0).sub(&max_m);
    for _ in 0..400 {
        let hit = numerator.signum() <= 0;
        if hit == want_hit {
            break;
        }
        lambda += if want_hit { -delta } else { delta };
        delta *= 2.0;
        r0 = place(lambda);
        numerator = cross_dy(&wr, &r0).sub(&max_m);
    }
    let achieved_gap = numerator.to_f64() / wl;

    let scenario = Scenario {
        until,
        on_collision: params.mode,
        polygons: vec![
            PolygonSpec {
                id: "A".to_string(),
                vertices: a_body,
                position: [0.0, 0.0],
                velocity: va,
                fixed: !params.a_moving,
            },
            PolygonSpec {
                id: "B".to_string(),
                vertices: b_body,
                position: r0,
                velocity: vb,
                fixed: false,
            },
        ],
        flight_plan_changes: Vec::new(),
        ..Default::default()
    };
    (
        scenario,
        FlypastInfo {
            achieved_gap,
            closest_time: tau,
        },
    )
}

/// `max_i cross(w, sign * p_i)` exactly, with `w` exact (`wf` its double
/// approximation): doubles pick the candidates, exact arithmetic decides.
fn exact_max_cross(w: &[Dy; 2], wf: [f64; 2], pts: &[[f64; 2]], sign: f64) -> Dy {
    let vals: Vec<f64> = pts
        .iter()
        .map(|p| sign * (wf[0] * p[1] - wf[1] * p[0]))
        .collect();
    let best = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let scale = (wf[0].abs() + wf[1].abs())
        * pts
            .iter()
            .map(|p| p[0].abs() + p[1].abs())
            .fold(0.0, f64::max);
    let tol = scale * 1e-12 + 1e-300;
    let mut out: Option<Dy> = None;
    for (p, v) in pts.iter().zip(&vals) {
        if *v >= best - tol {
            let c = cross_dy(w, p);
            let c = if sign < 0.0 { c.neg() } else { c };
            out = Some(match out {
                Some(o) if o.cmp_val(&c) >= 0 => o,
                _ => c,
            });
        }
    }
    out.expect("a polygon has vertices")
}

/// `cross(w, p)` exactly.
fn cross_dy(w: &[Dy; 2], p: &[f64; 2]) -> Dy {
    w[0].mul(&Dy::from_f64(p[1]))
        .sub(&w[1].mul(&Dy::from_f64(p[0])))
}

// ---------------------------------------------------------------------------
// Gas
// ---------------------------------------------------------------------------

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
    pub fn check(&self) -> Result<(), String> {
        if self.k > 1 << 22 {
            return Err(format!("k is {}: at most 2^22 polygons", self.k));
        }
        if self.min_n < 3 {
            return Err(format!(
                "min_n is {}: a polygon needs 3 vertices",
                self.min_n
            ));
        }
        if self.max_n < self.min_n || self.max_n > 1 << 16 {
            return Err(format!(
                "max_n is {}: it must be between min_n = {} and 65536",
                self.max_n, self.min_n
            ));
        }
        check_mode_until(Some(self.until))?;
        if !(self.max_speed.is_finite() && self.max_speed >= 0.0 && self.max_speed < 1e100) {
            return Err(format!(
                "max_speed is {}: it must be a finite number >= 0",
                self.max_speed
            ));
        }
        if self.k == 0 && !self.walls {
            return Err("k is 0 and there are no walls: nothing to generate".to_string());
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

/// Number of decimal digits of `x`.
fn digits(x: usize) -> usize {
    x.to_string().len()
}

/// Four fixed walls around `[0, w] x [0, h]`, `cell / 16` away from it, `cell /
/// 8` thick, leaving gaps at the corners.
fn box_walls(w: f64, h: f64, cell: f64) -> Vec<PolygonSpec> {
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
fn random_convex_polygon(rng: &mut Rng, n: usize, radius: f64) -> Vec<[f64; 2]> {
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
    pub fn check(&self) -> Result<(), String> {
        self.gas.check()?;
        if !(self.offset.is_finite() && self.offset.abs() <= 1e12) {
            return Err(format!("offset is {}: at most 1e12 in size", self.offset));
        }
        let s = self.slowdown;
        if !((1.0..=1e9).contains(&s) && s.log2().fract() == 0.0) {
            return Err(format!(
                "slowdown is {s}: it must be a power of two between 1 and 2^29"
            ));
        }
        if !(self.gas.until * s).is_finite() {
            return Err("until times slowdown overflows".to_string());
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

// ---------------------------------------------------------------------------
// Swarm
// ---------------------------------------------------------------------------

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
    pub fn check(&self) -> Result<(), String> {
        if self.k == 0 || self.k > 1 << 22 {
            return Err(format!("k is {}: it must be between 1 and 2^22", self.k));
        }
        if self.n < 3 || self.n > 1 << 16 {
            return Err(format!("n is {}: it must be between 3 and 65536", self.n));
        }
        let c = self.collisions_per_polygon;
        if !(c.is_finite() && c > 0.0 && c <= 1e6) {
            return Err(format!(
                "collisions_per_polygon is {c}: it must be a number > 0 and at most 1e6"
            ));
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
/// velocity component uniform in `[-1, 1]`. The walls are those of [`gas`]
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

// ---------------------------------------------------------------------------
// Exact degeneracies on the integer lattice
// ---------------------------------------------------------------------------

/// A pair of polygons whose first contact is planned: `a < b` (byte-wise)
/// first touch exactly at `time` (their closed sets are disjoint before it).
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedContact {
    /// Byte-wise smaller id.
    pub a: String,
    /// Byte-wise larger id.
    pub b: String,
    /// The exact instant of first contact (a small integer).
    pub time: f64,
}

/// Parameters of [`simultaneous`].
#[derive(Clone, Debug, PartialEq)]
pub struct SimultaneousParams {
    /// Number of pairs first touching at the common instant.
    pub pairs: usize,
    /// Also three polygons meeting at one point at that instant.
    pub triple: bool,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the interval (default: a little after the contacts).
    pub until: Option<f64>,
    /// Small shapes and short times (for test sweeps).
    pub small: bool,
    /// The seed (shapes, offsets, velocities, orientation).
    pub seed: u64,
}

impl Default for SimultaneousParams {
    fn default() -> Self {
        SimultaneousParams {
            pairs: 3,
            triple: true,
            mode: CollisionMode::Stop,
            until: None,
            small: false,
            seed: 0,
        }
    }
}

impl SimultaneousParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), String> {
        if self.pairs == 0 && !self.triple {
            return Err("no pairs and no triple: nothing to generate".to_string());
        }
        if self.pairs > 100_000 {
            return Err(format!("pairs is {}: at most 100000", self.pairs));
        }
        check_mode_until(self.until)
    }
}

/// Parameters of [`grazing`] and [`parallel`].
#[derive(Clone, Debug, PartialEq)]
pub struct DegenerateParams {
    /// Number of pairs.
    pub pairs: usize,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the interval (default: a little after the last planned contact).
    pub until: Option<f64>,
    /// Small shapes and short times (for test sweeps).
    pub small: bool,
    /// The seed (shapes, offsets, velocities, orientation).
    pub seed: u64,
}

impl Default for DegenerateParams {
    fn default() -> Self {
        DegenerateParams {
            pairs: 4,
            mode: CollisionMode::Stop,
            until: None,
            small: false,
            seed: 0,
        }
    }
}

impl DegenerateParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), String> {
        if self.pairs == 0 {
            return Err("pairs is 0: nothing to generate".to_string());
        }
        if self.pairs > 100_000 {
            return Err(format!("pairs is {}: at most 100000", self.pairs));
        }
        check_mode_until(self.until)
    }
}

/// Several pairs of lattice polygons that first touch at exactly the same
/// instant `T` (vertex–edge, vertex–vertex or edge–edge, chosen at random),
/// and, with `triple`, three polygons whose apexes meet at one point at `T`.
/// Pairs live in lanes far apart. Pairs are `a<i>`/`b<i>`, the triple
/// `t0`, `t1`, `t2`.
///
/// # Panics
///
/// If [`SimultaneousParams::check`] fails.
pub fn simultaneous(params: &SimultaneousParams) -> Scenario {
    simultaneous_with_contacts(params).0
}

/// [`simultaneous`] with the planned first contacts.
///
/// # Panics
///
/// If [`SimultaneousParams::check`] fails.
pub fn simultaneous_with_contacts(params: &SimultaneousParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 4);
    let t = rng.range_i64(1, if params.small { 3 } else { 4 });
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let kind = if rng.chance(0.25) {
            PairKind::FlushApproach
        } else {
            PairKind::Approach
        };
        lat.pair(&mut rng, kind, t, i);
    }
    if params.triple {
        lat.triple(&mut rng, t, params.pairs);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// Pairs of lattice polygons that touch tangentially: relative motion exactly
/// parallel to the separating line, so that a vertex slides along the line of
/// an edge and reaches it, or two vertices graze each other for an instant.
/// Each pair has its own integer contact time.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn grazing(params: &DegenerateParams) -> Scenario {
    grazing_with_contacts(params).0
}

/// [`grazing`] with the planned first contacts.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn grazing_with_contacts(params: &DegenerateParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 5);
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let t = rng.range_i64(1, if params.small { 3 } else { 4 });
        lat.pair(&mut rng, PairKind::Graze, t, i);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// Pairs of lattice polygons with edges on a common line: sliding along it
/// until their corners meet and the edges go on flush, or edges hitting each
/// other flat. Each pair has its own integer contact time.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn parallel(params: &DegenerateParams) -> Scenario {
    parallel_with_contacts(params).0
}

/// [`parallel`] with the planned first contacts.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn parallel_with_contacts(params: &DegenerateParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 6);
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let t = rng.range_i64(1, if params.small { 3 } else { 4 });
        let kind = if rng.chance(0.65) {
            PairKind::Slide
        } else {
            PairKind::FlushApproach
        };
        lat.pair(&mut rng, kind, t, i);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// How the two polygons of a lattice pair meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PairKind {
    /// B comes down onto A, with a random sideways component.
    Approach,
    /// Two horizontal edges come together flat, overlapping.
    FlushApproach,
    /// Sideways motion along the separating line; at least one face is a vertex.
    Graze,
    /// Sideways motion along the separating line; both faces are edges.
    Slide,
}

/// A polygon being built on the lattice (canonical frame).
struct LatticeBody {
    id: String,
    vertices: Vec<[i64; 2]>,
    /// Position at the contact time `t`.
    pos_t: [i64; 2],
    velocity: [i64; 2],
    fixed: bool,
    /// The contact time of its group.
    t: i64,
}

/// Builds degenerate scenes in a canonical frame: in each pair, A is below the
/// horizontal separating line and B above it. Lanes are far apart along x. At
/// the end an orientation-preserving integer matrix and a power-of-two scale
/// are applied to everything, which keeps every contact time and every
/// degeneracy exact.
struct Lattice {
    bodies: Vec<LatticeBody>,
    contacts: Vec<(String, String, i64)>,
    small: bool,
}

const LANE: i64 = 160;

impl Lattice {
    fn new(small: bool) -> Lattice {
        Lattice {
            bodies: Vec::new(),
            contacts: Vec::new(),
            small,
        }
    }

    fn radius(&self, rng: &mut Rng) -> i64 {
        rng.range_i64(2, if self.small { 4 } else { 5 })
    }

    fn target_n(&self, rng: &mut Rng) -> usize {
        rng.range_usize(3, if self.small { 9 } else { 12 })
    }

    fn pair(&mut self, rng: &mut Rng, kind: PairKind, t: i64, lane: usize) {
        let (edge_a, edge_b) = match kind {
            PairKind::Approach => (rng.chance(0.5), rng.chance(0.5)),
            PairKind::FlushApproach | PairKind::Slide => (true, true),
            PairKind::Graze => match rng.below(3) {
                0 => (false, false),
                1 => (true, false),
                _ => (false, true),
            },
        };
        let (ra, na) = (self.radius(rng), self.target_n(rng));
        let a = lattice_polygon(rng, na, ra);
        let a = with_face(rng, a, edge_a, true);
        let (rb, nb) = (self.radius(rng), self.target_n(rng));
        let b = lattice_polygon(rng, nb, rb);
        let b = with_face(rng, b, edge_b, false);
        let (ha, a1, a2) = face(&a, true);
        let (lb, b1, b2) = face(&b, false);
        let dir = if rng.chance(0.5) { 1 } else { -1 };
        let s = match kind {
            PairKind::Approach => rng.range_i64(a1 - b2, a2 - b1),
            PairKind::FlushApproach => rng.range_i64(a1 - b2 + 1, a2 - b1 - 1),
            PairKind::Graze | PairKind::Slide => {
                if dir > 0 {
                    a1 - b2
                } else {
                    a2 - b1
                }
            }
        };
        let w = match kind {
            PairKind::Approach => [rng.range_i64(-2, 2), -rng.range_i64(1, 3)],
            PairKind::FlushApproach => [0, -rng.range_i64(1, 3)],
            PairKind::Graze | PairKind::Slide => [dir * rng.range_i64(1, 3), 0],
        };
        let fixed = rng.chance(0.3);
        let va = if fixed {
            [0, 0]
        } else {
            [rng.range_i64(-2, 2), rng.range_i64(-2, 2)]
        };
        let origin = [lane as i64 * LANE, 0];
        let (ida, idb) = (format!("a{lane}"), format!("b{lane}"));
        self.contacts.push((ida.clone(), idb.clone(), t));
        self.bodies.push(LatticeBody {
            id: ida,
            vertices: a,
            pos_t: origin,
            velocity: va,
            fixed,
            t,
        });
        self.bodies.push(LatticeBody {
            id: idb,
            vertices: b,
            pos_t: [origin[0] + s, origin[1] + ha - lb],
            velocity: [va[0] + w[0], va[1] + w[1]],
            fixed: false,
            t,
        });
    }

    /// Three polygons in disjoint angular sectors around a common apex, each
    /// moving towards the apex from inside its sector: they meet at the apex at
    /// time `t`, and only there.
    fn triple(&mut self, rng: &mut Rng, t: i64, lane: usize) {
        let k = rng.range_i64(3, 5);
        // First quadrant, directions between (4,1) and (1,4).
        let c1: Vec<[i64; 2]> = vec![[0, 0], [4, 1], [k, k], [1, 4]];
        // Its mirror image in the y axis (order reversed to stay CCW).
        let mut c2: Vec<[i64; 2]> = c1.iter().map(|p| [-p[0], p[1]]).collect();
        c2.reverse();
        c2.rotate_right(1);
        // Pointing down, directions between (-1,-3) and (1,-3).
        let c3: Vec<[i64; 2]> = vec![[0, 0], [-1, -3], [0, -4], [1, -3]];
        let mut shapes = [c1, c2, c3];
        for shape in shapes.iter_mut() {
            let f = rng.range_i64(1, 2);
            for p in shape.iter_mut() {
                *p = [p[0] * f, p[1] * f];
            }
        }
        let m = [
            rng.range_i64(1, 2),
            rng.range_i64(1, 2),
            rng.range_i64(1, 2),
        ];
        let vel = [[-m[0], -m[0]], [m[1], -m[1]], [0, m[2]]];
        let fixed_one = if rng.chance(0.3) {
            Some(rng.below(3) as usize)
        } else {
            None
        };
        let apex = [lane as i64 * LANE, 0];
        let ids = ["t0", "t1", "t2"];
        for (i, shape) in shapes.into_iter().enumerate() {
            let fixed = fixed_one == Some(i);
            self.bodies.push(LatticeBody {
                id: ids[i].to_string(),
                vertices: shape,
                pos_t: apex,
                velocity: if fixed { [0, 0] } else { vel[i] },
                fixed,
                t,
            });
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            self.contacts
                .push((ids[i].to_string(), ids[j].to_string(), t));
        }
    }

    /// Applies a random orientation-preserving lattice map and dyadic scale,
    /// adds flight-plan changes at or after the contacts, and builds the
    /// scenario.
    fn finish(
        self,
        rng: &mut Rng,
        mode: CollisionMode,
        until: Option<f64>,
    ) -> (Scenario, Vec<PlannedContact>) {
        const MAPS: [[i64; 4]; 6] = [
            [1, 0, 0, 1],
            [1, 1, 0, 1],
            [1, 0, 1, 1],
            [1, -1, 1, 1],
            [2, 1, 1, 1],
            [1, 2, 0, 1],
        ];
        const ROTS: [[i64; 4]; 4] = [[1, 0, 0, 1], [0, -1, 1, 0], [-1, 0, 0, -1], [0, 1, -1, 0]];
        let a = *rng.pick(&MAPS).expect("maps");
        let r = *rng.pick(&ROTS).expect("rotations");
        // m = r * a, row-major [m00, m01, m10, m11].
        let m = [
            r[0] * a[0] + r[1] * a[2],
            r[0] * a[1] + r[1] * a[3],
            r[2] * a[0] + r[3] * a[2],
            r[2] * a[1] + r[3] * a[3],
        ];
        let scale = 0.5f64.powi(rng.range_i64(0, 3) as i32);
        let map = |p: [i64; 2]| -> [f64; 2] {
            [
                (m[0] * p[0] + m[1] * p[1]) as f64 * scale,
                (m[2] * p[0] + m[3] * p[1]) as f64 * scale,
            ]
        };
        let t_max = self.bodies.iter().map(|b| b.t).max().unwrap_or(1);
        let until = until
            .unwrap_or_else(|| (t_max + rng.range_i64(0, if self.small { 2 } else { 3 })) as f64);
        let mut polygons = Vec::new();
        let mut changes = Vec::new();
        for body in &self.bodies {
            let p0 = [
                body.pos_t[0] - body.t * body.velocity[0],
                body.pos_t[1] - body.t * body.velocity[1],
            ];
            polygons.push(PolygonSpec {
                id: body.id.clone(),
                vertices: body.vertices.iter().map(|&v| map(v)).collect(),
                position: map(p0),
                velocity: map(body.velocity),
                fixed: body.fixed,
            });
            // A change exactly at the contact (it must act after the
            // collision) or later; never before, which keeps the contacts.
            if !body.fixed && rng.chance(0.25) {
                let time = body.t + rng.range_i64(0, 2);
                if (time as f64) <= until {
                    let v = [rng.range_i64(-2, 2), rng.range_i64(-2, 2)];
                    changes.push(FlightPlanChange {
                        time: time as f64,
                        id: body.id.clone(),
                        velocity: map(v),
                    });
                }
            }
        }
        let contacts = self
            .contacts
            .into_iter()
            .map(|(a, b, t)| {
                let (a, b) = if a.as_bytes() <= b.as_bytes() {
                    (a, b)
                } else {
                    (b, a)
                };
                PlannedContact {
                    a,
                    b,
                    time: t as f64,
                }
            })
            .collect();
        (
            Scenario {
                until,
                on_collision: mode,
                polygons,
                flight_plan_changes: changes,
                ..Default::default()
            },
            contacts,
        )
    }
}

/// A random lattice polygon: about `n` points near a circle of radius `r`,
/// rounded to integers, and their strict convex hull (at least 3 vertices).
fn lattice_polygon(rng: &mut Rng, n: usize, r: i64) -> Vec<[i64; 2]> {
    loop {
        let phase = rng.range_f64(0.0, TAU);
        let step = TAU / n as f64;
        let pts: Vec<[i64; 2]> = (0..n)
            .map(|i| {
                let a = phase + (i as f64 + 0.15 + 0.7 * rng.next_f64()) * step;
                let (s, c) = a.sin_cos();
                [(r as f64 * c).round() as i64, (r as f64 * s).round() as i64]
            })
            .collect();
        let hull = hull_i64(pts);
        if hull.len() >= 3 {
            return hull;
        }
    }
}

/// Adds a new top (`top`) or bottom face to `poly`, one row beyond it: an
/// edge (`edge`) or a single vertex.
fn with_face(rng: &mut Rng, mut poly: Vec<[i64; 2]>, edge: bool, top: bool) -> Vec<[i64; 2]> {
    let xmin = poly.iter().map(|p| p[0]).min().expect("non-empty");
    let xmax = poly.iter().map(|p| p[0]).max().expect("non-empty");
    let y = if top {
        poly.iter().map(|p| p[1]).max().expect("non-empty") + 1
    } else {
        poly.iter().map(|p| p[1]).min().expect("non-empty") - 1
    };
    if edge {
        let x1 = rng.range_i64(xmin, xmax - 1);
        let x2 = rng.range_i64(x1 + 1, xmax);
        poly.push([x1, y]);
        poly.push([x2, y]);
    } else {
        poly.push([rng.range_i64(xmin, xmax), y]);
    }
    hull_i64(poly)
}

/// The top (`top`) or bottom face of a lattice polygon: `(y, x_min, x_max)`.
fn face(poly: &[[i64; 2]], top: bool) -> (i64, i64, i64) {
    let y = if top {
        poly.iter().map(|p| p[1]).max()
    } else {
        poly.iter().map(|p| p[1]).min()
    }
    .expect("non-empty");
    let xs = poly.iter().filter(|p| p[1] == y).map(|p| p[0]);
    let lo = xs.clone().min().expect("non-empty");
    let hi = xs.max().expect("non-empty");
    (y, lo, hi)
}

/// Strict convex hull of integer points (exact), counter-clockwise.
fn hull_i64(mut pts: Vec<[i64; 2]>) -> Vec<[i64; 2]> {
    pts.sort();
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [i64; 2], a: [i64; 2], b: [i64; 2]| -> i128 {
        (a[0] - o[0]) as i128 * (b[1] - o[1]) as i128
            - (a[1] - o[1]) as i128 * (b[0] - o[0]) as i128
    };
    monotone_chain(&pts, |o, a, b| cross(o, a, b).signum() as i32)
}

/// Andrew's monotone chain over sorted, deduplicated points with the given
/// exact orientation test: strict hull, counter-clockwise.
fn monotone_chain<P: Copy>(pts: &[P], orient: impl Fn(P, P, P) -> i32) -> Vec<P> {
    let mut lower: Vec<P> = Vec::new();
    for &p in pts {
        while lower.len() >= 2 && orient(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<P> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && orient(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// The strict convex hull of `points` (exact predicates on the doubles):
/// counter-clockwise, no repeated points, no three consecutive collinear
/// vertices. Fewer than 3 points come back when all points are collinear.
pub fn strict_convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut pts: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup_by(|a, b| a[0] == b[0] && a[1] == b[1]);
    if pts.len() < 3 {
        return pts;
    }
    monotone_chain(&pts, orient_exact)
}

/// The sign of the orientation of `(a, b, c)`, exactly: 1 counter-clockwise,
/// -1 clockwise, 0 collinear. A floating-point filter (Shewchuk's first error
/// bound) settles most cases; the rest is computed on exact dyadic numbers.
pub fn orient_exact(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i32 {
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    let det = left - right;
    let sum = left.abs() + right.abs();
    // (3 + 16 eps) eps with eps = 2^-53.
    let bound = 3.330_669_073_875_471_6e-16 * sum;
    if sum > 1e-280 && sum.is_finite() {
        if det > bound {
            return 1;
        }
        if -det > bound {
            return -1;
        }
    }
    let d = |p: [f64; 2], q: [f64; 2], i: usize| Dy::from_f64(p[i]).sub(&Dy::from_f64(q[i]));
    d(a, c, 0)
        .mul(&d(b, c, 1))
        .sub(&d(a, c, 1).mul(&d(b, c, 0)))
        .signum()
}

/// An exact dyadic number `m * 2^e`: every finite double is one, and sums,
/// differences and products stay exact.
#[derive(Clone, Debug)]
struct Dy {
    m: IBig,
    e: i32,
}

impl Dy {
    fn from_f64(x: f64) -> Dy {
        assert!(x.is_finite(), "exact arithmetic on a non-finite number");
        if x == 0.0 {
            return Dy {
                m: IBig::ZERO,
                e: 0,
            };
        }
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i32;
        let frac = bits & ((1u64 << 52) - 1);
        let (mant, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), exp - 1075)
        };
        let m = IBig::from(mant);
        Dy {
            m: if bits >> 63 == 1 { -m } else { m },
            e,
        }
    }

    fn add(&self, o: &Dy) -> Dy {
        let e = self.e.min(o.e);
        let a = &self.m << (self.e - e) as usize;
        let b = &o.m << (o.e - e) as usize;
        Dy { m: a + b, e }
    }

    fn neg(&self) -> Dy {
        Dy {
            m: -self.m.clone(),
            e: self.e,
        }
    }

    fn sub(&self, o: &Dy) -> Dy {
        self.add(&o.neg())
    }

    fn mul(&self, o: &Dy) -> Dy {
        Dy {
            m: &self.m * &o.m,
            e: self.e + o.e,
        }
    }

    fn signum(&self) -> i32 {
        if self.m > IBig::ZERO {
            1
        } else if self.m < IBig::ZERO {
            -1
        } else {
            0
        }
    }

    fn cmp_val(&self, o: &Dy) -> i32 {
        self.sub(o).signum()
    }

    /// The nearest double, about (display and placement only).
    fn to_f64(&self) -> f64 {
        let mut x = self.m.to_f64().value();
        let mut e = self.e;
        while e > 0 {
            let k = e.min(1000);
            x *= 2f64.powi(k);
            e -= k;
        }
        while e < 0 {
            let k = e.max(-1000);
            x *= 2f64.powi(k);
            e -= k;
        }
        x
    }
}

// ---------------------------------------------------------------------------
// Churn: polygons entering and leaving during the run
// ---------------------------------------------------------------------------

/// Parameters of [`churn`].
#[derive(Clone, Debug, PartialEq)]
pub struct ChurnParams {
    /// Number of moving polygons present at time 0 (besides the two fixed
    /// ones and the head-on pair).
    pub k: usize,
    /// Number of clusters of polygons inserted during the run.
    pub clusters: usize,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the simulated interval.
    pub until: f64,
    /// The seed.
    pub seed: u64,
}

impl Default for ChurnParams {
    fn default() -> Self {
        ChurnParams {
            k: 12,
            clusters: 4,
            mode: CollisionMode::Remove,
            until: 8.0,
            seed: 0,
        }
    }
}

impl ChurnParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), String> {
        if self.k > 1 << 16 {
            return Err(format!("k is {}: at most 65536 polygons", self.k));
        }
        if self.clusters > 1 << 10 {
            return Err(format!("clusters is {}: at most 1024", self.clusters));
        }
        if !(self.until.is_finite() && (1.0..=1e6).contains(&self.until)) {
            return Err(format!(
                "until is {}: it must be a number between 1 and 1e6",
                self.until
            ));
        }
        Ok(())
    }
}

/// The time grid of [`churn`]: every scheduled time is a multiple of it, so
/// that coinciding instants coincide exactly.
const CHURN_TICK: f64 = 1.0 / 64.0;

/// Margin added to every clearance of [`churn`]'s placements.
const CHURN_MARGIN: f64 = 0.125;

/// A multiple of [`CHURN_TICK`] in `(lo, hi]`, or `None` if there is none.
fn tick_in(rng: &mut Rng, lo: f64, hi: f64) -> Option<f64> {
    let first = (lo / CHURN_TICK).floor() as i64 + 1;
    let last = (hi / CHURN_TICK).floor() as i64;
    (first <= last).then(|| rng.range_i64(first, last) as f64 * CHURN_TICK)
}

/// A multiple of [`CHURN_TICK`] in `(lo, hi)`, or `None` if there is none.
fn tick_before(rng: &mut Rng, lo: f64, hi: f64) -> Option<f64> {
    let first = (lo / CHURN_TICK).floor() as i64 + 1;
    let last = (hi / CHURN_TICK).ceil() as i64 - 1;
    (first <= last).then(|| rng.range_i64(first, last) as f64 * CHURN_TICK)
}

/// `x` rounded to a multiple of 1/16.
fn sixteenth(x: f64) -> f64 {
    (x * 16.0).round() / 16.0
}

/// A velocity of random direction and a speed in `[lo, hi)`.
fn random_velocity(rng: &mut Rng, lo: f64, hi: f64) -> [f64; 2] {
    let angle = rng.range_f64(0.0, TAU);
    let speed = rng.range_f64(lo, hi);
    [speed * angle.cos(), speed * angle.sin()]
}

/// One polygon of a [`churn`] scene while it is being planned.
struct ChurnMember {
    spec: PolygonSpec,
    /// Insertion time; 0 for the polygons present at the start.
    time: f64,
    removal: Option<f64>,
    changes: Vec<(f64, [f64; 2])>,
    /// The polygon's motion must stay undisturbed up to this time.
    protect: Option<f64>,
    /// Largest distance of a vertex from the body frame's origin.
    radius: f64,
    /// A bound on the polygon's speed at every instant of the run.
    reach: f64,
}

impl ChurnMember {
    fn new(spec: PolygonSpec, time: f64) -> ChurnMember {
        let radius = spec
            .vertices
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        ChurnMember {
            spec,
            time,
            removal: None,
            changes: Vec::new(),
            protect: None,
            radius,
            reach: 0.0,
        }
    }

    /// Adds a change at `time` if it lies in the polygon's lifetime and the
    /// polygon has none at that time yet.
    fn change(&mut self, time: f64, velocity: [f64; 2]) {
        let alive = time > self.time && self.removal.is_none_or(|r| time < r);
        if alive && !self.spec.fixed && self.changes.iter().all(|c| c.0 != time) {
            self.changes.push((time, velocity));
        }
    }
}

/// The area of a counter-clockwise polygon (shoelace formula).
fn area(vertices: &[[f64; 2]]) -> f64 {
    let n = vertices.len();
    0.5 * (0..n)
        .map(|i| {
            let (u, v) = (vertices[i], vertices[(i + 1) % n]);
            u[0] * v[1] - u[1] * v[0]
        })
        .sum::<f64>()
}

/// Whether a polygon of radius `radius` and speed bound `reach`, inserted
/// at `position` at `time` (protected up to `protect`), keeps clear of the
/// already placed member `other`: it is free at its insertion whatever
/// happened before (`other` cannot have travelled farther than its speed
/// bound allows), and neither can reach the other before a protected time
/// of either.
fn churn_clear(
    position: [f64; 2],
    radius: f64,
    reach: f64,
    time: f64,
    protect: Option<f64>,
    other: &ChurnMember,
) -> bool {
    let d = (position[0] - other.spec.position[0]).hypot(position[1] - other.spec.position[1]);
    let sizes = radius + other.radius + CHURN_MARGIN;
    if d <= sizes + other.reach * (time - other.time) {
        return false;
    }
    let guarded = protect
        .into_iter()
        .chain(other.protect)
        .fold(time, f64::max);
    guarded <= time || d > sizes + reach * (guarded - time) + other.reach * (guarded - other.time)
}

/// Polygons entering and leaving the scene while it runs, for the
/// `insertions` and `removals` of the contract, in any collision mode.
///
/// The scene, every scheduled time a multiple of 1/64 but for the changes
/// at the next double after an insertion:
///
/// - at time 0, `k` random convex polygons `g<i>` with random velocities
///   (speed below 1/2), each in its own 2 × 2 cell of a grid, and two fixed
///   polygons `f0`, `f1` in further cells;
/// - a head-on pair of unit squares `hx-a`, `hx-b` far from the others,
///   closing at speed 1 along a dyadic course so that they touch exactly at
///   a multiple of 1/64 in `[until/4, until/2]`, the instant at which `hx-b`
///   is removed (in `remove` mode the collision removes it first, and the
///   removal does nothing);
/// - `clusters` clusters `c<q>-<m>` inserted during the run: two to four
///   polygons 3/2 apart heading for the cluster's centre, where the first
///   one sits (fixed in cluster 0 and sometimes in others, then removed
///   later); one of a cluster's moving polygons changes its flight plan
///   right after the insertion (at the next double for even clusters, 1/64
///   later for odd ones);
/// - instants shared by several events: cluster 1 enters at the head-on
///   pair's collision and removal; cluster 2 enters at the removal of `f0`,
///   together with a fixed polygon `f0-next` of the same shape in the very
///   place `f0` leaves (the removals of an instant come before its
///   insertions), and with a flight-plan change of `g0`;
/// - random removals of the polygons (present at the start or inserted) and
///   random flight-plan changes inside their lifetimes.
///
/// Every inserted polygon is placed where nothing can be at its insertion
/// time: each polygon's speed is bounded for the whole run (its planned
/// speeds in `stop` and `remove` mode; in `bounce` mode the speed at which
/// it would carry all the kinetic energy ever given to the scene, with a
/// margin for the response's rounding), and the insertion keeps clear of
/// the disk every earlier polygon can have swept since its own start. The
/// head-on pair is kept clear the same way up to its collision. Only
/// `f0-next` relies on nothing touching `f0` at its removal, which takes a
/// collision at exactly that instant.
///
/// The scenario is valid; the same parameters always give the same one.
///
/// # Panics
///
/// If [`ChurnParams::check`] fails.
pub fn churn(params: &ChurnParams) -> Scenario {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 11);
    let (k, until) = (params.k, params.until);
    let late = 0.75 * until;
    let mut members: Vec<ChurnMember> = Vec::new();

    // The polygons present at time 0: k moving ones and f0, f1 in a grid.
    let cols = (((k + 2) as f64).sqrt().ceil() as usize).max(1);
    let rows = (k + 2).div_ceil(cols);
    let width = digits(k.saturating_sub(1));
    for i in 0..k + 2 {
        let cell = [2.0 * (i % cols) as f64 + 1.0, 2.0 * (i / cols) as f64 + 1.0];
        let fixed = i >= k;
        let radius = if fixed {
            rng.range_f64(0.3, 0.6)
        } else {
            rng.range_f64(0.25, 0.45)
        };
        let slack = 1.0 - radius - 0.125;
        let n = rng.range_usize(3, 8);
        let spec = PolygonSpec {
            id: if fixed {
                format!("f{}", i - k)
            } else {
                format!("g{i:0width$}")
            },
            vertices: random_convex_polygon(&mut rng, n, radius),
            position: [
                cell[0] + rng.range_f64(-slack, slack),
                cell[1] + rng.range_f64(-slack, slack),
            ],
            velocity: if fixed {
                [0.0, 0.0]
            } else {
                random_velocity(&mut rng, 0.1, 0.5)
            },
            fixed,
        };
        let mut m = ChurnMember::new(spec, 0.0);
        if !fixed && rng.chance(0.3) {
            m.removal = tick_in(&mut rng, 0.0, until);
        }
        members.push(m);
    }
    let f0 = k;
    let shared = tick_in(&mut rng, 0.0, late).expect("until >= 1");
    members[f0].removal = Some(shared);
    if k > 0 {
        // g0 stays at least until then, and changes its plan at that instant
        if members[0].removal.is_some_and(|r| r <= shared) {
            members[0].removal = None;
        }
        let v = random_velocity(&mut rng, 0.1, 0.5);
        members[0].change(shared, v);
    }
    for _ in 0..k / 2 {
        let i = rng.below(k as u64) as usize;
        let end = members[i].removal.unwrap_or(until + CHURN_TICK);
        if let Some(t) = tick_before(&mut rng, 0.0, end) {
            let v = random_velocity(&mut rng, 0.1, 0.5);
            members[i].change(t, v);
        }
    }

    // The head-on pair: facing edges 1 + contact apart, closing at speed 1.
    let contact = tick_in(&mut rng, 0.25 * until - CHURN_TICK, 0.5 * until).expect("until >= 1");
    let dy = rng.range_i64(-12, 12) as f64 / 16.0;
    let square = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    let pair = members.len();
    for (id, velocity) in [("hx-a", [0.5, 0.0]), ("hx-b", [-0.5, 0.0])] {
        let mut m = ChurnMember::new(
            PolygonSpec {
                id: id.to_string(),
                vertices: square.clone(),
                position: [0.0, 0.0],
                velocity,
                fixed: false,
            },
            0.0,
        );
        m.protect = Some(contact);
        members.push(m);
    }
    members[pair + 1].removal = Some(contact);

    // The clusters (placed later).
    let ring: [[f64; 2]; 4] = [[1.5, 0.0], [-1.5, 0.0], [0.0, 1.5], [0.0, -1.5]];
    let mut clusters: Vec<(f64, Vec<usize>)> = Vec::new();
    for q in 0..params.clusters {
        let time = match q {
            0 => tick_in(&mut rng, 0.0, 1.0f64.min(0.5 * until)).expect("until >= 1"),
            1 => contact,
            2 => shared,
            _ => tick_in(&mut rng, 0.0, late).expect("until >= 1"),
        };
        let mut offsets = ring;
        rng.shuffle(&mut offsets);
        let count = if q == 0 { 3 } else { rng.range_usize(2, 4) };
        let mut indices = Vec::with_capacity(count);
        for (m, offset) in std::iter::once([0.0, 0.0])
            .chain(offsets)
            .take(count)
            .enumerate()
        {
            let fixed = m == 0 && (q == 0 || rng.chance(0.4));
            let radius = rng.range_f64(0.25, 0.45);
            let n = rng.range_usize(3, 8);
            let velocity = if fixed {
                [0.0, 0.0]
            } else if m == 0 {
                random_velocity(&mut rng, 0.1, 0.5)
            } else {
                let angle = (-offset[1]).atan2(-offset[0]) + rng.range_f64(-0.3, 0.3);
                let speed = rng.range_f64(0.25, 0.5);
                [speed * angle.cos(), speed * angle.sin()]
            };
            let mut member = ChurnMember::new(
                PolygonSpec {
                    id: format!("c{q}-{m}"),
                    vertices: random_convex_polygon(&mut rng, n, radius),
                    // the offset from the cluster's centre until placed
                    position: offset,
                    velocity,
                    fixed,
                },
                time,
            );
            let removed = if fixed {
                q == 0 || rng.chance(0.5)
            } else {
                rng.chance(0.3)
            };
            if removed {
                member.removal = tick_in(&mut rng, time, until);
            }
            indices.push(members.len());
            members.push(member);
        }
        // a flight-plan change right after the insertion
        if let Some(&first) = indices.iter().find(|&&i| !members[i].spec.fixed) {
            let at = if q % 2 == 0 {
                time.next_up()
            } else {
                time + CHURN_TICK
            };
            if at <= until {
                let v = random_velocity(&mut rng, 0.1, 0.5);
                members[first].change(at, v);
            }
        }
        for &i in &indices {
            if !members[i].spec.fixed && rng.chance(0.3) {
                let end = members[i].removal.unwrap_or(until + CHURN_TICK);
                if let Some(t) = tick_before(&mut rng, time, end) {
                    let v = random_velocity(&mut rng, 0.1, 0.5);
                    members[i].change(t, v);
                }
            }
        }
        clusters.push((time, indices));
    }
    // f0's successor: the same fixed shape where f0 leaves, at that instant.
    let successor = members.len();
    let next = ChurnMember::new(
        PolygonSpec {
            id: "f0-next".to_string(),
            ..members[f0].spec.clone()
        },
        shared,
    );
    members.push(next);

    // Speed bounds.
    let kinetic = |m: &ChurnMember| {
        let a = area(&m.spec.vertices);
        std::iter::once(m.spec.velocity)
            .chain(m.changes.iter().map(|c| c.1))
            .map(|v| 0.5 * a * (v[0] * v[0] + v[1] * v[1]))
            .sum::<f64>()
    };
    let energy: f64 = members.iter().filter(|m| !m.spec.fixed).map(kinetic).sum();
    for m in &mut members {
        m.reach = if m.spec.fixed {
            0.0
        } else if params.mode == CollisionMode::Bounce {
            1.25 * (2.0 * energy / area(&m.spec.vertices)).sqrt() + CHURN_TICK
        } else {
            std::iter::once(m.spec.velocity)
                .chain(m.changes.iter().map(|c| c.1))
                .map(|v| v[0].hypot(v[1]))
                .fold(0.0, f64::max)
        };
    }
    let fastest = members.iter().map(|m| m.reach).fold(0.0, f64::max);

    // Placement: the pair, then the clusters in order of time.
    let centre = [cols as f64, rows as f64];
    let scene = centre[0].hypot(centre[1]) + 1.0;
    let mut placed: Vec<usize> = (0..pair).collect();
    let place = |rng: &mut Rng,
                 members: &mut [ChurnMember],
                 placed: &mut Vec<usize>,
                 group: &[usize],
                 time: f64| {
        let offsets: Vec<[f64; 2]> = group.iter().map(|&i| members[i].spec.position).collect();
        let mut distance = scene + 2.0 + fastest * time;
        loop {
            for _ in 0..16 {
                let angle = rng.range_f64(0.0, TAU);
                let at = [
                    sixteenth(centre[0] + distance * angle.cos()),
                    sixteenth(centre[1] + distance * angle.sin()),
                ];
                let clear = group.iter().zip(&offsets).all(|(&i, o)| {
                    let m = &members[i];
                    let p = [at[0] + o[0], at[1] + o[1]];
                    placed
                        .iter()
                        .all(|&j| churn_clear(p, m.radius, m.reach, time, m.protect, &members[j]))
                });
                if clear {
                    for (&i, o) in group.iter().zip(&offsets) {
                        members[i].spec.position = [at[0] + o[0], at[1] + o[1]];
                    }
                    placed.extend_from_slice(group);
                    return;
                }
            }
            distance *= 1.25;
        }
    };
    members[pair + 1].spec.position = [1.0 + contact, dy];
    place(&mut rng, &mut members, &mut placed, &[pair, pair + 1], 0.0);
    clusters.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (time, indices) in &clusters {
        if *time == shared {
            placed.push(successor);
        }
        place(&mut rng, &mut members, &mut placed, indices, *time);
    }
    if !placed.contains(&successor) {
        placed.push(successor);
    }

    // The scenario.
    let mut scenario = Scenario {
        until,
        on_collision: params.mode,
        ..Default::default()
    };
    for m in members {
        for (time, velocity) in m.changes {
            scenario.flight_plan_changes.push(FlightPlanChange {
                time,
                id: m.spec.id.clone(),
                velocity,
            });
        }
        if let Some(time) = m.removal {
            scenario.removals.push(Removal {
                time,
                id: m.spec.id.clone(),
            });
        }
        if m.time > 0.0 {
            scenario.insertions.push(Insertion {
                time: m.time,
                polygon: m.spec,
            });
        } else {
            scenario.polygons.push(m.spec);
        }
    }
    scenario
}

// ---------------------------------------------------------------------------
// Demo
// ---------------------------------------------------------------------------

/// The built-in scene of `kss demo`: nine convex polygons of various sizes in
/// a 16 x 10 box of four fixed walls (with gaps at the corners), bouncing,
/// with a few collisions in the first seconds. All coordinates are dyadic.
pub fn demo() -> Scenario {
    let poly =
        |id: &str, vertices: Vec<[f64; 2]>, position: [f64; 2], velocity: [f64; 2]| PolygonSpec {
            id: id.to_string(),
            vertices,
            position,
            velocity,
            fixed: false,
        };
    let mut polygons = vec![
        poly(
            "triangle",
            vec![[0.0, 0.0], [2.0, 0.0], [1.0, 1.75]],
            [1.0, 2.5],
            [2.0, 0.0],
        ),
        poly(
            "square",
            vec![[0.0, 0.0], [1.5, 0.0], [1.5, 1.5], [0.0, 1.5]],
            [7.0, 2.0],
            [-1.0, 0.25],
        ),
        poly(
            "hexagon",
            vec![
                [1.0, 0.0],
                [0.5, 0.875],
                [-0.5, 0.875],
                [-1.0, 0.0],
                [-0.5, -0.875],
                [0.5, -0.875],
            ],
            [12.5, 2.5],
            [-1.5, 0.5],
        ),
        poly(
            "pentagon",
            vec![
                [0.0, -1.0],
                [0.9375, -0.3125],
                [0.5625, 0.8125],
                [-0.5625, 0.8125],
                [-0.9375, -0.3125],
            ],
            [6.0, 7.5],
            [-0.75, 0.0],
        ),
        poly(
            "kite",
            vec![[0.0, -1.0], [0.5, 0.0], [0.0, 1.5], [-0.5, 0.0]],
            [2.0, 7.0],
            [1.5, 0.0],
        ),
        poly(
            "bar",
            vec![[0.0, 0.0], [4.0, 0.0], [4.0, 0.5], [0.0, 0.5]],
            [9.0, 8.0],
            [0.0, -0.75],
        ),
        poly(
            "octagon",
            vec![
                [0.75, 0.0],
                [0.5, 0.5],
                [0.0, 0.75],
                [-0.5, 0.5],
                [-0.75, 0.0],
                [-0.5, -0.5],
                [0.0, -0.75],
                [0.5, -0.5],
            ],
            [14.0, 6.5],
            [-1.0, -1.25],
        ),
        poly(
            "shard",
            vec![[0.0, 0.0], [1.25, -0.25], [0.5, 0.5]],
            [10.5, 5.0],
            [0.5, 1.0],
        ),
        poly(
            "boulder",
            vec![
                [1.5, 0.0],
                [1.25, 0.875],
                [0.5, 1.375],
                [-0.5, 1.375],
                [-1.25, 0.875],
                [-1.5, 0.0],
                [-1.25, -0.875],
                [-0.5, -1.375],
                [0.5, -1.375],
                [1.25, -0.875],
            ],
            [7.5, 5.25],
            [0.25, -0.125],
        ),
    ];
    polygons.extend(box_walls(16.0, 10.0, 4.0));
    Scenario {
        until: 12.0,
        on_collision: CollisionMode::Bounce,
        polygons,
        flight_plan_changes: vec![FlightPlanChange {
            time: 6.0,
            id: "boulder".to_string(),
            velocity: [-0.5, 0.5],
        }],
        ..Default::default()
    }
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    /// Contract checks in doubles and exact predicates; `Err` says what broke.
    pub(super) fn check_valid(sc: &Scenario) -> Result<(), String> {
        if !(sc.until.is_finite() && sc.until > 0.0) {
            return Err(format!("until {}", sc.until));
        }
        let mut ids = std::collections::HashSet::new();
        for p in &sc.polygons {
            if p.id.is_empty() || !ids.insert(p.id.clone()) {
                return Err(format!("bad or duplicate id {:?}", p.id));
            }
            check_polygon(&p.vertices).map_err(|e| format!("polygon {:?}: {e}", p.id))?;
            let nums = p
                .vertices
                .iter()
                .flatten()
                .chain(&p.position)
                .chain(&p.velocity);
            if nums.clone().any(|x| !x.is_finite()) {
                return Err(format!("polygon {:?}: non-finite number", p.id));
            }
            if p.fixed && p.velocity != [0.0, 0.0] {
                return Err(format!("fixed polygon {:?} moves", p.id));
            }
        }
        let mut seen = std::collections::HashSet::new();
        for c in &sc.flight_plan_changes {
            let Some(p) = sc.polygons.iter().find(|p| p.id == c.id) else {
                return Err(format!("change for unknown {:?}", c.id));
            };
            if p.fixed {
                return Err(format!("change for fixed {:?}", c.id));
            }
            if !(c.time > 0.0 && c.time <= sc.until) {
                return Err(format!("change time {} out of range", c.time));
            }
            if !seen.insert((c.id.clone(), c.time.to_bits())) {
                return Err(format!("duplicate change {:?} at {}", c.id, c.time));
            }
        }
        for i in 0..sc.polygons.len() {
            for j in i + 1..sc.polygons.len() {
                let (a, b) = (&sc.polygons[i], &sc.polygons[j]);
                if relation_at(a, b, &[], &[], 0.0) != Relation::Apart {
                    return Err(format!("{:?} and {:?} not disjoint at 0", a.id, b.id));
                }
            }
        }
        Ok(())
    }

    fn check_polygon(v: &[[f64; 2]]) -> Result<(), String> {
        let n = v.len();
        if n < 3 {
            return Err(format!("{n} vertices"));
        }
        let mut turning = 0.0;
        for i in 0..n {
            let (a, b, c) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
            if a == b {
                return Err(format!("repeated vertex {i}"));
            }
            if orient_exact(a, b, c) <= 0 {
                return Err(format!("not strictly convex CCW at vertex {i}"));
            }
            let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
            turning += (e1[0] * e2[1] - e1[1] * e2[0]).atan2(e1[0] * e2[0] + e1[1] * e2[1]);
        }
        if (turning - TAU).abs() > 1e-6 {
            return Err(format!("winds {} turns", turning / TAU));
        }
        Ok(())
    }

    #[derive(Debug, PartialEq, Eq)]
    pub(super) enum Relation {
        Apart,
        Touching,
        Overlapping,
    }

    /// Position of `p` at time `t` (exact dyadic), given its changes.
    fn position_at(p: &PolygonSpec, changes: &[FlightPlanChange], t: f64) -> [Dy; 2] {
        let mut ch: Vec<&FlightPlanChange> = changes.iter().filter(|c| c.id == p.id).collect();
        ch.sort_by(|a, b| a.time.total_cmp(&b.time));
        let mut pos = [Dy::from_f64(p.position[0]), Dy::from_f64(p.position[1])];
        let mut v = p.velocity;
        let mut now = Dy::from_f64(0.0);
        let tt = Dy::from_f64(t);
        for c in ch {
            if c.time >= t {
                break;
            }
            let ct = Dy::from_f64(c.time);
            let dt = ct.sub(&now);
            for k in 0..2 {
                pos[k] = pos[k].add(&dt.mul(&Dy::from_f64(v[k])));
            }
            now = ct;
            v = c.velocity;
        }
        let dt = tt.sub(&now);
        for k in 0..2 {
            pos[k] = pos[k].add(&dt.mul(&Dy::from_f64(v[k])));
        }
        pos
    }

    /// Exact relation of two polygons (no collision response) at time `t`.
    pub(super) fn relation_at(
        a: &PolygonSpec,
        b: &PolygonSpec,
        ca: &[FlightPlanChange],
        cb: &[FlightPlanChange],
        t: f64,
    ) -> Relation {
        let pa = position_at(a, ca, t);
        let pb = position_at(b, cb, t);
        let world = |p: &[Dy; 2], vs: &[[f64; 2]]| -> Vec<[Dy; 2]> {
            vs.iter()
                .map(|v| [p[0].add(&Dy::from_f64(v[0])), p[1].add(&Dy::from_f64(v[1]))])
                .collect()
        };
        let wa = world(&pa, &a.vertices);
        let wb = world(&pb, &b.vertices);
        // Quick filter in doubles: bounding boxes far apart.
        let bbox = |w: &[[Dy; 2]]| {
            let xs: Vec<f64> = w.iter().map(|p| p[0].to_f64()).collect();
            let ys: Vec<f64> = w.iter().map(|p| p[1].to_f64()).collect();
            let f = |v: &Vec<f64>, mx: bool| {
                v.iter()
                    .cloned()
                    .fold(if mx { f64::MIN } else { f64::MAX }, |x, y| {
                        if mx {
                            x.max(y)
                        } else {
                            x.min(y)
                        }
                    })
            };
            [f(&xs, false), f(&ys, false), f(&xs, true), f(&ys, true)]
        };
        let (ba, bb) = (bbox(&wa), bbox(&wb));
        let slack = 1e-6 * (1.0 + ba.iter().chain(&bb).fold(0.0f64, |m, x| m.max(x.abs())));
        if ba[2] + slack < bb[0]
            || bb[2] + slack < ba[0]
            || ba[3] + slack < bb[1]
            || bb[3] + slack < ba[1]
        {
            return Relation::Apart;
        }
        let mut weak = false;
        for (p, q) in [(&wa, &wb), (&wb, &wa)] {
            let n = p.len();
            for i in 0..n {
                let (s, e) = (&p[i], &p[(i + 1) % n]);
                let ex = e[0].sub(&s[0]);
                let ey = e[1].sub(&s[1]);
                let mut max_side = -2;
                for r in q.iter() {
                    let side = ex
                        .mul(&r[1].sub(&s[1]))
                        .sub(&ey.mul(&r[0].sub(&s[0])))
                        .signum();
                    max_side = max_side.max(side);
                    if max_side > 0 {
                        break;
                    }
                }
                if max_side < 0 {
                    return Relation::Apart;
                }
                if max_side == 0 {
                    weak = true;
                }
            }
        }
        if weak {
            Relation::Touching
        } else {
            Relation::Overlapping
        }
    }

    fn check_family_seed(f: Family, seed: u64) {
        let sc = generate_small(f, seed);
        if let Err(e) = check_valid(&sc) {
            panic!("{} seed {seed}: {e}\n{sc:#?}", f.name());
        }
        let n = sc.polygons.len();
        assert!(
            (2..=8).contains(&n),
            "{} seed {seed}: {n} polygons",
            f.name()
        );
        for p in &sc.polygons {
            assert!(
                (3..=14).contains(&p.vertices.len()),
                "{} seed {seed}: {} vertices",
                f.name(),
                p.vertices.len()
            );
        }
    }

    #[test]
    fn names_round_trip() {
        for f in Family::ALL {
            assert_eq!(Family::from_name(f.name()), Some(f));
            assert!(!f.description().is_empty());
        }
        assert_eq!(Family::from_name("nope"), None);
    }

    #[test]
    fn small_instances_are_valid() {
        for f in Family::ALL {
            for seed in 0..300 {
                check_family_seed(f, seed);
            }
        }
    }

    #[test]
    fn small_instances_are_deterministic() {
        for f in Family::ALL {
            for seed in [0, 1, 17, u64::MAX] {
                assert_eq!(generate_small(f, seed), generate_small(f, seed));
            }
            assert_ne!(generate_small(f, 1), generate_small(f, 2));
        }
    }

    #[test]
    fn small_instances_use_every_mode() {
        for f in Family::ALL {
            let modes: std::collections::HashSet<_> =
                (0..60).map(|s| generate_small(f, s).on_collision).collect();
            assert_eq!(modes.len(), 3, "{}", f.name());
        }
    }

    #[test]
    fn library_validate_accepts_every_family() {
        let defaults = [
            flypast(&FlypastParams::default()),
            gas(&GasParams {
                walls: true,
                changes: 4,
                ..Default::default()
            }),
            far(&FarParams::default()),
            simultaneous(&SimultaneousParams::default()),
            grazing(&DegenerateParams::default()),
            parallel(&DegenerateParams::default()),
            demo(),
        ];
        for sc in &defaults {
            sc.validate().unwrap();
        }
        for f in Family::ALL {
            for seed in 0..200 {
                let sc = generate_small(f, seed);
                if let Err(e) = crate::scenario::Scenario::validate(&sc) {
                    panic!("{} seed {seed}: {e}", f.name());
                }
            }
        }
    }

    #[test]
    fn brute_reports_the_planned_contacts() {
        // In stop mode the reference reports exactly the planned contacts at
        // the earliest planned instant.
        let options = crate::RunOptions {
            structure: crate::StructureKind::Brute,
            ..Default::default()
        };
        for seed in 0..40 {
            let p = DegenerateParams {
                pairs: 3,
                seed,
                small: seed % 2 == 0,
                ..Default::default()
            };
            let s = SimultaneousParams {
                pairs: 2,
                triple: true,
                seed,
                small: seed % 2 == 1,
                ..Default::default()
            };
            for (name, (sc, planned)) in [
                ("simultaneous", simultaneous_with_contacts(&s)),
                ("grazing", grazing_with_contacts(&p)),
                ("parallel", parallel_with_contacts(&p)),
            ] {
                let first = planned.iter().map(|c| c.time).fold(f64::MAX, f64::min);
                let mut want: Vec<(String, String, f64)> = planned
                    .iter()
                    .filter(|c| c.time == first)
                    .map(|c| (c.a.clone(), c.b.clone(), c.time))
                    .collect();
                want.sort_by(|x, y| {
                    (x.0.as_bytes(), x.1.as_bytes()).cmp(&(y.0.as_bytes(), y.1.as_bytes()))
                });
                let mut got = Vec::new();
                crate::run(&sc, &options, &mut |e| {
                    got.push((e.a.clone(), e.b.clone(), e.time.to_f64()))
                })
                .unwrap_or_else(|e| panic!("{name} seed {seed}: {e}"));
                assert_eq!(got, want, "{name} seed {seed}");
            }
        }
    }

    #[test]
    fn brute_agrees_with_flypast_gaps() {
        for method in [
            crate::brute::PairMethod::Simple,
            crate::brute::PairMethod::Fast,
        ] {
            let options = crate::RunOptions {
                structure: crate::StructureKind::Brute,
                pair_method: method,
                ..Default::default()
            };
            for seed in 0..12 {
                for (n, gap) in [
                    (3, 0.0),
                    (8, 1e-12),
                    (8, -1e-12),
                    (33, 0.0),
                    (64, 0.05),
                    (64, -0.05),
                ] {
                    let p = FlypastParams {
                        n,
                        gap,
                        a_moving: seed % 2 == 0,
                        seed,
                        ..Default::default()
                    };
                    let sc = flypast(&p);
                    let mut events = 0;
                    crate::run(&sc, &options, &mut |_| events += 1).unwrap();
                    assert_eq!(events, usize::from(gap <= 0.0), "{p:?}");
                }
            }
        }
    }

    fn check_planned(sc: &Scenario, contacts: &[PlannedContact]) {
        assert!(!contacts.is_empty());
        for c in contacts {
            let a = sc.polygons.iter().find(|p| p.id == c.a).expect("a");
            let b = sc.polygons.iter().find(|p| p.id == c.b).expect("b");
            assert!(c.a.as_bytes() < c.b.as_bytes());
            let ch = &sc.flight_plan_changes;
            assert_eq!(
                relation_at(a, b, ch, ch, c.time),
                Relation::Touching,
                "{} {} at {}",
                c.a,
                c.b,
                c.time
            );
            for k in [1, 3, 10, 30] {
                let t = c.time - 0.5f64.powi(k);
                if t >= 0.0 {
                    assert_eq!(
                        relation_at(a, b, ch, ch, t),
                        Relation::Apart,
                        "{} {} at {t}",
                        c.a,
                        c.b
                    );
                }
            }
        }
    }

    #[test]
    fn planned_contacts_are_exact() {
        for seed in 0..150 {
            for small in [true, false] {
                let (sc, c) = simultaneous_with_contacts(&SimultaneousParams {
                    pairs: 3,
                    triple: true,
                    small,
                    seed,
                    ..Default::default()
                });
                check_valid(&sc).unwrap();
                check_planned(&sc, &c);
                assert!(c.iter().all(|x| x.time == c[0].time));
                assert_eq!(c.len(), 6);
                let p = DegenerateParams {
                    pairs: 3,
                    small,
                    seed,
                    ..Default::default()
                };
                let (sc, c) = grazing_with_contacts(&p);
                check_valid(&sc).unwrap();
                check_planned(&sc, &c);
                let (sc, c) = parallel_with_contacts(&p);
                check_valid(&sc).unwrap();
                check_planned(&sc, &c);
            }
        }
    }

    #[test]
    fn grazing_contacts_are_tangential() {
        // Just after a grazing contact the pair is never overlapping.
        for seed in 0..100 {
            let (sc, contacts) = grazing_with_contacts(&DegenerateParams {
                pairs: 2,
                seed,
                ..Default::default()
            });
            for c in &contacts {
                let a = sc.polygons.iter().find(|p| p.id == c.a).unwrap();
                let b = sc.polygons.iter().find(|p| p.id == c.b).unwrap();
                let t = c.time + 0.5f64.powi(20);
                assert_ne!(relation_at(a, b, &[], &[], t), Relation::Overlapping);
            }
        }
    }

    #[test]
    fn gas_and_far_defaults_are_valid() {
        for seed in 0..10 {
            let g = GasParams {
                seed,
                walls: true,
                changes: 5,
                ..Default::default()
            };
            let sc = gas(&g);
            check_valid(&sc).unwrap();
            assert_eq!(sc.polygons.len(), 20);
            let f = far(&FarParams {
                gas: g,
                ..Default::default()
            });
            check_valid(&f).unwrap();
            assert!(f
                .polygons
                .iter()
                .all(|p| p.position[0] + p.vertices[0][0] > 9e5));
        }
        let sc = gas(&GasParams {
            k: 100,
            min_n: 3,
            max_n: 40,
            walls: false,
            ..Default::default()
        });
        check_valid(&sc).unwrap();
    }

    #[test]
    fn swarm_is_valid_and_deterministic() {
        for (k, n, seed) in [(1, 3, 0), (7, 16, 1), (30, 8, 2), (12, 256, 3)] {
            let p = SwarmParams {
                k,
                n,
                seed,
                ..Default::default()
            };
            let sc = swarm(&p);
            check_valid(&sc).unwrap_or_else(|e| panic!("{p:?}: {e}"));
            sc.validate().unwrap();
            assert_eq!(sc, swarm(&p));
            assert_eq!(sc.polygons.len(), k + 4);
            assert_eq!(sc.on_collision, CollisionMode::Bounce);
            let moving: Vec<&PolygonSpec> = sc.polygons.iter().filter(|p| !p.fixed).collect();
            let square: f64 = moving
                .iter()
                .map(|p| p.velocity[0] * p.velocity[0] + p.velocity[1] * p.velocity[1])
                .sum();
            let rms = (square / k as f64).sqrt();
            assert_eq!(sc.until, swarm_until(k, n, rms, 12.0));
            assert_eq!(moving.len(), k);
            for (i, m) in moving.iter().enumerate() {
                assert_eq!(m.vertices.len(), n);
                assert!(m.velocity.iter().all(|v| (-1.0..=1.0).contains(v)));
                assert_eq!(m.id.trim_start_matches('s').parse::<usize>(), Ok(i));
                assert_eq!(m.id.len(), 1 + digits(k - 1));
            }
            let walls: Vec<&str> = sc
                .polygons
                .iter()
                .filter(|p| p.fixed)
                .map(|p| p.id.as_str())
                .collect();
            assert_eq!(
                walls,
                ["wall-bottom", "wall-left", "wall-right", "wall-top"]
            );
        }
        let a = swarm(&SwarmParams::default());
        let b = swarm(&SwarmParams {
            seed: 1,
            ..Default::default()
        });
        assert_ne!(a, b);
        // remove mode: the same motions and until
        let r = swarm(&SwarmParams {
            mode: CollisionMode::Remove,
            ..Default::default()
        });
        assert_eq!((r.polygons, r.until), (a.polygons, a.until));
        let given = swarm(&SwarmParams {
            until: Some(2.5),
            ..Default::default()
        });
        assert_eq!(given.until, 2.5);
    }

    #[test]
    fn swarm_until_follows_the_curve() {
        let reference = (2.0f64 / 3.0).sqrt();
        for k in [1, 10, 300, 1000, 100_000] {
            for n in [3, 16, 256, 65536] {
                let mut last = 0.0;
                for c in [0.01, 0.1, 1.0, 3.0, 6.0, 12.0, 24.0, 100.0] {
                    let t = swarm_until(k, n, reference, c);
                    assert!(t.is_finite() && t > last, "k {k} c {c}: {t} after {last}");
                    last = t;
                    // twice as fast: half the time
                    let fast = swarm_until(k, n, 2.0 * reference, c);
                    assert!((fast - t / 2.0).abs() <= 1e-12 * t, "{fast} {t}");
                }
            }
            // rounder polygons and fewer walls collide more often
            assert!(swarm_until(k, 8, reference, 12.0) > swarm_until(k, 64, reference, 12.0));
        }
        assert!(swarm_until(100, 16, reference, 12.0) < swarm_until(1000, 16, reference, 12.0));
        // measured: 1000 16-gons, 12 per polygon about t = 4.9
        let t = swarm_until(1000, 16, reference, 12.0);
        assert!((4.6..5.2).contains(&t), "{t}");
        assert!(swarm_until(10, 16, 0.0, 12.0).is_finite());
    }

    #[test]
    fn swarm_refuses_bad_parameters() {
        let ok = SwarmParams::default();
        assert!(ok.check().is_ok());
        for (bad, want) in [
            (SwarmParams { k: 0, ..ok.clone() }, "k is 0"),
            (SwarmParams { n: 2, ..ok.clone() }, "n is 2"),
            (
                SwarmParams {
                    collisions_per_polygon: 0.0,
                    ..ok.clone()
                },
                "collisions_per_polygon is 0",
            ),
            (
                SwarmParams {
                    collisions_per_polygon: f64::NAN,
                    ..ok.clone()
                },
                "collisions_per_polygon is NaN",
            ),
            (
                SwarmParams {
                    until: Some(-1.0),
                    ..ok.clone()
                },
                "until is -1",
            ),
        ] {
            let e = bad.check().unwrap_err();
            assert!(e.contains(want), "{e}");
        }
    }

    #[test]
    fn flypast_gap_is_achieved() {
        for seed in 0..40 {
            for &(n, gap, a_moving) in &[
                (3usize, 0.1, false),
                (5, 0.0, true),
                (17, -0.2, false),
                (64, 1e-9, true),
                (100, 0.5, false),
                (1000, 0.0, false),
            ] {
                let p = FlypastParams {
                    n,
                    gap,
                    a_moving,
                    seed,
                    ..Default::default()
                };
                let (sc, info) = flypast_with_info(&p);
                check_valid(&sc).unwrap();
                assert_eq!(sc.polygons[0].vertices.len(), n);
                if gap > 0.0 {
                    assert!(info.achieved_gap > 0.0);
                    assert!((info.achieved_gap - gap).abs() <= 1e-12, "{info:?}");
                } else {
                    assert!(info.achieved_gap <= 0.0);
                    assert!((info.achieved_gap - gap).abs() <= 1e-12, "{info:?}");
                }
                // B passes completely: disjoint again at `until`.
                let (a, b) = (&sc.polygons[0], &sc.polygons[1]);
                assert_eq!(relation_at(a, b, &[], &[], sc.until), Relation::Apart);
                let mid = relation_at(a, b, &[], &[], info.closest_time);
                if gap > 1e-6 {
                    assert_eq!(mid, Relation::Apart);
                }
                if gap < -1e-6 {
                    assert_ne!(mid, Relation::Apart);
                }
            }
        }
    }

    #[test]
    fn flypast_sampled_distance_matches_gap() {
        // Sampling the motion finely: the smallest distance is close to the gap.
        let p = FlypastParams {
            n: 12,
            gap: 0.25,
            seed: 3,
            ..Default::default()
        };
        let sc = flypast(&p);
        let (a, b) = (&sc.polygons[0], &sc.polygons[1]);
        let mut best = f64::MAX;
        for i in 0..=20_000 {
            let t = sc.until * i as f64 / 20_000.0;
            let pa = [
                a.position[0] + t * a.velocity[0],
                a.position[1] + t * a.velocity[1],
            ];
            let pb = [
                b.position[0] + t * b.velocity[0],
                b.position[1] + t * b.velocity[1],
            ];
            for u in &a.vertices {
                for v in &b.vertices {
                    let dx = pa[0] + u[0] - pb[0] - v[0];
                    let dy = pa[1] + u[1] - pb[1] - v[1];
                    best = best.min((dx * dx + dy * dy).sqrt());
                }
            }
        }
        // Vertex-vertex distances bound the true distance from above.
        assert!((0.25 - 1e-9..0.25 + 0.05).contains(&best), "{best}");
    }

    #[test]
    fn flypast_huge_is_strictly_convex() {
        let p = FlypastParams {
            n: 1 << 20,
            gap: 0.01,
            ..Default::default()
        };
        let (sc, info) = flypast_with_info(&p);
        assert!(info.achieved_gap > 0.0);
        for poly in &sc.polygons {
            assert_eq!(poly.vertices.len(), 1 << 20);
            check_polygon(&poly.vertices).unwrap();
        }
    }

    #[test]
    fn hull_is_strict() {
        let pts = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 1.0],
            [0.0, 0.0],
        ];
        assert_eq!(
            strict_convex_hull(&pts),
            vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
        );
        // Collinear in exact arithmetic although doubles round the products.
        let a = [0.1, 0.1];
        let b = [0.2, 0.2];
        let c = [0.30000000000000004, 0.30000000000000004];
        assert_eq!(orient_exact(a, b, c), 0);
        assert_eq!(orient_exact([0.0, 0.0], [1.0, 0.0], [0.5, 1e-300]), 1);
    }

    #[test]
    fn demo_is_valid() {
        check_valid(&demo()).unwrap();
    }

    #[test]
    #[should_panic(expected = "invalid generator parameters")]
    fn bad_params_panic() {
        flypast(&FlypastParams {
            n: 2,
            ..Default::default()
        });
    }

    const MODES: [CollisionMode; 3] = [
        CollisionMode::Stop,
        CollisionMode::Remove,
        CollisionMode::Bounce,
    ];

    fn churn_of(seed: u64, mode: CollisionMode) -> Scenario {
        churn(&ChurnParams {
            mode,
            seed,
            ..Default::default()
        })
    }

    fn polygon_of<'a>(sc: &'a Scenario, id: &str) -> &'a PolygonSpec {
        sc.polygons
            .iter()
            .chain(sc.insertions.iter().map(|i| &i.polygon))
            .find(|p| p.id == id)
            .unwrap_or_else(|| panic!("no polygon {id}"))
    }

    fn removal_of(sc: &Scenario, id: &str) -> Option<f64> {
        sc.removals.iter().find(|r| r.id == id).map(|r| r.time)
    }

    #[test]
    fn churn_is_valid_and_deterministic() {
        for seed in 0..40 {
            for mode in MODES {
                let sc = churn_of(seed, mode);
                sc.validate()
                    .unwrap_or_else(|e| panic!("seed {seed} {mode:?}: {e}"));
                assert_eq!(sc, churn_of(seed, mode), "seed {seed}");
                assert_eq!(sc.on_collision, mode);
            }
        }
        for (k, clusters, until) in [(0, 0, 1.0), (1, 1, 1.0), (3, 2, 2.5), (40, 9, 20.0)] {
            let sc = churn(&ChurnParams {
                k,
                clusters,
                until,
                mode: CollisionMode::Bounce,
                seed: 5,
            });
            sc.validate()
                .unwrap_or_else(|e| panic!("k {k}, clusters {clusters}: {e}"));
            assert_eq!(sc.polygons.iter().filter(|p| !p.fixed).count(), k + 2);
        }
    }

    #[test]
    fn churn_has_the_planned_coincidences() {
        for seed in 0..20 {
            let sc = churn_of(seed, CollisionMode::Bounce);
            // the head-on pair touches exactly when hx-b is removed
            let (a, b) = (polygon_of(&sc, "hx-a"), polygon_of(&sc, "hx-b"));
            let gap = (b.position[0] - 0.5) - (a.position[0] + 0.5);
            let closing = a.velocity[0] - b.velocity[0];
            assert!((a.position[1] - b.position[1]).abs() < 1.0);
            assert_eq!(a.velocity[1], 0.0);
            assert_eq!(b.velocity[1], 0.0);
            let contact = gap / closing;
            assert_eq!(contact * closing, gap, "seed {seed}: inexact contact");
            assert_eq!(removal_of(&sc, "hx-b"), Some(contact), "seed {seed}");
            // a fixed polygon inserted, then removed
            assert!(
                sc.insertions.iter().any(|i| i.polygon.fixed
                    && removal_of(&sc, &i.polygon.id).is_some_and(|r| r > i.time)),
                "seed {seed}"
            );
            // a change at the next double after an insertion, of an inserted polygon
            assert!(
                sc.flight_plan_changes.iter().any(|c| sc
                    .insertions
                    .iter()
                    .any(|i| i.polygon.id == c.id && c.time == i.time.next_up())),
                "seed {seed}"
            );
            // insertions at the instants of the collision, of f0's removal
            // (with its successor in its place) and of a change
            let inserted_at = |t: f64| sc.insertions.iter().any(|i| i.time == t);
            assert!(inserted_at(contact), "seed {seed}");
            let f0 = polygon_of(&sc, "f0");
            let gone = removal_of(&sc, "f0").expect("f0 leaves");
            let next = sc
                .insertions
                .iter()
                .find(|i| i.polygon.id == "f0-next")
                .expect("f0 has a successor");
            assert_eq!(next.time, gone);
            assert_eq!(
                (&next.polygon.vertices, next.polygon.position),
                (&f0.vertices, f0.position)
            );
            assert!(sc
                .insertions
                .iter()
                .any(|i| i.time == gone && i.polygon.id != "f0-next"));
            assert!(sc
                .flight_plan_changes
                .iter()
                .any(|c| c.id == "g00" && c.time == gone));
        }
    }

    #[test]
    fn churn_runs_with_every_insertion_free_and_the_pair_touching_on_time() {
        for seed in 0..12 {
            for mode in MODES {
                let sc = churn_of(seed, mode);
                let contact = removal_of(&sc, "hx-b").expect("hx-b leaves");
                let mut events = Vec::new();
                crate::run(&sc, &crate::RunOptions::default(), &mut |e| {
                    events.push((e.time.to_f64(), e.a.clone(), e.b.clone()));
                })
                .unwrap_or_else(|e| panic!("seed {seed} {mode:?}: {e}"));
                // nothing reaches the pair before it touches; in stop mode
                // only if nothing else collided first
                let pair = (contact, "hx-a".to_string(), "hx-b".to_string());
                let first = events.first().map(|e| e.0);
                if mode != CollisionMode::Stop || first == Some(contact) {
                    assert!(events.contains(&pair), "seed {seed} {mode:?}: {events:?}");
                }
                assert!(
                    events.iter().all(|e| e.0 >= contact
                        || !(["hx-a", "hx-b"].contains(&e.1.as_str())
                            || ["hx-a", "hx-b"].contains(&e.2.as_str()))),
                    "seed {seed} {mode:?}: {events:?}"
                );
            }
        }
    }

    #[test]
    fn churn_refuses_bad_parameters() {
        for p in [
            ChurnParams {
                until: 0.5,
                ..Default::default()
            },
            ChurnParams {
                until: f64::INFINITY,
                ..Default::default()
            },
            ChurnParams {
                k: 1 << 20,
                ..Default::default()
            },
            ChurnParams {
                clusters: 5000,
                ..Default::default()
            },
        ] {
            assert!(p.check().is_err(), "{p:?}");
        }
        assert!(ChurnParams::default().check().is_ok());
    }
}
