//! Plain data types for scenarios (the contract in `docs/scenario-format.md`)
//! and their semantic validation.
//!
//! The library never parses JSON: the `kss` binary reads the file and builds a
//! [`Scenario`]; [`Scenario::validate`] then checks every rule of the contract
//! that is not about JSON syntax, exactly.

/// What happens when two polygons collide.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum CollisionMode {
    /// Report every collision at the earliest collision time, then end.
    #[default]
    Stop,
    /// Both polygons of a colliding pair leave the scene (fixed ones stay).
    Remove,
    /// Elastic frictionless collision response; the simulation goes on.
    Bounce,
}

impl CollisionMode {
    /// The contract's name of the mode (`"stop"`, `"remove"`, `"bounce"`).
    pub fn name(self) -> &'static str {
        match self {
            CollisionMode::Stop => "stop",
            CollisionMode::Remove => "remove",
            CollisionMode::Bounce => "bounce",
        }
    }
}

/// One polygon of a scenario, as given in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct PolygonSpec {
    /// Unique non-empty id.
    pub id: String,
    /// Vertices in the body frame, counter-clockwise, strictly convex.
    pub vertices: Vec<[f64; 2]>,
    /// World position of the body frame's origin at time 0.
    pub position: [f64; 2],
    /// Velocity until the polygon's first flight-plan change.
    pub velocity: [f64; 2],
    /// A fixed polygon never moves and has infinite mass.
    pub fixed: bool,
}

/// From `time` on, polygon `id` moves with `velocity`.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightPlanChange {
    /// When the new velocity takes effect (`0 < time <= until`).
    pub time: f64,
    /// The polygon whose plan changes.
    pub id: String,
    /// The new velocity.
    pub velocity: [f64; 2],
}

/// Polygon `polygon.id` enters the scene at `time`; its `position` is the
/// world position of its body frame's origin at that time.
#[derive(Clone, Debug, PartialEq)]
pub struct Insertion {
    /// When the polygon enters (`0 < time <= until`).
    pub time: f64,
    /// The polygon, its position given at `time`.
    pub polygon: PolygonSpec,
}

/// Polygon `id` leaves the scene at `time` (fixed ones included).
#[derive(Clone, Debug, PartialEq)]
pub struct Removal {
    /// When the polygon leaves (`0 < time <= until`).
    pub time: f64,
    /// The polygon (an initial or an inserted one).
    pub id: String,
}

/// A whole scenario, as given in the file (not yet validated).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Scenario {
    /// End of the simulated interval `[0, until]`.
    pub until: f64,
    /// Collision response.
    pub on_collision: CollisionMode,
    /// The polygons present at time 0.
    pub polygons: Vec<PolygonSpec>,
    /// Flight-plan changes, in any order.
    pub flight_plan_changes: Vec<FlightPlanChange>,
    /// Polygons that enter the scene during the run, in any order.
    pub insertions: Vec<Insertion>,
    /// Polygons that leave the scene during the run, in any order.
    pub removals: Vec<Removal>,
}

