//! A gate: polygons enter at regular times, cross a field of fixed
//! obstacles and leave at an exit.
//!
//! The field is the strip `0 ≤ y ≤ 10` between two fixed walls, with
//! three fixed obstacles. Every quarter of a time unit a spawner inserts a
//! new polygon at the gate, `x = 1`, at a pseudo-random height, heading
//! east at speed 2 ([`kss::Simulation::insert`], the position given at the
//! current time). When the previous polygon is still in the way, `insert`
//! refuses with [`kss::SimError::Touches`] and the spawner tries again at
//! its next tick with the same polygon. A polygon that touches a wall or an
//! obstacle bounces off it ([`kss::Simulation::bounce`]); two polygons that
//! touch each other crash and both leave the scene
//! ([`kss::Simulation::remove_colliding`]). At every tick the program reads
//! the exact positions and removes ([`kss::Simulation::remove`]) the
//! polygons whose centre has passed the exit line `x = 28`, and those that
//! bounced back behind the gate (`x = -1`).
//!
//! It prints a line every twenty time units and the counts at the end,
//! and checks that every polygon is accounted for.
//!
//! ```sh
//! cargo run --release -p kss --example gate
//! ```

use std::collections::HashSet;
use std::f64::consts::TAU;

use kss::gen::regular_polygon;
use kss::num::Rational;
use kss::rng::Rng;
use kss::{CollisionEvent, PolygonSpec, SimError, SimOptions, Simulation};

/// Length of the walls' stretch east of the gate.
const LENGTH: f64 = 30.0;
/// Width of the field.
const WIDTH: f64 = 10.0;
/// A polygon whose centre passes this line leaves the scene.
const EXIT_X: f64 = 28.0;
/// A polygon that turned back leaves the scene when its centre passes
/// this line, behind the gate.
const BACK_X: f64 = -1.0;
/// The spawner's period (a double, so that the ticks are exact).
const TICK: f64 = 0.25;
/// The simulated interval is `[0, UNTIL]`.
const UNTIL: f64 = 120.0;

/// A fixed polygon with `vertices` around `centre`.
fn fixed(id: &str, vertices: Vec<[f64; 2]>, centre: [f64; 2]) -> PolygonSpec {
    PolygonSpec {
        id: id.into(),
        vertices,
        position: centre,
        velocity: [0.0, 0.0],
        fixed: true,
    }
}

/// A fixed axis-parallel rectangle `[x0, x1] × [y0, y1]`.
fn wall(id: &str, x0: f64, y0: f64, x1: f64, y1: f64) -> PolygonSpec {
    let (hw, hh) = ((x1 - x0) / 2.0, (y1 - y0) / 2.0);
    let vertices = vec![[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]];
    fixed(id, vertices, [x0 + hw, y0 + hh])
}

/// The walls and the obstacles.
fn field() -> Vec<PolygonSpec> {
    vec![
        wall("#wall-s", -2.0, -1.0, LENGTH + 2.0, 0.0),
        wall("#wall-n", -2.0, WIDTH, LENGTH + 2.0, WIDTH + 1.0),
        fixed("#rock-1", regular_polygon(8, 0.5, 0.2), [9.0, 3.0]),
        fixed("#rock-2", regular_polygon(6, 0.5, 0.0), [14.0, 7.0]),
        fixed("#rock-3", regular_polygon(3, 0.6, 0.0), [20.0, 4.5]),
    ]
}

/// The spawner's next polygon: a regular 3- to 7-gon at the gate, heading
/// east.
fn next_arrival(n: u64, rng: &mut Rng) -> PolygonSpec {
    let speed = 2.0;
    let heading = rng.range_f64(-0.1, 0.1);
    PolygonSpec {
        id: format!("p{n:04}"),
        vertices: regular_polygon(
            3 + (n % 5) as usize,
            rng.range_f64(0.2, 0.35),
            rng.range_f64(0.0, TAU),
        ),
        position: [1.0, rng.range_f64(3.5, 6.5)],
        velocity: [speed * heading.cos(), speed * heading.sin()],
        fixed: false,
    }
}

