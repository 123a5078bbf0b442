//! The liquid's surface as a screen-space mesh (seed 003 §3.2, after
//! Müller, Schirm & Duthaler 2007), the CPU twin of
//! `simulation/liquid/screen_mesh.wgsl`. Only the front-most layer the
//! camera sees is meshed, on a grid of the screen, and then carried back
//! to world space, so it reflects, refracts and casts light like any mesh.
//!
//! 1. **To screen space** ([`ScreenView::project`], eq. 21–23): a particle
//!    at x goes to (x_p, y_p) in pixels, its radius r to r_x, r_y pixels.
//!    The depth z_p is the clip w, the distance along the view axis: with
//!    Hydrolux's infinite reverse-Z projection the clip z is the same for
//!    every point, so w is the depth the method needs (linear, in metres,
//!    so z_max and r_z = r are in metres).
//! 2. **Depth map** ([`splat_depth`], eq. 24): nodes every h pixels
//!    ((W/h + 1) × (H/h + 1)); each particle lowers the nodes within its
//!    circle to z_p − r·√(1 − d²/r_p²), the front of its sphere.
//! 3. **Silhouettes** ([`silhouette_edges`], [`silhouette_cuts`]): a grid
//!    edge whose two depths differ by more than z_max (or with one node
//!    empty) is a silhouette edge. Each particle nearer than the edge's
//!    mean depth cuts the edge where its circle crosses it; the cut
//!    farthest from the front node is kept (Fig. 13).
//! 4. **Depth smoothing** ([`smooth_depth`]): a binomial filter of half
//!    length n_filter (Fig. 15), across then down, that takes only
//!    neighbours of the same layer (within z_max), so layers never blend.
//! 5. **Mesh** ([`mesh`], Fig. 14): one vertex per filled node; on a
//!    silhouette edge one vertex at the cut with the front layer's depth
//!    and, where the node behind is filled too, a second with the back
//!    layer's depth. Each grid square's four edges, cut or not, make the 16
//!    cases: the square's boundary splits at its cut edges into runs of
//!    corners; each run of filled corners, closed by the vertices on the
//!    cuts where it starts and ends, is one polygon, fanned into triangles.
//!    A run of empty corners makes nothing. Triangles wind counter-clockwise
//!    on the screen, so they face the camera.
//!    Each vertex but the outline's has a copy at the back of its layer
//!    ([`splat_back`]: the farthest sphere back among the particles whose
//!    front lies within z_max of the node's depth, filtered the same way),
//!    and each triangle is repeated on the copies, wound the other way: a
//!    back sheet that meets the front at the outline, so the mesh is a
//!    closed shell with the liquid's thickness (the seed's method meshes
//!    the front alone; the back sheet gives refraction its way out and
//!    absorption its path length).
//! 6. **Silhouette smoothing**: the front silhouette vertices, each joined
//!    to the next along the outline by the squares' closing edges, are
//!    moved n_iters times to the mean of themselves and those neighbours
//!    (the outline shrinks a little, as the seed says it should).
//! 7. **Back to world space** ([`ScreenView::unproject`], eq. 25–26), and
//!    per-vertex normals as the sum of the unit normals of the triangles
//!    around each vertex.

use super::surface::SurfaceMesh;
use glam::{Mat4, Vec3, Vec4};

/// "No vertex here" in the maps from nodes and edges to vertices.
pub const NONE: u32 = u32::MAX;
/// Half lengths of the depth filter allowed (Table 1: 0 to 10).
pub const MAX_FILTER: u32 = 10;
/// Rounds of silhouette smoothing allowed (Table 1: 0 to 10).
pub const MAX_SILHOUETTE_ITERATIONS: u32 = 10;
/// A particle whose circle is wider than this many node spacings (one
/// almost at the camera) is left out of the depth map: its splat would
/// cover a large part of the screen, and a camera that close is in the
/// liquid.
pub const MAX_SPLAT_REACH: f32 = 32.0;
/// The nearest depth a sphere's front is kept at (m): depths compare as
/// the bits of positive floats on the GPU.
pub const MIN_DEPTH: f32 = 1e-6;
/// Triangles one grid square makes at most (one cut edge: a run of four
/// corners and two cut vertices, a hexagon).
pub const MAX_SQUARE_TRIANGLES: usize = 4;

/// Table 1's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenMeshParams {
    /// h: pixels between the depth map's nodes (1 to 10).
    pub spacing: f32,
    /// r: the particles' radius (m).
    pub radius: f32,
    /// n_filter: the depth filter's half length (0 to 10).
    pub filter: u32,
    /// n_iters: rounds of silhouette smoothing (0 to 10).
    pub silhouette_iterations: u32,
    /// z_max (m): neighbours whose depths differ more are not joined
    /// (more than r_z = r).
    pub depth_threshold: f32,
}

