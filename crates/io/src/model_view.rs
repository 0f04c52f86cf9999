//! How a model rendered on its own is shown when its file has no camera or
//! lights: a room (a model that surrounds its own centre, such as a Cornell
//! box) is seen from inside, through its open side if it has one, and lit
//! from under its ceiling; any other model stands on a ground plane under
//! a soft key, fill and ambient light.

use crate::model::{to_dvec3, to_vec3, Model};
use glam::DVec3;
use gridrt_bbox::{Aabb, Ray, Real, Vec3};
use gridrt_tracer::{Camera, Light, Material, Projection, Rgb, Shear, Triangle};

/// Most triangles the room test looks at (it tests each against six
/// rays); a larger model is taken to be an object, not a room.
const MAX_ROOM_TRIANGLES: usize = 2_000_000;

/// The six axis directions, +z first: the open side of a room is looked
/// for in this order.
const AXES: [DVec3; 6] = [
    DVec3::Z,
    DVec3::X,
    DVec3::NEG_X,
    DVec3::NEG_Z,
    DVec3::Y,
    DVec3::NEG_Y,
];

/// When the model surrounds the centre of its bounds, facing it (rays
/// from there along at least five of the six axes meet a front face
/// first, and none meets a back face: a room open on one side at most),
/// the direction in which it is open (+z when it is closed, or open only
/// above or below); `None` for an object, whose faces turn away from any
/// point inside it.
pub(crate) fn room_opening(model: &Model) -> Option<DVec3> {
    if model.triangle_count() > MAX_ROOM_TRIANGLES {
        return None;
    }
    let c = model.bounds().centroid();
    let dirs = AXES.map(to_vec3);
    let shears = dirs.map(|d| Shear::new(&Ray::new(c, d)));
    // The first face met along each axis, in one pass over the triangles
    // (made as they are tested, not kept: a model of a million would take
    // 40 MB), each tested against the six rays.
    let mut first: [Option<(Real, Triangle)>; 6] = [None; 6];
    for [a, b, e] in model.triangles() {
        let t = Triangle::new(a, b, e);
        for (shear, best) in shears.iter().zip(&mut first) {
            let far = best.map_or(Real::INFINITY, |b| b.0);
            if let Some(h) = t.intersect(shear, 0.0, far) {
                *best = Some((h.t, t));
            }
        }
    }
    // Per axis, `Some(true)` when the first face faces the centre
    // (counter-clockwise seen from it), `None` for no face.
    let seen: [Option<bool>; 6] =
        std::array::from_fn(|i| first[i].map(|(_, t)| t.area_normal().dot(dirs[i]) < 0.0));
    let facing = seen.iter().filter(|&&f| f == Some(true)).count();
    if facing < 5 || seen.contains(&Some(false)) {
        return None;
    }
    let open = AXES[..4].iter().zip(&seen).find(|(_, f)| f.is_none());
    Some(open.map_or(DVec3::Z, |(d, _)| *d))
}

/// A camera inside the room `b`, near its wall in direction `open` (the
/// open side), looking at the far wall, with a field of view that holds
/// the far wall.
pub(crate) fn room_camera(b: Aabb, open: DVec3, aspect: f64) -> Camera {
    let c = to_dvec3(b.centroid());
    let half = to_dvec3(b.extent()) * 0.5;
    let depth = open.abs().dot(half);
    let eye = c + open * depth * 0.9;
    // The far wall, 1.9 half-depths away: half its height, and half its
    // width over the aspect ratio, must fit in half the field.
    let side = if open.x != 0.0 { half.z } else { half.x };
    let fit = half.y.max(side / aspect.max(1e-3));
    let vfov =
        (2.0 * (fit / (1.9 * depth).max(1e-9)).atan().to_degrees() * 1.05).clamp(20.0, 100.0);
    Camera {
        eye: to_vec3(eye),
        look_at: to_vec3(c),
        up: Vec3::Y,
        projection: Projection::Perspective {
            vfov_deg: vfov as Real,
        },
        lens: None,
    }
}

/// Lights of a room: ambient light and a point light just under the
/// middle of the ceiling, with shadows.
pub(crate) fn room_lights(b: Aabb) -> Vec<Light> {
    let c = to_dvec3(b.centroid());
    let half = to_dvec3(b.extent()) * 0.5;
    vec![
        Light::Ambient {
            color: Rgb::ONE,
            intensity: 0.3,
            occlusion: None,
        },
        Light::Point {
            position: to_vec3(c + DVec3::Y * half.y * 0.8),
            color: Rgb::ONE,
            intensity: 1.2,
            inverse_square: false,
            shadows: true,
        },
    ]
}

