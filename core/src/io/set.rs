//! [`AtomicFileSet`]: the outputs of one command, committed together or not at all.

use super::dir::AtomicDir;
use super::file::AtomicFile;
use super::journal::{SET_TAG, journal_bytes};
use super::steps::{
    OLD_TAG, Replace, exists, folder_and_name, place_new, remove_any, sibling, sync_folder,
};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The outputs of one command — files ([`AtomicFile`]) and folders ([`AtomicDir`]) — written to
/// their hidden temporaries first and committed together: after [`commit`](Self::commit) every
/// target shows its new content, and after a failed commit every target shows its old content
/// (or is absent if it was), never a mix.
///
/// The commit is one burst of renames after every member is complete: beside each target it
/// writes a journal `.NAME.set-PID` naming all targets, keeps an existing file aside as a hard
/// link `.NAME.old-PID` (an existing folder is renamed there), then moves every temporary in
/// (exclusively under [`Replace::No`]). Should a move fail, the moves already made are undone:
/// old content restored, newly created targets removed. On success the backups and journals
/// are deleted. A process killed during the burst leaves its journals behind; the next
/// [`AtomicFile::create`] or [`AtomicDir::create`] of any of the targets, once that process is
/// gone, finishes the set (no temporary left: every target was moved in) or undoes it (a
/// temporary left: the old contents come back).
///
/// ```
/// use neurotac_core::io::{AtomicFileSet, Replace};
/// let dir = tempfile::tempdir()?;
/// let mut set = AtomicFileSet::new(Replace::No);
/// set.write(dir.path().join("s.json"), "{}")?;
/// std::fs::write(set.dir(dir.path().join("events"))?.join("0.csv"), "t,x,y,on\n")?;
/// assert!(!dir.path().join("s.json").exists()); // nothing visible before the commit
/// set.commit()?;
/// assert!(dir.path().join("s.json").exists() && dir.path().join("events/0.csv").exists());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct AtomicFileSet {
    replace: Replace,
    members: Vec<Member>,
}

#[derive(Debug)]
enum Member {
    File(AtomicFile),
    Dir(AtomicDir),
}

impl Member {
    fn target(&self) -> &Path {
        match self {
            Member::File(f) => f.target(),
            Member::Dir(d) => d.target(),
        }
    }
}

impl AtomicFileSet {
    /// An empty set whose commit may replace existing targets only with [`Replace::Yes`].
    pub fn new(replace: Replace) -> Self {
        Self {
            replace,
            members: Vec::new(),
        }
    }

    /// Adds the file `target` ([`AtomicFile::create`]) and returns it to be written; a file
    /// already in the set is returned again.
    pub fn file(&mut self, target: impl AsRef<Path>) -> io::Result<&mut AtomicFile> {
        let target = target.as_ref();
        let at = match self.members.iter().position(|m| m.target() == target) {
            Some(at) => at,
            None => {
                let file = AtomicFile::create(target, self.replace)?;
                self.members.push(Member::File(file));
                self.members.len() - 1
            }
        };
        match &mut self.members[at] {
            Member::File(f) => Ok(f),
            Member::Dir(_) => Err(twice(target)),
        }
    }

