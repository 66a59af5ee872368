//! Kinetic sort-and-sweep: the kinetic broad phase a kinetic-data-structures
//! expert would pick, made exact.
//!
//! For each axis, the endpoints of the bodies' axis-aligned bounding boxes
//! (in the body frame, translated with the body) are kept in a sorted doubly
//! linked list. Each pair of neighbours in a list carries a *swap
//! certificate*: the endpoints' coordinates are linear in time, and the
//! certificate fails at the exact rational time their order must change.
//! A pair of bodies is a *candidate* while their closed boxes overlap on both
//! axes; for every candidate the exact next contact time is computed with the
//! library's pair machinery ([`kss::brute::contact_interval`]) and kept in an
//! ordered set of collision times.
//!
//! ## Order and ties
//!
//! The lists are sorted by the order valid *just after* the current time:
//! by coordinate, then by velocity, then minimum endpoints before maximum
//! endpoints (so that boxes touching with no relative motion count as
//! overlapping). A swap of a maximum before a minimum starts an overlap on
//! that axis; the pair becomes a candidate if the boxes' closed extents on
//! the other axis overlap at that instant (exactly, so that corner contacts at
//! that very instant are not lost). A swap of a minimum before a maximum ends
//! the overlap; the pair stops being a candidate, but a collision already
//! scheduled at that instant is kept (the boxes still touch then). Swaps due
//! at an instant are processed before the collisions of that instant.
//!
//! ## Same answers as brute
//!
//! A candidate's next contact is computed from the last time either body
//! changed its motion (or the pair was reported), exactly as the brute force
//! caches it, so both report identical events; the tests check this.

use std::cmp::Ordering;
use std::collections::{BTreeSet, HashMap, HashSet};

use kss::brute::{contact_interval, PairMethod};
use kss::num::{Rational, Sign, Time};
use kss::sim::{EventKey, EventQueue};
use kss::world::{BodyId, World};
use kss::Scenario;

use kss::{Collisions, Finder, RunError};

use crate::exact::{rational, BUDGET};
use crate::{Counters, Deadline, Event, Failure};

const NIL: u32 = u32::MAX;

/// One axis: the endpoints `2·body` (minimum) and `2·body + 1` (maximum).
#[derive(Clone, Debug)]
struct Axis {
    /// Coordinate at time 0 of the current piece (extrapolated).
    a: Vec<Rational>,
    /// Velocity.
    b: Vec<Rational>,
    /// Doubles near `a` and `b`, for the filter of [`Axis::cmp_at`].
    af: Vec<f64>,
    bf: Vec<f64>,
    prev: Vec<u32>,
    next: Vec<u32>,
    /// The certificate between an endpoint and its successor.
    cert: Vec<Option<EventKey>>,
}

fn is_max(e: u32) -> bool {
    e & 1 == 1
}

fn body_of(e: u32) -> u32 {
    e >> 1
}

impl Axis {
    /// Exact comparison of the coordinates of endpoints `e1` and `e2` at `t`.
    fn cmp_at(&self, e1: u32, e2: u32, t: &Rational, tf: f64) -> Ordering {
        let (i, j) = (e1 as usize, e2 as usize);
        let approx = (self.af[i] - self.af[j]) + (self.bf[i] - self.bf[j]) * tf;
        let scale =
            self.af[i].abs() + self.af[j].abs() + (self.bf[i].abs() + self.bf[j].abs()) * tf.abs();
        if approx.is_finite() && approx.abs() > scale * 1e-14 {
            return if approx > 0.0 {
                Ordering::Greater
            } else {
                Ordering::Less
            };
        }
        let d = self.a[i]
            .sub(&self.a[j])
            .add(&self.b[i].sub(&self.b[j]).mul(t));
        d.sign().to_ordering()
    }

    /// Whether the closed extents of bodies `p` and `q` overlap at `t`.
    fn closed_overlap(&self, p: u32, q: u32, t: &Rational, tf: f64) -> bool {
        self.cmp_at(2 * p, 2 * q + 1, t, tf) != Ordering::Greater
            && self.cmp_at(2 * q, 2 * p + 1, t, tf) != Ordering::Greater
    }
}

/// The kinetic sort-and-sweep structure.
#[derive(Debug)]
pub struct Sweep {
    axes: [Axis; 2],
    /// Swap certificates: `(axis, left endpoint)`.
    certs: EventQueue<Time, (u8, u32)>,
    collisions: BTreeSet<(Time, BodyId, BodyId)>,
    pair_time: HashMap<(BodyId, BodyId), Time>,
    neighbours: Vec<HashSet<u32>>,
    last_change: Vec<Rational>,
    reported_at: HashMap<(BodyId, BodyId), Rational>,
    /// Body-frame bounding boxes `[x_min, x_max, y_min, y_max]`.
    local_box: Vec<[Rational; 4]>,
    until: Time,
    swaps: u64,
    pair_tests: u64,
    max_certs: u64,
    /// The run gives up once this passes.
    deadline: Deadline,
}

