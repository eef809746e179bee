//! The cells a frame's packets are binned into: a grid of cells over a plane the rest positions
//! are mapped to (`CellMap`: the rest plane itself, or its perspective from behind the eye, where
//! equal cells are small near the eye and long far from it, as a screen's tiles are), each listing
//! the packets whose envelope's rectangle (ENVELOPE_SIGMAS along each axis) meets it. A map keeps
//! lines straight, so the rectangle is a convex quad in that plane (`Footprint`), tested exactly
//! against a cell's box. A pixel or a grid vertex then reads only the packets that reach it.
//! Square tiles of TILE_CELLS x TILE_CELLS cells each list, in packet order, the packets that meet
//! any of their cells, each with the part of its cell range inside the tile: the GPU bins the
//! packets into the cells itself (glsl/packet_bins.comp), an invocation a cell testing it against
//! the tile's list, so that every cell's list comes out in packet order with no atomics and no
//! sort (the same on every run and device). `lists` is the same binning on the CPU, for the
//! ground truth and the tests.

use super::{Packet, ENVELOPE_SIGMAS};
use glam::DVec2;

/// The envelope's steepest slope per unit of amplitude, times sigma: the window's, 6 x (1 - x) / 2
/// at its largest (x = 1/2, one sigma out), 3/4; across the plane the other axis's factor is at
/// most 1.
const ENVELOPE_STEEPEST: f64 = 0.75;

/// Cells per side at most: 65 536 cells, whose starts the GPU's one-workgroup scan covers.
pub const MAX_CELLS_PER_SIDE: u32 = 256;
pub const MAX_CELLS: u32 = MAX_CELLS_PER_SIDE * MAX_CELLS_PER_SIDE;

/// Cells per side of a frame's perspective grid: each then covers about 8 x 6 pixels at
/// 1024 x 768. Measured on `wake_mast` (examples/packet_cells.rs, 2026-12-05): a pixel reads 5.04
/// list entries for 4.40 that reach it, from 105 096 entries; square cells on the rest plane,
/// 7.45 from 145 767. A first version of the view's map at 256 a side read 4.67 (4.94 at 128)
/// from 302 984 entries: the binning's cost grows with them.
pub const PERSPECTIVE_CELLS_PER_SIDE: u32 = 128;

/// A tile's side in cells: TILE_CELLS^2 GPU invocations bin a tile. Four: the
/// cells' tests a tile's list costs grow with its area, its entries with its perimeter (measured
/// on `wake_mast`'s binning: 6.6 ms with tiles of 8 cells, 4.8 ms with 4).
pub const TILE_CELLS: u32 = 4;
/// A tile entry: the packet's index in its low TILE_INDEX_BITS bits (packets::sources::MAX_PACKETS
/// fits), then its cell range within the tile, first column and row and last column and row, two
/// bits each (0 to TILE_CELLS - 1): the GPU tests only those cells, as the CPU does.
pub const TILE_INDEX_BITS: u32 = 24;
const _: () = assert!(super::sources::MAX_PACKETS <= 1 << TILE_INDEX_BITS);
pub const MAX_TILES_PER_SIDE: u32 = MAX_CELLS_PER_SIDE / TILE_CELLS;
pub const MAX_TILES: u32 = MAX_TILES_PER_SIDE * MAX_TILES_PER_SIDE;

/// The tiles' lists' room for cells' lists of `max_entries`: a quarter of it. A tile entry has at
/// least one cell entry, and a packet meeting more than a quarter as many tiles as cells on
/// average meets many more cells, past the cells' own room.
pub fn tile_room(max_entries: usize) -> usize {
    max_entries / 4
}

/// Where rest positions (camera-relative, m) lie in the plane the cells divide.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum CellMap {
    /// The rest plane itself, square cells: the ground truth's, whose rays go anywhere.
    #[default]
    Plane,
    /// The rest plane in perspective from `offset` m behind the eye along `forward` (horizontal,
    /// unit): q = (x . left, 1) / w, w = x . forward + offset, left being forward turned a
    /// quarter counter-clockwise. `view`: the box in q (low, high corners) of every rest position
    /// the frame evaluates packets at (render::packet_view), all at w > 0; no cell lies outside it.
    Perspective { forward: DVec2, offset: f64, view: [DVec2; 2] },
}

