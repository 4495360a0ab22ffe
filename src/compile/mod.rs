//! [`ModelSpec`] → [`Model`]: body inertias from geoms or `<inertial>`, the node tree, address
//! tables, actuator resolution and a solvability check at the reference configuration.

use glam::{DMat3, DVec3};

mod actuators;
mod assets;
mod fluid;
mod inertia;
mod pairs;
pub mod params;
mod sensors;
mod tendons;
mod visual;

use actuators::{actuators, muscle_acc0, servo_damping};
use inertia::{body_inertias, fluid_box, inertia_axes, spring_dampers};
use sensors::sensors;
use tendons::tendons;
use crate::model::{ActuatorDyn, Connect, EqRef, GapPair, GeomType, Keyframe, Model, Options, PairTest, PlaneGroup, Transmission, Wrap, WORLD};
use crate::error::{Error, Result};
use crate::math::{SpatialInertia, Xform};
use crate::mjcf::{include, BodySpec, JointSpec, JointType, ModelSpec};
use crate::dynamics::DynamicsData;

impl Model {
    /// Parses and compiles MJCF text (its includes relative to the working directory).
    pub fn from_mjcf(xml: &str) -> Result<Model> {
        Model::from_expanded(&include::expand(xml, None)?)
    }

    /// Reads, parses and compiles an MJCF file.
    pub fn from_mjcf_file(path: &std::path::Path) -> Result<Model> {
        Ok(Model::load_file(path)?.0)
    }

    /// Reads and compiles a URDF file ([`crate::urdf`]).
    pub fn from_urdf_file(path: &std::path::Path, opts: &crate::urdf::UrdfOptions) -> Result<Model> {
        let text = crate::mjcf::read_file(path)?;
        Ok(Model::load_urdf(&text, path, opts)?.0)
    }

    fn load_urdf(text: &str, path: &std::path::Path, opts: &crate::urdf::UrdfOptions) -> Result<(Model, String)> {
        let mjcf = crate::urdf::to_mjcf(text, Some(path), opts).map_err(|e| e.in_file(path))?;
        Ok((Model::from_mjcf_in(&mjcf, path)?, mjcf))
    }

    /// Compiles MJCF text as if it were the file at `path` (includes and assets found from its
    /// directory; errors naming it).
    pub fn from_mjcf_in(xml: &str, path: &std::path::Path) -> Result<Model> {
        let expanded = include::expand(xml, Some(path)).map_err(|e| e.in_file(path))?;
        Model::from_expanded(&expanded).map_err(|e| e.in_file(path))
    }

    /// Reads, parses and compiles an MJCF file (or a URDF file, whose root is `<robot>`, with
    /// default [`crate::urdf::UrdfOptions`]); also gives its text with every include expanded
    /// (the model's whole description as MJCF, which needs no other file but its assets).
    pub fn load_file(path: &std::path::Path) -> Result<(Model, String)> {
        let text = crate::mjcf::read_file(path)?;
        if roxmltree::Document::parse(&text).is_ok_and(|d| d.root_element().has_tag_name("robot")) {
            return Model::load_urdf(&text, path, &crate::urdf::UrdfOptions::default());
        }
        let expanded = include::expand(&text, Some(path)).map_err(|e| e.in_file(path))?;
        let m = Model::from_expanded(&expanded).map_err(|e| e.in_file(path))?;
        Ok((m, expanded.text))
    }

    /// Parses and compiles expanded text, an error naming the file and line it comes from.
    fn from_expanded(x: &include::Expanded) -> Result<Model> {
        crate::mjcf::parse(&x.text).and_then(|spec| compile(spec, x)).map_err(|e| x.locate(e))
    }
}

