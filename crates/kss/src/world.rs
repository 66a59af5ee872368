//! The world: the table of moving bodies, their flight plans, and the
//! collision policy (`stop`, `remove`, `bounce`) shared by every structure.
//!
//! A structure (brute force, plain or hierarchical KSS) only finds *when* and
//! *which* polygons collide; the world decides what happens then, so that all
//! structures see the same trajectories and report the same events.
//!
//! ## Bounded numbers in `bounce` mode
//!
//! A bounce changes velocities at a rational collision time `t*`. Continuing
//! exactly from the position at `t*` would make every later collision time
//! depend on all earlier ones, and the integers would grow without bound. So a
//! bounced body takes a short *bridge*: from `t*` it moves in a straight line
//! to a dyadic anchor point `Q` that it reaches at a dyadic time `τ` slightly
//! after `t*` (`τ − t*` about `2^-36` of `t*`), and from `τ` on it moves with
//! the new velocity rounded to doubles. `Q` is the exact position the new
//! velocity would reach at `τ`, rounded to a grid about `2^-30` finer than
//! the distance covered, in the direction away from the contact partners, so
//! the bridge velocity differs from the new one by about `2^-30` of it
//! relatively, and the pair separates. Positions stay continuous, every
//! contact is still detected exactly, and all numbers after `τ` are dyadic
//! again, so their size stays bounded however long the run is. The same
//! bridge is used for a scenario flight-plan change that happens while a body
//! is on a bridge. `stop` and `remove` runs never need one.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::geom::{BodyPolygon, Point, PolygonDefect};
use crate::motion::{Frame, LinearPoint, Trajectory};
use crate::num::{Int, Interval, Rational, Sign, Time};
use crate::scenario::{CollisionMode, PolygonSpec, Scenario, ScenarioError};

/// Index of a body in the world.
///
/// Held as the index plus one, never zero, so that an
/// [`Obj`](crate::structure::Obj) (a body or `ω`) takes four bytes and a
/// point of the structure eight: the structure compares, hashes and copies
/// triples of points on every event. Ordered, hashed and printed by the
/// index.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct BodyId(std::num::NonZeroU32);

impl BodyId {
    /// The body of index `index` (below `u32::MAX`, which no body has).
    #[inline]
    pub const fn new(index: u32) -> BodyId {
        match std::num::NonZeroU32::new(index.wrapping_add(1)) {
            Some(n) => BodyId(n),
            None => panic!("a body index of u32::MAX"),
        }
    }

    /// As an index.
    #[inline]
    pub fn index(self) -> usize {
        self.raw() as usize
    }

    /// The index as a `u32`.
    #[inline]
    pub const fn raw(self) -> u32 {
        self.0.get() - 1
    }
}

impl std::hash::Hash for BodyId {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.raw().hash(state);
    }
}

impl std::fmt::Debug for BodyId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("BodyId").field(&self.raw()).finish()
    }
}

/// One polygon of the world.
#[derive(Clone, Debug)]
pub struct Body {
    /// The scenario id.
    pub id: String,
    /// The polygon in its body frame.
    pub shape: Arc<BodyPolygon>,
    /// Fixed bodies never move and have infinite mass.
    pub fixed: bool,
    /// False once removed (`remove` mode).
    pub alive: bool,
    /// Current piece of the path.
    pub traj: Trajectory,
    /// `traj` in integer form (shared with deferred failure times).
    pub frame: Arc<Frame>,
    /// Area (for bounce masses), as a double ([`Body::area`]), computed
    /// when first asked for (only a bounce needs it).
    area: LazyArea,
    /// Area centroid in the body frame ([`Body::centroid`]), computed
    /// when first asked for (only a bounce between non-parallel edges
    /// needs it).
    centroid: std::sync::OnceLock<Point>,
    /// Pending re-anchoring at the end of a bridge (see module docs).
    anchor: Option<(Time, u64)>,
    /// `traj`'s origin and velocity as doubles ([`Frame::motion_f64`]),
    /// for box filters.
    motion_f64: [f64; 4],
}

/// A double computed when first asked for, in one word (a `OnceLock<f64>`
/// takes two): the bits of the value, or [`LazyArea::UNSET`], a NaN that
/// no computation returns (an area is never NaN: it is a finite sum's
/// rounding, at most infinite).
#[derive(Debug)]
struct LazyArea(std::sync::atomic::AtomicU64);

impl LazyArea {
    const UNSET: u64 = 0x7ff8_dead_beef_0001;

    fn get_or_init(&self, f: impl FnOnce() -> f64) -> f64 {
        use std::sync::atomic::Ordering::Relaxed;
        let bits = self.0.load(Relaxed);
        if bits != Self::UNSET {
            return f64::from_bits(bits);
        }
        // (two threads may both compute it: the same value)
        let v = f();
        debug_assert_ne!(v.to_bits(), Self::UNSET);
        self.0.store(v.to_bits(), Relaxed);
        v
    }
}

impl Default for LazyArea {
    fn default() -> LazyArea {
        LazyArea(std::sync::atomic::AtomicU64::new(Self::UNSET))
    }
}

impl Clone for LazyArea {
    fn clone(&self) -> LazyArea {
        LazyArea(std::sync::atomic::AtomicU64::new(
            self.0.load(std::sync::atomic::Ordering::Relaxed),
        ))
    }
}

impl Body {
    /// The end `τ` of the bridge the body is on, if any: at `τ` its
    /// velocity changes to the one the bridge leads to (module docs).
    pub(crate) fn bridge_end(&self) -> Option<&Time> {
        self.anchor.as_ref().map(|(t, _)| t)
    }

    /// A body from its specification, its body frame's origin at
    /// `p.position` at time `t`; refuses a polygon or number that breaks
    /// the contract.
    pub(crate) fn new(p: &PolygonSpec, t: &Rational) -> Result<Body, ScenarioError> {
        let id = || p.id.clone();
        let shape = BodyPolygon::new(&p.vertices).map_err(|d| match d {
            PolygonDefect::TooFew => ScenarioError::TooFewVertices {
                id: id(),
                count: p.vertices.len(),
            },
            PolygonDefect::NonFinite(i) => ScenarioError::NonFinite {
                what: format!("polygon {:?} vertex {i}", p.id),
                value: if p.vertices[i][0].is_finite() {
                    p.vertices[i][1]
                } else {
                    p.vertices[i][0]
                },
            },
            PolygonDefect::Repeated(index) => ScenarioError::RepeatedVertex { id: id(), index },
            PolygonDefect::Collinear(index) => ScenarioError::CollinearVertices { id: id(), index },
            PolygonDefect::Clockwise => ScenarioError::Clockwise { id: id() },
            PolygonDefect::NotConvex(index) => ScenarioError::NotConvex { id: id(), index },
        })?;
        let position = finite_point(p.position, || format!("polygon {:?} position", p.id))?;
        let velocity = finite_point(p.velocity, || format!("polygon {:?} velocity", p.id))?;
        if p.fixed && !(velocity.x.is_zero() && velocity.y.is_zero()) {
            return Err(ScenarioError::FixedWithVelocity { id: id() });
        }
        let traj = Trajectory::through(t, &position, velocity);
        let frame = Arc::new(Frame::new(&traj, &shape));
        let motion = frame.motion_f64();
        Ok(Body {
            motion_f64: motion,
            id: p.id.clone(),
            shape: Arc::new(shape),
            fixed: p.fixed,
            alive: true,
            traj,
            frame,
            area: LazyArea::default(),
            centroid: std::sync::OnceLock::new(),
            anchor: None,
        })
    }

    /// The polygon's area (its mass in a bounce), the exact area rounded
    /// to a double.
    pub fn area(&self) -> f64 {
        self.area
            .get_or_init(|| self.shape.twice_area().to_f64() / 2.0)
    }

    /// The area centroid in the body frame, exactly.
    pub fn centroid(&self) -> &Point {
        self.centroid.get_or_init(|| self.shape.centroid())
    }

    /// A box `[x_min, x_max, y_min, y_max]` that holds the polygon at time
    /// `t`, in doubles, widened by far more than their rounding (a
    /// coordinate out of the doubles' range makes it infinite or NaN: the
    /// caller treats such a box as deciding nothing).
    pub fn bounds_f64(&self, t: f64) -> [f64; 4] {
        let [ox, oy, vx, vy] = self.motion_f64;
        let bx = self.shape.bounds();
        let (x, y) = (ox + vx * t, oy + vy * t);
        let scale = ox.abs() + oy.abs() + (vx.abs() + vy.abs()) * t.abs();
        let pad = 1e-9 * (scale + bx.iter().map(|c| c.abs()).sum::<f64>()) + 1e-300;
        [
            bx[0] + x - pad,
            bx[1] + x + pad,
            bx[2] + y - pad,
            bx[3] + y + pad,
        ]
    }

    /// The moving world position of vertex `i` on the current piece.
    pub fn vertex(&self, i: usize) -> LinearPoint {
        self.frame.vertex(&self.shape, i)
    }

    /// Exact world position of vertex `i` at rational time `t`.
    pub fn vertex_at(&self, i: usize, t: &Rational) -> Point {
        self.traj.position_at(t).add(&self.shape.vertex(i))
    }

    /// Whether this body and `other` move with one velocity on their
    /// current pieces, exactly (their frames' velocity enclosures tell most
    /// apart without reading a bridge's velocity, which would reduce it).
    pub fn same_velocity(&self, other: &Body) -> bool {
        let apart = |a: crate::num::Interval, b: crate::num::Interval| a.hi < b.lo || b.hi < a.lo;
        let [ax, ay] = self.frame.velocity_enclosure();
        let [bx, by] = other.frame.velocity_enclosure();
        if apart(ax, bx) || apart(ay, by) {
            // (on copies, which leave a bridge unreduced)
            debug_assert_ne!(self.traj.clone().velocity(), other.traj.clone().velocity());
            return false;
        }
        self.traj.velocity() == other.traj.velocity()
    }

    fn set_traj(&mut self, traj: Trajectory) {
        let frame = Frame::new(&traj, &self.shape);
        self.set_traj_frame(traj, frame);
    }

    /// [`Body::set_traj`] with the trajectory's frame made already.
    fn set_traj_frame(&mut self, traj: Trajectory, frame: Frame) {
        self.frame = Arc::new(frame);
        self.motion_f64 = self.frame.motion_f64();
        self.traj = traj;
    }
}

/// A pending velocity change.
#[derive(Clone, Debug)]
struct Change {
    body: BodyId,
    velocity: Point,
    /// For the end of a bridge, the body's position there (the bridge's
    /// dyadic end point); `None` for a scenario change.
    anchor: Option<Point>,
}

