//! `sinew.Model`: a compiled, immutable model shared by simulations.

use std::sync::Arc;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::arrays::{mats, ranges, rows3};
use super::errors::to_py;
use crate::render::Renderer;
use crate::model::{Actuation, ConstraintMode, FrictionModel, Integrator, JointType, Model};

/// A compiled model (MuJoCo's mjModel counterpart). Immutable; share it between simulations.
#[pyclass(name = "Model", module = "sinew._core", frozen)]
pub struct PyModel {
    pub inner: Arc<Model>,
    /// The MJCF text it was compiled from (its options may have changed since: `inner.opt`).
    source: Arc<str>,
    /// The file it was read from, where its asset paths start (None: the working directory).
    path: Option<std::path::PathBuf>,
    /// What its frames share, made at the first render.
    renderer: std::sync::OnceLock<Arc<Renderer>>,
}

impl PyModel {
    /// Wraps a model compiled from `source`.
    pub fn new(m: Model, source: Arc<str>) -> Self {
        PyModel { inner: Arc::new(m), source, path: None, renderer: std::sync::OnceLock::new() }
    }

    /// Wraps `m`, a changed copy of this model, keeping its source and path.
    fn sharing(&self, m: Model) -> Self {
        PyModel { path: self.path.clone(), ..PyModel::new(m, self.source.clone()) }
    }

    /// Wraps a model compiled from `source` read as the file at `path`.
    fn at(m: Model, source: Arc<str>, path: std::path::PathBuf) -> Self {
        PyModel { path: Some(path), ..PyModel::new(m, source) }
    }

    /// The model's renderer, made once.
    pub fn renderer(&self) -> Arc<Renderer> {
        self.renderer.get_or_init(|| Arc::new(Renderer::new(&self.inner))).clone()
    }
}

fn friction_name(f: FrictionModel) -> &'static str {
    match f {
        FrictionModel::OneTangent => "one_tangent",
        FrictionModel::Pyramid => "pyramid",
    }
}

fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::Euler => "Euler",
        Integrator::Rk4 => "RK4",
        Integrator::Leapfrog => "leapfrog",
    }
}

#[pymethods]
impl PyModel {
    /// Loads an MJCF file.
    #[staticmethod]
    fn from_mjcf(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let loaded = py.detach(|| {
            super::errors::guard_model("Model.from_mjcf", || {
                Model::load_file(&path)
            })
        })?;
        let (m, source) = loaded.map_err(|e| to_py(py, e))?;
        super::errors::emit_warnings(py, &m)?;
        Ok(PyModel::at(m, source.into(), std::path::absolute(&path).unwrap_or(path)))
    }

    /// Loads a URDF file: the root link fixed to the world unless `floating_base`; `<visual>`
    /// geometry drawn (no contacts, no mass) when `visual`; `package://NAME/…` found under the
    /// directories of `package_dirs` (each holding NAME, or NAME itself); a motor on every joint
    /// with an effort limit when `motors`; the links colliding with each other when
    /// `self_collision` (MuJoCo's rule; off by default, as in PyBullet).
    #[staticmethod]
    #[pyo3(signature = (path, *, floating_base=false, visual=false, package_dirs=None, motors=false, self_collision=false))]
    // Python's keywords, one argument each
    #[allow(clippy::too_many_arguments)]
    fn from_urdf(py: Python<'_>, path: std::path::PathBuf, floating_base: bool, visual: bool, package_dirs: Option<Vec<std::path::PathBuf>>, motors: bool, self_collision: bool) -> PyResult<Self> {
        let mjcf = super::urdf::urdf_to_mjcf(py, path.clone(), floating_base, visual, package_dirs, motors, self_collision)?;
        let loaded = py.detach(|| super::errors::guard_model("Model.from_urdf", || Model::from_mjcf_in(&mjcf, &path)))?;
        let m = loaded.map_err(|e| to_py(py, e))?;
        super::errors::emit_warnings(py, &m)?;
        Ok(PyModel::at(m, mjcf.into(), std::path::absolute(&path).unwrap_or(path)))
    }

