//! Lemke and the solve cascade on known and random LCPs.

use super::active_set::{eliminate, eliminate_wide, settle};
use super::lemke::{pivot, pivot_wide};
use super::{lemke, residual, solve, LcpStats, LcpWork, Problem, Role, ACCEPT_RESIDUAL, PIVOT_CAP_PER_ROW, REGULARISATION};

#[test]
fn solves_a_small_symmetric_problem() {
    let m = [2.0, 1.0, 1.0, 2.0];
    let q = [-1.0, -1.0];
    let mut z = [0.0; 2];
    let mut work = LcpWork::default();
    lemke(2, &m, &q, |_| false, &mut z, &mut work).unwrap();
    assert!((z[0] - 1.0 / 3.0).abs() < 1e-14 && (z[1] - 1.0 / 3.0).abs() < 1e-14);
    assert!(residual(2, &m, &q, &z, (&mut work.w, &mut work.nz)) < 1e-14);
}

#[test]
fn warm_start_recovers_the_lambda_of_a_contact_without_normal_force() {
    // one separating contact (q_n > 0) with a tangential demand: f = 0 and λ is any value
    // that keeps w_t ≥ 0; the active set {λ} leaves M_AA singular, so λ is recovered instead
    let (knn, ktt, mu) = (1.0, 1.0, 0.5);
    let m = [knn, 0.0, 0.0, 0.0, ktt, 1.0, mu, -1.0, 0.0];
    let q = [2.0, -3.0, 0.0];
    let role = [Role::Normal, Role::Friction { normal: 0, lambda: 2, mu }, Role::Lambda];
    let (mut z, mut work, mut stats) = ([0.0; 3], LcpWork::default(), LcpStats::default());
    assert!(solve(Problem { n: 3, m: &m, q: &q, role: &role }, true, Some(&[false, false, true]), &mut vec![], &mut z, &mut work, &mut stats));
    assert_eq!(stats.warm_starts, 1, "{stats:?}");
    assert_eq!(z, [0.0, 0.0, 3.0]);
    assert!(residual(3, &m, &q, &z, (&mut work.w, &mut work.nz)) < 1e-15);
}

/// An LCP: size, M (row-major), q and the variables' roles.
type Owned = (usize, Vec<f64>, Vec<f64>, Vec<Role>);

/// A seeded stream of numbers uniform in [−1, 1) (a linear congruential generator).
fn uniform(mut x: u64) -> impl FnMut() -> f64 {
    move || {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Random pyramid-friction problems: k contacts (normal, ±t1, ±t2, λ) with K = J Jᵀ + εI from a
/// random J, random demands; (n, M, q, roles) for each of `count` trials.
fn random_pyramid_problems(count: usize) -> Vec<Owned> {
    let mut rnd = uniform(11);
    let mut out = vec![];
    for trial in 0..count {
        let k = 1 + trial % 4;
        let (nr, n) = (5 * k, 6 * k);
        // 3 independent directions per contact, the mirrored tangents their negatives
        let dofs = 4 + trial % 5;
        let base: Vec<f64> = (0..3 * k * dofs).map(|_| rnd()).collect();
        let row = |j: usize| -> Vec<f64> {
            let (c, w) = (j / 5, j % 5);
            let (src, sign) = [(0, 1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)][w];
            base[(3 * c + src) * dofs..(3 * c + src + 1) * dofs].iter().map(|v| sign * v).collect()
        };
        let mut m = vec![0.0; n * n];
        let mut q = vec![0.0; n];
        let mut role = vec![Role::Lambda; n];
        for a in 0..nr {
            for b in 0..nr {
                m[a * n + b] = row(a).iter().zip(row(b)).map(|(u, v)| u * v).sum::<f64>();
            }
            m[a * n + a] *= 1.0 + REGULARISATION;
            let (c, w) = (a / 5, a % 5);
            let (normal, lambda, mu) = (5 * c, nr + c, 0.2 + 0.8 * (rnd() + 1.0) / 2.0);
            if w == 0 {
                role[a] = Role::Normal;
                q[a] = 2.0 * rnd() - 0.5;
            } else {
                role[a] = Role::Friction { normal, lambda, mu };
                q[a] = rnd();
                m[a * n + lambda] = 1.0;
                m[lambda * n + normal] = mu;
                m[lambda * n + a] = -1.0;
            }
        }
        out.push((n, m, q, role));
    }
    out
}

#[test]
fn solves_random_pyramid_friction_problems_without_fallback() {
    // every solution passes the independent check, and Lemke (not a fallback) finds it
    let (mut work, mut stats) = (LcpWork::default(), LcpStats::default());
    for (trial, (n, m, q, role)) in random_pyramid_problems(400).into_iter().enumerate() {
        let mut z = vec![0.0; n];
        assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut vec![], &mut z, &mut work, &mut stats));
        assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL, "trial {trial}: {stats:?}");
    }
    assert_eq!((stats.fallback_pgs, stats.inexact, stats.fallback_zero), (0, 0, 0), "{stats:?}");
    assert!(stats.pivots > 400, "{stats:?}");
}

