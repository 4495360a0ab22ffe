//! ③ Per-world scratch: everything a step derives, allocated once per model so that stepping
//! never allocates.

use glam::DVec3;

use crate::model::Model;
use crate::step::aba::AbaData;
use crate::step::collision::CollisionData;
use crate::step::constraint::ConstraintData;
use crate::step::lcp::{LcpStats, LcpWork};
use crate::step::integrate::Rk4Scratch;
use crate::step::kinematics::KinData;
use crate::step::stabilize::StabilizeData;

/// Derived quantities and scratch of one world.
#[derive(Clone, Debug, Default)]
pub struct Data {
    /// Stage 1 output.
    pub kin: KinData,
    /// ABA inward-pass quantities and spatial accelerations.
    pub aba: AbaData,
    /// Total applied generalised force (nv): actuators + passive.
    pub qfrc_applied: Vec<f64>,
    /// Joint accelerations of the last evaluation (nv).
    pub qacc: Vec<f64>,
    /// RK4 stage buffers.
    pub rk4: Rk4Scratch,
    /// Geom poses and contacts.
    pub coll: CollisionData,
    /// Constraint rows, K, b.
    pub con: ConstraintData,
    /// Constraint force (acceleration solve) or impulse (impact solve) per row and λ.
    pub force: Vec<f64>,
    /// LCP matrix and vector scratch.
    pub lcp_m: Vec<f64>,
    /// LCP vector.
    pub lcp_q: Vec<f64>,
    /// λ variable of each normal row with friction (usize::MAX: none).
    pub lcp_lambda: Vec<usize>,
    /// Role of each LCP variable.
    pub lcp_role: Vec<crate::step::lcp::Role>,
    /// LCP variables left out of the solve (held at zero force) and of K.
    pub lcp_out: Vec<bool>,
    /// Moving average of the solves with rows left out that had to bring one back.
    pub regrow_rate: f64,
    /// Lemke tableau.
    pub lcp_work: LcpWork,
    /// Solver statistics.
    pub stats: LcpStats,
    /// Impact solves run.
    pub impacts: u64,
    /// Limits whose rows this step must include (2 per joint: lower, upper).
    pub limit_forced: Vec<bool>,
    /// Post-stabilisation scratch and counters.
    pub post: StabilizeData,
    /// Friction tangents of the last step, keyed by (geom1, geom2, feature).
    pub tangents: Vec<((usize, usize, usize), DVec3)>,
    /// Tangents being recorded this step.
    pub tangents_next: Vec<((usize, usize, usize), DVec3)>,
    /// Trajectory feed-forward for motion control: reference velocities then accelerations (2 × nu).
    pub feedforward: Vec<f64>,
    /// Centre of mass and mass of each root's subtree, scratch for `sensors` (nbody).
    pub root_com: Vec<(DVec3, f64)>,
    /// Per-node spatial forces, scratch for `sensors` (nnode).
    pub node_force: Vec<crate::math::Force>,
    /// SplitMix64 state of this world's random tangents.
    pub rng: u64,
    /// Nanoseconds spent per pipeline stage, in [`crate::step::Stage`] order.
    #[cfg(feature = "stage-timing")]
    pub stage_ns: [u64; crate::step::STAGES],
}

impl Data {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        Data {
            kin: KinData::new(m),
            aba: AbaData::new(m),
            qfrc_applied: vec![0.0; m.nv],
            qacc: vec![0.0; m.nv],
            rk4: Rk4Scratch::new(m),
            coll: CollisionData::new(m),
            con: ConstraintData::new(m),
            force: vec![],
            lcp_m: vec![],
            lcp_q: vec![],
            lcp_lambda: vec![],
            lcp_role: vec![],
            lcp_out: vec![],
            regrow_rate: 0.0,
            lcp_work: LcpWork::default(),
            stats: LcpStats::default(),
            impacts: 0,
            limit_forced: vec![false; 2 * m.njnt],
            post: StabilizeData::new(m),
            tangents: vec![],
            tangents_next: vec![],
            feedforward: vec![0.0; 2 * m.nu],
            root_com: vec![(DVec3::ZERO, 0.0); m.nbody],
            node_force: vec![crate::math::Force::ZERO; m.nnode],
            rng: 0x5EED,
            #[cfg(feature = "stage-timing")]
            stage_ns: [0; crate::step::STAGES],
        }
    }

    /// Forgets what the last steps leave for the next (friction tangents, the LCP's warm start and
    /// regrow rate, cached kinematics, rows and forces), so that the next step is a fresh world's.
    pub fn forget_history(&mut self) {
        self.tangents.clear();
        self.regrow_rate = 0.0;
        self.force.clear();
        self.con.clear();
        self.coll.forget();
        self.lcp_work.warm.clear();
        self.lcp_work.warm_rows.clear();
        self.post.forget();
    }
}
