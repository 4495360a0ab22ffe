//! MuJoCo's `sensordata`: the sensors a model file declares ([`SensorKind`]), from a state's
//! kinematics and tendons and, for touch, the last step's contact forces. Positions, axes and
//! velocities are MuJoCo's to round-off; a touch sensor sums the normal forces of the contacts on
//! its site's body whose point lies within the site's volume (MuJoCo also counts a contact whose
//! normal ray from its point crosses the volume).

use glam::{DMat3, DVec3};

use crate::collision::Contact;
use crate::constraint::{Constraints, RowKind};
use crate::dynamics::kinematics::KinData;
use crate::dynamics::tendon::{geom_pose, TendonData};
use crate::model::{ConstraintMode, GeomType, Model, SensorFrame, SensorKind, Transmission, WORLD};

/// Writes every sensor of the state (`qpos`, `qvel`) with kinematics `kin` and tendons `ten`
/// into `out` (nsensordata), touch from the last step's contacts and constraint forces.
pub fn compute(m: &Model, kin: &KinData, ten: &TendonData, qpos: &[f64], qvel: &[f64], last: (&Constraints, &[Contact]), out: &mut [f64]) {
    for (s, kind) in m.sensor_kind.iter().enumerate() {
        let at = m.sensor_adr[s];
        let value = match *kind {
            SensorKind::JointPos(j) => Value::Scalar(qpos[m.jnt_qposadr[j]]),
            SensorKind::JointVel(j) => Value::Scalar(qvel[m.jnt_dofadr[j]]),
            SensorKind::TendonPos(t) => Value::Scalar(ten.length[t]),
            SensorKind::TendonVel(t) => Value::Scalar(ten.rate(m, t, qvel)),
            SensorKind::ActuatorPos(a) => Value::Scalar(actuator(m, ten, a, qpos, false)),
            SensorKind::ActuatorVel(a) => Value::Scalar(actuator(m, ten, a, qvel, true)),
            SensorKind::FramePos(f, reference) => {
                let (_, p) = pose(m, kin, f);
                Value::Vector(match reference.map(|r| pose(m, kin, r)) {
                    Some((rot, origin)) => rot.transpose() * (p - origin),
                    None => p,
                })
            }
            SensorKind::FrameAxis(f, axis, reference) => {
                let a = pose(m, kin, f).0.col(axis);
                Value::Vector(reference.map_or(a, |r| pose(m, kin, r).0.transpose() * a))
            }
            SensorKind::FrameLinVel(f) => Value::Vector(velocity(m, kin, f).1),
            SensorKind::FrameAngVel(f) => Value::Vector(velocity(m, kin, f).0),
            SensorKind::SubtreeCom(b) => Value::Vector(subtree(m, kin, b).com),
            SensorKind::SubtreeLinVel(b) => Value::Vector(subtree(m, kin, b).velocity),
            SensorKind::SubtreeAngMom(b) => Value::Vector(subtree(m, kin, b).momentum),
            SensorKind::Gyro(site) => {
                let (w, _) = velocity(m, kin, SensorFrame::Site(site));
                Value::Vector(pose(m, kin, SensorFrame::Site(site)).0.transpose() * w)
            }
            SensorKind::Velocimeter(site) => {
                let (_, v) = velocity(m, kin, SensorFrame::Site(site));
                Value::Vector(pose(m, kin, SensorFrame::Site(site)).0.transpose() * v)
            }
            SensorKind::Touch(site) => Value::Scalar(touch(m, kin, site, last)),
        };
        match value {
            Value::Scalar(x) => out[at] = x,
            Value::Vector(v) => out[at..at + 3].copy_from_slice(&v.to_array()),
        }
    }
}

/// One sensor's reading.
enum Value {
    Scalar(f64),
    Vector(DVec3),
}

/// Actuator a's length (`rate`: its velocity from `x` = qvel), gear times its joint's or tendon's.
fn actuator(m: &Model, ten: &TendonData, a: usize, x: &[f64], rate: bool) -> f64 {
    let gear = m.actuator_gear[a];
    match m.actuator_trn[a] {
        Transmission::Joint(j) => gear * if rate { x[m.jnt_dofadr[j]] } else { x[m.jnt_qposadr[j]] },
        Transmission::Tendon(t) => gear * if rate { ten.rate(m, t, x) } else { ten.length[t] },
    }
}

