//! Geometry assets. Each `<mesh>` read (file or inline), compiled into its principal frame, and
//! each mesh geom moved into that frame as MuJoCo's compiler moves it: the geom's position gains
//! the mesh's centre, its orientation the mesh's principal axes, its size becomes the mesh's
//! inertia box and its mass density × volume (or the mass given). Each `<hfield>` read (file,
//! inline or zeros) and normalized; a height-field geom takes its size and has no mass.

use std::path::{Path, PathBuf};

use glam::DMat3;

use crate::error::{Error, Result};
use crate::geometry::hfield::{normalize, read_hfield};
use crate::geometry::{read_mesh, HField, Mesh, RawMesh};
use crate::mjcf::include::Expanded;
use crate::mjcf::{GeomType, ModelSpec};

/// An asset file's path (its element at `line` of `x`): `meshdir` (or `assetdir`) and `file`
/// relative to the main file's directory, else the first of these that names a file: `file`
/// alone there, then both relative to the directory of the file the element is in (an
/// included file's own assets, as MuJoCo finds Menagerie's `mjx_panda.xml` meshes when a
/// Playground scene includes it).
fn asset_path(spec: &ModelSpec, x: &Expanded, line: u32, file: &str) -> PathBuf {
    let with_dir = |d: &Path| spec.meshdir.as_ref().map_or_else(|| d.join(file), |m| d.join(m).join(file));
    let first = with_dir(&x.dir);
    if first.is_file() {
        return first;
    }
    let own = x.dir_of(line);
    [x.dir.join(file), with_dir(own), own.join(file)].into_iter().find(|p| p.is_file()).unwrap_or(first)
}

/// The model's height fields, files found by [`asset_path`].
pub(super) fn load_hfields(spec: &ModelSpec, x: &Expanded) -> Result<Vec<HField>> {
    spec.hfields
        .iter()
        .map(|hs| {
            let (nrow, ncol, mut data) = match &hs.file {
                Some(f) => read_hfield(&asset_path(spec, x, hs.line, f)).map_err(|e| in_element(e, "hfield", hs.line))?,
                None if hs.elevation.is_empty() => (hs.nrow, hs.ncol, vec![0.0; hs.nrow * hs.ncol]),
                // MuJoCo reads inline elevations with the first row at +y
                None => (hs.nrow, hs.ncol, hs.elevation.chunks(hs.ncol.max(1)).rev().flatten().copied().collect()),
            };
            normalize(&mut data);
            Ok(HField { name: hs.name.clone(), nrow, ncol, size: hs.size, data })
        })
        .collect()
}

/// The model's meshes, files found by [`asset_path`].
pub(super) fn load_meshes(spec: &ModelSpec, x: &Expanded) -> Result<Vec<Mesh>> {
    spec.meshes
        .iter()
        .map(|ms| {
            let raw = match &ms.file {
                Some(f) => read_mesh(&asset_path(spec, x, ms.line, f)).map_err(|e| in_element(e, "mesh", ms.line))?,
                None => {
                    let raw = RawMesh { vert: ms.vertex.clone(), face: ms.face.clone(), ..RawMesh::default() };
                    crate::geometry::read::check(&raw).map_err(|m| Error::model("mesh", Some("vertex"), ms.line, m))?;
                    raw
                }
            };
            Mesh::new(&ms.name, &raw, &ms.placement).map_err(|m| Error::model("mesh", None, ms.line, m))
        })
        .collect()
}

/// A file's error, about the `element` at `line`.
fn in_element(e: Error, element: &str, line: u32) -> Error {
    match e {
        Error::Io(m, _) | Error::Compile(m) => Error::model(element, Some("file"), line, m),
        other => other,
    }
}

/// Moves each mesh geom into its mesh's frame and gives it the mesh's mass; gives each
/// height-field geom its field's size and no mass.
pub(super) fn fit_geoms(spec: &mut ModelSpec, meshes: &[Mesh], hfields: &[HField]) -> Result<()> {
    for g in spec.bodies.iter_mut().flat_map(|b| b.geoms.iter_mut()) {
        if g.kind == GeomType::Hfield {
            let name = g.hfield.as_deref().unwrap_or("");
            let h = hfields.iter().find(|h| h.name == name).ok_or_else(|| Error::model("geom", Some("hfield"), g.line, format!("unknown hfield '{name}'")))?;
            g.size = [h.size[0], h.size[1], h.size[2]];
            g.mass = Some(0.0);
            continue;
        }
        if g.kind != GeomType::Mesh {
            continue;
        }
        let name = g.mesh.as_deref().unwrap_or("");
        let mesh = meshes.iter().find(|m| m.name == name).ok_or_else(|| Error::model("geom", Some("mesh"), g.line, format!("unknown mesh '{name}'")))?;
        let f = &mesh.frame;
        g.pos += DMat3::from_quat(g.quat) * f.pos;
        g.quat = (g.quat * f.quat).normalize();
        g.size = f.boxsz.to_array();
        // the inertia box of this mass has the mesh's moments (box moments m/3 (b² + c²))
        g.mass = Some(g.mass.unwrap_or(g.density * f.volume));
    }
    Ok(())
}