fn key(a: BodyId, b: BodyId) -> (BodyId, BodyId) {
    (a.min(b), a.max(b))
}

impl Sweep {
    /// Builds the sorted lists and the candidates at time 0.
    pub fn new(world: &World) -> Sweep {
        let n = world.len();
        let empty_axis = || Axis {
            a: vec![Rational::zero(); 2 * n],
            b: vec![Rational::zero(); 2 * n],
            af: vec![0.0; 2 * n],
            bf: vec![0.0; 2 * n],
            prev: vec![NIL; 2 * n],
            next: vec![NIL; 2 * n],
            cert: vec![None; 2 * n],
        };
        let local_box = world
            .bodies()
            .iter()
            .map(|b| {
                let bx = b.shape.bounds();
                bx.map(|c| Rational::from_f64(c).expect("finite vertex"))
            })
            .collect();
        let mut s = Sweep {
            axes: [empty_axis(), empty_axis()],
            certs: EventQueue::new(),
            collisions: BTreeSet::new(),
            pair_time: HashMap::new(),
            neighbours: vec![HashSet::new(); n],
            last_change: vec![Rational::zero(); n],
            reported_at: HashMap::new(),
            local_box,
            until: world.until().clone(),
            swaps: 0,
            pair_tests: 0,
            max_certs: 0,
            deadline: Deadline::NONE,
        };
        for i in 0..n as u32 {
            s.set_motion(world, i);
        }
        let zero = Rational::zero();
        for ax in 0..2 {
            let axis = &mut s.axes[ax];
            let mut order: Vec<u32> = (0..2 * n as u32).collect();
            order.sort_by(|&p, &q| {
                let (i, j) = (p as usize, q as usize);
                axis.a[i]
                    .cmp(&axis.a[j])
                    .then_with(|| axis.b[i].cmp(&axis.b[j]))
                    .then_with(|| is_max(p).cmp(&is_max(q)))
                    .then_with(|| p.cmp(&q))
            });
            for w in order.windows(2) {
                axis.next[w[0] as usize] = w[1];
                axis.prev[w[1] as usize] = w[0];
            }
            for &e in &order {
                s.schedule_cert(ax, e, &zero);
            }
            if ax == 0 {
                // initial candidates: sweep the x list, test y exactly
                let mut active: Vec<u32> = Vec::new();
                let mut slot = vec![usize::MAX; n];
                for &e in &order {
                    let body = body_of(e);
                    if is_max(e) {
                        let at = slot[body as usize];
                        active.swap_remove(at);
                        if at < active.len() {
                            slot[active[at] as usize] = at;
                        }
                    } else {
                        let mut found = Vec::new();
                        for &other in &active {
                            if s.axes[1].closed_overlap(body, other, &zero, 0.0) {
                                found.push(other);
                            }
                        }
                        for other in found {
                            s.add_candidate(world, BodyId::new(body), BodyId::new(other), &zero);
                        }
                        slot[body as usize] = active.len();
                        active.push(body);
                    }
                }
            }
        }
        s.note_certs();
        s
    }

    fn set_motion(&mut self, world: &World, body: u32) {
        let b = world.body(BodyId::new(body));
        let (o, v) = (b.traj.origin(), b.traj.velocity());
        let bx = &self.local_box[body as usize];
        for (ax, (oc, vc)) in [(&o.x, &v.x), (&o.y, &v.y)].into_iter().enumerate() {
            let axis = &mut self.axes[ax];
            for (k, e) in [2 * body, 2 * body + 1].into_iter().enumerate() {
                let a = oc.add(&bx[2 * ax + k]);
                axis.af[e as usize] = a.to_f64();
                axis.bf[e as usize] = vc.to_f64();
                axis.a[e as usize] = a;
                axis.b[e as usize] = vc.clone();
            }
        }
    }

    /// When the order "`l` before `r`" (neighbours) must change, at or after `now`.
    fn failure_time(&self, ax: usize, l: u32, r: u32, now: &Rational) -> Option<Rational> {
        let axis = &self.axes[ax];
        let (i, j) = (l as usize, r as usize);
        let db = axis.b[j].sub(&axis.b[i]);
        let da = axis.a[j].sub(&axis.a[i]);
        match db.sign() {
            Sign::Negative => {
                // da + db·t = 0
                let t = da.div(&db.neg());
                Some(if t < *now { now.clone() } else { t })
            }
            Sign::Zero => match da.sign() {
                Sign::Negative => Some(now.clone()),
                Sign::Zero if is_max(l) && !is_max(r) => Some(now.clone()),
                _ => None,
            },
            Sign::Positive => None,
        }
    }

