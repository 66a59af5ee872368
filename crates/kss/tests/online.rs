//! The online API ([`kss::Simulation`]) against the brute-force reference:
//! random scenes driven by random scripts of advances, answers to the
//! collisions (built-in responses, new velocities, removals), velocity
//! changes, removals (fixed polygons too) and insertions (fixed ones too),
//! run in lockstep on `brute`, `plain` and `hierarchical` (with the audit
//! after every event and every call). Every call must give the same result
//! in all three (the same collision events with exact times, the same
//! refusals), and the scene must stay the same (exact positions and
//! velocities). The script decides from the reference's results only.
//!
//! Also: every invalid call is refused with its typed error and changes
//! nothing that a later call sees. `KSS_SLOW=1` runs many more scripts;
//! `KSS_SEEDS=n` sets their number.

use std::collections::{BTreeMap, HashMap};
use std::f64::consts::TAU;

use kss::gen::{generate_small, regular_polygon, Family};
use kss::num::{Rational, Time};
use kss::rng::Rng;
use kss::{
    CollisionEvent, PolygonSpec, ScenarioError, SimError, SimOptions, Simulation, StructureKind,
};

/// A structure of the lockstep runs, and for the hierarchy its
/// `approximate_above`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Kind(StructureKind, usize);

impl Kind {
    fn name(&self) -> String {
        match self {
            Kind(StructureKind::Hierarchical, 0) => {
                "hierarchical (every polygon approximated)".into()
            }
            Kind(s, _) => s.name().into(),
        }
    }
}

/// The structures compared; the first is the reference that drives the
/// script. The hierarchy twice: approximating every polygon (the scripts'
/// polygons are small), and with its default, which takes them as they
/// are.
const ALL: &[Kind] = &[
    Kind(StructureKind::Brute, 0),
    Kind(StructureKind::Plain, 0),
    Kind(StructureKind::Hierarchical, 0),
    Kind(StructureKind::Hierarchical, kss::DEFAULT_APPROXIMATE_ABOVE),
];

/// What the scripts of a sweep do.
#[derive(Clone, Copy, Debug)]
struct Config {
    /// The structures run in lockstep, the reference first.
    kinds: &'static [Kind],
    /// Whether polygons enter after time 0 (otherwise only at time 0,
    /// before the first advance).
    late_insertions: bool,
    /// Whether polygons enter at a collision instant before the pairs are
    /// answered (and not only after).
    insert_unanswered: bool,
}

fn scripts() -> u64 {
    match std::env::var("KSS_SLOW") {
        Ok(_) => 3000,
        Err(_) => std::env::var("KSS_SEEDS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(90),
    }
}

/// The options of a structure in the lockstep runs (the audit after every
/// call).
fn options(Kind(structure, above): Kind) -> SimOptions {
    SimOptions {
        structure,
        audit: structure != StructureKind::Brute,
        approximate_above: above,
        ..Default::default()
    }
}

/// What a collision event is compared by: exact time, pair, `again`.
type Key = (Time, String, String, bool);

fn keys(events: &[CollisionEvent]) -> Vec<Key> {
    events
        .iter()
        .map(|e| (e.time.clone(), e.a.clone(), e.b.clone(), e.again))
        .collect()
}

/// The name of an error's variant (for the counts).
fn variant(e: &SimError) -> &'static str {
    match e {
        SimError::Invalid(_) => "Invalid",
        SimError::UnknownPolygon(_) => "UnknownPolygon",
        SimError::NotPresent(_) => "NotPresent",
        SimError::Fixed(_) => "Fixed",
        SimError::EmptyId => "EmptyId",
        SimError::DuplicateId(_) => "DuplicateId",
        SimError::Touches { .. } => "Touches",
        SimError::BadTime { .. } => "BadTime",
        SimError::Unanswered { .. } => "Unanswered",
        SimError::NotColliding { .. } => "NotColliding",
        SimError::Aborted(_) => "Aborted",
        SimError::Internal(_) => "Internal",
        _ => "another",
    }
}

/// A call's outcome as compared: the value's key, or the error with every
/// field (as text: a NaN time is not equal to itself).
fn outcome<T, K>(r: &Result<T, SimError>, key: impl Fn(&T) -> K) -> Result<K, String> {
    match r {
        Ok(v) => Ok(key(v)),
        Err(e) => Err(format!("{e:?}")),
    }
}

/// What the scene looks like now, exactly: the time, and the id, position
/// and velocity of every present polygon in order.
type State = (Time, Vec<(String, [Rational; 2], [Rational; 2])>, u64);

fn state(sim: &Simulation) -> State {
    let polygons = sim
        .polygons()
        .map(|id| {
            (
                id.to_string(),
                sim.position(id).expect("present"),
                sim.velocity(id).expect("present"),
            )
        })
        .collect();
    (sim.now().clone(), polygons, sim.stats().collisions)
}

/// Counts over the scripts, printed with `--nocapture`.
#[derive(Default, Debug)]
struct Counts {
    scripts: u64,
    calls: u64,
    advances: u64,
    collisions: u64,
    again: u64,
    /// Collision instants with more than one pair.
    simultaneous: u64,
    insertions: u64,
    removals: u64,
    velocity_changes: u64,
    refusals: BTreeMap<&'static str, u64>,
}

impl Counts {
    fn add(&mut self, other: &Counts) {
        self.scripts += other.scripts;
        self.calls += other.calls;
        self.advances += other.advances;
        self.collisions += other.collisions;
        self.again += other.again;
        self.simultaneous += other.simultaneous;
        self.insertions += other.insertions;
        self.removals += other.removals;
        self.velocity_changes += other.velocity_changes;
        for (k, v) in &other.refusals {
            *self.refusals.entry(k).or_default() += v;
        }
    }
}

