//! Composite-rigid-body algorithm for the joint-space inertia matrix (Featherstone 2008, §6.2,
//! Table 6.2), plus a dense Cholesky solve for checks.

use crate::math::Force;
use crate::model::{Model, WORLD};
use crate::dynamics::kinematics::KinData;

/// Dense joint-space inertia M(q) (nv × nv, row-major), armature included.
pub fn crba(m: &Model, kin: &KinData) -> Vec<f64> {
    let nv = m.nv;
    // composite inertias, all in the kinematics' world coordinates (no transforms)
    let mut ic: Vec<_> = kin.inertia.iter().map(|i| i.to_art()).collect();
    for i in (0..m.nnode).rev() {
        let p = m.node_parent[i];
        if p != WORLD {
            let moved = ic[i];
            ic[p].add(&moved);
        }
    }
    let mut mm = vec![0.0; nv * nv];
    for i in 0..m.nnode {
        let di = m.node_dofadr[i];
        for r in 0..m.node_nv[i] {
            let f: Force = ic[i].mul_motion(&kin.s[i][r]);
            let mut j = i;
            loop {
                let dj = m.node_dofadr[j];
                for c in 0..m.node_nv[j] {
                    let x = kin.s[j][c].dot(&f);
                    mm[(di + r) * nv + dj + c] = x;
                    mm[(dj + c) * nv + di + r] = x;
                }
                let p = m.node_parent[j];
                if p == WORLD {
                    break;
                }
                j = p;
            }
        }
    }
    for (d, arm) in m.dof_armature.iter().enumerate() {
        mm[d * nv + d] += arm;
    }
    mm
}

/// Solves A x = b for symmetric positive-definite A (n × n, row-major) by Cholesky.
pub fn cholesky_solve(a: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut s = a[j * n + j];
        for k in 0..j {
            s -= l[j * n + k] * l[j * n + k];
        }
        let d = s.max(0.0).sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * y[k];
        }
        y[i] = s / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut s = y[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
    x
}
