//! What the MPI ranks of one launch compare before any work ([`run_digest`]): every rank must
//! run the same neurotac version and command with the same options on the same data, or the
//! result assembled from their blocks would be a silent mix.

use super::Cli;
use clap::{ArgAction, ArgMatches, Command, CommandFactory};
use neurotac_cluster::RunDigest;
use neurotac_experiments::datasets::recorded::list_recorded;
use std::path::{Path, PathBuf};

/// Options that may differ between ranks: they set how fast a rank runs (a machine's cores),
/// never what it computes.
const PER_RANK: [&str; 1] = ["threads"];

/// How an option naming data a command reads is compared: by content, so the same data at
/// another path (a copy on each machine) agrees and other data under the same name does not.
enum Read {
    /// One file: `--input` (a spike dataset or event file), `--params` (simulator parameters).
    File,
    /// A recorded dataset folder (`reproduce --dataset`): the event files it reads.
    RecordedFolder,
}

fn read_by(id: &str) -> Option<Read> {
    match id {
        "input" | "params" => Some(Read::File),
        "dataset" => Some(Read::RecordedFolder),
        _ => None,
    }
}

/// The digest of this process's command line: the neurotac version, the (sub)command, then
/// every option of each level in definition order — the files it names by content, the others
/// by value as given or defaulted (`(not given)` when absent) — except [`PER_RANK`]'s.
pub fn run_digest(matches: &ArgMatches) -> RunDigest {
    let mut digest = RunDigest::default();
    digest.setting("neurotac", env!("CARGO_PKG_VERSION"));
    let root = Cli::command();
    let mut levels: Vec<(&Command, &ArgMatches)> = vec![(&root, matches)];
    let mut path = Vec::new();
    let (mut command, mut m) = (&root, matches);
    while let Some((name, sub)) = m.subcommand() {
        let Some(found) = command.find_subcommand(name) else {
            break;
        };
        path.push(name);
        (command, m) = (found, sub);
        levels.push((command, m));
    }
    digest.setting("command", &path.join(" "));
    for (command, m) in levels {
        for arg in command.get_arguments() {
            let id = arg.get_id().as_str();
            let help = matches!(
                arg.get_action(),
                ArgAction::Help | ArgAction::HelpShort | ArgAction::HelpLong | ArgAction::Version
            );
            if help || PER_RANK.contains(&id) {
                continue;
            }
            let name = arg
                .get_long()
                .map_or_else(|| id.to_uppercase(), |long| format!("--{long}"));
            let values: Option<Vec<String>> = m.try_get_raw(id).ok().flatten().map(|raw| {
                raw.map(|v| v.to_string_lossy().into_owned())
                    .collect::<Vec<_>>()
            });
            match (values, read_by(id)) {
                (Some(v), Some(Read::File)) => digest.input_file(&name, Path::new(&v.join(" "))),
                (Some(v), Some(Read::RecordedFolder)) => {
                    recorded_folder(&mut digest, &name, Path::new(&v.join(" ")))
                }
                (Some(v), None) => digest.setting(&name, &v.join(" ")),
                (None, _) => digest.setting(&name, "(not given)"),
            }
        }
    }
    digest
}

/// A recorded dataset folder by the event files [`list_recorded`] finds in it.
fn recorded_folder(digest: &mut RunDigest, name: &str, dir: &Path) {
    match list_recorded(dir) {
        Ok(classes) => {
            let files: Vec<PathBuf> = classes.into_iter().flat_map(|(_, f)| f).collect();
            digest.input_files(name, dir, &files);
        }
        Err(e) => digest.input_unreadable(name, dir, &e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_cluster::PartKind;

    fn digest_of(args: &[&str]) -> RunDigest {
        let argv = std::iter::once("neurotac").chain(args.iter().copied());
        run_digest(&Cli::command().try_get_matches_from(argv).unwrap())
    }

    /// What ranks compare of a digest: each part's kind, name and digest (not how it is shown).
    fn compared(d: &RunDigest) -> Vec<(PartKind, String, [u8; 16])> {
        let parts = d.parts().iter();
        parts.map(|p| (p.kind, p.name.clone(), p.digest)).collect()
    }

    /// The name of the first part where the digests of `a` and `b` differ.
    fn first_difference(a: &[&str], b: &[&str]) -> Option<String> {
        let (a, b) = (compared(&digest_of(a)), compared(&digest_of(b)));
        assert_eq!(a.len(), b.len());
        let pair = a.into_iter().zip(b);
        pair.filter(|(x, y)| x != y).map(|(x, _)| x.1).next()
    }

    #[test]
    fn the_same_files_at_other_paths_and_other_thread_counts_agree() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.json"), dir.path().join("b.json"));
        std::fs::write(&a, "{}").unwrap();
        std::fs::write(&b, "{}").unwrap();
        let simulate = |params: &Path, threads: &str| {
            digest_of(&[
                "simulate",
                "--set",
                "artificial",
                "--out",
                "sim",
                "--params",
                params.to_str().unwrap(),
                "--threads",
                threads,
            ])
        };
        assert_eq!(compared(&simulate(&a, "1")), compared(&simulate(&b, "2")));
    }

    #[test]
    fn every_option_and_the_content_of_every_file_read_count() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.bin"), dir.path().join("b.bin"));
        std::fs::write(&a, "one dataset").unwrap();
        std::fs::write(&b, "another dataset").unwrap();
        let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
        fn classify<'a>(changed: &[&'a str]) -> Vec<&'a str> {
            let mut args = vec!["classify", "--coding", "temporal", "--dt", "10ms"];
            args.extend_from_slice(changed);
            args
        }
        let base = classify(&["--input", a, "--seed", "1"]);
        for (changed, part) in [
            (classify(&["--input", b, "--seed", "1"]), "--input"),
            (classify(&["--input", a, "--seed", "2"]), "--seed"),
            (classify(&["--input", a, "--seed", "1", "--k", "3"]), "--k"),
            (classify(&["--input", a, "--seed", "1", "--json"]), "--json"),
            (
                classify(&["--input", a, "--seed", "1", "--matrix", "m.npy"]),
                "--matrix",
            ),
        ] {
            assert_eq!(
                first_difference(&base, &changed).as_deref(),
                Some(part),
                "{changed:?}"
            );
        }
        // Spelling a default out agrees with leaving it out.
        let k4 = classify(&["--input", a, "--seed", "1", "--k", "4"]);
        assert_eq!(first_difference(&base, &k4), None);
        // Another command is the first difference.
        let search = ["search", "dt", "--input", a];
        let other = digest_of(&search);
        assert_eq!(other.parts()[1].shown, "search dt");
        assert_ne!(digest_of(&base).parts()[1], other.parts()[1]);
    }

    #[test]
    fn a_recorded_folder_counts_by_its_event_files_only() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        for class in ["cotton", "denim"] {
            std::fs::create_dir_all(root.join(class)).unwrap();
            std::fs::write(root.join(class).join("t1.csv"), "0,1,2,1\n").unwrap();
        }
        let reproduce = || digest_of(&["reproduce", "--dataset", root.to_str().unwrap()]);
        let before = reproduce();
        // A note beside the recordings is not read by reproduce, so it does not count.
        std::fs::write(root.join("cotton").join("notes.md"), "slid by hand").unwrap();
        assert_eq!(compared(&reproduce()), compared(&before));
        std::fs::write(root.join("denim").join("t1.csv"), "0,1,2,0\n").unwrap();
        assert_ne!(compared(&reproduce()), compared(&before));
    }
}
