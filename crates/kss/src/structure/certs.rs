//! The certificate set: what proves, between events, that the structure is
//! still valid (and therefore that no two polygons touch).
//!
//! * a finite partition triangle `(x, y, z)` stays positively oriented;
//! * in every corridor face between two bodies, every vertex next to a bridge
//!   (a *junction*) keeps its turn: convex corners stay convex, reflex
//!   junctions stay reflex (the paper certifies corners only; without the
//!   reflex ones a face can gain an unwatched fourth corner);
//! * at the finite end of every hull bridge the convex hull of everything
//!   stays locally convex (this replaces every test involving `ω`).
//!
//! Identical triples (a triangular face's three junctions) are one
//! certificate. Turns that are identically zero (three points that stay on a
//! line) never change and are not certificates.

use std::collections::BTreeMap;

use super::faces::turn_after;
use super::geo::Geo;
use super::{Att, CorrId, Kss, Obj};
use crate::num::{Sign, Time};
use crate::structure::StructureError;

/// Why a certificate exists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CertKind {
    /// A finite partition triangle's orientation.
    Triangle,
    /// A junction of a corridor face.
    Junction,
    /// Convexity of the hull at a hull-bridge end.
    HullTurn,
    /// Three points that stay on one line (a junction or hull turn that is
    /// identically straight, as when a polygon slides along another's edge):
    /// `p[1]` stays strictly between `p[0]` and `p[2]`. It fails only when
    /// two of them meet.
    Order,
}

/// A certificate: the turn `orient(p[0], p[1], p[2])` keeps the sign `sign`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cert {
    /// The three points (all finite).
    pub p: [Att; 3],
    /// The sign it must keep (never zero).
    pub sign: Sign,
    /// Why it exists.
    pub kind: CertKind,
}

/// `p` rotated so that its smallest point comes first (a rotation keeps the
/// orientation): the key under which a turn is stored.
#[inline]
pub fn rotate_to_min(p: [Att; 3]) -> [Att; 3] {
    // (the first smallest where points repeat; compared by their words,
    // which order points as `Att`'s `Ord` does)
    let [a, b, c] = p.map(Att::word);
    if a <= b && a <= c {
        p
    } else if b <= c {
        [p[1], p[2], p[0]]
    } else {
        [p[2], p[0], p[1]]
    }
}

impl Cert {
    /// The same certificate with its triple rotated so that the smallest
    /// point comes first (rotation keeps the orientation).
    pub fn canonical(self) -> Cert {
        if self.kind == CertKind::Order {
            let [a, m, b] = self.p;
            return Cert {
                p: [a.min(b), m, a.max(b)],
                ..self
            };
        }
        Cert {
            p: rotate_to_min(self.p),
            ..self
        }
    }
}

/// The order certificate of three points that stay on one line (their turn
/// is identically zero): whichever is strictly between the other two just
/// after `t` stays so. `None` if two of them coincide.
pub fn order_cert(world: &Geo, p: [Att; 3], t: &Time) -> Option<Cert> {
    let lp = |a: Att| match a.obj {
        Obj::Body(_) => world.point(a),
        Obj::Omega => unreachable!("finite points"),
    };
    let pts = p.map(lp);
    (0..3).find_map(|m| {
        let (a, b) = ((m + 1) % 3, (m + 2) % 3);
        (crate::motion::dot_poly(&pts[m], &pts[a], &pts[b]).sign_after(t) == Sign::Negative).then(
            || {
                Cert {
                    p: [p[a], p[m], p[b]],
                    sign: Sign::Positive,
                    kind: CertKind::Order,
                }
                .canonical()
            },
        )
    })
}

impl Kss {
    /// Every certificate of the structure, with the sign it must keep: positive
    /// for partition triangles and hull turns, and for junctions the class
    /// (convex or reflex) they have just after time `t`. A certificate that
    /// is already wrong just after `t` (a degenerate start: three points
    /// collinear at `t`) is included with its required sign; the simulation
    /// processes it at once. Sorted and deduplicated.
    pub fn certificates(&self, world: &Geo, t: &Time) -> Result<Vec<Cert>, StructureError> {
        let mut out: BTreeMap<[Att; 3], Cert> = BTreeMap::new();
        let mut add = |c: Cert| -> Result<(), StructureError> {
            let c = c.canonical();
            match out.get(&c.p) {
                Some(old) if old.sign != c.sign => Err(StructureError::Invariant(format!(
                    "contradictory certificates on {:?}",
                    c.p
                ))),
                Some(_) => Ok(()),
                None => {
                    out.insert(c.p, c);
                    Ok(())
                }
            }
        };
        let classify = |p: [Att; 3]| turn_after(world, p[0], p[1], p[2], t);
        for tri in &self.tris {
            if tri.c.iter().all(|c| !c.is_omega()) {
                add(Cert {
                    p: tri.c,
                    sign: Sign::Positive,
                    kind: CertKind::Triangle,
                })?;
            }
        }
        for ki in 0..self.corrs.len() {
            let k = CorrId(ki as u32);
            let c = &self.corrs[ki];
            if c.b == Obj::Omega {
                // hull turns at the hull-bridge ends of an ω-corridor
                let turns: Vec<[Att; 3]> = self
                    .hull_turns(world, k)
                    .into_iter()
                    .map(|(p, _)| p)
                    .collect();
                for p in turns {
                    if classify(p) != Sign::Zero {
                        add(Cert {
                            p,
                            sign: Sign::Positive,
                            kind: CertKind::HullTurn,
                        })?;
                    } else if let Some(c) = order_cert(world, p, t) {
                        add(c)?; // three hull points on a line for ever
                    }
                }
                continue;
            }
            for face in self.corridor_faces(world, k) {
                if face.len() < 3 {
                    continue; // an empty corridor
                }
                // a polygon vertex between two of its own is a chain
                // interior, reflex for ever; the others are junctions,
                // their turns taken around the face's places (a bridge
                // between two vertices resting on each other has length
                // zero: its two ends are one corner)
                let places = super::faces::resting_places(world, &face);
                let (n, m) = (places.len(), face.len());
                for x in 0..n {
                    let at = places[x];
                    let v = face[at];
                    let (u0, w0) = (face[(at + m - 1) % m], face[(at + 1) % m]);
                    if u0.obj == v.obj && v.obj == w0.obj {
                        continue; // chain interior: reflex for ever
                    }
                    let (u, w) = (face[places[(x + n - 1) % n]], face[places[(x + 1) % n]]);
                    let p = [u, v, w];
                    let sign = classify(p);
                    if sign != Sign::Zero {
                        add(Cert {
                            p,
                            sign,
                            kind: CertKind::Junction,
                        })?;
                    } else if let Some(c) = order_cert(world, p, t) {
                        add(c)?;
                    }
                }
            }
        }
        Ok(out.into_values().collect())
    }

