//! Contacts judged from outside (docs/metrics.md): after every step, every pair of robots
//! closer than r_i + r_j counts, whatever the robots do (in a bay, queued, standing still).
//! The engine's `contacts` must equal a count over all pairs of `Simulation::robots()`
//! positions, step by step, and `closest` the smallest distance among pairs within
//! r_i + r_j + margin. The count here shares nothing with the engine's grid.

use multibots_core::input::layout_params::Aisles;
use multibots_core::input::scenario::{ChargerUse, Orders, Placement, Tasks};
use multibots_core::{LayoutParams, Scenario, Simulation, Traffic, Unload};

fn xorshift(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

/// `robots` robots on a generated warehouse of `rows` × `cols` groups, the rest drawn with
/// `pick(k)` (a number below `k`): either aisle pattern, 1 to 4 unloading rows, few or many
/// chargers, shared, robots spread over parking slots (bays, charger queues), nearest or first
/// unloading.
fn generated(pick: &mut impl FnMut(u64) -> u64, robots: u32, rows: u32, cols: u32, traffic: Traffic) -> Scenario {
    let mut s = Scenario::paper(robots, &[]);
    let aisles = if pick(2) == 0 { Aisles::Paper } else { Aisles::Alternate };
    let unloading_rows = 1 + pick(u64::from(rows.min(4))) as u32;
    let chargers = 1 + pick(u64::from(cols + 1)) as u32;
    s.layout_generate = Some(LayoutParams { group_rows: rows, group_cols: cols, chargers, unloading_rows, aisles, ..LayoutParams::paper() });
    s.placement = Placement::Spread;
    s.charging.chargers = ChargerUse::Shared;
    s.unload = if pick(2) == 0 { Unload::Nearest } else { Unload::First };
    s.allocator = "nearest".into();
    s.traffic = traffic;
    s
}

/// A random generated warehouse, overloaded, with `robots` robots.
fn random_warehouse(seed: u64, traffic: Traffic) -> Scenario {
    let mut rng = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    let mut pick = |k: u64| xorshift(&mut rng) % k;
    let (rows, cols) = (3 + pick(6) as u32, 3 + pick(8) as u32);
    let robots = 20 + pick(180) as u32;
    let mut s = generated(&mut pick, robots, rows, cols, traffic);
    // Some fleets charge during the run, some never need to.
    s.robot.consumption = [0.0002, 0.002, 0.004][pick(3) as usize];
    s.collision.margin = [0.0, 3.0][pick(2) as usize];
    s.tasks = Tasks::Cells(vec![]);
    s.orders = Some(Orders { rate: f64::from(s.robots) / 60.0, horizon: 1200, restock: 50, seed, csv: None });
    s
}

/// Pairs closer than r_i + r_j, and the smallest distance among pairs within
/// r_i + r_j + margin, over every pair.
fn from_positions(sim: &Simulation, margin: f64) -> (u64, f64) {
    let r = sim.robots();
    let n = r.len();
    let (mut count, mut closest) = (0, f64::INFINITY);
    for i in 0..n {
        for j in i + 1..n {
            let (dx, dy) = (r.x[j] - r.x[i], r.y[j] - r.y[i]);
            let d = (dx * dx + dy * dy).sqrt();
            let touch = r.radius[i] + r.radius[j];
            if d < touch {
                count += 1;
            }
            if d <= touch + margin {
                closest = closest.min(d);
            }
        }
    }
    (count, closest)
}

#[test]
fn contacts_are_every_pair_closer_than_touching_after_every_step() {
    let mut seen = [0u64; 3];
    for seed in 1..=12u64 {
        for (k, traffic) in [Traffic::Wait, Traffic::Gate, Traffic::Reserve].into_iter().enumerate() {
            let mut s = random_warehouse(seed, traffic);
            // A fleet larger than the layout's parking: as many robots as it has slots.
            let mut sim = match Simulation::new(&s) {
                Ok(sim) => sim,
                Err(e) => {
                    let e = e.to_string();
                    let slots = e.split('(').nth(1).and_then(|t| t.split(')').next()).and_then(|t| t.parse().ok());
                    s.robots = slots.unwrap_or_else(|| panic!("{e}"));
                    Simulation::new(&s).unwrap()
                }
            };
            let (mut count, mut closest) = (0, f64::INFINITY);
            while !sim.done() {
                sim.step().unwrap();
                let (c, d) = from_positions(&sim, s.collision.margin);
                count += c;
                closest = closest.min(d);
            }
            let r = sim.result();
            let label = format!("seed {seed}, {traffic:?}, {} robots", s.robots);
            assert_eq!(r.contacts, count, "{label}");
            assert_eq!(r.closest.unwrap_or(f64::INFINITY), closest, "{label}");
            seen[k] += count;
        }
    }
    eprintln!("contacts seen (wait, gate, reserve): {seen:?}");
    // The cases hold contacts under `wait`, so the comparison can fail.
    assert!(seen[0] > 100, "contacts seen: {seen:?}");
}

/// Pairs closer than r_i + r_j, found with buckets of the contact distance (a fleet of
/// thousands makes the pass over every pair too slow); shares nothing with the engine.
fn touching_pairs(sim: &Simulation) -> Vec<(usize, usize, f64)> {
    let r = sim.robots();
    let reach = 2.0 * r.radius.iter().copied().fold(0.0, f64::max);
    let key = |i: usize| ((r.x[i] / reach).floor() as i64, (r.y[i] / reach).floor() as i64);
    let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>> = std::collections::HashMap::new();
    for i in 0..r.len() {
        buckets.entry(key(i)).or_default().push(i);
    }
    let mut pairs = Vec::new();
    for i in 0..r.len() {
        let (cx, cy) = key(i);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &j in buckets.get(&(cx + dx, cy + dy)).map_or(&[][..], |v| &v[..]) {
                    let d = (r.x[j] - r.x[i]).hypot(r.y[j] - r.y[i]);
                    if j > i && d < r.radius[i] + r.radius[j] {
                        pairs.push((i, j, d));
                    }
                }
            }
        }
    }
    pairs
}

