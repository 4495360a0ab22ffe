//! Invariants of the constraint-free dynamics: momentum of free systems in zero gravity, the
//! analytic torque-free asymmetric top, bounded energy of an undamped chain, unit quaternions.
#![allow(clippy::needless_range_loop)] // index loops follow the math's notation

mod common;

use common::{kinetic_energy, potential_energy, random_tree_mjcf_with, world_momentum, Rng};
use sinew::model::Integrator;
use sinew::{Model, State};

fn with(xml: &str, integrator: &str, dt: f64) -> Model {
    // drop any <option .../> the generator wrote, then set ours
    let mut xml = xml.to_string();
    if let Some(a) = xml.find("<option") {
        let b = a + xml[a..].find("/>").unwrap() + 2;
        xml.replace_range(a..b, "");
    }
    let xml = xml.replacen("<mujoco>", &format!("<mujoco><option integrator=\"{integrator}\" timestep=\"{dt}\" gravity=\"0 0 0\"><flag contact=\"disable\"/></option>"), 1);
    Model::from_mjcf(&xml).unwrap()
}

/// Relative drift of total momentum over `steps` steps from a random initial velocity.
fn momentum_drift(m: &Model, steps: usize, seed: u64) -> (f64, f64) {
    let mut s = State::new(m);
    let mut r = Rng(seed);
    for v in &mut s.qvel {
        *v = r.uniform(-1.0, 1.0);
    }
    s.forward(m);
    let (l0, p0) = world_momentum(m, &s.data.dynamics.kin);
    let (mut el, mut ep) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        s.step(m);
        sinew::dynamics::kinematics::forward(m, &s.qpos, &s.qvel, &mut s.data.dynamics.kin);
        let (l, p) = world_momentum(m, &s.data.dynamics.kin);
        el = el.max((l - l0).length() / l0.length());
        ep = ep.max((p - p0).length() / p0.length());
    }
    (el, ep)
}

const FREE_BODY: &str = "<mujoco><worldbody><body pos=\"0.1 0.2 0.3\" euler=\"10 20 30\"><freejoint/>\
    <geom type=\"box\" size=\"0.1 0.2 0.3\" pos=\"0.05 0 0.02\"/><geom type=\"sphere\" size=\"0.1\" pos=\"0 0.2 0\"/>\
    </body></worldbody></mujoco>";

fn free_chain() -> String {
    random_tree_mjcf_with(6, true, 42, false)
}

#[test]
fn free_body_in_zero_gravity_conserves_momentum() {
    let m = with(FREE_BODY, "RK4", 1e-4);
    let (el, ep) = momentum_drift(&m, 10_000, 1);
    assert!(el <= 1e-10 && ep <= 1e-10, "angular drift {el:e}, linear drift {ep:e}");
}

#[test]
fn free_chain_in_zero_gravity_conserves_momentum() {
    let m = with(&free_chain(), "RK4", 1e-4);
    assert!(m.dof_damping.iter().chain(&m.dof_armature).all(|&d| d == 0.0));
    let (el, ep) = momentum_drift(&m, 10_000, 2);
    assert!(el <= 1e-10 && ep <= 1e-10, "angular drift {el:e}, linear drift {ep:e}");
}

/// Jacobi elliptic functions sn, cn, dn of u with parameter m = k² (descending Landen / AGM,
/// Abramowitz & Stegun 16.4).
fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    let mut a = [1.0f64; 16];
    let mut c = [0.0f64; 16];
    let mut b = (1.0 - m).sqrt();
    c[0] = m.sqrt();
    let mut n = 0;
    while c[n].abs() > 1e-16 && n < 15 {
        a[n + 1] = 0.5 * (a[n] + b);
        c[n + 1] = 0.5 * (a[n] - b);
        b = (a[n] * b).sqrt();
        n += 1;
    }
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    for i in (1..=n).rev() {
        phi = 0.5 * (phi + (c[i] / a[i] * phi.sin()).asin());
    }
    let (sn, cn) = (phi.sin(), phi.cos());
    (sn, cn, (1.0 - m * sn * sn).sqrt())
}

