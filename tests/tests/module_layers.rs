//! Modules of a crate form layers: a module imports those below it, never one above. A circle
//! of imports through three or more files means the layers have run together (the harness
//! was five jobs in one crate that way), and once there it only grows. This test reads every
//! workspace crate's sources, follows each `use` and each `crate::`, `super::` and `self::`
//! path (and a path through a child module) to the file that defines it, and fails naming
//! each circle of more than two files.
//!
//! In the mission crates (the harness and the crates split from it) two files may import
//! each other only as a module and its own submodule (a `mod.rs` re-exporting what its child
//! defines, the child using its parent's items): two sibling modules that import each other
//! are one module in two files, or a layer inverted, and fail too.
use proc_macro2::{Delimiter, TokenStream, TokenTree};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use system_tests::workspace_root;

/// The mission crates, held to the stricter rule of the header.
const MISSION_CRATES: &[&str] = &["lander", "campaign", "report", "harness"];

/// One file of a crate's module tree.
struct File {
    /// Relative to the crate.
    path: PathBuf,
    /// The module the file defines (empty for a crate root).
    module: Vec<String>,
}

/// A crate root's module tree: every file with the module it defines.
struct Tree {
    files: Vec<File>,
    by_module: BTreeMap<Vec<String>, usize>,
}

fn parse(path: &Path) -> TokenStream {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: not Rust tokens: {e:?}", path.display()))
}

/// `mod name;` declarations of a token stream, with the inline modules they sit in.
fn declared(tokens: TokenStream, inside: &[String], out: &mut Vec<Vec<String>>) {
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    for (k, token) in tokens.iter().enumerate() {
        if let TokenTree::Ident(word) = token {
            if word != "mod" {
                continue;
            }
            let Some(TokenTree::Ident(name)) = tokens.get(k + 1) else {
                continue;
            };
            let mut module = inside.to_vec();
            module.push(name.to_string());
            match tokens.get(k + 2) {
                Some(TokenTree::Punct(p)) if p.as_char() == ';' => out.push(module),
                Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => {
                    declared(g.stream(), &module, out)
                }
                _ => {}
            }
        } else if let TokenTree::Group(g) = token {
            declared(g.stream(), inside, out);
        }
    }
}

/// The module tree grown from the root file `root` (relative to `dir`, the crate) through its
/// `mod` declarations.
fn tree(dir: &Path, root: &Path) -> Tree {
    let mut tree = Tree {
        files: Vec::new(),
        by_module: BTreeMap::new(),
    };
    let mut pending = vec![(root.to_path_buf(), Vec::<String>::new())];
    while let Some((path, module)) = pending.pop() {
        // Where this file's child modules live: beside a crate root or mod.rs, else in the
        // directory named after the file.
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let base = if module.is_empty() || name == "mod.rs" {
            path.parent().unwrap().to_path_buf()
        } else {
            path.with_extension("")
        };
        let mut children = Vec::new();
        declared(parse(&dir.join(&path)), &[], &mut children);
        for child in children {
            let mut location = base.clone();
            for part in &child[..child.len() - 1] {
                location.push(part);
            }
            let last = child.last().unwrap();
            let flat = location.join(format!("{last}.rs"));
            let nested = location.join(last).join("mod.rs");
            let found = if dir.join(&flat).is_file() {
                flat
            } else if dir.join(&nested).is_file() {
                nested
            } else {
                // `#[path]` or a generated file: out of this test's reach.
                continue;
            };
            let mut full = module.clone();
            full.extend(child);
            pending.push((found, full));
        }
        tree.by_module.insert(module.clone(), tree.files.len());
        tree.files.push(File { path, module });
    }
    tree
}

/// An import of one file by another, with the path that makes it.
type Edges = BTreeMap<(usize, usize), String>;

/// A path a file names, in the module it is written in.
struct Reference {
    file: usize,
    module: Vec<String>,
    segments: Vec<String>,
    kind: Kind,
}

enum Kind {
    /// A path in an expression, a type or a macro's arguments.
    Path,
    /// A `use`, bringing `name` into the module (`None` for a glob). A `pub use` re-exports:
    /// a path through it is followed to what it names, and it is no import of its own (a
    /// facade of its children is not a layer above them).
    Use { name: Option<String>, public: bool },
}

fn is_path_sep(tokens: &[TokenTree], k: usize) -> bool {
    matches!((tokens.get(k), tokens.get(k + 1)),
        (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b))) if a.as_char() == ':' && b.as_char() == ':')
}

