//! Polynomials in time of degree at most two with integer coefficients:
//! the certificate functions of kss.
//!
//! A certificate holds while its function is positive. Under piecewise-linear
//! translation the orientation of three moving points is such a polynomial
//! (degree <= 1 when two of the points belong to one body). Coefficients are
//! integers: callers scale rational coefficients by a positive factor, which
//! changes neither the signs nor the roots.

use super::{count_exact, count_filtered, lcm, Int, Interval, Rational, Sign, Time};

/// `c0 + c1·t + c2·t²` with integer coefficients.
#[derive(Clone, Debug)]
pub struct Poly {
    c: [Int; 3],
    iv: [Interval; 3],
}

impl Poly {
    /// `c0 + c1·t + c2·t²`.
    pub fn new(c0: Int, c1: Int, c2: Int) -> Poly {
        let big = [&c0, &c1, &c2].iter().any(|c| c.unsigned_bits() > 1000);
        let iv = if big {
            [Interval::ENTIRE; 3]
        } else {
            [
                Interval::of_int(&c0),
                Interval::of_int(&c1),
                Interval::of_int(&c2),
            ]
        };
        Poly {
            c: [c0, c1, c2],
            iv,
        }
    }

    /// The polynomial with these rational coefficients, scaled by a positive
    /// factor so that they become integers (same signs, same roots).
    pub fn from_rationals(c0: &Rational, c1: &Rational, c2: &Rational) -> Poly {
        let l = lcm(&lcm(c0.denom(), c1.denom()), c2.denom());
        let s = |c: &Rational| c.numer() * (&l / c.denom());
        Poly::new(s(c0), s(c1), s(c2))
    }

    /// Coefficient of `t^i` (`i <= 2`).
    pub fn coeff(&self, i: usize) -> &Int {
        &self.c[i]
    }

    /// The degree, or `None` for the zero polynomial.
    pub fn degree(&self) -> Option<usize> {
        (0..3).rev().find(|&i| !self.c[i].is_zero())
    }

    /// Whether the polynomial is identically zero.
    pub fn is_zero(&self) -> bool {
        self.degree().is_none()
    }

    /// The derivative.
    pub fn derivative(&self) -> Poly {
        Poly::new(self.c[1].clone(), Int::from(2) * &self.c[2], Int::ZERO)
    }

    /// `-self`.
    #[allow(clippy::should_implement_trait)]
    pub fn neg(&self) -> Poly {
        Poly::new(-self.c[0].clone(), -self.c[1].clone(), -self.c[2].clone())
    }

    /// An enclosure of the values on the interval `t`.
    pub fn eval_interval(&self, t: Interval) -> Interval {
        // Horner: c0 + t(c1 + t c2)
        self.iv[0] + t * (self.iv[1] + t * self.iv[2])
    }

    /// The exact value at a rational time.
    pub fn eval_rational(&self, t: &Rational) -> Rational {
        let p = t.numer();
        let q = t.denom();
        let num = &self.c[0] * q * q + &self.c[1] * p * q + &self.c[2] * p * p;
        Rational::new(num, q * q)
    }

    /// The exact sign at time `t` (filtered).
    pub fn sign_at(&self, t: &Time) -> Sign {
        if let Some(s) = self.eval_interval(t.interval()).sign() {
            count_filtered();
            return s;
        }
        count_exact();
        self.exact_sign_at(t)
    }

    fn exact_sign_at(&self, t: &Time) -> Sign {
        if let Some(r) = t.as_rational() {
            let p = r.numer();
            let q = r.denom();
            let v = &self.c[0] * q * q + &self.c[1] * p * q + &self.c[2] * p * p;
            return Sign::of(&v);
        }
        let x = t.as_root().expect("time is rational or a root");
        // a·P(x) = α + β x with α = a c0 − c2 c, β = a c1 − c2 b (a > 0), and
        // 2a(α + βx) = (2aα − bβ) ± β√d.
        let alpha = &x.a * &self.c[0] - &self.c[2] * &x.c;
        let beta = &x.a * &self.c[1] - &self.c[2] * &x.b;
        let a = Int::from(2) * &x.a * &alpha - &x.b * &beta;
        let b = if x.plus { beta } else { -beta };
        super::sign_a_plus_b_sqrt(&a, &b, &x.d)
    }

