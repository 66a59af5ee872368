//! Repair and rebuild: pops in place, removals and insertions of bodies,
//! the local retriangulation of a region where the local operations fail at
//! a degenerate instant, the rebuild for just after an instant, and the
//! hierarchy's coarsening (merges) after an operation.

use std::collections::{BTreeMap, BTreeSet};

use crate::num::{Sign, Time};
use crate::structure::geo::Geo;
use crate::structure::ops::Owner;
use crate::structure::StructureError;
use crate::structure::{Att, Obj};
use crate::world::BodyId;

use super::book::{cert_poly, due_is_failing, resting_flat};
use super::instant::Broken;
use super::tally::Rebuild;
use super::Owned;
use super::{due_time, CertId, Kinetic, QKey};

/// The local repair's candidate sets ([`Kinetic::repair_around`]): queue
/// `set` grown by the bodies `more` (with the number of growth rounds that
/// led to it), unless `more` is empty, `set` was grown twice already, or
/// the same set (in any order) is queued.
pub(super) fn grow_sets(
    sets: &mut Vec<Vec<BodyId>>,
    grown: &mut Vec<u8>,
    (set, rounds): (&[BodyId], u8),
    more: Vec<BodyId>,
) {
    if more.is_empty() || rounds >= 2 {
        return;
    }
    let mut bigger = set.to_vec();
    bigger.extend(more);
    bigger.sort();
    let queued = sets.iter().any(|x| {
        let mut x = x.clone();
        x.sort();
        x == bigger
    });
    if !queued {
        sets.push(bigger);
        grown.push(rounds + 1);
    }
}

/// Whether the new partition triangles of `plan`, made for the instant
/// `at`, hold from just after `now` to `at` (or stay flat while two of
/// their corners rest on each other).
pub(super) fn plan_holds(
    world: &Geo,
    plan: &crate::structure::remove::RemovalPlan,
    now: &Time,
    at: &Time,
) -> bool {
    plan.new_triangles().iter().all(|c| {
        if c.iter().any(|a| a.is_omega()) {
            return true;
        }
        let [x, y, z] = c.map(|a| world.point(a));
        let q = crate::motion::orient_poly(&x, &y, &z);
        (q.is_zero() && crate::structure::faces::flat_while_resting(world, *c))
            || (q.sign_after(now) == Sign::Positive
                && q.first_failure_after(now).is_none_or(|x| x > *at))
    })
}

/// The alive body other than `b` whose bounding box is nearest to `b`'s at
/// `now` (doubles: a starting point for [`Kinetic::insert_body`], which
/// checks everything exactly).
pub(super) fn nearest_body(world: &Geo, b: BodyId, now: &Time) -> Option<BodyId> {
    let t = now.to_f64();
    let bounds = |c: BodyId| world.body(c).bounds_f64(t);
    let nb = bounds(b);
    let gap = |o: [f64; 4]| {
        let dx = (o[0] - nb[1]).max(nb[0] - o[1]).max(0.0);
        let dy = (o[2] - nb[3]).max(nb[2] - o[3]).max(0.0);
        dx * dx + dy * dy
    };
    (0..world.bodies().len() as u32)
        .map(BodyId::new)
        .filter(|&c| c != b && world.body(c).alive)
        .map(|c| (gap(bounds(c)), c))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, c)| c)
}

/// The pops of one instant done in the structure but not yet normalized
/// nor refreshed ([`Kinetic::pop_deferred`], [`Kinetic::finish_pops`]).
#[derive(Default)]
pub(crate) struct PendingPops {
    /// Each pop's body and the vertices that changed place.
    moved: Vec<(BodyId, Vec<Att>)>,
    /// The certificates on those vertices before the first pop.
    named: super::book::Named,
    /// The touched triangles and corridors, and the owners of `named`.
    owners: BTreeSet<Owner>,
}

/// What [`Kinetic::remove_bodies`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetRemoval {
    /// The bodies are out of the structure.
    Removed,
    /// Their region has no plan: the structure is unchanged.
    NoPlan,
    /// The removal could not be done in place: the structure may be half
    /// changed (the caller rebuilds it).
    Failed,
}

