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

mod set;

pub use set::AtomicFileSet;

use crate::error::{ExistsError, NestedError, Nesting, SameFileError};
use std::ffi::OsString;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Component, Path, PathBuf};

/// Suffix tag of temporary files: `.NAME.tmp-PID`.
const TMP_TAG: &str = "tmp";
/// Suffix tag of folders being written: `.NAME.partial-PID`.
const PARTIAL_TAG: &str = "partial";
/// Suffix tag of replaced folders being deleted, and of an [`AtomicFileSet`]'s backups:
/// `.NAME.old-PID`.
const OLD_TAG: &str = "old";

/// Whether the commit of an output may replace a target that exists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Replace {
    /// Never: the commit is exclusive and fails with [`ExistsError`] (an [`io::Error`] of kind
    /// `AlreadyExists`) when the target exists at commit time.
    No,
    /// An existing target is replaced (`--force`).
    Yes,
}

impl Replace {
    /// [`Replace::Yes`] when `force` (the `--force` flag), else [`Replace::No`].
    pub fn when(force: bool) -> Self {
        match force {
            true => Replace::Yes,
            false => Replace::No,
        }
    }
}

/// The error of a commit that found `path` existing under [`Replace::No`].
fn exists(path: &Path) -> io::Error {
    io::Error::new(
        io::ErrorKind::AlreadyExists,
        ExistsError {
            path: path.to_path_buf(),
        },
    )
}

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
    committed: bool,
}

impl AtomicFile {
    /// Creates the temporary file `.NAME.tmp-PID` in the target's folder (which must exist),
    /// after cleaning up what interrupted runs for `target` left (temporary files of processes
    /// that no longer run; an [`AtomicFileSet`] commit cut short is finished or undone).
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
        set::recover_interrupted_sets(&folder, &name);
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
    /// move is exclusive and a target that exists by now fails with [`ExistsError`], the
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
    fn finish(&mut self) -> io::Result<Option<(PathBuf, PathBuf)>> {
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

/// A folder written under the hidden name `.NAME.partial-PID` beside its target and swapped onto
/// the target by [`commit`](Self::commit); dropped uncommitted, it removes the partial folder.
#[derive(Debug)]
pub struct AtomicDir {
    partial: PathBuf,
    target: PathBuf,
    replace: Replace,
    committed: bool,
}

impl AtomicDir {
    /// Creates the empty partial folder `.NAME.partial-PID` beside `target` (creating the
    /// target's parent folders), after cleaning up what interrupted runs for `target` left: an
    /// [`AtomicFileSet`] commit cut short is finished or undone, the partial and old folders of
    /// processes that no longer run are deleted, except that an old folder is renamed back to
    /// `target` when `target` does not exist (a swap cut between its two renames). `replace`
    /// decides what [`commit`](Self::commit) does when the target exists by then.
    pub fn create(target: impl AsRef<Path>, replace: Replace) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let (folder, name) = folder_and_name(&target)?;
        std::fs::create_dir_all(&folder)?;
        set::recover_interrupted_sets(&folder, &name);
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
    /// (a target that appeared meanwhile, even an empty folder, fails with [`ExistsError`]).
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

/// Moves the complete file or folder `from` onto `to` only if `to` does not exist, failing with
/// [`ExistsError`] otherwise — also when `to` appears while this runs (another process's
/// commit). A file is hard-linked onto `to` (which fails on an existing name) and its temporary
/// name removed; a folder is renamed with `RENAME_NOREPLACE` on Linux. Where neither works (a
/// file system without hard links, another system), the name `to` is first reserved by
/// creating it exclusively, then `from` is renamed onto the reservation.
fn place_new(from: &Path, to: &Path, folder: bool) -> io::Result<()> {
    let taken = |e: io::Error| match e.kind() {
        io::ErrorKind::AlreadyExists => exists(to),
        _ => e,
    };
    if folder {
        #[cfg(target_os = "linux")]
        match rename_noreplace(from, to) {
            Ok(()) => return Ok(()),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => return Err(exists(to)),
            Err(e)
                if !matches!(
                    e.raw_os_error(),
                    Some(libc::EINVAL | libc::ENOSYS | libc::EOPNOTSUPP)
                ) =>
            {
                return Err(e);
            }
            Err(_) => {}
        }
        std::fs::create_dir(to).map_err(taken)?;
    } else {
        match std::fs::hard_link(from, to) {
            Ok(()) => {
                let _ = std::fs::remove_file(from);
                return Ok(());
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => return Err(exists(to)),
            Err(_) => {}
        }
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(to)
            .map_err(taken)?;
    }
    std::fs::rename(from, to).inspect_err(|_| {
        let _ = match folder {
            true => std::fs::remove_dir(to),
            false => std::fs::remove_file(to),
        };
    })
}

/// `renameat2(from, to, RENAME_NOREPLACE)`: fails with `EEXIST` when `to` exists.
#[cfg(target_os = "linux")]
fn rename_noreplace(from: &Path, to: &Path) -> io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        std::ffi::CString::new(p.as_os_str().as_bytes())
            .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))
    };
    let (from, to) = (c(from)?, c(to)?);
    // SAFETY: two valid NUL-terminated paths relative to the working folder; renameat2 only
    // renames.
    let r = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            from.as_ptr(),
            libc::AT_FDCWD,
            to.as_ptr(),
            libc::RENAME_NOREPLACE,
        )
    };
    match r {
        0 => Ok(()),
        _ => Err(io::Error::last_os_error()),
    }
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

