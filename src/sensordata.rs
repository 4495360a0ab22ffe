//! MuJoCo's `sensordata`: the sensors a model file declares ([`SensorKind`]), from a state's
//! kinematics and tendons and, for touch, the last step's contact forces. Positions, axes and
//! velocities are MuJoCo's to round-off; a touch sensor sums the normal forces of the contacts on
//! its site's body whose point lies within the site's volume (MuJoCo also counts a contact whose
//! normal ray from its point crosses the volume). Accelerometers, force and torque sensors read
//! the state's accelerations under its controls and the last step's constraint forces, and the
//! interaction forces between bodies they imply (MuJoCo's `cacc` and `cfrc_int`, from
//! `mj_rnePostConstraint`): without constraints, MuJoCo's to round-off.

use glam::{DMat3, DVec3};

use crate::collision::ray::ray_primitive;
use crate::collision::Contact;
use crate::constraint::AppliedForces;
use crate::dynamics::kinematics::{point_accel, KinData};
use crate::dynamics::tendon::{self, geom_pose, TendonData};
use crate::dynamics::{self, aba};
use crate::math::{Force, Motion, SpatialInertia};
use crate::step::data::Data;
use crate::model::{ContactObject, ContactSensor, Model, SensorFrame, SensorKind, Transmission, WORLD};

/// Writes the sensors `which` (indices, in order) of world state `s` into `out`, one after
/// another (every sensor: `sensordata`'s layout): kinematics (those a step computed ahead for the
/// state it reached, when they are of `s`, which stay there for the next step), tendons and, when
/// a sensor reads them, accelerations are computed into `d`; touch, force and torque read the
/// last step's constraint forces there.
pub fn read(m: &Model, d: &mut Data, s: State<'_>, which: &[usize], out: &mut [f64]) {
    let last = (&d.constraints.applied, &d.coll.contacts[..]);
    if !which.iter().any(|&k| m.sensor_kind[k].reads_accelerations()) {
        let dy = &mut d.dynamics;
        let kin = dy.ahead.at(m, s.qpos, s.qvel);
        tendon::compute(m, kin, s.qpos, &mut dy.ten);
        compute(m, kin, &dy.ten, s, last, None, (which, out));
        return;
    }
    let dy = &mut d.dynamics;
    dy.ahead.take_into(m, s.qpos, s.qvel, &mut dy.kin);
    tendon::compute(m, &dy.kin, s.qpos, &mut dy.ten);
    let acc = accelerations(m, d, s);
    let dy = &d.dynamics;
    compute(m, &dy.kin, &dy.ten, s, (&d.constraints.applied, &d.coll.contacts), Some(&acc), (which, out));
    // the kinematics go back to the cache, for the next step
    let dy = &mut d.dynamics;
    std::mem::swap(&mut dy.kin, &mut dy.ahead.kin);
    dy.ahead.keep(s.qpos, s.qvel);
}

/// A world's state as the sensors read it.
#[derive(Clone, Copy)]
pub struct State<'a> {
    /// Positions (nq).
    pub qpos: &'a [f64],
    /// Velocities (nv).
    pub qvel: &'a [f64],
    /// Controls (nu).
    pub ctrl: &'a [f64],
    /// Activations (na).
    pub act: &'a [f64],
}

/// Each node's spatial acceleration (about the kinematics' origin, with the base's fictitious −g:
/// MuJoCo's `cacc`) and the force each body's parent exerts on its subtree (about the origin:
/// MuJoCo's `cfrc_int`).
struct Accelerations {
    a: Vec<Motion>,
    f_int: Vec<Force>,
}

