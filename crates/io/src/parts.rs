//! Parts of a frame: crop windows and tiles rendered by separate processes,
//! written as EXR files that record where they belong, and merged back.
//!
//! A part is a list of [`PixelRect`]s of the full image. `--crop` gives one
//! rectangle; `--tile I/N` gives tile `I` of `N`: the image is cut into
//! strips of [`STRIP`] rows and tile `I` takes strips `I, I + N, I + 2N, …`,
//! so every tile gets rows from the top, middle and bottom of the frame and
//! the tiles of one frame cost about the same however the cost is spread
//! over it.
//!
//! A part file is an OpenEXR file with one layer per rectangle: the
//! display window is the full image, each layer's data window is its
//! rectangle, and the image attribute `gridrt.fingerprint` identifies the
//! scene and every setting that changes a pixel. [`merge_parts`] accepts
//! parts only of one fingerprint and size whose rectangles cover the image
//! exactly once. Pixels are stored as rendered (32-bit float, non-finite
//! values kept), so the merged image is written by the same code as a full
//! render and is byte for byte the same file.

use crate::error::{Error, Result};
use crate::image_out::Staged;
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, ImageAttributes,
    IntegerBounds, Layer, LayerAttributes, Text, Vec2, WritableImage,
};
use gridrt_tracer::{Framebuffer, PixelRect, Rgb, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Rows per strip of a tile.
pub const STRIP: u32 = 16;

/// The EXR image attribute that holds a part's fingerprint.
const FINGERPRINT_ATTR: &str = "gridrt.fingerprint";

/// Which part of the frame a process renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PartSpec {
    /// A crop window, each bound in pixels or, when every bound is at most
    /// 1 and one has a fraction, as fractions of the image size.
    Crop([f64; 4]),
    /// Tile `index` of `count` (0-based).
    Tile {
        /// Which tile, below `count`.
        index: u32,
        /// How many tiles the frame is split into.
        count: u32,
    },
}

impl PartSpec {
    /// Parses `--crop X0,Y0,X1,Y1`.
    ///
    /// # Errors
    /// A message saying what is wrong with the text.
    pub fn parse_crop(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<&str> = s.split(',').map(str::trim).collect();
        if v.len() != 4 {
            return Err(format!(
                "expected X0,Y0,X1,Y1 (four numbers), got {} fields",
                v.len()
            ));
        }
        let mut b = [0.0; 4];
        for (slot, t) in b.iter_mut().zip(&v) {
            *slot = t
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x >= 0.0)
                .ok_or_else(|| format!("`{}` is not a number ≥ 0", t.escape_debug()))?;
        }
        Ok(Self::Crop(b))
    }

    /// Parses `--tile I/N`.
    ///
    /// # Errors
    /// A message saying what is wrong with the text.
    pub fn parse_tile(s: &str) -> std::result::Result<Self, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| "expected I/N, such as 0/4 (tile 0 of 4)".to_string())?;
        let index: u32 = i
            .trim()
            .parse()
            .map_err(|_| format!("tile index `{}` is not a whole number", i.escape_debug()))?;
        let count: u32 = n
            .trim()
            .parse()
            .map_err(|_| format!("tile count `{}` is not a whole number", n.escape_debug()))?;
        if count == 0 || index >= count {
            return Err(format!(
                "tile {index}/{count}: the index must be below the count (tiles are 0 … {})",
                count.saturating_sub(1)
            ));
        }
        Ok(Self::Tile { index, count })
    }

    /// The rectangles of a `width × height` image this part covers, in
    /// order (top to bottom).
    ///
    /// # Errors
    /// A message when the crop window is empty or outside the image, or
    /// the frame has fewer strips than tiles.
    pub fn rects(&self, width: u32, height: u32) -> std::result::Result<Vec<PixelRect>, String> {
        match *self {
            Self::Crop(b) => {
                let fractions = b.iter().all(|&x| x <= 1.0) && b.iter().any(|&x| x.fract() != 0.0);
                let px = |x: f64, size: u32| -> f64 {
                    if fractions {
                        (x * f64::from(size)).round()
                    } else {
                        x
                    }
                };
                let r = [
                    px(b[0], width),
                    px(b[1], height),
                    px(b[2], width),
                    px(b[3], height),
                ];
                if r.iter().any(|x| x.fract() != 0.0) {
                    return Err("crop bounds in pixels must be whole numbers".into());
                }
                if r[0] >= r[2] || r[1] >= r[3] {
                    return Err(format!(
                        "crop window {},{} – {},{} is empty: X0 < X1 and Y0 < Y1 are needed",
                        r[0], r[1], r[2], r[3]
                    ));
                }
                if r[2] > f64::from(width) || r[3] > f64::from(height) {
                    return Err(format!(
                        "crop window {},{} – {},{} reaches outside the {width} x {height} image",
                        r[0], r[1], r[2], r[3]
                    ));
                }
                // Whole numbers within the image: the conversions are exact.
                Ok(vec![PixelRect {
                    x0: r[0] as u32,
                    y0: r[1] as u32,
                    x1: r[2] as u32,
                    y1: r[3] as u32,
                }])
            }
            Self::Tile { index, count } => {
                let strips = height.div_ceil(STRIP);
                if count > strips {
                    return Err(format!(
                        "{count} tiles, but a {height}-row image has only {strips} strips of \
                         {STRIP} rows: use at most {strips} tiles"
                    ));
                }
                Ok((index..strips)
                    .step_by(count as usize)
                    .map(|s| PixelRect {
                        x0: 0,
                        y0: s * STRIP,
                        x1: width,
                        y1: ((s + 1) * STRIP).min(height),
                    })
                    .collect())
            }
        }
    }
}