impl ScreenMeshParams {
    /// Table 1's parameters of a liquid's scene keys (`fluid.screen_*`):
    /// r in particle spacings, z_max in particle radii.
    pub fn of(fluid: &crate::scene::FluidDesc) -> Self {
        let radius = fluid.screen_radius * fluid.particle_spacing();
        ScreenMeshParams {
            spacing: fluid.screen_spacing,
            radius,
            filter: fluid.screen_filter,
            silhouette_iterations: fluid.screen_silhouette_iterations,
            depth_threshold: fluid.screen_depth_threshold * radius,
        }
    }
}

/// The camera the mesh is made for.
#[derive(Clone, Copy, Debug)]
pub struct ScreenView {
    /// World → clip (P of eq. 21).
    pub view_proj: Mat4,
    /// The screen (W, H) in pixels.
    pub width: u32,
    pub height: u32,
}

/// A particle on the screen: position (pixels), depth (m), radii (pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub rx: f32,
    pub ry: f32,
}

impl ScreenView {
    /// The depth map's nodes across and down for spacing `h`.
    pub fn nodes(&self, h: f32) -> (usize, usize) {
        ((self.width as f32 / h) as usize + 1, (self.height as f32 / h) as usize + 1)
    }

    /// Eq. 21–23; `None` behind the camera. y_p grows upwards, like the
    /// clip space's y.
    pub fn project(&self, p: Vec3, r: f32) -> Option<Projected> {
        let c = self.view_proj * p.extend(1.0);
        if c.w <= 1e-4 {
            return None;
        }
        let (w, h) = (self.width as f32, self.height as f32);
        let row = |i| self.view_proj.row(i).truncate().length();
        Some(Projected {
            x: w * (0.5 + 0.5 * c.x / c.w),
            y: h * (0.5 + 0.5 * c.y / c.w),
            z: c.w,
            rx: 0.5 * r * w * row(0) / c.w,
            ry: 0.5 * r * h * row(1) / c.w,
        })
    }

    /// Eq. 25–26: the world point at pixel (x_p, y_p) and depth z_p (the
    /// clip w). Eq. 26 solves the unit homogeneous coordinate for w given
    /// the clip z; here w is known and it is solved for the clip z.
    pub fn unproject(&self, x: f32, y: f32, z: f32) -> Vec3 {
        self.unproject_by(&self.view_proj.inverse(), x, y, z)
    }

    /// [`Self::unproject`] with Q = P⁻¹ given (a mesh's vertices share it).
    pub fn unproject_by(&self, q: &Mat4, x: f32, y: f32, z: f32) -> Vec3 {
        let cx = (-1.0 + 2.0 * x / self.width as f32) * z;
        let cy = (-1.0 + 2.0 * y / self.height as f32) * z;
        let q4 = q.row(3);
        let cz = (1.0 - q4.x * cx - q4.y * cy - q4.w * z) / q4.z;
        (*q * Vec4::new(cx, cy, cz, z)).truncate()
    }
}

/// The depth map's grid: nodes (i, j) at (i·h, j·h) pixels, and its edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScreenGrid {
    pub nx: usize,
    pub ny: usize,
}

impl ScreenGrid {
    pub fn node(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }
    pub fn node_count(&self) -> usize {
        self.nx * self.ny
    }
    /// Edges along x, then along y.
    pub fn edge_count(&self) -> usize {
        (self.nx - 1) * self.ny + self.nx * (self.ny - 1)
    }
    /// The edge from node (i, j) to (i + 1, j).
    pub fn edge_x(&self, i: usize, j: usize) -> usize {
        j * (self.nx - 1) + i
    }
    /// The edge from node (i, j) to (i, j + 1).
    pub fn edge_y(&self, i: usize, j: usize) -> usize {
        (self.nx - 1) * self.ny + j * self.nx + i
    }
    /// An edge's two nodes, the lower first.
    pub fn edge_nodes(&self, e: usize) -> (usize, usize) {
        let along_x = (self.nx - 1) * self.ny;
        if e < along_x {
            let (i, j) = (e % (self.nx - 1), e / (self.nx - 1));
            (self.node(i, j), self.node(i + 1, j))
        } else {
            let e = e - along_x;
            let (i, j) = (e % self.nx, e / self.nx);
            (self.node(i, j), self.node(i, j + 1))
        }
    }
}

/// The projected particles in front of the camera and no wider than
/// [`MAX_SPLAT_REACH`] node spacings `h`.
pub fn project_all(
    view: &ScreenView,
    radius: f32,
    h: f32,
    particles: &[[f32; 3]],
) -> Vec<Projected> {
    particles
        .iter()
        .filter_map(|p| view.project(Vec3::from(*p), radius))
        .filter(|p| p.rx.max(p.ry) <= MAX_SPLAT_REACH * h)
        .collect()
}

/// Eq. 24: the front of every particle's sphere on the depth map (∞ where
/// no particle covers a node).
pub fn splat_depth(grid: ScreenGrid, h: f32, radius: f32, particles: &[Projected]) -> Vec<f32> {
    let mut depth = vec![f32::INFINITY; grid.node_count()];
    for p in particles {
        for_each_covered_node(grid, h, p, |n, reach| {
            let z = (p.z - radius * reach).max(MIN_DEPTH);
            depth[n] = depth[n].min(z);
        });
    }
    depth
}

