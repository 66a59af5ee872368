//! Corridor faces, junctions and the middle bridge.

use super::geo::Geo;
use super::local::PointMemo;
use super::{Att, CorrId, Kss, Obj};
use crate::motion::orient_poly;
use crate::num::{Sign, Time};
use crate::structure::StructureError;

/// Vertex `v − k` (clockwise by `k`) of the object of `a`.
pub fn step_cw(world: &Geo, a: Att, k: u32) -> Att {
    world.cw(a, k)
}

/// The sign of `orient(u, v, w)` just after time `t` (all three finite):
/// positive for a left turn.
pub fn turn_after(world: &Geo, u: Att, v: Att, w: Att, t: &Time) -> Sign {
    let lp = |a: Att| match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("turn_after on ω"),
    };
    // (two of the points are one moving point: zero for ever)
    if u == v || v == w || u == w {
        return Sign::Zero;
    }
    if let Some(s) = world.orient_filtered(u, v, w, t.interval()) {
        return s;
    }
    if let Some(s) =
        super::local::turn_known_or_on_edge_line(world, [u, v, w], t, super::local::Side::After)
    {
        return s;
    }
    world.memo_turn([u, v, w], t, true, || {
        orient_poly(&lp(u), &lp(v), &lp(w)).sign_after(t)
    })
}

/// [`turn_after`] with the points placed through `memo` (the points of one
/// computation at one instant `t`) for the midpoint–radius filter; where
/// it does not decide, [`turn_after`] itself.
fn turn_after_memo<const N: usize>(
    world: &Geo,
    memo: &mut PointMemo<N>,
    [u, v, w]: [Att; 3],
    t: &Time,
) -> Sign {
    if u == v || v == w || u == w {
        return Sign::Zero;
    }
    let tiv = t.interval();
    if let (Some(a), Some(b), Some(c)) = (
        memo.place(world, u, tiv),
        memo.place(world, v, tiv),
        memo.place(world, w, tiv),
    ) {
        if let Some(s) = crate::geom::orient_mid_rad(a, b, c) {
            super::counters::bump(super::counters::Counter::TurnsFiltered);
            return s;
        }
    }
    turn_after(world, u, v, w, t)
}

impl Kss {
    /// The boundary of corridor `k`'s region, counter-clockwise, as
    /// attachment points: `b_s, a_s, (A-chain), a_t, b_t, (B-chain)`, ending
    /// before `b_s` again. Consecutive equal points are not repeated.
    pub fn corridor_boundary(&self, world: &Geo, k: CorrId) -> Vec<Att> {
        let c = &self.corrs[k.0 as usize];
        let (a_s, b_s, _, b_t) = self.ends(k);
        let mut out = vec![b_s];
        for i in 0..=c.len_a {
            out.push(step_cw(world, a_s, i));
        }
        if c.b != Obj::Omega {
            for j in 0..c.len_b {
                out.push(step_cw(world, b_t, j));
            }
        }
        out
    }

    /// Compute middle bridges at time `t` for every corridor whose region
    /// has four convex corners (both chains non-empty and the four end-edge
    /// endpoints convex), by walking the geodesic diagonal `a_s ⇝ b_t`.
    pub fn place_middle_bridges(&mut self, world: &Geo, t: &Time) {
        for ki in 0..self.corrs.len() {
            self.place_middle_bridge(world, CorrId(ki as u32), t);
        }
    }

    /// Compute corridor `k`'s middle bridge at time `t` as
    /// [`Kss::place_middle_bridges`] does for all.
    pub fn place_middle_bridge(&mut self, world: &Geo, k: CorrId, t: &Time) {
        let ki = k.0 as usize;
        {
            let c = self.corrs[ki].clone();
            if c.b == Obj::Omega || c.len_a == 0 || c.len_b == 0 {
                self.corrs.on_same_bodies(ki).mid = None;
                return;
            }
            let (a_s, b_s, a_t, b_t) = self.ends(k);
            // (the walk's steps share their points)
            let mut memo = PointMemo::<8>::default();
            let mut tn = |u, v, w| turn_after_memo(world, &mut memo, [u, v, w], t);
            let mut conv = |u, v, w| tn(u, v, w) == Sign::Positive;
            let four = conv(b_s, a_s, step_cw(world, a_s, 1))
                && conv(step_ccw(world, a_t), a_t, b_t)
                && conv(a_t, b_t, step_cw(world, b_t, 1))
                && conv(step_ccw(world, b_s), b_s, a_s);
            if !four {
                self.corrs.on_same_bodies(ki).mid = None;
                return;
            }
            // α advances from a_s towards a_t and β from b_t towards b_s until
            // α is a convex corner of the face next to `t` (α − 1 left of
            // β → α) and β one of the face next to `s` (β − 1 left of α → β):
            // then α β is the straight part of the geodesic a_s ⇝ b_t.
            let (mut i, mut j) = (0u32, 0u32);
            loop {
                let alpha = step_cw(world, a_s, i);
                let beta = step_cw(world, b_t, j);
                let mut moved = false;
                if i < c.len_a && !conv(beta, alpha, step_cw(world, alpha, 1)) {
                    i += 1;
                    moved = true;
                }
                if j < c.len_b && !conv(alpha, beta, step_cw(world, beta, 1)) {
                    j += 1;
                    moved = true;
                }
                if !moved {
                    break;
                }
            }
            self.corrs.on_same_bodies(ki).mid = Some((i, j));
        }
    }
}

