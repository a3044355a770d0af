//! The guide's commands, run as a reader runs them: every `sh run` block of README.md and of
//! the book, page by page in a fresh folder from a clone's point of view (`examples/` is
//! there, `neurotac` is this build's binary), each block as one `sh -e` script after the
//! blocks before it. Pages with `python run` blocks are run by python/tests/test_guide.py
//! instead, where the Python package is installed.

mod guide_pages;

use guide_pages::{Block, blocks, pages, read, root, shown};
use std::path::Path;
use std::process::Command;

/// The `sh run` blocks of `page`, or none when the page has Python to run too.
fn shell_blocks(page: &Path) -> Vec<Block> {
    let all = blocks(&read(page));
    if all.iter().any(|b| b.language == "python" && b.has("run")) {
        return Vec::new();
    }
    all.into_iter()
        .filter(|b| b.language == "sh" && b.has("run"))
        .collect()
}

/// Runs the shell blocks of the pages whose path (from the repository's root) starts with one
/// of `prefixes`, each page in its own folder; the cache of simulated datasets is shared.
fn run_pages(prefixes: &[&str]) {
    let cache = std::env::temp_dir().join("neurotac-guide-cache");
    let bin = tempfile::tempdir().unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_neurotac"), bin.path().join("neurotac"))
        .unwrap();
    let path = format!(
        "{}:{}",
        bin.path().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    for page in pages() {
        let name = shown(&page);
        if !prefixes.iter().any(|p| name.starts_with(p)) {
            continue;
        }
        let dir = tempfile::tempdir().unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(root().join("examples"), dir.path().join("examples")).unwrap();
        for block in shell_blocks(&page) {
            let out = Command::new("sh")
                .arg("-e")
                .arg("-c")
                .arg(&block.text)
                .current_dir(dir.path())
                .env("PATH", &path)
                .env("NEUROTAC_CACHE", &cache)
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{name}:{}: the block failed:\n{}\n--- stderr:\n{}",
                block.line,
                block.text,
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
        }
    }
    println!("ran {ran} blocks of {prefixes:?}");
}

#[test]
fn the_front_page_and_getting_started_run_from_a_clone() {
    run_pages(&[
        "README.md",
        "docs/getting-started.md",
        "docs/introduction.md",
    ]);
}

#[test]
fn the_tutorials_run_from_a_clone() {
    run_pages(&["docs/tutorials/"]);
}

#[test]
fn the_how_to_guides_and_reference_run_from_a_clone() {
    run_pages(&[
        "docs/how-to/",
        "docs/reference/",
        "docs/measurements.md",
        "docs/gallery.md",
    ]);
}
