//! Refining the hierarchy's outer approximations where they meet: at the
//! start (every pair of approximations must be disjoint before the
//! structure is built on them) and when two approximations touch during the
//! run where the polygons do not (the paper's pop events).
//!
//! Two convex approximations are apart when an edge line of one has the
//! whole other strictly outside. When they are not, the approximation
//! vertices of each that are not strictly outside the other are popped
//! (each pop replaces a vertex `av(i, k)` by `av(i, top(i, k))` and
//! `av(top(i, k), k)`, cutting off the corner), or, if there is none (two
//! approximations crossing like a star of David), every approximation
//! vertex whose edges are involved. Popping only ever shrinks an
//! approximation towards its polygon, and polygons that are apart are
//! separated after finitely many pops, so the loops end.

use std::sync::Arc;

use super::counters::{bump, Counter};
use super::faces::turn_after;
use super::geo::{Approx, Geo, Shapes};
use super::Att;
use crate::geom::{orient, MidRad};
use crate::hier::EdgeArray;
use crate::motion::dot_poly;
use crate::num::{Interval, Rational, Sign, Time};
use crate::structure::StructureError;
use crate::world::{Body, BodyId, World};

/// Every alive body with more than `above` vertices seen through the
/// coarsest approximation of its hierarchy (at most about 32 lines each);
/// the others as they are ([`coarsest_shape`]).
pub fn coarsest_shapes(world: &World, above: usize) -> Shapes {
    Shapes {
        per: world
            .bodies()
            .iter()
            .map(|b| coarsest_shape(b, above).map(Box::new))
            .collect(),
        mids: Default::default(),
        faces: Default::default(),
        points: Default::default(),
        links: Default::default(),
    }
}

/// The coarsest approximation of `b`'s hierarchy; `None` for a removed
/// body, and for a polygon of at most `above` vertices, which the structure
/// then sees as it is (as the plain structure does).
pub fn coarsest_shape(b: &Body, above: usize) -> Option<Approx> {
    (b.alive && b.shape.len() > above).then(|| {
        let array = Arc::new(EdgeArray::new(&b.shape));
        let exposed = array.coarsest();
        Approx::new(array, exposed)
    })
}

/// Pop vertex `a` of its body's approximation; whether it changed.
pub fn pop(shapes: &mut Shapes, a: Att) -> bool {
    let super::Obj::Body(b) = a.obj else {
        return false;
    };
    match shapes.per.get_mut(b.index()).and_then(Option::as_mut) {
        Some(ap) => ap.pop(a.v as usize).is_some(),
        None => false,
    }
}

/// Whether `w`, collinear with `u` and `v` just after `t`, lies on the
/// closed segment `uv` just after `t` (filtered, then exact).
fn on_segment_after(geo: &Geo, u: Att, v: Att, w: Att, t: &Time) -> bool {
    // (u − w)·(v − w) <= 0
    geo.dot_filtered(u, w, v, t.interval())
        .unwrap_or_else(|| dot_poly(&geo.point(w), &geo.point(u), &geo.point(v)).sign_after(t))
        != Sign::Positive
}

