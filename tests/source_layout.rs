//! The source layout STYLE.md asks for, checked over every crate of the workspace: the root
//! package and each top-level directory with a `Cargo.toml` and a `src/` (`python/` and a future
//! `cli/` included; `target/` and `fuzz/` skipped). Three rules, one test each:
//!
//! 1. **No source file is longer than 800 lines** ("split a file past ~800 lines by concept"):
//!    every `*/src/**/*.rs`.
//! 2. **No two files import each other** ("a contract (trait, record type) lives below its users,
//!    so imports only point down"): no cycle in the file-level import graph of any crate.
//! 3. **No ticket numbers in source names** ("name tests and modules by the behaviour they guard,
//!    never by an issue number"): no issue word followed by a number (`_`, space, `-` or `#`
//!    between) in any `.rs` under a crate's `src/` or `tests/`.
//!
//! ## What "file A imports file B" means
//! Each crate root (`src/lib.rs`, `src/main.rs`, `src/bin/*`) is walked through its `mod x;`
//! declarations, which gives each file its module path (`a/b.rs` or `a/b/mod.rs` is `a::b`).
//! Comments, string and char literals and every `#[cfg(test)]` item are removed first, so test
//! modules, inline or in their own file, are not part of the graph. A path names an item when it
//! is a `use` declaration (nested groups, `self`, `super`, `crate`, globs, `as`, `pub use`), or a
//! path in code that starts with `crate::`, `self::`, `super::`, a child module declared in the
//! file (`mod run;` … `run::execute()`) or a name the file imported (`use crate::report::svg;` …
//! `svg::line(…)`).
//!
//! A path resolves to the deepest module file that exists; its next segment is looked up there.
//! The file that defines the name (`fn`, `struct`, `enum`, `trait`, `type`, `const`, `static`,
//! `union`, `macro_rules!`, inline `mod`) is the target; a file that imports or re-exports it
//! (`use`, `pub use`, globs) is followed to the defining file; a name not found stays with the
//! deepest module file. Names from other crates are no edge: crates form a DAG already. A
//! module's `pub use child::X` is its facade, not a dependency: only user → defining file counts.
//!
//! `NEUROTAC_LAYOUT_REPORT=1 cargo test --test source_layout -- --nocapture` prints a summary of
//! the import graph even when every rule holds.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fs;
use std::path::{Path, PathBuf};

/// Longest source file allowed, in lines.
const MAX_LINES: usize = 800;

/// This file, which has to spell out the rule it checks.
const THIS_FILE: &str = "tests/source_layout.rs";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `path` relative to the workspace root, with `/` separators.
fn relative(path: &Path) -> String {
    let rel = path.strip_prefix(root()).unwrap_or(path);
    let parts: Vec<_> = rel.iter().map(|c| c.to_string_lossy()).collect();
    parts.join("/")
}

/// The root package and every top-level directory with a `Cargo.toml` and a `src/`.
fn crate_dirs() -> Vec<PathBuf> {
    let entries = fs::read_dir(root()).expect("the workspace root is readable");
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.join("Cargo.toml").is_file() && p.join("src").is_dir())
        .filter(|p| !p.ends_with("target") && !p.ends_with("fuzz"))
        .collect();
    dirs.sort();
    dirs.insert(0, root());
    dirs
}

