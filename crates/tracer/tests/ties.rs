//! Ties in `t` go to the lower object index in every accelerator, seen in
//! the rendered image.

use crate::common::*;
use gridrt_grid::{Real, Vec3};
use gridrt_tracer::{AccelKind, Projection, Rgb};

/// An orthographic 9 × 9 view down −z with one pixel per unit: the ray of
/// pixel (x, y) starts at (x − 4, 4 − y, 5). Under each pixel centre of the
/// middle 7 × 7 two spheres meet: a ball of radius ½ at z = 0 and one of
/// radius ¼ at z = ¼, tangent at z = ½ and both hit at exactly t = 4.5.
/// The pairs alternate which comes first, and the first is red, the second
/// green (ambient light only, so a pixel is its sphere's colour).
#[test]
fn tied_spheres_show_the_lower_index() {
    let mut s = empty_scene(9, 9, Vec3::new(0.0, 0.0, 5.0));
    s.camera.projection = Projection::Orthographic { height: 9.0 };
    s.settings.max_depth = 0;
    s.lights = vec![ambient(1.0)];
    let red = material(&mut s, matte(Rgb::new(1.0, 0.0, 0.0), 1.0, 0.0));
    let green = material(&mut s, matte(Rgb::new(0.0, 1.0, 0.0), 1.0, 0.0));
    for y in -3i8..=3 {
        for x in -3i8..=3 {
            let (x, y) = (Real::from(x), Real::from(y));
            let big = sphere(Vec3::new(x, y, 0.0), 0.5);
            let small = sphere(Vec3::new(x, y, 0.25), 0.25);
            let (first, second) = if (x + y) as i32 % 2 == 0 {
                (big, small)
            } else {
                (small, big)
            };
            object(&mut s, first, red);
            object(&mut s, second, green);
        }
    }
    for accel in [AccelKind::Grid, AccelKind::DenseGrid, AccelKind::Exhaustive] {
        let (img, _) = render_with(&s, &opts(accel, Some(2)));
        for y in 1..8 {
            for x in 1..8 {
                assert_eq!(
                    img.get(x, y),
                    Rgb::new(1.0, 0.0, 0.0),
                    "{accel:?} ({x}, {y})"
                );
            }
        }
    }
}
