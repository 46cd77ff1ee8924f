//! Deferred priority recomputation as ROAM'97 §7.3 describes it: a priority is recomputed only
//! when its time-dependent bound could reach the crossover, and each recomputation is scheduled
//! on a small ring of per-frame lists. It is not a change to the mesh: it only decides when a
//! priority is recomputed, the meshes are those of full recomputation, and splits and merges
//! stay the frame loop's (`mod.rs`, `core/recompute.rs`).
//!
//! **The rule.** "Given a velocity bound on the viewpoint, bounds can be obtained for
//! screen-distortion priorities over time … Recomputation of a triangle can safely be deferred
//! until its priority bound overlaps the crossover priority. A deferral list is kept for each of
//! the next few dozen frames." The crossover is where the split queue meets the merge queue. With
//! a fixed tolerance τ it is τ itself. With a triangle target it moves (slowly, in roamsim's
//! reading of §7.3), so roamsim keeps a band around it, a *floor* G below and a *ceiling* H above
//! ([`Deferral`]): a split-queue triangle is deferred while its priority provably stays at or
//! below G, a mergeable diamond while its priority provably stays above H. Elements inside the
//! band are recomputed every frame. The frame loop (`mod.rs`) then never needs a stale priority:
//! if the largest split priority it sees is at most G, or the smallest merge priority above H,
//! the true one might be stale and it recomputes that whole queue first (the crossover left the
//! band). So deferral gives exactly the meshes of full recomputation. Raising G or lowering H is
//! always safe (a stale priority below the old G is below the new one); the band follows the
//! crossover that way after every frame (G = χ/(1 + m), H = χ·(1 + m), [`BAND_MARGIN`]).
//! Lowering G or raising H happens only after recomputing the queue concerned.
//!
//! **The bound.** Write a corner in camera coordinates as p = (p, q, r), ρ = |p|, and the thickness
//! vector as e = (a, b, c) (|e| = e_T). Eq. (3) is P = 2k·max N_i / min M_i with N_i = |(e × p_i)_xy|
//! and M_i = r_i² − c². Over j frames the eye moves by at most j·v metres (the experiment's speed
//! bound, v = √(v_h² + v_v²)) and, with a rotation bound θ radians per frame ([`MotionBound`]),
//! the camera turns by at most j·θ. A translation by Δ changes r_i by at most |Δ| and N_i by at
//! most e_T·|Δ|; a rotation by φ moves every camera-space vector w by at most φ·|w|, so it changes
//! r_i by at most φ·(ρ_i + |Δ|), N_i by at most φ·e_T·(ρ_i + |Δ|), and c by at most φ·e_T. With
//! ρ̂ = max ρ_i + L·v over the ring's L frames and w = v + θ·ρ̂, after j ≤ L frames:
//! - U(j) = 2k·(max N + e_T·w·j) / ((r_min − w·j)² − (|c| + θ·e_T·j)²), and +∞ once
//!   r_min − (w + θ·e_T)·j − |c| < near (the near-plane rule could fire);
//! - L(j) = 2k·max(0, max N − e_T·w·j) / ((r_min + w·j)² − κ), κ = c² without rotation (c is
//!   then constant) and 0 with it; an infinite priority stays infinite while
//!   r_min + (w + θ·e_T)·j − |c| < near.
//!
//! Without a rotation bound (θ = 0 here) a frame whose camera orientation changed recomputes every
//! priority: eq. (3) depends on the view direction. U(j) ≤ G and L(j) > H are quadratic in j, so
//! the number of safe frames has a **closed form** (the first positive root, computed stably and
//! then checked once against the bound itself, [`frames_at_most`], [`frames_above`]); it goes into
//! the list of frame f + 1 + j of a ring of [`RING_FRAMES`] lists, indexed by frame modulo the
//! ring: O(1) per schedule, no ordered map. Culling flags are exact every frame (`cull.rs`), so a
//! flag change triggers its own recomputation and needs no bound. A culled or zero-thickness
//! priority is constant (0) and is never scheduled.
//!
//! **The rotation bound.** [`MotionBound`]'s rotation is the experiment's
//! `speed_bounds.rotation_rad_per_frame` ([`super::Roam::new`]; tests may pass their own through
//! [`super::Roam::with_motion_bound`]); a frame whose camera turned by more than θ since the
//! previous one, or that the runner reports as breaking a bound, revalidates. An experiment that
//! declares no rotation bound gets its flight's largest turn (derived at load; 0 for a flight
//! that never turns, so any turn revalidates). Only π (`SpeedBound::NO_ROTATION_BOUND`) gives
//! none, and every turn then recomputes everything.