/// Every `.rs` file below `dir`, sorted; `target/` directories skipped.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries = fs::read_dir(&dir).into_iter().flatten().flatten();
        for path in entries.map(|e| e.path()) {
            if path.is_dir() && !path.ends_with("target") {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// Every source file of every crate with its line count.
fn source_files_with_lengths() -> Vec<(String, usize)> {
    let paths = crate_dirs()
        .into_iter()
        .flat_map(|d| rust_files(&d.join("src")));
    paths
        .map(|p| (relative(&p), read(&p).lines().count()))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Reading Rust: comments and literals out, then tokens, then the facts the graph needs.

/// The source without comments, doc comments, string and char literals (a string becomes `""`,
/// a char a space, a lifetime nothing), newlines kept. A `'` opens a char literal when an escape,
/// or one char and a closing `'`, follow; otherwise a lifetime.
fn strip(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    let (mut out, mut i) = (String::with_capacity(src.len()), 0);
    while i < c.len() {
        let start = i;
        let word_before = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
        // A string's opening quote: `"`, `b"`, `c"`, `r"`, `br#"`, …
        let mut quote = i + usize::from(!word_before && matches!(at(i), 'b' | 'c'));
        let raw = !word_before && at(quote) == 'r';
        quote += usize::from(raw);
        let hashes = (quote..).take_while(|&k| raw && at(k) == '#').count();
        quote += hashes;
        if at(i) == '/' && at(i + 1) == '/' {
            i = (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len());
        } else if at(i) == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                match (at(i), at(i + 1)) {
                    ('/', '*') => (depth, i) = (depth + 1, i + 2),
                    ('*', '/') => (depth, i) = (depth - 1, i + 2),
                    _ => i += 1,
                }
                if depth == 0 {
                    break;
                }
            }
        } else if at(quote) == '"' {
            let closes = |k: usize| c[k] == '"' && (1..=hashes).all(|h| at(k + h) == '#');
            let mut k = quote + 1;
            while k < c.len() && !closes(k) {
                k += if !raw && c[k] == '\\' { 2 } else { 1 };
            }
            i = k + 1 + hashes;
            out.push_str("\"\"");
        } else if at(i) == 'b' && at(i + 1) == '\'' && !word_before {
            i += 1; // a byte char: the char literal follows
            continue;
        } else if at(i) == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            let first = if at(i + 1) == '\\' { i + 3 } else { i + 2 };
            i = (first..c.len()).find(|&k| c[k] == '\'').unwrap_or(c.len()) + 1;
            out.push(' ');
        } else if at(i) == '\'' {
            let word = |k: &usize| c[*k].is_alphanumeric() || c[*k] == '_';
            i = (i + 1..c.len()).find(|k| !word(k)).unwrap_or(c.len()); // a lifetime
        } else {
            out.push(c[i]);
            i += 1;
            continue;
        }
        out.extend(c[start..i.min(c.len())].iter().filter(|&&ch| ch == '\n'));
    }
    out
}

/// Identifiers (keywords included), `::`, and single punctuation chars; numbers become `0`.
fn tokenize(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let word = |k: usize| {
        c.get(k)
            .is_some_and(|&ch| ch.is_alphanumeric() || ch == '_')
    };
    let (mut tokens, mut i) = (Vec::new(), 0);
    while i < c.len() {
        if c[i].is_whitespace() {
            i += 1;
        } else if word(i) {
            let end = (i..=c.len()).find(|&k| !word(k)).unwrap_or(c.len());
            let digits = c[i].is_ascii_digit();
            tokens.push(if digits {
                "0".into()
            } else {
                c[i..end].iter().collect()
            });
            i = end;
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            tokens.push("::".into());
            i += 2;
        } else {
            tokens.push(c[i].to_string());
            i += 1;
        }
    }
    tokens
}

fn is_ident(token: &str) -> bool {
    token.starts_with(|c: char| c.is_alphabetic() || c == '_')
}

/// Index just past the bracket group opening at `open`.
fn skip_group(t: &[String], open: usize) -> usize {
    let mut depth = 0;
    for (k, token) in t.iter().enumerate().skip(open) {
        match token.as_str() {
            "(" | "[" | "{" => depth += 1,
            ")" | "]" | "}" if depth == 1 => return k + 1,
            ")" | "]" | "}" => depth -= 1,
            _ => {}
        }
    }
    t.len()
}

/// The tokens without `#[cfg(test)]` items: an item (`mod`, `fn`, `impl`, `use`, …) up to its `;`
/// or the end of its block, a field or statement up to its `,` or `;`. `#![cfg(test)]` empties
/// the file.
fn drop_test_items(t: Vec<String>) -> Vec<String> {
    const ITEMS: [&str; 12] = [
        "fn", "mod", "impl", "use", "struct", "enum", "trait", "type", "const", "static", "unsafe",
        "extern",
    ];
    let is = |k: usize, s: &str| t.get(k).is_some_and(|x| x == s);
    let (mut out, mut i) = (Vec::with_capacity(t.len()), 0);
    while i < t.len() {
        let bang = usize::from(is(i + 1, "!"));
        let attr = ["#", "[", "cfg", "(", "test", ")", "]"];
        let at = |k: usize| if k == 0 { i } else { i + k + bang };
        if !attr.iter().enumerate().all(|(k, s)| is(at(k), s)) {
            out.push(t[i].clone());
            i += 1;
            continue;
        }
        if bang == 1 {
            return Vec::new();
        }
        let mut j = i + attr.len();
        while is(j, "#") && is(j + 1, "[") {
            j = skip_group(&t, j + 1); // further attributes
        }
        let after_pub = if is(j + 1, "(") {
            skip_group(&t, j + 1)
        } else {
            j + 1
        };
        let first = if is(j, "pub") { after_pub } else { j };
        let item = t.get(first).is_some_and(|s| ITEMS.contains(&s.as_str()));
        let mut depth = 0;
        while j < t.len() {
            match t[j].as_str() {
                "(" | "[" | "{" => depth += 1,
                ")" | "]" | "}" if depth == 0 => break, // the enclosing block ends
                "}" if depth == 1 => {
                    j += 1;
                    break;
                }
                ")" | "]" | "}" => depth -= 1,
                ";" if depth == 0 => {
                    j += 1;
                    break;
                }
                "," if depth == 0 && !item => break,
                _ => {}
            }
            j += 1;
        }
        i = j;
    }
    out
}