impl CellMap {
    /// Rest position x in the cells' plane; None behind the perspective's centre (w <= 0).
    pub fn apply(&self, x: DVec2) -> Option<DVec2> {
        match *self {
            CellMap::Plane => Some(x),
            CellMap::Perspective { forward, offset, .. } => {
                let w = x.dot(forward) + offset;
                (w > 0.0).then(|| DVec2::new(x.dot(forward.perp()), 1.0) / w)
            }
        }
    }

    /// FrameUniforms::packet_map: forward and offset (an offset of 0: the plane's own).
    pub fn uniform(&self) -> [f32; 4] {
        match *self {
            CellMap::Plane => [0.0; 4],
            CellMap::Perspective { forward, offset, .. } => [forward.x as f32, forward.y as f32, offset as f32, 0.0],
        }
    }

    /// Packet p's footprint in the cells' plane: the quad of its rectangle's corners, or where
    /// part of the rectangle lies behind the nearest rest position the view holds (half of it,
    /// w_near / 2), the box of the part in front; None where none of it is.
    fn footprint(&self, p: &Packet) -> Option<Footprint> {
        let (a, b) = (p.axis * (ENVELOPE_SIGMAS * p.sigma[0]), p.axis.perp() * (ENVELOPE_SIGMAS * p.sigma[1]));
        // Counter-clockwise: (axis, axis.perp()) turns as (x, y) does, and the perspective keeps
        // the turn (its Jacobian's determinant, 1 / w^3, is positive).
        let corners = [p.centre - a - b, p.centre + a - b, p.centre + a + b, p.centre - a + b];
        let CellMap::Perspective { forward, offset, view } = *self else {
            return Some(Footprint::of_quad(corners));
        };
        let clip = 0.5 / view[1].y;
        let w = corners.map(|c| c.dot(forward) + offset);
        if w.iter().all(|&w| w >= clip) {
            return Some(Footprint::of_quad(corners.map(|c| self.apply(c).expect("w > 0"))));
        }
        // The rectangle cut by w >= clip (Sutherland-Hodgman, one edge), then mapped.
        let mut kept = Vec::with_capacity(5);
        for i in 0..4 {
            let (j, (c, d)) = ((i + 1) % 4, (corners[i], corners[(i + 1) % 4]));
            if w[i] >= clip {
                kept.push(c);
            }
            if (w[i] >= clip) != (w[j] >= clip) {
                kept.push(c + (d - c) * ((clip - w[i]) / (w[j] - w[i])));
            }
        }
        let mapped: Vec<DVec2> = kept.iter().filter_map(|&c| self.apply(c)).collect();
        let (lo, hi) =
            mapped.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &q| (lo.min(q), hi.max(q)));
        (!mapped.is_empty()).then(|| Footprint::of_quad([lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]))
    }

    /// The part of the cells' plane that may hold cells: all of it for the plane's own.
    fn bounds(&self) -> (DVec2, DVec2) {
        match *self {
            CellMap::Plane => (DVec2::NEG_INFINITY, DVec2::INFINITY),
            CellMap::Perspective { view, .. } => (view[0], view[1]),
        }
    }
}

/// A packet's rectangle in the cells' plane as the GPU holds it: a convex quad, counter-clockwise,
/// in single precision (render::packets::GpuPacket), for the exact test of a cell against it, the
/// same on both sides.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub quad: [[f32; 2]; 4],
}

impl Footprint {
    fn of_quad(corners: [DVec2; 4]) -> Footprint {
        Footprint { quad: corners.map(|c| [c.x as f32, c.y as f32]) }
    }