/// Whether each edge is a silhouette edge: its depths differ by more than
/// z_max, or one of its nodes is empty (not both).
pub fn silhouette_edges(grid: ScreenGrid, depth: &[f32], z_max: f32) -> Vec<bool> {
    (0..grid.edge_count())
        .map(|e| {
            let (a, b) = grid.edge_nodes(e);
            let (za, zb) = (depth[a], depth[b]);
            match (za.is_finite(), zb.is_finite()) {
                (true, true) => (za - zb).abs() > z_max,
                (false, false) => false,
                _ => true,
            }
        })
        .collect()
}

/// The edge's front node (the nearer) and whether it is the edge's second.
fn front_is_second(depth: &[f32], a: usize, b: usize) -> bool {
    depth[b] < depth[a]
}

/// Where each silhouette edge is cut (Fig. 12–13), as the fraction of the
/// edge from its front node, the farthest of the particles' cuts that lie
/// nearer than the edge's mean depth; `None` where no particle cuts it
/// (the mesh then puts the vertex half way).
pub fn silhouette_cuts(
    grid: ScreenGrid,
    h: f32,
    particles: &[Projected],
    depth: &[f32],
    silhouette: &[bool],
) -> Vec<Option<f32>> {
    let mut cuts = vec![None::<f32>; grid.edge_count()];
    let offer = |e: usize, along: f32, cuts: &mut Vec<Option<f32>>, z: f32| {
        if !silhouette[e] || !(0.0..=1.0).contains(&along) {
            return;
        }
        let (a, b) = grid.edge_nodes(e);
        if z >= 0.5 * (depth[a] + depth[b]) {
            return;
        }
        let t = if front_is_second(depth, a, b) { 1.0 - along } else { along };
        let t = quantize_cut(t);
        if cuts[e].is_none_or(|old| t > old) {
            cuts[e] = Some(t);
        }
    };
    for p in particles {
        // Edges along x: rows within the circle, crossed at x_p ± half.
        for (rows, cols, axis_x) in [(grid.ny, grid.nx, true), (grid.nx, grid.ny, false)] {
            let (centre_across, r_across, centre_along, r_along) =
                if axis_x { (p.y, p.ry, p.x, p.rx) } else { (p.x, p.rx, p.y, p.ry) };
            let k0 = ((centre_across - r_across) / h).ceil().max(0.0) as usize;
            let k1 = ((centre_across + r_across) / h).floor();
            if k1 < 0.0 {
                continue;
            }
            for k in k0..=(k1 as usize).min(rows - 1) {
                let q = (k as f32 * h - centre_across) / r_across;
                if q * q >= 1.0 {
                    continue;
                }
                let half = r_along * (1.0 - q * q).sqrt();
                for x in [centre_along - half, centre_along + half] {
                    let m = (x / h).floor();
                    if m < 0.0 || m as usize >= cols - 1 {
                        continue;
                    }
                    let m = m as usize;
                    let along = x / h - m as f32;
                    let e = if axis_x { grid.edge_x(m, k) } else { grid.edge_y(k, m) };
                    offer(e, along, &mut cuts, p.z);
                }
            }
        }
    }
    cuts
}

/// The cuts are kept to 1/65536 of an edge, as the GPU keeps them.
pub fn quantize_cut(t: f32) -> f32 {
    (t.clamp(0.0, 1.0) * 65535.0).floor() / 65535.0
}

/// The binomial weights of half length `n` (Fig. 15; n = 3 gives
/// 1 6 15 20 15 6 1), weight of offset k at index n + k.
pub fn binomial_weights(n: u32) -> Vec<f32> {
    let n2 = 2 * n as u64;
    let mut w = vec![1u64; n2 as usize + 1];
    for k in 1..=n2 {
        w[k as usize] = w[k as usize - 1] * (n2 - k + 1) / k;
    }
    w.into_iter().map(|v| v as f32).collect()
}

/// One pass of the filter along x (`along_x`) or y over filled nodes,
/// taking only neighbours within z_max of the node in `raw` (its layer).
pub fn smooth_pass(
    grid: ScreenGrid,
    raw: &[f32],
    values: &[f32],
    n: u32,
    z_max: f32,
    along_x: bool,
) -> Vec<f32> {
    let w = binomial_weights(n);
    let n = n as i64;
    (0..grid.node_count())
        .map(|c| {
            if !raw[c].is_finite() {
                return f32::INFINITY;
            }
            let (i, j) = ((c % grid.nx) as i64, (c / grid.nx) as i64);
            let (mut sum, mut weight) = (0.0f32, 0.0f32);
            for k in -n..=n {
                let (ni, nj) = if along_x { (i + k, j) } else { (i, j + k) };
                if ni < 0 || nj < 0 || ni >= grid.nx as i64 || nj >= grid.ny as i64 {
                    continue;
                }
                let m = grid.node(ni as usize, nj as usize);
                if !raw[m].is_finite() || (raw[m] - raw[c]).abs() > z_max {
                    continue;
                }
                let wk = w[(k + n) as usize];
                sum += wk * values[m];
                weight += wk;
            }
            sum / weight
        })
        .collect()
}