#[test]
fn lemkes_accepted_paths_stay_within_half_the_pivot_cap() {
    // the cap ends paths that cycle on round-off; one that reaches an answer the check accepts
    // is far shorter (random friction and dry-friction problems, the first attempt's covering)
    let mut work = LcpWork::default();
    let (mut longest, mut accepted) = (0.0f64, 0);
    for (n, m, q, role) in random_pyramid_problems(400).into_iter().chain(random_dry_friction_problems(400)) {
        let mut z = vec![0.0; n];
        let Ok(p) = lemke(n, &m, &q, |i| role[i] == Role::Lambda, &mut z, &mut work) else { continue };
        if residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL {
            accepted += 1;
            longest = longest.max(p.saturating_sub(10) as f64 / n as f64);
        }
    }
    eprintln!("{accepted} accepted, the longest {longest:.2} n pivots");
    assert!(accepted > 600 && longest <= PIVOT_CAP_PER_ROW as f64 / 2.0, "{accepted} accepted, the longest {longest:.2} n");
}

/// A degenerate LCP met in a step (`cycling.txt`): four foot contacts, pyramid friction, μ = 1.
fn cycling_problem() -> Owned {
    let mut lines = include_str!("cycling.txt").lines().filter(|l| !l.starts_with('#'));
    let mut bits = || lines.next().unwrap().split(' ').map(|b| f64::from_bits(b.parse().unwrap())).collect::<Vec<f64>>();
    let (m, q) = (bits(), bits());
    let mut role = vec![Role::Lambda; 24];
    for c in 0..4 {
        role[5 * c] = Role::Normal;
        for t in 1..5 {
            role[5 * c + t] = Role::Friction { normal: 5 * c, lambda: 20 + c, mu: 1.0 };
        }
    }
    (24, m, q, role)
}

#[test]
fn a_lemke_path_that_cycles_on_round_off_stops_at_the_first_basis_it_meets_again() {
    // its first attempt's path comes back to a basis it has met (the lexicographic rule forbids
    // that only in exact arithmetic) and used to go round until the pivot cap; the cascade's
    // regularised retry solves it
    let (n, m, q, role) = cycling_problem();
    let (mut z, mut work) = (vec![0.0; n], LcpWork::default());
    let first = lemke(n, &m, &q, |i| role[i] == Role::Lambda, &mut z, &mut work);
    assert!(matches!(first, Err(p) if p < 4 * n), "{first:?}");
    let mut stats = LcpStats::default();
    assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut vec![], &mut z, &mut work, &mut stats));
    assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL, "{stats:?}");
    assert!(stats.pivots < (PIVOT_CAP_PER_ROW * n) as u64, "{stats:?}");
}

#[test]
fn a_warm_guess_one_contact_off_is_corrected_without_lemke() {
    // each problem solved, then solved again from its answer's active set with the first
    // contact's normal flipped: the warm start's correction passes settle 171 of the 247
    // (a single solve on the flipped set settles none), every answer checked
    let (mut work, mut stats) = (LcpWork::default(), LcpStats::default());
    let (mut tried, mut settled) = (0, 0);
    for (n, m, q, role) in random_pyramid_problems(400) {
        let mut z = vec![0.0; n];
        assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut vec![], &mut z, &mut work, &mut stats));
        let mut guess: Vec<bool> = z.iter().map(|&x| x > 0.0).collect();
        if !guess[0] {
            continue;
        }
        guess[0] = false;
        let before = stats.warm_starts;
        assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, Some(&guess), &mut vec![], &mut z, &mut work, &mut stats));
        assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL, "{stats:?}");
        tried += 1;
        settled += (stats.warm_starts - before) as usize;
    }
    eprintln!("{settled} of {tried} settled");
    assert!(tried > 100 && settled * 3 > tried, "{settled} of {tried} settled");
}

