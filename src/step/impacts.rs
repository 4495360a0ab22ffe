//! Stage 6 — the impact passes: velocity-level solves while rows approach fast and rebound.

use crate::constraint::impact::needs_impact;
use crate::constraint::rows::refresh;
use crate::constraint::solve::{apply, solve_rows, Level};
use crate::constraint::{impact_speed, World};
use crate::dynamics::{self, aba, external, fluid, forces, kinematics, tendon};
use crate::model::Model;
use crate::state::WorldState;
use crate::timing::{timed, Stage};

/// Stage 6: while a contact or limit row approaches fast and rebounds (restitution e > 0), a
/// velocity-level solve over the rows approaching, its impulses into q̇; each collision of a
/// sequence gets a pass of its own (rows not approaching take no part: `solve::apart`). A
/// plastic impact needs none: the force solve's row of a contact or limit closing within the
/// step asks for the impact's v⁺ = −d/h at the step's end, with the same K (its q is the
/// impact's over h, up to the arc term: `lcp_vector`), as it does for slow approaches. Whether
/// any pass ran.
pub(super) fn impacts(m: &Model, data: &mut World<'_>, s: &mut WorldState<'_>) -> bool {
    if m.opt.restitution == 0.0 {
        return false;
    }
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let speed = impact_speed(h, m.opt.gravity.length());
    let mut impacted = false;
    for _ in 0..MAX_IMPACT_PASSES {
        if !needs_impact(&data.constraints.con, h, lever, speed) {
            break;
        }
        impacted = true;
        data.constraints.impacts += 1;
        solve_rows(m, data, Level::Velocity);
        apply(m, data, s.qvel, 1.0);
        timed!(data, Stage::Impact, new_velocities(m, data, s));
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
fn new_velocities(m: &Model, data: &mut World<'_>, s: &WorldState<'_>) {
    let (qpos, qvel, ctrl) = (&*s.qpos, &*s.qvel, s.ctrl);
    let dy = &mut *data.dynamics;
    forces::applied(m, &dy.ten, qpos, qvel, (ctrl, &*s.act), &mut dy.qfrc_applied);
    if !dy.v_other.is_empty() {
        kinematics::velocities(m, &dy.kin, qvel, &mut dy.v_other);
        fluid::add_forces(m, &dy.kin, &dy.v_other, &mut dy.qfrc_applied);
    }
    external::add_forces(m, &dy.kin, &dy.xfrc_applied, &mut dy.qfrc_applied);
    external::add_gravcomp(m, &dy.kin, &mut dy.qfrc_applied);
    let tau = dynamics::total_force(&dy.qfrc_applied, &dy.qfrc_friction, dy.friction_known, &mut dy.tau);
    aba::backward_bias(m, &dy.kin, tau, &mut dy.aba);
    aba::forward(m, &data.dynamics.kin, &mut data.dynamics.aba, &mut data.dynamics.qacc);
    kinematics::forward_velocity(m, qvel, &mut data.dynamics.kin);
    // the tendons' J̇ q̇ of the new velocities (lengths and J are the configuration's)
    tendon::evaluate(m, &data.dynamics.kin, qpos, &mut data.dynamics.ten);
    refresh(m, data.dynamics, s, &data.constraints.feedforward, &mut data.constraints.con);
}