    fn schedule_cert(&mut self, ax: usize, l: u32, now: &Rational) {
        if let Some(k) = self.axes[ax].cert[l as usize].take() {
            self.certs.cancel(k);
        }
        let r = self.axes[ax].next[l as usize];
        if r == NIL {
            return;
        }
        if let Some(t) = self.failure_time(ax, l, r, now) {
            let t = Time::from_rational(t);
            if t <= self.until {
                let k = self.certs.schedule(t, 0, (ax as u8, l));
                self.axes[ax].cert[l as usize] = Some(k);
            }
        }
    }

    fn note_certs(&mut self) {
        let live = (self.certs.len() + self.collisions.len()) as u64;
        self.max_certs = self.max_certs.max(live);
    }

    fn set_collision(&mut self, pair: (BodyId, BodyId), t: Option<Time>) {
        if let Some(old) = self.pair_time.remove(&pair) {
            self.collisions.remove(&(old, pair.0, pair.1));
        }
        if let Some(t) = t {
            self.collisions.insert((t.clone(), pair.0, pair.1));
            self.pair_time.insert(pair, t);
        }
    }

    /// The pair's next contact from `since` on, if at or after `not_before`.
    fn compute(
        &mut self,
        world: &World,
        pair: (BodyId, BodyId),
        since: &Rational,
        not_before: &Rational,
    ) {
        self.pair_tests += 1;
        let next = contact_interval(world, pair.0, pair.1, PairMethod::Fast)
            .next_contact(since)
            .filter(|t| t >= not_before)
            .map(Time::from_rational)
            .filter(|t| *t <= self.until);
        self.set_collision(pair, next);
    }

    fn add_candidate(&mut self, world: &World, a: BodyId, b: BodyId, now: &Rational) {
        if !world.pair_active(a, b) || !self.neighbours[a.index()].insert(b.raw()) {
            return;
        }
        self.neighbours[b.index()].insert(a.raw());
        let pair = key(a, b);
        let mut since = self.last_change[a.index()]
            .clone()
            .max(self.last_change[b.index()].clone());
        if let Some(r) = self.reported_at.get(&pair) {
            since = since.max(r.clone());
        }
        self.compute(world, pair, &since, now);
    }

    fn remove_candidate(&mut self, a: BodyId, b: BodyId, now: &Rational) {
        if !self.neighbours[a.index()].remove(&b.raw()) {
            return;
        }
        self.neighbours[b.index()].remove(&a.raw());
        let pair = key(a, b);
        // a collision at this very instant stays (the boxes still touch now)
        if let Some(t) = self.pair_time.get(&pair) {
            let now_t = Time::from_rational(now.clone());
            if *t > now_t {
                self.set_collision(pair, None);
            }
        }
    }

    fn process_swap(&mut self, world: &World, ax: usize, l: u32, t: &Rational) {
        self.swaps += 1;
        let axis = &mut self.axes[ax];
        axis.cert[l as usize] = None; // just popped
        let r = axis.next[l as usize];
        let (p, n) = (axis.prev[l as usize], axis.next[r as usize]);
        // p, l, r, n  ->  p, r, l, n
        if p != NIL {
            axis.next[p as usize] = r;
        }
        axis.prev[r as usize] = p;
        axis.next[r as usize] = l;
        axis.prev[l as usize] = r;
        axis.next[l as usize] = n;
        if n != NIL {
            axis.prev[n as usize] = l;
        }
        if let Some(k) = axis.cert[r as usize].take() {
            self.certs.cancel(k);
        }
        if p != NIL {
            self.schedule_cert(ax, p, t);
        }
        self.schedule_cert(ax, r, t);
        self.schedule_cert(ax, l, t);
        let (bl, br) = (body_of(l), body_of(r));
        if bl != br && is_max(l) != is_max(r) {
            if is_max(l) {
                // a maximum passed behind a minimum: overlap starts on this axis
                let tf = t.to_f64();
                if self.axes[1 - ax].closed_overlap(bl, br, t, tf) {
                    self.add_candidate(world, BodyId::new(bl), BodyId::new(br), t);
                }
            } else {
                self.remove_candidate(BodyId::new(bl), BodyId::new(br), t);
            }
        }
    }

