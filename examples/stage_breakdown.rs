//! Per-stage cost of `step()` for each model given on the command line: 10 s of random controls
//! (a new uniform ctrl every 5 steps, seeded), pyramid friction, the model's dt, one thread.
//! Prints a Markdown row per model: steps/s with the timers on, then each stage's share of the
//! timed total. Needs the `stage-timing` feature; `benches/stage_breakdown.py` runs it on the
//! gymnasium models:
//! `cargo run --profile wheel --features stage-timing --example stage_breakdown -- model.xml…`

use sinew::step::{STAGES, STAGE_NAMES};

fn main() {
    let header: Vec<String> = STAGE_NAMES.iter().map(|s| format!("{s} %")).collect();
    println!("| model | steps/s (timers on) | {} |", header.join(" | "));
    println!("|---|---|{}", "---|".repeat(STAGES));
    for path in std::env::args().skip(1) {
        let mut m = match sinew::Model::from_mjcf_file(std::path::Path::new(&path)) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{path}: {e}");
                std::process::exit(1);
            }
        };
        m.opt.friction = sinew::model::FrictionModel::Pyramid;
        let mut s = sinew::State::new(&m);
        let mut x: u64 = 7;
        let steps = (10.0 / m.opt.timestep) as usize;
        let start = std::time::Instant::now();
        for k in 0..steps {
            if k % 5 == 0 {
                for (c, a) in s.ctrl.iter_mut().zip(&m.actuator_ctrlrange) {
                    x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                    let u = (x >> 11) as f64 / (1u64 << 53) as f64;
                    *c = a[0] + (a[1] - a[0]) * u;
                }
            }
            s.step(&m);
        }
        let rate = steps as f64 / start.elapsed().as_secs_f64();
        let total: u64 = s.data.stage_ns.iter().sum();
        let shares: Vec<String> = s.data.stage_ns.iter().map(|&t| format!("{:.1}", 100.0 * t as f64 / total as f64)).collect();
        let name = std::path::Path::new(&path).file_stem().unwrap().to_string_lossy().into_owned();
        println!("| {name} | {rate:.0} | {} |", shares.join(" | "));
    }
}
