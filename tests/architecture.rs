//! Data flows one way: no top-level module of `src/` may reach back to a
//! module that depends on it (plan, shade and shadow once formed cycles).
//! Read from the source: every `crate::name` outside test modules is an edge.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The top-level module each file belongs to, and the modules it names.
fn edges() -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
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
            let first = rel.components().next().unwrap().as_os_str();
            let top = first.to_string_lossy().trim_end_matches(".rs").to_string();
            let text = std::fs::read_to_string(&path).unwrap();
            // Test modules may reach anywhere.
            let code = text.split("#[cfg(test)]").next().unwrap_or("");
            let names = graph.entry(top.clone()).or_default();
            for (i, _) in code.match_indices("crate::") {
                let name: String = code[i + 7..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                // Lower case: a module (not a type re-exported at the root).
                if name != top && name.starts_with(|c: char| c.is_ascii_lowercase()) {
                    names.insert(name);
                }
            }
        }
    }
    graph
}

/// A cycle through `from`, if any, as the list of modules on it.
fn cycle_from(
    graph: &BTreeMap<String, BTreeSet<String>>,
    from: &str,
    path: &mut Vec<String>,
) -> Option<Vec<String>> {
    for next in graph.get(from).into_iter().flatten() {
        if let Some(at) = path.iter().position(|m| m == next) {
            let mut cycle = path[at..].to_vec();
            cycle.push(next.clone());
            return Some(cycle);
        }
        path.push(next.clone());
        if let Some(c) = cycle_from(graph, next, path) {
            return Some(c);
        }
        path.pop();
    }
    None
}

#[test]
fn the_top_level_modules_form_no_cycle() {
    let graph = edges();
    assert!(graph.contains_key("plan") && graph.contains_key("shade"));
    for module in graph.keys() {
        let mut path = vec![module.clone()];
        if let Some(cycle) = cycle_from(&graph, module, &mut path) {
            panic!("import cycle: {}", cycle.join(" → "));
        }
    }
}

#[test]
fn the_plan_depends_on_nothing_downstream() {
    let graph = edges();
    let plan = &graph["plan"];
    for downstream in ["render", "raster", "shade", "shadow", "term", "app"] {
        assert!(!plan.contains(downstream), "plan uses {downstream}");
    }
}
