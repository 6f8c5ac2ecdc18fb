//! Placeholder until issue 5's experiment lands.
fn main() {
    eprintln!("not implemented yet (issue 5)");
    std::process::exit(2);
}
