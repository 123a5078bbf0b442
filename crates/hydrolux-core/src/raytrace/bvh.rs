//! Meshes for traced rays: a bounding-volume hierarchy over a mesh's
//! triangles, built once on the CPU and walked by the GPU's tracer
//! (`passes/raytrace/traced_hits.wgsl`, `trace_mesh`) as by
//! [`MeshBvh::intersect`] here.
//!
//! Built top-down by the surface area heuristic over 12 bins of the
//! centroids' widest axis (Wald, *On fast Construction of SAH-based
//! Bounding Volume Hierarchies*, 2007), down to at most
//! [`LEAF_TRIANGLES`] triangles a leaf. Nodes are flattened depth first:
//! an inner node's first child follows it, its second is at `next`. Rays
//! are intersected with triangles by Möller–Trumbore (1997) in the mesh's
//! own space, so a moving body's tree is never rebuilt: its ray is carried
//! into the mesh's frame instead.

use glam::Vec3;

/// The most triangles a leaf holds.
pub const LEAF_TRIANGLES: usize = 4;
/// Bins the surface area heuristic tries per split.
const BINS: usize = 12;
/// The deepest a tree may be (the GPU walks it with a stack this deep).
pub const MAX_DEPTH: usize = 32;

/// One node, as the GPU reads it (two `vec4<f32>`): its box, and either
/// its first triangle and count (a leaf, `count` > 0) or the index of its
/// second child (`count` = 0; the first follows it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode {
    pub min: Vec3,
    pub max: Vec3,
    /// A leaf's first triangle (in [`MeshBvh::triangles`]), or an inner node's second child.
    pub first_or_next: u32,
    pub count: u32,
}

/// A mesh's triangles in leaf order and the tree over them.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshBvh {
    pub nodes: Vec<BvhNode>,
    /// Each triangle's three corners, in the order the leaves hold them.
    pub triangles: Vec<[Vec3; 3]>,
}

/// A ray's first hit on a mesh: the distance along it (in units of the
/// ray's direction), the triangle, and its geometric normal (not unit,
/// facing where the corners turn counter-clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    pub t: f32,
    pub triangle: usize,
    pub normal: Vec3,
}

#[derive(Clone, Copy)]
struct Bounds {
    min: Vec3,
    max: Vec3,
}

impl Bounds {
    const EMPTY: Bounds =
        Bounds { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };
    fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    fn join(self, o: Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }
    fn area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

impl MeshBvh {
    /// The tree over the triangles `indices` makes of `positions`.
    pub fn build(positions: &[Vec3], indices: &[u32]) -> MeshBvh {
        let tris: Vec<[Vec3; 3]> =
            indices.chunks_exact(3).map(|t| [0, 1, 2].map(|k| positions[t[k] as usize])).collect();
        let mut order: Vec<usize> = (0..tris.len()).collect();
        let centroids: Vec<Vec3> = tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF_TRIANGLES + 1);
        if !tris.is_empty() {
            split(&tris, &centroids, &mut order, 0, &mut nodes, 0);
        }
        let triangles = order.iter().map(|&i| tris[i]).collect();
        MeshBvh { nodes, triangles }
    }

