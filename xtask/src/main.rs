//! `cargo xtask <task>`: project automation (see the README).
use std::process::ExitCode;

const TASKS: &[(&str, &str)] = &[
    ("speedup-table", "regenerate Suffern's grid vs exhaustive speed-up table (docs/speedup-table.md)"),
    ("regress", "render every fixture scene and compare with fixtures/reference/"),
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        None | Some("help" | "-h" | "--help") => {
            println!("usage: cargo xtask <task> [options]\n\ntasks:");
            for (name, what) in TASKS {
                println!("  {name:<15} {what}");
            }
            ExitCode::SUCCESS
        }
        Some(other) => {
            eprintln!("xtask: `{other}` is not built yet or unknown; run `cargo xtask help`");
            ExitCode::FAILURE
        }
    }
}
