//! What the engine holds about the instant it is at.
//!
//! An instant begins with the first failure popped at a new time and ends
//! with the next motion change ([`Kinetic::motion_changed`], which every
//! collision response and flight-plan change goes through) or when the
//! queue moves past it. In between, the engine may be in any of these
//! situations, each kept here and nowhere else:
//!
//! - *classifying*: failures of the instant wait in `later` until every
//!   possible contact at it is known;
//! - *contacts found*: contact certificates and failures next to a contact
//!   wait in `waiting` for the collision response;
//! - *handling*: `handling` names the certificate whose failure an
//!   operation is repairing;
//! - *broken*: the local operations failed (or the hierarchy was refined)
//!   with contacts at the instant, and `broken` says what to rebuild once
//!   the response is applied;
//! - *settled*: pairs that touched without a collision, for the driver's
//!   pops;
//! - *cycling*: `recent` holds the last certificates handled at the instant,
//!   for the guard against operations that undo each other.

use std::collections::VecDeque;

use super::tally::Rebuild;
use crate::num::Time;
use crate::structure::events::Failure;
use crate::structure::Att;
use crate::world::BodyId;

#[cfg(doc)]
use super::Kinetic;
#[cfg(doc)]
use crate::structure::geo::Geo;

/// A failure's classification kept from its pop ([`InstantState::classified`]):
/// its triple, its bodies' views then, and the failure.
pub(super) type Classified = ([Att; 3], [[u64; 2]; 3], Failure);

/// A contact certificate known to be zero at the instant
/// ([`InstantState::zero`]): its triple and its points' bodies'
/// approximation versions then.
pub(super) type KnownZero = ([Att; 3], [u64; 3]);

/// A rebuild that waits for the collision response at this instant.
#[derive(Clone, Debug)]
pub(super) struct Broken {
    /// [`Rebuild::Degenerate`] or [`Rebuild::Refine`].
    pub(super) kind: Rebuild,
    /// For a refinement: the bodies whose approximations were refined (the
    /// region a local repair takes instead of a rebuild) and the failed
    /// certificates; for failed local operations: the bodies of the
    /// certificate on which they failed, with it and the certificates
    /// deferred after it. `None` after a refinement if an event was deferred
    /// meanwhile (the deferred events need the whole structure rebuilt).
    pub(super) around: Option<(Vec<BodyId>, Vec<[Att; 3]>)>,
}

/// The per-instant state of the kinetic layer (see the module docs).
#[derive(Debug, Default)]
pub(super) struct InstantState {
    /// Certificates popped at the current instant and set aside: contacts
    /// (the collision response changes the motions) and failures next to a
    /// contact. Rescheduled by [`Kinetic::motion_changed`].
    pub(super) waiting: Vec<[Att; 3]>,
    /// The contact certificates of `waiting` whose turn is known to be
    /// exactly zero at the instant (a failure root for the points it was
    /// computed for), with the versions of their points' bodies'
    /// approximations then ([`Geo::view_words`]). Positions are continuous
    /// through a response, so under the new motions the turn is zero there
    /// too, and [`Kinetic::motion_changed`] reads its sign just after the
    /// instant from the derivative where the filter decides it, instead of
    /// the exact polynomial. With the instant, which it holds for alone.
    pub(super) zero: Option<(Time, Vec<KnownZero>)>,
    /// Popped failures of the current instant that wait until every possible
    /// contact of the instant has been classified.
    /// (Inline: most instants have one or two.)
    pub(super) later: Option<(Time, smallvec::SmallVec<[[Att; 3]; 2]>)>,
    /// How each certificate of `later` was classified when it was popped
    /// ([`crate::structure::events::classify`]), with the views of its
    /// points' bodies then ([`Geo::view_words`]), and the instant: the same
    /// failure when it is handled at that instant, unless a pop or a motion
    /// change came between.
    pub(super) classified: Option<(Time, smallvec::SmallVec<[Classified; 2]>)>,
    /// The certificate whose failure is being handled.
    pub(super) handling: Option<[Att; 3]>,
    /// The rebuild that waits for the collision response, if any.
    pub(super) broken: Option<Broken>,
    /// Pairs of bodies that touched at the current instant without a
    /// collision (they slid along each other, or a response already
    /// separates them): with the hierarchy, the driver then pops the
    /// approximation points that would slide along the other body
    /// ([`Kinetic::take_settled`]).
    pub(super) settled: Vec<(BodyId, BodyId)>,
    /// The last few certificates handled at the instant of the last one
    /// (where local operations that cycle at one instant are repaired,
    /// [`Kinetic::repair_cycle`]).
    pub(super) recent: VecDeque<[Att; 3]>,
    /// The instant of `recent`.
    pub(super) recent_at: Option<Time>,
    /// The last instant at which an owner's certificates were refreshed
    /// (after an operation, a pop, a removal, an insertion, a repair or the
    /// construction): an operation at another instant is the first change
    /// of the structure at its own, which [`crate::structure::Kss::trust_op`]
    /// asks.
    pub(super) changed_at: Option<Time>,
}
