//! Resources and the bottleneck (docs/metrics.md): how busy each unloading zone, charger,
//! crossing and lane was, how long the queue before it grew, and which one limits the fleet.
//!
//! Each step (phase 8) a node is **busy** while a robot unloads or charges at it (unloading
//! zones, chargers), or while a robot waits to enter it (any node: a crossing serves robots
//! in a step, and a zone with a line is turning over to the next robot). Its **queue** is the robots waiting at collisions (or
//! held by a traffic policy) whose next node it is: the node they stand at or drive
//! towards. Robots queued for a shared charger (WAIT_CHARGER) form one more queue, the
//! charger pool's. A **lane** (an edge of the highway graph, one aisle between two crossings)
//! is busy while robots stand held on it, and its queue is those robots: the part of the
//! crossing's queue that stands on that lane, which says which way the queue reaches back.
//! Unloading zones nobody unloaded at count as crossings.
//!
//! The **bottleneck** is the binding constraint, named only when one is saturated: busy at
//! least half the steps, with a queue that has not drained (half a robot or more on average
//! over the later part of the run: from the run's last doubling of steps, so at least its
//! last quarter). Services (an unloading zone, a charger, the shared chargers' queue) come
//! first, the busiest; the queues at crossings upstream of a saturated service are its
//! symptoms. Without one, the saturated crossing with the longest queue. Without that,
//! nothing limits the fleet but its size and the orders, and none is named; nor when the
//! fleet stranded, out of energy (the run's own verdict says so). The remedy names only the
//! scenario keys this scenario has and has not set already ([`Setting`]).
//!
//! The queues of the last step ([`Queues`]) are what viewers draw; a replay keeps them, for
//! the resources its run reported, as the frames where they changed ([`QueueLog`]).

use crate::fleet::robot::{Robots, State};
use crate::ids::{NodeId, NONE};
use crate::input::layout_params::{ChargerWalls, LayoutParams};
use crate::world::layout::Layout;
use serde_json::{json, Value};

/// What kind of place a resource is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResourceKind {
    /// An unloading zone.
    Unloading,
    /// A charger.
    Charger,
    /// The shared chargers' queue (robots in WAIT_CHARGER), as one resource.
    ChargerQueue,
    /// Any other node of the highway graph.
    Crossing,
    /// An edge of the highway graph: the lane from one crossing to the next.
    Lane,
}

impl ResourceKind {
    /// `"unloading"`, `"charger"`, `"charger-queue"`, `"crossing"` or `"lane"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            ResourceKind::Unloading => "unloading",
            ResourceKind::Charger => "charger",
            ResourceKind::ChargerQueue => "charger-queue",
            ResourceKind::Crossing => "crossing",
            ResourceKind::Lane => "lane",
        }
    }
}

/// How one resource was used over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct ResourceUse {
    pub kind: ResourceKind,
    /// The node's name (`"chargers"` for the charger queue, `"U->V"` for the lane from node
    /// U to node V).
    pub node: String,
    /// Share of steps busy (see the module doc).
    pub busy: f64,
    /// Robots in its queue, on average over the steps, and at most.
    pub mean_queue: f64,
    pub longest_queue: u32,
}

impl ResourceUse {
    /// As JSON: `kind`, `node`, `busy`, `mean_queue`, `longest_queue` (the keys of the
    /// Python result's `resources`).
    #[must_use]
    pub fn to_json(&self) -> Value {
        json!({"kind": self.kind.as_str(), "node": self.node, "busy": self.busy, "mean_queue": self.mean_queue, "longest_queue": self.longest_queue})
    }
}

/// The resource that limits the fleet, and what would relieve it.
#[derive(Clone, Debug, PartialEq)]
pub struct Bottleneck {
    pub resource: ResourceUse,
    /// One line: the scenario keys that would relieve it.
    pub relieve: String,
}

impl Bottleneck {
    /// As JSON: the resource's keys and `relieve`.
    #[must_use]
    pub fn to_json(&self) -> Value {
        let mut v = self.resource.to_json();
        v["relieve"] = json!(self.relieve);
        v
    }
}

