//! Fluid forces: MuJoCo's inertia-box model (`mj_inertiaBoxFluidModel`). Each body with mass
//! moves through the medium (density ρ, viscosity μ, wind) as the box with its principal moments
//! of inertia, at its centre of mass in its principal axes: viscous drag of the sphere of the
//! box's mean side d (Stokes: −3π d μ v, −π d³ μ ω) and quadratic drag of the box's faces
//! (−½ ρ A_k |v_k| v_k, and −ρ b_k (b_i⁴ + b_j⁴)/64 |ω_k| ω_k about each axis), against the
//! body's velocity relative to the wind.

use glam::DVec3;

use super::kinematics::{add_joint_forces, KinData};
use crate::math::{Force, Motion};
use crate::model::{Model, WORLD};

/// Adds the fluid forces of the bodies moving at the node velocities `v` (the configuration's
/// kinematics in `kin`) to the joint forces `tau`; nothing without a medium.
#[inline]
pub fn add_forces(m: &Model, kin: &KinData, v: &[Motion], tau: &mut [f64]) {
    if m.opt.density != 0.0 || m.opt.viscosity != 0.0 {
        body_forces(m, kin, v, tau);
    }
}

/// [`add_forces`] in a medium.
fn body_forces(m: &Model, kin: &KinData, v: &[Motion], tau: &mut [f64]) {
    let (rho, mu) = (m.opt.density, m.opt.viscosity);
    for b in 1..m.nbody {
        let n = m.body_node[b];
        if n == WORLD || m.body_mass[b] < 1e-15 {
            continue;
        }
        // the principal frame at the centre of mass, and the velocities in it
        let rot = kin.xmat[b] * m.body_iaxes[b];
        let r = kin.xpos[b] + kin.xmat[b] * m.body_ipos[b] - kin.origin;
        let w = rot.transpose() * v[n].ang;
        let u = rot.transpose() * (v[n].point_velocity(r) - m.opt.wind);
        let s = m.body_fluid_box[b];
        let (mut torque, mut force) = (DVec3::ZERO, DVec3::ZERO);
        if mu > 0.0 {
            let d = (s.x + s.y + s.z) / 3.0;
            torque -= w * (std::f64::consts::PI * d * d * d * mu);
            force -= u * (3.0 * std::f64::consts::PI * d * mu);
        }
        if rho > 0.0 {
            let area = DVec3::new(s.y * s.z, s.x * s.z, s.x * s.y);
            force -= 0.5 * rho * area * u.abs() * u;
            let arm = DVec3::new(s.y.powi(4) + s.z.powi(4), s.x.powi(4) + s.z.powi(4), s.x.powi(4) + s.y.powi(4));
            torque -= rho * s * arm / 64.0 * w.abs() * w;
        }
        let (torque, force) = (rot * torque, rot * force);
        add_joint_forces(m, kin, n, &Force { ang: torque + r.cross(force), lin: force }, tau);
    }
}
