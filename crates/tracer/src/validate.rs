//! Validation of a [`Scene`] before it is prepared: every material, light,
//! object and sphere set, with the error that names what is wrong.

use crate::camera::CameraModel;
use crate::error::SceneError;
use crate::float::to_f64;
use crate::instancing::SharedMeshes;
use crate::lights::AreaLight;
use crate::prepare::MAX_PIXELS;
use crate::scene::{Geometry, Light, Material, Mesh, Occlusion, Rgb, Scene, SphereSet};
use crate::shapes::Sphere;
use gridrt_bbox::math::Lanes;
use gridrt_bbox::Real;

pub(crate) fn color_ok(c: Rgb) -> bool {
    c.is_finite() && c.cmpge(Rgb::ZERO).all()
}

fn coef_ok(k: f32) -> bool {
    k.is_finite() && k >= 0.0
}

fn check_material(i: usize, m: &Material) -> Result<(), SceneError> {
    let bad = |reason| {
        Err(SceneError::BadMaterial {
            material: i,
            reason,
        })
    };
    match *m {
        Material::Matte { color, ka, kd } => {
            if !color_ok(color) {
                return bad("the colour must be finite and ≥ 0 in every channel");
            }
            if !coef_ok(ka) || !coef_ok(kd) {
                return bad("ka and kd must be finite and ≥ 0");
            }
        }
        Material::Phong {
            color,
            ka,
            kd,
            ks,
            exp,
            specular,
        } => {
            if !color_ok(color) || !color_ok(specular) {
                return bad("the colours must be finite and ≥ 0 in every channel");
            }
            if ![ka, kd, ks, exp].into_iter().all(coef_ok) {
                return bad("ka, kd, ks and exp must be finite and ≥ 0");
            }
        }
        Material::Reflective {
            color,
            ka,
            kd,
            ks,
            exp,
            kr,
            reflect,
        } => {
            if !color_ok(color) || !color_ok(reflect) {
                return bad("the colours must be finite and ≥ 0 in every channel");
            }
            if ![ka, kd, ks, exp, kr].into_iter().all(coef_ok) {
                return bad("ka, kd, ks, exp and kr must be finite and ≥ 0");
            }
        }
        Material::Dielectric { ior, tint } => {
            if !(ior.is_finite() && ior > 0.0) {
                return bad("the index of refraction must be finite and > 0 (glass is about 1.5)");
            }
            if !color_ok(tint) {
                return bad("the tint must be finite and ≥ 0 in every channel (white = clear)");
            }
        }
        Material::Conductor { fresnel, roughness } => {
            if !(0.0..=1.0).contains(&roughness) {
                return bad("the roughness must be in [0, 1]");
            }
            match fresnel {
                crate::ConductorFresnel::Schlick { f0 } => {
                    if !color_ok(f0) || f0.max_element() > 1.0 {
                        return bad("the reflectance f0 must be in [0, 1] in every channel");
                    }
                }
                crate::ConductorFresnel::Complex { eta, k } => {
                    if !(eta.is_finite() && eta.cmpgt(Rgb::ZERO).all() && color_ok(k)) {
                        return bad(
                            "eta must be finite and > 0, k finite and ≥ 0, in every channel",
                        );
                    }
                }
            }
        }
        Material::RoughDielectric {
            ior,
            tint,
            roughness,
        } => {
            if !(ior.is_finite() && ior > 0.0) {
                return bad("the index of refraction must be finite and > 0 (glass is about 1.5)");
            }
            if !color_ok(tint) {
                return bad("the tint must be finite and ≥ 0 in every channel (white = clear)");
            }
            if !(0.0..=1.0).contains(&roughness) {
                return bad("the roughness must be in [0, 1]");
            }
        }
        Material::MetallicRoughness {
            base,
            metallic,
            roughness,
        } => {
            if !color_ok(base) || base.max_element() > 1.0 {
                return bad("the base colour must be in [0, 1] in every channel");
            }
            // `contains` is false for NaN.
            if !((0.0..=1.0).contains(&metallic) && (0.0..=1.0).contains(&roughness)) {
                return bad("metallic and roughness must be in [0, 1]");
            }
        }
        Material::Emissive { color, strength } => {
            if !color_ok(color) || !coef_ok(strength) {
                return bad("the colour and strength must be finite and ≥ 0");
            }
        }
    }
    Ok(())
}

