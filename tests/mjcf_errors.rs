//! Malformed and unsupported MJCF give errors naming element, attribute and line; accepted but
//! unmodelled features give warnings.
#![allow(clippy::needless_range_loop)] // index loops follow the math's notation

use sinew::{Error, Model};

fn err(xml: &str) -> Error {
    Model::from_mjcf(xml).expect_err("should fail")
}

#[test]
fn malformed_xml_reports_the_line() {
    match err("<mujoco>\n<worldbody>\n<body>\n</worldbody></mujoco>") {
        Error::Xml { line, .. } => assert_eq!(line, 4),
        e => panic!("{e:?}"),
    }
}

#[test]
fn bad_numbers_name_element_attribute_and_line() {
    let e = err("<mujoco>\n<worldbody>\n<body>\n<joint range=\"0 abc\"/>\n<geom size=\"0.1\"/></body></worldbody></mujoco>");
    assert_eq!(e, Error::model("joint", Some("range"), 4, "'abc' is not a number"));
    let e = err("<mujoco><worldbody><body><joint axis=\"0 1\"/><geom size=\"1\"/></body></worldbody></mujoco>");
    assert!(matches!(e, Error::Model { ref element, attribute: Some(ref a), line: 1, .. } if element == "joint" && a == "axis"), "{e}");
}

#[test]
fn unsupported_things_are_errors() {
    let cases = [
        ("<mujoco><worldbody><body><joint foo=\"1\"/><geom size=\"1\"/></body></worldbody></mujoco>", "joint", Some("foo")),
        ("<mujoco><worldbody><body><geom type=\"mesh\" size=\"1\"/></body></worldbody></mujoco>", "geom", Some("mesh")),
        ("<mujoco><worldbody><body><geom type=\"sdf\" size=\"1\"/></body></worldbody></mujoco>", "geom", Some("type")),
        ("<mujoco><worldbody><body><composite/></body></worldbody></mujoco>", "composite", None),
        ("<mujoco><equality><flex flex=\"a\"/></equality></mujoco>", "flex", None),
        ("<mujoco><equality><weld body1=\"a\"/></equality></mujoco>", "weld", Some("body1")),
        ("<mujoco><actuator><adhesion body=\"b\"/></actuator></mujoco>", "adhesion", None),
        ("<mujoco><actuator><general joint=\"j\" dyntype=\"muscle\"/></actuator></mujoco>", "general", Some("dyntype")),
        ("<mujoco><actuator><general joint=\"j\" dyntype=\"filter\" dynprm=\"0\"/></actuator></mujoco>", "general", Some("dynprm")),
        ("<mujoco><actuator><general joint=\"j\" actlimited=\"true\" actrange=\"1 0\"/></actuator></mujoco>", "general", Some("actrange")),
        ("<mujoco><actuator><position joint=\"j\"/></actuator></mujoco>", "position", Some("joint")),
        ("<mujoco><compiler coordinate=\"global\"/></mujoco>", "compiler", Some("coordinate")),
        ("<mujoco><tendon><spatial/></tendon></mujoco>", "spatial", None),
        ("<mujoco><tendon><fixed armature=\"1\"/></tendon></mujoco>", "fixed", Some("armature")),
        ("<mujoco><tendon><fixed limited=\"true\" range=\"1 0\"/></tendon></mujoco>", "fixed", Some("range")),
        ("<mujoco><worldbody><body><joint type=\"screw\"/></body></worldbody></mujoco>", "joint", Some("type")),
        ("<mujoco><worldbody><body><joint class=\"nope\"/></body></worldbody></mujoco>", "joint", Some("class")),
    ];
    for (xml, element, attr) in cases {
        match err(xml) {
            Error::Model { element: e, attribute: a, .. } => {
                assert_eq!((e.as_str(), a.as_deref()), (element, attr), "{xml}");
            }
            e => panic!("{xml}: {e:?}"),
        }
    }
}

