//! Stage 4 — the mixed LCP  w = M z + q,  z ≥ 0 ⟂ w ≥ 0, by Lemke's complementary pivoting.
//!
//! Why Lemke: the seed's friction rows (Kokkevis 2004, eqs. 19–21) make M non-symmetric and not
//! positive definite ([[K_nn, K_nt, 0], [K_tn, K_tt, 1], [μ, −1, 0]] per contact), so Dantzig-style
//! principal pivoting has no guarantee; Lemke's method is the textbook solver for this form
//! (Cottle, Pang & Stone, *The Linear Complementarity Problem*, 1992, §4.4). Redundant rows (four
//! coplanar box corners) make K singular; a tiny diagonal regulariser keeps pivots finite. Every
//! accepted solution is checked independently (w = M z + q recomputed); on failure the cascade
//! falls back to projected Gauss–Seidel on the normal rows alone (frictionless), then to zero force.

/// Counters Python can read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LcpStats {
    /// LCP solves attempted.
    pub solves: u64,
    /// Total Lemke pivots.
    pub pivots: u64,
    /// Solves that fell back to frictionless PGS.
    pub fallback_pgs: u64,
    /// Solves that fell back to zero force.
    pub fallback_zero: u64,
    /// Largest complementarity/feasibility residual of an accepted solution (last solve).
    pub residual: f64,
}

/// Reusable storage for the solver.
#[derive(Clone, Debug, Default)]
pub struct LcpWork {
    tab: Vec<f64>,
    basis: Vec<usize>,
    w: Vec<f64>,
}

/// Relative regulariser added to the diagonal of the force rows.
pub const REGULARISATION: f64 = 1e-11;
/// Pivot cap, as a multiple of the problem size.
pub const PIVOT_CAP_PER_ROW: usize = 50;

/// Lemke's algorithm. `m` is n × n row-major. Returns the pivot count, or None on ray
/// termination, pivot cap or non-finite values. `z` receives the solution.
pub fn lemke(n: usize, m: &[f64], q: &[f64], z: &mut [f64], work: &mut LcpWork) -> Option<usize> {
    z[..n].fill(0.0);
    let qmin = (0..n).map(|i| q[i]).fold(f64::INFINITY, f64::min);
    if n == 0 || qmin >= 0.0 {
        return Some(0);
    }
    // tableau columns: w (n) | z (n) | z0 | rhs
    let cols = 2 * n + 2;
    let (z0, rhs) = (2 * n, 2 * n + 1);
    work.tab.clear();
    work.tab.resize(n * cols, 0.0);
    work.basis.clear();
    for i in 0..n {
        let row = &mut work.tab[i * cols..(i + 1) * cols];
        row[i] = 1.0;
        for j in 0..n {
            row[n + j] = -m[i * n + j];
        }
        row[z0] = -1.0;
        row[rhs] = q[i];
        work.basis.push(i);
    }
    let mut r = (0..n).min_by(|&a, &b| q[a].total_cmp(&q[b])).unwrap();
    let mut entering = z0;
    let cap = PIVOT_CAP_PER_ROW * n + 10;
    for pivots in 1..=cap {
        pivot(&mut work.tab, cols, n, r, entering);
        let leaving = work.basis[r];
        work.basis[r] = entering;
        if leaving == z0 {
            for i in 0..n {
                let v = work.basis[i];
                if v >= n && v < 2 * n {
                    z[v - n] = work.tab[i * cols + rhs].max(0.0);
                }
            }
            return z[..n].iter().all(|x| x.is_finite()).then_some(pivots);
        }
        // complement of the leaving variable enters
        entering = if leaving < n { leaving + n } else { leaving - n };
        // minimum ratio test; prefer z0 on ties so the method terminates
        let mut best: Option<(usize, f64)> = None;
        for i in 0..n {
            let d = work.tab[i * cols + entering];
            if d > 1e-12 {
                let ratio = work.tab[i * cols + rhs] / d;
                match best {
                    None => best = Some((i, ratio)),
                    Some((bi, br)) => {
                        let tie = (ratio - br).abs() <= 1e-12 * br.abs().max(1e-300);
                        if ratio < br && !tie || tie && work.basis[i] == z0 && work.basis[bi] != z0 {
                            best = Some((i, ratio));
                        }
                    }
                }
            }
        }
        r = best?.0;
        if !work.tab[r * cols + rhs].is_finite() {
            return None;
        }
    }
    None
}

