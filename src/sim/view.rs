//! The camera of one frame: pose, lens and window, and the view volume (SPEC §2's camera:
//! position, yaw and pitch, `fovy`, a window of w × h pixels, near and far planes). It is not a
//! renderer's camera: it builds no projection matrix (the preview builds its own) and decides
//! nothing about a mesh; the runner, the audit and the algorithms ask it questions.
//!
//! Conventions (SPEC §2): right-handed world, z up, metres. Yaw is measured in the xy-plane from
//! +x towards +y; pitch is up from the horizontal. The camera's right vector is horizontal
//! (sin yaw, −cos yaw, 0) whatever the pitch, so looking straight down is well defined. All
//! camera arithmetic is `f64` and eye-relative (points are translated by −eye before any product),
//! so terrains far from the origin keep their precision; the runner builds the camera from a
//! pose already in the terrain's local frame.
//!
//! Two kinds of test against the view volume: [`Camera::sees`] decides for a point (the audit's
//! samples in view), while [`Camera::may_see_triangle`] and [`Camera::surely_misses_box`] are
//! conservative, answering "outside" only when every corner is outside one plane, so they may keep
//! what a point test would reject but never drop what it would keep.

use glam::{DVec2, DVec3};

/// Where the camera is and where it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub position: DVec3,
    /// Radians, from +x towards +y.
    pub yaw: f64,
    /// Radians, up from the horizontal; within [−π/2, π/2].
    pub pitch: f64,
}

impl Pose {
    /// The unit look direction: (cos pitch · cos yaw, cos pitch · sin yaw, sin pitch).
    pub fn forward(&self) -> DVec3 {
        let (sin_yaw, cos_yaw) = self.yaw.sin_cos();
        let (sin_pitch, cos_pitch) = self.pitch.sin_cos();
        DVec3::new(cos_pitch * cos_yaw, cos_pitch * sin_yaw, sin_pitch)
    }
}

/// The window and lens shared by every frame of an experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSettings {
    pub width_px: u32,
    pub height_px: u32,
    /// Vertical field of view in radians, in (0, π).
    pub fovy: f64,
    /// Near and far plane distances along the view direction, 0 < near < far.
    pub near: f64,
    pub far: f64,
}

impl ViewSettings {
    /// The angle one pixel subtends vertically (Wu's fovy/h), in radians.
    pub fn pixel_angle(&self) -> f64 {
        self.fovy / f64::from(self.height_px)
    }

    /// Pixels per unit of image-plane distance at focal length 1: (h/2)/tan(fovy/2).
    pub fn pixels_per_unit(&self) -> f64 {
        0.5 * f64::from(self.height_px) / (0.5 * self.fovy).tan()
    }

    pub fn aspect(&self) -> f64 {
        f64::from(self.width_px) / f64::from(self.height_px)
    }
}

/// A posed camera with its view volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub settings: ViewSettings,
    tan_half_fovy: f64,
    tan_half_fovx: f64,
    /// [`ViewSettings::pixels_per_unit`], computed once per camera rather than as a tangent per
    /// projection: every projection of a frame uses the same lens.
    pixels_per_unit: f64,
}

impl Camera {
    pub fn new(pose: &Pose, settings: ViewSettings) -> Camera {
        let (sin_yaw, cos_yaw) = pose.yaw.sin_cos();
        let forward = pose.forward();
        let right = DVec3::new(sin_yaw, -cos_yaw, 0.0);
        let up = right.cross(forward);
        let tan_half_fovy = (0.5 * settings.fovy).tan();
        Camera {
            eye: pose.position,
            forward,
            right,
            up,
            settings,
            tan_half_fovy,
            tan_half_fovx: tan_half_fovy * settings.aspect(),
            pixels_per_unit: settings.pixels_per_unit(),
        }
    }