/// `ModelSpec` → `Model`; asset files are found from `dir`.
fn compile(mut spec: ModelSpec, x: &include::Expanded) -> Result<Model> {
    let meshes = assets::load_meshes(&spec, x)?;
    let hfields = assets::load_hfields(&spec, x)?;
    assets::fit_geoms(&mut spec, &meshes, &hfields)?;
    let inertia = body_inertias(&spec);
    let mut m = Model {
        name: spec.name.clone(),
        opt: Options {
            timestep: spec.option.timestep,
            gravity: spec.option.gravity,
            integrator: spec.option.integrator,
            contact: spec.option.contact,
            limit: spec.option.limit,
            restitution: spec.restitution.unwrap_or(0.0),
            density: spec.option.density,
            viscosity: spec.option.viscosity,
            wind: spec.option.wind,
            implicit_actuators: spec.option.implicit,
            ..Options::default()
        },
        nu: spec.actuators.len(),
        nbody: spec.bodies.len(),
        body_name: spec.bodies.iter().map(|b| b.name.clone()).collect(),
        body_parent: spec.bodies.iter().map(|b| b.parent).collect(),
        body_mocap: spec.bodies.iter().map(|b| b.mocap).collect(),
        body_gravcomp: spec.bodies.iter().enumerate().filter(|(_, b)| b.gravcomp != 0.0).map(|(i, b)| (i, b.gravcomp)).collect(),
        body_pos: spec.bodies.iter().map(|b| b.pos).collect(),
        body_quat: spec.bodies.iter().map(|b| b.quat).collect(),
        body_mass: inertia.iter().map(|i| i.mass).collect(),
        body_ipos: inertia.iter().map(|i| i.com).collect(),
        body_inertia: inertia.iter().map(|i| i.ic).collect(),
        body_iaxes: spec.bodies.iter().zip(&inertia).map(|(b, i)| inertia_axes(&spec, b, i)).collect(),
        body_node: vec![WORLD; spec.bodies.len()],
        body_offset: vec![Xform::IDENTITY; spec.bodies.len()],
        warnings: spec.warnings.clone(),
        ..Model::default()
    };
    m.body_fluid_box = inertia.iter().zip(&m.body_iaxes).map(|(i, &axes)| fluid_box(i, axes)).collect();
    joints_and_nodes(&mut m, &spec)?;
    moving_planes_as_boxes(&mut m, &mut spec);
    params::node_inertias(&mut m, &inertia);
    geoms_and_sites(&mut m, &spec, &meshes, &hfields);
    m.opt.max_contacts = spec.option.nconmax.unwrap_or_else(|| crate::model::default_max_contacts(m.ngeom));
    m.meshes = std::sync::Arc::new(meshes);
    m.hfields = std::sync::Arc::new(hfields);
    m.keys = keyframes(&m, &spec)?;
    tendons(&mut m, &spec)?;
    equalities(&mut m, &spec)?;
    actuators(&mut m, &spec)?;
    sensors(&mut m, &spec)?;
    m.tendons_act = (0..m.ntendon).any(|t| {
        m.tendon_stiffness[t] != 0.0 || m.tendon_damping[t] != 0.0 || m.tendon_limited[t] || m.tendon_frictionloss[t] > 0.0
    }) || m.actuator_trn.iter().any(|t| matches!(t, Transmission::Tendon(_)));
    for (b1, b2) in &spec.contact_excludes {
        let find = |n: &str| {
            m.body_id(n).ok_or_else(|| Error::Compile(format!("<exclude> names unknown body '{n}'")))
        };
        let (i, j) = (find(b1)?, find(b2)?);
        m.exclude_pairs.push((i.min(j), i.max(j)));
    }
    let explicit = pairs::explicit_pairs(&mut m, &spec)?;
    for i in 0..m.ngeom {
        for j in i + 1..m.ngeom {
            // an explicit pair replaces the geoms' own, as in MuJoCo
            if pairs::can_collide(&m, i, j) && !explicit.iter().any(|p| (p.g1, p.g2) == (i, j)) {
                m.collision_pairs.push(pairs::geom_pair(&m, i, j));
            }
        }
    }
    m.collision_pairs.extend(explicit);
    m.collision_pairs.sort_by_key(|p| (p.g1, p.g2));
    m.body_reach = body_reaches(&m, false);
    m.arm_slides = arm_slides(&m);
    m.dof_arm = dof_arms(&m);
    pair_lists(&mut m);
    // the forward dynamics at qpos0, as MuJoCo's mj_setConst runs it
    let mut dy = DynamicsData::new(&m);
    crate::dynamics::forward(&m, &mut dy, &m.qpos0, &vec![0.0; m.nv], &vec![0.0; m.nu], &vec![0.0; m.na]);
    if pairs::leave_out_overlapping(&mut m, &dy.kin) {
        pair_lists(&mut m);
    }
    check_solvable(&m, &dy)?;
    muscle_acc0(&mut m, &dy);
    servo_damping(&mut m, &dy);
    spring_dampers(&mut m, &spec, &dy.kin);
    m.connects = connects(&m, &spec, &dy.kin)?;
    let mut order: Vec<(usize, EqRef)> = spec.equalities.iter().enumerate().map(|(e, s)| (s.order, EqRef::Coupling(e))).collect();
    order.extend(spec.connects.iter().enumerate().map(|(c, s)| (s.order, EqRef::Connect(c))));
    order.sort_unstable_by_key(|&(o, _)| o);
    m.eq_order = order.into_iter().map(|(_, e)| e).collect();
    m.motion_plane = motion_plane(&m, &dy.kin);
    m.vis = visual::compile(&spec, |n| m.body_id(n))?;
    Ok(m)
}

