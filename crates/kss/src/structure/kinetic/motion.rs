//! Flight-plan changes and collision responses: rescheduling only the
//! certificates of the bodies whose motion changed, with the corridors that
//! must be re-normalized first where the new motions make a certificate fail
//! at once.

use std::collections::BTreeSet;

use crate::motion::orient_poly;
use crate::num::{Interval, Sign, Time};
use crate::structure::certs::CertKind;
use crate::structure::geo::Geo;
use crate::structure::ops::Owner;
use crate::structure::StructureError;
use crate::structure::{Att, CorrId, Obj};
use crate::world::BodyId;

use super::book::{
    bridge_end, cert_enclosure_with, holds_by_motion_bound, holds_until_bridge_end, is_failing,
};
use super::instant::Broken;
use super::tally::Rebuild;
use super::{CertId, FastMap, Kinetic};

impl Kinetic {
    /// Bodies changed their motion at `now`: reschedule every certificate
    /// that involves one of them (flight-plan changes are local), and the
    /// certificates set aside at this instant.
    pub fn motion_changed(
        &mut self,
        world: &Geo,
        now: &Time,
        bodies: &[BodyId],
    ) -> Result<(), StructureError> {
        // (the motions changed: operations before this are no cycle of
        // operations after it)
        self.instant.recent.clear();
        // (nor is an operation after it the first change at this instant)
        self.instant.changed_at = Some(now.clone());
        for &_b in bodies {
            trace!(
                "motion of {_b:?} at {}: {:?}",
                now.to_f64(),
                world.body(_b).traj.velocity().to_f64()
            );
        }
        let waiting = std::mem::take(&mut self.instant.waiting);
        let zero = match std::mem::take(&mut self.instant.zero) {
            Some((at, ps)) if at == *now => ps,
            _ => Vec::new(),
        };
        // (each certificate once: from the list of the first of `bodies`
        // that it names, in the lists' order, then the set-aside contacts
        // that none of those lists holds; no sort)
        let room = bodies
            .iter()
            .filter_map(|b| self.by_body.get(b))
            .map(|set| set.len())
            .sum::<usize>()
            + waiting.len();
        let names = |p: &[Att; 3], among: &[BodyId]| {
            p.iter()
                .any(|a| matches!(a.obj, Obj::Body(x) if among.contains(&x)))
        };
        // (`ids[i]`: the id of `touched[i]`'s certificate, `None` if it has
        // none; nothing below drops one before the last loop)
        let mut touched: Vec<[Att; 3]> = Vec::with_capacity(room);
        let mut ids: Vec<Option<CertId>> = Vec::with_capacity(room);
        for (i, b) in bodies.iter().enumerate() {
            if bodies[..i].contains(b) {
                continue;
            }
            for &id in self.by_body.get(b).into_iter().flatten() {
                let Some(s) = self.certs.at(id) else {
                    continue;
                };
                if !names(&s.cert.p, &bodies[..i]) {
                    touched.push(s.cert.p);
                    ids.push(Some(id));
                }
            }
        }
        for (i, p) in waiting.iter().enumerate() {
            let id = self.certs.id(p);
            // (a stored certificate on one of `bodies` is in its list)
            if (id.is_some() && names(p, bodies)) || waiting[..i].contains(p) {
                continue;
            }
            touched.push(*p);
            ids.push(id);
        }
        // (each point's place at `now` and linear enclosure computed once:
        // the certificates on a body share its vertices, and nothing in
        // the loop below moves a point)
        let tiv = now.interval();
        let (mut places, mut linears, mark) = std::mem::take(&mut self.motion_memo);
        places.clear();
        linears.clear();
        // (a certificate that holds until a bridge of one of its bodies
        // ends is scheduled then, when that body's motion changes again;
        // `turning[i]`: the filter proved `touched[i]` a turn certificate
        // positive from now, so its turn is not zero at now)
        // (`kinds[i]`: the kind of `touched[i]`'s certificate)
        // (`encl[i]`: the enclosure of `touched[i]`'s certificate function,
        // computed once for the bridge check, its failure time and the
        // filters below)
        let mut turning = vec![false; touched.len()];
        let mut kinds: Vec<Option<CertKind>> = Vec::with_capacity(touched.len());
        let mut encl: Vec<Option<[Interval; 3]>> = Vec::with_capacity(touched.len());
        for ((p, &id), turning) in touched.iter().zip(&ids).zip(&mut turning) {
            let Some((id, cert)) = id.and_then(|id| Some((id, self.certs.at(id)?.cert))) else {
                kinds.push(None);
                encl.push(None);
                continue;
            };
            kinds.push(Some(cert.kind));
            // (the end of the bridge the certificate must hold until to be
            // idle: none for a contact of this instant, or off a bridge)
            let end = if waiting.contains(p) {
                None
            } else {
                bridge_end(world, &cert.p)
            };
            // (a turn certificate that its points' places now and their
            // speeds prove positive until then: idle, no enclosure needed;
            // nothing below reads one for it, its turn is not zero now)
            let place = |a: Att| *places.entry(a).or_insert_with(|| world.mid_rad(a, tiv));
            if let Some(_end) =
                end.filter(|end| holds_by_motion_bound(world, &cert, now, end, place))
            {
                #[cfg(debug_assertions)]
                {
                    let f = super::book::cert_poly(world, &cert);
                    debug_assert!(
                        f.sign_at(now) == Sign::Positive
                            && f.clone().failure_after_positive(now).is_none_or(|x| x > *_end),
                        "a certificate proved to hold until the bridge's end fails before: {cert:?}"
                    );
                }
                encl.push(None);
                self.idle_until_bridge_end(id);
                *turning = true;
                continue;
            }
            let e = cert_enclosure_with(&cert, |a| {
                *linears.entry(a).or_insert_with(|| world.linear_mr(a))
            });
            encl.push(e);
            if end.is_some_and(|end| holds_until_bridge_end(now, end, e)) {
                self.idle_until_bridge_end(id);
                *turning = cert.kind != CertKind::Order;
                continue;
            }
            if cert.kind != CertKind::Order {
                zero_turn_after(world, &cert, &zero, now, e);
            }
            self.reschedule_id(world, id, now, Some(e));
        }
        self.motion_memo = (places, linears, mark);
        // A corridor with a junction straight at `now` was shaped by its
        // turns just after `now` under the old motions (an operation of this
        // instant may have decomposed it again, even while its own failure
        // waited for this response). Under the new motions that shape may be
        // wrong, and the certificates, which keep the signs the structure
        // read, would not notice: such a corridor is normalized again.
        // (whether the f64 filter leaves each one's turn at `now` undecided:
        // asked once here for both uses below)
        // (only for the certificates that still exist: the points of one
        // dropped meanwhile may no longer be vertices)
        // (for a turn certificate, its function's enclosure at `now`: a
        // positive multiple of the turn or of its negation)
        let undecided: Vec<bool> = touched
            .iter()
            .zip(&turning)
            .zip(kinds.iter().zip(&encl))
            .map(|((p, &turning), (kind, e))| match (kind, e) {
                _ if turning => false,
                (None, _) => false,
                // (a value that is exactly zero is no proof of a sign)
                (Some(k), Some([c0, c1, c2])) if *k != CertKind::Order => !matches!(
                    (*c0 + tiv * (*c1 + tiv * *c2)).sign(),
                    Some(Sign::Positive | Sign::Negative)
                ),
                _ => world.orient_filtered(p[0], p[1], p[2], tiv).is_none(),
            })
            .collect();
        // (neither is read when the structure is about to be rebuilt: it
        // may not be whole then, a corridor's chain lengths behind its ends)
        let whole = self.instant.broken.is_none();
        let reshape = if whole {
            self.straight_now(world, &touched, &undecided, now)
        } else {
            BTreeSet::new()
        };
        // A bridge (an end or the middle one) between two vertices that rest on each other has
        // length zero, its corner the two ends' together; under the new
        // motions they may part, and the corridor's certificates are then
        // its two junctions again.
        let resting = if whole {
            // (the bodies whose points may part: those whose motion
            // changed, and those of the contacts set aside for the response)
            let mut moved: smallvec::SmallVec<[BodyId; 8]> = bodies.iter().copied().collect();
            moved.extend(waiting.iter().flatten().filter_map(|a| match a.obj {
                Obj::Body(b) => Some(b),
                Obj::Omega => None,
            }));
            moved.sort_unstable();
            moved.dedup();
            let mut mark = std::mem::take(&mut self.motion_memo.2);
            let resting = self.resting_now(world, &ids, &moved, now, &mut mark);
            self.motion_memo.2 = mark;
            resting
        } else {
            BTreeSet::new()
        };
        #[cfg(feature = "trace")]
        if std::env::var_os("KSS_DUMP").is_some() {
            eprintln!("resting at {}: {resting:?}", now.to_f64());
            self.kss.trace_dump();
        }
        for (((p, undecided), kind), e) in touched.into_iter().zip(undecided).zip(kinds).zip(encl) {
            // (a turn certificate whose turn the filter decided at `now`
            // is not zero then: nothing below concerns it, and no
            // certificate an owner's refresh puts on its points meanwhile
            // is an order one, which needs a zero turn)
            if !undecided && kind.is_some_and(|k| k != CertKind::Order) {
                continue;
            }
            let Some(s) = self.certs.get(&p) else {
                continue;
            };
            // the turn is zero just after now only if it is zero for ever
            // (the three points slide along one line); the filter rules
            // that out wherever it decides a sign
            let lp = |a: Att| world.point(a);
            // (and so does a coefficient of the certificate's function
            // that its enclosure shows is not zero, for a turn certificate
            // then and now: its function is a multiple of the turn)
            let nonzero = s.cert.kind != CertKind::Order
                && kind.is_some_and(|k| k != CertKind::Order)
                && e.is_some_and(|e| e.iter().any(|c| c.sign().is_some_and(|s| s != Sign::Zero)));
            let zero =
                undecided && !nonzero && orient_poly(&lp(p[0]), &lp(p[1]), &lp(p[2])).is_zero();
            if s.cert.kind == CertKind::Order {
                let owners: Vec<Owner> = s.owners.to_vec();
                // an order certificate whose three points leave their common
                // line is a turn again (unless it fails now: two of its points
                // meet, an event of this instant that recomputes its owners'
                // certificates). The straight junction or cusp it certified
                // may now have the wrong class for its face: the corridor is
                // normalized, and if no decomposition holds just after `now`
                // the junction keeps its old class and fails at once.
                // On the hull, where two of its points meet and the new
                // motions take them off their line, the turns decide: read
                // by the order, the meeting could drop the wrong one of the
                // two points from the hull.
                let on_hull = owners.iter().all(
                    |o| matches!(*o, Owner::Corr(k) if self.kss.corrs[k.0 as usize].b == Obj::Omega),
                );
                if zero
                    || (!on_hull && self.due_now(&p, s.key, now) && is_failing(world, &s.cert, now))
                {
                    continue;
                }
                trace!("order certificate {p:?} becomes a turn at {}", now.to_f64());
                for o in owners {
                    if let Owner::Corr(k) = o {
                        let mid = self.kss.corrs[k.0 as usize].mid;
                        if !self.kss.faces_valid(world, k, mid, now) {
                            self.kss.normalize(world, k, now, None)?;
                        }
                        self.refresh(world, o, now)?;
                    }
                }
            } else if zero && waiting.contains(&p) {
                // a contact that the response turned into sliding (its turn
                // is now zero for ever) is no longer a failure: its owners get
                // their certificates anew (an order certificate for that
                // triple)
                let owners: Vec<Owner> = s.owners.to_vec();
                self.instant.handling = Some(p);
                for o in owners {
                    if matches!(o, Owner::Corr(_)) {
                        self.refresh(world, o, now)?;
                    }
                }
                self.instant.handling = None;
            }
        }
        // (not when the structure is about to be rebuilt anyway)
        let (reshape, resting) = if self.instant.broken.is_some() {
            (BTreeSet::new(), BTreeSet::new())
        } else {
            (reshape, resting)
        };
        for &k in &resting {
            let mid = self.kss.corrs[k.0 as usize].mid;
            let due = self.owned_corr[k.0 as usize].iter().any(|&id| {
                self.certs
                    .at(id)
                    .is_some_and(|s| self.due_now(&s.cert.p, s.key, now))
            });
            if due {
                continue;
            }
            // (its certificates are the corner's, not the two junctions'
            // that must now hold: without a decomposition the region around
            // its two bodies is repaired, or the structure rebuilt, below)
            if !self.kss.faces_valid(world, k, mid, now)
                && self.kss.normalize(world, k, now, None).is_err()
            {
                let c = &self.kss.corrs[k.0 as usize];
                let bodies: Vec<BodyId> = [c.a, c.b]
                    .into_iter()
                    .filter_map(|o| match o {
                        Obj::Body(b) => Some(b),
                        Obj::Omega => None,
                    })
                    .collect();
                let first = (self.owned_corr[k.0 as usize].first())
                    .and_then(|&id| Some(self.certs.at(id)?.cert.p));
                self.instant.broken = Some(Broken {
                    kind: Rebuild::Degenerate,
                    around: first.map(|p| (bodies, vec![p])),
                });
                break;
            }
            self.refresh(world, Owner::Corr(k), now)?;
        }
        for k in reshape {
            if self.instant.broken.is_some() {
                break;
            }
            let mid = self.kss.corrs[k.0 as usize].mid;
            // (a corridor with a failure still due at this instant is left to
            // that event's operation)
            let due = self.owned_corr[k.0 as usize].iter().any(|&id| {
                self.certs
                    .at(id)
                    .is_some_and(|s| self.due_now(&s.cert.p, s.key, now))
            });
            if due || self.kss.faces_valid(world, k, mid, now) {
                continue;
            }
            trace!(
                "corridor {k:?} reshaped after the motion change at {}",
                now.to_f64()
            );
            // (where no decomposition holds, failures of this instant are
            // still to come and the corridor stays as it was, its held
            // junctions included: `normalize` restores only the bridge)
            let held = self.kss.held.get(&k).cloned();
            if self.kss.normalize(world, k, now, None).is_ok() {
                self.refresh(world, Owner::Corr(k), now)?;
            } else if let Some(h) = held {
                self.kss.held.insert(k, h);
            }
        }
        if let Some(Broken { kind, around }) = self.instant.broken.take() {
            let (around, triples) = around.unwrap_or_default();
            if kind == Rebuild::Refine && self.repair_refined(world, &around, &triples, now) {
                for p in &triples {
                    self.reschedule_idle(world, p, now);
                }
            } else if kind == Rebuild::Degenerate
                && !around.is_empty()
                && self.unbuildable.as_ref() != Some(now)
                && self.repair_around(world, (&around, false), triples[0], now)?
            {
                // (the local operations failed on `triples[0]` before the
                // response, the others were deferred after it; the region
                // around its bodies is whole again, and every one of them
                // that still exists is scheduled again)
                for p in &triples {
                    self.reschedule_unqueued(world, p, now);
                }
            } else {
                self.rebuild_after(world, now, kind)?;
            }
        }
        Ok(())
    }

