//! What a scene may read, and how much: the file-access policy and the
//! budgets that keep a hostile scene from reading files outside its folders,
//! hanging on a FIFO or exhausting memory.
//!
//! # File access
//! Every file a scene names, transitively (a `Mesh(file: …)`, an OBJ's
//! `mtllib`, a glTF buffer `uri`), is resolved here before anything touches
//! it:
//!
//! 1. the reference is decoded (glTF URIs are percent-decoded, `file:` URIs
//!    stripped) and joined to the folder of the file that names it;
//! 2. `.` and `..` are resolved lexically, and the result must lie under an
//!    allowed folder; otherwise the reference is refused *before* the file
//!    system is asked anything about it, so the refusal is the same whether
//!    the target exists or not and reveals nothing about it;
//! 3. the path is walked component by component; every symbolic link met is
//!    replaced by its target and the whole check starts again, so a link
//!    inside an allowed folder that points out of it is refused the same way;
//! 4. the file is opened without following a final link and without
//!    blocking (a FIFO cannot hang the open), and must be a regular file
//!    (checked on the open descriptor) no larger than the size limit.
//!
//! The allowed folders of a scene are its [`Sandbox`]'s roots; a model file
//! (OBJ, glTF) reads only from its own folder and the folders added
//! explicitly ([`Sandbox::allow`], `--allow-path`), never from the scene's
//! other roots.
//!
//! # Budgets
//! [`Limits`] caps the size of each file read, the primitives a scene
//! expands to (spheres, boxes, planes and triangles, counted before they
//! are allocated) and the nodes a glTF node graph expands to (counted with
//! memoisation before it is walked, so a graph whose children repeat cannot
//! run for 2^40 steps).

use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Most symbolic links followed while resolving one reference.
const MAX_LINKS: usize = 40;

/// Budgets of one load: each is named in the error that reports it, with
/// the command-line flag that raises it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest file read, in bytes (`--max-file-size`).
    pub max_file_bytes: u64,
    /// Most primitives (spheres, boxes, planes, triangles) a scene or model
    /// may expand to (`--max-primitives`).
    pub max_primitives: u64,
    /// Most nodes a glTF node graph may expand to, counting a node once for
    /// every path from a root to it (`--max-nodes`).
    pub max_nodes: u64,
}

impl Default for Limits {
    /// 1 GiB per file, 10 million primitives, 1 million expanded glTF nodes:
    /// every model in the project's test set is far below each (the
    /// largest has under a million triangles), and a scene at the
    /// primitive limit needs one to two GiB to render.
    fn default() -> Self {
        Self {
            max_file_bytes: 1 << 30,
            max_primitives: 10_000_000,
            max_nodes: 1_000_000,
        }
    }
}

impl Limits {
    /// The error for `what` (e.g. "12000000 triangles") over the primitive
    /// budget, reported against `file`.
    pub(crate) fn primitives_error(&self, file: &Path, place: &str, total: u64) -> Error {
        Error::Limit {
            path: file.to_path_buf(),
            place: place.to_string(),
            msg: format!(
                "the scene expands to at least {total} primitives, over the limit of {}: raise it with --max-primitives N if the machine has the memory",
                self.max_primitives
            ),
        }
    }
}

/// Which folders a load may read from, and its [`Limits`].
///
/// ```
/// use gridrt_io::Sandbox;
/// // A render service confines a job to its upload folder:
/// let dir = std::env::temp_dir();
/// let sandbox = Sandbox::confined(&[dir.as_path()]).unwrap();
/// assert_eq!(sandbox.roots().len(), 1);
/// ```
#[derive(Clone, Debug)]
pub struct Sandbox {
    /// Folders any scene file may read from (canonical).
    roots: Vec<PathBuf>,
    /// Folders added explicitly (canonical): the only ones a model file may
    /// read from besides its own folder.
    allowed: Vec<PathBuf>,
    /// The budgets.
    pub limits: Limits,
    /// Every file read through this sandbox (shared by its clones).
    read_log: Arc<Mutex<Vec<PathBuf>>>,
}

impl Sandbox {
    /// The command line's default for the input `file`: its folder (after
    /// resolving links) and the current working directory.
    #[must_use]
    pub fn for_input(file: &Path) -> Self {
        let mut s = Self::working_directory();
        if let Some(dir) = canonical(file).parent() {
            s.roots.insert(0, dir.to_path_buf());
        }
        s
    }

