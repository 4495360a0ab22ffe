//! Height fields: elevations read as MuJoCo reads them (inline, PNG with its top row at +y,
//! MuJoCo's binary grid, normalized to [0, 1]); every primitive and a mesh rest on a flat field
//! exactly where they rest on a plane; a ramp holds a box below its friction angle and lets it
//! slide above; a ball rests on a bump at the field's interpolated height.

use sinew::{Model, State};

/// A flat 5 × 5 field 2 m across at z = 0 (all elevations equal) or a plane, and a free body
/// whose one geom is `geom`.
fn scene(ground: &str, geom: &str) -> String {
    let (asset, floor) = match ground {
        "hfield" => (r#"<hfield name="h" nrow="5" ncol="5" size="1 1 0.5 0.2"/>"#, r#"<geom type="hfield" hfield="h"/>"#),
        _ => ("", r#"<geom type="plane" size="2 2 0.1"/>"#),
    };
    format!(
        r#"<mujoco><option timestep="0.002"/><asset>{asset}<mesh name="gem" vertex="0.1 0 -0.04  0.05 0.08660254 -0.04  -0.05 0.08660254 -0.04  -0.1 0 -0.04  -0.05 -0.08660254 -0.04  0.05 -0.08660254 -0.04 0.06 0 0.04  0.03 0.05196152 0.04  -0.03 0.05196152 0.04  -0.06 0 0.04  -0.03 -0.05196152 0.04  0.03 -0.05196152 0.04"/></asset>
        <worldbody>{floor}<body pos="0.13 0.07 0.3"><freejoint/>{geom}</body></worldbody></mujoco>"#
    )
}

fn settle(m: &Model, steps: usize) -> State {
    let mut s = State::new(m);
    for _ in 0..steps {
        s.step(m);
    }
    s
}

#[test]
fn every_shape_rests_on_a_flat_field_as_on_a_plane() {
    let shapes = [
        r#"<geom type="sphere" size="0.05"/>"#,
        r#"<geom type="capsule" size="0.03 0.08" quat="0.7071068 0.7071068 0 0"/>"#,
        r#"<geom type="box" size="0.05 0.06 0.04"/>"#,
        r#"<geom type="mesh" mesh="gem"/>"#,
    ];
    for geom in shapes {
        let (on_field, on_plane) = (Model::from_mjcf(&scene("hfield", geom)).unwrap(), Model::from_mjcf(&scene("plane", geom)).unwrap());
        let (a, b) = (settle(&on_field, 1000), settle(&on_plane, 1000));
        assert!((a.qpos[2] - b.qpos[2]).abs() < 1e-6, "{geom}: rests at z = {} on the field, {} on a plane", a.qpos[2], b.qpos[2]);
        assert!(a.qvel.iter().all(|v| v.abs() < 1e-5), "{geom}: still moving on the field: {:?}", a.qvel);
        let stats = a.data.constraints.stats;
        assert_eq!(stats.fallback_pgs + stats.fallback_zero, 0, "{geom}: fallback solves");
    }
}

#[test]
fn a_ramp_holds_a_box_below_its_friction_angle() {
    // elevation rises along x: 0.5 m over 2 m, 14.0° (holds with μ 0.3, 16.7°), or 1.2 m, 31.0°
    for (rise, holds) in [(0.5f64, true), (1.2, false)] {
        let slope = (rise / 2.0).atan();
        let (s, c) = ((slope / 2.0).sin(), (slope / 2.0).cos());
        let xml = format!(
            r#"<mujoco><option timestep="0.002"/><asset><hfield name="ramp" nrow="2" ncol="2" size="1 1 {rise} 0.1" elevation="0 1 0 1"/></asset>
            <worldbody><geom type="hfield" hfield="ramp" friction="0.3"/>
            <body pos="0 0 {}" quat="{c} 0 {} 0"><freejoint/><geom type="box" size="0.1 0.1 0.05" friction="0.3"/></body></worldbody></mujoco>"#,
            rise / 2.0 + 0.06 / slope.cos(),
            -s
        );
        let m = Model::from_mjcf(&xml).unwrap();
        let mut st = settle(&m, 100);
        let x0 = st.qpos[0];
        for _ in 0..400 {
            st.step(&m);
        }
        let moved = (st.qpos[0] - x0).abs();
        if holds {
            assert!(moved < 1e-6, "rise {rise}: slid {moved} m below the friction angle");
        } else {
            assert!(moved > 0.02, "rise {rise}: held ({moved} m) above the friction angle");
        }
    }
}

#[test]
fn a_ball_rests_on_a_bump_at_the_fields_height() {
    // a 3 × 3 field whose centre is raised: the ball dropped on the peak stays on it
    let xml = r#"<mujoco><option timestep="0.002"/><asset><hfield name="bump" nrow="3" ncol="3" size="1 1 0.3 0.1" elevation="0 0 0  0 1 0  0 0 0"/></asset>
        <worldbody><geom type="hfield" hfield="bump"/>
        <body pos="0 0 0.6"><freejoint/><geom type="sphere" size="0.05"/></body></worldbody></mujoco>"#;
    let m = Model::from_mjcf(xml).unwrap();
    let s = settle(&m, 1000);
    // on the apex the ball touches the peak itself: its centre one radius above it
    let expected = 0.3 + 0.05;
    assert!((s.qpos[2] - expected).abs() < 1e-6 && s.qpos[0].abs() < 1e-6, "ball at {:?}, expected z {expected}", &s.qpos[..3]);
}

#[test]
fn elevations_load_from_png_and_binary_files_as_mujoco_reads_them() {
    let dir = std::env::temp_dir().join(format!("sinew-hfields-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // a 3 × 2 grey image: top row (0, 50), middle (100, 150), bottom (200, 250)
    let pixels = [0u8, 50, 100, 150, 200, 250];
    let file = std::fs::File::create(dir.join("terrain.png")).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 2, 3);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(&pixels).unwrap();
    // MuJoCo's binary grid: nrow, ncol, then the elevations row by row
    let mut bin: Vec<u8> = [2i32, 2].iter().flat_map(|x| x.to_le_bytes()).collect();
    bin.extend([1.0f32, 3.0, 2.0, 5.0].iter().flat_map(|x| x.to_le_bytes()));
    std::fs::write(dir.join("terrain.bin"), bin).unwrap();
    let xml = r#"<mujoco><asset><hfield file="terrain.png" size="1 1 1 0.1"/><hfield name="b" file="terrain.bin" size="1 1 1 0.1"/></asset>
        <worldbody><geom type="hfield" hfield="terrain"/><geom type="hfield" hfield="b"/></worldbody></mujoco>"#;
    std::fs::write(dir.join("model.xml"), xml).unwrap();
    let m = Model::from_mjcf_file(&dir.join("model.xml")).unwrap();
    let h = &m.hfields[0];
    assert_eq!((h.nrow, h.ncol), (3, 2));
    // row 0 (−y) is the image's bottom row; normalized by the range 0–250
    let expected = [200.0, 250.0, 100.0, 150.0, 0.0, 50.0].map(|x: f64| x / 250.0);
    assert!(h.data.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12), "{:?}", h.data);
    let b = &m.hfields[1];
    assert_eq!(b.data, vec![0.0, 0.5, 0.25, 1.0]);
    // a file that is not an image, or whose grid does not match its size, is an error
    for (name, bytes) in [("bad.png", b"not a png".to_vec()), ("bad.bin", [3i32, 3].iter().flat_map(|x| x.to_le_bytes()).collect())] {
        std::fs::write(dir.join(name), bytes).unwrap();
        let xml = format!(r#"<mujoco><asset><hfield name="h" file="{name}" size="1 1 1 0.1"/></asset></mujoco>"#);
        std::fs::write(dir.join("bad.xml"), xml).unwrap();
        let e = Model::from_mjcf_file(&dir.join("bad.xml")).expect_err(name).to_string();
        assert!(e.contains("hfield") && e.contains(name), "{name}: {e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_height_fields_are_clear_errors() {
    let cases = [
        (r#"<hfield name="h" nrow="1" ncol="5" size="1 1 1 1"/>"#, "nrow"),
        (r#"<hfield name="h" nrow="2" ncol="2" size="1 1 1"/>"#, "size"),
        (r#"<hfield name="h" nrow="2" ncol="2" size="1 1 -1 1"/>"#, "positive"),
        (r#"<hfield name="h" nrow="2" ncol="2" size="1 1 1 1" elevation="1 2 3"/>"#, "elevation"),
        (r#"<hfield name="h" nrow="100000" ncol="100000" size="1 1 1 1"/>"#, "larger"),
    ];
    for (asset, says) in cases {
        let xml = format!(r#"<mujoco><asset>{asset}</asset><worldbody><geom type="hfield" hfield="h"/></worldbody></mujoco>"#);
        let e = Model::from_mjcf(&xml).unwrap_err().to_string();
        assert!(e.contains(says), "{asset}: {e}");
    }
}

#[test]
fn a_world_with_values_of_its_own_shares_the_models_meshes_and_heights_until_it_sets_heights() {
    use sinew::batch::Batch;
    use sinew::compile::params::Param;
    use std::sync::Arc;
    let m = Arc::new(Model::from_mjcf(&scene("hfield", r#"<geom type="mesh" mesh="gem"/>"#)).unwrap());
    let mut b = Batch::new(m.clone(), &[1, 2], Some(1)).unwrap();
    let friction: Vec<f64> = Param::GeomFriction.read(&m).iter().map(|f| f * 0.5).collect();
    b.set_param(Param::GeomFriction, &[0, 1], &[friction.clone(), friction].concat()).unwrap();
    for i in 0..2 {
        assert!(Arc::ptr_eq(&b.model_of(i).meshes, &m.meshes) && Arc::ptr_eq(&b.model_of(i).hfields, &m.hfields));
    }
    let heights: Vec<f64> = (0..25).map(|k| k as f64 / 25.0).collect();
    b.set_param(Param::HfieldData, &[1], &heights).unwrap();
    assert!(Arc::ptr_eq(&b.model_of(0).hfields, &m.hfields) && !Arc::ptr_eq(&b.model_of(1).hfields, &m.hfields));
    assert_eq!(b.model_of(1).hfields[0].data, heights);
    assert!(m.hfields[0].data.iter().all(|&h| h == m.hfields[0].data[0]), "the model's own heights changed");
}
