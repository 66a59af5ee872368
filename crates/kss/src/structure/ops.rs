//! The event operations: what the structure does when a certificate fails
//! without a collision.
//!
//! A failing certificate is three points on a line; one of them, `μ`, lies
//! strictly between the other two (`events::classify`). Every case is one of
//!
//! * `μ` lands on a bridge from inside a face next to it along a polygon
//!   edge: that bridge end slides onto `μ` (a middle bridge moves by one
//!   vertex; an end-edge moves its partition triangle's corner, which hands
//!   the polygon edge to the corridor on the far side of the triangle);
//! * a junction of a corridor face turns straight (`μ` is the junction): a
//!   reflex junction becomes convex. Next to a middle bridge the bridge end
//!   slides back over the polygon edge; next to an end-edge the corridor
//!   gains a fourth convex corner and gets the thin middle bridge from the
//!   end-edge's other end to `μ`'s neighbour (the note's E2);
//! * a partition triangle collapses onto its side: across an empty corridor
//!   the two triangles flip; across a non-empty one the triangle's corner
//!   slides along the corridor's first face (an ear slide);
//! * a hull turn goes straight: the hull bridge's end slides off the hull, or,
//!   when it was its polygon's only hull vertex, the hull bridge flips.
//!
//! After an operation the engine normalizes every corridor whose ends,
//! chains or middle bridge changed (`local::normalize`) and refreshes the
//! certificates of those corridors and of every changed triangle. A corridor
//! between two bodies across an unchanged side of a changed triangle keeps
//! its faces and certificates (`Outcome::near`): a slide or a flip moves
//! one corner of a triangle, and only the two corridors at that corner, and
//! hull corridors (whose turns read the triangle's third corner), see it.

use arrayvec::ArrayVec;

use super::certs::rotate_to_min;
use super::faces::{poly_edge, step_ccw, step_cw};
use super::geo::Geo;
use super::local::{dedup_sorted, turn, EdgeRef};
use super::{Att, CorrId, Kss, Obj, PartitionTriangle, TriId};
use crate::num::{Sign, Time};
use crate::structure::StructureError;

/// Which part of the structure a certificate belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Owner {
    /// A finite partition triangle's orientation.
    Tri(TriId),
    /// A corridor's junction or hull turn.
    Corr(CorrId),
}

/// An internal event of the kinetic structure: a certificate failure
/// repaired by a local operation, or a pop of the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum EventKind {
    /// A flip of a partition triangle's side between two bodies.
    Flip,
    /// A flip at the convex hull (a side to `ω`).
    HullFlip,
    /// An ear slide: a corner moves along its chain past a reflex turn.
    EarSlide,
    /// An end slide: a corridor's end-edge slides along a chain.
    EndSlide,
    /// A slide along the convex hull.
    HullSlide,
    /// A middle bridge slides to the next vertex.
    MidSlide,
    /// A thin corridor gets a middle bridge.
    InsertMid,
    /// An approximation vertex of the hierarchy replaced by the finer
    /// vertices below it, where approximations came close.
    Pop,
    /// A pop while the structure is built (the hierarchy refined where
    /// approximations touch at the start).
    InitialPop,
}

impl EventKind {
    /// The name in the statistics (`events_by_kind`).
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Flip => "flip",
            EventKind::HullFlip => "hull_flip",
            EventKind::EarSlide => "ear_slide",
            EventKind::EndSlide => "end_slide",
            EventKind::HullSlide => "hull_slide",
            EventKind::MidSlide => "mid_slide",
            EventKind::InsertMid => "insert_mid",
            EventKind::Pop => "pop",
            EventKind::InitialPop => "initial_pop",
        }
    }
}

impl std::fmt::Display for EventKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What an operation did and what it touched.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The operation.
    pub kind: EventKind,
    /// Partition triangles whose corners changed.
    pub tris: ArrayVec<TriId, 2>,
    /// Corridors whose ends, chains or middle bridge changed (or whose hull
    /// turns depend on a changed triangle): normalized and given their
    /// certificates anew.
    pub corrs: ArrayVec<CorrId, 5>,
    /// Corridors between two bodies next to a changed triangle whose own
    /// ends, chains and middle bridge did not change (their faces and
    /// certificates are what they were): candidates for coarsening only.
    pub near: ArrayVec<CorrId, 4>,
}

