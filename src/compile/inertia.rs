//! Mass properties of geoms and bodies, computed exactly as MuJoCo's compiler does
//! (uniform density; capsule = cylinder + two hemispheres; planes are massless), the bodies'
//! principal axes and fluid boxes, and the stiffness and damping a `springdamper` sets.

use glam::{DMat3, DVec3};

use crate::dynamics::kinematics::KinData;
use crate::math::{principal_axes, SpatialInertia};
use crate::mjcf::{BodySpec, GeomSpec, GeomType, InertiaFromGeom, ModelSpec};
use crate::model::Model;

/// Volume of a geom.
pub fn geom_volume(kind: GeomType, s: [f64; 3]) -> f64 {
    use std::f64::consts::PI;
    match kind {
        GeomType::Plane | GeomType::Hfield => 0.0,
        GeomType::Sphere => 4.0 / 3.0 * PI * s[0].powi(3),
        GeomType::Capsule => PI * s[0] * s[0] * (2.0 * s[1] + 4.0 / 3.0 * s[0]),
        GeomType::Cylinder => PI * s[0] * s[0] * 2.0 * s[1],
        // a mesh geom's mass is set from its mesh's volume (compile/meshes.rs)
        GeomType::Box | GeomType::Mesh => 8.0 * s[0] * s[1] * s[2],
        GeomType::Ellipsoid => 4.0 / 3.0 * PI * s[0] * s[1] * s[2],
    }
}

/// Principal moments of a geom of mass `m` about its centre, in its own frame.
fn geom_moments(kind: GeomType, s: [f64; 3], m: f64) -> DVec3 {
    use std::f64::consts::PI;
    match kind {
        GeomType::Plane | GeomType::Hfield => DVec3::ZERO,
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
        // a mesh's size is its inertia box: the box's moments are the mesh's
        GeomType::Box | GeomType::Mesh => {
            let (a, b, c) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
            DVec3::new(m / 3.0 * (b + c), m / 3.0 * (a + c), m / 3.0 * (a + b))
        }
        GeomType::Ellipsoid => {
            let (a, b, c) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
            DVec3::new(m / 5.0 * (b + c), m / 5.0 * (a + c), m / 5.0 * (a + b))
        }
    }
}

/// Mass and principal moments of a primitive geom whose mass is on its surface
/// (`shellinertia`: `density` per area, unless `mass` is given), as MuJoCo's compiler computes
/// them; None for the shapes sinew gives no shell (ellipsoids, meshes).
fn shell(kind: GeomType, s: [f64; 3], density: f64, mass: Option<f64>) -> Option<(f64, DVec3)> {
    use std::f64::consts::PI;
    let (r, h) = (s[0], 2.0 * s[1]);
    if kind == GeomType::Box {
        let [a, b, c] = s.map(|x| 2.0 * x);
        let area = 2.0 * (a * b + a * c + b * c);
        let m = mass.unwrap_or(density * area);
        // about the first axis: the two faces across it, then the two pairs beside it, each
        // plate's moment moved off by half the box
        let moment = |(a, b, c): (f64, f64, f64)| m / area * 2.0 * (b * c * (b * b + c * c) / 12.0 + a * c * (b * b / 4.0 + c * c / 12.0) + a * b * (b * b / 12.0 + c * c / 4.0));
        return Some((m, DVec3::new(moment((a, b, c)), moment((b, a, c)), moment((c, a, b)))));
    }
    // the parts' areas: a cylinder's side and caps, a capsule's side and sphere
    let (side, ends) = match kind {
        GeomType::Sphere => (0.0, 4.0 * PI * r * r),
        GeomType::Cylinder => (2.0 * PI * r * h, 2.0 * PI * r * r),
        GeomType::Capsule => (2.0 * PI * r * h, 4.0 * PI * r * r),
        _ => return None,
    };
    let m = mass.unwrap_or(density * (side + ends));
    let (ms, me) = (m * side / (side + ends), m * ends / (side + ends));
    // a thin tube: r² about its axis, r²/2 + h²/12 across it
    let (tube_z, tube_x) = (ms * r * r, ms * (r * r / 2.0 + h * h / 12.0));
    let (z, x) = match kind {
        GeomType::Sphere => (2.0 / 3.0 * me * r * r, 2.0 / 3.0 * me * r * r),
        // two disks at ±h/2
        GeomType::Cylinder => (me * r * r / 2.0, me * (r * r / 4.0 + h * h / 4.0)),
        // two hemispherical shells at ±h/2, each one's centroid r/2 beyond its rim
        _ => (2.0 / 3.0 * me * r * r, me * (2.0 / 3.0 * r * r + h * r / 2.0 + h * h / 4.0)),
    };
    Some((m, DVec3::new(tube_x + x, tube_x + x, tube_z + z)))
}

/// Rigid inertia of a geom expressed in its body's frame.
pub fn geom_inertia(g: &GeomSpec) -> SpatialInertia {
    let (m, moments) = g.shell.then(|| shell(g.kind, g.size, g.density, g.mass)).flatten().unwrap_or_else(|| {
        let m = g.mass.unwrap_or_else(|| g.density * geom_volume(g.kind, g.size));
        (m, geom_moments(g.kind, g.size, m))
    });
    let rot = DMat3::from_quat(g.quat);
    let local = SpatialInertia::new(m, DVec3::ZERO, DMat3::from_diagonal(moments));
    local.to_parent(rot, g.pos)
}

