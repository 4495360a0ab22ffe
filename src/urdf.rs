//! URDF as MuJoCo reads it: each link a body, each joint (revolute, continuous, prismatic,
//! fixed, floating) its child's joint placed at the joint's origin; bodies without joints (fixed
//! children, and a fixed root) fused into their parents, their inertias and geoms with them
//! (MuJoCo's `fusestatic`); collision geometry kept and visual geometry discarded unless asked;
//! links without `<inertial>` weighed from their geoms; `<mimic>` as a joint equality; the
//! `<mujoco><compiler …/></mujoco>` extension honoured. The robot is written as MJCF and compiled
//! as any model file, so every check and feature of the MJCF path applies.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DMat3, DQuat, DVec3};
use roxmltree::{Document, Node};

use crate::error::{Error, Result};
use crate::math::SpatialInertia;

/// How a URDF file becomes a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UrdfOptions {
    /// Give the root link a free joint (a legged robot), instead of fixing it to the world.
    pub floating_base: bool,
    /// Keep `<visual>` geometry (drawn, no contacts, no mass), as MuJoCo's `discardvisual="false"`.
    pub visual: bool,
    /// Where `package://NAME/…` is looked for: each directory holding NAME, or NAME itself.
    pub package_dirs: Vec<PathBuf>,
    /// Add a motor on every moving joint with an `effort` limit, its controls within ±effort (a
    /// URDF has no actuators; sinew's, not MuJoCo's, conversion).
    pub motors: bool,
    /// Let the robot's links collide with each other (MuJoCo's rule). Off by default, as in
    /// PyBullet: collision meshes of neighbouring links often overlap at every configuration,
    /// which an exact contact solver cannot resolve. Off, the robot's geoms have contype 2 and
    /// conaffinity 1: they meet the world's geoms (contype 1), not each other.
    pub self_collision: bool,
}

/// A pose: rotation and translation (child frame in parent frame).
#[derive(Clone, Copy, Debug)]
struct Pose {
    rot: DQuat,
    pos: DVec3,
}

impl Pose {
    const IDENTITY: Pose = Pose { rot: DQuat::IDENTITY, pos: DVec3::ZERO };
    fn then(&self, inner: &Pose) -> Pose {
        Pose { rot: (self.rot * inner.rot).normalize(), pos: self.pos + self.rot * inner.pos }
    }
}

/// A geom of a link: pose in the link frame, MJCF type and size attributes, colour.
#[derive(Clone, Debug)]
struct Geom {
    pose: Pose,
    /// MJCF attributes after the pose (type, size or mesh).
    shape: String,
    visual: bool,
    rgba: Option<[f64; 4]>,
}

#[derive(Clone, Debug)]
struct Link {
    name: String,
    /// Mass properties in the link frame.
    inertial: Option<SpatialInertia>,
    geoms: Vec<Geom>,
    /// Joint from the parent (None: the root, or fused away).
    joint: Option<usize>,
    /// Pose in the parent link's frame.
    pose: Pose,
    parent: Option<usize>,
    children: Vec<usize>,
}

#[derive(Clone, Debug)]
struct Joint {
    name: String,
    /// MJCF joint type; None: fixed.
    kind: Option<&'static str>,
    axis: DVec3,
    range: Option<[f64; 2]>,
    damping: f64,
    friction: f64,
    /// The `<limit effort>`: the largest force or torque (0: none given).
    effort: f64,
    mimic: Option<(String, f64, f64)>,
}

