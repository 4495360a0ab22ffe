//! The collision pairs a model carries, decided at compile time (`compile::pairs`): each pair's
//! broadphase test, the gap pairs, the plane groups, and which tree a geom moves with.

use super::{Model, WORLD};

/// A geom pair that may collide, with its broadphase test precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomPair {
    /// First geom (the lower index).
    pub g1: usize,
    /// Second geom.
    pub g2: usize,
    /// How the broadphase rejects the pair.
    pub test: PairTest,
    /// The larger of the two geoms' margins.
    pub margin: f64,
    /// The bounding radii of the bounded geoms, summed.
    pub radii: f64,
    /// An explicit pair's (`<contact><pair>`) friction; None: the geoms'
    /// ([`crate::collision::contact_friction`]).
    pub friction: Option<PairFriction>,
    /// Whether both geoms move (neither is the world's nor a plane): their relative motion then
    /// bounds how near the step can bring them.
    pub both_move: bool,
    /// Where the pair keeps what its last test found apart in `CollisionData` (a mesh, cylinder
    /// or ellipsoid against anything but a plane or a height field, or two boxes).
    pub kept: Option<u32>,
}

/// The friction of a pair's contacts: its condim, the sliding coefficient, and the torsional (condim ≥ 4, a length) and rolling (condim 6, a length)
/// coefficients, zero where the condim leaves them out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairFriction {
    /// MuJoCo's condim: 1, 3, 4 or 6.
    pub condim: u32,
    /// Sliding friction coefficient.
    pub mu: f64,
    /// Torsional coefficient: the largest couple about the normal per unit normal force.
    pub spin: f64,
    /// Rolling coefficient: the largest couple about a tangent per unit normal force.
    pub roll: f64,
}

impl PairFriction {
    /// Whether friction applies (condim > 1).
    pub fn sliding(&self) -> bool {
        self.condim > 1
    }

    /// The friction of condim `condim` with MuJoCo's coefficients (sliding, torsional, rolling).
    pub fn new(condim: u32, [mu, spin, roll]: [f64; 3]) -> PairFriction {
        PairFriction { condim, mu, spin: if condim >= 4 { spin } else { 0.0 }, roll: if condim >= 6 { roll } else { 0.0 } }
    }
}

/// A pair of two bounded geoms ([`PairTest::Spheres`]), which keeps a lower bound on its distance
/// while every plane group is apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GapPair {
    /// Index into [`Model::collision_pairs`].
    pub pair: usize,
    /// The geoms' bodies.
    pub bodies: [usize; 2],
    /// The deepest body both bodies descend from (or are): only the joints below it change the
    /// distance between the geoms.
    pub ancestor: usize,
    /// The pair's margin.
    pub margin: f64,
}

/// Broadphase test of a [`GeomPair`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairTest {
    /// Bounding spheres farther apart than their radii, margin and reach.
    Spheres,
    /// The bounding sphere of geom `other` farther above geom `plane` than its radius, margin and
    /// reach.
    Plane {
        /// The plane geom.
        plane: usize,
        /// The bounded geom.
        other: usize,
        /// The [`PlaneGroup`] whose single test rejects the pair first, if any.
        group: Option<usize>,
    },
    /// No bound: always tested (two planes).
    Always,
}

/// A world plane and the subtree of one child of the world: while the sphere about the child's
/// origin that holds every geom of the subtree stays above the plane, none of their pairs with the
/// plane needs a test of its own (the broadphase's upper level).
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneGroup {
    /// The plane geom (a world geom).
    pub plane: usize,
    /// The child of the world.
    pub body: usize,
    /// The body's [`Model::body_reach`] plus the largest margin of the group's pairs.
    pub radius: f64,
}

/// The tree geom g moves with ([`Model::node_tree`] of its body's node), or [`WORLD`].
pub fn geom_tree(m: &Model, g: usize) -> usize {
    let n = m.body_node[m.geom_body[g]];
    if n == WORLD { WORLD } else { m.node_tree[n] }
}

/// Whether geoms i and j move with the same tree (not the world).
pub fn same_tree(m: &Model, i: usize, j: usize) -> bool {
    geom_tree(m, i) != WORLD && geom_tree(m, i) == geom_tree(m, j)
}

/// Largest geom count for which [`Model::pair_bits`] is kept (2 MiB of bits).
pub const PAIR_BITS_GEOMS: usize = 4096;
