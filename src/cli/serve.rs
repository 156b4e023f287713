//! `ncsheet serve`: starts the workbench (`ncsheet_server`) on 127.0.0.1 and says its URL;
//! lists the macro files beside the workbook, which the server may then read.

use std::path::{Path, PathBuf};

use clap::Args;
use ncsheet_server::{Options, Server};

use super::report::{Error, Result};

/// Open the workbook in a browser: the grid, edits with undo, precedents and dependents,
/// saving, and a machining pane (chamfers, macros' NC programs and backplots).
///
/// The server listens on 127.0.0.1 only and prints its URL, which carries a random token:
/// every request must bring it, and requests from other sites are refused. The opened
/// workbook is saved over only when asked in the page. Stop it with Ctrl+C.
///
/// `--timeout` bounds each request as it bounds a command: a macro run stops at its
/// statement, the workbook's VBA functions stop with the edit's recalculation, and a request
/// still computing then is answered with an error while the server goes on serving.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// The port on 127.0.0.1; 0 takes a free one
    #[arg(long, value_name = "P", default_value_t = 0)]
    pub port: u16,
    /// Open the URL in the desktop's browser (xdg-open)
    #[arg(long)]
    pub open: bool,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
    #[command(flatten)]
    pub reading: super::WorkbookOptions,
}

/// Serves `args.file`, read as every other command reads a workbook (`--delimiter`,
/// `--locale`, the read limits), with `--timeout` for each request.
pub fn run(args: ServeArgs, delimiter: Option<u8>) -> Result<()> {
    let options = Options {
        port: args.port,
        macro_files: macro_files_beside(&args.file),
        open: super::open_options(delimiter),
        timeout: args.timeout.timeout,
        request_deadline: None,
    };
    let server = Server::open(&args.file, &options).map_err(|e| Error::User(e.to_string()))?;
    let url = server.url();
    println!("{url}");
    eprintln!("ncsheet: serving {} at {url} (Ctrl+C stops)", args.file.display());
    if args.open {
        if let Err(e) = std::process::Command::new("xdg-open").arg(&url).spawn() {
            eprintln!("ncsheet: cannot open a browser ({e}): open the URL above");
        }
    }
    server.run().map_err(|e| Error::User(e.to_string()))
}

/// The .bas files in the workbook's folder: the macros the page may run beside the
/// workbook's own modules.
fn macro_files_beside(file: &Path) -> Vec<PathBuf> {
    let folder = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let Ok(entries) = std::fs::read_dir(&folder) else { return Vec::new() };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bas")))
        .collect();
    files.sort();
    files
}