/// The principal axes of body `b`'s inertia `i` (columns, body axes): a body whose inertia is its
/// one geom's takes the geom's axes, and one given by a diagonal `<inertial>` that element's, as
/// MuJoCo's compiler does (which matters where moments are equal: fluid forces are not symmetric
/// about such axes).
pub(super) fn inertia_axes(spec: &ModelSpec, b: &BodySpec, i: &SpatialInertia) -> DMat3 {
    match (b.geoms.as_slice(), &b.inertial) {
        ([g], _) if from_geoms(spec, b) => DMat3::from_quat(g.quat),
        // a diagonal `<inertial>`: its own frame
        (_, Some(inertial)) if !from_geoms(spec, b) && inertial.inertia[3..] == [0.0; 3] => DMat3::from_quat(inertial.quat),
        _ => principal_axes(i.ic).1,
    }
}

/// The sides of the box with inertia `i`'s mass and its moments about `axes` (principal), along
/// them (MuJoCo's inertia-box fluid model).
pub(super) fn fluid_box(i: &SpatialInertia, axes: DMat3) -> DVec3 {
    if i.mass <= 0.0 {
        return DVec3::ZERO;
    }
    let p = axes.transpose() * i.ic * axes;
    let (a, b, c) = (p.x_axis.x, p.y_axis.y, p.z_axis.z);
    let side = |x: f64, y: f64, z: f64| ((y + z - x).max(1e-15) / i.mass * 6.0).sqrt();
    DVec3::new(side(a, b, c), side(b, a, c), side(c, a, b))
}

/// Whether body `b`'s inertia comes from its geoms (`<compiler inertiafromgeom>`).
pub(super) fn from_geoms(spec: &ModelSpec, b: &BodySpec) -> bool {
    match spec.inertiafromgeom {
        InertiaFromGeom::True => true,
        InertiaFromGeom::False => false,
        InertiaFromGeom::Auto => b.inertial.is_none(),
    }
}

/// Each body's mass properties in its own frame: from its geoms or its `<inertial>` as the
/// compiler's `inertiafromgeom` says, scaled to `settotalmass`.
pub(super) fn body_inertias(spec: &ModelSpec) -> Vec<SpatialInertia> {
    let mut inertia: Vec<SpatialInertia> = spec
        .bodies
        .iter()
        .enumerate()
        .map(|(id, b)| {
            if id == 0 {
                return SpatialInertia::ZERO;
            }
            if from_geoms(spec, b) {
                let [lo, hi] = spec.inertiagroups;
                b.geoms.iter().filter(|g| (lo..=hi).contains(&g.group)).fold(SpatialInertia::ZERO, |acc, g| acc.combine(&geom_inertia(g)))
            } else if let Some(i) = &b.inertial {
                let [xx, yy, zz, xy, xz, yz] = i.inertia;
                let local = DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz));
                SpatialInertia::new(i.mass, DVec3::ZERO, local).to_parent(DMat3::from_quat(i.quat), i.pos)
            } else {
                SpatialInertia::ZERO
            }
        })
        .map(|i| bounded(i, spec.bounds))
        .collect();
    inertia[0] = SpatialInertia::ZERO;
    if let Some(total) = spec.settotalmass {
        let sum: f64 = inertia.iter().map(|i| i.mass).sum();
        if sum > 0.0 {
            let k = total / sum;
            for i in &mut inertia {
                i.mass *= k;
                i.ic *= k;
            }
        }
    }
    inertia
}

/// A body's mass and principal moments raised to at least `boundmass` and `boundinertia`, as
/// MuJoCo's compiler bounds them (`mjCBody::Compile`), about the same principal axes.
fn bounded(mut i: SpatialInertia, [mass, moment]: [f64; 2]) -> SpatialInertia {
    i.mass = i.mass.max(mass);
    if moment > 0.0 {
        let (moments, axes) = principal_axes(i.ic);
        if moments.min_element() < moment {
            i.ic = axes * DMat3::from_diagonal(moments.max(DVec3::splat(moment))) * axes.transpose();
        }
    }
    i
}

/// Stiffness and damping of the joints with a `springdamper` (time constant τ, damping ratio ζ),
/// as MuJoCo sets them: with m the joint's effective inertia at qpos0, 1 / (M⁻¹)ᵢᵢ (`kin`: there),
/// stiffness m / (τ ζ)² and damping 2 m / τ.
pub(super) fn spring_dampers(m: &mut Model, spec: &ModelSpec, kin: &KinData) {
    let joints: Vec<_> = spec.bodies.iter().flat_map(|b| &b.joints).collect();
    if joints.iter().all(|j| j.springdamper.is_none()) {
        return;
    }
    let mass_matrix = crate::dynamics::crba::crba(m, kin);
    for (j, spec) in joints.iter().enumerate() {
        let Some([tc, dr]) = spec.springdamper else { continue };
        let d = m.jnt_dofadr[j];
        let mut unit = vec![0.0; m.nv];
        unit[d] = 1.0;
        let inertia = 1.0 / crate::dynamics::crba::cholesky_solve(&mass_matrix, &unit)[d];
        m.jnt_stiffness[j] = inertia / (tc * tc * dr * dr);
        m.dof_damping[d] = 2.0 * inertia / tc;
    }
}
