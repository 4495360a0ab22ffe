//! The renderer against the pinhole camera model and analytic shapes: where a geom appears, how
//! far away each pixel's surface is, the colours MJCF asks for, and MuJoCo's camera semantics.

use glam::DVec3;
use sinew::render::{CameraChoice, FreeCamera, Poses, Renderer};
use sinew::Model;

/// A scene lit by an ambient-only headlight, so a pixel's colour is its geom's rgba exactly.
fn scene(body: &str, extra: &str) -> Model {
    Model::from_mjcf(&format!(
        r#"<mujoco><visual><headlight ambient="1 1 1" diffuse="0 0 0" specular="0 0 0"/><map znear="0.01" zfar="50"/></visual>
        {extra}<worldbody>{body}</worldbody></mujoco>"#
    ))
    .unwrap()
}

/// The free camera `distance` from `lookat` on its −y side, looking along +y (azimuth 90°, elevation 0).
fn free(lookat: DVec3, distance: f64) -> CameraChoice {
    CameraChoice::Free(FreeCamera { lookat, distance, azimuth: 90.0, elevation: 0.0, track_body: None })
}

struct Shot {
    rgb: Vec<u8>,
    depth: Vec<f32>,
    w: usize,
    near: f64,
    far: f64,
}

impl Shot {
    fn take(m: &Model, cam: CameraChoice, w: usize, h: usize) -> Shot {
        let r = Renderer::new(m);
        let poses = Poses::new(m, &m.qpos0);
        let (mut rgb, mut depth) = (vec![0u8; w * h * 3], vec![0f32; w * h]);
        r.draw(m, &[(&poses, cam)], w, h, &mut rgb, &mut depth);
        Shot { rgb, depth, w, near: m.vis.znear * r.extent, far: m.vis.zfar * r.extent }
    }
    /// Metric depth along the view axis at pixel (x, y), None where nothing is drawn.
    fn z(&self, x: usize, y: usize) -> Option<f64> {
        let d = self.depth[y * self.w + x] as f64;
        (d < 1.0).then(|| self.near * self.far / (self.far - d * (self.far - self.near)))
    }
    fn px(&self, x: usize, y: usize) -> [u8; 3] {
        let k = 3 * (y * self.w + x);
        [self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]]
    }
}

