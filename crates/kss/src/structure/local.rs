//! Constant-time views of one corridor: its faces as at most two chain pieces
//! joined by bridges, their junctions, the certificates a corridor or a
//! partition triangle owns, whether a corridor's faces are pseudo-triangles,
//! and `normalize`, which restores that after an operation by walking the
//! middle bridge locally.
//!
//! Everything here costs O(1) orientation tests per corridor (plus the length
//! of a walk, which is short next to an event), so that an event touches only
//! the certificates of the few corridors and triangles it changes.

use arrayvec::ArrayVec;

use super::certs::{order_cert, Cert, CertKind};
use super::faces::{coincide_forever, step_ccw, step_cw, turn_after};
use super::geo::Geo;
use super::{Att, CorrId, Kss, Obj, TriId};
use crate::motion::dot_poly;
use crate::num::{Sign, Time};
use crate::structure::StructureError;

/// Which edge of a corridor face leaves or enters a junction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeRef {
    /// A polygon edge of the chain.
    Chain,
    /// The end-edge `(a_s, b_s)`.
    EndS,
    /// The end-edge `(b_t, a_t)`.
    EndT,
    /// The middle bridge `(α, β)`.
    Mid,
}

/// A vertex of a corridor face with a bridge on at least one side: the turn
/// `orient(prev, v, next)` along the face (counter-clockwise, face on the
/// left) and the edges it sits between.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Junction {
    /// The previous vertex along the face.
    pub prev: Att,
    /// The junction.
    pub v: Att,
    /// The next vertex along the face.
    pub next: Att,
    /// The edge `(prev, v)`.
    pub in_edge: EdgeRef,
    /// The edge `(v, next)`.
    pub out_edge: EdgeRef,
}

/// A corner of a corridor face ([`Kss::corners_with`]): its junction, and
/// the end of a bridge of length zero merged into it, if any.
type Corner = (Junction, Option<Att>);

/// The certificates of one owner: a corridor's corners (four per face at
/// most) or hull turns, a triangle's orientation.
pub type Certs = ArrayVec<Cert, MAX_CERTS>;

/// The most certificates one owner has ([`Certs`]).
pub const MAX_CERTS: usize = 8;

/// The junctions of one face: two per chain piece at most.
type FaceJunctions = ArrayVec<Junction, 4>;

/// Points placed at one instant (`ω` marks an unused entry: nothing
/// places it): a walk's ([`Kss::walk`], whose steps share their points)
/// and a validity check's (a corridor's junctions share most of theirs: a
/// corner is the next junction's neighbour). Below 16 entries, the last
/// `N` points placed, searched, with the next entry to replace; from 16,
/// each point in the entry its word's hash names (a validity check's
/// memo: one comparison per lookup where a search took up to sixteen). The
/// points are kept as their words ([`Att::word`]) apart from the places,
/// so that a search reads one short array. A point that is not found is
/// placed again, to the same place: the memo changes no answer.
pub(crate) struct PointMemo<const N: usize> {
    keys: [u64; N],
    places: [Option<crate::geom::MidRad>; N],
    next: usize,
}

impl<const N: usize> Default for PointMemo<N> {
    fn default() -> PointMemo<N> {
        PointMemo {
            keys: [Att::OMEGA.word(); N],
            places: [None; N],
            next: 0,
        }
    }
}

impl<const N: usize> PointMemo<N> {
    /// [`Geo::mid_rad`] of `a` at `t`, the same `t` at every call.
    pub(crate) fn place(
        &mut self,
        world: &Geo,
        a: Att,
        t: crate::num::Interval,
    ) -> Option<crate::geom::MidRad> {
        let w = a.word();
        if N >= 16 {
            // (a larger memo is direct-mapped by a hash of the word: one
            // comparison instead of a search; a point whose entry another
            // took is placed again, to the same place)
            // (`slot` takes the hash's top bits: `N` is a power of two)
            const { assert!(N < 16 || N.is_power_of_two()) };
            let i = super::geo::slot(w ^ (w >> 29), N);
            if self.keys[i] == w {
                return self.places[i];
            }
            let m = world.mid_rad(a, t);
            (self.keys[i], self.places[i]) = (w, m);
            return m;
        }
        if let Some(i) = self.keys.iter().position(|&k| k == w) {
            return self.places[i];
        }
        let m = world.mid_rad(a, t);
        let i = self.next % N;
        (self.keys[i], self.places[i]) = (w, m);
        self.next = self.next.wrapping_add(1);
        m
    }
}

/// A piece of chain in face order: from `start` clockwise over `len` edges
/// to `end`.
#[derive(Clone, Copy, Debug)]
struct Piece {
    start: Att,
    len: u32,
    end: Att,
}

/// A corridor face: two pieces, the bridge from the first piece's last vertex
/// to the second's start, and the bridge back.
#[derive(Clone, Copy, Debug)]
struct Face {
    p: [Piece; 2],
    e: [EdgeRef; 2],
}

/// The sign of `orient(u, v, w)` just after `t`.
pub fn turn(world: &Geo, u: Att, v: Att, w: Att, t: &Time) -> Sign {
    turn_after(world, u, v, w, t)
}

/// Which side of the current instant a corridor's signs are read on.
///
/// Normally just after it. When several certificates fail at one instant,
/// the operation for the first can leave a neighbouring corridor that has
/// no pseudo-triangle decomposition just after the instant until the others
/// are handled; that corridor is then checked, and its certificates signed,
/// just *before* the instant (where the structure was valid), so that the
/// junctions whose sign flips at the instant fail at once and are handled as
/// events of the same instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Just after the instant (the normal case).
    After,
    /// Just before it.
    Before,
}

fn lin(world: &Geo, a: Att) -> crate::motion::LinearPoint {
    match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("a finite point was expected"),
    }
}

/// The sign of `orient(u, v, w)` just on `side` of `t`.
pub fn turn_on(world: &Geo, u: Att, v: Att, w: Att, t: &Time, side: Side) -> Sign {
    // (two of the points are one moving point: zero for ever)
    if u == v || v == w || u == w {
        return Sign::Zero;
    }
    if let Some(s) = world.orient_filtered(u, v, w, t.interval()) {
        return s;
    }
    turn_on_exact(world, [u, v, w], t, side)
}

/// [`turn_on`] with the points placed through `memo` (the points of one
/// check at one instant `t`): the midpoint–radius filter on the memo's
/// places, then the interval filter and the exact sign as [`turn_on`].
fn turn_on_memo<const N: usize>(
    world: &Geo,
    memo: &mut PointMemo<N>,
    [u, v, w]: [Att; 3],
    t: &Time,
    side: Side,
) -> Sign {
    if u == v || v == w || u == w {
        return Sign::Zero;
    }
    let tiv = t.interval();
    let mut place = |a: Att| memo.place(world, a, tiv);
    if let (Some(a), Some(b), Some(c)) = (place(u), place(v), place(w)) {
        super::counters::bump(super::counters::Counter::TurnsFiltered);
        if let Some(s) = crate::geom::orient_mid_rad(a, b, c) {
            return s;
        }
        return turn_on_past_mid_rad(world, u, v, w, t, side);
    }
    turn_on(world, u, v, w, t, side)
}

/// [`turn_on`] for three distinct points whose midpoint–radius filter at
/// `t` ([`crate::geom::orient_mid_rad`] on [`Geo::mid_rad`]) left the turn
/// undecided: the interval filter, then the exact sign.
fn turn_on_past_mid_rad(world: &Geo, u: Att, v: Att, w: Att, t: &Time, side: Side) -> Sign {
    if let Some(s) = world.orient_intervals(u, v, w, t.interval()) {
        return s;
    }
    turn_on_exact(world, [u, v, w], t, side)
}

/// The sign of the turn of `[u, v, w]` just on `side` of `t` where the
/// filters leave it undecided: the instant's memo, or the exact sign.
fn turn_on_exact(world: &Geo, [u, v, w]: [Att; 3], t: &Time, side: Side) -> Sign {
    world.shapes.faces.note_exact_read();
    if let Some(s) = turn_known_or_on_edge_line(world, [u, v, w], t, side) {
        return s;
    }
    let after = side == Side::After;
    // (the instant's memo of exact turns, which `turn_after` shares)
    world.memo_turn([u, v, w], t, after, || {
        let p = crate::motion::orient_poly(&lin(world, u), &lin(world, v), &lin(world, w));
        // (both sides from one evaluation: a junction zero at the instant
        // is asked on both sides, a pop reading just before it and the
        // normalization after it; the memo keeps the other side)
        asked_side(&p, t, after, |other| {
            world.memo_record([u, v, w], t, !after, other)
        })
    })
}

