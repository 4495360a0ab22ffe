//! Shared helpers for the integration tests: a seeded RNG, random MJCF trees, assertions.
#![allow(dead_code)]

pub mod fuzz;

use sinew::math::{DVec3, Force};
use sinew::model::{JointType, Model};
use sinew::dynamics::kinematics::KinData;

/// SplitMix64: tiny, seeded, reproducible.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    pub fn vec3(&mut self, s: f64) -> String {
        format!("{} {} {}", self.uniform(-s, s), self.uniform(-s, s), self.uniform(-s, s))
    }
}

/// A random kinematic tree in MJCF with every joint type: `n` bodies, a free or hinged root, some
/// bodies carrying two or three joints, random geoms (box, capsule, sphere, ellipsoid, cylinder) at random
/// poses, random armature and damping.
pub fn random_tree_mjcf(n: usize, free_root: bool, seed: u64) -> String {
    random_tree_mjcf_with(n, free_root, seed, true)
}

/// [`random_tree_mjcf`], with armature and damping only when `passive` (without them a free
/// system conserves momentum and energy).
pub fn random_tree_mjcf_with(n: usize, free_root: bool, seed: u64, passive: bool) -> String {
    let mut r = Rng(seed);
    let mut parent = vec![usize::MAX; n];
    for i in 1..n {
        parent[i] = r.below(i);
    }
    fn body(i: usize, parent: &[usize], r: &mut Rng, free_root: bool, passive: bool) -> String {
        let mut s = format!("<body name=\"b{i}\" pos=\"{}\" euler=\"{}\">", r.vec3(0.5), r.vec3(60.0));
        if i == 0 && free_root {
            s += "<freejoint/>";
        } else {
            // several joints in one body share a dynamics node (up to six dofs, then a new one)
            let nj = match r.below(8) {
                0 => 3,
                1 | 2 => 2,
                _ => 1,
            };
            for k in 0..nj {
                let kind = ["hinge", "slide", "ball", "hinge"][r.below(4)];
                s += &format!(
                    "<joint name=\"j{i}_{k}\" type=\"{kind}\" axis=\"{}\" pos=\"{}\" armature=\"{}\" damping=\"{}\" ref=\"{}\"/>",
                    r.vec3(1.0),
                    r.vec3(0.2),
                    if passive { r.uniform(0.0, 0.1) } else { 0.0 },
                    if passive { r.uniform(0.0, 0.5) } else { 0.0 },
                    if kind == "ball" { 0.0 } else { r.uniform(-20.0, 20.0) }
                );
            }
        }
        for _ in 0..1 + r.below(2) {
            let g = match r.below(5) {
                0 => format!("type=\"box\" size=\"{} {} {}\"", r.uniform(0.05, 0.2), r.uniform(0.05, 0.2), r.uniform(0.05, 0.2)),
                1 => format!("type=\"capsule\" size=\"{} {}\"", r.uniform(0.03, 0.1), r.uniform(0.05, 0.3)),
                2 => format!("type=\"sphere\" size=\"{}\"", r.uniform(0.05, 0.2)),
                3 => format!("type=\"ellipsoid\" size=\"{} {} {}\"", r.uniform(0.05, 0.2), r.uniform(0.05, 0.2), r.uniform(0.05, 0.2)),
                _ => format!("type=\"cylinder\" size=\"{} {}\"", r.uniform(0.03, 0.1), r.uniform(0.05, 0.3)),
            };
            s += &format!("<geom {g} pos=\"{}\" euler=\"{}\" density=\"{}\"/>", r.vec3(0.2), r.vec3(90.0), r.uniform(300.0, 3000.0));
        }
        for c in 0..parent.len() {
            if parent[c] == i {
                s += &body(c, parent, r, false, passive);
            }
        }
        s + "</body>"
    }
    format!(
        "<mujoco><option gravity=\"0.3 -0.2 -9.81\"/><worldbody>{}</worldbody></mujoco>",
        body(0, &parent, &mut r, free_root, passive)
    )
}

