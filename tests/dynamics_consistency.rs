//! ABA against CRBA + dense solve and against RNEA on random trees with every joint type
//! (Featherstone 2008: ABA Table 7.1, CRBA Table 6.2, RNEA Table 5.1).
#![allow(clippy::needless_range_loop)] // index loops follow the math's notation

mod common;

use common::{random_state, random_tree_mjcf, rel_err, Rng};
use sinew::dynamics::crba::{cholesky_solve, crba};
use sinew::dynamics::rnea::rnea;
use sinew::{Data, Model};

fn check_tree(n: usize, free_root: bool, seed: u64) {
    let m = Model::from_mjcf(&random_tree_mjcf(n, free_root, seed)).expect("random tree compiles");
    let mut r = Rng(seed ^ 0xABCD);
    let mut data = Data::new(&m);
    for _ in 0..5 {
        let (q, v) = random_state(&m, &mut r);
        let tau: Vec<f64> = (0..m.nv).map(|_| r.uniform(-5.0, 5.0)).collect();
        // ABA with the applied force tau only: passive terms come from the model, so subtract them
        sinew::dynamics::kinematics::forward(&m, &q, &v, &mut data.dynamics.kin);
        sinew::dynamics::aba::backward(&m, &data.dynamics.kin, &tau, 0.0, &mut data.dynamics.aba);
        let mut qacc = vec![0.0; m.nv];
        sinew::dynamics::aba::forward(&m, &data.dynamics.kin, &mut data.dynamics.aba, &mut qacc);

        // CRBA: M qacc = tau - C(q, v)
        let mass = crba(&m, &data.dynamics.kin);
        let bias = rnea(&m, &data.dynamics.kin, &vec![0.0; m.nv]);
        let rhs: Vec<f64> = tau.iter().zip(&bias).map(|(t, c)| t - c).collect();
        let qacc_crba = cholesky_solve(&mass, &rhs);
        let e1 = rel_err(&qacc, &qacc_crba);
        assert!(e1 <= 1e-10, "ABA vs CRBA: rel err {e1:e} (n={n}, seed={seed})");

        // RNEA(q, v, qacc) + armature·qacc = tau
        let mut back = rnea(&m, &data.dynamics.kin, &qacc);
        for (d, b) in back.iter_mut().enumerate() {
            *b += m.dof_armature[d] * qacc[d];
        }
        let e2 = rel_err(&back, &tau);
        assert!(e2 <= 1e-10, "RNEA(ABA) vs tau: rel err {e2:e} (n={n}, seed={seed})");
    }
}

#[test]
fn aba_crba_rnea_agree_on_fixed_base_random_trees() {
    for seed in 0..20 {
        check_tree(2 + seed as usize % 12, false, seed);
    }
}

#[test]
fn aba_crba_rnea_agree_on_floating_base_random_trees() {
    for seed in 100..120 {
        check_tree(1 + seed as usize % 15, true, seed);
    }
}

#[test]
fn aba_crba_rnea_agree_on_a_long_chain() {
    check_tree(60, true, 7);
}

#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    let m = Model::from_mjcf(&random_tree_mjcf(12, true, 3)).unwrap();
    let mut data = Data::new(&m);
    let (q, v) = random_state(&m, &mut Rng(9));
    sinew::dynamics::kinematics::forward(&m, &q, &v, &mut data.dynamics.kin);
    let mass = crba(&m, &data.dynamics.kin);
    let nv = m.nv;
    for i in 0..nv {
        for j in 0..nv {
            assert!((mass[i * nv + j] - mass[j * nv + i]).abs() < 1e-12);
        }
        assert!(mass[i * nv + i] > 0.0);
    }
}

#[test]
fn velocity_update_after_an_impulse_equals_a_fresh_aba() {
    // the impact path keeps I^A, U, D⁻¹ and recomputes only v, c, p^A, u (same configuration)
    for (seed, free_root) in [(3, false), (4, true), (5, true)] {
        let m = Model::from_mjcf(&random_tree_mjcf(8, free_root, seed)).expect("random tree compiles");
        let mut r = Rng(seed);
        let (q, v) = random_state(&m, &mut r);
        let (_, v2) = random_state(&m, &mut r);
        let tau: Vec<f64> = (0..m.nv).map(|_| r.uniform(-5.0, 5.0)).collect();
        let mut data = Data::new(&m);
        let mut qacc = vec![0.0; m.nv];
        sinew::dynamics::kinematics::forward(&m, &q, &v, &mut data.dynamics.kin);
        sinew::dynamics::aba::backward(&m, &data.dynamics.kin, &tau, 0.01, &mut data.dynamics.aba);
        sinew::dynamics::kinematics::forward_velocity(&m, &v2, &mut data.dynamics.kin);
        sinew::dynamics::aba::backward_bias(&m, &data.dynamics.kin, &tau, &mut data.dynamics.aba);
        sinew::dynamics::aba::forward(&m, &data.dynamics.kin, &mut data.dynamics.aba, &mut qacc);
        let mut fresh = Data::new(&m);
        let mut qacc_fresh = vec![0.0; m.nv];
        sinew::dynamics::kinematics::forward(&m, &q, &v2, &mut fresh.dynamics.kin);
        sinew::dynamics::aba::backward(&m, &fresh.dynamics.kin, &tau, 0.01, &mut fresh.dynamics.aba);
        sinew::dynamics::aba::forward(&m, &fresh.dynamics.kin, &mut fresh.dynamics.aba, &mut qacc_fresh);
        let e = rel_err(&qacc, &qacc_fresh);
        assert!(e <= 1e-12, "velocity update vs fresh ABA: rel err {e:e} (seed={seed})");
    }
}