/// The depth filter, across then down (§3.2.6).
pub fn smooth_depth(grid: ScreenGrid, raw: &[f32], n: u32, z_max: f32) -> Vec<f32> {
    smooth_map(grid, raw, raw, n, z_max)
}

/// The depth filter over `values` (a map of the same nodes as `raw`), its
/// layers those of `raw`.
pub fn smooth_map(grid: ScreenGrid, raw: &[f32], values: &[f32], n: u32, z_max: f32) -> Vec<f32> {
    let across = smooth_pass(grid, raw, values, n, z_max, true);
    smooth_pass(grid, raw, &across, n, z_max, false)
}

/// The back of the front layer: at each filled node, the farthest back of
/// the spheres whose front there lies within z_max of the node's depth
/// (the front layer's particles, not those of a layer behind it); 0 where
/// the node is empty.
pub fn splat_back(
    grid: ScreenGrid,
    h: f32,
    radius: f32,
    z_max: f32,
    particles: &[Projected],
    raw: &[f32],
) -> Vec<f32> {
    let mut back = vec![0.0f32; grid.node_count()];
    for p in particles {
        for_each_covered_node(grid, h, p, |n, reach| {
            let front = (p.z - radius * reach).max(MIN_DEPTH);
            if front <= raw[n] + z_max {
                back[n] = back[n].max(p.z + radius * reach);
            }
        });
    }
    back
}

/// Each node within particle `p`'s circle, with √(1 − d²/r_p²) there.
fn for_each_covered_node(grid: ScreenGrid, h: f32, p: &Projected, mut f: impl FnMut(usize, f32)) {
    let i0 = ((p.x - p.rx) / h).ceil().max(0.0) as usize;
    let i1 = ((p.x + p.rx) / h).floor().min(grid.nx as f32 - 1.0);
    let j0 = ((p.y - p.ry) / h).ceil().max(0.0) as usize;
    let j1 = ((p.y + p.ry) / h).floor().min(grid.ny as f32 - 1.0);
    if i1 < 0.0 || j1 < 0.0 {
        return;
    }
    for j in j0..=j1 as usize {
        for i in i0..=i1 as usize {
            let dx = (i as f32 * h - p.x) / p.rx;
            let dy = (j as f32 * h - p.y) / p.ry;
            let d2 = dx * dx + dy * dy;
            if d2 <= 1.0 {
                f(grid.node(i, j), (1.0 - d2).sqrt());
            }
        }
    }
}

/// What a vertex is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexKind {
    /// A filled node of the depth map.
    Node,
    /// On a silhouette edge, with the front layer's depth.
    Front,
    /// On a silhouette edge between two filled nodes, with the back
    /// layer's depth.
    Back,
    /// The back sheet's copy of the vertex before it (the same pixel, the
    /// depth of the back of its layer).
    Sheet,
}

/// The mesh, with its vertices on the screen as well as in the world.
#[derive(Clone, Debug)]
pub struct ScreenMesh {
    pub grid: ScreenGrid,
    /// (x_p, y_p, z_p) of each vertex after silhouette smoothing.
    pub screen: Vec<[f32; 3]>,
    pub kinds: Vec<VertexKind>,
    /// The front sheet's indices: the mesh's first, the back sheet's after.
    pub front_indices: usize,
    /// The world-space mesh (positions by eq. 25–26, normals from its
    /// triangles).
    pub mesh: SurfaceMesh,
}

/// A square's corners (counter-clockwise on the screen) as offsets, and its
/// edges: edge k joins corner k and corner k + 1.
pub const SQUARE_CORNERS: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// The grid edge of square (i, j)'s edge `k`.
pub fn square_edge(grid: ScreenGrid, i: usize, j: usize, k: usize) -> usize {
    match k {
        0 => grid.edge_x(i, j),
        1 => grid.edge_y(i + 1, j),
        2 => grid.edge_x(i, j + 1),
        _ => grid.edge_y(i, j),
    }
}

/// Which of an edge's two squares square edge `k` is (the silhouette
/// links' slot): 0 for the square below or left of the edge, 1 above or
/// right.
pub const fn square_side(k: usize) -> usize {
    match k {
        0 | 3 => 1,
        _ => 0,
    }
}

