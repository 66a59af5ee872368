//! The exact event time: a rational, or an irrational root of an integer
//! quadratic, with a filtered exact total order.
//!
//! Every certificate function under piecewise-linear translation is a
//! polynomial of degree at most two in `t`, so every event time is of the form
//! `(-b ± √d) / 2a` with integers `a, b, d`. A [`Time`] carries an outward
//! rounded f64 enclosure; comparisons whose enclosures are disjoint are
//! decided by it, the others by exact integer arithmetic
//! ([`super::sign_a_plus_b_sqrt_plus_c_sqrt`]).

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, OnceLock};

use dashu_base::{Gcd, SquareRoot};

use super::{count_exact, count_filtered, Int, Interval, Rational};

/// An exact point in time.
///
/// A time may be *deferred* ([`Time::deferred`]): it is known by a rigorous
/// enclosure and a way to compute it exactly, and the exact form is computed
/// the first time something needs it (a comparison the enclosures cannot
/// decide, a sign at this instant, its rational value). Most certificate
/// failure times are replaced before they come due, so most are never
/// computed exactly. Deferral changes no answer, only when work is done.
#[derive(Clone)]
pub struct Time {
    kind: Kind,
    iv: Interval,
}

#[derive(Clone)]
enum Kind {
    Rat(Rational),
    /// The root `(-b + s·√d) / 2a` of the primitive irreducible `a t² + b t + c`
    /// with `a > 0`, `d = b² − 4ac > 0` not a square; `s = +1` if `plus`.
    /// (Boxed: a time is 72 bytes instead of 120, and most times are
    /// rational or deferred.)
    Root(Box<QuadRoot>),
    /// Computed on first use; the computed time is never itself deferred.
    Deferred(Arc<dyn Force>),
}

/// The exact computation behind a deferred [`Time`].
pub trait ExactTime: Send + Sync + 'static {
    /// The exact time. It must lie in the enclosure the deferred time was
    /// made with.
    fn exact(&self) -> Time;

    /// Whether the exact time is known to be rational without computing
    /// it (`false`: not known).
    fn known_rational(&self) -> bool {
        false
    }
}

trait Force: Send + Sync {
    fn force(&self) -> &Time;
    fn pending(&self) -> bool;
    fn known_rational(&self) -> bool;
    fn source(&self) -> &dyn std::any::Any;
}

struct Once<S> {
    src: S,
    cell: OnceLock<Time>,
    iv: Interval,
}

impl<S: ExactTime> Force for Once<S> {
    fn force(&self) -> &Time {
        self.cell.get_or_init(|| {
            let t = self.src.exact().resolved().clone();
            assert!(
                t.iv.overlaps(&self.iv),
                "a deferred time's exact value {t:?} is outside its enclosure [{:e}, {:e}]",
                self.iv.lo,
                self.iv.hi
            );
            // in debug builds (the test suite), containment checked exactly
            #[cfg(debug_assertions)]
            for (end, below) in [(self.iv.lo, true), (self.iv.hi, false)] {
                if let Some(e) = Time::from_f64(end) {
                    assert!(
                        if below { e <= t } else { t <= e },
                        "a deferred time's exact value {t:?} is outside its enclosure [{:e}, {:e}]",
                        self.iv.lo,
                        self.iv.hi
                    );
                }
            }
            t
        })
    }

    fn pending(&self) -> bool {
        self.cell.get().is_none()
    }

    fn known_rational(&self) -> bool {
        match self.cell.get() {
            Some(t) => matches!(t.kind, Kind::Rat(_)),
            None => self.src.known_rational(),
        }
    }

    fn source(&self) -> &dyn std::any::Any {
        &self.src
    }
}

#[derive(Clone, PartialEq, Eq, Hash)]
pub(crate) struct QuadRoot {
    pub(crate) a: Int,
    pub(crate) b: Int,
    pub(crate) c: Int,
    pub(crate) d: Int,
    pub(crate) plus: bool,
}

impl QuadRoot {
    fn s(&self, x: &Int) -> Int {
        if self.plus {
            x.clone()
        } else {
            -x.clone()
        }
    }

    /// Rational bounds `(lo, hi)` on the root with `√d` known to `k` bits.
    fn bounds(&self, k: usize) -> (Rational, Rational) {
        let s = (&self.d << (2 * k)).unsigned_abs_owned().sqrt();
        let s = Int::from(s);
        let base = -(&self.b << k);
        let den = (&self.a << (k + 1)).clone();
        let (lo, hi) = if self.plus {
            (&base + &s, &base + &s + Int::ONE)
        } else {
            (&base - &s - Int::ONE, &base - &s)
        };
        (Rational::new(lo, den.clone()), Rational::new(hi, den))
    }