/// The sign of the turn `pts` just on `side` of `t` from the instant's
/// memo, or read exactly on the real edge of an approximation edge's line
/// ([`turn_on_edge_line`]) and then remembered for `pts` too; `None` where
/// neither answers (the caller evaluates the turn itself).
pub(crate) fn turn_known_or_on_edge_line(
    world: &Geo,
    pts: [Att; 3],
    t: &Time,
    side: Side,
) -> Option<Sign> {
    let after = side == Side::After;
    if let Some(s) = world.memo_peek(pts, t, after) {
        super::counters::bump(super::counters::Counter::TurnsMemo);
        return Some(s);
    }
    let s = turn_on_edge_line(world, pts, t, side)?;
    world.memo_record(pts, t, after, s);
    Some(s)
}

/// The sign of `poly` just after `t` (`after`) or just before it, from one
/// evaluation of both sides; `other` is given the sign on the other side
/// (for the instant's memo).
fn asked_side(poly: &crate::num::Poly, t: &Time, after: bool, other: impl FnOnce(Sign)) -> Sign {
    let [before, just_after] = poly.signs_around(t);
    if after {
        other(before);
        just_after
    } else {
        other(just_after);
        before
    }
}

/// The exact sign of the turn `pts` just on `side` of `t` where two of its
/// points are the ends of an approximation edge on the line of a real
/// polygon edge ([`Geo::edge_line`]): the turn of the third point with
/// the real edge, computed on the polygon's own vertices under their key
/// in the instant's memo, where every approximation edge on that line
/// finds it. A pop puts new approximation vertices on the line that failed
/// at the instant: their turns with the other body's vertex are zero there.
/// `None` where no two points of the turn are such an edge.
fn turn_on_edge_line(world: &Geo, pts: [Att; 3], t: &Time, side: Side) -> Option<Sign> {
    let line = world.edge_line(pts)?;
    let after = side == Side::After;
    let body = world.body(line.body);
    let sign = super::memo::turn(line.keys, line.frames, t, after, || {
        let poly = crate::motion::orient_poly(
            &lin(world, line.x),
            &body.frame.vertex(&body.shape, line.from),
            &body.frame.vertex(&body.shape, line.to),
        );
        asked_side(&poly, t, after, |other| {
            super::memo::record(line.keys, line.frames, t, !after, other)
        })
    });
    #[cfg(debug_assertions)]
    {
        let direct = crate::motion::orient_poly(
            &lin(world, pts[0]),
            &lin(world, pts[1]),
            &lin(world, pts[2]),
        )
        .signs_around(t);
        debug_assert_eq!(
            sign,
            direct[usize::from(after)],
            "the turn of {pts:?} is not that of the real edge {} → {} of its line",
            line.from,
            line.to
        );
    }
    Some(sign)
}

/// Whether `v` is strictly between `u` and `w` just after `t` (for three
/// points that stay on one line).
pub fn between_after(world: &Geo, u: Att, v: Att, w: Att, t: &Time) -> bool {
    between_on(world, u, v, w, t, Side::After)
}

/// Whether `v` is strictly between `u` and `w` just on `side` of `t`.
pub fn between_on(world: &Geo, u: Att, v: Att, w: Att, t: &Time, side: Side) -> bool {
    // (two of the points are one moving point: `(u − v)·(w − v)` is a
    // square or zero for ever)
    if u == v || v == w || u == w {
        return false;
    }
    if let Some(s) = world.dot_filtered(u, v, w, t.interval()) {
        return s == Sign::Negative;
    }
    world.shapes.faces.note_exact_read();
    let d = dot_poly(&lin(world, v), &lin(world, u), &lin(world, w));
    let s = match side {
        Side::After => d.sign_after(t),
        Side::Before => d.sign_before(t),
    };
    s == Sign::Negative
}

/// Whether the polygon of junction `j`'s vertex `v` stays out of the face at
/// `v` just on `side` of `t`, given the junction's turn `s`: a bridge end
/// must not point into the polygon's corner at `v`, and the polygon's edges
/// at `v` that are not face edges must not point into the face's angle
/// (the intersection of the two left half-planes at a convex junction, their
/// union at a reflex one, one half-plane at a straight one).
fn junction_clear(world: &Geo, j: &Junction, s: Sign, t: &Time, side: Side) -> bool {
    junction_clear_placed(world, j, s, (t, side), &Placed::of(world, j, t))
}

/// A junction's five points (its vertex, the vertex's two neighbours on
/// its polygon, the junction's two other points) and their midpoints and
/// radii at an instant, placed once for the junction's own turn and its
/// clearance ([`junction_clear`]).
struct Placed {
    pts: [Att; 5],
    mids: [Option<crate::geom::MidRad>; 5],
    /// Whether all five points are placed (else the vertex's two polygon
    /// neighbours are not: [`Placed::of_turn_with`]).
    full: bool,
}

impl Placed {
    fn of(world: &Geo, j: &Junction, t: &Time) -> Placed {
        Placed::of_with(world, j, t, &mut PointMemo::<5>::default())
    }

    /// [`Placed::of`] with the points already placed at `t` by the same
    /// check in `memo` (a corridor's junctions share most of their
    /// points).
    fn of_with<const N: usize>(
        world: &Geo,
        j: &Junction,
        t: &Time,
        memo: &mut PointMemo<N>,
    ) -> Placed {
        let mut placed = Placed::of_turn_with(world, j, t, memo);
        placed.complete(world, t, memo);
        placed
    }

    /// [`Placed::of_with`] with only the junction's three points placed,
    /// for its turn ([`Placed::complete`] places the vertex's polygon
    /// neighbours, which its clearance reads).
    fn of_turn_with<const N: usize>(
        world: &Geo,
        j: &Junction,
        t: &Time,
        memo: &mut PointMemo<N>,
    ) -> Placed {
        let v = j.v;
        let (up, down) = (step_ccw(world, v), step_cw(world, v, 1));
        let tiv = t.interval();
        let mut place = |a: Att| memo.place(world, a, tiv);
        Placed {
            pts: [v, up, down, j.prev, j.next],
            mids: [place(v), None, None, place(j.prev), place(j.next)],
            full: false,
        }
    }

    /// Place the points [`Placed::of_turn_with`] left out.
    fn complete<const N: usize>(&mut self, world: &Geo, t: &Time, memo: &mut PointMemo<N>) {
        if !self.full {
            let tiv = t.interval();
            for x in [1, 2] {
                self.mids[x] = memo.place(world, self.pts[x], tiv);
            }
            self.full = true;
        }
    }

    /// The junction's turn `(prev, v, next)` where the midpoint–radius
    /// filter decides it (as [`Geo::orient_filtered`] does first).
    fn turn(&self) -> Option<Sign> {
        let [v, _, _, p, n] = self.mids;
        let s = crate::geom::orient_mid_rad(p?, v?, n?)?;
        super::counters::bump(super::counters::Counter::TurnsFiltered);
        Some(s)
    }

    /// The junction's turn just on `side` of `t`: [`Placed::turn`] where it
    /// decides, else the interval filter and the exact sign (as
    /// [`turn_on`], without asking the midpoint–radius filter again).
    fn turn_on(&self, world: &Geo, t: &Time, side: Side) -> Sign {
        if let Some(s) = self.turn() {
            return s;
        }
        let [v, _, _, p, n] = self.pts;
        let placed = self.mids[0].is_some() && self.mids[3].is_some() && self.mids[4].is_some();
        if placed && p != v && v != n && p != n {
            turn_on_past_mid_rad(world, p, v, n, t, side)
        } else {
            turn_on(world, p, v, n, t, side)
        }
    }
}

