//! The sensors a file declares, each object resolved (the kinds sinew does not compute left out
//! with a warning).

use crate::error::{Error, Result};
use crate::mjcf::{JointType, ModelSpec};
use crate::model::{Model, SensorFrame, SensorKind};

/// The `<sensor>`s sinew computes, each object resolved; the kinds it does not compute are left
/// out with a warning (their names stay out of `sensordata`).
pub(super) fn sensors(m: &mut Model, spec: &ModelSpec) -> Result<()> {
    for sp in &spec.sensors {
        let attr = |a: &str| sp.attrs.iter().find(|(k, _)| k == a).map(|(_, v)| v.as_str());
        let find = |names: &[String], a: &str| {
            let name = attr(a).ok_or_else(|| Error::model(&sp.kind, Some(a), sp.line, "required"))?;
            names.iter().position(|n| n == name).ok_or_else(|| Error::model(&sp.kind, Some(a), sp.line, format!("unknown {a} '{name}'")))
        };
        let frame = |ty: &str, name: &str| -> Result<Option<SensorFrame>> {
            let (Some(t), Some(_)) = (attr(ty), attr(name)) else { return Ok(None) };
            Ok(Some(match t {
                "body" => SensorFrame::Body(find(&m.body_name, name)?),
                "xbody" => SensorFrame::XBody(find(&m.body_name, name)?),
                "geom" => SensorFrame::Geom(find(&m.geom_name, name)?),
                "site" => SensorFrame::Site(find(&m.site_name, name)?),
                other => return Err(Error::model(&sp.kind, Some(ty), sp.line, format!("sensor frames are bodies, xbodies, geoms and sites, not '{other}'"))),
            }))
        };
        let scalar_joint = |a: &str| -> Result<usize> {
            let j = find(&m.jnt_name, a)?;
            if matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide) { Ok(j) } else { Err(Error::model(&sp.kind, Some(a), sp.line, "joint sensors read hinge and slide joints")) }
        };
        let object = || frame("objtype", "objname")?.ok_or_else(|| Error::model(&sp.kind, Some("objtype"), sp.line, "objtype and objname are required"));
        let kind = match sp.kind.as_str() {
            "jointpos" => SensorKind::JointPos(scalar_joint("joint")?),
            "jointvel" => SensorKind::JointVel(scalar_joint("joint")?),
            "tendonpos" => SensorKind::TendonPos(find(&m.tendon_name, "tendon")?),
            "tendonvel" => SensorKind::TendonVel(find(&m.tendon_name, "tendon")?),
            "actuatorpos" => SensorKind::ActuatorPos(find(&m.actuator_name, "actuator")?),
            "actuatorvel" => SensorKind::ActuatorVel(find(&m.actuator_name, "actuator")?),
            "framepos" => SensorKind::FramePos(object()?, frame("reftype", "refname")?),
            "framexaxis" | "frameyaxis" | "framezaxis" => {
                let axis = ["framexaxis", "frameyaxis", "framezaxis"].iter().position(|k| *k == sp.kind).unwrap_or(0);
                SensorKind::FrameAxis(object()?, axis, frame("reftype", "refname")?)
            }
            "framelinvel" | "frameangvel" if attr("reftype").is_some() => {
                return Err(Error::model(&sp.kind, Some("reftype"), sp.line, "velocity sensors in a reference frame are not supported"));
            }
            "framelinvel" => SensorKind::FrameLinVel(object()?),
            "frameangvel" => SensorKind::FrameAngVel(object()?),
            "subtreecom" => SensorKind::SubtreeCom(find(&m.body_name, "body")?),
            "subtreelinvel" => SensorKind::SubtreeLinVel(find(&m.body_name, "body")?),
            "subtreeangmom" => SensorKind::SubtreeAngMom(find(&m.body_name, "body")?),
            "gyro" => SensorKind::Gyro(find(&m.site_name, "site")?),
            "velocimeter" => SensorKind::Velocimeter(find(&m.site_name, "site")?),
            "touch" => SensorKind::Touch(find(&m.site_name, "site")?),
            "accelerometer" => SensorKind::Accelerometer(find(&m.site_name, "site")?),
            "force" => SensorKind::Force(find(&m.site_name, "site")?),
            "torque" => SensorKind::Torque(find(&m.site_name, "site")?),
            "rangefinder" => SensorKind::Rangefinder(find(&m.site_name, "site")?),
            other => {
                m.warnings.push(format!("<{other}> sensor '{}' at line {}: not computed by sinew, left out of sensordata", sp.name, sp.line));
                continue;
            }
        };
        m.sensor_adr.push(m.nsensordata);
        m.nsensordata += kind.dim();
        m.sensor_name.push(sp.name.clone());
        m.sensor_kind.push(kind);
    }
    Ok(())
}
