//! The broadphase's configuration-independent bounds: `Model::dof_arm` bounds the speed of every
//! geom point and `Model::body_reach` every geom point's distance from its subtree's root, at
//! random states of random trees; plane groups and the pairs' gaps reject no pair that touches.
#![allow(clippy::needless_range_loop)] // the shared helpers index as the math does

mod common;

use common::{random_state, random_tree_mjcf, Rng};
use sinew::math::{DVec3, Motion};
use sinew::model::{GeomType, PairTest};
use sinew::data::Data;
use sinew::collision::{collide, penetrations, reach_again, CollisionData};
use sinew::dynamics::kinematics::{forward, KinData};
use sinew::Model;
use sinew::state::WorldState;

/// Random trees, as generated, with every slide joint made a hinge (all arms finite), and with
/// every slide limited (arms finite while the slides keep within their ranges).
fn trees() -> Vec<Model> {
    let mut models = vec![];
    for seed in 0..40 {
        let xml = random_tree_mjcf(2 + (seed % 7) as usize, seed % 2 == 0, seed);
        models.push(Model::from_mjcf(&xml).unwrap());
        models.push(Model::from_mjcf(&xml.replace("type=\"slide\"", "type=\"hinge\"")).unwrap());
        if xml.contains("type=\"slide\"") {
            models.push(Model::from_mjcf(&xml.replace("type=\"slide\"", "type=\"slide\" limited=\"true\" range=\"-20.5 20.5\"")).unwrap());
        }
    }
    models
}

/// Points of geom g's bounding sphere in world: its centre and six points on the sphere.
fn sphere_points(m: &Model, kin: &KinData, g: usize, r: &mut Rng) -> Vec<DVec3> {
    let b = m.geom_body[g];
    let c = kin.xpos[b] + kin.xmat[b] * m.geom_pos[g];
    let mut pts = vec![c];
    for _ in 0..6 {
        let d = DVec3::new(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)).normalize();
        pts.push(c + d * m.geom_rbound[g]);
    }
    pts
}

/// Points of geom g's surface in its own frame: a box's corners, a capsule's or cylinder's rim
/// and caps, an ellipsoid's surface (random directions).
fn surface_points(m: &Model, g: usize, r: &mut Rng) -> Vec<DVec3> {
    let s = m.geom_size[g];
    let unit = |r: &mut Rng| DVec3::new(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)).normalize();
    (0..32)
        .map(|k| match m.geom_type[g] {
            GeomType::Box => DVec3::new(s[0], s[1], s[2]) * DVec3::new([1.0, -1.0][k % 2], [1.0, -1.0][k / 2 % 2], [1.0, -1.0][k / 4 % 2]),
            GeomType::Capsule => DVec3::new(0.0, 0.0, s[1] * [1.0, -1.0][k % 2]) + unit(r) * s[0],
            GeomType::Cylinder => {
                let t = r.uniform(0.0, std::f64::consts::TAU);
                DVec3::new(s[0] * t.cos(), s[0] * t.sin(), s[1] * [1.0, -1.0][k % 2])
            }
            GeomType::Ellipsoid => unit(r) * DVec3::new(s[0], s[1], s[2]),
            _ => unit(r) * m.geom_rbound[g],
        })
        .collect()
}

/// The broadphase's box of a geom (`Model::geom_body_box` turned into world axes, |R| h about the
/// geom's centre) holds every point of the geom, at random states of random trees, and is smaller
/// than the bounding sphere's box along every world axis for many of them.
#[test]
fn body_boxes_hold_their_geoms() {
    let mut r = Rng(11);
    let (mut checked, mut tighter) = (0, 0);
    for m in trees() {
        let mut kin = KinData::new(&m);
        for _ in 0..5 {
            let (q, v) = random_state(&m, &mut r);
            forward(&m, &q, &v, &mut kin);
            for g in (0..m.ngeom).filter(|&g| m.geom_type[g] != GeomType::Plane) {
                let Some(half) = m.geom_body_box[g] else {
                    assert_eq!(m.geom_type[g], GeomType::Sphere, "{}: geom {g} has no box", m.name);
                    continue;
                };
                let rot = kin.xmat[m.geom_body[g]];
                let world = rot.x_axis.abs() * half.x + rot.y_axis.abs() * half.y + rot.z_axis.abs() * half.z;
                let centre = rot * m.geom_pos[g];
                for p in surface_points(&m, g, &mut r) {
                    let d = (rot * (m.geom_pos[g] + m.geom_mat[g] * p) - centre).abs();
                    assert!(d.cmple(world + 1e-12).all(), "{}: geom {g}'s point {d} outside its box {world}", m.name);
                }
                checked += 1;
                tighter += (world.min_element() < 0.99 * m.geom_rbound[g]) as usize;
            }
        }
    }
    assert!(checked > 500 && tighter > checked / 3, "{checked} geoms checked, {tighter} with a box tighter than their sphere's");
}

