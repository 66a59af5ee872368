//! What the kinetic layer did, by kind: internal events, and the fallbacks
//! that are not events (searches, local repairs, rebuilds, stand-ins).

use std::collections::BTreeMap;

use crate::structure::ops::EventKind;

/// Why the structure is built again from scratch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rebuild {
    /// After a removal that could not be done in place.
    Removal,
    /// For an inserted polygon that could not be inserted in place.
    Insertion,
    /// At a degenerate instant where the local operations find no valid
    /// structure.
    Degenerate,
    /// After the hierarchy was refined at an instant with contacts.
    Refine,
    /// When the structure takes over from the reference that stood in.
    StandInEnd,
}

/// Counts of what the kinetic layer did.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// Internal events by kind.
    pub events: BTreeMap<EventKind, u64>,
    /// Corridor normalizations that had to search (no event).
    pub searches: u64,
    /// Rebuilds from scratch by [`Rebuild`] kind, in its order.
    rebuilds: [u64; 5],
    /// Pops done in place (without a rebuild).
    pub local_pops: u64,
    /// Polygons removed in place.
    pub local_removals: u64,
    /// Polygons inserted in place.
    pub local_insertions: u64,
    /// Degenerate instants repaired by a local retriangulation.
    pub local_repairs: u64,
    /// Approximation vertices merged away (coarsening).
    pub merges: u64,
    /// Times the reference stood in for the structure.
    pub stand_ins: u64,
}

impl Tally {
    /// Count `n` internal events of kind `kind`.
    pub fn events(&mut self, kind: EventKind, n: u64) {
        *self.events.entry(kind).or_default() += n;
    }

    /// Count a rebuild of kind `kind`.
    pub fn rebuilt(&mut self, kind: Rebuild) {
        self.rebuilds[kind as usize] += 1;
    }

    /// The rebuilds of kind `kind` so far.
    pub fn rebuilds(&self, kind: Rebuild) -> u64 {
        self.rebuilds[kind as usize]
    }
}