/// The same simulation with several structures, driven call by
/// call; every call's outcome and the scene after it are compared with the
/// reference's.
struct Lockstep {
    kinds: &'static [Kind],
    sims: Vec<Simulation>,
    /// The scene and the calls so far (for failure messages).
    log: Vec<String>,
    counts: Counts,
}

impl Lockstep {
    fn new(what: String, kinds: &'static [Kind], polygons: &[PolygonSpec]) -> Lockstep {
        let sims = kinds
            .iter()
            .map(|&k| {
                Simulation::new(polygons, &options(k))
                    .unwrap_or_else(|e| panic!("{what}: {} refuses the scene: {e}", k.name()))
            })
            .collect();
        Lockstep {
            kinds,
            sims,
            log: vec![what, format!("polygons: {polygons:?}")],
            counts: Counts::default(),
        }
    }

    fn reference(&self) -> &Simulation {
        &self.sims[0]
    }

    /// Make the call `f` (described by `call`) on every simulation; the
    /// outcomes, compared by `key`, and the scenes after it must be the
    /// reference's. Returns the reference's outcome.
    fn each<T, K: PartialEq + std::fmt::Debug>(
        &mut self,
        call: String,
        mut f: impl FnMut(&mut Simulation) -> Result<T, SimError>,
        key: impl Fn(&T) -> K,
    ) -> Result<T, SimError> {
        self.log.push(call);
        self.counts.calls += 1;
        let mut results: Vec<Result<T, SimError>> = self.sims.iter_mut().map(&mut f).collect();
        let want = outcome(&results[0], &key);
        let want_state = state(&self.sims[0]);
        for (i, r) in results.iter().enumerate().skip(1) {
            let got = outcome(r, &key);
            if got != want {
                self.fail(&format!(
                    "{} returns {got:?}, brute {want:?}",
                    self.kinds[i].name()
                ));
            }
            let got_state = state(&self.sims[i]);
            if got_state != want_state {
                self.fail(&format!(
                    "after the call, {} has the scene {got_state:?}, brute {want_state:?}",
                    self.kinds[i].name()
                ));
            }
        }
        let r = results.swap_remove(0);
        if let Err(e) = &r {
            assert!(
                !matches!(e, SimError::Internal(_)),
                "brute: internal error: {e}"
            );
            *self.counts.refusals.entry(variant(e)).or_default() += 1;
        }
        r
    }

    fn fail(&self, what: &str) -> ! {
        let start = self.log.len().saturating_sub(40);
        panic!(
            "{}\n{}\n  ...\n  {}\n{what}",
            self.log[0],
            self.log[1],
            self.log[start.max(2)..].join("\n  ")
        )
    }

    fn advance(&mut self, t: f64) -> Result<Vec<CollisionEvent>, SimError> {
        self.counts.advances += 1;
        let r = self.each(format!("advance({t:?})"), |s| s.advance(t), |e| keys(e));
        if let Ok(events) = &r {
            for e in events {
                if e.again {
                    self.counts.again += 1;
                } else {
                    self.counts.collisions += 1;
                }
            }
            self.counts.simultaneous += u64::from(events.len() > 1);
        }
        r
    }

    fn set_velocities(&mut self, changes: &[(String, [f64; 2])]) -> Result<(), SimError> {
        let changes: Vec<(&str, [f64; 2])> =
            changes.iter().map(|(id, v)| (id.as_str(), *v)).collect();
        let r = self.each(
            format!("set_velocities({changes:?})"),
            |s| s.set_velocities(&changes),
            |_| (),
        );
        if r.is_ok() {
            self.counts.velocity_changes += changes.len() as u64;
        }
        r
    }

    fn remove(&mut self, id: &str) -> Result<(), SimError> {
        let r = self.each(format!("remove({id:?})"), |s| s.remove(id), |_| ());
        self.counts.removals += u64::from(r.is_ok());
        r
    }

    fn insert(&mut self, p: &PolygonSpec) -> Result<(), SimError> {
        let r = self.each(format!("insert({p:?})"), |s| s.insert(p), |_| ());
        self.counts.insertions += u64::from(r.is_ok());
        r
    }

    fn bounce(&mut self, events: &[CollisionEvent]) -> Result<(), SimError> {
        self.each(
            format!("bounce({:?})", keys(events)),
            |s| s.bounce(events),
            |_| (),
        )
    }

    fn remove_colliding(&mut self, events: &[CollisionEvent]) -> Result<(), SimError> {
        self.each(
            format!("remove_colliding({:?})", keys(events)),
            |s| s.remove_colliding(events),
            |_| (),
        )
    }
}

/// A random script on one random scene.
struct Script {
    rng: Rng,
    run: Lockstep,
    /// Every polygon ever in the scene: its vertices and whether it is fixed.
    shapes: HashMap<String, (Vec<[f64; 2]>, bool)>,
    /// Typical polygon radius, speed and time span of the scene.
    size: f64,
    speed: f64,
    span: f64,
    next_id: usize,
    cfg: Config,
    /// Whether the first advance was made.
    started: bool,
}