/// The polygons of one square (Fig. 14's 16 cases by its cut edges
/// `cut_mask`, bit k for edge k), for the corners `filled`: each polygon
/// as the edge it starts on, its corners (0 to 3) and the edge it ends on;
/// with no cut edge, the whole square (start and end edge `None`).
pub fn square_polygons(
    cut_mask: u32,
    filled: [bool; 4],
) -> Vec<(Option<usize>, Vec<usize>, Option<usize>)> {
    if cut_mask == 0 {
        return if filled.iter().all(|&f| f) {
            vec![(None, vec![0, 1, 2, 3], None)]
        } else {
            Vec::new()
        };
    }
    let cut = |k: usize| cut_mask & (1 << k) != 0;
    let mut polygons = Vec::new();
    for start in 0..4 {
        let entering = (start + 3) % 4;
        if !cut(entering) || !filled[start] {
            continue;
        }
        let mut corners = vec![start];
        let mut k = start;
        while !cut(k) {
            k = (k + 1) % 4;
            corners.push(k);
        }
        polygons.push((Some(entering), corners, Some(k)));
    }
    polygons
}

/// The whole method, steps 1 to 7.
pub fn mesh(view: &ScreenView, params: &ScreenMeshParams, particles: &[[f32; 3]]) -> ScreenMesh {
    let h = params.spacing;
    let (nx, ny) = view.nodes(h);
    let grid = ScreenGrid { nx, ny };
    let projected = project_all(view, params.radius, h, particles);
    let raw = splat_depth(grid, h, params.radius, &projected);
    let silhouette = silhouette_edges(grid, &raw, params.depth_threshold);
    let cuts = silhouette_cuts(grid, h, &projected, &raw, &silhouette);
    let depth = smooth_depth(grid, &raw, params.filter, params.depth_threshold);
    let far = splat_back(grid, h, params.radius, params.depth_threshold, &projected, &raw);
    let far = smooth_map(grid, &raw, &far, params.filter, params.depth_threshold);

    // Vertices: the filled nodes, then each silhouette edge's one or two,
    // each but the outline's followed by its back-sheet copy.
    let mut screen = Vec::new();
    let mut kinds = Vec::new();
    let mut node_vertex = vec![NONE; grid.node_count()];
    for (n, z) in depth.iter().enumerate() {
        if z.is_finite() {
            node_vertex[n] = screen.len() as u32;
            let (x, y) = ((n % nx) as f32 * h, (n / nx) as f32 * h);
            screen.extend([[x, y, *z], [x, y, far[n]]]);
            kinds.extend([VertexKind::Node, VertexKind::Sheet]);
        }
    }
    let mut edge_vertex = vec![[NONE; 2]; grid.edge_count()];
    let pos = |n: usize| [(n % nx) as f32 * h, (n / nx) as f32 * h];
    for e in 0..grid.edge_count() {
        if !silhouette[e] {
            continue;
        }
        let (a, b) = grid.edge_nodes(e);
        let (front, back) = if front_is_second(&raw, a, b) { (b, a) } else { (a, b) };
        let t = cuts[e].unwrap_or(0.5);
        let (pf, pb) = (pos(front), pos(back));
        let xy = [pf[0] + t * (pb[0] - pf[0]), pf[1] + t * (pb[1] - pf[1])];
        edge_vertex[e][0] = screen.len() as u32;
        screen.push([xy[0], xy[1], depth[front]]);
        kinds.push(VertexKind::Front);
        if raw[back].is_finite() {
            screen.push([xy[0], xy[1], far[front]]);
            edge_vertex[e][1] = screen.len() as u32;
            screen.extend([[xy[0], xy[1], depth[back]], [xy[0], xy[1], far[back]]]);
            kinds.extend([VertexKind::Sheet, VertexKind::Back, VertexKind::Sheet]);
        }
    }
    // The vertex on edge `e` for the polygon on node `n`'s side.
    let side_vertex = |e: usize, n: usize| {
        let (a, b) = grid.edge_nodes(e);
        let front = if front_is_second(&raw, a, b) { b } else { a };
        edge_vertex[e][usize::from(n != front)]
    };

    // Triangles, square by square, and the silhouette's links.
    let mut indices = Vec::new();
    let mut links = vec![[NONE; 2]; screen.len()];
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let corner = |c: usize| grid.node(i + SQUARE_CORNERS[c].0, j + SQUARE_CORNERS[c].1);
            let edge = |k: usize| square_edge(grid, i, j, k);
            let mask = (0..4).fold(0, |m, k| m | (u32::from(silhouette[edge(k)]) << k));
            let filled = [0, 1, 2, 3].map(|c| raw[corner(c)].is_finite());
            for (enter, corners, leave) in square_polygons(mask, filled) {
                let mut poly = Vec::with_capacity(6);
                if let Some(k) = enter {
                    poly.push(side_vertex(edge(k), corner(corners[0])));
                }
                poly.extend(corners.iter().map(|&c| node_vertex[corner(c)]));
                if let Some(k) = leave {
                    poly.push(side_vertex(edge(k), corner(*corners.last().unwrap())));
                }
                for t in 1..poly.len() - 1 {
                    indices.extend([poly[0], poly[t], poly[t + 1]]);
                }
                if let (Some(ke), Some(kl)) = (enter, leave) {
                    let (first, last) = (poly[0], *poly.last().unwrap());
                    let front = |v: u32| kinds[v as usize] == VertexKind::Front;
                    if front(first) && front(last) {
                        links[first as usize][square_side(ke)] = last;
                        links[last as usize][square_side(kl)] = first;
                    }
                }
            }
        }
    }

    // The back sheet: each triangle again on the vertices' copies (the
    // outline's own vertices, which have none, close it), wound the other
    // way so it faces away from the camera.
    let sheet = |v: u32| {
        let copy = v as usize + 1;
        if kinds.get(copy) == Some(&VertexKind::Sheet) { copy as u32 } else { v }
    };
    let front_indices = indices.len();
    for t in 0..front_indices / 3 {
        let [a, b, c] = [0, 1, 2].map(|k| indices[3 * t + k]);
        indices.extend([sheet(a), sheet(c), sheet(b)]);
    }

    // Silhouette smoothing: the front silhouette's vertices to the mean of
    // themselves and their neighbours along it (the back sheet's copies
    // follow them).
    for _ in 0..params.silhouette_iterations {
        let before = screen.clone();
        for (v, l) in links.iter().enumerate() {
            if kinds[v] != VertexKind::Front {
                continue;
            }
            let mut sum = [before[v][0], before[v][1]];
            let mut count = 1.0;
            for &n in l.iter().filter(|&&n| n != NONE) {
                sum[0] += before[n as usize][0];
                sum[1] += before[n as usize][1];
                count += 1.0;
            }
            screen[v][0] = sum[0] / count;
            screen[v][1] = sum[1] / count;
        }
        for v in 1..screen.len() {
            if kinds[v] == VertexKind::Sheet {
                screen[v][0] = screen[v - 1][0];
                screen[v][1] = screen[v - 1][1];
            }
        }
    }

    let q = view.view_proj.inverse();
    let positions: Vec<[f32; 3]> =
        screen.iter().map(|s| view.unproject_by(&q, s[0], s[1], s[2]).to_array()).collect();
    let normals = vertex_normals(view, &q, &screen, &positions, &indices);
    ScreenMesh {
        grid,
        screen,
        kinds,
        front_indices,
        mesh: SurfaceMesh { positions, normals, indices },
    }
}

