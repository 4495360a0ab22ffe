//! Stage 2 — Featherstone's articulated-body algorithm (Featherstone 2008, §7.3, Table 7.1), split in two so
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
//! | `d_inv[i]`| D_i⁻¹             | D_i = S_iᵀ U_i + armature, inverted                |
//! | `u[i]`    | u_i               | τ_i − S_iᵀ p^A_i                                   |
//! | `a[i]`    | a_i               | spatial acceleration, with gravity as −g at the base |
//!
//! I^A, U and D⁻¹ depend on the configuration only, so they serve every test force of the step.

use crate::math::{ArtInertia, Force, Motion};
use crate::model::{JointType, Model, WORLD};

use super::kinematics::KinData;

/// `$f::<K>(args)` with K the node's dof count `$k` (1 to 6) as a constant, so that the callee's
/// small loops have fixed bounds and unroll.
macro_rules! sized {
    ($k:expr, $f:ident($($arg:expr),*)) => {
        match $k {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            5 => $f::<5>($($arg),*),
            _ => $f::<6>($($arg),*),
        }
    };
}

/// Quantities of the inward pass, kept for the outward pass and for test forces.
#[derive(Clone, Debug, Default)]
pub struct AbaData {
    /// I^A_i (nnode).
    pub ia: Vec<ArtInertia>,
    /// p^A_i (nnode).
    pub pa: Vec<Force>,
    /// U_i columns (nnode × 6).
    pub u_mat: Vec<[Force; 6]>,
    /// D_i⁻¹, inverted once so that each solve is a product (k × k, row-major in a 6 × 6 block) (nnode).
    pub d_inv: Vec<[f64; 36]>,
    /// u_i (nnode × 6).
    pub u: Vec<[f64; 6]>,
    /// Spatial accelerations a_i (nnode).
    pub a: Vec<Motion>,
    /// A joint whose D_i was not positive definite in the last inward pass.
    pub singular_node: Option<usize>,
    /// Whether any node may be locked ([`AbaData::lock_cap`]); false outside a step.
    pub locking: bool,
    /// Per node: the dry friction's cap of a one-dof joint the step may hold still (0: none), a
    /// joint stuck by its friction (`constraint::dry_friction`).
    pub lock_cap: Vec<f64>,
    /// Per node: the acceleration a held joint is given, −q̇/h (its velocity ends the step at 0).
    pub lock_qacc: Vec<f64>,
    /// Per node: whether the last inward pass held the joint (hybrid dynamics, Featherstone 2008,
    /// §9.2: a joint of known acceleration; its D⁻¹ left at 0, so the test forces pass through it).
    pub locked: Vec<bool>,
    /// Per node: D of a held joint (un-inverted).
    pub lock_d: Vec<f64>,
    /// Per node: the torque a held joint needs for its acceleration, from the last outward pass.
    pub lock_torque: Vec<f64>,
}

impl AbaData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        AbaData {
            ia: vec![ArtInertia::ZERO; m.nnode],
            pa: vec![Force::ZERO; m.nnode],
            u_mat: vec![[Force::ZERO; 6]; m.nnode],
            d_inv: vec![[0.0; 36]; m.nnode],
            u: vec![[0.0; 6]; m.nnode],
            a: vec![Motion::ZERO; m.nnode],
            singular_node: None,
            locking: false,
            lock_cap: vec![0.0; m.nnode],
            lock_qacc: vec![0.0; m.nnode],
            locked: vec![false; m.nnode],
            lock_d: vec![0.0; m.nnode],
            lock_torque: vec![0.0; m.nnode],
        }
    }
}

