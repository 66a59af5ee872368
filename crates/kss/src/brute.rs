//! The brute-force reference: all-pairs exact first-contact times under
//! piecewise-linear translation, event-driven over flight-plan changes.
//!
//! It is the test oracle for every structure and the naive baseline in the
//! benchmarks, so it is kept simple. Two independent ways to compute when a
//! pair touches are provided and tested against each other:
//!
//! * [`PairMethod::Simple`], `O(n·m)`: every vertex against every edge of the
//!   other polygon, in exact rationals;
//! * [`PairMethod::Fast`], `O(n + m)`: the relative position `d(t)` of the two
//!   bodies against the half-planes of their Minkowski difference.
//!
//! Both compute the closed interval of times during which the two (linearly
//! extrapolated) polygons share a point, and whether their interiors overlap
//! during it. A pair's next collision after `now` is the start of that
//! interval if it lies after `now`; if the pair already touches at `now` (only
//! possible in `bounce` mode), it collides at `now` exactly when the motion
//! makes the interiors overlap right after `now`, and not at all while it
//! slides or separates.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::geom::Point;
use crate::num::{lcm, Int, Interval, Rational, Sign, Time};
use crate::world::{BodyId, World};

/// How the reference computes a pair's contact interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PairMethod {
    /// Vertex against edge, `O(n·m)` per pair.
    Simple,
    /// Minkowski difference, `O(n + m)` per pair.
    #[default]
    Fast,
}

/// The closed interval of times (over the whole real line, motions
/// extrapolated linearly) during which two polygons share a point.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ContactInterval {
    /// They never touch.
    Never,
    /// They share a point for `t` in `[start, end]` (`None`: unbounded).
    During {
        /// First time they share a point (`None`: always did).
        start: Option<Rational>,
        /// Last time they share a point (`None`: always will).
        end: Option<Rational>,
        /// Whether their interiors overlap inside the interval (otherwise
        /// they only graze or slide along each other).
        penetrating: bool,
    },
}

impl ContactInterval {
    /// The pair's next collision at or after `now` (see module docs).
    pub fn next_contact(&self, now: &Rational) -> Option<Rational> {
        match self {
            ContactInterval::Never => None,
            ContactInterval::During {
                start,
                end,
                penetrating,
            } => {
                if let Some(s) = start {
                    if s > now {
                        return Some(s.clone());
                    }
                }
                let before_end = end.as_ref().is_none_or(|e| now < e);
                (*penetrating && before_end).then(|| now.clone())
            }
        }
    }
}

impl ContactInterval {
    /// Whether the pair shares a point on a whole interval that begins at
    /// `now` without their interiors overlapping (it rests or slides in
    /// contact just after `now`), and if so the end of that interval
    /// (`None`: never, on the current motions). A pair whose interiors
    /// overlap is a collision, not a resting contact.
    pub fn rests_after(&self, now: &Rational) -> Option<Option<Rational>> {
        match self {
            ContactInterval::During {
                start,
                end,
                penetrating: false,
            } if start.as_ref().is_none_or(|s| s <= now)
                && end.as_ref().is_none_or(|e| e > now) =>
            {
                Some(end.clone())
            }
            _ => None,
        }
    }
}

/// Relative motion `d(t) = pos_a(t) − pos_b(t) = d0 + w·t`.
fn relative_motion(world: &World, a: BodyId, b: BodyId) -> (Point, Point) {
    let (ba, bb) = (world.body(a), world.body(b));
    let d0 = ba.traj.origin().sub(bb.traj.origin());
    let w = ba.traj.velocity().sub(bb.traj.velocity());
    (d0, w)
}

/// The contact interval of bodies `a` and `b` on their current pieces.
pub fn contact_interval(
    world: &World,
    a: BodyId,
    b: BodyId,
    method: PairMethod,
) -> ContactInterval {
    match method {
        PairMethod::Simple => simple_interval(world, a, b),
        PairMethod::Fast => fast_interval(world, a, b),
    }
}