use super::bintree::TriangleKey;
use super::priority::Wedgie;

/// Frames the ring of deferral lists covers ("a deferral list is kept for each of the next few
/// dozen frames"); a priority is recomputed at least every `RING_FRAMES − 1` frames.
pub const RING_FRAMES: usize = 64;

/// The relative half-width of the band around a moving crossover (target mode).
pub const BAND_MARGIN: f64 = 0.1;

/// A relative margin against rounding between a bound and the priority it bounds.
const ROUNDING_MARGIN: f64 = 1e-9;

/// How far the camera can move per frame, as far as deferral is concerned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBound {
    /// The eye's displacement per frame, metres (√(v_h² + v_v²) of the experiment's bounds).
    pub metres_per_frame: f64,
    /// The camera's rotation per frame, radians (the angle of the rotation between consecutive
    /// camera frames); `None` when unbounded, i.e. any turn revalidates.
    pub radians_per_frame: Option<f64>,
}

/// When an element's priority is next due.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schedule {
    /// Its priority cannot change until its flags do (culled or zero thickness).
    Never,
    /// After this many more frames (0: the next frame).
    After(u64),
}

/// The deferral lists and the band around the crossover.
pub struct Deferral {
    ring: Vec<Vec<TriangleKey>>,
    /// G: every deferred split-queue priority is at most this.
    pub floor: f64,
    /// H: every deferred merge-queue priority is above this.
    pub ceiling: f64,
}

impl Deferral {
    /// A band fixed at τ (tolerance mode) or starting empty (target mode: G = 0, H = +∞, so
    /// nothing is deferred until the first crossover is known).
    pub fn new(tau: Option<f64>) -> Deferral {
        Deferral {
            ring: vec![Vec::new(); RING_FRAMES],
            floor: tau.unwrap_or(0.0),
            ceiling: tau.unwrap_or(f64::INFINITY),
        }
    }

    /// Queues `key` for frame `frame + 1 + after` (capped by the ring); returns that frame.
    pub fn schedule(&mut self, frame: u64, after: u64, key: TriangleKey) -> u64 {
        let due = frame + 1 + after.min(RING_FRAMES as u64 - 2);
        self.ring[(due % RING_FRAMES as u64) as usize].push(key);
        due
    }

    /// Takes the list of `frame` (the caller checks each entry is still due then).
    pub fn take_due(&mut self, frame: u64) -> Vec<TriangleKey> {
        std::mem::take(&mut self.ring[(frame % RING_FRAMES as u64) as usize])
    }

    /// Gives a list back to be reused (cleared).
    pub fn give_back(&mut self, frame: u64, mut list: Vec<TriangleKey>) {
        list.clear();
        let slot = &mut self.ring[(frame % RING_FRAMES as u64) as usize];
        if slot.is_empty() && slot.capacity() < list.capacity() {
            *slot = list;
        }
    }