/// Where two touching bodies touch.
#[derive(Clone, Debug)]
struct ContactGeometry {
    /// The one vertex the polygons share, when a hint proved that they
    /// touch there only (a vertex of `b`: `true`, or of `a`, and its
    /// index); `None` from the pass over `M`.
    single: Option<(bool, usize)>,
    /// The contract's normal, from `a` to `b`.
    normal: Point,
    /// Normals (from `a` to `b`) of the edges of `M` active at the contact.
    edge_normals: Vec<Point>,
    /// The active edges of `M`: the touched edge (`Ok(j)`: of `b`, `Err(i)`:
    /// of `a`) and the touching vertex of the other body.
    features: Vec<(Result<usize, usize>, usize)>,
}

/// Why [`World::insert`] refused a polygon.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Refused {
    /// It breaks a rule of the contract.
    Invalid(ScenarioError),
    /// It touches or overlaps this alive body.
    Touches(BodyId),
}

/// Ids of bodies whose trajectory changed, for the structure to update.
pub type Changed = Vec<BodyId>;

/// The world: bodies, pending flight-plan changes, the collision policy.
#[derive(Clone, Debug)]
pub struct World {
    bodies: Vec<Body>,
    /// How many of `bodies` are alive ([`World::alive_count`]).
    alive: usize,
    mode: CollisionMode,
    until: Time,
    until_f64: f64,
    changes: BTreeMap<(Time, u64), Change>,
    seq: u64,
    /// The instant of the last bounce and how often each pair was resolved then.
    bounce_instant: Option<Rational>,
    bounce_rounds: BTreeMap<(BodyId, BodyId), u32>,
    /// The latest contact computed ([`World::contact`]): a collision's
    /// point and its bounce response ask for the same one.
    last_contact: ContactMemo,
    /// The Minkowski differences of recent pairs of large polygons
    /// ([`World::minkowski`]).
    minkowski: MinkowskiCache,
    /// Where a structure found contacts of the latest instant
    /// ([`World::hint_contact`]).
    hints: ContactHints,
}

/// A contact as a structure found it: at `t`, vertex `vertex.1` of body
/// `vertex.0` on edge `edge.1` (from vertex `edge.1` to the next) of body
/// `edge.0`. Only a hint: [`World::contact`] checks it exactly.
#[derive(Clone, Debug)]
struct ContactHint {
    t: Rational,
    vertex: (BodyId, usize),
    edge: (BodyId, usize),
}

/// The hints of the latest instant (a few: one per contact; a clone starts
/// empty).
#[derive(Debug, Default)]
struct ContactHints(std::sync::Mutex<Vec<ContactHint>>);

impl Clone for ContactHints {
    fn clone(&self) -> ContactHints {
        ContactHints::default()
    }
}

/// The most hints kept for one instant.
const MAX_HINTS: usize = 16;

/// The edges of `M = B ⊕ (−A)` for a pair of body polygons, with their
/// common exponent ([`crate::geom::minkowski_edges_filtered`]).
pub(crate) type MinkowskiEdges = Arc<(Vec<crate::geom::FilteredEdge>, i64)>;

/// The number of entries of a [`MinkowskiCache`].
const MINKOWSKI_SLOTS: usize = 4;

/// The Minkowski differences of recent pairs of polygons, direct-mapped
/// and keyed by the two polygons themselves (each entry holds both, so
/// neither address can be reused while it is kept; a clone starts
/// empty). A body's polygon never changes in its own frame, so the
/// difference of a pair is the same at every instant: the collision
/// response asks for it several times (the contact, its point, the
/// reference's rule for the touch and after the response).
#[derive(Debug, Default)]
struct MinkowskiCache(std::sync::Mutex<Vec<MinkowskiEntry>>);

/// One entry of a [`MinkowskiCache`].
type MinkowskiEntry = Option<(Arc<BodyPolygon>, Arc<BodyPolygon>, MinkowskiEdges)>;

impl Clone for MinkowskiCache {
    fn clone(&self) -> MinkowskiCache {
        MinkowskiCache::default()
    }
}

/// The key of a [`ContactMemo`]: the two bodies, their frames
/// ([`Frame::uid`], never reused: a motion change is a new frame) and the
/// instant.
type ContactKey = (BodyId, BodyId, u64, u64, Rational);

/// The latest [`World::contact`] and what it was asked for (a clone starts
/// empty).
#[derive(Debug, Default)]
struct ContactMemo(std::sync::Mutex<Option<(ContactKey, Option<ContactGeometry>)>>);

impl ContactMemo {
    /// Body `id` took frame `new` in place of `old` at instant `t`, its
    /// position at `t` unchanged (a motion change keeps the position
    /// continuous): a contact at `t` depends only on the positions at `t`
    /// and the shapes, so the entry of `t` holds under the new frame too
    /// (the response's own check of the pair finds it).
    fn moved(&self, id: BodyId, old: u64, new: u64, t: &Rational) {
        let mut memo = self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(((ka, kb, ua, ub, kt), _)) = memo.as_mut() {
            if kt == t {
                if *ka == id && *ua == old {
                    *ua = new;
                }
                if *kb == id && *ub == old {
                    *ub = new;
                }
            }
        }
    }
}

impl Clone for ContactMemo {
    fn clone(&self) -> ContactMemo {
        ContactMemo::default()
    }
}

/// A collision found by a structure: bodies `a` and `b` touch at `time`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contact {
    /// Exact time.
    pub time: Rational,
    /// One body.
    pub a: BodyId,
    /// The other body.
    pub b: BodyId,
}

impl World {
    /// Validate `scenario` and build the world at time 0. `until` replaces the
    /// scenario's `until` (flight-plan changes after it are dropped).
    pub fn new(scenario: &Scenario, until: Option<f64>) -> Result<World, ScenarioError> {
        let until_f64 = until.unwrap_or(scenario.until);
        for u in [Some(scenario.until), until].into_iter().flatten() {
            if !(u.is_finite() && u > 0.0) {
                return Err(ScenarioError::BadUntil(u));
            }
        }
        let mut ids: BTreeMap<&str, usize> = BTreeMap::new();
        let mut bodies = Vec::with_capacity(scenario.polygons.len());
        for (index, p) in scenario.polygons.iter().enumerate() {
            if p.id.is_empty() {
                return Err(ScenarioError::EmptyId { index });
            }
            if ids.insert(&p.id, index).is_some() {
                return Err(ScenarioError::DuplicateId { id: p.id.clone() });
            }
            bodies.push(Body::new(p, &Rational::zero())?);
        }
        // polygons that enter later: checked as the initial ones (their
        // bodies are made when they enter)
        let mut inserted: BTreeMap<&str, usize> = BTreeMap::new();
        for (index, ins) in scenario.insertions.iter().enumerate() {
            let p = &ins.polygon;
            let what = || format!("insertions[{index}] time");
            let t = event_time(ins.time, scenario.until, what, || {
                ScenarioError::InsertionTimeOutOfRange {
                    index,
                    id: p.id.clone(),
                    time: ins.time,
                    until: scenario.until,
                }
            })?;
            if p.id.is_empty() {
                return Err(ScenarioError::EmptyInsertedId { index });
            }
            if ids.contains_key(p.id.as_str()) || inserted.insert(&p.id, index).is_some() {
                return Err(ScenarioError::DuplicateId { id: p.id.clone() });
            }
            Body::new(p, &t)?;
        }
        let until_time = Time::from_f64(until_f64).expect("finite");
        let mut changes = BTreeMap::new();
        let mut seen: BTreeMap<(&str, Time), usize> = BTreeMap::new();
        let mut seq = 0u64;
        for (index, c) in scenario.flight_plan_changes.iter().enumerate() {
            let spec = match (ids.get(c.id.as_str()), inserted.get(c.id.as_str())) {
                (Some(&i), _) => &scenario.polygons[i],
                (None, Some(&i)) => &scenario.insertions[i].polygon,
                (None, None) => {
                    return Err(ScenarioError::UnknownChangeId {
                        index,
                        id: c.id.clone(),
                    })
                }
            };
            if spec.fixed {
                return Err(ScenarioError::FixedWithChange {
                    index,
                    id: c.id.clone(),
                });
            }
            let what = || format!("flight_plan_changes[{index}] time");
            let t = event_time(c.time, scenario.until, what, || {
                ScenarioError::ChangeTimeOutOfRange {
                    index,
                    id: c.id.clone(),
                    time: c.time,
                    until: scenario.until,
                }
            })?;
            let velocity = finite_point(c.velocity, || {
                format!("flight_plan_changes[{index}] velocity")
            })?;
            let t = Time::from_rational(t);
            if let Some(first) = seen.insert((&c.id, t.clone()), index) {
                return Err(ScenarioError::DuplicateChange {
                    first,
                    second: index,
                    id: c.id.clone(),
                    time: c.time,
                });
            }
            if let Some(&i) = inserted.get(c.id.as_str()) {
                let entered = scenario.insertions[i].time;
                if c.time <= entered {
                    return Err(ScenarioError::ChangeOutsideLifetime {
                        index,
                        id: c.id.clone(),
                        time: c.time,
                        why: format!("at or before its insertion at time {entered}"),
                    });
                }
            }
            if let Some(&body) = ids.get(c.id.as_str()) {
                if t <= until_time {
                    changes.insert(
                        (t, seq),
                        Change {
                            body: BodyId::new(body as u32),
                            velocity,
                            anchor: None,
                        },
                    );
                    seq += 1;
                }
            }
        }
        let mut removed: BTreeMap<&str, usize> = BTreeMap::new();
        for (index, r) in scenario.removals.iter().enumerate() {
            let what = || format!("removals[{index}] time");
            event_time(r.time, scenario.until, what, || {
                ScenarioError::RemovalTimeOutOfRange {
                    index,
                    id: r.id.clone(),
                    time: r.time,
                    until: scenario.until,
                }
            })?;
            if !ids.contains_key(r.id.as_str()) && !inserted.contains_key(r.id.as_str()) {
                return Err(ScenarioError::UnknownRemovalId {
                    index,
                    id: r.id.clone(),
                });
            }
            if let Some(first) = removed.insert(&r.id, index) {
                return Err(ScenarioError::DuplicateRemoval {
                    first,
                    second: index,
                    id: r.id.clone(),
                });
            }
            if let Some(&i) = inserted.get(r.id.as_str()) {
                let entered = scenario.insertions[i].time;
                if r.time <= entered {
                    return Err(ScenarioError::RemovalNotAfterInsertion {
                        index,
                        id: r.id.clone(),
                        time: r.time,
                        inserted: entered,
                    });
                }
            }
        }
        for (index, c) in scenario.flight_plan_changes.iter().enumerate() {
            if let Some(&i) = removed.get(c.id.as_str()) {
                let left = scenario.removals[i].time;
                if c.time >= left {
                    return Err(ScenarioError::ChangeOutsideLifetime {
                        index,
                        id: c.id.clone(),
                        time: c.time,
                        why: format!("at or after its removal at time {left}"),
                    });
                }
            }
        }
        let world = World {
            alive: bodies.len(),
            bodies,
            mode: scenario.on_collision,
            until: until_time,
            until_f64,
            changes,
            seq,
            bounce_instant: None,
            bounce_rounds: BTreeMap::new(),
            last_contact: ContactMemo::default(),
            minkowski: MinkowskiCache::default(),
            hints: ContactHints::default(),
        };
        if let Some((a, b)) = world.first_overlap_at_zero() {
            return Err(ScenarioError::Overlap {
                a: world.bodies[a].id.clone(),
                b: world.bodies[b].id.clone(),
            });
        }
        Ok(world)
    }

