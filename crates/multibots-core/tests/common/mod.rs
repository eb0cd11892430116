//! Shared by the integration tests: the paper's task lists (TABLE III).

#![allow(dead_code)]

pub const PAPER_TASKS: [[u32; 10]; 5] = [
    [11, 8, 39, 28, 53, 1, 69, 42, 79, 6],
    [74, 50, 62, 15, 49, 34, 14, 72, 31, 37],
    [68, 79, 56, 47, 48, 75, 23, 50, 76, 16],
    [59, 6, 74, 2, 67, 49, 53, 28, 25, 79],
    [14, 65, 41, 75, 22, 36, 54, 74, 9, 48],
];