    /// The corner of triangle `t` that is neither `ω` nor `a`.
    pub fn other_finite_corner(&self, t: super::TriId, a: Att) -> Att {
        *self.tris[t.0 as usize]
            .c
            .iter()
            .find(|c| !c.is_omega() && **c != a)
            .expect("an infinite partition triangle has two finite corners")
    }
}

#[cfg(test)]
mod tests {
    use crate::gen::{gas, generate_small, Family, GasParams};
    use crate::num::{Rational, Time};
    use crate::structure::geo::Geo;
    use crate::world::World;

    #[test]
    fn certificates_are_few_and_hold() {
        let mut worst: f64 = 0.0;
        let mut failing = 0;
        for family in Family::ALL {
            for seed in 0..40 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let world = Geo::plain(&world);
                let (mut kss, _) = super::super::build::build(&world, &Rational::zero()).unwrap();
                kss.place_middle_bridges(&world, &Time::zero());
                let certs = kss
                    .certificates(&world, &Time::zero())
                    .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", family.name()));
                failing += certs
                    .iter()
                    .filter(|c| {
                        super::turn_after(&world, c.p[0], c.p[1], c.p[2], &Time::zero()) != c.sign
                    })
                    .count();
                let k = world.len().max(2) as f64;
                worst = worst.max(certs.len() as f64 / k);
            }
        }
        let s = gas(&GasParams {
            k: 300,
            min_n: 8,
            max_n: 64,
            walls: true,
            seed: 9,
            ..Default::default()
        });
        let world = World::new(&s, None).unwrap();
        let world = Geo::plain(&world);
        let (mut kss, _) = super::super::build::build(&world, &Rational::zero()).unwrap();
        kss.place_middle_bridges(&world, &Time::zero());
        let certs = kss.certificates(&world, &Time::zero()).unwrap();
        let ratio = certs.len() as f64 / world.len() as f64;
        eprintln!(
            "certificates per polygon: small scenes at most {worst:.2}, gas k=304: {ratio:.2}; \
             {failing} certificates fail at t = 0 in degenerate starts"
        );
        // 8 junctions per corridor face pair, 3k − 3 corridors, 2k − 2 triangles
        assert!(worst <= 26.0 && ratio <= 26.0);
    }

    proptest::proptest! {
        /// Points are ordered by object (bodies by index, `ω` after every
        /// body), then by vertex id: the order of their words, which
        /// `Att`'s `Ord` compares (body 3 stands for ω, body 2 for the
        /// largest index a world can have).
        #[test]
        fn points_are_ordered_by_object_then_vertex(
            a in (0u32..4, proptest::prelude::any::<u32>()),
            b in (0u32..4, proptest::prelude::any::<u32>()),
        ) {
            use crate::structure::{Att, Obj};
            use crate::world::BodyId;
            let att = |(o, v): (u32, u32)| match o {
                3 => Att::OMEGA,
                2 => Att { obj: Obj::Body(BodyId::new(u32::MAX - 1)), v },
                _ => Att { obj: Obj::Body(BodyId::new(o)), v },
            };
            let (x, y) = (att(a), att(b));
            let rank = |p: Att| match p.obj {
                Obj::Body(b) => (0u8, b.raw(), p.v),
                Obj::Omega => (1u8, 0, p.v),
            };
            proptest::prop_assert_eq!(x.cmp(&y), rank(x).cmp(&rank(y)));
            proptest::prop_assert_eq!(x.cmp(&y) == std::cmp::Ordering::Equal, x == y);
            proptest::prop_assert_eq!(x.partial_cmp(&y), Some(x.cmp(&y)));
        }

        /// `rotate_to_min` rotates its triple to the first of its smallest
        /// points by `Att`'s `Ord` (points repeat in the samples; body 3
        /// stands for ω, body 2 for the largest index a world can have).
        #[test]
        fn rotate_to_min_starts_at_the_first_smallest_point(
            p in proptest::array::uniform3((0u32..4, 0u32..3)),
        ) {
            use crate::structure::{Att, Obj};
            use crate::world::BodyId;
            let att = |(o, v): (u32, u32)| match o {
                3 => Att::OMEGA,
                2 => Att { obj: Obj::Body(BodyId::new(u32::MAX - 1)), v },
                _ => Att { obj: Obj::Body(BodyId::new(o)), v },
            };
            let p = p.map(att);
            let m = (0..3).min_by_key(|&i| p[i]).expect("three points");
            proptest::prop_assert_eq!(
                super::rotate_to_min(p),
                [p[m], p[(m + 1) % 3], p[(m + 2) % 3]]
            );
        }
    }
}
