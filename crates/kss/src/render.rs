//! Pictures: a snapshot of the scene at one instant, drawn as an SVG string.

/// One polygon as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapshotPolygon {
    /// Its id.
    pub id: String,
    /// World coordinates of its vertices at the snapshot time (display only).
    pub vertices: Vec<[f64; 2]>,
    /// Whether it is fixed.
    pub fixed: bool,
    /// Its velocity at the snapshot time.
    pub velocity: [f64; 2],
}

/// The scene at one instant, for display.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Snapshot {
    /// The time shown.
    pub time: f64,
    /// The polygons still in the scene.
    pub polygons: Vec<SnapshotPolygon>,
}
