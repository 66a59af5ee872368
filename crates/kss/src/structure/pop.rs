//! Popping an approximation vertex in place (the paper's section 4: "pop
//! the approximation vertex and restore the invariants using the convex
//! chain that was previously hidden"), instead of rebuilding the structure.
//!
//! Popping vertex `v = av(i, k)` of body `B` inserts `m = top(i, k)`: `v` is
//! replaced by `m' = av(i, m)` on the line `L_i` and `k' = av(m, k)` on
//! `L_k`, joined by a new edge on `L_m`. The approximation only shrinks, so
//! the free space only grows, by the triangle `(m', v, k')`.
//!
//! Around `v`, in the free space, the structure has (from the edge towards
//! `i` to the edge towards `k`'s successor) a corridor whose chain leaves
//! `v` clockwise, then `r ≥ 0` partition triangles with a corner at `v`
//! separated by corridors whose chain on `B` is empty at `v`, then a
//! corridor whose chain arrives at `v`. The new edge goes to exactly one of
//! these `r + 1` corridors, the triangles before it get the corner `m'` and
//! the ones after it `k'` (a partition triangle cannot take the edge: its
//! corners stay on three objects). Chain lengths and middle-bridge offsets
//! along `B` are recomputed from the new ends.
//!
//! Which corridor takes the edge is decided by validity: the candidates are
//! tried in order and the first whose touched corridors have a
//! pseudo-triangle decomposition, and whose touched partition triangles and
//! hull turns hold, just *before* the current instant is kept. Before the
//! instant the old approximations were disjoint and the structure valid, so
//! a correct local update is valid there too; the certificates that fail at
//! the instant itself (the two approximations still touch where the pop was
//! not enough) are then ordinary events of the instant. When the motions
//! changed at the instant (a flight-plan change or a collision response),
//! "before" under the new motions means nothing, and the candidates are
//! tried again just *after* the instant.
//!
//! A candidate can fail because a partition triangle at `v` turns inside
//! out: the new corner lies beyond the line through the triangle's other
//! two corners (a long thin triangle along a wall, whose far corners the
//! cut corner no longer sees). Had the corner moved there continuously,
//! the kinetic structure would have met that triangle's collapse and
//! flipped it or slid its corner along an ear. So if no candidate holds as
//! it is, each is tried again followed by such collapses of its inverted
//! triangles, depth first, up to a budget of operations, and kept if the
//! touched part of the structure then holds. Only if none does is the
//! structure left unchanged for the caller to rebuild (in the gas with
//! k = 1000 polygons, 1 pop of 461 instead of 7).
//!
//! Cost: one scan of the triangles and corridors to find the ones on `B`
//! (O(k)), walks along `B`'s chains (O(|S_B|)) to find the chains through
//! `v`, and per candidate the decomposition of the few corridors around `v`;
//! no triangulation and no certificate outside the touched owners.

use super::geo::{Geo, Shapes};
use super::local::{turn_on, Side};
use super::{Att, CorrId, Corridor, Kss, Obj, PartitionTriangle, TriId};
use crate::geom::MidRad;
use crate::num::{Sign, Time};
use crate::world::World;

/// The most operations [`Kss::flip_repair`] tries for one candidate of a
/// pop.
const REPAIR_OPS: u32 = 40;

/// What [`Kss::pop_vertex`] did.
#[derive(Clone, Debug)]
pub enum PopResult {
    /// Nothing to pop: not an approximation vertex, or not seen.
    NotPopped,
    /// Popped, and the structure was updated in place.
    Local {
        /// Corridors whose ends, chains or middle bridge may have changed.
        corrs: Vec<CorrId>,
        /// Partition triangles whose corners changed.
        tris: Vec<TriId>,
        /// The vertex ids of the body whose position or meaning changed
        /// (certificates on them must be recomputed).
        ids: Vec<Att>,
    },
    /// Popped, but no local update was found valid: the structure still
    /// describes the old approximation and must be rebuilt.
    Failed,
}

