//! The exposed set of one polygon: a sorted set of array indices `0..M`.
//!
//! Representation: a 64-ary bitset tree plus a Fenwick tree over word counts.
//!
//! - `bits[0]` has one bit per index; word `w` of `bits[l + 1]` has bit `b`
//!   set iff word `64·w + b` of `bits[l]` is non-zero. The top level is a
//!   single word. `contains` reads one bit; `succ`/`pred` climb until a word
//!   has a set bit on the wanted side and descend along the lowest (highest)
//!   set bits: `O(log_64 M)` word operations (at most 4 for `M <= 2^24`).
//! - `fen` is a Fenwick tree over the population counts of the `M/64` words
//!   of `bits[0]`: `rank` is a prefix sum plus one masked popcount, `select`
//!   a Fenwick descent plus a select inside one word, both `O(log M)`.
//!
//! `insert`/`remove` touch one bit per level and `O(log M)` Fenwick cells.
//! Memory is about `M/8 + M/16` bytes (bits and 32-bit counts per word),
//! so a whole-array set costs far less than the edge array itself.

/// A sorted set of indices in `0..M` with cyclic successor and predecessor,
/// rank and select (see the module documentation for the representation).
#[derive(Clone, Debug)]
pub struct Exposed {
    m: usize,
    len: usize,
    bits: Vec<Vec<u64>>,
    fen: Vec<u32>,
    /// [`Exposed::version`].
    version: u64,
    /// [`Exposed::last_removal`].
    removal: u64,
}

impl PartialEq for Exposed {
    fn eq(&self, other: &Exposed) -> bool {
        // (the version names contents, it is not one of them)
        self.m == other.m && self.len == other.len && self.bits == other.bits
    }
}

impl Eq for Exposed {}

