//! The audit: every invariant of the structure and of its certificate book
//! checked exactly at a rational instant between events, against a
//! recomputation from scratch.

use std::collections::BTreeSet;

use crate::num::{Rational, Sign, Time};
use crate::structure::geo::Geo;
use crate::structure::StructureError;

use super::book::{bridge_end, cert_poly, resting_flat};
use super::step::each_body;
use super::{CertId, Kinetic, QKey};
use crate::structure::ops::Owner;
use crate::structure::{CorrId, TriId};

impl Kinetic {
    /// Check every invariant at the rational instant `at`, strictly after the
    /// last event `now` and before the next one: topology, every corridor face
    /// a pseudo-triangle, every certificate holding, and the scheduled set
    /// equal to a from-scratch recomputation with the right failure times
    /// (a certificate out of the queue until a bridge ends: no failure up
    /// to that end).
    pub fn audit(&self, world: &Geo, now: &Time, at: &Rational) -> Result<(), StructureError> {
        let at_t = Time::from_rational(at.clone());
        self.kss.check_topology(world)?;
        self.kss.check_faces(world, &at_t)?;
        self.kss.check_bridges(world, at)?;
        let fresh = self.kss.certificates(world, &at_t)?;
        if fresh.len() != self.certs.len() {
            let have: BTreeSet<_> = self.certs.keys().collect();
            let want: BTreeSet<_> = fresh.iter().map(|c| &c.p).collect();
            return Err(StructureError::Invariant(format!(
                "{} certificates kept, {} expected (extra {:?}, missing {:?})",
                self.certs.len(),
                fresh.len(),
                have.difference(&want).take(3).collect::<Vec<_>>(),
                want.difference(&have).take(3).collect::<Vec<_>>(),
            )));
        }
        let (mut scheduled, mut idle) = (0, 0);
        for c in &fresh {
            if let Some(&a) = c.p.iter().find(|&&a| !world.enclosure_cache_agrees(a)) {
                return Err(StructureError::Invariant(format!(
                    "the cached enclosure of {a:?} (in certificate {:?}) is not the fresh one",
                    c.p
                )));
            }
            let s = self.certs.get(&c.p).ok_or_else(|| {
                StructureError::Invariant(format!("certificate {:?} missing", c.p))
            })?;
            if s.cert.sign != c.sign {
                return Err(StructureError::Invariant(format!(
                    "certificate {:?} has the wrong sign",
                    c.p
                )));
            }
            let p = cert_poly(world, c);
            match p.sign_at(&at_t) {
                Sign::Positive => {}
                Sign::Zero if resting_flat(world, c, &p) => {}
                _ if p.sign_before(&at_t) == Sign::Positive
                    && p.sign_after(&at_t) == Sign::Positive => {}
                s => {
                    return Err(StructureError::Invariant(format!(
                        "certificate {:?} is {s:?} at {at}",
                        c.p
                    )))
                }
            }
            let want = p.first_failure_after(now);
            let got = match s.key {
                Some(QKey::Near(k)) => self.queue.get(k).map(|(t, _)| t.clone()),
                // (known by its enclosure: the failure lies in it, strictly
                // after the current instant)
                Some(QKey::Far(k)) => {
                    let bounds = self
                        .far
                        .get(k)
                        .map(|(ft, _)| (Time::from_f64(ft.0.lo), Time::from_f64(ft.0.hi), ft.0));
                    match (&want, bounds) {
                        (Some(w), Some((Some(lo), Some(hi), _)))
                            if w > now && lo <= *w && *w <= hi =>
                        {
                            want.clone()
                        }
                        (_, b) => {
                            return Err(StructureError::Invariant(format!(
                                "certificate {:?} in the far queue at {:?}, fails at {want:?}",
                                c.p,
                                b.map(|(_, _, iv)| iv)
                            )))
                        }
                    }
                }
                None => None,
            };
            if s.idle {
                // out of the queue until a bridge of one of its bodies ends,
                // where it is scheduled again: no failure up to that end
                let end = bridge_end(world, &c.p);
                let holds = end.is_some_and(|e| want.as_ref().is_none_or(|w| w > e));
                if s.key.is_some() || !holds {
                    return Err(StructureError::Invariant(format!(
                        "certificate {:?} idle until a bridge ends at {end:?}, fails at {want:?}",
                        c.p
                    )));
                }
                idle += 1;
            } else if want != got {
                return Err(StructureError::Invariant(format!(
                    "certificate {:?} scheduled at {got:?}, fails at {want:?}",
                    c.p
                )));
            }
            scheduled += usize::from(got.is_some());
        }
        if idle != self.idle {
            return Err(StructureError::Invariant(format!(
                "{} certificates counted idle, {idle} marked",
                self.idle
            )));
        }
        if scheduled != self.queue.len() + self.far.len() {
            return Err(StructureError::Invariant(format!(
                "{} queued events for {scheduled} scheduled certificates",
                self.queue.len() + self.far.len()
            )));
        }
        self.audit_ids()
    }

