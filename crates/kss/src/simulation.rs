//! A simulation that the caller drives: advance to the next collision,
//! decide what happens (new velocities, removals, insertions, or one of the
//! built-in responses), advance again.
//!
//! [`Simulation`] is the core that [`crate::run`] and the `kss` command are
//! built on. Its time starts at 0 and only moves forward. Every call is
//! checked first and refused with a typed [`SimError`] that leaves the
//! simulation unchanged; a refused call changes nothing that a later call
//! sees.
//!
//! ## Collisions and responses
//!
//! [`Simulation::advance`] stops at the earliest collision instant up to
//! the requested time and returns every pair that collides then. The pairs
//! touch at that instant and their motions would make them overlap just
//! after it, so before advancing again the caller answers each pair: a new
//! velocity for one of its polygons ([`Simulation::set_velocity`]), the
//! removal of one of them ([`Simulation::remove`]), or a built-in response
//! ([`Simulation::bounce`], [`Simulation::remove_colliding`]). An advance
//! with a pair left unanswered is refused ([`SimError::Unanswered`]). A
//! pair whose answer still leaves it interpenetrating is returned again at
//! the same instant, with [`CollisionEvent::again`] set.
//!
//! ## Cost
//!
//! A velocity change reschedules the certificates of that polygon only. A
//! removal triangulates again the region the polygon leaves, and, with the
//! plain structure, an insertion the region around the polygon nearest to
//! the new one, in place (counted in [`RunStats::local_removals`] and
//! [`RunStats::local_insertions`]); where that region does not work, and
//! for every insertion with the hierarchical structure, the structure is
//! built again ([`RunStats::rebuilds`], [`RunStats::insert_rebuilds`]).
//! Finding the nearest polygon and checking that an insertion touches
//! nothing scan the polygons' bounding boxes in doubles (`O(k)`, a few
//! microseconds per thousand polygons).

use std::collections::{HashMap, HashSet};

use crate::brute::PairMethod;
use crate::engine::{audit, make_engine, Backend, KineticEngine, RunError, StructureKind};
pub use crate::engine::{Collisions, Finder};
use crate::geom::Point;
use crate::num::{Rational, Time};
use crate::runner::{CollisionEvent, RunStats};
use crate::scenario::{CollisionMode, PolygonSpec, Scenario, ScenarioError};
use crate::world::{BodyId, Refused, World};

/// Options of a [`Simulation`].
#[derive(Clone, Debug)]
pub struct SimOptions {
    /// The structure that finds the collisions.
    pub structure: StructureKind,
    /// Run the structure's audit (every invariant, exactly) after every
    /// event and every call: slow, for tests.
    pub audit: bool,
    /// For the brute-force structure: how a pair's contact time is computed.
    pub pair_method: PairMethod,
    /// For the hierarchical structure: polygons of at most this many
    /// vertices take part as they are, only larger ones through outer
    /// approximations ([`crate::RunOptions::approximate_above`]; default
    /// [`crate::DEFAULT_APPROXIMATE_ABOVE`], 0 approximates every polygon).
    pub approximate_above: usize,
}

impl Default for SimOptions {
    fn default() -> SimOptions {
        SimOptions {
            structure: StructureKind::default(),
            audit: false,
            pair_method: PairMethod::default(),
            approximate_above: crate::DEFAULT_APPROXIMATE_ABOVE,
        }
    }
}

