//! Tendons (MuJoCo's `mj_tendon`): each tendon's length, its Jacobian J (the length's rate per
//! unit q̇, MuJoCo's `ten_J`) and J̇ q̇. A fixed tendon's length is Σ coef · q. A spatial tendon's
//! is its path's: straight segments between consecutive sites, and around a wrapping sphere or
//! cylinder between the sites either side of it where the straight line would cross it (tangent
//! lines and the arc between them, on the side of the side site when one is given); each branch
//! after a pulley counts its length divided by the pulley's divisor. J of a segment is the unit
//! direction read against its end points' Jacobians; the arc's length moves with its tangent
//! points, whose motion along the surface changes nothing to first order, so the arc adds
//! length but no J (as MuJoCo's).

use glam::{DMat3, DVec2, DVec3};

use super::kinematics::{add_joint_forces, point_accel, point_vel, velocity_products, KinData};
use crate::math::{Force, Motion};
use crate::model::{GeomType, Model, PathPoint, Wrap};

/// The tendons of one evaluation.
#[derive(Clone, Debug, Default)]
pub struct TendonData {
    /// Lengths (ntendon).
    pub length: Vec<f64>,
    /// J, row-major (ntendon × nv): tendon t's rate is J_t · q̇ and a tension f on it applies the
    /// joint forces −f J_t (it pulls the path shorter).
    pub jac: Vec<f64>,
    /// J̇ q̇ (ntendon): a length's acceleration with q̈ = 0 (zero for fixed tendons).
    pub jdot_qdot: Vec<f64>,
    /// Velocity-product accelerations of the nodes (nnode).
    a_vp: Vec<Motion>,
}

impl TendonData {
    /// Buffers sized for `m`, with the fixed tendons' J (constant) filled in.
    pub fn new(m: &Model) -> Self {
        let mut jac = vec![0.0; m.ntendon * m.nv];
        for t in 0..m.ntendon {
            for w in m.tendon_terms(t) {
                jac[t * m.nv + w.dof] += w.coef;
            }
        }
        TendonData {
            length: vec![0.0; m.ntendon],
            jac,
            jdot_qdot: vec![0.0; m.ntendon],
            a_vp: vec![Motion::ZERO; if m.tendon_path.is_empty() { 0 } else { m.nnode }],
        }
    }

    /// Tendon t's J (nv).
    pub fn jac(&self, t: usize, nv: usize) -> &[f64] {
        &self.jac[t * nv..(t + 1) * nv]
    }

    /// Tendon t's rate J_t · q̇ (a fixed tendon's over its terms).
    pub fn rate(&self, m: &Model, t: usize, qvel: &[f64]) -> f64 {
        match m.tendon_terms(t) {
            [] => self.jac(t, m.nv).iter().zip(qvel).map(|(j, v)| j * v).sum(),
            terms => Wrap::rate(terms, qvel),
        }
    }

    /// tau += f J_t: the joint forces of a force f along tendon t (a fixed tendon's on its terms).
    pub fn apply(&self, m: &Model, t: usize, f: f64, tau: &mut [f64]) {
        match m.tendon_terms(t) {
            [] => {
                for (x, j) in tau.iter_mut().zip(self.jac(t, m.nv)) {
                    *x += j * f;
                }
            }
            terms => {
                for w in terms {
                    tau[w.dof] += w.coef * f;
                }
            }
        }
    }
}

/// Stage 2's tendons: [`compute`], skipped where no tendon acts on the motion (a model whose
/// tendons are there to be read, as gymnasium's humanoid's, pays nothing for them).
pub fn evaluate(m: &Model, kin: &KinData, qpos: &[f64], ten: &mut TendonData) {
    if m.tendons_act {
        compute(m, kin, qpos, ten);
    }
}

/// The tendons of (qpos, qvel) with its kinematics `kin` into `ten`: every length, and a spatial
/// tendon's J and J̇ q̇ (a fixed tendon's are constant).
pub fn compute(m: &Model, kin: &KinData, qpos: &[f64], ten: &mut TendonData) {
    let nv = m.nv;
    if !m.tendon_path.is_empty() {
        velocity_products(m, kin, &mut ten.a_vp);
    }
    for t in 0..m.ntendon {
        let terms = m.tendon_terms(t);
        if terms.is_empty() {
            let row = &mut ten.jac[t * nv..(t + 1) * nv];
            row.fill(0.0);
            (ten.length[t], ten.jdot_qdot[t]) = spatial(m, kin, &ten.a_vp, m.tendon_path(t), row);
        } else {
            ten.length[t] = Wrap::length(terms, qpos);
        }
    }
}

