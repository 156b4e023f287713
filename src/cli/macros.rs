//! `ncsheet macros`: the VBA project stored in an .xlsm — its modules and their procedures,
//! or the modules exported as .bas/.cls files as the VBA editor exports them.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use ncsheet::vba::project::{
    build_project_in, decode_module_file, guessed_code_page, is_readable_code_page, module_from_export, read_project,
    ModuleKind, NewModule, ProjectModule, VbaProject, READABLE_CODE_PAGES, UNKNOWN_CODE_PAGE,
};
use ncsheet::vba::project_edit::{add_modules, OnExisting, OnProtected};

use super::report::{Error, Result};

/// List the macros stored in a workbook (.xlsm): each module with its Subs and Functions.
///
/// With --export DIR, write every module into DIR as the VBA editor exports it (Module1.bas,
/// Sheet1.cls, …), ready for `ncsheet run WORKBOOK FILE.bas`. With --import FILE.bas -o
/// OUT.xlsm, add modules to the workbook's VBA project (made if it has none; every existing
/// module kept): modules are stored as source, which Excel compiles when it opens the file.
#[derive(Debug, Args)]
pub struct MacrosArgs {
    /// The workbook (.xlsm; with --import also .xlsx or .csv)
    pub file: PathBuf,
    /// Write the modules into this folder (made if missing) instead of listing them
    #[arg(long, value_name = "DIR", conflicts_with = "import")]
    pub export: Option<PathBuf>,
    /// A module to put into the workbook (.bas, or a class .cls; named by its Attribute VB_Name line, else
    /// its file name, else Module1, Module2 … as the VBA editor names a new module); give it once per module
    #[arg(long, value_name = "FILE.bas", requires = "output")]
    pub import: Vec<PathBuf>,
    /// With --import, the ANSI code page the module files are in when they are not UTF-8 (1252
    /// Western, 1251 Cyrillic, 932 Japanese, 936 Simplified Chinese, 949 Korean, 950 Traditional
    /// Chinese; readable: 874, 932, 936, 949, 950, 1250-1258, 10000, 20866, 28591-28599, 65001).
    /// A new project is written in it. Default: the workbook's own VBA project's; without one, a
    /// file with bytes past ASCII that is not UTF-8 is read in the code page its text is
    /// guessed to be in (said on stderr), or refused at its first such byte when none fits
    #[arg(long = "code-page", visible_alias = "codepage", value_name = "N", requires = "import",
          value_parser = parse_code_page)]
    pub code_page: Option<u16>,
    /// With --import, replace a standard module of the same name instead of refusing it
    #[arg(long, requires = "import")]
    pub replace: bool,
    /// With --import into a protected project (a password, locked for viewing), write it
    /// without the protection instead of refusing it
    #[arg(long, requires = "import")]
    pub unprotect: bool,
    /// The workbook to write with --import (.xlsm; never the input)
    #[arg(short, long, value_name = "OUT.xlsm")]
    pub output: Option<PathBuf>,
    /// Replace read-only or hard-linked files among those written
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
    #[command(flatten)]
    pub limits: super::limits::ReadLimitArgs,
}

pub fn run(args: MacrosArgs) -> Result<()> {
    if let Some(out) = &args.output {
        let on_existing = if args.replace { OnExisting::Replace } else { OnExisting::Refuse };
        let on_protected = if args.unprotect { OnProtected::Unprotect } else { OnProtected::Refuse };
        let policy = (on_existing, on_protected);
        return import(&args.file, &args.import, args.code_page, out, policy, args.force);
    }
    let project = open_project(&args.file)?;
    match &args.export {
        Some(dir) => export(&project, &args.file, dir, args.force),
        None => list(&project),
    }
}

/// Document modules as Excel makes them: the workbook's and each sheet's, bound to them by
/// code name (`VB_Base` names the Excel object's class).
fn document_module(name: &str, base: &str) -> NewModule {
    let source = format!(
        "Attribute VB_Name = \"{name}\"\r\nAttribute VB_Base = \"0{{{base}}}\"\r\n\
         Attribute VB_GlobalNameSpace = False\r\nAttribute VB_Creatable = False\r\n\
         Attribute VB_PredeclaredId = True\r\nAttribute VB_Exposed = True\r\n\
         Attribute VB_TemplateDerived = False\r\nAttribute VB_Customizable = True\r\n"
    );
    NewModule { name: name.to_string(), kind: ModuleKind::DocumentOrClass, source }
}

