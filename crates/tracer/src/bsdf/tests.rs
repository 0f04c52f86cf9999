//! Energy, density and sampling checks of the microfacet BSDFs.

use super::*;
use crate::float::to_f64;
use crate::hard_meshes::SplitMix;
use crate::sampling::maps::uniform_sphere;

const PI: f64 = std::f64::consts::PI;

/// A stratified `n × n` grid of the unit square (fixed, no seed needed).
fn grid(n: u32) -> impl Iterator<Item = (Real, Real)> {
    (0..n * n).map(move |i| {
        (
            ((i / n) as Real + 0.5) / n as Real,
            ((i % n) as Real + 0.5) / n as Real,
        )
    })
}

/// A fixed-seed stream of numbers in [0, 1): the top 24 bits of the
/// random meshes' SplitMix64.
struct Rng(SplitMix);

impl Rng {
    fn next(&mut self) -> Real {
        ((self.0.next() >> 40) as f64 / (1u64 << 24) as f64) as Real
    }
}

fn dir(theta_deg: f64) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin() as Real, 0.0, t.cos() as Real)
}

fn conductor(f0: Rgb, roughness: f32) -> Micro {
    Micro::Conductor {
        ggx: Ggx::from_roughness(roughness),
        fresnel: ConductorFresnel::Schlick { f0 },
    }
}

fn glass(roughness: f32) -> Micro {
    Micro::Glass {
        ggx: Ggx::from_roughness(roughness),
        eta: 1.5,
    }
}

/// The ratio of the index on `wi`'s side to the one on `wo`'s side.
fn etap(b: &Micro, wo: Vec3, wi: Vec3) -> f64 {
    match *b {
        Micro::Glass { eta, .. } if wo.z * wi.z < 0.0 => {
            if wo.z > 0.0 {
                to_f64(eta)
            } else {
                1.0 / to_f64(eta)
            }
        }
        _ => 1.0,
    }
}

/// The directional albedo `∫ f |cos θi| dωi` by sampling (transmission
/// counted as energy, i.e. without its `1/η'²` radiance scale), the mean
/// sampled direction and the fraction of samples that succeeded.
fn sampled(b: &Micro, wo: Vec3, n: u32) -> (f64, Vec3, f64) {
    let mut rng = Rng(SplitMix(7));
    let (mut albedo, mut mean, mut ok) = (0.0, Vec3::ZERO, 0u32);
    for u in grid(n) {
        let Some(s) = b.sample(wo, rng.next(), u) else {
            continue;
        };
        ok += 1;
        mean += s.wi;
        let w = if s.delta {
            f64::from(s.f.x)
        } else {
            f64::from(s.f.x) * to_f64(s.wi.z.abs() / s.pdf)
        };
        let e = etap(b, wo, s.wi);
        albedo += w * e * e;
    }
    let total = f64::from(n * n);
    (albedo / total, mean / total as Real, f64::from(ok) / total)
}

/// `∫ pdf dωi`, `∫ ωi pdf dωi` and the albedo `∫ f |cos| dωi` (as in
/// [`sampled`]) by quadrature over the sphere.
fn quadrature(b: &Micro, wo: Vec3, n: u32) -> (f64, Vec3, f64) {
    let dw = 4.0 * PI / f64::from(n * n);
    let (mut mass, mut mean, mut albedo) = (0.0, Vec3::ZERO, 0.0);
    for u in grid(n) {
        let wi = uniform_sphere(u);
        let (f, pdf) = b.eval(wo, wi);
        mass += to_f64(pdf) * dw;
        mean += wi * (to_f64(pdf) * dw) as Real;
        let e = etap(b, wo, wi);
        albedo += f64::from(f.x) * to_f64(wi.z.abs()) * dw * e * e;
    }
    (mass, mean, albedo)
}

#[test]
fn a_white_conductor_creates_no_energy() {
    // F0 = 1: Fresnel is 1 everywhere, so the directional albedo is the
    // microfacet model's own (single scattering loses some, never gains).
    for roughness in [0.1f32, 0.4, 0.7, 1.0] {
        for theta in [0.0, 30.0, 60.0, 80.0] {
            let b = conductor(Rgb::ONE, roughness);
            let (albedo, _, _) = sampled(&b, dir(theta), 128);
            assert!(albedo <= 1.01, "r {roughness} θ {theta}: {albedo}");
            // α = 1 at normal incidence loses most (half the sampled
            // normals reflect below the horizon).
            assert!(albedo > 0.25, "r {roughness} θ {theta}: {albedo}");
            if roughness <= 0.1 && theta <= 60.0 {
                assert!(albedo > 0.97, "r {roughness} θ {theta}: {albedo}");
            }
        }
    }
}

