//! Reference algorithms that are not on the hot path: test oracles and diagnostics.

pub mod crba;
pub mod rnea;