/// A 64-bit FNV-1a hash fed through `fmt::Write`, so a scene's `Debug`
/// text is hashed without being held in memory.
struct Fnv(u64);

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
        Ok(())
    }
}

/// A fingerprint of everything that decides a frame's pixels: the scene
/// with its settings (size, samples, depth, camera, every object, material
/// and light, exactly as loaded). The accelerator and the thread count are
/// left out: they never change a pixel. Two renders with equal
/// fingerprints produce the same image.
#[must_use]
pub fn fingerprint(scene: &Scene) -> String {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    // Writing into the hasher cannot fail.
    let _ = write!(h, "gridrt-part-v1 {scene:?}");
    format!("{:016x}", h.0)
}

/// Writes the rendered rectangles of one part as a multi-layer EXR file
/// (see the module doc), atomically. `images[k]` holds the pixels of
/// `rects[k]`.
///
/// # Errors
/// [`Error::Output`] for a path that is not `.exr`, [`Error::Write`] when
/// writing fails (nothing is left behind).
///
/// # Panics
/// When `images` and `rects` disagree in number or size (a caller bug).
pub fn write_part(
    path: &Path,
    full: (u32, u32),
    fingerprint: &str,
    rects: &[PixelRect],
    images: &[Framebuffer],
) -> Result<()> {
    stage_part(path, full, fingerprint, rects, images)?.commit()
}

