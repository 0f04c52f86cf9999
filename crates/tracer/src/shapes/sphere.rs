use super::{unit_or, Surface, SurfacePoint};
use gridrt_bbox::math::{LaneMat, Lanes, Vec3Lanes};
use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};
use gridrt_grid::{any_hits_prefiltered, closest_hits_prefiltered, PrimHit, Primitive};

/// A sphere: 16 bytes with `f32` (centre and radius), so a grid of a million
/// of them stays small.
///
/// The ray test is the numerically careful one of Haines et al., *Ray
/// Tracing Gems* ch. 7 ("Precision Improvements for Ray/Sphere
/// Intersection", also pbrt-v4 `Sphere::BasicIntersect`): the discriminant
/// comes from the ray's perpendicular distance to the centre, not from
/// `b² − 4ac`, and the two roots from the stable `q` form. It stays right for
/// rays that start far from a small sphere and for very large radii.
///
/// ```
/// use gridrt_tracer::Sphere;
/// use gridrt_grid::{Primitive, Ray, Real, Vec3};
/// let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
/// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
/// let h = s.closest_hit(&(), &ray, &Sphere::ray_data(&ray), 0.0, Real::INFINITY).unwrap();
/// assert_eq!(h.t, 4.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: Real,
}

impl Sphere {
    /// The centre's x, y and z and the radius: the sphere's column of a
    /// [`SphereFour`].
    #[inline(always)]
    fn lanes(&self) -> [Real; 4] {
        [self.center.x, self.center.y, self.center.z, self.radius]
    }

    /// A sphere from its centre and radius.
    #[inline]
    #[must_use]
    pub const fn new(center: Vec3, radius: Real) -> Self {
        Self { center, radius }
    }

    /// Both roots `t0 ≤ t1` of the ray/sphere quadratic, or `None` when the
    /// ray's line misses the sphere.
    #[inline]
    #[must_use]
    pub fn roots(&self, ray: &Ray) -> Option<(Real, Real)> {
        // In defined lanes: see `Vec3Lanes`.
        let d = Vec3Lanes::from(ray.dir);
        let f = Vec3Lanes::from(ray.origin) - Vec3Lanes::from(self.center);
        let r = self.radius;
        let a = d.dot(d);
        // Half of the quadratic's b.
        let b = f.dot(d);
        // The vector from the centre to the ray's closest point; its length
        // is accurate even when |f| is much larger than r.
        let l = f - d * (b / a);
        let ll = l.dot(l);
        // Most rays a grid hands to a sphere pass it by: reject those without
        // a square root. The margin makes this never reject a ray that the
        // exact test below accepts (it covers the rounding of ll and r²), so
        // the answers are those of the exact test alone. Also rejects NaN.
        if !(ll <= r * r * (1.0 + gamma(8))) {
            return None;
        }
        let len = ll.sqrt();
        // b² − ac = a·(r² − |l|²), with the difference of squares factored
        // to avoid cancellation near tangency.
        let disc = a * ((r - len) * (r + len));
        if !(disc >= 0.0) {
            // Also rejects NaN (a zero direction).
            return None;
        }
        let c = f.dot(f) - r * r;
        let q = if b < 0.0 {
            -b + disc.sqrt()
        } else {
            -b - disc.sqrt()
        };
        if q == 0.0 {
            // b = 0 and a tangent ray: a double root at t = 0 (the origin is on
            // the sphere); c / q would be 0/0.
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (c / q, q / a);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The nearest root in `[t_min, t_max]`.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_min: Real, t_max: Real) -> Option<Real> {
        let (t0, t1) = self.roots(ray)?;
        if t0 >= t_min && t0 <= t_max {
            Some(t0)
        } else if t1 >= t_min && t1 <= t_max {
            Some(t1)
        } else {
            None
        }
    }
}

/// Four spheres in lanes: the centres' x, y and z and the radii, sphere
/// `j` in lane `j` (zeros where there is none).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SphereFour(LaneMat);

impl SphereFour {
    /// Four spheres from their [`Sphere::lanes`], one column each.
    #[inline(always)]
    fn new(cols: [[Real; 4]; 4]) -> Self {
        Self(LaneMat::from_cols_array_2d(&cols).transpose())
    }
}

/// What the four-at-a-time test of [`Sphere`]s needs of a ray, computed
/// once per query rather than once per cell: the origin and direction
/// spread over the lanes, and `d · d`.
#[derive(Clone, Copy, Debug)]
pub struct SphereRay {
    origin: [Lanes; 3],
    dir: [Lanes; 3],
    dd: Lanes,
}

impl SphereRay {
    /// The lanes (bit `k` for `four[k]`) whose sphere the ray may hit: the
    /// rejection of [`Sphere::roots`] (the squared distance from the centre
    /// to the ray's line against `r²`) in SIMD lanes, with the same
    /// operations in the same order, so lane by lane the very same verdict.
    #[inline(always)]
    fn may_hit(&self, four: [&Sphere; 4]) -> u32 {
        self.may_hit_packed(&SphereFour::new(four.map(Sphere::lanes)))
    }

