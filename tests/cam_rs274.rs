//! The NC program of the sample cam run through LinuxCNC's rs274 interpreter: every ARC_FEED it
//! reports must end and be centred where our arcs are, to 1e-4 mm. Skipped (with a message)
//! where rs274 is not installed.

mod common;

use std::process::Command;

use ncsheet::geometry::cam::{by_disc, fit_cam, CamFit, CamOptions};
use ncsheet::nc::cam::{cam_program, CamNcOptions, Compensation};
use ncsheet::nc::cam_sheet::parse_sheet;
use ncsheet::nc::dialect;

/// The program as LinuxCNC reads it (the `iso` dialect writes a Fanuc O-number it rejects).
fn nc_program(cam: &CamFit, options: &CamNcOptions) -> String {
    dialect::by_name("linuxcnc").unwrap().render(&cam_program(cam, options).unwrap()).unwrap()
}

const SHEET: &str = include_str!("../sheets/cam-turret.csv");

/// rs274 (found on PATH), or `None` where it is not installed; on CI it must be (see
/// `common::rs274::available`).
fn rs274() -> Option<&'static str> {
    common::rs274::available().then_some("rs274")
}

fn sample_cams() -> Vec<CamFit> {
    sample_cams_at(0.001)
}

fn sample_cams_at(tolerance: f64) -> Vec<CamFit> {
    let options = CamOptions::either_side(tolerance, true);
    let segments = parse_sheet(SHEET).unwrap();
    by_disc(&segments).iter().map(|(d, s)| fit_cam(d, s, &options).unwrap()).collect()
}

/// rs274's canonical commands for `program`, or its complaint.
fn interpret(rs274: &str, program: &str) -> Result<String, String> {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cam.ngc");
    std::fs::write(&file, program).unwrap();
    // rs274 keeps state in the working directory and in $HOME (.tool.mmap): one of each per
    // run, so that parallel tests do not share them.
    let out = Command::new(rs274)
        .current_dir(dir.path())
        .env("HOME", dir.path())
        .arg("-g")
        .arg(&file)
        .output()
        .map_err(|e| format!("cannot run {rs274}: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if !out.status.success() || stdout.contains("error") || stderr.contains("error") {
        return Err(format!("rs274 failed ({}):\n{stderr}\n{stdout}", out.status));
    }
    Ok(stdout)
}

/// The numbers inside `NAME(...)` on each line that has it.
fn calls(canon: &str, name: &str) -> Vec<Vec<f64>> {
    canon
        .lines()
        .filter_map(|l| l.split_once(&format!("{name}(")))
        .map(|(_, rest)| rest.trim_end_matches(')').split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect()
}

#[test]
fn rs274_cuts_our_arcs() {
    let Some(rs274) = rs274() else {
        println!("skipped: rs274 (LinuxCNC) is not installed");
        return;
    };
    for cam in sample_cams() {
        let canon = interpret(rs274, &nc_program(&cam, &CamNcOptions::default())).unwrap();
        let arcs: Vec<_> = cam.arcs().collect();
        let feeds = calls(&canon, "ARC_FEED");
        assert_eq!(feeds.len(), arcs.len(), "disc {}: {canon}", cam.disc);
        for (i, (a, f)) in arcs.iter().zip(&feeds).enumerate() {
            // ARC_FEED(end x, end y, centre x, centre y, rotation, end z, ...)
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-4;
            assert!(
                close(f[0], a.end.x) && close(f[1], a.end.y),
                "disc {} arc {}: end {f:?} vs {a:?}",
                cam.disc,
                i + 1
            );
            assert!(
                close(f[2], a.centre.x) && close(f[3], a.centre.y),
                "disc {} arc {}: centre {f:?} vs {a:?}",
                cam.disc,
                i + 1
            );
            assert_eq!(f[4].signum(), a.turn.sign(), "disc {} arc {}: direction", cam.disc, i + 1);
        }
    }
}

#[test]
fn rs274_accepts_cutter_compensation() {
    let Some(rs274) = rs274() else {
        println!("skipped: rs274 (LinuxCNC) is not installed");
        return;
    };
    // At 0.01 mm, as a cam is cut: at 0.001 mm the wall of a return that drops almost
    // radially into a dwell (the valley at 210° of the completed sheet) ends in arcs that
    // LinuxCNC's one-move look-ahead refuses with compensation on ("Arc move in concave
    // corner").
    let cam = &sample_cams_at(0.01)[0];
    let options = CamNcOptions { compensation: Compensation::Right, ..CamNcOptions::default() };
    let canon = interpret(rs274, &nc_program(cam, &options)).unwrap();
    // The control adds its own corner arcs where segments meet at an angle (circle to log
    // spiral, across gaps), so there are at least as many arcs as ours.
    assert!(calls(&canon, "ARC_FEED").len() >= cam.n_arcs());
}
