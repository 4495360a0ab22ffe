//! Post-stabilisation (Cline & Pai 2003): penetration beyond the slop is taken out of the
//! positions at the end of the step, without a velocity kick.

use sinew::step::stabilize::SLOP;
use sinew::{Model, State};

const BALL: &str = r#"<mujoco><option timestep="0.002"/><worldbody><geom type="plane" size="5 5 .1"/>
<body pos="0 0 0.1"><freejoint/><geom type="sphere" size="0.1"/></body></worldbody></mujoco>"#;

#[test]
fn a_ball_started_5_mm_inside_the_floor_is_out_after_one_step_without_popping() {
    let m = Model::from_mjcf(BALL).unwrap();
    let mut s = State::new(&m);
    s.qpos[2] = 0.1 - 0.005;
    s.step(&m);
    assert!(s.qpos[2] >= 0.1 - SLOP, "still {} m inside", 0.1 - s.qpos[2]);
    // only the slop's worth of Baumgarte velocity (SLOP / 0.05 s), no 5 mm pop
    assert!(s.qvel[2].abs() <= 2.0 * SLOP / sinew::step::constraint::CORRECTION_TIME, "vz = {}", s.qvel[2]);
    assert_eq!(s.data.post.projections, 1);
    // at rest it stays: no further projection, no drift
    let z = s.qpos[2];
    for _ in 0..1000 {
        s.step(&m);
    }
    assert!((s.qpos[2] - z).abs() < 1e-4 && s.qvel[2].abs() < 1e-6);
}