/// Why a call on a [`Simulation`] was refused. Every variant but
/// [`SimError::Aborted`] and [`SimError::Internal`] leaves the simulation
/// unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A polygon or a number breaks a rule of the scenario contract.
    #[error(transparent)]
    Invalid(#[from] ScenarioError),
    /// No polygon ever had this id.
    #[error("no polygon has the id {0:?}")]
    UnknownPolygon(String),
    /// The polygon has left the scene.
    #[error("polygon {0:?} is no longer in the scene")]
    NotPresent(String),
    /// A fixed polygon's velocity cannot change.
    #[error("polygon {0:?} is fixed: its velocity cannot change")]
    Fixed(String),
    /// The polygon to insert has an empty id.
    #[error("the polygon to insert has an empty id; give it a unique non-empty id")]
    EmptyId,
    /// The id is taken (ids are never reused, not even after a removal).
    #[error("a polygon with the id {0:?} is or was in the scene; ids are never reused")]
    DuplicateId(String),
    /// An inserted polygon would touch or overlap a present one.
    #[error("polygon {inserted:?} would touch or overlap polygon {present:?} at t = {time}; insert it elsewhere or later")]
    Touches {
        /// The polygon to insert.
        inserted: String,
        /// The present polygon it meets.
        present: String,
        /// The current time.
        time: f64,
    },
    /// The requested time is not a finite number at or after the current time.
    #[error("cannot advance to t = {time}: the current time is {now} and time only moves forward")]
    BadTime {
        /// The time asked for.
        time: f64,
        /// The current time (rounded).
        now: f64,
    },
    /// A collision of the current instant has no response yet.
    #[error("polygons {a:?} and {b:?} collided at t = {time} and neither has a response yet; change a velocity, remove one of them, or call bounce/remove_colliding")]
    Unanswered {
        /// The pair's first polygon.
        a: String,
        /// The pair's second polygon.
        b: String,
        /// The instant of the collision (rounded).
        time: f64,
    },
    /// A response names a pair that did not collide at the current instant.
    #[error("polygons {a:?} and {b:?} did not collide at the current instant")]
    NotColliding {
        /// The pair's first polygon.
        a: String,
        /// The pair's second polygon.
        b: String,
    },
    /// A collision finder other than the built-in ones gave up
    /// ([`Simulation::with_finder`]); the simulation cannot go on.
    #[error("the collision finder gave up: {0}")]
    Aborted(String),
    /// A bug in kss; the simulation cannot go on.
    #[error("internal error (a bug in kss, please report it): {0}")]
    Internal(String),
}

impl From<RunError> for SimError {
    fn from(e: RunError) -> SimError {
        match e {
            RunError::Invalid(e) => SimError::Invalid(e),
            RunError::Aborted(e) => SimError::Aborted(e),
            // (the message without the variant's prefix: `SimError` adds its own)
            RunError::Internal(e) => SimError::Internal(e),
            other => SimError::Internal(other.to_string()),
        }
    }
}

/// Polygons moving by translation, their collisions found exactly, driven
/// by the caller (module docs).
pub struct Simulation {
    world: World,
    engine: Backend,
    structure: StructureKind,
    audit: bool,
    now: Time,
    ids: HashMap<String, BodyId>,
    /// The pairs returned at `now` that have no response yet.
    unanswered: Vec<(BodyId, BodyId)>,
    /// The pairs returned at `now` that the engine has not been told of
    /// (passed with the first change after they were returned).
    reported: Vec<(BodyId, BodyId)>,
    /// The pairs returned at the instant `reported_at`.
    reported_now: HashSet<(BodyId, BodyId)>,
    reported_at: Option<Time>,
    collisions: u64,
    /// Instants with velocity changes (flight-plan changes and bridge ends).
    change_instants: u64,
    last_change: Option<Time>,
    max_bits: u64,
    counters_before: Vec<u64>,
    build_seconds: f64,
    /// Set once an internal error happened: every later call fails.
    broken: Option<String>,
    /// The finder is not a built-in structure ([`Simulation::with_finder`]).
    custom: bool,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("structure", &self.structure)
            .field("now", &self.now.to_f64())
            .field("polygons", &self.ids.len())
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// A simulation of `polygons` (their positions at time 0) with the
    /// chosen structure; its time is 0. Refused, with the rule and the
    /// polygon named, when a polygon breaks the scenario contract or two
    /// polygons touch or overlap.
    pub fn new(polygons: &[PolygonSpec], options: &SimOptions) -> Result<Simulation, SimError> {
        let scenario = Scenario {
            until: f64::MAX,
            on_collision: CollisionMode::Bounce,
            polygons: polygons.to_vec(),
            ..Scenario::default()
        };
        let world = World::new(&scenario, None)?;
        Simulation::from_world(world, options)
    }

    /// A simulation of `world` (validated, at time 0).
    pub(crate) fn from_world(world: World, options: &SimOptions) -> Result<Simulation, SimError> {
        let start = std::time::Instant::now();
        let counters_before = crate::structure::counters::snapshot().to_vec();
        let engine = make_engine(&world, options)?;
        Simulation::assemble(world, engine, options, start, counters_before)
    }

