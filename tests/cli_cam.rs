//! `ncsheet arcfit` and `ncsheet cam` run as a user runs them; the NC program is read back by
//! LinuxCNC's rs274 and compared with the coordinate table of the same fit.

mod common;

use std::process::{Command, Output};

use common::rs274::{self, Move};

fn ncsheet(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

fn sheet() -> String {
    format!("{}/sheets/cam-turret.csv", env!("CARGO_MANIFEST_DIR"))
}

/// The rows of an arcs table as numbers (x0,y0,x1,y1,cx,cy,r) and the direction.
fn arcs(csv: &str) -> Vec<([f64; 7], String)> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x0,y0,x1,y1,cx,cy,r,dir"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let mut n = [0.0; 7];
            for (i, v) in f[..7].iter().enumerate() {
                n[i] = v.parse().unwrap();
            }
            (n, f[7].to_string())
        })
        .collect()
}

#[test]
fn arcfit_starts_and_ends_on_the_spiral() {
    let out = ncsheet(&[
        "arcfit", "--kind", "arch", "--r0", "79", "--phi0", "36", "--r1", "102", "--phi1", "160.2", "--tol", "0.01",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = arcs(&String::from_utf8(out.stdout).unwrap());
    // r = 79 mm at 36°, 102 mm at 160.2° (printed to 6 decimals).
    let (first, last) = (&table[0].0, &table[table.len() - 1].0);
    let at = |r: f64, deg: f64| (r * deg.to_radians().cos(), r * deg.to_radians().sin());
    let (x0, y0) = at(79.0, 36.0);
    let (x1, y1) = at(102.0, 160.2);
    assert!((first[0] - x0).abs() < 1e-6 && (first[1] - y0).abs() < 1e-6);
    assert!((last[2] - x1).abs() < 1e-6 && (last[3] - y1).abs() < 1e-6);
    // Radius grows with the angle: every arc turns counter-clockwise.
    assert!(table.iter().all(|(_, dir)| dir == "ccw"));
    // The bound for this piece at 0.01 mm is 4 arcs; at most ⌈1.25 × 4⌉ = 5.
    assert!(table.len() <= 5, "{} arcs", table.len());
}

#[test]
fn arcfit_rejects_what_has_no_geometry() {
    for bad in [
        vec!["--kind", "log", "--r0", "0", "--phi0", "0", "--r1", "10", "--phi1", "20", "--tol", "0.01"],
        vec!["--kind", "arch", "--r0", "10", "--phi0", "20", "--r1", "12", "--phi1", "20", "--tol", "0.01"],
        vec!["--kind", "arch", "--r0", "10", "--phi0", "0", "--r1", "12", "--phi1", "20", "--tol", "0"],
        vec!["--kind", "cone", "--r0", "10", "--phi0", "0", "--r1", "12", "--phi1", "20", "--tol", "0.01"],
    ] {
        let out = ncsheet(&[&["arcfit"], bad.as_slice()].concat());
        assert_eq!(out.status.code(), Some(1), "{bad:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).trim().is_empty());
    }
}

#[test]
fn cam_reports_the_gaps_of_the_printed_sheet_with_their_rows() {
    let out = ncsheet(&["cam", &sheet(), "--tol", "0.05"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("gap 160.2°–171°") && err.contains("row 5") && err.contains("row 7"), "{err}");
}

#[test]
fn cam_program_is_read_by_rs274_as_the_arcs_of_the_table() {
    if !rs274::available() {
        eprintln!("skipped: rs274 is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("cam.ngc");
    let common = ["cam", &sheet(), "--tol", "0.01", "--partial", "--disc", "R"];
    let table = ncsheet(&common);
    assert!(table.status.success());
    let table = arcs(&String::from_utf8(table.stdout).unwrap());
    let nc =
        ncsheet(&[&common[..], &["--format", "nc", "--dialect", "linuxcnc", "-o", program.to_str().unwrap()]].concat());
    assert!(nc.status.success(), "{}", String::from_utf8_lossy(&nc.stderr));
    let moves = rs274::moves(&program).unwrap();
    let read: Vec<&Move> = moves.iter().filter(|m| matches!(m, Move::Arc { .. })).collect();
    assert_eq!(read.len(), table.len());
    for (m, (a, dir)) in read.iter().zip(&table) {
        let Move::Arc { first_end, second_end, first_centre, second_centre, rotation, .. } = m else { unreachable!() };
        // The program has 4 decimals, the table 6: they agree to the program's resolution.
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-4;
        assert!(close(*first_end, a[2]) && close(*second_end, a[3]), "{m:?} vs {a:?}");
        assert!(close(*first_centre, a[4]) && close(*second_centre, a[5]), "{m:?} vs {a:?}");
        assert_eq!(*rotation, if dir == "ccw" { 1 } else { -1 });
    }
}
