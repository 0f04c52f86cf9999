//! The grid answers every closest-hit query exactly as testing every
//! primitive does, on arbitrary small scenes of spheres, boxes and
//! triangles, with arbitrary grid settings and rays.
#![no_main]

use arbitrary::Arbitrary;
use gridrt_bbox::{Real, Vec3};
use gridrt_grid::{Accelerator, CellStorage, Exhaustive, Grid, GridConfig, Ray};
use gridrt_tracer::{Cuboid, Shape, Sphere, Triangle};
use libfuzzer_sys::fuzz_target;

/// A coordinate: small integers over 8 give exact, often coincident values
/// (shared edges, rays along faces), the rest spread over [-100, 100].
#[derive(Arbitrary, Debug, Clone, Copy)]
struct C(i16);

impl C {
    fn get(self) -> Real {
        if self.0 % 3 == 0 {
            Real::from(self.0 / 3 % 9) / 8.0
        } else {
            Real::from(self.0) / 327.0
        }
    }
}

#[derive(Arbitrary, Debug, Clone, Copy)]
struct P([C; 3]);

impl P {
    fn get(self) -> Vec3 {
        Vec3::new(self.0[0].get(), self.0[1].get(), self.0[2].get())
    }
}

#[derive(Arbitrary, Debug)]
enum Prim {
    Sphere(P, u8),
    Box(P, P),
    Triangle(P, P, P),
}

#[derive(Arbitrary, Debug)]
struct Input {
    prims: Vec<Prim>,
    rays: Vec<(P, P, u8)>,
    m: u8,
    hashed: bool,
    nest: u8,
}

fuzz_target!(|input: Input| {
    let shapes: Vec<Shape> = input
        .prims
        .iter()
        .take(64)
        .filter_map(|p| match *p {
            Prim::Sphere(c, r) => {
                let radius = Real::from(r.max(1)) / 64.0;
                Some(Shape::Sphere(Sphere {
                    center: c.get(),
                    radius,
                }))
            }
            Prim::Box(a, b) => {
                let (a, b) = (a.get(), b.get());
                Some(Shape::Cuboid(Cuboid {
                    min: a.min(b),
                    max: a.max(b),
                }))
            }
            Prim::Triangle(a, b, c) => {
                Some(Shape::Triangle(Triangle::new(a.get(), b.get(), c.get())))
            }
        })
        .collect();
    if shapes.is_empty() {
        return;
    }
    let config = GridConfig {
        m: Real::from(input.m % 40 + 1) / 8.0,
        storage: if input.hashed {
            CellStorage::Hashed
        } else {
            CellStorage::Dense
        },
        nest_min_refs: u32::from(input.nest % 5) * 2,
        parallel_build: false,
        ..GridConfig::default()
    };
    let grid = Grid::build(shapes.clone(), &config);
    let all = Exhaustive::new(shapes);
    let mut scratch = grid.scratch();
    for (o, d, t) in input.rays.iter().take(64) {
        let dir = d.get();
        if dir == Vec3::ZERO {
            continue;
        }
        let ray = Ray::new(o.get(), dir);
        let t_max = if *t == 0 {
            Real::INFINITY
        } else {
            Real::from(*t) / 16.0
        };
        let a = grid.closest_hit(&ray, 0.0, t_max, &mut scratch);
        let b = all.closest_hit(&ray, 0.0, t_max, &mut ());
        assert_eq!(a, b, "ray {ray:?} t_max {t_max}");
    }
});
