//! [`AtomicDir`]: one output folder, filled hidden and moved onto its target when complete.

use super::journal::recover_interrupted_sets;
use super::steps::{
    OLD_TAG, PARTIAL_TAG, Replace, folder_and_name, place_new, remove_any, remove_stale,
    restore_interrupted_swap, sibling, sync_folder,
};
use std::io;
use std::path::{Path, PathBuf};

/// A folder written under the hidden name `.NAME.partial-PID` beside its target and swapped onto
/// the target by [`commit`](Self::commit); dropped uncommitted, it removes the partial folder.
#[derive(Debug)]
pub struct AtomicDir {
    pub(super) partial: PathBuf,
    pub(super) target: PathBuf,
    replace: Replace,
    pub(super) committed: bool,
}

impl AtomicDir {
    /// Creates the empty partial folder `.NAME.partial-PID` beside `target` (creating the
    /// target's parent folders), after cleaning up what interrupted runs for `target` left: an
    /// [`AtomicFileSet`](crate::io::AtomicFileSet) commit cut short is finished or undone, the partial and old folders of
    /// processes that no longer run are deleted, except that an old folder is renamed back to
    /// `target` when `target` does not exist (a swap cut between its two renames). `replace`
    /// decides what [`commit`](Self::commit) does when the target exists by then.
    pub fn create(target: impl AsRef<Path>, replace: Replace) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let (folder, name) = folder_and_name(&target)?;
        std::fs::create_dir_all(&folder)?;
        recover_interrupted_sets(&folder, &name);
        if !target.exists() {
            restore_interrupted_swap(&folder, &name, &target);
        }
        remove_stale(&folder, &name, &[PARTIAL_TAG, OLD_TAG]);
        let partial = sibling(&folder, &name, PARTIAL_TAG, std::process::id());
        if partial.exists() {
            std::fs::remove_dir_all(&partial)?;
        }
        std::fs::create_dir(&partial)?;
        Ok(Self {
            partial,
            target,
            replace,
            committed: false,
        })
    }

    /// The folder to write into.
    pub fn path(&self) -> &Path {
        &self.partial
    }

    /// The path the folder appears under after [`commit`](Self::commit).
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Moves the complete folder in. With [`Replace::Yes`] an existing target is swapped out:
    /// renamed to `.NAME.old-PID`, the new folder renamed onto the target, the old folder
    /// deleted. With [`Replace::No`] the folder is renamed in only while the target is absent
    /// (a target that appeared meanwhile, even an empty folder, fails with [`ExistsError`](crate::error::ExistsError)).
    pub fn commit(mut self) -> io::Result<()> {
        if self.replace == Replace::No {
            place_new(&self.partial, &self.target, true)?;
            self.committed = true;
            sync_folder(&self.target);
            return Ok(());
        }
        let (folder, name) = folder_and_name(&self.target)?;
        let old = sibling(&folder, &name, OLD_TAG, std::process::id());
        let replacing = std::fs::symlink_metadata(&self.target).is_ok();
        if replacing {
            if std::fs::symlink_metadata(&old).is_ok() {
                remove_any(&old)?;
            }
            std::fs::rename(&self.target, &old)?;
        }
        if let Err(e) = std::fs::rename(&self.partial, &self.target) {
            if replacing {
                // Put the old folder back; the partial one is removed on drop.
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(e);
        }
        self.committed = true;
        sync_folder(&self.target);
        if replacing {
            remove_any(&old)?;
        }
        Ok(())
    }
}

impl Drop for AtomicDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.partial);
        }
    }
}
