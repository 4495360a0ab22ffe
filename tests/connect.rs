//! `<connect>` and `<weld>` equalities as exact bilateral rows: a parallelogram four-bar linkage
//! (a closed loop) keeps its cranks parallel and its coupler level as the analytic answer has it,
//! with the loop closed after every step; a free body connected to the world at a point swings
//! as the same body on a ball joint; a welded box holds still, or moves with the arm it is welded
//! to as if part of it; K of the rows by test forces equals J M⁻¹ Jᵀ.

#![allow(clippy::needless_range_loop)] // index loops follow the math's notation (and common's)
mod common;

use sinew::model::{ConstraintMode, Integrator};
use sinew::{Model, State};

/// Two 0.5 m cranks hinged about y at x = 0 and x = 1, the coupler (1 m) hinged to the first
/// crank's tip and connected to the second's (whose geoms it overlaps there: excluded, as a
/// MuJoCo model of it would); both cranks start at `angle`.
fn four_bar(angle: f64) -> Model {
    let xml = format!(
        "<mujoco><worldbody>\
           <body name='crank1'><joint name='a' axis='0 1 0' ref='0'/><geom type='capsule' size='0.02' fromto='0 0 0 0 0 -0.5' mass='1'/>\
             <body name='coupler' pos='0 0 -0.5'><joint name='c' axis='0 1 0'/><geom type='capsule' size='0.02' fromto='0 0 0 1 0 0' mass='2'/></body></body>\
           <body name='crank2' pos='1 0 0'><joint name='b' axis='0 1 0'/><geom type='capsule' size='0.02' fromto='0 0 0 0 0 -0.5' mass='1'/></body>\
         </worldbody>\
         <contact><exclude body1='coupler' body2='crank2'/></contact>\
         <equality><connect body1='coupler' body2='crank2' anchor='1 0 0'/></equality>\
         <keyframe><key name='start' qpos='{angle} {n} {angle}'/></keyframe></mujoco>",
        n = -angle
    );
    Model::from_mjcf(&xml).unwrap()
}

#[test]
fn a_parallelogram_four_bar_keeps_its_cranks_parallel_and_its_coupler_level() {
    for mode in [sinew::model::ConstraintMode::Acceleration, sinew::model::ConstraintMode::Velocity] {
        let mut m = four_bar(0.6);
        m.opt.constraint_mode = mode;
        let mut s = State::new(&m);
        s.qpos.copy_from_slice(&m.keys[0].qpos);
        let (mut worst_gap, mut least, mut most) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
        for _ in 0..2000 {
            s.step(&m);
            let (a, c, b) = (s.qpos[0], s.qpos[1], s.qpos[2]);
            // the coupler's far end (crank1 tip + coupler) against crank2's tip
            let tip1 = [-0.5 * a.sin(), -0.5 * a.cos()];
            let end = [tip1[0] + (a + c).cos(), tip1[1] - (a + c).sin()];
            let tip2 = [1.0 - 0.5 * b.sin(), -0.5 * b.cos()];
            worst_gap = worst_gap.max((end[0] - tip2[0]).hypot(end[1] - tip2[1]));
            // a parallelogram: the cranks stay parallel, the coupler level (a + c = 0)
            assert!((a - b).abs() < 1e-6 && (a + c).abs() < 1e-6, "{mode:?}: a {a} b {b} c {c}");
            (least, most) = (least.min(a), most.max(a));
        }
        assert!(worst_gap < 1e-6, "{mode:?}: the loop opened by {worst_gap:e}");
        // it swings (from 0.6 through the bottom to about −0.6), not stuck
        assert!(least < -0.5 && most > 0.55, "{mode:?}: swung between {least} and {most}");
    }
}

#[test]
fn a_free_body_connected_to_the_world_swings_as_on_a_ball_joint() {
    let body = "<geom type='box' size='0.05 0.1 0.3' pos='0 0 -0.3' mass='2'/>";
    let ball = Model::from_mjcf(&format!("<mujoco><worldbody><body name='b' pos='0 0 1' euler='0.4 0.3 0'><joint type='ball'/>{body}</body></worldbody></mujoco>")).unwrap();
    let free = Model::from_mjcf(&format!(
        "<mujoco><worldbody><body name='b' pos='0 0 1' euler='0.4 0.3 0'><freejoint/>{body}</body></worldbody>\
         <equality><connect body1='b' anchor='0 0 0'/></equality></mujoco>"
    ))
    .unwrap();
    let (mut sb, mut sf) = (State::new(&ball), State::new(&free));
    for _ in 0..500 {
        sb.step(&ball);
        sf.step(&free);
    }
    // the pivot stays put, and the orientation follows the ball joint's
    let pivot = (sf.qpos[0].powi(2) + sf.qpos[1].powi(2) + (sf.qpos[2] - 1.0).powi(2)).sqrt();
    assert!(pivot < 1e-6, "the pivot moved {pivot:e}");
    let dot: f64 = (0..4).map(|k| sb.qpos[k] * sf.qpos[3 + k]).sum();
    assert!(1.0 - dot.abs() < 1e-4, "orientations differ: {:?} vs {:?}", &sb.qpos[..4], &sf.qpos[3..]);
}