    /// A pair of bodies that touch or overlap at time 0, if any: sort and
    /// sweep over bounding boxes (rounded outward), exact test on candidates.
    fn first_overlap_at_zero(&self) -> Option<(usize, usize)> {
        let zero = Rational::zero();
        let boxes: Vec<[f64; 4]> = self
            .bodies
            .iter()
            .map(|b| {
                let p = b.traj.position_at(&zero);
                let (piv_x, piv_y) = (p.x.interval(), p.y.interval());
                let bx = b.shape.bounds();
                [
                    (bx[0] + piv_x.lo).next_down(),
                    (bx[1] + piv_x.hi).next_up(),
                    (bx[2] + piv_y.lo).next_down(),
                    (bx[3] + piv_y.hi).next_up(),
                ]
            })
            .collect();
        let mut order: Vec<usize> = (0..self.bodies.len()).collect();
        order.sort_by(|&i, &j| boxes[i][0].total_cmp(&boxes[j][0]));
        let mut active: Vec<usize> = Vec::new();
        let mut found: Option<(usize, usize)> = None;
        for &i in &order {
            active.retain(|&j| boxes[j][1] >= boxes[i][0]);
            for &j in &active {
                let (bi, bj) = (&boxes[i], &boxes[j]);
                if bi[2] > bj[3] || bj[2] > bi[3] {
                    continue;
                }
                let (x, y) = (&self.bodies[i], &self.bodies[j]);
                if crate::geom::placed_polygons_intersect(
                    &x.shape,
                    &x.traj.position_at(&zero),
                    &y.shape,
                    &y.traj.position_at(&zero),
                ) {
                    let pair = (i.min(j), i.max(j));
                    // report the first pair in input order, deterministically
                    if found.is_none_or(|f| pair < f) {
                        found = Some(pair);
                    }
                }
            }
            active.push(i);
        }
        found
    }

    /// All bodies (removed ones included, with `alive == false`).
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// How many bodies are alive: kept as bodies come and go, so that a
    /// removal need not read every body (each a cache line or more apart).
    pub fn alive_count(&self) -> usize {
        debug_assert_eq!(
            self.alive,
            self.bodies.iter().filter(|b| b.alive).count(),
            "the count of alive bodies"
        );
        self.alive
    }

