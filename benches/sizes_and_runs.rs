//! The command line the size-curve benchmarks share (`ncsheet-bench-scaling`,
//! `ncsheet-bench-vba`): `--sizes LIST` of case names, `--runs N`, and the exit with the
//! bench's name on an error. Each includes it with `#[path]`, being a binary of its own.

use std::process::ExitCode;

pub struct Args {
    pub sizes: Vec<String>,
    pub runs: usize,
}

/// The arguments, `defaults` when `--sizes` is not given, three runs unless `--runs` says.
pub fn parse_args(defaults: &[&str]) -> Result<Args, String> {
    let mut args = Args { sizes: defaults.iter().map(|s| s.to_string()).collect(), runs: 3 };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sizes" => {
                let list = it.next().ok_or("--sizes needs a list")?;
                args.sizes = list.split(',').map(str::to_string).collect();
            }
            "--runs" => {
                args.runs = it.next().and_then(|v| v.parse().ok()).filter(|&r| r >= 1).ok_or("--runs needs N >= 1")?;
            }
            _ => return Err(format!("unknown argument {a:?} (--sizes LIST, --runs N)")),
        }
    }
    Ok(args)
}

/// The process's exit: success, or the error after the bench's name.
pub fn exit(bench: &str, result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{bench}: {e}");
            ExitCode::FAILURE
        }
    }
}
