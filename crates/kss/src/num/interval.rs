//! A closed f64 interval with outward rounding: the filter of every exact
//! decision. Each operation returns an interval that contains the exact
//! result of the operation on any points of its operands.

use super::{Int, Sign};

/// A closed interval `[lo, hi]` of reals, with `lo <= hi` (both may be
/// infinite). Arithmetic rounds outward, so enclosures stay rigorous.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

/// `floor(|x| / 2^k)` for an integer `x` of `k + 64` bits: its top 64
/// bits, read from its words (no copy of `x`).
// (a word is 64 bits here, 16 or 32 on other targets: `u64::from` is a
// conversion there)
#[allow(clippy::useless_conversion)]
fn top_bits(x: &Int, k: usize) -> u64 {
    let (_, words) = x.as_sign_words();
    let wb = dashu_int::Word::BITS as usize;
    let (mut idx, shift) = (k / wb, k % wb);
    // (the words from the one holding bit `k` on, low to high, until 64
    // bits are in: at most 64 + a word's bits, within 128)
    let mut acc = u128::from(u64::from(words[idx]) >> shift);
    let mut filled = wb - shift;
    idx += 1;
    while filled < 64 && idx < words.len() {
        acc |= u128::from(u64::from(words[idx])) << filled;
        filled += wb;
        idx += 1;
    }
    acc as u64
}

#[inline(always)]
fn down(x: f64) -> f64 {
    if x.is_nan() {
        f64::NEG_INFINITY
    } else {
        x.next_down()
    }
}

#[inline(always)]
fn up(x: f64) -> f64 {
    if x.is_nan() {
        f64::INFINITY
    } else {
        x.next_up()
    }
}

impl Interval {
    /// The whole real line (decides nothing).
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The single point `x` (exact).
    pub fn point(x: f64) -> Interval {
        Interval { lo: x, hi: x }
    }

    /// An enclosure of the integer `x` (the point where `x` fits `i128` and
    /// is a double).
    ///
    /// Not through `IBig::to_f64`: dashu-int 0.6.2 tags some conversions of
    /// integers past 64 bits `Exact` that are not (a 134-bit integer whose
    /// low 60 bits are zero, for one; the test below keeps such cases).
    /// Past `i128` the enclosure comes from the top 64 bits: `|x|` lies in
    /// `[m·2^k, (m + 1)·2^k]`.
    pub fn of_int(x: &Int) -> Interval {
        if let Ok(v) = i128::try_from(x) {
            return Interval::of_i128(v);
        }
        let negative = *x < Int::ZERO;
        let bits = dashu_base::BitTest::bit_len(x);
        let magnitude = if bits > 1024 {
            // at least 2^1024, past every double
            Interval {
                lo: f64::MAX,
                hi: f64::INFINITY,
            }
        } else {
            let k = bits - 64;
            let m = top_bits(x, k);
            // (products by 2^k, k <= 960, are exact; the upper one may
            // reach infinity)
            let scale = 2f64.powi(k as i32);
            Interval {
                lo: down(m as f64) * scale,
                hi: up((u128::from(m) + 1) as f64) * scale,
            }
        };
        if negative {
            -magnitude
        } else {
            magnitude
        }
    }

    /// An enclosure of the integer `x` (the point where `x` is a double).
    pub fn of_i128(x: i128) -> Interval {
        // (below 2^53 in magnitude a double holds it: one hardware
        // conversion, not the software one of an `i128`)
        if x.unsigned_abs() < 1 << 53 {
            return Interval::point(x as i64 as f64);
        }
        // (below 2^62 the hardware conversion of an `i64` rounds to the
        // nearest double as the software one of an `i128` does, and `v`,
        // at most 2^62, converts back exactly)
        if x.unsigned_abs() < 1 << 62 {
            let (n, v) = (x as i64, x as i64 as f64);
            return if v as i64 == n {
                Interval::point(v)
            } else {
                Interval {
                    lo: down(v),
                    hi: up(v),
                }
            };
        }
        let v = x as f64;
        // (`v` is an integer in [−2^127, 2^127]; `v as i128` is exact below
        // 2^127 and saturates at it, so that value is left out)
        if v < 2f64.powi(127) && v as i128 == x {
            Interval::point(v)
        } else {
            Interval {
                lo: down(v),
                hi: up(v),
            }
        }
    }