    /// The corridors between two bodies that own one of the turn
    /// certificates `ps` whose turn is zero at `now` (but not for ever);
    /// `undecided[i]`: whether the f64 filter leaves the turn of `ps[i]` at
    /// `now` undecided (where it decides, the turn is not zero).
    pub(super) fn straight_now(
        &self,
        world: &Geo,
        ps: &[[Att; 3]],
        undecided: &[bool],
        now: &Time,
    ) -> BTreeSet<CorrId> {
        let mut out = BTreeSet::new();
        for (p, &undecided) in ps.iter().zip(undecided) {
            if !undecided {
                continue;
            }
            let Some(s) = self.certs.get(p) else {
                continue;
            };
            if s.cert.kind == CertKind::Order {
                continue;
            }
            // (the instant's memo knows the exact turn at `now` of a
            // certificate whose failure time was computed exactly at this
            // motion change, and often its sign just after `now`, which,
            // not zero, shows that the turn is not zero for ever)
            let at = world.memo_peek_at(*p, now);
            let straight = match at {
                Some(Sign::Zero)
                    if world
                        .memo_peek(*p, now, true)
                        .is_some_and(|s| s != Sign::Zero) =>
                {
                    true
                }
                Some(Sign::Zero) | None => {
                    let lp = |a: Att| world.point(a);
                    let turn = orient_poly(&lp(p[0]), &lp(p[1]), &lp(p[2]));
                    !turn.is_zero() && turn.sign_at(now) == Sign::Zero
                }
                Some(_) => false,
            };
            #[cfg(debug_assertions)]
            {
                let lp = |a: Att| world.point(a);
                let turn = orient_poly(&lp(p[0]), &lp(p[1]), &lp(p[2]));
                debug_assert_eq!(
                    straight,
                    !turn.is_zero() && turn.sign_at(now) == Sign::Zero,
                    "the memo's turn of {p:?} at {now:?}"
                );
            }
            if !straight {
                continue;
            }
            for o in s.owners.iter() {
                if let Owner::Corr(k) = *o {
                    if self.kss.corrs[k.0 as usize].b != Obj::Omega {
                        out.insert(k);
                    }
                }
            }
        }
        out
    }

