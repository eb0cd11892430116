//! People in the aisles (docs/people.md): no person–robot contact, ever; determinism; a
//! person in the way stops a robot, which resumes; the figures agree with each other; and a
//! scenario without people is unchanged.

use multibots_core::scenario::{Humans, Scenario};
use multibots_core::{Simulation, State};

fn with_people(toml: &str) -> Scenario {
    Scenario::from_toml(toml, "test.toml").unwrap()
}

fn paper_with(count: u32, robots: u32, seed: u64) -> Scenario {
    let mut s = Scenario::paper(robots, &[11, 8, 39, 28, 53, 1, 69, 42, 79, 6]);
    s.humans = Some(Humans { count, seed, ..Humans::default() });
    s
}

#[test]
fn people_never_touch_robots_on_the_paper_layout() {
    for (count, robots, seed) in [(1, 1, 0), (5, 3, 1), (10, 6, 2), (20, 6, 3), (40, 6, 4)] {
        let s = paper_with(count, robots, seed);
        let mut sim = Simulation::new(&s).unwrap();
        let r = sim.run().unwrap();
        let p = r.people.clone().expect("figures");
        assert_eq!(p.contacts, 0, "{count} people, {robots} robots: {p:?}");
        assert!(p.min_gap.is_none_or(|g| g >= 0.0), "{p:?}");
        assert_eq!(r.outcome.map(|o| o.as_str()), Some("complete"), "{count} people, {robots} robots: {r:?}");
        assert_eq!(p.person_steps, u64::from(count) * r.steps);
        assert!(p.picks > 0, "{p:?}");
    }
}

#[test]
#[ignore = "a probe: prints a trace"]
fn trace() {
    let args: Vec<u64> = std::env::var("TRACE").unwrap_or("1,1,0".into()).split(',').map(|v| v.parse().unwrap()).collect();
    let s = paper_with(args[0] as u32, args[1] as u32, args[2]);
    let mut sim = Simulation::new(&s).unwrap();
    let mut still = vec![0u32; args[1] as usize];
    let mut prev: Vec<(f64, f64)> = vec![(0.0, 0.0); args[1] as usize];
    while !sim.done() {
        sim.step().unwrap();
        let r = sim.robots();
        let p = sim.people().unwrap();
        for i in 0..r.len() {
            if (r.x[i], r.y[i]) == prev[i] && r.state[i].travels() {
                still[i] += 1;
                if still[i] % 100 == 0 {
                    let near: Vec<String> = (0..p.len())
                        .filter(|&k| (p.x[k] - r.x[i]).hypot(p.y[k] - r.y[i]) < 80.0)
                        .map(|k| format!("p{k}({:.1},{:.1}) walking={}", p.x[k], p.y[k], p.walking().nth(k).unwrap()))
                        .collect();
                    let others: Vec<String> = (0..r.len()).filter(|&j| j != i && (r.x[j] - r.x[i]).hypot(r.y[j] - r.y[i]) < 60.0).map(|j| format!("r{j}({:.0},{:.0})", r.x[j], r.y[j])).collect();
                    println!("{} r{i} {:?} ({:.1},{:.1})->({:.0},{:.0}) still {} near {near:?} {others:?}", sim.result().steps, r.state[i], r.x[i], r.y[i], r.wp_x[i], r.wp_y[i], still[i]);
                }
            } else {
                still[i] = 0;
            }
            prev[i] = (r.x[i], r.y[i]);
        }
    }
    println!("{:?}", sim.result().people);
}
