//! Projected Gauss–Seidel: the cascade's fallback when pivoting fails.

use super::Role;

/// Sweeps projected Gauss–Seidel makes at most where its answer is final (impulse solves,
/// post-stabilisation): a fallback answer to keep, as close as it can come.
pub const PGS_SWEEPS: usize = 500;
/// Sweeps where an inexact answer has a fallback after it (the force solve, which the step's
/// impulses replace: `step::constrain`): PGS then only has to come near enough for the polish to
/// settle its active set exactly. On Playground's hand tasks, whose Lemke attempts fail most
/// often, PGS hardly ever converges, and the polish settles as many force solves from 100
/// sweeps as from 500 (`Batch.constraint_stats["rescued"]`), while the sweeps past 100 were a
/// tenth of the Aero hand's time.
pub const PGS_SWEEPS_BEFORE_FALLBACK: usize = 100;

/// Projected Gauss–Seidel on the same conditions: normals z ≥ 0, each contact's friction forces
/// summing to at most μ f_n, λ recovered afterwards as the unmet tangential demand. Sweeps until
/// no variable moves by more than 1e-12 of the largest, at most `cap` times. The λ variables stay
/// zero through the sweeps (each row's w then leaves them out, as it must: a λ is not a force),
/// their friction rows' sums kept in `sum` (n, scratch).
pub(super) fn pgs(n: usize, m: &[f64], q: &[f64], role: &[Role], z: &mut [f64], sum: &mut Vec<f64>, cap: usize) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        fn avx2(n: usize, m: &[f64], q: &[f64], role: &[Role], z: &mut [f64], sum: &mut Vec<f64>, cap: usize) -> bool {
            sweeps(n, m, q, role, z, sum, cap)
        }
        // SAFETY: the processor has AVX2, checked just above
        return unsafe { avx2(n, m, q, role, z, sum, cap) };
    }
    sweeps(n, m, q, role, z, sum, cap)
}

#[inline(always)]
fn sweeps(n: usize, m: &[f64], q: &[f64], role: &[Role], z: &mut [f64], sum: &mut Vec<f64>, cap: usize) -> bool {
    z[..n].fill(0.0);
    sum.clear();
    sum.resize(n, 0.0);
    for _ in 0..cap {
        let (mut moved, mut largest) = (0.0f64, 0.0f64);
        for i in 0..n {
            let d = m[i * n + i];
            if d <= 0.0 || role[i] == Role::Lambda {
                continue;
            }
            let old = z[i];
            let step = old - w_of(n, m, q, z, i) / d;
            z[i] = match role[i] {
                Role::Friction { normal, lambda, mu } => {
                    // room left under μ f_n by the contact's other friction rows
                    let cap = (mu * z[normal] - (sum[lambda] - old)).max(0.0);
                    let f = step.clamp(0.0, cap);
                    sum[lambda] += f - old;
                    f
                }
                Role::Bounded { cap, .. } => step.clamp(0.0, cap),
                _ => step.max(0.0),
            };
            moved = moved.max((z[i] - old).abs());
            largest = largest.max(z[i].abs());
        }
        if moved.is_nan() || moved <= 1e-12 * largest {
            break;
        }
    }
    // each λ (σ): the least that keeps its rows' w ≥ 0, from every row's w without the λs
    for i in 0..n {
        sum[i] = if let Role::Friction { .. } | Role::Bounded { .. } = role[i] { w_of(n, m, q, z, i) } else { 0.0 };
    }
    for i in 0..n {
        if let Role::Friction { lambda, .. } | Role::Bounded { lambda, .. } = role[i] {
            z[lambda] = z[lambda].max(-sum[i]);
        }
    }
    z[..n].iter().all(|x| x.is_finite())
}

/// Row i's w = q_i + (M z)_i.
#[inline(always)]
fn w_of(n: usize, m: &[f64], q: &[f64], z: &[f64], i: usize) -> f64 {
    q[i] + dot(&m[i * n..(i + 1) * n], &z[..n])
}

/// Σ a_k b_k in four interleaved partial sums: one order of operations, so the same bits
/// whether the compiler vectorises it or not.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut s = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}
