//! The parry2d-f64 baselines: what a practitioner with a geometry library
//! would write. Both work in doubles on their own copy of the scene, and
//! follow the contract's semantics as closely as doubles allow:
//!
//! - collisions at one instant (equal doubles) are reported sorted by id,
//!   before the flight-plan changes of that instant;
//! - `stop` ends after the first instant, `remove` takes both polygons out
//!   (fixed ones stay), `bounce` applies the contract's elastic impulse
//!   along the normal parry reports at the time of impact (masses from the
//!   area, fixed polygons infinitely heavy), pair by pair in id order.
//!
//! Time of impact is `parry2d_f64::query::cast_shapes` between
//! `ConvexPolygon`s with `stop_at_penetration: false`, so a touching pair
//! that separates after a bounce is not hit again. parry is tolerance-based:
//! its times are compared with the exact reference, never corrected.

use std::cmp::Ordering;
use std::collections::{BTreeSet, HashMap, HashSet};

use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::{cast_shapes, ShapeCastOptions};
use parry2d_f64::shape::ConvexPolygon;

use kss::{CollisionMode, Scenario};

use crate::{ordered, Counters, Deadline, Event, Failure};

/// A double with a total order (for ordered sets of event times).
#[derive(Clone, Copy, Debug)]
struct T(f64);

impl PartialEq for T {
    fn eq(&self, other: &Self) -> bool {
        self.0.total_cmp(&other.0).is_eq()
    }
}
impl Eq for T {}
impl PartialOrd for T {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for T {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// A polygon of the floating-point scene.
struct Body {
    id: String,
    shape: ConvexPolygon,
    /// Body-frame bounding box `[x_min, x_max, y_min, y_max]`.
    local: [f64; 4],
    fixed: bool,
    alive: bool,
    /// Position at time `tref`.
    p: Vector,
    tref: f64,
    v: Vector,
    inv_mass: f64,
}

impl Body {
    fn pos(&self, t: f64) -> Vector {
        self.p + self.v * (t - self.tref)
    }

    fn set_velocity(&mut self, t: f64, v: Vector) {
        self.p = self.pos(t);
        self.tref = t;
        self.v = v;
    }

    fn aabb(&self, t: f64) -> [f64; 4] {
        let p = self.pos(t);
        [
            self.local[0] + p.x,
            self.local[1] + p.x,
            self.local[2] + p.y,
            self.local[3] + p.y,
        ]
    }
}

/// The floating-point scene: bodies, pending flight-plan changes, the mode.
struct Scene {
    bodies: Vec<Body>,
    /// `(time, body, velocity)` sorted by time (stable).
    changes: Vec<(f64, usize, Vector)>,
    next_change: usize,
    until: f64,
    mode: CollisionMode,
    casts: u64,
}

impl Scene {
    fn new(scenario: &Scenario) -> Result<Scene, Failure> {
        let mut index = HashMap::new();
        let mut bodies = Vec::with_capacity(scenario.polygons.len());
        for (i, p) in scenario.polygons.iter().enumerate() {
            let pts: Vec<Vector> = p.vertices.iter().map(|v| Vector::new(v[0], v[1])).collect();
            let shape = ConvexPolygon::from_convex_polyline_unmodified(pts)
                .ok_or_else(|| Failure::Unsupported(format!("parry refuses polygon {:?}", p.id)))?;
            let mut local = [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ];
            let mut twice_area = 0.0;
            let n = p.vertices.len();
            for (k, v) in p.vertices.iter().enumerate() {
                local[0] = local[0].min(v[0]);
                local[1] = local[1].max(v[0]);
                local[2] = local[2].min(v[1]);
                local[3] = local[3].max(v[1]);
                let w = p.vertices[(k + 1) % n];
                twice_area += v[0] * w[1] - v[1] * w[0];
            }
            index.insert(p.id.as_str(), i);
            bodies.push(Body {
                id: p.id.clone(),
                shape,
                local,
                fixed: p.fixed,
                alive: true,
                p: Vector::new(p.position[0], p.position[1]),
                tref: 0.0,
                v: Vector::new(p.velocity[0], p.velocity[1]),
                inv_mass: if p.fixed { 0.0 } else { 2.0 / twice_area },
            });
        }
        let mut changes: Vec<(f64, usize, Vector)> = scenario
            .flight_plan_changes
            .iter()
            .filter(|c| c.time <= scenario.until)
            .filter_map(|c| {
                let &b = index.get(c.id.as_str())?;
                Some((c.time, b, Vector::new(c.velocity[0], c.velocity[1])))
            })
            .collect();
        changes.sort_by(|x, y| x.0.total_cmp(&y.0));
        Ok(Scene {
            bodies,
            changes,
            next_change: 0,
            until: scenario.until,
            mode: scenario.on_collision,
            casts: 0,
        })
    }

