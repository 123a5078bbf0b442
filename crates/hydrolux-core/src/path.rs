//! Scripted paths for kinematic bodies (`[objects.path]`): a boat that
//! turns, a buoy towed round a loop. Waypoints are joined by a cubic
//! Hermite spline in time whose tangents are Catmull–Rom's (the chord
//! through the neighbours over their time apart, in m/s), so the position
//! passes through every waypoint at its time and the velocity is
//! continuous: a hull that turns sheds a curved wake, not the burst of
//! waves a corner's instant change of velocity would. The body turns with
//! its path: its yaw follows the heading of its velocity (see
//! `bodies::BodyWorld`).

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// A path as a scene gives it: waypoints and either their times or a speed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PathDesc {
    /// World positions (m) of the object's centre, at least 2.
    pub points: Vec<[f32; 3]>,
    /// The time (s) it passes each point, increasing from 0; or empty, with `speed`.
    pub times: Vec<f32>,
    /// Speed (m/s) along the waypoints' chords, when no `times` are given.
    pub speed: f32,
    /// Back from the last point to the first and round again, forever;
    /// otherwise the object stops at the last point.
    pub closed: bool,
}

impl Default for PathDesc {
    fn default() -> Self {
        PathDesc { points: Vec::new(), times: Vec::new(), speed: 0.0, closed: false }
    }
}

/// Why a path cannot be followed: (what is wrong, what is allowed).
pub type PathError = (String, String);

impl PathDesc {
    /// The path, or what is wrong with it.
    pub fn build(&self) -> Result<KinematicPath, PathError> {
        let n = self.points.len();
        if !(2..=256).contains(&n) {
            return Err((format!("{n} points"), "2 to 256 points".into()));
        }
        if let Some(p) =
            self.points.iter().find(|p| !p.iter().all(|c| c.is_finite() && c.abs() <= 1e5))
        {
            return Err((format!("point {p:?}"), "finite points within ±100000 m".into()));
        }
        let points: Vec<DVec3> =
            self.points.iter().map(|p| DVec3::from(p.map(|c| c as f64))).collect();
        // Knots: one per point, and for a closed path one more, back at the first.
        let legs = if self.closed { n } else { n - 1 };
        let chord = |k: usize| (points[(k + 1) % n] - points[k]).length();
        let times: Vec<f64> = match (self.times.is_empty(), self.speed) {
            (false, s) if s != 0.0 => {
                return Err((
                    format!("times and speed {s}"),
                    "either times or a speed, not both".into(),
                ));
            }
            (false, _) => {
                let want = if self.closed { n + 1 } else { n };
                if self.times.len() != want {
                    return Err((
                        format!("{} times for {n} points", self.times.len()),
                        format!(
                            "one time per point{} ({want})",
                            if self.closed { " and one for the return to the first" } else { "" }
                        ),
                    ));
                }
                let t: Vec<f64> = self.times.iter().map(|&t| t as f64).collect();
                if t[0] != 0.0
                    || t.windows(2)
                        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
                    || !t[want - 1].is_finite()
                {
                    return Err((
                        format!("times {:?}", self.times),
                        "increasing times from 0 s".into(),
                    ));
                }
                t
            }
            (true, s) if s > 0.0 && s <= 1000.0 => {
                let mut t = vec![0.0];
                for k in 0..legs {
                    let d = chord(k);
                    if d <= 0.0 {
                        return Err((
                            format!("points {k} and {} the same", (k + 1) % n),
                            "distinct successive points".into(),
                        ));
                    }
                    t.push(t[k] + d / s as f64);
                }
                t
            }
            (true, s) => {
                return Err((
                    format!("speed {s}"),
                    "times, or a speed of 0 to 1000 m/s (not 0)".into(),
                ));
            }
        };
        Ok(KinematicPath { points, times, closed: self.closed })
    }
}