/// A URDF robot (the text of the file at `path`, whose directory relative paths start from) as
/// MJCF text, its mesh files as absolute paths: what a user edits to set the robot in a scene.
pub fn to_mjcf(text: &str, path: Option<&Path>, opts: &UrdfOptions) -> Result<String> {
    let doc = Document::parse(text).map_err(|e| Error::Xml { line: e.pos().row, message: e.to_string() })?;
    let root = doc.root_element();
    let line = |n: Node| doc.text_pos_at(n.range().start).row;
    let err = |n: Node, attr: Option<&str>, m: String| Error::model(n.tag_name().name(), attr, line(n), m);
    if root.tag_name().name() != "robot" {
        return Err(err(root, None, "root element must be <robot>".into()));
    }
    let dir = path.and_then(Path::parent).map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let materials: Vec<(String, [f64; 4])> = root
        .children()
        .filter(|c| c.has_tag_name("material"))
        .filter_map(|m| Some((m.attribute("name")?.to_string(), rgba_of(m)?)))
        .collect();
    let mut links: Vec<Link> = vec![];
    let mut meshes: Vec<(String, PathBuf, DVec3)> = vec![];
    let mut compiler = String::new();
    for c in root.children().filter(Node::is_element) {
        match c.tag_name().name() {
            "link" => {
                let link = read_link(c, &dir, opts, &materials, &mut meshes, &err)?;
                if links.iter().any(|l| l.name == link.name) {
                    return Err(err(c, Some("name"), format!("duplicate link '{}'", link.name)));
                }
                links.push(link);
            }
            "mujoco" => {
                for cc in c.children().filter(|n| n.has_tag_name("compiler")) {
                    for a in cc.attributes() {
                        match a.name() {
                            // sinew's own choices for URDF; others passed on
                            "discardvisual" | "fusestatic" | "strippath" | "angle" => {}
                            "meshdir" | "assetdir" => write!(compiler, " meshdir=\"{}\"", xml_escape(&dir.join(a.value()).to_string_lossy())).unwrap_or(()),
                            n => write!(compiler, " {n}=\"{}\"", xml_escape(a.value())).unwrap_or(()),
                        }
                    }
                }
            }
            _ => {}
        }
    }
    let mut joints: Vec<Joint> = vec![];
    for c in root.children().filter(|n| n.has_tag_name("joint")) {
        let j = read_joint(c, &mut links, joints.len(), &err)?;
        joints.push(j);
    }
    let roots: Vec<usize> = (0..links.len()).filter(|&l| links[l].parent.is_none()).collect();
    let [root_link] = roots[..] else {
        return Err(err(root, None, format!("a robot needs exactly one root link, found {}", roots.len())));
    };
    // every link hangs from the root: joints that close a loop leave some links unreachable
    let mut reached = vec![false; links.len()];
    let mut stack = vec![root_link];
    while let Some(l) = stack.pop() {
        if !std::mem::replace(&mut reached[l], true) {
            stack.extend(&links[l].children);
        }
    }
    if let Some(l) = reached.iter().position(|r| !r) {
        return Err(err(root, None, format!("link '{}' is not reachable from the root link: its joints form a loop", links[l].name)));
    }
    let mut out = format!("<mujoco model=\"{}\"><compiler angle=\"radian\"{compiler}/><asset>", xml_escape(root.attribute("name").unwrap_or("robot")));
    for (name, file, scale) in &meshes {
        write!(out, "<mesh name=\"{name}\" file=\"{}\" scale=\"{} {} {}\"/>", xml_escape(&file.to_string_lossy()), scale.x, scale.y, scale.z).unwrap_or(());
    }
    out += "</asset><worldbody>";
    let mut equalities = String::new();
    let w = Writer { links: &links, joints: &joints, self_collision: opts.self_collision };
    w.body(&mut out, &mut equalities, root_link, Pose::IDENTITY, opts.floating_base);
    out += "</worldbody>";
    if !equalities.is_empty() {
        write!(out, "<equality>{equalities}</equality>").unwrap_or(());
    }
    let driven = joints.iter().filter(|j| opts.motors && j.effort > 0.0 && matches!(j.kind, Some("hinge" | "slide")) && j.mimic.is_none());
    let motors: String = driven.map(|j| format!("<motor joint=\"{}\" ctrllimited=\"true\" ctrlrange=\"{} {}\"/>", xml_escape(&j.name), -j.effort, j.effort)).collect();
    if !motors.is_empty() {
        write!(out, "<actuator>{motors}</actuator>").unwrap_or(());
    }
    out += "</mujoco>";
    Ok(out)
}

