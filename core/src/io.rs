//! Outputs that are never half-written: atomic files and folders, and the input = output guard.
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
//! [`check_distinct`] refuses an output that is the same file as an input (same device and
//! inode: hard links, `./x` and symbolic links are caught) before anything is written.
//!
//! ```
//! use std::io::Write;
//! use neurotac_core::io::AtomicFile;
//! let dir = tempfile::tempdir()?;
//! let target = dir.path().join("out.csv");
//! let mut file = AtomicFile::create(&target)?;
//! writeln!(file, "t,x,y,on")?;
//! assert!(!target.exists()); // nothing visible before the commit
//! file.commit()?;
//! assert_eq!(std::fs::read_to_string(&target)?, "t,x,y,on\n");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::error::SameFileError;
use std::ffi::OsString;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Suffix tag of temporary files: `.NAME.tmp-PID`.
const TMP_TAG: &str = "tmp";
/// Suffix tag of folders being written: `.NAME.partial-PID`.
const PARTIAL_TAG: &str = "partial";
/// Suffix tag of replaced folders being deleted: `.NAME.old-PID`.
const OLD_TAG: &str = "old";

/// A file written beside its target under a hidden temporary name and renamed onto the target
/// by [`commit`](Self::commit); dropped uncommitted, it removes the temporary file.
///
/// A target that is a symbolic link to a file is replaced behind the link (the link stays). A
/// target that exists and is neither a file nor a folder (`/dev/stdout`, a named pipe) is
/// written directly: it cannot be renamed onto, and holds no content to keep.
///
/// Writes are buffered; [`Seek`] flushes the buffer first.
#[derive(Debug)]
pub struct AtomicFile {
    out: BufWriter<File>,
    /// The hidden file written and where it is renamed to (the target, or the file a symbolic
    /// link target points to); `None` when writing directly to a device or pipe.
    temp: Option<(PathBuf, PathBuf)>,
    target: PathBuf,
    committed: bool,
}

impl AtomicFile {
    /// Creates the temporary file `.NAME.tmp-PID` in the target's folder (which must exist),
    /// after removing temporary files of `target` left by processes that no longer run.
    pub fn create(target: impl AsRef<Path>) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let written = match std::fs::metadata(&target) {
            Ok(m) if !m.is_file() && !m.is_dir() => {
                let file = std::fs::OpenOptions::new().write(true).open(&target)?;
                return Ok(Self {
                    out: BufWriter::with_capacity(1 << 16, file),
                    temp: None,
                    target,
                    committed: false,
                });
            }
            Ok(m) if m.is_file() && target.is_symlink() => std::fs::canonicalize(&target)?,
            _ => target.clone(),
        };
        let (folder, name) = folder_and_name(&written)?;
        remove_stale(&folder, &name, &[TMP_TAG]);
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

    /// Flushes, `fsync`s the file, renames it onto the target (replacing an existing file) and
    /// `fsync`s the folder, so the target holds either the old or the complete new content even
    /// after a crash.
    pub fn commit(mut self) -> io::Result<()> {
        self.out.flush()?;
        let Some((temp, destination)) = &self.temp else {
            self.committed = true;
            return Ok(());
        };
        self.out.get_ref().sync_all()?;
        std::fs::rename(temp, destination)?;
        self.committed = true;
        sync_folder(destination);
        Ok(())
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
pub fn write(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes.as_ref())?;
    file.commit()
}

/// A folder written under the hidden name `.NAME.partial-PID` beside its target and swapped onto
/// the target by [`commit`](Self::commit); dropped uncommitted, it removes the partial folder.
#[derive(Debug)]
pub struct AtomicDir {
    partial: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl AtomicDir {
    /// Creates the empty partial folder `.NAME.partial-PID` beside `target` (creating the
    /// target's parent folders), after cleaning up what interrupted runs for `target` left: the
    /// partial and old folders of processes that no longer run are deleted, except that an old
    /// folder is renamed back to `target` when `target` does not exist (a swap cut between its
    /// two renames).
    pub fn create(target: impl AsRef<Path>) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let (folder, name) = folder_and_name(&target)?;
        std::fs::create_dir_all(&folder)?;
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

    /// Swaps the complete folder in: an existing target is renamed to `.NAME.old-PID`, the new
    /// folder renamed onto the target, and the old folder deleted. Whoever calls it has decided
    /// that an existing target may be replaced (e.g. `--force`).
    pub fn commit(mut self) -> io::Result<()> {
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

/// Fails when `output` is the same file as `input` (same device and inode; on other systems,
/// the same canonical path). A missing input or output is fine: nothing can be overwritten.
/// Call it before creating any output.
pub fn check_distinct(input: &Path, output: &Path) -> Result<(), SameFileError> {
    let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output)) else {
        return Ok(());
    };
    #[cfg(unix)]
    let same = {
        use std::os::unix::fs::MetadataExt;
        a.dev() == b.dev() && a.ino() == b.ino()
    };
    #[cfg(not(unix))]
    let same = {
        let _ = (a, b);
        matches!(
            (std::fs::canonicalize(input), std::fs::canonicalize(output)),
            (Ok(x), Ok(y)) if x == y
        )
    };
    if same {
        return Err(SameFileError {
            input: input.to_path_buf(),
            output: output.to_path_buf(),
        });
    }
    Ok(())
}

/// The folder holding `target` (`.` for a bare name) and the target's file name.
fn folder_and_name(target: &Path) -> io::Result<(PathBuf, OsString)> {
    let name = target.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} does not name a file", target.display()),
        )
    })?;
    let folder = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((folder, name.to_owned()))
}