/// A point of a tendon's path: its node and its position relative to `kin.origin`.
#[derive(Clone, Copy)]
struct Anchor {
    node: usize,
    r: DVec3,
}

/// Length and J̇ q̇ of a spatial tendon with path `path`, its J added into `row`.
fn spatial(m: &Model, kin: &KinData, a_vp: &[Motion], path: &[PathPoint], row: &mut [f64]) -> (f64, f64) {
    let site = |s: usize| {
        let b = m.site_body[s];
        Anchor { node: m.body_node[b], r: kin.xpos[b] + kin.xmat[b] * m.site_pos[s] - kin.origin }
    };
    let (mut length, mut jdot, mut divisor) = (0.0, 0.0, 1.0);
    let mut k = 0;
    while k + 1 < path.len() {
        let (a, next) = match (path[k], path[k + 1]) {
            (PathPoint::Pulley(d), _) => {
                divisor = d;
                k += 1;
                continue;
            }
            (_, PathPoint::Pulley(_)) => {
                k += 1;
                continue;
            }
            (PathPoint::Site(s), next) => (site(s), next),
            // the compiler puts a site before every geom
            (PathPoint::Geom { .. }, _) => unreachable!("a spatial tendon's geom follows a site"),
        };
        let mut add = |from: Anchor, to: Anchor| {
            let (l, jd) = segment(m, kin, a_vp, from, to, divisor, row);
            length += l;
            jdot += jd;
        };
        match next {
            PathPoint::Site(s) => {
                add(a, site(s));
                k += 1;
            }
            PathPoint::Geom { geom, side } => {
                // the compiler puts a site after every geom
                let PathPoint::Site(s) = path[k + 2] else { unreachable!("a spatial tendon's geom precedes a site") };
                let b = site(s);
                let node = m.body_node[m.geom_body[geom]];
                let side = side.map(|s| site(s).r + kin.origin);
                match wrap(m, kin, geom, a.r + kin.origin, b.r + kin.origin, side) {
                    Some((p0, p1, arc)) => {
                        add(a, Anchor { node, r: p0 - kin.origin });
                        add(Anchor { node, r: p1 - kin.origin }, b);
                        length += arc / divisor;
                    }
                    None => add(a, b),
                }
                k += 2;
            }
            PathPoint::Pulley(_) => unreachable!("handled above"),
        }
    }
    (length, jdot)
}

/// Length and J̇ q̇ of the straight segment `a` → `b` counted over `divisor`, its J added into
/// `row`: J = u · (J_b − J_a) / divisor with u the unit direction, and d/dt (u · Δv) = u · Δa +
/// |Δv − u (u · Δv)|² / ℓ.
fn segment(m: &Model, kin: &KinData, a_vp: &[Motion], a: Anchor, b: Anchor, divisor: f64, row: &mut [f64]) -> (f64, f64) {
    let d = b.r - a.r;
    let l = d.length();
    if l < MIN_VAL {
        return (l / divisor, 0.0);
    }
    let u = d / l;
    add_point_jacobian(m, kin, b, u / divisor, row);
    add_point_jacobian(m, kin, a, -u / divisor, row);
    let dv = point_vel(kin, b.node, b.r) - point_vel(kin, a.node, a.r);
    let da = point_accel(kin, a_vp, DVec3::ZERO, b.node, b.r) - point_accel(kin, a_vp, DVec3::ZERO, a.node, a.r);
    let across = dv - u * u.dot(dv);
    (l / divisor, (u.dot(da) + across.length_squared() / l) / divisor)
}

/// row += J_pᵀ dir: the joint forces of the force `dir` at point `p`, carried to the root.
fn add_point_jacobian(m: &Model, kin: &KinData, p: Anchor, dir: DVec3, row: &mut [f64]) {
    add_joint_forces(m, kin, p.node, &Force::at_point(p.r, dir), row);
}

/// MuJoCo's smallest value (`mjMINVAL`).
const MIN_VAL: f64 = 1e-15;