#[test]
fn dof_arms_bound_every_geom_point_speed_and_body_reach_its_distance() {
    let mut r = Rng(7);
    let (mut finite, mut tightest, mut ranged, mut beyond) = (0, 0.0_f64, 0, 0);
    for m in trees() {
        finite += m.dof_arm.iter().all(|c| c.is_finite()) as usize;
        ranged += !m.arm_slides.is_empty() as usize;
        let mut kin = KinData::new(&m);
        for _ in 0..10 {
            let (mut q, _) = random_state(&m, &mut r);
            // a limited slide carried past its range: the arms no longer bound the motion
            if let Some(&(qa, most)) = m.arm_slides.first() {
                let inside = q[qa];
                q[qa] = m.qpos0[qa] + 1.001 * most;
                assert!(!m.arms_hold(&q), "{}: a slide beyond its range", m.name);
                beyond += 1;
                q[qa] = inside;
            }
            // random_state moves a slide at most 1 from qpos0: within what the arms allow for
            assert!(m.arms_hold(&q), "{}: a state within the ranges", m.name);
            // a unit velocity of one dof at a time moves no point faster than that dof's arm
            for k in 0..m.nv {
                let mut v = vec![0.0; m.nv];
                v[k] = 1.0;
                forward(&m, &q, &v, &mut kin);
                for g in (0..m.ngeom).filter(|&g| m.geom_type[g] != GeomType::Plane && m.geom_body[g] != 0) {
                    let b = m.geom_body[g];
                    let node = &kin.v[m.body_node[b]];
                    for p in sphere_points(&m, &kin, g, &mut r) {
                        let u = node.point_velocity(p - kin.origin).length();
                        assert!(u <= m.dof_arm[k] * (1.0 + 1e-12) + 1e-12, "{}: dof {k} moves geom {g} at {u} > {}", m.name, m.dof_arm[k]);
                        tightest = tightest.max(u / m.dof_arm[k]);
                        // every ancestor's reach covers the point
                        let mut a = b;
                        while a != 0 {
                            let d = (p - kin.xpos[a]).length();
                            assert!(d <= m.body_reach[a] * (1.0 + 1e-12) + 1e-12, "{}: body {a} reach {} < {d}", m.name, m.body_reach[a]);
                            a = m.body_parent[a];
                        }
                    }
                }
            }
        }
    }
    assert!(finite >= 20 + ranged && ranged >= 10 && beyond >= 100, "{finite} trees with bounded arms, {ranged} by their slides' ranges, {beyond} states beyond");
    // the bounds are reached closely somewhere (a geom at full stretch from its joint)
    assert!(tightest > 0.9, "no point comes near its bound: {tightest}");
}

/// A free body over a floor with a hinged and a ball-jointed limb, joints at the body origins so
/// that the stretched limb reaches exactly as far as the group's sphere. Its geoms collide with the
/// floor only (contype/conaffinity as gymnasium's ant): a self-collision pair would need every
/// geom posed anyway, and the model would have no plane group.
const WALKER: &str = r#"<mujoco><default><geom contype="1" conaffinity="0"/></default>
<worldbody><geom name="floor" type="plane" size="5 5 .1" contype="0" conaffinity="1"/>
<body name="torso" pos="0 0 1"><freejoint/><geom type="capsule" fromto="0 0 -.3 0 0 .3" size=".1"/>
  <body pos="0 0 -.3"><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -.4" size=".05"/>
    <body pos="0 0 -.4"><joint type="ball"/><geom type="sphere" size=".08" pos="0 0 -.1"/></body></body>
  <body pos="0 0 .3"><joint type="hinge" axis="1 0 0"/><geom type="box" size=".05 .05 .1" pos="0 0 .1"/></body>
