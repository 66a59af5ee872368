//! How much work the kinetic structures did: counts of predicate
//! evaluations by the path they took (the f64 filter, the exact
//! arithmetic, the memo of the instant) and of the corridor walks, for
//! `--stats` and for profiling the cost of an event.
//!
//! The counts are kept per thread (the predicates are free functions of a
//! [`super::geo::Geo`], called from deep inside the operations);
//! [`crate::run`] reports the difference between the counts at its start
//! and at its end, so two runs interleaved on one thread would share them.

use std::cell::Cell;

/// What is counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Counter {
    /// Orientation tests at an instant through the f64 filter.
    TurnsFiltered,
    /// Those the filter could not decide.
    TurnsUndecided,
    /// Orientations just after or before an instant evaluated exactly.
    TurnsExact,
    /// Those answered by the memo of the instant instead.
    TurnsMemo,
    /// Certificate failure times computed.
    FailureTimes,
    /// Those the filter could not place, computed exactly.
    FailureTimesExact,
    /// Failure times placed with the sign just after the instant from the
    /// memo of exact turns (no exact certificate function).
    FailureTimesMemo,
    /// Failing checks of due certificates answered without arithmetic
    /// (the points are those their failure time was computed for).
    FailingKnown,
    /// Corridors normalized after an operation.
    Normalizations,
    /// Walks of a middle bridge along a corridor's chains.
    Walks,
    /// Corridors taken as an operation left them on the signs of the
    /// junctions it made, without their clearance
    /// ([`super::Kss::trust_op`]).
    TrustedChecks,
    /// Candidate updates of a pop checked for validity
    /// ([`super::pop`]), repairs by triangle collapses included.
    PopCandidates,
    /// Corridors normalized again after a pop, as owners of the
    /// certificates on the popped body's changed vertices.
    PopOwners,
    /// Removals of several bodies at one instant in one region (the two
    /// polygons of a collision in `remove` mode), each body also counted
    /// in `local_removals`.
    SetRemovals,
}

/// The names of the counters, in the order of the counters' indices.
pub const NAMES: [&str; 14] = [
    "turns_filtered",
    "turns_undecided",
    "turns_exact",
    "turns_memo",
    "failure_times",
    "failure_times_exact",
    "failure_times_memo",
    "failing_known",
    "normalizations",
    "walks",
    "trusted_checks",
    "pop_candidates",
    "pop_owners",
    "set_removals",
];

thread_local! {
    static COUNTS: [Cell<u64>; 14] = const { [const { Cell::new(0) }; 14] };
}

/// Count one `c`.
#[inline]
pub(crate) fn bump(c: Counter) {
    COUNTS.with(|x| {
        let cell = &x[c as usize];
        cell.set(cell.get() + 1);
    });
}

/// The counts of this thread so far, in the order of [`NAMES`].
pub fn snapshot() -> [u64; 14] {
    COUNTS.with(|x| x.each_ref().map(Cell::get))
}
