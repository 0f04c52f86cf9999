//! Textures at a hit: what the render loop's shading reads (albedo,
//! emission, perturbed shading normal) and the alpha test that lets rays
//! pass through cut-outs.

use super::{lookup, AlphaMode, MaterialMaps, TexQuery, Texture};
use crate::float::to_f32;
use crate::scene::Rgb;
use gridrt_bbox::{Ray, Real, Vec3};

/// A mesh triangle's texture-space frame: the position derivatives along
/// `u` and `v`, and how many texture units one world unit spans (the
/// square root of the ratio of the triangle's areas in the two spaces).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct TriFrame {
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub density: f32,
}

impl TriFrame {
    /// The frame of triangle `p` with texture coordinates `uv` (zero
    /// derivatives when the coordinates are degenerate).
    pub(crate) fn new(p: [Vec3; 3], uv: [glam::Vec2; 3]) -> Self {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let det = d1.x * d2.y - d2.x * d1.y;
        let world_area = to_f32(e1.cross(e2).length());
        let density = if world_area > 0.0 && det.is_finite() {
            (det.abs() / world_area).sqrt()
        } else {
            0.0
        };
        if det == 0.0 || !det.is_finite() {
            return Self {
                density,
                ..Self::default()
            };
        }
        let inv = 1.0 / det as Real;
        let (du1, dv1, du2, dv2) = (d1.x as Real, d1.y as Real, d2.x as Real, d2.y as Real);
        Self {
            dpdu: (e1 * dv2 - e2 * dv1) * inv,
            dpdv: (e2 * du1 - e1 * du2) * inv,
            density,
        }
    }
}

/// A hit's texture coordinates (both sets) and its triangle's texture
/// frame (of the first set: footprints and tangent frames use it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HitUv {
    pub uv: [glam::Vec2; 2],
    pub frame: TriFrame,
}

/// The scene's textures as shading reads them.
#[derive(Clone, Debug, Default)]
pub(crate) struct TextureData {
    pub list: Vec<Texture>,
    /// One entry per material; `None` for materials without active maps.
    /// Empty when no material has any.
    pub maps: Vec<Option<MaterialMaps>>,
    /// A pixel's footprint at distance `d` along a unit ray is
    /// `footprint[0] + footprint[1]·d` world units.
    pub footprint: [f32; 2],
    /// Whether some material tests alpha (rays then skip cut-outs).
    pub alpha: bool,
}

impl TextureData {
    /// Whether some material has active maps.
    #[inline]
    pub(crate) fn any(&self) -> bool {
        !self.maps.is_empty()
    }

    /// The maps of material `m`, if it has any.
    #[inline]
    pub(crate) fn of(&self, m: u32) -> Option<&MaterialMaps> {
        self.maps.get(m as usize).and_then(Option::as_ref)
    }

    /// The query at a hit `t` along `ray` with geometric normal `ng`.
    pub(crate) fn query(
        &self,
        ray: &Ray,
        t: Real,
        p: Vec3,
        ng: Vec3,
        uv: Option<HitUv>,
    ) -> TexQuery {
        let len = to_f32(ray.dir.length());
        let world = self.footprint[0] + self.footprint[1] * to_f32(t) * len;
        let cos = if len > 0.0 {
            (to_f32(ray.dir.dot(ng)) / len).abs()
        } else {
            1.0
        };
        // A grazing footprint is stretched along one axis; the isotropic
        // lookup takes the geometric mean of the two widths.
        let width = match uv {
            Some(h) => world * h.frame.density / cos.max(1e-2).sqrt(),
            None => 0.0,
        };
        let [uv, uv1] = uv.map_or([glam::Vec2::ZERO; 2], |h| h.uv);
        TexQuery { uv, uv1, p, width }
    }

    /// The alpha of material `maps` at `q`.
    pub(crate) fn alpha(&self, maps: &MaterialMaps, q: &TexQuery) -> f32 {
        let mut a = maps.alpha;
        if let Some(t) = maps.base_color.and_then(|r| lookup(&self.list, &r, q)) {
            a *= t[3];
        }
        if let Some(t) = maps.opacity.and_then(|r| lookup(&self.list, &r, q)) {
            a *= t[0];
        }
        a
    }

    /// Whether a ray passes through the hit at `t` (a cut-out, or the
    /// transmitted share of a blended surface).
    pub(crate) fn passes(&self, maps: &MaterialMaps, q: &TexQuery, ray: &Ray, t: Real) -> bool {
        match maps.alpha_mode {
            AlphaMode::Opaque => false,
            AlphaMode::Mask { cutoff } => self.alpha(maps, q) < cutoff,
            AlphaMode::Blend => self.alpha(maps, q) < hash01(ray, t),
        }
    }
}

