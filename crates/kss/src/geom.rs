//! Static exact geometry: points, convex body polygons and the predicates
//! every decision goes through.
//!
//! This is the only place (with [`crate::motion`], for moving points) where a
//! sign is computed from coordinates. Body-frame coordinates are doubles and
//! therefore dyadic rationals; a [`BodyPolygon`] stores them as integers over
//! one power of two so that predicates run on integers.

use crate::num::{decompose_f64, Int, Rational, Sign};

/// An exact point.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Point {
    /// x coordinate.
    pub x: Rational,
    /// y coordinate.
    pub y: Rational,
}

impl Point {
    /// The exact point with these double coordinates; `None` if one is not finite.
    pub fn from_f64(p: [f64; 2]) -> Option<Point> {
        Some(Point {
            x: Rational::from_f64(p[0])?,
            y: Rational::from_f64(p[1])?,
        })
    }

    /// `self + other`.
    pub fn add(&self, other: &Point) -> Point {
        Point {
            x: self.x.add(&other.x),
            y: self.y.add(&other.y),
        }
    }

    /// `self - other`.
    pub fn sub(&self, other: &Point) -> Point {
        Point {
            x: self.x.sub(&other.x),
            y: self.y.sub(&other.y),
        }
    }

    /// `self · s`.
    pub fn scale(&self, s: &Rational) -> Point {
        Point {
            x: self.x.mul(s),
            y: self.y.mul(s),
        }
    }

    /// Dot product.
    pub fn dot(&self, other: &Point) -> Rational {
        self.x.mul(&other.x).add(&self.y.mul(&other.y))
    }

    /// Cross product (z component).
    pub fn cross(&self, other: &Point) -> Rational {
        self.x.mul(&other.y).sub(&self.y.mul(&other.x))
    }

    /// For display.
    pub fn to_f64(&self) -> [f64; 2] {
        [self.x.to_f64(), self.y.to_f64()]
    }
}

/// Orientation of `r` with respect to the directed line `p → q`: positive if
/// `r` lies to the left.
pub fn orient(p: &Point, q: &Point, r: &Point) -> Sign {
    q.sub(p).cross(&r.sub(p)).sign()
}

/// A convex polygon in its body frame, stored exactly as integers
/// `(xs[i], ys[i]) · 2^exp`, counter-clockwise and strictly convex.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPolygon {
    xs: Vec<Int>,
    ys: Vec<Int>,
    exp: i64,
    f64s: Vec<[f64; 2]>,
}

/// What is wrong with a vertex list (see [`BodyPolygon::new`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolygonDefect {
    /// Fewer than three vertices.
    TooFew,
    /// A coordinate is not finite.
    NonFinite(usize),
    /// Vertex `i` equals vertex `i + 1`.
    Repeated(usize),
    /// Vertices `i - 1, i, i + 1` are collinear.
    Collinear(usize),
    /// Every turn is clockwise.
    Clockwise,
    /// The turn at vertex `i` goes the wrong way, or the boundary winds more than once.
    NotConvex(usize),
}

impl BodyPolygon {
    /// Check and convert a vertex list: at least three finite points,
    /// counter-clockwise, strictly convex, winding exactly once.
    pub fn new(vertices: &[[f64; 2]]) -> Result<BodyPolygon, PolygonDefect> {
        let n = vertices.len();
        if n < 3 {
            return Err(PolygonDefect::TooFew);
        }
        let mut parts = Vec::with_capacity(2 * n);
        for (i, v) in vertices.iter().enumerate() {
            for c in v {
                parts.push(decompose_f64(*c).ok_or(PolygonDefect::NonFinite(i))?);
            }
        }
        let exp = parts
            .iter()
            .filter(|(m, _)| !m.is_zero())
            .map(|(_, e)| *e)
            .min()
            .unwrap_or(0);
        let ints: Vec<Int> = parts
            .into_iter()
            .map(|(m, e)| if m.is_zero() { m } else { m << ((e - exp) as usize) })
            .collect();
        let xs: Vec<Int> = ints.iter().step_by(2).cloned().collect();
        let ys: Vec<Int> = ints.iter().skip(1).step_by(2).cloned().collect();
        let poly = BodyPolygon {
            xs,
            ys,
            exp,
            f64s: vertices.to_vec(),
        };
        poly.check_convex()?;
        Ok(poly)
    }

