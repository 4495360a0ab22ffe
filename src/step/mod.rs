//! ④ One simulation step. [`step`] reads as the pipeline; each stage lives in its own file.

pub mod aba;
pub mod collision;
pub mod constraint;
pub mod forces;
pub mod integrate;
pub mod kinematics;
pub mod lcp;
pub mod stabilize;

use glam::DVec3;

use crate::data::{Data, RowKey, ROW_CONTACT, ROW_LIMIT, ROW_MOTION};

/// Pipeline stages, for the per-stage cost breakdown (cargo feature `stage-timing`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Poses, velocities, velocity products.
    Kinematics,
    /// Applied forces and the ABA's passes.
    Dynamics,
    /// Contact detection (both checks).
    Collision,
    /// Constraint rows and their b.
    Rows,
    /// K and Δq̈ by test forces.
    Assembly,
    /// The LCP: vector, matrix, solve.
    Lcp,
    /// The velocity update after an impact.
    Impact,
    /// Time integration.
    Integration,
    /// Post-stabilisation check and projection.
    Projection,
}

/// Number of [`Stage`]s.
pub const STAGES: usize = 9;

/// Stage names, in [`Stage`] order.
pub const STAGE_NAMES: [&str; STAGES] = ["kinematics", "ABA", "collision", "rows", "K assembly", "LCP", "impact update", "integration", "post-stabilisation"];

/// Runs `$body`, adding its wall time to `$data.stage_ns[$stage]` with the `stage-timing` feature.
macro_rules! timed {
    ($data:expr, $stage:expr, $body:expr) => {{
        #[cfg(feature = "stage-timing")]
        let start = std::time::Instant::now();
        let out = $body;
        #[cfg(feature = "stage-timing")]
        {
            $data.stage_ns[$stage as usize] += start.elapsed().as_nanos() as u64;
        }
        #[cfg(not(feature = "stage-timing"))]
        let _ = $stage;
        out
    }};
}
use crate::model::{ConstraintMode, Integrator, Model};
use constraint::RowKind;

/// Forward dynamics at (qpos, qvel, ctrl) without constraints: fills `data.qacc` with the true
/// accelerations (no implicit damping), as MuJoCo's `mj_forward` with constraints disabled.
pub fn forward(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) {
    kinematics::forward(m, qpos, qvel, &mut data.kin);
    dynamics(m, data, qpos, qvel, ctrl, 0.0);
}

/// Applied forces and both ABA passes, on the kinematics already in `data.kin`; `h_damp` > 0
/// treats joint damping implicitly over that step.
fn dynamics(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64], h_damp: f64) {
    forces::applied(m, qpos, qvel, ctrl, &mut data.qfrc_applied);
    aba::backward(m, &data.kin, &data.qfrc_applied, h_damp, &mut data.aba);
    aba::forward(m, &data.kin, &mut data.aba, &mut data.qacc);
}