    /// One body.
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.index()]
    }

    /// Number of bodies (removed ones included).
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Whether there are no bodies.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// The collision policy.
    pub fn mode(&self) -> CollisionMode {
        self.mode
    }

    /// End of the simulated interval.
    pub fn until(&self) -> &Time {
        &self.until
    }

    /// End of the simulated interval, as given.
    pub fn until_f64(&self) -> f64 {
        self.until_f64
    }

    /// Whether the pair is ever checked: both alive and not both fixed.
    pub fn pair_active(&self, a: BodyId, b: BodyId) -> bool {
        let (x, y) = (self.body(a), self.body(b));
        a != b && x.alive && y.alive && !(x.fixed && y.fixed)
    }

    /// Time of the next pending flight-plan change (at most `until`).
    pub fn next_change_time(&self) -> Option<&Time> {
        self.changes.keys().next().map(|(t, _)| t)
    }

    /// Apply every change at exactly time `t` (which must be the next change
    /// time); returns the bodies whose trajectory changed.
    pub fn apply_changes_at(&mut self, t: &Time) -> Changed {
        let tr = t.as_rational().expect("change times are rational").clone();
        let mut changed = Vec::new();
        while let Some(entry) = self.changes.first_entry() {
            if entry.key().0 != *t {
                break;
            }
            let ((_, seq), c) = entry.remove_entry();
            let body = &mut self.bodies[c.body.index()];
            if !body.alive {
                continue;
            }
            if let Some(q) = &c.anchor {
                if body.anchor.as_ref().map(|a| a.1) != Some(seq) {
                    continue; // superseded by a later bounce
                }
                body.anchor = None;
                // (the bridge, unchanged since it was set, ends at `q`)
                debug_assert_eq!(body.traj.position_at(&tr), *q);
                let traj = Trajectory::through(&tr, q, c.velocity);
                let old = body.frame.uid();
                body.set_traj(traj);
                let new = body.frame.uid();
                self.last_contact.moved(c.body, old, new, &tr);
            } else {
                let v = c.velocity;
                self.set_velocity(c.body, &tr, v, None);
            }
            if !changed.contains(&c.body) {
                changed.push(c.body);
            }
        }
        changed
    }

    /// The largest bit length of a numerator or denominator of body `id`'s
    /// current path (origin and velocity).
    pub fn number_bits(&self, id: BodyId) -> u64 {
        self.number_bits_above(id, 0)
    }

    /// `max(floor, number_bits(id))`, without reducing a bridge's numbers
    /// where their common-denominator form shows that they cannot exceed
    /// `floor` ([`Trajectory::number_bits_above`]).
    pub fn number_bits_above(&self, id: BodyId, floor: u64) -> u64 {
        self.body(id).traj.number_bits_above(floor)
    }

    /// Take the scenario's flight-plan changes out of the queue (the bridge
    /// ends stay): the caller applies them itself with
    /// [`World::change_velocity`]. In queue order.
    pub(crate) fn take_plan(&mut self) -> Vec<(Time, BodyId, Point)> {
        let plan: Vec<(Time, u64)> = self
            .changes
            .iter()
            .filter(|(_, c)| c.anchor.is_none())
            .map(|(k, _)| k.clone())
            .collect();
        plan.into_iter()
            .map(|k| {
                let c = self.changes.remove(&k).expect("listed");
                (k.0, c.body, c.velocity)
            })
            .collect()
    }

    /// The first alive body that `body` (not in the world) would touch or
    /// overlap at time `t`, if any: a box test in doubles first (widened
    /// by far more than their rounding), exact on the candidates.
    fn first_contact_with(&self, body: &Body, t: &Rational) -> Option<BodyId> {
        let tf = t.to_f64();
        let bounds = |b: &Body| b.bounds_f64(tf);
        let nb = bounds(body);
        let pos = body.traj.position_at(t);
        self.bodies.iter().enumerate().find_map(|(i, o)| {
            if !o.alive {
                return None;
            }
            let ob = bounds(o);
            // (a box out of the doubles' range decides nothing)
            let finite = ob.iter().chain(&nb).all(|c| c.is_finite());
            let meets =
                !finite || (ob[0] <= nb[1] && nb[0] <= ob[1] && ob[2] <= nb[3] && nb[2] <= ob[3]);
            (meets
                && crate::geom::placed_polygons_intersect(
                    &body.shape,
                    &pos,
                    &o.shape,
                    &o.traj.position_at(t),
                ))
            .then_some(BodyId::new(i as u32))
        })
    }

    /// Add polygon `p` at time `t` (its `position` given at `t`), unless it
    /// breaks a rule of the contract or touches or overlaps an alive body;
    /// nothing changes then. The caller checks that its id is new.
    pub(crate) fn insert(&mut self, p: &PolygonSpec, t: &Rational) -> Result<BodyId, Refused> {
        let body = Body::new(p, t).map_err(Refused::Invalid)?;
        if let Some(other) = self.first_contact_with(&body, t) {
            return Err(Refused::Touches(other));
        }
        self.bodies.push(body);
        self.alive += 1;
        Ok(BodyId::new(self.bodies.len() as u32 - 1))
    }

    /// Remove one body at once, fixed ones included.
    pub(crate) fn remove_any(&mut self, id: BodyId) {
        let b = &mut self.bodies[id.index()];
        if b.alive {
            self.alive -= 1;
        }
        b.alive = false;
        b.anchor = None;
    }

    /// From time `t` on, body `id` moves with velocity `v`, its position
    /// continuous (with a bridge where `t` or the position is not dyadic:
    /// module docs). The caller checks that the body is alive and not fixed.
    pub(crate) fn change_velocity(&mut self, id: BodyId, t: &Rational, v: Point) {
        self.set_velocity(id, t, v, None);
    }

    /// Remove bodies (`remove` mode); fixed bodies stay.
    pub fn remove(&mut self, ids: &[BodyId]) -> Changed {
        let mut removed = Vec::new();
        for &id in ids {
            let b = &mut self.bodies[id.index()];
            if b.alive && !b.fixed {
                b.alive = false;
                b.anchor = None;
                self.alive -= 1;
                removed.push(id);
            }
        }
        removed
    }

    /// Set a body's velocity from time `t` on, keeping its position
    /// continuous; uses a bridge when the position or time is not dyadic
    /// (module docs). `away` is the direction to round the anchor towards.
    fn set_velocity(&mut self, id: BodyId, t: &Rational, v: Point, away: Option<&[Rational; 2]>) {
        let old = self.bodies[id.index()].frame.uid();
        #[cfg(debug_assertions)]
        let before = self.bodies[id.index()].traj.position_at(t);
        self.set_velocity_frame(id, t, v, away);
        // (on a copy: the body's bridge stays unreduced until read)
        #[cfg(debug_assertions)]
        debug_assert_eq!(self.bodies[id.index()].traj.clone().position_at(t), before);
        let new = self.bodies[id.index()].frame.uid();
        self.last_contact.moved(id, old, new, t);
    }

    /// [`World::set_velocity`] but for the contact memo.
    fn set_velocity_frame(
        &mut self,
        id: BodyId,
        t: &Rational,
        v: Point,
        away: Option<&[Rational; 2]>,
    ) {
        let body = &mut self.bodies[id.index()];
        body.anchor = None;
        if t.is_dyadic() {
            let p = body.traj.position_at(t);
            if p.x.is_dyadic() && p.y.is_dyadic() {
                body.set_traj(Trajectory::through(t, &p, v));
                return;
            }
        }
        // the position at `t`, origin + velocity · t, unreduced
        let tf = Frac::of(t);
        let (o, old_v) = (body.traj.origin(), body.traj.velocity().clone());
        let position = || {
            [
                Frac::of(&o.x).add(&Frac::of(&old_v.x).mul(&tf)),
                Frac::of(&o.y).add(&Frac::of(&old_v.y).mul(&tf)),
            ]
        };
        let (tau, q) = match bridge_anchor_dyadic(t, o, &old_v, &v, away) {
            Some(anchor) => {
                debug_assert_eq!(
                    anchor,
                    bridge_anchor(t, &position(), &v, &old_v, away),
                    "the bridge's end in integers"
                );
                anchor
            }
            None => bridge_anchor(t, &position(), &v, &old_v, away),
        };
        let dt = Time::from_rational(tau.clone());
        // the bridge from `p` at `t` to `q` at `τ`: velocity (q − p) / (τ − t)
        // and origin (p·τ − q·t) / (τ − t); over their common denominator,
        // reduced when read (`bridge_dyadic`), or each coordinate reduced
        // once (a body already on a bridge)
        let (bridge, frame) = match bridge_dyadic(t, o, &old_v, &tau, &q) {
            Some((b, [ox, oy, vx, vy], w)) => {
                let frame = Frame::over([ox, oy], [vx, vy], w, &body.shape);
                (b, frame)
            }
            None => {
                let p = position();
                let tauf = Frac::of(&tau);
                let span = tauf.sub(&tf);
                let coord = |p: &Frac, q: &Rational| {
                    let qf = Frac::of(q);
                    let velocity = qf.sub(p).div(&span).reduced();
                    let origin = p.mul(&tauf).sub(&qf.mul(&tf)).div(&span).reduced();
                    (origin, velocity)
                };
                let (ox, vx) = coord(&p[0], &q.x);
                let (oy, vy) = coord(&p[1], &q.y);
                let b = Trajectory::from_origin(Point { x: ox, y: oy }, Point { x: vx, y: vy });
                let frame = Frame::new(&b, &body.shape);
                (b, frame)
            }
        };
        #[cfg(debug_assertions)]
        {
            let reduced = Frame::new(&bridge.clone(), &body.shape);
            debug_assert!(frame.same_motion(&reduced), "the bridge's frame");
        }
        body.set_traj_frame(bridge, frame);
        let seq = self.seq;
        self.seq += 1;
        body.anchor = Some((dt.clone(), seq));
        self.changes.insert(
            (dt, seq),
            Change {
                body: id,
                velocity: v,
                anchor: Some(q),
            },
        );
    }

    /// Resolve the collisions of one instant in `bounce` mode: elastic
    /// impulses pair by pair in `(a, b)` id order, each with the velocities
    /// left by the previous one. Returns the bodies whose trajectory changed.
    ///
    /// The contract's normal (touched edge, common line, or centroid
    /// direction for a vertex–vertex contact) is used the first time a pair
    /// is resolved at an instant. A centroid-direction impulse can leave a
    /// vertex–vertex pair still moving into each other (or rounding can leave
    /// a tiny approach); the structure then reports the pair again at the
    /// same instant, and this second and any later round uses the normal of
    /// one of the two edges at the contact (the one the pair approaches
    /// least), with a restitution slightly above 1 that grows with each
    /// round, so the pair always separates or slides and no overlap occurs.
    pub fn bounce(&mut self, t: &Rational, pairs: &[(BodyId, BodyId)]) -> Changed {
        if self.bounce_instant.as_ref() != Some(t) {
            self.bounce_instant = Some(t.clone());
            self.bounce_rounds.clear();
        }
        let mut new_v: BTreeMap<BodyId, [f64; 2]> = BTreeMap::new();
        let mut away: BTreeMap<BodyId, [Rational; 2]> = BTreeMap::new();
        for &(a, b) in pairs {
            let key = (a.min(b), a.max(b));
            let round = *self
                .bounce_rounds
                .entry(key)
                .and_modify(|r| *r += 1)
                .or_insert(0);
            let va = self.current_velocity(a, &new_v);
            let vb = self.current_velocity(b, &new_v);
            let Some(contact) = self.contact(a, b, t) else {
                continue;
            };
            let rel = vb.sub(&va);
            let n = if round == 0 {
                contact.normal.clone()
            } else {
                // the active edge normal (from a to b) the pair approaches least
                let mut best: Option<(f64, &Point)> = None;
                for m in &contact.edge_normals {
                    let mf = m.to_f64();
                    let rf = rel.to_f64();
                    let score = (mf[0] * rf[0] + mf[1] * rf[1]) / mf[0].hypot(mf[1]);
                    if best.is_none_or(|(s, _)| score > s) {
                        best = Some((score, m));
                    }
                }
                best.expect("a contact has an active edge").1.clone()
            };
            // approaching iff (v_b − v_a) · n < 0, decided exactly
            if rel.dot(&n).sign() != Sign::Negative {
                continue;
            }
            let restitution = if round == 0 {
                1.0
            } else {
                1.0 + 2f64.powi((round as i32).min(60) - 30)
            };
            let (ba, bb) = (self.body(a), self.body(b));
            let vaf = va.to_f64();
            let vbf = vb.to_f64();
            let (new_a, new_b) = impulse(ba, bb, &n, vaf, vbf, restitution);
            let mut push = |id: BodyId, v: [f64; 2], sign: f64| {
                new_v.insert(id, v);
                let e = away
                    .entry(id)
                    .or_insert_with(|| [Rational::zero(), Rational::zero()]);
                if sign > 0.0 {
                    e[0] = e[0].add(&n.x);
                    e[1] = e[1].add(&n.y);
                } else {
                    e[0] = e[0].sub(&n.x);
                    e[1] = e[1].sub(&n.y);
                }
            };
            if !ba.fixed {
                push(a, new_a, -1.0);
            }
            if !bb.fixed {
                push(b, new_b, 1.0);
            }
        }
        let mut changed = Vec::new();
        for (id, v) in new_v {
            let v =
                Point::from_f64(v).unwrap_or_else(|| Point::from_f64([0.0, 0.0]).expect("zero"));
            self.set_velocity(id, t, v, away.get(&id));
            changed.push(id);
        }
        changed
    }

    fn current_velocity(&self, id: BodyId, new_v: &BTreeMap<BodyId, [f64; 2]>) -> Point {
        // (every velocity in `new_v` is finite: [`impulse`] saturates)
        match new_v.get(&id) {
            Some(v) => Point::from_f64(*v).expect("finite"),
            None => self.body(id).traj.velocity().clone(),
        }
    }

    /// The contact normal of touching bodies `a` and `b` at time `t`,
    /// pointing from `a` to `b` (not normalised): the touched edge's normal,
    /// the common line's normal for flush edges, the centroid direction for a
    /// vertex–vertex contact. `None` if they do not touch.
    pub fn contact_normal(&self, a: BodyId, b: BodyId, t: &Rational) -> Option<Point> {
        self.contact(a, b, t).map(|c| c.normal)
    }

    /// The reference's rule for bodies `a` and `b` that the structure
    /// finds touching at `t`, decided on their contact ([`World::contact`],
    /// which the collision's point and response ask for next), without a
    /// contact interval: where `d = pos_a − pos_b` lies on the boundary of
    /// `M = B ⊕ (−A)`, the contact begins at `t` (`d` was outside `M` just
    /// before) iff the pair approaches along one of the active edges'
    /// normals, and after a response at `t` (`answered`) the interiors
    /// overlap just after `t` iff it approaches along all of them. `None`
    /// where `d` is not on the boundary and `answered` is set (the caller
    /// asks the contact interval). The rule is symmetric in `a` and `b`;
    /// the contact is asked for in the order of the polygons' ids, the
    /// order in which a collision is reported and responded to, so that
    /// its point and response find it in the memo. Whether the pair
    /// approaches along a normal is decided by the frames' velocity
    /// enclosures where they decide it: after a response both bodies are
    /// on bridges, whose exact velocities are reduced only when read.
    pub(crate) fn touch_collides(
        &self,
        a: BodyId,
        b: BodyId,
        t: &Rational,
        answered: bool,
    ) -> Option<bool> {
        let (a, b) = if self.body(a).id.as_bytes() <= self.body(b).id.as_bytes() {
            (a, b)
        } else {
            (b, a)
        };
        let Some(c) = self.contact(a, b, t) else {
            // (apart, or already overlapping: no contact begins at `t`)
            return (!answered).then_some(false);
        };
        // (the sign of `(v_b − v_a)·m` from the frames' velocity
        // enclosures where they decide it; the exact velocities only where
        // not, computed once: a bridge's are reduced when read)
        let [ax, ay] = self.body(a).frame.velocity_enclosure();
        let [bx, by] = self.body(b).frame.velocity_enclosure();
        let (rx, ry) = (bx - ax, by - ay);
        let rel = std::cell::OnceCell::new();
        let approaches = |m: &Point| {
            match (rx * m.x.interval() + ry * m.y.interval()).sign() {
                Some(s @ (Sign::Positive | Sign::Negative)) => {
                    debug_assert_eq!(
                        s,
                        (self.body(b).traj.clone().velocity())
                            .sub(self.body(a).traj.clone().velocity())
                            .dot(m)
                            .sign(),
                        "the filtered sign of an approach"
                    );
                    s
                }
                _ => rel
                    .get_or_init(|| {
                        self.body(b)
                            .traj
                            .velocity()
                            .sub(self.body(a).traj.velocity())
                    })
                    .dot(m)
                    .sign(),
            }
        } == Sign::Negative;
        Some(if answered {
            c.edge_normals.iter().all(approaches)
        } else {
            c.edge_normals.iter().any(approaches)
        })
    }

    fn contact(&self, a: BodyId, b: BodyId, t: &Rational) -> Option<ContactGeometry> {
        let key = (a, b, self.body(a).frame.uid(), self.body(b).frame.uid());
        let mut memo = self
            .last_contact
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(((ka, kb, ua, ub, kt), c)) = memo.as_ref() {
            if (*ka, *kb, *ua, *ub) == key && kt == t {
                return c.clone();
            }
        }
        let c = self.contact_fresh(a, b, t);
        *memo = Some(((key.0, key.1, key.2, key.3, t.clone()), c.clone()));
        c
    }

    /// The edges of `M = B ⊕ (−A)` for bodies `a` and `b`
    /// ([`crate::geom::minkowski_edges_filtered`]), kept for recent pairs
    /// of polygons with 64 vertices or more between them (below that,
    /// computing them costs less than keeping them).
    pub(crate) fn minkowski(&self, a: BodyId, b: BodyId) -> MinkowskiEdges {
        let (sa, sb) = (&self.body(a).shape, &self.body(b).shape);
        if sa.len() + sb.len() < 64 {
            return Arc::new(crate::geom::minkowski_edges_filtered(sa, sb));
        }
        let h = (Arc::as_ptr(sa) as usize as u64)
            .rotate_left(17)
            .wrapping_add(Arc::as_ptr(sb) as usize as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let slot = (h >> 60) as usize % MINKOWSKI_SLOTS;
        let mut cache = self
            .minkowski
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if cache.is_empty() {
            cache.resize(MINKOWSKI_SLOTS, None);
        }
        if let Some((ka, kb, edges)) = &cache[slot] {
            if Arc::ptr_eq(ka, sa) && Arc::ptr_eq(kb, sb) {
                return edges.clone();
            }
        }
        let edges = Arc::new(crate::geom::minkowski_edges_filtered(sa, sb));
        cache[slot] = Some((sa.clone(), sb.clone(), edges.clone()));
        edges
    }

    fn contact_fresh(&self, a: BodyId, b: BodyId, t: &Rational) -> Option<ContactGeometry> {
        if let Some(c) = self.contact_hinted(a, b, t) {
            #[cfg(debug_assertions)]
            {
                let full = self.contact_pass(a, b, t).expect("a proved contact");
                debug_assert!(
                    (&full.normal, &full.edge_normals, &full.features)
                        == (&c.normal, &c.edge_normals, &c.features),
                    "the hinted contact of {a:?} and {b:?} at {t} is not the pass's: {c:?} {full:?}"
                );
            }
            return Some(c);
        }
        self.contact_pass(a, b, t)
    }

    /// Note that a structure found, at `t`, vertex `vertex.1` of body
    /// `vertex.0` touching edge `edge.1` of body `edge.0` (real polygon
    /// indices): [`World::contact`] of the pair at `t` tries it first, with
    /// a few exact tests instead of a pass over the Minkowski difference.
    /// A wrong hint costs those tests and changes nothing.
    pub(crate) fn hint_contact(
        &self,
        t: &Rational,
        vertex: (BodyId, usize),
        edge: (BodyId, usize),
    ) {
        let mut hints = self
            .hints
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if hints.first().is_some_and(|h| &h.t != t) {
            hints.clear();
        }
        if hints.len() < MAX_HINTS {
            hints.push(ContactHint {
                t: t.clone(),
                vertex,
                edge,
            });
        }
    }

    /// The contact of `a` and `b` at `t` from a hint ([`World::hint_contact`]),
    /// if one names the pair and the exact tests prove that the polygons
    /// share exactly its vertex, inside its edge: the vertex on the edge's
    /// line (the same test as [`World::contact_pass`]'s), strictly between
    /// the edge's ends (inside the polygon's two neighbouring edges), and
    /// its own two neighbours strictly beyond the line. Then the pair's only
    /// active edge of `M` is the one of the hinted edge, and the pass would
    /// find exactly this contact.
    fn contact_hinted(&self, a: BodyId, b: BodyId, t: &Rational) -> Option<ContactGeometry> {
        let hint = {
            let hints = self
                .hints
                .0
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            hints
                .iter()
                .find(|h| {
                    &h.t == t
                        && ((h.vertex.0, h.edge.0) == (a, b) || (h.vertex.0, h.edge.0) == (b, a))
                })?
                .clone()
        };
        let ((p, v), (q, j)) = (hint.vertex, hint.edge);
        let (bp, bq) = (self.body(p), self.body(q));
        let (np, nq) = (bp.shape.len(), bq.shape.len());
        if v >= np || j >= nq {
            return None;
        }
        let tt = Time::from_rational(t.clone());
        let tiv = tt.interval();
        let enclose = |body: &Body, i: usize| {
            let [x, y] = body.shape.int_vertex_enclosure(i);
            body.frame.enclose(x, y, tiv)
        };
        // the sign of orient(q_i, q_{i+1}, p_k) at `t`: the filter, then
        // the exact polynomial
        let side = |i: usize, k: usize| {
            let (i1, k) = ((i + 1) % nq, k % np);
            crate::geom::orient_enclosed(enclose(bq, i), enclose(bq, i1), enclose(bp, k))
                .unwrap_or_else(|| {
                    crate::motion::orient_poly(&bq.vertex(i), &bq.vertex(i1), &bp.vertex(k))
                        .sign_at(&tt)
                })
        };
        let clear = side((j + nq - 1) % nq, v) == Sign::Positive
            && side((j + 1) % nq, v) == Sign::Positive
            && side(j, v + np - 1) == Sign::Negative
            && side(j, v + 1) == Sign::Negative;
        if !clear {
            return None;
        }
        // the edge of `M = B ⊕ (−A)` of the hinted edge
        let (ba, bb) = (self.body(a), self.body(b));
        let source = if q == b { Ok(j) } else { Err(j) };
        let (e, exp) = crate::geom::minkowski_edge_of(&ba.shape, &bb.shape, source, v);
        // d = pos_a − pos_b on the edge's line: the pass's exact test
        if Relative::of(ba, bb, t, exp).side(&e) != std::cmp::Ordering::Equal {
            return None;
        }
        let crate::geom::MinkowskiEdge { nx, ny, .. } = e;
        let normal = Point {
            x: Rational::from_int(-nx),
            y: Rational::from_int(-ny),
        };
        Some(ContactGeometry {
            single: Some((p == b, v)),
            edge_normals: vec![normal.clone()],
            normal,
            features: vec![(source, v)],
        })
    }

    /// [`World::contact`] by a pass over the edges of `M`.
    fn contact_pass(&self, a: BodyId, b: BodyId, t: &Rational) -> Option<ContactGeometry> {
        let (ba, bb) = (self.body(a), self.body(b));
        let mut active: Vec<(Int, Int)> = Vec::new();
        let mut features = Vec::new();
        let mut outside = false;
        let mink = self.minkowski(a, b);
        let (edges, exp) = (&mink.0, mink.1);
        // d = pos_a − pos_b lies on the boundary of M = B ⊕ (−A)
        let d = Relative::of(ba, bb, t, exp);
        // (on enclosures first: only the edges that `d` may lie on, the
        // active ones, are compared exactly)
        let side = crate::geom::EdgeSideFilter::of_intervals(
            crate::num::quotient_interval(&d.xn, &d.xd),
            crate::num::quotient_interval(&d.yn, &d.yd),
            exp,
        );
        for e in edges {
            match side.of(e) {
                Some(std::cmp::Ordering::Less) => continue,
                Some(std::cmp::Ordering::Greater) => {
                    outside = true;
                    break;
                }
                _ => {}
            }
            let e = e.edge();
            match d.side(&e) {
                std::cmp::Ordering::Greater => outside = true,
                std::cmp::Ordering::Equal => {
                    features.push((e.source, e.other));
                    active.push((e.nx, e.ny));
                }
                std::cmp::Ordering::Less => {}
            }
        }
        if outside || active.is_empty() {
            return None;
        }
        // M's outward normals point from B to A: negate for a → b.
        let edge_normals: Vec<Point> = active
            .iter()
            .map(|n| Point {
                x: Rational::from_int(-n.0.clone()),
                y: Rational::from_int(-n.1.clone()),
            })
            .collect();
        let first = &active[0];
        let all_parallel = active
            .iter()
            .all(|n| (&n.0 * &first.1 - &n.1 * &first.0).is_zero());
        let normal = if all_parallel {
            edge_normals[0].clone()
        } else {
            let ca = ba.traj.position_at(t).add(ba.centroid());
            let cb = bb.traj.position_at(t).add(bb.centroid());
            cb.sub(&ca)
        };
        Some(ContactGeometry {
            single: None,
            normal,
            edge_normals,
            features,
        })
    }

    /// A point shared by touching bodies `a` and `b` at time `t` (the
    /// average of the touching vertices and touched edge ends that lie on
    /// both polygons: on the contact segment for flush edges), for display.
    pub fn contact_point(&self, a: BodyId, b: BodyId, t: &Rational) -> [f64; 2] {
        let (ba, bb) = (self.body(a), self.body(b));
        let Some(c) = self.contact(a, b, t) else {
            return ba.traj.position_at(t).add(ba.centroid()).to_f64();
        };
        // (the one shared vertex, when the contact proved it: the pass
        // below would find it the only candidate on both polygons)
        if let Some((on_b, i)) = c.single {
            let body = if on_b { bb } else { ba };
            return centroid_f64(&[body.vertex(i).at_to_f64(t)]);
        }
        let (na, nb) = (ba.shape.len(), bb.shape.len());
        // each candidate against every edge of both polygons: the f64
        // filter on enclosures of the positions at `t` first, the exact
        // sign of the moving points' integer polynomial only where it is
        // undecided (the touching edges); no rational positions but the
        // few averaged at the end
        let tt = Time::from_rational(t.clone());
        let tiv = tt.interval();
        let enclose = |body: &Body, i: usize| {
            let [x, y] = body.shape.int_vertex_enclosure(i);
            body.frame.enclose(x, y, tiv)
        };
        let ea: Vec<[Interval; 2]> = (0..na).map(|i| enclose(ba, i)).collect();
        let eb: Vec<[Interval; 2]> = (0..nb).map(|j| enclose(bb, j)).collect();
        // a candidate: a vertex of b (`true`) or of a, by index
        let mut candidates: Vec<(bool, usize)> = Vec::new();
        for (source, other) in &c.features {
            match *source {
                Ok(j) => candidates.extend([(true, j), (true, (j + 1) % nb), (false, *other)]),
                Err(i) => candidates.extend([(false, i), (false, (i + 1) % na), (true, *other)]),
            }
        }
        let body_of = |on_b: bool| if on_b { bb } else { ba };
        let enc_of = |(on_b, i): (bool, usize)| if on_b { eb[i] } else { ea[i] };
        // (a feature's vertex lies exactly on the line of the feature's
        // edge at `t`: `contact` compared them exactly, so that turn is
        // zero and needs no second exact evaluation)
        let on_line = |on_b: bool, i: usize, p: (bool, usize)| {
            c.features.iter().any(|&(source, other)| match source {
                Ok(j) => on_b && j == i && p == (false, other),
                Err(j) => !on_b && j == i && p == (true, other),
            })
        };
        let inside = |on_b: bool, p: (bool, usize)| {
            let (body, e) = (body_of(on_b), if on_b { &eb } else { &ea });
            let n = e.len();
            let ep = enc_of(p);
            (0..n).all(
                |i| match crate::geom::orient_enclosed(e[i], e[(i + 1) % n], ep) {
                    Some(s) => s == Sign::Positive,
                    None if on_line(on_b, i, p) => true,
                    None => {
                        let q = body_of(p.0).vertex(p.1);
                        crate::motion::orient_poly(&body.vertex(i), &body.vertex((i + 1) % n), &q)
                            .sign_at(&tt)
                            != Sign::Negative
                    }
                },
            )
        };
        // (a candidate is a vertex of its own polygon, so on it: only the
        // other polygon is tested)
        let on_both: Vec<[f64; 2]> = candidates
            .iter()
            .filter(|&&p| inside(!p.0, p))
            .map(|&(on_b, i)| body_of(on_b).vertex(i).at_to_f64(t))
            .collect();
        if on_both.is_empty() {
            let (on_b, i) = candidates[0];
            return body_of(on_b).vertex(i).at_to_f64(t);
        }
        centroid_f64(&on_both)
    }
}

