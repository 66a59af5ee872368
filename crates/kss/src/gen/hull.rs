//! Strict convex hulls with exact orientation tests: of integer points
//! ([`hull_i64`]) and of doubles ([`strict_convex_hull`], [`orient_exact`]).

use crate::geom::{orient, Point};

/// Strict convex hull of integer points (exact), counter-clockwise.
pub(crate) fn hull_i64(mut pts: Vec<[i64; 2]>) -> Vec<[i64; 2]> {
    pts.sort();
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [i64; 2], a: [i64; 2], b: [i64; 2]| -> i128 {
        (a[0] - o[0]) as i128 * (b[1] - o[1]) as i128
            - (a[1] - o[1]) as i128 * (b[0] - o[0]) as i128
    };
    monotone_chain(&pts, |o, a, b| cross(o, a, b).signum() as i32)
}

/// Andrew's monotone chain over sorted, deduplicated points with the given
/// exact orientation test: strict hull, counter-clockwise.
fn monotone_chain<P: Copy>(pts: &[P], orient: impl Fn(P, P, P) -> i32) -> Vec<P> {
    let mut lower: Vec<P> = Vec::new();
    for &p in pts {
        while lower.len() >= 2 && orient(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<P> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && orient(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// The strict convex hull of `points` (exact predicates on the doubles):
/// counter-clockwise, no repeated points, no three consecutive collinear
/// vertices. Fewer than 3 points come back when all points are collinear.
pub fn strict_convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut pts: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup_by(|a, b| a[0] == b[0] && a[1] == b[1]);
    if pts.len() < 3 {
        return pts;
    }
    monotone_chain(&pts, orient_exact)
}

/// The sign of the orientation of `(a, b, c)`, exactly: 1 counter-clockwise,
/// -1 clockwise, 0 collinear. A floating-point filter (Shewchuk's first error
/// bound) settles most cases; the rest is computed on exact dyadic numbers.
pub fn orient_exact(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i32 {
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    let det = left - right;
    let sum = left.abs() + right.abs();
    // (3 + 16 eps) eps with eps = 2^-53.
    let bound = 3.330_669_073_875_471_6e-16 * sum;
    if sum > 1e-280 && sum.is_finite() {
        if det > bound {
            return 1;
        }
        if -det > bound {
            return -1;
        }
    }
    // The filter's determinant is (a - c) × (b - c), the orientation of
    // (c, a, b), which is that of (a, b, c); the library's kernel decides it
    // on the exact values of the doubles.
    let exact = |p: [f64; 2]| Point::from_f64(p).expect("exact arithmetic on a non-finite number");
    orient(&exact(a), &exact(b), &exact(c)).as_i32()
}