    /// [`Self::may_hit`] for four spheres packed in lanes.
    #[inline(always)]
    fn may_hit_packed(&self, &SphereFour(c): &SphereFour) -> u32 {
        let SphereRay {
            origin: [ox, oy, oz],
            dir: [dx, dy, dz],
            dd: a,
        } = *self;
        let fx = ox - c.x_axis;
        let fy = oy - c.y_axis;
        let fz = oz - c.z_axis;
        let s = (fx * dx + fy * dy + fz * dz) / a;
        let (lx, ly, lz) = (fx - dx * s, fy - dy * s, fz - dz * s);
        let ll = lx * lx + ly * ly + lz * lz;
        let r = c.w_axis;
        ll.cmple(r * r * Lanes::splat(1.0 + gamma(8))).bitmask()
    }
}

impl Primitive for Sphere {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// The lanes of the four-at-a-time rejection.
    type RayData = SphereRay;

    /// Four spheres in lanes.
    type Four = SphereFour;

    const PACKS_FOUR: bool = true;

    fn pack_four(four: [Option<&Self>; 4], _: &()) -> SphereFour {
        SphereFour::new(four.map(|s| s.map_or([0.0; 4], Sphere::lanes)))
    }

    /// The rejection of `closest_hits`, read from the packed lanes.
    #[inline(always)]
    fn four_may_hit(four: &SphereFour, _: &Ray, data: &SphereRay) -> u32 {
        data.may_hit_packed(four)
    }

    #[inline]
    fn ray_data(ray: &Ray) -> SphereRay {
        let (o, d) = (ray.origin, ray.dir);
        SphereRay {
            origin: [o.x, o.y, o.z].map(Lanes::splat),
            dir: [d.x, d.y, d.z].map(Lanes::splat),
            dd: Lanes::splat(d.dot(d)),
        }
    }

    /// The centre ± radius, widened by the rounding of the two additions, so
    /// the box holds every point of the sphere.
    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        let r = Vec3::splat(self.radius);
        let pad = (self.center.abs() + r) * gamma(1);
        Aabb::new(self.center - r - pad, self.center + r + pad)
    }

    #[inline]
    fn closest_hit(
        &self,
        _: &(),
        ray: &Ray,
        _: &SphereRay,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        self.intersect(ray, t_min, t_max)
            .map(|t| PrimHit::new(t, 0.0, 0.0))
    }

    #[inline]
    fn any_hit(&self, _: &(), ray: &Ray, _: &SphereRay, t_min: Real, t_max: Real) -> bool {
        self.intersect(ray, t_min, t_max).is_some()
    }

