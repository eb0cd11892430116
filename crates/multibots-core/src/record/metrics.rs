//! The indicators T, S and C (spec section 6), Cost_total, the lifelong figures, and what
//! the engine counts per robot.
//!
//! - **T**, task time: the step in which the run completed (every goods delivered, every
//!   robot back home); none for a run that did not complete.
//! - **S**, collisions: waits begun (phase 3).
//! - **C**, charging count: arrivals at a charger to charge (phase 7).
//! - **Cost_total** = w_d · distance + w_t · T + w_c · S, with the scenario's `[cost]`
//!   weights; none where T is none.

use crate::fleet::robot::State;
use crate::input::scenario::{CostWeights, MetricsParams};

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every goods delivered and every robot back at its home charger.
    Complete,
    /// The step limit came first.
    Incomplete,
    /// A lifelong run reached its horizon.
    Horizon,
    /// No robot moved, dwelt or charged for `metrics.gridlock` steps while work remained:
    /// the fleet is jammed (see [`RunResult::gridlock`] for where).
    Gridlock,
    /// Robots ran out of energy while work remained, and the others could do nothing for
    /// `metrics.gridlock` steps (or every robot ran out: nothing more can happen).
    Stranded,
    /// Nothing happened for `metrics.gridlock` steps while work remained, and no robot was
    /// waiting or stranded: robots stood idle (a strategy that hands out no goods).
    Stalled,
    /// A lifelong run reached its horizon with its throughput collapsed: the last windows
    /// each delivered under a tenth of the best window while orders waited (see
    /// [`RunResult::collapse`] for when and where).
    Collapse,
    /// Robots kept moving, but nothing was picked up or delivered for two full battery cycles
    /// while work remained (robots going out and turning back to charge, for ever).
    Livelock,
    /// Original rules only: robots block each other for good, where the authors' code would
    /// wait forever ([`crate::rules::original`]). T is undefined.
    Deadlock,
    /// Original rules only: the authors' code raises an exception in this step, so it has no
    /// answer from here on ([`crate::rules::original`]). T is undefined.
    Fault,
}

impl Outcome {
    /// The outcome's name: `"complete"`, `"incomplete"`, `"horizon"`, `"gridlock"`,
    /// `"stranded"`, `"stalled"`, `"collapse"`, `"livelock"`, `"deadlock"` or `"fault"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Complete => "complete",
            Outcome::Incomplete => "incomplete",
            Outcome::Horizon => "horizon",
            Outcome::Gridlock => "gridlock",
            Outcome::Stranded => "stranded",
            Outcome::Stalled => "stalled",
            Outcome::Collapse => "collapse",
            Outcome::Livelock => "livelock",
            Outcome::Deadlock => "deadlock",
            Outcome::Fault => "fault",
        }
    }
}

/// Per-robot counters, one column each. Counts are 32-bit: no run is longer than
/// [`crate::input::limits::MAX_STEPS`] steps, and a robot counts at most one of each per step.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RobotStats {
    /// Distance travelled, px.
    pub distance: Vec<f64>,
    /// Steps spent waiting at collisions.
    pub wait_steps: Vec<u32>,
    /// Collisions S of this robot (waits begun).
    pub collisions: Vec<u32>,
    /// Steps ending in each state, indexed by the state code.
    pub state_steps: Vec<[u32; State::COUNT]>,
    /// Energy consumed.
    pub energy_used: Vec<f64>,
    /// Goods delivered.
    pub delivered: Vec<u32>,
    /// Charges C of this robot.
    pub charges: Vec<u32>,
    /// Steps spent waiting while on an order (TO_PICKUP or TO_DROP).
    pub order_waits: Vec<u32>,
}

impl RobotStats {
    /// Zeroed counters for `n` robots.
    #[must_use]
    pub fn new(n: usize) -> RobotStats {
        RobotStats {
            distance: vec![0.0; n],
            wait_steps: vec![0; n],
            collisions: vec![0; n],
            state_steps: vec![[0; State::COUNT]; n],
            energy_used: vec![0.0; n],
            delivered: vec![0; n],
            charges: vec![0; n],
            order_waits: vec![0; n],
        }
    }
}

