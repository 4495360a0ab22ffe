//! Lemke's complementary pivoting on a condensed tableau (Cottle, Pang & Stone 1992, §4.4).

use super::{LcpWork, PIVOT_CAP_PER_ROW};
use crate::math::splitmix64;

/// Lemke's algorithm with covering vector d (d_i = 1, except 0 on rows where `uncovered(i)` and
/// q_i ≥ 0). `m` is n × n row-major. Returns the pivot count, or, as the error, the pivots spent
/// before a ray termination, the pivot cap or non-finite values. `z` receives the solution.
///
/// The friction λ rows (q = 0) and the slack rows of bounded forces (q = cap ≥ 0) need no
/// covering; covering them too sends Lemke's path to a secondary ray on contacts whose tangential
/// demand exceeds what their (zero) normal force allows, which have the solution f = 0, λ > 0.
///
/// The tableau is condensed (Tucker's form): it keeps the columns of the n + 1 nonbasic variables
/// and the right-hand side, not the unit columns of the basic ones, so a pivot updates n × (n + 2)
/// entries instead of n × (2n + 2), with the same arithmetic on every entry it keeps. Variables are
/// numbered w_i = i, z_i = n + i, z0 = 2n.
pub fn lemke(n: usize, m: &[f64], q: &[f64], uncovered: impl Fn(usize) -> bool, z: &mut [f64], work: &mut LcpWork) -> Result<usize, usize> {
    z[..n].fill(0.0);
    let qmin = (0..n).map(|i| q[i]).fold(f64::INFINITY, f64::min);
    if n == 0 || qmin >= 0.0 {
        return Ok(0);
    }
    // columns: the nonbasic variables (at first z_0 … z_{n−1}, z0) | rhs
    let cols = n + 2;
    let rhs = n + 1;
    let z0 = 2 * n;
    // every entry is written below
    work.tab.resize(n * cols, 0.0);
    work.basis.clear();
    work.column.clear();
    work.column.extend((0..=2 * n).map(|v| if v < n { usize::MAX } else { v - n }));
    for i in 0..n {
        let row = &mut work.tab[i * cols..(i + 1) * cols];
        for j in 0..n {
            row[j] = -m[i * n + j];
        }
        row[n] = if uncovered(i) && q[i] >= 0.0 { 0.0 } else { -1.0 };
        row[rhs] = q[i];
        work.basis.push(i);
    }
    let mut r = (0..n).min_by(|&a, &b| q[a].total_cmp(&q[b])).unwrap();
    let mut entering = z0;
    let cap = PIVOT_CAP_PER_ROW * n + 10;
    // the basis met again: the path cycles on round-off (the lexicographic rule excludes it in
    // exact arithmetic) and would run to the cap. A basis's hash is the XOR of its variables'
    // random keys (Zobrist's), so a pivot updates it with two
    let key = |v: usize| splitmix64(v as u64);
    let mut basis_hash = (0..n).fold(0, |h, v| h ^ key(v));
    work.bases.clear();
    work.bases.reserve(cap);
    for pivots in 1..=cap {
        let c = work.column[entering];
        pivot_wide(&mut work.tab, cols, n, r, c);
        let leaving = work.basis[r];
        work.basis[r] = entering;
        work.column[entering] = usize::MAX;
        work.column[leaving] = c;
        basis_hash ^= key(leaving) ^ key(entering);
        if leaving == z0 {
            for i in 0..n {
                let v = work.basis[i];
                if v >= n && v < 2 * n {
                    z[v - n] = work.tab[i * cols + rhs].max(0.0);
                }
            }
            return if z[..n].iter().all(|x| x.is_finite()) { Ok(pivots) } else { Err(pivots) };
        }
        if work.bases.contains(&basis_hash) {
            return Err(pivots);
        }
        work.bases.push(basis_hash);
        // complement of the leaving variable enters
        entering = if leaving < n { leaving + n } else { leaving - n };
        r = ratio_test(&work.tab, cols, n, work.column[entering], &work.basis, &work.column, (&mut work.w, &mut work.cand)).ok_or(pivots)?;
        if !work.tab[r * cols + rhs].is_finite() {
            return Err(pivots);
        }
    }
    Err(cap)
}