/// Whether the three points of `q` and `p` are the same set. A certificate
/// is found among its owner's junctions or hull turns by its triple: a turn
/// certificate is the junction's triple rotated, but an order certificate is
/// stored as `[min end, middle, max end]`, which may be the junction's
/// triple reversed; this is the fallback when no rotation matches.
fn same_points(q: [Att; 3], p: [Att; 3]) -> bool {
    let (mut x, mut y) = (q, p);
    x.sort();
    y.sort();
    x == y
}

impl Kss {
    fn tri_index(&self, t: TriId, a: Att) -> Result<usize, StructureError> {
        self.tris[t.0 as usize]
            .c
            .iter()
            .position(|&c| c == a)
            .ok_or_else(|| {
                StructureError::Local(format!("{a:?} is not a corner of triangle {}", t.0))
            })
    }

    /// Move corner `ci` of triangle `tri` to its polygon neighbour `to`. The
    /// polygon edge between them passes from one of the two corridors at the
    /// corner to the other. Middle-bridge offsets are kept or clamped (the
    /// caller normalizes).
    pub fn corner_slide(
        &mut self,
        world: &Geo,
        tri: TriId,
        ci: usize,
        to: Att,
    ) -> Result<(), StructureError> {
        let v = self.tris[tri.0 as usize].c[ci];
        let cw = to == step_cw(world, v, 1);
        if v.is_omega() || (!cw && to != step_ccw(world, v)) {
            return Err(StructureError::Local(format!(
                "corner slide {v:?} → {to:?} is not along an edge"
            )));
        }
        let k1 = self.tris[tri.0 as usize].corr[ci];
        let s1 = (tri, ci as u8);
        let k0 = self.tris[tri.0 as usize].corr[(ci + 2) % 3];
        let s0 = (tri, ((ci + 2) % 3) as u8);
        let short =
            || StructureError::Local(format!("corner slide {v:?} → {to:?}: chain too short"));
        // corridor k1: v is the first point of its side (a_s or b_t)
        let c = self.corrs.on_same_bodies(k1.0 as usize);
        if c.s == s1 {
            if cw {
                c.len_a = c.len_a.checked_sub(1).ok_or_else(short)?;
                c.mid = c.mid.map(|(i, j)| (i.saturating_sub(1), j));
            } else {
                c.len_a += 1;
                c.mid = c.mid.map(|(i, j)| (i + 1, j));
            }
        } else if c.t == s1 {
            if cw {
                c.len_b = c.len_b.checked_sub(1).ok_or_else(short)?;
                c.mid = c.mid.map(|(i, j)| (i, j.saturating_sub(1)));
            } else {
                c.len_b += 1;
                c.mid = c.mid.map(|(i, j)| (i, j + 1));
            }
        } else {
            return Err(StructureError::Local(
                "corner slide: corridor does not link back".into(),
            ));
        }
        // corridor k0: v is the second point of its side (b_s or a_t)
        let c = self.corrs.on_same_bodies(k0.0 as usize);
        if c.s == s0 {
            if cw {
                c.len_b += 1;
            } else {
                c.len_b = c.len_b.checked_sub(1).ok_or_else(short)?;
                let lb = c.len_b;
                c.mid = c.mid.map(|(i, j)| (i, j.min(lb)));
            }
        } else if c.t == s0 {
            if cw {
                c.len_a += 1;
            } else {
                c.len_a = c.len_a.checked_sub(1).ok_or_else(short)?;
                let la = c.len_a;
                c.mid = c.mid.map(|(i, j)| (i.min(la), j));
            }
        } else {
            return Err(StructureError::Local(
                "corner slide: corridor does not link back".into(),
            ));
        }
        self.tris.on_same_bodies(tri.0 as usize).c[ci] = to;
        Ok(())
    }

