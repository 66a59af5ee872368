//! Property tests of the exact kernel (`kss::num` and `kss::motion`).
//!
//! Every decision in kss is taken by the f64 interval filter when it can and
//! by exact big-integer arithmetic otherwise. These tests check the kernel
//! against an *independent* exact reference written here ([`reference`]):
//! it represents a number as `(p + s·√d)/q`, decides equality algebraically
//! (linear independence of `1`, `√d1`, `√d2` over the rationals) and orders
//! unequal numbers by refining rational bounds built from a hand-written
//! integer square root until they separate. It shares no code with the
//! kernel's comparison (which squares), so agreement is meaningful.
//!
//! Inputs mix scales on purpose: small integers, machine words, integers up
//! to 2^200 (and a few beyond 1000 bits, where the filter gives up), every
//! class of double, and deliberately constructed near-ties (continued
//! fraction convergents, enclosure end points, roots of perturbed
//! polynomials) and exact ties (scaled polynomials, rational roots).
//!
//! The interval filter counters are process-wide; the test that measures
//! them takes [`STATS_LOCK`] for writing while every other test takes it for
//! reading, so no other comparison runs while it measures.

use std::cmp::Ordering;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::sync::{RwLock, RwLockReadGuard};

use kss::geom::{orient, BodyPolygon, Point};
use kss::motion::{orient_poly, Frame, LinearPoint, Trajectory};
use kss::num::{filter_stats, reset_filter_stats, Int, Poly, Rational, Sign, Time};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

use reference::{own_sign_at, Real, Q};

/// Serialises the filter-fraction measurement against every other test.
static STATS_LOCK: RwLock<()> = RwLock::new(());

/// Shared access for ordinary tests (they may run in parallel).
fn shared() -> RwLockReadGuard<'static, ()> {
    STATS_LOCK.read().unwrap_or_else(|e| e.into_inner())
}

