//! Layouts as data: the generator against the spec's paper layout, the layout file's round
//! trip, and every validation error.

use multibots_core::input::files::write_atomic;
use multibots_core::input::layout_file::LayoutFile;
use multibots_core::input::layout_params::Aisles;
use multibots_core::world::layout::NodeKind;
use multibots_core::world::layout_file;
use multibots_core::{Layout, LayoutParams, NodeId, Scenario, Simulation};

/// The paper layout written out from docs/model.md section 1, independently of the generator.
#[test]
fn generator_reproduces_the_spec_paper_layout_exactly() {
    let l = Layout::generate(&LayoutParams::paper(), "paper").unwrap();
    assert_eq!(l, Layout::paper());
    let letters = "ABCDEFGHIJKLMNOPQR";
    // Nodes: A..R at (25 + 150k, 25 + 250m), then CH0..CH5 at (25 + 150k, -15).
    assert_eq!(l.nodes.len(), 24);
    for (i, ch) in letters.chars().enumerate() {
        let (m, k) = (i / 6, i % 6);
        let n = &l.nodes[i];
        assert_eq!((n.name.as_str(), n.x, n.y, n.kind), (ch.to_string().as_str(), 25.0 + 150.0 * k as f64, 25.0 + 250.0 * m as f64, NodeKind::Highway));
    }
    for k in 0..6 {
        let n = &l.nodes[18 + k];
        assert_eq!((n.name.clone(), n.x, n.y, n.kind), (format!("CH{k}"), 25.0 + 150.0 * k as f64, -15.0, NodeKind::Charger));
    }
    // Edges, grouped by tail in node order, each tail's heads in the spec's expansion order.
    let table = ["B", "CH", "D", "EJ", "F", "L", "HA", "IN", "JC", "KP", "LE", "R", "G", "M", "NI", "O", "PK", "Q"];
    let mut expect = Vec::new();
    for (u, outs) in table.iter().enumerate() {
        for c in outs.chars() {
            let v = letters.find(c).unwrap();
            expect.push((NodeId(u as u32), NodeId(v as u32)));
        }
    }
    assert_eq!(l.edges, expect);
    // Spurs, zones.
    assert_eq!(l.spurs, (0..6).map(|k| (NodeId(18 + k), NodeId(k))).collect::<Vec<_>>());
    assert_eq!(l.departure, (0..6).map(NodeId).collect::<Vec<_>>());
    assert_eq!(l.unloading, (12..18).map(NodeId).collect::<Vec<_>>());
    assert_eq!(l.chargers, (18..24).map(NodeId).collect::<Vec<_>>());
    // Cells: id 8g + 2b + a with g = 2c + r; service point on aisle k = c + a, on the edge
    // between rows r and r + 1 in the aisle's direction (even aisles north, odd south).
    assert_eq!(l.cells.len(), 80);
    for c in 0..5usize {
        for r in 0..2usize {
            for b in 0..4usize {
                for a in 0..2usize {
                    let id = 8 * (2 * c + r) + 2 * b + a;
                    let cell = &l.cells[id];
                    let k = c + a;
                    assert_eq!((cell.x, cell.y, cell.w, cell.h), ((50 + 150 * c + 50 * a) as f64, (50 + 250 * r + 50 * b) as f64, 50.0, 50.0), "cell {id}");
                    assert_eq!(cell.service, ((25 + 150 * k) as f64, (75 + 250 * r + 50 * b) as f64), "cell {id}");
                    let (upper, lower) = (NodeId((6 * r + k) as u32), NodeId((6 * (r + 1) + k) as u32));
                    let edge = if k % 2 == 0 { (lower, upper) } else { (upper, lower) };
                    assert_eq!(cell.edge, edge, "cell {id}");
                }
            }
        }
    }
}