/// The robots queued in the last step, counted as for the report: at each node with a
/// queue, and for a shared charger.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Queues {
    /// Each node with a queue and its robots, in no particular order.
    pub nodes: Vec<(NodeId, u32)>,
    /// Robots queued for a shared charger (WAIT_CHARGER): the charger queue's.
    pub chargers: u32,
    /// Each lane with a queue, as (from, to) and the robots held on it.
    pub lanes: Vec<(NodeId, NodeId, u32)>,
}

/// The shortest mean queue, over the later part of the run, that makes a bottleneck: half a
/// robot waiting, on average, at every step. Below it robots rarely wait for anything and
/// nothing limits the fleet but its size and the orders.
const MIN_QUEUE: f64 = 0.5;

/// The busy share from which a resource with a standing queue is saturated.
const SATURATED: f64 = 0.5;

/// The first step count at which the queues' sums are kept for the later part of the run;
/// then at every doubling.
const FIRST_CHECKPOINT: u64 = 64;

/// What the scenario of a run already chose, which a bottleneck's remedy depends on: only
/// keys it has, and has not set already, are suggested.
#[derive(Clone, Debug, Default)]
#[allow(clippy::struct_excessive_bools)] // four independent choices of the scenario, each on or off
pub struct Setting {
    /// The generator's parameters, for a generated layout (None: a layout file or a named one).
    pub generated: Option<LayoutParams>,
    /// `charging.chargers = "shared"`.
    pub shared_chargers: bool,
    /// `charging.policy = "staggered"`.
    pub staggered: bool,
    /// `unload = "nearest"`.
    pub unload_nearest: bool,
    /// `traffic = "reserve"`.
    pub reserve: bool,
}

/// The queues' running sums at one step count: where the later part of the run starts.
#[derive(Clone, Debug, Default)]
struct Checkpoint {
    steps: u64,
    queued: Vec<u64>,
    pool: u64,
}

/// The running sums, per node, per lane (slots after the nodes', one per edge of the layout)
/// and for the charger queue.
#[derive(Clone, Debug, Default)]
pub(crate) struct Usage {
    nodes: usize,
    /// Per node, its outgoing lanes as (to, slot).
    lanes_from: Vec<Vec<(u32, u32)>>,
    steps: u64,
    /// Observations so far, and the one each node was last counted busy in, so a node
    /// counts once per observation.
    stamp: u64,
    busy: Vec<u64>,
    busy_at: Vec<u64>,
    /// Per node, the steps a robot unloaded or charged at it: which zones and chargers served.
    served: Vec<u64>,
    queued: Vec<u64>,
    longest: Vec<u32>,
    now: Vec<u32>,
    touched: Vec<u32>,
    pool_queued: u64,
    pool_longest: u32,
    /// Robot-steps holding a charger: charging at it, or driving to the one claimed.
    pool_held: u64,
    /// The last observation's queues (node, robots), and the charger queue's.
    last: Vec<(u32, u32)>,
    last_pool: u32,
    /// The sums at the last two doublings of the step count, and the next one's step.
    checkpoints: [Checkpoint; 2],
    next_checkpoint: u64,
}

impl Usage {
    pub fn new(layout: &Layout) -> Usage {
        let nodes = layout.nodes.len();
        let mut lanes_from = vec![Vec::new(); nodes];
        for (e, &(u, v)) in layout.edges.iter().enumerate() {
            lanes_from[u.index()].push((v.0, (nodes + e) as u32));
        }
        let slots = nodes + layout.edges.len();
        Usage {
            nodes,
            lanes_from,
            busy: vec![0; slots],
            busy_at: vec![u64::MAX; slots],
            served: vec![0; nodes],
            queued: vec![0; slots],
            longest: vec![0; slots],
            now: vec![0; slots],
            next_checkpoint: FIRST_CHECKPOINT,
            ..Usage::default()
        }
    }

    /// The slot of the lane from `u` to `v`, if the layout has one.
    fn lane(&self, u: u32, v: u32) -> Option<u32> {
        self.lanes_from.get(u as usize)?.iter().find(|&&(to, _)| to == v).map(|&(_, slot)| slot)
    }