/// Proptest configuration: `cases` cases, no regression files written.
///
/// Set `KSS_PROPTEST_SCALE=n` to run `n` times as many cases (a deeper
/// search; the default keeps the whole file well under 30 s).
fn config(cases: u32) -> ProptestConfig {
    let scale: u32 = std::env::var("KSS_PROPTEST_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    ProptestConfig {
        cases: cases.saturating_mul(scale.max(1)),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// An exact reference for real numbers of the form `(p + s·√d)/q`,
/// independent of the kernel's arithmetic.
mod reference {
    use std::cmp::Ordering;

    use dashu_base::BitTest;
    use kss::num::{Int, Rational, Sign};

    /// Integer square root `⌊√n⌋` by Newton's iteration from above.
    pub fn isqrt(n: &Int) -> Int {
        assert!(*n >= Int::ZERO, "isqrt of a negative number");
        if *n < Int::from(2) {
            return n.clone();
        }
        // 2^⌈bits/2⌉ >= √n; Newton's iteration decreases monotonically to ⌊√n⌋.
        let mut x = Int::ONE << n.bit_len().div_ceil(2);
        loop {
            let y = (&x + n / &x) >> 1;
            if y >= x {
                return x;
            }
            x = y;
        }
    }

    /// `⌊n / d⌋` for `d > 0`, whatever the rounding of `/`.
    pub fn floor_div(n: &Int, d: &Int) -> Int {
        assert!(*d > Int::ZERO);
        let mut q = n / d;
        while &q * d > *n {
            q -= Int::ONE;
        }
        while (&q + Int::ONE) * d <= *n {
            q += Int::ONE;
        }
        q
    }

    /// The sign of an integer.
    pub fn int_sign(x: &Int) -> Sign {
        match x.cmp(&Int::ZERO) {
            Ordering::Less => Sign::Negative,
            Ordering::Equal => Sign::Zero,
            Ordering::Greater => Sign::Positive,
        }
    }

    /// An exact rational `n/d` with `d > 0` (not necessarily reduced).
    #[derive(Clone, Debug)]
    pub struct Q {
        /// Numerator.
        pub n: Int,
        /// Denominator, positive.
        pub d: Int,
    }

    impl Q {
        /// `n/d`, `d != 0`.
        pub fn new(n: Int, d: Int) -> Q {
            assert!(!d.is_zero(), "zero denominator");
            if d < Int::ZERO {
                Q { n: -n, d: -d }
            } else {
                Q { n, d }
            }
        }

        /// The integer `n`.
        pub fn int(n: Int) -> Q {
            Q { n, d: Int::ONE }
        }

        /// The exact value of a finite double, decoded from its bits here.
        pub fn from_f64(x: f64) -> Option<Q> {
            if !x.is_finite() {
                return None;
            }
            let bits = x.to_bits();
            let biased = ((bits >> 52) & 0x7ff) as i64;
            let frac = bits & ((1u64 << 52) - 1);
            let (m, e) = if biased == 0 {
                (frac, -1074)
            } else {
                (frac | (1u64 << 52), biased - 1075)
            };
            let m = if bits >> 63 == 1 {
                -Int::from(m)
            } else {
                Int::from(m)
            };
            Some(if e >= 0 {
                Q::int(m << e as usize)
            } else {
                Q::new(m, Int::ONE << (-e) as usize)
            })
        }

        /// Exact order by cross-multiplication.
        pub fn cmp(&self, o: &Q) -> Ordering {
            (&self.n * &o.d).cmp(&(&o.n * &self.d))
        }

        /// `self + o`.
        pub fn add(&self, o: &Q) -> Q {
            Q::new(&self.n * &o.d + &o.n * &self.d, &self.d * &o.d)
        }

        /// `self + k`.
        pub fn add_int(&self, k: i64) -> Q {
            self.add(&Q::int(Int::from(k)))
        }

        /// The kernel's rational with this value.
        pub fn to_rational(&self) -> Rational {
            Rational::new(self.n.clone(), self.d.clone())
        }

        /// The value of a kernel rational.
        pub fn from_rational(r: &Rational) -> Q {
            Q::new(r.numer().clone(), r.denom().clone())
        }
    }

    /// The real `(p + s·√d)/q` with `q > 0`, `d >= 0`; normalised so that
    /// `s == 0` (a rational) or `d` is not a perfect square (an irrational).
    #[derive(Clone, Debug)]
    pub struct Real {
        p: Int,
        s: Int,
        d: Int,
        q: Int,
    }

    impl Real {
        fn normalized(p: Int, s: Int, d: Int, q: Int) -> Real {
            assert!(q > Int::ZERO && d >= Int::ZERO);
            if s.is_zero() || d.is_zero() {
                return Real {
                    p,
                    s: Int::ZERO,
                    d: Int::ZERO,
                    q,
                };
            }
            let r = isqrt(&d);
            if &r * &r == d {
                return Real {
                    p: p + s * r,
                    s: Int::ZERO,
                    d: Int::ZERO,
                    q,
                };
            }
            Real { p, s, d, q }
        }

        /// A rational.
        pub fn rational(x: &Q) -> Real {
            Real::normalized(x.n.clone(), Int::ZERO, Int::ZERO, x.d.clone())
        }

        /// Zero.
        pub fn zero() -> Real {
            Real::rational(&Q::int(Int::ZERO))
        }

        /// The exact value of a finite double.
        pub fn from_f64(x: f64) -> Option<Real> {
            Q::from_f64(x).map(|q| Real::rational(&q))
        }

        /// The larger (or smaller) real root of `a t² + b t + c`, `a != 0`,
        /// `b² − 4ac >= 0`.
        pub fn quad_root(a: &Int, b: &Int, c: &Int, larger: bool) -> Real {
            assert!(!a.is_zero());
            let d = b * b - Int::from(4) * a * c;
            assert!(d >= Int::ZERO, "no real root");
            // (−b + σ√d)/2a is the larger root iff σ·a > 0.
            let sigma = if (*a > Int::ZERO) == larger {
                Int::ONE
            } else {
                -Int::ONE
            };
            if *a > Int::ZERO {
                Real::normalized(-b.clone(), sigma, d, Int::from(2) * a)
            } else {
                Real::normalized(b.clone(), -sigma, d, Int::from(-2) * a)
            }
        }

        /// The value if it is rational.
        pub fn as_rational(&self) -> Option<Q> {
            self.s
                .is_zero()
                .then(|| Q::new(self.p.clone(), self.q.clone()))
        }

        /// Rational bounds `lo <= x <= hi` with `hi − lo = |s|/(q·2^k)`
        /// (exact, `lo == hi`, for a rational).
        pub fn bounds(&self, k: usize) -> (Q, Q) {
            if self.s.is_zero() {
                let x = Q::new(self.p.clone(), self.q.clone());
                return (x.clone(), x);
            }
            // r/2^k <= √d < (r+1)/2^k
            let r = isqrt(&(&self.d << (2 * k)));
            let base = &self.p << k;
            let den = &self.q << k;
            let a = &base + &self.s * &r;
            let b = &base + &self.s * (&r + Int::ONE);
            if self.s > Int::ZERO {
                (Q::new(a, den.clone()), Q::new(b, den))
            } else {
                (Q::new(b, den.clone()), Q::new(a, den))
            }
        }

        /// Whether two reals are equal, decided algebraically.
        pub fn equals(&self, o: &Real) -> bool {
            match (self.s.is_zero(), o.s.is_zero()) {
                (true, true) => &self.p * &o.q == &o.p * &self.q,
                (true, false) | (false, true) => false,
                (false, false) => {
                    // √d2 = (r/d1)·√d1 if d1·d2 = r² is a square; otherwise
                    // 1, √d1, √d2 are linearly independent over Q.
                    let prod = &self.d * &o.d;
                    let r = isqrt(&prod);
                    if &r * &r != prod {
                        return false;
                    }
                    &self.p * &o.q == &o.p * &self.q
                        && &self.s * &o.q * &self.d == &o.s * &self.q * &r
                }
            }
        }

        /// Exact order: equality algebraically, otherwise by refining bounds
        /// until they separate.
        pub fn cmp(&self, o: &Real) -> Ordering {
            if self.equals(o) {
                return Ordering::Equal;
            }
            let mut k = 16;
            loop {
                let (alo, ahi) = self.bounds(k);
                let (blo, bhi) = o.bounds(k);
                if ahi.cmp(&blo) == Ordering::Less {
                    return Ordering::Less;
                }
                if bhi.cmp(&alo) == Ordering::Less {
                    return Ordering::Greater;
                }
                k *= 2;
            }
        }

        /// The sign.
        pub fn sign(&self) -> Sign {
            match self.cmp(&Real::zero()) {
                Ordering::Less => Sign::Negative,
                Ordering::Equal => Sign::Zero,
                Ordering::Greater => Sign::Positive,
            }
        }

        /// The value of `c0 + c1·x + c2·x²` at `x = self`, exactly.
        pub fn poly_at(&self, c: &[Int; 3]) -> Real {
            // q²·P(x) = [c0 q² + c1 q p + c2 (p² + s² d)] + [c1 q s + 2 c2 p s]·√d
            let (p, s, d, q) = (&self.p, &self.s, &self.d, &self.q);
            let a = &c[0] * q * q + &c[1] * q * p + &c[2] * (p * p + s * s * d);
            let b = &c[1] * q * s + Int::from(2) * &c[2] * p * s;
            Real::normalized(a, b, d.clone(), q * q)
        }

        /// The first `n` continued-fraction convergents (best rational
        /// approximations; just the value for a rational).
        pub fn convergents(&self, n: usize) -> Vec<Q> {
            if self.s.is_zero() {
                return vec![Q::new(self.p.clone(), self.q.clone())];
            }
            // Write x = (P + √D)/Q with Q | D − P², as the classical
            // recurrence needs.
            let (p0, q0) = if self.s < Int::ZERO {
                (-self.p.clone(), -self.q.clone())
            } else {
                (self.p.clone(), self.q.clone())
            };
            let qa = if q0 < Int::ZERO {
                -q0.clone()
            } else {
                q0.clone()
            };
            let dd = &self.s * &self.s * &self.d * &qa * &qa;
            let mut p = p0 * &qa;
            let mut q = q0 * &qa;
            let r = isqrt(&dd);
            let (mut h0, mut h1) = (Int::ZERO, Int::ONE);
            let (mut k0, mut k1) = (Int::ONE, Int::ZERO);
            let mut out = Vec::with_capacity(n);
            for _ in 0..n {
                let a = if q > Int::ZERO {
                    floor_div(&(&p + &r), &q)
                } else {
                    floor_div(&(-&p - &r - Int::ONE), &(-q.clone()))
                };
                let h2 = &a * &h1 + &h0;
                let k2 = &a * &k1 + &k0;
                out.push(Q::new(h2.clone(), k2.clone()));
                (h0, h1, k0, k1) = (h1, h2, k1, k2);
                let p_next = &a * &q - &p;
                let q_next = (&dd - &p_next * &p_next) / &q;
                p = p_next;
                q = q_next;
            }
            out
        }
    }

    /// The sign of `c0 + c1·x + c2·x²` at a rational `x`, by direct integer
    /// evaluation (`x = n/d`, `d > 0`).
    pub fn own_sign_at(c: &[Int; 3], x: &Q) -> Sign {
        let v = &c[0] * &x.d * &x.d + &c[1] * &x.n * &x.d + &c[2] * &x.n * &x.n;
        int_sign(&v)
    }
}

// ---------------------------------------------------------------------------
// Samples: a kernel time together with its independent reference value.
// ---------------------------------------------------------------------------

/// A kernel [`Time`] and the same value in the reference representation.
#[derive(Clone, Debug)]
struct Sample {
    real: Real,
    time: Time,
}

impl Sample {
    /// The rational `n/d`.
    fn rational(n: Int, d: Int) -> Sample {
        let q = Q::new(n, d);
        Sample {
            time: Time::from_rational(q.to_rational()),
            real: Real::rational(&q),
        }
    }

    /// A reference rational.
    fn from_q(q: &Q) -> Sample {
        Sample::rational(q.n.clone(), q.d.clone())
    }

    /// A double, through [`Time::from_f64`] or through [`Rational::from_f64`].
    fn double(x: f64, via_rational: bool) -> Sample {
        let time = if via_rational {
            Time::from_rational(Rational::from_f64(x).expect("finite"))
        } else {
            Time::from_f64(x).expect("finite")
        };
        Sample {
            real: Real::from_f64(x).expect("finite"),
            time,
        }
    }

    /// A root of `a t² + b t + c` found by [`Poly::roots`] (`a != 0`,
    /// non-negative discriminant).
    fn root(a: &Int, b: &Int, c: &Int, larger: bool) -> Sample {
        let roots = Poly::new(c.clone(), b.clone(), a.clone()).roots();
        assert!(!roots.is_empty() && roots.len() <= 2);
        let time = if roots.len() == 2 && larger {
            roots[1].clone()
        } else {
            roots[0].clone()
        };
        Sample {
            real: Real::quad_root(a, b, c, larger),
            time,
        }
    }
}

/// The next double above a finite `x` (`f64::next_up` needs Rust 1.86,
/// above the crate's MSRV).
fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

/// The next double below a finite `x`.
fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// Hash of a time with the standard hasher.
fn hash_of(t: &Time) -> u64 {
    let mut h = DefaultHasher::new();
    t.hash(&mut h);
    h.finish()
}

// ---------------------------------------------------------------------------
// Strategies.
// ---------------------------------------------------------------------------

/// Integers in `[-20, 20]`.
fn small_int() -> impl Strategy<Value = Int> {
    (-20i64..=20).prop_map(Int::from)
}

/// Any 64-bit integer.
fn word_int() -> impl Strategy<Value = Int> {
    any::<i64>().prop_map(Int::from)
}

/// Integers of up to `max_bits <= 256` bits, either sign.
fn big_int(max_bits: usize) -> impl Strategy<Value = Int> {
    (
        any::<bool>(),
        prop::array::uniform4(any::<u64>()),
        1..=max_bits.min(256),
    )
        .prop_map(|(neg, limbs, bits)| {
            let mut x = Int::ZERO;
            for l in limbs {
                x = (x << 64) + Int::from(l);
            }
            let x = x >> (256 - bits);
            if neg {
                -x
            } else {
                x
            }
        })
}

/// Integers of every scale from tiny to 2^200.
fn mixed_int() -> impl Strategy<Value = Int> {
    prop_oneof![
        3 => small_int(),
        3 => word_int(),
        3 => big_int(200),
        1 => (any::<bool>(), 0usize..200).prop_map(|(neg, k)| {
            let x = Int::ONE << k;
            if neg { -x } else { x }
        }),
    ]
}

/// Non-zero integers of every scale.
fn nonzero_int() -> impl Strategy<Value = Int> {
    mixed_int().prop_map(|x| if x.is_zero() { Int::ONE } else { x })
}

/// Finite doubles of every class, including subnormals and zeros.
fn any_double() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::num::f64::POSITIVE
            | prop::num::f64::NEGATIVE
            | prop::num::f64::NORMAL
            | prop::num::f64::SUBNORMAL
            | prop::num::f64::ZERO,
        -1e6..1e6f64,
        -2.0..2.0f64,
    ]
}