    fn enclosure(&self) -> Interval {
        // Fast path: interval arithmetic with the stable formula.
        let a = Interval::of_int(&self.a);
        let b = Interval::of_int(&self.b);
        let c = Interval::of_int(&self.c);
        let d = Interval::of_int(&self.d);
        if a.is_finite() && b.is_finite() && c.is_finite() && d.is_finite() {
            let sq = d.sqrt();
            let two = Interval::point(2.0);
            // q = -(b + sign(b)·√d)/2 has no cancellation; roots are q/a and c/q.
            let b_nonneg = self.b >= Int::ZERO;
            let q = if b_nonneg {
                -(b + sq) / two
            } else {
                (sq - b) / two
            };
            // For b >= 0, q/a is the smaller root (the minus one); for b < 0, the larger.
            let iv = if self.plus != b_nonneg { q / a } else { c / q };
            if iv.is_finite() && iv.width() <= iv.lo.abs().max(iv.hi.abs()) * 1e-14 {
                return iv;
            }
        }
        // Exact refinement with integer square roots.
        let mut k = 64usize;
        loop {
            let (lo, hi) = self.bounds(k);
            let iv = lo.interval().hull(&hi.interval());
            let mag = iv.lo.abs().max(iv.hi.abs());
            if (iv.is_finite() && iv.width() <= mag * 1e-15) || k > 4096 {
                return iv;
            }
            k *= 2;
        }
    }
}

trait OwnedAbs {
    fn unsigned_abs_owned(&self) -> dashu_int::UBig;
}

impl OwnedAbs for Int {
    fn unsigned_abs_owned(&self) -> dashu_int::UBig {
        use dashu_base::UnsignedAbs;
        self.clone().unsigned_abs()
    }
}

impl Time {
    /// Time zero.
    pub fn zero() -> Time {
        Time::from_rational(Rational::zero())
    }

    /// An exact rational time.
    pub fn from_rational(r: Rational) -> Time {
        let iv = exact_point(&r).unwrap_or_else(|| r.interval());
        Time {
            kind: Kind::Rat(r),
            iv,
        }
    }

    /// The exact value of a finite double; `None` for NaN or infinities.
    pub fn from_f64(x: f64) -> Option<Time> {
        let r = Rational::from_f64(x)?;
        Some(Time {
            kind: Kind::Rat(r),
            iv: Interval::point(x),
        })
    }

    /// The root `(-b + s·√d)/2a` of `a t² + b t + c` (`a != 0`, discriminant
    /// `d = b² − 4ac >= 0`), the larger one if `larger`. Returns a rational
    /// time when the root is rational.
    pub(crate) fn quadratic_root(a: &Int, b: &Int, c: &Int, larger: bool) -> Time {
        let (mut a, mut b, mut c) = (a.clone(), b.clone(), c.clone());
        assert!(!a.is_zero(), "quadratic_root of a linear polynomial");
        let mut larger = larger;
        if a < Int::ZERO {
            a = -a;
            b = -b;
            c = -c;
            // negating the polynomial keeps its roots; the order of the two
            // roots is by value, so `larger` is unchanged.
            let _ = &mut larger;
        }
        let g = Int::from((&a).gcd(&b));
        let g = Int::from((&g).gcd(&c));
        if g > Int::ONE {
            a /= &g;
            b /= &g;
            c /= &g;
        }
        let d = &b * &b - Int::from(4) * &a * &c;
        assert!(
            d >= Int::ZERO,
            "quadratic_root with a negative discriminant"
        );
        let sq = Int::from(d.unsigned_abs_owned().sqrt());
        if &sq * &sq == d {
            let num = if larger { -&b + &sq } else { -&b - &sq };
            return Time::from_rational(Rational::new(num, Int::from(2) * &a));
        }
        let root = QuadRoot {
            a,
            b,
            c,
            d,
            plus: larger,
        };
        let iv = root.enclosure();
        Time {
            kind: Kind::Root(Box::new(root)),
            iv,
        }
    }