/// Minkowski difference: `A(t) ∩ B(t) ≠ ∅` iff `d(t) ∈ M = B ⊕ (−A)`; each
/// edge of `M` gives a linear constraint `α·t <= β`.
fn fast_interval(world: &World, a: BodyId, b: BodyId) -> ContactInterval {
    let (d0, w) = relative_motion(world, a, b);
    let mut den = d0.x.denom().clone();
    for r in [&d0.y, &w.x, &w.y] {
        den = lcm(&den, r.denom());
    }
    let sc = |r: &Rational| r.numer() * (&den / r.denom());
    let (mut dx, mut dy, mut wx, mut wy) = (sc(&d0.x), sc(&d0.y), sc(&w.x), sc(&w.y));
    let mink = world.minkowski(a, b);
    let (edges, exp) = (&mink.0, mink.1);
    // n·d(t) <= h·2^exp  ⇔  n·(D0 + W t) <= h·den·2^exp (all scaled to integers)
    let rhs_scale = if exp >= 0 {
        &den << exp as usize
    } else {
        let s = (-exp) as usize;
        dx <<= s;
        dy <<= s;
        wx <<= s;
        wy <<= s;
        den.clone()
    };
    // t_in = max over α<0 of β/α, t_out = min over α>0 of β/α, as (num, den>0).
    // Each edge's α and β on enclosures first: α's sign and an enclosure of
    // β/α decide most edges, and only the edges whose ratio may be the
    // extreme one are computed exactly.
    let iv = Interval::of_int;
    let (dxi, dyi, wxi, wyi, rsi) = (iv(&dx), iv(&dy), iv(&wx), iv(&wy), iv(&rhs_scale));
    let exact_alpha = |e: &crate::geom::MinkowskiEdge| &e.nx * &wx + &e.ny * &wy;
    let exact_beta =
        |e: &crate::geom::MinkowskiEdge| &e.h * &rhs_scale - (&e.nx * &dx + &e.ny * &dy);
    // (edge, sign of α, enclosure of β/α)
    let mut ratios: Vec<(usize, Sign, Interval)> = Vec::new();
    let mut parallel_strict = true;
    for (k, e) in edges.iter().enumerate() {
        let [nx, ny, h] = e.iv;
        let a = nx * wxi + ny * wyi;
        let b = h * rsi - (nx * dxi + ny * dyi);
        let sa = if a.lo > 0.0 {
            Sign::Positive
        } else if a.hi < 0.0 {
            Sign::Negative
        } else {
            Sign::of(&exact_alpha(&e.edge()))
        };
        match sa {
            Sign::Zero => {
                let sb = if b.lo > 0.0 {
                    Sign::Positive
                } else if b.hi < 0.0 {
                    Sign::Negative
                } else {
                    Sign::of(&exact_beta(&e.edge()))
                };
                match sb {
                    Sign::Negative => return ContactInterval::Never,
                    Sign::Zero => parallel_strict = false,
                    Sign::Positive => {}
                }
            }
            s => ratios.push((k, s, b / a)),
        }
    }
    // the exact extreme among the edges of one sign whose ratio may reach
    // the bound that the enclosures give
    let extreme = |sign: Sign| -> Option<(Int, Int)> {
        let of_sign = || ratios.iter().filter(move |r| r.1 == sign);
        let mut best: Option<(Int, Int)> = None;
        if sign == Sign::Negative {
            let bound = of_sign().map(|r| r.2.lo).fold(f64::NEG_INFINITY, f64::max);
            for &(k, _, _) in of_sign().filter(|r| r.2.hi >= bound) {
                let e = edges[k].edge();
                let f = (-exact_beta(&e), -exact_alpha(&e));
                if best.as_ref().is_none_or(|g| frac_cmp(&f, g).is_gt()) {
                    best = Some(f);
                }
            }
        } else {
            let bound = of_sign().map(|r| r.2.hi).fold(f64::INFINITY, f64::min);
            for &(k, _, _) in of_sign().filter(|r| r.2.lo <= bound) {
                let e = edges[k].edge();
                let f = (exact_beta(&e), exact_alpha(&e));
                if best.as_ref().is_none_or(|g| frac_cmp(&f, g).is_lt()) {
                    best = Some(f);
                }
            }
        }
        best
    };
    let t_in = extreme(Sign::Negative);
    let t_out = extreme(Sign::Positive);
    if let (Some(i), Some(o)) = (&t_in, &t_out) {
        if frac_cmp(i, o).is_gt() {
            return ContactInterval::Never;
        }
    }
    let nonzero_length = match (&t_in, &t_out) {
        (Some(i), Some(o)) => frac_cmp(i, o).is_lt(),
        _ => true,
    };
    ContactInterval::During {
        start: t_in.map(|(n, d)| Rational::new(n, d)),
        end: t_out.map(|(n, d)| Rational::new(n, d)),
        penetrating: nonzero_length && parallel_strict,
    }
}

