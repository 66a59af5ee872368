//! [`churn`]: polygons entering and leaving while the scene runs.

use super::InvalidParams;
use std::f64::consts::TAU;

use super::gas::random_convex_polygon;
use super::{check_or_panic, digits};
use crate::rng::Rng;
use crate::scenario::{CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, Scenario};

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
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.k > 1 << 16 {
            return Err(InvalidParams(format!(
                "k is {}: at most 65536 polygons",
                self.k
            )));
        }
        if self.clusters > 1 << 10 {
            return Err(InvalidParams(format!(
                "clusters is {}: at most 1024",
                self.clusters
            )));
        }
        if !(self.until.is_finite() && (1.0..=1e6).contains(&self.until)) {
            return Err(InvalidParams(format!(
                "until is {}: it must be a number between 1 and 1e6",
                self.until
            )));
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