    /// Only the current working directory (the built-in scene names no
    /// files; this is what it gets).
    #[must_use]
    pub fn working_directory() -> Self {
        Self {
            roots: std::env::current_dir()
                .and_then(std::fs::canonicalize)
                .into_iter()
                .collect(),
            allowed: Vec::new(),
            limits: Limits::default(),
            read_log: Arc::default(),
        }
    }

    /// Only the given folders (and a model's own folder for the files the
    /// model names): what a service uses to confine a job.
    ///
    /// # Errors
    /// [`Error::Arg`] when a folder does not exist or is not a folder.
    pub fn confined(dirs: &[&Path]) -> Result<Self> {
        let mut s = Self {
            roots: Vec::new(),
            allowed: Vec::new(),
            limits: Limits::default(),
            read_log: Arc::default(),
        };
        for d in dirs {
            s.allow(d)?;
        }
        Ok(s)
    }

    /// Adds a folder every file of the load may read from (`--allow-path`).
    ///
    /// # Errors
    /// [`Error::Arg`] when `dir` does not exist or is not a folder.
    pub fn allow(&mut self, dir: &Path) -> Result<()> {
        let canon = std::fs::canonicalize(dir)
            .map_err(|e| Error::arg("--allow-path", format!("{}: {e}", dir.display())))?;
        if !canon.is_dir() {
            return Err(Error::arg(
                "--allow-path",
                format!("{}: not a folder", dir.display()),
            ));
        }
        self.roots.push(canon.clone());
        self.allowed.push(canon);
        Ok(())
    }

    /// Every file read (or tried) through this sandbox so far: the inputs an
    /// output must not replace.
    #[must_use]
    pub fn files_read(&self) -> Vec<PathBuf> {
        self.read_log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// The folders a scene file may read from.
    #[must_use]
    pub fn roots(&self) -> &[PathBuf] {
        &self.roots
    }

    /// The canonical path of an input named directly (on the command line,
    /// or by a service), which must lie under one of the roots: a symbolic
    /// link in an upload folder cannot make the job read outside it.
    ///
    /// # Errors
    /// [`Error::Denied`] when the resolved path is outside every root.
    pub(crate) fn top_level(&self, path: &Path) -> Result<PathBuf> {
        let real = canonical(path);
        if self.roots.iter().any(|r| real.starts_with(r)) {
            Ok(real)
        } else {
            Err(Error::Denied {
                path: path.to_path_buf(),
                place: String::new(),
                reference: path.display().to_string(),
                model: false,
            })
        }
    }

    /// Resolves `reference`, named by the file `from` (a canonical path), for
    /// a scene (`model == false`: any root) or a model file (`model ==
    /// true`: `from`'s folder and the explicitly allowed folders). Returns
    /// the canonical path of a regular file, ready for [`Sandbox::read`].
    ///
    /// # Errors
    /// [`Error::Denied`] when the reference leads outside the allowed
    /// folders (the same error whether the target exists or not),
    /// [`Error::Read`] when an allowed path cannot be resolved.
    pub(crate) fn resolve(&self, from: &Path, reference: &Path, model: bool) -> Result<PathBuf> {
        let base = from.parent().unwrap_or_else(|| Path::new("/"));
        let scope: Vec<&Path> = if model {
            std::iter::once(base)
                .chain(self.allowed.iter().map(PathBuf::as_path))
                .collect()
        } else {
            self.roots.iter().map(PathBuf::as_path).collect()
        };
        let denied = || Error::Denied {
            path: from.to_path_buf(),
            place: String::new(),
            reference: reference.display().to_string(),
            model,
        };
        let inside = |p: &Path| scope.iter().any(|r| p.starts_with(r));
        let mut path = normalize(&base.join(reference));
        let mut links = 0;
        'restart: loop {
            if !inside(&path) {
                return Err(denied());
            }
            let mut done = PathBuf::from("/");
            let parts: Vec<Component> = path.components().collect();
            for (k, c) in parts.iter().enumerate() {
                let Component::Normal(name) = c else { continue };
                let next = done.join(name);
                let meta = std::fs::symlink_metadata(&next).map_err(|e| Error::read(&next, e))?;
                if meta.file_type().is_symlink() {
                    links += 1;
                    if links > MAX_LINKS {
                        return Err(Error::read(
                            &next,
                            std::io::Error::other("too many levels of symbolic links"),
                        ));
                    }
                    let target = std::fs::read_link(&next).map_err(|e| Error::read(&next, e))?;
                    let mut rest = done.join(target);
                    for c in &parts[k + 1..] {
                        rest.push(c.as_os_str());
                    }
                    path = normalize(&rest);
                    continue 'restart;
                }
                done = next;
            }
            return Ok(done);
        }
    }

