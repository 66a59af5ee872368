//! Constant-time views of one corridor: its faces as at most two chain pieces
//! joined by bridges, their junctions, the certificates a corridor or a
//! partition triangle owns, whether a corridor's faces are pseudo-triangles,
//! and `normalize`, which restores that after an operation by walking the
//! middle bridge locally.
//!
//! Everything here costs O(1) orientation tests per corridor (plus the length
//! of a walk, which is short next to an event), so that an event touches only
//! the certificates of the few corridors and triangles it changes.

use super::certs::{order_cert, Cert, CertKind};
use super::faces::{step_ccw, step_cw, turn_after};
use super::{Att, CorrId, Kss, Obj, TriId};
use crate::motion::dot_poly;
use crate::num::{Sign, Time};
use crate::world::World;

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

/// A piece of chain in face order: from `start` clockwise over `len` edges.
#[derive(Clone, Copy, Debug)]
struct Piece {
    start: Att,
    len: u32,
}

/// A corridor face: two pieces, the bridge from the first piece's last vertex
/// to the second's start, and the bridge back.
#[derive(Clone, Copy, Debug)]
struct Face {
    p: [Piece; 2],
    e: [EdgeRef; 2],
}

/// The sign of `orient(u, v, w)` just after `t`.
pub fn turn(world: &World, u: Att, v: Att, w: Att, t: &Time) -> Sign {
    turn_after(world, u, v, w, t)
}

/// Whether `v` is strictly between `u` and `w` just after `t` (for three
/// points that stay on one line).
pub fn between_after(world: &World, u: Att, v: Att, w: Att, t: &Time) -> bool {
    let lp = |a: Att| match a.obj {
        Obj::Body(b) => world.body(b).vertex(a.v as usize),
        Obj::Omega => unreachable!("between_after on ω"),
    };
    dot_poly(&lp(v), &lp(u), &lp(w)).sign_after(t) == Sign::Negative
}

impl Kss {
    /// The faces of corridor `k` between two bodies as pieces (none for an
    /// empty corridor or an ω-corridor), using middle bridge `mid`.
    fn faces_with(&self, world: &World, k: CorrId, mid: Option<(u32, u32)>) -> Vec<Face> {
        let c = &self.corrs[k.0 as usize];
        if c.b == Obj::Omega || (c.len_a == 0 && c.len_b == 0) {
            return Vec::new();
        }
        let (a_s, _b_s, _a_t, b_t) = self.ends(k);
        match mid {
            None => vec![Face {
                p: [
                    Piece {
                        start: a_s,
                        len: c.len_a,
                    },
                    Piece {
                        start: b_t,
                        len: c.len_b,
                    },
                ],
                e: [EdgeRef::EndT, EdgeRef::EndS],
            }],
            Some((i, j)) => {
                let alpha = step_cw(world, a_s, i);
                let beta = step_cw(world, b_t, j);
                vec![
                    Face {
                        p: [
                            Piece { start: a_s, len: i },
                            Piece {
                                start: beta,
                                len: c.len_b - j,
                            },
                        ],
                        e: [EdgeRef::Mid, EdgeRef::EndS],
                    },
                    Face {
                        p: [
                            Piece {
                                start: alpha,
                                len: c.len_a - i,
                            },
                            Piece { start: b_t, len: j },
                        ],
                        e: [EdgeRef::EndT, EdgeRef::Mid],
                    },
                ]
            }
        }
    }

    /// The junctions of the faces of corridor `k` with middle bridge `mid`,
    /// face by face (`None` for a face with fewer than three vertices).
    fn junctions_with(
        &self,
        world: &World,
        k: CorrId,
        mid: Option<(u32, u32)>,
    ) -> Vec<Option<Vec<Junction>>> {
        self.faces_with(world, k, mid)
            .into_iter()
            .map(|f| {
                if f.p[0].len == 0 && f.p[1].len == 0 {
                    return None;
                }
                let last = |p: Piece| step_cw(world, p.start, p.len);
                let mut out = Vec::with_capacity(4);
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
            })
            .collect()
    }

    /// The junctions of corridor `k` as it stands, all faces together.
    pub fn junctions(&self, world: &World, k: CorrId) -> Vec<Junction> {
        let mid = self.corrs[k.0 as usize].mid;
        self.junctions_with(world, k, mid)
            .into_iter()
            .flatten()
            .flatten()
            .collect()
    }

