//! Mass properties of geoms and bodies, computed exactly as MuJoCo's compiler does
//! (uniform density; capsule = cylinder + two hemispheres; planes are massless).

use glam::{DMat3, DVec3};

use crate::math::SpatialInertia;
use crate::mjcf::{GeomSpec, GeomType};

/// Volume of a geom.
pub fn geom_volume(kind: GeomType, s: [f64; 3]) -> f64 {
    use std::f64::consts::PI;
    match kind {
        GeomType::Plane => 0.0,
        GeomType::Sphere => 4.0 / 3.0 * PI * s[0].powi(3),
        GeomType::Capsule => PI * s[0] * s[0] * (2.0 * s[1] + 4.0 / 3.0 * s[0]),
        GeomType::Cylinder => PI * s[0] * s[0] * 2.0 * s[1],
        GeomType::Box => 8.0 * s[0] * s[1] * s[2],
        GeomType::Ellipsoid => 4.0 / 3.0 * PI * s[0] * s[1] * s[2],
    }
}

/// Principal moments of a geom of mass `m` about its centre, in its own frame.
fn geom_moments(kind: GeomType, s: [f64; 3], m: f64) -> DVec3 {
    use std::f64::consts::PI;
    match kind {
        GeomType::Plane => DVec3::ZERO,
        GeomType::Sphere => DVec3::splat(0.4 * m * s[0] * s[0]),
        GeomType::Capsule => {
            // split the mass between the cylinder and the two hemispheres by volume
            let (r, h) = (s[0], 2.0 * s[1]);
            let vc = PI * r * r * h;
            let vs = 4.0 / 3.0 * PI * r * r * r;
            let (mc, ms) = (m * vc / (vc + vs), m * vs / (vc + vs));
            let ix = mc * (h * h / 12.0 + r * r / 4.0) + ms * (0.4 * r * r + h * h / 4.0 + 3.0 * h * r / 8.0);
            DVec3::new(ix, ix, mc * r * r / 2.0 + ms * 0.4 * r * r)
        }
        GeomType::Cylinder => {
            let (r, h) = (s[0], 2.0 * s[1]);
            let ix = m * (3.0 * r * r + h * h) / 12.0;
            DVec3::new(ix, ix, m * r * r / 2.0)
        }
        GeomType::Box => {
            let (a, b, c) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
            DVec3::new(m / 3.0 * (b + c), m / 3.0 * (a + c), m / 3.0 * (a + b))
        }
        GeomType::Ellipsoid => {
            let (a, b, c) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
            DVec3::new(m / 5.0 * (b + c), m / 5.0 * (a + c), m / 5.0 * (a + b))
        }
    }
}

/// Rigid inertia of a geom expressed in its body's frame.
pub fn geom_inertia(g: &GeomSpec) -> SpatialInertia {
    let m = g.mass.unwrap_or_else(|| g.density * geom_volume(g.kind, g.size));
    let rot = DMat3::from_quat(g.quat);
    let local = SpatialInertia::new(m, DVec3::ZERO, DMat3::from_diagonal(geom_moments(g.kind, g.size, m)));
    local.to_parent(rot, g.pos)
}