fn frac_cmp(x: &(Int, Int), y: &(Int, Int)) -> std::cmp::Ordering {
    (&x.0 * &y.1).cmp(&(&y.0 * &x.1))
}

/// A pair's relative motion in integers: in a frame where `B` sits at the
/// origin and every length is scaled by the same positive factor, vertex `i`
/// of `A` is at `r0 + rw·t + M·a_i` and vertex `j` of `B` at `M·b_j`, with
/// `a_i`, `b_j` the body polygons' integer coordinates.
struct PairFrame {
    r0: (Int, Int),
    rw: (Int, Int),
    m: Int,
    a: Vec<(Int, Int)>,
    b: Vec<(Int, Int)>,
}

impl PairFrame {
    fn new(world: &World, a: BodyId, b: BodyId) -> PairFrame {
        let (d0, w) = relative_motion(world, a, b);
        let mut den = d0.x.denom().clone();
        for r in [&d0.y, &w.x, &w.y] {
            den = lcm(&den, r.denom());
        }
        let sc = |r: &Rational| r.numer() * (&den / r.denom());
        let (sa, sb) = (&world.body(a).shape, &world.body(b).shape);
        let exp = sa.exp().min(sb.exp());
        let ints = |p: &crate::geom::BodyPolygon| -> Vec<(Int, Int)> {
            let sh = (p.exp() - exp) as usize;
            (0..p.len())
                .map(|i| {
                    let (x, y) = p.int_vertex(i);
                    (x << sh, y << sh)
                })
                .collect()
        };
        let (mut r0, mut rw) = ((sc(&d0.x), sc(&d0.y)), (sc(&w.x), sc(&w.y)));
        let m = if exp >= 0 {
            &den << exp as usize
        } else {
            let s = (-exp) as usize;
            r0 = (&r0.0 << s, &r0.1 << s);
            rw = (&rw.0 << s, &rw.1 << s);
            den
        };
        PairFrame {
            r0,
            rw,
            m,
            a: ints(sa),
            b: ints(sb),
        }
    }
}

fn cross(u: &(Int, Int), v: &(Int, Int)) -> Int {
    &u.0 * &v.1 - &u.1 * &v.0
}

fn dot(u: &(Int, Int), v: &(Int, Int)) -> Int {
    &u.0 * &v.0 + &u.1 * &v.1
}

