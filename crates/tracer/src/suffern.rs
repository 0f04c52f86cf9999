//! Suffern's regular-grid benchmark scene (*Ray Tracing from the Ground Up*,
//! ch. 22, Table 22.1): N random spheres of total volume 0.1 in the cube
//! `[−1, 1]³`, seen from far away, 400 × 400 pixels, 1 ray per pixel, no
//! shadows.
//!
//! The random numbers come from a portable 64-bit LCG, so the scene is the
//! same on every platform and matches the Embree peer program
//! (`shared/peers/embree/embree_bench.c`) draw for draw and bit for bit:
//! same draw order, same `f32` arithmetic. Its pixels-hit counts are
//! [`REFERENCE_PIXELS_HIT`].
//!
//! ```
//! use gridrt_tracer::suffern;
//! let scene = suffern::scene(10);
//! assert_eq!(scene.objects.len(), 1); // one set of ten spheres
//! let r = gridrt_tracer::Renderer::new(&scene, &Default::default()).unwrap();
//! assert_eq!(r.count_camera_hits(), 16972);
//! ```

use crate::scene::{
    Camera, Geometry, Light, Material, Object, Projection, Rgb, Scene, Settings, SphereColors,
};
use crate::{RenderOptions, Renderer, SceneError, Sphere, SphereSet};
use gridrt_bbox::{Real, Vec3};
use std::sync::Arc;

/// The seed of the benchmark scene.
pub const DEFAULT_SEED: u64 = 15;

/// Pixels hit by camera rays in the benchmark scene (seed 15), from the
/// Embree peer, for N = 10 … 1,000,000.
pub const REFERENCE_PIXELS_HIT: [(usize, u64); 6] = [
    (10, 16_972),
    (100, 35_175),
    (1_000, 64_037),
    (10_000, 100_193),
    (100_000, 129_241),
    (1_000_000, 139_028),
];

/// Image side in pixels.
pub const RESOLUTION: u32 = 400;

/// The benchmark's random numbers: a 64-bit LCG with Knuth's MMIX constants,
/// `state ← state · 6364136223846793005 + 1442695040888963407 (mod 2⁶⁴)`,
/// giving `u = (state >> 40) / 2²⁴` in `[0, 1)` (24 bits, exact in `f32`).
///
/// ```
/// use gridrt_tracer::suffern::Lcg;
/// let mut rng = Lcg::new(15);
/// let u = rng.next_f32();
/// assert!((0.0..1.0).contains(&u));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lcg {
    state: u64,
}

impl Lcg {
    const MUL: u64 = 6_364_136_223_846_793_005;
    const ADD: u64 = 1_442_695_040_888_963_407;

    /// A generator with the given state.
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next number in `[0, 1)`.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        self.state = self.state.wrapping_mul(Self::MUL).wrapping_add(Self::ADD);
        (self.state >> 40) as f32 * (1.0 / 16_777_216.0)
    }

    /// Skips `k` draws in O(log k) steps (F. Brown, "Random number
    /// generation with arbitrary strides", 1994): `k` steps of the LCG are
    /// one affine map, composed here by repeated squaring.
    ///
    /// ```
    /// use gridrt_tracer::suffern::Lcg;
    /// let (mut a, mut b) = (Lcg::new(15), Lcg::new(15));
    /// for _ in 0..1000 {
    ///     a.next_f32();
    /// }
    /// b.skip(1000);
    /// assert_eq!(a, b);
    /// ```
    pub fn skip(&mut self, k: u64) {
        self.state = Steps::ONE.pow(k).apply(self.state);
    }

    /// The draws of a sphere's colour, the first of its draws ([`Lcg::color`]).
    const COLOR_DRAWS: u64 = 3;

    /// The draws of one sphere ([`Lcg::sphere`]).
    const SPHERE_DRAWS: u64 = 6;

    /// One sphere's [`Lcg::SPHERE_DRAWS`] draws: the colour (r, g, b), then
    /// the centre `x, y, z = 1 − 2u`, in that order, in `f32`.
    #[inline]
    fn sphere(&mut self) -> (Vec3, Rgb) {
        let color = self.color();
        (self.center(), color)
    }

    /// A sphere's first three draws: its colour.
    #[inline]
    fn color(&mut self) -> Rgb {
        let r = self.next_f32();
        let g = self.next_f32();
        let b = self.next_f32();
        Rgb::new(r, g, b)
    }

    /// A sphere's last three draws: its centre, `x, y, z = 1 − 2u`.
    #[inline]
    fn center(&mut self) -> Vec3 {
        let x = 1.0f32 - 2.0f32 * self.next_f32();
        let y = 1.0f32 - 2.0f32 * self.next_f32();
        let z = 1.0f32 - 2.0f32 * self.next_f32();
        Vec3::new(x as Real, y as Real, z as Real)
    }
}

