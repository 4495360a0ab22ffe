//! Spatial tendons and tendon rows: J of every path kind (sites, sphere and cylinder wraps with
//! and without side sites, pulleys) equals the length's derivative and J̇ q̇ its second; K of tendon
//! limit and friction rows by test torques equals J M⁻¹ Jᵀ; a string (a limited spatial tendon)
//! holds a swinging ball at its length as a rigid rod would; a tendon's dry friction holds below its
//! loss and lets go above it.

#![allow(clippy::needless_range_loop)] // index loops follow the math's notation (and common's)
mod common;

use sinew::dynamics::kinematics::{self, KinData};
use sinew::dynamics::tendon::{self, TendonData};
use sinew::{Model, State};

/// A three-link arm with a sphere and a cylinder to wrap around and a free box; every path kind.
const PATHS: &str = r#"<mujoco><worldbody>
  <site name="anchor" pos="0 0 1"/><site name="anchor2" pos="0.3 0.1 1.1"/>
  <body name="a" pos="0 0 0.5"><joint type="hinge" axis="0 1 0"/><joint type="hinge" axis="1 0 0"/>
    <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
    <geom name="ball" type="sphere" pos="0.2 0 0.05" size="0.06" contype="0" conaffinity="0"/>
    <site name="s1" pos="0.1 0 0.02"/><site name="side1" pos="0.2 0 0.2"/>
    <body name="b" pos="0.4 0 0"><joint type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <geom name="drum" type="cylinder" quat="0.707107 0.707107 0 0" size="0.05 0.05" contype="0" conaffinity="0"/>
      <site name="s2" pos="0.3 0 0.03"/><site name="side2" pos="0 0 0.2"/><site name="inner" pos="0.01 0 0.01"/>
      <body name="c" pos="0.4 0 0"><joint type="slide" axis="1 0 0"/><geom type="sphere" size="0.05"/>
        <site name="s3" pos="0 0 0.05"/></body></body></body>
  <body name="free" pos="0.5 0.5 1"><freejoint/><geom type="box" size="0.05 0.05 0.05"/><site name="s4" pos="0.05 0 0"/></body>
</worldbody><tendon>
  <spatial name="sides"><site site="s1"/><geom geom="ball" sidesite="side1"/><site site="s2"/><geom geom="drum" sidesite="side2"/><site site="s3"/></spatial>
  <spatial name="plain"><site site="anchor"/><geom geom="ball"/><site site="s2"/><geom geom="drum"/><site site="s3"/></spatial>
  <spatial name="pulleyed"><site site="anchor"/><site site="s1"/><pulley divisor="2"/><site site="anchor2"/><site site="s4"/></spatial>
  <spatial name="inside"><site site="s1"/><geom geom="drum" sidesite="inner"/><site site="s3"/></spatial>
</tendon></mujoco>"#;

/// Tendon lengths, J and J̇ q̇ at (qpos, qvel).
fn tendons(m: &Model, qpos: &[f64], qvel: &[f64]) -> TendonData {
    let mut kin = KinData::new(m);
    kinematics::forward(m, qpos, qvel, &mut kin);
    let mut ten = TendonData::new(m);
    tendon::compute(m, &kin, qpos, &mut ten);
    ten
}

/// A random configuration and velocity (the free body's quaternion normalised).
fn random_state(m: &Model, r: &mut common::Rng) -> (Vec<f64>, Vec<f64>) {
    let mut qpos: Vec<f64> = m.qpos0.iter().map(|q| q + r.uniform(-0.8, 0.8)).collect();
    let n = qpos.len();
    let norm = qpos[n - 4..].iter().map(|x| x * x).sum::<f64>().sqrt();
    qpos[n - 4..].iter_mut().for_each(|x| *x /= norm);
    (qpos, (0..m.nv).map(|_| r.uniform(-2.0, 2.0)).collect())
}

