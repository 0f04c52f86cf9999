//! Image textures: texels as `u8` (sRGB-encoded colour or linear data) or
//! linear `f32`, a mip pyramid built once by 2×2 box filtering in linear
//! space, wrap modes and nearest / bilinear / trilinear lookups.
//!
//! Texture space follows glTF: `(0, 0)` is the top-left corner of the
//! first texel row as stored, `u` grows to the right and `v` downwards;
//! a texel's centre is at `(x + ½, y + ½) / (width, height)`.

use super::TextureError;

/// What lies beyond `[0, 1]` in one texture coordinate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// The image repeats (glTF `REPEAT`, the default).
    #[default]
    Repeat,
    /// The edge texels extend outwards (`CLAMP_TO_EDGE`).
    Clamp,
    /// The image repeats, every other copy mirrored (`MIRRORED_REPEAT`).
    Mirror,
}

impl Wrap {
    /// The texel index for integer position `i` in a row of `n` texels.
    #[inline]
    fn index(self, i: i64, n: u32) -> usize {
        let n = i64::from(n);
        let k = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
        };
        k as usize
    }
}

/// How texels are combined within one mip level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TexFilter {
    /// The nearest texel (pixel art, data that must not be blended).
    Nearest,
    /// Bilinear interpolation of the four nearest texels (the default).
    #[default]
    Linear,
}

/// How an image texture is looked up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Sampler {
    /// Wrap mode along `u`.
    pub wrap_u: Wrap,
    /// Wrap mode along `v`.
    pub wrap_v: Wrap,
    /// Filter within a level (magnification, and minification within the
    /// two nearest levels).
    pub filter: TexFilter,
    /// Whether minified lookups use the mip pyramid (trilinear with
    /// [`TexFilter::Linear`], nearest level with [`TexFilter::Nearest`]);
    /// without, a minified lookup reads level 0 and aliases.
    pub mipmaps: bool,
}

impl Sampler {
    /// Repeat in both directions, bilinear, mipmapped: what a renderer does
    /// when a file says nothing.
    pub const DEFAULT: Self = Self {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: TexFilter::Linear,
        mipmaps: true,
    };
}

/// The largest texture side accepted (16384 texels).
pub const MAX_TEXTURE_SIDE: u32 = 1 << 14;

#[derive(Clone, Debug, PartialEq)]
enum Texels {
    /// Four bytes per texel; colour channels sRGB-encoded when `srgb`.
    U8 { texels: Vec<[u8; 4]>, srgb: bool },
    /// Linear floats.
    F32(Vec<[f32; 4]>),
}

#[derive(Clone, Debug, PartialEq)]
struct Level {
    width: u32,
    height: u32,
    texels: Texels,
}

impl Level {
    /// Texel `(x, y)` as linear RGBA.
    #[inline]
    fn fetch(&self, x: usize, y: usize) -> [f32; 4] {
        let k = y * self.width as usize + x;
        match &self.texels {
            Texels::U8 { texels, srgb } => {
                let t = texels[k];
                let c = |b: u8| {
                    if *srgb {
                        SRGB_TO_LINEAR[b as usize]
                    } else {
                        f32::from(b) / 255.0
                    }
                };
                [c(t[0]), c(t[1]), c(t[2]), f32::from(t[3]) / 255.0]
            }
            Texels::F32(v) => v[k],
        }
    }

    /// The next smaller level: each texel the mean of (up to) 2×2 texels,
    /// averaged in linear space.
    fn half(&self) -> Level {
        let (w, h) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let mut lin = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h as usize {
            for x in 0..w as usize {
                let mut s = [0.0f32; 4];
                let xs = [2 * x, (2 * x + 1).min(self.width as usize - 1)];
                let ys = [2 * y, (2 * y + 1).min(self.height as usize - 1)];
                for &yy in &ys {
                    for &xx in &xs {
                        let t = self.fetch(xx, yy);
                        for c in 0..4 {
                            s[c] += 0.25 * t[c];
                        }
                    }
                }
                lin.push(s);
            }
        }
        let texels = match &self.texels {
            Texels::U8 { srgb, .. } => Texels::U8 {
                texels: lin.iter().map(|t| encode_u8(*t, *srgb)).collect(),
                srgb: *srgb,
            },
            Texels::F32(_) => Texels::F32(lin),
        };
        Level {
            width: w,
            height: h,
            texels,
        }
    }

    /// Bilinear lookup at texture position `(u, v)`.
    #[inline]
    fn bilinear(&self, u: f32, v: f32, s: &Sampler) -> [f32; 4] {
        let x = u * self.width as f32 - 0.5;
        let y = v * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let xa = s.wrap_u.index(x0, self.width);
        let xb = s.wrap_u.index(x0 + 1, self.width);
        let ya = s.wrap_v.index(y0, self.height);
        let yb = s.wrap_v.index(y0 + 1, self.height);
        let (t00, t10, t01, t11) = (
            self.fetch(xa, ya),
            self.fetch(xb, ya),
            self.fetch(xa, yb),
            self.fetch(xb, yb),
        );
        std::array::from_fn(|c| {
            let top = t00[c] + (t10[c] - t00[c]) * fx;
            let bottom = t01[c] + (t11[c] - t01[c]) * fx;
            top + (bottom - top) * fy
        })
    }

