//! The 2023 task rules (the Start-Kit's `InfAssignSystem`, archive tag `2023-archive`): robot
//! k's j-th errand is task line (j·N + k) mod M. Each robot holds `numTasksReveal` errands
//! ahead; only the first counts, and it is done when the robot stands on it after a step.
//! Errands are numbered in the order they are revealed: all robots' first ones at step 0,
//! then robot by robot after each step.

/// One errand, as the result file lists it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Errand {
    /// The errand's id, in order of reveal.
    pub id: u32,
    /// Its cell.
    pub cell: u32,
}

/// What happened to an errand of one robot: (errand id, step, finished or assigned).
pub type RobotEvent = (u32, u32, bool);

/// The round-robin errands of every robot.
pub struct RoundRobin {
    ahead: Vec<std::collections::VecDeque<Errand>>,
    counter: Vec<u64>,
    reveal: usize,
    next_id: u32,
    /// Every errand revealed, in id order.
    pub all: Vec<Errand>,
    /// Per robot, its errands' events in order.
    pub events: Vec<Vec<RobotEvent>>,
    /// Errands finished so far.
    pub finished: u64,
}

impl RoundRobin {
    /// Reveals every robot's first errands (step 0).
    #[must_use]
    pub fn new(n: usize, reveal: usize, lines: &[Vec<u32>]) -> RoundRobin {
        let mut rr = RoundRobin {
            ahead: vec![std::collections::VecDeque::default(); n],
            counter: vec![0; n],
            reveal,
            next_id: 0,
            all: Vec::new(),
            events: vec![Vec::new(); n],
            finished: 0,
        };
        rr.refill(0, lines);
        rr
    }

    /// The cell robot `k` is heading for.
    #[must_use]
    pub fn goal(&self, k: usize) -> u32 {
        self.ahead[k].front().map_or(u32::MAX, |e| e.cell)
    }

    /// After the step that led to `t`: the robots on their first errand finish it; then each
    /// robot's errands are refilled, robot by robot. How many finished.
    pub fn update(&mut self, t: u32, loc: &[u32], lines: &[Vec<u32>]) -> u64 {
        let before = self.finished;
        for (k, &p) in loc.iter().enumerate() {
            if self.ahead[k].front().is_some_and(|e| e.cell == p) {
                let e = self.ahead[k].pop_front().expect("checked");
                self.events[k].push((e.id, t, true));
                self.finished += 1;
            }
        }
        self.refill(t, lines);
        self.finished - before
    }

    fn refill(&mut self, t: u32, lines: &[Vec<u32>]) {
        let n = self.ahead.len() as u64;
        let m = lines.len() as u64;
        for k in 0..self.ahead.len() {
            while self.ahead[k].len() < self.reveal {
                let line = (self.counter[k] * n + k as u64) % m;
                let e = Errand { id: self.next_id, cell: lines[line as usize][0] };
                self.ahead[k].push_back(e);
                self.all.push(e);
                self.events[k].push((e.id, t, false));
                self.next_id += 1;
                self.counter[k] += 1;
            }
        }
    }
}
