//! The scene model: what `gridrt-io` fills in and the renderer reads.
//!
//! Positions are in world space (meshes arrive already transformed).
//! Right-handed coordinates, y up by convention of the cameras in fixtures.
//! Colours are linear RGB (`glam::Vec3`, always f32, whatever `Real` is).

use crate::sampling::{Filter, SamplerKind};
use crate::shapes::Sphere;
use crate::texture::Textures;
use gridrt_bbox::{Aabb, Real, Vec3};
use std::sync::Arc;

/// A linear-RGB colour (always f32).
pub type Rgb = glam::Vec3;

/// Index into [`Scene::materials`].
pub type MaterialId = u32;

/// Everything needed to render one image.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// Resolution, samples, depth, background.
    pub settings: Settings,
    /// Materials, referred to by index from objects.
    pub materials: Vec<Material>,
    /// Light sources (including ambient light).
    pub lights: Vec<Light>,
    /// Geometry, each with a material.
    pub objects: Vec<Object>,
    /// Textures and the maps that bind them to materials (empty: none).
    pub textures: Textures,
}

/// Render settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Image width in pixels (at least 1).
    pub width: u32,
    /// Image height in pixels (at least 1).
    pub height: u32,
    /// Samples per pixel (at least 1). One sample goes through the pixel centre.
    pub spp: u32,
    /// Longest chain of reflection/refraction bounces after the camera ray.
    pub max_depth: u32,
    /// Radiance of rays that hit nothing.
    pub background: Rgb,
    /// How pixel samples (and, when path tracing, every other sample
    /// dimension) are placed. Unused at 1 spp, where the sample goes
    /// through the pixel centre.
    pub sampler: SamplerKind,
    /// The reconstruction filter (unused at 1 spp).
    pub filter: Filter,
    /// The light transport algorithm.
    pub integrator: IntegratorChoice,
    /// Longest path of the path tracer, in bounces (default 64; Russian
    /// roulette ends most paths long before).
    pub path_max_depth: u32,
}

/// Which integrator renders a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IntegratorChoice {
    /// Path tracing when some object emits light or the scene has a
    /// rectangle or disk light (an area light), else
    /// Whitted (or plain ray casting when nothing reflects or refracts).
    #[default]
    Auto,
    /// Suffern's Whitted tracer: direct light from point, directional and
    /// ambient lights, perfect mirror reflection and refraction.
    Whitted,
    /// Path tracing: global illumination, area lights, soft shadows.
    Path,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            width: 400,
            height: 400,
            spp: 1,
            max_depth: 5,
            background: Rgb::ZERO,
            sampler: SamplerKind::default(),
            filter: Filter::default(),
            integrator: IntegratorChoice::Auto,
            path_max_depth: 64,
        }
    }
}

/// A camera: where it is, where it looks, and how it projects.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// The point the camera looks at (the view direction is `look_at − eye`).
    pub look_at: Vec3,
    /// Up vector (need not be orthogonal to the view direction, must not be parallel).
    pub up: Vec3,
    /// How image positions map to rays.
    pub projection: Projection,
    /// A thin lens for depth of field; `None` (or a radius of 0) is a
    /// pinhole, whose rays all start at the eye.
    pub lens: Option<ThinLens>,
}

/// A thin lens (pbrt's `ProjectiveCamera`): rays start on a disk of radius
/// `radius` about the eye, in the image plane, and pass through the point
/// where the pinhole ray meets the plane of focus, `focus_distance` in
/// front of the eye along the view direction. Only that plane is sharp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    /// The aperture's radius in world units (≥ 0; 0 is a pinhole).
    pub radius: Real,
    /// Distance from the eye to the plane in focus, along the view
    /// direction (> 0 when `radius` > 0).
    pub focus_distance: Real,
}

