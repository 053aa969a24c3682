//! Data flows one way. Between crates Cargo itself refuses a cycle, and
//! `the_crates_follow_the_data_flow` pins their order; inside each crate no
//! module may reach back to a module that depends on it, between the
//! top-level modules nor between the files and folders of one folder.
//!
//! Read from the source. Every path a file names (`crate::…`, `super::…`,
//! `self::…`, a child module's name, and each path of a `use` tree) is
//! followed through the `pub use` re-exports to the module that defines
//! what it names, so `crate::Texture` in the texture crate is an edge
//! to `sample/texture.rs`. The edge joins the two modules' branches below
//! their deepest common folder: `app/view/cost.rs` naming `app::state` is the
//! edge view → state of `app/`. A folder's `mod.rs` that only declares and
//! re-exports is no node of its folder; one that defines items is (shown as
//! the folder's name in brackets), and then everything it re-exports counts
//! as its edges, since its items may use them. Paths into other crates
//! (`relief_scene::…`) are no edge inside a crate. Comment lines and test
//! modules (`#[cfg(test)]` onwards) are left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// A module path below the crate root (`["texture", "sample", "level"]`).
type ModPath = Vec<String>;

/// One source file: its module, its code, whether it defines items.
struct File {
    module: ModPath,
    code: String,
    /// `mod.rs` or `lib.rs`: its module has children.
    is_folder: bool,
}

/// The workspace's crates, leaves first, as the data flows: each may depend
/// only on crates before it. `.` is the root package (the application).
const CRATES: [&str; 9] = [
    "crates/core",
    "crates/texture",
    "crates/plasma",
    "crates/scene",
    "crates/pipeline",
    "crates/options",
    "crates/term",
    "crates/bench",
    ".",
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn src_files(krate: &str) -> Vec<File> {
    let src = root().join(krate).join("src");
    let mut files = Vec::new();
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path.strip_prefix(&src).unwrap();
            let mut module: ModPath = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().to_string())
                .collect();
            let last = module.pop().unwrap();
            // The binary is a crate of its own, naming the library as `relief::`.
            if module.is_empty() && last == "main.rs" {
                continue;
            }
            let is_folder = last == "mod.rs" || last == "lib.rs";
            if !is_folder {
                module.push(last.trim_end_matches(".rs").to_string());
            }
            let text = std::fs::read_to_string(&path).unwrap();
            // Test modules may reach anywhere.
            let code = text.split("#[cfg(test)]").next().unwrap_or("");
            let code: String = code
                .lines()
                .filter(|l| !l.trim_start().starts_with("//"))
                .map(|l| format!("{l}\n"))
                .collect();
            files.push(File {
                module,
                code,
                is_folder,
            });
        }
    }
    files.sort_by(|a, b| a.module.cmp(&b.module));
    files
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Parses a path or a `use` tree at `s[i..]` into the paths it names (each
/// a list of segments, `*` and `as` dropped); returns them and where it stopped.
fn parse_tree(s: &[char], mut i: usize) -> (Vec<Vec<String>>, usize) {
    let skip = |i: &mut usize| {
        while *i < s.len() && s[*i].is_whitespace() {
            *i += 1;
        }
    };
    let mut prefix = Vec::new();
    loop {
        skip(&mut i);
        if i < s.len() && s[i] == '{' {
            i += 1;
            let mut out = Vec::new();
            loop {
                skip(&mut i);
                if i >= s.len() {
                    return (out, i);
                }
                if s[i] == '}' {
                    i += 1;
                    break;
                }
                if s[i] == ',' {
                    i += 1;
                    continue;
                }
                let (paths, next) = parse_tree(s, i);
                if next == i {
                    // Not a path: give up on this group.
                    return (out, i);
                }
                for p in paths {
                    let mut full = prefix.clone();
                    full.extend(p);
                    out.push(full);
                }
                i = next;
            }
            return (out, i);
        }
        let start = i;
        if i < s.len() && s[i] == '$' {
            i += 1;
        }
        while i < s.len() && is_ident(s[i]) {
            i += 1;
        }
        if i == start {
            // `*` or nothing: the path ends at its prefix.
            if i < s.len() && s[i] == '*' {
                i += 1;
            }
            return (vec![prefix], i);
        }
        let seg: String = s[start..i].iter().collect();
        prefix.push(seg.trim_start_matches('$').to_string());
        skip(&mut i);
        if i + 1 < s.len() && s[i] == ':' && s[i + 1] == ':' {
            i += 2;
            continue;
        }
        // `as name`: the alias does not change what is named.
        let rest: String = s[i..(i + 3).min(s.len())].iter().collect();
        if rest == "as " {
            i += 3;
            skip(&mut i);
            while i < s.len() && is_ident(s[i]) {
                i += 1;
            }
        }
        return (vec![prefix], i);
    }
}

/// The module a file's path starts from: `crate`, `super`, `self`, or a
/// child of `module` (`None`: an outside crate or a local name).
fn absolute(module: &ModPath, path: &[String], modules: &BTreeSet<ModPath>) -> Option<ModPath> {
    let mut at = module.clone();
    let mut rest = path;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            at.clear();
            rest = &rest[1..];
        }
        Some("super" | "self") => {
            while let Some(first) = rest.first() {
                match first.as_str() {
                    "super" => {
                        at.pop();
                    }
                    "self" => {}
                    _ => break,
                }
                rest = &rest[1..];
            }
        }
        Some(child) => {
            let mut sub = module.clone();
            sub.push(child.to_string());
            if !modules.contains(&sub) {
                return None;
            }
        }
        None => return None,
    }
    // `{self, …}` in a group names the group's module.
    let mut out = at;
    out.extend(rest.iter().filter(|s| *s != "self").cloned());
    Some(out)
}

