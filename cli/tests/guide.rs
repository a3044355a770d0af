//! The guide (README.md and the mdBook in docs/) as a reader meets it: every internal link and
//! anchor resolves, every page is in the book's table of contents and every figure in the
//! gallery, every code block says where it runs (and an excerpt is what its file holds), and
//! the CLI reference is the binary's `--help`, word for word.
//!
//! `NEUROTAC_UPDATE_GUIDE=1 cargo test --release -p neurotac-cli --test guide` rewrites the CLI
//! reference (docs/reference/cli.md) from `--help`.

mod common;
mod guide_pages;

use common::neurotac;
use guide_pages::{Block, anchors, blocks, links, pages, read, root, shown};
use std::path::Path;

#[test]
fn every_internal_link_and_anchor_resolves() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = read(&page);
        let dir = page.parent().unwrap();
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((path, anchor)) => (path, Some(anchor)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                page.clone()
            } else {
                dir.join(path)
            };
            let at = format!("{}:{line}: {target}", shown(&page));
            if !file.exists() {
                broken.push(format!("{at}: no such file"));
                continue;
            }
            if let Some(anchor) = anchor
                && file.extension().is_some_and(|e| e == "md")
                && !anchors(&read(&file)).iter().any(|a| a == anchor)
            {
                broken.push(format!("{at}: no heading with this anchor"));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn every_page_of_the_book_is_in_its_table_of_contents() {
    let docs = root().join("docs");
    let summary = read(&docs.join("SUMMARY.md"));
    let listed: Vec<String> = links(&summary).into_iter().map(|(_, t)| t).collect();
    for page in pages() {
        let Ok(relative) = page.strip_prefix(&docs) else {
            continue; // README.md
        };
        let relative = relative.to_str().unwrap();
        if relative != "SUMMARY.md" {
            assert!(
                listed.iter().any(|l| l == relative),
                "docs/{relative} is not in docs/SUMMARY.md"
            );
        }
    }
}

#[test]
fn every_figure_is_in_the_gallery_with_its_command() {
    let docs = root().join("docs");
    let gallery = read(&docs.join("gallery.md"));
    for entry in std::fs::read_dir(&docs).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".png") || name.ends_with(".svg") {
            assert!(
                gallery.contains(&format!("`{name}`")),
                "docs/{name} is not in docs/gallery.md (with the command that made it)"
            );
        }
    }
}

/// What is wrong with how `block` says it is checked, if anything.
fn unchecked(block: &Block) -> Option<String> {
    let code = matches!(
        block.language.as_str(),
        "sh" | "python" | "rust" | "json" | "toml"
    );
    if !code {
        // Output shown as it was printed (text, tables): nothing to run.
        return (block.language != "text").then(|| {
            format!(
                "language '{}' (expected sh, python, rust, json or text)",
                block.language
            )
        });
    }
    if block.has("run") {
        return (!matches!(block.language.as_str(), "sh" | "python"))
            .then(|| "only sh and python blocks are run".to_owned());
    }
    if let Some(path) = block.tag("excerpt") {
        let file = std::fs::read_to_string(root().join(path)).ok()?;
        let lines: Vec<&str> = file.lines().map(str::trim).collect();
        return block
            .text
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !lines.contains(l))
            .map(|l| format!("excerpt of {path}, which has no line `{l}`"));
    }
    if let Some(test) = block.tag("test") {
        let Some((path, name)) = test.split_once("::") else {
            return Some(format!("test={test}: expected PATH::NAME"));
        };
        return match std::fs::read_to_string(root().join(path)) {
            Ok(file) if file.contains(name) => None,
            Ok(_) => Some(format!("test={test}: {path} has no `{name}`")),
            Err(e) => Some(format!("test={test}: {path}: {e}")),
        };
    }
    if block.has("bench") {
        let benches = block
            .text
            .lines()
            .all(|l| l.starts_with("cargo bench --bench "));
        return (!benches)
            .then(|| "a bench block holds only `cargo bench --bench NAME` lines".to_owned());
    }
    if block.has("hardware") {
        return None;
    }
    if block.has("schema") {
        let description: neurotac_core::NetworkDescription = match serde_json::from_str(&block.text)
        {
            Ok(d) => d,
            Err(e) => return Some(format!("not a network description: {e}")),
        };
        let mut b = match neurotac_core::NetworkBuilder::from_description(
            &description,
            &neurotac_neurons::BuiltinModels,
        ) {
            Ok(b) => b,
            Err(e) => return Some(format!("the network does not build: {e}")),
        };
        for name in ["afferents", "hidden"] {
            b.record_spikes(b.population(name).ok()?).ok()?;
        }
        return b
            .build(neurotac_core::NetworkConfig {
                dt_s: description.dt_s,
            })
            .err()
            .map(|e| format!("the network does not build: {e}"));
    }
    Some(
        "no tag saying where it runs (run, excerpt=PATH, test=PATH::NAME, bench, hardware, schema)"
            .to_owned(),
    )
}

