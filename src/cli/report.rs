//! What goes wrong, said once: the command's [`Error`] (rendered by `main` after `ncsheet: `)
//! and the problems of a sheet's cells (printed on stderr while the command goes on).
//!
//! Messages are built from the inside out with [`prepend`], which keeps a formula's caret
//! line under the right character however much context is put in front of it.

use std::fmt;
use std::io;

use ncsheet::io::notes::{Capped, MAX_NOTES};
use ncsheet::workbook::{Problem, ProblemKind, Workbook};

/// Why a command failed.
#[derive(Debug)]
pub enum Error {
    /// Bad input: a missing or malformed file, a formula that does not parse, a cell off the
    /// sheet. Exit code 1.
    User(String),
    /// Arguments that do not fit together (beyond what clap checks). Exit code 2.
    Usage(String),
    /// Writing the output failed; a closed pipe (`ncsheet eval … | head`) is not reported.
    Output(io::Error),
}

impl Error {
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::User(_) | Error::Output(_) => 1,
            Error::Usage(_) => 2,
        }
    }

    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, Error::Output(e) if e.kind() == io::ErrorKind::BrokenPipe)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::User(m) | Error::Usage(m) => f.write_str(m),
            Error::Output(e) => write!(f, "cannot write the output: {e}"),
        }
    }
}

impl From<io::Error> for Error {
    fn from(e: io::Error) -> Error {
        Error::Output(e)
    }
}

impl From<ncsheet::io::Error> for Error {
    fn from(e: ncsheet::io::Error) -> Error {
        Error::User(e.to_string())
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// `context` before the first line of `message`; later lines are indented by its width, so
/// that a caret line stays under the formula it points into.
pub fn prepend(context: &str, message: &str) -> String {
    let indent = " ".repeat(context.chars().count());
    let mut out = String::with_capacity(context.len() + message.len());
    for (i, line) in message.split('\n').enumerate() {
        if i == 0 {
            out.push_str(context);
        } else {
            out.push('\n');
            out.push_str(&indent);
        }
        // A message quotes cells' texts and formulas, which a file may fill with escapes.
        out.push_str(&printable(line));
    }
    out
}

/// `text` with the control characters a terminal acts on shown as pictures: C0 but tab and
/// line feed as U+2400 + code (`␛` for ESC, `␍` for a carriage return, which rewrites the
/// line), DEL as `␡`, C1 as U+FFFD. A cell's text `\x1b]0;…\x07` printed raw by `eval` set
/// the terminal's title; other sequences move the cursor or rewrite what was shown.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(acted_on) {
        return std::borrow::Cow::Borrowed(text);
    }
    text.chars()
        .map(|c| match c {
            c if !acted_on(c) => c,
            '\u{7f}' => '\u{2421}',
            c if c < ' ' => char::from_u32(0x2400 + c as u32).unwrap_or('\u{fffd}'),
            _ => '\u{fffd}',
        })
        .collect()
}

/// A control character a terminal acts on (tab and line feed only lay text out).
fn acted_on(c: char) -> bool {
    (c < ' ' && c != '\t' && c != '\n') || ('\u{7f}'..='\u{9f}').contains(&c)
}

/// One problem of a cell for a user: `Sheet1!B2: =1+*2` with a caret line.
pub fn render(wb: &Workbook, p: &Problem) -> String {
    prepend(&format!("{}: ", wb.cell_name(p.sheet, p.pos)), &p.render())
}

/// Prints problems on stderr after `context`, then the texts `locale` found read as numbers
/// of another locale: the first few by cell, the rest counted by kind (the import notes' rule,
/// `io::notes::Capped`), since a file of 200,000 bad formulas printed 400,000 lines.
pub fn print_capped(context: &str, wb: &Workbook, problems: Vec<Problem>, foreign_numbers: Vec<String>) {
    let mut capped = Capped::default();
    for p in problems {
        if capped.tell(kind_plural(&p)) {
            eprintln!("{}", prepend(context, &render(wb, &p)));
        }
    }
    for why in foreign_numbers {
        if capped.tell("texts read as numbers of another locale") {
            eprintln!("{}", prepend(context, &why));
        }
    }
    let why = format!("not shown: ncsheet names the first {MAX_NOTES} problems by cell");
    for more in capped.finish(&why) {
        eprintln!("{context}{more}");
    }
}

/// What many problems of `p`'s kind are, for the count of those not shown.
pub fn kind_plural(p: &Problem) -> &'static str {
    match p.kind {
        ProblemKind::Parse(_) => "formulas that do not parse",
        ProblemKind::UnknownFunction(_) => "unknown functions",
        ProblemKind::UnknownName(_) => "unknown names",
        ProblemKind::MissingSheet(_) => "references to a missing sheet",
        ProblemKind::Cycle(_) => "circular references",
        ProblemKind::IterationCut { .. } => "iterations stopped at the limit",
        ProblemKind::Note { .. } => "error values explained",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_lines_are_indented_by_the_context() {
        assert_eq!(prepend("a.csv: ", "=1+*2\n   ^ here"), "a.csv: =1+*2\n          ^ here");
        assert_eq!(prepend("x: ", "one line"), "x: one line");
    }
}