/// Copies of some partition triangles and corridors, put back when a tried
/// update does not hold.
struct Saved {
    tris: Vec<(TriId, PartitionTriangle)>,
    corrs: Vec<(CorrId, Corridor)>,
}

impl Saved {
    fn of(kss: &Kss, tris: &[TriId], corrs: &[CorrId]) -> Saved {
        Saved {
            tris: tris
                .iter()
                .map(|&ti| (ti, kss.tris[ti.0 as usize].clone()))
                .collect(),
            corrs: corrs
                .iter()
                .map(|&k| (k, kss.corrs[k.0 as usize].clone()))
                .collect(),
        }
    }

    fn restore(&self, kss: &mut Kss) {
        for (ti, tr) in &self.tris {
            kss.tris[ti.0 as usize] = tr.clone();
        }
        for (k, c) in &self.corrs {
            kss.corrs[k.0 as usize] = c.clone();
        }
    }
}

/// The position of `x` at `t` in doubles, for the trace (`None` at an
/// irrational instant).
#[cfg(feature = "trace")]
fn trace_pos(geo: &Geo, x: Att, t: &Time) -> Option<[f64; 2]> {
    t.as_rational()
        .and_then(|r| geo.position(x, r))
        .map(|p| p.to_f64())
}

/// The chain of a corridor on the popped body, as it was before the pop.
#[derive(Clone, Debug)]
struct ChainRec {
    corr: CorrId,
    /// The chain is the corridor's A-chain (else its B-chain).
    on_a: bool,
    /// Start and end of the chain (clockwise) before the pop.
    start: Att,
    end: Att,
    len: u32,
    /// The middle bridge's ends and offsets before the pop.
    mid: Option<(Att, Att, u32, u32)>,
}

/// Of `d` and `d + count`, the chain length nearest to `old` (a pop changes
/// a chain by at most a few edges; a chain may wrap all the way round).
fn nearest(d: u32, count: u32, old: u32) -> u32 {
    let wrap = d + count;
    if wrap.abs_diff(old) < d.abs_diff(old) {
        wrap
    } else {
        d
    }
}

impl Kss {
    /// The length of corridor `k`'s chain on object `o` (`None` if `o` is
    /// neither side).
    fn chain_len_on(&self, k: CorrId, o: Obj) -> Option<u32> {
        let c = &self.corrs[k.0 as usize];
        if c.a == o {
            Some(c.len_a)
        } else if c.b == o {
            Some(c.len_b)
        } else {
            None
        }
    }

    /// The partition-triangle corners at each of two vertices of body `b`,
    /// as `(triangle, corner index)` in the order of the triangles, from
    /// the triangles on `b` ([`Kss::incidence`]).
    fn corners_at(&self, b: crate::world::BodyId, v: [Att; 2]) -> [Vec<(TriId, usize)>; 2] {
        let mut out = [Vec::new(), Vec::new()];
        for ti in self.incidence.tris_on(&self.tris, b) {
            for (ci, c) in self.tris[ti as usize].c.iter().enumerate() {
                for (n, x) in v.iter().enumerate() {
                    if c == x {
                        out[n].push((TriId(ti), ci));
                    }
                }
            }
        }
        debug_assert_eq!(
            out,
            self.corners_at_scan(v),
            "the incidence index misses a triangle"
        );
        out
    }

    /// [`Kss::corners_at`] by a scan of every triangle (debug builds check
    /// the index against it).
    fn corners_at_scan(&self, v: [Att; 2]) -> [Vec<(TriId, usize)>; 2] {
        let mut out = [Vec::new(), Vec::new()];
        for (ti, tr) in self.tris.iter().enumerate() {
            for (ci, c) in tr.c.iter().enumerate() {
                for (n, x) in v.iter().enumerate() {
                    if c == x {
                        out[n].push((TriId(ti as u32), ci));
                    }
                }
            }
        }
        out
    }

