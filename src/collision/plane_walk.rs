//! A hull of many vertices on a plane: its vertices near the plane found by walking its edges.

use arrayvec::ArrayVec;
use glam::DVec3;

use super::convex::{on_plane, reduce, Manifold, Point, Polytope, PosedHull, MAX_POLY};
use super::data::Scratch;

/// [`on_plane`] for a hull of many vertices, reading only the vertices near the plane and their
/// neighbours: those within the margin are joined along the hull's edges (a linear function's
/// sublevel set on a convex polytope is connected, as in the simplex method), so a walk from the
/// lowest vertex (found by climbing) meets them all. The same contacts as [`on_plane`]: the walk
/// keeps a round-off more than the margin, and the vertices it met are tested as there, in
/// their order.
pub(super) fn hull_on_plane(h: &PosedHull, o: DVec3, n: DVec3, margin: f64, scratch: &mut Scratch) -> Manifold {
    let hull = h.hull;
    if !hull.climbs() || scratch.met.len() < hull.vert.len() {
        return on_plane(h, o, n, margin);
    }
    // heights above the plane in the hull's frame: h0 + v·n_local
    let nl = h.rot.transpose() * n;
    let h0 = (h.c - o).dot(n);
    let tol = 1e-9 * ((h.c - o).length() + hull.bounds.0.length() + hull.bounds.1.length());
    let (lowest, depth) = hull.support(-nl);
    if h0 - depth > margin + tol {
        return Manifold::new();
    }
    let (met, (seen, todo)) = (&mut scratch.met, &mut scratch.walk);
    seen.clear();
    todo.clear();
    met[lowest] = true;
    seen.push(lowest as u32);
    todo.push(lowest as u32);
    while let Some(i) = todo.pop() {
        for &j in hull.neighbours_of(i as usize) {
            if !met[j as usize] {
                met[j as usize] = true;
                seen.push(j);
                if h0 + hull.vert[j as usize].dot(nl) <= margin + tol {
                    todo.push(j);
                }
            }
        }
    }
    seen.sort_unstable();
    let mut pts: ArrayVec<Point, MAX_POLY> = ArrayVec::new();
    for &i in seen.iter() {
        met[i as usize] = false;
        let v = h.vert(i as usize);
        let d = (v - o).dot(n);
        if d <= margin && !pts.is_full() {
            pts.push((i as usize, v - n * (0.5 * d), n, d));
        }
    }
    reduce(&pts, n)
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DQuat, DVec3};

    use super::super::convex::tests::ellipsoid_points;
    use super::super::convex::{on_plane, Polytope, PosedHull, MAX_POLY};
    use super::super::data::Scratch;
    use crate::geometry::Hull;

    /// The walk from a hull's lowest vertex finds exactly the contacts of reading every vertex:
    /// a round hull and a sole (a flat bottom face under a rounded top), at random poses above, on
    /// and into a plane, within random margins (some with more vertices in them than a manifold's
    /// gather holds).
    #[test]
    fn a_hulls_walk_on_a_plane_finds_what_reading_every_vertex_finds() {
        let mut sole: Vec<DVec3> = (0..225).map(|i| DVec3::new((i % 15) as f64 * 0.01 - 0.07, (i / 15) as f64 * 0.006 - 0.042, 0.0)).collect();
        sole.extend(ellipsoid_points(300, DVec3::new(0.07, 0.04, 0.03)).into_iter().filter(|p| p.z > 0.0));
        let hulls = [Hull::new(&ellipsoid_points(400, DVec3::new(0.1, 0.07, 0.05))).unwrap(), Hull::new(&sole).unwrap()];
        let mut scratch = Scratch::sized(400);
        let mut x: u64 = 7;
        let mut rnd = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut touching, mut full) = (0, 0);
        for k in 0..2000 {
            let hull = &hulls[k % 2];
            assert!(hull.climbs());
            // a sole lying flat (on its face, or tilted a little) half the time
            let q = if k % 4 == 1 { DQuat::from_rotation_x(0.02 * rnd()) } else { DQuat::from_xyzw(rnd(), rnd(), rnd(), rnd()).normalize() };
            let h = PosedHull { hull, c: DVec3::new(rnd(), rnd(), 0.12 * rnd()), rot: DMat3::from_quat(q) };
            let (o, n, margin) = (DVec3::new(rnd(), rnd(), 0.0), DVec3::Z, 0.02 * (rnd() + 0.5));
            let walked = super::hull_on_plane(&h, o, n, margin, &mut scratch);
            assert_eq!(walked, on_plane(&h, o, n, margin), "pose {k}");
            assert!(scratch.met.iter().all(|&m| !m));
            touching += !walked.is_empty() as usize;
            full += ((0..hull.vert.len()).filter(|&i| (h.vert(i) - o).dot(n) <= margin).count() > MAX_POLY) as usize;
        }
        assert!(touching > 500 && full > 50, "{touching} poses touch, {full} fill the gather");
    }
}
