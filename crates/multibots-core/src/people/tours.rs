//! Pick tours: each worker starts at a station (an aisle crossing), visits a few storage
//! cells (drawn with a seeded portable generator, or read from a CSV), picks at each, and
//! returns to its station to rest before the next tour.
//!
//! People walk the aisles in either direction: their graph is the highway graph with every
//! edge two-way and without the chargers' spurs. A leg is a shortest path on it, then the
//! cell's service point, then the pick point at the shelf face.

use crate::error::{Error, Result};
use crate::fleet::robot::Robots;
use crate::ids::NONE;
use crate::input::csv::Tables;
use crate::input::scenario::Humans;
use crate::world::layout::NodeKind;
use crate::world::World;
use rand::{Rng, SeedableRng};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

type Points = Vec<(f64, f64)>;

/// A cell as a picker sees it: the ends of its aisle segment, its service point on the
/// aisle's line, and the pick point at the shelf face.
#[derive(Clone, Copy, Debug)]
struct PickCell {
    a: u32,
    b: u32,
    service: (f64, f64),
    pick: (f64, f64),
}

#[derive(Clone, Debug)]
pub(crate) struct Tours {
    adj: Vec<Vec<(u32, f64)>>,
    pos: Vec<(f64, f64)>,
    cells: Vec<PickCell>,
    station: Vec<u32>,
    /// Where each person rests: beside the warehouse, an aisle's width out from its station.
    station_pt: Vec<(f64, f64)>,
    /// The current tour's cells, and the index of the cell being walked to or picked at
    /// (`len`: the station).
    tour: Vec<Vec<u32>>,
    next: Vec<usize>,
    /// The cell a person stands at (`NONE`: at its station).
    at_cell: Vec<u32>,
    waypoints: Vec<Vec<(f64, f64)>>,
    wp: Vec<usize>,
    csv: Vec<Option<Vec<u32>>>,
    rng: rand_chacha::ChaCha8Rng,
    tour_len: u32,
    pick: u32,
    rest: u32,
    pub(crate) finished: u64,
    pub(crate) picked: u64,
    dist: Vec<f64>,
    prev: Vec<u32>,
}

