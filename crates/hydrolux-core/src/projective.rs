//! Projective texture mapping for local reflections and refractions (seed 000
//! §3.1.3 and §4.4, after Jensen & Goliáš; seed 002 §3 and §5).
//!
//! The reflection texture is the scene above the water, mirrored about the
//! mean water plane y = 0 and rendered by the main camera with a widened field
//! of view (waves reveal texels just outside the screen). The refraction
//! texture is the scene below the water, seen by the same widened camera. The
//! water shader finds where its reflected (refracted) ray meets a plane above
//! (below) the surface and projects that point into the texture. These are
//! the CPU twins of those lookups (`shaders/projective.wgsl`).

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Reflection about the mean water plane y = 0 (an involution, det = −1, so
/// mirrored triangles wind the other way).
pub fn mirror_matrix() -> Mat4 {
    Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0))
}

/// A clip plane: points with `plane.xyz · p + plane.w ≥ 0` are kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipPlane(pub Vec4);

impl ClipPlane {
    /// Keep what is above y = `height` (the reflection pass).
    pub fn above(height: f32) -> Self {
        ClipPlane(Vec4::new(0.0, 1.0, 0.0, -height))
    }
    /// Keep what is below y = `height` (the refraction pass).
    pub fn below(height: f32) -> Self {
        ClipPlane(Vec4::new(0.0, -1.0, 0.0, height))
    }
    /// Keep everything (the main view).
    pub fn none() -> Self {
        ClipPlane(Vec4::new(0.0, 0.0, 0.0, 1.0))
    }
    pub fn keeps(&self, p: Vec3) -> bool {
        self.0.truncate().dot(p) + self.0.w >= 0.0
    }
}

/// Scale of tan(fov/2) for a field of view widened by `margin` (0.5 = 50% more
/// image on every side's half-extent, seed 002 §3).
pub fn widened_projection_scale(margin: f32) -> f32 {
    1.0 + margin
}

/// Clip space → texture coordinates ([0, 1]², v down); `None` behind the camera.
pub fn clip_to_uv(clip: Vec4) -> Option<Vec2> {
    (clip.w > 1e-6).then(|| Vec2::new(0.5 + 0.5 * clip.x / clip.w, 0.5 - 0.5 * clip.y / clip.w))
}

/// Where the reflection texture (rendered with `view_proj` applied to the
/// mirrored scene) is read for a surface point `p` whose reflected ray is `r`:
/// the ray meets the plane y = `height` at Q (above the surface for a viewer
/// in air, below it for one in the water), and Q's mirror image is projected.
/// Rays parallel to the plane are followed `max_distance`.
pub fn reflection_uv(
    view_proj: &Mat4,
    p: Vec3,
    r: Vec3,
    height: f32,
    max_distance: f32,
) -> Option<Vec2> {
    let t = if r.y.abs() > 1e-4 {
        ((height - p.y) / r.y).clamp(0.0, max_distance)
    } else {
        max_distance
    };
    let q = p + r * t;
    clip_to_uv(*view_proj * mirror_matrix() * q.extend(1.0))
}

/// Where the refraction texture (rendered with `view_proj`) is read for a
/// surface point `p` whose refracted ray is `t_dir` (pointing down): where the
/// ray meets the plane y = −`depth` (seed 000 §4.4).
pub fn refraction_uv_plane(
    view_proj: &Mat4,
    p: Vec3,
    t_dir: Vec3,
    depth: f32,
    max_distance: f32,
) -> Option<Vec2> {
    let t = if t_dir.y < -1e-4 {
        ((p.y + depth) / -t_dir.y).clamp(0.0, max_distance)
    } else {
        max_distance
    };
    clip_to_uv(*view_proj * (p + t_dir * t).extend(1.0))
}

