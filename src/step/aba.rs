//! Featherstone's articulated-body algorithm (Featherstone 2008, §7.3, Table 7.1), split in two so
//! the constraint stage can reuse the articulated inertias between the passes.
//!
//! | here      | Featherstone 2008 | meaning                                            |
//! |-----------|-------------------|----------------------------------------------------|
//! | `ia[i]`   | I^A_i             | articulated-body inertia of the subtree at node i  |
//! | `pa[i]`   | p^A_i             | articulated bias force                             |
//! | `u_mat[i]`| U_i = I^A_i S_i   | 6 × n_i                                            |
//! | `d_inv[i]`| D_i⁻¹             | (S_iᵀ U_i + armature)⁻¹, n_i × n_i                 |
//! | `u[i]`    | u_i               | τ_i − S_iᵀ p^A_i                                   |
//! | `a[i]`    | a_i               | spatial acceleration, with gravity as −g at the base |
//!
//! I^A, U and D⁻¹ depend on the configuration only, so they serve every test force of the step.

use crate::math::{ArtInertia, Force, Motion};
use crate::model::{Model, WORLD};

use super::kinematics::KinData;

/// Quantities of the inward pass, kept for the outward pass and for test forces.
#[derive(Clone, Debug, Default)]
pub struct AbaData {
    /// I^A_i (njnt).
    pub ia: Vec<ArtInertia>,
    /// p^A_i (njnt).
    pub pa: Vec<Force>,
    /// U_i columns (njnt × 6).
    pub u_mat: Vec<[Force; 6]>,
    /// D_i⁻¹, row-major n_i × n_i in a 6 × 6 block (njnt).
    pub d_inv: Vec<[f64; 36]>,
    /// u_i (njnt × 6).
    pub u: Vec<[f64; 6]>,
    /// Spatial accelerations a_i in node coordinates (njnt).
    pub a: Vec<Motion>,
    /// A joint whose D_i was not positive definite in the last inward pass.
    pub singular_joint: Option<usize>,
}

impl AbaData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        AbaData {
            ia: vec![ArtInertia::ZERO; m.njnt],
            pa: vec![Force::ZERO; m.njnt],
            u_mat: vec![[Force::ZERO; 6]; m.njnt],
            d_inv: vec![[0.0; 36]; m.njnt],
            u: vec![[0.0; 6]; m.njnt],
            a: vec![Motion::ZERO; m.njnt],
            singular_joint: None,
        }
    }
}

/// Passes 1–2 (inward): I^A, p^A, U, D⁻¹, u for applied joint forces `tau`.
/// `h_damp` adds h·damping to D (implicit damping of semi-implicit Euler, as MuJoCo's `Euler`).
pub fn backward(m: &Model, kin: &KinData, tau: &[f64], h_damp: f64, aba: &mut AbaData) {
    // pass 1: rigid inertias and velocity-product bias forces v ×* I v
    for i in 0..m.njnt {
        aba.ia[i] = m.node_art[i];
        let v = kin.v[i];
        aba.pa[i] = v.cross_force(&m.node_inertia[i].mul_motion(&v));
    }
    aba.singular_joint = None;
    // pass 2: leaves to root
    for i in (0..m.njnt).rev() {
        let k = m.jnt_type[i].nv();
        let da = m.jnt_dofadr[i];
        let s = &kin.s[i];
        let ia = aba.ia[i];
        let mut d = [0.0; 36];
        for c in 0..k {
            aba.u_mat[i][c] = ia.mul_motion(&s[c]);
        }
        for r in 0..k {
            for c in 0..k {
                d[r * 6 + c] = s[r].dot(&aba.u_mat[i][c]);
            }
            d[r * 6 + r] += m.dof_armature[da + r] + h_damp * m.dof_damping[da + r];
            aba.u[i][r] = tau[da + r] - s[r].dot(&aba.pa[i]);
        }
        if !spd_inverse(k, &mut d) {
            aba.singular_joint.get_or_insert(i);
        }
        aba.d_inv[i] = d;
        let p = m.node_parent[i];
        if p == WORLD {
            continue;
        }
        // I^a = I^A − U D⁻¹ Uᵀ;  p^a = p^A + I^A c + U D⁻¹ (u − Uᵀ c)
        let um = &aba.u_mat[i];
        let c = kin.c[i];
        let mut ia_small = ia;
        let mut w = [0.0; 6];
        for r in 0..k {
            let mut acc = 0.0;
            for q in 0..k {
                ia_small.sub_outer(&um[r], &um[q], d[r * 6 + q]);
                acc += d[r * 6 + q] * (aba.u[i][q] - c.dot(&um[q]));
            }
            w[r] = acc;
        }
        let mut pa = aba.pa[i] + ia.mul_motion(&c);
        for r in 0..k {
            pa += um[r] * w[r];
        }
        let x = kin.x_up[i];
        let moved = ia_small.to_parent(&x);
        aba.ia[p].add(&moved);
        aba.pa[p] += x.inv_apply_force(&pa);
    }
}

