//! The certificate store: every certificate's [`Scheduled`] record in a
//! slab (a generational [`slotmap::SlotMap`]), found by its [`CertId`] (the queue's payloads, the owners' lists
//! and the bodies' sets hold ids, so the event loop reaches a record with
//! one indexed load) or by its three points (a hashed index, asked when an
//! owner's refresh looks for a certificate it may share with another).
//!
//! Dropping a certificate leaves its entry in the index: the entry of a
//! dropped certificate is *stale* (its id is no longer live, which a
//! dense map of the live ids answers in a few bytes per slot), a lookup
//! reads a stale entry as none, and storing a certificate on the same
//! points again overwrites it. The stale entries are purged in one pass
//! when the index would otherwise grow and at least an eighth of it is
//! stale, so its table grows only when it is at least seven eighths live
//! (the gasmix's peak heap is unchanged). A drop is then one access to
//! the record and none to the index, whose buckets are scattered: the
//! certificates that a removal drops are cold in the cache.
//!
//! The time a certificate out of the queue was popped at (while it waits
//! to be handled) is in a small map by id beside the records: a few
//! entries at a time, so that a pop allocates nothing and no record
//! carries the field.

use super::{FastMap, Scheduled};
use crate::structure::Att;

slotmap::new_key_type! {
    /// A certificate's place in the [`CertStore`]: a slot and its version.
    /// A slot is reused after its certificate is dropped; an id kept past
    /// that (an owner's list that still names a dropped certificate) no
    /// longer finds anything.
    pub(super) struct CertId;
}

/// The certificates of the structure: a slab of records (a
/// [`slotmap::SlotMap`]), an index from the three points to the id (with
/// stale entries, module docs) and the set of live ids.
#[derive(Debug, Default)]
pub(super) struct CertStore {
    slots: slotmap::SlotMap<CertId, Scheduled>,
    /// From the points to the id: every live certificate's entry, and
    /// stale entries of dropped ones.
    index: FastMap<[Att; 3], CertId>,
    /// The live ids (a version per slot: four bytes, where a record of
    /// `slots` is over a hundred), read where an id may be stale.
    live: slotmap::SecondaryMap<CertId, ()>,
    /// The failure time each certificate that is out of the queue was
    /// popped (or taken out of the queue) at, while it waits to be handled
    /// or handled again: a few at a time, kept apart from the records so
    /// that a pop neither allocates nor makes every record larger.
    popped: FastMap<CertId, crate::num::Time>,
}

impl CertStore {
    /// The number of certificates.
    pub(super) fn len(&self) -> usize {
        self.slots.len()
    }

    /// The id of the certificate on `p`, if there is one.
    pub(super) fn id(&self, p: &[Att; 3]) -> Option<CertId> {
        self.index.get(p).copied().filter(|&id| self.is_live(id))
    }

    /// Whether `id` names a stored certificate (one dense load).
    pub(super) fn is_live(&self, id: CertId) -> bool {
        self.live.contains_key(id)
    }

    /// The certificate on `p`.
    pub(super) fn get(&self, p: &[Att; 3]) -> Option<&Scheduled> {
        self.find(p).map(|(_, s)| s)
    }

    /// The certificate on `p` with its id.
    pub(super) fn find(&self, p: &[Att; 3]) -> Option<(CertId, &Scheduled)> {
        let id = self.id(p)?;
        Some((id, self.at(id)?))
    }

    /// The certificate on `p` with its id, to change.
    pub(super) fn find_mut(&mut self, p: &[Att; 3]) -> Option<(CertId, &mut Scheduled)> {
        let id = self.id(p)?;
        Some((id, self.at_mut(id)?))
    }

    /// The certificate with id `id` (`None` once it is dropped).
    pub(super) fn at(&self, id: CertId) -> Option<&Scheduled> {
        self.slots.get(id)
    }

    /// The certificate with id `id`, to change.
    pub(super) fn at_mut(&mut self, id: CertId) -> Option<&mut Scheduled> {
        self.slots.get_mut(id)
    }