/// A `<link>`: its inertial and the geoms it keeps (collision, and visual when asked), meshes
/// added to `meshes`.
fn read_link(c: Node, dir: &Path, opts: &UrdfOptions, materials: &[(String, [f64; 4])], meshes: &mut Vec<(String, PathBuf, DVec3)>, err: &ErrFn) -> Result<Link> {
    let name = c.attribute("name").ok_or_else(|| err(c, Some("name"), "a link needs a name".into()))?.to_string();
    let inertial = c.children().find(|n| n.has_tag_name("inertial")).map(|n| inertial(n, err)).transpose()?;
    let mut geoms = vec![];
    for g in c.children().filter(|n| n.has_tag_name("collision") || (opts.visual && n.has_tag_name("visual"))) {
        let visual = g.has_tag_name("visual");
        let Some(shape) = geometry(g, dir, opts, meshes, err)? else { continue };
        let rgba = g.children().find(|n| n.has_tag_name("material")).and_then(|m| {
            rgba_of(m).or_else(|| materials.iter().find(|(n, _)| Some(n.as_str()) == m.attribute("name")).map(|x| x.1))
        });
        geoms.push(Geom { pose: origin(g, err)?, shape, visual, rgba });
    }
    Ok(Link { name, inertial, geoms, joint: None, pose: Pose::IDENTITY, parent: None, children: vec![] })
}

/// A `<joint>` (number `index`), its child placed under its parent in `links`.
fn read_joint(c: Node, links: &mut [Link], index: usize, err: &ErrFn) -> Result<Joint> {
    let name = c.attribute("name").unwrap_or("").to_string();
    let link_of = |tag: &str| -> Result<usize> {
        let n = c.children().find(|n| n.has_tag_name(tag)).and_then(|n| n.attribute("link"));
        let n = n.ok_or_else(|| err(c, Some(tag), format!("joint '{name}' needs a {tag} link")))?;
        links.iter().position(|l| l.name == n).ok_or_else(|| err(c, Some(tag), format!("joint '{name}' names unknown link '{n}'")))
    };
    let (parent, child) = (link_of("parent")?, link_of("child")?);
    if links[child].parent.is_some() {
        return Err(err(c, Some("child"), format!("link '{}' is the child of two joints", links[child].name)));
    }
    let kind = match c.attribute("type").unwrap_or("") {
        "revolute" | "continuous" => Some("hinge"),
        "prismatic" => Some("slide"),
        "floating" => Some("free"),
        "fixed" => None,
        t => return Err(err(c, Some("type"), format!("joint type '{t}' is not supported (revolute, continuous, prismatic, fixed, floating)"))),
    };
    let limit = c.children().find(|n| n.has_tag_name("limit"));
    // equal limits (a common placeholder) leave the joint unlimited, as MuJoCo reads them;
    // so do limits beyond any state sinew holds (±1e16 stands for none)
    let range = match (c.attribute("type"), limit) {
        (Some("revolute" | "prismatic"), Some(l)) => Some([num(l, "lower", 0.0, &err)?, num(l, "upper", 0.0, &err)?])
            .filter(|r| r[0] != r[1] && r.iter().all(|x| x.abs() < crate::math::MAX_STATE)),
        _ => None,
    };
    let dynamics = c.children().find(|n| n.has_tag_name("dynamics"));
    let axis = match c.children().find(|n| n.has_tag_name("axis")) {
        Some(a) => vec3(a, "xyz", DVec3::X, &err)?,
        None => DVec3::X,
    };
    if kind.is_some_and(|k| k != "free") && axis.length() < 1e-12 {
        return Err(err(c, Some("axis"), format!("joint '{name}' has a zero axis")));
    }
    let mimic = c.children().find(|n| n.has_tag_name("mimic")).map(|m| -> Result<_> {
        Ok((m.attribute("joint").unwrap_or("").to_string(), num(m, "multiplier", 1.0, &err)?, num(m, "offset", 0.0, &err)?))
    });
    links[child].parent = Some(parent);
    links[child].pose = origin(c, &err)?;
    links[child].joint = Some(index);
    links[parent].children.push(child);
    Ok(Joint {
        name,
        kind,
        axis,
        range,
        damping: dynamics.map_or(Ok(0.0), |d| num(d, "damping", 0.0, &err))?,
        friction: dynamics.map_or(Ok(0.0), |d| num(d, "friction", 0.0, &err))?,
        effort: limit.map_or(Ok(0.0), |l| num(l, "effort", 0.0, &err))?.abs(),
        mimic: mimic.transpose()?,
    })
}

