//! Textures in renders: an image shows upright, mipmaps filter a distant
//! checker, cut-outs let camera and shadow rays through, emission maps
//! glow, and solid procedural textures need no coordinates.

use crate::common::{
    ambient, directional, empty_scene, material, matte, object, opts, render, render_with,
    uv_sphere,
};
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::texture::{AlphaMode, Checker, ImageTexture, Sampler, TexFilter};
use gridrt_tracer::{
    AccelKind, Affine, Geometry, MaterialMaps, Mesh, Projection, Rgb, Scene, Texture, TextureRef,
    TriangleStorage,
};
use std::sync::Arc;

/// A square `[-r, r]²` at height `y`, facing up, with `u` along +x and `v`
/// along +z, `tiles` copies of the texture across.
fn quad(r: Real, y: Real, tiles: f32) -> Geometry {
    let p = |x: Real, z: Real| Vec3::new(x, y, z);
    let t = tiles;
    Geometry::Mesh(Arc::new(Mesh {
        name: "quad".into(),
        positions: vec![p(-r, -r), p(-r, r), p(r, r), p(r, -r)],
        normals: vec![],
        uvs: vec![
            glam::Vec2::new(0.0, 0.0),
            glam::Vec2::new(0.0, t),
            glam::Vec2::new(t, t),
            glam::Vec2::new(t, 0.0),
        ],
        uvs1: vec![],
        colors: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }))
}

/// Looking straight down at the origin from above, the image's top towards
/// −z, an orthographic view 2 units high.
fn top_view(w: u32, h: u32) -> Scene {
    let mut s = empty_scene(w, h, Vec3::new(0.0, 5.0, 0.0));
    s.camera.up = Vec3::new(0.0, 0.0, -1.0);
    s.camera.projection = Projection::Orthographic { height: 2.0 };
    s
}

fn image(w: u32, h: u32, rgba: &[u8], sampler: Sampler) -> Texture {
    Texture::Image(Arc::new(
        ImageTexture::from_rgba8(w, h, rgba, false, sampler).unwrap(),
    ))
}

const NEAREST: Sampler = Sampler {
    filter: TexFilter::Nearest,
    mipmaps: false,
    ..Sampler::DEFAULT
};

/// Red, green / blue, white: a 2 × 2 image.
const QUADRANTS: [u8; 16] = [
    255, 0, 0, 255, 0, 255, 0, 255, //
    0, 0, 255, 255, 255, 255, 255, 255,
];

fn base_color(texture: u32) -> MaterialMaps {
    MaterialMaps {
        base_color: Some(TextureRef::new(texture)),
        ..MaterialMaps::default()
    }
}

