//! The model fields a world of a batch may hold values of its own for (domain randomization):
//! each [`Param`] is read and written by MuJoCo's name and shape, checked before anything
//! changes, and followed by everything the compiler derives from it.

use glam::{DMat3, DVec3};

use crate::dynamics::DynamicsData;
use crate::error::{Error, Result};
use crate::math::{SpatialInertia, Xform, MAX_DAMPING, MAX_STATE};
use crate::model::{EqRef, Model, PairFriction, Transmission, Wrap, WORLD};

/// A model field that may vary per world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// Body masses (nbody); setting them scales each body's inertia by the same factor.
    BodyMass,
    /// Centres of mass in the body frames (nbody × 3).
    BodyIpos,
    /// Principal moments of inertia about the body's inertial axes (nbody × 3), MuJoCo's.
    BodyInertia,
    /// Sliding, torsional and rolling friction (ngeom × 3); contacts read the first.
    GeomFriction,
    /// Joint damping per dof (nv).
    DofDamping,
    /// Armature inertia per dof (nv).
    DofArmature,
    /// Dry friction per dof (nv).
    DofFrictionloss,
    /// Joint stiffness (njnt).
    JntStiffness,
    /// Actuator gain: fixed, times length, times velocity (nu × 3).
    ActuatorGain,
    /// Actuator bias: fixed, times length, times velocity (nu × 3).
    ActuatorBias,
    /// Actuator gear (nu).
    ActuatorGear,
    /// Control range (nu × 2).
    ActuatorCtrlrange,
    /// Gravity (3).
    Gravity,
    /// The coefficient of each joint of the fixed tendons (MuJoCo's `wrap_prm` of their
    /// joint wraps, in tendon order): their lengths and the moment arms of actuators on them.
    WrapPrm,
    /// Every height field's elevations, one after another (MuJoCo's `hfield_data`: row 0 at −y,
    /// in units of the field's height).
    HfieldData,
    /// Body positions in their parents' frames (nbody × 3); only a body fixed to the world (no
    /// joint between it and the world) may take a value of its own: a target, an obstacle.
    BodyPos,
    /// Body orientations in their parents' frames (nbody × 4, w x y z, normalized when set), as
    /// `BodyPos`.
    BodyQuat,
    /// Whether each equality acts (1) or not (0), in the file's order (MuJoCo's `eq_active`,
    /// [`Model::eq_order`]): a weld switched on holds the bodies where the weld's reference
    /// puts them, closing any error within a step.
    EqActive,
    /// Each `<contact><pair>`'s friction (npair × 5, MuJoCo's `pair_friction`: two sliding,
    /// torsional, two rolling), in the file's order; its contacts read the first.
    PairFriction,
}

impl Param {
    /// Every field, in the order of [`Param::name`]s that `Batch` lists.
    pub const ALL: [Param; 19] = [
        Param::BodyMass,
        Param::BodyIpos,
        Param::BodyInertia,
        Param::GeomFriction,
        Param::DofDamping,
        Param::DofArmature,
        Param::DofFrictionloss,
        Param::JntStiffness,
        Param::ActuatorGain,
        Param::ActuatorBias,
        Param::ActuatorGear,
        Param::ActuatorCtrlrange,
        Param::Gravity,
        Param::WrapPrm,
        Param::HfieldData,
        Param::BodyPos,
        Param::BodyQuat,
        Param::EqActive,
        Param::PairFriction,
    ];