/// The affine map `x ↦ mul·x + add (mod 2⁶⁴)` that some number of
/// [`Lcg`] steps apply to its state (F. Brown, "Random number generation
/// with arbitrary strides", 1994): `k` steps compose into one such map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Steps {
    mul: u64,
    add: u64,
}

impl Steps {
    /// No step.
    const NONE: Self = Self { mul: 1, add: 0 };
    /// One step.
    const ONE: Self = Self {
        mul: Lcg::MUL,
        add: Lcg::ADD,
    };

    /// These steps, then `next`.
    #[inline]
    fn then(self, next: Self) -> Self {
        Self {
            mul: next.mul.wrapping_mul(self.mul),
            add: next.mul.wrapping_mul(self.add).wrapping_add(next.add),
        }
    }

    /// These steps taken `k` times, by repeated squaring: O(log k).
    fn pow(self, mut k: u64) -> Self {
        let (mut acc, mut sq) = (Self::NONE, self);
        while k > 0 {
            if k & 1 == 1 {
                acc = acc.then(sq);
            }
            sq = sq.then(sq);
            k >>= 1;
        }
        acc
    }

    #[inline]
    fn apply(self, state: u64) -> u64 {
        self.mul.wrapping_mul(state).wrapping_add(self.add)
    }
}

/// The random colours of a [`sphere_set`], drawn when asked rather than
/// stored: sphere `i`'s colour is the LCG's draws `6i`, `6i + 1`, `6i + 2`
/// from the seed, the very numbers [`spheres`] gives it.
///
/// The state before sphere `i`'s draws is the seed moved by `6i` steps,
/// one affine map, composed from tables of the maps of `6·j·256^l` steps
/// (`j < 256`, one table per byte of the largest index: 4 KiB each, three
/// for a million spheres). A colour then costs a load and a multiply–add
/// per byte and three draws, where a stored table costs 12 bytes a sphere
/// (12 MB of fresh memory for a million) and a cache miss per shading
/// lookup.
///
/// ```
/// use gridrt_tracer::suffern::{spheres, DrawnColors};
/// let colors = DrawnColors::new(15, 1000);
/// let drawn = spheres(1000, 15);
/// assert_eq!(colors.get(999), Some(drawn[999].color));
/// assert_eq!(colors.get(1000), None);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DrawnColors {
    seed: u64,
    len: usize,
    /// `jumps[l][j]`: the steps of `j·256^l` spheres.
    jumps: Box<[[Steps; 256]]>,
}

impl DrawnColors {
    /// The colours of the first `len` spheres for `seed`.
    #[must_use]
    pub fn new(seed: u64, len: usize) -> Self {
        // One level per byte of the largest index (at least one).
        let largest = len.saturating_sub(1) as u64;
        let levels = (1..8).find(|&l| largest >> (8 * l) == 0).unwrap_or(8);
        let mut jumps = vec![[Steps::NONE; 256]; levels].into_boxed_slice();
        let mut unit = Steps::ONE.pow(Lcg::SPHERE_DRAWS);
        for level in jumps.iter_mut() {
            for j in 1..256 {
                level[j] = level[j - 1].then(unit);
            }
            unit = level[255].then(unit);
        }
        Self { seed, len, jumps }
    }