struct Writer<'a> {
    links: &'a [Link],
    joints: &'a [Joint],
    self_collision: bool,
}

impl Writer<'_> {
    /// Writes link `l` at `pose` (in the enclosing MJCF body): a body when it has a joint (or is
    /// a floating root), else its geoms fused into the enclosing body (its inertia is added
    /// there by [`Writer::fused_inertia`]; the world keeps none).
    fn body(&self, out: &mut String, eq: &mut String, l: usize, pose: Pose, floating: bool) {
        let link = &self.links[l];
        let joint = link.joint.map(|j| &self.joints[j]).filter(|j| j.kind.is_some());
        let opens = joint.is_some() || floating;
        let inner = if opens {
            write!(out, "<body name=\"{}\" {}>", xml_escape(&link.name), pose_attrs(&pose)).unwrap_or(());
            if floating {
                out.push_str("<freejoint/>");
            }
            if let Some(j) = joint {
                self.joint(out, eq, j);
            }
            Pose::IDENTITY
        } else {
            pose
        };
        // a body's inertia is its link's and its fused descendants'; the world keeps none
        if opens && let Some(i) = self.fused_inertia(l, &Pose::IDENTITY, true) {
            write_inertial(out, &i);
        }
        for g in &link.geoms {
            let p = inner.then(&g.pose);
            let extra = match (g.visual, self.self_collision) {
                (true, _) => " contype=\"0\" conaffinity=\"0\" group=\"1\" mass=\"0\"",
                (false, false) => " contype=\"2\" conaffinity=\"1\"",
                (false, true) => "",
            };
            let rgba = g.rgba.map_or(String::new(), |c| format!(" rgba=\"{} {} {} {}\"", c[0], c[1], c[2], c[3]));
            write!(out, "<geom {} {}{extra}{rgba}/>", pose_attrs(&p), g.shape).unwrap_or(());
        }
        for &c in &link.children {
            let child = &self.links[c];
            self.body(out, eq, c, inner.then(&child.pose), false);
        }
        if opens {
            out.push_str("</body>");
        }
    }

    fn joint(&self, out: &mut String, eq: &mut String, j: &Joint) {
        let kind = j.kind.unwrap_or("hinge");
        if kind == "free" {
            write!(out, "<freejoint name=\"{}\"/>", xml_escape(&j.name)).unwrap_or(());
            return;
        }
        let range = j.range.map_or(" limited=\"false\"".to_string(), |r| format!(" limited=\"true\" range=\"{} {}\"", r[0], r[1]));
        write!(
            out,
            "<joint name=\"{}\" type=\"{kind}\" axis=\"{} {} {}\"{range} damping=\"{}\" frictionloss=\"{}\"/>",
            xml_escape(&j.name),
            j.axis.x,
            j.axis.y,
            j.axis.z,
            j.damping,
            j.friction
        )
        .unwrap_or(());
        if let Some((other, multiplier, offset)) = &j.mimic {
            write!(eq, "<joint joint1=\"{}\" joint2=\"{}\" polycoef=\"{offset} {multiplier} 0 0 0\"/>", xml_escape(&j.name), xml_escape(other)).unwrap_or(());
        }
    }

    /// The combined mass properties of link `l` at `pose` and of the descendants fused into it
    /// (children without joints; a massless one adds nothing, as in MuJoCo), in the enclosing
    /// body's frame; `top`: `l` is the body's own link.
    fn fused_inertia(&self, l: usize, pose: &Pose, top: bool) -> Option<SpatialInertia> {
        let link = &self.links[l];
        let own = link.inertial.filter(|i| top || i.mass > 0.0).map(|i| i.to_parent(DMat3::from_quat(pose.rot), pose.pos));
        let fused = link.children.iter().filter(|&&c| self.links[c].joint.is_none_or(|j| self.joints[j].kind.is_none()));
        fused.filter_map(|&c| self.fused_inertia(c, &pose.then(&self.links[c].pose), false)).chain(own).reduce(|a, b| a.combine(&b))
    }
}

