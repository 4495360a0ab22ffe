//! Stage 6 — impacts (Kokkevis 2004, §8.1): which rows approach fast enough to need the
//! velocity-level solve, and the end-of-step velocity a rebounding row asks for.

use super::system::{ConstraintData, RowKind};
use crate::model::Integrator;

/// needImpact (Kokkevis 2004, §8.1): a contact or limit approaching fast enough to close within this step.
pub fn needs_impact(con: &ConstraintData, h: f64, lever: f64, speed: f64) -> bool {
    (0..con.len()).any(|j| {
        matches!(con.kind[j], RowKind::Normal | RowKind::Limit) && approaching(con.vel[j], con.dist[j], con.vel[j] + h * con.b[j], lever, speed)
    })
}

/// A row moving into its constraint faster than `speed` (see [`impact_speed`](super::impact_speed)) that
/// would close within this step, given its velocity now and predicted at the step's end
/// (`lever`: [`crate::model::Options::lever`]).
pub fn approaching(vel: f64, dist: f64, vel_end: f64, lever: f64, speed: f64) -> bool {
    vel < -speed && dist + lever * vel_end.min(vel) < 0.0
}

/// Rows whose K_jj is below this fraction of the largest are inert: zero force.
pub(super) const INERT_ROW: f64 = 1e-12;

/// End-of-step velocity of a row rebounding with restitution e, on the row as a particle at gap d
/// with velocity v under its constraint-free acceleration a, the impact step being semi-implicit
/// Euler (x_end = d + h w). The step's end state is chosen with e² of the energy of a bounce off
/// the surface (not off the gap d, where the impact step starts), so the ball rises to e² of its
/// drop height whatever h, in the energy the free flight after it keeps: semi-implicit Euler keeps
/// H = −a x + v²/2 + a h v/2 exactly under constant a (and leapfrog the same H with d the gap at
/// the step's midpoint configuration), RK4 the true E = −a x + v²/2.
pub fn rebound(v: f64, d: f64, a: f64, e: f64, h: f64, integrator: Integrator) -> f64 {
    if integrator == Integrator::Rk4 {
        // −a (d + h w) + w²/2 = e² E
        let energy = (-a * d + 0.5 * v * v).max(0.0);
        let disc = a * a * h * h + 2.0 * a * d + 2.0 * e * e * energy;
        return a * h + disc.max(0.0).sqrt();
    }
    let energy = (-a * d + 0.5 * v * v + 0.5 * a * h * v).max(0.0);
    // x_end = d + h w:  −a (d + h w) + w²/2 + a h w/2 = e² H
    let disc = a * a * h * h + 8.0 * a * d + 8.0 * e * e * energy;
    0.5 * (a * h + disc.max(0.0).sqrt())
}