/// A path ready to evaluate: knots `times` (one per point, and one more
/// for a closed path's return), in seconds from 0.
#[derive(Clone, Debug, PartialEq)]
pub struct KinematicPath {
    points: Vec<DVec3>,
    times: Vec<f64>,
    closed: bool,
}

impl KinematicPath {
    /// The time (s) one round of a closed path takes, or the time an open
    /// one reaches its last point.
    pub fn duration(&self) -> f64 {
        *self.times.last().unwrap()
    }

    fn point(&self, k: usize) -> DVec3 {
        self.points[k % self.points.len()]
    }

    /// Catmull–Rom's tangent (m/s) at knot k: the chord through its
    /// neighbours over their time apart; an open path's ends take their
    /// one chord.
    fn tangent(&self, k: usize) -> DVec3 {
        let last = self.times.len() - 1;
        if self.closed {
            // Knot `last` is knot 0 again, one period on.
            let period = self.duration();
            let k = k % last;
            let (prev, t_prev) = if k == 0 {
                (last - 1, self.times[last - 1] - period)
            } else {
                (k - 1, self.times[k - 1])
            };
            return (self.point(k + 1) - self.point(prev)) / (self.times[k + 1] - t_prev);
        }
        let (a, b) = (k.saturating_sub(1), (k + 1).min(last));
        (self.point(b) - self.point(a)) / (self.times[b] - self.times[a])
    }

    /// Position (m) and velocity (m/s) at time `t` (s).
    pub fn at(&self, t: f64) -> (DVec3, DVec3) {
        let end = self.duration();
        let t = if self.closed {
            t.rem_euclid(end)
        } else if t >= end {
            return (self.point(self.times.len() - 1), DVec3::ZERO);
        } else if t < 0.0 {
            return (self.points[0], DVec3::ZERO);
        } else {
            t
        };
        let k = self.times.partition_point(|&x| x <= t).clamp(1, self.times.len() - 1) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let h = t1 - t0;
        let u = (t - t0) / h;
        let (p0, p1) = (self.point(k), self.point(k + 1));
        let (m0, m1) = (self.tangent(k) * h, self.tangent(k + 1) * h);
        let (u2, u3) = (u * u, u * u * u);
        let position = p0 * (2.0 * u3 - 3.0 * u2 + 1.0)
            + m0 * (u3 - 2.0 * u2 + u)
            + p1 * (-2.0 * u3 + 3.0 * u2)
            + m1 * (u3 - u2);
        let velocity = (p0 * (6.0 * u2 - 6.0 * u)
            + m0 * (3.0 * u2 - 4.0 * u + 1.0)
            + p1 * (-6.0 * u2 + 6.0 * u)
            + m1 * (3.0 * u2 - 2.0 * u))
            / h;
        (position, velocity)
    }

