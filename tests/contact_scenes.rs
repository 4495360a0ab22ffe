//! Analytic contact and limit scenes (impacts, restitution, friction thresholds), each over every
//! integrator, both constraint modes and both time steps where they apply.

#![allow(clippy::needless_range_loop)] // tests/common follows the math's index notation
mod common;

use common::Rng;
use sinew::model::{ConstraintMode, FrictionModel, Integrator};
use sinew::{Model, State};

const INTEGRATORS: [Integrator; 3] = [Integrator::Euler, Integrator::Leapfrog, Integrator::Rk4];
const MODES: [ConstraintMode; 2] = [ConstraintMode::Acceleration, ConstraintMode::Velocity];
const STEPS: [f64; 2] = [0.002, 0.01];

fn model(xml: &str, integrator: Integrator, mode: ConstraintMode, dt: f64, restitution: f64) -> Model {
    let mut m = Model::from_mjcf(xml).unwrap();
    m.opt.integrator = integrator;
    m.opt.constraint_mode = mode;
    m.opt.timestep = dt;
    m.opt.restitution = restitution;
    m
}

/// Calls `f(integrator, mode, dt)` over every combination.
fn every_scheme(mut f: impl FnMut(Integrator, ConstraintMode, f64)) {
    for integrator in INTEGRATORS {
        for mode in MODES {
            for dt in STEPS {
                f(integrator, mode, dt);
            }
        }
    }
}

const BALL: &str = "<mujoco><worldbody><geom type=\"plane\" size=\"5 5 .1\"/>\
    <body pos=\"0 0 1\"><freejoint/><geom type=\"sphere\" size=\"0.1\" mass=\"1\"/></body></worldbody></mujoco>";

#[test]
fn plastic_impacts_do_not_rebound() {
    // e = 0: a ball dropped 0.9 m stays on the floor, a pendulum swung into its limit in zero
    // gravity stays at it
    let pendulum = "<mujoco><option gravity=\"0 0 0\"/><worldbody><body pos=\"0 0 2\">\
        <joint type=\"hinge\" axis=\"0 1 0\" limited=\"true\" range=\"-30 30\"/>\
        <geom type=\"capsule\" fromto=\"0 0 0 0 0 -1\" size=\"0.05\" mass=\"1\"/></body></worldbody></mujoco>";
    every_scheme(|integrator, mode, dt| {
        let m = model(BALL, integrator, mode, dt, 0.0);
        let mut s = State::new(&m);
        let (mut touched, mut up) = (false, 0.0f64);
        for _ in 0..(2.0 / dt) as usize {
            s.step(&m);
            touched |= s.qpos[2] < 0.1 + 1e-3;
            if touched {
                up = up.max(s.qvel[2]);
            }
        }
        assert!(touched && up < 1e-6, "{integrator:?} {mode:?} dt {dt}: ball leaves the floor at {up} m/s");

        let m = model(pendulum, integrator, mode, dt, 0.0);
        let mut s = State::new(&m);
        s.qvel[0] = 3.0;
        let (mut hit, mut back) = (false, 0.0f64);
        for _ in 0..(0.5 / dt) as usize {
            s.step(&m);
            hit |= s.qpos[0] > 30f64.to_radians() - 1e-3;
            if hit {
                back = back.min(s.qvel[0]);
            }
        }
        assert!(hit && back > -1e-6, "{integrator:?} {mode:?} dt {dt}: pendulum rebounds from its limit at {back} rad/s");
    });
}

/// A chain of `n` thin capsules on hinges limited to ±30°, its free root `height` above the floor,
/// tilted and bent so links land one after another.
fn limited_chain(n: usize, height: f64) -> String {
    let mut xml = format!(
        "<mujoco><worldbody><geom type=\"plane\" size=\"10 10 .1\"/>\
         <body pos=\"0 0 {height}\" euler=\"0 20 0\"><freejoint/><geom type=\"capsule\" fromto=\"0 0 0 0.2 0 0\" size=\"0.01\" mass=\"0.1\"/>"
    );
    for k in 1..n {
        xml += &format!(
            "<body pos=\"0.2 0 0\" euler=\"0 {} 0\"><joint type=\"hinge\" axis=\"0 1 0\" limited=\"true\" range=\"-30 30\"/>\
             <geom type=\"capsule\" fromto=\"0 0 0 0.2 0 0\" size=\"0.01\" mass=\"0.1\"/>",
            if k % 2 == 0 { 25 } else { -25 }
        );
    }
    xml += &"</body>".repeat(n);
    xml + "</worldbody></mujoco>"
}

#[test]
fn limits_hold_while_contacts_act() {
    // a joint moving away from its limit has no limit row, and the contact forces of the landing
    // can turn it back past the limit: every limit holds within 1e-4 rad at the end of every step
    let xml = limited_chain(10, 0.6);
    for friction in [FrictionModel::OneTangent, FrictionModel::Pyramid] {
        for restitution in [0.0] {
            for seed in 1..9 {
                every_scheme(|integrator, mode, dt| {
                    let mut m = model(&xml, integrator, mode, dt, restitution);
                    m.opt.friction = friction;
                    let mut s = State::new(&m);
                    let mut rng = Rng(seed);
                    for v in &mut s.qvel {
                        *v = rng.uniform(-1.0, 1.0);
                    }
                    let mut worst = 0.0f64;
                    for _ in 0..(1.5 / dt) as usize {
                        s.step(&m);
                        for j in 1..m.njnt {
                            let (q, [lo, hi]) = (s.qpos[m.jnt_qposadr[j]], m.jnt_range[j]);
                            worst = worst.max(lo - q).max(q - hi);
                        }
                    }
                    assert!(worst <= 1e-4, "{friction:?} e {restitution} seed {seed} {integrator:?} {mode:?} dt {dt}: a joint ends a step {worst:e} rad past its limit");
                });
            }
        }
    }
}
