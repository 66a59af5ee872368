//! Running a scenario with a chosen structure: the entry point of the library.

use std::collections::BTreeMap;

use crate::num::Time;
use crate::scenario::{Scenario, ScenarioError};

/// Which kinetic structure computes the collisions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum StructureKind {
    /// The separation-sensitive hierarchical structure (the default).
    #[default]
    Hierarchical,
    /// The kinetic separation structure without the hierarchy.
    Plain,
    /// All-pairs exact time of impact: the reference.
    Brute,
}

impl StructureKind {
    /// The contract's name (`"hierarchical"`, `"plain"`, `"brute"`).
    pub fn name(self) -> &'static str {
        match self {
            StructureKind::Hierarchical => "hierarchical",
            StructureKind::Plain => "plain",
            StructureKind::Brute => "brute",
        }
    }
}

/// Options of a run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// The structure to use.
    pub structure: StructureKind,
    /// Replaces the scenario's `until` (flight-plan changes after it are ignored).
    pub until: Option<f64>,
    /// Run the structure's audit after every event.
    pub audit: bool,
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
    /// Largest number of active (scheduled) certificates.
    pub certificates_max: u64,
    /// Active certificates at the end.
    pub certificates_final: u64,
    /// Collisions reported.
    pub collisions: u64,
}

/// Why a run could not complete.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scenario is invalid.
    #[error(transparent)]
    Invalid(#[from] ScenarioError),
    /// The requested structure is not available yet.
    #[error("structure `{0}` is not implemented yet; use --structure brute")]
    NotImplemented(&'static str),
    /// A broken invariant: a bug in kss.
    #[error("internal error (a bug in kss, please report it): {0}")]
    Internal(String),
}

/// Validate `scenario` and run it, calling `on_event` for every collision in
/// order. Returns the statistics of the run.
pub fn run(
    scenario: &Scenario,
    options: &RunOptions,
    on_event: &mut dyn FnMut(&CollisionEvent),
) -> Result<RunStats, RunError> {
    let _ = (scenario, on_event);
    Err(RunError::NotImplemented(options.structure.name()))
}

/// Run `scenario` up to `time` (collisions handled as in [`run`]) and return
/// the scene at that instant, for pictures.
pub fn snapshot_at(
    scenario: &Scenario,
    options: &RunOptions,
    time: f64,
) -> Result<crate::render::Snapshot, RunError> {
    let _ = (scenario, time);
    Err(RunError::NotImplemented(options.structure.name()))
}