    /// The corridors among the owners of certificates `ids` (and the
    /// corridors at their ends) in which two
    /// points of two bodies are at one place at `now`: the two ends of a
    /// bridge (an end or the middle one), two points of a junction (a chain
    /// vertex resting on a bridge's end), or two points of a hull turn.
    /// While they rest, a turn through both is zero and has no certificate;
    /// a motion change that parts them must give the corridor its
    /// certificates anew. Only a corridor on one of the bodies `moved`
    /// (sorted), or on the hull, can have points that part: the points of a
    /// corridor between two bodies are theirs, and two bodies whose motions
    /// stay keep their points where they were. `mark` is the buffer of a
    /// bitmap of the corridors (its contents are replaced).
    pub(super) fn resting_now(
        &self,
        world: &Geo,
        ids: &[Option<CertId>],
        moved: &[BodyId],
        now: &Time,
        mark: &mut Vec<u64>,
    ) -> BTreeSet<CorrId> {
        // (two points of two bodies whose boxes are apart at `now` do not
        // meet: the boxes first, each computed once)
        let ti = now.interval();
        let boxes: std::cell::RefCell<FastMap<BodyId, Option<[Interval; 2]>>> = Default::default();
        let seen = |b: BodyId| {
            *boxes
                .borrow_mut()
                .entry(b)
                .or_insert_with(|| world.loose_box(b, ti))
        };
        let apart = |x: Obj, y: Obj| match (x, y) {
            (Obj::Body(p), Obj::Body(q)) if p != q => match (seen(p), seen(q)) {
                (Some(e), Some(f)) => !e[0].overlaps(&f[0]) || !e[1].overlaps(&f[1]),
                _ => false,
            },
            _ => false,
        };
        let meet = |x: Att, y: Att| {
            !apart(x.obj, y.obj) && crate::structure::faces::coincide_at(world, x, y, now)
        };
        // (each corridor once: marked in `mark`, a bitmap of the corridors,
        // rather than sorted; the order of the candidates changes nothing
        // below, whose result is a set)
        mark.clear();
        mark.resize(self.kss.corrs.len().div_ceil(64), 0);
        let mut first = |k: CorrId| {
            let (w, bit) = ((k.0 / 64) as usize, 1u64 << (k.0 % 64));
            let new = mark[w] & bit == 0;
            mark[w] |= bit;
            new
        };
        let parts = |o: Obj| match o {
            Obj::Body(b) => moved.binary_search(&b).is_ok(),
            Obj::Omega => true,
        };
        let on_moved = |k: CorrId| {
            let c = &self.kss.corrs[k.0 as usize];
            parts(c.a) || parts(c.b)
        };
        // the owners, and the corridors at their ends (a turn through two
        // resting points has no certificate that would name them, and an
        // empty corridor has none at all), those on a moved body or the
        // hull alone; sized for two owners a certificate
        let mut owners: Vec<CorrId> = Vec::with_capacity(2 * ids.len());
        for s in ids.iter().filter_map(|&id| self.certs.at(id?)) {
            for o in s.owners.iter() {
                if let Owner::Corr(k) = *o {
                    if first(k) {
                        owners.push(k);
                    }
                }
            }
        }
        let mut cands: Vec<CorrId> = Vec::with_capacity(2 * owners.len());
        for &k in &owners {
            let c = &self.kss.corrs[k.0 as usize];
            for tri in [c.s.0, c.t.0] {
                for n in self.kss.tris[tri.0 as usize].corr {
                    if first(n) && on_moved(n) {
                        cands.push(n);
                    }
                }
            }
        }
        cands.extend(owners.into_iter().filter(|&k| on_moved(k)));
        // (two bodies none of whose vertices can be at one place at `now`,
        // as their vertices' f64 positions prove, each pair asked once: a
        // corridor between them has only their vertices, and none rests)
        let mut vertex_apart: Vec<((BodyId, BodyId), bool)> = Vec::with_capacity(cands.len());
        let mut placed = Vec::with_capacity(2 * cands.len());
        let mut out = BTreeSet::new();
        for k in cands {
            let c = &self.kss.corrs[k.0 as usize];
            if apart(c.a, c.b) {
                continue;
            }
            if let (Obj::Body(p), Obj::Body(q)) = (c.a, c.b) {
                let key = (p.min(q), p.max(q));
                let known = vertex_apart.iter().find(|(x, _)| *x == key).map(|e| e.1);
                let proved = known.unwrap_or_else(|| {
                    let v = vertices_apart(world, p, q, ti, &mut placed);
                    vertex_apart.push((key, v));
                    v
                });
                if proved {
                    debug_assert!(
                        self.kss
                            .junctions(world, k)
                            .iter()
                            .flat_map(|j| [j.prev, j.v, j.next])
                            .chain({
                                let (a_s, b_s, a_t, b_t) = self.kss.ends(k);
                                [a_s, b_s, a_t, b_t]
                            })
                            .all(|x| x.obj == c.a || x.obj == c.b),
                        "a corridor between two bodies names a third"
                    );
                    continue;
                }
            }
            let rests = if c.b == Obj::Omega {
                self.kss
                    .hull_turns(world, k)
                    .iter()
                    .any(|&([x, y, z], _)| meet(x, y) || meet(y, z) || meet(x, z))
            } else {
                // (the points of a corridor between two bodies are theirs,
                // and their boxes overlap: each pair across the two asked
                // once, without the boxes)
                let (a_s, b_s, a_t, b_t) = self.kss.ends(k);
                let mut triples: arrayvec::ArrayVec<[Att; 3], 11> = arrayvec::ArrayVec::new();
                triples.push([a_s, b_s, b_s]);
                triples.push([a_t, b_t, b_t]);
                if let Some((i, j)) = c.mid {
                    let (x, y) = (world.cw(a_s, i), world.cw(b_t, j));
                    triples.push([x, y, y]);
                }
                triples.extend(
                    self.kss
                        .junctions(world, k)
                        .into_iter()
                        .map(|j| [j.prev, j.v, j.next]),
                );
                let mut pairs: arrayvec::ArrayVec<(Att, Att), 33> = arrayvec::ArrayVec::new();
                for &[x, y, z] in &triples {
                    for (u, v) in [(x, y), (y, z), (x, z)] {
                        let pair = (u.min(v), u.max(v));
                        if u.obj != v.obj && !pairs.contains(&pair) {
                            pairs.push(pair);
                        }
                    }
                }
                #[cfg(feature = "trace")]
                if std::env::var_os("KSS_DUMP").is_some() {
                    eprintln!("resting_now candidate {k:?}: {triples:?}");
                }
                pairs
                    .iter()
                    .any(|&(u, v)| crate::structure::faces::coincide_at(world, u, v, now))
            };
            #[cfg(feature = "trace")]
            if std::env::var_os("KSS_DUMP").is_some() {
                eprintln!("resting_now candidate {k:?} -> {rests}");
            }
            if rests {
                out.insert(k);
            }
        }
        out
    }
}