/// The approximation vertices to pop so that `a` and `b` come apart, or
/// `None` if they are apart already; `sign(u, v, w)` is the orientation
/// used (at an instant, or just after one).
///
/// With `on_segment` (whether `w`, collinear with `u` and `v`, lies on the
/// closed segment `uv`), the approximations may touch where the polygons
/// themselves slide along each other: a vertex on an edge's line counts as
/// outside unless it lies on the edge with one of the three points not
/// real. An approximation edge sliding along a real vertex of the other
/// polygon is not allowed to stand, even while the polygons are apart: a
/// real vertex of the polygon inside that edge would reach the sliding
/// vertex with no certificate to see it (gen_small grazing 422). The
/// approximation points among the edge's endpoints and the sliding vertex
/// are popped until they are real.
fn involved(
    geo: &Geo,
    (a, b): (BodyId, BodyId),
    at: Option<Interval>,
    sign: &dyn Fn(Att, Att, Att) -> Sign,
    on_segment: Option<&dyn Fn(Att, Att, Att) -> bool>,
) -> Option<Vec<Att>> {
    // (the vertices of each body as seen, in order; with `at`, placed once
    // in f64: a turn the filter decides there is the sign at and just
    // after the instant)
    let ((pa, ma), (pb, mb)) = (geo.placed_ring(a, at), geo.placed_ring(b, at));
    let real = |x: Att| geo.is_real(x);
    let turn = |(p, mp): (&[Att], &[Option<MidRad>]),
                i: usize,
                j: usize,
                (q, mq): (&[Att], &[Option<MidRad>]),
                k: usize| {
        if let (Some(x), Some(y), Some(z)) = (mp[i], mp[j], mq[k]) {
            bump(Counter::TurnsFiltered);
            if let Some(s) = crate::geom::orient_mid_rad(x, y, z) {
                return s;
            }
        }
        sign(p[i], p[j], q[k])
    };
    // a vertex on an edge's line that may stay there: off the edge, or a
    // real vertex sliding along a real edge
    let zero_ok = |u: Att, v: Att, w: Att| {
        on_segment.is_some_and(|on| (real(u) && real(v) && real(w)) || !on(u, v, w))
    };
    // (each test below asks a whole ring and stops at the first element
    // that decides it; the rings are convex and asked in order, so the
    // element that decided the previous test most often decides the next
    // one too: each search starts there, cyclically. The answers are those
    // of any order.)
    let from = |start: &std::cell::Cell<usize>, n: usize| {
        let s = start.get().min(n.saturating_sub(1));
        (0..n).map(move |x| (s + x) % n)
    };
    // an edge of `p` with every vertex of `q` outside, strictly or on its
    // line where allowed
    let separates = |p: (&[Att], &[Option<MidRad>]), q: (&[Att], &[Option<MidRad>])| {
        let n = p.0.len();
        let inner = std::cell::Cell::new(0);
        (0..n).any(|i| {
            let j = (i + 1) % n;
            let outside = |k: usize| match turn(p, i, j, q, k) {
                Sign::Negative => true,
                Sign::Zero => zero_ok(p.0[i], p.0[j], q.0[k]),
                Sign::Positive => false,
            };
            match from(&inner, q.0.len()).find(|&k| !outside(k)) {
                Some(k) => {
                    inner.set(k);
                    false
                }
                None => true,
            }
        })
    };
    let (ra, rb) = ((&pa[..], &ma[..]), (&pb[..], &mb[..]));
    if separates(ra, rb) || separates(rb, ra) {
        return None;
    }
    let facing = std::cell::Cell::new(0);
    let inside = |p: (&[Att], &[Option<MidRad>]), q: (&[Att], &[Option<MidRad>]), k: usize| {
        let n = p.0.len();
        match from(&facing, n).find(|&i| turn(p, i, (i + 1) % n, q, k) == Sign::Negative) {
            Some(i) => {
                facing.set(i);
                false
            }
            None => true,
        }
    };
    let mut out: Vec<Att> = (0..pb.len())
        .filter(|&k| !real(pb[k]) && inside(ra, rb, k))
        .map(|k| pb[k])
        .chain(
            (0..pa.len())
                .filter(|&k| !real(pa[k]) && inside(rb, ra, k))
                .map(|k| pa[k]),
        )
        .collect();
    if let Some(on) = on_segment {
        out.extend(sliding(geo, (&pa, &ma), (&pb, &mb), sign, on));
        out.sort();
        out.dedup();
    }
    if out.is_empty() {
        out = pa
            .iter()
            .chain(&pb)
            .filter(|&&w| !real(w))
            .copied()
            .collect();
    }
    Some(out)
}