const WORKBOOK_CLASS: &str = "00020819-0000-0000-C000-000000000046";
const WORKSHEET_CLASS: &str = "00020820-0000-0000-C000-000000000046";

fn import(
    file: &Path,
    modules: &[PathBuf],
    code_page: Option<u16>,
    out: &Path,
    (on_existing, on_protected): (OnExisting, OnProtected),
    force: bool,
) -> Result<()> {
    if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case("xlsm")) {
        return Err(Error::Usage(format!("{}: a workbook with macros is saved as .xlsm", out.display())));
    }
    if modules.is_empty() {
        return Err(Error::Usage("-o goes with --import FILE.bas".into()));
    }
    let mut inputs: Vec<&Path> = vec![file];
    inputs.extend(modules.iter().map(PathBuf::as_path));
    super::refuse_overwriting_inputs(&inputs, &[out], "the workbook with macros goes to a new file")?;
    let opened = ncsheet::document::Document::open_file(file, &super::open_options(None))?.into_opened();
    let mut layout = opened.layout.unwrap_or_default();
    if let Some(old) = &layout.vba_project {
        // The files are read as the VBA editor imports into this project: in its code page,
        // unless the user names theirs. A project that does not read is refused below, naming
        // its stream.
        let code_page = code_page.or_else(|| read_project(old).ok().map(|p| p.code_page));
        let names: Vec<String> =
            read_project(old).map(|p| p.modules.into_iter().map(|m| m.name).collect()).unwrap_or_default();
        // With --replace a file named after a module is meant to replace it.
        let replaceable = if matches!(on_existing, OnExisting::Replace) { names.clone() } else { Vec::new() };
        let new = read_modules(modules, code_page, Names { taken: names, replaceable: &replaceable })?;
        let bytes = add_modules(old, &new, on_existing, on_protected)
            .map_err(|e| Error::User(format!("{}: xl/vbaProject.bin: {e}", file.display())))?;
        let ncsheet::io::Origin::Xlsx(source) = &opened.origin else {
            unreachable!("only an xlsx package holds a VBA project")
        };
        let encoded = ncsheet::io::encode_with_vba_project(source, &bytes, out)?;
        super::write_outputs(&[encoded], false, force)?;
        eprintln!("ncsheet: wrote {} with {} module(s) imported", out.display(), modules.len());
        return Ok(());
    }
    let mut project = vec![document_module("ThisWorkbook", WORKBOOK_CLASS)];
    layout.workbook_code_name = Some("ThisWorkbook".into());
    for (i, sheet) in opened.workbook.sheet_names().iter().enumerate() {
        let entry = layout.sheets.entry(sheet.clone()).or_default();
        let code_name = entry.code_name.get_or_insert_with(|| format!("Sheet{}", i + 1)).clone();
        project.push(document_module(&code_name, WORKSHEET_CLASS));
    }
    let taken = project.iter().map(|m| m.name.clone()).collect();
    project.extend(read_modules(modules, code_page, Names { taken, replaceable: &[] })?);
    let project_code_page = code_page.or_else(|| first_guessed_code_page(modules)).unwrap_or(NEW_PROJECT_CODE_PAGE);
    let bytes = build_project_in(&project, 0x4E, project_code_page).map_err(|e| {
        let hint = if code_page.is_none() { " (--code-page N writes the project in another)" } else { "" };
        Error::User(format!("{}: {e}{hint}", out.display()))
    })?;
    layout.vba_project = Some(bytes);
    let encoded = ncsheet::io::encode_save(&opened.workbook, Some(&layout), &ncsheet::io::Origin::New, out)?;
    super::write_outputs(&[encoded], false, force)?;
    eprintln!("ncsheet: wrote {} with {} module(s) imported", out.display(), modules.len());
    Ok(())
}

/// The code page of the projects ncsheet makes when the user names none and no module file
/// says one by its text (Windows-1252).
const NEW_PROJECT_CODE_PAGE: u16 = 1252;

/// The code page the first module file in an ANSI code page is guessed to be in: a new project
/// is written in it, so a Cyrillic module is stored as a Russian Excel stores it.
pub(super) fn first_guessed_code_page(modules: &[PathBuf]) -> Option<u16> {
    modules.iter().find_map(|m| std::fs::read(m).ok().and_then(|bytes| guessed_code_page(&bytes)))
}

