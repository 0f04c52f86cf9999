//! From a [`Scene`] to what the renderer runs: validation, the primitives
//! for the accelerator, and the shading data.

use crate::accel_of::TriangleStorage;
use crate::camera::CameraModel;
use crate::emitters::EmitterShape;
use crate::error::SceneError;
use crate::instancing::{flattened, InstancingStats, SharedMeshes};
use crate::integrator::{DirectLight, MeshRef, MeshShading, PrimColors, PrimMaterials, SceneData};
use crate::lights::{AreaLight, Environment};
use crate::plan::{EffectPlan, IntegratorKind};
use crate::scene::{Geometry, Light, Material, Mesh, Rgb, Scene, SphereColors};
use crate::shapes::{Cuboid, Instance, MeshGrid, MeshTriangle, MeshVertices, Plane, Shape, Sphere};
use crate::texture::shade::TextureData;
use crate::validate::validate;
use gridrt_bbox::Real;
use gridrt_grid::GridConfig;
use prims::Out;
pub(crate) use prims::Prims;
use std::collections::HashMap;
use std::sync::Arc;

mod prims;

/// The largest image, in pixels, the renderer accepts (8192 × 8192).
pub const MAX_PIXELS: u64 = 1 << 26;

/// A validated scene, ready for an accelerator to be built over `prims`.
#[derive(Debug)]
pub(crate) struct Prepared {
    pub data: SceneData,
    pub prims: Prims,
    pub camera: CameraModel,
    pub plan: EffectPlan,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub instancing: InstancingStats,
    /// Each mesh with shading data and its first vertex: what
    /// [`Prepared::numbered`] renumbers when the triangles are indexed
    /// (`Prims::Mesh`, whose vertices await their spatial numbering).
    placed: Vec<(u32, u32)>,
}

impl Prepared {
    /// Numbers the vertices of indexed triangles in the triangles' spatial
    /// order ([`MeshVertices::renumber`]) and moves shading's per-vertex
    /// arrays into that numbering. The renderer calls it once the scene's
    /// objects may be gone: a mesh that only shading still holds first
    /// drops its positions and triangles, which the grid's primitives have
    /// copied, so they are not alive beside the order's keys.
    pub(crate) fn numbered(mut self) -> Self {
        let Prims::Mesh(verts, tris) = &mut self.prims else {
            return self;
        };
        MeshShading::release_positions(&mut self.data.meshes, &self.placed);
        let order = gridrt_grid::spatial_order_iter(tris, verts);
        let (numbered, new_of) = std::mem::take(verts).renumber(tris, order);
        *verts = numbered;
        MeshShading::renumber(&mut self.data.meshes, &self.placed, &new_of);
        self
    }
}

