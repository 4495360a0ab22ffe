//! Stage 5 — K and b by test forces (Kokkevis 2004, §5): column k of K is measured by pushing a unit test
//! force of row k through the ABA quantities kept from the inward pass (I^A, U, D⁻¹): a delta
//! inward pass and a delta outward pass (`delta_pass`), no 6×6 work, O(n) per column, O(mn + m²)
//! in all.

use glam::DVec3;

use super::delta_pass::{delta_pass, tree_ranges, Lanes, LANES};
use super::lcp;
use super::system::{tree_lists, ConstraintData, RowKind};
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::{point_accel, KinData};
use crate::model::{Model, WORLD};

/// Fills K (every entry: zero between rows of separate trees; by test forces), Δq̈ per unit
/// force, and b from the ABA outward-pass accelerations `aba.a` and `qacc0` of the same state.
pub fn assemble(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], out: &mut ConstraintData) {
    bias(m, kin, aba, qacc0, out);
    out.assembled = false;
    out.k.clear();
    responses(m, kin, aba, out, |_, _| true);
}

/// b alone: each row's acceleration with zero constraint force.
pub fn bias(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], out: &mut ConstraintData) {
    out.b.clear();
    let mut point = PointAccel::NONE;
    for j in 0..out.len() {
        let b = measure(m, kin, aba, qacc0, out, j, &mut point);
        out.b.push(b);
    }
}

/// K's columns and Δq̈ of the rows `needed` (by index and kind) not yet computed, by test forces (they depend on the
/// configuration, not on velocities). Each column is measured at every row, so a row left out
/// still has its accelerations under the forces of the rows computed. Consecutive columns on the
/// same trees are pushed together, one per lane of a delta pass, and written in row order.
pub fn responses(m: &Model, kin: &KinData, aba: &AbaData, out: &mut ConstraintData, needed: impl Fn(usize, RowKind) -> bool) {
    prepare(m, out);
    let (mut group, mut n) = ([0; LANES], 0);
    for k in 0..out.len() {
        if out.column_done[k] || !needed(k, out.kind[k]) {
            continue;
        }
        // a mirror row's column comes with its mirrored row's
        let pushed = if out.mirror[k] == usize::MAX { k } else { out.mirror[k] };
        if out.column_done[pushed] || group[..n].contains(&pushed) {
            continue;
        }
        let [a, b] = out.tree[pushed];
        if n == LANES || (n > 0 && out.tree[group[0]] != [a, b] && out.tree[group[0]] != [b, a]) {
            push_test_forces(m, kin, aba, out, &group[..n]);
            n = 0;
        }
        group[n] = pushed;
        n += 1;
    }
    if n > 0 {
        push_test_forces(m, kin, aba, out, &group[..n]);
    }
}

/// Columns `cols` of K and Δq̈ of those rows (at most [`LANES`], on the same trees), from a unit
/// test force of each (Kokkevis 2004; δp^A = −f at the point's node) in one lane of a delta pass,
/// and those of the rows mirroring them (the next row, if it is its mirror), their negations.
fn push_test_forces(m: &Model, kin: &KinData, aba: &AbaData, out: &mut ConstraintData, cols: &[usize]) {
    let nv = m.nv;
    // the forces move only the nodes of the rows' trees
    let trees = out.tree[cols[0]];
    out.delta.clear(m, trees);
    let mut dtau: [&[(usize, f64)]; LANES] = [&[]; LANES];
    let mut at = [None; LANES];
    for (lane, &k) in cols.iter().enumerate() {
        at[lane] = Some(k * nv);
        // the pass writes the dofs of the row's trees; a joint row across trees (an equality, a
        // tendon) reads the others too, where the force moves nothing (a mirror's likewise)
        let rows = if k + 1 < out.len() && out.mirror[k + 1] == k { 2 } else { 1 };
        out.dqdd[k * nv..(k + rows) * nv].fill(0.0);
        if out.kind[k].is_point() {
            for side in 0..2 {
                let n = out.node[k][side];
                if n != WORLD {
                    out.delta.sub_force(n, lane, &out.jac[k][side]);
                }
            }
        } else {
            // a joint row's test torque: a unit torque on its dof, or on its terms
            dtau[lane] = match out.term_span[k] {
                (_, 0) => std::slice::from_ref(&out.dof[k]),
                (start, len) => &out.terms[start..start + len],
            };
        }
    }
    delta_pass(m, kin, aba, trees, dtau, &mut out.delta, &mut out.dqdd, at);
    if aba.locking {
        write_held(m, aba, out, cols);
    }
    write_columns(m, out, cols);
}

