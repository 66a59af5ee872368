//! geom (in progress)
