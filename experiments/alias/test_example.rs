//! `test_example`: the paper's first example under the name it had before it became
//! `stretch_test` (older commands and scripts call it so). The same study through
//! the same entry: same flags, same output.

use penalty_lab::study::{self, stretch_test::StretchTest};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<StretchTest>()
}
