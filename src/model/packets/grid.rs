//! The cells a frame's packets are binned into: a grid of square cells over the rest plane
//! (camera-relative, as the shaders' rest positions are), each listing the packets whose envelope's
//! rectangle (ENVELOPE_SIGMAS along each axis) meets it (`Footprint::meets`; its bounding box
//! bounds the cells tested), so that a pixel or a grid vertex reads only the packets that reach
//! it. Square tiles of TILE_CELLS x TILE_CELLS cells each list, in packet order, the packets that
//! meet any of their cells, each with the part of its cell range inside the tile: the GPU bins the
//! packets into the cells itself (glsl/packet_bins.comp), an invocation a cell testing it
//! against the tile's list, so that every cell's list comes out in packet order with no atomics
//! and no sort (the same on every run and device). `lists` is the same binning on the CPU, for
//! the ground truth and the tests.

use super::{Packet, ENVELOPE_SIGMAS};
use glam::DVec2;

/// The envelope's steepest slope per unit of amplitude, times sigma: the window's, 6 x (1 - x) / 2
/// at its largest (x = 1/2, one sigma out), 3/4; across the plane the other axis's factor is at
/// most 1.
const ENVELOPE_STEEPEST: f64 = 0.75;

/// Cells per side at most: 65 536 cells, whose starts the GPU's one-workgroup scan covers.
pub const MAX_CELLS_PER_SIDE: u32 = 256;
pub const MAX_CELLS: u32 = MAX_CELLS_PER_SIDE * MAX_CELLS_PER_SIDE;

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

/// A packet's rectangle as the GPU holds it (single precision: glsl/packet_data.glsl's centre
/// and envelope), for the exact test of a cell against it, the same on both sides.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    /// The envelope's centre (m).
    pub centre: [f32; 2],
    /// Its first axis over its sigma, then the second's (1/m).
    pub axes: [f32; 4],
}

impl Footprint {
    pub fn of(p: &Packet) -> Footprint {
        let (along, across) = (p.axis / p.sigma[0], p.axis.perp() / p.sigma[1]);
        Footprint {
            centre: [p.centre.x as f32, p.centre.y as f32],
            axes: [along.x, along.y, across.x, across.y].map(|v| v as f32),
        }
    }

    /// Whether the square cell of half side `half` about `cell` meets the rectangle. Their
    /// separating axes are x and y (the cell range's box) and the rectangle's own two, on which
    /// the cell reaches half (|a.x| + |a.y|) past its centre's projection (in sigmas). Each
    /// operation rounded in this order, as glsl/packet_bins.comp `cell_meets` (precise, correctly
    /// rounded in Vulkan): the GPU's lists are the CPU's to the entry.
    pub fn meets(&self, cell: [f32; 2], half: f32) -> bool {
        let (c, a) = (self.centre, self.axes);
        let (rx, ry) = (cell[0] - c[0], cell[1] - c[1]);
        let u = rx * a[0] + ry * a[1];
        let v = rx * a[2] + ry * a[3];
        let reach = ENVELOPE_SIGMAS as f32;
        u.abs() < reach + half * (a[0].abs() + a[1].abs()) && v.abs() < reach + half * (a[2].abs() + a[3].abs())
    }
}

/// The grid of one frame's packets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PacketGrid {
    /// The corner of cell (0, 0) (m, in the packets' frame).
    pub origin: DVec2,
    /// Side of a cell (m).
    pub cell_m: f64,
    pub cols: u32,
    pub rows: u32,
    /// The cells of each packet's bounding box, inclusive: first column, first row, last column,
    /// last row. A packet is listed in those its rectangle meets (`Footprint::meets`).
    pub ranges: Vec<[u32; 4]>,
    /// Each packet's rectangle, as the GPU tests it.
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
    /// crest rises higher over the rest plane, nor a trough sinks lower.
    pub crest_m: f64,
    /// The largest sum over one cell's packets of a bound on each one's height slope over the
    /// rest plane, k a plus its envelope's steepest (ENVELOPE_STEEPEST a / sigma; the ground
    /// truth's march steps by it).
    pub slope: f64,
}

/// The half-extents along x and y of the bounding box of a packet's envelope: a rectangle
/// reaching ENVELOPE_SIGMAS sigmas along each of its axes.
fn half_extent(p: &Packet) -> DVec2 {
    let (a, [s0, s1]) = (p.axis, p.sigma);
    ENVELOPE_SIGMAS * DVec2::new(a.x.abs() * s0 + a.y.abs() * s1, a.y.abs() * s0 + a.x.abs() * s1)
}

