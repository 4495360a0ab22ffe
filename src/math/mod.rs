//! Spatial algebra in Featherstone's notation (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 2).
//! Knows nothing about models. 6-vectors are stored as (angular, linear) pairs of `DVec3`.

mod inertia;
mod spatial;

pub use glam::{DMat3, DQuat, DVec3};
pub use inertia::{principal_axes, ArtInertia, SpatialInertia};
pub use spatial::{Force, Motion, Xform};

/// SplitMix64's output for `state` (Steele, Lea & Flood 2014): a well-mixed 64-bit value; the
/// stream advances its state by [`SPLITMIX_GAMMA`] per draw.
#[inline]
pub fn splitmix64(state: u64) -> u64 {
    let mut z = state.wrapping_add(SPLITMIX_GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// SplitMix64's increment (2⁶⁴ / φ).
pub const SPLITMIX_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Largest magnitude a state entry may reach before the world counts as diverged (MuJoCo's
/// mjMAXVAL), and the largest number the loader and the options accept.
pub const MAX_STATE: f64 = 1e10;

/// Largest joint damping the loader and the per-world parameters accept: damping is implicit in
/// the Euler step (h·damping added to the ABA's D), where one beyond [`MAX_STATE`] only holds its
/// joint still (gymnasium-robotics' Fetch pins its base's slides with 1e11).
pub const MAX_DAMPING: f64 = 1e15;

/// Whether a state entry is NaN or beyond [`MAX_STATE`] (±inf included).
#[inline]
pub fn out_of_range(x: f64) -> bool {
    x.is_nan() || x.abs() > MAX_STATE
}

/// Half extents of the box, along the axes of a frame, that holds a box of half extents `half`
/// turned by `rot` in it: |rot| half, grown by a relative 1e-12 so that the same product rounded
/// differently never leaves part of what the box holds outside.
pub fn turned_box(rot: DMat3, half: DVec3) -> DVec3 {
    (rot.x_axis.abs() * half.x + rot.y_axis.abs() * half.y + rot.z_axis.abs() * half.z) * (1.0 + 1e-12)
}

/// Skew-symmetric cross-product matrix: `skew(a) * b == a.cross(b)`.
#[inline]
pub fn skew(a: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, a.z, -a.y),
        DVec3::new(-a.z, 0.0, a.x),
        DVec3::new(a.y, -a.x, 0.0),
    )
}

/// Outer product `a bᵀ`.
#[inline]
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Quaternion from MuJoCo's (w, x, y, z) order.
#[inline]
pub fn quat_wxyz(q: &[f64]) -> DQuat {
    DQuat::from_xyzw(q[1], q[2], q[3], q[0])
}

/// Integrates a unit quaternion by a body-frame angular velocity `omega` over `h`
/// (right multiplication by exp(ω h / 2), as MuJoCo's `mju_quatIntegrate`), then renormalises.
#[inline]
pub fn quat_integrate(q: DQuat, omega: DVec3, h: f64) -> DQuat {
    let angle = omega.length() * h;
    if angle == 0.0 || !angle.is_finite() {
        return if angle.is_finite() { q } else { DQuat::from_xyzw(f64::NAN, f64::NAN, f64::NAN, f64::NAN) };
    }
    let axis = omega / omega.length();
    (q * DQuat::from_axis_angle(axis, angle)).normalize()
}

/// Rotation vector `v` with `q2 = q1 * exp(v)`, i.e. the body-frame rotation taking `q1` to `q2`
/// (MuJoCo's `mju_subQuat(v, q2, q1)`).
#[inline]
pub fn quat_sub(q2: DQuat, q1: DQuat) -> DVec3 {
    let mut d = q1.conjugate() * q2;
    if d.w < 0.0 {
        d = -d;
    }
    let s = DVec3::new(d.x, d.y, d.z);
    let sn = s.length();
    if sn < 1e-300 {
        return DVec3::ZERO;
    }
    let angle = 2.0 * sn.atan2(d.w);
    s * (angle / sn)
}
