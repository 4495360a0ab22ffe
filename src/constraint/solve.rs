//! Stages 5–7 — the constraint solve: the LCP posed from the rows (q, the rows left out, the
//! warm start read through the rows' identities, K by test forces), solved by `lcp`, and its
//! forces or impulses applied to q̈ or q̇.

use crate::timing::{timed, Stage};
use super::history::RowKey;
use super::impact::{approaching, rebound, INERT_ROW};
use super::lcp::LcpWork;
use super::lcp;
use super::stabilize::corrected_start;
use super::system::{ConstraintData, RowKind};
use super::test_forces::{add_response, prepare, responses};
use super::{closing_velocity, correction_velocity, impact_speed, Constraints, World};
use crate::collision;
use crate::model::Model;

/// The LCP of a step's constraint solves (`constraint::solve`): its matrix and vector, each
/// variable's role, the answer, the warm start, Lemke's tableau and counters.
#[derive(Clone, Debug, Default)]
pub struct SolveData {
    /// Constraint force (acceleration solve) or impulse (impact solve) per row and λ.
    pub force: Vec<f64>,
    /// LCP matrix of the island being solved (row-major, its first k² entries).
    pub m: Vec<f64>,
    /// LCP vector.
    pub q: Vec<f64>,
    /// λ variable of each normal row with friction (usize::MAX: none).
    pub lambda: Vec<usize>,
    /// Role of each LCP variable of the island being solved.
    pub role: Vec<lcp::Role>,
    /// Island label of each LCP variable (`constraint::solve::island_labels`).
    pub group: Vec<usize>,
    /// The LCP variables island by island (by label, each island's in their order).
    pub order: Vec<usize>,
    /// Where each island ends in `order` (scratch for it).
    pub island_end: Vec<usize>,
    /// Number of each variable in its island's LCP while that is posed (else usize::MAX).
    pub local: Vec<usize>,
    /// The island's q, variables left out, warm set and answer.
    pub island_q: Vec<f64>,
    /// See `island_q`.
    pub island_out: Vec<bool>,
    /// See `island_q`.
    pub island_warm: Vec<bool>,
    /// See `island_q`.
    pub island_z: Vec<f64>,
    /// The island's rows whose test forces are not pushed, with their numbers in its LCP (in
    /// increasing row order): scratch for the matrix.
    pub unpushed: Vec<(usize, usize)>,
    /// LCP variables left out of the solve (held at zero force) and of K.
    pub out: Vec<bool>,
    /// Active set of this step's impact solve, which warm-starts the force solve on the same rows
    /// after it (empty: no impact this step, or rows rebuilt since).
    pub impact_warm: Vec<bool>,
    /// The active set the force solve starts from (`constraint::solve::warm_guess`).
    pub warm: Vec<bool>,
    /// Last step's λ variable of each of its rows that owns one, scratch for `constraint::solve::warm_guess`.
    pub warm_lambda: Vec<usize>,
    /// Last step's rows in the order of their identities, scratch for `constraint::solve::warm_guess`.
    pub warm_by_key: Vec<usize>,
    /// Lemke tableau.
    pub work: LcpWork,
}

/// Which solve the rows are posed for.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// The seed's impact solve.
    Velocity,
    /// The seed's per-step force solve.
    Acceleration,
    /// Velocity-level time stepping: impulses over the whole step.
    TimeStep,
}