/// The wrap of the path x0 → x1 (world) around sphere or cylinder `geom`, on the side of `side`
/// when given: the tangent points (world) and the length between them over the surface, or None
/// when the straight line clears the geom (MuJoCo's `mju_wrap` as of 3.x; MuJoCo 4 picks the
/// side of a side site by another rule, which docs/mjcf.md describes). The problem is posed in a plane:
/// a sphere's through its centre and both points, a cylinder's across its axis, where the wrap
/// is around a circle; a cylinder's path then climbs along the axis in proportion to length.
pub fn wrap(m: &Model, kin: &KinData, geom: usize, x0: DVec3, x1: DVec3, side: Option<DVec3>) -> Option<(DVec3, DVec3, f64)> {
    let (rot, centre) = geom_pose(m, kin, geom);
    let rad = m.geom_size[geom][0];
    let local = |x: DVec3| rot.transpose() * (x - centre);
    let (p0, p1) = (local(x0), local(x1));
    if p0.length() < MIN_VAL || p1.length() < MIN_VAL {
        return None;
    }
    let sphere = m.geom_type[geom] == GeomType::Sphere;
    let (axis0, axis1) = if sphere { sphere_plane(p0, p1) } else { (DVec3::X, DVec3::Y) };
    let flat = |p: DVec3| DVec2::new(p.dot(axis0), p.dot(axis1));
    let (d0, d1) = (flat(p0), flat(p1));
    // the side site: within the geom, the path touches the surface from inside; else it goes
    // round the side the site's direction in the plane points to
    let side = side.map(local);
    let (t0, t1, mut arc) = match side {
        Some(s) if s.length() < rad => wrap_inside(d0, d1, rad).map(|t| (t, t, 0.0))?,
        _ => wrap_circle(d0, d1, side.map(|s| flat(s).normalize() * rad), rad)?,
    };
    let lift = |t: DVec2| axis0 * t.x + axis1 * t.y;
    let (mut w0, mut w1) = (lift(t0), lift(t1));
    if !sphere {
        // along the axis in proportion to the length travelled in the plane
        let l0 = (p0.truncate() - w0.truncate()).length();
        let l1 = (p1.truncate() - w1.truncate()).length();
        let total = l0 + arc + l1;
        w0.z = p0.z + (p1.z - p0.z) * l0 / total;
        w1.z = p0.z + (p1.z - p0.z) * (l0 + arc) / total;
        arc = arc.hypot(w1.z - w0.z);
    }
    Some((rot * w0 + centre, rot * w1 + centre, arc))
}

/// The plane of a sphere wrap: axis 0 along p0, axis 1 in the plane of p0, p1 and the centre (any
/// plane through p0 when they are collinear).
fn sphere_plane(p0: DVec3, p1: DVec3) -> (DVec3, DVec3) {
    let axis0 = p0.normalize();
    let mut normal = p0.cross(p1);
    if normal.length() < MIN_VAL {
        // MuJoCo's choice: the axis of p0's largest component zeroed in (1, 1, 1)
        let a = axis0.abs();
        let i = if a.y > a.x && a.y > a.z { 1 } else if a.z > a.x && a.z > a.y { 2 } else { 0 };
        let mut other = DVec3::ONE;
        other[i] = 0.0;
        normal = axis0.cross(other);
    }
    let normal = normal.normalize();
    (axis0, normal.cross(axis0).normalize())
}

/// Whether the 2-D segments p1–p2 and p3–p4 cross.
fn segments_cross(p1: DVec2, p2: DVec2, p3: DVec2, p4: DVec2) -> bool {
    let det = (p4.y - p3.y) * (p2.x - p1.x) - (p4.x - p3.x) * (p2.y - p1.y);
    if det.abs() < MIN_VAL {
        return false;
    }
    let a = ((p4.x - p3.x) * (p1.y - p3.y) - (p4.y - p3.y) * (p1.x - p3.x)) / det;
    let b = ((p2.x - p1.x) * (p1.y - p3.y) - (p2.y - p1.y) * (p1.x - p3.x)) / det;
    (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)
}

/// Length of the arc of radius `rad` from p0 to p1 (on the circle), the long way round when the
/// turn's sense disagrees with the solution `ind`.
fn arc_length(p0: DVec2, p1: DVec2, ind: usize, rad: f64) -> f64 {
    let mut angle = p0.normalize().dot(p1.normalize()).clamp(-1.0, 1.0).acos();
    let cross = p0.y * p1.x - p0.x * p1.y;
    if (cross > 0.0 && ind == 1) || (cross < 0.0 && ind == 0) {
        angle = std::f64::consts::TAU - angle;
    }
    rad * angle
}