/// Make `a t² + b t + c` a true quadratic with real roots: `a != 0`, and `c`
/// negated if the discriminant is negative (then `ac < 0`).
fn fix_quad((a, b, c): (Int, Int, Int)) -> (Int, Int, Int) {
    let a = if a.is_zero() { Int::ONE } else { a };
    let d = &b * &b - Int::from(4) * &a * &c;
    let c = if d < Int::ZERO { -c } else { c };
    (a, b, c)
}

/// Quadratics with real roots, coefficients of mixed scales.
fn quad() -> impl Strategy<Value = (Int, Int, Int)> {
    prop_oneof![
        (small_int(), small_int(), small_int()).prop_map(fix_quad),
        (mixed_int(), mixed_int(), mixed_int()).prop_map(fix_quad),
        (word_int(), big_int(200), word_int()).prop_map(fix_quad),
        // beyond the f64 range: no finite interval for the coefficients
        (big_int(64), big_int(200), big_int(200), 1000usize..1100)
            .prop_map(|(a, b, c, k)| fix_quad((a, b << k, c << (k / 2)))),
    ]
}

/// Irrational (or, for square discriminants, rational) roots.
fn root_sample() -> impl Strategy<Value = Sample> {
    (quad(), any::<bool>()).prop_map(|((a, b, c), larger)| Sample::root(&a, &b, &c, larger))
}

/// Any kind of time: doubles, integer fractions, quadratic roots.
fn any_sample() -> impl Strategy<Value = Sample> {
    prop_oneof![
        2 => (any_double(), any::<bool>()).prop_map(|(x, v)| Sample::double(x, v)),
        2 => (mixed_int(), nonzero_int()).prop_map(|(n, d)| Sample::rational(n, d)),
        1 => (small_int(), 1i64..50).prop_map(|(n, d)| Sample::rational(n, Int::from(d))),
        // far outside the double range, both ways
        1 => (mixed_int(), nonzero_int(), -1300i64..1300).prop_map(|(n, d, e)| {
            if e >= 0 {
                Sample::rational(n << e as usize, d)
            } else {
                Sample::rational(n, d << (-e) as usize)
            }
        }),
        4 => root_sample(),
    ]
}

/// Two independent random times (almost never equal).
fn random_pair() -> impl Strategy<Value = (Sample, Sample)> {
    (any_sample(), any_sample())
}