/// Assembles the LCP over all rows plus one λ per friction row and solves it into `data.constraints.solve.force`.
pub fn solve_rows(m: &Model, data: &mut World<'_>, level: Level) {
    // q, and the rows the solve starts without
    let n = timed!(data, Stage::Lcp, lcp_vector(m, data, level).map(|n| (n, leave_out(data, level, n))));
    let Some((n, warm)) = n else {
        // every row already satisfied without force (a limit at rest, contacts separating):
        // f = 0 solves the LCP (a friction row's λ takes up its demand) and K is not needed
        data.constraints.stats.solves += 1;
        data.constraints.stats.residual = 0.0;
        record_warm(data, level);
        return;
    };
    // island by island: K's columns for the rows kept; more when the answer pushes into a row
    // left out
    let left_any = data.constraints.solve.out.contains(&true);
    let mut brought_back = false;
    prepare(m, &mut data.constraints.con);
    // the variables island by island, each island's in their order (one island, a single
    // character's, in place)
    if data.constraints.con.k_size.len() == 1 {
        let SolveData { group, order, .. } = &mut data.constraints.solve;
        group.clear();
        group.resize(n, 0);
        order.clear();
        order.extend(0..n);
    } else {
        island_labels(data, n);
        let SolveData { group, order, island_end, .. } = &mut data.constraints.solve;
        island_order(group, order, island_end, data.constraints.con.k_size.len());
    }
    let mut start = 0;
    while start < n {
        let label = data.constraints.solve.group[data.constraints.solve.order[start]];
        let end = (start..n).find(|&k| data.constraints.solve.group[data.constraints.solve.order[k]] != label).unwrap_or(n);
        loop {
            let (kin, aba) = (&data.dynamics.kin, &data.dynamics.aba);
            let Constraints { con, solve: SolveData { out: lcp_out, group, .. }, .. } = &mut *data.constraints;
            timed!(data, Stage::Assembly, responses(m, kin, aba, con, |k, _| !lcp_out[k] && group[k] == label));
            if timed!(data, Stage::Lcp, lcp_matrix_and_solve(m, data, level, start..end, warm)) {
                break;
            }
            brought_back = true;
        }
        start = end;
    }
    record_warm(data, level);
    // how often leaving rows out has cost another solve lately: past MAX_REGROW_RATE (a pile of
    // bodies, whose separating contacts the others keep pushing closed) nothing is left out,
    // and the rate decays, so that leaving out is tried again later
    data.constraints.history.regrow_rate = if left_any {
        (1.0 - REGROW_MEMORY) * data.constraints.history.regrow_rate + REGROW_MEMORY * brought_back as u8 as f64
    } else {
        REGROW_DECAY * data.constraints.history.regrow_rate
    };
}

/// Weight of the latest solve that left rows out in [`crate::step::data::History::regrow_rate`].
pub(super) const REGROW_MEMORY: f64 = 0.1;
/// Decay of [`crate::step::data::History::regrow_rate`] per solve that left nothing out (from 1 to below
/// [`MAX_REGROW_RATE`] in about 70 solves).
pub(super) const REGROW_DECAY: f64 = 0.99;
/// Regrow rate above which a solve leaves nothing out.
pub(super) const MAX_REGROW_RATE: f64 = 0.5;

/// Marks in `data.constraints.solve.out` the variables the solve starts without: each contact whose q says the
/// motion without its force separates it (q_n ≥ 0), with its friction rows and λ, unless it
/// carried force in the warm set (it probably will again), and the friction rows of a contact the
/// warm set keeps pressing with none of them (a box resting on a box: most rows of a stack). A
/// separating contact keeps no force unless others push it closed, and an idle friction row none
/// unless the contact's tangential demand grows past what the rows kept hold, which the solve
/// checks; their test forces are then never pushed.
/// Limit rows stay: contact forces push joints into their limits too often (leaving out those
/// with q ≥ 0 too had many brought back on Ant, for no gain). Nothing is left out while the recent
/// share of solves that had to bring a contact back exceeds `MAX_REGROW_RATE`. Returns whether
/// a warm set applies ([`warm_guess`]).
pub fn leave_out(data: &mut World<'_>, level: Level, n: usize) -> bool {
    let warm = warm_guess(data, level, n);
    let (con, q, guess, out) = (&data.constraints.con, &data.constraints.solve.q, &data.constraints.solve.warm, &mut data.constraints.solve.out);
    out.clear();
    out.resize(n, false);
    if data.constraints.history.regrow_rate > MAX_REGROW_RATE {
        return warm;
    }
    for j in 0..con.len() {
        match con.kind[j] {
            RowKind::Normal => out[j] = q[j] >= 0.0 && !(warm && guess[j]),
            RowKind::Tangent { normal } => {
                let left = out[normal];
                // a contact the warm set keeps pressing without friction force (a box resting on
                // another) keeps its friction rows out until the answer presses on one (leaving
                // out the idle rows of a contact with friction force brings one back too often)
                let idle = warm && guess[normal] && (normal + 1..con.len()).take_while(|&r| con.kind[r] == RowKind::Tangent { normal }).all(|r| !guess[r]);
                (out[j], out[data.constraints.solve.lambda[normal]]) = (left || idle, left);
            }
            // torsional and rolling rows likewise, group by group
            RowKind::Spin { normal, cone } => {
                // bounded by the normal forces of its geom pair's contacts (the normal rows
                // between the first one and the group)
                let normals = (normal..cone).filter(|&r| con.kind[r] == RowKind::Normal);
                let left = normals.clone().all(|r| out[r]);
                let idle = warm && normals.clone().any(|r| guess[r]) && (cone..con.len()).take_while(|&r| con.kind[r] == RowKind::Spin { normal, cone }).all(|r| !guess[r]);
                (out[j], out[data.constraints.solve.lambda[cone]]) = (left || idle, left);
            }
            _ => {}
        }
    }
    warm
}