    /// MuJoCo's name of the field (`gravity` for `opt.gravity`).
    pub fn name(self) -> &'static str {
        match self {
            Param::BodyMass => "body_mass",
            Param::BodyIpos => "body_ipos",
            Param::BodyInertia => "body_inertia",
            Param::GeomFriction => "geom_friction",
            Param::DofDamping => "dof_damping",
            Param::DofArmature => "dof_armature",
            Param::DofFrictionloss => "dof_frictionloss",
            Param::JntStiffness => "jnt_stiffness",
            Param::ActuatorGain => "actuator_gain",
            Param::ActuatorBias => "actuator_bias",
            Param::ActuatorGear => "actuator_gear",
            Param::ActuatorCtrlrange => "actuator_ctrlrange",
            Param::Gravity => "gravity",
            Param::WrapPrm => "wrap_prm",
            Param::HfieldData => "hfield_data",
            Param::BodyPos => "body_pos",
            Param::BodyQuat => "body_quat",
            Param::EqActive => "eq_active",
            Param::PairFriction => "pair_friction",
        }
    }

    /// The field called `name`.
    pub fn named(name: &str) -> Option<Param> {
        Param::ALL.into_iter().find(|p| p.name() == name)
    }

    /// (rows, columns) of the field in `m`; a field of one column per element is (n, 1).
    pub fn shape(self, m: &Model) -> (usize, usize) {
        match self {
            Param::BodyMass => (m.nbody, 1),
            Param::BodyIpos | Param::BodyInertia => (m.nbody, 3),
            Param::GeomFriction => (m.ngeom, 3),
            Param::DofDamping | Param::DofArmature | Param::DofFrictionloss => (m.nv, 1),
            Param::JntStiffness => (m.njnt, 1),
            Param::ActuatorGain | Param::ActuatorBias => (m.nu, 3),
            Param::ActuatorGear => (m.nu, 1),
            Param::ActuatorCtrlrange => (m.nu, 2),
            Param::Gravity => (1, 3),
            Param::WrapPrm => (m.tendon_wrap.len(), 1),
            Param::HfieldData => (m.hfields.iter().map(|h| h.data.len()).sum(), 1),
            Param::BodyPos => (m.nbody, 3),
            Param::BodyQuat => (m.nbody, 4),
            Param::EqActive => (m.eq_order.len(), 1),
            Param::PairFriction => (m.pair_geoms.len(), 5),
        }
    }

    /// The field's values in `m`, row after row.
    pub fn read(self, m: &Model) -> Vec<f64> {
        let v3 = |v: &[DVec3]| v.iter().flat_map(|x| x.to_array()).collect();
        match self {
            Param::BodyMass => m.body_mass.clone(),
            Param::BodyIpos => v3(&m.body_ipos),
            Param::BodyInertia => (0..m.nbody).flat_map(|b| principal_moments(m, b).to_array()).collect(),
            Param::GeomFriction => m.geom_friction.concat(),
            Param::DofDamping => m.dof_damping.clone(),
            Param::DofArmature => m.dof_armature.clone(),
            Param::DofFrictionloss => m.dof_frictionloss.clone(),
            Param::JntStiffness => m.jnt_stiffness.clone(),
            Param::ActuatorGain => m.actuator_gain.concat(),
            Param::ActuatorBias => m.actuator_bias.concat(),
            Param::ActuatorGear => m.actuator_gear.clone(),
            Param::ActuatorCtrlrange => m.actuator_ctrlrange.concat(),
            Param::Gravity => m.opt.gravity.to_array().to_vec(),
            Param::WrapPrm => m.tendon_wrap.iter().map(|w| w.coef).collect(),
            Param::HfieldData => m.hfields.iter().flat_map(|h| h.data.iter().copied()).collect(),
            Param::BodyPos => v3(&m.body_pos),
            Param::BodyQuat => m.body_quat.iter().flat_map(|q| [q.w, q.x, q.y, q.z]).collect(),
            Param::EqActive => m
                .eq_order
                .iter()
                .map(|&e| match e {
                    EqRef::Coupling(k) => m.eq_active[k],
                    EqRef::Connect(c) => m.connects[c].active,
                } as u8 as f64)
                .collect(),
            Param::PairFriction => m.pair_friction.concat(),
        }
    }

    /// Where value `k` (of rows of `cols`) stands as the field's NumPy array indexes it: `[k]`
    /// for gravity's (3,) and a column's (rows,), else `[row, column]`.
    fn at(self, k: usize, cols: usize) -> String {
        if self == Param::Gravity || cols == 1 { format!("[{}]", if cols == 1 { k } else { k % cols }) } else { format!("[{}, {}]", k / cols, k % cols) }
    }

    /// What is wrong with `values` (row after row, [`Param::shape`]) for `m`, naming the element.
    pub fn check(self, m: &Model, values: &[f64]) -> std::result::Result<(), String> {
        let (rows, cols) = self.shape(m);
        if values.len() != rows * cols {
            return Err(format!("{} takes {rows} × {cols} values, got {}", self.name(), values.len()));
        }
        let max = if self == Param::DofDamping { MAX_DAMPING } else { MAX_STATE };
        if let Some(k) = values.iter().position(|x| !x.is_finite() || x.abs() > max) {
            return Err(format!("{}{} = {} is not finite or beyond ±{max:e}", self.name(), self.at(k, cols), values[k]));
        }
        let non_negative = matches!(
            self,
            Param::BodyMass
                | Param::BodyInertia
                | Param::GeomFriction
                | Param::DofDamping
                | Param::DofArmature
                | Param::DofFrictionloss
                | Param::JntStiffness
                | Param::PairFriction
        );
        if let Some(k) = values.iter().position(|&x| non_negative && x < 0.0) {
            return Err(format!("{}{} = {} is negative", self.name(), self.at(k, cols), values[k]));
        }
        match self {
            Param::BodyInertia => (1..rows).try_for_each(|b| inertia_ok(m, b, &values[3 * b..3 * b + 3])),
            Param::ActuatorGain | Param::ActuatorBias => {
                let now = self.read(m);
                match (0..rows).find(|&a| m.actuator_muscle[a].is_some() && values[3 * a..3 * a + 3] != now[3 * a..3 * a + 3]) {
                    Some(a) => Err(format!("{}[{a}]: actuator {a} is a muscle, whose force its own curves set", self.name())),
                    None => Ok(()),
                }
            }
            Param::EqActive => match values.iter().position(|&x| x != 0.0 && x != 1.0) {
                Some(e) => Err(format!("eq_active[{e}] = {}: 0 (off) or 1 (on)", values[e])),
                None => Ok(()),
            },
            Param::ActuatorCtrlrange => match values.chunks(2).position(|r| r[0] > r[1]) {
                Some(a) => Err(format!("actuator_ctrlrange[{a}] = {:?}: its lower end is above its upper end", &values[2 * a..2 * a + 2])),
                None => Ok(()),
            },
            Param::BodyPos | Param::BodyQuat => {
                let now = self.read(m);
                if let Some(b) = (0..rows).find(|&b| values[b * cols..(b + 1) * cols] != now[b * cols..(b + 1) * cols] && (b == 0 || m.body_node[b] != WORLD)) {
                    return Err(format!("{}[{b}]: body '{}' is not fixed to the world: only such a body may be placed per world", self.name(), m.body_name[b]));
                }
                match values.chunks(4).position(|q| self == Param::BodyQuat && q.iter().map(|x| x * x).sum::<f64>() < 1e-20) {
                    Some(b) => Err(format!("body_quat[{b}] is zero: not a rotation")),
                    None => Ok(()),
                }
            }
            _ => Ok(()),
        }
    }

    /// Writes checked `values` into `m` (mass scales inertia), then what the compiler derives
    /// from them; fails if a joint is left moving no mass.
    pub fn write(self, m: &mut Model, values: &[f64]) -> Result<()> {
        self.assign(m, values);
        derive(m)
    }

    /// Writes checked `values` into `m`, nothing derived yet.
    fn assign(self, m: &mut Model, values: &[f64]) {
        let v3 = |k: usize| DVec3::from_slice(&values[3 * k..3 * k + 3]);
        let a3 = |k: usize| [values[3 * k], values[3 * k + 1], values[3 * k + 2]];
        match self {
            Param::BodyMass => {
                for (b, &mass) in values.iter().enumerate() {
                    if mass != m.body_mass[b] && m.body_mass[b] > 0.0 {
                        m.body_inertia[b] *= mass / m.body_mass[b];
                    }
                    m.body_mass[b] = mass;
                }
            }
            Param::BodyIpos => m.body_ipos = (0..m.nbody).map(v3).collect(),
            Param::BodyInertia => {
                for b in 0..m.nbody {
                    if v3(b) != principal_moments(m, b) {
                        let r = m.body_iaxes[b];
                        m.body_inertia[b] = r * DMat3::from_diagonal(v3(b)) * r.transpose();
                    }
                }
            }
            Param::GeomFriction => m.geom_friction = (0..m.ngeom).map(a3).collect(),
            Param::DofDamping => m.dof_damping.copy_from_slice(values),
            Param::DofArmature => m.dof_armature.copy_from_slice(values),
            Param::DofFrictionloss => m.dof_frictionloss.copy_from_slice(values),
            Param::JntStiffness => m.jnt_stiffness.copy_from_slice(values),
            Param::ActuatorGain => m.actuator_gain = (0..m.nu).map(a3).collect(),
            Param::ActuatorBias => m.actuator_bias = (0..m.nu).map(a3).collect(),
            Param::ActuatorGear => m.actuator_gear.copy_from_slice(values),
            Param::ActuatorCtrlrange => m.actuator_ctrlrange = values.chunks(2).map(|r| [r[0], r[1]]).collect(),
            Param::Gravity => m.opt.gravity = v3(0),
            Param::WrapPrm => {
                for (w, &coef) in m.tendon_wrap.iter_mut().zip(values) {
                    w.coef = coef;
                }
            }
            Param::BodyPos => m.body_pos = (0..m.nbody).map(v3).collect(),
            Param::BodyQuat => {
                for (b, q) in values.chunks(4).enumerate() {
                    let q = glam::DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
                    // a unit quaternion is kept as given (so a copy's values come back bit for bit)
                    if q != m.body_quat[b] {
                        m.body_quat[b] = if (q.length_squared() - 1.0).abs() < 1e-12 { q } else { q.normalize() };
                    }
                }
            }
            Param::EqActive => {
                for (&e, &on) in m.eq_order.iter().zip(values) {
                    match e {
                        EqRef::Coupling(k) => m.eq_active[k] = on != 0.0,
                        EqRef::Connect(c) => m.connects[c].active = on != 0.0,
                    }
                }
            }
            Param::PairFriction => {
                m.pair_friction = values.chunks(5).map(|r| [r[0], r[1], r[2], r[3], r[4]]).collect();
                for p in m.collision_pairs.iter_mut() {
                    if let (Some(f), Some(k)) = (p.friction.as_mut(), m.pair_geoms.iter().position(|&g| g == (p.g1, p.g2))) {
                        let [slide, _, spin, roll, _] = m.pair_friction[k];
                        *f = PairFriction::new(f.condim, [slide, spin, roll]);
                    }
                }
            }
            Param::HfieldData => {
                let mut rest = values;
                for h in std::sync::Arc::make_mut(&mut m.hfields).iter_mut() {
                    let (mine, after) = rest.split_at(h.data.len());
                    h.data.copy_from_slice(mine);
                    rest = after;
                }
            }
        }
    }
}