/// The accelerations of state `s` under its applied forces and the last step's constraint forces,
/// and the interaction forces they imply (RNEA's two passes over bodies, Featherstone 2008,
/// Table 5.1, with the contact forces as external forces). `d` holds the state's kinematics.
fn accelerations(m: &Model, d: &mut Data, s: State<'_>) -> Accelerations {
    let dy = &mut d.dynamics;
    // the applied forces (and the constraint-free accelerations, not used)
    dynamics::accelerations(m, dy, s.qpos, s.qvel, s.ctrl, s.act, 0.0);
    let (origin, mut qfrc_c) = (dy.kin.origin, vec![0.0; m.nv]);
    let mut f_ext = vec![Force::ZERO; m.nbody];
    let mut node_f = vec![Force::ZERO; m.nnode];
    let last = (&d.constraints.applied, &d.coll.contacts[..]);
    generalized_constraint_force(m, &dy.kin, last, &mut node_f, &mut qfrc_c, |b, at, f, couple| {
        f_ext[b] += Force::at_point(at - origin, f) + Force { ang: couple, lin: DVec3::ZERO }
    });
    let tau: Vec<f64> = dy.qfrc_applied.iter().zip(&qfrc_c).map(|(a, c)| a + c).collect();
    aba::backward(m, &dy.kin, &tau, 0.0, &mut dy.aba);
    aba::forward(m, &dy.kin, &mut dy.aba, &mut dy.qacc);
    let (kin, a) = (&dy.kin, dy.aba.a.clone());
    let mut f_int = vec![Force::ZERO; m.nbody];
    for b in 1..m.nbody {
        let n = m.body_node[b];
        let (an, vn) = if n == WORLD { (Motion::new(DVec3::ZERO, -m.opt.gravity), Motion::ZERO) } else { (a[n], kin.v[n]) };
        let inertia = SpatialInertia::new(m.body_mass[b], m.body_ipos[b], m.body_inertia[b]).to_parent(kin.xmat[b], kin.xpos[b] - origin);
        f_int[b] = inertia.mul_motion(&an) + vn.cross_force(&inertia.mul_motion(&vn)) - f_ext[b];
    }
    // leaves to root: each subtree's force (bodies are numbered parents first)
    for b in (1..m.nbody).rev() {
        let p = m.body_parent[b];
        if p != WORLD {
            let f = f_int[b];
            f_int[p] += f;
        }
    }
    Accelerations { a, f_int }
}

/// Writes the sensors `which` of state `st` with kinematics `kin`, tendons `ten` and, for the
/// sensors that read them, accelerations `acc` into `out`, one after another; touch from the last
/// step's contacts and constraint forces.
fn compute(m: &Model, kin: &KinData, ten: &TendonData, st: State<'_>, last: (&AppliedForces, &[Contact]), acc: Option<&Accelerations>, (which, out): (&[usize], &mut [f64])) {
    let (qpos, qvel) = (st.qpos, st.qvel);
    let mut at = 0;
    for &s in which {
        let kind = &m.sensor_kind[s];
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
            SensorKind::FrameQuat(f, reference) => {
                let rot = pose(m, kin, f).0;
                let q = mat2quat(reference.map_or(rot, |r| pose(m, kin, r).0.transpose() * rot));
                out[at..at + 4].copy_from_slice(&q);
                at += 4;
                continue;
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
            SensorKind::Contact(c) => {
                contacts(m, &c, last, &mut out[at..at + kind.dim()]);
                at += kind.dim();
                continue;
            }
            SensorKind::Rangefinder(site) => {
                let (rot, p) = pose(m, kin, SensorFrame::Site(site));
                Value::Scalar(crate::collision::ray::ray(m, kin, p, rot.col(2), m.site_body[site]))
            }
            SensorKind::Accelerometer(site) | SensorKind::Force(site) | SensorKind::Torque(site) => {
                // `read` computes the accelerations whenever such a sensor is read
                Value::Vector(acc.map_or(DVec3::ZERO, |acc| interaction(m, kin, acc, *kind, site)))
            }
        };
        match value {
            Value::Scalar(x) => out[at] = x,
            Value::Vector(v) => out[at..at + 3].copy_from_slice(&v.to_array()),
        }
        at += kind.dim();
    }
}

