//! Light transport: the shading data of a prepared scene, the tracer that
//! finds and shades hits, and the integrator trait (the Whitted integrator
//! is in `whitted.rs`, the path tracer in `path.rs`).

use crate::emitters::{Emitter, Emitters};
use crate::lights::{spot_falloff, AreaLight, Environment};
pub(crate) use crate::mesh_shading::{MeshRef, MeshShading, PrimMeshes};
use crate::plan::RayCounts;
use crate::robustness::RayOffset;
use crate::sampling::SampleStream;
use crate::scene::{Material, Rgb};
use crate::shapes::{Instance, Plane, Surface, SurfacePoint};
use crate::texture::shade::{self, HitUv, TextureData};
use crate::texture::MaterialMaps;
use gridrt_bbox::{Ray, Real, Vec3};
use gridrt_grid::{Accelerator, Hit};

/// A hit's mesh triangle with shading data: the mesh's tables, the
/// triangle's vertex indices, and the instance that placed it (whose
/// transform carries the mesh's normals and texture frames to world space).
pub(crate) struct MeshTriangle<'a> {
    mesh: &'a MeshShading,
    corners: [u32; 3],
    tri: u32,
    instance: Option<&'a Instance>,
}

/// A point or directional light, ready for shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum DirectLight {
    Point {
        position: Vec3,
        radiance: Rgb,
        inverse_square: bool,
        shadows: bool,
    },
    Directional {
        /// Unit vector towards the light.
        dir: Vec3,
        radiance: Rgb,
        shadows: bool,
    },
    Spot {
        position: Vec3,
        /// Unit axis of the cone, from the light.
        axis: Vec3,
        radiance: Rgb,
        cos_inner: Real,
        cos_outer: Real,
        inverse_square: bool,
        shadows: bool,
    },
}

impl DirectLight {
    /// The radiance scale of a point or spot light towards the unit
    /// direction `wi` (from the shading point to the light): 1 for a point
    /// light, the cone's falloff for a spot.
    #[inline]
    pub(crate) fn cone(&self, wi: Vec3) -> f32 {
        match *self {
            DirectLight::Spot {
                axis,
                cos_inner,
                cos_outer,
                ..
            } => spot_falloff(-wi.dot(axis), cos_outer, cos_inner),
            _ => 1.0,
        }
    }

    /// The light's radiance scale (zero: the light does nothing).
    pub(crate) fn radiance(&self) -> Rgb {
        match *self {
            DirectLight::Point { radiance, .. }
            | DirectLight::Directional { radiance, .. }
            | DirectLight::Spot { radiance, .. } => radiance,
        }
    }
}

/// The material of each accelerator primitive.
#[derive(Clone, Debug)]
pub(crate) enum PrimMaterials {
    /// Every primitive has this material (no table to look up).
    Uniform(u32),
    /// Primitive `i` has material `v[i]`.
    PerPrim(Vec<u32>),
}

impl Default for PrimMaterials {
    fn default() -> Self {
        PrimMaterials::PerPrim(Vec::new())
    }
}

impl PrimMaterials {
    #[inline]
    pub(crate) fn get(&self, i: usize) -> u32 {
        match self {
            PrimMaterials::Uniform(m) => *m,
            PrimMaterials::PerPrim(v) => v[i],
        }
    }
}

/// Everything shading needs besides the accelerator. Primitive `i` of the
/// accelerator has material `prim_material.get(i)`; planes come after all
/// primitives in the tie order.
/// The colour of each primitive: a table of its own, or a sphere set's
/// colours, shared with the scene (the scene's only primitives).
#[derive(Clone, Debug)]
pub(crate) enum PrimColors {
    Own(Vec<Rgb>),
    Set(std::sync::Arc<crate::SphereSet>),
}

impl Default for PrimColors {
    fn default() -> Self {
        Self::Own(Vec::new())
    }
}

impl PrimColors {
    /// Primitive `i`'s colour, if it has one.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> Option<Rgb> {
        match self {
            Self::Own(v) => v.get(i).copied(),
            Self::Set(s) => s.colors.get(i),
        }
    }

    /// Whether no primitive has a colour.
    #[cfg(test)]
    pub(crate) fn is_empty(&self) -> bool {
        match self {
            Self::Own(v) => v.is_empty(),
            Self::Set(s) => s.colors.is_empty(),
        }
    }

    /// Starts loading primitive `i`'s stored colour, if it has one.
    #[inline]
    fn prefetch(&self, i: usize) {
        let stored = match self {
            Self::Own(v) => v,
            Self::Set(s) => s.colors.stored(),
        };
        if let Some(a) = stored.get(i) {
            gridrt_grid::mem::prefetch(a);
        }
    }
}