    fn pair_active(&self, a: usize, b: usize) -> bool {
        let (x, y) = (&self.bodies[a], &self.bodies[b]);
        a != b && x.alive && y.alive && !(x.fixed && y.fixed)
    }

    fn next_change_time(&self) -> Option<f64> {
        self.changes.get(self.next_change).map(|c| c.0)
    }

    /// Applies every change at exactly `t`; returns the changed bodies.
    fn apply_changes_at(&mut self, t: f64) -> Vec<usize> {
        let mut changed = Vec::new();
        while let Some(&(ct, b, v)) = self.changes.get(self.next_change) {
            if ct != t {
                break;
            }
            self.next_change += 1;
            if self.bodies[b].alive {
                self.bodies[b].set_velocity(t, v);
                if !changed.contains(&b) {
                    changed.push(b);
                }
            }
        }
        changed
    }

    /// First contact of `a` and `b` within `[now, now + horizon]`: the time
    /// and parry's normal from `a` towards `b`.
    fn toi(&mut self, a: usize, b: usize, now: f64, horizon: f64) -> Option<(f64, Vector)> {
        if horizon < 0.0 {
            return None;
        }
        self.casts += 1;
        let (x, y) = (&self.bodies[a], &self.bodies[b]);
        let options = ShapeCastOptions {
            max_time_of_impact: horizon,
            target_distance: 0.0,
            stop_at_penetration: false,
            compute_impact_geometry_on_penetration: true,
        };
        let hit = cast_shapes(
            &Pose::from_translation(x.pos(now)),
            x.v,
            &x.shape,
            &Pose::from_translation(y.pos(now)),
            y.v,
            &y.shape,
            options,
        )
        .ok()
        .flatten()?;
        let t = now + hit.time_of_impact;
        (t <= self.until).then_some((t, hit.normal1))
    }

    /// The pairs sorted by id, as `(a, b)` indices with `id(a) < id(b)`.
    fn sort_pairs(&self, pairs: &mut [(usize, usize)]) {
        for p in pairs.iter_mut() {
            if self.bodies[p.0].id.as_bytes() > self.bodies[p.1].id.as_bytes() {
                *p = (p.1, p.0);
            }
        }
        pairs.sort_by(|x, y| {
            let k = |p: &(usize, usize)| {
                (
                    self.bodies[p.0].id.as_bytes().to_vec(),
                    self.bodies[p.1].id.as_bytes().to_vec(),
                )
            };
            k(x).cmp(&k(y))
        });
    }

    fn event(&self, t: f64, a: usize, b: usize) -> Event {
        let (x, y) = ordered(&self.bodies[a].id, &self.bodies[b].id);
        Event {
            time: t,
            a: x.to_string(),
            b: y.to_string(),
        }
    }