/// Random dry-friction problems: `d` dofs, each a ± pair of rows (J and −J) whose force is capped
/// by the dof's loss, each row with its slack σ (w_σ = cap − f); K = J Jᵀ (1 + ε) from random J,
/// random demands: (n, M, q, roles), rows first (+, − per dof), then their slacks.
fn random_dry_friction_problems(count: usize) -> Vec<Owned> {
    let mut rnd = uniform(5);
    let mut out = vec![];
    for trial in 0..count {
        let d = 2 + trial % 6;
        let (nr, n, dofs) = (2 * d, 4 * d, d + 3);
        let base: Vec<f64> = (0..d * dofs).map(|_| rnd()).collect();
        let row = |r: usize| base[r / 2 * dofs..(r / 2 + 1) * dofs].iter().map(move |v| if r % 2 == 0 { *v } else { -v });
        let (mut m, mut q, mut role) = (vec![0.0; n * n], vec![0.0; n], vec![Role::Lambda; n]);
        let demand: Vec<f64> = (0..d).map(|_| 3.0 * rnd()).collect();
        for a in 0..nr {
            for b in 0..nr {
                m[a * n + b] = row(a).zip(row(b)).map(|(u, v)| u * v).sum::<f64>();
            }
            m[a * n + a] *= 1.0 + REGULARISATION;
            let (slack, cap) = (nr + a, 0.2 + (rnd() + 1.0) / 2.0);
            q[a] = if a % 2 == 0 { demand[a / 2] } else { -demand[a / 2] };
            role[a] = Role::Bounded { lambda: slack, cap };
            (m[a * n + slack], m[slack * n + a], q[slack]) = (1.0, -1.0, cap);
        }
        out.push((n, m, q, role));
    }
    out
}

#[test]
fn a_joint_starting_to_slide_is_pinned_at_its_cap_a_pass_sooner() {
    // each answer's rows held at their caps, one at a time left out of the guess (a joint the
    // last step held starting to slide): the warm start pins it at its cap on its first
    // correction, so two passes settle 302 of the 713 (the rest need more: the other dofs move
    // with it). Without that the solve free of the cap shows the excess a pass later, and two
    // passes settle none
    let mut work = LcpWork::default();
    let (mut tried, mut settled) = (0, 0);
    for (n, m, q, role) in random_dry_friction_problems(300) {
        let mut z = vec![0.0; n];
        assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut vec![], &mut z, &mut work, &mut LcpStats::default()));
        assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL);
        for r in 0..n {
            let Role::Bounded { lambda: slack, .. } = role[r] else { continue };
            if z[r] > 0.0 && z[slack] > 0.0 {
                let guess = (0..n).map(|i| z[i] > 0.0 && i != r && i != slack);
                tried += 1;
                settled += settle(n, &m, &q, &role, guess, 2, &mut work).is_some() as usize;
            }
        }
    }
    assert!(tried > 200 && settled * 3 > tried, "{settled} of {tried} settled in two passes");
}

#[test]
fn leaving_out_separating_contacts_still_solves_the_whole_problem() {
    // the same problems with each contact whose normal q ≥ 0 left out at first (its friction
    // rows and λ follow): the answer passes the whole problem's check, some left-out
    // contacts, pushed closed by the others, are brought back, and a solve again after that
    // is settled by the warm start from the last answer at times
    let (mut work, mut stats) = (LcpWork::default(), LcpStats::default());
    for (trial, (n, m, q, role)) in random_pyramid_problems(400).into_iter().enumerate() {
        let mut out: Vec<bool> = (0..n).map(|i| role[i] == Role::Normal && q[i] >= 0.0).collect();
        let mut z = vec![0.0; n];
        let mut attempts = 0;
        while !solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut out, &mut z, &mut work, &mut stats) {
            attempts += 1;
            // a second bringing back brings back every row
            assert!(attempts <= 2, "trial {trial}: a third solve was needed");
        }
        assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL, "trial {trial}: {stats:?}");
    }
    assert_eq!(stats.solves, 400, "{stats:?}");
    assert!(stats.left_out > 100 && stats.regrown > 10 && stats.warm_starts > 0, "{stats:?}");
}

#[test]
fn a_second_bringing_back_brings_back_every_row() {
    // a chain of four frictionless contacts, each pressing only on the next (K tridiagonal):
    // the first one's force pushes the second closed, whose force pushes the third, and so
    // on; all but the first start left out. The second bringing back keeps every row, so the
    // third solve is the last
    let n = 4;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i * n + i] = 1.0;
        if i + 1 < n {
            (m[i * n + i + 1], m[(i + 1) * n + i]) = (-0.5, -0.5);
        }
    }
    let q = [-1.0, 0.1, 0.1, 0.1];
    let role = [Role::Normal; 4];
    let mut out = vec![false, true, true, true];
    let (mut z, mut work, mut stats) = ([0.0; 4], LcpWork::default(), LcpStats::default());
    let mut attempts = 1;
    while !solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut out, &mut z, &mut work, &mut stats) {
        attempts += 1;
    }
    assert_eq!((attempts, stats.regrown), (3, 2), "{stats:?}");
    assert!(z.iter().all(|&f| f > 0.0), "{z:?}");
    assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) < 1e-14);
}