/// What textures change at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Textured {
    /// The albedo, when a base-colour map applies.
    pub albedo: Option<Rgb>,
    /// Emitted radiance (zero when nothing emits).
    pub emission: Rgb,
    /// The shading normal after normal or bump mapping.
    pub ns: Vec3,
}

/// Applies `maps` at `q`: `base` is the albedo before texturing, `ns` the
/// shading normal and `ng` the geometric one (both outward), `frame` the
/// triangle's texture frame when it has texture coordinates.
pub(crate) fn apply(
    data: &TextureData,
    maps: &MaterialMaps,
    q: &TexQuery,
    base: Rgb,
    ns: Vec3,
    ng: Vec3,
    frame: Option<TriFrame>,
) -> Textured {
    let albedo = maps
        .base_color
        .and_then(|r| lookup(&data.list, &r, q))
        .map(|t| base * Rgb::new(t[0], t[1], t[2]));
    let emission = match maps.emissive {
        Some(r) => lookup(&data.list, &r, q).map_or(Rgb::ZERO, |t| {
            maps.emissive_factor * Rgb::new(t[0], t[1], t[2])
        }),
        None => maps.emissive_factor,
    };
    let mut n = ns;
    if let Some(f) = frame.filter(|f| f.dpdu != Vec3::ZERO) {
        if let Some(t) = maps.normal.and_then(|r| lookup(&data.list, &r, q)) {
            n = normal_mapped(t, maps.normal_scale, ns, f).unwrap_or(ns);
        } else if let Some(r) = maps.bump {
            n = bumped(data, &r, maps.bump_scale, q, ns, f).unwrap_or(ns);
        }
        // A perturbed normal that dips below the surface would light the
        // back: keep the unperturbed one there.
        if n.dot(ng) <= 0.0 {
            n = ns;
        }
    }
    Textured {
        albedo,
        emission,
        ns: n,
    }
}

/// The shading normal from a tangent-space normal-map texel.
fn normal_mapped(t: [f32; 4], scale: f32, ns: Vec3, f: TriFrame) -> Option<Vec3> {
    let x = (2.0 * t[0] - 1.0) * scale;
    let y = (2.0 * t[1] - 1.0) * scale;
    let z = 2.0 * t[2] - 1.0;
    let tangent = (f.dpdu - ns * ns.dot(f.dpdu)).try_normalize()?;
    // +Y of the map points along decreasing v (texture rows grow downwards).
    let b = -f.dpdv;
    let mut bitangent = ns.cross(tangent);
    if bitangent.dot(b) < 0.0 {
        bitangent = -bitangent;
    }
    (tangent * x as Real + bitangent * y as Real + ns * z as Real).try_normalize()
}

/// The shading normal displaced by a height map (pbrt's `BumpMap`, without
/// the normal's own derivatives): finite differences of the height, in
/// texture units, over about one texel or the footprint, whichever is larger.
fn bumped(
    data: &TextureData,
    r: &super::TextureRef,
    scale: f32,
    q: &TexQuery,
    ns: Vec3,
    f: TriFrame,
) -> Option<Vec3> {
    let texel = match data.list.get(r.texture as usize)? {
        Texture::Image(img) => 1.0 / img.size().0.max(img.size().1) as f32,
        _ => 1e-3,
    };
    let d = q.width.max(texel);
    let h = |du: f32, dv: f32| {
        let q = TexQuery {
            uv: q.uv + glam::Vec2::new(du, dv),
            uv1: q.uv1 + glam::Vec2::new(du, dv),
            ..*q
        };
        lookup(&data.list, r, &q).map_or(0.0, |t| t[0])
    };
    let h0 = h(0.0, 0.0);
    // Slopes in texture space; a step along u covers |dp/du| in world space.
    let hu = (h(d, 0.0) - h0) / d * scale;
    let hv = (h(0.0, d) - h0) / d * scale;
    let dpdu = f.dpdu + ns * (hu as Real * f.dpdu.length());
    let dpdv = f.dpdv + ns * (hv as Real * f.dpdv.length());
    let n = dpdu.cross(dpdv).try_normalize()?;
    Some(if n.dot(ns) < 0.0 { -n } else { n })
}