#[test]
fn j_is_the_lengths_derivative_for_every_path_kind() {
    let m = Model::from_mjcf(PATHS).unwrap();
    assert_eq!(m.ntendon, 4);
    let mut r = common::Rng(3);
    let (mut wrapped, eps) = ([0usize; 4], 1e-6);
    for _ in 0..300 {
        let (qpos, qvel) = random_state(&m, &mut r);
        let ten = tendons(&m, &qpos, &qvel);
        // the length along q ⊕ ±ε q̇, central difference
        let moved = |s: f64| {
            let mut q = qpos.clone();
            sinew::integrate::integrate_pos(&m, &mut q, &qvel, s);
            tendons(&m, &q, &qvel).length
        };
        let (up, down) = (moved(eps), moved(-eps));
        for t in 0..m.ntendon {
            let rate = ten.rate(&m, t, &qvel);
            let fd = (up[t] - down[t]) / (2.0 * eps);
            // a wrap switching on or off within ±ε has no derivative there
            if (ten.length[t] - up[t]).abs() > 1e-3 || (ten.length[t] - down[t]).abs() > 1e-3 {
                continue;
            }
            assert!((rate - fd).abs() < 1e-6 * (1.0 + fd.abs()), "tendon {t}: J q̇ {rate} vs {fd}");
            let straight = t == 2 || (ten.length[t] - straight_length(&m, &qpos, t)).abs() < 1e-12;
            wrapped[t] += !straight as usize;
        }
    }
    // the wraps were exercised: the sphere and drum tendons wrapped in many configurations
    assert!(wrapped[0] > 30 && wrapped[1] > 30 && wrapped[3] > 30, "{wrapped:?}");
}

/// The sum of site-to-site distances of tendon t, its geoms ignored (and no pulleys).
fn straight_length(m: &Model, qpos: &[f64], t: usize) -> f64 {
    let mut kin = KinData::new(m);
    kinematics::forward(m, qpos, &vec![0.0; m.nv], &mut kin);
    let sites: Vec<_> = m
        .tendon_path(t)
        .iter()
        .filter_map(|p| match p {
            sinew::model::PathPoint::Site(s) => Some(kin.xpos[m.site_body[*s]] + kin.xmat[m.site_body[*s]] * m.site_pos[*s]),
            _ => None,
        })
        .collect();
    sites.windows(2).map(|w| (w[1] - w[0]).length()).sum()
}

#[test]
fn jdot_qdot_is_the_rates_derivative_along_the_motion() {
    // the pulleyed tendon (sites only): d/dt (J q̇) at constant q̇ is J̇ q̇
    let m = Model::from_mjcf(PATHS).unwrap();
    let mut r = common::Rng(5);
    for _ in 0..50 {
        let (qpos, qvel) = random_state(&m, &mut r);
        let ten = tendons(&m, &qpos, &qvel);
        let rate_at = |s: f64| {
            let mut q = qpos.clone();
            sinew::integrate::integrate_pos(&m, &mut q, &qvel, s);
            tendons(&m, &q, &qvel).rate(&m, 2, &qvel)
        };
        let eps = 1e-6;
        let fd = (rate_at(eps) - rate_at(-eps)) / (2.0 * eps);
        assert!((ten.jdot_qdot[2] - fd).abs() < 1e-5 * (1.0 + fd.abs()), "J̇q̇ {} vs {fd}", ten.jdot_qdot[2]);
    }
}

/// A ball on two slide joints (x, z) hung from a world site by a string of length `length` (a
/// spatial tendon limited to [0, length]), and the same ball on a rigid rod (a hinge).
fn string_and_rod(length: f64, extra: &str) -> (Model, Model) {
    let string = format!(
        "<mujoco><option timestep='0.001' {extra}/><worldbody><site name='top' pos='0 0 1'/>\
           <body><joint name='x' type='slide' axis='1 0 0'/><joint name='z' type='slide' axis='0 0 1'/>\
             <geom size='0.02' mass='1' contype='0' conaffinity='0'/><site name='bob'/></body></worldbody>\
         <tendon><spatial limited='true' range='0 {length}'><site site='top'/><site site='bob'/></spatial></tendon></mujoco>"
    );
    let rod = format!(
        "<mujoco><option timestep='0.001' {extra}/><worldbody><body pos='0 0 1'><joint type='hinge' axis='0 1 0'/>\
           <geom size='0.02' mass='1' pos='0 0 -{length}' contype='0' conaffinity='0'/></body></worldbody></mujoco>"
    );
    (Model::from_mjcf(&string).unwrap(), Model::from_mjcf(&rod).unwrap())
}

