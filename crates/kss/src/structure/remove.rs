//! Removing a polygon in place (`remove` mode).
//!
//! Removing body `P` leaves a hole: the region `R` made of `P`, the
//! partition triangles with a corner on `P` and the corridors with `P` on
//! one side. `R` is bounded by the chains of `P`'s neighbours that faced
//! it (in those corridors) and by the sides of its triangles opposite
//! `P` (bridges between two neighbours, or rays to `ω` when `P` was on the
//! convex hull). Only `R` is triangulated again: an exact constrained
//! triangulation ([`crate::cdt`]) of the vertices on its boundary, with the
//! chain edges and the finite bridges as constraints, keeps the triangles
//! on `R`'s side of them,
//! and the edges of the local hull that bound `R` become new hull edges
//! (faces with `ω`). Faces on three objects are the new partition
//! triangles; corridors are walked as in the construction, except that a
//! walk that reaches a bridge of `R`'s boundary goes on through the
//! corridor outside it (which ended at a removed triangle), so that the
//! outside corridors that ended at `R` are merged into the new ones.
//!
//! Several bodies that leave at one instant and touch (the two of a
//! collision in `remove` mode) leave one hole, the union of their regions
//! ([`Kss::removal_plan_of`]): the corridors between them go with them, and
//! the region is triangulated once. Bodies whose regions are apart have no
//! such plan (the engine removes each group of collisions by itself).
//!
//! The cost is the size of `R`'s boundary (the facing chains), not the
//! number of polygons; a removal that cannot be done this way (the region
//! has no triangulation even shrunk, or fewer than two bodies stay) is
//! reported as an error and the caller rebuilds.

/// Maps and sets with the fast fixed hasher (keys are small ids).
type HashMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;
type HashSet<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;

use super::build::{cross_two_object_face, is_partition, Vertices};
use super::geo::Geo;
use super::{Att, CorrId, Corridor, Kss, Obj, PartitionTriangle, TriId};
use crate::cdt::{self, CdtError};
use crate::num::{Rational, Sign, Time};
use crate::structure::StructureError;
use crate::world::BodyId;

/// An end of a planned corridor: a side of a new triangle (by its index
/// among the new ones) or of a triangle that stays.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum End {
    New(usize, u8),
    Old(TriId, u8),
}

/// A corridor of the plan.
#[derive(Clone, Copy, Debug)]
struct PlannedCorr {
    a: Obj,
    b: Obj,
    s: End,
    t: End,
    len_a: u32,
    len_b: u32,
}

/// What removing a body changes, computed without touching the structure.
#[derive(Clone, Debug)]
pub struct RemovalPlan {
    /// Triangles that go (sorted): those with a corner on the body.
    pub dead_tris: Vec<TriId>,
    /// Corridors that go (sorted): those with the body on one side, and
    /// those outside that ended at a triangle that goes (merged into new
    /// ones).
    pub dead_corrs: Vec<CorrId>,
    new_tris: Vec<[Att; 3]>,
    new_tri_corr: Vec<[usize; 3]>,
    new_corrs: Vec<PlannedCorr>,
    /// Sides of triangles that stay whose corridor is a new one.
    far: Vec<(TriId, u8, usize)>,
}

impl RemovalPlan {
    /// The corners of the new partition triangles.
    pub fn new_triangles(&self) -> &[[Att; 3]] {
        &self.new_tris
    }
}

/// Why a region has no plan ([`Kss::retriangulation_plan`]), and the bodies
/// outside the set that the region should take in to have one (a bridge of
/// its boundary that crosses a polygon of the set names its two bodies).
#[derive(Clone, Debug, Default)]
pub struct PlanError {
    /// What failed.
    pub reason: String,
    /// Bodies to add to the set and try again (empty: none known).
    pub grow: Vec<BodyId>,
}

impl From<String> for PlanError {
    fn from(reason: String) -> PlanError {
        PlanError {
            reason,
            grow: Vec::new(),
        }
    }
}

impl From<&str> for PlanError {
    fn from(reason: &str) -> PlanError {
        PlanError::from(reason.to_string())
    }
}

impl std::fmt::Display for PlanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.reason)
    }
}

