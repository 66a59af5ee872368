//! kss: exact kinetic collision detection for moving convex polygons.
//!
//! (Crate documentation is being written; see README.md.)

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod brute;
pub mod gen;
pub mod geom;
pub mod motion;
pub mod num;
pub mod render;
pub mod rng;
pub mod runner;
pub mod scenario;
pub mod sim;
pub mod world;

pub use runner::{run, CollisionEvent, RunError, RunOptions, RunStats, StructureKind};
pub use scenario::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario, ScenarioError};
