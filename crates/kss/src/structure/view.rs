//! A display view of the kinetic separation structure: its partition
//! triangles, corridor faces, bridges and the certificates that fail next,
//! as doubles for [`crate::render`].
//!
//! Read-only: positions are exact at a rational instant and rounded to
//! doubles only at the end; nothing here changes the structure or its event
//! queue, and no double decides anything about the simulation.

use std::collections::BTreeSet;

use super::certs::CertKind;
use super::faces::step_cw;
use super::geo::Geo;
use super::kinetic::Kinetic;
use super::{Att, CorrId, Obj};
use crate::num::{Rational, Time};

/// A segment `[from, to]` in world coordinates.
pub type Segment = [[f64; 2]; 2];

/// One corridor as drawn.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct CorridorOverlay {
    /// Whether the corridor lies between a body and the point at infinity
    /// (unbounded: no face is drawn).
    pub omega: bool,
    /// Its faces (one, or two when it has a middle bridge), each a
    /// counter-clockwise cycle of world points; empty for an ω-corridor and
    /// for an empty corridor (both ends on one segment).
    pub faces: Vec<Vec<[f64; 2]>>,
}

/// A certificate that fails soon, as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct CertificateOverlay {
    /// Its three points `p[0], p[1], p[2]` at the snapshot time.
    pub points: [[f64; 2]; 3],
    /// Why it exists: `"triangle"`, `"junction"`, `"hull turn"` or `"order"`.
    pub kind: &'static str,
    /// Its exact failure time, rounded to a double (display only).
    pub time: f64,
}

/// The structure at the snapshot time, in world coordinates (display only).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct StructureOverlay {
    /// Partition triangles with three finite corners, counter-clockwise.
    pub triangles: Vec<[[f64; 2]; 3]>,
    /// The number of partition triangles with a corner at infinity (not drawn
    /// as areas; their finite side is an end-edge, their sides to `ω` are
    /// drawn as rays, see [`StructureOverlay::omega_rays`]).
    pub infinite_triangles: usize,
    /// Every corridor, in the structure's order.
    pub corridors: Vec<CorridorOverlay>,
    /// End-edges: sides of partition triangles between two finite corners,
    /// each once.
    pub end_edges: Vec<Segment>,
    /// Middle bridges (one per corridor that has one).
    pub middle_bridges: Vec<Segment>,
    /// Bridges to the point at infinity: a finite corner and the outward unit
    /// direction of the ray drawn from it.
    pub omega_rays: Vec<([f64; 2], [f64; 2])>,
    /// The certificates that fail next, earliest first.
    pub certificates: Vec<CertificateOverlay>,
    /// The hierarchical structure's outer approximations, one closed
    /// outline per polygon seen through one, with whether each vertex is a
    /// real polygon vertex (empty for the plain structure).
    pub approximations: Vec<Vec<([f64; 2], bool)>>,
    /// When set, the structure is not drawn and this text is shown instead
    /// (for instance: the run ended before the snapshot time).
    pub note: Option<String>,
}

impl StructureOverlay {
    /// The number of partition triangles, finite and infinite (`2k − 2` for
    /// `k ≥ 2` polygons).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len() + self.infinite_triangles
    }

    /// The number of corridor faces drawn (faces with at least three points).
    pub fn face_count(&self) -> usize {
        self.corridors
            .iter()
            .flat_map(|c| &c.faces)
            .filter(|f| f.len() >= 3)
            .count()
    }
}

/// The name of a certificate kind as shown in pictures.
pub fn kind_name(kind: CertKind) -> &'static str {
    match kind {
        CertKind::Triangle => "triangle",
        CertKind::Junction => "junction",
        CertKind::HullTurn => "hull turn",
        CertKind::Order => "order",
    }
}

/// The outer approximations of the bodies seen through one, at the
/// rational instant `at`: each outline counter-clockwise, with whether each
/// vertex is a real polygon vertex.
pub fn approximations(world: &Geo, at: &Rational) -> Vec<Vec<([f64; 2], bool)>> {
    let mut out = Vec::new();
    for (i, ap) in world.shapes.per.iter().enumerate() {
        let b = crate::world::BodyId::new(i as u32);
        if ap.is_none() || !world.body(b).alive {
            continue;
        }
        out.push(
            world
                .ids(b)
                .into_iter()
                .map(|v| {
                    let a = Att::vertex(b, v);
                    let p = world
                        .position(a, at)
                        .expect("a vertex, not ω, has a position")
                        .to_f64();
                    (p, world.is_real(a))
                })
                .collect(),
        );
    }
    out
}

