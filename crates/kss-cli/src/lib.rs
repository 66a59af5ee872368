//! The `kss` command line: the command-line grammar ([`cli`]) and the
//! commands themselves ([`commands`]), which read and write the files
//! (scenario files through [`kss::json`]) and the terminal.
//!
//! The binary (`src/main.rs`) only parses the arguments and calls
//! [`commands::execute`]; everything is in this library so that tests can call
//! it directly.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod commands;