/// The approximation points among an edge of one ring and a vertex of the
/// other that lie on the edge's line with the vertex on the closed edge
/// (`on_segment`), where not all three are real: an approximation edge
/// sliding along a vertex, or an approximation vertex sliding along an edge.
///
/// Each ring comes with its points placed in f64 at the instant at or just
/// after which `sign` is asked ([`places`]); a triple whose turn the filter
/// decides there is skipped: a turn that is not zero at the instant is not
/// zero just after it either.
fn sliding(
    geo: &Geo,
    (pa, ma): (&[Att], &[Option<MidRad>]),
    (pb, mb): (&[Att], &[Option<MidRad>]),
    sign: &dyn Fn(Att, Att, Att) -> Sign,
    on_segment: &dyn Fn(Att, Att, Att) -> bool,
) -> Vec<Att> {
    let reals = |p: &[Att]| -> Vec<bool> { p.iter().map(|&x| geo.is_real(x)).collect() };
    let (ra, rb) = (reals(pa), reals(pb));
    let mut out = Vec::new();
    for ((p, rp, mp), (q, rq, mq)) in [
        ((pa, &ra, ma), (pb, &rb, mb)),
        ((pb, &rb, mb), (pa, &ra, ma)),
    ] {
        // (a vertex on the closed edge at the instant is in the edge's
        // box then: only the vertices of `q` in `p`'s box are tried, and
        // each only against the edges whose box may hold it; every bound
        // rounded outward, so no triple that holds is skipped)
        let ks: Vec<usize> = match MidRad::bounding_box(mp) {
            Some(bp) => (0..q.len())
                .filter(|&k| !mq[k].is_some_and(|m| m.outside_box(bp)))
                .collect(),
            None => (0..q.len()).collect(),
        };
        if ks.is_empty() {
            continue;
        }
        let bq = MidRad::bounding_box(ks.iter().map(|&k| &mq[k]));
        for i in 0..p.len() {
            let j = (i + 1) % p.len();
            let (u, v) = (p[i], p[j]);
            let edge = MidRad::bounding_box([&mp[i], &mp[j]]);
            if let (Some(e), Some(bq)) = (edge, bq) {
                if crate::geom::boxes_apart(e, bq) {
                    continue;
                }
            }
            for &k in &ks {
                let w = q[k];
                if let (Some(e), Some(m)) = (edge, mq[k]) {
                    if m.outside_box(e) {
                        continue;
                    }
                }
                if rp[i] && rp[j] && rq[k] {
                    continue;
                }
                if let (Some(x), Some(y), Some(z)) = (mp[i], mp[j], mq[k]) {
                    bump(Counter::TurnsFiltered);
                    if crate::geom::orient_mid_rad(x, y, z).is_some() {
                        continue;
                    }
                }
                if sign(u, v, w) == Sign::Zero && on_segment(u, v, w) {
                    let real = [rp[i], rp[j], rq[k]];
                    out.extend(
                        [u, v, w]
                            .into_iter()
                            .zip(real)
                            .filter(|&(_, r)| !r)
                            .map(|(x, _)| x),
                    );
                }
            }
        }
    }
    out
}

/// Pops one approximation vertex (and updates whatever is built on the
/// approximations); `Ok(false)` if there was nothing to pop.
pub type Popper<'p> = &'p mut dyn FnMut(&mut Shapes, Att) -> Result<bool, StructureError>;

/// Pop the approximations of bodies `a` and `b` where, just after `t`, an
/// approximation edge of one slides along a vertex of the other or the
/// other way round (see `sliding`), until they do not; the number of
/// pops. Used after a collision response, when the pair may go on sliding
/// along each other.
pub fn unslide_after(
    world: &World,
    shapes: &mut Shapes,
    (a, b): (BodyId, BodyId),
    t: &Time,
    popper: Popper,
) -> Result<u64, StructureError> {
    let mut pops = 0;
    loop {
        let geo = Geo { world, shapes };
        let at = Some(t.interval());
        let ((pa, ma), (pb, mb)) = (geo.placed_ring(a, at), geo.placed_ring(b, at));
        let todo = sliding(
            &geo,
            (&pa, &ma),
            (&pb, &mb),
            &|u, v, w| turn_after(&geo, u, v, w, t),
            &|u, v, w| on_segment_after(&geo, u, v, w, t),
        );
        if todo.is_empty() {
            return Ok(pops);
        }
        let mut any = false;
        for x in todo {
            let popped = popper(shapes, x)?;
            any |= popped;
            pops += u64::from(popped);
        }
        if !any {
            return Ok(pops);
        }
    }
}

/// A test on three points seen through a [`Geo`].
type GeoTest<'a> = &'a dyn Fn(&Geo, Att, Att, Att) -> bool;

