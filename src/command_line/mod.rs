//! The program's front end: what the `signorini` binary adds to the library.
//!
//! ```text
//! arguments          the command line (clap), PETSc options split from the program's own
//! summary            the terminal summary of a run (stdout, within 100 columns)
//! terminal_progress  the spinner on stderr, only when it is a terminal
//! error_control      the `adapt` and `study` subcommands
//! bench_runner       the `bench` subcommands: each case in a child process, tables and plots
//! ```
pub mod arguments;
pub mod bench_runner;
pub mod error_control;
pub mod summary;
pub mod terminal_progress;