    /// The first hit of the ray o + t·d with t in (t_min, t_max), either
    /// side of a triangle.
    pub fn intersect(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<MeshHit> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = d.recip();
        let mut best: Option<MeshHit> = None;
        let mut reach = t_max;
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if slab(node.min, node.max, o, inv, t_min, reach).is_none() {
                continue;
            }
            if node.count > 0 {
                for k in node.first_or_next..node.first_or_next + node.count {
                    if let Some((t, n)) = triangle(self.triangles[k as usize], o, d)
                        && t > t_min
                        && t < reach
                    {
                        reach = t;
                        best = Some(MeshHit { t, triangle: k as usize, normal: n });
                    }
                }
            } else {
                let first = stack[top] + 1;
                // The nearer child last, so that it is walked first.
                let (a, b) = (first, node.first_or_next);
                let near_a = {
                    let (na, nb) = (self.nodes[a as usize], self.nodes[b as usize]);
                    let ca = 0.5 * (na.min + na.max) - o;
                    let cb = 0.5 * (nb.min + nb.max) - o;
                    ca.dot(d) <= cb.dot(d)
                };
                let (near, far) = if near_a { (a, b) } else { (b, a) };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        best
    }

    /// The same hit by testing every triangle (the reference the tree is
    /// tested against).
    pub fn intersect_all(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<MeshHit> {
        let mut best: Option<MeshHit> = None;
        for (k, tri) in self.triangles.iter().enumerate() {
            if let Some((t, n)) = triangle(*tri, o, d)
                && t > t_min
                && t < best.map_or(t_max, |b| b.t)
            {
                best = Some(MeshHit { t, triangle: k, normal: n });
            }
        }
        best
    }

    /// How deep the tree goes (a leaf alone is 1).
    pub fn depth(&self) -> usize {
        fn walk(nodes: &[BvhNode], i: usize) -> usize {
            let n = nodes[i];
            if n.count > 0 {
                1
            } else {
                1 + walk(nodes, i + 1).max(walk(nodes, n.first_or_next as usize))
            }
        }
        if self.nodes.is_empty() { 0 } else { walk(&self.nodes, 0) }
    }
}

/// Build the node over `order[lo..]` of length `order.len()` (a sub-slice
/// starting at triangle `offset`), appending it and its subtree to `nodes`.
fn split(
    tris: &[[Vec3; 3]],
    centroids: &[Vec3],
    order: &mut [usize],
    offset: usize,
    nodes: &mut Vec<BvhNode>,
    depth: usize,
) {
    let mut bounds = Bounds::EMPTY;
    let mut centre_bounds = Bounds::EMPTY;
    for &i in order.iter() {
        for p in tris[i] {
            bounds.grow(p);
        }
        centre_bounds.grow(centroids[i]);
    }
    let here = nodes.len();
    nodes.push(BvhNode {
        min: bounds.min,
        max: bounds.max,
        first_or_next: offset as u32,
        count: order.len() as u32,
    });
    if order.len() <= LEAF_TRIANGLES || depth + 1 >= MAX_DEPTH {
        return;
    }
    let extent = centre_bounds.max - centre_bounds.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let (lo, span) = (centre_bounds.min[axis], extent[axis]);
    let mut mid = order.len() / 2;
    if span > 0.0 {
        let bin =
            |i: usize| (((centroids[i][axis] - lo) / span * BINS as f32) as usize).min(BINS - 1);
        let mut bins = [(Bounds::EMPTY, 0usize); BINS];
        for &i in order.iter() {
            let b = &mut bins[bin(i)];
            for p in tris[i] {
                b.0.grow(p);
            }
            b.1 += 1;
        }
        // The cheapest of the BINS − 1 planes: Σ area × count each side.
        let mut best = (f32::INFINITY, 0);
        for cut in 1..BINS {
            let side = |r: std::ops::Range<usize>| {
                bins[r].iter().fold((Bounds::EMPTY, 0), |(b, c), (bb, cc)| (b.join(*bb), c + cc))
            };
            let ((lb, lc), (rb, rc)) = (side(0..cut), side(cut..BINS));
            if lc == 0 || rc == 0 {
                continue;
            }
            let cost = lb.area() * lc as f32 + rb.area() * rc as f32;
            if cost < best.0 {
                best = (cost, cut);
            }
        }
        if best.0.is_finite() {
            order.sort_by_key(|&i| bin(i) >= best.1);
            mid = order.iter().position(|&i| bin(i) >= best.1).unwrap_or(mid);
        } else {
            order.sort_by(|&a, &b| centroids[a][axis].total_cmp(&centroids[b][axis]));
        }
    } else {
        order.sort_by(|&a, &b| centroids[a][axis].total_cmp(&centroids[b][axis]));
    }
    nodes[here].count = 0;
    let (left, right) = order.split_at_mut(mid);
    split(tris, centroids, left, offset, nodes, depth + 1);
    nodes[here].first_or_next = nodes.len() as u32;
    split(tris, centroids, right, offset + mid, nodes, depth + 1);
}

/// Where the ray o + t·d (with `inv` = 1/d) is inside the box, clipped to
/// (t_min, t_max). Twin of `bvh_slab` in WGSL.
fn slab(min: Vec3, max: Vec3, o: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
    let a = (min - o) * inv;
    let b = (max - o) * inv;
    let near = a.min(b).max_element().max(t_min);
    let far = a.max(b).min_element().min(t_max);
    (near <= far).then_some((near, far))
}

/// Möller–Trumbore: where the ray meets the triangle (either side), and its
/// normal (e1 × e2). Twin of `bvh_triangle` in WGSL.
fn triangle(tri: [Vec3; 3], o: Vec3, d: Vec3) -> Option<(f32, Vec3)> {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - tri[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some((e2.dot(q) * inv, e1.cross(e2)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// The tree finds every ray's first hit on the bunny that testing
    /// every triangle finds, the same triangle at the same distance, and
    /// visits far fewer.
    #[test]
    fn the_tree_finds_what_testing_every_triangle_finds() {
        let mesh = crate::geometry::load::builtin_mesh("bunny").unwrap();
        let start = std::time::Instant::now();
        let bvh = MeshBvh::build(&mesh.positions, &mesh.indices);
        eprintln!(
            "{} triangles: {} nodes, depth {}, built in {:.1} ms",
            bvh.triangles.len(),
            bvh.nodes.len(),
            bvh.depth(),
            start.elapsed().as_secs_f64() * 1e3
        );
        assert_eq!(bvh.triangles.len(), mesh.triangle_count());
        assert!(bvh.depth() <= MAX_DEPTH, "depth {}", bvh.depth());
        // Every triangle in exactly one leaf, leaves tiling the list.
        let mut covered = vec![0u32; bvh.triangles.len()];
        for n in bvh.nodes.iter().filter(|n| n.count > 0) {
            assert!(n.count as usize <= LEAF_TRIANGLES);
            for k in n.first_or_next..n.first_or_next + n.count {
                covered[k as usize] += 1;
                for p in bvh.triangles[k as usize] {
                    assert!(
                        p.cmpge(n.min).all() && p.cmple(n.max).all(),
                        "a leaf's box holds its triangles"
                    );
                }
            }
        }
        assert!(covered.iter().all(|&c| c == 1));
        let (lo, hi) = (bvh.nodes[0].min, bvh.nodes[0].max);
        let centre = 0.5 * (lo + hi);
        let radius = (hi - lo).length();
        let mut rng = SplitMix64::new(7);
        let mut unit = || {
            let v = Vec3::new(
                rng.unit() as f32 * 2.0 - 1.0,
                rng.unit() as f32 * 2.0 - 1.0,
                rng.unit() as f32 * 2.0 - 1.0,
            );
            v.normalize_or(Vec3::Y)
        };
        let mut hits = 0;
        for _ in 0..2000 {
            // From a sphere around the mesh towards a point in its box.
            let o = centre + unit() * radius;
            let target = centre + unit() * 0.3 * radius;
            let d = target - o;
            let (a, b) = (
                bvh.intersect(o, d, 0.0, f32::INFINITY),
                bvh.intersect_all(o, d, 0.0, f32::INFINITY),
            );
            assert_eq!(a.map(|h| h.t), b.map(|h| h.t), "ray {o} → {target}");
            hits += a.is_some() as usize;
        }
        assert!(hits > 500, "{hits} of 2000 rays hit the bunny");
    }

    #[test]
    fn a_hit_is_where_the_ray_meets_the_triangle() {
        let positions =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0)];
        let bvh = MeshBvh::build(&positions, &[0, 2, 1]);
        let hit = bvh
            .intersect(Vec3::new(0.25, 2.0, 0.25), Vec3::new(0.0, -0.5, 0.0), 0.0, 10.0)
            .unwrap();
        assert!((hit.t - 4.0).abs() < 1e-6, "t in units of the direction: {}", hit.t);
        assert!(hit.normal.normalize().abs_diff_eq(Vec3::Y, 1e-6), "{}", hit.normal);
        assert!(
            bvh.intersect(Vec3::new(0.8, 2.0, 0.8), Vec3::NEG_Y, 0.0, 10.0).is_none(),
            "beside it"
        );
        assert!(
            bvh.intersect(Vec3::new(0.25, 2.0, 0.25), Vec3::NEG_Y, 0.0, 1.5).is_none(),
            "beyond t_max"
        );
    }
}
