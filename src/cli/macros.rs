//! `ncsheet macros`: the VBA project stored in an .xlsm — its modules and their procedures,
//! or the modules exported as .bas/.cls files as the VBA editor exports them.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use ncsheet::vba::project::{read_project, ProjectModule, VbaProject};

use super::report::{Error, Result};

/// List the macros stored in a workbook (.xlsm): each module with its Subs and Functions.
///
/// With --export DIR, write every module into DIR as the VBA editor exports it (Module1.bas,
/// Sheet1.cls, …), ready for `ncsheet run WORKBOOK FILE.bas`.
#[derive(Debug, Args)]
pub struct MacrosArgs {
    /// The workbook (.xlsm)
    pub file: PathBuf,
    /// Write the modules into this folder (made if missing) instead of listing them
    #[arg(long, value_name = "DIR")]
    pub export: Option<PathBuf>,
}

pub fn run(args: MacrosArgs) -> Result<()> {
    let project = open_project(&args.file)?;
    match &args.export {
        Some(dir) => export(&project, dir),
        None => list(&project),
    }
}

/// The VBA project of a workbook file; a workbook without one is an error saying so.
pub fn open_project(file: &Path) -> Result<VbaProject> {
    let opened = ncsheet::io::open(file)?;
    let Some(bytes) = opened.layout.and_then(|l| l.vba_project) else {
        return Err(Error::User(format!("{}: the workbook holds no VBA project (xl/vbaProject.bin)", file.display())));
    };
    read_project(&bytes).map_err(|e| Error::User(format!("{}: xl/vbaProject.bin: {e}", file.display())))
}

fn list(project: &VbaProject) -> Result<()> {
    let mut out = BufWriter::new(io::stdout().lock());
    for m in &project.modules {
        writeln!(out, "{} ({})", m.name, m.kind.extension())?;
        for p in procedures(&m.source) {
            writeln!(out, "  {p}")?;
        }
    }
    out.flush()?;
    Ok(())
}

fn export(project: &VbaProject, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::User(format!("{}: cannot make the folder: {e}", dir.display())))?;
    for m in &project.modules {
        let path = dir.join(file_name(m));
        ncsheet::io::atomic::write_file(&path, |w| w.write_all(m.source.as_bytes()))
            .map_err(|e| Error::User(format!("{}: {e}", path.display())))?;
        eprintln!("ncsheet: wrote {}", path.display());
    }
    Ok(())
}

/// `Module1.bas`; a module name is a VBA identifier, so it is a safe file name.
fn file_name(m: &ProjectModule) -> String {
    let safe: String = m.name.chars().map(|c| if c.is_alphanumeric() || c == '_' { c } else { '_' }).collect();
    format!("{safe}.{}", m.kind.extension())
}

/// The procedures a module declares, as their declaration lines read (`Sub Chamfer()`,
/// `Function Tip(d As Double) As Double`): the VBA editor's procedure list.
pub fn procedures(source: &str) -> Vec<String> {
    source.lines().map(str::trim).filter(|l| declares_procedure(l)).map(|l| l.to_string()).collect()
}

fn declares_procedure(line: &str) -> bool {
    let mut words = line.split_whitespace().peekable();
    while let Some(w) = words.peek() {
        if ["public", "private", "friend", "static"].iter().any(|m| w.eq_ignore_ascii_case(m)) {
            words.next();
        } else {
            break;
        }
    }
    match words.next() {
        Some(w) if w.eq_ignore_ascii_case("sub") || w.eq_ignore_ascii_case("function") => words.next().is_some(),
        Some(w) if w.eq_ignore_ascii_case("property") => words.nth(1).is_some(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn procedures_are_the_declaration_lines() {
        let src = "Attribute VB_Name = \"M\"\r\nPublic Sub A(x As Double)\r\n  Dim s\r\nEnd Sub\r\n\
                   Private Function B() As Long\r\nEnd Function\r\nProperty Get C() As Long\r\nEnd Property\r\n' Sub D()\r\n";
        assert_eq!(
            procedures(src),
            ["Public Sub A(x As Double)", "Private Function B() As Long", "Property Get C() As Long"]
        );
    }
}