    /// Pop approximation vertex `a` in `shapes` and update the structure in
    /// place for the instants just before `t` (module docs).
    pub fn pop_vertex(
        &mut self,
        world: &World,
        shapes: &mut Shapes,
        a: Att,
        t: &Time,
    ) -> PopResult {
        let Obj::Body(b) = a.obj else {
            return PopResult::NotPopped;
        };
        let body = a.obj;
        let k = a.v as usize;
        let i = {
            let Some(ap) = shapes.approx(b) else {
                return PopResult::NotPopped;
            };
            if !ap.exposed().contains(k) || ap.hidden(k) {
                return PopResult::NotPopped;
            }
            match ap.exposed().pred(k) {
                Some(i) => i,
                None => return PopResult::NotPopped,
            }
        };
        let old = Geo {
            world,
            shapes: &*shapes,
        };
        if old.is_real(a) {
            return PopResult::NotPopped;
        }
        let a_i = Att::vertex(b, i as u32);
        // the triangles with a corner at `v`, and every corridor along `B`
        let [at_v, at_i] = self.corners_at(b, [a, a_i]);
        let along = self.incidence.corrs_on(&self.corrs, b);
        #[cfg(debug_assertions)]
        {
            let on_body = |o: Obj| matches!(o, Obj::Body(x) if x == b);
            let scan: Vec<u32> = (0..self.corrs.len() as u32)
                .filter(|&ki| {
                    on_body(self.corrs[ki as usize].a) || on_body(self.corrs[ki as usize].b)
                })
                .collect();
            debug_assert_eq!(along, scan, "the incidence index misses a corridor");
        }
        let chains: Vec<ChainRec> = along
            .into_iter()
            .filter_map(|ki| {
                let ki = ki as usize;
                let kid = CorrId(ki as u32);
                let c = &self.corrs[ki];
                let on_a = c.a == body;
                let (a_s, b_s, a_t, b_t) = self.ends(kid);
                let (start, end, len) = if on_a {
                    (a_s, a_t, c.len_a)
                } else {
                    (b_t, b_s, c.len_b)
                };
                // only the chains through `v`, or ending at `i` (which may
                // become hidden), change
                let through = [start, end].iter().any(|&x| x == a || x == a_i)
                    || old.cw_distance(start, a, len).is_some();
                if !through {
                    return None;
                }
                let mid = c
                    .mid
                    .map(|(mi, mj)| (old.cw(a_s, mi), old.cw(b_t, mj), mi, mj));
                Some(ChainRec {
                    corr: kid,
                    on_a,
                    start,
                    end,
                    len,
                    mid,
                })
            })
            .collect();
        // the triangles at `v` in order from the edge towards `i`: each has
        // the corridor across its side leaving `v` (`corr[ci]`, whose chain
        // on `B` starts at `v`) and the one across its side arriving at `v`
        // (`corr[ci − 1]`); consecutive ones share a corridor whose chain is
        // empty at `v`
        let leave = |s: &Kss, (ti, ci): (TriId, usize)| s.tris[ti.0 as usize].corr[ci];
        let arrive = |s: &Kss, (ti, ci): (TriId, usize)| s.tris[ti.0 as usize].corr[(ci + 2) % 3];
        let mut order: Vec<(TriId, usize)> = Vec::with_capacity(at_v.len());
        if !at_v.is_empty() {
            let firsts: Vec<(TriId, usize)> = at_v
                .iter()
                .copied()
                .filter(|&x| {
                    self.chain_len_on(leave(self, x), body)
                        .is_some_and(|l| l > 0)
                })
                .collect();
            let [first] = firsts[..] else {
                #[cfg(feature = "trace")]
                eprintln!(
                    "pop {a:?}: {} triangles, {} leave on a chain",
                    at_v.len(),
                    firsts.len()
                );
                return self.pop_only(shapes, b, k);
            };
            let mut cur = first;
            loop {
                order.push(cur);
                let next = arrive(self, cur);
                if self.chain_len_on(next, body).is_none_or(|l| l > 0) || order.len() > at_v.len() {
                    break;
                }
                match at_v.iter().copied().find(|&x| leave(self, x) == next) {
                    Some(x) => cur = x,
                    None => break,
                }
            }
            if order.len() != at_v.len() {
                #[cfg(feature = "trace")]
                eprintln!(
                    "pop {a:?}: {} triangles, {} in order",
                    at_v.len(),
                    order.len()
                );
                return self.pop_only(shapes, b, k);
            }
        }
        #[cfg(feature = "trace")]
        {
            let mut copy = self.clone();
            let ids: Vec<CorrId> = chains.iter().map(|r| r.corr).collect();
            eprintln!(
                "pop {a:?}: old structure valid before t: {}",
                copy.pop_valid(&old, &ids, &[], t, Side::Before)
            );
            let pos = |x: Att| trace_pos(&old, x, t);
            for &(ti, _) in order.iter().chain(&at_i) {
                let tr = &self.tris[ti.0 as usize];
                eprintln!(
                    "  triangle {} {:?} at {:?} corridors {:?}",
                    ti.0,
                    tr.c,
                    tr.c.map(pos),
                    tr.corr.map(|k| {
                        let c = &self.corrs[k.0 as usize];
                        (k.0, c.len_a, c.len_b)
                    })
                );
            }
        }
        // the pop
        let Some(m) = shapes.per[b.index()].as_mut().and_then(|ap| ap.pop(k)) else {
            return PopResult::NotPopped;
        };
        let ap = shapes.approx(b).expect("popped");
        let mside = Att::vertex(b, m as u32);
        let kside = if ap.hidden(k) {
            Att::vertex(b, ap.next_visible(k) as u32)
        } else {
            a
        };
        let iside = if ap.hidden(i) { mside } else { a_i };
        let geo = Geo {
            world,
            shapes: &*shapes,
        };
        let count = geo.count(b);
        #[cfg(feature = "trace")]
        {
            eprintln!(
                "pop {a:?}: i {i} m {m} kside {:?} iside {:?} count {count}, order {order:?}, at_i {at_i:?}",
                kside.v, iside.v
            );
            let pos = |x: Att| trace_pos(&geo, x, t);
            eprintln!("  new points {:?} {:?}", pos(mside), pos(kside));
            for r in &chains {
                eprintln!("  chain {r:?} corr {:?}", self.corrs[r.corr.0 as usize]);
            }
        }
        // what to restore if a candidate fails
        let mut tri_ids: Vec<TriId> = at_v.iter().chain(&at_i).map(|&(ti, _)| ti).collect();
        tri_ids.sort();
        tri_ids.dedup();
        let mut corr_ids: Vec<CorrId> = chains.iter().map(|r| r.corr).collect();
        for &ti in &tri_ids {
            corr_ids.extend(self.tris[ti.0 as usize].corr);
        }
        corr_ids.sort();
        corr_ids.dedup();
        let saved = Saved::of(self, &tri_ids, &corr_ids);
        let remap = |x: Att, rec: &ChainRec, new_start: Att, new_end: Att| -> Att {
            if x == a {
                if rec.start == a {
                    new_start
                } else if rec.end == a {
                    new_end
                } else {
                    kside
                }
            } else if x == a_i {
                iside
            } else {
                x
            }
        };
        let candidates = order.len() + 1;
        // first every candidate as it is; then, if none holds, each with the
        // triangle collapses that repair the partition triangles it inverts
        for (repair, side, j) in [false, true].into_iter().flat_map(|repair| {
            [Side::Before, Side::After]
                .into_iter()
                .flat_map(move |side| (0..candidates).map(move |j| (repair, side, j)))
        }) {
            for (n, &(ti, ci)) in order.iter().enumerate() {
                self.tris.on_same_bodies(ti.0 as usize).c[ci] = if n < j { mside } else { kside };
            }
            for &(ti, ci) in &at_i {
                self.tris.on_same_bodies(ti.0 as usize).c[ci] = iside;
            }
            let mut ok = true;
            for rec in &chains {
                let (a_s, b_s, a_t, b_t) = self.ends(rec.corr);
                let (start, end) = if rec.on_a { (a_s, a_t) } else { (b_t, b_s) };
                let Some(d) = geo.cw_distance(start, end, count) else {
                    ok = false;
                    break;
                };
                let len = nearest(d, count, rec.len);
                let c = self.corrs.on_same_bodies(rec.corr.0 as usize);
                if rec.on_a {
                    c.len_a = len;
                } else {
                    c.len_b = len;
                }
                if let Some((alpha, beta, mi, mj)) = rec.mid {
                    let (x, old_off) = if rec.on_a { (alpha, mi) } else { (beta, mj) };
                    let x = remap(x, rec, start, end);
                    let off = geo
                        .cw_distance(start, x, count)
                        .map(|d| nearest(d, count, old_off).min(len));
                    let c = self.corrs.on_same_bodies(rec.corr.0 as usize);
                    c.mid = off.map(|o| if rec.on_a { (o, mj) } else { (mi, o) });
                }
            }
            #[cfg(feature = "trace")]
            eprintln!("pop {a:?} candidate {j}/{candidates} {side:?}: lengths ok {ok}");
            let (mut corrs, mut tris) = (corr_ids.clone(), tri_ids.clone());
            // a chain that wraps the whole polygon (one corridor along all
            // of it) defeats the local checks: a candidate can then let a
            // bridge cross the popped polygon (grazing-p50 of the quick
            // bench, after local removals); such a pop rebuilds
            let wraps = chains.iter().any(|r| r.start == r.end && r.len > 0);
            let valid = ok
                && !wraps
                && if repair {
                    self.flip_repair(&geo, (&mut corrs, &mut tris), t, side, &mut { REPAIR_OPS })
                } else {
                    self.pop_valid(&geo, &corrs, &tris, t, side)
                };
            if valid {
                let mut ids = vec![a, a_i, mside, kside];
                ids.sort();
                ids.dedup();
                return PopResult::Local { corrs, tris, ids };
            }
            saved.restore(self);
        }
        PopResult::Failed
    }

