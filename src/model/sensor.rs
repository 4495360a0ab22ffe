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
    /// A frame's orientation quaternion (w, x, y, z), world or in a reference frame.
    FrameQuat(SensorFrame, Option<SensorFrame>),
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
    /// The last step's contacts between two objects (MuJoCo's `<contact>` sensor).
    Contact(ContactSensor),
}

/// What a `<contact>` sensor matches and reports: `num` slots, each holding the fields of
/// `fields` in MuJoCo's order (found, dist, pos, normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSensor {
    /// The first object (`geom1`, `body1` or `subtree1`; any when absent).
    pub obj1: ContactObject,
    /// The second object.
    pub obj2: ContactObject,
    /// Slots (`num`).
    pub num: usize,
    /// Which of found (bit 0), dist (1), pos (2), normal (3) each slot holds.
    pub fields: u8,
    /// `reduce="mindist"`: the slots hold the nearest contacts (else the first found).
    pub mindist: bool,
}

/// The entries of the contact sensor fields found, dist, pos, normal (MuJoCo's `mjCONDATA_SIZE`).
pub const CONTACT_FIELD_SIZE: [usize; 4] = [1, 1, 3, 3];

impl ContactSensor {
    /// Entries per slot.
    pub fn slot_size(&self) -> usize {
        (0..4).filter(|b| self.fields & (1 << b) != 0).map(|b| CONTACT_FIELD_SIZE[b]).sum()
    }
}

/// One side of a contact sensor's match.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactObject {
    /// Any geom.
    Any,
    /// This geom.
    Geom(usize),
    /// A geom of this body.
    Body(usize),
    /// A geom of this body or its descendants.
    Subtree(usize),
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
            SensorKind::Contact(c) => c.num * c.slot_size(),
            SensorKind::FrameQuat(..) => 4,
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
