//! Steps a model 200 000 times with random controls (pyramid friction, Euler): a workload for `perf`.
//! `cargo build --profile profiling --example profile_step && perf record target/profiling/examples/profile_step model.xml`
//! A second argument `zero-gravity` switches gravity off (with a far floor: the cost of collision
//! that finds nothing); `free` switches contacts and limits off (the bare step); `own` keeps the
//! model's own integrator (RK4 for Ant, Hopper, Humanoid); a third and fourth set the step count
//! and the controls' random seed (`benches/ab_instructions.py` counts a short run's instructions);
//! `key` keeps the model's integrator and steps from its "home" keyframe (else its first) holding
//! the keyframe's controls, back to it every 300 steps as `Sim.reset` goes back
//! (`benches/robot_models.py`'s workload).
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let m = sinew::Model::from_mjcf_file(std::path::Path::new(&path)).unwrap();
    let mut m = m;
    m.opt.friction = sinew::model::FrictionModel::Pyramid;
    let mode = std::env::args().nth(2);
    if !matches!(mode.as_deref(), Some("own" | "key")) {
        m.opt.integrator = sinew::model::Integrator::Euler;
    }
    match mode.as_deref() {
        Some("zero-gravity") => m.opt.gravity = glam::DVec3::ZERO,
        Some("free") => (m.opt.contact, m.opt.limit) = (false, false),
        _ => {}
    }
    let mut s = sinew::State::new(&m);
    let arg = |i: usize, default: u64| std::env::args().nth(i).map_or(default, |a| a.parse().unwrap());
    if mode.as_deref() == Some("key") {
        let key = m.keys.iter().find(|k| k.name == "home").or(m.keys.first());
        let (qpos, ctrl) = key.map_or((m.qpos0.clone(), vec![0.0; m.nu]), |k| (k.qpos.clone(), k.ctrl.clone()));
        for k in 0..arg(3, 200_000) {
            if k % 300 == 0 {
                // reset as `Sim.reset` does, keeping the buffers a workload has grown
                s.qpos.copy_from_slice(&qpos);
                s.ctrl.copy_from_slice(&ctrl);
                s.qvel.fill(0.0);
                s.act.fill(0.0);
                s.time = 0.0;
                s.data.restore(None, &sinew::constraint::History::new());
            }
            s.step(&m);
        }
        println!("{:?} {:?}", &s.qpos[..m.nq.min(3)], s.data.constraints.stats);
        return;
    }
    let mut x = arg(4, 1);
    for k in 0..arg(3, 200_000) {
        if k % 10 == 0 {
            for c in s.ctrl.iter_mut() {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
                *c = ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0;
            }
        }
        s.step(&m);
        if k % 5000 == 0 { s.qpos.copy_from_slice(&m.qpos0); s.qvel.fill(0.0); }
    }
    println!("{:?} {:?}", &s.qpos[..m.nq.min(3)], s.data.constraints.stats);
}
