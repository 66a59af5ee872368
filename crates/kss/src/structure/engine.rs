//! The kinetic engine's certificate bookkeeping: every certificate of the
//! structure scheduled in the event queue at its exact failure time, updated
//! when flight plans change, and audited against a from-scratch recomputation.
//!
//! (Event processing, the operations of `ARCHITECTURE.md`, is the next step of
//! issue 3.)

use std::collections::{BTreeMap, BTreeSet};

use super::certs::Cert;
use super::{Att, Kss, Obj};
use crate::motion::orient_poly;
use crate::num::{Poly, Rational, Sign, Time};
use crate::sim::{EventKey, EventQueue};
use crate::world::{BodyId, World};

/// A certificate and where it sits in the queue.
#[derive(Clone, Debug)]
struct Scheduled {
    cert: Cert,
    /// `None` when the certificate never fails on the current motions.
    key: Option<EventKey>,
}

/// The structure with its certificates scheduled.
#[derive(Debug, Default)]
pub struct Kinetic {
    /// The combinatorial structure.
    pub kss: Kss,
    certs: BTreeMap<[Att; 3], Scheduled>,
    queue: EventQueue<Time, [Att; 3]>,
    max_active: usize,
}

/// The certificate function of `c`, oriented so that it is positive while
/// the certificate holds.
pub fn cert_poly(world: &World, c: &Cert) -> Poly {
    let lp = |a: Att| match a.obj {
        Obj::Body(b) => world.body(b).vertex(a.v as usize),
        Obj::Omega => unreachable!("certificates have finite points"),
    };
    let p = orient_poly(&lp(c.p[0]), &lp(c.p[1]), &lp(c.p[2]));
    if c.sign == Sign::Negative {
        p.neg()
    } else {
        p
    }
}

/// When certificate `c` fails, given that `now` is the current time: `now`
/// itself if it is already wrong just after `now`, else the first later root
/// where it stops being positive, if any.
pub fn failure_time(world: &World, c: &Cert, now: &Time) -> Option<Time> {
    let p = cert_poly(world, c);
    if p.sign_after(now) != Sign::Positive {
        return Some(now.clone());
    }
    p.first_failure_after(now)
}

impl Kinetic {
    /// Build the structure at time `t` and schedule its certificates.
    pub fn new(world: &World, t: &Rational) -> Result<Kinetic, String> {
        let mut kss = super::build::build(world, t).map_err(|e| e.to_string())?;
        let now = Time::from_rational(t.clone());
        kss.place_middle_bridges(world, &now);
        let mut k = Kinetic {
            kss,
            ..Default::default()
        };
        k.reschedule_all(world, &now)?;
        Ok(k)
    }

    /// Recompute the certificate set and (re)schedule whatever changed.
    pub fn reschedule_all(&mut self, world: &World, now: &Time) -> Result<(), String> {
        let fresh: BTreeMap<[Att; 3], Cert> = self
            .kss
            .certificates(world, now)?
            .into_iter()
            .map(|c| (c.p, c))
            .collect();
        let stale: Vec<[Att; 3]> = self
            .certs
            .keys()
            .filter(|p| {
                fresh
                    .get(*p)
                    .is_none_or(|c| c.sign != self.certs[*p].cert.sign)
            })
            .copied()
            .collect();
        for p in stale {
            self.drop_cert(&p);
        }
        for (p, c) in fresh {
            if !self.certs.contains_key(&p) {
                self.add_cert(world, c, now);
            }
        }
        Ok(())
    }

    fn add_cert(&mut self, world: &World, c: Cert, now: &Time) {
        let key = failure_time(world, &c, now).map(|t| self.queue.schedule(t, 0, c.p));
        self.certs.insert(c.p, Scheduled { cert: c, key });
        self.max_active = self.max_active.max(self.queue.len());
    }

    fn drop_cert(&mut self, p: &[Att; 3]) {
        if let Some(s) = self.certs.remove(p) {
            if let Some(k) = s.key {
                self.queue.cancel(k);
            }
        }
    }

    /// Bodies changed their motion at `now`: reschedule every certificate
    /// that involves one of them (flight-plan changes are local).
    pub fn motion_changed(&mut self, world: &World, now: &Time, bodies: &[BodyId]) {
        let set: BTreeSet<Obj> = bodies.iter().map(|&b| Obj::Body(b)).collect();
        let touched: Vec<[Att; 3]> = self
            .certs
            .keys()
            .filter(|p| p.iter().any(|a| set.contains(&a.obj)))
            .copied()
            .collect();
        for p in touched {
            let c = self.certs[&p].cert;
            self.drop_cert(&p);
            self.add_cert(world, c, now);
        }
    }

    /// The earliest scheduled failure, if any.
    pub fn next_time(&self) -> Option<&Time> {
        self.queue.peek().map(|(_, t, _, _)| t)
    }

    /// Certificates that can fail (scheduled) now, and at most so far.
    pub fn active(&self) -> (usize, usize) {
        (self.queue.len(), self.max_active)
    }

    /// All certificates, scheduled or not.
    pub fn certificate_count(&self) -> usize {
        self.certs.len()
    }

    /// Check every invariant at the rational instant `at`, strictly after the
    /// last event `now` and before the next one: topology, every corridor face
    /// a pseudo-triangle, every certificate holding, and the scheduled set
    /// equal to a from-scratch recomputation with the right failure times.
    pub fn audit(&self, world: &World, now: &Time, at: &Rational) -> Result<(), String> {
        let at_t = Time::from_rational(at.clone());
        self.kss.check_topology(world)?;
        self.kss.check_faces(world, &at_t)?;
        let fresh = self.kss.certificates(world, &at_t)?;
        if fresh.len() != self.certs.len() {
            return Err(format!(
                "{} certificates kept, {} expected",
                self.certs.len(),
                fresh.len()
            ));
        }
        let mut scheduled = 0;
        for c in &fresh {
            let s = self
                .certs
                .get(&c.p)
                .ok_or_else(|| format!("certificate {:?} missing", c.p))?;
            if s.cert.sign != c.sign {
                return Err(format!("certificate {:?} has the wrong sign", c.p));
            }
            let p = cert_poly(world, c);
            match p.sign_at(&at_t) {
                Sign::Positive => {}
                _ if p.sign_before(&at_t) == Sign::Positive
                    && p.sign_after(&at_t) == Sign::Positive => {}
                s => return Err(format!("certificate {:?} is {s:?} at {at}", c.p)),
            }
            let want = p.first_failure_after(now);
            let got = s
                .key
                .and_then(|k| self.queue.get(k))
                .map(|(t, _)| t.clone());
            if want != got {
                return Err(format!(
                    "certificate {:?} scheduled at {got:?}, fails at {want:?}",
                    c.p
                ));
            }
            scheduled += usize::from(got.is_some());
        }
        if scheduled != self.queue.len() {
            return Err(format!(
                "{} queued events for {scheduled} scheduled certificates",
                self.queue.len()
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate_small, Family};

    #[test]
    fn scheduled_certificates_audit_clean_before_the_first_event() {
        let mut audited = 0;
        for family in Family::ALL {
            for seed in 0..40 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let k = Kinetic::new(&world, &Rational::zero()).unwrap();
                let now = Time::zero();
                let Some(next) = k.next_time().cloned() else {
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
}
