//! The kinetic layer: every certificate of the structure scheduled in the
//! event queue at its exact failure time; failures popped in time order and
//! either reported as collisions or repaired by a local operation
//! ([`super::ops`]), after which only the touched corridors and triangles get
//! new certificates; flight-plan changes reschedule only the certificates of
//! the bodies involved; and an audit against a from-scratch recomputation.
//!
//! [`Kinetic`] is the structure with its certificates scheduled. Its methods
//! are grouped by concept:
//!
//! - `book`: certificates, their failure times and the event queue;
//! - `step`: one event, popped, classified and handled;
//! - `motion`: flight-plan changes and collision responses;
//! - `repair`: pops, removals, insertions, local repair, rebuilds, merges;
//! - `audit`: the exact check of every invariant between events.

use super::certs::Cert;
use super::geo::Geo;
use super::ops::Owner;
use super::{Att, CorrId, Kss};
use crate::num::{Rational, Time};
use crate::sim::{EventKey, EventQueue};
use crate::structure::StructureError;
use crate::world::BodyId;

/// Debug tracing of every failure (`--features trace`; the library does no
/// IO otherwise).
macro_rules! trace {
    ($($arg:tt)*) => {
        #[cfg(feature = "trace")]
        eprintln!($($arg)*);
    };
}

mod audit;
mod book;
mod instant;
mod motion;
mod repair;
mod step;
mod store;
mod tally;

pub(crate) use repair::PendingPops;
pub use repair::SetRemoval;
pub use tally::{Rebuild, Tally};

use instant::InstantState;
use store::{CertId, CertStore};

/// The certificates a corridor owns, in its order, inline: at most
/// [`MAX_CERTS`] (its junctions or hull turns), so that a refresh neither
/// allocates nor follows a pointer to read or replace them. A partition
/// triangle owns at most one ([`Kinetic::owned_tri`]).
///
/// [`MAX_CERTS`]: crate::structure::local::MAX_CERTS
type Owned = arrayvec::ArrayVec<CertId, { crate::structure::local::MAX_CERTS }>;

/// A hash map with a fixed hasher (the same order in every run).
type FastMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;

/// The certificates on one body ([`Kinetic::by_body`]): a list of ids in
/// the order they were added, which may still hold ids of certificates
/// dropped since (a drop does not search the list: it counts the body's
/// certificates down, and the list is purged of dropped ids once they are
/// a third of it). Readers skip the ids that the store no longer finds.
#[derive(Clone, Debug, Default)]
struct CertSet {
    ids: Vec<CertId>,
    /// How many of `ids` are live.
    live: usize,
}

/// The certificates on each body, indexed by body id ([`Kinetic::by_body`]):
/// body ids are dense, so a vector, not a hashed map, finds a body's set.
#[derive(Clone, Debug, Default)]
struct ByBody(Vec<CertSet>);

impl ByBody {
    /// The set of body `b` (`None` if it has never had one).
    fn get(&self, b: &BodyId) -> Option<&CertSet> {
        self.0.get(b.index())
    }

    fn get_mut(&mut self, b: &BodyId) -> Option<&mut CertSet> {
        self.0.get_mut(b.index())
    }

    /// The set of body `b`, made empty if it has none yet.
    fn at(&mut self, b: BodyId) -> &mut CertSet {
        if self.0.len() <= b.index() {
            self.0.resize_with(b.index() + 1, CertSet::default);
        }
        &mut self.0[b.index()]
    }

    /// Forget body `b`'s set (its memory too).
    fn remove(&mut self, b: &BodyId) {
        if let Some(set) = self.0.get_mut(b.index()) {
            *set = CertSet::default();
        }
    }
}

impl CertSet {
    /// Add certificate `id`, which is live and not in the set.
    fn insert(&mut self, id: CertId) {
        debug_assert!(!self.ids.contains(&id));
        // (grown by a few at a time while short: doubling would leave up
        // to half of a list of a few dozen unused)
        if self.ids.len() == self.ids.capacity() && self.ids.len() < 256 {
            self.ids.reserve_exact(8);
        }
        self.ids.push(id);
        self.live += 1;
    }

    /// Note that one of the set's certificates was dropped (`live` tells
    /// the ids still stored); the list is purged once a third of it is
    /// dropped ids, in a pass that keeps the order.
    fn dropped(&mut self, live: impl Fn(CertId) -> bool) {
        debug_assert!(self.live > 0, "a drop from a set without certificates");
        self.live -= 1;
        if self.ids.len() >= self.live + self.live / 2 + 8 {
            self.ids.retain(|&id| live(id));
            debug_assert_eq!(self.ids.len(), self.live, "a set's count of live ids");
        }
    }

    /// The number of certificates in the set.
    fn len(&self) -> usize {
        self.live
    }

    fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// The ids in the list: every certificate of the set, and ids of
    /// certificates dropped since (which the store does not find).
    fn iter(&self) -> std::slice::Iter<'_, CertId> {
        self.ids.iter()
    }
}

impl<'a> IntoIterator for &'a CertSet {
    type Item = &'a CertId;
    type IntoIter = std::slice::Iter<'a, CertId>;

    fn into_iter(self) -> std::slice::Iter<'a, CertId> {
        self.iter()
    }
}

/// The owners of a certificate: one or two nearly always, kept in place
/// (no allocation per certificate, and no second cache line to read when
/// an owner is added or taken off); more spill to the heap.
type Owners = smallvec::SmallVec<[Owner; 2]>;

/// A certificate, where it sits in the queue, and who owns it.
#[derive(Clone, Debug)]
struct Scheduled {
    cert: Cert,
    /// Where it waits for its failure ([`QKey`]): `None` when the
    /// certificate never fails on the current motions, or while it waits
    /// (a contact reported at the current instant).
    key: Option<QKey>,
    owners: Owners,
    /// What the three points were ([`Geo::point_id`]) when the failure
    /// time under `key` was computed (`None` when it has none): while they
    /// are the same points, the certificate is known to be wrong just after
    /// that time, which is a root where it turns negative (the flag:
    /// `true`) or the instant it was computed at, where it is not positive
    /// just after ([`book::failure_time`]). Also `None` when that time is
    /// deferred: its computation holds the points, and
    /// [`book::schedule_fp`] reads them there (no allocation and no
    /// lookup of the points for most certificates).
    /// (Boxed: the map of certificates stays small. The time a
    /// certificate out of the queue was popped at is kept by the store,
    /// [`CertStore::popped`].)
    fp: Option<Box<(Fingerprint, bool)>>,
    /// Out of the queue until the end of a bridge of one of its bodies
    /// ([`Kinetic::idle_until_bridge_end`]).
    idle: bool,
}

/// Where a scheduled certificate waits: in the queue of exact failure
/// times ([`Kinetic::queue`]), or in the far queue ([`Kinetic::far`]),
/// known by an enclosure of its failure time until that time could be the
/// next failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum QKey {
    /// In the queue of exact times.
    Near(EventKey),
    /// In the far queue.
    Far(EventKey),
}

impl QKey {
    /// The key in the queue of exact times (`None` in the far queue).
    fn near(self) -> Option<EventKey> {
        match self {
            QKey::Near(k) => Some(k),
            QKey::Far(_) => None,
        }
    }
}

/// A failure time known by a certified enclosure alone: a root of the
/// certificate's function that the f64 filter isolated strictly after the
/// instant it was computed at (the failure time itself, made exact only
/// when it could be the next failure). Ordered by its lower bound, then
/// its upper bound.
#[derive(Clone, Copy, Debug)]
struct FarTime(crate::num::Interval);

impl PartialEq for FarTime {
    fn eq(&self, other: &FarTime) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for FarTime {}

impl PartialOrd for FarTime {
    fn partial_cmp(&self, other: &FarTime) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for FarTime {
    fn cmp(&self, other: &FarTime) -> std::cmp::Ordering {
        (self.0.lo.total_cmp(&other.0.lo)).then(self.0.hi.total_cmp(&other.0.hi))
    }
}

impl crate::sim::Enclosed for FarTime {
    #[inline]
    fn enclosure(&self) -> (f64, f64) {
        (self.0.lo, self.0.lo)
    }
}

/// A certificate in the far queue: its id, the tie class and the
/// sequence number it takes into the queue of exact times
/// ([`EventQueue::reserve_seq`]: the place it had if queued there at once),
/// and which points its three points were when the enclosure was computed
/// (each by the id before it in its body's approximation,
/// [`Geo::pred_id`]), which its exact time reads ([`book::far_deferred`]):
/// an approximation's vertex can move (a pop or a merge) before the book
/// schedules its certificates again, and a failure time keeps the points
/// it was computed for, in either queue (see [`Scheduled::fp`]).
#[derive(Clone, Copy, Debug)]
struct FarEntry {
    id: CertId,
    preds: [u32; 3],
    tie: u64,
    seq: u64,
    /// (debug builds: the uids of the points' frames when it was
    /// scheduled, the same when its exact time is made: a motion change
    /// schedules the certificates of its bodies again)
    #[cfg(debug_assertions)]
    frames: [u64; 3],
}

/// The failure time a certificate is due at: its queued time, or the one it
/// was popped at (`None` in the far queue: it is not due before the
/// enclosure of its failure time, which lies after the current instant).
fn due_time<'a>(
    queue: &'a EventQueue<Time, CertId>,
    key: Option<QKey>,
    popped: Option<&'a Time>,
) -> Option<&'a Time> {
    match key {
        Some(QKey::Near(k)) => queue.get(k).map(|(t, _)| t),
        Some(QKey::Far(_)) => None,
        None => popped,
    }
}