/// Advances (qpos, qvel, time) by one time step under `ctrl`.
pub fn step(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &mut [f64], ctrl: &[f64], time: &mut f64) {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    // Euler and leapfrog treat damping implicitly (MuJoCo's `Euler`), and so does a step with
    // constraint rows, which is semi-implicit Euler; RK4's stages do not. An RK4 model evaluates
    // first as the last step needed (contacts and rows are chosen with these accelerations) and
    // again when this step turns out otherwise
    let h_damp = match m.opt.integrator {
        Integrator::Rk4 if !(m.may_constrain() && data.history.constrained) => 0.0,
        _ => h,
    };
    // leapfrog: the step's dynamics are the midpoint configuration's
    let leapfrog = m.opt.integrator == Integrator::Leapfrog;
    if leapfrog {
        data.post.qpos_start.copy_from_slice(qpos);
        timed!(data, Stage::Integration, integrate::integrate_pos(m, qpos, qvel, 0.5 * h));
    }
    // 1. poses and velocities
    timed!(data, Stage::Kinematics, stabilize::kinematics_of(m, data, qpos, qvel));
    // 2. articulated inertias and the constraint-free accelerations
    timed!(data, Stage::Dynamics, dynamics(m, data, qpos, qvel, ctrl, h_damp));
    // 3. contacts of this configuration (reach over the step from velocities and accelerations)
    timed!(data, Stage::Collision, collision::collide(m, &data.kin, &data.aba, qpos, qvel, &data.qacc, &mut data.coll));
    // 4. constraint rows: contacts (normal + friction), active limits, motion control
    timed!(data, Stage::Rows, build_rows(m, data, qpos, qvel, ctrl));
    data.history.constrained = !data.con.is_empty();
    if data.con.is_empty() {
        // nothing to constrain: the plain step
        data.force.clear();
        match m.opt.integrator {
            Integrator::Euler | Integrator::Leapfrog => timed!(data, Stage::Integration, integrate::kick_drift(m, qpos, qvel, &data.qacc, h, lever)),
            Integrator::Rk4 => {
                if h_damp != 0.0 {
                    timed!(data, Stage::Dynamics, dynamics(m, data, qpos, qvel, ctrl, 0.0));
                }
                timed!(data, Stage::Integration, rk4(m, data, qpos, qvel, ctrl, h))
            }
        }
        *time += h;
        return;
    }
    // with constraints the step is semi-implicit Euler (the seed's scheme) unless leapfrog, RK4's too
    if h_damp != h {
        timed!(data, Stage::Dynamics, dynamics(m, data, qpos, qvel, ctrl, h));
    }
    let (mut redo, mut impacted) = (false, false);
    data.impact_warm.clear();
    loop {
        // 5. b; K by test forces once a solve needs it (rows that the constraint-free motion
        // already satisfies need no K)
        timed!(data, Stage::Rows, constraint::bias(m, &data.kin, &data.aba, &data.qacc, &mut data.con));
        if m.opt.constraint_mode == ConstraintMode::Velocity {
            // 6'. one impulse solve: q̈ = q̈₀ + Σ p_k Δq̈⁽ᵏ⁾ / h
            solve_rows(m, data, Level::TimeStep);
            apply_to_qacc(m, data, 1.0 / h);
        } else {
            // 6. impacts: a velocity-level solve over all rows when something approaches fast and
            // rebounds (e > 0). A plastic impact needs none: the force solve's row of a contact or
            // limit closing within the step asks for the impact's v⁺ = −d/h at the step's end,
            // with the same K (its q is the impact's over h, up to the arc term: `lcp_vector`),
            // as it does for slow approaches
            if !redo && m.opt.restitution > 0.0 && needs_impact(&data.con, h, lever, constraint::impact_speed(h, m.opt.gravity.length())) {
                impacted = true;
                data.impacts += 1;
                solve_rows(m, data, Level::Velocity);
                apply(m, data, qvel, 1.0);
                // same configuration, so the same rows, K and articulated inertias. The applied
                // forces (damping, servos) are those of the new velocities; the velocity-product
                // bias forces stay those of the step's start, as velocity-level time stepping has
                // them (re-evaluated at the post-impact velocities they made a free-floating body
                // gain angular momentum at every impact: benches/free_flight.py); then the rows'
                // velocities and b anew
                timed!(data, Stage::Impact, {
                    forces::applied(m, qpos, qvel, ctrl, &mut data.qfrc_applied);
                    aba::backward_bias(m, &data.kin, &data.qfrc_applied, &mut data.aba);
                    aba::forward(m, &data.kin, &mut data.aba, &mut data.qacc);
                    kinematics::forward_velocity(m, qvel, &mut data.kin);
                    constraint::refresh(m, &data.kin, &data.aba, qpos, qvel, ctrl, &data.feedforward, &data.qacc, &mut data.con);
                });
            }
            // 7. constraint forces at the acceleration level, added to q̈
            solve_rows(m, data, Level::Acceleration);
            apply_to_qacc(m, data, 1.0);
        }
        // a limit or contact without a row that the constrained motion would reach (pushed there
        // by contact forces, say): add its row and solve once more from the constraint-free
        // accelerations
        // (with no force, no impulse and the accelerations the rows were chosen with, the motion is
        // the constraint-free one they were chosen for)
        let pushed = impacted || h_damp != h || data.force.iter().any(|&f| f != 0.0);
        let missed = pushed && (missed_limits(m, data, qpos, qvel) | timed!(data, Stage::Collision, missed_contacts(m, data, qvel)));
        if redo || !missed {
            break;
        }
        redo = true;
        // the first solve's limit rows stay (an impulse may have made them look inactive)
        for r in (0..data.con.len()).filter(|&r| data.con.kind[r] == RowKind::Limit) {
            let side = (data.con.dof[r].1 < 0.0) as usize;
            data.limit_forced[2 * data.con.source[r] + side] = true;
        }
        timed!(data, Stage::Dynamics, dynamics(m, data, qpos, qvel, ctrl, h));
        timed!(data, Stage::Rows, build_rows(m, data, qpos, qvel, ctrl));
        data.impact_warm.clear();
    }
    if redo {
        data.limit_forced.fill(false);
    }
    // 8. integrate
    timed!(data, Stage::Integration, integrate::kick_drift(m, qpos, qvel, &data.qacc, h, lever));
    // 9. limits leapfrog's drift crossed, penetration the linearised rows missed
    if leapfrog {
        timed!(data, Stage::Projection, stabilize::hold_limits(m, &data.post, qpos));
    }
    timed!(data, Stage::Projection, stabilize::project(m, data, qpos, qvel));
    *time += h;
}

