//! Saving never loses anything (issue 14): no command writes over its inputs, a failed
//! command leaves every file as it was, a csv keeps what was typed, and the atomic write
//! respects what sits at the target. Each input's sha256 (by `sha256sum`) is compared
//! before and after.

use std::fs;
use std::os::unix::fs::{symlink, PermissionsExt};
use std::path::Path;
use std::process::Command;

struct Run {
    code: i32,
    stderr: String,
}

fn ncsheet(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).current_dir(dir).output().unwrap();
    Run { code: out.status.code().expect("exited"), stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

fn sha256(path: &Path) -> String {
    let out = Command::new("sha256sum").arg(path).output().expect("sha256sum runs");
    String::from_utf8(out.stdout).unwrap().split_whitespace().next().unwrap_or_default().to_string()
}

/// The sha256 of each file, to compare after a command.
fn sums(dir: &Path, names: &[&str]) -> Vec<String> {
    names.iter().map(|n| sha256(&dir.join(n))).collect()
}

const BOOK: &str = "1,2\n=A1+B1,x\n";
const MACRO: &str = "Sub Main()\n  [A1] = 5\n  Nc.Line 10, 20\nEnd Sub\n";
const CAM: &str = "type,from_deg,to_deg,r_start,r_end\ncircle,0,180,20,20\narch,180,300,20,25\n";

fn folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("wb.csv"), BOOK).unwrap();
    fs::write(dir.path().join("m.bas"), MACRO).unwrap();
    fs::write(dir.path().join("cam.csv"), CAM).unwrap();
    dir
}

#[test]
fn no_command_writes_over_its_inputs_however_they_are_named() {
    let dir = folder();
    let d = dir.path();
    symlink(d.join("wb.csv"), d.join("link.csv")).unwrap();
    fs::hard_link(d.join("m.bas"), d.join("hard.bas")).unwrap();
    let inputs = ["wb.csv", "m.bas", "cam.csv"];
    let before = sums(d, &inputs);
    // The same file spelled through the parent folder.
    let round_about = format!("../{}/wb.csv", d.file_name().unwrap().to_string_lossy());
    let cases: &[&[&str]] = &[
        &["run", "wb.csv", "m.bas", "-o", "wb.csv"],
        &["run", "wb.csv", "m.bas", "-o", "m.bas"],
        &["run", "wb.csv", "m.bas", "-o", "./m.bas"],
        &["run", "wb.csv", "m.bas", "-o", "hard.bas"],
        &["run", "wb.csv", "m.bas", "--save", "link.csv"],
        &["run", "wb.csv", "m.bas", "--save", "m.bas"],
        &["run", "wb.csv", "m.bas", "-o", "out.nc", "--save", "out.nc"],
        &["cam", "cam.csv", "--partial", "-o", "cam.csv"],
        &["set", "wb.csv", "A1=3", "-o", "link.csv"],
        &["export", "wb.csv", "-o", &round_about],
    ];
    for args in cases {
        let run = ncsheet(d, args);
        assert_eq!(run.code, 2, "{args:?} must be refused: {}", run.stderr);
        assert!(run.stderr.contains("refusing to overwrite") || run.stderr.contains("same file"), "{}", run.stderr);
        assert_eq!(sums(d, &inputs), before, "{args:?} changed an input");
    }
    assert!(!d.join("out.nc").exists());
}