#[test]
fn every_code_block_says_where_it_runs() {
    let mut wrong = Vec::new();
    let (mut run, mut elsewhere, mut outputs, mut hardware) = (0, 0, 0, Vec::new());
    for page in pages() {
        for block in blocks(&read(&page)) {
            match unchecked(&block) {
                Some(why) => wrong.push(format!("{}:{}: {why}", shown(&page), block.line)),
                None if block.has("run") => run += 1,
                None if block.language == "text" => outputs += 1,
                None if block.has("hardware") => {
                    hardware.push(format!("{}:{}", shown(&page), block.line))
                }
                None => elsewhere += 1,
            }
        }
    }
    assert!(wrong.is_empty(), "code blocks:\n{}", wrong.join("\n"));
    println!(
        "{run} blocks run by the guide's tests, {elsewhere} by the tests or CI steps they name, {outputs} show output, {} need hardware CI does not have: {}",
        hardware.len(),
        hardware.join(", ")
    );
}

/// Every command and subcommand, as paths of names (`[]` is `neurotac` itself), in the order
/// `--help` lists them.
fn commands(path: &[String]) -> Vec<Vec<String>> {
    let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
    args.push("--help");
    let (ok, help, stderr) = neurotac(&args);
    assert!(ok, "{args:?}: {stderr}");
    let mut out = vec![path.to_vec()];
    let Some(listed) = help.split("Commands:\n").nth(1) else {
        return out;
    };
    for line in listed.lines().take_while(|l| l.starts_with("  ")) {
        let name = line.split_whitespace().next().unwrap();
        if name != "help" && line.starts_with("  ") && !line.starts_with("   ") {
            let mut sub = path.to_vec();
            sub.push(name.to_owned());
            out.extend(commands(&sub));
        }
    }
    out
}

/// The CLI reference page, made from every command's `--help`.
fn cli_reference() -> String {
    let mut page = String::from(
        "# Every command's --help\n\n\
         What `neurotac … --help` prints, for every command and subcommand (made from the \
         binary: `NEUROTAC_UPDATE_GUIDE=1 cargo test --release -p neurotac-cli --test guide` \
         rewrites this page, and the same test fails when the two differ). \
         [Commands](commands.md) has them at a glance.\n",
    );
    for path in commands(&[]) {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let (_, help, _) = neurotac(&args);
        let name = std::iter::once("neurotac")
            .chain(path.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join(" ");
        page.push_str(&format!(
            "\n## {name}\n\n```text\n{}\n```\n",
            help.trim_end()
        ));
    }
    page
}

#[test]
fn the_cli_reference_is_every_commands_help() {
    let path = root().join("docs/reference/cli.md");
    let expected = cli_reference();
    if std::env::var_os("NEUROTAC_UPDATE_GUIDE").is_some() {
        std::fs::write(&path, &expected).unwrap();
    }
    let page = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        page == expected,
        "docs/reference/cli.md is not what `--help` prints (NEUROTAC_UPDATE_GUIDE=1 cargo test --release -p neurotac-cli --test guide rewrites it)"
    );
    // Every command has its section, subcommands included.
    for command in [
        "reproduce",
        "simulate check",
        "bench neurons",
        "search vr",
        "view",
    ] {
        assert!(
            page.contains(&format!("\n## neurotac {command}\n")),
            "{command}"
        );
    }
}

#[test]
fn the_readme_is_a_front_page() {
    let readme = read(&root().join("README.md"));
    let lines = readme.lines().count();
    assert!(
        lines <= 250,
        "README.md has {lines} lines; the guide (docs/) holds the rest"
    );
    assert_eq!(
        readme.matches("![").count(),
        1,
        "README.md shows one figure"
    );
    assert!(Path::new(&root().join("docs/SUMMARY.md")).exists());
}
