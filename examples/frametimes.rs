use ocean::passes::ocean::Terms;
use ocean::renderer::Renderer;
use ocean::scene::Scene;
use ocean::vk::gpu::Gpu;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = if args.len() > 1 { Scene::load(std::path::Path::new(&args[1])).unwrap() } else { Scene::default() };
    let gpu = Gpu::new(false, None).unwrap();
    let mut r = Renderer::new(&gpu, &scene, 1024, 768, Terms::ALL).unwrap();
    let mut v = Vec::new();
    for _ in 0..25 { let f = r.render(&scene).unwrap(); v.push(f.pass_ms.iter().find(|p| p.0 == "ocean").unwrap().1); }
    let mut s = v[1..].to_vec(); s.sort_by(f64::total_cmp);
    println!("min {:.1} p25 {:.1} med {:.1} max {:.1}", s[0], s[s.len()/4], s[s.len()/2], s[s.len()-1]);
}