    /// One step, `times` times over (the same state for each: runs of quiet steps), with
    /// `waits` the robots held this step; `unloading_or_charger` marks those nodes.
    pub fn observe(&mut self, r: &Robots, waits: &[bool], unloading_or_charger: &[bool], times: u64) {
        if times == 0 {
            return;
        }
        self.steps += times;
        self.stamp += 1;
        self.last.clear();
        let t = self.stamp;
        let mut pool = 0u32;
        let mut holding = 0u64;
        let n = r.len();
        // Slices of exactly `n`: no bounds check per robot.
        let (states, goal, at_node, edge_v) = (&r.state[..n], &r.goal[..n], &r.at_node[..n], &r.edge_v[..n]);
        for (i, &held) in waits[..n].iter().enumerate() {
            let state = states[i];
            pool += u32::from(state == State::WaitCharger);
            holding += u64::from(matches!(state, State::Charging | State::ToCharger));
            if matches!(state, State::Unloading | State::Charging) {
                // It stands at the end of its route: the zone or the charger.
                let k = goal[i] as usize;
                if goal[i] != NONE && unloading_or_charger[k] && self.busy_at[k] != t {
                    self.busy_at[k] = t;
                    self.busy[k] += times;
                    self.served[k] += times;
                }
            }
            // Only held robots queue at a node: most robots are not, and read nothing more.
            if held {
                let node = if at_node[i] == NONE { edge_v[i] } else { at_node[i] };
                if node == NONE {
                    continue;
                }
                let lane = if at_node[i] == NONE { self.lane(r.edge_u[i], edge_v[i]) } else { None };
                for slot in std::iter::once(node).chain(lane) {
                    let k = slot as usize;
                    if self.now[k] == 0 {
                        self.touched.push(slot);
                    }
                    self.now[k] += 1;
                }
            }
        }
        for &node in &self.touched {
            let k = node as usize;
            let q = self.now[k];
            self.queued[k] += u64::from(q) * times;
            self.longest[k] = self.longest[k].max(q);
            self.last.push((node, q));
            if self.busy_at[k] != t {
                // A crossing is busy while robots wait to enter it, a lane while robots
                // stand held on it, a zone or charger while robots wait for it too: it is
                // then taken up by turning over to the next robot in line.
                self.busy_at[k] = t;
                self.busy[k] += times;
            }
            self.now[k] = 0;
        }
        self.touched.clear();
        self.pool_queued += u64::from(pool) * times;
        self.pool_held += holding * times;
        self.pool_longest = self.pool_longest.max(pool);
        self.last_pool = pool;
        if self.steps >= self.next_checkpoint {
            let [older, newer] = &mut self.checkpoints;
            std::mem::swap(older, newer);
            newer.steps = self.steps;
            newer.queued.clone_from(&self.queued);
            newer.pool = self.pool_queued;
            self.next_checkpoint = self.steps.saturating_mul(2);
        }
    }

    /// Where the later part of the run starts: the last doubling that leaves at least a
    /// quarter of the run after it (the start, for a run too short to have one).
    fn later_part(&self) -> Option<&Checkpoint> {
        self.checkpoints.iter().rev().find(|c| c.steps > 0 && 4 * (self.steps - c.steps) >= self.steps)
    }

    /// Slot `k`'s mean queue over the later part of the run (`None`: the charger queue).
    fn late_queue(&self, k: Option<usize>) -> f64 {
        let (total, from) = match k {
            Some(k) => (self.queued.get(k).copied().unwrap_or(0), self.later_part().map_or((0, 0), |c| (c.steps, c.queued.get(k).copied().unwrap_or(0)))),
            None => (self.pool_queued, self.later_part().map_or((0, 0), |c| (c.steps, c.pool))),
        };
        let (start, before) = from;
        (total - before) as f64 / (self.steps - start).max(1) as f64
    }

    /// The queues of the last step observed.
    pub fn queues(&self, layout: &Layout) -> Queues {
        let mut queues = Queues { chargers: self.last_pool, ..Queues::default() };
        for &(slot, q) in &self.last {
            match (slot as usize).checked_sub(self.nodes) {
                None => queues.nodes.push((NodeId(slot), q)),
                Some(e) => queues.lanes.push((layout.edges[e].0, layout.edges[e].1, q)),
            }
        }
        queues
    }

