//! The model's numbers a step reads (speed, energy, dwell, collision), taken once from a
//! validated scenario, and the per-robot tests on them that decide whether phase 7 has work
//! for a robot: shared by the step and by cruising (`cruise.rs`).

use crate::fleet::energy;
use crate::fleet::robot::State;
use crate::input::scenario::{ChargingPolicy, Scenario};

/// The model's numbers, taken from a validated scenario.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    pub speed: f64,
    pub energy_full: f64,
    pub threshold: f64,
    pub consumption: f64,
    /// What a robot standing in a charger queue draws per step.
    pub idle_consumption: f64,
    pub charge_rate: f64,
    pub loading: u32,
    pub unloading: u32,
    pub margin: f64,
    /// The collision angle, radians.
    pub angle: f64,
    pub step_limit: u64,
    /// Opportunistic charging: idle robots below this level go to charge.
    pub opportunistic: Option<f64>,
    /// Staggered charging: the highest of the robots' own levels (`charging::own_level`).
    pub staggered: Option<f64>,
}

impl Params {
    /// Whether phase 7 has anything to do for a robot in `state`, after this step's phases
    /// 2 to 6. Most robots have nothing due: under way, dwelling or charging, with energy to
    /// spare. Only the others take the full rules.
    #[inline]
    pub(crate) fn due(&self, state: State, routing: bool, dwell: u32, e: f64) -> bool {
        self.task_done(state, routing, dwell, e) || energy::below(e, self.threshold) || self.energy_acts(state, e)
    }

    /// A trip, a dwell or a charge that ended: the task cycle's transition is due.
    #[inline]
    fn task_done(&self, state: State, routing: bool, dwell: u32, e: f64) -> bool {
        match state {
            State::ToPickup | State::ToDrop | State::ToCharger | State::ToHome => !routing,
            State::Loading => dwell >= self.loading,
            State::Unloading => dwell >= self.unloading,
            State::Charging => energy::is_full(e, self.energy_full),
            _ => false,
        }
    }

    /// Stranding, or opportunistic charging, for a robot with energy `e`; with staggered
    /// charging, an idle robot below the highest level (whether it goes depends on its own
    /// level and on a free charger: phase 7 decides).
    #[inline]
    fn energy_acts(&self, state: State, e: f64) -> bool {
        energy::exhausted(e) || self.opportunistic.or(self.staggered).is_some_and(|level| state == State::Idle && energy::below(e, level))
    }

    /// Whether phase 7 would change anything for a robot (`marked` by the threshold rule):
    /// [`Params::due`] less robots below the threshold that the threshold rule has nothing
    /// left to do for (`Cycle::energy_rules`, `charging.rs`): marked already, or going to
    /// charge, charging, waiting for a charger, parked or going home. A robot fetching goods
    /// below it counts as acting (whether it puts them back depends on where it is). A
    /// charging robot below the threshold is due every step until it is full: without this,
    /// no run of steps could cruise through a charge.
    #[inline]
    pub(crate) fn acts(&self, state: State, routing: bool, dwell: u32, e: f64, marked: bool) -> bool {
        let threshold = energy::below(e, self.threshold)
            && match state {
                State::Idle | State::ToPickup => true,
                State::Loading | State::ToDrop | State::Unloading => !marked,
                _ => false,
            };
        // A stranded robot stays stranded.
        self.task_done(state, routing, dwell, e) || threshold || (state != State::Stranded && self.energy_acts(state, e))
    }

    /// Phases 5 and 6 for one robot in `state`: its dwell counter, charging, and consumption
    /// (counted in `energy_used`).
    #[inline]
    /// `standing`: the robot had no route under way this step.
    pub(crate) fn dwell_and_energy(&self, state: State, standing: bool, dwell: &mut u32, energy: &mut f64, energy_used: &mut f64) {
        match state {
            State::Loading | State::Unloading => *dwell += 1,
            State::Charging => *energy = energy::charge(*energy, self.charge_rate, self.energy_full),
            _ => {}
        }
        if !matches!(state, State::Charging | State::Parked | State::Stranded) {
            let rate = if state == State::WaitCharger && standing { self.idle_consumption } else { self.consumption };
            let e = energy::consume(*energy, rate);
            *energy_used += *energy - e;
            *energy = e;
        }
    }

    pub(crate) fn of(scenario: &Scenario) -> Params {
        let r = &scenario.robot;
        Params {
            speed: r.speed,
            energy_full: r.energy_full,
            threshold: r.threshold,
            consumption: r.consumption,
            idle_consumption: r.idle_consumption.unwrap_or(r.consumption / 10.0),
            charge_rate: r.charge_rate,
            loading: scenario.dwell.loading,
            unloading: scenario.dwell.unloading,
            margin: scenario.collision.margin,
            angle: scenario.collision.angle.to_radians(),
            step_limit: scenario.step_limit,
            opportunistic: (scenario.charging.policy == ChargingPolicy::Opportunistic).then_some(scenario.charging.level),
            staggered: (scenario.charging.policy == ChargingPolicy::Staggered).then_some(scenario.charging.level),
        }
    }
}

/// Steps without a pickup or a delivery that make a livelock: two full battery cycles (a
/// full charge used up, and a full charge), with gridlock detection; 0 without it.
pub(crate) fn livelock_after(scenario: &Scenario) -> u64 {
    let r = &scenario.robot;
    if scenario.metrics.gridlock == 0 {
        return 0;
    }
    (2.0 * (r.energy_full / r.consumption + r.energy_full / r.charge_rate)).ceil().min(1e15) as u64
}
