//! The collision data a model carries, decided once at compile time: bounding radii, MuJoCo's
//! configuration-independent pair filters, and each pair's broadphase test (run by
//! `collision`).

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mjcf::ModelSpec;
use crate::model::{GeomPair, GeomType, Model, PairFriction, PairTest, WORLD};

/// Bounding radius of a geom about its centre (planes: infinite).
pub fn geom_rbound(kind: GeomType, s: [f64; 3]) -> f64 {
    match kind {
        GeomType::Plane => f64::INFINITY,
        GeomType::Sphere => s[0],
        GeomType::Capsule | GeomType::Cylinder => s[0] + s[1],
        // a mesh's comes from its vertices (compile/mod.rs); its inertia box's is a stand-in
        GeomType::Box | GeomType::Mesh | GeomType::Hfield => DVec3::from_array(s).length(),
        GeomType::Ellipsoid => s[0].max(s[1]).max(s[2]),
    }
}

/// Half extents of a geom's box along its own axes (planes: infinite).
pub fn geom_half_extents(kind: GeomType, s: [f64; 3]) -> DVec3 {
    match kind {
        GeomType::Sphere => DVec3::splat(s[0]),
        GeomType::Capsule => DVec3::new(s[0], s[0], s[0] + s[1]),
        GeomType::Cylinder => DVec3::new(s[0], s[0], s[1]),
        GeomType::Box | GeomType::Ellipsoid => DVec3::from_array(s),
        GeomType::Plane | GeomType::Mesh | GeomType::Hfield => DVec3::splat(geom_rbound(kind, s)),
    }
}

/// Whether geoms i and j may collide at all (independent of configuration), by MuJoCo's filters
/// (`filterBodyPair`, `canCollide`): never within one weld (bodies joined without a joint, the
/// world and what is welded to it included) nor between a weld and its parent weld (unless that
/// is the world); contype/conaffinity bits; `<exclude>` pairs.
pub fn can_collide(m: &Model, i: usize, j: usize) -> bool {
    let (bi, bj) = (m.geom_body[i], m.geom_body[j]);
    let (wi, wj) = (weld(m, bi), weld(m, bj));
    if wi == wj {
        return false;
    }
    if m.geom_contype[i] & m.geom_conaffinity[j] == 0 && m.geom_contype[j] & m.geom_conaffinity[i] == 0 {
        return false;
    }
    let parent = |w: usize| weld(m, m.body_parent[w]);
    if wi != WORLD_BODY && wj != WORLD_BODY && (wi == parent(wj) || wj == parent(wi)) {
        return false;
    }
    !m.exclude_pairs.contains(&(bi.min(bj), bi.max(bj)))
}

/// The `<contact><pair>`s, each with its own friction and margin, geoms in index order; an
/// unknown geom name or a pair of one geom is an error. A pair given again replaces the earlier
/// one, with a warning (MuJoCo keeps both, and so would find each contact twice).
pub fn explicit_pairs(m: &mut Model, spec: &ModelSpec) -> Result<Vec<GeomPair>> {
    let mut out: Vec<GeomPair> = Vec::new();
    for p in &spec.contact_pairs {
        let id = |n: &str| {
            m.geom_id(n).ok_or_else(|| Error::Compile(format!("<pair> at line {} names unknown geom '{n}'", p.line)))
        };
        let (a, b) = (id(&p.geoms[0])?, id(&p.geoms[1])?);
        let (i, j) = (a.min(b), a.max(b));
        if i == j {
            return Err(Error::Compile(format!("<pair> at line {}: geoms '{}' and '{}' make no pair", p.line, p.geoms[0], p.geoms[1])));
        }
        let mut pair = geom_pair(m, i, j);
        // MuJoCo's five: two sliding, one torsional, two rolling (the first of each pair is used)
        let [slide, _, spin, roll, _] = p.friction;
        (pair.margin, pair.friction) = (p.margin, Some(PairFriction::new(p.condim, [slide, spin, roll])));
        match out.iter().position(|q| (q.g1, q.g2) == (i, j)) {
            Some(k) => {
                m.pair_friction[k] = p.friction;
                m.warnings.push(format!(
                    "<pair> at line {}: geoms '{}' and '{}' are paired again; this pair replaces the earlier one (MuJoCo would keep both and find each contact twice)",
                    p.line, p.geoms[0], p.geoms[1]
                ));
                out[k] = pair;
            }
            None => {
                out.push(pair);
                m.pair_geoms.push((i, j));
                m.pair_friction.push(p.friction);
            }
        }
    }
    Ok(out)
}

/// The world body.
const WORLD_BODY: usize = 0;

/// The body that body b is welded to (MuJoCo's `body_weldid`): itself when a joint moves it,
/// else its parent's weld; the world for the world and what is fixed to it.
fn weld(m: &Model, mut b: usize) -> usize {
    while b != WORLD_BODY && m.body_node[b] == m.body_node[m.body_parent[b]] {
        b = m.body_parent[b];
    }
    b
}

/// Depth beyond which two geoms of one robot overlapping at qpos0 may leave collision (m), a
/// millimetre: parts resting on each other overlap less.
pub const SELF_OVERLAP: f64 = 1e-3;

/// Joint travel (rad, or m of a slide) within which the joints must be able to undo such an
/// overlap at its contact's normal rate for the pair to stay.
pub const UNDO_TRAVEL: f64 = 1.0;

