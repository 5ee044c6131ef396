//! The documents stay true to the code: every test the validation manual names exists, every
//! relative link of the README and of `docs/` points at a file, the README stays a front door
//! (at most 250 lines), and no document speaks of how the project was made.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown documents a reader meets: the README and every `.md` under `docs/`.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md")];
    let mut pending = vec![root().join("docs")];
    while let Some(dir) = pending.pop() {
        for entry in fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                docs.push(path);
            }
        }
    }
    docs.sort();
    docs
}

/// Every `fn NAME` defined in the Rust sources under `dir`, and every name the PETSc suite
/// registers as a string (`("NAME", function)` in its table of cases).
fn functions_under(dir: &Path, names: &mut BTreeSet<String>) {
    for entry in fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            functions_under(&path, names);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = fs::read_to_string(&path).expect("a readable source file");
            for (i, _) in text.match_indices("(\"") {
                let rest = &text[i + 2..];
                let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if rest[name.len()..].starts_with("\",") && !name.is_empty() {
                    names.insert(name);
                }
            }
            for (i, _) in text.match_indices("fn ") {
                let rest = &text[i + 3..];
                let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if !name.is_empty() {
                    names.insert(name);
                }
            }
        }
    }
}

/// The backquoted identifiers of the last cell of each table row of the validation manual.
fn tests_named_in_validation_manual() -> Vec<(usize, String)> {
    let text = fs::read_to_string(root().join("docs/validation.md")).expect("docs/validation.md");
    let mut named = Vec::new();
    for (line_number, line) in text.lines().enumerate() {
        let line = line.trim();
        if !line.starts_with('|') || line.starts_with("|---") {
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').collect();
        let Some(last) = cells.last() else { continue };
        for (k, part) in last.split('`').enumerate() {
            // Odd pieces are inside backquotes; a test name is one identifier.
            if k % 2 == 1 && !part.is_empty() && part.chars().all(|c| c.is_alphanumeric() || c == '_') {
                named.push((line_number + 1, part.to_string()));
            }
        }
    }
    named
}

#[test]
fn validation_manual_names_real_tests() {
    let named = tests_named_in_validation_manual();
    assert!(named.len() > 50, "the manual names {} tests: the parser lost the tables", named.len());
    let mut functions = BTreeSet::new();
    functions_under(&root().join("tests"), &mut functions);
    functions_under(&root().join("src"), &mut functions);
    let missing: Vec<String> = named
        .iter()
        .filter(|(_, name)| !functions.contains(name))
        .map(|(line, name)| format!("docs/validation.md:{line}: `{name}`"))
        .collect();
    assert!(missing.is_empty(), "the validation manual names tests that do not exist:\n{}", missing.join("\n"));
}

#[test]
fn the_parser_of_the_manual_sees_a_missing_test() {
    // The check above can fail: a name that is no function is not among the functions.
    let mut functions = BTreeSet::new();
    functions_under(&root().join("tests"), &mut functions);
    assert!(functions.contains("validation_manual_names_real_tests"));
    assert!(!functions.contains("a_test_that_was_never_written"));
}

#[test]
fn readme_is_a_front_door() {
    let readme = fs::read_to_string(root().join("README.md")).expect("README.md");
    let lines = readme.lines().count();
    assert!(lines <= 250, "README.md has {lines} lines: keep it to what a newcomer reads first");
    for command in ["./setup.sh && cargo run --release -- run", "./setup.sh && cargo test --release"] {
        assert!(readme.contains(command), "README.md lost its set-up command `{command}`");
    }
}

#[test]
fn documents_speak_of_the_program_not_of_its_making() {
    let words = ["today", "yesterday", "this session", "the issue", "fixed today", "until 2026"];
    let mut found = Vec::new();
    for doc in documents() {
        let text = fs::read_to_string(&doc).expect("a readable document");
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            for word in words {
                if lower.contains(word) {
                    found.push(format!("{}:{}: '{word}'", doc.display(), n + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "documents speak of how the project was made:\n{}", found.join("\n"));
}

#[test]
fn relative_links_point_at_files() {
    let mut broken = Vec::new();
    for doc in documents() {
        let text = fs::read_to_string(&doc).expect("a readable document");
        let dir = doc.parent().expect("a document's folder");
        for (i, _) in text.match_indices("](") {
            let rest = &text[i + 2..];
            let Some(end) = rest.find(')') else { continue };
            let target = &rest[..end];
            if target.starts_with("http") || target.starts_with('#') || target.starts_with("mailto:") {
                continue;
            }
            let file = target.split('#').next().unwrap_or(target);
            if !dir.join(file).exists() {
                broken.push(format!("{}: ({target})", doc.display()));
            }
        }
    }
    assert!(broken.is_empty(), "links to files that do not exist:\n{}", broken.join("\n"));
}
