//! Writes the JSON Schemas of the scenario and layout files to `docs/schema/` and the field
//! tables of `docs/scenario-format.md`, all generated from the engine's schema types:
//! `cargo run -p multibots-core --example schema`, or with `-- --check` to fail when a
//! shipped copy is stale (`make lint`; `cargo test` checks it too).
use multibots_core::input::schema;
use std::path::Path;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the repository root");
    let fail = |e: String| -> ! {
        eprintln!("{e}");
        std::process::exit(1)
    };
    if std::env::args().any(|a| a == "--check") {
        let stale = schema::stale(&root).unwrap_or_else(|e| fail(e));
        if !stale.is_empty() {
            let names: Vec<String> = stale.iter().map(|p| p.display().to_string()).collect();
            fail(format!("stale: {} (run `cargo run -p multibots-core --example schema`)", names.join(", ")));
        }
        return;
    }
    for (path, text) in schema::outputs(&root).unwrap_or_else(|e| fail(e)) {
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            std::fs::create_dir_all(path.parent().expect("a folder")).unwrap_or_else(|e| fail(e.to_string()));
            std::fs::write(&path, text).unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
            println!("wrote {}", path.display());
        }
    }
}
