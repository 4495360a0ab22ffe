//! Joint and tendon equalities as exact bilateral rows: a linear coupling holds after every step
//! to the LCP's regulariser (1e-12 to 1e-9 of the motion), K of the rows by test forces equals J M⁻¹ Jᵀ, and a joint
//! fixed by an equality holds a load without drift.

#![allow(clippy::needless_range_loop)] // index loops follow the math's notation (and common's)
mod common;

use sinew::model::{ConstraintMode, Integrator};
use sinew::{Model, State};

/// Two independent hinged arms (two trees) and a slider on the first; `extra` goes in the file.
fn arms(extra: &str) -> Model {
    let xml = format!(
        "<mujoco><worldbody>\
           <body><joint name='a' axis='0 1 0'/><geom type='capsule' size='0.05' fromto='0 0 0 0.5 0 0'/>\
             <body pos='0.5 0 0'><joint name='s' type='slide' axis='1 0 0'/><geom size='0.08'/></body></body>\
           <body pos='0 1 0'><joint name='b' axis='0 1 0' damping='0.1'/><geom type='capsule' size='0.05' fromto='0 0 0 0.3 0 0'/></body>\
         </worldbody>\
         <tendon><fixed name='t1'><joint joint='a' coef='1'/><joint joint='s' coef='0.5'/></fixed>\
                 <fixed name='t2'><joint joint='b' coef='2'/></fixed></tendon>\
         <actuator><motor joint='a'/><motor joint='b'/><motor joint='s'/></actuator>{extra}</mujoco>"
    );
    Model::from_mjcf(&xml).unwrap()
}

/// Steps with pseudo-random controls and returns the largest |residual(state)| after a step.
fn worst(m: &Model, residual: impl Fn(&[f64]) -> f64) -> f64 {
    let mut s = State::new(m);
    let mut x = 1u64;
    let mut most = 0.0f64;
    for _ in 0..1500 {
        for c in s.ctrl.iter_mut() {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            *c = ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 4.0;
        }
        s.step(m);
        assert!(s.qpos.iter().all(|q| q.is_finite()));
        most = most.max(residual(&s.qpos).abs());
    }
    most
}

#[test]
fn a_linear_joint_coupling_holds_to_round_off() {
    let m = arms("<equality><joint joint1='b' joint2='a' polycoef='0.1 -2'/></equality>");
    // the arms start at 0, where the coupling asks b = 0.1: the first step brings it there
    let q = |q: &[f64]| q[2] - (0.1 - 2.0 * q[0]);
    let mut s = State::new(&m);
    s.step(&m);
    assert!(q(&s.qpos).abs() < 1e-9, "{}", q(&s.qpos));
    let w = worst(&m, q);
    assert!(w < 1e-8, "{w:e}");
    // the coupled arm moves: the rows carry the torque between the trees
    let mut s = State::new(&m);
    s.ctrl[0] = 1.0;
    for _ in 0..200 {
        s.step(&m);
    }
    assert!(s.qpos[0].abs() > 0.01 && q(&s.qpos).abs() < 1e-8, "{:?}", s.qpos);
}

#[test]
fn a_tendon_coupling_holds_to_round_off() {
    let m = arms("<equality><tendon tendon1='t1' tendon2='t2'/></equality>");
    // t1 − t1⁰ = t2 − t2⁰: a + 0.5 s = 2 b
    let w = worst(&m, |q| q[0] + 0.5 * q[1] - 2.0 * q[2]);
    assert!(w < 1e-8, "{w:e}");
}

#[test]
fn a_nonlinear_coupling_holds_within_1e6_in_every_mode_and_integrator() {
    // the rows are the coupling's linearisation plus its second order over the step's drift
    // (`rows::second_order_lift`): what a step leaves is of order (h q̇)³, and the next step
    // removes it (docs/physics.md says why no position projection). Here 6e-7 with the arms spun
    // by random torques up to several rad/s; 4e-5 with first-order rows
    for mode in [ConstraintMode::Acceleration, ConstraintMode::Velocity] {
        for integrator in [Integrator::Euler, Integrator::Leapfrog, Integrator::Rk4] {
            let mut m = arms("<equality><joint joint1='b' joint2='a' polycoef='0 1 0.5'/></equality>");
            (m.opt.constraint_mode, m.opt.integrator) = (mode, integrator);
            let w = worst(&m, |q| q[2] - (q[0] + 0.5 * q[0] * q[0]));
            assert!(w < 1e-6, "{mode:?}, {integrator:?}: {w:e}");
        }
    }
}

#[test]
fn an_inactive_equality_does_nothing() {
    let m = arms("<equality><joint joint1='b' joint2='a' active='false'/></equality>");
    let free = arms("");
    let (mut s, mut f) = (State::new(&m), State::new(&free));
    s.ctrl.copy_from_slice(&[1.0, -1.0, 0.5]);
    f.ctrl.copy_from_slice(&[1.0, -1.0, 0.5]);
    for _ in 0..100 {
        s.step(&m);
        f.step(&free);
    }
    assert_eq!(s.qpos, f.qpos);
}

#[test]
fn equality_rows_k_equals_j_minv_jt() {
    let m = arms("<equality><tendon tendon1='t1' tendon2='t2' polycoef='0 1.5'/><joint joint1='s'/></equality>");
    let mut s = State::new(&m);
    s.qpos.copy_from_slice(&[0.3, 0.05, -0.2]);
    s.qvel.copy_from_slice(&[0.5, -0.1, 0.2]);
    let (st, data) = s.split();
    let sys = sinew::step::constraint_system(&m, data, &st);
    assert_eq!(sys.kind.len(), 4);
    common::assert_k_is_j_minv_jt(&sys, m.nv);
}

#[test]
fn couplings_of_more_than_two_trees_and_unknown_names_are_errors() {
    let e = Model::from_mjcf(
        "<mujoco><worldbody><body><joint name='a'/><geom size='.1'/></body><body><joint name='b'/><geom size='.1'/></body>\
         <body><joint name='c'/><geom size='.1'/></body></worldbody>\
         <tendon><fixed name='t'><joint joint='b' coef='1'/><joint joint='c' coef='1'/></fixed></tendon>\
         <equality><tendon tendon1='t' tendon2='u'/></equality></mujoco>",
    )
    .unwrap_err();
    assert!(e.to_string().contains("unknown tendon 'u'"), "{e}");
    let e = Model::from_mjcf(
        "<mujoco><worldbody><body><joint name='a'/><geom size='.1'/></body><body><joint name='b'/><geom size='.1'/></body>\
         <body><joint name='c'/><geom size='.1'/></body></worldbody>\
         <tendon><fixed name='t'><joint joint='b' coef='1'/><joint joint='c' coef='1'/></fixed>\
         <fixed name='u'><joint joint='a'/></fixed></tendon>\
         <equality><tendon tendon1='t' tendon2='u'/></equality></mujoco>",
    )
    .unwrap_err();
    assert!(e.to_string().contains("two kinematic trees"), "{e}");
}

