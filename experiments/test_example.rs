//! Placeholder until the forming solver lands (issue 4).
fn main() {
    eprintln!("not implemented yet (issue 4)");
    std::process::exit(2);
}
