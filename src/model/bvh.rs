//! A bounding-volume hierarchy over objects' triangles, for the exact tracer (rays that meet a
//! hull, a pier, a reflected mast) and for any ray the CPU casts. Built top-down with the surface
//! area heuristic over binned centroids (Wald, "On fast Construction of SAH-based Bounding
//! Volume Hierarchies", 2007: 12 bins are within a few percent of the full sweep), laid out
//! depth-first in 32-byte nodes a shader reads as they are: an inner node's children are
//! adjacent, the left one next to it.
//!
//! Rays are met in f64 (Möller & Trumbore 1997) against the f32 vertices, so the tracer's hits
//! are exact to the vertices' own precision.

use glam::{DVec3, Vec3};

/// Triangles per leaf at most; a leaf is made sooner when splitting costs more than it saves.
pub const MAX_LEAF: usize = 4;
/// Centroid bins per axis for the SAH.
const BINS: usize = 12;
/// The cost of visiting a node against intersecting one triangle (the SAH's traversal term).
const TRAVERSAL_COST: f32 = 1.0;

/// 32 bytes: a box, and either two adjacent children (`count` 0, the left one at `first`) or a
/// leaf's `count` triangles from `first`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub min: [f32; 3],
    pub first: u32,
    pub max: [f32; 3],
    pub count: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    /// The triangles in leaf order.
    pub triangles: Vec<[Vec3; 3]>,
    /// Each leaf-ordered triangle's index in the list `build` was given.
    pub source: Vec<u32>,
}

/// Where a ray met a triangle: its distance along the ray (in units of the direction's length),
/// the triangle (its index in `build`'s list), and the barycentric weights of its second and
/// third corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub triangle: u32,
    pub uv: [f64; 2],
}

#[derive(Clone, Copy)]
struct Bounds {
    min: Vec3,
    max: Vec3,
}

impl Bounds {
    const EMPTY: Bounds = Bounds { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    fn grow(&mut self, p: Vec3) {
        (self.min, self.max) = (self.min.min(p), self.max.max(p));
    }

    fn join(self, o: Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    fn area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
}

/// The hierarchy over `triangles` (finite vertices: model::gltf checks them).
pub fn build(triangles: &[[Vec3; 3]]) -> Bvh {
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    let centroids: Vec<Vec3> = triangles.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
    let bounds_of = |t: &[Vec3; 3]| {
        let mut b = Bounds::EMPTY;
        t.iter().for_each(|&p| b.grow(p));
        b
    };
    let boxes: Vec<Bounds> = triangles.iter().map(bounds_of).collect();
    let mut nodes = vec![Node { min: [0.0; 3], first: 0, max: [0.0; 3], count: 0 }];
    // (node, first, count) still to split, depth-first.
    let mut todo = vec![(0usize, 0usize, triangles.len())];
    while let Some((index, first, count)) = todo.pop() {
        let items = &mut order[first..first + count];
        let bounds = items.iter().fold(Bounds::EMPTY, |b, &i| b.join(boxes[i as usize]));
        nodes[index].min = bounds.min.into();
        nodes[index].max = bounds.max.into();
        let split = if count > 1 { best_split(items, &centroids, &boxes, bounds) } else { None };
        let (axis, cut) = match split {
            Some(split) => split,
            // Every centroid in one point: no plane separates them, halve in order.
            None if count > MAX_LEAF => (0, f32::NAN),
            None => {
                nodes[index].first = first as u32;
                nodes[index].count = count as u32;
                continue;
            }
        };
        // Partition by the chosen plane; a degenerate cut (all centroids one side) halves.
        let mut mid = partition(items, |i| centroids[i as usize][axis] < cut);
        if mid == 0 || mid == count {
            items.sort_by(|a, b| centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis]));
            mid = count / 2;
        }
        let left = nodes.len();
        nodes.push(Node { min: [0.0; 3], first: 0, max: [0.0; 3], count: 0 });
        nodes.push(Node { min: [0.0; 3], first: 0, max: [0.0; 3], count: 0 });
        nodes[index].first = left as u32;
        nodes[index].count = 0;
        todo.push((left + 1, first + mid, count - mid));
        todo.push((left, first, mid));
    }
    let ordered = order.iter().map(|&i| triangles[i as usize]).collect();
    Bvh { nodes, triangles: ordered, source: order }
}

