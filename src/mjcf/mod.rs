//! Model description: the MJCF (MuJoCo XML) subset sinew reads, parsed into a [`ModelSpec`] with
//! defaults resolved, angles in radians and orientations as quaternions. `model::compile` turns the
//! spec into a [`crate::Model`].
//!
//! Supported: the elements and attributes used by gymnasium's MuJoCo model files (docs/mjcf.md).
//! What the renderer draws (geom colours, textures, materials, lights, cameras, `<visual>`) is kept
//! in [`VisualSpec`]; other visual-only elements (size, sensor, …) are accepted and ignored. MuJoCo's soft-constraint parameters (solref, solimp, …) are accepted
//! and ignored by design: sinew's constraints are exact. Anything else that would change the physics
//! and is not supported is an error, or a warning in [`ModelSpec::warnings`].

pub mod include;
mod lenient;
mod parse;
mod visual;

use glam::{DQuat, DVec3};

pub use parse::parse;
pub use visual::{Builtin, CameraSpec, LightSpec, MaterialSpec, TextureKind, TextureSpec, TrackMode, VisualSpec, DEFAULT_GEOM_RGBA, DEFAULT_SITE_RGBA};

/// Integration scheme for the constraint-free dynamics.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// Semi-implicit (symplectic) Euler with joint damping treated implicitly, as MuJoCo's `Euler`.
    Euler,
    /// Classical 4th-order Runge–Kutta, as MuJoCo's `RK4`.
    Rk4,
    /// Position Verlet (drift–kick–drift, sinew's own; no MJCF spelling): the step's forces,
    /// contacts and constraints are those of the midpoint configuration q + (h/2) q̇ at the step's
    /// initial velocity; then q̇ += h q̈ and q ← q_mid ⊕ (h/2) q̇. Exact under constant
    /// acceleration (free flight, sliding under friction), where Euler's positions lag by
    /// h² q̈ / 2 per step; second order for accelerations that depend on the configuration alone,
    /// first order (like Euler) through velocity-dependent terms such as a chain's Coriolis forces.
    Leapfrog,
}

/// Joint kinds (MuJoCo's `mjtJoint`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointType {
    /// 6 DOF: position + unit quaternion; qvel = world linear + body angular velocity.
    Free,
    /// 3 DOF: unit quaternion; qvel = body-frame angular velocity.
    Ball,
    /// 1 DOF translation along `axis`.
    Slide,
    /// 1 DOF rotation about `axis` through `pos`.
    Hinge,
}

impl JointType {
    /// Number of position coordinates.
    pub fn nq(self) -> usize {
        match self {
            JointType::Free => 7,
            JointType::Ball => 4,
            _ => 1,
        }
    }
    /// Number of velocity coordinates (degrees of freedom).
    pub fn nv(self) -> usize {
        match self {
            JointType::Free => 6,
            JointType::Ball => 3,
            _ => 1,
        }
    }
}

/// Geometric primitive kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeomType {
    /// Infinite plane, normal +z of its frame.
    Plane,
    /// Sphere of radius `size[0]`.
    Sphere,
    /// Capsule of radius `size[0]` and half-length `size[1]` along z.
    Capsule,
    /// Cylinder of radius `size[0]` and half-length `size[1]` along z.
    Cylinder,
    /// Box of half-sizes size[0..3].
    Box,
    /// Ellipsoid of semi-axes size[0..3].
    Ellipsoid,
    /// Convex hull of a mesh asset (`GeomSpec::mesh`); size: the half-sides of its inertia box.
    Mesh,
    /// Height field (`GeomSpec::hfield`); size: the field's x, y half-extents and height.
    Hfield,
}

