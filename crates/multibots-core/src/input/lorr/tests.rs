use super::*;

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::create_dir_all(dir.join(name).parent().unwrap()).unwrap();
    std::fs::write(dir.join(name), text).unwrap();
}

fn tiny(dir: &Path, agents: &str, tasks: &str, problem: &str) -> Result<Problem> {
    write(dir, "m.map", "type octile\nheight 2\nwidth 3\nmap\n...\n.@.\n");
    write(dir, "a.agents", agents);
    write(dir, "t.tasks", tasks);
    write(dir, "p.json", problem);
    Problem::load(&dir.join("p.json"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("mb-lorr-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

const P23: &str =
    r#"{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, "numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"}"#;
const P24: &str = r#"{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, "numTasksReveal": 1.5, "version": "2024 LoRR"}"#;

#[test]
fn reads_both_years() {
    let d = scratch("ok");
    let p = tiny(&d, "2\n0\n2\n", "3\n5\n3\n0\n", P23).unwrap();
    assert_eq!((p.version, p.starts.clone(), p.tasks.clone(), p.reveal()), (Version::Y2023, vec![0, 2], vec![vec![5], vec![3], vec![0]], 1));
    let p = tiny(&d, "# version for LoRR 2024\n2\n0\n2\n", "# version for LoRR 2024\n2\n5,0\n3\n", P24).unwrap();
    assert_eq!((p.version, p.tasks.clone(), p.reveal()), (Version::Y2024, vec![vec![5, 0], vec![3]], 3));
}

#[test]
fn bad_files_name_the_file_and_line() {
    let d = scratch("bad");
    let cases = [
        ("2\n0\n4\n", "3\n5\n3\n0\n", P23, "a.agents, line 3: start cell 4 (row 1, column 1) is an obstacle"),
        ("2\n0\n0\n", "3\n5\n3\n0\n", P23, "a.agents, line 3: two agents start on cell 0"),
        ("1\n0\n", "3\n5\n3\n0\n", P23, "a.agents, line 1: teamSize is 2 but the file has 1 agents"),
        ("2\n0\n2\n", "3\n5\nx\n0\n", P23, "t.tasks, line 3: 'x' is not a cell number"),
        ("2\n0\n2\n", "3\n5\n3\n", P23, "t.tasks, line 3: the file says 3 tasks but holds 2"),
        ("2\n0\n2\n", "2\n5,9\n3\n", P24, "t.tasks, line 2: cell 9 is off the 2 x 3 map"),
        ("2\n0\n2\n", "2\n5,0\n3\n", &P23.replace("roundrobin", "greedy"), "p.json, line 1: taskAssignmentStrategy 'greedy'"),
        ("2\n0\n2\n", "2\n5,0\n3\n", "{\n\"mapFile\": 3}", "p.json, line 2: mapFile = 3: expected text in quotes"),
        ("2\n0\n2\n", "2\n5,0\n3\n", &P23.replace("\"teamSize\": 2", "\"teamSize\": \"4\""), "p.json, line 1: teamSize = \"4\": expected a whole number"),
        ("2\n0\n2\n", "2\n5,0\n3\n", &P23.replace("\"teamSize\": 2", "\"teamSize\": 2.5"), "teamSize = 2.5: expected a whole number"),
        ("2\n0\n2\n", "2\n5,0\n3\n", "null", "p.json, line 1: expected a JSON object with mapFile, agentFile, taskFile and teamSize, not null"),
        ("2\n0\n2\n", "2\n5,0\n3\n", "[1, 2]", "p.json, line 1: expected a JSON object with mapFile, agentFile, taskFile and teamSize, not a list"),
        ("2\n0\n2\n", "2\n5,0\n3\n", "{\"mapFile\": ", "p.json, line 1: not JSON: EOF while parsing"),
        ("2\n0\n2\n", "2\n5,0\n3\n", r#"{"mapFile": "m.map", "agentFile": "a.agents", "teamSize": 2}"#, "taskFile: missing (a problem names"),
        (
            "2\n0\n2\n",
            "2\n5,0\n3\n",
            &P24.replace("1.5", "1e12"),
            "numTasksReveal = 1000000000000: with 2 robots it reveals 2000000000000 tasks at once; at most 10000000",
        ),
        (
            "2\n0\n2\n",
            "2\n5,0\n3\n",
            &P23.replace("\"teamSize\": 2", "\"teamSize\": 2000001"),
            "teamSize = 2000001: expected a number of robots from 1 to 1000000",
        ),
    ];
    for (agents, tasks, problem, want) in cases {
        let e = tiny(&d, agents, tasks, problem).unwrap_err().to_string();
        assert!(e.contains(want), "{e} lacks {want}");
        assert!(!e.contains('\n'));
        // The user's words, not serde's or Rust's.
        for word in ["i64", "u32", "f64", "invalid type", "struct", "ProblemJson", "sequence"] {
            assert!(!e.contains(word), "{e} says {word}");
        }
    }
    write(&d, "m.map", "type octile\nheight 2\nwidth 3\nmap\n...\n.?.\n");
    let e = GridMap::load(&d.join("m.map")).unwrap_err().to_string();
    assert!(e.ends_with("m.map, line 6: column 2: '?' is not a map cell ('.', 'E', 'S', '@', 'T')"), "{e}");
    write(&d, "m.map", "type octile\nheight 3\nwidth 3\nmap\n...\n...\n");
    assert!(GridMap::load(&d.join("m.map")).unwrap_err().to_string().contains("m.map, line 7: the map has 2 rows"));
}