/// The held joints' torque changes of the delta pass's lanes into `out.held_torque` for the
/// columns `cols` (and their mirrors, negated).
fn write_held(m: &Model, aba: &AbaData, out: &mut ConstraintData, cols: &[usize]) {
    let (nr, nv) = (out.len(), m.nv);
    if out.held_torque.len() < nr * nv {
        out.held_torque.resize(nr * nv, 0.0);
    }
    for range in tree_ranges(m, out.tree[cols[0]]) {
        for i in range.filter(|&i| aba.locked[i]) {
            let dof = m.node_dofadr[i];
            for (l, &k) in cols.iter().enumerate() {
                let v = out.delta.held[i].0[l];
                out.held_torque[k * nv + dof] = v;
                if k + 1 < nr && out.mirror[k + 1] == k {
                    out.held_torque[(k + 1) * nv + dof] = -v;
                }
            }
        }
    }
}

/// Columns `cols` of K from the delta pass's lanes, as if written one after another in row order
/// (K is symmetric, J M⁻¹ Jᵀ: a force's measures at the rows of its trees are its row, and its
/// mirror's, negated; a row pushed before holds its own measure of the force, and so does a
/// column of `cols` for the ones after it; rows of other trees are not written: zero, each
/// column's row zeroed first in a block of several trees), and the mirrors' Δq̈.
fn write_columns(m: &Model, out: &mut ConstraintData, cols: &[usize]) {
    let (nr, nv) = (out.len(), m.nv);
    let trees = out.tree[cols[0]];
    let mirrored = |k: usize| k + 1 < nr && out.mirror[k + 1] == k;
    // the block's rows, shared by the columns: K_jk of row j at `start + pos_j·size + pos_k`
    let (start, size) = (out.k_start[out.k_block[cols[0]]], out.k_size[out.k_block[cols[0]]]);
    let pos: [usize; LANES] = std::array::from_fn(|l| cols.get(l).map_or(0, |&k| out.k_pos[k]));
    let mut kk = std::mem::take(&mut out.k);
    let (first, second, a) = tree_lists(out, trees);
    let mut point = PointLanes::NONE;
    let row: [usize; LANES] = pos.map(|p| start + p * size);
    let mirror: [bool; LANES] = std::array::from_fn(|l| cols.get(l).is_some_and(|&k| mirrored(k)));
    // a block of several trees: the columns' rows (and their mirrors') read zero where no shared
    // tree writes them; the rows of rows never pushed are never read
    if out.block_tree[out.k_block[cols[0]]].1 {
        for l in 0..cols.len() {
            kk[row[l]..row[l] + if mirror[l] { 2 * size } else { size }].fill(0.0);
        }
    }
    let write = |kk: &mut [f64], l: usize, pj: usize, v: f64| {
        let row = row[l];
        kk[row + pj] = v;
        if mirror[l] {
            // (−d)·a = −(d·a) exactly: the mirror row's own measure (the block's next row)
            kk[row + size + pj] = -v;
        }
    };
    // every row's measures (rows pushed before: their own, copied), then each column's entries at
    // the columns before it and their mirrors, copied from theirs; a row of both trees is in both
    // lists: read once
    for &j in first.iter().chain(second.iter().filter(|&&j| a == WORLD || !out.tree[j].contains(&a))) {
        let pj = out.k_pos[j];
        let v = if out.column_done[j] {
            Lanes([0, 1, 2, 3].map(|l| kk[start + pj * size + pos[l]]))
        } else {
            delta_accels(out, nv, trees, cols, j, &mut point)
        };
        for l in 0..cols.len() {
            write(&mut kk, l, pj, v.0[l]);
        }
    }
    for l in 1..cols.len() {
        for &c in &cols[..l] {
            for j in if mirrored(c) { c..c + 2 } else { c..c + 1 } {
                let pj = out.k_pos[j];
                let v = kk[start + pj * size + pos[l]];
                write(&mut kk, l, pj, v);
            }
        }
    }
    out.k = kk;
    for &k in cols {
        out.column_done[k] = true;
        if mirrored(k) {
            let (done, rest) = out.dqdd.split_at_mut((k + 1) * nv);
            for r in tree_dofs(m, trees) {
                for (d, s) in rest[r.clone()].iter_mut().zip(&done[k * nv + r.start..k * nv + r.end]) {
                    *d = -s;
                }
            }
            out.column_done[k + 1] = true;
        }
    }
}