    fn check_convex(&self) -> Result<(), PolygonDefect> {
        let n = self.len();
        for i in 0..n {
            let j = (i + 1) % n;
            if self.xs[i] == self.xs[j] && self.ys[i] == self.ys[j] {
                return Err(PolygonDefect::Repeated(i));
            }
        }
        let turns: Vec<Sign> = (0..n).map(|i| self.turn(i)).collect();
        if let Some(i) = turns.iter().position(|s| *s == Sign::Zero) {
            return Err(PolygonDefect::Collinear(i));
        }
        if turns.iter().all(|s| *s == Sign::Negative) {
            // Clockwise if it winds once the other way; otherwise not convex.
            return if self.winding() == -1 {
                Err(PolygonDefect::Clockwise)
            } else {
                Err(PolygonDefect::NotConvex(0))
            };
        }
        if let Some(i) = turns.iter().position(|s| *s == Sign::Negative) {
            return Err(PolygonDefect::NotConvex(i));
        }
        if self.winding() != 1 {
            return Err(PolygonDefect::NotConvex(0));
        }
        Ok(())
    }

    /// Sign of the turn at vertex `i` (positive: left turn).
    fn turn(&self, i: usize) -> Sign {
        let n = self.len();
        let h = (i + n - 1) % n;
        let j = (i + 1) % n;
        let (ax, ay) = (&self.xs[i] - &self.xs[h], &self.ys[i] - &self.ys[h]);
        let (bx, by) = (&self.xs[j] - &self.xs[i], &self.ys[j] - &self.ys[i]);
        Sign::of(&(ax * by - ay * bx))
    }

    /// Number of full turns of the edge direction (counter-clockwise positive),
    /// assuming every turn has the same strict sign.
    fn winding(&self) -> i64 {
        let n = self.len();
        let dir = |i: usize| {
            let j = (i + 1) % n;
            (&self.xs[j] - &self.xs[i], &self.ys[j] - &self.ys[i])
        };
        // half 0: angle in [0, π); half 1: [π, 2π)
        let half = |d: &(Int, Int)| {
            if d.1 > Int::ZERO || (d.1.is_zero() && d.0 > Int::ZERO) {
                0
            } else {
                1
            }
        };
        let ccw = self.turn(0) == Sign::Positive;
        let mut wraps = 0i64;
        for i in 0..n {
            let a = dir(i);
            let b = dir((i + 1) % n);
            let (ha, hb) = (half(&a), half(&b));
            // Counter-clockwise: a wrap past angle 0 goes from half 1 to half 0.
            if ccw && ha == 1 && hb == 0 {
                wraps += 1;
            }
            if !ccw && ha == 0 && hb == 1 {
                wraps -= 1;
            }
        }
        wraps
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.xs.len()
    }

    /// Always false: a polygon has at least three vertices.
    pub fn is_empty(&self) -> bool {
        self.xs.is_empty()
    }

    /// Integer coordinates of vertex `i` (the point is `(x, y) · 2^exp`).
    pub fn int_vertex(&self, i: usize) -> (&Int, &Int) {
        (&self.xs[i], &self.ys[i])
    }

    /// The common binary exponent of the integer coordinates.
    pub fn exp(&self) -> i64 {
        self.exp
    }

    /// The exact vertex `i`.
    pub fn vertex(&self, i: usize) -> Point {
        Point {
            x: Rational::from_dyadic(self.xs[i].clone(), self.exp),
            y: Rational::from_dyadic(self.ys[i].clone(), self.exp),
        }
    }

    /// The vertices as given (exact doubles).
    pub fn f64_vertices(&self) -> &[[f64; 2]] {
        &self.f64s
    }

