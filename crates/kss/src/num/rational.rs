//! Exact rationals, reduced, with a positive denominator.
//!
//! Rationals appear where the inputs are combined into event times and
//! positions (collision times are rational under translation). Hot paths
//! (certificate functions) use integer-scaled polynomials instead.

use std::cmp::Ordering;
use std::fmt;

use dashu_base::{BitTest, DivRem, Gcd};

use super::{Int, Interval, Sign};

/// An exact rational `num / den` with `den > 0` and `gcd(num, den) = 1`.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Rational {
    num: Int,
    den: Int,
}

impl fmt::Debug for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{} (≈{:e})", self.num, self.den, self.to_f64())
    }
}

impl fmt::Display for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == Int::ONE {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

impl Rational {
    /// Zero.
    pub fn zero() -> Rational {
        Rational {
            num: Int::ZERO,
            den: Int::ONE,
        }
    }

    /// One.
    pub fn one() -> Rational {
        Rational {
            num: Int::ONE,
            den: Int::ONE,
        }
    }

    /// `num / den`, reduced. Panics if `den` is zero (a bug in the caller).
    pub fn new(num: Int, den: Int) -> Rational {
        assert!(!den.is_zero(), "rational with zero denominator");
        let (mut num, mut den) = if den < Int::ZERO {
            (-num, -den)
        } else {
            (num, den)
        };
        if num.is_zero() {
            return Rational::zero();
        }
        // a power-of-two denominator (dyadic values: inputs, and positions
        // at dyadic times) is reduced by shifts, without a gcd
        if is_power_of_two(&den) {
            let tz = num.trailing_zeros().unwrap_or(0);
            let dz = den.trailing_zeros().unwrap_or(0);
            let k = tz.min(dz);
            if k > 0 {
                num >>= k;
                den >>= k;
            }
            return Rational { num, den };
        }
        let g = Int::from((&num).gcd(&den));
        if g != Int::ONE {
            num /= &g;
            den /= &g;
        }
        Rational { num, den }
    }

    /// The integer `x`.
    pub fn from_int(x: Int) -> Rational {
        Rational {
            num: x,
            den: Int::ONE,
        }
    }

    /// The exact value of a finite double (a dyadic rational); `None` for NaN
    /// or infinities.
    pub fn from_f64(x: f64) -> Option<Rational> {
        let (m, e) = decompose_f64(x)?;
        Some(Rational::from_dyadic(m, e))
    }

    /// `m · 2^e`, reduced.
    pub fn from_dyadic(m: Int, e: i64) -> Rational {
        if m.is_zero() {
            return Rational::zero();
        }
        if e >= 0 {
            Rational {
                num: m << (e as usize),
                den: Int::ONE,
            }
        } else {
            let tz = m.trailing_zeros().unwrap_or(0) as i64;
            let k = tz.min(-e);
            let num = m >> (k as usize);
            let den = Int::ONE << ((-e - k) as usize);
            Rational { num, den }
        }
    }

    /// Numerator (carries the sign).
    pub fn numer(&self) -> &Int {
        &self.num
    }

    /// Denominator (positive).
    pub fn denom(&self) -> &Int {
        &self.den
    }

    /// Whether this is zero.
    pub fn is_zero(&self) -> bool {
        self.num.is_zero()
    }

    /// Whether the denominator is a power of two.
    pub fn is_dyadic(&self) -> bool {
        is_power_of_two(&self.den)
    }

    /// The sign.
    pub fn sign(&self) -> Sign {
        Sign::of(&self.num)
    }

    /// `self + other`.
    pub fn add(&self, other: &Rational) -> Rational {
        if self.den == other.den {
            return Rational::new(&self.num + &other.num, self.den.clone());
        }
        Rational::new(
            &self.num * &other.den + &other.num * &self.den,
            &self.den * &other.den,
        )
    }

