//! Ray casting against geoms, as MuJoCo's `mj_ray` does it: the distance along a ray to the
//! first geom surface it meets (from inside a geom, the way out), or −1. Geoms of an excluded
//! body and invisible geoms (alpha 0) are not seen; a plane is seen
//! from its front only, within its size where that is positive; a mesh by its triangles; a
//! height field by its surface's triangles and its base.

use glam::DVec3;

use crate::dynamics::kinematics::KinData;
use crate::dynamics::tendon::geom_pose;
use crate::geometry::grid_walk::{clip, triangle, walk};
use crate::geometry::HField;
use crate::model::{GeomType, Model};

/// Distance from `origin` along `dir` (a unit vector) to the nearest geom not on body
/// `exclude`, or −1 when the ray meets none (MuJoCo's `mj_ray` with every group and static
/// geoms included).
pub fn ray(m: &Model, kin: &KinData, origin: DVec3, dir: DVec3, exclude: usize) -> f64 {
    let mut best = f64::INFINITY;
    for g in 0..m.ngeom {
        if m.geom_body[g] == exclude || invisible(m, g) {
            continue;
        }
        let (rot, centre) = geom_pose(m, kin, g);
        // the ray in the geom's frame
        let (p, d) = (rot.transpose() * (origin - centre), rot.transpose() * dir);
        if let Some(t) = ray_geom(m, g, p, d).filter(|&t| t >= 0.0 && t < best) {
            best = t;
        }
    }
    if best.is_finite() { best } else { -1.0 }
}

/// Whether geom g is fully transparent (its colour as compiled: a material's where the geom
/// takes its material's colour).
fn invisible(m: &Model, g: usize) -> bool {
    m.vis.geom_rgba.get(g).is_some_and(|c| c[3] == 0.0)
}

/// The ray (p, d) in geom g's frame against its shape.
fn ray_geom(m: &Model, g: usize, p: DVec3, d: DVec3) -> Option<f64> {
    let s = m.geom_size[g];
    match m.geom_type[g] {
        GeomType::Plane => {
            // seen from the front (+z) only
            if d.z >= -1e-15 {
                return None;
            }
            let t = -p.z / d.z;
            let hit = p + t * d;
            let within = |v: f64, half: f64| half <= 0.0 || v.abs() <= half;
            (t >= 0.0 && within(hit.x, s[0]) && within(hit.y, s[1])).then_some(t)
        }
        kind @ (GeomType::Sphere | GeomType::Ellipsoid | GeomType::Capsule | GeomType::Cylinder | GeomType::Box) => ray_primitive(kind, s, p, d),
        GeomType::Mesh => {
            let mesh = &m.meshes[m.geom_mesh[g]?];
            min_of(mesh.face.iter().map(|f| triangle(p, d, f.map(|i| mesh.vert[i as usize]))))
        }
        GeomType::Hfield => hfield(&m.hfields[m.geom_hfield[g]?], p, d),
    }
}

/// The ray (p, d), in the frame of a primitive shape of `kind` and `size`, against it: the entry,
/// or the exit from inside (MuJoCo's `mju_rayGeom`); None for a plane, mesh or height field.
pub fn ray_primitive(kind: GeomType, s: [f64; 3], p: DVec3, d: DVec3) -> Option<f64> {
    match kind {
        GeomType::Sphere => sphere(p, d, s[0]),
        GeomType::Ellipsoid => {
            // a unit sphere in coordinates scaled by the semi-axes
            let r = DVec3::from_array(s);
            let (q, e) = (p / r, d / r);
            sphere(q, e, 1.0)
        }
        GeomType::Capsule => {
            let caps = [DVec3::new(0.0, 0.0, s[1]), DVec3::new(0.0, 0.0, -s[1])].map(|c| sphere(p - c, d, s[0]));
            min_of(caps.into_iter().chain([side(p, d, s[0], s[1])]))
        }
        GeomType::Cylinder => {
            let caps = [1.0, -1.0].map(|sign| disk(p, d, sign * s[1], s[0]));
            min_of(caps.into_iter().chain([side(p, d, s[0], s[1])]))
        }
        GeomType::Box => boxed(p, d, DVec3::from_array(s)),
        GeomType::Plane | GeomType::Mesh | GeomType::Hfield => None,
    }
}

/// The least of some distances.
fn min_of(ts: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    ts.flatten().filter(|t| *t >= 0.0).min_by(f64::total_cmp)
}

/// A sphere of radius `r` at the origin: the entry, or the exit from inside.
fn sphere(p: DVec3, d: DVec3, r: f64) -> Option<f64> {
    let (a, b, c) = (d.dot(d), p.dot(d), p.dot(p) - r * r);
    let disc = b * b - a * c;
    if a <= 0.0 || disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    min_of([(-b - root) / a, (-b + root) / a].into_iter().map(Some))
}

