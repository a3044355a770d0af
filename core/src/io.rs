//! Outputs that are never half-written, never silently lost, and never an input: atomic files,
//! folders and sets of them, and the input/output guards.
//!
//! Every file neurotac writes goes through an [`AtomicFile`]: the bytes go to a hidden temporary
//! file `.NAME.tmp-PID` beside the target, and only [`AtomicFile::commit`] (flush, `fsync`,
//! rename) makes them visible under the target's name. An error, a panic or an early return
//! drops the `AtomicFile`, which removes the temporary file; a process killed by a signal leaves
//! the temporary file behind, never a truncated target, and the next [`AtomicFile::create`] of
//! the same target removes it once its process is gone. So the target path always shows either
//! its old content or nothing (when it did not exist), never a prefix that reads back as valid.
//!
//! A folder of outputs (a report) is written the same way by an [`AtomicDir`]: into
//! `.NAME.partial-PID`, then swapped in by [`AtomicDir::commit`] (old folder renamed away to
//! `.NAME.old-PID` → new folder renamed in → old folder deleted). Partial and old folders of
//! processes that no longer run are cleaned up by the next [`AtomicDir::create`]; an old folder
//! whose swap was interrupted before the new one was renamed in is put back.
//!
//! Whether a commit may replace a target that exists is decided when the output is created
//! ([`Replace`], from `--force`): with [`Replace::No`] the commit is exclusive — it fails with
//! [`ExistsError`] when the target exists by then, even if it appeared after the run checked
//! (another run wrote it), instead of silently replacing it.
//!
//! Several outputs of one command are an [`AtomicFileSet`]: every file and folder is written to
//! its hidden temporary first, then all are renamed in together, or none (see the type).
//!
//! Tables and `t,x,y,on` event files are written and read as CSV through [`csv`] (one crate,
//! one dialect).
//!
//! [`check_distinct`] refuses an output that is the same file as an input (same device and
//! inode: hard links, `./x` and symbolic links are caught), and [`check_not_nested`] an output
//! that is, holds or lies inside an input (canonical paths), before anything is written.
//!
//! ```
//! use std::io::Write;
//! use neurotac_core::io::{AtomicFile, Replace};
//! let dir = tempfile::tempdir()?;
//! let target = dir.path().join("out.csv");
//! let mut file = AtomicFile::create(&target, Replace::No)?;
//! writeln!(file, "t,x,y,on")?;
//! assert!(!target.exists()); // nothing visible before the commit
//! file.commit()?;
//! assert_eq!(std::fs::read_to_string(&target)?, "t,x,y,on\n");
//! // Without Replace::Yes, an existing target is never replaced.
//! let again = AtomicFile::create(&target, Replace::No)?;
//! assert!(again.commit().is_err());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod csv;
mod dir;
mod file;
mod journal;
mod set;
mod steps;

pub use dir::AtomicDir;
pub use file::{AtomicFile, write};
pub use set::AtomicFileSet;
pub use steps::{Replace, process_alive};

use crate::error::{ExistsError, NestedError, Nesting, SameFileError};
use std::io;
use std::path::{Component, Path, PathBuf};
use steps::same_file;

/// The target named by an [`ExistsError`] anywhere in `error`'s chain of sources (also inside
/// an [`io::Error`]): the output a commit without [`Replace::Yes`] found existing.
pub fn existing_output<'a>(error: &'a (dyn std::error::Error + 'static)) -> Option<&'a Path> {
    let mut next = Some(error);
    while let Some(e) = next {
        let inner = e
            .downcast_ref::<io::Error>()
            .and_then(|io| io.get_ref())
            .map(|inner| inner as &(dyn std::error::Error + 'static))
            .unwrap_or(e);
        if let Some(found) = inner.downcast_ref::<ExistsError>() {
            return Some(&found.path);
        }
        next = e.source();
    }
    None
}

/// Fails when `output` is the same file as `input` (same device and inode; on other systems,
/// the same canonical path). A missing input or output is fine: nothing can be overwritten.
/// Call it before creating any output.
pub fn check_distinct(input: &Path, output: &Path) -> Result<(), SameFileError> {
    if same_file(input, output) {
        return Err(SameFileError {
            input: input.to_path_buf(),
            output: output.to_path_buf(),
        });
    }
    Ok(())
}

/// Fails when `output` is `input`, a folder holding `input`, or a path inside the folder
/// `input` — writing or replacing it could delete or change the input (`reproduce --dataset ds
/// --out ds --force`). Both are compared as canonical paths; a path that does not exist yet is
/// its nearest existing ancestor made canonical with the rest appended, so `./x`, `a/../x` and
/// symbolic links are seen through. Call it before creating any output.
pub fn check_not_nested(input: &Path, output: &Path) -> Result<(), NestedError> {
    let (Ok(i), Ok(o)) = (canonical_to_be(input), canonical_to_be(output)) else {
        return Ok(());
    };
    let nesting = if i == o {
        Nesting::Same
    } else if i.starts_with(&o) {
        Nesting::Holds
    } else if o.starts_with(&i) {
        Nesting::Inside
    } else {
        return Ok(());
    };
    Err(NestedError {
        input: input.to_path_buf(),
        output: output.to_path_buf(),
        nesting,
    })
}

/// The canonical form of `path`, which may not exist yet: its nearest existing ancestor made
/// canonical, with the rest of the path appended (`.` dropped, `..` taking a component off).
fn canonical_to_be(path: &Path) -> io::Result<PathBuf> {
    let absolute = std::path::absolute(path)?;
    let parts: Vec<Component> = absolute.components().collect();
    for existing in (1..=parts.len()).rev() {
        let Ok(mut base) = std::fs::canonicalize(PathBuf::from_iter(&parts[..existing])) else {
            continue;
        };
        for part in &parts[existing..] {
            match part {
                Component::ParentDir => {
                    base.pop();
                }
                Component::Normal(name) => base.push(name),
                _ => {}
            }
        }
        return Ok(base);
    }
    Err(io::Error::new(
        io::ErrorKind::NotFound,
        format!("no part of {} exists", path.display()),
    ))
}

#[cfg(test)]
mod tests;
