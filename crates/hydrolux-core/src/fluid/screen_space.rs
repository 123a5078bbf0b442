//! The liquid drawn by screen-space fluid rendering, the CPU twin of
//! `simulation/liquid/screen_space.wgsl` (seed 003 §3.2 names the family;
//! the method is van der Laan, Green & Sainz 2009, with the narrow-range
//! filter of Truong & Yuksel 2018). No mesh is made: the particles are
//! drawn as spheres into two screen images, which are smoothed and shaded
//! as a surface per pixel. It is the fast path beside the two meshes, and
//! a comparison for them (`hydrolux compare --surfaces`).
//!
//! 1. **Depth and thickness splats** ([`splat`]): per pixel, the ray
//!    through the pixel's centre meets each particle's sphere (radius r);
//!    the depth map keeps the nearest front (as the clip w, the distance
//!    along the view axis, like the screen-space mesh), the thickness map
//!    sums the chords (m along the ray), each cut short by the opaque scene
//!    where it lies nearer (`scene_w`) and weighted by the particle's share
//!    of its sphere ([`sphere_share`]): the spheres overlap, and the
//!    thickness is the liquid's.
//! 2. **Narrow-range filter** ([`filter`]): a Gaussian of the depths whose
//!    radius is a world length (`filter_radius`) seen at the pixel's depth
//!    (at most [`MAX_FILTER_PIXELS`]), σ half that radius, across then
//!    down. Its range is narrow around the centre's depth z_c: a sample
//!    nearer than z_c − `threshold` is another layer in front and is left
//!    out; one farther than z_c + `threshold` (or empty, which is the
//!    background) counts as z_c + `clamp`, so a layer's edge bends away
//!    gently instead of being dragged to what lies behind it. The
//!    thickness is blurred by the same Gaussian (empty pixels are 0 thick).
//! 3. **Normals from depth** ([`normal_at`]): the filtered depths back to
//!    world space (eq. 25–26, [`ScreenView::unproject_by`]); the normal is
//!    the cross product of the differences across and down, each taken on
//!    the side whose depth is nearer the centre's (no difference across a
//!    silhouette).
//!
//! The shading (per pixel, `screen_space.wgsl`) is the same water as the
//! meshes': Fresnel, the sky and the sun's glint mirrored, the scene
//! behind refracted through a slab of the pixel's thickness and absorbed
//! over it by the water's medium.
//!
//! Pixels are addressed as the images are: x across, y down, centres at
//! half-integers.

use super::screen_mesh::ScreenView;
use glam::{Mat4, Vec3, Vec4};

/// The filter's widest reach (pixels either side): a near liquid is
/// filtered no wider, so its cost per pixel is bounded.
pub const MAX_FILTER_PIXELS: u32 = 16;

/// The method's parameters, in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenSpaceParams {
    /// The particles' spheres (m).
    pub radius: f32,
    /// A particle's share of the liquid's volume over its sphere's volume:
    /// each chord counts this much, so that the thickness sums the liquid's
    /// volume, not the spheres' overlaps (at one particle spacing the
    /// spheres hold about 4 times the liquid).
    pub volume_share: f32,
    /// The filter's radius as a world length (m); 0 leaves the depths as
    /// splatted.
    pub filter_radius: f32,
    /// Depths differing by more are other layers (m).
    pub threshold: f32,
    /// Where a farther sample counts from the centre (m).
    pub clamp: f32,
}

impl ScreenSpaceParams {
    /// The parameters of a liquid's scene keys: the spheres of
    /// `fluid.screen_radius` particle spacings (shared with the screen
    /// mesh), the layers parted at `fluid.screen_depth_threshold` radii
    /// (shared too), the filter and clamp in radii.
    pub fn of(fluid: &crate::scene::FluidDesc) -> Self {
        let spacing = fluid.particle_spacing();
        let radius = fluid.screen_radius * spacing;
        ScreenSpaceParams {
            radius,
            volume_share: sphere_share(spacing, radius),
            filter_radius: fluid.screen_space_filter * radius,
            threshold: fluid.screen_depth_threshold * radius,
            clamp: fluid.screen_space_clamp * radius,
        }
    }
}

/// The share of a sphere of `radius` that a particle's cube of liquid
/// (side `spacing`) fills.
pub fn sphere_share(spacing: f32, radius: f32) -> f32 {
    spacing.powi(3) / (4.0 / 3.0 * std::f32::consts::PI * radius.powi(3))
}

/// The two images, row by row from the top; a depth of 0 is empty.
#[derive(Clone, Debug, PartialEq)]
pub struct FluidMaps {
    pub width: u32,
    pub height: u32,
    /// The nearest sphere's front as the clip w (m).
    pub depth: Vec<f32>,
    /// The summed chords (m).
    pub thickness: Vec<f32>,
}

