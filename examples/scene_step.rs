//! Steps an MJCF scene without controls for a number of simulated seconds (Euler, the friction
//! model given) and prints the wall time per step, the mean rows and contacts per step and the
//! LCP counters: a workload for timing and `perf` on scenes of many bodies (a tower, a pile).
//! `cargo build --profile profiling --example scene_step && target/profiling/examples/scene_step scene.xml 3 pyramid`
//! (with `--features stage-timing`, each stage's share of the step's time as well).
fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        eprintln!("usage: scene_step MODEL.xml SECONDS pyramid|one_tangent");
        std::process::exit(2);
    }
    let mut m = match sinew::Model::from_mjcf_file(std::path::Path::new(&args[1])) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{}: {e}", args[1]);
            std::process::exit(1);
        }
    };
    let Ok(seconds) = args[2].parse::<f64>() else {
        eprintln!("SECONDS: a number, not '{}'", args[2]);
        std::process::exit(2);
    };
    m.opt.friction = match args[3].as_str() {
        "one_tangent" | "seed" => sinew::model::FrictionModel::OneTangent,
        _ => sinew::model::FrictionModel::Pyramid,
    };
    m.opt.integrator = sinew::model::Integrator::Euler;
    let mut s = sinew::State::new(&m);
    let steps = (seconds / m.opt.timestep).round() as usize;
    let (mut rows, mut contacts) = (0, 0);
    let start = std::time::Instant::now();
    for _ in 0..steps {
        s.step(&m);
        rows += s.data.constraints.con.len();
        contacts += s.data.coll.contacts.len();
    }
    let wall = start.elapsed().as_secs_f64();
    let per = steps.max(1);
    println!("{steps} steps in {wall:.3} s ({:.1} us/step), {} rows and {} contacts a step", wall * 1e6 / per as f64, rows / per, contacts / per);
    println!("{:?}", s.data.constraints.stats);
    #[cfg(feature = "stage-timing")]
    {
        let total: u64 = s.data.stage_ns.iter().sum();
        for (name, t) in sinew::step::STAGE_NAMES.iter().zip(&s.data.stage_ns) {
            println!("{name}: {:.1}%", 100.0 * *t as f64 / total as f64);
        }
    }
}