fn check_light(i: usize, l: &Light) -> Result<(), SceneError> {
    let bad = |reason| Err(SceneError::BadLight { light: i, reason });
    let (color, intensity) = match *l {
        Light::Ambient {
            color,
            intensity,
            occlusion,
        } => {
            if let Some(o) = occlusion {
                if !(1..=Occlusion::MAX_SAMPLES).contains(&o.samples) {
                    return bad("the occlusion samples must be in 1..=1024");
                }
                // `!(x > 0)` is true for NaN.
                if !(o.distance > 0.0) {
                    return bad("the occlusion distance must be > 0 (omit it for no limit)");
                }
                if !(0.0..=1.0).contains(&o.min_amount) {
                    return bad("the occlusion's min_amount must be in [0, 1]");
                }
            }
            (color, intensity)
        }
        Light::Point {
            position,
            color,
            intensity,
            ..
        } => {
            if !position.is_finite() {
                return bad("the position is not finite; give finite coordinates");
            }
            (color, intensity)
        }
        Light::Directional {
            direction,
            color,
            intensity,
            ..
        } => {
            if !direction.is_finite() || direction.try_normalize().is_none() {
                return bad("the direction is zero or not finite; give the (non-zero) direction towards the light");
            }
            (color, intensity)
        }
        Light::Spot {
            position,
            direction,
            color,
            intensity,
            inner_deg,
            outer_deg,
            ..
        } => {
            if !position.is_finite() {
                return bad("the position is not finite; give finite coordinates");
            }
            if !direction.is_finite() || direction.try_normalize().is_none() {
                return bad("the direction is zero or not finite; give the (non-zero) direction the spot points to");
            }
            if !(outer_deg > 0.0 && outer_deg <= 180.0) {
                return bad("the outer angle must be in (0, 180] degrees");
            }
            if !(inner_deg >= 0.0 && inner_deg <= outer_deg) {
                return bad("the inner angle must be in [0, outer angle] degrees");
            }
            (color, intensity)
        }
        Light::Rect {
            corner,
            edge_u,
            edge_v,
            color,
            intensity,
        } => {
            if !corner.is_finite() || !edge_u.is_finite() || !edge_v.is_finite() {
                return bad("the corner and edges must be finite");
            }
            if AreaLight::rect(corner, edge_u, edge_v, 0).is_none() {
                return bad("the edges are zero or parallel; give two edges that span a rectangle");
            }
            (color, intensity)
        }
        Light::Disk {
            center,
            normal,
            radius,
            color,
            intensity,
        } => {
            if !center.is_finite() || !normal.is_finite() {
                return bad("the centre and normal must be finite");
            }
            if normal.try_normalize().is_none() {
                return bad("the normal is zero; give the side the disk emits to");
            }
            if !(radius > 0.0) || !radius.is_finite() {
                return bad("the radius must be finite and > 0");
            }
            (color, intensity)
        }
        Light::Environment {
            color,
            intensity,
            ref image,
        } => {
            if let Some(img) = image {
                let n = u64::from(img.width) * u64::from(img.height);
                if n == 0 || img.pixels.len() as u64 != n {
                    return bad(
                        "the environment image is empty or its pixel count is not width × height",
                    );
                }
                if n > MAX_PIXELS {
                    return bad("the environment image has more than 2^26 pixels; scale it down");
                }
                if !img.pixels.iter().all(|&p| color_ok(p)) {
                    return bad("the environment image has negative or non-finite pixels");
                }
            }
            (color, intensity)
        }
    };
    if !color_ok(color) || !coef_ok(intensity) {
        return bad("the colour and intensity must be finite and ≥ 0");
    }
    Ok(())
}