/// Camera projections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole camera with a vertical field of view in degrees.
    Perspective {
        /// Vertical field of view, degrees, in (0, 180).
        vfov_deg: Real,
    },
    /// Suffern's pinhole: a view plane at `distance` from the eye, pixels of
    /// `pixel_size` world units. The ray through pixel (c, r), r = 0 at the
    /// bottom, has direction `s·(c − w/2 + ½)·u + s·(r − h/2 + ½)·v − d·w`.
    ViewPlane {
        /// Eye to view-plane distance.
        distance: Real,
        /// Size of one pixel on the view plane.
        pixel_size: Real,
    },
    /// Parallel rays; `height` is the world-space height of the image.
    Orthographic {
        /// World-space height of the visible region.
        height: Real,
    },
}

/// A piece of geometry with its material.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The shape.
    pub geometry: Geometry,
    /// Index into [`Scene::materials`].
    pub material: MaterialId,
}

/// Shapes a scene can hold.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A sphere (radius > 0).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius, > 0.
        radius: Real,
    },
    /// An axis-aligned box.
    Cuboid {
        /// Smallest corner.
        min: Vec3,
        /// Largest corner.
        max: Vec3,
    },
    /// An infinite plane: kept outside the grid and tested separately.
    Plane {
        /// A point on the plane.
        point: Vec3,
        /// The normal (need not be unit length, must not be zero).
        normal: Vec3,
    },
    /// A triangle mesh in world space; each triangle goes into the grid.
    /// Shared, so that an `Object` stays small, cloning a scene does not
    /// copy the mesh, and the renderer shades from the mesh's own arrays
    /// (normals, colours, texture coordinates, indices) instead of copies.
    Mesh(Arc<Mesh>),
    /// Many spheres of the object's material, each with an optional colour
    /// of its own: one object for what would otherwise be one object and
    /// one material per sphere (Suffern's benchmark of a million spheres,
    /// `RandomSpheres` in a scene file). Shared, so that cloning a scene
    /// does not copy the spheres; each sphere is one grid primitive, in
    /// the set's order.
    Spheres(Arc<SphereSet>),
    /// A mesh in its own (object) space placed by a transform. Instances
    /// of one `Arc<Mesh>` share its arrays and, when there are several, one
    /// grid of its triangles, which rays enter through `to_world`'s
    /// inverse (Suffern's `Instance`, pbrt's object instances). A mirroring
    /// transform keeps the mesh's front faces (counter-clockwise winding)
    /// on the same side of the surface, as glTF asks.
    Instance {
        /// The mesh, shared with the other instances of it.
        mesh: Arc<Mesh>,
        /// Object to world (invertible, finite); boxed, so that an
        /// `Object` stays small.
        to_world: Box<crate::transform::Affine>,
    },
}

impl Geometry {
    /// The box around the geometry in world space ([`Aabb::EMPTY`] for a
    /// plane, which is unbounded, and for an empty mesh or set).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        match self {
            Geometry::Sphere { center, radius } => Aabb::new(
                *center - Vec3::splat(*radius),
                *center + Vec3::splat(*radius),
            ),
            Geometry::Cuboid { min, max } => Aabb::new(*min, *max),
            Geometry::Plane { .. } => Aabb::EMPTY,
            Geometry::Mesh(m) => m.bounds(),
            Geometry::Spheres(set) => set.bounds(),
            Geometry::Instance { mesh, to_world } => {
                let b = mesh.bounds();
                if b.is_empty() {
                    b
                } else {
                    to_world.bounds(&b)
                }
            }
        }
    }
}

/// The spheres of a [`Geometry::Spheres`] object: 16 bytes per sphere
/// (`f32`) and their colours, the representation from the scene loader to
/// the grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereSet {
    /// The spheres (radius > 0, finite).
    pub spheres: Vec<Sphere>,
    /// The colours that replace the albedo (`color`) of the object's
    /// material when it is Matte, Phong or Reflective, if any.
    pub colors: SphereColors,
}

/// The colours of a [`SphereSet`]'s spheres.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum SphereColors {
    /// None: the object's material colours every sphere.
    #[default]
    None,
    /// One colour per sphere (12 bytes each).
    Each(Vec<Rgb>),
    /// Suffern's random colours, drawn when asked (no bytes per sphere).
    Drawn(crate::suffern::DrawnColors),
}