/// Pop `a`'s and `b`'s approximations until `sign` says they are apart;
/// the number of pops.
fn separate(
    world: &World,
    shapes: &mut Shapes,
    (a, b): (BodyId, BodyId),
    at: Option<Interval>,
    sign: &dyn Fn(&Geo, Att, Att, Att) -> Sign,
    on_segment: Option<GeoTest>,
    popper: Popper,
) -> Result<u64, StructureError> {
    let mut pops = 0;
    loop {
        let geo = Geo { world, shapes };
        let on = on_segment.map(|f| move |u, v, w| f(&geo, u, v, w));
        let on_ref = on.as_ref().map(|f| f as &dyn Fn(Att, Att, Att) -> bool);
        let Some(todo) = involved(&geo, (a, b), at, &|u, v, w| sign(&geo, u, v, w), on_ref) else {
            return Ok(pops);
        };
        if todo.is_empty() {
            return Err(StructureError::Local(format!(
                "bodies {} and {} overlap with no approximation vertex left to refine",
                world.body(a).id,
                world.body(b).id
            )));
        }
        for x in todo {
            pops += u64::from(popper(shapes, x)?);
        }
    }
}

/// Pop the approximations of bodies `a` and `b` until they are apart just
/// after `t` (touching along a line is allowed: the polygons may slide
/// along each other); the number of pops. Each pop goes through `popper`
/// (which may update a structure built on the approximations).
pub fn separate_after(
    world: &World,
    shapes: &mut Shapes,
    (a, b): (BodyId, BodyId),
    t: &Time,
    popper: Popper,
) -> Result<u64, StructureError> {
    separate(
        world,
        shapes,
        (a, b),
        Some(t.interval()),
        &|geo, u, v, w| turn_after(geo, u, v, w, t),
        Some(&|geo, u, v, w| on_segment_after(geo, u, v, w, t)),
        popper,
    )
}

/// Pop approximations until every two are apart (closed sets disjoint) at
/// time `t`; the number of pops. A sweep over bounding boxes finds the
/// pairs to test.
pub fn separate_all_at(
    world: &World,
    shapes: &mut Shapes,
    t: &Rational,
) -> Result<u64, StructureError> {
    separate_all(world, shapes, t, &|geo, u, v, w| {
        let p = |x: Att| geo.position(x, t).expect("a vertex, not ω, has a position");
        orient(&p(u), &p(v), &p(w))
    })
}

/// Pop approximations until `sign` says every two whose boxes meet at `t`
/// are apart (no touching allowed); the number of pops.
fn separate_all(
    world: &World,
    shapes: &mut Shapes,
    t: &Rational,
    sign: &dyn Fn(&Geo, Att, Att, Att) -> Sign,
) -> Result<u64, StructureError> {
    let mut pops = 0;
    let at = crate::num::Time::from_rational(t.clone()).interval();
    for pair in box_pairs(world, shapes, t) {
        pops += separate(
            world,
            shapes,
            pair,
            Some(at),
            sign,
            None,
            &mut |shapes, x| Ok(pop(shapes, x)),
        )?;
    }
    Ok(pops)
}

/// Pop every approximation vertex of every body once (one level finer
/// everywhere); the number of pops.
pub fn pop_every_level(world: &World, shapes: &mut Shapes) -> u64 {
    let mut todo = Vec::new();
    {
        let geo = Geo { world, shapes };
        for (i, body) in world.bodies().iter().enumerate() {
            let id = BodyId::new(i as u32);
            if body.alive && shapes.per.get(i).is_some_and(Option::is_some) {
                todo.extend(
                    geo.ids(id)
                        .into_iter()
                        .map(|v| Att::vertex(id, v))
                        .filter(|&a| !geo.is_real(a)),
                );
            }
        }
    }
    todo.into_iter().map(|a| u64::from(pop(shapes, a))).sum()
}

/// Pop approximations until every two are strictly apart (closed sets
/// disjoint) just after `t`; the number of pops. For a structure built
/// afresh for just after an instant at which no two polygons stay in
/// contact (the approximations of polygons that touch at `t` may still
/// touch, or lie flush, just after it, and no free-space triangulation
/// exists then). Fails if two polygons do stay in contact.
pub fn separate_all_strictly_after(
    world: &World,
    shapes: &mut Shapes,
    t: &Time,
) -> Result<u64, StructureError> {
    let r = t
        .as_rational()
        .ok_or_else(|| StructureError::Local("irrational time".into()))?;
    separate_all(world, shapes, r, &|geo, u, v, w| {
        turn_after(geo, u, v, w, t)
    })
}

