//! Lifelong operation, shared chargers and spread placement (docs/model.md section 7).

use multibots_core::{Outcome, Scenario, Simulation, State};

/// 40 robots on a 3 x 4 grid of 2 x 6 groups, Poisson orders, shared chargers.
fn lifelong(extra: &str) -> Scenario {
    let text = format!(
        r#"
robots = 40
tasks = []
placement = "spread"
unload = "nearest"
{extra}
[layout_generate]
group_rows = 3
group_cols = 4
group_height = 6
chargers = 3
[charging]
chargers = "shared"
[orders]
rate = 0.2
horizon = 3000
restock = 50
seed = 7
"#
    );
    Scenario::from_toml(&text, "lifelong.toml").unwrap()
}

#[test]
fn goods_are_conserved_at_every_step() {
    let mut sim = Simulation::new(&lifelong("")).unwrap();
    let mut saw_waiting = false;
    while !sim.done() {
        sim.step().unwrap();
        let r = sim.result();
        let l = r.lifelong.unwrap();
        // ordered = delivered + in flight + queued (allocation queue + backlog for stock).
        assert_eq!(l.ordered, r.delivered + l.in_flight + l.queued + l.waiting, "step {}", sim.t());
        saw_waiting |= l.waiting > 0;
        // Each cell has at most one order in the queue or on its way.
        let mut cells: Vec<u32> = sim.queue_cells();
        cells.extend((0..sim.robots().len()).filter(|&i| sim.robots().goods[i] != u32::MAX && !sim.robots().carrying[i]).map(|i| sim.robots().cell[i]));
        let n = cells.len();
        cells.sort_unstable();
        cells.dedup();
        assert_eq!(cells.len(), n, "a cell ordered twice at once at step {}", sim.t());
    }
    let r = sim.result();
    // 3 chargers for 40 robots whose battery lasts 2,000 steps: some strand in the queue, and
    // a run that loses robots is not a normal horizon.
    let stranded = sim.robots().state.iter().filter(|&&s| s == State::Stranded).count();
    assert!(stranded > 0);
    assert_eq!((r.outcome, r.collapse.as_ref().map(|c| c.stranded as usize)), (Some(Outcome::Stranded), Some(stranded)));
    assert_eq!(r.steps, 3000);
    assert_eq!(r.t, None);
    let l = r.lifelong.clone().unwrap();
    assert!(r.delivered > 50, "{}", r.delivered);
    assert!(saw_waiting, "some orders should wait for a restock");
    assert!((r.throughput.unwrap() - r.delivered as f64 / 3.0).abs() < 1e-9);
    assert_eq!(r.windows.len(), 3);
    assert_eq!(r.windows.iter().sum::<u64>(), r.delivered);
    let (p50, p95, p99) = (l.latency_p50.unwrap(), l.latency_p95.unwrap(), l.latency_p99.unwrap());
    assert!(p50 <= p95 && p95 <= p99);
    assert!(r.utilisation > 0.0 && r.utilisation <= 1.0);
    assert!(r.wait_share >= 0.0 && r.wait_share + r.utilisation <= 1.0);
    assert!(l.energy_per_delivery.unwrap() > 0.0);
}

#[test]
fn runs_are_deterministic_and_the_seed_matters() {
    let a = Simulation::new(&lifelong("")).unwrap().run().unwrap();
    let b = Simulation::new(&lifelong("")).unwrap().run().unwrap();
    assert_eq!(a, b);
    let mut s = lifelong("");
    s.orders.as_mut().unwrap().seed = 8;
    let c = Simulation::new(&s).unwrap().run().unwrap();
    assert_ne!(a.lifelong.unwrap().ordered, c.lifelong.unwrap().ordered);
}

#[test]
fn shared_chargers_hold_one_robot_each_and_the_rest_queue() {
    // A battery that reaches the threshold after ~400 steps: everyone needs one of the three
    // chargers soon, with 600 steps of reserve to get there.
    let mut sim = Simulation::new(&lifelong("[robot]\nconsumption = 0.01\nthreshold = 6.0\n")).unwrap();
    let chargers = sim.world().layout.chargers.clone();
    let mut queued = 0;
    while !sim.done() {
        sim.step().unwrap();
        let r = sim.robots();
        for &c in &chargers {
            let heading = (0..r.len()).filter(|&i| matches!(r.state[i], State::ToCharger | State::Charging) && r.charger[i] == c.0).count();
            assert!(heading <= 1, "charger {c} claimed by {heading} robots at step {}", sim.t());
        }
        queued = queued.max((0..r.len()).filter(|&i| r.state[i] == State::WaitCharger).count());
    }
    assert!(queued > 0, "more robots than chargers: some must have queued");
    // Three chargers for 40 robots: most strand in the queue (the chargers are the
    // bottleneck), but every charger served robots.
    assert!(sim.c() >= 3, "robots charged: C = {}", sim.c());
}