impl Kinetic {
    /// Pop approximation vertex `a` (in `shapes`) at `t` and update the
    /// structure in place ([`crate::structure::Kss::pop_vertex`]): the touched corridors are
    /// normalized and their owners' certificates, and every certificate on a
    /// vertex of the body that moved, recomputed. Returns whether the
    /// approximation changed and whether the structure followed (if not, it
    /// must be rebuilt on the new approximations).
    pub fn pop_local(
        &mut self,
        world: &crate::world::World,
        shapes: &mut crate::structure::geo::Shapes,
        a: Att,
        t: &Time,
    ) -> Result<(bool, bool), StructureError> {
        let mut pending = PendingPops::default();
        let (changed, followed) = self.pop_deferred(world, shapes, a, t, &mut pending)?;
        if !followed {
            return Ok((changed, false));
        }
        Ok((changed, self.finish_pops(world, shapes, t, pending, None)?))
    }

    /// [`Kinetic::pop_local`] up to the pop in the structure: the touched
    /// corridors keep the middle bridges the pop's check set (for one side
    /// of `t`), and what the normalizations and the refreshes need is added
    /// to `pending`, for [`Kinetic::finish_pops`] once the instant's last
    /// pop is done. The pops of one instant are one change of the
    /// structure: normalizing after each would look for decompositions just
    /// after `t` while the instant's other popped vertices still fail
    /// there (a decomposition held against the motion, searched at every
    /// start, for each), and would schedule certificates the next pop
    /// replaces.
    pub(crate) fn pop_deferred(
        &mut self,
        world: &crate::world::World,
        shapes: &mut crate::structure::geo::Shapes,
        a: Att,
        t: &Time,
        pending: &mut PendingPops,
    ) -> Result<(bool, bool), StructureError> {
        let (corrs, tris, ids) = match self.kss.pop_vertex(world, shapes, a, t) {
            crate::structure::pop::PopResult::NotPopped => return Ok((false, true)),
            crate::structure::pop::PopResult::Failed => {
                trace!("pop of {a:?} at {} not local: rebuilding", t.to_f64());
                return Ok((true, false));
            }
            crate::structure::pop::PopResult::Local { corrs, tris, ids } => (corrs, tris, ids),
        };
        let Obj::Body(b) = a.obj else {
            unreachable!("a popped vertex is on a body")
        };
        // every certificate on a changed vertex, and its owners (the book
        // is as it was before the instant's first pop: only
        // `finish_pops` refreshes it)
        let (named, owners) = self.owners_naming(b, &ids);
        pending.named.merge(named);
        pending.owners.extend(owners);
        pending.owners.extend(corrs.iter().map(|&k| Owner::Corr(k)));
        pending.owners.extend(tris.iter().map(|&t| Owner::Tri(t)));
        pending.moved.push((b, ids));
        self.tally.local_pops += 1;
        Ok((true, true))
    }