/// `<inertial>` of mass properties in the body frame.
fn write_inertial(out: &mut String, i: &SpatialInertia) {
    let (c, f) = (i.com, i.ic);
    write!(
        out,
        "<inertial pos=\"{} {} {}\" mass=\"{}\" fullinertia=\"{} {} {} {} {} {}\"/>",
        c.x, c.y, c.z, i.mass, f.x_axis.x, f.y_axis.y, f.z_axis.z, f.y_axis.x, f.z_axis.x, f.z_axis.y
    )
    .unwrap_or(());
}

/// `pos` and `quat` attributes of a pose.
fn pose_attrs(p: &Pose) -> String {
    format!("pos=\"{} {} {}\" quat=\"{} {} {} {}\"", p.pos.x, p.pos.y, p.pos.z, p.rot.w, p.rot.x, p.rot.y, p.rot.z)
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;").replace('>', "&gt;")
}

type ErrFn<'a> = dyn Fn(Node, Option<&str>, String) -> Error + 'a;

fn num(n: Node, attr: &str, default: f64, err: &ErrFn) -> Result<f64> {
    match n.attribute(attr) {
        None => Ok(default),
        Some(v) => v.trim().parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| err(n, Some(attr), format!("'{v}' is not a finite number"))),
    }
}

fn vec3(n: Node, attr: &str, default: DVec3, err: &ErrFn) -> Result<DVec3> {
    let Some(v) = n.attribute(attr) else { return Ok(default) };
    let x: Vec<f64> = v.split_whitespace().map(str::parse).collect::<std::result::Result<_, _>>().map_err(|_| err(n, Some(attr), format!("'{v}' is not three numbers")))?;
    match x[..] {
        [a, b, c] if x.iter().all(|x| x.is_finite()) => Ok(DVec3::new(a, b, c)),
        _ => Err(err(n, Some(attr), format!("'{v}' is not three finite numbers"))),
    }
}

/// An element's `<origin xyz rpy>`: rpy are fixed-axis roll, pitch, yaw (R = Rz Ry Rx).
fn origin(n: Node, err: &ErrFn) -> Result<Pose> {
    let Some(o) = n.children().find(|c| c.has_tag_name("origin")) else { return Ok(Pose::IDENTITY) };
    let (xyz, rpy) = (vec3(o, "xyz", DVec3::ZERO, err)?, vec3(o, "rpy", DVec3::ZERO, err)?);
    let rot = DQuat::from_rotation_z(rpy.z) * DQuat::from_rotation_y(rpy.y) * DQuat::from_rotation_x(rpy.x);
    Ok(Pose { rot, pos: xyz })
}

fn inertial(n: Node, err: &ErrFn) -> Result<SpatialInertia> {
    let o = origin(n, err)?;
    let mass = n.children().find(|c| c.has_tag_name("mass")).map_or(Ok(0.0), |m| num(m, "value", 0.0, err))?;
    if mass < 0.0 {
        return Err(err(n, Some("mass"), format!("negative mass {mass}")));
    }
    let i = n.children().find(|c| c.has_tag_name("inertia"));
    let get = |a: &str| i.map_or(Ok(0.0), |i| num(i, a, 0.0, err));
    let (xx, yy, zz, xy, xz, yz) = (get("ixx")?, get("iyy")?, get("izz")?, get("ixy")?, get("ixz")?, get("iyz")?);
    let local = DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz));
    let rot = DMat3::from_quat(o.rot);
    Ok(SpatialInertia::new(mass, o.pos, rot * local * rot.transpose()))
}