impl Script {
    fn new(seed: u64, cfg: Config) -> Script {
        let family = Family::ALL[(seed % Family::ALL.len() as u64) as usize];
        let s = generate_small(family, seed / Family::ALL.len() as u64);
        let mut rng = Rng::with_stream(seed, 0x0004_114e);
        let mut polygons = s.polygons.clone();
        // some polygons stand still for good
        for p in &mut polygons {
            if rng.chance(0.15) {
                p.fixed = true;
                p.velocity = [0.0, 0.0];
            }
        }
        let size = polygons
            .iter()
            .flat_map(|p| p.vertices.iter())
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max)
            .max(0.1);
        let speed = polygons
            .iter()
            .map(|p| p.velocity[0].hypot(p.velocity[1]))
            .fold(0.0, f64::max);
        let speed = if speed > 0.0 { speed } else { 1.0 };
        let shapes = polygons
            .iter()
            .map(|p| (p.id.clone(), (p.vertices.clone(), p.fixed)))
            .collect();
        let what = format!(
            "script {seed} ({} seed {})",
            family.name(),
            seed / Family::ALL.len() as u64
        );
        Script {
            rng,
            run: Lockstep::new(what, cfg.kinds, &polygons),
            shapes,
            size,
            speed,
            span: s.until,
            next_id: 0,
            cfg,
            started: false,
        }
    }

    fn present(&self) -> Vec<String> {
        self.run.reference().polygons().map(String::from).collect()
    }

    fn is_fixed(&self, id: &str) -> bool {
        self.shapes.get(id).is_some_and(|s| s.1)
    }

    /// Where polygon `id`'s vertex average is now (approximately).
    fn centre(&self, id: &str) -> [f64; 2] {
        let p = self.run.reference().position(id).expect("present");
        let v = &self.shapes[id].0;
        let n = v.len() as f64;
        [
            p[0].to_f64() + v.iter().map(|q| q[0]).sum::<f64>() / n,
            p[1].to_f64() + v.iter().map(|q| q[1]).sum::<f64>() / n,
        ]
    }

    fn random_velocity(&mut self) -> [f64; 2] {
        let s = self.speed;
        match self.rng.below(6) {
            0 => [0.0, 0.0],
            // along an axis: flush edges of axis-aligned shapes slide
            1 => [self.rng.range_f64(-s, s), 0.0],
            2 => [0.0, self.rng.range_f64(-s, s)],
            _ => [self.rng.range_f64(-s, s), self.rng.range_f64(-s, s)],
        }
    }

    /// Any id: mostly present ones, sometimes a removed or an unknown one.
    fn any_id(&mut self) -> String {
        let present = self.present();
        match self.rng.below(10) {
            0 => "nobody".to_string(),
            1 => {
                let mut all: Vec<&String> = self.shapes.keys().collect();
                all.sort();
                self.rng
                    .pick(&all)
                    .map(|s| s.to_string())
                    .unwrap_or_default()
            }
            _ => self.rng.pick(&present).cloned().unwrap_or_default(),
        }
    }

    /// A new polygon near `near` (or near a present polygon, or anywhere
    /// around the scene), fixed sometimes; its id is new, or sometimes one
    /// that is or was in use.
    fn random_polygon(&mut self, near: Option<[f64; 2]>) -> PolygonSpec {
        let id = if self.rng.chance(0.05) && !self.shapes.is_empty() {
            let mut all: Vec<&String> = self.shapes.keys().collect();
            all.sort();
            self.rng.pick(&all).map(|s| s.to_string()).unwrap()
        } else {
            self.next_id += 1;
            format!("new{}", self.next_id)
        };
        let r = self.size * self.rng.range_f64(0.2, 0.7);
        let vertices = match self.rng.below(3) {
            0 => {
                let (w, h) = (r, r * self.rng.range_f64(0.3, 1.5));
                vec![[-w, -h], [w, -h], [w, h], [-w, h]]
            }
            _ => regular_polygon(self.rng.range_usize(3, 7), r, self.rng.range_f64(0.0, TAU)),
        };
        let present = self.present();
        let base = match near {
            Some(p) => p,
            None => match self.rng.pick(&present).cloned() {
                Some(id) => self.centre(&id),
                None => [0.0, 0.0],
            },
        };
        let d = self.size * self.rng.range_f64(0.3, 3.0);
        let a = self.rng.range_f64(0.0, TAU);
        let position = [base[0] + d * a.cos(), base[1] + d * a.sin()];
        let fixed = self.rng.chance(0.2);
        let velocity = if fixed {
            [0.0, 0.0]
        } else {
            self.random_velocity()
        };
        PolygonSpec {
            id,
            vertices,
            position,
            velocity,
            fixed,
        }
    }

    /// Try to insert a new polygon; right after a successful insertion,
    /// sometimes change its velocity at once.
    fn insert(&mut self, near: Option<[f64; 2]>) {
        let p = self.random_polygon(near);
        let new = !self.shapes.contains_key(&p.id);
        match self.run.insert(&p) {
            Ok(()) => {
                assert!(new, "the id {:?} was in use", p.id);
                self.shapes
                    .insert(p.id.clone(), (p.vertices.clone(), p.fixed));
                if self.rng.chance(0.3) {
                    let v = self.random_velocity();
                    let _ = self.run.set_velocities(&[(p.id.clone(), v)]);
                }
            }
            Err(SimError::DuplicateId(_)) => assert!(!new),
            Err(SimError::Touches { .. }) => assert!(new),
            Err(e) => self.run.fail(&format!("insertion refused: {e}")),
        }
    }

    /// A velocity for polygon `mover` that takes it away from `other`
    /// (along the line between their centres, relative to `other`'s
    /// velocity).
    fn away(&mut self, mover: &str, other: &str) -> [f64; 2] {
        let (m, o) = (self.centre(mover), self.centre(other));
        let (dx, dy) = (m[0] - o[0], m[1] - o[1]);
        let len = dx.hypot(dy).max(1e-300);
        let v = self.run.reference().velocity(other).expect("present");
        let s = self.speed * self.rng.range_f64(0.2, 1.5);
        [v[0].to_f64() + dx / len * s, v[1].to_f64() + dy / len * s]
    }

    /// [`Script::between`] at a collision instant before the pairs are
    /// answered: an insertion only if the script inserts then.
    fn between_answered(&mut self, events: &[CollisionEvent]) {
        if self.cfg.insert_unanswered {
            self.between();
            return;
        }
        match self.rng.below(3) {
            0 => {
                let id = self.any_id();
                let v = self.random_velocity();
                let _ = self.run.set_velocities(&[(id, v)]);
            }
            1 => {
                let id = self.any_id();
                let _ = self.run.remove(&id);
            }
            _ => {
                // refused before anything else is looked at
                let mut p = self.random_polygon(Some(events[0].point));
                p.vertices.reverse();
                match self.run.insert(&p) {
                    Err(SimError::Invalid(ScenarioError::Clockwise { .. }))
                    | Err(SimError::DuplicateId(_)) => {}
                    r => self.run.fail(&format!("clockwise insertion: {r:?}")),
                }
            }
        }
    }

    fn may_insert(&self) -> bool {
        self.cfg.late_insertions || !self.started
    }

    /// A random call between advances.
    fn between(&mut self) {
        match self.rng.below(10) {
            0..=2 => {
                let n = self.rng.range_usize(1, 3);
                let changes: Vec<(String, [f64; 2])> = (0..n)
                    .map(|_| {
                        let id = self.any_id();
                        let v = if self.rng.chance(0.03) {
                            [f64::NAN, 0.0]
                        } else {
                            self.random_velocity()
                        };
                        (id, v)
                    })
                    .collect();
                let _ = self.run.set_velocities(&changes);
            }
            3 => {
                let id = self.any_id();
                let _ = self.run.remove(&id);
            }
            _ if self.may_insert() => self.insert(None),
            _ => {
                let id = self.any_id();
                let v = self.random_velocity();
                let _ = self.run.set_velocities(&[(id, v)]);
            }
        }
    }

    /// Answer `events` (the reference's, returned by the latest advance)
    /// at random; `round` counts the answers at this instant so far.
    fn answer(&mut self, events: &[CollisionEvent], round: u32) {
        // at the instant of the collisions, before answering
        if self.rng.chance(0.15) {
            let t = self.run.reference().now().to_f64() + self.span;
            match self.run.advance(t) {
                Err(SimError::Unanswered { .. }) => {}
                r => self
                    .run
                    .fail(&format!("advance with unanswered pairs: {r:?}")),
            }
        }
        if self.cfg.insert_unanswered && self.rng.chance(0.15) {
            let e = self.rng.pick(events).expect("events").clone();
            self.insert(Some(e.point));
        }
        if self.rng.chance(0.1) {
            self.between_answered(events);
        }
        if round >= 3 {
            // bounce always ends in separating or sliding
            self.run.bounce(events).expect("bounce");
            return;
        }
        match self.rng.below(5) {
            0 => self.run.bounce(events).expect("bounce"),
            1 => self.run.remove_colliding(events).expect("remove_colliding"),
            2 => {
                // one call: a polygon of each pair moves away
                let mut changes = Vec::new();
                for e in events {
                    let (a, b) = (e.a.clone(), e.b.clone());
                    let reference = self.run.reference();
                    if !reference.contains(&a) || !reference.contains(&b) {
                        continue; // answered by the removal
                    }
                    let (m, o) =
                        if self.is_fixed(&a) || (!self.is_fixed(&b) && self.rng.chance(0.5)) {
                            (b, a)
                        } else {
                            (a, b)
                        };
                    let v = self.away(&m, &o);
                    changes.push((m, v));
                }
                self.run.set_velocities(&changes).expect("set_velocities");
            }
            _ => {
                for e in events {
                    let (a, b) = (e.a.as_str(), e.b.as_str());
                    let gone =
                        !self.run.reference().contains(a) || !self.run.reference().contains(b);
                    let choice = self.rng.below(if gone { 3 } else { 6 });
                    match choice {
                        0 => self.run.bounce(std::slice::from_ref(e)).expect("bounce"),
                        1 => self
                            .run
                            .remove_colliding(std::slice::from_ref(e))
                            .expect("remove_colliding"),
                        2 if gone => {}
                        2 | 3 => {
                            let id = if self.rng.chance(0.5) { a } else { b };
                            self.run.remove(id).expect("remove");
                        }
                        _ => {
                            let (m, o) = if self.is_fixed(a) || (!self.is_fixed(b) && choice == 4) {
                                (b, a)
                            } else {
                                (a, b)
                            };
                            let v = self.away(m, o);
                            self.run
                                .set_velocities(&[(m.to_string(), v)])
                                .expect("set_velocity");
                        }
                    }
                }
            }
        }
        // after answering, at the same instant
        if self.may_insert() && self.rng.chance(0.15) {
            let e = self.rng.pick(events).expect("events").clone();
            self.insert(Some(e.point));
        }
        if self.rng.chance(0.1) {
            self.between();
        }
    }

    /// Run `calls` random steps, then compare the final scenes.
    fn run(mut self, steps: usize) -> Counts {
        // a few polygons enter at time 0
        for _ in 0..self.rng.range_usize(0, 3) {
            self.insert(None);
        }
        let mut round = 0;
        let mut instant: Option<Time> = None;
        for _ in 0..steps {
            if self.rng.chance(0.4) {
                self.between();
                continue;
            }
            let now = self.run.reference().now().to_f64();
            let t = match self.rng.below(20) {
                0 => now,
                1 => f64::NAN,
                2 => now - self.span,
                _ => now + self.span * self.rng.range_f64(0.0, 0.5),
            };
            self.started = true;
            let events = match self.run.advance(t) {
                Ok(events) => events,
                Err(SimError::BadTime { .. }) => continue,
                Err(e) => self.run.fail(&format!("advance refused: {e}")),
            };
            if events.is_empty() {
                continue;
            }
            let at = events[0].time.clone();
            round = if instant.as_ref() == Some(&at) {
                round + 1
            } else {
                0
            };
            instant = Some(at);
            self.answer(&events, round);
        }
        let mut counts = std::mem::take(&mut self.run.counts);
        counts.scripts = 1;
        counts
    }
}