    /// Loads MJCF text; its includes and asset files are found as if it were the file `path`
    /// (None: relative to the working directory).
    #[staticmethod]
    #[pyo3(signature = (xml, path=None))]
    fn from_mjcf_string(py: Python<'_>, xml: &str, path: Option<std::path::PathBuf>) -> PyResult<Self> {
        let m = super::errors::guard_model("Model.from_mjcf_string", || match &path {
            Some(p) => Model::from_mjcf_in(xml, p),
            None => Model::from_mjcf(xml),
        })?
        .map_err(|e| to_py(py, e))?;
        super::errors::emit_warnings(py, &m)?;
        Ok(match path {
            Some(p) => PyModel::at(m, xml.into(), p),
            None => PyModel::new(m, xml.into()),
        })
    }

    /// The height fields' names.
    #[getter]
    fn hfield_names(&self) -> Vec<String> {
        self.inner.hfields.iter().map(|h| h.name.clone()).collect()
    }

    /// Each height field's x and y half-extents, height and base depth (nhfield, 4).
    #[getter]
    fn hfield_size<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        numpy::PyArray1::from_vec(py, self.inner.hfields.iter().flat_map(|h| h.size).collect()).reshape([self.inner.hfields.len(), 4])
    }

    /// The elevations (nrow, ncol), in [0, 1] of the field's height, of height field `hfield` (a
    /// name or an index): a copy.
    fn hfield_data<'py>(&self, py: Python<'py>, hfield: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let h = &self.inner.hfields[hfield_index(&self.inner, hfield)?];
        numpy::PyArray1::from_vec(py, h.data.clone()).reshape([h.nrow, h.ncol])
    }

    /// The model's value of a field a batch's worlds may vary (`Batch.set_params` names them).
    fn param<'py>(&self, py: Python<'py>, field: &str) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
        let p = super::params::named(field)?;
        numpy::PyArray1::from_vec(py, p.read(&self.inner)).reshape(super::params::shape(p, &self.inner))
    }

    /// A copy whose height field `hfield` (a name or an index) has the elevations `data` (nrow,
    /// ncol), each finite, in units of the field's height (MuJoCo's `hfield_data`: 0 at the
    /// base's top, 1 at the field's height); everything else shared.
    fn with_hfield_data(&self, hfield: &Bound<'_, PyAny>, data: numpy::PyReadonlyArray2<'_, f64>) -> PyResult<Self> {
        let k = hfield_index(&self.inner, hfield)?;
        let h = &self.inner.hfields[k];
        let a = data.as_array();
        if a.shape() != [h.nrow, h.ncol] {
            return Err(PyValueError::new_err(format!("height field '{}' is {} × {}, got data of shape {:?}", h.name, h.nrow, h.ncol, a.shape())));
        }
        if let Some(bad) = a.iter().find(|x| !x.is_finite() || x.abs() > crate::math::MAX_STATE) {
            return Err(PyValueError::new_err(format!("height field '{}': elevation {bad} is not finite or beyond ±{:e}", h.name, crate::math::MAX_STATE)));
        }
        let mut m = (*self.inner).clone();
        std::sync::Arc::make_mut(&mut m.hfields)[k].data = a.iter().copied().collect();
        Ok(self.sharing(m))
    }

    /// A copy with some options replaced (the model itself never changes); `integrator` is
    /// "Euler", "RK4" or "leapfrog".
    #[pyo3(signature = (*, timestep=None, integrator=None, gravity=None, restitution=None, contact=None, limit=None, friction=None, pd_gains=None, constraint_mode=None, trajectory_gains=None))]
    // Python's keywords, one argument each (what the method's signature and stub show)
    #[allow(clippy::too_many_arguments)]
    fn with_options(
        &self,
        timestep: Option<f64>,
        integrator: Option<&str>,
        gravity: Option<[f64; 3]>,
        restitution: Option<f64>,
        contact: Option<bool>,
        limit: Option<bool>,
        friction: Option<&str>,
        pd_gains: Option<(f64, f64)>,
        constraint_mode: Option<&str>,
        trajectory_gains: Option<(f64, f64)>,
    ) -> PyResult<Self> {
        let mut m = (*self.inner).clone();
        if let Some(h) = timestep {
            if !(h.is_finite() && h > 0.0 && h <= 1.0) {
                return Err(PyValueError::new_err(format!("timestep must lie in (0, 1] s, got {h}")));
            }
            m.opt.timestep = h;
        }
        if let Some(i) = integrator {
            m.opt.integrator = match i {
                "Euler" => Integrator::Euler,
                "RK4" => Integrator::Rk4,
                "leapfrog" => Integrator::Leapfrog,
                _ => return Err(PyValueError::new_err(format!("integrator must be 'Euler', 'RK4' or 'leapfrog', got '{i}'"))),
            };
        }
        if let Some(g) = gravity {
            if g.iter().any(|x| crate::math::out_of_range(*x)) {
                return Err(PyValueError::new_err(format!("gravity must be finite and within ±{:e}, as in a model file", crate::math::MAX_STATE)));
            }
            m.opt.gravity = glam::DVec3::from_array(g);
        }
        if let Some(e) = restitution {
            if !(0.0..=1.0).contains(&e) {
                return Err(PyValueError::new_err(format!("restitution must lie in [0, 1], got {e}")));
            }
            m.opt.restitution = e;
        }
        if let Some(c) = contact {
            m.opt.contact = c;
        }
        if let Some(l) = limit {
            m.opt.limit = l;
        }
        if let Some((kp, kd)) = trajectory_gains {
            if !(kp >= 0.0 && kd >= 0.0 && kp <= crate::math::MAX_STATE && kd <= crate::math::MAX_STATE) {
                return Err(PyValueError::new_err(format!("trajectory_gains must lie in [0, 1e10], got ({kp}, {kd})")));
            }
            if pd_gains.is_some() {
                return Err(PyValueError::new_err("give pd_gains or trajectory_gains, not both"));
            }
            m.opt.actuation = Actuation::Trajectory { kp, kd };
        }
        if let Some(c) = constraint_mode {
            m.opt.constraint_mode = match c {
                "acceleration" => ConstraintMode::Acceleration,
                "velocity" => ConstraintMode::Velocity,
                _ => return Err(PyValueError::new_err(format!("constraint_mode must be 'acceleration' or 'velocity', got '{c}'"))),
            };
        }
        if let Some((kp, kd)) = pd_gains {
            if !(kp >= 0.0 && kd >= 0.0 && kp <= crate::math::MAX_STATE && kd <= crate::math::MAX_STATE) {
                return Err(PyValueError::new_err(format!("pd_gains must lie in [0, 1e10], got ({kp}, {kd})")));
            }
            m.opt.actuation = Actuation::Pd { kp, kd };
        }
        if !matches!(m.opt.actuation, Actuation::Motor) {
            let servos = if pd_gains.is_some() { "pd_gains" } else { "trajectory_gains" };
            if let Some(a) = (0..m.nu).find(|&a| m.actuator_joint(a).is_none() || m.actuator_gain[a] != [1.0, 0.0, 0.0] || m.actuator_bias[a] != [0.0; 3] || m.actuator_actadr[a].is_some()) {
                return Err(PyValueError::new_err(format!(
                    "{servos} drive motors on joints; actuator {a} ('{}') is not one",
                    m.actuator_name[a]
                )));
            }
        }
        if let Some(f) = friction {
            m.opt.friction = match f {
                // "seed" (the paper's model) is the old name, still accepted
                "one_tangent" | "seed" => FrictionModel::OneTangent,
                "pyramid" => FrictionModel::Pyramid,
                _ => return Err(PyValueError::new_err(format!("friction must be 'pyramid' or 'one_tangent', got '{f}'"))),
            };
        }
        Ok(self.sharing(m))
    }

    /// Number of position coordinates.
    #[getter]
    fn nq(&self) -> usize {
        self.inner.nq
    }
    /// Number of degrees of freedom.
    #[getter]
    fn nv(&self) -> usize {
        self.inner.nv
    }
    /// Number of actuators.
    #[getter]
    fn nu(&self) -> usize {
        self.inner.nu
    }
    /// Number of actuator activations (actuators with dynamics: `Sim.act`).
    #[getter]
    fn na(&self) -> usize {
        self.inner.na
    }
    /// Number of bodies including the world.
    #[getter]
    fn nbody(&self) -> usize {
        self.inner.nbody
    }
    /// Number of joints.
    #[getter]
    fn njnt(&self) -> usize {
        self.inner.njnt
    }
    /// Number of geoms.
    #[getter]
    fn ngeom(&self) -> usize {
        self.inner.ngeom
    }
    /// Time step (s).
    #[getter]
    fn timestep(&self) -> f64 {
        self.inner.opt.timestep
    }
    /// Integrator name: "Euler", "RK4", "leapfrog", or "implicitfast" (Euler with the actuators' damping implicit).
    #[getter]
    fn integrator(&self) -> &'static str {
        match self.inner.opt.integrator {
            Integrator::Euler if self.inner.opt.implicit_actuators => "implicitfast",
            i => integrator_name(i),
        }
    }
    /// Contact restitution coefficient e.
    #[getter]
    fn restitution(&self) -> f64 {
        self.inner.opt.restitution
    }
    /// Friction formulation: "pyramid" (±t₁, ±t₂) or "one_tangent" (the seed's, Kokkevis eqs. 19–21).
    #[getter]
    fn friction(&self) -> &'static str {
        friction_name(self.inner.opt.friction)
    }
    /// "acceleration" (the seed's impact solve when a contact rebounds, e > 0, then the force
    /// solve) or "velocity" (time stepping).
    #[getter]
    fn constraint_mode(&self) -> &'static str {
        match self.inner.opt.constraint_mode {
            ConstraintMode::Acceleration => "acceleration",
            ConstraintMode::Velocity => "velocity",
        }
    }
    /// PD gains (kp, kd) when actuators are position servos, else None (motors).
    #[getter]
    fn pd_gains(&self) -> Option<(f64, f64)> {
        match self.inner.opt.actuation {
            Actuation::Pd { kp, kd } => Some((kp, kd)),
            _ => None,
        }
    }
    /// Trajectory-following gains (kp, kd) when actuators are motion-control rows, else None.
    #[getter]
    fn trajectory_gains(&self) -> Option<(f64, f64)> {
        match self.inner.opt.actuation {
            Actuation::Trajectory { kp, kd } => Some((kp, kd)),
            _ => None,
        }
    }
    /// Whether contacts are simulated.
    #[getter]
    fn contact(&self) -> bool {
        self.inner.opt.contact
    }
    /// Whether joint limits are enforced.
    #[getter]
    fn limit(&self) -> bool {
        self.inner.opt.limit
    }
    /// Gravity vector.
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.opt.gravity.to_array())
    }
    /// Reference configuration (nq,).
    #[getter]
    fn qpos0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.qpos0)
    }
    /// Body masses (nbody,).
    #[getter]
    fn body_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.body_mass)
    }
    /// Body centres of mass in body frames (nbody, 3).
    #[getter]
    fn body_ipos<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.body_ipos.iter().map(|v| v.to_array()))
    }
    /// Rotational inertia about the centre of mass, body axes (nbody, 3, 3).
    #[getter]
    fn body_inertia_tensor<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        mats(py, &self.inner.body_inertia)
    }
    /// Body positions relative to their parents (nbody, 3).
    #[getter]
    fn body_pos<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.body_pos.iter().map(|v| v.to_array()))
    }
    /// Body orientations relative to their parents, (w, x, y, z) (nbody, 4).
    #[getter]
    fn body_quat<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.inner.body_quat.iter().map(|q| vec![q.w, q.x, q.y, q.z]).collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }
    /// Parent body indices (nbody,).
    #[getter]
    fn body_parent(&self) -> Vec<usize> {
        self.inner.body_parent.clone()
    }
    /// Body names.
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.inner.body_name.clone()
    }
    /// The mocap bodies (MuJoCo's `body_mocapid` order): each placed per world with
    /// `Batch.set_params("body_pos" / "body_quat", ...)`.
    #[getter]
    fn mocap_bodies(&self) -> Vec<usize> {
        (0..self.inner.nbody).filter(|&b| self.inner.body_mocap[b]).collect()
    }
    /// Joint names.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner.jnt_name.clone()
    }
    /// Joint types: "free", "ball", "slide" or "hinge".
    #[getter]
    fn joint_types(&self) -> Vec<&'static str> {
        self.inner
            .jnt_type
            .iter()
            .map(|t| match t {
                JointType::Free => "free",
                JointType::Ball => "ball",
                JointType::Slide => "slide",
                JointType::Hinge => "hinge",
            })
            .collect()
    }
    /// First qpos index of each joint.
    #[getter]
    fn jnt_qposadr(&self) -> Vec<usize> {
        self.inner.jnt_qposadr.clone()
    }
    /// First qvel index of each joint.
    #[getter]
    fn jnt_dofadr(&self) -> Vec<usize> {
        self.inner.jnt_dofadr.clone()
    }
    /// Joint limits (njnt, 2).
    #[getter]
    fn jnt_range<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        ranges(py, self.inner.jnt_range.iter().copied())
    }
    /// Each joint's total actuator force range (njnt, 2; MuJoCo's `actuatorfrcrange`): ±inf
    /// where it is not limited.
    #[getter]
    fn jnt_actfrcrange<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = &self.inner;
        let range = |j: usize| m.dof_actfrcrange.iter().find(|&&(d, _)| d == m.jnt_dofadr[j]).map_or([f64::NEG_INFINITY, f64::INFINITY], |&(_, r)| r);
        ranges(py, (0..m.njnt).map(range))
    }
    /// Whether each joint is limited.
    #[getter]
    fn jnt_limited(&self) -> Vec<bool> {
        self.inner.jnt_limited.clone()
    }
    /// Geom names.
    #[getter]
    fn geom_names(&self) -> Vec<String> {
        self.inner.geom_name.clone()
    }
    /// Site names.
    #[getter]
    fn site_names(&self) -> Vec<String> {
        self.inner.site_name.clone()
    }
    /// Names of the sensors sinew computes, in `sensordata`'s order.
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        self.inner.sensor_name.clone()
    }
    /// Each sensor's first entry in `Sim.sensordata`.
    #[getter]
    fn sensor_adr(&self) -> Vec<usize> {
        self.inner.sensor_adr.clone()
    }
    /// Each sensor's number of entries.
    #[getter]
    fn sensor_dim(&self) -> Vec<usize> {
        self.inner.sensor_kind.iter().map(|k| k.dim()).collect()
    }
    /// Length of `Sim.sensordata`.
    #[getter]
    fn nsensordata(&self) -> usize {
        self.inner.nsensordata
    }
    /// Number of tendons.
    #[getter]
    fn ntendon(&self) -> usize {
        self.inner.ntendon
    }
    /// Tendon names.
    #[getter]
    fn tendon_names(&self) -> Vec<String> {
        self.inner.tendon_name.clone()
    }
    /// Tendon length limits (ntendon, 2); NaN for an unlimited tendon.
    #[getter]
    fn tendon_range<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = &self.inner;
        ranges(py, (0..m.ntendon).map(|t| if m.tendon_limited[t] { m.tendon_range[t] } else { [f64::NAN; 2] }))
    }
    /// Actuator names.
    #[getter]
    fn actuator_names(&self) -> Vec<String> {
        self.inner.actuator_name.clone()
    }
    /// Actuator control ranges (nu, 2).
    #[getter]
    fn actuator_ctrlrange<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        ranges(py, self.inner.actuator_ctrlrange.iter().copied())
    }
    /// Actuator force ranges (nu, 2): ±inf where the force is not limited.
    #[getter]
    fn actuator_forcerange<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = &self.inner;
        ranges(py, m.actuator_forcerange.iter().zip(&m.actuator_forcelimited).map(|(&r, &lim)| if lim { r } else { [f64::NEG_INFINITY, f64::INFINITY] }))
    }
    /// Whether each actuator clamps its control.
    #[getter]
    fn actuator_ctrllimited(&self) -> Vec<bool> {
        self.inner.actuator_ctrllimited.clone()
    }
    /// Site positions in their bodies' frames (nsite, 3).
    #[getter]
    fn site_pos<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.site_pos.iter().map(|v| v.to_array()))
    }
    /// Body of each site.
    #[getter]
    fn site_body(&self) -> Vec<usize> {
        self.inner.site_body.clone()
    }
    /// Site orientations in their bodies' frames (nsite, 3, 3).
    #[getter]
    fn site_mat<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        mats(py, &self.inner.site_mat)
    }
    /// Site sizes (nsite, 3), as a geom's of the site's shape.
    #[getter]
    fn site_size<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.site_size.iter().copied())
    }
    /// The two geoms (lower index first) of each `<contact><pair>`, in the file's order (npair, 2):
    /// MuJoCo's `pair_geom1`, `pair_geom2`.
    #[getter]
    fn pair_geoms(&self) -> Vec<(usize, usize)> {
        self.inner.pair_geoms.clone()
    }
    /// Body of each geom.
    #[getter]
    fn geom_body(&self) -> Vec<usize> {
        self.inner.geom_body.clone()
    }
    /// Geom positions in their bodies' frames (ngeom, 3); a mesh geom's is its mesh's centre.
    #[getter]
    fn geom_pos<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.geom_pos.iter().map(|v| v.to_array()))
    }
    /// Geom orientations in their bodies' frames (ngeom, 3, 3).
    #[getter]
    fn geom_mat<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        mats(py, &self.inner.geom_mat)
    }
    /// Geom size parameters (ngeom, 3), MuJoCo's `geom_size`.
    #[getter]
    fn geom_size<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.geom_size.iter().copied())
    }
    /// Actuator gear ratios (nu,).
    #[getter]
    fn actuator_gear<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.actuator_gear)
    }
    /// Dof driven by each actuator, −1 for one on a tendon.
    #[getter]
    fn actuator_dofadr(&self) -> Vec<i64> {
        let m = &self.inner;
        (0..m.nu).map(|a| m.actuator_joint(a).map_or(-1, |j| m.jnt_dofadr[j] as i64)).collect()
    }
    /// Names of the keyframes (`<keyframe><key>`), in order.
    #[getter]
    fn key_names(&self) -> Vec<String> {
        self.inner.keys.iter().map(|k| k.name.clone()).collect()
    }
    /// Keyframe `key` (a name or an index) as a dict of time, qpos, qvel, ctrl, and the mocap
    /// bodies' mpos (nmocap, 3) and mquat (nmocap, 4).
    fn keyframe<'py>(&self, py: Python<'py>, key: Bound<'py, PyAny>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let k = &self.inner.keys[keyframe_index(&self.inner, &key)?];
        let d = pyo3::types::PyDict::new(py);
        d.set_item("time", k.time)?;
        d.set_item("qpos", PyArray1::from_slice(py, &k.qpos))?;
        d.set_item("qvel", PyArray1::from_slice(py, &k.qvel))?;
        d.set_item("ctrl", PyArray1::from_slice(py, &k.ctrl))?;
        d.set_item("mpos", PyArray1::from_slice(py, &k.mpos).reshape([k.mpos.len() / 3, 3])?)?;
        d.set_item("mquat", PyArray1::from_slice(py, &k.mquat).reshape([k.mquat.len() / 4, 4])?)?;
        Ok(d)
    }
    /// Model features accepted but not simulated.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// The model's size (MuJoCo's `stat.extent`, or `<statistic extent>`): the clipping planes are
    /// `znear`, `zfar` times it.
    #[getter]
    fn extent(&self) -> f64 {
        self.renderer().extent
    }

    /// Near and far clipping distances of every camera (m): depth images are z-buffer values
    /// between them.
    #[getter]
    fn clip(&self) -> (f64, f64) {
        let e = self.renderer().extent;
        (self.inner.vis.znear * e, self.inner.vis.zfar * e)
    }

    /// Camera names, in camera-id order (empty for unnamed cameras).
    #[getter]
    fn camera_names(&self) -> Vec<String> {
        self.inner.vis.cameras.iter().map(|c| c.name.clone()).collect()
    }

    /// Geom centres in world (ngeom, 3) at configuration `qpos`.
    fn geom_xpos<'py>(&self, py: Python<'py>, qpos: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = &self.inner;
        let q = super::arrays::checked_values(&qpos, "qpos", &[m.nq])?;
        let poses = crate::render::Poses::new(m, &q);
        let flat: Vec<f64> = (0..m.ngeom).flat_map(|g| poses.geom_xpos(m, g).to_array()).collect();
        PyArray1::from_vec(py, flat).reshape([m.ngeom, 3])
    }

    /// Pickles as its MJCF text and options (`sinew._pickle.model` rebuilds it).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<super::Reduced<'py>> {
        let o = &self.inner.opt;
        let d = pyo3::types::PyDict::new(py);
        d.set_item("timestep", o.timestep)?;
        d.set_item("integrator", integrator_name(o.integrator))?;
        d.set_item("gravity", o.gravity.to_array())?;
        d.set_item("restitution", o.restitution)?;
        d.set_item("contact", o.contact)?;
        d.set_item("limit", o.limit)?;
        d.set_item("friction", friction_name(o.friction))?;
        d.set_item("constraint_mode", match o.constraint_mode {
            ConstraintMode::Acceleration => "acceleration",
            ConstraintMode::Velocity => "velocity",
        })?;
        match o.actuation {
            Actuation::Motor => {}
            Actuation::Pd { kp, kd } => d.set_item("pd_gains", (kp, kd))?,
            Actuation::Trajectory { kp, kd } => d.set_item("trajectory_gains", (kp, kd))?,
        }
        let fields = pyo3::types::PyDict::new(py);
        for h in self.inner.hfields.iter() {
            fields.set_item(&h.name, numpy::PyArray1::from_vec(py, h.data.clone()).reshape([h.nrow, h.ncol])?)?;
        }
        let path = self.path.as_ref().map(|p| p.to_string_lossy().into_owned());
        let args = pyo3::types::PyTuple::new(
            py,
            [self.source.to_string().into_pyobject(py)?.into_any(), d.into_any(), path.into_pyobject(py)?.into_any(), fields.into_any()],
        )?;
        Ok((py.import("sinew._pickle")?.getattr("model")?, args))
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        format!(
            "Model('{}', nq={}, nv={}, nu={}, nbody={}, timestep={}, integrator={})",
            m.name,
            m.nq,
            m.nv,
            m.nu,
            m.nbody,
            m.opt.timestep,
            integrator_name(m.opt.integrator)
        )
    }
}

