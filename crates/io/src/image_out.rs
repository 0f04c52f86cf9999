//! Writing images (PNG, EXR) and other outputs atomically.

use crate::error::{Error, Result};
use gridrt_tracer::{srgb8_into, Rgb, Srgb8Image};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Image formats gridrt writes, chosen by the output file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// `.png`: 8-bit RGB, sRGB-encoded (the IEC 61966-2-1 transfer
    /// function, not a 2.2 gamma), values clamped to [0, 1].
    Png,
    /// `.exr`: OpenEXR, linear RGB 32-bit float, values as rendered.
    Exr,
}

impl ImageFormat {
    /// The format for an output path, by extension (case-insensitive).
    ///
    /// # Errors
    /// [`Error::Output`] for another or no extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("exr") => Ok(Self::Exr),
            Some(e) => Err(Error::output(
                path,
                format!(
                    "unknown image format \".{e}\": use .png (8-bit sRGB) or .exr (linear float)"
                ),
            )),
            None => Err(Error::output(
                path,
                "no file extension: use .png (8-bit sRGB) or .exr (linear float)",
            )),
        }
    }
}

/// Checks, before any work, that `path` can become an output file: its
/// directory exists and it is not itself a directory.
///
/// # Errors
/// [`Error::Output`] saying what to fix.
pub fn check_output_dir(path: &Path) -> Result<()> {
    if path.as_os_str().is_empty() {
        return Err(Error::output(path, "empty output path"));
    }
    check_replaceable(path)?;
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(Error::output(
            path,
            format!(
                "the directory {} does not exist: create it first or choose another path",
                dir.display()
            ),
        ));
    }
    Ok(())
}

/// Checks an image output path: extension and directory.
///
/// # Errors
/// [`Error::Output`] for an unknown extension or a missing directory.
pub fn check_image_path(path: &Path) -> Result<ImageFormat> {
    let format = ImageFormat::from_path(path)?;
    check_output_dir(path)?;
    Ok(format)
}

/// The directory a file goes in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes linear-RGB pixels (row-major, row 0 at the top) as PNG or EXR,
/// by the path's extension, atomically (see [`write_atomic`]).
///
/// # Errors
/// [`Error::Output`] for a bad path, [`Error::Write`] when writing fails
/// (the file is then left as it was).
///
/// # Panics
/// If `pixels.len() != width · height` (a caller bug, not bad input).
pub fn write_image(path: &Path, width: u32, height: u32, pixels: &[Rgb]) -> Result<()> {
    stage_image(path, width, height, pixels)?.commit()
}

/// [`write_image`] up to the rename: the image is complete and synced in a
/// temporary file beside `path`, which [`Staged::commit`] renames into
/// place (dropping the [`Staged`] removes it).
///
/// # Errors
/// As [`write_image`].
///
/// # Panics
/// If `pixels.len() != width · height` (a caller bug, not bad input).
pub fn stage_image(path: &Path, width: u32, height: u32, pixels: &[Rgb]) -> Result<Staged> {
    assert_eq!(
        pixels.len() as u64,
        u64::from(width) * u64::from(height),
        "pixel count must be width × height"
    );
    let format = check_image_path(path)?;
    stage(path, |file| {
        let mut w = BufWriter::new(file);
        match format {
            ImageFormat::Png => {
                let mut bytes = vec![0; 3 * pixels.len()];
                srgb8_into(&mut bytes, pixels);
                encode_png8(&mut w, width, height, &bytes)?;
            }
            ImageFormat::Exr => {
                let clean = |x: f32| if x.is_finite() { x } else { 0.0 };
                let bytes: Vec<u8> = pixels
                    .iter()
                    .flat_map(|p| [clean(p.x), clean(p.y), clean(p.z)])
                    .flat_map(f32::to_ne_bytes)
                    .collect();
                let enc = image::codecs::openexr::OpenExrEncoder::new(&mut w);
                image::ImageEncoder::write_image(
                    enc,
                    &bytes,
                    width,
                    height,
                    image::ExtendedColorType::Rgb32F,
                )
                .map_err(image_io_error)?;
            }
        }
        w.flush()
    })
}

/// Stages an 8-bit sRGB image as a PNG at `path` (which must name a
/// `.png`), as [`stage_image`] does with linear pixels: the same bytes for
/// [`Srgb8Image::from_linear`] of those pixels.
///
/// # Errors
/// As [`write_image`]; [`Error::Output`] also when `path` is not a PNG.
///
/// # Panics
/// If `image.bytes.len() != 3 · width · height` (a caller bug).
pub fn stage_png8(path: &Path, image: &Srgb8Image) -> Result<Staged> {
    assert_eq!(
        image.bytes.len() as u64,
        3 * u64::from(image.width) * u64::from(image.height),
        "byte count must be 3 × width × height"
    );
    if check_image_path(path)? != ImageFormat::Png {
        return Err(Error::output(
            path,
            "8-bit sRGB pixels are written as PNG only",
        ));
    }
    stage(path, |file| {
        let mut w = BufWriter::new(file);
        encode_png8(&mut w, image.width, image.height, &image.bytes)?;
        w.flush()
    })
}

/// Encodes 8-bit RGB `bytes` as a PNG into `w`.
fn encode_png8(w: &mut impl Write, width: u32, height: u32, bytes: &[u8]) -> std::io::Result<()> {
    let enc = image::codecs::png::PngEncoder::new(w);
    image::ImageEncoder::write_image(enc, bytes, width, height, image::ExtendedColorType::Rgb8)
        .map_err(image_io_error)
}

