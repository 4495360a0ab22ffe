//! A compiled mesh: its surface and convex hull in the frame MuJoCo moves it into (centre of
//! mass at the origin, principal axes along x, y, z), its mass properties per unit density.

use glam::{DMat3, DQuat, DVec3};

use super::hull::Hull;
use super::mass::{mass_frame, MeshFrame, MeshInertia};
use super::read::RawMesh;

/// How a `<mesh>` element places and scales its file's vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPlacement {
    /// Per-axis scale (a negative product mirrors the mesh and flips its faces).
    pub scale: DVec3,
    /// The file's point that becomes the origin (MuJoCo's `refpos`).
    pub refpos: DVec3,
    /// The file's frame that becomes the mesh frame (MuJoCo's `refquat`).
    pub refquat: DQuat,
    /// Mass distribution.
    pub inertia: MeshInertia,
}

impl Default for MeshPlacement {
    fn default() -> Self {
        MeshPlacement { scale: DVec3::ONE, refpos: DVec3::ZERO, refquat: DQuat::IDENTITY, inertia: MeshInertia::Legacy }
    }
}

/// A mesh asset, compiled.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Name.
    pub name: String,
    /// Vertices in the mesh frame.
    pub vert: Vec<DVec3>,
    /// Triangles (of the hull when the file gives no faces).
    pub face: Vec<[u32; 3]>,
    /// Each triangle's corner normals in the mesh frame, when the file gives normals.
    pub corner_normal: Vec<[DVec3; 3]>,
    /// Convex hull in the mesh frame: the collision shape.
    pub hull: Hull,
    /// Mass properties, and where the mesh frame lies in the file's.
    pub frame: MeshFrame,
    /// Largest distance of a vertex from the origin.
    pub rbound: f64,
}

impl Mesh {
    /// Compiles `raw` placed by `p`; an error names what is degenerate.
    pub fn new(name: &str, raw: &RawMesh, p: &MeshPlacement) -> Result<Mesh, String> {
        if raw.vert.len() < 4 {
            return Err(format!("mesh '{name}' has {} vertices; at least 4 are needed", raw.vert.len()));
        }
        let turn = DMat3::from_quat(p.refquat.normalize()).transpose();
        let vert: Vec<DVec3> = raw.vert.iter().map(|v| turn * (DVec3::from_array(v.map(f64::from)) - p.refpos) * p.scale).collect();
        let mirrored = p.scale.x * p.scale.y * p.scale.z < 0.0;
        let hull = Hull::new(&vert).ok_or_else(|| format!("mesh '{name}': its vertices span no volume"))?;
        let face: Vec<[u32; 3]> = if raw.face.is_empty() {
            hull.tris.iter().map(|t| t.map(|i| vert.iter().position(|v| *v == hull.vert[i as usize]).unwrap_or(0) as u32)).collect()
        } else if mirrored {
            raw.face.iter().map(|&[a, b, c]| [a, c, b]).collect()
        } else {
            raw.face.clone()
        };
        let frame = mass_frame(&vert, &face, Some(&hull), p.inertia).map_err(|e| format!("mesh '{name}': {e}"))?;
        let rot = DMat3::from_quat(frame.quat).transpose();
        let to_frame = |v: DVec3| rot * (v - frame.pos);
        let vert: Vec<DVec3> = vert.into_iter().map(to_frame).collect();
        let mut hull = hull;
        hull.move_into(rot, frame.pos);
        let rbound = vert.iter().map(|v| v.length()).fold(0.0, f64::max);
        // the file's normals through the same placement (the inverse-transpose of the scale, so
        // they stay perpendicular to the scaled faces; MuJoCo multiplies, which differs only for
        // unequal scales), normalized
        let normal: Vec<DVec3> = raw.normal.iter().map(|n| (rot * (turn * DVec3::from_array(n.map(f64::from)) / p.scale)).normalize_or(DVec3::Z)).collect();
        let corner_normal = if normal.is_empty() || raw.face.is_empty() {
            vec![]
        } else {
            raw.face_normal.iter().map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] }.map(|i| normal[i as usize])).collect()
        };
        Ok(Mesh { name: name.to_string(), vert, face, corner_normal, hull, frame, rbound })
    }
}
