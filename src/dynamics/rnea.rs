//! Recursive Newton–Euler inverse dynamics (Featherstone 2008, §5.3, Table 5.1).

use crate::math::{Force, Motion};
use crate::model::{Model, WORLD};
use crate::dynamics::kinematics::KinData;

/// τ = ID(q, q̇, q̈) for the rigid bodies (armature and passive forces excluded), gravity as the
/// fictitious base acceleration −g. `kin` must hold the kinematics of (q, q̇); in its world
/// coordinates every ^iX_λ is the identity.
pub fn rnea(m: &Model, kin: &KinData, qacc: &[f64]) -> Vec<f64> {
    let n = m.nnode;
    let mut a = vec![Motion::ZERO; n];
    let mut f = vec![Force::ZERO; n];
    let a0 = Motion::new(glam::DVec3::ZERO, -m.opt.gravity);
    // pass 1: accelerations and body forces
    for i in 0..n {
        let p = m.node_parent[i];
        let ap = if p == WORLD { a0 } else { a[p] };
        let mut ai = ap + kin.c[i];
        for k in 0..m.node_nv[i] {
            ai += kin.s[i][k] * qacc[m.node_dofadr[i] + k];
        }
        a[i] = ai;
        let inertia = &kin.inertia[i];
        f[i] = inertia.mul_motion(&ai) + kin.v[i].cross_force(&inertia.mul_motion(&kin.v[i]));
    }
    // pass 2: joint forces, leaves to root
    let mut tau = vec![0.0; m.nv];
    for i in (0..n).rev() {
        for k in 0..m.node_nv[i] {
            tau[m.node_dofadr[i] + k] = kin.s[i][k].dot(&f[i]);
        }
        let p = m.node_parent[i];
        if p != WORLD {
            let fp = f[i];
            f[p] += fp;
        }
    }
    tau
}