/// A name a `use` declaration binds (`alias` is `*` for a glob), or a path in code (no alias).
#[derive(Debug, Clone, Default)]
struct Name {
    path: Vec<String>,
    alias: String,
    public: bool,
    /// How many inline modules of the file enclose it (`super` leaves those first).
    inline: usize,
}

/// What the graph needs from one file.
#[derive(Debug, Default)]
struct Parsed {
    /// Items defined at the top level of the file.
    defs: BTreeSet<String>,
    /// `mod x;` declarations (the ones under `#[cfg(test)]` are gone).
    mods: Vec<String>,
    uses: Vec<Name>,
    /// Paths of two or more segments in code.
    paths: Vec<Name>,
    /// Every identifier in code (what a glob import may provide).
    idents: BTreeSet<String>,
}

/// One `use` tree from `t[*i]`, under `prefix`: nested groups, `self`, globs, `as`.
fn use_tree(t: &[String], i: &mut usize, prefix: &[String], like: &Name, out: &mut Vec<Name>) {
    let mut path = prefix.to_vec();
    let name = |path: Vec<String>, alias: String| Name {
        path,
        alias,
        ..like.clone()
    };
    while let Some(token) = t.get(*i) {
        *i += 1;
        match token.as_str() {
            "{" => {
                while t.get(*i).is_some_and(|s| s != "}") {
                    let start = *i;
                    use_tree(t, i, &path, like, out);
                    *i += usize::from(*i == start || t.get(*i).is_some_and(|s| s == ","));
                }
                *i += 1;
            }
            "*" => out.push(name(path.clone(), "*".into())),
            word if is_ident(word) => {
                path.push(word.to_string());
                if t.get(*i).is_some_and(|s| s == "::") {
                    *i += 1;
                    continue;
                }
                if path.last().is_some_and(|s| s == "self") {
                    path.pop();
                }
                let mut alias = path.last().cloned().unwrap_or_default();
                if t.get(*i).is_some_and(|s| s == "as") {
                    alias = t.get(*i + 1).cloned().unwrap_or_default();
                    *i += 2;
                }
                out.push(name(path.clone(), alias));
            }
            _ => *i -= 1,
        }
        return;
    }
}

fn parse(src: &str) -> Parsed {
    let t = drop_test_items(tokenize(&strip(src)));
    let tok = |k: usize| t.get(k).map_or("", String::as_str);
    let mut p = Parsed::default();
    let (mut depth, mut inline, mut i) = (0, Vec::new(), 0);
    while i < t.len() {
        let word = tok(i);
        match word {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if inline.last() == Some(&depth) {
                    inline.pop();
                }
            }
            "use" => {
                let before = |k: usize| i.checked_sub(k).map_or("", tok);
                let public = before(1) == "pub" || (before(1) == ")" && before(4) == "pub");
                let like = Name {
                    public,
                    inline: inline.len(),
                    ..Name::default()
                };
                i += 1 + usize::from(tok(i + 1) == "::");
                use_tree(&t, &mut i, &[], &like, &mut p.uses);
                continue;
            }
            "mod" if tok(i + 2) == ";" => p.mods.push(tok(i + 1).to_string()),
            "mod" if tok(i + 2) == "{" => {
                if depth == 0 {
                    p.defs.insert(tok(i + 1).to_string());
                }
                inline.push(depth);
            }
            "fn" | "struct" | "enum" | "trait" | "type" | "const" | "static" | "union"
                if depth == 0 =>
            {
                let name = tok(i + 1 + usize::from(tok(i + 1) == "mut"));
                let keyword = matches!(name, "fn" | "unsafe" | "async" | "extern" | "_");
                let union = word != "union" || matches!(tok(i + 2), "{" | "<");
                if is_ident(name) && !keyword && union {
                    p.defs.insert(name.to_string());
                }
            }
            "macro_rules" if depth == 0 && tok(i + 1) == "!" => {
                p.defs.insert(tok(i + 2).to_string());
            }
            _ => {}
        }
        if is_ident(word) {
            p.idents.insert(word.to_string());
            if (i == 0 || tok(i - 1) != "::") && tok(i + 1) == "::" && is_ident(tok(i + 2)) {
                let mut path = vec![word.to_string()];
                let mut k = i + 1;
                while tok(k) == "::" && is_ident(tok(k + 1)) {
                    path.push(tok(k + 1).to_string());
                    k += 2;
                }
                p.paths.push(Name {
                    path,
                    inline: inline.len(),
                    ..Name::default()
                });
            }
        }
        i += 1;
    }
    p
}

