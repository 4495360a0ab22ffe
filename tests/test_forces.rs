//! K built by pushing unit test forces through the ABA quantities (Kokkevis 2004) equals
//! J M⁻¹ Jᵀ from CRBA + Cholesky, on random trees with every joint type and on gymnasium-like
//! rows (contact normals, tangents, two-body contacts and joint limits).
#![allow(clippy::needless_range_loop)] // index loops follow the math's notation

mod common;

use common::{random_state, random_tree_mjcf, Rng};
use sinew::dynamics::crba::{cholesky_solve, crba};
use sinew::math::{DVec3, Motion};
use sinew::model::{GeomType, JointType, Model, PairFriction, WORLD};
use sinew::collision::Contact;
use sinew::constraint::{self, ConstraintData, RowKind};
use sinew::dynamics::{aba, kinematics};
use sinew::integrate;
use sinew::Data;

/// Row j of J: the row's acceleration per unit q̈ of each dof, without velocity terms.
fn jacobian(m: &Model, data: &Data, con: &ConstraintData) -> Vec<Vec<f64>> {
    let kin = &data.dynamics.kin;
    let mut rows = vec![vec![0.0; m.nv]; con.len()];
    for dof in 0..m.nv {
        // spatial accelerations of every node for q̈ = e_dof
        let mut a = vec![Motion::ZERO; m.nnode];
        for i in 0..m.nnode {
            let p = m.node_parent[i];
            let mut ai = if p == WORLD { Motion::ZERO } else { a[p] };
            for r in 0..m.node_nv[i] {
                if m.node_dofadr[i] + r == dof {
                    ai += kin.s[i][r];
                }
            }
            a[i] = ai;
        }
        for j in 0..con.len() {
            rows[j][dof] = match con.kind[j] {
                RowKind::Limit | RowKind::Motion { .. } => if con.dof[j].0 == dof { con.dof[j].1 } else { 0.0 },
                // a joint equality: its terms over the dofs of both joints
                RowKind::Equality => con.joint_terms(j).iter().filter(|t| t.0 == dof).map(|t| t.1).sum(),
                // torsional and rolling friction: the sides' relative turning about dir
                RowKind::Spin { .. } => {
                    let w = |side: usize| if con.node[j][side] == WORLD { DVec3::ZERO } else { a[con.node[j][side]].ang };
                    con.dir[j].dot(w(0) - w(1))
                }
                _ => {
                    let mut acc = DVec3::ZERO;
                    for side in 0..2 {
                        let n = con.node[j][side];
                        if n == WORLD {
                            continue;
                        }
                        let r = kin.rel(n, con.point[j][side]);
                        let w = a[n].lin + a[n].ang.cross(r);
                        acc += if side == 0 { w } else { -w };
                    }
                    con.dir[j].dot(acc)
                }
            };
        }
    }
    rows
}

