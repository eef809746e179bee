//! How many list entries a scene's pixels read for the packets that reach them, binned on the rest
//! plane (square cells, 256 a side) and in the view's perspective (render::packet_view, as the
//! renderer bins them), by distance band: what the shading's packet loop costs on a CPU driver,
//! which runs every entry's whole term. Pixels at the f64 camera's rays' points on the rest sphere.
//! `cargo run --release --example packet_cells -- scenes/wake_mast.toml [width height]`
use glam::DVec2;
use ocean::model::packets::grid::{CellMap, PacketGrid, MAX_CELLS_PER_SIDE};
use ocean::model::packets::sources::Sources;
use ocean::model::scene::Scene;
use ocean::render::frame::CameraFrame;

const BANDS_M: [f64; 9] = [0.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, f64::INFINITY];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: packet_cells SCENE.toml [WIDTH HEIGHT]")?;
    let width: u32 = args.next().map_or(Ok(256), |s| s.parse())?;
    let height: u32 = args.next().map_or(Ok(192), |s| s.parse())?;
    let scene = Scene::load(std::path::Path::new(&path))?;
    let eye = DVec2::new(scene.camera.x_m, scene.camera.y_m);
    let field = Sources::of_scene(&scene)?.field(scene.render.time_s).relative_to(eye);
    let waves = ocean::model::waves::generate(&scene);
    let camera = CameraFrame::new(&scene, &waves, width, height);
    let pixels: Vec<DVec2> = (0..width * height)
        .filter_map(|i| {
            let (px, py) = (i % width, i / width);
            let ndc = [(px as f64 + 0.5) / width as f64 * 2.0 - 1.0, (py as f64 + 0.5) / height as f64 * 2.0 - 1.0];
            camera.sea_hit(camera.ray(ndc)).map(|hit| hit.point.truncate())
        })
        .collect();
    println!("{} packets, {} sea pixels of {width}x{height}", field.packets.len(), pixels.len());
    let mut grids =
        vec![("rest plane", PacketGrid::new(&field.packets, usize::MAX, CellMap::Plane, MAX_CELLS_PER_SIDE))];
    let view =
        |crest| ocean::render::packet_view::cell_map(&scene, &waves, crest, width, height, scene.render.grid_cell_px);
    let started = std::time::Instant::now();
    let sources = Sources::of_scene(&scene)?;
    let frame = ocean::render::packets::FramePackets::new(&sources, scene.render.time_s, eye, usize::MAX, view);
    let map = frame.grid.map;
    println!("the frame's grid built in {:.2} ms: {map:?}", started.elapsed().as_secs_f64() * 1e3);
    grids.push(("perspective", frame.grid));
    for (name, grid) in &grids {
        let (starts, lists) = grid.lists();
        // Per band: pixels, entries read, entries that reach the pixel.
        let mut bands = [(0usize, 0usize, 0usize); BANDS_M.len() - 1];
        for &x in &pixels {
            let band = &mut bands[BANDS_M.windows(2).position(|b| x.length() < b[1]).expect("the last is infinite")];
            band.0 += 1;
            if let Some(c) = grid.cell(x) {
                for &i in &lists[starts[c as usize] as usize..starts[c as usize + 1] as usize] {
                    band.1 += 1;
                    band.2 += usize::from(field.packets[i as usize].reaches(x));
                }
            }
        }
        let (n, read, reach) = bands.iter().fold((0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
        let per = |v: usize, n: usize| v as f64 / n.max(1) as f64;
        println!(
            "{name}: {}x{} cells, {} entries; a sea pixel reads {:.2}, {:.2} of them reach it",
            grid.cols,
            grid.rows,
            grid.entries,
            per(read, n),
            per(reach, n)
        );
        for (b, &(n, read, reach)) in bands.iter().enumerate().filter(|(_, b)| b.1 > 0) {
            let (lo, hi) = (BANDS_M[b], BANDS_M[b + 1]);
            println!("  {lo}-{hi} m: {n} pixels, reads {:.2}, reach {:.2}", per(read, n), per(reach, n));
        }
    }
    Ok(())
}
