//! One step of the engine: pop the next failure, classify it (a contact, a
//! failure next to a contact, an approximation touching where the polygons
//! do not, or a structural event), and handle it by a local operation; the
//! guard against local operations that cycle at one instant.

use std::collections::BTreeSet;

use crate::num::{Interval, Time};
use crate::structure::certs::CertKind;
use crate::structure::events::{classify, nearby_contact, settled_between, Failure};
use crate::structure::geo::Geo;
use crate::structure::ops::{Outcome, Owner};
use crate::structure::StructureError;
use crate::structure::{Att, CorrId, Kss, Obj, TriId};
use crate::world::BodyId;

use super::book::due_is_failing;
use super::instant::Broken;
use super::tally::Rebuild;
use super::{due_time, Kinetic, QKey, Step};

/// How many handled certificates [`Kinetic::repair_cycle`] looks back at.
pub(super) const RECENT: usize = 8;

/// The distinct bodies of a triple.
pub(super) fn bodies_of(p: &[Att; 3]) -> Vec<BodyId> {
    let mut v: Vec<BodyId> = p
        .iter()
        .filter_map(|a| match a.obj {
            Obj::Body(b) => Some(b),
            Obj::Omega => None,
        })
        .collect();
    v.sort();
    v.dedup();
    v
}

/// The distinct bodies of the points `p`, in increasing order, without
/// allocating ([`bodies_of`] as an iterator).
pub(super) fn each_body(p: &[Att; 3]) -> impl Iterator<Item = BodyId> {
    let mut v = p.map(|a| match a.obj {
        Obj::Body(b) => Some(b),
        Obj::Omega => None,
    });
    v.sort();
    let mut last = None;
    v.into_iter().flatten().filter(move |&b| {
        let new = last != Some(b);
        last = Some(b);
        new
    })
}

/// Note a contact's features as the failing certificate on `p` shows
/// them, a vertex of one body against a polygon edge of the other, for
/// the world's contact at `t` ([`crate::world::World::hint_contact`],
/// which checks them exactly): a real vertex against an edge between two
/// real vertices, or against an approximation edge, whose line is a real
/// edge's ([`Geo::edge_line`]: the real edge is the hint; a vertex that an
/// approximation touches elsewhere on the line is not a contact, and the
/// world's exact tests refuse the hint then).
fn hint_contact(world: &Geo, p: &[Att; 3], t: &Time) {
    let real = |a: Att| match world.point_id(a)? {
        (_, (u32::MAX, v)) => Some(v as usize),
        _ => None,
    };
    for i in 0..3 {
        let (x, y, z) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        let (Obj::Body(bz), Obj::Body(bx)) = (z.obj, x.obj) else {
            continue;
        };
        if bz == bx || y.obj != x.obj {
            continue;
        }
        let (Some(vz), Some(vx), Some(vy)) = (real(z), real(x), real(y)) else {
            continue;
        };
        let n = world.world.body(bx).shape.len();
        let j = if (vx + 1) % n == vy {
            vx
        } else if (vy + 1) % n == vx {
            vy
        } else {
            continue;
        };
        // (the instant computed only for a contact of real features)
        if let Some(r) = t.as_rational() {
            world.world.hint_contact(r, (bz, vz), (bx, j));
        }
        return;
    }
    let Some(line) = world.edge_line(*p) else {
        return;
    };
    let (Obj::Body(bz), Some(vz)) = (line.x.obj, real(line.x)) else {
        return;
    };
    let n = world.world.body(line.body).shape.len();
    let j = if (line.from + 1) % n == line.to {
        line.from
    } else {
        line.to
    };
    if let Some(r) = t.as_rational() {
        world.world.hint_contact(r, (bz, vz), (line.body, j));
    }
}