/// For a turn that is identically zero (the three points stay collinear:
/// no relative motion across their line), whether `v` lies strictly between
/// `u` and `w`, a straight angle, which never changes. `t` must be rational.
pub fn straight_forever(world: &Geo, u: Att, v: Att, w: Att, t: &Time) -> bool {
    let Some(t) = t.as_rational() else {
        return false;
    };
    let pos =
        |a: Att| super::build::position(world, a, t).expect("a vertex, not ω, has a position");
    let (pu, pv, pw) = (pos(u), pos(v), pos(w));
    pu.sub(&pv).dot(&pw.sub(&pv)).sign() == Sign::Negative
}

/// Whether `u`, `v`, `w` (on one line for ever, with a zero turn just after
/// `t`) make a cusp just after `t`: `u` and `w` on the same side of `v`, on
/// at least two bodies. Two bodies that slide along each other pinch a face
/// this way; the cusp is a convex corner of angle zero, and the order
/// certificate of the triple ends it.
pub fn cusp_forever(world: &Geo, u: Att, v: Att, w: Att, t: &Time) -> bool {
    let d = crate::motion::dot_poly(&lin(world, v), &lin(world, u), &lin(world, w));
    (u.obj != v.obj || w.obj != v.obj) && d.sign_after(t) == Sign::Positive
}

fn lin(world: &Geo, a: Att) -> crate::motion::LinearPoint {
    match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("a finite point was expected"),
    }
}

/// Whether `x` and `y`, on two bodies, stay at one place for the whole
/// current motion: a vertex resting on a vertex of another polygon (their
/// bodies move alike). A bridge between them has length zero; the face
/// corner there is the one between the two polygons' edges.
pub fn coincide_forever(world: &Geo, x: Att, y: Att) -> bool {
    let (Obj::Body(bx), Obj::Body(by)) = (x.obj, y.obj) else {
        return false;
    };
    // (two bodies that move apart never rest on each other: the cheap test)
    if bx == by || !world.body(bx).same_velocity(world.body(by)) {
        return false;
    }
    if let (Some(ex), Some(ey)) = (world.enclose_linear(x), world.enclose_linear(y)) {
        if ex.iter().zip(&ey).any(|(a, b)| !a.overlaps(b)) {
            return false;
        }
    }
    let (p, q) = (lin(world, x), lin(world, y));
    crate::motion::dot_poly(&p, &q, &q).is_zero()
}

/// Whether vertices `x` and `y` of two bodies are at one place at instant
/// `t` (an f64 filter on `|x − y|²`, then exact).
pub fn coincide_at(world: &Geo, x: Att, y: Att, t: &Time) -> bool {
    if x.obj == y.obj || x.is_omega() || y.is_omega() {
        return false;
    }
    // (two positions at `t` that are apart in one coordinate by more than
    // their radii: the cheap test)
    let ti = t.interval();
    if let (Some(mx), Some(my)) = (world.mid_rad(x, ti), world.mid_rad(y, ti)) {
        if mx.apart(my) {
            return false;
        }
    }
    let (p, q) = (lin(world, x), lin(world, y));
    crate::motion::dot_poly(&p, &q, &q).sign_at(t) == Sign::Zero
}

/// Whether two of a partition triangle's corners rest on each other
/// ([`coincide_forever`]): a triangle with a side of length zero, flat for
/// as long as they rest (where three polygons met at a point and one of
/// them rests on another). Its certificate never fails meanwhile; when a
/// motion change parts them it is a turn again, and fails at once if the
/// triangle is inverted.
pub fn flat_while_resting(world: &Geo, c: [Att; 3]) -> bool {
    (0..3).any(|i| coincide_forever(world, c[i], c[(i + 1) % 3]))
}

/// The positions in a face cycle of its places: every vertex but one that
/// rests on the vertex before it ([`coincide_forever`]), which is the same
/// corner of the face.
pub fn resting_places(world: &Geo, face: &[Att]) -> Vec<usize> {
    let n = face.len();
    let keep: Vec<usize> = (0..n)
        .filter(|&x| n < 3 || !coincide_forever(world, face[(x + n - 1) % n], face[x]))
        .collect();
    if keep.is_empty() {
        vec![0]
    } else {
        keep
    }
}