    /// The texel that holds texture position `(u, v)`.
    #[inline]
    fn nearest(&self, u: f32, v: f32, s: &Sampler) -> [f32; 4] {
        let x = (u * self.width as f32).floor() as i64;
        let y = (v * self.height as f32).floor() as i64;
        self.fetch(
            s.wrap_u.index(x, self.width),
            s.wrap_v.index(y, self.height),
        )
    }
}

/// An image texture with its mip pyramid (level 0 is the image).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    levels: Vec<Level>,
    sampler: Sampler,
}

impl ImageTexture {
    /// A texture from 8-bit RGBA texels, row after row from the top;
    /// `srgb` says that the colour channels are sRGB-encoded (colour
    /// maps), else they are linear data (normal, metallic-roughness maps).
    /// Alpha is always linear.
    ///
    /// # Errors
    /// [`TextureError::Size`] when a side is 0 or over
    /// [`MAX_TEXTURE_SIDE`], or `rgba` does not hold `4·width·height` bytes.
    pub fn from_rgba8(
        width: u32,
        height: u32,
        rgba: &[u8],
        srgb: bool,
        sampler: Sampler,
    ) -> Result<Self, TextureError> {
        check_size(width, height, rgba.len(), 4)?;
        let texels = rgba
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        Ok(Self::with_levels(
            Level {
                width,
                height,
                texels: Texels::U8 { texels, srgb },
            },
            sampler,
        ))
    }

    /// A texture from linear floating-point RGBA texels (HDR images), row
    /// after row from the top. Non-finite values become 0.
    ///
    /// # Errors
    /// As [`ImageTexture::from_rgba8`], with one texel per `[f32; 4]`.
    pub fn from_rgba32f(
        width: u32,
        height: u32,
        rgba: Vec<[f32; 4]>,
        sampler: Sampler,
    ) -> Result<Self, TextureError> {
        check_size(width, height, rgba.len(), 1)?;
        let texels = rgba
            .into_iter()
            .map(|t| t.map(|c| if c.is_finite() { c } else { 0.0 }))
            .collect();
        Ok(Self::with_levels(
            Level {
                width,
                height,
                texels: Texels::F32(texels),
            },
            sampler,
        ))
    }

    fn with_levels(base: Level, sampler: Sampler) -> Self {
        let mut levels = vec![base];
        if sampler.mipmaps {
            while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
                let next = last.half();
                levels.push(next);
            }
        }
        Self { levels, sampler }
    }

    /// Width and height of the image (level 0).
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// The number of mip levels (1 without mipmaps).
    #[must_use]
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// The sampler.
    #[must_use]
    pub fn sampler(&self) -> Sampler {
        self.sampler
    }

    /// Linear RGBA at texture position `uv` for a lookup whose footprint
    /// is `width` texture-space units across (0: a point). The level of
    /// detail is `log2(width · max(w, h))`; trilinear filtering blends the
    /// two nearest levels.
    #[must_use]
    pub fn lookup(&self, uv: glam::Vec2, width: f32) -> [f32; 4] {
        let (u, v) = (sanitize(uv.x), sanitize(uv.y));
        let s = &self.sampler;
        let base = &self.levels[0];
        let texels = width * base.width.max(base.height) as f32;
        let lod = if texels > 1.0 && texels.is_finite() {
            texels.log2().min((self.levels.len() - 1) as f32)
        } else {
            0.0
        };
        let at = |l: usize| {
            let level = &self.levels[l];
            match s.filter {
                TexFilter::Nearest => level.nearest(u, v, s),
                TexFilter::Linear => level.bilinear(u, v, s),
            }
        };
        if lod <= 0.0 || self.levels.len() == 1 {
            return at(0);
        }
        if s.filter == TexFilter::Nearest {
            return at(lod.round() as usize);
        }
        let l0 = lod.floor() as usize;
        let f = lod - l0 as f32;
        let a = at(l0);
        if f == 0.0 || l0 + 1 >= self.levels.len() {
            return a;
        }
        let b = at(l0 + 1);
        std::array::from_fn(|c| a[c] + (b[c] - a[c]) * f)
    }
}

/// A texture coordinate that is finite (NaN and infinities read as 0), and
/// small enough that `x · width` stays exact in an `i64`.
#[inline]
fn sanitize(x: f32) -> f32 {
    if x.is_finite() {
        x.clamp(-1e6, 1e6)
    } else {
        0.0
    }
}

fn check_size(width: u32, height: u32, len: usize, per: usize) -> Result<(), TextureError> {
    if width == 0 || height == 0 || width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(TextureError::Size {
            width,
            height,
            reason: "each side must be 1 to 16384 texels",
        });
    }
    if len != width as usize * height as usize * per {
        return Err(TextureError::Size {
            width,
            height,
            reason: "the texel data does not match the size",
        });
    }
    Ok(())
}

/// sRGB transfer function, decoding (IEC 61966-2-1).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB transfer function, encoding.
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