/// What [`Kss::apply_removal`] did: the ids of the new triangles and
/// corridors, and the ones that were moved to fill the freed slots
/// (`(from, to)`, applied in order).
#[derive(Clone, Debug, Default)]
pub struct Spliced {
    /// The new triangles.
    pub tris: Vec<TriId>,
    /// The new corridors.
    pub corrs: Vec<CorrId>,
    /// Triangles moved from the end of the list into a freed slot.
    pub moved_tris: Vec<(TriId, TriId)>,
    /// Corridors moved from the end of the list into a freed slot.
    pub moved_corrs: Vec<(CorrId, CorrId)>,
}

/// The outside corridor beyond a bridge of `R`'s boundary, and whether the
/// walk enters it at its end `s` (else at `t`).
type Portal = (CorrId, bool);

/// What a region plan is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Region {
    /// Remove the one body of the set.
    Remove,
    /// Triangulate the region again, the set's bodies kept.
    Keep,
    /// Add the set's first body, not yet in the structure.
    Insert,
}

impl Kss {
    /// Plan the removal of body `p` at time `t` (module docs). `world` must
    /// still see every other body as the structure does; `p`'s own
    /// geometry is not used.
    pub fn removal_plan(
        &self,
        world: &Geo,
        p: BodyId,
        now: &Time,
    ) -> Result<RemovalPlan, StructureError> {
        self.removal_plan_of(world, &[p], now)
    }

    /// Plan the removal of the bodies `set` together at time `t`: one
    /// region, the union of each body's ([`Kss::removal_plan`]), triangulated
    /// once; the corridors between two bodies of the set go with them.
    /// `world` must still see every other body as the structure does.
    pub fn removal_plan_of(
        &self,
        world: &Geo,
        set: &[BodyId],
        now: &Time,
    ) -> Result<RemovalPlan, StructureError> {
        let t = now
            .as_rational()
            .ok_or_else(|| StructureError::Local("an irrational instant".into()))?;
        let alive = world.alive_count();
        if alive < 2 {
            return Err(StructureError::Local(format!("{alive} bodies stay")));
        }
        self.region_plan(world, set, t, Region::Remove)
            .map_err(|e| StructureError::Local(e.reason))
    }

    /// Plan a *local retriangulation* around the bodies `set` (alive in
    /// `world`): the region `R` made of the partition triangles with a
    /// corner on one of them and the corridors with one of them on a side
    /// (for one body, the region of its removal, [`Kss::removal_plan`]),
    /// with the bodies kept inside it as obstacles (their edges are
    /// constraints too), triangulated afresh with the positions at the
    /// rational instant `at`. The repair of a degenerate instant that the
    /// local operations cannot resolve (a settled contact, such as three
    /// polygons meeting at one point and moving apart): the structure
    /// changes only inside `R`, so the cost is the bodies' degrees and the
    /// chains facing them, not the number of polygons. The counts stay: as
    /// many new triangles and corridors as go.
    pub fn retriangulation_plan(
        &self,
        world: &Geo,
        set: &[BodyId],
        at: &Rational,
    ) -> Result<RemovalPlan, PlanError> {
        self.region_plan(world, set, at, Region::Keep)
    }

    /// Plan the *insertion* of body `set[0]`, alive in `world` but not yet
    /// in the structure, into the region around the other bodies of `set`
    /// ([`Kss::retriangulation_plan`] with the new body among the kept
    /// ones): the region must contain it, and the plan has two partition
    /// triangles and three corridors more than the region had (a body more
    /// in a triangulation of the bodies and `ω`). An error names the
    /// bodies to grow the set by where it knows them (a boundary bridge
    /// that the new body crosses).
    pub fn insertion_plan(
        &self,
        world: &Geo,
        set: &[BodyId],
        at: &Rational,
    ) -> Result<RemovalPlan, PlanError> {
        self.region_plan(world, set, at, Region::Insert)
    }