    /// Every unloading zone and charger, the charger queue where robots queued, and the ten
    /// crossings and the ten lanes with the longest mean queue (of those with any); then the
    /// bottleneck (none for a fleet that `stranded`, out of energy).
    pub fn report(&self, layout: &Layout, setting: &Setting, stranded: bool) -> (Vec<ResourceUse>, Option<Bottleneck>) {
        let steps = self.steps.max(1) as f64;
        let of = |kind, k: usize| ResourceUse {
            kind,
            node: if k < self.nodes {
                layout.nodes[k].name.clone()
            } else {
                let (u, v) = layout.edges[k - self.nodes];
                lane_name(layout, u, v)
            },
            busy: self.busy.get(k).map_or(0.0, |&b| b as f64 / steps),
            mean_queue: self.queued.get(k).map_or(0.0, |&q| q as f64 / steps),
            longest_queue: self.longest.get(k).copied().unwrap_or(0),
        };
        // Unloading zones and chargers nobody used are crossings (robots only pass them).
        let used = |n: &crate::ids::NodeId| self.served.get(n.index()).is_some_and(|&b| b > 0);
        // Each resource with its slot (None: the charger queue), for its queue's later part.
        let mut out: Vec<(ResourceUse, Option<usize>)> =
            layout.unloading.iter().filter(|n| used(n)).map(|n| (of(ResourceKind::Unloading, n.index()), Some(n.index()))).collect();
        out.extend(layout.chargers.iter().map(|n| (of(ResourceKind::Charger, n.index()), Some(n.index()))));
        if self.pool_longest > 0 {
            // The pool's share: of the chargers' time, how much a robot held one (charging
            // at it, or driving to the one it claimed, which no other robot may take).
            let chargers = layout.chargers.len().max(1) as f64;
            let busy = (self.pool_held as f64 / (steps * chargers)).min(1.0);
            let pool = ResourceUse {
                kind: ResourceKind::ChargerQueue,
                node: "chargers".into(),
                busy,
                mean_queue: self.pool_queued as f64 / steps,
                longest_queue: self.pool_longest,
            };
            out.push((pool, None));
        }
        let special: std::collections::HashSet<usize> = layout.unloading.iter().filter(|n| used(n)).chain(&layout.chargers).map(|n| n.index()).collect();
        let longest_ten = |kind, slots: std::ops::Range<usize>| {
            let mut v: Vec<(ResourceUse, Option<usize>)> =
                slots.filter(|k| !special.contains(k) && self.queued[*k] > 0).map(|k| (of(kind, k), Some(k))).collect();
            v.sort_by(|a, b| b.0.mean_queue.total_cmp(&a.0.mean_queue).then_with(|| a.0.node.cmp(&b.0.node)));
            v.truncate(10);
            v
        };
        out.extend(longest_ten(ResourceKind::Crossing, 0..self.nodes));
        // A lane's queue is part of the queue of the crossing it leads to: the lanes only say
        // where that queue stands, and are never the bottleneck themselves.
        let lanes = longest_ten(ResourceKind::Lane, self.nodes..self.queued.len());
        let saturated = |(u, k): &&(ResourceUse, Option<usize>)| u.busy >= SATURATED && self.late_queue(*k) >= MIN_QUEUE;
        let busiest = |a: &&(ResourceUse, Option<usize>), b: &&(ResourceUse, Option<usize>)| {
            a.0.busy.total_cmp(&b.0.busy).then_with(|| a.0.mean_queue.total_cmp(&b.0.mean_queue)).then_with(|| b.0.node.cmp(&a.0.node))
        };
        let longest = |a: &&(ResourceUse, Option<usize>), b: &&(ResourceUse, Option<usize>)| {
            self.late_queue(a.1).total_cmp(&self.late_queue(b.1)).then_with(|| b.0.node.cmp(&a.0.node))
        };
        let service = out.iter().filter(|(u, _)| u.kind != ResourceKind::Crossing).filter(saturated).max_by(busiest);
        let bottleneck = service
            .or_else(|| out.iter().filter(|(u, _)| u.kind == ResourceKind::Crossing).filter(saturated).max_by(longest))
            .filter(|_| !stranded)
            .map(|(u, _)| Bottleneck { resource: u.clone(), relieve: relieve(u.kind, layout, setting) });
        let out = out.into_iter().chain(lanes).map(|(u, _)| u).collect();
        (out, bottleneck)
    }
}

