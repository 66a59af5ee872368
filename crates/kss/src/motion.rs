//! Motion: linear trajectories of rigid translating bodies, moving points in
//! homogeneous integer form, and certificate functions (orientations of three
//! moving points as polynomials in time).
//!
//! A body translates: at time `t` its world vertex is `position(t) + v` with
//! `v` the body-frame vertex and `position(t) = origin + velocity·t` on the
//! current piece of its piecewise-linear path (`origin` is the position the
//! piece would have at `t = 0`). A [`LinearPoint`] is such a world vertex in
//! the form `((x0 + x1·t)/w, (y0 + y1·t)/w)` with integers and `w > 0`, so that
//! [`orient_poly`] needs only integer arithmetic.

use crate::geom::{BodyPolygon, Point};
use crate::num::{lcm, Int, Interval, Poly, Rational};
use std::sync::OnceLock;

/// One linear piece of a body's path: `position(t) = origin + velocity·t`.
///
/// The origin and velocity are in lowest terms when read. A bridge's
/// ([`crate::world`]) is made as integers over one common denominator and
/// reduced (two gcds per coordinate, of numbers as long as the collision
/// time's) only when first read: the structure reads the body's frame
/// instead, and most bridges end without anything reading them.
#[derive(Clone, Debug)]
pub struct Trajectory(Repr);

/// A [`Trajectory`]'s numbers: in lowest terms (most trajectories; the
/// size of the two points, so that no body is larger for the other case),
/// or a bridge's common-denominator integers, boxed with their reduction
/// once read (only a body on a bridge pays for the box).
#[derive(Clone, Debug)]
enum Repr {
    /// `[origin, velocity]`.
    Reduced([Point; 2]),
    /// A bridge's.
    Over(Box<Over>),
}

/// `[ox, oy, vx, vy]` over `w > 0`, not reduced, and `[origin, velocity]`
/// in lowest terms once read.
#[derive(Clone, Debug)]
struct Over {
    n: [Int; 4],
    w: Int,
    reduced: OnceLock<[Point; 2]>,
}

impl PartialEq for Trajectory {
    fn eq(&self, other: &Trajectory) -> bool {
        self.origin() == other.origin() && self.velocity() == other.velocity()
    }
}

impl Eq for Trajectory {}

impl Trajectory {
    /// The piece at `origin` at time 0 that moves with `velocity`.
    pub fn from_origin(origin: Point, velocity: Point) -> Trajectory {
        Trajectory(Repr::Reduced([origin, velocity]))
    }

    /// The piece at `(ox/w, oy/w)` at time 0 that moves with `(vx/w,
    /// vy/w)`, `w > 0`, the fractions in any terms: reduced when first read.
    pub(crate) fn over(n: [Int; 4], w: Int) -> Trajectory {
        debug_assert!(w > Int::ZERO, "a trajectory's denominator is positive");
        Trajectory(Repr::Over(Box::new(Over {
            n,
            w,
            reduced: OnceLock::new(),
        })))
    }

    /// The piece that is at `position` at time `time` and moves with `velocity`.
    pub fn through(time: &Rational, position: &Point, velocity: Point) -> Trajectory {
        let t = time.neg();
        let origin = Point {
            x: position.x.mul_add(&velocity.x, &t),
            y: position.y.mul_add(&velocity.y, &t),
        };
        Trajectory::from_origin(origin, velocity)
    }

    /// `[origin, velocity]`, reduced on first read.
    fn parts(&self) -> &[Point; 2] {
        match &self.0 {
            Repr::Reduced(p) => p,
            Repr::Over(over) => over.reduced.get_or_init(|| {
                let r = |x: &Int| Rational::new(x.clone(), over.w.clone());
                let n = &over.n;
                [
                    Point {
                        x: r(&n[0]),
                        y: r(&n[1]),
                    },
                    Point {
                        x: r(&n[2]),
                        y: r(&n[3]),
                    },
                ]
            }),
        }
    }

    /// Whether the origin and velocity are in lowest terms already.
    #[cfg(test)]
    pub(crate) fn is_reduced(&self) -> bool {
        match &self.0 {
            Repr::Reduced(_) => true,
            Repr::Over(over) => over.reduced.get().is_some(),
        }
    }

    /// Position at time `t`.
    pub fn position_at(&self, t: &Rational) -> Point {
        let [o, v] = self.parts();
        Point {
            x: o.x.mul_add(&v.x, t),
            y: o.y.mul_add(&v.y, t),
        }
    }