/// The I/O error inside an encoder's error (so "File too large" or "No
/// space left on device" reach the message), else the encoder's error.
fn image_io_error(e: image::ImageError) -> std::io::Error {
    match e {
        image::ImageError::IoError(io) => io,
        other => std::io::Error::other(other),
    }
}

/// Writes a file atomically: the content goes to a temporary file in the
/// same directory, which is renamed over `path` only once it is complete
/// and synced. A failure or an interruption never leaves a half-written
/// `path` and never replaces a good one; the temporary file is removed.
///
/// # Errors
/// [`Error::Write`] naming `path`; [`Error::Output`] when `path` exists
/// and is not a regular file (a device such as `/dev/null` is never
/// replaced).
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut File) -> std::io::Result<()>,
) -> Result<()> {
    stage(path, write)?.commit()
}

/// An output written completely to a temporary file, waiting to be renamed
/// over its path. Dropped without [`Staged::commit`], the temporary file is
/// removed and the path is untouched.
#[derive(Debug)]
pub struct Staged {
    tmp: tempfile::NamedTempFile,
    path: std::path::PathBuf,
}

impl Staged {
    /// Renames the temporary file over the path.
    ///
    /// # Errors
    /// [`Error::Output`] when the path has become a non-regular file,
    /// [`Error::Write`] when the rename fails (the temporary file is then
    /// removed).
    pub fn commit(self) -> Result<()> {
        check_replaceable(&self.path)?;
        let path = self.path;
        self.tmp.persist(&path).map_err(|e| Error::Write {
            path: path.clone(),
            source: e.error,
        })?;
        Ok(())
    }
}

/// The first step of [`write_atomic`]: everything but the rename.
///
/// # Errors
/// As [`write_atomic`].
pub fn stage(path: &Path, write: impl FnOnce(&mut File) -> std::io::Result<()>) -> Result<Staged> {
    check_replaceable(path)?;
    let werr = |source| Error::Write {
        path: path.to_path_buf(),
        source,
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".gridrt-")
        .suffix(".tmp")
        .tempfile_in(parent_dir(path))
        .map_err(werr)?;
    write(tmp.as_file_mut()).map_err(werr)?;
    tmp.as_file().sync_all().map_err(werr)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // tempfile creates 0600; an output file should be readable like any other.
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))
            .map_err(werr)?;
    }
    Ok(Staged {
        tmp,
        path: path.to_path_buf(),
    })
}

/// An existing `path` must be a regular file (a symbolic link to one is
/// replaced by the output, its target left alone): a rename over a device,
/// FIFO or socket would replace the special file itself.
fn check_replaceable(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(Error::output(path, "is a directory: give a file name")),
        Ok(m) if !m.is_file() => Err(Error::output(
            path,
            "is a special file (a device, FIFO or socket), not a regular file: gridrt writes an output by replacing the file, so give the path of a regular file",
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a.PNG")).unwrap(),
            ImageFormat::Png
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("a.exr")).unwrap(),
            ImageFormat::Exr
        );
        let e = ImageFormat::from_path(Path::new("a.jpg"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown image format \".jpg\""), "{e}");
        assert!(ImageFormat::from_path(Path::new("a")).is_err());
    }

    #[test]
    fn png_and_exr_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let px = vec![Rgb::new(0.0, 0.5, 1.0), Rgb::new(2.0, 0.25, f32::NAN)];
        let png = dir.path().join("a.png");
        write_image(&png, 2, 1, &px).unwrap();
        let img = image::open(&png).unwrap().to_rgb8();
        assert_eq!(img.get_pixel(0, 0).0, [0, 188, 255]);
        assert_eq!(img.get_pixel(1, 0).0, [255, 137, 0]);
        let exr = dir.path().join("a.exr");
        write_image(&exr, 2, 1, &px).unwrap();
        let img = image::open(&exr).unwrap().to_rgb32f();
        assert_eq!(img.get_pixel(1, 0).0, [2.0, 0.25, 0.0]);
        // No temporary file is left behind.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
    }

    #[test]
    fn png_from_srgb_bytes_is_the_png_from_linear_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let px: Vec<Rgb> = (0..12)
            .map(|i| Rgb::new(i as f32 / 7.0, 0.001 * i as f32, f32::NAN))
            .collect();
        let fb = gridrt_tracer::Framebuffer {
            width: 4,
            height: 3,
            pixels: px.clone(),
        };
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        write_image(&a, 4, 3, &px).unwrap();
        stage_png8(&b, &Srgb8Image::from_linear(&fb))
            .unwrap()
            .commit()
            .unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        // Bytes are for PNGs only.
        let err = stage_png8(&dir.path().join("c.exr"), &Srgb8Image::from_linear(&fb));
        assert!(err.unwrap_err().to_string().contains("PNG only"));
    }

    #[test]
    fn a_failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("keep.txt");
        std::fs::write(&p, "good").unwrap();
        let r = write_atomic(&p, |f| {
            f.write_all(b"half")?;
            Err(std::io::Error::other("disk on fire"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "good");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn missing_directories_are_reported_before_writing() {
        let e = check_image_path(Path::new("/nonexistent-gridrt-dir/x.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
    }
}
