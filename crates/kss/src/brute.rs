//! brute (in progress)