    /// Four spheres at a time (`SphereRay::may_hit`); the spheres it
    /// keeps go through `closest_hit`. Most spheres a grid cell hands over
    /// are rejected there. Inlined into the grid's walk: a call per cell
    /// costs more than the rejection of the cell's spheres.
    #[inline(always)]
    fn closest_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        data: &SphereRay,
        t_min: Real,
        t_max: Real,
        _best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        closest_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            data,
            t_min,
            t_max,
            None,
            keep,
            #[inline(always)]
            |four| data.may_hit(four),
        );
    }

    /// Four spheres at a time, as [`Sphere::closest_hits`], until one is hit
    /// (a shadow ray's work in a cell).
    #[inline(always)]
    fn any_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        data: &SphereRay,
        t_min: Real,
        t_max: Real,
    ) -> bool {
        any_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            data,
            t_min,
            t_max,
            #[inline(always)]
            |four| data.may_hit(four),
        )
    }

    /// Arvo's test: the squared distance from the centre to the box, against
    /// r² with a margin for rounding (never `false` for a touching box).
    #[inline]
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        if cell.is_empty() {
            return false;
        }
        let q = self.center.clamp(cell.min, cell.max);
        let d = q - self.center;
        let r = self.radius;
        d.dot(d) <= r * r * (1.0 + gamma(8))
    }
}