    /// Whether this is the point `[0, 0]` (an exact zero: arithmetic never
    /// rounds a non-zero result to it).
    pub fn is_zero(&self) -> bool {
        self.lo == 0.0 && self.hi == 0.0
    }

    /// The sign of every point of the interval, if they all agree.
    pub fn sign(&self) -> Option<Sign> {
        if self.lo > 0.0 {
            Some(Sign::Positive)
        } else if self.hi < 0.0 {
            Some(Sign::Negative)
        } else if self.is_zero() {
            Some(Sign::Zero)
        } else {
            None
        }
    }

    /// Whether the interval is a finite, non-empty range.
    pub fn is_finite(&self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }

    /// Width `hi - lo` (rounded up).
    pub fn width(&self) -> f64 {
        up(self.hi - self.lo)
    }

    /// The midpoint (for display).
    pub fn mid(&self) -> f64 {
        if self.lo.is_finite() && self.hi.is_finite() {
            self.lo * 0.5 + self.hi * 0.5
        } else if self.lo.is_finite() {
            self.lo
        } else {
            self.hi
        }
    }

    /// Square root of the non-negative part of the interval.
    pub fn sqrt(self) -> Interval {
        let lo = if self.lo <= 0.0 {
            0.0
        } else {
            down(self.lo.sqrt()).max(0.0)
        };
        let hi = if self.hi < 0.0 {
            0.0
        } else {
            up(self.hi.sqrt())
        };
        Interval { lo, hi }
    }

    /// The square: `{x² : x in self}` (never negative, unlike `self * self`).
    pub fn square(self) -> Interval {
        let (a, b) = (self.lo.abs(), self.hi.abs());
        let (small, big) = if self.lo <= 0.0 && self.hi >= 0.0 {
            (0.0, a.max(b))
        } else {
            (a.min(b), a.max(b))
        };
        let hi = big * big;
        if hi.is_nan() {
            return Interval::ENTIRE;
        }
        Interval {
            lo: down(small * small).max(0.0),
            hi: up(hi),
        }
    }

    /// Whether the two intervals share a point.
    pub fn overlaps(&self, other: &Interval) -> bool {
        !(self.hi < other.lo || other.hi < self.lo)
    }

    /// The convex hull of two intervals.
    pub fn hull(&self, other: &Interval) -> Interval {
        Interval {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }
}

impl std::ops::Add for Interval {
    type Output = Interval;

    #[inline(always)]
    fn add(self, other: Interval) -> Interval {
        // adding an exact zero is exact
        if other.is_zero() {
            return self;
        }
        if self.is_zero() {
            return other;
        }
        Interval {
            lo: down(self.lo + other.lo),
            hi: up(self.hi + other.hi),
        }
    }
}

impl std::ops::Sub for Interval {
    type Output = Interval;

    #[inline(always)]
    fn sub(self, other: Interval) -> Interval {
        // subtracting an exact zero, or from one, is exact
        if other.is_zero() {
            return self;
        }
        if self.is_zero() {
            return -other;
        }
        Interval {
            lo: down(self.lo - other.hi),
            hi: up(self.hi - other.lo),
        }
    }
}

impl std::ops::Mul for Interval {
    type Output = Interval;

