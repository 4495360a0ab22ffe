//! Rigid-body and articulated-body spatial inertias (Featherstone 2008, §2.13, §7.2).

use glam::{DMat3, DVec3};

use super::{outer, skew, Force, Motion, Xform};

/// Rigid-body inertia: mass m, centre of mass c and rotational inertia I_c about the centre of mass,
/// all in the body frame (Featherstone 2008, eq. 2.63).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialInertia {
    /// Mass.
    pub mass: f64,
    /// Centre of mass in body coordinates.
    pub com: DVec3,
    /// Rotational inertia about the centre of mass, body axes.
    pub ic: DMat3,
}

impl Default for SpatialInertia {
    fn default() -> Self {
        SpatialInertia::ZERO
    }
}

impl SpatialInertia {
    /// The inertia of nothing.
    pub const ZERO: SpatialInertia = SpatialInertia { mass: 0.0, com: DVec3::ZERO, ic: DMat3::ZERO };

    /// Builds the inertia from mass, centre of mass and rotational inertia about it.
    pub fn new(mass: f64, com: DVec3, ic: DMat3) -> Self {
        SpatialInertia { mass, com, ic }
    }

    /// Sum of two rigid inertias given in the same frame (parallel-axis theorem).
    pub fn combine(&self, o: &SpatialInertia) -> SpatialInertia {
        let m = self.mass + o.mass;
        if m <= 0.0 {
            return SpatialInertia::ZERO;
        }
        let com = (self.com * self.mass + o.com * o.mass) / m;
        let shift = |s: &SpatialInertia| {
            let d = s.com - com;
            s.ic + (DMat3::IDENTITY * d.length_squared() - outer(d, d)) * s.mass
        };
        SpatialInertia { mass: m, com, ic: shift(self) + shift(o) }
    }

    /// The same inertia expressed in a parent frame in which this frame has pose (`rot`, `pos`).
    pub fn to_parent(&self, rot: DMat3, pos: DVec3) -> SpatialInertia {
        SpatialInertia { mass: self.mass, com: rot * self.com + pos, ic: rot * self.ic * rot.transpose() }
    }

    /// Momentum I v of a spatial velocity.
    #[inline]
    pub fn mul_motion(&self, v: &Motion) -> Force {
        // linear momentum m (v_O + ω × c); angular about O: I_c ω + c × linear momentum
        let lin = (v.lin + v.ang.cross(self.com)) * self.mass;
        Force { ang: self.ic * v.ang + self.com.cross(lin), lin }
    }

    /// The 6×6 form as an articulated inertia (Featherstone 2008, eq. 2.63).
    pub fn to_art(&self) -> ArtInertia {
        let cx = skew(self.com);
        ArtInertia { a: self.ic - cx * cx * self.mass, b: cx * self.mass, c: DMat3::IDENTITY * self.mass }
    }
}

/// `lt * m` for a product known to be symmetric (a congruence Eᵀ S E): the upper triangle formed,
/// then mirrored.
#[inline]
fn sym_congruence(lt: &DMat3, m: &DMat3) -> DMat3 {
    let row = |i: usize| DVec3::new(lt.x_axis[i], lt.y_axis[i], lt.z_axis[i]);
    let (r0, r1, r2) = (row(0), row(1), row(2));
    let (c0, c1, c2) = (m.x_axis, m.y_axis, m.z_axis);
    let (m00, m01, m02) = (r0.dot(c0), r0.dot(c1), r0.dot(c2));
    let (m11, m12, m22) = (r1.dot(c1), r1.dot(c2), r2.dot(c2));
    DMat3::from_cols(DVec3::new(m00, m01, m02), DVec3::new(m01, m11, m12), DVec3::new(m02, m12, m22))
}

/// Symmetric 6×6 (articulated-body) inertia [[A, B], [Bᵀ, C]] acting on (ω, v) motions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArtInertia {
    /// Angular–angular block (symmetric).
    pub a: DMat3,
    /// Angular–linear block.
    pub b: DMat3,
    /// Linear–linear block (symmetric).
    pub c: DMat3,
}

