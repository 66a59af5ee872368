//! Classifying a certificate failure: which point of the collinear triple is
//! in the middle, and whether that is a collision.
//!
//! A collision is reported exactly when a vertex of one body lies in the
//! closed polygon edge of another (or two vertices of different bodies
//! coincide). Every other failure is a change of the structure: a vertex
//! meeting a bridge, or a junction turning straight.

use super::certs::Cert;
use super::faces::poly_edge;
use super::geo::Geo;
use super::{Att, Obj};
use crate::geom::MidRad;
use crate::motion::{middle_of_collinear, LinearPoint};
use crate::num::Time;
use crate::world::BodyId;

/// What a failing certificate means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// Bodies `a` and `b` touch.
    Contact {
        /// One body.
        a: BodyId,
        /// The other.
        b: BodyId,
        /// A third body whose vertex coincides with both (three polygons
        /// meeting at one point).
        third: Option<BodyId>,
    },
    /// `middle` lies strictly between `ends`, which are not a polygon edge of
    /// another body (a vertex meeting a bridge, or a straight junction).
    Between {
        /// The middle point.
        middle: Att,
        /// The two outer points.
        ends: (Att, Att),
    },
}

fn point(world: &Geo, a: Att) -> LinearPoint {
    match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("certificates have finite points"),
    }
}

fn body(a: Att) -> BodyId {
    match a.obj {
        Obj::Body(b) => b,
        Obj::Omega => unreachable!("certificates have finite points"),
    }
}

/// Classify certificate `c`, whose three points are collinear at time `t`.
pub fn classify(world: &Geo, c: &Cert, t: &Time) -> Failure {
    // which point is strictly between the other two: (a − m)·(b − m) < 0,
    // from the filter where it decides (at most one point can be), exactly
    // otherwise
    // (the three points placed once for the midpoint–radius filter, the
    // interval filter only where it does not decide)
    let tiv = t.interval();
    let mids = c.p.map(|a| world.mid_rad(a, tiv));
    let filtered: [Option<crate::num::Sign>; 3] = std::array::from_fn(|m| {
        let (u, v, w) = (m, (m + 1) % 3, (m + 2) % 3);
        if let (Some(mu), Some(mv), Some(mw)) = (mids[u], mids[v], mids[w]) {
            if let Some(s) = crate::geom::dot_mid_rad(mu, mv, mw) {
                return Some(s);
            }
        }
        world.dot_filtered(c.p[v], c.p[u], c.p[w], tiv)
    });
    let middle = match filtered
        .iter()
        .position(|&s| s == Some(crate::num::Sign::Negative))
    {
        Some(m) => Some(m),
        None => {
            let pts = c.p.map(|a| point(world, a));
            middle_of_collinear([&pts[0], &pts[1], &pts[2]], t)
        }
    };
    match middle {
        None => {
            // two of the points coincide: vertices of two different bodies
            let coincide = |i: usize, j: usize| {
                c.p[i].obj != c.p[j].obj
                    && t.as_rational().is_none_or(|r| {
                        let pos = |a: Att| {
                            super::build::position(world, a, r)
                                .expect("a vertex, not ω, has a position")
                        };
                        pos(c.p[i]) == pos(c.p[j])
                    })
            };
            let found: Vec<(usize, usize)> = [(0, 1), (1, 2), (0, 2)]
                .into_iter()
                .filter(|&(i, j)| coincide(i, j))
                .collect();
            let (x, y) = found
                .first()
                .map(|&(i, j)| (c.p[i], c.p[j]))
                .unwrap_or((c.p[0], c.p[1]));
            let third = (found.len() == 3).then(|| body(c.p[2]));
            Failure::Contact {
                a: body(x),
                b: body(y),
                third,
            }
        }
        Some(m) => {
            let (middle, x, y) = (c.p[m], c.p[(m + 1) % 3], c.p[(m + 2) % 3]);
            if poly_edge(world, x, y) && middle.obj != x.obj {
                Failure::Contact {
                    a: body(middle),
                    b: body(x),
                    third: None,
                }
            } else {
                Failure::Between {
                    middle,
                    ends: (x, y),
                }
            }
        }
    }
}

