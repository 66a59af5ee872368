//! kss: exact kinetic collision detection for moving convex polygons.
//!
//! Given convex polygons that translate along piecewise-linear flight plans,
//! kss reports every collision exactly and in time order, without stepping
//! time. It implements the *separation-sensitive kinetic separation
//! structure* of Kirkpatrick and Speckmann, and ships the exact all-pairs
//! reference it is tested against.
//!
//! # Contents
//!
//! - [`run`]: validate a [`Scenario`] and report its collisions ([`CollisionEvent`]).
//! - [`Simulation`]: the same, driven by the caller: advance to the next
//!   collision, answer it (new velocities, removals, insertions, or a
//!   built-in response), advance again.
//! - [`scenario`]: the input data and its errors; [`gen`]: scenario generators.
//! - `json` (with the `serde` feature): scenario files' JSON text, read into a
//!   [`Scenario`] and written from one (`docs/scenario-format.md`).
//! - [`num`]: exact numbers and the exact, filtered order of event [`num::Time`]s.
//! - [`sim`]: the event queue; [`world`]: bodies, flight plans, collision policy.
//! - [`runner`]: the engines behind [`run`], and snapshots of a run.
//! - [`brute`]: the all-pairs reference; [`render`]: SVG pictures.
//!
//! The geometry kernel (`geom`), moving points and certificate functions
//! (`motion`), the per-polygon hierarchy of outer approximations (`hier`),
//! the exact constrained triangulation (`cdt`) and the kinetic separation
//! structure itself (`structure`: construction, certificates, local
//! operations, local repair, pops and merges, audit) are internal. The cargo
//! feature `internals` makes them public for debugging tools and property
//! tests; they are not a stable API.
//!
//! # Should I use this?
//!
//! Use kss when you need collision *times* you can trust exactly (planning,
//! discrete-event simulation, testing other collision code) for convex
//! polygons on known linear motions. Do not use it for rotating bodies or
//! for interactive physics where approximate contacts are fine.
//!
//! # Example
//!
//! ```
//! use kss::{run, CollisionMode, PolygonSpec, RunOptions, Scenario, StructureKind};
//!
//! let square = |id: &str, x: f64, vx: f64| PolygonSpec {
//!     id: id.into(),
//!     vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
//!     position: [x, 0.0],
//!     velocity: [vx, 0.0],
//!     fixed: false,
//! };
//! let scenario = Scenario {
//!     until: 10.0,
//!     on_collision: CollisionMode::Stop,
//!     polygons: vec![square("a", 0.0, 2.0), square("b", 2.0, -1.0)],
//!     ..Default::default()
//! };
//! let options = RunOptions { structure: StructureKind::Brute, ..Default::default() };
//! let mut events = Vec::new();
//! run(&scenario, &options, &mut |e| events.push(e.clone()))?;
//! // the gap of 1 closes at speed 3: contact at exactly t = 1/3
//! assert_eq!(events.len(), 1);
//! assert_eq!(events[0].time.as_rational().unwrap().to_string(), "1/3");
//! # Ok::<(), kss::RunError>(())
//! ```
//!
//! The same kind of scene driven step by step with a [`Simulation`]: two
//! unit squares meet, bounce, and the left one bounces again off a fixed
//! square.
//!
//! ```
//! use kss::{PolygonSpec, SimOptions, Simulation};
//!
//! let square = |id: &str, x: f64, vx: f64, fixed: bool| PolygonSpec {
//!     id: id.into(),
//!     vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
//!     position: [x, 0.0],
//!     velocity: [vx, 0.0],
//!     fixed,
//! };
//! let polygons = [
//!     square("a", 0.0, 1.0, false),
//!     square("b", 3.0, -1.0, false),
//!     square("wall", -3.0, 0.0, true),
//! ];
//! let mut sim = Simulation::new(&polygons, &SimOptions::default())?;
//! // the gap of 2 between a and b closes at speed 2: contact at t = 1
//! let events = sim.advance(10.0)?;
//! assert_eq!((events[0].a.as_str(), events[0].b.as_str()), ("a", "b"));
//! assert_eq!(events[0].time.as_rational().unwrap().to_string(), "1");
//! // equal masses swap velocities: a moves left at speed 1
//! sim.bounce(&events)?;
//! assert_eq!(sim.velocity("a")?[0].to_f64(), -1.0);
//! // a (its left side at x = 1) reaches the wall's side at x = -2 at t = 4
//! let events = sim.advance(10.0)?;
//! assert_eq!((events[0].a.as_str(), events[0].b.as_str()), ("a", "wall"));
//! assert_eq!(events[0].time.as_rational().unwrap().to_string(), "4");
//! sim.bounce(&events)?;
//! // no more collisions: both move right at speed 1 until t = 10
//! assert!(sim.advance(10.0)?.is_empty());
//! assert_eq!(sim.now().to_f64(), 10.0);
//! assert_eq!(sim.position("a")?[0].to_string(), "4");
//! assert_eq!(sim.position("b")?[0].to_string(), "11");
//! # Ok::<(), kss::SimError>(())
//! ```
//!
//! # Glossary
//!
//! - **trajectory / flight plan**: a body's piecewise-linear path; its velocity
//!   changes at given times, its position is continuous.
//! - **certificate**: an elementary geometric test (the sign of an orientation
//!   of three moving points) that holds between events.
//! - **certificate function**: the certificate as a polynomial in time, of
//!   degree at most two, positive while the certificate holds.
//! - **event**: the failure time of a certificate (a root of its function), or
//!   a flight-plan change; processed in exact time order.
//! - **audit**: a check of every invariant of a structure, exactly, at a
//!   rational instant strictly between two event times.
//! - **partition triangle**: a free-space triangle whose corners lie on three
//!   different objects (the point at infinity counts as one); there are 2k − 2.
//! - **corridor**: a region of free space between two partition triangles,
//!   bounded by two end-edges and two polygon chains; there are 3k − 3.
//! - **pseudo-triangle**: a face with exactly three convex corners joined by
//!   concave chains; each corridor holds at most two.
//! - **approximation vertex**: a vertex of a polygon's coarse outer
//!   approximation (intersection of two supporting lines) in the hierarchy.
//! - **pop / merge**: refining an approximation by one level where two
//!   approximations touch (an event), and coarsening it again where the
//!   polygons have moved apart.
//! - **local repair**: triangulating again only the region around a few
//!   polygons, for just after a degenerate instant that the local
//!   operations cannot resolve (instead of rebuilding everything).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod brute;
#[cfg(feature = "internals")]
pub mod cdt;
#[cfg(not(feature = "internals"))]
#[allow(dead_code)]
pub(crate) mod cdt;
mod engine;
pub mod gen;
#[cfg(feature = "internals")]
pub mod geom;
#[cfg(not(feature = "internals"))]
#[allow(dead_code)]
pub(crate) mod geom;
#[cfg(feature = "internals")]
pub mod hier;
#[cfg(not(feature = "internals"))]
#[allow(dead_code)]
pub(crate) mod hier;
#[cfg(feature = "serde")]
pub mod json;
#[cfg(feature = "internals")]
pub mod motion;
#[cfg(not(feature = "internals"))]
#[allow(dead_code)]
pub(crate) mod motion;
pub mod num;
pub mod render;
pub mod rng;
pub mod runner;
pub mod scenario;
pub mod sim;
pub mod simulation;
#[cfg(feature = "internals")]
pub mod structure;
#[cfg(not(feature = "internals"))]
#[allow(dead_code)]
pub(crate) mod structure;
pub mod world;

pub use runner::{
    run, run_with_finder, CollisionEvent, RunError, RunOptions, RunStats, StructureKind,
    DEFAULT_APPROXIMATE_ABOVE,
};
pub use scenario::{
    CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, Scenario, ScenarioError,
};
pub use simulation::{Collisions, Finder, SimError, SimOptions, Simulation};
