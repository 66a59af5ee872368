//! The engines that find collisions: the brute-force reference and the
//! kinetic structure (plain or hierarchical), behind one trait that the
//! [`crate::simulation::Simulation`] drives. An engine only finds *when* and
//! *which* polygons collide; the [`World`] holds the motions.

use std::collections::BTreeMap;

use crate::brute::Brute;
use crate::num::{Rational, Time};
use crate::scenario::ScenarioError;
use crate::world::{BodyId, World};

/// Debug output for `--features trace` builds only.
macro_rules! trace {
    ($($arg:tt)*) => {
        #[cfg(feature = "trace")]
        eprintln!($($arg)*);
    };
}

mod brute;
mod kinetic;

use brute::BruteEngine;
pub(crate) use kinetic::KineticEngine;

/// Which kinetic structure computes the collisions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum StructureKind {
    /// The separation-sensitive hierarchical structure (the default): the
    /// kinetic separation structure on outer approximations of the polygons
    /// of more than [`crate::RunOptions::approximate_above`] vertices, the
    /// others as they are.
    #[default]
    Hierarchical,
    /// The kinetic separation structure without the hierarchy.
    Plain,
    /// All-pairs exact time of impact: the reference.
    Brute,
}

impl StructureKind {
    /// The contract's name (`"hierarchical"`, `"plain"`, `"brute"`).
    pub fn name(self) -> &'static str {
        match self {
            StructureKind::Hierarchical => "hierarchical",
            StructureKind::Plain => "plain",
            StructureKind::Brute => "brute",
        }
    }
}