    /// How many spheres have a colour.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no sphere has a colour.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Sphere `i`'s colour, or `None` past the last sphere.
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize) -> Option<Rgb> {
        if i >= self.len {
            return None;
        }
        let mut state = self.seed;
        let mut k = i;
        for level in &*self.jumps {
            state = level[k & 255].apply(state);
            k >>= 8;
        }
        Some(Lcg::new(state).color())
    }
}

/// The common radius of `n` spheres of total volume 0.1, computed in `f32`
/// exactly as the book and the Embree peer do:
/// `powf(0.75 · (0.1 / n) / 3.14159, 0.333333)`.
///
/// # Panics
/// Debug builds assert `n > 0`.
#[must_use]
#[allow(clippy::approx_constant)] // the book's 3.14159, on purpose
pub fn sphere_radius(n: usize) -> f32 {
    debug_assert!(n > 0, "at least one sphere");
    let volume = 0.1f32 / n as f32;
    (0.75f32 * volume / 3.14159f32).powf(0.333_333f32)
}

/// One sphere of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomSphere {
    /// Centre, uniform in `[−1, 1]³`.
    pub center: Vec3,
    /// Radius ([`sphere_radius`]).
    pub radius: Real,
    /// Colour: the first three draws.
    pub color: Rgb,
}

/// The `n` spheres for a seed: per sphere, three draws for the colour (r, g,
/// b), then `x, y, z = 1 − 2u`, in that order, in `f32`.
#[must_use]
pub fn spheres(n: usize, seed: u64) -> Vec<RandomSphere> {
    let mut rng = Lcg::new(seed);
    let radius = sphere_radius(n.max(1)) as Real;
    (0..n)
        .map(|_| {
            let (center, color) = rng.sphere();
            RandomSphere {
                center,
                radius,
                color,
            }
        })
        .collect()
}

/// The `n` spheres for a seed as a [`SphereSet`] with the random colours
/// (the same numbers as [`spheres`], without the detour through a vector
/// of [`RandomSphere`]; the colours as [`DrawnColors`], computed when
/// asked).
///
/// Each LCG step waits for the one before, so one sequence is drawn as
/// four independent ones, each started with [`Lcg::skip`] at its share
/// of the spheres and stepped in turn, which lets the processor overlap
/// them: the same numbers in the same places.
#[must_use]
pub fn sphere_set(n: usize, seed: u64) -> SphereSet {
    sphere_set_threads(n, seed, 1)
}

/// [`sphere_set`] on up to `threads` threads, each drawing its share of
/// the spheres from its own [`Lcg::skip`] start: the same set whatever the
/// thread count.
///
/// ```
/// use gridrt_tracer::suffern::{sphere_set, sphere_set_threads};
/// let (a, b) = (sphere_set(1000, 15), sphere_set_threads(1000, 15, 3));
/// assert_eq!(a, b);
/// ```
#[must_use]
pub fn sphere_set_threads(n: usize, seed: u64, threads: usize) -> SphereSet {
    let radius = sphere_radius(n.max(1)) as Real;
    // Below this many spheres per thread a thread costs more than it saves.
    const MIN_SHARE: usize = 1 << 15;
    let parts = threads.min(n / MIN_SHARE).max(1);
    let mut spheres: Vec<Sphere> = gridrt_grid::mem::with_capacity(n);
    {
        let mut s = &mut spheres.spare_capacity_mut()[..n];
        std::thread::scope(|scope| {
            for p in 0..parts {
                let (start, end) = (n * p / parts, n * (p + 1) / parts);
                let (sp, st) = std::mem::take(&mut s).split_at_mut(end - start);
                s = st;
                let mut fill = move || draw(seed, start, radius, sp);
                if p + 1 == parts {
                    fill();
                } else {
                    scope.spawn(fill);
                }
            }
        });
    }
    // SAFETY: the parts cover `0..n` and `draw` writes every element of
    // its part.
    unsafe {
        spheres.set_len(n);
    }
    SphereSet {
        spheres,
        colors: SphereColors::Drawn(DrawnColors::new(seed, n)),
    }
}