#[test]
fn an_image_shows_upright_with_its_linear_colours() {
    let mut s = top_view(8, 8);
    let m = material(&mut s, matte(Rgb::ONE, 1.0, 0.0));
    s.lights.push(ambient(1.0));
    object(&mut s, quad(1.0, 0.0, 1.0), m);
    s.textures.list.push(image(2, 2, &QUADRANTS, NEAREST));
    s.textures.maps.push(base_color(0));
    let (img, _) = render(&s);
    assert_eq!(img.get(1, 1), Rgb::new(1.0, 0.0, 0.0));
    assert_eq!(img.get(6, 1), Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(img.get(1, 6), Rgb::new(0.0, 0.0, 1.0));
    assert_eq!(img.get(6, 6), Rgb::ONE);
    // Without the maps the quad is plain white: the texture made the difference.
    s.textures.maps.clear();
    let (img, _) = render(&s);
    assert_eq!(img.get(1, 1), Rgb::ONE);
}

#[test]
fn a_texture_on_the_second_set_reads_the_second_coordinates() {
    let mut s = top_view(8, 8);
    let m = material(&mut s, matte(Rgb::ONE, 1.0, 0.0));
    s.lights.push(ambient(1.0));
    let mut q = quad(1.0, 0.0, 1.0);
    if let Geometry::Mesh(mesh) = &mut q {
        // The second set puts the whole quad in the image's green texel.
        std::sync::Arc::make_mut(mesh).uvs1 = vec![glam::Vec2::new(0.75, 0.25); 4];
    }
    object(&mut s, q, m);
    s.textures.list.push(image(2, 2, &QUADRANTS, NEAREST));
    let on_set = |set: u8| MaterialMaps {
        base_color: Some(TextureRef {
            set,
            ..TextureRef::new(0)
        }),
        ..MaterialMaps::default()
    };
    s.textures.maps.push(on_set(1));
    let (img, _) = render(&s);
    assert!(img.pixels.iter().all(|p| *p == Rgb::new(0.0, 1.0, 0.0)));
    // The first set still shows the four quadrants.
    s.textures.maps[0] = on_set(0);
    let (img, _) = render(&s);
    assert_eq!(img.get(1, 1), Rgb::new(1.0, 0.0, 0.0));
    assert_eq!(img.get(6, 6), Rgb::ONE);
    // A mesh with one set reads it for references to the second.
    if let Geometry::Mesh(mesh) = &mut s.objects[0].geometry {
        std::sync::Arc::make_mut(mesh).uvs1.clear();
    }
    s.textures.maps[0] = on_set(1);
    let (img, _) = render(&s);
    assert_eq!(img.get(1, 1), Rgb::new(1.0, 0.0, 0.0));
}

/// A 64 × 64 black-and-white checker tiled 15.7 times across the quad,
/// seen at 16 × 16 pixels: about 63 texels per pixel.
fn distant_checker(mipmaps: bool) -> Vec<Rgb> {
    let mut s = top_view(16, 16);
    let m = material(&mut s, matte(Rgb::ONE, 1.0, 0.0));
    s.lights.push(ambient(1.0));
    object(&mut s, quad(1.0, 0.0, 15.7), m);
    let mut rgba = Vec::new();
    for y in 0..64u32 {
        for x in 0..64u32 {
            let b = if (x + y) % 2 == 0 { 255 } else { 0 };
            rgba.extend([b, b, b, 255]);
        }
    }
    let sampler = Sampler {
        mipmaps,
        ..Sampler::DEFAULT
    };
    s.textures.list.push(image(64, 64, &rgba, sampler));
    s.textures.maps.push(base_color(0));
    render(&s).0.pixels
}

#[test]
fn mipmaps_filter_a_minified_checker_to_its_mean() {
    let filtered = distant_checker(true);
    assert!(
        filtered.iter().all(|p| (p.x - 0.5).abs() < 0.05),
        "{:?}",
        &filtered[..4]
    );
    // Without mipmaps the same view aliases: pixels far from the mean.
    let aliased = distant_checker(false);
    assert!(aliased.iter().any(|p| (p.x - 0.5).abs() > 0.3));
}

/// A floor at y = 0 under a quad at y = 1 whose left half has alpha 0,
/// lit from straight above with shadows.
fn cut_out(mode: AlphaMode) -> Scene {
    let mut s = top_view(8, 8);
    let floor = material(&mut s, matte(Rgb::new(0.0, 0.0, 1.0), 0.0, 1.0));
    let leaf = material(&mut s, matte(Rgb::new(1.0, 0.0, 0.0), 0.0, 1.0));
    s.lights.push(directional(Vec3::Y, 3.0, true));
    object(&mut s, quad(2.0, 0.0, 1.0), floor);
    object(&mut s, quad(1.0, 1.0, 1.0), leaf);
    let rgba = [255, 255, 255, 0, 255, 255, 255, 255];
    s.textures.list.push(image(2, 1, &rgba, NEAREST));
    s.textures.maps = vec![
        MaterialMaps::default(),
        MaterialMaps {
            base_color: Some(TextureRef::new(0)),
            alpha_mode: mode,
            ..MaterialMaps::default()
        },
    ];
    s
}

#[test]
fn cut_outs_let_camera_and_shadow_rays_through() {
    let (img, stats) = render(&cut_out(AlphaMode::Mask { cutoff: 0.5 }));
    let (left, right) = (img.get(1, 4), img.get(6, 4));
    // Left: the lit floor through the hole; right: the leaf, lit.
    assert!(left.z > 0.5 && left.x == 0.0, "{left}");
    assert!(right.x > 0.5 && right.z == 0.0, "{right}");
    assert!(stats.rays.shadow > 0);
    // Opaque, the leaf hides the floor.
    let (img, _) = render(&cut_out(AlphaMode::Opaque));
    assert!(img.get(1, 4).x > 0.5);
}

#[test]
fn blending_transmits_about_one_minus_alpha_and_ignores_threads() {
    let mut s = cut_out(AlphaMode::Blend);
    // Alpha 0.25 everywhere.
    s.textures.list[0] = image(1, 1, &[255, 255, 255, 64], NEAREST);
    s.settings.spp = 64;
    let one = render_with(&s, &opts(AccelKind::Grid, Some(1))).0;
    let two = render_with(&s, &opts(AccelKind::Grid, Some(2))).0;
    assert_eq!(one.pixels, two.pixels);
    // The leaf covers the centre: a lit white surface is 3/π bright, and
    // the leaf is seen by about a quarter of the rays; the floor by three
    // quarters, of which three quarters reach the light through the leaf.
    let p = one.get(4, 4);
    let lit = 3.0 / std::f32::consts::PI;
    assert!((p.x / lit - 0.25).abs() < 0.1, "{p}");
    assert!((p.z / lit - 0.75 * 0.75).abs() < 0.1, "{p}");
}

#[test]
fn an_emission_map_glows_without_lights() {
    let mut s = top_view(8, 8);
    let m = material(&mut s, matte(Rgb::ZERO, 0.0, 1.0));
    object(&mut s, quad(1.0, 0.0, 1.0), m);
    s.textures.list.push(image(2, 2, &QUADRANTS, NEAREST));
    s.textures.maps.push(MaterialMaps {
        emissive: Some(TextureRef::new(0)),
        emissive_factor: Rgb::splat(2.0),
        ..MaterialMaps::default()
    });
    let (img, _) = render(&s);
    assert_eq!(img.get(1, 1), Rgb::new(2.0, 0.0, 0.0));
    assert_eq!(img.get(6, 6), Rgb::splat(2.0));
}

#[test]
fn a_solid_checker_colours_a_plane_without_coordinates() {
    let mut s = top_view(8, 8);
    let m = material(&mut s, matte(Rgb::ONE, 1.0, 0.0));
    s.lights.push(ambient(1.0));
    object(
        &mut s,
        Geometry::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        m,
    );
    s.textures.list.push(Texture::Checker(Checker {
        size: 0.5,
        even: Rgb::ONE,
        odd: Rgb::ZERO,
    }));
    s.textures.maps.push(base_color(0));
    let (img, _) = render(&s);
    // Pixels 2 apart (half a unit) alternate.
    assert_ne!(img.get(1, 1), img.get(3, 1));
    assert_eq!(img.get(1, 1), img.get(5, 1));
    assert_eq!(img.get(1, 1), img.get(3, 3));
}

#[test]
fn a_reference_to_a_missing_texture_is_an_error() {
    let mut s = top_view(4, 4);
    let m = material(&mut s, matte(Rgb::ONE, 1.0, 0.0));
    object(&mut s, quad(1.0, 0.0, 1.0), m);
    s.textures.maps.push(base_color(5));
    let e = gridrt_tracer::render(&s, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("texture 5"), "{e}");
}

#[test]
fn vertex_colours_replace_the_albedo_and_interpolate() {
    let mut s = top_view(8, 8);
    let m = material(&mut s, matte(Rgb::splat(0.3), 1.0, 0.0));
    s.lights.push(ambient(1.0));
    let Geometry::Mesh(mut mesh) = quad(1.0, 0.0, 1.0) else {
        unreachable!()
    };
    // Corners at x = −1 red, at x = +1 green.
    let (red, green) = (Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0));
    std::sync::Arc::make_mut(&mut mesh).colors = vec![red, red, green, green];
    object(&mut s, Geometry::Mesh(mesh), m);
    let (img, _) = render(&s);
    let (left, right) = (img.get(0, 4), img.get(7, 4));
    assert!(left.x > 0.8 && left.y < 0.2, "{left}");
    assert!(right.y > 0.8 && right.x < 0.2, "{right}");
    // Halfway, half of each.
    let mid = (img.get(3, 4) + img.get(4, 4)) * 0.5;
    assert!(
        (mid.x - 0.5).abs() < 0.1 && (mid.y - 0.5).abs() < 0.1,
        "{mid}"
    );
}