    #[inline(always)]
    fn mul(self, other: Interval) -> Interval {
        let (a, b) = (self, other);
        if a.is_zero() || b.is_zero() {
            return Interval::point(0.0);
        }
        // the extreme products by the signs of the operands (the classic
        // nine cases), rather than all four products and their min and max
        let (lo, hi) = if a.lo >= 0.0 {
            if b.lo >= 0.0 {
                (a.lo * b.lo, a.hi * b.hi)
            } else if b.hi <= 0.0 {
                (a.hi * b.lo, a.lo * b.hi)
            } else {
                (a.hi * b.lo, a.hi * b.hi)
            }
        } else if a.hi <= 0.0 {
            if b.lo >= 0.0 {
                (a.lo * b.hi, a.hi * b.lo)
            } else if b.hi <= 0.0 {
                (a.hi * b.hi, a.lo * b.lo)
            } else {
                (a.lo * b.hi, a.lo * b.lo)
            }
        } else if b.lo >= 0.0 {
            (a.lo * b.hi, a.hi * b.hi)
        } else if b.hi <= 0.0 {
            (a.hi * b.lo, a.lo * b.lo)
        } else {
            (
                (a.lo * b.hi).min(a.hi * b.lo),
                (a.lo * b.lo).max(a.hi * b.hi),
            )
        };
        if lo.is_nan() || hi.is_nan() {
            // 0 · ∞ at an end: give up rather than guess
            return Interval::ENTIRE;
        }
        Interval {
            lo: down(lo),
            hi: up(hi),
        }
    }
}

impl std::ops::Div for Interval {
    type Output = Interval;

    fn div(self, other: Interval) -> Interval {
        if other.lo <= 0.0 && other.hi >= 0.0 {
            return Interval::ENTIRE;
        }
        let p = [
            self.lo / other.lo,
            self.lo / other.hi,
            self.hi / other.lo,
            self.hi / other.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval {
            lo: down(lo),
            hi: up(hi),
        }
    }
}

impl std::ops::Neg for Interval {
    type Output = Interval;

    fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn int_enclosures() {
        let big = Int::from(1u128 << 100) + Int::from(1);
        let iv = Interval::of_int(&big);
        assert!(iv.lo < iv.hi);
        assert!(iv.lo <= 2f64.powi(100) && 2f64.powi(100) <= iv.hi);
        assert_eq!(
            Interval::of_int(&Int::from(12345)),
            Interval::point(12345.0)
        );
        let huge = Int::from(1) << 2000;
        let iv = Interval::of_int(&huge);
        assert!(iv.hi.is_infinite() && iv.lo == f64::MAX);
    }

    /// `of_int` encloses integers of every length, those past 64 bits with
    /// many low zero bits too (dashu-int 0.6.2 calls some of their
    /// conversions to f64 exact that are not: the first case is one).
    #[test]
    fn int_enclosures_hold_the_integer() {
        let holds = |x: &Int| {
            let iv = Interval::of_int(x);
            let r = crate::num::Rational::from_int(x.clone());
            let lo = crate::num::Rational::from_f64(iv.lo);
            let hi = crate::num::Rational::from_f64(iv.hi);
            assert!(lo.is_none_or(|lo| lo <= r), "{x}: {iv:?}");
            assert!(hi.is_none_or(|hi| r <= hi), "{x}: {iv:?}");
        };
        let known: Int = "13031795572555964228897880566452730200064"
            .parse()
            .expect("an integer");
        holds(&known);
        holds(&-known);
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..20_000 {
            let mut x = Int::ZERO;
            for _ in 0..1 + rng.below(5) {
                x = (x << 64) + Int::from(rng.next_u64());
            }
            let keep = rng.below(120) as usize;
            x = (x >> keep) << keep;
            if rng.below(2) == 0 {
                x = -x;
            }
            holds(&x);
            // (the top 64 bits read from the words are those of a shift)
            let bits = dashu_base::BitTest::bit_len(&x);
            if bits >= 128 {
                let k = bits - 64;
                let magnitude = if x < Int::ZERO { -x.clone() } else { x.clone() };
                let shifted = u64::try_from(&(magnitude >> k)).expect("64 bits");
                assert_eq!(top_bits(&x, k), shifted, "{x}");
            }
        }
    }

