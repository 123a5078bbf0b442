//! The camera of the viewer and the web page (position, yaw, pitch): keys
//! move it, a pinch or the wheel moves it along the view, and a drag turns
//! it in place (flying) or swings it around the point it looks at
//! (orbiting: `distance` ahead, the scene's `look_at` to begin with).

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
    /// Orbiting: turns swing the camera around its pivot, and the wheel
    /// moves it towards the pivot, never through it.
    pub orbit: bool,
    /// How far ahead the pivot is (m).
    pub distance: f32,
}

/// The nearest the camera comes to its pivot (m).
pub const NEAREST_PIVOT: f32 = 0.2;

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
            orbit: false,
            distance: (c.look_at - c.position).length().max(NEAREST_PIVOT),
        }
    }

    /// The point the camera orbits: `distance` along the view.
    pub fn pivot(&self) -> Vec3 {
        self.position + self.forward() * self.distance
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
    /// Orbiting, the camera swings around its pivot as it turns (turning
    /// right carries it left around the pivot: what is near it follows the
    /// pointer, as if grabbed).
    pub fn turn(&mut self, right: f32, up: f32) {
        let pivot = self.pivot();
        self.yaw += right;
        self.pitch = (self.pitch + up).clamp(-1.5, 1.5);
        if self.orbit {
            self.position = pivot - self.forward() * self.distance;
        }
    }

    /// A drag of (dx, dy) pixels turns the view, 0.003 rad per pixel (or
    /// swings it around the pivot, 0.006 rad per pixel).
    pub fn drag(&mut self, dx: f32, dy: f32) {
        let rate = if self.orbit { 0.006 } else { 0.003 };
        self.turn(dx * rate, -dy * rate);
    }

    /// Move along the view by `metres` (a wheel step, a pinch): flying, the
    /// pivot moves with the camera; orbiting, the camera moves towards its
    /// pivot, a tenth of the way per metre asked, and stops short of it.
    pub fn dolly(&mut self, metres: f32) {
        if self.orbit {
            let pivot = self.pivot();
            let scale = (1.0 - 0.1 * metres).clamp(0.5, 2.0);
            self.distance = (self.distance * scale).max(NEAREST_PIVOT);
            self.position = pivot - self.forward() * self.distance;
        } else {
            self.position += self.forward() * metres;
        }
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

    /// Orbiting keeps the pivot where it was and the camera at its distance,
    /// looking at it; the wheel closes in on it without passing it; back to
    /// flying, a drag turns the camera in place.
    #[test]
    fn orbiting_swings_the_camera_around_the_point_it_looks_at() {
        let scene = Camera {
            position: Vec3::new(3.4, 2.4, 4.6),
            look_at: Vec3::new(-0.2, -0.9, -0.3),
            up: Vec3::Y,
            fov_y_deg: 50.0,
        };
        let mut c = FlyCamera::from_scene(&scene);
        assert!((c.pivot() - scene.look_at).length() < 1e-4);
        c.orbit = true;
        let d = c.distance;
        c.drag(300.0, -120.0);
        c.fly(Motion { turn_right: 1.0, ..Default::default() }, 0.5);
        assert!((c.pivot() - scene.look_at).length() < 1e-4, "{:?}", c.pivot());
        assert!(((c.position - scene.look_at).length() - d).abs() < 1e-4);
        assert!((c.position - scene.position).length() > 1.0, "it moved around");
        let look = c.camera();
        assert!(((look.look_at - look.position).normalize() - c.forward()).length() < 1e-5);
        // Dragging right carries the camera left around the pivot.
        let before = c.position;
        let right = c.forward().cross(Vec3::Y).normalize();
        c.drag(50.0, 0.0);
        assert!((c.position - before).dot(right) < 0.0);
        for _ in 0..100 {
            c.dolly(5.0);
        }
        assert_eq!(c.distance, NEAREST_PIVOT);
        assert!((c.pivot() - scene.look_at).length() < 1e-4);
        c.orbit = false;
        let (at, pivot) = (c.position, c.pivot());
        c.drag(100.0, 0.0);
        assert_eq!(c.position, at, "flying, a drag turns in place");
        assert!((c.pivot() - pivot).length() > 0.01);
    }
}