    /// Reads a whole file that `Sandbox::resolve` returned, or the file
    /// named on the command line: it must be a regular file (a FIFO, a
    /// device or a folder is refused without blocking) within the size
    /// limit.
    ///
    /// # Errors
    /// [`Error::Read`], [`Error::NotRegular`], [`Error::Limit`].
    pub fn read(&self, path: &Path) -> Result<Vec<u8>> {
        if let Ok(mut log) = self.read_log.lock() {
            log.push(path.to_path_buf());
        }
        let file = open_regular(path)?;
        let meta = file.metadata().map_err(|e| Error::read(path, e))?;
        if !meta.is_file() {
            return Err(not_regular(path, &meta));
        }
        let limit = self.limits.max_file_bytes;
        if meta.len() > limit {
            return Err(self.size_error(path, meta.len()));
        }
        let mut bytes = Vec::with_capacity(meta.len() as usize);
        // A file growing while read is cut at the limit and reported.
        file.take(limit.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|e| Error::read(path, e))?;
        if bytes.len() as u64 > limit {
            return Err(self.size_error(path, bytes.len() as u64));
        }
        Ok(bytes)
    }

    fn size_error(&self, path: &Path, size: u64) -> Error {
        Error::Limit {
            path: path.to_path_buf(),
            place: String::new(),
            msg: format!(
                "the file is {size} bytes, over the limit of {} bytes: raise it with --max-file-size BYTES",
                self.limits.max_file_bytes
            ),
        }
    }
}

/// `path` with links resolved, or, when it does not exist, its folder
/// resolved and its name kept, or else `path` made absolute lexically.
pub(crate) fn canonical(path: &Path) -> PathBuf {
    if let Ok(c) = std::fs::canonicalize(path) {
        return c;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match (std::fs::canonicalize(dir), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => normalize(path),
    }
}

/// The error for a path that is not a regular file, saying what it is.
fn not_regular(path: &Path, meta: &std::fs::Metadata) -> Error {
    let t = meta.file_type();
    let mut kind = if t.is_dir() {
        "a folder"
    } else {
        "a special file"
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            kind = "a FIFO";
        } else if t.is_char_device() || t.is_block_device() {
            kind = "a device";
        } else if t.is_socket() {
            kind = "a socket";
        }
    }
    Error::NotRegular {
        path: path.to_path_buf(),
        kind,
    }
}

/// Opens `path` for reading without blocking on a FIFO and, on Unix,
/// without following a final symbolic link; a folder is refused.
fn open_regular(path: &Path) -> Result<std::fs::File> {
    // Refuse a device or FIFO before opening it: opening some devices has
    // effects of its own.
    let meta = std::fs::metadata(path).map_err(|e| Error::read(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, &meta));
    }
    let mut opts = std::fs::OpenOptions::new();
    opts.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        opts.custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY | libc::O_NOFOLLOW);
    }
    let file = opts.open(path).map_err(|e| Error::read(path, e))?;
    let meta = file.metadata().map_err(|e| Error::read(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, &meta));
    }
    #[cfg(unix)]
    {
        // Back to blocking reads for the regular file.
        use std::os::fd::AsRawFd;
        let fd = file.as_raw_fd();
        // SAFETY: `fd` is a descriptor this function owns through `file`;
        // fcntl with F_GETFL/F_SETFL reads and sets its status flags only.
        unsafe {
            let flags = libc::fcntl(fd, libc::F_GETFL);
            if flags >= 0 {
                libc::fcntl(fd, libc::F_SETFL, flags & !libc::O_NONBLOCK);
            }
        }
    }
    Ok(file)
}

/// `path` with `.` and `..` resolved lexically (`..` at the root stays at
/// the root), made absolute against the working directory.
fn normalize(path: &Path) -> PathBuf {
    let abs;
    let path = if path.is_absolute() {
        path
    } else {
        abs = std::env::current_dir()
            .unwrap_or_else(|_| PathBuf::from("/"))
            .join(path);
        &abs
    };
    let mut out = PathBuf::from("/");
    for c in path.components() {
        match c {
            Component::Prefix(p) => out.push(p.as_os_str()),
            Component::RootDir => out.push(Component::RootDir.as_os_str()),
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            Component::Normal(n) => out.push(n),
        }
    }
    out
}

