//! People in the aisles (docs/people.md): no person–robot contact, ever; determinism; a
//! person in a robot's path stops it, and it resumes; the figures agree with each other; and
//! a scenario without people is unchanged.

use multibots_core::input::scenario::{Humans, Scenario};
use multibots_core::Simulation;

fn paper_with(count: u32, robots: u32, seed: u64) -> Scenario {
    let mut s = Scenario::paper(robots, &[11, 8, 39, 28, 53, 1, 69, 42, 79, 6]);
    s.humans = Some(Humans { count, seed, ..Humans::default() });
    s
}

#[test]
fn people_never_touch_robots_and_the_work_gets_done() {
    for (count, robots, seed) in [(1, 1, 0), (5, 3, 1), (10, 6, 2), (20, 6, 3), (3, 2, 7), (15, 4, 8)] {
        let s = paper_with(count, robots, seed);
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let p = r.people.clone().expect("figures");
        assert_eq!(p.contacts, 0, "{count} people, {robots} robots: {p:?}");
        assert!(p.min_gap.is_some_and(|g| g >= 0.0), "{p:?}");
        assert_eq!(r.outcome.map(multibots_core::Outcome::as_str), Some("complete"), "{count} people, {robots} robots: {p:?}");
        assert_eq!(p.person_steps, u64::from(count) * r.steps);
        assert!(p.picks > 0 && p.warning_steps > 0, "{p:?}");
        assert!(p.gap_p1.unwrap() >= p.min_gap.unwrap().floor() - 1e-9, "{p:?}");
        assert!(p.stopped_steps >= p.protective_stops, "{p:?}");
    }
}

#[test]
fn crowds_never_touch_robots() {
    // Many more people than the small warehouse can take: the fleet may not finish (a robot
    // can run flat waiting), but nobody is touched.
    for (count, robots, seed) in [(40, 6, 4), (80, 6, 5)] {
        let mut s = paper_with(count, robots, seed);
        s.step_limit = 6000;
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let p = r.people.unwrap();
        assert_eq!(p.contacts, 0, "{p:?}");
        assert!(p.min_gap.unwrap() >= 0.0);
    }
}

#[test]
fn people_among_a_thousand_robots() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/warehouse-1000.toml")).unwrap();
    let mut s = Scenario::from_toml(&text, "warehouse-1000.toml").unwrap();
    s.humans = Some(Humans { count: 200, seed: 3, ..Humans::default() });
    s.orders.as_mut().unwrap().horizon = 2500;
    for traffic in ["wait", "gate", "reserve"] {
        s.traffic = toml::from_str::<toml::Table>(&format!("t = \"{traffic}\"")).unwrap()["t"].clone().try_into().unwrap();
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let p = r.people.unwrap();
        assert_eq!(p.contacts, 0, "{traffic}: {p:?}");
        assert!(p.protective_stops > 0 && p.picks > 0, "{traffic}: {p:?}");
        assert!(r.delivered > 0, "{traffic}");
        if traffic == "reserve" {
            // A robot stopped for a person is a standing robot its lane keeps its distance
            // from: no robot touches another (issue 30, item 6).
            assert_eq!(r.contacts, 0, "{:?}", r.closest);
        }
    }
}

