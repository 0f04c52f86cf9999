//! Ambient occlusion (Suffern ch. 17): the share of an ambient light that
//! reaches a shading point, estimated with occlusion rays over the
//! cosine-weighted hemisphere.

use crate::integrator::{ThreadState, Tracer};
use crate::sampling::maps::{cosine_hemisphere, Frame};
use crate::sampling::{rotated_hammersley, SampleStream};
use crate::scene::{Occlusion, Rgb};
use crate::shapes::{Surface, SurfacePoint};
use crate::whitted::on_side;
use gridrt_bbox::{Ray, Real, Vec3};
use gridrt_grid::Accelerator;

/// An ambient light with occlusion, ready for shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AmbientOccluder {
    /// `color · intensity`.
    pub radiance: Rgb,
    /// Occlusion rays per shading point, ≥ 1.
    pub samples: u32,
    /// Length of the occlusion rays (∞: no limit).
    pub distance: Real,
    /// The share a fully occluded point still gets.
    pub min_amount: f32,
}

impl AmbientOccluder {
    pub(crate) fn new(radiance: Rgb, o: Occlusion) -> Self {
        Self {
            radiance,
            samples: o.samples.max(1),
            distance: o.distance,
            min_amount: o.min_amount,
        }
    }

    /// The radiance that reaches a point `free` of whose `samples`
    /// occlusion rays hit nothing.
    #[inline]
    pub(crate) fn radiance(&self, free: u32) -> Rgb {
        let open = free as f32 / self.samples as f32;
        self.radiance * (self.min_amount + (1.0 - self.min_amount) * open)
    }
}

/// The radiance of the scene's occluded ambient lights that reaches `sp`:
/// for each light, `samples` directions of the cosine-weighted hemisphere
/// about the shading normal `ns` (turned to the viewer's side, as is the
/// geometric normal `ng`), a Hammersley set rotated by one 2D sample of the
/// pixel sample's stream. A direction that `ns` tilts below the surface is
/// mirrored back above it. Each occlusion ray leaves the surface with the
/// robust offset of shadow rays and is counted in
/// [`crate::RayCounts::ambient_occlusion`].
pub(crate) fn occluded_ambient<A>(
    tr: &Tracer<'_, A>,
    sp: &SurfacePoint,
    ng: Vec3,
    ns: Vec3,
    stream: &mut SampleStream,
    ts: &mut ThreadState<A::Scratch>,
) -> Rgb
where
    A: Accelerator,
    A::Prim: Surface,
{
    let frame = Frame::new(ns);
    let mut l = Rgb::ZERO;
    for o in &tr.data.occluders {
        let u = stream.next_2d();
        let mut free = 0;
        for k in 0..o.samples {
            let w = frame.to_world(cosine_hemisphere(rotated_hammersley(k, o.samples, u)));
            let w = on_side(w, ng, ns, true);
            let origin = tr.data.ray_offset.origin(sp.p, sp.p_err, ng, w);
            ts.counts.ambient_occlusion += 1;
            if !tr.occluded(&Ray::new(origin, w), o.distance, &mut ts.scratch) {
                free += 1;
            }
        }
        l += o.radiance(free);
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_share_runs_from_min_amount_to_one() {
        let o = AmbientOccluder::new(
            Rgb::splat(2.0),
            Occlusion {
                samples: 4,
                distance: Real::INFINITY,
                min_amount: 0.25,
            },
        );
        assert_eq!(o.radiance(4), Rgb::splat(2.0));
        assert_eq!(o.radiance(0), Rgb::splat(0.5));
        assert_eq!(o.radiance(2), Rgb::splat(1.25));
    }
}