impl Default for ArtInertia {
    fn default() -> Self {
        ArtInertia::ZERO
    }
}

impl ArtInertia {
    /// Zero inertia.
    pub const ZERO: ArtInertia = ArtInertia { a: DMat3::ZERO, b: DMat3::ZERO, c: DMat3::ZERO };

    /// I m: the force needed to give this inertia the acceleration m.
    #[inline]
    pub fn mul_motion(&self, m: &Motion) -> Force {
        Force { ang: self.a * m.ang + self.b * m.lin, lin: self.b.transpose() * m.ang + self.c * m.lin }
    }

    /// Congruence Xᵀ I X: an inertia in child coordinates expressed in the parent's, for
    /// X = ^iX_λ (Featherstone 2008, Table 7.1, I^A_λ += ^iX_λᵀ I^a_i ^iX_λ).
    pub fn to_parent(&self, x: &Xform) -> ArtInertia {
        // rotate: Eᵀ M E (A and C symmetric, so only their upper triangles are formed)
        let et = x.e.transpose();
        let a = sym_congruence(&et, &(self.a * x.e));
        let b = et * self.b * x.e;
        let c = sym_congruence(&et, &(self.c * x.e));
        // translate by r (r× as cross products): A' = A + P + Pᵀ − r×C r×, B' = B + r×C,
        // with P = r× Bᵀ
        let r = x.r;
        let cross_cols = |m: DMat3| DMat3::from_cols(r.cross(m.x_axis), r.cross(m.y_axis), r.cross(m.z_axis));
        let p = cross_cols(b.transpose());
        let rc = cross_cols(c);
        let rcr = cross_cols(rc.transpose());
        ArtInertia { a: a + p + p.transpose() + rcr, b: b + rc, c }
    }

    /// Subtracts u₁ d u₂ᵀ (with its symmetric counterpart handled by the caller's loop).
    #[inline]
    pub fn sub_outer(&mut self, u1: &Force, u2: &Force, d: f64) {
        self.a -= outer(u1.ang, u2.ang * d);
        self.b -= outer(u1.ang, u2.lin * d);
        self.c -= outer(u1.lin, u2.lin * d);
    }

    /// Adds another inertia in the same frame.
    #[inline]
    pub fn add(&mut self, o: &ArtInertia) {
        self.a += o.a;
        self.b += o.b;
        self.c += o.c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn rigid_and_articulated_forms_agree() {
        let i = SpatialInertia::new(2.5, DVec3::new(0.1, -0.2, 0.3), DMat3::from_diagonal(DVec3::new(0.4, 0.5, 0.6)));
        let m = Motion::new(DVec3::new(1.0, -2.0, 0.5), DVec3::new(0.3, 0.1, -0.7));
        let (f1, f2) = (i.mul_motion(&m), i.to_art().mul_motion(&m));
        assert!((f1.ang - f2.ang).length() < 1e-14 && (f1.lin - f2.lin).length() < 1e-14);
    }

    #[test]
    fn congruence_matches_xt_i_x() {
        let i = SpatialInertia::new(2.5, DVec3::new(0.1, -0.2, 0.3), DMat3::from_diagonal(DVec3::new(0.4, 0.5, 0.6)));
        let x = Xform::from_pose_quat(DQuat::from_rotation_y(0.8) * DQuat::from_rotation_x(-0.3), DVec3::new(0.5, 1.0, -2.0));
        let m = Motion::new(DVec3::new(1.0, -2.0, 0.5), DVec3::new(0.3, 0.1, -0.7));
        let direct = x.inv_apply_force(&i.to_art().mul_motion(&x.apply_motion(&m)));
        let moved = i.to_art().to_parent(&x).mul_motion(&m);
        assert!((direct.ang - moved.ang).length() < 1e-13 && (direct.lin - moved.lin).length() < 1e-13);
        // the rigid-body form moved to the parent is the same inertia
        let (rot, pos) = x.pose();
        let rigid = i.to_parent(rot, pos).mul_motion(&m);
        assert!((direct.ang - rigid.ang).length() < 1e-13 && (direct.lin - rigid.lin).length() < 1e-13);
    }
}