/// Passes 1–2 (inward): I^A, p^A, U, D⁻¹, u for applied joint forces `tau`.
/// `h_damp` adds h·damping to D (implicit damping of semi-implicit Euler, as MuJoCo's `Euler`;
/// with the actuators' velocity feedback, as its `implicitfast`).
pub fn backward(m: &Model, kin: &KinData, tau: &[f64], h_damp: f64, aba: &mut AbaData) {
    // pass 1: rigid inertias and velocity-product bias forces v ×* I v
    for (ia, inertia) in aba.ia.iter_mut().zip(&kin.inertia) {
        *ia = inertia.to_art();
    }
    rigid_bias(kin, &mut aba.pa);
    aba.singular_node = None;
    let AbaData { ia: ia_all, pa: pa_all, u_mat, d_inv, u, singular_node, locking, lock_cap, lock_qacc, locked, lock_d, .. } = aba;
    // pass 2: leaves to root, each node at its own size so the small loops unroll
    for i in (0..m.nnode).rev() {
        let p = m.node_parent[i];
        let args = (m, kin, tau, h_damp, i, &ia_all[i], &pa_all[i]);
        let (um, d, ui) = (&mut u_mat[i], &mut d_inv[i], &mut u[i]);
        if *locking && lock_cap[i] > 0.0 {
            let (ok, held, ia_small, pa) = inward_held(args, um, d, ui, (lock_cap[i], lock_qacc[i], &mut lock_d[i]), p != WORLD);
            locked[i] = held;
            if !ok {
                singular_node.get_or_insert(i);
            }
            if p != WORLD {
                ia_all[p].add(&ia_small);
                pa_all[p] += pa;
            }
            continue;
        }
        locked[i] = false;
        let (ok, ia_small, pa) = sized!(m.node_nv[i], inward(args, um, d, ui, p != WORLD));
        if !ok {
            singular_node.get_or_insert(i);
        }
        if p != WORLD {
            ia_all[p].add(&ia_small);
            pa_all[p] += pa;
        }
    }
}

/// Node i's inward step with K dofs: U = I^A S, D⁻¹, u = τ − Sᵀ p^A and, when it has a parent,
/// the I^a = I^A − U D⁻¹ Uᵀ and p^a it hands on. Returns whether D was positive definite. A free
/// joint's first three columns are the world translations (0, e_k): their U is a column of I^A's
/// lower blocks and their rows of Sᵀ pick components, with no products.
#[allow(clippy::type_complexity)]
#[inline(always)]
fn inward<const K: usize>(
    (m, kin, tau, h_damp, i, ia, pa): (&Model, &KinData, &[f64], f64, usize, &ArtInertia, &Force),
    um: &mut [Force; 6],
    d: &mut [f64; 36],
    ui: &mut [f64; 6],
    has_parent: bool,
) -> (bool, ArtInertia, Force) {
    let da = m.node_dofadr[i];
    let s = &kin.s[i];
    let free = K == 6 && m.jnt_type[m.node_jntadr[i]] == JointType::Free;
    // Sᵀ f for column r
    let s_dot = |r: usize, f: &Force| if free && r < 3 { f.lin[r] } else { s[r].dot(f) };
    for c in 0..K {
        um[c] = if free && c < 3 { Force::new(ia.b.col(c), ia.c.col(c)) } else { ia.mul_motion(&s[c]) };
    }
    for r in 0..K {
        for c in 0..K {
            d[r * 6 + c] = s_dot(r, &um[c]);
        }
        d[r * 6 + r] += m.dof_armature[da + r] + h_damp * (m.dof_damping[da + r] + m.dof_actdamping[da + r]);
        ui[r] = tau[da + r] - s_dot(r, pa);
    }
    let ok = invert_d(K, d);
    if !has_parent {
        return (ok, ArtInertia::ZERO, Force::ZERO);
    }
    // I^a = I^A − U D⁻¹ Uᵀ = I^A − Σ_r U_r W_rᵀ with W = U D⁻¹
    let mut ia_small = *ia;
    for r in 0..K {
        let mut w = Force::ZERO;
        for c in 0..K {
            w += um[c] * d[c * 6 + r];
        }
        ia_small.sub_outer(&um[r], &w, 1.0);
    }
    (ok, ia_small, articulated_bias::<K>(ia, um, d, ui, &kin.c[i], pa))
}