    /// The bodies that share a partition triangle or a corridor with a body
    /// of `set`, not in it (sorted), from the triangles and corridors on
    /// the set's bodies ([`Kss::incidence`]).
    pub fn neighbours(&self, set: &[BodyId]) -> Vec<BodyId> {
        let mut out: Vec<BodyId> = Vec::new();
        let mut add = |objs: &[Obj]| {
            out.extend(objs.iter().filter_map(|&o| match o {
                Obj::Body(b) if !set.contains(&b) => Some(b),
                _ => None,
            }));
        };
        for &b in set {
            for t in self.incidence.tris_on(&self.tris, b) {
                add(&self.tris[t as usize].c.map(|c| c.obj));
            }
            for k in self.incidence.corrs_on(&self.corrs, b) {
                let c = &self.corrs[k as usize];
                add(&[c.a, c.b]);
            }
        }
        out.sort();
        out.dedup();
        #[cfg(debug_assertions)]
        {
            let in_set = |o: Obj| matches!(o, Obj::Body(b) if set.contains(&b));
            let mut scan: Vec<BodyId> = Vec::new();
            let mut add = |objs: &[Obj]| {
                if objs.iter().any(|&o| in_set(o)) {
                    scan.extend(objs.iter().filter_map(|&o| match o {
                        Obj::Body(b) if !set.contains(&b) => Some(b),
                        _ => None,
                    }));
                }
            };
            for t in &self.tris {
                add(&t.c.map(|c| c.obj));
            }
            for c in &self.corrs {
                add(&[c.a, c.b]);
            }
            scan.sort();
            scan.dedup();
            debug_assert_eq!(out, scan, "the incidence index misses a neighbour");
        }
        out
    }

