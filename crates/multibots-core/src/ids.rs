//! Newtypes for the things the engine hands out indices for.

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        #[repr(transparent)]
        pub struct $name(pub u32);

        impl $name {
            #[inline]
            #[must_use]
            pub const fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl From<u32> for $name {
            fn from(v: u32) -> Self {
                Self(v)
            }
        }

        impl From<$name> for u32 {
            fn from(v: $name) -> u32 {
                v.0
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

id_type!(
    /// A robot, numbered 0..N in the order of the scenario's start nodes.
    RobotId
);
id_type!(
    /// A storage cell; in the paper layout `8g + 2b + a`.
    CellId
);
id_type!(
    /// A node of the highway graph; chargers are nodes too, after the highway nodes.
    NodeId
);
id_type!(
    /// One goods item of the task list (or one order, in lifelong mode).
    GoodsId
);

/// Marks "none" in the engine's `u32` columns.
pub const NONE: u32 = u32::MAX;