#[test]
fn a_sphere_projects_to_the_disc_the_pinhole_model_predicts_at_its_analytic_depth() {
    let m = scene(r#"<body pos="0.3 0 0.2"><joint type="slide" limited="false"/><geom type="sphere" size="0.25" rgba="1 0 0 1"/></body>"#, "");
    // eye at (0, −3, 0) looking along +y; fovy 45°, 201 × 201 pixels
    let (w, f) = (201usize, 45f64);
    let shot = Shot::take(&m, free(DVec3::ZERO, 3.0), w, w);
    let focal = (w as f64 / 2.0) / (f.to_radians() / 2.0).tan();
    let (cx, cy) = (100.5 + focal * 0.3 / 3.0, 100.5 - focal * 0.2 / 3.0);
    // the disc's pixel centres lie within the sphere's silhouette: a circle of radius
    // focal · r / sqrt(d² − r²) about the projected centre (the centre is off-axis by
    // < 0.12 rad here, which moves the silhouette by well under a pixel)
    let radius = focal * 0.25 / (3.0f64.powi(2) + 0.3f64.powi(2) + 0.2f64.powi(2) - 0.25f64.powi(2)).sqrt();
    let mut wrong = 0;
    for y in 0..w {
        for x in 0..w {
            let r = ((x as f64 + 0.5 - cx).powi(2) + (y as f64 + 0.5 - cy).powi(2)).sqrt();
            let drawn = shot.z(x, y).is_some();
            if (r < radius - 1.0 && !drawn) || (r > radius + 1.0 && drawn) {
                wrong += 1;
            }
        }
    }
    assert_eq!(wrong, 0, "pixels off the predicted disc");
    // the pixel at the projected centre sees the sphere's nearest point
    let z = shot.z(cx as usize, cy as usize).unwrap();
    let d = DVec3::new(0.3, 3.0, 0.2).length() - 0.25;
    assert!((z - d * 3.0 / DVec3::new(0.3, 3.0, 0.2).length()).abs() < 2e-3, "depth {z} vs analytic about {d}");
    // ambient-only light: the exact colour
    assert_eq!(shot.px(cx as usize, cy as usize), [255, 0, 0]);
}

#[test]
fn each_primitive_is_seen_at_its_analytic_distance() {
    // each geom's nearest face towards an eye on −y at distance 3, seen through the image centre
    for (geom, front) in [
        (r#"type="sphere" size="0.3""#, 0.3),
        (r#"type="box" size="0.2 0.4 0.1""#, 0.4),
        (r#"type="capsule" size="0.1 0.3" euler="0 90 0""#, 0.1),
        (r#"type="cylinder" size="0.15 0.3" euler="90 0 0""#, 0.3),
        (r#"type="ellipsoid" size="0.1 0.35 0.2""#, 0.35),
        (r#"type="capsule" size="0.1 0.3" euler="90 0 0""#, 0.4),
    ] {
        let m = scene(&format!(r#"<body><joint type="slide" limited="false"/><geom {geom} rgba="0 1 0 1"/></body>"#), "");
        let shot = Shot::take(&m, free(DVec3::ZERO, 3.0), 65, 65);
        // the centre pixel looks along the axis
        let z = shot.z(32, 32).unwrap_or(f64::NAN);
        // within the float32 z-buffer's resolution at this depth
        assert!((z - (3.0 - front)).abs() < 1e-4, "{geom}: depth {z}, analytic {}", 3.0 - front);
        assert_eq!(shot.px(32, 32), [0, 255, 0], "{geom}");
    }
}

#[test]
fn a_checker_floor_tiles_its_texture_texrepeat_times() {
    // a 2 m × 2 m floor with texrepeat 2: four repeats of 2 × 2 checks, 0.5 m each
    let m = scene(
        r#"<geom type="plane" size="1 1 0.1" material="m" rgba="1 1 1 1"/><body pos="0 0 5"><joint type="slide" limited="false"/><geom size="0.01"/></body>"#,
        r#"<asset><texture name="t" type="2d" builtin="checker" rgb1="1 1 1" rgb2="0 0 0" width="8" height="8"/>
           <material name="m" texture="t" texrepeat="2 2"/></asset>"#,
    );
    // straight down from 4 m onto the floor (elevation −90 is singular: −89.999)
    let cam = CameraChoice::Free(FreeCamera { lookat: DVec3::ZERO, distance: 4.0, azimuth: 90.0, elevation: -89.999, track_body: None });
    let w = 400;
    let shot = Shot::take(&m, cam, w, w);
    // metres per pixel on the floor
    let focal = (w as f64 / 2.0) / (22.5f64.to_radians()).tan();
    let at = |x: f64, y: f64| {
        // floor (x, y) seen at column w/2 + focal x / 4, row w/2 − focal y / 4 (image up is +y)
        shot.px((w as f64 / 2.0 + focal * x / 4.0) as usize, (w as f64 / 2.0 - focal * y / 4.0) as usize)
    };
    for (x, y) in [(0.25, 0.25), (-0.25, -0.25), (0.75, 0.25), (0.25, 0.75)] {
        let expect = if ((x / 0.5f64).floor() as i64 + (y / 0.5f64).floor() as i64) % 2 == 0 { [0, 0, 0] } else { [255, 255, 255] };
        assert_eq!(at(x, y), expect, "check at ({x}, {y})");
    }
    assert_ne!(at(0.25, 0.25), at(0.75, 0.25), "neighbouring checks differ");
    // beyond the floor's edge, nothing (no skybox: black, depth 1)
    let edge = (w as f64 / 2.0 + focal * 1.2 / 4.0) as usize;
    assert!(shot.z(edge, w / 2).is_none());
}

#[test]
fn model_cameras_follow_their_modes() {
    let m = Model::from_mjcf(
        r#"<mujoco><worldbody>
            <camera name="still" pos="0 -4 1" xyaxes="1 0 0 0 0 1"/>
            <body name="cart" pos="0 0 1">
              <joint name="x" type="slide" axis="1 0 0" limited="false"/>
              <geom type="box" size="0.2 0.2 0.2"/>
              <camera name="fixed" pos="0 -2 0" xyaxes="1 0 0 0 0 1"/>
              <camera name="track" mode="track" pos="0 -2 0" xyaxes="1 0 0 0 0 1"/>
              <camera name="trackcom" mode="trackcom" pos="0 -2 0" xyaxes="1 0 0 0 0 1"/>
              <body name="pole" pos="0 0 0.5"><joint name="h" type="hinge" axis="0 1 0" limited="false"/><geom type="capsule" fromto="0 0 0 0 0 1" size="0.05"/></body>
            </body>
            <body name="watcher" pos="3 -3 2"><joint type="slide" axis="0 0 1" limited="false"/><geom size="0.1"/>
              <camera name="target" mode="targetbody" target="cart"/></body>
          </worldbody></mujoco>"#,
    )
    .unwrap();
    let r = Renderer::new(&m);
    let cam = |name: &str| CameraChoice::Model(m.vis.cameras.iter().position(|c| c.name == name).unwrap());
    // cart moved 1 m along x, pole turned 90°
    let q = [1.0, std::f64::consts::FRAC_PI_2, 0.0];
    let p = Poses::new(&m, &q);
    let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
    assert!(close(r.view(&m, &p, &cam("still")).pos, DVec3::new(0.0, -4.0, 1.0)));
    assert!(close(r.view(&m, &p, &cam("fixed")).pos, DVec3::new(1.0, -2.0, 1.0)));
    assert!(close(r.view(&m, &p, &cam("track")).pos, DVec3::new(1.0, -2.0, 1.0)));
    // trackcom keeps its offset from the subtree's centre of mass as at qpos0
    let p0 = Poses::new(&m, &m.qpos0);
    let cart = m.body_id("cart").unwrap();
    let offset = r.view(&m, &p0, &cam("trackcom")).pos - p0.com[cart];
    assert!(close(r.view(&m, &p, &cam("trackcom")).pos, p.com[cart] + offset));
    assert!((p.com[cart] - p0.com[cart] - DVec3::X).length() > 1e-3, "the pole's turn moves the centre of mass off the cart's 1 m");
    // targetbody looks at the cart's origin, image x horizontal
    let v = r.view(&m, &p, &cam("target"));
    assert!((v.forward - (DVec3::new(1.0, 0.0, 1.0) - v.pos).normalize()).length() < 1e-12);
    assert!(v.right.z.abs() < 1e-12);
    // the free camera orbits its lookat; tracking looks at the body's subtree centre of mass
    let f = FreeCamera { lookat: DVec3::new(0.0, 0.0, 1.0), distance: 2.0, azimuth: 90.0, elevation: -30.0, track_body: None };
    let v = r.view(&m, &p, &CameraChoice::Free(f));
    assert!(close(v.pos, DVec3::new(0.0, -2.0 * 30f64.to_radians().cos(), 1.0 + 2.0 * 30f64.to_radians().sin())));
    let v = r.view(&m, &p, &CameraChoice::Free(FreeCamera { track_body: Some(cart), ..f }));
    assert!(close(v.pos + 2.0 * v.forward, p.com[cart]));
}

#[test]
fn the_extent_is_mujocos() {
    // MuJoCo's extent for this model is 4.0 (hopper's floor: a tenth of 20 on each side)
    let m = Model::from_mjcf(
        r#"<mujoco><worldbody><geom type="plane" size="20 20 .1"/>
           <body pos="0 0 1.25"><joint type="slide" axis="0 0 1" limited="false"/><geom type="capsule" size="0.05 0.2"/></body>
           </worldbody></mujoco>"#,
    )
    .unwrap();
    assert_eq!(Renderer::new(&m).extent, 4.0);
    let given = Model::from_mjcf(r#"<mujoco><statistic extent="7"/><worldbody><body><joint type="slide" limited="false"/><geom size="1"/></body></worldbody></mujoco>"#).unwrap();
    assert_eq!(Renderer::new(&given).extent, 7.0);
}

#[test]
fn batched_frames_equal_single_frames() {
    let m = scene(r#"<geom type="plane" size="0 0 1" rgba="0.2 0.3 0.4 1"/><body pos="0 0 1"><freejoint/><geom type="box" size="0.3 0.2 0.1" rgba="1 1 0 1"/></body>"#, "");
    let r = Renderer::new(&m);
    let mut q2 = m.qpos0.clone();
    q2[0] = 0.4;
    let (a, b) = (Poses::new(&m, &m.qpos0), Poses::new(&m, &q2));
    let cam = free(DVec3::new(0.0, 0.0, 1.0), 3.0);
    let (w, h) = (37, 23);
    let mut both = vec![0u8; 2 * w * h * 3];
    r.draw(&m, &[(&a, cam), (&b, cam)], w, h, &mut both, &mut []);
    for (k, p) in [&a, &b].into_iter().enumerate() {
        let mut one = vec![0u8; w * h * 3];
        r.draw(&m, &[(p, cam)], w, h, &mut one, &mut []);
        assert_eq!(one, both[k * w * h * 3..(k + 1) * w * h * 3]);
    }
    assert_ne!(both[..w * h * 3], both[w * h * 3..], "the box moved");
}

#[test]
fn a_box_written_as_a_mesh_draws_as_the_primitive_box() {
    // the same box (turned, so three faces show) as a primitive and as mesh triangles: the same
    // pixels drawn, at the same depths, in the same colour
    let verts = "-.25 -.125 -.0625  .25 -.125 -.0625  -.25 .125 -.0625  .25 .125 -.0625  -.25 -.125 .0625  .25 -.125 .0625  -.25 .125 .0625  .25 .125 .0625";
    let body = |geom: &str| format!(r#"<body euler="20 30 40"><joint type="slide" limited="false"/>{geom}</body>"#);
    let primitive = scene(&body(r#"<geom type="box" size=".25 .125 .0625" rgba="0 1 0 1"/>"#), "");
    let mesh = scene(&body(r#"<geom type="mesh" mesh="b" rgba="0 1 0 1"/>"#), &format!(r#"<asset><mesh name="b" vertex="{verts}"/></asset>"#));
    let (a, b) = (Shot::take(&primitive, free(DVec3::ZERO, 1.5), 101, 101), Shot::take(&mesh, free(DVec3::ZERO, 1.5), 101, 101));
    let mut drawn = 0;
    for y in 0..101 {
        for x in 0..101 {
            match (a.z(x, y), b.z(x, y)) {
                (Some(za), Some(zb)) => {
                    drawn += 1;
                    assert!((za - zb).abs() < 1e-4, "pixel ({x}, {y}): depth {za} vs {zb}");
                    assert_eq!(a.px(x, y), b.px(x, y), "pixel ({x}, {y})");
                }
                (None, None) => {}
                (za, zb) => panic!("pixel ({x}, {y}) drawn in one only: {za:?} vs {zb:?}"),
            }
        }
    }
    assert!(drawn > 500, "the box covers {drawn} pixels");
}