/// Run [`scripts`] random scripts; the counts.
fn sweep(cfg: Config) -> Counts {
    let mut total = Counts::default();
    for seed in 0..scripts() {
        total.add(&Script::new(seed, cfg).run(40));
    }
    eprintln!("online {cfg:?}: {total:?}");
    assert!(total.collisions >= total.scripts, "{total:?}");
    assert!(total.simultaneous > 0 && total.again > 0, "{total:?}");
    assert!(total.insertions > 0 && total.removals > 0, "{total:?}");
    for v in [
        "Touches",
        "Unanswered",
        "BadTime",
        "Fixed",
        "NotPresent",
        "UnknownPolygon",
        "DuplicateId",
        "Invalid",
    ] {
        assert!(total.refusals.contains_key(v), "no {v} refusal: {total:?}");
    }
    total
}

/// Random scripts on random scenes of every generator family, with
/// polygons entering at any time (at collision instants too, before and
/// after the pairs are answered): every call gives the same outcome with
/// the plain structure as with the reference, and the scene stays the
/// same, exactly.
#[test]
fn random_scripts_plain_matches_brute() {
    sweep(Config {
        kinds: &ALL[..2],
        late_insertions: true,
        insert_unanswered: true,
    });
}

/// Random scripts with both kinetic structures, polygons entering at time
/// 0 only: every call gives the same outcome as with the reference, and
/// the scene stays the same, exactly.
#[test]
fn random_scripts_match_brute() {
    sweep(Config {
        kinds: ALL,
        late_insertions: false,
        insert_unanswered: false,
    });
}

