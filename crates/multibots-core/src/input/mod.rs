//! What a user hands the engine, read and checked: scenario files and their tables
//! (`scenario`), layout files (`layout_file`), the JSON schemas and field tables generated
//! from them (`schema`), reading files within a size limit and writing them whole
//! (`files`), one reader for CSV tables of numbers (`csv`), and the limits every input is
//! held to (`limits`, `docs/limits.md`). Nothing here simulates: a checked scenario goes on to
//! [`crate::world`] and [`crate::rules`].

pub(crate) mod csv;
pub mod files;
pub mod layout_file;
pub mod layout_params;
pub mod limits;
pub mod lorr;
pub(crate) mod messages;
pub mod scenario;
pub mod schema;