// ---------------------------------------------------------------------------------------------
// The file graph.

struct SourceFile {
    path: String,
    /// The crate root (library or binary) the file belongs to.
    unit: usize,
    module: Vec<String>,
    parsed: Parsed,
}

/// Where a path leads.
enum Target {
    Module,
    /// The file that defines the named item.
    Defined(usize, String),
    /// The name was not found: the deepest module file on the path.
    Guessed(usize, String),
    /// Another crate, or a name local to a file.
    Elsewhere,
}

#[derive(Default)]
struct Graph {
    files: Vec<SourceFile>,
    /// Per crate root: module path → file.
    modules: Vec<HashMap<Vec<String>, usize>>,
    /// (user, defining file) → the items behind the edge.
    edges: BTreeMap<(usize, usize), BTreeSet<String>>,
}

fn concat(a: &[String], b: &[String]) -> Vec<String> {
    a.iter().chain(b).cloned().collect()
}

impl Graph {
    /// Walks the crate roots of every crate through their `mod` declarations, then links files.
    fn build() -> Graph {
        let mut g = Graph::default();
        for dir in crate_dirs() {
            let (src, bin) = (dir.join("src"), dir.join("src/bin"));
            let roots = [src.join("lib.rs"), src.join("main.rs")].into_iter().chain(
                rust_files(&bin)
                    .into_iter()
                    .filter(|p| p.parent() == Some(bin.as_path()) || p.ends_with("main.rs")),
            );
            for root in roots.filter(|p| p.is_file()) {
                g.add_unit(root);
            }
        }
        for f in 0..g.files.len() {
            for (to, name) in g.imports_of(f) {
                if to != f {
                    g.edges.entry((f, to)).or_default().insert(name);
                }
            }
        }
        g
    }

    fn add_unit(&mut self, root: PathBuf) {
        let unit = self.modules.len();
        self.modules.push(HashMap::new());
        let mut stack = vec![(root, Vec::<String>::new())];
        while let Some((path, module)) = stack.pop() {
            let parsed = parse(&read(&path));
            let mut dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
            if !module.is_empty() && !path.ends_with("mod.rs") {
                dir = dir.join(path.file_stem().unwrap_or_default());
            }
            for child in &parsed.mods {
                let files = [
                    dir.join(format!("{child}.rs")),
                    dir.join(child).join("mod.rs"),
                ];
                if let Some(file) = files.into_iter().find(|p| p.is_file()) {
                    stack.push((file, concat(&module, std::slice::from_ref(child))));
                }
            }
            self.modules[unit].insert(module.clone(), self.files.len());
            self.files.push(SourceFile {
                path: relative(&path),
                unit,
                module,
                parsed,
            });
        }
    }

    /// `name`'s path as written in file `f`, made absolute in its crate; `None` if it leaves
    /// the crate or stays inside an inline module of the file.
    fn absolute(&self, f: usize, name: &Name, depth: usize) -> Option<Vec<String>> {
        let (file, path) = (&self.files[f], &name.path);
        match path.first()?.as_str() {
            "crate" => Some(path[1..].to_vec()),
            "self" if name.inline == 0 => Some(concat(&file.module, &path[1..])),
            "super" => {
                let supers = path.iter().take_while(|s| *s == "super").count();
                let up = supers.checked_sub(name.inline).filter(|&up| up > 0)?;
                let parent = file.module.len().checked_sub(up)?;
                Some(concat(&file.module[..parent], &path[supers..]))
            }
            _ if self.modules[file.unit].contains_key(&concat(&file.module, &path[..1])) => {
                Some(concat(&file.module, path)) // a child module
            }
            first if depth < 8 => {
                let uses = &file.parsed.uses;
                let bound = uses.iter().find(|u| u.alias == first && u.path.len() > 1)?;
                Some(concat(&self.absolute(f, bound, depth + 1)?, &path[1..]))
            }
            _ => None,
        }
    }