    /// The contract's elastic impulse along `n` (from `a` to `b`), if the
    /// pair approaches along it. Returns whether velocities changed.
    fn bounce(&mut self, t: f64, a: usize, b: usize, n: Vector) -> bool {
        let len = n.length();
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return false;
        }
        let n = n / len;
        let (ia, ib) = (self.bodies[a].inv_mass, self.bodies[b].inv_mass);
        let (va, vb) = (self.bodies[a].v, self.bodies[b].v);
        let u = (vb - va).dot(n);
        if u >= 0.0 || ia + ib == 0.0 {
            return false;
        }
        let j = -2.0 * u / (ia + ib);
        if ia > 0.0 {
            self.bodies[a].set_velocity(t, va - n * (j * ia));
        }
        if ib > 0.0 {
            self.bodies[b].set_velocity(t, vb + n * (j * ib));
        }
        true
    }
}

/// At most this many rounds of collisions of one pair at one instant.
const MAX_ROUNDS: u32 = 8;

/// Event-driven all-pairs time of impact with parry2d-f64.
pub fn run_toi(scenario: &Scenario, deadline: Deadline) -> Result<(Vec<Event>, Counters), Failure> {
    let mut s = Scene::new(scenario)?;
    let n = s.bodies.len();
    let mut queue: BTreeSet<(T, usize, usize)> = BTreeSet::new();
    let mut pair: HashMap<(usize, usize), (f64, Vector)> = HashMap::new();
    let mut max_queued = 0usize;
    let mut events = Vec::new();
    let mut changes = 0u64;
    let mut instant = f64::NAN;
    let mut rounds: HashMap<(usize, usize), u32> = HashMap::new();

    fn recompute(
        s: &mut Scene,
        queue: &mut BTreeSet<(T, usize, usize)>,
        pair: &mut HashMap<(usize, usize), (f64, Vector)>,
        a: usize,
        b: usize,
        now: f64,
    ) {
        let k = (a.min(b), a.max(b));
        if let Some((t, _)) = pair.remove(&k) {
            queue.remove(&(T(t), k.0, k.1));
        }
        if !s.pair_active(k.0, k.1) {
            return;
        }
        if let Some((t, normal)) = s.toi(k.0, k.1, now, s.until - now) {
            queue.insert((T(t), k.0, k.1));
            pair.insert(k, (t, normal));
        }
    }

    for i in 0..n {
        if deadline.passed() {
            return Err(Failure::Budget);
        }
        for j in i + 1..n {
            recompute(&mut s, &mut queue, &mut pair, i, j, 0.0);
        }
    }
    max_queued = max_queued.max(queue.len());
    loop {
        if deadline.passed() {
            return Err(Failure::Budget);
        }
        let tc = queue.first().map(|x| x.0 .0);
        let tch = s.next_change_time();
        match (tc, tch) {
            (Some(tc), tch) if tch.is_none_or(|ch| tc <= ch) => {
                if tc != instant {
                    instant = tc;
                    rounds.clear();
                }
                let mut pairs: Vec<(usize, usize)> = queue
                    .iter()
                    .take_while(|x| x.0 .0 == tc)
                    .map(|x| (x.1, x.2))
                    .collect();
                s.sort_pairs(&mut pairs);
                for &(a, b) in &pairs {
                    let r = rounds.entry((a.min(b), a.max(b))).or_insert(0);
                    *r += 1;
                    if *r == 1 {
                        events.push(s.event(tc, a, b));
                    }
                }
                match s.mode {
                    CollisionMode::Stop => break,
                    CollisionMode::Remove => {
                        let mut removed = Vec::new();
                        for &(a, b) in &pairs {
                            for x in [a, b] {
                                if s.bodies[x].alive && !s.bodies[x].fixed {
                                    s.bodies[x].alive = false;
                                    removed.push(x);
                                }
                            }
                        }
                        for &(a, b) in &pairs {
                            recompute(&mut s, &mut queue, &mut pair, a, b, tc);
                        }
                        for x in removed {
                            for o in 0..n {
                                if o != x {
                                    let k = (x.min(o), x.max(o));
                                    if let Some((t, _)) = pair.remove(&k) {
                                        queue.remove(&(T(t), k.0, k.1));
                                    }
                                }
                            }
                        }
                    }
                    CollisionMode::Bounce => {
                        let mut changed: Vec<usize> = Vec::new();
                        for &(a, b) in &pairs {
                            let k = (a.min(b), a.max(b));
                            let Some(&(_, normal)) = pair.get(&k) else {
                                continue;
                            };
                            // parry's normal points from k.0 to k.1
                            let (from, to) = (k.0, k.1);
                            if s.bounce(tc, from, to, normal) {
                                for x in [from, to] {
                                    if !changed.contains(&x) {
                                        changed.push(x);
                                    }
                                }
                            }
                        }
                        let mut done: HashSet<(usize, usize)> = HashSet::new();
                        for &(a, b) in &pairs {
                            let k = (a.min(b), a.max(b));
                            done.insert(k);
                            if rounds.get(&k).copied().unwrap_or(0) >= MAX_ROUNDS {
                                // give up on this pair at this instant
                                if let Some((t, _)) = pair.remove(&k) {
                                    queue.remove(&(T(t), k.0, k.1));
                                }
                                continue;
                            }
                            recompute(&mut s, &mut queue, &mut pair, a, b, tc);
                        }
                        for &c in &changed {
                            for o in 0..n {
                                let k = (c.min(o), c.max(o));
                                if o != c && done.insert(k) {
                                    recompute(&mut s, &mut queue, &mut pair, c, o, tc);
                                }
                            }
                        }
                    }
                }
            }
            (_, Some(ch)) => {
                let changed = s.apply_changes_at(ch);
                changes += 1;
                for &c in &changed {
                    for o in 0..n {
                        if o != c {
                            recompute(&mut s, &mut queue, &mut pair, c, o, ch);
                        }
                    }
                }
            }
            (_, None) => break,
        }
        max_queued = max_queued.max(queue.len());
    }
    let collisions = events.len() as u64;
    Ok((
        events,
        Counters {
            collisions,
            events: collisions + changes,
            certificates_max: max_queued as u64,
            pair_tests: s.casts,
            ..Default::default()
        },
    ))
}

/// Fixed time step `dt` with continuous collision detection: each step (cut
/// at flight-plan change times) gathers the pairs whose swept bounding boxes
/// overlap (sort and sweep on x), casts them with parry over the step, and
/// resolves the earliest impacts; in `bounce` mode the rest of the step is
/// re-cast after each resolved instant, at most 8 times per step (Box2D's
/// default number of TOI sub-steps), and impacts left after that are not
/// seen.
pub fn run_step(
    scenario: &Scenario,
    dt: f64,
    deadline: Deadline,
) -> Result<(Vec<Event>, Counters), Failure> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(Failure::Unsupported(format!("time step {dt}")));
    }
    const MAX_SUBSTEPS: u32 = 8;
    let mut s = Scene::new(scenario)?;
    let mut events = Vec::new();
    let mut steps = 0u64;
    let mut substeps = 0u64;
    let mut t = 0.0f64;
    let mut k = 0u64;
    let mut rounds: HashMap<(usize, usize), u32> = HashMap::new();
    let mut instant = f64::NAN;
    'run: while t < s.until {
        if deadline.passed() {
            return Err(Failure::Budget);
        }
        let boundary = ((k + 1) as f64 * dt).min(s.until);
        let t_end = match s.next_change_time() {
            Some(ch) if ch < boundary => ch,
            _ => boundary,
        };
        if t_end >= boundary {
            k += 1;
        }
        steps += 1;
        let mut sub = 0;
        loop {
            let mut hits = candidate_hits(&mut s, t, t_end);
            if hits.is_empty() {
                break;
            }
            hits.sort_by(|x, y| x.0.total_cmp(&y.0));
            match s.mode {
                CollisionMode::Stop => {
                    let t1 = hits[0].0;
                    let mut pairs: Vec<(usize, usize)> = hits
                        .iter()
                        .take_while(|h| h.0 == t1)
                        .map(|h| (h.1, h.2))
                        .collect();
                    s.sort_pairs(&mut pairs);
                    for (a, b) in pairs {
                        events.push(s.event(t1, a, b));
                    }
                    break 'run;
                }
                CollisionMode::Remove => {
                    let mut i = 0;
                    while i < hits.len() {
                        let t1 = hits[i].0;
                        let mut pairs = Vec::new();
                        while i < hits.len() && hits[i].0 == t1 {
                            let (a, b) = (hits[i].1, hits[i].2);
                            if s.pair_active(a, b) {
                                pairs.push((a, b));
                            }
                            i += 1;
                        }
                        s.sort_pairs(&mut pairs);
                        for &(a, b) in &pairs {
                            events.push(s.event(t1, a, b));
                        }
                        for (a, b) in pairs {
                            for x in [a, b] {
                                if !s.bodies[x].fixed {
                                    s.bodies[x].alive = false;
                                }
                            }
                        }
                    }
                    break;
                }
                CollisionMode::Bounce => {
                    let t1 = hits[0].0;
                    if t1 != instant {
                        instant = t1;
                        rounds.clear();
                    }
                    let mut group: Vec<(usize, usize, Vector)> = hits
                        .iter()
                        .take_while(|h| h.0 == t1)
                        .map(|h| (h.1, h.2, h.3))
                        .collect();
                    group.sort_by(|x, y| {
                        let k = |p: &(usize, usize, Vector)| {
                            let (a, b) = ordered(&s.bodies[p.0].id, &s.bodies[p.1].id);
                            (a.as_bytes().to_vec(), b.as_bytes().to_vec())
                        };
                        k(x).cmp(&k(y))
                    });
                    for &(a, b, normal) in &group {
                        let r = rounds.entry((a.min(b), a.max(b))).or_insert(0);
                        *r += 1;
                        if *r == 1 {
                            events.push(s.event(t1, a, b));
                        }
                        s.bounce(t1, a, b, normal);
                    }
                    sub += 1;
                    substeps += 1;
                    t = t1;
                    if sub >= MAX_SUBSTEPS {
                        break;
                    }
                }
            }
        }
        t = t_end;
        if s.next_change_time() == Some(t_end) {
            s.apply_changes_at(t_end);
        }
    }
    let collisions = events.len() as u64;
    Ok((
        events,
        Counters {
            collisions,
            events: steps + substeps,
            certificates_max: 0,
            pair_tests: s.casts,
            ..Default::default()
        },
    ))
}