/// An accelerometer's, force sensor's or torque sensor's reading at `site`, in its frame.
fn interaction(m: &Model, kin: &KinData, acc: &Accelerations, kind: SensorKind, site: usize) -> DVec3 {
    let (rot, p) = pose(m, kin, SensorFrame::Site(site));
    let b = m.site_body[site];
    let r = p - kin.origin;
    let world = match kind {
        SensorKind::Accelerometer(_) => match m.body_node[b] {
            WORLD => -m.opt.gravity,
            n => point_accel(kin, &acc.a, DVec3::ZERO, n, r),
        },
        SensorKind::Force(_) => acc.f_int[b].lin,
        // the torque about the site
        _ => acc.f_int[b].ang - r.cross(acc.f_int[b].lin),
    };
    rot.transpose() * world
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

/// The normal force of the last step's contacts on site `site`'s body whose ray — from the contact
/// point along its normal, away from that body — meets the site's volume (MuJoCo's rule: a contact
/// within the volume counts, and so does one whose normal points into it).
fn touch(m: &Model, kin: &KinData, site: usize, (forces, contacts): (&AppliedForces, &[Contact])) -> f64 {
    let body = m.site_body[site];
    let (rot, centre) = pose(m, kin, SensorFrame::Site(site));
    let mut total = 0.0;
    for (c, f) in contacts.iter().zip(&forces.contact) {
        if m.geom_body[c.geom1] != body && m.geom_body[c.geom2] != body {
            continue;
        }
        // the normal points into body 1 (from geom2 to geom1): away from body 1 is −n
        let away = if m.geom_body[c.geom1] == body { -c.normal } else { c.normal };
        let (p, d) = (rot.transpose() * (c.pos - centre), rot.transpose() * away);
        if f.normal > 0.0 && ray_primitive(m.site_type[site], m.site_size[site], p, d).is_some() {
            total += f.normal;
        }
    }
    total
}

/// The unit quaternion (w, x, y, z) of a rotation matrix, by MuJoCo's `mju_mat2Quat` (its largest
/// component computed first, so w ≥ 0 for turns under half a turn).
fn mat2quat(r: DMat3) -> [f64; 4] {
    let e = |i: usize, j: usize| r.col(j)[i];
    let q = if e(0, 0) + e(1, 1) + e(2, 2) > 0.0 {
        let w = 0.5 * (1.0 + e(0, 0) + e(1, 1) + e(2, 2)).sqrt();
        [w, 0.25 * (e(2, 1) - e(1, 2)) / w, 0.25 * (e(0, 2) - e(2, 0)) / w, 0.25 * (e(1, 0) - e(0, 1)) / w]
    } else if e(0, 0) > e(1, 1) && e(0, 0) > e(2, 2) {
        let x = 0.5 * (1.0 + e(0, 0) - e(1, 1) - e(2, 2)).sqrt();
        [0.25 * (e(2, 1) - e(1, 2)) / x, x, 0.25 * (e(0, 1) + e(1, 0)) / x, 0.25 * (e(0, 2) + e(2, 0)) / x]
    } else if e(1, 1) > e(2, 2) {
        let y = 0.5 * (1.0 - e(0, 0) + e(1, 1) - e(2, 2)).sqrt();
        [0.25 * (e(0, 2) - e(2, 0)) / y, 0.25 * (e(0, 1) + e(1, 0)) / y, y, 0.25 * (e(1, 2) + e(2, 1)) / y]
    } else {
        let z = 0.5 * (1.0 - e(0, 0) - e(1, 1) + e(2, 2)).sqrt();
        [0.25 * (e(1, 0) - e(0, 1)) / z, 0.25 * (e(0, 2) + e(2, 0)) / z, 0.25 * (e(1, 2) + e(2, 1)) / z, z]
    };
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

/// A contact sensor's slots (MuJoCo's `mjSENS_CONTACT`) from the last step's contacts: those
/// between its objects within the pair's margin or carrying force (an exact resting contact may
/// sit a round-off above its surface), the first `num` found or, with `mindist`, the nearest.
/// Each slot holds the number found, the distance, point and normal (pointing away from the first
/// object), as its fields ask; slots beyond the number found are zero.
fn contacts(m: &Model, c: &ContactSensor, (forces, list): (&AppliedForces, &[Contact]), out: &mut [f64]) {
    out.fill(0.0);
    let matched = |k: usize| -> Option<bool> {
        let con = &list[k];
        let touching = con.dist <= m.geom_margin[con.geom1].max(m.geom_margin[con.geom2]) || forces.contact.get(k).is_some_and(|f| f.normal > 0.0);
        if !touching {
            return None;
        }
        let is = |o: ContactObject, g: usize| match o {
            ContactObject::Any => true,
            ContactObject::Geom(i) => g == i,
            ContactObject::Body(b) => m.geom_body[g] == b,
            ContactObject::Subtree(b) => {
                let mut x = m.geom_body[g];
                while x > b {
                    x = m.body_parent[x];
                }
                x == b
            }
        };
        let (g1, g2) = (con.geom1, con.geom2);
        let forward = is(c.obj1, g1) && is(c.obj2, g2);
        let reverse = is(c.obj1, g2) && is(c.obj2, g1);
        // Some(true): the first object is geom 2 (sinew's normal points into geom 1, from geom 2)
        (forward || reverse).then_some(!forward)
    };
    let found = (0..list.len()).filter(|&k| matched(k).is_some()).count();
    let mut last_pick: Option<usize> = None;
    for slot in out.chunks_mut(c.slot_size()).take(found) {
        // the next contact: in list order, or the nearest after the last picked (ties by order)
        let after = |k: usize| last_pick.is_none_or(|p| if c.mindist { (list[k].dist, k) > (list[p].dist, p) } else { k > p });
        let pick = (0..list.len()).filter(|&k| matched(k).is_some() && after(k)).min_by(|&a, &b| {
            if c.mindist { list[a].dist.total_cmp(&list[b].dist).then(a.cmp(&b)) } else { a.cmp(&b) }
        });
        let Some(k) = pick else { break };
        last_pick = Some(k);
        let away = if matched(k) == Some(true) { list[k].normal } else { -list[k].normal };
        let mut at = 0;
        for (bit, value) in [(0, [found as f64, 0.0, 0.0]), (1, [list[k].dist, 0.0, 0.0]), (2, list[k].pos.to_array()), (3, away.to_array())] {
            if c.fields & (1 << bit) != 0 {
                let n = crate::model::sensor::CONTACT_FIELD_SIZE[bit];
                slot[at..at + n].copy_from_slice(&value[..n]);
                at += n;
            }
        }
    }
}

/// The last step's constraint forces (`last`: what its rows applied, and its contacts) as
/// generalised forces `qfrc` (Jᵀ f, nv), with each contact force on a body passed to
/// `on_body(body, point, force, couple)` (the couple of torsional and rolling friction); `node_f`
/// (nnode) is scratch.
pub fn generalized_constraint_force(
    m: &Model, kin: &KinData, (forces, contacts): (&AppliedForces, &[Contact]), node_f: &mut [Force], qfrc: &mut [f64], mut on_body: impl FnMut(usize, DVec3, DVec3, DVec3),
) {
    qfrc.fill(0.0);
    if forces.contact.is_empty() && forces.connect.is_empty() && forces.joint.is_empty() {
        return;
    }
    // spatial constraint forces per node (world coordinates about the kinematics' origin), for Jᵀ f
    node_f.fill(Force::ZERO);
    for (c, f) in contacts.iter().zip(&forces.contact) {
        let (f_c, t_c) = (f.total, f.torque);
        if f_c == DVec3::ZERO && t_c == DVec3::ZERO {
            continue;
        }
        for (g, sign) in [(c.geom1, 1.0), (c.geom2, -1.0)] {
            let b = m.geom_body[g];
            let (fs, ts) = (f_c * sign, t_c * sign);
            on_body(b, c.pos, fs, ts);
            let n = m.body_node[b];
            if n != WORLD {
                node_f[n] += Force::at_point(c.pos - kin.origin, fs);
                if ts != DVec3::ZERO {
                    node_f[n] += Force { ang: ts, lin: DVec3::ZERO };
                }
            }
        }
    }
    // connects pull their two points together
    for c in &forces.connect {
        let at = |r: DVec3| if c.angular { Force { ang: c.force, lin: DVec3::ZERO } } else { Force::at_point(r, c.force) };
        let [n0, n1] = c.node;
        if n0 != WORLD {
            node_f[n0] += at(c.arm[0]);
        }
        if n1 != WORLD {
            node_f[n1] -= at(c.arm[1]);
        }
    }
    // τ = Jᵀ f: leaves to root, as RNEA's second pass (Featherstone 2008, Table 5.1)
    for i in (0..m.nnode).rev() {
        for r in 0..m.node_nv[i] {
            qfrc[m.node_dofadr[i] + r] += kin.s[i][r].dot(&node_f[i]);
        }
        let p = m.node_parent[i];
        if p != WORLD {
            let fp = node_f[i];
            node_f[p] += fp;
        }
    }
    for &(dof, f) in &forces.joint {
        qfrc[dof] += f;
    }
}