/// For a turn certificate `c` that [`InstantState::zero`] (`zero`) knows
/// to be exactly zero at `now` (its points the same: their bodies'
/// approximations unchanged): its sign just after `now` under the new
/// motions is the sign of its function's derivative there, which `e` (the
/// certificate's [`cert_enclosure`] for those motions) decides unless
/// the derivative may be zero. Where it does, the instant's memo of exact
/// turns learns the turn's sign at `now` (zero) and just after it, which
/// [`super::book::failure_time`] and [`Kinetic::straight_now`] read
/// instead of evaluating the turn exactly.
///
/// [`InstantState::zero`]: super::instant::InstantState::zero
fn zero_turn_after(
    world: &Geo,
    c: &crate::structure::certs::Cert,
    zero: &[super::instant::KnownZero],
    now: &Time,
    e: Option<[Interval; 3]>,
) {
    let Some([_, c1, c2]) = e else {
        return;
    };
    let known = zero
        .iter()
        .any(|(p, versions)| *p == c.p && *versions == c.p.map(|a| world.obj_view_words(a.obj)[0]));
    if !known {
        return;
    }
    let t = now.interval();
    let after = match (c1 + (c2 + c2) * t).sign() {
        Some(s @ (Sign::Positive | Sign::Negative)) => s,
        _ => return,
    };
    // (the certificate's function is the turn, or its negation)
    let turn = |s: Sign| if c.sign == Sign::Negative { s.neg() } else { s };
    #[cfg(debug_assertions)]
    {
        let [_, at, exact] = super::book::cert_poly(world, c).signs_at_and_around(now);
        debug_assert_eq!(
            (at, exact),
            (Sign::Zero, after),
            "a contact certificate known zero at the instant: {c:?}"
        );
    }
    world.memo_record(c.p, now, true, turn(after));
    world.memo_record_at(c.p, now, Sign::Zero);
}

