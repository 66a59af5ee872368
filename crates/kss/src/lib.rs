//! kss: exact kinetic collision detection for moving convex polygons.
//!
//! (Crate documentation is being written; see README.md.)

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod num;
pub mod geom;
pub mod motion;
pub mod sim;
pub mod scenario;
pub mod world;
pub mod brute;
pub mod gen;
pub mod render;
pub mod rng;
pub mod runner;

pub use runner::{run, CollisionEvent, RunError, RunOptions, RunStats, StructureKind};
pub use scenario::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario, ScenarioError};
