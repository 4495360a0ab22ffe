//! Constraints as rows of `a = K f + b` (Kokkevis 2004): the rows of a step (contacts with
//! friction, joint limits, motion control), K and b by test forces, impacts, the LCP that finds
//! the forces, and post-stabilisation.
//!
//! Files in the order a step uses them: `system` (the rows as arrays), `rows` (building them),
//! `dry_friction` (the friction of dofs sliding on, known ahead), `test_forces` (K and b, through `delta_pass`), `impact`, `solve` (posing the LCP per island), `lcp` (solving it),
//! `stabilize`; `history` is what the next step reads, `applied` what is read after the step.

pub mod applied;
pub mod delta_pass;
pub mod dry_friction;
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

pub use applied::AppliedForces;
pub use history::{History, RowKey};
pub use system::{closing_velocity, correction_velocity, impact_speed, jacobian, ConstraintData, RowKind, CORRECTION_TIME, IMPACT_SPEED, SLIDING_SPEED};

/// What the constraint stages keep for one world — the history the next step reads, the forces
/// read after the step, motion control's feed-forward and the counters — and their scratch: the
/// rows, the solve and post-stabilisation, which a batch's worlds borrow from its threads
/// ([`crate::step::data::Kept`]).
#[derive(Clone, Debug, Default)]
pub struct Constraints {
    /// Constraint rows, K, b.
    pub con: ConstraintData,
    /// The constraint solves' LCP, answer and warm start.
    pub solve: solve::SolveData,
    /// What building the rows needs besides them.
    pub rows: rows::RowScratch,
    /// Post-stabilisation scratch.
    pub post: stabilize::StabilizeData,
    /// The state a leapfrog step began with, before its opening drift.
    pub start: StepStart,
    /// What the next step reads from the steps before it.
    pub history: History,
    /// The forces the last step's rows applied.
    pub applied: AppliedForces,
    /// Trajectory feed-forward for motion control: reference velocities then accelerations (2 × nu).
    pub feedforward: Vec<f64>,
    /// LCP solver statistics, of the force, impact and projection solves alike.
    pub stats: lcp::LcpStats,
    /// Impact solves run.
    pub impacts: u64,
    /// Projections run.
    pub projections: u64,
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
            rows: rows::RowScratch::new(m),
            post: stabilize::StabilizeData::new(m),
            start: StepStart { qpos: vec![0.0; m.nq], qvel: vec![0.0; m.nv] },
            feedforward: vec![0.0; 2 * m.nu],
            ..Default::default()
        }
    }

    /// Drops the rows and forces of the last step.
    pub fn forget_scratch(&mut self) {
        self.solve.force.clear();
        self.solve.impact_warm.clear();
        self.con.clear();
        self.applied.clear();
    }
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
