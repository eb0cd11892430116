//! A neighbour list kept from step to step (a Verlet list): for each robot, the robots that
//! stood within `radius` of it when the list was built. A robot moves a few px per step, so
//! the list stays valid for several steps: a pair that is within `cover` of each other now
//! was within `cover + 2m` when the list was built, `m` being the farthest any robot has
//! moved since. Each step costs one pass over the positions to find `m`; the grid is only
//! rebuilt when `cover` would fall below what the step needs.

use super::grid::Bins;

/// How much wider than needed a list is built: the list then serves until some robot has
/// moved `SKIN / 2` of the need. Measured at 1,000 robots (large): see `docs/benchmarks.md`.
const SKIN: f64 = 1.0;

/// Relative slack far above the rounding of a distance (a few units in the last place).
const SLACK: f64 = 1e-9;

#[derive(Clone, Debug, Default)]
pub(super) struct Neighbours {
    /// Positions when the list was built.
    bx: Vec<f64>,
    by: Vec<f64>,
    /// Every pair closer than this when the list was built is listed.
    radius: f64,
    /// Every pair closer than this at the positions of the last [`Neighbours::refresh`] is
    /// listed.
    pub(super) cover: f64,
    /// The neighbours of robot `i` are `list[start[i]..start[i + 1]]`, itself excluded.
    pub(super) start: Vec<u32>,
    pub(super) list: Vec<u32>,
    bins: Bins,
}

impl Neighbours {
    /// Makes sure that every pair closer than `need` at positions `x`, `y` is listed:
    /// keeps the list if the robots moved little since it was built, else builds it anew.
    pub(super) fn refresh(&mut self, x: &[f64], y: &[f64], need: f64) {
        let n = x.len();
        if self.bx.len() == n && self.start.len() == n + 1 {
            let (y, bx, by) = (&y[..n], &self.bx[..n], &self.by[..n]);
            let mut m2 = 0.0f64;
            let mut nan = false;
            for i in 0..n {
                let (dx, dy) = (x[i] - bx[i], y[i] - by[i]);
                let d2 = dx * dx + dy * dy;
                m2 = m2.max(d2);
                nan |= d2.is_nan();
            }
            let cover = self.radius * (1.0 - SLACK) - 2.0 * m2.sqrt() * (1.0 + SLACK);
            if !nan && cover >= need {
                self.cover = cover;
                return;
            }
        }
        self.build(x, y, need * (1.0 + SKIN));
    }

    /// Lists, for every robot, the robots within `radius` of it at positions `x`, `y`.
    pub(super) fn build(&mut self, x: &[f64], y: &[f64], radius: f64) {
        let n = x.len();
        let y = &y[..n];
        self.bx.clear();
        self.bx.extend_from_slice(x);
        self.by.clear();
        self.by.extend_from_slice(y);
        self.radius = radius;
        self.cover = radius * (1.0 - SLACK);
        let r2 = radius * radius;
        self.bins.sort(x, y, radius);
        let bins = &self.bins;
        let (order, sx, sy) = (&bins.order[..], &bins.sx[..], &bins.sy[..]);
        self.start.clear();
        self.list.clear();
        for i in 0..n {
            self.start.push(self.list.len() as u32);
            let c = bins.cell[i];
            if c == u32::MAX {
                continue;
            }
            let (xi, yi) = (x[i], y[i]);
            for (k0, k1) in bins.around(c) {
                for k in k0..k1 {
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    if dx * dx + dy * dy <= r2 && order[k] as usize != i {
                        self.list.push(order[k]);
                    }
                }
            }
        }
        self.start.push(self.list.len() as u32);
    }
}
