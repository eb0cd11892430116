//! What happens during a step, for replays, live viewers and the Python API.
//!
//! The engine owns the event codes and their names: replays store the codes, and the binding
//! and the viewer's server hand the names on ([`EventKind::ALL`]), so no other language
//! declares them again.

use crate::ids::NONE;

/// What happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum EventKind {
    /// A robot was given goods (phase 1); `cell` is the goods' cell.
    Assign = 1,
    /// A robot below the threshold put its goods back in the queue (phase 7).
    PutBack = 2,
    /// A robot finished loading and carries the goods.
    Pickup = 3,
    /// A robot finished unloading: one delivery.
    Deliver = 4,
    /// A robot began to wait: one collision S.
    Wait = 5,
    /// A robot reached its charger to charge: one charge C.
    Charge = 6,
    /// A robot ran out of energy.
    Strand = 7,
    /// A cell restocked (lifelong; no robot).
    Restock = 8,
    /// An order arrived for a cell (lifelong; no robot).
    Order = 9,
}

impl EventKind {
    /// Every kind, in code order.
    pub const ALL: [EventKind; 9] = [
        EventKind::Assign,
        EventKind::PutBack,
        EventKind::Pickup,
        EventKind::Deliver,
        EventKind::Wait,
        EventKind::Charge,
        EventKind::Strand,
        EventKind::Restock,
        EventKind::Order,
    ];

    /// The code replays store.
    #[must_use]
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The kind of a stored code.
    #[must_use]
    pub fn from_code(code: u32) -> Option<EventKind> {
        EventKind::ALL.iter().copied().find(|k| k.code() == code)
    }

    /// The upper-case name replays, the viewer and the Python API show.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Assign => "ASSIGN",
            EventKind::PutBack => "PUT_BACK",
            EventKind::Pickup => "PICKUP",
            EventKind::Deliver => "DELIVER",
            EventKind::Wait => "WAIT",
            EventKind::Charge => "CHARGE",
            EventKind::Strand => "STRAND",
            EventKind::Restock => "RESTOCK",
            EventKind::Order => "ORDER",
        }
    }
}

/// An event: in step `step`, `robot` (or `NONE`) did `kind`, with `cell` where it applies
/// (else `NONE`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event {
    pub step: u64,
    pub kind: EventKind,
    pub robot: u32,
    pub cell: u32,
}

impl Event {
    /// An event of no robot (restocks and orders).
    #[must_use]
    pub fn of_cell(step: u64, kind: EventKind, cell: u32) -> Event {
        Event { step, kind, robot: NONE, cell }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_are_dense() {
        for (k, kind) in EventKind::ALL.iter().enumerate() {
            assert_eq!(kind.code(), k as u32 + 1);
            assert_eq!(EventKind::from_code(kind.code()), Some(*kind));
        }
        assert_eq!(EventKind::from_code(0), None);
        assert_eq!(EventKind::from_code(10), None);
    }
}
