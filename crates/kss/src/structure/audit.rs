//! Exact checks of the structure's invariants (the audit).

use super::geo::Geo;
use super::{Att, Kss, Obj};
use crate::structure::StructureError;

impl Kss {
    /// Check the combinatorial invariants: `2k − 2` partition triangles and
    /// `3k − 3` corridors for `k` alive bodies, corners of each partition
    /// triangle on three objects, each corridor linked from both its ends,
    /// chains that run from one end to the other, and chains that cover
    /// every polygon edge exactly once.
    pub fn check_topology(&self, world: &Geo) -> Result<(), StructureError> {
        let k = world.bodies().iter().filter(|b| b.alive).count();
        if k != world.alive_count() {
            return Err(StructureError::Invariant(format!(
                "{k} bodies alive, the world counts {}",
                world.alive_count()
            )));
        }
        if k < 2 {
            return if self.tris.is_empty() && self.corrs.is_empty() {
                Ok(())
            } else {
                Err(StructureError::Invariant(
                    "structure for fewer than two bodies".into(),
                ))
            };
        }
        if self.tris.len() != 2 * k - 2 || self.corrs.len() != 3 * k - 3 {
            return Err(StructureError::Invariant(format!(
                "{} partition triangles and {} corridors for k = {k} (want {} and {})",
                self.tris.len(),
                self.corrs.len(),
                2 * k - 2,
                3 * k - 3
            )));
        }
        for (ti, t) in self.tris.iter().enumerate() {
            let [x, y, z] = t.c;
            if x.obj == y.obj || y.obj == z.obj || x.obj == z.obj {
                return Err(StructureError::Invariant(format!(
                    "partition triangle {ti} has two corners on one object"
                )));
            }
            for i in 0..3 {
                let c = &self.corrs[t.corr[i].0 as usize];
                let here = (super::TriId(ti as u32), i as u8);
                if c.s != here && c.t != here {
                    return Err(StructureError::Invariant(format!(
                        "corridor {:?} does not link back to triangle {ti}",
                        t.corr[i]
                    )));
                }
            }
        }
        let mut covered: Vec<Vec<u8>> = (0..world.len())
            .map(|b| vec![0u8; world.id_bound(crate::world::BodyId::new(b as u32))])
            .collect();
        for (ki, c) in self.corrs.iter().enumerate() {
            let (a_s, b_s, a_t, b_t) = self.ends(super::CorrId(ki as u32));
            if a_s.obj != c.a || a_t.obj != c.a || b_s.obj != c.b || b_t.obj != c.b {
                return Err(StructureError::Invariant(format!(
                    "corridor {ki}: ends on the wrong objects"
                )));
            }
            if c.a == Obj::Omega {
                return Err(StructureError::Invariant(format!("corridor {ki}: A is ω")));
            }
            walk_chain(world, a_s, a_t, c.len_a, &mut covered)
                .map_err(|e| e.within(format_args!("corridor {ki}, A-chain")))?;
            if c.b == Obj::Omega {
                if c.len_b != 0 {
                    return Err(StructureError::Invariant(format!(
                        "corridor {ki}: a chain on ω"
                    )));
                }
            } else {
                walk_chain(world, b_t, b_s, c.len_b, &mut covered)
                    .map_err(|e| e.within(format_args!("corridor {ki}, B-chain")))?;
            }
            if let Some((i, j)) = c.mid {
                if i > c.len_a || j > c.len_b {
                    return Err(StructureError::Invariant(format!(
                        "corridor {ki}: middle bridge off its chains"
                    )));
                }
            }
        }
        for (bi, cov) in covered.iter().enumerate() {
            if !world.bodies()[bi].alive {
                continue;
            }
            let ids = world.ids(crate::world::BodyId::new(bi as u32));
            if let Some(&e) = ids.iter().find(|&&e| cov[e as usize] != 1) {
                return Err(StructureError::Invariant(format!(
                    "edge {e} of body {} is in {} corridor chains",
                    world.bodies()[bi].id,
                    cov[e as usize]
                )));
            }
        }
        Ok(())
    }
}