    /// Twice the signed area, exactly.
    pub fn twice_area(&self) -> Rational {
        let n = self.len();
        let mut s = Int::ZERO;
        for i in 0..n {
            let j = (i + 1) % n;
            s += &self.xs[i] * &self.ys[j] - &self.xs[j] * &self.ys[i];
        }
        Rational::from_dyadic(s, 2 * self.exp)
    }

    /// The area centroid, exactly.
    pub fn centroid(&self) -> Point {
        let n = self.len();
        let (mut cx, mut cy, mut a) = (Int::ZERO, Int::ZERO, Int::ZERO);
        for i in 0..n {
            let j = (i + 1) % n;
            let cr = &self.xs[i] * &self.ys[j] - &self.xs[j] * &self.ys[i];
            cx += (&self.xs[i] + &self.xs[j]) * &cr;
            cy += (&self.ys[i] + &self.ys[j]) * &cr;
            a += cr;
        }
        // centroid = (Σ (x_i + x_j) cr) / (3 Σ cr) in integer units, times 2^exp
        let den = a * Int::from(3);
        let scale = Rational::from_dyadic(Int::ONE, self.exp);
        Point {
            x: Rational::new(cx, den.clone()).mul(&scale),
            y: Rational::new(cy, den).mul(&scale),
        }
    }
}

/// Whether two convex polygons, given by their exact vertices in
/// counter-clockwise order, share a point (closed sets). Separating-axis
/// test over the edges of both, `O(n·m)`; for validation and audits.
pub fn convex_polygons_intersect(a: &[Point], b: &[Point]) -> bool {
    !(has_separating_edge(a, b) || has_separating_edge(b, a))
}

/// Whether some edge line of `a` has all of `b` strictly on its outer side.
fn has_separating_edge(a: &[Point], b: &[Point]) -> bool {
    let n = a.len();
    (0..n).any(|i| {
        let p = &a[i];
        let q = &a[(i + 1) % n];
        b.iter().all(|r| orient(p, q, r) == Sign::Negative)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let p = BodyPolygon::new(&sq).unwrap();
        assert_eq!(p.twice_area(), Rational::from_int(Int::from(2)));
        assert_eq!(
            p.centroid(),
            Point::from_f64([0.5, 0.5]).unwrap()
        );
        let mut cw = sq;
        cw.reverse();
        assert_eq!(BodyPolygon::new(&cw), Err(PolygonDefect::Clockwise));
        assert_eq!(
            BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]]),
            Err(PolygonDefect::Collinear(1))
        );
        assert_eq!(
            BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            Err(PolygonDefect::Repeated(1))
        );
        assert!(matches!(
            BodyPolygon::new(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [2.0, 2.0], [0.0, 2.0]]),
            Err(PolygonDefect::NotConvex(_))
        ));
        // pentagram: every turn is left but it winds twice
        let star: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
                [a.cos(), a.sin()]
            })
            .collect();
        assert_eq!(BodyPolygon::new(&star), Err(PolygonDefect::NotConvex(0)));
        assert_eq!(BodyPolygon::new(&sq[..2]), Err(PolygonDefect::TooFew));
        assert_eq!(
            BodyPolygon::new(&[[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]]),
            Err(PolygonDefect::NonFinite(1))
        );
        // tiny and huge coordinates together stay exact
        let mixed = BodyPolygon::new(&[[0.0, 0.0], [1e6, 1e-9], [0.5, 1e6]]).unwrap();
        assert_eq!(mixed.vertex(1).to_f64(), [1e6, 1e-9]);
    }

    #[test]
    fn intersection() {
        let sq = |x: f64, y: f64| -> Vec<Point> {
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
                .iter()
                .map(|p| Point::from_f64([p[0] + x, p[1] + y]).unwrap())
                .collect()
        };
        assert!(convex_polygons_intersect(&sq(0.0, 0.0), &sq(0.5, 0.5)));
        assert!(convex_polygons_intersect(&sq(0.0, 0.0), &sq(1.0, 0.0))); // touching edge
        assert!(convex_polygons_intersect(&sq(0.0, 0.0), &sq(1.0, 1.0))); // touching corner
        assert!(!convex_polygons_intersect(&sq(0.0, 0.0), &sq(1.0 + 1e-12, 0.0)));
    }
}
