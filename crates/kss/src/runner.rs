//! Running a scenario with a chosen structure: the entry point of the
//! library for a whole scenario, built on the [`Simulation`] that a caller
//! can also drive itself.

use std::collections::BTreeMap;

use crate::brute::PairMethod;
pub use crate::engine::{RunError, StructureKind};
use crate::num::{Rational, Time};
use crate::scenario::{CollisionMode, PolygonSpec, Scenario};
use crate::simulation::{Finder, SimError, SimOptions, Simulation};
use crate::structure::geo::{Geo, Shapes};
use crate::structure::kinetic::Kinetic;
use crate::world::World;

/// The default of [`RunOptions::approximate_above`]: the hierarchy sees
/// polygons of at most 32 vertices as they are. Without a hierarchy a pass
/// of two of them costs at most a few dozen events, and the refinements
/// (pops) that approximations need where polygons come close cost more than
/// the events they save: on dense swarms of 16-, 24- and 32-gons the
/// plain structure takes 30–40 % less time than the hierarchy
/// approximating every polygon (`docs/design/hierarchy.md`, "Which
/// polygons are approximated").
pub const DEFAULT_APPROXIMATE_ABOVE: usize = 32;

/// Options of a run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The structure to use.
    pub structure: StructureKind,
    /// Replaces the scenario's `until` (flight-plan changes after it are ignored).
    pub until: Option<f64>,
    /// Run the structure's audit after every event.
    pub audit: bool,
    /// For the brute-force structure: how a pair's contact time is computed
    /// (both methods must give identical results; tests compare them).
    pub pair_method: PairMethod,
    /// For the hierarchical structure: polygons of at most this many
    /// vertices take part as they are, and only the larger ones through
    /// their hierarchies of outer approximations (default
    /// [`DEFAULT_APPROXIMATE_ABOVE`]; 0 approximates every polygon). The
    /// collisions are the same whatever it is; only the cost changes.
    pub approximate_above: usize,
}

impl Default for RunOptions {
    fn default() -> RunOptions {
        RunOptions {
            structure: StructureKind::default(),
            until: None,
            audit: false,
            pair_method: PairMethod::default(),
            approximate_above: DEFAULT_APPROXIMATE_ABOVE,
        }
    }
}

/// One reported collision: polygons `a < b` (byte-wise) first touch at `time`.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionEvent {
    /// The exact collision time.
    pub time: Time,
    /// Id of the first polygon (byte-wise smaller).
    pub a: String,
    /// Id of the second polygon.
    pub b: String,
    /// A contact point at `time` (for display only).
    pub point: [f64; 2],
    /// The pair collided already at this instant: its response left it
    /// interpenetrating, and it needs another ([`Simulation::advance`]).
    /// [`run`] reports a pair once per instant.
    pub again: bool,
}