/// Walk `len` edges clockwise from `from`; it must end at `to`. Marks the
/// edges covered (edge `i` joins vertices `i` and `i + 1`).
fn walk_chain(
    world: &Geo,
    from: Att,
    to: Att,
    len: u32,
    covered: &mut [Vec<u8>],
) -> Result<(), StructureError> {
    let Obj::Body(b) = from.obj else {
        return Err(StructureError::Invariant("chain on ω".into()));
    };
    let n = world.count(b);
    if len > n {
        return Err(StructureError::Invariant(format!(
            "{len} edges on a {n}-gon"
        )));
    }
    let mut v = from;
    for _ in 0..len {
        let prev = world.cw(v, 1);
        covered[b.index()][prev.v as usize] += 1;
        v = prev;
    }
    let v = v.v;
    if v != to.v {
        return Err(StructureError::Invariant(format!(
            "walked {len} edges from {} to {}, expected {}",
            from.v, v, to.v
        )));
    }
    Ok(())
}

impl Kss {
    /// Check that no bridge (a side of a partition triangle between two
    /// finite corners, or a middle bridge) passes through the interior of a
    /// polygon at the rational instant `t`. With the face checks this is what
    /// makes the faces tile the free space: a face whose sign pattern is a
    /// pseudo-triangle's but which wraps around a polygon has a bridge
    /// through that polygon. `O(bridges · N)` exact tests after a box filter.
    pub fn check_bridges(
        &self,
        world: &Geo,
        t: &crate::num::Rational,
    ) -> Result<(), StructureError> {
        use super::build::position;
        use crate::geom::{segment_meets_convex_interior, Point};
        let placed: Vec<Option<(Vec<Point>, [f64; 4])>> = world
            .bodies()
            .iter()
            .enumerate()
            .map(|(bi, b)| {
                b.alive.then(|| {
                    let id = crate::world::BodyId::new(bi as u32);
                    let pts: Vec<Point> = world
                        .ids(id)
                        .into_iter()
                        .map(|v| {
                            position(world, super::Att::vertex(id, v), t)
                                .expect("a vertex, not ω, has a position")
                        })
                        .collect();
                    let mut bx = [
                        f64::INFINITY,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                    ];
                    for p in &pts {
                        let [x, y] = p.to_f64();
                        bx = [bx[0].min(x), bx[1].min(y), bx[2].max(x), bx[3].max(y)];
                    }
                    (pts, bx)
                })
            })
            .collect();
        let mut bridges: Vec<(Att, Att)> = Vec::new();
        for tri in &self.tris {
            for i in 0..3 {
                let (x, y) = (tri.c[i], tri.c[(i + 1) % 3]);
                if !x.is_omega() && !y.is_omega() {
                    bridges.push((x, y));
                }
            }
        }
        for ki in 0..self.corrs.len() {
            let k = super::CorrId(ki as u32);
            if let Some((i, j)) = self.corrs[ki].mid {
                let (a_s, _, _, b_t) = self.ends(k);
                bridges.push((
                    super::faces::step_cw(world, a_s, i),
                    super::faces::step_cw(world, b_t, j),
                ));
            }
        }
        // hull sides appear in one finite and one infinite triangle, or in
        // two triangles: checking a segment twice is harmless
        for (x, y) in bridges {
            let (p, q) = (
                position(world, x, t).expect("a vertex, not ω, has a position"),
                position(world, y, t).expect("a vertex, not ω, has a position"),
            );
            let (pf, qf) = (p.to_f64(), q.to_f64());
            // a little slack: the box filter must never skip a real hit
            let slack = |v: f64| v.abs() * 1e-9 + 1e-300;
            let (lo_x, hi_x) = (pf[0].min(qf[0]), pf[0].max(qf[0]));
            let (lo_y, hi_y) = (pf[1].min(qf[1]), pf[1].max(qf[1]));
            for (bi, body) in placed.iter().enumerate() {
                let Some((pts, bx)) = body else { continue };
                if hi_x + slack(hi_x) < bx[0] - slack(bx[0])
                    || lo_x - slack(lo_x) > bx[2] + slack(bx[2])
                    || hi_y + slack(hi_y) < bx[1] - slack(bx[1])
                    || lo_y - slack(lo_y) > bx[3] + slack(bx[3])
                {
                    continue;
                }
                if segment_meets_convex_interior(&p, &q, pts) {
                    return Err(StructureError::Invariant(format!(
                        "bridge {x:?}–{y:?} passes through the interior of body {bi}"
                    )));
                }
            }
        }
        Ok(())
    }
}