#[test]
fn torque_free_asymmetric_body_matches_the_analytic_solution() {
    // a box at the body origin: principal axes = body axes, I1 < I2 < I3
    let xml = "<mujoco><option integrator=\"RK4\" timestep=\"1e-4\" gravity=\"0 0 0\"/><worldbody>\
        <body><freejoint/><geom type=\"box\" size=\"0.3 0.2 0.1\" mass=\"2\"/></body></worldbody></mujoco>";
    let m = Model::from_mjcf(xml).unwrap();
    let i = m.body_inertia[1];
    let (i1, i2, i3) = (i.col(0).x, i.col(1).y, i.col(2).z);
    assert!(i1 < i2 && i2 < i3);
    let (w10, w30) = (1.0, 3.0);
    let e2 = i1 * w10 * w10 + i3 * w30 * w30; // 2E
    let l2 = (i1 * w10).powi(2) + (i3 * w30).powi(2);
    assert!(l2 > e2 * i2, "case L² > 2E I2");
    let amp1 = ((e2 * i3 - l2) / (i1 * (i3 - i1))).sqrt();
    let amp2 = ((e2 * i3 - l2) / (i2 * (i3 - i2))).sqrt();
    let amp3 = ((l2 - e2 * i1) / (i3 * (i3 - i1))).sqrt();
    let rate = ((i3 - i2) * (l2 - e2 * i1) / (i1 * i2 * i3)).sqrt();
    let k2 = (i2 - i1) * (e2 * i3 - l2) / ((i3 - i2) * (l2 - e2 * i1));

    let mut s = State::new(&m);
    s.qvel[3] = w10;
    s.qvel[5] = w30;
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        s.step(&m);
        let (sn, cn, dn) = jacobi(rate * s.time, k2);
        let exact = [amp1 * cn, amp2 * sn, amp3 * dn];
        for k in 0..3 {
            worst = worst.max((s.qvel[3 + k] - exact[k]).abs() / w30);
        }
    }
    assert!(worst <= 1e-5, "body angular velocity vs Jacobi solution at 10 s: rel err {worst:e}");
}

/// Quaternion and body angular velocity of a torque-free body with principal inertia `i` after
/// `t` seconds from identity, by classical RK4 in R⁷ on q̇ = ½ q ⊗ (0, ω), I ω̇ = −ω × I ω: an
/// integrator independent of the simulator's Lie-group one.
fn euclidean_top(i: [f64; 3], w0: [f64; 3], t: f64, h: f64) -> [f64; 7] {
    let f = |x: &[f64; 7]| -> [f64; 7] {
        let (q, w) = ([x[0], x[1], x[2], x[3]], [x[4], x[5], x[6]]);
        [
            -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]),
            0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]),
            0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]),
            0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]),
            (i[1] - i[2]) * w[1] * w[2] / i[0],
            (i[2] - i[0]) * w[2] * w[0] / i[1],
            (i[0] - i[1]) * w[0] * w[1] / i[2],
        ]
    };
    let add = |x: &[f64; 7], k: &[f64; 7], s: f64| -> [f64; 7] { std::array::from_fn(|n| x[n] + s * k[n]) };
    let mut x = [1.0, 0.0, 0.0, 0.0, w0[0], w0[1], w0[2]];
    for _ in 0..(t / h).round() as usize {
        let k1 = f(&x);
        let k2 = f(&add(&x, &k1, h / 2.0));
        let k3 = f(&add(&x, &k2, h / 2.0));
        let k4 = f(&add(&x, &k3, h));
        x = std::array::from_fn(|n| x[n] + h / 6.0 * (k1[n] + 2.0 * k2[n] + 2.0 * k3[n] + k4[n]));
    }
    x
}

