//! The close-up render of the teapot in the stadium for `cargo xtask
//! scenes`: the view (eye (1.2, 1.6, 5), look-at (1.2, 0.6, 0),
//! vertical fov 40°), 640×480, 1 spp, one point light with shadows, on 2
//! threads with the default accelerator (`auto`), build and render timed.

use crate::corpus::CLOSE;
use gridrt_tracer::{Camera, Light, Projection, RenderOptions, Renderer, Rgb};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// What the close-up render took.
#[derive(Clone, Debug)]
pub struct CloseUp {
    /// `Renderer::new`: preparing the scene and building the accelerator.
    pub build_s: f64,
    /// `Renderer::render`, wall clock.
    pub render_s: f64,
    /// `Renderer::render`, CPU time of the whole process (both threads):
    /// half of it is what the wall clock would read on an idle machine
    /// with the two threads busy throughout.
    pub render_cpu_s: f64,
    /// Rays of all kinds.
    pub rays: u64,
    /// `grid` or `hierarchy`.
    pub chose: &'static str,
}

/// Renders the close-up view; `None` when the stadium is absent.
pub fn close_up(shared: &Path) -> Option<CloseUp> {
    let file = shared.join("scenes/teapot_in_stadium/teapot_in_stadium.obj");
    let model = gridrt_io::load_model_in(&file, &gridrt_io::Sandbox::for_input(&file)).ok()?;
    let mut scene = gridrt_io::scene_from_model(model).scene;
    scene.camera = Camera {
        eye: CLOSE.eye,
        look_at: CLOSE.look_at,
        up: gridrt_grid::Vec3::Y,
        projection: Projection::Perspective { vfov_deg: 40.0 },
        lens: None,
    };
    scene.settings.width = 640;
    scene.settings.height = 480;
    scene.settings.spp = 1;
    scene.lights = vec![Light::Point {
        position: gridrt_grid::Vec3::new(3.0, 6.0, 6.0),
        color: Rgb::ONE,
        intensity: 1.0,
        inverse_square: false,
        shadows: true,
    }];
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    let t = Instant::now();
    let r = Renderer::new(&scene, &options).ok()?;
    let build_s = t.elapsed().as_secs_f64();
    let chose = match r.grid_stats() {
        Some(g) if g.nested_cells > 0 => "hierarchy",
        _ => "grid",
    };
    let t = Instant::now();
    let c = crate::scenes::cpu_s(crate::scenes::PROCESS_CPU);
    let (_, stats) = r.render(&|_, _| {}, &AtomicBool::new(false)).ok()?;
    Some(CloseUp {
        build_s,
        render_s: t.elapsed().as_secs_f64(),
        render_cpu_s: crate::scenes::cpu_s(crate::scenes::PROCESS_CPU) - c,
        rays: stats.rays.total(),
        chose,
    })
}
