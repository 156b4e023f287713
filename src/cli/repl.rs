//! `ncsheet repl`: edit a loaded workbook one command at a time. With a terminal on stdin
//! there is a prompt and line editing (rustyline); piped input is read as plain lines, so a
//! script can drive a session and, with `--timings`, measure each edit from outside.

use std::io::{self, BufRead, IsTerminal, Write};
use std::path::Path;
use std::time::Instant;

use ncsheet::formula::ast::SheetId;
use ncsheet::io::xlsx::Layout;
use ncsheet::io::{Opened, Origin};
use ncsheet::workbook::Workbook;
use rustyline::error::ReadlineError;

use super::output::{self, OutputFormat, Selection};
use super::report::{self, prepend, Error, Result};
use super::target::{parse_assignment, parse_target, Assignment, Target};

const HELP: &str = "\
commands:
  CELL=INPUT    set a cell (a value, or a formula starting with =) and recalculate
  CELL, RANGE   print values (B3, A1:D20, Sheet1!B3, or a defined name: alpha)
  show CELL     the cell's formula, value, format, the cells it reads and that read it
  save PATH     save the workbook as `set -o PATH` does: from the file opened, only the
                changed cells rewritten (save PATH --force: over a read-only file)
  help          this list
  quit          leave (also exit, or end of input)";

/// Where lines come from: an editor with a prompt, or plain lines from a pipe.
enum Lines {
    Editor(Box<rustyline::DefaultEditor>),
    Piped(io::StdinLock<'static>),
}

impl Lines {
    fn next(&mut self, prompt: &str) -> Result<Option<String>> {
        match self {
            Lines::Editor(editor) => loop {
                match editor.readline(prompt) {
                    Ok(line) => {
                        let _ = editor.add_history_entry(line.as_str());
                        return Ok(Some(line));
                    }
                    // Ctrl-C drops the line being typed, as in a shell.
                    Err(ReadlineError::Interrupted) => continue,
                    Err(ReadlineError::Eof) => return Ok(None),
                    Err(e) => return Err(Error::User(format!("cannot read the terminal: {e}"))),
                }
            },
            Lines::Piped(stdin) => read_piped_line(stdin).map_err(|e| Error::User(format!("cannot read stdin: {e}"))),
        }
    }
}

/// One line of piped input, ended by LF, CR LF or a lone CR (old Mac files): each is a
/// line break, so a CR-only file is many commands, not one.
fn read_piped_line(input: &mut impl BufRead) -> io::Result<Option<String>> {
    let mut line = Vec::new();
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            return Ok((!line.is_empty()).then(|| String::from_utf8_lossy(&line).into_owned()));
        }
        match buf.iter().position(|&b| b == b'\n' || b == b'\r') {
            Some(i) => {
                let cr = buf[i] == b'\r';
                line.extend_from_slice(&buf[..i]);
                input.consume(i + 1);
                if cr && input.fill_buf()?.first() == Some(&b'\n') {
                    input.consume(1);
                }
                return Ok(Some(String::from_utf8_lossy(&line).into_owned()));
            }
            None => {
                let n = buf.len();
                line.extend_from_slice(buf);
                input.consume(n);
            }
        }
    }
}

enum Flow {
    Continue,
    Quit,
}

struct Session<'a> {
    file: &'a Path,
    wb: Workbook,
    sheet: SheetId,
    /// The file opened, which a save starts from (as `set` does).
    origin: Origin,
    /// The file's layout: the number formats values are shown with, and what a save keeps.
    layout: Option<Layout>,
    /// `--delimiter`: the separator of a csv saved from a workbook that was not one.
    delimiter: Option<u8>,
}

/// Runs commands until `quit` or the end of input. Piped, it fails (exit code 1) when any
/// command failed, so a script notices; each failure was reported when it happened.
pub fn run(file: &Path, opened: Opened, sheet: SheetId, timings: bool, delimiter: Option<u8>) -> Result<()> {
    let interactive = io::stdin().is_terminal();
    let mut lines = if interactive {
        let editor =
            rustyline::DefaultEditor::new().map_err(|e| Error::User(format!("cannot start line editing: {e}")))?;
        Lines::Editor(Box::new(editor))
    } else {
        Lines::Piped(io::stdin().lock())
    };
    let prompt = format!(
        "{}> ",
        file.file_name().map_or_else(|| file.display().to_string(), |n| n.to_string_lossy().into_owned())
    );
    if interactive {
        eprintln!("ncsheet repl on {}: type help for commands", file.display());
    }
    let Opened { workbook: wb, origin, layout, .. } = opened;
    let mut session = Session { file, wb, sheet, origin, layout, delimiter };
    let mut n_failed = 0;
    let stdout = io::stdout();
    while let Some(line) = lines.next(&prompt)? {
        let command = line.trim();
        if command.is_empty() {
            continue;
        }
        let start = Instant::now();
        let mut out = stdout.lock();
        let res = session.command(command, &mut out);
        out.flush()?;
        let flow = match res {
            Ok(flow) => flow,
            Err(e) if matches!(e, Error::Output(_)) => return Err(e),
            Err(e) => {
                eprintln!("{}", prepend("ncsheet: ", &e.to_string()));
                n_failed += 1;
                Flow::Continue
            }
        };
        if timings {
            eprintln!("time_s={:.6}", start.elapsed().as_secs_f64());
        }
        if let Flow::Quit = flow {
            break;
        }
    }
    if n_failed > 0 && !interactive {
        let commands = if n_failed == 1 { "command" } else { "commands" };
        return Err(Error::User(format!("{}: {n_failed} {commands} failed", file.display())));
    }
    Ok(())
}