/// [`inward`] for a one-dof joint that the step may hold still: held when its dry friction's
/// `cap` alone could give it the acceleration `qdd` (|D q̈| ≤ cap), as a joint of known
/// acceleration (Featherstone 2008, §9.2): D⁻¹ left at 0, its whole I^A handed on and
/// p^a = p^A + I^A c + U q̈. Returns whether D was positive definite, whether it is held, I^a, p^a.
#[allow(clippy::type_complexity)]
fn inward_held(
    args: (&Model, &KinData, &[f64], f64, usize, &ArtInertia, &Force),
    um: &mut [Force; 6],
    d: &mut [f64; 36],
    ui: &mut [f64; 6],
    (cap, qdd, d_held): (f64, f64, &mut f64),
    has_parent: bool,
) -> (bool, bool, ArtInertia, Force) {
    let (m, kin, _, h_damp, i, ia, pa) = args;
    let (ia, pa, c) = (*ia, *pa, kin.c[i]);
    let (ok, ia_small, pa_small) = inward::<1>(args, um, d, ui, has_parent);
    let da = m.node_dofadr[i];
    let dd = kin.s[i][0].dot(&um[0]) + m.dof_armature[da] + h_damp * (m.dof_damping[da] + m.dof_actdamping[da]);
    if !ok || (dd * qdd).abs() > cap {
        return (ok, false, ia_small, pa_small);
    }
    *d_held = dd;
    d[0] = 0.0;
    (ok, true, ia, pa + ia.mul_motion(&c) + um[0] * qdd)
}

/// The inward pass's bias terms p^A and u alone, for new velocities and forces `tau` on the
/// configuration whose I^A, U and D⁻¹ are already in `aba` (after an impulse).
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
        let pa = if aba.locked[i] {
            aba.pa[i] + aba.ia[i].mul_motion(&kin.c[i]) + aba.u_mat[i][0] * aba.lock_qacc[i]
        } else {
            sized!(k, articulated_bias(&aba.ia[i], &aba.u_mat[i], &aba.d_inv[i], &aba.u[i], &kin.c[i], &aba.pa[i]))
        };
        aba.pa[p] += pa;
    }
}

/// Pass 1's velocity-product bias forces v_i ×* I_i v_i of the rigid bodies.
fn rigid_bias(kin: &KinData, pa: &mut [Force]) {
    for ((p, v), inertia) in pa.iter_mut().zip(&kin.v).zip(&kin.inertia) {
        *p = v.cross_force(&inertia.mul_motion(v));
    }
}

/// The bias force a node of K dofs hands its parent:
/// p^a = p^A + I^A c + U D⁻¹ (u − Uᵀ c) (Featherstone 2008, Table 7.1).
#[inline(always)]
fn articulated_bias<const K: usize>(ia: &ArtInertia, um: &[Force; 6], d: &[f64; 36], u: &[f64; 6], c: &Motion, pa: &Force) -> Force {
    let mut w = [0.0; 6];
    for r in 0..K {
        w[r] = u[r] - c.dot(&um[r]);
    }
    solve_sized::<K>(d, &mut w);
    let mut out = *pa + ia.mul_motion(c);
    for r in 0..K {
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
        aba.a[i] = if aba.locked[i] { held_accel(m, kin, aba, i, a, qacc) } else { joint_accel(m, kin, aba, i, &aba.u[i], a, qacc) };
    }
}

/// One held node of the outward pass (Featherstone 2008, §9.2): q̈ the prescribed one, and the
/// torque that gives it, D q̈ − (u − Uᵀ a'), into `aba.lock_torque`; returns a = a' + S q̈.
fn held_accel(m: &Model, kin: &KinData, aba: &mut AbaData, i: usize, a_prime: Motion, qacc: &mut [f64]) -> Motion {
    let qdd = aba.lock_qacc[i];
    aba.lock_torque[i] = aba.lock_d[i] * qdd - (aba.u[i][0] - a_prime.dot(&aba.u_mat[i][0]));
    qacc[m.node_dofadr[i]] = qdd;
    a_prime + kin.s[i][0] * qdd
}