</body></worldbody></mujoco>"#;

#[test]
fn plane_groups_reject_no_touching_pair() {
    let m = Model::from_mjcf(WALKER).unwrap();
    assert_eq!(m.plane_groups.len(), 1, "one floor, one free body");
    // the same model with every pair tested by its narrowphase
    let mut brute = m.clone();
    brute.plane_groups.clear();
    for p in &mut brute.collision_pairs {
        p.test = PairTest::Always;
    }
    brute.gap_pairs.clear();
    brute.pairs_without_gap = (0..brute.collision_pairs.len()).collect();
    let (mut kin, mut cd, mut cd_brute) = (KinData::new(&m), CollisionData::new(&m), CollisionData::new(&brute));
    let mut r = Rng(3);
    let mut touching = 0;
    for _ in 0..20000 {
        let (mut q, v) = random_state(&m, &mut r);
        // heights from well clear of the floor to sunk into it
        q[2] = r.uniform(-0.2, 1.2);
        forward(&m, &q, &v, &mut kin);
        penetrations(&m, &kin, &mut cd);
        penetrations(&brute, &kin, &mut cd_brute);
        assert_eq!(cd.contacts, cd_brute.contacts, "q = {q:?}");
        touching += !cd.contacts.is_empty() as usize;
    }
    assert!(touching > 2000 && touching < 19000, "{touching} of 20000 states touch: not a test of both sides");
}

/// Steps a random walk through the configurations of `m` (velocities drifting by up to `drift`
/// per step, clamped to ±`v_max`, positions following over 0.01 s, a jump to a random state every
/// `jump` steps) and checks at every step that detection keeping the pairs' gaps finds the
/// contacts of detection from scratch, and so does the second look with end velocities
/// ([`reach_again`]). Returns (gap skips, axis skips, detections with contacts, detections).
fn walk(m: &Model, r: &mut Rng, steps: usize, jump: usize, drift: f64, v_max: f64) -> (usize, usize, usize, usize) {
    let (mut skipped, mut kept_skips, mut touching) = (0, 0, 0);
    let mut data = Data::new(m);
    let mut cd = CollisionData::new(m);
    let mut node_v = vec![Motion::ZERO; m.nnode];
    let (mut q, mut v) = random_state(m, r);
    let ctrl = vec![0.0; m.nu];
    for step in 0..steps {
        if step % jump == jump - 1 {
            (q, v) = random_state(m, r);
        }
        let mut time = 0.0;
        let s = WorldState { time: &mut time, qpos: &mut q, qvel: &mut v, ctrl: &ctrl, act: &mut [] };
        sinew::step::forward(m, &mut data, &s);
        collide(m, &data.dynamics, &s, &mut cd);
        let mut fresh = CollisionData::new(m);
        collide(m, &data.dynamics, &s, &mut fresh);
        assert_eq!(cd.contacts, fresh.contacts, "{} step {step}", m.name);
        skipped += cd.gap_skips;
        kept_skips += cd.kept_skips();
        // constraint forces changed the velocities: the pairs the new ones can close
        let v_end: Vec<f64> = v.iter().map(|x| x * r.uniform(0.0, 30.0)).collect();
        reach_again(m, &data.dynamics.kin, &v_end, &mut node_v, &mut cd);
        reach_again(m, &data.dynamics.kin, &v_end, &mut node_v, &mut fresh);
        assert_eq!(cd.contacts, fresh.contacts, "{} step {step}, end velocities", m.name);
        touching += !fresh.contacts.is_empty() as usize;
        for x in v.iter_mut() {
            *x = (*x + r.uniform(-drift, drift)).clamp(-v_max, v_max);
        }
        let dq = v.iter().map(|x| 0.01 * x).collect::<Vec<_>>();
        sinew::integrate::integrate_pos(m, &mut q, &dq, 1.0);
    }
    (skipped, kept_skips, touching, steps)
}

/// Along random walks through random trees (no floor: every plane group is apart, so the gaps are
/// in use), detection with the pairs' gaps finds what detection from scratch finds.
#[test]
fn gaps_reject_no_pair_that_touches() {
    let mut r = Rng(11);
    let (mut skipped, mut touching, mut tested) = (0, 0, 0);
    for m in trees().iter().filter(|m| !m.gap_pairs.is_empty()) {
        let (s, _, t, n) = walk(m, &mut r, 600, 100, 0.5, 3.0);
        (skipped, touching, tested) = (skipped + s, touching + t, tested + n);
    }
    // both sides: pairs spared by their gaps, and states with contacts
    assert!(skipped > 2 * tested, "{skipped} gap skips in {tested} detections");
    assert!(touching > tested / 20 && touching < tested, "{touching} of {tested} detections touch");
}

