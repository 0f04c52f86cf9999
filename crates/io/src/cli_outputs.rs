//! Outputs beyond one image: the `--crop`/`--tile` parts and the `--aov`
//! passes of `gridrt render`, and the commands `gridrt merge` and
//! `gridrt diff`.

use crate::diff::{diff_files, kind_name, write_diff_image, ImageValues};
use crate::error::{Error, Result};
use crate::parts::{merge_parts, PartSpec};
use clap::Args;
use gridrt_tracer::{
    Aov, AovImage, Cancelled, Framebuffer, LiveImage, PixelRect, RenderStats, Renderer, Srgb8Image,
};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Options of `gridrt merge`.
#[derive(Debug, Clone, Args)]
pub struct MergeArgs {
    /// The parts: EXR files written by `gridrt render --tile I/N` or
    /// `--crop`, which together cover the image once.
    #[arg(value_name = "PARTS", required = true, num_args = 1..)]
    pub parts: Vec<PathBuf>,
    /// The full image: .png (8-bit sRGB) or .exr (linear float), the same
    /// file a render of the whole frame writes.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
}

/// Options of `gridrt diff`.
#[derive(Debug, Clone, Args)]
pub struct DiffArgs {
    /// The first image (.png or .exr).
    #[arg(value_name = "A")]
    pub a: PathBuf,
    /// The second image, of the same format and size.
    #[arg(value_name = "B")]
    pub b: PathBuf,
    /// Also write the difference of every channel, magnified by --gain, as
    /// an image (.png or .exr).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// A pixel counts as "over" when a channel differs by more than this
    /// (8-bit steps for PNG, linear values for EXR).
    #[arg(long, value_name = "T", default_value_t = 0.0)]
    pub threshold: f64,
    /// Magnification of the difference image.
    #[arg(long, value_name = "G", default_value_t = 32.0)]
    pub gain: f32,
}

/// `--crop` and `--tile` of `gridrt render`: which part of the frame to render.
#[derive(Debug, Clone, Copy, Args)]
pub struct PartArgs {
    /// Render only this window, X0,Y0,X1,Y1 (X1 and Y1 excluded), in
    /// pixels or, all at most 1, as fractions of the image (0.5,0,1,0.5 is
    /// the top-right quarter). Writes an EXR part for `gridrt merge`.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = PartSpec::parse_crop, conflicts_with = "tile")]
    pub crop: Option<PartSpec>,
    /// Render only tile I of N (0-based): interleaved strips of rows, so
    /// the tiles cost about the same. Writes an EXR part for `gridrt merge`.
    #[arg(long, value_name = "I/N", value_parser = PartSpec::parse_tile)]
    pub tile: Option<PartSpec>,
}

/// `--aov` of `gridrt render`: a list of passes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AovList(pub Vec<Aov>);

fn parse_aov_list(s: &str) -> std::result::Result<AovList, String> {
    crate::parse_aovs(s).map(AovList)
}

/// `--aov` of `gridrt render`.
#[derive(Debug, Clone, Args)]
pub struct AovArgs {
    /// Also write render passes, comma-separated: albedo, normal, depth,
    /// position, prim-id, material-id, cells-visited, tests (or all). In an
    /// .exr image they are extra channels (albedo.R, normal.X, depth.Z,
    /// tests.V, …); beside a .png image, pictures OUT.PASS.png.
    #[arg(long, value_name = "LIST", value_parser = parse_aov_list, conflicts_with_all = ["crop", "tile"])]
    pub aov: Option<AovList>,
}

/// The render passes `aovs` asks for, over the whole image: rendered
/// before the renderer is let go (a part has none).
pub(crate) fn render_passes(
    renderer: &Renderer,
    rendered: &Rendered,
    aovs: Option<&AovList>,
) -> Vec<AovImage> {
    match (rendered, aovs) {
        (Rendered::Full(_) | Rendered::Srgb8(_), Some(AovList(list))) => {
            let (w, h) = renderer.size();
            let all = PixelRect {
                x0: 0,
                y0: 0,
                x1: w,
                y1: h,
            };
            renderer.render_aovs(list, all)
        }
        _ => Vec::new(),
    }
}

