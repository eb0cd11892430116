//! The engine's layering, enforced (docs/architecture.md): each top-level folder of `src/`
//! names only the layers below it, and no rule set under `rules/` names another. Read from
//! the source: every `crate::` path, `use crate::{a, b}` groups included, outside comments
//! and outside `#[cfg(test)]` modules (a test may set up its case from any layer).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// From the bottom up. `error` and `ids` hold no model and are below everything.
const LAYERS: &[&str] = &["ids", "error", "input", "world", "fleet", "collision", "people", "traffic", "alloc", "record", "rules", "output", "learning"];

/// The rule sets under `rules/`: none names another.
const RULE_SETS: &[&str] = &["paper", "original", "grid"];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text with comments and `#[cfg(test)]` modules blanked out.
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]") {
            // The item after it: a module in braces is skipped to its closing brace.
            let Some(next) = lines.next() else { break };
            if next.trim_start().starts_with("mod ") && next.trim_end().ends_with('{') {
                let mut depth = 1i32;
                for l in lines.by_ref() {
                    depth += l.matches('{').count() as i32 - l.matches('}').count() as i32;
                    if depth <= 0 {
                        break;
                    }
                }
            }
            continue;
        }
        out.push_str(line.split("//").next().unwrap_or_default());
        out.push('\n');
    }
    out
}

/// Every `(first, second)` segment pair of the `crate::` paths in `code`: `crate::a::b::C`
/// gives `("a", Some("b"))`, and `crate::{a::b, c}` gives one pair per item of the group.
fn paths(code: &str) -> Vec<(String, Option<String>)> {
    let ident = |s: &str| -> String { s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect() };
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(k) = rest.find("crate::") {
        let before = rest[..k].chars().next_back();
        rest = &rest[k + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue; // `multibots_core::...` and the like
        }
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 1;
            let end = group
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '{' => 1,
                        '}' => -1,
                        _ => 0,
                    };
                    depth == 0
                })
                .map_or(group.len(), |(i, _)| i);
            let (mut item, mut level) = (String::new(), 0);
            for c in group[..end].chars().chain(std::iter::once(',')) {
                match c {
                    '{' => level += 1,
                    '}' => level -= 1,
                    ',' if level == 0 => {
                        let first = ident(item.trim());
                        let second = item.trim().strip_prefix(&first).and_then(|r| r.strip_prefix("::")).map(ident);
                        if !first.is_empty() {
                            out.push((first, second));
                        }
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                item.push(c);
            }
        } else {
            let first = ident(rest);
            let second = rest[first.len()..].strip_prefix("::").map(ident);
            out.push((first, second));
        }
    }
    out
}

#[test]
fn no_layer_names_a_higher_one_and_no_rule_set_names_another() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let rank = |name: &str| LAYERS.iter().position(|&l| l == name);
    let mut wrong: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut seen_layers = std::collections::BTreeSet::new();
    for file in &files {
        let rel = file.strip_prefix(&src).expect("under src").to_string_lossy().replace('\\', "/");
        let parts: Vec<&str> = rel.split('/').collect();
        let layer = parts[0].trim_end_matches(".rs");
        if layer == "lib" {
            continue; // the crate root declares the layers and re-exports from them
        }
        let Some(own) = rank(layer) else { panic!("{rel}: top-level `{layer}` is not in LAYERS (tests/engine/layers.rs): place it in the order") };
        seen_layers.insert(layer.to_string());
        let set = (layer == "rules" && parts.len() > 2).then(|| parts[1]);
        let text = std::fs::read_to_string(file).expect("readable source");
        for (first, second) in paths(&code_of(&text)) {
            match rank(&first) {
                Some(other) if other > own => wrong.entry(rel.clone()).or_default().push(format!("names `crate::{first}` (a higher layer)")),
                Some(_) => {
                    if let (Some(set), true, Some(second)) = (set, first == "rules", second.as_deref()) {
                        if RULE_SETS.contains(&second) && second != set {
                            wrong.entry(rel.clone()).or_default().push(format!("rule set `{set}` names rule set `{second}`"));
                        }
                    }
                }
                None if first == "xorshift" => {}
                // A re-export of the crate root hides which layer it comes from.
                None => wrong.entry(rel.clone()).or_default().push(format!("names `crate::{first}`: name it by its layer's path")),
            }
        }
    }
    assert!(wrong.is_empty(), "layering broken:\n{}", wrong.iter().map(|(f, w)| format!("  {f}: {}", w.join("; "))).collect::<Vec<_>>().join("\n"));
    assert_eq!(seen_layers.len(), LAYERS.len(), "LAYERS names a folder that no longer exists: {seen_layers:?}");
}

#[test]
fn the_reader_finds_grouped_and_plain_paths_and_skips_comments_and_tests() {
    let code = code_of(
        "use crate::{a::b, c};\nuse crate::d::{e, f::g};\n// crate::h\nx = crate::i::j(1); y = multibots_core::k;\n#[cfg(test)]\nmod tests {\n    use crate::z;\n}\nuse crate::m;\n",
    );
    let got = paths(&code);
    let want: Vec<(String, Option<String>)> = [("a", Some("b")), ("c", None), ("d", Some("")), ("i", Some("j")), ("m", None)]
        .iter()
        .map(|(a, b)| ((*a).to_string(), b.map(str::to_string)))
        .collect();
    assert_eq!(got, want);
}
