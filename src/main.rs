//! The `ncsheet` binary: parses the command line and renders a failure once, ripgrep style
//! (`ncsheet: parts.csv: Sheet1!B3: …`). Exit codes: 0 success, 1 bad input (a file, a cell,
//! a formula), 2 bad usage (clap's code for its own errors too).

use std::io::Write as _;
use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    let args = match cli::Cli::try_parse_grouped() {
        Ok(args) => args,
        Err(e) => {
            // `--tol 0,01` typed in a decimal-comma locale: say what the option wants.
            let hint = std::env::args().find_map(|a| cli::locale::number_option_hint(&a));
            let code = e.exit_code();
            let _ = e.print();
            if let (Some(hint), clap::error::ErrorKind::ValueValidation) = (hint, e.kind()) {
                eprintln!("hint: {hint}");
            }
            return ExitCode::from(code as u8);
        }
    };
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        // `ncsheet eval big.csv | head`: the reader has all it wanted.
        Err(e) if e.is_broken_pipe() => ExitCode::SUCCESS,
        Err(e) => {
            // A standard error closed too (`… 2>&1 | head`) leaves the exit code to say it:
            // `eprintln!` would panic there.
            let _ = writeln!(std::io::stderr(), "{}", cli::report::prepend("ncsheet: ", &e.to_string()));
            ExitCode::from(e.exit_code())
        }
    }
}