/// The next [`Exposed::version`].
static NEXT_VERSION: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn fresh_version() -> u64 {
    NEXT_VERSION.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl Exposed {
    /// The empty set over indices `0..m`.
    pub fn new(m: usize) -> Exposed {
        assert!(m >= 1, "an exposed set needs a non-empty index range");
        let mut bits = Vec::new();
        let mut width = m;
        loop {
            let words = width.div_ceil(64);
            bits.push(vec![0u64; words]);
            if words == 1 {
                break;
            }
            width = words;
        }
        let words0 = bits[0].len();
        Exposed {
            m,
            len: 0,
            bits,
            fen: vec![0; words0 + 1],
            version: fresh_version(),
            removal: fresh_version(),
        }
    }

    /// A number that names the current contents among every set made in
    /// this process (never 0): every insertion or removal that changes the
    /// set gives it a new one, and a clone keeps it (its contents are the
    /// same). Caches key on it.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// A number that names the last removal from the set (or its making),
    /// never shared with another set unless by a clone: while it stays the
    /// same, the set has only gained elements. For an approximation
    /// (intersection of the exposed lines' half-planes) that means it only
    /// shrank, so a box computed for it earlier still holds it.
    pub fn last_removal(&self) -> u64 {
        self.removal
    }

    /// The set of every index in `0..m`.
    pub fn full(m: usize) -> Exposed {
        Exposed::from_indices(m, 0..m)
    }

    /// The set of the given indices (each `< m`; repeats are ignored).
    pub fn from_indices(m: usize, indices: impl IntoIterator<Item = usize>) -> Exposed {
        let mut s = Exposed::new(m);
        for k in indices {
            s.insert(k);
        }
        s
    }

    /// The size `M` of the index range.
    pub fn universe(&self) -> usize {
        self.m
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether `k` is in the set (`false` for `k >= M`).
    pub fn contains(&self, k: usize) -> bool {
        k < self.m && self.bits[0][k >> 6] >> (k & 63) & 1 == 1
    }

    /// Insert `k < M`; `false` if it was already there.
    pub fn insert(&mut self, k: usize) -> bool {
        assert!(k < self.m, "index {k} out of range 0..{}", self.m);
        if self.contains(k) {
            return false;
        }
        let mut pos = k;
        for level in self.bits.iter_mut() {
            let (w, b) = (pos >> 6, pos & 63);
            let was_zero = level[w] == 0;
            level[w] |= 1 << b;
            if !was_zero {
                break;
            }
            pos = w;
        }
        self.fen_add(k >> 6, 1);
        self.len += 1;
        self.version = fresh_version();
        true
    }

    /// Remove `k`; `false` if it was not there.
    pub fn remove(&mut self, k: usize) -> bool {
        if !self.contains(k) {
            return false;
        }
        let mut pos = k;
        for level in self.bits.iter_mut() {
            let (w, b) = (pos >> 6, pos & 63);
            level[w] &= !(1 << b);
            if level[w] != 0 {
                break;
            }
            pos = w;
        }
        self.fen_add(k >> 6, -1);
        self.len -= 1;
        self.version = fresh_version();
        self.removal = fresh_version();
        true
    }

    /// The smallest element `>= k`, if any.
    pub fn next_at_or_after(&self, k: usize) -> Option<usize> {
        if k >= self.m {
            return None;
        }
        let mut level = 0;
        let mut pos = k;
        loop {
            let (w, b) = (pos >> 6, pos & 63);
            let words = &self.bits[level];
            if w >= words.len() {
                return None;
            }
            let word = words[w] & (!0u64 << b);
            if word != 0 {
                pos = (w << 6) | word.trailing_zeros() as usize;
                break;
            }
            if level + 1 == self.bits.len() {
                return None;
            }
            pos = w + 1;
            level += 1;
        }
        while level > 0 {
            level -= 1;
            pos = (pos << 6) | self.bits[level][pos].trailing_zeros() as usize;
        }
        Some(pos)
    }

    /// The largest element `<= k`, if any (`k >= M` counts as `M − 1`).
    #[inline]
    pub fn prev_at_or_before(&self, k: usize) -> Option<usize> {
        // (the word of `k` and the two before it first, on the bottom
        // level: where an approximation's ids lie close, its predecessor
        // is there, without the climb up the summary levels and back)
        let pos = k.min(self.m - 1);
        let words = &self.bits[0];
        let mut w = pos >> 6;
        let word = words[w] & (!0u64 >> (63 - (pos & 63)));
        if word != 0 {
            return Some((w << 6) | (63 - word.leading_zeros() as usize));
        }
        for _ in 0..2 {
            if w == 0 {
                return None;
            }
            w -= 1;
            if words[w] != 0 {
                return Some((w << 6) | (63 - words[w].leading_zeros() as usize));
            }
        }
        if w == 0 {
            return None;
        }
        self.prev_climbing((w << 6) - 1)
    }

    /// [`Exposed::prev_at_or_before`] of `k < M` through the summary levels.
    fn prev_climbing(&self, k: usize) -> Option<usize> {
        let mut level = 0;
        let mut pos = k;
        loop {
            let (w, b) = (pos >> 6, pos & 63);
            let mask = if b == 63 {
                !0u64
            } else {
                (1u64 << (b + 1)) - 1
            };
            let word = self.bits[level][w] & mask;
            if word != 0 {
                pos = (w << 6) | (63 - word.leading_zeros() as usize);
                break;
            }
            if w == 0 || level + 1 == self.bits.len() {
                return None;
            }
            pos = w - 1;
            level += 1;
        }
        while level > 0 {
            level -= 1;
            pos = (pos << 6) | (63 - self.bits[level][pos].leading_zeros() as usize);
        }
        Some(pos)
    }

    /// The next element after `k` cyclically: the smallest element `> k`,
    /// else the smallest element. `k` itself when it is the only element;
    /// `None` only for the empty set. `k` need not be in the set.
    pub fn succ(&self, k: usize) -> Option<usize> {
        self.next_at_or_after(k + 1)
            .or_else(|| self.next_at_or_after(0))
    }

    /// The element before `k` cyclically: the largest element `< k`, else
    /// the largest element. `k` itself when it is the only element; `None`
    /// only for the empty set. `k` need not be in the set.
    pub fn pred(&self, k: usize) -> Option<usize> {
        let below = if k == 0 {
            None
        } else {
            self.prev_at_or_before(k - 1)
        };
        below.or_else(|| self.prev_at_or_before(self.m - 1))
    }

    /// The number of elements `< k` (`k <= M`).
    pub fn rank(&self, k: usize) -> usize {
        if k >= self.m {
            return self.len;
        }
        let (w, b) = (k >> 6, k & 63);
        let low = self.bits[0][w] & ((1u64 << b) - 1);
        self.fen_prefix(w) + low.count_ones() as usize
    }

    /// The `r`-th smallest element (from 0), if `r < len`.
    pub fn select(&self, r: usize) -> Option<usize> {
        if r >= self.len {
            return None;
        }
        // Fenwick descent: the largest word count prefix `w` with sum <= r.
        let words = self.fen.len() - 1;
        let mut w = 0usize;
        let mut rest = r;
        let mut step = if words == 0 {
            0
        } else {
            1usize << (usize::BITS - 1 - words.leading_zeros())
        };
        while step > 0 {
            let next = w + step;
            if next <= words && (self.fen[next] as usize) <= rest {
                w = next;
                rest -= self.fen[next] as usize;
            }
            step >>= 1;
        }
        // words 0..w hold `r − rest` elements; the answer is in word w
        Some((w << 6) | select_in_word(self.bits[0][w], rest))
    }

    /// The elements in increasing order.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        let mut next = self.next_at_or_after(0);
        std::iter::from_fn(move || {
            let k = next?;
            next = self.next_at_or_after(k + 1);
            Some(k)
        })
    }

    fn fen_add(&mut self, word: usize, delta: i32) {
        let mut i = word + 1;
        while i < self.fen.len() {
            self.fen[i] = (self.fen[i] as i64 + delta as i64) as u32;
            i += i & i.wrapping_neg();
        }
    }

    /// Sum of the counts of words `0..word`.
    fn fen_prefix(&self, word: usize) -> usize {
        let mut i = word;
        let mut s = 0usize;
        while i > 0 {
            s += self.fen[i] as usize;
            i &= i - 1;
        }
        s
    }
}

/// The position of the `r`-th lowest set bit of `w` (`r < popcount(w)`), by
/// halving the window six times.
fn select_in_word(w: u64, mut r: usize) -> usize {
    let mut pos = 0usize;
    let mut width = 32usize;
    while width > 0 {
        let low = (w >> pos) & ((1u64 << width) - 1);
        let c = low.count_ones() as usize;
        if r >= c {
            r -= c;
            pos += width;
        }
        width >>= 1;
    }
    pos
}

#[cfg(test)]
mod tests {
    use super::Exposed;

    #[test]
    fn only_a_removal_changes_the_last_removal() {
        let mut s = Exposed::from_indices(100, [3, 40, 77]);
        let r0 = s.last_removal();
        assert_ne!(Exposed::from_indices(100, [3, 40, 77]).last_removal(), r0);
        s.insert(50);
        s.insert(3);
        assert_eq!(s.last_removal(), r0);
        assert_eq!(s.clone().last_removal(), r0);
        assert!(!s.remove(4));
        assert_eq!(s.last_removal(), r0);
        assert!(s.remove(50));
        let r1 = s.last_removal();
        assert_ne!(r1, r0);
        s.insert(50);
        assert_eq!(s.last_removal(), r1);
    }

    #[test]
    fn every_change_gives_a_new_version_and_a_clone_keeps_it() {
        let mut s = Exposed::from_indices(100, [3, 40, 77]);
        let v0 = s.version();
        assert_ne!(v0, 0);
        let copy = s.clone();
        assert_eq!(copy.version(), v0);
        // no change, no new version
        assert!(!s.insert(40));
        assert!(!s.remove(41));
        assert_eq!(s.version(), v0);
        assert!(s.insert(41));
        let v1 = s.version();
        assert_ne!(v1, v0);
        assert!(s.remove(41));
        // the same contents again, under a version never seen before
        assert_eq!(s, copy);
        assert!(s.version() != v0 && s.version() != v1);
        // another set never shares a version
        assert_ne!(Exposed::from_indices(100, [3, 40, 77]).version(), v0);
    }
}