/// Simulation options (`<option>`, `<compiler>`, `<flag>`).
#[derive(Clone, Debug, PartialEq)]
pub struct OptionSpec {
    /// Time step in seconds.
    pub timestep: f64,
    /// Gravity vector.
    pub gravity: DVec3,
    /// Integrator.
    pub integrator: Integrator,
    /// `implicit` or `implicitfast`: actuator damping implicit (the integrator is Euler's).
    pub implicit: bool,
    /// Contacts enabled (`<flag contact>`).
    pub contact: bool,
    /// Joint limits enabled (`<flag limit>`).
    pub limit: bool,
    /// Density of the medium, for fluid forces.
    pub density: f64,
    /// Viscosity of the medium, for fluid forces.
    pub viscosity: f64,
    /// Velocity of the medium.
    pub wind: DVec3,
    /// Most contacts a step keeps (`<size nconmax>`; None: sized from the model).
    pub nconmax: Option<usize>,
}

/// A `<contact><pair>`: two geoms that collide whatever contype, conaffinity, `<exclude>` and
/// their bodies' kinship say, with the pair's own friction, condim and margin.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSpec {
    /// The geoms' names.
    pub geoms: [String; 2],
    /// Friction: two sliding, torsional, two rolling (MuJoCo's defaults after those given).
    pub friction: [f64; 5],
    /// Contact dimensionality (1: frictionless).
    pub condim: u32,
    /// Distance within which the pair is in contact.
    pub margin: f64,
    /// Line of the element, for errors.
    pub line: u32,
}

/// A joint as written, with defaults applied and units converted.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// Name (may be empty).
    pub name: String,
    /// Kind.
    pub kind: JointType,
    /// Anchor in the body frame.
    pub pos: DVec3,
    /// Unit axis in the body frame (hinge, slide).
    pub axis: DVec3,
    /// Reference position (qpos0 for hinge/slide).
    pub reference: f64,
    /// Lower/upper limit.
    pub range: [f64; 2],
    /// Whether the range is enforced.
    pub limited: bool,
    /// Limit activation margin.
    pub margin: f64,
    /// Armature inertia added to each DOF.
    pub armature: f64,
    /// Viscous damping per DOF.
    pub damping: f64,
    /// Dry friction: the torque (force) that holds each dof at rest, exactly.
    pub frictionloss: f64,
    /// Spring stiffness.
    pub stiffness: f64,
    /// (time constant, damping ratio) that set stiffness and damping from the joint's inertia at
    /// qpos0, overriding both.
    pub springdamper: Option<[f64; 2]>,
    /// Spring rest position.
    pub springref: f64,
    /// The range the total actuator force on a hinge or slide joint is clamped to (MuJoCo's
    /// `actuatorfrcrange` when limited).
    pub actfrcrange: Option<[f64; 2]>,
    /// Source line.
    pub line: u32,
}

/// A geom as written, with defaults applied and `fromto` resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct GeomSpec {
    /// Name (may be empty).
    pub name: String,
    /// Kind.
    pub kind: GeomType,
    /// Size parameters (meaning depends on kind).
    pub size: [f64; 3],
    /// Position in the body frame.
    pub pos: DVec3,
    /// Orientation in the body frame.
    pub quat: DQuat,
    /// Density for mass-from-volume.
    pub density: f64,
    /// Explicit mass, overriding density.
    pub mass: Option<f64>,
    /// `shellinertia`: the mass on the surface (density per area), not through the volume.
    pub shell: bool,
    /// Sliding, torsional, rolling friction.
    pub friction: [f64; 3],
    /// Contact type bitmask.
    pub contype: u32,
    /// Contact affinity bitmask.
    pub conaffinity: u32,
    /// Contact dimensionality (1 = frictionless, 3 = sliding friction).
    pub condim: u32,
    /// Contact priority: the higher geom of a pair sets its condim and friction (MuJoCo's rule).
    pub priority: i32,
    /// Contact detection margin.
    pub margin: f64,
    /// Colour (MuJoCo's default [`DEFAULT_GEOM_RGBA`] unless given).
    pub rgba: [f64; 4],
    /// Material name.
    pub material: Option<String>,
    /// Mesh asset name (a mesh geom's shape).
    pub mesh: Option<String>,
    /// Height-field asset name (a height-field geom's shape).
    pub hfield: Option<String>,
    /// Visibility group (MuJoCo's viewer draws groups 0–2 by default).
    pub group: i32,
    /// `fluidshape="ellipsoid"`: the geom moves through the medium as its ellipsoid, with these
    /// `fluidcoef` (blunt drag, slender drag, angular drag, Kutta lift, Magnus lift).
    pub fluid: Option<[f64; 5]>,
    /// Source line.
    pub line: u32,
}