/// Vertex against edge, both ways, in exact integer arithmetic.
fn simple_interval(world: &World, a: BodyId, b: BodyId) -> ContactInterval {
    let f = PairFrame::new(world, a, b);
    // Times as fractions (num, den > 0); None = unbounded.
    let mut start: Option<Option<(Int, Int)>> = None;
    let mut end: Option<Option<(Int, Int)>> = None;
    let mut touch = |lo: Option<(Int, Int)>, hi: Option<(Int, Int)>| {
        start = Some(match (start.take(), lo) {
            (None, lo) => lo,
            (Some(None), _) | (_, None) => None,
            (Some(Some(s)), Some(l)) => Some(if frac_cmp(&l, &s).is_lt() { l } else { s }),
        });
        end = Some(match (end.take(), hi) {
            (None, hi) => hi,
            (Some(None), _) | (_, None) => None,
            (Some(Some(e)), Some(h)) => Some(if frac_cmp(&h, &e).is_gt() { h } else { e }),
        });
    };
    let frac = |n: Int, d: Int| if d < Int::ZERO { (-n, -d) } else { (n, d) };
    // Vertices of P moving by `sign·(r0 + rw t)` against the edges of Q.
    let mut vertex_edges = |p: &[(Int, Int)], q: &[(Int, Int)], negate: bool| {
        let (r0, rw) = if negate {
            (
                (-f.r0.0.clone(), -f.r0.1.clone()),
                (-f.rw.0.clone(), -f.rw.1.clone()),
            )
        } else {
            (f.r0.clone(), f.rw.clone())
        };
        let m = q.len();
        for pi in p {
            for j in 0..m {
                let (qj, qk) = (&q[j], &q[(j + 1) % m]);
                let e = (&qk.0 - &qj.0, &qk.1 - &qj.1);
                // rel(t) = r0 + M (p_i − q_j) + rw t
                let rel0 = (
                    &r0.0 + &f.m * (&pi.0 - &qj.0),
                    &r0.1 + &f.m * (&pi.1 - &qj.1),
                );
                let (c0, c1) = (cross(&e, &rel0), cross(&e, &rw));
                // along the edge: e · rel(t) ∈ [0, M e·e]
                let (s0, s1) = (dot(&e, &rel0), dot(&e, &rw));
                let ee = &f.m * dot(&e, &e);
                if !c1.is_zero() {
                    let (tn, td) = frac(-c0, c1);
                    // s(t) = s0 + s1 tn/td ∈ [0, ee]  ⇔  s0 td + s1 tn ∈ [0, ee td]
                    let st = &s0 * &td + &s1 * &tn;
                    if st >= Int::ZERO && st <= &ee * &td {
                        touch(Some((tn.clone(), td.clone())), Some((tn, td)));
                    }
                } else if c0.is_zero() {
                    if s1.is_zero() {
                        if s0 >= Int::ZERO && s0 <= ee {
                            touch(None, None);
                        }
                    } else {
                        let t0 = frac(-s0.clone(), s1.clone());
                        let t1 = frac(&ee - &s0, s1);
                        let (lo, hi) = if frac_cmp(&t0, &t1).is_lt() {
                            (t0, t1)
                        } else {
                            (t1, t0)
                        };
                        touch(Some(lo), Some(hi));
                    }
                }
            }
        }
    };
    vertex_edges(&f.a, &f.b, false);
    vertex_edges(&f.b, &f.a, true);
    let (Some(start), Some(end)) = (start, end) else {
        return ContactInterval::Never;
    };
    // Interiors overlap somewhere inside iff they do at an inner instant.
    let one = (Int::ONE, Int::ONE);
    let inner = match (&start, &end) {
        (Some(s), Some(e)) if frac_cmp(s, e).is_lt() => {
            Some((&s.0 * &e.1 + &e.0 * &s.1, Int::from(2) * &s.1 * &e.1))
        }
        (Some(_), Some(_)) => None,
        (Some(s), None) => Some((&s.0 + &s.1, s.1.clone())),
        (None, Some(e)) => Some((&e.0 - &e.1, e.1.clone())),
        (None, None) => Some((Int::ZERO, one.1.clone())),
    };
    let penetrating = inner.is_some_and(|(tn, td)| f.interiors_overlap(&tn, &td));
    let rat = |x: Option<(Int, Int)>| x.map(|(n, d)| Rational::new(n, d));
    ContactInterval::During {
        start: rat(start),
        end: rat(end),
        penetrating,
    }
}