/// Validates the scene and converts it. Triangles with two equal vertices
/// are left out of the grid (no ray can hit them).
/// `mesh_grid` builds the grids of shared meshes; `None` bakes every
/// instance into world space. `storage` says how a scene of mesh
/// triangles alone stores them.
pub(crate) fn prepare(
    scene: &Scene,
    mesh_grid: Option<&GridConfig>,
    storage: TriangleStorage,
) -> Result<Prepared, SceneError> {
    let shared = match mesh_grid {
        Some(_) => SharedMeshes::of(scene),
        None => SharedMeshes::none(),
    };
    let (count, all_spheres) = validate(scene, &shared)?;
    let s = &scene.settings;
    let camera = CameraModel::new(&scene.camera, s.width, s.height)?;
    let mut plan = EffectPlan::for_scene(scene);
    let mut data = shading_data(scene, &plan);
    data.tex = texture_data(scene, camera.footprint());
    let (prims, instancing, placed) = convert(
        scene,
        Counts {
            count,
            all_spheres,
            storage,
        },
        &Instancing {
            shared,
            mesh_grid: mesh_grid.copied().unwrap_or_default(),
        },
        plan.light_sampling,
        &mut data,
    );
    data.emitters.finish(prims.len());
    plan.area_lights = data.emitters.list.len() as u32;
    // The path tracer samples an image environment (BSDF sampling finds a
    // constant one); Whitted samples either kind when the plan samples
    // lights, since its rays gather no diffuse light.
    let env_sampled = data.env.as_ref().is_some_and(|e| {
        if plan.integrator == IntegratorKind::Path {
            e.sampled()
        } else {
            plan.light_sampling
        }
    });
    data.env_pick = match (env_sampled, data.emitters.is_empty()) {
        (false, _) => 0.0,
        (true, true) => 1.0,
        (true, false) => 0.5,
    };
    plan.env_sampling = env_sampled;
    plan.light_sampling = plan.area_lights > 0 || env_sampled;
    if plan.integrator == IntegratorKind::Path {
        let emits = scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material as usize)
                .is_some_and(|m| emission(m) != Rgb::ZERO)
        });
        let emits = emits || !data.area_lights.is_empty() || data.env.is_some();
        if !emits && data.lights.is_empty() && s.background == Rgb::ZERO {
            return Err(SceneError::NothingEmits);
        }
    }
    Ok(Prepared {
        data,
        prims,
        camera,
        plan,
        width: s.width,
        height: s.height,
        spp: s.spp,
        instancing,
        placed,
    })
}

/// The albedo of a material, as a per-primitive colour table records it.
pub(crate) fn albedo(m: &Material) -> Rgb {
    match *m {
        Material::Matte { color, .. }
        | Material::Phong { color, .. }
        | Material::Reflective { color, .. } => color,
        Material::MetallicRoughness { base, .. } => base,
        Material::Dielectric { .. }
        | Material::RoughDielectric { .. }
        | Material::Conductor { .. }
        | Material::Emissive { .. } => Rgb::ONE,
    }
}

/// Materials, lights and background for shading.
fn shading_data(scene: &Scene, plan: &EffectPlan) -> SceneData {
    let mut data = SceneData {
        materials: scene.materials.clone(),
        background: scene.settings.background,
        max_depth: plan.max_depth,
        path_depth: scene.settings.path_max_depth,
        ..SceneData::default()
    };
    for l in &scene.lights {
        match *l {
            Light::Ambient {
                color,
                intensity,
                occlusion,
            } => match occlusion {
                Some(o) if plan.ambient_occlusion && color * intensity != Rgb::ZERO => data
                    .occluders
                    .push(crate::occlusion::AmbientOccluder::new(color * intensity, o)),
                _ => data.ambient += color * intensity,
            },
            Light::Point {
                position,
                color,
                intensity,
                inverse_square,
                shadows,
            } => data.lights.push(DirectLight::Point {
                position,
                radiance: color * intensity,
                inverse_square,
                shadows: shadows && plan.shadows,
            }),
            Light::Directional {
                direction,
                color,
                intensity,
                shadows,
            } => data.lights.push(DirectLight::Directional {
                dir: direction.normalize(),
                radiance: color * intensity,
                shadows: shadows && plan.shadows,
            }),
            Light::Spot {
                position,
                direction,
                color,
                intensity,
                inner_deg,
                outer_deg,
                inverse_square,
                shadows,
            } => data.lights.push(DirectLight::Spot {
                position,
                axis: direction.normalize(),
                radiance: color * intensity,
                cos_inner: Real::from(inner_deg).to_radians().cos(),
                cos_outer: Real::from(outer_deg).to_radians().cos(),
                inverse_square,
                shadows: shadows && plan.shadows,
            }),
            Light::Rect {
                corner,
                edge_u,
                edge_v,
                color,
                intensity,
            } => {
                let material = data.materials.len() as u32;
                if let Some(l) = AreaLight::rect(corner, edge_u, edge_v, material) {
                    data.materials.push(Material::Emissive {
                        color,
                        strength: intensity,
                    });
                    data.area_lights.push(l);
                }
            }
            Light::Disk {
                center,
                normal,
                radius,
                color,
                intensity,
            } => {
                let material = data.materials.len() as u32;
                if let Some(l) = AreaLight::disk(center, normal, radius, material) {
                    data.materials.push(Material::Emissive {
                        color,
                        strength: intensity,
                    });
                    data.area_lights.push(l);
                }
            }
            // Set up below, once the plan says it is in use.
            Light::Environment { .. } => {}
        }
    }
    if plan.environment {
        for l in &scene.lights {
            if let Light::Environment {
                color,
                intensity,
                ref image,
            } = *l
            {
                data.env = Some(Environment::new(color * intensity, image.clone()));
            }
        }
    }
    if plan.light_sampling {
        for l in &mut data.area_lights {
            let radiance = match data.materials[l.material as usize] {
                Material::Emissive { color, strength } => color * strength,
                _ => Rgb::ZERO,
            };
            l.emitter = data
                .emitters
                .push_shape(l.emitter_shape(), radiance)
                .unwrap_or(u32::MAX);
        }
    }
    if plan.direct_lights == 0 {
        // Nothing reacts to them: no light loop at all.
        data.lights.clear();
    }
    // Lights of zero radiance only cost time.
    data.lights.retain(|l| l.radiance() != Rgb::ZERO);

    data
}