/// `d = pos_a − pos_b` at an instant as the unreduced fractions `xn / xd`
/// and `yn / yd` ([`relative_position`]), ready to be compared with the
/// edges of `M = B ⊕ (−A)` in the units `2^exp` of their common exponent.
struct Relative {
    xn: Int,
    xd: Int,
    yn: Int,
    yd: Int,
    /// `xd · yd`.
    den: Int,
    lshift: usize,
    rshift: usize,
}

impl Relative {
    /// `d` for bodies `ba` (A) and `bb` (B) at `t`, against edges of
    /// exponent `exp`.
    fn of(ba: &Body, bb: &Body, t: &Rational, exp: i64) -> Relative {
        let [(xn, xd), (yn, yd)] = relative_position(&ba.traj, &bb.traj, t);
        let den = &xd * &yd;
        let (lshift, rshift) = if exp < 0 {
            ((-exp) as usize, 0)
        } else {
            (0, exp as usize)
        };
        Relative {
            xn,
            xd,
            yn,
            yd,
            den,
            lshift,
            rshift,
        }
    }

    /// `d · n` against `h · 2^exp` for edge `e` (`Greater`: `d` outside its
    /// half-plane; `Equal`: on its line), exactly: both sides times the
    /// positive `xd · yd · 2^max(−exp, 0)`, in integers (no rational
    /// arithmetic, no gcd per edge).
    fn side(&self, e: &crate::geom::MinkowskiEdge) -> std::cmp::Ordering {
        let lhs = (&self.xn * &e.nx * &self.yd + &self.yn * &e.ny * &self.xd) << self.lshift;
        let rhs = (&e.h * &self.den) << self.rshift;
        lhs.cmp(&rhs)
    }
}

