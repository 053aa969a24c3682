use std::sync::Arc;
use std::time::Instant;
fn main() {
    let scene = relief::Scene::cube(Arc::new(relief::texture::procedural::brick()), true);
    let mut r = relief::Renderer::new();
    let mut fb = relief::Framebuffer::new(320, 240);
    for (name, s) in [
        ("phong", relief::Settings::default()),
        (
            "flat-untex",
            relief::Settings {
                shading: relief::settings::Shading::Flat,
                texture: false,
                ..Default::default()
            },
        ),
    ] {
        let mut times = vec![];
        for i in 0..400 {
            let mut s = s;
            s.rotation.y += i as f32 * 0.5;
            let t = Instant::now();
            r.render(&scene, &s, &mut fb);
            times.push(t.elapsed().as_secs_f64() * 1e6);
        }
        times.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!("{name}: median {:.1} us", times[times.len() / 2]);
    }
}
