//! Driving an exact collision finder over a [`kss::world::World`], with the
//! same loop semantics as the library's runner: collisions at an instant
//! come before the flight-plan changes of that instant, every pair colliding
//! at an instant is reported once (sorted by id), and the world applies
//! `stop`, `remove` or `bounce`.
//!
//! The library's own engine trait is private, so the exact baselines
//! implement [`ExactFinder`] and run through [`drive`]; the library's
//! [`kss::brute::Brute`] implements it too, which tests that this loop is
//! the library's.

use std::collections::HashSet;

use kss::brute::{Brute, PairMethod};
use kss::num::{Rational, Time};
use kss::world::{BodyId, World};
use kss::CollisionMode;

use crate::{Counters, Deadline, Event, Failure};

/// The earliest collision instant at most a limit and the pairs colliding then.
pub type Collisions = Option<(Time, Vec<(BodyId, BodyId)>)>;

/// An exact structure that finds the next collisions of a world.
pub trait ExactFinder {
    /// Process internal events up to the earliest collision time at most
    /// `limit`; return that time and every pair colliding then.
    fn next_collisions(&mut self, world: &World, limit: &Time) -> Collisions;
    /// The world changed at `now`: `bodies` changed trajectory or were
    /// removed; `reported` were just reported as colliding.
    fn update(
        &mut self,
        world: &World,
        now: &Rational,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    );
    /// Internal events processed so far (certificate failures).
    fn internal_events(&self) -> u64;
    /// Largest number of scheduled certificates so far.
    fn certificates_max(&self) -> u64;
    /// Pair time-of-impact computations so far.
    fn pair_tests(&self) -> u64;
}

impl ExactFinder for Brute {
    fn next_collisions(&mut self, _world: &World, limit: &Time) -> Collisions {
        Brute::next_collisions(self, limit)
    }

    fn update(
        &mut self,
        world: &World,
        now: &Rational,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) {
        Brute::update(self, world, now, bodies, reported)
    }

    fn internal_events(&self) -> u64 {
        0
    }

    fn certificates_max(&self) -> u64 {
        self.max_queued() as u64
    }

    fn pair_tests(&self) -> u64 {
        self.pair_computations()
    }
}

/// Runs `finder` on `world` to the end, returning the events in order.
pub fn drive(
    world: &mut World,
    finder: &mut dyn ExactFinder,
    deadline: Deadline,
) -> Result<(Vec<Event>, Counters), Failure> {
    let mut events = Vec::new();
    let mut changes = 0u64;
    let mut instant: Option<Time> = None;
    let mut reported_now: HashSet<(BodyId, BodyId)> = HashSet::new();
    let end = world.until().clone();
    loop {
        if deadline.passed() {
            return Err(Failure::Budget);
        }
        let limit = match world.next_change_time() {
            Some(t) if *t < end => t.clone(),
            _ => end.clone(),
        };
        if let Some((t, pairs)) = finder.next_collisions(world, &limit) {
            let tr = t
                .as_rational()
                .ok_or_else(|| Failure::Error("irrational collision time".into()))?
                .clone();
            let mut named: Vec<(String, String, BodyId, BodyId)> = pairs
                .iter()
                .map(|&(a, b)| {
                    let (ia, ib) = (world.body(a).id.as_str(), world.body(b).id.as_str());
                    if ia.as_bytes() <= ib.as_bytes() {
                        (ia.to_string(), ib.to_string(), a, b)
                    } else {
                        (ib.to_string(), ia.to_string(), b, a)
                    }
                })
                .collect();
            named.sort_by(|x, y| {
                (x.0.as_bytes(), x.1.as_bytes()).cmp(&(y.0.as_bytes(), y.1.as_bytes()))
            });
            if instant.as_ref() != Some(&t) {
                instant = Some(t.clone());
                reported_now.clear();
            }
            let tf = t.to_f64();
            for (ia, ib, a, b) in &named {
                if reported_now.insert((*a, *b)) {
                    events.push(Event {
                        time: tf,
                        a: ia.clone(),
                        b: ib.clone(),
                    });
                }
            }
            let ordered: Vec<(BodyId, BodyId)> = named.iter().map(|x| (x.2, x.3)).collect();
            match world.mode() {
                CollisionMode::Stop => break,
                CollisionMode::Remove => {
                    let ids: Vec<BodyId> = ordered.iter().flat_map(|&(a, b)| [a, b]).collect();
                    let removed = world.remove(&ids);
                    finder.update(world, &tr, &removed, &ordered);
                }
                CollisionMode::Bounce => {
                    let changed = world.bounce(&tr, &ordered);
                    finder.update(world, &tr, &changed, &ordered);
                }
            }
        } else {
            match world.next_change_time() {
                Some(t) if *t <= end => {
                    let t = t.clone();
                    let changed = world.apply_changes_at(&t);
                    changes += 1;
                    let tr = t
                        .as_rational()
                        .ok_or_else(|| Failure::Error("irrational change time".into()))?
                        .clone();
                    finder.update(world, &tr, &changed, &[]);
                }
                _ => break,
            }
        }
    }
    let collisions = events.len() as u64;
    Ok((
        events,
        Counters {
            collisions,
            events: finder.internal_events() + collisions + changes,
            certificates_max: finder.certificates_max(),
            pair_tests: finder.pair_tests(),
            ..Default::default()
        },
    ))
}

/// The library's brute force through [`drive`] (for testing the loop).
pub fn run_brute_driven(
    scenario: &kss::Scenario,
    deadline: Deadline,
) -> Result<(Vec<Event>, Counters), Failure> {
    let mut world = World::new(scenario, None).map_err(|e| Failure::Error(e.to_string()))?;
    let mut brute = Brute::new(&world, PairMethod::Fast);
    drive(&mut world, &mut brute, deadline)
}
