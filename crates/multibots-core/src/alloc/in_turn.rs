//! `in-turn`: the paper's rule. Idle robots, in ascending id, take the goods at the front of
//! the queue ("the robots fetch in turn according to the order of the goods").

use super::{AllocView, Allocator, Assignment};
use crate::error::Result;

/// The paper's allocation rule, and the default.
#[derive(Clone, Copy, Debug, Default)]
pub struct InTurn;

impl Allocator for InTurn {
    fn name(&self) -> &'static str {
        "in-turn"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Vec<Assignment>) -> Result<()> {
        out.extend(view.idle.iter().zip(view.goods).map(|(&robot, g)| Assignment { robot, goods: g.id }));
        Ok(())
    }
}