    /// Follows an absolute path of crate root `unit` to the file that defines what it names.
    fn resolve(&self, unit: usize, path: &[String], depth: usize) -> Target {
        let modules = &self.modules[unit];
        let known = |k: &usize| modules.contains_key(&path[..*k]);
        let k = (0..=path.len()).rev().find(known).unwrap_or(0); // the crate root is known
        let m = modules[&path[..k]];
        let Some(name) = path.get(k) else {
            return Target::Module;
        };
        let parsed = &self.files[m].parsed;
        if parsed.defs.contains(name) {
            return Target::Defined(m, name.clone());
        }
        if depth > 8 {
            return Target::Elsewhere;
        }
        if let Some(u) = parsed.uses.iter().find(|u| &u.alias == name) {
            return match self.absolute(m, u, 0) {
                Some(base) => self.resolve(unit, &concat(&base, &path[k + 1..]), depth + 1),
                None => Target::Elsewhere, // imported from another crate
            };
        }
        for glob in parsed.uses.iter().filter(|u| u.alias == "*") {
            if let Some(base) = self.absolute(m, glob, 0) {
                let found = self.resolve(unit, &concat(&base, &path[k..]), depth + 1);
                if matches!(found, Target::Module | Target::Defined(..)) {
                    return found;
                }
            }
        }
        Target::Guessed(m, name.clone())
    }

    /// The files `f` imports, with the item behind each: `use` declarations, then code paths.
    fn imports_of(&self, f: usize) -> Vec<(usize, String)> {
        let (file, mut targets) = (&self.files[f], Vec::new());
        let resolve = |path: &[String]| self.resolve(file.unit, path, 0);
        for u in &file.parsed.uses {
            let Some(base) = self.absolute(f, u, 0) else {
                continue;
            };
            let facade =
                u.public && base.len() > file.module.len() && base.starts_with(&file.module);
            if u.alias != "*" && !facade {
                targets.push(resolve(&base));
            } else if u.alias == "*" && !matches!(resolve(&base), Target::Module) {
                targets.push(resolve(&base)); // the variants of an enum
            } else if u.alias == "*" {
                for name in file.parsed.idents.difference(&file.parsed.defs) {
                    let found = resolve(&concat(&base, std::slice::from_ref(name)));
                    if matches!(found, Target::Defined(..)) {
                        targets.push(found);
                    }
                }
            }
        }
        for path in &file.parsed.paths {
            if let Some(base) = self.absolute(f, path, 0) {
                targets.push(resolve(&base));
            }
        }
        let items = targets.into_iter().filter_map(|t| match t {
            Target::Defined(file, name) | Target::Guessed(file, name) => Some((file, name)),
            _ => None,
        });
        items.collect()
    }

    /// Strongly connected components of more than one file (Tarjan), each sorted by path.
    fn cycles(&self) -> Vec<Vec<usize>> {
        struct Tarjan {
            next: Vec<Vec<usize>>,
            index: Vec<usize>, // usize::MAX: not visited yet
            low: Vec<usize>,
            stack: Vec<usize>,
            found: Vec<Vec<usize>>,
        }
        fn visit(s: &mut Tarjan, v: usize, counter: &mut usize) {
            (s.index[v], s.low[v], *counter) = (*counter, *counter, *counter + 1);
            s.stack.push(v);
            for w in s.next[v].clone() {
                if s.index[w] == usize::MAX {
                    visit(s, w, counter);
                    s.low[v] = s.low[v].min(s.low[w]);
                } else if s.stack.contains(&w) {
                    s.low[v] = s.low[v].min(s.index[w]);
                }
            }
            if s.low[v] == s.index[v] {
                let at = s.stack.iter().rposition(|&w| w == v).unwrap_or(0);
                let component: Vec<usize> = s.stack.split_off(at);
                if component.len() > 1 {
                    s.found.push(component);
                }
            }
        }
        let n = self.files.len();
        let mut next = vec![Vec::new(); n];
        self.edges.keys().for_each(|&(a, b)| next[a].push(b));
        let (index, low, stack, found) = (vec![usize::MAX; n], vec![0; n], vec![], vec![]);
        let mut s = Tarjan {
            next,
            index,
            low,
            stack,
            found,
        };
        let mut counter = 0;
        for v in 0..n {
            if s.index[v] == usize::MAX {
                visit(&mut s, v, &mut counter);
            }
        }
        let path = |f: &usize| self.files[*f].path.clone();
        s.found.iter_mut().for_each(|c| c.sort_by_key(path));
        s.found.sort_by_key(|c| path(&c[0]));
        s.found
    }