    /// The sign on an open interval just after `t`: the sign at `t` if it is
    /// not zero, else that of the first non-vanishing derivative.
    /// [`Sign::Zero`] only for the zero polynomial.
    pub fn sign_after(&self, t: &Time) -> Sign {
        self.signs_around(t)[1]
    }

    /// The sign on an open interval just before `t`.
    pub fn sign_before(&self, t: &Time) -> Sign {
        self.signs_around(t)[0]
    }

    /// [`Poly::sign_before`] and [`Poly::sign_after`] of `t`, from one
    /// evaluation at `t` (and of the derivative where that is zero).
    pub fn signs_around(&self, t: &Time) -> [Sign; 2] {
        let [before, _, after] = self.signs_at_and_around(t);
        [before, after]
    }

    /// The signs just before `t`, at `t` and just after `t`
    /// ([`Poly::sign_before`], [`Poly::sign_at`], [`Poly::sign_after`]),
    /// from one evaluation at `t` (and of the derivative where that is
    /// zero).
    pub fn signs_at_and_around(&self, t: &Time) -> [Sign; 3] {
        let s = self.sign_at(t);
        if s != Sign::Zero {
            return [s, s, s];
        }
        let s1 = self.derivative().sign_at(t);
        if s1 != Sign::Zero {
            return [s1.neg(), Sign::Zero, s1];
        }
        let s2 = Sign::of(&self.c[2]);
        [s2, Sign::Zero, s2]
    }

    /// The distinct real roots, in increasing order (none for the zero
    /// polynomial or a non-zero constant).
    pub fn roots(&self) -> Vec<Time> {
        match self.degree() {
            None | Some(0) => Vec::new(),
            Some(1) => vec![Time::from_rational(Rational::new(
                -self.c[0].clone(),
                self.c[1].clone(),
            ))],
            Some(_) => {
                let (c, b, a) = (&self.c[0], &self.c[1], &self.c[2]);
                let d = b * b - Int::from(4) * a * c;
                if d < Int::ZERO {
                    Vec::new()
                } else if d.is_zero() {
                    vec![Time::from_rational(Rational::new(
                        -b.clone(),
                        Int::from(2) * a,
                    ))]
                } else {
                    vec![
                        Time::quadratic_root(a, b, c, false),
                        Time::quadratic_root(a, b, c, true),
                    ]
                }
            }
        }
    }

    /// The first root strictly after `t`, if any.
    pub fn first_root_after(&self, t: &Time) -> Option<Time> {
        self.roots().into_iter().find(|r| r > t)
    }

    /// The first time strictly after `t` at which the function stops being
    /// positive on a neighbourhood to the right: the first root after `t` at
    /// which the sign just after is not positive. Roots where the function
    /// only touches zero (even multiplicity) and stays positive are skipped;
    /// use [`Poly::first_root_after`] to see those too.
    pub fn first_failure_after(&self, t: &Time) -> Option<Time> {
        self.failure_root().filter(|r| r > t)
    }

    /// [`Poly::first_failure_after`] for a function known to be positive
    /// just after `t`; the root is deferred ([`Time::deferred`]) where the
    /// filter can place it after `t`.
    pub fn failure_after_positive(self, t: &Time) -> Option<Time> {
        match filtered_root(self.iv, t.interval()) {
            Filtered::Never => None,
            Filtered::At(iv) => Some(Time::deferred(iv, FailureRoot(self))),
            Filtered::Unsure => self.first_failure_after(t),
        }
    }

    /// The one root at which the function can turn from positive to not
    /// positive (whether before or after any given time): the root of a
    /// decreasing linear function, the double root of a quadratic that opens
    /// downwards, the smaller root of one that opens upwards, the larger of
    /// one that opens downwards. `None` if there is no such root.
    pub fn failure_root(&self) -> Option<Time> {
        // The sign just after each root follows from the root structure, so
        // no evaluation at a root (where the filter can never decide) is
        // needed, and only the one root where the sign can turn non-positive
        // is constructed.
        match self.degree() {
            None | Some(0) => None,
            // a linear function fails at its root only if it decreases
            Some(1) => (Sign::of(&self.c[1]) == Sign::Negative)
                .then(|| Time::from_rational(Rational::new(-self.c[0].clone(), self.c[1].clone()))),
            Some(_) => {
                let (c, b, a) = (&self.c[0], &self.c[1], &self.c[2]);
                let d = b * b - Int::from(4) * a * c;
                let opens_up = Sign::of(a) == Sign::Positive;
                if d < Int::ZERO {
                    None
                } else if d.is_zero() {
                    // a double root: positive just after it iff a > 0
                    (!opens_up)
                        .then(|| Time::from_rational(Rational::new(-b.clone(), Int::from(2) * a)))
                } else {
                    // two simple roots: the function turns negative after the
                    // smaller one when a > 0, after the larger one when a < 0
                    Some(Time::quadratic_root(a, b, c, !opens_up))
                }
            }
        }
    }
}