/// Answers the collisions of one instant: polygons bounce off fixed ones
/// and crash into each other; returns how many pairs crashed.
fn respond(sim: &mut Simulation, events: &[CollisionEvent]) -> Result<u64, SimError> {
    let is_fixed = |id: &str| id.starts_with('#');
    let crashes = events
        .iter()
        .filter(|e| !is_fixed(&e.a) && !is_fixed(&e.b))
        .count() as u64;
    let crashed: HashSet<&str> = events
        .iter()
        .filter(|e| !is_fixed(&e.a) && !is_fixed(&e.b))
        .flat_map(|e| [e.a.as_str(), e.b.as_str()])
        .collect();
    // `remove_colliding` answers the pairs it is given: those of the
    // crashed polygons with fixed ones go with them (fixed polygons stay)
    let (gone, off_fixed): (Vec<CollisionEvent>, Vec<CollisionEvent>) = events
        .iter()
        .cloned()
        .partition(|e| crashed.contains(e.a.as_str()) || crashed.contains(e.b.as_str()));
    sim.remove_colliding(&gone)?;
    sim.bounce(&off_fixed)?;
    Ok(crashes)
}

fn main() -> Result<(), SimError> {
    let mut rng = Rng::new(7);
    let mut sim = Simulation::new(&field(), &SimOptions::default())?;
    let exit = Rational::from_f64(EXIT_X).expect("a finite double");
    let back = Rational::from_f64(BACK_X).expect("a finite double");

    let (mut spawned, mut refused, mut exited, mut crash_pairs, mut bounces) =
        (0u64, 0u64, 0u64, 0u64, 0u64);
    let mut turned_back = 0u64;
    let mut waiting = next_arrival(0, &mut rng);
    let mut tick = 0u64;
    loop {
        let t = tick as f64 * TICK;
        // advance to the tick, answering every collision on the way
        loop {
            let events = sim.advance(t)?;
            if events.is_empty() {
                break;
            }
            let crashed = respond(&mut sim, &events)?;
            crash_pairs += crashed;
            bounces += events.len() as u64 - crashed;
        }
        // the exits: exact positions, compared exactly
        let moving: Vec<String> = sim
            .polygons()
            .filter(|id| !id.starts_with('#'))
            .map(str::to_string)
            .collect();
        for id in moving {
            let x = &sim.position(&id)?[0];
            if *x >= exit {
                sim.remove(&id)?;
                exited += 1;
            } else if *x <= back {
                sim.remove(&id)?;
                turned_back += 1;
            }
        }
        if t >= UNTIL {
            break;
        }
        // the gate: the waiting polygon enters now, or waits for the next tick
        match sim.insert(&waiting) {
            Ok(()) => {
                spawned += 1;
                waiting = next_arrival(spawned, &mut rng);
            }
            Err(SimError::Touches { .. }) => refused += 1,
            Err(e) => return Err(e),
        }
        if tick % 80 == 0 {
            let moving = sim.polygons().filter(|id| !id.starts_with('#')).count();
            println!(
                "t = {t:5.1}: {moving:3} polygons in the field, {spawned:3} spawned, {exited:3} exited, {crash_pairs:3} crashes"
            );
        }
        tick += 1;
    }

    let left = sim.polygons().filter(|id| !id.starts_with('#')).count() as u64;
    let crashed = spawned - exited - turned_back - left;
    let stats = sim.stats();
    println!();
    println!("until t = {UNTIL}, a spawn every {TICK}:");
    println!("  spawned           {spawned}");
    println!("  refused at the gate (tried again later) {refused}");
    println!("  exited            {exited}");
    println!("  turned back       {turned_back}");
    println!("  crashed           {crashed} (in {crash_pairs} crashes)");
    println!("  bounces           {bounces}");
    println!("  still in the field {left}");
    println!(
        "structure {}: {} events, {} rebuilds for insertions",
        stats.structure, stats.events_processed, stats.insert_rebuilds
    );
    assert!(
        crashed <= 2 * crash_pairs,
        "every crashed polygon left in a crash"
    );
    Ok(())
}