    /// `self + b·c`, reduced once (not after the product and again after
    /// the sum).
    pub fn mul_add(&self, b: &Rational, c: &Rational) -> Rational {
        // (a zero product, as at time zero or for a body at rest: `self`)
        if b.num.is_zero() || c.num.is_zero() {
            return self.clone();
        }
        let (pn, pd) = (&b.num * &c.num, &b.den * &c.den);
        if self.den == pd {
            return Rational::new(&self.num + pn, pd);
        }
        Rational::new(&self.num * &pd + pn * &self.den, &self.den * pd)
    }

    /// `self - other`.
    pub fn sub(&self, other: &Rational) -> Rational {
        self.add(&other.neg())
    }

    /// `self * other`.
    pub fn mul(&self, other: &Rational) -> Rational {
        Rational::new(&self.num * &other.num, &self.den * &other.den)
    }

    /// `self / other`; panics if `other` is zero (a bug in the caller).
    pub fn div(&self, other: &Rational) -> Rational {
        assert!(!other.is_zero(), "division by zero rational");
        Rational::new(&self.num * &other.den, &self.den * &other.num)
    }

    /// `-self`.
    #[allow(clippy::should_implement_trait)]
    pub fn neg(&self) -> Rational {
        Rational {
            num: -self.num.clone(),
            den: self.den.clone(),
        }
    }

    /// The average of two rationals.
    pub fn midpoint(&self, other: &Rational) -> Rational {
        let s = self.add(other);
        Rational::new(s.num, s.den * Int::from(2))
    }

    /// A rigorous f64 enclosure.
    pub fn interval(&self) -> Interval {
        if let Some(q) = quotient_enclosure(&self.num, &self.den) {
            return q;
        }
        // Large or tiny values: scale to a 64-bit quotient.
        let x = self.to_f64_slow();
        if x.abs() < 1e-290 {
            // Tiny values: a coarse but rigorous enclosure touching zero (the
            // exact path decides signs).
            return if self.num > Int::ZERO {
                Interval {
                    lo: 0.0,
                    hi: 1e-290,
                }
            } else {
                Interval {
                    lo: -1e-290,
                    hi: 0.0,
                }
            };
        }
        Interval {
            lo: x.next_down().next_down(),
            hi: x.next_up().next_up(),
        }
    }

    /// The nearest double, within a couple of units in the last place (for
    /// display and for outputs; never for decisions).
    pub fn to_f64(&self) -> f64 {
        if self.num.is_zero() {
            return 0.0;
        }
        let (nb, db) = (self.num.bit_len(), self.den.bit_len());
        if nb <= 53 && db <= 53 {
            // both exact as doubles: one IEEE division rounds correctly
            return self.num.to_f64().value() / self.den.to_f64().value();
        }
        self.to_f64_slow()
    }

    /// `num / den` (`den` not zero) rounded as [`Rational::to_f64`]
    /// rounds it, without reducing the fraction first (the rounding reads
    /// only the value): for values that are only displayed.
    pub fn quotient_to_f64(num: Int, den: Int) -> f64 {
        assert!(!den.is_zero(), "quotient with zero denominator");
        let (num, den) = if den < Int::ZERO {
            (-num, -den)
        } else {
            (num, den)
        };
        Rational { num, den }.to_f64()
    }

    /// Correctly rounded (to nearest, ties to even) for results in the
    /// normal range: a quotient with at least 65 significant bits plus a
    /// sticky bit for the remainder, rounded once.
    fn to_f64_slow(&self) -> f64 {
        if self.num.is_zero() {
            return 0.0;
        }
        let nb = self.num.bit_len() as i64;
        let db = self.den.bit_len() as i64;
        if nb <= 127 && self.den.trailing_zeros() == Some(db as usize - 1) {
            // a dyadic value (most trajectories are): the numerator rounded
            // once (`u128 as f64` rounds correctly), then scaled by the
            // power of two exactly
            let n = i128::try_from(&self.num).expect("at most 127 bits");
            let v = scale_pow2(n.unsigned_abs() as f64, 1 - db);
            return if n < 0 { -v } else { v };
        }
        let s = 66 - (nb - db);
        let n = if self.num < Int::ZERO {
            -self.num.clone()
        } else {
            self.num.clone()
        };
        let (num, den) = if s >= 0 {
            (n << s as usize, self.den.clone())
        } else {
            (n, &self.den << (-s) as usize)
        };
        let (mut q, r) = (&num).div_rem(&den);
        if !r.is_zero() {
            q |= Int::ONE; // sticky bit, far below the rounding position
        }
        // (q has at most 68 bits: `u128 as f64` rounds it correctly, which
        // dashu-int's `to_f64` does not promise past 64 bits)
        let qf = u128::try_from(&q).expect("at most 68 bits") as f64;
        let v = scale_pow2(qf, -s);
        if self.num < Int::ZERO {
            -v
        } else {
            v
        }
    }