#[test]
fn densities_integrate_to_the_share_of_successful_samples() {
    let cases = [
        (conductor(Rgb::splat(0.8), 0.5), dir(40.0)),
        (conductor(Rgb::splat(0.8), 0.9), dir(75.0)),
        (
            Micro::gltf(Rgb::new(0.8, 0.5, 0.2), 0.3, 0.5, dir(30.0).z),
            dir(30.0),
        ),
        (glass(0.5), dir(35.0)),
        (glass(0.5), -dir(20.0)),
    ];
    for (b, wo) in cases {
        let (mass, _, _) = quadrature(&b, wo, 700);
        let (_, _, ok) = sampled(&b, wo, 128);
        assert!(mass <= 1.01, "{b:?}: ∫pdf = {mass}");
        assert!(
            (mass - ok).abs() < 0.02,
            "{b:?}: ∫pdf = {mass}, sampled {ok}"
        );
        assert!(mass > 0.8, "{b:?}: ∫pdf = {mass}");
    }
}

#[test]
fn sampled_directions_follow_the_density_and_the_value() {
    // First moments: the mean sampled direction equals ∫ ωi pdf, and the
    // sampled albedo (Σ f cos / pdf) equals the quadrature of f cos.
    let cases = [
        (conductor(Rgb::new(0.9, 0.6, 0.3), 0.6), dir(50.0)),
        (
            Micro::gltf(Rgb::new(0.7, 0.7, 0.7), 0.0, 0.6, dir(20.0).z),
            dir(20.0),
        ),
        (
            Micro::gltf(Rgb::new(0.9, 0.8, 0.2), 1.0, 0.4, dir(60.0).z),
            dir(60.0),
        ),
        (glass(0.6), dir(30.0)),
        (glass(0.6), -dir(50.0)),
    ];
    for (b, wo) in cases {
        let (mass, qmean, qalbedo) = quadrature(&b, wo, 700);
        let (salbedo, smean, ok) = sampled(&b, wo, 160);
        let qmean = qmean / mass as Real * ok as Real;
        assert!((qmean - smean).length() < 0.02, "{b:?}: {qmean} vs {smean}");
        assert!(
            (qalbedo - salbedo).abs() < 0.02,
            "{b:?}: {qalbedo} vs {salbedo}"
        );
    }
}

#[test]
fn vanishing_roughness_converges_to_the_mirror() {
    let f0 = Rgb::new(0.95, 0.64, 0.54);
    let wo = dir(45.0);
    let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
    let fresnel = ConductorFresnel::Schlick { f0 }.eval(to_f32(wo.z)).x;
    let mut last_spread = f64::INFINITY;
    for roughness in [0.3f32, 0.1, 0.05] {
        let b = conductor(f0, roughness);
        let mut rng = Rng(SplitMix(3));
        let (mut spread, mut albedo) = (0.0, 0.0);
        let n = 64;
        for u in grid(n) {
            let Some(s) = b.sample(wo, rng.next(), u) else {
                continue;
            };
            spread += to_f64(1.0 - s.wi.dot(mirror));
            albedo += f64::from(s.f.x) * to_f64(s.wi.z / s.pdf);
        }
        spread /= f64::from(n * n);
        albedo /= f64::from(n * n);
        assert!(spread < last_spread, "r {roughness}: {spread}");
        last_spread = spread;
        if roughness <= 0.05 {
            assert!(spread < 1e-4, "{spread}");
            assert!(
                (albedo - f64::from(fresnel)).abs() < 0.01,
                "{albedo} vs {fresnel}"
            );
        }
    }
    // Roughness 0 is the mirror itself.
    let s = conductor(f0, 0.0).sample(wo, 0.5, (0.5, 0.5)).unwrap();
    assert!(s.delta && (s.wi - mirror).length() < 1e-6);
    assert!((s.f.x - fresnel).abs() < 1e-6);
}

#[test]
fn rough_glass_is_reciprocal_and_conserves_energy() {
    let b = glass(0.4);
    let mut rng = Rng(SplitMix(11));
    let mut checked = 0;
    for _ in 0..400 {
        let wo = uniform_sphere((rng.next(), rng.next()));
        let wi = uniform_sphere((rng.next(), rng.next()));
        let (f1, _) = b.eval(wo, wi);
        let (f2, _) = b.eval(wi, wo);
        // f(ωo, ωi)·η(ωi)² = f(ωi, ωo)·η(ωo)² (radiance BSDFs).
        let side = |w: Vec3| if w.z > 0.0 { 1.0 } else { 1.5f64 };
        let a = f64::from(f1.x) * side(wi).powi(2);
        let c = f64::from(f2.x) * side(wo).powi(2);
        // In f32 the generalised half vector's denominator cancels
        // (ωi·ωm and ωo·ωm/η' have opposite signs in transmission).
        let tol = if cfg!(feature = "f64") { 1e-5 } else { 2e-2 };
        assert!(
            (a - c).abs() <= tol * a.max(c).max(1e-3),
            "{wo} {wi}: {a} vs {c}"
        );
        checked += usize::from(f1.x > 0.0);
    }
    assert!(checked > 50);
    for theta in [0.0, 40.0, 70.0] {
        for wo in [dir(theta), -dir(theta)] {
            let (albedo, _, _) = sampled(&b, wo, 128);
            assert!(albedo <= 1.01 && albedo > 0.8, "{wo}: {albedo}");
        }
    }
    // Smooth glass: reflection and transmission shares sum to 1.
    let (albedo, _, _) = sampled(&glass(0.0), dir(30.0), 64);
    assert!((albedo - 1.0).abs() < 1e-3, "{albedo}");
}
