//! Static exact geometry: points, convex body polygons and the predicates
//! every decision goes through.
//!
//! This is the only place (with [`crate::motion`], for moving points) where a
//! sign is computed from coordinates. Body-frame coordinates are doubles and
//! therefore dyadic rationals; a [`BodyPolygon`] stores them as integers over
//! one power of two so that predicates run on integers.

use crate::num::{Int, Interval, Rational, Sign};

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
    // an outward-rounded f64 enclosure first; the exact rationals only when
    // it contains zero
    let (px, py) = (p.x.interval(), p.y.interval());
    let d = (q.x.interval() - px) * (r.y.interval() - py)
        - (q.y.interval() - py) * (r.x.interval() - px);
    if let Some(s) = d.sign() {
        return s;
    }
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
    /// Enclosures of the integer coordinates (the filter's input, converted
    /// once rather than at every orientation test).
    ivs: Vec<[Interval; 2]>,
    /// The body-frame bounding box (see [`BodyPolygon::bounds`]).
    bbox: [f64; 4],
    /// The largest bit length of the integer coordinates (below 63: the
    /// Minkowski passes run on `i128`, without allocation).
    bits: u32,
    /// The integer coordinates as `i128` when `bits` is at most 100 (the
    /// input of those passes).
    small: Option<Vec<[i128; 2]>>,
    /// With `small`: the edge of least angle in `[0, 2π)`, and the edge of
    /// least angle reversed (where the Minkowski walk starts on this
    /// polygon as `B` and as `A`).
    first_edges: [usize; 2],
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
        if let Some(i) = vertices
            .iter()
            .position(|v| !(v[0].is_finite() && v[1].is_finite()))
        {
            return Err(PolygonDefect::NonFinite(i));
        }
        // each coordinate as `m · 2^e` (`|m| < 2^53`), and the least
        // exponent of a nonzero one: the common unit
        let parts: Vec<[(i64, i64); 2]> = vertices
            .iter()
            .map(|v| v.map(crate::num::split_f64))
            .collect();
        let exp = parts
            .iter()
            .flatten()
            .filter(|(m, _)| *m != 0)
            .map(|(_, e)| *e)
            .min()
            .unwrap_or(0);
        // (in `i128` where every coordinate fits in 100 bits on that unit, as
        // almost always: no big integer is made but the stored ones)
        let widest = parts
            .iter()
            .flatten()
            .filter(|(m, _)| *m != 0)
            .map(|(_, e)| e - exp)
            .max()
            .unwrap_or(0);
        // (`narrow`: the integers as `i128`, kept for `small` below)
        let (xs, ys, ivs, narrow): (Vec<Int>, Vec<Int>, Vec<[Interval; 2]>, _) = if widest <= 47 {
            let int = |(m, e): (i64, i64)| {
                if m == 0 {
                    0
                } else {
                    i128::from(m) << (e - exp)
                }
            };
            // (each integer `m · 2^(e − exp)` is a double exactly: `|m| <
            // 2^53` and the shift is at most 47, so its enclosure is a
            // point, made without a conversion from `i128`)
            let point = |(m, e): (i64, i64)| {
                let iv = if m == 0 {
                    Interval::point(0.0)
                } else {
                    Interval::point(m as f64 * (1u64 << (e - exp)) as f64)
                };
                debug_assert_eq!(iv, Interval::of_i128(int((m, e))), "the point of {m}·2^{e}");
                iv
            };
            let narrow: Vec<[i128; 2]> = parts.iter().map(|p| p.map(int)).collect();
            (
                narrow.iter().map(|p| Int::from(p[0])).collect(),
                narrow.iter().map(|p| Int::from(p[1])).collect(),
                parts.iter().map(|p| p.map(point)).collect(),
                Some(narrow),
            )
        } else {
            let ivs = parts
                .iter()
                .map(|p| p.map(|(m, e)| Int::from(m) << ((e - exp).max(0) as usize)))
                .map(|[x, y]| {
                    let iv = [Interval::of_int(&x), Interval::of_int(&y)];
                    ((x, y), iv)
                });
            let ((xs, ys), ivs) = ivs.unzip();
            (xs, ys, ivs, None)
        };
        #[cfg(debug_assertions)]
        {
            // the same integers as from the big-integer decomposition
            let wide: Vec<(Int, i64)> = vertices
                .iter()
                .flatten()
                .map(|&c| crate::num::decompose_f64(c).expect("finite"))
                .collect();
            for (k, (m, e)) in wide.into_iter().enumerate() {
                let v = if m.is_zero() {
                    m
                } else {
                    m << ((e - exp) as usize)
                };
                let got = if k % 2 == 0 { &xs[k / 2] } else { &ys[k / 2] };
                debug_assert_eq!(&v, got, "coordinate {k} on the common unit");
            }
        }
        let mut bbox = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for v in vertices {
            bbox[0] = bbox[0].min(v[0]);
            bbox[1] = bbox[1].max(v[0]);
            bbox[2] = bbox[2].min(v[1]);
            bbox[3] = bbox[3].max(v[1]);
        }
        let bits = xs
            .iter()
            .chain(&ys)
            .map(|c| dashu_base::BitTest::bit_len(c) as u32)
            .max()
            .unwrap_or(0);
        let small = (bits <= 100).then(|| {
            narrow.unwrap_or_else(|| {
                xs.iter()
                    .zip(&ys)
                    .map(|(x, y)| [x, y].map(|c| i128::try_from(c).expect("below 2^100")))
                    .collect()
            })
        });
        let first_edges = small.as_deref().map_or([0, 0], first_edges_i128);
        let poly = BodyPolygon {
            xs,
            ys,
            exp,
            f64s: vertices.to_vec(),
            ivs,
            bbox,
            bits,
            small,
            first_edges,
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
    /// The integer coordinates as `i128` when their bit length is at most
    /// 62: differences then fit in 63 bits and a cross product of two in
    /// 127, so the exact tests below need no big integers.
    fn narrow(&self) -> Option<&[[i128; 2]]> {
        self.small.as_deref().filter(|_| self.bits <= 62)
    }

    fn turn(&self, i: usize) -> Sign {
        let n = self.len();
        let h = (i + n - 1) % n;
        let j = (i + 1) % n;
        if let Some(v) = self.narrow() {
            let (ax, ay) = (v[i][0] - v[h][0], v[i][1] - v[h][1]);
            let (bx, by) = (v[j][0] - v[i][0], v[j][1] - v[i][1]);
            let s = Sign::of_i128(ax * by - ay * bx);
            debug_assert_eq!(s, self.turn_big(i), "the i128 turn of vertex {i}");
            return s;
        }
        // (coordinates of up to 100 bits: differences in `i128`, their
        // products compared in 256 bits)
        if let Some(v) = self.small.as_deref() {
            let (ax, ay) = (v[i][0] - v[h][0], v[i][1] - v[h][1]);
            let (bx, by) = (v[j][0] - v[i][0], v[j][1] - v[i][1]);
            let s = cross_sign_wide(ax, ay, bx, by);
            debug_assert_eq!(s, self.turn_big(i), "the 256-bit turn of vertex {i}");
            return s;
        }
        self.turn_big(i)
    }

    /// [`BodyPolygon::turn`] on the big integers.
    fn turn_big(&self, i: usize) -> Sign {
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
        // half 0: angle in [0, π); half 1: [π, 2π), of the direction from
        // vertex `i` to the next (whose coordinates' signs are those of the
        // differences)
        let half_of = |dx: Sign, dy: Sign| {
            if dy == Sign::Positive || (dy == Sign::Zero && dx == Sign::Positive) {
                0
            } else {
                1
            }
        };
        let dir_half = |i: usize| {
            let j = (i + 1) % n;
            let big = || {
                half_of(
                    Sign::of(&(&self.xs[j] - &self.xs[i])),
                    Sign::of(&(&self.ys[j] - &self.ys[i])),
                )
            };
            // (the signs of differences only: `i128` holds them for
            // coordinates of up to 100 bits)
            match self.small.as_deref() {
                Some(v) => {
                    let h = half_of(
                        Sign::of_i128(v[j][0] - v[i][0]),
                        Sign::of_i128(v[j][1] - v[i][1]),
                    );
                    debug_assert_eq!(h, big(), "the i128 direction of edge {i}");
                    h
                }
                None => big(),
            }
        };
        let ccw = self.turn(0) == Sign::Positive;
        let mut wraps = 0i64;
        for i in 0..n {
            let (ha, hb) = (dir_half(i), dir_half((i + 1) % n));
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

    /// The integer coordinates of every vertex as `i128`, where they have
    /// at most 100 bits (as [`BodyPolygon::int_vertex`]).
    pub(crate) fn small_vertices(&self) -> Option<&[[i128; 2]]> {
        self.small.as_deref()
    }

    /// Enclosures of the integer coordinates of vertex `i` (as
    /// [`Interval::of_int`] of [`BodyPolygon::int_vertex`]).
    pub fn int_vertex_enclosure(&self, i: usize) -> [Interval; 2] {
        self.ivs[i]
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

    /// The body-frame bounding box `[min x, max x, min y, max y]` (exact:
    /// the coordinates are the given doubles).
    pub fn bounds(&self) -> [f64; 4] {
        self.bbox
    }

    /// A body-frame disk `(centre, radius)` that holds the polygon: the
    /// centre of the bounding box, and a radius rounded up from the
    /// farthest vertex (an infinite radius where the distances overflow).
    /// Computed at each call, O(n) in doubles (not kept in the polygon: a
    /// field per polygon moves the benchmark's peak memory by megabytes).
    pub fn bounding_disk(&self) -> ([f64; 2], f64) {
        bounding_disk(&self.f64s, &self.bbox)
    }

    /// Twice the signed area, exactly.
    pub fn twice_area(&self) -> Rational {
        let n = self.len();
        if let Some(v) = self.narrow() {
            // (each term below 2^127 in size; a sum of `n` terms checked)
            let sum = (0..n).try_fold(0i128, |acc, i| {
                let j = (i + 1) % n;
                acc.checked_add(v[i][0] * v[j][1] - v[j][0] * v[i][1])
            });
            if let Some(sum) = sum {
                let a = Rational::from_dyadic(Int::from(sum), 2 * self.exp);
                debug_assert_eq!(a, self.twice_area_big(), "the i128 area");
                return a;
            }
        }
        self.twice_area_big()
    }

    /// [`BodyPolygon::twice_area`] on the big integers.
    fn twice_area_big(&self) -> Rational {
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

/// Whether the segment `pq` meets the interior of the convex polygon `poly`
/// (exact vertices, counter-clockwise). Touching the boundary, or running
/// along an edge, does not count. Separating-axis test over the polygon's
/// edges and the segment's line, `O(n)`; for audits.
pub fn segment_meets_convex_interior(p: &Point, q: &Point, poly: &[Point]) -> bool {
    let n = poly.len();
    let edge_separates = (0..n).any(|i| {
        let (a, b) = (&poly[i], &poly[(i + 1) % n]);
        orient(a, b, p) != Sign::Positive && orient(a, b, q) != Sign::Positive
    });
    if edge_separates {
        return false;
    }
    let sides: Vec<Sign> = poly.iter().map(|r| orient(p, q, r)).collect();
    let line_separates =
        sides.iter().all(|s| *s != Sign::Negative) || sides.iter().all(|s| *s != Sign::Positive);
    !line_separates
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

/// The sign of `orient(u, v, w)` from enclosures of the three positions, if
/// the enclosures decide it and it is not zero (the f64 filter of the
/// orientation tests; callers that enclose each point once use it for
/// several turns).
pub fn orient_enclosed(
    [ux, uy]: [Interval; 2],
    [vx, vy]: [Interval; 2],
    [wx, wy]: [Interval; 2],
) -> Option<Sign> {
    let d = (vx - ux) * (wy - uy) - (vy - uy) * (wx - ux);
    d.sign().filter(|&s| s != Sign::Zero)
}

/// A point known to lie within `r` of `(x, y)` in each coordinate: the
/// midpoint–radius form of a moving position at an instant
/// ([`MidRad::at`]), for [`orient_mid_rad`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MidRad {
    /// Midpoint, x.
    pub x: f64,
    /// Midpoint, y.
    pub y: f64,
    /// Radius (the same bound for both coordinates).
    pub r: f64,
}

/// Whether two closed boxes `[x_lo, x_hi, y_lo, y_hi]` (of
/// [`MidRad::bounding_box`]) are certainly apart: one lies beyond a side of
/// the other.
#[inline]
pub fn boxes_apart(a: [f64; 4], b: [f64; 4]) -> bool {
    a[1] < b[0] || b[1] < a[0] || a[3] < b[2] || b[3] < a[2]
}

/// The unit roundoff of f64, `2^-53`.
pub(crate) const EPS: f64 = f64::EPSILON / 2.0;

/// An absolute term that covers the rounding of products that underflow
/// (each at most `2^-1074`; a few dozen operations).
pub(crate) const TINY: f64 = 1e-300;

impl MidRad {
    /// A box `[x_lo, x_hi, y_lo, y_hi]` that certainly holds every point
    /// of `pts` (each bound rounded outward by one step); `None` if there is
    /// none, or one is missing or not finite.
    pub fn bounding_box<'a>(pts: impl IntoIterator<Item = &'a Option<MidRad>>) -> Option<[f64; 4]> {
        let mut b: Option<[f64; 4]> = None;
        for m in pts {
            let p = m.as_ref()?.bounds();
            // (a NaN would drop out of `min` and `max`)
            if !p.iter().all(|v| v.is_finite()) {
                return None;
            }
            b = Some(match b {
                None => p,
                Some(b) => [
                    b[0].min(p[0]),
                    b[1].max(p[1]),
                    b[2].min(p[2]),
                    b[3].max(p[3]),
                ],
            });
        }
        b
    }

    /// Whether the point is certainly outside the closed box `b` (of
    /// [`MidRad::bounding_box`]): beyond one of its sides.
    #[inline]
    pub fn outside_box(self, b: [f64; 4]) -> bool {
        let [x_lo, x_hi, y_lo, y_hi] = self.bounds();
        x_hi < b[0] || x_lo > b[1] || y_hi < b[2] || y_lo > b[3]
    }

    /// `[x_lo, x_hi, y_lo, y_hi]` with the point certainly in `[x_lo,
    /// x_hi] × [y_lo, y_hi]`: the midpoint minus (plus) the radius, each
    /// rounded to nearest and then one step outward, which covers the
    /// rounding (half a step). A bound may be infinite or NaN.
    #[inline]
    pub fn bounds(self) -> [f64; 4] {
        [
            (self.x - self.r).next_down(),
            (self.x + self.r).next_up(),
            (self.y - self.r).next_down(),
            (self.y + self.r).next_up(),
        ]
    }

    /// Whether the two points are certainly apart: their midpoints differ
    /// in one coordinate by more than the two radii (with a margin for the
    /// rounding of the difference, the sum and the product).
    #[inline]
    pub fn apart(self, other: MidRad) -> bool {
        let reach = (self.r + other.r) * (1.0 + 8.0 * f64::EPSILON) + f64::MIN_POSITIVE;
        (self.x - other.x).abs() > reach || (self.y - other.y).abs() > reach
    }

    /// The position `(x0 + x1·t, y0 + y1·t)` for some `x0, x1, y0, y1` in
    /// the enclosures `lin` and a time in `t`; `None` if a value is not
    /// finite. Every rounding of the computation is bounded into the radius:
    /// the midpoints' own, the products' and sums', and the radius's (a
    /// factor `1 + 16ε` on a sum of non-negative terms, each computed with
    /// at most four roundings, and `TINY` for underflow).
    #[inline]
    pub fn at(lin: [Interval; 4], t: Interval) -> Option<MidRad> {
        let tm = 0.5 * (t.lo + t.hi);
        let ht = 0.5 * (t.hi - t.lo);
        let tmax = t.lo.abs().max(t.hi.abs());
        let coord = |c0: Interval, c1: Interval| {
            let (m0, r0) = (0.5 * (c0.lo + c0.hi), 0.5 * (c0.hi - c0.lo));
            let (m1, r1) = (0.5 * (c1.lo + c1.hi), 0.5 * (c1.hi - c1.lo));
            let p = m0 + m1 * tm;
            let r = r0 + r1 * tmax + m1.abs() * ht + 3.0 * EPS * (m0.abs() + (m1 * tm).abs());
            (p, r)
        };
        let (x, rx) = coord(lin[0], lin[1]);
        let (y, ry) = coord(lin[2], lin[3]);
        let r = rx.max(ry) * (1.0 + 16.0 * EPS) + TINY;
        (x.is_finite() && y.is_finite() && r.is_finite()).then_some(MidRad { x, y, r })
    }
}

/// A real number known to lie within `r` of `m`: the midpoint–radius
/// arithmetic of the certificate filters. Every operation bounds its
/// rounding into the radius: a sum's or a product's own (`ε` of the
/// midpoint), the radius's (a factor `1 + 4ε` on its non-negative terms)
/// and a product's underflow (`TINY`). The point `(0, 0)` is an exact zero
/// and stays one through products.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mr {
    /// Midpoint.
    pub m: f64,
    /// Radius.
    pub r: f64,
}

impl Mr {
    /// The exact zero.
    pub const ZERO: Mr = Mr { m: 0.0, r: 0.0 };

    /// The exact double `x`.
    #[inline]
    pub fn point(x: f64) -> Mr {
        Mr { m: x, r: 0.0 }
    }

    /// The same set as the interval `c` or a larger one (`None` when `c`
    /// is not finite).
    #[inline]
    pub fn of(c: Interval) -> Option<Mr> {
        if c.lo == c.hi {
            return c.lo.is_finite().then_some(Mr::point(c.lo));
        }
        let m = 0.5 * c.lo + 0.5 * c.hi;
        let r = (c.hi - m).max(m - c.lo) * (1.0 + 4.0 * EPS);
        (m.is_finite() && r.is_finite()).then_some(Mr { m, r })
    }

    /// Whether this is the exact zero.
    #[inline]
    pub fn is_zero(self) -> bool {
        self.m == 0.0 && self.r == 0.0
    }

    /// An interval that holds every number within `r` of `m` (the point
    /// `[0, 0]` for the exact zero; not finite where a value overflowed).
    #[inline]
    pub fn interval(self) -> Interval {
        if self.r == 0.0 {
            return Interval::point(self.m);
        }
        let (lo, hi) = (self.m - self.r, self.m + self.r);
        Interval {
            lo: if lo.is_nan() {
                f64::NEG_INFINITY
            } else {
                lo.next_down()
            },
            hi: if hi.is_nan() {
                f64::INFINITY
            } else {
                hi.next_up()
            },
        }
    }
}

impl std::ops::Add for Mr {
    type Output = Mr;

    /// The sum.
    #[inline]
    fn add(self, o: Mr) -> Mr {
        let m = self.m + o.m;
        Mr {
            m,
            r: (self.r + o.r + EPS * m.abs()) * (1.0 + 4.0 * EPS),
        }
    }
}

impl std::ops::Sub for Mr {
    type Output = Mr;

    /// The difference.
    #[inline]
    fn sub(self, o: Mr) -> Mr {
        // (negation is exact: the same rounding as the sum)
        self + (-o)
    }
}

impl std::ops::Mul for Mr {
    type Output = Mr;

    /// The product (exactly zero when a factor is).
    #[inline]
    fn mul(self, o: Mr) -> Mr {
        if self.is_zero() || o.is_zero() {
            return Mr::ZERO;
        }
        let m = self.m * o.m;
        let r = self.m.abs() * o.r + o.m.abs() * self.r + self.r * o.r + EPS * m.abs();
        Mr {
            m,
            r: r * (1.0 + 4.0 * EPS) + TINY,
        }
    }
}

impl std::ops::Neg for Mr {
    type Output = Mr;

    /// The negation (exact).
    #[inline]
    fn neg(self) -> Mr {
        Mr {
            m: -self.m,
            r: self.r,
        }
    }
}

/// An instant's enclosure in the form [`MidRad::at`] and
/// [`crate::motion::Frame::mid_rad_of_vertex`] read it: midpoint `tm`,
/// half-width `ht` (rounded up) and largest magnitude `tmax`.
#[derive(Clone, Copy, Debug)]
pub struct TimeMidRad {
    /// Midpoint.
    pub tm: f64,
    /// Half-width, rounded up.
    pub ht: f64,
    /// `max(|lo|, |hi|)`.
    pub tmax: f64,
}

impl TimeMidRad {
    /// The form of enclosure `t`.
    #[inline]
    pub fn of(t: Interval) -> TimeMidRad {
        let tm = 0.5 * t.lo + 0.5 * t.hi;
        // (a difference of doubles is within ε of its rounding, relatively;
        // the product adds another ε)
        TimeMidRad {
            tm,
            ht: (t.hi - tm).max(tm - t.lo) * (1.0 + 4.0 * EPS),
            tmax: t.lo.abs().max(t.hi.abs()),
        }
    }
}

/// The sign of a filter's f64 value `v` where its error bound `bound`
/// decides it: `v` beyond `±bound`, both finite; `None` otherwise.
#[inline]
fn sign_beyond(v: f64, bound: f64) -> Option<Sign> {
    if !(bound.is_finite() && v.is_finite()) {
        None
    } else if v > bound {
        Some(Sign::Positive)
    } else if v < -bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// `(m, r)` of a set of points for [`orient_box_bound`] and
/// [`in_circle_box_bound`]: `r` the largest radius, `m` the largest absolute
/// midpoint coordinate plus `r`, rounded up, so that every point within the
/// radii has coordinates at most `m` in absolute value; `None` where a
/// midpoint or radius is not finite.
fn box_extent(mids: &[MidRad]) -> Option<(f64, f64)> {
    let (mut m, mut r) = (0.0f64, 0.0f64);
    for p in mids {
        if !(p.x.is_finite() && p.y.is_finite() && p.r.is_finite()) {
            return None;
        }
        m = m.max(p.x.abs()).max(p.y.abs());
        r = r.max(p.r);
    }
    Some(((m + r) * (1.0 + 4.0 * EPS), r))
}

/// A bound for [`orient_in_box`] over a set of points, or infinite where
/// none is usable (a non-finite midpoint or radius: then nothing is
/// decided); `m` and `r` as [`box_extent`] gives them.
///
/// With `u = 2r + 2εm` (a difference of two midpoints computed in f64 is
/// within `u` of the difference of any two points within their radii) and
/// every difference at most `2m(1 + ε)`, each of the two products of the
/// orientation is within `(2m(1 + ε) + 2m)·u` of the exact one, rounding a
/// product adds at most `ε(2m(1 + ε))²` and the subtraction at most
/// `ε·2(2m(1 + ε))²(1 + ε)`: together at most `8.00001·m·u + 16.0001·ε·m²`.
/// The bound is that, times `1 + 2^-20` for its own rounding, plus `TINY`
/// for underflow; infinite where a product could overflow.
pub(crate) fn orient_box_bound(mids: &[MidRad]) -> f64 {
    let Some((m, r)) = box_extent(mids) else {
        return f64::INFINITY;
    };
    let u = (2.0 * r + 2.0 * EPS * m) * (1.0 + 4.0 * EPS);
    let bound = (8.00001 * m * u + 16.0001 * EPS * m * m) * (1.0 + 1.0 / 1048576.0) + TINY;
    // (and no product of two differences overflows)
    if (16.0 * m * m).is_finite() {
        bound
    } else {
        f64::INFINITY
    }
}

/// The sign of `orient(u, v, w)` for any three points within the radii of
/// `u`, `v`, `w`, decided by one comparison with `bound`, an
/// [`orient_box_bound`] of a set that holds the three; `None` (undecided)
/// where the f64 value is within the bound, or for a zero.
#[inline]
pub(crate) fn orient_in_box(u: MidRad, v: MidRad, w: MidRad, bound: f64) -> Option<Sign> {
    let det = (v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x);
    if det > bound {
        Some(Sign::Positive)
    } else if det < -bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// The sign of `orient(u, v, w)` for any three points within the radii of
/// `u`, `v`, `w`, if the f64 evaluation at the midpoints with its error
/// bound decides it and it is not zero (the cheap first filter of the
/// orientation tests: a dozen products and no branch per operation).
///
/// With `d1 = v − u`, `d2 = w − u` computed in f64 and `u1`, `u2` bounds on
/// their distance from every pair of points within the radii (the radii
/// and the subtraction's rounding), the exact determinant is within
/// `|d1x|·u2y + u1x·|d2y| + u1x·u2y + |d1y|·u2x + u1y·|d2x| + u1y·u2x` of
/// `d1x·d2y − d1y·d2x`, whose f64 evaluation adds at most
/// `3ε(|d1x·d2y| + |d1y·d2x|)`; the bound itself is computed with a
/// factor `1 + 32ε` and `TINY` for underflow.
#[inline]
pub fn orient_mid_rad(u: MidRad, v: MidRad, w: MidRad) -> Option<Sign> {
    let ([d1x, d1y], [u1x, u1y], [d2x, d2y], [u2x, u2y]) = mid_rad_differences(u, v, w);
    two_products_sign([(d1x, u1x), (d2y, u2y)], [(d1y, u1y), (d2x, u2x)], true)
}

/// The sign of the dot product `(v − u)·(w − u)` for any three points
/// within the radii of `u`, `v`, `w`, if the f64 evaluation at the
/// midpoints with its error bound decides it and it is not zero: the bound
/// of [`orient_mid_rad`] with the products paired as in the dot product,
/// `|d1x|·u2x + u1x·|d2x| + u1x·u2x + |d1y|·u2y + u1y·|d2y| + u1y·u2y`
/// for the points and `3ε(|d1x·d2x| + |d1y·d2y|)` for the evaluation.
#[inline]
pub fn dot_mid_rad(u: MidRad, v: MidRad, w: MidRad) -> Option<Sign> {
    let ([d1x, d1y], [u1x, u1y], [d2x, d2y], [u2x, u2y]) = mid_rad_differences(u, v, w);
    two_products_sign([(d1x, u1x), (d2x, u2x)], [(d1y, u1y), (d2y, u2y)], false)
}

/// `d1 = v − u` and `d2 = w − u` computed in f64 at the midpoints, each
/// with a bound per coordinate on its distance from every pair of points
/// within the radii (the radii and the subtraction's rounding): `(d1, u1,
/// d2, u2)`.
#[inline]
pub(crate) fn mid_rad_differences(
    u: MidRad,
    v: MidRad,
    w: MidRad,
) -> ([f64; 2], [f64; 2], [f64; 2], [f64; 2]) {
    let (d1x, d1y) = (v.x - u.x, v.y - u.y);
    let (d2x, d2y) = (w.x - u.x, w.y - u.y);
    let (r1, r2) = (u.r + v.r, u.r + w.r);
    (
        [d1x, d1y],
        [r1 + EPS * d1x.abs(), r1 + EPS * d1y.abs()],
        [d2x, d2y],
        [r2 + EPS * d2x.abs(), r2 + EPS * d2y.abs()],
    )
}

/// The sign of `a·b − c·d` (`minus`) or `a·b + c·d`, each factor given as
/// `(value, bound on its error)`, where the f64 evaluation with its error
/// bound ([`two_products`]) decides it, the bound computed with a factor
/// `1 + 32ε` and `TINY` for underflow.
#[inline]
fn two_products_sign(ab: [(f64, f64); 2], cd: [(f64, f64); 2], minus: bool) -> Option<Sign> {
    let (value, err) = two_products(ab, cd, minus);
    let bound = err * (1.0 + 32.0 * EPS) + TINY;
    sign_beyond(value, bound)
}

/// `a·b − c·d` (`minus`) or `a·b + c·d` in f64, each factor given as
/// `(value, bound on its error)`, and a bound on the error of that value:
/// `|a|·eb + ea·|b| + ea·eb` and the same for `c·d` for the factors,
/// `3ε(|a·b| + |c·d|)` for the evaluation (the bound's own rounding, a
/// few operations on positive terms, is the caller's to cover).
#[inline]
pub(crate) fn two_products(
    [(a, ea), (b, eb)]: [(f64, f64); 2],
    [(c, ec), (d, ed)]: [(f64, f64); 2],
    minus: bool,
) -> (f64, f64) {
    let (p, q) = (a * b, c * d);
    let value = if minus { p - q } else { p + q };
    let err = a.abs() * eb
        + ea * b.abs()
        + ea * eb
        + c.abs() * ed
        + ec * d.abs()
        + ec * ed
        + 3.0 * EPS * (p.abs() + q.abs());
    (value, err)
}

impl MidRad {
    /// The order of the x coordinates of any two points within the radii
    /// of `self` and `other`, if the midpoints decide it (the margin of
    /// [`MidRad::apart`]).
    #[inline]
    pub fn cmp_x(self, other: MidRad) -> Option<std::cmp::Ordering> {
        decided_order(self.x - other.x, self.r + other.r)
    }

    /// As [`MidRad::cmp_x`], for the y coordinates.
    #[inline]
    pub fn cmp_y(self, other: MidRad) -> Option<std::cmp::Ordering> {
        decided_order(self.y - other.y, self.r + other.r)
    }
}

fn decided_order(diff: f64, radii: f64) -> Option<std::cmp::Ordering> {
    let reach = radii * (1.0 + 8.0 * f64::EPSILON) + f64::MIN_POSITIVE;
    if !(diff.is_finite() && reach.is_finite()) || diff.abs() <= reach {
        return None;
    }
    Some(if diff > 0.0 {
        std::cmp::Ordering::Greater
    } else {
        std::cmp::Ordering::Less
    })
}

/// A value within `e` of the computed `v` (a running error bound: every
/// operation adds the propagated errors of its operands and `ε·|v|` for
/// its own rounding).
#[derive(Clone, Copy)]
struct Bounded {
    v: f64,
    e: f64,
}

impl Bounded {
    fn diff(a: f64, b: f64, radii: f64) -> Bounded {
        let v = a - b;
        Bounded {
            v,
            e: radii + EPS * v.abs(),
        }
    }
    fn mul(self, o: Bounded) -> Bounded {
        let v = self.v * o.v;
        Bounded {
            v,
            e: self.v.abs() * o.e + self.e * o.v.abs() + self.e * o.e + EPS * v.abs(),
        }
    }
    fn add(self, o: Bounded) -> Bounded {
        let v = self.v + o.v;
        Bounded {
            v,
            e: self.e + o.e + EPS * v.abs(),
        }
    }
    fn sub(self, o: Bounded) -> Bounded {
        let v = self.v - o.v;
        Bounded {
            v,
            e: self.e + o.e + EPS * v.abs(),
        }
    }
}

/// A bound for [`in_circle_in_box`] over a set of points: the bound of
/// [`in_circle_static`] with its permanent, its largest difference and its
/// radii replaced by what they can be at most for any four points of the
/// set, which only makes it larger (with `m` and `r` of [`box_extent`]:
/// every difference computed in f64 at most
/// `D = 2m(1 + ε)`, the permanent at most `12·D⁴`, `δ` at most `2r + 2εD`);
/// times `1 + 2^-20` for its own rounding. Infinite where none is usable (a
/// non-finite midpoint or radius) or a term could overflow.
pub(crate) fn in_circle_box_bound(mids: &[MidRad]) -> f64 {
    let Some((m, r)) = box_extent(mids) else {
        return f64::INFINITY;
    };
    let big = 2.0 * m * (1.0 + 4.0 * EPS);
    let perm = 12.0 * big * big * big * big * (1.0 + 16.0 * EPS);
    let delta = (2.0 * r + 2.0 * EPS * big) * (1.0 + 4.0 * EPS);
    let mm = (big + delta) * (1.0 + 4.0 * EPS);
    let bound = (16.0 * EPS * perm + 48.0 * mm * mm * mm * delta)
        * (1.0 + 64.0 * EPS)
        * (1.0 + 1.0 / 1048576.0)
        + TINY;
    if (4.0 * perm).is_finite() && bound.is_finite() {
        bound
    } else {
        f64::INFINITY
    }
}

/// [`in_circle_static`]'s determinant decided by one comparison with
/// `bound`, an [`in_circle_box_bound`] of a set that holds the four points;
/// `None` where it does not decide.
#[inline]
pub(crate) fn in_circle_in_box(
    a: MidRad,
    b: MidRad,
    c: MidRad,
    d: MidRad,
    bound: f64,
) -> Option<Sign> {
    let (ax, ay) = (a.x - d.x, a.y - d.y);
    let (bx, by) = (b.x - d.x, b.y - d.y);
    let (cx, cy) = (c.x - d.x, c.y - d.y);
    let la = ax * ax + ay * ay;
    let lb = bx * bx + by * by;
    let lc = cx * cx + cy * cy;
    let det = la * (bx * cy - by * cx) + lb * (cx * ay - cy * ax) + lc * (ax * by - ay * bx);
    if det > bound {
        Some(Sign::Positive)
    } else if det < -bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// [`in_circle_mid_rad`] with one static error bound instead of a running
/// one: the determinant of the midpoints' differences from `d` in f64,
/// decided where it exceeds the rounding of its evaluation (`16ε` of the
/// permanent, the differences taken as its exact inputs) plus what moving
/// the six differences within their radii can change (each partial
/// derivative is at most `8M³` where every difference is at most `M`,
/// so `48·M³·δ` for a change of at most `δ` in each). Cheaper than the
/// running bound and looser where the four points are at very different
/// distances from `d`; `None` where it does not decide.
#[inline]
pub fn in_circle_static(a: MidRad, b: MidRad, c: MidRad, d: MidRad) -> Option<Sign> {
    let (ax, ay) = (a.x - d.x, a.y - d.y);
    let (bx, by) = (b.x - d.x, b.y - d.y);
    let (cx, cy) = (c.x - d.x, c.y - d.y);
    let la = ax * ax + ay * ay;
    let lb = bx * bx + by * by;
    let lc = cx * cx + cy * cy;
    let (bc1, bc2) = (bx * cy, by * cx);
    let (ca1, ca2) = (cx * ay, cy * ax);
    let (ab1, ab2) = (ax * by, ay * bx);
    let det = la * (bc1 - bc2) + lb * (ca1 - ca2) + lc * (ab1 - ab2);
    let perm =
        la * (bc1.abs() + bc2.abs()) + lb * (ca1.abs() + ca2.abs()) + lc * (ab1.abs() + ab2.abs());
    // the largest difference and the largest change of one (the radii of
    // both ends and the rounding of the subtraction)
    let big = ax
        .abs()
        .max(ay.abs())
        .max(bx.abs().max(by.abs()))
        .max(cx.abs().max(cy.abs()));
    let delta = a.r.max(b.r).max(c.r) + d.r + 2.0 * EPS * big;
    let m = big + delta;
    let bound = (16.0 * EPS * perm + 48.0 * m * m * m * delta) * (1.0 + 64.0 * EPS) + TINY;
    sign_beyond(det, bound)
}

/// The sign of the in-circle determinant of `(a, b, c, d)` (positive when
/// `d` is inside the circle through the counter-clockwise `a, b, c`) for
/// any four points within the radii, if the f64 evaluation with its
/// running error bound decides it and it is not zero. The bound is taken
/// with a factor `1 + 64ε` (the rounding of the bound's own computation,
/// a few dozen operations deep) and `TINY` for underflow.
pub fn in_circle_mid_rad(a: MidRad, b: MidRad, c: MidRad, d: MidRad) -> Option<Sign> {
    let rel = |p: MidRad| {
        let x = Bounded::diff(p.x, d.x, p.r + d.r);
        let y = Bounded::diff(p.y, d.y, p.r + d.r);
        (x, y, x.mul(x).add(y.mul(y)))
    };
    let (ax, ay, al) = rel(a);
    let (bx, by, bl) = rel(b);
    let (cx, cy, cl) = rel(c);
    let det = al
        .mul(bx.mul(cy).sub(by.mul(cx)))
        .add(bl.mul(cx.mul(ay).sub(cy.mul(ax))))
        .add(cl.mul(ax.mul(by).sub(ay.mul(bx))));
    let bound = det.e * (1.0 + 64.0 * EPS) + TINY;
    sign_beyond(det.v, bound)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 256-bit cross product's sign is the big integers' one, for
    /// components of every length up to 2^125, equal products and zeros
    /// among them.
    #[test]
    fn a_wide_cross_product_has_the_big_integers_sign() {
        let mut rng = crate::rng::Rng::new(53);
        let pick = |rng: &mut crate::rng::Rng| -> i128 {
            let bits = rng.below(126) as u32;
            let m = ((u128::from(rng.next_u64()) << 64) | u128::from(rng.next_u64()))
                >> (128 - bits.max(1));
            let v = m as i128;
            match rng.below(10) {
                0 => 0,
                1 => (1i128 << 125) - 1,
                2 => -((1i128 << 125) - 1),
                _ if rng.below(2) == 0 => -v,
                _ => v,
            }
        };
        for round in 0..20_000 {
            let [ax, ay, bx, by] = [0; 4].map(|_| pick(&mut rng));
            // (every third case has equal products)
            let (bx, by) = if round % 3 == 0 { (ax, ay) } else { (bx, by) };
            let big = Int::from(ax) * Int::from(by) - Int::from(ay) * Int::from(bx);
            assert_eq!(
                cross_sign_wide(ax, ay, bx, by),
                Sign::of(&big),
                "{ax} {ay} {bx} {by}"
            );
        }
    }

    /// A bounding box holds every point within the radii exactly (each
    /// corner of each point's square, compared as exact rationals), at
    /// scales from 1e-300 to 1e300; a point exactly on its side is not
    /// outside it; a missing or non-finite point gives no box.
    #[test]
    fn bounding_box_holds_its_points_exactly() {
        let mut rng = crate::rng::Rng::new(29);
        let exact = |v: f64| Point::from_f64([v, 0.0]).expect("finite").x;
        for round in 0..2000 {
            let scale = 10f64.powi((round % 61) * 10 - 300);
            let pts: Vec<Option<MidRad>> = (0..1 + round as usize % 5)
                .map(|_| {
                    let c = |rng: &mut crate::rng::Rng| (rng.next_f64() * 2.0 - 1.0) * scale;
                    let r = if rng.below(3) == 0 {
                        0.0
                    } else {
                        rng.next_f64() * scale * 1e-9
                    };
                    Some(MidRad {
                        x: c(&mut rng),
                        y: c(&mut rng),
                        r,
                    })
                })
                .collect();
            let b = MidRad::bounding_box(&pts).expect("finite points have a box");
            for m in pts.iter().flatten() {
                assert!(!m.outside_box(b));
                // the extreme points of the square, exactly
                for (c, lo, hi) in [(m.x, b[0], b[1]), (m.y, b[2], b[3])] {
                    let (r, c) = (exact(m.r), exact(c));
                    assert!(exact(lo) <= c.sub(&r), "{lo} above {c:?} - {r:?}");
                    assert!(c.add(&r) <= exact(hi), "{hi} below {c:?} + {r:?}");
                }
            }
        }
        let p = |x: f64| Some(MidRad { x, y: 0.0, r: 0.0 });
        let b = MidRad::bounding_box(&[p(0.0), p(1.0)]).expect("a box");
        assert!(!p(1.0).unwrap().outside_box(b));
        assert!(p(2.0).unwrap().outside_box(b));
        assert!(!p(f64::NAN).unwrap().outside_box(b));
        assert_eq!(MidRad::bounding_box(&[p(0.0), None]), None);
        assert_eq!(MidRad::bounding_box(&[p(0.0), p(f64::NAN)]), None);
        assert_eq!(
            MidRad::bounding_box(&[p(f64::MAX), p(0.0)]).map(|b| b[1]),
            None
        );
        assert_eq!(MidRad::bounding_box(std::iter::empty()), None);
        assert!(boxes_apart(b, [1.5, 2.0, 0.0, 0.0]));
        assert!(!boxes_apart(b, [1.0, 2.0, 0.0, 0.0]));
    }

    /// The in-circle filter never decides a sign other than the exact one
    /// for points within its radii, at scales from 1e-300 to 1e300, and
    /// decides most of them.
    #[test]
    fn in_circle_filter_agrees_with_the_exact_sign() {
        let mut rng = crate::rng::Rng::new(17);
        let exact_in_circle = |p: [[f64; 2]; 4]| {
            let q = p.map(|c| Point::from_f64(c).expect("finite"));
            let r = [0, 1, 2].map(|i| {
                let d = q[i].sub(&q[3]);
                let l = d.dot(&d);
                (d, l)
            });
            let cross = |a: &Point, b: &Point| a.cross(b);
            r[0].1
                .mul(&cross(&r[1].0, &r[2].0))
                .add(&r[1].1.mul(&cross(&r[2].0, &r[0].0)))
                .add(&r[2].1.mul(&cross(&r[0].0, &r[1].0)))
                .sign()
        };
        let (mut decided, mut decided_static, mut decided_box) = (0, 0, 0);
        for scale in [1e-300, 1e-9, 1.0, 1e9, 1e150] {
            for _ in 0..3000 {
                let mut pt = || {
                    let x = rng.range_f64(-1.0, 1.0) * scale;
                    let y = rng.range_f64(-1.0, 1.0) * scale;
                    let r = [0.0, scale * 1e-12, scale * 1e-3][rng.below(3) as usize];
                    let (tx, ty) = (
                        x + r * rng.range_f64(-1.0, 1.0),
                        y + r * rng.range_f64(-1.0, 1.0),
                    );
                    (MidRad { x, y, r }, [tx, ty])
                };
                let (mut a, mut b, mut c, mut d) = (pt(), pt(), pt(), pt());
                if rng.chance(0.3) {
                    // four points on one circle, up to their rounding
                    let on = |p: &mut (MidRad, [f64; 2]), k: f64| {
                        let (x, y) = (k.cos() * scale, k.sin() * scale);
                        *p = (MidRad { x, y, r: 0.0 }, [x, y]);
                    };
                    on(&mut a, 0.3);
                    on(&mut b, 1.9);
                    on(&mut c, 4.0);
                    on(&mut d, rng.range_f64(0.0, std::f64::consts::TAU));
                }
                let want = exact_in_circle([a.1, b.1, c.1, d.1]);
                if let Some(s) = in_circle_mid_rad(a.0, b.0, c.0, d.0) {
                    decided += 1;
                    assert_eq!(s, want, "{a:?} {b:?} {c:?} {d:?}");
                }
                if let Some(s) = in_circle_static(a.0, b.0, c.0, d.0) {
                    decided_static += 1;
                    assert_eq!(s, want, "static: {a:?} {b:?} {c:?} {d:?}");
                }
                // the bound of a set that holds the four, and of one that
                // also holds a point farther out
                let far = MidRad {
                    x: -1.5 * scale,
                    y: 0.5 * scale,
                    r: scale * 1e-12,
                };
                for set in [vec![a.0, b.0, c.0, d.0], vec![d.0, far, c.0, b.0, a.0]] {
                    let bound = in_circle_box_bound(&set);
                    if let Some(s) = in_circle_in_box(a.0, b.0, c.0, d.0, bound) {
                        decided_box += 1;
                        assert_eq!(s, want, "box: {a:?} {b:?} {c:?} {d:?}");
                    }
                }
            }
        }
        assert!(decided > 5000, "decided {decided}");
        assert!(decided_static > 5000, "decided {decided_static} (static)");
        // (a set's largest radius bounds every test in it: the sets with a
        // point of radius 1e-3 of the scale decide little)
        assert!(decided_box > 3000, "decided {decided_box} (box)");
    }

    /// Sums, differences and products of midpoint–radius numbers hold the
    /// exact result for any operands within the radii (each operand's two
    /// extremes and its midpoint), at scales from subnormal products to
    /// 1e150, and a product with the exact zero is the exact zero.
    #[test]
    fn mr_arithmetic_holds_the_exact_results() {
        let mut rng = crate::rng::Rng::new(11);
        let r = |x: f64| Rational::from_f64(x).expect("finite");
        let holds = |x: Mr, v: &Rational| {
            let iv = x.interval();
            r(iv.lo) <= *v && *v <= r(iv.hi)
        };
        let mut products = 0;
        for _ in 0..4000 {
            let operand = |rng: &mut crate::rng::Rng| {
                let e = rng.range_i64(-560, 150) as i32;
                let m = rng.range_f64(-1.0, 1.0) * 2f64.powi(e);
                let rad = if rng.chance(0.3) {
                    0.0
                } else {
                    m.abs() * rng.range_f64(0.0, 1e-12)
                };
                Mr { m, r: rad }
            };
            let (a, b) = (operand(&mut rng), operand(&mut rng));
            let ends = |x: Mr| [r(x.m).sub(&r(x.r)), r(x.m), r(x.m).add(&r(x.r))];
            for x in ends(a) {
                for y in ends(b) {
                    assert!(holds(a + b, &x.add(&y)), "{a:?} + {b:?}");
                    assert!(holds(a - b, &x.sub(&y)), "{a:?} - {b:?}");
                    assert!(holds(a * b, &x.mul(&y)), "{a:?} * {b:?}");
                    products += 1;
                }
            }
            assert_eq!(a * Mr::ZERO, Mr::ZERO);
            assert_eq!(Mr::ZERO * b, Mr::ZERO);
        }
        assert!(products >= 36_000);
    }

    /// Two midpoint–radius forms that both hold one point are never
    /// called apart, at scales from 1e-300 to 1e300.
    #[test]
    fn mid_rad_points_holding_one_point_are_never_apart() {
        let mut rng = crate::rng::Rng::new(7);
        let mut next = || rng.range_f64(-0.5, 0.5);
        for scale in [1e-300, 1e-9, 1.0, 1e9, 1e300] {
            for _ in 0..2000 {
                // one point P, two midpoints near it, radii that reach it
                let (px, py) = (next() * scale, next() * scale);
                let near = |d: f64| d * scale * 1e-6;
                let (ax, ay) = (px + near(next()), py + near(next()));
                let (bx, by) = (px + near(next()), py + near(next()));
                let reach = |mx: f64, my: f64| ((mx - px).abs().max((my - py).abs())) * 1.5;
                let a = MidRad {
                    x: ax,
                    y: ay,
                    r: reach(ax, ay),
                };
                let b = MidRad {
                    x: bx,
                    y: by,
                    r: reach(bx, by),
                };
                assert!(
                    !a.apart(b) && !b.apart(a),
                    "{a:?} {b:?} both hold ({px}, {py})"
                );
            }
        }
        let a = MidRad {
            x: 0.0,
            y: 0.0,
            r: 1.0,
        };
        assert!(
            !a.apart(MidRad {
                x: 2.0,
                y: 0.0,
                r: 1.0
            }),
            "touching"
        );
        assert!(a.apart(MidRad {
            x: 2.5,
            y: 0.0,
            r: 1.0
        }));
        assert!(a.apart(MidRad {
            x: 0.0,
            y: -2.5,
            r: 1.0
        }));
    }

    /// The midpoint–radius filters of the turn and the dot product never
    /// contradict the exact sign: points on a grid (so that many triples
    /// are collinear, at right angles, or nearly so), each perturbed within
    /// its radius, against exact rational orientation and dot product.
    #[test]
    fn mid_rad_orientation_never_contradicts_the_exact_sign() {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut decided, mut dots, mut boxed) = (0, 0, 0);
        for round in 0..20_000 {
            let scale = [1.0, 1e-12, 3.0e9, 0.1][round % 4];
            let mut pt = || {
                let x = ((next() % 64) as f64 - 32.0) * scale / 8.0;
                let y = ((next() % 64) as f64 - 32.0) * scale / 8.0;
                let r = [0.0, scale * 1e-12, scale * 1e-3][(next() % 3) as usize];
                // the true point: somewhere within the radius
                let f = |k: u64| (k % 1001) as f64 / 1000.0 * 2.0 - 1.0;
                let (tx, ty) = (x + r * f(next()), y + r * f(next()));
                (MidRad { x, y, r }, [tx, ty])
            };
            let (a, b, c) = (pt(), pt(), pt());
            let exact = |p: [f64; 2]| Point::from_f64(p).expect("finite");
            let o = orient(&exact(a.1), &exact(b.1), &exact(c.1));
            if let Some(s) = orient_mid_rad(a.0, b.0, c.0) {
                decided += 1;
                assert_eq!(s, o, "{a:?} {b:?} {c:?}");
            }
            // the bound of a set that holds the three, and of one that also
            // holds a point at the grid's corner
            let corner = MidRad {
                x: 4.0 * scale,
                y: -4.0 * scale,
                r: 0.0,
            };
            for set in [vec![a.0, b.0, c.0], vec![corner, c.0, b.0, a.0]] {
                if let Some(s) = orient_in_box(a.0, b.0, c.0, orient_box_bound(&set)) {
                    boxed += 1;
                    assert_eq!(s, o, "box: {a:?} {b:?} {c:?}");
                }
            }
            let (pa, pb, pc) = (exact(a.1), exact(b.1), exact(c.1));
            let dot = pb.sub(&pa).dot(&pc.sub(&pa));
            if let Some(s) = dot_mid_rad(a.0, b.0, c.0) {
                dots += 1;
                assert_eq!(s, dot.sign(), "dot {a:?} {b:?} {c:?}");
            }
        }
        assert!(
            decided > 10_000 && dots > 10_000 && boxed > 20_000,
            "the filters decide most triples ({decided} turns, {dots} dots, {boxed} in boxes)"
        );
    }

    /// The Minkowski pass on `i128` (shifted coordinates below `2^124`)
    /// gives the same edges in the same order as the one on big integers,
    /// for polygons of one scale and of very different scales (shifted
    /// coordinates), regular and irregular, with parallel edges, with
    /// coordinates of up to 100 bits (cross products past `i128`) and past
    /// it (the big-integer pass); the filtered edges are the same edges,
    /// their enclosures hold the exact integers.
    #[test]
    fn minkowski_edges_on_i128_are_the_big_integer_ones() {
        let regular = |n: usize, r: f64, phase: f64, c: [f64; 2]| -> Vec<[f64; 2]> {
            (0..n)
                .map(|i| {
                    let a = phase + std::f64::consts::TAU * i as f64 / n as f64;
                    [c[0] + r * a.cos(), c[1] + r * a.sin()]
                })
                .collect()
        };
        let shapes = [
            regular(16, 0.4, 0.3, [0.0, 0.0]),
            regular(4, 1.0, 0.0, [0.0, 0.0]),
            vec![[0.0, 0.0], [32.0, 0.0], [32.0, 0.125], [0.0, 0.125]],
            regular(7, 0.001, 1.1, [5.0, -3.0]),
            regular(64, 3.0, 0.01, [-1.0, 2.0]),
            vec![[0.0, 0.0], [1.0, 0.0], [1.5, 0.5], [1.0, 1.0], [0.0, 1.0]],
            // coordinates of about 90 bits, and of more than 100
            vec![[1e-12, 0.0], [1.0, 1e-9], [0.5, 0.75 + 1e-11]],
            vec![[-1e-25, 0.0], [1.0, 1e-20], [0.5, 0.75]],
        ];
        let (mut fast, mut wide, mut big) = (0, 0, 0);
        for x in &shapes {
            for y in &shapes {
                let (a, b) = (BodyPolygon::new(x).unwrap(), BodyPolygon::new(y).unwrap());
                let mut got = Vec::new();
                let exp = for_each_minkowski_edge(&a, &b, |e| got.push(e));
                let e0 = a.exp.min(b.exp);
                let mut want = Vec::new();
                minkowski_edges_big(
                    &a,
                    &b,
                    ((a.exp - e0) as usize, (b.exp - e0) as usize),
                    &mut |e| want.push(e),
                );
                assert_eq!(exp, e0);
                assert_eq!(got, want);
                let (filtered, fexp) = minkowski_edges_filtered(&a, &b);
                assert_eq!(fexp, e0);
                assert_eq!(
                    filtered.iter().map(FilteredEdge::edge).collect::<Vec<_>>(),
                    want
                );
                for f in &filtered {
                    let e = f.edge();
                    for (iv, x) in f.iv.iter().zip([&e.nx, &e.ny, &e.h]) {
                        let r = Rational::from_int(x.clone());
                        let lo = Rational::from_f64(iv.lo).expect("finite");
                        let hi = Rational::from_f64(iv.hi).expect("finite");
                        assert!(lo <= r && r <= hi, "{iv:?} does not hold {x}");
                    }
                }
                let shifted = |p: &BodyPolygon| p.bits as i64 + p.exp - e0;
                if a.small.is_some() && b.small.is_some() && shifted(&a).max(shifted(&b)) <= 124 {
                    fast += 1;
                    if a.bits.max(b.bits) > 62 {
                        wide += 1;
                    }
                } else {
                    big += 1;
                }
            }
        }
        assert!(fast >= 30, "the i128 path ran on only {fast} pairs");
        assert!(wide >= 10, "only {wide} pairs had coordinates past 62 bits");
        assert!(big >= 5, "the big-integer path ran on only {big} pairs");
    }

    /// The filtered orientation agrees with the exact formula, on exactly
    /// collinear triples (thirds, which no double represents) and on
    /// triples a tiny rational step off the line, at small and huge scales.
    #[test]
    fn filtered_orientation_is_exact() {
        let r = |n: i64, d: i64| Rational::new(Int::from(n), Int::from(d));
        for scale in [1i64, 3, 1 << 40, -(1 << 52)] {
            for k in -5i64..=5 {
                let p = Point {
                    x: r(scale, 3),
                    y: r(2 * scale, 7),
                };
                let q = Point {
                    x: r(4 * scale, 3),
                    y: r(9 * scale, 7),
                };
                // on the line p + s (q − p) with s = 5/11, then nudged by k/10^30
                let s = r(5, 11);
                let on = p.add(&q.sub(&p).scale(&s));
                let nudge = Rational::new(Int::from(k), Int::from(10).pow(30));
                let w = Point {
                    x: on.x.clone(),
                    y: on.y.add(&nudge),
                };
                let exact = q.sub(&p).cross(&w.sub(&p)).sign();
                assert_eq!(orient(&p, &q, &w), exact, "scale {scale} k {k}");
            }
        }
    }

    #[test]
    fn validation() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let p = BodyPolygon::new(&sq).unwrap();
        assert_eq!(p.twice_area(), Rational::from_int(Int::from(2)));
        assert_eq!(p.centroid(), Point::from_f64([0.5, 0.5]).unwrap());
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
        // huge coordinates and zeros: a common unit above 1 (the integers
        // in i128; debug builds compare them with the big-integer ones)
        let huge = BodyPolygon::new(&[[0.0, 0.0], [1e20, 0.0], [0.0, -1e20]]);
        assert_eq!(huge, Err(PolygonDefect::Clockwise));
        let huge = BodyPolygon::new(&[[0.0, 0.0], [1e20, 0.0], [0.0, 3e20]]).unwrap();
        assert_eq!(huge.vertex(2).to_f64(), [0.0, 3e20]);
        assert!(huge.exp() > 0);
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
        assert!(!convex_polygons_intersect(
            &sq(0.0, 0.0),
            &sq(1.0 + 1e-12, 0.0)
        ));
        let pt = |x: f64, y: f64| Point::from_f64([x, y]).unwrap();
        let meets = |p, q| segment_meets_convex_interior(&p, &q, &sq(0.0, 0.0));
        assert!(meets(pt(-1.0, 0.5), pt(2.0, 0.5))); // through
        assert!(meets(pt(0.0, 0.0), pt(1.0, 1.0))); // diagonal, corner to corner
        assert!(meets(pt(0.5, 0.5), pt(0.6, 0.5))); // inside
        assert!(!meets(pt(0.0, 0.0), pt(1.0, 0.0))); // along an edge
        assert!(!meets(pt(-1.0, 0.0), pt(3.0, 0.0))); // along an edge line
        assert!(!meets(pt(1.0, 0.0), pt(2.0, -1.0))); // from a corner outwards
        assert!(!meets(pt(-1.0, 1.0), pt(1.0, -1.0))); // grazing a corner
        assert!(!meets(pt(2.0, 0.0), pt(2.0, 1.0))); // apart
    }
}

/// One edge of the Minkowski difference `M = B ⊕ (−A)` of two body polygons,
/// as the half-plane `n · x <= h` in integer units (see
/// [`for_each_minkowski_edge`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MinkowskiEdge {
    /// Outward normal, in units of `2^exp`.
    pub nx: Int,
    /// Outward normal, y.
    pub ny: Int,
    /// Support value `n · v` for a vertex `v` of the edge, in units of `2^(2·exp)`.
    pub h: Int,
    /// Which polygon the edge comes from and its index there: `Ok(j)` for
    /// edge `j` of `B` (touched by vertex `other` of `A`), `Err(i)` for edge
    /// `i` of `A` (touched by vertex `other` of `B`).
    pub source: Result<usize, usize>,
    /// The vertex of the other polygon that is extreme along this edge's normal.
    pub other: usize,
}

/// Visit the edges of `M = B ⊕ (−A)` in counter-clockwise order, in `O(n + m)`.
///
/// `A` and `B` placed at positions `pa` and `pb` intersect (closed sets) iff
/// `pa − pb ∈ M`, that is iff `n · (pa − pb) <= h · 2^exp` for every edge,
/// where `exp` is the returned common exponent (coordinates of both polygons
/// are brought to the integer units `2^exp`).
pub fn for_each_minkowski_edge(
    a: &BodyPolygon,
    b: &BodyPolygon,
    mut visit: impl FnMut(MinkowskiEdge),
) -> i64 {
    let exp = a.exp.min(b.exp);
    let sa = (a.exp - exp) as usize;
    let sb = (b.exp - exp) as usize;
    if minkowski_walk_i128(a, b, (sa, sb), &mut |e: SmallEdge, source, other| {
        let [nx, ny, h] = e.exact();
        visit(MinkowskiEdge {
            nx,
            ny,
            h,
            source,
            other,
        })
    }) {
        return exp;
    }
    minkowski_edges_big(a, b, (sa, sb), &mut visit);
    exp
}

/// An edge of `M` from the `i128` walk: its normal `(nx, ny)` and the
/// vertex `v` of `M` it starts at, in the common integer units (each
/// below `2^126` in magnitude); `h = n · v` may exceed `i128`.
#[derive(Clone, Copy, Debug)]
struct SmallEdge {
    n: [i128; 2],
    v: [i128; 2],
}

impl SmallEdge {
    /// `nx`, `ny` and `h` exactly.
    fn exact(&self) -> [Int; 3] {
        let [nx, ny] = self.n.map(Int::from);
        let [vx, vy] = self.v.map(Int::from);
        let h = &nx * &vx + &ny * &vy;
        [nx, ny, h]
    }

    /// Enclosures of `nx`, `ny` and `h` (`h` exact in `i128` where it fits).
    fn enclosures(&self) -> [Interval; 3] {
        let [nx, ny] = self.n;
        let [vx, vy] = self.v;
        let [inx, iny] = [nx, ny].map(Interval::of_i128);
        // (factors below 2^63: products below 2^126, their sum in range)
        let small = (nx.unsigned_abs() | ny.unsigned_abs() | vx.unsigned_abs() | vy.unsigned_abs())
            < 1 << 63;
        let h = if small {
            Some(nx * vx + ny * vy)
        } else {
            nx.checked_mul(vx)
                .zip(ny.checked_mul(vy))
                .and_then(|(p, q)| p.checked_add(q))
        };
        let ih = match h {
            Some(h) => Interval::of_i128(h),
            None => inx * Interval::of_i128(vx) + iny * Interval::of_i128(vy),
        };
        [inx, iny, ih]
    }
}

/// The Minkowski walk ([`merge_by_angle`]) on `i128`, where each polygon's integer
/// coordinates shifted to the common units (by `sa` for A, `sb` for B)
/// stay below `2^124`: edge vectors and `M`'s vertices below `2^125`. The
/// order of the edges is decided on each polygon's own (unshifted) edge
/// vectors ([`angle_cmp_i128`]): a positive scale changes no angle, so the
/// edges come in the same order as on big integers. Returns `false`
/// (visiting nothing) where the coordinates do not fit.
fn minkowski_walk_i128(
    a: &BodyPolygon,
    b: &BodyPolygon,
    (sa, sb): (usize, usize),
    visit: &mut impl FnMut(SmallEdge, Result<usize, usize>, usize),
) -> bool {
    let (Some(va), Some(vb)) = (a.small.as_deref(), b.small.as_deref()) else {
        return false;
    };
    if a.bits as usize + sa > 124 || b.bits as usize + sb > 124 {
        return false;
    }
    let (n, m) = (va.len(), vb.len());
    // unshifted edge vectors: B's edges and the reversed edges of A
    let edge_b = |j: usize| {
        let ([x0, y0], [x1, y1]) = (vb[j], vb[(j + 1) % m]);
        (x1 - x0, y1 - y0)
    };
    let edge_na = |i: usize| {
        let ([x0, y0], [x1, y1]) = (va[i], va[(i + 1) % n]);
        (x0 - x1, y0 - y1)
    };
    let first = (a.first_edges[1], b.first_edges[0]);
    let b_first =
        |i: usize, j: usize| angle_cmp_i128(edge_b(j), edge_na(i)) != std::cmp::Ordering::Greater;
    merge_by_angle((n, m), first, b_first, |i, j, take_b| {
        // current vertex of M: b_j − a_i, in the common units
        let [bx, by] = vb[j].map(|c| c << sb);
        let [ax, ay] = va[i].map(|c| c << sa);
        let (ex, ey) = if take_b {
            let (x, y) = edge_b(j);
            (x << sb, y << sb)
        } else {
            let (x, y) = edge_na(i);
            (x << sa, y << sa)
        };
        visit(
            SmallEdge {
                n: [ey, -ex],
                v: [bx - ax, by - ay],
            },
            if take_b { Ok(j) } else { Err(i) },
            if take_b { i } else { j },
        );
    });
    true
}

/// An edge of `M = B ⊕ (−A)` with enclosures of its integers (the f64
/// filter of the tests against it); its exact integers
/// ([`FilteredEdge::edge`]) are built only for the edges the filter
/// leaves undecided.
#[derive(Clone, Debug)]
pub(crate) struct FilteredEdge {
    /// Enclosures of `nx`, `ny` and `h`.
    pub iv: [Interval; 3],
    exact: EdgeInts,
}

/// The exact integers of a [`FilteredEdge`].
#[derive(Clone, Debug)]
enum EdgeInts {
    /// The edge from the `i128` walk, with its source and other vertex.
    Small(SmallEdge, Result<usize, usize>, usize),
    /// The edge on big integers.
    Big(MinkowskiEdge),
}

impl FilteredEdge {
    /// The exact edge.
    pub(crate) fn edge(&self) -> MinkowskiEdge {
        match &self.exact {
            EdgeInts::Small(e, source, other) => {
                let [nx, ny, h] = e.exact();
                MinkowskiEdge {
                    nx,
                    ny,
                    h,
                    source: *source,
                    other: *other,
                }
            }
            EdgeInts::Big(e) => e.clone(),
        }
    }
}

/// The edges of [`for_each_minkowski_edge`] in the same order, each with
/// enclosures of its integers, and the common exponent. Where the
/// coordinates fit the `i128` path no big integer is built.
pub(crate) fn minkowski_edges_filtered(
    a: &BodyPolygon,
    b: &BodyPolygon,
) -> (Vec<FilteredEdge>, i64) {
    let exp = a.exp.min(b.exp);
    let sa = (a.exp - exp) as usize;
    let sb = (b.exp - exp) as usize;
    let mut out = Vec::with_capacity(a.len() + b.len());
    if minkowski_walk_i128(a, b, (sa, sb), &mut |e: SmallEdge, source, other| {
        out.push(FilteredEdge {
            iv: e.enclosures(),
            exact: EdgeInts::Small(e, source, other),
        })
    }) {
        return (out, exp);
    }
    minkowski_edges_big(a, b, (sa, sb), &mut |e| {
        out.push(FilteredEdge {
            iv: [&e.nx, &e.ny, &e.h].map(Interval::of_int),
            exact: EdgeInts::Big(e),
        })
    });
    (out, exp)
}

/// [`for_each_minkowski_edge`] on big integers (`A`'s coordinates shifted
/// left by `sa`, `B`'s by `sb`), where they do not fit
/// [`minkowski_walk_i128`] (which gives the same edges in the same order).
fn minkowski_edges_big(
    a: &BodyPolygon,
    b: &BodyPolygon,
    (sa, sb): (usize, usize),
    visit: &mut impl FnMut(MinkowskiEdge),
) {
    let (n, m) = (a.len(), b.len());
    let av = |i: usize| (&a.xs[i] << sa, &a.ys[i] << sa);
    let bv = |j: usize| (&b.xs[j] << sb, &b.ys[j] << sb);
    // Edge directions: B's edges, and the reversed edges of A (edges of −A).
    let edge_b = |j: usize| {
        let ((x0, y0), (x1, y1)) = (bv(j), bv((j + 1) % m));
        (x1 - x0, y1 - y0)
    };
    let edge_na = |i: usize| {
        let ((x0, y0), (x1, y1)) = (av(i), av((i + 1) % n));
        (x0 - x1, y0 - y1)
    };
    let j0 = (0..m)
        .min_by(|&x, &y| angle_cmp(&edge_b(x), &edge_b(y)))
        .expect("non-empty");
    let i0 = (0..n)
        .min_by(|&x, &y| angle_cmp(&edge_na(x), &edge_na(y)))
        .expect("non-empty");
    let b_first =
        |i: usize, j: usize| angle_cmp(&edge_b(j), &edge_na(i)) != std::cmp::Ordering::Greater;
    merge_by_angle((n, m), (i0, j0), b_first, |i, j, take_b| {
        let (e, _) = if take_b {
            minkowski_edge_of(a, b, Ok(j), i)
        } else {
            minkowski_edge_of(a, b, Err(i), j)
        };
        visit(e);
    });
}

/// The edge of `M = B ⊕ (−A)` ([`for_each_minkowski_edge`]) from edge
/// `source` (`Ok(j)`: edge `j` of `b`; `Err(i)`: edge `i` of `a`,
/// reversed) with `other` as the other polygon's vertex at it, computed
/// alone, with the same integers the whole walk gives that edge, and the
/// common exponent. Whether `other` is the vertex the walk pairs with
/// `source` is the caller's to know.
pub(crate) fn minkowski_edge_of(
    a: &BodyPolygon,
    b: &BodyPolygon,
    source: Result<usize, usize>,
    other: usize,
) -> (MinkowskiEdge, i64) {
    let exp = a.exp.min(b.exp);
    let (sa, sb) = ((a.exp - exp) as usize, (b.exp - exp) as usize);
    let (n, m) = (a.len(), b.len());
    let av = |i: usize| (&a.xs[i] << sa, &a.ys[i] << sa);
    let bv = |j: usize| (&b.xs[j] << sb, &b.ys[j] << sb);
    // (the walk's current vertex of `M` at the edge is b_j − a_i)
    let ((ex, ey), (vx, vy)) = match source {
        Ok(j) => {
            let ((x0, y0), (x1, y1)) = (bv(j), bv((j + 1) % m));
            let (ax, ay) = av(other);
            ((x1 - &x0, y1 - &y0), (x0 - ax, y0 - ay))
        }
        Err(i) => {
            let ((x0, y0), (x1, y1)) = (av(i), av((i + 1) % n));
            let (bx, by) = bv(other);
            ((&x0 - x1, &y0 - y1), (bx - x0, by - y0))
        }
    };
    let (nx, ny) = (ey, -ex);
    let h = &nx * &vx + &ny * &vy;
    (
        MinkowskiEdge {
            nx,
            ny,
            h,
            source,
            other,
        },
        exp,
    )
}

/// The merge behind [`for_each_minkowski_edge`]: the `m` edges of `B` and
/// the `n` reversed edges of `A` in counter-clockwise order of angle, from
/// the least-angled of each (`first`: `(i0, j0)`), B's edge first on a tie
/// (`b_first(i, j)`: B's edge `j` comes no later than A's reversed edge
/// `i`). Calls `visit(i, j, take_b)` for each edge of `M` in order, with
/// the current edge indices and whether it is B's.
fn merge_by_angle(
    (n, m): (usize, usize),
    (i0, j0): (usize, usize),
    b_first: impl Fn(usize, usize) -> bool,
    mut visit: impl FnMut(usize, usize, bool),
) {
    let (mut ib, mut ia) = (0usize, 0usize);
    while ib < m || ia < n {
        let j = (j0 + ib) % m;
        let i = (i0 + ia) % n;
        let take_b = if ib == m {
            false
        } else if ia == n {
            true
        } else {
            b_first(i, j)
        };
        visit(i, j, take_b);
        if take_b {
            ib += 1;
        } else {
            ia += 1;
        }
    }
}

/// The edge of least angle of the polygon with vertices `v`, and of least
/// angle reversed ([`BodyPolygon::first_edges`]).
fn first_edges_i128(v: &[[i128; 2]]) -> [usize; 2] {
    let n = v.len();
    let edge = |i: usize| {
        let ([x0, y0], [x1, y1]) = (v[i], v[(i + 1) % n]);
        (x1 - x0, y1 - y0)
    };
    let least = |f: &dyn Fn(usize) -> (i128, i128)| {
        (0..n)
            .min_by(|&x, &y| angle_cmp_i128(f(x), f(y)))
            .expect("non-empty")
    };
    [
        least(&edge),
        least(&|i| {
            let (x, y) = edge(i);
            (-x, -y)
        }),
    ]
}

/// The sign of `ax·by − ay·bx` for components below `2^126` in magnitude:
/// the two products compared exactly as 256-bit sign and magnitude.
pub(crate) fn cross_sign_wide(ax: i128, ay: i128, bx: i128, by: i128) -> Sign {
    // (components below 2^63: each product below 2^126, compared in i128)
    if (ax.unsigned_abs() | ay.unsigned_abs() | bx.unsigned_abs() | by.unsigned_abs()) < 1 << 63 {
        return Sign::from_ordering((ax * by).cmp(&(ay * bx)));
    }
    // |a|·|b| as (high, low) 128-bit halves, from 64-bit limbs
    let wide = |a: u128, b: u128| -> (u128, u128) {
        const M: u128 = (1 << 64) - 1;
        let (a1, a0, b1, b0) = (a >> 64, a & M, b >> 64, b & M);
        let (ll, lh, hl, hh) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
        let mid = (ll >> 64) + (lh & M) + (hl & M);
        (
            (hh + (lh >> 64) + (hl >> 64) + (mid >> 64)),
            (ll & M) | (mid << 64),
        )
    };
    let product = |a: i128, b: i128| -> (Sign, (u128, u128)) {
        let s = Sign::of_i128(a).mul(Sign::of_i128(b));
        (s, wide(a.unsigned_abs(), b.unsigned_abs()))
    };
    let ((sp, mp), (sq, mq)) = (product(ax, by), product(ay, bx));
    match (sp, sq) {
        (Sign::Positive, Sign::Positive) => Sign::from_ordering(mp.cmp(&mq)),
        (Sign::Negative, Sign::Negative) => Sign::from_ordering(mq.cmp(&mp)),
        (p, q) => Sign::from_ordering(p.cmp(&q)),
    }
}

/// [`angle_cmp`] on `i128` vectors (components below `2^101`): the cross
/// products on `i128` where they fit, compared in 256 bits
/// ([`cross_sign_wide`]) where not.
fn angle_cmp_i128(u: (i128, i128), v: (i128, i128)) -> std::cmp::Ordering {
    let half = |d: (i128, i128)| u8::from(!(d.1 > 0 || (d.1 == 0 && d.0 > 0)));
    let (hu, hv) = (half(u), half(v));
    if hu != hv {
        return hu.cmp(&hv);
    }
    // (components below 2^63: each product below 2^126, no check needed)
    let small = |d: (i128, i128)| (d.0.unsigned_abs() | d.1.unsigned_abs()) < 1 << 63;
    if small(u) && small(v) {
        return (u.1 * v.0).cmp(&(u.0 * v.1));
    }
    // (larger ones: the products compared in 256 bits)
    cross_sign_wide(u.1, u.0, v.1, v.0).to_ordering()
}

/// Compare the angles in `[0, 2π)` of two non-zero integer vectors.
fn angle_cmp(u: &(Int, Int), v: &(Int, Int)) -> std::cmp::Ordering {
    let half = |d: &(Int, Int)| {
        if d.1 > Int::ZERO || (d.1 == Int::ZERO && d.0 > Int::ZERO) {
            0
        } else {
            1
        }
    };
    let (hu, hv) = (half(u), half(v));
    if hu != hv {
        return hu.cmp(&hv);
    }
    // same half: u before v iff v is counter-clockwise of u
    (&u.1 * &v.0).cmp(&(&u.0 * &v.1))
}

/// The f64 filter of a Minkowski edge's inequality `n · d <= h · 2^exp`
/// (`d` the relative position of two placed polygons, `exp` the edges'
/// exponent): enclosures of both sides.
pub(crate) struct EdgeSideFilter {
    dx: Interval,
    dy: Interval,
    unit: Option<Interval>,
}

impl EdgeSideFilter {
    /// The filter for relative position `d` and exponent `exp`.
    pub(crate) fn new(d: &Point, exp: i64) -> EdgeSideFilter {
        EdgeSideFilter::of_intervals(d.x.interval(), d.y.interval(), exp)
    }

    /// The filter for a relative position enclosed by `dx` and `dy`.
    pub(crate) fn of_intervals(dx: Interval, dy: Interval, exp: i64) -> EdgeSideFilter {
        EdgeSideFilter {
            dx,
            dy,
            unit: (-1000..=1000)
                .contains(&exp)
                .then(|| Interval::point(2f64.powi(exp as i32))),
        }
    }

    /// `Greater` or `Less` when the enclosures show `n · d` strictly above
    /// or below `h · 2^exp` for edge `e`; `None` when they cannot tell (an
    /// exponent out of the doubles' range, or enclosures that overlap).
    pub(crate) fn of(&self, e: &FilteredEdge) -> Option<std::cmp::Ordering> {
        let unit = self.unit?;
        let [nx, ny, h] = e.iv;
        let lhs = self.dx * nx + self.dy * ny;
        let rhs = h * unit;
        if lhs.lo > rhs.hi {
            Some(std::cmp::Ordering::Greater)
        } else if lhs.hi < rhs.lo {
            Some(std::cmp::Ordering::Less)
        } else {
            None
        }
    }
}

/// The disk of [`BodyPolygon::bounding_disk`] for `vertices` with bounding
/// box `bbox`: every distance enclosed with outward rounding.
fn bounding_disk(vertices: &[[f64; 2]], bbox: &[f64; 4]) -> ([f64; 2], f64) {
    let c = [0.5 * bbox[0] + 0.5 * bbox[1], 0.5 * bbox[2] + 0.5 * bbox[3]];
    let p = Interval::point;
    let r = vertices
        .iter()
        .map(|v| {
            ((p(v[0]) - p(c[0])).square() + (p(v[1]) - p(c[1])).square())
                .sqrt()
                .hi
        })
        .fold(
            0.0,
            |r: f64, d| if d.is_nan() { f64::INFINITY } else { r.max(d) },
        );
    (c, r)
}

/// Whether body polygons `a` at `pa` and `b` at `pb` share a point (closed
/// sets), exactly, in `O(n + m)`.
pub fn placed_polygons_intersect(a: &BodyPolygon, pa: &Point, b: &BodyPolygon, pb: &Point) -> bool {
    let d = pa.sub(pb);
    // each edge's test `n · d <= h · 2^exp` on enclosures first: a
    // separating edge ends the walk, an edge that certainly holds is done,
    // and only the others are tested exactly
    let (edges, exp) = minkowski_edges_filtered(a, b);
    let side = EdgeSideFilter::new(&d, exp);
    let mut undecided: Vec<MinkowskiEdge> = Vec::new();
    for e in &edges {
        match side.of(e) {
            Some(std::cmp::Ordering::Greater) => return false,
            Some(_) => {}
            None => undecided.push(e.edge()),
        }
    }
    let unit = Rational::from_dyadic(Int::ONE, exp);
    undecided.into_iter().all(|e| {
        let lhs =
            d.x.mul(&Rational::from_int(e.nx))
                .add(&d.y.mul(&Rational::from_int(e.ny)));
        lhs <= Rational::from_int(e.h).mul(&unit)
    })
}

#[cfg(test)]
mod minkowski_tests {
    use super::*;

    fn world(p: &BodyPolygon, at: [f64; 2]) -> Vec<Point> {
        let o = Point::from_f64(at).unwrap();
        (0..p.len()).map(|i| p.vertex(i).add(&o)).collect()
    }

    /// The bounding disk holds every vertex (distances compared exactly),
    /// for regular polygons off the origin at scales from 1e-150 to 1e150,
    /// and is not much larger than the polygon.
    #[test]
    fn bounding_disk_holds_every_vertex_exactly() {
        let exact = |v: f64| Point::from_f64([v, 0.0]).expect("finite").x;
        for (i, scale) in [1e-150, 1e-20, 1.0, 3.7, 1e20, 1e150]
            .into_iter()
            .enumerate()
        {
            for n in [3, 4, 7, 16, 257] {
                let vs: Vec<[f64; 2]> = crate::gen::regular_polygon(n, scale, 0.1 * i as f64)
                    .into_iter()
                    .map(|[x, y]| [x + 0.3 * scale, y - 2.0 * scale])
                    .collect();
                let p = BodyPolygon::new(&vs).expect("a convex polygon");
                let ([cx, cy], r) = p.bounding_disk();
                assert!(
                    r.is_finite() && r <= 1.5 * scale,
                    "radius {r} at scale {scale}"
                );
                let r2 = exact(r).mul(&exact(r));
                for v in &vs {
                    let (dx, dy) = (exact(v[0]).sub(&exact(cx)), exact(v[1]).sub(&exact(cy)));
                    assert!(
                        dx.mul(&dx).add(&dy.mul(&dy)) <= r2,
                        "{v:?} outside the disk"
                    );
                }
            }
        }
    }

    #[test]
    fn agrees_with_separating_axes() {
        let mut seed = 12345u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 1000) as f64 / 250.0 - 2.0
        };
        let shapes = [
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            vec![[0.0, 0.0], [2.0, 0.5], [0.5, 1.0]],
            vec![
                [-1.0, -0.5],
                [0.5, -1.0],
                [1.0, 0.25],
                [0.0, 1.0],
                [-1.0, 0.5],
            ],
        ];
        let polys: Vec<BodyPolygon> = shapes
            .iter()
            .map(|s| BodyPolygon::new(s).unwrap())
            .collect();
        for _ in 0..3000 {
            let a = &polys[(next() * 100.0).abs() as usize % 3];
            let b = &polys[(next() * 100.0).abs() as usize % 3];
            // quarter-unit grid positions make touching configurations common
            let pa = [(next() * 4.0).round() / 4.0, (next() * 4.0).round() / 4.0];
            let pb = [(next() * 4.0).round() / 4.0, (next() * 4.0).round() / 4.0];
            let expected = convex_polygons_intersect(&world(a, pa), &world(b, pb));
            let got = placed_polygons_intersect(
                a,
                &Point::from_f64(pa).unwrap(),
                b,
                &Point::from_f64(pb).unwrap(),
            );
            assert_eq!(got, expected, "a at {pa:?}, b at {pb:?}");
        }
    }
}
