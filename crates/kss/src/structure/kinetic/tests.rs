//! Unit tests of the kinetic layer.

use super::book::cert_enclosure;
use super::*;
use crate::gen::{generate_small, Family};
use crate::num::Sign;
use crate::structure::geo::Geo;
use crate::world::World;

#[test]
fn scheduled_certificates_audit_clean_before_the_first_event() {
    let mut audited = 0;
    for family in Family::ALL {
        for seed in 0..40 {
            let s = generate_small(family, seed);
            let world = World::new(&s, None).unwrap();
            let world = Geo::plain(&world);
            let k = Kinetic::new(&world, &Rational::zero()).unwrap();
            let now = Time::zero();
            let Some(next) = k.next_time() else {
                continue;
            };
            if next == now {
                continue; // a degenerate start: the first event is at once
            }
            let at = now.rational_between(&next);
            k.audit(&world, &now, &at)
                .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", family.name()));
            audited += 1;
        }
    }
    assert!(audited > 150, "{audited}");
}

/// The audit checks the certificates' ids, not only their records: a
/// body's set, an owner's list or the queue's payload that lost or
/// changed an id is reported, and so is a popped time kept for a
/// certificate that is queued.
#[test]
fn the_audit_reports_ids_out_of_step_with_the_records() {
    let s = generate_small(Family::ALL[0], 1);
    let world = World::new(&s, None).unwrap();
    let world = Geo::plain(&world);
    let fresh = || Kinetic::new(&world, &Rational::zero()).unwrap();
    let k = fresh();
    let now = Time::zero();
    let next = k.next_time().expect("a scheduled failure");
    assert!(next > now);
    let at = now.rational_between(&next);
    k.audit(&world, &now, &at).unwrap();
    let (id, p, owner) = k
        .certs
        .iter()
        .find(|(_, s)| s.key.is_some())
        .map(|(id, s)| (id, s.cert.p, s.owners[0]))
        .expect("a queued certificate");
    let other = k.certs.iter().map(|(id, _)| id).find(|&x| x != id).unwrap();
    // a body's set without it
    let mut k = fresh();
    let b = step::each_body(&p).next().unwrap();
    k.by_body.at(b).ids.retain(|&x| x != id);
    assert!(k.audit(&world, &now, &at).is_err());
    // ... and counted out too
    let mut k = fresh();
    let set = k.by_body.at(b);
    set.ids.retain(|&x| x != id);
    set.live -= 1;
    assert!(k.audit(&world, &now, &at).is_err());
    // its owner's list without it
    let mut k = fresh();
    match owner {
        Owner::Tri(t) => {
            k.owned_tri[t.0 as usize].take_if(|x| *x == id);
        }
        Owner::Corr(c) => k.owned_corr[c.0 as usize].retain(|x| *x != id),
    }
    assert!(k.audit(&world, &now, &at).is_err());
    // its queued event naming another certificate
    let mut k = fresh();
    let key = k.certs.at(id).unwrap().key.unwrap();
    match key {
        QKey::Near(key) => *k.queue.payload_mut(key).unwrap() = other,
        QKey::Far(key) => k.far.payload_mut(key).unwrap().id = other,
    }
    assert!(k.audit(&world, &now, &at).is_err());
    // a popped time for a certificate that is still queued
    let mut k = fresh();
    k.certs.set_popped(id, now.clone());
    assert!(k.audit(&world, &now, &at).is_err());
}

/// Calls `f` with a view of the scene of each family and seed below
/// `seeds`, plain and with every polygon approximated, and the vertices
/// (real or approximation) of its first `bodies` bodies.
fn each_view(seeds: u64, bodies: usize, mut f: impl FnMut(&Geo, &[Att])) {
    for family in Family::ALL {
        for seed in 0..seeds {
            let s = generate_small(family, seed);
            let world = World::new(&s, None).unwrap();
            for hierarchical in [false, true] {
                let mut shapes = crate::structure::geo::Shapes::default();
                if hierarchical {
                    shapes = crate::structure::refine::coarsest_shapes(&world, 0);
                }
                let geo = Geo {
                    world: &world,
                    shapes: &shapes,
                };
                let pts: Vec<Att> = (0..world.len().min(bodies))
                    .flat_map(|b| {
                        let b = crate::world::BodyId::new(b as u32);
                        geo.ids(b).into_iter().map(move |v| Att::vertex(b, v))
                    })
                    .collect();
                f(&geo, &pts);
            }
        }
    }
}

