//! Embree 3 on the benchmark's spheres (feature `embree`), measured as the
//! peer program `shared/peers/embree/embree_bench.c` does: one
//! `RTC_GEOMETRY_TYPE_SPHERE_POINT` geometry with the spheres as `FLOAT4`
//! (x, y, z, r), build quality medium on a device with `threads=1`,
//! `rtcCommitScene` timed as the build, then one `rtcIntersect1` per pixel
//! centre on this thread (flush-to-zero and denormals-are-zero on, as Embree
//! recommends), no shading.
//!
//! The few declarations below are written from Embree 3.13's headers
//! (`/usr/include/embree3`); only what the benchmark calls is declared.
//! `build.rs` links `libembree3` when the feature is on.

use crate::measure::{camera_ray, timed};
use gridrt_tracer::Sphere;
use std::ffi::{c_char, c_uint, c_void, CString};
use std::time::Duration;

#[allow(non_camel_case_types)]
type ssize_t = isize;

/// `RTCDevice`, `RTCScene`, `RTCGeometry`: opaque handles.
type Handle = *mut c_void;

const RTC_GEOMETRY_TYPE_SPHERE_POINT: u32 = 50;
const RTC_BUFFER_TYPE_VERTEX: u32 = 1;
const RTC_FORMAT_FLOAT4: u32 = 0x9004;
const RTC_BUILD_QUALITY_MEDIUM: u32 = 1;
const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
const RTC_DEVICE_PROPERTY_VERSION_MAJOR: u32 = 1;
const RTC_DEVICE_PROPERTY_VERSION_MINOR: u32 = 2;
const RTC_DEVICE_PROPERTY_VERSION_PATCH: u32 = 3;

/// `struct RTCRay` (16-byte aligned).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
struct RtcRay {
    org_x: f32,
    org_y: f32,
    org_z: f32,
    tnear: f32,
    dir_x: f32,
    dir_y: f32,
    dir_z: f32,
    time: f32,
    tfar: f32,
    mask: c_uint,
    id: c_uint,
    flags: c_uint,
}

/// `struct RTCHit` with `RTC_MAX_INSTANCE_LEVEL_COUNT` = 1.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
struct RtcHit {
    ng_x: f32,
    ng_y: f32,
    ng_z: f32,
    u: f32,
    v: f32,
    prim_id: c_uint,
    geom_id: c_uint,
    inst_id: [c_uint; 1],
}

/// `struct RTCRayHit`.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
struct RtcRayHit {
    ray: RtcRay,
    hit: RtcHit,
}

/// `struct RTCIntersectContext` with one instance level and no min-width.
#[repr(C)]
#[derive(Debug)]
struct RtcIntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [c_uint; 1],
}

#[link(name = "embree3")]
extern "C" {
    fn rtcNewDevice(config: *const c_char) -> Handle;
    fn rtcReleaseDevice(device: Handle);
    fn rtcGetDeviceError(device: Handle) -> u32;
    fn rtcGetDeviceProperty(device: Handle, prop: u32) -> ssize_t;
    fn rtcNewScene(device: Handle) -> Handle;
    fn rtcSetSceneBuildQuality(scene: Handle, quality: u32);
    fn rtcReleaseScene(scene: Handle);
    fn rtcNewGeometry(device: Handle, kind: u32) -> Handle;
    fn rtcSetNewGeometryBuffer(
        geometry: Handle,
        kind: u32,
        slot: c_uint,
        format: u32,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: Handle);
    fn rtcAttachGeometry(scene: Handle, geometry: Handle) -> c_uint;
    fn rtcReleaseGeometry(geometry: Handle);
    fn rtcCommitScene(scene: Handle);
    fn rtcIntersect1(scene: Handle, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHit);
}

/// An Embree device (`threads=1`, as the peer's default).
#[derive(Debug)]
pub struct Device(Handle);

impl Device {
    /// Creates the device.
    ///
    /// # Errors
    /// When Embree cannot make one (unsupported CPU, bad configuration).
    pub fn new() -> Result<Self, String> {
        let config = CString::new("threads=1").map_err(|e| e.to_string())?;
        // SAFETY: a valid NUL-terminated string; a null result is handled.
        let dev = unsafe { rtcNewDevice(config.as_ptr()) };
        if dev.is_null() {
            // SAFETY: Embree documents rtcGetDeviceError(NULL) for a failed rtcNewDevice.
            let code = unsafe { rtcGetDeviceError(std::ptr::null_mut()) };
            return Err(format!("rtcNewDevice failed (error {code})"));
        }
        Ok(Self(dev))
    }

