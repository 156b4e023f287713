//! Runs LinuxCNC's stand-alone interpreter `rs274` on a program and reads back the moves it
//! would make (its canonical machining commands), so tests check NC text with a real
//! interpreter instead of with our own parser.

use std::path::Path;
use std::process::Command;

/// One canonical move, in the interpreter's units (mm, X as a radius on a lathe).
#[derive(Clone, Debug, PartialEq)]
pub enum Move {
    Traverse {
        x: f64,
        y: f64,
        z: f64,
    },
    Feed {
        x: f64,
        y: f64,
        z: f64,
    },
    /// `ARC_FEED(first_end, second_end, first_centre, second_centre, rotation, axis_end, …)`;
    /// in the XZ plane (G18) "first" is Z and "second" is X.
    Arc {
        first_end: f64,
        second_end: f64,
        first_centre: f64,
        second_centre: f64,
        rotation: i32,
        axis_end: f64,
    },
}

/// Whether `rs274` can be run here; tests that need it skip (and say so) when it cannot.
/// On CI (`CI` set) it must be there: `.ci/run` installs it.
pub fn available() -> bool {
    let found = Command::new("rs274").arg("-h").output().is_ok();
    assert!(found || std::env::var_os("CI").is_none(), "rs274 is missing on CI (linuxcnc-uspace)");
    found
}

/// The moves `rs274 -g` reads from `program`, or the interpreter's complaint.
pub fn moves(program: &Path) -> Result<Vec<Move>, String> {
    Ok(canon(program)?.lines().filter_map(parse_line).collect())
}

/// The feed mode in force at the program's first cut (`STRAIGHT_FEED` or `ARC_FEED`), as
/// rs274 reports it in `SET_FEED_MODE(spindle, mode)`: 0 per minute, 1 per revolution;
/// `None` when no feed mode was set before it (or the program does not cut).
pub fn feed_mode_at_first_cut(program: &Path) -> Result<Option<i32>, String> {
    let text = canon(program)?;
    let mut mode = None;
    for line in text.lines() {
        if let Some((_, rest)) = line.split_once("SET_FEED_MODE(") {
            mode = rest.trim_end_matches(')').split(',').nth(1).and_then(|m| m.trim().parse().ok());
        }
        if line.contains("STRAIGHT_FEED(") || line.contains("ARC_FEED(") {
            return Ok(mode);
        }
    }
    Ok(None)
}

/// rs274's canonical commands for `program`, one per line, or its complaint.
pub fn canon(program: &Path) -> Result<String, String> {
    canon_with_tools(program, None)
}

/// A tool table for `rs274 -t` with one tool of the given length (mm) in pocket 1. The
/// stand-alone interpreter reads a table's lengths in inches (its default machine units:
/// a table `Z50` becomes a 1270 mm offset), so the length is written in inches.
pub fn tool_table(dir: &Path, tool: u32, length_mm: f64) -> std::path::PathBuf {
    let path = dir.join("tool.tbl");
    std::fs::write(&path, format!("T{tool} P1 Z{:.9} D0.25 ;length {length_mm} mm\n", length_mm / 25.4)).unwrap();
    path
}

/// [`canon`] with the tool table `tools` (`rs274 -t`).
pub fn canon_with_tools(program: &Path, tools: Option<&Path>) -> Result<String, String> {
    // rs274 keeps state in the working directory (its parameter file) and maps
    // `$HOME/.tool.mmap`; two runs sharing either crash each other (SIGBUS). Each program's
    // own folder is its working directory and its HOME.
    let dir = program.parent().unwrap_or(Path::new("."));
    let out = Command::new("rs274")
        .current_dir(dir)
        .env("HOME", dir)
        .args(tools.map(|t| vec![std::ffi::OsStr::new("-t"), t.as_os_str()]).unwrap_or_default())
        .arg("-g")
        .arg(program)
        .output()
        .map_err(|e| format!("rs274: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    if !out.status.success() || text.contains("error") || text.contains("Error") {
        return Err(text);
    }
    Ok(text)
}

/// The Z of the tool length offset in force at each `STRAIGHT_FEED`/`STRAIGHT_TRAVERSE`,
/// with the move's programmed (x, y, z): rs274 reports positions in program coordinates and
/// the offset apart (`USE_TOOL_LENGTH_OFFSET(x y z, …)`), so the spindle's point the machine
/// drives is the move's z plus the offset.
pub fn moves_with_length_offset(canon: &str) -> Vec<([f64; 3], f64)> {
    let mut offset = 0.0;
    let mut out = Vec::new();
    for line in canon.lines() {
        if let Some((_, rest)) = line.split_once("USE_TOOL_LENGTH_OFFSET(") {
            let first = rest.split(',').next().unwrap_or("");
            offset = first.split_whitespace().nth(2).and_then(|z| z.parse().ok()).expect("an offset's z");
        }
        if let Some(Move::Traverse { x, y, z } | Move::Feed { x, y, z }) = parse_line(line) {
            out.push(([x, y, z], offset));
        }
    }
    out
}

/// The moves of rs274's canonical commands `canon` (from [`canon_with_tools`]).
#[allow(dead_code)]
pub fn moves_of(canon: &str) -> Vec<Move> {
    canon.lines().filter_map(parse_line).collect()
}

fn parse_line(line: &str) -> Option<Move> {
    let (name, rest) = line.split_once('(')?;
    let args: Vec<f64> = rest.trim_end_matches(')').split(',').filter_map(|a| a.trim().parse().ok()).collect();
    let name = name.split_whitespace().last()?;
    match name {
        "STRAIGHT_TRAVERSE" => Some(Move::Traverse { x: args[0], y: args[1], z: args[2] }),
        "STRAIGHT_FEED" => Some(Move::Feed { x: args[0], y: args[1], z: args[2] }),
        "ARC_FEED" => Some(Move::Arc {
            first_end: args[0],
            second_end: args[1],
            first_centre: args[2],
            second_centre: args[3],
            rotation: args[4] as i32,
            axis_end: args[5],
        }),
        _ => None,
    }
}