/// Indexed triangles read normals, colours and both texture-coordinate
/// sets from one table renumbered like the grid's vertices: every mesh
/// must still find its own rows, whichever arrays it has.
#[test]
fn indexed_triangles_shade_like_copies() {
    let mut s = top_view(40, 40);
    s.camera.projection = Projection::Orthographic { height: 3.0 };
    let textured = material(&mut s, matte(Rgb::ONE, 0.3, 0.7));
    let plain = material(&mut s, matte(Rgb::splat(0.6), 0.3, 0.7));
    s.lights.push(ambient(0.5));
    s.lights
        .push(directional(Vec3::new(1.0, -2.0, 0.5), 1.0, true));
    s.textures.list.push(image(2, 2, &QUADRANTS, NEAREST));
    s.textures.maps.push(MaterialMaps {
        base_color: Some(TextureRef {
            set: 1,
            ..TextureRef::new(0)
        }),
        ..MaterialMaps::default()
    });
    // A textured quad with a second coordinate set, a smaller one with
    // colours only, a flat triangle with nothing, and a smooth sphere
    // placed by a transform (baked: the scene stays triangles alone).
    let mut q = quad(1.4, 0.0, 2.0);
    if let Geometry::Mesh(m) = &mut q {
        let m = Arc::make_mut(m);
        m.uvs1 = m
            .uvs
            .iter()
            .map(|t| glam::Vec2::new(t.y, t.x) * 0.7)
            .collect();
    }
    object(&mut s, q, textured);
    let mut c = quad(0.5, 0.2, 1.0);
    if let Geometry::Mesh(m) = &mut c {
        let m = Arc::make_mut(m);
        m.uvs.clear();
        m.colors = vec![Rgb::X, Rgb::Y, Rgb::Z, Rgb::ONE];
    }
    object(&mut s, c, plain);
    let flat = Mesh {
        name: "flat".into(),
        positions: vec![
            Vec3::new(-1.3, 0.3, 1.3),
            Vec3::new(-0.6, 0.3, 1.3),
            Vec3::new(-1.3, 0.3, 0.6),
        ],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    object(&mut s, Geometry::Mesh(Arc::new(flat)), plain);
    let ball = Geometry::Instance {
        mesh: Arc::new(uv_sphere(Vec3::ZERO, 0.4, 12, 8)),
        to_world: Box::new(Affine::translation(Vec3::new(0.8, 0.5, -0.8))),
    };
    object(&mut s, ball, plain);
    let mut o = opts(AccelKind::Grid, Some(2));
    o.instancing = false;
    let (want, _) = render_with(&s, &o);
    o.triangles = TriangleStorage::Indexed;
    let r = gridrt_tracer::Renderer::new(&s, &o).unwrap();
    assert!(format!("{r:?}").contains("indexed triangles"));
    let (img, _) = r.render(&|_, _| {}, &Default::default()).unwrap();
    assert!(img == want);
    // The scene shows each kind: texels of more than two colours, and
    // vertex colours.
    let distinct = |f: &dyn Fn(&Rgb) -> bool| img.pixels.iter().filter(|p| f(p)).count();
    assert!(distinct(&|p| p.x > 2.0 * p.y + 0.05) > 10);
    assert!(distinct(&|p| p.z > 2.0 * p.x + 0.05) > 10);
}