    /// Flip the empty corridor across side `e` of triangle `t1`: with
    /// `t1 = (p, q, r)` (side `e` = `(q, r)`) and the triangle across it
    /// `(d, r, q)`, the two become `(p, q, d)` and `(p, d, r)` joined by a
    /// new empty corridor `(p, d)` (which reuses the old one's index).
    pub fn flip(&mut self, t1: TriId, e: usize) -> Result<Outcome, StructureError> {
        let k = self.tris[t1.0 as usize].corr[e];
        let kc = self.corrs[k.0 as usize].clone();
        if kc.len_a != 0 || kc.len_b != 0 {
            return Err(StructureError::Local(
                "flip across a non-empty corridor".into(),
            ));
        }
        let here = (t1, e as u8);
        let (t2, e2) = if kc.s == here {
            kc.t
        } else if kc.t == here {
            kc.s
        } else {
            return Err(StructureError::Local(
                "flip: corridor does not link back".into(),
            ));
        };
        let (e2, tr1, tr2) = (
            e2 as usize,
            self.tris[t1.0 as usize].clone(),
            self.tris[t2.0 as usize].clone(),
        );
        let (q, r, p) = (tr1.c[e], tr1.c[(e + 1) % 3], tr1.c[(e + 2) % 3]);
        if tr2.c[e2] != r || tr2.c[(e2 + 1) % 3] != q {
            return Err(StructureError::Local(
                "flip: the two triangles do not share the side".into(),
            ));
        }
        let d = tr2.c[(e2 + 2) % 3];
        if d.obj == p.obj {
            return Err(StructureError::Local(
                "flip would join two vertices of one object".into(),
            ));
        }
        let c_pq = tr1.corr[(e + 2) % 3];
        let c_rp = tr1.corr[(e + 1) % 3];
        let c_qd = tr2.corr[(e2 + 1) % 3];
        let c_dr = tr2.corr[(e2 + 2) % 3];
        self.tris[t1.0 as usize] = PartitionTriangle {
            c: [p, q, d],
            corr: [c_pq, c_qd, k],
        };
        self.tris[t2.0 as usize] = PartitionTriangle {
            c: [p, d, r],
            corr: [k, c_dr, c_rp],
        };
        let map = [
            ((t1, ((e + 2) % 3) as u8), (t1, 0u8)),
            ((t2, ((e2 + 1) % 3) as u8), (t1, 1)),
            ((t2, ((e2 + 2) % 3) as u8), (t2, 1)),
            ((t1, ((e + 1) % 3) as u8), (t2, 2)),
        ];
        let mut outer: ArrayVec<CorrId, 4> = [c_pq, c_qd, c_dr, c_rp].into();
        outer.sort();
        dedup_sorted(&mut outer);
        outer.retain(|kk| *kk != k);
        for &kk in &outer {
            let c = self.corrs.on_same_bodies(kk.0 as usize);
            for end in [&mut c.s, &mut c.t] {
                if let Some(&(_, new)) = map.iter().find(|(old, _)| old == end) {
                    *end = new;
                }
            }
        }
        let c = &mut self.corrs[k.0 as usize];
        if p.is_omega() {
            (c.a, c.b, c.s, c.t) = (d.obj, p.obj, (t1, 2), (t2, 0));
        } else {
            (c.a, c.b, c.s, c.t) = (p.obj, d.obj, (t2, 0), (t1, 2));
        }
        c.mid = None;
        // (the four outer corridors keep their sides' two corners: only a
        // hull corridor's turns read the triangle's third corner)
        let (mut corrs, mut near) = (ArrayVec::new(), ArrayVec::new());
        for kk in outer {
            if self.corrs[kk.0 as usize].b == Obj::Omega {
                corrs.push(kk);
            } else {
                near.push(kk);
            }
        }
        corrs.push(k);
        Ok(Outcome {
            kind: if p.is_omega() || d.is_omega() || q.is_omega() || r.is_omega() {
                EventKind::HullFlip
            } else {
                EventKind::Flip
            },
            tris: [t1, t2].into(),
            corrs,
            near,
        })
    }

