//! The pointer on the water, as in the `pool` demo Hydrolux imitates
//! (evanw/webgl-water): press on the water and drag to draw ripples; press
//! on a moving body and drag to pull it through the water; a key drops the
//! ball in from above. The same in the viewer and the web page.

use glam::Vec3;
use hydrolux::Renderer;
use hydrolux::core::camera::Camera;

/// Crater a pointer press makes (m): radius and depth.
pub const RIPPLE_RADIUS: f32 = hydrolux::core::scene::POINTER_RADIUS;
pub const RIPPLE_STRENGTH: f32 = 0.008;

/// The ray under a point of the view: `ndc` in [−1, 1]² (y up), `aspect`
/// width / height. Returns (origin, unit direction).
pub fn view_ray(camera: &Camera, ndc: [f32; 2], aspect: f32) -> (Vec3, Vec3) {
    let forward = camera.forward();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let t = (0.5 * camera.fov_y_deg.to_radians()).tan();
    let dir = (forward + right * (ndc[0] * t * aspect) + up * (ndc[1] * t)).normalize();
    (camera.position, dir)
}

/// Where the ray meets the mean water level (y = 0), if ahead.
fn on_water(origin: Vec3, dir: Vec3) -> Option<Vec3> {
    let t = -origin.y / dir.y;
    (dir.y.abs() > 1e-6 && t > 0.0 && t < 1e4).then(|| origin + dir * t)
}

enum Grab {
    /// Drawing ripples: where the last crater went.
    Water(Vec3),
    /// Pulling body `index` in the plane facing the camera at `depth` m.
    Body { index: usize, depth: f32, offset: Vec3 },
}

#[derive(Default)]
pub struct Pointer {
    grab: Option<Grab>,
}

impl Pointer {
    /// A press at `ndc`: grabs a body under it, or the water. Returns
    /// whether it grabbed something (else the press is the camera's).
    pub fn press(&mut self, r: &mut Renderer, camera: &Camera, ndc: [f32; 2], aspect: f32) -> bool {
        let (o, d) = view_ray(camera, ndc, aspect);
        let mut nearest: Option<(f32, usize, Vec3)> = None;
        for (i, b) in r.bodies().iter().enumerate() {
            let c = b.pose.position.as_vec3();
            let radius =
                r.scene().objects[b.object].scale.iter().fold(0.0f32, |m, s| m.max(s.abs())) * 0.5;
            let oc = o - c;
            let bq = oc.dot(d);
            let disc = bq * bq - (oc.length_squared() - radius * radius);
            if disc >= 0.0 {
                let t = -bq - disc.sqrt();
                if t > 0.0 && nearest.is_none_or(|n| t < n.0) {
                    nearest = Some((t, i, c));
                }
            }
        }
        if let Some((t, index, c)) = nearest {
            let hit = o + d * t;
            let depth = (hit - o).dot(camera.forward());
            self.grab = Some(Grab::Body { index, depth, offset: c - hit });
            return true;
        }
        if let Some(p) = on_water(o, d)
            && r.disturb(p.x, p.z, RIPPLE_RADIUS, RIPPLE_STRENGTH)
        {
            self.grab = Some(Grab::Water(p));
            return true;
        }
        false
    }

    /// The pointer moved to `ndc` while pressed.
    pub fn drag(&mut self, r: &mut Renderer, camera: &Camera, ndc: [f32; 2], aspect: f32) {
        let (o, d) = view_ray(camera, ndc, aspect);
        match &mut self.grab {
            Some(Grab::Water(last)) => {
                let Some(p) = on_water(o, d) else { return };
                // Craters along the stroke, about a radius apart.
                let steps = ((p - *last).length() / RIPPLE_RADIUS).ceil().clamp(1.0, 16.0) as usize;
                for s in 1..=steps {
                    let q = last.lerp(p, s as f32 / steps as f32);
                    r.disturb(q.x, q.z, RIPPLE_RADIUS, RIPPLE_STRENGTH / steps.min(4) as f32);
                }
                *last = p;
            }
            Some(Grab::Body { index, depth, offset }) => {
                let t = *depth / d.dot(camera.forward()).max(1e-3);
                r.pull_body(*index, o + d * t + *offset);
            }
            None => {}
        }
    }

    pub fn release(&mut self) {
        self.grab = None;
    }

    pub fn grabbing(&self) -> bool {
        self.grab.is_some()
    }
}

/// Drop the first moving body in from a metre above the water under
/// `ndc` (or above where it is, if that misses the water).
pub fn drop_ball(r: &mut Renderer, camera: &Camera, ndc: [f32; 2], aspect: f32) -> bool {
    let Some(first) = r.bodies().first().map(|b| b.pose.position.as_vec3()) else { return false };
    let (o, d) = view_ray(camera, ndc, aspect);
    let above = on_water(o, d).unwrap_or(first);
    r.place_body(0, Vec3::new(above.x, 1.0, above.z));
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_of_the_view_looks_along_the_camera() {
        let cam = Camera {
            position: Vec3::new(0.0, 2.0, 3.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 60.0,
        };
        let (o, d) = view_ray(&cam, [0.0, 0.0], 1.5);
        assert!((d - cam.forward()).length() < 1e-6 && o == cam.position);
        let p = on_water(o, d).unwrap();
        assert!(p.length() < 1e-5, "the view's centre is the look-at point: {p}");
        // The top edge of the view is half the field of view above the axis.
        let (_, top) = view_ray(&cam, [0.0, 1.0], 1.5);
        assert!((top.angle_between(d).to_degrees() - 30.0).abs() < 1e-3);
    }
}