/// A `<mesh>` asset: its vertices from a file or inline, and how they are placed.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshSpec {
    /// Name (the file's stem unless given).
    pub name: String,
    /// File, relative to `meshdir` (else `assetdir`, else the model file's directory).
    pub file: Option<String>,
    /// Inline vertices (x y z …), rounded to single precision as MuJoCo stores them.
    pub vertex: Vec<[f32; 3]>,
    /// Inline triangles.
    pub face: Vec<[u32; 3]>,
    /// Scale, reference frame and mass distribution.
    pub placement: crate::geometry::MeshPlacement,
    /// Source line.
    pub line: u32,
}

/// An `<hfield>` asset.
#[derive(Clone, Debug, PartialEq)]
pub struct HFieldSpec {
    /// Name (the file's stem unless given).
    pub name: String,
    /// PNG or binary grid file, found as mesh files are.
    pub file: Option<String>,
    /// Rows and columns (with `elevation`, or zeros).
    pub nrow: usize,
    /// Columns.
    pub ncol: usize,
    /// x, y half-extents, height of elevation 1, base depth.
    pub size: [f64; 4],
    /// Inline elevations (nrow × ncol), or empty.
    pub elevation: Vec<f64>,
    /// Source line.
    pub line: u32,
}

/// A site: a named frame on a body with no physics.
#[derive(Clone, Debug, PartialEq)]
pub struct SiteSpec {
    /// Name (may be empty).
    pub name: String,
    /// Position in the body frame.
    pub pos: DVec3,
    /// Orientation in the body frame.
    pub quat: DQuat,
    /// Shape (a touch sensor's zone).
    pub kind: GeomType,
    /// Size parameters, as a geom's of that shape.
    pub size: [f64; 3],
    /// Colour (MuJoCo's default [`DEFAULT_SITE_RGBA`] unless given).
    pub rgba: [f64; 4],
    /// Material name.
    pub material: Option<String>,
    /// Visual group (MuJoCo draws groups 0–2).
    pub group: i32,
    /// Line in the file.
    pub line: u32,
}

/// Explicit `<inertial>`.
#[derive(Clone, Debug, PartialEq)]
pub struct InertialSpec {
    /// Mass.
    pub mass: f64,
    /// Centre of mass in the body frame.
    pub pos: DVec3,
    /// Orientation of the principal axes.
    pub quat: DQuat,
    /// Principal moments, or the full tensor (xx, yy, zz, xy, xz, yz) in the inertial frame.
    pub inertia: [f64; 6],
}

/// A body with its joints, geoms and sites. Body 0 is the world.
#[derive(Clone, Debug, PartialEq)]
pub struct BodySpec {
    /// Name.
    pub name: String,
    /// Parent body index (0 for children of the world; the world is its own parent).
    pub parent: usize,
    /// Position relative to the parent.
    pub pos: DVec3,
    /// Orientation relative to the parent.
    pub quat: DQuat,
    /// Joints in order.
    pub joints: Vec<JointSpec>,
    /// Geoms in order.
    pub geoms: Vec<GeomSpec>,
    /// Sites in order.
    pub sites: Vec<SiteSpec>,
    /// Explicit inertial, if given.
    pub inertial: Option<InertialSpec>,
    /// Cameras in order.
    pub cameras: Vec<CameraSpec>,
    /// Lights in order.
    pub lights: Vec<LightSpec>,
    /// A mocap body (MuJoCo's `mocap="true"`): a child of the world without joints, placed per
    /// world at run time.
    pub mocap: bool,
    /// Gravity compensation (MuJoCo's `gravcomp`): this fraction of the body's weight is held up
    /// by a force at its centre of mass.
    pub gravcomp: f64,
    /// Source line.
    pub line: u32,
}