/// Every node's queue and the charger queue, frame by frame, kept as the frames where they
/// changed: what a replay's footer holds for the resources its run reported.
#[derive(Clone, Debug, Default)]
pub struct QueueLog {
    /// The nodes' names, then the lanes', which the report's resources go by.
    names: Vec<String>,
    /// Each lane's (from, to) and its slot (after the nodes').
    lane_slot: std::collections::HashMap<(u32, u32), usize>,
    /// Each node's queue in the frame last recorded.
    now: Vec<u32>,
    /// Per node, `[frame, robots, frame, robots, ...]`: from that frame on, that queue.
    changes: Vec<Vec<u64>>,
    /// The nodes with a queue in the frame last recorded.
    queued: Vec<u32>,
    /// Per node, the last frame (+ 1) it had a queue in.
    seen: Vec<u64>,
    pool: u32,
    pool_changes: Vec<u64>,
}

impl QueueLog {
    /// A log for `layout`'s nodes; every queue is empty until recorded otherwise.
    #[must_use]
    pub fn new(layout: &Layout) -> QueueLog {
        let nodes = layout.nodes.len();
        let names = layout.nodes.iter().map(|n| n.name.clone()).chain(layout.edges.iter().map(|&(u, v)| lane_name(layout, u, v))).collect();
        let lane_slot = layout.edges.iter().enumerate().map(|(e, &(u, v))| ((u.0, v.0), nodes + e)).collect();
        let slots = nodes + layout.edges.len();
        QueueLog { names, lane_slot, now: vec![0; slots], changes: vec![Vec::new(); slots], seen: vec![0; slots], ..QueueLog::default() }
    }

    /// The queues of `frame` (recorded in order).
    pub fn record(&mut self, frame: u64, q: &Queues) {
        let mark = frame + 1;
        let lanes = q.lanes.iter().filter_map(|&(u, v, count)| Some((*self.lane_slot.get(&(u.0, v.0))?, count)));
        let queued: Vec<(usize, u32)> = q.nodes.iter().map(|&(n, count)| (n.index(), count)).chain(lanes).collect();
        for &(k, count) in &queued {
            self.seen[k] = mark;
            if self.now[k] != count {
                self.now[k] = count;
                self.changes[k].extend([frame, u64::from(count)]);
            }
        }
        // A node queued in the last frame and not in this one has emptied.
        for &k in &self.queued {
            let k = k as usize;
            if self.seen[k] != mark {
                self.now[k] = 0;
                self.changes[k].extend([frame, 0]);
            }
        }
        self.queued.clear();
        self.queued.extend(queued.iter().map(|&(k, _)| k as u32));
        if q.chargers != self.pool {
            self.pool = q.chargers;
            self.pool_changes.extend([frame, u64::from(q.chargers)]);
        }
    }

    /// For each of `resources` (a run's report), the frames where its queue changed, as
    /// `[frame, robots, ...]`.
    #[must_use]
    pub fn to_json(&self, resources: &[ResourceUse]) -> Value {
        let none: Vec<u64> = Vec::new();
        resources
            .iter()
            .map(|u| {
                let changes = if u.kind == ResourceKind::ChargerQueue {
                    &self.pool_changes
                } else {
                    self.names.iter().position(|n| *n == u.node).map_or(&none, |k| &self.changes[k])
                };
                json!(changes)
            })
            .collect()
    }
}

