//! The options that bound what a command may spend (docs/limits.md): a wall-clock
//! `--timeout`, which every command that does work takes (all but `functions`), and the limits on reading files
//! (`ncsheet::io::limits`), which the commands that read workbooks take.

use std::sync::OnceLock;
use std::time::Duration;

use clap::Args;
use ncsheet::io::limits::ReadLimits;

/// The time a command may take (see docs/limits.md): every command's that does work a
/// timeout could stop. Global, so that `nc`'s subcommands take it too.
#[derive(Debug, Args)]
pub struct TimeoutArg {
    /// Stop the command after this many seconds of wall-clock time, with an error; a macro
    /// stops at the statement it was running (default: no limit)
    // `--max-seconds`: the option's first name, kept for the scripts that use it.
    #[arg(long, global = true, alias = "max-seconds", value_name = "SECONDS", value_parser = parse_seconds)]
    pub timeout: Option<f64>,
}

impl TimeoutArg {
    /// Starts the clock of `--timeout`.
    pub fn apply(&self) {
        if let Some(seconds) = self.timeout {
            let _ = DEADLINE.set(ncsheet::vba::Deadline::after(seconds));
            start_clock(seconds);
        }
    }
}

/// What a file may make ncsheet hold (see docs/limits.md): the options of the commands that
/// read workbooks.
#[derive(Debug, Default, Args)]
#[command(next_help_heading = "Limits on reading files")]
pub struct ReadLimitArgs {
    /// The most one part of an xlsx package may inflate to: 1G, 512M, 4096K or bytes
    /// (default 1G)
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_part_size: Option<u64>,
    /// The most one part of an xlsx package may inflate to per byte of its compressed size,
    /// once it passes 1 MiB (default 100; zip bombs reach 1000)
    #[arg(long, value_name = "RATIO", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_zip_ratio: Option<u64>,
    /// The longest field of a csv file (default 1M)
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_csv_field: Option<u64>,
    /// The longest line (record) of a csv file (default 64M)
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_csv_line: Option<u64>,
}

impl ReadLimitArgs {
    /// Keeps the read limits for every workbook this command opens.
    pub fn apply(&self) {
        let default = ReadLimits::default();
        let _ = READ_LIMITS.set(ReadLimits {
            part_bytes: self.max_part_size.unwrap_or(default.part_bytes),
            zip_ratio: self.max_zip_ratio.unwrap_or(default.zip_ratio),
            csv_field_bytes: self.max_csv_field.unwrap_or(default.csv_field_bytes),
            csv_line_bytes: self.max_csv_line.unwrap_or(default.csv_line_bytes),
        });
    }
}

/// The read limits of this command's options (the command line's, handed to each document).
static READ_LIMITS: OnceLock<ReadLimits> = OnceLock::new();

/// The read limits every workbook this command opens is held to.
pub fn read_limits() -> ReadLimits {
    READ_LIMITS.get().copied().unwrap_or_default()
}

/// How long after `--timeout` the clock ends the process.
const GRACE: Duration = Duration::from_millis(100);

/// When `--timeout` runs out, once [`TimeoutArg::apply`] has started the clock.
static DEADLINE: OnceLock<ncsheet::vba::Deadline> = OnceLock::new();

/// The `--timeout` of this command, for work that can stop itself at a clear place first
/// (a macro, at its statement); the clock thread ends everything else.
pub fn deadline() -> Option<ncsheet::vba::Deadline> {
    DEADLINE.get().copied()
}

/// A thread that ends the process when `--timeout` runs out, whatever the command is doing
/// (a long recalculation, a macro, a tool path): only the command line may exit, and only
/// a clock outside the work can stop any work. An interrupted save leaves the target as it
/// was (`io::atomic`).
fn start_clock(seconds: f64) {
    std::thread::spawn(move || {
        // A moment's grace, so that a macro stopping itself at the deadline says where.
        std::thread::sleep(Duration::from_secs_f64(seconds) + GRACE);
        eprintln!("ncsheet: stopped: the command ran past its --timeout of {seconds} s");
        std::process::exit(1);
    });
}

fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s > 0.0 && s <= 1e9 => Ok(s),
        _ => Err(format!("'{text}' is not a number of seconds between 0 and 1e9")),
    }
}

/// `1G`, `512M`, `64K` (binary units, case-insensitive, an optional `B` or `iB`) or bytes.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let lower = text.trim().to_ascii_lowercase();
    let body = lower.strip_suffix("ib").or_else(|| lower.strip_suffix('b')).unwrap_or(&lower);
    let (digits, shift) = match body.char_indices().last() {
        Some((i, 'k')) => (&body[..i], 10),
        Some((i, 'm')) => (&body[..i], 20),
        Some((i, 'g')) => (&body[..i], 30),
        Some((i, 't')) => (&body[..i], 40),
        _ => (body, 0),
    };
    let bad = || format!("'{text}' is not a size (bytes, or a number with K, M, G or T)");
    let n: u64 = digits.trim().parse().map_err(|_| bad())?;
    n.checked_mul(1 << shift).filter(|&n| n > 0).ok_or_else(bad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_take_binary_units() {
        assert_eq!(parse_size("1G"), Ok(1 << 30));
        assert_eq!(parse_size("512m"), Ok(512 << 20));
        assert_eq!(parse_size("4096KiB"), Ok(4 << 20));
        assert_eq!(parse_size("1000"), Ok(1000));
        assert!(parse_size("1.5G").is_err());
        assert!(parse_size("0").is_err());
        assert!(parse_seconds("-1").is_err());
    }
}
