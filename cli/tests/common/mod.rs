//! Runs the `neurotac` binary of this build.
#![allow(dead_code)] // each test file uses what it needs

use std::path::Path;
use std::process::Command;

/// `(success, stdout, stderr)` of `neurotac ARGS`.
pub fn neurotac(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A small artificial `reproduce` (3 slides per texture, 12 epochs) into `out`, caching
/// datasets in `cache`, with `extra` arguments.
pub fn small_reproduce(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    let mut args = vec![
        "reproduce",
        "--set",
        "artificial",
        "--trials",
        "3",
        "--epochs",
        "12",
        "--tau-step",
        "30ms",
        "--out",
        out,
        "--cache",
        cache,
    ];
    args.extend_from_slice(extra);
    neurotac(&args)
}

/// The arguments of a one-slide artificial `simulate` into `out`, caching datasets in
/// `cache`.
pub fn small_simulate_args<'a>(out: &'a Path, cache: &'a Path) -> Vec<&'a str> {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    vec![
        "simulate",
        "--set",
        "artificial",
        "--trials",
        "1",
        "--out",
        out,
        "--cache",
        cache,
    ]
}

/// A one-slide artificial `simulate` into `out` ([`small_simulate_args`]), with `extra`
/// arguments.
pub fn small_simulate(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let mut args = small_simulate_args(out, cache);
    args.extend_from_slice(extra);
    neurotac(&args)
}

/// `mpirun` when it is on the PATH (Open MPI), else `None` with the reason printed.
pub fn mpirun() -> Option<std::path::PathBuf> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join("mpirun"))
            .find(|p| p.is_file())
    });
    if found.is_none() {
        eprintln!(
            "skipped: mpirun is not installed (Debian: apt-get install openmpi-bin libopenmpi-dev)"
        );
    }
    found
}

/// `mpirun` allowed to run as root (as in CI), keeping its session files in `session`.
///
/// Each launch gets its own session folder: Open MPI 4 launches started at the same moment
/// race to create the shared `/tmp/ompi.HOST.UID` folder and one of them fails with
/// "mkdir … File exists", so tests running in parallel must not share it.
fn open_mpi(mpirun: &Path, session: &Path) -> Command {
    let mut c = Command::new(mpirun);
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("TMPDIR", session)
        .arg("--oversubscribe");
    c
}