/// The constraint system a step from (qpos, qvel, ctrl) starts with, for inspection (MuJoCo's
/// `efc_J` and `efc_AR` are the like), at that configuration (leapfrog's step would use its
/// midpoint's).
#[derive(Clone, Debug)]
pub struct ConstraintSystem {
    /// Row kinds.
    pub kind: Vec<RowKind>,
    /// J (rows × nv, row-major): each row's velocity per unit q̇.
    pub jac: Vec<f64>,
    /// K (rows × rows, row-major), every column by test forces: each row's acceleration per unit
    /// force of each row.
    pub k: Vec<f64>,
    /// b: each row's acceleration without constraint force.
    pub b: Vec<f64>,
    /// The joint-space inertia K is built with (nv × nv, CRBA): M, plus h times the joint damping,
    /// which the constrained step treats implicitly (K = J (M + h B)⁻¹ Jᵀ).
    pub inertia: Vec<f64>,
}

/// Stages 1–5 of [`step`] on a copy of `data` (the world and its history are untouched): the
/// rows of the state and their J, K and b.
pub fn constraint_system(m: &Model, data: &Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) -> ConstraintSystem {
    let mut d = data.clone();
    let h = m.opt.timestep;
    kinematics::forward(m, qpos, qvel, &mut d.kin);
    // the constrained step's dynamics: damping implicit over the step, whatever the integrator
    dynamics(m, &mut d, qpos, qvel, ctrl, h);
    collision::collide(m, &d.kin, &d.aba, qpos, qvel, &d.qacc, &mut d.coll);
    build_rows(m, &mut d, qpos, qvel, ctrl);
    constraint::assemble(m, &d.kin, &d.aba, &d.qacc, &mut d.con);
    let mut inertia = crate::dynamics::crba::crba(m, &d.kin);
    for (k, damping) in m.dof_damping.iter().enumerate() {
        inertia[k * m.nv + k] += h * damping;
    }
    ConstraintSystem { kind: d.con.kind.clone(), jac: constraint::dense_jacobian(m, &d.kin, &d.con), k: d.con.k.clone(), b: d.con.b.clone(), inertia }
}

/// Appends to the contacts those the step's final velocities q̇ + h q̈ can reach but the first
/// detection's margin did not cover.
fn missed_contacts(m: &Model, data: &mut Data, qvel: &[f64]) -> bool {
    if !m.opt.contact || m.collision_pairs.is_empty() {
        return false;
    }
    let h = m.opt.timestep;
    let Data { kin, coll, post, qacc, .. } = data;
    for ((e, v), a) in post.vel_end.iter_mut().zip(qvel).zip(qacc.iter()) {
        *e = v + h * a;
    }
    // post.kin is free until the post-stabilisation check, which recomputes it
    collision::reach_again(m, kin, &post.vel_end, &mut post.kin.v, coll)
}

/// Marks in `data.limit_forced` each limit without a row that q̇ + h q̈ would cross within the step.
fn missed_limits(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64]) -> bool {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let mut any = false;
    for j in m.limited_joints() {
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        let [lo, hi] = m.jnt_range[j];
        let v_end = qvel[da] + h * data.qacc[da];
        for (side, (dist, sign)) in [(qpos[qa] - lo, 1.0), (hi - qpos[qa], -1.0)].into_iter().enumerate() {
            let has_row = || (0..data.con.len()).any(|r| data.con.kind[r] == RowKind::Limit && data.con.source[r] == j && data.con.dof[r].1 == sign);
            if dist + lever * sign * v_end < 0.0 && !has_row() {
                data.limit_forced[2 * j + side] = true;
                any = true;
            }
        }
    }
    any
}