    /// [`Kss::removal_plan`], [`Kss::retriangulation_plan`] or
    /// [`Kss::insertion_plan`] (by `region`) at the rational instant `t`.
    fn region_plan(
        &self,
        world: &Geo,
        set: &[BodyId],
        t: &Rational,
        region: Region,
    ) -> Result<RemovalPlan, PlanError> {
        let keep = region != Region::Remove;
        let in_set = |o: Obj| matches!(o, Obj::Body(b) if set.contains(&b));
        // (from the incidence index: the triangles and corridors on the
        // set's bodies, in the order of their ids)
        let on_set = |of: &dyn Fn(BodyId) -> Vec<u32>| {
            let mut ids: Vec<u32> = set.iter().flat_map(|&b| of(b)).collect();
            ids.sort_unstable();
            ids.dedup();
            ids
        };
        let dead_tris: Vec<TriId> = on_set(&|b| self.incidence.tris_on(&self.tris, b))
            .into_iter()
            .map(TriId)
            .collect();
        let star: Vec<CorrId> = on_set(&|b| self.incidence.corrs_on(&self.corrs, b))
            .into_iter()
            .map(CorrId)
            .collect();
        debug_assert_eq!(
            dead_tris,
            (0..self.tris.len())
                .filter(|&i| self.tris[i].c.iter().any(|c| in_set(c.obj)))
                .map(|i| TriId(i as u32))
                .collect::<Vec<_>>(),
            "the incidence index misses a triangle"
        );
        debug_assert_eq!(
            star,
            (0..self.corrs.len())
                .filter(|&i| in_set(self.corrs[i].a) || in_set(self.corrs[i].b))
                .map(|i| CorrId(i as u32))
                .collect::<Vec<_>>(),
            "the incidence index misses a corridor"
        );
        if dead_tris.len() < 2 && !keep {
            return Err("the body has fewer than two triangles".into());
        }
        // (sorted: found by a binary search)
        let is_dead = |t: &TriId| dead_tris.binary_search(t).is_ok();
        // the bridges of R's boundary, each with R on its left, and the
        // outside corridors beyond them
        let mut portal: HashMap<(Att, Att), Portal> =
            HashMap::with_capacity_and_hasher(dead_tris.len(), Default::default());
        let mut merged: Vec<CorrId> = Vec::with_capacity(dead_tris.len());
        let mut bridges: Vec<(Att, Att)> = Vec::with_capacity(dead_tris.len());
        for &tri in &dead_tris {
            let c = self.tris[tri.0 as usize].c;
            // the sides away from the set (one for a single body)
            for j in 0..3 {
                let (x, y) = (c[j], c[(j + 1) % 3]);
                if in_set(x.obj) || in_set(y.obj) {
                    continue;
                }
                let k = self.tris[tri.0 as usize].corr[j];
                let kc = &self.corrs[k.0 as usize];
                let at_s = kc.s == (tri, j as u8);
                if !at_s && kc.t != (tri, j as u8) {
                    return Err(format!("corridor {k:?} does not end at triangle {tri:?}").into());
                }
                if portal.insert((y, x), (k, at_s)).is_some() {
                    return Err("two bridges on one side".into());
                }
                if !merged.contains(&k) {
                    merged.push(k);
                }
                bridges.push((x, y));
            }
        }
        // the chains of the region's corridors, walked clockwise (free
        // space on the left): those facing the set bound the region from
        // outside, a kept body's own bound it from inside
        // (sized for the chains facing the set)
        let facing: usize = star
            .iter()
            .map(|k| {
                let c = &self.corrs[k.0 as usize];
                (c.len_a + c.len_b) as usize
            })
            .sum();
        let mut chains: Vec<(Att, Att)> = Vec::with_capacity(facing);
        let mut ends: Vec<Att> = Vec::with_capacity(4 * star.len());
        for &k in &star {
            let c = &self.corrs[k.0 as usize];
            let (a_s, _, _, b_t) = self.ends(k);
            for (obj, from, len) in [(c.a, a_s, c.len_a), (c.b, b_t, c.len_b)] {
                // a kept body's boundary is taken whole below
                if from.is_omega() || in_set(obj) {
                    continue;
                }
                ends.push(from);
                let mut v = from;
                for _ in 0..len {
                    let w = world.cw(v, 1);
                    chains.push((v, w));
                    v = w;
                }
                ends.push(v);
            }
        }
        // a kept body's whole boundary as it is now (the union of its
        // chains in the region's corridors; read from the polygon rather
        // than walked along the chains, whose lengths are stale when its
        // approximation was just refined)
        if keep {
            for &b in set {
                for id in world.ids(b) {
                    let v = Att::vertex(b, id);
                    chains.push((v, world.cw(v, 1)));
                }
            }
        }
        // local vertex numbering
        let mut index: HashMap<Att, usize> = HashMap::with_capacity_and_hasher(
            chains.len() + bridges.len() + ends.len(),
            Default::default(),
        );
        let mut atts: Vec<Att> = Vec::with_capacity(chains.len() + bridges.len() + ends.len());
        let mut add = |a: Att, atts: &mut Vec<Att>| {
            if !a.is_omega() {
                index.entry(a).or_insert_with(|| {
                    atts.push(a);
                    atts.len() - 1
                });
            }
        };
        for &(u, v) in chains.iter().chain(&bridges) {
            add(u, &mut atts);
            add(v, &mut atts);
        }
        for &a in &ends {
            add(a, &mut atts);
        }
        let mut constraints: HashSet<(usize, usize)> =
            HashSet::with_capacity_and_hasher(chains.len() + bridges.len(), Default::default());
        for &(u, v) in chains.iter().chain(&bridges) {
            if u.is_omega() || v.is_omega() {
                continue;
            }
            let (x, y) = (index[&u], index[&v]);
            if x == y {
                return Err("a constraint of length zero".into());
            }
            constraints.insert((x.min(y), x.max(y)));
        }
        // the local triangulation, oriented exactly, with its adjacency
        // (which triangle lies across a side, which one holds an edge)
        let mut mesh: Option<cdt::Triangulation> = None;
        if atts.len() >= 3 {
            // polygon edges first and bridges last, so that a bridge that
            // crosses a polygon is the constraint reported
            let mut edges: Vec<[usize; 2]> = constraints.iter().map(|&(x, y)| [x, y]).collect();
            edges.sort_unstable_by_key(|&[x, y]| (atts[x].obj != atts[y].obj, x, y));
            // a crossing constraint names bodies outside the set to grow it
            // by (a bridge of the region's boundary that a polygon of the
            // set crosses at once: its triangle beyond is inverted just
            // after `t`, a failure of this instant still queued)
            let grow = |conflicts: &[[usize; 2]]| -> Vec<BodyId> {
                let mut out: Vec<BodyId> = conflicts
                    .iter()
                    .flatten()
                    .filter_map(|&x| match atts[x].obj {
                        Obj::Body(b) if !set.contains(&b) => Some(b),
                        _ => None,
                    })
                    .collect();
                out.sort();
                out.dedup();
                out
            };
            // exactly at `t`; where polygons touch at `t` (one sliding
            // along another's edge, a vertex on an edge) the region has no
            // triangulation, and it comes from the infinitesimally shrunk
            // copy (as the construction does), checked exactly below
            let local = |shrink: bool| {
                let vertices = Vertices::new(world, t, atts.clone(), shrink);
                cdt::triangulate_with_adjacency(atts.len(), &edges, &vertices)
            };
            let faces = match local(false) {
                Ok(faces) => faces,
                Err(first) => local(true).map_err(|_| {
                    let conflicts = match &first {
                        CdtError::Crossing(c) => c.clone(),
                        _ => Vec::new(),
                    };
                    PlanError {
                        grow: grow(&conflicts),
                        reason: first.to_string(),
                    }
                })?,
            };
            // every triangle is counter-clockwise exactly, or flat between
            // two polygons in contact (from the shrunk copy: a partition
            // triangle that is flat does not hold just after `t` and is
            // refused by the caller; a corridor's is checked by its
            // decomposition)
            mesh = Some(faces);
        }
        let tris: Vec<[usize; 3]> = mesh
            .as_ref()
            .map_or_else(Vec::new, |m| (0..m.len()).map(|f| m.triangle(f)).collect());
        // the faces of R: triangles reached from the inner side of the
        // boundary without crossing it, and ω-faces on new hull edges
        let is_constraint = |x: usize, y: usize| constraints.contains(&(x.min(y), x.max(y)));
        let mut inside = vec![false; tris.len()];
        let mut hull: Vec<(usize, usize)> = Vec::new();
        let mut stack: Vec<usize> = Vec::with_capacity(tris.len());
        // (the triangle `f` on the left of the directed edge `(x, y)`, or
        // a hull edge where there is none)
        let enter = |f: Option<usize>,
                     (x, y): (usize, usize),
                     inside: &mut Vec<bool>,
                     stack: &mut Vec<usize>,
                     hull: &mut Vec<(usize, usize)>| match f {
            Some(f) => {
                if !inside[f] {
                    inside[f] = true;
                    stack.push(f);
                }
            }
            None => hull.push((x, y)),
        };
        for &(u, v) in chains.iter().chain(&bridges) {
            if u.is_omega() || v.is_omega() {
                continue;
            }
            let (x, y) = (index[&u], index[&v]);
            let f = mesh.as_ref().and_then(|m| m.left_of(x, y));
            enter(f, (x, y), &mut inside, &mut stack, &mut hull);
        }
        while let Some(f) = stack.pop() {
            let tri = tris[f];
            for i in 0..3 {
                let (x, y) = (tri[i], tri[(i + 1) % 3]);
                if !is_constraint(x, y) {
                    // (the triangle across side `i` holds `(y, x)`)
                    let g = mesh.as_ref().and_then(|m| m.across(f, i));
                    enter(g, (y, x), &mut inside, &mut stack, &mut hull);
                }
            }
        }
        hull.sort_unstable();
        hull.dedup();
        // (a kept hull body's ω-corridor makes the region unbounded too)
        let touches_omega = bridges.iter().any(|&(x, y)| x.is_omega() || y.is_omega())
            || (keep
                && star
                    .iter()
                    .any(|k| self.corrs[k.0 as usize].b == Obj::Omega));
        if !hull.is_empty() && !touches_omega {
            return Err("a hull edge in a bounded region".into());
        }
        let mut faces: Vec<[Att; 3]> = Vec::with_capacity(tris.len() + hull.len());
        for (f, tri) in tris.iter().enumerate() {
            if inside[f] {
                faces.push(tri.map(|x| atts[x]));
            }
        }
        for &(x, y) in &hull {
            faces.push([atts[x], atts[y], Att::OMEGA]);
        }
        let mut side_of: HashMap<(Att, Att), (usize, usize)> =
            HashMap::with_capacity_and_hasher(3 * faces.len(), Default::default());
        for (fi, f) in faces.iter().enumerate() {
            if f[0].obj == f[1].obj && f[1].obj == f[2].obj {
                return Err("a face inside a polygon".into());
            }
            for i in 0..3 {
                let (x, y) = (f[i], f[(i + 1) % 3]);
                if x.obj == y.obj && !x.is_omega() && world.ccw(x) != y && world.ccw(y) != x {
                    return Err("a face side cuts through a polygon".into());
                }
                if side_of.insert((x, y), (fi, i)).is_some() {
                    return Err("a side in two faces".into());
                }
            }
        }
        // (the new triangle of each face that is one)
        let mut tri_of: Vec<Option<usize>> = vec![None; faces.len()];
        let mut new_tris: Vec<[Att; 3]> = Vec::with_capacity(dead_tris.len() + 2);
        for (fi, f) in faces.iter().enumerate() {
            if is_partition(f) {
                tri_of[fi] = Some(new_tris.len());
                new_tris.push(*f);
            }
        }
        let mut dead_corrs: Vec<CorrId> = star.clone();
        dead_corrs.extend(merged.iter().copied());
        dead_corrs.sort_unstable();
        dead_corrs.dedup();
        if dead_corrs.len() != star.len() + merged.len() {
            return Err("a corridor both on the body and beyond a bridge".into());
        }
        // (signed: each body removed takes two triangles and three
        // corridors, an insertion adds them)
        let (gone_tris, gone_corrs): (isize, isize) = match region {
            Region::Remove => (2 * set.len() as isize, 3 * set.len() as isize),
            Region::Keep => (0, 0),
            Region::Insert => (-2, -3),
        };
        if new_tris.len() as isize + gone_tris != dead_tris.len() as isize
            || (dead_corrs.len() as isize) < gone_corrs
        {
            return Err(format!(
                "{} new triangles for {} removed",
                new_tris.len(),
                dead_tris.len()
            )
            .into());
        }
        // walk the corridors: from every side of a new triangle, and from
        // the far end of every merged corridor that stays
        let mut starts: Vec<End> = Vec::with_capacity(3 * new_tris.len() + 2 * merged.len());
        for (ti, _) in new_tris.iter().enumerate() {
            for i in 0..3 {
                starts.push(End::New(ti, i as u8));
            }
        }
        for &k in &merged {
            let c = &self.corrs[k.0 as usize];
            for e in [c.s, c.t] {
                if !is_dead(&e.0) {
                    starts.push(End::Old(e.0, e.1));
                }
            }
        }
        let corner = |e: End, i: usize| match e {
            End::New(ti, j) => new_tris[ti][(j as usize + i) % 3],
            End::Old(tri, j) => self.corner(tri, j as usize + i),
        };
        let mut assigned: HashMap<End, usize> =
            HashMap::with_capacity_and_hasher(starts.len(), Default::default());
        let mut used: HashSet<CorrId> = HashSet::default();
        let mut new_corrs: Vec<PlannedCorr> = Vec::with_capacity(starts.len() / 2 + 1);
        let limit = faces.len() + 2 * merged.len() + 4;
        for &start in &starts {
            if assigned.contains_key(&start) {
                continue;
            }
            let (p0, q0) = (corner(start, 0), corner(start, 1));
            if p0.is_omega() {
                continue;
            }
            let (mut len_a, mut len_b) = (0u32, 0u32);
            let (mut x, mut y) = (p0, q0);
            // from a triangle that stays, the walk begins inside the merged
            // corridor across its side
            let mut through: Option<Portal> = match start {
                End::New(..) => None,
                End::Old(tri, j) => {
                    let k = self.tris[tri.0 as usize].corr[j as usize];
                    Some((k, self.corrs[k.0 as usize].s == (tri, j)))
                }
            };
            let mut steps = 0;
            let end = loop {
                steps += 1;
                if steps > limit {
                    return Err("a corridor walk does not end".into());
                }
                if let Some((k, at_s)) = through.take() {
                    if !used.insert(k) {
                        return Err(format!("corridor {k:?} merged twice").into());
                    }
                    let c = &self.corrs[k.0 as usize];
                    let (a_s, b_s, a_t, b_t) = self.ends(k);
                    let (out, la, lb) = if at_s {
                        ((a_t, b_t, c.t), c.len_a, c.len_b)
                    } else {
                        ((b_s, a_s, c.s), c.len_b, c.len_a)
                    };
                    len_a += la;
                    len_b += lb;
                    (x, y) = (out.0, out.1);
                    if !is_dead(&out.2 .0) {
                        break End::Old(out.2 .0, out.2 .1);
                    }
                    continue;
                }
                if let Some(&(fi, sj)) = side_of.get(&(y, x)) {
                    let g = &faces[fi];
                    if let Some(ti) = tri_of[fi] {
                        break End::New(ti, sj as u8);
                    }
                    let on_a;
                    ((x, y), on_a) = cross_two_object_face(g, sj, p0.obj);
                    if on_a {
                        len_a += 1;
                    } else {
                        len_b += 1;
                    }
                } else if let Some(&portal) = portal.get(&(y, x)) {
                    through = Some(portal);
                } else {
                    return Err("a corridor walk left the region".into());
                }
            };
            let j = new_corrs.len();
            for e in [start, end] {
                if assigned.insert(e, j).is_some() {
                    return Err("a triangle side in two corridors".into());
                }
            }
            new_corrs.push(PlannedCorr {
                a: p0.obj,
                b: q0.obj,
                s: start,
                t: end,
                len_a,
                len_b,
            });
        }
        if used.len() != merged.len() {
            return Err("a corridor beyond a bridge was not merged".into());
        }
        if new_corrs.len() as isize + gone_corrs != dead_corrs.len() as isize {
            return Err(format!(
                "{} new corridors for {} removed",
                new_corrs.len(),
                dead_corrs.len()
            )
            .into());
        }
        let mut new_tri_corr = vec![[usize::MAX; 3]; new_tris.len()];
        let mut far = Vec::new();
        for (&e, &j) in &assigned {
            match e {
                End::New(ti, i) => new_tri_corr[ti][i as usize] = j,
                End::Old(tri, i) => far.push((tri, i, j)),
            }
        }
        if new_tri_corr.iter().flatten().any(|&j| j == usize::MAX) {
            return Err("a new triangle side without corridor".into());
        }
        far.sort_unstable();
        Ok(RemovalPlan {
            dead_tris,
            dead_corrs,
            new_tris,
            new_tri_corr,
            new_corrs,
            far,
        })
    }