/// The `mpirun -n RANKS --oversubscribe neurotac ARGS` command, its Open MPI session files in
/// `session` (a folder that outlives the launch).
pub fn mpirun_command(mpirun: &Path, session: &Path, ranks: usize, args: &[&str]) -> Command {
    let mut c = open_mpi(mpirun, session);
    c.args(["-n", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_neurotac"))
        .args(args);
    c
}

/// `(success, stdout, stderr)` of `mpirun -n RANKS neurotac ARGS`.
pub fn neurotac_on_ranks(mpirun: &Path, ranks: usize, args: &[&str]) -> (bool, String, String) {
    let session = tempfile::tempdir().unwrap();
    let out = mpirun_command(mpirun, session.path(), ranks, args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `(success, stdout, stderr)` of an MPMD launch, one rank per entry of `per_rank`:
/// `mpirun -n 1 neurotac ARGS0 : -n 1 neurotac ARGS1 : …` (each rank its own command line).
pub fn neurotac_per_rank(mpirun: &Path, per_rank: &[Vec<&str>]) -> (bool, String, String) {
    let session = tempfile::tempdir().unwrap();
    let mut c = open_mpi(mpirun, session.path());
    for (rank, args) in per_rank.iter().enumerate() {
        if rank > 0 {
            c.arg(":");
        }
        c.args(["-n", "1"])
            .arg(env!("CARGO_BIN_EXE_neurotac"))
            .args(args);
    }
    let out = c.output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Writes a recorded dataset: class `c` (folder `texture<c>`) has pins twitching every
/// `30 + 20·c` ms for 1.2 s, `counts[c]` slides of it (CSV event files), plus a note that is
/// not an event file.
pub fn recorded_dataset(dir: &Path, counts: &[usize]) {
    let classes: Vec<(String, usize)> = (counts.iter().enumerate())
        .map(|(c, &n)| (format!("texture{c}"), n))
        .collect();
    recorded_classes(dir, &classes);
}

/// [`recorded_dataset`] with the classes' folder names given: `(name, slides)` per class.
pub fn recorded_classes(dir: &Path, classes: &[(String, usize)]) {
    use neurotac_core::{Event, EventBuffer, Timestamp};
    use neurotac_sensor::taxel::TaxelLayout;
    for (c, (name, n)) in classes.iter().enumerate() {
        let class = dir.join(name);
        std::fs::create_dir_all(&class).unwrap();
        for trial in 0..*n {
            let period = 30_000 + 20_000 * c as i64;
            let mut events = Vec::new();
            for burst in 0..(1_200_000 / period) {
                for (p, &(cx, cy)) in TaxelLayout::neurotac_default().centres().iter().enumerate() {
                    for (k, (dx, dy)) in [(0, 0), (1, 0), (0, 1), (-1, 0)].into_iter().enumerate() {
                        events.push(Event {
                            t: Timestamp(
                                5_000_000
                                    + burst * period
                                    + p as i64 * 40
                                    + k as i64 * 150
                                    + trial as i64 * 7,
                            ),
                            x: (cx.round() as i32 + dx) as u16,
                            y: (cy.round() as i32 + dy) as u16,
                            polarity: k % 2 == 0,
                        });
                    }
                }
            }
            events.sort_by_key(|e| e.t);
            let buffer: EventBuffer = events.into_iter().collect();
            let path = class.join(format!("{trial:02}.csv"));
            let sensor = neurotac_sensor::format::DAVIS240_SIZE;
            neurotac_sensor::format::write_file(&path, &buffer, sensor).unwrap();
        }
        std::fs::write(class.join("notes.md"), "not an event file").unwrap();
    }
}

/// A CSV file read back by the `csv` crate in strict mode: the header's names (each non-empty,
/// no two alike) and every record, each with as many fields as the header (else the test
/// fails, naming the file).
pub fn read_csv_strict(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(false)
        .from_path(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header: Vec<String> = (reader.headers())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .iter()
        .map(String::from)
        .collect();
    let mut names = header.clone();
    names.sort();
    names.dedup();
    assert!(
        names.len() == header.len() && names.iter().all(|n| !n.is_empty()),
        "{}: header {header:?}",
        path.display()
    );
    let rows = reader
        .records()
        .map(|r| {
            let r = r.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            r.iter().map(String::from).collect()
        })
        .collect();
    (header, rows)
}

/// The tables of a Markdown text (runs of lines starting with `|`), each as its rows of cells
/// (split at every `|` not escaped as `\|`); the separator line is a row too.
pub fn markdown_tables(text: &str) -> Vec<Vec<Vec<String>>> {
    let mut tables: Vec<Vec<Vec<String>>> = Vec::new();
    let mut in_table = false;
    for line in text.lines() {
        let Some(inner) = line.trim_end().strip_prefix('|') else {
            in_table = false;
            continue;
        };
        let mut cells = vec![String::new()];
        let mut escaped = false;
        for c in inner.chars() {
            match c {
                '|' if !escaped => cells.push(String::new()),
                _ => cells.last_mut().unwrap().push(c),
            }
            escaped = c == '\\' && !escaped;
        }
        // The closing `|` leaves an empty last cell.
        if cells.last().is_some_and(|c| c.is_empty()) {
            cells.pop();
        }
        let row = cells.into_iter().map(|c| c.trim().to_owned()).collect();
        match in_table {
            true => tables.last_mut().unwrap().push(row),
            false => tables.push(vec![row]),
        }
        in_table = true;
    }
    tables
}

/// Fails unless every table of the Markdown file at `path` has, in every row, as many cells as
/// its header, and a separator line right under the header.
pub fn assert_markdown_tables_are_whole(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap();
    for table in markdown_tables(&text) {
        let width = table[0].len();
        assert!(
            table.len() >= 2 && table[1].iter().all(|c| c.starts_with("---")),
            "{}: a table without its separator line: {table:?}",
            path.display()
        );
        for row in &table {
            assert_eq!(
                row.len(),
                width,
                "{}: a row of another width than the header {:?}: {row:?}",
                path.display(),
                table[0]
            );
        }
    }
}

/// Every file under `dir` (recursively) whose name ends with `.ext`, sorted.
pub fn files_with_extension(dir: &Path, ext: &str) -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == ext) {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}