impl BodySpec {
    /// The world body (index 0, its own parent), declared at `line`.
    pub fn world(line: u32) -> BodySpec {
        BodySpec {
            name: "world".into(),
            parent: 0,
            pos: DVec3::ZERO,
            quat: DQuat::IDENTITY,
            joints: vec![],
            geoms: vec![],
            sites: vec![],
            inertial: None,
            cameras: vec![],
            lights: vec![],
            mocap: false,
            gravcomp: 0.0,
            line,
        }
    }
}

/// What an actuator pulls on.
#[derive(Clone, Debug, PartialEq)]
pub enum TransmissionSpec {
    /// A hinge or slide joint, by name.
    Joint(String),
    /// A fixed tendon, by name.
    Tendon(String),
}

/// An actuator (`<motor>`, `<position>`, `<velocity>` or `<general>`), as MuJoCo's general one:
/// force = gain · ctrl + bias₀ + bias₁ · length + bias₂ · velocity of its transmission (times
/// gear), applied through the transmission times gear.
#[derive(Clone, Debug, PartialEq)]
pub struct ActuatorSpec {
    /// Element (`motor`, `position`, `velocity`, `general`, …).
    pub kind: String,
    /// Name (may be empty).
    pub name: String,
    /// The joint or tendon it drives.
    pub target: TransmissionSpec,
    /// Gear ratio.
    pub gear: f64,
    /// Control range.
    pub ctrlrange: [f64; 2],
    /// Whether ctrl is clamped to `ctrlrange`.
    pub ctrllimited: bool,
    /// Actuator force range.
    pub forcerange: [f64; 2],
    /// Whether the force is clamped to `forcerange`.
    pub forcelimited: bool,
    /// Affine gain g₀ + g₁ · length + g₂ · velocity (MuJoCo's `gainprm[0..3]`; fixed: g₀ alone).
    pub gain: [f64; 3],
    /// Affine bias (MuJoCo's `biasprm[0..3]`; zero for none).
    pub bias: [f64; 3],
    /// Activation dynamics.
    pub dynamics: ActuatorDyn,
    /// Activation range, when limited.
    pub actrange: Option<[f64; 2]>,
    /// A muscle's force parameters (its gain and bias are then MuJoCo's muscle curves).
    pub muscle: Option<MuscleSpec>,
    /// MuJoCo's `inheritrange` (0: none): the servo's range is its target's, scaled about its
    /// middle by this.
    pub inheritrange: f64,
    /// Source line.
    pub line: u32,
}

/// An actuator's activation dynamics (MuJoCo's `dyntype`): with an activation `act`, the force
/// is gain · act + bias instead of gain · ctrl + bias.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActuatorDyn {
    /// No activation: the force reads ctrl.
    None,
    /// act˙ = ctrl.
    Integrator,
    /// act˙ = (ctrl − act) / τ, integrated as the model's integrator does.
    Filter(f64),
    /// The same filter, integrated exactly over each step: act += (ctrl − act)(1 − e^(−h/τ)).
    FilterExact(f64),
    /// A muscle's activation (MuJoCo's `mju_muscleDynamics`): act˙ = (ctrl − act)/τ, τ the
    /// activation time constant (τ_act (0.5 + 1.5 act)) while ctrl exceeds act, the deactivation one
    /// (τ_deact / (0.5 + 1.5 act)) otherwise, blended over a width when smoothed:
    /// [τ_act, τ_deact, width].
    Muscle([f64; 3]),
}

/// A muscle's force parameters (MuJoCo's `gainprm` = `biasprm` of a muscle: range[0..2], force,
/// scale, lmin, lmax, vmax, fpmax, fvmax) and the actuator length range they are read over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MuscleSpec {
    /// The nine parameters.
    pub prm: [f64; 9],
    /// `lengthrange`, when given.
    pub lengthrange: Option<[f64; 2]>,
}

