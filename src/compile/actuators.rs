//! The actuators: each on a hinge or slide joint or a fixed tendon, its ranges (MuJoCo's
//! `inheritrange`), a servo's damping from its `dampratio`, and a muscle's length range and acc0.

use crate::dynamics::DynamicsData;
use crate::error::{Error, Result};
use crate::mjcf::{ActuatorSpec, JointType, ModelSpec, MuscleSpec, TransmissionSpec};
use crate::model::{ActuatorDyn, Model, Muscle, Transmission};

/// The actuators, each on a hinge or slide joint or a fixed tendon, with their moment arms.
pub(super) fn actuators(m: &mut Model, spec: &ModelSpec) -> Result<()> {
    for a in &spec.actuators {
        let trn = match &a.target {
            TransmissionSpec::Joint(name) => {
                let Some(j) = m.jnt_name.iter().position(|n| n == name) else {
                    return Err(Error::model(&a.kind, Some("joint"), a.line, format!("unknown joint '{name}'")));
                };
                if !matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide) {
                    return Err(Error::model(&a.kind, Some("joint"), a.line, "actuators drive hinge or slide joints only"));
                }
                Transmission::Joint(j)
            }
            TransmissionSpec::Tendon(name) => {
                let Some(t) = m.tendon_name.iter().position(|n| n == name) else {
                    return Err(Error::model(&a.kind, Some("tendon"), a.line, format!("unknown tendon '{name}'")));
                };
                Transmission::Tendon(t)
            }
        };
        let (ctrlrange, actrange) = inherited_ranges(m, a, trn)?;
        m.actuator_trn.push(trn);
        m.actuator_name.push(a.name.clone());
        m.actuator_gear.push(a.gear);
        m.actuator_ctrlrange.push(ctrlrange);
        m.actuator_ctrllimited.push(a.ctrllimited);
        m.actuator_forcerange.push(a.forcerange);
        m.actuator_forcelimited.push(a.forcelimited);
        m.actuator_gain.push(a.gain);
        m.actuator_actadr.push((a.dynamics != ActuatorDyn::None).then_some(m.na));
        m.na += (a.dynamics != ActuatorDyn::None) as usize;
        m.actuator_dyn.push(a.dynamics);
        m.actuator_actrange.push(actrange);
        m.actuator_bias.push(a.bias);
        let muscle = a.muscle.map(|s| muscle_range(m, a, &s, trn).map(|lengthrange| Muscle { prm: s.prm, lengthrange, acc0: 0.0 })).transpose()?;
        m.actuator_muscle.push(muscle);
    }
    super::params::actuator_derived(m);
    Ok(())
}

/// An actuator's control and activation ranges: its own, or with MuJoCo's `inheritrange` (a
/// position servo's control range, an intvelocity servo's activation range) its joint's or
/// tendon's range scaled about its middle (`mjCActuator::Compile`).
fn inherited_ranges(m: &Model, a: &ActuatorSpec, trn: Transmission) -> Result<([f64; 2], Option<[f64; 2]>)> {
    if a.inheritrange <= 0.0 {
        return Ok((a.ctrlrange, a.actrange));
    }
    let servo = a.gain[0] == -a.bias[1] && a.gain[1..] == [0.0; 2];
    let err = |what: &str| Error::model(&a.kind, Some("inheritrange"), a.line, what);
    if !servo || !matches!(a.dynamics, ActuatorDyn::None | ActuatorDyn::FilterExact(_) | ActuatorDyn::Integrator) {
        return Err(err("inheritrange is for position and intvelocity actuators only"));
    }
    let [lo, hi] = match trn {
        Transmission::Joint(j) => m.jnt_range[j],
        Transmission::Tendon(t) => m.tendon_range[t],
    };
    if lo == hi {
        return Err(err("inheritrange needs a range on the joint or tendon it drives"));
    }
    let (mid, radius) = (0.5 * (hi + lo), 0.5 * (hi - lo) * a.inheritrange);
    let range = [mid - radius, mid + radius];
    Ok(match a.dynamics {
        ActuatorDyn::Integrator => (a.ctrlrange, Some(range)),
        _ => (range, a.actrange),
    })
}