    /// The largest integer `<= self`.
    pub fn floor(&self) -> Int {
        let (q, r) = (&self.num / &self.den, &self.num % &self.den);
        if r < Int::ZERO {
            q - Int::ONE
        } else {
            q
        }
    }
}

/// The quotient of the enclosures of `num` and `den > 0`, where both are
/// finite and the quotient is finite and normal (or exactly zero).
fn quotient_enclosure(num: &Int, den: &Int) -> Option<Interval> {
    let n = Interval::of_int(num);
    let d = Interval::of_int(den);
    if n.is_finite() && d.is_finite() && d.lo > 0.0 {
        let q = n / d;
        if q.is_finite() && (q.lo.abs() > f64::MIN_POSITIVE || q.lo == 0.0 && q.hi == 0.0) {
            return Some(q);
        }
    }
    None
}

/// A rigorous f64 enclosure of `num / den` (`den > 0`) without reducing
/// the fraction: the quotient of the two integers' enclosures, or the
/// whole line where that is not finite and normal (a filter on it then
/// decides nothing).
pub(crate) fn quotient_interval(num: &Int, den: &Int) -> Interval {
    quotient_enclosure(num, den).unwrap_or(Interval::ENTIRE)
}

/// `x · 2^e` without intermediate overflow or underflow where avoidable.
pub(crate) fn scale_pow2(mut x: f64, mut e: i64) -> f64 {
    while e > 1000 {
        x *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= 2f64.powi(-1000);
        e += 1000;
    }
    x * 2f64.powi(e as i32)
}

/// A finite double as `m · 2^e` with an integer `m` (exact); `None` for NaN and infinities.
pub fn decompose_f64(x: f64) -> Option<(Int, i64)> {
    if !x.is_finite() {
        return None;
    }
    let (m, e) = split_f64(x);
    Some((Int::from(m), e))
}

/// Finite `x` as `(m, e)` with `x = m · 2^e` and `|m| < 2^53`: the
/// significand and exponent of its bits (`(0, 0)` for zero), as
/// [`decompose_f64`] gives them, without a big integer.
pub fn split_f64(x: f64) -> (i64, i64) {
    debug_assert!(x.is_finite(), "split_f64 of a non-finite number");
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (if bits >> 63 == 1 { -m } else { m }, e)
}

/// Whether `|x|` is a power of two (without copying `x`: the magnitude's
/// bit length and trailing zeros).
pub(crate) fn is_power_of_two(x: &Int) -> bool {
    let n = x.bit_len();
    n > 0 && x.trailing_zeros() == Some(n - 1)
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> Ordering {
        if self.den == other.den {
            return self.num.cmp(&other.num);
        }
        let sa = self.sign();
        let sb = other.sign();
        if sa != sb {
            return sa.cmp(&sb);
        }
        (&self.num * &other.den).cmp(&(&other.num * &self.den))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul_add_and_new_reduce_like_the_separate_operations() {
        let vals: Vec<Rational> = [(3, 7), (-5, 12), (1, 8), (-6, 4), (0, 5), (9, 1), (10, 16)]
            .iter()
            .map(|&(n, d)| Rational::new(Int::from(n), Int::from(d)))
            .collect();
        for a in &vals {
            for b in &vals {
                for c in &vals {
                    let fused = a.mul_add(b, c);
                    let separate = a.add(&b.mul(c));
                    // equal as reduced pairs: numerator and denominator alike
                    assert_eq!(fused.numer(), separate.numer());
                    assert_eq!(fused.denom(), separate.denom());
                    let g = Int::from(fused.numer().gcd(fused.denom()));
                    assert!(fused.is_zero() || g == Int::ONE, "{fused:?} is not reduced");
                }
            }
        }
    }

    #[test]
    fn from_f64_exact() {
        let r = Rational::from_f64(0.1).unwrap();
        assert_eq!(r.denom(), &(Int::ONE << 55));
        assert_eq!(r.to_f64(), 0.1);
        assert_eq!(
            Rational::from_f64(-3.0).unwrap(),
            Rational::from_int(Int::from(-3))
        );
        assert_eq!(Rational::from_f64(0.5).unwrap().to_string(), "1/2");
        let tiny = Rational::from_f64(f64::from_bits(1)).unwrap();
        assert_eq!(tiny.to_f64(), f64::from_bits(1));
        let huge = Rational::from_f64(f64::MAX).unwrap();
        assert_eq!(huge.to_f64(), f64::MAX);
        assert!(Rational::from_f64(f64::NAN).is_none());
    }

    #[test]
    fn arithmetic_and_order() {
        let a = Rational::new(Int::from(1), Int::from(3));
        let b = Rational::new(Int::from(-2), Int::from(-6));
        assert_eq!(a, b);
        let c = a.add(&Rational::from_f64(0.5).unwrap());
        assert_eq!(c, Rational::new(Int::from(5), Int::from(6)));
        assert!(a < c);
        assert!(a.neg() < a);
        assert_eq!(c.mul(&a).div(&a), c);
        assert_eq!(
            Rational::new(Int::from(-7), Int::from(2)).floor(),
            Int::from(-4)
        );
        let iv = a.interval();
        assert!(iv.lo < 1.0 / 3.0 + 1e-17 && iv.hi > 1.0 / 3.0 - 1e-17 && iv.lo <= iv.hi);
    }

    /// Regression (golden `head_on_decimal`): numerator and denominator
    /// above 2^53 were rounded separately before dividing (double rounding).
    #[test]
    fn to_f64_rounds_once() {
        let r = Rational::new(
            Int::from(57646075230342355u64),
            Int::from(36028797018963966u64),
        );
        assert_eq!(r.to_f64(), 1.6000000000000003);
        // a value just above a tie between two doubles must round up
        let one = Int::ONE << 60;
        let tie_plus = Rational::new((&one << 53) + (&one << 0) + Int::ONE, &one << 53);
        assert_eq!(tie_plus.to_f64(), 1.0 + f64::EPSILON);
    }

    /// A dyadic value (its denominator a power of two) rounds as the
    /// same value with a denominator that is not one.
    #[test]
    fn dyadic_values_round_as_any_other() {
        let nums = [
            Int::from(1),
            Int::from(-3),
            (Int::ONE << 60) + Int::ONE,
            -((Int::ONE << 100) + (Int::ONE << 47) + Int::ONE),
            (Int::ONE << 126) - Int::ONE,
            (Int::ONE << 120) + (Int::ONE << 67),
        ];
        for n in &nums {
            for k in [0usize, 1, 52, 64, 200, 1000] {
                let d = Int::ONE << k;
                let dyadic = Rational::new(n.clone(), d.clone());
                let other = Rational::quotient_to_f64(n * Int::from(3), d * Int::from(3));
                assert_eq!(dyadic.to_f64(), other, "{n} / 2^{k}");
            }
        }
    }

    #[test]
    fn large_values_convert() {
        let big = Rational::new(Int::ONE << 3000, (Int::ONE << 2990) * Int::from(3));
        let x = big.to_f64();
        assert!((x - 1024.0 / 3.0).abs() < 1e-12);
        let iv = big.interval();
        assert!(iv.lo <= 1024.0 / 3.0 && iv.hi >= 1024.0 / 3.0);
    }
}
