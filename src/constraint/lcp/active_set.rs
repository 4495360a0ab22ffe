//! Solving on a guessed active set: the warm start from the last step's set, and the polish of
//! a pivoting answer (the rows with force solved as equations, checked independently).

use super::lemke::sub_scaled;
use super::{residual, LcpWork, Role, ACCEPT_RESIDUAL};

/// Scaled w (as in [`residual`]) below which [`settle`] adds an inactive friction row. Redundant
/// contacts (the corners under a box) share their tangential load in many ways: dropping a force
/// that an answer left a round-off below zero leaves its row's w a round-off below zero, and
/// adding it back then cycles. Other rows are added at any negative w.
const ADD_TOLERANCE: f64 = 1e-9;

/// Active-set passes from a warm guess at most (each one solve on the set): in a pile, where
/// contacts come and go, 8 passes settle a fifth more solves than 3 and halve Lemke's pivots
/// (`scene_step` counters); single characters hardly need more than 3.
pub(super) const WARM_PASSES: usize = 8;
/// Active-set passes polishing an answer at most (the first pass accepts a good answer).
const POLISH_PASSES: usize = 10;

/// The warm start: solves on the guessed active set `start`; while the answer fails the check,
/// drops the variables it makes negative and adds those whose w it makes negative (a friction
/// row's beyond [`ADD_TOLERANCE`]), with the friction rows of a contact left without normal force
/// and the λ (σ) left without an active row, and solves again, up to `passes` times (a contact the
/// last step or this step's impact left inactive now pressing, a joint now driven into its limit);
/// a set met before ends it (the passes cycle), with the answer the last pass would have left.
/// The residual of an answer in `work.trial` that passes the independent check, or None.
pub(super) fn settle(n: usize, m: &[f64], q: &[f64], role: &[Role], start: impl Iterator<Item = bool>, passes: usize, work: &mut LcpWork) -> Option<f64> {
    let mut guess = std::mem::take(&mut work.guess);
    guess.clear();
    guess.extend(start.take(n));
    // every pass's set, to recognise a cycle
    let mut seen = std::mem::take(&mut work.seen);
    seen.clear();
    let mut settled = None;
    for pass in 0..passes {
        // a set met before repeats the passes since: they did not settle, nor will they
        if let Some(first) = seen.chunks_exact(n.max(1)).position(|s| s == &guess[..]) {
            // the answer of the last pass the cycle would have run (a polish keeps it)
            let last = first + (passes - 1 - first) % (pass - first);
            guess.copy_from_slice(&seen[last * n..(last + 1) * n]);
            solve_on(n, m, q, role, |i| guess[i], work);
            break;
        }
        seen.extend_from_slice(&guess);
        if !solve_on(n, m, q, role, |i| guess[i], work) {
            break;
        }
        let res = residual(n, m, q, &work.trial, (&mut work.w, &mut work.nz));
        if res <= ACCEPT_RESIDUAL && work.trial.iter().all(|&x| x >= 0.0) {
            settled = Some(res);
            break;
        }
        let mut changed = false;
        // w_i below zero beyond round-off, scaled as in `residual`
        let pressing = |i: usize| work.w[i] < -ADD_TOLERANCE * (1.0 + q[i].abs() + work.nz.iter().map(|&j| (m[i * n + j] * work.trial[j]).abs()).sum::<f64>());
        for i in 0..n {
            let now = if guess[i] && !work.free[i] { work.trial[i] > 0.0 } else { work.trial[i] > 0.0 || (work.w[i] < 0.0 && (!matches!(role[i], Role::Friction { .. }) || pressing(i))) };
            changed |= now != guess[i];
            guess[i] = now;
        }
        // a bounded force joining the set at its cap: when the force that would zero its own w
        // alone, −w_i / M_ii, exceeds the cap, it joins pinned there (its slack active), a pass
        // sooner than the solve free of the cap would show it (a joint starting to slide)
        for i in 0..n {
            if let Role::Bounded { lambda, cap } = role[i]
                && guess[i]
                && !guess[lambda]
                && work.trial[i] == 0.0
                && -work.w[i] > cap * m[i * n + i]
            {
                guess[lambda] = true;
            }
        }
        // a contact without normal force has no friction force (|f_t| ≤ μ f_n); one that starts
        // pressing starts sticking too, on the rows its tangential demand pushes against (their
        // w without λ, which was free while the normal was inactive, below zero)
        for i in 0..n {
            if let Role::Friction { normal, lambda, .. } = role[i] {
                if guess[i] && !guess[normal] {
                    guess[i] = false;
                    changed = true;
                } else if !guess[i] && guess[normal] && work.free[lambda] && work.w[i] - work.trial[lambda] < 0.0 {
                    guess[i] = true;
                }
            }
        }
        // a λ (σ) is positive only with one of its rows at the bound (else its column in M_AA is
        // zero): without one active, it goes too
        let used = &mut work.used;
        used.clear();
        used.resize(n, false);
        for i in 0..n {
            if let Role::Friction { lambda, .. } | Role::Bounded { lambda, .. } = role[i]
                && guess[i]
            {
                used[lambda] = true;
            }
        }
        for i in 0..n {
            if role[i] == Role::Lambda && guess[i] && !used[i] {
                guess[i] = false;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    work.guess = guess;
    work.seen = seen;
    settled
}

/// Solves on the active set {i : `active(i)`} into `work.trial`: M_AA z_A = −q_A, z = 0 elsewhere.
/// The λ of a contact whose normal force is inactive is not fixed by its own row (μ·0 − Σ 0 = 0
/// for any λ, so M_AA would be singular): it is left out and set afterwards to the least value
/// that keeps the contact's friction rows' w ≥ 0. False when singular or non-finite; the result
/// may be negative.
fn solve_on(n: usize, m: &[f64], q: &[f64], role: &[Role], active: impl Fn(usize) -> bool, work: &mut LcpWork) -> bool {
    work.free.clear();
    work.free.resize(n, false);
    for r in role {
        if let Role::Friction { normal, lambda, .. } = *r
            && !active(normal)
        {
            work.free[lambda] = true;
        }
    }
    // a bounded force with its slack active is at its cap (w_σ = cap − f = 0): it is set, not
    // solved for (σ's row and column hold only their ∓1: `Role::Bounded`)
    work.pinned.clear();
    work.guess_pinned.clear();
    work.guess_pinned.resize(n, false);
    for (i, r) in role.iter().enumerate() {
        if let Role::Bounded { lambda: s, .. } = *r
            && active(i)
            && active(s)
        {
            debug_assert!(m[s * n + i] == -1.0 && m[i * n + s] == 1.0 && m[s * n + s] == 0.0);
            work.pinned.push((i, s));
            (work.guess_pinned[i], work.guess_pinned[s]) = (true, true);
        }
    }
    work.active.clear();
    let pinned = &work.guess_pinned;
    work.active.extend((0..n).filter(|&i| active(i) && !work.free[i] && !pinned[i]));
    if !solve_active(n, m, q, work) {
        return false;
    }
    for i in 0..n {
        if let Role::Friction { lambda, .. } = role[i]
            && work.free[lambda]
        {
            // w_i without λ's own contribution (M_iλ = 1), over the forces the solve set (the
            // row has no entry at another contact's λ or at a slack)
            let set = if work.pinned.is_empty() { &work.active } else { &work.support };
            let wi = q[i] + set.iter().map(|&j| m[i * n + j] * work.trial[j]).sum::<f64>();
            work.trial[lambda] = work.trial[lambda].max(-wi);
        }
    }
    true
}

/// Solves M_AA z_A = −q_A on the active set `work.active` (z = 0 elsewhere) into `work.trial` by
/// Gaussian elimination with partial pivoting and back substitution, with each pinned force of
/// `work.pinned` at its cap (q of its slack) and the slack from the force's own row. False when
/// singular or non-finite.
fn solve_active(n: usize, m: &[f64], q: &[f64], work: &mut LcpWork) -> bool {
    let LcpWork { tab: a, active, trial, pinned, support, .. } = work;
    let k = active.len();
    trial.clear();
    trial.resize(n, 0.0);
    for &(f, s) in pinned.iter() {
        trial[f] = q[s];
    }
    // augmented k × (k + 1) system in the tableau buffer, the pinned forces moved to the right
    let w = k + 1;
    a.clear();
    for &i in active.iter() {
        let row = &m[i * n..(i + 1) * n];
        a.extend(active.iter().map(|&j| row[j]));
        a.push(-q[i] - pinned.iter().map(|&(f, _)| row[f] * trial[f]).sum::<f64>());
    }
    if !eliminate_wide(a, k) {
        return false;
    }
    // back substitution
    for r in (0..k).rev() {
        let row = &a[r * w..(r + 1) * w];
        let mut x = row[k];
        for (c, &i) in active.iter().enumerate().skip(r + 1) {
            x -= row[c] * trial[i];
        }
        trial[active[r]] = x * row[r];
    }
    // with forces pinned, the variables z may be nonzero at besides λ and the slacks, in order:
    // the rows of M_AA and the pinned forces (without, the active set alone)
    support.clear();
    if !pinned.is_empty() {
        support.extend(active.iter().copied());
        support.extend(pinned.iter().map(|&(f, _)| f));
        support.sort_unstable();
    }
    // each slack: what keeps its force's row at w = 0 (M_fσ = 1; a force's row has no entry at
    // another force's slack)
    for &(f, s) in pinned.iter() {
        let row = &m[f * n..(f + 1) * n];
        trial[s] = -q[f] - support.iter().map(|&j| row[j] * trial[j]).sum::<f64>();
    }
    trial.iter().all(|x| x.is_finite())
}

/// Forward elimination with partial pivoting of the augmented k × (k + 1) system `a`, each pivot
/// replaced by its reciprocal (for the back substitution); false when singular.
#[inline(always)]
pub(super) fn eliminate(a: &mut [f64], k: usize) -> bool {
    let w = k + 1;
    for c in 0..k {
        let p = (c..k).max_by(|&x, &y| a[x * w + c].abs().total_cmp(&a[y * w + c].abs())).unwrap();
        if a[p * w + c].abs() < 1e-300 {
            return false;
        }
        if p != c {
            let (top, bottom) = a.split_at_mut(p * w);
            top[c * w..(c + 1) * w].swap_with_slice(&mut bottom[..w]);
        }
        // eliminate column c below the pivot
        let (upper, lower) = a[..k * w].split_at_mut((c + 1) * w);
        let prow = &mut upper[c * w + c..(c + 1) * w];
        let inv = 1.0 / prow[0];
        for row in lower.chunks_exact_mut(w) {
            let f = row[c] * inv;
            if f != 0.0 {
                sub_scaled(&mut row[c..], f, prow);
            }
        }
        prow[0] = inv;
    }
    true
}

/// [`eliminate`], compiled for AVX2 as well, as [`pivot_wide`].
pub(super) fn eliminate_wide(a: &mut [f64], k: usize) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        fn avx2(a: &mut [f64], k: usize) -> bool {
            eliminate(a, k)
        }
        // SAFETY: the processor has AVX2, checked just above
        return unsafe { avx2(a, k) };
    }
    eliminate(a, k)
}

/// Re-solves from Lemke's active set A = {z > 0} ([`settle`]), removing the round-off the tableau
/// accumulates on degenerate problems (and the error of the retry's regulariser), or, unsettled,
/// the last pass's answer with negative forces cut to zero; the polished z is kept only if it
/// lowers the residual. Returns the residual of the z it leaves.
pub(super) fn polish(n: usize, m: &[f64], q: &[f64], role: &[Role], z: &mut [f64], work: &mut LcpWork) -> f64 {
    let before = residual(n, m, q, z, (&mut work.w, &mut work.nz));
    if z[..n].iter().all(|&x| x <= 0.0) {
        return before;
    }
    // unsettled, the last pass's answer with its negative forces cut to zero (redundant contacts
    // leave some a round-off below zero)
    let after = settle(n, m, q, role, z[..n].iter().map(|&x| x > 0.0), POLISH_PASSES, work).unwrap_or_else(|| {
        for x in work.trial.iter_mut() {
            *x = x.max(0.0);
        }
        residual(n, m, q, &work.trial, (&mut work.w, &mut work.nz))
    });
    if after < before {
        z[..n].copy_from_slice(&work.trial);
        return after;
    }
    before
}