/// Seed 002 eq. 1: W = U + dv·R, with dv the distance from the surface to
/// what the refraction texture shows behind it, clamped to `max_dv`.
pub fn refraction_uv_depth(
    view_proj: &Mat4,
    p: Vec3,
    t_dir: Vec3,
    dv: f32,
    max_dv: f32,
) -> Option<Vec2> {
    clip_to_uv(*view_proj * (p + t_dir * dv.clamp(0.0, max_dv)).extend(1.0))
}

/// The sun's shadow space, bent by refraction (twin of
/// `shaders/shadow_space.wgsl`): a point `depth` = −y below the mean surface
/// is moved back up the refracted beam (`travel`, pointing down) to its entry
/// point, then down the unrefracted beam (`-sun_dir`) to the same depth. An
/// orthographic projection along the sun then gives every point on one
/// refracted beam the same texel (exact for a flat surface).
pub fn shadow_space(world: Vec3, sun_dir: Vec3, travel: Vec3) -> Vec3 {
    let d = (-world.y).max(0.0);
    let entry = world - travel * (d / (-travel.y).max(1e-3));
    entry - sun_dir * (d / sun_dir.y.max(1e-3))
}

/// Orthographic light view-projection along `sun_dir` covering the box
/// [min, max] (depth 0 nearest the sun, 1 farthest).
pub fn sun_view_projection(sun_dir: Vec3, min: Vec3, max: Vec3) -> Mat4 {
    let centre = 0.5 * (min + max);
    let radius = (0.5 * (max - min)).length().max(1e-3);
    let up = if sun_dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = glam::camera::rh::view::look_at_mat4(centre + sun_dir * 2.0 * radius, centre, up);
    glam::camera::rh::proj::directx::orthographic(
        -radius,
        radius,
        -radius,
        radius,
        radius * 0.5,
        radius * 3.5,
    ) * view
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::optics::{reflect, refract};

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(1.0, 4.0, 6.0),
            look_at: Vec3::new(0.0, 0.0, -10.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
        }
    }

    #[test]
    fn refracted_beam_shares_its_shadow_texel() {
        let sun = crate::sky::sun_direction(35.0, 20.0);
        let travel = refract(-sun, Vec3::Y, 1.0, 1.333).unwrap();
        let vp = sun_view_projection(sun, Vec3::splat(-20.0), Vec3::splat(20.0));
        let entry = Vec3::new(2.0, 0.0, -3.0);
        let texel = |p: Vec3| (vp * shadow_space(p, sun, travel).extend(1.0)).truncate().truncate();
        for depth in [0.5f32, 3.0, 9.0] {
            let under = entry + travel * (depth / -travel.y);
            assert!((texel(under) - texel(entry)).length() < 1e-5, "depth {depth}");
            // Depth along the light still grows down the beam (occlusion order).
            let z = |p: Vec3| (vp * shadow_space(p, sun, travel).extend(1.0)).z;
            assert!(z(under) > z(entry));
        }
        // Above the water nothing moves.
        let above = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(shadow_space(above, sun, travel), above);
        // The box fits inside the light's clip volume.
        for c in [Vec3::splat(-20.0), Vec3::splat(20.0), Vec3::new(20.0, -20.0, 20.0)] {
            let p = vp * c.extend(1.0);
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z), "{p}");
        }
    }

    #[test]
    fn mirror_is_an_orientation_reversing_involution() {
        let m = mirror_matrix();
        assert!((m * m).abs_diff_eq(Mat4::IDENTITY, 0.0));
        assert_eq!(m.determinant(), -1.0);
        assert_eq!(m.transform_point3(Vec3::new(1.0, 2.0, 3.0)), Vec3::new(1.0, -2.0, 3.0));
    }

    #[test]
    fn clip_planes_split_at_the_water() {
        let (up, down) = (Vec3::new(3.0, 0.5, -2.0), Vec3::new(3.0, -0.5, -2.0));
        assert!(ClipPlane::above(0.0).keeps(up) && !ClipPlane::above(0.0).keeps(down));
        assert!(ClipPlane::below(0.0).keeps(down) && !ClipPlane::below(0.0).keeps(up));
        assert!(
            !ClipPlane::below(0.2).keeps(Vec3::new(0.0, 0.3, 0.0))
                && ClipPlane::below(0.2).keeps(Vec3::new(0.0, 0.1, 0.0))
        );
        // Mirroring maps the kept half of the reflection pass below the water.
        assert!(!ClipPlane::above(0.0).keeps(mirror_matrix().transform_point3(up)));
        assert!(ClipPlane::none().keeps(Vec3::splat(-1e6)));
    }

    #[test]
    fn flat_water_reflects_exactly_whatever_the_plane_height() {
        let cam = camera();
        let vp = cam.view_projection(1.5);
        // A point above the water and where the camera sees its mirror image.
        let x = Vec3::new(-2.0, 3.0, -14.0);
        let image = mirror_matrix().transform_point3(x);
        let d = (image - cam.position).normalize();
        let p = cam.position + d * (cam.position.y / -d.y);
        assert!(p.y.abs() < 1e-4);
        let r = reflect(d, Vec3::Y);
        let want = clip_to_uv(vp * image.extend(1.0)).unwrap();
        for h in [0.5, 3.0, 20.0] {
            let uv = reflection_uv(&vp, p, r, h, 1e4).unwrap();
            assert!((uv - want).length() < 1e-4, "plane {h}: {uv} vs {want}");
        }
    }

    #[test]
    fn from_below_flat_water_mirrors_the_scene_under_it() {
        // A viewer under the water sees an underwater point's mirror image
        // (total internal reflection) where the mirrored point projects.
        let cam = Camera {
            position: Vec3::new(0.0, -3.0, 6.0),
            look_at: Vec3::new(0.0, 0.0, -10.0),
            up: Vec3::Y,
            fov_y_deg: 60.0,
        };
        let vp = cam.view_projection(1.5);
        let x = Vec3::new(1.0, -2.0, -12.0);
        let image = mirror_matrix().transform_point3(x);
        let d = (image - cam.position).normalize();
        let p = cam.position + d * (-cam.position.y / d.y);
        let want = clip_to_uv(vp * image.extend(1.0)).unwrap();
        for h in [-0.5, -2.0, -8.0] {
            let uv = reflection_uv(&vp, p, reflect(d, Vec3::NEG_Y), h, 1e4).unwrap();
            assert!((uv - want).length() < 1e-4, "plane {h}: {uv} vs {want}");
        }
    }

    #[test]
    fn a_tilted_normal_moves_the_lookup() {
        let cam = camera();
        let vp = cam.view_projection(1.5);
        let p = Vec3::new(0.0, 0.0, -8.0);
        let d = (p - cam.position).normalize();
        let flat = reflection_uv(&vp, p, reflect(d, Vec3::Y), 2.0, 1e4).unwrap();
        let n = Vec3::new(0.1, 1.0, 0.0).normalize();
        let tilted = reflection_uv(&vp, p, reflect(d, n), 2.0, 1e4).unwrap();
        assert!((tilted - flat).length() > 0.01);
        // Refraction through flat water, plane and depth estimates agree when
        // dv is the true distance to the plane.
        let t = refract(d, Vec3::Y, 1.0, 1.333).unwrap();
        let a = refraction_uv_plane(&vp, p, t, 2.0, 1e4).unwrap();
        let b = refraction_uv_depth(&vp, p, t, 2.0 / -t.y, 100.0).unwrap();
        assert!((a - b).length() < 1e-5);
        // Refraction bends towards the vertical: the ray meets the plane
        // nearer the camera than a straight one, lower on screen (larger v).
        let straight = clip_to_uv(vp * (p + d * (2.0 / -d.y)).extend(1.0)).unwrap();
        assert!(a.y > straight.y, "{a} vs {straight}");
    }
}