    /// A deferred time: `iv` must be a rigorous enclosure of `src.exact()`,
    /// which is computed (once) when first needed.
    pub fn deferred<S: ExactTime>(iv: Interval, src: S) -> Time {
        Time {
            kind: Kind::Deferred(Arc::new(Once {
                src,
                cell: OnceLock::new(),
                iv,
            })),
            iv,
        }
    }

    /// The exact computation behind a deferred time, if this is one made
    /// with a computation of type `S` (computed yet or not).
    pub(crate) fn deferred_source<S: ExactTime>(&self) -> Option<&S> {
        match &self.kind {
            Kind::Deferred(f) => f.source().downcast_ref::<S>(),
            _ => None,
        }
    }

    /// Whether this is a deferred time whose exact form is not computed yet
    /// (for tests and statistics).
    pub fn is_pending(&self) -> bool {
        match &self.kind {
            Kind::Deferred(f) => f.pending(),
            _ => false,
        }
    }

    /// The exact form: `self` unless deferred, else the computed time.
    fn resolved(&self) -> &Time {
        match &self.kind {
            Kind::Deferred(f) => f.force(),
            _ => self,
        }
    }

    /// Whether `self` and `other` are the same instant by their exact
    /// representations (rationals are reduced and irrational roots carry
    /// their primitive minimal polynomial, so equal times have equal
    /// representations). Forces deferred times.
    /// Whether `self` and `other` are certainly the same instant without
    /// computing a deferred time: one deferred computation shared by both
    /// (a clone), or two computed times with the same representation.
    /// `false` may also mean "could not tell cheaply".
    pub(crate) fn is_known_same(&self, other: &Time) -> bool {
        match (&self.kind, &other.kind) {
            (Kind::Deferred(x), Kind::Deferred(y)) => Arc::ptr_eq(x, y),
            (Kind::Deferred(_), _) | (_, Kind::Deferred(_)) => {
                !self.is_pending() && !other.is_pending() && self.same_representation(other)
            }
            _ => self.same_representation(other),
        }
    }

    pub(crate) fn same_representation(&self, other: &Time) -> bool {
        match (&self.resolved().kind, &other.resolved().kind) {
            (Kind::Rat(x), Kind::Rat(y)) => x == y,
            (Kind::Root(x), Kind::Root(y)) => x == y,
            _ => false,
        }
    }

    /// Whether this time is known to be rational without computing a
    /// deferred time (a deferred one whose computation says so, see
    /// [`ExactTime::known_rational`]); `false` may also mean "could not
    /// tell cheaply".
    pub fn known_rational(&self) -> bool {
        match &self.kind {
            Kind::Rat(_) => true,
            Kind::Root(_) => false,
            Kind::Deferred(f) => f.known_rational(),
        }
    }

    /// The rational value, if this time is rational.
    pub fn as_rational(&self) -> Option<&Rational> {
        match &self.resolved().kind {
            Kind::Rat(r) => Some(r),
            _ => None,
        }
    }

    pub(crate) fn as_root(&self) -> Option<&QuadRoot> {
        match &self.resolved().kind {
            Kind::Root(q) => Some(q),
            _ => None,
        }
    }

    /// A rigorous f64 enclosure of this time.
    pub fn interval(&self) -> Interval {
        self.iv
    }

    /// The time as a double, within a relative error far below 1e-12 (for
    /// display and output only).
    pub fn to_f64(&self) -> f64 {
        match &self.resolved().kind {
            Kind::Deferred(_) => unreachable!("resolved"),
            Kind::Rat(r) => r.to_f64(),
            Kind::Root(q) => {
                // `bounds(k)` is tight to 2^-k/(2a) in absolute terms, which is
                // not enough for roots much smaller than that: refine until the
                // bounds agree to a relative 2^-48 (or convert to the same
                // double, e.g. below the normal range).
                let mut k = 128;
                loop {
                    let (lo, hi) = q.bounds(k);
                    let (l, h) = (lo.to_f64(), hi.to_f64());
                    let tol = l.abs().min(h.abs()) * 2f64.powi(-48);
                    if l == h || (l.signum() == h.signum() && h - l <= tol) || k > 1 << 16 {
                        return l;
                    }
                    k *= 2;
                }
            }
        }
    }

    /// Rational lower and upper bounds, at least as tight as `2^-k` in
    /// absolute terms (exact for rational times).
    fn bounds(&self, k: usize) -> (Rational, Rational) {
        match &self.resolved().kind {
            Kind::Rat(r) => (r.clone(), r.clone()),
            Kind::Root(q) => q.bounds(k),
            Kind::Deferred(_) => unreachable!("resolved"),
        }
    }

