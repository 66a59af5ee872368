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
        let s = self.sign_at(t);
        if s != Sign::Zero {
            return s;
        }
        let d = self.derivative();
        let s1 = d.sign_at(t);
        if s1 != Sign::Zero {
            return s1;
        }
        Sign::of(&self.c[2])
    }

    /// The sign on an open interval just before `t`.
    pub fn sign_before(&self, t: &Time) -> Sign {
        let s = self.sign_at(t);
        if s != Sign::Zero {
            return s;
        }
        let d = self.derivative();
        let s1 = d.sign_at(t);
        if s1 != Sign::Zero {
            return s1.neg();
        }
        Sign::of(&self.c[2])
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
        // The sign just after each root follows from the root structure, so
        // no evaluation at a root (where the filter can never decide) is
        // needed, and only the one root where the sign can turn non-positive
        // is constructed.
        let root = match self.degree() {
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
        };
        root.filter(|r| r > t)
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
    fn from_rationals_scales_positively() {
        let half = Rational::from_f64(0.5).unwrap();
        let third = Rational::new(Int::from(-1), Int::from(3));
        let q = Poly::from_rationals(&half, &third, &Rational::zero());
        assert_eq!(q.coeff(0), &Int::from(3));
        assert_eq!(q.coeff(1), &Int::from(-2));
        assert_eq!(q.roots(), vec![t(1.5)]);
    }
}