impl FluidMaps {
    pub fn empty(width: u32, height: u32) -> Self {
        let n = (width * height) as usize;
        FluidMaps { width, height, depth: vec![0.0; n], thickness: vec![0.0; n] }
    }

    pub fn index(&self, x: u32, y: u32) -> usize {
        (y * self.width + x) as usize
    }

    /// Pixels the liquid covers.
    pub fn covered(&self) -> usize {
        self.depth.iter().filter(|&&z| z > 0.0).count()
    }
}

/// Pixels per metre at unit depth, down the screen (the filter's scale).
pub fn pixels_per_metre(view: &ScreenView) -> f32 {
    0.5 * view.height as f32 * view.view_proj.row(1).truncate().length()
}

/// How the clip w grows along a unit of `dir` from the eye (w is 0 at the
/// eye of a perspective camera).
pub fn w_per_metre(view: &ScreenView, dir: Vec3) -> f32 {
    view.view_proj.row(3).truncate().dot(dir)
}

/// The unit ray from `eye` through the centre of pixel (x, y).
pub fn pixel_ray(view: &ScreenView, q: &Mat4, eye: Vec3, x: u32, y: u32) -> Vec3 {
    let far = pixel_point(view, q, x as f32 + 0.5, y as f32 + 0.5, 1.0);
    (far - eye).normalize()
}

/// The world point at image position (x, y) (pixels, y down) and depth w.
pub fn pixel_point(view: &ScreenView, q: &Mat4, x: f32, y: f32, w: f32) -> Vec3 {
    view.unproject_by(q, x, view.height as f32 - y, w)
}

/// The clip w of the opaque scene from the depth buffer's value `z` at
/// normalised device position (ndc_x, ndc_y): infinite where the buffer
/// is empty (0 with reversed Z).
pub fn scene_w(q: &Mat4, ndc_x: f32, ndc_y: f32, z: f32) -> f32 {
    let h = *q * Vec4::new(ndc_x, ndc_y, z, 1.0);
    if h.w > 0.0 { 1.0 / h.w } else { f32::INFINITY }
}

/// The entry and exit distances of the ray (`eye`, unit `dir`) through
/// the sphere at `centre`, or `None` if it misses or starts inside.
pub fn sphere_chord(eye: Vec3, dir: Vec3, centre: Vec3, r: f32) -> Option<(f32, f32)> {
    let oc = eye - centre;
    let b = oc.dot(dir);
    let disc = b * b - (oc.length_squared() - r * r);
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let t0 = -b - s;
    (t0 > 0.0).then_some((t0, -b + s))
}

/// Step 1: the depth and thickness splats of spheres of `radius` at
/// `particles` for a camera at `eye`, each chord weighted by `share`.
/// `scene_w` (per pixel, the opaque scene's clip w, infinite where none)
/// hides the spheres behind it and cuts the chords that reach it.
pub fn splat(
    view: &ScreenView,
    eye: Vec3,
    (radius, share): (f32, f32),
    particles: &[[f32; 3]],
    scene_w: Option<&[f32]>,
) -> FluidMaps {
    let mut maps = FluidMaps::empty(view.width, view.height);
    let q = view.view_proj.inverse();
    let (w, h) = (view.width as i64, view.height as i64);
    for p in particles {
        let c = Vec3::from(*p);
        let Some(s) = view.project(c, radius) else { continue };
        // The silhouette of a near sphere is wider than r/w: widen, as the
        // GPU's quad does, and test every pixel exactly.
        let dist = (c - eye).length();
        let grow = dist / (dist * dist - radius * radius).max(1e-8).sqrt();
        let (rx, ry) = (s.rx * grow + 1.0, s.ry * grow + 1.0);
        let cy = h as f32 - s.y;
        let x0 = ((s.x - rx).floor() as i64).max(0);
        let x1 = ((s.x + rx).ceil() as i64).min(w - 1);
        let y0 = ((cy - ry).floor() as i64).max(0);
        let y1 = ((cy + ry).ceil() as i64).min(h - 1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (x, y) = (x as u32, y as u32);
                let dir = pixel_ray(view, &q, eye, x, y);
                let Some((t0, t1)) = sphere_chord(eye, dir, c, radius) else { continue };
                let k = w_per_metre(view, dir);
                let i = maps.index(x, y);
                let limit = scene_w.map_or(f32::INFINITY, |s| s[i]);
                let front = t0 * k;
                if front > limit {
                    continue;
                }
                let back = t1.min(limit / k.max(1e-12));
                if maps.depth[i] == 0.0 || front < maps.depth[i] {
                    maps.depth[i] = front;
                }
                maps.thickness[i] += share * (back - t0);
            }
        }
    }
    maps
}

