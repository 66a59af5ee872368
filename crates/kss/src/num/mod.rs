//! Exact numbers: big integers, rationals, polynomials in time of degree at
//! most two, and the exact [`Time`] type with a filtered total order.
//!
//! Every decision in kss goes through this module. `f64` appears here only as
//! an *interval filter*: each value carries a rigorous enclosure `[lo, hi]`
//! computed with outward rounding, and a comparison or sign test whose
//! enclosure excludes the answer's ambiguity is decided from it; otherwise the
//! exact big-integer path decides. [`filter_stats`] counts how often each path
//! was taken.
//!
//! Input doubles are exact dyadic rationals ([`Rational::from_f64`] never
//! rounds). Polynomial coefficients are kept as integers: a certificate
//! function is scaled by a positive factor, which changes neither its sign
//! nor its roots, so that no rational arithmetic (and no gcd) is needed on the
//! hot path.

mod interval;
mod poly;
mod rational;
mod time;

pub use dashu_int::IBig as Int;
pub use interval::Interval;
pub use poly::{filtered_failure, filtered_root, Filtered, Poly};
pub(crate) use rational::quotient_interval;
pub use rational::{decompose_f64, split_f64, Rational};
pub use time::{ExactTime, Time};

use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};

/// The sign of an exact quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Sign {
    /// Less than zero.
    Negative,
    /// Exactly zero.
    Zero,
    /// Greater than zero.
    Positive,
}

impl Sign {
    /// The sign of an integer.
    pub fn of(x: &Int) -> Sign {
        match x.sign() {
            _ if x.is_zero() => Sign::Zero,
            dashu_int::Sign::Positive => Sign::Positive,
            dashu_int::Sign::Negative => Sign::Negative,
        }
    }

    /// The sign of a machine integer.
    pub fn of_i128(x: i128) -> Sign {
        Sign::from_ordering(x.cmp(&0))
    }

    /// The sign of `x - y` given by an ordering.
    pub fn from_ordering(o: std::cmp::Ordering) -> Sign {
        match o {
            std::cmp::Ordering::Less => Sign::Negative,
            std::cmp::Ordering::Equal => Sign::Zero,
            std::cmp::Ordering::Greater => Sign::Positive,
        }
    }

    /// The ordering of a quantity with this sign against zero.
    pub fn to_ordering(self) -> std::cmp::Ordering {
        match self {
            Sign::Negative => std::cmp::Ordering::Less,
            Sign::Zero => std::cmp::Ordering::Equal,
            Sign::Positive => std::cmp::Ordering::Greater,
        }
    }

    /// The opposite sign.
    #[allow(clippy::should_implement_trait)]
    pub fn neg(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }

    /// The sign of a product.
    #[allow(clippy::should_implement_trait)]
    pub fn mul(self, other: Sign) -> Sign {
        match (self, other) {
            (Sign::Zero, _) | (_, Sign::Zero) => Sign::Zero,
            (a, b) if a == b => Sign::Positive,
            _ => Sign::Negative,
        }
    }

    /// `+1`, `0` or `-1`.
    pub fn as_i32(self) -> i32 {
        match self {
            Sign::Negative => -1,
            Sign::Zero => 0,
            Sign::Positive => 1,
        }
    }
}

/// Sign of `a + b·√d` for integers `a`, `b` and `d >= 0`, exactly.
pub fn sign_a_plus_b_sqrt(a: &Int, b: &Int, d: &Int) -> Sign {
    let sa = Sign::of(a);
    let sb = Sign::of(b);
    if sb == Sign::Zero || d.is_zero() {
        return sa;
    }
    if sa == Sign::Zero || sa == sb {
        return sb;
    }
    // Opposite signs: compare a² with b²·d.
    let lhs = a * a;
    let rhs = b * b * d;
    sa.mul(Sign::from_ordering(lhs.cmp(&rhs)))
}

/// Sign of `a + b·√d1 + c·√d2` for integers, `d1, d2 >= 0`, exactly.
pub fn sign_a_plus_b_sqrt_plus_c_sqrt(a: &Int, b: &Int, d1: &Int, c: &Int, d2: &Int) -> Sign {
    let sx = sign_a_plus_b_sqrt(a, b, d1);
    let sy = if d2.is_zero() {
        Sign::Zero
    } else {
        Sign::of(c)
    };
    if sy == Sign::Zero {
        return sx;
    }
    if sx == Sign::Zero || sx == sy {
        return sy;
    }
    // X = a + b√d1 and Y = c√d2 have opposite signs: sign(X+Y) = sx·sign(X² − Y²),
    // with X² − Y² = (a² + b²d1 − c²d2) + 2ab·√d1.
    let p = a * a + b * b * d1 - c * c * d2;
    let q = Int::from(2) * a * b;
    sx.mul(sign_a_plus_b_sqrt(&p, &q, d1))
}