/// Checks everything; returns the number of grid primitives and whether
/// they are all spheres.
pub(crate) fn validate(scene: &Scene, shared: &SharedMeshes) -> Result<(usize, bool), SceneError> {
    let s = &scene.settings;
    if s.width == 0 || s.height == 0 {
        return Err(SceneError::EmptyImage {
            width: s.width,
            height: s.height,
        });
    }
    if u64::from(s.width) * u64::from(s.height) > MAX_PIXELS {
        return Err(SceneError::ImageTooLarge {
            width: s.width,
            height: s.height,
            max: MAX_PIXELS,
        });
    }
    if s.spp == 0 {
        return Err(SceneError::ZeroSamples);
    }
    if !s.filter.is_valid() {
        return Err(SceneError::BadFilter {
            filter: s.filter.describe(),
        });
    }
    if !s.background.is_finite() {
        return Err(SceneError::SettingNotFinite { what: "background" });
    }
    CameraModel::new(&scene.camera, s.width, s.height)?;
    for (i, m) in scene.materials.iter().enumerate() {
        check_material(i, m)?;
    }
    for (i, l) in scene.lights.iter().enumerate() {
        check_light(i, l)?;
        if matches!(l, Light::Environment { .. })
            && scene.lights[..i]
                .iter()
                .any(|l| matches!(l, Light::Environment { .. }))
        {
            return Err(SceneError::BadLight {
                light: i,
                reason: "a second Environment light: a scene has at most one",
            });
        }
    }
    scene
        .textures
        .check(scene.materials.len())
        .map_err(|reason| SceneError::BadTextures { reason })?;

    // Validate objects and count primitives.
    let mut all_spheres = true;
    let mut count = 0usize;
    for (i, o) in scene.objects.iter().enumerate() {
        if o.material as usize >= scene.materials.len() {
            return Err(SceneError::MaterialOutOfRange {
                object: i,
                material: o.material,
                count: scene.materials.len(),
            });
        }
        match &o.geometry {
            Geometry::Sphere { center, radius } => {
                if !center.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "sphere centre",
                    });
                }
                if !(*radius > 0.0 && radius.is_finite()) {
                    return Err(SceneError::BadRadius {
                        object: i,
                        radius: to_f64(*radius),
                    });
                }
                count += 1;
            }
            Geometry::Cuboid { min, max } => {
                if !min.is_finite() || !max.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "box corner",
                    });
                }
                if min.cmpgt(*max).any() {
                    return Err(SceneError::InvertedCuboid { object: i });
                }
                all_spheres = false;
                count += 1;
            }
            Geometry::Plane { point, normal } => {
                if !point.is_finite() || !normal.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "plane point or normal",
                    });
                }
                if normal.try_normalize().is_none() {
                    return Err(SceneError::ZeroNormal { object: i });
                }
            }
            Geometry::Mesh(m) => {
                check_mesh(i, m)?;
                all_spheres = false;
                count += m.triangles.len();
            }
            Geometry::Instance { mesh, to_world } => {
                check_mesh(i, mesh)?;
                if to_world.inverse().is_none() {
                    return Err(SceneError::BadTransform {
                        object: i,
                        reason: "the transform has a non-finite entry or is singular (a zero scale or a flattening matrix): it must be invertible",
                    });
                }
                if !to_world.keeps_finite(&mesh.bounds()) {
                    return Err(SceneError::BadTransform {
                        object: i,
                        reason: "the transformed mesh has non-finite coordinates: use a smaller scale or translation",
                    });
                }
                all_spheres = false;
                count += if shared.keeps(scene, o) {
                    1
                } else {
                    mesh.triangles.len()
                };
            }
            Geometry::Spheres(set) => {
                check_set(i, set)?;
                count += set.spheres.len();
            }
        }
    }
    if count > u32::MAX as usize {
        return Err(SceneError::TooManyPrimitives { count });
    }
    Ok((count, all_spheres))
}

fn check_set(object: usize, set: &SphereSet) -> Result<(), SceneError> {
    if !set.colors.is_empty() && set.colors.len() != set.spheres.len() {
        return Err(SceneError::SphereSetColors {
            object,
            colors: set.colors.len(),
            spheres: set.spheres.len(),
        });
    }
    // One branch-free pass in lanes first; the loop naming the first bad
    // one runs only when there is one.
    if !spheres_ok(&set.spheres) {
        for (sphere, s) in set.spheres.iter().enumerate() {
            let bad = |reason| SceneError::BadSetSphere {
                object,
                sphere,
                reason,
            };
            if !center_ok(s) {
                return Err(bad("the centre is not finite; give finite coordinates"));
            }
            if !radius_ok(s) {
                return Err(bad("the radius must be finite and > 0"));
            }
        }
    }
    // Drawn colours are in [0, 1) by construction; stored ones are checked.
    let given = set.colors.stored();
    if !colors_ok(given) {
        let sphere = given.iter().position(|&c| !color_ok(c)).unwrap_or(0);
        return Err(SceneError::BadSetSphere {
            object,
            sphere,
            reason: "the colour must be finite and ≥ 0 in every channel",
        });
    }
    Ok(())
}

fn center_ok(s: &Sphere) -> bool {
    s.center.is_finite()
}

fn radius_ok(s: &Sphere) -> bool {
    s.radius > 0.0 && s.radius.is_finite()
}

