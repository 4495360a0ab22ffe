//! Rigid-body and articulated-body spatial inertias (Featherstone 2008, §2.13, §7.2).

use glam::{DMat3, DVec3};

use super::{outer, skew, Force, Motion};

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
    #[inline]
    pub fn to_parent(&self, rot: DMat3, pos: DVec3) -> SpatialInertia {
        // R I_c Rᵀ is symmetric: its upper triangle from the rows of R I_c and the rows of R
        let ri = rot * self.ic;
        let row = |m: &DMat3, i: usize| DVec3::new(m.x_axis[i], m.y_axis[i], m.z_axis[i]);
        let (r0, r1, r2) = (row(&rot, 0), row(&rot, 1), row(&rot, 2));
        let (a0, a1, a2) = (row(&ri, 0), row(&ri, 1), row(&ri, 2));
        let (m00, m01, m02, m11, m12, m22) = (a0.dot(r0), a0.dot(r1), a0.dot(r2), a1.dot(r1), a1.dot(r2), a2.dot(r2));
        let ic = DMat3::from_cols(DVec3::new(m00, m01, m02), DVec3::new(m01, m11, m12), DVec3::new(m02, m12, m22));
        SpatialInertia { mass: self.mass, com: rot * self.com + pos, ic }
    }

    /// Momentum I v of a spatial velocity.
    #[inline]
    pub fn mul_motion(&self, v: &Motion) -> Force {
        // linear momentum m (v_O + ω × c); angular about O: I_c ω + c × linear momentum
        let lin = (v.lin + v.ang.cross(self.com)) * self.mass;
        Force { ang: self.ic * v.ang + self.com.cross(lin), lin }
    }

    /// The 6×6 form as an articulated inertia (Featherstone 2008, eq. 2.63).
    #[inline]
    pub fn to_art(&self) -> ArtInertia {
        // A = I_c − m c×c× = I_c + m (|c|² 1 − c cᵀ), B = m c×, C = m 1
        let (m, c) = (self.mass, self.com);
        let mc = c * m;
        let sq = mc.dot(c);
        let a = self.ic + DMat3::from_diagonal(DVec3::splat(sq)) - DMat3::from_cols(c * mc.x, c * mc.y, c * mc.z);
        ArtInertia { a, b: skew(mc), c: DMat3::from_diagonal(DVec3::splat(m)) }
    }
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

/// The principal moments and axes of a symmetric 3×3 inertia: (moments, axes as columns) with
/// `i = axes · diag(moments) · axesᵀ`, by cyclic Jacobi rotations (Golub & Van Loan 2013, §8.5).
/// An inertia already diagonal keeps the frame's own axes, as MuJoCo's compiler does.
pub fn principal_axes(i: DMat3) -> (DVec3, DMat3) {
    let mut a = [[0.0; 3]; 3];
    for (r, row) in a.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = i.col(c)[r];
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= 1e-15 * scale {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // the rotation in the (p, q) plane that zeroes a[p][q]
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let axes = DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    );
    (DVec3::new(a[0][0], a[1][1], a[2][2]), axes)
}

#[cfg(test)]
mod tests {
    use super::SpatialInertia;
    use crate::math::Motion;
    use glam::{DMat3, DVec3};
    use glam::DQuat;

    #[test]
    fn rigid_and_articulated_forms_agree() {
        let i = SpatialInertia::new(2.5, DVec3::new(0.1, -0.2, 0.3), DMat3::from_diagonal(DVec3::new(0.4, 0.5, 0.6)));
        let m = Motion::new(DVec3::new(1.0, -2.0, 0.5), DVec3::new(0.3, 0.1, -0.7));
        let (f1, f2) = (i.mul_motion(&m), i.to_art().mul_motion(&m));
        assert!((f1.ang - f2.ang).length() < 1e-14 && (f1.lin - f2.lin).length() < 1e-14);
    }

    #[test]
    fn moved_inertia_is_the_rotated_and_shifted_one() {
        let i = SpatialInertia::new(2.5, DVec3::new(0.1, -0.2, 0.3), DMat3::from_cols(DVec3::new(0.4, 0.05, -0.02), DVec3::new(0.05, 0.5, 0.01), DVec3::new(-0.02, 0.01, 0.6)));
        let rot = DMat3::from_quat(DQuat::from_rotation_y(0.8) * DQuat::from_rotation_x(-0.3));
        let pos = DVec3::new(0.5, 1.0, -2.0);
        let moved = i.to_parent(rot, pos);
        assert_eq!(moved.mass, i.mass);
        assert!((moved.com - (rot * i.com + pos)).length() < 1e-15);
        assert!((moved.ic - rot * i.ic * rot.transpose()).abs_diff_eq(DMat3::ZERO, 1e-15));
    }

    #[test]
    fn principal_axes_diagonalise_an_inertia() {
        let rot = DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        for moments in [DVec3::new(3.0, 2.0, 1.0), DVec3::new(2.0, 2.0, 0.5)] {
            let i = rot * DMat3::from_diagonal(moments) * rot.transpose();
            let (p, axes) = super::principal_axes(i);
            let back = axes * DMat3::from_diagonal(p) * axes.transpose();
            assert!((back - i).abs_diff_eq(DMat3::ZERO, 1e-12), "{back:?}");
            assert!((axes.transpose() * axes).abs_diff_eq(DMat3::IDENTITY, 1e-12));
            let (mut got, mut want) = (p.to_array(), moments.to_array());
            got.sort_by(f64::total_cmp);
            want.sort_by(f64::total_cmp);
            assert!(got.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{got:?}");
        }
        // a diagonal inertia keeps its frame
        assert_eq!(super::principal_axes(DMat3::from_diagonal(DVec3::new(1.0, 2.0, 3.0))).1, DMat3::IDENTITY);
    }
}