    /// After the pops of `pending` at `t` ([`Kinetic::pop_deferred`]):
    /// normalize the touched corridors just after `t` and recompute the
    /// certificates of every owner of a touched face or of a certificate on
    /// a moved vertex. Returns whether the structure followed (if not, it
    /// must be rebuilt on the new approximations).
    ///
    /// With `failed`, the body of a pop that the structure could not
    /// follow (its approximation is refined in `shapes`, the structure is
    /// as before that pop): the faces on that body, or at a triangle with
    /// a corner on it, are left as they are, for the repair of the region
    /// around it or the rebuild that comes next; the pops before it are
    /// finished everywhere else (faces away from the failed pop's body,
    /// such as those a pop's triangle collapses changed between two other
    /// bodies, would otherwise keep certificates of faces that are gone).
    pub(crate) fn finish_pops(
        &mut self,
        world: &crate::world::World,
        shapes: &crate::structure::geo::Shapes,
        t: &Time,
        mut pending: PendingPops,
        failed: Option<BodyId>,
    ) -> Result<bool, StructureError> {
        if pending.moved.is_empty() {
            return Ok(true);
        }
        if let Some(b) = failed {
            let kss = &self.kss;
            let on_tri = |ti: crate::structure::TriId| {
                kss.tris[ti.0 as usize]
                    .c
                    .iter()
                    .any(|x| x.obj == Obj::Body(b))
            };
            pending.owners.retain(|o| match *o {
                Owner::Tri(ti) => !on_tri(ti),
                Owner::Corr(k) => {
                    let c = &kss.corrs[k.0 as usize];
                    c.a != Obj::Body(b) && c.b != Obj::Body(b) && !on_tri(c.s.0) && !on_tri(c.t.0)
                }
            });
        }
        let geo = Geo { world, shapes };
        // (a corridor without a decomposition is left as it is, for the
        // repair or the rebuild that comes next; the others are finished)
        let mut unfollowed = Vec::new();
        for o in &pending.owners {
            if let Owner::Corr(k) = *o {
                crate::structure::counters::bump(crate::structure::counters::Counter::PopOwners);
                if let Err(_e) = self.kss.normalize(&geo, k, t, None) {
                    trace!("pops at {}: {_e}; rebuilding", t.to_f64());
                    unfollowed.push(*o);
                }
            }
        }
        for o in &unfollowed {
            pending.owners.remove(o);
        }
        self.refresh_moved(&geo, &pending.moved, (pending.named, pending.owners), t)?;
        Ok(unfollowed.is_empty())
    }

    /// Remove body `b` (already dead in `world`; every other body seen as
    /// the structure sees it) at `now` in place ([`crate::structure::Kss::removal_plan`],
    /// [`crate::structure::Kss::apply_removal`]): the slots are renumbered, the new corridors
    /// normalized, and their certificates and the new triangles' scheduled
    /// (those that the triangles and corridors that went also had are taken
    /// over, the others dropped). Returns `false` when the removal cannot
    /// be done locally (the caller rebuilds; the structure may then be half
    /// changed), in particular when a new certificate fails at once that
    /// is neither taken over nor held by normalization.
    pub fn remove_body(
        &mut self,
        world: &Geo,
        b: BodyId,
        now: &Time,
    ) -> Result<bool, StructureError> {
        Ok(self.remove_bodies(world, &[b], now)? == SetRemoval::Removed)
    }

    /// Remove the bodies `set` (already dead in `world`, every other body
    /// seen as the structure sees it) at `now` together, with one region
    /// for all of them ([`crate::structure::Kss::removal_plan_of`]; for
    /// one body, [`Kinetic::remove_body`]): two polygons
    /// that collide in `remove` mode touch, and the corridors between them
    /// that removing one would make the other's removal takes away again
    /// are never made. [`SetRemoval::NoPlan`] when their region has no
    /// plan (the structure is unchanged: remove them one at a time),
    /// [`SetRemoval::Failed`] when the splice failed (the caller rebuilds;
    /// the structure may be half changed).
    pub fn remove_bodies(
        &mut self,
        world: &Geo,
        set: &[BodyId],
        now: &Time,
    ) -> Result<SetRemoval, StructureError> {
        if self.instant.broken.is_some() {
            return Ok(SetRemoval::Failed);
        }
        if world.alive_count() < 2 {
            // nothing stays to separate: the empty structure
            self.replace_with(Kinetic::default());
            self.tally.local_removals += set.len() as u64;
            return Ok(SetRemoval::Removed);
        }
        let plan = match self.kss.removal_plan_of(world, set, now) {
            Ok(plan) => plan,
            Err(_e) => {
                trace!("removal of {set:?} at {} not local: {_e}", now.to_f64());
                return Ok(SetRemoval::NoPlan);
            }
        };
        if !self.splice(world, plan, set[0], set, now)? {
            return Ok(SetRemoval::Failed);
        }
        if set.len() > 1 {
            crate::structure::counters::bump(crate::structure::counters::Counter::SetRemovals);
        }
        self.tally.local_removals += set.len() as u64;
        Ok(SetRemoval::Removed)
    }

