//! The brute-force reference as a collision finder.

use std::collections::BTreeMap;

use super::{world_time, Collisions, Finder, RunError};
use crate::brute::Brute;
use crate::num::{Rational, Time};
use crate::world::{BodyId, World};

pub(super) struct BruteEngine(pub(super) Brute);

impl Finder for BruteEngine {
    fn next_collisions(&mut self, _world: &World, limit: &Time) -> Result<Collisions, RunError> {
        Ok(self.0.next_collisions(limit))
    }

    fn update(
        &mut self,
        world: &World,
        now: &Time,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) -> Result<(), RunError> {
        let now = world_time(now)?;
        self.0.update(world, now, bodies, reported);
        Ok(())
    }

    fn next_time(&self) -> Option<Time> {
        self.0.next_time().cloned()
    }

    fn audit(&self, world: &World, now: &Time, at: &Rational) -> Result<(), String> {
        let now = now.as_rational().ok_or("irrational world time")?;
        self.0.audit(world, now, at)
    }

    fn insert(&mut self, world: &World, now: &Time, b: BodyId) -> Result<(), RunError> {
        let now = world_time(now)?;
        self.0.update(world, now, &[b], &[]);
        Ok(())
    }

    fn certificates(&self) -> (u64, u64) {
        (self.0.queued() as u64, self.0.max_queued() as u64)
    }

    fn internal_events(&self) -> BTreeMap<String, u64> {
        BTreeMap::new()
    }
}
