//! The certificate book and the event queue: each certificate's failure
//! function and exact failure time (f64 filter first, exact roots on a
//! tie), its owners (the partition triangles and corridors it certifies),
//! and the scheduling, rescheduling and dropping of certificates as the
//! structure changes.

use std::collections::{BTreeMap, BTreeSet};

use crate::motion::{orient_poly, LinearPoint};
use crate::num::{
    filtered_failure, filtered_root, ExactTime, Filtered, Interval, Poly, Sign, Time,
};
use crate::sim::EventQueue;
use crate::structure::certs::Cert;
use crate::structure::geo::{Geo, PointRef};
use crate::structure::ops::Owner;
use crate::structure::StructureError;
use crate::structure::{Att, CorrId, Obj, TriId};
use crate::world::BodyId;

use super::instant::InstantState;
use super::step::each_body;
use super::Owned;
use super::{
    due_time, fingerprint, CertId, FarEntry, FarTime, Fingerprint, Kinetic, QKey, Scheduled,
};
use crate::structure::local::MAX_CERTS;

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
pub(super) fn cert_poly_of(
    kind: crate::structure::certs::CertKind,
    sign: Sign,
    p: &[LinearPoint; 3],
) -> Poly {
    if kind == crate::structure::certs::CertKind::Order {
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
///
/// Each coefficient is a signed sum of products `u_i · v_j` of the
/// differences `u = q − p` and `v = r − p` of the points' linear positions
/// (midpoint–radius enclosures, [`Geo::linear_mr`]). The value is computed
/// once in plain f64 and bounded once, rather than each operation carrying
/// its own radius: a difference `d = fl(b − a)` is within
/// `e = r_a + r_b + ε|d|` of the true one; a product of two such is within
/// `|d|·e' + |d'|·e + e·e'` of `d·d'`; the rounding of at most four
/// products and three sums is within `5ε` of the sum `S` of the products'
/// magnitudes. The bound `(Σ inputs + 5εS)·(1 + 32ε) + TINY` covers these
/// terms and the rounding of the bound's own sums and products (all of
/// nonnegative numbers, fewer than 32 operations deep), and the underflow
/// of the products. A coefficient all of whose products have a factor that
/// is exactly zero (a velocity difference of two points of one body) is
/// the exact zero.
pub(super) fn cert_enclosure(world: &Geo, c: &Cert) -> Option<[Interval; 3]> {
    cert_enclosure_with(c, |a| world.linear_mr(a))
}

/// [`cert_enclosure`] with each point's [`Geo::linear_mr`] from `linear`
/// (a memo of them, where many certificates share points).
pub(super) fn cert_enclosure_with(
    c: &Cert,
    mut linear: impl FnMut(Att) -> Option<[crate::geom::Mr; 4]>,
) -> Option<[Interval; 3]> {
    use crate::geom::EPS;
    let order = c.kind == crate::structure::certs::CertKind::Order;
    // the same points as cert_poly: Order is −(p0 − p1)·(p2 − p1)
    let [p, q, r] = if order { [c.p[1], c.p[0], c.p[2]] } else { c.p };
    let [ep, eq, er] = [linear(p)?, linear(q)?, linear(r)?];
    // b − a per component `[x0, x1, y0, y1]` as (value, bound); the
    // velocity part is exactly zero for two points of one body
    let diff = |same: bool, ea: &[crate::geom::Mr; 4], eb: &[crate::geom::Mr; 4]| {
        let one = |k: usize| {
            let d = eb[k].m - ea[k].m;
            (d, ea[k].r + eb[k].r + EPS * d.abs())
        };
        let zero = (0.0, 0.0);
        [
            one(0),
            if same { zero } else { one(1) },
            one(2),
            if same { zero } else { one(3) },
        ]
    };
    let u = diff(p.obj == q.obj, &ep, &eq);
    let v = diff(p.obj == r.obj, &ep, &er);
    const X0: usize = 0;
    const X1: usize = 1;
    const Y0: usize = 2;
    const Y1: usize = 3;
    let mut e = if order {
        [
            signed_products(&u, &v, [(X0, X0, false), (Y0, Y0, false)]),
            signed_products(
                &u,
                &v,
                [
                    (X0, X1, false),
                    (X1, X0, false),
                    (Y0, Y1, false),
                    (Y1, Y0, false),
                ],
            ),
            signed_products(&u, &v, [(X1, X1, false), (Y1, Y1, false)]),
        ]
    } else {
        [
            signed_products(&u, &v, [(X0, Y0, false), (Y0, X0, true)]),
            signed_products(
                &u,
                &v,
                [
                    (X0, Y1, false),
                    (X1, Y0, false),
                    (Y0, X1, true),
                    (Y1, X0, true),
                ],
            ),
            // u and v move alike when q and r are on one body
            if q.obj == r.obj {
                Interval::point(0.0)
            } else {
                signed_products(&u, &v, [(X1, Y1, false), (Y1, X1, true)])
            },
        ]
    };
    if order || c.sign == Sign::Negative {
        e = e.map(|x| -x);
    }
    Some(e)
}

/// `Σ ±u_i·v_j` over `terms` (`(i, j, negated)`), enclosed as
/// [`cert_enclosure`] says, for differences `u` and `v` given as
/// (value, bound) per component.
#[inline(always)]
fn signed_products<const N: usize>(
    u: &[(f64, f64); 4],
    v: &[(f64, f64); 4],
    terms: [(usize, usize, bool); N],
) -> Interval {
    use crate::geom::{EPS, TINY};
    let (mut m, mut bound, mut mags, mut zero) = (0.0f64, 0.0f64, 0.0f64, true);
    for (i, j, neg) in terms {
        let ((a, ea), (b, eb)) = (u[i], v[j]);
        let x = a * b;
        m += if neg { -x } else { x };
        bound += a.abs() * eb + b.abs() * ea + ea * eb;
        mags += x.abs();
        zero &= (a == 0.0 && ea == 0.0) || (b == 0.0 && eb == 0.0);
    }
    if zero {
        return Interval::point(0.0);
    }
    let r = (bound + 5.0 * EPS * mags) * (1.0 + 32.0 * EPS) + TINY;
    crate::geom::Mr { m, r }.interval()
}

/// A deferred failure time's exact computation: the certificate's three
/// points with the frames they moved by when it was scheduled.
struct DeferredFailure {
    p: [PointRef; 3],
    kind: crate::structure::certs::CertKind,
    sign: Sign,
}

impl DeferredFailure {
    /// What the three points were when the failure time was computed
    /// ([`fingerprint`] then).
    fn fingerprint(&self) -> Fingerprint {
        self.p.each_ref().map(PointRef::id)
    }
}

/// A fingerprint that no points have (a frame's uid is never 0).
const NO_POINTS: Fingerprint = [(0, (0, 0)); 3];

/// What a certificate's points were when its failure time `due` was
/// computed, and whether `due` is a root of its function (see
/// [`Scheduled::fp`]): `fp` where the book keeps it, else read from `due`'s
/// deferred computation, which holds the points: the book keeps none only
/// for a deferred time made for the certificate itself
/// ([`enqueue_with`]), a root after the instant it was computed at.
pub(super) fn schedule_fp(
    fp: Option<&(Fingerprint, bool)>,
    due: Option<&Time>,
) -> Option<(Fingerprint, bool)> {
    if let Some(&f) = fp {
        return Some(f);
    }
    let src = due?.deferred_source::<DeferredFailure>()?;
    Some((src.fingerprint(), true))
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

    /// A turn certificate with two points that move alike (one frame) has
    /// a function of degree at most one in time: its roots are rational.
    fn known_rational(&self) -> bool {
        let [a, b, c] = &self.p;
        self.kind != crate::structure::certs::CertKind::Order
            && (a.same_frame(b) || b.same_frame(c) || a.same_frame(c))
    }
}

/// Certificate enclosure `e` (a [`cert_enclosure`]) paired with what
/// [`filtered_failure`] makes of it at `now`. A scheduling asks the filter
/// once: the answer serves the far queue ([`far_failure`]) and then
/// [`failure_time`].
pub(super) fn filter_at(e: Option<[Interval; 3]>, now: &Time) -> Option<([Interval; 3], Filtered)> {
    e.map(|e| (e, filtered_failure(e, now.interval())))
}

/// When certificate `c` fails, given that `now` is the current time: `now`
/// itself if it is already wrong just after `now`, else the first later root
/// where it stops being positive, if any; `filtered` is the certificate's
/// [`cert_enclosure`] with the filter's answer ([`filter_at`]).
pub(super) fn failure_time(
    world: &Geo,
    c: &Cert,
    now: &Time,
    filtered: Option<([Interval; 3], Filtered)>,
) -> Option<Time> {
    use crate::structure::counters::{bump, Counter};
    bump(Counter::FailureTimes);
    // (`None` only if a point is no vertex of its body's approximation,
    // which the enclosures already rule out)
    let deferred = |iv: Interval| deferred_failure(world, c, iv);
    if let Some((_, f)) = filtered {
        match f {
            Filtered::Never => return None,
            Filtered::At(iv) => {
                if let Some(t) = deferred(iv) {
                    return Some(t);
                }
            }
            Filtered::Unsure => {}
        }
    }
    let e = filtered.map(|(e, _)| e);
    // the sign just after `now` of an orientation certificate (most often
    // zero at `now`: its points were collinear at this event) from the
    // instant's memo of exact turns, when it knows it
    let orient = c.kind != crate::structure::certs::CertKind::Order;
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
    let [_, at, after] = p.signs_at_and_around(now);
    if orient {
        if known.is_none() {
            world.memo_record(c.p, now, true, signed(after));
        }
        // (the sign at `now` too: a motion change asks it next, for the
        // corridors with a junction straight at `now`)
        world.memo_record_at(c.p, now, signed(at));
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
/// ([`crate::structure::faces::flat_while_resting`]): it holds until a motion change
/// parts them.
pub(super) fn resting_flat(world: &Geo, c: &Cert, p: &Poly) -> bool {
    p.is_zero()
        && c.kind == crate::structure::certs::CertKind::Triangle
        && crate::structure::faces::flat_while_resting(world, c.p)
}

/// Whether certificate `c` is already wrong just after `now` (it fails at
/// `now`).
pub(super) fn is_failing(world: &Geo, c: &Cert, now: &Time) -> bool {
    cert_poly(world, c).sign_after(now) != Sign::Positive
}

/// [`is_failing`] for a certificate that is due at `now` (queued at `now`,
/// or popped at `now`): known without arithmetic while its points are the
/// ones its failure time `due` was computed for (see [`Scheduled::fp`]),
/// evaluated exactly otherwise.
pub(super) fn due_is_failing(
    world: &Geo,
    c: &Cert,
    (fp, due): (Option<&(Fingerprint, bool)>, Option<&Time>),
    now: &Time,
) -> bool {
    if let (Some((f, root)), Some(at)) = (schedule_fp(fp, due), due) {
        if Some(f) == fingerprint(world, &c.p) && at.is_known_same(now) {
            crate::structure::counters::bump(crate::structure::counters::Counter::FailingKnown);
            // (a failure root: negative just after it; the instant's memo
            // of turns learns that for the orientation)
            if root && c.kind != crate::structure::certs::CertKind::Order {
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
pub(super) fn tie(world: &Geo, p: &[Att; 3]) -> u64 {
    let possible_contact = (0..3).any(|i| {
        let (x, y, z) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        z.obj != x.obj && crate::structure::faces::poly_edge(world, x, y)
    });
    u64::from(!possible_contact)
}

/// The earliest end of a bridge among the bodies of the points `p`
/// ([`crate::world::Body::bridge_end`]), if one of them is on a bridge.
pub(super) fn bridge_end<'a>(world: &'a Geo, p: &[Att; 3]) -> Option<&'a Time> {
    p.iter()
        .filter_map(|a| match a.obj {
            Obj::Body(b) => world.body(b).bridge_end(),
            Obj::Omega => None,
        })
        .min()
}

/// Whether a certificate holds from `now` to `end`, the earliest end of a
/// bridge among its bodies ([`bridge_end`]), as the f64 filter proves it:
/// its function is positive on the whole span. At that
/// bridge's end the body's motion changes and every certificate on it is
/// scheduled again, so until then it needs no failure time.
/// `e` is the certificate's [`cert_enclosure`].
pub(super) fn holds_until_bridge_end(now: &Time, end: &Time, e: Option<[Interval; 3]>) -> bool {
    let Some([c0, c1, c2]) = e else {
        return false;
    };
    let span = now.interval().hull(&end.interval());
    (c0 + span * (c1 + span * c2)).sign() == Some(Sign::Positive)
}

/// Whether turn certificate `c` is positive from `now` to `end` as its
/// points' places at `now` and how far they can move by `end` prove it,
/// without its coefficients' enclosure (the cheap first test of
/// [`holds_until_bridge_end`]; `false` where it does not prove it, and
/// for an order certificate). With `d1 = q − p` and `d2 = r − p` at `now`
/// (midpoints and radii, [`Geo::mid_rad`]: `|d1x|` at most `M1x` and so
/// on) and each coordinate of a difference moving by at most `Δ1x` and so
/// on until `end` (the sum of its two points' speeds in that coordinate,
/// from their frames' velocity enclosures, times `end − now`; every body
/// moves linearly until the earliest bridge end among its certificate's
/// bodies), the turn `d1x·d2y − d1y·d2x` changes by at most `Δ1x·M2y +
/// M1x·Δ2y + Δ1x·Δ2y + Δ1y·M2x + M1y·Δ2x + Δ1y·Δ2x`; it holds if its
/// value at `now`, less the error of the f64 evaluation, exceeds that.
/// All of it positive terms, each rounding at most `ε`: a factor `1 +
/// 64ε` and `TINY` cover them.
/// `place(a)` is [`Geo::mid_rad`] of `a` at `now.interval()` (a memo of
/// them, where many certificates share points).
pub(super) fn holds_by_motion_bound(
    world: &Geo,
    c: &Cert,
    now: &Time,
    end: &Time,
    mut place: impl FnMut(Att) -> Option<crate::geom::MidRad>,
) -> bool {
    use crate::geom::{EPS, TINY};
    if c.kind == crate::structure::certs::CertKind::Order {
        return false;
    }
    let t = now.interval();
    let [Some(u), Some(v), Some(w)] = c.p.map(&mut place) else {
        return false;
    };
    let speed = |a: Att| -> [f64; 2] {
        match a.obj {
            Obj::Body(b) => world
                .body(b)
                .frame
                .velocity_enclosure()
                .map(|e| e.lo.abs().max(e.hi.abs())),
            Obj::Omega => [f64::INFINITY; 2],
        }
    };
    let [su, sv, sw] = c.p.map(speed);
    let span = (end.interval().hi - t.lo) * (1.0 + 4.0 * EPS);
    // (the turn at `now` and its error, as the midpoint–radius filter
    // of the orientation computes them)
    let ([d1x, d1y], [r1x, r1y], [d2x, d2y], [r2x, r2y]) =
        crate::geom::mid_rad_differences(u, v, w);
    let (value, err) =
        crate::geom::two_products([(d1x, r1x), (d2y, r2y)], [(d1y, r1y), (d2x, r2x)], true);
    let (m1x, m1y, m2x, m2y) = (
        d1x.abs() + r1x,
        d1y.abs() + r1y,
        d2x.abs() + r2x,
        d2y.abs() + r2y,
    );
    let (e1x, e1y) = ((su[0] + sv[0]) * span, (su[1] + sv[1]) * span);
    let (e2x, e2y) = ((su[0] + sw[0]) * span, (su[1] + sw[1]) * span);
    let moved = e1x * m2y + m1x * e2y + e1x * e2y + e1y * m2x + m1y * e2x + e1y * e2x;
    let signed = if c.sign == Sign::Negative {
        -value
    } else {
        value
    };
    let need = (err + moved) * (1.0 + 64.0 * EPS) + TINY;
    need.is_finite() && signed.is_finite() && signed > need
}

/// Queue certificate `c` (stored under `id`) at its failure time after
/// `now`, if it has one: its queue key and [`Scheduled::fp`]. On the queue
/// alone (a certificate of the book may be borrowed meanwhile).
fn enqueue_in(
    queues: Queues<'_>,
    world: &Geo,
    (c, id): (&Cert, CertId),
    now: &Time,
) -> (Option<QKey>, Option<Box<(Fingerprint, bool)>>) {
    enqueue_with(queues, world, (c, id), now, cert_enclosure(world, c))
}

/// The two queues of the book ([`Kinetic::queue`], [`Kinetic::far`]).
type Queues<'a> = (
    &'a mut EventQueue<Time, CertId>,
    &'a mut EventQueue<FarTime, FarEntry>,
);

/// Take the event of `key` out of its queue.
fn cancel_in((queue, far): Queues<'_>, key: QKey) {
    match key {
        QKey::Near(k) => {
            queue.cancel(k);
        }
        QKey::Far(k) => {
            far.cancel(k);
        }
    }
}

/// [`enqueue_in`] given `e`, the certificate's [`cert_enclosure`]. A
/// failure time that the filter isolates strictly after `now` goes to the
/// far queue by its enclosure ([`far_failure`]); the others, exact or
/// deferred, to the queue of exact times.
fn enqueue_with(
    (queue, far): Queues<'_>,
    world: &Geo,
    (c, id): (&Cert, CertId),
    now: &Time,
    e: Option<[Interval; 3]>,
) -> (Option<QKey>, Option<Box<(Fingerprint, bool)>>) {
    let filtered = filter_at(e, now);
    if let Some((iv, preds)) = filtered.and_then(|(_, f)| far_failure(world, c, now, f)) {
        let entry = FarEntry {
            id,
            preds,
            tie: tie(world, &c.p),
            seq: queue.reserve_seq(),
            #[cfg(debug_assertions)]
            frames: fingerprint(world, &c.p)
                .expect("the points of a far certificate are vertices")
                .map(|(uid, _)| uid),
        };
        return (Some(QKey::Far(far.schedule(FarTime(iv), 0, entry))), None);
    }
    let Some(t) = failure_time(world, c, now, filtered) else {
        return (None, None);
    };
    // (a deferred time made here holds the points it was computed for: the
    // book keeps them only for the other times. `now` itself, when it is
    // the deferred failure time of another certificate, is no such time:
    // the book keeps this certificate's points then, or a fingerprint
    // that no points have where they have none, so that
    // [`schedule_fp`] never reads the other certificate's points)
    let root = !t.is_known_same(now);
    let fp = match t.deferred_source::<DeferredFailure>() {
        Some(_src) if root => {
            debug_assert_eq!(Some(_src.fingerprint()), fingerprint(world, &c.p));
            None
        }
        Some(_) => Some(Box::new((
            fingerprint(world, &c.p).unwrap_or(NO_POINTS),
            root,
        ))),
        None => fingerprint(world, &c.p).map(|f| Box::new((f, root))),
    };
    (
        Some(QKey::Near(queue.schedule(t, tie(world, &c.p), id))),
        fp,
    )
}

/// The enclosure of certificate `c`'s failure time after `now` where the
/// f64 filter isolates it strictly after `now` (`f`: [`filtered_failure`]
/// of its [`cert_enclosure`] at `now`), as [`failure_time`] would defer
/// it, and the ids before its points' ids ([`Geo::pred_id`]), which tell
/// the points it was computed for: the exact time is that deferred time
/// on those points ([`far_deferred`]), made when it could be the next
/// failure.
fn far_failure(world: &Geo, c: &Cert, now: &Time, f: Filtered) -> Option<(Interval, [u32; 3])> {
    let after = now.interval();
    match f {
        Filtered::At(iv) if iv.lo > after.hi => {
            // (a certificate has an enclosure only where its points are
            // vertices of the bodies' views, which have them)
            let pred = |j: usize| world.pred_id(c.p[j]);
            let preds = [pred(0)?, pred(1)?, pred(2)?];
            crate::structure::counters::bump(crate::structure::counters::Counter::FailureTimes);
            Some((iv, preds))
        }
        _ => None,
    }
}

/// The deferred failure time of certificate `c` in the far queue (at `ft`,
/// as `e`): the root in that enclosure of its function on the points it
/// was computed for, each moving by its body's frame of now, which is the
/// frame it was computed with (a motion change schedules its bodies'
/// certificates again).
pub(super) fn far_deferred(world: &Geo, c: &Cert, ft: &FarTime, e: &FarEntry) -> Option<Time> {
    let point = |j: usize| match c.p[j] {
        Att {
            obj: Obj::Body(b),
            v,
        } => world.point_ref_after(b, e.preds[j], v),
        _ => None,
    };
    let src = DeferredFailure {
        p: [point(0)?, point(1)?, point(2)?],
        kind: c.kind,
        sign: c.sign,
    };
    #[cfg(debug_assertions)]
    assert_eq!(
        src.p.each_ref().map(|x| x.id().0),
        e.frames,
        "a body of far certificate {:?} changed its motion",
        c.p
    );
    Some(Time::deferred(ft.0, src))
}

/// The deferred failure time of certificate `c` in enclosure `iv`: the
/// root the filter isolated ([`failure_time`], [`far_failure`]).
pub(super) fn deferred_failure(world: &Geo, c: &Cert, iv: Interval) -> Option<Time> {
    let [a, b, d] = c.p.map(|x| world.point_ref(x));
    let src = DeferredFailure {
        p: [a?, b?, d?],
        kind: c.kind,
        sign: c.sign,
    };
    Some(Time::deferred(iv, src))
}

/// [`Kinetic::due_now`] on the queue and the instant's state alone (a
/// certificate of the book may be borrowed meanwhile).
fn due_in(
    queue: &EventQueue<Time, CertId>,
    instant: &InstantState,
    p: &[Att; 3],
    key: Option<QKey>,
    now: &Time,
) -> bool {
    match key {
        Some(QKey::Near(k)) => queue.get(k).is_some_and(|(t, _)| t == now),
        // (its failure is strictly after the current instant)
        Some(QKey::Far(_)) => false,
        None => {
            instant.waiting.contains(p)
                || instant.later.as_ref().is_some_and(|(_, ps)| ps.contains(p))
        }
    }
}

/// The record of certificate `c`, owned by `o`, before it is queued.
fn unscheduled(c: Cert, o: Owner) -> Scheduled {
    Scheduled {
        cert: c,
        key: None,
        owners: smallvec::smallvec![o],
        fp: None,
        idle: false,
    }
}

impl Kinetic {
    pub(super) fn schedule_everything(
        &mut self,
        world: &Geo,
        now: &Time,
    ) -> Result<(), StructureError> {
        self.owned_tri = vec![None; self.kss.tris.len()];
        self.owned_corr = vec![Owned::new(); self.kss.corrs.len()];
        for ti in 0..self.kss.tris.len() {
            self.refresh(world, Owner::Tri(TriId(ti as u32)), now)?;
        }
        // each corridor's certificates right after its normalization: they
        // are the junctions its faces were found valid with, read from the
        // validity cache while it still holds them (it keeps a few hundred
        // corridors)
        for ki in 0..self.kss.corrs.len() {
            let steps = self.kss.normalize(world, CorrId(ki as u32), now, None)?;
            if steps > 0 {
                self.tally.searches += 1;
            }
            self.refresh(world, Owner::Corr(CorrId(ki as u32)), now)?;
        }
        Ok(())
    }

    /// Recompute the certificates owned by `o` at `now`: drop the ones it no
    /// longer owns, schedule the new ones.
    pub(super) fn refresh(
        &mut self,
        world: &Geo,
        o: Owner,
        now: &Time,
    ) -> Result<(), StructureError> {
        if !(self.instant.changed_at.as_ref()).is_some_and(|c| c.is_known_same(now)) {
            self.instant.changed_at = Some(now.clone());
        }
        let fresh = match o {
            Owner::Tri(t) => self.kss.triangle_certs(t),
            Owner::Corr(k) => self.kss.corridor_certs(world, k, now),
        };
        let old = self.take_owned(o);
        // certificates that fail at `now` and have not been handled yet keep
        // their sign (and stay due now): recomputing them with the sign they
        // have just after `now` would swallow the failure when two fail at
        // one instant and the operation for the first touches the second
        let mut pending: BTreeMap<[Att; 3], Cert> = BTreeMap::new();
        // `same[i]`: `fresh[i]` is a certificate that `o` owns already (its
        // id), as it is, either shared with another owner or not due at
        // this instant: it keeps its place in the queue (its failure time
        // depends only on its points) and its owners, `o` again last
        let mut same: [Option<CertId>; MAX_CERTS] = [None; MAX_CERTS];
        for &id in &old {
            let Some(s) = self.certs.at_mut(id) else {
                continue;
            };
            let p = s.cert.p;
            let shared = s.owners.iter().any(|&x| x != o);
            s.owners.retain(|x| *x != o);
            if let Some(i) = fresh.iter().position(|c| *c == s.cert) {
                if shared
                    || !(self.instant.handling == Some(p)
                        || due_in(&self.queue, &self.instant, &p, s.key, now))
                {
                    s.owners.push(o);
                    same[i] = Some(id);
                    continue;
                }
            }
            if s.owners.is_empty() {
                let (cert, key) = (s.cert, s.key);
                let due = self.instant.handling == Some(p) || self.due_now(&p, key, now);
                if self.instant.handling != Some(p) && due {
                    let s = self.certs.at(id).expect("stored");
                    let at = due_time(&self.queue, key, self.certs.popped(id));
                    if due_is_failing(world, &cert, (s.fp.as_deref(), at), now) {
                        pending.insert(p, cert);
                    }
                }
                self.drop_id(id);
            }
        }
        let kept: arrayvec::ArrayVec<CertId, MAX_CERTS> = same.iter().flatten().copied().collect();
        let mut mine = Owned::new();
        for (i, c) in fresh.iter().enumerate() {
            if let Some(id) = same[i] {
                mine.push(id);
                continue;
            }
            let c = match pending.get(&c.p) {
                Some(old) if old.sign != c.sign => *old,
                _ => *c,
            };
            let id = match self.certs.insert_new(unscheduled(c, o)) {
                Ok(id) => {
                    self.schedule_stored(world, c, id, now);
                    mine.push(id);
                    continue;
                }
                Err(id) => id,
            };
            let s = self.certs.at_mut(id).expect("indexed");
            // a certificate left without owners (a removal in progress)
            // is taken over only as it is
            if s.owners.is_empty() && s.cert != c {
                self.drop_id(id);
                mine.push(self.schedule_new(world, c, o, now));
                continue;
            }
            if s.cert.sign != c.sign
                && (self.instant.handling == Some(c.p) || !is_failing(world, &s.cert, now))
            {
                let e = format!(
                    "contradictory certificates on {:?} ({:?} and {:?})",
                    c.p, s.owners, o
                );
                // no owner list names `o`'s certificates kept above any
                // more: `o` leaves them, and those left without an owner go
                for &id in &kept {
                    if let Some(s) = self.certs.at_mut(id) {
                        s.owners.retain(|x| *x != o);
                        if s.owners.is_empty() {
                            self.drop_id(id);
                        }
                    }
                }
                return Err(StructureError::Local(e));
            }
            // (a kept certificate of the other sign fails now and will be
            // handled)
            if !s.owners.contains(&o) {
                s.owners.push(o);
            }
            mine.push(id);
        }
        self.put_owned(o, mine);
        self.max_active = self.max_active.max(self.active_now());
        Ok(())
    }

    /// The certificates owner `o` owns (none for an owner out of range).
    pub(super) fn owned(&self, o: Owner) -> &[CertId] {
        match o {
            Owner::Tri(t) => self
                .owned_tri
                .get(t.0 as usize)
                .map_or(&[], Option::as_slice),
            Owner::Corr(k) => self
                .owned_corr
                .get(k.0 as usize)
                .map_or(&[], |l| l.as_slice()),
        }
    }

    /// Take owner `o`'s list of certificates, leaving it empty.
    pub(super) fn take_owned(&mut self, o: Owner) -> Owned {
        match o {
            Owner::Tri(t) => self.owned_tri[t.0 as usize].take().into_iter().collect(),
            Owner::Corr(k) => std::mem::take(&mut self.owned_corr[k.0 as usize]),
        }
    }

    /// Make `mine` owner `o`'s list of certificates (at most one for a
    /// triangle).
    pub(super) fn put_owned(&mut self, o: Owner, mine: Owned) {
        match o {
            Owner::Tri(t) => {
                debug_assert!(
                    mine.len() <= 1,
                    "a triangle owns {} certificates",
                    mine.len()
                );
                self.owned_tri[t.0 as usize] = mine.first().copied();
            }
            Owner::Corr(k) => self.owned_corr[k.0 as usize] = mine,
        }
    }

    /// Schedule certificate `c`, not yet known, for owner `o`: its id.
    pub(super) fn schedule_new(&mut self, world: &Geo, c: Cert, o: Owner, now: &Time) -> CertId {
        let id = self.certs.insert(unscheduled(c, o));
        self.schedule_stored(world, c, id, now);
        id
    }

    /// Schedule certificate `c`, just stored under `id` as [`unscheduled`]:
    /// its failure time queued, its bodies' sets.
    fn schedule_stored(&mut self, world: &Geo, c: Cert, id: CertId, now: &Time) {
        let (key, fp) = enqueue_in((&mut self.queue, &mut self.far), world, (&c, id), now);
        let s = self.certs.at_mut(id).expect("just stored");
        (s.key, s.fp) = (key, fp);
        for b in each_body(&c.p) {
            self.by_body.at(b).insert(id);
        }
        if let Some(ids) = self.scheduled.as_mut() {
            ids.push(id);
        }
    }

    /// Whether the certificate on `p` (queued under `key`) can be failing at
    /// `now`: queued at `now`, or popped at this instant and set aside. A
    /// failing certificate is always one of these, so the exact test need not
    /// run for the others (most of the certificates an operation replaces).
    pub(super) fn due_now(&self, p: &[Att; 3], key: Option<QKey>, now: &Time) -> bool {
        due_in(&self.queue, &self.instant, p, key, now)
    }

    /// Drop the certificate with id `id` (if it is still stored): out of the
    /// store, its bodies' sets and the queue.
    pub(super) fn drop_id(&mut self, id: CertId) {
        if let Some(s) = self.certs.remove(id) {
            if s.idle {
                self.idle -= 1;
            }
            let certs = &self.certs;
            for b in each_body(&s.cert.p) {
                if let Some(set) = self.by_body.get_mut(&b) {
                    set.dropped(|x| certs.is_live(x));
                }
            }
            if let Some(k) = s.key {
                cancel_in((&mut self.queue, &mut self.far), k);
            }
        }
    }

    /// Move into the queue of exact times every certificate of the far
    /// queue whose failure time could be no later than that queue's
    /// first (all of them while it is empty), each with the deferred time
    /// its enclosure was isolated for and the place in the order it had
    /// when scheduled: afterwards the queue's first failure is the next
    /// one. Called before the queue is read for the next failure.
    pub(super) fn admit(&mut self, world: &Geo) {
        while let Some((fk, ft, _, &entry)) = self.far.peek() {
            let ft = *ft;
            if let Some((_, t, _, _)) = self.queue.peek() {
                if ft.0.lo > t.interval().hi {
                    return;
                }
            }
            self.far.cancel(fk);
            let Some(s) = self.certs.at_mut(entry.id) else {
                continue;
            };
            debug_assert_eq!(s.key, Some(QKey::Far(fk)), "a far event of another key");
            let t = far_deferred(world, &s.cert, &ft, &entry)
                .expect("the points of a far certificate are vertices");
            let key = self
                .queue
                .schedule_at_seq(t, entry.tie, entry.seq, entry.id);
            s.key = Some(QKey::Near(key));
        }
    }

    /// Take certificate `id` out of the queue until the end of a bridge of
    /// one of its bodies ([`holds_until_bridge_end`]).
    pub(super) fn idle_until_bridge_end(&mut self, id: CertId) {
        if let Some(s) = self.certs.at_mut(id) {
            if let Some(k) = s.key.take() {
                cancel_in((&mut self.queue, &mut self.far), k);
            }
            s.fp = None;
            if !s.idle {
                s.idle = true;
                self.idle += 1;
            }
            self.certs.clear_popped(id);
        }
    }

    /// Compute the failure time of the certificate on `p` again and queue
    /// it there.
    pub(super) fn reschedule(&mut self, world: &Geo, p: &[Att; 3], now: &Time) {
        if let Some(id) = self.certs.id(p) {
            self.reschedule_id(world, id, now, None);
        }
    }

    /// [`Kinetic::reschedule`] by id, given the certificate's
    /// [`cert_enclosure`] (`Some(e)`; `None`: computed here).
    pub(super) fn reschedule_id(
        &mut self,
        world: &Geo,
        id: CertId,
        now: &Time,
        e: Option<Option<[Interval; 3]>>,
    ) {
        let Some(s) = self.certs.at_mut(id) else {
            return;
        };
        if s.idle {
            s.idle = false;
            self.idle -= 1;
        }
        if let Some(k) = s.key.take() {
            cancel_in((&mut self.queue, &mut self.far), k);
        }
        let e = e.unwrap_or_else(|| cert_enclosure(world, &s.cert));
        let queues = (&mut self.queue, &mut self.far);
        let (key, fp) = enqueue_with(queues, world, (&s.cert, id), now, e);
        (s.key, s.fp) = (key, fp);
        self.certs.clear_popped(id);
        self.max_active = self.max_active.max(self.active_now());
    }

    /// The certificates on body `b` that name one of `ids`, in the order of
    /// their points.
    pub(super) fn certs_naming(&self, b: BodyId, ids: &[Att]) -> Vec<([Att; 3], CertId)> {
        let mut out: Vec<([Att; 3], CertId)> = self
            .by_body
            .get(&b)
            .into_iter()
            .flatten()
            .filter_map(|&id| {
                let p = self.certs.at(id)?.cert.p;
                p.iter().any(|x| ids.contains(x)).then_some((p, id))
            })
            .collect();
        out.sort_unstable_by_key(|&(p, _)| p);
        out
    }

    /// The certificates on body `b` that name one of `ids`
    /// ([`Kinetic::certs_naming`]), and their owners.
    pub(super) fn owners_naming(&self, b: BodyId, ids: &[Att]) -> (Named, BTreeSet<Owner>) {
        let named = self.certs_naming(b, ids);
        let owners = named
            .iter()
            .filter_map(|&(_, id)| self.certs.at(id))
            .flat_map(|s| s.owners.iter().copied())
            .collect();
        (Named(named), owners)
    }

    /// After vertices `ids` of body `b` changed place, for each `(b, ids)`
    /// of `moved` (pops or a merge): recompute the certificates of
    /// `owners`, then schedule again every certificate still naming one of
    /// those vertices (its points moved) that the refreshes did not schedule
    /// anew. `named` is what [`Kinetic::owners_naming`] found for each
    /// before the refreshes (merged, [`Named::merge`]): a certificate naming
    /// one of the vertices afterwards is one of those still there, or one
    /// the refreshes scheduled anew (only they make certificates, and a
    /// certificate's points never change), so the bodies' certificates are
    /// not searched again.
    pub(super) fn refresh_moved(
        &mut self,
        geo: &Geo,
        moved: &[(BodyId, Vec<Att>)],
        (named, owners): (Named, BTreeSet<Owner>),
        t: &Time,
    ) -> Result<(), StructureError> {
        // (a certificate the owners' refreshes scheduled anew has its
        // failure time from the vertices' new places already)
        self.scheduled = Some(Vec::new());
        let refreshed = owners.into_iter().try_for_each(|o| self.refresh(geo, o, t));
        let fresh = self.scheduled.take().unwrap_or_default();
        refreshed?;
        let still: Vec<([Att; 3], CertId)> = named
            .0
            .into_iter()
            .filter(|&(p, id)| self.certs.at(id).is_some_and(|s| s.cert.p == p))
            .collect();
        #[cfg(debug_assertions)]
        {
            let mut now_naming = Named(Vec::new());
            for (b, ids) in moved {
                now_naming.merge(Named(self.certs_naming(*b, ids)));
            }
            debug_assert_eq!(
                still
                    .iter()
                    .filter(|(_, id)| !fresh.contains(id))
                    .collect::<Vec<_>>(),
                now_naming
                    .0
                    .iter()
                    .filter(|(_, id)| !fresh.contains(id))
                    .collect::<Vec<_>>(),
                "a certificate naming the moved vertices was made outside the refreshes"
            );
        }
        #[cfg(not(debug_assertions))]
        let _ = moved;
        for (_, id) in still {
            if !fresh.contains(&id) {
                self.reschedule_id(geo, id, t, None);
            }
        }
        Ok(())
    }

    /// Rename owner `from` to `to` on certificates `ids`.
    pub(super) fn rename(&mut self, ids: &[CertId], from: Owner, to: Owner) {
        for &id in ids {
            if let Some(s) = self.certs.at_mut(id) {
                for x in s.owners.iter_mut() {
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
        let p = crate::structure::certs::rotate_to_min(*p);
        self.reschedule_unqueued(world, &p, now);
    }

    /// Schedule the certificate on `p` (its points as stored) again if it
    /// is out of the queue: popped and not handled, or idle.
    pub(super) fn reschedule_unqueued(&mut self, world: &Geo, p: &[Att; 3], now: &Time) {
        if let Some(id) = self.certs.id(p) {
            if self.certs.at(id).is_some_and(|s| s.key.is_none()) {
                self.reschedule_id(world, id, now, None);
            }
        }
    }
}

/// The certificates on a body that name some vertices, in the order of
/// their points ([`Kinetic::owners_naming`]), for [`Kinetic::refresh_moved`].
#[derive(Default)]
pub(super) struct Named(Vec<([Att; 3], CertId)>);

impl Named {
    /// Take in `other`'s certificates (of another body, or found later),
    /// keeping the order of their points and each once.
    pub(super) fn merge(&mut self, other: Named) {
        self.0.extend(other.0);
        self.0.sort_unstable_by_key(|&(p, _)| p);
        self.0.dedup();
    }
}
