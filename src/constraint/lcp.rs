//! The LCP solver of stages 6, 7 and 9 — the mixed LCP  w = M z + q,  z ≥ 0 ⟂ w ≥ 0, by Lemke's complementary pivoting.
//!
//! Why Lemke: the seed's friction rows (Kokkevis 2004, eqs. 19–21) make M non-symmetric and not
//! positive definite ([[K_nn, K_nt, 0], [K_tn, K_tt, 1], [μ, −1, 0]] per contact), so Dantzig-style
//! principal pivoting has no guarantee; Lemke's method is the textbook solver for this form
//! (Cottle, Pang & Stone, *The Linear Complementarity Problem*, 1992, §4.4). Redundant rows (four
//! coplanar box corners) make K singular; a tiny diagonal regulariser keeps pivots finite. Every
//! accepted solution is checked independently (w = M z + q recomputed); on failure the cascade
//! retries Lemke with a 100× regulariser (redundant contacts sharing a tangential demand can end
//! the first path on a ray), then once more covering the λ rows too, each answer checked against
//! the unregularised problem, then falls back to projected Gauss–Seidel on the same conditions,
//! whose answer is solved again from its active set (often exactly: PGS is near the solution even
//! where Lemke's path fails), then to zero force.
//!
//! Before any of that, the rows the caller marks as needing no force (which ones is
//! `solve.rs`'s policy) are left out: the cascade solves the principal subproblem without them
//! (a contact's friction rows and λ go with its normal); a left-out normal, or friction row of a
//! kept contact, whose w the answer makes negative is brought back and the caller solves again.
//! The answer solves the whole LCP: a left-out row has z = 0 and w ≥ 0, a left-out contact's
//! friction rows z = 0 and the λ that keeps their w ≥ 0, and no λ reaches a row outside its
//! contact.
//!
//! Files: this one poses the cascade (islands, left-out rows, the order of attempts); `lemke`
//! pivots, `active_set` solves on a guessed active set (warm start, polish), `pgs` is the
//! fallback.

/// One LCP w = M z + q over `n` variables (M n × n, row-major), with each variable's role.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    /// Number of variables.
    pub n: usize,
    /// M (n × n, row-major).
    pub m: &'a [f64],
    /// q (n).
    pub q: &'a [f64],
    /// What each variable is (n).
    pub role: &'a [Role],
}

/// Counters Python can read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LcpStats {
    /// LCP solves attempted (one per island of touching trees).
    pub solves: u64,
    /// Total Lemke pivots, of the attempts that found no answer too.
    pub pivots: u64,
    /// Solves settled by the previous step's active set, without pivoting.
    pub warm_starts: u64,
    /// Solves settled by a later Lemke attempt (more strongly regularised; then also covering λ;
    /// then with λ's diagonal stiffened too).
    pub retries: u64,
    /// Solves whose Lemke attempts failed the check, settled exactly (passing it) from projected
    /// Gauss–Seidel's answer.
    pub rescued: u64,
    /// Solves that fell back to projected Gauss–Seidel's answer, which fails the check.
    pub fallback_pgs: u64,
    /// Solves that kept a Lemke solution failing the check because it beat the fallback.
    pub inexact: u64,
    /// Solves that fell back to zero force.
    pub fallback_zero: u64,
    /// Steps whose force LCP had no exact answer (a configuration of Painlevé's, a pile's
    /// redundant contacts), solved as impulses over the step instead (`step::constrain`); their
    /// force solves' fallbacks are not counted above.
    pub impulse_steps: u64,
    /// Variables (rows and their λ) left out of solves as needing no force, summed over solves.
    pub left_out: u64,
    /// Times an answer pushed into a left-out row, which was brought back and the problem solved
    /// again.
    pub regrown: u64,
    /// Largest complementarity/feasibility residual of an accepted solution (last solve).
    pub residual: f64,
}