    /// Whether every face of corridor `k` with middle bridge `mid` is a
    /// pseudo-triangle just after `t`: three convex junctions, the others
    /// reflex or straight for ever (chain interiors are reflex for ever).
    pub fn faces_valid(&self, world: &World, k: CorrId, mid: Option<(u32, u32)>, t: &Time) -> bool {
        let c = &self.corrs[k.0 as usize];
        if let Some((i, j)) = mid {
            if i > c.len_a || j > c.len_b || (i == 0 && j == c.len_b) || (i == c.len_a && j == 0) {
                return false;
            }
        }
        for face in self.junctions_with(world, k, mid) {
            let Some(js) = face else {
                // a face with two vertices: only an empty corridor has one
                if c.len_a == 0 && c.len_b == 0 {
                    continue;
                }
                return false;
            };
            let mut convex = 0;
            for j in &js {
                match turn(world, j.prev, j.v, j.next, t) {
                    Sign::Positive => convex += 1,
                    Sign::Negative => {}
                    Sign::Zero => {
                        if !between_after(world, j.prev, j.v, j.next, t) {
                            return false;
                        }
                    }
                }
            }
            // a face whose pieces are single vertices has fewer junction
            // entries than vertices only when a piece repeats a triple;
            // triangles list each corner once per piece end
            if convex != 3 {
                return false;
            }
        }
        true
    }

    /// The certificates owned by partition triangle `t`.
    pub fn triangle_certs(&self, tri: TriId) -> Vec<Cert> {
        let c = self.tris[tri.0 as usize].c;
        if c.iter().any(|a| a.is_omega()) {
            return Vec::new();
        }
        vec![Cert {
            p: c,
            sign: Sign::Positive,
            kind: CertKind::Triangle,
        }
        .canonical()]
    }

