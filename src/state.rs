//! A world's state as one value: MuJoCo's integration state (time, qpos, qvel, act, ctrl), borrowed
//! from wherever it is kept (a `Sim`'s arrays, a batch's rows, an owned [`crate::State`]).

use crate::math::out_of_range;

/// One world's state for one call: the step advances `time`, `qpos`, `qvel` and `act` and holds
/// `ctrl` over the step.
#[derive(Debug)]
pub struct WorldState<'a> {
    /// Simulated time (s).
    pub time: &'a mut f64,
    /// Positions (nq).
    pub qpos: &'a mut [f64],
    /// Velocities (nv).
    pub qvel: &'a mut [f64],
    /// Controls (nu).
    pub ctrl: &'a [f64],
    /// Actuator activations (na).
    pub act: &'a mut [f64],
}

impl WorldState<'_> {
    /// The same state, borrowed again for a shorter call.
    pub fn reborrow(&mut self) -> WorldState<'_> {
        WorldState { time: &mut *self.time, qpos: &mut *self.qpos, qvel: &mut *self.qvel, ctrl: self.ctrl, act: &mut *self.act }
    }

    /// The first entry of time, qpos or qvel that is non-finite or beyond [`crate::math::MAX_STATE`]:
    /// (array name, index, value).
    pub fn bad_entry(&self) -> Option<(&'static str, usize, f64)> {
        for (name, v) in [("qpos", &*self.qpos), ("qvel", &*self.qvel), ("act", &*self.act)] {
            if let Some(i) = v.iter().position(|&x| out_of_range(x)) {
                return Some((name, i, v[i]));
            }
        }
        out_of_range(*self.time).then_some(("time", 0, *self.time))
    }
}
