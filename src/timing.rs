//! The pipeline's stages, and the per-stage wall time kept with the `stage-timing` feature
//! (`benches/stage_breakdown.py`).

/// Pipeline stages, for the per-stage cost breakdown (cargo feature `stage-timing`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Poses, velocities, velocity products.
    Kinematics,
    /// Applied forces and the ABA's passes.
    Dynamics,
    /// Contact detection (both checks).
    Collision,
    /// Constraint rows and their b.
    Rows,
    /// K and Δq̈ by test forces.
    Assembly,
    /// The LCP: vector, matrix, solve.
    Lcp,
    /// The velocity update after an impact.
    Impact,
    /// Time integration.
    Integration,
    /// Post-stabilisation check and projection.
    Projection,
}

/// Number of [`Stage`]s.
pub const STAGES: usize = 9;

/// Stage names, in [`Stage`] order.
pub const STAGE_NAMES: [&str; STAGES] = ["kinematics", "ABA", "collision", "rows", "K assembly", "LCP", "impact update", "integration", "post-stabilisation"];

/// Runs `$body`, adding its wall time to `$data.stage_ns[$stage]` with the `stage-timing` feature.
macro_rules! timed {
    ($data:expr, $stage:expr, $body:expr) => {{
        #[cfg(feature = "stage-timing")]
        let start = std::time::Instant::now();
        let out = $body;
        #[cfg(feature = "stage-timing")]
        {
            $data.stage_ns[$stage as usize] += start.elapsed().as_nanos() as u64;
        }
        #[cfg(not(feature = "stage-timing"))]
        let _ = $stage;
        out
    }};
}
pub(crate) use timed;