    fn corner_slide_outcome(
        &mut self,
        world: &Geo,
        tri: TriId,
        ci: usize,
        to: Att,
        kind: EventKind,
    ) -> Result<Outcome, StructureError> {
        self.corner_slide(world, tri, ci, to)?;
        // (the corridor across the side opposite the corner keeps its two
        // corners: it changes only if it is a hull corridor, whose turns
        // read the triangle's third corner)
        let around = self.tris[tri.0 as usize].corr;
        let opposite = around[(ci + 1) % 3];
        let mut corrs: ArrayVec<CorrId, 5> = ArrayVec::new();
        corrs.extend([around[ci], around[(ci + 2) % 3]]);
        let mut near = ArrayVec::new();
        if self.corrs[opposite.0 as usize].b == Obj::Omega {
            corrs.push(opposite);
        } else if !corrs.contains(&opposite) {
            near.push(opposite);
        }
        Ok(Outcome {
            kind,
            tris: [tri].into_iter().collect(),
            corrs,
            near,
        })
    }

    /// Process the failure of a certificate on triple `p` owned by `owner`,
    /// whose point `middle` lies strictly between the other two at `t` (not a
    /// collision). Every decision is the sign just after `t`.
    pub fn process(
        &mut self,
        world: &Geo,
        owner: Owner,
        p: [Att; 3],
        middle: Att,
        t: &Time,
    ) -> Result<Outcome, StructureError> {
        match owner {
            Owner::Tri(tri) => self.triangle_collapse(world, tri, middle, t),
            Owner::Corr(k) if self.corrs[k.0 as usize].b == Obj::Omega => {
                self.hull_event(world, k, p, middle)
            }
            Owner::Corr(k) => self.junction_event(world, k, p, middle),
        }
    }

    /// A partition triangle collapses with corner `middle` between the
    /// other two: a flip across the opposite side if its corridor is empty,
    /// else an ear slide along that corridor's first face (decided with the
    /// turns just after `t`).
    pub(super) fn triangle_collapse(
        &mut self,
        world: &Geo,
        tri: TriId,
        middle: Att,
        t: &Time,
    ) -> Result<Outcome, StructureError> {
        let m = self.tri_index(tri, middle)?;
        let side = (m + 1) % 3;
        let k = self.tris[tri.0 as usize].corr[side];
        let kc = self.corrs[k.0 as usize].clone();
        if kc.len_a == 0 && kc.len_b == 0 {
            return self.flip(tri, side);
        }
        // ear slide: μ enters the corridor's first face f at side (b, c);
        // f's triangle on that side is (c, b, b') or (c', c, b), where b' and
        // c' are the neighbours of b and c along f
        let corners = self.tris[tri.0 as usize].c;
        let (b, c) = (corners[(m + 1) % 3], corners[(m + 2) % 3]);
        let end = if kc.s == (tri, side as u8) {
            EdgeRef::EndS
        } else {
            EdgeRef::EndT
        };
        let js = self.junctions(world, k);
        let b1 = js
            .iter()
            .find(|j| j.v == b && j.in_edge == end && j.prev == c)
            .map(|j| j.next);
        let c1 = js
            .iter()
            .find(|j| j.v == c && j.out_edge == end && j.next == b)
            .map(|j| j.prev);
        let (Some(b1), Some(c1)) = (b1, c1) else {
            return Err(StructureError::Local(format!(
                "triangle {}: corridor face not found",
                tri.0
            )));
        };
        let tn = |u, v, w| turn(world, u, v, w, t);
        let (cbb1, c1cb) = (tn(c, b, b1), tn(c1, c, b));
        if b1 == step_cw(world, b, 1)
            && cbb1 == Sign::Positive
            && (b1 == c1 || c1cb == Sign::Negative || tn(c, b1, c1) == Sign::Positive)
        {
            return self.corner_slide_outcome(world, tri, (m + 1) % 3, b1, EventKind::EarSlide);
        }
        if c1 == step_ccw(world, c)
            && c1cb == Sign::Positive
            && (b1 == c1 || cbb1 == Sign::Negative || tn(b, b1, c1) == Sign::Positive)
        {
            return self.corner_slide_outcome(world, tri, (m + 2) % 3, c1, EventKind::EarSlide);
        }
        Err(StructureError::Local(format!(
            "triangle {} = {corners:?} collapses ({middle:?} in the middle) onto corridor {kc:?} \
             with no ear to slide along (b1 {b1:?}, c1 {c1:?}; turns cbb1 {:?} cb1c1 {:?} c1cb {:?} bb1c1 {:?})",
            tri.0,
            cbb1,
            tn(c, b1, c1),
            c1cb,
            tn(b, b1, c1),
        )))
    }