/// The scene's textures as shading reads them.
fn texture_data(scene: &Scene, footprint: [f32; 2]) -> TextureData {
    let t = &scene.textures;
    let mut maps: Vec<_> = (0..scene.materials.len())
        .map(|i| t.maps.get(i).filter(|m| m.is_active()).cloned())
        .collect();
    if maps.iter().all(Option::is_none) {
        maps.clear();
    }
    let alpha = maps
        .iter()
        .flatten()
        .any(|m| m.alpha_mode != crate::texture::AlphaMode::Opaque);
    TextureData {
        list: t.list.clone(),
        maps,
        footprint,
        alpha,
    }
}

/// The emitted radiance of a material (zero for non-emitters).
fn emission(m: &Material) -> Rgb {
    match *m {
        Material::Emissive { color, strength } => color * strength,
        _ => Rgb::ZERO,
    }
}

/// Adds primitive `prim` to the area lights when its material emits.
fn add_emitter(data: &mut SceneData, prim: usize, shape: &Shape, material: u32) {
    let radiance = data
        .materials
        .get(material as usize)
        .map_or(Rgb::ZERO, emission);
    if radiance == Rgb::ZERO {
        return;
    }
    let shape = match shape {
        &Shape::Triangle(t) | &Shape::MtTriangle(crate::shapes::MtTriangle(t)) => {
            let [p0, p1, p2] = t.vertices();
            let (e1, e2) = (p1 - p0, p2 - p0);
            let Some(n) = e1.cross(e2).try_normalize() else {
                return;
            };
            EmitterShape::Triangle { p0, e1, e2, n }
        }
        &Shape::Sphere(sp) => EmitterShape::Sphere {
            center: sp.center,
            radius: sp.radius,
        },
        // Boxes are not sampled; paths that hit them still see their light.
        // Emissive instances are flattened (`instancing`), never shared.
        Shape::Cuboid(_) | Shape::Instance(_) => return,
    };
    data.emitters.push(prim, shape, radiance);
}

/// Fills `data` with the primitives' materials and returns the primitives:
/// each object's in turn (a sphere set's in the set's order, a mesh's in
/// triangle order without those with two equal vertices).
/// What validation counted: grid primitives, and whether all are spheres.
struct Counts {
    count: usize,
    all_spheres: bool,
    storage: TriangleStorage,
}

/// Which meshes stay shared, and how to build their grids.
struct Instancing {
    shared: SharedMeshes,
    mesh_grid: GridConfig,
}

