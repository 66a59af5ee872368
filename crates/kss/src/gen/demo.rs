//! [`demo`]: the built-in scene of `kss demo`.

use super::gas::box_walls;
use crate::scenario::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario};

/// The built-in scene of `kss demo`: nine convex polygons of various sizes in
/// a 16 x 10 box of four fixed walls (with gaps at the corners), bouncing,
/// with a few collisions in the first seconds. All coordinates are dyadic.
pub fn demo() -> Scenario {
    let poly =
        |id: &str, vertices: Vec<[f64; 2]>, position: [f64; 2], velocity: [f64; 2]| PolygonSpec {
            id: id.to_string(),
            vertices,
            position,
            velocity,
            fixed: false,
        };
    let mut polygons = vec![
        poly(
            "triangle",
            vec![[0.0, 0.0], [2.0, 0.0], [1.0, 1.75]],
            [1.0, 2.5],
            [2.0, 0.0],
        ),
        poly(
            "square",
            vec![[0.0, 0.0], [1.5, 0.0], [1.5, 1.5], [0.0, 1.5]],
            [7.0, 2.0],
            [-1.0, 0.25],
        ),
        poly(
            "hexagon",
            vec![
                [1.0, 0.0],
                [0.5, 0.875],
                [-0.5, 0.875],
                [-1.0, 0.0],
                [-0.5, -0.875],
                [0.5, -0.875],
            ],
            [12.5, 2.5],
            [-1.5, 0.5],
        ),
        poly(
            "pentagon",
            vec![
                [0.0, -1.0],
                [0.9375, -0.3125],
                [0.5625, 0.8125],
                [-0.5625, 0.8125],
                [-0.9375, -0.3125],
            ],
            [6.0, 7.5],
            [-0.75, 0.0],
        ),
        poly(
            "kite",
            vec![[0.0, -1.0], [0.5, 0.0], [0.0, 1.5], [-0.5, 0.0]],
            [2.0, 7.0],
            [1.5, 0.0],
        ),
        poly(
            "bar",
            vec![[0.0, 0.0], [4.0, 0.0], [4.0, 0.5], [0.0, 0.5]],
            [9.0, 8.0],
            [0.0, -0.75],
        ),
        poly(
            "octagon",
            vec![
                [0.75, 0.0],
                [0.5, 0.5],
                [0.0, 0.75],
                [-0.5, 0.5],
                [-0.75, 0.0],
                [-0.5, -0.5],
                [0.0, -0.75],
                [0.5, -0.5],
            ],
            [14.0, 6.5],
            [-1.0, -1.25],
        ),
        poly(
            "shard",
            vec![[0.0, 0.0], [1.25, -0.25], [0.5, 0.5]],
            [10.5, 5.0],
            [0.5, 1.0],
        ),
        poly(
            "boulder",
            vec![
                [1.5, 0.0],
                [1.25, 0.875],
                [0.5, 1.375],
                [-0.5, 1.375],
                [-1.25, 0.875],
                [-1.5, 0.0],
                [-1.25, -0.875],
                [-0.5, -1.375],
                [0.5, -1.375],
                [1.25, -0.875],
            ],
            [7.5, 5.25],
            [0.25, -0.125],
        ),
    ];
    polygons.extend(box_walls(16.0, 10.0, 4.0));
    Scenario {
        until: 12.0,
        on_collision: CollisionMode::Bounce,
        polygons,
        flight_plan_changes: vec![FlightPlanChange {
            time: 6.0,
            id: "boulder".to_string(),
            velocity: [-0.5, 0.5],
        }],
        ..Default::default()
    }
}
