//! The one error type of gridrt-io.

use std::fmt;
use std::path::{Path, PathBuf};

/// Everything that can go wrong reading scenes, meshes and ray files, or
/// writing images and reports.
///
/// Every message names the file and, where there is one, the place in it
/// (RON `line:column`, OBJ line, glTF node and primitive, CSV line) and says
/// what to fix. The `gridrt` binary prints it as one line `error: …`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be opened or read: it does not exist, is not
    /// readable, or is a directory. Fix the path; paths inside a scene file
    /// are relative to the scene file's directory.
    #[error("{}: cannot read the file: {}", .path.display(), io_message(.source))]
    Read {
        /// The file, as it was resolved.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },

    /// A file names another file outside the folders it may read (see
    /// [`Sandbox`](crate::Sandbox)). The message names the reference as
    /// written and the flag that allows it, and says nothing about the
    /// target (not whether it exists).
    #[error(
        "{}{}: \"{reference}\" is outside the folders {} may read ({}): allow its folder with --allow-path DIR",
        .path.display(),
        Place(.place),
        if *.model { "a model file" } else { "the scene" },
        if *.model {
            "its own folder and --allow-path folders"
        } else {
            "the input's folder, the working directory and --allow-path folders"
        }
    )]
    Denied {
        /// The file that holds the reference.
        path: PathBuf,
        /// Where in it, or empty.
        place: String,
        /// The reference as written (decoded).
        reference: String,
        /// True when the reference is in a model file (OBJ, glTF).
        model: bool,
    },

    /// An input is not a regular file (a FIFO, a device, a folder): gridrt
    /// reads regular files only, so it cannot hang or read without end.
    #[error("{}: is {kind}, not a regular file: give a regular file", .path.display())]
    NotRegular {
        /// The file.
        path: PathBuf,
        /// What it is instead: `a folder`, `a FIFO`, `a device`, …
        kind: &'static str,
    },

    /// A budget of [`Limits`](crate::Limits) was exceeded: a file too
    /// large, a scene expanding to too many primitives or glTF nodes. The
    /// message names the limit and the flag that raises it.
    #[error("{}{}: {msg}", .path.display(), Place(.place))]
    Limit {
        /// The file.
        path: PathBuf,
        /// Where in it, or empty.
        place: String,
        /// The limit and the flag that raises it.
        msg: String,
    },

    /// A RON scene file is not well formed or does not follow the scene
    /// schema (syntax error, unknown or missing field, wrong type, a value
    /// out of range). See `docs/scene-format.md`.
    #[error("{}:{line}:{col}: {msg}", .path.display())]
    Ron {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
        /// What is wrong and what to write instead.
        msg: String,
    },

    /// A scene is well formed but its content is invalid: a reference to an
    /// undefined material, a degenerate camera, a mesh override naming a
    /// material the mesh does not have, an empty scene.
    #[error("{}{}: {msg}", .path.display(), Place(.place))]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// Where: `line:col` when it could be found, then the element
        /// (`objects[2]`, `camera`), or empty.
        place: String,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// A mesh file named by a scene could not be loaded; the inner error
    /// names the mesh file and the place in it, this one the scene and the
    /// object that refers to it.
    #[error("{}{}: {source}", .scene.display(), Place(.place))]
    Mesh {
        /// The scene file.
        scene: PathBuf,
        /// Where in the scene (`line:col: objects[3]`).
        place: String,
        /// Why the mesh could not be loaded.
        #[source]
        source: Box<Error>,
    },

    /// An OBJ or MTL file is malformed: an unparsable or non-finite number,
    /// a face index out of range, an empty mesh.
    #[error("{}{}: {msg}", .path.display(), Line(*.line))]
    Obj {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line, when known.
        line: Option<usize>,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// A texture image cannot be decoded (not a PNG, JPEG, HDR or EXR
    /// image, truncated, too large) or a texture reference is invalid.
    /// `path` is the image file, or the model file for an embedded image;
    /// `place` names the image and the material that uses it.
    #[error("{}{}: {msg}", .path.display(), Place(.place))]
    Texture {
        /// The image file, or the model that embeds the image.
        path: PathBuf,
        /// Which image and material, or empty.
        place: String,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// A glTF file is malformed or uses something gridrt does not support:
    /// invalid JSON, a missing or short buffer, an accessor out of bounds,
    /// non-finite positions, no meshes.
    #[error("{}{}: {msg}", .path.display(), Place(.place))]
    Gltf {
        /// The `.gltf` or `.glb` file.
        path: PathBuf,
        /// Where: `node 3 "wheel", mesh 1, primitive 0`, `buffer 0`, or empty.
        place: String,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// A PLY file is malformed: a bad header, a payload shorter than the
    /// header says, a non-finite vertex, a face index out of range, no
    /// `vertex` element with `x`, `y`, `z` or no faces.
    #[error("{}{}: {msg}", .path.display(), Place(.place))]
    Ply {
        /// The `.ply` file.
        path: PathBuf,
        /// Where: `line 12` (header, ASCII payload), `vertex 7`, `face 3`, or empty.
        place: String,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// A line of a rays CSV file is not `ox,oy,oz,dx,dy,dz[,tmin,tmax]`.
    #[error("{}:{line}: {msg}", .path.display())]
    Rays {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// An input file that is not a scene or model gridrt reads, judged by
    /// its extension: a material library, a glTF buffer, a texture, a
    /// licence file, a mesh format gridrt does not read (STL, FBX, …). Give
    /// a `.ron` scene or an `.obj`, `.ply`, `.gltf` or `.glb` model instead
    /// (`gridrt rays` takes models only); the message says what the file probably is.
    #[error(
        "{}: not a {} gridrt supports{}; {}",
        .path.display(),
        if *.models_only { "mesh" } else { "scene" },
        ext_note(.path),
        if *.models_only {
            "use an .obj, .ply, .gltf or .glb model"
        } else {
            "use a .ron scene, or an .obj, .ply, .gltf or .glb model"
        }
    )]
    UnsupportedInput {
        /// The file.
        path: PathBuf,
        /// True where only models are accepted (`gridrt rays`), not scenes.
        models_only: bool,
    },

    /// An output path that cannot be used: unknown extension, a directory
    /// that does not exist. Checked before rendering.
    #[error("{}: {msg}", .path.display())]
    Output {
        /// The output path as given.
        path: PathBuf,
        /// What is wrong and how to fix it.
        msg: String,
    },

    /// Writing an output file failed (disk full, no permission). The target
    /// is left as it was: output goes to a temporary file that is renamed
    /// into place only once complete.
    #[error("{}: cannot write: {}", .path.display(), io_message(.source))]
    Write {
        /// The output path.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },

    /// A command-line value is out of range (`--spp 0`, `--width 100000`).
    #[error("{arg}: {msg}")]
    Arg {
        /// The option, e.g. `--spp`.
        arg: String,
        /// What is wrong and what is allowed.
        msg: String,
    },

    /// The renderer rejected the scene (the tracer's own validation).
    #[error("{}: {msg}", .path.display())]
    Render {
        /// The scene file.
        path: PathBuf,
        /// The renderer's message.
        msg: String,
    },

    /// Parts of a frame cannot be merged, or two images cannot be compared:
    /// a file that is not a part, parts of different renders, overlapping
    /// parts or missing pixels, images of different sizes. The message
    /// names the file and says which.
    #[error("{}: {msg}", .path.display())]
    Images {
        /// The part or image at fault.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },

    /// The render was cancelled (Ctrl-C) before its image was written;
    /// nothing was written and existing files were left as they were. The
    /// binary prints this message without the `error: ` prefix and exits
    /// with 130, as a shell does for a command stopped by Ctrl-C.
    #[error("interrupted; nothing written")]
    Cancelled,

    /// The render was cancelled (Ctrl-C) with `--save-on-interrupt`: the
    /// image so far was written and the missing tiles listed beside it. The
    /// binary prints the message without `error: ` and exits with 130.
    #[error("interrupted; {note}")]
    Interrupted {
        /// What was saved where, and what is missing.
        note: String,
    },
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// A [`Error::Read`] for `path`.
    pub(crate) fn read(path: &Path, source: std::io::Error) -> Self {
        Self::Read {
            path: path.to_path_buf(),
            source,
        }
    }

    /// The error with `from` (a resolved path) shown as `to` (the path as
    /// the user wrote it) where it names the file itself.
    pub(crate) fn renamed(self, from: &Path, to: &Path) -> Self {
        let fix = |p: PathBuf| if p == from { to.to_path_buf() } else { p };
        match self {
            Self::Read { path, source } => Self::Read {
                path: fix(path),
                source,
            },
            Self::NotRegular { path, kind } => Self::NotRegular {
                path: fix(path),
                kind,
            },
            Self::Denied {
                path,
                place,
                reference,
                model,
            } => Self::Denied {
                path: fix(path),
                place,
                reference,
                model,
            },
            Self::Limit { path, place, msg } => Self::Limit {
                path: fix(path),
                place,
                msg,
            },
            other => other,
        }
    }

    /// A [`Error::Scene`] with a place.
    pub(crate) fn scene(path: &Path, place: impl Into<String>, msg: impl Into<String>) -> Self {
        Self::Scene {
            path: path.to_path_buf(),
            place: place.into(),
            msg: msg.into(),
        }
    }

    /// A [`Error::Obj`].
    pub(crate) fn obj(path: &Path, line: Option<usize>, msg: impl Into<String>) -> Self {
        Self::Obj {
            path: path.to_path_buf(),
            line,
            msg: msg.into(),
        }
    }

    /// A [`Error::Ply`].
    pub(crate) fn ply(path: &Path, place: impl Into<String>, msg: impl Into<String>) -> Self {
        Self::Ply {
            path: path.to_path_buf(),
            place: place.into(),
            msg: msg.into(),
        }
    }

    /// A [`Error::Gltf`].
    pub(crate) fn gltf(path: &Path, place: impl Into<String>, msg: impl Into<String>) -> Self {
        Self::Gltf {
            path: path.to_path_buf(),
            place: place.into(),
            msg: msg.into(),
        }
    }

    /// A [`Error::Output`].
    pub(crate) fn output(path: &Path, msg: impl Into<String>) -> Self {
        Self::Output {
            path: path.to_path_buf(),
            msg: msg.into(),
        }
    }

    /// A [`Error::Arg`].
    pub(crate) fn arg(arg: &str, msg: impl Into<String>) -> Self {
        Self::Arg {
            arg: arg.to_string(),
            msg: msg.into(),
        }
    }
}

/// `text` with control characters (newlines, escapes, DEL, C1) written
/// as `\n`, `\u{1b}`, …, so a name in a message cannot move the cursor or
/// forge a line. The `gridrt` binary prints every message through it.
///
/// ```
/// assert_eq!(gridrt_io::escape_control("a\nb\u{1b}[2J"), "a\\nb\\u{1b}[2J");
/// ```
#[must_use]
pub fn escape_control(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// An I/O error as a short sentence, with a hint for the common cases.
fn io_message(e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    let hint = match e.kind() {
        ErrorKind::NotFound => " (check the path; paths in a scene are relative to the scene file)",
        ErrorKind::PermissionDenied => " (check the file's permissions)",
        _ => "",
    };
    format!("{e}{hint}")
}

/// The extension of `path`, quoted, and what a file with it probably is,
/// for the unsupported-file message.
fn ext_note(path: &Path) -> String {
    let Some(ext) = path.extension() else {
        return " (the file has no extension)".to_string();
    };
    let ext = ext.to_string_lossy();
    let what = match ext.to_ascii_lowercase().as_str() {
        "mtl" => ": it is an OBJ material library, give the .obj that uses it",
        "bin" => ": it is probably a glTF buffer, give the .gltf that refers to it",
        "png" | "jpg" | "jpeg" | "ktx2" | "webp" | "exr" | "hdr" | "tga" | "bmp" => {
            ": it is an image, a texture or a render"
        }
        "stl" | "fbx" | "dae" | "3ds" | "blend" | "usd" | "usda" | "usdc" | "usdz"
        | "off" | "x3d" | "wrl" | "abc" => {
            ": gridrt does not read this mesh format, convert it to OBJ, PLY or glTF (Blender, MeshLab)"
        }
        "txt" | "md" | "license" | "licence" => ": it is a text file",
        "ron" => ": it is a scene file, which holds no mesh of its own",
        _ => "",
    };
    format!(" (\".{ext}\"{what})")
}

/// Formats a place after a path: `:12:5: objects[2]` stays glued to the
/// path, a named place gets `: ` first, and an empty place disappears.
struct Place<'a>(&'a String);

impl fmt::Display for Place<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.0.as_str();
        if p.is_empty() {
            Ok(())
        } else if p.starts_with(|c: char| c.is_ascii_digit()) {
            write!(f, ":{p}")
        } else {
            write!(f, ": {p}")
        }
    }
}

/// Formats an optional line number after a path.
struct Line(Option<usize>);

impl fmt::Display for Line {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(l) => write!(f, ":{l}"),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_join_the_path() {
        let p = Path::new("a.ron");
        assert_eq!(
            Error::scene(p, "3:4: objects[1]", "bad").to_string(),
            "a.ron:3:4: objects[1]: bad"
        );
        assert_eq!(
            Error::scene(p, "camera", "bad").to_string(),
            "a.ron: camera: bad"
        );
        assert_eq!(Error::scene(p, "", "bad").to_string(), "a.ron: bad");
        assert_eq!(Error::obj(p, Some(7), "bad").to_string(), "a.ron:7: bad");
        assert_eq!(Error::obj(p, None, "bad").to_string(), "a.ron: bad");
    }

    #[test]
    fn not_found_says_what_to_check() {
        let e = Error::read(
            Path::new("x.obj"),
            std::io::Error::from(std::io::ErrorKind::NotFound),
        );
        assert!(e.to_string().contains("check the path"), "{e}");
    }
}
