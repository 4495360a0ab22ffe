//! The compiled model: immutable, flat arrays, every index resolved. Shared by all worlds.
//!
//! Arrays follow MuJoCo's `<object>_<field>` naming. Joints, dofs and qpos/qvel addresses are in
//! MuJoCo's order. The dynamics tree has one *node* per body with joints (a body whose joints
//! exceed six dofs together gets one per group of consecutive joints that fit): its frame is the
//! body frame, its joints act in order as MuJoCo's do (hinge/slide coordinates relative to `ref`,
//! rotations about the anchor `pos`, (w, x, y, z) quaternions for ball and free joints, free-joint
//! qvel = world linear velocity then body-frame angular velocity), and a body without joints is
//! welded to its parent's node with a fixed offset.

mod pairs;
pub mod sensor;
pub mod visual;

use glam::{DMat3, DQuat, DVec3};

pub use crate::mjcf::{ActuatorDyn, GeomType, Integrator, JointType};
pub use pairs::{geom_tree, same_tree, GapPair, GeomPair, PairFriction, PairTest, PlaneGroup, PAIR_BITS_GEOMS};
pub use sensor::{ContactObject, ContactSensor, SensorFrame, SensorKind};
use crate::math::{SpatialInertia, Xform};

/// Parent index of nodes attached to the world.
pub const WORLD: usize = usize::MAX;

/// How friction is posed in the LCP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionModel {
    /// The seed's three conditions per contact (Kokkevis 2004, eqs. 19–21): one tangent, opposite
    /// the step's constraint-free slip, else the last valid or a random one.
    OneTangent,
    /// Six conditions per contact: ±t₁, ±t₂ and one λ (a four-sided friction pyramid). The
    /// default: it resists a push across its first tangent, which one tangent cannot, for some
    /// more time per step (`results/friction_models.md`).
    Pyramid,
}

/// How constraints enter the step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstraintMode {
    /// The seed's scheme: an impact solve when something approaches, then constraint forces at the
    /// acceleration level (Kokkevis 2004, §8.1).
    Acceleration,
    /// Time stepping at the velocity level (Stewart & Trinkle 1996; Anitescu & Potra 1997): one
    /// impulse solve per step with the same K, Δq̇ = Σ p_k Δq̈⁽ᵏ⁾. Always solvable where the
    /// acceleration-level problem is not (Painlevé).
    Velocity,
}

/// What an actuator's control means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Actuation {
    /// MuJoCo's motor: force = gear · ctrl (ctrl clamped to ctrlrange).
    Motor,
    /// PD servo to the position target ctrl (rad or m) on the actuated joint, evaluated every
    /// step: force = gear · clamp(kp (ctrl − q) − kd q̇, ctrlrange), so the motor's own limit bounds it.
    Pd {
        /// Proportional gain, control units per rad (or per m).
        kp: f64,
        /// Derivative gain, control units per rad/s (or per m/s).
        kd: f64,
    },
    /// Trajectory following by motion-control rows (Kokkevis 2004, §8.3): ctrl is each actuated
    /// joint's position target; the LCP finds the joint torque that gives the acceleration
    /// q̈_ref + kd (q̇_ref − q̇) + kp (ctrl − q), together with contacts and limits, bounded by
    /// gear · max|ctrlrange| when the actuator is ctrllimited.
    Trajectory {
        /// Position gain (1/s²).
        kp: f64,
        /// Velocity gain (1/s).
        kd: f64,
    },
}

/// What an actuator drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transmission {
    /// A hinge or slide joint.
    Joint(usize),
    /// A fixed tendon.
    Tendon(usize),
}

/// A `<connect>` equality: a point of body1 held at a point of body2.
#[derive(Clone, Debug, PartialEq)]
pub struct Connect {
    /// Name (may be empty).
    pub name: String,
    /// The bodies (body2 may be the world, 0).
    pub body: [usize; 2],
    /// Each side's point in its body's frame (body2's: where body1's anchor is at qpos0).
    pub anchor: [DVec3; 2],
    /// A weld's relative rotation R₂ᵀR₁ at qpos0, held too; None for a connect.
    pub rel: Option<glam::DQuat>,
    /// Whether it is active.
    pub active: bool,
}