/// Statistics of a run (the contract's `--stats` object, less `wall_seconds`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunStats {
    /// The structure's name.
    pub structure: &'static str,
    /// Number of polygons.
    pub polygons: usize,
    /// Total number of vertices.
    pub vertices: usize,
    /// Every event processed (internal, collisions, flight-plan changes).
    pub events_processed: u64,
    /// Events by kind.
    pub events_by_kind: BTreeMap<String, u64>,
    /// Largest number of active certificates: queued, or out of the queue
    /// until a bridge of a collision response ends, where they are queued
    /// again.
    pub certificates_max: u64,
    /// Active certificates at the end.
    pub certificates_final: u64,
    /// Collisions reported.
    pub collisions: u64,
    /// The largest bit length of an exact number (numerator or denominator
    /// of a position or velocity) on any body's path during the run. It
    /// stays bounded however long a `bounce` run is (see [`crate::world`]).
    pub max_number_bits: u64,
    /// Times the kinetic structure was rebuilt from scratch after polygons
    /// were removed (0 for `brute`).
    pub rebuilds: u64,
    /// Times it was rebuilt for just after an instant where several
    /// degeneracies coincide and the local operations found no valid
    /// structure (0 for `brute`).
    pub degenerate_rebuilds: u64,
    /// Times the hierarchical structure was rebuilt because a pop could not
    /// be done in place (0 for `plain` and `brute`).
    pub refine_rebuilds: u64,
    /// Times the kinetic structure was built again for a polygon inserted
    /// during the run (0 for `brute`).
    pub insert_rebuilds: u64,
    /// Approximation vertices merged away where polygons moved apart
    /// (coarsening; 0 for `plain` and `brute`). Not certificate failures,
    /// so not counted in `events_processed`.
    pub merges: u64,
    /// Polygons inserted in place during the run, without a rebuild (0
    /// for `brute`).
    pub local_insertions: u64,
    /// Polygons removed in place (`remove` mode), without a rebuild (0 for
    /// `brute`).
    pub local_removals: u64,
    /// Settled contacts (three polygons meeting at one point and moving
    /// apart) that the local operations could not resolve, repaired by
    /// triangulating again only the region around one of the polygons
    /// instead of rebuilding (0 for `brute`; see ARCHITECTURE.md, "Local
    /// repair").
    pub local_repairs: u64,
    /// Times the reference stood in for the kinetic structure because two
    /// polygons stayed in contact where the structure had to be built
    /// afresh (0 for `brute`; see ARCHITECTURE.md, "Resting contacts").
    pub stand_ins: u64,
    /// Times the structure, built afresh, took over again from the
    /// reference (once no pair rested in contact at an update).
    pub stand_in_ends: u64,
    /// The kinetic structure's work by kind (construction included; empty
    /// for `brute`): predicate evaluations by the path they took and
    /// corridor walks (by name).
    pub work: BTreeMap<String, u64>,
    /// Wall time, in seconds, of building the exact world from the
    /// scenario (with its validation) and the structure with its
    /// certificates, before the first event: the rest of a run's wall time
    /// is the events' and the teardown's.
    pub build_seconds: f64,
    /// Wall time, in seconds, of the run after its construction: every
    /// event with its collision responses, flight-plan changes,
    /// insertions and removals, up to the end of the run, with the calls
    /// of the run's event callback; not freeing the structure and the
    /// world afterwards. Set by [`run`] and [`run_with_finder`]; 0 in
    /// [`Simulation::stats`] (a caller that drives a simulation times its
    /// own calls).
    pub events_seconds: f64,
}

/// Validate `scenario` and run it, calling `on_event` for every collision in
/// order. Returns the statistics of the run.
pub fn run(
    scenario: &Scenario,
    options: &RunOptions,
    on_event: &mut dyn FnMut(&CollisionEvent),
) -> Result<RunStats, RunError> {
    let start = std::time::Instant::now();
    let mut sim = simulation(scenario, options, options.structure)?;
    let build_seconds = start.elapsed().as_secs_f64();
    let events_start = std::time::Instant::now();
    drive(scenario, &mut sim, None, on_event)?;
    let events_seconds = events_start.elapsed().as_secs_f64();
    let mut stats = sim.stats();
    stats.build_seconds = build_seconds;
    stats.events_seconds = events_seconds;
    Ok(stats)
}

/// [`run`] with a collision finder of the caller's (built by `make` from
/// the world at time 0) instead of a built-in structure: the same loop, the
/// same responses, the same statistics (the finder's own in
/// [`RunStats::work`]). For comparing other exact finders with kss.
pub fn run_with_finder(
    scenario: &Scenario,
    options: &RunOptions,
    make: &mut dyn FnMut(&World) -> Box<dyn Finder>,
    on_event: &mut dyn FnMut(&CollisionEvent),
) -> Result<RunStats, RunError> {
    let start = std::time::Instant::now();
    let mut world = World::new(scenario, options.until)?;
    world.take_plan();
    let finder = make(&world);
    let mut sim = Simulation::with_finder(world, finder, options.audit)?;
    let build_seconds = start.elapsed().as_secs_f64();
    let events_start = std::time::Instant::now();
    drive(scenario, &mut sim, None, on_event)?;
    let events_seconds = events_start.elapsed().as_secs_f64();
    let mut stats = sim.stats();
    stats.build_seconds = build_seconds;
    stats.events_seconds = events_seconds;
    Ok(stats)
}

/// The simulation of `scenario` at time 0 with `structure` (the scenario's
/// flight-plan changes, insertions and removals are [`drive`]'s).
fn simulation(
    scenario: &Scenario,
    options: &RunOptions,
    structure: StructureKind,
) -> Result<Simulation, RunError> {
    let mut world = World::new(scenario, options.until)?;
    // applied by `drive` through the simulation, by id
    world.take_plan();
    let sim_options = SimOptions {
        structure,
        audit: options.audit,
        pair_method: options.pair_method,
        approximate_above: options.approximate_above,
    };
    Ok(Simulation::from_world(world, &sim_options)?)
}