fn rgba_of(material: Node) -> Option<[f64; 4]> {
    let c = material.children().find(|c| c.has_tag_name("color"))?.attribute("rgba")?;
    let v: Vec<f64> = c.split_whitespace().filter_map(|x| x.parse().ok()).collect();
    (v.len() == 4).then(|| [v[0], v[1], v[2], v[3]])
}

/// A `<collision>` or `<visual>` element's geometry as MJCF attributes (None: nothing to draw or
/// collide, such as a mesh format sinew does not read in a visual).
fn geometry(g: Node, dir: &Path, opts: &UrdfOptions, meshes: &mut Vec<(String, PathBuf, DVec3)>, err: &ErrFn) -> Result<Option<String>> {
    let Some(shape) = g.children().find(|c| c.has_tag_name("geometry")).and_then(|c| c.children().find(Node::is_element)) else {
        return Ok(None);
    };
    let positive = |a: &str| -> Result<f64> {
        let x = num(shape, a, 0.0, err)?;
        if x > 0.0 { Ok(x) } else { Err(err(shape, Some(a), format!("{a} must be positive, got {x}"))) }
    };
    Ok(Some(match shape.tag_name().name() {
        "box" => {
            let s = vec3(shape, "size", DVec3::ZERO, err)?;
            if s.min_element() <= 0.0 {
                return Err(err(shape, Some("size"), "box sizes must be positive".into()));
            }
            format!("type=\"box\" size=\"{} {} {}\"", s.x / 2.0, s.y / 2.0, s.z / 2.0)
        }
        "sphere" => format!("type=\"sphere\" size=\"{}\"", positive("radius")?),
        "cylinder" => format!("type=\"cylinder\" size=\"{} {}\"", positive("radius")?, positive("length")? / 2.0),
        "capsule" => format!("type=\"capsule\" size=\"{} {}\"", positive("radius")?, positive("length")? / 2.0),
        "mesh" => {
            let uri = shape.attribute("filename").ok_or_else(|| err(shape, Some("filename"), "a mesh needs a filename".into()))?;
            let ext = Path::new(uri).extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            if !matches!(ext.as_str(), "stl" | "obj" | "msh") {
                if g.has_tag_name("visual") {
                    return Ok(None);
                }
                return Err(err(shape, Some("filename"), format!("mesh '{uri}': only STL, OBJ and .msh files are read")));
            }
            let file = resolve(uri, dir, &opts.package_dirs).ok_or_else(|| {
                err(shape, Some("filename"), format!("mesh '{uri}' not found (package directories: {:?}; the URDF's directory)", opts.package_dirs))
            })?;
            let scale = vec3(shape, "scale", DVec3::ONE, err)?;
            let name = match meshes.iter().find(|(_, f, s)| *f == file && *s == scale) {
                Some((n, _, _)) => n.clone(),
                None => {
                    let n = format!("mesh{}", meshes.len());
                    meshes.push((n.clone(), file, scale));
                    n
                }
            };
            format!("type=\"mesh\" mesh=\"{name}\"")
        }
        other => return Err(err(shape, None, format!("unknown geometry <{other}>"))),
    }))
}

/// The file a mesh URI names: `package://NAME/rest` under a package directory (one holding NAME,
/// or NAME itself), a `file://` or plain path (relative to the URDF's directory), else the file's
/// base name in the URDF's directory (MuJoCo's `strippath`).
fn resolve(uri: &str, dir: &Path, packages: &[PathBuf]) -> Option<PathBuf> {
    let mut candidates: Vec<PathBuf> = vec![];
    if let Some(rest) = uri.strip_prefix("package://") {
        let (pkg, tail) = rest.split_once('/').unwrap_or((rest, ""));
        for p in packages {
            candidates.push(p.join(pkg).join(tail));
            if p.file_name().is_some_and(|n| n == pkg) {
                candidates.push(p.join(tail));
            }
        }
    } else {
        candidates.push(dir.join(uri.strip_prefix("file://").unwrap_or(uri)));
    }
    if let Some(base) = Path::new(uri).file_name() {
        candidates.push(dir.join(base));
    }
    candidates.into_iter().find(|c| c.is_file()).map(|c| std::fs::canonicalize(&c).unwrap_or(c))
}