/// The SAH's best axis and cut for `items` in `bounds`, where splitting beats a leaf.
fn best_split(items: &[u32], centroids: &[Vec3], boxes: &[Bounds], bounds: Bounds) -> Option<(usize, f32)> {
    let mut centre = Bounds::EMPTY;
    items.iter().for_each(|&i| centre.grow(centroids[i as usize]));
    let leaf_cost = items.len() as f32;
    let mut best: Option<(f32, usize, f32)> = None;
    for axis in 0..3 {
        let (lo, hi) = (centre.min[axis], centre.max[axis]);
        if hi - lo <= f32::EPSILON * lo.abs().max(hi.abs()).max(1.0) {
            continue; // every centroid on one plane: nothing to cut along this axis
        }
        let scale = BINS as f32 / (hi - lo);
        let bin_of = |c: f32| (((c - lo) * scale) as usize).min(BINS - 1);
        let mut bins = [(Bounds::EMPTY, 0usize); BINS];
        for &i in items {
            let b = &mut bins[bin_of(centroids[i as usize][axis])];
            (b.0, b.1) = (b.0.join(boxes[i as usize]), b.1 + 1);
        }
        // Areas and counts left of each cut, from the left and from the right.
        let mut left = [(0.0f32, 0usize); BINS - 1];
        let (mut b, mut n) = (Bounds::EMPTY, 0);
        for k in 0..BINS - 1 {
            (b, n) = (b.join(bins[k].0), n + bins[k].1);
            left[k] = (b.area(), n);
        }
        let (mut b, mut n) = (Bounds::EMPTY, 0);
        for k in (1..BINS).rev() {
            (b, n) = (b.join(bins[k].0), n + bins[k].1);
            let (area_l, n_l) = left[k - 1];
            if n_l == 0 || n == 0 {
                continue;
            }
            let cost =
                TRAVERSAL_COST + (area_l * n_l as f32 + b.area() * n as f32) / bounds.area().max(f32::MIN_POSITIVE);
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, lo + k as f32 / scale));
            }
        }
    }
    best.filter(|(cost, _, _)| *cost < leaf_cost || items.len() > MAX_LEAF).map(|(_, axis, cut)| (axis, cut))
}

/// Moves the items `left` accepts first; returns how many.
fn partition(items: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut mid = 0;
    for k in 0..items.len() {
        if left(items[k]) {
            items.swap(k, mid);
            mid += 1;
        }
    }
    mid
}

impl Bvh {
    /// The nearest triangle the ray `origin + t dir` meets with t in (t_min, t_max), from either
    /// side.
    pub fn intersect(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.triangles.is_empty() {
            return None;
        }
        let inverse = dir.recip(); // ±inf along axes the ray does not move on: the slab test holds
        let mut best: Option<Hit> = None;
        let mut stack = vec![0usize];
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index];
            let limit = best.map_or(t_max, |h| h.t);
            if !slab(node, origin, inverse, t_min, limit) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first as usize + 1);
                stack.push(node.first as usize);
                continue;
            }
            for k in node.first as usize..(node.first + node.count) as usize {
                let limit = best.map_or(t_max, |h| h.t);
                if let Some((t, uv)) = triangle_hit(&self.triangles[k], origin, dir, t_min, limit) {
                    best = Some(Hit { t, triangle: self.source[k], uv });
                }
            }
        }
        best
    }
}

/// Whether the ray meets the node's box within (t_min, t_max).
fn slab(node: &Node, origin: DVec3, inverse: DVec3, t_min: f64, t_max: f64) -> bool {
    let (lo, hi) = (Vec3::from(node.min).as_dvec3(), Vec3::from(node.max).as_dvec3());
    let (a, b) = ((lo - origin) * inverse, (hi - origin) * inverse);
    // NaN (0 * inf, a ray in a face's plane) compares false and is left out by max/min.
    let near = a.min(b).max_element().max(t_min);
    let far = a.max(b).min_element().min(t_max);
    near <= far
}