/// The side of a cylinder of radius `r` along z within |z| ≤ `half`.
fn side(p: DVec3, d: DVec3, r: f64, half: f64) -> Option<f64> {
    let (a, b, c) = (d.x * d.x + d.y * d.y, p.x * d.x + p.y * d.y, p.x * p.x + p.y * p.y - r * r);
    let disc = b * b - a * c;
    if a <= 1e-30 || disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    min_of([(-b - root) / a, (-b + root) / a].into_iter().map(|t| ((p.z + t * d.z).abs() <= half).then_some(t)))
}

/// The disk of radius `r` in the plane z = `z`.
fn disk(p: DVec3, d: DVec3, z: f64, r: f64) -> Option<f64> {
    if d.z.abs() < 1e-30 {
        return None;
    }
    let t = (z - p.z) / d.z;
    let hit = p + t * d;
    (hit.x * hit.x + hit.y * hit.y <= r * r).then_some(t)
}

/// A box of half-sides `h` about the origin: the entry, or the exit from inside (slabs).
fn boxed(p: DVec3, d: DVec3, h: DVec3) -> Option<f64> {
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-30 {
            if p[k].abs() > h[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((-h[k] - p[k]) / d[k], (h[k] - p[k]) / d[k]);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
    }
    if near > far || far < 0.0 {
        return None;
    }
    Some(if near >= 0.0 { near } else { far })
}

/// A height field: its base box and its surface's triangles, the cells visited in order along
/// the ray's path over the grid.
fn hfield(h: &HField, p: DVec3, d: DVec3) -> Option<f64> {
    let [sx, sy, sz, base] = h.size;
    let base_hit = boxed(p - DVec3::new(0.0, 0.0, -0.5 * base), d, DVec3::new(sx, sy, 0.5 * base));
    // the part of the ray over the grid, within the field's height
    let span = clip(p, d, (0.0, f64::INFINITY), [-sx, -sy, 0.0], [sx, sy, sz]);
    let surface = span.and_then(|(t0, t1)| surface_hit(h, p, d, t0, t1));
    min_of([base_hit, surface].into_iter().chain((0..4).map(|k| wall_hit(h, p, d, k))))
}

/// One of the field's four outer walls (x = −size₀, +size₀, y = −size₁, +size₁), from the
/// base's top up to the surface's edge, which is linear between grid points.
fn wall_hit(h: &HField, p: DVec3, d: DVec3, k: usize) -> Option<f64> {
    let (axis, sign) = (k / 2, if k.is_multiple_of(2) { -1.0 } else { 1.0 });
    let (other, n_along) = if axis == 0 { (1, h.nrow) } else { (0, h.ncol) };
    if d[axis].abs() < 1e-30 {
        return None;
    }
    let t = (sign * h.size[axis] - p[axis]) / d[axis];
    let hit = p + t * d;
    let half = h.size[other];
    if t < 0.0 || hit[other].abs() > half || hit.z < 0.0 {
        return None;
    }
    // the surface's height over the wall at the hit, between the grid points either side
    let u = (hit[other] + half) / (2.0 * half) * (n_along - 1) as f64;
    let i = (u.floor() as usize).min(n_along - 2);
    let at = |j: usize| {
        let (r, c) = if axis == 0 { (j, if sign < 0.0 { 0 } else { h.ncol - 1 }) } else { (if sign < 0.0 { 0 } else { h.nrow - 1 }, j) };
        h.vertex(r, c).z
    };
    let f = u - i as f64;
    (hit.z <= at(i) * (1.0 - f) + at(i + 1) * f).then_some(t)
}

/// The first surface triangle the ray meets between t0 and t1, walking the grid's cells in the
/// order the ray crosses them; a hit a rounding beyond its cell's exit is kept until a nearer one
/// or the walk's end.
fn surface_hit(h: &HField, p: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<f64> {
    let [sx, sy, ..] = h.size;
    let cells = (h.ncol - 1, h.nrow - 1);
    let size = (2.0 * sx / cells.0 as f64, 2.0 * sy / cells.1 as f64);
    let mut best = f64::INFINITY;
    let hit = walk(cells, (-sx, -sy), size, p, d, (t0, t1), |c, r, _, exit| {
        for tri in h.cell_triangles(r, c) {
            if let Some(t) = triangle(p, d, tri).filter(|&t| t >= 0.0) {
                best = best.min(t);
            }
        }
        (best <= exit).then_some(best)
    });
    hit.or(best.is_finite().then_some(best))
}