#[test]
fn a_string_swings_a_ball_as_a_rod_does_and_never_stretches() {
    for extra in ["", "integrator='RK4'"] {
        for mode in [sinew::model::ConstraintMode::Acceleration, sinew::model::ConstraintMode::Velocity] {
            let (mut string, mut rod) = string_and_rod(0.5, extra);
            string.opt.constraint_mode = mode;
            rod.opt.constraint_mode = mode;
            // released taut at 40°, at rest
            let angle = 40f64.to_radians();
            let (mut s, mut p) = (State::new(&string), State::new(&rod));
            s.qpos.copy_from_slice(&[0.5 * angle.sin(), 1.0 - 0.5 * angle.cos()]);
            p.qpos[0] = -angle;
            let (mut stretch, mut apart) = (0.0f64, 0.0f64);
            for _ in 0..2000 {
                s.step(&string);
                p.step(&rod);
                let (x, z) = (s.qpos[0], s.qpos[1]);
                let length = (x * x + (z - 1.0).powi(2)).sqrt();
                stretch = stretch.max(length - 0.5);
                let (xr, zr) = (0.5 * (-p.qpos[0]).sin(), 1.0 - 0.5 * p.qpos[0].cos());
                apart = apart.max(((x - xr).powi(2) + (z - zr).powi(2)).sqrt());
            }
            assert!(stretch < 1e-6, "{extra} {mode:?}: the string stretched by {stretch:e} m");
            assert!(apart < 3e-3, "{extra} {mode:?}: string and rod {apart:e} m apart after 2 s");
        }
    }
}

/// A two-link arm on a slider, a string from the world to its tip (limited) and a fixed tendon,
/// both with dry friction `loss`.
fn arm_with_tendons(range: f64, loss: f64) -> Model {
    Model::from_mjcf(&format!(
        "<mujoco><worldbody><site name='top' pos='0.2 0 1.2'/>\
           <body><joint name='s' type='slide' axis='1 0 0'/><geom size='0.05'/>\
             <body><joint name='a' axis='0 1 0'/><geom type='capsule' size='0.03' fromto='0 0 0 0 0 0.5'/>\
               <body pos='0 0 0.5'><joint name='b' axis='0 1 0'/><geom type='capsule' size='0.03' fromto='0 0 0 0.4 0 0'/>\
                 <site name='tip' pos='0.4 0 0'/></body></body></body></worldbody>\
         <tendon><spatial limited='true' range='0 {range}' frictionloss='{loss}'><site site='top'/><site site='tip'/></spatial>\
           <fixed frictionloss='{loss}'><joint joint='a' coef='1'/><joint joint='b' coef='-0.5'/></fixed></tendon></mujoco>"
    ))
    .unwrap()
}

#[test]
fn tendon_limit_and_friction_rows_k_equals_j_minv_jt() {
    // the tip starts 0.73 m from the top: a range of 0.72 puts the string past its limit
    let m = arm_with_tendons(0.72, 0.3);
    let mut s = State::new(&m);
    s.qvel.copy_from_slice(&[0.2, -0.4, 0.7]);
    let (st, data) = s.split();
    let sys = sinew::step::constraint_system(&m, data, &st);
    let kinds: Vec<_> = sys.kind.iter().map(|k| format!("{k:?}")).collect();
    assert_eq!(kinds, ["Limit", "DryFriction", "DryFriction", "DryFriction", "DryFriction"], "{kinds:?}");
    common::assert_k_is_j_minv_jt(&sys, m.nv);
}

#[test]
fn a_tendons_dry_friction_holds_below_its_loss_and_slips_above_it() {
    // a pendulum at 0.3 rad, gravity's torque about 0.7 N m, its hinge inside a fixed tendon
    // (length 2 a: 2 N m of torque per N) or under a string from a world site to its tip (moment
    // arm about 0.49 m):
    // friction holds it still when the loss exceeds what gravity asks, else it swings
    for tendon in ["<fixed frictionloss='{loss}'><joint joint='a' coef='2'/></fixed>", "<spatial frictionloss='{loss}'><site site='top'/><site site='tip'/></spatial>"] {
        for (loss, moves) in [(3.0, false), (0.2, true)] {
            let xml = format!(
                "<mujoco><worldbody><site name='top' pos='1 0 1'/><body pos='0 0 1'><joint name='a' axis='0 1 0'/>\
                   <geom type='capsule' size='0.03' fromto='0 0 0 0 0 -0.5' mass='1'/><site name='tip' pos='0 0 -0.5'/></body></worldbody>\
                 <tendon>{}</tendon></mujoco>",
                tendon.replace("{loss}", &loss.to_string())
            );
            let m = Model::from_mjcf(&xml).unwrap();
            let mut s = State::new(&m);
            s.qpos[0] = 0.3;
            for _ in 0..500 {
                s.step(&m);
            }
            let moved = (s.qpos[0] - 0.3).abs();
            if moves {
                assert!(moved > 0.05, "{tendon} loss {loss}: moved only {moved}");
            } else {
                assert!(moved < 1e-9, "{tendon} loss {loss}: moved {moved:e}");
            }
        }
    }
}