/// Why a scenario is invalid. Every message names the offending polygon(s) or
/// entry and says how to fix it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// `until` is not a finite number greater than 0.
    #[error("`until` is {0}: it must be a finite number greater than 0")]
    BadUntil(f64),
    /// A number is NaN or infinite.
    #[error("{what} is not a finite number ({value}); use finite numbers only")]
    NonFinite {
        /// Where the number is (for example `polygon "a" vertex 2`).
        what: String,
        /// The value found.
        value: f64,
    },
    /// A polygon id is empty.
    #[error("polygon #{index} has an empty id; give every polygon a unique non-empty id")]
    EmptyId {
        /// Index in the `polygons` array.
        index: usize,
    },
    /// Two polygons share an id.
    #[error("two polygons have the id {id:?}; ids must be unique")]
    DuplicateId {
        /// The repeated id.
        id: String,
    },
    /// Fewer than three vertices.
    #[error("polygon {id:?} has {count} vertices; a polygon needs at least 3")]
    TooFewVertices {
        /// The polygon.
        id: String,
        /// How many vertices it has.
        count: usize,
    },
    /// Two consecutive vertices are equal.
    #[error(
        "polygon {id:?} repeats vertex {index} (it equals the next vertex); remove the duplicate"
    )]
    RepeatedVertex {
        /// The polygon.
        id: String,
        /// Index of the first of the two equal vertices.
        index: usize,
    },
    /// Three consecutive vertices are collinear.
    #[error("polygon {id:?} has collinear consecutive vertices around vertex {index}; remove vertex {index} (polygons must be strictly convex)")]
    CollinearVertices {
        /// The polygon.
        id: String,
        /// The middle vertex of the collinear triple.
        index: usize,
    },
    /// The vertices turn clockwise.
    #[error("polygon {id:?} is clockwise; list its vertices counter-clockwise (reverse them)")]
    Clockwise {
        /// The polygon.
        id: String,
    },
    /// The polygon is not convex (or not simple).
    #[error("polygon {id:?} is not convex at vertex {index}; polygons must be convex with counter-clockwise vertices")]
    NotConvex {
        /// The polygon.
        id: String,
        /// A vertex where it turns the wrong way (or where it winds more than once).
        index: usize,
    },
    /// A fixed polygon has a non-zero velocity.
    #[error("polygon {id:?} is fixed but has a non-zero velocity; remove the velocity or set `fixed` to false")]
    FixedWithVelocity {
        /// The polygon.
        id: String,
    },
    /// A flight-plan change names a fixed polygon.
    #[error("flight_plan_changes[{index}] changes fixed polygon {id:?}; a fixed polygon cannot change its plan")]
    FixedWithChange {
        /// Index in `flight_plan_changes`.
        index: usize,
        /// The polygon.
        id: String,
    },
    /// A flight-plan change names no polygon.
    #[error("flight_plan_changes[{index}] names unknown polygon {id:?}; use the id of one of the polygons")]
    UnknownChangeId {
        /// Index in `flight_plan_changes`.
        index: usize,
        /// The id given.
        id: String,
    },
    /// A flight-plan change time is outside `(0, until]`.
    #[error("flight_plan_changes[{index}] (polygon {id:?}) has time {time}, outside (0, until = {until}]; use a time in that interval")]
    ChangeTimeOutOfRange {
        /// Index in `flight_plan_changes`.
        index: usize,
        /// The polygon.
        id: String,
        /// The time given.
        time: f64,
        /// The scenario's `until`.
        until: f64,
    },
    /// Two flight-plan changes of one polygon at one time.
    #[error("flight_plan_changes[{first}] and [{second}] both change polygon {id:?} at time {time}; keep one")]
    DuplicateChange {
        /// Index of the first change.
        first: usize,
        /// Index of the second change.
        second: usize,
        /// The polygon.
        id: String,
        /// The common time.
        time: f64,
    },
    /// An inserted polygon's id is empty.
    #[error("insertions[{index}] has a polygon with an empty id; give every polygon a unique non-empty id")]
    EmptyInsertedId {
        /// Index in the `insertions` array.
        index: usize,
    },
    /// An insertion time is outside `(0, until]`.
    #[error("insertions[{index}] (polygon {id:?}) has time {time}, outside (0, until = {until}]; use a time in that interval")]
    InsertionTimeOutOfRange {
        /// Index in `insertions`.
        index: usize,
        /// The inserted polygon.
        id: String,
        /// The time given.
        time: f64,
        /// The scenario's `until`.
        until: f64,
    },
    /// A removal time is outside `(0, until]`.
    #[error("removals[{index}] (polygon {id:?}) has time {time}, outside (0, until = {until}]; use a time in that interval")]
    RemovalTimeOutOfRange {
        /// Index in `removals`.
        index: usize,
        /// The polygon.
        id: String,
        /// The time given.
        time: f64,
        /// The scenario's `until`.
        until: f64,
    },
    /// A removal names no polygon.
    #[error("removals[{index}] names unknown polygon {id:?}; use the id of an initial or an inserted polygon")]
    UnknownRemovalId {
        /// Index in `removals`.
        index: usize,
        /// The id given.
        id: String,
    },
    /// Two removals of one polygon.
    #[error("removals[{first}] and [{second}] both remove polygon {id:?}; keep one")]
    DuplicateRemoval {
        /// Index of the first removal.
        first: usize,
        /// Index of the second removal.
        second: usize,
        /// The polygon.
        id: String,
    },
    /// An inserted polygon is removed at or before its insertion.
    #[error("removals[{index}] removes polygon {id:?} at time {time}, not after its insertion at time {inserted}; remove it later")]
    RemovalNotAfterInsertion {
        /// Index in `removals`.
        index: usize,
        /// The polygon.
        id: String,
        /// The removal time.
        time: f64,
        /// The insertion time.
        inserted: f64,
    },
    /// A flight-plan change outside its polygon's lifetime.
    #[error("flight_plan_changes[{index}] changes polygon {id:?} at time {time}, {why}; a polygon's plan changes only while it is in the scene")]
    ChangeOutsideLifetime {
        /// Index in `flight_plan_changes`.
        index: usize,
        /// The polygon.
        id: String,
        /// The change time.
        time: f64,
        /// Which end of the lifetime it misses.
        why: String,
    },
    /// Two polygons touch or overlap at time 0.
    #[error("polygons {a:?} and {b:?} touch or overlap at time 0; move them apart (polygons must be disjoint at the start)")]
    Overlap {
        /// First polygon of the pair.
        a: String,
        /// Second polygon of the pair.
        b: String,
    },
}