/// `--code-page N`: a Windows code page ncsheet reads, or a usage error listing them.
pub fn parse_code_page(text: &str) -> std::result::Result<u16, String> {
    let refused = || format!("'{text}' is no code page ncsheet reads ({READABLE_CODE_PAGES})");
    let code_page: u16 = text.trim().parse().map_err(|_| refused())?;
    if is_readable_code_page(code_page) {
        Ok(code_page)
    } else {
        Err(refused())
    }
}

/// A module file's text: in the ANSI code page `code_page`, as the VBA editor exports it, or
/// Unicode (a byte-order mark, or valid UTF-8); bytes of neither are an error at their place,
/// and so is a byte past ASCII when no code page is known, with the option that names one.
pub fn read_module_text(path: &Path, code_page: Option<u16>) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::User(format!("{}: cannot read: {e}", path.display())))?;
    let guessed = if code_page.is_none() { guessed_code_page(&bytes) } else { None };
    if let Some(guess) = guessed {
        eprintln!(
            "ncsheet: {}: read in code page {guess}, guessed from its text (--code-page N names another)",
            path.display()
        );
    }
    decode_module_file(&bytes, code_page.or(guessed)).map_err(|e| {
        let hint = if e.message.starts_with(UNKNOWN_CODE_PAGE) {
            format!(": the VBA editor saves a module in the system's ANSI code page; name it with --code-page N \
                     (1252 Western, 1251 Cyrillic, 932 Japanese …; readable: {READABLE_CODE_PAGES}) or save the file as UTF-8")
        } else {
            String::new()
        };
        Error::User(format!("{}:{}:{}: {}{hint}", path.display(), e.line, e.column, e.message))
    })
}

/// The module names a file without an `Attribute VB_Name` line is named beside.
pub(super) struct Names<'n> {
    /// The project's modules: a file is not named as one of them.
    pub taken: Vec<String>,
    /// Those of them a file's name may name all the same, as the one it replaces (`--replace`).
    pub replaceable: &'n [String],
}

/// The .bas and .cls files `paths` as modules, in order, each named by its `Attribute VB_Name`
/// line, else by its file name, else as the VBA editor names an import without a name: the
/// first of Module1, Module2 … (Class1 … for a class) that neither `names` nor an earlier file
/// holds, said on stderr.
pub(super) fn read_modules(paths: &[PathBuf], code_page: Option<u16>, mut names: Names) -> Result<Vec<NewModule>> {
    let mut modules = Vec::with_capacity(paths.len());
    for path in paths {
        let module = read_module(path, code_page, &names)?;
        names.taken.push(module.name.clone());
        modules.push(module);
    }
    Ok(modules)
}

/// One module file as [`read_modules`] reads it, beside the modules `names`.
fn read_module(path: &Path, code_page: Option<u16>, names: &Names) -> Result<NewModule> {
    let text = read_module_text(path, code_page)?;
    let is_cls = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("cls"));
    let (kind, source) =
        module_from_export(&text, is_cls).map_err(|m| Error::User(format!("{}: {m}", path.display())))?;
    let attribute = source
        .lines()
        .find_map(|l| l.trim().strip_prefix("Attribute VB_Name = ").map(|n| n.trim_matches('"').to_string()));
    let name = match attribute {
        Some(name) => name,
        None => name_from_file(path, kind, names),
    };
    if !ncsheet::vba::project_edit::is_module_name(&name) {
        return Err(Error::User(format!(
            "{}: '{name}' is not a VBA module name (a letter, then letters, digits or _, at most 31)",
            path.display()
        )));
    }
    Ok(NewModule { name, kind, source })
}

/// The name of a module file without an `Attribute VB_Name` line: its file name when that is a
/// module name no other module has (or one it replaces), else the editor's next free Module*N*
/// (Class*N*).
fn name_from_file(path: &Path, kind: ModuleKind, names: &Names) -> String {
    let among = |list: &[String], name: &str| list.iter().any(|t| t.eq_ignore_ascii_case(name));
    let is_taken = |name: &str| among(&names.taken, name);
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let free = !is_taken(&stem) || among(names.replaceable, &stem);
    if ncsheet::vba::project_edit::is_module_name(&stem) && free {
        return stem;
    }
    let base = if kind == ModuleKind::Class { "Class" } else { "Module" };
    let name = (1..).map(|n| format!("{base}{n}")).find(|n| !is_taken(n)).expect("a free name");
    eprintln!(
        "ncsheet: {}: no Attribute VB_Name line, and its file name is no free module name: read as {name}, \
         as the VBA editor names such an import",
        path.display()
    );
    name
}