    /// The velocity.
    pub fn velocity(&self) -> &Point {
        &self.parts()[1]
    }

    /// The position extrapolated to time 0.
    pub fn origin(&self) -> &Point {
        &self.parts()[0]
    }

    /// `max(floor, b)` where `b` is the largest bit length of a numerator
    /// or denominator of the origin and velocity in lowest terms. A
    /// trajectory not reduced yet is reduced for it only where its
    /// integers could exceed `floor`: each fraction over the common
    /// denominator with their common powers of two taken out is no shorter
    /// than in lowest terms.
    pub fn number_bits_above(&self, floor: u64) -> u64 {
        use dashu_base::BitTest;
        if let Repr::Over(over) = &self.0 {
            if over.reduced.get().is_none() {
                let (n, w) = (&over.n, &over.w);
                let wz = w.trailing_zeros().unwrap_or(0);
                let most = n
                    .iter()
                    .map(|x| {
                        let z = x.trailing_zeros().map_or(wz, |z| z.min(wz));
                        x.bit_len().max(w.bit_len()) - z
                    })
                    .max()
                    .unwrap_or(0) as u64;
                if most <= floor {
                    return floor;
                }
            }
        }
        let [o, v] = self.parts();
        [&o.x, &o.y, &v.x, &v.y]
            .iter()
            .flat_map(|r| [r.numer().bit_len(), r.denom().bit_len()])
            .max()
            .map_or(floor, |b| floor.max(b as u64))
    }

    /// The continuous continuation that moves with `velocity` from time `at` on.
    pub fn with_velocity_from(&self, at: &Rational, velocity: Point) -> Trajectory {
        Trajectory::through(at, &self.position_at(at), velocity)
    }
}

/// A body's current trajectory in integer form, ready to produce moving
/// vertices: vertex `i` is `((ox + m·X_i + vx·t)/w, (oy + m·Y_i + vy·t)/w)`
/// where `(X_i, Y_i)` are the body polygon's integer coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    ox: Int,
    oy: Int,
    vx: Int,
    vy: Int,
    m: Int,
    w: Int,
    /// Enclosures of `ox/w, oy/w, vx/w, vy/w, m/w` (the f64 filter's view;
    /// a velocity component that is exactly zero is the point `[0, 0]`).
    iv: [Interval; 5],
    /// The origin and velocity enclosures of `iv` in midpoint–radius form,
    /// per coordinate `[origin, velocity]` ([`Frame::mid_rad_of_vertex`]);
    /// a non-finite enclosure is a midpoint NaN, which nothing decides on.
    mr: [[crate::geom::Mr; 2]; 2],
    /// A number no other frame made in this process has (a clone keeps
    /// it: its values are the same): the key of cached enclosures.
    uid: u64,
}