/// Whether `lanes` gives every item of `xs` all four lanes set, the masks
/// combined without a branch.
fn all_lanes<T>(xs: &[T], lanes: impl Fn(&T) -> u32) -> bool {
    xs.iter().fold(0xf, |ok, x| ok & lanes(x)) == 0xf
}

/// Whether every sphere passes [`center_ok`] and [`radius_ok`]: its four
/// numbers compared in lanes with their open bounds, which NaN fails.
fn spheres_ok(spheres: &[Sphere]) -> bool {
    let lo = Lanes::new(
        Real::NEG_INFINITY,
        Real::NEG_INFINITY,
        Real::NEG_INFINITY,
        0.0,
    );
    let hi = Lanes::splat(Real::INFINITY);
    all_lanes(spheres, |s| {
        let v = Lanes::new(s.center.x, s.center.y, s.center.z, s.radius);
        (v.cmpgt(lo) & v.cmplt(hi)).bitmask()
    })
}

/// Whether every colour passes [`color_ok`], in lanes as in [`spheres_ok`].
fn colors_ok(colors: &[Rgb]) -> bool {
    let hi = glam::Vec4::splat(f32::INFINITY);
    all_lanes(colors, |c| {
        let v = glam::Vec4::new(c.x, c.y, c.z, 0.0);
        (v.cmpge(glam::Vec4::ZERO) & v.cmplt(hi)).bitmask()
    })
}

/// The checks of a mesh's arrays: attribute counts, finite values,
/// indices in range.
fn check_mesh(i: usize, m: &Mesh) -> Result<(), SceneError> {
    let nv = m.positions.len();
    let name = || m.name.clone();
    let counts = [
        ("normals", m.normals.len()),
        ("uvs", m.uvs.len()),
        ("second uvs", m.uvs1.len()),
        ("colors", m.colors.len()),
    ];
    for (attribute, n) in counts {
        if n != 0 && n != nv {
            return Err(SceneError::MeshAttributeCount {
                object: i,
                mesh: name(),
                attribute,
                count: n,
                vertices: nv,
            });
        }
    }
    for (attribute, list) in [("position", &m.positions), ("normal", &m.normals)] {
        if let Some(v) = list.iter().position(|p| !p.is_finite()) {
            return Err(SceneError::MeshNotFinite {
                object: i,
                mesh: name(),
                attribute,
                vertex: v,
            });
        }
    }
    if let Some(v) = m.colors.iter().position(|c| !color_ok(*c)) {
        return Err(SceneError::MeshNotFinite {
            object: i,
            mesh: name(),
            attribute: "colour (or a negative one)",
            vertex: v,
        });
    }
    for (t, tri) in m.triangles.iter().enumerate() {
        if let Some(&index) = tri.iter().find(|&&k| k as usize >= nv) {
            return Err(SceneError::MeshIndexOutOfRange {
                object: i,
                mesh: name(),
                triangle: t,
                index,
                vertices: nv,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::Vec3;

    const SPECIAL: [f32; 9] = [
        0.0,
        -0.0,
        1.5,
        -2.0,
        f32::MIN_POSITIVE,
        f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ];

    /// The lane checks accept exactly what the scalar rules accept, for
    /// every combination of special values in every coordinate, alone and
    /// among good neighbours at any place.
    #[test]
    fn lane_checks_agree_with_the_scalar_rules() {
        let good = Sphere::new(Vec3::ONE, 0.5);
        for &x in &SPECIAL {
            for &y in &SPECIAL {
                for &r in &SPECIAL {
                    let s = Sphere::new(Vec3::new(x as Real, y as Real, 1.0), r as Real);
                    let scalar = center_ok(&s) && radius_ok(&s);
                    assert_eq!(spheres_ok(&[s]), scalar, "{s:?}");
                    let mut many = vec![good; 7];
                    many[(x.to_bits() ^ r.to_bits()) as usize % 7] = s;
                    assert_eq!(spheres_ok(&many), scalar, "{s:?} among others");
                    let c = Rgb::new(x, y, r);
                    assert_eq!(colors_ok(&[c]), color_ok(c), "{c:?}");
                    let mut colors = vec![Rgb::ONE; 5];
                    colors[4] = c;
                    assert_eq!(colors_ok(&colors), color_ok(c), "{c:?} among others");
                }
            }
        }
        assert!(spheres_ok(&[]) && colors_ok(&[]));
    }
}