    /// A simulation of `world` (at time 0, as [`World::new`] builds it from a
    /// scenario; the scenario's flight-plan changes are the world's own, and
    /// applied as the simulation advances) whose collisions `finder`
    /// finds, for comparing other exact finders with the built-in
    /// structures on the same loop. `audit` runs the finder's
    /// [`Finder::audit`] after every step. The statistics name the
    /// structure `"custom"`.
    pub fn with_finder(
        world: World,
        finder: Box<dyn Finder>,
        audit: bool,
    ) -> Result<Simulation, SimError> {
        let options = SimOptions {
            audit,
            ..SimOptions::default()
        };
        let counters_before = crate::structure::counters::snapshot().to_vec();
        let mut sim = Simulation::assemble(
            world,
            Backend::Other(finder),
            &options,
            std::time::Instant::now(),
            counters_before,
        )?;
        sim.custom = true;
        Ok(sim)
    }

    fn assemble(
        world: World,
        engine: Backend,
        options: &SimOptions,
        start: std::time::Instant,
        counters_before: Vec<u64>,
    ) -> Result<Simulation, SimError> {
        let ids = world
            .bodies()
            .iter()
            .enumerate()
            .map(|(i, b)| (b.id.clone(), BodyId::new(i as u32)))
            .collect();
        let max_bits = (0..world.len() as u32)
            .map(|i| world.number_bits(BodyId::new(i)))
            .max()
            .unwrap_or(0);
        let sim = Simulation {
            world,
            engine,
            structure: options.structure,
            audit: options.audit,
            now: Time::zero(),
            ids,
            unanswered: Vec::new(),
            reported: Vec::new(),
            reported_now: HashSet::new(),
            reported_at: None,
            collisions: 0,
            change_instants: 0,
            last_change: None,
            max_bits,
            counters_before,
            build_seconds: start.elapsed().as_secs_f64(),
            broken: None,
            custom: false,
        };
        sim.audit_if()?;
        Ok(sim)
    }

    /// The current time, exact.
    pub fn now(&self) -> &Time {
        &self.now
    }

    /// The ids of the polygons in the scene now, in the order they came in.
    pub fn polygons(&self) -> impl Iterator<Item = &str> {
        self.world
            .bodies()
            .iter()
            .filter(|b| b.alive)
            .map(|b| b.id.as_str())
    }

    /// Whether polygon `id` is in the scene now.
    pub fn contains(&self, id: &str) -> bool {
        self.ids.get(id).is_some_and(|&b| self.world.body(b).alive)
    }

    /// Polygon `id`'s position now (the world position of its body frame's
    /// origin), exact.
    pub fn position(&self, id: &str) -> Result<[Rational; 2], SimError> {
        let b = self.present(id)?;
        let now = self.now_rational()?;
        let p = self.world.body(b).traj.position_at(&now);
        Ok([p.x, p.y])
    }

    /// Polygon `id`'s velocity now, exact. (Just after a velocity change at
    /// an instant that is not a double, a polygon takes a short bridge to a
    /// point on a coarser grid, and this is the bridge's velocity; see
    /// [`crate::world`].)
    pub fn velocity(&self, id: &str) -> Result<[Rational; 2], SimError> {
        let b = self.present(id)?;
        let v = self.world.body(b).traj.velocity();
        Ok([v.x.clone(), v.y.clone()])
    }

    /// Statistics so far (the contract's `--stats` object, less the wall
    /// time of the events).
    pub fn stats(&self) -> RunStats {
        let mut stats = RunStats {
            structure: if self.custom {
                "custom"
            } else {
                self.structure.name()
            },
            polygons: self.world.len(),
            vertices: self.world.bodies().iter().map(|b| b.shape.len()).sum(),
            ..RunStats::default()
        };
        let (final_certs, max_certs) = self.engine.certificates();
        let mut by_kind = self.engine.internal_events();
        by_kind.insert("collision".into(), self.collisions);
        by_kind.insert("flight_plan_change".into(), self.change_instants);
        stats.events_processed = by_kind.values().sum();
        stats.events_by_kind = by_kind;
        stats.certificates_final = final_certs;
        stats.certificates_max = max_certs;
        (
            stats.rebuilds,
            stats.degenerate_rebuilds,
            stats.refine_rebuilds,
        ) = self.engine.rebuilds();
        stats.insert_rebuilds = self.engine.insert_rebuilds();
        stats.local_insertions = self.engine.local_insertions();
        stats.merges = self.engine.merges();
        stats.local_removals = self.engine.local_removals();
        stats.local_repairs = self.engine.local_repairs();
        (stats.stand_ins, stats.stand_in_ends) = self.engine.stand_ins();
        stats.collisions = self.collisions;
        stats.max_number_bits = self.max_bits;
        stats.build_seconds = self.build_seconds;
        if self.custom {
            stats.work = self.engine.work();
        } else if self.structure != StructureKind::Brute {
            let after = crate::structure::counters::snapshot();
            stats.work = crate::structure::counters::NAMES
                .iter()
                .zip(after.iter().zip(&self.counters_before))
                .map(|(name, (a, b))| (name.to_string(), a - b))
                .collect();
        }
        stats
    }

