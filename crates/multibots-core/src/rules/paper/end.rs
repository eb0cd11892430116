//! Phase 8 (spec section 4): completion, then a fleet that can do nothing more (all
//! stranded, or jammed), then the step limit or the horizon; and the run's result so far
//! ([`crate::record::metrics`] says what each figure means).

use crate::fleet::placement::Homes;
use crate::fleet::robot::{Robots, State};
use crate::ids::NONE;
use crate::people::PeopleFigures;
use crate::record::metrics::{Collapse, Gridlock, LifelongStats, Outcome, RunResult};
use crate::rules::paper::goods_queue::GoodsQueue;
use crate::rules::paper::lifelong::{self, Lifelong};
use crate::rules::paper::pipeline::Pipeline;
use crate::rules::paper::state::Record;
use crate::rules::paper::{Paper, Params};
use crate::world::World;

impl Pipeline {
    /// Phase 8: completion first, then a fleet that can do nothing more (all stranded, or
    /// jammed), then the step limit (or the horizon).
    pub(crate) fn end(&self, p: &Params, world: &World, robots: &Robots, goods: &GoodsQueue, homes: &Homes, record: &mut Record) {
        let n = robots.len();
        let (waits, _) = crate::traffic::moves(self.traffic.as_ref(), &self.collisions, n);
        record.observe_resources(robots, waits, 1);
        let tally = &mut record.tally;
        let complete = goods.lifelong.is_none() && tally.delivered == tally.goods_total && (0..n).all(|i| homes.at_home(robots, i));
        let work_remains = if goods.lifelong.is_some() { tally.delivered < tally.goods_total } else { !complete };
        let jammed = tally.end_step(self.progress, work_remains);
        let mut end = End { world, robots, waits, record };
        if complete {
            end.record.outcome = Some(Outcome::Complete);
        } else if work_remains && robots.state.iter().all(|&s| s == State::Stranded) {
            end.report_strand(None);
            end.record.outcome = Some(Outcome::Stranded);
        } else if jammed {
            // Collision waiting's own waits, not a traffic policy's (`reserve` leaves them
            // empty).
            end.declare_stall(&self.collisions.waits);
        } else if end.record.tally.livelocked(work_remains) {
            end.record.outcome = Some(Outcome::Livelock);
        } else if let Some(ll) = &goods.lifelong {
            if end.record.tally.t >= ll.horizon {
                end.record.outcome = Some(end.at_horizon(work_remains));
            }
        } else if end.record.tally.t >= p.step_limit {
            end.record.outcome = Some(Outcome::Incomplete);
        }
    }
}

/// What phase 8's verdicts read and write: `waits` is phase 3's answer.
struct End<'a> {
    world: &'a World,
    robots: &'a Robots,
    waits: &'a [bool],
    record: &'a mut Record,
}