/// Random trees whose boxes are meshes, rocks of 60 vertices (hulls of over a hundred edges,
/// whose tests begin with GJK) or pebbles of 10 (tested by separating axes), with a floor or
/// without: what a pair's last test found apart (GJK's axis, a separating face) settles many
/// tests, and detection keeping them finds exactly the contacts of detection from scratch.
#[test]
fn kept_separations_change_no_contact() {
    let mut r = Rng(3);
    let mut mesh = |name: &str, n: usize| {
        let vertex: Vec<String> = (0..n)
            .map(|_| {
                let d = DVec3::new(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)).normalize();
                format!("{} {} {}", 0.12 * d.x, 0.08 * d.y, 0.1 * d.z)
            })
            .collect();
        format!("<mesh name=\"{name}\" vertex=\"{}\"/>", vertex.join(" "))
    };
    let asset = format!("<asset>{}{}</asset>", mesh("rock", 60), mesh("pebble", 10));
    let (mut settled, mut touching, mut tested) = (0, 0, 0);
    for seed in 0..24 {
        let mut xml = random_tree_mjcf(3 + (seed % 5) as usize, true, seed).replace("type=\"slide\"", "type=\"hinge\"");
        // the boxes rocks and pebbles in turn
        let mut k = 0;
        while let Some(at) = xml.find("type=\"box\" size=\"") {
            let end = at + 18 + xml[at + 18..].find('"').unwrap();
            xml.replace_range(at..=end, ["type=\"mesh\" mesh=\"rock\"", "type=\"mesh\" mesh=\"pebble\""][k % 2]);
            k += 1;
        }
        xml = xml.replace("<worldbody>", &format!("{asset}<worldbody>"));
        if seed % 2 == 0 {
            xml = xml.replace("<worldbody>", "<worldbody><geom type=\"plane\" size=\"5 5 .1\" pos=\"0 0 -.6\"/>");
        }
        let m = Model::from_mjcf(&xml).unwrap();
        let (_, s, t, n) = walk(&m, &mut r, 400, 100, 0.5, 3.0);
        (settled, touching, tested) = (settled + s, touching + t, tested + n);
    }
    assert!(settled > tested / 4, "{settled} tests settled by kept separations in {tested} detections");
    assert!(touching > tested / 20 && touching < tested, "{touching} of {tested} detections touch");
}

/// A pebble (a hull of 10 vertices, tested by separating axes), and then a box, on an arm
/// swinging back and forth past four others, near and touching: the face that held a pair apart
/// settles its next tests, and the contacts are those of detection from scratch.
#[test]
fn a_kept_separating_face_changes_no_contact() {
    let pebble = "0.05 0 0  -0.05 0 0  0 0.04 0  0 -0.04 0  0 0 0.045  0 0 -0.045  0.03 0.02 0.03  -0.03 -0.02 0.03  0.03 -0.02 -0.03  -0.03 0.02 -0.03";
    for shape in [r#"type="mesh" mesh="pebble""#, r#"type="box" size=".04 .03 .035""#] {
        let others: String = (0..4)
            .map(|k| {
                let t = 0.6 + 0.5 * k as f64;
                format!("<geom {shape} pos=\"{} {} {}\" euler=\"{} 20 40\"/>", 0.3 * t.cos(), 0.3 * t.sin(), 0.04 * k as f64 - 0.06, 30 * k)
            })
            .collect();
        let m = Model::from_mjcf(&format!(
            r#"<mujoco><asset><mesh name="pebble" vertex="{pebble}"/></asset><worldbody>{others}
            <body><joint type="hinge" axis="0 0 1"/><geom {shape} pos=".3 0 0" euler="10 50 0"/></body>
            </worldbody></mujoco>"#
        ))
        .unwrap();
        let mut r = Rng(9);
        let (_, settled, touching, tested) = walk(&m, &mut r, 6000, 6000, 0.3, 2.0);
        assert!(settled > tested / 20, "{shape}: {settled} tests settled by kept faces in {tested} detections");
        assert!(touching > tested / 50 && touching < tested / 2, "{shape}: {touching} of {tested} detections touch");
    }
}