#[test]
fn csv_orders_arrive_at_their_steps_and_wait_for_stock() {
    let dir = std::env::temp_dir().join(format!("multibots-lifelong-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("orders.csv");
    // Header, a comment, cell 5 twice: the second order waits for the restock.
    std::fs::write(&csv, "step,cell\n# two orders for one cell\n1,5\n1,5\n3,9\n200,11\n").unwrap();
    let mut s = lifelong("");
    let o = s.orders.as_mut().unwrap();
    o.rate = 0.0;
    o.csv = Some(csv.display().to_string());
    o.horizon = 5000;
    let mut sim = Simulation::new(&s).unwrap();
    sim.step().unwrap();
    let l = sim.result().lifelong.unwrap();
    assert_eq!((l.ordered, l.waiting), (2, 1));
    sim.step().unwrap();
    sim.step().unwrap();
    assert_eq!(sim.result().lifelong.unwrap().ordered, 3);
    let r = sim.run().unwrap();
    assert_eq!(r.delivered, 4, "every order delivered, the second for cell 5 after its restock");
    std::fs::write(&csv, "1,5\nx,7\n").unwrap();
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.starts_with("orders.csv = \"") && e.contains("line 2: expected `step,cell`"), "{e}");
    std::fs::write(&csv, "1,5000\n").unwrap();
    assert!(Simulation::new(&s).err().unwrap().to_string().contains("line 1: cell 5000 out of range"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_lifelong_and_placement_fields_are_named() {
    let err = |extra: &str| Simulation::new(&lifelong(extra)).err().map(|e| e.to_string()).unwrap_or_default();
    let mut s = lifelong("");
    s.orders.as_mut().unwrap().horizon = 0;
    assert_eq!(s.check_values().unwrap_err().to_string(), "orders.horizon = 0: must be at least 1 step");
    let mut s = lifelong("");
    s.orders.as_mut().unwrap().restock = 0;
    assert_eq!(s.check_values().unwrap_err().to_string(), "orders.restock = 0: must be at least 1 step");
    let mut s = lifelong("");
    s.orders.as_mut().unwrap().rate = -1.0;
    assert_eq!(s.check_values().unwrap_err().to_string(), "orders.rate = -1: must be 0 or more");
    let mut s = lifelong("");
    s.orders.as_mut().unwrap().rate = 0.0;
    assert!(s.check_values().unwrap_err().to_string().starts_with("orders.rate = 0: no orders"));
    assert!(err("starts = [\"A\"]\n").starts_with("starts = [\"A\"]: not used with placement = \"spread\""));
    let mut s = lifelong("");
    s.charging.chargers = multibots_core::input::scenario::ChargerUse::Home;
    assert!(Simulation::new(&s).err().unwrap().to_string().starts_with("placement = \"spread\": robots placed on aisles share chargers"));
    let mut s = lifelong("");
    s.robots = 5000;
    assert!(Simulation::new(&s).err().unwrap().to_string().starts_with("robots = 5000: more robots than parking slots"));
}

#[test]
fn paper_scenarios_are_untouched_by_the_extensions() {
    // Shared chargers in the paper layout: one robot per charger anyway; the worked example.
    let mut s = Scenario::paper(1, &[42]);
    s.charging.chargers = multibots_core::input::scenario::ChargerUse::Shared;
    assert_eq!(Simulation::new(&s).unwrap().run().unwrap().t, Some(726));
    let s = Scenario::paper(6, &multibots_core::input::scenario::PAPER_TASKS[0]);
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(r.lifelong, None);
    assert_eq!(r.outcome, Some(Outcome::Complete));
    // The scenario file of a paper run gains no new field.
    assert!(!s.to_toml().contains("placement") && !s.to_toml().contains("orders") && !s.to_toml().contains("chargers"));
}
