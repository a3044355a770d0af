//! Ranks agree on what they compute from before any work.
//!
//! Every rank of a distributed command must run the same command on the same data: a rank
//! started with another seed, or reading another file, would contribute blocks of another
//! computation, and the assembled result would be a silent mix. A [`RunDigest`] is one rank's
//! account of what its result depends on, as named parts: settings, compared by value, and
//! inputs, compared by content (a 128-bit SipHash-2-4 of their bytes, so the same data at
//! different paths agrees and different data under the same name does not).
//! [`Cluster::agree_on`](crate::Cluster::agree_on) all-gathers the parts and compares every
//! rank's with rank 0's; every rank finds the same first difference and returns the same
//! [`ClusterError::Disagree`](crate::ClusterError::Disagree).
//!
//! The digest guards against mistakes (a different file, seed or build per rank), not against
//! someone forging two files with the same digest: the SipHash key is fixed and public.
//!
//! ```
//! use neurotac_cluster::{Cluster, RunDigest};
//! let mut digest = RunDigest::default();
//! digest.setting("--seed", "7");
//! digest.input_file("--input", "Cargo.toml".as_ref());
//! let cluster = Cluster::from_environment()?;
//! cluster.agree_on(&digest)?; // a group of one agrees with itself
//! # Ok::<(), neurotac_cluster::ClusterError>(())
//! ```

use neurotac_core::{Ranks, RanksError};
use siphasher::sip128::{Hasher128, SipHasher24};
use std::fmt;
use std::hash::Hasher;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The digest of an input that could not be read. Ranks that all fail to read an input agree
/// (the command then reports the failure itself); a rank that reads it and one that does not
/// disagree.
const UNREADABLE: [u8; 16] = [0; 16];

/// What a [`DigestPart`] stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartKind {
    /// A setting (an option of the command line), compared by value.
    Setting,
    /// Data read from files, compared by content.
    Input,
}

/// One named part of a [`RunDigest`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DigestPart {
    /// Setting or input.
    pub kind: PartKind,
    /// Its name, e.g. `--seed` or `--input`.
    pub name: String,
    /// How it is shown in messages: a setting's value, an input's path.
    pub shown: String,
    /// The 128-bit digest compared: of a setting's value, of an input's content.
    pub digest: [u8; 16],
}

impl DigestPart {
    fn readable(&self) -> bool {
        self.digest != UNREADABLE
    }
}

/// What one rank's result depends on: named settings and inputs, each digested (see the
/// [module docs](self)). Parts are compared in the order they were added.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RunDigest {
    parts: Vec<DigestPart>,
}

impl RunDigest {
    /// The parts so far, in order.
    pub fn parts(&self) -> &[DigestPart] {
        &self.parts
    }

    /// Adds a setting `name` with `value`, compared by value.
    pub fn setting(&mut self, name: &str, value: &str) {
        let digest = digest_of(|h| h.write(value.as_bytes()));
        self.push(PartKind::Setting, name, value.to_owned(), digest);
    }

    /// Adds the file at `path` as the input `name`, compared by content. A file that cannot be
    /// read is recorded as unreadable (with the reason, shown in messages).
    pub fn input_file(&mut self, name: &str, path: &Path) {
        let (shown, digest) = match file_digest(path) {
            Ok(digest) => (path.display().to_string(), digest),
            Err(e) => (unreadable(path, &e), UNREADABLE),
        };
        self.push(PartKind::Input, name, shown, digest);
    }

    /// Adds `files`, read together as the input `name` found at `root` (a folder of
    /// recordings), compared by their paths relative to `root` and their contents, in order.
    pub fn input_files(&mut self, name: &str, root: &Path, files: &[PathBuf]) {
        let mut folder = SipHasher24::new();
        folder.write_usize(files.len());
        for file in files {
            let relative = file.strip_prefix(root).unwrap_or(file);
            let relative = relative.as_os_str().as_encoded_bytes();
            folder.write_usize(relative.len());
            folder.write(relative);
            match file_digest(file) {
                Ok(digest) => folder.write(&digest),
                Err(e) => {
                    return self.push(PartKind::Input, name, unreadable(file, &e), UNREADABLE);
                }
            }
        }
        let digest = folder.finish128().as_bytes();
        self.push(PartKind::Input, name, root.display().to_string(), digest);
    }