impl End<'_> {
    /// How a lifelong run that reached its horizon ended: `horizon`, or, while orders waited,
    /// `stranded` if robots ran out of energy (one by one while the rest still moved: the
    /// fleet is shrinking, whatever its throughput), else `collapse` if its throughput
    /// collapsed ([`crate::record::metrics::Tally::collapsed`]), with when and where in the
    /// result.
    fn at_horizon(&mut self, work_remains: bool) -> Outcome {
        let r = &self.robots;
        let n = r.len();
        let stranded = (0..n).filter(|&i| r.state[i] == State::Stranded).count() as u32;
        let collapsed = self.record.tally.collapsed();
        if !work_remains || (collapsed.is_none() && stranded == 0) {
            return Outcome::Horizon;
        }
        self.report_strand(collapsed);
        if stranded > 0 {
            Outcome::Stranded
        } else {
            Outcome::Collapse
        }
    }

    /// Fills the result's `collapse` (when and where) for a run that ends `collapse` or
    /// `stranded`: from the collapse's first window if the windows `collapsed` (first window,
    /// best, last), else from the step the first robot ran out of energy; where the stranded
    /// robots (and after a collapse the waiting ones) stand.
    fn report_strand(&mut self, collapsed: Option<(usize, u64, u64)>) {
        let r = &self.robots;
        let n = r.len();
        let stranded = (0..n).filter(|&i| r.state[i] == State::Stranded).count() as u32;
        let out = |i: usize| r.state[i] == State::Stranded;
        let crossings = if collapsed.is_some() {
            let waits = self.waits;
            self.busiest_nodes((0..n).filter(|&i| waits[i] || out(i)))
        } else {
            // Not the waits: a stall names its waiting robots itself (`declare_stall`).
            self.busiest_nodes((0..n).filter(|&i| out(i)))
        };
        let windows = self.record.tally.windows();
        let first_stranded = (stranded > 0).then(|| self.record.tally.first_stranded.unwrap_or(self.record.tally.t));
        let (step, best, last) = match collapsed {
            Some((first, best, last)) => (first as u64 * self.record.tally.window() + 1, best, last),
            None => (first_stranded.unwrap_or(self.record.tally.t), windows.iter().copied().max().unwrap_or(0), windows.last().copied().unwrap_or(0)),
        };
        self.record.tally.collapse = Some(Collapse { step, best, last, stranded, collapsed: collapsed.is_some(), first_stranded, crossings });
    }

    /// The nodes `robots` stand at or drive towards, with how many robots each, most first
    /// (at most ten).
    fn busiest_nodes(&self, robots: impl Iterator<Item = usize>) -> Vec<(String, u32)> {
        let r = &self.robots;
        let layout = &self.world.layout;
        let mut per_node = vec![0u32; layout.nodes.len()];
        for i in robots {
            let node = if r.at_node[i] == NONE { r.edge_v[i] } else { r.at_node[i] };
            if node != NONE {
                per_node[node as usize] += 1;
            }
        }
        let mut crossings: Vec<(String, u32)> = per_node.iter().enumerate().filter(|(_, &c)| c > 0).map(|(k, &c)| (layout.nodes[k].name.clone(), c)).collect();
        crossings.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
        crossings.truncate(10);
        crossings
    }

    /// Ends a run that made no progress for too long: a gridlock (robots wait, and where),
    /// stranded robots, or robots standing idle.
    fn declare_stall(&mut self, waits: &[bool]) {
        let r = &self.robots;
        let waiting: Vec<u32> = (0..r.len()).filter(|&i| waits[i]).map(|i| i as u32).collect();
        if waiting.is_empty() {
            let stranded = r.state.contains(&crate::fleet::robot::State::Stranded);
            if stranded {
                self.report_strand(None);
            }
            self.record.outcome = Some(if stranded { Outcome::Stranded } else { Outcome::Stalled });
            return;
        }
        let crossings = self.busiest_nodes(waiting.iter().map(|&i| i as usize));
        self.record.tally.gridlock = Some(Gridlock { step: self.record.tally.t, waiting, crossings });
        self.record.outcome = Some(Outcome::Gridlock);
    }
}

impl Paper {
    /// The indicators and per-robot statistics so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        let r = &self.robots;
        let stranded = (0..r.len()).filter(|&i| r.state[i] == State::Stranded).map(|i| i as u32).collect();
        let lifelong = self.goods.lifelong.as_ref().map(|ll| self.lifelong_stats(ll));
        let rec = &self.record;
        let t = rec.tally.t;
        let mut result = rec.tally.result(rec.outcome, stranded, r.len(), &rec.cost_weights, lifelong);
        let crowd = &self.crowd;
        result.people = crowd.people.as_ref().map(|p| PeopleFigures { alone: crowd.alone.as_ref().map(|a| Box::new(a.figures(t))), ..p.figures(t) });
        let stranded = rec.outcome == Some(Outcome::Stranded);
        (result.resources, result.bottleneck) = rec.usage.report(&self.world.layout, &rec.setting, stranded);
        result
    }

    fn lifelong_stats(&self, ll: &Lifelong) -> LifelongStats {
        let mut lat = ll.latencies.clone();
        lat.sort_unstable();
        let tally = &self.record.tally;
        let energy: f64 = tally.stats.energy_used.iter().sum();
        let r = &self.robots;
        LifelongStats {
            ordered: ll.ordered(),
            in_flight: (0..r.len()).filter(|&i| r.goods[i] != crate::ids::NONE).count() as u64,
            queued: self.goods.queue.len() as u64,
            waiting: ll.waiting,
            latency_p50: lifelong::percentile(&lat, 50.0),
            latency_p95: lifelong::percentile(&lat, 95.0),
            latency_p99: lifelong::percentile(&lat, 99.0),
            latency_mean: (!lat.is_empty()).then(|| lat.iter().sum::<u64>() as f64 / lat.len() as f64),
            energy_per_delivery: (tally.delivered > 0).then(|| energy / tally.delivered as f64),
        }
    }

    /// The step an unfinished run would stop at: the horizon of a lifelong run, else the step
    /// limit.
    pub(crate) fn limit(&self) -> u64 {
        self.goods.lifelong.as_ref().map_or(self.p.step_limit, |ll| ll.horizon)
    }
}
