//! Unclear errors (issue 30): messages that blamed the wrong thing or spoke of an option
//! nobody gave now say what is wrong and where, in the words of the one who wrote the input.

mod common;

use common::cli::{ncsheet, Run};
use ncsheet::eval::{Value, XlError};

// ---------------------------------------------------------------------------------------
// TEXT's format codes

#[test]
fn text_names_the_bracket_a_format_code_leaves_open() {
    // Excel refuses a code with a `[` no `]` closes (TEXT is #VALUE!); the note blamed
    // "digit placeholders in dates", which `[` has nothing to do with.
    for (formula, place) in [("=TEXT(1,\"[\")", 1), ("=TEXT(1,\"0.00 [Red\")", 6), ("=TEXT(1,\"\"\"[\"\"0 [\")", 6)] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Value), "{formula}");
        let note = notes.join("\n");
        assert!(note.contains(&format!("the \"[\" at character {place} is not closed by \"]\"")), "{formula}: {note}");
        assert!(!note.contains("digit placeholders"), "{formula}: {note}");
    }
    // A date code with a digit placeholder says so in words that name the mix.
    let (value, notes, _) = common::sheet::eval_a1("=TEXT(1,\"mm0\")");
    assert_eq!(value, Value::Error(XlError::Value));
    assert!(notes.join("\n").contains("a date or time code holds a digit placeholder"), "{notes:?}");
}

// ---------------------------------------------------------------------------------------
// NC programs

/// `ncsheet nc COMMAND FILE` on `program` written to a file named `name` in a folder of its own.
fn nc(command: &str, name: &str, program: &str, extra: &[&str]) -> Run {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, program).unwrap();
    let mut args = vec!["nc", command, path.to_str().unwrap()];
    args.extend(extra);
    ncsheet(&args)
}

/// LinuxCNC's own example of a subroutine (LinuxCNC documentation, "O Codes",
/// "Subroutines": `o100 sub` … `o100 endsub`, then `o100 call`).
const O_CODE_PROGRAM: &str = "G21 G17 G90\no100 sub\nG53 G00 X0 Y0 Z0\no100 endsub\no100 call\nM2\n";

#[test]
fn o_code_subroutines_are_named_as_such_not_read_as_a_word_s() {
    // `o100 sub` was read as the word O100 and then a word S with no number ("the word S has
    // no number after it"). Read as linuxcnc the subroutine now runs, and what stops it is
    // the block inside (G53, machine coordinates, which the reader does not take), at its own
    // line; read as another dialect the O-code is named, with its line and column, for every
    // command that reads a program.
    let svg = tempfile::tempdir().unwrap();
    let svg = svg.path().join("plot.svg");
    let commands: [(&str, Vec<&str>); 3] = [
        ("check", vec![]),
        ("time", vec!["--accel", "1000", "--rapid", "10000"]),
        ("plot", vec!["--output", svg.to_str().unwrap()]),
    ];
    for (command, extra) in &commands {
        for (name, program) in [("sub.ngc", O_CODE_PROGRAM), ("sub.nc", O_CODE_PROGRAM)] {
            let run = nc(command, name, program, extra);
            assert_ne!(run.code, 0, "nc {command} {name}: {}", run.stdout);
            let said = &run.stderr;
            assert!(said.contains("line 3, column 1: G53"), "nc {command} {name}: {said}");
            assert!(!said.contains("the word S"), "nc {command} {name}: {said}");
            let mut iso = extra.clone();
            iso.extend(["--dialect", "iso"]);
            let run = nc(command, name, program, &iso);
            assert!(run.stderr.contains("line 2, column 1: `o100 sub` is a LinuxCNC O-code"), "{}", run.stderr);
        }
    }
    // A named subroutine the file does not hold is refused by name; a loop read as another
    // dialect is named as LinuxCNC's.
    let run = nc("check", "loop.ngc", "G21 G90\no<pocket> call [2]\nM2\n", &["--dialect", "linuxcnc"]);
    assert!(run.stderr.contains("o<pocket> call: the subroutine is not in this program"), "{}", run.stderr);
    let run = nc("check", "loop.nc", "G21 G90\nO101 while [1 LT 3]\nO101 endwhile\nM2\n", &["--dialect", "iso"]);
    assert!(run.stderr.contains("`O101 while` is a LinuxCNC O-code"), "{}", run.stderr);
}

#[test]
fn an_o_code_tells_that_a_program_is_linuxcnc() {
    // `o100 sub` on the first line was taken for Fanuc's program number O100.
    let run = nc("check", "sub.nc", O_CODE_PROGRAM, &[]);
    assert!(run.stderr.contains("read as linuxcnc (the word O100 SUB, an O-code)"), "{}", run.stderr);
}

#[test]
fn the_dialect_note_does_not_speak_of_an_option_nobody_gave() {
    // Without --dialect the note said "--dialect says otherwise"; it now says how to give one.
    let run = nc("check", "plain.ngc", "G21 G17 G90\nG0 X1 Y1\nM2\n", &[]);
    assert!(run.stderr.contains("give --dialect to read it otherwise"), "{}", run.stderr);
    assert!(!run.stderr.contains("--dialect says otherwise"), "{}", run.stderr);
}