    /// Advance to the earliest collision instant at most `until` and return
    /// every pair that collides then, sorted by `(a, b)`; or, if none does,
    /// advance to `until` and return nothing. Refused while a collision of
    /// the current instant has no response (module docs).
    pub fn advance(&mut self, until: f64) -> Result<Vec<CollisionEvent>, SimError> {
        self.check()?;
        let target = match Time::from_f64(until) {
            Some(t) if t >= self.now => t,
            _ => {
                return Err(SimError::BadTime {
                    time: until,
                    now: self.now.to_f64(),
                })
            }
        };
        self.advance_to(&target)
    }

    /// [`Simulation::advance`] to an exact time (at or after now).
    pub(crate) fn advance_to(&mut self, target: &Time) -> Result<Vec<CollisionEvent>, SimError> {
        self.check()?;
        if let Some(&(a, b)) = self.unanswered.first() {
            return Err(SimError::Unanswered {
                a: self.world.body(a).id.clone(),
                b: self.world.body(b).id.clone(),
                time: self.now.to_f64(),
            });
        }
        let r = self.guard(|s| s.advance_inner(target));
        r.map_err(SimError::from)
    }

    fn advance_inner(&mut self, target: &Time) -> Result<Vec<CollisionEvent>, RunError> {
        loop {
            // the bridge ends (see `crate::world`) are the world's own changes
            let limit = match self.world.next_change_time() {
                Some(t) if t < target => t.clone(),
                _ => target.clone(),
            };
            if let Some((t, pairs)) = self.engine.next_collisions(&self.world, &limit)? {
                return self.report(t, pairs);
            }
            match self.world.next_change_time() {
                Some(t) if t <= target => {
                    let t = t.clone();
                    self.now = t.clone();
                    let changed = self.world.apply_changes_at(&t);
                    self.changed_at(&changed);
                    self.engine.update(&self.world, &self.now, &changed, &[])?;
                    self.audit_if()?;
                }
                _ => {
                    self.now = target.clone();
                    return Ok(Vec::new());
                }
            }
        }
    }

    /// The collisions at `t`: named, sorted, remembered until answered.
    fn report(
        &mut self,
        t: Time,
        pairs: Vec<(BodyId, BodyId)>,
    ) -> Result<Vec<CollisionEvent>, RunError> {
        let tr = t
            .as_rational()
            .ok_or_else(|| RunError::Internal("irrational collision time".into()))?
            .clone();
        let world = &self.world;
        let mut named: Vec<(&str, &str, BodyId, BodyId)> = pairs
            .iter()
            .map(|&(a, b)| {
                let (ia, ib) = (world.body(a).id.as_str(), world.body(b).id.as_str());
                if ia.as_bytes() <= ib.as_bytes() {
                    (ia, ib, a, b)
                } else {
                    (ib, ia, b, a)
                }
            })
            .collect();
        named.sort_by(|x, y| {
            (x.0.as_bytes(), x.1.as_bytes()).cmp(&(y.0.as_bytes(), y.1.as_bytes()))
        });
        if self.reported_at.as_ref() != Some(&t) {
            self.reported_at = Some(t.clone());
            self.reported_now.clear();
        }
        let mut events = Vec::with_capacity(named.len());
        for &(ia, ib, a, b) in &named {
            let again = !self.reported_now.insert((a, b));
            if !again {
                self.collisions += 1;
            }
            events.push(CollisionEvent {
                time: t.clone(),
                a: ia.to_string(),
                b: ib.to_string(),
                point: world.contact_point(a, b, &tr),
                again,
            });
        }
        let ordered: Vec<(BodyId, BodyId)> = named.iter().map(|x| (x.2, x.3)).collect();
        self.now = t;
        self.unanswered = ordered.clone();
        self.reported = ordered;
        Ok(events)
    }

    /// Change the velocity of polygon `id` from now on; its position stays
    /// continuous. Answers the collisions of the current instant that it
    /// is part of.
    pub fn set_velocity(&mut self, id: &str, velocity: [f64; 2]) -> Result<(), SimError> {
        self.set_velocities(&[(id, velocity)])
    }