impl Session<'_> {
    fn command(&mut self, command: &str, out: &mut dyn Write) -> Result<Flow> {
        match command.split_once(char::is_whitespace).map_or((command, ""), |(c, rest)| (c, rest.trim())) {
            ("quit" | "exit", "") => return Ok(Flow::Quit),
            ("help", "") => writeln!(out, "{HELP}")?,
            ("save", "") => return Err(Error::User("save needs a file name: save PATH".into())),
            ("save", rest) => self.save(rest, out)?,
            ("show", "") => return Err(Error::User("show needs a cell: show B3".into())),
            ("show", what) => {
                for word in what.split_whitespace() {
                    let target = parse_target(word).map_err(|e| Error::User(format!("{word}: {e}")))?;
                    write!(out, "{}", super::show::describe_target(&self.wb, self.file, &target, self.sheet)?)?;
                }
            }
            _ if command.contains('=') => {
                let assignment = parse_assignment(command).map_err(|e| Error::User(format!("{command}: {e}")))?;
                self.set(assignment, out)?;
            }
            _ => {
                let target = parse_target(command)
                    .map_err(|_| Error::User(format!("unknown command '{command}' (type help for the list)")))?;
                let selection = self.select(&target).map_err(|e| match target.name {
                    Some(_) if !command.contains(['!', ' ']) => Error::User(format!(
                        "unknown command '{command}': not a command, a cell or a defined name (type help for the list)"
                    )),
                    _ => e,
                })?;
                super::refuse_huge_prints(&self.wb, self.sheet, std::slice::from_ref(&selection))?;
                let shown = self.shown();
                output::print_selections(out, &self.wb, self.sheet, &[selection], OutputFormat::Table, &shown)?;
            }
        }
        Ok(Flow::Continue)
    }

    /// Sets a cell and prints its new value. A formula that does not parse is refused (the
    /// cell keeps what it had); new problems, such as a circular reference, are reported.
    fn set(&mut self, assignment: Assignment, out: &mut dyn Write) -> Result<()> {
        let (sheet, pos) = super::locate_cell(&self.wb, self.file, &assignment.target, self.sheet)?;
        // Typed in the user's locale: a number of another locale is refused, with the spelling meant.
        let input = self
            .wb
            .typed_input(&assignment.input)
            .map_err(|why| Error::User(format!("{}: {}: {why}", self.file.display(), self.wb.cell_name(sheet, pos))))?;
        let input = input.into_owned();
        let news = match self.wb.set_input(sheet, pos, &input) {
            Ok(news) => news,
            Err(p) => return Err(super::in_file(self.file, Error::User(report::render(&self.wb, &p)))),
        };
        writeln!(out, "{}", self.shown().text(&self.wb, sheet, pos))?;
        if let Some(doubt) = super::hints::doubt_about(&self.wb, sheet, pos, &input) {
            eprintln!("ncsheet: {}: {}: warning: {doubt}", self.file.display(), self.wb.cell_name(sheet, pos));
        }
        report::print_capped(&format!("ncsheet: {}: ", self.file.display()), &self.wb, news, Vec::new());
        Ok(())
    }

    /// `save PATH [--force]`: the one save of `set -o`, starting from the file opened so
    /// that what ncsheet does not model is kept; never over the file opened.
    fn save(&self, args: &str, out: &mut dyn Write) -> Result<()> {
        let words: Vec<&str> = args.split_whitespace().collect();
        let force = words.contains(&"--force");
        let path = match words.iter().filter(|w| **w != "--force").collect::<Vec<_>>()[..] {
            [path] => Path::new(path),
            _ => return Err(Error::User("save needs one file name: save PATH (or save PATH --force)".into())),
        };
        super::refuse_overwriting_inputs(&[self.file], &[path], "save the session elsewhere")?;
        let encoded =
            ncsheet::io::encode_save_with(&self.wb, self.layout.as_ref(), &self.origin, path, self.delimiter)?;
        super::write_outputs(&[encoded], false, force)?;
        writeln!(out, "saved {}", path.display())?;
        Ok(())
    }

    fn shown(&self) -> output::Shown<'_> {
        output::Shown { layout: self.layout.as_ref(), ..output::Shown::default() }
    }

    fn select(&self, target: &Target) -> Result<Selection> {
        super::locate(&self.wb, self.file, target, self.sheet)
    }
}