#[test]
fn massless_moving_body_is_a_compile_error() {
    let e = err("<mujoco><worldbody><body><joint name=\"j\"/></body></worldbody></mujoco>");
    assert!(matches!(e, Error::Compile(ref m) if m.contains("'j'")), "{e}");
}

#[test]
fn unknown_actuator_joint_is_an_error() {
    let e = err("<mujoco><worldbody><body><joint name=\"a\"/><geom size=\"1\"/></body></worldbody><actuator><motor joint=\"b\"/></actuator></mujoco>");
    assert!(matches!(e, Error::Model { ref attribute, .. } if attribute.as_deref() == Some("joint")), "{e}");
}

#[test]
fn unmodelled_physics_gives_warnings() {
    let m = Model::from_mjcf("<mujoco><option viscosity=\"0.1\" integrator=\"implicit\"/><worldbody><body><joint name=\"j\" frictionloss=\"1\"/><geom size=\"1\"/></body></worldbody>\
        <tendon><fixed frictionloss=\"1\"><joint joint=\"j\"/></fixed></tendon></mujoco>").unwrap();
    // the implicit integrator is read as implicitfast; fluid forces and joint and tendon friction are modelled
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert!(m.warnings[0].contains("implicitfast"), "{:?}", m.warnings);
    let m = Model::from_mjcf("<mujoco><option integrator=\"implicitfast\"/><worldbody><body><joint/><geom size=\"1\"/></body></worldbody></mujoco>").unwrap();
    assert!(m.warnings.is_empty() && m.opt.implicit_actuators, "{:?}", m.warnings);
    // torsional and rolling friction are modelled
    let m = Model::from_mjcf("<mujoco><worldbody><body><freejoint/><geom name=\"g\" size=\"1\" condim=\"6\"/></body></worldbody></mujoco>").unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

#[test]
fn defaults_classes_and_childclass_resolve() {
    let xml = r#"<mujoco><default><joint damping="1"/><default class="a"><joint damping="2" armature="0.5"/>
        <default class="b"><joint armature="3"/></default></default></default>
        <worldbody><body childclass="a"><joint/><geom size="1"/><body><joint class="b"/><geom size="1"/></body>
        <body><joint class="main"/><geom size="1"/></body></body></worldbody></mujoco>"#;
    let m = Model::from_mjcf(xml).unwrap();
    assert_eq!(m.dof_damping, vec![2.0, 2.0, 1.0]);
    assert_eq!(m.dof_armature, vec![0.5, 3.0, 0.0]);
}

#[test]
fn orientations_agree_with_each_other() {
    // the same 90° rotation about z in four notations
    let forms = ["quat=\"0.7071067811865476 0 0 0.7071067811865476\"", "axisangle=\"0 0 1 90\"", "euler=\"0 0 90\"", "xyaxes=\"0 1 0 -1 0 0\""];
    let quats: Vec<_> = forms
        .iter()
        .map(|f| {
            let m = Model::from_mjcf(&format!("<mujoco><worldbody><body {f}><geom size=\"1\"/></body></worldbody></mujoco>")).unwrap();
            m.body_quat[1]
        })
        .collect();
    for q in &quats {
        assert!(q.abs_diff_eq(quats[0], 1e-12), "{q:?} vs {:?}", quats[0]);
    }
}

#[test]
fn a_free_joint_is_never_limited_whatever_its_class_says() {
    // MuJoCo's mjCJoint::Compile sets limited false on a free joint: MuJoCo's own flattened
    // 22_humanoids.xml gives its free joints a class with limited="true" and no range
    let xml = "<mujoco><default><joint limited='true'/></default><worldbody><body><joint type='free'/>\
        <geom size='0.1'/><body><joint axis='0 1 0' range='-1 1'/><geom size='0.1' pos='0 0 -0.3'/></body></body></worldbody></mujoco>";
    let m = Model::from_mjcf(xml).unwrap();
    assert_eq!(m.jnt_limited, vec![false, true]);
}