#[test]
fn a_run_whose_save_fails_writes_nothing() {
    let dir = folder();
    let d = dir.path();
    // The program is fine; the workbook cannot be saved as .xlsm (no VBA project to keep).
    let run = ncsheet(d, &["run", "wb.csv", "m.bas", "-o", "prog.nc", "--save", "out.xlsm"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(!d.join("prog.nc").exists(), "the program was written before the save failed");
    assert!(!d.join("out.xlsm").exists());
    // A save target that cannot be replaced (a directory) stops the program file too.
    fs::create_dir(d.join("dir.csv")).unwrap();
    fs::write(d.join("prog.nc"), "old").unwrap();
    let run = ncsheet(d, &["run", "wb.csv", "m.bas", "-o", "prog.nc", "--save", "dir.csv"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("prog.nc")).unwrap(), "old");
}

#[test]
fn a_csv_keeps_what_was_typed_and_only_edited_cells_change() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let typed = "id,when,big,amount,rate,price\r\n\
                 007,2024-01-10,12345678901234567890,\"1,234\",50%,$100\r\n\
                 short\r\n\
                 \r\n\
                 \"quoted\",=B2+1,  spaced  ,TRUE,'12,x\r\n";
    fs::write(d.join("t.csv"), typed).unwrap();
    let run = ncsheet(d, &["set", "t.csv", "C3=42", "--in-place"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let expected = "id,when,big,amount,rate,price\r\n\
                    007,2024-01-10,12345678901234567890,\"1,234\",50%,$100\r\n\
                    short,,42\r\n\
                    \r\n\
                    \"quoted\",=B2+1,  spaced  ,TRUE,'12,x\r\n";
    assert_eq!(fs::read_to_string(d.join("t.csv")).unwrap(), expected);
    // A far cell adds its row only, in the file's line ending; no row is padded.
    let run = ncsheet(d, &["set", "t.csv", "XFD9=1", "B2=", "-o", "far.csv"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let far = fs::read_to_string(d.join("far.csv")).unwrap();
    let lines: Vec<&str> = far.split("\r\n").collect();
    assert_eq!(lines[1], "007,,12345678901234567890,\"1,234\",50%,$100");
    assert_eq!(lines[2], "short,,42");
    assert_eq!(lines[5..8], ["", "", ""]);
    assert_eq!(lines[8].len(), 16384, "XFD is column 16384: 16383 commas and the 1");
    assert!(far.len() < 20_000);
}

#[test]
fn the_save_follows_symlinks_and_refuses_special_files() {
    let dir = folder();
    let d = dir.path();
    symlink("wb.csv", d.join("link.csv")).unwrap();
    let run = ncsheet(d, &["set", "link.csv", "A1=7", "--in-place"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(fs::symlink_metadata(d.join("link.csv")).unwrap().file_type().is_symlink());
    assert_eq!(fs::read_to_string(d.join("wb.csv")).unwrap(), "7,2\n=A1+B1,x\n");

    assert!(Command::new("mkfifo").arg(d.join("fifo.csv")).status().unwrap().success());
    symlink("fifo.csv", d.join("to-fifo.csv")).unwrap();
    symlink("/dev/null", d.join("null.csv")).unwrap();
    for (target, what) in [("fifo.csv", "FIFO"), ("to-fifo.csv", "FIFO"), ("null.csv", "device")] {
        let run = ncsheet(d, &["export", "wb.csv", "-o", target]);
        assert_eq!(run.code, 1, "{target}: {}", run.stderr);
        assert!(run.stderr.contains(what), "{target}: {}", run.stderr);
    }
    assert!(!fs::metadata(d.join("fifo.csv")).unwrap().is_file());
}

#[test]
fn read_only_and_hard_linked_targets_need_force() {
    let dir = folder();
    let d = dir.path();
    fs::write(d.join("ro.csv"), "old\n").unwrap();
    fs::set_permissions(d.join("ro.csv"), fs::Permissions::from_mode(0o444)).unwrap();
    let run = ncsheet(d, &["export", "wb.csv", "-o", "ro.csv"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("read-only"), "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("ro.csv")).unwrap(), "old\n");
    let run = ncsheet(d, &["export", "wb.csv", "-o", "ro.csv", "--force"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("ro.csv")).unwrap(), "1,2\n3,x\n");
    assert_eq!(fs::metadata(d.join("ro.csv")).unwrap().permissions().mode() & 0o777, 0o444);

    fs::write(d.join("a.csv"), "old\n").unwrap();
    fs::hard_link(d.join("a.csv"), d.join("b.csv")).unwrap();
    let run = ncsheet(d, &["export", "wb.csv", "-o", "a.csv"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("hard links"), "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("b.csv")).unwrap(), "old\n");
}
