//! Fluid forces: MuJoCo's two models. The inertia-box model (`mj_inertiaBoxFluidModel`): each body
//! with mass moves through the medium (density ρ, viscosity μ, wind) as the box with its principal
//! moments of inertia, at its centre of mass in its principal axes: viscous drag of the sphere of
//! the box's mean side d (Stokes: −3π d μ v, −π d³ μ ω) and quadratic drag of the box's faces
//! (−½ ρ A_k |v_k| v_k, and −ρ b_k (b_i⁴ + b_j⁴)/64 |ω_k| ω_k about each axis), against the
//! body's velocity relative to the wind. The ellipsoid model (`mj_ellipsoidFluidModel`), for a
//! body with geoms of `fluidshape="ellipsoid"`: each such geom as its ellipsoid, with the fluid's
//! added-mass forces, blunt and slender drag, Kutta and Magnus lift and Stokes drag (MuJoCo's
//! documentation, "Fluid forces", after Andersen, Pesavento & Wang 2005).

use glam::DVec3;

use super::kinematics::{add_joint_forces, KinData};
use crate::math::{Force, Motion};
use crate::model::{GeomFluid, Model, WORLD};

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
        // a body with ellipsoid geoms meets the fluid through them (below)
        if m.body_fluid_ellipsoid[b] {
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
    for (g, f) in m.geom_fluid.iter().enumerate() {
        let (Some(f), b) = (f, m.geom_body[g]) else { continue };
        let n = m.body_node[b];
        if n != WORLD && m.body_mass[b] >= 1e-15 {
            ellipsoid_forces(m, kin, &v[n], g, f, tau);
        }
    }
}

/// The ellipsoid model's force on geom `g` (constants `f`) of a body moving at `v` (its node's
/// velocity), into `tau`: computed in the geom's frame at its centre, against the velocity
/// relative to the wind.
fn ellipsoid_forces(m: &Model, kin: &KinData, v: &Motion, g: usize, f: &GeomFluid, tau: &mut [f64]) {
    let (rho, mu) = (m.opt.density, m.opt.viscosity);
    let b = m.geom_body[g];
    let rot = kin.xmat[b] * m.geom_mat[g];
    let r = kin.xpos[b] + kin.xmat[b] * m.geom_pos[g] - kin.origin;
    let w = rot.transpose() * v.ang;
    let u = rot.transpose() * (v.point_velocity(r) - m.opt.wind);
    let [blunt, slender, angular, kutta, magnus] = f.coef;
    let s = f.semiaxes;
    // added mass: the fluid's momentum carried along, turned by the motion
    let (p_lin, p_ang) = (rho * f.virtual_mass * u, rho * f.virtual_inertia * w);
    let mut torque = p_lin.cross(u) + p_ang.cross(w);
    let mut force = p_lin.cross(w);
    // Magnus lift of the spinning body, Kutta lift of the area it presents to the flow
    let pi = std::f64::consts::PI;
    let volume = 4.0 / 3.0 * pi * s.x * s.y * s.z;
    force += magnus * rho * volume * w.cross(u);
    let faces = DVec3::new(s.y * s.z, s.z * s.x, s.x * s.y);
    let proj_denom = (faces * faces * faces * faces * u * u).element_sum();
    let proj_num = (faces * faces * u * u).element_sum();
    let area = pi * (proj_denom / proj_num.max(1e-15)).sqrt();
    let normal = faces * faces * u;
    let cos_alpha = proj_num / (u.length() * proj_denom).max(1e-15);
    force += (kutta * rho * cos_alpha * area * normal.cross(u)).cross(u);
    // drag: Stokes' on the equivalent sphere, and quadratic, blunt across the presented area and
    // slender across the rest of the largest section
    let (d_max, d_min) = (s.max_element(), s.min_element());
    let d_mid = s.element_sum() - d_max - d_min;
    let diameter = 2.0 / 3.0 * s.element_sum();
    let largest = |i: usize| 8.0 / 15.0 * pi * s[i] * s[(i + 1) % 3].max(s[(i + 2) % 3]).powi(4);
    let moments = DVec3::new(largest(0), largest(1), largest(2));
    let i_max = 8.0 / 15.0 * pi * d_mid * d_max.powi(4);
    let spin = w * (angular * moments + slender * (i_max - moments));
    let linear = mu * 3.0 * pi * diameter + rho * u.length() * (area * blunt + slender * (pi * d_max * d_mid - area));
    let angular = mu * pi * diameter * diameter * diameter + rho * spin.length();
    torque -= angular * w;
    force -= linear * u;
    let (torque, force) = (rot * torque, rot * force);
    add_joint_forces(m, kin, m.body_node[b], &Force { ang: torque + r.cross(force), lin: force }, tau);
}
