//! The sensors a file declares, each object resolved (the kinds sinew does not compute left out
//! with a warning).

use crate::error::{Error, Result};
use crate::mjcf::{JointType, ModelSpec};
use crate::model::{ContactObject, ContactSensor, Model, SensorFrame, SensorKind};

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
            "framequat" => SensorKind::FrameQuat(object()?, frame("reftype", "refname")?),
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
            "contact" => match contact(m, &attr, sp.line)? {
                Ok(c) => SensorKind::Contact(c),
                Err(why) => {
                    m.warnings.push(format!("<contact> sensor '{}' at line {}: {why}, left out of sensordata", sp.name, sp.line));
                    continue;
                }
            },
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

/// A `<contact>` sensor's objects, slots, fields and reduction; `Ok(Err(why))` for what sinew
/// does not compute (forces, torques and tangents; force reductions; site filters).
fn contact<'a>(m: &Model, attr: &impl Fn(&str) -> Option<&'a str>, line: u32) -> Result<std::result::Result<ContactSensor, String>> {
    let object = |side: &str| -> Result<ContactObject> {
        let given: Vec<(&str, &str)> = ["geom", "body", "subtree"].iter().filter_map(|k| attr(&format!("{k}{side}")).map(|v| (*k, v))).collect();
        let Some(&(kind, name)) = given.first() else { return Ok(ContactObject::Any) };
        if given.len() > 1 {
            return Err(Error::model("contact", Some(&format!("{kind}{side}")), line, format!("one of geom{side}, body{side}, subtree{side}")));
        }
        let names = if kind == "geom" { &m.geom_name } else { &m.body_name };
        let i = names.iter().position(|n| n == name).ok_or_else(|| Error::model("contact", Some(&format!("{kind}{side}")), line, format!("unknown {kind} '{name}'")))?;
        Ok(match kind {
            "geom" => ContactObject::Geom(i),
            "body" => ContactObject::Body(i),
            _ => ContactObject::Subtree(i),
        })
    };
    let (obj1, obj2) = (object("1")?, object("2")?);
    let num = match attr("num").map(str::parse::<usize>) {
        None => 1,
        Some(Ok(n)) if n >= 1 => n,
        _ => return Err(Error::model("contact", Some("num"), line, "a positive integer")),
    };
    let mut fields = 0u8;
    for f in attr("data").unwrap_or("found").split_whitespace() {
        match ["found", "dist", "pos", "normal"].iter().position(|k| *k == f) {
            Some(b) => fields |= 1 << b,
            None if ["force", "torque", "tangent"].contains(&f) => return Ok(Err(format!("data '{f}' is not computed by sinew"))),
            None => return Err(Error::model("contact", Some("data"), line, format!("unknown field '{f}'"))),
        }
    }
    let mindist = match attr("reduce").unwrap_or("none") {
        "none" => false,
        "mindist" => true,
        r @ ("maxforce" | "netforce") => return Ok(Err(format!("reduce '{r}' is not computed by sinew"))),
        r => return Err(Error::model("contact", Some("reduce"), line, format!("unknown reduction '{r}'"))),
    };
    if fields == 0 {
        return Err(Error::model("contact", Some("data"), line, "at least one field"));
    }
    Ok(Ok(ContactSensor { obj1, obj2, num, fields, mindist }))
}