    /// [`Simulation::set_velocity`] for several polygons at once (one
    /// update of the structure). Either every change is made or none.
    pub fn set_velocities(&mut self, changes: &[(&str, [f64; 2])]) -> Result<(), SimError> {
        self.check()?;
        let mut bodies = Vec::with_capacity(changes.len());
        let mut seen = HashSet::new();
        for &(id, v) in changes {
            let b = self.present(id)?;
            if self.world.body(b).fixed {
                return Err(SimError::Fixed(id.to_string()));
            }
            let p = Point::from_f64(v).ok_or_else(|| ScenarioError::NonFinite {
                what: format!("the new velocity of polygon {id:?}"),
                value: if v[0].is_finite() { v[1] } else { v[0] },
            })?;
            if seen.insert(b) {
                bodies.push((b, p));
            } else {
                // the last change of a body wins
                if let Some(e) = bodies.iter_mut().find(|e| e.0 == b) {
                    e.1 = p;
                }
            }
        }
        let now = self.now_rational()?;
        let ids: Vec<BodyId> = bodies.iter().map(|e| e.0).collect();
        for (b, p) in bodies {
            self.world.change_velocity(b, &now, p);
        }
        self.changed_at(&ids);
        self.answer(&ids, &[]);
        self.update(&ids)
    }

    /// Remove polygon `id` (fixed ones too) from the scene now. Answers the
    /// collisions of the current instant that it is part of.
    pub fn remove(&mut self, id: &str) -> Result<(), SimError> {
        self.check()?;
        let b = self.present(id)?;
        self.world.remove_any(b);
        self.answer(&[b], &[]);
        self.update(&[b])
    }

    /// Insert `polygon` now: its `position` is where its body frame's
    /// origin is now. Refused when its id is or was in use, when it breaks
    /// a rule of the contract, or when it touches or overlaps a polygon in
    /// the scene ([`SimError::Touches`] names that polygon).
    pub fn insert(&mut self, polygon: &PolygonSpec) -> Result<(), SimError> {
        self.check()?;
        if polygon.id.is_empty() {
            return Err(SimError::EmptyId);
        }
        if self.ids.contains_key(&polygon.id) {
            return Err(SimError::DuplicateId(polygon.id.clone()));
        }
        let now = self.now_rational()?;
        let b = match self.world.insert(polygon, &now) {
            Ok(b) => b,
            Err(Refused::Invalid(e)) => return Err(e.into()),
            Err(Refused::Touches(other)) => {
                return Err(SimError::Touches {
                    inserted: polygon.id.clone(),
                    present: self.world.body(other).id.clone(),
                    time: self.now.to_f64(),
                })
            }
        };
        self.ids.insert(polygon.id.clone(), b);
        self.max_bits = self.world.number_bits_above(b, self.max_bits);
        let now = self.now.clone();
        self.guard(|s| {
            if !s.reported.is_empty() {
                // the reference recomputes the reported pairs at the first
                // change after they were returned
                let reported = std::mem::take(&mut s.reported);
                s.engine.update(&s.world, &now, &[], &reported)?;
            }
            s.engine.insert(&s.world, &now, b)?;
            s.audit_if()
        })
        .map_err(SimError::from)
    }

    /// The contract's `bounce` response to `collisions` (returned by the
    /// latest [`Simulation::advance`]): elastic frictionless impulses, pair
    /// by pair in `(a, b)` order, masses proportional to area, fixed
    /// polygons of infinite mass.
    pub fn bounce(&mut self, collisions: &[CollisionEvent]) -> Result<(), SimError> {
        self.check()?;
        let pairs = self.pairs_of(collisions)?;
        let now = self.now_rational()?;
        let changed = self.world.bounce(&now, &pairs);
        for &b in &changed {
            self.max_bits = self.world.number_bits_above(b, self.max_bits);
        }
        self.answer(&[], &pairs);
        self.update(&changed)
    }

    /// The contract's `remove` response to `collisions` (returned by the
    /// latest [`Simulation::advance`]): both polygons of each pair leave
    /// the scene, except fixed ones. As with [`Simulation::remove`], the
    /// other pairs of a polygon that leaves are answered too.
    pub fn remove_colliding(&mut self, collisions: &[CollisionEvent]) -> Result<(), SimError> {
        self.check()?;
        let pairs = self.pairs_of(collisions)?;
        let ids: Vec<BodyId> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
        let removed = self.world.remove(&ids);
        self.answer(&removed, &pairs);
        self.update(&removed)
    }

