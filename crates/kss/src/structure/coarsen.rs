//! Coarsening: undoing a pop where the polygons have moved apart again, so
//! that long runs and repeated encounters stay cheap (the paper's Fig. 9
//! shows the hierarchy shifting; it gives no rule: the one here is stated in
//! `docs/design/hierarchy.md`, "Coarsening").
//!
//! Id `k` of body `B` may leave the exposed set when `[p, k]` and `[k, q]`
//! are the two halves of one dyadic block (`p`, `q` its exposed neighbours:
//! the merge exactly undoes the pop that inserted `k`) and the turn from
//! `L_p` to `L_q` is acute ([`crate::hier::EdgeArray::merge_ok`]). Then the
//! vertices `A = av(p, k)` (id `k`) and `C = av(k, q)` (id `q`) give way to
//! `Z = av(p, q)` (id `q`): the approximation grows by the triangle
//! `(A, Z, C)`.
//!
//! In the structure, `k` and `q` must both be interior vertices of one
//! corridor chain that carry no middle bridge (nothing else is attached to
//! them), so the merge only shortens that chain by one edge and moves `q`.
//! It is done when the grown triangle, scaled by 3/2 about the midpoint of
//! `A C` (hysteresis: a margin half as large as the triangle itself), meets
//! nothing of that corridor (the other chain, the end-edges, the middle
//! bridge, or for a hull corridor the hull bridges), decided exactly at the
//! current instant, and the corridor's faces are pseudo-triangles just
//! after it (else the merge is undone). It is not tried while a
//! certificate still names `k` or one on `q` fails at the instant. Only a
//! few candidates are tried per
//! event (a rotating position along the chains of the corridors the event
//! touched), so the cost per event stays O(chain length).

use super::faces::{step_ccw, step_cw};
use super::geo::{Geo, Shapes};
use super::{Att, CorrId, Kss, Obj};
use crate::geom::{orient, Point};
use crate::num::{Interval, Rational, Sign, Time};
use crate::world::World;

/// Whether the closed segment `(p, q)` and the closed triangle `t` (counter-
/// clockwise) meet: no separating line among the triangle's edge lines and
/// the segment's line.
fn segment_meets_triangle(p: &Point, q: &Point, t: &[Point; 3]) -> bool {
    for i in 0..3 {
        let (a, b) = (&t[i], &t[(i + 1) % 3]);
        if orient(a, b, p) == Sign::Negative && orient(a, b, q) == Sign::Negative {
            return false;
        }
    }
    let sides: Vec<Sign> = t.iter().map(|x| orient(p, q, x)).collect();
    if p != q
        && (sides.iter().all(|&s| s == Sign::Positive)
            || sides.iter().all(|&s| s == Sign::Negative))
    {
        return false;
    }
    true
}

/// [`segment_meets_triangle`] from enclosures of the points (the triangle
/// counter-clockwise), where the f64 filter decides every sign the answer
/// rests on; `None` otherwise.
fn segment_meets_triangle_enclosed(
    p: [Interval; 2],
    q: [Interval; 2],
    t: &[[Interval; 2]; 3],
) -> Option<bool> {
    use crate::geom::orient_enclosed;
    let neg = Some(Sign::Negative);
    let pos = Some(Sign::Positive);
    // (a sign the filter decides is the exact one, and not zero)
    let mut edges_meet = true;
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let (sp, sq) = (orient_enclosed(a, b, p), orient_enclosed(a, b, q));
        if sp == neg && sq == neg {
            return Some(false);
        }
        edges_meet &= sp == pos || sq == pos;
    }
    let sides = t.map(|x| orient_enclosed(p, q, x));
    if sides.iter().all(|&s| s == pos) || sides.iter().all(|&s| s == neg) {
        // (p ≠ q: their turn with a corner is not zero)
        return Some(false);
    }
    (edges_meet && sides.contains(&pos) && sides.contains(&neg)).then_some(true)
}

/// `x` scaled by the margin's factor 3/2 about `m`.
fn widen_about(m: &Point, x: &Point) -> Point {
    m.add(
        &x.sub(m)
            .scale(&Rational::from_dyadic(crate::num::Int::from(3), -1)),
    )
}

