//! Draws frames of a model for profiling the renderer: `cargo run --release --example
//! render_frames -- MODEL.xml [FRAMES]`.
use sinew::render::{CameraChoice, FreeCamera, Poses, Renderer};
use sinew::Model;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let m = Model::from_mjcf_file(std::path::Path::new(&args[1])).expect("model");
    let frames: usize = args.get(2).map_or(20, |s| s.parse().expect("frames"));
    let r = Renderer::new(&m);
    let poses = Poses::new(&m, &m.qpos0);
    let cam = CameraChoice::Free(FreeCamera { lookat: glam::DVec3::new(0.0, 0.0, 0.5), distance: 4.0, azimuth: 90.0, elevation: -45.0, track_body: None });
    let (w, h) = (480, 480);
    let mut rgb = vec![0u8; w * h * 3];
    let t = std::time::Instant::now();
    for _ in 0..frames {
        r.draw(&m, &[(&poses, cam)], w, h, &mut rgb, &mut []);
    }
    let s = t.elapsed().as_secs_f64();
    println!("{frames} frames of {w}×{h}: {:.1} frames/s", frames as f64 / s);
}