/// Each vertex's normal: the sum of its triangles' unit normals; a vertex
/// of none faces the camera.
fn vertex_normals(
    view: &ScreenView,
    q: &Mat4,
    screen: &[[f32; 3]],
    positions: &[[f32; 3]],
    indices: &[u32],
) -> Vec<[f32; 3]> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(positions[t[k] as usize]));
        let n = (b - a).cross(c - a).normalize_or_zero();
        for &v in t {
            sum[v as usize] += n;
        }
    }
    sum.iter()
        .zip(screen)
        .map(|(n, s)| {
            let towards_eye = view.unproject_by(q, s[0], s[1], s[2])
                - view.unproject_by(q, s[0], s[1], s[2] + 1.0);
            n.try_normalize().unwrap_or(towards_eye.normalize()).to_array()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera at the origin looking down −z with a 90° field of view on a
    /// 64 × 64 screen: one pixel is 1/32 of the depth across.
    fn view() -> ScreenView {
        let proj = glam::camera::rh::proj::directx::perspective_infinite_reverse(
            std::f32::consts::FRAC_PI_2,
            1.0,
            0.01,
        );
        ScreenView { view_proj: proj, width: 64, height: 64 }
    }

    /// The world point seen at pixel (x, y) at depth z.
    fn at(x: f32, y: f32, z: f32) -> [f32; 3] {
        [(x / 32.0 - 1.0) * z, (y / 32.0 - 1.0) * z, -z]
    }

    fn params(radius: f32) -> ScreenMeshParams {
        ScreenMeshParams {
            spacing: 4.0,
            radius,
            filter: 0,
            silhouette_iterations: 0,
            depth_threshold: 0.5,
        }
    }

    #[test]
    fn projection_is_undone_by_eq_25_26() {
        let v = view();
        for p in [[0.3, -0.2, -2.0], [1.5, 0.7, -4.0], [-3.0, 2.0, -9.0]] {
            let s = v.project(Vec3::from(p), 0.1).unwrap();
            let back = v.unproject(s.x, s.y, s.z);
            assert!((back - Vec3::from(p)).length() < 1e-4 * s.z, "{p:?} → {back}");
            // Eq. 23: 0.1 m at depth z spans 0.1·32/z pixels here.
            assert!((s.rx - 3.2 / s.z).abs() < 1e-4 && (s.ry - s.rx).abs() < 1e-5);
        }
        assert!(v.project(Vec3::new(0.0, 0.0, 1.0), 0.1).is_none());
    }

    #[test]
    fn binomial_weights_are_pascals_row() {
        assert_eq!(binomial_weights(0), vec![1.0]);
        assert_eq!(binomial_weights(3), vec![1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0]);
    }

    /// Hand-worked: one particle exactly on node (8, 8), its circle 0.6 of
    /// a spacing across, covers that node alone. The node is one vertex at
    /// the sphere's front; its four edges are silhouette edges, each cut
    /// 0.6 of the way out; the four squares around it make one triangle
    /// each (case: two cut edges meeting at one filled corner) — a diamond.
    #[test]
    fn one_particle_makes_a_diamond() {
        let v = view();
        let z = 2.0;
        // r_p = r·32/z pixels = 0.6·4 → r = 0.15.
        let r = 0.15;
        let m = mesh(&v, &params(r), &[at(32.0, 32.0, z)]);
        assert_eq!(m.kinds.iter().filter(|k| **k == VertexKind::Node).count(), 1);
        assert_eq!(m.kinds.iter().filter(|k| **k == VertexKind::Front).count(), 4);
        // Four triangles in front, four behind on the back sheet.
        assert_eq!((m.front_indices, m.mesh.indices.len()), (12, 24));
        let node = m.screen[0];
        assert_eq!([node[0], node[1]], [32.0, 32.0]);
        assert!((node[2] - (z - r)).abs() < 1e-5);
        // Its back-sheet copy is at the back of the sphere.
        assert_eq!(m.kinds[1], VertexKind::Sheet);
        assert!((m.screen[1][2] - (z + r)).abs() < 1e-5);
        let mut offsets: Vec<(i32, i32)> = m
            .screen
            .iter()
            .zip(&m.kinds)
            .filter(|(_, k)| **k == VertexKind::Front)
            .map(|(s, _)| s)
            .map(|s| {
                (((s[0] - 32.0) * 100.0).round() as i32, ((s[1] - 32.0) * 100.0).round() as i32)
            })
            .collect();
        offsets.sort();
        assert_eq!(offsets, vec![(-240, 0), (0, -240), (0, 240), (240, 0)]);
        // Every triangle faces the camera (+z here) and is wound so.
        for (k, t) in m.mesh.triangles().enumerate() {
            let [a, b, c] = t.map(Vec3::from);
            let towards = (b - a).cross(c - a).z > 0.0;
            assert_eq!(towards, 3 * k < m.front_indices, "triangle {k}");
        }
        // One round of silhouette smoothing: the right vertex (2.4, 0) to
        // the mean of itself and the top and bottom ones, (0.8, 0).
        let smoothed = mesh(
            &v,
            &ScreenMeshParams { silhouette_iterations: 1, ..params(r) },
            &[at(32.0, 32.0, z)],
        );
        let right = smoothed
            .screen
            .iter()
            .zip(&m.screen)
            .find(|(_, before)| before[0] > 34.0)
            .map(|(after, _)| after[0] - 32.0)
            .unwrap();
        assert!((right - 0.8).abs() < 1e-4, "{right}");
    }

    /// Hand-worked: with r = 0.3 m, a near particle (z = 2, r_p = 4.8 px)
    /// on node (8, 8) fills it and its four neighbours 4 px away; a far one
    /// (z = 4, r_p = 2.4 px) on node (10, 8) fills that node alone. The
    /// edge (9, 8)–(10, 8) joins the two layers (1.834 against 3.7 m, more
    /// than z_max = 1 apart): a silhouette edge between two filled nodes,
    /// so it has two vertices at its cut, one at each layer's depth. Only
    /// the near particle is nearer than the edge's mean depth, and its
    /// circle crosses the edge 0.8 px past (9, 8): the cut is at 0.2.
    #[test]
    fn two_layers_make_front_and_back_vertices() {
        let v = view();
        let (near, far) = (at(32.0, 32.0, 2.0), at(40.0, 32.0, 4.0));
        let p = ScreenMeshParams { depth_threshold: 1.0, ..params(0.3) };
        let grid = ScreenGrid { nx: 17, ny: 17 };
        let projected = project_all(&v, p.radius, 4.0, &[near, far]);
        let raw = splat_depth(grid, 4.0, p.radius, &projected);
        let n = |i, j| grid.node(i, j);
        let filled: Vec<usize> = (0..raw.len()).filter(|&k| raw[k].is_finite()).collect();
        let mut expected = vec![n(8, 7), n(7, 8), n(8, 8), n(9, 8), n(10, 8), n(8, 9)];
        expected.sort();
        assert_eq!(filled, expected);
        assert!((raw[n(10, 8)] - 3.7).abs() < 1e-5);
        let side = 2.0 - 0.3 * (1.0f32 - (4.0f32 / 4.8).powi(2)).sqrt();
        assert!((raw[n(9, 8)] - side).abs() < 1e-5, "{}", raw[n(9, 8)]);
        let silhouette = silhouette_edges(grid, &raw, p.depth_threshold);
        let e = grid.edge_x(9, 8);
        assert!(silhouette[e] && !silhouette[grid.edge_x(8, 8)]);
        let cuts = silhouette_cuts(grid, 4.0, &projected, &raw, &silhouette);
        assert!((cuts[e].unwrap() - 0.2).abs() < 1e-4, "{:?}", cuts[e]);

        let m = mesh(&v, &p, &[near, far]);
        let backs: Vec<usize> =
            (0..m.kinds.len()).filter(|&k| m.kinds[k] == VertexKind::Back).collect();
        assert_eq!(backs.len(), 1, "only the edge (9, 8)–(10, 8) joins two filled layers");
        let (back, front) = (backs[0], backs[0] - 2);
        assert_eq!(m.kinds[front], VertexKind::Front);
        assert_eq!((m.kinds[front + 1], m.kinds[back + 1]), (VertexKind::Sheet, VertexKind::Sheet));
        // The back sheet's copies: the back of each layer's spheres.
        assert!(
            (m.screen[front + 1][2] - (2.0 + 0.3 * (1.0f32 - (4.0f32 / 4.8).powi(2)).sqrt())).abs()
                < 1e-4
        );
        assert!((m.screen[back + 1][2] - 4.3).abs() < 1e-5);
        assert!((m.screen[front][0] - 36.8).abs() < 1e-3 && m.screen[front][1] == 32.0);
        assert_eq!(m.screen[front][..2], m.screen[back][..2]);
        assert!((m.screen[front][2] - side).abs() < 1e-5);
        assert!((m.screen[back][2] - 3.7).abs() < 1e-5);
        // The back vertex is used: the far layer's triangles reach it.
        assert!(m.mesh.indices.contains(&(back as u32)));
    }

    /// A wall of particles square to the view: the depth map is flat, the
    /// filter leaves it flat, there are no silhouettes inside, and the mesh
    /// lies on the wall's front, facing the camera, with the wall's area.
    #[test]
    fn a_wall_facing_the_camera_is_meshed_flat() {
        let v = view();
        let z = 1.0;
        let s = 0.05;
        let mut particles = Vec::new();
        for a in -10..=10 {
            for b in -10..=10 {
                particles.push([a as f32 * s, b as f32 * s, -z]);
            }
        }
        let p = ScreenMeshParams {
            radius: s,
            filter: 2,
            depth_threshold: 0.2,
            spacing: 1.0,
            silhouette_iterations: 0,
        };
        let m = mesh(&v, &p, &particles);
        for (pos, kind) in m.mesh.positions.iter().zip(&m.kinds) {
            let inside = pos[0].abs() < 0.4 && pos[1].abs() < 0.4;
            if *kind == VertexKind::Node && inside {
                // Between the spheres' fronts (z − r) and their seams.
                assert!((-pos[2] - (z - s)).abs() < 0.2 * s, "{pos:?}");
            }
        }
        for (n, pos) in m.mesh.normals.iter().zip(&m.mesh.positions) {
            if pos[0].abs() < 0.4 && pos[1].abs() < 0.4 {
                let kind = m.kinds[m.mesh.positions.iter().position(|p| p == pos).unwrap()];
                let facing = if kind == VertexKind::Sheet { -n[2] } else { n[2] };
                assert!(facing > 0.9, "{kind:?} {n:?}");
            }
        }
        // The wall spans 20 s + 2 r = 1.1 m on a side (its circles' outline).
        let front =
            SurfaceMesh { indices: m.mesh.indices[..m.front_indices].to_vec(), ..m.mesh.clone() };
        let area = front.area();
        assert!((area - 1.1 * 1.1).abs() < 0.1 * 1.21, "{area}");
        // Consistently wound: an inside edge is used once each way.
        let mut edges = std::collections::HashMap::new();
        for t in m.mesh.indices.chunks(3) {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&c| c == 1), "no edge is used twice in one direction");
        // Front and back sheet meet at the outline: the shell is closed.
        assert!(edges.keys().all(|(a, b)| edges.contains_key(&(*b, *a))), "an open edge");
    }

    #[test]
    fn squares_make_the_16_cases() {
        // No cut: the square; all cut: four corner triangles.
        assert_eq!(square_polygons(0, [true; 4]).len(), 1);
        let all = square_polygons(0b1111, [true; 4]);
        assert_eq!(all.len(), 4);
        assert!(all.iter().all(|(_, c, _)| c.len() == 1));
        // One cut: one polygon of every corner and two cut vertices.
        let one = square_polygons(0b0001, [true; 4]);
        assert_eq!(one, vec![(Some(0), vec![1, 2, 3, 0], Some(0))]);
        // Opposite cuts: two runs of two corners.
        assert_eq!(square_polygons(0b0101, [true; 4]).len(), 2);
        // Empty corners make nothing.
        assert!(
            square_polygons(0b1001, [false, true, true, true])
                .iter()
                .all(|(_, c, _)| !c.contains(&0))
        );
        // Each case's triangles: at most MAX_SQUARE_TRIANGLES.
        for mask in 0..16 {
            let tris: usize = square_polygons(mask, [true; 4])
                .iter()
                .map(|(s, c, e)| c.len() + usize::from(s.is_some()) + usize::from(e.is_some()) - 2)
                .sum();
            assert!(tris <= MAX_SQUARE_TRIANGLES, "case {mask:04b}: {tris}");
        }
    }
}