/// What the collision pairs give: their kept slots, the sweep lists, the plane groups and the
/// gaps.
fn pair_lists(m: &mut Model) {
    pairs::kept_slots(m);
    sweep_lists(m);
    m.plane_groups = plane_groups(m);
    m.gaps_within_trees = m.gap_pairs.iter().all(|gp| gp.ancestor != 0);
    m.gap_arms = gap_arms(m);
}

/// Joints, dofs and nodes in MuJoCo's order: each body's joints share a node while their dofs
/// fit in six; a body without joints rides on its parent's node.
fn joints_and_nodes(m: &mut Model, spec: &ModelSpec) -> Result<()> {
    for (b, body) in spec.bodies.iter().enumerate().skip(1) {
        let parent = body.parent;
        // this body's frame relative to the parent body's node frame
        let offset = Xform::from_pose_quat(body.quat, body.pos);
        let from_parent_node = m.body_offset[parent].then(&offset);
        if body.joints.is_empty() {
            m.body_node[b] = m.body_node[parent];
            m.body_offset[b] = from_parent_node;
            continue;
        }
        let first_node = m.node_parent.len();
        for j in &body.joints {
            if j.kind == JointType::Free && (parent != 0 || m.body_node[parent] != WORLD || body.joints.len() != 1) {
                return Err(Error::model("joint", None, j.line, "a free joint must be the only joint of a child of the world"));
            }
            let id = m.jnt_type.len();
            add_joint(m, j, b, body);
            // a body's joints share a node while their dofs fit in six (a free joint is alone)
            let n = m.node_parent.len();
            let joins = n > first_node && m.node_nv[n - 1] + j.kind.nv() <= 6;
            if joins {
                m.node_jntnum[n - 1] += 1;
                m.node_nv[n - 1] += j.kind.nv();
            } else {
                m.node_parent.push(if n == first_node { m.body_node[parent] } else { n - 1 });
                m.node_jntadr.push(id);
                m.node_jntnum.push(1);
                m.node_dofadr.push(m.nv);
                m.node_nv.push(j.kind.nv());
                m.node_xtree.push(if n == first_node { from_parent_node } else { Xform::IDENTITY });
                m.node_inertia.push(SpatialInertia::ZERO);
            }
            m.jnt_node.push(m.node_parent.len() - 1);
            m.nv += j.kind.nv();
        }
        m.body_node[b] = m.node_parent.len() - 1;
    }
    m.njnt = m.jnt_type.len();
    m.nnode = m.node_parent.len();
    (m.node_tree, m.node_end) = node_trees(&m.node_parent);
    Ok(())
}

/// Joint `j` of body `b`: its fields, its qpos0 and spring reference, and its dofs' damping and
/// armature (qpos addresses grow here; dof addresses with the node in [`joints_and_nodes`]).
fn add_joint(m: &mut Model, j: &JointSpec, b: usize, body: &BodySpec) {
    let id = m.jnt_type.len();
    m.jnt_name.push(j.name.clone());
    m.jnt_type.push(j.kind);
    m.jnt_body.push(b);
    m.jnt_qposadr.push(m.nq);
    m.jnt_dofadr.push(m.nv);
    m.jnt_pos.push(j.pos);
    m.jnt_axis.push(j.axis);
    m.jnt_range.push(j.range);
    m.jnt_limited.push(j.limited);
    m.jnt_margin.push(j.margin);
    m.jnt_stiffness.push(j.stiffness);
    if let Some(range) = j.actfrcrange {
        m.dof_actfrcrange.push((m.nv, range));
    }
    match j.kind {
        JointType::Free => {
            let (p, q) = (body.pos, body.quat);
            m.qpos0.extend([p.x, p.y, p.z, q.w, q.x, q.y, q.z]);
        }
        JointType::Ball => m.qpos0.extend([1.0, 0.0, 0.0, 0.0]),
        _ => m.qpos0.push(j.reference),
    }
    match j.kind {
        JointType::Hinge | JointType::Slide => m.qpos_spring.push(j.springref),
        // ball and free springs rest at the reference configuration, as in MuJoCo
        _ => m.qpos_spring.extend_from_slice(&m.qpos0[m.nq..]),
    }
    m.nq += j.kind.nq();
    for _ in 0..j.kind.nv() {
        m.dof_damping.push(j.damping);
        m.dof_armature.push(j.armature);
        m.dof_frictionloss.push(j.frictionloss);
        m.dof_jnt.push(id);
    }
}