/// Whether both paths exist and name the same file (same device and inode; on other systems,
/// the same canonical path).
fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
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
    use crate::error::Nesting;
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
            let mut f = AtomicFile::create(&target, Replace::No).unwrap();
            f.write_all(b"half").unwrap();
            assert!(!target.exists());
        }
        assert_eq!(folder_names(dir.path()), Vec::<String>::new());
        write(&target, b"old", Replace::No).unwrap();
        {
            let mut f = AtomicFile::create(&target, Replace::No).unwrap();
            f.write_all(b"new but failed").unwrap();
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        assert_eq!(folder_names(dir.path()), ["o.csv"]);
        write(&target, b"new", Replace::Yes).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(folder_names(dir.path()), ["o.csv"]);
    }

    #[test]
    fn an_atomic_file_seeks_back_to_patch_a_header() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("o.bin");
        let mut f = AtomicFile::create(&target, Replace::No).unwrap();
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
        write(&link, "new", Replace::Yes).unwrap();
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
        write(&fifo, "through the pipe", Replace::Yes).unwrap();
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
        assert!(AtomicFile::create(dir.path().join("missing/o.csv"), Replace::No).is_err());
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
        let f = AtomicFile::create(dir.path().join("o.aedat4"), Replace::No).unwrap();
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
        let new = AtomicDir::create(&target, Replace::Yes).unwrap();
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
        let failed = AtomicDir::create(&target, Replace::Yes).unwrap();
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
        let d = AtomicDir::create(&target, Replace::Yes).unwrap();
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
        let d = AtomicDir::create(&target, Replace::Yes).unwrap();
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

    #[test]
    fn an_exclusive_commit_loses_to_a_file_written_meanwhile() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("d.npy");
        let mut ours = AtomicFile::create(&target, Replace::No).unwrap();
        ours.write_all(b"ours").unwrap();
        // Another run commits first, between our create and our commit.
        std::fs::write(&target, b"theirs").unwrap();
        let e = ours.commit().unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::AlreadyExists);
        assert_eq!(existing_output(&e), Some(target.as_path()));
        assert_eq!(
            e.to_string(),
            format!("{} already exists", target.display())
        );
        assert_eq!(std::fs::read(&target).unwrap(), b"theirs");
        assert_eq!(folder_names(dir.path()), ["d.npy"]);
        // Asked to replace, it does.
        write(&target, b"forced", Replace::Yes).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"forced");
    }

    #[test]
    fn an_exclusive_folder_commit_loses_to_a_folder_made_meanwhile_even_an_empty_one() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("report");
        let ours = AtomicDir::create(&target, Replace::No).unwrap();
        std::fs::write(ours.path().join("ours.md"), "ours").unwrap();
        std::fs::create_dir(&target).unwrap();
        let e = ours.commit().unwrap_err();
        assert_eq!(existing_output(&e), Some(target.as_path()));
        assert_eq!(folder_names(&target), Vec::<String>::new());
        assert_eq!(folder_names(dir.path()), ["report"]);
        std::fs::remove_dir(&target).unwrap();
        let ours = AtomicDir::create(&target, Replace::No).unwrap();
        std::fs::write(ours.path().join("ours.md"), "ours").unwrap();
        ours.commit().unwrap();
        assert_eq!(folder_names(&target), ["ours.md"]);
    }

    /// Three outputs a.json, b.svg, c.png holding "old" (when `existing`), a set writing "new"
    /// to all three, and its hidden temporary of c.png.
    fn set_of_three(dir: &Path, existing: bool, replace: Replace) -> (AtomicFileSet, PathBuf) {
        let names = ["a.json", "b.svg", "c.png"];
        if existing {
            for name in names {
                std::fs::write(dir.join(name), "old").unwrap();
            }
        }
        let mut set = AtomicFileSet::new(replace);
        for name in names {
            set.write(dir.join(name), "new").unwrap();
        }
        let temp = sibling(dir, &OsString::from("c.png"), TMP_TAG, std::process::id());
        assert!(temp.exists());
        (set, temp)
    }

    fn contents(dir: &Path, names: &[&str]) -> Vec<String> {
        let read = |n: &&str| std::fs::read_to_string(dir.join(n)).unwrap_or("absent".into());
        names.iter().map(read).collect()
    }

    #[test]
    fn a_set_whose_third_move_fails_leaves_every_target_as_it_was() {
        let names = ["a.json", "b.svg", "c.png"];
        for (existing, replace) in [(true, Replace::Yes), (false, Replace::No)] {
            let dir = tempfile::tempdir().unwrap();
            let (set, temp) = set_of_three(dir.path(), existing, replace);
            // The third move cannot happen: its temporary file is gone.
            std::fs::remove_file(&temp).unwrap();
            assert!(set.commit().is_err());
            let before = if existing { "old" } else { "absent" };
            assert_eq!(contents(dir.path(), &names), [before; 3]);
            let left: Vec<String> = match existing {
                true => names.iter().map(|n| n.to_string()).collect(),
                false => vec![],
            };
            assert_eq!(folder_names(dir.path()), left, "no hidden file is left");
        }
    }

    #[test]
    fn a_set_refuses_a_file_where_a_folder_stands_before_moving_anything() {
        let dir = tempfile::tempdir().unwrap();
        let (set, _) = set_of_three(dir.path(), true, Replace::Yes);
        std::fs::remove_file(dir.path().join("c.png")).unwrap();
        std::fs::create_dir(dir.path().join("c.png")).unwrap();
        let e = set.commit().unwrap_err();
        assert!(e.to_string().contains("c.png is a folder"), "{e}");
        assert_eq!(contents(dir.path(), &["a.json", "b.svg"]), ["old", "old"]);
        assert_eq!(folder_names(dir.path()), ["a.json", "b.svg", "c.png"]);
    }

    #[test]
    fn an_exclusive_set_moves_nothing_when_one_target_appeared_meanwhile() {
        let dir = tempfile::tempdir().unwrap();
        let (set, _) = set_of_three(dir.path(), false, Replace::No);
        std::fs::write(dir.path().join("b.svg"), "theirs").unwrap();
        let e = set.commit().unwrap_err();
        assert_eq!(
            existing_output(&e),
            Some(dir.path().join("b.svg").as_path())
        );
        assert_eq!(
            contents(dir.path(), &["a.json", "b.svg", "c.png"]),
            ["absent", "theirs", "absent"]
        );
        assert_eq!(folder_names(dir.path()), ["b.svg"]);
    }

    #[test]
    fn a_set_of_files_and_a_folder_replaces_them_all_together() {
        let dir = tempfile::tempdir().unwrap();
        let (mut set, _) = set_of_three(dir.path(), true, Replace::Yes);
        let events = dir.path().join("events");
        std::fs::create_dir(&events).unwrap();
        std::fs::write(events.join("old.csv"), "old").unwrap();
        let partial = set.dir(&events).unwrap().to_path_buf();
        assert_eq!(set.dir(&events).unwrap(), partial, "the same folder again");
        std::fs::write(partial.join("new.csv"), "new").unwrap();
        set.commit().unwrap();
        assert_eq!(
            contents(dir.path(), &["a.json", "b.svg", "c.png"]),
            ["new"; 3]
        );
        assert_eq!(folder_names(&events), ["new.csv"]);
        assert_eq!(
            folder_names(dir.path()),
            ["a.json", "b.svg", "c.png", "events"]
        );
    }

    #[test]
    fn a_set_commit_killed_midway_is_undone_by_the_next_create() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let pid = dead_pid();
        let hidden = |name: &str, tag: &str| sibling(d, &OsString::from(name), tag, pid);
        let journal: Vec<u8> = ["a.json", "b.svg", "c.png"]
            .iter()
            .flat_map(|n| {
                let mut p = d.join(n).into_os_string().into_encoded_bytes();
                p.push(0);
                p
            })
            .collect();
        for name in ["a.json", "b.svg", "c.png"] {
            std::fs::write(hidden(name, "set"), &journal).unwrap();
        }
        // a.json was moved in (its old content kept aside), b.svg not yet (kept aside as a
        // second name of the old file), c.png is new and not moved in yet.
        std::fs::write(hidden("a.json", OLD_TAG), "old").unwrap();
        std::fs::write(d.join("a.json"), "new").unwrap();
        std::fs::write(d.join("b.svg"), "old").unwrap();
        std::fs::hard_link(d.join("b.svg"), hidden("b.svg", OLD_TAG)).unwrap();
        std::fs::write(hidden("b.svg", TMP_TAG), "new").unwrap();
        std::fs::write(hidden("c.png", TMP_TAG), "new").unwrap();
        drop(AtomicFile::create(d.join("c.png"), Replace::No).unwrap());
        assert_eq!(
            contents(d, &["a.json", "b.svg", "c.png"]),
            ["old", "old", "absent"]
        );
        assert_eq!(folder_names(d), ["a.json", "b.svg"]);
    }

    #[test]
    fn a_set_commit_killed_after_its_moves_is_finished_by_the_next_create() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let pid = dead_pid();
        let hidden = |name: &str, tag: &str| sibling(d, &OsString::from(name), tag, pid);
        let mut journal = d.join("a.json").into_os_string().into_encoded_bytes();
        journal.push(0);
        journal.extend(d.join("events").into_os_string().into_encoded_bytes());
        std::fs::write(hidden("a.json", "set"), &journal).unwrap();
        std::fs::write(hidden("events", "set"), &journal).unwrap();
        std::fs::write(d.join("a.json"), "new").unwrap();
        std::fs::write(hidden("a.json", OLD_TAG), "old").unwrap();
        std::fs::create_dir(d.join("events")).unwrap();
        std::fs::create_dir(hidden("events", OLD_TAG)).unwrap();
        drop(AtomicDir::create(d.join("events"), Replace::No).unwrap());
        assert_eq!(contents(d, &["a.json"]), ["new"]);
        assert_eq!(folder_names(d), ["a.json", "events"]);
    }

    #[test]
    fn an_output_that_is_holds_or_lies_inside_an_input_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let ds = dir.path().join("ds");
        std::fs::create_dir_all(ds.join("cotton")).unwrap();
        let nesting =
            |input: &Path, output: &Path| check_not_nested(input, output).err().map(|e| e.nesting);
        assert_eq!(nesting(&ds, &ds), Some(Nesting::Same));
        assert_eq!(nesting(&ds, &ds.join("../ds/.")), Some(Nesting::Same));
        assert_eq!(nesting(&ds, dir.path()), Some(Nesting::Holds));
        assert_eq!(nesting(&ds, &ds.join("report")), Some(Nesting::Inside));
        // Not there yet: the nearest existing folder is made canonical, the rest appended.
        assert_eq!(nesting(&ds, &ds.join("new/deeper")), Some(Nesting::Inside));
        assert_eq!(
            nesting(&ds, &dir.path().join("new/../ds")),
            Some(Nesting::Same)
        );
        #[cfg(unix)]
        {
            let link = dir.path().join("link");
            std::os::unix::fs::symlink(&ds, &link).unwrap();
            assert_eq!(nesting(&ds, &link), Some(Nesting::Same));
            assert_eq!(nesting(&link.join("cotton"), &ds), Some(Nesting::Holds));
        }
        assert_eq!(
            nesting(&ds, &dir.path().join("ds2")),
            None,
            "a sibling with a longer name"
        );
        assert_eq!(nesting(&ds.join("cotton"), &ds.join("report")), None);
        let e = check_not_nested(&ds, dir.path()).unwrap_err().to_string();
        assert!(
            e.contains(&ds.display().to_string()) && e.contains(&dir.path().display().to_string()),
            "{e}"
        );
    }
}