/// Impacts within `[t, t_end]` of the pairs whose swept boxes overlap:
/// `(time, a, b, normal from a to b)` with `a < b` as indices.
fn candidate_hits(s: &mut Scene, t: f64, t_end: f64) -> Vec<(f64, usize, usize, Vector)> {
    let mut boxes: Vec<(usize, [f64; 4])> = Vec::new();
    for (i, b) in s.bodies.iter().enumerate() {
        if !b.alive {
            continue;
        }
        let (p, q) = (b.aabb(t), b.aabb(t_end));
        boxes.push((
            i,
            [
                p[0].min(q[0]),
                p[1].max(q[1]),
                p[2].min(q[2]),
                p[3].max(q[3]),
            ],
        ));
    }
    boxes.sort_by(|x, y| x.1[0].total_cmp(&y.1[0]));
    let mut active: Vec<usize> = Vec::new();
    let mut candidates = Vec::new();
    for (pos, (i, bx)) in boxes.iter().enumerate() {
        active.retain(|&j| boxes[j].1[1] >= bx[0]);
        for &j in &active {
            let (o, ob) = boxes[j];
            if ob[2] <= bx[3] && bx[2] <= ob[3] && s.pair_active(*i, o) {
                candidates.push((*i.min(&o), *i.max(&o)));
            }
        }
        active.push(pos);
    }
    let mut hits = Vec::new();
    for (a, b) in candidates {
        if let Some((time, normal)) = s.toi(a, b, t, t_end - t) {
            if time <= t_end {
                hits.push((time, a, b, normal));
            }
        }
    }
    hits
}