#[derive(Clone, Debug, Default)]
pub(crate) struct SceneData {
    pub materials: Vec<Material>,
    pub prim_material: PrimMaterials,
    /// Empty, or one colour per primitive that replaces the albedo (`color`)
    /// of its Matte, Phong or Reflective material (a sphere set's colours).
    pub prim_albedo: PrimColors,
    /// Empty when no mesh has shading data; else which mesh triangle
    /// each primitive is.
    pub prim_mesh: PrimMeshes,
    pub meshes: Vec<MeshShading>,
    pub planes: Vec<Plane>,
    pub plane_material: Vec<u32>,
    /// Sum of the radiance of the ambient lights without occlusion (and
    /// of those with occlusion when the plan traces no occlusion rays).
    pub ambient: Rgb,
    /// The ambient lights with occlusion, when the plan traces occlusion
    /// rays.
    pub occluders: Vec<crate::occlusion::AmbientOccluder>,
    pub lights: Vec<DirectLight>,
    pub background: Rgb,
    /// The environment light, which replaces `background` when present.
    pub env: Option<Environment>,
    /// Probability that a light sample goes to the environment rather
    /// than to the area lights: 0 when the environment is not sampled as
    /// a light (the path tracer samples only an image, Whitted any
    /// environment when lit surfaces need light), 1 without area lights.
    pub env_pick: Real,
    pub max_depth: u32,
    /// The sampled area lights (emissive primitives, rectangles and disks)
    /// when the plan samples lights; empty otherwise.
    pub emitters: Emitters,
    /// Rectangle and disk lights: surfaces outside the grid, tested after
    /// it like the planes (they come after the planes in the tie order).
    pub area_lights: Vec<AreaLight>,
    /// Longest path of the path tracer, in bounces.
    pub path_depth: u32,
    /// How secondary rays leave surfaces (`RenderOptions::ray_offset`).
    pub ray_offset: RayOffset,
    /// Textures and the materials' maps.
    pub tex: TextureData,
}

impl SceneData {
    /// Radiance of a ray along `dir` that hits nothing: the environment's,
    /// else the background.
    #[inline]
    pub(crate) fn miss(&self, dir: Vec3) -> Rgb {
        match &self.env {
            Some(e) => e.radiance(dir.normalize()),
            None => self.background,
        }
    }

    /// The sampled area light that `found` is, if it is one (`None` for
    /// planes and when lights are not sampled).
    #[inline]
    pub(crate) fn sampled_emitter(&self, found: Found) -> Option<&Emitter> {
        match found {
            Found::Prim(h) => self.emitters.of(h.prim),
            Found::Area { index, .. } => self
                .area_lights
                .get(index as usize)
                .and_then(|a| self.emitters.get(a.emitter)),
            Found::Plane { .. } => None,
        }
    }

    /// One light sample for next-event estimation from `p`: the
    /// environment with probability `env_pick`, else an area light chosen
    /// by power. `cosine_about` asks a constant environment for directions
    /// cosine-weighted about that normal (an image is always sampled by
    /// its own importance). The second dimension pair is drawn from
    /// `stream` only when there is a light to sample.
    #[inline]
    pub(crate) fn sample_direct(
        &self,
        p: Vec3,
        u1: Real,
        stream: &mut SampleStream,
        cosine_about: Option<Vec3>,
    ) -> Option<DirectSample> {
        if self.env_pick > 0.0 && u1 < self.env_pick {
            let u2 = stream.next_2d();
            let env = self.env.as_ref()?;
            let es = match cosine_about {
                Some(n) => env.sample_at(n, u2),
                None => env.sample(u2),
            }?;
            return Some(DirectSample {
                wi: es.wi,
                radiance: es.radiance,
                pdf: self.env_pick * es.pdf,
                point: None,
            });
        }
        if self.emitters.is_empty() {
            return None;
        }
        let u2 = stream.next_2d();
        // The rest of u1 chooses among the area lights.
        let (u1, pick) = if self.env_pick > 0.0 {
            let u = (u1 - self.env_pick) / (1.0 - self.env_pick);
            (u.clamp(0.0, 1.0 - Real::EPSILON), 1.0 - self.env_pick)
        } else {
            (u1, 1.0)
        };
        let ls = self.emitters.sample(p, u1, u2)?;
        Some(DirectSample {
            wi: ls.wi,
            radiance: ls.radiance,
            pdf: ls.pdf * pick,
            point: Some(ls.point),
        })
    }
}

