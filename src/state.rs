//! ③ The integrable state of one world, for Rust users and tests (the Python layer keeps the same
//! arrays in NumPy and steps them in place).

use crate::data::Data;
use crate::model::Model;

/// qpos, qvel, ctrl and time of one world, with its scratch.
#[derive(Clone, Debug)]
pub struct State {
    /// Positions (nq).
    pub qpos: Vec<f64>,
    /// Velocities (nv).
    pub qvel: Vec<f64>,
    /// Controls (nu).
    pub ctrl: Vec<f64>,
    /// Simulated time (s).
    pub time: f64,
    /// Derived quantities of the last evaluation.
    pub data: Data,
}

impl State {
    /// The reference state qpos0, zero velocity and control.
    pub fn new(m: &Model) -> Self {
        State { qpos: m.qpos0.clone(), qvel: vec![0.0; m.nv], ctrl: vec![0.0; m.nu], time: 0.0, data: Data::new(m) }
    }

    /// One step.
    pub fn step(&mut self, m: &Model) {
        crate::step::step(m, &mut self.data, &mut self.qpos, &mut self.qvel, &self.ctrl, &mut self.time);
    }

    /// Accelerations at the current state without advancing (writes `data`).
    pub fn forward(&mut self, m: &Model) -> &[f64] {
        crate::step::forward(m, &mut self.data, &self.qpos, &self.qvel, &self.ctrl);
        &self.data.qacc
    }
}