/// A glTF `uri` as a relative or absolute path: percent-decoded, a `file:`
/// scheme removed. `None` for another scheme (`http:` …).
pub(crate) fn uri_path(uri: &str) -> std::result::Result<PathBuf, String> {
    let rest = match uri.get(..5) {
        Some(s) if s.eq_ignore_ascii_case("file:") => {
            let r = &uri[5..];
            // file:///abs and file:/abs are absolute; file://host/… names a host.
            match r.strip_prefix("//") {
                Some(after) if after.starts_with('/') => after,
                Some(_) => return Err("a file: URI with a host name is not supported".into()),
                None => r,
            }
        }
        _ => {
            let scheme = uri
                .find(':')
                .filter(|&i| {
                    i > 1
                        && uri[..i]
                            .chars()
                            .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
                })
                .map(|i| &uri[..i]);
            if let Some(s) = scheme {
                return Err(format!(
                    "a {s}: URI is not a file: download it beside the .gltf and refer to it by a relative path"
                ));
            }
            uri
        }
    };
    let text = crate::model::base64::percent_decode(rest)?;
    if text.contains('\0') {
        return Err("the URI contains a NUL byte".into());
    }
    Ok(PathBuf::from(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_is_lexical() {
        assert_eq!(normalize(Path::new("/a/b/../c/./d")), Path::new("/a/c/d"));
        assert_eq!(normalize(Path::new("/../../x")), Path::new("/x"));
    }

    #[test]
    fn uris_decode_before_the_check() {
        assert_eq!(uri_path("%2E%2E/x.bin").unwrap(), Path::new("../x.bin"));
        assert_eq!(
            uri_path("file:///etc/passwd").unwrap(),
            Path::new("/etc/passwd")
        );
        assert_eq!(
            uri_path("FILE:/etc/passwd").unwrap(),
            Path::new("/etc/passwd")
        );
        assert!(uri_path("http://x/y.bin").is_err());
        assert!(uri_path("a%00b").is_err());
        assert_eq!(uri_path("a b.bin").unwrap(), Path::new("a b.bin"));
    }

    #[test]
    fn references_stay_inside() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        let inner = root.join("in");
        std::fs::create_dir(&inner).unwrap();
        std::fs::write(inner.join("a.obj"), "x").unwrap();
        std::fs::write(root.join("secret.txt"), "s").unwrap();
        let sb = Sandbox::confined(&[inner.as_path()]).unwrap();
        let from = inner.join("scene.ron");
        assert_eq!(
            sb.resolve(&from, Path::new("a.obj"), false).unwrap(),
            inner.join("a.obj")
        );
        for bad in [
            "../secret.txt",
            "../nothing.txt",
            "/etc/passwd",
            "sub/../../secret.txt",
        ] {
            let e = sb.resolve(&from, Path::new(bad), false).unwrap_err();
            assert!(matches!(e, Error::Denied { .. }), "{bad}: {e}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(root.join("secret.txt"), inner.join("link.obj")).unwrap();
            std::os::unix::fs::symlink("/nonexistent-gridrt", inner.join("dangling.obj")).unwrap();
            for bad in ["link.obj", "dangling.obj"] {
                let e = sb.resolve(&from, Path::new(bad), false).unwrap_err();
                assert!(matches!(e, Error::Denied { .. }), "{bad}: {e}");
            }
        }
    }

    #[test]
    fn a_confined_job_cannot_start_outside() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        let job = root.join("job");
        std::fs::create_dir(&job).unwrap();
        std::fs::write(root.join("other.ron"), "()").unwrap();
        let sb = Sandbox::confined(&[job.as_path()]).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(root.join("other.ron"), job.join("s.ron")).unwrap();
            let e = crate::load_scene_in(&job.join("s.ron"), &sb).unwrap_err();
            assert!(matches!(e, Error::Denied { .. }), "{e}");
        }
        let e = crate::load_scene_in(&root.join("other.ron"), &sb).unwrap_err();
        assert!(matches!(e, Error::Denied { .. }), "{e}");
    }

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let mut sb = Sandbox::confined(&[dir.path()]).unwrap();
        let f = dir.path().join("f.txt");
        std::fs::write(&f, "12345").unwrap();
        assert_eq!(sb.read(&f).unwrap(), b"12345");
        sb.limits.max_file_bytes = 4;
        let e = sb.read(&f).unwrap_err().to_string();
        assert!(e.contains("--max-file-size"), "{e}");
        let e = sb.read(dir.path()).unwrap_err();
        assert!(
            matches!(e, Error::NotRegular { .. } | Error::Read { .. }),
            "{e}"
        );
        #[cfg(unix)]
        {
            let e = sb.read(Path::new("/dev/zero")).unwrap_err();
            assert!(matches!(e, Error::NotRegular { .. }), "{e}");
        }
    }
}
