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

/// Every command that writes a file takes --force for a read-only target and refuses
/// without it, leaving the target as it was (cam, arcfit and ballpath wrote over it).
#[test]
fn every_writing_command_refuses_a_read_only_target_without_force() {
    let dir = folder();
    let d = dir.path();
    fs::write(
        d.join("m.bas"),
        "Sub Main()\n  [A1] = 5\n  Nc.FeedPerRev 0.1\n  Nc.Spindle 500\n  Nc.Line 10, 20\nEnd Sub\n",
    )
    .unwrap();
    let ballpath = ["ballpath", "--surface", "0", "--radius", "1", "--x", "0:1", "--y", "0:1", "--stepover", "1"];
    let ballpath: Vec<&str> = ballpath.iter().copied().chain(["--step", "1"]).collect();
    let arcfit =
        ["arcfit", "--kind", "arch", "--r0", "20", "--phi0", "0", "--r1", "25", "--phi1", "90", "--tol", "0.05"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["set", "wb.csv", "A1=3", "-o"], "out.csv"),
        (vec!["export", "wb.csv", "-o"], "out.csv"),
        (vec!["run", "wb.csv", "m.bas", "-o"], "out.nc"),
        (vec!["run", "wb.csv", "m.bas", "--save"], "out.csv"),
        (vec!["cam", "cam.csv", "--partial", "-o"], "out.nc"),
        (arcfit.iter().copied().chain(["-o"]).collect(), "out.csv"),
        (ballpath.iter().copied().chain(["-o"]).collect(), "out.csv"),
        (vec!["macros", "wb.csv", "--import", "m.bas", "-o"], "out.xlsm"),
    ];
    for (args, target) in cases {
        fs::write(d.join(target), "old\n").unwrap();
        fs::set_permissions(d.join(target), fs::Permissions::from_mode(0o444)).unwrap();
        let with_target: Vec<&str> = args.iter().copied().chain([target]).collect();
        let run = ncsheet(d, &with_target);
        assert_eq!(run.code, 1, "{with_target:?}: {}", run.stderr);
        assert!(run.stderr.contains("read-only"), "{with_target:?}: {}", run.stderr);
        assert_eq!(fs::read_to_string(d.join(target)).unwrap(), "old\n", "{with_target:?} wrote");
        let forced: Vec<&str> = with_target.iter().copied().chain(["--force"]).collect();
        let run = ncsheet(d, &forced);
        assert_eq!(run.code, 0, "{forced:?}: {}", run.stderr);
        assert_ne!(fs::read_to_string(d.join(target)).unwrap_or_default(), "old\n", "{forced:?} did not write");
        fs::set_permissions(d.join(target), fs::Permissions::from_mode(0o644)).unwrap();
        fs::remove_file(d.join(target)).unwrap();
    }
    // A session's save too.
    fs::write(d.join("ro.csv"), "old\n").unwrap();
    fs::set_permissions(d.join("ro.csv"), fs::Permissions::from_mode(0o444)).unwrap();
    let run = repl(d, "wb.csv", "A1=9\nsave ro.csv\n");
    assert!(run.stderr.contains("read-only"), "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("ro.csv")).unwrap(), "old\n");
    let run = repl(d, "wb.csv", "A1=9\nsave ro.csv --force\n");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("ro.csv")).unwrap(), "9,2\n=A1+B1,x\n");
}

/// `cam` never writes over its design sheet, however the output is spelled, --force or not
/// (`ballpath` reads no file).
#[test]
fn cam_and_arcfit_refuse_their_input_as_output() {
    let dir = folder();
    let d = dir.path();
    symlink(d.join("cam.csv"), d.join("cam-link.csv")).unwrap();
    let before = sums(d, &["cam.csv"]);
    for out in ["cam.csv", "./cam.csv", "cam-link.csv"] {
        let run = ncsheet(d, &["cam", "cam.csv", "--partial", "-o", out, "--force"]);
        assert_eq!(run.code, 2, "{out}: {}", run.stderr);
        assert!(run.stderr.contains("refusing to overwrite"), "{}", run.stderr);
    }
    assert_eq!(sums(d, &["cam.csv"]), before);
}

fn repl(dir: &Path, book: &str, script: &str) -> Run {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["repl", book])
        .current_dir(dir)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(script.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    Run { code: out.status.code().expect("exited"), stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

/// A csv edit that replaces a formula by a constant names the cell before writing, and
/// --in-place then needs --force.
#[test]
fn replacing_a_formula_by_a_constant_is_said_and_in_place_needs_force() {
    let dir = folder();
    let d = dir.path();
    let before = sums(d, &["wb.csv"]);
    let run = ncsheet(d, &["set", "wb.csv", "A2=5", "--in-place"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!A2") && run.stderr.contains("replaced by constants"), "{}", run.stderr);
    assert!(run.stderr.contains("nothing was written"), "{}", run.stderr);
    assert_eq!(sums(d, &["wb.csv"]), before);
    // To another file it is written, and said.
    let run = ncsheet(d, &["set", "wb.csv", "A2=5", "-o", "out.csv"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!A2"), "{}", run.stderr);
    // A formula replaced by another formula, or a constant by a constant, is no loss.
    let run = ncsheet(d, &["set", "wb.csv", "A2==A1*2", "B1=4", "--in-place"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("not kept"), "{}", run.stderr);
    let run = ncsheet(d, &["set", "wb.csv", "A2=5", "--in-place", "--force"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(fs::read_to_string(d.join("wb.csv")).unwrap(), "1,4\n5,x\n");
    // A macro writing over a formula: said before the save is written.
    fs::write(d.join("book.csv"), BOOK).unwrap();
    fs::write(d.join("over.bas"), "Sub Main()\n  [A2] = 5\nEnd Sub\n").unwrap();
    let run = ncsheet(d, &["run", "book.csv", "over.bas", "--save", "saved.csv"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!A2") && run.stderr.contains("replaced by constants"), "{}", run.stderr);
}