/// The alive polygons of `world` as drawn, vertex `i` of body `b` at
/// `vertex(b, i)` (display only).
fn snapshot_polygons(
    world: &World,
    vertex: impl Fn(&crate::world::Body, usize) -> [f64; 2],
) -> Vec<crate::render::SnapshotPolygon> {
    world
        .bodies()
        .iter()
        .filter(|b| b.alive)
        .map(|b| crate::render::SnapshotPolygon {
            id: b.id.clone(),
            vertices: (0..b.shape.len()).map(|i| vertex(b, i)).collect(),
            fixed: b.fixed,
            velocity: b.traj.velocity().to_f64(),
        })
        .collect()
}

/// Run `scenario` up to `time` (collisions handled as in [`run`]) and return
/// the scene at that instant, for pictures.
pub fn snapshot_at(
    scenario: &Scenario,
    options: &RunOptions,
    time: f64,
) -> Result<crate::render::Snapshot, RunError> {
    let t = Time::from_f64(time).ok_or_else(|| RunError::Internal(format!("bad time {time}")))?;
    let mut sim = simulation(scenario, options, options.structure)?;
    drive(scenario, &mut sim, Some(&t), &mut |_| {})?;
    let polygons = snapshot_polygons(sim.world(), |b, i| b.vertex(i).at_f64(time));
    Ok(crate::render::Snapshot {
        time,
        polygons,
        structure: None,
    })
}

/// A run of the kinetic separation structure (plain or hierarchical)
/// stopped at one instant (see [`plain_state_at`]).
#[derive(Debug)]
pub struct PlainState {
    /// The world after every event up to the instant (later flight-plan
    /// changes not applied yet).
    pub world: World,
    /// The structure after every event at or before the instant, with its
    /// certificates scheduled: valid just after [`PlainState::time`].
    pub kinetic: Kinetic,
    /// How the structure sees the bodies (their outer approximations for the
    /// hierarchical structure; empty for plain).
    pub shapes: Shapes,
    /// The instant, exactly.
    pub time: Rational,
    /// If the run ended before the instant (the first collision in `stop`
    /// mode, or the scenario's `until`), when: the structure is not
    /// maintained after that, so it need not be valid at the instant.
    pub ended: Option<Time>,
}

/// Run `scenario` with the kinetic separation structure up to the instant
/// `time` (the exact value of the double; collisions handled as in [`run`],
/// every event at or before `time` processed except flight-plan changes at
/// exactly `time`) and return the world and the structure then. The
/// structure is the hierarchical one if `options.structure` says so, the
/// plain one otherwise; `options.until` and `options.audit` apply.
pub fn plain_state_at(
    scenario: &Scenario,
    options: &RunOptions,
    time: f64,
) -> Result<PlainState, RunError> {
    let t = Time::from_f64(time).ok_or_else(|| RunError::Internal(format!("bad time {time}")))?;
    let structure = match options.structure {
        StructureKind::Hierarchical => StructureKind::Hierarchical,
        _ => StructureKind::Plain,
    };
    let mut sim = simulation(scenario, options, structure)?;
    let mut last: Option<Time> = None;
    drive(scenario, &mut sim, Some(&t), &mut |e| {
        last = Some(e.time.clone());
    })?;
    let (world, engine) = sim.into_kinetic();
    let engine = engine.ok_or_else(|| RunError::Internal("no kinetic structure".into()))?;
    let ended = match last {
        Some(c) if world.mode() == CollisionMode::Stop && c < t => Some(c),
        _ if *world.until() < t => Some(world.until().clone()),
        _ => None,
    };
    let time = t.as_rational().expect("a double is rational").clone();
    Ok(PlainState {
        world,
        kinetic: engine.k,
        shapes: engine.shapes,
        time,
        ended,
    })
}