    /// Forgets every scheduled recomputation.
    pub fn clear(&mut self) {
        for list in &mut self.ring {
            list.clear();
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.ring
            .iter()
            .map(|l| l.capacity() * std::mem::size_of::<TriangleKey>())
            .sum()
    }
}

/// The per-frame speed of any corner in camera coordinates (w) and the per-frame growth of |c|.
fn rates(wedgie: &Wedgie, motion: MotionBound) -> (f64, f64) {
    let v = motion.metres_per_frame;
    let theta = motion.radians_per_frame.unwrap_or(0.0);
    let reach = wedgie.max_distance + RING_FRAMES as f64 * v;
    (v + theta * reach, theta * wedgie.thickness)
}

/// U(j): an upper bound of the priority after `j` frames.
pub fn upper_bound(wedgie: &Wedgie, motion: MotionBound, j: f64, scale: f64, near: f64) -> f64 {
    if wedgie.constant {
        return wedgie.value;
    }
    let (w, grow) = rates(wedgie, motion);
    let depth = wedgie.min_depth - w * j;
    let c = wedgie.c_abs + grow * j;
    if depth - c < near {
        return f64::INFINITY;
    }
    scale * (wedgie.max_numerator + wedgie.thickness * w * j) / (depth * depth - c * c)
}

/// L(j): a lower bound of the priority after `j` frames.
pub fn lower_bound(wedgie: &Wedgie, motion: MotionBound, j: f64, scale: f64, near: f64) -> f64 {
    if wedgie.constant {
        return wedgie.value;
    }
    let (w, grow) = rates(wedgie, motion);
    if wedgie.value.is_infinite() {
        let still_behind = wedgie.min_depth + (w + grow) * j - wedgie.c_abs < near;
        return if still_behind { f64::INFINITY } else { 0.0 };
    }
    let kappa = if grow == 0.0 {
        wedgie.c_abs * wedgie.c_abs
    } else {
        0.0
    };
    let depth = wedgie.min_depth + w * j;
    let numerator = (wedgie.max_numerator - wedgie.thickness * w * j).max(0.0);
    scale * numerator / (depth * depth - kappa)
}

/// How many more frames a split-queue priority provably stays at or below `floor`.
pub fn frames_at_most(
    wedgie: &Wedgie,
    floor: f64,
    motion: MotionBound,
    scale: f64,
    near: f64,
) -> Schedule {
    if wedgie.constant {
        return Schedule::Never;
    }
    let below =
        |j: f64| upper_bound(wedgie, motion, j, scale, near) * (1.0 + ROUNDING_MARGIN) <= floor;
    if !below(0.0) {
        return Schedule::After(0);
    }
    let cap = (RING_FRAMES - 2) as f64;
    let (w, grow) = rates(wedgie, motion);
    if w == 0.0 && grow == 0.0 {
        return Schedule::After(cap as u64);
    }
    // floor·D(j) − 2k·(N + e_T·w·j) = A·j² + B·j + C ≥ 0, C ≥ 0 and B < 0: up to the first
    // positive root.
    let (r, c, e) = (wedgie.min_depth, wedgie.c_abs, wedgie.thickness);
    let a = floor * (w * w - grow * grow);
    let b = -2.0 * floor * (r * w + c * grow) - scale * e * w;
    let c0 = floor * (r * r - c * c) - scale * wedgie.max_numerator;
    let discriminant = b * b - 4.0 * a * c0;
    let root = if discriminant < 0.0 {
        f64::INFINITY
    } else {
        2.0 * c0.max(0.0) / (-b + discriminant.sqrt())
    };
    let near_limit = (r - c - near) / (w + grow);
    let mut frames = root.min(near_limit).min(cap).max(0.0).floor();
    // The root is computed in floating point: settle the last frame against the bound itself.
    while frames > 0.0 && !below(frames) {
        frames -= 1.0;
    }
    if frames < cap && below(frames + 1.0) {
        frames += 1.0;
    }
    Schedule::After(frames as u64)
}

/// How many more frames a priority provably stays above `ceiling` (0 when it is not above it
/// now; a constant priority above it never changes).
pub fn frames_above(
    wedgie: &Wedgie,
    ceiling: f64,
    motion: MotionBound,
    scale: f64,
    near: f64,
) -> Schedule {
    if wedgie.constant {
        return if wedgie.value > ceiling {
            Schedule::Never
        } else {
            Schedule::After(0)
        };
    }
    let above =
        |j: f64| lower_bound(wedgie, motion, j, scale, near) * (1.0 - ROUNDING_MARGIN) > ceiling;
    if !above(0.0) {
        return Schedule::After(0);
    }
    let cap = (RING_FRAMES - 2) as f64;
    let (w, grow) = rates(wedgie, motion);
    if w == 0.0 && grow == 0.0 {
        return Schedule::After(cap as u64);
    }
    let (r, e) = (wedgie.min_depth, wedgie.thickness);
    let root = if wedgie.value.is_infinite() {
        // Still behind while r + (w + grow)·j − |c| < near.
        (near - r + wedgie.c_abs) / (w + grow)
    } else {
        let kappa = if grow == 0.0 {
            wedgie.c_abs * wedgie.c_abs
        } else {
            0.0
        };
        // ceiling·(r + w·j)² − ceiling·κ − 2k·(N − e_T·w·j) = A·j² + B·j + C < 0, C < 0,
        // A, B ≥ 0: below the positive root.
        let a = ceiling * w * w;
        let b = 2.0 * ceiling * r * w + scale * e * w;
        let c0 = ceiling * (r * r - kappa) - scale * wedgie.max_numerator;
        let discriminant = (b * b - 4.0 * a * c0).max(0.0);
        let denominator = b + discriminant.sqrt();
        if denominator == 0.0 {
            f64::INFINITY
        } else {
            2.0 * (-c0).max(0.0) / denominator
        }
    };
    let mut frames = (root.ceil() - 1.0).min(cap).max(0.0);
    while frames > 0.0 && !above(frames) {
        frames -= 1.0;
    }
    if frames < cap && above(frames + 1.0) {
        frames += 1.0;
    }
    Schedule::After(frames as u64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::view::{Camera, Pose, ViewSettings};
    use glam::DVec3;

    fn settings() -> ViewSettings {
        ViewSettings {
            width_px: 600,
            height_px: 600,
            fovy: 60f64.to_radians(),
            near: 1.0,
            far: 1e5,
        }
    }

    /// Eq. (3) from first principles for a triangle of corners `corners` and thickness `e`.
    fn eq3(camera: &Camera, corners: [DVec3; 3], e: f64) -> Wedgie {
        let up = camera.direction_to_camera(DVec3::Z) * e;
        let (mut n, mut m, mut r, mut rho) = (0.0f64, f64::INFINITY, f64::INFINITY, 0.0f64);
        let mut behind = false;
        for corner in corners {
            let p = camera.to_camera(corner);
            rho = rho.max(p.length());
            r = r.min(p.z);
            if p.z - up.z.abs() < camera.settings.near {
                behind = true;
                continue;
            }
            n = n.max(
                ((up.x * p.z - up.z * p.x).powi(2) + (up.y * p.z - up.z * p.y).powi(2)).sqrt(),
            );
            m = m.min(p.z * p.z - up.z * up.z);
        }
        Wedgie {
            value: if behind {
                f64::INFINITY
            } else {
                2.0 * n / m * camera.settings.pixels_per_unit()
            },
            constant: false,
            thickness: e,
            max_numerator: n,
            min_depth: r,
            c_abs: up.z.abs(),
            max_distance: rho,
        }
    }

    fn camera(position: DVec3, yaw: f64, pitch: f64) -> Camera {
        Camera::new(
            &Pose {
                position,
                yaw,
                pitch,
            },
            settings(),
        )
    }

    /// Cameras that move at most `v` metres and turn at most `theta` radians per frame, in
    /// every combination of extreme directions, for `frames` frames.
    fn extreme_paths(v: f64, theta: f64, frames: usize) -> Vec<Vec<Camera>> {
        let mut paths = Vec::new();
        let start = (DVec3::new(0.0, 0.0, 80.0), 0.3, -0.35);
        for direction in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
            DVec3::new(0.6, 0.0, -0.8),
        ] {
            for (dyaw, dpitch) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.0, 0.0)] {
                let path = (0..=frames)
                    .map(|f| {
                        let f = f as f64;
                        camera(
                            start.0 + direction * v * f,
                            start.1 + dyaw * theta * f,
                            start.2 + dpitch * theta * f,
                        )
                    })
                    .collect();
                paths.push(path);
            }
        }
        paths
    }

    #[test]
    fn the_bounds_hold_under_every_extreme_motion_with_and_without_rotation() {
        let triangles = [
            [
                DVec3::new(300.0, 40.0, 10.0),
                DVec3::new(340.0, 40.0, 12.0),
                DVec3::new(300.0, 80.0, 5.0),
            ],
            [
                DVec3::new(60.0, -20.0, 30.0),
                DVec3::new(60.0, 20.0, 30.0),
                DVec3::new(100.0, 0.0, 35.0),
            ],
            [
                DVec3::new(2000.0, 900.0, 0.0),
                DVec3::new(2400.0, 900.0, 40.0),
                DVec3::new(2000.0, 1300.0, 20.0),
            ],
        ];
        let scale = 2.0 * settings().pixels_per_unit();
        let mut checked = 0;
        for (v, theta) in [(3.0, 0.0), (3.0, 0.004), (0.0, 0.01), (10.0, 0.02)] {
            let motion = MotionBound {
                metres_per_frame: v,
                radians_per_frame: (theta > 0.0).then_some(theta),
            };
            for path in extreme_paths(v, theta, 30) {
                for corners in triangles {
                    for e in [0.5, 4.0, 25.0] {
                        let start = eq3(&path[0], corners, e);
                        for (j, camera) in path.iter().enumerate() {
                            let now = eq3(camera, corners, e).value;
                            let (upper, lower) = (
                                upper_bound(&start, motion, j as f64, scale, 1.0),
                                lower_bound(&start, motion, j as f64, scale, 1.0),
                            );
                            assert!(
                                now <= upper * (1.0 + 1e-12),
                                "v {v}, θ {theta}, e {e}, frame {j}: {now} > U {upper}"
                            );
                            assert!(
                                now >= lower * (1.0 - 1e-12),
                                "v {v}, θ {theta}, e {e}, frame {j}: {now} < L {lower}"
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 10_000);
    }

    #[test]
    fn the_closed_form_frame_counts_are_the_largest_the_bounds_allow() {
        let motion = MotionBound {
            metres_per_frame: 4.0,
            radians_per_frame: Some(0.003),
        };
        let scale = 2.0 * settings().pixels_per_unit();
        let view = camera(DVec3::new(0.0, 0.0, 60.0), 0.0, -0.3);
        for distance in [40.0, 150.0, 600.0, 3000.0] {
            let corners = [
                DVec3::new(distance, 0.0, 0.0),
                DVec3::new(distance + 20.0, 0.0, 3.0),
                DVec3::new(distance, 20.0, 1.0),
            ];
            let wedgie = eq3(&view, corners, 2.0);
            for factor in [1.01, 1.5, 4.0, 40.0] {
                let floor = wedgie.value * factor;
                let Schedule::After(frames) = frames_at_most(&wedgie, floor, motion, scale, 1.0)
                else {
                    panic!("not constant");
                };
                for j in 0..=frames {
                    assert!(upper_bound(&wedgie, motion, j as f64, scale, 1.0) <= floor);
                }
                if frames < (RING_FRAMES - 2) as u64 {
                    assert!(
                        upper_bound(&wedgie, motion, (frames + 1) as f64, scale, 1.0) > floor,
                        "distance {distance}, ×{factor}: {frames} frames is not the largest"
                    );
                }
                let ceiling = wedgie.value / factor;
                let Schedule::After(frames) = frames_above(&wedgie, ceiling, motion, scale, 1.0)
                else {
                    panic!("not constant");
                };
                for j in 0..=frames {
                    assert!(lower_bound(&wedgie, motion, j as f64, scale, 1.0) > ceiling);
                }
                if frames < (RING_FRAMES - 2) as u64 && frames > 0 {
                    assert!(
                        lower_bound(&wedgie, motion, (frames + 1) as f64, scale, 1.0) <= ceiling,
                        "distance {distance}, ÷{factor}: {frames} frames is not the largest"
                    );
                }
            }
        }
    }

    #[test]
    fn a_rotation_bound_shortens_deferral_and_no_motion_defers_to_the_ring() {
        let scale = 2.0 * settings().pixels_per_unit();
        let view = camera(DVec3::new(0.0, 0.0, 60.0), 0.0, -0.3);
        let corners = [
            DVec3::new(500.0, 0.0, 0.0),
            DVec3::new(520.0, 0.0, 3.0),
            DVec3::new(500.0, 20.0, 1.0),
        ];
        let wedgie = eq3(&view, corners, 2.0);
        let frames = |motion| match frames_at_most(&wedgie, wedgie.value * 3.0, motion, scale, 1.0)
        {
            Schedule::After(frames) => frames,
            Schedule::Never => u64::MAX,
        };
        let still = MotionBound {
            metres_per_frame: 0.0,
            radians_per_frame: None,
        };
        let moving = MotionBound {
            metres_per_frame: 5.0,
            radians_per_frame: None,
        };
        let turning = MotionBound {
            radians_per_frame: Some(0.005),
            ..moving
        };
        assert_eq!(frames(still), (RING_FRAMES - 2) as u64);
        assert!(
            frames(moving) > frames(turning),
            "{} vs {}",
            frames(moving),
            frames(turning)
        );
        assert!(frames(turning) > 0);
        let culled = Wedgie {
            constant: true,
            value: 0.0,
            ..wedgie
        };
        assert_eq!(
            frames_at_most(&culled, 1.0, moving, scale, 1.0),
            Schedule::Never
        );
    }
}