/// Lays K out in blocks ([`ConstraintData::k`]), sizes Δq̈ and lists each tree's rows, once per
/// set of rows. Test forces write K only between rows that share a tree (and Δq̈ on the row's
/// trees' dofs): in a block of several trees a row is zeroed as its test force is pushed
/// ([`write_columns`]), a block of one tree is written whole by the test forces of its rows.
pub fn prepare(m: &Model, out: &mut ConstraintData) {
    if out.assembled {
        return;
    }
    let (nr, nv) = (out.len(), m.nv);
    lay_out_blocks(m.nnode, out);
    if out.dqdd.len() < nr * nv {
        out.dqdd.resize(nr * nv, 0.0);
    }
    out.column_done.clear();
    out.column_done.resize(nr, false);
    list_tree_rows(m.nnode, out);
    out.assembled = true;
}

/// The blocks of K: rows whose trees rows link (union–find over the trees) share a block,
/// numbered in the order of their first rows, as are the rows within each (rows on no tree share
/// one), and whether each holds rows of more than one tree (`block_tree`).
fn lay_out_blocks(nnode: usize, out: &mut ConstraintData) {
    let ConstraintData { tree, k, k_block, k_pos, k_start, k_size, block_tree, block_of_root, tree_link: link, .. } = out;
    let nr = tree.len();
    // rows on one tree (a single character's): one block, the rows in place
    let first = tree.first().map_or(WORLD, |t| if t[0] != WORLD { t[0] } else { t[1] });
    if tree.iter().all(|t| t.iter().all(|&x| x == first || x == WORLD)) {
        k_block.clear();
        k_block.resize(nr, 0);
        k_pos.clear();
        k_pos.extend(0..nr);
        k_size.clear();
        k_size.push(nr);
        k_start.clear();
        k_start.push(0);
        block_tree.clear();
        block_tree.push((first, false));
        k.resize(nr * nr, 0.0);
        return;
    }
    link.resize(nnode, 0);
    block_of_root.resize(nnode, usize::MAX);
    for &t in tree.iter().flatten().filter(|&&t| t != WORLD) {
        link[t] = t;
        block_of_root[t] = usize::MAX;
    }
    for &[a, b] in tree.iter() {
        if a != WORLD && b != WORLD {
            let (a, b) = (lcp::root(link, a), lcp::root(link, b));
            link[a.max(b)] = a.min(b);
        }
    }
    k_block.clear();
    k_pos.clear();
    k_size.clear();
    block_tree.clear();
    let mut treeless = usize::MAX;
    for &[a, b] in tree.iter() {
        let t = if a != WORLD { a } else { b };
        let slot = if t == WORLD { &mut treeless } else { &mut block_of_root[lcp::root(link, t)] };
        if *slot == usize::MAX {
            *slot = k_size.len();
            k_size.push(0);
            block_tree.push((t, false));
        }
        let blk = *slot;
        k_block.push(blk);
        k_pos.push(k_size[blk]);
        k_size[blk] += 1;
        let (first, several) = &mut block_tree[blk];
        *several |= [a, b].iter().any(|&x| x != WORLD && x != *first);
    }
    let mut start = 0;
    k_start.clear();
    for &size in k_size.iter() {
        k_start.push(start);
        start += size * size;
    }
    k.resize(start, 0.0);
}

