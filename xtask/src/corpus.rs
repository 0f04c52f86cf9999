//! The scene corpus of `cargo xtask scenes`: the scenes, their primitives
//! (triangles in the model file's order, triangles generated from the
//! teapot by [`crate::corpus_generated`], or Suffern's spheres) and their
//! ray sets (camera rays, one cosine-distributed bounce from the camera
//! hits, and the stadium's prop rays). Loading is `gridrt_io`'s; nothing
//! here traces.

// `Real` is f32 or f64 (the `f64` feature): casts to it are not no-ops in
// both builds.
#![allow(clippy::unnecessary_cast)]

use crate::corpus_generated::Generated;
use gridrt_grid::{Accelerator, Hit, Primitive, Ray, Real, Vec3};
use gridrt_tracer::{Projection, Sphere, Triangle};
use std::path::{Path, PathBuf};

/// A scene's primitives.
#[derive(Debug)]
pub enum Prims {
    /// Triangles, as vertex triples (the grids and Embree get the same).
    Tris(Vec<[Vec3; 3]>),
    /// Spheres (no Embree peer: `embree_rays` reads triangles).
    Spheres(Vec<Sphere>),
}

impl Prims {
    pub fn len(&self) -> usize {
        match self {
            Prims::Tris(t) => t.len(),
            Prims::Spheres(s) => s.len(),
        }
    }

    pub fn triangles(&self) -> Vec<Triangle> {
        match self {
            Prims::Tris(t) => t.iter().map(|v| Triangle::new(v[0], v[1], v[2])).collect(),
            Prims::Spheres(_) => Vec::new(),
        }
    }

    /// The unit normal of primitive `prim` at `p`, facing against `dir`.
    fn normal(&self, prim: u32, p: Vec3, dir: Vec3) -> Vec3 {
        let n = match self {
            Prims::Tris(t) => {
                let [a, b, c] = t[prim as usize];
                (b - a).cross(c - a)
            }
            Prims::Spheres(s) => p - s[prim as usize].center,
        };
        let n = n.normalize_or_zero();
        if n.dot(dir) > 0.0 {
            -n
        } else {
            n
        }
    }

    /// The box of every primitive.
    fn bounds(&self) -> gridrt_bbox::Aabb {
        match self {
            Prims::Tris(t) => tris_bounds(t),
            Prims::Spheres(s) => s
                .iter()
                .fold(gridrt_bbox::Aabb::EMPTY, |b, s| b.union(s.bounds(&()))),
        }
    }
}

/// The box of every vertex of `tris`.
pub fn tris_bounds(tris: &[[Vec3; 3]]) -> gridrt_bbox::Aabb {
    tris.iter()
        .flatten()
        .fold(gridrt_bbox::Aabb::EMPTY, |b, p| b.grow(*p))
}

/// One ray query with its range.
#[derive(Clone, Copy, Debug)]
pub struct Query {
    pub ray: Ray,
    pub t_min: Real,
}

/// A named set of rays.
#[derive(Debug)]
pub struct RaySet {
    /// `camera`, `incoherent` or `props`.
    pub kind: &'static str,
    /// What the rays are (for the report).
    pub about: String,
    pub rays: Vec<Query>,
}

/// One corpus scene.
#[derive(Debug)]
pub struct CorpusScene {
    pub name: &'static str,
    pub about: String,
    pub prims: Prims,
    pub sets: Vec<RaySet>,
}

/// The fewest bounce rays that make an incoherent set.
const MIN_BOUNCES: usize = 1000;

/// A pinhole view.
#[derive(Clone, Copy, Debug)]
pub struct View {
    pub eye: Vec3,
    pub look_at: Vec3,
    pub vfov_deg: f64,
}

