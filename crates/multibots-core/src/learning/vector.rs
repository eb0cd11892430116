//! Many dispatchers stepped in one call, on threads: the vector environment's engine.
//!
//! Each call takes one action per environment, steps every environment to the next robot
//! that decides (running the engine between decision points) and writes every observation,
//! reward and ending into the caller's arrays, which the binding fills without the GIL. An
//! environment whose episode ended starts its next one at the following call, which ignores
//! its action and pays no reward (Gymnasium's "next step" autoreset): every environment
//! follows the trajectory a single dispatcher would.
//!
//! All actions are checked before any environment moves, so a refused action changes
//! nothing. Environments are split into one contiguous chunk per worker thread (scoped
//! threads, as in [`crate::rules::batch`]); with one worker everything runs on the calling thread.

use super::dispatcher::Dispatcher;
use super::observation::{ObsMut, FLEET_FEATURES, GOODS_FEATURES, ROBOT_FEATURES};
use super::Settings;
use crate::error::{Error, Result};
use crate::input::scenario::Scenario;
use crate::world::World;

/// Where one call's results go: one row per environment in every array.
pub struct Batch<'a> {
    /// `ROBOT_FEATURES` per environment.
    pub robot: &'a mut [f32],
    /// `robots × FLEET_FEATURES` per environment.
    pub fleet: &'a mut [f32],
    /// `max_queue × GOODS_FEATURES` per environment.
    pub queue: &'a mut [f32],
    /// `max_queue + 2` per environment.
    pub mask: &'a mut [u8],
    pub reward: &'a mut [f64],
    pub terminated: &'a mut [bool],
    pub truncated: &'a mut [bool],
    /// The action was masked out and taken as "wait".
    pub invalid: &'a mut [bool],
    /// The robot deciding now, or -1 at the end of an episode.
    pub robot_id: &'a mut [i64],
    /// The run's step.
    pub t: &'a mut [u64],
}

impl<'a> Batch<'a> {
    /// The rows of the first `len` environments, and the rest.
    fn split(self, len: usize, sizes: Sizes) -> (Batch<'a>, Batch<'a>) {
        fn cut<T>(s: &mut [T], at: usize) -> (&mut [T], &mut [T]) {
            s.split_at_mut(at)
        }
        let (robot, robot2) = cut(self.robot, len * sizes.robot);
        let (fleet, fleet2) = cut(self.fleet, len * sizes.fleet);
        let (queue, queue2) = cut(self.queue, len * sizes.queue);
        let (mask, mask2) = cut(self.mask, len * sizes.mask);
        let (reward, reward2) = cut(self.reward, len);
        let (terminated, terminated2) = cut(self.terminated, len);
        let (truncated, truncated2) = cut(self.truncated, len);
        let (invalid, invalid2) = cut(self.invalid, len);
        let (robot_id, robot_id2) = cut(self.robot_id, len);
        let (t, t2) = cut(self.t, len);
        (
            Batch { robot, fleet, queue, mask, reward, terminated, truncated, invalid, robot_id, t },
            Batch {
                robot: robot2,
                fleet: fleet2,
                queue: queue2,
                mask: mask2,
                reward: reward2,
                terminated: terminated2,
                truncated: truncated2,
                invalid: invalid2,
                robot_id: robot_id2,
                t: t2,
            },
        )
    }
}

/// Row sizes of the observation arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sizes {
    pub robot: usize,
    pub fleet: usize,
    pub queue: usize,
    pub mask: usize,
}

/// Many dispatchers.
pub struct VectorDispatch {
    envs: Vec<Dispatcher>,
    /// Ended at the last call: restarts at the next.
    restart: Vec<bool>,
    /// The scenario an environment's next episode runs (else its current one).
    next: Vec<Option<Scenario>>,
    workers: usize,
}

impl VectorDispatch {
    /// One dispatcher per scenario (every one with as many robots), on `workers` threads
    /// (0: one per core).
    pub fn new(scenarios: &[Scenario], settings: &Settings, workers: usize) -> Result<VectorDispatch> {
        let Some(first) = scenarios.first() else { return Err(Error::scenario("num_envs", 0, "must be 1 or more")) };
        let world = World::of(first)?;
        let mut envs = Vec::with_capacity(scenarios.len());
        for (k, s) in scenarios.iter().enumerate() {
            if s.robots != first.robots {
                return Err(Error::scenario(
                    format!("scenarios[{k}].robots"),
                    s.robots,
                    format!("every environment needs as many robots as the first ({})", first.robots),
                ));
            }
            let w = super::dispatcher::world_for(&world, first, s)?;
            envs.push(Dispatcher::with_world(w, s, settings.clone())?);
        }
        let n = envs.len();
        Ok(VectorDispatch { envs, restart: vec![false; n], next: vec![None; n], workers })
    }

    /// Environments.
    #[must_use]
    pub fn len(&self) -> usize {
        self.envs.len()
    }