fn convert(
    scene: &Scene,
    Counts {
        count,
        all_spheres,
        storage,
    }: Counts,
    instancing: &Instancing,
    sample_lights: bool,
    data: &mut SceneData,
) -> (Prims, InstancingStats, Vec<(u32, u32)>) {
    // One material for every primitive: no per-primitive table.
    let materials = || {
        scene
            .objects
            .iter()
            .filter(|o| match &o.geometry {
                Geometry::Plane { .. } => false,
                Geometry::Spheres(set) => !set.spheres.is_empty(),
                _ => true,
            })
            .map(|o| o.material)
    };
    let uniform = match materials().next() {
        None => Some(0),
        Some(first) => materials().all(|m| m == first).then_some(first),
    };
    // Textured materials need the meshes' texture coordinates.
    let textured = data.tex.maps.iter().any(Option::is_some);
    // A colour per primitive as soon as one sphere set has colours.
    let colored = scene
        .objects
        .iter()
        .any(|o| matches!(&o.geometry, Geometry::Spheres(set) if !set.colors.is_empty()));
    let smooth = textured
        || scene.objects.iter().any(|o| {
            let m = match &o.geometry {
                Geometry::Mesh(m) => &**m,
                Geometry::Instance { mesh, .. } => &**mesh,
                _ => return false,
            };
            !m.normals.is_empty() || !m.colors.is_empty()
        });
    for o in &scene.objects {
        if let Geometry::Plane { point, normal } = o.geometry {
            data.planes.push(Plane::new(point, normal));
            data.plane_material.push(o.material);
        }
    }
    // A scene whose primitives are all one sphere set's: the set as it is.
    let mut sources = scene.objects.iter().filter(|o| match &o.geometry {
        Geometry::Sphere { .. } => true,
        Geometry::Spheres(set) => !set.spheres.is_empty(),
        _ => false,
    });
    if let (true, Some(o), None) = (all_spheres, sources.next(), sources.next()) {
        if let Geometry::Spheres(set) = &o.geometry {
            if sample_lights {
                for (k, &sp) in set.spheres.iter().enumerate() {
                    add_emitter(data, k, &Shape::Sphere(sp), o.material);
                }
            }
            data.prim_material = PrimMaterials::Uniform(o.material);
            if !set.colors.is_empty() {
                data.prim_albedo = PrimColors::Set(Arc::clone(set));
            }
            return (
                Prims::Set(Arc::clone(set)),
                InstancingStats::default(),
                Vec::new(),
            );
        }
    }
    let mut per_prim = Vec::new();
    if uniform.is_none() {
        per_prim.reserve(count);
    }
    let mut albedos = Vec::new();
    if colored {
        albedos.reserve(count);
    }
    // The tables of `n` primitives of `material`, with `colors` (empty, or
    // one per primitive).
    let mut record =
        |material: u32, n: usize, colors: &SphereColors, mesh: MeshRef, data: &mut SceneData| {
            if uniform.is_none() {
                per_prim.resize(per_prim.len() + n, material);
            }
            if colored {
                let a = albedo(&data.materials[material as usize]);
                colors.extend_into(&mut albedos, n, a);
            }
            if smooth {
                data.prim_mesh.extend(n, mesh);
            }
        };
    let mut stats = InstancingStats::default();
    // Indexed triangles: (shading data, first vertex) of each mesh.
    let mut placed = Vec::new();
    let prims = if all_spheres {
        let mut spheres: Vec<Sphere> = Vec::with_capacity(count);
        for o in &scene.objects {
            let first = spheres.len();
            match &o.geometry {
                Geometry::Sphere { center, radius } => {
                    spheres.push(Sphere::new(*center, *radius));
                    record(o.material, 1, &SphereColors::None, MeshRef::NONE, data);
                }
                Geometry::Spheres(set) => {
                    spheres.extend_from_slice(&set.spheres);
                    record(
                        o.material,
                        set.spheres.len(),
                        &set.colors,
                        MeshRef::NONE,
                        data,
                    );
                }
                _ => {}
            }
            if sample_lights {
                for (k, &sp) in spheres.iter().enumerate().skip(first) {
                    add_emitter(data, k, &Shape::Sphere(sp), o.material);
                }
            }
        }
        Prims::Spheres(spheres)
    } else {
        // Only mesh triangles in the grid: the compact type.
        let triangles_only = scene.objects.iter().all(|o| match &o.geometry {
            Geometry::Mesh(_) | Geometry::Plane { .. } => true,
            Geometry::Instance { .. } => !instancing.shared.keeps(scene, o),
            Geometry::Spheres(set) => set.spheres.is_empty(),
            Geometry::Sphere { .. } | Geometry::Cuboid { .. } => false,
        });
        // Indexed triangles need every vertex of the scene in one array.
        let vertices: usize = scene
            .objects
            .iter()
            .map(|o| match &o.geometry {
                Geometry::Mesh(m) | Geometry::Instance { mesh: m, .. } => m.positions.len(),
                _ => 0,
            })
            .sum();
        let indexed = storage.resolve(count) == TriangleStorage::Indexed
            && vertices <= MeshTriangle::MAX_VERTICES;
        let mut shapes = if triangles_only && indexed {
            Out::Mesh(MeshVertices::default(), Vec::with_capacity(count))
        } else if triangles_only {
            Out::Triangles(Vec::with_capacity(count))
        } else {
            Out::Shapes(Vec::with_capacity(count))
        };
        let mut grids: HashMap<*const Mesh, Arc<MeshGrid>> = HashMap::new();
        for o in &scene.objects {
            let first = shapes.len();
            let flat = match &o.geometry {
                Geometry::Instance { mesh, to_world } if !instancing.shared.keeps(scene, o) => {
                    flattened(mesh, to_world).map(Arc::new)
                }
                _ => None,
            };
            match &o.geometry {
                Geometry::Sphere { center, radius } => {
                    shapes.push(Sphere::new(*center, *radius).into());
                    record(o.material, 1, &SphereColors::None, MeshRef::NONE, data);
                }
                Geometry::Spheres(set) => {
                    for &sp in &set.spheres {
                        shapes.push(Shape::from(sp));
                    }
                    record(
                        o.material,
                        set.spheres.len(),
                        &set.colors,
                        MeshRef::NONE,
                        data,
                    );
                }
                Geometry::Cuboid { min, max } => {
                    shapes.push(Cuboid::new(*min, *max).into());
                    record(o.material, 1, &SphereColors::None, MeshRef::NONE, data);
                }
                Geometry::Plane { .. } => {}
                Geometry::Mesh(_) => {}
                Geometry::Instance { mesh, to_world } => {
                    if flat.is_none() {
                        let grid =
                            Arc::clone(grids.entry(Arc::as_ptr(mesh)).or_insert_with(|| {
                                let uvs = textured && !mesh.uvs.is_empty();
                                let shading =
                                    if mesh.normals.is_empty() && mesh.colors.is_empty() && !uvs {
                                        u32::MAX
                                    } else {
                                        data.meshes.push(MeshShading::new(Arc::clone(mesh), uvs));
                                        (data.meshes.len() - 1) as u32
                                    };
                                Arc::new(MeshGrid::new(
                                    Arc::clone(mesh),
                                    &instancing.mesh_grid,
                                    shading,
                                ))
                            }));
                        if let Some(inst) = Instance::new(grid, **to_world) {
                            shapes.push(Shape::Instance(Arc::new(inst)));
                            stats.instances += 1;
                            record(o.material, 1, &SphereColors::None, MeshRef::NONE, data);
                        }
                    }
                }
            }
            let mesh = match &o.geometry {
                Geometry::Mesh(m) => Some(m),
                _ => flat.as_ref(),
            };
            if let Some(m) = mesh {
                let uvs = textured && !m.uvs.is_empty() && data.tex.of(o.material).is_some();
                let mesh_id = if m.normals.is_empty() && m.colors.is_empty() && !uvs {
                    u32::MAX
                } else {
                    // The mesh's arrays are shared, not copied.
                    data.meshes.push(MeshShading::new(Arc::clone(m), uvs));
                    (data.meshes.len() - 1) as u32
                };
                let first = shapes.add_vertices(&m.positions);
                if mesh_id != u32::MAX {
                    placed.push((mesh_id, first));
                }
                for (t, &v) in m.triangles.iter().enumerate() {
                    if !shapes.push_triangle(&m.positions, first, v) {
                        continue;
                    }
                    let r = MeshRef {
                        mesh: mesh_id,
                        tri: t as u32,
                    };
                    record(o.material, 1, &SphereColors::None, r, data);
                }
            }
            if sample_lights {
                for k in first..shapes.len() {
                    add_emitter(data, k, &shapes.shape(k), o.material);
                }
            }
        }
        stats.shared_meshes = grids.len();
        stats.bytes = grids.values().map(|g| g.bytes()).sum::<usize>()
            + stats.instances * std::mem::size_of::<Instance>();
        shapes.finish()
    };
    data.prim_material = match uniform {
        Some(m) => PrimMaterials::Uniform(m),
        None => PrimMaterials::PerPrim(per_prim),
    };
    data.prim_albedo = PrimColors::Own(albedos);
    (prims, stats, placed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::PrimMaterials;
    use crate::scene::{Object, SphereSet};
    use crate::suffern;
    use gridrt_bbox::Vec3;
    use std::sync::Arc;

    fn set_object(set: SphereSet, material: u32) -> Object {
        Object {
            geometry: Geometry::Spheres(Arc::new(set)),
            material,
        }
    }

    #[test]
    fn a_coloured_set_is_one_material_and_its_colours() {
        let scene = suffern::scene(50);
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(0)));
        let Geometry::Spheres(set) = &scene.objects[0].geometry else {
            panic!("the benchmark is one sphere set");
        };
        assert!(matches!(&p.data.prim_albedo, PrimColors::Set(s) if Arc::ptr_eq(s, set)));
        assert_eq!(p.data.prim_albedo.get(49), set.colors.get(49));
        // The set itself, shared with the scene: no copy.
        assert!(matches!(&p.prims, Prims::Set(s) if Arc::ptr_eq(s, set)));
    }

    #[test]
    fn objects_around_a_set_take_their_materials_colour() {
        let mut scene = suffern::scene(5);
        let red = Rgb::new(0.8, 0.1, 0.1);
        scene.materials.push(Material::Matte {
            color: red,
            ka: 0.25,
            kd: 0.75,
        });
        let sphere = |x| Object {
            geometry: Geometry::Sphere {
                center: Vec3::new(x, 0.0, 0.0),
                radius: 0.5,
            },
            material: 1,
        };
        scene.objects.insert(0, sphere(-3.0));
        // A set without colours takes its material's.
        let plain = SphereSet {
            spheres: suffern::sphere_set(3, 7).spheres,
            colors: SphereColors::None,
        };
        scene.objects.push(set_object(plain, 1));
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        let Geometry::Spheres(set) = &scene.objects[1].geometry else {
            panic!("object 1 is the benchmark's set");
        };
        let mut want = vec![red];
        set.colors.extend_into(&mut want, 5, Rgb::ZERO);
        want.extend([red; 3]);
        assert!(matches!(&p.data.prim_albedo, PrimColors::Own(v) if *v == want));
        let mut ids = vec![1];
        ids.extend([0; 5]);
        ids.extend([1; 3]);
        assert!(matches!(&p.data.prim_material, PrimMaterials::PerPrim(v) if *v == ids));
        assert_eq!(p.prims.len(), 9);
    }

    #[test]
    fn uncoloured_scenes_keep_no_colour_table() {
        let mut scene = suffern::scene(0);
        scene.objects.push(set_object(
            SphereSet {
                spheres: suffern::sphere_set(4, 3).spheres,
                colors: SphereColors::None,
            },
            0,
        ));
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        assert!(p.data.prim_albedo.is_empty());
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(0)));
        assert_eq!(p.prims.len(), 4);
    }

    #[test]
    fn shading_reads_the_scenes_mesh_arrays_without_copies() {
        // Two triangles of a quad, smooth-shaded, and one with two equal
        // vertices between them (left out of the grid).
        let mesh = Arc::new(Mesh {
            name: "quad".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: vec![Vec3::Z; 4],
            triangles: vec![[0, 1, 2], [0, 0, 1], [0, 2, 3]],
            ..Mesh::default()
        });
        let mut scene = suffern::scene(0);
        scene.objects.push(Object {
            geometry: Geometry::Sphere {
                center: Vec3::new(5.0, 0.0, 0.0),
                radius: 1.0,
            },
            material: 0,
        });
        scene.objects.push(Object {
            geometry: Geometry::Mesh(Arc::clone(&mesh)),
            material: 0,
        });
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        let shading = &p.data.meshes[0];
        assert_eq!(shading.normals().as_ptr(), mesh.normals.as_ptr());
        assert_eq!(shading.corners(1, None), Some(mesh.triangles[1]));
        // The scene's, the test's and the shading's references.
        assert_eq!(Arc::strong_count(&mesh), 3);
        // Primitive 0 is the sphere; 1 and 2 the quad's triangles 0 and 2.
        assert_eq!(p.prims.len(), 3);
        let at = |prim| p.data.prim_mesh.get(prim).map(|r| (r.mesh, r.tri));
        assert_eq!(at(0), Some((u32::MAX, 0)));
        assert_eq!(at(1), Some((0, 0)));
        assert_eq!(at(2), Some((0, 2)));
        assert_eq!(at(3), None);
    }

    #[test]
    fn mesh_triangles_alone_get_the_compact_type() {
        let quad = |x: Real| {
            Arc::new(Mesh {
                positions: vec![
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x + 1.0, 0.0, 0.0),
                    Vec3::new(x + 1.0, 1.0, 0.0),
                    Vec3::new(x, 1.0, 0.0),
                ],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                ..Mesh::default()
            })
        };
        let mut scene = suffern::scene(0);
        scene.objects.clear();
        for x in [0.0, 2.0] {
            scene.objects.push(Object {
                geometry: Geometry::Mesh(quad(x)),
                material: 0,
            });
        }
        scene.objects.push(Object {
            geometry: Geometry::Plane {
                point: Vec3::ZERO,
                normal: Vec3::Y,
            },
            material: 0,
        });
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        assert!(matches!(&p.prims, Prims::Triangles(v) if v.len() == 4));
        // Möller–Trumbore triangles are shapes of their own kind.
        let mt = crate::robustness::with_triangle_test(
            p.prims,
            crate::robustness::TriangleTest::MollerTrumbore,
        );
        assert!(matches!(&mt, Prims::Shapes(v)
            if v.len() == 4 && v.iter().all(|s| matches!(s, Shape::MtTriangle(_)))));
        // A sphere beside them: shapes.
        scene.objects.push(Object {
            geometry: Geometry::Sphere {
                center: Vec3::new(0.0, 5.0, 0.0),
                radius: 1.0,
            },
            material: 0,
        });
        let p = prepare(
            &scene,
            Some(&GridConfig::default()),
            TriangleStorage::Copies,
        )
        .unwrap();
        assert!(matches!(&p.prims, Prims::Shapes(v) if v.len() == 5));
    }
}