impl SphereColors {
    /// Sphere `i`'s colour, or `None` when the set has none or `i` is past
    /// its last sphere.
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize) -> Option<Rgb> {
        match self {
            Self::None => None,
            Self::Each(v) => v.get(i).copied(),
            Self::Drawn(d) => d.get(i),
        }
    }

    /// The colours stored one per sphere: those of [`SphereColors::Each`],
    /// else none (drawn colours are computed, not stored).
    #[must_use]
    pub fn stored(&self) -> &[Rgb] {
        match self {
            Self::Each(v) => v,
            Self::None | Self::Drawn(_) => &[],
        }
    }

    /// How many spheres have a colour (0 for [`SphereColors::None`]).
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            Self::None => 0,
            Self::Each(v) => v.len(),
            Self::Drawn(d) => d.len(),
        }
    }

    /// Whether no sphere has a colour.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends the colours of spheres `0..n` to `out`, `otherwise` for each
    /// that has none.
    pub fn extend_into(&self, out: &mut Vec<Rgb>, n: usize, otherwise: Rgb) {
        out.reserve(n);
        out.extend((0..n).map(|i| self.get(i).unwrap_or(otherwise)));
    }
}

impl SphereSet {
    /// The box around every sphere ([`Aabb::EMPTY`] for an empty set).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.spheres.iter().fold(Aabb::EMPTY, |b, s| {
            b.union(Aabb::new(
                s.center - Vec3::splat(s.radius),
                s.center + Vec3::splat(s.radius),
            ))
        })
    }
}

/// A triangle mesh with shared vertex arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// A name for reports (file and group, or node and primitive).
    pub name: String,
    /// Vertex positions: world space, or object space for an instance.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals for smooth shading: empty, or one per position.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates: empty, or one per position. As in
    /// glTF, `(0, 0)` is the top-left corner of an image and `v` grows
    /// downwards (loaders of OBJ and PLY files flip their `v`).
    pub uvs: Vec<glam::Vec2>,
    /// A second texture-coordinate set, read by textures whose
    /// [`crate::TextureRef::set`] is 1: empty, or one per position.
    pub uvs1: Vec<glam::Vec2>,
    /// Per-vertex linear-RGB colours (PLY `red`, `green`, `blue`): empty,
    /// or one per position. Interpolated over each triangle, they replace
    /// the albedo of a Matte, Phong or Reflective material (a base-colour
    /// map then multiplies them).
    pub colors: Vec<Rgb>,
    /// Triangles as indices into `positions` (counter-clockwise = front).
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The box around the vertices that triangles use ([`Aabb::EMPTY`]
    /// without triangles; indices out of range are skipped).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.triangles
            .iter()
            .flatten()
            .filter_map(|&k| self.positions.get(k as usize))
            .fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }
}