/// A hinged arm carrying two fingers on limited slides, swept past three obstacles: the hinge's
/// arm (`Model::dof_arm`) counts the fingers by their ranges, so the gaps spare pairs (with an
/// unlimited slide it is unbounded and spares none); the walk's jumps carry the fingers past
/// their ranges too, where the arms bound nothing and every pair is tested: either way detection
/// finds the contacts of detection from scratch.
#[test]
fn fingers_on_limited_slides_keep_the_gaps_in_use() {
    let m = Model::from_mjcf(
        r#"<mujoco><worldbody>
        <geom type="box" size=".05 .05 .05" pos=".3 .25 0"/><geom type="box" size=".04 .04 .04" pos="-.25 .2 .05"/>
        <geom type="capsule" fromto=".1 -.4 0 .1 -.2 0" size=".02"/>
        <body><joint type="hinge" axis="0 0 1"/><geom type="box" size=".15 .02 .02" pos=".15 0 0"/>
          <body pos=".3 0 0"><joint type="slide" axis="0 1 0" range="-.6 .6"/><geom type="box" size=".01 .03 .01" pos="0 .03 0"/></body>
          <body pos=".3 0 0"><joint type="slide" axis="0 -1 0" range="-.6 .6"/><geom type="box" size=".01 .03 .01" pos="0 -.03 0"/></body>
        </body></worldbody></mujoco>"#,
    )
    .unwrap();
    assert_eq!(m.arm_slides.len(), 2);
    assert!(m.dof_arm.iter().all(|a| a.is_finite()), "{:?}", m.dof_arm);
    let mut r = Rng(17);
    let (skipped, _, touching, tested) = walk(&m, &mut r, 20000, 400, 0.2, 2.0);
    assert!(skipped > tested / 2, "{skipped} gap skips in {tested} detections");
    assert!(touching > tested / 50 && touching < tested / 2, "{touching} of {tested} detections touch");
}

/// An arm folding slowly onto its base: while its pairs are far apart the whole tree's travel
/// settles them at once, and detection still finds every contact as they close. (The base is
/// welded to the world, so, as in MuJoCo, only `<exclude>` keeps the upper arm from colliding
/// with it at their joint.)
#[test]
fn gaps_settled_at_once_reject_no_pair_that_touches() {
    let m = Model::from_mjcf(
        r#"<mujoco><worldbody><body name="base"><geom type="capsule" fromto="0 0 0 0 0 .3" size=".05"/>
        <body name="upper" pos="0 0 .3"><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".04"/>
          <body pos=".3 0 0"><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".04"/>
            <body pos=".3 0 0"><joint type="ball"/><geom type="box" size=".05 .05 .05" pos=".1 0 0"/></body>
          </body></body></body></worldbody>
        <contact><exclude body1="base" body2="upper"/></contact></mujoco>"#,
    )
    .unwrap();
    assert_eq!(m.gap_pairs.len(), 3);
    let mut r = Rng(5);
    let (skipped, _, touching, tested) = walk(&m, &mut r, 20000, 2000, 0.05, 1.0);
    assert!(skipped > tested, "{skipped} gap skips in {tested} detections");
    assert!(touching > tested / 50 && touching < tested / 2, "{touching} of {tested} detections touch");
}

/// A floor and 24 free bodies of every shape, packed into a small box: more pairs than the
/// sweep's threshold (`collision::SWEEP_PAIRS`).
fn crowd(seed: u64) -> String {
    let mut r = Rng(seed);
    let shapes = ["type='sphere' size='0.07'", "type='capsule' size='0.04 0.1'", "type='box' size='0.05 0.08 0.06'", "type='cylinder' size='0.05 0.07'"];
    let bodies: String = (0..24)
        .map(|i| format!("<body pos='{}'><freejoint/><geom {}/></body>", r.vec3(0.4), shapes[i % 4]))
        .collect();
    format!("<mujoco><worldbody><geom type='plane' size='5 5 0.1'/>{bodies}</worldbody></mujoco>")
}

