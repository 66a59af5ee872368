//! Running an exact collision finder of the benchmark through the library's
//! own loop ([`kss::run_with_finder`]): the same order of things at an
//! instant, the same responses (`stop`, `remove`, `bounce`), the same
//! statistics as `kss run`. A finder checks the run's time budget itself
//! ([`BUDGET`]).

use std::collections::BTreeMap;

use kss::brute::{Brute, PairMethod};
use kss::num::{Rational, Time};
use kss::world::{BodyId, World};
use kss::{Collisions, Finder, RunError, RunOptions, Scenario};

use crate::{Counters, Deadline, Event, Failure};

/// The message of a finder whose time budget ran out
/// ([`RunError::Aborted`]).
pub const BUDGET: &str = "the time budget ran out";

/// Runs the finder that `make` builds on `scenario` to the end through the
/// library's loop, returning the events in order and the counters.
pub fn run(
    scenario: &Scenario,
    make: &mut dyn FnMut(&World) -> Box<dyn Finder>,
) -> Result<(Vec<Event>, Counters), Failure> {
    let mut events = Vec::new();
    let stats = kss::run_with_finder(scenario, &RunOptions::default(), make, &mut |e| {
        events.push(Event {
            time: e.time.to_f64(),
            a: e.a.clone(),
            b: e.b.clone(),
        })
    })
    .map_err(|e| match e {
        RunError::Aborted(m) if m == BUDGET => Failure::Budget,
        RunError::Aborted(m) => Failure::Unsupported(m),
        other => Failure::Error(other.to_string()),
    })?;
    let counters = Counters {
        collisions: stats.collisions,
        events: stats.events_processed,
        certificates_max: stats.certificates_max,
        pair_tests: stats.work.get("pair_tests").copied().unwrap_or(0),
        ..Default::default()
    };
    Ok((events, counters))
}

/// The library's brute force as a finder of the caller's (for testing that
/// [`kss::run_with_finder`] is the loop of `kss run`).
pub struct BruteFinder {
    brute: Brute,
    deadline: Deadline,
}

impl Finder for BruteFinder {
    fn next_collisions(&mut self, _world: &World, limit: &Time) -> Result<Collisions, RunError> {
        if self.deadline.passed() {
            return Err(RunError::Aborted(BUDGET.into()));
        }
        Ok(self.brute.next_collisions(limit))
    }

    fn update(
        &mut self,
        world: &World,
        now: &Time,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) -> Result<(), RunError> {
        self.brute.update(world, rational(now)?, bodies, reported);
        Ok(())
    }

    fn insert(&mut self, world: &World, now: &Time, b: BodyId) -> Result<(), RunError> {
        self.brute.update(world, rational(now)?, &[b], &[]);
        Ok(())
    }

    fn next_time(&self) -> Option<Time> {
        self.brute.next_time().cloned()
    }

    fn certificates(&self) -> (u64, u64) {
        (self.brute.queued() as u64, self.brute.max_queued() as u64)
    }

    fn internal_events(&self) -> BTreeMap<String, u64> {
        BTreeMap::new()
    }

    fn work(&self) -> BTreeMap<String, u64> {
        BTreeMap::from([("pair_tests".to_string(), self.brute.pair_computations())])
    }
}

/// An update instant (always rational: collisions and plan changes).
pub(crate) fn rational(now: &Time) -> Result<&Rational, RunError> {
    now.as_rational()
        .ok_or_else(|| RunError::Internal("an irrational update instant".into()))
}

/// The library's brute force run as a finder of the caller's.
pub fn run_brute_driven(
    scenario: &Scenario,
    deadline: Deadline,
) -> Result<(Vec<Event>, Counters), Failure> {
    run(scenario, &mut |world| {
        Box::new(BruteFinder {
            brute: Brute::new(world, PairMethod::Fast),
            deadline,
        })
    })
}