/// As [`random_scripts_match_brute`], polygons entering at any time.
#[test]
fn random_scripts_with_insertions_match_brute() {
    sweep(Config {
        kinds: ALL,
        late_insertions: true,
        insert_unanswered: true,
    });
}

fn rect(id: &str, w: f64, h: f64, at: [f64; 2], velocity: [f64; 2], fixed: bool) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices: vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]],
        position: at,
        velocity,
        fixed,
    }
}

fn square(id: &str, at: [f64; 2], velocity: [f64; 2]) -> PolygonSpec {
    rect(id, 1.0, 1.0, at, velocity, false)
}

fn lockstep(what: &str, polygons: &[PolygonSpec]) -> Lockstep {
    Lockstep::new(what.to_string(), ALL, polygons)
}

fn time(t: &Time) -> String {
    t.as_rational().expect("rational").to_string()
}

/// Events as `"time a b"` (`" again"` added where set).
fn pairs(events: &[CollisionEvent]) -> Vec<String> {
    events
        .iter()
        .map(|e| {
            let again = if e.again { " again" } else { "" };
            format!("{} {} {}{again}", time(&e.time), e.a, e.b)
        })
        .collect()
}

/// Two squares hit a third from both sides at one instant; the removal of
/// the pair `(a, b)` removes `b`, which answers `(b, c)` too (a polygon
/// that has left collides with nothing).
#[test]
fn remove_colliding_answers_the_other_pairs_of_a_removed_polygon() {
    let mut run = lockstep(
        "two squares hit a third from both sides",
        &[
            square("a", [0.0, 0.0], [1.0, 0.0]),
            square("b", [2.0, 0.0], [0.0, 0.0]),
            square("c", [4.0, 0.0], [-1.0, 0.0]),
        ],
    );
    let events = run.advance(10.0).expect("advance");
    assert_eq!(pairs(&events), ["1 a b", "1 b c"]);
    run.remove_colliding(&events[..1])
        .expect("remove_colliding");
    assert!(!run.reference().contains("b") && run.reference().contains("c"));
    assert_eq!(run.advance(10.0).expect("advance c"), []);
    assert_eq!(run.reference().position("c").unwrap()[0].to_string(), "-6");
}

/// Simultaneous contacts, the removal of a fixed polygon at the instant of
/// its collision, insertions at that instant (a fixed polygon, and a
/// moving one whose velocity changes right after), and further collisions
/// with the inserted polygons.
#[test]
fn calls_at_a_collision_instant_match_brute() {
    let mut run = lockstep(
        "two squares hit two fixed walls at one instant",
        &[
            square("a", [0.0, 0.0], [1.0, 0.0]),
            rect("w1", 1.0, 3.0, [2.0, -1.0], [0.0, 0.0], true),
            square("c", [0.0, 5.0], [1.0, 0.0]),
            rect("w2", 1.0, 3.0, [2.0, 4.0], [0.0, 0.0], true),
        ],
    );
    let events = run.advance(10.0).expect("advance");
    assert_eq!(events.len(), 2, "{events:?}");
    assert!(events.iter().all(|e| time(&e.time) == "1" && !e.again));
    // the fixed wall leaves at the instant of its collision
    run.remove("w1").expect("remove the fixed wall");
    assert_eq!(
        run.advance(10.0),
        Err(SimError::Unanswered {
            a: "c".into(),
            b: "w2".into(),
            time: 1.0
        })
    );
    run.bounce(&events[1..]).expect("bounce c off w2");
    // a fixed polygon enters at that instant where w1 was, farther on
    run.insert(&rect("f", 1.0, 3.0, [6.0, -1.0], [0.0, 0.0], true))
        .expect("insert f");
    // a moving one enters and turns at once
    run.insert(&square("g", [-1.0, 10.0], [0.0, 0.0]))
        .expect("insert g");
    run.set_velocities(&[("g".into(), [0.0, -2.0])])
        .expect("turn g");
    // c (bounced back) and g meet at t = 3, a hits f at t = 5
    let events = run.advance(10.0).expect("advance");
    assert_eq!(pairs(&events), ["3 c g"]);
    run.remove_colliding(&events).expect("remove c and g");
    let events = run.advance(10.0).expect("advance");
    assert_eq!(pairs(&events), ["5 a f"]);
    // the fixed polygon that entered leaves too
    run.remove("f").expect("remove f");
    assert_eq!(run.advance(10.0).expect("advance"), []);
    assert_eq!(run.reference().polygons().collect::<Vec<_>>(), ["a", "w2"]);
}