/// Every absolute path a file names, and those it re-exports (`pub use`).
fn named_paths(file: &File, modules: &BTreeSet<ModPath>) -> (Vec<ModPath>, Vec<ModPath>) {
    let s: Vec<char> = file.code.chars().collect();
    let mut named = Vec::new();
    let mut exported = Vec::new();
    let children: BTreeSet<&str> = modules
        .iter()
        .filter(|m| m.len() == file.module.len() + 1 && m.starts_with(&file.module))
        .map(|m| m.last().unwrap().as_str())
        .collect();
    let mut i = 0;
    while i < s.len() {
        let at_word = i == 0 || !(is_ident(s[i - 1]) || s[i - 1] == ':' || s[i - 1] == '$');
        if !at_word || !(is_ident(s[i]) || s[i] == '$') {
            i += 1;
            continue;
        }
        let word_end = (i..s.len()).find(|&j| !is_ident(s[j]) && s[j] != '$');
        let word_end = word_end.unwrap_or(s.len());
        let word: String = s[i..word_end].iter().collect();
        if word == "use" {
            let before: String = s[i.saturating_sub(12)..i].iter().collect();
            let public = before.trim_end().ends_with("pub") || before.trim_end().ends_with(')');
            let (paths, next) = parse_tree(&s, word_end);
            for p in paths {
                if let Some(abs) = absolute(&file.module, &p, modules) {
                    if public {
                        exported.push(abs.clone());
                    }
                    named.push(abs);
                }
            }
            i = next.max(i + 1);
            continue;
        }
        let anchored = matches!(word.as_str(), "crate" | "$crate" | "super" | "self")
            || children.contains(word.as_str());
        let followed = s.get(word_end) == Some(&':') && s.get(word_end + 1) == Some(&':');
        if anchored && followed {
            let (paths, next) = parse_tree(&s, i);
            for p in paths {
                if let Some(abs) = absolute(&file.module, &p, modules) {
                    named.push(abs);
                }
            }
            i = next.max(i + 1);
            continue;
        }
        i = word_end;
    }
    (named, exported)
}

/// The graph of one crate read from its `src/`.
struct Crate {
    files: Vec<File>,
    modules: BTreeSet<ModPath>,
    /// `pub use` names of each module: name → the path it stands for.
    reexports: BTreeMap<ModPath, BTreeMap<String, ModPath>>,
}

impl Crate {
    fn read(krate: &str) -> Crate {
        let files = src_files(krate);
        let modules: BTreeSet<ModPath> = files.iter().map(|f| f.module.clone()).collect();
        let mut reexports: BTreeMap<ModPath, BTreeMap<String, ModPath>> = BTreeMap::new();
        for file in &files {
            let (_, exported) = named_paths(file, &modules);
            for path in exported {
                if let Some(name) = path.last() {
                    reexports
                        .entry(file.module.clone())
                        .or_default()
                        .insert(name.clone(), path.clone());
                }
            }
        }
        Crate {
            files,
            modules,
            reexports,
        }
    }