/// [`junction_clear`] with the junction's points placed.
fn junction_clear_placed(
    world: &Geo,
    j: &Junction,
    s: Sign,
    (t, side): (&Time, Side),
    placed: &Placed,
) -> bool {
    let v = j.v;
    // each of the five points enclosed once (midpoint and radius) for the
    // up to eight turns below; the interval filter and the exact turn only
    // where that does not decide
    let Placed { pts, mids, .. } = placed;
    // (the points by their place in `pts`: the vertex, its two polygon
    // neighbours, the junction's two other points)
    const V: usize = 0;
    const UP: usize = 1;
    const DOWN: usize = 2;
    const PREV: usize = 3;
    const NEXT: usize = 4;
    let tn = |[a, b, c]: [usize; 3]| {
        let (pa, pb, pc) = (pts[a], pts[b], pts[c]);
        if let (Some(ea), Some(eb), Some(ec)) = (mids[a], mids[b], mids[c]) {
            super::counters::bump(super::counters::Counter::TurnsFiltered);
            if let Some(s) = crate::geom::orient_mid_rad(ea, eb, ec) {
                return s;
            }
            if pa != pb && pb != pc && pa != pc {
                return turn_on_past_mid_rad(world, pa, pb, pc, t, side);
            }
        }
        turn_on(world, pa, pb, pc, t, side)
    };
    // the polygon's corner at v: left of (down → v) and of (v → up)
    let in_corner =
        |w: usize| tn([DOWN, V, w]) == Sign::Positive && tn([V, UP, w]) == Sign::Positive;
    // a zero turn is straight, or a cusp (an angle of zero: two bodies
    // sliding along each other pinch the face)
    let cusp = s == Sign::Zero && !between_on(world, j.prev, v, j.next, t, side);
    // (each side's turn read only where the other does not decide)
    let in_face = |x: usize| {
        let (l, r) = (|| tn([PREV, V, x]), || tn([V, NEXT, x]));
        match s {
            Sign::Positive => l() == Sign::Positive && r() == Sign::Positive,
            Sign::Negative => l() == Sign::Positive || r() == Sign::Positive,
            Sign::Zero => !cusp && l() == Sign::Positive,
        }
    };
    for w in [PREV, NEXT] {
        if pts[w].obj != v.obj && in_corner(w) {
            return false;
        }
    }
    for x in [UP, DOWN] {
        if pts[x] != j.prev && pts[x] != j.next && in_face(x) {
            return false;
        }
    }
    true
}

/// The junction certificates [`Kss::known`] holds, for one check.
#[derive(Clone, Copy)]
struct Known<'a>(&'a Certs);

impl Known<'_> {
    /// The known certificate of junction `j` (its triple, rotated), if any.
    fn known_junction(self, j: &Junction) -> Option<Cert> {
        let p = super::certs::rotate_to_min([j.prev, j.v, j.next]);
        self.0.iter().find(|c| c.p == p).copied()
    }
}

/// Sort `certs` and drop repeats.
fn sort_dedup(certs: &mut Certs) {
    certs.sort();
    dedup_sorted(certs);
}

/// Drop the repeats of sorted `xs` (`Vec::dedup` for an `ArrayVec`).
pub(crate) fn dedup_sorted<T: PartialEq + Copy, const N: usize>(xs: &mut ArrayVec<T, N>) {
    let mut kept = 0;
    for i in 0..xs.len() {
        if kept == 0 || xs[i] != xs[kept - 1] {
            xs[kept] = xs[i];
            kept += 1;
        }
    }
    xs.truncate(kept);
}

/// The junctions of `faces` (a corridor's, [`Kss::faces_with`]), face by
/// face (`None` for a face with fewer than three vertices).
fn junctions_of(world: &Geo, faces: &ArrayVec<Face, 2>) -> ArrayVec<Option<FaceJunctions>, 2> {
    faces.iter().map(|f| face_junctions(world, f)).collect()
}

/// The junctions of face `f` ([`junctions_of`]).
fn face_junctions(world: &Geo, f: &Face) -> Option<FaceJunctions> {
    if f.p[0].len == 0 && f.p[1].len == 0 {
        return None;
    }
    let last = |p: Piece| p.end;
    let mut out = FaceJunctions::new();
    for x in 0..2 {
        let p = f.p[x];
        let (prev_piece, next_piece) = (f.p[1 - x], f.p[1 - x]);
        let (e_in, e_out) = (f.e[1 - x], f.e[x]);
        let before = last(prev_piece);
        let after = next_piece.start;
        if p.len == 0 {
            out.push(Junction {
                prev: before,
                v: p.start,
                next: after,
                in_edge: e_in,
                out_edge: e_out,
            });
        } else {
            let l = last(p);
            out.push(Junction {
                prev: before,
                v: p.start,
                next: step_cw(world, p.start, 1),
                in_edge: e_in,
                out_edge: EdgeRef::Chain,
            });
            out.push(Junction {
                prev: step_ccw(world, l),
                v: l,
                next: after,
                in_edge: EdgeRef::Chain,
                out_edge: e_out,
            });
        }
    }
    Some(out)
}

/// [`junctions_of`] as corners ([`Kss::corners_with`]).
fn corners_of(world: &Geo, faces: &ArrayVec<Face, 2>) -> ArrayVec<Option<ArrayVec<Corner, 4>>, 2> {
    faces
        .iter()
        .map(|f| {
            face_junctions(world, f).map(|js| {
                let n = js.len();
                // the junction leaving each bridge of length zero
                let merged: ArrayVec<bool, 4> = (0..n)
                    .map(|x| {
                        let y = (x + 1) % n;
                        js[x].out_edge != EdgeRef::Chain
                            && js[y].in_edge == js[x].out_edge
                            && coincide_forever(world, js[x].v, js[y].v)
                    })
                    .collect();
                if !merged.contains(&true) {
                    return js.into_iter().map(|j| (j, None)).collect();
                }
                // (the face's other junctions name each corner by the
                // end kept, as the face's cycle of places does)
                let named = |a: Att| {
                    (0..n)
                        .find(|&x| merged[x] && js[(x + 1) % n].v == a)
                        .map_or(a, |x| js[x].v)
                };
                (0..n)
                    .filter(|&y| !merged[(y + n - 1) % n])
                    .map(|x| {
                        let j = js[x];
                        if merged[x] {
                            let j2 = js[(x + 1) % n];
                            let corner = Junction {
                                prev: named(j.prev),
                                v: j.v,
                                next: named(j2.next),
                                in_edge: j.in_edge,
                                out_edge: j2.out_edge,
                            };
                            (corner, Some(j2.v))
                        } else {
                            let j = Junction {
                                prev: named(j.prev),
                                next: named(j.next),
                                ..j
                            };
                            (j, None)
                        }
                    })
                    .collect()
            })
        })
        .collect()
}

impl Kss {
    /// The faces of corridor `k` between two bodies as pieces (none for an
    /// empty corridor or an ω-corridor), using middle bridge `mid`.
    fn faces_with(&self, world: &Geo, k: CorrId, mid: Option<(u32, u32)>) -> ArrayVec<Face, 2> {
        let c = &self.corrs[k.0 as usize];
        let mut out = ArrayVec::new();
        if c.b == Obj::Omega || (c.len_a == 0 && c.len_b == 0) {
            return out;
        }
        // (chain a runs clockwise from a_s over len_a edges to a_t, chain b
        // from b_t to b_s)
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let piece = |start: Att, len: u32, end: Att| {
            debug_assert_eq!(end, step_cw(world, start, len), "a chain's end");
            Piece { start, len, end }
        };
        match mid {
            None => out.push(Face {
                p: [piece(a_s, c.len_a, a_t), piece(b_t, c.len_b, b_s)],
                e: [EdgeRef::EndT, EdgeRef::EndS],
            }),
            Some((i, j)) => {
                let alpha = step_cw(world, a_s, i);
                let beta = step_cw(world, b_t, j);
                out.push(Face {
                    p: [piece(a_s, i, alpha), piece(beta, c.len_b - j, b_s)],
                    e: [EdgeRef::Mid, EdgeRef::EndS],
                });
                out.push(Face {
                    p: [piece(alpha, c.len_a - i, a_t), piece(b_t, j, beta)],
                    e: [EdgeRef::EndT, EdgeRef::Mid],
                });
            }
        }
        out
    }

    /// The junctions of the faces of corridor `k` with middle bridge `mid`,
    /// face by face (`None` for a face with fewer than three vertices).
    fn junctions_with(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
    ) -> ArrayVec<Option<FaceJunctions>, 2> {
        junctions_of(world, &self.faces_with(world, k, mid))
    }

    /// The junctions of corridor `k` as it stands, all faces together.
    pub fn junctions(&self, world: &Geo, k: CorrId) -> ArrayVec<Junction, 8> {
        let mid = self.corrs[k.0 as usize].mid;
        self.junctions_with(world, k, mid)
            .into_iter()
            .flatten()
            .flatten()
            .collect()
    }