/// For the audit: every two approximations have disjoint interiors at time
/// `t` (they may touch where the polygons slide along each other).
pub fn check_apart(world: &World, shapes: &Shapes, t: &Rational) -> Result<(), StructureError> {
    let geo = Geo { world, shapes };
    for (a, b) in box_pairs(world, shapes, t) {
        let sign = |u: Att, v: Att, w: Att| {
            let p = |x: Att| geo.position(x, t).expect("a vertex, not ω, has a position");
            orient(&p(u), &p(v), &p(w))
        };
        let on_segment = |u: Att, v: Att, w: Att| {
            let p = |x: Att| geo.position(x, t).expect("a vertex, not ω, has a position");
            let (pu, pv, pw) = (p(u), p(v), p(w));
            pu.sub(&pw).dot(&pv.sub(&pw)).sign() != Sign::Positive
        };
        if involved(&geo, (a, b), None, &sign, Some(&on_segment)).is_some() {
            #[cfg(feature = "trace")]
            for id in [a, b] {
                let pts: Vec<(u32, bool, [f64; 2])> = geo
                    .ids(id)
                    .into_iter()
                    .map(|v| {
                        let x = Att::vertex(id, v);
                        let q = geo.position(x, t).expect("a vertex, not ω, has a position");
                        (v, geo.is_real(x), [q.x.to_f64(), q.y.to_f64()])
                    })
                    .collect();
                eprintln!("approximation of {id:?} at {}: {pts:?}", t.to_f64());
            }
            return Err(StructureError::Local(format!(
                "the approximations of {} and {} overlap at t = {t}",
                world.body(a).id,
                world.body(b).id
            )));
        }
    }
    Ok(())
}

/// The pairs of alive bodies whose approximations' bounding boxes meet at
/// time `t`, the boxes enclosing the vertices' exact positions
/// ([`Geo::seen_box`]), so that rounding never hides an overlap.
fn box_pairs(world: &World, shapes: &Shapes, t: &Rational) -> Vec<(BodyId, BodyId)> {
    let geo = Geo { world, shapes };
    let tiv = t.interval();
    let boxes: Vec<Option<[f64; 4]>> = world
        .bodies()
        .iter()
        .enumerate()
        .map(|(i, body)| {
            body.alive.then(|| {
                // the enclosures of the approximation's vertices at `t`
                // (rigorous: an overlap is never hidden); a box that is
                // not finite meets every other one
                match geo.seen_box(BodyId::new(i as u32), tiv) {
                    Some([x, y]) => [x.lo, y.lo, x.hi, y.hi],
                    None => [
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                        f64::INFINITY,
                        f64::INFINITY,
                    ],
                }
            })
        })
        .collect();
    let mut order: Vec<usize> = (0..boxes.len()).filter(|&i| boxes[i].is_some()).collect();
    order.sort_by(|&i, &j| {
        let (x, y) = (boxes[i].expect("alive"), boxes[j].expect("alive"));
        x[0].total_cmp(&y[0])
    });
    let mut pairs = Vec::new();
    for (n, &i) in order.iter().enumerate() {
        let bi = boxes[i].expect("alive");
        for &j in &order[n + 1..] {
            let bj = boxes[j].expect("alive");
            if bj[0] > bi[2] {
                break;
            }
            if bj[1] > bi[3] || bi[1] > bj[3] {
                continue;
            }
            pairs.push((BodyId::new(i as u32), BodyId::new(j as u32)));
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate_small, Family};

    #[test]
    fn coarsest_approximations_are_refined_until_apart() {
        for family in Family::ALL {
            for seed in 0..20 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let mut shapes = coarsest_shapes(&world, 0);
                separate_all_at(&world, &mut shapes, &Rational::zero()).unwrap();
                let geo = Geo {
                    world: &world,
                    shapes: &shapes,
                };
                let n = world.len();
                for i in 0..n {
                    let a = BodyId::new(i as u32);
                    let ap = shapes.approx(a).unwrap();
                    ap.array
                        .check_exposed(&world.body(a).shape, ap.exposed())
                        .unwrap();
                    for j in i + 1..n {
                        let b = BodyId::new(j as u32);
                        let sign = |u, v, w| {
                            let p = |x: Att| geo.position(x, &Rational::zero()).unwrap();
                            orient(&p(u), &p(v), &p(w))
                        };
                        assert!(involved(&geo, (a, b), None, &sign, None).is_none());
                    }
                }
                check_apart(&world, &shapes, &Rational::zero()).unwrap();
            }
        }
    }
}