/// Resolves `segments` as written in module `current` to an absolute module path; `None` for
/// a path that does not start inside the crate.
fn absolute(segments: &[String], current: &[String], tree: &Tree) -> Option<Vec<String>> {
    let mut at = current.to_vec();
    let mut rest = segments;
    match segments.first().map(String::as_str) {
        Some("crate") => {
            at.clear();
            rest = &segments[1..];
        }
        Some("self") => rest = &segments[1..],
        Some("super") => {
            while rest.first().is_some_and(|s| s == "super") {
                at.pop()?;
                rest = &rest[1..];
            }
            if rest.first().is_some_and(|s| s == "self") {
                rest = &rest[1..];
            }
        }
        Some(first) => {
            // A path through a child module of this one (2018 paths).
            let mut child = current.to_vec();
            child.push(first.to_owned());
            if !tree.by_module.contains_key(&child) {
                return None;
            }
        }
        None => return None,
    }
    at.extend(rest.iter().cloned());
    Some(at)
}

/// What each module's `use`s bring in: (module, name) to the absolute path named.
type Aliases = BTreeMap<(Vec<String>, String), Vec<String>>;

/// The file defining what the absolute `path` names: the longest module prefix, followed
/// through the `use`s of that module.
fn target(path: &[String], tree: &Tree, aliases: &Aliases) -> Option<usize> {
    let mut path = path.to_vec();
    // Bounded: re-exports may (wrongly) name each other.
    for _ in 0..16 {
        let n = (0..=path.len())
            .rev()
            .find(|&n| tree.by_module.contains_key(&path[..n]))?;
        match path
            .get(n)
            .and_then(|name| aliases.get(&(path[..n].to_vec(), name.clone())))
        {
            Some(named) if n < path.len() => {
                let mut next = named.clone();
                next.extend(path[n + 1..].iter().cloned());
                if next == path {
                    return tree.by_module.get(&path[..n]).copied();
                }
                path = next;
            }
            _ => return tree.by_module.get(&path[..n]).copied(),
        }
    }
    None
}

/// The paths of a `use` tree with the name each brings in: `a::b::{c, d::e as f, self, *}`
/// gives `a::b::c` (c), `a::b::d::e` (f), `a::b` (b) and `a::b` (a glob).
fn use_paths(
    tokens: &[TokenTree],
    prefix: &[String],
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let mut path = prefix.to_vec();
    let mut alias = None;
    let mut glob = false;
    let mut grouped = false;
    let mut k = 0;
    while k < tokens.len() {
        match &tokens[k] {
            TokenTree::Ident(word) if word == "as" => {
                if let Some(TokenTree::Ident(name)) = tokens.get(k + 1) {
                    alias = Some(name.to_string());
                }
                k += 1;
            }
            TokenTree::Ident(word) => path.push(word.to_string()),
            TokenTree::Punct(p) if p.as_char() == '*' => glob = true,
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => {
                let inner: Vec<TokenTree> = g.stream().into_iter().collect();
                for part in inner.split(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ','))
                {
                    use_paths(part, &path, out);
                }
                grouped = true;
            }
            _ => {}
        }
        k += 1;
    }
    if grouped || path.len() == prefix.len() && !glob {
        return;
    }
    if glob {
        out.push((path, None));
        return;
    }
    if path.last().is_some_and(|s| s == "self") {
        path.pop();
    }
    let name = alias.or_else(|| path.last().cloned());
    out.push((path, name));
}