    fn hull_event(
        &mut self,
        world: &Geo,
        k: CorrId,
        p: [Att; 3],
        middle: Att,
    ) -> Result<Outcome, StructureError> {
        let turns = self.hull_turns(world, k);
        let key = rotate_to_min(p);
        let Some(&(_, x)) = turns
            .iter()
            .find(|(q, _)| rotate_to_min(*q) == key)
            .or_else(|| turns.iter().find(|(q, _)| same_points(*q, p)))
        else {
            return Err(StructureError::Local(
                "hull event: no such hull turn".into(),
            ));
        };
        if middle != x {
            return Err(StructureError::Local(format!(
                "hull turn at {x:?} fails with {middle:?} in the middle"
            )));
        }
        let c = self.corrs[k.0 as usize].clone();
        let (a_s, _, a_t, _) = self.ends(k);
        if c.len_a == 0 {
            self.flip(c.s.0, c.s.1 as usize)
        } else if x == a_s {
            let ci = self.tri_index(c.s.0, a_s)?;
            self.corner_slide_outcome(
                world,
                c.s.0,
                ci,
                step_cw(world, a_s, 1),
                EventKind::HullSlide,
            )
        } else {
            let ci = self.tri_index(c.t.0, a_t)?;
            self.corner_slide_outcome(world, c.t.0, ci, step_ccw(world, a_t), EventKind::HullSlide)
        }
    }

    fn junction_event(
        &mut self,
        world: &Geo,
        k: CorrId,
        p: [Att; 3],
        middle: Att,
    ) -> Result<Outcome, StructureError> {
        let plan = self.junction_plan(world, k, p, middle)?;
        self.slide_planned(world, k, plan)
    }

    /// The operation for the failure of a junction of corridor `k` (not an
    /// ω-corridor) whose [`Kss::junction_plan`] is `plan`, read before
    /// anything changed: what [`Kss::process`] does for it.
    pub fn slide_planned(
        &mut self,
        world: &Geo,
        k: CorrId,
        (e, from, to, onto): (EdgeRef, Att, Att, bool),
    ) -> Result<Outcome, StructureError> {
        self.slide_bridge(world, k, e, from, to, onto)
    }

    /// Which bridge end the failure of junction `p` of corridor `k` (with
    /// `middle` between the other two) moves: `(bridge, from, to, onto)`
    /// for `Kss::slide_bridge`.
    pub fn junction_plan(
        &self,
        world: &Geo,
        k: CorrId,
        p: [Att; 3],
        middle: Att,
    ) -> Result<(EdgeRef, Att, Att, bool), StructureError> {
        let all = self.junctions(world, k);
        let key = rotate_to_min(p);
        let mut js: arrayvec::ArrayVec<_, 8> = all
            .iter()
            .filter(|j| rotate_to_min([j.prev, j.v, j.next]) == key)
            .copied()
            .collect();
        if js.is_empty() {
            js = all
                .into_iter()
                .filter(|j| same_points([j.prev, j.v, j.next], p))
                .collect();
        }
        // μ lands on a face edge next to it
        for j in &js {
            if middle == j.prev && j.out_edge != EdgeRef::Chain {
                if j.in_edge == EdgeRef::Chain {
                    return Ok((j.out_edge, j.v, middle, true));
                }
                if poly_edge(world, j.next, middle) {
                    return Ok((j.out_edge, j.next, middle, true));
                }
            }
            if middle == j.next && j.in_edge != EdgeRef::Chain {
                if j.out_edge == EdgeRef::Chain {
                    return Ok((j.in_edge, j.v, middle, true));
                }
                if poly_edge(world, j.prev, middle) {
                    return Ok((j.in_edge, j.prev, middle, true));
                }
            }
        }
        // a junction turns straight
        for j in &js {
            if middle == j.v {
                match (j.in_edge, j.out_edge) {
                    (EdgeRef::Chain, e) if e != EdgeRef::Chain => {
                        return Ok((e, j.v, j.prev, false));
                    }
                    (e, EdgeRef::Chain) if e != EdgeRef::Chain => {
                        return Ok((e, j.v, j.next, false));
                    }
                    _ => {}
                }
            }
        }
        Err(StructureError::Local(format!(
            "corridor {}: no operation for {p:?} with {middle:?} in the middle",
            k.0
        )))
    }