    /// The module that defines what `path` names, through re-exports.
    fn resolve(&self, path: &[String]) -> ModPath {
        let mut path = path.to_vec();
        let mut at: ModPath = Vec::new();
        let mut i = 0;
        let mut hops = 0;
        while i < path.len() {
            let mut next = at.clone();
            next.push(path[i].clone());
            if self.modules.contains(&next) {
                at = next;
                i += 1;
                continue;
            }
            match self.reexports.get(&at).and_then(|r| r.get(&path[i])) {
                Some(target) if hops < 32 && *target != next => {
                    hops += 1;
                    let mut new = target.clone();
                    new.extend(path[i + 1..].iter().cloned());
                    path = new;
                    at.clear();
                    i = 0;
                }
                _ => break,
            }
        }
        at
    }

    /// Whether the file of `module` defines items of its own.
    fn defines_items(code: &str) -> bool {
        code.lines().any(|l| {
            let l = l.trim_start();
            let l = l.strip_prefix("pub(crate) ").unwrap_or(l);
            let l = l.strip_prefix("pub ").unwrap_or(l);
            [
                "fn ", "struct ", "enum ", "impl", "trait ", "const ", "static ", "type ",
            ]
            .iter()
            .any(|k| l.starts_with(k))
                || l.starts_with("macro_rules!")
        })
    }

    /// Edges of every folder: folder → (branch → branches it names). A
    /// branch is a child's name, or `[folder]` for the folder's own `mod.rs`.
    fn folder_graphs(&self) -> BTreeMap<ModPath, BTreeMap<String, BTreeSet<String>>> {
        let mut graphs: BTreeMap<ModPath, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
        let own = |folder: &ModPath| format!("[{}]", folder.last().map_or("src", |s| s));
        for file in &self.files {
            let (named, _) = named_paths(file, &self.modules);
            let has_children = self
                .modules
                .iter()
                .any(|m| m.len() > file.module.len() && m.starts_with(&file.module));
            let index = (file.is_folder || has_children) && !Self::defines_items(&file.code);
            for path in named {
                let target = self.resolve(&path);
                let inside = target.starts_with(&file.module) && target != file.module;
                // A pure index's declarations and re-exports of its own
                // children are no dependency.
                if index && inside {
                    continue;
                }
                let common = file
                    .module
                    .iter()
                    .zip(&target)
                    .take_while(|(a, b)| a == b)
                    .count();
                let folder: ModPath = target[..common].to_vec();
                let from = file
                    .module
                    .get(common)
                    .cloned()
                    .unwrap_or_else(|| own(&folder));
                let to = target.get(common).cloned().unwrap_or_else(|| own(&folder));
                if from == to {
                    continue;
                }
                graphs
                    .entry(folder)
                    .or_default()
                    .entry(from)
                    .or_default()
                    .insert(to);
            }
        }
        graphs
    }
}

/// The nodes `from` reaches.
fn reach(graph: &BTreeMap<String, BTreeSet<String>>, from: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from.to_string()];
    while let Some(node) = stack.pop() {
        for next in graph.get(&node).into_iter().flatten() {
            if seen.insert(next.clone()) {
                stack.push(next.clone());
            }
        }
    }
    seen
}

/// The graph's cycles, as its strongly connected components of more than
/// one node (the modules that all reach one another), each sorted.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> BTreeSet<Vec<String>> {
    let reached: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|n| (n, reach(graph, n))).collect();
    let mut found = BTreeSet::new();
    for (node, from_node) in &reached {
        let component: Vec<String> = from_node
            .iter()
            .filter(|other| reached.get(other).is_some_and(|r| r.contains(*node)))
            .cloned()
            .collect();
        if component.len() > 1 {
            found.insert(component);
        }
    }
    found
}

/// The `relief-*` crates a manifest depends on (not its dev-dependencies).
fn relief_dependencies(krate: &str) -> Vec<String> {
    let manifest = std::fs::read_to_string(root().join(krate).join("Cargo.toml")).unwrap();
    let deps = manifest.split("[dependencies]").nth(1).unwrap_or("");
    let deps = deps.split("\n[").next().unwrap_or("");
    deps.lines()
        .filter_map(|l| l.trim().strip_prefix("relief-"))
        .map(|l| format!("crates/{}", l.split(['.', ' ', '=']).next().unwrap()))
        .collect()
}

#[test]
fn the_crates_follow_the_data_flow() {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    for (i, krate) in CRATES.iter().enumerate() {
        if *krate != "." {
            assert!(
                manifest.contains(&format!("\"{krate}\"")),
                "{krate} is no member"
            );
        }
        for dep in relief_dependencies(krate) {
            let at = CRATES.iter().position(|c| *c == dep);
            assert!(
                at.is_some_and(|at| at < i),
                "{krate} depends on {dep}, which is not upstream of it"
            );
        }
    }
    // The terminal knows nothing of scenes or how they are drawn.
    assert_eq!(relief_dependencies("crates/term"), ["crates/core"]);
}