    /// Its bounding box's corners (low, high).
    fn bounds(&self) -> (DVec2, DVec2) {
        let q = self.quad.map(|[x, y]| DVec2::new(x as f64, y as f64));
        (q.iter().fold(q[0], |lo, &c| lo.min(c)), q.iter().fold(q[0], |hi, &c| hi.max(c)))
    }

    /// Whether the cell about `centre` of half sides `half` meets the quad. Their separating axes
    /// are x and y (the cell range's box) and the quad's four edges' normals: the cell lies wholly
    /// outside an edge where its centre's distance past it reaches the box's half extent along the
    /// normal. Each operation rounded in this order, as glsl/packet_bins.comp `cell_meets`
    /// (precise, correctly rounded in Vulkan): the GPU's lists are the CPU's to the entry.
    pub fn meets(&self, centre: [f32; 2], half: [f32; 2]) -> bool {
        (0..4).all(|i| {
            let (p, n) = (self.quad[i], self.quad[(i + 1) % 4]);
            let (ex, ey) = (n[0] - p[0], n[1] - p[1]);
            let (dx, dy) = (centre[0] - p[0], centre[1] - p[1]);
            // The outward normal of a counter-clockwise edge (e.x, e.y) is (e.y, -e.x).
            let beyond = dx * ey - dy * ex;
            let reach = half[0] * ey.abs() + half[1] * ex.abs();
            beyond < reach
        })
    }
}

/// The grid of one frame's packets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PacketGrid {
    /// How rest positions map to the cells' plane.
    pub map: CellMap,
    /// The corner of cell (0, 0) in the cells' plane.
    pub origin: DVec2,
    /// A cell's sides (equal on the rest plane).
    pub cell: DVec2,
    pub cols: u32,
    pub rows: u32,
    /// The cells of each packet's bounding box, inclusive: first column, first row, last column,
    /// last row (first past last where it meets no cell). A packet is listed in those its
    /// quad meets (`Footprint::meets`).
    pub ranges: Vec<[u32; 4]>,
    /// Each packet's quad, as the GPU tests it.
    pub footprints: Vec<Footprint>,
    /// The number of (cell, packet) pairs: the lists' total length.
    pub entries: usize,
    /// Each tile's start in `tile_packets` (one more start than tiles, the last the total), tiles
    /// row by row, `tiles()` of them.
    pub tile_starts: Vec<u32>,
    /// The packets that meet at least one cell of each tile, in packet order within a tile: each
    /// its index and its range within the tile (`tile_entry`).
    pub tile_packets: Vec<u32>,
    /// The largest sum of the amplitudes of the packets that overlap one cell (m): no packet
    /// crest rises higher over the rest plane, nor a trough sinks lower, within the cells.
    pub crest_m: f64,
    /// The largest sum over one cell's packets of a bound on each one's height slope over the
    /// rest plane, k a plus its envelope's steepest (ENVELOPE_STEEPEST a / sigma; the ground
    /// truth's march steps by it).
    pub slope: f64,
}

/// A range that holds no cell.
const NO_CELLS: [u32; 4] = [1, 1, 0, 0];