/// A plane on a body that moves becomes a slab under it, with a warning: a box as wide as the
/// plane's half-sizes (100 m where they are 0: infinite), as thick as its narrower side (at most
/// 1 m), its top face the plane, massless (sinew collides planes that do not move; MuJoCo's
/// moving plane is an infinite half-space). Planes on bodies fixed to the world stay planes.
fn moving_planes_as_boxes(m: &mut Model, spec: &mut ModelSpec) {
    for (b, body) in spec.bodies.iter_mut().enumerate() {
        if m.body_node[b] == WORLD {
            continue;
        }
        for g in body.geoms.iter_mut().filter(|g| g.kind == GeomType::Plane) {
            let half = [g.size[0], g.size[1]].map(|s| if s > 0.0 { s } else { 100.0 });
            let thick = half[0].min(half[1]).min(1.0);
            g.kind = GeomType::Box;
            g.size = [half[0], half[1], thick];
            g.pos -= g.quat * DVec3::new(0.0, 0.0, thick);
            g.mass = Some(0.0);
            m.warnings.push(format!(
                "<geom> '{}' at line {}: a plane on a moving body is collided as a {}×{}×{} m slab under it (sinew's planes do not move)",
                g.name, g.line, 2.0 * half[0], 2.0 * half[1], thick
            ));
        }
    }
}

/// Geoms and sites in body order.
fn geoms_and_sites(m: &mut Model, spec: &ModelSpec, meshes: &[crate::geometry::Mesh], hfields: &[crate::geometry::HField]) {
    for (b, body) in spec.bodies.iter().enumerate() {
        for g in &body.geoms {
            let mesh = g.mesh.as_ref().and_then(|n| meshes.iter().position(|x| &x.name == n));
            let hfield = g.hfield.as_ref().and_then(|n| hfields.iter().position(|x| &x.name == n));
            m.geom_mesh.push(mesh);
            m.geom_hfield.push(hfield);
            m.geom_name.push(g.name.clone());
            m.geom_type.push(g.kind);
            m.geom_body.push(b);
            m.geom_size.push(g.size);
            m.geom_pos.push(g.pos);
            m.geom_quat.push(g.quat);
            m.geom_mat.push(DMat3::from_quat(g.quat));
            let rbound = match (mesh, hfield) {
                (Some(k), _) => meshes[k].rbound,
                (_, Some(k)) => hfields[k].rbound(),
                _ => pairs::geom_rbound(g.kind, g.size),
            };
            m.geom_rbound.push(rbound);
            let half = match (mesh, hfield) {
                (Some(k), _) => meshes[k].vert.iter().fold(DVec3::ZERO, |h, v| h.max(v.abs())),
                (_, Some(_)) => DVec3::splat(rbound),
                _ => pairs::geom_half_extents(g.kind, g.size),
            };
            let smaller = half.min_element() < rbound;
            m.geom_body_box.push(smaller.then(|| crate::math::turned_box(m.geom_mat[m.geom_mat.len() - 1], half)));
            m.geom_friction.push(g.friction);
            m.geom_contype.push(g.contype);
            m.geom_conaffinity.push(g.conaffinity);
            m.geom_condim.push(g.condim);
            m.geom_priority.push(g.priority);
            m.geom_margin.push(g.margin);
            m.geom_fluid.push(g.fluid.map(|coef| fluid::geom_fluid(g.kind, g.size, coef)));
        }
        for s in &body.sites {
            m.site_name.push(s.name.clone());
            m.site_body.push(b);
            m.site_pos.push(s.pos);
            m.site_mat.push(DMat3::from_quat(s.quat));
            m.site_type.push(s.kind);
            m.site_size.push(s.size);
        }
    }
    m.ngeom = m.geom_type.len();
    m.body_fluid_ellipsoid = (0..m.nbody).map(|b| (0..m.ngeom).any(|g| m.geom_body[g] == b && m.geom_fluid[g].is_some())).collect();
}