/// The frame's world axes and origin.
fn pose(m: &Model, kin: &KinData, f: SensorFrame) -> (DMat3, DVec3) {
    match f {
        SensorFrame::Body(b) => (kin.xmat[b] * m.body_iaxes[b], kin.xpos[b] + kin.xmat[b] * m.body_ipos[b]),
        SensorFrame::XBody(b) => (kin.xmat[b], kin.xpos[b]),
        SensorFrame::Geom(g) => geom_pose(m, kin, g),
        SensorFrame::Site(s) => {
            let b = m.site_body[s];
            (kin.xmat[b] * m.site_mat[s], kin.xpos[b] + kin.xmat[b] * m.site_pos[s])
        }
    }
}

/// The body a frame moves with.
fn body_of(m: &Model, f: SensorFrame) -> usize {
    match f {
        SensorFrame::Body(b) | SensorFrame::XBody(b) => b,
        SensorFrame::Geom(g) => m.geom_body[g],
        SensorFrame::Site(s) => m.site_body[s],
    }
}

/// The frame's world angular velocity and its origin's world linear velocity.
fn velocity(m: &Model, kin: &KinData, f: SensorFrame) -> (DVec3, DVec3) {
    let n = m.body_node[body_of(m, f)];
    if n == WORLD {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let p = pose(m, kin, f).1;
    (kin.v[n].ang, kin.v[n].point_velocity(p - kin.origin))
}

/// A subtree's centre of mass, its velocity and the angular momentum about it.
struct Subtree {
    com: DVec3,
    velocity: DVec3,
    momentum: DVec3,
}

/// The subtree of body `root` (bodies are numbered parents first).
fn subtree(m: &Model, kin: &KinData, root: usize) -> Subtree {
    let inside = |mut b: usize| {
        while b > root {
            b = m.body_parent[b];
        }
        b == root
    };
    let bodies = || (root..m.nbody).filter(|&b| inside(b) && m.body_mass[b] > 0.0);
    let (mut mass, mut mc, mut mv) = (0.0, DVec3::ZERO, DVec3::ZERO);
    for b in bodies() {
        let (_, v) = velocity(m, kin, SensorFrame::Body(b));
        mass += m.body_mass[b];
        mc += m.body_mass[b] * pose(m, kin, SensorFrame::Body(b)).1;
        mv += m.body_mass[b] * v;
    }
    if mass <= 0.0 {
        return Subtree { com: kin.xpos[root], velocity: DVec3::ZERO, momentum: DVec3::ZERO };
    }
    let (com, vcom) = (mc / mass, mv / mass);
    let mut momentum = DVec3::ZERO;
    for b in bodies() {
        let (w, v) = velocity(m, kin, SensorFrame::Body(b));
        let c = pose(m, kin, SensorFrame::Body(b)).1;
        let inertia = kin.xmat[b] * m.body_inertia[b] * kin.xmat[b].transpose();
        momentum += inertia * w + m.body_mass[b] * (c - com).cross(v - vcom);
    }
    Subtree { com, velocity: vcom, momentum }
}

/// The normal force of the last step's contacts on site `site`'s body whose point lies within
/// the site's volume.
fn touch(m: &Model, kin: &KinData, site: usize, (constraints, contacts): (&Constraints, &[Contact])) -> f64 {
    let (con, force) = (&constraints.con, &constraints.solve.force);
    if force.len() < con.len() {
        return 0.0;
    }
    let body = m.site_body[site];
    let (rot, centre) = pose(m, kin, SensorFrame::Site(site));
    // velocity-level time stepping solves for impulses over the step
    let per_force = if m.opt.constraint_mode == ConstraintMode::Velocity { 1.0 / m.opt.timestep } else { 1.0 };
    let mut total = 0.0;
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Normal) {
        let c = &contacts[con.source[j]];
        if m.geom_body[c.geom1] != body && m.geom_body[c.geom2] != body {
            continue;
        }
        if inside(m.site_type[site], m.site_size[site], rot.transpose() * (c.pos - centre)) {
            total += force[j] * per_force;
        }
    }
    total
}

/// Whether the point `p` (shape coordinates) lies within the shape.
fn inside(kind: GeomType, size: [f64; 3], p: DVec3) -> bool {
    let [a, b, c] = size;
    match kind {
        GeomType::Sphere => p.length() <= a,
        GeomType::Capsule => DVec3::new(p.x, p.y, p.z - p.z.clamp(-b, b)).length() <= a,
        GeomType::Cylinder => p.x.hypot(p.y) <= a && p.z.abs() <= b,
        GeomType::Box => p.x.abs() <= a && p.y.abs() <= b && p.z.abs() <= c,
        GeomType::Ellipsoid => (p / DVec3::new(a, b, c)).length_squared() <= 1.0,
        GeomType::Plane | GeomType::Mesh | GeomType::Hfield => false,
    }
}