    /// Repair the structure for just after `now` by retriangulating the
    /// region around `bodies` together (then, with `singles`, around each
    /// alone; [`crate::structure::Kss::retriangulation_plan`]), the first for which a plan
    /// exists whose new partition triangles hold on all of `(now, at]` for
    /// its instant `at` and whose new corridors decompose just after `now`
    /// without holding a junction against the motion, except between two
    /// polygons outside the set (`handled`, the failing certificate, is
    /// never held); counted as `local_repair`.
    /// The local alternative to [`Kinetic::rebuild_after`] at a settled
    /// contact. Returns `false` when no body gives a repair; the structure
    /// is then unchanged, or half changed if the splice failed (the caller
    /// rebuilds it either way).
    pub fn repair_around(
        &mut self,
        world: &Geo,
        (bodies, singles): (&[BodyId], bool),
        handled: [Att; 3],
        now: &Time,
    ) -> Result<bool, StructureError> {
        if self.instant.broken.is_some() {
            return Ok(false);
        }
        // the certificate being handled is never held against the motion
        // by the new corridors' normalization (its event would repeat)
        self.kss.handling = Some(handled);
        let repaired = self.repair_with(world, (bodies, singles), now);
        self.kss.handling = None;
        repaired
    }

    /// After the approximations of `bodies` were refined where the
    /// structure could not follow in place (failing `triples` at `now`,
    /// popped): triangulate again the region around those bodies only, as
    /// [`Kinetic::repair_around`] (every triangle and corridor that names
    /// one of their vertices is in that region, so no stale vertex stays);
    /// counted as a local repair. `false` when there is none (the caller
    /// rebuilds the whole structure; a half-done splice is replaced then).
    pub fn repair_refined(
        &mut self,
        world: &Geo,
        bodies: &[BodyId],
        triples: &[[Att; 3]],
        now: &Time,
    ) -> bool {
        if bodies.is_empty() || self.instant.broken.is_some() {
            return false;
        }
        // the certificates that failed stay out of the queue until their
        // owners are rescheduled (the repair takes them over or drops them)
        let handled = triples
            .first()
            .map(|&p| crate::structure::certs::rotate_to_min(p));
        self.kss.handling = handled;
        let repaired = self.repair_with(world, (bodies, false), now);
        self.kss.handling = None;
        if !matches!(repaired, Ok(true)) {
            return false;
        }
        // the new region took over certificates it shares with the old one
        // without computing their failure times again, but the refined
        // approximation vertices moved: every certificate on these bodies
        // is scheduled anew
        // (in the order of their points)
        let on_bodies: BTreeMap<[Att; 3], CertId> = bodies
            .iter()
            .filter_map(|b| self.by_body.get(b))
            .flatten()
            .filter_map(|&id| Some((self.certs.at(id)?.cert.p, id)))
            .collect();
        for &id in on_bodies.values() {
            self.reschedule_id(world, id, now, None);
        }
        true
    }