/// The identities of a certificate's three points ([`Geo::point_id`]).
type Fingerprint = [(u64, (u32, u32)); 3];

/// The fingerprint of the points of `p` now (`None` if one is `ω` or not
/// a vertex of its body's current approximation).
fn fingerprint(world: &Geo, p: &[Att; 3]) -> Option<Fingerprint> {
    Some([
        world.point_id(p[0])?,
        world.point_id(p[1])?,
        world.point_id(p[2])?,
    ])
}

/// The structure with its certificates scheduled.
#[derive(Debug, Default)]
pub struct Kinetic {
    /// The combinatorial structure.
    pub kss: Kss,
    /// Every certificate, by id and by its points ([`CertStore`]);
    /// iterated only where the order does not matter or is sorted first.
    certs: CertStore,
    /// The certificates that involve each body (for local rescheduling when
    /// a flight plan changes): unordered ([`CertSet`]), sorted where the
    /// order matters (it decides the queue's insertion order, the last
    /// tie-breaker).
    by_body: ByBody,
    /// The certificate each partition triangle owns (its orientation;
    /// none for a triangle with a corner at `ω`).
    owned_tri: Vec<Option<CertId>>,
    /// The certificates each corridor owns.
    owned_corr: Vec<Owned>,
    /// The certificates whose exact failure time could be the next one
    /// (or the one being handled), by that time.
    queue: EventQueue<Time, CertId>,
    /// The other scheduled certificates, by an enclosure of their failure
    /// times: each fails strictly after the current instant, and
    /// [`Kinetic::admit`] moves over those that could fail no later than
    /// the first failure in `queue` before that queue is read. No exact
    /// (deferred) time is made for a certificate that is dropped before it
    /// could be the next failure, which is most of them.
    far: EventQueue<FarTime, FarEntry>,
    /// Certificates out of the queue until a bridge ends (`Scheduled::idle`):
    /// counted as scheduled.
    idle: usize,
    max_active: usize,
    /// What the engine holds about the current instant.
    instant: InstantState,
    /// Internal events and fallbacks by kind.
    pub tally: Tally,
    /// The instant of the latest [`Kinetic::rebuild_after`] that found no
    /// structure (polygons may rest in contact there; the driver decides).
    pub unbuildable: Option<Time>,
    /// The corridors the last operation touched (where coarsening is tried).
    last_touched: Vec<CorrId>,
    /// While `Some`, the ids of the certificates scheduled anew
    /// ([`Kinetic::refresh_moved`]: they need no second failure time).
    scheduled: Option<Vec<CertId>>,
    /// Rotates the coarsening candidates.
    tick: u64,
    /// The places and the linear enclosures of the points a motion change
    /// asks for ([`Kinetic::motion_changed`]), and the bitmap of the
    /// corridors it looks for resting points in ([`Kinetic::resting_now`]),
    /// emptied at each: kept only so that a motion change does not
    /// allocate them again.
    motion_memo: MotionMemo,
}

/// [`Kinetic::motion_memo`].
type MotionMemo = (
    FastMap<Att, Option<crate::geom::MidRad>>,
    FastMap<Att, Option<[crate::geom::Mr; 4]>>,
    Vec<u64>,
);

impl Kinetic {
    /// Every certificate with its owners and scheduled failure time (a
    /// debugging view, in the order of their points; `world` is the view
    /// the structure sees the bodies through).
    pub fn certificate_list(&self, world: &Geo) -> Vec<(Cert, Vec<Owner>, Option<Time>)> {
        let mut keys: Vec<&[Att; 3]> = self.certs.keys().collect();
        keys.sort();
        keys.into_iter()
            .map(|p| {
                let s = self.certs.get(p).expect("a stored certificate");
                let t = match s.key {
                    Some(QKey::Near(k)) => self.queue.get(k).map(|(t, _)| t.clone()),
                    Some(QKey::Far(k)) => self
                        .far
                        .get(k)
                        .and_then(|(ft, e)| book::far_deferred(world, &s.cert, ft, e)),
                    None => None,
                };
                (s.cert, s.owners.to_vec(), t)
            })
            .collect()
    }
}

/// What one step of the engine did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// No failure at or before the limit.
    Idle,
    /// A structural event at this time.
    Internal(Time),
    /// Two bodies touch at this time.
    Contact(Time, Vec<(BodyId, BodyId)>),
    /// A failure at this time next to a contact, set aside.
    Deferred(Time),
    /// Two approximations touch at this time where the polygons do not (a
    /// certificate with an approximation vertex on this triple failed): the
    /// hierarchy must refine them there.
    Refine(Time, [Att; 3]),
}