    /// Store `s`, which must be on points that have no certificate yet.
    pub(super) fn insert(&mut self, s: Scheduled) -> CertId {
        let p = s.cert.p;
        self.make_room();
        let id = self.slots.insert(s);
        self.live.insert(id, ());
        let old = self.index.insert(p, id);
        debug_assert!(
            old.is_none_or(|old| !self.is_live(old)),
            "two certificates on {p:?}"
        );
        id
    }

    /// Store `s` if its points have no certificate yet: `Ok` with its new
    /// id; else `Err` with the id of the certificate on them (`s` is not
    /// stored). One search of the index for both.
    pub(super) fn insert_new(&mut self, s: Scheduled) -> Result<CertId, CertId> {
        use std::collections::hash_map::Entry;
        self.make_room();
        match self.index.entry(s.cert.p) {
            Entry::Occupied(e) if self.live.contains_key(*e.get()) => Err(*e.get()),
            Entry::Occupied(mut e) => {
                let id = self.slots.insert(s);
                self.live.insert(id, ());
                e.insert(id);
                Ok(id)
            }
            Entry::Vacant(e) => {
                let id = self.slots.insert(s);
                self.live.insert(id, ());
                e.insert(id);
                Ok(id)
            }
        }
    }

    /// Take the certificate with id `id` out of the store (its index entry
    /// stays, stale: module docs; its popped time goes).
    pub(super) fn remove(&mut self, id: CertId) -> Option<Scheduled> {
        let s = self.slots.remove(id)?;
        self.live.remove(id);
        self.clear_popped(id);
        Some(s)
    }

    /// The failure time certificate `id` was popped at, while it is out of
    /// the queue waiting to be handled (`None` otherwise).
    pub(super) fn popped(&self, id: CertId) -> Option<&crate::num::Time> {
        if self.popped.is_empty() {
            return None;
        }
        self.popped.get(&id)
    }

    /// Note that certificate `id` was popped at `t`.
    pub(super) fn set_popped(&mut self, id: CertId, t: crate::num::Time) {
        debug_assert!(self.is_live(id), "a popped time for a dropped certificate");
        self.popped.insert(id, t);
    }

    /// Forget the time certificate `id` was popped at (it is queued again,
    /// idle or dropped).
    pub(super) fn clear_popped(&mut self, id: CertId) {
        if !self.popped.is_empty() {
            self.popped.remove(&id);
        }
    }