#[test]
fn rk4_rotates_free_and_ball_joints_to_fourth_order() {
    // a torque-free body with I = (1, 2, 3), on a free joint and on a ball joint: the quaternion
    // error after 5 s falls 16-fold as dt halves
    let reference = euclidean_top([1.0, 2.0, 3.0], [1.0, 0.1, 0.2], 5.0, 1e-5);
    // tests/scenes/top.xml, shared with benches/physics_scenes.py
    let template = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/top.xml")).unwrap();
    for joint in ["free", "ball"] {
        let mut errors = vec![];
        for dt in [0.01f64, 0.005] {
            let mut m = Model::from_mjcf(&template.replace("{joint}", joint)).unwrap();
            m.opt.timestep = dt;
            let (qa, da) = (m.jnt_qposadr[0] + if m.nq == 7 { 3 } else { 0 }, m.jnt_dofadr[0] + if m.nv == 6 { 3 } else { 0 });
            let mut s = State::new(&m);
            s.qvel[da..da + 3].copy_from_slice(&[1.0, 0.1, 0.2]);
            for _ in 0..(5.0 / dt).round() as usize {
                s.step(&m);
            }
            let err = (0..4).map(|k| (s.qpos[qa + k] - reference[k]).abs()).fold(0.0, f64::max);
            let werr = (0..3).map(|k| (s.qvel[da + k] - reference[4 + k]).abs()).fold(0.0, f64::max);
            assert!(werr < 1e-9, "{joint} dt {dt}: angular velocity error {werr:e}");
            errors.push(err);
        }
        // MuJoCo 4.0's RK4 on the same model: 2.0e-11 and 1.2e-12
        assert!(errors[0] < 5e-11, "{joint}: quaternion error {:e} at dt 0.01", errors[0]);
        assert!(errors[0] / errors[1] > 12.0, "{joint}: quaternion errors {errors:?} not fourth order");
    }
}

/// Maximum |E − E0| / (M g L) over 10 s of an undamped pendulum chain swinging under gravity.
fn chain_energy_drift(integrator: Integrator, dt: f64) -> f64 {
    let mut xml = String::from("<mujoco><option gravity=\"0 0 -9.81\" timestep=\"DT\"><flag contact=\"disable\"/></option><worldbody>");
    for i in 0..5 {
        xml += &format!("<body pos=\"{} 0 0\"><joint type=\"hinge\" axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0.3 0 0\" size=\"0.04\"/>", if i == 0 { 0.0 } else { 0.3 });
    }
    xml += &"</body>".repeat(5);
    xml += "</worldbody></mujoco>";
    let mut m = Model::from_mjcf(&xml.replace("DT", &dt.to_string())).unwrap();
    m.opt.integrator = integrator;
    let mut s = State::new(&m);
    s.forward(&m);
    let e0 = kinetic_energy(&m, &s.data.dynamics.kin) + potential_energy(&m, &s.data.dynamics.kin);
    // energy scale: the whole chain's mass lifted by its length
    let scale = m.body_mass.iter().sum::<f64>() * 9.81 * 1.5;
    let mut worst = 0.0f64;
    let steps = (10.0 / dt).round() as usize;
    for _ in 0..steps {
        s.step(&m);
        sinew::dynamics::kinematics::forward(&m, &s.qpos, &s.qvel, &mut s.data.dynamics.kin);
        let e = kinetic_energy(&m, &s.data.dynamics.kin) + potential_energy(&m, &s.data.dynamics.kin);
        worst = worst.max((e - e0).abs() / scale);
    }
    worst
}

#[test]
fn undamped_chain_energy_stays_bounded() {
    // measured (this test's eprintln): Euler 0.16 of M g L, leapfrog 0.16 (its velocity-product
    // terms use the step's initial velocity: first order, like Euler), RK4 3e-6, for a 5-link
    // chain swinging from horizontal
    let euler = chain_energy_drift(Integrator::Euler, 1e-3);
    let leapfrog = chain_energy_drift(Integrator::Leapfrog, 1e-3);
    let rk4 = chain_energy_drift(Integrator::Rk4, 1e-3);
    eprintln!("energy drift over 10 s at dt=1e-3: Euler {euler:e}, leapfrog {leapfrog:e}, RK4 {rk4:e}");
    assert!(euler < 0.3, "Euler energy drift {euler:e}");
    assert!(leapfrog < 0.3, "leapfrog energy drift {leapfrog:e}");
    assert!(rk4 < 1e-5, "RK4 energy drift {rk4:e}");
}

#[test]
fn quaternions_stay_unit() {
    let m = with(&free_chain(), "Euler", 5e-3);
    let mut s = State::new(&m);
    let mut r = Rng(5);
    for v in &mut s.qvel {
        *v = r.uniform(-3.0, 3.0);
    }
    for _ in 0..5000 {
        s.step(&m);
    }
    for j in 0..m.njnt {
        let a = m.jnt_qposadr[j];
        let q = match m.jnt_type[j] {
            sinew::model::JointType::Free => &s.qpos[a + 3..a + 7],
            sinew::model::JointType::Ball => &s.qpos[a..a + 4],
            _ => continue,
        };
        let n: f64 = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((n - 1.0).abs() < 1e-12, "joint {j}: |q| = {n}");
    }
}