/// A `<joint>` or `<tendon>` equality: x₁ − x₁⁰ = Σₖ polycoef\[k\] (x₂ − x₂⁰)ᵏ, x a joint's
/// position or a fixed tendon's length and x⁰ its value at qpos0 (x₁ − x₁⁰ = polycoef\[0\] without
/// a second object).
#[derive(Clone, Debug, PartialEq)]
pub struct EqualitySpec {
    /// Name (may be empty).
    pub name: String,
    /// Joints (false) or tendons (true).
    pub tendon: bool,
    /// The constrained object.
    pub obj1: String,
    /// The object it follows, if any.
    pub obj2: Option<String>,
    /// Polynomial coefficients (degree 4 at most).
    pub polycoef: [f64; 5],
    /// Whether the constraint starts active.
    pub active: bool,
    /// Its place among the file's equalities of every kind (MuJoCo's equality order).
    pub order: usize,
    /// Source line.
    pub line: u32,
}

/// A `<connect>` equality: the point `anchor` of body1 (its frame) held at the point of body2
/// (the world when absent) it coincides with at qpos0.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectSpec {
    /// Name (may be empty).
    pub name: String,
    /// The first body.
    pub body1: String,
    /// The second body, or the world.
    pub body2: Option<String>,
    /// The point in body1's frame.
    pub anchor: DVec3,
    /// A weld: the bodies' relative rotation at qpos0 is held too.
    pub weld: bool,
    /// Whether the constraint starts active.
    pub active: bool,
    /// Its place among the file's equalities of every kind (MuJoCo's equality order).
    pub order: usize,
    /// Source line.
    pub line: u32,
}

/// A `<sensor>` child as written: its kind (the element's name), name and object attributes.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorSpec {
    /// The element's name (`jointpos`, `touch`, …).
    pub kind: String,
    /// Name (may be empty).
    pub name: String,
    /// The attributes naming its objects (`joint`, `site`, `objtype`, `objname`, …).
    pub attrs: Vec<(String, String)>,
    /// Source line.
    pub line: u32,
}

/// A `<key>` of `<keyframe>`: a named state (absent arrays are qpos0 and zeros).
#[derive(Clone, Debug, PartialEq)]
pub struct KeySpec {
    /// Name (may be empty).
    pub name: String,
    /// Time.
    pub time: f64,
    /// Positions (nq), if given.
    pub qpos: Option<Vec<f64>>,
    /// Velocities (nv), if given.
    pub qvel: Option<Vec<f64>>,
    /// Controls (nu), if given.
    pub ctrl: Option<Vec<f64>>,
    /// Activations (na), if given.
    pub act: Option<Vec<f64>>,
    /// Mocap bodies' positions (3 each), if given.
    pub mpos: Option<Vec<f64>>,
    /// Mocap bodies' orientations (4 each, w x y z), if given.
    pub mquat: Option<Vec<f64>>,
    /// Source line.
    pub line: u32,
}

/// A tendon: fixed (length Σ coef · q over hinge and slide joints) or spatial (a path through
/// sites, around wrapping geoms, split by pulleys), with a spring, a damper, limits and dry friction.
#[derive(Clone, Debug, PartialEq)]
pub struct TendonSpec {
    /// Name (may be empty).
    pub name: String,
    /// What its length is.
    pub path: TendonPathSpec,
    /// Spring stiffness.
    pub stiffness: f64,
    /// Damping.
    pub damping: f64,
    /// The spring's rest length, or deadband [low, high]; None: the length at qpos0.
    pub springlength: Option<[f64; 2]>,
    /// Length limits [low, high] when limited.
    pub range: Option<[f64; 2]>,
    /// Distance from a limit within which its row is built.
    pub margin: f64,
    /// Dry friction: the largest force its friction rows exert.
    pub frictionloss: f64,
    /// Source line.
    pub line: u32,
}