/// What would relieve a bottleneck of this kind, in keys the scenario has and has not set.
fn relieve(kind: ResourceKind, layout: &Layout, setting: &Setting) -> String {
    let g = setting.generated.as_ref();
    let mut advice: Vec<String> = Vec::new();
    match kind {
        ResourceKind::Unloading => {
            if !setting.unload_nearest && layout.unloading.len() > 1 {
                advice.push("unload = \"nearest\" (each cell's goods to its nearest zone)".into());
            }
            match g {
                Some(g) => {
                    let rows = unloading_rows(layout);
                    if rows < g.group_rows as usize {
                        advice.push(format!("more unloading zones: layout_generate.unloading_rows = {}", rows + 1));
                    } else {
                        advice.push("more unloading zones: a wider layout (layout_generate.group_cols)".into());
                    }
                }
                None => advice.push("more unloading zones in the layout".into()),
            }
            if !setting.unload_nearest && layout.unloading.len() <= 1 {
                advice.push("with unload = \"nearest\"".into());
            }
        }
        ResourceKind::Charger | ResourceKind::ChargerQueue => {
            if !setting.shared_chargers {
                advice.push("charging.chargers = \"shared\"".into());
            }
            match g {
                Some(g) if g.charger_walls != ChargerWalls::All => advice.push(format!(
                    "more chargers, near every part of the warehouse: layout_generate.chargers above {} with charger_walls = \"all\"",
                    layout.chargers.len()
                )),
                Some(_) => advice.push(format!("more chargers: layout_generate.chargers above {}", layout.chargers.len())),
                None => advice.push("more chargers in the layout".into()),
            }
            if setting.shared_chargers && !setting.staggered {
                advice.push("robots that charge early a few at a time (charging.policy = \"staggered\"; docs/charging.md)".into());
            }
        }
        ResourceKind::Crossing | ResourceKind::Lane => {
            // A layout whose westward traffic shares few aisles, collision waiting where
            // reservations would keep crossings clear.
            if g.is_some() && few_westward_rows(layout) {
                advice.push("layout_generate.aisles = \"alternate\"".into());
            }
            if !setting.reserve {
                advice.push("traffic = \"reserve\"".into());
            }
            if advice.is_empty() {
                return "spread the flow: more aisles (a wider or longer layout), or fewer robots on it".into();
            }
            return format!("spread the flow: {}", advice.join(", "));
        }
    }
    advice.join(", or ")
}

/// The rows of crossings that hold unloading zones.
fn unloading_rows(layout: &Layout) -> usize {
    let mut rows: Vec<u64> = layout.unloading.iter().map(|&n| layout.pos(n).1.to_bits()).collect();
    rows.sort_unstable();
    rows.dedup();
    rows.len()
}

/// The name of the lane from `u` to `v`: `"U->V"`.
#[must_use]
pub fn lane_name(layout: &Layout, u: NodeId, v: NodeId) -> String {
    format!("{}->{}", layout.nodes[u.index()].name, layout.nodes[v.index()].name)
}