/// Every path the tokens name, in module `current` of file `file`.
fn references(tokens: TokenStream, file: usize, current: &[String], out: &mut Vec<Reference>) {
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    let mut k = 0;
    while k < tokens.len() {
        match &tokens[k] {
            TokenTree::Ident(word) if word == "mod" => {
                if let (Some(TokenTree::Ident(name)), Some(TokenTree::Group(g))) =
                    (tokens.get(k + 1), tokens.get(k + 2))
                {
                    if g.delimiter() == Delimiter::Brace {
                        let mut inner = current.to_vec();
                        inner.push(name.to_string());
                        references(g.stream(), file, &inner, out);
                        k += 3;
                        continue;
                    }
                }
                k += 1;
            }
            TokenTree::Ident(word) if word == "use" => {
                // `pub use` and `pub(crate) use` alike.
                let public = match (k.checked_sub(1).map(|j| &tokens[j]), k.checked_sub(2)) {
                    (Some(TokenTree::Ident(p)), _) => p == "pub",
                    (Some(TokenTree::Group(g)), Some(j)) => {
                        g.delimiter() == Delimiter::Parenthesis
                            && matches!(&tokens[j], TokenTree::Ident(p) if p == "pub")
                    }
                    _ => false,
                };
                let end = tokens[k..]
                    .iter()
                    .position(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ';'))
                    .map_or(tokens.len(), |n| k + n);
                let mut paths = Vec::new();
                use_paths(&tokens[k + 1..end], &[], &mut paths);
                for (segments, name) in paths {
                    out.push(Reference {
                        file,
                        module: current.to_vec(),
                        segments,
                        kind: Kind::Use { name, public },
                    });
                }
                k = end + 1;
            }
            TokenTree::Ident(word) => {
                // `crate::a::b`, `super::c`, `child::d`, not the tail of a longer path.
                let after_sep = k >= 2 && is_path_sep(&tokens, k - 2);
                let dollar =
                    k >= 1 && matches!(&tokens[k - 1], TokenTree::Punct(p) if p.as_char() == '$');
                if after_sep || dollar || !is_path_sep(&tokens, k + 1) {
                    k += 1;
                    continue;
                }
                let mut segments = vec![word.to_string()];
                let mut j = k + 1;
                while is_path_sep(&tokens, j) {
                    match tokens.get(j + 2) {
                        Some(TokenTree::Ident(next)) => {
                            segments.push(next.to_string());
                            j += 3;
                        }
                        _ => break,
                    }
                }
                out.push(Reference {
                    file,
                    module: current.to_vec(),
                    segments,
                    kind: Kind::Path,
                });
                k = j;
            }
            TokenTree::Group(g) => {
                references(g.stream(), file, current, out);
                k += 1;
            }
            _ => k += 1,
        }
    }
}

/// The imports between the files of `tree`, from every path they name.
fn edges(dir: &Path, tree: &Tree) -> Edges {
    let mut all = Vec::new();
    for (k, file) in tree.files.iter().enumerate() {
        references(parse(&dir.join(&file.path)), k, &file.module, &mut all);
    }
    let mut aliases = Aliases::new();
    for r in &all {
        if let Kind::Use {
            name: Some(name), ..
        } = &r.kind
        {
            if let Some(path) = absolute(&r.segments, &r.module, tree) {
                aliases.insert((r.module.clone(), name.clone()), path);
            }
        }
    }
    let mut edges = Edges::new();
    for r in &all {
        if matches!(r.kind, Kind::Use { public: true, .. }) {
            continue;
        }
        let Some(path) = absolute(&r.segments, &r.module, tree) else {
            continue;
        };
        if let Some(to) = target(&path, tree, &aliases) {
            if to != r.file {
                edges
                    .entry((r.file, to))
                    .or_insert_with(|| r.segments.join("::"));
            }
        }
    }
    edges
}

/// Strongly connected components of the file graph (Tarjan), each as file indices.
fn components(n: usize, edges: &Edges) -> Vec<Vec<usize>> {
    struct State<'a> {
        next: Vec<Vec<usize>>,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        counter: usize,
        out: Vec<Vec<usize>>,
        _edges: &'a Edges,
    }
    fn visit(v: usize, s: &mut State<'_>) {
        s.index[v] = Some(s.counter);
        s.low[v] = s.counter;
        s.counter += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for w in s.next[v].clone() {
            match s.index[w] {
                None => {
                    visit(w, s);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(i) if s.on_stack[w] => s.low[v] = s.low[v].min(i),
                _ => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            s.out.push(component);
        }
    }
    let mut next = vec![Vec::new(); n];
    for &(a, b) in edges.keys() {
        next[a].push(b);
    }
    let mut s = State {
        next,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        counter: 0,
        out: Vec::new(),
        _edges: edges,
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(v, &mut s);
        }
    }
    s.out.into_iter().filter(|c| c.len() > 1).collect()
}

/// The files of `component` and every import between them, as `a.rs -> b.rs (b::x)`.
fn circle(component: &[usize], tree: &Tree, edges: &Edges) -> String {
    let inside: BTreeSet<usize> = component.iter().copied().collect();
    let mut files: Vec<String> = component
        .iter()
        .map(|&f| tree.files[f].path.display().to_string())
        .collect();
    files.sort();
    let imports: Vec<String> = edges
        .iter()
        .filter(|((a, b), _)| inside.contains(a) && inside.contains(b))
        .map(|((a, b), path)| {
            format!(
                "{} -> {} ({path})",
                tree.files[*a].path.display(),
                tree.files[*b].path.display()
            )
        })
        .collect();
    format!(
        "a circle of {} files: {}; their imports of each other: {}",
        files.len(),
        files.join(", "),
        imports.join("; ")
    )
}

