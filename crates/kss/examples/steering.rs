//! Steering agents: a caller-chosen response to every contact.
//!
//! Forty small convex agents move in a box of four fixed walls (the walls
//! leave narrow gaps at the corners, so that no two polygons touch at time
//! 0, and the gaps are too narrow for an agent to slip through). The
//! program drives a [`kss::Simulation`] itself: it advances to the next
//! contact, and each agent of each touching pair steers away with a
//! velocity of its own choosing, then it advances again. The new heading
//! points from the contact point towards the agent's centre, turned by a
//! deterministic pseudo-random angle of at most 0.45 rad, at a new
//! pseudo-random speed. For a convex agent the centre lies strictly on its
//! own side of every line that separates it from the other polygon at the
//! contact point, and the turn is smaller than the angle that leaves to
//! spare for these regular agents, so the pair separates; an agent caught
//! in several contacts at one instant steers along the sum of its
//! headings, and a pair that this leaves interpenetrating comes back at
//! the same instant (`again`) and is answered with the built-in
//! [`kss::Simulation::bounce`].
//!
//! It prints the first contacts, then a summary (contacts by kind, the
//! exact time of the last one, the structure's statistics) and checks that
//! every agent is still inside the box.
//!
//! ```sh
//! cargo run --release -p kss --example steering
//! ```

use std::collections::BTreeMap;
use std::f64::consts::TAU;

use kss::gen::regular_polygon;
use kss::rng::Rng;
use kss::{PolygonSpec, SimError, SimOptions, Simulation, StructureKind};

/// Side of the square box (its inside is `[0, SIDE]²`).
const SIDE: f64 = 12.0;
/// Number of agents.
const AGENTS: usize = 40;
/// The simulated interval is `[0, UNTIL]`.
const UNTIL: f64 = 60.0;
/// How many contacts the log prints one by one.
const LOGGED: usize = 12;

/// An axis-parallel rectangle `[x0, x1] × [y0, y1]`, fixed, centred on its
/// body frame's origin.
fn wall(id: &str, x0: f64, y0: f64, x1: f64, y1: f64) -> PolygonSpec {
    let (hw, hh) = ((x1 - x0) / 2.0, (y1 - y0) / 2.0);
    PolygonSpec {
        id: id.into(),
        vertices: vec![[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]],
        position: [x0 + hw, y0 + hh],
        velocity: [0.0, 0.0],
        fixed: true,
    }
}

/// The four walls, one unit thick, each stopping `gap` short of the
/// corners.
fn walls(gap: f64) -> Vec<PolygonSpec> {
    vec![
        wall("wall-s", gap, -1.0, SIDE - gap, 0.0),
        wall("wall-n", gap, SIDE, SIDE - gap, SIDE + 1.0),
        wall("wall-w", -1.0, gap, 0.0, SIDE - gap),
        wall("wall-e", SIDE, gap, SIDE + 1.0, SIDE - gap),
    ]
}

/// The agents: regular 3- to 8-gons of circumradius 0.2–0.35, one per cell
/// of a grid inside the box, with pseudo-random velocities.
fn agents(rng: &mut Rng) -> Vec<PolygonSpec> {
    let cols = (AGENTS as f64).sqrt().ceil() as usize;
    let cell = SIDE / cols as f64;
    (0..AGENTS)
        .map(|i| {
            let heading = rng.range_f64(0.0, TAU);
            let speed = rng.range_f64(0.5, 1.5);
            PolygonSpec {
                id: format!("agent-{i:02}"),
                vertices: regular_polygon(
                    3 + i % 6,
                    rng.range_f64(0.2, 0.35),
                    rng.range_f64(0.0, TAU),
                ),
                position: [
                    (i % cols) as f64 * cell + cell / 2.0,
                    (i / cols) as f64 * cell + cell / 2.0,
                ],
                velocity: [speed * heading.cos(), speed * heading.sin()],
                fixed: false,
            }
        })
        .collect()
}