/// The next [`Frame::uid`].
static NEXT_FRAME_UID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl Frame {
    /// The frame of a body polygon moving along `traj`.
    pub fn new(traj: &Trajectory, body: &BodyPolygon) -> Frame {
        let o = traj.origin();
        let v = traj.velocity();
        let dens = [o.x.denom(), o.y.denom(), v.x.denom(), v.y.denom()];
        let mut w = dens[0].clone();
        for d in &dens[1..] {
            w = lcm(&w, d);
        }
        let scale = |r: &Rational| r.numer() * (&w / r.denom());
        Frame::over(
            [scale(&o.x), scale(&o.y)],
            [scale(&v.x), scale(&v.y)],
            w,
            body,
        )
    }

    /// The frame of a body polygon moving from origin `o/w` with velocity
    /// `v/w` (`w > 0`; the fractions need not be in lowest terms, which
    /// spares the least common multiple of four denominators when the
    /// caller has a common one: a bridge's, see [`crate::world`]).
    pub(crate) fn over(
        [ox, oy]: [Int; 2],
        [vx, vy]: [Int; 2],
        w: Int,
        body: &BodyPolygon,
    ) -> Frame {
        debug_assert!(w > Int::ZERO, "a frame's denominator is positive");
        let (mut ox, mut oy, mut vx, mut vy, mut w) = (ox, oy, vx, vy, w);
        let e = body.exp();
        let m;
        if e >= 0 {
            m = &w << e as usize;
        } else {
            let s = (-e) as usize;
            ox <<= s;
            oy <<= s;
            vx <<= s;
            vy <<= s;
            m = w.clone();
            w <<= s;
        }
        let wi = Interval::of_int(&w);
        let iv = [&ox, &oy, &vx, &vy, &m].map(|x| {
            if x.is_zero() {
                Interval::point(0.0)
            } else {
                Interval::of_int(x) / wi
            }
        });
        // (a point, an exact zero velocity among them, keeps radius zero)
        let mid_rad = |c: Interval| {
            crate::geom::Mr::of(c).unwrap_or(crate::geom::Mr {
                m: f64::NAN,
                r: f64::INFINITY,
            })
        };
        let [ox_mr, oy_mr, vx_mr, vy_mr] = [iv[0], iv[1], iv[2], iv[3]].map(mid_rad);
        Frame {
            ox,
            oy,
            vx,
            vy,
            m,
            w,
            iv,
            mr: [[ox_mr, vx_mr], [oy_mr, vy_mr]],
            uid: NEXT_FRAME_UID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        }
    }

    /// Whether `self` and `other` move a body polygon alike: the same
    /// origin, velocity and scale as fractions (their integers may differ
    /// by a common factor; [`Frame::over`]).
    pub fn same_motion(&self, other: &Frame) -> bool {
        [
            (&self.ox, &other.ox),
            (&self.oy, &other.oy),
            (&self.vx, &other.vx),
            (&self.vy, &other.vy),
            (&self.m, &other.m),
        ]
        .iter()
        .all(|(a, b)| *a * &other.w == *b * &self.w)
    }

    /// A number that identifies this frame's values among all frames made
    /// in this process (never 0).
    pub fn uid(&self) -> u64 {
        self.uid
    }

    /// An enclosure of the world position at a time in `t` of the
    /// body-frame point given by enclosures `x`, `y` of its coordinates on
    /// the grid of this frame's body polygon (units `2^exp`): the f64
    /// filter's view of [`Frame::homogeneous`]. Never decides anything by
    /// itself.
    pub fn enclose(&self, x: Interval, y: Interval, t: Interval) -> [Interval; 2] {
        let [ox, oy, vx, vy, m] = self.iv;
        [ox + m * x + vx * t, oy + m * y + vy * t]
    }

    /// Enclosures `[x0, x1, y0, y1]` of the world position `(x0 + x1·t,
    /// y0 + y1·t)` of the body-frame point given by enclosures `x`, `y` of its
    /// coordinates on the body polygon's grid (as in [`Frame::enclose`]).
    /// The velocity terms are those of the frame itself: points of one frame
    /// share them exactly.
    pub fn linear_enclosure(&self, x: Interval, y: Interval) -> [Interval; 4] {
        let [ox, oy, vx, vy, m] = self.iv;
        [ox + m * x, vx, oy + m * y, vy]
    }

    /// [`Frame::linear_enclosure`] of a vertex of the body polygon given by
    /// its coordinates as the input doubles `(x, y)` (exactly `2^exp` times
    /// its integer coordinates, so that the grid scale's product is not
    /// needed): one rounded sum per coordinate.
    pub fn linear_enclosure_of_vertex(&self, [x, y]: [f64; 2]) -> [Interval; 4] {
        let [ox, oy, vx, vy, _] = self.iv;
        [ox + Interval::point(x), vx, oy + Interval::point(y), vy]
    }

    /// The position at a time in `t` of the body polygon vertex given by its
    /// input doubles `(x, y)` (as in [`Frame::linear_enclosure_of_vertex`]),
    /// in midpoint–radius form, from the frame's own midpoint–radius terms:
    /// no interval sum per vertex. `None` if a value is not finite.
    ///
    /// Per coordinate the position is `o + x + v·T` with `o` within `ro` of
    /// `mo`, `v` within `rv` of `mv` and `T` within `ht` of `tm`; the
    /// midpoint `fl(fl(mo + x) + fl(mv·tm))` is within
    /// `ro + rv·tmax + |mv|·ht` of it plus its three roundings, at most
    /// `3ε(|mo + x| + |mv·tm|)`; the radius's own rounding is covered by a
    /// factor `1 + 16ε` on its non-negative terms and `TINY` for underflow
    /// (as in [`crate::geom::MidRad::at`]).
    #[inline]
    pub fn mid_rad_of_vertex(
        &self,
        [x, y]: [f64; 2],
        t: crate::geom::TimeMidRad,
    ) -> Option<crate::geom::MidRad> {
        use crate::geom::{Mr, EPS, TINY};
        let coord = |[Mr { m: mo, r: ro }, Mr { m: mv, r: rv }]: [Mr; 2], c: f64| {
            let s1 = mo + c;
            let s2 = mv * t.tm;
            let r = ro + rv * t.tmax + mv.abs() * t.ht + 3.0 * EPS * (s1.abs() + s2.abs());
            (s1 + s2, r)
        };
        let (px, rx) = coord(self.mr[0], x);
        let (py, ry) = coord(self.mr[1], y);
        let r = rx.max(ry) * (1.0 + 16.0 * EPS) + TINY;
        (px.is_finite() && py.is_finite() && r.is_finite()).then_some(crate::geom::MidRad {
            x: px,
            y: py,
            r,
        })
    }

    /// The origin and velocity `[ox, oy, vx, vy]` as doubles: the
    /// midpoints of this frame's enclosures of them, within a few units in
    /// the last place (NaN where an enclosure is not finite). For box
    /// filters widened by far more than that, never for decisions.
    pub fn motion_f64(&self) -> [f64; 4] {
        let [[ox, vx], [oy, vy]] = self.mr;
        [ox.m, oy.m, vx.m, vy.m]
    }

    /// The linear position `(x0 + x1·t, y0 + y1·t)` of the body polygon
    /// vertex given by its input doubles `(x, y)` in midpoint–radius form
    /// `[x0, x1, y0, y1]`: [`Frame::linear_enclosure_of_vertex`] without
    /// interval sums (`None` where a value is not finite).
    #[inline]
    pub fn linear_mr_of_vertex(&self, [x, y]: [f64; 2]) -> Option<[crate::geom::Mr; 4]> {
        use crate::geom::Mr;
        let [[ox, x1], [oy, y1]] = self.mr;
        // (a velocity that is exactly zero stays the exact zero)
        let (x0, y0) = (ox + Mr::point(x), oy + Mr::point(y));
        [x0, x1, y0, y1]
            .iter()
            .all(|v| v.m.is_finite() && v.r.is_finite())
            .then_some([x0, x1, y0, y1])
    }

    /// The enclosures `[x1, y1]` of the velocity, the terms of every
    /// [`Frame::linear_enclosure`] of this frame that do not depend on the
    /// point.
    pub fn velocity_enclosure(&self) -> [Interval; 2] {
        [self.iv[2], self.iv[3]]
    }

    /// The moving world position of body vertex `i`.
    pub fn vertex(&self, body: &BodyPolygon, i: usize) -> LinearPoint {
        let (x, y) = body.int_vertex(i);
        LinearPoint {
            x0: &self.ox + &self.m * x,
            x1: self.vx.clone(),
            y0: &self.oy + &self.m * y,
            y1: self.vy.clone(),
            w: self.w.clone(),
        }
    }

    /// The moving world position of the body-frame point `(x/w, y/w)` given
    /// in homogeneous integer coordinates (`w > 0`) on the grid of the body
    /// polygon this frame was built for (units `2^exp`, `exp` its
    /// [`BodyPolygon::exp`]), such as an approximation vertex of the
    /// hierarchy. For `(X_i, Y_i, 1)` this is exactly [`Frame::vertex`]`(body, i)`;
    /// otherwise numerators and denominator are multiplied by `w`.
    pub fn homogeneous(&self, x: &Int, y: &Int, w: &Int) -> LinearPoint {
        debug_assert!(*w > Int::ZERO, "homogeneous weight must be positive");
        if w.is_one() {
            return LinearPoint {
                x0: &self.ox + &self.m * x,
                x1: self.vx.clone(),
                y0: &self.oy + &self.m * y,
                y1: self.vy.clone(),
                w: self.w.clone(),
            };
        }
        LinearPoint {
            x0: &self.ox * w + &self.m * x,
            x1: &self.vx * w,
            y0: &self.oy * w + &self.m * y,
            y1: &self.vy * w,
            w: &self.w * w,
        }
    }
}