    /// Move the end `from` of bridge `e` of corridor `k` to its polygon
    /// neighbour `to`. `onto`: `to` lies on the bridge (the bridge sweeps over
    /// it); otherwise the junction at `from` has turned straight.
    fn slide_bridge(
        &mut self,
        world: &Geo,
        k: CorrId,
        e: EdgeRef,
        from: Att,
        to: Att,
        onto: bool,
    ) -> Result<Outcome, StructureError> {
        let ki = k.0 as usize;
        let c = self.corrs[ki].clone();
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let bad = || {
            StructureError::Local(format!(
                "corridor {ki}: cannot slide {e:?} from {from:?} to {to:?}"
            ))
        };
        match e {
            EdgeRef::Chain => Err(bad()),
            EdgeRef::Mid => {
                let (i, j) = c.mid.ok_or_else(bad)?;
                let alpha = step_cw(world, a_s, i);
                let beta = step_cw(world, b_t, j);
                let m = if from == alpha && to == step_cw(world, alpha, 1) && i < c.len_a {
                    (i + 1, j)
                } else if from == alpha && to == step_ccw(world, alpha) && i > 0 {
                    (i - 1, j)
                } else if from == beta && to == step_cw(world, beta, 1) && j < c.len_b {
                    (i, j + 1)
                } else if from == beta && to == step_ccw(world, beta) && j > 0 {
                    (i, j - 1)
                } else {
                    return Err(bad());
                };
                self.corrs.on_same_bodies(ki).mid = Some(m);
                Ok(Outcome {
                    kind: EventKind::MidSlide,
                    tris: ArrayVec::new(),
                    corrs: [k].into_iter().collect(),
                    near: ArrayVec::new(),
                })
            }
            EdgeRef::EndS | EdgeRef::EndT if onto => {
                let tri = if e == EdgeRef::EndS { c.s.0 } else { c.t.0 };
                let ci = self.tri_index(tri, from)?;
                self.corner_slide_outcome(world, tri, ci, to, EventKind::EndSlide)
            }
            EdgeRef::EndS | EdgeRef::EndT => {
                // a corner of the corridor turned convex: the thin middle
                // bridge from the end-edge's other end to `to`
                let m = if e == EdgeRef::EndS && from == a_s && c.len_a > 0 {
                    (1, c.len_b)
                } else if e == EdgeRef::EndS && from == b_s && c.len_b > 0 {
                    (0, c.len_b - 1)
                } else if e == EdgeRef::EndT && from == a_t && c.len_a > 0 {
                    (c.len_a - 1, 0)
                } else if e == EdgeRef::EndT && from == b_t && c.len_b > 0 {
                    (c.len_a, 1)
                } else {
                    return Err(bad());
                };
                self.corrs.on_same_bodies(ki).mid = Some(m);
                Ok(Outcome {
                    kind: EventKind::InsertMid,
                    tris: ArrayVec::new(),
                    corrs: [k].into_iter().collect(),
                    near: ArrayVec::new(),
                })
            }
        }
    }
}