/// A square lands on a fixed floor and slides along it (a new velocity),
/// another lands at the same instant and stays on it; the first slides
/// into the second, which slides on after the bounce and bounces off a
/// fixed post back.
#[test]
fn sliding_contacts_after_bounce_match_brute() {
    let mut run = lockstep(
        "squares land on a floor and slide",
        &[
            square("a", [0.0, 2.0], [0.0, -1.0]),
            square("d", [3.0, 2.0], [0.0, -1.0]),
            rect("floor", 12.0, 1.0, [-1.0, 0.0], [0.0, 0.0], true),
            rect("post", 1.0, 3.0, [7.0, 1.5], [0.0, 0.0], true),
        ],
    );
    let events = run.advance(10.0).expect("advance");
    assert_eq!(events.len(), 2, "{events:?}");
    run.set_velocities(&[("a".into(), [1.0, 0.0]), ("d".into(), [0.0, 0.0])])
        .expect("slide a, stop d");
    let mut seen = Vec::new();
    for _ in 0..10 {
        let events = run.advance(10.0).expect("advance");
        if events.is_empty() {
            break;
        }
        seen.extend(
            keys(&events)
                .into_iter()
                .map(|k| (time(&k.0), k.1, k.2, k.3)),
        );
        run.bounce(&events).expect("bounce");
    }
    let first = &seen[0];
    assert_eq!(
        (first.0.as_str(), first.1.as_str(), first.2.as_str()),
        ("3", "a", "d")
    );
    assert!(seen.iter().any(|e| e.1 == "d" && e.2 == "post"), "{seen:?}");
    // the floor leaves while d slides on it; a polygon enters later
    run.remove("floor").expect("remove the floor");
    run.insert(&square("late", [20.0, 20.0], [0.0, 0.0]))
        .expect("insert");
    run.set_velocities(&[("late".into(), [-1.0, -1.0])])
        .expect("turn late");
    let _ = run.advance(40.0);
}

/// A polygon enters far away while a collision waits for its answer.
#[test]
fn insertion_before_answering_a_collision() {
    let mut run = lockstep(
        "two squares head on",
        &[
            square("a", [0.0, 0.0], [1.0, 0.0]),
            square("b", [3.0, 0.0], [-1.0, 0.0]),
        ],
    );
    let events = run.advance(5.0).expect("advance");
    run.insert(&square("c", [0.0, 10.0], [0.0, 0.0]))
        .expect("insert");
    run.bounce(&events).expect("bounce");
    assert_eq!(run.advance(5.0).expect("advance"), []);
}

/// A polygon enters far away while a square slides along a fixed floor.
#[test]
fn insertion_while_sliding() {
    let mut run = lockstep(
        "a square lands on a floor and slides",
        &[
            square("a", [0.0, 2.0], [0.0, -1.0]),
            rect("floor", 10.0, 1.0, [-5.0, 0.0], [0.0, 0.0], true),
        ],
    );
    let events = run.advance(5.0).expect("advance");
    assert_eq!(events.len(), 1);
    run.set_velocities(&[("a".into(), [1.0, 0.0])])
        .expect("slide");
    assert_eq!(run.advance(1.5).expect("advance"), []);
    run.insert(&square("c", [0.0, 10.0], [0.0, 0.0]))
        .expect("insert");
    assert_eq!(run.advance(5.0).expect("advance"), []);
}

/// The same in a scenario file: the square bounces, then slides (a
/// flight-plan change), and a polygon enters while it slides.
#[test]
fn scenario_insertion_while_sliding() {
    let s = kss::Scenario {
        until: 4.0,
        on_collision: kss::CollisionMode::Bounce,
        polygons: vec![
            square("a", [0.0, 2.0], [0.0, -1.0]),
            rect("floor", 10.0, 1.0, [-5.0, 0.0], [0.0, 0.0], true),
        ],
        flight_plan_changes: vec![kss::FlightPlanChange {
            time: 1.0,
            id: "a".into(),
            velocity: [1.0, 0.0],
        }],
        insertions: vec![kss::Insertion {
            time: 1.5,
            polygon: square("c", [0.0, 10.0], [0.0, 0.0]),
        }],
        ..Default::default()
    };
    for structure in ALL {
        let opts = kss::RunOptions {
            structure: structure.0,
            audit: true,
            approximate_above: structure.1,
            ..Default::default()
        };
        let mut n = 0;
        let r = kss::run(&s, &opts, &mut |_| n += 1);
        assert!(r.is_ok(), "{}: {r:?}", structure.name());
        assert_eq!(n, 1, "{}", structure.name());
    }
}

// ---------------------------------------------------------------------------
// Refused calls
// ---------------------------------------------------------------------------

/// The scene of the refusal tests: `a` and `b` meet head on at t = 1 and
/// bounce; `b` then hits `d` at t = 6; `c` is removed at time 0; `w` is a
/// fixed wall.
fn refusal_scene() -> Vec<PolygonSpec> {
    vec![
        square("a", [0.0, 0.0], [1.0, 0.0]),
        square("b", [3.0, 0.0], [-1.0, 0.0]),
        square("c", [0.0, -5.0], [0.0, 0.0]),
        square("d", [8.0, 0.0], [0.0, 0.0]),
        rect("w", 1.0, 1.0, [0.0, 5.0], [0.0, 0.0], true),
    ]
}