/// The connect equalities, body2's point where body1's anchor is at qpos0 (`kin`: there).
fn connects(m: &Model, spec: &ModelSpec, kin: &crate::dynamics::kinematics::KinData) -> Result<Vec<Connect>> {
    spec.connects
        .iter()
        .map(|c| {
            let element = if c.weld { "weld" } else { "connect" };
            let find = |name: &str, attr: &str| m.body_id(name).ok_or_else(|| Error::model(element, Some(attr), c.line, format!("unknown body '{name}'")));
            let b1 = find(&c.body1, "body1")?;
            let b2 = c.body2.as_deref().map_or(Ok(0), |n| find(n, "body2"))?;
            if b1 == b2 {
                return Err(Error::model(element, Some("body2"), c.line, "an equality joins two different bodies"));
            }
            let world = kin.xpos[b1] + kin.xmat[b1] * c.anchor;
            let anchor2 = kin.xmat[b2].transpose() * (world - kin.xpos[b2]);
            let rel = c.weld.then(|| glam::DQuat::from_mat3(&(kin.xmat[b2].transpose() * kin.xmat[b1])).normalize());
            Ok(Connect { name: c.name.clone(), body: [b1, b2], anchor: [c.anchor, anchor2], rel, active: c.active })
        })
        .collect()
}

/// The keyframes, each array checked against the model's sizes and the state's bounds.
fn keyframes(m: &Model, spec: &ModelSpec) -> Result<Vec<Keyframe>> {
    let nu = spec.actuators.len();
    let na = spec.actuators.iter().filter(|a| a.dynamics != ActuatorDyn::None).count();
    let mocap: Vec<usize> = (0..m.nbody).filter(|&b| m.body_mocap[b]).collect();
    spec.keys
        .iter()
        .map(|k| {
            let array = |given: &Option<Vec<f64>>, attr: &str, n: usize, default: &[f64]| match given {
                Some(v) if v.len() != n => Err(Error::model("key", Some(attr), k.line, format!("expected {n} numbers, got {}", v.len()))),
                Some(v) => Ok(v.clone()),
                None => Ok(default.to_vec()),
            };
            Ok(Keyframe {
                name: k.name.clone(),
                time: k.time,
                qpos: array(&k.qpos, "qpos", m.nq, &m.qpos0)?,
                qvel: array(&k.qvel, "qvel", m.nv, &vec![0.0; m.nv])?,
                ctrl: array(&k.ctrl, "ctrl", nu, &vec![0.0; nu])?,
                act: array(&k.act, "act", na, &vec![0.0; na])?,
                mpos: array(&k.mpos, "mpos", 3 * mocap.len(), &mocap.iter().flat_map(|&b| m.body_pos[b].to_array()).collect::<Vec<_>>())?,
                mquat: array(&k.mquat, "mquat", 4 * mocap.len(), &mocap.iter().flat_map(|&b| { let q = m.body_quat[b]; [q.w, q.x, q.y, q.z] }).collect::<Vec<_>>())?,
            })
        })
        .collect()
}