/// The index of height field `hfield` (a name or an index); a `ValueError` names those there are.
fn hfield_index(m: &Model, hfield: &Bound<'_, PyAny>) -> PyResult<usize> {
    let names: Vec<&str> = m.hfields.iter().map(|h| h.name.as_str()).collect();
    let found = if let Ok(i) = hfield.extract::<i64>() {
        usize::try_from(i).ok().filter(|&i| i < names.len())
    } else if let Ok(name) = hfield.extract::<String>() {
        names.iter().position(|n| *n == name)
    } else {
        None
    };
    found.ok_or_else(|| PyValueError::new_err(format!("unknown height field {hfield}; the model has {names:?}")))
}

/// The index of keyframe `key` (a name or an index); a `ValueError` names the keys there are.
pub fn keyframe_index(m: &Model, key: &Bound<'_, PyAny>) -> PyResult<usize> {
    let names: Vec<&str> = m.keys.iter().map(|k| k.name.as_str()).collect();
    let found = if let Ok(i) = key.extract::<i64>() {
        usize::try_from(i).ok().filter(|&i| i < m.keys.len())
    } else if let Ok(name) = key.extract::<String>() {
        names.iter().position(|n| *n == name)
    } else {
        None
    };
    found.ok_or_else(|| PyValueError::new_err(format!("no keyframe {key}: the model's keys are {names:?} (by name or index)")))
}
