//! A short run of the mutation fuzzer (`examples/fuzz.rs` runs it for as long as you like): no
//! input panics, hangs or leaves a non-finite value the divergence check misses.

#![allow(clippy::needless_range_loop)]

mod common;

use common::fuzz;

#[test]
fn mutated_models_and_states_never_panic_hang_or_go_silently_non_finite() {
    // gymnasium's model files when Python can say where they are, and sinew's own in any case
    let dir = std::process::Command::new("python3")
        .args(["-c", "from sinew.tasks import ASSETS; print(ASSETS)"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| std::path::PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    let corpus = fuzz::corpus(dir.as_deref());
    let mut tally = fuzz::Tally::default();
    for k in 0..600u64 {
        let (_, xml) = &corpus[k as usize % corpus.len()];
        tally.add(&fuzz::model_input(xml, k, 20));
    }
    for (_, xml) in &corpus {
        let Ok(m) = sinew::Model::from_mjcf(xml) else { continue };
        if m.nq == 0 {
            continue;
        }
        let saved = fuzz::saved_state(&m, 100, 3);
        for k in 0..60u64 {
            tally.add(&fuzz::state_input(&m, &saved, k, 10));
        }
    }
    assert!(tally.loaded > 20 && tally.accepted > 10, "the mutations leave inputs that load: {tally:?}");
    assert_eq!(tally.failures_total(), 0, "{:#?}", tally.failures);
}
