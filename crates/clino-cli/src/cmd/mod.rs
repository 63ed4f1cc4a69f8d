//! One module per subcommand.
pub mod allan;
pub mod demo;
pub mod redundancy;
pub mod stewart;
pub mod testbench;
pub mod calibrate;
pub mod survey;