/// The active set a force solve starts from, into `data.constraints.solve.warm` (n variables); whether there is
/// one. After this step's impact solve, on the same rows: its active set (a contact the impact
/// stopped now rests on its force). Else last step's, read through the rows' identities
/// ([`row_key`]): a row last step also had keeps its activity, and so does its contact's λ (a
/// bounded motion row's σ); a new contact or limit row starts active when q says the motion
/// without force drives into it (q < 0), with the friction rows its q drives against. With the
/// same rows as last step this is last step's active set as it was.
pub fn warm_guess(data: &mut World<'_>, level: Level, n: usize) -> bool {
    let coll = &*data.coll;
    let Constraints { con, history, solve, .. } = &mut *data.constraints;
    let SolveData { impact_warm, warm: guess, lambda: lcp_lambda, warm_lambda: old_lambda, warm_by_key: by_key, q, .. } = solve;
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
        RowKey::Contact { within, cone, .. } if within > 0 => i.checked_sub(within - cone),
        RowKey::Motion { bounded: true, .. } | RowKey::DryFriction { .. } => Some(i),
        _ => None,
    }, old_lambda);
    if keys.is_empty() || old_n != warm.len() {
        return false;
    }
    guess.resize(n, false);
    // rows keep their order across steps, so each row's key is looked for after the last match
    // first, then among the keys in order (each key is recorded once), sorted at the first miss
    by_key.clear();
    let mut at = 0;
    for j in 0..con.len() {
        let key = row_key(con, &coll.contacts, j);
        let found = if keys.get(at) == Some(&key) {
            Some(at)
        } else {
            if by_key.is_empty() {
                by_key.extend(0..keys.len());
                by_key.sort_unstable_by_key(|&i| keys[i]);
            }
            by_key.binary_search_by_key(&key, |&i| keys[i]).ok().map(|k| by_key[k])
        };
        let Some(i) = found else {
            // a new row: a contact or limit the motion without force drives into starts pressing,
            // a friction row of such a contact sticking against the demand
            guess[j] = match con.kind[j] {
                RowKind::Normal | RowKind::Limit => q[j] < 0.0,
                RowKind::Tangent { normal } | RowKind::Spin { normal, .. } => guess[normal] && q[j] < 0.0,
                _ => false,
            };
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
/// usize::MAX): one per contact with friction rows, shared by them (eq. 21 sums their forces), one
/// per group of torsional or rolling rows, owned by its first row, and
/// one σ per torque-bounded motion-control row (the same pattern with a constant bound), in the
/// order of their rows; `owner(j)` is the row owning row j's λ. Returns the variable count.
pub fn number_lambdas(nr: usize, owner: impl Fn(usize) -> Option<usize>, lambda: &mut Vec<usize>) -> usize {
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
pub fn lcp_vector(m: &Model, data: &mut World<'_>, level: Level) -> Option<usize> {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    // slower approaches are not impacts and get no restitution: resting contacts do not jitter
    let impact = impact_speed(h, m.opt.gravity.length());
    let nr = data.constraints.con.len();
    let kind = &data.constraints.con.kind;
    let n = number_lambdas(nr, |j| match kind[j] {
        RowKind::Tangent { normal } => Some(normal),
        RowKind::Spin { cone, .. } => Some(cone),
        RowKind::Motion { bounded: true } | RowKind::DryFriction => Some(j),
        _ => None,
    }, &mut data.constraints.solve.lambda);
    data.constraints.solve.q.clear();
    data.constraints.solve.q.resize(n, 0.0);
    data.constraints.solve.force.clear();
    data.constraints.solve.force.resize(n, 0.0);
    let con = &data.constraints.con;
    let q = &mut data.constraints.solve.q;
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
            // an equality: its error (in `dist`) gone at the step's end, to second order in the
            // drift (`lift`); linear terms the step keeps exactly
            (RowKind::Equality | RowKind::Connect { .. }, Level::Acceleration) => (-dist / lever + con.lift[j] - vel) / h,
            (RowKind::Equality | RowKind::Connect { .. }, Level::Velocity | Level::TimeStep) => -dist / lever + con.lift[j] - (vel + h * con.b[j]),
            // dry friction: the dof at rest at the step's end (no force in an instant's impact)
            (RowKind::DryFriction, Level::Acceleration) => -vel / h,
            (RowKind::DryFriction, Level::Velocity) => 0.0,
            (RowKind::DryFriction, Level::TimeStep) => -(vel + h * con.b[j]),
            (RowKind::Tangent { .. } | RowKind::Spin { .. }, Level::Acceleration) => -vel / h,
            (RowKind::Tangent { .. } | RowKind::Spin { .. }, Level::Velocity) => -vel,
            // time stepping: end-of-step velocity v⁺ (tangents: 0; normals: close the gap or remove
            // a fraction of the penetration; restitution for fast approach) against the predicted
            // constraint-free v_p = v + h b
            (RowKind::Tangent { .. } | RowKind::Spin { .. }, Level::TimeStep) => -(vel + h * con.b[j]),
            (_, Level::TimeStep) => {
                let mut target = closing_velocity(dist, corrected_start(con.kind[j], con.dist_start[j]), h, lever) + con.lift[j];
                if -vel > impact && dist + lever * vel < 0.0 && m.opt.restitution > 0.0 {
                    target = target.max(rebound(vel, dist, con.b[j], m.opt.restitution, h, m.opt.integrator));
                }
                target - (vel + h * con.b[j])
            }
            (_, Level::Acceleration) => {
                let target = closing_velocity(dist, corrected_start(con.kind[j], con.dist_start[j]), h, lever) + con.lift[j];
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
                    if e > 0.0 { rebound(vel, dist, con.b[j], e, h, m.opt.integrator) - vp } else { -gap - vp }
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
    let trivial = (0..nr).all(|j| q[j] >= 0.0 || con.kind[j].is_friction());
    (!trivial).then_some(n)
}

/// Whether row j takes no part in an impact solve: a contact (its friction rows too) or limit
/// that is not itself approaching fast. The rows that approach together are resolved together
/// (a simultaneous impact); a row that an impact sets approaching gets a pass of its own after it
/// (sequential collisions: a ball resting on a ball dropped on the floor leaves at about 2v, the
/// last of a line of balls with the first one's speed), each pass keeping what its restitution
/// keeps.
/// `impact`: [`impact_speed`].
fn apart(m: &Model, con: &ConstraintData, j: usize, impact: f64) -> bool {
    let r = match con.kind[j] {
        RowKind::Tangent { normal } | RowKind::Spin { normal, .. } => normal,
        RowKind::Normal | RowKind::Limit => j,
        RowKind::Motion { .. } | RowKind::DryFriction | RowKind::Equality | RowKind::Connect { .. } => return false,
    };
    let h = m.opt.timestep;
    !approaching(con.vel[r], con.dist[r], con.vel[r] + h * con.b[r], m.opt.lever(), impact)
}

/// The LCP of one island, the variables `data.constraints.solve.order[island]` (every row and λ of a set of
/// trees that touch, in their order): M from K and the friction and bound couplings, solved into
/// `data.constraints.solve.force`, from the warm set in `data.constraints.solve.warm` when `warm` ([`warm_guess`]). False
/// when the solve brought back rows left out, whose K columns it needs.
pub fn lcp_matrix_and_solve(m: &Model, data: &mut World<'_>, level: Level, island: std::ops::Range<usize>, warm: bool) -> bool {
    let h = m.opt.timestep;
    let Constraints { con, solve, stats, .. } = &mut *data.constraints;
    let nr = con.len();
    let SolveData { m: mm, q: all_q, out: all_out, warm: all_warm, force, role, lambda, order, local, island_q, island_out, island_warm, island_z, unpushed, work, .. } = solve;
    let vars = &order[island];
    let k = vars.len();
    // one island of every variable (a single character) is solved in place; an island of some is
    // gathered, each variable numbered in the island's LCP by `local`
    let whole = k == all_q.len();
    if !whole {
        gather_island(vars, (all_q, all_out, all_warm), warm, local, (island_q, island_out, island_warm, island_z));
    }
    let (q, out, z, guess) = if whole {
        (&mut *all_q, &mut *all_out, &mut *force, &*all_warm)
    } else {
        (&mut *island_q, &mut *island_out, &mut *island_z, &*island_warm)
    };
    let at = |v: usize| if whole { v } else { local[v] };
    // every entry of M is written below, once (no clearing first; the buffer only grows)
    if mm.len() < k * k {
        mm.resize(k * k, 0.0);
    }
    let mm = &mut mm[..k * k];
    role.clear();
    role.resize(k, lcp::Role::Lambda);
    // the island's rows come first among its variables (rows are numbered before every λ)
    let rows = vars.partition_point(|&v| v < nr);
    // a row no force can move (K_jj ≈ 0 beside the island's others: the out-of-plane friction of
    // a planar model) carries no force; left in, it makes the LCP degenerate, so the solve leaves
    // it out (w = z, q = 0). Rows whose K column is not computed are left out already and read
    // only as rows, at the columns computed: each computed row's measures are scattered into them
    // below (their own K rows are not written)
    let done = &con.column_done;
    let (k_max, pushed) = vars[..rows].iter().filter(|&&j| done[j]).fold((0.0f64, 0), |(k_max, n), &j| (k_max.max(con.k[con.k_index(j, j)]), n + 1));
    // a left-out row is zeroed whole where most rows are pushed, else at the pushed columns
    let sparse = 4 * pushed < rows;
    let impact = impact_speed(h, m.opt.gravity.length());
    // the island's rows are its block's, in order (K's block row copied whole), unless some are
    // missing from it
    let whole_block = rows > 0 && con.k_size[con.k_block[vars[0]]] == rows;
    // the λ and σ rows hold only the couplings their rows set
    mm[rows * k..].fill(0.0);
    unpushed.clear();
    for (a, &j) in vars[..rows].iter().enumerate() {
        let krow = con.k_row(j);
        let kjj = if done[j] { krow[con.k_pos[j]] } else { 0.0 };
        if (done[j] && kjj <= INERT_ROW * k_max) || (level == Level::Velocity && apart(m, con, j, impact)) {
            mm[a * k..(a + 1) * k].fill(0.0);
            mm[a * k + a] = 1.0;
            q[a] = 0.0;
            role[a] = lcp::Role::Normal;
            out[a] = true;
            continue;
        }
        if !done[j] {
            // left out (its test force was not pushed): read only at the kept columns, all pushed,
            // which `scatter_unpushed` writes
            if !sparse {
                mm[a * k..a * k + rows].fill(0.0);
            }
            unpushed.push((j, a));
        } else if whole_block {
            mm[a * k..a * k + rows].copy_from_slice(krow);
        } else {
            for (x, &jj) in mm[a * k..a * k + rows].iter_mut().zip(&vars[..rows]) {
                *x = con.k_at(j, jj);
            }
        }
        mm[a * k + rows..(a + 1) * k].fill(0.0);
        mm[a * k + a] = kjj + lcp::REGULARISATION * kjj.abs().max(1e-300);
        match con.kind[j] {
            RowKind::Tangent { normal } => {
                // (20): (a_t − a_t^d) + λ ≥ 0;  (21): μ f_n − Σ f_t ≥ 0 ⟂ λ ≥ 0
                let (lam, normal) = (at(lambda[normal]), at(normal));
                mm[a * k + lam] = 1.0;
                mm[lam * k + normal] = con.mu[j];
                mm[lam * k + a] = -1.0;
                role[a] = lcp::Role::Friction { normal, lambda: lam, mu: con.mu[j] };
            }
            RowKind::Spin { normal, cone } => role[a] = spin_coupling(con, j, (normal, cone), a, &at, lambda, out, (mm, k)),
            RowKind::Motion { bounded: true } | RowKind::DryFriction => {
                // (a − a^d) + σ ≥ 0 ⟂ f ≥ 0;  f_max − f ≥ 0 ⟂ σ ≥ 0, f_max a force (an impulse per step
                // when time stepping, none during an impact)
                let sigma = at(lambda[j]);
                let cap = con.cap[j] * match level {
                    Level::Acceleration => 1.0,
                    Level::TimeStep => h,
                    Level::Velocity => 0.0,
                };
                mm[a * k + sigma] = 1.0;
                mm[sigma * k + a] = -1.0;
                q[sigma] = cap;
                role[a] = lcp::Role::Bounded { lambda: sigma, cap };
            }
            _ => role[a] = lcp::Role::Normal,
        }
    }
    scatter_unpushed(con, &vars[..rows], unpushed, sparse, mm, k);
    // an inexact force solve is replaced by the step's impulses (`step::constrain`)
    work.fallback_follows = level == Level::Acceleration;
    let solved = lcp::solve(lcp::Problem { n: k, m: mm, q, role }, false, warm.then_some(&guess[..]), out, z, work, stats);
    if !whole {
        for (a, &v) in vars.iter().enumerate() {
            (force[v], all_out[v], local[v]) = (island_z[a], island_out[a], usize::MAX);
        }
    }
    solved
}

/// Torsional or rolling row j's couplings, as a sliding row's (seed eqs. 20–21) over its group
/// (μ a length, the rows couples) with f_n the normal force of its geom pair's contacts together
/// (the normal rows from `normal` to the group's first row `cone`), into the island's k × k
/// matrix `mm` (row j its variable a, `at` the island's number of a variable); its role, whose
/// normal is a kept one of them.
#[allow(clippy::too_many_arguments)]
fn spin_coupling(con: &ConstraintData, j: usize, (normal, cone): (usize, usize), a: usize, at: &impl Fn(usize) -> usize, lambda: &[usize], out: &[bool], (mm, k): (&mut [f64], usize)) -> lcp::Role {
    let lam = at(lambda[cone]);
    let mut kept = at(normal);
    for r in (normal..cone).filter(|&r| con.kind[r] == RowKind::Normal) {
        mm[lam * k + at(r)] = con.mu[j];
        if out[kept] && !out[at(r)] {
            kept = at(r);
        }
    }
    mm[a * k + lam] = 1.0;
    mm[lam * k + a] = -1.0;
    lcp::Role::Friction { normal: kept, lambda: lam, mu: con.mu[j] }
}

/// Gathers an island's variables `vars` from the whole problem's (q, left out, warm set) into
/// the island's arrays (q, left out, warm set, z), numbering each in the island by `local`.
fn gather_island(vars: &[usize], (q, out, warm_set): (&[f64], &[bool], &[bool]), warm: bool, local: &mut Vec<usize>, island: (&mut Vec<f64>, &mut Vec<bool>, &mut Vec<bool>, &mut Vec<f64>)) {
    let (island_q, island_out, island_warm, island_z) = island;
    local.resize(q.len(), usize::MAX);
    for (a, &v) in vars.iter().enumerate() {
        local[v] = a;
    }
    island_q.clear();
    island_q.extend(vars.iter().map(|&v| q[v]));
    island_out.clear();
    island_out.extend(vars.iter().map(|&v| out[v]));
    island_warm.clear();
    if warm {
        island_warm.extend(vars.iter().map(|&v| warm_set[v]));
    }
    island_z.clear();
    island_z.resize(vars.len(), 0.0);
}

/// The island's rows whose K column was not computed (`unpushed`: row, island index), written at
/// the columns computed: K_jj' = K_j'j, nonzero only between rows that share a tree (within the
/// span of those of row j'), and with `zero` zero at the other columns computed (else zeroed
/// already); the columns not computed are left as they were. `rows` are the island's rows, `mm`
/// its k × k matrix.
fn scatter_unpushed(con: &ConstraintData, rows: &[usize], unpushed: &[(usize, usize)], zero: bool, mm: &mut [f64], k: usize) {
    if unpushed.is_empty() {
        return;
    }
    let done = &con.column_done;
    for (b, &jj) in rows.iter().enumerate().filter(|&(_, &jj)| done[jj]) {
        // zero where the rows share no tree
        if zero {
            for &(_, a) in unpushed {
                mm[a * k + b] = 0.0;
            }
        }
        let (lo, hi) = con.sharing_span(jj);
        let from = unpushed.partition_point(|&(j, _)| j < lo);
        let krow = con.k_row(jj);
        for &(j, a) in unpushed[from..].iter().take_while(|&&(j, _)| j <= hi) {
            mm[a * k + b] = krow[con.k_pos[j]];
        }
    }
}

/// The variables island by island into `order`, each island's in their order (counted out by
/// their labels `group`, `blocks` of them), `end` left holding where each island ends.
fn island_order(group: &[usize], order: &mut Vec<usize>, end: &mut Vec<usize>, blocks: usize) {
    end.clear();
    end.resize(blocks + 1, 0);
    for &g in group {
        end[g + 1] += 1;
    }
    for b in 1..end.len() {
        end[b] += end[b - 1];
    }
    order.clear();
    order.resize(group.len(), 0);
    for (i, &g) in group.iter().enumerate() {
        order[end[g]] = i;
        end[g] += 1;
    }
}

/// Labels each of the n LCP variables with its island into `data.constraints.solve.group`: a
/// row's block of K (the trees it touches joined with every tree a row connects them to), which
/// a λ or σ takes from its row. Rows of different labels share no body, so K (and M) has no
/// entry between them.
fn island_labels(data: &mut World<'_>, n: usize) {
    let SolveData { group, lambda, .. } = &mut data.constraints.solve;
    let con = &data.constraints.con;
    group.clear();
    group.resize(n, usize::MAX);
    for (j, &block) in con.k_block.iter().enumerate() {
        group[j] = block;
        if lambda[j] != usize::MAX {
            group[lambda[j]] = block;
        }
    }
}

/// Keeps the active set of a solve: an impact's for the force solve after it, an
/// acceleration-level or time-stepping one's for the next step's.
pub fn record_warm(data: &mut World<'_>, level: Level) {
    if level == Level::Velocity {
        data.constraints.solve.impact_warm.clear();
        data.constraints.solve.impact_warm.extend(data.constraints.solve.force.iter().map(|&f| f > 0.0));
    } else {
        data.constraints.history.warm.clear();
        data.constraints.history.warm.extend(data.constraints.solve.force.iter().map(|&f| f > 0.0));
        data.constraints.history.warm_rows.clear();
        for j in 0..data.constraints.con.len() {
            let key = row_key(&data.constraints.con, &data.coll.contacts, j);
            data.constraints.history.warm_rows.push(key);
        }
    }
}

/// Identity of row j across steps ([`RowKey`]).
pub fn row_key(con: &ConstraintData, contacts: &[collision::Contact], j: usize) -> RowKey {
    match con.kind[j] {
        RowKind::Limit => RowKey::Limit { joint: con.source[j], lower: con.dof[j].1 > 0.0 },
        RowKind::Motion { bounded } => RowKey::Motion { actuator: con.source[j], bounded, positive: con.dof[j].1 > 0.0 },
        RowKind::DryFriction => RowKey::DryFriction { dof: con.source[j], positive: con.dof[j].1 > 0.0 },
        RowKind::Equality => RowKey::Equality { equality: con.source[j], positive: con.dof[j].1 > 0.0 },
        RowKind::Connect { .. } => RowKey::Connect { axis: con.source[j], positive: con.mirror[j] == usize::MAX },
        kind => {
            let c = &contacts[con.source[j]];
            let (within, cone) = match kind {
                RowKind::Tangent { normal } => (j - normal, 0),
                RowKind::Spin { normal, cone } => (j - normal, cone - normal),
                _ => (0, 0),
            };
            RowKey::Contact { geom1: c.geom1, geom2: c.geom2, feature: c.feature, within, cone }
        }
    }
}

/// The work the last solve's rows do over the step toward targets that ask for energy: a
/// contact or limit removing the penetration the step began with (impulse times the correction
/// velocity), an equality removing its error (impulse times −d/lever), and motion control, whose
/// work Σ p (v + v⁺) / 2 is counted whole (v⁺ its end-of-step velocity, w = 0 where it
/// pushes). The rows' other work (stopping an approach, friction, the arc terms that keep a
/// turning body's point on the surface) is not positive in the exact motion. `level`: the
/// solve applied (acceleration or time step).
pub fn correction_work(m: &Model, data: &World<'_>, level: Level) -> f64 {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let (con, solve) = (&data.constraints.con, &data.constraints.solve);
    let mut work = 0.0;
    for j in (0..con.len()).filter(|&j| solve.force[j] != 0.0) {
        let impulse = if level == Level::Acceleration { h * solve.force[j] } else { solve.force[j] };
        work += impulse * match con.kind[j] {
            RowKind::Normal | RowKind::Limit if con.dist[j] <= 0.0 => correction_velocity(corrected_start(con.kind[j], con.dist_start[j]).min(0.0), h),
            RowKind::Equality | RowKind::Connect { .. } => -con.dist[j] / lever,
            RowKind::Motion { .. } => {
                // a = K f + b = b − q where the row pushes
                let (vel, b, q) = (con.vel[j], con.b[j], solve.q[j]);
                let end = if level == Level::Acceleration { vel + h * (b - q) } else { vel + h * b - q };
                0.5 * (vel + end)
            }
            _ => 0.0,
        };
    }
    work
}

/// q̈ += scale · Σ_k f_k Δq̈⁽ᵏ⁾.
pub fn apply_to_qacc(m: &Model, data: &mut World<'_>, scale: f64) {
    let mut qacc = std::mem::take(&mut data.dynamics.qacc);
    apply(m, data, &mut qacc, scale);
    data.dynamics.qacc = qacc;
}

/// target += scale · Σ_k f_k Δq̈⁽ᵏ⁾ (forces into accelerations, or impulses into velocities).
pub fn apply(m: &Model, data: &World<'_>, target: &mut [f64], scale: f64) {
    let nv = m.nv;
    for k in 0..data.constraints.con.len() {
        let f = data.constraints.solve.force[k] * scale;
        if f != 0.0 {
            add_response(m, data.constraints.con.tree[k], f, &data.constraints.con.dqdd[k * nv..(k + 1) * nv], target);
        }
    }
}
