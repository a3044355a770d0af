//! Tests of atomic outputs and the input/output guards.

use super::steps::{OLD_TAG, PARTIAL_TAG, TMP_TAG, sibling};
use super::*;
use crate::error::Nesting;
use crate::testing::folder_names;
use std::ffi::OsString;
use std::io::{Seek, SeekFrom, Write};
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
