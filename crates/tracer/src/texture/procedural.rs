//! Procedural (solid) textures of Suffern's chapters 30 and 31: a 3D
//! checker and fractional Brownian motion (fBm) over lattice value noise.
//! Both are functions of the world-space hit point, so they need no
//! texture coordinates and work on every shape.

use crate::float::to_f32;
use crate::scene::Rgb;
use gridrt_bbox::Vec3;

/// A 3D checker: cubes of side `size` alternate between `even` and `odd`
/// (Suffern's `Checker3D`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    /// Side of one cube, world units (> 0).
    pub size: f32,
    /// Colour of the cube that holds the origin's positive corner.
    pub even: Rgb,
    /// Colour of its neighbours.
    pub odd: Rgb,
}

impl Checker {
    /// The colour at world position `p`.
    #[must_use]
    pub fn eval(&self, p: Vec3) -> Rgb {
        let k = |x| (crate::float::to_f64(x) / f64::from(self.size)).floor() as i64;
        // A tiny nudge keeps points exactly on a face of a cube (a plane
        // through the origin) from flickering between the two colours.
        let (x, y, z) = (p.x + 1e-4, p.y + 1e-4, p.z + 1e-4);
        if (k(x) + k(y) + k(z)).rem_euclid(2) == 0 {
            self.even
        } else {
            self.odd
        }
    }
}

/// Fractional Brownian motion: `octaves` layers of value noise, each at
/// `lacunarity` times the frequency and `gain` times the amplitude of the
/// one before, normalised to [0, 1] and mapped to a colour between `low`
/// and `high` (Suffern's `FBmTexture` over `LinearNoise`, with a smooth
/// interpolant so that no lattice planes show).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fbm {
    /// Frequency of the first octave, lattice cells per world unit (> 0).
    pub scale: f32,
    /// Number of octaves (1 to 16).
    pub octaves: u32,
    /// Frequency ratio between octaves (Suffern's default 2).
    pub lacunarity: f32,
    /// Amplitude ratio between octaves (Suffern's default 0.5).
    pub gain: f32,
    /// Colour where the noise is 0.
    pub low: Rgb,
    /// Colour where the noise is 1.
    pub high: Rgb,
    /// Seed of the lattice values (different seeds, unrelated patterns).
    pub seed: u32,
}

impl Fbm {
    /// The fBm value in [0, 1] at world position `p`.
    #[must_use]
    pub fn value(&self, p: Vec3) -> f32 {
        let p = glam::Vec3::new(to_f32(p.x), to_f32(p.y), to_f32(p.z)) * self.scale;
        let (mut sum, mut amp, mut freq, mut total) = (0.0f32, 1.0f32, 1.0f32, 0.0f32);
        for octave in 0..self.octaves.clamp(1, 16) {
            sum += amp * value_noise(p * freq, self.seed.wrapping_add(octave));
            total += amp;
            amp *= self.gain;
            freq *= self.lacunarity;
        }
        if total > 0.0 {
            (0.5 + 0.5 * sum / total).clamp(0.0, 1.0)
        } else {
            0.5
        }
    }

    /// The colour at world position `p`.
    #[must_use]
    pub fn eval(&self, p: Vec3) -> Rgb {
        self.low.lerp(self.high, self.value(p))
    }
}

/// Value noise in [-1, 1]: hashed lattice values blended with the quintic
/// fade `6t⁵ − 15t⁴ + 10t³` (continuous first and second derivatives).
fn value_noise(p: glam::Vec3, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (fx, fy, fz) = (fade(f.x), fade(f.y), fade(f.z));
    let (ix, iy, iz) = (wrap_i32(cell.x), wrap_i32(cell.y), wrap_i32(cell.z));
    let v = |dx: i32, dy: i32, dz: i32| {
        lattice(
            ix.wrapping_add(dx),
            iy.wrapping_add(dy),
            iz.wrapping_add(dz),
            seed,
        )
    };
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(v(0, 0, 0), v(1, 0, 0), fx);
    let x10 = lerp(v(0, 1, 0), v(1, 1, 0), fx);
    let x01 = lerp(v(0, 0, 1), v(1, 0, 1), fx);
    let x11 = lerp(v(0, 1, 1), v(1, 1, 1), fx);
    lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz)
}