    fn check(&self, what: &str) -> Result<(), String> {
        // SAFETY: the device is valid for the lifetime of `self`.
        match unsafe { rtcGetDeviceError(self.0) } {
            0 => Ok(()),
            code => Err(format!("{what} failed (Embree error {code})")),
        }
    }

    fn version(&self) -> String {
        // SAFETY: the device is valid; properties are plain integers.
        let p = |k| unsafe { rtcGetDeviceProperty(self.0, k) };
        format!(
            "{}.{}.{}",
            p(RTC_DEVICE_PROPERTY_VERSION_MAJOR),
            p(RTC_DEVICE_PROPERTY_VERSION_MINOR),
            p(RTC_DEVICE_PROPERTY_VERSION_PATCH)
        )
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: made by rtcNewDevice, released once.
        unsafe { rtcReleaseDevice(self.0) }
    }
}

/// A committed scene, released on drop.
struct Scene(Handle);

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: made by rtcNewScene, released once.
        unsafe { rtcReleaseScene(self.0) }
    }
}

/// Embree's version as the library reports it (a device is made to ask).
pub fn version() -> String {
    Device::new().map_or_else(|e| format!("(unavailable: {e})"), |d| d.version())
}

/// Builds the sphere scene; returns it and the `rtcCommitScene` time.
#[allow(clippy::unnecessary_cast)] // `Real` is f64 with the `f64` feature
fn build(dev: &Device, spheres: &[Sphere]) -> Result<(Scene, Duration), String> {
    // SAFETY: every handle comes from the device and is checked for errors;
    // the vertex buffer is Embree's own, `4 · n` floats long, and filled
    // before rtcCommitGeometry.
    unsafe {
        let scene = Scene(rtcNewScene(dev.0));
        dev.check("rtcNewScene")?;
        rtcSetSceneBuildQuality(scene.0, RTC_BUILD_QUALITY_MEDIUM);
        let geom = rtcNewGeometry(dev.0, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        dev.check("rtcNewGeometry")?;
        let buf = rtcSetNewGeometryBuffer(
            geom,
            RTC_BUFFER_TYPE_VERTEX,
            0,
            RTC_FORMAT_FLOAT4,
            4 * std::mem::size_of::<f32>(),
            spheres.len(),
        )
        .cast::<f32>();
        if let Err(e) = dev.check("rtcSetNewGeometryBuffer") {
            rtcReleaseGeometry(geom);
            return Err(e);
        }
        let xyzr = std::slice::from_raw_parts_mut(buf, 4 * spheres.len());
        for (dst, s) in xyzr.chunks_exact_mut(4).zip(spheres) {
            dst.copy_from_slice(&[
                s.center.x as f32,
                s.center.y as f32,
                s.center.z as f32,
                s.radius as f32,
            ]);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene.0, geom);
        rtcReleaseGeometry(geom);
        dev.check("building the geometry")?;
        let ((), t) = timed(|| rtcCommitScene(scene.0));
        dev.check("rtcCommitScene")?;
        Ok((scene, t))
    }
}

/// Sets flush-to-zero and denormals-are-zero for the current thread (as
/// `embree_bench.c` does) and restores the old mode on drop.
struct FtzGuard(#[allow(dead_code)] u32);

impl FtzGuard {
    #[allow(deprecated)] // _mm_getcsr/_mm_setcsr: no stable replacement without asm
    fn new() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
            // SAFETY: reading and writing MXCSR only changes float rounding
            // behaviour of this thread; the old value is restored on drop.
            unsafe {
                let old = _mm_getcsr();
                _mm_setcsr(old | 0x8040); // FTZ (bit 15) | DAZ (bit 6)
                Self(old)
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        Self(0)
    }
}

impl Drop for FtzGuard {
    #[allow(deprecated)]
    fn drop(&mut self) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: restores the value read in `new`.
        unsafe {
            std::arch::x86_64::_mm_setcsr(self.0);
        }
    }
}

/// Traces every pixel centre; per pixel (`r · resolution + c`, r = 0 at the
/// bottom) the primitive hit or `u32::MAX`.
#[allow(clippy::unnecessary_cast)] // `Real` is f64 with the `f64` feature
fn trace(scene: &Scene, resolution: u32, prims: &mut Vec<u32>) {
    let _ftz = FtzGuard::new();
    prims.clear();
    let mut ctx = RtcIntersectContext {
        flags: 0,
        filter: std::ptr::null(),
        inst_id: [RTC_INVALID_GEOMETRY_ID],
    };
    for r in 0..resolution {
        for c in 0..resolution {
            let ray = camera_ray(c, r, resolution);
            let mut rh = RtcRayHit {
                ray: RtcRay {
                    org_x: ray.origin.x as f32,
                    org_y: ray.origin.y as f32,
                    org_z: ray.origin.z as f32,
                    tnear: 0.0,
                    dir_x: ray.dir.x as f32,
                    dir_y: ray.dir.y as f32,
                    dir_z: ray.dir.z as f32,
                    time: 0.0,
                    tfar: f32::INFINITY,
                    mask: u32::MAX,
                    id: 0,
                    flags: 0,
                },
                hit: RtcHit {
                    geom_id: RTC_INVALID_GEOMETRY_ID,
                    inst_id: [RTC_INVALID_GEOMETRY_ID],
                    ..RtcHit::default()
                },
            };
            // SAFETY: a committed scene, an initialised context and an
            // aligned, initialised ray/hit, as rtcIntersect1 requires.
            unsafe { rtcIntersect1(scene.0, &mut ctx, &mut rh) };
            prims.push(if rh.hit.geom_id == RTC_INVALID_GEOMETRY_ID {
                u32::MAX
            } else {
                rh.hit.prim_id
            });
        }
    }
}

/// Embree's numbers for one N.
#[derive(Debug)]
pub struct Measured {
    /// `rtcCommitScene`, median seconds.
    pub build: f64,
    /// The trace of every pixel on one thread, median seconds.
    pub trace: f64,
    /// Pixels hit.
    pub pixels_hit: u64,
    /// Per pixel (r · resolution + c, r = 0 at the bottom) the sphere hit or
    /// `u32::MAX`.
    pub prims: Vec<u32>,
}

/// Builds `runs` times and traces `runs` times (after a warm-up), medians.
///
/// # Errors
/// An Embree error as text.
pub fn measure(
    dev: &Device,
    spheres: &[Sphere],
    resolution: u32,
    runs: usize,
) -> Result<Measured, String> {
    let mut builds = Vec::new();
    let mut scene = None;
    for _ in 0..runs.max(1) {
        let (s, t) = build(dev, spheres)?;
        builds.push(t);
        scene = Some(s);
    }
    let scene = scene.ok_or("no build")?;
    let mut prims = Vec::with_capacity((resolution * resolution) as usize);
    trace(&scene, resolution, &mut prims); // warm-up
    let mut traces = Vec::new();
    for _ in 0..runs.max(1) {
        traces.push(timed(|| trace(&scene, resolution, &mut prims)).1);
    }
    Ok(Measured {
        build: crate::util::median(builds).as_secs_f64(),
        trace: crate::util::median(traces).as_secs_f64(),
        pixels_hit: prims.iter().filter(|&&p| p != u32::MAX).count() as u64,
        prims,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_tracer::suffern;

    #[test]
    fn layouts_match_embree_3() {
        assert_eq!(std::mem::size_of::<RtcRay>(), 48);
        assert_eq!(std::mem::size_of::<RtcHit>(), 32);
        assert_eq!(std::mem::size_of::<RtcRayHit>(), 80);
        assert_eq!(std::mem::align_of::<RtcRayHit>(), 16);
        assert_eq!(std::mem::size_of::<RtcIntersectContext>(), 24);
    }

    #[test]
    fn embree_hits_the_reference_pixels() {
        let dev = Device::new().unwrap();
        let set = suffern::sphere_set(100, suffern::DEFAULT_SEED);
        let m = measure(&dev, &set.spheres, 400, 1).unwrap();
        assert_eq!(m.pixels_hit, 35_175);
        assert!(version().starts_with("3."));
    }
}
