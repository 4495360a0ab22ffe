//! A [`Task`] from the keyword arguments `Batch.set_task` receives (`envs/sinew/tasks.py` passes
//! the gymnasium v5 env's arguments, defaults filled in).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::Model;
use crate::task::{Healthy, Task};

/// Reads named parameters, each exactly once; unknown names are an error.
struct Params<'py> {
    kind: String,
    dict: Bound<'py, PyDict>,
    used: Vec<String>,
}

impl<'py> Params<'py> {
    fn get<T: for<'a> FromPyObject<'a, 'py>>(&mut self, name: &str) -> PyResult<T> {
        self.used.push(name.to_owned());
        let value = self.dict.get_item(name)?.ok_or_else(|| PyValueError::new_err(format!("task {}: missing parameter '{name}'", self.kind)))?;
        value.extract().map_err(|_| PyValueError::new_err(format!("task {}: parameter '{name}' has the wrong type", self.kind)))
    }

    fn range(&mut self, name: &str) -> PyResult<[f64; 2]> {
        let (lo, hi): (f64, f64) = self.get(name)?;
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(PyValueError::new_err(format!("task {}: '{name}' must be a range (low ≤ high), got ({lo}, {hi})", self.kind)));
        }
        Ok([lo, hi])
    }

    fn weight(&mut self, name: &str) -> PyResult<f64> {
        let w: f64 = self.get(name)?;
        if !w.is_finite() {
            return Err(PyValueError::new_err(format!("task {}: '{name}' must be finite, got {w}", self.kind)));
        }
        Ok(w)
    }

    fn skip(&mut self, m: &Model, most: usize) -> PyResult<usize> {
        let exclude: bool = self.get("exclude_current_positions_from_observation")?;
        Ok(if exclude { most.min(m.nq) } else { 0 })
    }

    fn done(self) -> PyResult<()> {
        for key in self.dict.keys() {
            let k: String = key.extract()?;
            if !self.used.contains(&k) {
                return Err(PyValueError::new_err(format!("task {}: unknown parameter '{k}'", self.kind)));
            }
        }
        Ok(())
    }
}

fn body(m: &Model, kind: &str, name: &str) -> PyResult<usize> {
    m.body_id(name).ok_or_else(|| PyValueError::new_err(format!("task {kind}: the model has no body '{name}'")))
}

/// Builds task `kind` for model `m` from `params`.
pub fn parse(m: &Model, kind: &str, params: Bound<'_, PyDict>) -> PyResult<Task> {
    let mut p = Params { kind: kind.to_owned(), dict: params, used: vec![] };
    let task = match kind {
        "InvertedPendulum" => {
            if m.nq < 2 {
                return Err(PyValueError::new_err("task InvertedPendulum: the model needs two joints"));
            }
            Task::InvertedPendulum
        }
        "InvertedDoublePendulum" => {
            if m.site_body.is_empty() || m.nv < 3 {
                return Err(PyValueError::new_err("task InvertedDoublePendulum: the model needs a tip site and three joints"));
            }
            Task::InvertedDoublePendulum { healthy_reward: p.weight("healthy_reward")?, tip: (m.site_body[0], m.site_pos[0]) }
        }
        "Reacher" => {
            if m.nq < 2 || m.nv < 2 {
                return Err(PyValueError::new_err("task Reacher: the model needs two joints"));
            }
            let bodies = (body(m, kind, "fingertip")?, body(m, kind, "target")?);
            Task::Reacher { dist_weight: p.weight("reward_dist_weight")?, ctrl_weight: p.weight("reward_control_weight")?, bodies }
        }
        "Hopper" | "Walker2d" | "HalfCheetah" => {
            if m.nq < 3 {
                return Err(PyValueError::new_err(format!("task {kind}: the model needs a planar root (three joints)")));
            }
            let healthy = if kind == "HalfCheetah" {
                None
            } else {
                Some(Healthy {
                    reward: p.weight("healthy_reward")?,
                    z: p.range("healthy_z_range")?,
                    angle: p.range("healthy_angle_range")?,
                    state: if kind == "Hopper" { Some(p.range("healthy_state_range")?) } else { None },
                    terminate: p.get("terminate_when_unhealthy")?,
                })
            };
            Task::Planar {
                forward_weight: p.weight("forward_reward_weight")?,
                ctrl_weight: p.weight("ctrl_cost_weight")?,
                skip: p.skip(m, 1)?,
                clip_qvel: kind != "HalfCheetah",
                healthy,
            }
        }
        "Ant" | "Humanoid" => {
            if m.nq < 7 || m.nv < 6 {
                return Err(PyValueError::new_err(format!("task {kind}: the model needs a free root joint")));
            }
            let weights = [
                p.weight("forward_reward_weight")?,
                p.weight("ctrl_cost_weight")?,
                p.weight("contact_cost_weight")?,
                p.weight("healthy_reward")?,
            ];
            let (z, terminate, skip) = (p.range("healthy_z_range")?, p.get("terminate_when_unhealthy")?, p.skip(m, 2)?);
            if kind == "Ant" {
                let main: usize = p.get("main_body")?;
                if main >= m.nbody {
                    return Err(PyValueError::new_err(format!("task Ant: main_body {main} is not a body index (nbody = {})", m.nbody)));
                }
                let (force_range, cfrc) = (p.range("contact_force_range")?, p.get("include_cfrc_ext_in_observation")?);
                Task::Ant { weights, main, z, force_range, terminate, skip, cfrc }
            } else {
                let parts = [
                    p.get("include_cinert_in_observation")?,
                    p.get("include_cvel_in_observation")?,
                    p.get("include_qfrc_actuator_in_observation")?,
                    p.get("include_cfrc_ext_in_observation")?,
                ];
                Task::Humanoid { weights, cost_range: p.range("contact_cost_range")?, z, terminate, skip, parts }
            }
        }
        _ => return Err(PyValueError::new_err(format!("unknown task '{kind}'"))),
    };
    p.done()?;
    Ok(task)
}