#[test]
fn tours_from_a_csv() {
    // Person 0 picks cells 11 and 53 (in that order, again and again); person 1 cell 79.
    let dir = std::env::temp_dir().join(format!("mb-people-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("tours.csv");
    std::fs::write(&csv, "person,cell\n0,11\n0,53\n1,79\n").unwrap();
    let mut s = paper_with(2, 2, 0);
    s.humans.as_mut().unwrap().csv = Some(csv.display().to_string());
    s.step_limit = 3000;
    let r = Simulation::new(&s).unwrap().run().unwrap();
    let p = r.people.unwrap();
    assert_eq!(p.contacts, 0);
    assert!(p.picks >= 3 && p.tours >= 1, "{p:?}");
    std::fs::write(&csv, "0,80\n").unwrap();
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.contains("humans.csv") && e.contains("cell 80"), "{e}");
    std::fs::write(&csv, "2,1\n").unwrap();
    assert!(Simulation::new(&s).err().unwrap().to_string().contains("person 2"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn same_seed_same_run() {
    let s = paper_with(12, 5, 9);
    let (mut a, mut b) = (Simulation::new(&s).unwrap(), Simulation::new(&s).unwrap());
    while !a.done() {
        a.step().unwrap();
        b.step().unwrap();
        let (pa, pb) = (a.people().unwrap(), b.people().unwrap());
        assert!(pa.x.iter().zip(&pb.x).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert!(pa.y.iter().zip(&pb.y).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert_eq!(a.robots().x, b.robots().x);
    }
    assert_eq!(a.result(), b.result());
    let other = Simulation::new(&paper_with(12, 5, 10)).unwrap().run().unwrap();
    assert_ne!(other.people, a.result().people, "another seed, other tours");
}

#[test]
fn without_people_nothing_changes() {
    let plain = Scenario::paper(4, &[11, 8, 39, 28, 53, 1, 69, 42, 79, 6]);
    let mut zero = plain.clone();
    zero.humans = Some(Humans::default()); // count 0
    let (a, b) = (Simulation::new(&plain).unwrap().run().unwrap(), Simulation::new(&zero).unwrap().run().unwrap());
    assert_eq!(a, b);
    assert!(a.people.is_none());
}

#[test]
fn a_person_in_the_path_stops_the_robot_which_then_resumes() {
    // One robot, one person whose tour crosses its path: the robot stops (a protective
    // stop, not a collision) and still completes; S stays 0.
    let mut stopped_some = false;
    for seed in 0..6 {
        let s = paper_with(1, 1, seed);
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let p = r.people.unwrap();
        assert_eq!(r.s, 0);
        assert_eq!(r.outcome.map(multibots_core::Outcome::as_str), Some("complete"));
        if p.protective_stops > 0 {
            stopped_some = true;
            assert!(p.stopped_steps >= p.protective_stops);
        }
    }
    assert!(stopped_some, "some tour crosses the robot's path");
}

#[test]
fn people_figures_are_refused_with_the_original_rules_and_bad_values() {
    let mut s = paper_with(2, 2, 0);
    s.rules = toml::from_str::<toml::Table>("r = \"original\"").unwrap()["r"].clone().try_into().unwrap();
    assert!(Simulation::new(&s).err().unwrap().to_string().contains("humans.count"));
    for (field, h) in [
        ("humans.speed", Humans { count: 1, speed: f64::NAN, ..Humans::default() }),
        ("humans.slow", Humans { count: 1, slow: 0.0, ..Humans::default() }),
        ("humans.count", Humans { count: 10_000_000, ..Humans::default() }),
        ("humans.tour", Humans { count: 1, tour: 0, ..Humans::default() }),
        ("humans.px_per_m", Humans { count: 1, px_per_m: 1e300, ..Humans::default() }),
    ] {
        let mut s = paper_with(1, 1, 0);
        s.humans = Some(h);
        let e = Simulation::new(&s).err().unwrap().to_string();
        assert!(e.contains(field), "{e}");
    }
}

/// Every field of `[humans]` has its range (docs/limits.md), checked before anything is
/// built from it: a tour of 4294967295 cells aborted the process (17 GB asked for), a tiny
/// deceleration, scale or step panicked in the zones, and a wide warning zone blamed
/// `px_per_m`.
#[test]
fn every_humans_field_is_bounded_and_the_error_names_it() {
    let cases = [
        (Humans { tour: u32::MAX, ..Humans::default() }, "humans.tour = 4294967295: at most 100 cells per tour (docs/limits.md)"),
        (Humans { decel: 1e-300, ..Humans::default() }, "humans.decel = 1e-300: must be from 0.01 and at most 100 m/s² (docs/limits.md)"),
        (Humans { px_per_m: 1e-300, ..Humans::default() }, "humans.px_per_m = 1e-300: must be from 0.01 and at most 1000 px per m (docs/limits.md)"),
        (Humans { step_seconds: 1e-300, ..Humans::default() }, "humans.step_seconds = 1e-300: must be from 0.001 and at most 10 s (docs/limits.md)"),
        (Humans { speed: 1e6, ..Humans::default() }, "humans.speed = 1000000: must be above 0 and at most 10 m/s (docs/limits.md)"),
        (Humans { radius: 1e5, ..Humans::default() }, "humans.radius = 100000: must be above 0 and at most 5 m (docs/limits.md)"),
        (Humans { warning: 1e6, ..Humans::default() }, "humans.warning = 1000000: at most 100 m (docs/limits.md)"),
        (Humans { protective: f64::INFINITY, ..Humans::default() }, "humans.protective = inf: must be 0 or more"),
    ];
    for (h, want) in cases {
        let mut s = paper_with(1, 1, 0);
        s.humans = Some(Humans { count: 2, ..h });
        assert_eq!(Simulation::new(&s).err().unwrap().to_string(), want);
    }
    // The robots' stopping distance: its largest factor is named.
    let mut s = paper_with(1, 1, 0);
    s.humans = Some(Humans { count: 2, ..Humans::default() });
    s.robot.speed = 1e5;
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.starts_with("robot.speed = 100000: a robot would need "), "{e}");
    s.robot.speed = 40.0;
    s.humans = Some(Humans { count: 2, decel: 0.01, px_per_m: 0.01, ..Humans::default() });
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.starts_with("humans.px_per_m = 0.01: a robot would need "), "{e}");
    // At the edges of every range the run is built.
    let mut s = paper_with(1, 1, 0);
    s.humans = Some(Humans { count: 2, tour: 100, decel: 0.01, step_seconds: 10.0, speed: 10.0, radius: 0.01, warning: 100.0, ..Humans::default() });
    assert!(Simulation::new(&s).is_ok());
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
                    let others: Vec<String> = (0..r.len())
                        .filter(|&j| j != i && (r.x[j] - r.x[i]).hypot(r.y[j] - r.y[i]) < 60.0)
                        .map(|j| format!("r{j}({:.0},{:.0})", r.x[j], r.y[j]))
                        .collect();
                    println!(
                        "{} r{i} {:?} ({:.1},{:.1})->({:.0},{:.0}) still {} near {near:?} {others:?}",
                        sim.result().steps,
                        r.state[i],
                        r.x[i],
                        r.y[i],
                        r.wp_x[i],
                        r.wp_y[i],
                        still[i]
                    );
                }
            } else {
                still[i] = 0;
            }
            prev[i] = (r.x[i], r.y[i]);
        }
    }
    println!("{:?}", sim.result().people);
}