impl Surface for Sphere {
    /// The hit point is projected back onto the sphere (pbrt-v4 §6.8.5), so
    /// its error is a few ULPs of the radius, not of the ray's length.
    #[inline]
    fn surface(&self, _: &(), ray: &Ray, h: &PrimHit) -> SurfacePoint {
        let raw = ray.at(h.t) - self.center;
        let len = raw.length();
        let local = if len > 0.0 {
            raw * (self.radius / len)
        } else {
            Vec3::new(0.0, 0.0, self.radius)
        };
        let p = self.center + local;
        let p_err = local.abs() * gamma(5) + (self.center.abs() + p.abs()) * gamma(2);
        SurfacePoint {
            p,
            p_err,
            n: unit_or(local, Vec3::Z),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_grid::NO_SLOT;

    #[test]
    fn hits_from_outside_and_inside() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
        let out = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0));
        assert_eq!(s.roots(&out), Some((2.0, 3.0)));
        let inside = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::X);
        assert_eq!(s.intersect(&inside, 0.0, Real::INFINITY), Some(1.0));
        assert_eq!(s.intersect(&inside, 0.0, 0.5), None);
        // Closed interval: a hit exactly at t_max counts.
        assert_eq!(s.intersect(&out, 0.0, 2.0), Some(2.0));
        let away = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(s.intersect(&away, 0.0, Real::INFINITY), None);
    }

    #[test]
    fn zero_direction_is_a_miss_not_nan() {
        let s = Sphere::new(Vec3::ZERO, 1.0);
        let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
        assert_eq!(s.roots(&r), None);
    }

    #[test]
    fn overlaps_box_is_exact_on_corners() {
        let s = Sphere::new(Vec3::ZERO, 1.0);
        // The corner cube near (1,1,1): its nearest point is at distance
        // 0.9·√3 ≈ 1.56 > 1, though its box overlaps the sphere's bounds.
        let cell = Aabb::new(Vec3::splat(0.9), Vec3::splat(2.0));
        assert!(s.bounds(&()).overlaps(&cell));
        assert!(!s.overlaps_box(&(), &cell));
        assert!(s.overlaps_box(
            &(),
            &Aabb::new(Vec3::new(1.0, -1.0, -1.0), Vec3::splat(2.0))
        ));
        assert!(s.overlaps_box(&(), &Aabb::new(Vec3::splat(-0.1), Vec3::splat(0.1))));
        assert!(!s.overlaps_box(&(), &Aabb::EMPTY));
    }

    #[test]
    fn surface_point_is_on_the_sphere() {
        let s = Sphere::new(Vec3::new(3.0, -2.0, 7.0), 0.5);
        let ray = Ray::new(
            Vec3::new(100.0, 40.0, -30.0),
            s.center - Vec3::new(100.0, 40.0, -30.0),
        );
        let t = s.intersect(&ray, 0.0, Real::INFINITY).unwrap();
        let sp = s.surface(&(), &ray, &PrimHit::new(t, 0.0, 0.0));
        let dist = (sp.p - s.center).length();
        assert!((dist - 0.5).abs() <= 4.0 * Real::EPSILON * 8.0);
        assert!((sp.n.length() - 1.0).abs() < 1e-5);
        assert!(sp.p_err.max_element() > 0.0);
    }

    /// Every hit `closest_hits` reports, in order, each `keep` returning `t_max`.
    fn all_hits(
        spheres: &[Sphere],
        refs: &[u32],
        ray: &Ray,
        t_max: Real,
        batched: bool,
    ) -> Vec<(u32, PrimHit)> {
        let mut hits = Vec::new();
        let mut keep = |r: u32, h: PrimHit| {
            hits.push((r, h));
            t_max
        };
        let data = Sphere::ray_data(ray);
        if batched {
            Sphere::closest_hits(
                spheres,
                &(),
                refs,
                ray,
                &data,
                0.0,
                t_max,
                NO_SLOT,
                &mut keep,
            );
        } else {
            for &r in refs {
                if let Some(h) = spheres[r as usize].closest_hit(&(), ray, &data, 0.0, t_max) {
                    keep(r, h);
                }
            }
        }
        hits
    }

    proptest::proptest! {
        /// The four-lane rejection keeps exactly the spheres the scalar test
        /// hits, in every lane of full and partial chunks, for rays through
        /// random points and rays that graze a sphere (the rejection's edge);
        /// the four-at-a-time any-hit test agrees with one at a time.
        #[test]
        fn four_at_a_time_equals_one_at_a_time(
            cr in proptest::collection::vec(proptest::array::uniform4(-1.0f32..1.0), 1..12),
            picks in proptest::collection::vec(0usize..64, 0..12),
            o in proptest::array::uniform3(-4.0f32..4.0),
            aim in proptest::array::uniform3(-1.0f32..1.0),
            graze in proptest::option::of((0usize..64, -1e-5f32..1e-5)),
            t_max in proptest::prop_oneof![proptest::strategy::Just(f32::INFINITY), 0.0f32..8.0],
        ) {
            let spheres: Vec<Sphere> = cr
                .iter()
                .map(|c| Sphere::new(Vec3::new(c[0] as Real, c[1] as Real, c[2] as Real), 0.01 + 0.3 * c[3].abs() as Real))
                .collect();
            let refs: Vec<u32> = picks.iter().map(|&i| (i % spheres.len()) as u32).collect();
            let origin = Vec3::new(o[0] as Real, o[1] as Real, o[2] as Real);
            let mut target = Vec3::new(aim[0] as Real, aim[1] as Real, aim[2] as Real);
            if let Some((i, e)) = graze {
                // Aim one radius (times 1 ± e) off the centre, across the ray.
                let s = spheres[i % spheres.len()];
                let d = s.center - origin;
                let side = d.cross(Vec3::Z).try_normalize().unwrap_or(Vec3::X);
                target = s.center + side * s.radius * (1.0 + e as Real);
            }
            let ray = Ray::new(origin, target - origin);
            let t_max = t_max as Real;
            proptest::prop_assert_eq!(
                all_hits(&spheres, &refs, &ray, t_max, true),
                all_hits(&spheres, &refs, &ray, t_max, false)
            );
            let data = Sphere::ray_data(&ray);
            proptest::prop_assert_eq!(
                Sphere::any_hits(&spheres, &(), &refs, &ray, &data, 0.0, t_max),
                refs.iter().any(|&r| spheres[r as usize].any_hit(&(), &ray, &data, 0.0, t_max))
            );
        }
    }
}
