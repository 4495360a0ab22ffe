//! Featherstone's articulated-body algorithm (Featherstone 2008, §7.3, Table 7.1), split in two so
//! the constraint stage can reuse the articulated inertias between the passes. Everything is in
//! the world coordinates of [`KinData`] (about its `origin`), so every ^iX_λ of the table is the
//! identity: a child's I^a and p^a add to its parent's as they are, and a parent's acceleration is
//! its child's a'.
//!
//! | here      | Featherstone 2008 | meaning                                            |
//! |-----------|-------------------|----------------------------------------------------|
//! | `ia[i]`   | I^A_i             | articulated-body inertia of the subtree at node i  |
//! | `pa[i]`   | p^A_i             | articulated bias force                             |
//! | `u_mat[i]`| U_i = I^A_i S_i   | 6 × n_i                                            |
//! | `d_fac[i]`| D_i = L Lᵀ        | D_i = S_iᵀ U_i + armature, factorised (1 dof: D⁻¹) |
//! | `u[i]`    | u_i               | τ_i − S_iᵀ p^A_i                                   |
//! | `a[i]`    | a_i               | spatial acceleration, with gravity as −g at the base |
//!
//! I^A, U and D's factor depend on the configuration only, so they serve every test force of the step.

use crate::math::{ArtInertia, Force, Motion};
use crate::model::{Model, WORLD};

use super::kinematics::KinData;

/// Quantities of the inward pass, kept for the outward pass and for test forces.
#[derive(Clone, Debug, Default)]
pub struct AbaData {
    /// I^A_i (nnode).
    pub ia: Vec<ArtInertia>,
    /// p^A_i (nnode).
    pub pa: Vec<Force>,
    /// U_i columns (nnode × 6).
    pub u_mat: Vec<[Force; 6]>,
    /// D_i for [`solve_d`]: 1/D_i for one dof, else the Cholesky factor L (D_i = L Lᵀ, lower
    /// triangle row-major in a 6 × 6 block, diagonal stored as 1/L_jj) (nnode).
    pub d_fac: Vec<[f64; 36]>,
    /// u_i (nnode × 6).
    pub u: Vec<[f64; 6]>,
    /// Spatial accelerations a_i (nnode).
    pub a: Vec<Motion>,
    /// A joint whose D_i was not positive definite in the last inward pass.
    pub singular_node: Option<usize>,
}

impl AbaData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        AbaData {
            ia: vec![ArtInertia::ZERO; m.nnode],
            pa: vec![Force::ZERO; m.nnode],
            u_mat: vec![[Force::ZERO; 6]; m.nnode],
            d_fac: vec![[0.0; 36]; m.nnode],
            u: vec![[0.0; 6]; m.nnode],
            a: vec![Motion::ZERO; m.nnode],
            singular_node: None,
        }
    }
}

/// Passes 1–2 (inward): I^A, p^A, U, D (factorised), u for applied joint forces `tau`.
/// `h_damp` adds h·damping to D (implicit damping of semi-implicit Euler, as MuJoCo's `Euler`).
pub fn backward(m: &Model, kin: &KinData, tau: &[f64], h_damp: f64, aba: &mut AbaData) {
    // pass 1: rigid inertias and velocity-product bias forces v ×* I v
    for (ia, inertia) in aba.ia.iter_mut().zip(&kin.inertia) {
        *ia = inertia.to_art();
    }
    rigid_bias(kin, &mut aba.pa);
    aba.singular_node = None;
    let AbaData { ia: ia_all, pa: pa_all, u_mat, d_fac, u, singular_node, .. } = aba;
    // pass 2: leaves to root
    for i in (0..m.nnode).rev() {
        let k = m.node_nv[i];
        let da = m.node_dofadr[i];
        let s = &kin.s[i];
        let ia = &ia_all[i];
        let (um, d, ui) = (&mut u_mat[i], &mut d_fac[i], &mut u[i]);
        for c in 0..k {
            um[c] = ia.mul_motion(&s[c]);
        }
        for r in 0..k {
            for c in 0..k {
                d[r * 6 + c] = s[r].dot(&um[c]);
            }
            d[r * 6 + r] += m.dof_armature[da + r] + h_damp * m.dof_damping[da + r];
            ui[r] = tau[da + r] - s[r].dot(&pa_all[i]);
        }
        if !factorise(k, d) {
            singular_node.get_or_insert(i);
        }
        let p = m.node_parent[i];
        if p == WORLD {
            continue;
        }
        // I^a = I^A − U D⁻¹ Uᵀ (= I^A − V Vᵀ with V = U L⁻ᵀ)
        let mut ia_small = *ia;
        if k == 1 {
            ia_small.sub_outer(&um[0], &um[0], d[0]);
        } else {
            let mut v = [Force::ZERO; 6];
            for r in 0..k {
                let mut col = um[r];
                for q in 0..r {
                    col -= v[q] * d[r * 6 + q];
                }
                v[r] = col * d[r * 6 + r];
                ia_small.sub_outer(&v[r], &v[r], 1.0);
            }
        }
        let pa = articulated_bias(k, ia, um, d, ui, &kin.c[i], &pa_all[i]);
        ia_all[p].add(&ia_small);
        pa_all[p] += pa;
    }
}

