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
