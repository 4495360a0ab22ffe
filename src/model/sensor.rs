//! What the sensors a model file declares measure.

/// What a sensor measures (MuJoCo's sensor types of the same names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorKind {
    /// A hinge's or slide's position.
    JointPos(usize),
    /// A hinge's or slide's velocity.
    JointVel(usize),
    /// A tendon's length.
    TendonPos(usize),
    /// A tendon's velocity.
    TendonVel(usize),
    /// An actuator's length (gear times its joint's or tendon's).
    ActuatorPos(usize),
    /// An actuator's velocity.
    ActuatorVel(usize),
    /// A frame's position, world or in a reference frame.
    FramePos(SensorFrame, Option<SensorFrame>),
    /// One axis (0 x, 1 y, 2 z) of a frame, world or in a reference frame.
    FrameAxis(SensorFrame, usize, Option<SensorFrame>),
    /// A frame origin's world linear velocity.
    FrameLinVel(SensorFrame),
    /// A frame's world angular velocity.
    FrameAngVel(SensorFrame),
    /// The centre of mass of a body's subtree.
    SubtreeCom(usize),
    /// The velocity of the centre of mass of a body's subtree.
    SubtreeLinVel(usize),
    /// The angular momentum of a body's subtree about its centre of mass.
    SubtreeAngMom(usize),
    /// A site's angular velocity, in its frame.
    Gyro(usize),
    /// A site's linear velocity, in its frame.
    Velocimeter(usize),
    /// The normal force of the last step's contacts on the site's body within the site's volume.
    Touch(usize),
    /// A site's proper acceleration (its classical acceleration less gravity), in its frame.
    Accelerometer(usize),
    /// The force the site's body's parent exerts on the body's subtree, in the site's frame.
    Force(usize),
    /// That interaction's torque about the site, in the site's frame.
    Torque(usize),
    /// The distance along the site's z axis to the first geom it meets (not of the site's
    /// body), −1 for none.
    Rangefinder(usize),
}

impl SensorKind {
    /// Number of `sensordata` entries.
    pub fn dim(&self) -> usize {
        match self {
            SensorKind::JointPos(_)
            | SensorKind::JointVel(_)
            | SensorKind::TendonPos(_)
            | SensorKind::TendonVel(_)
            | SensorKind::ActuatorPos(_)
            | SensorKind::ActuatorVel(_)
            | SensorKind::Touch(_)
            | SensorKind::Rangefinder(_) => 1,
            _ => 3,
        }
    }
}

impl SensorKind {
    /// Whether it reads accelerations or interaction forces, which take a forward-dynamics pass.
    pub fn reads_accelerations(&self) -> bool {
        matches!(self, SensorKind::Accelerometer(_) | SensorKind::Force(_) | SensorKind::Torque(_))
    }
}

/// A frame a sensor reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorFrame {
    /// A body's inertial frame (centre of mass, principal axes).
    Body(usize),
    /// A body's own frame.
    XBody(usize),
    /// A geom's frame.
    Geom(usize),
    /// A site's frame.
    Site(usize),
}