/// `pos_a − pos_b` at `t` for bodies moving along `ta` and `tb`, each
/// coordinate as a fraction `(numerator, denominator)` with a positive
/// denominator, not reduced: `o + v·t` over `od · vd · td`, then the
/// difference over the product of the two denominators.
fn relative_position(ta: &Trajectory, tb: &Trajectory, t: &Rational) -> [(Int, Int); 2] {
    let (tn, td) = (t.numer(), t.denom());
    let at = |o: &Rational, v: &Rational| -> (Int, Int) {
        let (on, od, vn, vd) = (o.numer(), o.denom(), v.numer(), v.denom());
        (on * vd * td + vn * tn * od, od * vd * td)
    };
    let coord = |i: usize| {
        // (the coordinate `i` of each, borrowed)
        let [(oa, va), (ob, vb)] = [ta, tb].map(|tr| {
            let (o, v) = (tr.origin(), tr.velocity());
            if i == 0 {
                (&o.x, &v.x)
            } else {
                (&o.y, &v.y)
            }
        });
        let (na, da) = at(oa, va);
        let (nb, db) = at(ob, vb);
        (&na * &db - &nb * &da, da * db)
    };
    [coord(0), coord(1)]
}

/// The velocities of `a` and `b` after the elastic impulse along the
/// contact normal `n` (from `a` to `b`), in doubles, from their velocities
/// `va`, `vb` before (the pair approaches along `n`).
///
/// The masses are the areas. Where the areas, the normal, the velocities
/// and the impulse are ordinary doubles this is the textbook formula. Where
/// one of them is not (an area beyond the doubles' range or below their
/// smallest normal value, a normal whose length overflows, velocities near
/// `f64::MAX`, an impulse below the normal doubles, as for a polygon of
/// area 1e-278 whose inverse mass is 1e278), the same impulse is computed
/// from the exact ratio of the areas, the normal's direction from the
/// exact ratio of its coordinates, and the velocities scaled by a power of
/// two; a result beyond the doubles' range saturates at `±f64::MAX`.
fn impulse(
    ba: &Body,
    bb: &Body,
    n: &Point,
    va: [f64; 2],
    vb: [f64; 2],
    restitution: f64,
) -> ([f64; 2], [f64; 2]) {
    let inv_a = if ba.fixed { 0.0 } else { 1.0 / ba.area() };
    let inv_b = if bb.fixed { 0.0 } else { 1.0 / bb.area() };
    let nf = n.to_f64();
    let len = nf[0].hypot(nf[1]);
    let nh = [nf[0] / len, nf[1] / len];
    let u = (vb[0] - va[0]) * nh[0] + (vb[1] - va[1]) * nh[1];
    let j = -(1.0 + restitution) * u / (inv_a + inv_b);
    let new_a = [va[0] - j * inv_a * nh[0], va[1] - j * inv_a * nh[1]];
    let new_b = [vb[0] + j * inv_b * nh[0], vb[1] + j * inv_b * nh[1]];
    let normal = |x: f64| x.is_finite() && (x == 0.0 || x.abs() >= f64::MIN_POSITIVE);
    let ordinary = [ba.area(), bb.area()].iter().all(|&m| normal(m) && m > 0.0)
        && normal(len)
        && len > 0.0
        && normal(u)
        // (the impulse itself: below the normal doubles for a tiny mass, it
        // would leave the velocities as they were)
        && normal(j)
        && (j != 0.0 || u == 0.0)
        && [new_a, new_b].iter().flatten().all(|&x| normal(x));
    if ordinary {
        return (new_a, new_b);
    }
    // each body's share of the exchange: m_b / (m_a + m_b) for a
    let (share_a, share_b) = match (ba.fixed, bb.fixed) {
        (true, _) => (0.0, 1.0),
        (_, true) => (1.0, 0.0),
        _ => {
            let (ma, mb) = (ba.shape.twice_area(), bb.shape.twice_area());
            let sum = ma.add(&mb);
            (mb.div(&sum).to_f64(), ma.div(&sum).to_f64())
        }
    };
    let nh = unit_direction(n);
    // velocities scaled by a power of two so that the largest is near 1
    let big = va.iter().chain(&vb).fold(0.0f64, |m, x| m.max(x.abs()));
    let e = if big > 0.0 {
        big.log2().floor() as i32
    } else {
        0
    };
    let (down, up) = (
        2f64.powi(-e.clamp(-1000, 1000)),
        2f64.powi(e.clamp(-1000, 1000)),
    );
    let (sa, sb) = (va.map(|x| x * down), vb.map(|x| x * down));
    let u = (sb[0] - sa[0]) * nh[0] + (sb[1] - sa[1]) * nh[1];
    let k = (1.0 + restitution) * u;
    let back = |x: f64| (x * up).clamp(-f64::MAX, f64::MAX);
    (
        [0, 1].map(|i| back(sa[i] + k * share_a * nh[i])),
        [0, 1].map(|i| back(sb[i] - k * share_b * nh[i])),
    )
}

/// The unit vector of the exact nonzero direction `n`, in doubles, from
/// the ratio of its coordinates (no overflow or underflow of its length).
fn unit_direction(n: &Point) -> [f64; 2] {
    let sx = if n.x.sign() == Sign::Negative {
        -1.0
    } else {
        1.0
    };
    let sy = if n.y.sign() == Sign::Negative {
        -1.0
    } else {
        1.0
    };
    let abs = |x: &Rational| match x.sign() {
        Sign::Negative => x.neg(),
        _ => x.clone(),
    };
    let (ax, ay) = (abs(&n.x), abs(&n.y));
    if ay.is_zero() {
        return [sx, 0.0];
    }
    if ax.is_zero() {
        return [0.0, sy];
    }
    if ax >= ay {
        let r = ay.div(&ax).to_f64();
        let l = 1.0f64.hypot(r);
        [sx / l, sy * r / l]
    } else {
        let r = ax.div(&ay).to_f64();
        let l = 1.0f64.hypot(r);
        [sx * r / l, sy / l]
    }
}

fn centroid_f64(ps: &[[f64; 2]]) -> [f64; 2] {
    let n = ps.len() as f64;
    let s = ps
        .iter()
        .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
    [s[0] / n, s[1] / n]
}

/// The exact time of a scheduled entry: finite (else `NonFinite` naming
/// `what`) and in `(0, until]` (else `out_of_range`).
fn event_time(
    time: f64,
    until: f64,
    what: impl Fn() -> String,
    out_of_range: impl Fn() -> ScenarioError,
) -> Result<Rational, ScenarioError> {
    if !time.is_finite() {
        return Err(ScenarioError::NonFinite {
            what: what(),
            value: time,
        });
    }
    if !(time > 0.0 && time <= until) {
        return Err(out_of_range());
    }
    Ok(Rational::from_f64(time).expect("finite"))
}

fn finite_point(p: [f64; 2], what: impl Fn() -> String) -> Result<Point, ScenarioError> {
    for c in p {
        if !c.is_finite() {
            return Err(ScenarioError::NonFinite {
                what: what(),
                value: c,
            });
        }
    }
    Ok(Point::from_f64(p).expect("finite"))
}

/// `floor(log2 x)` for a positive double, clamped to the doubles'
/// exponents (an infinite `x`, the double of a velocity beyond their
/// range, gives 1100, not `i32::MAX`).
fn pow2_floor(x: f64) -> i32 {
    x.log2().floor().clamp(-1100.0, 1100.0) as i32
}