    /// After a candidate of a pop left partition triangles among `tris`
    /// inverted just on `side` of `t` (the new corner lies beyond the line
    /// of the triangle's other two corners): do what the kinetic structure
    /// would have done had the corner moved there, a triangle collapse (a
    /// flip across an empty corridor or an ear slide along a non-empty one)
    /// with one of its corners in the middle, and again, depth first, at
    /// most `budget` operations in all, until the touched part of the
    /// structure holds; the operated triangles and corridors join
    /// `touched`. On failure the structure is as it was.
    ///
    /// The corners are tried in the order of their angle in the inverted
    /// triangle, largest first (the corner that crossed the line of the
    /// other two is most likely the middle one); that order, computed in
    /// f64, only decides what is tried first: every result is checked
    /// exactly ([`Kss::pop_valid`]).
    fn flip_repair(
        &mut self,
        geo: &Geo,
        touched: (&mut Vec<CorrId>, &mut Vec<TriId>),
        t: &Time,
        side: Side,
        budget: &mut u32,
    ) -> bool {
        let (corrs, tris) = touched;
        let inverted = |s: &Kss, ti: TriId| {
            let c = s.tris[ti.0 as usize].c;
            !c.iter().any(|x| x.is_omega())
                && turn_on(geo, c[0], c[1], c[2], t, side) != Sign::Positive
        };
        let Some(&bad) = tris.iter().find(|&&ti| inverted(self, ti)) else {
            return false;
        };
        let corners = self.tris[bad.0 as usize].c;
        let tf = t.to_f64();
        let pos = corners.map(|x| geo.point(x).at_f64(tf));
        let angle = |i: usize| {
            let (p, q, r) = (pos[i], pos[(i + 1) % 3], pos[(i + 2) % 3]);
            let (u, v) = ([q[0] - p[0], q[1] - p[1]], [r[0] - p[0], r[1] - p[1]]);
            let cos = (u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1]));
            if cos.is_nan() {
                0.0
            } else {
                -cos
            }
        };
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| angle(j).total_cmp(&angle(i)));
        // the triangles and corridors a collapse of `bad` may change: `bad`,
        // the triangles across its sides, and the corridors around them
        let mut near_tris = vec![bad];
        for k in self.tris[bad.0 as usize].corr {
            let c = &self.corrs[k.0 as usize];
            near_tris.extend([c.s.0, c.t.0]);
        }
        near_tris.sort();
        near_tris.dedup();
        let mut near_corrs: Vec<CorrId> = near_tris
            .iter()
            .flat_map(|ti| self.tris[ti.0 as usize].corr)
            .collect();
        near_corrs.sort();
        near_corrs.dedup();
        let saved = Saved::of(self, &near_tris, &near_corrs);
        for e in order {
            if *budget == 0 {
                return false;
            }
            *budget -= 1;
            let Ok(out) = self.triangle_collapse(geo, bad, corners[e], t) else {
                saved.restore(self);
                continue;
            };
            let (mut c2, mut t2) = (corrs.clone(), tris.clone());
            c2.extend(out.corrs.iter().chain(&out.near).copied());
            t2.extend(out.tris.iter().copied());
            c2.sort();
            c2.dedup();
            t2.sort();
            t2.dedup();
            if self.pop_valid(geo, &c2, &t2, t, side)
                || self.flip_repair(geo, (&mut c2, &mut t2), t, side, budget)
            {
                #[cfg(feature = "trace")]
                eprintln!(
                    "  repaired: triangle {} collapses at corner {e}: {}",
                    bad.0,
                    out.kind.name()
                );
                *corrs = c2;
                *tris = t2;
                return true;
            }
            saved.restore(self);
        }
        false
    }

    /// Pop in `shapes` only (the structure is left for a rebuild).
    fn pop_only(&self, shapes: &mut Shapes, b: crate::world::BodyId, k: usize) -> PopResult {
        match shapes.per[b.index()].as_mut().and_then(|ap| ap.pop(k)) {
            Some(_) => PopResult::Failed,
            None => PopResult::NotPopped,
        }
    }

    /// Whether the touched corridors have pseudo-triangle faces (setting
    /// their middle bridges), and the touched partition triangles and hull
    /// turns hold, just on `side` of `t`.
    fn pop_valid(
        &mut self,
        geo: &Geo,
        corrs: &[CorrId],
        tris: &[TriId],
        t: &Time,
        side: Side,
    ) -> bool {
        super::counters::bump(super::counters::Counter::PopCandidates);
        let sign = |p: [Att; 3]| turn_on(geo, p[0], p[1], p[2], t, side);
        let holds = |p: [Att; 3]| sign(p) == Sign::Positive;
        // each body's ring (and its points' midpoints and radii) once
        let tiv = t.interval();
        let mut rings: Vec<(crate::world::BodyId, Ring)> = Vec::new();
        // (the triangles' signs first: most candidates that fail, fail
        // there, before any side is tested against a polygon)
        for &ti in tris {
            let c = self.tris[ti.0 as usize].c;
            if !c.iter().any(|x| x.is_omega()) && !holds(c) {
                #[cfg(feature = "trace")]
                eprintln!(
                    "  triangle {} does not hold before t: {c:?} at {:?}",
                    ti.0,
                    c.map(|x| trace_pos(geo, x, t))
                );
                return false;
            }
            // three corners on three objects
            if c[0].obj == c[1].obj || c[1].obj == c[2].obj || c[0].obj == c[2].obj {
                return false;
            }
        }
        for &ti in tris {
            let c = self.tris[ti.0 as usize].c;
            // no side crosses the polygon at the opposite corner (the sign
            // pattern alone let a pop through with a side across it:
            // gen_small grazing 2529, hierarchical)
            for i in 0..3 {
                let (x, p, q) = (c[i], c[(i + 1) % 3], c[(i + 2) % 3]);
                if let (Obj::Body(b), false, false) = (x.obj, p.is_omega(), q.is_omega()) {
                    // (an edge that separates the side from the polygon,
                    // looked for next to `x` first without listing the
                    // ring; the ring only where none does)
                    if separated(geo, (b, x), [p, q], tiv, &sign) {
                        continue;
                    }
                    let at = match rings.iter().position(|r| r.0 == b) {
                        Some(at) => at,
                        None => {
                            rings.push((b, ring_of(geo, b)));
                            rings.len() - 1
                        }
                    };
                    if line_splits(geo, &rings[at].1, [p, q], tiv, &sign) {
                        #[cfg(feature = "trace")]
                        eprintln!(
                            "  triangle {}: side {p:?}-{q:?} crosses body {}",
                            ti.0,
                            b.raw()
                        );
                        return false;
                    }
                }
            }
        }
        for &k in corrs {
            let c = &self.corrs[k.0 as usize];
            if c.b == Obj::Omega {
                let turns = self.hull_turns(geo, k);
                let hull_ok = turns.iter().all(|&(p, _)| sign(p) != Sign::Negative);
                // a polygon's only hull vertex: both hull bridges there
                // keep the polygon inside (its neighbours on the inner side
                // of each); the turn (y, a_s, x) alone lets through a
                // bridge that cuts the polygon off the hull, with a twisted
                // corridor behind it that no junction sign shows (the
                // bridge through a polygon at 7.7e-34 beside one moving at
                // 3e226)
                let tangent = |[y, v, x]: [Att; 3]| {
                    [
                        super::faces::step_ccw(geo, v),
                        super::faces::step_cw(geo, v, 1),
                    ]
                    .into_iter()
                    .filter(|&n| n != v)
                    .all(|n| sign([y, v, n]) != Sign::Negative && sign([v, x, n]) != Sign::Negative)
                };
                let hull_ok = hull_ok && (c.len_a > 0 || turns.iter().all(|&(p, _)| tangent(p)));
                if !hull_ok {
                    #[cfg(feature = "trace")]
                    eprintln!("  hull turns of corridor {} fail before t", k.0);
                    return false;
                }
                continue;
            }
            if c.len_a == 0 && c.len_b == 0 {
                // an empty corridor's bridge has no junction to check: it
                // must not point into the polygon's corner at either end
                // (strictly left of both edges there), else it runs through
                // that polygon
                let (a_s, b_s, _, _) = self.ends(k);
                let into = |v: Att, w: Att| {
                    let (up, down) = (
                        super::faces::step_ccw(geo, v),
                        super::faces::step_cw(geo, v, 1),
                    );
                    sign([down, v, w]) == Sign::Positive && sign([v, up, w]) == Sign::Positive
                };
                if into(a_s, b_s) || into(b_s, a_s) {
                    #[cfg(feature = "trace")]
                    eprintln!(
                        "  the bridge of empty corridor {} enters a polygon before t",
                        k.0
                    );
                    return false;
                }
                self.corrs.on_same_bodies(k.0 as usize).mid = None;
                continue;
            }
            let hint = c.mid;
            if self.decompose(geo, k, t, hint, side).is_none() {
                #[cfg(feature = "trace")]
                eprintln!(
                    "  corridor {} has no decomposition before t: {:?}",
                    k.0, self.corrs[k.0 as usize]
                );
                return false;
            }
        }
        true
    }
}

