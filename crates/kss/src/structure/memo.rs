//! A memo of the exact turns of one instant.
//!
//! At an event instant the failing certificate's three points are collinear,
//! and the operations that follow (normalization, the validity of the faces
//! around them, the junctions' failure times) ask for the same few
//! orientations "just after" (or "just before") that instant many times
//! over; where the f64 filter cannot decide them each one is an exact
//! evaluation with big integers. This memo keeps the exact answers of the
//! current instant, and the signs *at* the instant that an exact failure
//! time computed on the way (a collision response asks whether the
//! contact's turn is zero there right after scheduling it).
//!
//! An entry is keyed by what the three points *are*, not by their names:
//! each point is its body's [`Frame`] (a new one at every motion change,
//! held by the memo so that its address cannot be reused) and its
//! body-frame point (a real vertex, or the approximation vertex
//! `av(i, k)` of the hierarchy's static edge array). A pop, a merge or a
//! flight-plan change therefore never finds a stale entry: the points it
//! changes have other keys. The memo is emptied when the instant changes
//! (any instant that is not provably the same one).

use std::cell::RefCell;
use std::collections::HashMap;

/// A map with the fast fixed hasher (keys are addresses and small ids).
type FastMap<K, V> = HashMap<K, V, foldhash::fast::FixedState>;
use std::sync::Arc;

use crate::motion::Frame;
use crate::num::{Sign, Time};

/// What a point is: its frame (by address) and its body-frame point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct PointKey {
    frame: usize,
    /// `u32::MAX` for a real vertex, else the approximation vertex's `i`.
    i: u32,
    /// The real vertex, or the approximation vertex's `k`.
    k: u32,
}

impl PointKey {
    /// The key of real vertex `v` of the body moving by `frame`.
    pub(crate) fn real(frame: &Arc<Frame>, v: usize) -> PointKey {
        PointKey {
            frame: Arc::as_ptr(frame) as usize,
            i: u32::MAX,
            k: v as u32,
        }
    }

    /// The key of the approximation vertex `av(i, k)` of the body moving by
    /// `frame`.
    pub(crate) fn approx(frame: &Arc<Frame>, i: usize, k: usize) -> PointKey {
        PointKey {
            frame: Arc::as_ptr(frame) as usize,
            i: i as u32,
            k: k as u32,
        }
    }
}

#[derive(Default)]
struct Memo {
    at: Option<Time>,
    /// The frames of the keys by address (held, so that no address is
    /// reused meanwhile).
    frames: FastMap<usize, Arc<Frame>>,
    /// Sorted triple, and just before ([`BEFORE`]), just after
    /// ([`AFTER`]) or at ([`AT`]) the instant: the sign of the sorted
    /// triple's orientation.
    signs: FastMap<([PointKey; 3], u8), Sign>,
}

/// Just before the memo's instant (a key's side).
const BEFORE: u8 = 0;
/// Just after the memo's instant.
const AFTER: u8 = 1;
/// At the memo's instant itself.
const AT: u8 = 2;

/// The side of a sign just after (`after`) or before the instant.
fn side(after: bool) -> u8 {
    if after {
        AFTER
    } else {
        BEFORE
    }
}

thread_local! {
    static MEMO: RefCell<Memo> = RefCell::new(Memo::default());
}

/// Whether `a` and `b` are certainly the same instant, cheaply (`false`
/// may also mean "could not tell cheaply").
fn same_instant(a: &Time, b: &Time) -> bool {
    let (x, y) = (a.interval(), b.interval());
    if x.hi < y.lo || y.hi < x.lo {
        return false;
    }
    a.is_known_same(b) || a.same_representation(b)
}

/// `keys` sorted, and whether sorting them was an odd permutation (which
/// flips the orientation).
fn sorted(keys: [PointKey; 3]) -> ([PointKey; 3], bool) {
    let mut k = keys;
    let mut odd = false;
    for (x, y) in [(0, 1), (1, 2), (0, 1)] {
        if k[y] < k[x] {
            k.swap(x, y);
            odd = !odd;
        }
    }
    (k, odd)
}