/// A geom's constants in MuJoCo's ellipsoid fluid model (its `geom_fluid`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomFluid {
    /// Blunt drag, slender drag, angular drag, Kutta lift and Magnus lift coefficients.
    pub coef: [f64; 5],
    /// The equivalent ellipsoid's semi-axes, along the geom's axes.
    pub semiaxes: DVec3,
    /// Volume of fluid carried along per unit density, along each axis.
    pub virtual_mass: DVec3,
    /// Moment of inertia of the fluid carried along per unit density, about each axis.
    pub virtual_inertia: DVec3,
}

/// A muscle actuator's force constants (MuJoCo's `gainprm`/`biasprm`, `actuator_lengthrange` and
/// `actuator_acc0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Muscle {
    /// range[0..2], force, scale, lmin, lmax, vmax, fpmax, fvmax.
    pub prm: [f64; 9],
    /// The actuator lengths the range maps to.
    pub lengthrange: [f64; 2],
    /// ‖M⁻¹ moment‖ at qpos0: the peak force is scale / acc0 when force is negative.
    pub acc0: f64,
}

/// One of the model's equalities ([`Model::eq_order`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EqRef {
    /// A joint or tendon coupling (its index below [`Model::neq`]).
    Coupling(usize),
    /// A connect or weld (its index in [`Model::connects`]).
    Connect(usize),
}

/// A named state of the model (MuJoCo's `<key>`).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    /// Name (may be empty).
    pub name: String,
    /// Time.
    pub time: f64,
    /// Positions (nq).
    pub qpos: Vec<f64>,
    /// Velocities (nv).
    pub qvel: Vec<f64>,
    /// Controls (nu).
    pub ctrl: Vec<f64>,
    /// Activations (na).
    pub act: Vec<f64>,
    /// Mocap bodies' positions (3 each, [`Model::body_mocap`] order).
    pub mpos: Vec<f64>,
    /// Mocap bodies' orientations (4 each, w x y z).
    pub mquat: Vec<f64>,
}

/// One term of a linear length: coef · qpos\[qpos\] along dof `dof` (a hinge's or slide's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wrap {
    /// The joint's dof.
    pub dof: usize,
    /// The joint's qpos address.
    pub qpos: usize,
    /// Coefficient.
    pub coef: f64,
}

impl Wrap {
    /// The length Σ coef · x\[qpos\] of `terms` at positions `x`.
    pub fn length(terms: &[Wrap], x: &[f64]) -> f64 {
        terms.iter().map(|w| w.coef * x[w.qpos]).sum()
    }

    /// Its rate Σ coef · qvel\[dof\].
    pub fn rate(terms: &[Wrap], qvel: &[f64]) -> f64 {
        terms.iter().map(|w| w.coef * qvel[w.dof]).sum()
    }
}

/// One element of a spatial tendon's path (MuJoCo's wrap objects).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathPoint {
    /// A site the path passes through.
    Site(usize),
    /// A sphere or cylinder geom the path wraps around where the straight line between the sites
    /// either side of it would cross it, on the side of site `side` when given.
    Geom {
        /// The geom.
        geom: usize,
        /// The side site.
        side: Option<usize>,
    },
    /// A pulley: the path's branches after it count their length divided by `divisor`.
    Pulley(f64),
}

/// Simulation options.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Time step (s).
    pub timestep: f64,
    /// Gravity (m/s²).
    pub gravity: DVec3,
    /// Integrator.
    pub integrator: Integrator,
    /// Contacts enabled.
    pub contact: bool,
    /// Joint limits enabled.
    pub limit: bool,
    /// Contact restitution coefficient e in [0, 1].
    pub restitution: f64,
    /// Friction formulation.
    pub friction: FrictionModel,
    /// Meaning of ctrl.
    pub actuation: Actuation,
    /// Acceleration-level (seed) or velocity-level constraint handling.
    pub constraint_mode: ConstraintMode,
    /// Density of the medium (kg/m³), for fluid forces.
    pub density: f64,
    /// Viscosity of the medium (Pa s), for fluid forces.
    pub viscosity: f64,
    /// Velocity of the medium (m/s).
    pub wind: DVec3,
    /// Most contacts a step keeps; beyond it, the deepest ([`default_max_contacts`]).
    pub max_contacts: usize,
    /// MuJoCo's `implicitfast` (and `implicit`): the actuators' velocity feedback on a joint is
    /// treated implicitly with its damping ([`Model::dof_actdamping`]).
    pub implicit_actuators: bool,
    /// Whether a step holds a joint stuck by its dry friction still, with no rows
    /// (`constraint::dry_friction`); off, its rows are posed. The answers agree.
    pub hold_stuck_joints: bool,
}