    /// A rational strictly between `self` and `later`; panics unless
    /// `self < later` (a bug in the caller). Used to audit a structure at an
    /// instant where no certificate is degenerate.
    pub fn rational_between(&self, later: &Time) -> Rational {
        assert!(self < later, "rational_between needs self < later");
        // Try a short double between the enclosures first.
        if self.iv.hi < later.iv.lo {
            if let Some(r) = simple_between(self.iv.hi, later.iv.lo).and_then(Rational::from_f64) {
                let t = Time::from_rational(r.clone());
                if *self < t && t < *later {
                    return r;
                }
            }
        }
        let mut k = 64;
        loop {
            let (_, a_hi) = self.bounds(k);
            let (b_lo, _) = later.bounds(k);
            if a_hi < b_lo {
                let m = a_hi.midpoint(&b_lo);
                // strictly inside because a <= a_hi < m < b_lo <= b
                return m;
            }
            if let (Some(a), Some(b)) = (self.as_rational(), later.as_rational()) {
                return a.midpoint(b);
            }
            k *= 2;
        }
    }

    fn exact_cmp(&self, other: &Time) -> Ordering {
        match (&self.resolved().kind, &other.resolved().kind) {
            (Kind::Deferred(_), _) | (_, Kind::Deferred(_)) => unreachable!("resolved"),
            (Kind::Rat(x), Kind::Rat(y)) => x.cmp(y),
            (Kind::Root(x), Kind::Rat(r)) => root_cmp_rational(x, r),
            (Kind::Rat(r), Kind::Root(x)) => root_cmp_rational(x, r).reverse(),
            (Kind::Root(x), Kind::Root(y)) => {
                if x == y {
                    return Ordering::Equal;
                }
                // x1 − x2 = [a2(−b1 + s1√d1) − a1(−b2 + s2√d2)] / (2 a1 a2)
                let a = &x.a * &y.b - &y.a * &x.b;
                let b = x.s(&y.a);
                let c = -y.s(&x.a);
                super::sign_a_plus_b_sqrt_plus_c_sqrt(&a, &b, &x.d, &c, &y.d).to_ordering()
            }
        }
    }
}

/// Sign of `x − p/q` for an irrational quadratic root `x`.
fn root_cmp_rational(x: &QuadRoot, r: &Rational) -> Ordering {
    // x − p/q = (−b q − 2 a p + s q √d) / (2 a q)
    let p = r.numer();
    let q = r.denom();
    let a = -(&x.b * q) - Int::from(2) * &x.a * p;
    let b = x.s(q);
    super::sign_a_plus_b_sqrt(&a, &b, &x.d).to_ordering()
}

/// The double `x` exactly equal to `r`, as a point interval, if there is one.
fn exact_point(r: &Rational) -> Option<Interval> {
    if !r.is_dyadic() {
        return None;
    }
    let x = r.to_f64();
    if !x.is_finite() {
        return None;
    }
    let back = Rational::from_f64(x)?;
    (back == *r).then(|| Interval::point(x))
}

/// A double with few significant bits strictly between `lo < hi`, if any.
fn simple_between(lo: f64, hi: f64) -> Option<f64> {
    if lo >= hi || !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    let mid = lo * 0.5 + hi * 0.5;
    if !(lo < mid && mid < hi) {
        return None;
    }
    if mid == 0.0 {
        // Zero is the simplest double (and `log2(0)` below would overflow).
        return Some(0.0);
    }
    // Round the midpoint to as few bits as stay strictly inside.
    let mut best = mid;
    for bits in (1..=52).rev() {
        let scale = 2f64.powi(bits - mid.abs().log2().floor() as i32);
        if !scale.is_finite() || scale == 0.0 {
            continue;
        }
        let cand = (mid * scale).round() / scale;
        if lo < cand && cand < hi {
            best = cand;
        } else {
            break;
        }
    }
    Some(best)
}