/// Pairs of distinct times that are deliberately very close, so that the
/// filter must hand over to exact arithmetic.
fn near_tie_pair() -> impl Strategy<Value = (Sample, Sample)> {
    prop_oneof![
        // A root and one of its continued-fraction convergents.
        (root_sample(), 1usize..40).prop_map(|(s, n)| {
            let c = s.real.convergents(n);
            let q = c.last().expect("one convergent").clone();
            (s, Sample::from_q(&q))
        }),
        // Two consecutive convergents (Farey neighbours).
        (root_sample(), 2usize..40).prop_map(|(s, n)| {
            let c = s.real.convergents(n);
            let m = c.len();
            let a = Sample::from_q(&c[m.saturating_sub(2)]);
            let b = Sample::from_q(&c[m - 1]);
            (a, b)
        }),
        // A root and a rational bound on it, 2^-k away.
        (root_sample(), 8usize..400, any::<bool>()).prop_map(|(s, k, hi)| {
            let (lo, up) = s.real.bounds(k);
            let q = if hi { up } else { lo };
            (s, Sample::from_q(&q))
        }),
        // A root and a double next to it, or an end point of its enclosure.
        (root_sample(), 0usize..5).prop_map(|(s, which)| {
            let f = s.time.to_f64();
            let iv = s.time.interval();
            let x = [f, next_up(f), next_down(f), iv.lo, iv.hi][which];
            let x = if x.is_finite() { x } else { 0.0 };
            (s, Sample::double(x, which % 2 == 0))
        }),
        // Roots of a quadratic and of a slightly perturbed multiple of it.
        (
            quad(),
            prop_oneof![nonzero_int(), (1usize..150).prop_map(|k| Int::ONE << k)],
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(|((a, b, c), m, up, larger)| {
                let delta = if up { Int::ONE } else { -Int::ONE };
                let (a2, b2) = (&m * &a, &m * &b);
                let mut c2 = &m * &c + &delta;
                if &b2 * &b2 - Int::from(4) * &a2 * &c2 < Int::ZERO {
                    c2 = &m * &c - &delta;
                }
                (
                    Sample::root(&a, &b, &c, larger),
                    Sample::root(&a2, &b2, &c2, larger),
                )
            }),
        // A root x of one quadratic and a root of (k t − h)(u t − v) ± 1,
        // where h/k is a convergent of x: two unrelated discriminants.
        (
            root_sample(),
            2usize..30,
            prop_oneof![(1i64..20).prop_map(Int::from), nonzero_int()],
            mixed_int(),
            any::<bool>(),
        )
            .prop_map(|(s, n, u, v, up)| {
                let hk = s.real.convergents(n).pop().expect("one convergent");
                let (h, k) = (hk.n.clone(), hk.d.clone());
                let mut delta = if up { Int::ONE } else { -Int::ONE };
                let a = &k * &u;
                let b = -(&k * &v + &h * &u);
                if &b * &b - Int::from(4) * &a * (&h * &v + &delta) < Int::ZERO {
                    delta = -delta;
                }
                let c = &h * &v + &delta;
                // the root near h/k is the larger one iff v/u < h/k
                let larger = Q::new(v, u).cmp(&hk) == Ordering::Less;
                (s, Sample::root(&a, &b, &c, larger))
            }),
        // x and a root of N²·p(t − 1/N) ± 1, which is within about 1/N of x.
        (
            quad(),
            prop_oneof![nonzero_int(), (1usize..150).prop_map(|k| Int::ONE << k)],
            any::<bool>(),
            any::<bool>(),
        )
            .prop_map(|((a, b, c), n, up, larger)| {
                let mut delta = if up { Int::ONE } else { -Int::ONE };
                let a2 = &a * &n * &n;
                let b2 = &b * &n * &n - Int::from(2) * &a * &n;
                let c0 = &a - &b * &n + &c * &n * &n;
                if &b2 * &b2 - Int::from(4) * &a2 * (&c0 + &delta) < Int::ZERO {
                    delta = -delta;
                }
                (
                    Sample::root(&a, &b, &c, larger),
                    Sample::root(&a2, &b2, &(c0 + delta), larger),
                )
            }),
        // A rational and a neighbour at distance 1/(q·m).
        (mixed_int(), nonzero_int(), nonzero_int()).prop_map(|(p, q, m)| {
            let a = Sample::rational(p.clone(), q.clone());
            let b = Sample::rational(&p * &m + Int::ONE, &q * &m);
            (a, b)
        }),
        // A fraction and the double nearest to it.
        (mixed_int(), nonzero_int(), any::<bool>()).prop_map(|(p, q, v)| {
            let a = Sample::rational(p, q);
            let x = a.time.to_f64();
            let x = if x.is_finite() { x } else { 0.0 };
            (a, Sample::double(x, v))
        }),
    ]
}

/// Pairs of equal times with different constructions.
fn exact_tie_pair() -> impl Strategy<Value = (Sample, Sample)> {
    prop_oneof![
        // The same root of a polynomial and of a (possibly negative) multiple.
        (quad(), nonzero_int(), any::<bool>()).prop_map(|((a, b, c), k, larger)| {
            (
                Sample::root(&a, &b, &c, larger),
                Sample::root(&(&k * &a), &(&k * &b), &(&k * &c), larger),
            )
        }),
        // √n as a root of t² − n and of 4t² − 4n.
        (2i64..10_000, any::<bool>()).prop_map(|(n, larger)| {
            let n = Int::from(n);
            (
                Sample::root(&Int::ONE, &Int::ZERO, &-n.clone(), larger),
                Sample::root(&Int::from(4), &Int::ZERO, &(Int::from(-4) * n), larger),
            )
        }),
        // p/q against the matching root of (q t − p)(s t − r).
        (mixed_int(), nonzero_int(), mixed_int(), nonzero_int()).prop_map(|(p, q, r, s)| {
            let x = Real::rational(&Q::new(p.clone(), q.clone()));
            let y = Real::rational(&Q::new(r.clone(), s.clone()));
            let larger = x.cmp(&y) == Ordering::Greater;
            let a = &q * &s;
            let b = -(&p * &s + &r * &q);
            let c = &p * &r;
            (Sample::rational(p, q), Sample::root(&a, &b, &c, larger))
        }),
        // p/q against the root of the linear k·(q t − p).
        (mixed_int(), nonzero_int(), nonzero_int()).prop_map(|(p, q, k)| {
            let root = Poly::new(-(&k * &p), &k * &q, Int::ZERO).roots();
            let x = Q::new(p.clone(), q.clone());
            (
                Sample::rational(p, q),
                Sample {
                    real: Real::rational(&x),
                    time: root[0].clone(),
                },
            )
        }),
        // A double against the same dyadic rational with a common factor.
        (any_double(), nonzero_int(), any::<bool>()).prop_map(|(x, k, v)| {
            let q = Q::from_f64(x).expect("finite");
            (Sample::double(x, v), Sample::rational(&q.n * &k, &q.d * &k))
        }),
        // A fraction against itself with a common factor.
        (mixed_int(), nonzero_int(), nonzero_int()).prop_map(|(p, q, k)| {
            (
                Sample::rational(p.clone(), q.clone()),
                Sample::rational(&p * &k, &q * &k),
            )
        }),
    ]
}

// ---------------------------------------------------------------------------
// Checks.
// ---------------------------------------------------------------------------

/// The enclosure of a time contains its exact value.
fn check_enclosure(s: &Sample) -> Result<(), TestCaseError> {
    let iv = s.time.interval();
    prop_assert!(iv.lo <= iv.hi, "empty enclosure {:?}", iv);
    match Real::from_f64(iv.lo) {
        Some(lo) => prop_assert!(
            lo.cmp(&s.real) != Ordering::Greater,
            "enclosure {:?} misses {:?}",
            iv,
            s
        ),
        None => prop_assert_eq!(iv.lo, f64::NEG_INFINITY),
    }
    match Real::from_f64(iv.hi) {
        Some(hi) => prop_assert!(
            hi.cmp(&s.real) != Ordering::Less,
            "enclosure {:?} misses {:?}",
            iv,
            s
        ),
        None => prop_assert_eq!(iv.hi, f64::INFINITY),
    }
    Ok(())
}

/// The kernel orders a pair as the reference does, in both directions, and
/// `==`, `Hash` and `partial_cmp` agree with `cmp`.
fn check_pair(a: &Sample, b: &Sample) -> Result<Ordering, TestCaseError> {
    check_enclosure(a)?;
    check_enclosure(b)?;
    let expect = a.real.cmp(&b.real);
    prop_assert_eq!(a.time.cmp(&b.time), expect, "{:?} vs {:?}", a, b);
    prop_assert_eq!(b.time.cmp(&a.time), expect.reverse(), "{:?} vs {:?}", b, a);
    prop_assert_eq!(a.time.partial_cmp(&b.time), Some(expect));
    prop_assert_eq!(a.time == b.time, expect == Ordering::Equal);
    if expect == Ordering::Equal {
        prop_assert_eq!(hash_of(&a.time), hash_of(&b.time), "{:?} vs {:?}", a, b);
    }
    Ok(expect)
}

proptest! {
    #![proptest_config(config(5000))]

    /// The filtered order of two random times equals the exact reference
    /// order (almost all of these are decided by the filter).
    #[test]
    fn filter_agrees_with_reference_on_random_pairs((a, b) in random_pair()) {
        let _g = shared();
        check_pair(&a, &b)?;
    }

    /// Near-ties: the filter must not decide wrongly when the enclosures
    /// nearly touch; the exact path must decide correctly when they overlap.
    #[test]
    fn filter_agrees_with_reference_on_near_ties((a, b) in near_tie_pair()) {
        let _g = shared();
        check_pair(&a, &b)?;
    }
}

proptest! {
    #![proptest_config(config(3000))]

    /// Exact ties built in different ways compare `Equal` (and hash equally).
    #[test]
    fn exact_ties_compare_equal((a, b) in exact_tie_pair()) {
        let _g = shared();
        let o = check_pair(&a, &b)?;
        prop_assert_eq!(o, Ordering::Equal, "construction is not a tie: {:?} {:?}", a, b);
    }
}

/// A pool of times mixing random values, ties and near-ties.
fn pool() -> impl Strategy<Value = Vec<Sample>> {
    (
        prop::collection::vec(any_sample(), 1..5),
        prop::collection::vec(exact_tie_pair(), 0..3),
        prop::collection::vec(near_tie_pair(), 0..3),
    )
        .prop_map(|(single, ties, near)| {
            let mut v = single;
            for (a, b) in ties.into_iter().chain(near) {
                v.push(a);
                v.push(b);
            }
            v
        })
}

proptest! {
    #![proptest_config(config(500))]

    /// `cmp` is a total order: antisymmetric, transitive on every triple,
    /// reflexive, consistent with `==` and `Hash`, and sorting by it agrees
    /// with the reference order.
    #[test]
    fn comparisons_are_a_total_order(mut v in pool()) {
        let _g = shared();
        let n = v.len();
        let ord: Vec<Vec<Ordering>> = v
            .iter()
            .map(|a| v.iter().map(|b| a.time.cmp(&b.time)).collect())
            .collect();
        for i in 0..n {
            prop_assert_eq!(ord[i][i], Ordering::Equal);
            for j in 0..n {
                prop_assert_eq!(ord[i][j], ord[j][i].reverse());
                prop_assert_eq!(ord[i][j], v[i].real.cmp(&v[j].real));
                prop_assert_eq!(v[i].time == v[j].time, ord[i][j] == Ordering::Equal);
                if ord[i][j] == Ordering::Equal {
                    prop_assert_eq!(hash_of(&v[i].time), hash_of(&v[j].time));
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    if ord[i][j] != Ordering::Greater && ord[j][k] != Ordering::Greater {
                        prop_assert!(ord[i][k] != Ordering::Greater, "not transitive: {} {} {}", i, j, k);
                        if ord[i][j] == Ordering::Less || ord[j][k] == Ordering::Less {
                            prop_assert_eq!(ord[i][k], Ordering::Less);
                        }
                    }
                }
            }
        }
        v.sort_by(|a, b| a.time.cmp(&b.time));
        for w in v.windows(2) {
            prop_assert!(w[0].real.cmp(&w[1].real) != Ordering::Greater, "{:?}", w);
        }
    }
}

// ---------------------------------------------------------------------------
// Polynomials: roots, signs, failure times.
// ---------------------------------------------------------------------------

/// Coefficients `[c0, c1, c2]` of every shape: zero, constants, linear,
/// quadratics with 0, 1 (double) or 2 roots, rational roots, near-double
/// roots, huge coefficients (beyond the filter's 1000-bit limit).
fn poly_coeffs() -> impl Strategy<Value = [Int; 3]> {
    prop_oneof![
        1 => Just([Int::ZERO, Int::ZERO, Int::ZERO]),
        1 => nonzero_int().prop_map(|c| [c, Int::ZERO, Int::ZERO]),
        3 => (mixed_int(), nonzero_int()).prop_map(|(c0, c1)| [c0, c1, Int::ZERO]),
        4 => (mixed_int(), mixed_int(), nonzero_int()).prop_map(|(c0, c1, c2)| [c0, c1, c2]),
        2 => (small_int(), small_int(), small_int()).prop_map(|(c0, c1, c2)| [c0, c1, c2]),
        // k (p t − q)²: a double root
        2 => (nonzero_int(), nonzero_int(), mixed_int()).prop_map(|(k, p, q)| {
            [&k * &q * &q, Int::from(-2) * &k * &p * &q, &k * &p * &p]
        }),
        // k (p1 t − q1)(p2 t − q2): a perfect-square discriminant
        2 => (nonzero_int(), nonzero_int(), mixed_int(), nonzero_int(), mixed_int())
            .prop_map(|(k, p1, q1, p2, q2)| {
                [&k * &q1 * &q2, -(&k * (&p1 * &q2 + &p2 * &q1)), &k * &p1 * &p2]
            }),
        // k (p t − q)² ± 1: two very close roots, or none
        2 => (nonzero_int(), nonzero_int(), mixed_int(), any::<bool>())
            .prop_map(|(k, p, q, up)| {
                let e = if up { Int::ONE } else { -Int::ONE };
                [&k * &q * &q + e, Int::from(-2) * &k * &p * &q, &k * &p * &p]
            }),
        // coefficients of more than 1000 bits
        1 => (big_int(200), big_int(200), big_int(200), 900usize..1100)
            .prop_map(|(c0, c1, c2, s)| {
                let c2 = if c2.is_zero() { Int::ONE } else { c2 };
                [c0 << s, c1 << (s / 2), c2]
            }),
    ]
}

/// The reference real roots of `c0 + c1 t + c2 t²`, increasing.
fn ref_roots(c: &[Int; 3]) -> Vec<Real> {
    if !c[2].is_zero() {
        let d = &c[1] * &c[1] - Int::from(4) * &c[2] * &c[0];
        match d.cmp(&Int::ZERO) {
            Ordering::Less => vec![],
            Ordering::Equal => vec![Real::quad_root(&c[2], &c[1], &c[0], false)],
            Ordering::Greater => vec![
                Real::quad_root(&c[2], &c[1], &c[0], false),
                Real::quad_root(&c[2], &c[1], &c[0], true),
            ],
        }
    } else if !c[1].is_zero() {
        vec![Real::rational(&Q::new(-c[0].clone(), c[1].clone()))]
    } else {
        vec![]
    }
}

fn poly_of(c: &[Int; 3]) -> Poly {
    Poly::new(c[0].clone(), c[1].clone(), c[2].clone())
}

fn time_of(q: &Q) -> Time {
    Time::from_rational(q.to_rational())
}

/// Everything about the roots of one polynomial: the kernel's roots match
/// the reference ones, and rational samples strictly inside each gap
/// between/around them.
struct RootLayout {
    /// Kernel roots.
    roots: Vec<Time>,
    /// Reference roots, same order.
    refs: Vec<Real>,
    /// `gaps[i]` is a rational strictly between root `i − 1` and root `i`
    /// (`gaps[0]` below every root, `gaps[n]` above every root).
    gaps: Vec<Q>,
}

/// Compute and validate the root layout of a polynomial.
fn layout(c: &[Int; 3]) -> Result<RootLayout, TestCaseError> {
    let p = poly_of(c);
    let roots = p.roots();
    let refs = ref_roots(c);
    prop_assert_eq!(roots.len(), refs.len(), "root count of {:?}", c);
    for (t, x) in roots.iter().zip(&refs) {
        // the reference root really is a root
        prop_assert_eq!(x.poly_at(c).sign(), Sign::Zero);
        // the kernel root is the reference root: bracket it
        for k in [40, 300] {
            let (lo, hi) = x.bounds(k);
            prop_assert!(
                time_of(&lo) <= *t && *t <= time_of(&hi),
                "root {:?} vs {:?}",
                t,
                x
            );
        }
        prop_assert_eq!(p.sign_at(t), Sign::Zero, "not a root: {:?} of {:?}", t, c);
    }
    for w in roots.windows(2) {
        prop_assert!(w[0] < w[1], "roots not increasing: {:?}", roots);
    }
    let mut gaps = Vec::with_capacity(refs.len() + 1);
    match (refs.first(), refs.last()) {
        (Some(first), Some(last)) => {
            gaps.push(first.bounds(8).0.add_int(-1));
            for (i, w) in roots.windows(2).enumerate() {
                let m = Q::from_rational(&w[0].rational_between(&w[1]));
                let mr = Real::rational(&m);
                prop_assert_eq!(refs[i].cmp(&mr), Ordering::Less);
                prop_assert_eq!(mr.cmp(&refs[i + 1]), Ordering::Less);
                gaps.push(m);
            }
            gaps.push(last.bounds(8).1.add_int(1));
        }
        _ => gaps.push(Q::int(Int::ZERO)),
    }
    Ok(RootLayout { roots, refs, gaps })
}

/// The sign the polynomial must have in each gap, from the root structure:
/// leading sign above every root, flipping across simple roots only.
fn expected_gap_signs(c: &[Int; 3], n_roots: usize) -> Vec<Sign> {
    use reference::int_sign;
    let deg = (0..3).rev().find(|&i| !c[i].is_zero());
    let lead = deg.map_or(Sign::Zero, |i| int_sign(&c[i]));
    let double = deg == Some(2) && n_roots == 1;
    let mut signs = vec![lead; n_roots + 1];
    for i in (0..n_roots).rev() {
        signs[i] = if double {
            signs[i + 1]
        } else {
            signs[i + 1].neg()
        };
    }
    signs
}

proptest! {
    #![proptest_config(config(2500))]

    /// `roots()` are exact, distinct, increasing roots; the sign between and
    /// around them follows the root structure and matches exact evaluation
    /// (`eval_rational` and a direct integer evaluation); `sign_after` and
    /// `sign_before` at each root match the sign in the adjacent gap.
    #[test]
    fn roots_are_exact_and_signs_follow_them(c in poly_coeffs(), extra in any_sample()) {
        let _g = shared();
        let p = poly_of(&c);
        let l = layout(&c)?;
        let expected = expected_gap_signs(&c, l.roots.len());
        for (g, want) in l.gaps.iter().zip(&expected) {
            let own = own_sign_at(&c, g);
            prop_assert_eq!(own, *want, "gap {:?} of {:?}", g, c);
            prop_assert_eq!(p.sign_at(&time_of(g)), own);
            prop_assert_eq!(p.eval_rational(&g.to_rational()).sign(), own);
        }
        for (i, t) in l.roots.iter().enumerate() {
            prop_assert_eq!(p.sign_before(t), expected[i], "before root {} of {:?}", i, c);
            prop_assert_eq!(p.sign_after(t), expected[i + 1], "after root {} of {:?}", i, c);
        }
        // Away from roots, sign_at/after/before agree with the reference.
        let want = extra.real.poly_at(&c).sign();
        prop_assert_eq!(p.sign_at(&extra.time), want, "at {:?}", extra);
        if want != Sign::Zero {
            prop_assert_eq!(p.sign_after(&extra.time), want);
            prop_assert_eq!(p.sign_before(&extra.time), want);
        }
        if let Some(q) = extra.real.as_rational() {
            prop_assert_eq!(p.eval_rational(&q.to_rational()).sign(), own_sign_at(&c, &q));
        }
    }

    /// The sign of one polynomial at the (irrational) roots of another, some
    /// of them shared (multiples) or nearly shared (perturbations), matches
    /// the reference.
    #[test]
    fn sign_at_foreign_roots_matches_reference(
        c in poly_coeffs(),
        other in poly_coeffs(),
        k in nonzero_int(),
        mode in 0usize..3,
    ) {
        let _g = shared();
        let d = match mode {
            0 => other,
            1 => [&k * &c[0], &k * &c[1], &k * &c[2]],
            _ => [&k * &c[0] + Int::ONE, &k * &c[1], &k * &c[2]],
        };
        let p = poly_of(&d);
        let roots = poly_of(&c).roots();
        let refs = ref_roots(&c);
        prop_assert_eq!(roots.len(), refs.len());
        for (t, x) in roots.iter().zip(&refs) {
            prop_assert_eq!(p.sign_at(t), x.poly_at(&d).sign(), "{:?} at {:?}", d, x);
        }
    }

    /// `first_failure_after(t)` is the first root after `t` where the sign
    /// just after is not positive, and `first_root_after(t)` the first root
    /// after `t`, by a brute-force scan over the reference roots with the
    /// signs of the gaps evaluated directly.
    #[test]
    fn first_failure_matches_brute_force(c in poly_coeffs(), extra in any_sample(), pick in any::<usize>()) {
        let _g = shared();
        let p = poly_of(&c);
        let l = layout(&c)?;
        // start times: every root, every gap sample, and a random time
        let mut starts: Vec<Sample> = l
            .roots
            .iter()
            .zip(&l.refs)
            .map(|(t, x)| Sample { real: x.clone(), time: t.clone() })
            .collect();
        starts.extend(l.gaps.iter().map(Sample::from_q));
        starts.push(extra);
        let s = &starts[pick % starts.len()];
        let after: Vec<usize> = (0..l.refs.len())
            .filter(|&j| l.refs[j].cmp(&s.real) == Ordering::Greater)
            .collect();
        let want_root = after.first().map(|&j| l.roots[j].clone());
        let want_fail = after
            .iter()
            .find(|&&j| own_sign_at(&c, &l.gaps[j + 1]) != Sign::Positive)
            .map(|&j| l.roots[j].clone());
        prop_assert_eq!(p.first_root_after(&s.time), want_root, "from {:?}", s);
        prop_assert_eq!(p.first_failure_after(&s.time), want_fail, "from {:?}", s);
    }
}

// ---------------------------------------------------------------------------
// rational_between, Rational conversions.
// ---------------------------------------------------------------------------

/// Check `rational_between` on an ordered pair.
fn check_between(a: &Sample, b: &Sample) -> Result<(), TestCaseError> {
    let (lo, hi) = match a.real.cmp(&b.real) {
        Ordering::Less => (a, b),
        Ordering::Greater => (b, a),
        Ordering::Equal => return Ok(()),
    };
    let m = Real::rational(&Q::from_rational(&lo.time.rational_between(&hi.time)));
    prop_assert_eq!(lo.real.cmp(&m), Ordering::Less, "{:?} {:?}", lo, hi);
    prop_assert_eq!(m.cmp(&hi.real), Ordering::Less, "{:?} {:?}", lo, hi);
    Ok(())
}

proptest! {
    #![proptest_config(config(2500))]

    /// `rational_between(a, b)` is strictly between, for random and nearly
    /// tied pairs and for pairs straddling zero.
    #[test]
    fn rational_between_is_strictly_between(
        (a, b) in prop_oneof![random_pair(), near_tie_pair()],
        mirror in any::<bool>(),
    ) {
        let _g = shared();
        check_between(&a, &b)?;
        if mirror {
            // −x < x: the midpoint of the enclosures is zero
            if let Some(q) = a.real.as_rational() {
                let neg = Sample::rational(-q.n.clone(), q.d.clone());
                check_between(&neg, &a)?;
            }
        }
    }

    /// Every finite double converts to the exact dyadic rational and back
    /// without loss, and the rational's enclosure contains it.
    #[test]
    fn from_f64_round_trips(
        x in prop_oneof![
            any_double(),
            (1u64..(1u64 << 52), any::<bool>())
                .prop_map(|(m, neg)| f64::from_bits(m | (u64::from(neg) << 63))),
            any::<u64>().prop_map(f64::from_bits).prop_filter("finite", |x| x.is_finite()),
        ]
    ) {
        let _g = shared();
        check_from_f64(x)?;
    }

    /// The enclosure of any rational contains it (huge, tiny and ordinary
    /// fractions), `Time::from_rational` keeps a containing enclosure, and
    /// `to_f64` is within a few units in the last place.
    #[test]
    fn rational_enclosures_contain_value(
        n in mixed_int(),
        d in nonzero_int(),
        shift in prop_oneof![Just(0i64), -1200i64..1200],
    ) {
        let _g = shared();
        let q = if shift >= 0 {
            Q::new(n << shift as usize, d)
        } else {
            Q::new(n, d << (-shift) as usize)
        };
        let r = q.to_rational();
        let real = Real::rational(&q);
        check_enclosure(&Sample { real: real.clone(), time: Time::from_rational(r.clone()) })?;
        check_rational_interval(&r, &real)?;
        let f = r.to_f64();
        if f.is_finite() && f.abs() >= f64::MIN_POSITIVE && f.abs() < f64::MAX / 16.0 {
            let mut lo = f;
            let mut hi = f;
            for _ in 0..4 {
                lo = next_down(lo);
                hi = next_up(hi);
            }
            let (lo, hi) = (Real::from_f64(lo).unwrap(), Real::from_f64(hi).unwrap());
            prop_assert!(lo.cmp(&real) == Ordering::Less && real.cmp(&hi) == Ordering::Less,
                "to_f64 {:e} far from {:?}", f, q);
        }
    }

    /// `Time::to_f64` of a root has a relative error far below 1e-12 (here:
    /// below 2^-43 ≈ 1.1e-13), whatever the scale of the coefficients.
    #[test]
    fn time_to_f64_is_accurate(s in root_sample()) {
        let _g = shared();
        check_time_to_f64(&s)?;
    }
}

/// `Rational::interval()` contains the value (exact comparison of the bounds).
fn check_rational_interval(r: &Rational, real: &Real) -> Result<(), TestCaseError> {
    let iv = r.interval();
    prop_assert!(iv.lo <= iv.hi);
    if let Some(lo) = Real::from_f64(iv.lo) {
        prop_assert!(lo.cmp(real) != Ordering::Greater, "{:?} not in {:?}", r, iv);
    }
    if let Some(hi) = Real::from_f64(iv.hi) {
        prop_assert!(hi.cmp(real) != Ordering::Less, "{:?} not in {:?}", r, iv);
    }
    Ok(())
}

/// A double converts exactly to a reduced dyadic rational and back.
fn check_from_f64(x: f64) -> Result<(), TestCaseError> {
    let r = Rational::from_f64(x).expect("finite");
    let q = Q::from_f64(x).unwrap();
    let real = Real::rational(&q);
    // same value, reduced, positive power-of-two denominator
    prop_assert!(
        Q::from_rational(&r).cmp(&q) == Ordering::Equal,
        "{:e} -> {:?}",
        x,
        r
    );
    prop_assert!(*r.denom() > Int::ZERO && r.is_dyadic());
    let two = Int::from(2);
    prop_assert!(
        *r.denom() == Int::ONE || (r.numer() % &two) != Int::ZERO,
        "not reduced"
    );
    let back = r.to_f64();
    if x == 0.0 {
        prop_assert_eq!(back, 0.0);
    } else {
        prop_assert_eq!(
            back.to_bits(),
            x.to_bits(),
            "{:e} -> {:?} -> {:e}",
            x,
            r,
            back
        );
    }
    check_rational_interval(&r, &real)?;
    // both constructors of a time from a double agree and enclose it
    let t = Time::from_f64(x).unwrap();
    prop_assert_eq!(t.interval().lo, x);
    prop_assert_eq!(t.interval().hi, x);
    let u = Time::from_rational(r);
    prop_assert_eq!(t.cmp(&u), Ordering::Equal);
    check_enclosure(&Sample { real, time: u })?;
    Ok(())
}

/// Relative accuracy of `Time::to_f64`, checked exactly.
fn check_time_to_f64(s: &Sample) -> Result<(), TestCaseError> {
    let f = s.time.to_f64();
    let mag = f.abs();
    if !(1e-280..=1e280).contains(&mag) {
        return Ok(());
    }
    let tol = Q::from_f64(mag * 2f64.powi(-43)).unwrap();
    let fq = Q::from_f64(f).unwrap();
    let lo = Real::rational(&fq.add(&Q::new(-tol.n.clone(), tol.d.clone())));
    let hi = Real::rational(&fq.add(&tol));
    prop_assert!(
        lo.cmp(&s.real) != Ordering::Greater && s.real.cmp(&hi) != Ordering::Greater,
        "to_f64 = {:e} of {:?}",
        f,
        s
    );
    Ok(())
}

/// Extreme and special doubles convert exactly.
#[test]
fn from_f64_extremes() {
    let _g = shared();
    let specials = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        f64::MAX,
        f64::MIN,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        next_down(f64::MIN_POSITIVE),
        f64::from_bits(1),
        -f64::from_bits(1),
        f64::from_bits((1 << 52) - 1),
        2f64.powi(-1022),
        2f64.powi(1023),
        f64::EPSILON,
        1.0 + f64::EPSILON,
        next_down(1.0),
        9007199254740993.0,
        next_down(f64::MAX),
    ];
    for x in specials {
        check_from_f64(x).unwrap();
    }
    assert!(Rational::from_f64(f64::NAN).is_none());
    assert!(Rational::from_f64(f64::INFINITY).is_none());
    assert!(Rational::from_f64(f64::NEG_INFINITY).is_none());
}