/// A point moving linearly: `((x0 + x1·t)/w, (y0 + y1·t)/w)`, integers, `w > 0`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LinearPoint {
    /// x numerator, constant term.
    pub x0: Int,
    /// x numerator, coefficient of t.
    pub x1: Int,
    /// y numerator, constant term.
    pub y0: Int,
    /// y numerator, coefficient of t.
    pub y1: Int,
    /// Common positive denominator.
    pub w: Int,
}

impl LinearPoint {
    /// The exact position at a rational time.
    pub fn at(&self, t: &Rational) -> Point {
        let x = Rational::new(
            &self.x0 * t.denom() + &self.x1 * t.numer(),
            &self.w * t.denom(),
        );
        let y = Rational::new(
            &self.y0 * t.denom() + &self.y1 * t.numer(),
            &self.w * t.denom(),
        );
        Point { x, y }
    }

    /// The position at time `t`, each coordinate rounded to the nearest
    /// double ([`Point::to_f64`] of [`LinearPoint::at`], without its
    /// reductions).
    pub fn at_to_f64(&self, t: &Rational) -> [f64; 2] {
        let den = &self.w * t.denom();
        [
            Rational::quotient_to_f64(&self.x0 * t.denom() + &self.x1 * t.numer(), den.clone()),
            Rational::quotient_to_f64(&self.y0 * t.denom() + &self.y1 * t.numer(), den),
        ]
    }