/// The run of the refusal scene up to the collision at t = 1 (unanswered),
/// or (with `later`) up to the next one at t = 6; returns the first
/// collisions.
fn refusal_setup(sim: &mut Simulation, later: bool) -> Vec<CollisionEvent> {
    sim.remove("c").expect("remove c");
    let first = sim.advance(20.0).expect("advance");
    assert_eq!(keys(&first).len(), 1);
    assert_eq!(time(&first[0].time), "1");
    if later {
        sim.bounce(&first).expect("bounce");
        let next = sim.advance(20.0).expect("advance");
        assert_eq!(pairs(&next), ["6 b d"]);
    }
    first
}

/// The rest of a run: bounce whatever waits for an answer, then advance to
/// t = 20 bouncing every collision; the events and the final scene.
fn finish(sim: &mut Simulation, pending: &[CollisionEvent]) -> (Vec<Key>, State) {
    let mut seen = Vec::new();
    if !pending.is_empty() {
        sim.bounce(pending).expect("bounce the pending collisions");
    }
    for _ in 0..50 {
        let events = sim.advance(20.0).expect("advance");
        if events.is_empty() {
            break;
        }
        seen.extend(keys(&events));
        sim.bounce(&events).expect("bounce");
    }
    assert_eq!(sim.now().to_f64(), 20.0);
    (seen, state(sim))
}

/// Make the invalid call `bad` on one of two simulations of the refusal
/// scene (after [`refusal_setup`]) with every structure: it must be refused
/// as `expected` says, and change nothing: the scene right after it and
/// every later event and the final scene are those of the simulation
/// without the call.
fn refused(
    what: &str,
    later: bool,
    bad: impl Fn(&mut Simulation, &[CollisionEvent]) -> Result<(), SimError>,
    expected: impl Fn(&SimError) -> bool,
) {
    for &structure in ALL {
        let new = || Simulation::new(&refusal_scene(), &options(structure)).expect("scene");
        let (mut with, mut without) = (new(), new());
        let first = refusal_setup(&mut with, later);
        refusal_setup(&mut without, later);
        let pending = if later {
            with.advance(0.0).unwrap_err(); // still unanswered
            let next = vec![CollisionEvent {
                time: with.now().clone(),
                a: "b".into(),
                b: "d".into(),
                point: [0.0, 0.0],
                again: false,
            }];
            next
        } else {
            first.clone()
        };
        let r = bad(&mut with, &first);
        match &r {
            Err(e) if expected(e) => {}
            r => panic!("{what} ({}): {r:?}", structure.name()),
        }
        assert_eq!(
            state(&with),
            state(&without),
            "{what} ({}) changed the scene",
            structure.name()
        );
        let (a, b) = (finish(&mut with, &pending), finish(&mut without, &pending));
        assert_eq!(a, b, "{what} ({}) changed the run", structure.name());
        // (the run goes on after the call)
        assert_eq!(a.0.is_empty(), later, "{what}: {a:?}");
    }
}

#[test]
fn unknown_and_removed_ids_are_refused() {
    let unknown = |e: &SimError| *e == SimError::UnknownPolygon("zz".into());
    let gone = |e: &SimError| *e == SimError::NotPresent("c".into());
    refused(
        "velocity of an unknown id",
        false,
        |s, _| s.set_velocity("zz", [1.0, 0.0]),
        unknown,
    );
    refused(
        "velocity of a removed id",
        false,
        |s, _| s.set_velocity("c", [1.0, 0.0]),
        gone,
    );
    refused(
        "removal of an unknown id",
        false,
        |s, _| s.remove("zz"),
        unknown,
    );
    refused("removal of a removed id", false, |s, _| s.remove("c"), gone);
    // one bad change refuses them all: `a` keeps its velocity and its
    // collision stays unanswered
    refused(
        "velocities with an unknown id",
        false,
        |s, _| s.set_velocities(&[("a", [-1.0, 0.0]), ("zz", [1.0, 0.0])]),
        unknown,
    );
}

#[test]
fn fixed_and_non_finite_velocities_are_refused() {
    refused(
        "velocity of a fixed polygon",
        false,
        |s, _| s.set_velocity("w", [1.0, 0.0]),
        |e| *e == SimError::Fixed("w".into()),
    );
    for v in [
        [f64::NAN, 0.0],
        [0.0, f64::INFINITY],
        [f64::NEG_INFINITY, 1.0],
    ] {
        refused(
            "non-finite velocity",
            false,
            |s, _| s.set_velocities(&[("b", [2.0, 0.0]), ("a", v)]),
            |e| matches!(e, SimError::Invalid(ScenarioError::NonFinite { .. })),
        );
    }
}

#[test]
fn bad_insertions_are_refused() {
    let dup = |id: &'static str| move |e: &SimError| *e == SimError::DuplicateId(id.into());
    refused(
        "a present id",
        false,
        |s, _| s.insert(&square("a", [0.0, 20.0], [0.0, 0.0])),
        dup("a"),
    );
    // ids are never reused
    refused(
        "a removed id",
        false,
        |s, _| s.insert(&square("c", [0.0, 20.0], [0.0, 0.0])),
        dup("c"),
    );
    // sharing an edge with the wall (closed sets touch)
    refused(
        "touching",
        false,
        |s, _| s.insert(&square("n", [1.0, 5.0], [0.0, 0.0])),
        |e| matches!(e, SimError::Touches { inserted, present, .. } if inserted == "n" && present == "w"),
    );
    // touching the colliding pair at their contact point
    refused(
        "touching at a corner",
        true,
        |s, _| s.insert(&square("n", [7.0, -1.0], [0.0, 0.0])),
        |e| matches!(e, SimError::Touches { inserted, .. } if inserted == "n"),
    );
    refused(
        "clockwise",
        false,
        |s, _| {
            let mut p = square("n", [0.0, 20.0], [0.0, 0.0]);
            p.vertices.reverse();
            s.insert(&p)
        },
        |e| *e == SimError::Invalid(ScenarioError::Clockwise { id: "n".into() }),
    );
    refused(
        "too few vertices",
        false,
        |s, _| {
            let mut p = square("n", [0.0, 20.0], [0.0, 0.0]);
            p.vertices.truncate(2);
            s.insert(&p)
        },
        |e| {
            *e == SimError::Invalid(ScenarioError::TooFewVertices {
                id: "n".into(),
                count: 2,
            })
        },
    );
    refused(
        "empty id",
        false,
        |s, _| s.insert(&square("", [0.0, 20.0], [0.0, 0.0])),
        |e| *e == SimError::EmptyId,
    );
    refused(
        "fixed with a velocity",
        false,
        |s, _| s.insert(&rect("n", 1.0, 1.0, [0.0, 20.0], [1.0, 0.0], true)),
        |e| *e == SimError::Invalid(ScenarioError::FixedWithVelocity { id: "n".into() }),
    );
    refused(
        "non-finite position",
        false,
        |s, _| s.insert(&square("n", [f64::NAN, 20.0], [0.0, 0.0])),
        |e| matches!(e, SimError::Invalid(ScenarioError::NonFinite { .. })),
    );
}