/// The workspace's member crates: name and directory.
fn members() -> Vec<(String, PathBuf)> {
    let root = workspace_root();
    // A member `fmu-*` stands for several folders: expanded as cargo expands it.
    fmu_metadata::workspace_members(&root)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .map(|m| {
            let dir = root.join(m);
            let own: toml::Table = std::fs::read_to_string(dir.join("Cargo.toml"))
                .unwrap()
                .parse()
                .unwrap();
            (own["package"]["name"].as_str().unwrap().to_owned(), dir)
        })
        .collect()
}

/// The crate roots of a crate, relative to it: the library, the binary, `src/bin/*`.
fn roots(dir: &Path) -> Vec<PathBuf> {
    let mut roots: Vec<PathBuf> = ["src/lib.rs", "src/main.rs"]
        .iter()
        .map(PathBuf::from)
        .filter(|p| dir.join(p).is_file())
        .collect();
    if let Ok(entries) = std::fs::read_dir(dir.join("src/bin")) {
        let mut bins: Vec<PathBuf> = entries
            .filter_map(|e| e.ok())
            .map(|e| e.path())
            .filter_map(|p| {
                let name = p.file_name()?.to_owned();
                if p.is_dir() && p.join("main.rs").is_file() {
                    Some(Path::new("src/bin").join(name).join("main.rs"))
                } else if p.extension().is_some_and(|e| e == "rs") {
                    Some(Path::new("src/bin").join(name))
                } else {
                    None
                }
            })
            .collect();
        bins.sort();
        roots.extend(bins);
    }
    roots
}

/// Every forbidden circle of one crate, described.
fn circles(name: &str, dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    for root in roots(dir) {
        let tree = tree(dir, &root);
        let edges = edges(dir, &tree);
        for component in components(tree.files.len(), &edges) {
            let nested = |a: &File, b: &File| {
                a.module.len() + 1 == b.module.len() && b.module.starts_with(&a.module)
            };
            let allowed_pair = component.len() == 2 && {
                let (a, b) = (&tree.files[component[0]], &tree.files[component[1]]);
                !MISSION_CRATES.contains(&name) || nested(a, b) || nested(b, a)
            };
            if !allowed_pair {
                found.push(format!("{name}: {}", circle(&component, &tree, &edges)));
            }
        }
    }
    found.sort();
    found.dedup();
    found
}

#[test]
fn no_crate_has_a_module_circle_of_more_than_two_files() {
    let members = members();
    assert!(
        members.iter().any(|(name, _)| name == "harness"),
        "the workspace members were not read"
    );
    let mut failures = Vec::new();
    for (name, dir) in &members {
        failures.extend(circles(name, dir));
    }
    assert!(
        failures.is_empty(),
        "module circles (a module imports one above it):\n{}",
        failures.join("\n")
    );
}

/// The parser must see the circles it is there to catch.
#[test]
fn a_circle_through_three_files_is_found() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(src.join("verdict")).unwrap();
    let write = |path: &str, text: &str| std::fs::write(src.join(path), text).unwrap();
    write(
        "lib.rs",
        "pub mod scenarios;\npub mod retarget;\npub mod verdict;\n",
    );
    write("scenarios.rs", "pub fn f() { crate::retarget::g() }\n");
    write(
        "retarget.rs",
        "use super::verdict::{self, scenario::h};\npub fn g() {}\n",
    );
    write("verdict/mod.rs", "pub mod scenario;\n");
    write(
        "verdict/scenario.rs",
        "use crate::{scenarios::f as load};\n#[cfg(test)]\nmod tests { use super::*; }\n",
    );
    let found = circles("anything", dir.path());
    assert_eq!(found.len(), 1, "{found:?}");
    for import in [
        "src/scenarios.rs -> src/retarget.rs (crate::retarget::g)",
        "src/retarget.rs -> src/verdict/scenario.rs (super::verdict::scenario::h)",
        "src/verdict/scenario.rs -> src/scenarios.rs (crate::scenarios::f)",
    ] {
        assert!(found[0].contains(import), "{import}: {found:?}");
    }
    // Two sibling files importing each other pass elsewhere, not in a mission crate.
    write("retarget.rs", "use crate::scenarios::f;\npub fn g() {}\n");
    assert!(circles("anything", dir.path()).is_empty());
    let found = circles("lander", dir.path());
    assert_eq!(found.len(), 1, "{found:?}");
}