/// The reference itself: known values, orders and convergents.
#[test]
fn reference_sanity() {
    let i = Int::from;
    let sqrt2 = Real::quad_root(&i(1), &i(0), &i(-2), true);
    let sqrt8_half = Real::quad_root(&i(4), &i(0), &i(-8), true);
    let minus_sqrt2 = Real::quad_root(&i(-3), &i(0), &i(6), false);
    assert!(sqrt2.equals(&sqrt8_half));
    assert_eq!(sqrt2.cmp(&sqrt8_half), Ordering::Equal);
    assert_eq!(minus_sqrt2.cmp(&sqrt2), Ordering::Less);
    assert_eq!(minus_sqrt2.sign(), Sign::Negative);
    let c: Vec<(i64, i64)> = sqrt2
        .convergents(5)
        .iter()
        .map(|q| {
            (
                q.n.to_string().parse().unwrap(),
                q.d.to_string().parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(c, vec![(1, 1), (3, 2), (7, 5), (17, 12), (41, 29)]);
    // golden ratio (1 + √5)/2 = [1; 1, 1, ...]; its conjugate (1 − √5)/2 = [−1; 2, 1, 1, ...]
    let phi = Real::quad_root(&i(1), &i(-1), &i(-1), true);
    let last = phi.convergents(10).pop().unwrap();
    assert_eq!(
        (last.n.to_string(), last.d.to_string()),
        ("89".into(), "55".into())
    );
    let psi = Real::quad_root(&i(1), &i(-1), &i(-1), false);
    let c = psi.convergents(3);
    assert_eq!(c[0].cmp(&Q::int(i(-1))), Ordering::Equal);
    assert_eq!(c[1].cmp(&Q::new(i(-1), i(2))), Ordering::Equal);
    assert_eq!(c[2].cmp(&Q::new(i(-2), i(3))), Ordering::Equal);
    // rational roots and double roots normalise to rationals
    let two = Real::quad_root(&i(1), &i(-3), &i(2), true);
    assert_eq!(
        two.as_rational().unwrap().cmp(&Q::int(i(2))),
        Ordering::Equal
    );
    assert_eq!(
        reference::isqrt(&((Int::ONE << 400) - Int::ONE)),
        (Int::ONE << 200) - Int::ONE
    );
    assert_eq!(reference::isqrt(&(Int::ONE << 400)), Int::ONE << 200);
    assert_eq!(
        own_sign_at(&[i(-2), i(0), i(1)], &Q::new(i(3), i(2))),
        Sign::Positive
    );
}

// ---------------------------------------------------------------------------
// Regression tests for kernel bugs found by these properties.
// ---------------------------------------------------------------------------

/// `rational_between` of two times whose enclosures are symmetric around zero
/// (the double midpoint is 0): `simple_between` took `log2(0) = −∞` and
/// overflowed an `i32` subtraction (a panic in debug builds).
#[test]
fn rational_between_straddling_zero_does_not_overflow() {
    let _g = shared();
    let a = Time::from_f64(-1.0).unwrap();
    let b = Time::from_f64(1.0).unwrap();
    let m = Time::from_rational(a.rational_between(&b));
    assert!(a < m && m < b);
    let r = Time::from_rational(Rational::new(Int::from(-1), Int::from(3)));
    let s = Time::from_rational(Rational::new(Int::from(1), Int::from(3)));
    let m = Time::from_rational(r.rational_between(&s));
    assert!(r < m && m < s);
}

/// `Time::to_f64` of an irrational root much smaller than `1/a` (here the
/// root ≈ 2^-100 of t² + 2^100·t − 1) used a fixed absolute precision of
/// 2^-128 and was off by a relative 2e-9, breaking its documented accuracy.
#[test]
fn to_f64_of_tiny_root_is_accurate() {
    let _g = shared();
    let p = Poly::new(Int::from(-1), Int::ONE << 100, Int::ONE);
    let roots = p.roots();
    let s = Sample {
        real: Real::quad_root(&Int::ONE, &(Int::ONE << 100), &Int::from(-1), true),
        time: roots[1].clone(),
    };
    check_time_to_f64(&s).unwrap();
}

// ---------------------------------------------------------------------------
// Moving points: orient_poly against the static predicate.
// ---------------------------------------------------------------------------

/// A coordinate at realistic scales.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0..10.0f64,
        -1e6..1e6f64,
        (-1000i32..1000).prop_map(|k| 0.1234567 * f64::from(k)),
        (-8i32..8).prop_map(f64::from),
    ]
}

/// A small convex body: a random triangle (made counter-clockwise) or an
/// axis-aligned rectangle; `None` when degenerate.
fn body() -> impl Strategy<Value = Option<BodyPolygon>> {
    prop_oneof![
        prop::array::uniform3((coord(), coord())).prop_map(|v| {
            let v: Vec<[f64; 2]> = v.iter().map(|&(x, y)| [x * 1e-3, y * 1e-3]).collect();
            BodyPolygon::new(&v).ok().or_else(|| {
                let r: Vec<[f64; 2]> = v.iter().rev().copied().collect();
                BodyPolygon::new(&r).ok()
            })
        }),
        (coord(), coord(), 0.001..50.0f64, 0.001..50.0f64).prop_map(|(x, y, w, h)| {
            BodyPolygon::new(&[[x, y], [x + w, y], [x + w, y + h], [x, y + h]]).ok()
        }),
    ]
}

/// A body on a linear trajectory through a position at a reference time.
#[derive(Clone, Debug)]
struct Mover {
    body: BodyPolygon,
    traj: Trajectory,
}

fn mover() -> impl Strategy<Value = Option<Mover>> {
    (body(), coord(), coord(), coord(), coord(), -100.0..100.0f64).prop_map(
        |(b, px, py, vx, vy, t0)| {
            let body = b?;
            let t0 = Rational::from_f64(t0)?;
            let pos = Point::from_f64([px, py])?;
            let vel = Point::from_f64([vx * 1e-3, vy])?;
            Some(Mover {
                body,
                traj: Trajectory::through(&t0, &pos, vel),
            })
        },
    )
}

/// A rational instant: a double or a small fraction.
fn instant() -> impl Strategy<Value = Rational> {
    prop_oneof![
        (-200.0..200.0f64).prop_map(|x| Rational::from_f64(x).unwrap()),
        (-1000i64..1000, 1i64..1000).prop_map(|(p, q)| Rational::new(Int::from(p), Int::from(q))),
    ]
}

proptest! {
    #![proptest_config(config(1000))]

    /// `orient_poly` of three moving vertices has, at every rational
    /// instant, the sign of the static `orient` of their positions (both
    /// from `LinearPoint::at` and from `Trajectory::position_at` plus the
    /// body vertex), is of degree <= 1 when two of the points share a body,
    /// and vanishes (with `orient`) at its rational roots.
    #[test]
    fn orient_poly_agrees_with_static_orient(
        movers in prop::array::uniform3(mover()),
        picks in prop::array::uniform3((0usize..3, 0usize..4)),
        instants in prop::collection::vec(instant(), 1..6),
    ) {
        let _g = shared();
        prop_assume!(movers.iter().all(Option::is_some));
        let movers: Vec<Mover> = movers.into_iter().map(Option::unwrap).collect();
        let frames: Vec<Frame> = movers.iter().map(|m| Frame::new(&m.traj, &m.body)).collect();
        let pts: Vec<(usize, usize, LinearPoint)> = picks
            .iter()
            .map(|&(b, v)| {
                let v = v % movers[b].body.len();
                (b, v, frames[b].vertex(&movers[b].body, v))
            })
            .collect();
        let cert = orient_poly(&pts[0].2, &pts[1].2, &pts[2].2);
        let shared_body = pts[0].0 == pts[1].0 || pts[0].0 == pts[2].0 || pts[1].0 == pts[2].0;
        if shared_body {
            prop_assert!(cert.degree().is_none_or(|d| d <= 1), "degree {:?}", cert.degree());
        }
        let mut times = instants;
        times.extend(cert.roots().iter().filter_map(|r| r.as_rational().cloned()));
        for t in &times {
            let world = |k: usize| {
                let (b, v, _) = &pts[k];
                movers[*b].traj.position_at(t).add(&movers[*b].body.vertex(*v))
            };
            let (a, b, c) = (world(0), world(1), world(2));
            prop_assert_eq!(&pts[0].2.at(t), &a);
            prop_assert_eq!(&pts[1].2.at(t), &b);
            prop_assert_eq!(&pts[2].2.at(t), &c);
            let want = orient(&a, &b, &c);
            prop_assert_eq!(cert.sign_at(&Time::from_rational(t.clone())), want, "at {:?}", t);
            prop_assert_eq!(cert.eval_rational(t).sign(), want);
        }
        for r in cert.roots() {
            if let Some(t) = r.as_rational() {
                let pos: Vec<Point> = pts.iter().map(|p| p.2.at(t)).collect();
                prop_assert_eq!(orient(&pos[0], &pos[1], &pos[2]), Sign::Zero);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Filter efficiency.
// ---------------------------------------------------------------------------

/// On random, non-tied comparisons (doubles, fractions and quadratic roots
/// of mixed scales) the interval filter decides more than 90% of the time.
/// Runs alone (exclusive lock) so that the process-wide counters only see
/// its own comparisons.
#[test]
fn filter_decides_most_random_comparisons() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;

    let mut runner = TestRunner::deterministic();
    let strategy = any_sample();
    let samples: Vec<Sample> = (0..4000)
        .map(|_| strategy.new_tree(&mut runner).expect("sample").current())
        .collect();
    let pairs: Vec<(&Sample, &Sample)> = samples
        .chunks(2)
        .map(|c| (&c[0], &c[1]))
        .filter(|(a, b)| a.real.cmp(&b.real) != Ordering::Equal)
        .collect();
    let _g = STATS_LOCK.write().unwrap_or_else(|e| e.into_inner());
    reset_filter_stats();
    let results: Vec<Ordering> = pairs.iter().map(|(a, b)| a.time.cmp(&b.time)).collect();
    let stats = filter_stats();
    drop(_g);
    for ((a, b), got) in pairs.iter().zip(results) {
        assert_eq!(got, a.real.cmp(&b.real), "{a:?} vs {b:?}");
    }
    println!(
        "filter fraction on {} random non-tied comparisons: {:.4} ({} filtered, {} exact)",
        pairs.len(),
        stats.filter_fraction(),
        stats.filtered,
        stats.exact
    );
    assert_eq!(stats.filtered + stats.exact, pairs.len() as u64);
    assert!(stats.filter_fraction() > 0.9, "{stats:?}");

    // For contrast (not asserted): deliberate near-ties mostly need the
    // exact path, which is what the near-tie properties exercise.
    let near = near_tie_pair();
    let near: Vec<(Sample, Sample)> = (0..1000)
        .map(|_| near.new_tree(&mut runner).expect("pair").current())
        .collect();
    let _g = STATS_LOCK.write().unwrap_or_else(|e| e.into_inner());
    reset_filter_stats();
    for (a, b) in &near {
        std::hint::black_box(a.time.cmp(&b.time));
    }
    let stats = filter_stats();
    drop(_g);
    println!(
        "filter fraction on {} near-tie comparisons: {:.4} ({} filtered, {} exact)",
        near.len(),
        stats.filter_fraction(),
        stats.filtered,
        stats.exact
    );
}