/// [`ConstraintData`]'s lists of each tree's rows (counted, then filled: O(nnode + rows)).
fn list_tree_rows(nnode: usize, out: &mut ConstraintData) {
    let start = &mut out.tree_row_start;
    start.clear();
    start.resize(nnode + 1, 0);
    // a row's distinct trees (WORLD: none)
    let sides = |[a, b]: [usize; 2]| [a, if b == a { WORLD } else { b }];
    for &trees in &out.tree {
        for t in sides(trees) {
            if t != WORLD {
                start[t + 1] += 1;
            }
        }
    }
    for t in 0..nnode {
        start[t + 1] += start[t];
    }
    out.tree_rows.clear();
    out.tree_rows.resize(start[nnode], 0);
    // filled from each list's end, rows in reverse: each list ends up in row order
    for (j, &trees) in out.tree.iter().enumerate().rev() {
        for t in sides(trees) {
            if t != WORLD {
                start[t + 1] -= 1;
                out.tree_rows[start[t + 1]] = j;
            }
        }
    }
    // each count was taken back once per row: start[t + 1] is now where tree t's list starts,
    // so the array is shifted by one
    start.rotate_left(1);
    start[nnode] = out.tree_rows.len();
}

/// The relative acceleration of a contact's point (side 1's less side 2's) with no constraint
/// force ([`measure`]; under test forces, [`PointLanes`]), kept while the rows of that contact
/// (its normal row `normal` and the friction rows after it) are read in turn.
pub(super) struct PointAccel {
    normal: usize,
    accel: DVec3,
}

impl PointAccel {
    /// No contact's yet.
    pub(super) const NONE: PointAccel = PointAccel { normal: usize::MAX, accel: DVec3::ZERO };

    /// Row j's acceleration: a joint row's from `qacc` (its dof's, signed), a contact row's along
    /// its direction from its contact's point acceleration, `accel()` unless kept from the
    /// contact's row before.
    #[inline(always)]
    pub(super) fn row(&mut self, cd: &ConstraintData, j: usize, qacc: &[f64], accel: impl FnOnce() -> DVec3) -> f64 {
        let normal = match cd.kind[j] {
            RowKind::Normal => j,
            RowKind::Tangent { normal } => normal,
            RowKind::Connect { .. } | RowKind::Spin { .. } => return cd.dir[j].dot(accel()),
            RowKind::Limit | RowKind::Motion { .. } | RowKind::DryFriction | RowKind::Equality => return cd.joint_rate(j, qacc),
        };
        if self.normal != normal {
            *self = PointAccel { normal, accel: accel() };
        }
        cd.dir[j].dot(self.accel)
    }
}

/// Whether tree `t` is one of the trees `trees` a test force moved.
#[inline]
fn moves(trees: [usize; 2], t: usize) -> bool {
    t != WORLD && (t == trees[0] || t == trees[1])
}

/// [`PointAccel`] for the test forces of a delta pass's lanes.
struct PointLanes {
    normal: usize,
    accel: [Lanes; 3],
}

impl PointLanes {
    const NONE: PointLanes = PointLanes { normal: usize::MAX, accel: [Lanes::ZERO; 3] };
}

/// d · a in every lane, as `DVec3::dot` sums.
#[inline(always)]
fn dot3(d: DVec3, a: &[Lanes; 3]) -> Lanes {
    a[0] * d.x + a[1] * d.y + a[2] * d.z
}

/// Accelerations of row j under the test forces `cols` on the trees `trees`, one per lane, whose
/// responses are in `cd.delta.a` and their Δq̈ rows (nv each) (K entries): a contact's delta point
/// acceleration (δa_n's at the point, over the sides in those trees: the others do not move)
/// along its direction, the point's computed once for the rows of a contact (`point`), or a joint
/// row's δq̈. Each lane's arithmetic is that of its force alone, as [`PointAccel::row`] reads a row.
#[inline(always)]
fn delta_accels(cd: &ConstraintData, nv: usize, trees: [usize; 2], cols: &[usize], j: usize, point: &mut PointLanes) -> Lanes {
    let normal = match cd.kind[j] {
        RowKind::Normal => j,
        RowKind::Tangent { normal } => normal,
        RowKind::Connect { .. } | RowKind::Spin { .. } => return dot3(cd.dir[j], &point_accels(cd, trees, j)),
        RowKind::Limit | RowKind::Motion { .. } | RowKind::DryFriction | RowKind::Equality => {
            return Lanes(std::array::from_fn(|l| cols.get(l).map_or(0.0, |&k| cd.joint_rate(j, &cd.dqdd[k * nv..(k + 1) * nv]))));
        }
    };
    if point.normal != normal {
        *point = PointLanes { normal, accel: point_accels(cd, trees, j) };
    }
    dot3(cd.dir[j], &point.accel)
}