impl Kss {
    /// Try to merge away one interior vertex of corridor `k`'s chains, the
    /// `tick`-th candidate in chain order (module docs), unless `busy(k, q)`
    /// (certificates that name the vertex to remove, or that fail at this
    /// instant on the one to move). Returns the id whose position changed
    /// (`q`), or `None`.
    pub fn coarsen_one(
        &mut self,
        world: &World,
        shapes: &mut Shapes,
        k: CorrId,
        t: &Time,
        tick: u64,
        busy: &dyn Fn(Att, Att) -> bool,
    ) -> Option<Att> {
        let c = self.corrs[k.0 as usize].clone();
        // (only an approximation's vertex is ever hidden)
        let approximated = |o: Obj| matches!(o, Obj::Body(b) if shapes.approx(b).is_some());
        if !approximated(c.a) && !approximated(c.b) {
            return None;
        }
        let (a_s, b_s, a_t, b_t) = self.ends(k);
        // candidate chains: A from a_s (len_a), B from b_t (len_b)
        let mut chains: arrayvec::ArrayVec<(Att, u32, bool), 2> = arrayvec::ArrayVec::new();
        chains.push((a_s, c.len_a, true));
        if c.b != Obj::Omega {
            chains.push((b_t, c.len_b, false));
        }
        let total: u32 = chains.iter().map(|&(_, l, _)| l.saturating_sub(2)).sum();
        if total == 0 {
            return None;
        }
        // the `tick`-th interior position with both `k` and `q = ccw(k)`
        // strictly inside the chain: cw offsets 2..len from the start
        let mut n = (tick % u64::from(total)) as u32;
        let (start, _, on_a) = chains
            .iter()
            .copied()
            .find(|&(_, l, _)| {
                let here = l.saturating_sub(2);
                if n < here {
                    true
                } else {
                    n -= here;
                    false
                }
            })
            .expect("a chain with the position");
        let d = n + 2; // offset of `k` from the chain's start
        let (kv, qv, bid) = {
            let geo = Geo {
                world,
                shapes: &*shapes,
            };
            let kv = step_cw(&geo, start, d);
            let qv = step_ccw(&geo, kv);
            let Obj::Body(bid) = kv.obj else {
                return None;
            };
            (kv, qv, bid)
        };
        if let Some((mi, mj)) = c.mid {
            let geo = Geo {
                world,
                shapes: &*shapes,
            };
            let alpha = step_cw(&geo, a_s, mi);
            let beta = step_cw(&geo, b_t, mj);
            if [alpha, beta].iter().any(|x| *x == kv || *x == qv) {
                return None;
            }
        }
        let ap = shapes.approx(bid)?;
        let kk = kv.v as usize;
        let (p, q) = (ap.exposed().pred(kk)?, ap.exposed().succ(kk)?);
        if q != qv.v as usize || ap.hidden(kk) || ap.hidden(p) || ap.hidden(q) {
            return None;
        }
        if !ap.array.merge_ok(ap.exposed(), kk) {
            return None;
        }
        // a certificate still names `k`, or one on `q` fails at this
        // instant: not now (asked after the approximation's own tests,
        // which turn down more candidates and read no certificate)
        if busy(kv, qv) {
            return None;
        }
        // positions at `t`: A (id k), C (id q) now; Z (id q) after; the
        // triangle `big` is ACZ scaled by 3/2 about the midpoint m of AC
        // (each corner x becomes (3x − m)/2). Its f64 enclosure first: a segment whose box
        // misses the triangle's box misses the triangle, and only the
        // others need the exact positions. (Merges happen at rational
        // instants only. The instant's exact value is asked for only where
        // exact positions are needed, since asking computes a deferred
        // event time; the filter needs only the instant's enclosure.)
        let body = world.body(bid);
        let tiv = t.interval();
        let enc = |i: usize, j: usize| {
            let [x, y] = ap.array.av_enclose(i, j)?;
            Some(body.frame.enclose(x, y, tiv))
        };
        let big_box = match (enc(p, kk), enc(kk, q), enc(p, q)) {
            (Some(ea), Some(ec), Some(ez)) => {
                let (half, wide) = (Interval::point(0.5), Interval::point(1.5));
                let m = [(ea[0] + ec[0]) * half, (ea[1] + ec[1]) * half];
                let scaled =
                    |x: [Interval; 2]| [wide * x[0] - half * m[0], wide * x[1] - half * m[1]];
                let b = [scaled(ea), scaled(ec), scaled(ez)];
                // (counter-clockwise, as `exact_big` orders it)
                let b = match crate::geom::orient_enclosed(b[0], b[1], b[2]) {
                    Some(Sign::Negative) => Some([b[0], b[2], b[1]]),
                    Some(_) => Some(b),
                    None => None,
                };
                b.map(|b| {
                    let hull = |d: usize| {
                        let lo = b[0][d].lo.min(b[1][d].lo).min(b[2][d].lo);
                        let hi = b[0][d].hi.max(b[1][d].hi).max(b[2][d].hi);
                        (lo, hi)
                    };
                    ([hull(0), hull(1)], b)
                })
            }
            _ => None,
        };
        let exact_big = || -> Option<[Point; 3]> {
            let r = t.as_rational()?;
            let at = |h: crate::hier::HomPoint| {
                body.traj.position_at(r).add(&h.to_point(body.shape.exp()))
            };
            let pa = at(ap.array.av(p, kk)?);
            let pc = at(ap.array.av(kk, q)?);
            let pz = at(ap.array.av(p, q)?);
            let m = pa
                .add(&pc)
                .scale(&Rational::from_dyadic(crate::num::Int::from(1), -1));
            let big = [
                widen_about(&m, &pa),
                widen_about(&m, &pc),
                widen_about(&m, &pz),
            ];
            let big = if orient(&big[0], &big[1], &big[2]) == Sign::Negative {
                [big[0].clone(), big[2].clone(), big[1].clone()]
            } else {
                big
            };
            if orient(&big[0], &big[1], &big[2]) == Sign::Zero {
                return None;
            }
            Some(big)
        };
        let mut exact: Option<[Point; 3]> = None;
        if big_box.is_none() {
            // (a flat triangle, or one the filter cannot tell from flat)
            exact = Some(exact_big()?);
        }
        // everything of the corridor but the merged chain
        let geo = Geo {
            world,
            shapes: &*shapes,
        };
        let mut segs: Vec<(Att, Att)> = Vec::new();
        if c.b == Obj::Omega {
            let x = self.other_finite_corner(c.s.0, a_s);
            let y = self.other_finite_corner(c.t.0, a_t);
            segs.push((a_s, x));
            segs.push((a_t, y));
        } else {
            segs.push((a_s, b_s));
            segs.push((a_t, b_t));
            if let Some((mi, mj)) = c.mid {
                segs.push((step_cw(&geo, a_s, mi), step_cw(&geo, b_t, mj)));
            }
            let (other, olen) = if on_a { (b_t, c.len_b) } else { (a_s, c.len_a) };
            let mut x = other;
            for _ in 0..olen {
                let y = step_cw(&geo, x, 1);
                segs.push((x, y));
                x = y;
            }
            if olen == 0 {
                segs.push((other, other));
            }
        }
        // (a chain's segments share their ends: each end enclosed once)
        let mut last: Option<(Att, Option<[Interval; 2]>)> = None;
        for (u, v) in segs {
            let eu = match last {
                Some((x, e)) if x == u => e,
                _ => geo.enclose(u, tiv),
            };
            let ev = geo.enclose(v, tiv);
            last = Some((v, ev));
            if let (Some((bb, tri)), Some(eu), Some(ev)) = (big_box, eu, ev) {
                let apart =
                    |d: usize| eu[d].hi.max(ev[d].hi) < bb[d].0 || eu[d].lo.min(ev[d].lo) > bb[d].1;
                if apart(0) || apart(1) {
                    continue;
                }
                // (the signs of the exact test, where the filter decides them)
                let decided = segment_meets_triangle_enclosed(eu, ev, &tri);
                #[cfg(debug_assertions)]
                if let (Some(d), Some(big), Some(pu), Some(pv)) = (
                    decided,
                    exact_big(),
                    t.as_rational().and_then(|r| geo.position(u, r)),
                    t.as_rational().and_then(|r| geo.position(v, r)),
                ) {
                    assert_eq!(
                        d,
                        segment_meets_triangle(&pu, &pv, &big),
                        "the filter misjudges the merge's triangle"
                    );
                }
                match decided {
                    Some(false) => continue,
                    Some(true) => return None,
                    None => {}
                }
            }
            if exact.is_none() {
                exact = Some(exact_big()?);
            }
            let big = exact.as_ref().expect("computed above");
            let r = t.as_rational()?;
            let (Some(pu), Some(pv)) = (geo.position(u, r), geo.position(v, r)) else {
                return None;
            };
            if segment_meets_triangle(&pu, &pv, big) {
                return None;
            }
        }
        // (at a rational instant only. Where a deferred instant's
        // certificate tells it rational by its degree, that is known
        // without computing it; an instant that only computing it would
        // tell is passed over like an irrational one: a merge is never
        // needed, and such instants, roots of certificates over three
        // bodies, are mostly irrational)
        if !t.known_rational() && (t.is_pending() || t.as_rational().is_none()) {
            return None;
        }
        debug_assert!(
            t.as_rational().is_some(),
            "a merge at an irrational instant"
        );
        // merge, re-measure the chain and check the faces just after `t`
        let saved = self.corrs[k.0 as usize].clone();
        let mid_before = c.mid;
        {
            let ap = shapes.per[bid.index()].as_mut()?;
            if !ap.merge(kk, &world.body(bid).shape) {
                return None;
            }
        }
        let undo = |shapes: &mut Shapes| {
            if let Some(ap) = shapes.per[bid.index()].as_mut() {
                ap.unmerge(kk);
            }
        };
        {
            let ap = shapes.approx(bid).expect("merged");
            if ap.hidden(p) || ap.hidden(q) {
                undo(shapes);
                return None;
            }
        }
        let cm = &mut self.corrs[k.0 as usize];
        if on_a {
            cm.len_a -= 1;
        } else {
            cm.len_b -= 1;
        }
        if let Some((mi, mj)) = mid_before {
            // `k` at offset `d` from the start: a bridge end beyond it moves
            // one step closer
            cm.mid = Some(if on_a {
                (if mi > d { mi - 1 } else { mi }, mj)
            } else {
                (mi, if mj > d { mj - 1 } else { mj })
            });
        }
        let geo = Geo {
            world,
            shapes: &*shapes,
        };
        let ok = if c.b == Obj::Omega {
            self.hull_turns(&geo, k)
                .into_iter()
                .all(|(p3, _)| super::local::turn(&geo, p3[0], p3[1], p3[2], t) == Sign::Positive)
        } else {
            let mid = self.corrs[k.0 as usize].mid;
            self.faces_valid(&geo, k, mid, t)
        };
        if !ok {
            self.corrs[k.0 as usize] = saved;
            undo(shapes);
            return None;
        }
        Some(qv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: i64, y: i64) -> Point {
        Point::from_f64([x as f64, y as f64]).expect("finite")
    }

    #[test]
    fn segments_and_triangles() {
        let t = [pt(0, 0), pt(4, 0), pt(0, 4)];
        assert!(segment_meets_triangle(&pt(1, 1), &pt(9, 9), &t));
        assert!(segment_meets_triangle(&pt(-1, 2), &pt(5, 2), &t));
        assert!(!segment_meets_triangle(&pt(3, 3), &pt(9, 9), &t));
        assert!(segment_meets_triangle(&pt(2, 2), &pt(9, 9), &t)); // touches
        assert!(!segment_meets_triangle(&pt(-1, -1), &pt(-1, 9), &t));
        assert!(!segment_meets_triangle(&pt(5, -1), &pt(-1, -2), &t));
        assert!(segment_meets_triangle(&pt(1, 1), &pt(1, 1), &t));
    }
}
