//! Lindstrom et al.'s vertex criterion (1996; SPEC §4's vertical-projection error) in the paper's
//! own form: a squared comparison, no square root, a vertex kept only when its screen error
//! exceeds τ.
//!
//! With d = vertex − eye, the vertical-projection error is λ·δ·√(dx²+dy²)/(dx²+dy²+dz²); the paper
//! squares both sides of "error > τ" to compare λ²δ²(dx²+dy²) with τ²(dx²+dy²+dz²)². This is the
//! one place the criterion is written: the block step's exact evaluations and the brute force
//! both call [`Tolerance::keeps`], so they agree bit for bit.

use glam::DVec3;

/// λ² and τ² of one run: what the criterion needs besides the vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    lambda_squared: f64,
    tau_squared: f64,
}

impl Tolerance {
    /// λ = (h/2)/tan(fovy/2) in pixels per unit at distance 1, τ in pixels (≥ 0).
    pub fn new(lambda: f64, tau_px: f64) -> Tolerance {
        Tolerance {
            lambda_squared: lambda * lambda,
            tau_squared: tau_px * tau_px,
        }
    }

    /// Whether a vertex of nested error `delta` at `offset` = vertex − eye is kept:
    /// λ²δ²(dx²+dy²) > τ²(dx²+dy²+dz²)². False for δ = 0 and for an eye straight above or below
    /// the vertex (or on it), whatever τ.
    pub fn keeps(&self, delta: f32, offset: DVec3) -> bool {
        let horizontal = offset.x * offset.x + offset.y * offset.y;
        let distance_squared = horizontal + offset.z * offset.z;
        let delta = f64::from(delta);
        self.lambda_squared * delta * delta * horizontal
            > self.tau_squared * distance_squared * distance_squared
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::metrics::vertical_projection_error_px;

    #[test]
    fn the_squared_form_agrees_with_the_metric_away_from_ties() {
        let lambda = 519.6;
        let eye = DVec3::new(10.0, -20.0, 300.0);
        for (k, vertex) in [
            DVec3::new(400.0, 10.0, 120.0),
            DVec3::new(-35.0, 80.0, 290.0),
            DVec3::new(10.5, -20.0, 0.0),
        ]
        .into_iter()
        .enumerate()
        {
            for delta in [0.01f32, 0.7, 3.0, 40.0] {
                let projected = vertical_projection_error_px(eye, vertex, f64::from(delta), lambda);
                for tau in [0.0, 0.5, 1.0, 2.0, 8.0] {
                    if (projected - tau).abs() < 1e-9 * tau.max(1.0) {
                        continue;
                    }
                    assert_eq!(
                        Tolerance::new(lambda, tau).keeps(delta, vertex - eye),
                        projected > tau,
                        "vertex {k}, δ {delta}, τ {tau}: projected {projected}"
                    );
                }
            }
        }
    }

    #[test]
    fn an_error_of_exactly_tau_is_removed_and_so_is_a_vertex_under_the_eye() {
        // δ = 1 m seen side-on from 100 m with λ = 500: exactly 5 px.
        let offset = DVec3::new(100.0, 0.0, 0.0);
        assert!(!Tolerance::new(500.0, 5.0).keeps(1.0, offset));
        assert!(Tolerance::new(500.0, 4.999).keeps(1.0, offset));
        for tau in [0.0, 1.0] {
            let tolerance = Tolerance::new(500.0, tau);
            assert!(
                !tolerance.keeps(3.0, DVec3::ZERO),
                "eye on the vertex, τ {tau}"
            );
            assert!(
                !tolerance.keeps(3.0, DVec3::new(0.0, 0.0, -50.0)),
                "straight below"
            );
            assert!(!tolerance.keeps(0.0, offset), "δ = 0");
        }
        assert!(Tolerance::new(500.0, 0.0).keeps(1e-6, DVec3::new(1e5, 0.0, 1e5)));
    }
}