impl PacketGrid {
    /// The grid over `packets` in the cells' plane of `map`, the finest of cells at most
    /// `per_side` to a side whose lists hold at most `max_entries` pairs and whose tiles' lists
    /// at most `tile_room(max_entries)` (coarser cells, fewer pairs: each cell side doubled until
    /// they fit). Square cells over the rest plane; over a perspective, `per_side` a side of the
    /// box the view and the packets share. Empty without packets in it.
    pub fn new(packets: &[Packet], max_entries: usize, map: CellMap, per_side: u32) -> PacketGrid {
        let footprints: Vec<Option<Footprint>> = packets.iter().map(|p| map.footprint(p)).collect();
        let (lo, hi) = footprints
            .iter()
            .flatten()
            .map(Footprint::bounds)
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a), hi.max(b)));
        let (view_lo, view_hi) = map.bounds();
        let (lo, hi) = (lo.max(view_lo), hi.min(view_hi));
        if !(lo.x < hi.x && lo.y < hi.y) {
            return PacketGrid { map, ..Self::unbinned(packets.len()) };
        }
        let size = hi - lo;
        let mut cell = match map {
            CellMap::Plane => DVec2::splat(size.max_element() / per_side as f64),
            CellMap::Perspective { .. } => size / per_side as f64,
        };
        loop {
            let grid = Self::with_cells(packets, &footprints, map, lo, size, cell, per_side);
            let fits = grid.entries <= max_entries && grid.tile_packets.len() <= tile_room(max_entries);
            if fits || grid.cols * grid.rows == 1 {
                return grid;
            }
            cell *= 2.0;
        }
    }

    /// A grid of no cells, its `count` packets listed nowhere (a view that holds no sea).
    pub fn unbinned(count: usize) -> PacketGrid {
        PacketGrid {
            ranges: vec![NO_CELLS; count],
            footprints: vec![Footprint::default(); count],
            ..Default::default()
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn with_cells(
        packets: &[Packet],
        footprints: &[Option<Footprint>],
        map: CellMap,
        origin: DVec2,
        size: DVec2,
        cell: DVec2,
        per_side: u32,
    ) -> PacketGrid {
        let count = |extent: f64, side: f64| ((extent / side).ceil() as u32).clamp(1, per_side);
        let (cols, rows) = (count(size.x, cell.x), count(size.y, cell.y));
        let cell_of = |x: f64, side: f64, n: u32| ((x / side).floor().max(0.0) as u32).min(n - 1);
        let mut sums = vec![0.0f64; (cols * rows) as usize];
        let mut slopes = vec![0.0f64; (cols * rows) as usize];
        let mut grid = PacketGrid { map, origin, cell, cols, rows, ..Default::default() };
        let tiles_x = cols.div_ceil(TILE_CELLS);
        // (tile, packet) pairs in packet order; `last` drops a packet's repeats in a tile.
        let mut tile_pairs = Vec::new();
        let mut last = vec![u32::MAX; grid.tiles() as usize];
        for (i, (p, footprint)) in packets.iter().zip(footprints).enumerate() {
            let (footprint, r) = match footprint {
                Some(f) => {
                    let (a, b) = f.bounds();
                    let (a, b) = (a - origin, b - origin);
                    let outside = b.x < 0.0 || b.y < 0.0 || a.x > size.x || a.y > size.y;
                    let r = [
                        cell_of(a.x, cell.x, cols),
                        cell_of(a.y, cell.y, rows),
                        cell_of(b.x, cell.x, cols),
                        cell_of(b.y, cell.y, rows),
                    ];
                    (*f, if outside { NO_CELLS } else { r })
                }
                None => (Footprint::default(), NO_CELLS),
            };
            let slope = p.amplitude * (p.k + ENVELOPE_STEEPEST / p.sigma[0].min(p.sigma[1]));
            for (x, y) in grid.cells_met(r, &footprint) {
                sums[(y * cols + x) as usize] += p.amplitude;
                slopes[(y * cols + x) as usize] += slope;
                grid.entries += 1;
                let tile = (y / TILE_CELLS * tiles_x + x / TILE_CELLS) as usize;
                if last[tile] != i as u32 {
                    last[tile] = i as u32;
                    tile_pairs.push((tile as u32, tile_entry(i as u32, r, x / TILE_CELLS, y / TILE_CELLS)));
                }
            }
            grid.ranges.push(r);
            grid.footprints.push(footprint);
        }
        (grid.tile_starts, grid.tile_packets) = group_by_key(grid.tiles() as usize, &tile_pairs);
        grid.crest_m = sums.iter().copied().fold(0.0, f64::max);
        grid.slope = slopes.iter().copied().fold(0.0, f64::max);
        grid
    }

    /// The tiles covering the grid (partial ones at its far edges included).
    pub fn tiles(&self) -> u32 {
        self.cols.div_ceil(TILE_CELLS) * self.rows.div_ceil(TILE_CELLS)
    }

    /// FrameUniforms::packet_grid: the corner of cell (0, 0) and a cell's sides, in single
    /// precision (as the GPU has them).
    pub fn uniform(&self) -> [f32; 4] {
        [self.origin.x, self.origin.y, self.cell.x, self.cell.y].map(|v| v as f32)
    }

    /// The cells of box `range` that `footprint` meets, row by row.
    fn cells_met<'a>(&self, range: [u32; 4], footprint: &'a Footprint) -> impl Iterator<Item = (u32, u32)> + 'a {
        let [ox, oy, sx, sy] = self.uniform();
        let half = [0.5 * sx, 0.5 * sy];
        (range[1]..=range[3]).flat_map(move |y| (range[0]..=range[2]).map(move |x| (x, y))).filter(move |&(x, y)| {
            let centre = [ox + (x as f32 + 0.5) * sx, oy + (y as f32 + 0.5) * sy];
            footprint.meets(centre, half)
        })
    }

    /// The cell holding rest position x, if the grid covers it.
    pub fn cell(&self, x: DVec2) -> Option<u32> {
        let c = (self.map.apply(x)? - self.origin) / self.cell;
        let inside = c.x >= 0.0 && c.y >= 0.0 && c.x < self.cols as f64 && c.y < self.rows as f64;
        inside.then(|| c.y as u32 * self.cols + c.x as u32)
    }

    /// Every cell's list, on the CPU: the start of each cell's run in `entries` (one more start
    /// than cells, the last the total), and the packets' indices, in packet order within a cell.
    pub fn lists(&self) -> (Vec<u32>, Vec<u32>) {
        let pairs: Vec<(u32, u32)> = (self.ranges.iter().zip(&self.footprints).enumerate())
            .flat_map(|(i, (r, f))| self.cells_met(*r, f).map(move |(x, y)| (y * self.cols + x, i as u32)))
            .collect();
        group_by_key((self.cols * self.rows) as usize, &pairs)
    }
}