/// The inward pass's bias terms p^A and u alone, for new velocities and forces `tau` on the
/// configuration whose I^A, U and D's factor are already in `aba` (after an impulse).
pub fn backward_bias(m: &Model, kin: &KinData, tau: &[f64], aba: &mut AbaData) {
    rigid_bias(kin, &mut aba.pa);
    for i in (0..m.nnode).rev() {
        let k = m.node_nv[i];
        let da = m.node_dofadr[i];
        for r in 0..k {
            aba.u[i][r] = tau[da + r] - kin.s[i][r].dot(&aba.pa[i]);
        }
        let p = m.node_parent[i];
        if p == WORLD {
            continue;
        }
        let pa = articulated_bias(k, &aba.ia[i], &aba.u_mat[i], &aba.d_fac[i], &aba.u[i], &kin.c[i], &aba.pa[i]);
        aba.pa[p] += pa;
    }
}

/// Pass 1's velocity-product bias forces v_i ×* I_i v_i of the rigid bodies.
fn rigid_bias(kin: &KinData, pa: &mut [Force]) {
    for ((p, v), inertia) in pa.iter_mut().zip(&kin.v).zip(&kin.inertia) {
        *p = v.cross_force(&inertia.mul_motion(v));
    }
}

/// The bias force node i hands its parent (before the transform):
/// p^a = p^A + I^A c + U D⁻¹ (u − Uᵀ c) (Featherstone 2008, Table 7.1).
#[inline(always)]
fn articulated_bias(k: usize, ia: &ArtInertia, um: &[Force; 6], d: &[f64; 36], u: &[f64; 6], c: &Motion, pa: &Force) -> Force {
    let mut w = [0.0; 6];
    for r in 0..k {
        w[r] = u[r] - c.dot(&um[r]);
    }
    solve_d(k, d, &mut w);
    let mut out = *pa + ia.mul_motion(c);
    for r in 0..k {
        out += um[r] * w[r];
    }
    out
}

/// Pass 3 (outward): accelerations `qacc` (nv) and spatial accelerations, with the fictitious
/// base acceleration −g standing in for gravity (Featherstone 2008, §5.3).
pub fn forward(m: &Model, kin: &KinData, aba: &mut AbaData, qacc: &mut [f64]) {
    let a0 = Motion::new(glam::DVec3::ZERO, -m.opt.gravity);
    for i in 0..m.nnode {
        let p = m.node_parent[i];
        let a_parent = if p == WORLD { a0 } else { aba.a[p] };
        let a = a_parent + kin.c[i];
        aba.a[i] = joint_accel(m, kin, aba, i, &aba.u[i], a, qacc);
    }
}

/// One node of the outward pass: q̈_i = D_i⁻¹(u_i − U_iᵀ a'_i) into `qacc`, returning
/// a_i = a'_i + S_i q̈_i. Shared by the main pass and the test-force delta pass.
#[inline]
pub fn joint_accel(m: &Model, kin: &KinData, aba: &AbaData, i: usize, u: &[f64; 6], a_prime: Motion, qacc: &mut [f64]) -> Motion {
    let k = m.node_nv[i];
    let da = m.node_dofadr[i];
    let mut rhs = [0.0; 6];
    for r in 0..k {
        rhs[r] = u[r] - a_prime.dot(&aba.u_mat[i][r]);
    }
    solve_d(k, &aba.d_fac[i], &mut rhs);
    let mut a = a_prime;
    for r in 0..k {
        qacc[da + r] = rhs[r];
        a += kin.s[i][r] * rhs[r];
    }
    a
}

/// Factorises a symmetric positive-definite k × k matrix D (row-major in a 6 × 6 block) in place
/// for [`solve_d`]: 1/D for k = 1, else its Cholesky factor L (D = L Lᵀ) with 1/L_jj on the
/// diagonal, so solves multiply. Returns false, leaving zeros, when D is not positive definite.
pub fn factorise(k: usize, d: &mut [f64; 36]) -> bool {
    if k == 1 {
        let ok = d[0] > 1e-300 && d[0].is_finite();
        d[0] = if ok { 1.0 / d[0] } else { 0.0 };
        return ok;
    }
    let scale = (0..k).map(|i| d[i * 6 + i].abs()).fold(0.0, f64::max);
    for j in 0..k {
        let mut s = d[j * 6 + j];
        for q in 0..j {
            s -= d[j * 6 + q] * d[j * 6 + q];
        }
        if s.is_nan() || s <= 1e-14 * scale || scale == 0.0 {
            *d = [0.0; 36];
            return false;
        }
        let inv = 1.0 / s.sqrt();
        d[j * 6 + j] = inv;
        for i in j + 1..k {
            let mut s = d[i * 6 + j];
            for q in 0..j {
                s -= d[i * 6 + q] * d[j * 6 + q];
            }
            d[i * 6 + j] = s * inv;
        }
    }
    true
}

/// x ← D⁻¹ x on the first k entries, D as [`factorise`] left it (two triangular solves for k > 1).
#[inline]
pub fn solve_d(k: usize, d: &[f64; 36], x: &mut [f64; 6]) {
    if k == 1 {
        x[0] *= d[0];
        return;
    }
    for i in 0..k {
        let mut s = x[i];
        for q in 0..i {
            s -= d[i * 6 + q] * x[q];
        }
        x[i] = s * d[i * 6 + i];
    }
    for i in (0..k).rev() {
        let mut s = x[i];
        for q in i + 1..k {
            s -= d[q * 6 + i] * x[q];
        }
        x[i] = s * d[i * 6 + i];
    }
}