    /// [`Kss::junctions_with`] as corners: where a bridge's two ends rest
    /// on each other ([`coincide_forever`]: a vertex on a vertex, a bridge
    /// of length zero), the two junctions at it are one corner,
    /// `(prev, α, next)` of the one that leaves the bridge and the one
    /// that enters it, paired with the end left out (which the face's other
    /// junctions then name by the end kept, as the face's cycle of places does).
    fn corners_with(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
    ) -> ArrayVec<Option<ArrayVec<Corner, 4>>, 2> {
        corners_of(world, &self.faces_with(world, k, mid))
    }

    /// The corners of corridor `k` as it stands (`Kss::corners_with` with its own middle bridge),
    /// all faces together: what its junction certificates are made of.
    pub fn corners(&self, world: &Geo, k: CorrId) -> ArrayVec<Junction, 8> {
        let mid = self.corrs[k.0 as usize].mid;
        self.corners_with(world, k, mid)
            .into_iter()
            .flatten()
            .flatten()
            .map(|(j, _)| j)
            .collect()
    }

    /// Whether every face of corridor `k` with middle bridge `mid` is a
    /// pseudo-triangle just after `t`: three convex junctions, the others
    /// reflex or straight for ever (chain interiors are reflex for ever).
    pub fn faces_valid(&self, world: &Geo, k: CorrId, mid: Option<(u32, u32)>, t: &Time) -> bool {
        self.faces_valid_on(world, k, mid, t, Side::After)
    }

    /// [`Kss::faces_valid`] read on `side` of `t`.
    pub fn faces_valid_on(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
        t: &Time,
        side: Side,
    ) -> bool {
        let sign = |j: &Junction| turn_on(world, j.prev, j.v, j.next, t, side);
        let key = self.faces_key(world, k, mid, (t, side));
        if let Some(v) = world.shapes.faces.get(&key, t) {
            debug_assert_eq!(
                v,
                self.faces_valid_core(world, k, mid, (t, side), &sign, true, &mut None),
                "the validity cache answers for another corridor: {k:?}"
            );
            return v;
        }
        let mut certs = (!self.held.contains_key(&k)).then(Certs::new);
        let reads = world.shapes.faces.exact_reads();
        let v = self.faces_valid_core(world, k, mid, (t, side), &sign, true, &mut certs);
        let certs = certs.filter(|_| v);
        if side == Side::Before {
            // (every sign read at the instant itself, none beside it: the
            // same answer and certificates just after it)
            if world.shapes.faces.exact_reads() == reads {
                let after = self.faces_key(world, k, mid, (t, Side::After));
                world.shapes.faces.put(after, t, v, certs);
            }
            world.shapes.faces.put(key, t, v, None);
        } else {
            world.shapes.faces.put(key, t, v, certs);
        }
        v
    }

    /// Everything [`Kss::faces_valid_on`] reads but the instant itself, as
    /// words: the corridor's objects, chain lengths, middle bridge and
    /// ends, the side, the instant's enclosure, and each body's view
    /// ([`Geo::view_words`]).
    fn faces_key(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
        (t, side): (&Time, Side),
    ) -> super::geo::FacesKey {
        let c = &self.corrs[k.0 as usize];
        let obj = |o: Obj| Att { obj: o, v: 0 }.word();
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let [va, ua] = world.obj_view_words(c.a);
        let [vb, ub] = world.obj_view_words(c.b);
        let tiv = t.interval();
        [
            obj(c.a),
            obj(c.b),
            (u64::from(c.len_a) << 32) | u64::from(c.len_b),
            mid.map_or(u64::MAX, |(i, j)| (u64::from(i) << 32) | u64::from(j)),
            a_s.word(),
            b_s.word(),
            a_t.word(),
            b_t.word(),
            u64::from(side == Side::After),
            tiv.lo.to_bits(),
            tiv.hi.to_bits(),
            va,
            ua,
            vb,
            ub,
        ]
    }

    /// [`Kss::faces_valid`] with the junction signs given by `sign`, on the
    /// sign pattern alone.
    fn faces_valid_signed(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
        t: &Time,
        sign: &dyn Fn(&Junction) -> Sign,
    ) -> bool {
        self.faces_valid_core(world, k, mid, (t, Side::After), sign, false, &mut None)
    }

    /// Whether corridor `k`'s faces with middle bridge `mid` are
    /// pseudo-triangles on `side` of `t`, the junctions signed by `sign`
    /// (with `clear`, each junction keeping its polygon out of its face
    /// too). Collects into `certs` (when given) the junction certificates
    /// that [`Kss::corridor_certs`] makes of the faces' corners; sets it to
    /// `None` where it cannot (an ω-corridor, a zero turn, whose
    /// certificate is an order one, or a face skipped as a path traversed
    /// twice).
    #[allow(clippy::too_many_arguments)]
    fn faces_valid_core(
        &self,
        world: &Geo,
        k: CorrId,
        mid: Option<(u32, u32)>,
        (t, side): (&Time, Side),
        sign: &dyn Fn(&Junction) -> Sign,
        clear: bool,
        certs: &mut Option<Certs>,
    ) -> bool {
        let c = &self.corrs[k.0 as usize];
        if c.b == Obj::Omega {
            *certs = None;
        }
        if let Some((i, j)) = mid {
            if i > c.len_a || j > c.len_b || (i == 0 && j == c.len_b) || (i == c.len_a && j == 0) {
                return false;
            }
        }
        let shapes = self.faces_with(world, k, mid);
        // (the junctions known to hold: only with `clear`, just after the
        // instant they are known at)
        let known = self
            .known
            .as_ref()
            .filter(|(at, _)| clear && side == Side::After && at.is_known_same(t))
            .map(|(_, certs)| Known(certs));
        // (two bodies that move alike may leave a face that is a path
        // traversed twice: an edge resting on an identical edge)
        let alike = match (c.a, c.b) {
            (Obj::Body(a), Obj::Body(b)) => world.body(a).same_velocity(world.body(b)),
            _ => false,
        };
        // (the points placed at `t` so far, shared by the junctions)
        let mut memo = PointMemo::<16>::default();
        // (read in place: a face's corners are a few hundred bytes)
        let corners = corners_of(world, &shapes);
        for (fi, face) in corners.iter().enumerate() {
            if alike {
                let f = shapes[fi];
                let cycle: Vec<Att> =
                    f.p.iter()
                        .flat_map(|p| (0..=p.len).map(move |x| (p.start, x)))
                        .map(|(a, x)| step_cw(world, a, x))
                        .collect();
                let places = super::faces::collapse_resting(world, &cycle);
                if super::faces::doubly_traversed(world, &places) {
                    *certs = None;
                    continue;
                }
            }
            let Some(js) = face else {
                // a face with two vertices: only an empty corridor has one
                if c.len_a == 0 && c.len_b == 0 {
                    continue;
                }
                return false;
            };
            let mut convex = 0;
            let mut all_zero = true;
            for (j, rest) in js {
                // a face with two places (a resting corner with a single
                // vertex opposite) is no pseudo-triangle
                if rest.is_some() && j.prev == j.next {
                    return false;
                }
                // a junction whose certificate is known to hold just after
                // `t` (`Kss::known`): its sign as it was. Not at a point of
                // the certificate being handled, which is zero at `t`. Its
                // clearance is tested all the same, but in the check of a
                // corridor as an operation left it for the only failure of
                // its instant (`Kss::trust_op`): a certificate names its
                // three points, not which of them was the vertex of the
                // junction it was made for (a triangular face's three
                // corners share one), and the junction on the same points
                // at another vertex was never tested.
                if let Some(cert) = known
                    .filter(|_| rest.is_none())
                    .filter(|_| !self.handling.is_some_and(|h| h.contains(&j.v)))
                    .and_then(|k| k.known_junction(j))
                {
                    debug_assert_eq!(
                        cert.sign,
                        sign(j),
                        "a known junction {j:?} has another sign just after the instant"
                    );
                    if self.trust_op.get() {
                        debug_assert!(
                            junction_clear(world, j, cert.sign, t, side),
                            "a junction {j:?} of an operation's corridor is not clear of its polygon"
                        );
                    } else {
                        let placed = Placed::of_with(world, j, t, &mut memo);
                        if !junction_clear_placed(world, j, cert.sign, (t, side), &placed) {
                            return false;
                        }
                    }
                    all_zero = false;
                    if let Some(cs) = certs.as_mut() {
                        if cs.try_push(cert).is_err() {
                            *certs = None;
                        }
                    }
                    if cert.sign == Sign::Positive {
                        convex += 1;
                    }
                    continue;
                }
                // (with `clear`, the sign is the turn on `side` of `t`:
                // the junction's points are placed once for the filter of
                // that turn and for its clearance)
                // (in the check of the corridor as the operation left it,
                // for the only failure of its instant, the clearance of a
                // junction that does not turn straight is not tested:
                // `Kss::trust_op`; its vertex's neighbours are placed only
                // where it is)
                let trust = known.is_some() && self.trust_op.get();
                let mut placed = if !clear {
                    None
                } else if trust {
                    Some(Placed::of_turn_with(world, j, t, &mut memo))
                } else {
                    Some(Placed::of_with(world, j, t, &mut memo))
                };
                let s = match placed.as_ref() {
                    Some(placed) => {
                        let s = placed.turn_on(world, t, side);
                        debug_assert_eq!(s, sign(j), "the placed turn of {j:?} is not its sign");
                        s
                    }
                    None => sign(j),
                };
                all_zero &= s == Sign::Zero;
                if s == Sign::Zero {
                    *certs = None;
                } else if let Some(cs) = certs.as_mut() {
                    let cert = Cert {
                        p: [j.prev, j.v, j.next],
                        sign: s,
                        kind: CertKind::Junction,
                    }
                    .canonical();
                    if cs.try_push(cert).is_err() {
                        *certs = None;
                    }
                }
                // the end of a bridge of length zero left out of the corner
                // keeps its polygon out of the face too
                if let Some(r) = rest {
                    let other = Junction { v: *r, ..*j };
                    if clear && !junction_clear(world, &other, s, t, side) {
                        return false;
                    }
                }
                // a junction must also keep its polygon out of the face (a
                // pseudo-triangle's sign pattern alone allows a face that
                // wraps around a vertex); not checked when some signs are
                // held against the motion (the geometry just after the
                // instant is the failing one until those are handled)
                // (not for a junction the operation made, in the check of
                // the corridor as the operation left it for the only
                // failure of its instant: `Kss::trust_op`)
                if let Some(placed) = placed.as_mut() {
                    if trust && s != Sign::Zero {
                        debug_assert!(
                            {
                                placed.complete(world, t, &mut memo);
                                junction_clear_placed(world, j, s, (t, side), placed)
                            },
                            "a junction {j:?} that an operation made is not clear of its polygon"
                        );
                    } else {
                        placed.complete(world, t, &mut memo);
                        if !junction_clear_placed(world, j, s, (t, side), placed) {
                            return false;
                        }
                    }
                }
                match s {
                    Sign::Positive => convex += 1,
                    Sign::Negative => {}
                    Sign::Zero => {
                        // a zero turn just after an instant is zero for
                        // ever (a vertex sliding along an edge's line):
                        // straight, or a cusp (a convex corner of angle
                        // zero, where two sliding bodies pinch the face)
                        if between_on(world, j.prev, j.v, j.next, t, side) {
                        } else if between_on(world, j.v, j.prev, j.next, t, side)
                            || between_on(world, j.v, j.next, j.prev, t, side)
                            // (or its two neighbours rest on each other: the
                            // corner at a bridge of length zero, between two
                            // polygons flush along an edge, is a cusp too)
                            || coincide_forever(world, j.prev, j.next)
                        {
                            convex += 1;
                        } else {
                            return false;
                        }
                    }
                }
            }
            // a face whose pieces are single vertices has fewer junction
            // entries than vertices only when a piece repeats a triple;
            // triangles list each corner once per piece end
            // a flat face: every vertex on one line for ever (two bodies
            // sliding flush along a common line, their chains single edges
            // that overlap): its two ends are cusps and the rest straight
            let flat = all_zero && convex == 2 && shapes[fi].p.iter().all(|p| p.len <= 1);
            if convex != 3 && !flat {
                return false;
            }
        }
        // checked last: the faces above reject most candidates more cheaply
        match (clear, mid) {
            (true, Some(m)) if c.b != Obj::Omega => {
                !self.bridge_over_flush_edges(world, k, m, (t, side), &mut memo)
            }
            _ => true,
        }
    }

