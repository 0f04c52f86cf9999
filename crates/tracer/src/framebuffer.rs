//! Rendered pixels: the [`Framebuffer`] and the [`PixelRect`] windows a
//! render can be limited to.

use crate::scene::Rgb;

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