impl PairFrame {
    /// Whether the interiors overlap at `t = tn/td` (`td > 0`): no edge line
    /// of either polygon weakly separates them.
    fn interiors_overlap(&self, tn: &Int, td: &Int) -> bool {
        let shift = (
            &self.r0.0 * td + &self.rw.0 * tn,
            &self.r0.1 * td + &self.rw.1 * tn,
        );
        let mt = &self.m * td;
        let pa: Vec<(Int, Int)> = self
            .a
            .iter()
            .map(|p| (&shift.0 + &mt * &p.0, &shift.1 + &mt * &p.1))
            .collect();
        let pb: Vec<(Int, Int)> = self.b.iter().map(|p| (&mt * &p.0, &mt * &p.1)).collect();
        !(weakly_separates(&pa, &pb) || weakly_separates(&pb, &pa))
    }
}

/// Whether some edge line of `p` has all of `q` on its closed outer side.
fn weakly_separates(p: &[(Int, Int)], q: &[(Int, Int)]) -> bool {
    (0..p.len()).any(|i| {
        let (u, v) = (&p[i], &p[(i + 1) % p.len()]);
        let e = (&v.0 - &u.0, &v.1 - &u.1);
        q.iter()
            .all(|x| cross(&e, &(&x.0 - &u.0, &x.1 - &u.1)) <= Int::ZERO)
    })
}

/// Whether the interiors of two bodies overlap at time `t`.
pub fn interiors_overlap(world: &World, a: BodyId, b: BodyId, t: &Rational) -> bool {
    PairFrame::new(world, a, b).interiors_overlap(t.numer(), t.denom())
}

/// The brute-force engine: every active pair's next collision in one ordered set.
#[derive(Clone, Debug)]
pub struct Brute {
    method: PairMethod,
    queue: BTreeSet<(Time, BodyId, BodyId)>,
    pair_time: HashMap<(BodyId, BodyId), Time>,
    max_queued: usize,
    pair_computations: u64,
}

impl Brute {
    /// Compute every pair's next collision at time 0.
    pub fn new(world: &World, method: PairMethod) -> Brute {
        Brute::new_at(world, method, &Rational::zero())
    }

    /// Compute every pair's next collision at or after `now`, on the
    /// world's current motions: a pair that touches at `now` collides then
    /// only if its interiors overlap right after `now` (the rule of
    /// [`ContactInterval::next_contact`]).
    pub fn new_at(world: &World, method: PairMethod, now: &Rational) -> Brute {
        let mut brute = Brute {
            method,
            queue: BTreeSet::new(),
            pair_time: HashMap::new(),
            max_queued: 0,
            pair_computations: 0,
        };
        let n = world.len() as u32;
        for i in 0..n {
            for j in i + 1..n {
                brute.recompute(world, now, BodyId::new(i), BodyId::new(j));
            }
        }
        brute
    }

    fn recompute(&mut self, world: &World, now: &Rational, a: BodyId, b: BodyId) {
        let key = (a.min(b), a.max(b));
        if let Some(t) = self.pair_time.remove(&key) {
            self.queue.remove(&(t, key.0, key.1));
        }
        if !world.pair_active(a, b) {
            return;
        }
        self.pair_computations += 1;
        let next = contact_interval(world, key.0, key.1, self.method).next_contact(now);
        if let Some(t) = next {
            let t = Time::from_rational(t);
            if t <= *world.until() {
                self.queue.insert((t.clone(), key.0, key.1));
                self.pair_time.insert(key, t);
                self.max_queued = self.max_queued.max(self.queue.len());
            }
        }
    }

    /// The earliest collision time at most `limit` and every pair colliding then.
    pub fn next_collisions(&mut self, limit: &Time) -> Option<(Time, Vec<(BodyId, BodyId)>)> {
        let (t0, _, _) = self.queue.first()?.clone();
        if t0 > *limit {
            return None;
        }
        let pairs = self
            .queue
            .iter()
            .take_while(|(t, _, _)| *t == t0)
            .map(|(_, a, b)| (*a, *b))
            .collect();
        Some((t0, pairs))
    }