/// The filter's reach (pixels either side) at depth `z`.
pub fn filter_reach(params: &ScreenSpaceParams, scale: f32, z: f32) -> u32 {
    if z <= 0.0 || params.filter_radius <= 0.0 {
        return 0;
    }
    ((params.filter_radius * scale / z).ceil() as u32).min(MAX_FILTER_PIXELS)
}

/// One pass of step 2 along (dx, dy), for a perspective view (`scale`:
/// pixels per metre at unit depth).
pub fn filter_pass(
    maps: &FluidMaps,
    params: &ScreenSpaceParams,
    scale: f32,
    dx: i32,
    dy: i32,
) -> FluidMaps {
    filter_pass_by(maps, params, |z| filter_reach(params, scale, z), (dx, dy), false)
}

/// One pass of step 2 along `step`, reaching `reach(z)` pixels either side
/// of a pixel at depth z; with `backs`, the second channel is averaged over
/// filled pixels alone.
fn filter_pass_by(
    maps: &FluidMaps,
    params: &ScreenSpaceParams,
    reach: impl Fn(f32) -> u32,
    (dx, dy): (i32, i32),
    backs: bool,
) -> FluidMaps {
    let mut out = FluidMaps::empty(maps.width, maps.height);
    for y in 0..maps.height {
        for x in 0..maps.width {
            let i = maps.index(x, y);
            let zc = maps.depth[i];
            if zc <= 0.0 {
                continue;
            }
            let reach = reach(zc) as i32;
            let sigma = 0.5 * reach.max(1) as f32;
            let (mut zs, mut zw, mut ts, mut tw) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
            for k in -reach..=reach {
                let (sx, sy) = (x as i32 + k * dx, y as i32 + k * dy);
                if sx < 0 || sy < 0 || sx >= maps.width as i32 || sy >= maps.height as i32 {
                    continue;
                }
                let g = (-((k * k) as f32) / (2.0 * sigma * sigma)).exp();
                let j = maps.index(sx as u32, sy as u32);
                let z = maps.depth[j];
                if !backs || z > 0.0 {
                    ts += g * maps.thickness[j];
                    tw += g;
                }
                if z > 0.0 && z < zc - params.threshold {
                    continue;
                }
                let z = if z <= 0.0 || z > zc + params.threshold { zc + params.clamp } else { z };
                zs += g * z;
                zw += g;
            }
            out.depth[i] = zs / zw;
            out.thickness[i] = ts / tw.max(1e-20);
        }
    }
    out
}

/// Step 2: the narrow-range filter across, then down.
pub fn filter(maps: &FluidMaps, params: &ScreenSpaceParams, view: &ScreenView) -> FluidMaps {
    let scale = pixels_per_metre(view);
    let across = filter_pass(maps, params, scale, 1, 0);
    filter_pass(&across, params, scale, 0, 1)
}

/// Steps 1 and 2.
pub fn render(
    view: &ScreenView,
    eye: Vec3,
    params: &ScreenSpaceParams,
    particles: &[[f32; 3]],
) -> FluidMaps {
    filter(&splat(view, eye, (params.radius, params.volume_share), particles, None), params, view)
}

/// The surface under pixel (x, y) of filtered `maps`: its front, or its
/// back (the front carried along the pixel's ray by the thickness: the
/// back of a single layer).
pub fn surface_point(
    view: &ScreenView,
    q: &Mat4,
    maps: &FluidMaps,
    x: u32,
    y: u32,
    back: bool,
) -> Vec3 {
    let i = maps.index(x, y);
    let front = pixel_point(view, q, x as f32 + 0.5, y as f32 + 0.5, maps.depth[i]);
    if !back {
        return front;
    }
    let eye = pixel_point(view, q, x as f32 + 0.5, y as f32 + 0.5, 0.0);
    front + (front - eye).normalize() * maps.thickness[i].max(0.0)
}

/// Step 3: the unit normal of the front (facing the eye) or of the back
/// (facing away) at pixel (x, y) of filtered `maps`; `None` where the
/// pixel is empty. Each difference, across and down, is taken towards the
/// neighbour whose depth is nearer the pixel's (within `threshold`); where
/// either way has none, the normal faces along the view ray.
pub fn normal_at(
    view: &ScreenView,
    q: &Mat4,
    maps: &FluidMaps,
    threshold: f32,
    (x, y): (u32, u32),
    back: bool,
) -> Option<Vec3> {
    let zc = maps.depth[maps.index(x, y)];
    if zc <= 0.0 {
        return None;
    }
    let front = pixel_point(view, q, x as f32 + 0.5, y as f32 + 0.5, zc);
    let ray = (front - pixel_point(view, q, x as f32 + 0.5, y as f32 + 0.5, 0.5 * zc)).normalize();
    let fallback = if back { ray } else { -ray };
    let point = |x, y| surface_point(view, q, maps, x, y, back);
    Some(normal_from(maps, threshold, (x, y), point, fallback))
}