/// Möller–Trumbore in f64: the distance and the second and third corners' weights.
fn triangle_hit(tri: &[Vec3; 3], origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Option<(f64, [f64; 2])> {
    let [a, b, c] = tri.map(|p| p.as_dvec3());
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None; // the ray lies in the triangle's plane, or the triangle is degenerate
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) / det;
    (t > t_min && t < t_max).then_some((t, [u, v]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic generator (xorshift64*), so that the test sees the same soup every run.
    struct Random(u64);
    impl Random {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn point(&mut self, scale: f64) -> DVec3 {
            DVec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * scale
        }
    }

    #[test]
    fn every_ray_meets_what_brute_force_meets() {
        let mut random = Random(0x9e37_79b9_7f4a_7c15);
        // A soup of small and large triangles, some sharing a plane, one degenerate.
        let mut triangles: Vec<[Vec3; 3]> = (0..3000)
            .map(|k| {
                let centre = random.point(100.0);
                let size = if k % 10 == 0 { 20.0 } else { 2.0 };
                [0, 1, 2].map(|_| (centre + random.point(size)).as_vec3())
            })
            .collect();
        triangles.push([Vec3::ONE, Vec3::ONE, Vec3::ONE]);
        triangles.extend((0..50).map(|k| {
            let x = k as f32;
            [Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 0.0, 0.0), Vec3::new(x, 0.0, 1.0)]
        }));
        let bvh = build(&triangles);
        let mut seen = bvh.source.clone();
        seen.sort();
        assert_eq!(seen, (0..triangles.len() as u32).collect::<Vec<_>>(), "each triangle in one leaf");
        for node in bvh.nodes.iter().filter(|n| n.count == 0) {
            for child in &bvh.nodes[node.first as usize..node.first as usize + 2] {
                for axis in 0..3 {
                    assert!(node.min[axis] <= child.min[axis] && child.max[axis] <= node.max[axis]);
                }
            }
        }
        assert!(bvh.nodes.iter().all(|n| n.count as usize <= MAX_LEAF));
        let brute = |o: DVec3, d: DVec3| {
            triangles
                .iter()
                .enumerate()
                .filter_map(|(i, t)| triangle_hit(t, o, d, 0.0, f64::INFINITY).map(|(t, _)| (t, i as u32)))
                .min_by(|a, b| a.0.total_cmp(&b.0))
        };
        let mut hits = 0;
        for k in 0..2000 {
            let origin = random.point(150.0);
            // Some rays along an axis (their inverse direction has infinities).
            let dir = if k % 7 == 0 { DVec3::Y } else { (random.point(2.0) - origin * 0.004).normalize() };
            let ours = bvh.intersect(origin, dir, 0.0, f64::INFINITY).map(|h| (h.t, h.triangle));
            let truth = brute(origin, dir);
            match (ours, truth) {
                (Some(a), Some(b)) => {
                    assert!((a.0 - b.0).abs() <= 1e-9 * b.0.max(1.0), "ray {k}: {a:?} against {b:?}");
                    hits += 1;
                }
                (a, b) => assert_eq!(a, b, "ray {k}"),
            }
        }
        assert!(hits > 200, "only {hits} rays met anything: the test would prove little");
        // Far shallower than a list: a ray visits a few dozen nodes, not thousands of triangles.
        let depth = {
            let mut deepest = 0;
            let mut stack = vec![(0usize, 1usize)];
            while let Some((i, d)) = stack.pop() {
                deepest = deepest.max(d);
                if bvh.nodes[i].count == 0 {
                    let f = bvh.nodes[i].first as usize;
                    stack.extend([(f, d + 1), (f + 1, d + 1)]);
                }
            }
            deepest
        };
        assert!(depth < 40, "depth {depth}");
    }

    #[test]
    fn triangles_in_one_place_still_split_into_small_leaves() {
        let stacked = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]; 37];
        let bvh = build(&stacked);
        assert!(bvh.nodes.iter().all(|n| n.count as usize <= MAX_LEAF), "{:?}", bvh.nodes);
        let hit = bvh.intersect(DVec3::new(0.25, 0.25, 1.0), DVec3::NEG_Z, 0.0, f64::INFINITY).unwrap();
        assert!((hit.t - 1.0).abs() < 1e-12 && (hit.uv[0] - 0.25).abs() < 1e-12, "{hit:?}");
        assert!(build(&[]).intersect(DVec3::ZERO, DVec3::X, 0.0, 1.0).is_none());
    }
}
