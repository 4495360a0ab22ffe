//! Dry friction (`frictionloss`) as exact bounded rows: below its breakaway torque a joint stays
//! at rest (to the LCP's regulariser); above it the joint accelerates with the torque less the friction; K of the
//! rows by test forces equals J M⁻¹ Jᵀ.

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
    let n = sys.kind.len();
    assert_eq!(n, 8, "a ± pair per dof");
    assert!(sys.kind.iter().all(|k| *k == sinew::constraint::RowKind::DryFriction));
    let nv = m.nv;
    // J M⁻¹ Jᵀ by solving M X = Jᵀ (Gaussian elimination on the small dense system)
    let mut minv_jt = vec![0.0; nv * n];
    for r in 0..n {
        let mut a = sys.inertia.clone();
        let mut b: Vec<f64> = (0..nv).map(|k| sys.jac[r * nv + k]).collect();
        for c in 0..nv {
            let p = (c..nv).max_by(|&x, &y| a[x * nv + c].abs().total_cmp(&a[y * nv + c].abs())).unwrap();
            for k in 0..nv {
                a.swap(c * nv + k, p * nv + k);
            }
            b.swap(c, p);
            for i in c + 1..nv {
                let f = a[i * nv + c] / a[c * nv + c];
                for k in c..nv {
                    a[i * nv + k] -= f * a[c * nv + k];
                }
                b[i] -= f * b[c];
            }
        }
        for c in (0..nv).rev() {
            let t: f64 = (c + 1..nv).map(|k| a[c * nv + k] * b[k]).sum();
            b[c] = (b[c] - t) / a[c * nv + c];
        }
        for k in 0..nv {
            minv_jt[k * n + r] = b[k];
        }
    }
    for i in 0..n {
        for j in 0..n {
            let jmj: f64 = (0..nv).map(|k| sys.jac[i * nv + k] * minv_jt[k * n + j]).sum();
            assert!((sys.k[i * n + j] - jmj).abs() < 1e-10 * (1.0 + jmj.abs()), "K[{i}][{j}] {} vs {jmj}", sys.k[i * n + j]);
        }
    }
}