/// A number in [0, 1) that depends only on the ray and `t`: the threshold
/// of stochastic transparency, the same on every thread.
fn hash01(ray: &Ray, t: Real) -> f32 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let words = [
        ray.origin.x,
        ray.origin.y,
        ray.origin.z,
        ray.dir.x,
        ray.dir.y,
        ray.dir.z,
        t,
    ];
    for w in words {
        h ^= u64::from(to_f32(w).to_bits());
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
        h ^= h >> 29;
    }
    h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h ^= h >> 32;
    (h >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{ImageTexture, Sampler, TextureRef};
    use glam::Vec2;

    fn flat_frame() -> TriFrame {
        TriFrame::new(
            [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.0, -1.0)],
            [
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 0.0),
            ],
        )
    }

    #[test]
    fn frame_of_a_unit_triangle() {
        let f = flat_frame();
        assert!((f.dpdu - Vec3::X).length() < 1e-6);
        // v grows towards +z (down the image is towards the viewer).
        assert!((f.dpdv - Vec3::Z).length() < 1e-6);
        assert!((f.density - 1.0).abs() < 1e-6);
    }

    fn data_with(texel: [u8; 4]) -> TextureData {
        let img = ImageTexture::from_rgba8(1, 1, &texel, false, Sampler::DEFAULT).unwrap();
        TextureData {
            list: vec![Texture::Image(img.into())],
            maps: vec![],
            footprint: [0.0, 0.0],
            alpha: false,
        }
    }

    fn query() -> TexQuery {
        TexQuery {
            uv: Vec2::new(0.5, 0.5),
            uv1: Vec2::new(0.5, 0.5),
            p: Vec3::ZERO,
            width: 0.0,
        }
    }

    #[test]
    fn flat_normal_map_keeps_the_normal_and_tilted_ones_tilt_towards_u() {
        let maps = MaterialMaps {
            normal: Some(TextureRef::new(0)),
            ..MaterialMaps::default()
        };
        let flat = data_with([128, 128, 255, 255]);
        let t = apply(
            &flat,
            &maps,
            &query(),
            Rgb::ONE,
            Vec3::Y,
            Vec3::Y,
            Some(flat_frame()),
        );
        assert!((t.ns - Vec3::Y).length() < 0.01, "{}", t.ns);
        let tilted = data_with([255, 128, 128, 255]);
        let t = apply(
            &tilted,
            &maps,
            &query(),
            Rgb::ONE,
            Vec3::Y,
            Vec3::Y,
            Some(flat_frame()),
        );
        assert!(t.ns.x > 0.9, "{}", t.ns);
        // Map +Y is along decreasing v, which is −z here.
        let up = data_with([128, 255, 128, 255]);
        let t = apply(
            &up,
            &maps,
            &query(),
            Rgb::ONE,
            Vec3::Y,
            Vec3::Y,
            Some(flat_frame()),
        );
        assert!(t.ns.z < -0.9, "{}", t.ns);
    }

    #[test]
    fn base_colour_multiplies_and_emission_scales() {
        let d = data_with([255, 0, 255, 255]);
        let maps = MaterialMaps {
            base_color: Some(TextureRef::new(0)),
            emissive: Some(TextureRef::new(0)),
            emissive_factor: Rgb::splat(2.0),
            ..MaterialMaps::default()
        };
        let t = apply(&d, &maps, &query(), Rgb::splat(0.5), Vec3::Y, Vec3::Y, None);
        assert_eq!(t.albedo, Some(Rgb::new(0.5, 0.0, 0.5)));
        assert_eq!(t.emission, Rgb::new(2.0, 0.0, 2.0));
    }

    #[test]
    fn mask_and_blend_follow_alpha() {
        let d = data_with([255, 255, 255, 64]);
        let mut maps = MaterialMaps {
            base_color: Some(TextureRef::new(0)),
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..MaterialMaps::default()
        };
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(d.passes(&maps, &query(), &ray, 1.0));
        maps.alpha_mode = AlphaMode::Mask { cutoff: 0.2 };
        assert!(!d.passes(&maps, &query(), &ray, 1.0));
        maps.alpha_mode = AlphaMode::Opaque;
        assert!(!d.passes(&maps, &query(), &ray, 1.0));
        // Blend: about 1 − 64/255 of many rays pass.
        maps.alpha_mode = AlphaMode::Blend;
        let n = 4000;
        let passed = (0..n)
            .filter(|&i| {
                let r = Ray::new(Vec3::new(i as Real * 0.01, 0.0, 0.0), Vec3::Z);
                d.passes(&maps, &query(), &r, 1.0)
            })
            .count();
        let share = passed as f32 / n as f32;
        assert!((share - (1.0 - 64.0 / 255.0)).abs() < 0.03, "{share}");
    }
}