#[test]
fn reserve_lets_no_two_robots_touch_on_random_warehouses() {
    // Issue 30's first target, from positions: warehouses of 100 to 2,000 robots with either
    // aisle pattern, nearest or first unloading, few or many shared chargers, batteries that
    // charge or not, some with people on the floor; every step.
    let mut charged = 0;
    for seed in 1..=6u64 {
        let mut rng = seed.wrapping_mul(0xd134_2543_de82_ef95) | 1;
        let mut pick = |k: u64| xorshift(&mut rng) % k;
        let robots = [100, 250, 500, 900, 1400, 2000][seed as usize - 1];
        let cols = f64::from(robots / 4).sqrt() as u32 + pick(5) as u32;
        let rows = robots / (4 * cols) + 2 + pick(3) as u32;
        let mut s = generated(&mut pick, robots, rows, cols, Traffic::Reserve);
        let (aisles, unloading_rows, chargers) = s.layout_generate.as_ref().map(|p| (p.aisles, p.unloading_rows, p.chargers)).unwrap();
        // Small fleets charge within the horizon (a battery cycle of 810 steps of driving); a big
        // warehouse's longest trip needs a battery that lasts longer.
        s.robot.consumption = if robots <= 500 { [0.0002, 0.008][pick(2) as usize] } else { [0.0002, 0.0008][pick(2) as usize] };
        s.collision.margin = [0.0, 3.0][pick(2) as usize];
        if seed % 2 == 0 {
            s.humans = Some(multibots_core::input::scenario::Humans { count: robots / 20, seed, ..Default::default() });
        }
        s.tasks = Tasks::Cells(vec![]);
        s.orders = Some(Orders { rate: f64::from(robots) / 80.0, horizon: 1500, restock: 50, seed, csv: None });
        let label = format!("seed {seed}: {robots} robots, {rows}x{cols} {aisles:?}, {unloading_rows} unloading rows, {chargers} chargers");
        let mut sim = Simulation::new(&s).unwrap_or_else(|e| panic!("{label}: {e}"));
        while !sim.done() {
            sim.step().unwrap();
            let pairs = touching_pairs(&sim);
            assert!(pairs.is_empty(), "{label}, step {}: {:?}", sim.t(), &pairs[..pairs.len().min(5)]);
        }
        let r = sim.result();
        assert_eq!(r.contacts, 0, "{label}");
        assert!(r.delivered > 0, "{label}");
        charged += u64::from(r.c > 0);
    }
    // Charger queues (robots waiting in their bays) are among the cases.
    assert!(charged > 0);
}