/// The sweep of the geoms' boxes (many trees, many pairs) finds every contact that testing every
/// pair finds: detection after a step and the step itself (its detection with the step's reach
/// and its second look with the end velocities) give the same contacts and the same motion.
#[test]
fn the_sweep_finds_the_contacts_of_testing_every_pair() {
    let m = Model::from_mjcf(&crowd(5)).unwrap();
    assert!(m.collision_pairs.len() >= 256 && !m.sweep_geoms.is_empty(), "{} pairs", m.collision_pairs.len());
    // the same model, every pair tested on its bounds without the sweep
    let mut brute = m.clone();
    brute.pairs_unswept = (0..brute.collision_pairs.len()).collect();
    brute.sweep_geoms.clear();
    let mut r = Rng(11);
    let (mut touching, mut states) = (0, 0);
    for _ in 0..300 {
        let (mut q, mut v) = random_state(&m, &mut r);
        for b in 0..24 {
            // packed within 0.8 m, some bodies down at the floor
            q[7 * b..7 * b + 3].copy_from_slice(&[r.uniform(-0.4, 0.4), r.uniform(-0.4, 0.4), r.uniform(-0.05, 0.6)]);
        }
        v.iter_mut().for_each(|x| *x *= 0.5);
        let (mut qb, mut vb) = (q.clone(), v.clone());
        let (mut sim, mut sim_brute) = (sinew::State::new(&m), sinew::State::new(&brute));
        for _ in 0..3 {
            (sim.qpos, sim.qvel) = (q.clone(), v.clone());
            (sim_brute.qpos, sim_brute.qvel) = (qb.clone(), vb.clone());
            sim.step(&m);
            sim_brute.step(&brute);
            assert_eq!(sim.data.coll.contacts, sim_brute.data.coll.contacts);
            assert_eq!((&sim.qpos, &sim.qvel), (&sim_brute.qpos, &sim_brute.qvel));
            touching += !sim.data.coll.contacts.is_empty() as usize;
            states += 1;
            (q, v, qb, vb) = (sim.qpos.clone(), sim.qvel.clone(), sim_brute.qpos.clone(), sim_brute.qvel.clone());
        }
        let mut kin = KinData::new(&m);
        forward(&m, &q, &v, &mut kin);
        let (mut cd, mut cd_brute) = (CollisionData::new(&m), CollisionData::new(&brute));
        penetrations(&m, &kin, &mut cd);
        penetrations(&brute, &kin, &mut cd_brute);
        assert_eq!(cd.contacts, cd_brute.contacts);
    }
    assert!(touching > states / 2, "{touching} of {states} steps touch: not a test of the sweep");
}

/// Two feet 2 cm apart (boxes, cylinders, capsules) on the legs of a robot falling at 20 m/s with
/// no floor (so every pair is tested through the gaps' path): each foot's own reach is 8 cm, but
/// the feet move alike, and detection bounds the pair by their relative motion: no (speculative)
/// contact between them at any step, as in MuJoCo. A kick that swings the legs together brings
/// the contacts back.
#[test]
fn a_falling_robots_feet_keep_their_distance() {
    for foot in [r#"type="box" size=".05 .05 .02""#, r#"type="cylinder" size=".05 .02""#, r#"type="capsule" size=".02 .03" quat="1 1 0 0""#] {
        let m = Model::from_mjcf(&format!(
            r#"<mujoco><option timestep=".004"/><worldbody><body name="pelvis"><freejoint/><geom type="box" size=".1 .1 .05"/>
            <body pos="0 .06 0"><joint type="hinge" axis="1 0 0"/><geom {foot} pos="0 0 -.3"/></body>
            <body pos="0 -.06 0"><joint type="hinge" axis="1 0 0"/><geom {foot} pos="0 0 -.3"/></body>
            </body></worldbody></mujoco>"#
        ))
        .unwrap();
        let mut s = sinew::State::new(&m);
        s.qvel[2] = -20.0;
        for step in 0..50 {
            s.step(&m);
            assert!(s.data.coll.contacts.is_empty(), "{foot} step {step}: {:?}", s.data.coll.contacts);
        }
        // the legs swing toward each other at 5 rad/s (0.3 m arms: 1.5 m/s, 6 mm a step each)
        (s.qvel[6], s.qvel[7]) = (-5.0, 5.0);
        let touched = (0..20).any(|_| {
            s.step(&m);
            !s.data.coll.contacts.is_empty()
        });
        assert!(touched, "{foot}: the swinging feet found no contact");
    }
}