/// Contacts a step keeps unless `<size nconmax>` says otherwise: four per geom (a box on a floor
/// touches it at its corners), at least 128 and at most 1024 (K is dense over a step's rows:
/// 1024 contacts with pyramid friction are 5120 rows, 210 MB).
pub fn default_max_contacts(ngeom: usize) -> usize {
    (4 * ngeom).clamp(128, 1024)
}

impl Model {
    /// The joint actuator `a` drives, when it drives one.
    pub fn actuator_joint(&self, a: usize) -> Option<usize> {
        match self.actuator_trn[a] {
            Transmission::Joint(j) => Some(j),
            Transmission::Tendon(_) => None,
        }
    }

    /// Actuator `a`'s moment arms.
    pub fn moment(&self, a: usize) -> &[Wrap] {
        &self.actuator_moment[self.actuator_moment_adr[a]..self.actuator_moment_adr[a + 1]]
    }

    /// The terms of side `side` (0: the constrained object, 1: the one it follows) of equality `e`.
    pub fn eq_side(&self, e: usize, side: usize) -> &[Wrap] {
        &self.eq_wrap[self.eq_adr[2 * e + side]..self.eq_adr[2 * e + side + 1]]
    }

    /// Fixed tendon `t`'s terms (empty for a spatial tendon).
    pub fn tendon_terms(&self, t: usize) -> &[Wrap] {
        &self.tendon_wrap[self.tendon_adr[t]..self.tendon_adr[t + 1]]
    }

    /// Spatial tendon `t`'s path (empty for a fixed tendon).
    pub fn tendon_path(&self, t: usize) -> &[PathPoint] {
        &self.tendon_path[self.tendon_path_adr[t]..self.tendon_path_adr[t + 1]]
    }

    /// Whether [`Model::dof_arm`] bounds the geoms' motion at `qpos`: every limited slide within
    /// the travel the arms allow for (a gripper's fingers within their range).
    pub fn arms_hold(&self, qpos: &[f64]) -> bool {
        self.arm_slides.iter().all(|&(qa, most)| (qpos[qa] - self.qpos0[qa]).abs() <= most)
    }

    /// Limited tendons (with limits enabled).
    pub fn limited_tendons(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.ntendon).filter(|&t| self.opt.limit && self.tendon_limited[t])
    }
}

impl Default for Options {
    /// MuJoCo's defaults (`mj_defaultOption`) and sinew's: pyramid friction, motors,
    /// acceleration-level constraints, no restitution.
    fn default() -> Self {
        Options {
            timestep: 0.002,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            integrator: Integrator::Euler,
            contact: true,
            limit: true,
            restitution: 0.0,
            friction: FrictionModel::Pyramid,
            actuation: Actuation::Motor,
            constraint_mode: ConstraintMode::Acceleration,
            density: 0.0,
            viscosity: 0.0,
            wind: DVec3::ZERO,
            max_contacts: default_max_contacts(0),
            implicit_actuators: false,
            hold_stuck_joints: true,
        }
    }
}

impl Options {
    /// How far the step's final velocity carries a position from the configuration the step's
    /// dynamics and constraints are evaluated at: h (semi-implicit Euler; RK4 when constrained),
    /// h/2 (leapfrog, evaluated at the midpoint). Every end-of-step prediction (speculative
    /// contacts, limits within reach, the velocity that closes a gap) uses it.
    pub fn lever(&self) -> f64 {
        match self.integrator {
            Integrator::Leapfrog => 0.5 * self.timestep,
            Integrator::Euler | Integrator::Rk4 => self.timestep,
        }
    }
}