/// Reusable storage for the solver.
#[derive(Clone, Debug, Default)]
pub struct LcpWork {
    /// Whether the caller replaces an inexact answer (the force solve, by the step's impulses):
    /// projected Gauss–Seidel then stops sooner (`pgs::PGS_SWEEPS_BEFORE_FALLBACK`).
    pub fallback_follows: bool,
    tab: Vec<f64>,
    basis: Vec<usize>,
    /// Tableau column of each variable (usize::MAX while basic).
    column: Vec<usize>,
    w: Vec<f64>,
    /// The nonzero variables of an answer being checked ([`residual`]).
    nz: Vec<usize>,
    active: Vec<usize>,
    /// The active variables and pinned forces of an active-set solve with forces pinned, in
    /// order: where its answer may be nonzero besides λ and the slacks.
    support: Vec<usize>,
    trial: Vec<f64>,
    stiff: Vec<f64>,
    best: Vec<f64>,
    /// λ variables [`solve_on`] leaves out of the solve.
    free: Vec<bool>,
    /// The warm start's guessed active set.
    guess: Vec<bool>,
    /// The sets of [`settle`]'s passes so far, one after another.
    seen: Vec<bool>,
    /// The λ (σ) variables with an active row ([`settle`]).
    used: Vec<bool>,
    /// Candidate rows of the ratio test.
    cand: Vec<usize>,
    /// The bases a Lemke path has met, as Zobrist hashes ([`lemke`]).
    bases: Vec<u64>,
    /// Projected Gauss–Seidel's sums of each λ's friction forces.
    pgs_sum: Vec<f64>,
    /// Bounded forces an active-set solve holds at their caps, with their slacks, and which
    /// variables those are.
    pinned: Vec<(usize, usize)>,
    guess_pinned: Vec<bool>,
    /// The subproblem without the rows that need no force.
    sub: Subproblem,
    /// One island of it ([`islands`]), the union–find forest that finds them from M, and the
    /// variables ordered island by island.
    island: Subproblem,
    parent: Vec<usize>,
    order: Vec<usize>,
}

/// A principal subproblem: the LCP on the variables `keep`, numbered in that order.
#[derive(Clone, Debug, Default)]
struct Subproblem {
    /// Variable of the whole problem of each kept one.
    keep: Vec<usize>,
    /// Number in the subproblem of each variable of the whole problem (kept ones only).
    index: Vec<usize>,
    m: Vec<f64>,
    q: Vec<f64>,
    role: Vec<Role>,
    warm: Vec<bool>,
    z: Vec<f64>,
    /// After an answer that brought rows back: its active set and those rows, which warm-start
    /// the next solve (the same problem with more rows kept); empty otherwise.
    retry: Vec<bool>,
    /// The rows the last answer brought back.
    brought: Vec<usize>,
    /// The kept variables with a nonzero answer ([`Subproblem::bring_back`]).
    pressing: Vec<usize>,
}

/// Relative regulariser added to the diagonal of the force rows.
pub const REGULARISATION: f64 = 1e-8;
/// Relative regulariser of the second Lemke attempt on a degenerate problem.
pub const RETRY_REGULARISATION: f64 = 1e-6;
/// Largest scaled residual of an accepted solution (tableau round-off on degenerate problems,
/// such as four coplanar corners, stays around 1e-6).
pub const ACCEPT_RESIDUAL: f64 = 1e-5;
/// Pivot cap of one Lemke attempt, as a multiple of the problem size (plus 10). Accepted answers
/// took at most 4.7 n pivots (gymnasium's, dm_control's and Playground's tasks under random
/// actions, the contact-scene tests); a path beyond that cycles on round-off in a degenerate
/// problem and ends at the cap, which then bounds the cost before the regularised retry (at
/// 50 n, one step of Menagerie's G1 with hands spent 10,610 pivots there: 64 ms, 400× its
/// median step).
pub const PIVOT_CAP_PER_ROW: usize = 10;

