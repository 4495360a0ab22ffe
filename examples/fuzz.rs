//! The mutation fuzzer of `tests/common/fuzz.rs`, for as long as you like:
//! `cargo run --release --example fuzz -- --inputs 1000000 [--steps 100] [--seed 1] [--corpus DIR] [--out FILE]`
//! Half the inputs are mutated models (from the seed corpus: gymnasium's MuJoCo model files in
//! DIR, and a few of sinew's own), half mutated full states of the corpus models, restored and
//! stepped. Prints the tally; with `--out`, writes it as a Markdown table. Exits 1 on any panic,
//! hang or silent non-finite value.

#[path = "../tests/common/mod.rs"]
#[allow(clippy::needless_range_loop)]
mod common;

use common::fuzz;
use rayon::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).cloned();
    let inputs: u64 = arg("--inputs").map_or(10_000, |s| s.parse().expect("--inputs N"));
    let steps: usize = arg("--steps").map_or(100, |s| s.parse().expect("--steps N"));
    let seed: u64 = arg("--seed").map_or(1, |s| s.parse().expect("--seed S"));
    let dir = arg("--corpus").map(std::path::PathBuf::from);
    if dir.is_none() {
        eprintln!("no --corpus DIR: fuzzing sinew's built-in model alone (gymnasium's assets make the usual corpus)");
    }
    let corpus = fuzz::corpus(dir.as_deref());
    let models: Vec<(usize, sinew::Model)> =
        corpus.iter().enumerate().filter_map(|(i, (_, x))| sinew::Model::from_mjcf(x).ok().filter(|m| m.nq > 0).map(|m| (i, m))).collect();
    let saved: Vec<Vec<f64>> = models.iter().map(|(_, m)| fuzz::saved_state(m, 200, seed)).collect();
    eprintln!("corpus: {} files ({} models to mutate states of); {inputs} inputs, {steps} steps each", corpus.len(), models.len());
    let start = std::time::Instant::now();
    let tally = (0..inputs)
        .into_par_iter()
        .map(|k| {
            let input_seed = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ k;
            if k % 2 == 0 {
                fuzz::model_input(&corpus[(k / 2) as usize % corpus.len()].1, input_seed, steps)
            } else {
                let j = (k / 2) as usize % models.len();
                fuzz::state_input(&models[j].1, &saved[j], input_seed, steps)
            }
        })
        .reduce(fuzz::Tally::default, |mut a, b| {
            a.add(&b);
            a
        });
    let secs = start.elapsed().as_secs_f64();
    println!("{tally:#?}\n{secs:.0} s");
    if let Some(out) = arg("--out") {
        let table = format!(
            "<!-- cargo run --release --example fuzz -- --inputs {inputs} --steps {steps} --seed {seed}{} --out {out} -->\n\
             | inputs | models (loaded, stepped {steps} steps) | states (accepted, stepped) | diverged (detected) | panics | hangs (> {} s) | silent non-finite | wall time |\n\
             |---|---|---|---|---|---|---|---|\n\
             | {} | {} ({}) | {} ({}) | {} | {} | {} | {} | {secs:.0} s |\n",
            dir.as_ref().map_or(String::new(), |d| format!(" --corpus {}", d.display())),
            fuzz::HANG.as_secs(),
            tally.models + tally.states,
            tally.models,
            tally.loaded,
            tally.states,
            tally.accepted,
            tally.diverged,
            tally.panics,
            tally.hangs,
            tally.silent_nonfinite,
        );
        std::fs::write(&out, table).expect("write --out");
    }
    if tally.failures_total() > 0 {
        std::process::exit(1);
    }
}