fn main() -> Result<(), SimError> {
    let mut rng = Rng::new(2024);
    let mut polygons = walls(0.05);
    polygons.extend(agents(&mut rng));
    let options = SimOptions {
        structure: StructureKind::Hierarchical,
        ..SimOptions::default()
    };
    let mut sim = Simulation::new(&polygons, &options)?;
    let is_wall = |id: &str| id.starts_with("wall");

    let (mut agent_contacts, mut wall_contacts, mut again, mut instants) = (0u64, 0u64, 0u64, 0u64);
    let mut last = None;
    loop {
        let events = sim.advance(UNTIL)?;
        if events.is_empty() {
            break;
        }
        instants += 1;
        let (fresh, repeated): (Vec<_>, Vec<_>) = events.into_iter().partition(|e| !e.again);
        if !repeated.is_empty() {
            // the steering of an agent in several contacts left these pairs
            // interpenetrating: the built-in elastic response separates them
            again += repeated.len() as u64;
            sim.bounce(&repeated)?;
        }
        // each agent steers along the sum of its headings away from its
        // contact points, at one new speed
        let mut heading: BTreeMap<&str, [f64; 2]> = BTreeMap::new();
        for e in &fresh {
            if is_wall(&e.a) || is_wall(&e.b) {
                wall_contacts += 1;
            } else {
                agent_contacts += 1;
            }
            let n = agent_contacts + wall_contacts;
            if n as usize <= LOGGED {
                println!(
                    "t = {:9.5}  {} touches {} at ({:.3}, {:.3})",
                    e.time.to_f64(),
                    e.a,
                    e.b,
                    e.point[0],
                    e.point[1]
                );
            } else if n as usize == LOGGED + 1 {
                println!("...");
            }
            for id in [e.a.as_str(), e.b.as_str()] {
                if is_wall(id) {
                    continue;
                }
                let [x, y] = sim.position(id)?.map(|c| c.to_f64());
                let (dx, dy) = (x - e.point[0], y - e.point[1]);
                let len = dx.hypot(dy);
                let h = heading.entry(id).or_insert([0.0, 0.0]);
                h[0] += dx / len;
                h[1] += dy / len;
            }
            last = Some(e.time.clone());
        }
        let mut changes = Vec::new();
        for (id, [hx, hy]) in heading {
            let turn = rng.range_f64(-0.45, 0.45);
            let speed = rng.range_f64(0.5, 1.5);
            let len = hx.hypot(hy);
            let v = if len < 1e-9 {
                // squeezed from opposite sides: stand still
                [0.0, 0.0]
            } else {
                let (c, s) = (turn.cos(), turn.sin());
                let (ux, uy) = (hx / len, hy / len);
                [speed * (c * ux - s * uy), speed * (s * ux + c * uy)]
            };
            changes.push((id, v));
        }
        if !changes.is_empty() {
            sim.set_velocities(&changes)?;
        }
    }

    let mut outside = 0;
    for id in sim.polygons().filter(|id| !is_wall(id)) {
        let [x, y] = sim.position(id)?.map(|c| c.to_f64());
        if !(0.0..=SIDE).contains(&x) || !(0.0..=SIDE).contains(&y) {
            outside += 1;
        }
    }
    let stats = sim.stats();
    println!();
    println!(
        "{AGENTS} agents in a {SIDE} × {SIDE} box, simulated until t = {}",
        sim.now().to_f64()
    );
    println!(
        "contacts: {} ({agent_contacts} agent–agent, {wall_contacts} agent–wall) at {instants} instants; {again} pairs needed the built-in bounce",
        agent_contacts + wall_contacts
    );
    if let Some(t) = last {
        // contact times of translating polygons are rational
        match t.as_rational() {
            Some(r) => println!("last contact at t = {r} (exact) ≈ {}", t.to_f64()),
            None => println!("last contact at t ≈ {}", t.to_f64()),
        }
    }
    println!(
        "structure {}: {} events, at most {} certificates",
        stats.structure, stats.events_processed, stats.certificates_max
    );
    println!("agents outside the box: {outside}");
    assert_eq!(outside, 0, "an agent left the box");
    Ok(())
}