    /// The ids that have a popped time (the audit checks that each is
    /// live and out of the queue).
    pub(super) fn popped_ids(&self) -> impl Iterator<Item = CertId> + '_ {
        self.popped.keys().copied()
    }

    /// Purge the index's stale entries if it is full (the next new key
    /// would grow it) and at least an eighth of its entries are stale: a
    /// pass over the table for every eighth of it dropped, and the table
    /// grows only where a strict index's would be nearly full too.
    fn make_room(&mut self) {
        let len = self.index.len();
        if len < self.index.capacity() {
            return;
        }
        let stale = len - self.slots.len();
        if stale * 8 >= len {
            let live = &self.live;
            self.index.retain(|_, id| live.contains_key(*id));
        }
    }

    /// Whether the index finds every stored certificate by its points (its
    /// other entries are stale): the audit's check.
    pub(super) fn index_agrees(&self) -> bool {
        self.slots
            .iter()
            .all(|(id, s)| self.index.get(&s.cert.p) == Some(&id))
            && self.live.len() == self.slots.len()
    }

    /// Every certificate with its id, in no particular order.
    pub(super) fn iter(&self) -> impl Iterator<Item = (CertId, &Scheduled)> + '_ {
        self.slots.iter()
    }

    /// Every certificate's points, in no particular order.
    pub(super) fn keys(&self) -> impl Iterator<Item = &[Att; 3]> + '_ {
        self.slots.values().map(|s| &s.cert.p)
    }

    /// Every certificate, in no particular order.
    pub(super) fn values(&self) -> impl Iterator<Item = &Scheduled> + '_ {
        self.slots.values()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::Sign;
    use crate::structure::certs::{Cert, CertKind};
    use crate::structure::ops::Owner;
    use crate::structure::{Obj, TriId};
    use crate::world::BodyId;

    fn rec(v: u32) -> Scheduled {
        let a = |b: u32, v: u32| Att {
            obj: Obj::Body(BodyId::new(b)),
            v,
        };
        Scheduled {
            cert: Cert {
                p: [a(0, v), a(1, v), a(2, v)],
                sign: Sign::Positive,
                kind: CertKind::Triangle,
            },
            key: None,
            owners: smallvec::smallvec![Owner::Tri(TriId(v))],
            fp: None,
            idle: false,
        }
    }

    #[test]
    fn a_dropped_certificates_id_finds_nothing_after_its_slot_is_reused() {
        let mut store = CertStore::default();
        let a = store.insert(rec(1));
        let b = store.insert(rec(2));
        assert_eq!(store.len(), 2);
        let p1 = store.at(a).expect("stored").cert.p;
        assert_eq!(store.id(&p1), Some(a));
        assert!(store.remove(a).is_some());
        assert!(store.at(a).is_none());
        assert!(store.get(&p1).is_none());
        assert!(store.remove(a).is_none());
        let c = store.insert(rec(3));
        assert_ne!(c, a, "the reused slot has a new generation");
        assert!(store.at(a).is_none());
        assert_eq!(store.at(c).map(|s| s.owners[0]), Some(Owner::Tri(TriId(3))));
        assert_eq!(store.at(b).map(|s| s.owners[0]), Some(Owner::Tri(TriId(2))));
        assert_eq!(store.len(), 2);
        assert_eq!(store.values().count(), 2);
        assert_eq!(store.keys().count(), 2);
    }

    #[test]
    fn insert_new_stores_only_on_points_without_a_certificate() {
        let mut store = CertStore::default();
        let a = store.insert_new(rec(1)).expect("new points");
        let mut again = rec(1);
        again.owners = smallvec::smallvec![Owner::Tri(TriId(9))];
        assert_eq!(store.insert_new(again), Err(a));
        assert_eq!(store.len(), 1);
        assert_eq!(store.at(a).map(|s| s.owners[0]), Some(Owner::Tri(TriId(1))));
        let b = store.insert_new(rec(2)).expect("new points");
        assert_ne!(a, b);
        assert_eq!(store.id(&store.at(b).expect("stored").cert.p), Some(b));
        assert!(store.remove(a).is_some());
        let c = store.insert_new(rec(1)).expect("the points are free again");
        assert_ne!(c, a);
        assert_eq!(store.len(), 2);
    }

    #[test]
    fn stale_entries_are_purged_before_the_index_grows() {
        let mut store = CertStore::default();
        let mut ids: Vec<CertId> = (0..60).map(|v| store.insert(rec(v))).collect();
        // churn: drop the oldest, store one on new points, many times over
        for v in 60..20_000 {
            let id = ids.remove(0);
            let p = store.at(id).expect("stored").cert.p;
            assert!(store.remove(id).is_some());
            assert!(store.id(&p).is_none(), "a dropped certificate is found");
            ids.push(store.insert_new(rec(v)).expect("new points"));
            // (a strict index holds the 60 and grows once it is half full)
            assert!(store.index.capacity() <= 4 * 60, "the index grew at {v}");
        }
        assert!(store.index_agrees());
        assert_eq!(store.len(), 60);
        assert_eq!(store.keys().count(), 60);
        // a stale entry's points take a new certificate
        let id = ids[0];
        let p = store.at(id).expect("stored").cert.p;
        store.remove(id);
        let again = store.insert_new(rec(p[0].v)).expect("free points");
        assert_ne!(again, id);
        assert_eq!(store.id(&p), Some(again));
        assert!(store.index_agrees());
    }
}
