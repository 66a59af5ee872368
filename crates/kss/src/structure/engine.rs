//! The kinetic engine: every certificate of the structure scheduled in the
//! event queue at its exact failure time; failures popped in time order and
//! either reported as collisions or repaired by a local operation
//! (`ops`), after which only the touched corridors and triangles get new
//! certificates; flight-plan changes reschedule only the certificates of the
//! bodies involved; and an audit against a from-scratch recomputation.

use std::collections::{BTreeMap, BTreeSet};

use super::certs::Cert;
use super::events::{classify, nearby_contact, settled_between, Failure};
use super::geo::{Geo, PointRef};
use super::ops::{Outcome, Owner};
use super::{Att, CorrId, Kss, Obj, TriId};
use crate::motion::{orient_poly, LinearPoint};
use crate::num::{
    filtered_failure, filtered_root, ExactTime, Filtered, Interval, Poly, Rational, Sign, Time,
};
use crate::sim::{EventKey, EventQueue};
use crate::world::BodyId;

/// Debug tracing of every failure (`--features trace`; the library does no
/// IO otherwise).
macro_rules! trace {
    ($($arg:tt)*) => {
        #[cfg(feature = "trace")]
        eprintln!($($arg)*);
    };
}

/// A hash map with a fixed hasher (the same order in every run).
type FastMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;

/// A certificate, where it sits in the queue, and who owns it.
#[derive(Clone, Debug)]
struct Scheduled {
    cert: Cert,
    /// `None` when the certificate never fails on the current motions, or
    /// while it waits (a contact reported at the current instant).
    key: Option<EventKey>,
    owners: Vec<Owner>,
    /// What the three points were ([`Geo::point_id`]) when the failure
    /// time under `key` was computed (`None` when it has none): while they
    /// are the same points, the certificate is known to be wrong just after
    /// that time, which is a root where it turns negative (the flag:
    /// `true`) or the instant it was computed at, where it is not positive
    /// just after ([`failure_time`]).
    /// (Boxed, as is `popped`: the map of certificates stays small.)
    fp: Option<Box<(Fingerprint, bool)>>,
    /// The failure time it was popped (or taken out of the queue) at, while
    /// it waits to be handled or handled again (`None` while queued).
    popped: Option<Box<Time>>,
}

/// The failure time a certificate is due at: its queued time, or the one it
/// was popped at.
fn due_time<'a>(
    queue: &'a EventQueue<Time, [Att; 3]>,
    key: Option<EventKey>,
    popped: &'a Option<Box<Time>>,
) -> Option<&'a Time> {
    match key {
        Some(k) => queue.get(k).map(|(t, _)| t),
        None => popped.as_deref(),
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
    /// Hashed (with a fixed, deterministic hasher): looked up several times
    /// per event; iterated only where the order does not matter or is
    /// sorted first.
    certs: FastMap<[Att; 3], Scheduled>,
    /// The certificates that involve each body (for local rescheduling when
    /// a flight plan changes).
    by_body: FastMap<BodyId, BTreeSet<[Att; 3]>>,
    owned_tri: Vec<Vec<[Att; 3]>>,
    owned_corr: Vec<Vec<[Att; 3]>>,
    queue: EventQueue<Time, [Att; 3]>,
    max_active: usize,
    /// Certificates popped at the current instant and set aside: contacts
    /// (the collision response changes the motions) and failures next to a
    /// contact. Rescheduled by [`Kinetic::motion_changed`].
    waiting: Vec<[Att; 3]>,
    /// Popped failures of the current instant that wait until every possible
    /// contact of the instant has been classified.
    later: Option<(Time, Vec<[Att; 3]>)>,
    /// The certificate whose failure is being handled.
    handling: Option<[Att; 3]>,
    /// The local operations failed (or the hierarchy was refined) at an
    /// instant with contacts: the structure is rebuilt when the collision
    /// response is applied (the rebuild's kind for the statistics).
    broken: Option<&'static str>,
    /// For a `refine_rebuild` after the response: the bodies whose
    /// approximations were refined (the region a local repair takes
    /// instead); for a `degenerate_rebuild`, the bodies of the certificate
    /// on which the local operations failed, with it and the certificates
    /// deferred after it. `None` after a refinement if an event was
    /// deferred meanwhile (the deferred events need the whole structure
    /// rebuilt).
    broken_around: Option<(Vec<BodyId>, Vec<[Att; 3]>)>,
    /// Internal events by kind.
    pub counts: BTreeMap<&'static str, u64>,
    /// The instant of the latest [`Kinetic::rebuild_after`] that found no
    /// structure (polygons may rest in contact there; the driver decides).
    pub unbuildable: Option<Time>,
    /// Pairs of bodies that touched at the current instant without a
    /// collision (they slid along each other, or a response already
    /// separates them): with the hierarchy, the driver then pops the
    /// approximation points that would slide along the other body
    /// ([`Kinetic::take_settled`]).
    settled: Vec<(BodyId, BodyId)>,
    /// The corridors the last operation touched (where coarsening is tried).
    last_touched: Vec<CorrId>,
    /// The last few certificates handled at the instant of the last one
    /// (where local operations that cycle at one instant are repaired,
    /// [`Kinetic::repair_cycle`]).
    recent: std::collections::VecDeque<[Att; 3]>,
    /// The instant of `recent`.
    recent_at: Option<Time>,
    /// Rotates the coarsening candidates.
    tick: u64,
}

impl Kinetic {
    /// Every certificate with its owners and scheduled failure time (a
    /// debugging view, in the order of their points).
    pub fn certificate_list(&self) -> Vec<(Cert, Vec<Owner>, Option<Time>)> {
        let mut keys: Vec<&[Att; 3]> = self.certs.keys().collect();
        keys.sort();
        keys.into_iter()
            .map(|p| {
                let s = &self.certs[p];
                let t = s
                    .key
                    .and_then(|k| self.queue.get(k).map(|(t, _)| t.clone()));
                (s.cert, s.owners.clone(), t)
            })
            .collect()
    }
}

/// The certificate function of `c`, oriented so that it is positive while
/// the certificate holds.
pub fn cert_poly(world: &Geo, c: &Cert) -> Poly {
    let lp = |a: Att| match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("certificates have finite points"),
    };
    cert_poly_of(c.kind, c.sign, &c.p.map(lp))
}

/// [`cert_poly`] from the certificate's three moving points.
fn cert_poly_of(kind: super::certs::CertKind, sign: Sign, p: &[LinearPoint; 3]) -> Poly {
    if kind == super::certs::CertKind::Order {
        return crate::motion::dot_poly(&p[1], &p[0], &p[2]).neg();
    }
    let q = orient_poly(&p[0], &p[1], &p[2]);
    if sign == Sign::Negative {
        q.neg()
    } else {
        q
    }
}

/// Enclosures of the coefficients of a positive multiple of [`cert_poly`]
/// (an enclosure `[0, 0]` where the coefficient is exactly zero because two
/// of the points are on one body), from the f64 view of the points.
fn cert_enclosure(world: &Geo, c: &Cert) -> Option<[Interval; 3]> {
    use crate::geom::Mr;
    let order = c.kind == super::certs::CertKind::Order;
    // the same points as cert_poly: Order is −(p0 − p1)·(p2 − p1)
    let [p, q, r] = if order { [c.p[1], c.p[0], c.p[2]] } else { c.p };
    // (midpoint–radius arithmetic: a few products per operation and no
    // branch, where intervals take the extreme products by cases)
    let [ep, eq, er] = [
        world.linear_mr(p)?,
        world.linear_mr(q)?,
        world.linear_mr(r)?,
    ];
    // q − p as linear positions; the velocity part is exactly zero for two
    // points of one body
    let diff = |a: Att, ea: &[Mr; 4], b: Att, eb: &[Mr; 4]| {
        let same = a.obj == b.obj;
        [
            eb[0] - ea[0],
            if same { Mr::ZERO } else { eb[1] - ea[1] },
            eb[2] - ea[2],
            if same { Mr::ZERO } else { eb[3] - ea[3] },
        ]
    };
    let [ux0, ux1, uy0, uy1] = diff(p, &ep, q, &eq);
    let [vx0, vx1, vy0, vy1] = diff(p, &ep, r, &er);
    let same_qr = q.obj == r.obj;
    // (a sum with an exact zero is the other term, exactly)
    let plus = |a: Mr, b: Mr| {
        if a.is_zero() {
            b
        } else if b.is_zero() {
            a
        } else {
            a + b
        }
    };
    let mut e = if order {
        [
            plus(ux0 * vx0, uy0 * vy0),
            plus(plus(ux0 * vx1, ux1 * vx0), plus(uy0 * vy1, uy1 * vy0)),
            plus(ux1 * vx1, uy1 * vy1),
        ]
    } else {
        [
            plus(ux0 * vy0, -(uy0 * vx0)),
            plus(plus(ux0 * vy1, ux1 * vy0), -plus(uy0 * vx1, uy1 * vx0)),
            // u and v move alike when q and r are on one body
            if same_qr {
                Mr::ZERO
            } else {
                plus(ux1 * vy1, -(uy1 * vx1))
            },
        ]
    };
    if order || c.sign == Sign::Negative {
        e = e.map(|x| -x);
    }
    Some(e.map(Mr::interval))
}