/// `m` with every field of [`Param::ALL`] set to `fields` (in that order) and the rotational
/// inertias to `inertia` ([`read_inertia_matrices`]'s, bit for bit), each checked, derived once.
pub fn restore(m: &mut Model, fields: &[Vec<f64>], inertia: &[f64]) -> Result<()> {
    if fields.len() != Param::ALL.len() {
        return Err(Error::Input(format!("{} fields expected, got {}", Param::ALL.len(), fields.len())));
    }
    for (p, values) in Param::ALL.iter().zip(fields) {
        p.check(m, values).map_err(Error::Input)?;
        p.assign(m, values);
    }
    write_inertia_matrices(m, inertia)
}

/// Every body's rotational inertia (3 × 3, columns), bit for bit.
pub fn read_inertia_matrices(m: &Model) -> Vec<f64> {
    m.body_inertia.iter().flat_map(|i| i.to_cols_array()).collect()
}

/// Sets every body's rotational inertia as [`read_inertia_matrices`] gave it.
pub fn write_inertia_matrices(m: &mut Model, values: &[f64]) -> Result<()> {
    if values.len() != 9 * m.nbody || values.iter().any(|x| !x.is_finite()) {
        return Err(Error::Input(format!("inertia matrices: {} finite values expected, got {}", 9 * m.nbody, values.len())));
    }
    m.body_inertia = values.chunks(9).map(DMat3::from_cols_slice).collect();
    derive(m)
}