/// The bridge from the position at `t` of the trajectory with origin `o`
/// and velocity `v` to `q` at `τ`, where `o`, `v`, `q` and `τ` are dyadic
/// (`None` otherwise: a body already on a bridge): with each of them
/// written over one power of two, `o = O/2^k` and so on, and `t = n/d`,
/// the velocity is `(Q·d − O·d − V·n) / S` and the origin
/// `((O·d + V·n)·T − Q·n·2^k) / (2^k·S)`, where `S = T·d − n·2^k > 0`:
/// integers no longer than `t`'s. Returned over their common denominator
/// `2^k·S`, unreduced: as a trajectory that reduces them when first read
/// ([`Trajectory::over`]), and as the integers `[ox, oy, vx, vy]` and
/// `2^k·S` for [`Frame::over`].
#[allow(clippy::type_complexity)]
fn bridge_dyadic(
    t: &Rational,
    o: &Point,
    v: &Point,
    tau: &Rational,
    q: &Point,
) -> Option<(Trajectory, [Int; 4], Int)> {
    use dashu_base::BitTest;
    let all = [&o.x, &o.y, &v.x, &v.y, tau, &q.x, &q.y];
    if !all.iter().all(|x| x.is_dyadic()) {
        return None;
    }
    // the common exponent: the largest denominator's
    let k = all
        .iter()
        .map(|x| x.denom().bit_len() - 1)
        .max()
        .expect("seven values");
    let scaled = |x: &Rational| x.numer() << (k - (x.denom().bit_len() - 1));
    let (n, d) = (t.numer(), t.denom());
    let nk = n << k;
    let big_t = scaled(tau);
    let s = &big_t * d - &nk;
    let sk = &s << k;
    let coord = |o: &Rational, v: &Rational, q: &Rational| {
        let (big_o, big_v, big_q) = (scaled(o), scaled(v), scaled(q));
        let pd = &big_o * d + &big_v * n;
        let vel = &big_q * d - &pd;
        let org = pd * &big_t - big_q * &nk;
        (org, vel << k)
    };
    let (oxn, vxn) = coord(&o.x, &v.x, &q.x);
    let (oyn, vyn) = coord(&o.y, &v.y, &q.y);
    let n = [oxn, oyn, vxn, vyn];
    Some((Trajectory::over(n.clone(), sk.clone()), n, sk))
}