/// [`write_part`] up to the rename: the part in a temporary file beside
/// `path`, put in place by [`Staged::commit`].
///
/// # Errors
/// As [`write_part`].
///
/// # Panics
/// As [`write_part`].
pub fn stage_part(
    path: &Path,
    full: (u32, u32),
    fingerprint: &str,
    rects: &[PixelRect],
    images: &[Framebuffer],
) -> Result<Staged> {
    assert_eq!(rects.len(), images.len(), "one image per rectangle");
    if crate::ImageFormat::from_path(path)? != crate::ImageFormat::Exr {
        return Err(Error::output(
            path,
            "a crop or tile is written as .exr, which records its place in the full image; \
             `gridrt merge` turns the parts into a .png or .exr",
        ));
    }
    crate::check_output_dir(path)?;
    let layers: Vec<Layer<AnyChannels<FlatSamples>>> = rects
        .iter()
        .zip(images)
        .enumerate()
        .map(|(k, (r, img))| {
            assert_eq!((img.width, img.height), (r.width(), r.height()));
            let channel = |name: &str, get: fn(&Rgb) -> f32| {
                AnyChannel::new(name, FlatSamples::F32(img.pixels.iter().map(get).collect()))
            };
            let mut attrs = LayerAttributes::named(format!("part{k}").as_str());
            attrs.layer_position = Vec2(r.x0 as i32, r.y0 as i32);
            // OpenEXR keeps one header per layer; the fingerprint goes in
            // each, where every reader finds it.
            attrs.other.insert(
                Text::from(FINGERPRINT_ATTR),
                AttributeValue::Text(Text::from(fingerprint)),
            );
            Layer::new(
                (r.width() as usize, r.height() as usize),
                attrs,
                Encoding::FAST_LOSSLESS,
                AnyChannels::sort(
                    vec![
                        channel("R", |p| p.x),
                        channel("G", |p| p.y),
                        channel("B", |p| p.z),
                    ]
                    .into(),
                ),
            )
        })
        .collect();
    let attrs = ImageAttributes::new(IntegerBounds::from_dimensions((
        full.0 as usize,
        full.1 as usize,
    )));
    let image = Image::from_layers(attrs, layers);
    crate::stage(path, |file| {
        let mut w = std::io::BufWriter::new(file);
        image
            .write()
            .non_parallel()
            .to_buffered(&mut w)
            .map_err(std::io::Error::other)?;
        std::io::Write::flush(&mut w)
    })
}

/// One part read back.
#[derive(Debug)]
struct Part {
    path: PathBuf,
    full: (u32, u32),
    fingerprint: String,
    /// The rectangles and their pixels.
    rects: Vec<(PixelRect, Vec<Rgb>)>,
}

fn read_part(path: &Path) -> Result<Part> {
    let bad = |msg: String| Error::Images {
        path: path.to_path_buf(),
        msg,
    };
    let image = exr::prelude::read_all_flat_layers_from_file(path)
        .map_err(|e| bad(format!("not a readable EXR part: {e}")))?;
    let key = Text::from(FINGERPRINT_ATTR);
    let mut prints = image
        .layer_data
        .iter()
        .map(|l| match l.attributes.other.get(&key) {
            Some(AttributeValue::Text(t)) => Some(t.to_string()),
            _ => None,
        });
    let fingerprint = match prints.next().flatten() {
        Some(f) if prints.all(|p| p.as_ref() == Some(&f)) => f,
        _ => {
            return Err(bad(
                "has no gridrt part fingerprint: only files written by `gridrt render --crop` \
                 or `--tile` can be merged"
                    .into(),
            ))
        }
    };
    let dw = image.attributes.display_window;
    if dw.position != Vec2(0, 0) {
        return Err(bad("its display window does not start at 0,0".into()));
    }
    let full = (
        u32::try_from(dw.size.0).map_err(|_| bad("display window too large".into()))?,
        u32::try_from(dw.size.1).map_err(|_| bad("display window too large".into()))?,
    );
    let mut rects = Vec::new();
    for layer in &image.layer_data {
        let pos = layer.attributes.layer_position;
        let (w, h) = (layer.size.0, layer.size.1);
        let rect = (|| {
            let x0 = u32::try_from(pos.0).ok()?;
            let y0 = u32::try_from(pos.1).ok()?;
            let x1 = x0.checked_add(u32::try_from(w).ok()?)?;
            let y1 = y0.checked_add(u32::try_from(h).ok()?)?;
            (x1 <= full.0 && y1 <= full.1).then_some(PixelRect { x0, y0, x1, y1 })
        })()
        .ok_or_else(|| bad("a layer lies outside the full image".into()))?;
        let channel = |name: &str| -> Result<&Vec<f32>> {
            layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq(name))
                .and_then(|c| match &c.sample_data {
                    FlatSamples::F32(v) => Some(v),
                    _ => None,
                })
                .ok_or_else(|| bad(format!("a layer has no 32-bit float channel {name}")))
        };
        let (r, g, b) = (channel("R")?, channel("G")?, channel("B")?);
        let pixels = r
            .iter()
            .zip(g)
            .zip(b)
            .map(|((&r, &g), &b)| Rgb::new(r, g, b))
            .collect();
        rects.push((rect, pixels));
    }
    Ok(Part {
        path: path.to_path_buf(),
        full,
        fingerprint,
        rects,
    })
}