/// Body `b`'s principal moments: its inertia about its centre of mass along its inertial axes.
fn principal_moments(m: &Model, b: usize) -> DVec3 {
    let r = m.body_iaxes[b];
    let p = r.transpose() * m.body_inertia[b] * r;
    DVec3::new(p.x_axis.x, p.y_axis.y, p.z_axis.z)
}

/// Principal moments of body `b` that a rigid body can have: positive where it has mass, and
/// each at most the sum of the other two (MuJoCo's compiler check).
fn inertia_ok(m: &Model, b: usize, d: &[f64]) -> std::result::Result<(), String> {
    let (x, y, z) = (d[0], d[1], d[2]);
    if m.body_mass[b] > 0.0 && d.iter().any(|&v| v <= 0.0) {
        return Err(format!("body_inertia[{b}] = {d:?} is not positive definite (body '{}' has mass)", m.body_name[b]));
    }
    let slack = 1e-12 * (x + y + z);
    if x > y + z + slack || y > x + z + slack || z > x + y + slack {
        return Err(format!("body_inertia[{b}] = {d:?} breaks the triangle inequality (no rigid body has it)"));
    }
    Ok(())
}

/// Each actuator's moment arms ([`Model::actuator_moment`]) from its transmission and gear, and
/// whether its force is its control times a fixed gain ([`Model::actuator_plain`]).
pub(super) fn actuator_derived(m: &mut Model) {
    m.actuator_moment.clear();
    m.actuator_moment_adr = vec![0];
    for a in 0..m.nu {
        let gear = m.actuator_gear[a];
        match m.actuator_trn[a] {
            Transmission::Joint(j) => m.actuator_moment.push(Wrap { dof: m.jnt_dofadr[j], qpos: m.jnt_qposadr[j], coef: gear }),
            Transmission::Tendon(t) => {
                for k in m.tendon_adr[t]..m.tendon_adr[t + 1] {
                    let w = m.tendon_wrap[k];
                    m.actuator_moment.push(Wrap { coef: gear * w.coef, ..w });
                }
            }
        }
        m.actuator_moment_adr.push(m.actuator_moment.len());
    }
    m.dof_actdamping = vec![0.0; m.nv];
    if m.opt.implicit_actuators {
        for a in (0..m.nu).filter(|&a| m.actuator_muscle[a].is_none()) {
            if let Transmission::Joint(j) = m.actuator_trn[a] {
                m.dof_actdamping[m.jnt_dofadr[j]] += (-m.actuator_bias[a][2]).max(0.0) * m.actuator_gear[a] * m.actuator_gear[a];
            }
        }
    }
    m.actuator_plain = (0..m.nu)
        .map(|a| m.actuator_dyn[a] == crate::model::ActuatorDyn::None && m.actuator_gain[a][1..] == [0.0; 2] && m.actuator_bias[a] == [0.0; 3])
        .collect();
}

