//! The 2026 delays against the Start-Kit's own generator (`DelayGenerator.cpp`, tag `v3.1.0`,
//! built with GCC 12's libstdc++): the same intervals, robot by robot, for the seven example
//! problems' `delayConfig` and ten edge cases (Poisson means of 12, 30 and 100, an odd team,
//! no deviation, a wide Gaussian, `minDelay == maxDelay`, `pDelay` 0 and 1, a range of a
//! million), each over the ticks the golden data covers (`tests/data/lorr26/README.md`).

use flate2::read::GzDecoder;
use multibots_core::input::lorr::{DelayConfig, DurationModel, EventModel};
use multibots_core::rules::grid::y2026::delays::Delays;
use serde_json::Value;
use std::io::Read;

fn config(c: &Value) -> DelayConfig {
    DelayConfig {
        seed: c["seed"].as_u64().unwrap() as u32,
        min_delay: c["minDelay"].as_i64().unwrap() as i32,
        max_delay: c["maxDelay"].as_i64().unwrap() as i32,
        event_model: if c["eventModel"] == "poisson" { EventModel::Poisson } else { EventModel::Bernoulli },
        p_delay: c["pDelay"].as_f64().unwrap(),
        duration_model: if c["durationModel"] == "gaussian" { DurationModel::Gaussian } else { DurationModel::Uniform },
        gauss_mean_ratio: c["gaussMeanRatio"].as_f64().unwrap(),
        gauss_std_ratio: c["gaussStdRatio"].as_f64().unwrap(),
    }
}

#[test]
fn intervals_match_the_start_kits_generator() {
    let gz = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/lorr26/delay_golden.jsonl.gz")).unwrap();
    let mut text = String::new();
    GzDecoder::new(&gz[..]).read_to_string(&mut text).unwrap();
    let mut names = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let g: Value = serde_json::from_str(line).unwrap();
        let n = g["teamSize"].as_u64().unwrap() as usize;
        let mut delays = Delays::new(&config(&g["delayConfig"]), n);
        let mut got = vec![Vec::new(); n];
        let mut started = Vec::new();
        for _ in 0..g["ticks"].as_u64().unwrap() {
            started.clear();
            delays.tick(&mut started);
            for &(a, from, to) in &started {
                got[a as usize].push(vec![u64::from(from), u64::from(to)]);
            }
        }
        let want: Vec<Vec<Vec<u64>>> = serde_json::from_value(g["delayIntervals"].clone()).unwrap();
        let name = g["name"].as_str().unwrap().to_string();
        assert_eq!(got, want, "{name}");
        names.push(name);
    }
    assert_eq!(names.len(), 17);
    assert!(names.iter().any(|n| n == "poisson_lam100"));
}