/// What the f64 filter can tell about when a certificate fails, from
/// enclosures of its function's coefficients (see [`filtered_failure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filtered {
    /// Positive just after `now` and never failing later.
    Never,
    /// Positive just after `now`; fails at [`Poly::failure_root`] of the
    /// exact function, which lies in this interval, strictly after `now`.
    At(Interval),
    /// The filter cannot tell; ask the exact function.
    Unsure,
}

/// The f64 filter of [`Poly::sign_after`] and [`Poly::first_failure_after`]
/// together: `c` encloses the coefficients `c0, c1, c2` of a positive
/// multiple of a certificate function (an enclosure that is exactly `[0, 0]`
/// says the coefficient is exactly zero), and `now` encloses the current
/// time. Decides only what the enclosures prove; everything else is
/// [`Filtered::Unsure`].
pub fn filtered_failure(c: [Interval; 3], now: Interval) -> Filtered {
    let [c0, c1, c2] = c;
    // positive at (every point of the enclosure of) now, hence just after
    let at_now = c0 + now * (c1 + now * c2);
    if at_now.sign() != Some(Sign::Positive) {
        return Filtered::Unsure;
    }
    filtered_root(c, now)
}

/// [`filtered_failure`] for a function already known to be positive just
/// after `now`: only where its failure root lies.
pub fn filtered_root(c: [Interval; 3], now: Interval) -> Filtered {
    let [c0, c1, c2] = c;
    if !now.is_finite() {
        return Filtered::Unsure;
    }
    // a root's enclosure is worth keeping only when it is tight; a wide one
    // would only make comparisons fall back to the exact path. (The
    // enclosures of the certificates' coefficients are some 1e-13 wide,
    // relatively, and a root's some 1e-12 to 1e-11: distinct event times
    // are much further apart than that.)
    let tight =
        |r: Interval| r.is_finite() && r.width() <= (r.lo.abs().max(r.hi.abs()) * 1e-9).max(1e-300);
    let after = |r: Interval| {
        if r.lo > now.hi && tight(r) {
            Filtered::At(r)
        } else {
            Filtered::Unsure
        }
    };
    if c2.is_zero() {
        if c1.is_zero() || c1.lo > 0.0 {
            return Filtered::Never;
        }
        if c1.hi < 0.0 {
            // positive at now and decreasing: the root is after now
            return after(-c0 / c1);
        }
        return Filtered::Unsure;
    }
    if c2.sign().is_none() {
        return Filtered::Unsure;
    }
    let d = c1.square() - Interval::point(4.0) * c0 * c2;
    if d.hi < 0.0 {
        return Filtered::Never;
    }
    if d.sign() != Some(Sign::Positive) {
        return Filtered::Unsure;
    }
    // the failure root is (−c1 − √d)/2c2 whatever the sign of c2 (the
    // smaller root when c2 > 0, the larger when c2 < 0); computed without
    // cancellation
    let s = d.sqrt();
    let two = Interval::point(2.0);
    let r = if c1.lo < 0.0 && c1.hi <= 0.0 {
        (two * c0) / (s - c1)
    } else {
        -(c1 + s) / (two * c2)
    };
    if r.hi < now.lo {
        // the function is positive at now, after the root where it turns
        // negative: it never fails after now (a > 0: now is past both
        // roots), or the enclosures contradict each other (a < 0)
        return if c2.lo > 0.0 {
            Filtered::Never
        } else {
            Filtered::Unsure
        };
    }
    after(r)
}

/// The deferred [`Poly::failure_root`] of a polynomial.
struct FailureRoot(Poly);

impl super::ExactTime for FailureRoot {
    fn exact(&self) -> Time {
        self.0
            .failure_root()
            .expect("the filter proved that the function fails")
    }