    /// The heading (rad, about +y, from +x towards −z as yaw turns) of
    /// the velocity at `t`, or `None` where it stands still.
    pub fn heading(&self, t: f64) -> Option<f64> {
        let (_, v) = self.at(t);
        (v.x * v.x + v.z * v.z > 1e-12).then(|| (-v.z).atan2(v.x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(closed: bool) -> PathDesc {
        PathDesc {
            points: vec![[0.0, 0.3, 0.0], [10.0, 0.3, 0.0], [10.0, 0.3, -10.0], [0.0, 0.3, -10.0]],
            closed,
            speed: 5.0,
            ..Default::default()
        }
    }

    /// It passes each waypoint at its time; between, its velocity is the
    /// position's derivative; across a waypoint it does not jump.
    #[test]
    fn a_path_passes_its_points_at_their_times_with_a_continuous_velocity() {
        let desc = PathDesc {
            points: vec![[0.0, 0.0, 0.0], [4.0, 0.0, 1.0], [6.0, 1.0, 5.0], [2.0, 0.0, 9.0]],
            times: vec![0.0, 1.5, 2.5, 5.0],
            ..Default::default()
        };
        let path = desc.build().unwrap();
        for (p, &t) in desc.points.iter().zip(&desc.times) {
            let (at, _) = path.at(t as f64 - 1e-9);
            assert!(at.distance(DVec3::from(p.map(|c| c as f64))) < 1e-6, "{t}: {at}");
        }
        for k in 1..200 {
            let t = k as f64 * 0.025;
            let h = 1e-5;
            let numeric = (path.at(t + h).0 - path.at(t - h).0) / (2.0 * h);
            assert!(numeric.distance(path.at(t).1) < 1e-4, "{t}: {numeric} vs {}", path.at(t).1);
        }
        for &t in &desc.times[1..3] {
            let (before, after) = (path.at(t as f64 - 1e-9).1, path.at(t as f64 + 1e-9).1);
            assert!(before.distance(after) < 1e-6, "at {t}: {before} then {after}");
        }
        // Past its end it rests at the last point.
        assert_eq!(path.at(9.0), (DVec3::new(2.0, 0.0, 9.0), DVec3::ZERO));
    }

    /// A closed loop at a speed comes round in perimeter / speed, again
    /// and again, smooth where it closes, its mean speed the speed asked.
    #[test]
    fn a_closed_loop_at_a_speed_repeats_at_perimeter_over_speed() {
        let path = square(true).build().unwrap();
        assert!((path.duration() - 40.0 / 5.0).abs() < 1e-12);
        for t in [0.0, 1.3, 5.7] {
            assert!(path.at(t).0.distance(path.at(t + 3.0 * path.duration()).0) < 1e-9);
        }
        let (before, after) = (path.at(8.0 - 1e-9).1, path.at(8.0 + 1e-9).1);
        assert!(before.distance(after) < 1e-6, "{before} {after}");
        let n = 8000;
        let dt = path.duration() / n as f64;
        let length: f64 = (0..n).map(|k| path.at((k as f64 + 0.5) * dt).1.length() * dt).sum();
        let mean = length / path.duration();
        // The spline cuts the square's corners a little.
        assert!((mean - 5.0).abs() < 0.1 * 5.0, "mean speed {mean}");
        // Heading, mid-leg: along +x first, then towards −z (a quarter
        // turn left); at a corner it is half way between.
        assert!(path.heading(1.0).unwrap().abs() < 1e-9);
        assert!((path.heading(2.0).unwrap() - std::f64::consts::FRAC_PI_4).abs() < 1e-9);
        assert!((path.heading(3.0).unwrap() - std::f64::consts::FRAC_PI_2).abs() < 0.05);
        // An open path stands still past its end, with no heading.
        assert_eq!(square(false).build().unwrap().heading(100.0), None);
    }

    #[test]
    fn bad_paths_say_what_is_allowed() {
        let one = PathDesc { points: vec![[0.0; 3]], speed: 1.0, ..Default::default() };
        assert!(one.build().unwrap_err().1.contains("2 to 256"));
        let both = PathDesc { times: vec![0.0, 1.0, 2.0, 3.0], ..square(false) };
        assert!(both.build().unwrap_err().1.contains("not both"));
        let backwards = PathDesc { times: vec![0.0, 2.0, 1.0, 3.0], speed: 0.0, ..square(false) };
        assert!(backwards.build().unwrap_err().1.contains("increasing"));
        let short = PathDesc { times: vec![0.0, 2.0, 3.0, 4.0], speed: 0.0, ..square(true) };
        assert!(short.build().unwrap_err().1.contains("return to the first"));
        let still = PathDesc { speed: 0.0, ..square(false) };
        assert!(still.build().unwrap_err().1.contains("speed"));
        let repeated =
            PathDesc { points: vec![[1.0; 3], [1.0; 3]], speed: 1.0, ..Default::default() };
        assert!(repeated.build().unwrap_err().1.contains("distinct"));
    }
}
