//! Geometry assets: `<mesh>` (a file or inline vertices and faces, placed by scale and a
//! reference frame) and `<hfield>` (a file, inline elevations or a grid of zeros).

use glam::{DQuat, DVec3};
use roxmltree::Node;

use super::element::El;
use super::Parser;
use crate::error::Result;
use crate::geometry::{MeshInertia, MeshPlacement};
use crate::mjcf::{HFieldSpec, MeshSpec};

const MESH_ATTRS: &[&str] = &[
    "name", "class", "file", "vertex", "face", "normal", "texcoord", "scale", "refpos", "refquat", "inertia",
    "maxhullvert", "smoothnormal", "content_type",
];

const HFIELD_ATTRS: &[&str] = &["name", "file", "nrow", "ncol", "size", "elevation", "content_type"];

impl Parser<'_> {
    pub(super) fn hfield(&mut self, n: Node) -> Result<HFieldSpec> {
        let e = self.el(n, None)?;
        e.check(HFIELD_ATTRS)?;
        let (file, name) = file_and_name(&e, "height field")?;
        let size = e.arr::<4>("size")?.ok_or_else(|| e.err("size", "a height field needs a size (x y z base)"))?;
        if size.iter().any(|&s| s <= 0.0) {
            return Err(e.err("size", format!("sizes must be positive, got {size:?}")));
        }
        let (nrow, ncol) = (e.uint("nrow", 0)? as usize, e.uint("ncol", 0)? as usize);
        let elevation = e.nums("elevation")?.unwrap_or_default();
        if file.is_some() && (nrow > 0 || ncol > 0 || !elevation.is_empty()) {
            return Err(e.err("file", "a height field from a file takes no nrow, ncol or elevation"));
        }
        if file.is_none() && (nrow < 2 || ncol < 2) {
            return Err(e.err("nrow", format!("a height field needs a file or nrow, ncol of at least 2, got {nrow} × {ncol}")));
        }
        if nrow.saturating_mul(ncol) > 1 << 26 {
            return Err(e.err("nrow", format!("a {nrow} × {ncol} grid is larger than sinew accepts (2^26 points)")));
        }
        if !elevation.is_empty() && elevation.len() != nrow * ncol {
            return Err(e.err("elevation", format!("{} values for a {nrow} × {ncol} grid", elevation.len())));
        }
        Ok(HFieldSpec { name, file, nrow, ncol, size, elevation, line: e.line })
    }

    pub(super) fn mesh(&mut self, n: Node) -> Result<MeshSpec> {
        let e = self.el(n, None)?;
        e.check(MESH_ATTRS)?;
        let (file, name) = file_and_name(&e, "mesh")?;
        let vertex = e.nums("vertex")?.unwrap_or_default();
        if vertex.len() % 3 != 0 {
            return Err(e.err("vertex", format!("expected x y z triples, got {} numbers", vertex.len())));
        }
        let face = e.nums("face")?.unwrap_or_default();
        if face.len() % 3 != 0 || face.iter().any(|&i| i < 0.0 || i.fract() != 0.0 || i as usize >= vertex.len() / 3) {
            return Err(e.err("face", "expected triples of indices of the given vertices"));
        }
        if file.is_some() != vertex.is_empty() {
            return Err(e.err("file", "a mesh needs a file or inline vertices, not both"));
        }
        let inertia = match e.get("inertia").unwrap_or("legacy") {
            "legacy" => MeshInertia::Legacy,
            "convex" => MeshInertia::Convex,
            "exact" => MeshInertia::Exact,
            "shell" => MeshInertia::Shell,
            v => return Err(e.err("inertia", format!("expected legacy, convex, exact or shell, got '{v}'"))),
        };
        let scale = e.vec3("scale", DVec3::ONE)?;
        if scale.to_array().contains(&0.0) {
            return Err(e.err("scale", "must not be zero"));
        }
        let refquat = match e.arr::<4>("refquat")? {
            Some(q) => DQuat::from_xyzw(q[1], q[2], q[3], q[0]),
            None => DQuat::IDENTITY,
        };
        if refquat.length() < 1e-12 {
            return Err(e.err("refquat", "zero quaternion"));
        }
        Ok(MeshSpec {
            name,
            file,
            vertex: vertex.chunks_exact(3).map(|v| [v[0] as f32, v[1] as f32, v[2] as f32]).collect(),
            face: face.chunks_exact(3).map(|f| [f[0] as u32, f[1] as u32, f[2] as u32]).collect(),
            placement: MeshPlacement { scale, refpos: e.vec3("refpos", DVec3::ZERO)?, refquat, inertia },
            line: e.line,
        })
    }
}

/// An asset's `file` and its name: `name`, else the file's stem (MuJoCo's rule); an asset with
/// neither is an error.
fn file_and_name(e: &El, what: &str) -> Result<(Option<String>, String)> {
    let file = e.get("file").map(str::to_string);
    let name = match (e.get("name"), &file) {
        (Some(s), _) => s.to_string(),
        (None, Some(f)) => std::path::Path::new(f).file_stem().and_then(|s| s.to_str()).unwrap_or(f).to_string(),
        (None, None) => return Err(e.err("name", format!("a {what} without a file needs a name"))),
    };
    Ok((file, name))
}