    /// The ids agree with the records: the index, each queued event's
    /// payload, the owners' lists and the bodies' sets name each
    /// certificate by its id, and nothing else.
    fn audit_ids(&self) -> Result<(), StructureError> {
        let bad = |what: String| Err(StructureError::Invariant(what));
        let mut on_bodies = 0;
        for (id, s) in self.certs.iter() {
            let p = s.cert.p;
            if self.certs.id(&p) != Some(id) {
                return bad(format!("certificate {p:?} is not indexed by its id"));
            }
            let queued = match s.key {
                Some(QKey::Near(k)) => Some(self.queue.get(k).map(|(_, &q)| q)),
                Some(QKey::Far(k)) => Some(self.far.get(k).map(|(_, e)| e.id)),
                None => None,
            };
            if queued.is_some_and(|q| q != Some(id)) {
                return bad(format!("the queued event of {p:?} names another id"));
            }
            for b in each_body(&p) {
                on_bodies += 1;
                if !self
                    .by_body
                    .get(&b)
                    .is_some_and(|set| set.iter().any(|&x| x == id))
                {
                    return bad(format!("certificate {p:?} is not in the set of {b:?}"));
                }
            }
            for o in &s.owners {
                if !self.owned(*o).contains(&id) {
                    return bad(format!("owner {o:?} of {p:?} does not list it"));
                }
            }
        }
        let mut in_sets = 0;
        for set in &self.by_body.0 {
            let live: Vec<CertId> = set
                .iter()
                .copied()
                .filter(|&x| self.certs.is_live(x))
                .collect();
            if live.len() != set.len() {
                return bad(format!(
                    "a body's set counts {} certificates and lists {}",
                    set.len(),
                    live.len()
                ));
            }
            in_sets += live.len();
        }
        if !self.certs.index_agrees() {
            return bad("the index by points does not find a certificate".into());
        }
        if in_sets != on_bodies {
            return bad(format!(
                "{in_sets} entries in the bodies' sets for {on_bodies} certificates on bodies"
            ));
        }
        let lists = (self.owned_tri.iter().enumerate())
            .map(|(i, l)| (Owner::Tri(TriId(i as u32)), l.as_slice()))
            .chain(
                (self.owned_corr.iter().enumerate())
                    .map(|(i, l)| (Owner::Corr(CorrId(i as u32)), l.as_slice())),
            );
        for (o, list) in lists {
            for &id in list {
                if !self.certs.at(id).is_some_and(|s| s.owners.contains(&o)) {
                    return bad(format!("{o:?} lists a certificate it does not own"));
                }
            }
        }
        // a popped time belongs to a stored certificate out of the queue
        for id in self.certs.popped_ids() {
            match self.certs.at(id) {
                Some(s) if s.key.is_none() => {}
                Some(s) => {
                    return bad(format!(
                        "certificate {:?} is queued and has a popped time",
                        s.cert.p
                    ));
                }
                None => return bad("a popped time for a dropped certificate".into()),
            }
        }
        Ok(())
    }
}
