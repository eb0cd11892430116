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
        let m = self.graph.blocked.len();
        for (v, value) in [(&mut self.graph.index, u32::MAX), (&mut self.graph.low, 0)] {
            v.clear();
            v.resize(m, value);
        }
        for v in [&mut self.graph.on_stack, &mut self.graph.released] {
            v.clear();
            v.resize(m, false);
        }
        self.graph.stack.clear();
        self.graph.call.clear();
        let mut next_index = 0u32;
        for root in 0..m {
            if self.graph.index[root] != u32::MAX {
                continue;
            }
            self.graph.call.push((root as u32, self.graph.edge_start[root]));
            self.graph.index[root] = next_index;
            self.graph.low[root] = next_index;
            next_index += 1;
            self.graph.stack.push(root as u32);
            self.graph.on_stack[root] = true;
            while let Some(&mut (v, ref mut e)) = self.graph.call.last_mut() {
                let v = v as usize;
                if *e < self.graph.edge_start[v + 1] {
                    let w = super::blocking::place(&self.graph.blocked_bits, &self.graph.rank, self.graph.edge_to[*e as usize] as usize);
                    *e += 1;
                    if w == u32::MAX {
                        continue;
                    }
                    let w = w as usize;
                    if self.graph.index[w] == u32::MAX {
                        self.graph.index[w] = next_index;
                        self.graph.low[w] = next_index;
                        next_index += 1;
                        self.graph.stack.push(w as u32);
                        self.graph.on_stack[w] = true;
                        self.graph.call.push((w as u32, self.graph.edge_start[w]));
                    } else if self.graph.on_stack[w] {
                        self.graph.low[v] = self.graph.low[v].min(self.graph.index[w]);
                    }
                    continue;
                }
                self.graph.call.pop();
                if let Some(&(parent, _)) = self.graph.call.last() {
                    let p = parent as usize;
                    self.graph.low[p] = self.graph.low[p].min(self.graph.low[v]);
                }
                if self.graph.low[v] == self.graph.index[v] {
                    // Places follow ids: the smallest place is the smallest robot.
                    let mut smallest = u32::MAX;
                    let mut size = 0;
                    loop {
                        let w = self.graph.stack.pop().expect("the component is on the stack");
                        self.graph.on_stack[w as usize] = false;
                        smallest = smallest.min(w);
                        size += 1;
                        if w as usize == v {
                            break;
                        }
                    }
                    if size >= 2 {
                        self.graph.released[smallest as usize] = true;
                    }
                }
            }
        }
    }
}
