//! A ray against a height field's grid, in either precision (rangefinders in f64, the renderer in
//! f32): the part of the ray inside a box (slabs), the walk over the grid cells its footprint
//! crosses, nearest first (Amanatides & Woo 1987, *A Fast Voxel Traversal Algorithm for Ray
//! Tracing*), and the ray's distance to a triangle (Möller & Trumbore 1997).

use std::ops::{Add, Div, Mul, Sub};

use glam::{DVec3, Vec3A};

/// A scalar of the walk: f32 or f64.
pub trait Real: Copy + PartialOrd + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> {
    /// 0, 1 and ∞.
    const ZERO: Self;
    const ONE: Self;
    const INFINITY: Self;
    /// The type's machine epsilon.
    const EPSILON: Self;
    fn floor(self) -> Self;
    fn abs(self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    /// A cell index from a non-negative whole value.
    fn index(self) -> usize;
    /// A count as a value.
    fn count(n: usize) -> Self;
}

macro_rules! real {
    ($t:ty) => {
        impl Real for $t {
            const ZERO: $t = 0.0;
            const ONE: $t = 1.0;
            const INFINITY: $t = <$t>::INFINITY;
            const EPSILON: $t = <$t>::EPSILON;
            #[inline(always)]
            fn floor(self) -> $t {
                <$t>::floor(self)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn min(self, other: $t) -> $t {
                <$t>::min(self, other)
            }
            #[inline(always)]
            fn max(self, other: $t) -> $t {
                <$t>::max(self, other)
            }
            #[inline(always)]
            fn index(self) -> usize {
                self as usize
            }
            #[inline(always)]
            fn count(n: usize) -> $t {
                n as $t
            }
        }
    };
}
real!(f32);
real!(f64);

/// A 3-vector of the walk's precision: glam's `Vec3A` (f32) or `DVec3` (f64).
pub trait Vector: Copy + Sub<Output = Self> {
    type T: Real;
    fn at(self, k: usize) -> Self::T;
    fn dot(self, other: Self) -> Self::T;
    fn cross(self, other: Self) -> Self;
}

macro_rules! vector {
    ($v:ty, $t:ty) => {
        impl Vector for $v {
            type T = $t;
            #[inline(always)]
            fn at(self, k: usize) -> $t {
                self[k]
            }
            #[inline(always)]
            fn dot(self, other: $v) -> $t {
                <$v>::dot(self, other)
            }
            #[inline(always)]
            fn cross(self, other: $v) -> $v {
                <$v>::cross(self, other)
            }
        }
    };
}
vector!(Vec3A, f32);
vector!(DVec3, f64);

/// The part of [t0, t1] in which `o + t d` is inside the box [lo, hi] (slabs), if any.
pub fn clip<V: Vector>(o: V, d: V, (t0, t1): (V::T, V::T), lo: [V::T; 3], hi: [V::T; 3]) -> Option<(V::T, V::T)> {
    let (mut ta, mut tb) = (t0, t1);
    for k in 0..3 {
        let (ok, dk) = (o.at(k), d.at(k));
        if dk == V::T::ZERO {
            if ok < lo[k] || ok > hi[k] {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo[k] - ok) / dk, (hi[k] - ok) / dk);
        ta = ta.max(u.min(v));
        tb = tb.min(u.max(v));
    }
    (ta <= tb).then_some((ta, tb))
}

/// Visits the cells of an n.0 × n.1 grid (corner `origin`, cell size `size`, in x and y) that
/// the footprint of `o + t d` crosses for t in [ta, tb], nearest first, each with the t it enters
/// and leaves by, until `visit` returns a value.
pub fn walk<V: Vector, R>(n: (usize, usize), origin: (V::T, V::T), size: (V::T, V::T), o: V, d: V, (ta, tb): (V::T, V::T), mut visit: impl FnMut(usize, usize, V::T, V::T) -> Option<R>) -> Option<R> {
    let zero = V::T::ZERO;
    let (o, d) = ([o.at(0), o.at(1)], [d.at(0), d.at(1)]);
    let start = |k: usize, n: usize, origin: V::T, size: V::T| ((o[k] + d[k] * ta - origin) / size).floor().max(zero).index().min(n - 1);
    let (mut i, mut j) = (start(0, n.0, origin.0, size.0), start(1, n.1, origin.1, size.1));
    // the t at which the footprint crosses the next line of each axis, and between lines
    let next = |k: usize, cell: usize, origin: V::T, size: V::T| match d[k] {
        v if v > zero => (origin + size * V::T::count(cell + 1) - o[k]) / v,
        v if v < zero => (origin + size * V::T::count(cell) - o[k]) / v,
        _ => V::T::INFINITY,
    };
    let (mut nx, mut ny) = (next(0, i, origin.0, size.0), next(1, j, origin.1, size.1));
    let (sx, sy) = (size.0 / d[0].abs(), size.1 / d[1].abs());
    let mut t = ta;
    loop {
        let out = nx.min(ny).min(tb);
        if let Some(r) = visit(i, j, t, out) {
            return Some(r);
        }
        if out >= tb {
            return None;
        }
        t = out;
        if nx <= ny {
            i = match (d[0] > zero, i) {
                (true, i) if i + 1 < n.0 => i + 1,
                (false, i) if i > 0 => i - 1,
                _ => return None,
            };
            nx = nx + sx;
        } else {
            j = match (d[1] > zero, j) {
                (true, j) if j + 1 < n.1 => j + 1,
                (false, j) if j > 0 => j - 1,
                _ => return None,
            };
            ny = ny + sy;
        }
    }
}

/// The distance along `o + t d` to triangle (a, b, c), from either side (Möller & Trumbore
/// 1997); none when the ray runs parallel to its plane (to rounding).
#[inline]
pub fn triangle<V: Vector>(o: V, d: V, [a, b, c]: [V; 3]) -> Option<V::T> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    let eps = V::T::EPSILON;
    if det * det <= eps * eps * e1.dot(e1) * e2.dot(e2) * d.dot(d) {
        return None;
    }
    let inv = V::T::ONE / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if u < V::T::ZERO || u > V::T::ONE {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < V::T::ZERO || u + v > V::T::ONE {
        return None;
    }
    Some(e2.dot(q) * inv)
}
