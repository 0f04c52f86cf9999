//! What robustness costs: `Aabb::hit` (parallel slabs tested directly, no
//! `0·∞ = NaN`, exit widened by 2·γ(3)) against the textbook slab test
//! (Williams et al. 2005 / Suffern's `BBox::hit`: reciprocals straight into
//! min/max, no special cases), on the same seeded rays and boxes.
//!
//! Run with `cargo bench -p gridrt-bbox` (add `--features f64` for doubles).
//! Each iteration tests every ray against every box of a small array, so the
//! numbers are throughput; about half of the tests hit.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use gridrt_bbox::{Aabb, Ray, Real, Vec3};

const RAYS: usize = 256;
const BOXES: usize = 64;

/// SplitMix64 (Steele, Lea & Flood 2014): seeded inputs without an RNG crate.
struct SplitMix64(u64);

impl SplitMix64 {
    fn unit(&mut self) -> Real {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as Real / (1u64 << 24) as Real
    }

    fn vec(&mut self, lo: Real, hi: Real) -> Vec3 {
        let mut c = || lo + (hi - lo) * self.unit();
        Vec3::new(c(), c(), c())
    }
}

/// The textbook slab test: no handling of zero direction components (an
/// origin on a slab plane gives `0·∞ = NaN`), no widening of the exit.
#[inline]
fn naive_hit(b: &Aabb, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
    b.hit_textbook(ray, t_min, t_max)
}

fn inputs() -> (Vec<Ray>, Vec<Aabb>) {
    let mut rng = SplitMix64(0x736c_6162);
    let rays = (0..RAYS)
        .map(|_| {
            let target = rng.vec(-1.0, 1.0);
            let origin = rng.vec(-4.0, 4.0) + Vec3::new(0.0, 0.0, 6.0);
            Ray::new(origin, target - origin)
        })
        .collect();
    let boxes = (0..BOXES)
        .map(|_| {
            let c = rng.vec(-1.0, 1.0);
            let h = rng.vec(0.2, 0.8);
            Aabb::new(c - h, c + h)
        })
        .collect();
    (rays, boxes)
}

fn slab(c: &mut Criterion) {
    let (rays, boxes) = inputs();
    let hits_of = |f: &dyn Fn(&Aabb, &Ray) -> bool| {
        rays.iter()
            .flat_map(|r| boxes.iter().map(move |b| (b, r)))
            .filter(|(b, r)| f(b, r))
            .count()
    };
    let robust = hits_of(&|b, r| b.hit(r, 0.0, Real::INFINITY).is_some());
    let naive = hits_of(&|b, r| naive_hit(b, r, 0.0, Real::INFINITY).is_some());
    // Same answers on these generic inputs: the difference is only in the
    // hard cases (tests/slab.rs), so the timing compares like with like.
    assert_eq!(robust, naive, "the two slab tests disagree on generic rays");

    let mut g = c.benchmark_group("slab");
    g.throughput(Throughput::Elements((RAYS * BOXES) as u64));
    g.bench_function("robust (Aabb::hit)", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in black_box(&rays) {
                for bx in black_box(&boxes) {
                    n += u32::from(bx.hit(r, 0.0, Real::INFINITY).is_some());
                }
            }
            n
        });
    });
    g.bench_function("naive (textbook)", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in black_box(&rays) {
                for bx in black_box(&boxes) {
                    n += u32::from(naive_hit(bx, r, 0.0, Real::INFINITY).is_some());
                }
            }
            n
        });
    });
    g.finish();
}

criterion_group!(benches, slab);
criterion_main!(benches);