/// `folder/.NAME.TAG-PID`.
fn sibling(folder: &Path, name: &OsString, tag: &str, pid: u32) -> PathBuf {
    let mut hidden = OsString::from(".");
    hidden.push(name);
    hidden.push(format!(".{tag}-{pid}"));
    folder.join(hidden)
}

/// The siblings `.NAME.TAG-PID` of `name` in `folder`, for each tag, with their PIDs.
fn siblings<'a>(
    folder: &Path,
    name: &OsString,
    tags: &'a [&'a str],
) -> impl Iterator<Item = (PathBuf, &'a str, u32)> + 'a {
    let mut prefix = OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let prefix = prefix.into_encoded_bytes();
    let entries = std::fs::read_dir(folder).into_iter().flatten().flatten();
    entries.filter_map(move |entry| {
        let file_name = entry.file_name().into_encoded_bytes();
        let rest = file_name.strip_prefix(prefix.as_slice())?;
        let rest = std::str::from_utf8(rest).ok()?;
        let (tag, pid) = rest.rsplit_once('-')?;
        let tag = *tags.iter().find(|t| **t == tag)?;
        let pid: u32 = pid.parse().ok()?;
        Some((entry.path(), tag, pid))
    })
}

/// Deletes the `.NAME.TAG-PID` siblings of processes that no longer run.
fn remove_stale(folder: &Path, name: &OsString, tags: &[&str]) {
    let stale: Vec<PathBuf> = siblings(folder, name, tags)
        .filter(|(_, _, pid)| !process_alive(*pid))
        .map(|(path, _, _)| path)
        .collect();
    for path in stale {
        let _ = remove_any(&path);
    }
}

/// Renames the old folder of a dead process's interrupted swap back onto the missing target.
fn restore_interrupted_swap(folder: &Path, name: &OsString, target: &Path) {
    let old = siblings(folder, name, &[OLD_TAG]).find(|(_, _, pid)| !process_alive(*pid));
    if let Some((old, _, _)) = old {
        let _ = std::fs::rename(old, target);
    }
}

/// Removes a file or a folder tree.
fn remove_any(path: &Path) -> io::Result<()> {
    if std::fs::symlink_metadata(path)?.is_dir() {
        std::fs::remove_dir_all(path)
    } else {
        std::fs::remove_file(path)
    }
}

/// `fsync`s the folder holding `path` so a rename in it survives a crash (best effort: not
/// every system can open a folder).
fn sync_folder(path: &Path) {
    if let Ok((folder, _)) = folder_and_name(path) {
        if let Ok(dir) = File::open(folder) {
            let _ = dir.sync_all();
        }
    }
}

/// `true` when a process with this id runs (or may run: without a way to ask, it is assumed
/// alive so that nothing of it is deleted).
pub fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else {
            return false;
        };
        if pid <= 0 {
            return false;
        }
        // SAFETY: kill with signal 0 only checks whether the process exists; it sends nothing.
        let r = unsafe { libc::kill(pid, 0) };
        r == 0 || io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(unix))]
    {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::folder_names;
    #[cfg(unix)]
    use std::os::unix::fs::FileTypeExt;

    /// The id of a process that has exited.
    fn dead_pid() -> u32 {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        assert!(!process_alive(pid));
        pid
    }

    #[test]
    fn an_uncommitted_file_leaves_the_old_content_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("o.csv");
        {
            let mut f = AtomicFile::create(&target).unwrap();
            f.write_all(b"half").unwrap();
            assert!(!target.exists());
        }
        assert_eq!(folder_names(dir.path()), Vec::<String>::new());
        write(&target, b"old").unwrap();
        {
            let mut f = AtomicFile::create(&target).unwrap();
            f.write_all(b"new but failed").unwrap();
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        assert_eq!(folder_names(dir.path()), ["o.csv"]);
        write(&target, b"new").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(folder_names(dir.path()), ["o.csv"]);
    }

    #[test]
    fn an_atomic_file_seeks_back_to_patch_a_header() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("o.bin");
        let mut f = AtomicFile::create(&target).unwrap();
        f.write_all(b"0000body").unwrap();
        f.seek(SeekFrom::Start(0)).unwrap();
        f.write_all(b"HEAD").unwrap();
        f.commit().unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"HEADbody");
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_stays_and_a_pipe_is_written_directly() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write(&link, "new").unwrap();
        assert!(link.is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        assert_eq!(folder_names(dir.path()), ["link.csv", "real.csv"]);
        // A named pipe (as /dev/stdout may be) is written, not replaced.
        let fifo = dir.path().join("pipe.csv");
        let c_path = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path; mkfifo only creates the pipe.
        assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        write(&fifo, "through the pipe").unwrap();
        assert_eq!(reader.join().unwrap(), "through the pipe");
        assert!(fifo.metadata().unwrap().file_type().is_fifo());
        assert_eq!(
            folder_names(dir.path()),
            ["link.csv", "pipe.csv", "real.csv"]
        );
    }

    #[test]
    fn a_file_in_a_missing_folder_fails_at_create() {
        let dir = tempfile::tempdir().unwrap();
        assert!(AtomicFile::create(dir.path().join("missing/o.csv")).is_err());
    }

    #[test]
    fn temporaries_of_dead_processes_are_removed_and_live_ones_kept() {
        let dir = tempfile::tempdir().unwrap();
        let name = OsString::from("o.aedat4");
        let dead = sibling(dir.path(), &name, TMP_TAG, dead_pid());
        let live = sibling(dir.path(), &name, TMP_TAG, std::process::id());
        let other = sibling(dir.path(), &OsString::from("p.aedat4"), TMP_TAG, dead_pid());
        for p in [&dead, &live, &other] {
            std::fs::write(p, b"x").unwrap();
        }
        let f = AtomicFile::create(dir.path().join("o.aedat4")).unwrap();
        assert!(!dead.exists());
        assert!(live.exists(), "our own temporary is the one being written");
        assert!(
            other.exists(),
            "another target's temporary is not ours to judge"
        );
        drop(f);
    }

    #[test]
    fn a_folder_swap_replaces_the_whole_folder() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("report");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("old.md"), "old").unwrap();
        let new = AtomicDir::create(&target).unwrap();
        std::fs::write(new.path().join("new.md"), "new").unwrap();
        assert_eq!(
            folder_names(&target),
            ["old.md"],
            "the old folder is intact until the commit"
        );
        new.commit().unwrap();
        assert_eq!(folder_names(&target), ["new.md"]);
        assert_eq!(folder_names(dir.path()), ["report"]);
        // Dropped uncommitted: the partial folder goes, the target stays.
        let failed = AtomicDir::create(&target).unwrap();
        std::fs::write(failed.path().join("x.md"), "x").unwrap();
        drop(failed);
        assert_eq!(folder_names(dir.path()), ["report"]);
        assert_eq!(folder_names(&target), ["new.md"]);
    }

    #[test]
    fn partial_folders_of_dead_processes_are_removed_on_the_next_run() {
        let dir = tempfile::tempdir().unwrap();
        let name = OsString::from("report");
        let partial = sibling(dir.path(), &name, PARTIAL_TAG, dead_pid());
        std::fs::create_dir(&partial).unwrap();
        std::fs::write(partial.join("a.md"), "a").unwrap();
        let target = dir.path().join("report");
        std::fs::create_dir(&target).unwrap();
        let old = sibling(dir.path(), &name, OLD_TAG, dead_pid());
        std::fs::create_dir(&old).unwrap();
        let d = AtomicDir::create(&target).unwrap();
        assert!(!partial.exists());
        assert!(
            !old.exists(),
            "the target exists, so a dead run's old folder is stale"
        );
        d.commit().unwrap();
        assert_eq!(folder_names(dir.path()), ["report"]);
    }

    #[test]
    fn a_swap_cut_between_its_renames_gets_the_old_folder_back() {
        let dir = tempfile::tempdir().unwrap();
        let name = OsString::from("report");
        let pid = dead_pid();
        // The old folder was renamed away, the new one not yet renamed in.
        let old = sibling(dir.path(), &name, OLD_TAG, pid);
        std::fs::create_dir(&old).unwrap();
        std::fs::write(old.join("old.md"), "old").unwrap();
        let partial = sibling(dir.path(), &name, PARTIAL_TAG, pid);
        std::fs::create_dir(&partial).unwrap();
        let target = dir.path().join("report");
        let d = AtomicDir::create(&target).unwrap();
        assert_eq!(folder_names(&target), ["old.md"]);
        drop(d);
        assert_eq!(folder_names(dir.path()), ["report"]);
    }

    #[test]
    fn same_file_is_caught_through_links_and_dot_paths() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("s.aedat");
        std::fs::write(&input, b"x").unwrap();
        let dotted = dir.path().join(".").join("s.aedat");
        assert!(check_distinct(&input, &dotted).is_err());
        let link = dir.path().join("hard.aedat");
        std::fs::hard_link(&input, &link).unwrap();
        let e = check_distinct(&input, &link).unwrap_err();
        assert!(e.to_string().contains("hard.aedat"), "{e}");
        #[cfg(unix)]
        {
            let sym = dir.path().join("sym.aedat");
            std::os::unix::fs::symlink(&input, &sym).unwrap();
            assert!(check_distinct(&sym, &input).is_err());
        }
        let other = dir.path().join("o.aedat");
        assert!(
            check_distinct(&input, &other).is_ok(),
            "a new output is fine"
        );
        std::fs::write(&other, b"x").unwrap();
        assert!(check_distinct(&input, &other).is_ok());
    }
}
