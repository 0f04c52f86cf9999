//! Rendered pixels: the [`Framebuffer`] and the [`PixelRect`] windows a
//! render can be limited to.

use crate::scene::Rgb;
use crate::srgb8_into;

/// A rectangle of pixels `x0..x1` × `y0..y1` of an image (row 0 at the
/// top; the upper bounds excluded).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PixelRect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelRect {
    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }
}

/// A rendered image: linear RGB, row-major, row 0 at the **top**.
#[derive(Clone, Debug, PartialEq)]
pub struct Framebuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels, row 0 first (the top of the image).
    pub pixels: Vec<Rgb>,
}

impl Framebuffer {
    /// A black image.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
        }
    }

    /// The pixel in column `x` of row `y` (row 0 at the top).
    ///
    /// # Panics
    /// When `x ≥ width` or `y ≥ height`.
    #[inline]
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside the image"
        );
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The number of pixels with a NaN or infinite channel (0 for a sound
    /// render).
    #[must_use]
    pub fn non_finite_pixels(&self) -> usize {
        self.pixels.iter().filter(|p| !p.is_finite()).count()
    }
}

/// A rendered image as 8-bit sRGB, three bytes a pixel, row-major, row 0
/// at the top: the form a PNG stores, in a quarter of a [`Framebuffer`]'s
/// memory. [`crate::Renderer::render_srgb8`] converts each tile as it
/// finishes ([`srgb8_into`](crate::srgb8_into)), so the linear image never
/// exists whole.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Srgb8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `3 × width × height` bytes, R, G, B of each pixel in turn.
    pub bytes: Vec<u8>,
}

impl Srgb8Image {
    /// The 8-bit image of a linear one: what its tiles would have given.
    #[must_use]
    pub fn from_linear(image: &Framebuffer) -> Self {
        let mut bytes = vec![0; 3 * image.pixels.len()];
        srgb8_into(&mut bytes, &image.pixels);
        Self {
            width: image.width,
            height: image.height,
            bytes,
        }
    }
}

/// How a render keeps its pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PixelFormat {
    /// Linear floats: a [`Framebuffer`].
    Linear,
    /// 8-bit sRGB: an [`Srgb8Image`].
    Srgb8,
}

/// The image a render fills in, tile by tile.
pub(crate) enum ImageBuf {
    Linear(Framebuffer),
    Srgb8(Srgb8Image),
}

impl ImageBuf {
    /// A black image of `format`.
    pub(crate) fn new(width: u32, height: u32, format: PixelFormat) -> Self {
        match format {
            PixelFormat::Linear => Self::Linear(Framebuffer::new(width, height)),
            PixelFormat::Srgb8 => Self::Srgb8(Srgb8Image {
                width,
                height,
                bytes: vec![0; 3 * width as usize * height as usize],
            }),
        }
    }

    /// The linear image (of a render asked for one).
    pub(crate) fn into_linear(self) -> Framebuffer {
        match self {
            Self::Linear(f) => f,
            Self::Srgb8(_) => unreachable!("rendered as linear floats"),
        }
    }

    /// The 8-bit image (of a render asked for one).
    pub(crate) fn into_srgb8(self) -> Srgb8Image {
        match self {
            Self::Srgb8(img) => img,
            Self::Linear(_) => unreachable!("rendered as sRGB bytes"),
        }
    }

    /// Stores the linear pixels `run` from pixel `start` (row-major) on.
    pub(crate) fn put(&mut self, start: usize, run: &[Rgb]) {
        match self {
            Self::Linear(f) => f.pixels[start..start + run.len()].copy_from_slice(run),
            Self::Srgb8(img) => srgb8_into(&mut img.bytes[3 * start..3 * (start + run.len())], run),
        }
    }
}

/// The image of a render in progress, filled in tile by tile, for writing
/// partial images while it runs and for saving what was done when it is
/// interrupted ([`crate::Renderer::render_live`]). Shared between the
/// render's workers and any thread that takes snapshots.
#[derive(Debug, Default)]
pub struct LiveImage {
    state: std::sync::Mutex<LiveState>,
    rays: std::sync::atomic::AtomicU64,
    /// Counts rays only, keeping no pixels ([`LiveImage::rays_only`]).
    rays_only: bool,
}

#[derive(Debug, Default)]
struct LiveState {
    image: Option<Framebuffer>,
    /// Every tile of the render, and whether it is done.
    tiles: Vec<(PixelRect, bool)>,
}

impl LiveImage {
    /// An empty live image, to hand to a render.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A live image that only counts the render's rays (for a progress
    /// bar): it keeps no copy of the pixels, which would be a second
    /// framebuffer as large as the render's own, and its
    /// [`snapshot`](Self::snapshot) is `None`.
    #[must_use]
    pub fn rays_only() -> Self {
        Self {
            rays_only: true,
            ..Self::default()
        }
    }

    /// The state, also after a worker panicked while holding it (a tile's
    /// pixels are copied in whole or not at all; a poisoned lock loses
    /// nothing).
    fn lock(&self) -> std::sync::MutexGuard<'_, LiveState> {
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Starts a render of a `width × height` image cut into `tiles`.
    pub(crate) fn start(&self, width: u32, height: u32, tiles: Vec<PixelRect>) {
        self.rays.store(0, std::sync::atomic::Ordering::Relaxed);
        if self.rays_only {
            return;
        }
        let mut s = self.lock();
        s.image = Some(Framebuffer::new(width, height));
        s.tiles = tiles.into_iter().map(|t| (t, false)).collect();
    }

    /// Copies a finished tile's pixels (row-major within the tile) in.
    pub(crate) fn finish_tile(&self, index: usize, pixels: &[Rgb], rays: u64) {
        self.rays
            .fetch_add(rays, std::sync::atomic::Ordering::Relaxed);
        if self.rays_only {
            return;
        }
        let mut s = self.lock();
        let LiveState { image, tiles } = &mut *s;
        let (Some(image), Some((r, done))) = (image.as_mut(), tiles.get_mut(index)) else {
            return;
        };
        let w = r.width() as usize;
        for (row, y) in (r.y0..r.y1).enumerate() {
            let start = y as usize * image.width as usize + r.x0 as usize;
            image.pixels[start..start + w].copy_from_slice(&pixels[row * w..(row + 1) * w]);
        }
        *done = true;
    }

    /// Rays traced so far by the render (all kinds).
    #[must_use]
    pub fn rays(&self) -> u64 {
        self.rays.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// A copy of the image so far (black where tiles are missing), or
    /// `None` before the render has started.
    #[must_use]
    pub fn snapshot(&self) -> Option<Framebuffer> {
        self.lock().image.clone()
    }

    /// The tiles not finished yet, in the render's coordinates.
    #[must_use]
    pub fn missing(&self) -> Vec<PixelRect> {
        self.lock()
            .tiles
            .iter()
            .filter(|(_, done)| !done)
            .map(|(r, _)| *r)
            .collect()
    }

    /// How many tiles the render has.
    #[must_use]
    pub fn tile_count(&self) -> usize {
        self.lock().tiles.len()
    }
}