fn build_rows(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) {
    let Data { kin, aba, coll, con, history, tangents_next, feedforward, qacc, limit_forced, .. } = data;
    let crate::data::History { tangents, rng, .. } = history;
    tangents_next.clear();
    let h = m.opt.timestep;
    constraint::rows(
        m,
        kin,
        aba,
        qpos,
        qvel,
        qacc,
        limit_forced,
        ctrl,
        feedforward,
        &coll.contacts,
        |ci, n, vt, at| {
            let c = &coll.contacts[ci];
            let key = (c.geom1, c.geom2, c.feature);
            let speed = vt.length();
            // the slip the step would give the contact without constraint forces
            let slip = vt + h * at;
            // dynamic friction opposes sliding (Kokkevis 2004, §8.1); a contact at rest that the
            // step would set slipping is treated alike (sinew's choice: a fixed tangent across the
            // slip lets it creep); otherwise static friction reuses the last valid tangent of a
            // persisting contact, or a random one for a new contact, as the seed does
            let t = if speed > constraint::SLIDING_SPEED {
                -vt / speed
            } else if slip.length() > constraint::SLIDING_SPEED {
                -slip / slip.length()
            } else if let Some((_, t)) = tangents.iter().find(|(k, t)| *k == key && t.dot(n).abs() < 1e-6) {
                *t
            } else {
                random_tangent(rng, n)
            };
            tangents_next.push((key, t));
            t
        },
        con,
    );
    std::mem::swap(tangents, tangents_next);
}

/// A unit vector orthogonal to `n` at a random angle, from the world's own SplitMix64 stream.
fn random_tangent(state: &mut u64, n: DVec3) -> DVec3 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    let angle = (z >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
    let (a, b) = n.any_orthonormal_pair();
    a * angle.cos() + b * angle.sin()
}

/// needImpact (Kokkevis 2004, §8.1): a contact or limit approaching fast enough to close within this step.
fn needs_impact(con: &constraint::ConstraintData, h: f64, lever: f64, speed: f64) -> bool {
    (0..con.len()).any(|j| {
        matches!(con.kind[j], RowKind::Normal | RowKind::Limit) && approaching(con.vel[j], con.dist[j], con.vel[j] + h * con.b[j], lever, speed)
    })
}

/// A row moving into its constraint faster than `speed` (see [`constraint::impact_speed`]) that
/// would close within this step, given its velocity now and predicted at the step's end
/// (`lever`: [`crate::model::Options::lever`]).
fn approaching(vel: f64, dist: f64, vel_end: f64, lever: f64, speed: f64) -> bool {
    vel < -speed && dist + lever * vel_end.min(vel) < 0.0
}

/// Rows whose K_jj is below this fraction of the largest are inert: zero force.
const INERT_ROW: f64 = 1e-12;