    /// Whether every new corridor of the retriangulation `plan` has a
    /// pseudo-triangle decomposition just after `now` (after its geodesic
    /// middle bridge, as [`Kss::apply_removal`]'s callers place it). The
    /// plan is applied, the corridors normalized, and every slot it touched
    /// restored: `O(|R|)`, the structure unchanged afterwards. The hull
    /// turns at the new hull bridges must hold just after `now` too. A
    /// corridor between two polygons outside `set` (the polygons the
    /// region was made around) may hold junctions against the motion: a
    /// degeneracy of theirs at the same instant, whose certificates then
    /// fail at once and are handled as further events of the instant, as
    /// after any operation. On failure, the two objects of the first
    /// corridor without either.
    pub fn retriangulation_decomposes(
        &mut self,
        world: &Geo,
        plan: &RemovalPlan,
        set: &[BodyId],
        now: &Time,
    ) -> Result<(), [Obj; 2]> {
        debug_assert!(
            plan.new_tris.len() >= plan.dead_tris.len(),
            "a retriangulation or an insertion plan"
        );
        let (tris0, corrs0) = (self.tris.len(), self.corrs.len());
        let tris: Vec<(TriId, PartitionTriangle)> = (plan.dead_tris.iter().copied())
            .chain(plan.far.iter().map(|&(t, _, _)| t))
            .map(|t| (t, self.tris[t.0 as usize].clone()))
            .collect();
        type Saved = (CorrId, Corridor, Option<Vec<[Att; 3]>>);
        let corrs: Vec<Saved> = (plan.dead_corrs.iter())
            .map(|&k| {
                (
                    k,
                    self.corrs[k.0 as usize].clone(),
                    self.held.get(&k).cloned(),
                )
            })
            .collect();
        let spliced = self.apply_removal(plan.clone());
        // (a decomposition that holds junctions against the motion is not
        // one just after `now`: those certificates would fail at once; only
        // between two polygons outside the set, a degeneracy of theirs)
        // (and the hull must be locally convex just after `now` at the ends
        // of its new bridges: the triangulation's hull is that of the
        // instant tried, and a hull turn can change sign in between)
        let failed = spliced.corrs.iter().find_map(|&k| {
            self.place_middle_bridge(world, k, now);
            let c = &self.corrs[k.0 as usize];
            let inside = |o: Obj| matches!(o, Obj::Body(b) if set.contains(&b));
            let may_hold = !inside(c.a) && !inside(c.b);
            let ok = self.normalize(world, k, now, None).is_ok()
                && (may_hold || !self.held.contains_key(&k))
                && (self.corrs[k.0 as usize].b != Obj::Omega
                    || self.hull_turns(world, k).iter().all(|(p, _)| {
                        super::local::turn(world, p[0], p[1], p[2], now) != Sign::Negative
                    }));
            let c = &self.corrs[k.0 as usize];
            (!ok).then_some([c.a, c.b])
        });
        // (an insertion's extra slots go)
        for k in corrs0..self.corrs.len() {
            self.held.remove(&CorrId(k as u32));
        }
        self.tris.truncate(tris0);
        self.corrs.truncate(corrs0);
        for (t, tri) in tris {
            self.tris[t.0 as usize] = tri;
        }
        for (k, c, held) in corrs {
            self.corrs[k.0 as usize] = c;
            match held {
                Some(h) => self.held.insert(k, h),
                None => self.held.remove(&k),
            };
        }
        match failed {
            None => Ok(()),
            Some(pair) => Err(pair),
        }
    }