/// Soft lights for an object: ambient light, a key light from above the
/// camera's right shoulder with shadows, and a shadowless fill light from
/// the left.
pub(crate) fn object_lights(camera: &Camera) -> Vec<Light> {
    let back = to_dvec3(camera.eye - camera.look_at).normalize_or(DVec3::Z);
    let up = to_dvec3(camera.up).normalize_or(DVec3::Y);
    let right = up.cross(back).normalize_or(DVec3::X);
    let key = (back + up * 0.9 + right * 0.5).normalize_or(DVec3::Y);
    let fill = (back + up * 0.3 - right * 0.9).normalize_or(DVec3::Y);
    vec![
        Light::Ambient {
            color: Rgb::ONE,
            intensity: 0.3,
            occlusion: None,
        },
        Light::Directional {
            direction: to_vec3(key),
            color: Rgb::ONE,
            intensity: 2.4,
            shadows: true,
        },
        Light::Directional {
            direction: to_vec3(fill),
            color: Rgb::ONE,
            intensity: 0.8,
            shadows: false,
        },
    ]
}

/// The ground under an object: a plane a hair below its lowest point
/// (so that faces lying on it do not fight with it), and its material.
pub(crate) fn ground(b: Aabb) -> (Vec3, Material) {
    let gap = to_dvec3(b.extent()).length() * 1e-4;
    let mut p = b.centroid();
    p.y = b.min.y - gap as Real;
    (
        p,
        Material::Matte {
            color: Rgb::splat(0.55),
            ka: 0.25,
            kd: 0.75,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelMesh;
    use gridrt_tracer::Mesh;

    /// A box of six quads; `open` leaves out the +z face.
    fn room(open: bool) -> Model {
        let positions = (0..8)
            .map(|i| {
                Vec3::new(
                    (i & 1) as Real * 2.0 - 1.0,
                    ((i >> 1) & 1) as Real * 2.0 - 1.0,
                    ((i >> 2) & 1) as Real * 2.0 - 1.0,
                )
            })
            .collect();
        let mut quads = vec![
            [0, 2, 3, 1],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        if !open {
            quads.push([4, 5, 7, 6]);
        }
        let triangles = quads
            .iter()
            // Reversed: the walls face the inside.
            .flat_map(|q| [[q[0], q[2], q[1]], [q[0], q[3], q[2]]])
            .collect();
        Model {
            path: "room.obj".into(),
            meshes: vec![ModelMesh {
                mesh: std::sync::Arc::new(Mesh {
                    name: "room".into(),
                    positions,
                    normals: vec![],
                    uvs: vec![],
                    uvs1: vec![],
                    colors: vec![],
                    triangles,
                }),
                material: None,
                mirrored: false,
                placement: None,
            }],
            materials: vec![],
            cameras: vec![],
            lights: vec![],
            textures: Vec::new(),
            warnings: vec![],
        }
    }

    #[test]
    fn rooms_are_seen_from_inside_through_their_open_side() {
        assert_eq!(room_opening(&room(true)), Some(DVec3::Z));
        assert_eq!(room_opening(&room(false)), Some(DVec3::Z));
        let cam = room_camera(room(true).bounds(), DVec3::Z, 4.0 / 3.0);
        assert!(cam.eye.z > 0.8 && cam.eye.z < 1.0, "{}", cam.eye);
        // Turned a quarter round, the open side faces +x.
        let mut m = room(true);
        for p in &mut std::sync::Arc::make_mut(&mut m.meshes[0].mesh).positions {
            *p = Vec3::new(p.z, p.y, -p.x);
        }
        assert_eq!(room_opening(&m), Some(DVec3::X));
    }

    #[test]
    fn half_a_room_and_a_closed_object_are_not_rooms() {
        // A back wall, floor and ceiling do not surround the centre.
        let mut m = room(true);
        std::sync::Arc::make_mut(&mut m.meshes[0].mesh)
            .triangles
            .truncate(6);
        assert_eq!(room_opening(&m), None);
        // The closed box turned inside out: its faces look away from the
        // centre, as an object's do.
        let mut m = room(false);
        for t in &mut std::sync::Arc::make_mut(&mut m.meshes[0].mesh).triangles {
            t.swap(1, 2);
        }
        assert_eq!(room_opening(&m), None);
    }
}