/// The bridge end: a dyadic time `τ > t` and a dyadic point `Q` near
/// `p + v·(τ − t)` (module docs).
fn bridge_anchor(
    t: &Rational,
    p: &[Frac; 2],
    v: &Point,
    old_v: &Point,
    away: Option<&[Rational; 2]>,
) -> (Rational, Point) {
    // (2^-36 of `t` at every scale: a bounce at t = 1e-307 between bodies
    // at 1e308 must not take a bridge as long as 2^-36 of a fixed floor,
    // within which they would collide again and again with ever longer
    // numbers)
    let tf = t.to_f64().abs().max(f64::MIN_POSITIVE);
    let g = pow2_floor(tf) - 36;
    // τ = (floor(t / G) + 2)·G with G = 2^g, so τ − t ∈ (G, 2G]
    let (k, _) = Frac::of(t).floor_scaled(-i64::from(g));
    let tau = Rational::from_dyadic(k + Int::from(2), i64::from(g));
    let vf = v.to_f64();
    let of = old_v.to_f64();
    let speed = vf
        .iter()
        .chain(of.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .clamp(1e-300, f64::MAX);
    let r = pow2_floor(speed) - 30 + g;
    // the target p + v·(τ − t), unreduced
    let span = Frac::of(&tau).sub(&Frac::of(t));
    let target = |p: &Frac, v: &Rational| p.add(&Frac::of(v).mul(&span));
    let round = |x: Frac, dir: Sign| -> Rational {
        // x / 2^r rounded in direction `dir`, times 2^r
        let (fl, exact) = x.floor_scaled(-i64::from(r));
        let m = match dir {
            Sign::Positive if !exact => fl + Int::ONE,
            _ => fl,
        };
        Rational::from_dyadic(m, i64::from(r))
    };
    let dir = |i: usize| away.map_or(Sign::Zero, |a| a[i].sign());
    let q = Point {
        x: round(target(&p[0], &v.x), dir(0)),
        y: round(target(&p[1], &v.y), dir(1)),
    };
    (tau, q)
}

/// [`bridge_anchor`] where the trajectory's origin `o` and velocity `old_v`
/// and the new velocity `v` are dyadic (a body off a bridge; `None`
/// otherwise), the same `τ` and `Q` in integers: with `t = n/d` and the
/// dyadic values over one power of two `2^K` (`o = O/2^K` and so on, `τ =
/// T/2^K`), the position at `t` is `P/(2^K·d)` with `P = O·d + V·n`, `τ − t
/// = S/(2^K·d)` with `S = T·d − n·2^K`, and the target `p + v·(τ − t)` is
/// `(P·2^K + W·S)/(2^{2K}·d)`: a few products and one division per
/// coordinate, where [`Frac`]'s general sums multiply denominators.
fn bridge_anchor_dyadic(
    t: &Rational,
    o: &Point,
    old_v: &Point,
    v: &Point,
    away: Option<&[Rational; 2]>,
) -> Option<(Rational, Point)> {
    use dashu_base::{BitTest, DivRemEuclid};
    let dyadic = [&o.x, &o.y, &old_v.x, &old_v.y, &v.x, &v.y];
    if !dyadic.iter().all(|x| x.is_dyadic()) {
        return None;
    }
    // τ and the rounding grid as `bridge_anchor` takes them
    let tf = t.to_f64().abs().max(f64::MIN_POSITIVE);
    let g = i64::from(pow2_floor(tf) - 36);
    let (k, _) = Frac::of(t).floor_scaled(-g);
    let k2 = k + Int::from(2);
    let tau = Rational::from_dyadic(k2.clone(), g);
    let speed = v
        .to_f64()
        .iter()
        .chain(old_v.to_f64().iter())
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .clamp(1e-300, f64::MAX);
    let r = i64::from(pow2_floor(speed) - 30) + g;
    // the common exponent: the dyadic values' and τ's
    let exp = |x: &Rational| (x.denom().bit_len() - 1) as i64;
    let big_k = dyadic
        .iter()
        .map(|x| exp(x))
        .max()
        .expect("six values")
        .max(-g);
    let scaled = |x: &Rational| x.numer() << ((big_k - exp(x)) as usize);
    let (n, d) = (t.numer(), t.denom());
    let nk = n << (big_k as usize);
    let big_t = k2 << ((g + big_k) as usize);
    let s = &big_t * d - &nk;
    let dir = |i: usize| away.map_or(Sign::Zero, |a| a[i].sign());
    let coord = |o: &Rational, ov: &Rational, w: &Rational, i: usize| -> Rational {
        let p = scaled(o) * d + scaled(ov) * n;
        let x = (p << (big_k as usize)) + scaled(w) * &s;
        // floor(x / (2^{2K}·d) / 2^r), and whether it is exact
        let e = -r - 2 * big_k;
        let (fl, rem) = if e >= 0 {
            (x << (e as usize)).div_rem_euclid(d)
        } else {
            x.div_rem_euclid(d << ((-e) as usize))
        };
        let m = match dir(i) {
            Sign::Positive if !rem.is_zero() => fl + Int::ONE,
            _ => fl,
        };
        Rational::from_dyadic(m, r)
    };
    let q = Point {
        x: coord(&o.x, &old_v.x, &v.x, 0),
        y: coord(&o.y, &old_v.y, &v.y, 1),
    };
    Some((tau, q))
}

/// An exact fraction `num / den` (`den > 0`) kept unreduced: the bridge's
/// intermediate values, each final one reduced once ([`Frac::reduced`])
/// rather than after every operation (a reduction is a gcd of numbers as
/// long as the collision time's).
struct Frac {
    num: Int,
    den: Int,
}

impl Frac {
    fn of(x: &Rational) -> Frac {
        Frac {
            num: x.numer().clone(),
            den: x.denom().clone(),
        }
    }

    fn add(&self, o: &Frac) -> Frac {
        if self.den == o.den {
            return Frac {
                num: &self.num + &o.num,
                den: self.den.clone(),
            };
        }
        Frac {
            num: &self.num * &o.den + &o.num * &self.den,
            den: &self.den * &o.den,
        }
    }

    fn sub(&self, o: &Frac) -> Frac {
        self.add(&Frac {
            num: -o.num.clone(),
            den: o.den.clone(),
        })
    }

    fn mul(&self, o: &Frac) -> Frac {
        Frac {
            num: &self.num * &o.num,
            den: &self.den * &o.den,
        }
    }

    /// `self / o` (`o` not zero).
    fn div(&self, o: &Frac) -> Frac {
        let (num, den) = (&self.num * &o.den, &self.den * &o.num);
        if den < Int::ZERO {
            Frac {
                num: -num,
                den: -den,
            }
        } else {
            Frac { num, den }
        }
    }

    fn reduced(self) -> Rational {
        Rational::new(self.num, self.den)
    }

    /// `floor(self · 2^e)`, and whether that is its exact value.
    fn floor_scaled(&self, e: i64) -> (Int, bool) {
        use dashu_base::DivRemEuclid;
        // (one division: the quotient rounded down and a remainder in
        // `[0, d)`, `d` being positive)
        let (q, rem) = if e >= 0 {
            (&self.num << (e as usize)).div_rem_euclid(&self.den)
        } else {
            (&self.num).div_rem_euclid(&self.den << ((-e) as usize))
        };
        (q, rem.is_zero())
    }
}

/// Validation needs the exact polygons and their placement, which the world
/// builds; it is defined here so that `scenario` stays a data module that
/// depends on nothing above it.
impl Scenario {
    /// Check every rule of the contract that is not about JSON syntax,
    /// exactly. The first broken rule is reported.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        World::new(self, None).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{CollisionMode, PolygonSpec, Scenario};

    fn square(id: &str, side: f64, x: f64, vx: f64) -> PolygonSpec {
        PolygonSpec {
            id: id.into(),
            vertices: vec![[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]],
            position: [x, 0.0],
            velocity: [vx, 0.0],
            fixed: false,
        }
    }

    fn bodies(s: &Scenario) -> World {
        World::new(s, None).unwrap_or_else(|e| panic!("{e}"))
    }

    /// A 2×2 square at the origin, at rest, and a triangle whose apex
    /// `(0, 1)` starts at `(3, dy + 1)` moving left at speed 1: at t = 1
    /// the apex reaches the square's right edge (edge 1, from `(2, 0)` to
    /// `(2, 2)`), inside it for `dy = 0`, at its corner `(2, 2)` for
    /// `dy = 1`.
    fn apex_on_edge(dy: f64) -> World {
        let mut tri = square("t", 1.0, 3.0, -1.0);
        tri.vertices = vec![[0.0, 1.0], [1.0, 0.0], [1.0, 2.0]];
        tri.position = [3.0, dy];
        let s = Scenario {
            until: 4.0,
            on_collision: CollisionMode::Bounce,
            polygons: vec![square("s", 2.0, 0.0, 0.0), tri],
            ..Scenario::default()
        };
        bodies(&s)
    }

    /// A hint that names the contact's vertex and edge gives the pass's
    /// contact and point; one that does not, or at another instant, or a
    /// vertex on a corner, is refused and the pass answers.
    #[test]
    fn a_hinted_contact_is_the_pass_and_a_wrong_hint_is_refused() {
        let (sq, tri) = (BodyId::new(0), BodyId::new(1));
        let one = Rational::from_int(Int::from(1));
        let w = apex_on_edge(0.0);
        let pass = w.contact_pass(sq, tri, &one).expect("they touch at t = 1");
        // (the triangle's vertex 0 on the square's edge 1: `M`'s edge of
        // edge 1 of `a`)
        assert_eq!(pass.features, vec![(Err(1), 0)]);
        let point = w.contact_point(sq, tri, &one);
        assert_eq!(point, [2.0, 1.0]);
        // the right hint
        let w = apex_on_edge(0.0);
        w.hint_contact(&one, (tri, 0), (sq, 1));
        let c = w.contact_hinted(sq, tri, &one).expect("the hint is proved");
        assert_eq!(
            (&c.normal, &c.edge_normals, &c.features),
            (&pass.normal, &pass.edge_normals, &pass.features)
        );
        assert_eq!(c.single, Some((true, 0)));
        assert_eq!(w.contact_point(sq, tri, &one), point);
        // wrong vertex, wrong edge, another instant
        for (v, j, t) in [(1, 1, 1), (0, 0, 1), (0, 2, 1), (0, 1, 2)] {
            let w = apex_on_edge(0.0);
            let at = Rational::from_int(Int::from(t));
            w.hint_contact(&at, (tri, v), (sq, j));
            assert!(w.contact_hinted(sq, tri, &one).is_none(), "{v} {j} {t}");
            assert_eq!(w.contact_point(sq, tri, &one), point);
        }
        // the apex on the square's corner: two edges of `M` are active
        let w = apex_on_edge(1.0);
        w.hint_contact(&one, (tri, 0), (sq, 1));
        assert!(w.contact_hinted(sq, tri, &one).is_none());
        assert!(w.contact_pass(sq, tri, &one).expect("touch").features.len() > 1);
    }

    /// A contact asked at an instant and again after a response there (new
    /// frames, the positions at the instant unchanged) comes from the memo,
    /// whose entry names the new frames, and is the contact computed
    /// afresh; at a dyadic instant and at one where the response takes a
    /// bridge.
    #[test]
    fn a_contact_asked_again_after_a_response_at_its_instant_is_the_memos() {
        let (a, b) = (BodyId::new(0), BodyId::new(1));
        let third = Rational::new(Int::from(4), Int::from(3));
        for (v, t) in [(1.0, Rational::from_int(Int::from(1))), (0.75, third)] {
            let s = Scenario {
                until: 4.0,
                on_collision: CollisionMode::Bounce,
                polygons: vec![square("a", 1.0, -2.0, v), square("b", 1.0, 1.0, -v)],
                ..Default::default()
            };
            let mut w = bodies(&s);
            let before = w.contact(a, b, &t).expect("they touch");
            let frames = |w: &World| (w.body(a).frame.uid(), w.body(b).frame.uid());
            let old = frames(&w);
            assert_eq!(w.bounce(&t, &[(a, b)]), vec![a, b]);
            assert_ne!(frames(&w), old);
            let key = w
                .last_contact
                .0
                .lock()
                .expect("one thread")
                .as_ref()
                .map(|(k, _)| (k.2, k.3));
            assert_eq!(key, Some(frames(&w)), "v = {v}");
            let after = w.contact(a, b, &t).expect("they touch");
            let fresh = w.contact_fresh(a, b, &t).expect("they touch");
            let parts = |c: &ContactGeometry| {
                (
                    c.normal.clone(),
                    c.edge_normals.clone(),
                    c.features.clone(),
                    c.single,
                )
            };
            assert_eq!(parts(&after), parts(&fresh), "v = {v}");
            assert_eq!(parts(&after), parts(&before), "v = {v}");
        }
    }

    /// A response at an instant that is not dyadic puts both bodies on a
    /// bridge whose origin and velocity are reduced only when read: the
    /// velocity comparison of two bodies that move apart and the bit count
    /// over a floor they cannot exceed leave them unreduced, and read they
    /// are the bridge's position at the instant and its end, in lowest
    /// terms, with the bit count of the reduced numbers.
    #[test]
    fn a_bridge_reduces_its_numbers_only_when_read() {
        let (a, b) = (BodyId::new(0), BodyId::new(1));
        let t = Rational::new(Int::from(4), Int::from(3));
        let s = Scenario {
            until: 4.0,
            on_collision: CollisionMode::Bounce,
            polygons: vec![square("a", 1.0, -2.0, 0.75), square("b", 1.0, 1.0, -0.75)],
            ..Default::default()
        };
        let mut w = bodies(&s);
        let at_t = |w: &World, id: BodyId| w.body(id).traj.position_at(&t);
        let before = [at_t(&w, a), at_t(&w, b)];
        assert_eq!(w.bounce(&t, &[(a, b)]), vec![a, b]);
        for id in [a, b] {
            assert!(!w.body(id).traj.is_reduced(), "{id:?}");
        }
        assert!(!w.body(a).same_velocity(w.body(b)));
        assert_eq!(w.number_bits_above(a, 10_000), 10_000);
        for id in [a, b] {
            assert!(!w.body(id).traj.is_reduced(), "{id:?}");
        }
        let bits = w.number_bits(a);
        assert!(w.body(a).traj.is_reduced());
        let traj = &w.body(a).traj;
        let (o, v) = (traj.origin().clone(), traj.velocity().clone());
        let fresh = Trajectory::from_origin(o.clone(), v.clone());
        assert_eq!(*traj, fresh);
        assert_eq!(fresh.number_bits_above(0), bits);
        for r in [&o.x, &o.y, &v.x, &v.y] {
            assert_eq!(*r, Rational::new(r.numer().clone(), r.denom().clone()));
        }
        assert_eq!([at_t(&w, a), at_t(&w, b)], before);
        // (the bridge ends where its end's change starts the body)
        let (end, change) = w
            .changes
            .iter()
            .find(|(_, c)| c.body == a)
            .expect("a bridge");
        let tau = end.0.as_rational().expect("a rational end").clone();
        let q = change.anchor.clone().expect("an anchor");
        assert_eq!(w.body(a).traj.position_at(&tau), q);
    }

    /// Two equal squares head-on swap their velocities, at the unit scale
    /// and where the areas, the normal's length and the relative velocity
    /// are beyond the doubles' range (2^600-sided squares at ±1.5·2^1023).
    #[test]
    fn equal_masses_swap_velocities_at_every_scale() {
        let n = Point::from_f64([1.0, 0.0]).expect("finite");
        for (side, v) in [(1.0, 1.0), (2f64.powi(600), 1.5 * 2f64.powi(1023))] {
            let s = Scenario {
                until: 1.0,
                on_collision: CollisionMode::Bounce,
                polygons: vec![
                    square("a", side, -2.0 * side, v),
                    square("b", side, side, -v),
                ],
                ..Default::default()
            };
            let w = bodies(&s);
            let (ba, bb) = (w.body(BodyId::new(0)), w.body(BodyId::new(1)));
            let r = Rational::from_f64(side).expect("finite");
            let big = n.scale(&r.mul(&r)); // beyond the doubles at 2^600
            for normal in [&n, &big] {
                let (a, b) = impulse(ba, bb, normal, [v, 0.0], [-v, 0.0], 1.0);
                assert_eq!((a, b), ([-v, 0.0], [v, 0.0]), "side {side}");
            }
        }
    }

    /// A subnormal-sized polygon (zero area in doubles) against a unit
    /// one: the light one takes (almost) the whole exchange, the heavy one
    /// keeps its velocity.
    #[test]
    fn a_polygon_with_an_area_below_the_doubles_bounces_off_a_unit_one() {
        let tiny = 2f64.powi(-1070);
        let s = Scenario {
            until: 1.0,
            on_collision: CollisionMode::Bounce,
            polygons: vec![square("a", tiny, -2.0, 1.0), square("b", 1.0, 1.0, 0.0)],
            ..Default::default()
        };
        let w = bodies(&s);
        let n = Point::from_f64([1.0, 0.0]).expect("finite");
        let (a, b) = impulse(
            w.body(BodyId::new(0)),
            w.body(BodyId::new(1)),
            &n,
            [1.0, 0.0],
            [0.0, 0.0],
            1.0,
        );
        assert_eq!(a, [-1.0, 0.0]);
        assert_eq!(b, [0.0, 0.0]);
        // an exact direction whose coordinates overflow as doubles
        let huge = Point {
            x: Rational::from_f64(f64::MAX)
                .expect("finite")
                .mul(&Rational::from_f64(4.0).expect("finite")),
            y: Rational::from_f64(f64::MAX)
                .expect("finite")
                .mul(&Rational::from_f64(-4.0).expect("finite")),
        };
        let d = unit_direction(&huge);
        assert_eq!(d[0], -d[1]);
        assert!((d[0] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
    }

    /// A polygon of area 1e-278 (an ordinary double, whose inverse mass is
    /// 1e278) bounces off a fixed one at 1e-218: the textbook impulse
    /// `-2u / (1/m)` is far below the doubles' range, and the velocity
    /// still reverses (as in the fuzzer's scene at t = 8e251,
    /// `testdata/regressions/extreme_bounce_of_a_1e-139_polygon_off_a_fixed_one_at_8e251.json`).
    #[test]
    fn a_polygon_of_area_1e_minus_278_bounces_off_a_fixed_one() {
        let mut fixed = square("a", 1.0, -2.0, 0.0);
        fixed.fixed = true;
        let s = Scenario {
            until: 1.0,
            on_collision: CollisionMode::Bounce,
            polygons: vec![fixed, square("b", 1e-139, 1.0, 0.0)],
            ..Default::default()
        };
        let w = bodies(&s);
        assert!(w.body(BodyId::new(1)).area() < 1e-277);
        let n = Point::from_f64([1.0, 0.0]).expect("finite");
        let (a, b) = impulse(
            w.body(BodyId::new(0)),
            w.body(BodyId::new(1)),
            &n,
            [0.0, 0.0],
            [-3e-218, 1e-218],
            1.0,
        );
        assert_eq!(a, [0.0, 0.0]);
        assert_eq!(b, [3e-218, 1e-218]);
    }
}