/// Whether bodies `x` and `y` are certainly apart at `t` by their
/// polygons' bounding disks ([`crate::geom::BodyPolygon::bounding_disk`]):
/// the distance of the placed centres, enclosed at `t`, exceeds the two
/// radii. One pass over both polygons' vertices in doubles (where the
/// exact test walks their Minkowski difference in integers); it decides
/// two round polygons whose boxes meet at a corner.
fn disks_apart(world: &Geo, (x, y): (BodyId, BodyId), t: &Time) -> bool {
    let centre = |b: BodyId| {
        let body = world.world.body(b);
        let ([cx, cy], r) = body.shape.bounding_disk();
        let p = Interval::point;
        let [px, py] = body.frame.enclose(p(0.0), p(0.0), t.interval());
        (px + p(cx), py + p(cy), r)
    };
    let ((ax, ay, ra), (bx, by, rb)) = (centre(x), centre(y));
    let d = ((ax - bx).square() + (ay - by).square()).sqrt();
    d.lo > (Interval::point(ra) + Interval::point(rb)).hi
}

/// The pairs in contact at `t` for a contact failure of triple `p` between
/// `a` and `b`: that pair, and any other pair among the triple's bodies and
/// the bodies at the corners of the partition triangles that end the
/// certificate's corridors, that touches at `t` too (three polygons meeting
/// at one point need not have a certificate that involves two of them).
pub(super) fn contact_pairs(
    world: &Geo,
    kss: &Kss,
    owners: &[Owner],
    p: &[Att; 3],
    t: &Time,
    (a, b, third): (BodyId, BodyId, Option<BodyId>),
    apart: Option<(BodyId, BodyId)>,
) -> Vec<(BodyId, BodyId)> {
    let mut v = vec![(a, b)];
    if let Some(c) = third {
        v.push((a, c));
        v.push((b, c));
    }
    // approximations touching where the polygons certainly do not: a
    // refinement, not a contact to look around
    if third.is_none() && apart.is_some() {
        return v;
    }
    let Some(r) = t.as_rational() else {
        return v;
    };
    let mut near: BTreeSet<BodyId> = BTreeSet::new();
    let mut add = |x: Att| {
        if let Obj::Body(b) = x.obj {
            near.insert(b);
        }
    };
    p.iter().for_each(|&x| add(x));
    for o in owners {
        let tris: Vec<TriId> = match *o {
            Owner::Tri(tri) => vec![tri],
            Owner::Corr(k) => {
                let c = &kss.corrs[k.0 as usize];
                vec![c.s.0, c.t.0]
            }
        };
        for tri in tris {
            kss.tris[tri.0 as usize].c.iter().for_each(|&x| add(x));
        }
    }
    let near: Vec<BodyId> = near.into_iter().collect();
    for i in 0..near.len() {
        for j in i + 1..near.len() {
            let (x, y) = (near[i], near[j]);
            if v.iter().any(|&(c, d)| (c.min(d), c.max(d)) == (x, y)) {
                continue;
            }
            let (bx, by) = (world.body(x), world.body(y));
            // bounding boxes first (rigorous enclosures of the placed boxes
            // at `t`), the exact test only where they meet
            let boxed = |body: &crate::world::Body| {
                let [x0, x1, y0, y1] = body.shape.bounds();
                let o = Interval::point(0.0);
                let [px, py] = body.frame.enclose(o, o, t.interval());
                let p = Interval::point;
                [
                    (px + p(x0)).lo,
                    (px + p(x1)).hi,
                    (py + p(y0)).lo,
                    (py + p(y1)).hi,
                ]
            };
            let (ex, ey) = (boxed(bx), boxed(by));
            let boxes_meet = !(ex[1] < ey[0] || ey[1] < ex[0] || ex[3] < ey[2] || ey[3] < ex[2]);
            if bx.alive
                && by.alive
                && boxes_meet
                && !disks_apart(world, (x, y), t)
                && crate::geom::placed_polygons_intersect(
                    &bx.shape,
                    &bx.traj.position_at(r),
                    &by.shape,
                    &by.traj.position_at(r),
                )
            {
                v.push((x, y));
            }
        }
    }
    v
}