    /// The certificates owned by corridor `k` at time `t`: its junctions
    /// (with the class they have just after `t`) or, for an ω-corridor, the
    /// hull turns at its hull-bridge ends. Turns that are identically zero
    /// are left out.
    pub fn corridor_certs(&self, world: &World, k: CorrId, t: &Time) -> Vec<Cert> {
        let mut out: Vec<Cert> = Vec::new();
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
            for j in self.junctions(world, k) {
                let sign = turn(world, j.prev, j.v, j.next, t);
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
        out.sort();
        out.dedup();
        out
    }

    /// The hull turns of ω-corridor `k`, each with the vertex it certifies:
    /// `(a_s − 1, a_s, x)` and `(y, a_t, a_t + 1)`, or `(y, a_s, x)` when
    /// `a_s` is its polygon's only hull vertex (`x`, `y`: the hull
    /// neighbours on other objects).
    pub fn hull_turns(&self, world: &World, k: CorrId) -> Vec<([Att; 3], Att)> {
        let c = &self.corrs[k.0 as usize];
        let (a_s, _, a_t, _) = self.ends(k);
        let x = self.other_finite_corner(c.s.0, a_s);
        let y = self.other_finite_corner(c.t.0, a_t);
        if c.len_a == 0 {
            vec![([y, a_s, x], a_s)]
        } else {
            vec![
                ([step_cw(world, a_s, 1), a_s, x], a_s),
                ([y, a_t, step_ccw(world, a_t)], a_t),
            ]
        }
    }

    /// Whether corridor `k` has four convex corners just after `t` (it needs
    /// a middle bridge), given both chains are non-empty.
    fn four_corners(&self, world: &World, k: CorrId, t: &Time) -> bool {
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let conv = |u, v, w| turn(world, u, v, w, t) == Sign::Positive;
        conv(b_s, a_s, step_cw(world, a_s, 1))
            && conv(step_ccw(world, a_t), a_t, b_t)
            && conv(a_t, b_t, step_cw(world, b_t, 1))
            && conv(step_ccw(world, b_s), b_s, a_s)
    }

    /// Restore corridor `k`'s faces to pseudo-triangles just after `t`.
    /// Keeps a valid middle bridge; otherwise drops it when the corridor has
    /// three convex corners, or walks it from its old place (or from `hint`)
    /// to a valid one. Returns how many walk steps a repair took (0 when
    /// nothing was repaired), or an error if no decomposition was found.
    pub fn normalize(
        &mut self,
        world: &World,
        k: CorrId,
        t: &Time,
        hint: Option<(u32, u32)>,
    ) -> Result<u32, String> {
        let ki = k.0 as usize;
        let c = &self.corrs[ki];
        if c.b == Obj::Omega || (c.len_a == 0 && c.len_b == 0) {
            self.corrs[ki].mid = None;
            return Ok(0);
        }
        let (len_a, len_b) = (c.len_a, c.len_b);
        let mid = c
            .mid
            .filter(|&(i, j)| i <= len_a && j <= len_b)
            .filter(|&(i, j)| !((i == 0 && j == len_b) || (i == len_a && j == 0)));
        self.corrs[ki].mid = mid;
        if self.faces_valid(world, k, mid, t) {
            return Ok(0);
        }
        if len_a > 0 && len_b > 0 && self.four_corners(world, k, t) {
            let starts: Vec<(u32, u32)> = hint
                .into_iter()
                .chain(mid)
                .chain([(0, 0), (len_a, len_b)])
                .collect();
            let limit = 2 * (len_a + len_b) + 8;
            for &start in &starts {
                for ty in [Diagonal::SourceToTarget, Diagonal::TargetToSource] {
                    if let Some((m, steps)) = self.walk(world, k, t, start, ty, limit) {
                        if self.faces_valid(world, k, Some(m), t) {
                            self.corrs[ki].mid = Some(m);
                            return Ok(steps.max(1));
                        }
                    }
                }
            }
        } else if self.faces_valid(world, k, None, t) {
            self.corrs[ki].mid = None;
            return Ok(1);
        }
        Err(format!(
            "corridor {ki}: no pseudo-triangle decomposition found (len {len_a}/{len_b}, mid {mid:?})"
        ))
    }

    /// Walk a middle bridge of diagonal type `ty` from `start` until its four
    /// tangency conditions hold.
    fn walk(
        &self,
        world: &World,
        k: CorrId,
        t: &Time,
        start: (u32, u32),
        ty: Diagonal,
        limit: u32,
    ) -> Option<((u32, u32), u32)> {
        let c = &self.corrs[k.0 as usize];
        let (len_a, len_b) = (c.len_a, c.len_b);
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        let (mut i, mut j) = (start.0.min(len_a), start.1.min(len_b));
        let tn = |u, v, w| turn(world, u, v, w, t);
        for steps in 0..limit {
            let alpha = step_cw(world, a_s, i);
            let beta = step_cw(world, b_t, j);
            // α's turn in face t (towards α − 1, or b_t when α = a_t) and in
            // face s (from α + 1, or b_s when α = a_s); β's likewise
            let a_in_t = if i < len_a {
                tn(beta, alpha, step_cw(world, alpha, 1))
            } else {
                tn(beta, a_t, b_t)
            };
            let a_in_s = if i > 0 {
                tn(step_ccw(world, alpha), alpha, beta)
            } else {
                tn(b_s, a_s, beta)
            };
            let b_in_s = if j < len_b {
                tn(alpha, beta, step_cw(world, beta, 1))
            } else {
                tn(alpha, b_s, a_s)
            };
            let b_in_t = if j > 0 {
                tn(step_ccw(world, beta), beta, alpha)
            } else {
                tn(a_t, b_t, alpha)
            };
            let pos = |s: Sign| s == Sign::Positive;
            let mv: Option<(i64, i64)> = match ty {
                // a_s ⇝ b_t: α convex in t, reflex in s; β convex in s, reflex in t
                Diagonal::SourceToTarget => {
                    if !pos(a_in_t) && i < len_a {
                        Some((1, 0))
                    } else if i > 0 && pos(a_in_s) {
                        Some((-1, 0))
                    } else if !pos(b_in_s) && j < len_b {
                        Some((0, 1))
                    } else if j > 0 && pos(b_in_t) {
                        Some((0, -1))
                    } else {
                        None
                    }
                }
                // b_s ⇝ a_t: α convex in s, reflex in t; β convex in t, reflex in s
                Diagonal::TargetToSource => {
                    if !pos(a_in_s) && i > 0 {
                        Some((-1, 0))
                    } else if i < len_a && pos(a_in_t) {
                        Some((1, 0))
                    } else if !pos(b_in_t) && j > 0 {
                        Some((0, -1))
                    } else if j < len_b && pos(b_in_s) {
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
