//! Releasing cycles of the "blocked by" graph: the smallest id of each strongly connected
//! component of two or more robots moves (spec phase 3).

use super::Collisions;

impl Collisions {
    /// Marks `released` the smallest robot of each strongly connected component of two or
    /// more robots (Tarjan's algorithm without recursion), over the robots in `blocked`, by
    /// their places there. A robot that is not blocked has no way out, so it is never on a
    /// cycle, and edges to it are skipped. Expects `blocked_bits` and `rank` to give the
    /// places of this step's blocked robots (`Collisions::rank_blocked`).
    pub(super) fn release_cycles(&mut self) {
        let m = self.blocked.len();
        for (v, value) in [(&mut self.index, u32::MAX), (&mut self.low, 0)] {
            v.clear();
            v.resize(m, value);
        }
        for v in [&mut self.on_stack, &mut self.released] {
            v.clear();
            v.resize(m, false);
        }
        self.stack.clear();
        self.call.clear();
        let mut next_index = 0u32;
        for root in 0..m {
            if self.index[root] != u32::MAX {
                continue;
            }
            self.call.push((root as u32, self.edge_start[root]));
            self.index[root] = next_index;
            self.low[root] = next_index;
            next_index += 1;
            self.stack.push(root as u32);
            self.on_stack[root] = true;
            while let Some(&mut (v, ref mut e)) = self.call.last_mut() {
                let v = v as usize;
                if *e < self.edge_start[v + 1] {
                    let w = super::place(&self.blocked_bits, &self.rank, self.edge_to[*e as usize] as usize);
                    *e += 1;
                    if w == u32::MAX {
                        continue;
                    }
                    let w = w as usize;
                    if self.index[w] == u32::MAX {
                        self.index[w] = next_index;
                        self.low[w] = next_index;
                        next_index += 1;
                        self.stack.push(w as u32);
                        self.on_stack[w] = true;
                        self.call.push((w as u32, self.edge_start[w]));
                    } else if self.on_stack[w] {
                        self.low[v] = self.low[v].min(self.index[w]);
                    }
                    continue;
                }
                self.call.pop();
                if let Some(&(parent, _)) = self.call.last() {
                    let p = parent as usize;
                    self.low[p] = self.low[p].min(self.low[v]);
                }
                if self.low[v] == self.index[v] {
                    // Places follow ids: the smallest place is the smallest robot.
                    let mut smallest = u32::MAX;
                    let mut size = 0;
                    loop {
                        let w = self.stack.pop().expect("the component is on the stack");
                        self.on_stack[w as usize] = false;
                        smallest = smallest.min(w);
                        size += 1;
                        if w as usize == v {
                            break;
                        }
                    }
                    if size >= 2 {
                        self.released[smallest as usize] = true;
                    }
                }
            }
        }
    }
}