/// Lexicographic minimum-ratio test (Cottle, Pang & Stone 1992, §4.9) on the condensed tableau's
/// column `ce`: the rows whose rhs/d is within round-off of the smallest, ties broken by z0 first,
/// then by the columns of B⁻¹ (the full tableau's w columns: a nonbasic w's tableau column, a
/// basic one's unit column) over d, so degenerate problems (redundant contacts) cannot cycle.
/// `ratio` and `cand` are scratch.
fn ratio_test(tab: &[f64], cols: usize, n: usize, ce: usize, basis: &[usize], column: &[usize], (ratio, cand): (&mut Vec<f64>, &mut Vec<usize>)) -> Option<usize> {
    let rhs = n + 1;
    let z0 = 2 * n;
    let tol = 1e-11;
    ratio.clear();
    let mut best = f64::INFINITY;
    for row in tab[..n * cols].chunks_exact(cols) {
        let d = row[ce];
        let r = if d > tol { row[rhs] / d } else { f64::INFINITY };
        best = best.min(r);
        ratio.push(r);
    }
    // no bounded ratio, or a tableau gone non-finite (absurd model parameters): Lemke fails and
    // the caller falls back
    if !best.is_finite() || ratio.iter().any(|r| r.is_nan()) {
        return None;
    }
    let slack = tol * (1.0 + best.abs());
    cand.clear();
    cand.extend((0..n).filter(|&i| ratio[i] <= best + slack));
    if cand.len() == 1 {
        return Some(cand[0]);
    }
    if let Some(&i) = cand.iter().find(|&&i| basis[i] == z0) {
        return Some(i);
    }
    let mut w = 0;
    while cand.len() > 1 && w < n {
        let val = |i: usize| {
            let b = match column[w] {
                usize::MAX => (basis[i] == w) as u8 as f64,
                c => tab[i * cols + c],
            };
            b / tab[i * cols + ce]
        };
        let min = cand.iter().map(|&i| val(i)).fold(f64::INFINITY, f64::min);
        cand.retain(|&i| val(i) <= min + tol * (1.0 + min.abs()));
        w += 1;
    }
    cand.first().copied()
}

/// Pivots the condensed tableau (`n` rows of `cols`) on row r, column c: the entering variable of
/// column c becomes row r's basic variable, and the leaving one takes column c (its unit column,
/// pivoted: 1/p in row r, −f_i/p elsewhere).
#[inline(always)]
pub(super) fn pivot(tab: &mut [f64], cols: usize, n: usize, r: usize, c: usize) {
    let (before, rest) = tab[..n * cols].split_at_mut(r * cols);
    let (prow, after) = rest.split_at_mut(cols);
    let inv = 1.0 / prow[c];
    for x in prow.iter_mut() {
        *x *= inv;
    }
    prow[c] = inv;
    for row in before.chunks_exact_mut(cols).chain(after.chunks_exact_mut(cols)) {
        let f = row[c];
        if f != 0.0 {
            sub_scaled(row, f, prow);
            row[c] = -f * inv;
        }
    }
}

/// [`pivot`], compiled for AVX2 as well and run so where the processor has it (detected at run
/// time): 4-wide registers, the same products and differences lane by lane, so the same results
/// (`lcp::tests`).
pub(super) fn pivot_wide(tab: &mut [f64], cols: usize, n: usize, r: usize, c: usize) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        fn avx2(tab: &mut [f64], cols: usize, n: usize, r: usize, c: usize) {
            pivot(tab, cols, n, r, c);
        }
        // SAFETY: the processor has AVX2, checked just above
        unsafe { avx2(tab, cols, n, r, c) };
        return;
    }
    pivot(tab, cols, n, r, c);
}

/// y −= f·x over the shorter of the two (the eliminations' inner loop).
#[inline(always)]
pub(super) fn sub_scaled(y: &mut [f64], f: f64, x: &[f64]) {
    for (a, b) in y.iter_mut().zip(x) {
        *a -= f * b;
    }
}