/// Why a run could not complete.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// The scenario is invalid.
    #[error(transparent)]
    Invalid(#[from] ScenarioError),
    /// The requested structure is not available yet.
    #[error("structure `{0}` is not implemented yet; use --structure brute")]
    NotImplemented(&'static str),
    /// A polygon inserted during the run touches or overlaps a polygon in
    /// the scene at its insertion time (checked during the run: presence
    /// can depend on earlier collisions).
    #[error("polygon {inserted:?}, inserted at t = {time}, touches or overlaps polygon {present:?}, which is in the scene then; insert it elsewhere or at another time")]
    InsertionTouches {
        /// The inserted polygon.
        inserted: String,
        /// The present polygon it meets.
        present: String,
        /// The insertion time.
        time: f64,
    },
    /// A collision finder other than the built-in ones gave up (for
    /// example, a benchmark's time budget ran out).
    #[error("the collision finder gave up: {0}")]
    Aborted(String),
    /// A broken invariant: a bug in kss.
    #[error("internal error (a bug in kss, please report it): {0}")]
    Internal(String),
}

/// The earliest collision instant and the pairs colliding then.
pub type Collisions = Option<(Time, Vec<(BodyId, BodyId)>)>;

/// An exact collision finder that a [`crate::Simulation`] drives: the
/// built-in structures (brute force, plain, hierarchical) and any other
/// finder (the benchmark's exact baselines plug in through it, see
/// [`crate::Simulation::with_finder`]). The simulation owns the [`World`]
/// (the motions) and calls the finder in time order: `next_collisions`
/// with a limit at or after every earlier call's, then, at the instant of
/// the collisions or at the limit, `update` or `insert` for every change
/// the caller makes there.
pub trait Finder {
    /// Process internal events up to the earliest collision time at most
    /// `limit`; return that time and every pair colliding then.
    fn next_collisions(&mut self, world: &World, limit: &Time) -> Result<Collisions, RunError>;
    /// The world changed at `now`: `bodies` changed trajectory or were
    /// removed; `reported` were just reported as colliding.
    fn update(
        &mut self,
        world: &World,
        now: &Time,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) -> Result<(), RunError>;
    /// The time of the next internal event, if any (for choosing audit instants).
    fn next_time(&self) -> Option<Time>;
    /// Check every invariant at the rational instant `at` (strictly between
    /// events; `now` is the last event time). None by default.
    fn audit(&self, _world: &World, _now: &Time, _at: &Rational) -> Result<(), String> {
        Ok(())
    }
    /// Work counters by name, for the statistics ([`crate::RunStats::work`]).
    fn work(&self) -> BTreeMap<String, u64> {
        BTreeMap::new()
    }
    /// Body `b` entered the world at `now`; it touches no alive body then.
    fn insert(&mut self, world: &World, now: &Time, b: BodyId) -> Result<(), RunError>;
    /// Active certificates now and at most.
    fn certificates(&self) -> (u64, u64);
    /// Internal events by kind.
    fn internal_events(&self) -> BTreeMap<String, u64>;
    /// Times the structure was rebuilt from scratch: after removals, and at
    /// degenerate instants, and when a pop could not be done in place.
    fn rebuilds(&self) -> (u64, u64, u64) {
        (0, 0, 0)
    }
    /// Times the structure was built again for an inserted polygon.
    fn insert_rebuilds(&self) -> u64 {
        0
    }
    /// Polygons inserted in place.
    fn local_insertions(&self) -> u64 {
        0
    }
    /// Approximation vertices merged away (coarsening).
    fn merges(&self) -> u64 {
        0
    }
    /// Polygons removed in place.
    fn local_removals(&self) -> u64 {
        0
    }
    /// Degenerate instants repaired by a local retriangulation.
    fn local_repairs(&self) -> u64 {
        0
    }

    /// Times the reference stood in for the structure, and times the
    /// structure took over again.
    fn stand_ins(&self) -> (u64, u64) {
        (0, 0)
    }
}

/// The world's current time, which is always rational (updates happen at
/// collision and flight-plan instants).
pub(super) fn world_time(now: &Time) -> Result<&Rational, RunError> {
    now.as_rational()
        .ok_or_else(|| RunError::Internal("irrational world time".into()))
}

pub(crate) fn make_engine(world: &World, options: &crate::SimOptions) -> Result<Backend, RunError> {
    let audit = options.audit;
    match options.structure {
        StructureKind::Brute => Ok(Backend::Other(Box::new(BruteEngine(Brute::new(
            world,
            options.pair_method,
        ))))),
        StructureKind::Plain => Ok(Backend::Kinetic(Box::new(KineticEngine::new(
            world, audit, false, 0,
        )?))),
        StructureKind::Hierarchical => Ok(Backend::Kinetic(Box::new(KineticEngine::new(
            world,
            audit,
            true,
            options.approximate_above,
        )?))),
    }
}

/// The finder of a simulation: the kinetic structure (kept by type, for
/// pictures of it) or any other.
pub(crate) enum Backend {
    Kinetic(Box<KineticEngine>),
    Other(Box<dyn Finder>),
}

impl Backend {
    fn get(&self) -> &dyn Finder {
        match self {
            Backend::Kinetic(k) => k.as_ref(),
            Backend::Other(f) => f.as_ref(),
        }
    }

    fn get_mut(&mut self) -> &mut dyn Finder {
        match self {
            Backend::Kinetic(k) => k.as_mut(),
            Backend::Other(f) => f.as_mut(),
        }
    }
}

impl Finder for Backend {
    fn next_collisions(&mut self, world: &World, limit: &Time) -> Result<Collisions, RunError> {
        self.get_mut().next_collisions(world, limit)
    }
    fn update(
        &mut self,
        world: &World,
        now: &Time,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) -> Result<(), RunError> {
        self.get_mut().update(world, now, bodies, reported)
    }
    fn next_time(&self) -> Option<Time> {
        self.get().next_time()
    }
    fn audit(&self, world: &World, now: &Time, at: &Rational) -> Result<(), String> {
        self.get().audit(world, now, at)
    }
    fn work(&self) -> BTreeMap<String, u64> {
        self.get().work()
    }
    fn insert(&mut self, world: &World, now: &Time, b: BodyId) -> Result<(), RunError> {
        self.get_mut().insert(world, now, b)
    }
    fn certificates(&self) -> (u64, u64) {
        self.get().certificates()
    }
    fn internal_events(&self) -> BTreeMap<String, u64> {
        self.get().internal_events()
    }
    fn rebuilds(&self) -> (u64, u64, u64) {
        self.get().rebuilds()
    }
    fn insert_rebuilds(&self) -> u64 {
        self.get().insert_rebuilds()
    }
    fn local_insertions(&self) -> u64 {
        self.get().local_insertions()
    }
    fn merges(&self) -> u64 {
        self.get().merges()
    }
    fn local_removals(&self) -> u64 {
        self.get().local_removals()
    }
    fn local_repairs(&self) -> u64 {
        self.get().local_repairs()
    }
    fn stand_ins(&self) -> (u64, u64) {
        self.get().stand_ins()
    }
}

/// Audit at a rational instant strictly after `now` and before the next event.
pub(crate) fn audit(
    world: &World,
    engine: &dyn Finder,
    now: &Time,
    end: &Time,
) -> Result<(), RunError> {
    let mut next = end.clone();
    for t in [engine.next_time(), world.next_change_time().cloned()]
        .into_iter()
        .flatten()
    {
        if t < next {
            next = t;
        }
    }
    if *now >= next {
        // Another event is due at this very instant (audit once it is done),
        // or the run ends here (nothing after `until` is simulated).
        return Ok(());
    }
    let at = now.rational_between(&next);
    engine
        .audit(world, now, &at)
        .map_err(|e| RunError::Internal(format!("audit failed after t = {now}: {e}")))
}