#[test]
fn layout_files_round_trip_and_run_the_worked_example() {
    let dir = std::env::temp_dir().join(format!("multibots-layouts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("paper.toml");
    write_atomic(&path, &layout_file::to_toml(&Layout::paper(), Some(LayoutParams::paper()))).unwrap();
    assert_eq!(layout_file::read(&path).unwrap(), Layout::paper());
    // The same layout from the file runs the spec's worked example: T = 726.
    let s = Scenario { layout: path.display().to_string(), ..Scenario::paper(1, &[42]) };
    assert_eq!(Simulation::new(&s).unwrap().run().unwrap().t, Some(726));
    // A generated grid, too.
    let p = LayoutParams { group_rows: 5, group_cols: 7, group_width: 1, group_height: 6, chargers: 3, ..LayoutParams::paper() };
    let big = Layout::generate(&p, "g").unwrap();
    let back = layout_file::from_toml(&layout_file::to_toml(&big, Some(p)), "g.toml").unwrap();
    assert_eq!(back, big);
    layout_file::check_layout(&back).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

fn paper_file() -> LayoutFile {
    layout_file::to_file(&Layout::paper(), None)
}

fn err(f: &LayoutFile) -> String {
    match layout_file::from_file(f) {
        Err(e) => e.to_string(),
        Ok(l) => layout_file::check_layout(&l).map_or_else(|e| e.to_string(), |_| "no error".to_string()),
    }
}

#[test]
fn every_validation_error_names_the_field() {
    type Mutation = (&'static str, fn(&mut LayoutFile));
    let cases: Vec<Mutation> = vec![
        ("layout name: must not be empty", |f| f.name = " ".into()),
        ("layout bounds: ", |f| f.bounds = [0.0, 0.0, -1.0, 5.0]),
        ("layout bounds: coordinates must be finite", |f| f.bounds[2] = f64::NAN),
        ("layout aisle_width: 0 must be greater than 0", |f| f.aisle_width = 0.0),
        ("layout cell_size: -1 must be greater than 0", |f| f.cell_size = -1.0),
        ("layout nodes: no highway node", |f| f.nodes.clear()),
        ("layout nodes[1].name: \"A\" names two nodes", |f| f.nodes[1].name = "A".into()),
        ("layout chargers[0].name: \"B\" names two nodes", |f| f.chargers[0].name = "B".into()),
        ("layout nodes[2].name: must not be empty", |f| f.nodes[2].name = String::new()),
        ("layout nodes[3]: coordinates must be finite", |f| f.nodes[3].x = f64::INFINITY),
        ("layout nodes[0].out[0]: unknown node \"Z\"", |f| f.nodes[0].out[0] = "Z".into()),
        ("layout nodes[0].out[0]: \"CH0\" is a charger, not a highway node", |f| f.nodes[0].out[0] = "CH0".into()),
        ("layout nodes[0].out[1]: \"A\" is an edge from the node to itself", |f| f.nodes[0].out.push("A".into())),
        ("layout nodes[1].out[2]: \"C\" is listed twice", |f| f.nodes[1].out.push("C".into())),
        ("layout nodes[0].out[0]: \"B\" stands where \"A\" stands", |f| (f.nodes[1].x, f.nodes[1].y) = (25.0, 25.0)),
        ("layout chargers[0].node: unknown node \"ZZ\"", |f| f.chargers[0].node = "ZZ".into()),
        ("layout chargers[1].node: \"CH0\" is a charger", |f| f.chargers[1].node = "CH0".into()),
        ("layout chargers[0]: stands on its spur node", |f| f.chargers[0].y = 25.0),
        ("layout chargers: no charger", |f| f.chargers.clear()),
        ("layout cells[42].edge[1]: unknown node \"Q2\"", |f| f.cells[42].edge[1] = "Q2".into()),
        ("layout cells[42].edge: is not a highway edge", |f| f.cells[42].edge = ["I".into(), "O".into()]),
        ("layout cells[42].service: does not lie strictly inside its edge", |f| f.cells[42].service = [325.0, 275.0]),
        ("layout cells[42].service: does not lie strictly inside its edge", |f| f.cells[42].service = [330.0, 375.0]),
        ("layout cells[5]: size 0 x 50 must be positive", |f| f.cells[5].w = 0.0),
        ("layout departure[1]: \"A\" is listed twice", |f| f.departure[1] = "A".into()),
        ("layout departure[0]: unknown node \"X\"", |f| f.departure[0] = "X".into()),
        ("layout unloading[0]: \"CH1\" is a charger", |f| f.unloading[0] = "CH1".into()),
        ("layout departure: no zone given", |f| f.departure.clear()),
        ("layout unloading: no zone given", |f| f.unloading.clear()),
        ("layout edges: the highway graph is not strongly connected: node E cannot reach node A", |f| f.nodes[5].out.clear()),
        ("layout edges: the highway graph is not strongly connected", |f| f.nodes[12].out.clear()),
    ];
    for (expect, mutate) in cases {
        let mut f = paper_file();
        mutate(&mut f);
        let e = err(&f);
        assert!(e.starts_with(expect), "expected `{expect}`, got `{e}`");
        assert!(!e.contains('\n'));
    }
    assert_eq!(err(&paper_file()), "no error");
}

#[test]
fn file_syntax_errors_name_the_file_and_the_field() {
    let text = layout_file::to_toml(&Layout::paper(), None);
    let e = layout_file::from_toml(&text.replacen("cell_size", "cell_sise", 1), "w.toml").unwrap_err().to_string();
    assert!(e.starts_with("w.toml: ") && e.contains("unknown field `cell_sise`"), "{e}");
    let e = layout_file::from_toml(&text.replacen("aisle_width = 50.0", "aisle_width = \"wide\"", 1), "w.toml").unwrap_err().to_string();
    assert_eq!(e, "w.toml: aisle_width = \"wide\": expected a number");
    let e = layout_file::from_toml("name = [", "w.toml").unwrap_err().to_string();
    assert!(e.starts_with("w.toml: ") && !e.contains('\n'), "{e}");
    let e = layout_file::read(std::path::Path::new("/nonexistent/w.toml")).unwrap_err().to_string();
    assert!(e.starts_with("/nonexistent/w.toml: "), "{e}");
}

#[test]
fn generator_parameter_errors() {
    let bad = |p: LayoutParams| Layout::generate(&p, "x").unwrap_err().to_string();
    let paper = LayoutParams::paper;
    assert_eq!(bad(LayoutParams { group_rows: 0, ..paper() }), "layout.group_rows = 0: must be at least 1");
    assert_eq!(bad(LayoutParams { group_cols: 0, ..paper() }), "layout.group_cols = 0: must be at least 1");
    assert!(bad(LayoutParams { group_width: 3, ..paper() }).starts_with("layout.group_width = 3: must be 1 or 2"));
    assert_eq!(bad(LayoutParams { group_height: 0, ..paper() }), "layout.group_height = 0: must be at least 1");
    assert_eq!(bad(LayoutParams { aisle: 0.0, ..paper() }), "layout.aisle = 0: must be greater than 0");
    assert!(bad(LayoutParams { chargers: 12, ..paper() }).starts_with("layout.chargers = 12: must be between 1 and 11"));
    assert!(bad(LayoutParams { group_rows: 200, group_cols: 200, chargers: 1, ..paper() }).contains("layout too large"));
    // A size past its limit names the field that makes it so, with its value (issue 28).
    assert_eq!(
        bad(LayoutParams { group_height: 2_000_000_000, ..paper() }),
        "layout.group_height = 2000000000: layout too large: 40000000000 storage cells (at most 1000000)"
    );
    assert_eq!(bad(LayoutParams { aisle: 1e308, ..paper() }), "layout.aisle = 1e308: layout too large: more than 1e308 px across (at most 1e7)");
    assert_eq!(bad(LayoutParams { cell: 1e6, ..paper() }), "layout.cell = 1000000: layout too large: 1.000e7 px across (at most 1e7)");
    assert!(bad(LayoutParams { spur: 1e300, ..paper() }).starts_with("layout.spur = 1e300: layout too large"));
    assert!(
        bad(LayoutParams { group_rows: 1000, cell: 10_000.0, chargers: 1, group_cols: 1, ..paper() }).starts_with("layout.group_rows = 1000: layout too large")
    );
    assert!(bad(LayoutParams { group_cols: 20_000, group_rows: 1, group_height: 1, group_width: 1, chargers: 1, unloading_rows: 1, ..paper() })
        .starts_with("layout.group_cols = 20000: layout too large: 40002 aisle crossings"));
    assert!(bad(LayoutParams { group_cols: u32::MAX, chargers: 2, ..paper() }).starts_with("layout.group_cols = 4294967295: layout too large"));
    assert_eq!(
        LayoutParams::from_json(r#"{"group_rows": 4294967296}"#).unwrap_err().to_string(),
        "layout.group_rows = 4294967296: expected a whole number from 0 to 4294967295"
    );
    assert_eq!(LayoutParams::from_json(r#"{"aisle": [1]}"#).unwrap_err().to_string(), "layout.aisle: expected a number, not a list");
    // Through a scenario, the fields are named as the scenario names them.
    let s = Scenario::from_toml("tasks = [1]\n[layout_generate]\ngroup_rows = 0", "s.toml").unwrap();
    assert_eq!(Simulation::new(&s).err().unwrap().to_string(), "layout_generate.group_rows = 0: must be at least 1");
    let s = Scenario::from_toml("layout = \"other\"\ntasks = [1]\n[layout_generate]\ngroup_rows = 3", "s.toml").unwrap();
    assert!(Simulation::new(&s).err().unwrap().to_string().contains("give either layout or [layout_generate], not both"));
    let s = Scenario::from_toml("layout = \"hall\"\ntasks = [1]", "s.toml").unwrap();
    assert!(Simulation::new(&s).err().unwrap().to_string().starts_with("layout = \"hall\": unknown layout"));
}

#[test]
fn generated_grids_are_valid_and_route_like_the_literal_search() {
    for (rows, cols, w, h) in [(1, 1, 1, 1), (3, 4, 2, 3), (2, 6, 1, 5)] {
        let p = LayoutParams { group_rows: rows, group_cols: cols, group_width: w, group_height: h, chargers: cols + 1, ..LayoutParams::paper() };
        let l = Layout::generate(&p, "g").unwrap();
        let g = layout_file::check_layout(&l).unwrap();
        for u in 0..l.nodes.len() as u32 {
            for t in 0..l.nodes.len() as u32 {
                assert_eq!(g.node_path(NodeId(u), NodeId(t)), g.bfs_path(NodeId(u), NodeId(t)), "{rows}x{cols}: {u} -> {t}");
            }
        }
    }
}

#[test]
fn auto_choices_suit_the_warehouse_size() {
    // A scenario's [layout_generate] leaves aisles and unloading rows to the generator.
    let table = |extra: &str| format!("robots = 1\ntasks = [0]\n[layout_generate]\n{extra}");
    let auto = Scenario::from_toml(&table(""), "s.toml").unwrap().layout_generate.unwrap();
    assert_eq!(Layout::generate(&auto, "paper").unwrap(), Layout::paper(), "the paper's size gives the paper's layout");
    let unloading_rows = |rows: u32| {
        let p = Scenario::from_toml(&table(&format!("group_rows = {rows}\ngroup_cols = 6\nchargers = 7")), "s.toml").unwrap().layout_generate.unwrap();
        let layout = Layout::generate(&p, "g").unwrap();
        // Each unloading row holds one zone per crossing of a row (group_cols + 1).
        (layout.unloading.len() / 7, p.resolved().aisles)
    };
    assert_eq!(unloading_rows(2), (1, Aisles::Paper));
    assert_eq!(unloading_rows(3), (1, Aisles::Alternate));
    assert_eq!(unloading_rows(6), (2, Aisles::Alternate));
    assert_eq!(unloading_rows(12), (3, Aisles::Alternate));
    // What a scenario says is kept, and written back; "auto" is the default, not written.
    let s = Scenario::from_toml(&table("group_rows = 12\naisles = \"paper\"\nunloading_rows = 1"), "s.toml").unwrap();
    let text = s.to_toml();
    assert!(text.contains("aisles = \"paper\"") && text.contains("unloading_rows = 1"), "{text}");
    assert_eq!(Scenario::from_toml(&text, "s.toml").unwrap(), s);
    assert!(!Scenario::from_toml(&table("group_rows = 12"), "s.toml").unwrap().to_toml().contains("auto"));
    let e = Scenario::from_toml(&table("unloading_rows = 0"), "s.toml").unwrap_err().to_string();
    assert!(e.contains("unloading_rows") && e.contains("\"auto\" or a count"), "{e}");
}