fn pivot(tab: &mut [f64], cols: usize, n: usize, r: usize, c: usize) {
    let p = tab[r * cols + c];
    for j in 0..cols {
        tab[r * cols + j] /= p;
    }
    for i in 0..n {
        if i == r {
            continue;
        }
        let f = tab[i * cols + c];
        if f != 0.0 {
            for j in 0..cols {
                tab[i * cols + j] -= f * tab[r * cols + j];
            }
        }
    }
}

/// Independent check: max over rows of violations of z ≥ 0, w ≥ 0 and z·w = 0, scaled.
pub fn residual(n: usize, m: &[f64], q: &[f64], z: &[f64], w: &mut Vec<f64>) -> f64 {
    w.clear();
    let mut worst = 0.0f64;
    for i in 0..n {
        let wi: f64 = q[i] + (0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>();
        let scale = 1.0 + q[i].abs() + (0..n).map(|j| (m[i * n + j] * z[j]).abs()).sum::<f64>();
        worst = worst.max((-z[i]).max(0.0)).max((-wi).max(0.0) / scale).max((z[i] * wi).abs() / scale);
        w.push(wi);
    }
    if worst.is_nan() { f64::INFINITY } else { worst }
}

/// Solves with the cascade Lemke → PGS on `normal_rows` → zero; returns the path taken in `stats`.
pub fn solve(n: usize, m: &[f64], q: &[f64], normal_rows: &[bool], z: &mut [f64], work: &mut LcpWork, stats: &mut LcpStats) {
    stats.solves += 1;
    if let Some(p) = lemke(n, m, q, z, work) {
        stats.pivots += p as u64;
        let res = residual(n, m, q, z, &mut work.w);
        if res <= 1e-6 {
            stats.residual = res;
            return;
        }
    }
    stats.fallback_pgs += 1;
    if pgs(n, m, q, normal_rows, z) {
        stats.residual = residual(n, m, q, z, &mut work.w);
        return;
    }
    stats.fallback_zero += 1;
    z[..n].fill(0.0);
    stats.residual = 0.0;
}

/// Projected Gauss–Seidel on the normal rows only (others held at zero).
fn pgs(n: usize, m: &[f64], q: &[f64], normal_rows: &[bool], z: &mut [f64]) -> bool {
    z[..n].fill(0.0);
    for _ in 0..200 {
        for i in (0..n).filter(|&i| normal_rows[i]) {
            let d = m[i * n + i];
            if d <= 0.0 {
                continue;
            }
            let wi: f64 = q[i] + (0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>();
            z[i] = (z[i] - wi / d).max(0.0);
        }
    }
    z[..n].iter().all(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_symmetric_problem() {
        let m = [2.0, 1.0, 1.0, 2.0];
        let q = [-1.0, -1.0];
        let mut z = [0.0; 2];
        let mut work = LcpWork::default();
        lemke(2, &m, &q, &mut z, &mut work).unwrap();
        assert!((z[0] - 1.0 / 3.0).abs() < 1e-14 && (z[1] - 1.0 / 3.0).abs() < 1e-14);
        assert!(residual(2, &m, &q, &z, &mut work.w) < 1e-14);
    }

    #[test]
    fn solves_the_seed_friction_block() {
        // one contact: normal, tangent, λ; gravity pulls along the tangent harder than μ allows
        let (knn, ktt, mu) = (1.0, 1.0, 0.3);
        let m = [knn, 0.0, 0.0, 0.0, ktt, 1.0, mu, -1.0, 0.0];
        let q = [-9.81, -5.0, 0.0];
        let mut z = [0.0; 3];
        let mut work = LcpWork::default();
        lemke(3, &m, &q, &mut z, &mut work).unwrap();
        assert!((z[0] - 9.81).abs() < 1e-12, "{z:?}");
        assert!((z[1] - mu * 9.81).abs() < 1e-12, "friction saturates: {z:?}");
        assert!(residual(3, &m, &q, &z, &mut work.w) < 1e-12);
    }
}