fn encode_u8(t: [f32; 4], srgb: bool) -> [u8; 4] {
    let q = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    let c = |x: f32| if srgb { q(linear_to_srgb(x)) } else { q(x) };
    [c(t[0]), c(t[1]), c(t[2]), q(t[3])]
}

/// `srgb_to_linear(b / 255)` for every byte.
static SRGB_TO_LINEAR: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|b| srgb_to_linear(b as f32 / 255.0)));

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn checker(n: u32, sampler: Sampler) -> ImageTexture {
        let mut rgba = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let b = if (x + y) % 2 == 0 { 255 } else { 0 };
                rgba.extend([b, b, b, 255]);
            }
        }
        ImageTexture::from_rgba8(n, n, &rgba, false, sampler).unwrap()
    }

    #[test]
    fn srgb_round_trips_every_byte() {
        for b in 0..=255u8 {
            let l = SRGB_TO_LINEAR[b as usize];
            assert_eq!(encode_u8([l, l, l, 1.0], true)[0], b);
        }
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn wrap_modes_fold_indices() {
        assert_eq!(Wrap::Repeat.index(-1, 4), 3);
        assert_eq!(Wrap::Repeat.index(9, 4), 1);
        assert_eq!(Wrap::Clamp.index(-7, 4), 0);
        assert_eq!(Wrap::Clamp.index(7, 4), 3);
        assert_eq!(Wrap::Mirror.index(4, 4), 3);
        assert_eq!(Wrap::Mirror.index(-1, 4), 0);
        assert_eq!(Wrap::Mirror.index(8, 4), 0);
    }

    #[test]
    fn texel_centres_read_exactly_and_bilinear_blends() {
        let t = checker(4, Sampler::DEFAULT);
        assert_eq!(t.lookup(Vec2::new(0.125, 0.125), 0.0)[0], 1.0);
        assert_eq!(t.lookup(Vec2::new(0.375, 0.125), 0.0)[0], 0.0);
        // Halfway between two texel centres: the mean.
        assert!((t.lookup(Vec2::new(0.25, 0.125), 0.0)[0] - 0.5).abs() < 1e-6);
        // Repeat: one period further is the same.
        let a = t.lookup(Vec2::new(0.3, 0.7), 0.0);
        let b = t.lookup(Vec2::new(1.3, -0.3), 0.0);
        assert!((a[0] - b[0]).abs() < 1e-5);
    }

    #[test]
    fn mip_pyramid_averages_to_grey_and_wide_footprints_use_it() {
        let t = checker(8, Sampler::DEFAULT);
        assert_eq!(t.level_count(), 4);
        // A footprint of the whole texture reads the 1×1 level: the mean.
        let far = t.lookup(Vec2::new(0.3, 0.6), 1.0);
        assert!((far[0] - 0.5).abs() < 0.01, "{far:?}");
        // Without mipmaps the same lookup aliases to a texel.
        let s = Sampler {
            mipmaps: false,
            ..Sampler::DEFAULT
        };
        let t = checker(8, s);
        assert_eq!(t.level_count(), 1);
        let v = t.lookup(Vec2::new(1.0 / 16.0, 1.0 / 16.0), 1.0)[0];
        assert_eq!(v, 1.0);
    }

    #[test]
    fn srgb_mips_average_in_linear_space() {
        // Black and white sRGB texels average to linear 0.5, not to sRGB 128.
        let rgba = [0, 0, 0, 255, 255, 255, 255, 255];
        let t = ImageTexture::from_rgba8(2, 1, &rgba, true, Sampler::DEFAULT).unwrap();
        let v = t.lookup(Vec2::new(0.5, 0.5), 1.0)[0];
        assert!((v - 0.5).abs() < 0.01, "{v}");
    }

    #[test]
    fn nearest_filter_and_clamp() {
        let s = Sampler {
            wrap_u: Wrap::Clamp,
            wrap_v: Wrap::Clamp,
            filter: TexFilter::Nearest,
            mipmaps: false,
        };
        let t = checker(2, s);
        assert_eq!(t.lookup(Vec2::new(-3.0, 0.1), 0.0)[0], 1.0);
        assert_eq!(t.lookup(Vec2::new(5.0, 0.1), 0.0)[0], 0.0);
        assert_eq!(t.lookup(Vec2::new(f32::NAN, 0.1), 0.0)[0], 1.0);
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert!(ImageTexture::from_rgba8(0, 1, &[], true, Sampler::DEFAULT).is_err());
        assert!(ImageTexture::from_rgba8(2, 2, &[0; 12], true, Sampler::DEFAULT).is_err());
        let big = MAX_TEXTURE_SIDE + 1;
        assert!(
            ImageTexture::from_rgba32f(big, 1, vec![[0.0; 4]; big as usize], Sampler::DEFAULT)
                .is_err()
        );
        let t = ImageTexture::from_rgba32f(1, 1, vec![[f32::NAN, 1.0, 2.0, 1.0]], Sampler::DEFAULT)
            .unwrap();
        assert_eq!(t.lookup(Vec2::ZERO, 0.0), [0.0, 1.0, 2.0, 1.0]);
    }
}