/// Whether a face's places (its cycle with resting places collapsed,
/// [`collapse_resting`]) are a path traversed twice: from one cusp to
/// another and back, each place on the way back resting on its partner on
/// the way out. Such a face has no area for as long as they rest (an edge
/// resting on an identical edge of another polygon leaves one between the
/// two pinches); it is a pseudo-triangle reduced to a path, and nothing in
/// it can change until a motion change parts the pairs.
pub fn doubly_traversed(world: &Geo, places: &[Att]) -> bool {
    let n = places.len();
    if n < 4 || n % 2 != 0 {
        return false;
    }
    (0..n / 2).any(|r| {
        (1..n / 2).all(|i| coincide_forever(world, places[(r + i) % n], places[(r + n - i) % n]))
    })
}

/// A face cycle with each vertex that rests on the vertex before it left
/// out ([`resting_places`]): the face's corners as they are.
pub fn collapse_resting(world: &Geo, face: &[Att]) -> Vec<Att> {
    resting_places(world, face)
        .into_iter()
        .map(|x| face[x])
        .collect()
}

/// Whether `x` and `y` are the two ends of one polygon edge.
pub fn poly_edge(world: &Geo, x: Att, y: Att) -> bool {
    x.obj == y.obj && !x.is_omega() && (step_ccw(world, x) == y || step_ccw(world, y) == x)
}

/// Vertex `v + 1` (counter-clockwise neighbour) of the object of `a`.
pub fn step_ccw(world: &Geo, a: Att) -> Att {
    world.ccw(a)
}

impl Kss {
    /// The faces of corridor `k` (one, or two when it has a middle bridge),
    /// each as its boundary cycle counter-clockwise.
    pub fn corridor_faces(&self, world: &Geo, k: CorrId) -> Vec<Vec<Att>> {
        let c = &self.corrs[k.0 as usize];
        let (a_s, b_s, _a_t, b_t) = self.ends(k);
        match c.mid {
            None => vec![self.corridor_boundary(world, k)],
            Some((i, j)) => {
                let mut s_face = vec![b_s];
                for x in 0..=i {
                    s_face.push(step_cw(world, a_s, x));
                }
                for y in j..c.len_b {
                    s_face.push(step_cw(world, b_t, y));
                }
                let mut t_face = Vec::new();
                for x in i..=c.len_a {
                    t_face.push(step_cw(world, a_s, x));
                }
                for y in 0..=j {
                    t_face.push(step_cw(world, b_t, y));
                }
                vec![s_face, t_face]
            }
        }
    }

    /// Check that every face of every corridor between two bodies is a
    /// pseudo-triangle just after time `t`: exactly three convex vertices,
    /// every other vertex reflex; and that no middle bridge runs along
    /// flush edges of both its bodies.
    pub fn check_faces(&self, world: &Geo, t: &Time) -> Result<(), StructureError> {
        for ki in 0..self.corrs.len() {
            let k = CorrId(ki as u32);
            if self.corrs[ki].b == Obj::Omega {
                continue;
            }
            if let Some(mid) = self.corrs[ki].mid {
                if self.bridge_over_flush_edges(
                    world,
                    k,
                    mid,
                    (t, super::local::Side::After),
                    &mut PointMemo::<4>::default(),
                ) {
                    return Err(StructureError::Invariant(format!(
                        "corridor {ki}: the middle bridge runs along flush edges of both bodies"
                    )));
                }
            }
            for (fi, face) in self.corridor_faces(world, k).iter().enumerate() {
                // (a bridge between two vertices resting on each other has
                // length zero: its two ends are one corner)
                let face = collapse_resting(world, face);
                if doubly_traversed(world, &face) {
                    continue; // a path traversed twice, while it rests
                }
                let n = face.len();
                if n < 3 {
                    if n == 2 && self.corrs[ki].len_a == 0 && self.corrs[ki].len_b == 0 {
                        continue; // an empty corridor
                    }
                    return Err(StructureError::Invariant(format!(
                        "corridor {ki} face {fi} has {n} vertices"
                    )));
                }
                let mut convex = 0;
                let mut all_zero = true;
                for x in 0..n {
                    let (u, v, w) = (face[(x + n - 1) % n], face[x], face[(x + 1) % n]);
                    let s = turn_after(world, u, v, w, t);
                    all_zero &= s == Sign::Zero;
                    match s {
                        Sign::Positive => convex += 1,
                        Sign::Negative => {}
                        Sign::Zero if straight_forever(world, u, v, w, t) => {}
                        // a cusp: two bodies sliding along each other pinch
                        // the face (a convex corner of angle zero)
                        Sign::Zero if cusp_forever(world, u, v, w, t) => convex += 1,
                        Sign::Zero => {
                            return Err(StructureError::Invariant(format!(
                                "corridor {ki} face {fi}: zero angle at {v:?}"
                            )));
                        }
                    }
                }
                // a flat face (two bodies sliding flush along a common
                // line): two cusps, every other vertex straight
                if convex != 3 && !(all_zero && convex == 2) {
                    return Err(StructureError::Invariant(format!(
                        "corridor {ki} face {fi} has {convex} convex vertices: {face:?}"
                    )));
                }
            }
        }
        Ok(())
    }
}