/// The f64 filter of the orientation and order tests never contradicts
/// the exact polynomials: on every triple of (real and approximation)
/// vertices of the degenerate families, where collinear points and
/// contacts at dyadic instants abound, at integer, dyadic and
/// non-dyadic instants.
#[test]
fn filtered_turns_agree_with_the_exact_ones() {
    let (mut decided, mut undecided) = (0u64, 0u64);
    each_view(6, 3, |geo, pts| {
        for t in ["0", "1", "2", "0.375", "1/3", "7/5"] {
            let t = match t.split_once('/') {
                Some((p, q)) => Time::from_rational(Rational::new(
                    p.parse::<i64>().unwrap().into(),
                    q.parse::<i64>().unwrap().into(),
                )),
                None => Time::from_f64(t.parse().unwrap()).unwrap(),
            };
            let lp = |a: Att| geo.point(a);
            for (i, &u) in pts.iter().enumerate() {
                for &v in &pts[i + 1..] {
                    for &w in pts.iter().step_by(3) {
                        let exact = crate::motion::orient_poly(&lp(u), &lp(v), &lp(w)).sign_at(&t);
                        match geo.orient_filtered(u, v, w, t.interval()) {
                            Some(f) => {
                                assert_eq!(f, exact, "{u:?} {v:?} {w:?} at {t}");
                                decided += 1;
                            }
                            None => undecided += 1,
                        }
                        let dot = crate::motion::dot_poly(&lp(v), &lp(u), &lp(w)).sign_at(&t);
                        if let Some(f) = geo.dot_filtered(u, v, w, t.interval()) {
                            assert_eq!(f, dot, "{u:?} {v:?} {w:?} at {t}");
                        }
                    }
                }
            }
        }
    });
    assert!(decided > 1000 && undecided > 10, "{decided} {undecided}");
}

