//! sinew: articulated-body simulation after Kokkevis, *Practical Physics for Articulated
//! Characters* (GDC 2004), on Featherstone's articulated-body algorithm.
//!
//! Data flow, in module order:
//! MJCF text → [`mjcf::parse`] → [`mjcf::ModelSpec`] → [`Model`] (compiled, immutable) →
//! [`Data`] + qpos/qvel/ctrl (one world) → [`step::step`]: kinematics → ABA → collision →
//! constraint rows → impact (rebounding contacts) and acceleration LCPs → integration →
//! post-stabilisation.
#![warn(missing_docs)]
// index loops follow the papers' notation (row j, column k, dof i) across several arrays at once
#![allow(clippy::needless_range_loop)]

pub mod error;
pub mod math;

// ① description
pub mod mjcf;
// ② compiled model
pub mod model;
// ③ state and scratch (a world's per-stage scratch lives with the step: `step::data`)
pub use step::data;
pub mod state;
// ④ the step
pub mod step;
// ⑤ many worlds, and what environments observe of them
pub mod batch;
pub mod sensors;
pub mod tasks;
// ⑥ pictures
pub mod render;
// reference algorithms, used as checks
pub mod dynamics;

#[cfg(feature = "python")]
mod python;

pub use data::Data;
pub use error::{Error, Result};
pub use model::Model;
pub use state::State;