/// Like [`snapshot_at`] with the kinetic structure (plain, or hierarchical
/// if `options.structure` says so), and with the structure itself in
/// [`crate::render::Snapshot::structure`]: partition triangles, corridor
/// faces, bridges, the `highlight` certificates that fail first (see
/// `structure::view::overlay`) and, for the hierarchy, the outer
/// approximations. If the run ended before `time` (see
/// [`PlainState::ended`]), the structure carries a note instead.
pub fn structure_snapshot_at(
    scenario: &Scenario,
    options: &RunOptions,
    time: f64,
    highlight: usize,
) -> Result<crate::render::Snapshot, RunError> {
    let state = plain_state_at(scenario, options, time)?;
    let world = &state.world;
    let polygons = snapshot_polygons(world, |b, i| b.vertex_at(i, &state.time).to_f64());
    let structure = match &state.ended {
        None => {
            let geo = Geo {
                world,
                shapes: &state.shapes,
            };
            let mut o =
                crate::structure::view::overlay(&geo, &state.kinetic, &state.time, highlight);
            o.approximations = crate::structure::view::approximations(&geo, &state.time);
            o
        }
        Some(end) => crate::render::StructureOverlay {
            note: Some(format!(
                "structure not drawn: the run ended at t = {} ({})",
                end.to_f64(),
                if world.mode() == CollisionMode::Stop && end < world.until() {
                    "stop at the first collision"
                } else {
                    "until"
                }
            )),
            ..Default::default()
        },
    };
    Ok(crate::render::Snapshot {
        time,
        polygons,
        structure: Some(structure),
    })
}

/// What the scenario does at one instant besides collisions, in the
/// contract's order: removals, then insertions, then flight-plan changes.
#[derive(Default)]
struct Actions<'a> {
    removals: Vec<&'a str>,
    insertions: Vec<&'a PolygonSpec>,
    changes: Vec<(&'a str, [f64; 2])>,
}

/// Run the scenario on `sim` (at time 0): collisions at an instant come
/// first (reported, then `stop`, `remove` or `bounce`), then the removals,
/// insertions and flight-plan changes of that instant. With `stop_at`, the
/// run ends at that time (for snapshots; nothing scheduled at exactly
/// `stop_at` is applied).
fn drive(
    scenario: &Scenario,
    sim: &mut Simulation,
    stop_at: Option<&Time>,
    on_event: &mut dyn FnMut(&CollisionEvent),
) -> Result<(), RunError> {
    let until = sim.world().until().clone();
    let mode = sim.world().mode();
    let end = match stop_at {
        Some(t) if *t < until => t.clone(),
        _ => until,
    };
    let mut schedule: BTreeMap<Time, Actions> = BTreeMap::new();
    let applies = |time: f64| {
        let t = Time::from_f64(time).expect("validated: finite");
        (t <= end && (t < end || stop_at.is_none())).then_some(t)
    };
    for r in &scenario.removals {
        if let Some(t) = applies(r.time) {
            schedule.entry(t).or_default().removals.push(&r.id);
        }
    }
    for i in &scenario.insertions {
        if let Some(t) = applies(i.time) {
            schedule.entry(t).or_default().insertions.push(&i.polygon);
        }
    }
    for c in &scenario.flight_plan_changes {
        if let Some(t) = applies(c.time) {
            schedule
                .entry(t)
                .or_default()
                .changes
                .push((&c.id, c.velocity));
        }
    }
    loop {
        let target = schedule.keys().next().unwrap_or(&end).clone();
        let events = sim.advance_to(&target)?;
        if !events.is_empty() {
            for e in events.iter().filter(|e| !e.again) {
                on_event(e);
            }
            match mode {
                CollisionMode::Stop => break,
                CollisionMode::Remove => sim.remove_colliding(&events)?,
                CollisionMode::Bounce => sim.bounce(&events)?,
            }
            continue;
        }
        let Some(actions) = schedule.remove(&target) else {
            break;
        };
        for id in actions.removals {
            // (a polygon that already left in a collision stays gone)
            if sim.contains(id) {
                sim.remove(id)?;
            }
        }
        for p in actions.insertions {
            sim.insert(p)?;
        }
        let changes: Vec<(&str, [f64; 2])> = actions
            .changes
            .into_iter()
            .filter(|(id, _)| sim.contains(id))
            .collect();
        if !changes.is_empty() {
            sim.set_velocities(&changes)?;
        }
    }
    Ok(())
}

impl From<SimError> for RunError {
    fn from(e: SimError) -> RunError {
        match e {
            SimError::Invalid(e) => RunError::Invalid(e),
            SimError::Touches {
                inserted,
                present,
                time,
            } => RunError::InsertionTouches {
                inserted,
                present,
                time,
            },
            SimError::Internal(e) => RunError::Internal(e),
            SimError::Aborted(e) => RunError::Aborted(e),
            other => RunError::Internal(other.to_string()),
        }
    }
}
