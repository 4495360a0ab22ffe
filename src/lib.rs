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
pub mod geometry;
pub mod timing;

// rooms in dependency order: each imports only the rooms above it in this list
pub mod mjcf;
pub mod urdf;
pub mod model;
pub mod state;
pub mod dynamics;
pub mod compile;
pub mod integrate;
pub mod collision;
pub mod constraint;
pub mod step;
pub mod batch;
pub mod sensors;
pub mod sensordata;
pub mod tasks;
pub mod render;
pub use step::data;

#[cfg(feature = "python")]
mod python;

pub use data::Data;
pub use error::{Error, Result};
pub use model::Model;
pub use step::state::State;