    /// Whether there are none (never: `new` needs one).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.envs.is_empty()
    }

    /// Row sizes of the observation arrays.
    #[must_use]
    pub fn sizes(&self) -> Sizes {
        let q = self.envs[0].settings().max_queue;
        Sizes { robot: ROBOT_FEATURES, fleet: self.envs[0].robots() * FLEET_FEATURES, queue: q * GOODS_FEATURES, mask: q + 2 }
    }

    /// Environment `k`.
    #[must_use]
    pub fn env(&self, k: usize) -> &Dispatcher {
        &self.envs[k]
    }

    /// The scenario environment `k`'s next episode runs (checked when it starts).
    pub fn set_next(&mut self, k: usize, scenario: Scenario) {
        self.next[k] = Some(scenario);
    }

    /// Starts a new episode in every environment (with the scenarios set for them, if any)
    /// and writes the first observations; rewards and endings are zero.
    pub fn reset(&mut self, out: Batch<'_>) -> Result<()> {
        self.restart.fill(true);
        self.run(None, out)
    }

    /// Takes one action per environment (ignored for an environment that restarts).
    ///
    /// # Errors
    /// [`Error::Decision`] naming the environment for an action it refuses; no environment
    /// moves then.
    pub fn step(&mut self, actions: &[i64], out: Batch<'_>) -> Result<()> {
        if actions.len() != self.envs.len() {
            return Err(Error::Decision { step: 0, reason: format!("actions: {} given, one per environment ({}) expected", actions.len(), self.envs.len()) });
        }
        for (k, env) in self.envs.iter().enumerate() {
            if !self.restart[k] {
                env.check(actions[k]).map_err(|e| in_env(k, e))?;
            }
        }
        self.run(Some(actions), out)
    }

    fn run(&mut self, actions: Option<&[i64]>, out: Batch<'_>) -> Result<()> {
        let n = self.envs.len();
        let sizes = self.sizes();
        let workers = crate::rules::batch::worker_count(self.workers, n);
        let per = n.div_ceil(workers);
        let mut results: Vec<Result<()>> = Vec::with_capacity(workers);
        std::thread::scope(|scope| {
            let mut handles = Vec::with_capacity(workers);
            let mut rest = out;
            let mut envs: &mut [Dispatcher] = &mut self.envs;
            let mut restart: &mut [bool] = &mut self.restart;
            let mut next: &mut [Option<Scenario>] = &mut self.next;
            let mut first = 0;
            while !envs.is_empty() {
                let len = per.min(envs.len());
                let (chunk, tail) = std::mem::take(&mut envs).split_at_mut(len);
                envs = tail;
                let (r, rt) = std::mem::take(&mut restart).split_at_mut(len);
                restart = rt;
                let (nx, nt) = std::mem::take(&mut next).split_at_mut(len);
                next = nt;
                let (rows, tail_rows) = rest.split(len, sizes);
                rest = tail_rows;
                let acts = actions.map(|a| &a[first..first + len]);
                let base = first;
                first += len;
                if envs.is_empty() {
                    // The last chunk runs on the calling thread.
                    results.push(step_chunk(chunk, r, nx, acts, rows, sizes, base));
                } else {
                    handles.push(scope.spawn(move || step_chunk(chunk, r, nx, acts, rows, sizes, base)));
                }
            }
            for h in handles {
                results.push(h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
            }
        });
        results.into_iter().collect()
    }
}

fn in_env(k: usize, e: Error) -> Error {
    match e {
        Error::Decision { step, reason } => Error::Decision { step, reason: format!("env {k}: {reason}") },
        other => other,
    }
}