/// A tendon's length.
#[derive(Clone, Debug, PartialEq)]
pub enum TendonPathSpec {
    /// (joint name, coefficient) of each term.
    Fixed(Vec<(String, f64)>),
    /// The path's elements in order, each with its source line.
    Spatial(Vec<(PathSpec, u32)>),
}

/// One element of a spatial tendon's path.
#[derive(Clone, Debug, PartialEq)]
pub enum PathSpec {
    /// A site, by name.
    Site(String),
    /// A sphere or cylinder the path wraps around, with the optional site that picks the side.
    Geom {
        /// Geom name.
        geom: String,
        /// Side site name.
        sidesite: Option<String>,
    },
    /// A pulley: the branches after it count length / divisor.
    Pulley(f64),
}

/// How body inertias are obtained (`<compiler inertiafromgeom>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InertiaFromGeom {
    /// Always from geoms.
    True,
    /// Never from geoms.
    False,
    /// From geoms when a body has no `<inertial>`.
    Auto,
}

/// A whole parsed model description.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSpec {
    /// Model name.
    pub name: String,
    /// Options.
    pub option: OptionSpec,
    /// Bodies in document order; index 0 is the world.
    pub bodies: Vec<BodySpec>,
    /// Actuators in document order.
    pub actuators: Vec<ActuatorSpec>,
    /// Fixed tendons.
    pub tendons: Vec<TendonSpec>,
    /// Joint and tendon equality constraints.
    pub equalities: Vec<EqualitySpec>,
    /// Keyframes.
    pub keys: Vec<KeySpec>,
    /// `<sensor>`s, in order.
    pub sensors: Vec<SensorSpec>,
    /// Connect equalities.
    pub connects: Vec<ConnectSpec>,
    /// `<compiler inertiafromgeom>`.
    pub inertiafromgeom: InertiaFromGeom,
    /// `<compiler inertiagrouprange>`: the geom groups whose geoms give a body's inertia.
    pub inertiagroups: [i32; 2],
    /// `<compiler settotalmass>`, when positive.
    pub settotalmass: Option<f64>,
    /// `<compiler boundmass boundinertia>`: the least mass and principal moment of a body.
    pub bounds: [f64; 2],
    /// Body-name pairs excluded from contact (`<contact><exclude>`).
    pub contact_excludes: Vec<(String, String)>,
    /// Geom pairs that collide whatever their filters say, with their own friction (`<contact><pair>`).
    pub contact_pairs: Vec<PairSpec>,
    /// Contact restitution from `<custom><numeric name="sinew/restitution">`.
    pub restitution: Option<f64>,
    /// Textures, materials, `<visual>` and `<statistic>`.
    pub visual: VisualSpec,
    /// Mesh assets.
    pub meshes: Vec<MeshSpec>,
    /// Height-field assets.
    pub hfields: Vec<HFieldSpec>,
    /// `<compiler meshdir>`, else `assetdir`: where mesh files are found.
    pub meshdir: Option<String>,
    /// Things accepted but not modelled that may change the physics.
    pub warnings: Vec<String>,
}

/// The text of a model file (MJCF or URDF), with the XML only MuJoCo's parser accepts mended
/// ([`lenient::mend`]): an `Io` error when it cannot be read, an `Xml` error naming the line
/// when it is not UTF-8.
pub fn read_file(path: &std::path::Path) -> crate::error::Result<String> {
    let bytes = std::fs::read(path).map_err(|e| crate::error::Error::io(format!("cannot read model file '{}'", path.display()), &e))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() as u32;
        crate::error::Error::Xml { line, message: format!("'{}' is not UTF-8 text (invalid byte at offset {at})", path.display()) }
    })?;
    Ok(match lenient::mend(&text) {
        std::borrow::Cow::Owned(mended) => mended,
        std::borrow::Cow::Borrowed(_) => text,
    })
}
