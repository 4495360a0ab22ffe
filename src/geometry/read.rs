//! Mesh files as MuJoCo reads them: STL (binary or ASCII), Wavefront OBJ (its first object,
//! triangles and quads) and MuJoCo's binary `.msh`. Coordinates are single precision in all
//! three, as in MuJoCo's model.

use std::path::Path;

use crate::error::{Error, Result};

/// A mesh as a file gives it: vertices and triangles (indices into `vert`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RawMesh {
    /// Vertex positions.
    pub vert: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub face: Vec<[u32; 3]>,
    /// Normals the file gives (OBJ `vn`, `.msh`), or none.
    pub normal: Vec<[f32; 3]>,
    /// Each triangle's corners' normals (indices into `normal`), when `normal` is given.
    pub face_normal: Vec<[u32; 3]>,
}

/// Reads the mesh file at `path` by its extension (`.stl`, `.obj` or `.msh`, any case).
pub fn read_mesh(path: &Path) -> Result<RawMesh> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| Error::io(format!("cannot read mesh file '{name}'"), &e))?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let mesh = match ext.as_str() {
        "stl" => stl(&bytes),
        "obj" => obj(&bytes),
        "msh" => msh(&bytes),
        _ => Err(format!("unknown mesh file type '.{ext}' (expected .stl, .obj or .msh)")),
    }
    .map_err(|m| Error::Compile(format!("mesh file '{name}': {m}")))?;
    check(&mesh).map_err(|m| Error::Compile(format!("mesh file '{name}': {m}")))?;
    Ok(mesh)
}

/// Every face names an existing vertex and every coordinate is finite and within 2³⁰ (MuJoCo's
/// bound); normals, when given, are finite and named by every face.
pub fn check(m: &RawMesh) -> std::result::Result<(), String> {
    if !m.normal.is_empty()
        && (m.face_normal.len() != m.face.len() || m.face_normal.iter().flatten().any(|&i| i as usize >= m.normal.len()) || m.normal.iter().flatten().any(|x| !x.is_finite()))
    {
        return Err("its normals do not match its faces or are not finite".into());
    }
    if let Some(f) = m.face.iter().position(|f| f.iter().any(|&i| i as usize >= m.vert.len())) {
        return Err(format!("face {f} names a vertex beyond the {} given", m.vert.len()));
    }
    if m.vert.iter().flatten().any(|x| !x.is_finite() || x.abs() > (1u32 << 30) as f32) {
        return Err("a vertex coordinate is not finite or exceeds 2^30".into());
    }
    Ok(())
}

fn stl(bytes: &[u8]) -> std::result::Result<RawMesh, String> {
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).map_err(|e| format!("not a valid STL file: {e}"))?;
    if mesh.faces.is_empty() {
        return Err("no triangles".into());
    }
    // STL's facet normals are not read (MuJoCo computes a mesh's normals)
    Ok(RawMesh {
        vert: mesh.vertices.iter().map(|v| v.0).collect(),
        face: mesh.faces.iter().map(|f| f.vertices.map(|i| i as u32)).collect(),
        ..RawMesh::default()
    })
}

fn obj(bytes: &[u8]) -> std::result::Result<RawMesh, String> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: false, ..Default::default() };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &opts, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| format!("not a valid OBJ file: {e}"))?;
    let Some(first) = models.first() else { return Err("no object".into()) };
    let m = &first.mesh;
    let normal: Vec<[f32; 3]> = m.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]).collect();
    let face_normal: Vec<[u32; 3]> = m.normal_indices.chunks_exact(3).map(|f| [f[0], f[1], f[2]]).collect();
    let usable = face_normal.len() == m.indices.len() / 3 && face_normal.iter().flatten().all(|&i| (i as usize) < normal.len());
    Ok(RawMesh {
        vert: m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
        face: m.indices.chunks_exact(3).map(|f| [f[0], f[1], f[2]]).collect(),
        normal: if usable { normal } else { vec![] },
        face_normal: if usable { face_normal } else { vec![] },
    })
}

/// MuJoCo's `.msh`: four int32 counts (vertices, normals, texture coordinates, faces), then the
/// vertices, normals and texture coordinates as float32 and the faces as int32 triples.
fn msh(bytes: &[u8]) -> std::result::Result<RawMesh, String> {
    let word = |k: usize| -> std::result::Result<[u8; 4], String> {
        bytes.get(4 * k..4 * k + 4).map(|w| [w[0], w[1], w[2], w[3]]).ok_or_else(|| "file too short".to_string())
    };
    let count = |k| word(k).map(i32::from_le_bytes);
    let (nv, nn, nt, nf) = (count(0)?, count(1)?, count(2)?, count(3)?);
    if nv < 4 || nn < 0 || nt < 0 || nf < 0 || (nn > 0 && nn != nv) || (nt > 0 && nt != nv) {
        return Err(format!("invalid sizes (vertices {nv}, normals {nn}, texcoords {nt}, faces {nf})"));
    }
    let (nv, nn, nt, nf) = (nv as usize, nn as usize, nt as usize, nf as usize);
    let words = 4 + 3 * nv + 3 * nn + 2 * nt + 3 * nf;
    if bytes.len() != 4 * words {
        return Err(format!("size {} bytes, expected {}", bytes.len(), 4 * words));
    }
    let float = |k| word(k).map(f32::from_le_bytes);
    let vert = (0..nv).map(|i| Ok([float(4 + 3 * i)?, float(5 + 3 * i)?, float(6 + 3 * i)?])).collect::<std::result::Result<_, String>>()?;
    let normal = (0..nn).map(|i| Ok([float(4 + 3 * nv + 3 * i)?, float(5 + 3 * nv + 3 * i)?, float(6 + 3 * nv + 3 * i)?])).collect::<std::result::Result<Vec<_>, String>>()?;
    let f0 = 4 + 3 * nv + 3 * nn + 2 * nt;
    let index = |k| count(k).and_then(|i| u32::try_from(i).map_err(|_| "negative face index".to_string()));
    let face: Vec<[u32; 3]> = (0..nf).map(|i| Ok([index(f0 + 3 * i)?, index(f0 + 3 * i + 1)?, index(f0 + 3 * i + 2)?])).collect::<std::result::Result<_, String>>()?;
    // per-vertex normals: each corner's is its vertex's
    let face_normal = if normal.is_empty() { vec![] } else { face.clone() };
    Ok(RawMesh { vert, face, normal, face_normal })
}
