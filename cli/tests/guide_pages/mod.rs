//! The pages of the guide (README.md and the mdBook in docs/) and their fenced code blocks, for
//! the tests that check their links, run their commands and compare the CLI reference with
//! `--help`.
#![allow(dead_code)] // each test file uses what it needs

use std::path::{Path, PathBuf};

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_owned()
}

/// Every page: README.md and every Markdown file under docs/, sorted.
pub fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let mut stack = vec![root().join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    pages.sort();
    pages
}

/// A page's path from the repository's root, for messages.
pub fn shown(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// One fenced code block: its first line's number (1-based), language, tags and text.
#[derive(Debug, Clone)]
pub struct Block {
    pub line: usize,
    pub language: String,
    pub tags: Vec<String>,
    pub text: String,
}

impl Block {
    /// The value of tag `name=value`, if the block has it.
    pub fn tag(&self, name: &str) -> Option<&str> {
        self.tags
            .iter()
            .find_map(|t| t.strip_prefix(name)?.strip_prefix('='))
    }

    /// Whether the block has the bare tag `name`.
    pub fn has(&self, name: &str) -> bool {
        self.tags.iter().any(|t| t == name)
    }
}

/// The fenced code blocks of `text` (``` fences; the info string is the language, then tags
/// separated by spaces).
pub fn blocks(text: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<(usize, String, Vec<String>, Vec<&str>)> = None;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match (&mut open, fence) {
            (None, true) => {
                let info = line.trim_start().trim_start_matches('`');
                let mut words = info.split_whitespace().map(str::to_owned);
                let language = words.next().unwrap_or_default();
                open = Some((i + 1, language, words.collect(), Vec::new()));
            }
            (Some(_), true) => {
                let (line, language, tags, body) = open.take().unwrap();
                blocks.push(Block {
                    line,
                    language,
                    tags,
                    text: body.join("\n"),
                });
            }
            (Some((_, _, _, body)), false) => body.push(line),
            (None, false) => {}
        }
    }
    assert!(open.is_none(), "a code block is not closed");
    blocks
}

/// The anchor mdBook gives a heading (lower case; letters, digits, `_` and `-` kept, spaces to
/// `-`, the rest dropped).
pub fn anchor(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c.to_lowercase().next().unwrap())
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// The anchors of a page's headings (outside code blocks); GitHub and mdBook make the same
/// ones for these headings.
pub fn anchors(text: &str) -> Vec<String> {
    let mut in_code = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        } else if !in_code && line.starts_with('#') {
            let heading = line.trim_start_matches('#');
            // Inline code keeps its text: `neurotac tradeoff` → neurotac-tradeoff.
            out.push(anchor(&heading.replace('`', "")));
        }
    }
    out
}

/// The targets of a page's Markdown links and images, `(line, target)`, outside code blocks
/// and inline code.
pub fn links(text: &str) -> Vec<(usize, String)> {
    let mut in_code = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Drop inline code spans.
        let mut plain = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((i + 1, after[..end].to_owned()));
            rest = &after[end..];
        }
    }
    out
}

/// A page's text.
pub fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}
