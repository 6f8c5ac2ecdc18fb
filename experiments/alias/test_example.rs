//! `test_example`: the paper's first example under the name it had before it became
//! `stretch_test` (issue 27's commands and older scripts call it so). The same program —
//! `experiments/stretch_test.rs` compiled under this name: same flags, same output.

#[path = "../stretch_test.rs"]
mod stretch_test;

fn main() -> std::process::ExitCode {
    stretch_test::main()
}