/// The sign of the orientation of the points `keys` just after (`after`)
/// or before time `t`, if the memo knows it.
pub(crate) fn peek(keys: [PointKey; 3], t: &Time, after: bool) -> Option<Sign> {
    let (k, odd) = sorted(keys);
    let s = MEMO.with(|m| {
        let m = m.borrow();
        if !m.at.as_ref().is_some_and(|at| same_instant(at, t)) {
            return None;
        }
        m.signs.get(&(k, side(after))).copied()
    })?;
    Some(if odd { s.neg() } else { s })
}

/// The sign of the orientation of the points `keys` at time `t` itself,
/// if the memo knows it.
pub(crate) fn peek_at(keys: [PointKey; 3], t: &Time) -> Option<Sign> {
    let (k, odd) = sorted(keys);
    let s = MEMO.with(|m| {
        let m = m.borrow();
        if !m.at.as_ref().is_some_and(|at| same_instant(at, t)) {
            return None;
        }
        m.signs.get(&(k, AT)).copied()
    })?;
    Some(if odd { s.neg() } else { s })
}

/// Remember `s`, the sign of the orientation of the points `keys` (with
/// frames `frames`) just after (`after`) or before time `t`, computed
/// exactly.
pub(crate) fn record(
    keys: [PointKey; 3],
    frames: [&Arc<Frame>; 3],
    t: &Time,
    after: bool,
    s: Sign,
) {
    let (k, odd) = sorted(keys);
    let s = if odd { s.neg() } else { s };
    with_instant(frames, t, |m| {
        m.signs.insert((k, side(after)), s);
    });
}

/// Remember `s`, the sign of the orientation of the points `keys` (with
/// frames `frames`) at time `t` itself, computed exactly.
pub(crate) fn record_at(keys: [PointKey; 3], frames: [&Arc<Frame>; 3], t: &Time, s: Sign) {
    let (k, odd) = sorted(keys);
    let s = if odd { s.neg() } else { s };
    with_instant(frames, t, |m| {
        m.signs.insert((k, AT), s);
    });
}

/// `f` on the memo of instant `t` (emptied first if it held another
/// instant), with `frames` held.
fn with_instant(frames: [&Arc<Frame>; 3], t: &Time, f: impl FnOnce(&mut Memo)) {
    MEMO.with(|m| {
        let mut m = m.borrow_mut();
        if !m.at.as_ref().is_some_and(|at| same_instant(at, t)) {
            m.at = Some(t.clone());
            m.frames.clear();
            m.signs.clear();
        }
        for fr in frames {
            m.frames
                .entry(Arc::as_ptr(fr) as usize)
                .or_insert_with(|| fr.clone());
        }
        f(&mut m);
    });
}