    /// The root of an integer polynomial of degree one is rational.
    fn known_rational(&self) -> bool {
        self.0.degree() == Some(1)
    }
}

impl PartialEq for Poly {
    fn eq(&self, other: &Self) -> bool {
        self.c == other.c
    }
}

impl Eq for Poly {}

trait UnsignedBits {
    fn unsigned_bits(&self) -> usize;
}

impl UnsignedBits for Int {
    fn unsigned_bits(&self) -> usize {
        use dashu_base::BitTest;
        self.bit_len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(c0: i64, c1: i64, c2: i64) -> Poly {
        Poly::new(Int::from(c0), Int::from(c1), Int::from(c2))
    }

    fn t(x: f64) -> Time {
        Time::from_f64(x).unwrap()
    }

    #[test]
    fn signs_and_roots() {
        let q = p(-2, 0, 1); // t² − 2
        let r = q.roots();
        assert_eq!(r.len(), 2);
        assert_eq!(q.sign_at(&r[1]), Sign::Zero);
        assert_eq!(q.sign_after(&r[1]), Sign::Positive);
        assert_eq!(q.sign_before(&r[1]), Sign::Negative);
        assert_eq!(q.sign_at(&t(1.5)), Sign::Positive);
        assert_eq!(q.first_root_after(&t(0.0)), Some(r[1].clone()));
        // (t − 1)²: double root, touches zero
        let d = p(1, -2, 1);
        assert_eq!(d.roots(), vec![t(1.0)]);
        assert_eq!(d.sign_after(&t(1.0)), Sign::Positive);
        assert_eq!(d.first_failure_after(&t(0.0)), None);
        assert_eq!(d.first_root_after(&t(0.0)), Some(t(1.0)));
        // 3 − t fails at 3
        let l = p(3, -1, 0);
        assert_eq!(l.first_failure_after(&t(0.0)), Some(t(3.0)));
        assert_eq!(l.first_failure_after(&t(3.0)), None);
        // sign of another polynomial at an irrational root
        let other = p(0, 1, 0); // t
        assert_eq!(other.sign_at(&r[0]), Sign::Negative);
        let same = p(-4, 0, 2); // 2t² − 4 vanishes at ±√2
        assert_eq!(same.sign_at(&r[0]), Sign::Zero);
    }

    #[test]
    fn signs_around_are_the_signs_just_before_at_and_just_after() {
        // roots simple and double, rational and irrational, a constant,
        // the zero polynomial; instants at, between and beside the roots
        // (every other root at least 0.08 away from each instant: the signs
        // 2^-20 before and after it are the signs just beside it)
        let polys = [
            p(-2, 0, 1),
            p(1, -2, 1),
            p(3, -1, 0),
            p(0, 1, 0),
            p(0, 0, -1),
            p(5, 0, 0),
            p(0, 0, 0),
            p(-4, 0, 2),
        ];
        let mut instants: Vec<Time> = [-1.0, 0.0, 0.5, 1.0, 1.5, 3.0].into_iter().map(t).collect();
        instants.extend(p(-2, 0, 1).roots());
        let d = 2f64.powi(-20);
        for q in &polys {
            for at in &instants {
                let x = at.to_f64();
                let beside = [t(x - d), t(x + d)].map(|b| q.sign_at(&b));
                assert_eq!(q.signs_around(at), beside, "{q:?} at {at:?}");
                assert_eq!(
                    q.signs_at_and_around(at),
                    [beside[0], q.sign_at(at), beside[1]],
                    "{q:?} at {at:?}"
                );
                assert_eq!(
                    [q.sign_before(at), q.sign_after(at)],
                    beside,
                    "{q:?} at {at:?}"
                );
            }
        }
    }

    #[test]
    fn from_rationals_scales_positively() {
        let half = Rational::from_f64(0.5).unwrap();
        let third = Rational::new(Int::from(-1), Int::from(3));
        let q = Poly::from_rationals(&half, &third, &Rational::zero());
        assert_eq!(q.coeff(0), &Int::from(3));
        assert_eq!(q.coeff(1), &Int::from(-2));
        assert_eq!(q.roots(), vec![t(1.5)]);
    }

    /// The filter's answers, checked against the exact path on every
    /// polynomial with small coefficients (scaled up so that they are not
    /// all exactly representable) and a range of current times.
    #[test]
    fn filtered_failure_agrees_with_the_exact_answer() {
        let nows = [t(-2.0), t(0.0), t(0.5), t(1.0), t(3.0)];
        let mut deferred = 0;
        for c0 in -4i64..=4 {
            for c1 in -4i64..=4 {
                for c2 in -3i64..=3 {
                    for scale in [1i64, 3, (1 << 40) + 1] {
                        let q = p(c0 * scale, c1 * scale, c2 * scale);
                        for now in &nows {
                            let exact_positive = q.sign_after(now) == Sign::Positive;
                            let exact = q.first_failure_after(now);
                            match filtered_failure(q.iv, now.interval()) {
                                Filtered::Never => {
                                    assert!(exact_positive && exact.is_none(), "{q:?} at {now:?}")
                                }
                                Filtered::At(iv) => {
                                    assert!(exact_positive, "{q:?} at {now:?}");
                                    let r = exact.clone().expect("a failure");
                                    assert!(
                                        r.interval().overlaps(&iv) && iv.lo > now.interval().hi
                                    );
                                    deferred += 1;
                                }
                                Filtered::Unsure => {}
                            }
                            if exact_positive {
                                // the deferred root, once computed, is the exact one
                                let d = q.clone().failure_after_positive(now);
                                assert_eq!(d, exact, "{q:?} at {now:?}");
                            }
                        }
                    }
                }
            }
        }
        assert!(deferred > 1000, "the filter deferred only {deferred} roots");
    }

    /// [`filtered_root`] for functions known (exactly) to be positive just
    /// after `now`, most of them zero at `now` (the certificates whose sign
    /// just after an event comes from the memo of exact turns), against
    /// the exact path; including enclosures that are not points (the
    /// coefficients perturbed by a few ulps, as the points' f64 views are).
    #[test]
    fn filtered_root_of_a_function_positive_just_after_now_agrees() {
        let mut placed = 0;
        for r0 in -3i64..=3 {
            for r1 in -3i64..=3 {
                for a in [-2i64, -1, 1, 2] {
                    for scale in [1i64, (1 << 40) + 1] {
                        // a (t − r0)(t − r1): zero at now = r0
                        let q = p(a * r0 * r1 * scale, -a * (r0 + r1) * scale, a * scale);
                        let now = t(r0 as f64);
                        if q.sign_after(&now) != Sign::Positive {
                            continue;
                        }
                        let exact = q.first_failure_after(&now);
                        let widen = |x: Interval| Interval {
                            lo: x.lo - x.lo.abs() * 4.0 * f64::EPSILON,
                            hi: x.hi + x.hi.abs() * 4.0 * f64::EPSILON,
                        };
                        for iv in [q.iv, q.iv.map(widen)] {
                            match filtered_root(iv, now.interval()) {
                                Filtered::Never => assert!(exact.is_none(), "{q:?} at {now:?}"),
                                Filtered::At(r) => {
                                    let e = exact.clone().expect("a failure");
                                    assert!(e.interval().overlaps(&r) && r.lo > now.interval().hi);
                                    placed += 1;
                                }
                                Filtered::Unsure => {}
                            }
                        }
                    }
                }
            }
        }
        assert!(placed > 50, "the filter placed only {placed} roots");
    }

    #[test]
    fn deferred_times_order_hash_and_compute_once() {
        use std::collections::hash_map::DefaultHasher;
        use std::hash::{Hash, Hasher};
        let q = p(-2, 0, 1); // t² − 2 fails (turns negative) at −√2
        let q = q.neg(); // 2 − t² fails at +√2
        let d = q.clone().failure_after_positive(&t(0.0)).expect("fails");
        assert!(d.is_pending());
        let exact = q.first_failure_after(&t(0.0)).expect("fails");
        // filtered comparisons leave it pending
        assert!(d < t(1.5) && d > t(1.4));
        assert!(d.is_pending());
        // an exact comparison computes it
        assert_eq!(d, exact);
        assert!(!d.is_pending());
        let h = |x: &Time| {
            let mut s = DefaultHasher::new();
            x.hash(&mut s);
            s.finish()
        };
        assert_eq!(h(&d), h(&exact));
        assert_eq!(d.as_rational(), None);
        assert_eq!(format!("{d:?}"), format!("{exact:?}"));
    }
}