/// Stages the image of a render of `size` pixels and its `passes`
/// ([`render_passes`]): a part as an EXR part, a full image with its passes
/// as EXR channels or as pictures beside a PNG.
pub(crate) fn stage_rendered(
    output: &Path,
    size: (u32, u32),
    rendered: &Rendered,
    passes: &[AovImage],
    fingerprint: Option<&str>,
) -> Result<Vec<crate::Staged>> {
    let image = match rendered {
        Rendered::Part(rects, images) => {
            let f = fingerprint.unwrap_or_default();
            return Ok(vec![crate::stage_part(output, size, f, rects, images)?]);
        }
        Rendered::Full(image) => image,
        Rendered::Srgb8(image) => {
            let mut staged = vec![crate::stage_png8(output, image)?];
            staged.extend(crate::stage_aov_pngs(output, passes)?);
            return Ok(staged);
        }
    };
    if passes.is_empty() {
        return Ok(vec![crate::stage_image(
            output,
            image.width,
            image.height,
            &image.pixels,
        )?]);
    }
    if crate::ImageFormat::from_path(output)? == crate::ImageFormat::Exr {
        Ok(vec![crate::stage_exr_with_aovs(output, image, passes)?])
    } else {
        let mut staged = vec![crate::stage_image(
            output,
            image.width,
            image.height,
            &image.pixels,
        )?];
        staged.extend(crate::stage_aov_pngs(output, passes)?);
        Ok(staged)
    }
}

/// The pass pictures `gridrt render` will write beside a PNG `output`.
pub(crate) fn pass_paths(output: &Path, aovs: Option<&AovList>) -> Vec<PathBuf> {
    match (aovs, crate::ImageFormat::from_path(output)) {
        (Some(AovList(list)), Ok(crate::ImageFormat::Png)) => list
            .iter()
            .map(|&a| crate::aov_png_path(output, a))
            .collect(),
        _ => Vec::new(),
    }
}

/// `--write-partial` and `--save-on-interrupt` of `gridrt render`.
#[derive(Debug, Clone, Copy, Args)]
pub struct PartialArgs {
    /// Write the image so far every SECONDS while rendering (atomically;
    /// tiles not yet rendered are black), for watching a long render.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub write_partial: Option<f64>,
    /// On Ctrl-C, write the image so far (instead of nothing) and list the
    /// missing tiles in OUT.missing, one X0,Y0,X1,Y1 per line, ready for
    /// `--crop`.
    #[arg(long)]
    pub save_on_interrupt: bool,
}

fn parse_seconds(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.1 => Ok(x),
        _ => Err(format!(
            "`{}` is not a number of seconds ≥ 0.1",
            s.escape_debug()
        )),
    }
}

/// Renders the whole frame, writing partial images every
/// `partial.write_partial` seconds while it runs (on a thread of its own).
pub(crate) fn render_watched(
    renderer: &Renderer,
    output: &Path,
    partial: PartialArgs,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
    live: &LiveImage,
) -> std::result::Result<(Framebuffer, RenderStats), Cancelled> {
    let Some(every) = partial.write_partial else {
        return renderer.render_live(progress, cancel, live);
    };
    let finished = AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let every = std::time::Duration::from_secs_f64(every);
            let mut last = std::time::Instant::now();
            let mut warned = false;
            while !finished.load(Ordering::SeqCst) {
                std::thread::sleep(std::time::Duration::from_millis(50));
                if last.elapsed() < every || finished.load(Ordering::SeqCst) {
                    continue;
                }
                last = std::time::Instant::now();
                if let Some(img) = live.snapshot() {
                    if let Err(e) = crate::write_framebuffer(output, &img) {
                        if !warned {
                            eprintln!("warning: partial image not written: {e}");
                            warned = true;
                        }
                    }
                }
            }
        });
        let out = renderer.render_live(progress, cancel, live);
        finished.store(true, Ordering::SeqCst);
        out
    })
}

/// After a Ctrl-C with `--save-on-interrupt`: writes the image so far to
/// `output` and the missing tiles to `OUTPUT.missing`, and returns the
/// error that says so.
pub(crate) fn save_interrupted(output: &Path, live: &LiveImage) -> Error {
    let Some(img) = live.snapshot() else {
        return Error::Cancelled;
    };
    let missing = live.missing();
    let list_path = missing_list_path(output);
    let list: String = missing
        .iter()
        .map(|r| format!("{},{},{},{}\n", r.x0, r.y0, r.x1, r.y1))
        .collect();
    let written = crate::stage_image(output, img.width, img.height, &img.pixels).and_then(|i| {
        let l = crate::stage(&list_path, |f| f.write_all(list.as_bytes()))?;
        i.commit()?;
        l.commit()
    });
    match written {
        Ok(()) => Error::Interrupted {
            note: format!(
                "wrote the image so far to {} ({} of {} tiles done; the missing ones, \
                 for --crop, are listed in {})",
                output.display(),
                live.tile_count() - missing.len(),
                live.tile_count(),
                list_path.display()
            ),
        },
        Err(e) => Error::Interrupted {
            note: format!("the image so far could not be saved: {e}"),
        },
    }
}