/// Writes spheres `start..start + s.len()` of the sequence into `s`, in
/// [`LANES`] interleaved lanes (stepping over their colours' draws).
fn draw(seed: u64, start: usize, radius: Real, s: &mut [std::mem::MaybeUninit<Sphere>]) {
    let n = s.len();
    let share = n.div_ceil(LANES);
    let color_draws = Steps::ONE.pow(Lcg::COLOR_DRAWS);
    let mut lanes: [Lcg; LANES] = std::array::from_fn(|l| {
        let mut rng = Lcg::new(seed);
        rng.skip(Lcg::SPHERE_DRAWS * (start + l * share) as u64);
        rng
    });
    for i in 0..share {
        for (l, rng) in lanes.iter_mut().enumerate() {
            let k = l * share + i;
            if k < n {
                rng.state = color_draws.apply(rng.state);
                s[k].write(Sphere::new(rng.center(), radius));
            }
        }
    }
}

/// Independent LCG sequences [`sphere_set`] interleaves.
const LANES: usize = 4;

/// The benchmark for `n` spheres, drawn on the options' threads
/// ([`sphere_set_threads`]), ready to render: the same scene as
/// [`scene`].
///
/// # Errors
/// None in practice (the scene is valid); the signature is that of
/// [`Renderer::new`].
pub fn renderer(n: usize, seed: u64, options: &RenderOptions) -> Result<Renderer, SceneError> {
    let threads = options
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    Renderer::new(&scene_of(sphere_set_threads(n, seed, threads)), options)
}

fn matte(color: Rgb) -> Material {
    Material::Matte {
        color,
        ka: 0.25,
        kd: 0.75,
    }
}

/// The benchmark camera: eye (0, 0, 20) looking at the origin, up +y, view
/// plane at distance 3600 with pixels of size 1.
#[must_use]
pub fn camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 20.0),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::ViewPlane {
            distance: 3600.0,
            pixel_size: 1.0,
        },
        lens: None,
    }
}

/// The whole benchmark scene for `n` spheres with the default seed.
#[must_use]
pub fn scene(n: usize) -> Scene {
    scene_with_seed(n, DEFAULT_SEED)
}

/// The benchmark scene for `n` spheres and a seed: 400 × 400, 1 spp, the
/// [`camera`], black background, an ambient light (white, 1) and a
/// directional light from (−10, 20, 20) of radiance 3 that casts no
/// shadows; one object, the [`sphere_set`], of a white matte material
/// (`ka` 0.25, `kd` 0.75) that each sphere's random colour tints.
#[must_use]
pub fn scene_with_seed(n: usize, seed: u64) -> Scene {
    scene_of(sphere_set(n, seed))
}