/// The joint and tendon equalities, each side as its terms and its value at qpos0.
fn equalities(m: &mut Model, spec: &ModelSpec) -> Result<()> {
    m.eq_adr.push(0);
    for e in &spec.equalities {
        let (element, attrs) = if e.tendon { ("tendon", ["tendon1", "tendon2"]) } else { ("joint", ["joint1", "joint2"]) };
        let mut refs = [0.0; 2];
        for (side, name) in [Some(&e.obj1), e.obj2.as_ref()].into_iter().enumerate() {
            if let Some(name) = name {
                let terms: Vec<Wrap> = if e.tendon {
                    let t = m.tendon_name.iter().position(|n| n == name);
                    let t = t.ok_or_else(|| Error::model(element, Some(attrs[side]), e.line, format!("unknown tendon '{name}'")))?;
                    if m.tendon_terms(t).is_empty() {
                        return Err(Error::model(element, Some(attrs[side]), e.line, "tendon equalities couple fixed tendons only"));
                    }
                    m.tendon_terms(t).to_vec()
                } else {
                    let j = m.jnt_name.iter().position(|n| n == name);
                    let j = j.ok_or_else(|| Error::model(element, Some(attrs[side]), e.line, format!("unknown joint '{name}'")))?;
                    if !matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide) {
                        return Err(Error::model(element, Some(attrs[side]), e.line, "joint equalities couple hinge and slide joints only"));
                    }
                    vec![Wrap { dof: m.jnt_dofadr[j], qpos: m.jnt_qposadr[j], coef: 1.0 }]
                };
                refs[side] = Wrap::length(&terms, &m.qpos0);
                m.eq_wrap.extend(terms);
            }
            m.eq_adr.push(m.eq_wrap.len());
        }
        // an equality row's K holds the trees of its dofs, two at most
        let mut trees: Vec<usize> = m.eq_wrap[m.eq_adr[2 * m.neq]..].iter().map(|w| m.node_tree[m.jnt_node[m.dof_jnt[w.dof]]]).collect();
        trees.sort_unstable();
        trees.dedup();
        if trees.len() > 2 {
            return Err(Error::model(element, None, e.line, "an equality may couple the joints of two kinematic trees at most"));
        }
        m.eq_name.push(e.name.clone());
        m.eq_ref.push(refs);
        m.eq_polycoef.push(e.polycoef);
        m.eq_active.push(e.active);
        m.neq += 1;
    }
    Ok(())
}

/// [`Model::geom_first_pair`], [`Model::sweep_geoms`] and [`Model::pairs_unswept`] from the pairs
/// (in (g1, g2) order).
fn sweep_lists(m: &mut Model) {
    let mut first = vec![m.collision_pairs.len(); m.ngeom + 1];
    let mut swept = vec![false; m.ngeom];
    m.pairs_unswept.clear();
    for (k, p) in m.collision_pairs.iter().enumerate().rev() {
        first[p.g1] = k;
        if p.test == PairTest::Spheres {
            (swept[p.g1], swept[p.g2]) = (true, true);
        } else {
            m.pairs_unswept.push(k);
        }
    }
    m.pairs_unswept.reverse();
    // a geom without pairs of its own starts where the next one does
    for g in (0..m.ngeom).rev() {
        first[g] = first[g].min(first[g + 1]);
    }
    m.geom_first_pair = first;
    m.pair_partner = m.collision_pairs.iter().map(|p| p.g2 as u32).collect();
    m.pair_bits.clear();
    m.pair_rank.clear();
    if m.ngeom <= crate::model::PAIR_BITS_GEOMS {
        m.pair_bits.resize((m.ngeom * m.ngeom).div_ceil(64), 0);
        for p in &m.collision_pairs {
            let bit = p.g1 * m.ngeom + p.g2;
            m.pair_bits[bit / 64] |= 1 << (bit % 64);
        }
        // a pair's index is its bit's rank when no two pairs share their geoms
        if m.collision_pairs.windows(2).all(|w| (w[0].g1, w[0].g2) < (w[1].g1, w[1].g2)) {
            let mut before = 0;
            for &word in &m.pair_bits {
                m.pair_rank.push(before);
                before += word.count_ones();
            }
        }
    }
    m.sweep_geoms = (0..m.ngeom).filter(|&g| swept[g]).collect();
}

/// How far a body's joints can carry its origin from where its parent puts it: 2|anchor| per
/// hinge or ball joint (a turn about the anchor), unboundedly by a slide, unless `ranged` and the
/// slide is limited ([`Model::arm_slides`]); joints `after` the given one only, when it is Some.
fn joint_travel(m: &Model, b: usize, after: Option<usize>, ranged: bool) -> f64 {
    (0..m.njnt)
        .filter(|&j| m.jnt_body[j] == b && after.is_none_or(|a| j > a))
        .map(|j| match m.jnt_type[j] {
            JointType::Slide => m.arm_slides.iter().find(|s| ranged && s.0 == m.jnt_qposadr[j]).map_or(f64::INFINITY, |s| s.1),
            _ => 2.0 * m.jnt_pos[j].length(),
        })
        .sum()
}