/// Steps environments `base..base + envs.len()`, writing their rows.
fn step_chunk(
    envs: &mut [Dispatcher],
    restart: &mut [bool],
    next: &mut [Option<Scenario>],
    actions: Option<&[i64]>,
    out: Batch<'_>,
    sizes: Sizes,
    base: usize,
) -> Result<()> {
    let Batch { robot, fleet, queue, mask, reward, terminated, truncated, invalid, robot_id, t } = out;
    for (j, env) in envs.iter_mut().enumerate() {
        if restart[j] {
            env.reset(next[j].take().as_ref()).map_err(|e| in_env(base + j, e))?;
            reward[j] = 0.0;
            terminated[j] = false;
            truncated[j] = false;
            invalid[j] = false;
        } else {
            let code = actions.map_or(0, |a| a[j]);
            let tr = env.step(code).map_err(|e| in_env(base + j, e))?;
            reward[j] = tr.reward;
            terminated[j] = tr.terminated;
            truncated[j] = tr.truncated;
            invalid[j] = tr.invalid;
        }
        restart[j] = env.ended();
        robot_id[j] = env.robot().map_or(-1, |r| i64::from(r.0));
        t[j] = env.progress().t;
        env.observe(ObsMut {
            robot: &mut robot[j * sizes.robot..(j + 1) * sizes.robot],
            fleet: &mut fleet[j * sizes.fleet..(j + 1) * sizes.fleet],
            queue: &mut queue[j * sizes.queue..(j + 1) * sizes.queue],
            mask: &mut mask[j * sizes.mask..(j + 1) * sizes.mask],
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::PAPER_TASKS;
    use crate::learning::observation::Observation;

    struct Buffers {
        robot: Vec<f32>,
        fleet: Vec<f32>,
        queue: Vec<f32>,
        mask: Vec<u8>,
        reward: Vec<f64>,
        terminated: Vec<bool>,
        truncated: Vec<bool>,
        invalid: Vec<bool>,
        robot_id: Vec<i64>,
        t: Vec<u64>,
    }

    impl Buffers {
        fn new(m: usize, s: Sizes) -> Buffers {
            Buffers {
                robot: vec![0.0; m * s.robot],
                fleet: vec![0.0; m * s.fleet],
                queue: vec![0.0; m * s.queue],
                mask: vec![0; m * s.mask],
                reward: vec![0.0; m],
                terminated: vec![false; m],
                truncated: vec![false; m],
                invalid: vec![false; m],
                robot_id: vec![0; m],
                t: vec![0; m],
            }
        }
        fn batch(&mut self) -> Batch<'_> {
            Batch {
                robot: &mut self.robot,
                fleet: &mut self.fleet,
                queue: &mut self.queue,
                mask: &mut self.mask,
                reward: &mut self.reward,
                terminated: &mut self.terminated,
                truncated: &mut self.truncated,
                invalid: &mut self.invalid,
                robot_id: &mut self.robot_id,
                t: &mut self.t,
            }
        }
    }

    /// The first allowed action after `k` allowed ones, cycling.
    fn pick(mask: &[u8], k: usize) -> i64 {
        let allowed: Vec<usize> = (0..mask.len()).filter(|&a| mask[a] == 1).collect();
        allowed[k % allowed.len()] as i64
    }

    #[test]
    fn a_vector_follows_the_single_dispatchers_trajectories_on_any_thread_count() {
        const CALLS: usize = 80;
        let scenarios: Vec<Scenario> = PAPER_TASKS.iter().map(|g| Scenario::paper(3, g)).collect();
        let settings = Settings::of(&scenarios[0]);
        // Single dispatchers, driven by the same choice rule, record their trajectories: a
        // digest of each observation, and each reward.
        let digest = |o: &Observation| o.robot.iter().chain(&o.queue).chain(&o.fleet).map(|&x| f64::from(x)).sum::<f64>();
        let mut want = Vec::new();
        for s in &scenarios {
            let mut d = Dispatcher::new(s, settings.clone()).unwrap();
            let mut obs = Observation::zeros(3, 10);
            d.observe(obs.as_mut());
            let mut traj = Vec::new();
            for k in 0..CALLS {
                let reward = if d.ended() {
                    d.reset(None).unwrap();
                    0.0
                } else {
                    d.step(pick(&obs.mask, k)).unwrap().reward
                };
                d.observe(obs.as_mut());
                traj.push((digest(&obs), reward));
            }
            want.push(traj);
        }
        for workers in [1, 2, 4] {
            let mut v = VectorDispatch::new(&scenarios, &settings, workers).unwrap();
            let sizes = v.sizes();
            let mut b = Buffers::new(5, sizes);
            v.reset(b.batch()).unwrap();
            for k in 0..CALLS {
                let acts: Vec<i64> = (0..5).map(|e| pick(&b.mask[e * sizes.mask..(e + 1) * sizes.mask], k)).collect();
                v.step(&acts, b.batch()).unwrap();
                for (e, traj) in want.iter().enumerate() {
                    let (r, f, q) = (sizes.robot, sizes.fleet, sizes.queue);
                    let o = Observation {
                        robot: b.robot[e * r..(e + 1) * r].to_vec(),
                        fleet: b.fleet[e * f..(e + 1) * f].to_vec(),
                        queue: b.queue[e * q..(e + 1) * q].to_vec(),
                        mask: Vec::new(),
                    };
                    assert_eq!((digest(&o), b.reward[e]), traj[k], "workers {workers} env {e} call {k}");
                }
            }
        }
    }

    #[test]
    fn a_refused_action_names_its_environment_and_moves_none() {
        let scenarios: Vec<Scenario> = (0..3).map(|_| Scenario::paper(2, &PAPER_TASKS[0])).collect();
        let mut v = VectorDispatch::new(&scenarios, &Settings::of(&scenarios[0]), 1).unwrap();
        let mut b = Buffers::new(3, v.sizes());
        v.reset(b.batch()).unwrap();
        let e = v.step(&[0, 10, 0], b.batch()).unwrap_err().to_string();
        assert_eq!(e, "decision at step 1: env 1: action = 10 (charge now): not allowed for robot 0: robot 0 is full (energy 10)");
        assert!((0..3).all(|k| v.env(k).robot() == Some(crate::ids::RobotId(0))));
    }
}