/// Surface materials (Suffern's ray-cast and Whitted chapters).
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian: ambient `ka·color` plus diffuse `kd·color/π`.
    Matte {
        /// Albedo.
        color: Rgb,
        /// Ambient coefficient.
        ka: f32,
        /// Diffuse coefficient.
        kd: f32,
    },
    /// Matte plus a Phong glossy highlight `ks·(r·wo)^exp`.
    Phong {
        /// Diffuse albedo.
        color: Rgb,
        /// Ambient coefficient.
        ka: f32,
        /// Diffuse coefficient.
        kd: f32,
        /// Specular coefficient.
        ks: f32,
        /// Phong exponent.
        exp: f32,
        /// Colour of the highlight.
        specular: Rgb,
    },
    /// Phong plus perfect mirror reflection `kr·reflect`. With ka = kd = ks
    /// = 0 it is a perfect mirror.
    Reflective {
        /// Diffuse albedo.
        color: Rgb,
        /// Ambient coefficient.
        ka: f32,
        /// Diffuse coefficient.
        kd: f32,
        /// Specular coefficient.
        ks: f32,
        /// Phong exponent.
        exp: f32,
        /// Mirror reflectance.
        kr: f32,
        /// Colour of the mirror reflection.
        reflect: Rgb,
    },
    /// A smooth dielectric (glass, water): Fresnel-weighted reflection and
    /// refraction, total internal reflection, optional tint per unit length
    /// inside (Beer's law; white = clear).
    Dielectric {
        /// Index of refraction inside (outside is 1).
        ior: f32,
        /// Transmittance per unit distance inside.
        tint: Rgb,
    },
    /// A metal: GGX (Trowbridge–Reitz) microfacet reflection with Smith
    /// masking, weighted by the conductor's Fresnel term (pbrt-v4's
    /// `ConductorBxDF`). Roughness 0 is a perfect mirror.
    Conductor {
        /// The Fresnel term: an artist's colour at normal incidence, or a
        /// complex index of refraction.
        fresnel: ConductorFresnel,
        /// Perceptual roughness in `[0, 1]`; the GGX width is `α = roughness²`.
        roughness: f32,
    },
    /// A rough dielectric (frosted glass): GGX microfacet reflection and
    /// transmission chosen by the dielectric Fresnel term (pbrt-v4's
    /// `DielectricBxDF`), Beer's law inside like [`Material::Dielectric`].
    /// Scene loaders turn roughness 0 into a smooth [`Material::Dielectric`].
    RoughDielectric {
        /// Index of refraction inside (outside is 1).
        ior: f32,
        /// Transmittance per unit distance inside.
        tint: Rgb,
        /// Perceptual roughness in `(0, 1]`; `α = roughness²`.
        roughness: f32,
    },
    /// glTF 2.0's metallic-roughness material (the specification's
    /// appendix B): a Lambertian base weighted by `1 − F` plus a GGX lobe
    /// with Schlick's `F`, `F₀ = lerp(0.04, base, metallic)`, diffuse colour
    /// `base·(1 − metallic)`. A metallic-roughness texture (blue = metallic,
    /// green = roughness) multiplies both factors.
    MetallicRoughness {
        /// Base colour (a base-colour texture multiplies it).
        base: Rgb,
        /// Metalness in `[0, 1]`.
        metallic: f32,
        /// Perceptual roughness in `[0, 1]`; `α = roughness²`.
        roughness: f32,
    },
    /// Emits `color·strength` and reflects nothing.
    Emissive {
        /// Emitted colour.
        color: Rgb,
        /// Emitted radiance scale.
        strength: f32,
    },
}

/// The Fresnel term of a [`Material::Conductor`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Schlick's approximation from the reflectance at normal incidence
    /// (the metal's colour, as artists give it).
    Schlick {
        /// Reflectance at normal incidence, per channel in `[0, 1]`.
        f0: Rgb,
    },
    /// The exact Fresnel equations of a complex index of refraction
    /// `eta + i·k` per channel (measured metal data, as pbrt and Mitsuba
    /// take it).
    Complex {
        /// Real part of the index (> 0).
        eta: Rgb,
        /// Absorption coefficient (≥ 0).
        k: Rgb,
    },
}

/// An equirectangular (latitude-longitude) environment image in linear
/// RGB, rows from the top (the zenith, +y) down; the image centre looks
/// along −z and columns grow towards +x.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EnvImage {
    /// Columns (≥ 1).
    pub width: u32,
    /// Rows (≥ 1).
    pub height: u32,
    /// `width × height` colours, row by row.
    pub pixels: Vec<Rgb>,
}

/// Ambient occlusion of an ambient light (Suffern ch. 17, the
/// `AmbientOccluder`). At each shaded point `samples` directions are drawn
/// from the cosine-weighted hemisphere about the shading normal, on the
/// side the viewing ray came from, and an occlusion ray of length
/// `distance` is traced along each. A point whose rays are all free gets
/// the full ambient light; one whose rays are all blocked gets
/// `min_amount` of it; in between, the share of free rays interpolates:
/// `L = L_ambient · (min_amount + (1 − min_amount) · free / samples)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occlusion {
    /// Occlusion rays per shaded point and pixel sample, ≥ 1.
    pub samples: u32,
    /// How far an occluder may be to count, > 0 (`Real::INFINITY`: at any
    /// distance).
    pub distance: Real,
    /// The share of the ambient light a fully occluded point still gets,
    /// in `[0, 1]` (Suffern's `min_amount`).
    pub min_amount: f32,
}

