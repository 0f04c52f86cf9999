//! The `gridrt` command-line renderer.
fn main() {
    eprintln!("gridrt: the renderer is not built yet (see the open issues)");
    std::process::exit(2);
}
