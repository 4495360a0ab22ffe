//! Dry friction (`frictionloss`) as exact bounded rows: below its breakaway torque a joint stays
//! at rest (to the LCP's regulariser); above it the joint accelerates with the torque less the friction; K of the
//! rows by test forces equals J M⁻¹ Jᵀ.

#![allow(clippy::needless_range_loop)] // index loops follow the math's notation (and common's)
mod common;

use sinew::{Model, State};

/// A horizontal pendulum: a 1 kg point-like sphere 0.5 m out on a hinge about y, gravity −z, so
/// gravity's torque about the hinge is m g L.
fn pendulum(frictionloss: f64, mode: &str) -> (Model, f64, f64) {
    let xml = format!(
        "<mujoco><option gravity='0 0 -9.81'/><worldbody><body><joint name='hinge' axis='0 1 0' frictionloss='{frictionloss}'/>\
         <geom type='sphere' size='0.01' mass='1' pos='0.5 0 0'/></body></worldbody></mujoco>"
    );
    let m = Model::from_mjcf(&xml).unwrap();
    let m = match mode {
        "velocity" => {
            let mut v = m.clone();
            v.opt.constraint_mode = sinew::model::ConstraintMode::Velocity;
            v
        }
        _ => m,
    };
    let inertia = 0.25 + 0.4 * 0.01 * 0.01; // m L² + the sphere's own 2/5 m r²
    (m, 9.81 * 0.5, inertia)
}

#[test]
fn below_breakaway_a_joint_does_not_move_at_all() {
    for mode in ["acceleration", "velocity"] {
        let (m, torque, _) = pendulum(1.01 * 9.81 * 0.5, mode);
        let mut s = State::new(&m);
        for _ in 0..2000 {
            s.step(&m);
        }
        // at rest to the LCP's regulariser (1e-8 of K's diagonal): MuJoCo's soft friction lets
        // this pendulum creep 0.08 rad in these 4 s
        assert!(s.qpos[0].abs() < 1e-8 && s.qvel[0].abs() < 1e-9, "{mode}: q {} v {} under torque {torque}", s.qpos[0], s.qvel[0]);
    }
}

#[test]
fn above_breakaway_it_accelerates_with_the_torque_less_the_friction() {
    for mode in ["acceleration", "velocity"] {
        let loss = 0.3 * 9.81 * 0.5;
        let (m, torque, inertia) = pendulum(loss, mode);
        let mut s = State::new(&m);
        s.step(&m);
        // gravity pulls the far end down: about y that is a positive rotation
        let expected = (torque - loss) / inertia;
        let got = s.qvel[0] / m.opt.timestep;
        assert!((got - expected).abs() < 1e-9 * expected, "{mode}: {got} vs {expected}");
    }
}

#[test]
fn friction_rows_k_equals_j_minv_jt() {
    let xml = "<mujoco><worldbody><body><joint type='ball' frictionloss='0.2'/><geom type='capsule' size='0.05' fromto='0 0 0 0.4 0 0'/>\
        <body pos='0.4 0 0'><joint axis='0 1 0' frictionloss='0.1' damping='0.3'/><geom type='box' size='0.1 0.05 0.02' pos='0.1 0 0'/></body>\
        </body></worldbody></mujoco>";
    let m = Model::from_mjcf(xml).unwrap();
    let mut s = State::new(&m);
    s.qvel.copy_from_slice(&[0.3, -0.2, 0.5, 1.0]);
    let (st, data) = s.split();
    let sys = sinew::step::constraint_system(&m, data, &st);
    assert_eq!(sys.kind.len(), 8, "a ± pair per dof");
    assert!(sys.kind.iter().all(|k| *k == sinew::constraint::RowKind::DryFriction));
    common::assert_k_is_j_minv_jt(&sys, m.nv);
}