/// A light sample of [`SceneData::sample_direct`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct DirectSample {
    /// Unit direction towards the light.
    pub wi: Vec3,
    /// Radiance arriving from it, before occlusion.
    pub radiance: Rgb,
    /// Density per unit solid angle, the choice of the light included.
    pub pdf: Real,
    /// The point on an area light; `None` for the environment, whose
    /// shadow ray is unbounded.
    pub point: Option<Vec3>,
}

/// What a ray found: a grid primitive or a plane.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Found {
    Prim(Hit),
    Plane {
        index: u32,
        t: Real,
    },
    /// A rectangle or disk light.
    Area {
        index: u32,
        t: Real,
    },
}

impl Found {
    #[inline]
    fn t(&self) -> Real {
        match *self {
            Found::Prim(h) => h.t,
            Found::Plane { t, .. } | Found::Area { t, .. } => t,
        }
    }
}

/// The accelerator and the shading data, shared by all threads.
pub(crate) struct Tracer<'a, A> {
    pub accel: &'a A,
    pub data: &'a SceneData,
}

/// One thread's mutable state: the accelerator's scratch (mailbox) and the
/// ray counters of the tile being rendered.
pub(crate) struct ThreadState<S> {
    pub scratch: S,
    pub counts: RayCounts,
}

/// Radiance along a ray, the distance to what it hit (∞ for a miss) and
/// whether it hit anything.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Li {
    pub color: Rgb,
    pub t: Real,
    pub hit: bool,
}

/// How the closest hit looks to shading.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shading {
    /// Ray parameter of the hit.
    pub(crate) t: Real,
    pub(crate) sp: SurfacePoint,
    pub(crate) material: u32,
    /// Shading normal (interpolated for smooth meshes), outward.
    pub(crate) ns: Vec3,
    /// The primitive's own colour (or its textured one), replacing the
    /// material's albedo.
    pub(crate) albedo: Option<Rgb>,
    /// Radiance emitted by an emission map (zero without one).
    pub(crate) emission: Rgb,
    /// Metallic and roughness from a metallic-roughness map (they replace
    /// the factors of a [`Material::MetallicRoughness`]).
    pub(crate) metal_rough: Option<(f32, f32)>,
}

impl Shading {
    /// Ray parameter of the hit.
    pub(crate) fn t(&self) -> Real {
        self.t
    }

    /// Shading normal, outward.
    pub(crate) fn normal(&self) -> Vec3 {
        self.ns
    }

    /// Index of the material.
    pub(crate) fn material(&self) -> u32 {
        self.material
    }

    /// Diffuse albedo: the primitive's own colour, else its material's
    /// (1 for glass, the emitted colour for emitters).
    pub(crate) fn albedo(&self, data: &SceneData) -> Rgb {
        self.albedo
            .unwrap_or_else(|| match data.materials.get(self.material as usize) {
                Some(Material::Emissive { color, .. }) => *color,
                Some(m) => crate::prepare::albedo(m),
                None => Rgb::ONE,
            })
    }
}

