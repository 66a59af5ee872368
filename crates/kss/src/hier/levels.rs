//! Levels of array indices and the dyadic `top` of a cyclic interval: pure
//! bit arithmetic on indices `0..M`, `M = 2^h` (design note §B.2).

/// The level of index `k` in an array of `2^h` entries: the number of
/// trailing zero bits of `k`, and `h` for `k = 0`.
///
/// Layer `ℓ` of the hierarchy keeps the indices of level `>= ℓ`, that is the
/// multiples of `2^ℓ`.
pub fn level(k: usize, h: u32) -> u32 {
    if k == 0 {
        h
    } else {
        k.trailing_zeros().min(h)
    }
}

/// Number of indices strictly inside the cyclic interval from `i` to `j`
/// (going up from `i`, wrapping modulo `M = 2^h`), plus one: `(j − i) mod M`,
/// and `M` when `i == j` (the interval is then the whole cycle but `i`).
pub fn gap(i: usize, j: usize, h: u32) -> usize {
    let m = 1usize << h;
    match (j + m - i) & (m - 1) {
        0 => m,
        d => d,
    }
}

/// The index of maximum level strictly inside the cyclic interval `(i, j)`
/// of an array of `M = 2^h` entries; `None` if the interval is empty
/// (`j == i + 1 mod M`).
///
/// The interval runs up from `i` to `j`, wrapping modulo `M`; for `i == j` it
/// is the whole cycle except `i`. The index is unique: two indices of equal
/// maximum level `ℓ` would have a multiple of `2^(ℓ+1)` between them.
///
/// Computed in `O(1)`: unwrap to `lo = i`, `hi = i + gap − 1` (so that
/// `lo < hi` are plain integers below `2M`), let `d` be the highest bit in
/// which `lo` and `hi` differ; the answer keeps the common prefix above `d`,
/// has bit `d` set and every lower bit clear (that is `hi` with the bits
/// below `d` cleared), reduced modulo `M`. It is `> lo` and `<= hi`, and no
/// number in `(lo, hi]` has more trailing zeros. Unwrapping does not change
/// levels: the only multiple of `M` in `(lo, lo + M)` is `M` itself, whose
/// residue `0` has level `h`, and `x` and `x − M` have equal trailing zeros
/// for `M < x < 2M`.
pub fn top(i: usize, j: usize, h: u32) -> Option<usize> {
    let m = 1usize << h;
    debug_assert!(i < m && j < m);
    let g = gap(i, j, h);
    if g < 2 {
        return None;
    }
    let lo = i;
    let hi = i + g - 1;
    let d = usize::BITS - 1 - (lo ^ hi).leading_zeros();
    Some((hi & !((1usize << d) - 1)) & (m - 1))
}

/// Whether the cyclic interval from `i` to `j` is a dyadic block: its gap
/// (see [`gap`]) is a power of two `2^ℓ` and `i` is a multiple of it, so the
/// interval is `[a·2^ℓ, (a+1)·2^ℓ]` (the last block of a layer ends at
/// `M ≡ 0`). Dyadic blocks are exactly the intervals between consecutive
/// kept indices of some layer.
pub fn is_dyadic(i: usize, j: usize, h: u32) -> bool {
    let g = gap(i, j, h);
    g.is_power_of_two() && i % g == 0
}

/// The sibling merge that exactly undoes a pop: `k` may leave the exposed
/// set between its neighbours `p` and `s` iff `[p, k]` and `[k, s]` are the
/// two halves of one dyadic block `[p, s]` (then `k == top(p, s)`, but the
/// converse fails: `top(2, 8) == 4` while `[2, 8]` is not dyadic).
pub fn is_sibling_merge(p: usize, k: usize, s: usize, h: u32) -> bool {
    if p == k || k == s || p == s {
        return false;
    }
    // p ≠ s: the two gaps add up to gap(p, s) < M
    gap(p, k, h) == gap(k, s, h) && is_dyadic(p, s, h)
}
