//! The integrable state of one world, for Rust users and tests (the Python layer keeps the same
//! arrays in NumPy and steps them in place).

use crate::step::data::Data;
use crate::model::Model;
use crate::state::WorldState;

/// qpos, qvel, act, ctrl and time of one world, with its scratch.
#[derive(Clone, Debug)]
pub struct State {
    /// Positions (nq).
    pub qpos: Vec<f64>,
    /// Velocities (nv).
    pub qvel: Vec<f64>,
    /// Controls (nu).
    pub ctrl: Vec<f64>,
    /// Actuator activations (na).
    pub act: Vec<f64>,
    /// Simulated time (s).
    pub time: f64,
    /// Derived quantities of the last evaluation.
    pub data: Data,
}

impl State {
    /// The reference state qpos0, zero velocity and control.
    pub fn new(m: &Model) -> Self {
        State { qpos: m.qpos0.clone(), qvel: vec![0.0; m.nv], ctrl: vec![0.0; m.nu], act: vec![0.0; m.na], time: 0.0, data: Data::new(m) }
    }

    /// The state borrowed as one value, beside the world's scratch.
    pub fn split(&mut self) -> (WorldState<'_>, &mut Data) {
        (WorldState { time: &mut self.time, qpos: &mut self.qpos, qvel: &mut self.qvel, ctrl: &self.ctrl, act: &mut self.act }, &mut self.data)
    }

    /// One step.
    pub fn step(&mut self, m: &Model) {
        let (mut s, data) = self.split();
        crate::step::step(m, data, &mut s);
    }

    /// Accelerations at the current state without advancing (writes `data`).
    pub fn forward(&mut self, m: &Model) -> &[f64] {
        let (s, data) = self.split();
        crate::step::forward(m, data, &s);
        &self.data.dynamics.qacc
    }
}

/// A world's state as one flat array, as `Sim.get_state` and `Batch.get_state` give it:
/// [time, qpos (nq), qvel (nv), act (na), ctrl (nu)], MuJoCo's integration state, then for a full state the
/// trajectory feed-forward (2 nu) and the history the next step reads ([`crate::constraint::History`]).
pub struct FlatState<'a> {
    /// Simulated time.
    pub time: f64,
    /// Positions.
    pub qpos: &'a [f64],
    /// Velocities.
    pub qvel: &'a [f64],
    /// Activations.
    pub act: &'a [f64],
    /// Controls.
    pub ctrl: &'a [f64],
    /// Feed-forward and history of a full state.
    pub full: Option<(&'a [f64], crate::constraint::History)>,
}

impl<'a> FlatState<'a> {
    /// Appends the state of a world (with its feed-forward and history: the full state) to `out`.
    pub fn write(time: f64, (qpos, qvel, act): (&[f64], &[f64], &[f64]), ctrl: &[f64], full: Option<(&[f64], &crate::constraint::History)>, out: &mut Vec<f64>) {
        out.push(time);
        out.extend_from_slice(qpos);
        out.extend_from_slice(qvel);
        out.extend_from_slice(act);
        out.extend_from_slice(ctrl);
        if let Some((feedforward, history)) = full {
            out.extend_from_slice(feedforward);
            history.to_flat(out);
        }
    }

    /// Reads a flat state of `m`, checking its length and every number (finite time, qpos, qvel
    /// act and ctrl within the divergence bound; a valid history).
    pub fn read(m: &Model, v: &'a [f64]) -> crate::error::Result<FlatState<'a>> {
        let (nq, nv, na, nu) = (m.nq, m.nv, m.na, m.nu);
        let short = 1 + nq + nv + na + nu;
        let len = v.len();
        if len != short && len < short + 2 * nu + crate::constraint::history::FLAT_HISTORY_MIN {
            return Err(crate::error::Error::Input(format!(
                "state: expected shape [{short}] (time, qpos, qvel, act, ctrl) or a full state from get_state(full=True), got length {len}"
            )));
        }
        if let Some(i) = v[..short].iter().position(|&x| crate::math::out_of_range(x)) {
            return Err(crate::error::Error::Input(format!("state: element {i} is {} (must be finite, within ±{:e})", v[i], crate::math::MAX_STATE)));
        }
        let full = if len == short {
            None
        } else {
            let ff = &v[short..short + 2 * nu];
            if let Some(i) = ff.iter().position(|x| !x.is_finite()) {
                return Err(crate::error::Error::Input(format!("state: feed-forward element {i} is {} (must be finite)", ff[i])));
            }
            Some((ff, crate::constraint::History::from_flat(&v[short + 2 * nu..], m.ngeom, m.nv)?))
        };
        let (q, a) = (1 + nq, 1 + nq + nv);
        Ok(FlatState { time: v[0], qpos: &v[1..q], qvel: &v[q..a], act: &v[a..a + na], ctrl: &v[a + na..short], full })
    }

    /// The feed-forward and history the state gives a world (a short state: none, and a new
    /// world's history).
    pub fn kept(&self) -> (Option<&'a [f64]>, crate::constraint::History) {
        match &self.full {
            Some((ff, history)) => (Some(*ff), history.clone()),
            None => (None, crate::constraint::History::new()),
        }
    }
}
