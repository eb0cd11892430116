//! The shipped JSON Schemas and the field tables of docs/scenario-format.md are generated
//! from the engine's schema; this fails when they are stale.
use multibots_core::input::schema;
use std::path::Path;

#[test]
fn generated_schema_and_docs_are_current() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let stale = schema::stale(&root).unwrap();
    assert!(stale.is_empty(), "stale: {stale:?}; run `cargo run -p multibots-core --example schema`");
}

#[test]
fn the_schema_describes_every_field_with_its_default() {
    let s = schema::scenario();
    let props = s["properties"].as_object().unwrap();
    for field in ["layout", "robots", "tasks", "unload", "allocator", "robot", "collision", "charging"] {
        assert!(props.contains_key(field), "{field}");
    }
    assert_eq!(s["required"], serde_json::json!(["tasks"]));
    assert_eq!(s["$defs"]["Unload"]["default"], "auto");
    let robot = &s["$defs"]["RobotParams"]["properties"];
    assert_eq!(robot["radius"]["default"], 12.5);
    assert!(robot["radius"]["description"].as_str().unwrap().contains("px"));
}