#[test]
fn bad_advances_are_refused() {
    let bad_time = |e: &SimError| matches!(e, SimError::BadTime { .. });
    for t in [0.5, -1.0, f64::NAN, f64::INFINITY] {
        refused(
            "bad time",
            false,
            move |s, _| s.advance(t).map(drop),
            bad_time,
        );
    }
    refused(
        "unanswered",
        false,
        |s, _| s.advance(2.0).map(drop),
        |e| {
            *e == SimError::Unanswered {
                a: "a".into(),
                b: "b".into(),
                time: 1.0,
            }
        },
    );
    // answering one polygon of the pair by a velocity that is refused
    // leaves it unanswered
    refused(
        "unanswered after a refused answer",
        false,
        |s, _| {
            s.set_velocities(&[("a", [-1.0, 0.0]), ("w", [0.0, 1.0])])
                .unwrap_err();
            s.advance(2.0).map(drop)
        },
        |e| matches!(e, SimError::Unanswered { .. }),
    );
}

#[test]
fn responses_to_other_collisions_are_refused() {
    let not = |a: &'static str, b: &'static str| {
        move |e: &SimError| {
            *e == SimError::NotColliding {
                a: a.into(),
                b: b.into(),
            }
        }
    };
    let event = |s: &Simulation, a: &str, b: &str| CollisionEvent {
        time: s.now().clone(),
        a: a.into(),
        b: b.into(),
        point: [0.0, 0.0],
        again: false,
    };
    // a pair that does not touch, at the current instant
    refused(
        "bounce a, w",
        false,
        |s, _| s.bounce(&[event(s, "a", "w")]),
        not("a", "w"),
    );
    refused(
        "remove_colliding a, d",
        false,
        |s, _| s.remove_colliding(&[event(s, "a", "d")]),
        not("a", "d"),
    );
    // the pair reversed, and an unknown id
    refused(
        "bounce b, a",
        false,
        |s, _| s.bounce(&[event(s, "b", "a")]),
        not("b", "a"),
    );
    refused(
        "bounce a, zz",
        false,
        |s, _| s.bounce(&[event(s, "a", "zz")]),
        not("a", "zz"),
    );
    // the right pair at another time
    refused(
        "bounce at another time",
        false,
        |s, first| {
            let mut e = first[0].clone();
            e.time = Time::from_f64(0.5).unwrap();
            s.bounce(&[e])
        },
        not("a", "b"),
    );
    // a valid pair with an invalid one: neither is applied
    refused(
        "remove_colliding with one bad pair",
        false,
        |s, first| s.remove_colliding(&[first[0].clone(), event(s, "b", "d")]),
        not("b", "d"),
    );
    // the collision of an earlier instant
    refused(
        "bounce an earlier collision",
        true,
        |s, first| s.bounce(first),
        not("a", "b"),
    );
    refused(
        "remove_colliding an earlier collision",
        true,
        |s, first| s.remove_colliding(first),
        not("a", "b"),
    );
}

/// Scripts of the long sweep in which three polygons meet at one point
/// while a fourth is elsewhere (the third polygon between the other two, so
/// that the outer two share no face of the structure): all three pairs are
/// collisions at that instant.
#[test]
fn three_polygons_meeting_at_a_point_report_every_pair() {
    let all_at_zero = Config {
        kinds: ALL,
        late_insertions: false,
        insert_unanswered: false,
    };
    Script::new(1568, all_at_zero).run(40);
    let plain_late = Config {
        kinds: &ALL[..2],
        late_insertions: true,
        insert_unanswered: true,
    };
    Script::new(902, plain_late).run(40);
}

/// A script of the long sweep (gas seed 490): the plain structure finds a
/// partition triangle collapsing onto a corridor with no ear to slide
/// along (every turn of the candidate ear is zero at the instant), and no
/// rebuild just after the instant, t = 2.4677, where `g0` meets the bottom
/// wall; the cause is not traced.
#[test]
#[ignore = "bug: the plain structure fails with an internal error (a triangle collapses onto a corridor with no ear; no rebuild just after t = 2.4677 found)"]
fn a_triangle_collapsing_onto_a_corridor_without_an_ear() {
    Script::new(
        2941,
        Config {
            kinds: ALL,
            late_insertions: false,
            insert_unanswered: false,
        },
    )
    .run(40);
}

/// A script of the long sweep (parallel seed 345) with velocity changes
/// and insertions at t = 2: the approximations of two polygons near the
/// origin stay apart. (The hierarchy builds its structure again for an
/// insertion; inserted in place, these approximations overlap at t = 17/8
/// without an event.)
#[test]
fn approximations_stay_apart_after_calls_at_one_instant() {
    Script::new(
        2074,
        Config {
            kinds: ALL,
            late_insertions: true,
            insert_unanswered: true,
        },
    )
    .run(40);
}