#[test]
fn connect_rows_k_equals_j_minv_jt() {
    let m = four_bar(0.3);
    let mut s = State::new(&m);
    s.qpos.copy_from_slice(&m.keys[0].qpos);
    s.qvel.copy_from_slice(&[0.4, -0.2, 0.1]);
    let (st, data) = s.split();
    let sys = sinew::step::constraint_system(&m, data, &st);
    assert_eq!(sys.kind.len(), 6, "a ± pair per axis");
    common::assert_k_is_j_minv_jt(&sys, m.nv);
}

#[test]
fn a_box_welded_to_the_world_holds_still_and_one_welded_to_an_arm_moves_as_one_body() {
    // a free box welded where it starts: gravity cannot move it
    let m = Model::from_mjcf(
        "<mujoco><worldbody><body name='box' pos='0.3 0.2 1' euler='0.3 0.2 0.1'><freejoint/><geom type='box' size='0.1 0.2 0.05' mass='3'/></body></worldbody>\
         <equality><weld body1='box'/></equality></mujoco>",
    )
    .unwrap();
    let mut s = State::new(&m);
    for _ in 0..1000 {
        s.step(&m);
    }
    let moved = s.qpos.iter().zip(&m.qpos0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(moved < 1e-6, "the welded box moved {moved:e}");
    // a box welded to a driven arm (the geoms overlapping there excluded from contact) against
    // the same box rigidly part of the arm
    let arm = |extra: &str, boxed: &str| {
        format!(
            "<mujoco><worldbody><body name='arm'><joint axis='0 1 0' damping='0.1'/><geom type='capsule' size='0.03' fromto='0 0 0 0.5 0 0'/>{boxed}</body>{extra}</worldbody>\
             <actuator><motor joint='{j}'/></actuator>{eq}</mujoco>",
            j = "hinge",
            eq = if extra.is_empty() { "" } else { "<contact><exclude body1='box' body2='arm'/></contact><equality><weld body1='box' body2='arm'/></equality>" }
        )
    };
    let boxed = "<geom type='box' size='0.1 0.05 0.05' pos='0.5 0 0' mass='2'/>";
    let rigid = Model::from_mjcf(&arm("", boxed).replace("<joint axis", "<joint name='hinge' axis")).unwrap();
    let welded = Model::from_mjcf(
        &arm("<body name='box' pos='0.5 0 0'><freejoint/><geom type='box' size='0.1 0.05 0.05' mass='2'/></body>", "")
            .replace("<joint axis", "<joint name='hinge' axis"),
    )
    .unwrap();
    for (mode, integrator) in [(ConstraintMode::Acceleration, Integrator::Euler), (ConstraintMode::Velocity, Integrator::Euler), (ConstraintMode::Acceleration, Integrator::Leapfrog), (ConstraintMode::Acceleration, Integrator::Rk4)] {
        let (mut rigid, mut welded) = (rigid.clone(), welded.clone());
        (rigid.opt.constraint_mode, rigid.opt.integrator, welded.opt.constraint_mode, welded.opt.integrator) = (mode, integrator, mode, integrator);
        let (mut a, mut b) = (State::new(&rigid), State::new(&welded));
        let mut worst = 0.0f64;
        for k in 0..1000 {
            let u = (k as f64 * 0.01).sin() * 5.0;
            a.ctrl[0] = u;
            b.ctrl[0] = u;
            a.step(&rigid);
            b.step(&welded);
            // the box stays at the arm's end after every step: the rows take the points' arcs
            // over the step (their second order), leaving an error of order (h ω)³ r (7e-7 m
            // here, the arm turning at up to 9 rad/s; 8e-5 m when the rows were first order)
            let (x, z) = (0.5 * b.qpos[0].cos(), -0.5 * b.qpos[0].sin());
            worst = worst.max((b.qpos[1] - x).abs().max((b.qpos[3] - z).abs()));
        }
        assert!(worst < 1e-6, "{mode:?}, {integrator:?}: the box left the arm's end by {worst:e}");
        // (RK4 steps the rigid arm, which has no rows, by its stages and the welded one by
        // semi-implicit Euler: their angles differ by the integrators' error, 7e-3 here)
        if integrator != Integrator::Rk4 {
            assert!((a.qpos[0] - b.qpos[0]).abs() < 2e-5, "{mode:?}, {integrator:?}: arm angle {} vs {}", a.qpos[0], b.qpos[0]);
        }
    }
}