/// Whether the layout's horizontal aisles run west on fewer rows than half of those running
/// east (the paper's directions: one westward row for all the westward traffic).
fn few_westward_rows(layout: &Layout) -> bool {
    let mut east: Vec<u64> = Vec::new();
    let mut west: Vec<u64> = Vec::new();
    for &(u, v) in &layout.edges {
        let ((ux, uy), (vx, vy)) = (layout.pos(u), layout.pos(v));
        if uy == vy {
            let rows = if vx > ux { &mut east } else { &mut west };
            rows.push(uy.to_bits());
        }
    }
    for rows in [&mut east, &mut west] {
        rows.sort_unstable();
        rows.dedup();
    }
    2 * west.len() < east.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::layout_params::{Aisles, LayoutParams};

    #[test]
    fn a_queue_log_keeps_the_frames_where_each_queue_changed() {
        let layout = Layout::generate(&LayoutParams { group_rows: 2, group_cols: 2, chargers: 3, ..LayoutParams::paper() }, "g").unwrap();
        let (a, b) = (NodeId(1), NodeId(2));
        let (u, v) = layout.edges[0];
        let mut log = QueueLog::new(&layout);
        let frames = [
            Queues::default(),
            Queues { nodes: vec![(a, 2)], chargers: 0, lanes: vec![(u, v, 1)] },
            Queues { nodes: vec![(a, 2), (b, 1)], chargers: 3, lanes: vec![(u, v, 1)] },
            Queues { nodes: vec![(b, 4)], chargers: 3, lanes: vec![(u, v, 2)] },
            Queues::default(),
        ];
        for (f, q) in frames.iter().enumerate() {
            log.record(f as u64, q);
        }
        let use_of = |kind, node: &str| ResourceUse { kind, node: node.into(), busy: 0.0, mean_queue: 0.0, longest_queue: 0 };
        let resources = [
            use_of(ResourceKind::Crossing, &layout.nodes[1].name),
            use_of(ResourceKind::Crossing, &layout.nodes[2].name),
            use_of(ResourceKind::ChargerQueue, "chargers"),
            use_of(ResourceKind::Crossing, &layout.nodes[3].name),
            use_of(ResourceKind::Lane, &lane_name(&layout, u, v)),
        ];
        assert_eq!(log.to_json(&resources), json!([[1, 2, 3, 0], [2, 1, 3, 4, 4, 0], [2, 3, 4, 0], [], [1, 1, 3, 2, 4, 0]]));
    }

    #[test]
    fn crossing_advice_names_only_what_the_run_does_not_do() {
        let layout = |aisles| Layout::generate(&LayoutParams { group_rows: 6, group_cols: 4, chargers: 5, aisles, ..LayoutParams::paper() }, "g").unwrap();
        let (paper, alternate) = (layout(Aisles::Paper), layout(Aisles::Alternate));
        assert!(few_westward_rows(&paper) && !few_westward_rows(&alternate));
        let advice = |l: &Layout, reserve| {
            let setting = Setting { generated: Some(LayoutParams::paper()), shared_chargers: true, unload_nearest: true, reserve, ..Setting::default() };
            relieve(ResourceKind::Crossing, l, &setting)
        };
        assert_eq!(advice(&paper, false), "spread the flow: layout_generate.aisles = \"alternate\", traffic = \"reserve\"");
        assert_eq!(advice(&paper, true), "spread the flow: layout_generate.aisles = \"alternate\"");
        assert_eq!(advice(&alternate, false), "spread the flow: traffic = \"reserve\"");
        assert!(!advice(&alternate, true).contains("alternate") && !advice(&alternate, true).contains("reserve"));
    }

    #[test]
    fn a_remedy_names_only_keys_the_scenario_has_and_has_not_set() {
        let params = LayoutParams { group_rows: 6, group_cols: 4, chargers: 5, ..LayoutParams::paper() };
        let layout = Layout::generate(&params, "g").unwrap();
        let generated = Setting { generated: Some(params.clone()), shared_chargers: true, ..Setting::default() };
        let chargers = relieve(ResourceKind::ChargerQueue, &layout, &generated);
        assert!(chargers.contains("layout_generate.chargers above 5") && chargers.contains("charger_walls = \"all\""), "{chargers}");
        assert!(chargers.contains("staggered"), "{chargers}");
        // Already staggered, chargers already on every wall: neither is suggested again.
        let walls = LayoutParams { charger_walls: ChargerWalls::All, ..params.clone() };
        let set = Setting { generated: Some(walls), staggered: true, ..generated.clone() };
        let chargers = relieve(ResourceKind::ChargerQueue, &layout, &set);
        assert!(!chargers.contains("staggered") && !chargers.contains("charger_walls"), "{chargers}");
        // A layout file is not told about the generator's keys.
        let file = Setting { generated: None, ..generated.clone() };
        for kind in [ResourceKind::Unloading, ResourceKind::ChargerQueue, ResourceKind::Crossing] {
            let advice = relieve(kind, &layout, &file);
            assert!(!advice.contains("layout_generate"), "{kind:?}: {advice}");
        }
        // One unloading row of six: one more is the remedy, with "nearest" when not set.
        let zones = relieve(ResourceKind::Unloading, &layout, &generated);
        assert!(zones.contains("layout_generate.unloading_rows = 2") && zones.contains("unload = \"nearest\""), "{zones}");
        let nearest = Setting { unload_nearest: true, ..generated };
        assert!(!relieve(ResourceKind::Unloading, &layout, &nearest).contains("nearest"));
    }
}