    /// Camera-space coordinates (right, up, depth) of a world point.
    pub fn to_camera(&self, world: DVec3) -> DVec3 {
        let d = world - self.eye;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// Camera-space image of a world direction (no translation).
    pub fn direction_to_camera(&self, direction: DVec3) -> DVec3 {
        DVec3::new(
            direction.dot(self.right),
            direction.dot(self.up),
            direction.dot(self.forward),
        )
    }

    /// Pixel coordinates (from the image centre, y up) of a camera-space point in front of the
    /// near plane, or `None` behind it.
    pub fn project_camera(&self, c: DVec3) -> Option<DVec2> {
        (c.z >= self.settings.near).then(|| DVec2::new(c.x / c.z, c.y / c.z) * self.pixels_per_unit)
    }

    /// [`ViewSettings::pixels_per_unit`], as [`Camera::project_camera`] uses it.
    pub fn pixels_per_unit(&self) -> f64 {
        self.pixels_per_unit
    }

    /// Whether a world point lies inside the view volume (frustum between near and far).
    pub fn sees(&self, world: DVec3) -> bool {
        self.sees_camera(self.to_camera(world))
    }

    /// [`Camera::sees`] for a point already in camera coordinates ([`Camera::to_camera`]).
    #[inline]
    pub fn sees_camera(&self, c: DVec3) -> bool {
        c.z >= self.settings.near
            && c.z <= self.settings.far
            && c.x.abs() <= c.z * self.tan_half_fovx
            && c.y.abs() <= c.z * self.tan_half_fovy
    }

    /// tan(fovx/2) and tan(fovy/2), as [`Camera::sees`] uses them (computed once per camera).
    pub fn tan_half_fov(&self) -> (f64, f64) {
        (self.tan_half_fovx, self.tan_half_fovy)
    }

    /// Whether every point of the axis-aligned box `[low, high]` surely fails [`Camera::sees`]:
    /// all eight corners lie outside one plane of the view volume by more than a margin that
    /// covers the rounding of `sees` (so no point of the box, evaluated as `sees` evaluates it,
    /// can pass). `false` means "maybe seen". Used to skip whole tiles of samples exactly.
    pub fn surely_misses_box(&self, low: DVec3, high: DVec3) -> bool {
        let corners = [0, 1, 2, 3, 4, 5, 6, 7].map(|k: u32| {
            let pick = |bit: u32, a: f64, b: f64| if k & (1 << bit) == 0 { a } else { b };
            DVec3::new(
                pick(0, low.x, high.x),
                pick(1, low.y, high.y),
                pick(2, low.z, high.z),
            )
        });
        let c = corners.map(|p| self.to_camera(p));
        // Rounding of sees() is about 1e-16 of the coordinates' magnitude; the margin is far
        // above it and far below anything that matters for which tiles are skipped.
        let magnitude = corners
            .iter()
            .map(|p| (*p - self.eye).abs().max_element())
            .fold(self.eye.abs().max_element(), f64::max);
        let margin = 1e-9 * (1.0 + magnitude) * (1.0 + self.tan_half_fovx + self.tan_half_fovy);
        let (tx, ty) = (self.tan_half_fovx, self.tan_half_fovy);
        let (near, far) = (self.settings.near, self.settings.far);
        let planes: [&dyn Fn(DVec3) -> f64; 6] = [
            &|p| p.z - near,
            &|p| far - p.z,
            &|p| p.z * tx - p.x,
            &|p| p.z * tx + p.x,
            &|p| p.z * ty - p.y,
            &|p| p.z * ty + p.y,
        ];
        planes
            .iter()
            .any(|inside| c.iter().all(|&p| inside(p) < -margin))
    }

    /// The view volume seen from above: the convex hull, counter-clockwise, of its eight
    /// corners (near and far planes) projected onto the horizontal plane, in the camera's
    /// coordinates (world or local, as its pose was). What a map draws as the frustum's
    /// footprint; it reaches out to the far plane, so a caller clips it to what it shows.
    pub fn footprint(&self) -> Vec<DVec2> {
        let (tx, ty) = (self.tan_half_fovx, self.tan_half_fovy);
        let mut corners = Vec::with_capacity(8);
        for depth in [self.settings.near, self.settings.far] {
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = self.eye
                    + self.forward * depth
                    + self.right * (sx * tx * depth)
                    + self.up * (sy * ty * depth);
                corners.push(p.truncate());
            }
        }
        convex_hull(corners)
    }