/// The benchmark scene around a set of spheres (see [`scene_with_seed`]).
#[must_use]
pub fn scene_of(set: SphereSet) -> Scene {
    Scene {
        textures: Default::default(),
        camera: camera(),
        settings: Settings {
            width: RESOLUTION,
            height: RESOLUTION,
            spp: 1,
            max_depth: 0,
            background: Rgb::ZERO,
            // As a scene file's `max_depth: 0` sets both depths.
            path_max_depth: 0,
            ..Settings::default()
        },
        materials: vec![matte(Rgb::ONE)],
        lights: vec![
            Light::Ambient {
                color: Rgb::ONE,
                intensity: 1.0,
                occlusion: None,
            },
            Light::Directional {
                direction: Vec3::new(-10.0, 20.0, 20.0),
                color: Rgb::ONE,
                intensity: 3.0,
                shadows: false,
            },
        ],
        objects: vec![Object {
            geometry: Geometry::Spheres(Arc::new(set)),
            material: 0,
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lcg_matches_the_peer() {
        // state1 = 15·a + c (mod 2^64), computed by hand with u128.
        let a: u128 = 6_364_136_223_846_793_005;
        let c: u128 = 1_442_695_040_888_963_407;
        let s1 = ((15 * a + c) % (1u128 << 64)) as u64;
        let mut rng = Lcg::new(15);
        assert_eq!(rng.next_f32(), (s1 >> 40) as f32 / 16_777_216.0);
    }

    #[test]
    fn skip_is_stepping() {
        for k in [0u64, 1, 2, 3, 6, 7, 64, 1000, 12_345] {
            let mut a = Lcg::new(DEFAULT_SEED);
            for _ in 0..k {
                a.next_f32();
            }
            let mut b = Lcg::new(DEFAULT_SEED);
            b.skip(k);
            assert_eq!(a, b, "k = {k}");
        }
    }

    #[test]
    fn drawn_colours_are_the_draws_at_any_index() {
        let len = (1 << 24) + 7;
        let colors = DrawnColors::new(DEFAULT_SEED, len);
        for i in [
            0,
            1,
            2,
            255,
            256,
            257,
            65_535,
            65_536,
            999_999,
            1 << 24,
            len - 1,
        ] {
            let mut rng = Lcg::new(DEFAULT_SEED);
            rng.skip(Lcg::SPHERE_DRAWS * i as u64);
            assert_eq!(colors.get(i), Some(rng.color()), "sphere {i}");
        }
        assert_eq!(colors.get(len), None);
        assert_eq!(DrawnColors::new(DEFAULT_SEED, 0).get(0), None);
        assert_eq!(DrawnColors::new(DEFAULT_SEED, 1).jumps.len(), 1);
        assert_eq!(DrawnColors::new(DEFAULT_SEED, 257).jumps.len(), 2);
    }

    #[test]
    fn the_interleaved_set_is_the_sequence() {
        for (n, threads) in [
            (0usize, 1usize),
            (1, 1),
            (2, 1),
            (3, 1),
            (4, 1),
            (5, 1),
            (7, 1),
            (8, 1),
            (9, 1),
            (1001, 1),
            (1001, 4),
            (100_003, 3),
        ] {
            let set = sphere_set_threads(n, DEFAULT_SEED, threads);
            let want = spheres(n, DEFAULT_SEED);
            assert_eq!(set.spheres.len(), n);
            assert_eq!(set.colors.get(n), None);
            for (k, w) in want.iter().enumerate() {
                assert_eq!(set.spheres[k].center, w.center, "n = {n}, sphere {k}");
                assert_eq!(set.spheres[k].radius, w.radius);
                assert_eq!(set.colors.get(k), Some(w.color), "n = {n}, sphere {k}");
            }
        }
    }

    #[test]
    fn radius_gives_total_volume_0_1() {
        for n in [10usize, 1000, 1_000_000] {
            let r = f64::from(sphere_radius(n));
            let vol = n as f64 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
            assert!((vol - 0.1).abs() < 1e-4, "n = {n}: {vol}");
        }
    }

    #[test]
    fn centres_are_in_the_cube() {
        let s = spheres(1000, DEFAULT_SEED);
        assert!(s.iter().all(|s| s.center.abs().max_element() <= 1.0));
        assert!(s
            .iter()
            .all(|s| s.color.min_element() >= 0.0 && s.color.max_element() < 1.0));
        // Reproducible.
        assert_eq!(s, spheres(1000, DEFAULT_SEED));
        let set = sphere_set(1000, DEFAULT_SEED);
        for (k, (a, b)) in s.iter().zip(&set.spheres).enumerate() {
            assert_eq!(
                (a.center, a.radius, Some(a.color)),
                (b.center, b.radius, set.colors.get(k))
            );
        }
    }
}