/// One body with several joints is one multi-dof node (a 6-dof cap splits it); the same joints in
/// nested bodies at the same pose, the outer ones massless, are one node each. Both must give the
/// same motion, with velocity products (the node's c) included. (Ten dofs on one rigid body are
/// redundant: armature keeps them solvable.)
#[test]
fn joints_sharing_a_body_move_as_nested_massless_bodies() {
    let joints = [
        r#"<joint name="a" type="hinge" axis="0.3 1 0.2" pos="0.1 0 0.05" armature="0.1"/>"#,
        r#"<joint name="b" type="slide" axis="1 0.2 -0.4" armature="0.1"/>"#,
        r#"<joint name="c" type="ball" pos="0 0.1 0" armature="0.1"/>"#,
        r#"<joint name="d" type="ball" pos="0.05 0 0" armature="0.1"/>"#,
        r#"<joint name="e" type="hinge" axis="0 0 1" pos="0 -0.1 0" ref="0.3" armature="0.1"/>"#,
    ];
    let geom = r#"<geom type="box" size="0.1 0.2 0.3" pos="0.1 0.05 0"/><body pos="0.2 0 0"><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.05"/></body>"#;
    let shared = format!(r#"<mujoco><worldbody><body pos="0 0 1" euler="10 20 30">{}{geom}</body></worldbody></mujoco>"#, joints.concat());
    let mut nested = geom.to_string();
    for (k, j) in joints.iter().enumerate().rev() {
        let pose = if k == 0 { r#"pos="0 0 1" euler="10 20 30""# } else { "" };
        nested = format!("<body {pose}>{j}{nested}</body>");
    }
    let nested = format!("<mujoco><worldbody>{nested}</worldbody></mujoco>");
    let (ms, mn) = (Model::from_mjcf(&shared).unwrap(), Model::from_mjcf(&nested).unwrap());
    assert_eq!((ms.nnode, mn.nnode), (3, 6), "ten dofs in one body make a 6-dof and a 4-dof node");
    let mut r = Rng(11);
    let (mut ds, mut dn) = (Data::new(&ms), Data::new(&mn));
    for _ in 0..5 {
        let (q, v) = random_state(&ms, &mut r);
        let tau: Vec<f64> = (0..ms.nv).map(|_| r.uniform(-5.0, 5.0)).collect();
        let mut acc = [vec![0.0; ms.nv], vec![0.0; ms.nv]];
        for ((m, d), a) in [(&ms, &mut ds), (&mn, &mut dn)].into_iter().zip(&mut acc) {
            sinew::dynamics::kinematics::forward(m, &q, &v, &mut d.dynamics.kin);
            sinew::dynamics::aba::backward(m, &d.dynamics.kin, &tau, 0.0, &mut d.dynamics.aba);
            sinew::dynamics::aba::forward(m, &d.dynamics.kin, &mut d.dynamics.aba, a);
        }
        let e = rel_err(&acc[0], &acc[1]);
        assert!(e <= 1e-10, "shared-body vs nested qacc: rel err {e:e}");
    }
}

/// The dynamics are evaluated about the first node's origin, not the world's: a floating tree
/// 20 km from the world origin accelerates as it does at the origin, to the round-off of its
/// positions (with the world origin as reference this measured 6e-6).
#[test]
fn accelerations_do_not_depend_on_where_the_model_is() {
    let m = Model::from_mjcf(&random_tree_mjcf(8, true, 5)).unwrap();
    let mut r = Rng(9);
    let mut data = Data::new(&m);
    for _ in 0..5 {
        let (q, v) = random_state(&m, &mut r);
        let tau: Vec<f64> = (0..m.nv).map(|_| r.uniform(-5.0, 5.0)).collect();
        let mut far = q.clone();
        for (k, shift) in [1.2e4, -2.0e4, 3.0e3].into_iter().enumerate() {
            far[k] += shift;
        }
        let mut acc = [vec![0.0; m.nv], vec![0.0; m.nv]];
        for (qq, a) in [&q, &far].into_iter().zip(&mut acc) {
            sinew::dynamics::kinematics::forward(&m, qq, &v, &mut data.dynamics.kin);
            sinew::dynamics::aba::backward(&m, &data.dynamics.kin, &tau, 0.0, &mut data.dynamics.aba);
            sinew::dynamics::aba::forward(&m, &data.dynamics.kin, &mut data.dynamics.aba, a);
        }
        let e = rel_err(&acc[1], &acc[0]);
        assert!(e <= 1e-10, "qacc 20 km away vs at the origin: rel err {e:e}");
    }
}