fn check(xml: &str, seed: u64) {
    let m = Model::from_mjcf(xml).unwrap();
    let mut r = Rng(seed);
    let mut data = Data::new(&m);
    let (q, v) = random_state(&m, &mut r);
    kinematics::forward(&m, &q, &v, &mut data.dynamics.kin);
    aba::backward(&m, &data.dynamics.kin, &vec![0.0; m.nv], 0.0, &mut data.dynamics.aba);
    let mut qacc = vec![0.0; m.nv];
    aba::forward(&m, &data.dynamics.kin, &mut data.dynamics.aba, &mut qacc);
    // synthetic contacts: random points between random geoms (bodies) and the world or each other
    let mut contacts = vec![];
    for k in 0..6 {
        let g1 = r.below(m.ngeom);
        let g2 = if k % 2 == 0 { usize::MAX } else { r.below(m.ngeom) };
        if g2 != usize::MAX && m.geom_body[g1] == m.geom_body[g2] {
            continue;
        }
        let n = DVec3::new(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(0.2, 1.0)).normalize();
        contacts.push(Contact {
            geom1: g1,
            geom2: g2,
            feature: k,
            pos: DVec3::new(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)),
            normal: n,
            dist: -1e-4,
            // every third contact with torsional and rolling friction (condim 6)
            friction: PairFriction::new(if k % 3 == 0 { 6 } else { 3 }, [0.8, 0.02, 0.005]),
        });
    }
    // a world geom to stand for the ground: index past the end maps to the world below
    let mut m2 = m.clone();
    m2.geom_body.push(0);
    m2.geom_type.push(GeomType::Plane);
    m2.geom_size.push([1.0; 3]);
    m2.ngeom += 1;
    for c in &mut contacts {
        if c.geom2 == usize::MAX {
            c.geom2 = m.ngeom;
        }
    }
    let mut con = ConstraintData::new(&m2);
    let ctrl = vec![0.0; m2.nu];
    let ff = vec![0.0; 2 * m2.nu];
    let forced = vec![false; 2 * m2.njnt];
    constraint::rows::push_contact_rows(&m2, &data.dynamics.kin, &data.dynamics.aba, &contacts, |_, n, _, _| n.any_orthonormal_vector(), &mut con);
    constraint::rows::push_limit_rows(&m2, &q, &v, &qacc, &forced, &mut con);
    constraint::rows::push_motion_rows(&m2, &q, &v, &ctrl, &ff, &mut con);
    constraint::rows::push_equality_rows(&m2, &q, &v, &mut con);
    // a scratch another world's step used: its Δq̈ must not reach these columns (an equality
    // across trees reads its test forces' responses at the other tree's dofs too)
    con.dqdd = vec![f64::NAN; 64 * m2.nv];
    constraint::test_forces::assemble(&m2, &data.dynamics.kin, &data.dynamics.aba, &qacc, &mut con);
    let nr = con.len();
    assert!(nr >= 6, "rows {nr}");
    assert!(contacts.iter().all(|c| c.friction.condim != 6) || con.kind.iter().any(|k| matches!(k, RowKind::Spin { .. })));
    let j = jacobian(&m2, &data, &con);
    let mass = crba(&m, &data.dynamics.kin);
    let mut worst = 0.0f64;
    let scale = (0..nr).map(|i| con.k_at(i, i).abs()).fold(0.0, f64::max);
    for c in 0..nr {
        let minv_jt = cholesky_solve(&mass, &j[c]);
        for rr in 0..nr {
            let reference: f64 = j[rr].iter().zip(&minv_jt).map(|(a, b)| a * b).sum();
            worst = worst.max((con.k_at(rr, c) - reference).abs() / scale);
        }
    }
    assert!((0..nr * nr).all(|i| con.k_at(i / nr, i % nr).is_finite()), "K not finite (seed {seed})");
    assert!(worst <= 1e-9, "K vs J M⁻¹ Jᵀ: rel err {worst:e} (seed {seed})");
    check_arc(&m, &data.dynamics.kin, &q, &v, &con, seed);
}

/// The arc terms J̇ q̇ · n of each contact normal row, of its contact points and of its centres,
/// equal the second derivative of the gap between those body-fixed points moved along the
/// constant-velocity path q ⊕ t q̇ (central differences).
fn check_arc(m: &Model, kin0: &kinematics::KinData, q: &[f64], v: &[f64], con: &ConstraintData, seed: u64) {
    let gap_at = |t: f64, j: usize, pts: [DVec3; 2]| {
        let mut qt = q.to_vec();
        integrate::integrate_pos(m, &mut qt, v, t);
        let mut kin = kinematics::KinData::new(m);
        kinematics::forward(m, &qt, v, &mut kin);
        let point = |side: usize| {
            let (n, p) = (con.node[j][side], pts[side]);
            if n == WORLD { p } else { kin.node_rot[n] * p + kin.node_pos[n] }
        };
        con.dir[j].dot(point(0) - point(1))
    };
    let eps = 1e-4;
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Normal) {
        let arcs = constraint::system::arcs(kin0, con, j);
        for (arc, pts) in arcs.into_iter().zip([con.point[j], con.centre[j]]) {
            let second = (gap_at(eps, j, pts) - 2.0 * gap_at(0.0, j, pts) + gap_at(-eps, j, pts)) / (eps * eps);
            let scale = 1.0 + arc.abs();
            assert!((second - arc).abs() <= 1e-5 * scale, "arc {arc} vs finite differences {second} (seed {seed})");
        }
    }
}