    /// After the world changed at `now`: recompute the reported pairs and
    /// every pair of a changed or removed body.
    pub fn update(
        &mut self,
        world: &World,
        now: &Rational,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) {
        for &(a, b) in reported {
            self.recompute(world, now, a, b);
        }
        let n = world.len() as u32;
        let mut done: BTreeSet<(BodyId, BodyId)> = BTreeSet::new();
        for &c in bodies {
            for o in 0..n {
                let o = BodyId::new(o);
                if o == c {
                    continue;
                }
                let key = (c.min(o), c.max(o));
                if done.insert(key) {
                    self.recompute(world, now, key.0, key.1);
                }
            }
        }
    }

    /// Number of queued pair times (the brute force's "certificates").
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// Largest number of queued pair times so far.
    pub fn max_queued(&self) -> usize {
        self.max_queued
    }

    /// Number of pair computations so far.
    pub fn pair_computations(&self) -> u64 {
        self.pair_computations
    }

    /// The earliest queued time, if any.
    pub fn next_time(&self) -> Option<&Time> {
        self.queue.first().map(|(t, _, _)| t)
    }

    /// Check every cached pair time against a fresh computation by the other
    /// method, and that no two active bodies overlap at the instant `at`.
    pub fn audit(&self, world: &World, now: &Rational, at: &Rational) -> Result<(), String> {
        let other = match self.method {
            PairMethod::Simple => PairMethod::Fast,
            PairMethod::Fast => PairMethod::Simple,
        };
        let n = world.len() as u32;
        for i in 0..n {
            for j in i + 1..n {
                let (a, b) = (BodyId::new(i), BodyId::new(j));
                if !world.pair_active(a, b) {
                    continue;
                }
                let fresh = contact_interval(world, a, b, other)
                    .next_contact(now)
                    .map(Time::from_rational)
                    .filter(|t| t <= world.until());
                let cached = self.pair_time.get(&(a, b)).cloned();
                if fresh != cached {
                    return Err(format!(
                        "pair ({}, {}): cached next contact {:?}, fresh {:?}",
                        world.body(a).id,
                        world.body(b).id,
                        cached,
                        fresh
                    ));
                }
                if interiors_overlap(world, a, b, at) {
                    return Err(format!(
                        "bodies {} and {} overlap at {}",
                        world.body(a).id,
                        world.body(b).id,
                        at
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Counters by event kind (for statistics).
pub type KindCounts = BTreeMap<String, u64>;

#[cfg(test)]
mod tests {
    use super::ContactInterval;
    use crate::num::Rational;

    fn r(n: i64) -> Rational {
        Rational::from_int(n.into())
    }

    #[test]
    fn a_resting_or_sliding_pair_rests_and_an_overlapping_one_does_not() {
        let during = |start: Option<i64>, end: Option<i64>, penetrating| ContactInterval::During {
            start: start.map(r),
            end: end.map(r),
            penetrating,
        };
        // in contact from 1 on, for ever, or until 5
        assert_eq!(during(Some(1), None, false).rests_after(&r(1)), Some(None));
        assert_eq!(
            during(Some(1), Some(5), false).rests_after(&r(3)),
            Some(Some(r(5)))
        );
        // the contact ends at the instant, or begins later
        assert_eq!(during(Some(1), Some(3), false).rests_after(&r(3)), None);
        assert_eq!(during(Some(4), None, false).rests_after(&r(3)), None);
        // interiors that overlap: a collision (one a structure may have
        // missed), never a resting contact
        assert_eq!(during(Some(1), None, true).rests_after(&r(1)), None);
        assert_eq!(ContactInterval::Never.rests_after(&r(1)), None);
    }
}