/// The certificate filter's coefficient enclosures ([`cert_enclosure`],
/// f64 values with one bound per coefficient) hold the exact coefficients of the
/// certificate function (in real coordinates, a positive multiple of
/// [`cert_poly`]), for every kind and sign, on triples of real and
/// approximation vertices of every family, moving and fixed, and are
/// exact zeros where a coefficient is exactly zero by construction.
#[test]
fn certificate_enclosures_hold_the_exact_coefficients() {
    use crate::structure::certs::CertKind;
    let mut checked = 0u64;
    each_view(4, 4, |geo, pts| {
        // the exact linear position (x0 + x1·t, y0 + y1·t)
        let lin = |a: Att| {
            let l = geo.point(a);
            let q = |n: &crate::num::Int| Rational::new(n.clone(), l.w.clone());
            [q(&l.x0), q(&l.x1), q(&l.y0), q(&l.y1)]
        };
        for (i, &u) in pts.iter().enumerate().step_by(2) {
            for &v in pts[i + 1..].iter().step_by(2) {
                for &w in pts.iter().step_by(3) {
                    if u == w || v == w {
                        continue;
                    }
                    for (kind, sign) in [
                        (CertKind::Junction, Sign::Positive),
                        (CertKind::Triangle, Sign::Negative),
                        (CertKind::Order, Sign::Positive),
                    ] {
                        let c = Cert {
                            p: [u, v, w],
                            sign,
                            kind,
                        };
                        let Some(e) = cert_enclosure(geo, &c) else {
                            continue;
                        };
                        let order = kind == CertKind::Order;
                        let [p, q, r] = if order { [v, u, w] } else { [u, v, w] };
                        let [pp, pq, pr] = [lin(p), lin(q), lin(r)];
                        let d = |a: &[Rational; 4], b: &[Rational; 4]| {
                            [0, 1, 2, 3].map(|k| b[k].sub(&a[k]))
                        };
                        let [ux0, ux1, uy0, uy1] = d(&pp, &pq);
                        let [vx0, vx1, vy0, vy1] = d(&pp, &pr);
                        let m = |a: &Rational, b: &Rational| a.mul(b);
                        let mut exact = if order {
                            [
                                m(&ux0, &vx0).add(&m(&uy0, &vy0)),
                                m(&ux0, &vx1)
                                    .add(&m(&ux1, &vx0))
                                    .add(&m(&uy0, &vy1))
                                    .add(&m(&uy1, &vy0)),
                                m(&ux1, &vx1).add(&m(&uy1, &vy1)),
                            ]
                        } else {
                            [
                                m(&ux0, &vy0).sub(&m(&uy0, &vx0)),
                                m(&ux0, &vy1)
                                    .add(&m(&ux1, &vy0))
                                    .sub(&m(&uy0, &vx1))
                                    .sub(&m(&uy1, &vx0)),
                                m(&ux1, &vy1).sub(&m(&uy1, &vx1)),
                            ]
                        };
                        if order || sign == Sign::Negative {
                            exact = exact.map(|x| x.neg());
                        }
                        for (iv, x) in e.iter().zip(&exact) {
                            if iv.is_zero() {
                                assert!(x.is_zero(), "{c:?}: {x} is no zero");
                            }
                            let lo = Rational::from_f64(iv.lo);
                            let hi = Rational::from_f64(iv.hi);
                            assert!(
                                lo.is_none_or(|lo| lo <= *x) && hi.is_none_or(|hi| *x <= hi),
                                "{c:?}: {iv:?} misses {x}"
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
    });
    assert!(checked > 5000, "{checked}");
}

/// Pops done in place at the start, one approximation vertex after
/// another, leave a structure that passes the full audit (certificates,
/// tiling, pseudo-triangles) after every pop.
#[test]
fn pops_in_place_keep_the_structure_valid() {
    let (mut local, mut audited) = (0, 0);
    for family in [Family::Gas, Family::Flypast, Family::Far] {
        for seed in 0..12 {
            let s = generate_small(family, seed);
            let world = World::new(&s, None).unwrap();
            let mut shapes = crate::structure::refine::coarsest_shapes(&world, 0);
            crate::structure::refine::separate_all_at(&world, &mut shapes, &Rational::zero())
                .unwrap();
            let geo = Geo {
                world: &world,
                shapes: &shapes,
            };
            let mut k = Kinetic::new(&geo, &Rational::zero()).unwrap();
            let now = Time::zero();
            for round in 0..24 {
                // the `round`-th approximation vertex of all bodies
                let geo = Geo {
                    world: &world,
                    shapes: &shapes,
                };
                let verts: Vec<Att> = (0..world.len())
                    .flat_map(|b| {
                        let b = BodyId::new(b as u32);
                        geo.ids(b).into_iter().map(move |v| Att::vertex(b, v))
                    })
                    .filter(|&a| !geo.is_real(a))
                    .collect();
                if verts.is_empty() {
                    break;
                }
                let a = verts[(round * 7 + seed as usize) % verts.len()];
                let (changed, followed) = k.pop_local(&world, &mut shapes, a, &now).unwrap();
                assert!(changed, "{a:?} was not popped");
                if !followed {
                    break; // the structure would be rebuilt
                }
                local += 1;
                let geo = Geo {
                    world: &world,
                    shapes: &shapes,
                };
                let Some(next) = k.next_time() else {
                    continue;
                };
                if next == now {
                    break; // a failure at once: the engine would handle it
                }
                let at = now.rational_between(&next);
                k.audit(&geo, &now, &at).unwrap_or_else(|e| {
                    panic!("{} seed {seed} pop {round} of {a:?}: {e}", family.name())
                });
                crate::structure::refine::check_apart(&world, &shapes, &at).unwrap();
                audited += 1;
            }
        }
    }
    assert!(
        local > 100 && audited > 100,
        "{local} local pops, {audited} audited"
    );
}

#[test]
fn point_words_order_triples_as_the_points_do() {
    use crate::world::BodyId;
    let pts: Vec<Att> = [0u32, 1, 7, u32::MAX - 1]
        .into_iter()
        .flat_map(|b| [0u32, 3, u32::MAX].map(|v| Att::vertex(BodyId::new(b), v)))
        .chain([Att::OMEGA])
        .collect();
    let mut triples: Vec<[Att; 3]> = Vec::new();
    for (i, &a) in pts.iter().enumerate() {
        for &b in &pts[i..] {
            for &c in pts.iter().rev().take(5) {
                triples.push([a, b, c]);
                triples.push([c, a, b]);
            }
        }
    }
    let mut by_ord = triples.clone();
    by_ord.sort();
    let mut words: Vec<[u64; 3]> = triples.iter().map(|p| p.map(Att::word)).collect();
    words.sort_unstable();
    let by_word: Vec<[Att; 3]> = words.iter().map(|w| w.map(Att::from_word)).collect();
    assert_eq!(by_ord, by_word);
}

/// A turn certificate with two points on one body has a failure time of
/// degree at most one: `Time::known_rational` says so before the time is
/// computed, and the computed time is rational (on the plain and the
/// approximated views of the small families, with either sign).
#[test]
fn failure_times_of_two_points_on_one_body_are_known_rational() {
    use crate::structure::certs::{Cert, CertKind};
    let (mut claimed, mut deferred) = (0, 0);
    each_view(6, 3, |geo, pts| {
        let now = Time::zero();
        for w in pts.windows(2) {
            let (u, v) = (w[0], w[1]);
            if u.obj != v.obj {
                continue;
            }
            for &x in pts.iter().filter(|x| x.obj != u.obj).take(4) {
                for sign in [Sign::Positive, Sign::Negative] {
                    let c = Cert {
                        p: [u, v, x],
                        sign,
                        kind: CertKind::Junction,
                    };
                    let e = cert_enclosure(geo, &c);
                    let Some(t) =
                        super::book::failure_time(geo, &c, &now, super::book::filter_at(e, &now))
                    else {
                        continue;
                    };
                    if !t.is_pending() {
                        continue;
                    }
                    deferred += 1;
                    if t.known_rational() {
                        claimed += 1;
                        assert!(t.is_pending(), "computed to answer");
                        assert!(t.as_rational().is_some(), "{c:?}: {t:?} is not rational");
                    }
                }
            }
        }
    });
    assert!(
        claimed > 20 && claimed == deferred,
        "{claimed} of {deferred}"
    );
}

/// A collision response places its contact certificates, whose turns are
/// zero at the instant, from their derivatives under the new motions
/// (`InstantState::zero`, checked against the exact sign in debug
/// builds), not from exact polynomials: on swarms of octagons in `bounce`
/// mode, with the audit after every event, the exact failure times are a
/// small fraction of the collisions (about one per collision otherwise),
/// and the collisions are the reference's.
#[test]
fn collision_responses_place_their_contacts_without_exact_failure_times() {
    use crate::gen::{swarm, SwarmParams};
    use crate::{run, RunOptions, StructureKind};
    for seed in [1, 2] {
        let s = swarm(&SwarmParams {
            k: 24,
            n: 8,
            seed,
            ..SwarmParams::default()
        });
        let collisions = |structure, audit| {
            let mut out = Vec::new();
            let opts = RunOptions {
                structure,
                audit,
                ..Default::default()
            };
            let stats = run(&s, &opts, &mut |e| {
                out.push((e.time.clone(), e.a.clone(), e.b.clone()))
            })
            .expect("the run");
            (out, stats)
        };
        let (want, _) = collisions(StructureKind::Brute, false);
        let (got, stats) = collisions(StructureKind::Plain, true);
        assert_eq!(got, want, "seed {seed}");
        let exact = stats.work["failure_times_exact"];
        assert!(
            stats.collisions >= 100,
            "seed {seed}: {} collisions",
            stats.collisions
        );
        assert!(
            2 * exact <= stats.collisions,
            "seed {seed}: {exact} exact failure times for {} collisions",
            stats.collisions
        );
    }
}
