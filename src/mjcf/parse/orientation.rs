//! MJCF's orientation attributes (`quat`, `axisangle`, `euler` with the compiler's `eulerseq`,
//! `xyaxes`, `zaxis`) as one unit quaternion.

use glam::{DMat3, DQuat, DVec3};

use super::{El, Parser};
use crate::error::Result;

impl Parser<'_> {
    /// Orientation from quat / axisangle / euler / xyaxes / zaxis (at most one).
    pub(super) fn orientation(&self, e: &El) -> Result<DQuat> {
        let given: Vec<&str> =
            ["quat", "axisangle", "euler", "xyaxes", "zaxis"].into_iter().filter(|a| e.node.attribute(*a).is_some()).collect();
        if given.len() > 1 {
            return Err(e.err(given[1], format!("conflicts with '{}': give one orientation", given[0])));
        }
        if let Some(q) = e.arr::<4>("quat")? {
            let q = DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
            if q.length() < 1e-12 {
                return Err(e.err("quat", "zero quaternion"));
            }
            return Ok(q.normalize());
        }
        if let Some(a) = e.arr::<4>("axisangle")? {
            let axis = DVec3::new(a[0], a[1], a[2]);
            if axis.length() < 1e-12 {
                return Err(e.err("axisangle", "zero axis"));
            }
            return Ok(DQuat::from_axis_angle(axis.normalize(), self.angle(a[3])));
        }
        if let Some(a) = e.arr::<3>("euler")? {
            let mut q = DQuat::IDENTITY;
            for (i, &c) in self.eulerseq.iter().enumerate() {
                let axis = match c.to_ascii_lowercase() {
                    b'x' => DVec3::X,
                    b'y' => DVec3::Y,
                    _ => DVec3::Z,
                };
                let r = DQuat::from_axis_angle(axis, self.angle(a[i]));
                q = if c.is_ascii_lowercase() { q * r } else { r * q };
            }
            return Ok(q);
        }
        if let Some(a) = e.arr::<6>("xyaxes")? {
            let x = DVec3::new(a[0], a[1], a[2]);
            let y = DVec3::new(a[3], a[4], a[5]);
            if x.length() < 1e-12 {
                return Err(e.err("xyaxes", "zero x axis"));
            }
            let x = x.normalize();
            let y = y - x * x.dot(y);
            if y.length() < 1e-12 {
                return Err(e.err("xyaxes", "y axis parallel to x axis"));
            }
            let y = y.normalize();
            return Ok(DQuat::from_mat3(&DMat3::from_cols(x, y, x.cross(y))).normalize());
        }
        if let Some(z) = e.arr::<3>("zaxis")? {
            let z = DVec3::from_array(z);
            if z.length() < 1e-12 {
                return Err(e.err("zaxis", "zero axis"));
            }
            return Ok(quat_z_to(z.normalize()));
        }
        Ok(DQuat::IDENTITY)
    }
}

/// The shortest rotation taking +z to the unit vector `z` (MuJoCo's `mju_quatZ2Vec`).
pub(super) fn quat_z_to(z: DVec3) -> DQuat {
    if z.z < -1.0 + 1e-14 {
        return DQuat::from_xyzw(1.0, 0.0, 0.0, 0.0);
    }
    DQuat::from_rotation_arc(DVec3::Z, z)
}