/// A body's vertices as the structure sees them, counter-clockwise (each
/// placed at the instant only when a test reads it: the search for a
/// separating edge nearly always reads a few).
type Ring = Vec<Att>;

/// Body `b`'s [`Ring`].
fn ring_of(geo: &Geo, b: crate::world::BodyId) -> Ring {
    geo.ids(b).into_iter().map(|v| Att::vertex(b, v)).collect()
}

/// Turn `(a, b, c)` of three placed points: the midpoint–radius filter,
/// else `sign`.
fn placed_turn(
    (a, ma): (Att, Option<MidRad>),
    (b, mb): (Att, Option<MidRad>),
    (c, mc): (Att, Option<MidRad>),
    sign: &dyn Fn([Att; 3]) -> Sign,
) -> Sign {
    if let (Some(ma), Some(mb), Some(mc)) = (ma, mb, mc) {
        super::counters::bump(super::counters::Counter::TurnsFiltered);
        if let Some(s) = crate::geom::orient_mid_rad(ma, mb, mc) {
            return s;
        }
    }
    sign([a, b, c])
}

/// Whether an edge of body `b`'s polygon as seen (counter-clockwise:
/// outside is negative) has both ends of segment `pq` on its closed outer
/// side: then `pq` does not cross the polygon. The edges are tried from
/// those at `x` (a visible vertex of `b`, the triangle's corner facing the
/// segment, where a separating edge almost always is) outwards, alternately
/// counter-clockwise and clockwise, walked with [`Geo::ccw`]/[`Geo::cw`]
/// instead of listing the ring; `false` once every edge was tried. Turns
/// go through the midpoint–radius filter first, then `sign`.
fn separated(
    geo: &Geo,
    (b, x): (crate::world::BodyId, Att),
    [p, q]: [Att; 2],
    t: crate::num::Interval,
    sign: &dyn Fn([Att; 3]) -> Sign,
) -> bool {
    let m = match geo.shapes.approx(b) {
        None => geo.world.body(b).shape.len(),
        Some(ap) => ap.visible_len(),
    };
    debug_assert!(
        {
            let ring = ring_of(geo, b);
            ring.len() == m && ring.contains(&x)
        },
        "a triangle's corner {x:?} is not one of the {m} visible vertices"
    );
    let placed = |a: Att| (a, geo.mid_rad(a, t));
    let (p, q) = (placed(p), placed(q));
    let separates = |u: Att, w: Att| {
        let (u, w) = (placed(u), placed(w));
        placed_turn(u, w, p, sign) != Sign::Positive && placed_turn(u, w, q, sign) != Sign::Positive
    };
    // (the edges after `x` end at `ahead`, those before it start at
    // `behind`)
    let (mut ahead, mut behind) = (x, x);
    for d in 0..m {
        let found = if d % 2 == 0 {
            let next = geo.ccw(ahead);
            let s = separates(ahead, next);
            ahead = next;
            s
        } else {
            let prev = geo.cw(behind, 1);
            let s = separates(prev, behind);
            behind = prev;
            s
        };
        if found {
            return true;
        }
    }
    false
}

/// Whether the polygon `ring` has vertices strictly on both sides of the
/// line of segment `pq`: where no edge separates them ([`separated`]),
/// whether `pq` crosses the polygon's interior. Turns go through the
/// midpoint–radius filter first, then `sign`.
fn line_splits(
    geo: &Geo,
    ring: &Ring,
    [p, q]: [Att; 2],
    t: crate::num::Interval,
    sign: &dyn Fn([Att; 3]) -> Sign,
) -> bool {
    let placed = |a: Att| (a, geo.mid_rad(a, t));
    let (p, q) = (placed(p), placed(q));
    let (mut pos, mut neg) = (false, false);
    for &v in ring {
        match placed_turn(p, q, placed(v), sign) {
            Sign::Positive => pos = true,
            Sign::Negative => neg = true,
            Sign::Zero => {}
        }
        if pos && neg {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::nearest;

    #[test]
    fn nearest_length_prefers_the_closer_wrap() {
        assert_eq!(nearest(0, 10, 0), 0);
        assert_eq!(nearest(0, 10, 10), 10);
        assert_eq!(nearest(1, 10, 0), 1);
        assert_eq!(nearest(9, 10, 10), 9);
        assert_eq!(nearest(0, 11, 10), 11);
    }
}
