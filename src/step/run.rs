//! `n` steps of one world under a panic guard: the one loop `Sim.step` and [`crate::batch::Batch::step`] run.

use super::data::Data;
use super::step;
use crate::model::Model;
use crate::state::WorldState;

/// A step that left the state out of the finite range ([`crate::math::MAX_STATE`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Divergence {
    /// Which of the call's steps (0-based).
    pub step: usize,
    /// The first entry out of range: (array name, index, value).
    pub entry: (&'static str, usize, f64),
    /// Time after that step.
    pub time: f64,
}

/// Steps the world `n` times, stopping after the first step that leaves its state out of range
/// (the state is then as that step left it).
pub fn advance(m: &Model, data: &mut Data, s: &mut WorldState<'_>, n: usize) -> Option<Divergence> {
    for k in 0..n {
        step(m, data, s);
        if let Some(entry) = s.bad_entry() {
            return Some(Divergence { step: k, entry, time: *s.time });
        }
    }
    None
}

/// Runs `f` on the world, recording where it began in `data.fault`. A panic (a bug) puts the
/// state back there, forgets the history and gives the panic's message.
pub fn guarded<R>(data: &mut Data, s: &mut WorldState<'_>, f: impl FnOnce(&mut Data, &mut WorldState<'_>) -> R) -> Result<R, String> {
    data.fault.save(s);
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&mut *data, &mut s.reborrow()))) {
        Ok(r) => Ok(r),
        Err(e) => {
            data.fault.restore(s);
            data.forget_history();
            Err(crate::error::panic_message(&*e))
        }
    }
}