/// What a run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Task time T: the step in which the run completed; `None` when incomplete.
    pub t: Option<u64>,
    /// Collisions S.
    pub s: u64,
    /// Charging count C.
    pub c: u64,
    /// `None` only while the run is still going.
    pub outcome: Option<Outcome>,
    /// Steps run.
    pub steps: u64,
    pub delivered: u64,
    pub goods_total: u64,
    /// Robots that ran out of energy.
    pub stranded: Vec<u32>,
    /// Cost_total = w_d · distance + w_t · T + w_c · S; `None` where T is `None`.
    pub cost: Option<f64>,
    /// Steps per throughput window.
    pub window: u64,
    /// Deliveries in each complete window of `window` steps, from the start.
    pub windows: Vec<u64>,
    /// Deliveries per 1,000 steps after the warm-up; `None` if the run ended before it.
    pub throughput: Option<f64>,
    /// Deliveries per 1,000 steps over the last half of the complete windows after the
    /// warm-up: the rate the fleet sustains; `None` without such a window.
    pub sustained_throughput: Option<f64>,
    /// Share of robot-steps after the warm-up spent waiting at collisions.
    pub wait_share: f64,
    /// Share of robot-steps after the warm-up spent working on orders (TO_PICKUP, LOADING,
    /// TO_DROP or UNLOADING) and not waiting.
    pub utilisation: f64,
    /// Contacts: pairs of robots closer than r_i + r_j after a step in which one of them
    /// moved, counted once per pair and step.
    pub contacts: u64,
    /// The smallest distance between two robots seen after a move (pairs within reach of
    /// each other only); `None` if no two robots ever came near.
    pub closest: Option<f64>,
    /// Where the fleet jammed, for outcome `gridlock`.
    pub gridlock: Option<Gridlock>,
    /// When and where throughput collapsed, or robots stranded, for outcomes `collapse` and
    /// `stranded`.
    pub collapse: Option<Collapse>,
    /// How busy each unloading zone, charger and the busiest crossings were, and their
    /// queues (paper rules; empty under the original rules).
    pub resources: Vec<crate::record::resources::ResourceUse>,
    /// The resource with the longest mean queue, and what would relieve it.
    pub bottleneck: Option<crate::record::resources::Bottleneck>,
    pub robots: RobotStats,
    /// Lifelong runs only: throughput, latency, utilisation, energy per delivery.
    pub lifelong: Option<LifelongStats>,
    /// Runs with people only: the safety figures (docs/people.md).
    pub people: Option<crate::people::PeopleFigures>,
}

/// The figures of a lifelong run (docs/model.md section 7).
#[derive(Clone, Debug, PartialEq)]
pub struct LifelongStats {
    /// Orders that arrived (the task list's count as arriving at step 0).
    pub ordered: u64,
    /// Orders a robot is fetching or carrying.
    pub in_flight: u64,
    /// Orders in the allocation queue.
    pub queued: u64,
    /// Orders waiting for their cell to restock.
    pub waiting: u64,
    /// Order-to-delivery latency, steps: nearest-rank percentiles and the mean.
    pub latency_p50: Option<u64>,
    pub latency_p95: Option<u64>,
    pub latency_p99: Option<u64>,
    pub latency_mean: Option<f64>,
    /// Energy the fleet used per delivery.
    pub energy_per_delivery: Option<f64>,
}

/// Where a fleet jammed.
#[derive(Clone, Debug, PartialEq)]
pub struct Gridlock {
    /// The step the gridlock was declared (the last of the steps without progress).
    pub step: u64,
    /// Robots waiting at collisions, ascending.
    pub waiting: Vec<u32>,
    /// The crossings waiting robots stand at or queue for (the node ahead of them), with
    /// how many robots each, most first (at most ten).
    pub crossings: Vec<(String, u32)>,
}

/// When and where a lifelong run's throughput collapsed, or its robots stranded.
#[derive(Clone, Debug, PartialEq)]
pub struct Collapse {
    /// The first step of the first window of the run of last windows that each delivered
    /// under a tenth of the best window; if the throughput held but robots stranded, the step
    /// the first of them ran out of energy.
    pub step: u64,
    /// Deliveries in the best window, and in the last one.
    pub best: u64,
    pub last: u64,
    /// Robots out of energy at the end.
    pub stranded: u32,
    /// Whether the windows collapsed (else robots stranded while the throughput held).
    pub collapsed: bool,
    /// The step the first robot ran out of energy, if any did.
    pub first_stranded: Option<u64>,
    /// Where robots stood still at the end: the crossings that waiting or stranded robots
    /// (only stranded ones if the throughput held) stand at or drive towards, with how many
    /// robots each, most first (at most ten).
    pub crossings: Vec<(String, u32)>,
}