    /// Check every invariant of the structure exactly, at a rational
    /// instant after now and before the next event.
    pub fn audit(&self) -> Result<(), SimError> {
        self.check()?;
        audit(&self.world, &self.engine, &self.now, self.world.until()).map_err(SimError::from)
    }

    /// The world (for pictures and tests inside the crate).
    pub(crate) fn world(&self) -> &World {
        &self.world
    }

    /// The kinetic engine, if the structure is one (for pictures).
    pub(crate) fn into_kinetic(self) -> (World, Option<KineticEngine>) {
        match self.engine {
            Backend::Kinetic(k) => (self.world, Some(*k)),
            Backend::Other(_) => (self.world, None),
        }
    }

    /// The pairs of `collisions`, each of which must have been returned at
    /// the current instant.
    fn pairs_of(&self, collisions: &[CollisionEvent]) -> Result<Vec<(BodyId, BodyId)>, SimError> {
        let mut pairs = Vec::with_capacity(collisions.len());
        for c in collisions {
            let not = || SimError::NotColliding {
                a: c.a.clone(),
                b: c.b.clone(),
            };
            let (Some(&a), Some(&b)) = (self.ids.get(&c.a), self.ids.get(&c.b)) else {
                return Err(not());
            };
            let now = self.reported_at.as_ref() == Some(&self.now) && c.time == self.now;
            if !now || !self.reported_now.contains(&(a, b)) {
                return Err(not());
            }
            if !pairs.contains(&(a, b)) {
                pairs.push((a, b));
            }
        }
        Ok(pairs)
    }

    /// The pairs that involve a body of `bodies`, and `pairs`, are answered.
    fn answer(&mut self, bodies: &[BodyId], pairs: &[(BodyId, BodyId)]) {
        self.unanswered.retain(|&(a, b)| {
            !(bodies.contains(&a) || bodies.contains(&b) || pairs.contains(&(a, b)))
        });
    }

    /// Tell the engine that `bodies` changed motion or left at now.
    fn update(&mut self, bodies: &[BodyId]) -> Result<(), SimError> {
        let now = self.now.clone();
        let reported = std::mem::take(&mut self.reported);
        self.guard(|s| {
            s.engine.update(&s.world, &now, bodies, &reported)?;
            s.audit_if()
        })
        .map_err(SimError::from)
    }

    /// Count the velocity changes of `bodies` at now.
    fn changed_at(&mut self, bodies: &[BodyId]) {
        for &b in bodies {
            self.max_bits = self.world.number_bits_above(b, self.max_bits);
        }
        if !bodies.is_empty() && self.last_change.as_ref() != Some(&self.now) {
            self.last_change = Some(self.now.clone());
            self.change_instants += 1;
        }
    }

    fn audit_if(&self) -> Result<(), RunError> {
        if self.audit {
            audit(&self.world, &self.engine, &self.now, self.world.until())?;
        }
        Ok(())
    }

    /// Run `f`; an internal error breaks the simulation for good.
    fn guard<T>(
        &mut self,
        f: impl FnOnce(&mut Simulation) -> Result<T, RunError>,
    ) -> Result<T, RunError> {
        let r = f(self);
        if let Err(RunError::Internal(e)) = &r {
            self.broken = Some(e.clone());
        }
        r
    }

    fn check(&self) -> Result<(), SimError> {
        match &self.broken {
            Some(e) => Err(SimError::Internal(format!(
                "the simulation stopped at an earlier internal error: {e}"
            ))),
            None => Ok(()),
        }
    }

    fn present(&self, id: &str) -> Result<BodyId, SimError> {
        let &b = self
            .ids
            .get(id)
            .ok_or_else(|| SimError::UnknownPolygon(id.to_string()))?;
        if !self.world.body(b).alive {
            return Err(SimError::NotPresent(id.to_string()));
        }
        Ok(b)
    }

    fn now_rational(&self) -> Result<Rational, SimError> {
        self.now
            .as_rational()
            .cloned()
            .ok_or_else(|| SimError::Internal("irrational current time".into()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_internal_error_says_so_once() {
        let e = SimError::from(RunError::Internal("x".into()));
        assert_eq!(
            e.to_string(),
            "internal error (a bug in kss, please report it): x"
        );
    }
}