/// `out.png` → `out.png.missing`.
fn missing_list_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".missing");
    PathBuf::from(name)
}

impl PartArgs {
    /// The part asked for, if any.
    #[must_use]
    pub fn spec(&self) -> Option<PartSpec> {
        self.crop.or(self.tile)
    }
}

/// What `gridrt render` rendered.
pub(crate) enum Rendered {
    /// The whole frame.
    Full(Framebuffer),
    /// The whole frame as 8-bit sRGB, for a PNG.
    Srgb8(Srgb8Image),
    /// A part: its rectangles and their pixels.
    Part(Vec<PixelRect>, Vec<Framebuffer>),
}

/// Renders the rectangles of `spec`: one window for a crop, the strips of
/// a tile in one job.
pub(crate) fn render_part(
    renderer: &Renderer,
    spec: PartSpec,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> Result<std::result::Result<(Rendered, RenderStats), Cancelled>> {
    let (w, h) = renderer.size();
    let arg = if matches!(spec, PartSpec::Crop(_)) {
        "--crop"
    } else {
        "--tile"
    };
    let rects = spec.rects(w, h).map_err(|msg| Error::Arg {
        arg: arg.into(),
        msg,
    })?;
    if let [one] = rects[..] {
        return Ok(renderer
            .render_window(one, progress, cancel)
            .map(|(img, stats)| (Rendered::Part(rects, vec![img]), stats)));
    }
    // Strips of whole rows: one job, cut into the strips afterwards.
    let rows: Vec<u32> = rects.iter().flat_map(|r| r.y0..r.y1).collect();
    Ok(renderer
        .render_rows(&rows, progress, cancel)
        .map(|(img, stats)| {
            let mut images = Vec::with_capacity(rects.len());
            let mut start = 0;
            for r in &rects {
                let n = r.width() as usize * r.height() as usize;
                images.push(Framebuffer {
                    width: r.width(),
                    height: r.height(),
                    pixels: img.pixels[start..start + n].to_vec(),
                });
                start += n;
            }
            (Rendered::Part(rects, images), stats)
        }))
}

/// `gridrt merge`.
pub(crate) fn merge(a: &MergeArgs, out: &mut dyn Write) -> Result<()> {
    crate::check_image_path(&a.output)?;
    crate::cli::check_outputs(&[("-o", a.output.as_path())], &a.parts)?;
    let image = merge_parts(&a.parts)?;
    crate::write_framebuffer(&a.output, &image)?;
    let _ = writeln!(
        out,
        "merged {} parts into {} ({} x {})",
        a.parts.len(),
        a.output.display(),
        image.width,
        image.height
    );
    Ok(())
}

/// `gridrt diff`: prints the numbers; an error (exit 1) when any pixel
/// differs, like `cmp`.
pub(crate) fn diff(a: &DiffArgs, out: &mut dyn Write) -> Result<()> {
    if let Some(o) = &a.output {
        crate::check_image_path(o)?;
        crate::cli::check_outputs(&[("-o", o.as_path())], &[a.a.clone(), a.b.clone()])?;
    }
    let (d, diff_image) = diff_files(&a.a, &a.b, a.threshold)?;
    let unit = match diff_image.kind {
        ImageValues::Srgb8 => "8-bit steps",
        ImageValues::Linear => "linear",
    };
    let pct = |n: usize| 100.0 * n as f64 / d.pixels.max(1) as f64;
    let _ = write!(
        out,
        "{} vs {}: {} x {}, {}\n\
         pixels differing  {} of {} ({:.4}%)\n\
         over threshold    {} ({:.4}%, a channel differs by more than {})\n\
         mean abs error    {:.6} ({unit})\n\
         RMSE              {:.6} ({unit})\n\
         max difference    {} ({unit})\n",
        a.a.display(),
        a.b.display(),
        diff_image.width,
        diff_image.height,
        kind_name(diff_image.kind),
        d.pixels_differing,
        d.pixels,
        pct(d.pixels_differing),
        d.pixels_over,
        pct(d.pixels_over),
        a.threshold,
        d.mean_abs,
        d.rmse,
        d.max,
    );
    if let Some(o) = &a.output {
        write_diff_image(o, &diff_image, a.gain)?;
    }
    if d.pixels_differing > 0 {
        return Err(Error::Images {
            path: a.b.clone(),
            msg: format!(
                "differs from {} in {} pixels",
                a.a.display(),
                d.pixels_differing
            ),
        });
    }
    Ok(())
}