/// A position-like servo's damping from its damping ratio (MuJoCo's `dampratio`, kept as a
/// positive `biasprm[2]`): kv = dampratio · 2 √(kp · m), m the inertia its transmission
/// reflects at qpos0, Σ 1 / ((M⁻¹)ᵢᵢ moment²) over its dofs, M the joint-space inertia there,
/// armature included (MuJoCo 4.0's `set0`, engine_setconst.c, with `dof_invweight0`).
pub(super) fn servo_damping(m: &mut Model, dy: &DynamicsData) {
    let servos: Vec<usize> = (0..m.nu).filter(|&a| m.actuator_gain[a][0] == -m.actuator_bias[a][1] && m.actuator_bias[a][2] > 0.0).collect();
    if servos.is_empty() {
        return;
    }
    let mass = crate::dynamics::crba::crba(m, &dy.kin);
    for a in servos {
        let moment: Vec<(usize, f64)> = match m.actuator_trn[a] {
            Transmission::Joint(_) => m.moment(a).iter().map(|w| (w.dof, w.coef)).collect(),
            Transmission::Tendon(t) => dy.ten.jac(t, m.nv).iter().enumerate().map(|(d, j)| (d, m.actuator_gear[a] * j)).collect(),
        };
        let inverse_diagonal = |d: usize| {
            let mut unit = vec![0.0; m.nv];
            unit[d] = 1.0;
            crate::dynamics::crba::cholesky_solve(&mass, &unit)[d]
        };
        let reflected: f64 = moment.iter().filter(|(_, c)| c * c > 1e-15).map(|&(d, c)| 1.0 / (inverse_diagonal(d) * c * c)).sum();
        let kp = m.actuator_gain[a][0];
        m.actuator_bias[a][2] = -(m.actuator_bias[a][2] * 2.0 * (kp * reflected).sqrt());
    }
    super::params::actuator_derived(m);
}

/// A muscle's actuator length range: its `lengthrange`, else its limited joint's or tendon's range
/// times its gear, with a warning (MuJoCo finds an unset range by simulating the model, and gets
/// other values); an error when there is neither.
fn muscle_range(m: &mut Model, a: &ActuatorSpec, s: &MuscleSpec, trn: Transmission) -> Result<[f64; 2]> {
    if let Some(range) = s.lengthrange {
        return Ok(range);
    }
    let limits = match trn {
        Transmission::Joint(j) => m.jnt_limited[j].then_some(m.jnt_range[j]),
        Transmission::Tendon(t) => m.tendon_limited[t].then_some(m.tendon_range[t]),
    };
    let Some([lo, hi]) = limits else {
        return Err(Error::model(&a.kind, Some("lengthrange"), a.line, "a muscle on an unlimited joint or tendon needs its lengthrange"));
    };
    m.warnings.push(format!(
        "<muscle> '{}' at line {}: lengthrange taken from its {} range times gear (MuJoCo computes it by simulation; give lengthrange to match it)",
        a.name,
        a.line,
        if matches!(trn, Transmission::Joint(_)) { "joint's" } else { "tendon's" }
    ));
    let (x, y) = (lo * a.gear, hi * a.gear);
    Ok([x.min(y), x.max(y)])
}

/// Each muscle's acc0: ‖M⁻¹ moment‖ at qpos0 (MuJoCo's `actuator_acc0`), `dy` the dynamics there.
pub(super) fn muscle_acc0(m: &mut Model, dy: &DynamicsData) {
    if m.actuator_muscle.iter().all(Option::is_none) {
        return;
    }
    let mass = crate::dynamics::crba::crba(m, &dy.kin);
    for a in 0..m.nu {
        let Some(muscle) = m.actuator_muscle[a] else { continue };
        let mut moment = vec![0.0; m.nv];
        match m.actuator_trn[a] {
            Transmission::Joint(_) => m.moment(a).iter().for_each(|w| moment[w.dof] += w.coef),
            Transmission::Tendon(t) => moment.iter_mut().zip(dy.ten.jac(t, m.nv)).for_each(|(x, j)| *x = m.actuator_gear[a] * j),
        }
        let acc = crate::dynamics::crba::cholesky_solve(&mass, &moment);
        m.actuator_muscle[a] = Some(Muscle { acc0: acc.iter().map(|x| x * x).sum::<f64>().sqrt(), ..muscle });
    }
}