#[test]
fn the_safety_figures_count_every_robot_near_a_person_as_positions_give_it() {
    // Robots with a person inside their warning zone, step by step, recomputed from the
    // positions after each step, and the smallest gap. Under spread placement robots step
    // into and out of bays, landing beside their route beyond a step of travel: they count
    // too (the people's queries once missed such a robot when the grid's cells did not
    // happen to hold its place from before the move).
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../benchmarks/sizes/people.toml")).unwrap();
    let s = Scenario::from_toml(&text, "people.toml").unwrap();
    let h = s.humans.clone().unwrap();
    let rh = h.radius * h.px_per_m;
    let mut sim = Simulation::new(&s).unwrap();
    let warning = sim.people().unwrap().zone_radii()[1];
    let (mut samples, mut min_gap) = (0u64, f64::INFINITY);
    for _ in 0..2000 {
        sim.step().unwrap();
        let (r, p) = (sim.robots(), sim.people().unwrap());
        for i in 0..r.len() {
            let mut near = false;
            for k in 0..p.len() {
                let d = (p.x[k] - r.x[i]).hypot(p.y[k] - r.y[i]);
                if d < warning {
                    near = true;
                    min_gap = min_gap.min(d - r.radius[i] - rh);
                }
            }
            samples += u64::from(near);
        }
    }
    let f = sim.people().unwrap().figures(sim.t());
    assert!(samples > 100, "people meet robots: {samples}");
    assert_eq!(f.warning_steps, samples, "{f:?}");
    assert_eq!(f.min_gap, Some(min_gap), "{f:?}");
}