impl PacketGrid {
    /// The grid over `packets`, the finest of square cells at most MAX_CELLS_PER_SIDE to a side
    /// whose lists hold at most `max_entries` pairs and whose tiles' lists at most
    /// `tile_room(max_entries)` (coarser cells, fewer pairs: each cell side doubled until
    /// they fit). Empty without packets.
    pub fn new(packets: &[Packet], max_entries: usize) -> PacketGrid {
        Self::with_side(packets, max_entries, MAX_CELLS_PER_SIDE)
    }

    /// `new` with at most `per_side` cells a side.
    pub fn with_side(packets: &[Packet], max_entries: usize, per_side: u32) -> PacketGrid {
        let Some(first) = packets.first() else { return PacketGrid::default() };
        let (mut lo, mut hi) = (first.centre, first.centre);
        for p in packets {
            let h = half_extent(p);
            lo = lo.min(p.centre - h);
            hi = hi.max(p.centre + h);
        }
        let size = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let mut cell_m = size.max_element() / per_side as f64;
        loop {
            let grid = Self::with_cells(packets, lo, size, cell_m, per_side);
            let fits = grid.entries <= max_entries && grid.tile_packets.len() <= tile_room(max_entries);
            if fits || grid.cols * grid.rows == 1 {
                return grid;
            }
            cell_m *= 2.0;
        }
    }

    fn with_cells(packets: &[Packet], origin: DVec2, size: DVec2, cell_m: f64, per_side: u32) -> PacketGrid {
        let count = |extent: f64| ((extent / cell_m).ceil() as u32).clamp(1, per_side);
        let (cols, rows) = (count(size.x), count(size.y));
        let cell_of = |x: f64, n: u32| ((x / cell_m).floor().max(0.0) as u32).min(n - 1);
        let mut sums = vec![0.0f64; (cols * rows) as usize];
        let mut slopes = vec![0.0f64; (cols * rows) as usize];
        let mut grid = PacketGrid { origin, cell_m, cols, rows, ..Default::default() };
        let tiles_x = cols.div_ceil(TILE_CELLS);
        // (tile, packet) pairs in packet order; `last` drops a packet's repeats in a tile.
        let mut tile_pairs = Vec::new();
        let mut last = vec![u32::MAX; grid.tiles() as usize];
        for (i, p) in packets.iter().enumerate() {
            let h = half_extent(p);
            let (a, b) = (p.centre - h - origin, p.centre + h - origin);
            let r = [cell_of(a.x, cols), cell_of(a.y, rows), cell_of(b.x, cols), cell_of(b.y, rows)];
            let footprint = Footprint::of(p);
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

    /// The corner of cell (0, 0) and a cell's side, in single precision (as the GPU has them:
    /// FrameUniforms::packet_grid).
    pub fn origin_and_side_f32(&self) -> ([f32; 2], f32) {
        ([self.origin.x as f32, self.origin.y as f32], self.cell_m as f32)
    }

    /// The cells of box `range` that `footprint` meets, row by row.
    fn cells_met<'a>(&self, range: [u32; 4], footprint: &'a Footprint) -> impl Iterator<Item = (u32, u32)> + 'a {
        let (origin, side) = self.origin_and_side_f32();
        let half = 0.5 * side;
        (range[1]..=range[3]).flat_map(move |y| (range[0]..=range[2]).map(move |x| (x, y))).filter(move |&(x, y)| {
            let centre = [origin[0] + (x as f32 + 0.5) * side, origin[1] + (y as f32 + 0.5) * side];
            footprint.meets(centre, half)
        })
    }

    /// The cell holding rest position x, if the grid covers it.
    pub fn cell(&self, x: DVec2) -> Option<u32> {
        let c = (x - self.origin) / self.cell_m;
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
        Packet { centre, direction: DVec2::X, k: 1.0, amplitude, axis, sigma, phase: 0.0, in_phase: [false; 2] }
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
        let grid = PacketGrid::new(&ps, usize::MAX);
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

    /// A tile lists, in packet order, exactly the packets its cells list.
    #[test]
    fn a_tile_lists_the_packets_of_its_cells_in_order() {
        let ps = packets();
        let grid = PacketGrid::new(&ps, usize::MAX);
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
            in_phase: [false; 2],
        };
        let spread = [p, Packet { centre: DVec2::new(100.0, 100.0), ..p }];
        let grid = PacketGrid::with_side(&spread, usize::MAX, 32);
        let (starts, entries) = grid.lists();
        let listed = |x: DVec2| {
            let c = grid.cell(x).unwrap() as usize;
            entries[starts[c] as usize..starts[c + 1] as usize].contains(&0)
        };
        let cell = grid.cell_m;
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
        let fine = PacketGrid::new(&ps, usize::MAX);
        let coarse = PacketGrid::new(&ps, fine.entries / 3);
        assert!(
            coarse.entries <= fine.entries / 3 && coarse.cell_m >= 2.0 * fine.cell_m,
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