impl Tours {
    pub(crate) fn new(h: &Humans, world: &World, tables: &Tables, robots: &Robots, radius: f64) -> Result<Tours> {
        let layout = &world.layout;
        let pos: Vec<(f64, f64)> = layout.nodes.iter().map(|n| (n.x, n.y)).collect();
        let mut adj: Vec<Vec<(u32, f64)>> = vec![Vec::new(); pos.len()];
        for &(u, v) in &layout.edges {
            let (u, v) = (u.index(), v.index());
            let len = (pos[u].0 - pos[v].0).hypot(pos[u].1 - pos[v].1);
            for (p, q) in [(u, v), (v, u)] {
                #[allow(clippy::cast_possible_truncation)]
                if !adj[p].iter().any(|&(w, _)| w as usize == q) {
                    adj[p].push((q as u32, len));
                }
            }
        }
        let half = layout.aisle_width / 2.0;
        let cells = layout
            .cells
            .iter()
            .map(|c| {
                let (a, b) = (c.edge.0.index(), c.edge.1.index());
                let (dx, dy) = (pos[b].0 - pos[a].0, pos[b].1 - pos[a].1);
                let len = dx.hypot(dy).max(f64::MIN_POSITIVE);
                let (ux, uy) = (dx / len, dy / len);
                // From the service point towards the cell's centre, across the aisle.
                let (vx, vy) = (c.x + c.w / 2.0 - c.service.0, c.y + c.h / 2.0 - c.service.1);
                let along = vx * ux + vy * uy;
                let (px, py) = (vx - along * ux, vy - along * uy);
                let across = px.hypot(py);
                let reach = (half - radius).max(0.0);
                let pick = if across > 1e-9 { (c.service.0 + px / across * reach, c.service.1 + py / across * reach) } else { c.service };
                #[allow(clippy::cast_possible_truncation)]
                PickCell { a: a as u32, b: b as u32, service: c.service, pick }
            })
            .collect::<Vec<_>>();
        let n = h.count as usize;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(h.seed);
        // Stations: beside the warehouse, an aisle's width out from a crossing on its edge,
        // away from the chargers, so resting people stand out of the robots' way. Shuffled,
        // then dealt out in turn.
        let [x0, y0, x1, y1] = layout.bounds;
        let aisle = layout.aisle_width;
        let keep_off = aisle + robots.radius.iter().copied().fold(0.0, f64::max) + radius + 2.0 * robots.speed.iter().copied().fold(0.0, f64::max);
        let chargers: Vec<(f64, f64)> = layout.nodes.iter().filter(|n| n.kind == NodeKind::Charger).map(|n| (n.x, n.y)).collect();
        let mut candidates: Vec<(u32, (f64, f64))> = Vec::new();
        for (u, node) in layout.nodes.iter().enumerate() {
            if node.kind != NodeKind::Highway || adj[u].is_empty() {
                continue;
            }
            // A crossing in the outermost aisle: its station is half an aisle beyond the wall.
            let out = if node.x - x0 <= aisle {
                Some((x0 - aisle / 2.0, node.y))
            } else if x1 - node.x <= aisle {
                Some((x1 + aisle / 2.0, node.y))
            } else if y1 - node.y <= aisle {
                Some((node.x, y1 + aisle / 2.0))
            } else if node.y - y0 <= aisle {
                Some((node.x, y0 - aisle / 2.0))
            } else {
                None
            };
            if let Some(pt) = out {
                if chargers.iter().all(|&c| dist(c, pt) >= keep_off) && robots.x.iter().zip(&robots.y).all(|(&x, &y)| dist((x, y), pt) >= keep_off) {
                    #[allow(clippy::cast_possible_truncation)]
                    candidates.push((u as u32, pt));
                }
            }
        }
        if candidates.is_empty() {
            return Err(Error::scenario(
                "humans.count",
                h.count,
                "no crossing on the warehouse's edge is free for a station: the layout has no room for people",
            ));
        }
        for k in (1..candidates.len()).rev() {
            candidates.swap(k, rng.random_range(0..=k));
        }
        let (station, station_pt): (Vec<u32>, Vec<(f64, f64)>) = (0..n).map(|k| candidates[k % candidates.len()]).unzip();
        let mut csv = vec![None; n];
        if let Some(path) = &h.csv {
            let table = tables.read("humans.csv", std::path::Path::new(path))?;
            for row in table.rows::<u64, u64>("person,cell") {
                let (line, person, cell) = row?;
                if person >= n as u64 {
                    return Err(table.error(line, format!("person {person} out of range 0..{}", n.saturating_sub(1))));
                }
                if cell >= cells.len() as u64 {
                    return Err(table.error(line, format!("cell {cell} out of range 0..{}", cells.len().saturating_sub(1))));
                }
                #[allow(clippy::cast_possible_truncation)]
                csv[person as usize].get_or_insert_with(Vec::new).push(cell as u32);
            }
        }
        let mut t = Tours {
            adj,
            pos,
            cells,
            station,
            station_pt,
            tour: vec![Vec::new(); n],
            next: vec![0; n],
            at_cell: vec![NONE; n],
            waypoints: vec![Vec::new(); n],
            wp: vec![0; n],
            csv,
            rng,
            tour_len: h.tour,
            pick: h.pick,
            rest: h.rest,
            finished: 0,
            picked: 0,
            dist: Vec::new(),
            prev: Vec::new(),
        };
        for k in 0..n {
            t.new_tour(k);
        }
        Ok(t)
    }

    /// Where person `k` starts: its station.
    pub(crate) fn start(&self, k: usize) -> (f64, f64) {
        self.station_pt[k]
    }

    /// The point person `k` walks to, if it has one.
    pub(crate) fn waypoint(&self, k: usize) -> Option<(f64, f64)> {
        self.waypoints[k].get(self.wp[k]).copied()
    }

    /// Whether person `k` walks to one of the last two points of its leg (the cell's service
    /// and pick points, or the station): points to reach, not crossings to pass.
    pub(crate) fn last_two(&self, k: usize) -> bool {
        let to_cell = self.next[k] < self.tour[k].len();
        self.wp[k] + if to_cell { 2 } else { 1 } >= self.waypoints[k].len()
    }

