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

/// The trajectory of a step that takes the friction of each dof sliding on as a known force
/// (`constraint::dry_friction`), beside one that poses every friction row each step (the
/// history's sliding dofs forgotten before each), over `steps`: the largest difference of qpos
/// and qvel, the steps that took a known force, and the velocity reversals on the way.
fn known_beside_rows(m: &Model, s0: &State, steps: usize) -> (f64, usize, usize) {
    let (mut known, mut rows) = (s0.clone(), s0.clone());
    let (mut worst, mut used, mut reversals) = (0.0f64, 0, 0);
    for _ in 0..steps {
        used += !known.data.constraints.history.sliding.is_empty() as usize;
        let before = known.qvel.clone();
        known.step(m);
        rows.data.constraints.history.sliding.clear();
        rows.step(m);
        reversals += before.iter().zip(&known.qvel).filter(|(a, b)| **a * **b < 0.0).count();
        for (a, b) in known.qpos.iter().chain(&known.qvel).zip(rows.qpos.iter().chain(&rows.qvel)) {
            worst = worst.max((a - b).abs());
        }

    }
    assert!(rows.data.constraints.history.sliding.len() <= m.nv);
    (worst, used, reversals)
}

#[test]
fn a_sliding_dofs_friction_taken_as_known_gives_the_rows_answer() {
    // a three-link chain with friction on every hinge, swinging from a tilt, its foot dragging
    // over the floor: dofs slide, stop and turn, and contacts come and go. Planar: the contact's
    // friction directions are ±x either way (in 3D the tangent follows the slip the step would
    // have without constraint forces, which the known friction moves: another pyramid)
    let xml = "<mujoco><option timestep='0.002'/><worldbody><geom type='plane' size='5 5 0.1'/>\
        <body pos='0 0 1.1'><joint axis='0 1 0' frictionloss='0.4' damping='0.05'/><geom type='capsule' size='0.04' fromto='0 0 0 0 0 -0.4'/>\
        <body pos='0 0 -0.4'><joint axis='0 1 0' frictionloss='0.2'/><geom type='capsule' size='0.04' fromto='0 0 0 0 0 -0.4'/>\
        <body pos='0 0 -0.4'><joint axis='0 1 0' frictionloss='0.1' armature='0.01'/><geom type='capsule' size='0.04' fromto='0 0 0 0 0 -0.35'/>\
        </body></body></body></worldbody></mujoco>";
    let m = Model::from_mjcf(xml).unwrap();
    let mut s = State::new(&m);
    s.qpos.copy_from_slice(&[0.9, -0.6, 0.5]);
    let (worst, used, reversals) = known_beside_rows(&m, &s, 1500);
    assert!(used > 500, "the known forces were taken on {used} of 1500 steps");
    assert!(reversals >= 3, "{reversals} velocity reversals");
    assert!(worst < 1e-9, "largest difference {worst:e}");
}

#[test]
fn a_known_friction_is_checked_and_posed_as_rows_when_it_would_turn_the_dof() {
    // a hinge sliding slowly against its friction: the known force would reverse it within a
    // step, and the step must stop it exactly instead (the rows' answer)
    let (m, _, _) = pendulum(9.81 * 0.5 * 1.5, "acceleration");
    let mut s = State::new(&m);
    s.qvel[0] = 0.01;
    s.data.constraints.history.sliding = vec![(0, true)];
    s.step(&m);
    assert!(s.qvel[0].abs() < 1e-8, "stopped, not turned: {}", s.qvel[0]);
    assert!(s.data.constraints.history.sliding.is_empty());
    // sliding fast, it slows by h (loss − m g L) / I and stays a known force
    let (m, torque, inertia) = pendulum(9.81 * 0.5 * 1.5, "acceleration");
    let mut s = State::new(&m);
    s.qvel[0] = -2.0;
    s.data.constraints.history.sliding = vec![(0, false)];
    s.step(&m);
    let expected = -2.0 + m.opt.timestep * (torque + 1.5 * torque) / inertia;
    assert!((s.qvel[0] - expected).abs() < 1e-12, "{} vs {expected}", s.qvel[0]);
    assert_eq!(s.data.constraints.history.sliding, vec![(0, false)]);
}