/// The sign of the orientation of the points `keys` (with frames `frames`)
/// just after (`after`) or before time `t`, from the memo or from
/// `compute` (which is then remembered).
pub(crate) fn turn(
    keys: [PointKey; 3],
    frames: [&Arc<Frame>; 3],
    t: &Time,
    after: bool,
    compute: impl FnOnce() -> Sign,
) -> Sign {
    if let Some(s) = peek(keys, t, after) {
        super::counters::bump(super::counters::Counter::TurnsMemo);
        return s;
    }
    super::counters::bump(super::counters::Counter::TurnsExact);
    let s = compute();
    record(keys, frames, t, after, s);
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{BodyPolygon, Point};
    use crate::motion::Trajectory;
    use crate::num::Rational;

    fn frame() -> Arc<Frame> {
        let body = BodyPolygon::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        let r = |x: f64| Rational::from_f64(x).unwrap();
        let traj = Trajectory::through(
            &r(0.0),
            &Point {
                x: r(0.0),
                y: r(0.0),
            },
            Point {
                x: r(1.0),
                y: r(0.5),
            },
        );
        Arc::new(Frame::new(&traj, &body))
    }

    fn unused() -> Sign {
        panic!("the memo should have answered")
    }

    #[test]
    fn a_permuted_triple_is_answered_with_the_permutation_sign() {
        let f = frame();
        let t = Time::from_f64(0.25).unwrap();
        let [a, b, c] = [0, 1, 2].map(|v| PointKey::real(&f, v));
        let fs = [&f, &f, &f];
        assert_eq!(
            turn([a, b, c], fs, &t, true, || Sign::Positive),
            Sign::Positive
        );
        // even permutations keep the sign, odd ones flip it
        assert_eq!(turn([b, c, a], fs, &t, true, unused), Sign::Positive);
        assert_eq!(turn([c, a, b], fs, &t, true, unused), Sign::Positive);
        assert_eq!(turn([b, a, c], fs, &t, true, unused), Sign::Negative);
        assert_eq!(turn([a, c, b], fs, &t, true, unused), Sign::Negative);
        assert_eq!(turn([c, b, a], fs, &t, true, unused), Sign::Negative);
        // just before the instant is another question
        assert_eq!(turn([a, b, c], fs, &t, false, || Sign::Zero), Sign::Zero);
        assert_eq!(turn([c, b, a], fs, &t, false, unused), Sign::Zero);
    }

    #[test]
    fn another_instant_or_another_frame_is_computed_again() {
        let (f, g) = (frame(), frame());
        let t = Time::from_f64(0.5).unwrap();
        let [a, b, c] = [0, 1, 2].map(|v| PointKey::real(&f, v));
        let fs = [&f, &f, &f];
        assert_eq!(
            turn([a, b, c], fs, &t, true, || Sign::Positive),
            Sign::Positive
        );
        // the same points moving by another frame (a motion change)
        let c2 = PointKey::real(&g, 2);
        assert_eq!(
            turn([a, b, c2], [&f, &f, &g], &t, true, || Sign::Negative),
            Sign::Negative
        );
        // the same triple at another instant
        let u = Time::from_f64(0.75).unwrap();
        assert_eq!(
            turn([a, b, c], fs, &u, true, || Sign::Negative),
            Sign::Negative
        );
        // and back at the first instant: the memo was emptied
        assert_eq!(turn([a, b, c], fs, &t, true, || Sign::Zero), Sign::Zero);
    }

    #[test]
    fn a_recorded_sign_is_peeked_at_its_instant_only() {
        let f = frame();
        let t = Time::from_f64(0.125).unwrap();
        let [a, b, c] = [0, 1, 2].map(|v| PointKey::real(&f, v));
        record([a, b, c], [&f, &f, &f], &t, true, Sign::Negative);
        assert_eq!(peek([c, a, b], &t, true), Some(Sign::Negative));
        assert_eq!(peek([a, c, b], &t, true), Some(Sign::Positive));
        // not before the instant, and not at another instant
        assert_eq!(peek([a, b, c], &t, false), None);
        assert_eq!(peek([a, b, c], &Time::from_f64(0.375).unwrap(), true), None);
        // a turn of the instant is answered from the record
        assert_eq!(
            turn([b, c, a], [&f, &f, &f], &t, true, unused),
            Sign::Negative
        );
    }

    #[test]
    fn a_sign_at_the_instant_is_its_own_question() {
        let f = frame();
        let t = Time::from_f64(0.625).unwrap();
        let [a, b, c] = [0, 1, 2].map(|v| PointKey::real(&f, v));
        record_at([a, b, c], [&f, &f, &f], &t, Sign::Positive);
        assert_eq!(peek_at([b, c, a], &t), Some(Sign::Positive));
        assert_eq!(peek_at([b, a, c], &t), Some(Sign::Negative));
        // neither just after nor just before, nor at another instant
        assert_eq!(peek([a, b, c], &t, true), None);
        assert_eq!(peek([a, b, c], &t, false), None);
        assert_eq!(peek_at([a, b, c], &Time::from_f64(0.875).unwrap()), None);
        // and a record at another instant empties it
        record(
            [a, b, c],
            [&f, &f, &f],
            &Time::from_f64(0.75).unwrap(),
            true,
            Sign::Zero,
        );
        assert_eq!(peek_at([a, b, c], &t), None);
    }

    #[test]
    fn an_approximation_vertex_is_not_the_real_vertex_of_the_same_id() {
        let f = frame();
        assert_ne!(PointKey::real(&f, 3), PointKey::approx(&f, 2, 3));
        assert_ne!(PointKey::approx(&f, 1, 3), PointKey::approx(&f, 2, 3));
    }
}