/// The relative acceleration of row j's points (a couple's: its bodies' relative angular
/// acceleration) in every lane, as [`delta_accels`] reads it.
#[inline(always)]
fn point_accels(cd: &ConstraintData, trees: [usize; 2], j: usize) -> [Lanes; 3] {
    let ([n0, n1], [t0, t1], r) = (cd.node[j], cd.tree[j], cd.arm[j]);
    let a = &cd.delta.a;
    if cd.kind[j].is_couple() {
        let side = |n: usize, t: usize| if moves(trees, t) { [a[n][0], a[n][1], a[n][2]] } else { [Lanes::ZERO; 3] };
        let (s0, s1) = (side(n0, t0), side(n1, t1));
        return [s0[0] - s1[0], s0[1] - s1[1], s0[2] - s1[2]];
    }
    // δa's point velocity lin + ang × r, as `Motion::point_velocity` and `DVec3::cross` compute it
    let at = |n: usize, r: DVec3| {
        let v = &a[n];
        [v[3] + (v[1] * r.z - v[2] * r.y), v[4] + (v[2] * r.x - v[0] * r.z), v[5] + (v[0] * r.y - v[1] * r.x)]
    };
    let r1 = if cd.kind[j] == (RowKind::Connect { angular: false }) { cd.arm2[j] } else { r };
    let mut accel = [Lanes::ZERO; 3];
    if moves(trees, t0) {
        let p = at(n0, r);
        accel = [accel[0] + p[0], accel[1] + p[1], accel[2] + p[2]];
    }
    if moves(trees, t1) {
        let p = at(n1, r1);
        accel = [accel[0] - p[0], accel[1] - p[1], accel[2] - p[2]];
    }
    accel
}

/// Acceleration of row j with zero constraint force (its b): from the actual accelerations, with
/// velocity-product and gravity terms.
/// `point` carries the point's acceleration from a contact's row to its next ones.
pub(super) fn measure(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], cd: &ConstraintData, j: usize, point: &mut PointAccel) -> f64 {
    if cd.term_span[j].1 > 0 {
        return cd.joint_rate(j, qacc0) + cd.jdot[j];
    }
    point.row(cd, j, qacc0, || {
        let ([n0, n1], [p0, p1]) = (cd.node[j], cd.point[j]);
        if cd.kind[j].is_couple() {
            let alpha = |n: usize| if n == WORLD { DVec3::ZERO } else { aba.a[n].ang };
            return alpha(n0) - alpha(n1);
        }
        let g = m.opt.gravity;
        point_accel(kin, &aba.a, g, n0, kin.rel(n0, p0)) - point_accel(kin, &aba.a, g, n1, kin.rel(n1, p1))
    })
}

/// target += f · Δq̈ of a row on the trees `trees`, whose Δq̈ (`dqdd`, nv long) is zero, and not
/// kept, off their dofs.
pub fn add_response(m: &Model, trees: [usize; 2], f: f64, dqdd: &[f64], target: &mut [f64]) {
    for r in tree_dofs(m, trees) {
        for (t, d) in target[r.clone()].iter_mut().zip(&dqdd[r]) {
            *t += f * d;
        }
    }
}

/// The dof ranges of the trees `trees`, as [`tree_ranges`].
pub fn tree_dofs(m: &Model, trees: [usize; 2]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    tree_ranges(m, trees).into_iter().filter(|r| !r.is_empty()).map(|r| m.node_dofadr[r.start]..m.node_dofadr[r.end - 1] + m.node_nv[r.end - 1])
}