    /// Whether middle bridge `(i, j)` of corridor `k` runs along an edge of
    /// *each* of its bodies just on `side` of `t`: a neighbour of each end
    /// lies strictly inside the bridge. The two inner vertices then sit in
    /// different faces and no certificate sees them meet (issue 4's known
    /// failure: a contact on that line missed); the tangent bridge between
    /// the inner vertices is the one to take.
    pub(crate) fn bridge_over_flush_edges<const N: usize>(
        &self,
        world: &Geo,
        k: CorrId,
        (i, j): (u32, u32),
        (t, side): (&Time, Side),
        memo: &mut PointMemo<N>,
    ) -> bool {
        let c = &self.corrs[k.0 as usize];
        let (a_s, _, _, b_t) = self.ends(k);
        let alpha = step_cw(world, a_s, i);
        let beta = step_cw(world, b_t, j);
        // an end's neighbours along its chain (only there is the bridge
        // between the inner vertices a decomposition of the corridor too)
        let along = |x: Att, at: u32, len: u32| {
            [
                (at > 0).then(|| step_ccw(world, x)),
                (at < len).then(|| step_cw(world, x, 1)),
            ]
        };
        let mut inside = |x: Att, ns: [Option<Att>; 2], y: Att| {
            ns.into_iter().flatten().any(|n| {
                n != x
                    && turn_on_memo(world, memo, [x, n, y], t, side) == Sign::Zero
                    && between_on(world, x, n, y, t, side)
            })
        };
        inside(alpha, along(alpha, i, c.len_a), beta)
            && inside(beta, along(beta, j, c.len_b), alpha)
    }

    /// The certificates owned by partition triangle `t`.
    pub fn triangle_certs(&self, tri: TriId) -> Certs {
        let c = self.tris[tri.0 as usize].c;
        let mut out = Certs::new();
        if c.iter().any(|a| a.is_omega()) {
            return out;
        }
        out.push(
            Cert {
                p: c,
                sign: Sign::Positive,
                kind: CertKind::Triangle,
            }
            .canonical(),
        );
        out
    }

    /// The certificates owned by corridor `k` at time `t`: its junctions
    /// (with the class they have just after `t`) or, for an ω-corridor, the
    /// hull turns at its hull-bridge ends. Turns that are identically zero
    /// are left out.
    pub fn corridor_certs(&self, world: &Geo, k: CorrId, t: &Time) -> Certs {
        let c = &self.corrs[k.0 as usize];
        if c.b != Obj::Omega && !self.held.contains_key(&k) {
            let key = self.faces_key(world, k, c.mid, (t, Side::After));
            // (the certificates read off the faces when the validity
            // cache last found this corridor valid at this instant)
            if let Some(mut out) = world.shapes.faces.certs(&key, t) {
                sort_dedup(&mut out);
                debug_assert_eq!(
                    out,
                    self.corridor_certs_fresh(world, k, t),
                    "the validity cache's certificates are another corridor's: {k:?}"
                );
                return out;
            }
        }
        self.corridor_certs_fresh(world, k, t)
    }

    /// [`Kss::corridor_certs`] read from the corners' turns.
    fn corridor_certs_fresh(&self, world: &Geo, k: CorrId, t: &Time) -> Certs {
        let flipped: &[[Att; 3]] = self.held.get(&k).map_or(&[], |v| v.as_slice());
        let mut out = Certs::new();
        let c = &self.corrs[k.0 as usize];
        if c.b == Obj::Omega {
            for (p, _) in self.hull_turns(world, k) {
                if turn(world, p[0], p[1], p[2], t) != Sign::Zero {
                    out.push(
                        Cert {
                            p,
                            sign: Sign::Positive,
                            kind: CertKind::HullTurn,
                        }
                        .canonical(),
                    );
                } else if let Some(c) = order_cert(world, p, t) {
                    out.push(c);
                }
            }
        } else {
            for j in self.corners(world, k) {
                let mut sign = turn(world, j.prev, j.v, j.next, t);
                if flipped.contains(&[j.prev, j.v, j.next]) {
                    sign = sign.neg();
                }
                if sign != Sign::Zero {
                    out.push(
                        Cert {
                            p: [j.prev, j.v, j.next],
                            sign,
                            kind: CertKind::Junction,
                        }
                        .canonical(),
                    );
                } else if let Some(c) = order_cert(world, [j.prev, j.v, j.next], t) {
                    out.push(c);
                }
            }
        }
        sort_dedup(&mut out);
        out
    }

