//! Post-stabilisation (Cline & Pai 2003): penetration beyond the slop is taken out of the
//! positions at the end of the step; the velocity keeps only the correction term's for the slop,
//! SLOP / T.
#![allow(clippy::needless_range_loop)] // index loops follow the math's notation

use sinew::constraint::stabilize::SLOP;
use sinew::{Model, State};

const BALL: &str = r#"<mujoco><option timestep="0.002"/><worldbody><geom type="plane" size="5 5 .1"/>
<body pos="0 0 0.1"><freejoint/><geom type="sphere" size="0.1"/></body></worldbody></mujoco>"#;

#[test]
fn a_ball_started_5_mm_inside_the_floor_is_out_after_one_step_of_bounded_passes() {
    let m = Model::from_mjcf(BALL).unwrap();
    let mut s = State::new(&m);
    s.qpos[2] = 0.1 - 0.005;
    s.step(&m);
    assert!(s.qpos[2] >= 0.1 - SLOP, "still {} m inside", 0.1 - s.qpos[2]);
    // the correction term's velocity for the slop, SLOP / T, and no more (the whole depth's d / T
    // would remain once the projection has it out: a hop)
    let expected = SLOP / sinew::constraint::CORRECTION_TIME;
    assert!((s.qvel[2] - expected).abs() < 1e-6 * expected, "vz = {}", s.qvel[2]);
    // in passes of at most DEPENETRATION_SPEED · h (2 mm) each: three
    assert_eq!(s.data.constraints.projections, 3);
    // it comes to rest on the floor
    for _ in 0..1000 {
        s.step(&m);
    }
    assert!((s.qpos[2] - 0.1).abs() < SLOP && s.qvel[2].abs() < 1e-6, "z = {}, vz = {}", s.qpos[2], s.qvel[2]);
}

/// A fixed palm (a box) with a finger on a hinge whose hub, a sphere on the hinge axis, sinks
/// `depth` into the palm at every angle; a free ball rests `ball_depth` inside the floor.
fn overlapping_hub(depth: f64, ball_depth: f64) -> String {
    format!(
        r#"<mujoco><option timestep="0.002"/><worldbody><geom name="floor" type="plane" size="2 2 0.1"/>
        <body name="palm" pos="0 0 0.5"><geom name="palm" type="box" size="0.05 0.05 0.02"/>
          <body name="finger" pos="0 0 {z}"><joint name="hinge" axis="0 0 1" damping="0.01"/>
            <geom name="hub" type="sphere" size="0.02"/><geom name="tip" type="capsule" fromto="0 0 0.01 0.08 0 0.01" size="0.005"/>
          </body></body>
        <body pos="1 0 {bz}"><freejoint/><geom name="ball" type="sphere" size="0.05"/></body></worldbody>
        <actuator><motor joint="hinge" ctrlrange="-1 1"/></actuator></mujoco>"#,
        z = 0.02 + 0.02 - depth,
        bz = 0.05 - ball_depth
    )
}

#[test]
fn parts_of_one_robot_overlapping_at_qpos0_leave_collision_and_others_stay() {
    // 1 cm: the hub overlaps the palm alike at every hinge angle, which no joint can undo; the
    // pair leaves collision with a warning naming it, and the finger turns freely and finite
    let m = Model::from_mjcf(&overlapping_hub(0.01, 0.002)).unwrap();
    let warned = m.warnings.iter().find(|w| w.contains("overlap at qpos0")).expect("a warning");
    assert!(warned.contains("palm and hub (10.0 mm)"), "{warned}");
    let pair = |a: &str, b: &str| {
        let (i, j) = (m.geom_id(a).unwrap(), m.geom_id(b).unwrap());
        m.collision_pairs.iter().any(|p| (p.g1, p.g2) == (i.min(j), i.max(j)))
    };
    assert!(!pair("palm", "hub"));
    // the tip still meets the palm, and the ball overlapping the floor (parts of no one robot) stays
    assert!(pair("palm", "tip") && pair("floor", "ball"));
    let mut s = State::new(&m);
    s.ctrl[0] = 1.0;
    for _ in 0..500 {
        s.step(&m);
    }
    let spin = s.qvel[0];
    assert!(spin.is_finite() && spin > 0.0 && s.qvel.iter().all(|v| v.is_finite() && v.abs() < 1e3), "{:?}", s.qvel);
    // 0.5 mm, within the slop of parts that rest on each other: the pair stays
    let m = Model::from_mjcf(&overlapping_hub(0.0005, 0.0)).unwrap();
    assert!(!m.warnings.iter().any(|w| w.contains("overlap at qpos0")), "{:?}", m.warnings);
    // a finger whose tip sinks 5 mm into the palm, which its hinge lifts out at 0.08 m/rad: the
    // pair stays, and the step eases the tip out
    let xml = r#"<mujoco><option timestep="0.002" gravity="0 0 0"/><worldbody>
        <body name="palm"><geom name="palm" type="box" size="0.1 0.05 0.02"/>
          <body pos="0 0 0.035"><joint axis="0 1 0" damping="0.1"/>
            <geom name="tip" type="capsule" fromto="0 0 0 0.08 0 -0.015" size="0.005"/></body></body>
        </worldbody></mujoco>"#;
    let m = Model::from_mjcf(xml).unwrap();
    assert!(!m.warnings.iter().any(|w| w.contains("overlap at qpos0")), "{:?}", m.warnings);
    let mut s = State::new(&m);
    for _ in 0..100 {
        s.step(&m);
    }
    assert!(s.qpos[0] < -0.04 && s.qvel[0].abs() < 1.0, "q {} q̇ {}", s.qpos[0], s.qvel[0]);
}
