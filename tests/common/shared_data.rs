//! Where the shared DAVIS240C recording lives: `shared/data/davis240` beside the workspace (it
//! is not part of the repository). The one lookup of it, included with `#[path]` by every test
//! and bench that reads it (the facade's tests and benches, `sensor/tests`,
//! `experiments/tests`), so each reports its absence the same way.

use std::path::{Path, PathBuf};

/// `<workspace>/../shared/data/davis240`, or `None` (with the reason printed) when it is absent.
#[allow(dead_code)] // some includers only use `davis240_file`
pub fn davis240_dir() -> Option<PathBuf> {
    // The including crate's folder, up to the workspace root (the folder of `Cargo.lock`).
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = crate_dir
        .ancestors()
        .find(|d| d.join("Cargo.lock").is_file())
        .unwrap_or(crate_dir);
    let dir = root.join("../shared/data/davis240");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared DAVIS240C recording is not part of the repository)",
            dir.display()
        );
        None
    }
}

/// The file `name` of the recording's folder, or `None` (with the reason printed).
#[allow(dead_code)] // some includers only use `davis240_dir`
pub fn davis240_file(name: &str) -> Option<PathBuf> {
    let path = davis240_dir()?.join(name);
    if path.is_file() {
        Some(path)
    } else {
        eprintln!("skipping: {} is absent", path.display());
        None
    }
}
