//! Stage 5's delta pass (Kokkevis 2004, §5): the response of the articulated system to test
//! forces, through the ABA quantities kept from the inward pass (I^A, U, D⁻¹): a delta inward
//! pass along each force's path to the root and a delta outward pass over its trees, O(n), no
//! 6×6 work. Four test forces go through at once, one per lane, each lane's arithmetic that of its
//! force pushed alone.

use glam::DVec3;

use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::math::Force;
use crate::model::{Model, WORLD};

/// Test forces one delta pass carries, one per lane: the columns of K it measures at once.
pub const LANES: usize = 4;

/// One number per lane, the arithmetic lane by lane (each lane's operations those of its test
/// force pushed alone; the compiler keeps the lanes in vector registers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Lanes(pub(super) [f64; LANES]);

impl Lanes {
    pub(super) const ZERO: Lanes = Lanes([0.0; LANES]);

    #[inline(always)]
    fn splat(x: f64) -> Lanes {
        Lanes([x; LANES])
    }

    /// `self` in the lanes of `mask`, `other` in the rest.
    #[inline(always)]
    fn select(self, mask: [bool; LANES], other: Lanes) -> Lanes {
        let mut out = other;
        for l in 0..LANES {
            if mask[l] {
                out.0[l] = self.0[l];
            }
        }
        out
    }
}

impl std::ops::Add for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn add(self, o: Lanes) -> Lanes {
        Lanes([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2], self.0[3] + o.0[3]])
    }
}

impl std::ops::Sub for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn sub(self, o: Lanes) -> Lanes {
        Lanes([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2], self.0[3] - o.0[3]])
    }
}

impl std::ops::Mul<f64> for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn mul(self, s: f64) -> Lanes {
        Lanes([self.0[0] * s, self.0[1] * s, self.0[2] * s, self.0[3] * s])
    }
}

/// A spatial vector per lane, by component: angular x, y, z, then linear x, y, z.
pub(super) type Spatial = [Lanes; 6];

pub(super) const ZERO_LANES: Spatial = [Lanes::ZERO; 6];

/// A delta pass's scratch (Kokkevis 2004, §5: the response to a test force through the ABA's
/// quantities): per node δp^A (the test forces, then their articulated sums), δu (per dof) and δa,
/// each lane one test force's.
#[derive(Clone, Debug, Default)]
pub struct DeltaScratch {
    /// δp^A per node (nnode): the test forces in world coordinates going in.
    pub(super) pa: Vec<Spatial>,
    /// δu per node (nnode), a row per dof.
    u: Vec<Spatial>,
    /// Spatial δa per node (nnode).
    pub(super) a: Vec<Spatial>,
    /// Per node held still (`AbaData::locked`): the change of the torque that holds it,
    /// −(δu − Uᵀ δa') (nnode; written only at held nodes).
    pub(super) held: Vec<Lanes>,
}

impl DeltaScratch {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        DeltaScratch { pa: vec![ZERO_LANES; m.nnode], u: vec![ZERO_LANES; m.nnode], a: vec![ZERO_LANES; m.nnode], held: vec![Lanes::ZERO; m.nnode] }
    }

    /// No test force on the nodes of the trees `trees`.
    pub fn clear(&mut self, m: &Model, trees: [usize; 2]) {
        for range in tree_ranges(m, trees) {
            self.pa[range].fill(ZERO_LANES);
        }
    }

    /// δp^A of node n in lane `lane` −= f: the test force f on the node.
    pub fn sub_force(&mut self, n: usize, lane: usize, f: &Force) {
        for (c, v) in parts(f.ang, f.lin).into_iter().enumerate() {
            self.pa[n][c].0[lane] -= v;
        }
    }
}

/// A spatial vector's six components, angular first.
#[inline(always)]
fn parts(ang: DVec3, lin: DVec3) -> [f64; 6] {
    [ang.x, ang.y, ang.z, lin.x, lin.y, lin.z]
}

/// s · v in every lane, summed as `Motion::dot` sums (each half's three products in order, then
/// the halves).
#[inline(always)]
fn dot(s: &[f64; 6], v: &Spatial) -> Lanes {
    (v[0] * s[0] + v[1] * s[1] + v[2] * s[2]) + (v[3] * s[3] + v[4] * s[4] + v[5] * s[5])
}

/// x = D⁻¹ b (k × k, row-major in a 6 × 6 block) in every lane, each row's products summed in
/// order as the ABA's solves sum them.
#[inline(always)]
fn solve_lanes(k: usize, d: &[f64; 36], b: &Spatial) -> Spatial {
    let mut x = ZERO_LANES;
    for r in 0..k {
        let mut sum = b[0] * d[r * 6];
        for c in 1..k {
            sum = sum + b[c] * d[r * 6 + c];
        }
        x[r] = sum;
    }
    x
}