/// The collision pairs (index, deepest distance) whose geoms overlap by more than
/// [`SELF_OVERLAP`] at qpos0 (`kin`: there), whose bodies share an ancestor below the world
/// (parts of one robot), and whose deepest contact no dof can move out within [`UNDO_TRAVEL`]
/// (its normal's rate per unit of the fastest dof times that travel is less than the depth): a
/// finger's hub inside its palm overlaps alike at every angle, and an exact contact there pushes
/// without end (robosuite's G1 three-finger grippers, 1.6 cm at a normal rate of 1e-4 m/rad).
/// Overlaps the joints can undo (a lying humanoid's hand in its hip) stay, and are eased apart.
/// An explicit `<pair>` asks for its contact and stays.
pub fn overlapping_at_qpos0(m: &Model, kin: &crate::dynamics::kinematics::KinData) -> Vec<(usize, f64)> {
    let mut cd = crate::collision::CollisionData::new(m);
    crate::collision::penetrations(m, kin, &mut cd);
    let ancestors = |mut b: usize| {
        let mut up = vec![b];
        while b != 0 {
            b = m.body_parent[b];
            up.push(b);
        }
        up
    };
    let one_robot = |g1: usize, g2: usize| {
        let a = ancestors(m.geom_body[g1]);
        ancestors(m.geom_body[g2]).into_iter().find(|b| a.contains(b)).is_some_and(|b| b != 0)
    };
    let mut found: Vec<(usize, f64)> = Vec::new();
    let stuck = |c: &crate::collision::Contact| {
        let rate = crate::constraint::stabilize::contact_normal_rate(m, kin, c).iter().fold(0.0, |a: f64, r| a.max(r.abs()));
        -c.dist > rate * UNDO_TRAVEL
    };
    for c in &cd.contacts {
        if c.dist >= -SELF_OVERLAP || !one_robot(c.geom1, c.geom2) || !stuck(c) {
            continue;
        }
        let (g1, g2) = (c.geom1.min(c.geom2), c.geom1.max(c.geom2));
        let Some(k) = m.collision_pairs.iter().position(|p| (p.g1, p.g2) == (g1, g2) && p.friction.is_none()) else { continue };
        match found.iter_mut().find(|f| f.0 == k) {
            Some(f) => f.1 = f.1.min(c.dist),
            None => found.push((k, c.dist)),
        }
    }
    found.sort_unstable_by_key(|f| f.0);
    found
}

/// Pairs a warning names at most.
const LISTED: usize = 8;

/// Leaves the pairs [`overlapping_at_qpos0`] finds out of collision, with a warning naming each
/// and its depth; whether there were any (the lists built from the pairs are then stale).
pub fn leave_out_overlapping(m: &mut Model, kin: &crate::dynamics::kinematics::KinData) -> bool {
    let overlapping = overlapping_at_qpos0(m, kin);
    if overlapping.is_empty() {
        return false;
    }
    let name = |g: usize| m.geom_name.get(g).filter(|n| !n.is_empty()).cloned().unwrap_or_else(|| format!("#{g}"));
    let mut list: Vec<String> = overlapping.iter().take(LISTED).map(|&(k, d)| {
        let p = &m.collision_pairs[k];
        format!("{} and {} ({:.1} mm)", name(p.g1), name(p.g2), -d * 1e3)
    }).collect();
    if overlapping.len() > LISTED {
        list.push(format!("{} more", overlapping.len() - LISTED));
    }
    m.warnings.push(format!(
        "geoms of one robot overlap at qpos0: {}; sinew leaves these pairs out of collision (as MoveIt disables the \
         pairs in collision by default), where MuJoCo keeps them as soft contacts: no joint can move these \
         contacts apart, and an exact contact would fling the joints",
        list.join(", ")
    ));
    let pairs = std::mem::take(&mut m.collision_pairs);
    m.collision_pairs = pairs.into_iter().enumerate().filter(|(k, _)| !overlapping.iter().any(|o| o.0 == *k)).map(|(_, p)| p).collect();
    true
}

/// Numbers the pairs that keep what their test found apart ([`GeomPair::kept`]).
pub fn kept_slots(m: &mut Model) {
    let gjk = |t: GeomType| matches!(t, GeomType::Mesh | GeomType::Cylinder | GeomType::Ellipsoid);
    let flat = |t: GeomType| matches!(t, GeomType::Plane | GeomType::Hfield);
    let mut slots = 0;
    for p in &mut m.collision_pairs {
        let (t1, t2) = (m.geom_type[p.g1], m.geom_type[p.g2]);
        let boxes = t1 == GeomType::Box && t2 == GeomType::Box;
        p.kept = (boxes || ((gjk(t1) || gjk(t2)) && !flat(t1) && !flat(t2))).then(|| {
            slots += 1;
            slots - 1
        });
    }
}

/// The broadphase test of geoms i < j, which [`can_collide`].
pub fn geom_pair(m: &Model, i: usize, j: usize) -> GeomPair {
    let margin = m.geom_margin[i].max(m.geom_margin[j]);
    let (ri, rj) = (m.geom_rbound[i], m.geom_rbound[j]);
    let (test, radii) = match (ri.is_finite(), rj.is_finite()) {
        (true, true) => (PairTest::Spheres, ri + rj),
        (false, true) if m.geom_type[i] == GeomType::Plane => (PairTest::Plane { plane: i, other: j, group: None }, rj),
        (true, false) if m.geom_type[j] == GeomType::Plane => (PairTest::Plane { plane: j, other: i, group: None }, ri),
        _ => (PairTest::Always, 0.0),
    };
    let moves = |g: usize| m.body_node[m.geom_body[g]] != WORLD && m.geom_type[g] != GeomType::Plane;
    GeomPair { g1: i, g2: j, test, margin, radii, friction: None, both_move: moves(i) && moves(j), kept: None }
}
