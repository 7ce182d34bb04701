//! `starcages`: the StarCages desktop cage editor.
//!
//! The interactive editor arrives with the editor issue; until then this binary says so and
//! points to the command-line tool, which already binds coordinates.

fn main() {
    eprintln!(
        "The StarCages editor ({}) is not built yet. Use `cargo run --release -p starcages-cli -- --help` for the command-line tool.",
        env!("CARGO_PKG_NAME")
    );
    std::process::exit(1);
}
