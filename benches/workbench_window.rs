//! The time of the workbench's largest window of cells (`/api/cells`, 1,000 rows × 200
//! columns) over a sheet that holds much elsewhere: N spilling formulas below the window, and
//! every cell of the window an error with its explanation (issue 30, runaway: each cell shown
//! looked through all the sheet's spill anchors and all the workbook's problems). See
//! benches/README.md.
//!
//!     cargo run --release --bin ncsheet-bench-window -- [--sizes spills-25000,spills-100000] [--runs N]
//!
//! Each answer is checked (200,000 cells, each with its explanation): a wrong one stops the bench.

#[path = "sizes_and_runs.rs"]
mod sizes_and_runs;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::ExitCode;
use std::time::Instant;

use ncsheet_server::{Options, Server, TOKEN_HEADER};

/// Spilling formulas below the window: a quarter, a half and the whole of the case.
const DEFAULT_SIZES: &[&str] = &["spills-25000", "spills-50000", "spills-100000"];

/// The window: the largest the server answers.
const ROWS: usize = 1000;
const COLS: usize = 200;

fn main() -> ExitCode {
    sizes_and_runs::exit("ncsheet-bench-window", run())
}

fn run() -> Result<(), String> {
    let args = sizes_and_runs::parse_args(DEFAULT_SIZES)?;
    println!("| spills below | cells in the window | best of {} | per cell |", args.runs);
    println!("|---|---|---|---|");
    for size in &args.sizes {
        let spills: usize = size
            .strip_prefix("spills-")
            .and_then(|n| n.parse().ok())
            .ok_or_else(|| format!("bad case {size:?} (spills-N)"))?;
        let folder = std::env::temp_dir().join(format!("ncsheet-bench-window-{}-{spills}", std::process::id()));
        std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
        let best = serve(&folder, spills).and_then(|(port, token)| best_window(port, &token, args.runs));
        let _ = std::fs::remove_dir_all(&folder);
        let best = best?;
        println!("| {spills} | {} | {best:.3} s | {:.2} µs |", ROWS * COLS, best * 1e6 / (ROWS * COLS) as f64);
    }
    Ok(())
}

/// The shortest of `runs` answers of the whole window, in seconds, each checked.
fn best_window(port: u16, token: &str, runs: usize) -> Result<f64, String> {
    let mut best = f64::MAX;
    for _ in 0..runs {
        let start = Instant::now();
        let body = get(port, token, &format!("/api/cells?sheet=0&r0=0&r1={}&c0=0&c1={}", ROWS - 1, COLS - 1))?;
        best = best.min(start.elapsed().as_secs_f64());
        check(&body)?;
    }
    Ok(best)
}

/// A workbench serving a csv, written in `folder`, of the window's `=1+` cells above `spills`
/// spilling formulas: its port and its token (the server has read the file once it answers).
fn serve(folder: &std::path::Path, spills: usize) -> Result<(u16, String), String> {
    let file = folder.join("window.csv");
    let broken = ["=1+"; COLS].join(",");
    let mut text = format!("{broken}\n").repeat(ROWS);
    text.push_str(&"\"=SEQUENCE(1,2)\"\n".repeat(spills));
    std::fs::write(&file, text).map_err(|e| e.to_string())?;
    let server = Server::open(&file, &Options::default()).map_err(|e| e.to_string())?;
    let (port, token) = (server.port(), server.token().to_string());
    std::thread::spawn(move || server.run());
    Ok((port, token))
}

/// The body of `GET path`, as the page asks it.
fn get(port: u16, token: &str, path: &str) -> Result<String, String> {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
    let request = format!(
        "GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n{TOKEN_HEADER}: {token}\r\nConnection: close\r\n\r\n"
    );
    stream.write_all(request.as_bytes()).map_err(|e| e.to_string())?;
    let mut answer = String::new();
    stream.read_to_string(&mut answer).map_err(|e| e.to_string())?;
    if !answer.starts_with("HTTP/1.1 200") {
        return Err(format!("GET {path}: {}", answer.lines().next().unwrap_or("no answer")));
    }
    Ok(answer.split_once("\r\n\r\n").map_or(String::new(), |(_, b)| b.to_string()))
}

/// The window holds all its cells, the last explained as the `=1+` it is.
fn check(body: &str) -> Result<(), String> {
    let json: serde_json::Value = serde_json::from_str(body).map_err(|e| e.to_string())?;
    let cells = json["cells"].as_array().ok_or("no cells in the answer")?;
    let last = cells.last().and_then(|c| c["explain"].as_str()).unwrap_or("");
    if cells.len() != ROWS * COLS || !last.contains("=1+") {
        return Err(format!("{} cells, the last explained {last:?}", cells.len()));
    }
    Ok(())
}