    /// Apply a removal plan: the new triangles and corridors take the
    /// lowest freed slots, the triangles that stay point to the new
    /// corridors, and the last triangles and corridors move into the slots
    /// left over (every reference to them follows).
    pub fn apply_removal(&mut self, plan: RemovalPlan) -> Spliced {
        // (an insertion has more new triangles and corridors than freed
        // slots: the others go at the end)
        let (tris0, corrs0) = (self.tris.len(), self.corrs.len());
        let (dt, dc) = (plan.dead_tris.len(), plan.dead_corrs.len());
        let tri_id = |ti: usize| match plan.dead_tris.get(ti) {
            Some(&t) => t,
            None => TriId((tris0 + ti - dt) as u32),
        };
        let corr_id = |j: usize| match plan.dead_corrs.get(j) {
            Some(&k) => k,
            None => CorrId((corrs0 + j - dc) as u32),
        };
        let end = |e: End| match e {
            End::New(ti, i) => (tri_id(ti), i),
            End::Old(tri, i) => (tri, i),
        };
        for (ti, c) in plan.new_tris.iter().enumerate() {
            let tri = PartitionTriangle {
                c: *c,
                corr: plan.new_tri_corr[ti].map(corr_id),
            };
            let slot = tri_id(ti).0 as usize;
            if slot == self.tris.len() {
                self.tris.push(tri);
            } else {
                self.tris[slot] = tri;
            }
        }
        for (j, c) in plan.new_corrs.iter().enumerate() {
            let k = corr_id(j);
            self.held.remove(&k);
            let corr = Corridor {
                a: c.a,
                b: c.b,
                s: end(c.s),
                t: end(c.t),
                len_a: c.len_a,
                len_b: c.len_b,
                mid: None,
            };
            if k.0 as usize == self.corrs.len() {
                self.corrs.push(corr);
            } else {
                self.corrs[k.0 as usize] = corr;
            }
        }
        for &(tri, i, j) in &plan.far {
            self.tris[tri.0 as usize].corr[i as usize] = corr_id(j);
        }
        let mut out = Spliced {
            tris: (0..plan.new_tris.len()).map(tri_id).collect(),
            corrs: (0..plan.new_corrs.len()).map(corr_id).collect(),
            ..Default::default()
        };
        // the freed triangle slots left over are filled from the end
        let free: Vec<u32> = plan
            .dead_tris
            .get(plan.new_tris.len()..)
            .unwrap_or_default()
            .iter()
            .map(|t| t.0)
            .collect();
        let len = self.tris.len() as u32 - free.len() as u32;
        let sources = (len..self.tris.len() as u32).filter(|x| !free.contains(x));
        let holes = free.iter().copied().filter(|&x| x < len);
        for (src, dst) in sources.zip(holes) {
            let tri = self.tris[src as usize].clone();
            for i in 0..3 {
                let c = &mut self.corrs[tri.corr[i].0 as usize];
                let here = (TriId(src), i as u8);
                if c.s == here {
                    c.s = (TriId(dst), i as u8);
                }
                if c.t == here {
                    c.t = (TriId(dst), i as u8);
                }
            }
            self.tris[dst as usize] = tri;
            out.moved_tris.push((TriId(src), TriId(dst)));
        }
        self.tris.truncate(len as usize);
        let free: Vec<u32> = plan
            .dead_corrs
            .get(plan.new_corrs.len()..)
            .unwrap_or_default()
            .iter()
            .map(|k| k.0)
            .collect();
        for &k in &free {
            self.held.remove(&CorrId(k));
        }
        let len = self.corrs.len() as u32 - free.len() as u32;
        let sources = (len..self.corrs.len() as u32).filter(|x| !free.contains(x));
        let holes = free.iter().copied().filter(|&x| x < len);
        for (src, dst) in sources.zip(holes) {
            let c = self.corrs[src as usize].clone();
            self.tris[c.s.0 .0 as usize].corr[c.s.1 as usize] = CorrId(dst);
            self.tris[c.t.0 .0 as usize].corr[c.t.1 as usize] = CorrId(dst);
            if let Some(h) = self.held.remove(&CorrId(src)) {
                self.held.insert(CorrId(dst), h);
            }
            self.corrs[dst as usize] = c;
            out.moved_corrs.push((CorrId(src), CorrId(dst)));
        }
        self.corrs.truncate(len as usize);
        out
    }
}