/// The structural reading of a failure that [`classify`] calls a contact,
/// for a pair whose collision response at this instant already separates it
/// (or lets it slide): when a vertex `y` of one body coincides with a vertex
/// `x` of another and the third point `z` is on `x`'s body, `x` is the middle
/// (the bridge or junction through `z` and `y` reaches `x`'s polygon at
/// `x`). `None` when no such reading exists (three bodies meet, or the
/// touch is inside an edge).
pub fn settled_between(world: &Geo, c: &Cert, t: &Time) -> Option<Failure> {
    let r = t.as_rational()?;
    let pos =
        |a: Att| super::build::position(world, a, r).expect("a vertex, not ω, has a position");
    for (i, j, k) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
        let (p, q, z) = (c.p[i], c.p[j], c.p[k]);
        if p.obj == q.obj || pos(p) != pos(q) {
            continue;
        }
        let (x, y) = if z.obj == p.obj {
            (p, q)
        } else if z.obj == q.obj {
            (q, p)
        } else {
            // a partition triangle with corners on three bodies, two of
            // which coincide: the one that slides into the other's polygon
            // edge just after `t` stays a corner, the other (`x`) is the
            // middle (it has passed the side between the other two)
            let on_edge = |u: Att, w: Att| slides_on_edge(world, u, w, t);
            return match (on_edge(p, q), on_edge(q, p)) {
                (true, false) => Some(Failure::Between {
                    middle: q,
                    ends: (p, z),
                }),
                (false, true) => Some(Failure::Between {
                    middle: p,
                    ends: (q, z),
                }),
                _ => None,
            };
        };
        return Some(Failure::Between {
            middle: x,
            ends: (y, z),
        });
    }
    None
}

/// Whether vertex `u` lies strictly inside a polygon edge at vertex `w`
/// (of another body) just after `t`, and stays on that edge's line.
fn slides_on_edge(world: &Geo, u: Att, w: Att, t: &Time) -> bool {
    use super::local::between_after;
    let lp = |a: Att| point(world, a);
    [
        super::faces::step_ccw(world, w),
        super::faces::step_cw(world, w, 1),
    ]
    .into_iter()
    .any(|w1| {
        crate::motion::orient_poly(&lp(w), &lp(w1), &lp(u)).sign_after(t) == crate::num::Sign::Zero
            && between_after(world, w, u, w1, t)
    })
}

