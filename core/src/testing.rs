//! Test support shared by the tests of every crate (hidden from the documentation): where the
//! shared data lives, and what a test does when it is absent; what a folder holds.
//!
//! The real recordings (`../shared/data/…` beside the repository, or the folder named by the
//! environment variable `NEUROTAC_SHARED_DATA`) are not part of the repository. A test that
//! needs them calls [`shared_data`]: when the folder is absent the test prints why it skips and
//! returns — unless the environment variable `CI` is set (non-empty, not `false` or `0`), where
//! a missing folder fails the test, so that a CI run never passes without having read the data.
//!
//! [`fuzz`] holds what the fuzz targets check, shared with the tests that replay their corpus.

use std::path::{Path, PathBuf};

pub mod fuzz;

/// The names in `folder` (hidden ones included), sorted: what a test expects a command to
/// have left behind. Panics when the folder cannot be read (a test's precondition).
pub fn folder_names(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .expect("readable folder")
        .map(|e| {
            e.expect("folder entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// Environment variable naming the shared `data` folder (default: `../shared/data` beside the
/// workspace).
pub const DATA_ENV: &str = "NEUROTAC_SHARED_DATA";

/// `true` when the environment variable `CI` is set to anything but empty, `false` or `0`.
pub fn ci_is_set() -> bool {
    std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0")
}

/// The shared `data` folder: `$NEUROTAC_SHARED_DATA`, else `../shared/data` beside the workspace.
pub fn data_root() -> PathBuf {
    match std::env::var_os(DATA_ENV) {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        // This crate sits one level below the workspace root.
        _ => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
    }
}

/// What a test does about the folder `dir`: `Ok(Some(dir))` when it exists; `Ok(None)` (skip)
/// when it does not and `ci` is `false` (the reason is printed); `Err` with the reason when it
/// does not and `ci` is `true`.
pub fn decide(dir: PathBuf, exists: bool, ci: bool) -> Result<Option<PathBuf>, String> {
    if exists {
        return Ok(Some(dir));
    }
    let why = format!(
        "the shared data is not at {} (it is not part of the repository; set {DATA_ENV} to its `data` folder)",
        dir.display()
    );
    if ci {
        return Err(format!("CI is set, so tests that need it fail: {why}"));
    }
    eprintln!("skipped: {why}");
    Ok(None)
}

/// The shared-data folder `sub` (e.g. `davis240`), or `None` after printing why the calling
/// test skips. Panics when the folder is absent and `CI` is set.
pub fn shared_data(sub: &str) -> Option<PathBuf> {
    let dir = data_root().join(sub);
    let exists = dir.is_dir();
    match decide(dir, exists, ci_is_set()) {
        Ok(found) => found,
        Err(why) => panic!("{why}"),
    }
}

/// A global allocator that counts the allocations (and reallocations) of each thread, for
/// "steps allocate nothing after warm-up" tests: declare
/// `#[global_allocator] static GLOBAL: CountingAllocator = CountingAllocator;` in the test
/// binary and read [`allocations_on_this_thread`] before and after the measured part.
pub struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

// SAFETY: every call is forwarded unchanged to the system allocator; only a thread-local
// counter (which does not allocate) is updated besides.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { std::alloc::System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: `ptr` came from `alloc` above with this layout.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { std::alloc::System.realloc(ptr, layout, new_size) }
    }
}

/// Allocations counted by [`CountingAllocator`] on this thread so far.
pub fn allocations_on_this_thread() -> u64 {
    ALLOCATIONS.with(std::cell::Cell::get)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_shared_data_skips_locally_and_fails_under_ci() {
        let dir = PathBuf::from("/nonexistent/shared/data/davis240");
        assert_eq!(decide(dir.clone(), true, true), Ok(Some(dir.clone())));
        assert_eq!(decide(dir.clone(), true, false), Ok(Some(dir.clone())));
        assert_eq!(decide(dir.clone(), false, false), Ok(None));
        let why = decide(dir, false, true).unwrap_err();
        assert!(
            why.contains("CI is set") && why.contains("/nonexistent/shared/data/davis240"),
            "{why}"
        );
    }

    #[test]
    fn shared_data_follows_the_environment() {
        // Only the folder is compared: the environment variable is read, not written, so
        // parallel tests cannot interfere.
        let root = data_root();
        match std::env::var_os(DATA_ENV) {
            Some(dir) if !dir.is_empty() => assert_eq!(root, PathBuf::from(dir)),
            _ => assert!(root.ends_with("../../shared/data"), "{}", root.display()),
        }
    }
}
