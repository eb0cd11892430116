//! Delays (the Start-Kit's `DelayGenerator`, tag `v3.1.0`): once per tick, every delay under
//! way counts down one tick; then, among the robots not delayed (those whose delay ends now
//! included, in id order), some are picked and each gets a duration `d`: the robot is held (its
//! action forced to a wait, a move under way paused) on this tick and the `d - 1` after, and the
//! interval `[tick, tick + d]` (end exclusive) is recorded. Picking: `bernoulli`, each free robot
//! with probability `pDelay` (one draw per free robot, even when `pDelay` is 0 or 1); `poisson`,
//! a Poisson(`teamSize · pDelay`) count of them, the first of a shuffle of the free list.
//! Durations: `minDelay` when it equals `maxDelay` (no draw); `uniform` over the range;
//! `gaussian`, a normal draw of mean `min + span · gaussMeanRatio` and deviation `span ·
//! gaussStdRatio`, rounded half away from zero and clamped (no draw when the deviation is 0).
//!
//! The draws are libstdc++'s (`random.rs`), so the intervals are the Start-Kit's for the same
//! `delayConfig` and team, tick for tick (`tests/engine/lorr26_delays.rs`).

use super::random::{poisson, round_half_away, shuffle, Mt19937, Normal};
use crate::input::lorr::{DelayConfig, DurationModel, EventModel};

/// The delay generator.
pub struct Delays {
    cfg: DelayConfig,
    rng: Mt19937,
    /// Ticks of delay left per robot.
    remaining: Vec<u32>,
    free: Vec<u32>,
    tick: u32,
}

impl Delays {
    /// The generator for a team of `n` robots.
    #[must_use]
    pub fn new(cfg: &DelayConfig, n: usize) -> Delays {
        Delays { rng: Mt19937::new(cfg.seed), cfg: cfg.clone(), remaining: vec![0; n], free: Vec::with_capacity(n), tick: 0 }
    }

    /// Plays one tick: counts the delays down and draws the new ones, each appended to
    /// `started` as (robot, start tick, end tick) in the order drawn.
    pub fn tick(&mut self, started: &mut Vec<(u32, u32, u32)>) {
        self.free.clear();
        for (a, r) in self.remaining.iter_mut().enumerate() {
            *r = r.saturating_sub(1);
            if *r == 0 {
                self.free.push(a as u32);
            }
        }
        let c = self.tick;
        self.tick += 1;
        if self.free.is_empty() {
            return;
        }
        let first = started.len();
        match self.cfg.event_model {
            EventModel::Bernoulli => {
                for &a in &self.free {
                    if self.rng.canonical() < self.cfg.p_delay {
                        started.push((a, c, 0));
                    }
                }
            }
            EventModel::Poisson => {
                let k = poisson(&mut self.rng, self.remaining.len() as f64 * self.cfg.p_delay).min(self.free.len() as i64);
                if k > 0 {
                    shuffle(&mut self.rng, &mut self.free);
                    started.extend(self.free[..k as usize].iter().map(|&a| (a, c, 0)));
                }
            }
        }
        for s in &mut started[first..] {
            let d = self.duration();
            self.remaining[s.0 as usize] = d;
            s.2 = c.saturating_add(d);
        }
    }

    fn duration(&mut self) -> u32 {
        let (lo, hi) = (self.cfg.min_delay, self.cfg.max_delay);
        if lo == hi {
            return lo as u32;
        }
        let d = match self.cfg.duration_model {
            DurationModel::Uniform => self.rng.uniform(lo, hi),
            DurationModel::Gaussian => {
                let span = f64::from(hi - lo);
                let mean = f64::from(lo) + span * self.cfg.gauss_mean_ratio;
                let sd = span * self.cfg.gauss_std_ratio;
                let v = if sd <= 0.0 { mean } else { Normal::default().draw(&mut self.rng, mean, sd) };
                // `int(lround(v))`, clamped.
                let r = round_half_away(v);
                if r.is_nan() {
                    lo
                } else {
                    (r.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32).clamp(lo, hi)
                }
            }
        };
        d as u32
    }

    /// Whether robot `a` is held now (after this tick's draw).
    #[must_use]
    pub fn held(&self, a: usize) -> bool {
        self.remaining[a] > 0
    }

    /// Ticks of delay robot `a` has left.
    #[must_use]
    pub fn left(&self, a: usize) -> u32 {
        self.remaining[a]
    }
}