    /// The points person `k` has passed on its leg, latest first.
    pub(crate) fn passed(&self, k: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.waypoints[k][..self.wp[k].min(self.waypoints[k].len())].iter().rev().copied()
    }

    /// Person `k` reached its waypoint: the next one, or, at the end of the leg, what it
    /// does there (pick, or rest at the station).
    pub(crate) fn reached(&mut self, k: usize) -> Option<super::Phase> {
        self.wp[k] += 1;
        if self.wp[k] < self.waypoints[k].len() {
            return None;
        }
        if self.next[k] < self.tour[k].len() {
            self.picked += 1;
            self.at_cell[k] = self.tour[k][self.next[k]];
            Some(super::Phase::Pick(self.pick))
        } else {
            self.finished += 1;
            self.at_cell[k] = NONE;
            Some(super::Phase::Rest(self.rest))
        }
    }

    /// Picking or resting is over: plan the next leg.
    pub(crate) fn depart(&mut self, k: usize) {
        if self.at_cell[k] == NONE {
            self.new_tour(k);
        } else {
            self.next[k] += 1;
            self.plan(k);
        }
    }

    fn new_tour(&mut self, k: usize) {
        self.tour[k] = match &self.csv[k] {
            Some(list) => list.clone(),
            #[allow(clippy::cast_possible_truncation)]
            None => (0..self.tour_len).map(|_| self.rng.random_range(0..self.cells.len()) as u32).collect(),
        };
        self.next[k] = 0;
        self.at_cell[k] = NONE;
        self.plan(k);
    }

    /// The waypoints from where person `k` stands to its next goal.
    fn plan(&mut self, k: usize) {
        // Sources: the station's node, or the two ends of the cell's aisle segment (via its
        // service point).
        let mut wps = Vec::new();
        let sources: Vec<(u32, f64)> = if self.at_cell[k] == NONE {
            vec![(self.station[k], dist(self.station_pt[k], self.pos[self.station[k] as usize]))]
        } else {
            let c = self.cells[self.at_cell[k] as usize];
            wps.push(c.service);
            vec![(c.a, dist(c.service, self.pos[c.a as usize])), (c.b, dist(c.service, self.pos[c.b as usize]))]
        };
        let (targets, tail): (Vec<(u32, f64)>, Points) = if self.next[k] < self.tour[k].len() {
            let c = self.cells[self.tour[k][self.next[k]] as usize];
            (vec![(c.a, dist(self.pos[c.a as usize], c.service)), (c.b, dist(self.pos[c.b as usize], c.service))], vec![c.service, c.pick])
        } else {
            (vec![(self.station[k], 0.0)], vec![self.station_pt[k]])
        };
        self.shortest(&sources);
        let (end, _) =
            targets.iter().map(|&(t, extra)| (t, self.dist[t as usize] + extra)).min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0))).expect("a target");
        let mut nodes = vec![end];
        while self.prev[*nodes.last().expect("a node") as usize] != NONE {
            nodes.push(self.prev[*nodes.last().expect("a node") as usize]);
        }
        nodes.reverse();
        wps.extend(nodes.iter().map(|&u| self.pos[u as usize]));
        wps.extend(tail);
        self.waypoints[k] = wps;
        self.wp[k] = 0;
    }

    /// Dijkstra from several sources with starting costs; ties go to the lower node.
    fn shortest(&mut self, sources: &[(u32, f64)]) {
        let n = self.pos.len();
        self.dist.clear();
        self.dist.resize(n, f64::INFINITY);
        self.prev.clear();
        self.prev.resize(n, NONE);
        let mut heap = BinaryHeap::new();
        for &(s, d) in sources {
            if d < self.dist[s as usize] {
                self.dist[s as usize] = d;
                // Non-negative floats order as their bits do.
                heap.push(Reverse((d.to_bits(), s)));
            }
        }
        while let Some(Reverse((d, u))) = heap.pop() {
            let d = f64::from_bits(d);
            if d > self.dist[u as usize] {
                continue;
            }
            for &(v, len) in &self.adj[u as usize] {
                let nd = d + len;
                if nd < self.dist[v as usize] {
                    self.dist[v as usize] = nd;
                    self.prev[v as usize] = u;
                    heap.push(Reverse((nd.to_bits(), v)));
                }
            }
        }
    }
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}