/// The least common multiple of two positive integers.
pub fn lcm(a: &Int, b: &Int) -> Int {
    use dashu_base::{BitTest, Gcd};
    if a == b {
        return a.clone();
    }
    // a power of two (the denominators of dyadic values) by shifts: the
    // lcm of `x` and `2^k` is `x·2^(k − tz(x))` if `k > tz(x)`, else `x`
    // (for positive `x`)
    let pow2 = |x: &Int, y: &Int| -> Option<Int> {
        if x.is_zero() || !rational::is_power_of_two(y) || x < &Int::ZERO {
            return None;
        }
        let k = y.bit_len() - 1;
        let tz = x.trailing_zeros().unwrap_or(0);
        Some(if k > tz {
            x.clone() << (k - tz)
        } else {
            x.clone()
        })
    };
    if let Some(l) = pow2(a, b).or_else(|| pow2(b, a)) {
        return l;
    }
    let g = Int::from(a.gcd(b));
    a / &g * b
}

static FILTER_DECIDED: AtomicU64 = AtomicU64::new(0);
static EXACT_DECIDED: AtomicU64 = AtomicU64::new(0);

/// How many filtered decisions (time comparisons and sign evaluations) the
/// f64 interval filter settled, and how many needed exact arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilterStats {
    /// Decided by the interval filter.
    pub filtered: u64,
    /// Decided by exact big-integer arithmetic.
    pub exact: u64,
}

impl FilterStats {
    /// Fraction of decisions taken by the filter (1.0 when there were none).
    pub fn filter_fraction(&self) -> f64 {
        let total = self.filtered + self.exact;
        if total == 0 {
            1.0
        } else {
            self.filtered as f64 / total as f64
        }
    }
}

/// The process-wide counters of filtered and exact decisions.
pub fn filter_stats() -> FilterStats {
    FilterStats {
        filtered: FILTER_DECIDED.load(AtomicOrdering::Relaxed),
        exact: EXACT_DECIDED.load(AtomicOrdering::Relaxed),
    }
}

/// Reset the counters of [`filter_stats`].
pub fn reset_filter_stats() {
    FILTER_DECIDED.store(0, AtomicOrdering::Relaxed);
    EXACT_DECIDED.store(0, AtomicOrdering::Relaxed);
}

pub(crate) fn count_filtered() {
    FILTER_DECIDED.fetch_add(1, AtomicOrdering::Relaxed);
}

pub(crate) fn count_exact() {
    EXACT_DECIDED.fetch_add(1, AtomicOrdering::Relaxed);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn i(x: i64) -> Int {
        Int::from(x)
    }

    /// The least common multiple, powers of two by shifts included, against
    /// `a·b / gcd(a, b)`.
    #[test]
    fn lcm_agrees_with_the_gcd_formula() {
        use dashu_base::Gcd;
        let values: Vec<Int> = [1i64, 2, 3, 4, 6, 8, 12, 96, 1 << 40, 3 << 40, 5, 7 * 1024]
            .iter()
            .map(|&x| i(x))
            .chain([
                Int::ONE << 200,
                (Int::ONE << 150) * i(3),
                (Int::ONE << 90) * i(7) + i(1),
            ])
            .collect();
        for a in &values {
            for b in &values {
                let want = a * b / Int::from(a.gcd(b));
                assert_eq!(lcm(a, b), want, "lcm({a}, {b})");
            }
        }
    }

    #[test]
    fn sqrt_signs() {
        // 3 - 2√2 > 0 (≈ 0.17)
        assert_eq!(sign_a_plus_b_sqrt(&i(3), &i(-2), &i(2)), Sign::Positive);
        // 2 - √4 = 0
        assert_eq!(sign_a_plus_b_sqrt(&i(2), &i(-1), &i(4)), Sign::Zero);
        // -3 + 2√2 < 0
        assert_eq!(sign_a_plus_b_sqrt(&i(-3), &i(2), &i(2)), Sign::Negative);
        // √2 + √3 - √10 < 0 (3.146 - 3.162)
        assert_eq!(
            sign_a_plus_b_sqrt_plus_c_sqrt(&i(0), &i(1), &i(2), &i(1), &i(3)),
            Sign::Positive
        );
        assert_eq!(
            sign_a_plus_b_sqrt_plus_c_sqrt(&i(0), &i(-1), &i(10), &i(1), &i(2)),
            Sign::Negative
        );
        // 1 + √2 - √(3+2√2)... use exact tie: √8 - 2√2 = 0
        assert_eq!(
            sign_a_plus_b_sqrt_plus_c_sqrt(&i(0), &i(1), &i(8), &i(-2), &i(2)),
            Sign::Zero
        );
    }
}
