//! Resource limits: every size the input controls is checked against one of these before
//! anything is allocated for it, so a hostile or mistaken scenario, layout or orders file
//! gets a one-line error naming the field, the value and the limit, never an abort or
//! runaway memory (docs/limits.md). They are build-time constants: raise one here, and
//! rebuild, if a real study needs more.

/// Largest input file the engine reads (scenario, layout, orders CSV), bytes.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Most nodes a layout may have (crossings and chargers): the next-hop table takes one byte
/// per pair of nodes, 144 MB at this size.
pub const MAX_NODES: usize = 12_000;

/// Most storage cells a layout may have.
pub const MAX_CELLS: usize = 1_000_000;

/// Largest coordinate (or extent) of a layout, px.
pub const MAX_COORD: f64 = 1e7;

/// Most robots in a fleet.
pub const MAX_ROBOTS: u32 = 1_000_000;

/// Longest run, steps (`step_limit`, `orders.horizon`): each robot's counters (waits,
/// steps in each state) are 32-bit, 4 bytes where 64-bit ones took 8.
pub const MAX_STEPS: u64 = u32::MAX as u64;
// Unlike the other limits, this one cannot be raised alone: the counters would wrap.
const _: () = assert!(MAX_STEPS <= u32::MAX as u64, "per-robot counters are u32 (metrics.rs)");

/// Longest League of Robot Runners run, steps (the problem's clock is 32-bit, as the
/// Start-Kit's).
pub const MAX_LORR_STEPS: u64 = u32::MAX as u64;

/// Most tasks a League of Robot Runners problem may reveal at once (2024: the pool of
/// `int(numTasksReveal · teamSize)`; 2023: `int(numTasksReveal)` errands ahead of each robot),
/// all allocated at the start: about 40 bytes each, 400 MB at this size.
pub const MAX_REVEALED_TASKS: u64 = 10_000_000;

/// Most cells of a League of Robot Runners map: about 60 bytes a cell once a planner has its
/// tables (a 7,000 × 7,000 map, 49 million cells, takes 3 GB).
pub const MAX_MAP_CELLS: u64 = 50_000_000;

/// Longest plan time limit of a League of Robot Runners run, ms: an hour a round.
pub const MAX_PLAN_TIME_LIMIT_MS: u64 = 3_600_000;

/// Most workers on the floor (`[humans] count`).
pub const MAX_HUMANS: u32 = 100_000;

/// Most orders a lifelong run may expect (`orders.rate × orders.horizon`). What outlives an
/// order is its latency, 8 bytes a delivery: 800 MB at the end of a run this long. Orders in
/// progress take 24 bytes each, dropped at delivery (`lifelong.rs`).
pub const MAX_ORDERS: f64 = 100_000_000.0;

/// Highest order rate, orders per step.
pub const MAX_ORDER_RATE: f64 = 100_000.0;

/// Deepest nesting of a scenario, layout or sweep spec (TOML) or of scenario JSON: tables,
/// lists and the parts of dotted keys, counted together. Checked on the text before a parser
/// recurses into it (`files::check_toml_shape`); the deepest real file nests 5 levels.
pub const MAX_NESTING: usize = 32;

/// Longest key (one part of a dotted key) in a scenario, layout or sweep spec, bytes.
pub const MAX_KEY_BYTES: usize = 1024;

/// Most throughput windows a run may fill (run length / `metrics.window`): 8 bytes each, 80 MB.
pub const MAX_WINDOWS: u64 = 10_000_000;

/// Most storage cells in one worker's pick tour (`[humans] tour`): each worker holds its
/// tour, 4 bytes a cell (100,000 workers × 100 cells: 40 MB).
pub const MAX_TOUR: u32 = 100;

/// Ranges of the `[humans]` fields in metres, seconds and m/s² (docs/limits.md): beyond them
/// the zones around robots or the walking model leave any layout's scale. `(low, high)`,
/// the low end excluded where the field must be above 0.
pub const HUMAN_SPEED: (f64, f64) = (0.0, 10.0);
pub const HUMAN_RADIUS: (f64, f64) = (0.0, 5.0);
pub const HUMAN_PX_PER_M: (f64, f64) = (0.01, 1000.0);
pub const HUMAN_STEP_SECONDS: (f64, f64) = (0.001, 10.0);
pub const HUMAN_DECEL: (f64, f64) = (0.01, 100.0);
pub const HUMAN_ZONE_M: f64 = 100.0;

/// Most cells of the collision grid: beyond it the grid's cells grow (which changes no
/// result, only how many candidates each robot looks at).
pub const MAX_GRID_CELLS: usize = 1 << 22;