impl Occlusion {
    /// The most occlusion rays per shaded point that a scene may ask for.
    pub const MAX_SAMPLES: u32 = 1024;
}

/// Light sources.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Constant light from everywhere; lights `ka·color` of every material.
    /// With `occlusion`, Suffern's ambient occluder: the light a point gets
    /// is scaled by how open its hemisphere is (Whitted only; the path
    /// tracer gathers no ambient light).
    Ambient {
        /// Colour.
        color: Rgb,
        /// Radiance scale.
        intensity: f32,
        /// Ambient occlusion; `None`: the same light everywhere.
        occlusion: Option<Occlusion>,
    },
    /// A point light.
    Point {
        /// Position.
        position: Vec3,
        /// Colour.
        color: Rgb,
        /// Radiance scale.
        intensity: f32,
        /// Divide by distance² (physically right); off = Suffern's default.
        inverse_square: bool,
        /// Whether it casts shadows.
        shadows: bool,
    },
    /// A light infinitely far away.
    Directional {
        /// Direction **towards** the light (need not be unit length).
        direction: Vec3,
        /// Colour.
        color: Rgb,
        /// Radiance scale.
        intensity: f32,
        /// Whether it casts shadows.
        shadows: bool,
    },
    /// A spot light: a point light whose light is limited to a cone about
    /// `direction`, full inside `inner_deg`, falling off smoothly
    /// (pbrt-v4's smoothstep in the cosine) to nothing at `outer_deg`.
    Spot {
        /// Position.
        position: Vec3,
        /// The axis of the cone, **from** the light (need not be unit length).
        direction: Vec3,
        /// Colour.
        color: Rgb,
        /// Radiance scale on the axis.
        intensity: f32,
        /// Half-angle of the cone of full intensity, degrees, in `[0, outer_deg]`.
        inner_deg: f32,
        /// Half-angle where the light ends, degrees, in `(0, 180]`.
        outer_deg: f32,
        /// Divide by distance² (physically right); off = Suffern's default.
        inverse_square: bool,
        /// Whether it casts shadows.
        shadows: bool,
    },
    /// An area light: a parallelogram (a rectangle when the edges are
    /// perpendicular) emitting `color·intensity` as radiance from its front
    /// face, the side `edge_u × edge_v` points to. It is visible, occludes
    /// like any surface, and is sampled for soft shadows.
    Rect {
        /// One corner.
        corner: Vec3,
        /// The first edge from `corner`.
        edge_u: Vec3,
        /// The second edge from `corner`.
        edge_v: Vec3,
        /// Colour.
        color: Rgb,
        /// Emitted radiance scale.
        intensity: f32,
    },
    /// An area light: a disk emitting `color·intensity` as radiance from its
    /// front face, the side `normal` points to. Visible, occluding and
    /// sampled like [`Light::Rect`].
    Disk {
        /// Centre.
        center: Vec3,
        /// The front side (need not be unit length, must not be zero).
        normal: Vec3,
        /// Radius, > 0.
        radius: Real,
        /// Colour.
        color: Rgb,
        /// Emitted radiance scale.
        intensity: f32,
    },
    /// Light from infinitely far away in every direction: radiance
    /// `color·intensity`, times the image's colour in that direction when
    /// there is an image. It replaces the `background` for rays that leave
    /// the scene; the path tracer samples the image by its brightness. At
    /// most one per scene.
    Environment {
        /// Colour.
        color: Rgb,
        /// Radiance scale.
        intensity: f32,
        /// An equirectangular image (shared, so cloning a scene is cheap).
        image: Option<std::sync::Arc<EnvImage>>,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_object_stays_small() {
        // Six coordinates (a box or a plane), the tag and the material:
        // objects must not pay for a mesh's vectors each.
        let limit = 6 * std::mem::size_of::<Real>() + 16;
        assert!(
            std::mem::size_of::<Object>() <= limit,
            "{}",
            std::mem::size_of::<Object>()
        );
    }
}