/// A deferred failure time's exact computation: the certificate's three
/// points with the frames they moved by when it was scheduled.
struct DeferredFailure {
    p: [PointRef; 3],
    kind: super::certs::CertKind,
    sign: Sign,
}

impl ExactTime for DeferredFailure {
    fn exact(&self) -> Time {
        cert_poly_of(
            self.kind,
            self.sign,
            &self.p.each_ref().map(PointRef::linear),
        )
        .failure_root()
        .expect("the filter proved that the certificate fails")
    }
}

/// When certificate `c` fails, given that `now` is the current time: `now`
/// itself if it is already wrong just after `now`, else the first later root
/// where it stops being positive, if any.
pub fn failure_time(world: &Geo, c: &Cert, now: &Time) -> Option<Time> {
    use super::counters::{bump, Counter};
    bump(Counter::FailureTimes);
    // (`None` only if a point is no vertex of its body's approximation,
    // which the enclosures already rule out)
    let deferred = |iv: Interval| -> Option<Time> {
        let [a, b, d] = c.p.map(|x| world.point_ref(x));
        let src = DeferredFailure {
            p: [a?, b?, d?],
            kind: c.kind,
            sign: c.sign,
        };
        Some(Time::deferred(iv, src))
    };
    let e = cert_enclosure(world, c);
    if let Some(e) = e {
        match filtered_failure(e, now.interval()) {
            Filtered::Never => return None,
            Filtered::At(iv) => {
                if let Some(t) = deferred(iv) {
                    return Some(t);
                }
            }
            Filtered::Unsure => {}
        }
    }
    // the sign just after `now` of an orientation certificate (most often
    // zero at `now`: its points were collinear at this event) from the
    // instant's memo of exact turns, when it knows it
    let orient = c.kind != super::certs::CertKind::Order;
    let signed = |s: Sign| if c.sign == Sign::Negative { s.neg() } else { s };
    let known = if orient {
        world.memo_peek(c.p, now, true).map(signed)
    } else {
        None
    };
    match (known, e) {
        (Some(Sign::Negative), _) => {
            bump(Counter::FailureTimesMemo);
            return Some(now.clone());
        }
        (Some(Sign::Positive), Some(e)) => match filtered_root(e, now.interval()) {
            Filtered::Never => {
                bump(Counter::FailureTimesMemo);
                return None;
            }
            Filtered::At(iv) => {
                if let Some(t) = deferred(iv) {
                    bump(Counter::FailureTimesMemo);
                    return Some(t);
                }
            }
            Filtered::Unsure => {}
        },
        _ => {}
    }
    bump(Counter::FailureTimesExact);
    let p = cert_poly(world, c);
    let after = p.sign_after(now);
    if orient && known.is_none() {
        world.memo_record(c.p, now, true, signed(after));
    }
    if after != Sign::Positive {
        // (a partition triangle flat while two of its corners rest on each
        // other holds until a motion change parts them)
        if resting_flat(world, c, &p) {
            return None;
        }
        return Some(now.clone());
    }
    p.failure_after_positive(now)
}

/// Whether certificate `c`, whose polynomial is `p`, is a partition
/// triangle that stays flat while two of its corners rest on each other
/// ([`super::faces::flat_while_resting`]): it holds until a motion change
/// parts them.
fn resting_flat(world: &Geo, c: &Cert, p: &Poly) -> bool {
    p.is_zero()
        && c.kind == super::certs::CertKind::Triangle
        && super::faces::flat_while_resting(world, c.p)
}

/// The local repair's candidate sets ([`Kinetic::repair_around`]): queue
/// `set` grown by the bodies `more` (with the number of growth rounds that
/// led to it), unless `more` is empty, `set` was grown twice already, or
/// the same set (in any order) is queued.
fn grow_sets(
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
fn plan_holds(world: &Geo, plan: &super::remove::RemovalPlan, now: &Time, at: &Time) -> bool {
    plan.new_triangles().iter().all(|c| {
        if c.iter().any(|a| a.is_omega()) {
            return true;
        }
        let [x, y, z] = c.map(|a| world.point(a));
        let q = crate::motion::orient_poly(&x, &y, &z);
        (q.is_zero() && super::faces::flat_while_resting(world, *c))
            || (q.sign_after(now) == Sign::Positive
                && q.first_failure_after(now).is_none_or(|x| x > *at))
    })
}

/// The alive body other than `b` whose bounding box is nearest to `b`'s at
/// `now` (doubles: a starting point for [`Kinetic::insert_body`], which
/// checks everything exactly).
fn nearest_body(world: &Geo, b: BodyId, now: &Time) -> Option<BodyId> {
    let t = now.to_f64();
    let bounds = |c: BodyId| world.body(c).bounds_f64(t);
    let nb = bounds(b);
    let gap = |o: [f64; 4]| {
        let dx = (o[0] - nb[1]).max(nb[0] - o[1]).max(0.0);
        let dy = (o[2] - nb[3]).max(nb[2] - o[3]).max(0.0);
        dx * dx + dy * dy
    };
    (0..world.bodies().len() as u32)
        .map(BodyId)
        .filter(|&c| c != b && world.body(c).alive)
        .map(|c| (gap(bounds(c)), c))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, c)| c)
}

/// How many handled certificates [`Kinetic::repair_cycle`] looks back at.
const RECENT: usize = 8;

