//! Rendering arguments (size, camera, which worlds) → [`crate::render`], and frames → NumPy.

use std::sync::Arc;

use glam::DVec3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::Model;
use crate::render::{CameraChoice, FreeCamera, Poses, Renderer, MAX_SIDE};

/// Most bytes one render call may return.
const MAX_BYTES: usize = 1 << 32;

/// Checks an image size.
pub fn check_size(width: i64, height: i64, frames: usize) -> PyResult<(usize, usize)> {
    let side = |v: i64, what: &str| {
        if v < 1 || v as usize > MAX_SIDE {
            return Err(PyValueError::new_err(format!("{what} must be between 1 and {MAX_SIDE} pixels, got {v}")));
        }
        Ok(v as usize)
    };
    let (w, h) = (side(width, "width")?, side(height, "height")?);
    if w * h * 7 * frames.max(1) > MAX_BYTES {
        return Err(PyValueError::new_err(format!(
            "{frames} frames of {w}×{h} would take more than {} GiB; render fewer worlds or smaller frames",
            MAX_BYTES >> 30
        )));
    }
    Ok((w, h))
}

/// The camera a `camera` argument names: None or −1 for the model's default free camera, a
/// camera index or name, or a dict of free-camera settings (`lookat`, `distance`, `azimuth`,
/// `elevation`, and `trackbodyid` with `type="tracking"`), missing keys taken from the default.
pub fn camera(m: &Model, r: &Renderer, cam: Option<&Bound<'_, PyAny>>) -> PyResult<CameraChoice> {
    let ncam = m.vis.cameras.len();
    let names = || m.vis.cameras.iter().map(|c| c.name.as_str()).filter(|n| !n.is_empty()).collect::<Vec<_>>();
    let mut free = default_free(m, r);
    let Some(cam) = cam else { return Ok(CameraChoice::Free(free)) };
    if cam.is_none() {
        return Ok(CameraChoice::Free(free));
    }
    if let Ok(i) = cam.extract::<i64>() {
        return match i {
            -1 => Ok(CameraChoice::Free(free)),
            i if i >= 0 && (i as usize) < ncam => Ok(CameraChoice::Model(i as usize)),
            _ => Err(PyValueError::new_err(format!("camera id {i} out of range: the model has {ncam} cameras (ids 0..{ncam}, or -1 for the free camera)"))),
        };
    }
    if let Ok(name) = cam.extract::<String>() {
        return m.vis.cameras.iter().position(|c| c.name == name).map(CameraChoice::Model).ok_or_else(|| {
            PyValueError::new_err(format!("no camera named '{name}'; the model's cameras: {:?}", names()))
        });
    }
    let d = cam.cast::<PyDict>().map_err(|_| PyTypeError::new_err("camera must be None, an int, a str or a dict of free-camera settings"))?;
    let mut tracking = false;
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        let num = |v: &Bound<'_, PyAny>| -> PyResult<f64> {
            let x: f64 = v.extract().map_err(|_| PyTypeError::new_err(format!("camera['{key}'] must be a number")))?;
            if !x.is_finite() {
                return Err(PyValueError::new_err(format!("camera['{key}'] must be finite, got {x}")));
            }
            Ok(x)
        };
        match key.as_str() {
            "lookat" => {
                let v: Vec<f64> = v.extract().map_err(|_| PyTypeError::new_err("camera['lookat'] must be 3 numbers"))?;
                if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
                    return Err(PyValueError::new_err(format!("camera['lookat'] must be 3 finite numbers, got {v:?}")));
                }
                free.lookat = DVec3::new(v[0], v[1], v[2]);
            }
            "distance" => {
                free.distance = num(&v)?;
                if free.distance <= 0.0 {
                    return Err(PyValueError::new_err(format!("camera['distance'] must be positive, got {}", free.distance)));
                }
            }
            "azimuth" => free.azimuth = num(&v)?,
            "elevation" => free.elevation = num(&v)?,
            "trackbodyid" => {
                let b: i64 = v.extract().map_err(|_| PyTypeError::new_err("camera['trackbodyid'] must be an int"))?;
                if b < -1 || b >= m.nbody as i64 {
                    return Err(PyValueError::new_err(format!("camera['trackbodyid'] {b} out of range: the model has {} bodies", m.nbody)));
                }
                free.track_body = (b >= 0).then_some(b as usize);
            }
            "type" => {
                // MuJoCo's mjtCamera: 0 free, 1 tracking
                tracking = match v.extract::<String>().as_deref() {
                    Ok("free") => false,
                    Ok("tracking") => true,
                    _ => match v.extract::<i64>() {
                        Ok(0) => false,
                        Ok(1) => true,
                        _ => return Err(PyValueError::new_err("camera['type'] must be 'free' (0) or 'tracking' (1)")),
                    },
                };
            }
            // MuJoCo's fixed-camera fields, meaningless for a free camera
            "fixedcamid" | "orthographic" => {}
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown camera setting '{other}'; known: lookat, distance, azimuth, elevation, trackbodyid, type"
                )));
            }
        }
    }
    if !tracking {
        free.track_body = None;
    }
    Ok(CameraChoice::Free(free))
}