/// A compiled model. Build it with [`Model::from_mjcf`].
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// Options.
    pub opt: Options,
    /// Number of position coordinates.
    pub nq: usize,
    /// Number of degrees of freedom.
    pub nv: usize,
    /// Number of actuators.
    pub nu: usize,
    /// Number of bodies, world included.
    pub nbody: usize,
    /// Number of joints.
    pub njnt: usize,
    /// Number of dynamics nodes: a node is one joint, or several consecutive non-free joints of
    /// one body (≤ 6 dofs together) treated as one multi-dof joint.
    pub nnode: usize,
    /// Number of geoms.
    pub ngeom: usize,
    /// Reference configuration (nq).
    pub qpos0: Vec<f64>,
    /// Spring rest configuration (nq).
    pub qpos_spring: Vec<f64>,

    /// Body names (nbody).
    pub body_name: Vec<String>,
    /// Parent body (nbody), of a lower index; the world is its own parent.
    pub body_parent: Vec<usize>,
    /// Whether the body is a mocap body (nbody): fixed to the world, placed per world at run time
    /// through `body_pos` and `body_quat`.
    pub body_mocap: Vec<bool>,
    /// The bodies whose weight is compensated, with the fraction (MuJoCo's `gravcomp`: a force of
    /// −fraction · mass · gravity at the centre of mass, a passive force).
    pub body_gravcomp: Vec<(usize, f64)>,
    /// Position relative to the parent body (nbody).
    pub body_pos: Vec<DVec3>,
    /// Orientation relative to the parent body (nbody).
    pub body_quat: Vec<DQuat>,
    /// Mass (nbody).
    pub body_mass: Vec<f64>,
    /// Centre of mass in the body frame (nbody).
    pub body_ipos: Vec<DVec3>,
    /// Rotational inertia about the centre of mass, body axes (nbody).
    pub body_inertia: Vec<DMat3>,
    /// Principal axes of the rotational inertia, as columns in body axes (nbody).
    pub body_iaxes: Vec<DMat3>,
    /// Sides of the box with the body's principal moments of inertia, along `body_iaxes` (nbody):
    /// what the fluid sees.
    pub body_fluid_box: Vec<DVec3>,
    /// Whether a geom of the body has `fluidshape="ellipsoid"`: the body then meets the medium
    /// through those geoms' ellipsoids, not its inertia box (nbody).
    pub body_fluid_ellipsoid: Vec<bool>,
    /// Node whose frame the body moves with, or [`WORLD`] (nbody).
    pub body_node: Vec<usize>,
    /// Body frame relative to its node frame (nbody).
    pub body_offset: Vec<Xform>,

    /// Joint names (njnt).
    pub jnt_name: Vec<String>,
    /// Joint type (njnt).
    pub jnt_type: Vec<JointType>,
    /// Body the joint moves (njnt).
    pub jnt_body: Vec<usize>,
    /// First qpos address (njnt).
    pub jnt_qposadr: Vec<usize>,
    /// First qvel address (njnt).
    pub jnt_dofadr: Vec<usize>,
    /// Anchor in the joint's predecessor frame (njnt).
    pub jnt_pos: Vec<DVec3>,
    /// Unit axis (njnt).
    pub jnt_axis: Vec<DVec3>,
    /// Limits (njnt).
    pub jnt_range: Vec<[f64; 2]>,
    /// Whether limits apply (njnt).
    pub jnt_limited: Vec<bool>,
    /// Limit activation margin (njnt).
    pub jnt_margin: Vec<f64>,
    /// Spring stiffness (njnt).
    pub jnt_stiffness: Vec<f64>,

    /// Viscous damping (nv).
    pub dof_damping: Vec<f64>,
    /// The actuators' velocity feedback on each dof, −∂τ/∂q̇ = −bias₂ gear² of the actuators on its
    /// joint (nv; zero unless [`Options::implicit_actuators`]): damping the step treats implicitly.
    pub dof_actdamping: Vec<f64>,
    /// Armature inertia (nv).
    pub dof_armature: Vec<f64>,
    /// Dry friction per dof: the largest force its friction rows exert (nv).
    pub dof_frictionloss: Vec<f64>,
    /// Joint of each dof (nv).
    pub dof_jnt: Vec<usize>,
    /// Bound on the speed a unit velocity of the dof gives any point of a geom it moves: 1 for a
    /// translational dof; for a rotational one, the greatest distance such a point can have from
    /// the joint's anchor, or ∞ when an unlimited slide joint beyond the dof makes it unbounded
    /// (nv). A limited slide beyond it counts by its range ([`Model::arm_slides`]), so the bound
    /// holds where [`Model::arms_hold`]. A point then moves at most Σ_k `dof_arm[k]` |q̇_k|.
    pub dof_arm: Vec<f64>,
    /// The limited slide joints, as `dof_arm` counts them: (qpos address, the most |q − qpos0|
    /// the arms allow for: the range's farther end from qpos0, and a hundredth of the range).
    pub arm_slides: Vec<(usize, f64)>,

    /// Parent node or [`WORLD`] (nnode).
    pub node_parent: Vec<usize>,
    /// First joint of the node (nnode); its joints are consecutive.
    pub node_jntadr: Vec<usize>,
    /// Number of joints in the node (nnode).
    pub node_jntnum: Vec<usize>,
    /// Node of each joint (njnt).
    pub jnt_node: Vec<usize>,
    /// First dof of the node (nnode); its dofs are consecutive.
    pub node_dofadr: Vec<usize>,
    /// Number of dofs of the node (nnode).
    pub node_nv: Vec<usize>,
    /// ^{pred}X_{parent}: parent node frame to the frame its first joint moves from (nnode).
    pub node_xtree: Vec<Xform>,
    /// Rigid inertia carried by the node frame (its body plus welded descendants) (nnode).
    pub node_inertia: Vec<SpatialInertia>,
    /// Root node of each node's tree (nnode): the node whose parent is the world. Trees share no
    /// joint, so a force on one moves no other (their rows' K entries are zero).
    pub node_tree: Vec<usize>,
    /// Per node: one past the last node of its subtree (nnode). Nodes are numbered parents first
    /// and depth first, so a tree rooted at r is the nodes r..node_end\[r\].
    pub node_end: Vec<usize>,

    /// Geom names (ngeom).
    pub geom_name: Vec<String>,
    /// Geom type (ngeom).
    pub geom_type: Vec<GeomType>,
    /// Owning body (ngeom).
    pub geom_body: Vec<usize>,
    /// Size parameters (ngeom).
    pub geom_size: Vec<[f64; 3]>,
    /// Position in the body frame (ngeom).
    pub geom_pos: Vec<DVec3>,
    /// Orientation in the body frame (ngeom).
    pub geom_quat: Vec<DQuat>,
    /// [`Model::geom_quat`] as rotation matrices (ngeom).
    pub geom_mat: Vec<DMat3>,
    /// Bounding radius about the geom centre; infinite for planes (ngeom).
    pub geom_rbound: Vec<f64>,
    /// Half extents about the geom centre of a box that holds the geom, along its body's axes
    /// (ngeom): the broadphase turns it into world axes (|R| h) within the bounding sphere's box.
    /// None where no turn makes it smaller than the sphere's (a sphere's).
    pub geom_body_box: Vec<Option<DVec3>>,
    /// Mesh of each geom (mesh geoms), an index into `meshes`.
    pub geom_mesh: Vec<Option<usize>>,
    /// Mesh assets, in the frames their geoms use: shared by every world's copy of the model.
    pub meshes: std::sync::Arc<Vec<crate::geometry::Mesh>>,
    /// Height field of each geom (height-field geoms), an index into `hfields`.
    pub geom_hfield: Vec<Option<usize>>,
    /// Height-field assets: shared until a world's own heights are set (copied on write).
    pub hfields: std::sync::Arc<Vec<crate::geometry::HField>>,
    /// Friction (sliding, torsional, rolling) (ngeom).
    pub geom_friction: Vec<[f64; 3]>,
    /// Contact type bits (ngeom).
    pub geom_contype: Vec<u32>,
    /// Contact affinity bits (ngeom).
    pub geom_conaffinity: Vec<u32>,
    /// Contact dimensionality (ngeom).
    pub geom_condim: Vec<u32>,
    /// Contact priority (ngeom): a pair takes the higher geom's condim and friction, the larger
    /// of each at equal priority.
    pub geom_priority: Vec<i32>,
    /// Contact margin (ngeom).
    pub geom_margin: Vec<f64>,
    /// The ellipsoid fluid model's constants of a geom with `fluidshape="ellipsoid"` (ngeom).
    pub geom_fluid: Vec<Option<GeomFluid>>,

    /// Site names.
    pub site_name: Vec<String>,
    /// Site body.
    pub site_body: Vec<usize>,
    /// Site position in the body frame.
    pub site_pos: Vec<DVec3>,
    /// Site orientation in the body frame.
    pub site_mat: Vec<DMat3>,
    /// Site shape.
    pub site_type: Vec<GeomType>,
    /// Site size parameters, as a geom's of its shape.
    pub site_size: Vec<[f64; 3]>,

    /// The sensors the file declares that sinew computes (nsensor).
    pub sensor_kind: Vec<SensorKind>,
    /// Sensor names (nsensor).
    pub sensor_name: Vec<String>,
    /// Each sensor's first entry in `sensordata` (nsensor).
    pub sensor_adr: Vec<usize>,
    /// Length of `sensordata`.
    pub nsensordata: usize,

    /// Number of tendons.
    pub ntendon: usize,
    /// Tendon names (ntendon).
    pub tendon_name: Vec<String>,
    /// A fixed tendon's terms, `tendon_wrap[tendon_adr[t]..tendon_adr[t + 1]]`: length Σ coef ·
    /// qpos (empty for a spatial tendon).
    pub tendon_wrap: Vec<Wrap>,
    /// See `tendon_wrap` (ntendon + 1).
    pub tendon_adr: Vec<usize>,
    /// A spatial tendon's path, `tendon_path[tendon_path_adr[t]..tendon_path_adr[t + 1]]` (empty
    /// for a fixed tendon).
    pub tendon_path: Vec<PathPoint>,
    /// See `tendon_path` (ntendon + 1).
    pub tendon_path_adr: Vec<usize>,
    /// Spring stiffness (ntendon).
    pub tendon_stiffness: Vec<f64>,
    /// Damping (ntendon).
    pub tendon_damping: Vec<f64>,
    /// The spring's deadband [low, high] of lengths where it exerts no force (ntendon).
    pub tendon_springlength: Vec<[f64; 2]>,
    /// Whether the length is limited to `tendon_range` (ntendon).
    pub tendon_limited: Vec<bool>,
    /// Length limits [low, high] (ntendon).
    pub tendon_range: Vec<[f64; 2]>,
    /// Distance from a limit within which its row is built (ntendon).
    pub tendon_margin: Vec<f64>,
    /// Dry friction: the largest force the tendon's friction rows exert (ntendon).
    pub tendon_frictionloss: Vec<f64>,
    /// Length at qpos0 (ntendon).
    pub tendon_length0: Vec<f64>,
    /// Whether any tendon acts on the motion (a spring, damper, limit, dry friction or actuator on
    /// it; equalities read their own terms): the step evaluates the tendons only then.
    pub tendons_act: bool,
    /// Number of joint and tendon equality constraints.
    pub neq: usize,
    /// Equality names (neq).
    pub eq_name: Vec<String>,
    /// Each equality's two sides as lengths: x₁ − x₁⁰ − poly(x₂ − x₂⁰) = 0, each x a sum of
    /// coef · qpos terms (a joint: one term; a tendon: its terms), `eq_wrap[eq_adr[2e]..eq_adr[2e + 1]]`
    /// for x₁ and `eq_wrap[eq_adr[2e + 1]..eq_adr[2e + 2]]` for x₂ (empty without a second object).
    pub eq_wrap: Vec<Wrap>,
    /// See `eq_wrap` (2 neq + 1).
    pub eq_adr: Vec<usize>,
    /// x₁⁰ and x₂⁰: the sides at qpos0 (neq).
    pub eq_ref: Vec<[f64; 2]>,
    /// Polynomial coefficients (neq).
    pub eq_polycoef: Vec<[f64; 5]>,
    /// Whether each equality is active (neq).
    pub eq_active: Vec<bool>,
    /// Connect equalities.
    pub connects: Vec<Connect>,
    /// Every equality in the file's order (MuJoCo's): a coupling of joints or tendons (an index
    /// below `neq`) or a connect or weld (into `connects`).
    pub eq_order: Vec<EqRef>,
    /// Keyframes: named states (time, qpos, qvel, ctrl), absent arrays filled with qpos0 and zeros.
    pub keys: Vec<Keyframe>,
    /// Actuator names (nu).
    pub actuator_name: Vec<String>,
    /// What each actuator drives (nu).
    pub actuator_trn: Vec<Transmission>,
    /// Each actuator's moment arms, `actuator_moment[actuator_moment_adr[a]..actuator_moment_adr[a + 1]]`:
    /// its length is Σ coef · qpos and its force f adds coef · f to each dof (coef includes gear).
    pub actuator_moment: Vec<Wrap>,
    /// See `actuator_moment` (nu + 1).
    pub actuator_moment_adr: Vec<usize>,
    /// Affine gain g₀ + g₁ · length + g₂ · velocity: force = gain · (ctrl, or act) + bias (nu).
    pub actuator_gain: Vec<[f64; 3]>,
    /// Activation dynamics (nu).
    pub actuator_dyn: Vec<ActuatorDyn>,
    /// Each actuator's activation in `act`, if it has one (nu).
    pub actuator_actadr: Vec<Option<usize>>,
    /// Activation range [low, high] when limited (nu).
    pub actuator_actrange: Vec<Option<[f64; 2]>>,
    /// A muscle's force parameters, length range and acc0 (nu; None for other actuators).
    pub actuator_muscle: Vec<Option<Muscle>>,
    /// Number of activations (actuators with dynamics).
    pub na: usize,
    /// Actuators whose force is gain₀ · ctrl alone (no dynamics, fixed gain, no bias) (nu).
    pub actuator_plain: Vec<bool>,
    /// Affine bias b₀ + b₁ · length + b₂ · velocity (nu).
    pub actuator_bias: Vec<[f64; 3]>,
    /// Gear (nu).
    pub actuator_gear: Vec<f64>,
    /// Control range (nu).
    pub actuator_ctrlrange: Vec<[f64; 2]>,
    /// Whether ctrl is clamped (nu).
    pub actuator_ctrllimited: Vec<bool>,
    /// Force range (nu).
    pub actuator_forcerange: Vec<[f64; 2]>,
    /// Whether the force is clamped (nu).
    pub actuator_forcelimited: Vec<bool>,
    /// The dofs whose total actuator force is clamped, with their ranges (MuJoCo's joint
    /// `actuatorfrcrange`; hinge and slide joints only).
    pub dof_actfrcrange: Vec<(usize, [f64; 2])>,

    /// Geom pairs that pass the configuration-independent collision filters, with what the
    /// broadphase reads of them.
    pub collision_pairs: Vec<GeomPair>,
    /// The geoms (lower index first) of each `<contact><pair>`, in the file's order (npair).
    pub pair_geoms: Vec<(usize, usize)>,
    /// Each `<contact><pair>`'s friction as MuJoCo keeps it (npair × 5); its contacts read the
    /// first ([`GeomPair::friction`]).
    pub pair_friction: Vec<[f64; 5]>,
    /// Normal of the plane all motion stays in, when every joint is a hinge about it or a slide
    /// along it (hopper, walker, half-cheetah): friction out of that plane can do nothing there.
    pub motion_plane: Option<DVec3>,
    /// Body-pair contact exclusions (sorted pairs).
    pub exclude_pairs: Vec<(usize, usize)>,
    /// Bound, valid at every configuration, on the distance from the body's origin to any point of
    /// a geom (planes excepted) of its subtree; ∞ when a slide joint within makes it unbounded
    /// (nbody).
    pub body_reach: Vec<f64>,
    /// The plane groups the [`PairTest::Plane`] pairs refer to.
    pub plane_groups: Vec<PlaneGroup>,
    /// The pairs of two bounded geoms.
    pub gap_pairs: Vec<GapPair>,
    /// Whether every gap pair's common ancestor is below the world, so that the joints above a
    /// child of the world move both its geoms alike.
    pub gaps_within_trees: bool,
    /// (qpos address, arm) of each joint that can move a gap pair's geoms relative to each other
    /// (with `gaps_within_trees`, those below the children of the world), when all are hinges or
    /// slides: `collision::gaps::quick_travel` then bounds how far the gaps shrank in one pass.
    pub gap_arms: Option<Vec<(usize, f64)>>,
    /// Per geom (ngeom + 1): the first of its pairs in `collision_pairs` as the lower geom; the
    /// pairs are in (g1, g2) order, so geom i's are `geom_first_pair[i]..geom_first_pair[i + 1]`
    /// by increasing g2.
    pub geom_first_pair: Vec<usize>,
    /// The second geom of each pair (as `u32`, packed for [`Model::geom_first_pair`]'s searches).
    pub pair_partner: Vec<u32>,
    /// Bit i · ngeom + j set when geoms i < j make a pair (empty for models of more than
    /// [`PAIR_BITS_GEOMS`] geoms): the sweep's overlapping boxes that are no pair cost one load.
    pub pair_bits: Vec<u64>,
    /// Per word of [`Model::pair_bits`], the pairs of the words before it (empty when two pairs
    /// share their geoms): the index of a pair is then its bit's rank, found without a search.
    pub pair_rank: Vec<u32>,
    /// The geoms of [`PairTest::Spheres`] pairs, which the sweep of the broadphase bounds by
    /// boxes (within a tree too: dm_control's dog has 5,438 pairs of its own geoms).
    pub sweep_geoms: Vec<usize>,
    /// Indices into `collision_pairs` of the other pairs (a plane's, two planes'), in order:
    /// tested on their bounds without the sweep.
    pub pairs_unswept: Vec<usize>,
    /// Indices into `collision_pairs` of the other pairs outside plane groups (a plane's with a
    /// geom of unbounded reach, two planes'): with the gap pairs, the only ones tested while every
    /// group is apart.
    pub pairs_without_gap: Vec<usize>,
    /// How the model looks (the renderer's; the physics never reads it).
    pub vis: visual::Visual,
    /// What the model file asks for that sinew does not model.
    pub warnings: Vec<String>,
}

