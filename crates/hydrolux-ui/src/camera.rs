//! A fly camera (position, yaw, pitch) for the viewer and the web page:
//! keys move it, a drag turns it, a pinch or the wheel moves it along the
//! view.

use glam::Vec3;
use hydrolux_core::camera::Camera;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlyCamera {
    pub position: Vec3,
    /// Heading (rad) from +x towards +z.
    pub yaw: f32,
    /// Elevation (rad), within ±1.5.
    pub pitch: f32,
    pub fov_y_deg: f32,
}

/// Which way to move, from held keys or buttons: each −1, 0 or 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    pub forward: f32,
    pub right: f32,
    pub up: f32,
    /// Turning (arrow keys): yaw and pitch.
    pub turn_right: f32,
    pub turn_up: f32,
    pub fast: bool,
}

impl FlyCamera {
    pub fn from_scene(c: &Camera) -> Self {
        let f = c.forward();
        FlyCamera {
            position: c.position,
            yaw: f.z.atan2(f.x),
            pitch: f.y.clamp(-1.0, 1.0).asin(),
            fov_y_deg: c.fov_y_deg,
        }
    }

    pub fn forward(&self) -> Vec3 {
        Vec3::new(
            self.pitch.cos() * self.yaw.cos(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.sin(),
        )
    }

    pub fn camera(&self) -> Camera {
        Camera {
            position: self.position,
            look_at: self.position + self.forward(),
            up: Vec3::Y,
            fov_y_deg: self.fov_y_deg,
        }
    }

    /// Fly for `dt` seconds: 8 m/s (40 fast) along the view, flat sideways,
    /// and straight up; turn at 1.2 rad/s.
    pub fn fly(&mut self, m: Motion, dt: f32) {
        let speed = if m.fast { 40.0 } else { 8.0 } * dt;
        let f = self.forward();
        let flat = Vec3::new(f.x, 0.0, f.z).normalize_or_zero();
        let right = flat.cross(Vec3::Y);
        self.position += (f * m.forward + right * m.right + Vec3::Y * m.up) * speed;
        self.turn(m.turn_right * 1.2 * dt, m.turn_up * 1.2 * dt);
    }

    /// Turn by angles (rad); the pitch stays short of straight up or down.
    pub fn turn(&mut self, right: f32, up: f32) {
        self.yaw += right;
        self.pitch = (self.pitch + up).clamp(-1.5, 1.5);
    }

    /// A drag of (dx, dy) pixels turns the view, 0.003 rad per pixel.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.turn(dx * 0.003, -dy * 0.003);
    }

    /// Move along the view by `metres` (a wheel step, a pinch).
    pub fn dolly(&mut self, metres: f32) {
        self.position += self.forward() * metres;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_looks_where_the_scene_says_and_flies_along_it() {
        let scene = Camera {
            position: Vec3::new(1.0, 3.0, 2.0),
            look_at: Vec3::new(4.0, 3.0, 6.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
        };
        let mut c = FlyCamera::from_scene(&scene);
        assert!((c.forward() - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-5);
        c.fly(Motion { forward: 1.0, ..Default::default() }, 0.5);
        assert!((c.position - Vec3::new(3.4, 3.0, 5.2)).length() < 1e-4);
        c.drag(0.0, -1e4);
        assert_eq!(c.pitch, 1.5, "clamped short of straight up");
        c.dolly(-2.0);
        assert!(c.camera().forward().dot(c.forward()) > 0.999);
    }
}
