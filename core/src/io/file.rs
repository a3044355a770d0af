//! [`AtomicFile`]: one output file, written hidden and moved onto its target when complete.

use super::journal::recover_interrupted_sets;
use super::steps::{
    OLD_TAG, Replace, TMP_TAG, folder_and_name, place_new, remove_stale, sibling, sync_folder,
};
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// A file written beside its target under a hidden temporary name and renamed onto the target
/// by [`commit`](Self::commit); dropped uncommitted, it removes the temporary file.
///
/// A target that is a symbolic link to a file is replaced behind the link (the link stays). A
/// target that exists and is neither a file nor a folder (`/dev/stdout`, a named pipe) is
/// written directly: it cannot be renamed onto, and holds no content to keep. A target that is
/// a folder is refused at [`create`](Self::create).
///
/// Writes are buffered; [`Seek`] flushes the buffer first.
#[derive(Debug)]
pub struct AtomicFile {
    out: BufWriter<File>,
    /// The hidden file written and where it is renamed to (the target, or the file a symbolic
    /// link target points to); `None` when writing directly to a device or pipe.
    temp: Option<(PathBuf, PathBuf)>,
    target: PathBuf,
    replace: Replace,
    pub(super) committed: bool,
}

impl AtomicFile {
    /// Creates the temporary file `.NAME.tmp-PID` in the target's folder (which must exist),
    /// after cleaning up what interrupted runs for `target` left (temporary files of processes
    /// that no longer run; an [`AtomicFileSet`](crate::io::AtomicFileSet) commit cut short is finished or undone).
    /// `replace` decides what [`commit`](Self::commit) does when the target exists by then.
    pub fn create(target: impl AsRef<Path>, replace: Replace) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let written = match std::fs::metadata(&target) {
            Ok(m) if m.is_dir() => {
                return Err(io::Error::new(
                    io::ErrorKind::IsADirectory,
                    format!("{} is a folder, not a file", target.display()),
                ));
            }
            Ok(m) if !m.is_file() => {
                let file = std::fs::OpenOptions::new().write(true).open(&target)?;
                return Ok(Self {
                    out: BufWriter::with_capacity(1 << 16, file),
                    temp: None,
                    target,
                    replace,
                    committed: false,
                });
            }
            Ok(_) if target.is_symlink() => std::fs::canonicalize(&target)?,
            _ => target.clone(),
        };
        let (folder, name) = folder_and_name(&written)?;
        recover_interrupted_sets(&folder, &name);
        remove_stale(&folder, &name, &[TMP_TAG, OLD_TAG]);
        let temp = sibling(&folder, &name, TMP_TAG, std::process::id());
        let file = std::fs::OpenOptions::new()
            .write(true)
            .read(true)
            .create(true)
            .truncate(true)
            .open(&temp)?;
        Ok(Self {
            out: BufWriter::with_capacity(1 << 16, file),
            temp: Some((temp, written)),
            target,
            replace,
            committed: false,
        })
    }

    /// The path the file appears under after [`commit`](Self::commit), as given.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// A second handle to the temporary file, for a writer that must own its output (a boxed
    /// encoder): what it writes and flushes is what [`commit`](Self::commit) makes visible.
    /// Write either through this handle or through the `AtomicFile`, not both.
    pub fn try_clone_file(&self) -> io::Result<File> {
        self.out.get_ref().try_clone()
    }

    /// Flushes and `fsync`s the file, then moves it onto the target and `fsync`s the folder, so
    /// the target holds either the old or the complete new content even after a crash. With
    /// [`Replace::Yes`] an existing target is replaced (one rename); with [`Replace::No`] the
    /// move is exclusive and a target that exists by now fails with [`ExistsError`](crate::error::ExistsError), the
    /// temporary file being removed.
    pub fn commit(mut self) -> io::Result<()> {
        let Some((temp, destination)) = self.finish()? else {
            self.committed = true;
            return Ok(());
        };
        match self.replace {
            Replace::Yes => std::fs::rename(&temp, &destination)?,
            Replace::No => place_new(&temp, &destination, false)?,
        }
        self.committed = true;
        sync_folder(&destination);
        Ok(())
    }

    /// Flushes and `fsync`s the temporary file; its path and destination (`None` when written
    /// directly).
    pub(super) fn finish(&mut self) -> io::Result<Option<(PathBuf, PathBuf)>> {
        self.out.flush()?;
        if self.temp.is_some() {
            self.out.get_ref().sync_all()?;
        }
        Ok(self.temp.clone())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.out.write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.out.write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.out.seek(pos)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if let (false, Some((temp, _))) = (self.committed, &self.temp) {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Writes `bytes` to `path` atomically (an [`AtomicFile`] created, filled and committed).
pub fn write(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>, replace: Replace) -> io::Result<()> {
    let mut file = AtomicFile::create(path, replace)?;
    file.write_all(bytes.as_ref())?;
    file.commit()
}