/// Sums at the end of the warm-up, subtracted from the final ones for steady figures.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Snapshot {
    delivered: u64,
    waits: u64,
    on_orders: u64,
    order_waits: u64,
}

impl Snapshot {
    fn of(t: &Tally) -> Snapshot {
        let st = &t.stats;
        Snapshot {
            delivered: t.delivered,
            waits: st.wait_steps.iter().map(|&w| u64::from(w)).sum(),
            on_orders: st
                .state_steps
                .iter()
                .map(|s| [State::ToPickup, State::Loading, State::ToDrop, State::Unloading].iter().map(|&k| u64::from(s[k as usize])).sum::<u64>())
                .sum(),
            order_waits: st.order_waits.iter().map(|&w| u64::from(w)).sum(),
        }
    }
}

/// The running counts of a simulation: the step, S, C and deliveries, and per-robot counters.
#[derive(Clone, Debug)]
pub(crate) struct Tally {
    /// The current step (0 before the first).
    pub t: u64,
    pub s: u64,
    pub c: u64,
    pub delivered: u64,
    /// Goods in the task list (orders so far, in lifelong runs).
    pub goods_total: u64,
    pub stats: RobotStats,
    window: u64,
    windows: Vec<u64>,
    /// Deliveries when the current window began.
    window_mark: u64,
    warmup: u64,
    /// Taken when the warm-up ends.
    steady: Option<Snapshot>,
    gridlock_after: u64,
    /// Steps in a row without progress.
    pub stalled: u64,
    pub contacts: u64,
    pub closest: f64,
    pub gridlock: Option<Gridlock>,
    pub collapse: Option<Collapse>,
    /// The step the first robot ran out of energy.
    pub first_stranded: Option<u64>,
    /// The last step a robot picked up or delivered goods.
    pub last_work: u64,
    /// Steps without a pickup or delivery (while work remains) that make a livelock; 0: never.
    pub livelock_after: u64,
}

impl Tally {
    #[must_use]
    pub fn new(robots: usize, goods_total: u64, p: &MetricsParams) -> Tally {
        let mut t = Tally {
            t: 0,
            s: 0,
            c: 0,
            delivered: 0,
            goods_total,
            stats: RobotStats::new(robots),
            window: p.window,
            windows: Vec::new(),
            window_mark: 0,
            warmup: p.warmup,
            steady: None,
            gridlock_after: p.gridlock,
            stalled: 0,
            contacts: 0,
            closest: f64::INFINITY,
            gridlock: None,
            collapse: None,
            first_stranded: None,
            last_work: 0,
            livelock_after: 0,
        };
        if p.warmup == 0 {
            t.steady = Some(Snapshot::default());
        }
        t
    }

    /// Steps left out of the steady figures.
    #[must_use]
    pub fn warmup(&self) -> u64 {
        self.warmup
    }

    /// With livelock detection after `steps` steps without a pickup or delivery.
    #[must_use]
    pub fn with_livelock_after(mut self, steps: u64) -> Tally {
        self.livelock_after = steps;
        self
    }

    /// Whether work has waited too long for a pickup or a delivery.
    #[must_use]
    pub fn livelocked(&self, work_remains: bool) -> bool {
        work_remains && self.livelock_after > 0 && self.t - self.last_work >= self.livelock_after
    }

    /// How many of the next steps, while work remains, a step limit of `step_limit` and, each
    /// step, `progress` as given, surely end with no verdict: not gridlocked
    /// ([`Tally::end_step`]), not livelocked, not at the limit. The pickups and deliveries that
    /// would reset the livelock count are not counted on.
    #[must_use]
    pub(crate) fn steps_without_verdict(&self, progress: bool, step_limit: u64) -> u64 {
        // Step j from now (j = 1, 2, ...) is step t + j, with `stalled + j` steps in a row
        // without progress.
        let mut k = step_limit.saturating_sub(self.t + 1);
        if !progress && self.gridlock_after > 0 {
            k = k.min(self.gridlock_after.saturating_sub(self.stalled + 1));
        }
        if self.livelock_after > 0 {
            k = k.min((self.last_work + self.livelock_after).saturating_sub(self.t + 1));
        }
        k
    }