#[test]
fn solves_the_seed_friction_block() {
    // one contact: normal, tangent, λ; gravity pulls along the tangent harder than μ allows
    let (knn, ktt, mu) = (1.0, 1.0, 0.3);
    let m = [knn, 0.0, 0.0, 0.0, ktt, 1.0, mu, -1.0, 0.0];
    let q = [-9.81, -5.0, 0.0];
    let mut z = [0.0; 3];
    let mut work = LcpWork::default();
    lemke(3, &m, &q, |i| i == 2, &mut z, &mut work).unwrap();
    assert!((z[0] - 9.81).abs() < 1e-12, "{z:?}");
    assert!((z[1] - mu * 9.81).abs() < 1e-12, "friction saturates: {z:?}");
    assert!(residual(3, &m, &q, &z, (&mut work.w, &mut work.nz)) < 1e-12);
}

#[test]
fn a_problem_of_separate_groups_is_solved_group_by_group() {
    // three problems interleaved into one: M has no entry between the groups (bodies that do
    // not touch), and each group is solved exactly as it would be alone
    let groups: Vec<Owned> = random_pyramid_problems(12).into_iter().skip(5).take(3).collect();
    let n: usize = groups.iter().map(|p| p.0).sum();
    let mut global: Vec<Vec<usize>> = groups.iter().map(|p| vec![0; p.0]).collect();
    let (mut next, mut i) = (vec![0; 3], 0);
    while i < n {
        for g in 0..3 {
            if next[g] < groups[g].0 {
                global[g][next[g]] = i;
                (next[g], i) = (next[g] + 1, i + 1);
            }
        }
    }
    let (mut m, mut q, mut role) = (vec![0.0; n * n], vec![0.0; n], vec![Role::Lambda; n]);
    for ((ng, mg, qg, rg), map) in groups.iter().zip(&global) {
        for a in 0..*ng {
            q[map[a]] = qg[a];
            role[map[a]] = match rg[a] {
                Role::Friction { normal, lambda, mu } => Role::Friction { normal: map[normal], lambda: map[lambda], mu },
                Role::Bounded { lambda, cap } => Role::Bounded { lambda: map[lambda], cap },
                r => r,
            };
            for b in 0..*ng {
                m[map[a] * n + map[b]] = mg[a * ng + b];
            }
        }
    }
    {
        let (mut work, mut stats) = (LcpWork::default(), LcpStats::default());
        let mut z = vec![0.0; n];
        assert!(solve(Problem { n, m: &m, q: &q, role: &role }, true, None, &mut vec![], &mut z, &mut work, &mut stats));
        assert!(residual(n, &m, &q, &z, (&mut work.w, &mut work.nz)) <= ACCEPT_RESIDUAL, "{stats:?}");
        let mut pivots = 0;
        for ((ng, mg, qg, rg), map) in groups.iter().zip(&global) {
            let (mut zg, mut alone) = (vec![0.0; *ng], LcpStats::default());
            assert!(solve(Problem { n: *ng, m: mg, q: qg, role: rg }, true, None, &mut vec![], &mut zg, &mut work, &mut alone));
            pivots += alone.pivots;
            for a in 0..*ng {
                assert_eq!(z[map[a]], zg[a], "group variable {a}");
            }
        }
        assert!(pivots > 0);
        assert_eq!(stats.pivots, pivots, "each group pivots as it would alone");
    }
}

#[test]
fn the_wide_eliminations_give_the_plain_ones_bits() {
    // sizes around the 4-wide blocks, values spanning magnitudes (round-off would show)
    let mut seed = 7u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 10f64.powi((seed % 13) as i32 - 6)
    };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for k in 1..14 {
        let a: Vec<f64> = (0..k * (k + 1)).map(|_| next()).collect();
        let (mut wide, mut plain) = (a.clone(), a.clone());
        assert_eq!(eliminate_wide(&mut wide, k), eliminate(&mut plain, k));
        assert_eq!(bits(&wide), bits(&plain), "elimination of size {k}");
        let cols = k + 2;
        let t: Vec<f64> = (0..k * cols).map(|_| next()).collect();
        let (mut wide, mut plain) = (t.clone(), t.clone());
        pivot_wide(&mut wide, cols, k, k / 2, k / 3);
        pivot(&mut plain, cols, k, k / 2, k / 3);
        assert_eq!(bits(&wide), bits(&plain), "pivot of size {k}");
    }
}
