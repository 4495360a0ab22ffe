//! ③ Per-world scratch: everything a step derives, allocated once per model so that stepping
//! never allocates.

use crate::model::Model;
use crate::step::aba::AbaData;
use crate::step::integrate::Rk4Scratch;
use crate::step::kinematics::KinData;

/// Derived quantities and scratch of one world.
#[derive(Clone, Debug, Default)]
pub struct Data {
    /// Stage 1 output.
    pub kin: KinData,
    /// ABA inward-pass quantities and spatial accelerations.
    pub aba: AbaData,
    /// Total applied generalised force (nv): actuators + passive.
    pub qfrc_applied: Vec<f64>,
    /// Joint accelerations of the last evaluation (nv).
    pub qacc: Vec<f64>,
    /// RK4 stage buffers.
    pub rk4: Rk4Scratch,
}

impl Data {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        Data {
            kin: KinData::new(m),
            aba: AbaData::new(m),
            qfrc_applied: vec![0.0; m.nv],
            qacc: vec![0.0; m.nv],
            rk4: Rk4Scratch::new(m),
        }
    }
}