/// Whether the f64 positions of the vertices of bodies `p` and `q` at a
/// time in `t` prove that no vertex of `p` is at one place with a vertex of
/// `q` then: every pair is apart by more than their radii
/// ([`crate::geom::MidRad::apart`]). Asked only of two bodies seen as
/// their real polygons (whose positions cost a few products each); `false`
/// for any other pair, or where a position is not finite.
/// `placed` keeps each body's vertex positions for the next pair (the
/// bodies whose motion changed are in most pairs).
fn vertices_apart(
    world: &Geo,
    p: BodyId,
    q: BodyId,
    t: Interval,
    placed: &mut Vec<(BodyId, Option<Vec<crate::geom::MidRad>>)>,
) -> bool {
    use crate::geom::MidRad;
    let mut place = |b: BodyId| -> usize {
        if let Some(i) = placed.iter().position(|(x, _)| *x == b) {
            return i;
        }
        let m = if world.shapes.approx(b).is_some() {
            None
        } else {
            // (sized at once: collecting into an `Option` would grow it)
            let n = world.body(b).shape.len() as u32;
            let mut v = Vec::with_capacity(n as usize);
            (0..n)
                .all(|k| {
                    world
                        .mid_rad(Att::vertex(b, k), t)
                        .map(|m| v.push(m))
                        .is_some()
                })
                .then_some(v)
        };
        placed.push((b, m));
        placed.len() - 1
    };
    let (ip, iq) = (place(p), place(q));
    let (Some(mp), Some(mq)) = (&placed[ip].1, &placed[iq].1) else {
        return false;
    };
    // (only the vertices of `p` near `q`'s box are compared one by one)
    let bound = |v: &[MidRad]| {
        v.iter().fold(
            [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ],
            |b, m| {
                [
                    b[0].min(m.x - m.r),
                    b[1].max(m.x + m.r),
                    b[2].min(m.y - m.r),
                    b[3].max(m.y + m.r),
                ]
            },
        )
    };
    // (a square around that box: every rounding above, of the box's ends,
    // its centre and its half-width, is within `ε` of the largest
    // coordinate `m`, and `4εm` covers them)
    let [x0, x1, y0, y1] = bound(mq);
    let m = x0.abs().max(x1.abs()).max(y0.abs()).max(y1.abs());
    let eps = f64::EPSILON;
    let box_q = MidRad {
        x: 0.5 * x0 + 0.5 * x1,
        y: 0.5 * y0 + 0.5 * y1,
        r: (0.5 * x1 - 0.5 * x0).max(0.5 * y1 - 0.5 * y0) * (1.0 + 4.0 * eps)
            + 4.0 * eps * m
            + f64::MIN_POSITIVE,
    };
    mp.iter()
        .filter(|u| !box_q.r.is_finite() || !u.apart(box_q))
        .all(|u| mq.iter().all(|w| u.apart(*w)))
}