impl Model {
    /// Hinge and slide joints with a range: the joints limits act on (ball and free joints' ranges
    /// are not enforced).
    pub fn limited_joints(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.njnt).filter(|&j| self.jnt_limited[j] && matches!(self.jnt_type[j], JointType::Hinge | JointType::Slide))
    }

    /// Whether a step can have constraint rows: contacts, joint and tendon limits, equalities, dry
    /// friction or motion control.
    pub fn may_constrain(&self) -> bool {
        (self.opt.contact && !self.collision_pairs.is_empty())
            || (self.opt.limit && self.limited_joints().next().is_some())
            || self.limited_tendons().next().is_some()
            || self.eq_active.contains(&true)
            || self.connects.iter().any(|c| c.active)
            || self.dof_frictionloss.iter().chain(&self.tendon_frictionloss).any(|&f| f > 0.0)
            || (matches!(self.opt.actuation, Actuation::Trajectory { .. }) && self.nu > 0)
    }

    /// Whether the applied forces read the bodies' poses (spatial tendons, fluid forces), not the
    /// nodes' alone.
    pub fn forces_read_bodies(&self) -> bool {
        !self.tendon_path.is_empty() || self.opt.density > 0.0 || self.opt.viscosity > 0.0
    }

    /// Index of the body named `name`.
    pub fn body_id(&self, name: &str) -> Option<usize> {
        self.body_name.iter().position(|n| n == name)
    }

    /// Index of the geom named `name`.
    pub fn geom_id(&self, name: &str) -> Option<usize> {
        self.geom_name.iter().position(|n| n == name)
    }
}