    /// Approximate position at time `t` (display only).
    pub fn at_f64(&self, t: f64) -> [f64; 2] {
        let w = self.w.to_f64().value();
        [
            (self.x0.to_f64().value() + self.x1.to_f64().value() * t) / w,
            (self.y0.to_f64().value() + self.y1.to_f64().value() * t) / w,
        ]
    }
}

/// `q − p` as a linear vector, scaled by the positive `p.w · q.w` (or not at
/// all when the denominators agree).
fn diff(p: &LinearPoint, q: &LinearPoint) -> [Int; 4] {
    if p.w == q.w {
        [&q.x0 - &p.x0, &q.x1 - &p.x1, &q.y0 - &p.y0, &q.y1 - &p.y1]
    } else {
        [
            &q.x0 * &p.w - &p.x0 * &q.w,
            &q.x1 * &p.w - &p.x1 * &q.w,
            &q.y0 * &p.w - &p.y0 * &q.w,
            &q.y1 * &p.w - &p.y1 * &q.w,
        ]
    }
}

/// The certificate function `orient(p(t), q(t), r(t)) = (q − p) × (r − p)`,
/// scaled by a positive factor: positive while `r` is left of `p → q`.
/// Degree 2 in general; degree <= 1 when two of the points move together.
pub fn orient_poly(p: &LinearPoint, q: &LinearPoint, r: &LinearPoint) -> Poly {
    let [ux0, ux1, uy0, uy1] = diff(p, q);
    let [vx0, vx1, vy0, vy1] = diff(p, r);
    let c0 = &ux0 * &vy0 - &uy0 * &vx0;
    // `q` and `r` move alike (two points of one body, over one
    // denominator): `u` and `v` have the same velocity part `w`, so the
    // quadratic term is zero and the linear one is `(u − v) × w`, the same
    // integers as the general sums below with two products instead of six
    if q.w == r.w && q.x1 == r.x1 && q.y1 == r.y1 {
        debug_assert!(ux1 == vx1 && uy1 == vy1);
        let c1 = (&ux0 - &vx0) * &uy1 - (&uy0 - &vy0) * &ux1;
        debug_assert_eq!(c1, &ux0 * &vy1 + &ux1 * &vy0 - &uy0 * &vx1 - &uy1 * &vx0);
        return Poly::new(c0, c1, Int::ZERO);
    }
    let c1 = &ux0 * &vy1 + &ux1 * &vy0 - &uy0 * &vx1 - &uy1 * &vx0;
    let c2 = &ux1 * &vy1 - &uy1 * &vx1;
    Poly::new(c0, c1, c2)
}

/// `(q − p) · (r − p)` as a polynomial in time, scaled by a positive factor:
/// with [`orient_poly`] it locates `r` relative to `p` and `q` (positive when
/// `r` is on the same side of `p` as `q`).
pub fn dot_poly(p: &LinearPoint, q: &LinearPoint, r: &LinearPoint) -> Poly {
    let [ux0, ux1, uy0, uy1] = diff(p, q);
    let [vx0, vx1, vy0, vy1] = diff(p, r);
    let c0 = &ux0 * &vx0 + &uy0 * &vy0;
    let c1 = &ux0 * &vx1 + &ux1 * &vx0 + &uy0 * &vy1 + &uy1 * &vy0;
    let c2 = &ux1 * &vx1 + &uy1 * &vy1;
    Poly::new(c0, c1, c2)
}