/// [`Model::arm_slides`]: each limited slide's farther range end from qpos0, and a hundredth of
/// its range to spare (a finger pressed against its limit sits a round-off beyond it).
fn arm_slides(m: &Model) -> Vec<(usize, f64)> {
    (0..m.njnt)
        .filter(|&j| m.jnt_type[j] == JointType::Slide && m.jnt_limited[j])
        .map(|j| {
            let (qa, [lo, hi]) = (m.jnt_qposadr[j], m.jnt_range[j]);
            (qa, (lo - m.qpos0[qa]).abs().max((hi - m.qpos0[qa]).abs()) + 0.01 * (hi - lo).abs())
        })
        .collect()
}

/// [`Model::node_tree`] and [`Model::node_end`] from the parents (numbered parents first).
fn node_trees(parent: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = parent.len();
    let mut tree = vec![0; n];
    for i in 0..n {
        tree[i] = if parent[i] == WORLD { i } else { tree[parent[i]] };
    }
    // a subtree ends where its root's end is: children come after their parents
    let mut end: Vec<usize> = (1..=n).collect();
    for i in (0..n).rev() {
        if parent[i] != WORLD {
            end[parent[i]] = end[parent[i]].max(end[i]);
        }
    }
    (tree, end)
}

/// [`Model::body_reach`], bottom-up: a body's own geoms, and each child's reach from where the
/// child's origin can be (a limited slide's by its range when `ranged`: `Model::dof_arm`'s).
fn body_reaches(m: &Model, ranged: bool) -> Vec<f64> {
    let mut reach = vec![0.0_f64; m.nbody];
    for g in (0..m.ngeom).filter(|&g| m.geom_type[g] != GeomType::Plane) {
        let b = m.geom_body[g];
        reach[b] = reach[b].max(m.geom_pos[g].length() + m.geom_rbound[g]);
    }
    // children come after their parents
    for c in (1..m.nbody).rev() {
        let p = m.body_parent[c];
        reach[p] = reach[p].max(m.body_pos[c].length() + joint_travel(m, c, None, ranged) + reach[c]);
    }
    reach
}

/// [`Model::dof_arm`]: a rotational joint's arm is its anchor's distance to the body's origin
/// once the joints that follow it in the body have moved that, plus the body's reach.
fn dof_arms(m: &Model) -> Vec<f64> {
    let mut arm = vec![0.0; m.nv];
    let reach = body_reaches(m, true);
    for j in 0..m.njnt {
        let b = m.jnt_body[j];
        let rotational = m.jnt_pos[j].length() + joint_travel(m, b, Some(j), true) + reach[b];
        let da = m.jnt_dofadr[j];
        match m.jnt_type[j] {
            JointType::Slide => arm[da] = 1.0,
            JointType::Hinge => arm[da] = rotational,
            JointType::Ball => arm[da..da + 3].fill(rotational),
            // linear velocity of the body's origin, then angular velocity about it
            JointType::Free => {
                arm[da..da + 3].fill(1.0);
                arm[da + 3..da + 6].fill(reach[b]);
            }
        }
    }
    arm
}

/// [`Model::gap_arms`]: None when one of the joints is a ball or free joint.
fn gap_arms(m: &Model) -> Option<Vec<(usize, f64)>> {
    let counted = (0..m.njnt).filter(|&j| !(m.gaps_within_trees && m.body_parent[m.jnt_body[j]] == 0));
    counted
        .map(|j| matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide).then(|| (m.jnt_qposadr[j], m.dof_arm[m.jnt_dofadr[j]])))
        .collect()
}