    /// Adds the input `name` at `path` as unreadable for `reason` (e.g. a folder that could not
    /// be listed).
    pub fn input_unreadable(&mut self, name: &str, path: &Path, reason: &dyn fmt::Display) {
        self.push(PartKind::Input, name, unreadable(path, reason), UNREADABLE);
    }

    fn push(&mut self, kind: PartKind, name: &str, shown: String, digest: [u8; 16]) {
        self.parts.push(DigestPart {
            kind,
            name: name.to_owned(),
            shown,
            digest,
        });
    }

    /// The parts as bytes: per part its kind, name and shown text (each a `u32` length and
    /// UTF-8), and digest.
    fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        for p in &self.parts {
            out.push(p.kind as u8);
            for text in [&p.name, &p.shown] {
                let len = u32::try_from(text.len()).unwrap_or(u32::MAX);
                out.extend(len.to_le_bytes());
                out.extend(&text.as_bytes()[..len as usize]);
            }
            out.extend(p.digest);
        }
        out
    }

    /// The parts of [`to_bytes`](Self::to_bytes); `Err` says what is malformed.
    fn from_bytes(mut bytes: &[u8]) -> Result<Self, String> {
        fn take<'a>(bytes: &mut &'a [u8], n: usize) -> Result<&'a [u8], String> {
            if bytes.len() < n {
                return Err(format!(
                    "{} bytes left where {n} were expected",
                    bytes.len()
                ));
            }
            let (head, tail) = bytes.split_at(n);
            *bytes = tail;
            Ok(head)
        }
        fn text(bytes: &mut &[u8]) -> Result<String, String> {
            let len = u32::from_le_bytes(take(bytes, 4)?.try_into().expect("4 bytes"));
            let raw = take(bytes, len as usize)?;
            String::from_utf8(raw.to_vec()).map_err(|e| e.to_string())
        }
        let mut digest = RunDigest::default();
        while !bytes.is_empty() {
            let kind = match take(&mut bytes, 1)?[0] {
                k if k == PartKind::Setting as u8 => PartKind::Setting,
                k if k == PartKind::Input as u8 => PartKind::Input,
                k => return Err(format!("unknown part kind {k}")),
            };
            let name = text(&mut bytes)?;
            let shown = text(&mut bytes)?;
            let hash = take(&mut bytes, 16)?.try_into().expect("16 bytes");
            digest.push(kind, &name, shown, hash);
        }
        Ok(digest)
    }
}

/// The 128-bit SipHash-2-4 (fixed key) of what `feed` writes.
fn digest_of(feed: impl FnOnce(&mut SipHasher24)) -> [u8; 16] {
    let mut h = SipHasher24::new();
    feed(&mut h);
    h.finish128().as_bytes()
}