/// The normal at filled pixel (x, y) from the surface's points there and
/// at its neighbours (`point`): the cross product of the differences
/// across and down, each towards the neighbour whose depth is nearer the
/// pixel's (within `threshold`), turned to the side `fallback` faces;
/// `fallback` where either way has none.
fn normal_from(
    maps: &FluidMaps,
    threshold: f32,
    (x, y): (u32, u32),
    point: impl Fn(u32, u32) -> Vec3,
    fallback: Vec3,
) -> Vec3 {
    let zc = maps.depth[maps.index(x, y)];
    let centre = point(x, y);
    let side = |dx: i32, dy: i32| -> Option<Vec3> {
        let mut best: Option<(f32, Vec3)> = None;
        for sign in [-1i32, 1] {
            let (sx, sy) = (x as i32 + sign * dx, y as i32 + sign * dy);
            if sx < 0 || sy < 0 || sx >= maps.width as i32 || sy >= maps.height as i32 {
                continue;
            }
            let z = maps.depth[maps.index(sx as u32, sy as u32)];
            let gap = (z - zc).abs();
            if z <= 0.0 || gap > threshold || best.is_some_and(|(g, _)| g <= gap) {
                continue;
            }
            best = Some((gap, (point(sx as u32, sy as u32) - centre) * sign as f32));
        }
        best.map(|(_, d)| d)
    };
    let n = match (side(1, 0), side(0, 1)) {
        (Some(a), Some(d)) => a.cross(d).normalize_or(fallback),
        _ => fallback,
    };
    if n.dot(fallback) < 0.0 { -n } else { n }
}

/// The liquid seen from the sun: the orthographic light view in which the
/// refractive things' light paths are traced (`passes/water_object`, seed
/// 004), texels addressed as images are (x across, y down). The same
/// three steps make the surface the light enters and leaves, so that the
/// liquid drawn this way casts caustics: the depth is the distance (m)
/// along the light from the view's near plane, and the filter's reach is
/// the same everywhere (no perspective).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunView {
    /// World → clip, orthographic (`projective::sun_view_projection`).
    pub view_proj: Mat4,
    /// Texels per side.
    pub resolution: u32,
}

/// The entering and leaving faces under one texel of a [`SunView`]: unit
/// normals facing the sun (the front) and away from it (the back), and
/// their depths as the light view's z (0 at its near plane, 1 at its far).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunFaces {
    pub front: Vec3,
    pub front_z: f32,
    pub back: Vec3,
    pub back_z: f32,
}

impl SunView {
    /// Texel (x, y)'s ray: its origin on the near plane, the light's unit
    /// direction and the depth (m) the view's z spans.
    pub fn texel_ray(&self, x: f32, y: f32) -> (Vec3, Vec3, f32) {
        let q = self.view_proj.inverse();
        let k = self.resolution as f32;
        let (nx, ny) = (2.0 * x / k - 1.0, 1.0 - 2.0 * y / k);
        let near = q.project_point3(Vec3::new(nx, ny, 0.0));
        let far = q.project_point3(Vec3::new(nx, ny, 1.0));
        let span = (far - near).length();
        (near, (far - near) / span, span)
    }

    /// Texels per metre across the light.
    pub fn texels_per_metre(&self) -> f32 {
        0.5 * self.resolution as f32 * self.view_proj.row(0).truncate().length()
    }

    /// The world point of texel (x, y) (its centre) at depth `t` (m).
    pub fn point(&self, x: u32, y: u32, t: f32) -> Vec3 {
        let (origin, dir, _) = self.texel_ray(x as f32 + 0.5, y as f32 + 0.5);
        origin + dir * t
    }

