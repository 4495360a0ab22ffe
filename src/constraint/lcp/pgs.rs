//! Projected Gauss–Seidel: the cascade's fallback when pivoting fails.

use super::Role;

/// Projected Gauss–Seidel on the same conditions: normals z ≥ 0, each contact's friction forces
/// summing to at most μ f_n, λ recovered afterwards as the unmet tangential demand. Sweeps until
/// no variable moves by more than 1e-12 of the largest, at most 500 times.
pub(super) fn pgs(n: usize, m: &[f64], q: &[f64], role: &[Role], z: &mut [f64]) -> bool {
    z[..n].fill(0.0);
    let w_of = |z: &[f64], i: usize| q[i] + (0..n).filter(|&j| role[j] != Role::Lambda).map(|j| m[i * n + j] * z[j]).sum::<f64>();
    // during the sweeps z[λ] of a contact holds the sum of its friction forces
    for _ in 0..500 {
        let (mut moved, mut largest) = (0.0f64, 0.0f64);
        for i in 0..n {
            let d = m[i * n + i];
            if d <= 0.0 {
                continue;
            }
            let old = z[i];
            match role[i] {
                Role::Normal => z[i] = (old - w_of(z, i) / d).max(0.0),
                Role::Friction { normal, lambda, mu } => {
                    // room left under μ f_n by the contact's other friction rows
                    let cap = (mu * z[normal] - (z[lambda] - old)).max(0.0);
                    z[i] = (old - w_of(z, i) / d).clamp(0.0, cap);
                    z[lambda] += z[i] - old;
                }
                Role::Bounded { cap, .. } => z[i] = (old - w_of(z, i) / d).clamp(0.0, cap),
                Role::Lambda => continue,
            }
            moved = moved.max((z[i] - old).abs());
            largest = largest.max(z[i].abs());
        }
        if moved.is_nan() || moved <= 1e-12 * largest {
            break;
        }
    }
    for i in 0..n {
        if let Role::Friction { lambda, .. } | Role::Bounded { lambda, .. } = role[i] {
            z[lambda] = 0.0;
        }
    }
    for i in 0..n {
        if let Role::Friction { lambda, .. } | Role::Bounded { lambda, .. } = role[i] {
            z[lambda] = z[lambda].max(-w_of(z, i));
        }
    }
    z[..n].iter().all(|x| x.is_finite())
}