#[test]
fn test_force_k_matches_dense_delassus_on_random_trees() {
    for seed in 0..12 {
        check(&random_tree_mjcf(3 + seed as usize % 9, seed % 2 == 0, seed), seed);
    }
}

/// Several random trees side by side in one world (names made distinct).
fn forest_mjcf(sizes: &[usize], seed: u64) -> String {
    let mut head = String::new();
    let mut bodies = String::new();
    for (t, &n) in sizes.iter().enumerate() {
        let xml = random_tree_mjcf(n, t % 2 == 0, seed * 31 + t as u64);
        let (open, close) = (xml.find("<worldbody>").unwrap(), xml.find("</worldbody>").unwrap());
        if t == 0 {
            head = xml[..open].to_string();
        }
        bodies += &xml[open + "<worldbody>".len()..close].replace("name=\"", &format!("name=\"t{t}_"));
    }
    format!("{head}<worldbody>{bodies}</worldbody></mujoco>")
}

/// K of rows on separate trees, each test force pushed through its own trees' nodes only, is
/// J M⁻¹ Jᵀ with its zeros between trees that share no row.
#[test]
fn test_force_k_matches_dense_delassus_on_forests() {
    for seed in 0..8 {
        let xml = forest_mjcf(&[2 + seed as usize % 4, 3, 1 + seed as usize % 3], seed);
        let m = Model::from_mjcf(&xml).unwrap();
        assert!(m.node_end[0] < m.nnode, "more than one tree");
        // an equality coupling a hinge or slide of the first tree to one of the second
        let one = |t: &str| (0..m.njnt).find(|&j| m.jnt_name[j].starts_with(t) && matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide)).map(|j| m.jnt_name[j].clone());
        let (a, b) = (one("t0_").unwrap(), one("t1_").unwrap());
        check(&xml.replace("</mujoco>", &format!("<equality><joint joint1=\"{a}\" joint2=\"{b}\"/></equality></mujoco>")), seed);
    }
}

#[test]
fn limit_rows_match_the_inverse_mass_matrix() {
    let xml = "<mujoco><worldbody><body><joint name='a' range='-1 1'/><geom size='0.1' pos='0.3 0 0'/>\
        <body pos='0.5 0 0'><joint name='b' type='slide' axis='1 0 0' range='-0.5 0.5'/><geom size='0.1'/></body></body></worldbody></mujoco>";
    let m = Model::from_mjcf(xml).unwrap();
    let mut data = Data::new(&m);
    let q = vec![-1.0, 0.5];
    let v = vec![0.0, 0.0];
    kinematics::forward(&m, &q, &v, &mut data.dynamics.kin);
    aba::backward(&m, &data.dynamics.kin, &[0.0, 0.0], 0.0, &mut data.dynamics.aba);
    let mut qacc = vec![0.0; 2];
    aba::forward(&m, &data.dynamics.kin, &mut data.dynamics.aba, &mut qacc);
    let mut con = ConstraintData::new(&m);
    constraint::rows::push_limit_rows(&m, &q, &v, &qacc, &[false; 4], &mut con);
    assert_eq!(con.len(), 2, "both joints sit at a limit");
    constraint::test_forces::assemble(&m, &data.dynamics.kin, &data.dynamics.aba, &qacc, &mut con);
    let mass = crba(&m, &data.dynamics.kin);
    let minv0 = cholesky_solve(&mass, &[1.0, 0.0]);
    let minv1 = cholesky_solve(&mass, &[0.0, 1.0]);
    // rows: joint a at its lower limit (+1), joint b at its upper limit (−1)
    let expect = [minv0[0], -minv1[0], -minv0[1], minv1[1]];
    let k = con.k_dense();
    for (k, e) in k.iter().zip(expect) {
        assert!((k - e).abs() < 1e-12 * e.abs().max(1.0), "{k:?} vs {expect:?}");
    }
}