/// Independent check: max over rows of violations of z ≥ 0, w ≥ 0 and z·w = 0, scaled. `w`
/// receives w = M z + q, summed over the nonzero z (listed in `nz`; an active set is usually a
/// small part of the variables).
pub fn residual(n: usize, m: &[f64], q: &[f64], z: &[f64], (w, nz): (&mut Vec<f64>, &mut Vec<usize>)) -> f64 {
    w.clear();
    nz.clear();
    nz.extend((0..n).filter(|&j| z[j] != 0.0));
    let mut worst = 0.0f64;
    for (i, row) in m[..n * n].chunks_exact(n).enumerate() {
        // four partial sums: the additions of one row overlap instead of waiting on each other
        let (mut sum, mut abs) = ([0.0; 4], [0.0; 4]);
        let quads = nz.chunks_exact(4);
        let rest = quads.remainder();
        for quad in quads {
            for (l, &j) in quad.iter().enumerate() {
                let a = row[j] * z[j];
                sum[l] += a;
                abs[l] += a.abs();
            }
        }
        for (l, &j) in rest.iter().enumerate() {
            let a = row[j] * z[j];
            sum[l] += a;
            abs[l] += a.abs();
        }
        let wi = q[i] + ((sum[0] + sum[1]) + (sum[2] + sum[3]));
        let scale = 1.0 + q[i].abs() + ((abs[0] + abs[1]) + (abs[2] + abs[3]));
        worst = worst.max((-z[i]).max(0.0)).max((-wi).max(0.0) / scale).max((z[i] * wi).abs() / scale);
        w.push(wi);
    }
    if worst.is_nan() { f64::INFINITY } else { worst }
}

/// Solves the LCP on the variables not marked in `out` (which the caller sizes to n or leaves
/// empty: nothing left out), holding the others at zero (module docs); a contact's friction rows
/// and λ follow its normal. With `split`, the problem is solved island by island (`islands`);
/// a caller that already solves each island alone (the step, by its rows' trees) passes false. False when the answer pushed into a left-out normal: that row and its contact are then
/// unmarked in `out` (every row, if this was already such a second solve), their columns of M
/// are needed, and the caller solves again, which starts from this answer's active set plus the
/// rows brought back (of this attempt, the statistics keep its pivots and count it in
/// `regrown`).
pub fn solve(p: Problem<'_>, split: bool, warm: Option<&[bool]>, out: &mut Vec<bool>, z: &mut [f64], work: &mut LcpWork, stats: &mut LcpStats) -> bool {
    let Problem { n, m, q, role } = p;
    let start = *stats;
    stats.solves += 1;
    let mut sub = std::mem::take(&mut work.sub);
    // a solve again after bringing rows back starts from the last answer's active set
    let mut retry = std::mem::take(&mut sub.retry);
    let retrying = retry.len() == n;
    let warm = if retrying { Some(&retry[..]) } else { warm };
    out.resize(n, false);
    for i in 0..n {
        if let Role::Friction { normal, lambda, .. } = role[i] {
            (out[i], out[lambda]) = (out[i] || out[normal], out[normal]);
        }
    }
    if !out.contains(&true) {
        islands(p, split, warm, z, work, stats);
        retry.clear();
        sub.retry = retry;
        work.sub = sub;
        return true;
    }
    sub.keep.clear();
    sub.keep.extend((0..n).filter(|&i| !out[i]));
    let k = sub.keep.len();
    sub.gather(n, m, q, role, warm);
    let Subproblem { m: sm, q: sq, role: sr, warm: sw, z: sz, .. } = &mut sub;
    if k > 0 {
        islands(Problem { n: k, m: sm, q: sq, role: sr }, split, warm.map(|_| &sw[..]), sz, work, stats);
    } else {
        stats.residual = 0.0;
    }
    z[..n].fill(0.0);
    for (r, &i) in sub.keep.iter().enumerate() {
        z[i] = sub.z[r];
    }
    let solved = !sub.bring_back(n, m, q, role, out, z);
    if !solved && retrying {
        // a second round: every row comes back (a pile of bodies can push one after another)
        out.fill(false);
    }
    retry.clear();
    if !solved {
        // the answer's active set, and the normals brought back
        retry.extend((0..n).map(|i| z[i] > 0.0));
        for &i in &sub.brought {
            retry[i] = true;
        }
    }
    sub.retry = retry;
    if solved {
        stats.left_out += (n - k) as u64;
        // each left-out contact's λ: the least that keeps its friction rows' w ≥ 0 (a kept
        // contact's left-out friction rows have w ≥ 0 with its λ: `bring_back`)
        for i in 0..n {
            if let Role::Friction { lambda, .. } = role[i]
                && out[i]
                && out[lambda]
            {
                z[lambda] = z[lambda].max(-left_out_w(n, m, q, z, &sub.pressing, i).0);
            }
        }
    } else {
        *stats = LcpStats { pivots: stats.pivots, regrown: start.regrown + 1, ..start };
    }
    work.sub = sub;
    solved
}