    /// A cycle's files and the edges inside it, with the items behind each edge.
    fn describe(&self, component: &[usize]) -> String {
        let path = |f: usize| self.files[f].path.as_str();
        let mut text = format!("({} files):\n", component.len());
        for &f in component {
            text += &format!("    {}\n", path(f));
        }
        text += "  edges (user → defining file (items)):\n";
        for ((a, b), items) in &self.edges {
            if component.contains(a) && component.contains(b) {
                let items: Vec<&str> = items.iter().map(String::as_str).collect();
                let items = items.join(", ");
                text += &format!("    {} → {} ({items})\n", path(*a), path(*b));
            }
        }
        text
    }
}

// ---------------------------------------------------------------------------------------------
// The rules.

#[test]
fn no_source_file_is_longer_than_800_lines() {
    let long: Vec<String> = source_files_with_lengths()
        .into_iter()
        .filter(|(_, lines)| *lines > MAX_LINES)
        .map(|(path, lines)| format!("  {path}: {lines} lines"))
        .collect();
    assert!(
        long.is_empty(),
        "{} source file(s) longer than {MAX_LINES} lines; split each by concept (STYLE.md, \
         Layout):\n{}",
        long.len(),
        long.join("\n")
    );
}

#[test]
fn no_two_files_import_each_other() {
    let graph = Graph::build();
    let cycles = graph.cycles();
    if std::env::var("NEUROTAC_LAYOUT_REPORT").is_ok_and(|v| v == "1") {
        let mut sizes = source_files_with_lengths();
        sizes.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let (files, edges, roots) = (graph.files.len(), graph.edges.len(), graph.modules.len());
        println!(
            "import graph: {files} files under {roots} crate roots, {edges} edges, {} cycle(s)",
            cycles.len()
        );
        println!("largest files:");
        for (path, lines) in sizes.iter().take(5) {
            println!("  {path}: {lines} lines");
        }
    }
    let described: Vec<String> = cycles
        .iter()
        .enumerate()
        .map(|(k, c)| format!("cycle {} {}", k + 1, graph.describe(c)))
        .collect();
    assert!(
        cycles.is_empty(),
        "{} import cycle(s) between files; move the named items (or the contract they belong \
         to) below their users, so imports only point down (STYLE.md, Layout):\n{}",
        cycles.len(),
        described.join("\n")
    );
}

/// Does `line` hold the issue word (any case) followed by a number? The word is built from
/// pieces so that this file does not match itself.
fn names_a_ticket(line: &str) -> bool {
    let word = ["iss", "ue"].concat();
    let lower = line.to_lowercase();
    let b = lower.as_bytes();
    lower.match_indices(&word).any(|(at, _)| {
        let word_start = at == 0 || !b[at - 1].is_ascii_alphanumeric(); // not "tissue"
        let mut k = at + word.len();
        k += usize::from(matches!(b.get(k), Some(b'_' | b' ' | b'-')));
        k += usize::from(b.get(k) == Some(&b'#'));
        word_start && b.get(k).is_some_and(u8::is_ascii_digit)
    })
}

#[test]
fn no_ticket_numbers_in_source_names() {
    let (mut hits, mut per_file) = (Vec::new(), Vec::new());
    let dirs = crate_dirs()
        .into_iter()
        .flat_map(|d| [d.join("src"), d.join("tests")]);
    for path in dirs.flat_map(|d| rust_files(&d)) {
        let rel = relative(&path);
        let before = hits.len();
        for (n, line) in read(&path).lines().enumerate() {
            if rel != THIS_FILE && names_a_ticket(line) {
                hits.push(format!("  {rel}:{}: {}", n + 1, line.trim()));
            }
        }
        if hits.len() > before {
            per_file.push(format!("  {rel}: {}", hits.len() - before));
        }
    }
    assert!(
        hits.is_empty(),
        "{} line(s) name a ticket number; say what the code or test guards instead (STYLE.md, \
         Naming):\n{}\nper file:\n{}",
        hits.len(),
        hits.join("\n"),
        per_file.join("\n")
    );
}
