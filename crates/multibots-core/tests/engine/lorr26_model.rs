//! The 2026 action model against the Start-Kit's own (`ActionModel.cpp`, tag `v3.1.0`), tick by
//! tick: the actions decided, the states after the tick and the messages, text included, on
//! random maps, fleets, squares of 0.3 to 2 cells and counters of 1 to 10
//! (`tests/data/lorr26/README.md` says how the data was made). `LORR26_GOLDEN=FILE` checks a
//! whole golden file of the same form too (all 60 scenarios of the harness).

use flate2::read::GzDecoder;
use multibots_core::rules::grid::action::Action;
use multibots_core::rules::grid::y2026::footprint::{Floor, Pose};
use multibots_core::rules::grid::y2026::model::ActionModel;
use serde_json::Value;
use std::io::Read;

fn action(c: char) -> Action {
    match c {
        'F' => Action::F,
        'R' => Action::R,
        'C' => Action::C,
        'W' => Action::W,
        _ => Action::T,
    }
}

/// Plays every scenario of a golden file; the ticks compared.
fn check(text: &str) -> usize {
    let mut ticks = 0;
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let s: Value = serde_json::from_str(line).unwrap();
        let (rows, cols) = (s["rows"].as_u64().unwrap() as u32, s["cols"].as_u64().unwrap() as u32);
        let map: Vec<bool> =
            s["map"].as_array().unwrap().iter().flat_map(|r| r.as_str().unwrap().chars().map(|c| c == '@' || c == 'T').collect::<Vec<_>>()).collect();
        let floor = Floor::new(rows, cols, map, s["agentSize"].as_f64().unwrap() as f32, s["agentCounter"].as_u64().unwrap() as u32);
        let mut states: Vec<Pose> = s["start"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Pose { loc: p[0].as_u64().unwrap() as u32, heading: p[1].as_u64().unwrap() as u8, count: 0, doing: Action::T })
            .collect();
        let mut model = ActionModel::default();
        let mut next = Vec::new();
        let scenario = s["scenario"].as_u64().unwrap();
        for (t, tick) in s["ticks"].as_array().unwrap().iter().enumerate() {
            if tick.get("exception").is_some() {
                break;
            }
            let mut act: Vec<Action> = tick["req"].as_str().unwrap().chars().map(action).collect();
            model.step(&floor, &states, &mut act, t as u32 + 1, &mut next);
            let decided: String = act.iter().map(|a| a.letter()).collect();
            assert_eq!(decided, tick["dec"].as_str().unwrap(), "scenario {scenario} tick {t}: decided actions");
            for (i, (p, want)) in next.iter().zip(tick["state"].as_array().unwrap()).enumerate() {
                let got = (p.loc, p.heading, p.count, p.doing.letter());
                let want = (
                    want[0].as_u64().unwrap() as u32,
                    want[1].as_u64().unwrap() as u8,
                    want[2].as_u64().unwrap() as u32,
                    want[3].as_str().unwrap().chars().next().unwrap(),
                );
                assert_eq!(got, want, "scenario {scenario} tick {t}: robot {i}'s state");
            }
            let got: Vec<(i64, i64, u64, String)> = model.errors.iter().map(|e| (e.agent, e.other, u64::from(e.time), e.message.clone())).collect();
            let want: Vec<(i64, i64, u64, String)> = tick["errors"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| (e[0].as_i64().unwrap(), e[1].as_i64().unwrap(), e[2].as_u64().unwrap(), e[3].as_str().unwrap().to_string()))
                .collect();
            assert_eq!(got, want, "scenario {scenario} tick {t}: messages");
            states.clone_from(&next);
            ticks += 1;
        }
    }
    ticks
}

#[test]
fn ticks_match_the_start_kits_model() {
    let gz = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/lorr26/actionmodel_golden.jsonl.gz")).unwrap();
    let mut text = String::new();
    GzDecoder::new(&gz[..]).read_to_string(&mut text).unwrap();
    assert_eq!(check(&text), 16 * 150);
    if let Ok(path) = std::env::var("LORR26_GOLDEN") {
        let whole = std::fs::read_to_string(path).unwrap();
        assert!(check(&whole) > 0);
    }
}