/// The distinct bodies of a triple.
fn bodies_of(p: &[Att; 3]) -> Vec<BodyId> {
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

/// Whether certificate `c` is already wrong just after `now` (it fails at
/// `now`).
fn is_failing(world: &Geo, c: &Cert, now: &Time) -> bool {
    cert_poly(world, c).sign_after(now) != Sign::Positive
}

/// [`is_failing`] for a certificate that is due at `now` (queued at `now`,
/// or popped at `now`): known without arithmetic while its points are the
/// ones its failure time `due` was computed for (see [`Scheduled::fp`]),
/// evaluated exactly otherwise.
fn due_is_failing(
    world: &Geo,
    c: &Cert,
    (fp, due): (Option<&(Fingerprint, bool)>, Option<&Time>),
    now: &Time,
) -> bool {
    if let (Some(&(f, root)), Some(at)) = (fp, due) {
        if Some(f) == fingerprint(world, &c.p) && at.is_known_same(now) {
            super::counters::bump(super::counters::Counter::FailingKnown);
            // (a failure root: negative just after it; the instant's memo
            // of turns learns that for the orientation)
            if root && c.kind != super::certs::CertKind::Order {
                let s = if c.sign == Sign::Negative {
                    Sign::Positive
                } else {
                    Sign::Negative
                };
                world.memo_record(c.p, now, true, s);
            }
            return true;
        }
    }
    is_failing(world, c, now)
}

/// Order among failures at one instant: a vertex against another body's
/// polygon edge (a possible contact) comes first, so that every contact of an
/// instant is known before the structure changes around it.
fn tie(world: &Geo, p: &[Att; 3]) -> u64 {
    let possible_contact = (0..3).any(|i| {
        let (x, y, z) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        z.obj != x.obj && super::faces::poly_edge(world, x, y)
    });
    u64::from(!possible_contact)
}

/// The pairs in contact at `t` for a contact failure of triple `p` between
/// `a` and `b`: that pair, and any other pair among the triple's bodies and
/// the bodies at the corners of the partition triangles that end the
/// certificate's corridors, that touches at `t` too (three polygons meeting
/// at one point need not have a certificate that involves two of them).
fn contact_pairs(
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
    let Some(r) = t.as_rational() else {
        return v;
    };
    // approximations touching where the polygons certainly do not: a
    // refinement, not a contact to look around
    if third.is_none() && apart.is_some() {
        return v;
    }
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
    pub fn new(world: &Geo, t: &Rational) -> Result<Kinetic, String> {
        let (kss, perturbed) = super::build::build(world, t).map_err(|e| e.to_string())?;
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
    ) -> Result<Kinetic, String> {
        // every alive polygon is in a structure of the right size: one built
        // at an instant where polygons overlap lacks some (a cheap check;
        // the rebuilds for just after an instant try an earlier one then)
        let n = world.bodies().iter().filter(|b| b.alive).count();
        if n >= 2 && (kss.tris.len() != 2 * n - 2 || kss.corrs.len() != 3 * n - 3) {
            return Err(format!(
                "{} partition triangles and {} corridors for {n} polygons: polygons overlap at t = {}",
                kss.tris.len(),
                kss.corrs.len(),
                t.to_f64()
            ));
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
    pub fn rebuild(&mut self, world: &Geo, t: &Rational) -> Result<(), String> {
        let fresh = Kinetic::new(world, t)?;
        self.replace_with(fresh);
        Ok(())
    }

    /// Become `fresh`, keeping the event counts and the largest queue size.
    fn replace_with(&mut self, mut fresh: Kinetic) {
        fresh.counts = std::mem::take(&mut self.counts);
        // the touches of this instant still need their pops afterwards
        fresh.settled = std::mem::take(&mut self.settled);
        fresh.max_active = fresh.max_active.max(self.max_active);
        *self = fresh;
    }

    fn schedule_everything(&mut self, world: &Geo, now: &Time) -> Result<(), String> {
        self.owned_tri = vec![Vec::new(); self.kss.tris.len()];
        self.owned_corr = vec![Vec::new(); self.kss.corrs.len()];
        for ki in 0..self.kss.corrs.len() {
            let steps = self.kss.normalize(world, CorrId(ki as u32), now, None)?;
            if steps > 0 {
                *self.counts.entry("repair").or_default() += 1;
            }
        }
        for ti in 0..self.kss.tris.len() {
            self.refresh(world, Owner::Tri(TriId(ti as u32)), now)?;
        }
        for ki in 0..self.kss.corrs.len() {
            self.refresh(world, Owner::Corr(CorrId(ki as u32)), now)?;
        }
        Ok(())
    }

    /// Recompute the certificates owned by `o` at `now`: drop the ones it no
    /// longer owns, schedule the new ones.
    fn refresh(&mut self, world: &Geo, o: Owner, now: &Time) -> Result<(), String> {
        let fresh = match o {
            Owner::Tri(t) => self.kss.triangle_certs(t),
            Owner::Corr(k) => self.kss.corridor_certs(world, k, now),
        };
        let old = match o {
            Owner::Tri(t) => std::mem::take(&mut self.owned_tri[t.0 as usize]),
            Owner::Corr(k) => std::mem::take(&mut self.owned_corr[k.0 as usize]),
        };
        // certificates that fail at `now` and have not been handled yet keep
        // their sign (and stay due now): recomputing them with the sign they
        // have just after `now` would swallow the failure when two fail at
        // one instant and the operation for the first touches the second
        let mut pending: BTreeMap<[Att; 3], Cert> = BTreeMap::new();
        let mut kept: Vec<[Att; 3]> = Vec::new();
        for p in &old {
            let Some(s) = self.certs.get_mut(p) else {
                continue;
            };
            s.owners.retain(|&x| x != o);
            if s.owners.is_empty() {
                let (cert, key, fp) = (s.cert, s.key, s.fp.as_deref().copied());
                let at = due_time(&self.queue, key, &s.popped).cloned();
                let due = self.handling == Some(*p) || self.due_now(p, key, now);
                if !due && fresh.contains(&cert) {
                    // the same certificate again, not due at this instant:
                    // it keeps its place in the queue (its failure time
                    // depends only on its points) and is owned again below
                    kept.push(*p);
                    continue;
                }
                if self.handling != Some(*p)
                    && due
                    && due_is_failing(world, &cert, (fp.as_ref(), at.as_ref()), now)
                {
                    pending.insert(*p, cert);
                }
                self.drop_cert(p);
            }
        }
        let mut mine = Vec::with_capacity(fresh.len());
        for c in fresh {
            let c = match pending.get(&c.p) {
                Some(old) if old.sign != c.sign => *old,
                _ => c,
            };
            match self.certs.get_mut(&c.p) {
                // a certificate left without owners (a removal in progress)
                // is taken over only as it is
                Some(s) if s.owners.is_empty() && s.cert != c => {
                    self.drop_cert(&c.p);
                    self.schedule_new(world, c, o, now);
                }
                Some(s) if s.cert.sign != c.sign => {
                    if self.handling == Some(c.p) || !is_failing(world, &s.cert, now) {
                        let e = format!(
                            "contradictory certificates on {:?} ({:?} and {:?})",
                            c.p, s.owners, o
                        );
                        // no owner list names the certificates kept above
                        // any more: they go, as they did before keeping
                        for p in &kept {
                            if self.certs.get(p).is_some_and(|s| s.owners.is_empty()) {
                                self.drop_cert(p);
                            }
                        }
                        return Err(e);
                    }
                    // the kept certificate fails now and will be handled
                    if !s.owners.contains(&o) {
                        s.owners.push(o);
                    }
                }
                Some(s) => {
                    if !s.owners.contains(&o) {
                        s.owners.push(o);
                    }
                }
                None => self.schedule_new(world, c, o, now),
            }
            mine.push(c.p);
        }
        match o {
            Owner::Tri(t) => self.owned_tri[t.0 as usize] = mine,
            Owner::Corr(k) => self.owned_corr[k.0 as usize] = mine,
        }
        self.max_active = self.max_active.max(self.queue.len());
        Ok(())
    }

    /// Queue certificate `c` at its failure time after `now`, if it has
    /// one: its queue key and [`Scheduled::fp`].
    fn enqueue(
        &mut self,
        world: &Geo,
        c: &Cert,
        now: &Time,
    ) -> (Option<EventKey>, Option<Box<(Fingerprint, bool)>>) {
        let Some(t) = failure_time(world, c, now) else {
            return (None, None);
        };
        let root = !t.is_known_same(now);
        let fp = fingerprint(world, &c.p).map(|f| Box::new((f, root)));
        (Some(self.queue.schedule(t, tie(world, &c.p), c.p)), fp)
    }

    /// Schedule certificate `c`, not yet known, for owner `o`.
    fn schedule_new(&mut self, world: &Geo, c: Cert, o: Owner, now: &Time) {
        let (key, fp) = self.enqueue(world, &c, now);
        for b in bodies_of(&c.p) {
            self.by_body.entry(b).or_default().insert(c.p);
        }
        self.certs.insert(
            c.p,
            Scheduled {
                cert: c,
                key,
                owners: vec![o],
                fp,
                popped: None,
            },
        );
    }

    /// Whether the certificate on `p` (queued under `key`) can be failing at
    /// `now`: queued at `now`, or popped at this instant and set aside. A
    /// failing certificate is always one of these, so the exact test need not
    /// run for the others (most of the certificates an operation replaces).
    fn due_now(&self, p: &[Att; 3], key: Option<EventKey>, now: &Time) -> bool {
        match key {
            Some(k) => self.queue.get(k).is_some_and(|(t, _)| t == now),
            None => {
                self.waiting.contains(p)
                    || self.later.as_ref().is_some_and(|(_, ps)| ps.contains(p))
            }
        }
    }

    fn drop_cert(&mut self, p: &[Att; 3]) {
        if let Some(s) = self.certs.remove(p) {
            for b in bodies_of(p) {
                if let Some(set) = self.by_body.get_mut(&b) {
                    set.remove(p);
                }
            }
            if let Some(k) = s.key {
                self.queue.cancel(k);
            }
        }
    }

    fn reschedule(&mut self, world: &Geo, p: &[Att; 3], now: &Time) {
        let Some(s) = self.certs.get_mut(p) else {
            return;
        };
        let (c, old) = (s.cert, s.key.take());
        if let Some(k) = old {
            self.queue.cancel(k);
        }
        let (key, fp) = self.enqueue(world, &c, now);
        if let Some(s) = self.certs.get_mut(p) {
            (s.key, s.fp, s.popped) = (key, fp, None);
        }
        self.max_active = self.max_active.max(self.queue.len());
    }

    /// Bodies changed their motion at `now`: reschedule every certificate
    /// that involves one of them (flight-plan changes are local), and the
    /// certificates set aside at this instant.
    pub fn motion_changed(
        &mut self,
        world: &Geo,
        now: &Time,
        bodies: &[BodyId],
    ) -> Result<(), String> {
        // (the motions changed: operations before this are no cycle of
        // operations after it)
        self.recent.clear();
        let mut touched: Vec<[Att; 3]> = bodies
            .iter()
            .filter_map(|b| self.by_body.get(b))
            .flatten()
            .copied()
            .collect();
        for &_b in bodies {
            trace!(
                "motion of {_b:?} at {}: {:?}",
                now.to_f64(),
                world.body(_b).traj.velocity().to_f64()
            );
        }
        let waiting = std::mem::take(&mut self.waiting);
        touched.extend(waiting.iter().copied());
        touched.sort();
        touched.dedup();
        for p in &touched {
            self.reschedule(world, p, now);
        }
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
        let undecided: Vec<bool> = touched
            .iter()
            .map(|p| {
                self.certs.contains_key(p)
                    && world
                        .orient_filtered(p[0], p[1], p[2], now.interval())
                        .is_none()
            })
            .collect();
        let reshape = self.straight_now(world, &touched, &undecided, now);
        // A bridge (an end or the middle one) between two vertices that rest on each other has
        // length zero, its corner the two ends' together; under the new
        // motions they may part, and the corridor's certificates are then
        // its two junctions again.
        let resting = self.resting_now(world, &touched, now);
        #[cfg(feature = "trace")]
        if std::env::var_os("KSS_DUMP").is_some() {
            eprintln!("resting at {}: {resting:?}", now.to_f64());
            self.kss.trace_dump();
        }
        for (p, undecided) in touched.into_iter().zip(undecided) {
            let Some(s) = self.certs.get(&p) else {
                continue;
            };
            // the turn is zero just after now only if it is zero for ever
            // (the three points slide along one line); the filter rules
            // that out wherever it decides a sign
            let lp = |a: Att| world.point(a);
            let zero = undecided && orient_poly(&lp(p[0]), &lp(p[1]), &lp(p[2])).is_zero();
            let owners: Vec<Owner> = s.owners.clone();
            if s.cert.kind == super::certs::CertKind::Order {
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
                self.handling = Some(p);
                for o in owners {
                    if matches!(o, Owner::Corr(_)) {
                        self.refresh(world, o, now)?;
                    }
                }
                self.handling = None;
            }
        }
        // (not when the structure is about to be rebuilt anyway)
        let (reshape, resting) = if self.broken.is_some() {
            (BTreeSet::new(), BTreeSet::new())
        } else {
            (reshape, resting)
        };
        for &k in &resting {
            let mid = self.kss.corrs[k.0 as usize].mid;
            let due = self.owned_corr[k.0 as usize].iter().any(|p| {
                self.certs
                    .get(p)
                    .is_some_and(|s| self.due_now(p, s.key, now))
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
                let first = self.owned_corr[k.0 as usize].first().copied();
                self.broken = Some("degenerate_rebuild");
                self.broken_around = first.map(|p| (bodies, vec![p]));
                break;
            }
            self.refresh(world, Owner::Corr(k), now)?;
        }
        for k in reshape {
            if self.broken.is_some() {
                break;
            }
            let mid = self.kss.corrs[k.0 as usize].mid;
            // (a corridor with a failure still due at this instant is left to
            // that event's operation)
            let due = self.owned_corr[k.0 as usize].iter().any(|p| {
                self.certs
                    .get(p)
                    .is_some_and(|s| self.due_now(p, s.key, now))
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
        if let Some(kind) = self.broken.take() {
            let (around, triples) = self.broken_around.take().unwrap_or_default();
            if kind == "refine_rebuild" && self.repair_refined(world, &around, &triples, now) {
                for p in &triples {
                    self.reschedule_idle(world, p, now);
                }
            } else if kind == "degenerate_rebuild"
                && !around.is_empty()
                && self.unbuildable.as_ref() != Some(now)
                && self.repair_around(world, (&around, false), triples[0], now)?
            {
                // (the local operations failed on `triples[0]` before the
                // response, the others were deferred after it; the region
                // around its bodies is whole again, and every one of them
                // that still exists is scheduled again)
                for p in &triples {
                    if self.certs.get(p).is_some_and(|s| s.key.is_none()) {
                        self.reschedule(world, p, now);
                    }
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
    fn straight_now(
        &self,
        world: &Geo,
        ps: &[[Att; 3]],
        undecided: &[bool],
        now: &Time,
    ) -> BTreeSet<CorrId> {
        let mut out = BTreeSet::new();
        for (p, &undecided) in ps.iter().zip(undecided) {
            let Some(s) = self.certs.get(p) else {
                continue;
            };
            if s.cert.kind == super::certs::CertKind::Order || !undecided {
                continue;
            }
            let lp = |a: Att| world.point(a);
            let turn = orient_poly(&lp(p[0]), &lp(p[1]), &lp(p[2]));
            if turn.is_zero() || turn.sign_at(now) != Sign::Zero {
                continue;
            }
            for o in &s.owners {
                if let Owner::Corr(k) = *o {
                    if self.kss.corrs[k.0 as usize].b != Obj::Omega {
                        out.insert(k);
                    }
                }
            }
        }
        out
    }

    /// The corridors among the owners of certificates `ps` (and the
    /// corridors at their ends) in which two
    /// points of two bodies are at one place at `now`: the two ends of a
    /// bridge (an end or the middle one), two points of a junction (a chain
    /// vertex resting on a bridge's end), or two points of a hull turn.
    /// While they rest, a turn through both is zero and has no certificate;
    /// a motion change that parts them must give the corridor its
    /// certificates anew.
    fn resting_now(&self, world: &Geo, ps: &[[Att; 3]], now: &Time) -> BTreeSet<CorrId> {
        // (two points of two bodies whose boxes are apart at `now` do not
        // meet: the boxes first, each computed once)
        let ti = now.interval();
        let boxes: std::cell::RefCell<FastMap<BodyId, Option<[Interval; 2]>>> = Default::default();
        let seen = |b: BodyId| {
            *boxes
                .borrow_mut()
                .entry(b)
                .or_insert_with(|| world.seen_box(b, ti))
        };
        let apart = |x: Obj, y: Obj| match (x, y) {
            (Obj::Body(p), Obj::Body(q)) if p != q => match (seen(p), seen(q)) {
                (Some(e), Some(f)) => !e[0].overlaps(&f[0]) || !e[1].overlaps(&f[1]),
                _ => false,
            },
            _ => false,
        };
        let meet =
            |x: Att, y: Att| !apart(x.obj, y.obj) && super::faces::coincide_at(world, x, y, now);
        let owners: BTreeSet<CorrId> = ps
            .iter()
            .filter_map(|p| self.certs.get(p))
            .flat_map(|s| s.owners.iter())
            .filter_map(|o| match *o {
                Owner::Corr(k) => Some(k),
                Owner::Tri(_) => None,
            })
            .collect();
        // (and the corridors at their ends: a turn through two resting
        // points has no certificate that would name them, and an empty
        // corridor has none at all)
        let mut cands = owners.clone();
        for k in owners {
            let c = &self.kss.corrs[k.0 as usize];
            for tri in [c.s.0, c.t.0] {
                cands.extend(self.kss.tris[tri.0 as usize].corr);
            }
        }
        let mut out = BTreeSet::new();
        for k in cands {
            let c = &self.kss.corrs[k.0 as usize];
            if apart(c.a, c.b) {
                continue;
            }
            let triples: Vec<[Att; 3]> = if c.b == Obj::Omega {
                self.kss
                    .hull_turns(world, k)
                    .into_iter()
                    .map(|(p, _)| p)
                    .collect()
            } else {
                let (a_s, b_s, a_t, b_t) = self.kss.ends(k);
                let mut v = vec![[a_s, b_s, b_s], [a_t, b_t, b_t]];
                if let Some((i, j)) = c.mid {
                    let (x, y) = (world.cw(a_s, i), world.cw(b_t, j));
                    v.push([x, y, y]);
                }
                v.extend(
                    self.kss
                        .junctions(world, k)
                        .into_iter()
                        .map(|j| [j.prev, j.v, j.next]),
                );
                v
            };
            let rests = triples
                .iter()
                .any(|t| meet(t[0], t[1]) || meet(t[1], t[2]) || meet(t[0], t[2]));
            #[cfg(feature = "trace")]
            if std::env::var_os("KSS_DUMP").is_some() {
                eprintln!("resting_now candidate {k:?}: {triples:?} -> {rests}");
            }
            if rests {
                out.insert(k);
            }
        }
        out
    }

    /// The certificates on body `b` that name one of `ids`.
    fn certs_naming(&self, b: BodyId, ids: &[Att]) -> Vec<[Att; 3]> {
        self.by_body
            .get(&b)
            .into_iter()
            .flatten()
            .filter(|p| p.iter().any(|x| ids.contains(x)))
            .copied()
            .collect()
    }

    /// The owners of the certificates on body `b` that name one of `ids`.
    fn owners_naming(&self, b: BodyId, ids: &[Att]) -> BTreeSet<Owner> {
        self.certs_naming(b, ids)
            .iter()
            .filter_map(|p| self.certs.get(p))
            .flat_map(|s| s.owners.iter().copied())
            .collect()
    }

    /// After vertices `ids` of body `b` changed place (a pop or a merge):
    /// recompute the certificates of `owners`, then schedule again every
    /// certificate still naming one of `ids` (its points moved).
    fn refresh_moved(
        &mut self,
        geo: &Geo,
        (b, ids): (BodyId, &[Att]),
        owners: BTreeSet<Owner>,
        t: &Time,
    ) -> Result<(), String> {
        for o in owners {
            self.refresh(geo, o, t)?;
        }
        for p in &self.certs_naming(b, ids) {
            self.reschedule(geo, p, t);
        }
        Ok(())
    }

    /// Pop approximation vertex `a` (in `shapes`) at `t` and update the
    /// structure in place ([`Kss::pop_vertex`]): the touched corridors are
    /// normalized and their owners' certificates, and every certificate on a
    /// vertex of the body that moved, recomputed. Returns whether the
    /// approximation changed and whether the structure followed (if not, it
    /// must be rebuilt on the new approximations).
    pub fn pop_local(
        &mut self,
        world: &crate::world::World,
        shapes: &mut super::geo::Shapes,
        a: Att,
        t: &Time,
    ) -> Result<(bool, bool), String> {
        let (corrs, tris, ids) = match self.kss.pop_vertex(world, shapes, a, t) {
            super::pop::PopResult::NotPopped => return Ok((false, true)),
            super::pop::PopResult::Failed => {
                trace!("pop of {a:?} at {} not local: rebuilding", t.to_f64());
                return Ok((true, false));
            }
            super::pop::PopResult::Local { corrs, tris, ids } => (corrs, tris, ids),
        };
        let geo = Geo {
            world,
            shapes: &*shapes,
        };
        let Obj::Body(b) = a.obj else {
            unreachable!("a popped vertex is on a body")
        };
        // every certificate on a changed vertex, and its owners
        let mut owners = self.owners_naming(b, &ids);
        owners.extend(corrs.iter().map(|&k| Owner::Corr(k)));
        owners.extend(tris.iter().map(|&t| Owner::Tri(t)));
        for o in &owners {
            if let Owner::Corr(k) = *o {
                super::counters::bump(super::counters::Counter::PopOwners);
                if let Err(_e) = self.kss.normalize(&geo, k, t, None) {
                    trace!("pop of {a:?}: {_e}; rebuilding");
                    return Ok((true, false));
                }
            }
        }
        self.refresh_moved(&geo, (b, &ids), owners, t)?;
        *self.counts.entry("local_pop").or_default() += 1;
        Ok((true, true))
    }

    /// Remove body `b` (already dead in `world`; every other body seen as
    /// the structure sees it) at `now` in place ([`Kss::removal_plan`],
    /// [`Kss::apply_removal`]): the slots are renumbered, the new corridors
    /// normalized, and their certificates and the new triangles' scheduled
    /// (those that the triangles and corridors that went also had are taken
    /// over, the others dropped). Returns `false` when the removal cannot
    /// be done locally (the caller rebuilds; the structure may then be half
    /// changed), in particular when a new certificate fails at once that
    /// is neither taken over nor held by normalization.
    pub fn remove_body(&mut self, world: &Geo, b: BodyId, now: &Time) -> Result<bool, String> {
        if self.broken.is_some() {
            return Ok(false);
        }
        if world.bodies().iter().filter(|x| x.alive).count() < 2 {
            // nothing stays to separate: the empty structure
            self.replace_with(Kinetic::default());
            *self.counts.entry("local_remove").or_default() += 1;
            return Ok(true);
        }
        let plan = match self.kss.removal_plan(world, b, now) {
            Ok(plan) => plan,
            Err(_e) => {
                trace!("removal of {b:?} at {} not local: {_e}", now.to_f64());
                return Ok(false);
            }
        };
        if !self.splice(world, plan, b, true, now)? {
            return Ok(false);
        }
        *self.counts.entry("local_remove").or_default() += 1;
        Ok(true)
    }

    /// Repair the structure for just after `now` by retriangulating the
    /// region around `bodies` together (then, with `singles`, around each
    /// alone; [`Kss::retriangulation_plan`]), the first for which a plan
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
    ) -> Result<bool, String> {
        if self.broken.is_some() {
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
        if bodies.is_empty() || self.broken.is_some() {
            return false;
        }
        // the certificates that failed stay out of the queue until their
        // owners are rescheduled (the repair takes them over or drops them)
        let handled = triples.first().map(|&p| super::certs::rotate_to_min(p));
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
        let on_bodies: BTreeSet<[Att; 3]> = bodies
            .iter()
            .filter_map(|b| self.by_body.get(b))
            .flatten()
            .copied()
            .collect();
        for p in &on_bodies {
            self.reschedule(world, p, now);
        }
        true
    }

    fn repair_with(
        &mut self,
        world: &Geo,
        (bodies, singles): (&[BodyId], bool),
        now: &Time,
    ) -> Result<bool, String> {
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
                if !self.splice(world, plan, b, false, now)? {
                    return Ok(false);
                }
                *self.counts.entry("local_repair").or_default() += 1;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Insert body `b` into the structure at `now`: `b` is alive in `world`
    /// (seen through its shapes), touches no other body, and is not in the
    /// structure yet. The region around the body nearest to it (its
    /// partition triangles and corridors) is triangulated again with `b`
    /// in it ([`Kss::insertion_plan`]), for an instant just after `now` at
    /// which the new partition triangles hold from `now` on and the new
    /// corridors decompose; where `b` does not lie in that region (or
    /// crosses its boundary), the set grows by the neighbours of its
    /// bodies, a few rounds at most. Counted as `local_insert`. The cost is
    /// the region's size (and a scan of the bodies for the nearest and of
    /// the structure for neighbours), not a new triangulation of
    /// everything. `false` when no region works: the structure is then
    /// unchanged, or half changed if the splice failed (the caller
    /// rebuilds it either way).
    pub fn insert_body(&mut self, world: &Geo, b: BodyId, now: &Time) -> Result<bool, String> {
        if self.broken.is_some() || self.kss.tris.is_empty() {
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
                if !self.splice(world, plan, b, false, now)? {
                    return Ok(false);
                }
                *self.counts.entry("local_insert").or_default() += 1;
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
    /// ones (for the removal of body `b` when `removed`, else for a
    /// retriangulation around it): the slots are renumbered, the new
    /// corridors normalized, and their certificates and the new triangles'
    /// scheduled, taking over those they share with what went. `false` when
    /// the result does not hold just after `now`.
    fn splice(
        &mut self,
        world: &Geo,
        plan: super::remove::RemovalPlan,
        b: BodyId,
        removed: bool,
        now: &Time,
    ) -> Result<bool, String> {
        // the certificates of what goes lose their owners but stay for the
        // moment: the new triangles and corridors take over the ones they
        // share (most of a merged corridor's junctions) without computing
        // their failure times again
        let mut orphans: Vec<[Att; 3]> = Vec::new();
        let dead = (plan.dead_tris.iter().map(|&t| Owner::Tri(t)))
            .chain(plan.dead_corrs.iter().map(|&k| Owner::Corr(k)));
        for o in dead {
            let mine = match o {
                Owner::Tri(t) => std::mem::take(&mut self.owned_tri[t.0 as usize]),
                Owner::Corr(k) => std::mem::take(&mut self.owned_corr[k.0 as usize]),
            };
            for p in mine {
                if let Some(s) = self.certs.get_mut(&p) {
                    s.owners.retain(|&x| x != o);
                    if s.owners.is_empty() {
                        orphans.push(p);
                    }
                }
            }
        }
        let spliced = self.kss.apply_removal(plan);
        for &(src, dst) in &spliced.moved_tris {
            let mine = std::mem::take(&mut self.owned_tri[src.0 as usize]);
            self.rename(&mine, Owner::Tri(src), Owner::Tri(dst));
            self.owned_tri[dst.0 as usize] = mine;
        }
        self.owned_tri.resize(self.kss.tris.len(), Vec::new());
        for &(src, dst) in &spliced.moved_corrs {
            let mine = std::mem::take(&mut self.owned_corr[src.0 as usize]);
            self.rename(&mine, Owner::Corr(src), Owner::Corr(dst));
            self.owned_corr[dst.0 as usize] = mine;
        }
        self.owned_corr.resize(self.kss.corrs.len(), Vec::new());
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
        for p in orphans {
            match self.certs.get(&p) {
                Some(s) if s.owners.is_empty() => self.drop_cert(&p),
                Some(_) => {
                    adopted.insert(p);
                }
                None => {}
            }
        }
        if removed {
            if self.by_body.get(&b).is_some_and(|s| !s.is_empty()) {
                trace!("removal of {b:?}: certificates on it stay");
                return Ok(false);
            }
            self.by_body.remove(&b);
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
            .map(|&p| super::certs::rotate_to_min(p))
            .collect();
        let fresh: Vec<[Att; 3]> = spliced
            .tris
            .iter()
            .flat_map(|t| &self.owned_tri[t.0 as usize])
            .chain(
                spliced
                    .corrs
                    .iter()
                    .flat_map(|k| &self.owned_corr[k.0 as usize]),
            )
            .copied()
            .collect();
        for p in &fresh {
            let Some(s) = self.certs.get(p) else {
                return Ok(false);
            };
            if adopted.contains(p) || held.contains(p) {
                continue;
            }
            if self.due_now(p, s.key, now)
                && due_is_failing(
                    world,
                    &s.cert,
                    (s.fp.as_deref(), due_time(&self.queue, s.key, &s.popped)),
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

    /// Rename owner `from` to `to` on certificates `ps`.
    fn rename(&mut self, ps: &[[Att; 3]], from: Owner, to: Owner) {
        for p in ps {
            if let Some(s) = self.certs.get_mut(p) {
                for x in &mut s.owners {
                    if *x == from {
                        *x = to;
                    }
                }
            }
        }
    }

    /// Schedule the certificate on `p` again if it was popped from the queue
    /// and not handled (a refinement replaced its failure).
    pub fn reschedule_idle(&mut self, world: &Geo, p: &[Att; 3], now: &Time) {
        let p = super::certs::rotate_to_min(*p);
        if self.certs.get(&p).is_some_and(|s| s.key.is_none()) {
            self.reschedule(world, &p, now);
        }
    }

    /// Give up on the local operations at this instant (they cycle) and
    /// rebuild once the collision response has been applied.
    pub fn give_up_instant(&mut self) {
        self.broken = Some("degenerate_rebuild");
        self.broken_around = None;
    }

    /// The structure is rebuilt (counted as `kind`) once the collision
    /// response at this instant has been applied; for a refinement of the
    /// approximations of `around` alone (and no other event deferred
    /// meanwhile), only the region around those bodies is triangulated
    /// again ([`Kinetic::repair_refined`]) where that works, and the failed
    /// `triples` are scheduled again.
    pub fn rebuild_after_response(
        &mut self,
        kind: &'static str,
        (around, triples): (&[BodyId], &[[Att; 3]]),
    ) {
        if self.broken.is_none() {
            self.broken = Some(kind);
            self.broken_around = Some((around.to_vec(), triples.to_vec()));
        } else {
            self.broken_around = None;
        }
    }

    /// The pairs that touched without a collision since the last call (see
    /// the field `settled`).
    pub fn take_settled(&mut self) -> Vec<(BodyId, BodyId)> {
        std::mem::take(&mut self.settled)
    }

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
    ) -> Result<Step, String> {
        let head = self
            .queue
            .peek()
            .map(|(key, t, tie, &p)| (key, t.clone(), tie, p));
        let use_later = match (&self.later, &head) {
            (None, _) => false,
            (Some(_), None) => true,
            (Some((lt, _)), Some((_, t, tie, _))) => t > lt || *tie > 0,
        };
        if use_later {
            let (t, ps) = self.later.as_mut().expect("checked");
            let t = t.clone();
            let p = ps.pop().expect("non-empty");
            if ps.is_empty() {
                self.later = None;
            }
            return self.handle_or_rebuild(world, p, t, contacts, collides);
        }
        let Some((key, t, tie, p)) = head else {
            return Ok(Step::Idle);
        };
        if &t > limit {
            return Ok(Step::Idle);
        }
        self.queue.pop();
        let s = self
            .certs
            .get_mut(&p)
            .ok_or_else(|| format!("queued certificate {p:?} unknown"))?;
        if s.key != Some(key) {
            return Err(format!("certificate {p:?} scheduled twice"));
        }
        s.key = None;
        s.popped = Some(Box::new(t.clone()));
        trace!(
            "pop t={} tie {tie} {:?} {:?}",
            t.to_f64(),
            s.cert.p,
            s.owners
        );
        if tie == 0 {
            let cert = s.cert;
            let (pairs, apart) = match classify(world, &cert, &t) {
                Failure::Contact { a, b, third } => {
                    let owners = s.owners.clone();
                    let apart = super::events::real_touch_excluded(world, &p, &t);
                    let pairs =
                        contact_pairs(world, &self.kss, &owners, &p, &t, (a, b, third), apart);
                    (pairs, apart)
                }
                Failure::Between { .. } => {
                    (nearby_contact(world, &p, &t).into_iter().collect(), None)
                }
            };
            if let Some(step) = self.touch(world, p, &t, pairs, apart, collides) {
                return Ok(step);
            }
            // not a contact, or a touch that is not a collision: a
            // structural failure
            match &mut self.later {
                Some((_, ps)) => ps.push(p),
                None => self.later = Some((t.clone(), vec![p])),
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
    /// ([`super::events::real_touch_excluded`]): it gets no contact test
    /// (that costs O(n) and would make every pop as dear as the polygons
    /// are large).
    fn touch(
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
            self.waiting.push(p);
            return Some(Step::Contact(t.clone(), colliding));
        }
        p.iter()
            .any(|&a| !world.is_real(a))
            .then(|| Step::Refine(t.clone(), p))
    }

    /// [`Kinetic::handle`], falling back to [`Kinetic::rebuild_after`] when
    /// the local operations cannot resolve a degenerate instant (and no
    /// contact is pending at it).
    fn handle_or_rebuild(
        &mut self,
        world: &Geo,
        p: [Att; 3],
        t: Time,
        contacts: &[(BodyId, BodyId)],
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Result<Step, String> {
        if self.broken.is_some() {
            // this event waits for the rebuild. After a refinement a local
            // repair would miss it; after failed local operations it is
            // scheduled again once the region around them is repaired (and
            // handled then, at this instant if it still fails at it)
            match (self.broken, self.broken_around.as_mut()) {
                (Some("degenerate_rebuild"), Some((_, triples))) => triples.push(p),
                _ => self.broken_around = None,
            }
            return Ok(Step::Deferred(t));
        }
        match self.handle(world, p, t.clone(), contacts, collides) {
            Err(e) if contacts.is_empty() && self.waiting.is_empty() => {
                trace!("local operations failed at {}: {e}; repairing", t.to_f64());
                #[cfg(feature = "trace")]
                self.kss.trace_dump();
                // (with those of the certificate whose operation failed: a
                // triangle handled first for `p`'s corridor may have a
                // polygon that `p` does not name)
                let mut bodies = bodies_of(&p);
                if self.recent_at.as_ref() == Some(&t) {
                    if let Some(q) = self.recent.back() {
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
                    if self.certs.get(&p).is_some_and(|s| s.key.is_none()) {
                        self.reschedule(world, &p, &t);
                    }
                    return Ok(Step::Internal(t));
                }
                trace!("no local repair at {}: rebuilding", t.to_f64());
                self.rebuild_after(world, &t, "degenerate_rebuild")
                    .map_err(|r| format!("{e}; then {r}"))?;
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
                self.broken = Some("degenerate_rebuild");
                self.broken_around = Some((bodies_of(&p), vec![p]));
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
        self.recent_at.as_ref() == Some(now)
            && self
                .recent
                .back()
                .is_some_and(|p| self.recent.iter().filter(|&q| q == p).count() >= 4)
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
        self.recent.clear();
        true
    }

    /// The local operations cycle at `now` ([`Kinetic::cycling`], or the
    /// driver's guard: far more operations at one instant than the
    /// structure has corridors): repair
    /// the region around the polygons of the last certificates handled, as
    /// at a settled contact ([`Kinetic::repair_around`]), so that the
    /// structure is the one for just after `now`. `false` when there is
    /// none (the caller rebuilds the whole structure).
    pub fn repair_cycle(&mut self, world: &Geo, now: &Time) -> Result<bool, String> {
        let Some(&last) = self.recent.back() else {
            return Ok(false);
        };
        trace!("repair_cycle at {}", now.to_f64());
        let mut bodies: Vec<BodyId> = self.recent.iter().flat_map(bodies_of).collect();
        bodies.sort();
        bodies.dedup();
        if !self.repair_around(world, (&bodies, false), last, now)? {
            return Ok(false);
        }
        for p in std::mem::take(&mut self.recent) {
            if self.certs.get(&p).is_some_and(|s| s.key.is_none()) {
                self.reschedule(world, &p, now);
            }
        }
        Ok(true)
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
        kind: &'static str,
    ) -> Result<(), String> {
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
                    *self.counts.entry(kind).or_default() += 1;
                    return Ok(());
                }
            }
            hi = at_t;
        }
        self.unbuildable = Some(now.clone());
        Err(format!("no rebuild just after t = {now} found"))
    }

    /// Where the searches for an instant just after `now` (a rebuild, a
    /// local repair) start, halving towards `now`: the old structure's next
    /// failure after `now` gives the scale of the gaps between events, so
    /// the search starts there rather than far away, where polygons have
    /// moved into each other and every attempt fails (each a whole
    /// triangulation); at most one time unit later. (The f64 only bounds the
    /// search from above: any instant after `now` would do.)
    fn search_start(&self, now: &Time) -> Result<Time, String> {
        let f = now.to_f64();
        let mut hi = Time::from_f64(f + f.abs().max(1.0)).ok_or("time out of range")?;
        if let Some(next) = self.queue_times_after(now) {
            if next < hi {
                hi = next;
            }
        }
        Ok(hi)
    }

    /// The earliest queued failure time strictly after `now` (O(queue)).
    fn queue_times_after(&self, now: &Time) -> Option<Time> {
        // the earliest queued time, unless failures of this very instant
        // are still queued
        if let Some((_, t, _, _)) = self.queue.peek() {
            if t > now {
                return Some(t.clone());
            }
        }
        self.queue
            .iter()
            .map(|(_, t, _, _)| t)
            .filter(|t| *t > now)
            .min()
            .cloned()
    }

    /// Handle the failure of the (popped) certificate on `p` at `t`.
    fn handle(
        &mut self,
        world: &Geo,
        p: [Att; 3],
        t: Time,
        contacts: &[(BodyId, BodyId)],
        collides: &dyn Fn(BodyId, BodyId, &Time) -> bool,
    ) -> Result<Step, String> {
        let Some(s) = self.certs.get(&p) else {
            return Ok(Step::Deferred(t)); // replaced by an earlier operation
        };
        if s.key.is_some() {
            return Ok(Step::Deferred(t)); // rescheduled meanwhile
        }
        let (cert, fp, popped) = (s.cert, s.fp.as_deref().copied(), s.popped.clone());
        let owners = s.owners.clone();
        if self.recent_at.as_ref() != Some(&t) {
            self.recent.clear();
            self.recent_at = Some(t.clone());
        }
        if self.recent.len() == RECENT {
            self.recent.pop_front();
        }
        self.recent.push_back(p);
        if !due_is_failing(world, &cert, (fp.as_ref(), popped.as_deref()), &t) {
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
        let mut failure = classify(world, &cert, &t);
        if let Failure::Contact { a, b, third } = failure {
            let apart = super::events::real_touch_excluded(world, &p, &t);
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
                if !self.settled.contains(&pair) {
                    self.settled.push(pair);
                }
            }
            match settled_between(world, &cert, &t) {
                Some(f) => failure = f,
                None => {
                    trace!("settled contact at {}: repairing", t.to_f64());
                    if contacts.is_empty() && self.waiting.is_empty() {
                        let bodies: Vec<BodyId> =
                            [Some(a), Some(b), third].into_iter().flatten().collect();
                        if self.repair_around(world, (&bodies, true), p, &t)? {
                            if self.certs.get(&p).is_some_and(|s| s.key.is_none()) {
                                self.reschedule(world, &p, &t);
                            }
                            return Ok(Step::Internal(t));
                        }
                        trace!("no local repair at {}: rebuilding", t.to_f64());
                        self.rebuild_after(world, &t, "degenerate_rebuild")?;
                        return Ok(Step::Internal(t));
                    }
                    // contacts at this instant: set aside until the
                    // response has set the motions, then handled again
                    // (repaired then, if it still fails)
                    self.waiting.push(p);
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
                    self.waiting.push(p);
                    return Ok(Step::Deferred(t));
                }
                let owner = *owners.first().ok_or("certificate without owner")?;
                // a partition triangle at an end of the corridor that
                // collapses at this instant goes first: the corridor's
                // operations assume its end triangles, and two of its
                // junctions can otherwise hand an edge back and forth
                // across the degenerate triangle for ever
                let moved_tri = match owner {
                    Owner::Corr(k) if self.kss.corrs[k.0 as usize].b != Obj::Omega => {
                        let c = &self.kss.corrs[k.0 as usize];
                        match self.kss.junction_plan(world, k, p, middle) {
                            Ok((super::local::EdgeRef::EndS, _, _, true)) => Some(c.s.0),
                            Ok((super::local::EdgeRef::EndT, _, _, true)) => Some(c.t.0),
                            _ => None,
                        }
                    }
                    _ => None,
                };
                // (only the triangle whose corner the operation would move)
                let collapsing = moved_tri.and_then(|tri| {
                    let q = self.kss.triangle_certs(tri).first().map(|c| c.p)?;
                    let s = self.certs.get(&q)?;
                    let due = s
                        .key
                        .is_some_and(|key| self.queue.get(key).is_some_and(|(tq, _)| *tq == t));
                    let at = due_time(&self.queue, s.key, &s.popped);
                    (q != p && due && due_is_failing(world, &s.cert, (s.fp.as_deref(), at), &t))
                        .then_some((tri, q))
                });
                if let Some((_tri, q)) = collapsing {
                    trace!("triangle {} collapses first", _tri.0);
                    if let Some(s) = self.certs.get_mut(&q) {
                        if let Some(key) = s.key.take() {
                            self.queue.cancel(key);
                            s.popped = Some(Box::new(t.clone()));
                        }
                    }
                    self.reschedule(world, &p, &t);
                    return self.handle(world, q, t, contacts, collides);
                }
                let out = self.kss.process(world, owner, p, middle, &t)?;
                self.handling = Some(p);
                self.kss.handling = Some(p);
                let applied = self.apply(world, out, &t);
                self.handling = None;
                self.kss.handling = None;
                applied?;
                // a certificate that outlived the operation unchanged fails
                // again if it is still wrong just after t
                if self.certs.get(&p).is_some_and(|s| s.key.is_none()) {
                    self.reschedule(world, &p, &t);
                }
                Ok(Step::Internal(t))
            }
        }
    }

    fn apply(&mut self, world: &Geo, out: Outcome, t: &Time) -> Result<(), String> {
        *self.counts.entry(out.kind).or_default() += 1;
        let mut corrs = out.corrs;
        corrs.sort();
        corrs.dedup();
        for &k in &corrs {
            if self.kss.normalize(world, k, t, None)? > 0 {
                *self.counts.entry("repair").or_default() += 1;
            }
        }
        for tri in out.tris {
            self.refresh(world, Owner::Tri(tri), t)?;
        }
        for &k in &corrs {
            self.refresh(world, Owner::Corr(k), t)?;
        }
        self.last_touched = corrs;
        Ok(())
    }

    /// Coarsen the approximations (in `shapes`) where the last operation
    /// touched the structure: one merge candidate per touched corridor
    /// ([`Kss::coarsen_one`]); the merged corridor is normalized and the
    /// certificates on the moved vertex recomputed. Returns the number of
    /// merges.
    pub fn coarsen(
        &mut self,
        world: &crate::world::World,
        shapes: &mut super::geo::Shapes,
        t: &Time,
    ) -> Result<u64, String> {
        let mut merges = 0;
        for k in std::mem::take(&mut self.last_touched) {
            self.tick = self.tick.wrapping_add(1);
            let (by_body, certs, queue) = (&self.by_body, &self.certs, &self.queue);
            let busy = |kv: Att, qv: Att| {
                let Obj::Body(b) = kv.obj else {
                    return true;
                };
                by_body.get(&b).is_some_and(|set| {
                    set.iter().any(|p| {
                        p.contains(&kv)
                            || (p.contains(&qv)
                                && certs.get(p).is_none_or(|s| {
                                    s.key.is_none_or(|key| {
                                        queue.get(key).is_some_and(|(tq, _)| tq == t)
                                    })
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
            let mut owners = self.owners_naming(b, &[q]);
            owners.insert(Owner::Corr(k));
            self.refresh_moved(&geo, (b, &[q]), owners, t)?;
        }
        *self.counts.entry("merge").or_default() += merges;
        Ok(merges)
    }

    /// The earliest scheduled failure, if any.
    pub fn next_time(&self) -> Option<&Time> {
        match &self.later {
            Some((t, _)) => Some(t),
            None => self.queue.peek().map(|(_, t, _, _)| t),
        }
    }

    /// Certificates that can fail (scheduled) now, and at most so far.
    pub fn active(&self) -> (usize, usize) {
        (self.queue.len(), self.max_active)
    }

    /// All certificates, scheduled or not.
    pub fn certificate_count(&self) -> usize {
        self.certs.len()
    }

    /// Check every invariant at the rational instant `at`, strictly after the
    /// last event `now` and before the next one: topology, every corridor face
    /// a pseudo-triangle, every certificate holding, and the scheduled set
    /// equal to a from-scratch recomputation with the right failure times.
    pub fn audit(&self, world: &Geo, now: &Time, at: &Rational) -> Result<(), String> {
        let at_t = Time::from_rational(at.clone());
        self.kss.check_topology(world)?;
        self.kss.check_faces(world, &at_t)?;
        self.kss.check_bridges(world, at)?;
        let fresh = self.kss.certificates(world, &at_t)?;
        if fresh.len() != self.certs.len() {
            let have: BTreeSet<_> = self.certs.keys().collect();
            let want: BTreeSet<_> = fresh.iter().map(|c| &c.p).collect();
            return Err(format!(
                "{} certificates kept, {} expected (extra {:?}, missing {:?})",
                self.certs.len(),
                fresh.len(),
                have.difference(&want).take(3).collect::<Vec<_>>(),
                want.difference(&have).take(3).collect::<Vec<_>>(),
            ));
        }
        let mut scheduled = 0;
        for c in &fresh {
            if let Some(&a) = c.p.iter().find(|&&a| !world.enclosure_cache_agrees(a)) {
                return Err(format!(
                    "the cached enclosure of {a:?} (in certificate {:?}) is not the fresh one",
                    c.p
                ));
            }
            let s = self
                .certs
                .get(&c.p)
                .ok_or_else(|| format!("certificate {:?} missing", c.p))?;
            if s.cert.sign != c.sign {
                return Err(format!("certificate {:?} has the wrong sign", c.p));
            }
            let p = cert_poly(world, c);
            match p.sign_at(&at_t) {
                Sign::Positive => {}
                Sign::Zero if resting_flat(world, c, &p) => {}
                _ if p.sign_before(&at_t) == Sign::Positive
                    && p.sign_after(&at_t) == Sign::Positive => {}
                s => return Err(format!("certificate {:?} is {s:?} at {at}", c.p)),
            }
            let want = p.first_failure_after(now);
            let got = s
                .key
                .and_then(|k| self.queue.get(k))
                .map(|(t, _)| t.clone());
            if want != got {
                return Err(format!(
                    "certificate {:?} scheduled at {got:?}, fails at {want:?}",
                    c.p
                ));
            }
            scheduled += usize::from(got.is_some());
        }
        if scheduled != self.queue.len() {
            return Err(format!(
                "{} queued events for {scheduled} scheduled certificates",
                self.queue.len()
            ));
        }
        Ok(())
    }

    // ----- read-only views (for pictures; no effect on the simulation) -----

    /// Every certificate scheduled in the event queue with its failure time,
    /// in no particular order (certificates that never fail on the current
    /// motions, or that wait for a collision response, are not listed).
    pub fn scheduled(&self) -> impl Iterator<Item = (&Time, &Cert)> + '_ {
        self.queue
            .iter()
            .filter_map(|(_, t, _, p)| self.certs.get(p).map(|s| (t, &s.cert)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate_small, Family};
    use crate::structure::geo::Geo;
    use crate::world::World;

    #[test]
    fn scheduled_certificates_audit_clean_before_the_first_event() {
        let mut audited = 0;
        for family in Family::ALL {
            for seed in 0..40 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let world = Geo::plain(&world);
                let k = Kinetic::new(&world, &Rational::zero()).unwrap();
                let now = Time::zero();
                let Some(next) = k.next_time().cloned() else {
                    continue;
                };
                if next == now {
                    continue; // a degenerate start: the first event is at once
                }
                let at = now.rational_between(&next);
                k.audit(&world, &now, &at)
                    .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", family.name()));
                audited += 1;
            }
        }
        assert!(audited > 150, "{audited}");
    }

    /// Calls `f` with a view of the scene of each family and seed below
    /// `seeds`, plain and with every polygon approximated, and the vertices
    /// (real or approximation) of its first `bodies` bodies.
    fn each_view(seeds: u64, bodies: usize, mut f: impl FnMut(&Geo, &[Att])) {
        for family in Family::ALL {
            for seed in 0..seeds {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                for hierarchical in [false, true] {
                    let mut shapes = crate::structure::geo::Shapes::default();
                    if hierarchical {
                        shapes = crate::structure::refine::coarsest_shapes(&world, 0);
                    }
                    let geo = Geo {
                        world: &world,
                        shapes: &shapes,
                    };
                    let pts: Vec<Att> = (0..world.len().min(bodies))
                        .flat_map(|b| {
                            let b = crate::world::BodyId(b as u32);
                            geo.ids(b).into_iter().map(move |v| Att::vertex(b, v))
                        })
                        .collect();
                    f(&geo, &pts);
                }
            }
        }
    }

    /// The f64 filter of the orientation and order tests never contradicts
    /// the exact polynomials: on every triple of (real and approximation)
    /// vertices of the degenerate families, where collinear points and
    /// contacts at dyadic instants abound, at integer, dyadic and
    /// non-dyadic instants.
    #[test]
    fn filtered_turns_agree_with_the_exact_ones() {
        let (mut decided, mut undecided) = (0u64, 0u64);
        each_view(6, 3, |geo, pts| {
            for t in ["0", "1", "2", "0.375", "1/3", "7/5"] {
                let t = match t.split_once('/') {
                    Some((p, q)) => Time::from_rational(Rational::new(
                        p.parse::<i64>().unwrap().into(),
                        q.parse::<i64>().unwrap().into(),
                    )),
                    None => Time::from_f64(t.parse().unwrap()).unwrap(),
                };
                let lp = |a: Att| geo.point(a);
                for (i, &u) in pts.iter().enumerate() {
                    for &v in &pts[i + 1..] {
                        for &w in pts.iter().step_by(3) {
                            let exact =
                                crate::motion::orient_poly(&lp(u), &lp(v), &lp(w)).sign_at(&t);
                            match geo.orient_filtered(u, v, w, t.interval()) {
                                Some(f) => {
                                    assert_eq!(f, exact, "{u:?} {v:?} {w:?} at {t}");
                                    decided += 1;
                                }
                                None => undecided += 1,
                            }
                            let dot = crate::motion::dot_poly(&lp(v), &lp(u), &lp(w)).sign_at(&t);
                            if let Some(f) = geo.dot_filtered(u, v, w, t.interval()) {
                                assert_eq!(f, dot, "{u:?} {v:?} {w:?} at {t}");
                            }
                        }
                    }
                }
            }
        });
        assert!(decided > 1000 && undecided > 10, "{decided} {undecided}");
    }

    /// The certificate filter's coefficient enclosures ([`cert_enclosure`],
    /// midpoint–radius arithmetic) hold the exact coefficients of the
    /// certificate function (in real coordinates, a positive multiple of
    /// [`cert_poly`]), for every kind and sign, on triples of real and
    /// approximation vertices of every family, moving and fixed, and are
    /// exact zeros where a coefficient is exactly zero by construction.
    #[test]
    fn certificate_enclosures_hold_the_exact_coefficients() {
        use crate::structure::certs::CertKind;
        let mut checked = 0u64;
        each_view(4, 4, |geo, pts| {
            // the exact linear position (x0 + x1·t, y0 + y1·t)
            let lin = |a: Att| {
                let l = geo.point(a);
                let q = |n: &crate::num::Int| Rational::new(n.clone(), l.w.clone());
                [q(&l.x0), q(&l.x1), q(&l.y0), q(&l.y1)]
            };
            for (i, &u) in pts.iter().enumerate().step_by(2) {
                for &v in pts[i + 1..].iter().step_by(2) {
                    for &w in pts.iter().step_by(3) {
                        if u == w || v == w {
                            continue;
                        }
                        for (kind, sign) in [
                            (CertKind::Junction, Sign::Positive),
                            (CertKind::Triangle, Sign::Negative),
                            (CertKind::Order, Sign::Positive),
                        ] {
                            let c = Cert {
                                p: [u, v, w],
                                sign,
                                kind,
                            };
                            let Some(e) = cert_enclosure(geo, &c) else {
                                continue;
                            };
                            let order = kind == CertKind::Order;
                            let [p, q, r] = if order { [v, u, w] } else { [u, v, w] };
                            let [pp, pq, pr] = [lin(p), lin(q), lin(r)];
                            let d = |a: &[Rational; 4], b: &[Rational; 4]| {
                                [0, 1, 2, 3].map(|k| b[k].sub(&a[k]))
                            };
                            let [ux0, ux1, uy0, uy1] = d(&pp, &pq);
                            let [vx0, vx1, vy0, vy1] = d(&pp, &pr);
                            let m = |a: &Rational, b: &Rational| a.mul(b);
                            let mut exact = if order {
                                [
                                    m(&ux0, &vx0).add(&m(&uy0, &vy0)),
                                    m(&ux0, &vx1)
                                        .add(&m(&ux1, &vx0))
                                        .add(&m(&uy0, &vy1))
                                        .add(&m(&uy1, &vy0)),
                                    m(&ux1, &vx1).add(&m(&uy1, &vy1)),
                                ]
                            } else {
                                [
                                    m(&ux0, &vy0).sub(&m(&uy0, &vx0)),
                                    m(&ux0, &vy1)
                                        .add(&m(&ux1, &vy0))
                                        .sub(&m(&uy0, &vx1))
                                        .sub(&m(&uy1, &vx0)),
                                    m(&ux1, &vy1).sub(&m(&uy1, &vx1)),
                                ]
                            };
                            if order || sign == Sign::Negative {
                                exact = exact.map(|x| x.neg());
                            }
                            for (iv, x) in e.iter().zip(&exact) {
                                if iv.is_zero() {
                                    assert!(x.is_zero(), "{c:?}: {x} is no zero");
                                }
                                let lo = Rational::from_f64(iv.lo);
                                let hi = Rational::from_f64(iv.hi);
                                assert!(
                                    lo.is_none_or(|lo| lo <= *x) && hi.is_none_or(|hi| *x <= hi),
                                    "{c:?}: {iv:?} misses {x}"
                                );
                            }
                            checked += 1;
                        }
                    }
                }
            }
        });
        assert!(checked > 5000, "{checked}");
    }

    /// Pops done in place at the start, one approximation vertex after
    /// another, leave a structure that passes the full audit (certificates,
    /// tiling, pseudo-triangles) after every pop.
    #[test]
    fn pops_in_place_keep_the_structure_valid() {
        let (mut local, mut audited) = (0, 0);
        for family in [Family::Gas, Family::Flypast, Family::Far] {
            for seed in 0..12 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let mut shapes = crate::structure::refine::coarsest_shapes(&world, 0);
                crate::structure::refine::separate_all_at(&world, &mut shapes, &Rational::zero())
                    .unwrap();
                let geo = Geo {
                    world: &world,
                    shapes: &shapes,
                };
                let mut k = Kinetic::new(&geo, &Rational::zero()).unwrap();
                let now = Time::zero();
                for round in 0..24 {
                    // the `round`-th approximation vertex of all bodies
                    let geo = Geo {
                        world: &world,
                        shapes: &shapes,
                    };
                    let verts: Vec<Att> = (0..world.len())
                        .flat_map(|b| {
                            let b = BodyId(b as u32);
                            geo.ids(b).into_iter().map(move |v| Att::vertex(b, v))
                        })
                        .filter(|&a| !geo.is_real(a))
                        .collect();
                    if verts.is_empty() {
                        break;
                    }
                    let a = verts[(round * 7 + seed as usize) % verts.len()];
                    let (changed, followed) = k.pop_local(&world, &mut shapes, a, &now).unwrap();
                    assert!(changed, "{a:?} was not popped");
                    if !followed {
                        break; // the structure would be rebuilt
                    }
                    local += 1;
                    let geo = Geo {
                        world: &world,
                        shapes: &shapes,
                    };
                    let Some(next) = k.next_time().cloned() else {
                        continue;
                    };
                    if next == now {
                        break; // a failure at once: the engine would handle it
                    }
                    let at = now.rational_between(&next);
                    k.audit(&geo, &now, &at).unwrap_or_else(|e| {
                        panic!("{} seed {seed} pop {round} of {a:?}: {e}", family.name())
                    });
                    crate::structure::refine::check_apart(&world, &shapes, &at).unwrap();
                    audited += 1;
                }
            }
        }
        assert!(
            local > 100 && audited > 100,
            "{local} local pops, {audited} audited"
        );
    }
}