/// Whether every point within the radii of `a`'s points is strictly on
/// one side of every point within the radii of `b`'s, along `x` or along
/// `y` (the boxes of the two sets are apart): the box sides `m ± r` and
/// their difference are computed in f64, each rounding at most `ε`
/// relatively, so the gap must exceed `4ε` times the sides' magnitudes
/// (and `TINY` for underflow).
fn boxes_apart(a: [MidRad; 3], b: [MidRad; 3]) -> bool {
    use crate::geom::{EPS, TINY};
    let side = |s: [MidRad; 3], c: fn(&MidRad) -> f64| {
        let lo = s.iter().map(|m| c(m) - m.r).fold(f64::INFINITY, f64::min);
        let hi = s
            .iter()
            .map(|m| c(m) + m.r)
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let below = |hi: f64, lo: f64| {
        let gap = lo - hi;
        gap.is_finite() && gap > 4.0 * EPS * (hi.abs() + lo.abs()) + TINY
    };
    [|m: &MidRad| m.x, |m: &MidRad| m.y].into_iter().any(|c| {
        let ((alo, ahi), (blo, bhi)) = (side(a, c), side(b, c));
        below(ahi, blo) || below(bhi, alo)
    })
}

/// For a failure of a vertex against the line of another body's polygon
/// edge that is not itself a contact (the vertex is beyond an end of the
/// edge), whether the two bodies nevertheless touch at `t` right there: a
/// vertex of one in a closed edge of the other among the edges and vertices
/// next to the failing triple. This catches flush edge-against-edge contacts,
/// where every vertex reaches the other's line at once and the structure's
/// certificates may all report "beyond the end". `None` whenever an exact
/// sign is needed at an irrational `t` (such certificates are linear, their
/// failures rational).
pub fn nearby_contact(world: &Geo, p: &[Att; 3], t: &Time) -> Option<(BodyId, BodyId)> {
    let tiv = t.interval();
    // the vertex z of one body and an edge endpoint x of the other
    let (z, x) = (0..3).find_map(|i| {
        let (x, y, z) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        (x.obj == y.obj && z.obj != x.obj && poly_edge(world, x, y)).then_some((z, x))
    })?;
    let near = |a: Att| [world.cw(a, 1), a, world.ccw(a)];
    // (the six points placed once for the midpoint–radius filter of the
    // twelve turns below, which `Geo::orient_filtered` would place again
    // for each)
    let pts: [Att; 6] = {
        let (nz, nx) = (near(z), near(x));
        [nz[0], nz[1], nz[2], nx[0], nx[1], nx[2]]
    };
    let mids = pts.map(|a| world.mid_rad(a, tiv));
    let mid = |a: Att| pts.iter().position(|&q| q == a).and_then(|i| mids[i]);
    // exact signs at `t` from the moving points' integer polynomials (no
    // rational positions: no gcd); `None` where they are needed at an
    // irrational `t` (the rationality of a deferred event time is asked
    // only there: it computes the time)
    let touches = |u: Att, e0: Att, e1: Att| -> Option<bool> {
        if let (Some(m0), Some(m1), Some(mu)) = (mid(e0), mid(e1), mid(u)) {
            if crate::geom::orient_mid_rad(m0, m1, mu).is_some() {
                super::counters::bump(super::counters::Counter::TurnsFiltered);
                return Some(false);
            }
            // (u beyond an end of the edge, the usual case for the failing
            // triple itself, whose turn is zero at `t`: its dot product on
            // the same placed points, before the turn's interval filter)
            if crate::geom::dot_mid_rad(mu, m0, m1) == Some(crate::num::Sign::Positive) {
                return Some(false);
            }
        }
        if world.orient_filtered(e0, e1, u, tiv).is_some() {
            return Some(false);
        }
        // (e0 − u)·(e1 − u) > 0: u is beyond an end of the edge (the usual
        // case here), decided without the exact turn
        if world.dot_filtered(e0, u, e1, tiv) == Some(crate::num::Sign::Positive) {
            return Some(false);
        }
        t.as_rational()?;
        let (pu, p0, p1) = (world.point(u), world.point(e0), world.point(e1));
        Some(
            crate::motion::orient_poly(&p0, &p1, &pu).sign_at(t) == crate::num::Sign::Zero
                && crate::motion::dot_poly(&pu, &p0, &p1).sign_at(t) != crate::num::Sign::Positive,
        )
    };
    let search = || {
        for (a, b) in [(z, x), (x, z)] {
            let nb = near(b);
            for u in near(a) {
                for e in [(nb[0], nb[1]), (nb[1], nb[2])] {
                    if touches(u, e.0, e.1)? {
                        return Some((body(a), body(b)));
                    }
                }
            }
        }
        None
    };
    // (every edge above joins two of one body's three points, and every
    // vertex tested is one of the other body's three: where the boxes of
    // the two triples are apart, no vertex is in an edge)
    if let [Some(a0), Some(a1), Some(a2), Some(b0), Some(b1), Some(b2)] = mids {
        if boxes_apart([a0, a1, a2], [b0, b1, b2]) {
            debug_assert_eq!(search(), None, "a contact between boxes apart");
            return None;
        }
    }
    search()
}

/// For a triple whose vertex `w` lies at time `t` strictly inside an
/// approximation edge `(x, y)` of another body, the pair of bodies if their
/// polygons certainly do not touch there, decided in O(1) without the
/// pair's contact test: the edge's line `L` supports both approximations,
/// so the polygons can only meet on `L`; if `w`'s neighbours are off `L`,
/// `w` is the only point of its approximation on it, and the polygons touch
/// only if `w` is a real vertex lying on the real part of the edge (the
/// base segment of the edge's entry in the hierarchy). `None` when this
/// cannot be decided so (no approximation, an irrational instant, two
/// vertices meeting, or approximations sliding along `L`). `zero` says that
/// the turn of `p` is known to be zero at `t` (a certificate on `p` whose
/// failure time `t` is a root of its function).
pub fn real_touch_excluded(
    world: &Geo,
    p: &[Att; 3],
    t: &Time,
    zero: bool,
) -> Option<(BodyId, BodyId)> {
    // only between two approximations, and only where the three points are
    // collinear at `t` (the filter rules that out cheaply)
    let approximated = |a: Att| matches!(a.obj, Obj::Body(b) if world.shapes.approx(b).is_some());
    let tiv = t.interval();
    if !p.iter().all(|&a| approximated(a)) || world.orient_filtered(p[0], p[1], p[2], tiv).is_some()
    {
        return None;
    }
    // exact signs at `t` from the moving points' integer polynomials (no
    // rational positions: no gcd)
    use crate::motion::{dot_poly, orient_poly};
    use crate::num::Sign;
    // (rational without computing it where the triple's failure time
    // says so: its exact value is then computed only where a filter
    // below cannot decide)
    if !t.known_rational() {
        t.as_rational()?;
    }
    debug_assert!(t.as_rational().is_some(), "a time known rational is not");
    // (the exact moving points, made only where a filter below does not
    // decide)
    let exact = std::cell::OnceCell::new();
    let pts = || exact.get_or_init(|| p.map(|a| world.point(a)));
    let turn_zero = || {
        let pts = pts();
        orient_poly(&pts[0], &pts[1], &pts[2]).sign_at(t) == Sign::Zero
    };
    debug_assert!(!zero || turn_zero(), "the turn of {p:?} is not zero");
    if !zero && !turn_zero() {
        return None;
    }
    // (a − m)·(b − m) < 0 (the f64 filter first: a sign it decides is
    // the one at every time in `t`'s enclosure)
    let strictly_between = |m: usize, a: usize, b: usize| {
        let s = world
            .dot_filtered(p[a], p[m], p[b], tiv)
            .unwrap_or_else(|| {
                let pts = pts();
                dot_poly(&pts[m], &pts[a], &pts[b]).sign_at(t)
            });
        s == Sign::Negative
    };
    let m = (0..3).find(|&m| strictly_between(m, (m + 1) % 3, (m + 2) % 3))?;
    let (w, x, y) = (p[m], p[(m + 1) % 3], p[(m + 2) % 3]);
    if w.obj == x.obj || x.obj != y.obj {
        return None;
    }
    // the edge runs counter-clockwise from `x` to `y` (or the other way)
    // and lies on the line of `x`'s entry
    let x = if world.ccw(x) == y {
        x
    } else if world.ccw(y) == x {
        y
    } else {
        return None;
    };
    let (Obj::Body(u), Obj::Body(v)) = (w.obj, x.obj) else {
        return None;
    };
    let ap = world.shapes.approx(v)?;
    world.shapes.approx(u)?;
    // `w` alone on the line among its approximation's vertices (a turn the
    // filter decides is not zero)
    for nb in [world.ccw(w), world.cw(w, 1)] {
        let off = world
            .orient_filtered(p[(m + 1) % 3], p[(m + 2) % 3], nb, tiv)
            .is_some();
        if !off {
            let pts = pts();
            let (px, py) = (&pts[(m + 1) % 3], &pts[(m + 2) % 3]);
            if orient_poly(px, py, &world.point(nb)).sign_at(t) == Sign::Zero {
                return None;
            }
        }
    }
    let apart = Some((u, v));
    if !world.is_real(w) {
        return apart;
    }
    // the real part of the edge: entry `x`'s base segment, moved to `t`
    let body = world.body(v);
    let k = x.v as usize;
    let (i0, i1) = (
        ap.array.base_vertex_of_entry_start(k),
        ap.array.base_vertex_of_entry_end(k),
    );
    let (s0, s1) = (body.vertex(i0), body.vertex(i1));
    let wp = &pts()[m];
    // (w − a)·(b − a) < 0: w beyond a, away from b
    let outside = |a: &crate::motion::LinearPoint, b: &crate::motion::LinearPoint| {
        dot_poly(a, wp, b).sign_at(t) == Sign::Negative
    };
    // a degenerate segment (one base vertex): w must be that vertex
    let off_point = || dot_poly(&s0, wp, wp).sign_at(t) != Sign::Zero;
    if outside(&s0, &s1) || outside(&s1, &s0) || (i0 == i1 && off_point()) {
        return apart;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::Sign;
    use crate::scenario::{CollisionMode, PolygonSpec, Scenario};
    use crate::structure::certs::CertKind;
    use crate::structure::geo::Geo;
    use crate::world::World;

    fn square(id: &str, x: f64, y: f64, vx: f64) -> PolygonSpec {
        PolygonSpec {
            id: id.into(),
            vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            position: [x, y],
            velocity: [vx, 0.0],
            fixed: false,
        }
    }

    #[test]
    fn vertex_on_edge_and_vertex_on_vertex() {
        // b's vertex 0 at (3, 0.5) moves left onto a's edge 1 → 2 (x = 1)
        let s = Scenario {
            until: 10.0,
            on_collision: CollisionMode::Stop,
            polygons: vec![square("a", 0.0, 0.0, 0.0), square("b", 3.0, 0.5, -1.0)],
            flight_plan_changes: vec![],
            ..Default::default()
        };
        let w = World::new(&s, None).unwrap();
        let w = Geo::plain(&w);
        let (a, b) = (BodyId::new(0), BodyId::new(1));
        let cert = Cert {
            p: [Att::vertex(a, 1), Att::vertex(a, 2), Att::vertex(b, 0)],
            sign: Sign::Negative,
            kind: CertKind::Junction,
        };
        let t = Time::from_f64(2.0).unwrap();
        assert_eq!(
            classify(&w, &cert, &t),
            Failure::Contact {
                a: b,
                b: a,
                third: None
            }
        );
        // the other way round: a's vertex 2 at (1, 1) lies inside b's edge
        // 3 → 0 (x = 1, y from 1.5 to 0.5) at t = 2
        let cert2 = Cert {
            p: [Att::vertex(a, 2), Att::vertex(b, 3), Att::vertex(b, 0)],
            sign: Sign::Positive,
            kind: CertKind::Junction,
        };
        assert_eq!(
            classify(&w, &cert2, &t),
            Failure::Contact { a, b, third: None }
        );
    }

    #[test]
    fn boxes_apart_only_with_a_gap_beyond_the_radii() {
        let m = |x: f64, y: f64, r: f64| MidRad { x, y, r };
        let a = [m(0.0, 0.0, 0.1), m(1.0, 0.0, 0.1), m(1.0, 1.0, 0.1)];
        // apart along x, on either side, and along y
        assert!(boxes_apart(
            a,
            [m(1.3, 0.0, 0.1), m(2.0, 5.0, 0.0), m(3.0, -5.0, 0.0)]
        ));
        assert!(boxes_apart(
            [m(1.3, 0.0, 0.1), m(2.0, 5.0, 0.0), m(3.0, -5.0, 0.0)],
            a
        ));
        assert!(boxes_apart(
            a,
            [m(0.5, -0.3, 0.1), m(-4.0, -2.0, 0.0), m(9.0, -1.0, 0.0)]
        ));
        // boxes that touch or overlap, and a gap within the rounding
        assert!(!boxes_apart(
            a,
            [m(1.1, 0.0, 0.0), m(2.0, 0.0, 0.0), m(3.0, 0.0, 0.0)]
        ));
        assert!(!boxes_apart(
            a,
            [m(0.5, 0.5, 0.0), m(5.0, 5.0, 0.0), m(6.0, 6.0, 0.0)]
        ));
        let e = 1.1 + 1e-17;
        assert!(!boxes_apart(
            a,
            [m(e + 0.1, 0.0, 0.1), m(2.0, 0.0, 0.0), m(3.0, 0.0, 0.0)]
        ));
        // not finite: never apart
        let inf = [
            m(f64::INFINITY, 0.0, 0.0),
            m(0.0, 0.0, 0.0),
            m(0.0, 0.0, 0.0),
        ];
        assert!(!boxes_apart(a, inf));
    }
}