    /// `of_i128` encloses every `i128`, as a point exactly where the value
    /// is a double, and agrees with `of_int` on the same integer.
    #[test]
    fn i128_enclosures() {
        let cases = [
            0i128,
            1,
            -1,
            (1 << 53) - 1,
            -(1 << 53) + 1,
            1 << 53,
            -(1 << 53),
            (1 << 53) + 1,
            -(1 << 53) - 1,
            1 << 100,
            (1 << 100) + 1,
            i128::MAX,
            i128::MIN,
            i128::MIN + 1,
            (1 << 126) - 3,
            (1 << 62) - 1,
            -(1 << 62) + 1,
            1 << 62,
            (1 << 62) + 1,
            (1 << 61) + 1,
            -(1 << 61) - 3,
            (1 << 54) + 2,
            (1 << 54) + 1,
            -(1 << 54) - 1,
        ];
        for x in cases {
            let iv = Interval::of_i128(x);
            let exact = Int::from(x);
            let (lo, hi) = (
                crate::num::Rational::from_f64(iv.lo).expect("finite"),
                crate::num::Rational::from_f64(iv.hi).expect("finite"),
            );
            let r = crate::num::Rational::from_int(exact.clone());
            assert!(lo <= r && r <= hi, "{x} outside {iv:?}");
            assert_eq!(
                iv.lo == iv.hi,
                (x as f64) as i128 == x && x != i128::MAX,
                "{x}"
            );
            assert_eq!(
                iv.lo == iv.hi,
                Interval::of_int(&exact).lo == Interval::of_int(&exact).hi,
                "{x}"
            );
        }
    }

    /// Between 2^53 and 2^62 in magnitude, `of_i128` (the `i64`
    /// conversion) is the enclosure of the `i128` conversion: the point
    /// where that double is the integer, else the two doubles next to it.
    #[test]
    fn i128_enclosures_between_2_53_and_2_62() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for i in 0..20_000u32 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            // (every bit length from 54 to 62, both signs)
            let bits = 54 + (i % 9);
            let magnitude = (state >> (64 - bits)) as i128 | 1 << (bits - 1);
            let x = if i % 2 == 0 { magnitude } else { -magnitude };
            let v = x as f64;
            let reference = if v as i128 == x {
                Interval::point(v)
            } else {
                Interval {
                    lo: v.next_down(),
                    hi: v.next_up(),
                }
            };
            assert_eq!(Interval::of_i128(x), reference, "{x}");
        }
    }

    #[test]
    fn products_enclose_every_corner() {
        // the sign cases against the four corner products, on a grid of
        // intervals with ends of every sign, zeros and infinities
        let ends = [
            f64::NEG_INFINITY,
            -3.5,
            -1.0,
            -0.0,
            0.0,
            0.25,
            2.0,
            f64::INFINITY,
        ];
        let mut ivs = Vec::new();
        for &lo in &ends {
            for &hi in &ends {
                if lo <= hi {
                    ivs.push(Interval { lo, hi });
                }
            }
        }
        for &a in &ivs {
            for &b in &ivs {
                let p = a * b;
                for x in [a.lo, a.hi] {
                    for y in [b.lo, b.hi] {
                        let c = x * y;
                        if !c.is_nan() {
                            assert!(p.lo <= c && c <= p.hi, "{a:?} * {b:?} = {p:?} misses {c}");
                        }
                    }
                }
                // an interior point too
                let (x, y) = (a.mid(), b.mid());
                if x.is_finite() && y.is_finite() && !(x * y).is_nan() {
                    assert!(p.lo <= x * y && x * y <= p.hi);
                }
            }
        }
        let sq = Interval { lo: -2.0, hi: 3.0 }.square();
        assert!(sq.lo == 0.0 && sq.hi >= 9.0);
        let sq = Interval { lo: -3.0, hi: -2.0 }.square();
        assert!(sq.lo <= 4.0 && sq.lo > 3.9 && sq.hi >= 9.0);
    }

    #[test]
    fn outward() {
        let a = Interval::point(0.1);
        let b = Interval::point(0.2);
        let s = a + b;
        assert!(s.lo < 0.30000000000000004 && s.hi >= 0.30000000000000004);
        let q = Interval::point(1.0) / Interval::point(3.0);
        assert!(q.lo < 1.0 / 3.0 && q.hi > 1.0 / 3.0);
        assert_eq!(
            Interval::point(1.0) / Interval { lo: -1.0, hi: 1.0 },
            Interval::ENTIRE
        );
    }
}