/// Packet `index`'s entry in tile (tx, ty): its index and its cell `range` clipped to the tile,
/// in the tile's own cells (TILE_INDEX_BITS).
pub fn tile_entry(index: u32, range: [u32; 4], tx: u32, ty: u32) -> u32 {
    debug_assert!(index < 1 << TILE_INDEX_BITS && TILE_CELLS == 4);
    let local = |v: u32, t: u32| v.clamp(t * TILE_CELLS, t * TILE_CELLS + TILE_CELLS - 1) - t * TILE_CELLS;
    let bounds = [local(range[0], tx), local(range[1], ty), local(range[2], tx), local(range[3], ty)];
    bounds.iter().enumerate().fold(index, |word, (i, &b)| word | b << (TILE_INDEX_BITS + 2 * i as u32))
}

/// (key, value) pairs grouped by key, a counting sort that keeps their order within a key: each
/// key's start among the values (one more start than `keys`, the last the total), and the values.
fn group_by_key(keys: usize, pairs: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut starts = vec![0u32; keys + 1];
    for &(key, _) in pairs {
        starts[key as usize + 1] += 1;
    }
    for i in 0..keys {
        starts[i + 1] += starts[i];
    }
    let mut cursor = starts.clone();
    let mut values = vec![0u32; pairs.len()];
    for &(key, value) in pairs {
        values[cursor[key as usize] as usize] = value;
        cursor[key as usize] += 1;
    }
    (starts, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn packet(centre: DVec2, sigma: [f64; 2], amplitude: f64) -> Packet {
        let axis = DVec2::new(0.6, 0.8);
        Packet { centre, direction: DVec2::X, k: 1.0, amplitude, axis, sigma, phase: 0.0, in_phase: [None; 2] }
    }

    fn packets() -> Vec<Packet> {
        (0..200)
            .map(|i| {
                let t = i as f64;
                packet(
                    DVec2::new(37.0 * (t * 0.7).sin(), 23.0 * (t * 1.3).cos()),
                    [1.0 + t % 5.0, 0.5 + t % 3.0],
                    0.01 * t,
                )
            })
            .collect()
    }

    /// Every point a packet's envelope reaches lies in a cell that lists it.
    #[test]
    fn every_packet_is_listed_wherever_it_reaches() {
        let ps = packets();
        let grid = PacketGrid::new(&ps, usize::MAX, CellMap::Plane, MAX_CELLS_PER_SIDE);
        let (starts, entries) = grid.lists();
        assert_eq!(entries.len(), grid.entries);
        let mut checked = 0;
        for i in -100..=100 {
            for j in -70..=70 {
                let x = DVec2::new(i as f64 * 0.55, j as f64 * 0.6);
                for (n, _) in ps.iter().enumerate().filter(|(_, p)| p.reaches(x)) {
                    let c = grid.cell(x).expect("inside the grid") as usize;
                    assert!(entries[starts[c] as usize..starts[c + 1] as usize].contains(&(n as u32)), "{x} {n}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 10_000, "{checked}");
    }

    /// In perspective too, every point of the view a packet reaches lies in a cell that lists it;
    /// cells grow with the distance from the eye, and a packet wholly outside the view is listed
    /// nowhere.
    #[test]
    fn perspective_cells_list_every_packet_wherever_it_reaches_in_view() {
        let mut ps = packets();
        // One packet straddling the clipping line behind the nearest viewed point, one far behind.
        ps.push(packet(DVec2::new(-9.0, 3.0), [4.0, 2.0], 0.1));
        ps.push(packet(DVec2::new(-300.0, 0.0), [4.0, 2.0], 0.1));
        let (forward, offset) = (DVec2::new(0.8, 0.6), 10.0);
        let map = CellMap::Perspective { forward, offset, view: [DVec2::new(-2.0, 0.01), DVec2::new(2.0, 0.1)] };
        let grid = PacketGrid::new(&ps, usize::MAX, map, 64);
        let (starts, entries) = grid.lists();
        let mut checked = 0;
        for i in -100..=100 {
            for j in -70..=70 {
                let x = DVec2::new(i as f64 * 0.55, j as f64 * 0.6);
                let Some(q) = map.apply(x) else { continue };
                if !(q.cmpgt(DVec2::new(-2.0, 0.01)).all() && q.cmplt(DVec2::new(2.0, 0.1)).all()) {
                    continue;
                }
                for (n, _) in ps.iter().enumerate().filter(|(_, p)| p.reaches(x)) {
                    let c = grid.cell(x).expect("inside the grid") as usize;
                    assert!(entries[starts[c] as usize..starts[c + 1] as usize].contains(&(n as u32)), "{x} {n}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 5_000, "{checked}");
        assert!(grid.ranges[ps.len() - 1] == NO_CELLS && grid.ranges[ps.len() - 2] != NO_CELLS);
        // A cell's depth along `forward` near the eye and 30 m out.
        let depth = |d: f64| {
            let c = grid.cell(forward * d).unwrap();
            let (lo, hi) = (grid.origin.y + (c / grid.cols) as f64 * grid.cell.y, grid.cell.y);
            1.0 / lo - 1.0 / (lo + hi)
        };
        assert!(depth(30.0) > 4.0 * depth(1.0), "{} {}", depth(30.0), depth(1.0));
    }

    /// A tile lists, in packet order, exactly the packets its cells list.
    #[test]
    fn a_tile_lists_the_packets_of_its_cells_in_order() {
        let ps = packets();
        let grid = PacketGrid::new(&ps, usize::MAX, CellMap::Plane, MAX_CELLS_PER_SIDE);
        let (starts, entries) = grid.lists();
        let tiles_x = grid.cols.div_ceil(TILE_CELLS);
        assert_eq!(grid.tile_starts.len(), grid.tiles() as usize + 1);
        for tile in 0..grid.tiles() {
            let (tx, ty) = (tile % tiles_x, tile / tiles_x);
            let mut of_cells: Vec<u32> = (ty * TILE_CELLS..((ty + 1) * TILE_CELLS).min(grid.rows))
                .flat_map(|y| (tx * TILE_CELLS..((tx + 1) * TILE_CELLS).min(grid.cols)).map(move |x| y * grid.cols + x))
                .flat_map(|c| entries[starts[c as usize] as usize..starts[c as usize + 1] as usize].to_vec())
                .collect();
            of_cells.sort_unstable();
            of_cells.dedup();
            let listed: Vec<u32> = grid.tile_packets
                [grid.tile_starts[tile as usize] as usize..grid.tile_starts[tile as usize + 1] as usize]
                .iter()
                .map(|e| e & ((1 << TILE_INDEX_BITS) - 1))
                .collect();
            assert_eq!(listed, of_cells, "tile {tile}");
        }
        assert!(grid.tiles() > 4 && grid.tile_packets.len() > ps.len(), "{} {}", grid.tiles(), grid.tile_packets.len());
    }

    /// The reach the CPU tests cells with is the GPU's (glsl/packet_data.glsl's literal 2.0,
    /// rounded once to single precision), and a cell is listed only where the rectangle meets it.
    #[test]
    fn cells_are_listed_only_where_the_rectangle_meets_them() {
        assert_eq!(ENVELOPE_SIGMAS as f32, 2.0f32);
        // A thin packet along the diagonal: its box holds cells off the diagonal that the
        // rectangle misses.
        let p = Packet {
            centre: DVec2::ZERO,
            direction: DVec2::X,
            k: 1.0,
            amplitude: 0.1,
            axis: DVec2::new(1.0, 1.0).normalize(),
            sigma: [4.0, 0.1],
            phase: 0.0,
            in_phase: [None; 2],
        };
        let spread = [p, Packet { centre: DVec2::new(100.0, 100.0), ..p }];
        let grid = PacketGrid::new(&spread, usize::MAX, CellMap::Plane, 32);
        let (starts, entries) = grid.lists();
        let listed = |x: DVec2| {
            let c = grid.cell(x).unwrap() as usize;
            entries[starts[c] as usize..starts[c + 1] as usize].contains(&0)
        };
        let cell = grid.cell.x;
        let in_box = |x: DVec2| {
            let (c, r) = (grid.cell(x).unwrap(), grid.ranges[0]);
            (r[0]..=r[2]).contains(&(c % grid.cols)) && (r[1]..=r[3]).contains(&(c / grid.cols))
        };
        let off = [DVec2::new(0.9, -0.9) * cell, DVec2::new(-0.9, 0.9) * cell];
        assert!(listed(DVec2::splat(0.2 * cell)) && listed(DVec2::splat(-0.2 * cell)));
        assert!(off.iter().all(|&x| in_box(x) && !listed(x)), "{grid:?}");
    }

    /// Coarser cells where the lists would not fit, and the crest bound is a real bound.
    #[test]
    fn cells_coarsen_to_fit_and_the_crest_bounds_every_height() {
        let ps = packets();
        let fine = PacketGrid::new(&ps, usize::MAX, CellMap::Plane, MAX_CELLS_PER_SIDE);
        let coarse = PacketGrid::new(&ps, fine.entries / 3, CellMap::Plane, MAX_CELLS_PER_SIDE);
        assert!(
            coarse.entries <= fine.entries / 3 && coarse.cell.x >= 2.0 * fine.cell.x,
            "{} {}",
            coarse.entries,
            fine.entries
        );
        let field = super::super::PacketField { packets: ps.clone(), ..Default::default() };
        let highest = (0..4000)
            .map(|i| DVec2::new(-40.0 + 0.02 * i as f64, 20.0 * (i as f64 * 0.01).sin()))
            .map(|x| field.height(x).abs())
            .fold(0.0, f64::max);
        assert!(
            highest > 0.0 && highest <= fine.crest_m && fine.crest_m <= coarse.crest_m,
            "{highest} {} {}",
            fine.crest_m,
            coarse.crest_m
        );
    }
}