/// Whether the turn of `c`'s points is known to be zero at `t`: `c` is a
/// turn certificate whose failure time `due` is `t` and a root of its
/// function, computed for the points it still has (`fp`, as
/// [`super::book::due_is_failing`] reads it).
fn root_at(
    world: &Geo,
    c: &crate::structure::certs::Cert,
    fp: Option<&(super::Fingerprint, bool)>,
    due: Option<&Time>,
    t: &Time,
) -> bool {
    c.kind != crate::structure::certs::CertKind::Order
        && matches!((super::book::schedule_fp(fp, due), due), (Some((f, true)), Some(at))
            if at.is_known_same(t) && Some(f) == super::fingerprint(world, &c.p))
}

impl Kinetic {
    /// Whether a failure that could be a contact is still queued at `t`
    /// (such failures are popped first at an instant).
    pub fn contact_candidate_due(&self, t: &Time) -> bool {
        self.queue
            .peek()
            .is_some_and(|(_, tq, tie, _)| tq == t && tie == 0)
    }

    /// Pop and handle the earliest failure if it is at most `limit`.
    ///
    /// At one instant, every failure that could be a contact (a vertex
    /// against another body's polygon edge) is classified before any
    /// structural operation: the contacts are reported, and failures that
    /// involve a body in contact at this instant are set aside until the
    /// collision response has changed the motions (`contacts` lists the pairs
    /// found so far at this instant). `collides(a, b, t)` says whether a
    /// touch of the pair at `t` is a collision (the driver's rule: a contact
    /// that begins at `t`, or one that still interpenetrates after its
    /// collision response); a touch that is not one (two bodies that slide
    /// along each other reach the end of an edge, or a pair that the
    /// response already separates) is a structural event.
    pub fn step(
        &mut self,
        world: &Geo,
        limit: &Time,
        contacts: &[(BodyId, BodyId)],
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Result<Step, StructureError> {
        // (the far queue's certificates that could fail first are moved
        // into the queue of exact times: its head is then the next failure)
        self.admit(world);
        let head = self
            .queue
            .peek()
            .map(|(key, t, tie, &p)| (key, t.clone(), tie, p));
        let use_later = match (&self.instant.later, &head) {
            (None, _) => false,
            (Some(_), None) => true,
            (Some((lt, _)), Some((_, t, tie, _))) => t > lt || *tie > 0,
        };
        if use_later {
            let (t, ps) = self.instant.later.as_mut().expect("checked");
            let t = t.clone();
            let p = ps.pop().expect("non-empty");
            if ps.is_empty() {
                self.instant.later = None;
            }
            return self.handle_or_rebuild(world, p, t, contacts, collides);
        }
        let Some((key, t, tie, id)) = head else {
            return Ok(Step::Idle);
        };
        if &t > limit {
            return Ok(Step::Idle);
        }
        self.queue.pop();
        let s = self.certs.at_mut(id).ok_or_else(|| {
            StructureError::Invariant(format!("queued certificate {id:?} unknown"))
        })?;
        let p = s.cert.p;
        if s.key != Some(QKey::Near(key)) {
            return Err(StructureError::Local(format!(
                "certificate {p:?} scheduled twice"
            )));
        }
        s.key = None;
        self.certs.set_popped(id, t.clone());
        let s = self.certs.at(id).expect("stored");
        trace!(
            "pop t={} tie {tie} {:?} {:?}",
            t.to_f64(),
            s.cert.p,
            s.owners
        );
        // (a failure root of a turn on an approximation edge's line: the
        // turn has its sign just before the instant and the opposite just
        // after it; the instant's memo of turns learns both for the real
        // edge of that line, where a pop at this instant puts new points)
        if let Some(line) = world.edge_line(p) {
            if root_at(world, &s.cert, s.fp.as_deref(), Some(&t), &t) {
                let sign = s.cert.sign;
                crate::structure::memo::record(line.keys, line.frames, &t, false, sign);
                crate::structure::memo::record(line.keys, line.frames, &t, true, sign.neg());
            }
        }
        if tie == 0 {
            let cert = s.cert;
            let failure = classify(world, &cert, &t);
            let (pairs, apart, zero) = match failure {
                Failure::Contact { a, b, third } => {
                    let zero = root_at(world, &cert, s.fp.as_deref(), Some(&t), &t);
                    let owners = s.owners.clone();
                    let apart = crate::structure::events::real_touch_excluded(world, &p, &t, zero);
                    // (no contact to prove where the polygons are apart:
                    // nor the exact instant to compute for its hint)
                    if apart.is_none() {
                        hint_contact(world, &p, &t);
                    }
                    let pairs =
                        contact_pairs(world, &self.kss, &owners, &p, &t, (a, b, third), apart);
                    (pairs, apart, zero)
                }
                Failure::Between { .. } => (
                    nearby_contact(world, &p, &t).into_iter().collect(),
                    None,
                    false,
                ),
            };
            if let Some(step) = self.touch(world, p, &t, pairs, apart, collides) {
                // (a contact set aside whose turn is known zero now: see
                // `InstantState::zero`)
                if zero && matches!(step, Step::Contact(..)) {
                    let versions = p.map(|a| world.obj_view_words(a.obj)[0]);
                    match &mut self.instant.zero {
                        Some((at, ps)) if *at == t => ps.push((p, versions)),
                        _ => self.instant.zero = Some((t.clone(), vec![(p, versions)])),
                    }
                }
                return Ok(step);
            }
            // not a contact, or a touch that is not a collision: a
            // structural failure
            match &mut self.instant.later {
                Some((_, ps)) => ps.push(p),
                None => self.instant.later = Some((t.clone(), smallvec::smallvec![p])),
            }
            let views = p.map(|a| world.obj_view_words(a.obj));
            match &mut self.instant.classified {
                Some((at, kept)) if at.is_known_same(&t) => kept.push((p, views, failure)),
                _ => {
                    self.instant.classified =
                        Some((t.clone(), smallvec::smallvec![(p, views, failure)]))
                }
            }
            return Ok(Step::Deferred(t));
        }
        self.handle_or_rebuild(world, p, t, contacts, collides)
    }

    /// The failure of `p` at `t` where the bodies of `pairs` touch: a
    /// contact if some pair collides by the driver's rule (`collides`), else
    /// a refinement if the triple has an approximation vertex; `None` for a
    /// structural failure (no touch, or a touch that is not a collision).
    /// `apart` is a pair whose polygons certainly do not meet there
    /// ([`crate::structure::events::real_touch_excluded`]): it gets no contact test
    /// (that costs O(n) and would make every pop as dear as the polygons
    /// are large).
    pub(super) fn touch(
        &mut self,
        world: &Geo,
        p: [Att; 3],
        t: &Time,
        pairs: Vec<(BodyId, BodyId)>,
        apart: Option<(BodyId, BodyId)>,
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Option<Step> {
        if pairs.is_empty() {
            return None;
        }
        let colliding: Vec<(BodyId, BodyId)> = pairs
            .into_iter()
            .filter(|&(a, b)| apart != Some((a, b)) && apart != Some((b, a)))
            .filter(|&(a, b)| collides(a, b, t))
            .collect();
        if !colliding.is_empty() {
            self.instant.waiting.push(p);
            return Some(Step::Contact(t.clone(), colliding));
        }
        p.iter()
            .any(|&a| !world.is_real(a))
            .then(|| Step::Refine(t.clone(), p))
    }

    /// [`Kinetic::handle`], falling back to [`Kinetic::rebuild_after`] when
    /// the local operations cannot resolve a degenerate instant (and no
    /// contact is pending at it).
    pub(super) fn handle_or_rebuild(
        &mut self,
        world: &Geo,
        p: [Att; 3],
        t: Time,
        contacts: &[(BodyId, BodyId)],
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Result<Step, StructureError> {
        if self.instant.broken.is_some() {
            // this event waits for the rebuild. After a refinement a local
            // repair would miss it; after failed local operations it is
            // scheduled again once the region around them is repaired (and
            // handled then, at this instant if it still fails at it)
            if let Some(b) = self.instant.broken.as_mut() {
                match (b.kind, b.around.as_mut()) {
                    (Rebuild::Degenerate, Some((_, triples))) => triples.push(p),
                    _ => b.around = None,
                }
            }
            return Ok(Step::Deferred(t));
        }
        match self.handle(world, p, t.clone(), contacts, collides) {
            Err(e) if contacts.is_empty() && self.instant.waiting.is_empty() => {
                trace!("local operations failed at {}: {e}; repairing", t.to_f64());
                #[cfg(feature = "trace")]
                self.kss.trace_dump();
                // (with those of the certificate whose operation failed: a
                // triangle handled first for `p`'s corridor may have a
                // polygon that `p` does not name)
                let mut bodies = bodies_of(&p);
                if self.instant.recent_at.as_ref() == Some(&t) {
                    if let Some(q) = self.instant.recent.back() {
                        bodies.extend(bodies_of(q));
                        bodies.sort();
                        bodies.dedup();
                    }
                }
                // (only all of them together: the failed operation may have
                // changed corridors between any two of them before failing,
                // and the region must take every such corridor; not after a
                // failed rebuild, which may have left a repair half done)
                if self.unbuildable.as_ref() != Some(&t)
                    && self.repair_around(world, (&bodies, false), p, &t)?
                {
                    self.reschedule_unqueued(world, &p, &t);
                    return Ok(Step::Internal(t));
                }
                trace!("no local repair at {}: rebuilding", t.to_f64());
                self.rebuild_after(world, &t, Rebuild::Degenerate)
                    .map_err(|r| StructureError::Local(format!("{e}; then {r}")))?;
                Ok(Step::Internal(t))
            }
            Err(_e) => {
                // contacts at this instant: repair once the collision
                // response has set the motions (`motion_changed`), around
                // the failing certificate's bodies (if nothing else is
                // deferred meanwhile), else rebuild then
                trace!(
                    "local operations failed at {}: {_e}; repairing after the response",
                    t.to_f64()
                );
                self.instant.broken = Some(Broken {
                    kind: Rebuild::Degenerate,
                    around: Some((bodies_of(&p), vec![p])),
                });
                Ok(Step::Deferred(t))
            }
            other => other,
        }
    }

    /// Whether the local operations seem to cycle at `now`: the last
    /// certificate handled was handled three times before at this instant, among
    /// the last few (the driver then switches to the alternate
    /// normalization, [`Kinetic::alternate_normalization`], and if they
    /// still cycle tries [`Kinetic::repair_cycle`]).
    pub fn cycling(&self, now: &Time) -> bool {
        let recent = &self.instant.recent;
        self.instant.recent_at.as_ref() == Some(now)
            && recent
                .back()
                .is_some_and(|p| recent.iter().filter(|&q| q == p).count() >= 4)
    }

    /// The local operations cycle at `now`: for the rest of the instant,
    /// [`Kss::normalize`] takes the decomposition that holds the fewest
    /// junctions against the motion rather than the first that works (two
    /// operations that undo each other usually meet at a junction held
    /// needlessly, whose failure hands an edge back). `false` if it already
    /// did at `now` (the caller repairs then).
    pub fn alternate_normalization(&mut self, now: &Time) -> bool {
        if self.kss.fewest_held.as_ref() == Some(now) {
            return false;
        }
        trace!(
            "operations cycle at {}: the alternate normalization",
            now.to_f64()
        );
        self.kss.fewest_held = Some(now.clone());
        self.instant.recent.clear();
        true
    }

    /// The local operations cycle at `now` ([`Kinetic::cycling`], or the
    /// driver's guard: far more operations at one instant than the
    /// structure has corridors): repair
    /// the region around the polygons of the last certificates handled, as
    /// at a settled contact ([`Kinetic::repair_around`]), so that the
    /// structure is the one for just after `now`. `false` when there is
    /// none (the caller rebuilds the whole structure).
    pub fn repair_cycle(&mut self, world: &Geo, now: &Time) -> Result<bool, StructureError> {
        let Some(&last) = self.instant.recent.back() else {
            return Ok(false);
        };
        trace!("repair_cycle at {}", now.to_f64());
        let mut bodies: Vec<BodyId> = self.instant.recent.iter().flat_map(bodies_of).collect();
        bodies.sort();
        bodies.dedup();
        if !self.repair_around(world, (&bodies, false), last, now)? {
            return Ok(false);
        }
        for p in std::mem::take(&mut self.instant.recent) {
            self.reschedule_unqueued(world, &p, now);
        }
        Ok(true)
    }

    /// Handle the failure of the (popped) certificate on `p` at `t`.
    pub(super) fn handle(
        &mut self,
        world: &Geo,
        p: [Att; 3],
        t: Time,
        contacts: &[(BodyId, BodyId)],
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Result<Step, StructureError> {
        let Some((id, s)) = self.certs.find(&p) else {
            return Ok(Step::Deferred(t)); // replaced by an earlier operation
        };
        if s.key.is_some() {
            return Ok(Step::Deferred(t)); // rescheduled meanwhile
        }
        let (cert, fp, popped) = (
            s.cert,
            s.fp.as_deref().copied(),
            self.certs.popped(id).cloned(),
        );
        let owners = s.owners.clone();
        if self.instant.recent_at.as_ref() != Some(&t) {
            self.instant.recent.clear();
            self.instant.recent_at = Some(t.clone());
        }
        if self.instant.recent.len() == RECENT {
            self.instant.recent.pop_front();
        }
        self.instant.recent.push_back(p);
        if !due_is_failing(world, &cert, (fp.as_ref(), popped.as_ref()), &t) {
            // an operation at this instant made it hold again
            self.reschedule(world, &p, &t);
            return Ok(Step::Deferred(t));
        }
        trace!(
            "handle t={} {:?} {:?} {:?} {:?} -> {:?}",
            t.to_f64(),
            cert.p,
            cert.sign,
            cert.kind,
            owners,
            classify(world, &cert, &t)
        );
        #[cfg(feature = "trace")]
        if std::env::var_os("KSS_DUMP").is_some() {
            self.kss.trace_dump();
        }
        // (as it was classified when it was popped, if the views of its
        // bodies are the same: a function of its points, the instant and
        // those views)
        let views = p.map(|a| world.obj_view_words(a.obj));
        let known = match &mut self.instant.classified {
            Some((at, kept)) if at.is_known_same(&t) => kept
                .iter()
                .position(|(q, v, _)| *q == p && *v == views)
                .map(|i| kept.swap_remove(i).2),
            _ => None,
        };
        let mut failure = match known {
            Some(f) => {
                debug_assert_eq!(
                    f,
                    classify(world, &cert, &t),
                    "a kept classification of {p:?}"
                );
                f
            }
            None => classify(world, &cert, &t),
        };
        if let Failure::Contact { a, b, third } = failure {
            let zero = root_at(world, &cert, fp.as_ref(), popped.as_ref(), &t);
            let apart = crate::structure::events::real_touch_excluded(world, &p, &t, zero);
            let pairs = contact_pairs(world, &self.kss, &owners, &p, &t, (a, b, third), apart);
            if let Some(step) = self.touch(world, p, &t, pairs, apart, collides) {
                return Ok(step);
            }
            // two polygons touch but do not collide (they slid along each
            // other, or the collision response at this instant already
            // separates them): a structural event at the touching vertex
            // if there is one
            for pair in [Some((a, b)), third.map(|c| (a, c)), third.map(|c| (b, c))]
                .into_iter()
                .flatten()
            {
                let pair = (pair.0.min(pair.1), pair.0.max(pair.1));
                if !self.instant.settled.contains(&pair) {
                    self.instant.settled.push(pair);
                }
            }
            match settled_between(world, &cert, &t) {
                Some(f) => failure = f,
                None => {
                    trace!("settled contact at {}: repairing", t.to_f64());
                    if contacts.is_empty() && self.instant.waiting.is_empty() {
                        let bodies: Vec<BodyId> =
                            [Some(a), Some(b), third].into_iter().flatten().collect();
                        if self.repair_around(world, (&bodies, true), p, &t)? {
                            self.reschedule_unqueued(world, &p, &t);
                            return Ok(Step::Internal(t));
                        }
                        trace!("no local repair at {}: rebuilding", t.to_f64());
                        self.rebuild_after(world, &t, Rebuild::Degenerate)?;
                        return Ok(Step::Internal(t));
                    }
                    // contacts at this instant: set aside until the
                    // response has set the motions, then handled again
                    // (repaired then, if it still fails)
                    self.instant.waiting.push(p);
                    return Ok(Step::Deferred(t));
                }
            }
        }
        match failure {
            Failure::Contact { .. } => unreachable!("contacts are handled above"),
            Failure::Between { middle, .. } => {
                let near_contact = contacts.iter().any(|&(a, b)| {
                    p.iter()
                        .any(|x| x.obj == Obj::Body(a) || x.obj == Obj::Body(b))
                });
                if near_contact {
                    self.instant.waiting.push(p);
                    return Ok(Step::Deferred(t));
                }
                let owner = *owners
                    .first()
                    .ok_or_else(|| StructureError::Invariant("certificate without owner".into()))?;
                // a partition triangle at an end of the corridor that
                // collapses at this instant goes first: the corridor's
                // operations assume its end triangles, and two of its
                // junctions can otherwise hand an edge back and forth
                // across the degenerate triangle for ever
                // (a junction's plan, read once: for this test and for the
                // operation below)
                let plan = match owner {
                    Owner::Corr(k) if self.kss.corrs[k.0 as usize].b != Obj::Omega => self
                        .kss
                        .junction_plan(world, k, p, middle)
                        .ok()
                        .map(|plan| (k, plan)),
                    _ => None,
                };
                let moved_tri = plan.and_then(|(k, plan)| {
                    let c = &self.kss.corrs[k.0 as usize];
                    match plan {
                        (crate::structure::local::EdgeRef::EndS, _, _, true) => Some(c.s.0),
                        (crate::structure::local::EdgeRef::EndT, _, _, true) => Some(c.t.0),
                        _ => None,
                    }
                });
                // (only the triangle whose corner the operation would move)
                let collapsing = moved_tri.and_then(|tri| {
                    let q = self.kss.triangle_certs(tri).first().map(|c| c.p)?;
                    let (qid, s) = self.certs.find(&q)?;
                    let due = s
                        .key
                        .and_then(QKey::near)
                        .is_some_and(|key| self.queue.get(key).is_some_and(|(tq, _)| *tq == t));
                    let at = due_time(&self.queue, s.key, self.certs.popped(qid));
                    (q != p && due && due_is_failing(world, &s.cert, (s.fp.as_deref(), at), &t))
                        .then_some((tri, q))
                });
                if let Some((_tri, q)) = collapsing {
                    trace!("triangle {} collapses first", _tri.0);
                    if let Some((qid, s)) = self.certs.find_mut(&q) {
                        // (due at this instant: in the queue of exact times)
                        if let Some(key) = s.key.and_then(QKey::near) {
                            s.key = None;
                            // (the instant's time it keeps instead of its
                            // own does not hold its points: the book keeps
                            // them, see `book::schedule_fp`)
                            if s.fp.is_none() {
                                let own = self.queue.get(key).map(|(tq, _)| tq);
                                s.fp = super::book::schedule_fp(None, own).map(Box::new);
                            }
                            self.queue.cancel(key);
                            self.certs.set_popped(qid, t.clone());
                        }
                    }
                    self.reschedule(world, &p, &t);
                    return self.handle(world, q, t, contacts, collides);
                }
                let out = match plan {
                    Some((k, plan)) => self.kss.slide_planned(world, k, plan)?,
                    None => self.kss.process(world, owner, p, middle, &t)?,
                };
                self.instant.handling = Some(p);
                self.kss.handling = Some(p);
                let applied = self.apply(world, out, &t);
                self.instant.handling = None;
                self.kss.handling = None;
                applied?;
                // a certificate that outlived the operation unchanged fails
                // again if it is still wrong just after t
                self.reschedule_unqueued(world, &p, &t);
                Ok(Step::Internal(t))
            }
        }
    }

    /// The junction certificates of corridor `k` known to keep their sign
    /// just after `t` ([`crate::structure::Kss::known`]): those queued
    /// strictly after `t`, when nothing else fails at `t` (the queue's next
    /// failure is later, nothing waits at this instant) and the corridor
    /// holds no junction against the motion; `None` otherwise.
    fn known_junctions(
        &self,
        k: CorrId,
        t: &Time,
    ) -> Option<(Time, crate::structure::local::Certs)> {
        if !self.instant.waiting.is_empty()
            || self.instant.later.is_some()
            || self.kss.held.contains_key(&k)
            || self.queue.peek().is_some_and(|(_, tq, _, _)| tq == t)
        {
            return None;
        }
        let mut out = crate::structure::local::Certs::new();
        for &id in &self.owned_corr[k.0 as usize] {
            let Some(s) = self.certs.at(id) else {
                continue;
            };
            // (out of the queue: it never fails, or holds until a bridge
            // ends; the one being handled was popped)
            let later = match s.key {
                Some(QKey::Near(key)) => self.queue.get(key).is_some_and(|(tq, _)| tq != t),
                // (its failure is strictly after the current instant)
                Some(QKey::Far(_)) => true,
                None => self.instant.handling != Some(s.cert.p),
            };
            if s.cert.kind == CertKind::Junction && later && out.try_push(s.cert).is_err() {
                break;
            }
        }
        Some((t.clone(), out))
    }

    pub(super) fn apply(
        &mut self,
        world: &Geo,
        out: Outcome,
        t: &Time,
    ) -> Result<(), StructureError> {
        self.tally.events(out.kind, 1);
        let mut corrs = out.corrs;
        corrs.sort();
        crate::structure::local::dedup_sorted(&mut corrs);
        // (the first change of the structure at this instant: see
        // `Kss::trust_op`)
        let first = self
            .instant
            .changed_at
            .as_ref()
            .is_none_or(|c| !c.is_known_same(t) && c != t);
        for &k in &corrs {
            self.kss.known = self.known_junctions(k, t);
            self.kss.op_alone = first;
            let steps = self.kss.normalize(world, k, t, None);
            self.kss.op_alone = false;
            self.kss.known = None;
            if steps? > 0 {
                self.tally.searches += 1;
            }
        }
        for tri in out.tris {
            self.refresh(world, Owner::Tri(tri), t)?;
        }
        for &k in &corrs {
            self.refresh(world, Owner::Corr(k), t)?;
        }
        // (the corridors next to a changed triangle that did not change are
        // candidates for coarsening too; the list's buffer is kept from
        // event to event)
        self.last_touched.clear();
        self.last_touched
            .extend(corrs.iter().chain(&out.near).copied());
        self.last_touched.sort();
        self.last_touched.dedup();
        Ok(())
    }
}