/// MuJoCo's default free camera (`mjv_defaultFreeCamera`): the model centre from 1.5 extents at
/// the model's `<global>` azimuth and elevation.
pub fn default_free(m: &Model, r: &Renderer) -> FreeCamera {
    FreeCamera { lookat: r.center, distance: 1.5 * r.extent, azimuth: m.vis.azimuth, elevation: m.vis.elevation, track_body: None }
}

/// One camera per world: a list or tuple of `camera` arguments (one each), else one for all.
pub fn cameras(m: &Model, r: &Renderer, cam: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Vec<CameraChoice>> {
    if let Some(c) = cam
        && (c.is_instance_of::<pyo3::types::PyList>() || c.is_instance_of::<pyo3::types::PyTuple>())
    {
        let items: Vec<Bound<'_, PyAny>> = c.try_iter()?.collect::<PyResult<_>>()?;
        if items.len() != n {
            return Err(PyValueError::new_err(format!("camera: a list needs one camera per rendered world ({n}), got {}", items.len())));
        }
        return items.iter().map(|c| camera(m, r, Some(c))).collect();
    }
    Ok(vec![camera(m, r, cam)?; n])
}

/// What a render call returns: frames of `width` × `height`, rgb and/or depth, with a leading
/// world axis unless `single`.
#[derive(Clone, Copy)]
pub struct Frames {
    pub width: usize,
    pub height: usize,
    pub rgb: bool,
    pub depth: bool,
    pub single: bool,
}

/// Draws the worlds at `qpos` rows (each world's model, whose kinematics place its bodies, and
/// its qpos), world k through `cams[k]`, the GIL released,
/// and returns rgb (n, H, W, 3) uint8 and/or depth (n, H, W) float32, a tuple when both (`single`:
/// one world, without the leading axis).
pub fn draw<'py>(py: Python<'py>, m: &Arc<Model>, r: &Renderer, qpos: &[(&Model, &[f64])], looks: &[super::placed::WorldLook], cams: &[CameraChoice], frames: Frames) -> PyResult<Bound<'py, PyAny>> {
    let Frames { width, height, rgb, depth, single } = frames;
    if !rgb && !depth {
        return Err(PyValueError::new_err("nothing to render: rgb and depth are both False"));
    }
    let n = qpos.len();
    let mut rgb_buf = vec![0u8; if rgb { n * height * width * 3 } else { 0 }];
    let mut depth_buf = vec![0f32; if depth { n * height * width } else { 0 }];
    py.detach(|| {
        super::errors::guard("render", || {
            let poses: Vec<Poses> = qpos.iter().zip(looks).map(|((own, q), (placed, surfaces))| Poses::new(own, q).with_placed(placed).with_surfaces(surfaces.clone())).collect();
            let worlds: Vec<(&Poses, CameraChoice)> = poses.iter().zip(cams).map(|(p, c)| (p, *c)).collect();
            r.draw(m, &worlds, width, height, &mut rgb_buf, &mut depth_buf);
        })
    })?;
    let mut out = vec![];
    if rgb {
        out.push(PyArray1::from_vec(py, rgb_buf).reshape([n, height, width, 3])?.into_any());
    }
    if depth {
        out.push(PyArray1::from_vec(py, depth_buf).reshape([n, height, width])?.into_any());
    }
    if single {
        out = out.into_iter().map(|a| a.get_item(0)).collect::<PyResult<_>>()?;
    }
    match out.len() {
        1 => Ok(out.remove(0)),
        _ => Ok(pyo3::types::PyTuple::new(py, out)?.into_any()),
    }
}

