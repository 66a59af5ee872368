//! The per-polygon implicit hierarchy of outer approximations (design note
//! §B.1–B.2; Kirkpatrick & Speckmann §3): pure static geometry, no kinetics.
//!
//! - [`EdgeArray`]: the polygon's boundary as `M = 2^h` supporting lines in
//!   counter-clockwise order: the `n` real edges, in order, with zero-length
//!   entries (lines through one vertex) inserted at vertices with a large
//!   exterior angle and as padding, so that consecutive normals turn by at
//!   most about `2π/max(n, 5)` and always by less than `π/2`.
//! - [`levels`]: `level(k)` (trailing zeros, `level(0) = h`) and
//!   `top(i, j)`, the index of maximum level strictly inside a cyclic
//!   interval, in `O(1)` bit arithmetic.
//! - [`Exposed`]: the exposed set `S` of one polygon, a sorted set of
//!   indices with cyclic successor/predecessor, rank and select.
//! - Approximation vertices [`EdgeArray::av`], [`EdgeArray::av_is_real`],
//!   the initial set [`EdgeArray::coarsest`], [`EdgeArray::pop`],
//!   [`EdgeArray::merge`], and the audits [`EdgeArray::check`] and
//!   [`EdgeArray::check_exposed`].
//!
//! # Conventions
//!
//! - Lines are `nx·x + ny·y <= c` on the body polygon's integer grid
//!   ([`crate::geom::BodyPolygon::int_vertex`], units `2^exp`); points are
//!   [`HomPoint`]s `(X, Y, W)`, `W > 0`, on the same grid.
//! - **Approximate polygon** of an exposed set `S`: `P̃ = ∩_{k ∈ S}` half-plane
//!   of `L_k`. It contains the polygon `P`.
//! - **Vertex ids**: the vertex of `P̃` *with id `k`* (`k ∈ S`) is
//!   `av(pred_S(k), k)`, the start of `P̃`'s edge on `L_k` (counter-clockwise).
//!   With `S` = every index and no zero-length entry (`M = n`), vertex id `k`
//!   is polygon vertex `k`, so the plain structure is the case `S` = all.
//!   A vertex is *real* when it is a base vertex ([`EdgeArray::av_is_real`]);
//!   two ids can name the same real vertex when a zero-length entry is exposed
//!   (`P̃` then has a zero-length edge there).
//! - A **gap** of `S` is a pair `(i, j)` of cyclically consecutive elements.
//!   `S` is valid ([`EdgeArray::check_exposed`]) iff every gap is a dyadic
//!   block `[a·2^ℓ, (a+1)·2^ℓ]` turning by an angle in `(0, π/2)`.
//!   [`EdgeArray::pop`] splits a gap at its `top` (its midpoint),
//!   [`EdgeArray::merge`] joins two sibling gaps.
//!
//! # Exactness
//!
//! No `f64` decides anything here. The only floating-point computations
//! choose how many zero-length entries a vertex gets and in which directions
//! (then checked exactly, with an exact fallback); those choices affect
//! constants, never correctness.

mod array;
mod exposed;
pub mod levels;

pub use array::{EdgeArray, HomPoint};

/// A broken invariant of a polygon's hierarchy, found by its checks.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct HierarchyError(pub String);
pub use exposed::Exposed;

#[cfg(test)]
mod tests;
