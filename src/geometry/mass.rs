//! A mesh's volume, centre and principal inertia as MuJoCo's compiler computes them
//! (`mjCMesh::Process`), and the frame it moves the mesh into: vertices relative to the centre,
//! along the principal axes. A mesh geom's frame is that frame, so its mass and moments are those
//! of a primitive: density × volume, density × moments.

use glam::{DMat3, DQuat, DVec3};

use super::hull::Hull;
use crate::math::principal_axes;

/// MuJoCo's smallest positive value (`mjMINVAL`).
const MINVAL: f64 = 1e-15;

/// How a mesh's mass is distributed (MuJoCo's `<mesh inertia>`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshInertia {
    /// Volume of the convex hull.
    Convex,
    /// Signed volume of a closed, consistently oriented mesh.
    Exact,
    /// Sum of unsigned tetrahedra volumes about the surface centroid (MuJoCo's default).
    #[default]
    Legacy,
    /// Mass on the surface.
    Shell,
}

/// The mass properties of a mesh per unit density, and the frame they are principal in.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshFrame {
    /// Centre of mass in the mesh file's frame (after scale and reference frame).
    pub pos: DVec3,
    /// Principal axes in that frame.
    pub quat: DQuat,
    /// Volume (surface area for a shell).
    pub volume: f64,
    /// Principal moments per unit density, descending.
    pub moments: DVec3,
    /// Half-sides of the box with this volume and these moments (MuJoCo's `geom_size`).
    pub boxsz: DVec3,
}

/// Area, unit normal and centroid of a triangle (area 0 and normal 0 when degenerate).
fn triangle(a: DVec3, b: DVec3, c: DVec3) -> (f64, DVec3, DVec3) {
    let n = (b - a).cross(c - a);
    let len = n.length();
    let cen = (a + b + c) / 3.0;
    if len < MINVAL {
        return (0.0, DVec3::ZERO, cen);
    }
    (len / 2.0, n / len, cen)
}

/// The mass properties of the surface (`vert`, `face`) with distribution `mode`; the hull is
/// needed for [`MeshInertia::Convex`]. An error names what is degenerate.
pub fn mass_frame(vert: &[DVec3], face: &[[u32; 3]], hull: Option<&Hull>, mode: MeshInertia) -> Result<MeshFrame, String> {
    // area-weighted centroid of the faces: the apex of the tetrahedra
    let (mut area, mut facecen) = (0.0, DVec3::ZERO);
    for f in face {
        let (a, _, c) = triangle(vert[f[0] as usize], vert[f[1] as usize], vert[f[2] as usize]);
        facecen += a * c;
        area += a;
    }
    if area < MINVAL {
        return Err("mesh surface area is too small".into());
    }
    facecen /= area;
    let (v, tris): (&[DVec3], &[[u32; 3]]) = match (mode, hull) {
        (MeshInertia::Convex, Some(h)) => (&h.vert, &h.tris),
        (MeshInertia::Convex, None) => return Err("mesh has no convex hull (its vertices span no volume)".into()),
        _ => (vert, face),
    };
    let corners = |f: &[u32; 3]| (v[f[0] as usize], v[f[1] as usize], v[f[2] as usize]);
    // the element of volume of a triangle about `apex`: its tetrahedron or, for a shell, its area
    let element = |(a, n, c): (f64, DVec3, DVec3), apex: DVec3| {
        let vol = match mode {
            MeshInertia::Shell => a,
            _ => (c - apex).dot(n) * a / 3.0,
        };
        if mode == MeshInertia::Legacy { vol.abs() } else { vol }
    };
    let (mut total, mut com) = (0.0, DVec3::ZERO);
    for f in tris {
        let (a, b, c) = corners(f);
        let t = triangle(a, b, c);
        let vol = element(t, facecen);
        total += vol;
        com += vol * (t.2 * 0.75 + facecen * 0.25);
    }
    if total < MINVAL {
        return Err(if total < 0.0 { "mesh volume is negative (misoriented triangles)".into() } else { "mesh volume is too small (try inertia=\"shell\")".into() });
    }
    com /= total;
    // products of inertia about the centre (Tonon 2004 for tetrahedra; MuJoCo's formula)
    let (mut volume, mut p) = (0.0, [0.0; 6]);
    let k = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let c = if mode == MeshInertia::Shell { 12.0 } else { 20.0 };
    for f in tris {
        let (d, e, g) = corners(f);
        let (d, e, g) = (d - com, e - com, g - com);
        let vol = element(triangle(d, e, g), DVec3::ZERO);
        volume += vol;
        for (pj, &(r, s)) in p.iter_mut().zip(&k) {
            *pj += vol / c
                * (2.0 * (d[r] * d[s] + e[r] * e[s] + g[r] * g[s]) + d[r] * e[s] + d[s] * e[r] + d[r] * g[s] + d[s] * g[r] + e[r] * g[s] + e[s] * g[r]);
        }
    }
    let inertia = DMat3::from_cols(
        DVec3::new(p[1] + p[2], -p[3], -p[4]),
        DVec3::new(-p[3], p[0] + p[2], -p[5]),
        DVec3::new(-p[4], -p[5], p[0] + p[1]),
    );
    let (moments, axes) = principal_axes(inertia);
    // descending moments, a right-handed frame (MuJoCo's order)
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| moments[j].total_cmp(&moments[i]));
    let (x, y) = (axes.col(order[0]), axes.col(order[1]));
    let axes = DMat3::from_cols(x, y, x.cross(y));
    let moments = DVec3::new(moments[order[0]], moments[order[1]], moments[order[2]]);
    if moments.z <= 0.0 {
        return Err("an eigenvalue of the mesh inertia is not positive".into());
    }
    let (a, b, cc) = (moments.x, moments.y, moments.z);
    let (rtol, atol) = (1e-6, 1e-9);
    if a + b < cc * (1.0 - rtol) - atol || a + cc < b * (1.0 - rtol) - atol || b + cc < a * (1.0 - rtol) - atol {
        return Err("the eigenvalues of the mesh inertia violate A + B >= C".into());
    }
    let side = |x: f64, y: f64, z: f64| 0.5 * (6.0 * (y + z - x).max(0.0) / volume).sqrt();
    Ok(MeshFrame {
        pos: com,
        quat: DQuat::from_mat3(&axes).normalize(),
        volume,
        moments,
        boxsz: DVec3::new(side(a, b, cc), side(b, a, cc), side(cc, a, b)),
    })
}