impl LcpStats {
    /// Adds `o`'s counters to these; the residual becomes the larger of the two.
    pub fn add(&mut self, o: &LcpStats) {
        let LcpStats { solves, pivots, warm_starts, retries, rescued, fallback_pgs, inexact, fallback_zero, impulse_steps, left_out, regrown, residual } = *o;
        self.solves += solves;
        self.pivots += pivots;
        self.warm_starts += warm_starts;
        self.retries += retries;
        self.rescued += rescued;
        self.fallback_pgs += fallback_pgs;
        self.inexact += inexact;
        self.fallback_zero += fallback_zero;
        self.impulse_steps += impulse_steps;
        self.left_out += left_out;
        self.regrown += regrown;
        self.residual = self.residual.max(residual);
    }

    /// Whether a solve since `before` kept an answer that fails the check (or zero force).
    pub fn inexact_since(&self, before: &LcpStats) -> bool {
        (self.fallback_pgs, self.inexact, self.fallback_zero) != (before.fallback_pgs, before.inexact, before.fallback_zero)
    }
}

impl Subproblem {
    /// The kept rows' M, q, roles (renumbered) and warm set.
    fn gather(&mut self, n: usize, m: &[f64], q: &[f64], role: &[Role], warm: Option<&[bool]>) {
        let k = self.keep.len();
        self.index.clear();
        self.index.resize(n, usize::MAX);
        for (r, &i) in self.keep.iter().enumerate() {
            self.index[i] = r;
        }
        self.m.clear();
        self.q.clear();
        self.role.clear();
        self.warm.clear();
        for &i in &self.keep {
            self.m.extend(self.keep.iter().map(|&j| m[i * n + j]));
            self.q.push(q[i]);
            self.role.push(match role[i] {
                Role::Friction { normal, lambda, mu } => Role::Friction { normal: self.index[normal], lambda: self.index[lambda], mu },
                Role::Bounded { lambda, cap } => Role::Bounded { lambda: self.index[lambda], cap },
                r => r,
            });
            if let Some(w) = warm.filter(|w| w.len() == n) {
                self.warm.push(w[i]);
            }
        }
        self.z.clear();
        self.z.resize(k, 0.0);
    }

    /// Unmarks in `out` each left-out normal row, with its contact, and each left-out friction row
    /// of a kept contact, whose w the answer `z` makes negative (beyond round-off), listing them
    /// in `brought`; whether there was one.
    fn bring_back(&mut self, n: usize, m: &[f64], q: &[f64], role: &[Role], out: &mut [bool], z: &[f64]) -> bool {
        self.brought.clear();
        // the kept variables with a nonzero answer: w of a left-out row sums over these
        let pressing = &mut self.pressing;
        pressing.clear();
        pressing.extend(self.keep.iter().copied().filter(|&j| z[j] != 0.0));
        for i in 0..n {
            let checked = match role[i] {
                Role::Normal => true,
                // its w counts the contact's λ, which is kept
                Role::Friction { normal, .. } => !out[normal],
                _ => false,
            };
            if !out[i] || !checked {
                continue;
            }
            let (wi, scale) = left_out_w(n, m, q, z, pressing, i);
            if wi < -LEFT_OUT_TOLERANCE * scale || wi.is_nan() {
                out[i] = false;
                self.brought.push(i);
            }
        }
        // a normal brought back brings its friction rows and λ
        for i in 0..n {
            if let Role::Friction { normal, lambda, .. } = role[i]
                && out[lambda]
                && !out[normal]
            {
                out[i] = false;
                out[lambda] = false;
            }
        }
        !self.brought.is_empty()
    }
}

/// w_i of a left-out row from the answer `z`, whose nonzero kept variables are `pressing`, and
/// its scale as in [`residual`].
fn left_out_w(n: usize, m: &[f64], q: &[f64], z: &[f64], pressing: &[usize], i: usize) -> (f64, f64) {
    pressing.iter().fold((q[i], 1.0 + q[i].abs()), |(w, scale), &j| {
        let a = m[i * n + j] * z[j];
        (w + a, scale + a.abs())
    })
}