/// The digest of a file's bytes, read in blocks.
fn file_digest(path: &Path) -> std::io::Result<[u8; 16]> {
    let mut file = std::fs::File::open(path)?;
    let mut h = SipHasher24::new();
    let mut block = vec![0u8; 1 << 20];
    loop {
        match file.read(&mut block) {
            Ok(0) => return Ok(h.finish128().as_bytes()),
            Ok(n) => h.write(&block[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn unreadable(path: &Path, reason: &dyn fmt::Display) -> String {
    format!("{} (unreadable: {reason})", path.display())
}

fn hex(digest: &[u8; 16]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The message of a [`Disagreement`]: how rank `rank`'s part differs from rank 0's.
fn disagreement(rank: usize, theirs: &DigestPart, ours: &DigestPart) -> String {
    let input = |p: &DigestPart| match p.readable() {
        true => format!("{}, digest {}", p.shown, hex(&p.digest)),
        false => p.shown.clone(),
    };
    match (theirs.kind, ours.kind) {
        (PartKind::Input, PartKind::Input) if theirs.name == ours.name => format!(
            "ranks disagree on the inputs: rank {rank} read a different {} ({}) than rank 0 ({})",
            ours.name,
            input(theirs),
            input(ours)
        ),
        _ => {
            let said = |p: &DigestPart| match p.kind {
                PartKind::Setting => format!("{} {}", p.name, p.shown),
                PartKind::Input => format!("{} {}", p.name, input(p)),
            };
            format!(
                "ranks disagree on the settings: rank {rank} was started with {}, rank 0 with {}",
                said(theirs),
                said(ours)
            )
        }
    }
}

/// A part that one rank has and another lacks (ranks of different builds).
fn missing(like: &DigestPart) -> DigestPart {
    DigestPart {
        kind: PartKind::Setting,
        name: like.name.clone(),
        shown: "(nothing: another build of neurotac?)".to_owned(),
        digest: UNREADABLE,
    }
}

/// A rank started with other settings or reading other inputs than rank 0: the first rank and
/// part that differ, the same on every rank.
#[derive(Debug, thiserror::Error)]
#[error("{}", disagreement(*.rank, .theirs, .ours))]
pub struct Disagreement {
    /// The first rank that differs from rank 0.
    pub rank: usize,
    /// Its part that differs.
    pub theirs: Box<DigestPart>,
    /// Rank 0's part.
    pub ours: Box<DigestPart>,
}

/// Every rank's `digest` compared with rank 0's (see [`crate::Cluster::agree_on`]): the first
/// [`Disagreement`], or an exchange that failed. Collective.
pub(crate) fn agree_on(
    ranks: &dyn Ranks,
    digest: &RunDigest,
) -> Result<Result<(), Disagreement>, RanksError> {
    if ranks.size() == 1 {
        return Ok(Ok(()));
    }
    let gathered = ranks.all_gather_bytes(&digest.to_bytes())?;
    let mut all = Vec::with_capacity(gathered.len());
    for (rank, bytes) in gathered.iter().enumerate() {
        let parts = RunDigest::from_bytes(bytes).map_err(|reason| RanksError::Malformed {
            rank,
            during: "the ranks' agreement on their inputs",
            reason,
        })?;
        all.push(parts.parts);
    }
    let root = &all[0];
    for (rank, parts) in all.iter().enumerate().skip(1) {
        let first_difference =
            (0..root.len().max(parts.len())).find_map(|i| match (parts.get(i), root.get(i)) {
                (Some(t), Some(o)) if t.kind == o.kind && t.name == o.name => {
                    (t.digest != o.digest).then(|| (t.clone(), o.clone()))
                }
                (Some(t), Some(o)) => Some((t.clone(), o.clone())),
                (Some(t), None) => Some((t.clone(), missing(t))),
                (None, Some(o)) => Some((missing(o), o.clone())),
                (None, None) => None,
            });
        if let Some((theirs, ours)) = first_difference {
            return Ok(Err(Disagreement {
                rank,
                theirs: Box::new(theirs),
                ours: Box::new(ours),
            }));
        }
    }
    Ok(Ok(()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::ranks::ThreadRanks;

    /// `agree_on` on a thread group whose rank `r` has the digest `digests[r]`: every rank's
    /// result, as a message or `Ok`.
    fn agree(digests: &[RunDigest]) -> Vec<Result<(), String>> {
        ThreadRanks::run(digests.len(), |r| {
            (agree_on(r, &digests[r.rank()]).unwrap()).map_err(|e| e.to_string())
        })
    }

    fn settings(pairs: &[(&str, &str)]) -> RunDigest {
        let mut d = RunDigest::default();
        for (name, value) in pairs {
            d.setting(name, value);
        }
        d
    }

    #[test]
    fn ranks_with_the_same_settings_and_data_at_different_paths_agree() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.json"), dir.path().join("b.json"));
        std::fs::write(&a, b"same data").unwrap();
        std::fs::write(&b, b"same data").unwrap();
        let digests: Vec<RunDigest> = [&a, &b, &a]
            .iter()
            .map(|path| {
                let mut d = settings(&[("command", "distances"), ("--seed", "1")]);
                d.input_file("--input", path);
                d
            })
            .collect();
        assert!(agree(&digests).iter().all(Result::is_ok));
    }

    #[test]
    fn a_rank_reading_other_data_under_the_same_name_stops_every_rank_naming_both_files() {
        let dir = tempfile::tempdir().unwrap();
        let (one, other) = (dir.path().join("one"), dir.path().join("other"));
        std::fs::create_dir_all(&one).unwrap();
        std::fs::create_dir_all(&other).unwrap();
        std::fs::write(one.join("d.json"), b"dataset 1").unwrap();
        std::fs::write(other.join("d.json"), b"dataset 2").unwrap();
        let digests: Vec<RunDigest> = [&one, &one, &other]
            .iter()
            .map(|folder| {
                let mut d = settings(&[("--seed", "1")]);
                d.input_file("--input", &folder.join("d.json"));
                d
            })
            .collect();
        let results = agree(&digests);
        let message = results[0].clone().unwrap_err();
        assert!(results.iter().all(|r| r.as_ref().err() == Some(&message)));
        let digest_2 = hex(&file_digest(&other.join("d.json")).unwrap());
        assert!(
            message.starts_with("ranks disagree on the inputs: rank 2 read a different --input (")
                && message.contains(&format!("other/d.json, digest {digest_2}) than rank 0 ("))
                && message.contains("one/d.json, digest "),
            "{message}"
        );
    }

    #[test]
    fn a_rank_started_with_another_setting_stops_every_rank_naming_both_values() {
        let digests = [
            settings(&[("command", "simulate"), ("--seed", "1")]),
            settings(&[("command", "simulate"), ("--seed", "2")]),
        ];
        let results = agree(&digests);
        let expected = "ranks disagree on the settings: rank 1 was started with --seed 2, \
                        rank 0 with --seed 1";
        assert_eq!(results, vec![Err(expected.to_owned()); 2]);
        // Another command altogether is said first.
        let digests = [
            settings(&[("command", "distances"), ("--seed", "1")]),
            settings(&[("command", "classify"), ("--k", "4")]),
        ];
        assert_eq!(
            agree(&digests)[1],
            Err(
                "ranks disagree on the settings: rank 1 was started with command classify, \
                 rank 0 with command distances"
                    .to_owned()
            )
        );
    }

    #[test]
    fn an_input_unreadable_on_every_rank_agrees_and_on_one_rank_does_not() {
        let dir = tempfile::tempdir().unwrap();
        let (missing, present) = (dir.path().join("missing.bin"), dir.path().join("d.bin"));
        std::fs::write(&present, b"data").unwrap();
        let with = |path: &Path| {
            let mut d = RunDigest::default();
            d.input_file("--input", path);
            d
        };
        let both_missing = [with(&missing), with(&missing)];
        assert!(agree(&both_missing).iter().all(Result::is_ok));
        let message = agree(&[with(&present), with(&missing)])[0]
            .clone()
            .unwrap_err();
        assert!(
            message.contains("rank 1 read a different --input (")
                && message.contains("missing.bin (unreadable: ")
                && message.contains("d.bin, digest "),
            "{message}"
        );
    }

    #[test]
    fn a_folder_of_files_differs_by_a_file_name_or_content() {
        let dir = tempfile::tempdir().unwrap();
        let make = |name: &str, file: &str, content: &[u8]| {
            let root = dir.path().join(name);
            std::fs::create_dir_all(root.join("cotton")).unwrap();
            let path = root.join("cotton").join(file);
            std::fs::write(&path, content).unwrap();
            let mut d = RunDigest::default();
            d.input_files("--dataset", &root, &[path]);
            d
        };
        let base = make("a", "t1.csv", b"0,1,2");
        assert_eq!(
            base.parts()[0].shown,
            dir.path().join("a").display().to_string()
        );
        assert!(agree(&[base.clone(), make("b", "t1.csv", b"0,1,2")])[0].is_ok());
        assert!(agree(&[base.clone(), make("c", "t2.csv", b"0,1,2")])[0].is_err());
        assert!(agree(&[base, make("d", "t1.csv", b"0,1,3")])[0].is_err());
    }

    #[test]
    fn digests_survive_the_exchange_and_malformed_bytes_are_refused() {
        let mut d = settings(&[("command", "reproduce"), ("--epochs", "(not given)")]);
        d.input_unreadable("--dataset", "rec".as_ref(), &"no class folders");
        assert_eq!(RunDigest::from_bytes(&d.to_bytes()), Ok(d.clone()));
        let bytes = d.to_bytes();
        assert!(RunDigest::from_bytes(&bytes[..bytes.len() - 1]).is_err());
        assert!(RunDigest::from_bytes(&[9]).is_err());
        // Digests are the same in every process and build (a fixed key, not a random one):
        // SipHash-2-4-128 of "1" with the zero key.
        assert_eq!(
            hex(&settings(&[("--seed", "1")]).parts()[0].digest),
            "ecf78b0cb5fc31befbc2822d4689108a"
        );
    }
}
