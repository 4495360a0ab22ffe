//! `<include>`: nested files spliced in place (paths beside the including file, else beside the
//! main one), the same model as the text pasted by hand, and errors naming the file and line they
//! are in.

use std::path::{Path, PathBuf};

use sinew::{Error, Model};

/// A fresh directory with `files` (relative path, text) written in it, removed when dropped.
fn tree(name: &str, files: &[(&str, &str)]) -> Tree {
    let dir = std::env::temp_dir().join(format!("sinew-include-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (path, text) in files {
        let p = dir.join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    Tree(dir)
}

/// A test's directory of model files ([`tree`]).
struct Tree(PathBuf);

impl std::ops::Deref for Tree {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Tree {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const ARM: &str = "<mujoco>\n  <body name='arm' pos='0 0 1'>\n    <joint name='shoulder' axis='0 1 0'/>\n    <geom type='capsule' size='0.1' fromto='0 0 0 0.5 0 0'/>\n    <include file='hand.xml'/>\n  </body>\n</mujoco>\n";
const HAND: &str = "<mujoco>\n<body name='hand' pos='0.5 0 0'>\n  <joint name='wrist' axis='0 1 0'/>\n  <geom size='0.05'/>\n</body>\n</mujoco>\n";

fn main_xml(arm: &str) -> String {
    format!("<mujoco model='m'>\n  <option timestep='0.005'/>\n  <worldbody>\n    <include file='{arm}'/>\n  </worldbody>\n  <actuator><motor joint='wrist'/></actuator>\n</mujoco>\n")
}

#[test]
fn nested_includes_give_the_model_pasted_by_hand() {
    let dir = tree("nested", &[("main.xml", &main_xml("parts/arm.xml")), ("parts/arm.xml", ARM), ("parts/hand.xml", HAND)]);
    let (m, text) = Model::load_file(&dir.join("main.xml")).unwrap();
    assert!(!text.contains("<include"), "{text}");
    let pasted = "<mujoco model='m'><option timestep='0.005'/><worldbody>\
        <body name='arm' pos='0 0 1'><joint name='shoulder' axis='0 1 0'/><geom type='capsule' size='0.1' fromto='0 0 0 0.5 0 0'/>\
        <body name='hand' pos='0.5 0 0'><joint name='wrist' axis='0 1 0'/><geom size='0.05'/></body></body>\
        </worldbody><actuator><motor joint='wrist'/></actuator></mujoco>";
    let by_hand = Model::from_mjcf(pasted).unwrap();
    assert_eq!((m.nq, m.nv, m.nu, m.nbody), (by_hand.nq, by_hand.nv, by_hand.nu, by_hand.nbody));
    assert_eq!(m.body_name, by_hand.body_name);
    assert_eq!(m.body_mass, by_hand.body_mass);
    assert_eq!(m.opt.timestep, 0.005);
    // the expanded text stands alone
    assert_eq!(Model::from_mjcf(&text).unwrap().body_mass, m.body_mass);
}

#[test]
fn a_path_is_taken_beside_the_main_file_when_not_beside_the_including_one() {
    // hand.xml sits beside main.xml, not beside parts/arm.xml
    let dir = tree("main-dir", &[("main.xml", &main_xml("parts/arm.xml")), ("parts/arm.xml", ARM), ("hand.xml", HAND)]);
    assert_eq!(Model::from_mjcf_file(&dir.join("main.xml")).unwrap().nq, 2);
}

fn in_file(e: Error) -> (PathBuf, Error) {
    match e {
        Error::InFile { file, error } => (PathBuf::from(file), *error),
        e => panic!("not in a file: {e:?}"),
    }
}

#[test]
fn an_error_in_an_included_file_names_that_file_and_its_line() {
    let bad_hand = HAND.replace("axis='0 1 0'", "axis='0 1'");
    let dir = tree("error", &[("main.xml", &main_xml("parts/arm.xml")), ("parts/arm.xml", ARM), ("parts/hand.xml", &bad_hand)]);
    let (file, e) = in_file(Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err());
    assert_eq!(file, dir.join("parts/hand.xml"));
    assert!(matches!(e, Error::Model { ref element, line: 3, .. } if element == "joint"), "{e:?}");
    // and one in the main file after the includes, its own line
    let bad_main = main_xml("parts/arm.xml").replace("joint='wrist'", "joint='elbow'");
    let dir = tree("error-main", &[("main.xml", &bad_main), ("parts/arm.xml", ARM), ("parts/hand.xml", HAND)]);
    let (file, e) = in_file(Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err());
    assert_eq!(file, dir.join("main.xml"));
    assert!(matches!(e, Error::Model { ref element, line: 6, .. } if element == "motor"), "{e:?}");
}

#[test]
fn missing_cyclic_and_malformed_includes_are_errors() {
    let dir = tree("missing", &[("main.xml", &main_xml("nowhere.xml"))]);
    let (file, e) = in_file(Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err());
    assert_eq!(file, dir.join("main.xml"));
    assert!(matches!(e, Error::Model { ref element, line: 4, .. } if element == "include"), "{e:?}");
    let dir = tree("cycle", &[("main.xml", &main_xml("arm.xml")), ("arm.xml", &ARM.replace("hand.xml", "arm.xml"))]);
    let e = Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err();
    assert!(e.to_string().contains("includes itself"), "{e}");
    let dir = tree("root", &[("main.xml", &main_xml("arm.xml")), ("arm.xml", "<robot/>")]);
    let (file, _) = in_file(Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err());
    assert_eq!(file, dir.join("arm.xml"));
    let dir = tree("xml", &[("main.xml", &main_xml("arm.xml")), ("arm.xml", "<mujoco>\n<body>\n</mujoco>")]);
    let (file, e) = in_file(Model::from_mjcf_file(&dir.join("main.xml")).unwrap_err());
    assert_eq!(file, dir.join("arm.xml"));
    assert!(matches!(e, Error::Xml { line: 3, .. }), "{e:?}");
}

#[test]
fn text_without_includes_is_read_as_it_is() {
    let xml = "<mujoco><worldbody><body><joint/><geom size='0.1'/></body></worldbody></mujoco>";
    assert_eq!(Model::from_mjcf(xml).unwrap().nq, 1);
    let _ = Path::new(".");
}