impl Kinetic {
    /// Build the structure at time `t` and schedule its certificates.
    pub fn new(world: &Geo, t: &Rational) -> Result<Kinetic, StructureError> {
        let (kss, perturbed) = super::build::build(world, t)?;
        Kinetic::from_built(world, t, kss, perturbed)
    }

    /// The engine on a freshly built structure: middle bridges placed,
    /// corridors normalized, certificates scheduled; a build from the
    /// shrunk copy is checked exactly first.
    pub(crate) fn from_built(
        world: &Geo,
        t: &Rational,
        kss: Kss,
        perturbed: super::build::Perturbed,
    ) -> Result<Kinetic, StructureError> {
        // every alive polygon is in a structure of the right size: one built
        // at an instant where polygons overlap lacks some (a cheap check;
        // the rebuilds for just after an instant try an earlier one then)
        let n = world.alive_count();
        if n >= 2 && (kss.tris.len() != 2 * n - 2 || kss.corrs.len() != 3 * n - 3) {
            return Err(StructureError::Build(format!(
                "{} partition triangles and {} corridors for {n} polygons: polygons overlap at t = {}",
                kss.tris.len(),
                kss.corrs.len(),
                t.to_f64()
            )));
        }
        let mut k = Kinetic {
            kss,
            ..Default::default()
        };
        let now = Time::from_rational(t.clone());
        k.kss.place_middle_bridges(world, &now);
        k.schedule_everything(world, &now)?;
        if perturbed == super::build::Perturbed::Yes {
            // built from shrunk polygons: only a candidate until the exact
            // checks accept it (O(N) and more, but only where polygons touch)
            k.kss.check_topology(world)?;
            k.kss.check_faces(world, &now)?;
            k.kss.check_bridges(world, t)?;
        }
        Ok(k)
    }

    /// Rebuild the structure from scratch at `t` (after polygons were removed)
    /// and schedule its certificates.
    pub fn rebuild(&mut self, world: &Geo, t: &Rational) -> Result<(), StructureError> {
        let fresh = Kinetic::new(world, t)?;
        self.replace_with(fresh);
        Ok(())
    }

    /// Become `fresh`, keeping the event counts and the largest queue size.
    fn replace_with(&mut self, mut fresh: Kinetic) {
        fresh.tally = std::mem::take(&mut self.tally);
        // the touches of this instant still need their pops afterwards
        fresh.instant.settled = std::mem::take(&mut self.instant.settled);
        // (a rebuild changes the structure at this instant)
        if fresh.instant.changed_at.is_none() {
            fresh.instant.changed_at = self.instant.changed_at.take();
        }
        fresh.max_active = fresh.max_active.max(self.max_active);
        *self = fresh;
    }

    /// The earliest scheduled failure, if any, or an instant no later than
    /// it (the lower bound of a failure time in the far queue that may
    /// come first: every failure after the current instant is at this
    /// instant or later).
    pub fn next_time(&self) -> Option<Time> {
        let near = match &self.instant.later {
            Some((t, _)) => Some(t),
            None => self.queue.peek().map(|(_, t, _, _)| t),
        };
        let far = self
            .far
            .peek()
            .and_then(|(_, ft, _, _)| Time::from_f64(ft.0.lo));
        match (near, far) {
            (Some(t), Some(lo)) if lo < *t => Some(lo),
            (Some(t), _) => Some(t.clone()),
            (None, lo) => lo,
        }
    }

    /// Certificates that can fail (scheduled, or to be scheduled when a
    /// bridge ends) now, and at most so far.
    pub fn active(&self) -> (usize, usize) {
        (self.active_now(), self.max_active)
    }

    /// Certificates in the queue or out of it until a bridge ends.
    fn active_now(&self) -> usize {
        self.queue.len() + self.far.len() + self.idle
    }

    /// All certificates, scheduled or not.
    pub fn certificate_count(&self) -> usize {
        self.certs.len()
    }

    // ----- read-only views (for pictures; no effect on the simulation) -----

    /// Every certificate scheduled in the event queues with its failure
    /// time, in no particular order (certificates that never fail on the
    /// current motions, or that wait for a collision response, are not
    /// listed); `world` is the view the structure sees the bodies through.
    pub fn scheduled<'a>(&'a self, world: &'a Geo) -> impl Iterator<Item = (Time, &'a Cert)> + 'a {
        let near = (self.queue.iter())
            .filter_map(|(_, t, _, &id)| self.certs.at(id).map(|s| (t.clone(), &s.cert)));
        let far = self.far.iter().filter_map(|(_, ft, _, e)| {
            let s = self.certs.at(e.id)?;
            Some((book::far_deferred(world, &s.cert, ft, e)?, &s.cert))
        });
        near.chain(far)
    }
}

#[cfg(test)]
mod tests;
