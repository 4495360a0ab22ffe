//! Actuator activations (MuJoCo's `act`): their rates act˙ from ctrl and act, and their advance
//! over a step — an integrator's and a filter's by the rate, an exact filter's by its exact
//! solution, each clamped to its `actrange` when limited (MuJoCo's `mj_advance`).

use crate::model::{ActuatorDyn, Model};

/// The activations' rates (na) at controls `ctrl` (clamped to ctrlrange when limited) and
/// activations `act`.
pub fn rates(m: &Model, ctrl: &[f64], act: &[f64], act_dot: &mut [f64]) {
    for a in 0..m.nu {
        let Some(i) = m.actuator_actadr[a] else { continue };
        let u = if m.actuator_ctrllimited[a] { ctrl[a].clamp(m.actuator_ctrlrange[a][0], m.actuator_ctrlrange[a][1]) } else { ctrl[a] };
        act_dot[i] = match m.actuator_dyn[a] {
            ActuatorDyn::Integrator => u,
            ActuatorDyn::Filter(tau) | ActuatorDyn::FilterExact(tau) => (u - act[i]) / tau,
            ActuatorDyn::Muscle(tau) => super::muscle::activation_rate(u, act[i], tau),
            ActuatorDyn::None => 0.0,
        };
    }
}

/// act ← act advanced over h at the rates `act_dot`: act + h act˙, or for an exact filter
/// act + act˙ τ (1 − e^(−h/τ)); then clamped to its range.
pub fn advance(m: &Model, act: &mut [f64], act_dot: &[f64], h: f64) {
    for a in 0..m.nu {
        let Some(i) = m.actuator_actadr[a] else { continue };
        act[i] += match m.actuator_dyn[a] {
            ActuatorDyn::FilterExact(tau) => act_dot[i] * tau * (1.0 - (-h / tau).exp()),
            _ => h * act_dot[i],
        };
        if let Some([lo, hi]) = m.actuator_actrange[a] {
            act[i] = act[i].clamp(lo, hi);
        }
    }
}