/// Groups each pair of a world plane and a geom under a child of the world with a bounded reach
/// into that child's [`PlaneGroup`], lists the pairs that are not ([`Model::gap_pairs`] and
/// [`Model::pairs_without_gap`]), and returns the groups.
fn plane_groups(m: &mut Model) -> Vec<PlaneGroup> {
    // the child of the world whose subtree holds each pair's geom, for pairs a group could hold
    let root_of = |p: &crate::model::GeomPair| {
        let PairTest::Plane { plane, other, .. } = p.test else { return None };
        let mut root = m.geom_body[other];
        while m.body_parent[root] != 0 {
            root = m.body_parent[root];
        }
        (m.geom_body[plane] == 0 && m.body_reach[root].is_finite()).then_some((plane, root))
    };
    let roots: Vec<Option<(usize, usize)>> = m.collision_pairs.iter().map(root_of).collect();
    let mut groups: Vec<PlaneGroup> = vec![];
    m.gap_pairs.clear();
    m.pairs_without_gap.clear();
    for (k, root) in roots.into_iter().enumerate() {
        let Some((plane, body)) = root else {
            let p = &m.collision_pairs[k];
            if p.test != PairTest::Spheres {
                m.pairs_without_gap.push(k);
                continue;
            }
            let bodies = [m.geom_body[p.g1], m.geom_body[p.g2]];
            // parents have lower indices
            let [mut a, mut b] = bodies;
            while a != b {
                if a > b {
                    a = m.body_parent[a];
                } else {
                    b = m.body_parent[b];
                }
            }
            m.gap_pairs.push(GapPair { pair: k, bodies, ancestor: a, margin: p.margin });
            continue;
        };
        let p = &mut m.collision_pairs[k];
        let radius = m.body_reach[body] + p.margin;
        let g = match groups.iter().position(|g| (g.plane, g.body) == (plane, body)) {
            Some(g) => {
                groups[g].radius = groups[g].radius.max(radius);
                g
            }
            None => {
                groups.push(PlaneGroup { plane, body, radius });
                groups.len() - 1
            }
        };
        if let PairTest::Plane { group, .. } = &mut p.test {
            *group = Some(g);
        }
    }
    groups
}

/// The normal every hinge axis is parallel to and every slide axis perpendicular to, in world at
/// the reference configuration (rotations about that normal keep it so), or None.
/// `kin`: the kinematics at qpos0.
fn motion_plane(m: &Model, kin: &crate::dynamics::kinematics::KinData) -> Option<DVec3> {
    // a hinge's or slide's axis in world: its subspace column's rotation or translation part
    let world_axis = |j: usize| {
        let n = m.jnt_node[j];
        let s = kin.s[n][m.jnt_dofadr[j] - m.node_dofadr[n]];
        if m.jnt_type[j] == JointType::Hinge { s.ang } else { s.lin }.normalize()
    };
    let normal = world_axis((0..m.njnt).find(|&j| m.jnt_type[j] == JointType::Hinge)?);
    let planar = (0..m.njnt).all(|j| match m.jnt_type[j] {
        JointType::Hinge => world_axis(j).cross(normal).length() < 1e-9,
        JointType::Slide => world_axis(j).dot(normal).abs() < 1e-9,
        _ => false,
    });
    planar.then_some(normal)
}

/// Every joint must move some mass: the articulated inertia seen by each dof at the reference
/// configuration must be positive definite, or the forward dynamics would divide by zero
/// (`data`: the forward dynamics at qpos0).
fn check_solvable(m: &Model, dy: &DynamicsData) -> Result<()> {
    if let Some(n) = dy.aba.singular_node {
        let j0 = m.node_jntadr[n];
        let names: Vec<String> = m.jnt_name[j0..j0 + m.node_jntnum[n]].iter().map(|s| format!("'{s}'")).collect();
        let (noun, verb) = if names.len() == 1 { ("joint", "moves") } else { ("joints", "move") };
        return Err(Error::Compile(format!(
            "{noun} {} (body '{}') {verb} no mass or inertia: give its body geoms or an <inertial>",
            names.join(", "),
            m.body_name[m.jnt_body[j0]]
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::model::Model;
    use glam::DVec3;

    /// A chain whose second body is turned 90° about x, its hinge about its own z: every hinge
    /// still turns about world y, so the model is planar; turned the other way it is not.
    #[test]
    fn motion_plane_reads_joint_axes_in_world() {
        let chain = |axis2: &str| {
            format!(
                r#"<mujoco><worldbody><body><joint type="hinge" axis="0 1 0"/><geom size="0.1"/>
                <body pos="0.5 0 0" euler="90 0 0"><joint type="hinge" axis="{axis2}"/><geom size="0.1"/>
                </body></body></worldbody></mujoco>"#
            )
        };
        let planar = Model::from_mjcf(&chain("0 0 1")).unwrap();
        let normal = planar.motion_plane.expect("both hinges turn about world y");
        assert!(normal.cross(DVec3::Y).length() < 1e-12, "{normal}");
        assert!(Model::from_mjcf(&chain("0 1 0")).unwrap().motion_plane.is_none());
    }
}