    /// Step 1 from the sun: each texel's ray through the spheres, the
    /// nearest front's depth and, in the thickness's place, the farthest
    /// back's depth (m from the near plane). (The chords'
    /// sum, the camera's thickness, ripples with the particles' lattice by
    /// ±10%: the exit of a liquid resting on the floor would be now above
    /// it, now below.) Nothing cuts them: the paths stop at the opaque
    /// scene themselves.
    pub fn splat(&self, radius: f32, particles: &[[f32; 3]]) -> FluidMaps {
        let k = self.resolution;
        let mut maps = FluidMaps::empty(k, k);
        let mut back = vec![0.0f32; maps.depth.len()];
        let reach = radius * self.texels_per_metre() + 1.0;
        for p in particles {
            let c = Vec3::from(*p);
            let ndc = self.view_proj.project_point3(c);
            let (cx, cy) = (0.5 * (ndc.x + 1.0) * k as f32, 0.5 * (1.0 - ndc.y) * k as f32);
            let x0 = ((cx - reach).floor().max(0.0)) as u32;
            let y0 = ((cy - reach).floor().max(0.0)) as u32;
            let x1 = ((cx + reach).ceil().min(k as f32 - 1.0)).max(0.0) as u32;
            let y1 = ((cy + reach).ceil().min(k as f32 - 1.0)).max(0.0) as u32;
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let (origin, dir, _) = self.texel_ray(x as f32 + 0.5, y as f32 + 0.5);
                    let Some((t0, t1)) = sphere_chord(origin, dir, c, radius) else { continue };
                    let i = maps.index(x, y);
                    if maps.depth[i] == 0.0 || t0 < maps.depth[i] {
                        maps.depth[i] = t0;
                    }
                    back[i] = back[i].max(t1);
                }
            }
        }
        maps.thickness = back;
        maps
    }

    /// Step 2 from the sun: the narrow-range filter, its reach the same at
    /// every depth; the backs are averaged over the liquid's texels alone
    /// (an empty one has none: counted as 0 it would lift the back near
    /// every outline).
    pub fn filter(&self, maps: &FluidMaps, params: &ScreenSpaceParams) -> FluidMaps {
        let reach = |_| filter_reach(params, self.texels_per_metre(), 1.0);
        let across = filter_pass_by(maps, params, reach, (1, 0), true);
        filter_pass_by(&across, params, reach, (0, 1), true)
    }

    /// Step 3 from the sun: the faces under texel (x, y) of filtered
    /// `maps` (the front at the depth, the back at the second channel's);
    /// `None` where the texel is empty.
    pub fn faces(&self, maps: &FluidMaps, threshold: f32, (x, y): (u32, u32)) -> Option<SunFaces> {
        let i = maps.index(x, y);
        let t = maps.depth[i];
        if t <= 0.0 {
            return None;
        }
        let (_, dir, span) = self.texel_ray(x as f32 + 0.5, y as f32 + 0.5);
        let at = |back: bool| {
            move |x, y| {
                let j = maps.index(x, y);
                let depth = if back { maps.thickness[j].max(maps.depth[j]) } else { maps.depth[j] };
                self.point(x, y, depth)
            }
        };
        Some(SunFaces {
            front: normal_from(maps, threshold, (x, y), at(false), -dir),
            front_z: t / span,
            back: normal_from(maps, threshold, (x, y), at(true), dir),
            back_z: maps.thickness[i].max(t) / span,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(eye: Vec3, target: Vec3, width: u32, height: u32) -> ScreenView {
        let camera =
            crate::camera::Camera { position: eye, look_at: target, up: Vec3::Y, fov_y_deg: 45.0 };
        let view_proj = camera.view_projection(width as f32 / height as f32);
        ScreenView { view_proj, width, height }
    }

    fn params(radius: f32) -> ScreenSpaceParams {
        ScreenSpaceParams {
            radius,
            volume_share: 1.0,
            filter_radius: 3.0 * radius,
            threshold: 4.0 * radius,
            clamp: radius,
        }
    }

    /// One sphere seen head on: the centre pixel is a diameter thick and
    /// its depth is the sphere's front; the thickness summed over the
    /// pixels' footprints (at the sphere's distance) is its volume.
    #[test]
    fn one_sphere_is_its_diameter_thick_and_holds_its_volume() {
        let (eye, r) = (Vec3::new(0.0, 0.0, 2.0), 0.1);
        let view = camera(eye, Vec3::ZERO, 128, 128);
        let maps = splat(&view, eye, (r, 1.0), &[[0.0; 3]], None);
        let i = maps.index(64, 64);
        assert!((maps.thickness[i] - 2.0 * r).abs() < 1e-3, "{}", maps.thickness[i]);
        assert!((maps.depth[i] - (2.0 - r)).abs() < 1e-3, "{}", maps.depth[i]);
        // A pixel's side at distance 2 m; the pixels' rays fan out, so the
        // footprint is taken at the centre's distance (an error of r/2,
        // about 0.1%, in the area's scale).
        let side = 2.0 / pixels_per_metre(&view);
        let volume: f32 = maps.thickness.iter().sum::<f32>() * side * side;
        let exact = 4.0 / 3.0 * std::f32::consts::PI * r * r * r;
        assert!((volume / exact - 1.0).abs() < 0.02, "{volume} m³, a sphere holds {exact} m³");
        // The disc the sphere covers: πr² seen at 2 m (its silhouette is
        // a touch wider, r·d/√(d²−r²)).
        let area = maps.covered() as f32 * side * side;
        let disc = std::f32::consts::PI * r * r * 4.0 / (4.0 - r * r);
        assert!((area / disc - 1.0).abs() < 0.03, "{area} m², disc {disc} m²");
    }

    /// A block of liquid on the particles' lattice (spheres of one spacing,
    /// overlapping) seen end on: its thickness, over a cell's worth of
    /// pixels, is the block's depth, not the spheres' overlap.
    #[test]
    fn a_block_of_particles_is_as_thick_as_the_block() {
        let (eye, s) = (Vec3::new(0.0, 0.0, 2.0), 0.02);
        // Several pixels per cell: the chords' sum varies across a cell
        // (from 0.48 to 1.35 times the block's depth), so the mean is taken
        // over whole cells.
        let view = camera(eye, Vec3::ZERO, 384, 384);
        let mut particles = Vec::new();
        for i in 0..12 {
            for j in 0..12 {
                for k in 0..6 {
                    let at = |n: i32, c: f32| (n as f32 - c) * s;
                    particles.push([at(i, 5.5), at(j, 5.5), at(k, 5.5)]);
                }
            }
        }
        let maps = splat(&view, eye, (s, sphere_share(s, s)), &particles, None);
        // The pixels over the block's middle two cells each way.
        let cell = s * pixels_per_metre(&view) / 2.0;
        let (lo, hi) = ((192.0 - 2.0 * cell).round() as u32, (192.0 + 2.0 * cell).round() as u32);
        let (mut sum, mut n) = (0.0, 0);
        for y in lo..hi {
            for x in lo..hi {
                sum += maps.thickness[maps.index(x, y)];
                n += 1;
            }
        }
        let mean = sum / n as f32;
        assert!((mean / (6.0 * s) - 1.0).abs() < 0.1, "{mean} m, the block is {} m deep", 6.0 * s);
    }

    /// A sphere in front of another: the depth map keeps the nearer front,
    /// the thickness map both chords; a scene nearer than the back sphere
    /// hides it and cuts nothing of the front one.
    #[test]
    fn the_nearer_front_is_kept_and_the_chords_add() {
        let (eye, r) = (Vec3::new(0.0, 0.0, 2.0), 0.1);
        // An odd size, so that the middle pixel's ray is the axis.
        let view = camera(eye, Vec3::ZERO, 63, 63);
        let spheres = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5]];
        let maps = splat(&view, eye, (r, 1.0), &spheres, None);
        let i = maps.index(31, 31);
        assert!((maps.depth[i] - 1.4).abs() < 1e-3);
        assert!((maps.thickness[i] - 4.0 * r).abs() < 2e-3);
        let wall = vec![1.85; 63 * 63];
        let cut = splat(&view, eye, (r, 1.0), &spheres, Some(&wall));
        assert!((cut.depth[i] - 1.4).abs() < 1e-3);
        assert!((cut.thickness[i] - 2.0 * r).abs() < 2e-3);
        // A scene through the front sphere's middle cuts its chord in half.
        let floor = vec![1.5; 63 * 63];
        let half = splat(&view, eye, (r, 1.0), &spheres, Some(&floor));
        assert!((half.thickness[i] - r).abs() < 2e-3, "{}", half.thickness[i]);
    }

    /// The filter keeps what a surface should keep: a flat and a tilted
    /// plane away from their edges, and a step between two layers (the
    /// near layer's edge bends back by at most the clamp, the far layer is
    /// untouched by the near one); noise on a plane is smoothed out.
    #[test]
    fn the_narrow_range_filter_keeps_planes_and_layers_and_smooths_noise() {
        let view = camera(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, 64, 64);
        let p = params(0.01);
        let scale = pixels_per_metre(&view);
        let reach = filter_reach(&p, scale, 2.0);
        assert!((2..16).contains(&reach), "{reach}");
        let mut maps = FluidMaps::empty(64, 64);
        for y in 0..64 {
            for x in 0..64 {
                let i = maps.index(x, y);
                maps.depth[i] = 2.0 + 0.001 * x as f32;
                maps.thickness[i] = 0.3;
            }
        }
        let f = filter(&maps, &p, &view);
        for y in reach..64 - reach {
            for x in reach..64 - reach {
                let i = maps.index(x, y);
                assert!((f.depth[i] - maps.depth[i]).abs() < 1e-5, "{x},{y}");
                assert!((f.thickness[i] - 0.3).abs() < 1e-5);
            }
        }
        // Two layers: left half at 2 m, right half 0.2 m behind.
        let mut step = FluidMaps::empty(64, 64);
        for y in 0..64 {
            for x in 0..64 {
                let i = step.index(x, y);
                step.depth[i] = if x < 32 { 2.0 } else { 2.2 };
            }
        }
        let f = filter(&step, &p, &view);
        for x in 16..48 {
            let z = f.depth[step.index(x, 32)];
            if x < 32 {
                assert!(z >= 2.0 && z <= 2.0 + p.clamp, "near layer at {x}: {z}");
            } else {
                assert!((z - 2.2).abs() < 1e-6, "far layer at {x}: {z}");
            }
        }
        // Noise of ±2 mm on a plane: its spread shrinks more than 2.5 fold
        // (a reach of 2 pixels here).
        let mut noisy = FluidMaps::empty(64, 64);
        let mut seed = 1u32;
        for z in &mut noisy.depth {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            *z = 2.0 + 0.004 * ((seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5);
        }
        let f = filter(&noisy, &p, &view);
        let spread = |d: &[f32]| {
            let inner: Vec<f32> =
                (16..48).flat_map(|y| (16..48).map(move |x| d[y * 64 + x])).collect();
            let mean = inner.iter().sum::<f32>() / inner.len() as f32;
            (inner.iter().map(|z| (z - mean).powi(2)).sum::<f32>() / inner.len() as f32).sqrt()
        };
        let (before, after) = (spread(&noisy.depth), spread(&f.depth));
        assert!(after < 0.4 * before, "spread {before} → {after}");
    }

    /// The normals of a sphere's depth point out of the sphere, front and
    /// back; a plane's are the plane's, to its edge, and a slab's back is
    /// parallel to its front.
    #[test]
    fn normals_from_depth_are_the_surfaces_normals() {
        let eye = Vec3::new(0.0, 0.0, 2.0);
        let view = camera(eye, Vec3::ZERO, 96, 96);
        let q = view.view_proj.inverse();
        let r = 0.3;
        let maps = splat(&view, eye, (r, 1.0), &[[0.0; 3]], None);
        let mut checked = 0;
        for y in 0..96 {
            for x in 0..96 {
                let i = maps.index(x, y);
                if maps.depth[i] <= 0.0 {
                    continue;
                }
                let n = normal_at(&view, &q, &maps, 0.05, (x, y), false).expect("filled");
                let p = pixel_point(&view, &q, x as f32 + 0.5, y as f32 + 0.5, maps.depth[i]);
                let exact = p.normalize();
                // Away from the outline, where the sphere turns away fast.
                if exact.z > 0.5 {
                    assert!(n.dot(exact) > 0.995, "{x},{y}: {n} vs {exact}");
                    // The back, where the ray leaves the ball.
                    let back = normal_at(&view, &q, &maps, 0.05, (x, y), true).expect("filled");
                    let b = surface_point(&view, &q, &maps, x, y, true);
                    assert!((b.length() - r).abs() < 2e-3, "{x},{y}: the back at {b}");
                    assert!(back.dot(b.normalize()) > 0.99, "{x},{y}: {back} vs {}", b.normalize());
                    checked += 1;
                }
            }
        }
        assert!(checked > 500, "{checked}");
        // The plane z = 0 seen at an angle: its normal everywhere.
        let eye = Vec3::new(0.0, 1.0, 2.0);
        let view = camera(eye, Vec3::ZERO, 48, 48);
        let q = view.view_proj.inverse();
        let mut plane = FluidMaps::empty(48, 48);
        let mut slab = FluidMaps::empty(48, 48);
        for y in 0..48 {
            for x in 0..48 {
                let dir = pixel_ray(&view, &q, eye, x, y);
                let t = -eye.z / dir.z;
                let i = plane.index(x, y);
                plane.depth[i] = t * w_per_metre(&view, dir);
                slab.depth[i] = plane.depth[i];
                // The chord through a slab 5 cm thick.
                slab.thickness[i] = 0.05 / -dir.z;
            }
        }
        for (x, y) in [(0, 0), (47, 0), (24, 24), (0, 47), (47, 47)] {
            let n = normal_at(&view, &q, &plane, 0.05, (x, y), false).expect("filled");
            assert!(n.dot(Vec3::Z) > 0.9999, "{x},{y}: {n}");
            // A slab 5 cm thick along every ray: its back is parallel.
            let back = normal_at(&view, &q, &slab, 0.05, (x, y), true).expect("filled");
            assert!(back.dot(-Vec3::Z) > 0.999, "{x},{y}: {back}");
        }
    }

    /// The depth buffer's value back to the clip w.
    #[test]
    fn the_scene_depth_is_its_clip_w() {
        let view = camera(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, 64, 64);
        let q = view.view_proj.inverse();
        let c = view.view_proj * Vec4::new(0.1, -0.2, 0.3, 1.0);
        let w = scene_w(&q, c.x / c.w, c.y / c.w, c.z / c.w);
        assert!((w - c.w).abs() < 1e-4 * c.w, "{w} vs {}", c.w);
        assert_eq!(scene_w(&q, 0.0, 0.0, 0.0), f32::INFINITY);
    }

    fn sun(dir: Vec3, resolution: u32, half: f32) -> SunView {
        let lo = Vec3::splat(-half);
        let view_proj = crate::projective::sun_view_projection(dir.normalize(), lo, -lo);
        SunView { view_proj, resolution }
    }

    /// From the sun, one sphere: the texel over its centre sees its front
    /// and a diameter of it; its faces point at the sun and away.
    #[test]
    fn the_sun_sees_a_sphere_through_its_diameter() {
        let dir = Vec3::new(0.3, 1.0, 0.2).normalize();
        let view = sun(dir, 257, 0.5);
        let r = 0.1;
        let maps = view.splat(r, &[[0.0; 3]]);
        // The centre projects to the middle texel (an odd count).
        let i = maps.index(128, 128);
        let through = maps.thickness[i] - maps.depth[i];
        assert!((through - 2.0 * r).abs() < 1e-3, "{through}");
        let p = view.point(128, 128, maps.depth[i]);
        assert!((p.length() - r).abs() < 1e-3 && p.normalize().dot(dir) > 0.99, "{p}");
        let faces = view.faces(&maps, 0.05, (128, 128)).expect("covered");
        assert!(faces.front.dot(dir) > 0.99, "{}", faces.front);
        assert!(faces.back.dot(-dir) > 0.99, "{}", faces.back);
        assert!(faces.back_z > faces.front_z);
        // Its disc, πr², in texels.
        let side = 1.0 / view.texels_per_metre();
        let area = maps.covered() as f32 * side * side;
        let disc = std::f32::consts::PI * r * r;
        assert!((area / disc - 1.0).abs() < 0.1, "{area} m², disc {disc} m²");
    }

    /// A slab of particles lit at a slant: after the filter its middle is
    /// flat, the light enters through the top (normal up) at the top's
    /// depth, and leaves through the bottom (normal down) after a path as
    /// long as the spheres' union is deep along the light.
    #[test]
    fn the_sun_sees_a_slab_enter_at_its_top_and_leave_at_its_bottom() {
        let dir = Vec3::new(0.4, 1.0, 0.0).normalize();
        let view = sun(dir, 96, 0.6);
        let s = 0.02;
        let mut particles = Vec::new();
        for i in 0..30 {
            for j in 0..5 {
                for k in 0..30 {
                    let at = |n: i32, c: f32| (n as f32 - c) * s;
                    particles.push([at(i, 14.5), at(j, 2.0), at(k, 14.5)]);
                }
            }
        }
        let p = ScreenSpaceParams {
            radius: s,
            volume_share: sphere_share(s, s),
            filter_radius: 3.0 * s,
            threshold: 4.0 * s,
            clamp: s,
        };
        let maps = view.filter(&view.splat(p.radius, &particles), &p);
        let (mut checked, mut path, mut back) = (0, 0.0, Vec3::ZERO);
        for y in 40..56 {
            for x in 40..56 {
                let faces = view.faces(&maps, p.threshold, (x, y)).expect("over the slab");
                assert!(faces.front.dot(Vec3::Y) > 0.99, "{x},{y}: {}", faces.front);
                assert!(faces.back.dot(-Vec3::Y) > 0.97, "{x},{y}: {}", faces.back);
                back += faces.back;
                // The top's spheres: within a radius of the top layer.
                let top = view.point(x, y, maps.depth[maps.index(x, y)]);
                assert!((top.y - 2.0 * s).abs() < 1.2 * s, "{x},{y}: top at {top}");
                let i = maps.index(x, y);
                path += maps.thickness[i] - maps.depth[i];
                checked += 1;
            }
        }
        // From the top layer's spheres' front to the bottom layer's back:
        // four spacings and a diameter, crossed at the sun's slant.
        let expected = (4.0 * s + 2.0 * s) / dir.y;
        let mean = path / checked as f32;
        assert!((mean / expected - 1.0).abs() < 0.1, "{mean} m along the light, {expected} m");
        assert!(back.normalize().dot(-Vec3::Y) > 0.999, "{}", back.normalize());
    }
}