/// Reads parts written by [`write_part`] and assembles the full image.
///
/// # Errors
/// [`Error::Images`] naming the part when a file is not a part, when parts
/// come from different scenes or settings or image sizes, when two parts
/// cover one pixel, or when pixels are covered by no part (the message
/// names the first uncovered rows and columns).
pub fn merge_parts(paths: &[PathBuf]) -> Result<Framebuffer> {
    let Some(first_path) = paths.first() else {
        return Err(Error::Images {
            path: PathBuf::from("(none)"),
            msg: "no parts given".into(),
        });
    };
    let first = read_part(first_path)?;
    let (w, h) = first.full;
    let mut image = Framebuffer::new(w, h);
    // Which part covers each pixel (index + 1; 0 = none yet).
    let mut owner = vec![0u32; w as usize * h as usize];
    let mut parts = vec![first];
    for p in &paths[1..] {
        parts.push(read_part(p)?);
    }
    for (k, part) in parts.iter().enumerate() {
        if part.fingerprint != parts[0].fingerprint || part.full != (w, h) {
            return Err(Error::Images {
                path: part.path.clone(),
                msg: format!(
                    "is a part of another render than {} (scene, settings or size differ)",
                    parts[0].path.display()
                ),
            });
        }
        for (rect, pixels) in &part.rects {
            let rw = rect.width() as usize;
            for y in rect.y0..rect.y1 {
                let row = y as usize * w as usize;
                for x in rect.x0..rect.x1 {
                    let i = row + x as usize;
                    if owner[i] != 0 {
                        return Err(Error::Images {
                            path: part.path.clone(),
                            msg: format!(
                                "overlaps {} at pixel ({x}, {y}): each pixel must come from \
                                 one part",
                                parts[owner[i] as usize - 1].path.display()
                            ),
                        });
                    }
                    owner[i] = k as u32 + 1;
                    let j = (y - rect.y0) as usize * rw + (x - rect.x0) as usize;
                    image.pixels[i] = pixels[j];
                }
            }
        }
    }
    if let Some(i) = owner.iter().position(|&o| o == 0) {
        let (x, y) = (i % w as usize, i / w as usize);
        let missing = owner.iter().filter(|&&o| o == 0).count();
        return Err(Error::Images {
            path: first_path.clone(),
            msg: format!(
                "the parts leave {missing} pixels of the {w} x {h} image uncovered, the first \
                 at ({x}, {y}): a tile or crop window is missing"
            ),
        });
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_partition_the_rows() {
        for (h, n) in [(120, 1), (120, 4), (121, 3), (16, 1), (100, 7)] {
            let mut seen = vec![0u32; h as usize];
            for i in 0..n {
                let rects = PartSpec::Tile { index: i, count: n }.rects(50, h).unwrap();
                for r in rects {
                    assert_eq!((r.x0, r.x1), (0, 50));
                    for y in r.y0..r.y1 {
                        seen[y as usize] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "h {h}, n {n}");
        }
    }

    #[test]
    fn too_many_tiles_and_bad_specs_are_refused() {
        assert!(PartSpec::Tile { index: 0, count: 9 }
            .rects(10, 120)
            .is_err());
        assert!(PartSpec::parse_tile("4/4").is_err());
        assert!(PartSpec::parse_tile("1/0").is_err());
        assert!(PartSpec::parse_tile("a/3").is_err());
        assert!(PartSpec::parse_tile("2").is_err());
        assert_eq!(
            PartSpec::parse_tile("1/3"),
            Ok(PartSpec::Tile { index: 1, count: 3 })
        );
    }

    #[test]
    fn crop_in_pixels_and_fractions() {
        let px = PartSpec::parse_crop("10,20,30,40").unwrap();
        assert_eq!(
            px.rects(100, 50).unwrap(),
            vec![PixelRect {
                x0: 10,
                y0: 20,
                x1: 30,
                y1: 40
            }]
        );
        let frac = PartSpec::parse_crop("0.25,0,0.5,1").unwrap();
        assert_eq!(
            frac.rects(100, 50).unwrap(),
            vec![PixelRect {
                x0: 25,
                y0: 0,
                x1: 50,
                y1: 50
            }]
        );
        // 0,0,1,1 has no fraction: it is one pixel, not the whole image.
        let one = PartSpec::parse_crop("0,0,1,1").unwrap();
        assert_eq!(one.rects(100, 50).unwrap()[0].width(), 1);
        assert!(PartSpec::parse_crop("10,20,5,40")
            .unwrap()
            .rects(100, 50)
            .is_err());
        assert!(PartSpec::parse_crop("0,0,101,10")
            .unwrap()
            .rects(100, 50)
            .is_err());
        assert!(PartSpec::parse_crop("1.5,0,3,4")
            .unwrap()
            .rects(100, 50)
            .is_err());
        assert!(PartSpec::parse_crop("0,0,1").is_err());
        assert!(PartSpec::parse_crop("0,0,nan,1").is_err());
        assert!(PartSpec::parse_crop("-1,0,1,1").is_err());
    }

    #[test]
    fn parts_round_trip_and_merge_checks() {
        let dir = tempfile::tempdir().unwrap();
        let px = |x: u32, y: u32| Rgb::new(x as f32, y as f32, f32::INFINITY);
        let img = |r: PixelRect| Framebuffer {
            width: r.width(),
            height: r.height(),
            pixels: (r.y0..r.y1)
                .flat_map(|y| (r.x0..r.x1).map(move |x| px(x, y)))
                .collect(),
        };
        let a = PixelRect {
            x0: 0,
            y0: 0,
            x1: 5,
            y1: 2,
        };
        let b = PixelRect {
            x0: 0,
            y0: 2,
            x1: 5,
            y1: 3,
        };
        let pa = dir.path().join("a.exr");
        let pb = dir.path().join("b.exr");
        write_part(&pa, (5, 3), "f1", &[a], &[img(a)]).unwrap();
        write_part(&pb, (5, 3), "f1", &[b], &[img(b)]).unwrap();
        let full = merge_parts(&[pb.clone(), pa.clone()]).unwrap();
        for y in 0..3 {
            for x in 0..5 {
                assert_eq!(full.get(x, y), px(x, y));
            }
        }
        // A gap, an overlap, another scene.
        let gap = merge_parts(std::slice::from_ref(&pa))
            .unwrap_err()
            .to_string();
        assert!(gap.contains("uncovered") && gap.contains("(0, 2)"), "{gap}");
        let twice = merge_parts(&[pa.clone(), pb.clone(), pa.clone()]).unwrap_err();
        assert!(twice.to_string().contains("overlaps"), "{twice}");
        let pc = dir.path().join("c.exr");
        write_part(&pc, (5, 3), "f2", &[b], &[img(b)]).unwrap();
        let other = merge_parts(&[pa.clone(), pc]).unwrap_err().to_string();
        assert!(other.contains("another render"), "{other}");
        // Not an EXR part at all.
        let junk = dir.path().join("junk.exr");
        std::fs::write(&junk, b"not an image").unwrap();
        assert!(merge_parts(&[junk])
            .unwrap_err()
            .to_string()
            .contains("junk.exr"));
        // A part must be EXR.
        assert!(write_part(&dir.path().join("a.png"), (5, 3), "f", &[a], &[img(a)]).is_err());
    }
}
