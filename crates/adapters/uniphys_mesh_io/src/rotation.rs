//! A rotation of the whole asset applied at ingest, and a deterministic random one from a seed.

use glam::DQuat;
use uniphys_geometry::SplitMix64;

/// A rotation applied to the whole asset (meshes and joints) right after the unit and up-axis
/// conversion, about the origin of the service frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AssetRotation {
    /// The rotation, as a unit quaternion: `p_rotated = rotated_from_input * p`.
    pub rotated_from_input: DQuat,
    /// The seed it was drawn from, if it was drawn by [`AssetRotation::from_seed`].
    pub seed: Option<u64>,
}

impl AssetRotation {
    /// A rotation drawn uniformly from SO(3) with [`SplitMix64`] seeded with `seed`: the same
    /// seed gives the same rotation on every platform.
    #[must_use]
    pub fn from_seed(seed: u64) -> Self {
        Self {
            rotated_from_input: uniform_rotation(&mut SplitMix64::new(seed)),
            seed: Some(seed),
        }
    }

    /// One sentence saying what was applied, for run notes.
    #[must_use]
    pub fn describe(&self) -> String {
        // q and -q are the same rotation; the one with w >= 0 has an angle in [0, pi].
        let q = if self.rotated_from_input.w < 0.0 {
            -self.rotated_from_input
        } else {
            self.rotated_from_input
        };
        let (axis, angle_rad) = q.to_axis_angle();
        let source = self.seed.map_or_else(
            || "a given rotation".to_owned(),
            |s| format!("the uniform random rotation of seed {s}"),
        );
        format!(
            "whole asset rotated by {source} after unit and up-axis conversion: quaternion (x, y, z, w) = ({:.6}, {:.6}, {:.6}, {:.6}), {:.4} rad about ({:.4}, {:.4}, {:.4})",
            q.x, q.y, q.z, q.w, angle_rad, axis.x, axis.y, axis.z
        )
    }
}

/// A uniformly distributed rotation (Shoemake's subgroup algorithm: three uniforms in [0, 1)
/// give a uniformly distributed unit quaternion).
#[must_use]
pub fn uniform_rotation(rng: &mut SplitMix64) -> DQuat {
    let u1 = rng.next_f64();
    let u2 = rng.next_f64() * std::f64::consts::TAU;
    let u3 = rng.next_f64() * std::f64::consts::TAU;
    let a = (1.0 - u1).sqrt();
    let b = u1.sqrt();
    DQuat::from_xyzw(a * u2.sin(), a * u2.cos(), b * u3.sin(), b * u3.cos()).normalize()
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    #[test]
    fn same_seed_gives_the_same_unit_rotation_and_seeds_differ() {
        let a = AssetRotation::from_seed(7);
        let b = AssetRotation::from_seed(7);
        let c = AssetRotation::from_seed(8);
        assert_eq!(a, b);
        assert_ne!(a.rotated_from_input, c.rotated_from_input);
        assert!((a.rotated_from_input.length() - 1.0).abs() < 1e-12);
        assert_eq!(a.seed, Some(7));
        assert!(a.describe().contains("seed 7"), "{}", a.describe());
    }

    #[test]
    fn rotated_up_vectors_spread_over_the_sphere() {
        // A uniform rotation sends +Z to a uniform direction: the mean of many is near 0 and
        // about a third of them have |z| < 1/3 (the sphere's area is uniform in z).
        let mut rng = SplitMix64::new(1);
        let n = 4000;
        let mut sum = DVec3::ZERO;
        let mut band = 0;
        for _ in 0..n {
            let v = uniform_rotation(&mut rng) * DVec3::Z;
            sum += v;
            if v.z.abs() < 1.0 / 3.0 {
                band += 1;
            }
        }
        let mean = sum / f64::from(n);
        assert!(mean.length() < 0.05, "{mean}");
        let share = f64::from(band) / f64::from(n);
        assert!((share - 1.0 / 3.0).abs() < 0.03, "{share}");
    }
}