/// Solves the LCP island by island. Variables couple when M has an entry between them; rows of
/// bodies that touch neither each other nor a common body share none (K = J M⁻¹ Jᵀ is zero
/// between separate trees), so a pile of separate bodies splits into independent LCPs, each
/// solved by [`cascade`] at its own size's cost instead of the whole's. The islands are found
/// from M's entries by union–find, unless not `split`. One island is solved as it is.
fn islands(p: Problem<'_>, split: bool, warm: Option<&[bool]>, z: &mut [f64], work: &mut LcpWork, stats: &mut LcpStats) {
    let Problem { n, m, q, role } = p;
    if !split || couplings(n, m, &mut work.parent) {
        cascade(p, warm, z, work, stats);
        return;
    }
    // the variables island by island (by root), each island's in their order
    let (label, order) = (&work.parent, &mut work.order);
    order.clear();
    order.extend(0..n);
    order.sort_unstable_by_key(|&i| (label[i], i));
    let mut island = std::mem::take(&mut work.island);
    let mut worst = 0.0f64;
    let mut start = 0;
    while start < n {
        let l = work.parent[work.order[start]];
        let end = (start..n).find(|&k| work.parent[work.order[k]] != l).unwrap_or(n);
        island.keep.clear();
        island.keep.extend_from_slice(&work.order[start..end]);
        island.gather(n, m, q, role, warm);
        let k = island.keep.len();
        let Subproblem { m: im, q: iq, role: ir, warm: iw, z: iz, .. } = &mut island;
        cascade(Problem { n: k, m: im, q: iq, role: ir }, warm.map(|_| &iw[..]), iz, work, stats);
        worst = worst.max(stats.residual);
        for (k, &i) in island.keep.iter().enumerate() {
            z[i] = island.z[k];
        }
        start = end;
    }
    stats.residual = worst;
    work.island = island;
}

/// Labels each variable with its island's root (union–find over M's nonzero entries) into
/// `parent`; whether everything is one island. The scan stops once it is: for one body's
/// contacts (every gymnasium task) that is within the first row, O(n) and not O(n²).
fn couplings(n: usize, m: &[f64], parent: &mut Vec<usize>) -> bool {
    parent.clear();
    parent.extend(0..n);
    let mut groups = n;
    for i in 0..n {
        for j in i + 1..n {
            if m[i * n + j] != 0.0 || m[j * n + i] != 0.0 {
                let (a, b) = (root(parent, i), root(parent, j));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                    groups -= 1;
                    if groups == 1 {
                        return true;
                    }
                }
            }
        }
    }
    for i in 0..n {
        parent[i] = root(parent, i);
    }
    groups <= 1
}

/// The root of i's set in the union–find forest `parent` (halving the path on the way).
pub(super) fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Largest scaled negative w a left-out row may be left with (round-off).
const LEFT_OUT_TOLERANCE: f64 = 1e-12;

