//! Constraints as rows of `a = K f + b` (Kokkevis 2004): the rows of a step (contacts with
//! friction, joint limits, motion control), K and b by test forces, impacts, the LCP that finds
//! the forces, and post-stabilisation.
//!
//! Files in the order a step uses them: `system` (the rows as arrays), `rows` (building them),
//! `test_forces` (K and b), `impact`, `solve` (posing the LCP per island), `lcp` (solving it),
//! `stabilize`; `history` is what the next step reads.

pub mod history;
pub mod impact;
pub mod lcp;
pub mod rows;
pub mod solve;
pub mod stabilize;
pub mod system;
pub mod test_forces;

use crate::collision::CollisionData;
use crate::dynamics::DynamicsData;
use crate::model::Model;

pub use history::{History, RowKey};
pub use system::{closing_velocity, correction_velocity, impact_speed, jacobian, ConstraintData, RowKind, CORRECTION_TIME, IMPACT_SPEED, SLIDING_SPEED};

/// What the constraint stages keep for one world: the rows, the solve, post-stabilisation, the
/// history the next step reads, and motion control's feed-forward.
#[derive(Clone, Debug, Default)]
pub struct Constraints {
    /// Constraint rows, K, b.
    pub con: ConstraintData,
    /// The constraint solves' LCP, answer, warm start and counters.
    pub solve: solve::SolveData,
    /// What building the rows needs besides them.
    pub rows: rows::RowScratch,
    /// Post-stabilisation scratch and counters.
    pub post: stabilize::StabilizeData,
    /// What the next step reads from the steps before it.
    pub history: History,
    /// Trajectory feed-forward for motion control: reference velocities then accelerations (2 × nu).
    pub feedforward: Vec<f64>,
    /// The state a leapfrog step began with, before its opening drift.
    pub start: StepStart,
}

/// The state a leapfrog step began with: its rows' gaps are taken before the opening drift, and
/// the limits the drift crossed are held (`stabilize::hold_limits`).
#[derive(Clone, Debug, Default)]
pub struct StepStart {
    /// qpos before the opening drift (nq).
    pub qpos: Vec<f64>,
    /// qvel the opening drift moved with (nv).
    pub qvel: Vec<f64>,
}

impl Constraints {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        Constraints {
            con: ConstraintData::new(m),
            solve: solve::SolveData::default(),
            rows: rows::RowScratch::new(m),
            post: stabilize::StabilizeData::new(m),
            history: History::new(),
            feedforward: vec![0.0; 2 * m.nu],
            start: StepStart { qpos: vec![0.0; m.nq], qvel: vec![0.0; m.nv] },
        }
    }

    /// Drops the rows and forces of the last step.
    pub fn forget_scratch(&mut self) {
        self.solve.force.clear();
        self.solve.impact_warm.clear();
        self.con.clear();
    }

    /// Exchanges the buffers a step's solve sizes to its rows with `b`: a batch lends a thread's
    /// to each world for its step and takes them back after ([`SolveBuffers`]).
    pub fn swap_buffers(&mut self, b: &mut SolveBuffers) {
        std::mem::swap(&mut self.con.k, &mut b.k);
        std::mem::swap(&mut self.con.zeroed_trees, &mut b.zeroed_trees);
        std::mem::swap(&mut self.con.dqdd, &mut b.dqdd);
        std::mem::swap(&mut self.solve.m, &mut b.m);
        std::mem::swap(&mut self.solve.work, &mut b.work);
        self.post.swap_buffers(&mut b.post);
    }
}

/// The buffers a step's constraint solve sizes to its rows — K (with the rows' trees it was
/// zeroed for) and Δq̈, the LCP's matrix and work, post-stabilisation's rows and LCP — which grow
/// with a world's contacts to several times the rest of its scratch. Nothing reads them from one
/// step to the next, so a batch keeps one set per thread and lends it to each world for its step
/// ([`Constraints::swap_buffers`]) instead of keeping one per world.
#[derive(Clone, Debug, Default)]
pub struct SolveBuffers {
    k: Vec<f64>,
    zeroed_trees: Vec<[usize; 2]>,
    dqdd: Vec<f64>,
    m: Vec<f64>,
    work: lcp::LcpWork,
    post: stabilize::PostBuffers,
}

/// One world as the constraint stages see it: its dynamics (which an impact re-evaluates), its
/// contacts and the constraint stages' own data.
pub struct World<'a> {
    /// Kinematics, ABA quantities, applied forces and q̈.
    pub dynamics: &'a mut DynamicsData,
    /// Geom poses and contacts.
    pub coll: &'a mut CollisionData,
    /// Rows, solve, post-stabilisation, history.
    pub constraints: &'a mut Constraints,
    /// Nanoseconds per pipeline stage.
    #[cfg(feature = "stage-timing")]
    pub stage_ns: &'a mut [u64; crate::timing::STAGES],
}