/// Each node's rigid inertia: its bodies' inertias moved into its frame.
pub(super) fn node_inertias(m: &mut Model, inertia: &[SpatialInertia]) {
    for b in 1..m.nbody {
        let n = m.body_node[b];
        if n == WORLD {
            continue;
        }
        let (rot, pos) = m.body_offset[b].pose();
        let moved = inertia[b].to_parent(rot, pos);
        m.node_inertia[n] = m.node_inertia[n].combine(&moved);
    }
}

/// What the compiler derives from the fields of [`Param`]: the nodes' inertias, the fluid boxes,
/// the actuators' moment arms; then the check that every joint moves some mass.
fn derive(m: &mut Model) -> Result<()> {
    let inertia: Vec<SpatialInertia> = (0..m.nbody).map(|b| SpatialInertia::new(m.body_mass[b], m.body_ipos[b], m.body_inertia[b])).collect();
    m.node_inertia.fill(SpatialInertia::ZERO);
    node_inertias(m, &inertia);
    m.body_fluid_box = inertia.iter().zip(&m.body_iaxes).map(|(i, &axes)| super::fluid_box(i, axes)).collect();
    actuator_derived(m);
    // the world-fixed bodies' poses, parents first (as `compile::joints_and_nodes` sets them)
    for b in 1..m.nbody {
        if m.body_node[b] == WORLD {
            let p = m.body_parent[b];
            m.body_offset[b] = m.body_offset[p].then(&Xform::from_pose_quat(m.body_quat[b], m.body_pos[b]));
        }
    }
    let mut dy = DynamicsData::new(m);
    crate::dynamics::forward(m, &mut dy, &m.qpos0, &vec![0.0; m.nv], &vec![0.0; m.nu], &vec![0.0; m.na]);
    super::check_solvable(m, &dy).map_err(|e| Error::Input(e.to_string()))
}