/// The wrap of d0 → d1 around the circle of radius `rad` at the origin: tangent points and arc
/// length, of the two tangent solutions the one nearer the side point `sd` (else the shorter),
/// or None when the segment clears the circle (or passes on the side point's side of it).
fn wrap_circle(d0: DVec2, d1: DVec2, sd: Option<DVec2>, rad: f64) -> Option<(DVec2, DVec2, f64)> {
    let (sq0, sq1, sqr) = (d0.length_squared(), d1.length_squared(), rad * rad);
    if sq0 < sqr || sq1 < sqr || rad < MIN_VAL {
        return None;
    }
    let dif = d1 - d0;
    let dd = dif.length_squared();
    if dd < MIN_VAL {
        return None;
    }
    // no wrap where the segment clears the circle, unless the side point is across it
    let nearest = d0 + dif * (-dif.dot(d0) / dd).clamp(0.0, 1.0);
    if nearest.length_squared() > sqr && sd.is_none_or(|sd| sd.dot(nearest) >= 0.0) {
        return None;
    }
    let (s0, s1) = ((sq0 - sqr).sqrt(), (sq1 - sqr).sqrt());
    let solution = |sgn: f64| {
        (
            DVec2::new(d0.x * sqr + sgn * rad * d0.y * s0, d0.y * sqr - sgn * rad * d0.x * s0) / sq0,
            DVec2::new(d1.x * sqr - sgn * rad * d1.y * s1, d1.y * sqr + sgn * rad * d1.x * s1) / sq1,
        )
    };
    let sols = [solution(1.0), solution(-1.0)];
    let good = sols.map(|(a, b)| {
        if segments_cross(d0, a, d1, b) {
            -10000.0
        } else {
            match sd {
                Some(sd) => (a + b).normalize().dot(sd),
                None => -(a - b).length_squared(),
            }
        }
    });
    let i = if good[0] > good[1] { 0 } else { 1 };
    let (a, b) = sols[i];
    if segments_cross(d0, a, d1, b) {
        return None;
    }
    Some((a, b, arc_length(a, b, i, rad)))
}

/// The wrap of d0 → d1 inside the circle of radius `rad` (a side site within it): the one point
/// on the circle where the path touches it, found by Newton's method on
/// asin(A z) + asin(B z) − 2 asin(z) + G = 0; None when the segment crosses the circle.
fn wrap_inside(d0: DVec2, d1: DVec2, rad: f64) -> Option<DVec2> {
    let (len0, len1) = (d0.length(), d1.length());
    let dif = d1 - d0;
    let dd = dif.length_squared();
    if len0 <= rad || len1 <= rad || rad < MIN_VAL || len0 < MIN_VAL || len1 < MIN_VAL {
        return None;
    }
    if dd > MIN_VAL {
        let a = -dif.dot(d0) / dd;
        if a > 0.0 && a < 1.0 && (d0 + dif * a).length() <= rad {
            return None;
        }
    }
    // where the solve fails: the midpoint's direction
    let fallback = (0.5 * (d0 + d1)).normalize() * rad;
    let (ca, cb) = (rad / len0, rad / len1);
    let cos_g = (len0 * len0 + len1 * len1 - dd) / (2.0 * len0 * len1);
    if cos_g < -1.0 + MIN_VAL {
        return None;
    }
    if cos_g > 1.0 - MIN_VAL {
        return Some(fallback);
    }
    let g = cos_g.acos();
    let asin = |x: f64| x.clamp(-1.0, 1.0).asin();
    let f_of = |z: f64| asin(ca * z) + asin(cb * z) - 2.0 * asin(z) + g;
    let mut z = 1.0 - 1e-7;
    let mut f = f_of(z);
    if f > 0.0 {
        return Some(fallback);
    }
    let mut iter = 0;
    while iter < 20 && f.abs() > 1e-6 {
        let root = |c: f64| (1.0 - z * z * c * c).sqrt().max(MIN_VAL);
        let df = ca / root(ca) + cb / root(cb) - 2.0 / root(1.0);
        if df > -MIN_VAL {
            return Some(fallback);
        }
        let z1 = z - f / df;
        if z1 > z {
            return Some(fallback);
        }
        z = z1;
        f = f_of(z);
        if f > 1e-6 {
            return Some(fallback);
        }
        iter += 1;
    }
    if iter >= 20 {
        return Some(fallback);
    }
    let (vec, ang) = if d0.x * d1.y - d0.y * d1.x > 0.0 { (d0, asin(z) - asin(ca * z)) } else { (d1, asin(z) - asin(cb * z)) };
    let v = vec.normalize();
    Some(DVec2::new(ang.cos() * v.x - ang.sin() * v.y, ang.sin() * v.x + ang.cos() * v.y) * rad)
}

/// The world pose of geom g (axes, centre) from its body's.
pub fn geom_pose(m: &Model, kin: &KinData, g: usize) -> (DMat3, DVec3) {
    let b = m.geom_body[g];
    (kin.xmat[b] * m.geom_mat[g], kin.xpos[b] + kin.xmat[b] * m.geom_pos[g])
}
