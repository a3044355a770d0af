//! The journal of an [`AtomicFileSet`](crate::io::AtomicFileSet) commit, and the recovery of
//! a commit cut short by a killed process.

use super::steps::{
    OLD_TAG, PARTIAL_TAG, TMP_TAG, folder_and_name, process_alive, remove_any, same_file, sibling,
    siblings,
};
use std::io;
use std::path::{Path, PathBuf};

/// Suffix tag of a set commit's journal: `.NAME.set-PID` beside every member's target, listing
/// the targets of the whole set.
pub(super) const SET_TAG: &str = "set";

/// The journal's content: every destination as an absolute path, NUL-separated.
pub(super) fn journal_bytes<'a>(
    destinations: impl IntoIterator<Item = &'a Path>,
) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    for destination in destinations {
        bytes.extend_from_slice(
            std::path::absolute(destination)?
                .as_os_str()
                .as_encoded_bytes(),
        );
        bytes.push(0);
    }
    Ok(bytes)
}

/// The destinations listed in a journal (none if it cannot be read).
fn journal_targets(journal: &Path) -> Vec<PathBuf> {
    let bytes = std::fs::read(journal).unwrap_or_default();
    bytes
        .split(|b| *b == 0)
        .filter(|p| !p.is_empty())
        .map(|p| {
            #[cfg(unix)]
            let path =
                PathBuf::from(<std::ffi::OsStr as std::os::unix::ffi::OsStrExt>::from_bytes(p));
            #[cfg(not(unix))]
            let path = PathBuf::from(String::from_utf8_lossy(p).into_owned());
            path
        })
        .collect()
}

/// `.NAME.TAG-PID` beside `target`.
fn beside(target: &Path, tag: &str, pid: u32) -> Option<PathBuf> {
    let (folder, name) = folder_and_name(target).ok()?;
    Some(sibling(&folder, &name, tag, pid))
}

/// Finishes or undoes the set commits of processes that no longer run whose journals lie beside
/// `folder/name` (see [`AtomicFileSet`](crate::io::AtomicFileSet)): when a temporary of any target of the set is left,
/// the burst was cut short and every target gets its old content back; otherwise every target
/// was moved in, and only the backups are left to delete.
pub(super) fn recover_interrupted_sets(folder: &Path, name: &std::ffi::OsString) {
    let journals: Vec<(PathBuf, u32)> = siblings(folder, name, &[SET_TAG])
        .filter(|(_, _, pid)| !process_alive(*pid))
        .map(|(path, _, pid)| (path, pid))
        .collect();
    for (journal, pid) in journals {
        let targets = journal_targets(&journal);
        let temp = |target: &Path| {
            [TMP_TAG, PARTIAL_TAG]
                .iter()
                .filter_map(|tag| beside(target, tag, pid))
                .find(|p| std::fs::symlink_metadata(p).is_ok())
        };
        let cut_short = targets.iter().any(|t| temp(t).is_some());
        for target in &targets {
            let Some(old) = beside(target, OLD_TAG, pid) else {
                continue;
            };
            let old_kept = std::fs::symlink_metadata(&old).ok();
            if cut_short {
                let temp = temp(target);
                // The target is this set's new content when its temporary is gone (moved in)
                // or is the same file (hard-linked in, the temporary name not yet removed).
                let moved_in = temp.as_ref().is_none_or(|t| same_file(t, target));
                match old_kept {
                    Some(meta) => {
                        if meta.is_dir() && moved_in {
                            let _ = remove_any(target);
                        }
                        let _ = std::fs::rename(&old, target);
                    }
                    None if moved_in => {
                        let _ = remove_any(target);
                    }
                    None => {}
                }
                if let Some(temp) = temp {
                    let _ = remove_any(&temp);
                }
            }
            // After a restore the backup is gone, or is still there as the very file of the
            // target (renaming a file onto itself does nothing).
            if !cut_short || same_file(&old, target) {
                let _ = remove_any(&old);
            }
            if let Some(j) = beside(target, SET_TAG, pid) {
                let _ = std::fs::remove_file(j);
            }
        }
        let _ = std::fs::remove_file(&journal);
    }
}