    /// The hull turns of ω-corridor `k`, each with the vertex it certifies:
    /// `(a_s − 1, a_s, x)` and `(y, a_t, a_t + 1)`, or `(y, a_s, x)` when
    /// `a_s` is its polygon's only hull vertex (`x`, `y`: the hull
    /// neighbours on other objects).
    pub fn hull_turns(&self, world: &Geo, k: CorrId) -> ArrayVec<([Att; 3], Att), 2> {
        let c = &self.corrs[k.0 as usize];
        let (a_s, _, a_t, _) = self.ends(k);
        let x = self.other_finite_corner(c.s.0, a_s);
        let y = self.other_finite_corner(c.t.0, a_t);
        let mut out = ArrayVec::new();
        if c.len_a == 0 {
            out.push(([y, a_s, x], a_s));
        } else {
            out.push(([step_cw(world, a_s, 1), a_s, x], a_s));
            out.push(([y, a_t, step_ccw(world, a_t)], a_t));
        }
        out
    }

    /// Whether corridor `k` has four convex corners just after `t` (it needs
    /// a middle bridge), given both chains are non-empty.
    fn four_corners(&self, world: &Geo, k: CorrId, t: &Time, side: Side) -> bool {
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let conv = |u, v, w| turn_on(world, u, v, w, t, side) == Sign::Positive;
        conv(b_s, a_s, step_cw(world, a_s, 1))
            && conv(step_ccw(world, a_t), a_t, b_t)
            && conv(a_t, b_t, step_cw(world, b_t, 1))
            && conv(step_ccw(world, b_s), b_s, a_s)
    }

    /// Restore corridor `k`'s faces to pseudo-triangles just after `t`.
    /// Keeps a valid middle bridge; otherwise drops it when the corridor has
    /// three convex corners, or walks it from its old place (or from `hint`)
    /// to a valid one. Where none holds just after `t` (other failures of
    /// the instant are still to be handled), it keeps one that holds with
    /// some junctions that are zero at `t` held against the motion
    /// ([`Kss::held`]); the candidates are the middle bridge it had, the
    /// one from just before `t`, none, the walks' results just after `t`
    /// and the bridges between two vertices that touch at `t`, and it takes
    /// the first that works (with [`Kss::fewest_held`] at `t`, the one holding the
    /// fewest). Returns how many walk steps a repair took (0 when nothing
    /// was repaired), or an error if no decomposition was found.
    pub fn normalize(
        &mut self,
        world: &Geo,
        k: CorrId,
        t: &Time,
        hint: Option<(u32, u32)>,
    ) -> Result<u32, StructureError> {
        // (the walks of this call are remembered until it returns)
        *self.walk_memo.borrow_mut() = Some(super::WalkMemo::default());
        let r = self.normalize_walking(world, k, t, hint);
        *self.walk_memo.borrow_mut() = None;
        r
    }

    /// [`Kss::normalize`] with the walk memo on.
    fn normalize_walking(
        &mut self,
        world: &Geo,
        k: CorrId,
        t: &Time,
        hint: Option<(u32, u32)>,
    ) -> Result<u32, StructureError> {
        super::counters::bump(super::counters::Counter::Normalizations);
        let ki = k.0 as usize;
        let c = &self.corrs[ki];
        if c.b == Obj::Omega || (c.len_a == 0 && c.len_b == 0) {
            self.corrs.on_same_bodies(ki).mid = None;
            self.held.remove(&k);
            return Ok(0);
        }
        let (len_a, len_b) = (c.len_a, c.len_b);
        let mid = c
            .mid
            .filter(|&(i, j)| i <= len_a && j <= len_b)
            .filter(|&(i, j)| !((i == 0 && j == len_b) || (i == len_a && j == 0)));
        self.corrs.on_same_bodies(ki).mid = mid;
        self.held.remove(&k);
        if let Some(steps) = self.decompose(world, k, t, hint, Side::After) {
            return Ok(steps);
        }
        // No decomposition just after `t`: other certificates fail at this
        // instant and their operations are still to come. Keep a
        // decomposition that is valid with some junctions that are zero at
        // `t` read with their sign from just before `t` (all of them, or the
        // fewest that work); those junctions' certificates then fail at once
        // and are handled as further events of this instant.
        // the operation's own middle bridge first (the one from just before
        // the instant may be what the operation just replaced)
        let mut candidates: Vec<Option<(u32, u32)>> = vec![mid];
        if self.decompose(world, k, t, hint, Side::Before).is_some() {
            candidates.push(self.corrs[ki].mid);
        }
        candidates.push(None);
        // (an end junction that fails at this instant keeps `decompose` from
        // walking the middle bridge: the walk's own tangencies just after
        // the instant give the candidates that go with the end's slide)
        if len_a > 0 && len_b > 0 {
            let starts: Vec<(u32, u32)> = [mid, hint, Some((0, 0)), Some((len_a, len_b))]
                .into_iter()
                .flatten()
                .collect();
            let walked: Vec<(u32, u32)> = self
                .walks(world, k, (t, Side::After), &starts)
                .map(|(m, _)| m)
                .collect();
            for m in walked {
                if !candidates.contains(&Some(m)) {
                    candidates.push(Some(m));
                }
            }
        }
        for m in self.touching_bridges(world, k, t) {
            if !candidates.contains(&Some(m)) {
                candidates.push(Some(m));
            }
        }
        // (a walked bridge may hold outright: `decompose` walks only where
        // the four corners are convex)
        for &m in &candidates[1..] {
            if m.is_some() && self.faces_valid_on(world, k, m, t, Side::After) {
                self.corrs.on_same_bodies(ki).mid = m;
                return Ok(1);
            }
        }
        // (the first candidate that works; or, once the operations at this
        // instant were seen to cycle, the one that holds the fewest
        // junctions against the motion: a junction held needlessly can hand
        // an edge back and forth with a neighbour, see `fewest_held`)
        type Held = (Option<(u32, u32)>, Vec<[Att; 3]>);
        let mut best: Option<Held> = None;
        for m in candidates {
            if let Some(flips) = self.fewest_flips(world, k, m, t) {
                if best.as_ref().is_none_or(|(_, b)| flips.len() < b.len()) {
                    let done = flips.len() <= 1 || self.fewest_held.as_ref() != Some(t);
                    best = Some((m, flips));
                    if done {
                        break;
                    }
                }
            }
        }
        if let Some((m, flips)) = best {
            self.corrs.on_same_bodies(ki).mid = m;
            if !flips.is_empty() {
                self.held.insert(k, flips);
            }
            return Ok(1);
        }
        self.corrs.on_same_bodies(ki).mid = mid;
        #[cfg(feature = "trace")]
        {
            eprintln!(
                "normalize failed: {:?} ends {:?}",
                self.corrs[ki],
                self.ends(k)
            );
            for m in [mid, None] {
                for j in self
                    .junctions_with(world, k, m)
                    .into_iter()
                    .flatten()
                    .flatten()
                {
                    eprintln!(
                        "  mid {m:?}: {:?} {:?} {:?} before {:?} after {:?}",
                        j.prev,
                        j.v,
                        j.next,
                        turn_on(world, j.prev, j.v, j.next, t, Side::Before),
                        turn_on(world, j.prev, j.v, j.next, t, Side::After)
                    );
                }
            }
        }
        Err(StructureError::Local(format!(
            "corridor {ki}: no pseudo-triangle decomposition found (len {len_a}/{len_b}, mid {mid:?})"
        )))
    }