/// A lattice coordinate as an integer (NaN reads as 0; far coordinates
/// saturate, and the pattern there is constant, which is harmless).
fn wrap_i32(x: f32) -> i32 {
    if x.is_finite() {
        x as i32
    } else {
        0
    }
}

/// The value of lattice point `(x, y, z)` in [-1, 1]: a 32-bit integer hash
/// (the mixing of Jenkins' lookup3 finaliser), so that the pattern is the
/// same on every machine and needs no permutation table.
fn lattice(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = seed ^ 0x9e37_79b9;
    for k in [x as u32, y as u32, z as u32] {
        h ^= k.wrapping_mul(0x85eb_ca6b);
        h = h.rotate_left(13).wrapping_mul(5).wrapping_add(0xe654_6b64);
    }
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 23) as f32 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::Real;
    use proptest::prelude::*;

    fn fbm() -> Fbm {
        Fbm {
            scale: 2.0,
            octaves: 6,
            lacunarity: 2.0,
            gain: 0.5,
            low: Rgb::ZERO,
            high: Rgb::ONE,
            seed: 7,
        }
    }

    #[test]
    fn checker_alternates_across_faces() {
        let c = Checker {
            size: 1.0,
            even: Rgb::ONE,
            odd: Rgb::ZERO,
        };
        assert_eq!(c.eval(Vec3::new(0.5, 0.5, 0.5)), Rgb::ONE);
        assert_eq!(c.eval(Vec3::new(1.5, 0.5, 0.5)), Rgb::ZERO);
        assert_eq!(c.eval(Vec3::new(-0.5, 0.5, 0.5)), Rgb::ZERO);
        assert_eq!(c.eval(Vec3::new(1.5, 1.5, 0.5)), Rgb::ONE);
        // On the plane y = 0 the pattern is a 2D checker, without flicker.
        assert_eq!(c.eval(Vec3::new(0.5, 0.0, 0.5)), Rgb::ONE);
    }

    #[test]
    fn fbm_is_deterministic_and_varies() {
        let f = fbm();
        let values: Vec<f32> = (0..200)
            .map(|i| f.value(Vec3::new(i as Real * 0.137, 0.3, -0.2 * i as Real)))
            .collect();
        let again: Vec<f32> = (0..200)
            .map(|i| f.value(Vec3::new(i as Real * 0.137, 0.3, -0.2 * i as Real)))
            .collect();
        assert_eq!(values, again);
        let (lo, hi) = values
            .iter()
            .fold((1.0f32, 0.0f32), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(hi - lo > 0.3, "noise too flat: {lo}..{hi}");
        let other = Fbm { seed: 8, ..f };
        assert_ne!(
            f.value(Vec3::new(0.3, 0.3, 0.3)),
            other.value(Vec3::new(0.3, 0.3, 0.3))
        );
    }

    #[test]
    fn noise_is_continuous_across_lattice_planes() {
        let f = Fbm {
            octaves: 1,
            ..fbm()
        };
        let a = f.value(Vec3::new(0.5 - 1e-4, 0.2, 0.3));
        let b = f.value(Vec3::new(0.5 + 1e-4, 0.2, 0.3));
        assert!((a - b).abs() < 1e-2, "{a} vs {b}");
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(28), ..ProptestConfig::default() })]
        #[test]
        fn fbm_stays_in_unit_range(x in -1e4f32..1e4, y in -1e4f32..1e4, z in -1e4f32..1e4) {
            let v = fbm().value(Vec3::new(x as _, y as _, z as _));
            prop_assert!((0.0..=1.0).contains(&v));
        }
    }
}