    /// Adds the file `target` holding `bytes`.
    pub fn write(&mut self, target: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> io::Result<()> {
        self.file(target)?.write_all(bytes.as_ref())
    }

    /// Adds the folder `target` ([`AtomicDir::create`]) and returns the hidden folder to fill;
    /// a folder already in the set is returned again.
    pub fn dir(&mut self, target: impl AsRef<Path>) -> io::Result<&Path> {
        let target = target.as_ref();
        let at = match self.members.iter().position(|m| m.target() == target) {
            Some(at) => at,
            None => {
                self.members
                    .push(Member::Dir(AtomicDir::create(target, self.replace)?));
                self.members.len() - 1
            }
        };
        match &self.members[at] {
            Member::Dir(d) => Ok(d.path()),
            Member::File(_) => Err(twice(target)),
        }
    }

    /// Commits every member together (see the type). Fails, changing no target, when under
    /// [`Replace::No`] a target exists ([`ExistsError`](crate::error::ExistsError) inside the [`io::Error`]) or a
    /// file's target is a folder; a move that fails midway is undone.
    pub fn commit(mut self) -> io::Result<()> {
        let mut moves = Vec::with_capacity(self.members.len());
        for member in &mut self.members {
            let (temp, destination, folder) = match member {
                Member::File(f) => match f.finish()? {
                    Some((temp, destination)) => (temp, destination, false),
                    None => continue, // a device or pipe, written directly
                },
                Member::Dir(d) => (d.partial.clone(), d.target.clone(), true),
            };
            let (dir, name) = folder_and_name(&destination)?;
            let existing = std::fs::symlink_metadata(&destination).ok();
            if let Some(meta) = &existing {
                if self.replace == Replace::No {
                    return Err(exists(&destination));
                }
                if !folder && meta.is_dir() {
                    return Err(io::Error::new(
                        io::ErrorKind::IsADirectory,
                        format!("{} is a folder, not a file", destination.display()),
                    ));
                }
            }
            moves.push(Move {
                old: sibling(&dir, &name, OLD_TAG, std::process::id()),
                journal: sibling(&dir, &name, SET_TAG, std::process::id()),
                temp,
                destination,
                folder,
                existed: existing.is_some(),
            });
        }
        commit_moves(&moves, self.replace)?;
        for member in &mut self.members {
            match member {
                Member::File(f) => f.committed = true,
                Member::Dir(d) => d.committed = true,
            }
        }
        Ok(())
    }
}

/// A target named both as a file and as a folder.
fn twice(target: &Path) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "{} is named both as a file and as a folder",
            target.display()
        ),
    )
}

/// One member's move at commit.
struct Move {
    /// The complete temporary file or partial folder.
    temp: PathBuf,
    /// Where it goes.
    destination: PathBuf,
    /// `.NAME.old-PID`: the old content while the set is committed.
    old: PathBuf,
    /// `.NAME.set-PID`: the journal beside the destination.
    journal: PathBuf,
    folder: bool,
    /// The destination existed (and is replaced).
    existed: bool,
}

/// Journals → backups → the burst of moves → backups and journals removed; undone on failure.
fn commit_moves(moves: &[Move], replace: Replace) -> io::Result<()> {
    let cleanup = |moves: &[Move]| {
        for m in moves {
            if m.existed && !m.folder {
                let _ = std::fs::remove_file(&m.old);
            }
            let _ = std::fs::remove_file(&m.journal);
        }
    };
    let listing = journal_bytes(moves.iter().map(|m| m.destination.as_path()))?;
    for (i, m) in moves.iter().enumerate() {
        let kept =
            std::fs::write(&m.journal, &listing).and_then(|()| match m.existed && !m.folder {
                true => keep_aside(&m.destination, &m.old),
                false => Ok(()),
            });
        if let Err(e) = kept {
            cleanup(&moves[..=i]);
            return Err(e);
        }
    }
    for (i, m) in moves.iter().enumerate() {
        if let Err(e) = move_in(m, replace) {
            for done in moves[..i].iter().rev() {
                undo(done);
            }
            cleanup(moves);
            return Err(e);
        }
    }
    for m in moves {
        sync_folder(&m.destination);
    }
    for m in moves {
        if m.existed {
            let _ = remove_any(&m.old);
        }
        let _ = std::fs::remove_file(&m.journal);
    }
    Ok(())
}

/// A second name `old` for the existing file `destination` (a hard link; a copy where the file
/// system has none), so that its content survives the rename onto it.
fn keep_aside(destination: &Path, old: &Path) -> io::Result<()> {
    let _ = std::fs::remove_file(old);
    std::fs::hard_link(destination, old).or_else(|_| std::fs::copy(destination, old).map(drop))
}

/// Moves one member in: an existing folder is renamed aside first (and back if the move fails).
fn move_in(m: &Move, replace: Replace) -> io::Result<()> {
    if m.folder && m.existed {
        std::fs::rename(&m.destination, &m.old)?;
        return place_new(&m.temp, &m.destination, true).inspect_err(|_| {
            let _ = std::fs::rename(&m.old, &m.destination);
        });
    }
    match replace {
        Replace::Yes => std::fs::rename(&m.temp, &m.destination),
        Replace::No => place_new(&m.temp, &m.destination, m.folder),
    }
}

/// Undoes a member's move: the old content back, or the new target removed.
fn undo(m: &Move) {
    if m.existed {
        if m.folder {
            let _ = std::fs::remove_dir_all(&m.destination);
        }
        let _ = std::fs::rename(&m.old, &m.destination);
    } else {
        let _ = remove_any(&m.destination);
    }
}