    /// The fewest junctions of corridor `k` with middle bridge `m`, among
    /// those whose turn is zero at `t` (but not for ever), whose sign must be
    /// reversed from the one just after `t` for every face to be a
    /// pseudo-triangle; `None` if no such set exists.
    fn fewest_flips(
        &self,
        world: &Geo,
        k: CorrId,
        m: Option<(u32, u32)>,
        t: &Time,
    ) -> Option<Vec<[Att; 3]>> {
        let faces = self.corners_with(world, k, m);
        let js: Vec<Junction> = faces.iter().flatten().flatten().map(|(j, _)| *j).collect();
        let zero: Vec<usize> = (0..js.len())
            .filter(|&x| {
                let j = js[x];
                // (a turn the f64 filter decides at `t` is not zero there)
                if world
                    .orient_filtered(j.prev, j.v, j.next, t.interval())
                    .is_some()
                {
                    return false;
                }
                let p = crate::motion::orient_poly(
                    &lin(world, j.prev),
                    &lin(world, j.v),
                    &lin(world, j.next),
                );
                p.sign_after(t) != Sign::Zero
                    && p.sign_at(t) == Sign::Zero
                    && self.handling.map(super::certs::rotate_to_min)
                        != Some(super::certs::rotate_to_min([j.prev, j.v, j.next]))
            })
            .collect();
        #[cfg(feature = "trace")]
        eprintln!(
            "fewest_flips mid {m:?}: {} junctions, zero at t: {:?}",
            js.len(),
            zero.iter()
                .map(|&x| (js[x].prev, js[x].v, js[x].next))
                .collect::<Vec<_>>()
        );
        if zero.is_empty() || zero.len() > 10 {
            return None;
        }
        let mut masks: Vec<u32> = (1..(1u32 << zero.len())).collect();
        masks.sort_by_key(|m| m.count_ones());
        for mask in masks {
            let flips: Vec<[Att; 3]> = (0..zero.len())
                .filter(|b| mask & (1 << b) != 0)
                .map(|b| {
                    let j = js[zero[b]];
                    [j.prev, j.v, j.next]
                })
                .collect();
            let sign = |j: &Junction| {
                let s = turn(world, j.prev, j.v, j.next, t);
                if flips.contains(&[j.prev, j.v, j.next]) {
                    s.neg()
                } else {
                    s
                }
            };
            if self.faces_valid_signed(world, k, m, t, &sign) {
                return Some(flips);
            }
        }
        None
    }

    /// Find a middle bridge (or none) that makes corridor `k`'s faces
    /// pseudo-triangles just on `side` of `t`, keeping the current one if it
    /// does; sets it and returns the walk length (0: nothing changed).
    pub(crate) fn decompose(
        &mut self,
        world: &Geo,
        k: CorrId,
        t: &Time,
        hint: Option<(u32, u32)>,
        side: Side,
    ) -> Option<u32> {
        let ki = k.0 as usize;
        let (len_a, len_b, mid) = {
            let c = &self.corrs[ki];
            (c.len_a, c.len_b, c.mid)
        };
        // (the corridor as the operation left it: see `Kss::trust_op`)
        self.trust_op.set(self.op_alone && self.known.is_some());
        let kept = self.faces_valid_on(world, k, mid, t, side);
        if kept && self.trust_op.get() {
            super::counters::bump(super::counters::Counter::TrustedChecks);
        }
        self.trust_op.set(false);
        if kept {
            return Some(0);
        }
        if len_a > 0 && len_b > 0 && self.four_corners(world, k, t, side) {
            let starts: Vec<(u32, u32)> = hint
                .into_iter()
                .chain(mid)
                .chain([(0, 0), (len_a, len_b)])
                .collect();
            let found = self
                .walks(world, k, (t, side), &starts)
                .find(|&(m, _)| self.faces_valid_on(world, k, Some(m), t, side));
            if let Some((m, steps)) = found {
                self.corrs.on_same_bodies(ki).mid = Some(m);
                return Some(steps.max(1));
            }
        } else if self.faces_valid_on(world, k, None, t, side) {
            self.corrs.on_same_bodies(ki).mid = None;
            return Some(1);
        }
        // two chains that rest on each other at a vertex pinch the corridor
        // there: the bridge of length zero between those vertices
        for m in self.resting_bridges(world, k, t) {
            if Some(m) != mid && self.faces_valid_on(world, k, Some(m), t, side) {
                self.corrs.on_same_bodies(ki).mid = Some(m);
                return Some(1);
            }
        }
        // two chains that touch at `t` (a vertex on a vertex, parting just
        // after) may pinch the corridor there: the bridge between them
        for m in self.touching_bridges(world, k, t) {
            if Some(m) != mid && self.faces_valid_on(world, k, Some(m), t, side) {
                self.corrs.on_same_bodies(ki).mid = Some(m);
                return Some(1);
            }
        }
        None
    }

    /// The middle bridges `(i, j)` of corridor `k` between a vertex of each
    /// chain that coincide at `t`, among the corridor's end vertices and the
    /// points of the certificate being handled (where a vertex touched a
    /// vertex at this instant). Tried only when no other decomposition
    /// holds: the at most seven points are compared first
    /// ([`super::faces::coincide_at`]), and only a pair that coincides is
    /// placed on the chains
    /// ([`Geo::cw_distance`], ranks in each approximation's exposed set).
    fn touching_bridges(&self, world: &Geo, k: CorrId, t: &Time) -> Vec<(u32, u32)> {
        let c = &self.corrs[k.0 as usize];
        let (len_a, len_b) = (c.len_a, c.len_b);
        if c.b == Obj::Omega || len_a == 0 || len_b == 0 {
            return Vec::new();
        }
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let mut pts: Vec<Att> = vec![a_s, b_s, a_t, b_t];
        pts.extend(self.handling.into_iter().flatten());
        pts.sort();
        pts.dedup();
        let mut out = Vec::new();
        for &x in pts.iter().filter(|x| x.obj == c.a) {
            for &y in pts.iter().filter(|y| y.obj == c.b) {
                if !super::faces::coincide_at(world, x, y, t) {
                    continue;
                }
                let (Some(i), Some(j)) = (
                    world.cw_distance(a_s, x, len_a),
                    world.cw_distance(b_t, y, len_b),
                ) else {
                    continue;
                };
                if (i == 0 && j == len_b) || (i == len_a && j == 0) || out.contains(&(i, j)) {
                    continue;
                }
                out.push((i, j));
            }
        }
        out
    }

    /// The middle bridges `(i, j)` of corridor `k` whose two ends rest on
    /// each other ([`coincide_forever`]), where its chains touch that way.
    /// Tried only when no other decomposition holds, and only when the two
    /// bodies move alike (`O(1)` otherwise): then `O(len_a · len_b)` f64
    /// comparisons, exact ones only where the enclosures overlap.
    fn resting_bridges(&self, world: &Geo, k: CorrId, t: &Time) -> Vec<(u32, u32)> {
        let c = &self.corrs[k.0 as usize];
        let (len_a, len_b) = (c.len_a, c.len_b);
        let (Obj::Body(ba), Obj::Body(bb)) = (c.a, c.b) else {
            return Vec::new();
        };
        if len_a == 0 || len_b == 0 || !world.body(ba).same_velocity(world.body(bb)) {
            return Vec::new();
        }
        let (a_s, _, _, b_t) = self.ends(k);
        let tiv = t.interval();
        let a: Vec<(Att, Option<[crate::num::Interval; 2]>)> = (0..=len_a)
            .map(|i| {
                let x = step_cw(world, a_s, i);
                (x, world.enclose(x, tiv))
            })
            .collect();
        let b: Vec<(Att, Option<[crate::num::Interval; 2]>)> = (0..=len_b)
            .map(|j| {
                let y = step_cw(world, b_t, j);
                (y, world.enclose(y, tiv))
            })
            .collect();
        let mut out = Vec::new();
        for (i, (x, ex)) in a.iter().enumerate() {
            for (j, (y, ey)) in b.iter().enumerate() {
                let (i, j) = (i as u32, j as u32);
                // (the end bridges are not middle bridges)
                if (i == 0 && j == len_b) || (i == len_a && j == 0) {
                    continue;
                }
                if let (Some(ex), Some(ey)) = (ex, ey) {
                    if !ex[0].overlaps(&ey[0]) || !ex[1].overlaps(&ey[1]) {
                        continue;
                    }
                }
                if coincide_forever(world, *x, *y) {
                    out.push((i, j));
                }
            }
        }
        out
    }