/// The VBA project of a workbook file; a workbook without one is an error saying so.
pub fn open_project(file: &Path) -> Result<VbaProject> {
    let doc = ncsheet::document::Document::open_file(file, &super::open_options(None))?;
    WorkbookProject { file, read: doc.vba_project() }.get().cloned()
}

/// A workbook's own VBA project as its document read it when it opened (`read`): read once,
/// for every use of it.
#[derive(Clone, Copy)]
pub struct WorkbookProject<'d> {
    /// The workbook, for messages.
    pub file: &'d Path,
    pub read: Option<std::result::Result<&'d VbaProject, &'d ncsheet::vba::ProjectError>>,
}

impl<'d> WorkbookProject<'d> {
    /// The project, or why the workbook has none.
    pub fn get(self) -> Result<&'d VbaProject> {
        match self.read {
            Some(Ok(project)) => Ok(project),
            Some(Err(e)) => Err(Error::User(format!("{}: xl/vbaProject.bin: {e}", self.file.display()))),
            None => Err(Error::User(format!(
                "{}: the workbook holds no VBA project (xl/vbaProject.bin)",
                self.file.display()
            ))),
        }
    }
}

/// The module a `run` of a workbook's own macros means, and the Sub to call in it:
/// `--sub Module1.Chamfer`, `--sub Chamfer` (the module that declares it), or no `--sub` when
/// the project has one standard module.
pub fn pick_macro<'p>(project: &'p VbaProject, sub: Option<&str>) -> Result<(&'p ProjectModule, Option<String>)> {
    let modules = || project.modules.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ");
    if let Some((module, name)) = sub.and_then(|s| s.split_once('.')) {
        let m = project.modules.iter().find(|m| m.name.eq_ignore_ascii_case(module));
        let m = m.ok_or_else(|| Error::User(format!("no module {module} in the workbook (modules: {})", modules())))?;
        return Ok((m, Some(name.to_string())));
    }
    let candidates: Vec<&ProjectModule> = match sub {
        Some(name) => project.modules.iter().filter(|m| m.declares(name)).collect(),
        None => project.modules.iter().filter(|m| m.kind == ModuleKind::Standard).collect(),
    };
    match (candidates.as_slice(), sub) {
        ([m], _) => Ok((m, sub.map(str::to_string))),
        ([], Some(name)) => Err(Error::User(format!("no module declares {name} (modules: {})", modules()))),
        ([], None) => {
            Err(Error::User("the workbook's VBA project has no standard module: name one with --sub MODULE.SUB".into()))
        }
        (_, _) => Err(Error::Usage(format!(
            "several modules could be meant ({}): name one with --sub MODULE.SUB",
            candidates.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ")
        ))),
    }
}

fn list(project: &VbaProject) -> Result<()> {
    if let Some(p) = project.protection.filter(|p| p.is_protected()) {
        eprintln!("ncsheet: the VBA project {} (its source is read all the same)", p.describe());
    }
    let mut out = BufWriter::new(io::stdout().lock());
    for m in &project.modules {
        writeln!(out, "{} ({})", m.name, m.kind.extension())?;
        for p in m.procedures() {
            writeln!(out, "  {p}")?;
        }
    }
    out.flush()?;
    Ok(())
}

/// Writes every module into `dir`: all of them, or (one refused) none.
fn export(project: &VbaProject, workbook: &Path, dir: &Path, force: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::User(format!("{}: cannot make the folder: {e}", dir.display())))?;
    let files: Vec<_> = project
        .modules
        .iter()
        .map(|m| ncsheet::io::Encoded::new(&dir.join(file_name(m)), m.source.as_bytes().to_vec()))
        .collect();
    let paths: Vec<&Path> = files.iter().map(|f| f.path.as_path()).collect();
    super::refuse_overwriting_inputs(&[workbook], &paths, "export the modules into another folder")?;
    super::write_outputs(&files, false, force)?;
    for f in &files {
        eprintln!("ncsheet: wrote {}", f.path.display());
    }
    Ok(())
}

/// `Module1.bas`; a module name is a VBA identifier, so it is a safe file name.
fn file_name(m: &ProjectModule) -> String {
    let safe: String = m.name.chars().map(|c| if c.is_alphanumeric() || c == '_' { c } else { '_' }).collect();
    format!("{safe}.{}", m.kind.extension())
}