impl PartialEq for Time {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Time {}

impl Hash for Time {
    fn hash<H: Hasher>(&self, state: &mut H) {
        // Rationals are reduced and irrational roots carry their primitive
        // minimal polynomial, so equal times have equal representations.
        match &self.resolved().kind {
            Kind::Rat(r) => {
                0u8.hash(state);
                r.hash(state);
            }
            Kind::Root(q) => {
                1u8.hash(state);
                q.hash(state);
            }
            Kind::Deferred(_) => unreachable!("resolved"),
        }
    }
}

impl PartialOrd for Time {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Time {
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (&self.iv, &other.iv);
        if a.hi < b.lo {
            count_filtered();
            return Ordering::Less;
        }
        if b.hi < a.lo {
            count_filtered();
            return Ordering::Greater;
        }
        if a.lo == a.hi && b.lo == b.hi && a.lo == b.lo {
            // Point enclosures are only given to times that equal that double.
            if matches!(self.kind, Kind::Rat(_)) && matches!(other.kind, Kind::Rat(_)) {
                count_filtered();
                return Ordering::Equal;
            }
        }
        count_exact();
        self.exact_cmp(other)
    }
}

impl fmt::Debug for Time {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.resolved().kind {
            Kind::Deferred(_) => unreachable!("resolved"),
            Kind::Rat(r) => write!(f, "Time({r:?})"),
            Kind::Root(q) => write!(
                f,
                "Time(root{} of {}t²+{}t+{} ≈{:e})",
                if q.plus { "+" } else { "-" },
                q.a,
                q.b,
                q.c,
                self.to_f64()
            ),
        }
    }
}

impl fmt::Display for Time {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.to_f64())
    }
}

impl From<Rational> for Time {
    fn from(r: Rational) -> Time {
        Time::from_rational(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn int(x: i64) -> Int {
        Int::from(x)
    }

    /// A deferred time computed by a closure, with a claim on whether it
    /// is rational.
    struct Claim(bool, fn() -> Time);

    impl ExactTime for Claim {
        fn exact(&self) -> Time {
            (self.1)()
        }
        fn known_rational(&self) -> bool {
            self.0
        }
    }

    #[test]
    fn a_time_known_rational_is_known_without_computing_it() {
        let half = || Time::from_f64(0.5).unwrap();
        let root = || Time::quadratic_root(&int(1), &int(0), &int(-2), true);
        let near = |x: f64| Interval {
            lo: x.next_down(),
            hi: x.next_up(),
        };
        // the computation's claim answers while the time is pending
        let t = Time::deferred(near(0.5), Claim(true, half));
        assert!(t.known_rational() && t.is_pending());
        // no claim: not known until computed, then what it is
        let t = Time::deferred(near(0.5), Claim(false, half));
        assert!(!t.known_rational());
        assert!(t.as_rational().is_some() && t.known_rational());
        let s = Time::deferred(near(std::f64::consts::SQRT_2), Claim(false, root));
        assert!(s.as_rational().is_none() && !s.known_rational());
        // exact times answer for themselves
        assert!(half().known_rational() && !root().known_rational());
    }

    #[test]
    fn roots_and_order() {
        // t² − 2 = 0: ±√2
        let p = Time::quadratic_root(&int(1), &int(0), &int(-2), true);
        let m = Time::quadratic_root(&int(1), &int(0), &int(-2), false);
        assert!(m < p);
        assert!((p.to_f64() - 2f64.sqrt()).abs() < 1e-15);
        // the double nearest to √2 lies just above it
        let s2 = std::f64::consts::SQRT_2;
        assert!(p < Time::from_f64(s2).unwrap());
        assert!(p > Time::from_f64(s2.next_down()).unwrap());
        // 2t² − 4 = 0 is the same root: equal, same hash
        let p2 = Time::quadratic_root(&int(-2), &int(0), &int(4), true);
        assert_eq!(p, p2);
        // perfect square discriminant: rational
        let r = Time::quadratic_root(&int(1), &int(-3), &int(2), true);
        assert_eq!(r.as_rational(), Some(&Rational::from_int(int(2))));
        // sqrt(2) vs sqrt(8)/2
        let q = Time::quadratic_root(&int(4), &int(0), &int(-8), true);
        assert_eq!(p, q);
    }

    #[test]
    fn between() {
        let a = Time::from_f64(1.0).unwrap();
        let b = Time::from_f64(1.0f64.next_up()).unwrap();
        let m = Time::from_rational(a.rational_between(&b));
        assert!(a < m && m < b);
        let p = Time::quadratic_root(&int(1), &int(0), &int(-2), true);
        let r = Time::from_rational(Rational::new(int(1414213562373095), int(1000000000000000)));
        assert!(r < p);
        let m = Time::from_rational(r.rational_between(&p));
        assert!(r < m && m < p);
        assert!(p > Time::zero());
    }
}
