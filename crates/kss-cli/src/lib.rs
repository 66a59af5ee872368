//! The `kss` command line: reading and writing scenario files ([`json`]), the
//! command-line grammar ([`cli`]) and the commands themselves ([`commands`]).
//!
//! The binary (`src/main.rs`) only parses the arguments and calls
//! [`commands::execute`]; everything is in this library so that tests can call
//! it directly.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod commands;
pub mod json;