    /// The middle bridges reached by walking from each of `starts` with
    /// either diagonal type ([`Kss::walk`], at most `2(len_a + len_b) + 8`
    /// steps each), with their walk lengths, lazily and in that order.
    fn walks<'a>(
        &'a self,
        world: &'a Geo,
        k: CorrId,
        (t, side): (&'a Time, Side),
        starts: &'a [(u32, u32)],
    ) -> impl Iterator<Item = ((u32, u32), u32)> + 'a {
        let c = &self.corrs[k.0 as usize];
        let limit = 2 * (c.len_a + c.len_b) + 8;
        starts.iter().flat_map(move |&start| {
            [Diagonal::SourceToTarget, Diagonal::TargetToSource]
                .into_iter()
                .filter_map(move |ty| self.walk(world, k, (t, side), start, ty, limit))
        })
    }

    /// Walk a middle bridge of diagonal type `ty` from `start` until its four
    /// tangency conditions hold just on `side` of `t`, in at most `limit`
    /// steps.
    fn walk(
        &self,
        world: &Geo,
        k: CorrId,
        (t, side): (&Time, Side),
        start: (u32, u32),
        ty: Diagonal,
        limit: u32,
    ) -> Option<((u32, u32), u32)> {
        let key: super::WalkKey = (
            k.0,
            start,
            ty == Diagonal::SourceToTarget,
            side == Side::After,
        );
        if let Some(memo) = self.walk_memo.borrow().as_ref() {
            if let Some((_, r)) = memo.walks.iter().find(|(x, _)| *x == key) {
                return *r;
            }
        }
        let r = self.walk_fresh(world, k, (t, side), start, ty, limit);
        if let Some(memo) = self.walk_memo.borrow_mut().as_mut() {
            memo.walks.push((key, r));
        }
        r
    }

    /// [`Kss::walk`] computed.
    fn walk_fresh(
        &self,
        world: &Geo,
        k: CorrId,
        (t, side): (&Time, Side),
        start: (u32, u32),
        ty: Diagonal,
        limit: u32,
    ) -> Option<((u32, u32), u32)> {
        super::counters::bump(super::counters::Counter::Walks);
        let c = &self.corrs[k.0 as usize];
        let (len_a, len_b) = (c.len_a, c.len_b);
        let (a_s, _, _, b_t) = self.ends(k);
        let (mut i, mut j) = (start.0.min(len_a), start.1.min(len_b));
        // a cusp (a zero turn whose neighbours lie on one side of `v`: two
        // sliding bodies pinch the corridor) counts as convex, as in
        // `faces_valid_core`
        // (the walk's points, placed for the midpoint–radius filter once
        // each while they stay near the bridge's two ends: a step moves
        // one end to a neighbour, and the four turns of a step share their
        // points)
        let tiv = t.interval();
        let placed: std::cell::RefCell<PointMemo<8>> = Default::default();
        let place = |a: Att| placed.borrow_mut().place(world, a, tiv);
        // (`Err(true)`: the three points are placed and distinct, and the
        // filter leaves their turn undecided)
        let filtered = |u: Att, v: Att, w: Att| -> Result<Sign, bool> {
            if u == v || v == w || u == w {
                return Err(false);
            }
            let (Some(a), Some(b), Some(c)) = (place(u), place(v), place(w)) else {
                return Err(false);
            };
            let s = crate::geom::orient_mid_rad(a, b, c).ok_or(true)?;
            super::counters::bump(super::counters::Counter::TurnsFiltered);
            Ok(s)
        };
        let tn = |u, v, w| {
            let s = match filtered(u, v, w) {
                Ok(s) => return s,
                Err(true) => turn_on_past_mid_rad(world, u, v, w, t, side),
                Err(false) => turn_on(world, u, v, w, t, side),
            };
            match s {
                Sign::Zero
                    if between_on(world, v, u, w, t, side)
                        || between_on(world, v, w, u, t, side) =>
                {
                    Sign::Positive
                }
                s => s,
            }
        };
        // (the bridge's ends move one step at a time: a step from the
        // previous end, not `i` steps from the chain's start, which costs
        // `O(i)` on an approximation)
        let (mut alpha, mut beta) = (step_cw(world, a_s, i), step_cw(world, b_t, j));
        // Each step is a function of the position alone (the instant and
        // side are fixed), so a walk that comes back to a position cycles
        // and would only run out its limit: it ends there, without a
        // bridge. Where the corridor's positions fit in a bitset of 4096
        // bits, the walk ends at its first return to a position; on longer
        // chains, Brent's cycle detection (the position is compared with
        // one saved at steps 1, 2, 4, 8, ..., which finds any cycle within
        // about twice its length and tail). A walk that fails has no
        // tangent to find and goes round the corridor, often for more
        // steps than its limit allows Brent to see.
        let width = len_b as usize + 1;
        let exact = (len_a as usize + 1) * width <= 64 * 64;
        let mut seen = [0u64; 64];
        // (the positions that earlier walks of this normalization, of this
        // corridor, type and side, passed through into a cycle: every walk
        // that reaches one cycles too, so one that ends in a cycle adds its
        // own)
        let cycle_key = (k.0, ty == Diagonal::SourceToTarget, side == Side::After);
        // (read in place: nothing in the walk writes the memo)
        let memo = exact.then(|| self.walk_memo.borrow());
        let cycling: Option<&[u64; 64]> = memo.as_ref().and_then(|m| {
            m.as_ref()?
                .cycling
                .iter()
                .find(|(x, _)| *x == cycle_key)
                .map(|(_, bits)| &**bits)
        });
        let cycles = |seen: &[u64; 64]| {
            if let Some(memo) = self.walk_memo.borrow_mut().as_mut() {
                match memo.cycling.iter_mut().find(|(x, _)| *x == cycle_key) {
                    Some((_, bits)) => bits.iter_mut().zip(seen).for_each(|(b, s)| *b |= s),
                    None => memo.cycling.push((cycle_key, Box::new(*seen))),
                }
            }
        };
        let (mut saved, mut power) = ((i, j), 1u32);
        for steps in 0..limit {
            if exact {
                let x = i as usize * width + j as usize;
                let bit = 1u64 << (x % 64);
                if seen[x / 64] & bit != 0 || cycling.is_some_and(|c| c[x / 64] & bit != 0) {
                    drop(memo);
                    cycles(&seen);
                    return None;
                }
                seen[x / 64] |= bit;
            } else if steps > 0 {
                if (i, j) == saved {
                    return None;
                }
                if steps == power {
                    (saved, power) = ((i, j), power.saturating_mul(2));
                }
            }
            debug_assert_eq!(alpha, step_cw(world, a_s, i));
            debug_assert_eq!(beta, step_cw(world, b_t, j));
            // α's turn in face t (towards α + 1) and in face s (from α − 1);
            // β's likewise. Each is read only where the rule below needs
            // it, and only where α (β) can move that way: a step is decided
            // by its first rule that holds, most often by one turn.
            let a_in_t = || tn(beta, alpha, step_cw(world, alpha, 1));
            let a_in_s = || tn(step_ccw(world, alpha), alpha, beta);
            let b_in_s = || tn(alpha, beta, step_cw(world, beta, 1));
            let b_in_t = || tn(step_ccw(world, beta), beta, alpha);
            let pos = |s: Sign| s == Sign::Positive;
            let mv: Option<(i64, i64)> = match ty {
                // a_s ⇝ b_t: α convex in t, reflex in s; β convex in s, reflex in t
                Diagonal::SourceToTarget => {
                    if i < len_a && !pos(a_in_t()) {
                        Some((1, 0))
                    } else if i > 0 && pos(a_in_s()) {
                        Some((-1, 0))
                    } else if j < len_b && !pos(b_in_s()) {
                        Some((0, 1))
                    } else if j > 0 && pos(b_in_t()) {
                        Some((0, -1))
                    } else {
                        None
                    }
                }
                // b_s ⇝ a_t: α convex in s, reflex in t; β convex in t, reflex in s
                Diagonal::TargetToSource => {
                    if i > 0 && !pos(a_in_s()) {
                        Some((-1, 0))
                    } else if i < len_a && pos(a_in_t()) {
                        Some((1, 0))
                    } else if j > 0 && !pos(b_in_t()) {
                        Some((0, -1))
                    } else if j < len_b && pos(b_in_s()) {
                        Some((0, 1))
                    } else {
                        None
                    }
                }
            };
            match mv {
                None => return Some(((i, j), steps)),
                Some((di, dj)) => {
                    i = (i as i64 + di) as u32;
                    j = (j as i64 + dj) as u32;
                    let step = |x: Att, d: i64| match d {
                        1 => step_cw(world, x, 1),
                        -1 => step_ccw(world, x),
                        _ => x,
                    };
                    (alpha, beta) = (step(alpha, di), step(beta, dj));
                }
            }
        }
        None
    }
}

/// The two ways to split a corridor with four convex corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Diagonal {
    /// The geodesic from `a_s` to `b_t`.
    SourceToTarget,
    /// The geodesic from `b_s` to `a_t`.
    TargetToSource,
}
