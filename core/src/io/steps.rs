//! The file-system steps of a commit: hidden sibling names, exclusive moves, stale entries of
//! dead processes.

use crate::error::ExistsError;
use std::ffi::OsString;
use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

/// Suffix tag of temporary files: `.NAME.tmp-PID`.
pub(super) const TMP_TAG: &str = "tmp";
/// Suffix tag of folders being written: `.NAME.partial-PID`.
pub(super) const PARTIAL_TAG: &str = "partial";
/// Suffix tag of replaced folders being deleted, and of an [`AtomicFileSet`]'s backups:
/// `.NAME.old-PID`.
pub(super) const OLD_TAG: &str = "old";

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
pub(super) fn exists(path: &Path) -> io::Error {
    io::Error::new(
        io::ErrorKind::AlreadyExists,
        ExistsError {
            path: path.to_path_buf(),
        },
    )
}

/// Moves the complete file or folder `from` onto `to` only if `to` does not exist, failing with
/// [`ExistsError`] otherwise — also when `to` appears while this runs (another process's
/// commit). A file is hard-linked onto `to` (which fails on an existing name) and its temporary
/// name removed; a folder is renamed with `RENAME_NOREPLACE` on Linux. Where neither works (a
/// file system without hard links, another system), the name `to` is first reserved by
/// creating it exclusively, then `from` is renamed onto the reservation.
pub(super) fn place_new(from: &Path, to: &Path, folder: bool) -> io::Result<()> {
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
pub(super) fn rename_noreplace(from: &Path, to: &Path) -> io::Result<()> {
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

/// Whether both paths exist and name the same file (same device and inode; on other systems,
/// the same canonical path).
pub(super) fn same_file(a: &Path, b: &Path) -> bool {
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

/// The folder holding `target` (`.` for a bare name) and the target's file name.
pub(super) fn folder_and_name(target: &Path) -> io::Result<(PathBuf, OsString)> {
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
pub(super) fn sibling(folder: &Path, name: &OsString, tag: &str, pid: u32) -> PathBuf {
    let mut hidden = OsString::from(".");
    hidden.push(name);
    hidden.push(format!(".{tag}-{pid}"));
    folder.join(hidden)
}

/// The siblings `.NAME.TAG-PID` of `name` in `folder`, for each tag, with their PIDs.
pub(super) fn siblings<'a>(
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
pub(super) fn remove_stale(folder: &Path, name: &OsString, tags: &[&str]) {
    let stale: Vec<PathBuf> = siblings(folder, name, tags)
        .filter(|(_, _, pid)| !process_alive(*pid))
        .map(|(path, _, _)| path)
        .collect();
    for path in stale {
        let _ = remove_any(&path);
    }
}

/// Renames the old folder of a dead process's interrupted swap back onto the missing target.
pub(super) fn restore_interrupted_swap(folder: &Path, name: &OsString, target: &Path) {
    let old = siblings(folder, name, &[OLD_TAG]).find(|(_, _, pid)| !process_alive(*pid));
    if let Some((old, _, _)) = old {
        let _ = std::fs::rename(old, target);
    }
}

/// Removes a file or a folder tree.
pub(super) fn remove_any(path: &Path) -> io::Result<()> {
    if std::fs::symlink_metadata(path)?.is_dir() {
        std::fs::remove_dir_all(path)
    } else {
        std::fs::remove_file(path)
    }
}

/// `fsync`s the folder holding `path` so a rename in it survives a crash (best effort: not
/// every system can open a folder).
pub(super) fn sync_folder(path: &Path) {
    if let Ok((folder, _)) = folder_and_name(path)
        && let Ok(dir) = File::open(folder)
    {
        let _ = dir.sync_all();
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