    pub(super) fn repair_with(
        &mut self,
        world: &Geo,
        (bodies, singles): (&[BodyId], bool),
        now: &Time,
    ) -> Result<bool, StructureError> {
        let hi = self.search_start(now)?;
        // all of them together first (the broken faces may lie between any
        // two), then each alone
        let mut sets: Vec<Vec<BodyId>> = vec![bodies.to_vec()];
        if singles && bodies.len() > 1 {
            sets.extend(bodies.iter().map(|&b| vec![b]));
        }
        // a set whose region has a corridor between two other bodies that
        // does not decompose just after `now` (a degeneracy of theirs at
        // the same instant) is tried again with those bodies in it, at most
        // twice from each first set
        let mut grown: Vec<u8> = vec![0; sets.len()];
        let mut i = 0;
        while i < sets.len() {
            let set = sets[i].clone();
            let rounds = grown[i];
            i += 1;
            let b = set[0];
            let mut hi_b = hi.clone();
            for _ in 0..40 {
                let at = now.rational_between(&hi_b);
                let at_t = Time::from_rational(at.clone());
                let plan = match self.kss.retriangulation_plan(world, &set, &at) {
                    Ok(plan) => plan,
                    Err(e) => {
                        trace!(
                            "repair around {set:?} at {}: {e} (grow by {:?})",
                            at_t.to_f64(),
                            e.grow
                        );
                        // (a boundary bridge crossed by the set at once: the
                        // set is tried again with its bodies, as below)
                        grow_sets(&mut sets, &mut grown, (&set, rounds), e.grow);
                        hi_b = at_t;
                        continue;
                    }
                };
                // the new triangles must hold from just after `now` to `at`
                if !plan_holds(world, &plan, now, &at_t) {
                    trace!(
                        "repair around {set:?} at {}: a triangle fails before",
                        at_t.to_f64()
                    );
                    hi_b = at_t;
                    continue;
                }
                // and every new corridor must have a decomposition just
                // after `now` (tried, and undone)
                if let Err(pair) = self.kss.retriangulation_decomposes(world, &plan, &set, now) {
                    trace!(
                        "repair around {set:?} at {}: a corridor {pair:?} does not decompose",
                        at_t.to_f64()
                    );
                    let more: Vec<BodyId> = (pair.iter())
                        .filter_map(|o| match *o {
                            Obj::Body(c) if !set.contains(&c) => Some(c),
                            _ => None,
                        })
                        .collect();
                    grow_sets(&mut sets, &mut grown, (&set, rounds), more);
                    hi_b = at_t;
                    continue;
                }
                if !self.splice(world, plan, b, &[], now)? {
                    return Ok(false);
                }
                self.tally.local_repairs += 1;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Insert body `b` into the structure at `now`: `b` is alive in `world`
    /// (seen through its shapes), touches no other body, and is not in the
    /// structure yet. The region around the body nearest to it (its
    /// partition triangles and corridors) is triangulated again with `b`
    /// in it ([`crate::structure::Kss::insertion_plan`]), for an instant just after `now` at
    /// which the new partition triangles hold from `now` on and the new
    /// corridors decompose; where `b` does not lie in that region (or
    /// crosses its boundary), the set grows by the neighbours of its
    /// bodies, a few rounds at most. Counted as `local_insert`. The cost is
    /// the region's size (and a scan of the bodies for the nearest and of
    /// the structure for neighbours), not a new triangulation of
    /// everything. `false` when no region works: the structure is then
    /// unchanged, or half changed if the splice failed (the caller
    /// rebuilds it either way).
    pub fn insert_body(
        &mut self,
        world: &Geo,
        b: BodyId,
        now: &Time,
    ) -> Result<bool, StructureError> {
        if self.instant.broken.is_some() || self.kss.tris.is_empty() {
            return Ok(false);
        }
        let Some(first) = nearest_body(world, b, now) else {
            return Ok(false);
        };
        let mut set = vec![b, first];
        let hi = self.search_start(now)?;
        for _round in 0..4 {
            let mut hi_b = hi.clone();
            let mut more: Vec<BodyId> = Vec::new();
            for _ in 0..12 {
                let at = now.rational_between(&hi_b);
                let at_t = Time::from_rational(at.clone());
                let plan = match self.kss.insertion_plan(world, &set, &at) {
                    Ok(plan) => plan,
                    Err(e) => {
                        trace!("insertion of {b:?} with {set:?}: {e}");
                        more = e.grow;
                        break;
                    }
                };
                if !plan_holds(world, &plan, now, &at_t) {
                    hi_b = at_t;
                    continue;
                }
                if let Err(pair) = self.kss.retriangulation_decomposes(world, &plan, &set, now) {
                    trace!("insertion of {b:?} with {set:?}: {pair:?} does not decompose");
                    more = pair
                        .iter()
                        .filter_map(|o| match *o {
                            Obj::Body(c) => Some(c),
                            Obj::Omega => None,
                        })
                        .collect();
                    break;
                }
                if !self.splice(world, plan, b, &[], now)? {
                    return Ok(false);
                }
                self.tally.local_insertions += 1;
                return Ok(true);
            }
            more.retain(|c| !set.contains(c));
            if more.is_empty() {
                more = self.kss.neighbours(&set);
            }
            if more.is_empty() {
                return Ok(false);
            }
            set.extend(more);
        }
        Ok(false)
    }

    /// Replace the triangles and corridors that `plan` takes out by its new
    /// ones (for the removal of the bodies `removed`, or, when there are
    /// none, for a retriangulation around body `b`): the slots are renumbered, the new
    /// corridors normalized, and their certificates and the new triangles'
    /// scheduled, taking over those they share with what went. `false` when
    /// the result does not hold just after `now`.
    pub(super) fn splice(
        &mut self,
        world: &Geo,
        plan: crate::structure::remove::RemovalPlan,
        b: BodyId,
        removed: &[BodyId],
        now: &Time,
    ) -> Result<bool, StructureError> {
        // (`b` names the splice in traces)
        let _ = b;
        // the certificates of what goes lose their owners but stay for the
        // moment: the new triangles and corridors take over the ones they
        // share (most of a merged corridor's junctions) without computing
        // their failure times again
        let mut orphans: Vec<CertId> =
            Vec::with_capacity(4 * (plan.dead_tris.len() + plan.dead_corrs.len()));
        let dead = (plan.dead_tris.iter().map(|&t| Owner::Tri(t)))
            .chain(plan.dead_corrs.iter().map(|&k| Owner::Corr(k)));
        for o in dead {
            let mine = self.take_owned(o);
            for id in mine {
                if let Some(s) = self.certs.at_mut(id) {
                    s.owners.retain(|x| *x != o);
                    if s.owners.is_empty() {
                        orphans.push(id);
                    }
                }
            }
        }
        let spliced = self.kss.apply_removal(plan);
        for &(src, dst) in &spliced.moved_tris {
            let mine = self.owned_tri[src.0 as usize].take();
            self.rename(mine.as_slice(), Owner::Tri(src), Owner::Tri(dst));
            self.owned_tri[dst.0 as usize] = mine;
        }
        self.owned_tri.resize(self.kss.tris.len(), None);
        for &(src, dst) in &spliced.moved_corrs {
            let mine = std::mem::take(&mut self.owned_corr[src.0 as usize]);
            self.rename(&mine, Owner::Corr(src), Owner::Corr(dst));
            self.owned_corr[dst.0 as usize] = mine;
        }
        self.owned_corr.resize(self.kss.corrs.len(), Owned::new());
        self.last_touched.clear();
        for &k in &spliced.corrs {
            self.kss.place_middle_bridge(world, k, now);
            if let Err(_e) = self.kss.normalize(world, k, now, None) {
                trace!("removal of {b:?}: {_e}");
                return Ok(false);
            }
        }
        // (an error here leaves the structure half changed: the caller
        // rebuilds it)
        for &tri in &spliced.tris {
            if self.refresh(world, Owner::Tri(tri), now).is_err() {
                return Ok(false);
            }
        }
        for &k in &spliced.corrs {
            if self.refresh(world, Owner::Corr(k), now).is_err() {
                return Ok(false);
            }
        }
        // (certificates taken over as they were: if one fails now, it did
        // before the removal too, and is handled as an event of this instant)
        let mut adopted: BTreeSet<[Att; 3]> = BTreeSet::new();
        for id in orphans {
            match self.certs.at(id) {
                Some(s) if s.owners.is_empty() => self.drop_id(id),
                Some(s) => {
                    adopted.insert(s.cert.p);
                }
                None => {}
            }
        }
        for gone in removed {
            if self.by_body.get(gone).is_some_and(|s| !s.is_empty()) {
                trace!("removal of {gone:?}: certificates on it stay");
                return Ok(false);
            }
            self.by_body.remove(gone);
        }
        // the new structure must hold just after `now`: no new certificate
        // fails at once (only those due now can) but the ones taken over and
        // the junctions that normalization holds against the motion (zero
        // now, failing at this instant as events still to come)
        let held: BTreeSet<[Att; 3]> = spliced
            .corrs
            .iter()
            .filter_map(|k| self.kss.held.get(k))
            .flatten()
            .map(|&p| crate::structure::certs::rotate_to_min(p))
            .collect();
        let fresh = (spliced.tris.iter())
            .flat_map(|t| &self.owned_tri[t.0 as usize])
            .chain((spliced.corrs.iter()).flat_map(|k| &self.owned_corr[k.0 as usize]));
        for &id in fresh {
            let Some(s) = self.certs.at(id) else {
                return Ok(false);
            };
            let p = &s.cert.p;
            if adopted.contains(p) || held.contains(p) {
                continue;
            }
            if self.due_now(p, s.key, now)
                && due_is_failing(
                    world,
                    &s.cert,
                    (
                        s.fp.as_deref(),
                        due_time(&self.queue, s.key, self.certs.popped(id)),
                    ),
                    now,
                )
            {
                trace!(
                    "splice around {b:?}: certificate {:?} fails at once",
                    s.cert
                );
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Give up on the local operations at this instant (they cycle) and
    /// rebuild once the collision response has been applied.
    pub fn give_up_instant(&mut self) {
        self.instant.broken = Some(Broken {
            kind: Rebuild::Degenerate,
            around: None,
        });
    }

    /// The structure is rebuilt (counted as `kind`) once the collision
    /// response at this instant has been applied; for a refinement of the
    /// approximations of `around` alone (and no other event deferred
    /// meanwhile), only the region around those bodies is triangulated
    /// again ([`Kinetic::repair_refined`]) where that works, and the failed
    /// `triples` are scheduled again.
    pub fn rebuild_after_response(
        &mut self,
        kind: Rebuild,
        (around, triples): (&[BodyId], &[[Att; 3]]),
    ) {
        match self.instant.broken.as_mut() {
            None => {
                self.instant.broken = Some(Broken {
                    kind,
                    around: Some((around.to_vec(), triples.to_vec())),
                })
            }
            Some(b) => b.around = None,
        }
    }

    /// The pairs that touched without a collision since the last call (see
    /// the field `settled`).
    pub fn take_settled(&mut self) -> Vec<(BodyId, BodyId)> {
        std::mem::take(&mut self.instant.settled)
    }

    /// Rebuild the structure from scratch for the instants just after `now`:
    /// built at a rational instant `at > now` so close to `now` that every
    /// new certificate holds on all of `(now, at]`, then scheduled from
    /// `now`. The fallback for instants where several degeneracies coincide
    /// and the local operations find no valid structure (counted as
    /// `degenerate_rebuild`; see ARCHITECTURE.md).
    pub fn rebuild_after(
        &mut self,
        world: &Geo,
        now: &Time,
        kind: Rebuild,
    ) -> Result<(), StructureError> {
        let mut hi = self.search_start(now)?;
        trace!("rebuild_after {now}: search from {hi:?}");
        for _ in 0..200 {
            let at = now.rational_between(&hi);
            let at_t = Time::from_rational(at.clone());
            let built = Kinetic::new(world, &at);
            if let Err(_e) = &built {
                trace!("rebuild at {} failed: {_e}", at_t.to_f64());
            }
            if let Ok(mut fresh) = built {
                let holds = fresh.certs.values().all(|s| {
                    let p = cert_poly(world, &s.cert);
                    // (or a partition triangle flat while two corners rest)
                    resting_flat(world, &s.cert, &p)
                        || (p.sign_after(now) == Sign::Positive
                            && p.first_failure_after(now).is_none_or(|f| f > at_t))
                });
                trace!("rebuild at {} holds {holds}", at_t.to_f64());
                #[cfg(feature = "trace")]
                if holds {
                    fresh.kss.trace_dump();
                }
                if holds {
                    let mut keys: Vec<[Att; 3]> = fresh.certs.keys().copied().collect();
                    keys.sort();
                    for p in &keys {
                        fresh.reschedule(world, p, now);
                    }
                    self.replace_with(fresh);
                    self.tally.rebuilt(kind);
                    return Ok(());
                }
            }
            hi = at_t;
        }
        self.unbuildable = Some(now.clone());
        Err(StructureError::Local(format!(
            "no rebuild just after t = {now} found"
        )))
    }

    /// Where the searches for an instant just after `now` (a rebuild, a
    /// local repair) start, halving towards `now`: the old structure's next
    /// failure after `now` gives the scale of the gaps between events, so
    /// the search starts there rather than far away, where polygons have
    /// moved into each other and every attempt fails (each a whole
    /// triangulation); at most one time unit later. (The f64 only bounds the
    /// search from above: any instant after `now` would do.)
    pub(super) fn search_start(&self, now: &Time) -> Result<Time, StructureError> {
        let f = now.to_f64();
        let mut hi = Time::from_f64(f + f.abs().max(1.0))
            .ok_or_else(|| StructureError::Local("time out of range".into()))?;
        if let Some(next) = self.queue_times_after(now) {
            if next < hi {
                hi = next;
            }
        }
        Ok(hi)
    }

    /// The earliest queued failure time strictly after `now` (O(queue)),
    /// where the far queue's failures count by the lower ends of their
    /// enclosures, which are no later: no exact time is made here, where a
    /// refinement may have moved some of their points since they were
    /// scheduled, and a structure left behind by the current time (a
    /// stand-in's) may hold failures before `now`.
    pub(super) fn queue_times_after(&self, now: &Time) -> Option<Time> {
        let after = |t: &Time| t > now;
        // the earliest queued time, unless failures of this very instant
        // are still queued
        let near = match self.queue.peek() {
            Some((_, t, _, _)) if after(t) => Some(t.clone()),
            _ => self
                .queue
                .iter()
                .map(|(_, t, _, _)| t)
                .filter(|t| after(t))
                .min()
                .cloned(),
        };
        let lo = |ft: &super::FarTime| Time::from_f64(ft.0.lo);
        let far = match self.far.peek().and_then(|(_, ft, _, _)| lo(ft)) {
            Some(t) if after(&t) => Some(t),
            _ => self
                .far
                .iter()
                .filter_map(|(_, ft, _, _)| lo(ft))
                .filter(after)
                .min(),
        };
        near.into_iter().chain(far).min()
    }

    /// Coarsen the approximations (in `shapes`) where the last operation
    /// touched the structure: one merge candidate per touched corridor
    /// ([`crate::structure::Kss::coarsen_one`]); the merged corridor is normalized and the
    /// certificates on the moved vertex recomputed. Returns the number of
    /// merges.
    pub fn coarsen(
        &mut self,
        world: &crate::world::World,
        shapes: &mut crate::structure::geo::Shapes,
        t: &Time,
    ) -> Result<u64, StructureError> {
        let mut merges = 0;
        let touched = std::mem::take(&mut self.last_touched);
        for &k in &touched {
            self.tick = self.tick.wrapping_add(1);
            let (by_body, certs, queue) = (&self.by_body, &self.certs, &self.queue);
            let busy = |kv: Att, qv: Att| {
                let Obj::Body(b) = kv.obj else {
                    return true;
                };
                by_body.get(&b).is_some_and(|set| {
                    set.iter().any(|&id| {
                        let Some(s) = certs.at(id) else {
                            return false;
                        };
                        let p = &s.cert.p;
                        p.contains(&kv)
                            || (p.contains(&qv)
                                && s.key.is_none_or(|key| match key {
                                    QKey::Near(key) => {
                                        queue.get(key).is_some_and(|(tq, _)| tq == t)
                                    }
                                    QKey::Far(_) => false,
                                }))
                    })
                })
            };
            let Some(q) = self.kss.coarsen_one(world, shapes, k, t, self.tick, &busy) else {
                continue;
            };
            merges += 1;
            trace!("merge at {} in {k:?}: {q:?} hidden", t.to_f64());
            let geo = Geo {
                world,
                shapes: &*shapes,
            };
            self.kss.normalize(&geo, k, t, None)?;
            let Obj::Body(b) = q.obj else {
                continue;
            };
            let (named, mut owners) = self.owners_naming(b, &[q]);
            owners.insert(Owner::Corr(k));
            self.refresh_moved(&geo, &[(b, vec![q])], (named, owners), t)?;
        }
        // (the list's buffer for the next event, unless the loop made a
        // new list)
        if self.last_touched.is_empty() {
            let mut touched = touched;
            touched.clear();
            self.last_touched = touched;
        }
        self.tally.merges += merges;
        Ok(merges)
    }
}