/// A torso on a hinge with two three-hinge arms driven by position servos, friction loss on
/// every arm hinge, the right arm long enough to drag over the floor.
fn two_arms() -> Model {
    let arm = |side: &str, x: f64, len: f64| {
        let body = |i: usize, loss: f64| {
            format!("<joint name='{side}{i}' axis='0 1 0' frictionloss='{loss}' armature='0.01'/><geom type='capsule' size='0.03' fromto='0 0 0 0 0 -{len}'/>")
        };
        format!("<body pos='{x} 0 0'>{}<body pos='0 0 -{len}'>{}<body pos='0 0 -{len}'>{}</body></body></body>", body(1, 0.6), body(2, 0.3), body(3, 0.15))
    };
    let servos: String = ["l1", "l2", "l3", "r1", "r2", "r3"].iter().map(|n| format!("<position joint='{n}' kp='8' kv='1.5' ctrlrange='-1 1'/>")).collect();
    let xml = format!(
        "<mujoco><option timestep='0.002'/><worldbody><geom type='plane' size='5 5 0.1'/>\
         <body pos='0 0 1.2'><joint name='torso' axis='1 0 0' damping='0.5'/><geom type='box' size='0.3 0.05 0.05'/>\
         {}{}</body></worldbody><actuator>{servos}</actuator></mujoco>",
        arm("l", -0.3, 0.25),
        arm("r", 0.3, 0.42)
    );
    Model::from_mjcf(&xml).unwrap()
}

#[test]
fn a_joint_held_by_its_friction_gives_the_rows_answer() {
    // the servos' targets change every 500 steps: the arms swing, stop and stick, the long one
    // drags and rests on the floor; the free arm's hinges are held still while they stick. Each
    // step beside the same step with every stuck dof's rows posed, from the same state
    let m = two_arms();
    let mut rows_model = m.clone();
    rows_model.opt.hold_stuck_joints = false;
    let mut s = State::new(&m);
    let mut rng = common::Rng(5);
    let (mut worst, mut holding, mut touching) = (0.0f64, 0, 0);
    for step in 0..3000 {
        if step % 500 == 0 {
            for u in 0..m.nu {
                s.ctrl[u] = rng.uniform(-1.0, 1.0);
            }
        }
        let mut rows = s.clone();
        s.step(&m);
        rows.step(&rows_model);
        assert!(rows.data.dynamics.aba.locked.iter().all(|&l| !l));
        if s.data.dynamics.aba.locked.iter().any(|&l| l) {
            holding += 1;
            touching += !s.data.coll.contacts.is_empty() as usize;
            for (a, b) in s.qvel.iter().zip(&rows.qvel) {
                worst = worst.max((a - b).abs());
            }
        }
    }
    assert!(holding > 600, "joints held on {holding} of 3000 steps");
    assert!(touching > 600, "the long arm touched the floor on {touching} of them");
    assert!(worst < 1e-9, "largest difference of q̇ {worst:e}");
}
#[test]
fn a_held_joint_is_exactly_still_and_lets_go_past_its_friction() {
    // below breakaway the held hinge does not move by a bit; above it, it is let go and slides
    let (m, torque, _) = pendulum(1.01 * 9.81 * 0.5, "acceleration");
    let mut s = State::new(&m);
    for _ in 0..500 {
        s.step(&m);
        assert!(s.data.dynamics.aba.locked[0]);
    }
    assert_eq!((s.qpos[0], s.qvel[0]), (0.0, 0.0));
    let applied = &s.data.constraints.applied.joint;
    assert!(applied.len() == 1 && (applied[0].1 + torque).abs() < 1e-12, "the friction holds gravity's torque: {applied:?}");
    let (m, _, _) = pendulum(0.99 * 9.81 * 0.5, "acceleration");
    let mut s = State::new(&m);
    s.step(&m);
    assert!(!s.data.dynamics.aba.locked[0] && s.qvel[0] > 0.0);
}
