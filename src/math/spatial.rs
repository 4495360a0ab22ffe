//! Motion and force 6-vectors and Plücker transforms (Featherstone 2008, §2.2–2.8).

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use glam::{DMat3, DQuat, DVec3};

/// Spatial motion vector (angular ω, linear v at the frame origin): velocities and accelerations.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Angular part ω.
    pub ang: DVec3,
    /// Linear part v_O (velocity of the body-fixed point at the frame origin).
    pub lin: DVec3,
}

/// Spatial force vector (moment n about the frame origin, force f).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Force {
    /// Moment about the frame origin.
    pub ang: DVec3,
    /// Linear force.
    pub lin: DVec3,
}

impl Motion {
    /// The zero motion.
    pub const ZERO: Motion = Motion { ang: DVec3::ZERO, lin: DVec3::ZERO };

    /// Builds a motion from angular and linear parts.
    #[inline]
    pub const fn new(ang: DVec3, lin: DVec3) -> Self {
        Motion { ang, lin }
    }

    /// Motion cross product `self ×m m` (Featherstone 2008, eq. 2.31).
    #[inline]
    pub fn cross_motion(&self, m: &Motion) -> Motion {
        Motion {
            ang: self.ang.cross(m.ang),
            lin: self.ang.cross(m.lin) + self.lin.cross(m.ang),
        }
    }

    /// Force cross product `self ×* f` (Featherstone 2008, eq. 2.32).
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force {
            ang: self.ang.cross(f.ang) + self.lin.cross(f.lin),
            lin: self.ang.cross(f.lin),
        }
    }

    /// Scalar product with a force (power).
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        self.ang.dot(f.ang) + self.lin.dot(f.lin)
    }

    /// Linear velocity of the body-fixed point `p` (coordinates in this frame).
    #[inline]
    pub fn point_velocity(&self, p: DVec3) -> DVec3 {
        self.lin + self.ang.cross(p)
    }

    /// True when all six components are finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.ang.is_finite() && self.lin.is_finite()
    }
}

impl Force {
    /// The zero force.
    pub const ZERO: Force = Force { ang: DVec3::ZERO, lin: DVec3::ZERO };

    /// Builds a force from moment and linear parts.
    #[inline]
    pub const fn new(ang: DVec3, lin: DVec3) -> Self {
        Force { ang, lin }
    }

    /// A pure force `f` acting at point `p` (coordinates in this frame).
    #[inline]
    pub fn at_point(p: DVec3, f: DVec3) -> Self {
        Force { ang: p.cross(f), lin: f }
    }
}

macro_rules! vec6_ops {
    ($t:ident) => {
        impl Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t {
                $t { ang: self.ang + o.ang, lin: self.lin + o.lin }
            }
        }
        impl Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t {
                $t { ang: self.ang - o.ang, lin: self.lin - o.lin }
            }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) {
                self.ang += o.ang;
                self.lin += o.lin;
            }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) {
                self.ang -= o.ang;
                self.lin -= o.lin;
            }
        }
        impl Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t {
                $t { ang: -self.ang, lin: -self.lin }
            }
        }
        impl Mul<f64> for $t {
            type Output = $t;
            #[inline]
            fn mul(self, s: f64) -> $t {
                $t { ang: self.ang * s, lin: self.lin * s }
            }
        }
    };
}
vec6_ops!(Motion);
vec6_ops!(Force);

/// Plücker transform ^B X_A from frame A to frame B, stored as (E, r): E rotates A-coordinates into
/// B-coordinates and r is B's origin in A-coordinates (Featherstone 2008, §2.8, eq. 2.24).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Xform {
    /// Rotation from A-coordinates to B-coordinates.
    pub e: DMat3,
    /// Origin of B expressed in A-coordinates.
    pub r: DVec3,
}

impl Default for Xform {
    fn default() -> Self {
        Xform::IDENTITY
    }
}

impl Xform {
    /// The identity transform.
    pub const IDENTITY: Xform = Xform { e: DMat3::IDENTITY, r: DVec3::ZERO };

    /// Transform to a frame B whose pose in A is (`rot`, `pos`): axes `rot`, origin `pos`.
    #[inline]
    pub fn from_pose(rot: DMat3, pos: DVec3) -> Self {
        Xform { e: rot.transpose(), r: pos }
    }

    /// Same as [`Xform::from_pose`] with a quaternion.
    #[inline]
    pub fn from_pose_quat(q: DQuat, pos: DVec3) -> Self {
        Xform::from_pose(DMat3::from_quat(q), pos)
    }

    /// Pose (axes, origin) of frame B in frame A.
    #[inline]
    pub fn pose(&self) -> (DMat3, DVec3) {
        (self.e.transpose(), self.r)
    }

    /// Composition: for `self` = ^B X_A and `next` = ^C X_B, returns ^C X_A.
    #[inline]
    pub fn then(&self, next: &Xform) -> Xform {
        Xform { e: next.e * self.e, r: self.r + self.e.transpose() * next.r }
    }
}

#[cfg(test)]
mod tests {
    use super::Xform;
    use glam::{DMat3, DQuat, DVec3};

    #[test]
    fn composition_composes_the_poses() {
        let a = Xform::from_pose_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1), DVec3::new(0.4, -1.0, 2.0));
        let b = Xform::from_pose_quat(DQuat::from_rotation_z(0.4), DVec3::new(1.0, 0.0, -0.5));
        let ((ra, pa), (rb, pb), (rc, pc)) = (a.pose(), b.pose(), a.then(&b).pose());
        // C's pose in A: B's axes carried by A's, B's origin placed in A
        assert!((rc - ra * rb).abs_diff_eq(DMat3::ZERO, 1e-14));
        assert!((pc - (pa + ra * pb)).length() < 1e-14);
    }
}
