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
        sinew::step::kinematics::forward(&m, &q, &v, &mut data.kin);
        sinew::step::aba::backward(&m, &data.kin, &tau, 0.0, &mut data.aba);
        let mut qacc = vec![0.0; m.nv];
        sinew::step::aba::forward(&m, &data.kin, &mut data.aba, &mut qacc);

        // CRBA: M qacc = tau - C(q, v)
        let mass = crba(&m, &data.kin);
        let bias = rnea(&m, &data.kin, &vec![0.0; m.nv]);
        let rhs: Vec<f64> = tau.iter().zip(&bias).map(|(t, c)| t - c).collect();
        let qacc_crba = cholesky_solve(&mass, &rhs);
        let e1 = rel_err(&qacc, &qacc_crba);
        assert!(e1 <= 1e-10, "ABA vs CRBA: rel err {e1:e} (n={n}, seed={seed})");

        // RNEA(q, v, qacc) + armature·qacc = tau
        let mut back = rnea(&m, &data.kin, &qacc);
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
    sinew::step::kinematics::forward(&m, &q, &v, &mut data.kin);
    let mass = crba(&m, &data.kin);
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
        sinew::step::kinematics::forward(&m, &q, &v, &mut data.kin);
        sinew::step::aba::backward(&m, &data.kin, &tau, 0.01, &mut data.aba);
        sinew::step::kinematics::forward_velocity(&m, &v2, &mut data.kin);
        sinew::step::aba::backward_bias(&m, &data.kin, &tau, &mut data.aba);
        sinew::step::aba::forward(&m, &data.kin, &mut data.aba, &mut qacc);
        let mut fresh = Data::new(&m);
        let mut qacc_fresh = vec![0.0; m.nv];
        sinew::step::kinematics::forward(&m, &q, &v2, &mut fresh.kin);
        sinew::step::aba::backward(&m, &fresh.kin, &tau, 0.01, &mut fresh.aba);
        sinew::step::aba::forward(&m, &fresh.kin, &mut fresh.aba, &mut qacc_fresh);
        let e = rel_err(&qacc, &qacc_fresh);
        assert!(e <= 1e-12, "velocity update vs fresh ABA: rel err {e:e} (seed={seed})");
    }
}