/// Solves with the cascade warm start → Lemke → Lemke more strongly regularised → Lemke covering
/// λ → Lemke with λ's diagonal stiffened → projected Gauss–Seidel, polished from its active set (or Lemke's inexact answer when that
/// has the smaller residual) → zero; counts the path in `stats`. `warm`, when given, is the
/// previous step's active set for the same rows: if solving on it directly passes the independent
/// check, no pivoting is needed (resting contacts).
fn cascade(p: Problem<'_>, warm: Option<&[bool]>, z: &mut [f64], work: &mut LcpWork, stats: &mut LcpStats) {
    let Problem { n, m, q, role } = p;
    if let Some(prev) = warm.filter(|w| w.len() == n)
        && let Some(res) = settle(n, m, q, role, prev.iter().copied(), WARM_PASSES, work)
    {
        z[..n].copy_from_slice(&work.trial);
        stats.warm_starts += 1;
        stats.residual = res;
        return;
    }
    // Lemke; once more with a stronger regulariser when its answer fails the check (redundant
    // contacts sharing their demand can end the path on a ray), once more covering every row,
    // λ too (which ends some of those paths elsewhere), and once more with λ's and σ's diagonal
    // stiffened as well: the matrix is then strictly copositive, for which Lemke's path cannot
    // end on a ray (Cottle, Pang & Stone 1992, Thm 4.4.13) — the rays left were a λ with no
    // friction force; each answer polished and checked against the problem as posed; the best
    // failing answer is kept in `best`
    let mut stiff = std::mem::take(&mut work.stiff);
    let mut lemke_res = f64::INFINITY;
    for attempt in 0..4 {
        let retry = attempt > 0;
        if attempt == 1 {
            stiff.clear();
            stiff.extend_from_slice(&m[..n * n]);
            for i in (0..n).filter(|&i| role[i] != Role::Lambda) {
                stiff[i * n + i] += RETRY_REGULARISATION * m[i * n + i].abs();
            }
        }
        if attempt == 3 {
            // w_λ = μ f_n − Σ f_t + ε λ: the cone exceeded by ε λ while sliding, ε a millionth of
            // the inverse of the friction row's own K (its force per unit acceleration)
            for i in 0..n {
                if let Role::Friction { lambda, .. } | Role::Bounded { lambda, .. } = role[i]
                    && m[i * n + i] > 0.0
                {
                    let eps = RETRY_REGULARISATION / m[i * n + i];
                    stiff[lambda * n + lambda] = stiff[lambda * n + lambda].max(eps);
                }
            }
        }
        let uncovered = |i: usize| attempt < 2 && role[i] == Role::Lambda;
        let p = lemke(n, if retry { &stiff } else { m }, q, uncovered, z, work);
        stats.pivots += p.unwrap_or_else(|spent| spent) as u64;
        if p.is_err() {
            continue;
        }
        let res = polish(n, m, q, role, z, work);
        if res <= ACCEPT_RESIDUAL {
            work.stiff = stiff;
            stats.retries += retry as u64;
            stats.residual = res;
            return;
        }
        if res < lemke_res {
            lemke_res = res;
            work.best.clear();
            work.best.extend_from_slice(&z[..n]);
        }
    }
    work.stiff = stiff;
    // Lemke failed the check: projected Gauss–Seidel, polished (near the solution, its active set
    // often settles it exactly), unless Lemke's answer was the closer one
    let sweeps = if work.fallback_follows { PGS_SWEEPS_BEFORE_FALLBACK } else { PGS_SWEEPS };
    if pgs(n, m, q, role, z, &mut work.pgs_sum, sweeps) {
        let pgs_res = polish(n, m, q, role, z, work);
        if pgs_res <= lemke_res {
            if pgs_res <= ACCEPT_RESIDUAL {
                stats.rescued += 1;
            } else {
                stats.fallback_pgs += 1;
            }
            stats.residual = pgs_res;
        } else {
            z[..n].copy_from_slice(&work.best);
            stats.inexact += 1;
            stats.residual = lemke_res;
        }
        return;
    }
    if lemke_res.is_finite() {
        z[..n].copy_from_slice(&work.best);
        stats.inexact += 1;
        stats.residual = lemke_res;
        return;
    }
    stats.fallback_zero += 1;
    z[..n].fill(0.0);
    stats.residual = 0.0;
}


/// What an LCP variable is, for the projected Gauss–Seidel fallback.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// A normal or limit force: z ≥ 0.
    Normal,
    /// A friction force bounded by μ times the force of variable `normal`; its λ is `lambda`.
    Friction {
        /// The normal force's variable.
        normal: usize,
        /// The λ variable shared by the contact's friction rows.
        lambda: usize,
        /// Friction coefficient.
        mu: f64,
    },
    /// A force bounded by the constant `cap`, whose slack variable is `lambda`: the slack's row
    /// is w_σ = cap − f (its only entry −1 at the force) and its column only the force's row's +1.
    Bounded {
        /// The slack variable.
        lambda: usize,
        /// Largest force.
        cap: f64,
    },
    /// The auxiliary λ of eq. (21), or the slack of a bounded force.
    Lambda,
}


mod active_set;
mod lemke;
mod pgs;

use active_set::{polish, settle, WARM_PASSES};
pub use lemke::lemke;
use pgs::{pgs, PGS_SWEEPS, PGS_SWEEPS_BEFORE_FALLBACK};
#[cfg(test)]
mod tests;
