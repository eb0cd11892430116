//! The robots: their columns (struct of arrays, `robot`), how they follow routes on the
//! highway graph (`route`), how a move is made (`motion`: [`motion::Motion`], the view of the
//! columns a move writes), the bays where they stand aside (`bay`), their batteries
//! (`energy`), and where they start, park and unload (`placement`). The rules of a step decide what
//! robots do; this layer says what a robot is and how it travels.

pub(crate) mod bay;
pub(crate) mod energy;
pub(crate) mod motion;
pub(crate) mod placement;
pub mod robot;
pub mod route;