/// One node of the outward pass: q̈_i = D_i⁻¹(u_i − U_iᵀ a'_i) into `qacc`, returning
/// a_i = a'_i + S_i q̈_i. Shared by the main pass and the test-force delta pass.
#[inline(always)]
pub fn joint_accel(m: &Model, kin: &KinData, aba: &AbaData, i: usize, u: &[f64; 6], a_prime: Motion, qacc: &mut [f64]) -> Motion {
    sized!(m.node_nv[i], outward(m, kin, aba, i, u, a_prime, qacc))
}

/// [`joint_accel`] for a node of K dofs.
#[inline(always)]
fn outward<const K: usize>(m: &Model, kin: &KinData, aba: &AbaData, i: usize, u: &[f64; 6], a_prime: Motion, qacc: &mut [f64]) -> Motion {
    let da = m.node_dofadr[i];
    let mut rhs = [0.0; 6];
    for r in 0..K {
        rhs[r] = u[r] - a_prime.dot(&aba.u_mat[i][r]);
    }
    solve_sized::<K>(&aba.d_inv[i], &mut rhs);
    let mut a = a_prime;
    for r in 0..K {
        qacc[da + r] = rhs[r];
        a += kin.s[i][r] * rhs[r];
    }
    a
}

/// Inverts a symmetric positive-definite k × k matrix D (row-major in a 6 × 6 block) in place for
/// its solves, so that every later solve is one matrix–vector product. Returns false, leaving
/// zeros, when D is not positive definite.
pub fn invert_d(k: usize, d: &mut [f64; 36]) -> bool {
    if k == 1 {
        let ok = d[0] > 1e-300 && d[0].is_finite();
        d[0] = if ok { 1.0 / d[0] } else { 0.0 };
        return ok;
    }
    sized!(k, invert_sized(d))
}

/// [`invert_d`] for k = K: D = L Δ Lᵀ with L unit lower triangular (no square roots, one
/// division per column), then D⁻¹ = L⁻ᵀ Δ⁻¹ L⁻¹.
fn invert_sized<const K: usize>(d: &mut [f64; 36]) -> bool {
    let scale = (0..K).map(|i| d[i * 6 + i].abs()).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        *d = [0.0; 36];
        return false;
    }
    let (mut l, mut inv_delta) = ([0.0; 36], [0.0; 6]);
    let mut delta = [0.0; 6];
    for j in 0..K {
        let mut dj = d[j * 6 + j];
        for q in 0..j {
            dj -= l[j * 6 + q] * l[j * 6 + q] * delta[q];
        }
        if dj.is_nan() || dj <= 1e-14 * scale {
            *d = [0.0; 36];
            return false;
        }
        delta[j] = dj;
        inv_delta[j] = 1.0 / dj;
        for i in j + 1..K {
            let mut s = d[i * 6 + j];
            for q in 0..j {
                s -= l[i * 6 + q] * l[j * 6 + q] * delta[q];
            }
            l[i * 6 + j] = s * inv_delta[j];
        }
    }
    // M = L⁻¹ (unit lower), by forward substitution on the columns of the identity
    let mut mi = [0.0; 36];
    for c in 0..K {
        mi[c * 6 + c] = 1.0;
        for i in c + 1..K {
            let mut s = 0.0;
            for q in c..i {
                s -= l[i * 6 + q] * mi[q * 6 + c];
            }
            mi[i * 6 + c] = s;
        }
    }
    // D⁻¹ = Mᵀ Δ⁻¹ M
    for r in 0..K {
        for c in r..K {
            let mut s = 0.0;
            for q in c..K {
                s += mi[q * 6 + r] * inv_delta[q] * mi[q * 6 + c];
            }
            d[r * 6 + c] = s;
            d[c * 6 + r] = s;
        }
    }
    true
}

/// x ← D⁻¹ x on the first K entries, D⁻¹ as [`invert_d`] left it: each entry's products
/// summed in order.
#[inline(always)]
fn solve_sized<const K: usize>(d: &[f64; 36], x: &mut [f64; 6]) {
    let b = *x;
    for r in 0..K {
        x[r] = (0..K).map(|c| d[r * 6 + c] * b[c]).sum();
    }
}