    fn unlink(&mut self, ax: usize, e: u32, now: &Rational) {
        let axis = &mut self.axes[ax];
        let (p, n) = (axis.prev[e as usize], axis.next[e as usize]);
        if p != NIL {
            axis.next[p as usize] = n;
        }
        if n != NIL {
            axis.prev[n as usize] = p;
        }
        axis.prev[e as usize] = NIL;
        axis.next[e as usize] = NIL;
        if let Some(k) = axis.cert[e as usize].take() {
            self.certs.cancel(k);
        }
        if p != NIL {
            self.schedule_cert(ax, p, now);
        }
    }

    /// Number of swap certificates processed so far.
    pub fn swaps(&self) -> u64 {
        self.swaps
    }
}

impl Finder for Sweep {
    fn next_collisions(&mut self, world: &World, limit: &Time) -> Result<Collisions, RunError> {
        if self.deadline.passed() {
            return Err(RunError::Aborted(BUDGET.into()));
        }
        loop {
            let swap_due = match (self.certs.peek(), self.collisions.first()) {
                (Some((_, ts, _, _)), c) => ts <= limit && c.is_none_or(|(tc, _, _)| ts <= tc),
                (None, _) => false,
            };
            if swap_due {
                let (_, ts, (ax, l)) = self.certs.pop().expect("peeked");
                let t = ts.as_rational().expect("swap times are rational").clone();
                self.process_swap(world, ax as usize, l, &t);
                self.note_certs();
                continue;
            }
            let Some((t0, _, _)) = self.collisions.first().cloned() else {
                return Ok(None);
            };
            if t0 > *limit {
                return Ok(None);
            }
            let pairs = self
                .collisions
                .iter()
                .take_while(|(t, _, _)| *t == t0)
                .map(|(_, a, b)| (*a, *b))
                .collect();
            return Ok(Some((t0, pairs)));
        }
    }

    fn update(
        &mut self,
        world: &World,
        now: &Time,
        bodies: &[BodyId],
        reported: &[(BodyId, BodyId)],
    ) -> Result<(), RunError> {
        let now = rational(now)?;
        for &(a, b) in reported {
            let pair = key(a, b);
            self.reported_at.insert(pair, now.clone());
            if world.pair_active(a, b) && self.neighbours[a.index()].contains(&b.raw()) {
                self.compute(world, pair, now, now);
            } else {
                self.set_collision(pair, None);
            }
        }
        for &c in bodies {
            self.last_change[c.index()] = now.clone();
            if !world.body(c).alive {
                for ax in 0..2 {
                    self.unlink(ax, 2 * c.raw(), now);
                    self.unlink(ax, 2 * c.raw() + 1, now);
                }
                let others: Vec<u32> = self.neighbours[c.index()].drain().collect();
                for o in others {
                    self.neighbours[o as usize].remove(&c.raw());
                    self.set_collision(key(c, BodyId::new(o)), None);
                }
                continue;
            }
            self.set_motion(world, c.raw());
            for ax in 0..2 {
                for e in [2 * c.raw(), 2 * c.raw() + 1] {
                    let p = self.axes[ax].prev[e as usize];
                    if p != NIL {
                        self.schedule_cert(ax, p, now);
                    }
                    self.schedule_cert(ax, e, now);
                }
            }
            let others: Vec<u32> = self.neighbours[c.index()].iter().copied().collect();
            for o in others {
                self.compute(world, key(c, BodyId::new(o)), now, now);
            }
        }
        self.note_certs();
        Ok(())
    }

    fn insert(&mut self, _world: &World, _now: &Time, _b: BodyId) -> Result<(), RunError> {
        Err(RunError::Aborted(
            "the sort-and-sweep baseline does not take insertions".into(),
        ))
    }

    fn next_time(&self) -> Option<Time> {
        let swap = self.certs.peek().map(|(_, t, _, _)| t);
        let collision = self.collisions.first().map(|(t, _, _)| t);
        match (swap, collision) {
            (Some(s), Some(c)) => Some(s.min(c).clone()),
            (s, c) => s.or(c).cloned(),
        }
    }

    fn certificates(&self) -> (u64, u64) {
        (self.certs.len() as u64, self.max_certs)
    }

    fn internal_events(&self) -> std::collections::BTreeMap<String, u64> {
        std::collections::BTreeMap::from([("swap".to_string(), self.swaps)])
    }

    fn work(&self) -> std::collections::BTreeMap<String, u64> {
        std::collections::BTreeMap::from([("pair_tests".to_string(), self.pair_tests)])
    }
}

/// Runs the kinetic sort-and-sweep on `scenario`.
pub fn run(scenario: &Scenario, deadline: Deadline) -> Result<(Vec<Event>, Counters), Failure> {
    crate::exact::run(scenario, &mut |world| {
        let mut sweep = Sweep::new(world);
        sweep.deadline = deadline;
        Box::new(sweep)
    })
}