/// The inward pass's bias terms p^A and u alone, for new velocities and forces `tau` on the
/// configuration whose I^A, U and D⁻¹ are already in `aba` (after an impulse).
pub fn backward_bias(m: &Model, kin: &KinData, tau: &[f64], aba: &mut AbaData) {
    for i in 0..m.njnt {
        let v = kin.v[i];
        aba.pa[i] = v.cross_force(&m.node_inertia[i].mul_motion(&v));
    }
    for i in (0..m.njnt).rev() {
        let k = m.jnt_type[i].nv();
        let da = m.jnt_dofadr[i];
        for r in 0..k {
            aba.u[i][r] = tau[da + r] - kin.s[i][r].dot(&aba.pa[i]);
        }
        let p = m.node_parent[i];
        if p == WORLD {
            continue;
        }
        // p^a = p^A + I^A c + U D⁻¹ (u − Uᵀ c)
        let (um, d, c) = (&aba.u_mat[i], &aba.d_inv[i], kin.c[i]);
        let mut pa = aba.pa[i] + aba.ia[i].mul_motion(&c);
        for r in 0..k {
            let mut w = 0.0;
            for q in 0..k {
                w += d[r * 6 + q] * (aba.u[i][q] - c.dot(&um[q]));
            }
            pa += um[r] * w;
        }
        aba.pa[p] += kin.x_up[i].inv_apply_force(&pa);
    }
}

/// Pass 3 (outward): accelerations `qacc` (nv) and spatial accelerations, with the fictitious
/// base acceleration −g standing in for gravity (Featherstone 2008, §5.3).
pub fn forward(m: &Model, kin: &KinData, aba: &mut AbaData, qacc: &mut [f64]) {
    let a0 = Motion::new(glam::DVec3::ZERO, -m.opt.gravity);
    for i in 0..m.njnt {
        let p = m.node_parent[i];
        let a_parent = if p == WORLD { a0 } else { aba.a[p] };
        let a = kin.x_up[i].apply_motion(&a_parent) + kin.c[i];
        aba.a[i] = joint_accel(m, kin, aba, i, &aba.u[i], a, qacc);
    }
}

/// One node of the outward pass: q̈_i = D_i⁻¹(u_i − U_iᵀ a'_i) into `qacc`, returning
/// a_i = a'_i + S_i q̈_i. Shared by the main pass and the test-force delta pass.
#[inline]
pub fn joint_accel(m: &Model, kin: &KinData, aba: &AbaData, i: usize, u: &[f64; 6], a_prime: Motion, qacc: &mut [f64]) -> Motion {
    let k = m.jnt_type[i].nv();
    let da = m.jnt_dofadr[i];
    let mut rhs = [0.0; 6];
    for r in 0..k {
        rhs[r] = u[r] - a_prime.dot(&aba.u_mat[i][r]);
    }
    let d = &aba.d_inv[i];
    let mut a = a_prime;
    for r in 0..k {
        let mut x = 0.0;
        for q in 0..k {
            x += d[r * 6 + q] * rhs[q];
        }
        qacc[da + r] = x;
        a += kin.s[i][r] * x;
    }
    a
}

/// In-place inverse of a symmetric positive-definite k × k matrix (row-major in a 6 × 6 block) by
/// Cholesky factorisation. Returns false, leaving zeros, when it is not positive definite.
pub fn spd_inverse(k: usize, d: &mut [f64; 36]) -> bool {
    if k == 1 {
        let ok = d[0] > 1e-300 && d[0].is_finite();
        d[0] = if ok { 1.0 / d[0] } else { 0.0 };
        return ok;
    }
    // L Lᵀ = D
    let mut l = [0.0; 36];
    let scale = (0..k).map(|i| d[i * 6 + i].abs()).fold(0.0, f64::max);
    for j in 0..k {
        let mut s = d[j * 6 + j];
        for q in 0..j {
            s -= l[j * 6 + q] * l[j * 6 + q];
        }
        if !(s > 1e-14 * scale) || scale == 0.0 {
            *d = [0.0; 36];
            return false;
        }
        let ljj = s.sqrt();
        l[j * 6 + j] = ljj;
        for i in j + 1..k {
            let mut s = d[i * 6 + j];
            for q in 0..j {
                s -= l[i * 6 + q] * l[j * 6 + q];
            }
            l[i * 6 + j] = s / ljj;
        }
    }
    // D⁻¹ = L⁻ᵀ L⁻¹, column by column
    let mut inv = [0.0; 36];
    for c in 0..k {
        let mut y = [0.0; 6];
        for i in 0..k {
            let mut s = if i == c { 1.0 } else { 0.0 };
            for q in 0..i {
                s -= l[i * 6 + q] * y[q];
            }
            y[i] = s / l[i * 6 + i];
        }
        for i in (0..k).rev() {
            let mut s = y[i];
            for q in i + 1..k {
                s -= l[q * 6 + i] * inv[q * 6 + c];
            }
            inv[i * 6 + c] = s / l[i * 6 + i];
        }
    }
    *d = inv;
    true
}