    /// Conservative test of a triangle against the view volume: `false` only when all three
    /// corners are outside one of the six planes (so the triangle is surely outside).
    pub fn may_see_triangle(&self, corners: [DVec3; 3]) -> bool {
        let c = corners.map(|p| self.to_camera(p));
        let all = |outside: &dyn Fn(DVec3) -> bool| c.iter().all(|&p| outside(p));
        let (tx, ty) = (self.tan_half_fovx, self.tan_half_fovy);
        let (near, far) = (self.settings.near, self.settings.far);
        !(all(&|p| p.z < near)
            || all(&|p| p.z > far)
            || all(&|p| p.x > p.z * tx)
            || all(&|p| -p.x > p.z * tx)
            || all(&|p| p.y > p.z * ty)
            || all(&|p| -p.y > p.z * ty))
    }
}

/// The convex hull of `points`, counter-clockwise from the lowest-leftmost point (Andrew's
/// monotone chain); collinear points are dropped.
fn convex_hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * points.len());
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn settings() -> ViewSettings {
        ViewSettings {
            width_px: 600,
            height_px: 600,
            fovy: 60f64.to_radians(),
            near: 1.0,
            far: 1000.0,
        }
    }

    #[test]
    fn a_camera_looking_along_x_sees_ahead_and_not_behind() {
        let camera = Camera::new(
            &Pose {
                position: DVec3::ZERO,
                yaw: 0.0,
                pitch: 0.0,
            },
            settings(),
        );
        assert!(camera.sees(DVec3::new(10.0, 0.0, 0.0)));
        assert!(!camera.sees(DVec3::new(-10.0, 0.0, 0.0)));
        assert!(!camera.sees(DVec3::new(2000.0, 0.0, 0.0)));
        // +y is to the left when looking along +x.
        assert!(camera.to_camera(DVec3::new(10.0, 1.0, 0.0)).x < 0.0);
        assert!(camera.to_camera(DVec3::new(10.0, 0.0, 1.0)).y > 0.0);
    }

    #[test]
    fn the_footprint_of_a_level_camera_is_the_trapezoid_between_its_near_and_far_planes() {
        let settings = ViewSettings {
            fovy: FRAC_PI_2,
            near: 1.0,
            far: 100.0,
            ..settings()
        };
        let pose = Pose {
            position: DVec3::new(0.0, 0.0, 50.0),
            yaw: 0.0,
            pitch: 0.0,
        };
        let footprint = Camera::new(&pose, settings).footprint();
        let expected = [(1.0, -1.0), (100.0, -100.0), (100.0, 100.0), (1.0, 1.0)];
        assert_eq!(footprint.len(), 4, "{footprint:?}");
        for (corner, (x, y)) in footprint.iter().zip(expected) {
            assert!(
                (corner.x - x).abs() < 1e-9 && (corner.y - y).abs() < 1e-9,
                "{footprint:?}"
            );
        }
    }

    #[test]
    fn the_footprint_of_a_camera_looking_down_surrounds_the_point_below_it() {
        let pose = Pose {
            position: DVec3::new(5.0, 7.0, 100.0),
            yaw: 0.3,
            pitch: -FRAC_PI_2,
        };
        let footprint = Camera::new(&pose, settings()).footprint();
        let below = DVec2::new(5.0, 7.0);
        let n = footprint.len();
        assert_eq!(n, 4);
        // Counter-clockwise: the point is left of every edge.
        for k in 0..n {
            let (a, b) = (footprint[k], footprint[(k + 1) % n]);
            assert!((b - a).perp_dot(below - a) > 0.0, "{footprint:?}");
        }
    }

    #[test]
    fn looking_straight_down_is_well_defined() {
        let camera = Camera::new(
            &Pose {
                position: DVec3::new(0.0, 0.0, 100.0),
                yaw: 0.3,
                pitch: -FRAC_PI_2,
            },
            settings(),
        );
        assert!(camera.sees(DVec3::ZERO));
        assert!(camera.up.is_finite() && (camera.up.length() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_point_at_the_top_edge_of_the_view_projects_to_half_the_window_height() {
        let camera = Camera::new(
            &Pose {
                position: DVec3::ZERO,
                yaw: 0.0,
                pitch: 0.0,
            },
            settings(),
        );
        let top = DVec3::new(10.0, 0.0, 10.0 * 30f64.to_radians().tan());
        let pixel = camera.project_camera(camera.to_camera(top)).unwrap();
        assert!((pixel.y - 300.0).abs() < 1e-9, "{pixel:?}");
    }
}
