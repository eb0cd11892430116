//! Releasing cycles of the "blocked by" graph: the smallest id of each strongly connected
//! component of two or more robots moves (spec phase 3).

use super::blocking::Blocking;

const UNSEEN: u32 = u32::MAX;
/// The component is known (the robot left Tarjan's stack).
const DONE: u32 = u32::MAX - 1;

impl Blocking {
    /// Who waits: `waits[i]` for every blocked robot but the smallest of each strongly
    /// connected component of two or more (Tarjan's algorithm without recursion, over the
    /// blocked robots in the order listed: the components, and so the answer, do not depend
    /// on it). A robot that is not blocked has no way out, so it is never on a
    /// cycle, and edges to it are skipped.
    pub(super) fn release(&mut self, waits: &mut [bool]) {
        let start = std::mem::take(&mut self.start);
        self.release_rows(waits, |v| (start[v], start[v + 1]));
        self.start = start;
    }

    /// [`Blocking::release`] for the rows of the lists' way: robot `v`'s blockers are
    /// `to[span[v].0..span[v].1]` (`rows_of_pairs`, `blocking.rs`); the spans are cleared
    /// after.
    pub(super) fn release_spans(&mut self, waits: &mut [bool]) {
        let mut span = std::mem::take(&mut self.span);
        self.release_rows(waits, |v| span[v]);
        for &v in &self.blocked {
            span[v as usize] = (0, 0);
        }
        self.span = span;
    }

    /// The release, robot `v`'s blockers being `to[row(v).0..row(v).1]` (an empty row: not
    /// blocked).
    fn release_rows(&mut self, waits: &mut [bool], row: impl Fn(usize) -> (u32, u32)) {
        waits.fill(false);
        let Blocking { to, blocked, index, low, stack, call, released, .. } = self;
        let to = &to[..];
        released.clear();
        if blocked.is_empty() {
            return;
        }
        stack.clear();
        call.clear();
        let is_blocked = |w: usize| {
            let (a, b) = row(w);
            a != b
        };
        let mut next = 0u32;
        for &root in blocked.iter() {
            waits[root as usize] = true;
            if index[root as usize] != UNSEEN {
                continue;
            }
            index[root as usize] = next;
            low[root as usize] = next;
            next += 1;
            stack.push(root);
            call.push((root, row(root as usize).0));
            while let Some(&mut (v, ref mut e)) = call.last_mut() {
                let v = v as usize;
                if *e < row(v).1 {
                    let w = to[*e as usize] as usize;
                    *e += 1;
                    if !is_blocked(w) {
                        continue;
                    }
                    match index[w] {
                        UNSEEN => {
                            index[w] = next;
                            low[w] = next;
                            next += 1;
                            stack.push(w as u32);
                            call.push((w as u32, row(w).0));
                        }
                        DONE => {}
                        seen => low[v] = low[v].min(seen),
                    }
                    continue;
                }
                call.pop();
                if let Some(&(parent, _)) = call.last() {
                    let p = parent as usize;
                    low[p] = low[p].min(low[v]);
                }
                if low[v] == index[v] {
                    let mut smallest = u32::MAX;
                    let mut size = 0;
                    loop {
                        let w = stack.pop().expect("the component is on the stack");
                        index[w as usize] = DONE;
                        smallest = smallest.min(w);
                        size += 1;
                        if w as usize == v {
                            break;
                        }
                    }
                    if size >= 2 {
                        released.push(smallest);
                    }
                }
            }
        }
        for &r in released.iter() {
            waits[r as usize] = false;
        }
        // Back to unseen for the next step.
        for &i in blocked.iter() {
            index[i as usize] = UNSEEN;
        }
    }
}
