//! Stage 6 — impacts (Kokkevis 2004, §8.1): which rows approach fast enough to need the
//! velocity-level solve, and the end-of-step velocity a rebounding row asks for.

use super::*;

/// Stage 6: while a contact or limit row approaches fast and rebounds (restitution e > 0), a
/// velocity-level solve over the rows approaching, its impulses into q̇; each collision of a
/// sequence gets a pass of its own (rows not approaching take no part: `solve::apart`). A
/// plastic impact needs none: the force solve's row of a contact or limit closing within the
/// step asks for the impact's v⁺ = −d/h at the step's end, with the same K (its q is the
/// impact's over h, up to the arc term: `lcp_vector`), as it does for slow approaches. Whether
/// any pass ran.
pub(super) fn impacts(m: &Model, data: &mut Data, qpos: &[f64], qvel: &mut [f64], ctrl: &[f64]) -> bool {
    if m.opt.restitution == 0.0 {
        return false;
    }
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let speed = constraint::impact_speed(h, m.opt.gravity.length());
    let mut impacted = false;
    for _ in 0..MAX_IMPACT_PASSES {
        if !needs_impact(&data.con, h, lever, speed) {
            break;
        }
        impacted = true;
        data.solve.impacts += 1;
        solve_rows(m, data, Level::Velocity);
        apply(m, data, qvel, 1.0);
        timed!(data, Stage::Impact, new_velocities(m, data, qpos, qvel, ctrl));
    }
    impacted
}

/// Impact passes at most per step (a sequence of collisions, one per pass).
const MAX_IMPACT_PASSES: usize = 16;

/// After an impulse has changed q̇ in the same configuration (same rows, K and articulated
/// inertias): the applied forces (damping, servos) of the new velocities, the velocity-product
/// bias forces kept from the step's start, as velocity-level time stepping has them
/// (re-evaluated at the post-impact velocities they made a free-floating body gain angular
/// momentum at every impact: benches/free_flight.py), then the rows' velocities and b anew.
fn new_velocities(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) {
    forces::applied(m, qpos, qvel, ctrl, &mut data.qfrc_applied);
    aba::backward_bias(m, &data.kin, &data.qfrc_applied, &mut data.aba);
    aba::forward(m, &data.kin, &mut data.aba, &mut data.qacc);
    kinematics::forward_velocity(m, qvel, &mut data.kin);
    constraint::refresh(m, &data.kin, &data.aba, qpos, qvel, ctrl, &data.feedforward, &data.qacc, &mut data.con);
}

/// needImpact (Kokkevis 2004, §8.1): a contact or limit approaching fast enough to close within this step.
pub(super) fn needs_impact(con: &constraint::ConstraintData, h: f64, lever: f64, speed: f64) -> bool {
    (0..con.len()).any(|j| {
        matches!(con.kind[j], RowKind::Normal | RowKind::Limit) && approaching(con.vel[j], con.dist[j], con.vel[j] + h * con.b[j], lever, speed)
    })
}

/// A row moving into its constraint faster than `speed` (see [`constraint::impact_speed`]) that
/// would close within this step, given its velocity now and predicted at the step's end
/// (`lever`: [`crate::model::Options::lever`]).
pub(super) fn approaching(vel: f64, dist: f64, vel_end: f64, lever: f64, speed: f64) -> bool {
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
pub(super) fn rebound(v: f64, d: f64, a: f64, e: f64, h: f64, integrator: Integrator) -> f64 {
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