/// A random valid state: perturbed hinge/slide coordinates, random unit quaternions, random velocities.
pub fn random_state(m: &Model, r: &mut Rng) -> (Vec<f64>, Vec<f64>) {
    let mut q = m.qpos0.clone();
    for j in 0..m.njnt {
        let a = m.jnt_qposadr[j];
        let quat = |r: &mut Rng| {
            let v = [r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)];
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            v.map(|x| x / n)
        };
        match m.jnt_type[j] {
            JointType::Free => {
                for k in 0..3 {
                    q[a + k] += r.uniform(-1.0, 1.0);
                }
                q[a + 3..a + 7].copy_from_slice(&quat(r));
            }
            JointType::Ball => q[a..a + 4].copy_from_slice(&quat(r)),
            _ => q[a] += r.uniform(-1.0, 1.0),
        }
    }
    let v = (0..m.nv).map(|_| r.uniform(-2.0, 2.0)).collect();
    (q, v)
}

/// max |a − b| / max(1, max |b|).
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0f64, |s, x| s.max(x.abs()));
    a.iter().zip(b).fold(0.0f64, |e, (x, y)| e.max((x - y).abs())) / scale
}

/// Total spatial momentum in world coordinates about the world origin: (angular, linear).
pub fn world_momentum(m: &Model, kin: &KinData) -> (DVec3, DVec3) {
    let (mut ang, mut lin) = (DVec3::ZERO, DVec3::ZERO);
    // the kinematics' spatial quantities are about `kin.origin`, in world axes
    for i in 0..m.nnode {
        let h: Force = kin.inertia[i].mul_motion(&kin.v[i]);
        ang += h.ang + kin.origin.cross(h.lin);
        lin += h.lin;
    }
    (ang, lin)
}

/// Kinetic energy ½ Σ vᵢᵀ Iᵢ vᵢ.
pub fn kinetic_energy(m: &Model, kin: &KinData) -> f64 {
    (0..m.nnode).map(|i| 0.5 * kin.v[i].dot(&kin.inertia[i].mul_motion(&kin.v[i]))).sum()
}

/// Gravitational potential energy −Σ m g·c.
pub fn potential_energy(m: &Model, kin: &KinData) -> f64 {
    let mut e = 0.0;
    for i in 0..m.nnode {
        let c = kin.node_pos[i] + kin.node_rot[i] * m.node_inertia[i].com;
        e -= m.node_inertia[i].mass * m.opt.gravity.dot(c);
    }
    e
}

/// Asserts that K of `sys` (by test forces) equals J M⁻¹ Jᵀ with its M (nv × nv), entry by entry
/// to 1e-10 relative: M X = Jᵀ solved by Gaussian elimination with partial pivoting.
pub fn assert_k_is_j_minv_jt(sys: &sinew::step::ConstraintSystem, nv: usize) {
    let n = sys.kind.len();
    for j in 0..n {
        let (mut a, mut x) = (sys.inertia.clone(), (0..nv).map(|k| sys.jac[j * nv + k]).collect::<Vec<f64>>());
        for c in 0..nv {
            let p = (c..nv).max_by(|&u, &v| a[u * nv + c].abs().total_cmp(&a[v * nv + c].abs())).unwrap();
            for k in 0..nv {
                a.swap(c * nv + k, p * nv + k);
            }
            x.swap(c, p);
            for i in c + 1..nv {
                let f = a[i * nv + c] / a[c * nv + c];
                for k in c..nv {
                    a[i * nv + k] -= f * a[c * nv + k];
                }
                x[i] -= f * x[c];
            }
        }
        for c in (0..nv).rev() {
            let t: f64 = (c + 1..nv).map(|k| a[c * nv + k] * x[k]).sum();
            x[c] = (x[c] - t) / a[c * nv + c];
        }
        for i in 0..n {
            let jmj: f64 = (0..nv).map(|k| sys.jac[i * nv + k] * x[k]).sum();
            assert!((sys.k[i * n + j] - jmj).abs() < 1e-10 * (1.0 + jmj.abs()), "K[{i}][{j}] {} vs {jmj}", sys.k[i * n + j]);
        }
    }
}