impl<'a, A> Tracer<'a, A>
where
    A: Accelerator,
    A::Prim: Surface,
{
    /// The closest hit in `[0, t_max]`: the accelerator first, then the
    /// planes, which win only when strictly nearer (they come after every
    /// primitive in index order, so ties keep the lower index).
    #[inline]
    pub(crate) fn closest(
        &self,
        ray: &Ray,
        t_max: Real,
        scratch: &mut A::Scratch,
    ) -> Option<Found> {
        let mut best = self.closest_prim(ray, t_max, scratch).map(Found::Prim);
        if !self.data.planes.is_empty() {
            let mut far = best.map_or(t_max, |b| b.t());
            for (i, p) in self.data.planes.iter().enumerate() {
                if let Some(t) = p.intersect(ray, 0.0, far) {
                    if best.is_none() || t < far {
                        best = Some(Found::Plane { index: i as u32, t });
                        far = t;
                    }
                }
            }
        }
        if !self.data.area_lights.is_empty() {
            let mut far = best.map_or(t_max, |b| b.t());
            for (i, l) in self.data.area_lights.iter().enumerate() {
                if let Some(t) = l.intersect(ray, far) {
                    if best.is_none() || t < far {
                        best = Some(Found::Area { index: i as u32, t });
                        far = t;
                    }
                }
            }
        }
        best
    }

    /// The accelerator's closest hit in `[0, t_max]`, skipping the
    /// surfaces a ray passes through (alpha cut-outs and blending): the
    /// query restarts just beyond each such hit.
    #[inline]
    fn closest_prim(&self, ray: &Ray, t_max: Real, scratch: &mut A::Scratch) -> Option<Hit> {
        let mut t_min = 0.0;
        loop {
            let h = self.accel.closest_hit(ray, t_min, t_max, scratch)?;
            if !self.data.tex.alpha || !self.passes(ray, &h) {
                return Some(h);
            }
            t_min = crate::float::next_up(h.t);
        }
    }

    /// Whether `ray` passes through primitive hit `h` (alpha).
    fn passes(&self, ray: &Ray, h: &Hit) -> bool {
        let i = h.prim as usize;
        let material = self.data.prim_material.get(i);
        let Some(maps) = self.data.tex.of(material) else {
            return false;
        };
        let p = ray.at(h.t);
        let uv = self
            .mesh_triangle(h)
            .and_then(|t| Self::uv_at(&t, h.u, h.v));
        // Alpha is read at the finest level: cut-out edges stay sharp.
        let [uv, uv1] = uv.map_or([glam::Vec2::ZERO; 2], |h| h.uv);
        let q = crate::texture::TexQuery {
            uv,
            uv1,
            p,
            width: 0.0,
        };
        self.data.tex.passes(maps, &q, ray, h.t)
    }

    /// The mesh triangle a hit is on, when its mesh has shading data
    /// (normals, colours or texture coordinates), with the instance that
    /// placed it.
    #[inline]
    fn mesh_triangle(&self, h: &Hit) -> Option<MeshTriangle<'_>> {
        if self.data.meshes.is_empty() {
            return None;
        }
        let prim = &self.accel.primitives()[h.slot as usize];
        let (m, instance) = match prim.instance() {
            Some(inst) => (
                MeshRef {
                    mesh: inst.shared().shading,
                    tri: h.part,
                },
                Some(inst),
            ),
            None => (self.data.prim_mesh.get(h.prim)?, None),
        };
        let mesh = self.data.meshes.get(m.mesh as usize)?;
        Some(MeshTriangle {
            mesh,
            corners: mesh.corners(m.tri, prim.vertex_indices())?,
            tri: m.tri,
            instance,
        })
    }

    /// Texture coordinates (both sets; the first twice where the mesh has
    /// one) and the triangle's texture frame at barycentrics `(u, v)` of a
    /// textured mesh triangle.
    #[inline]
    fn uv_at(t: &MeshTriangle, u: Real, v: Real) -> Option<HitUv> {
        let mesh = t.mesh;
        let mut frame = *mesh.frames.get(t.tri as usize)?;
        let [a, b, c] = t.corners;
        let (u, v) = (crate::float::to_f32(u), crate::float::to_f32(v));
        let at = |set: &[glam::Vec2]| {
            set[a as usize] * (1.0 - u - v) + set[b as usize] * u + set[c as usize] * v
        };
        let uv = at(mesh.uvs());
        let uv1 = if mesh.uvs1().is_empty() {
            uv
        } else {
            at(mesh.uvs1())
        };
        if let Some(inst) = t.instance {
            frame = inst.frame_to_world(frame);
        }
        Some(HitUv {
            uv: [uv, uv1],
            frame,
        })
    }

    /// The interpolated vertex colour at barycentrics `(u, v)` of a mesh
    /// triangle, when its mesh has colours.
    #[inline]
    fn vertex_color(t: &MeshTriangle, u: Real, v: Real) -> Option<Rgb> {
        let colors = t.mesh.colors();
        if colors.is_empty() {
            return None;
        }
        let [a, b, c] = t.corners;
        let (u, v) = (crate::float::to_f32(u), crate::float::to_f32(v));
        let k = |j: u32| colors[j as usize];
        Some(k(a) * (1.0 - u - v) + k(b) * u + k(c) * v)
    }

    /// The interpolated vertex normal at barycentrics `(u, v)` of a mesh
    /// triangle, in world space (not unit length), when its mesh has
    /// normals.
    #[inline]
    fn vertex_normal(t: &MeshTriangle, u: Real, v: Real) -> Option<Vec3> {
        let normals = t.mesh.normals();
        if normals.is_empty() {
            return None;
        }
        let [a, b, c] = t.corners;
        let n =
            normals[a as usize] * (1.0 - u - v) + normals[b as usize] * u + normals[c as usize] * v;
        Some(match t.instance {
            Some(inst) => inst.normal_to_world(n),
            None => n,
        })
    }

    /// Whether the light of `ls` reaches the surface point `sp` (geometric
    /// normal `ng`): one shadow ray, counted as a light sample.
    #[inline]
    pub(crate) fn sample_visible(
        &self,
        sp: &SurfacePoint,
        ng: Vec3,
        ls: &DirectSample,
        ts: &mut ThreadState<A::Scratch>,
    ) -> bool {
        let o = self.data.ray_offset.origin(sp.p, sp.p_err, ng, ls.wi);
        ts.counts.light_sample += 1;
        let (shadow, t_max) = match ls.point {
            Some(q) => (Ray::new(o, q - o), LIGHT_T_MAX),
            None => (Ray::new(o, ls.wi), Real::INFINITY),
        };
        !self.occluded(&shadow, t_max, &mut ts.scratch)
    }

    /// Whether anything lies on the ray within `[0, t_max]`.
    #[inline]
    pub(crate) fn occluded(&self, ray: &Ray, t_max: Real, scratch: &mut A::Scratch) -> bool {
        let hit = if self.data.tex.alpha {
            self.closest_prim(ray, t_max, scratch).is_some()
        } else {
            self.accel.any_hit(ray, 0.0, t_max, scratch)
        };
        hit || self
            .data
            .planes
            .iter()
            .any(|p| p.intersect(ray, 0.0, t_max).is_some())
            || self
                .data
                .area_lights
                .iter()
                .any(|l| l.intersect(ray, t_max).is_some())
    }

    /// Starts loading the per-primitive data [`Tracer::shading`] will read
    /// for `found`, so that the cache misses overlap other work.
    #[inline]
    pub(crate) fn prefetch(&self, found: Option<Found>) {
        if let Some(Found::Prim(h)) = found {
            let i = h.prim as usize;
            self.data.prim_albedo.prefetch(i);
            if let PrimMaterials::PerPrim(v) = &self.data.prim_material {
                if let Some(m) = v.get(i) {
                    gridrt_grid::mem::prefetch(m);
                }
            }
        }
    }

    /// What shading needs to know about a hit: the surface point, normals,
    /// material and colour. The loads of per-primitive data happen here, so
    /// that a render loop can gather them for several hits at once.
    #[inline]
    pub(crate) fn shading(&self, ray: &Ray, found: Found) -> Shading {
        if self.data.tex.any() {
            self.textured(ray, found)
        } else {
            self.untextured(ray, found)
        }
    }

    /// The shading of a primitive's hit `h`, on mesh triangle `tri` if it is one.
    #[inline(always)]
    fn prim_shading(&self, ray: &Ray, h: &Hit, tri: Option<&MeshTriangle<'_>>) -> Shading {
        let i = h.prim as usize;
        // The accelerator's own storage (a grid's cell order) holds
        // the primitive in `slot`; the per-primitive tables go by
        // primitive index.
        let sp = self.accel.primitives()[h.slot as usize].surface(
            self.accel.shared(),
            ray,
            &h.prim_hit(),
        );
        let mut ns = sp.n;
        // Keep the shading normal on the geometric front side.
        if let Some(n) = tri.and_then(|t| Self::vertex_normal(t, h.u, h.v)?.try_normalize()) {
            ns = if n.dot(sp.n) < 0.0 { -n } else { n };
        }
        Shading {
            t: h.t,
            sp,
            material: self.data.prim_material.get(i),
            ns,
            albedo: tri
                .and_then(|t| Self::vertex_color(t, h.u, h.v))
                .or_else(|| self.data.prim_albedo.get(i)),
            emission: Rgb::ZERO,
            metal_rough: None,
        }
    }

    /// [`Tracer::shading`] before textures.
    #[inline]
    fn untextured(&self, ray: &Ray, found: Found) -> Shading {
        match found {
            Found::Prim(h) => self.prim_shading(ray, &h, self.mesh_triangle(&h).as_ref()),
            Found::Plane { index, t } => {
                let sp = self.data.planes[index as usize].surface(ray, t);
                Shading {
                    t,
                    sp,
                    material: self.data.plane_material[index as usize],
                    ns: sp.n,
                    albedo: None,
                    emission: Rgb::ZERO,
                    metal_rough: None,
                }
            }
            Found::Area { index, t } => {
                let l = &self.data.area_lights[index as usize];
                let sp = l.surface(ray, t);
                Shading {
                    t,
                    sp,
                    material: l.material,
                    ns: sp.n,
                    albedo: None,
                    emission: Rgb::ZERO,
                    metal_rough: None,
                }
            }
        }
    }

    /// [`Tracer::shading`] in a scene with textures: out of line, so that
    /// untextured scenes' shading stays small and builds its result in
    /// place (a `Shading` whose address is taken lives on the stack, and
    /// copying it out after field-by-field stores stalls store-to-load
    /// forwarding on every hit).
    #[inline(never)]
    fn textured(&self, ray: &Ray, found: Found) -> Shading {
        let (sh, tri) = match found {
            Found::Prim(h) => {
                let tri = self.mesh_triangle(&h);
                (
                    self.prim_shading(ray, &h, tri.as_ref()),
                    tri.map(|t| (t, h)),
                )
            }
            _ => (self.untextured(ray, found), None),
        };
        // Area lights' own surfaces are never textured.
        let maps = match found {
            Found::Area { .. } => None,
            _ => self.data.tex.of(sh.material),
        };
        let Some(maps) = maps else {
            return sh;
        };
        let uv = tri.and_then(|(t, h)| Self::uv_at(&t, h.u, h.v));
        self.apply_textures(ray, sh, maps, uv)
    }

    /// Applies the textures `maps` of `sh`'s material to it.
    fn apply_textures(
        &self,
        ray: &Ray,
        mut sh: Shading,
        maps: &MaterialMaps,
        uv: Option<HitUv>,
    ) -> Shading {
        let q = self.data.tex.query(ray, sh.t, sh.sp.p, sh.sp.n, uv);
        let base = sh.albedo.unwrap_or_else(|| {
            self.data
                .materials
                .get(sh.material as usize)
                .map_or(Rgb::ONE, crate::prepare::albedo)
        });
        let t = shade::apply(
            &self.data.tex,
            maps,
            &q,
            base,
            sh.ns,
            sh.sp.n,
            uv.map(|h| h.frame),
        );
        sh.albedo = t.albedo.or(sh.albedo);
        if maps.metallic_roughness.is_some() {
            sh.metal_rough = Some(maps.metallic_roughness(&self.data.tex.list, &q));
        }
        sh.emission = t.emission;
        sh.ns = t.ns;
        sh
    }
}

/// A light transport algorithm. Implementations are zero-sized types whose
/// const parameters switch effects on and off at compile time.
pub(crate) trait Integrator {
    /// Whether the render loop should trace a row of camera rays first,
    /// then gather their [`Shading`] (overlapping the cache misses of
    /// per-primitive data), then call [`Integrator::shade`]; otherwise it
    /// calls [`Integrator::li`] per ray.
    const BATCH: bool;

    /// Whether it draws random numbers from the pixel sample's stream (the
    /// render loop then gives every sample its own stream, even at 1 spp).
    const SAMPLED: bool = false;

    /// Radiance arriving along `ray` (`depth` secondary bounces so far).
    fn li<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface;

    /// Radiance arriving along `ray` whose closest hit (or miss) is known.
    fn shade<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        hit: Option<&Shading>,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface;
}

pub(crate) use crate::whitted::{face_forward, point_shadow_t_max, Whitted, LIGHT_T_MAX};