/// Response of the articulated system to the test forces in `delta.pa` (world coordinates) or
/// the joint torques `dtau` (dof, value), a set per lane, on the nodes of the trees `trees` (the
/// others do not move): a delta ABA with the inertias of the main pass (velocity terms cancel),
/// each lane's arithmetic that of its force pushed alone. Writes lane l's Δq̈ of those trees'
/// dofs into `dqdd[at[l]..]` (None: a lane not used) and spatial Δa of their nodes into
/// `delta.a`; leaves `delta.pa` modified.
#[allow(clippy::too_many_arguments)]
pub fn delta_pass(m: &Model, kin: &KinData, aba: &AbaData, trees: [usize; 2], dtau: [&[(usize, f64)]; LANES], delta: &mut DeltaScratch, dqdd: &mut [f64], at: [Option<usize>; LANES]) {
    // compiled for AVX2 as well: a lane operation is then one instruction with its broadcast
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        #[allow(clippy::too_many_arguments)]
        fn avx2(m: &Model, kin: &KinData, aba: &AbaData, trees: [usize; 2], dtau: [&[(usize, f64)]; LANES], delta: &mut DeltaScratch, dqdd: &mut [f64], at: [Option<usize>; LANES]) {
            delta_lanes(m, kin, aba, trees, dtau, delta, dqdd, at)
        }
        // SAFETY: the processor has AVX2, checked just above
        return unsafe { avx2(m, kin, aba, trees, dtau, delta, dqdd, at) };
    }
    delta_lanes(m, kin, aba, trees, dtau, delta, dqdd, at)
}

/// [`delta_pass`]'s body.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn delta_lanes(m: &Model, kin: &KinData, aba: &AbaData, trees: [usize; 2], dtau: [&[(usize, f64)]; LANES], delta: &mut DeltaScratch, dqdd: &mut [f64], at: [Option<usize>; LANES]) {
    let DeltaScratch { pa: dpa, u: du, a: da, held } = delta;
    let s_parts = |i: usize, r: usize| parts(kin.s[i][r].ang, kin.s[i][r].lin);
    let u_parts = |i: usize, r: usize| parts(aba.u_mat[i][r].ang, aba.u_mat[i][r].lin);
    let torques = dtau.iter().any(|t| !t.is_empty());
    // inward: δu_i = δτ_i − S_iᵀ δp^A_i;  δp^A_λ += δp^A_i + U_i D_i⁻¹ δu_i; a lane whose force
    // is off node i (δp^A = 0, no torque there) keeps δu = 0 and hands nothing on
    let ranges = tree_ranges(m, trees);
    for part in [1, 0] {
        for i in ranges[part].clone().rev() {
            let k = m.node_nv[i];
            let d0 = m.node_dofadr[i];
            let torqued = |l: usize| dtau[l].iter().any(|&(dof, _)| dof >= d0 && dof < d0 + k);
            let mut active = [false; LANES];
            for c in &dpa[i] {
                for l in 0..LANES {
                    active[l] |= c.0[l] != 0.0;
                }
            }
            if torques {
                for (l, a) in active.iter_mut().enumerate() {
                    *a |= torqued(l);
                }
            }
            du[i] = ZERO_LANES;
            if !active.contains(&true) {
                continue;
            }
            for r in 0..k {
                // τ: an empty sum is −0, as a lane pushed alone sums it
                let t = if torques {
                    Lanes(std::array::from_fn(|l| dtau[l].iter().filter(|&&(dof, _)| dof == d0 + r).map(|&(_, v)| v).sum()))
                } else {
                    Lanes::splat(-0.0)
                };
                du[i][r] = (t - dot(&s_parts(i, r), &dpa[i])).select(active, Lanes::ZERO);
            }
            let p = m.node_parent[i];
            if p == WORLD {
                continue;
            }
            let w = solve_lanes(k, &aba.d_inv[i], &du[i]);
            let mut pa = dpa[i];
            for r in 0..k {
                let u = u_parts(i, r);
                for c in 0..6 {
                    pa[c] = pa[c] + w[r] * u[c];
                }
            }
            for c in 0..6 {
                dpa[p][c] = (dpa[p][c] + pa[c]).select(active, dpa[p][c]);
            }
        }
    }
    // outward: δa'_i = δa_λ;  δq̈_i = D⁻¹(δu_i − Uᵀ δa'_i);  δa_i = δa'_i + S δq̈_i
    for part in [0, 1] {
        for i in ranges[part].clone() {
            let p = m.node_parent[i];
            let (k, d0) = (m.node_nv[i], m.node_dofadr[i]);
            let mut a = if p == WORLD { ZERO_LANES } else { da[p] };
            let mut rhs = ZERO_LANES;
            for r in 0..k {
                rhs[r] = du[i][r] - dot(&u_parts(i, r), &a);
            }
            if aba.locking && aba.locked[i] {
                // a held joint's D⁻¹ is 0 (its q̈ does not change): the torque holding it does
                held[i] = Lanes::ZERO - rhs[0];
            }
            let qdd = solve_lanes(k, &aba.d_inv[i], &rhs);
            for r in 0..k {
                let s = s_parts(i, r);
                for c in 0..6 {
                    a[c] = a[c] + qdd[r] * s[c];
                }
                for (l, start) in at.iter().enumerate() {
                    if let Some(start) = start {
                        dqdd[start + d0 + r] = qdd[r].0[l];
                    }
                }
            }
            da[i] = a;
        }
    }
}

/// The node ranges of the trees `trees` ([`Model::node_tree`]; [`WORLD`] and a repeat name
/// none), first node first.
pub fn tree_ranges(m: &Model, trees: [usize; 2]) -> [std::ops::Range<usize>; 2] {
    let [a, b] = trees;
    let (a, b) = if a == WORLD || (b != WORLD && b < a) { (b, a) } else { (a, b) };
    let range = |t: usize| if t == WORLD { 0..0 } else { t..m.node_end[t] };
    [range(a), if b == a { 0..0 } else { range(b) }]
}