/// End-of-step velocity of a row rebounding with restitution e, on the row as a particle at gap d
/// with velocity v under its constraint-free acceleration a: semi-implicit Euler keeps
/// H = −a x + v²/2 + a h v/2 exactly under constant a, so the step's end state is chosen with
/// H = e² H(d, v) — the energy of a bounce off the surface (not off the gap d, where the impact
/// step starts), so the ball rises to e² of its drop height whatever h. Leapfrog keeps the same
/// H with d the gap at the step's midpoint configuration (x_end = d + h w / 2), so the same
/// rebound serves it.
fn rebound(v: f64, d: f64, a: f64, e: f64, h: f64) -> f64 {
    let energy = (-a * d + 0.5 * v * v + 0.5 * a * h * v).max(0.0);
    // x_end = d + h w:  −a (d + h w) + w²/2 + a h w/2 = e² H
    let disc = a * a * h * h + 8.0 * a * d + 8.0 * e * e * energy;
    0.5 * (a * h + disc.max(0.0).sqrt())
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Level {
    /// The seed's impact solve.
    Velocity,
    /// The seed's per-step force solve.
    Acceleration,
    /// Velocity-level time stepping: impulses over the whole step.
    TimeStep,
}

/// Assembles the LCP over all rows plus one λ per friction row and solves it into `data.force`.
fn solve_rows(m: &Model, data: &mut Data, level: Level) {
    // q, and the rows the solve starts without
    let n = timed!(data, Stage::Lcp, lcp_vector(m, data, level).map(|n| (n, leave_out(data, level, n))));
    let Some((n, warm)) = n else {
        // every row already satisfied without force (a limit at rest, contacts separating):
        // f = 0 solves the LCP (a friction row's λ takes up its demand) and K is not needed
        data.stats.solves += 1;
        data.stats.residual = 0.0;
        record_warm(data, level);
        return;
    };
    // K's columns for the rows kept; more when the answer pushes into a row left out
    let left_any = data.lcp_out.contains(&true);
    let mut brought_back = false;
    loop {
        let Data { kin, aba, con, lcp_out, .. } = data;
        timed!(data, Stage::Assembly, constraint::responses(m, kin, aba, con, |k, _| !lcp_out[k]));
        if timed!(data, Stage::Lcp, lcp_matrix_and_solve(m, data, level, n, warm)) {
            break;
        }
        brought_back = true;
    }
    // how often leaving rows out has cost another solve lately: past MAX_REGROW_RATE (a pile of
    // bodies, whose separating contacts the others keep pushing closed) nothing is left out,
    // and the rate decays, so that leaving out is tried again later
    data.history.regrow_rate = if left_any {
        (1.0 - REGROW_MEMORY) * data.history.regrow_rate + REGROW_MEMORY * brought_back as u8 as f64
    } else {
        REGROW_DECAY * data.history.regrow_rate
    };
}

/// Weight of the latest solve that left rows out in [`crate::data::History::regrow_rate`].
const REGROW_MEMORY: f64 = 0.1;
/// Decay of [`crate::data::History::regrow_rate`] per solve that left nothing out (from 1 to below
/// [`MAX_REGROW_RATE`] in about 70 solves).
const REGROW_DECAY: f64 = 0.99;
/// Regrow rate above which a solve leaves nothing out.
const MAX_REGROW_RATE: f64 = 0.5;

/// Marks in `data.lcp_out` the variables the solve starts without: each contact whose q says the
/// motion without its force separates it (q_n ≥ 0), with its friction rows and λ, unless it
/// carried force in the warm set (it probably will again). A separating contact keeps no force
/// unless others push it closed, which the solve checks; its test forces are then never pushed.
/// Limit rows stay: contact forces push joints into their limits too often (leaving out those
/// with q ≥ 0 too had many brought back on Ant, for no gain). Nothing is left out while the recent
/// share of solves that had to bring a contact back exceeds [`MAX_REGROW_RATE`]. Returns whether
/// a warm set applies ([`warm_guess`]).
fn leave_out(data: &mut Data, level: Level, n: usize) -> bool {
    let warm = warm_guess(data, level, n);
    let (con, q, guess, out) = (&data.con, &data.lcp_q, &data.lcp_warm, &mut data.lcp_out);
    out.clear();
    out.resize(n, false);
    if data.history.regrow_rate > MAX_REGROW_RATE {
        return warm;
    }
    for j in 0..con.len() {
        match con.kind[j] {
            RowKind::Normal => out[j] = q[j] >= 0.0 && !(warm && guess[j]),
            RowKind::Tangent { normal } => {
                let left = out[normal];
                (out[j], out[data.lcp_lambda[normal]]) = (left, left);
            }
            _ => {}
        }
    }
    warm
}

/// The active set a force solve starts from, into `data.lcp_warm` (n variables); whether there is
/// one. After this step's impact solve, on the same rows: its active set (a contact the impact
/// stopped now rests on its force). Else last step's, read through the rows' identities
/// ([`row_key`]): a row last step also had keeps its activity, and so does its contact's λ (a
/// bounded motion row's σ); a new row starts inactive. With the same rows as last step this is
/// last step's active set as it was.
fn warm_guess(data: &mut Data, level: Level, n: usize) -> bool {
    let Data { con, coll, history, impact_warm, lcp_warm: guess, lcp_lambda, warm_lambda: old_lambda, .. } = data;
    guess.clear();
    if level == Level::Velocity {
        return false;
    }
    if !impact_warm.is_empty() {
        guess.extend_from_slice(impact_warm);
        return true;
    }
    let (keys, warm) = (&history.warm_rows, &history.warm);
    // last step's λ (σ) variable of each owner row, from its rows' identities
    let old_n = number_lambdas(keys.len(), |i| match keys[i] {
        (ROW_CONTACT, _, _, _, within) if within > 0 => i.checked_sub(within),
        (ROW_MOTION, _, _, 1, _) => Some(i),
        _ => None,
    }, old_lambda);
    if keys.is_empty() || old_n != warm.len() {
        return false;
    }
    guess.resize(n, false);
    // rows keep their order across steps, so each search starts after the last match
    let mut at = 0;
    for j in 0..con.len() {
        let key = row_key(con, &coll.contacts, j);
        let Some(i) = (at..keys.len()).chain(0..at.min(keys.len())).find(|&i| keys[i] == key) else {
            continue;
        };
        at = i + 1;
        guess[j] = warm[i];
        if lcp_lambda[j] != usize::MAX && old_lambda[i] != usize::MAX {
            guess[lcp_lambda[j]] = warm[old_lambda[i]];
        }
    }
    true
}

/// Numbers the LCP's λ variables after the `nr` rows, into `lambda` (per row: the λ it owns, or
/// usize::MAX): one per contact with friction rows, shared by them (eq. 21 sums their forces), and
/// one σ per torque-bounded motion-control row (the same pattern with a constant bound), in the
/// order of their rows; `owner(j)` is the row owning row j's λ. Returns the variable count.
fn number_lambdas(nr: usize, owner: impl Fn(usize) -> Option<usize>, lambda: &mut Vec<usize>) -> usize {
    lambda.clear();
    lambda.resize(nr, usize::MAX);
    let mut n = nr;
    for j in 0..nr {
        if let Some(o) = owner(j)
            && lambda[o] == usize::MAX
        {
            lambda[o] = n;
            n += 1;
        }
    }
    n
}

/// The LCP's variables (rows, then one λ per contact with friction and one σ per bounded
/// motion-control row: [`number_lambdas`]) and its vector q, into `data`; their count, or None
/// when q ≥ 0 on every row but friction rows.
fn lcp_vector(m: &Model, data: &mut Data, level: Level) -> Option<usize> {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    // slower approaches are not impacts and get no restitution: resting contacts do not jitter
    let impact = constraint::impact_speed(h, m.opt.gravity.length());
    let nr = data.con.len();
    let kind = &data.con.kind;
    let n = number_lambdas(nr, |j| match kind[j] {
        RowKind::Tangent { normal } => Some(normal),
        RowKind::Motion { bounded: true } => Some(j),
        _ => None,
    }, &mut data.lcp_lambda);
    data.lcp_q.clear();
    data.lcp_q.resize(n, 0.0);
    data.force.clear();
    data.force.resize(n, 0.0);
    let con = &data.con;
    let q = &mut data.lcp_q;
    // contact points and centres move on arcs the rows' linear prediction leaves out: the
    // end-of-step targets add `con.lift` (`constraint::arc_lift`)
    for j in 0..nr {
        let (vel, dist) = (con.vel[j], con.dist[j]);
        // desired values: acceleration a^d, or velocity change Δv^d for impacts
        let desired = match (con.kind[j], level) {
            // motion control: the trajectory's acceleration; impacts leave the joint's velocity alone
            (RowKind::Motion { .. }, Level::Acceleration) => con.desired[j],
            (RowKind::Motion { .. }, Level::Velocity) => 0.0,
            (RowKind::Motion { .. }, Level::TimeStep) => h * (con.desired[j] - con.b[j]),
            (RowKind::Tangent { .. }, Level::Acceleration) => -vel / h,
            (RowKind::Tangent { .. }, Level::Velocity) => -vel,
            // time stepping: end-of-step velocity v⁺ (tangents: 0; normals: close the gap or remove
            // a fraction of the penetration; restitution for fast approach) against the predicted
            // constraint-free v_p = v + h b
            (RowKind::Tangent { .. }, Level::TimeStep) => -(vel + h * con.b[j]),
            (_, Level::TimeStep) => {
                let mut target = if dist > 0.0 { -dist / lever } else { constraint::correction_velocity(dist, h) } + con.lift[j];
                if -vel > impact && dist + lever * vel < 0.0 && m.opt.restitution > 0.0 {
                    target = target.max(rebound(vel, dist, con.b[j], m.opt.restitution, h));
                }
                target - (vel + h * con.b[j])
            }
            (_, Level::Acceleration) => {
                let target = if dist > 0.0 { -dist / lever } else { constraint::correction_velocity(dist, h) } + con.lift[j];
                (target - vel) / h
            }
            // end-of-step velocity v⁺ for a row that closes within this step: the rebound with
            // restitution, else −d/h, which just closes the gap (v_p: velocity predicted at the
            // step's end without constraint forces)
            (_, Level::Velocity) => {
                let e = if -vel > impact { m.opt.restitution } else { 0.0 };
                let vp = vel + h * con.b[j];
                let gap = dist.max(0.0) / lever;
                if approaching(vel, dist, vp, lever, impact) {
                    if e > 0.0 { rebound(vel, dist, con.b[j], e, h) - vp } else { -gap - vp }
                } else {
                    (-gap - vp).min(0.0)
                }
            }
        };
        q[j] = match level {
            Level::Acceleration => con.b[j] - desired,
            Level::Velocity | Level::TimeStep => -desired,
        };
    }
    let trivial = (0..nr).all(|j| q[j] >= 0.0 || matches!(con.kind[j], RowKind::Tangent { .. }));
    (!trivial).then_some(n)
}

/// M from K and the friction and bound couplings; solves into `data.force`, from the warm set in
/// `data.lcp_warm` when `warm` ([`warm_guess`]). False when the solve brought back rows left out,
/// whose K columns it needs.
fn lcp_matrix_and_solve(m: &Model, data: &mut Data, level: Level, n: usize, warm: bool) -> bool {
    let h = m.opt.timestep;
    let con = &data.con;
    let nr = con.len();
    data.lcp_m.clear();
    data.lcp_m.resize(n * n, 0.0);
    data.lcp_role.clear();
    data.lcp_role.resize(n, lcp::Role::Lambda);
    let (mm, q) = (&mut data.lcp_m, &mut data.lcp_q);
    // a row no force can move (K_jj ≈ 0: the out-of-plane friction of a planar model) carries no
    // force; left in, it makes the LCP degenerate, so the solve leaves it out (w = z, q = 0).
    // Rows whose K column is not computed are left out already and read only as rows
    let done = &con.column_done;
    let k_max = (0..nr).filter(|&j| done[j]).map(|j| con.k[j * nr + j]).fold(0.0, f64::max);
    for j in 0..nr {
        if done[j] && con.k[j * nr + j] <= INERT_ROW * k_max {
            mm[j * n + j] = 1.0;
            q[j] = 0.0;
            data.lcp_role[j] = lcp::Role::Normal;
            data.lcp_out[j] = true;
            continue;
        }
        mm[j * n..j * n + nr].copy_from_slice(&con.k[j * nr..(j + 1) * nr]);
        let kjj = con.k[j * nr + j];
        mm[j * n + j] = kjj + lcp::REGULARISATION * kjj.abs().max(1e-300);
        match con.kind[j] {
            RowKind::Tangent { normal } => {
                // (20): (a_t − a_t^d) + λ ≥ 0;  (21): μ f_n − Σ f_t ≥ 0 ⟂ λ ≥ 0
                let lam = data.lcp_lambda[normal];
                mm[j * n + lam] = 1.0;
                mm[lam * n + normal] = con.mu[j];
                mm[lam * n + j] = -1.0;
                data.lcp_role[j] = lcp::Role::Friction { normal, lambda: lam, mu: con.mu[j] };
            }
            RowKind::Motion { bounded: true } => {
                // (a − a^d) + σ ≥ 0 ⟂ f ≥ 0;  f_max − f ≥ 0 ⟂ σ ≥ 0, f_max a force (an impulse per step
                // when time stepping, none during an impact)
                let sigma = data.lcp_lambda[j];
                let cap = con.cap[j] * match level {
                    Level::Acceleration => 1.0,
                    Level::TimeStep => h,
                    Level::Velocity => 0.0,
                };
                mm[j * n + sigma] = 1.0;
                mm[sigma * n + j] = -1.0;
                q[sigma] = cap;
                data.lcp_role[j] = lcp::Role::Bounded { lambda: sigma, cap };
            }
            _ => data.lcp_role[j] = lcp::Role::Normal,
        }
    }
    let warm = warm.then_some(&data.lcp_warm[..]);
    let solved = lcp::solve(n, &data.lcp_m, &data.lcp_q, &data.lcp_role, warm, &mut data.lcp_out, &mut data.force, &mut data.lcp_work, &mut data.stats);
    if solved {
        record_warm(data, level);
    }
    solved
}

/// Keeps the active set of a solve: an impact's for the force solve after it, an
/// acceleration-level or time-stepping one's for the next step's.
fn record_warm(data: &mut Data, level: Level) {
    if level == Level::Velocity {
        data.impact_warm.clear();
        data.impact_warm.extend(data.force.iter().map(|&f| f > 0.0));
    } else {
        data.history.warm.clear();
        data.history.warm.extend(data.force.iter().map(|&f| f > 0.0));
        data.history.warm_rows.clear();
        for j in 0..data.con.len() {
            let key = row_key(&data.con, &data.coll.contacts, j);
            data.history.warm_rows.push(key);
        }
    }
}

/// Identity of row j across steps ([`RowKey`]): kind, then the contact (geoms, feature) and the row's position
/// within it, or the joint and the side (a motion row: its actuator, whether it is bounded, and
/// the side).
fn row_key(con: &constraint::ConstraintData, contacts: &[collision::Contact], j: usize) -> RowKey {
    match con.kind[j] {
        RowKind::Limit => (ROW_LIMIT, con.source[j], 0, 0, (con.dof[j].1 > 0.0) as usize),
        RowKind::Motion { bounded } => (ROW_MOTION, con.source[j], 0, bounded as usize, (con.dof[j].1 > 0.0) as usize),
        kind => {
            let c = &contacts[con.source[j]];
            let within = match kind {
                RowKind::Tangent { normal } => j - normal,
                _ => 0,
            };
            (ROW_CONTACT, c.geom1, c.geom2, c.feature, within)
        }
    }
}

/// q̈ += scale · Σ_k f_k Δq̈⁽ᵏ⁾.
fn apply_to_qacc(m: &Model, data: &mut Data, scale: f64) {
    let mut qacc = std::mem::take(&mut data.qacc);
    apply(m, data, &mut qacc, scale);
    data.qacc = qacc;
}

/// target += scale · Σ_k f_k Δq̈⁽ᵏ⁾ (forces into accelerations, or impulses into velocities).
fn apply(m: &Model, data: &Data, target: &mut [f64], scale: f64) {
    let nv = m.nv;
    for k in 0..data.con.len() {
        let f = data.force[k] * scale;
        if f != 0.0 {
            for (t, d) in target.iter_mut().zip(&data.con.dqdd[k * nv..(k + 1) * nv]) {
                *t += f * d;
            }
        }
    }
}

/// Classical RK4 over the whole (qpos, qvel) state, quaternions composed on the manifold.
fn rk4(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &mut [f64], ctrl: &[f64], h: f64) {
    use integrate::{integrate_pos, RK4_A, RK4_B};
    let mut rk = std::mem::take(&mut data.rk4);
    // stage 1 is the step's own evaluation (without implicit damping)
    rk.kv[0].copy_from_slice(qvel);
    rk.ka[0].copy_from_slice(&data.qacc);
    for i in 1..4 {
        // stage state: X0 + h Σ_j A_ij F_j
        rk.qpos.copy_from_slice(qpos);
        rk.dv.fill(0.0);
        rk.qvel.copy_from_slice(qvel);
        for j in 0..i {
            let a = RK4_A[i - 1][j];
            if a == 0.0 {
                continue;
            }
            for k in 0..m.nv {
                rk.dv[k] += a * rk.kv[j][k];
                rk.qvel[k] += h * a * rk.ka[j][k];
            }
        }
        integrate_pos(m, &mut rk.qpos, &rk.dv, h);
        // the dynamics need the nodes only (the next step recomputes the kinematics)
        kinematics::forward_nodes(m, &rk.qpos, &rk.qvel, &mut data.kin);
        dynamics(m, data, &rk.qpos, &rk.qvel, ctrl, 0.0);
        rk.kv[i].copy_from_slice(&rk.qvel);
        rk.ka[i].copy_from_slice(&data.qacc);
    }
    rk.dv.fill(0.0);
    for j in 0..4 {
        for k in 0..m.nv {
            rk.dv[k] += RK4_B[j] * rk.kv[j][k];
            qvel[k] += h * RK4_B[j] * rk.ka[j][k];
        }
    }
    integrate_pos(m, qpos, &rk.dv, h);
    // report the acceleration at the start of the step
    data.qacc.copy_from_slice(&rk.ka[0]);
    data.rk4 = rk;
}