/// The structure of `kinetic` drawn at the rational instant `at` (between
/// its last processed event and its next one, or at the last event time):
/// every partition triangle and corridor, the end-edges, middle bridges and
/// bridges to `ω`, and the `highlight` scheduled certificates that fail
/// first (in exact time order; ties by their points), with their failure
/// times rounded to doubles.
pub fn overlay(
    world: &Geo,
    kinetic: &Kinetic,
    at: &Rational,
    highlight: usize,
) -> StructureOverlay {
    let kss = &kinetic.kss;
    let pos =
        |a: Att| -> Option<[f64; 2]> { super::build::position(world, a, at).map(|p| p.to_f64()) };
    let mut o = StructureOverlay::default();
    let mut seen: BTreeSet<(Att, Att)> = BTreeSet::new();
    let mut end_edge = |o: &mut StructureOverlay, u: Att, v: Att| {
        if seen.insert((u.min(v), u.max(v))) {
            if let (Some(p), Some(q)) = (pos(u), pos(v)) {
                o.end_edges.push([p, q]);
            }
        }
    };
    for tri in &kss.tris {
        match tri.c.iter().position(|c| c.is_omega()) {
            Some(w) => {
                o.infinite_triangles += 1;
                // (x, y, ω) counter-clockwise: ω lies left of x → y
                let (x, y) = (tri.c[(w + 1) % 3], tri.c[(w + 2) % 3]);
                end_edge(&mut o, x, y);
                if let (Some(p), Some(q)) = (pos(x), pos(y)) {
                    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                    let len = dx.hypot(dy);
                    if len > 0.0 && len.is_finite() {
                        let n = [-dy / len, dx / len];
                        o.omega_rays.push((p, n));
                        o.omega_rays.push((q, n));
                    }
                }
            }
            None => {
                let [a, b, c] = tri.c;
                if let (Some(p), Some(q), Some(r)) = (pos(a), pos(b), pos(c)) {
                    o.triangles.push([p, q, r]);
                }
                end_edge(&mut o, a, b);
                end_edge(&mut o, b, c);
                end_edge(&mut o, c, a);
            }
        }
    }
    for ki in 0..kss.corrs.len() {
        let k = CorrId(ki as u32);
        let c = &kss.corrs[ki];
        let omega = c.b == Obj::Omega;
        let mut view = CorridorOverlay {
            omega,
            faces: Vec::new(),
        };
        if !omega {
            view.faces = kss
                .corridor_faces(world, k)
                .into_iter()
                .filter(|f| f.len() >= 3)
                .map(|f| f.into_iter().filter_map(pos).collect())
                .collect();
            if let Some((i, j)) = c.mid {
                let (a_s, _, _, b_t) = kss.ends(k);
                let (alpha, beta) = (step_cw(world, a_s, i), step_cw(world, b_t, j));
                if let (Some(p), Some(q)) = (pos(alpha), pos(beta)) {
                    o.middle_bridges.push([p, q] as Segment);
                }
            }
        }
        o.corridors.push(view);
    }
    if highlight > 0 {
        let mut next: Vec<(Time, &super::certs::Cert)> = kinetic.scheduled(world).collect();
        next.sort_by(|x, y| x.0.cmp(&y.0).then_with(|| x.1.p.cmp(&y.1.p)));
        for (t, c) in next.into_iter().take(highlight) {
            let [Some(p), Some(q), Some(r)] = c.p.map(pos) else {
                continue;
            };
            o.certificates.push(CertificateOverlay {
                points: [p, q, r],
                kind: kind_name(c.kind),
                time: t.to_f64(),
            });
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use crate::gen::{gas, generate_small, Family, GasParams};
    use crate::render::Snapshot;
    use crate::runner::{structure_snapshot_at, RunOptions};

    /// The view's counts and the SVG's elements agree with the structure's
    /// invariants: `2k − 2` partition triangles, `3k − 3` corridors, at most
    /// two faces per corridor split by a middle bridge.
    fn check(snap: &Snapshot, time: f64, highlight: usize) {
        let o = snap.structure.as_ref().expect("a structure");
        assert!(o.note.is_none(), "{:?}", o.note);
        let k = snap.polygons.len();
        assert!(k >= 2, "{k}");
        assert_eq!(o.triangle_count(), 2 * k - 2);
        assert_eq!(o.corridors.len(), 3 * k - 3);
        assert!(o.infinite_triangles >= 2);
        let finite_faces: usize = o
            .corridors
            .iter()
            .filter(|c| !c.omega)
            .map(|c| c.faces.len())
            .sum();
        assert_eq!(o.face_count(), finite_faces);
        assert!(o.corridors.iter().all(|c| c.faces.len() <= 2));
        assert!(o
            .corridors
            .iter()
            .filter(|c| c.omega)
            .all(|c| c.faces.is_empty()));
        assert_eq!(
            o.middle_bridges.len(),
            o.corridors.iter().filter(|c| c.faces.len() == 2).count()
        );
        assert_eq!(o.omega_rays.len(), 2 * o.infinite_triangles);
        assert!(o.certificates.len() <= highlight);
        assert!(o.certificates.windows(2).all(|w| w[0].time <= w[1].time));
        assert!(o.certificates.iter().all(|c| c.time >= time));

        let text = crate::render::svg(snap, &crate::render::RenderOptions::default());
        assert_eq!(text.matches("<g id=\"structure\">").count(), 1);
        assert_eq!(
            text.matches("class=\"partition-triangle\"").count(),
            o.triangles.len()
        );
        assert_eq!(
            text.matches("class=\"corridor-face\"").count(),
            o.face_count()
        );
        assert_eq!(
            text.matches("class=\"middle-bridge\"").count(),
            o.middle_bridges.len()
        );
        assert_eq!(
            text.matches("class=\"certificate\"").count(),
            o.certificates.len()
        );
        assert_eq!(text.matches("<g").count(), text.matches("</g>").count());
        assert!(!text.contains("NaN"));
    }

    #[test]
    fn view_of_a_small_gas_scene_counts_right() {
        let scenario = generate_small(Family::Gas, 3);
        let time = scenario.until / 3.0;
        let snap = structure_snapshot_at(&scenario, &RunOptions::default(), time, 5).unwrap();
        check(&snap, time, 5);
    }

    #[test]
    fn view_of_a_larger_gas_scene_counts_right() {
        let scenario = gas(&GasParams {
            k: 12,
            seed: 3,
            ..Default::default()
        });
        for (time, highlight) in [(0.0, 5), (1.25, 3), (2.0, 0)] {
            let snap =
                structure_snapshot_at(&scenario, &RunOptions::default(), time, highlight).unwrap();
            check(&snap, time, highlight);
            let o = snap.structure.as_ref().unwrap();
            assert!(o.triangles.len() >= 10 && !o.middle_bridges.is_empty());
            assert_eq!(o.certificates.len(), highlight);
        }
    }
}