/// Which of three collinear points lies between the other two at time `t`
/// (index 0, 1 or 2), decided exactly; `None` if two of them coincide.
pub fn middle_of_collinear(pts: [&LinearPoint; 3], t: &crate::num::Time) -> Option<usize> {
    use crate::num::Sign;
    for m in 0..3 {
        let (a, b) = (pts[(m + 1) % 3], pts[(m + 2) % 3]);
        // m is strictly between a and b iff (a − m)·(b − m) < 0
        if dot_poly(pts[m], a, b).sign_at(t) == Sign::Negative {
            return Some(m);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::orient;
    use crate::num::{Sign, Time};

    fn r(x: f64) -> Rational {
        Rational::from_f64(x).unwrap()
    }

    fn pt(x: f64, y: f64) -> Point {
        Point::from_f64([x, y]).unwrap()
    }

    /// A triangle of size about `scale` around the origin of its frame.
    fn scaled_triangle(scale: f64) -> BodyPolygon {
        BodyPolygon::new(&[
            [-0.3 * scale, -0.1 * scale],
            [0.7 * scale, 0.05 * scale],
            [0.1 * scale, 0.9 * scale],
        ])
        .unwrap()
    }

    /// The enclosure of a vertex from its input doubles holds the exact
    /// linear position, for frames through non-dyadic instants (large
    /// denominators) and polygons of several scales.
    #[test]
    fn vertex_enclosures_from_the_input_doubles_hold_the_exact_position() {
        let within = |iv: Interval, num: &Int, w: &Int| {
            let x = Rational::new(num.clone(), w.clone());
            r(iv.lo) <= x && x <= r(iv.hi)
        };
        for scale in [1.0, 3.0e-7, 1.5e9] {
            let poly = scaled_triangle(scale);
            let t = Rational::new(Int::from(7), Int::from(3));
            for (p, v) in [
                (pt(0.25, -1.5), pt(1.0 / 3.0, 0.2)),
                (pt(1e6, 3.0), pt(-0.1, 1e-9)),
            ] {
                let traj = Trajectory::through(&t, &p, v);
                let frame = Frame::new(&traj, &poly);
                for (i, &xy) in poly.f64_vertices().iter().enumerate() {
                    let e = frame.linear_enclosure_of_vertex(xy);
                    let lp = frame.vertex(&poly, i);
                    assert!(within(e[0], &lp.x0, &lp.w), "x0 of {i} at scale {scale}");
                    assert!(within(e[1], &lp.x1, &lp.w), "x1 of {i}");
                    assert!(within(e[2], &lp.y0, &lp.w), "y0 of {i}");
                    assert!(within(e[3], &lp.y1, &lp.w), "y1 of {i}");
                }
            }
        }
    }

    /// A trajectory is no larger than its origin and velocity (every body
    /// holds one; a bridge's integers are boxed).
    #[test]
    fn a_trajectory_is_the_size_of_its_origin_and_velocity() {
        assert_eq!(
            std::mem::size_of::<Trajectory>(),
            std::mem::size_of::<[Point; 2]>()
        );
    }

    /// A frame made over a common denominator that is not the least one
    /// ([`Frame::over`], a bridge's) moves the polygon as the frame of the
    /// trajectory does: the same exact vertex positions at an instant, the
    /// same motion ([`Frame::same_motion`]), enclosures that hold them; a
    /// frame of another trajectory is not the same motion.
    #[test]
    fn frames_over_an_unreduced_denominator_move_alike() {
        let t = Rational::new(Int::from(7), Int::from(3));
        let at = Rational::new(Int::from(-11), Int::from(5));
        for scale in [1.0, 3.0e-7, 1.5e9] {
            let poly = scaled_triangle(scale);
            for (p, v) in [
                (pt(0.25, -1.5), pt(1.0 / 3.0, 0.2)),
                (pt(1e6, 3.0), pt(-0.1, 0.0)),
            ] {
                let traj = Trajectory::through(&t, &p, v);
                let reduced = Frame::new(&traj, &poly);
                // origin and velocity over 6·(the least common multiple)
                let o = traj.origin();
                let vel = traj.velocity();
                let dens = [o.x.denom(), o.y.denom(), vel.x.denom(), vel.y.denom()];
                let w = dens[1..]
                    .iter()
                    .fold(dens[0].clone(), |w, d| crate::num::lcm(&w, d))
                    * Int::from(6);
                let num = |r: &Rational| r.numer() * (&w / r.denom());
                let frame = Frame::over(
                    [num(&o.x), num(&o.y)],
                    [num(&vel.x), num(&vel.y)],
                    w.clone(),
                    &poly,
                );
                assert!(frame.same_motion(&reduced) && reduced.same_motion(&frame));
                assert_ne!(frame.uid(), reduced.uid());
                for (i, &xy) in poly.f64_vertices().iter().enumerate() {
                    let (a, b) = (frame.vertex(&poly, i), reduced.vertex(&poly, i));
                    let place = |l: &LinearPoint| {
                        let q = |x0: &Int, x1: &Int| {
                            Rational::new(x0.clone(), l.w.clone())
                                .add(&Rational::new(x1.clone(), l.w.clone()).mul(&at))
                        };
                        (q(&l.x0, &l.x1), q(&l.y0, &l.y1))
                    };
                    assert_eq!(place(&a), place(&b), "vertex {i} at scale {scale}");
                    let e = frame.linear_enclosure_of_vertex(xy);
                    let within = |iv: Interval, num: &Int| {
                        let x = Rational::new(num.clone(), a.w.clone());
                        r(iv.lo) <= x && x <= r(iv.hi)
                    };
                    assert!(within(e[0], &a.x0) && within(e[1], &a.x1));
                    assert!(within(e[2], &a.y0) && within(e[3], &a.y1));
                }
                let other = Frame::new(&Trajectory::through(&t, &p, pt(0.5, 0.5)), &poly);
                assert!(!frame.same_motion(&other));
            }
        }
    }

    /// A frame's origin and velocity as doubles are within a few units in
    /// the last place of the exact values, for frames through non-dyadic
    /// instants (large denominators) and polygons of several scales; an
    /// exact zero velocity stays zero.
    #[test]
    fn frame_motion_f64_is_within_a_few_ulps() {
        let t = Rational::new(Int::from(7), Int::from(3));
        for scale in [1.0, 3.0e-7, 1.5e9] {
            let poly = scaled_triangle(scale);
            for (p, v) in [
                (pt(0.25, -1.5), pt(1.0 / 3.0, 0.2)),
                (pt(1e6, 3.0), pt(-0.1, 1e-9)),
                (pt(-2.5, 1e-3), pt(0.0, 0.0)),
            ] {
                let traj = Trajectory::through(&t, &p, v);
                let got = Frame::new(&traj, &poly).motion_f64();
                let want = [
                    traj.origin().x.to_f64(),
                    traj.origin().y.to_f64(),
                    traj.velocity().x.to_f64(),
                    traj.velocity().y.to_f64(),
                ];
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() <= 8.0 * f64::EPSILON * w.abs(),
                        "{got:?} against {want:?} at scale {scale}"
                    );
                }
            }
        }
    }

    /// The midpoint–radius position of a vertex from its input doubles
    /// holds the exact position at both ends and the middle of the
    /// enclosure of an instant with a large denominator (so that the
    /// enclosure is not a point), for frames through non-dyadic instants
    /// and polygons of several scales, slow and fast.
    #[test]
    fn vertex_mid_rad_holds_the_exact_position() {
        let mut checked = 0;
        for scale in [1.0, 3.0e-7, 1.5e9, 1e-300, 1e250] {
            let poly = scaled_triangle(scale);
            let t0 = Rational::new(Int::from(7), Int::from(3));
            for (p, v) in [
                (pt(0.25, -1.5), pt(1.0 / 3.0, 0.2)),
                (pt(1e6, 3.0), pt(-0.1, 1e-9)),
                (pt(-2e-200, 5e-310), pt(3e40, -7.0)),
            ] {
                let traj = Trajectory::through(&t0, &p, v);
                let frame = Frame::new(&traj, &poly);
                for at in [
                    Rational::new(Int::from(10), Int::from(7)),
                    Rational::new(Int::from(-1_000_001), Int::from(3)),
                    Rational::new(Int::from(1), Int::from(3) << 200),
                ] {
                    let tiv = at.interval();
                    let tmr = crate::geom::TimeMidRad::of(tiv);
                    // instants within the enclosure: its ends and `at`
                    let instants = [r(tiv.lo), r(tiv.hi), at.clone()];
                    for (i, &xy) in poly.f64_vertices().iter().enumerate() {
                        let Some(m) = frame.mid_rad_of_vertex(xy, tmr) else {
                            continue;
                        };
                        let lp = frame.vertex(&poly, i);
                        checked += 1;
                        for t in &instants {
                            let q = lp.at(t);
                            let (dx, dy) = (q.x.sub(&r(m.x)), q.y.sub(&r(m.y)));
                            let rad = r(m.r);
                            for d in [dx, dy] {
                                assert!(
                                    d <= rad && d.neg() <= rad,
                                    "vertex {i} at scale {scale}, {p:?}: {m:?} misses {q:?} at {t:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
        assert!(checked >= 60, "only {checked} positions were finite");
    }

    #[test]
    fn frame_vertices_and_orientation() {
        let tri = BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.5]]).unwrap();
        let a = Trajectory::through(&r(0.0), &pt(0.0, 0.0), pt(0.0, 0.0));
        let b = Trajectory::through(&r(1.0), &pt(3.0, 0.25), pt(-1.0, 0.0));
        let fa = Frame::new(&a, &tri);
        let fb = Frame::new(&b, &tri);
        // vertex 0 of b at time 1 is (3, 0.25)
        assert_eq!(fb.vertex(&tri, 0).at(&r(1.0)), pt(3.0, 0.25));
        assert_eq!(fb.vertex(&tri, 1).at(&r(2.0)), pt(3.0, 0.25));
        // b's vertex 0 crosses the line of a's edge 1→2 (x + 2y = 1) when
        // 4 − t + 0.5 = 1, i.e. t = 3.5
        let p = fa.vertex(&tri, 1);
        let q = fa.vertex(&tri, 2);
        let v = fb.vertex(&tri, 0);
        let cert = orient_poly(&p, &q, &v);
        assert_eq!(cert.degree(), Some(1));
        assert_eq!(cert.roots(), vec![Time::from_f64(3.5).unwrap()]);
        assert_eq!(cert.sign_at(&Time::zero()), Sign::Negative);
        // agrees with the static predicate
        let t = r(1.25);
        assert_eq!(
            cert.sign_at(&Time::from_rational(t.clone())),
            orient(&p.at(&t), &q.at(&t), &v.at(&t))
        );
    }

    #[test]
    fn middle_point_at_an_irrational_instant() {
        let tri = BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        let t0 = r(0.0);
        let fa = Frame::new(&Trajectory::through(&t0, &pt(0.0, 0.0), pt(1.0, 0.0)), &tri);
        let fb = Frame::new(&Trajectory::through(&t0, &pt(5.0, 0.0), pt(0.0, 1.0)), &tri);
        let fc = Frame::new(&Trajectory::through(&t0, &pt(0.0, 3.0), pt(2.0, 0.0)), &tri);
        let (a, b, c) = (fa.vertex(&tri, 0), fb.vertex(&tri, 0), fc.vertex(&tri, 0));
        let cert = orient_poly(&a, &b, &c);
        assert_eq!(cert.roots().len(), 2);
        assert!(
            cert.roots()[0].as_rational().is_none(),
            "an irrational instant"
        );
        for root in cert.roots() {
            let m = middle_of_collinear([&a, &b, &c], &root).expect("distinct points");
            // the middle point is inside the segment of the other two
            let (p, q) = ([&a, &b, &c][(m + 1) % 3], [&a, &b, &c][(m + 2) % 3]);
            assert_eq!(
                dot_poly([&a, &b, &c][m], p, q).sign_at(&root),
                Sign::Negative
            );
        }
    }

    #[test]
    fn three_bodies_quadratic() {
        let tri = BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        let t0 = r(0.0);
        let fa = Frame::new(&Trajectory::through(&t0, &pt(0.0, 0.0), pt(1.0, 0.0)), &tri);
        let fb = Frame::new(&Trajectory::through(&t0, &pt(5.0, 0.0), pt(0.0, 1.0)), &tri);
        let fc = Frame::new(
            &Trajectory::through(&t0, &pt(0.0, 5.0), pt(0.1, -0.5)),
            &tri,
        );
        let c = orient_poly(
            &fa.vertex(&tri, 0),
            &fb.vertex(&tri, 0),
            &fc.vertex(&tri, 0),
        );
        assert_eq!(c.degree(), Some(2));
        for root in c.roots() {
            assert_eq!(c.sign_at(&root), Sign::Zero);
        }
    }
}