#[test]
fn the_plan_depends_on_nothing_downstream() {
    let graphs = Crate::read("crates/pipeline").folder_graphs();
    let top = &graphs[&Vec::<String>::new()];
    for downstream in ["render", "raster", "shade", "shadow"] {
        let plan_uses = top.get("plan").is_some_and(|p| p.contains(downstream));
        assert!(!plan_uses, "plan uses {downstream}");
    }
    assert!(graphs[&Vec::<String>::new()]["render"].contains("plan"));
}

fn path(s: &str) -> ModPath {
    s.split("::").map(String::from).collect()
}

#[test]
fn paths_are_followed_through_reexports_to_their_module() {
    let texture = Crate::read("crates/texture");
    // An item re-exported at the crate's root, and a module's own item.
    assert_eq!(texture.resolve(&path("Texture")), path("sample::texture"));
    assert_eq!(texture.resolve(&path("Level")), path("sample::level"));
    assert_eq!(
        texture.resolve(&path("sample::filter::sample")),
        path("sample::filter")
    );
    // A `use` group with `self` and a nested group, read from a file; a
    // path into another crate is no edge.
    let file = File {
        module: path("decode::load"),
        code: "use super::{xpm::{self, Xpm}, tiff_picture::Refusal};\nfn f() { crate::Texture::new(); relief_core::budget::Budget::new(); }\n".into(),
        is_folder: false,
    };
    let (named, _) = named_paths(&file, &texture.modules);
    assert!(named.contains(&path("decode::xpm")));
    assert!(named.contains(&path("decode::xpm::Xpm")));
    assert!(named.contains(&path("decode::tiff_picture::Refusal")));
    assert!(named.contains(&path("Texture::new")));
    assert_eq!(named.len(), 4, "{named:?}");
    // Edges land in the deepest common folder.
    assert!(texture.folder_graphs()[&path("decode")]["load"].contains("xpm"));
    let app = Crate::read(".").folder_graphs();
    assert!(app[&path("app")]["view"].contains("state"));
    assert!(app[&Vec::new()]["still"].contains("app"));
}

#[test]
fn no_folder_has_a_cycle() {
    let mut folders = 0;
    let mut found = Vec::new();
    for krate in CRATES {
        let graphs = Crate::read(krate).folder_graphs();
        folders += graphs.len();
        for (folder, graph) in &graphs {
            for cycle in cycles(graph) {
                found.push(format!(
                    "{krate}/src/{}: {}",
                    folder.join("/"),
                    cycle.join(", ")
                ));
            }
        }
    }
    assert!(folders > 20, "folders read: {folders}");
    assert!(found.is_empty(), "import cycles inside folders: {found:#?}");
}

#[test]
fn only_indexes_re_export() {
    // A file imports an item from the file that defines it: only a folder's
    // `mod.rs` or a crate's `lib.rs` names its children's items (its face).
    let mut found = Vec::new();
    let mut files = 0;
    for krate in CRATES {
        for file in src_files(krate) {
            files += 1;
            if file.is_folder {
                continue;
            }
            for line in file
                .code
                .lines()
                .filter(|l| l.trim_start().starts_with("pub use "))
            {
                found.push(format!(
                    "{krate}/src/{}: {}",
                    file.module.join("/"),
                    line.trim()
                ));
            }
        }
    }
    assert!(files > 200, "files read: {files}");
    assert!(found.is_empty(), "re-exports outside an index: {found:#?}");
}

#[test]
fn a_cycle_is_found() {
    // The check itself: two files naming each other form one cycle, a
    // third that only names them is outside it.
    let edges = |list: &[(&str, &[&str])]| -> BTreeMap<String, BTreeSet<String>> {
        list.iter()
            .map(|(from, to)| (from.to_string(), to.iter().map(|t| t.to_string()).collect()))
            .collect()
    };
    let graph = edges(&[("a", &["b"]), ("b", &["a"]), ("c", &["a"])]);
    let found = cycles(&graph);
    assert_eq!(found.len(), 1);
    assert!(found.contains(&vec!["a".to_string(), "b".to_string()]));
    assert!(cycles(&edges(&[("a", &["b"]), ("c", &["a"])])).is_empty());
}