    /// End of a step: windows, the warm-up, and the count of steps without progress.
    /// Returns whether the fleet is gridlocked (when work remains).
    pub fn end_step(&mut self, progress: bool, work_remains: bool) -> bool {
        if self.t % self.window == 0 {
            self.windows.push(self.delivered - self.window_mark);
            self.window_mark = self.delivered;
        }
        if self.t == self.warmup && self.steady.is_none() {
            self.steady = Some(Snapshot::of(self));
        }
        self.stalled = if progress || !work_remains { 0 } else { self.stalled + 1 };
        self.gridlock_after > 0 && self.stalled >= self.gridlock_after
    }
}

/// Cost_total of a complete run with task time `t`, fleet distance `distance` and `s`
/// collisions.
#[must_use]
pub(crate) fn cost_total(w: &CostWeights, t: Option<u64>, distance: f64, s: u64) -> Option<f64> {
    t.map(|t| w.distance * distance + w.time * t as f64 + w.collision * s as f64)
}

impl Tally {
    /// The result so far: `outcome` (None while running), the robots out of energy, the fleet
    /// size, the cost weights and the lifelong figures.
    #[must_use]
    pub fn result(&self, outcome: Option<Outcome>, stranded: Vec<u32>, robots: usize, weights: &CostWeights, lifelong: Option<LifelongStats>) -> RunResult {
        let t = (outcome == Some(Outcome::Complete)).then_some(self.t);
        RunResult {
            t,
            s: self.s,
            c: self.c,
            outcome,
            steps: self.t,
            delivered: self.delivered,
            goods_total: self.goods_total,
            stranded,
            cost: cost_total(weights, t, self.stats.distance.iter().sum(), self.s),
            window: self.window,
            windows: self.windows.clone(),
            throughput: None,
            sustained_throughput: self.sustained(),
            wait_share: 0.0,
            utilisation: 0.0,
            contacts: self.contacts,
            closest: self.closest.is_finite().then_some(self.closest),
            gridlock: self.gridlock.clone(),
            collapse: self.collapse.clone(),
            resources: Vec::new(),
            bottleneck: None,
            robots: self.stats.clone(),
            lifelong,
            people: None,
        }
        .with_steady(self.steady.map(|s| (s, Snapshot::of(self), self.t - self.warmup, robots as u64)))
    }

    /// Whether the throughput has collapsed: at least 4 complete windows, of which the last
    /// quarter (at least 2) each delivered under a tenth of the best window. Returns the
    /// first window of the run of last windows under a tenth of the best, the best and the
    /// last window's deliveries.
    #[must_use]
    pub fn collapsed(&self) -> Option<(usize, u64, u64)> {
        let w = &self.windows;
        let best = w.iter().copied().max().unwrap_or(0);
        let low = |d: u64| d * 10 < best;
        let tail = (w.len() / 4).max(2);
        if w.len() < 4 || best == 0 || !w[w.len() - tail..].iter().all(|&d| low(d)) {
            return None;
        }
        let first = w.iter().rposition(|&d| !low(d)).map_or(0, |k| k + 1);
        Some((first, best, w[w.len() - 1]))
    }

    /// Steps per window.
    #[must_use]
    pub fn window(&self) -> u64 {
        self.window
    }

    /// Deliveries in each complete window so far.
    #[must_use]
    pub fn windows(&self) -> &[u64] {
        &self.windows
    }

    /// Deliveries per 1,000 steps over the last half of the complete windows after the
    /// warm-up.
    fn sustained(&self) -> Option<f64> {
        let first = self.warmup.div_ceil(self.window) as usize;
        let after = self.windows.get(first..).unwrap_or(&[]);
        let last_half = &after[after.len() / 2..];
        (!last_half.is_empty()).then(|| last_half.iter().sum::<u64>() as f64 * 1000.0 / (last_half.len() as u64 * self.window) as f64)
    }
}

impl RunResult {
    /// Fills the steady-state figures from the warm-up snapshot and the final sums, over
    /// `steps` steps after the warm-up and `robots` robots.
    fn with_steady(mut self, steady: Option<(Snapshot, Snapshot, u64, u64)>) -> RunResult {
        if let Some((at_warmup, now, steps, robots)) = steady {
            let robot_steps = (steps * robots).max(1) as f64;
            self.throughput = (steps > 0).then(|| (now.delivered - at_warmup.delivered) as f64 * 1000.0 / steps as f64);
            self.wait_share = (now.waits - at_warmup.waits) as f64 / robot_steps;
            let work = (now.on_orders - at_warmup.on_orders).saturating_sub(now.order_waits - at_warmup.order_waits);
            self.utilisation = work as f64 / robot_steps;
        }
        self
    }
}