/// What a scene is made from.
#[derive(Clone, Debug)]
pub enum Source {
    /// A model file (OBJ, glTF, GLB), moved by `offset`; its own camera or
    /// one framing it when `view` is `None`. With `floor`, the model
    /// stands on a square of two triangles [`FLOOR_SIZE`] times its
    /// longest extent across: a large, detailed object in a large scene.
    Model {
        file: PathBuf,
        offset: [f64; 3],
        views: Vec<(&'static str, Option<View>)>,
        props: bool,
        floor: bool,
    },
    /// Suffern's `n` random spheres (seed 15), his 400×400 camera.
    Spheres(usize),
    /// Suffern's 1,000 spheres, each a 32×17 UV sphere (1,024,000
    /// triangles, as the Embree peer's `-m` case), his camera.
    SphereMesh,
    /// A scene generated from the committed teapot ([`crate::corpus_generated`]).
    Generated(Generated),
}

/// How many times a model's longest extent its floor spans
/// ([`Source::Model`]).
pub const FLOOR_SIZE: Real = 400.0;

/// A corpus entry: a name, a source, whether its files come from
/// `../shared` (skipped when absent).
#[derive(Clone, Debug)]
pub struct Entry {
    pub name: &'static str,
    pub source: Source,
    pub shared: bool,
}

/// The close-up view of the stadium's props.
pub const CLOSE: View = View {
    eye: Vec3::new(1.2, 1.6, 5.0),
    look_at: Vec3::new(1.2, 0.6, 0.0),
    vfov_deg: 40.0,
};

/// The corpus: `root` is the repository, `shared` the `../shared` folder.
pub fn entries(root: &Path, shared: &Path) -> Vec<Entry> {
    let s = |rel: &str| shared.join("scenes").join(rel);
    let model = |file: PathBuf, views: Vec<(&'static str, Option<View>)>| Source::Model {
        file,
        offset: [0.0; 3],
        views,
        props: false,
        floor: false,
    };
    let framed = || vec![("", None)];
    vec![
        Entry {
            name: "stadium",
            source: Source::Model {
                file: s("teapot_in_stadium/teapot_in_stadium.obj"),
                offset: [0.0; 3],
                views: vec![("far", None), ("close", Some(CLOSE))],
                props: true,
                floor: false,
            },
            shared: true,
        },
        Entry {
            name: "2CylinderEngine",
            source: model(s("gltf_2cylinder_engine/2CylinderEngine.glb"), framed()),
            shared: true,
        },
        Entry {
            name: "CesiumMilkTruck",
            source: model(
                root.join("fixtures/meshes/gltf_cesium_milk_truck/CesiumMilkTruck.glb"),
                framed(),
            ),
            shared: false,
        },
        Entry {
            name: "bunny",
            source: model(s("bunny/stanford-bunny.obj"), framed()),
            shared: true,
        },
        Entry {
            name: "dragon",
            source: model(s("dragon/dragon.glb"), framed()),
            shared: true,
        },
        Entry {
            name: "dragon+floor",
            source: Source::Model {
                file: s("dragon/dragon.glb"),
                offset: [0.0; 3],
                views: framed(),
                props: false,
                floor: true,
            },
            shared: true,
        },
        Entry {
            name: "cornell",
            source: model(
                root.join("fixtures/meshes/cornell_box/CornellBox-Original.obj"),
                framed(),
            ),
            shared: false,
        },
        Entry {
            name: "teapot+1e5",
            source: Source::Model {
                file: root.join("fixtures/meshes/teapot/teapot.obj"),
                offset: [1e5, 0.0, 0.0],
                views: framed(),
                props: false,
                floor: false,
            },
            shared: false,
        },
        Entry {
            name: "teapots",
            source: Source::Generated(Generated::Teapots),
            shared: false,
        },
        Entry {
            name: "city",
            source: Source::Generated(Generated::City),
            shared: false,
        },
        Entry {
            name: "spheres-1e6",
            source: Source::Spheres(1_000_000),
            shared: false,
        },
        Entry {
            name: "mesh-1024000",
            source: Source::SphereMesh,
            shared: false,
        },
    ]
}

/// A tiny deterministic generator (the 64-bit LCG of the Embree peer).
pub struct Lcg(pub u64);

impl Lcg {
    /// A number in `[0, 1)`.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Camera rays through the pixel centres of a `w`×`h` pinhole image, row
/// by row from the top.
pub fn camera_rays(v: View, w: u32, h: u32) -> Vec<Query> {
    let fwd = (v.look_at - v.eye).normalize();
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    let tan = (v.vfov_deg.to_radians() * 0.5).tan();
    let aspect = f64::from(w) / f64::from(h);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let sx = ((f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0) * tan * aspect;
            let sy = (1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0) * tan;
            let d = fwd + right * sx as Real + up * sy as Real;
            out.push(Query {
                ray: Ray::new(v.eye, d.normalize()),
                t_min: 0.0,
            });
        }
    }
    out
}

/// Suffern's 400×400 camera rays (eye (0, 0, 20), view plane at 3600).
pub fn suffern_rays() -> Vec<Query> {
    let n = gridrt_tracer::suffern::RESOLUTION;
    (0..n)
        .flat_map(|r| (0..n).map(move |c| (c, r)))
        .map(|(c, r)| Query {
            ray: crate::measure::camera_ray(c, r, n),
            t_min: 0.0,
        })
        .collect()
}

/// One cosine-distributed bounce from every camera hit: from the hit
/// point, lifted off the surface along its normal by a margin above the
/// rounding of the point, into the hemisphere facing the camera. Fixed
/// seed, so every accelerator and Embree trace the same rays.
pub fn bounce_rays(prims: &Prims, camera: &[Query], hits: &[Option<Hit>]) -> Vec<Query> {
    let b = prims.bounds();
    let diag = (b.max - b.min).length();
    let mut rng = Lcg(0x5eed);
    let mut out = Vec::new();
    for (q, h) in camera.iter().zip(hits) {
        let Some(h) = h else { continue };
        let p = q.ray.at(h.t);
        let n = prims.normal(h.prim, p, q.ray.dir);
        if n == Vec3::ZERO {
            continue;
        }
        let eps = 1e-5 * diag + 1e-5 * p.abs().max_element();
        let (u1, u2) = (rng.next(), rng.next());
        let r = u1.sqrt();
        let phi = std::f64::consts::TAU * u2;
        let (t1, t2) = onb(n);
        let d = t1 * (r * phi.cos()) as Real
            + t2 * (r * phi.sin()) as Real
            + n * (1.0 - u1).max(0.0).sqrt() as Real;
        let d = d.normalize_or_zero();
        if d == Vec3::ZERO {
            continue;
        }
        out.push(Query {
            ray: Ray::new(p + n * eps, d),
            t_min: 0.0,
        });
    }
    out
}

/// Two unit vectors completing `n` to an orthonormal basis (Duff et al.
/// 2017).
fn onb(n: Vec3) -> (Vec3, Vec3) {
    let s: Real = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// `count` rays from `eye` at vertices of the small meshes (the props),
/// picked with a fixed seed.
fn prop_rays(small: &[Vec3], eye: Vec3, count: usize) -> Vec<Query> {
    let mut rng = Lcg(0x7e4);
    (0..count.min(small.len() * 16))
        .filter_map(|_| {
            let k = ((rng.next() * small.len() as f64) as usize).min(small.len() - 1);
            let d = small[k] - eye;
            (d != Vec3::ZERO).then(|| Query {
                ray: Ray::new(eye, d),
                t_min: 0.0,
            })
        })
        .collect()
}

/// Every answer of `rays` against the exhaustive accelerator's twin: the
/// hits the bounce rays start from. Uses whatever `A` is given.
pub fn closest_all<A: Accelerator>(a: &A, rays: &[Query]) -> Vec<Option<Hit>> {
    let mut s = a.scratch();
    rays.iter()
        .map(|q| a.closest_hit(&q.ray, q.t_min, Real::INFINITY, &mut s))
        .collect()
}

/// Loads an entry and makes its ray sets (`w`×`h` camera rays per view).
///
/// # Errors
/// A message naming the file when it cannot be read.
pub fn load(e: &Entry, root: &Path, w: u32, h: u32) -> Result<CorpusScene, String> {
    let (prims, views, about, props_from): (Prims, Vec<(String, Vec<Query>)>, String, _) = match &e
        .source
    {
        Source::Model {
            file,
            offset,
            views,
            props,
            floor,
        } => {
            let sandbox = gridrt_io::Sandbox::for_input(file);
            let model = gridrt_io::load_model_in(file, &sandbox).map_err(|e| e.to_string())?;
            let off = Vec3::new(offset[0] as Real, offset[1] as Real, offset[2] as Real);
            let mut tris: Vec<[Vec3; 3]> = model
                .triangles()
                .map(|t| [t[0] + off, t[1] + off, t[2] + off])
                .collect();
            if *floor {
                tris.extend(floor_under(&tris));
            }
            let small: Vec<Vec3> = if *props {
                small_mesh_vertices(&model, off)
            } else {
                Vec::new()
            };
            let loaded = gridrt_io::scene_from_model(model);
            let cam = &loaded.scene.camera;
            let vfov = match cam.projection {
                Projection::Perspective { vfov_deg } => f64::from(vfov_deg as f32),
                _ => 40.0,
            };
            let framed = View {
                eye: cam.eye + off,
                look_at: cam.look_at + off,
                vfov_deg: vfov,
            };
            let sets = views
                .iter()
                .map(|(label, v)| view_rays(label, v.unwrap_or(framed), w, h))
                .collect();
            let about = format!(
                "{}{}{}",
                crate::util::show(file),
                if *offset == [0.0; 3] {
                    String::new()
                } else {
                    format!(" moved by ({}, {}, {})", offset[0], offset[1], offset[2])
                },
                if *floor {
                    format!(" on a floor {FLOOR_SIZE} times its size")
                } else {
                    String::new()
                }
            );
            (Prims::Tris(tris), sets, about, small)
        }
        Source::Spheres(n) => {
            let spheres = gridrt_tracer::suffern::spheres(*n, gridrt_tracer::suffern::DEFAULT_SEED)
                .into_iter()
                .map(|s| Sphere::new(s.center, s.radius))
                .collect();
            (
                Prims::Spheres(spheres),
                vec![("Suffern's 400×400 camera".to_string(), suffern_rays())],
                format!("Suffern's {n} random spheres (seed 15)"),
                Vec::new(),
            )
        }
        Source::Generated(g) => {
            let built = crate::corpus_generated::build(*g, root)?;
            let sets = built
                .views
                .iter()
                .map(|&(label, v)| view_rays(label, v, w, h))
                .collect();
            (Prims::Tris(built.tris), sets, built.about, Vec::new())
        }
        Source::SphereMesh => {
            let spheres =
                gridrt_tracer::suffern::spheres(1000, gridrt_tracer::suffern::DEFAULT_SEED);
            let tris = uv_sphere_mesh(&spheres, 32, 17);
            (
                Prims::Tris(tris),
                vec![("Suffern's 400×400 camera".to_string(), suffern_rays())],
                "Suffern's 1000 spheres as 32×17 UV spheres".to_string(),
                Vec::new(),
            )
        }
    };
    let mut sets = Vec::new();
    // The camera hits, for the bounce rays, from a flat grid (every
    // accelerator gives the same answers).
    let finder = Finder::new(&prims);
    for (about, rays) in views {
        let hits = finder.closest(&rays);
        let bounce = bounce_rays(&prims, &rays, &hits);
        let label = about.split(':').next().unwrap_or("").to_string();
        let kinds: (&'static str, &'static str) = match label.as_str() {
            "far" => ("far camera", "far incoherent"),
            "close" => ("close camera", "close incoherent"),
            "high" => ("high camera", "high incoherent"),
            _ => ("camera", "incoherent"),
        };
        sets.push(RaySet {
            kind: kinds.0,
            about: about.clone(),
            rays,
        });
        // A view that hits almost nothing (the teapots from outside their
        // cube) has too few bounces to time.
        if bounce.len() >= MIN_BOUNCES {
            sets.push(RaySet {
                kind: kinds.1,
                about: format!("one cosine bounce from the hits of: {about}"),
                rays: bounce,
            });
        }
    }
    if !props_from.is_empty() {
        let eye = Vec3::new(1.2, 2.5, 4.9);
        sets.push(RaySet {
            kind: "props",
            about: format!(
                "100000 rays from (1.2, 2.5, 4.9) at the vertices of the teapot and the bunny ({} vertices)",
                props_from.len()
            ),
            rays: prop_rays(&props_from, eye, 100_000),
        });
    }
    Ok(CorpusScene {
        name: e.name,
        about,
        prims,
        sets,
    })
}

/// The two triangles of a square [`FLOOR_SIZE`] times the longest extent
/// of `tris` across, centred under them at the bottom of their box.
fn floor_under(tris: &[[Vec3; 3]]) -> [[Vec3; 3]; 2] {
    let b = tris_bounds(tris);
    let half = 0.5 * FLOOR_SIZE * (b.max - b.min).max_element();
    let c = (b.min + b.max) * 0.5;
    let at = |dx: Real, dz: Real| Vec3::new(c.x + dx * half, b.min.y, c.z + dz * half);
    let [a, b, c, d] = [at(-1.0, -1.0), at(1.0, -1.0), at(1.0, 1.0), at(-1.0, 1.0)];
    [[a, c, b], [a, d, c]]
}

/// The camera rays of view `v`, and what they are for the report (after
/// the view's `label` and a colon, if it has one).
fn view_rays(label: &str, v: View, w: u32, h: u32) -> (String, Vec<Query>) {
    let about = format!(
        "{w}×{h} from ({:.4}, {:.4}, {:.4}) to ({:.4}, {:.4}, {:.4}), fov {:.0}°",
        v.eye.x, v.eye.y, v.eye.z, v.look_at.x, v.look_at.y, v.look_at.z, v.vfov_deg
    );
    let about = if label.is_empty() {
        about
    } else {
        format!("{label}: {about}")
    };
    (about, camera_rays(v, w, h))
}

/// The vertices of the meshes whose box is under a hundredth of the
/// model's (the props of the stadium).
fn small_mesh_vertices(model: &gridrt_io::Model, off: Vec3) -> Vec<Vec3> {
    let all = model.bounds();
    let big = (all.max - all.min).length();
    model
        .meshes
        .iter()
        .map(|m| &*m.mesh)
        .filter(|m| {
            let b = m
                .positions
                .iter()
                .fold(gridrt_bbox::Aabb::EMPTY, |b, p| b.grow(*p));
            (b.max - b.min).length() < 0.01 * big
        })
        .flat_map(|m| m.positions.iter().map(move |&p| p + off))
        .collect()
}

/// Answers closest-hit queries with a flat grid over the scene (to place
/// the bounce rays).
enum Finder {
    Tris(gridrt_grid::Grid<Triangle>),
    Spheres(gridrt_grid::Grid<Sphere>),
}

impl Finder {
    fn new(p: &Prims) -> Self {
        let c = gridrt_grid::GridConfig::default();
        match p {
            Prims::Tris(_) => Finder::Tris(gridrt_grid::Grid::build(p.triangles(), &c)),
            Prims::Spheres(s) => Finder::Spheres(gridrt_grid::Grid::build(s.clone(), &c)),
        }
    }
    fn closest(&self, rays: &[Query]) -> Vec<Option<Hit>> {
        match self {
            Finder::Tris(g) => closest_all(g, rays),
            Finder::Spheres(g) => closest_all(g, rays),
        }
    }
}

/// Suffern's spheres tessellated as the Embree peer's mesh case does:
/// `slices` × `stacks` UV spheres, poles first.
pub fn uv_sphere_mesh(
    spheres: &[gridrt_tracer::suffern::RandomSphere],
    slices: usize,
    stacks: usize,
) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::with_capacity(spheres.len() * 2 * slices * (stacks - 1));
    for s in spheres {
        let (c, rad) = (s.center, s.radius as f64);
        let v3 = |x: f64, y: f64, z: f64| c + Vec3::new(x as Real, y as Real, z as Real);
        let mut verts = vec![v3(0.0, rad, 0.0)];
        for k in 1..stacks {
            for j in 0..slices {
                let th = std::f64::consts::PI * k as f64 / stacks as f64;
                let ph = std::f64::consts::TAU * j as f64 / slices as f64;
                verts.push(v3(
                    rad * th.sin() * ph.sin(),
                    rad * th.cos(),
                    rad * th.sin() * ph.cos(),
                ));
            }
        }
        let south = verts.len();
        verts.push(v3(0.0, -rad, 0.0));
        let ring = |k: usize, j: usize| 1 + (k - 1) * slices + j % slices;
        for j in 0..slices {
            tris.push([verts[0], verts[ring(1, j)], verts[ring(1, j + 1)]]);
            tris.push([
                verts[south],
                verts[ring(stacks - 1, j + 1)],
                verts[ring(stacks - 1, j)],
            ]);
        }
        for k in 1..stacks - 1 {
            for j in 0..slices {
                tris.push([
                    verts[ring(k, j)],
                    verts[ring(k + 1, j)],
                    verts[ring(k + 1, j + 1)],
                ]);
                tris.push([
                    verts[ring(k, j)],
                    verts[ring(k + 1, j + 1)],
                    verts[ring(k, j + 1)],
                ]);
            }
        }
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_grid::Exhaustive;

    #[test]
    fn the_floor_lies_under_the_model_facing_up() {
        let tri = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(2.0, 2.5, 3.0),
            Vec3::new(1.0, 4.0, 3.5),
        ];
        let floor = floor_under(&[tri]);
        for t in floor {
            assert!(t.iter().all(|p| p.y == 2.0));
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            assert!(n.y > 0.0 && n.x == 0.0 && n.z == 0.0, "{n:?}");
        }
        let xs = floor.iter().flatten().map(|p| p.x);
        let span = xs.clone().fold(Real::MIN, Real::max) - xs.fold(Real::MAX, Real::min);
        assert_eq!(span, FLOOR_SIZE * 2.0);
    }

    #[test]
    fn the_mesh_has_the_peers_triangle_count() {
        let s = gridrt_tracer::suffern::spheres(3, 15);
        assert_eq!(uv_sphere_mesh(&s, 32, 17).len(), 3 * 1024);
    }

    #[test]
    fn bounces_leave_the_surface_into_the_camera_side() {
        let tri = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let prims = Prims::Tris(vec![tri]);
        let cam = camera_rays(
            View {
                eye: Vec3::new(0.0, 0.0, 3.0),
                look_at: Vec3::ZERO,
                vfov_deg: 20.0,
            },
            8,
            8,
        );
        let hits = Finder::new(&prims).closest(&cam);
        assert!(hits.iter().filter(|h| h.is_some()).count() > 10);
        let b = bounce_rays(&prims, &cam, &hits);
        assert_eq!(b.len(), hits.iter().filter(|h| h.is_some()).count());
        assert!(b.iter().all(|q| q.ray.origin.z > 0.0 && q.ray.dir.z > 0.0));
        let e = Exhaustive::new(prims.triangles());
        assert!(closest_all(&e, &b).iter().all(Option::is_none));
    }
}
