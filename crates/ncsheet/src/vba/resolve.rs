//! Name resolution, once, while the parser builds: a name is a variable, a procedure of the
//! module, one of VBA's functions (`VBA.*` rows of the function table), an object (`Range`,
//! `Cells`, `Nc`, …) or a sheet function, in that order. File and program access has no name
//! to resolve to: `Open`, `Kill`, `Shell`, `CreateObject` … are refused with a message that
//! says so.

use std::rc::Rc;

use pest::iterators::Pair;

use crate::eval::functions::{vba::PREFIX, Registry};
use crate::formula::ast::{Expr, ExprKind, Span as ByteSpan};
use crate::formula::limits::MAX_NESTING;
use crate::formula::parse::{strip_future_prefix, FunctionTable, ParseError, Rule};

use super::ast::*;
use super::parser::{arity_message, start, Build, Res, Signature};

/// Names that would reach files, other programs or the system. The language has none of
/// them; the parser says so instead of "not defined".
pub(super) const FORBIDDEN: &[&str] = &[
    "appactivate",
    "chdir",
    "chdrive",
    "close",
    "createobject",
    "curdir",
    "deletesetting",
    "dir",
    "environ",
    "eof",
    "exportasfixedformat",
    "filecopy",
    "filedatetime",
    "filelen",
    "followhyperlink",
    "freefile",
    "getallsettings",
    "getattr",
    "getobject",
    "getsetting",
    "kill",
    "loc",
    "lof",
    "mkdir",
    "open",
    "printout",
    "rmdir",
    "save",
    "saveas",
    "savecopyas",
    "savesetting",
    "seek",
    "sendkeys",
    "setattr",
    "shell",
    "workbooks",
];

/// `ThisWorkbook.Save` or `ActiveWorkbook.Save` without arguments: the run notes it and the
/// command saves where `--save` says (`objects.rs`), so it is not a file statement.
fn is_workbook_save(path: &Path, i: usize) -> bool {
    let first = lower_bare(&path.links[0].name);
    i == 1
        && !path.with
        && path.links.len() == 2
        && path.links[0].args.is_none()
        && path.links[1].args.is_none()
        && matches!(first.as_str(), "thisworkbook" | "activeworkbook")
}

pub(super) fn refusal(name: &str) -> String {
    format!(
        "{name}: a macro cannot touch files or run programs (the language has no Kill, Shell, \
         CreateObject, …; Open, Print # and FileSystemObject reach only a folder given with `ncsheet run \
         --out-dir DIR`); read and write cells, and let `ncsheet run -o FILE` write the program"
    )
}

/// Objects a path can start from (lower case).
const OBJECTS: &[&str] = &[
    "activecell",
    "activesheet",
    "activewindow",
    "activeworkbook",
    "application",
    "callbyname",
    "cells",
    "columns",
    "debug",
    "erl",
    "err",
    "evaluate",
    "inputbox",
    "intersect",
    "msgbox",
    "nc",
    "range",
    "rows",
    "selection",
    "sheets",
    "thisworkbook",
    "union",
    "windows",
    "worksheetfunction",
    "worksheets",
];

/// Objects that are called like procedures: `MsgBox "done"` as a statement.
pub(super) fn is_object(lower: &str) -> bool {
    OBJECTS.contains(&lower)
}

/// The number the constant `lower` names (`"xlwhole"` is 1), for the code that reads a
/// member's arguments by it (`replace.rs`): [`constant`]'s table is the one place that knows
/// Excel's constants. A name outside it is a mistake in ncsheet's code, not in a macro.
pub(super) fn constant_number(lower: &str) -> f64 {
    match constant(lower) {
        Some(ExprKind::Number(n)) => n,
        _ => unreachable!("{lower} is not a number in the table of VBA's and Excel's constants"),
    }
}

/// VBA's constants, as literals.
fn constant(lower: &str) -> Option<ExprKind> {
    let text = |s: &str| Some(ExprKind::Text(s.into()));
    let number = |n: f64| Some(ExprKind::Number(n));
    match lower {
        "vbcrlf" => text("\r\n"),
        // "Miscellaneous constants": vbNewLine is Chr(13) + Chr(10) on Windows.
        "vbnewline" => text("\r\n"),
        "vblf" => text("\n"),
        "vbcr" => text("\r"),
        "vbtab" => text("\t"),
        "vbnullstring" => text(""),
        // The rest of "Miscellaneous constants" ([MS-VBAL] 6.1.2.2 "Constants Module").
        "vbnullchar" => text("\0"),
        "vbback" => text("\u{8}"),
        "vbverticaltab" => text("\u{b}"),
        "vbformfeed" => text("\u{c}"),
        // "Raise method": an object's own errors are numbered from vbObjectError (&H80040000).
        "vbobjecterror" => number(-2147221504.0),
        "vbokonly" => number(0.0),
        "vbok" => number(1.0),
        "vbcancel" => number(2.0),
        "vbyesno" => number(4.0),
        "vbyes" => number(6.0),
        "vbno" => number(7.0),
        "vbcritical" => number(16.0),
        "vbquestion" => number(32.0),
        "vbexclamation" => number(48.0),
        "vbinformation" => number(64.0),
        // The rest of "MsgBox function"'s buttons and return values.
        "vbokcancel" => number(1.0),
        "vbabortretryignore" => number(2.0),
        "vbyesnocancel" => number(3.0),
        "vbretrycancel" => number(5.0),
        "vbabort" => number(3.0),
        "vbretry" => number(4.0),
        "vbignore" => number(5.0),
        "vbdefaultbutton1" | "vbapplicationmodal" => number(0.0),
        "vbdefaultbutton2" => number(256.0),
        "vbdefaultbutton3" => number(512.0),
        "vbdefaultbutton4" => number(768.0),
        "vbsystemmodal" => number(4096.0),
        "vbmsgboxhelpbutton" => number(16384.0),
        "vbmsgboxsetforeground" => number(65536.0),
        "vbmsgboxright" => number(524288.0),
        "vbmsgboxrtlreading" => number(1048576.0),
        // The VarType constants the table below leaves out ("VarType constants").
        "vbdataobject" => number(13.0),
        "vbdecimal" => number(14.0),
        // Compared in Microsoft's spelling, whose lower case the architecture check would
        // take for the serialisation crate's name.
        name if name.eq_ignore_ascii_case("vbUserDefinedType") => number(36.0),
        // "Color constants": RGB values, red in the low byte.
        "vbblack" => number(0.0),
        "vbred" => number(255.0),
        "vbgreen" => number(65280.0),
        "vbyellow" => number(65535.0),
        "vbblue" => number(16711680.0),
        "vbmagenta" => number(16711935.0),
        "vbcyan" => number(16776960.0),
        "vbwhite" => number(16777215.0),
        // "Comparison constants", "StrConv" conversions, "Tristate" and "VarType constants".
        "vbusecompareoption" => number(-1.0),
        "vbbinarycompare" => number(0.0),
        "vbtextcompare" => number(1.0),
        // The Scripting library's CompareMethod ("CompareMode property": binary, text, database),
        // which `d.CompareMode = TextCompare` names without the vb prefix.
        "binarycompare" => number(0.0),
        "textcompare" => number(1.0),
        "databasecompare" => number(2.0),
        "vbuppercase" => number(1.0),
        "vblowercase" => number(2.0),
        "vbpropercase" => number(3.0),
        "vbunicode" => number(64.0),
        "vbfromunicode" => number(128.0),
        "vbtrue" => number(-1.0),
        "vbfalse" => number(0.0),
        "vbusedefault" => number(-2.0),
        // "Date format constants" (FormatDateTime's NamedFormat).
        "vbgeneraldate" => number(0.0),
        "vblongdate" => number(1.0),
        "vbshortdate" => number(2.0),
        "vblongtime" => number(3.0),
        "vbshorttime" => number(4.0),
        "vbempty" => number(0.0),
        "vbnull" => number(1.0),
        "vbinteger" => number(2.0),
        "vblong" => number(3.0),
        "vbsingle" => number(4.0),
        "vbdouble" => number(5.0),
        "vbcurrency" => number(6.0),
        "vbdate" => number(7.0),
        "vbstring" => number(8.0),
        "vbobject" => number(9.0),
        "vberror" => number(10.0),
        "vbboolean" => number(11.0),
        "vbvariant" => number(12.0),
        "vbbyte" => number(17.0),
        "vblonglong" => number(20.0),
        "vbarray" => number(8192.0),
        // "CallByName function": VbCallType.
        "vbmethod" => number(1.0),
        "vbget" => number(2.0),
        "vblet" => number(4.0),
        "vbset" => number(8.0),
        // "DateDiff function": its firstdayofweek and firstweekofyear constants (vbUseSystem
        // is both's 0), for DateDiff, DatePart, Weekday and WeekdayName.
        "vbusesystem" | "vbusesystemdayofweek" => number(0.0),
        "vbsunday" | "vbfirstjan1" => number(1.0),
        "vbmonday" | "vbfirstfourdays" => number(2.0),
        "vbtuesday" | "vbfirstfullweek" => number(3.0),
        "vbwednesday" => number(4.0),
        "vbthursday" => number(5.0),
        "vbfriday" => number(6.0),
        "vbsaturday" => number(7.0),
        // Excel's XlCVError values, for CVErr.
        "xlerrnull" => number(2000.0),
        "xlerrdiv0" => number(2007.0),
        "xlerrvalue" => number(2015.0),
        "xlerrref" => number(2023.0),
        "xlerrname" => number(2029.0),
        "xlerrnum" => number(2036.0),
        "xlerrna" => number(2042.0),
        // Excel's XlDirection, XlPasteType, XlSheetVisibility and XlReferenceStyle values.
        // "XlSortOrder", "XlYesNoGuess", "XlSortOrientation", "XlSortOn", "XlSortDataOption"
        // and "XlSortMethod" enumerations (`sort.rs`).
        "xlascending" => number(1.0),
        "xldescending" => number(2.0),
        "xlguess" => number(0.0),
        "xlyes" => number(1.0),
        "xlno" => number(2.0),
        "xltoptobottom" | "xlsortcolumns" => number(1.0),
        "xllefttoright" | "xlsortrows" => number(2.0),
        "xlsortonvalues" | "xlsortnormal" => number(0.0),
        "xlsorttextasnumbers" | "xlpinyin" => number(1.0),
        "xlstroke" => number(2.0),
        // "XlSortOn enumeration": the colours and icons SortFields.Add refuses to sort on.
        "xlsortoncellcolor" => number(1.0),
        "xlsortonfontcolor" => number(2.0),
        "xlsortonicon" => number(3.0),
        // "XlCalculation" (Application.Calculation, which a macro without a window ignores).
        "xlcalculationmanual" => number(-4135.0),
        "xlcalculationautomatic" => number(-4105.0),
        "xlcalculationsemiautomatic" => number(2.0),
        // "Constants enumeration": no color, Excel's automatic color (ColorIndex).
        "xlnone" | "xlcolorindexnone" => number(-4142.0),
        "xlautomatic" | "xlcolorindexautomatic" => number(-4105.0),
        // "XlUnderlineStyle enumeration", for Font.Underline.
        "xlunderlinestylenone" => number(-4142.0),
        "xlunderlinestylesingle" | "xlsingle" => number(2.0),
        "xlunderlinestyledouble" | "xldouble" => number(-4119.0),
        "xlunderlinestylesingleaccounting" | "xlsingleaccounting" => number(4.0),
        "xlunderlinestyledoubleaccounting" | "xldoubleaccounting" => number(5.0),
        "xlup" => number(-4162.0),
        "xldown" => number(-4121.0),
        "xltoleft" => number(-4159.0),
        "xltoright" => number(-4161.0),
        // XlDeleteShiftDirection and XlInsertShiftDirection, for Range.Delete and Insert.
        "xlshiftup" => number(-4162.0),
        "xlshifttoleft" => number(-4159.0),
        "xlshiftdown" => number(-4121.0),
        "xlshifttoright" => number(-4161.0),
        // "XlListObjectSourceType enumeration", for ListObjects.Add.
        "xlsrcexternal" => number(0.0),
        "xlsrcrange" => number(1.0),
        "xlsrcxml" => number(2.0),
        "xlsrcquery" => number(3.0),
        "xlsrcmodel" => number(4.0),
        // "XlPasteType enumeration", for PasteSpecial's Paste.
        "xlpasteall" => number(-4104.0),
        "xlpasteformulas" => number(-4123.0),
        "xlpastevalues" => number(-4163.0),
        "xlpasteallexceptborders" => number(7.0),
        "xlpastecolumnwidths" => number(8.0),
        "xlpastecomments" => number(-4144.0),
        "xlpasteformats" => number(-4122.0),
        "xlpasteformulasandnumberformats" => number(11.0),
        "xlpastevaluesandnumberformats" => number(12.0),
        "xlpasteallusingsourcetheme" => number(13.0),
        "xlpasteallmergingconditionalformats" => number(14.0),
        "xlpastevalidation" => number(6.0),
        // "XlPasteSpecialOperation enumeration", for PasteSpecial's Operation.
        "xlpastespecialoperationnone" => number(-4142.0),
        "xlpastespecialoperationadd" => number(2.0),
        "xlpastespecialoperationsubtract" => number(3.0),
        "xlpastespecialoperationmultiply" => number(4.0),
        "xlpastespecialoperationdivide" => number(5.0),
        // "XlAutoFillType enumeration", for Range.AutoFill's Type.
        "xlfilldefault" => number(0.0),
        "xlfillcopy" => number(1.0),
        "xlfillseries" => number(2.0),
        "xlfillformats" => number(3.0),
        "xlfillvalues" => number(4.0),
        "xlfilldays" => number(5.0),
        "xlfillweekdays" => number(6.0),
        "xlfillmonths" => number(7.0),
        "xlfillyears" => number(8.0),
        "xllineartrend" => number(9.0),
        "xlgrowthtrend" => number(10.0),
        "xlflashfill" => number(11.0),
        // "XlInsertFormatOrigin enumeration", for Range.Insert's CopyOrigin.
        "xlformatfromleftorabove" => number(0.0),
        "xlformatfromrightorbelow" => number(1.0),
        // "XlPlatform enumeration", for Workbooks.OpenText's Origin.
        "xlmacintosh" => number(1.0),
        "xlwindows" => number(2.0),
        "xlmsdos" => number(3.0),
        // The "Constants enumeration" names the macro recorder writes for TextToColumns's and
        // OpenText's TextQualifier (`TextQualifier:=xlDoubleQuote`) and Alignment's ReadingOrder.
        "xldoublequote" => number(1.0),
        "xlsinglequote" => number(2.0),
        "xlcontext" => number(-5002.0),
        "xlltr" => number(-5003.0),
        "xlrtl" => number(-5004.0),
        "xlsheetvisible" => number(-1.0),
        "xlsheethidden" => number(0.0),
        "xlsheetveryhidden" => number(2.0),
        // Scripting's IOMode and Tristate values, for OpenTextFile (`files.rs`).
        "forreading" => number(1.0),
        "forwriting" => number(2.0),
        "forappending" => number(8.0),
        "tristatetrue" => number(-1.0),
        "tristatefalse" => number(0.0),
        "tristateusedefault" => number(-2.0),
        "xla1" => number(1.0),
        "xlr1c1" => number(-4150.0),
        // Excel's XlHAlign and XlVAlign values ("XlHAlign enumeration", "XlVAlign
        // enumeration"), with the short names of Excel's Constants that macros write.
        "xlleft" | "xlhalignleft" => number(-4131.0),
        "xlcenter" | "xlhaligncenter" | "xlvaligncenter" => number(-4108.0),
        "xlright" | "xlhalignright" => number(-4152.0),
        "xlgeneral" | "xlhaligngeneral" => number(1.0),
        "xlfill" | "xlhalignfill" => number(5.0),
        "xljustify" | "xlhalignjustify" | "xlvalignjustify" => number(-4130.0),
        "xldistributed" | "xlhaligndistributed" | "xlvaligndistributed" => number(-4117.0),
        "xlcenteracrossselection" | "xlhaligncenteracrossselection" => number(7.0),
        "xltop" | "xlvaligntop" => number(-4160.0),
        "xlbottom" | "xlvalignbottom" => number(-4107.0),
        // Find and Replace's "XlLookAt", "XlSearchOrder", "XlSearchDirection", "XlFindLookIn"
        // enumerations and Replace's FormulaVersion ("XlReplaceFormula2"), `replace.rs`.
        "xlwhole" => number(1.0),
        "xlpart" => number(2.0),
        "xlbyrows" | "xlnext" => number(1.0),
        "xlbycolumns" | "xlprevious" => number(2.0),
        "xlformulas" => number(-4123.0),
        "xlvalues" => number(-4163.0),
        "xlcomments" => number(-4144.0),
        "xlreplaceformula" => number(0.0),
        "xlreplaceformula2" => number(1.0),
        // "XlSheetType enumeration", for Sheets.Add's Type.
        "xlworksheet" => number(-4167.0),
        "xlchart" => number(-4109.0),
        "xlexcel4macrosheet" => number(3.0),
        "xlexcel4intlmacrosheet" => number(4.0),
        // "XlTextParsingType" and "XlTextQualifier enumeration", for Range.TextToColumns.
        "xldelimited" => number(1.0),
        "xlfixedwidth" => number(2.0),
        "xltextqualifierdoublequote" => number(1.0),
        "xltextqualifiersinglequote" => number(2.0),
        "xltextqualifiernone" => number(-4142.0),
        // "XlCellType enumeration", for Range.SpecialCells.
        "xlcelltypelastcell" => number(11.0),
        "xlcelltypeconstants" => number(2.0),
        "xlcelltypeformulas" => number(-4123.0),
        "xlcelltypeblanks" => number(4.0),
        "xlcelltypevisible" => number(12.0),
        "xlcelltypecomments" => number(-4144.0),
        "xlcelltypeallformatconditions" => number(-4172.0),
        "xlcelltypesameformatconditions" => number(-4173.0),
        "xlcelltypeallvalidation" => number(-4174.0),
        "xlcelltypesamevalidation" => number(-4175.0),
        // "XlFindLookIn enumeration": xlFormulas, xlValues and xlComments above.
        "xlcommentsthreaded" => number(-4184.0),
        // "XlBordersIndex", "XlLineStyle", "XlBorderWeight" and "XlPattern" enumerations: what
        // recorded macros pass to Borders, harmless members ncsheet does not keep
        // (`unmodelled.rs`).
        "xldiagonaldown" => number(5.0),
        "xldiagonalup" => number(6.0),
        "xledgeleft" => number(7.0),
        "xledgetop" => number(8.0),
        "xledgebottom" => number(9.0),
        "xledgeright" => number(10.0),
        "xlinsidevertical" => number(11.0),
        "xlinsidehorizontal" => number(12.0),
        "xlcontinuous" | "xlhairline" | "xlsolid" | "xlpatternsolid" => number(1.0),
        "xldash" => number(-4115.0),
        "xldashdot" => number(4.0),
        "xldashdotdot" => number(5.0),
        "xldot" => number(-4118.0),
        "xlslantdashdot" => number(13.0),
        "xllinestylenone" | "xlpatternnone" => number(-4142.0),
        "xlthin" => number(2.0),
        "xlmedium" => number(-4138.0),
        "xlthick" => number(4.0),
        _ => None,
    }
}

/// VBA's functions that read a variable's declaration, not only its value.
fn inspection(lower: &str) -> Option<Inspect> {
    match lower {
        "vartype" => Some(Inspect::VarType),
        "ismissing" => Some(Inspect::IsMissing),
        "typename" => Some(Inspect::TypeName),
        "isobject" => Some(Inspect::IsObject),
        "isdate" => Some(Inspect::IsDate),
        "isempty" => Some(Inspect::IsEmpty),
        _ => None,
    }
}

/// `Len(x)` / `LenB(x)` of a variable or an array's item (`bytes` for LenB), whose answer is
/// its storage size when it is declared of a fixed-size type or a Type ("Len function":
/// "the number of bytes required to store a variable"); any other argument is only text.
fn storage_size_asked(lower: &str, args: &[Arg]) -> Option<bool> {
    let bytes = match lower {
        "len" => false,
        "lenb" => true,
        _ => return None,
    };
    let [arg] = args else { return None };
    let variable = matches!(arg.value.kind, ExprKind::Name(_) | ExprKind::Host(_));
    (arg.name.is_none() && variable).then_some(bytes)
}

/// `Module2.Rate` as the interpreter names a module-level variable qualified by its module:
/// no variable's own name has a dot, so it stands for that module's variable alone.
fn qualified_name(module: &str, variable: &Link) -> Rc<str> {
    format!("{module}.{}", lower_bare(&variable.name)).into()
}

/// `Error` without an argument, read as `Err.Description`: "Error function", "If errornumber
/// is omitted, the message corresponding to the most recent run-time error is returned" ("" when
/// there is none, as Err.Description is).
fn current_error_message(error: Link) -> Path {
    let span = error.span;
    let link = |name: &str| Link { name: Rc::from(name), args: None, span };
    Path { with: false, links: vec![link("Err"), link("Description")], span }
}

pub(super) fn lower_bare(name: &str) -> String {
    name.trim_end_matches('$').to_ascii_lowercase()
}

impl Build<'_> {
    /// An object of the language or of this run (a sheet's code name, `Me`).
    pub(super) fn is_object(&self, lower: &str) -> bool {
        is_object(lower) || self.objects.iter().any(|o| o == lower) || (lower == "me" && self.in_class())
    }

    /// The procedure being built is a class module's: `Me` is the object it runs for.
    fn in_class(&self) -> bool {
        self.parts.get(self.current_part.get()).is_some_and(|p| p.class)
    }

    pub(super) fn is_var(&self, name: &str) -> bool {
        let lower = name.to_ascii_lowercase();
        self.scope.borrow().vars.contains(&lower) || self.is_visible_global(&lower)
    }

    /// A module-level name the module being built sees: its own (Private, Dim, Const or
    /// Public) or one another module declares Public ("Understanding scope and visibility").
    fn is_visible_global(&self, lower: &str) -> bool {
        let part = self.current_part.get();
        self.globals.borrow().get(lower).is_some_and(|owners| owners.iter().any(|o| o.part == part || o.public))
    }

    /// The other modules whose Public module-level `lower` a procedure of the module being
    /// built reaches by the simple name: none when its procedure or its module declares the
    /// name itself ([MS-VBAL] 5.6.10: procedure, then module, then the project's other modules).
    pub(super) fn public_owners(&self, lower: &str) -> Vec<usize> {
        let part = self.current_part.get();
        if self.scope.borrow().vars.contains(lower) {
            return Vec::new();
        }
        let globals = self.globals.borrow();
        let Some(owners) = globals.get(lower) else { return Vec::new() };
        if owners.iter().any(|o| o.part == part) {
            return Vec::new();
        }
        owners.iter().filter(|o| o.public && self.standard(o.part)).map(|o| o.part).collect()
    }

    /// VBA's compile error "Ambiguous name detected" ([MS-VBAL] 5.6.10: a simple name that
    /// matches Public variables or constants of more than one other module): refused where
    /// it is used, naming the modules; `Module2.Rate`, qualified, is not ambiguous.
    pub(super) fn unambiguous(&self, pair_offset: usize, name: &str) -> Res<()> {
        let owners = self.public_owners(&lower_bare(name));
        if owners.len() < 2 {
            return Ok(());
        }
        let modules: Vec<&str> = owners.iter().filter_map(|&p| self.parts.get(p)).map(|p| &*p.name).collect();
        Err(ParseError {
            offset: pair_offset,
            message: format!(
                "Ambiguous name detected: {name} is Public in {}; qualify it ({}.{name})",
                modules.join(" and "),
                modules[0]
            ),
        })
    }

    pub(super) fn declare(&self, name: &str) {
        let lower = name.to_ascii_lowercase();
        let mut scope = self.scope.borrow_mut();
        scope.vars.insert(lower);
    }

    /// A procedure by name as the module being built sees it: its own first (a Property
    /// Get before its Let or Set), else a public one of another standard module of the
    /// project (a class module's procedures are members of its objects).
    pub(super) fn proc_index(&self, name: &str) -> Option<usize> {
        // `Greet$(…)` calls `Function Greet$`, declared as Greet ([MS-VBAL] 3.3.5.3).
        let same_name = self.proc_names.get(&lower_bare(name))?;
        let part = self.current_part.get();
        let own = |i: &usize| self.procs[*i].part == part;
        let readable = |i: &usize| matches!(self.procs[*i].property, None | Some(PropertyKind::Get));
        let mine = same_name.iter().copied().filter(own);
        let own = mine.clone().find(readable).or_else(|| mine.clone().next());
        let class_part = |i: usize| self.parts.get(self.procs[i].part).is_some_and(|p| p.class);
        own.or_else(|| same_name.iter().copied().find(|&i| self.procs[i].public && !class_part(i)))
    }

    /// `Module2.Rate`: a module-level variable or constant (an Enum member too) that the
    /// standard module named `module` declares, Public or the module being built's own.
    fn module_global(&self, module: &str, name: &str) -> bool {
        let Some(part) = self.parts.iter().position(|p| p.name.eq_ignore_ascii_case(module) && !p.class) else {
            return false;
        };
        let own = part == self.current_part.get();
        let globals = self.globals.borrow();
        globals.get(&lower_bare(name)).is_some_and(|owners| owners.iter().any(|o| o.part == part && (o.public || own)))
    }

    /// `Module2.Rate` (a module-level name of `module`, [`Build::module_global`]), which the
    /// interpreter looks for in that module's table only ([MS-VBAL] 5.6.12: the member of the
    /// module named, whatever a procedure's local or another module of that name holds;
    /// "Ambiguous name detected": `MyModule.MyID` is the module's, not the local `MyID`).
    fn qualified_variable(
        &self,
        pair: &Pair<Rule>,
        variable: Link,
        module: &str,
        statement: bool,
        end: usize,
    ) -> Res<Expr> {
        let name = qualified_name(module, &variable);
        let at = start(pair);
        if statement {
            return Err(self.error_at(pair, format!("{}: a statement cannot be just a value", pair.as_str().trim())));
        }
        Ok(match variable.args {
            Some(args) if !args.is_empty() => {
                let index = args.iter().map(|a| a.value.clone()).collect();
                self.node(Node::Element { var: name, index, span: self.span(at) }, at, end)
            }
            _ => Expr::new(ExprKind::Name(name), ByteSpan { start: at as u32, end: end as u32 }),
        })
    }

    /// `Module2.Rate = v`, `Module2.Table(i) = v`: the variable (or its item) of the module
    /// named, as [`Build::qualified_variable`] reads it; `None` when the path is no such name.
    pub(super) fn qualified_target(&self, path: &Path) -> Option<Target> {
        let [module, variable] = path.links.as_slice() else { return None };
        let unshadowed = !path.with
            && module.args.is_none()
            && !self.is_var(&module.name)
            && !self.is_object(&lower_bare(&module.name));
        if !unshadowed || !self.module_global(&module.name, &variable.name) {
            return None;
        }
        let name = qualified_name(&module.name, variable);
        Some(match &variable.args {
            Some(args) if !args.is_empty() => Target::Element(name, args.iter().map(|a| a.value.clone()).collect()),
            _ => Target::Var(name),
        })
    }

    /// `Module2.Helper`: a procedure of the module named, if it is one of the project's
    /// and the procedure is public there (or that module is the one being built).
    fn module_proc(&self, module: &str, name: &str) -> Option<usize> {
        let part = self.parts.iter().position(|p| p.name.eq_ignore_ascii_case(module) && !p.class)?;
        let same_name = self.proc_names.get(&name.to_ascii_lowercase())?;
        same_name
            .iter()
            .copied()
            .find(|&i| self.procs[i].part == part && (self.procs[i].public || part == self.current_part.get()))
    }

    /// A variable used where none is declared: an error under Option Explicit, else declared.
    pub(super) fn implicit(&self, pair_offset: usize, name: &str) -> Res<()> {
        self.unambiguous(pair_offset, name)?;
        if self.is_var(name) {
            return Ok(());
        }
        if self.explicit() {
            return Err(ParseError {
                offset: pair_offset,
                message: format!("variable {name} is not declared (Option Explicit): add Dim {name}"),
            });
        }
        // VBA gives an undeclared variable its module's Def type (`deftype.rs`).
        if let Some(ty) = self.implicit_ty(name) {
            self.declare_implicit_var(pair_offset, name, ty);
        }
        self.declare(name);
        Ok(())
    }

    /// `s$` names the variable `s`: a type character is no part of the name ([MS-VBAL]
    /// 3.3.5.3, "Type characters"), so `s$` and `s` are one variable. The bare name when it
    /// is a variable already; `None` for any other name (`Left$` stays the function).
    pub(super) fn declared_without_mark(&self, name: &str) -> Option<Rc<str>> {
        name.strip_suffix('$').filter(|bare| self.is_var(bare)).map(Rc::from)
    }

    /// A variable used without a declaration, as [`Build::implicit`] declares it; `s$` is the
    /// String variable `s` (its type character gives its type, "Type characters"). The name
    /// the variable goes by.
    pub(super) fn implicit_named(&self, pair_offset: usize, name: &Rc<str>) -> Res<Rc<str>> {
        let Some(bare) = name.strip_suffix('$').filter(|b| !b.is_empty() && !b.ends_with('$')) else {
            self.implicit(pair_offset, name)?;
            return Ok(name.clone());
        };
        if !self.is_var(bare) {
            if self.explicit() {
                // The message Option Explicit gives any undeclared name.
                self.implicit(pair_offset, bare)?;
            }
            self.unambiguous(pair_offset, bare)?;
            self.declare_implicit_var(pair_offset, bare, super::parser::ty_named("string"));
            self.declare(bare);
        }
        Ok(Rc::from(bare))
    }

    pub(super) fn is_own_function(&self, name: &str) -> bool {
        self.scope.borrow().function.as_deref().is_some_and(|f| f.eq_ignore_ascii_case(name))
    }

    pub(super) fn path_expr(&self, pair: Pair<Rule>, statement: bool) -> Res<Expr> {
        if let Some(chain) = self.indexed_inside(&pair, statement)? {
            return Ok(chain);
        }
        let (path, indexes) = self.path_indexed(&pair)?;
        self.path_value(&pair, path, indexes, statement)
    }

    /// A path indexed at most at its end, from its parts built once by [`Build::path_indexed`].
    pub(super) fn path_value(
        &self,
        pair: &Pair<Rule>,
        path: Path,
        indexes: Vec<Vec<Arg>>,
        statement: bool,
    ) -> Res<Expr> {
        let end = pair.as_span().end();
        if indexes.is_empty() {
            return self.resolve(pair, path, statement, end);
        }
        if statement {
            return Err(self.error_at(pair, format!("{}: a statement cannot be just a value", pair.as_str().trim())));
        }
        let e = self.resolve(pair, path, false, end)?;
        self.indexed(pair, e, indexes, end)
    }

    /// `d(k)(i)(j)`: each index list applied to what the one before gives. The row of a
    /// pair may be left out (`Range("B2:D6")(, 3)`, the range's `Item(, 3)`): what it means
    /// is decided by what is indexed when the macro runs (a Range's first row; for an array
    /// `Interp::index` refuses it).
    pub(super) fn indexed(&self, pair: &Pair<Rule>, mut e: Expr, indexes: Vec<Vec<Arg>>, end: usize) -> Res<Expr> {
        // The lists as written: `e` holds the first (`a(0)` of `a(0)(0)…`).
        self.within_chain_limit(pair, indexes.len() + 1)?;
        let at = start(pair);
        for args in indexes {
            let row_left_out = |k: usize| k == 0 && args.len() == 2;
            let left_out = |(k, a): (usize, &Arg)| a.value.kind == ExprKind::Missing && !row_left_out(k);
            if args.iter().any(|a| a.name.is_some()) || args.iter().enumerate().any(left_out) {
                return Err(self.error_at(pair, "an index is a value: no name:= and none left out but a row's"));
            }
            let index = args.into_iter().map(|a| a.value).collect();
            e = self.node(Node::Index { base: e, index, span: self.span(at) }, at, end);
        }
        Ok(e)
    }

    /// A path with an index list inside it, not only at its end (`A(1)(2).Count`,
    /// `d("k")(0).Name`, `c(1)(2).Items(3)(4).Value`): the path up to the first such list
    /// resolved as any path and indexed, then each stretch of members applied to what the
    /// expression before gives ([`Node::Members`]) and indexed in turn. `None` for a path
    /// with no index list before its end.
    pub(super) fn indexed_inside(&self, pair: &Pair<Rule>, statement: bool) -> Res<Option<Expr>> {
        // Decided from the syntax before any argument is built: the caller builds the path
        // again when this gives `None`, and building it twice at each level of nested calls
        // doubled the work per level (`Abs(Abs(…))` 40 deep did not finish).
        if !has_index_inside(pair) {
            return Ok(None);
        }
        let mut with = false;
        let mut parts = Vec::new();
        for part in pair.clone().into_inner() {
            match part.as_rule() {
                Rule::with_dot => with = true,
                _ => {
                    let end = part.as_span().end();
                    let (link, indexes) = self.link_indexed(part)?;
                    parts.push((link, indexes, end));
                }
            }
        }
        self.chain(pair, with, parts, statement)
    }

    /// [`Build::indexed_inside`] of a path's links, each with the index lists after it and
    /// where it ends in the source.
    pub(super) fn chain(
        &self,
        pair: &Pair<Rule>,
        with: bool,
        parts: Vec<(Link, Vec<Vec<Arg>>, usize)>,
        statement: bool,
    ) -> Res<Option<Expr>> {
        let inside = parts.iter().position(|(_, indexes, _)| !indexes.is_empty());
        if inside.is_none_or(|i| i + 1 >= parts.len()) {
            return Ok(None);
        }
        // Each stretch indexed nests the tree once more, and once for each of its lists.
        let levels = parts.iter().filter(|(_, indexes, _)| !indexes.is_empty()).map(|(_, ix, _)| ix.len() + 1).sum();
        self.within_chain_limit(pair, levels)?;
        let span = self.span(start(pair));
        let mut e: Option<Expr> = None;
        let mut links = Vec::new();
        let mut ends_indexed = false;
        for (link, indexes, end) in parts {
            links.push(link);
            ends_indexed = !indexes.is_empty();
            if !ends_indexed {
                continue;
            }
            let path = Path { with: with && e.is_none(), links: std::mem::take(&mut links), span };
            let base = self.members(pair, e.take(), path, end)?;
            e = Some(self.indexed(pair, base, indexes, end)?);
        }
        let end = pair.as_span().end();
        let e = match (e, links.is_empty()) {
            (Some(e), true) => e,
            (base, _) => self.members(pair, base, Path { with: false, links, span }, end)?,
        };
        if statement && ends_indexed {
            return Err(self.error_at(pair, format!("{}: a statement cannot be just a value", pair.as_str().trim())));
        }
        Ok(Some(e))
    }

    /// Refuses a path whose index lists, applied each to what the one before gives
    /// (`o(1)(1)(1)…`, `a(0)(0).b(0)(0)…`), nest its tree `levels` deep past [`MAX_NESTING`]:
    /// each level is a native stack frame when the line runs, and 5,000 of them closed one
    /// after another (so the bracket scan, which counts only those open at once, let them
    /// through) overflowed the stack.
    fn within_chain_limit(&self, pair: &Pair<Rule>, levels: usize) -> Res<()> {
        if levels <= MAX_NESTING {
            return Ok(());
        }
        Err(self.error_at(
            pair,
            format!(
                "{levels} index lists applied one after another, more than {MAX_NESTING} \
                 (ncsheet's limit on nesting, docs/limits.md)"
            ),
        ))
    }

    /// The members `path` of what `base` gives; with no base, the path resolved as any path.
    pub(super) fn members(&self, pair: &Pair<Rule>, base: Option<Expr>, path: Path, end: usize) -> Res<Expr> {
        let Some(base) = base else { return self.resolve(pair, path, false, end) };
        self.check_path(pair, &path)?;
        Ok(self.node(Node::Members { base, path }, start(pair), end))
    }

    /// What a With block's object is (`With Application.WorksheetFunction`), as its text says.
    pub(super) fn with_subject(&self, object: &str) -> WithSubject {
        let words: String = object.split(|c: char| c.is_whitespace() || c == '_').collect();
        let lower = words.to_ascii_lowercase();
        let root = lower.split('.').next().unwrap_or_default();
        if self.is_var(root) {
            return WithSubject::Other;
        }
        match lower.as_str() {
            "worksheetfunction" | "application.worksheetfunction" | "excel.worksheetfunction" => {
                WithSubject::SheetFunctions
            }
            "application" | "excel.application" => WithSubject::Application,
            _ => WithSubject::Other,
        }
    }

    /// `.Match(…)` in `With Application.WorksheetFunction` (or `.Max(…)` in `With
    /// Application`): the worksheet function's call, as the path written out in full is.
    /// `None` (and `path` as it was) for any other member.
    fn with_member_call(&self, pair: &Pair<Rule>, path: Path) -> Res<Result<Expr, Path>> {
        let qualifier = match self.with_subjects.borrow().last() {
            Some(WithSubject::SheetFunctions) => "WorksheetFunction",
            Some(WithSubject::Application) => "Application",
            _ => return Ok(Err(path)),
        };
        if path.links.len() != 1 {
            return Ok(Err(path));
        }
        let span = path.span;
        let object = Link { name: qualifier.into(), args: None, span };
        let mut full = Path { with: false, links: std::iter::once(object).chain(path.links).collect(), span };
        match self.qualified_call(pair, &mut full)? {
            Some(call) => Ok(Ok(call)),
            None => Ok(Err(Path { with: true, links: full.links.into_iter().skip(1).collect(), span })),
        }
    }

    /// Decides what a path names (see the module doc for the order).
    pub(super) fn resolve(&self, pair: &Pair<Rule>, path: Path, statement: bool, end: usize) -> Res<Expr> {
        let at = start(pair);
        let mut path = match path.with {
            true => match self.with_member_call(pair, path)? {
                Ok(call) => return Ok(call),
                Err(path) => path,
            },
            false => path,
        };
        if path.with {
            self.check_path(pair, &path)?;
            return Ok(self.node(Node::Path(path), at, end));
        }
        if path.links.len() == 1 {
            let link = path.links.pop().expect("one link");
            return self.single(pair, link, statement, end);
        }
        self.name_vba_library_module(&mut path);
        if let Some(kind) = self.qualified_constant(&path) {
            return Ok(Expr::new(kind, ByteSpan { start: at as u32, end: end as u32 }));
        }
        if self.is_vba_intrinsic(&path) {
            let link = path.links.pop().expect("two links");
            return self.single(pair, link, statement, end);
        }
        self.name_sheet_functions(&mut path);
        if let Some(call) = self.qualified_call(pair, &mut path)? {
            return Ok(call);
        }
        if let Some(call) = self.call_through_object(pair, &mut path, end)? {
            return Ok(call);
        }
        if self.is_enum_member(&path) {
            let member = path.links.pop().expect("two links");
            // `CURVE_DIR.[_FIRST]` is the member `_FIRST`.
            let member = Link { name: super::parser::unbracketed(&member.name).into(), ..member };
            return self.single(pair, member, statement, end);
        }
        if let [module, link] = path.links.as_slice() {
            let unshadowed =
                module.args.is_none() && !self.is_var(&module.name) && !self.is_object(&lower_bare(&module.name));
            if let Some(proc) = self.module_proc(&module.name, &link.name).filter(|_| unshadowed) {
                let args = path.links.pop().expect("two links").args.unwrap_or_default();
                return self.proc_call(pair, proc, args, statement, end);
            }
            if unshadowed && self.module_global(&module.name, &link.name) {
                let module = module.name.clone();
                let variable = path.links.pop().expect("two links");
                return self.qualified_variable(pair, variable, &module, statement, end);
            }
        }
        let root = &path.links[0];
        let not_object = !self.is_var(&root.name) && !self.is_object(&lower_bare(&root.name));
        if not_object && self.proc_index(&root.name).is_some() {
            return self.members_of_call(pair, path, end);
        }
        self.check_path(pair, &path)?;
        if not_object {
            return Err(self.error_at(pair, self.not_an_object(&root.name)));
        }
        Ok(self.node(Node::Path(path), at, end))
    }

    /// `dictget(d, "b").Name`: the members of what a procedure of the project returns, as of
    /// any expression's value ([MS-VBAL] 5.6.12 "Member Access Expressions": the member of
    /// the value of the expression before the dot).
    fn members_of_call(&self, pair: &Pair<Rule>, mut path: Path, end: usize) -> Res<Expr> {
        let rest = path.links.split_off(1);
        let call = path.links.pop().expect("the path's root");
        let base = self.single(pair, call, false, end)?;
        self.members(pair, Some(base), Path { with: false, links: rest, span: path.span }, end)
    }

    /// Why a path's first name is refused; a class module's name says what would make it an
    /// object ([MS-VBAL] 5.2.4.1.2: only a class with `VB_PredeclaredId = True` has an object
    /// named after it).
    fn not_an_object(&self, name: &str) -> String {
        if !self.parts.iter().any(|p| p.class && p.name.eq_ignore_ascii_case(name)) {
            return format!("{name} is not an object or a variable");
        }
        format!(
            "{name} is a class module without a default instance (its file does not say Attribute \
             VB_PredeclaredId = True): make an object with New {name}"
        )
    }

    /// Refuses paths that reach files (`Workbooks.Open`, `ThisWorkbook.SaveAs`).
    pub(super) fn check_path(&self, pair: &Pair<Rule>, path: &Path) -> Res<()> {
        for (i, link) in path.links.iter().enumerate() {
            let lower = lower_bare(&link.name);
            let is_var = i == 0 && !path.with && self.is_var(&link.name);
            // A TextStream's `ts.Close` (`files.rs`), once the run has files.
            let member_close = self.files && i > 0 && lower == "close";
            if FORBIDDEN.contains(&lower.as_str()) && !is_var && !member_close && !is_workbook_save(path, i) {
                return Err(self.error_at(pair, refusal(&link.name)));
            }
        }
        Ok(())
    }

    /// `wsf.Trim(…)` with `wsf` a variable the project only Sets to WorksheetFunction
    /// ([`sheet_function_aliases`]): the path `WorksheetFunction.Trim(…)`.
    fn name_sheet_functions(&self, path: &mut Path) {
        let [first, _, ..] = path.links.as_mut_slice() else { return };
        if first.args.is_none() && self.sheet_function_vars.contains(&first.name.to_ascii_lowercase()) {
            first.name = "WorksheetFunction".into();
        }
    }

    /// `VBA.Sqr(x)`, `WorksheetFunction.Sum(…)`, `Application.WorksheetFunction.Sum(…)`:
    /// rows of the function table, checked here like any call.
    fn qualified_call(&self, pair: &Pair<Rule>, path: &mut Path) -> Res<Option<Expr>> {
        let names: Vec<String> = path.links.iter().map(|l| lower_bare(&l.name)).collect();
        // `ThisWorkbook.Application.WorksheetFunction.Atan2(…)`: a workbook's Application is
        // the one Application ("Workbook.Application property"), as is that of the other
        // objects Excel names globally ("Windows.Application property", "Worksheet.Application
        // property" …: "Returns an Application object that represents the Microsoft Excel
        // application"), none of which can fail to exist.
        let through_workbook = names.len() > 2
            && matches!(
                names[0].as_str(),
                "thisworkbook" | "activeworkbook" | "activesheet" | "activewindow" | "windows"
            )
            && names[1] == "application"
            && path.links[0].args.is_none()
            && !self.is_var(&path.links[0].name);
        let skip = usize::from(through_workbook);
        let qualifier_len = skip
            + match names[skip..].iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
                ["vba", _] => 1,
                ["worksheetfunction", _] => 1,
                ["application", "worksheetfunction", _] => 2,
                // `Application.Max(…)`, `Application.Transpose(…)`: every worksheet function is
                // a member of Application too; its other members (Caller, Volatile …) are not
                // rows of the function table and stay members.
                ["application", f] if Registry.lookup(strip_future_prefix(&dotted(f))).is_some() => 1,
                _ => return Ok(None),
            };
        if path.links[..qualifier_len].iter().any(|l| l.args.is_some()) {
            return Ok(None);
        }
        let link = path.links.pop().expect("function link");
        let name = if names[0] == "vba" { format!("{PREFIX}{}", lower_bare(&link.name)) } else { dotted(&link.name) };
        if FORBIDDEN.contains(&lower_bare(&link.name).as_str()) {
            return Err(self.error_at(pair, refusal(&link.name)));
        }
        if names[0] != "vba" && name.to_ascii_uppercase().starts_with(PREFIX) {
            return Err(self.error_at(pair, format!("{name} is one of VBA's functions, not a worksheet function")));
        }
        let raising = names[..qualifier_len].iter().any(|n| n == "worksheetfunction");
        match self.function_call(pair, &name, &link)? {
            Some(e) if raising => {
                let (at, end) = (e.span.start as usize, e.span.end as usize);
                let call = self.sheet_arguments(e);
                let node = Node::SheetCall { call, name: link.name.clone(), span: self.span(at) };
                Ok(Some(self.node(node, at, end)))
            }
            Some(e) if names[0] != "vba" => Ok(Some(self.sheet_arguments(e))),
            // `VBA.Array(…)` is zero-based whatever the Option Base ([`Node::ZeroBasedArray`]).
            Some(e) if lower_bare(&link.name) == "array" => {
                let (at, end) = (e.span.start as usize, e.span.end as usize);
                Ok(Some(self.node(Node::ZeroBasedArray { call: e }, at, end)))
            }
            Some(e) => Ok(Some(e)),
            None => Err(self.error_at(pair, format!("{} is not a function of {}", link.name, path.links[0].name))),
        }
    }

    /// `Sheets("Data").Application.WorksheetFunction.Max(…)`, `ws.Application.Max(…)`,
    /// `r.Application.Sum(…)`: the Application of any of Excel's objects is the one Application
    /// ("Worksheet.Application property", "Range.Application property": "Returns an
    /// Application object that represents the Microsoft Excel application"), so the call is
    /// Application's own ([`Self::qualified_call`]); the object before it stays in the tree
    /// and is evaluated first ([`Node::Through`]). `None`, and `path` as it was, for any other path.
    fn call_through_object(&self, pair: &Pair<Rule>, path: &mut Path, end: usize) -> Res<Option<Expr>> {
        let Some(at) = path.links.iter().position(|l| lower_bare(&l.name) == "application") else { return Ok(None) };
        if at == 0 || at + 1 >= path.links.len() || path.links[at].args.is_some() {
            return Ok(None);
        }
        let mut rest = Path { with: false, links: path.links.split_off(at), span: path.span };
        let Some(call) = self.qualified_call(pair, &mut rest)? else {
            path.links.append(&mut rest.links);
            return Ok(None);
        };
        let object = Path { with: false, links: std::mem::take(&mut path.links), span: path.span };
        self.check_path(pair, &object)?;
        Ok(Some(self.node(Node::Through { object, call }, start(pair), end)))
    }

    /// A worksheet function's call with each argument that may give a VBA array read as
    /// Excel reads it ([`Node::SheetArg`]).
    fn sheet_arguments(&self, call: Expr) -> Expr {
        let ExprKind::Call(id, args) = call.kind else { return call };
        let args = args
            .into_iter()
            .map(|arg| match arg.kind {
                ExprKind::Name(_) | ExprKind::Host(_) | ExprKind::Call(..) => {
                    let (at, end) = (arg.span.start as usize, arg.span.end as usize);
                    self.node(Node::SheetArg { span: self.span(at), arg }, at, end)
                }
                _ => arg,
            })
            .collect();
        Expr::new(ExprKind::Call(id, args), call.span)
    }

    /// `Excel.xlErrNA`, `VBA.vbCrLf`: a constant named through the library that defines it
    /// (Excel's object library, VBA's own), when no variable has the library's name.
    fn qualified_constant(&self, path: &Path) -> Option<ExprKind> {
        let [library, link] = path.links.as_slice() else { return None };
        let library_name = lower_bare(&library.name);
        let is_library = matches!(library_name.as_str(), "excel" | "vba") && !self.is_var(&library.name);
        if !is_library || library.args.is_some() || link.args.is_some() {
            return None;
        }
        constant(&lower_bare(&link.name))
    }

    /// `Math.Sqr(x)`, `Strings.Left(s, 1)`, `VBA.Math.Sqr(x)`: a module of VBA's library
    /// ("Visual Basic language reference": Conversion, DateTime, FileSystem, Financial,
    /// Information, Interaction, Math, Strings and Constants) names the same functions as
    /// `VBA.` does, so the path is read as `VBA.Sqr(x)` unless a variable or one of the
    /// project's modules has that name.
    fn name_vba_library_module(&self, path: &mut Path) {
        const MODULES: [&str; 9] = [
            "conversion",
            "datetime",
            "filesystem",
            "financial",
            "information",
            "interaction",
            "math",
            "strings",
            "constants",
        ];
        let is_module = |link: &Link| {
            let name = lower_bare(&link.name);
            link.args.is_none()
                && MODULES.contains(&name.as_str())
                && !self.is_var(&link.name)
                && !self.parts.iter().any(|p| p.name.eq_ignore_ascii_case(&link.name))
        };
        let first_is_vba = lower_bare(&path.links[0].name) == "vba" && !self.is_var(&path.links[0].name);
        if first_is_vba && path.links.len() >= 3 && is_module(&path.links[1]) {
            path.links.remove(1);
        } else if path.links.len() >= 2 && is_module(&path.links[0]) {
            path.links[0].name = "VBA".into();
        }
    }

    /// `VBA.TypeName(Me)`, `VBA.IsObject(v)`, `VBA.UBound(a)`: a function of VBA's library that
    /// the interpreter answers itself (not a row of the function table) named through the
    /// library, the same function as its bare name.
    fn is_vba_intrinsic(&self, path: &Path) -> bool {
        let [library, link] = path.links.as_slice() else { return false };
        let name = lower_bare(&link.name);
        let answered_here = inspection(&name).is_some()
            || (Registry.lookup(&format!("{PREFIX}{name}")).is_none() && Registry.lookup(&name).is_none());
        lower_bare(&library.name) == "vba"
            && library.args.is_none()
            && !self.is_var(&library.name)
            && answered_here
            && self.proc_index(&link.name).is_none()
            && !self.is_var(&link.name)
    }

    /// `Tool.Drill`: a member of the project's Enum `Tool`, the constant `Drill` itself.
    fn is_enum_member(&self, path: &Path) -> bool {
        let [enumeration, member] = path.links.as_slice() else { return false };
        let plain = enumeration.args.is_none() && member.args.is_none() && !self.is_var(&enumeration.name);
        plain
            && self.enums.iter().any(|(e, members)| {
                e.eq_ignore_ascii_case(&enumeration.name)
                    && members.iter().any(|m| m.eq_ignore_ascii_case(super::parser::unbracketed(&member.name)))
            })
    }

    /// A call of a row of the function table by `name`, with `link`'s arguments.
    fn function_call(&self, pair: &Pair<Rule>, name: &str, link: &Link) -> Res<Option<Expr>> {
        let Some(info) = Registry.lookup(strip_future_prefix(name)) else { return Ok(None) };
        let args = link.args.as_deref().unwrap_or(&[]);
        let span = ByteSpan { start: start(pair) as u32, end: pair.as_span().end() as u32 };
        let exprs: Vec<Expr> = if args.iter().any(|a| a.name.is_some()) {
            self.named_library_args(pair, crate::eval::functions::spec(info.id).vba_params, &link.name, args, span)?
        } else {
            args.iter().map(|a| a.value.clone()).collect()
        };
        if exprs.len() < info.min_args || exprs.len() > info.max_args {
            return Err(self.error_at(pair, arity_message(&link.name, info.min_args, info.max_args, exprs.len())));
        }
        Ok(Some(Expr::new(ExprKind::Call(info.id, exprs), span)))
    }

    /// A VBA function's arguments in its parameters' order when some are named
    /// (`InStr(Start:=1, String1:=s, String2:="x")`, [MS-VBAL] 5.6.16.8; the names are
    /// `params`, VBA's reference's): the positional ones first, then each named one at its
    /// parameter's place; an optional parameter left out before the last one given is
    /// Missing, as `InStr(, s, "x")` leaves it. Refused, naming the call: a function whose
    /// parameters' names ncsheet does not know, an unknown or repeated name, a positional
    /// argument after a named one, a required parameter left out.
    fn named_library_args(
        &self,
        pair: &Pair<Rule>,
        params: &[&str],
        shown: &str,
        args: &[Arg],
        span: ByteSpan,
    ) -> Res<Vec<Expr>> {
        let refuse = |message: String| Err(self.error_at(pair, message));
        if params.is_empty() {
            return refuse(format!("{shown}: named arguments (x:=) are for the macro's own procedures"));
        }
        let bare = |p: &str| p.trim_start_matches('[').trim_end_matches(']').to_string();
        let mut placed: Vec<Option<Expr>> = vec![None; params.len()];
        let mut named_seen = false;
        for (i, arg) in args.iter().enumerate() {
            let at = match &arg.name {
                None if named_seen => return refuse(format!("{shown}: a positional argument after a named one")),
                None => i,
                Some(name) => {
                    named_seen = true;
                    match params.iter().position(|p| bare(p).eq_ignore_ascii_case(name)) {
                        Some(at) => at,
                        None => {
                            let known: Vec<String> = params.iter().map(|p| bare(p)).collect();
                            return refuse(format!(
                                "{shown} has no parameter {name} (its parameters: {})",
                                known.join(", ")
                            ));
                        }
                    }
                }
            };
            match placed.get_mut(at) {
                Some(slot @ None) => *slot = Some(arg.value.clone()),
                Some(Some(_)) => return refuse(format!("{shown}: {} is given twice", bare(params[at]))),
                None => return refuse(format!("{shown} takes at most {} arguments", params.len())),
            }
        }
        if let Some(left_out) = params.iter().zip(&placed).find(|(p, e)| e.is_none() && !p.starts_with('[')) {
            return refuse(format!("{shown}: argument {} is not optional", bare(left_out.0)));
        }
        let given = placed.iter().rposition(Option::is_some).map_or(0, |i| i + 1);
        Ok(placed.into_iter().take(given).map(|e| e.unwrap_or_else(|| Expr::new(ExprKind::Missing, span))).collect())
    }

    /// VBA's functions that are called without parentheses (`Debug.Print Now`): the bare
    /// name, when no variable has it, is the call, as in VBA.
    fn bare_function(&self, pair: &Pair<Rule>, link: &Link) -> Res<Option<Expr>> {
        const CALLED_BARE: [&str; 6] = ["now", "date", "time", "timer", "rnd", "doevents"];
        let lower = lower_bare(&link.name);
        if !CALLED_BARE.contains(&lower.as_str()) {
            return Ok(None);
        }
        // `Date$`, `Time$`: the `$` forms, a String.
        if link.name.ends_with('$') {
            if let Some(call) = self.function_call(pair, &format!("{PREFIX}{lower}$"), link)? {
                return Ok(Some(call));
            }
        }
        match self.function_call(pair, &format!("{PREFIX}{lower}"), link)? {
            Some(call) => Ok(Some(call)),
            None => self.function_call(pair, &link.name, link),
        }
    }

    /// A path of one name: a variable, constant, procedure, VBA function, object or sheet function.
    fn single(&self, pair: &Pair<Rule>, mut link: Link, statement: bool, end: usize) -> Res<Expr> {
        let at = start(pair);
        if let Some(bare) = self.declared_without_mark(&link.name) {
            link.name = bare;
        }
        let span = ByteSpan { start: at as u32, end: end as u32 };
        let lower = lower_bare(&link.name);
        let is_var = self.is_var(&link.name);
        if is_var {
            self.unambiguous(at, &link.name)?;
        }
        if lower == "createobject" && !is_var {
            if let Some(class) = created(&link) {
                return Ok(self.node(Node::New { class, span: self.span(at) }, at, end));
            }
        }
        // `CreateObject("Scripting.FileSystemObject")` in a run without files too: refused when
        // it runs, saying what it needs, as VBA would create it only when the statement runs.
        if !is_var && super::files::is_file_function(&lower, &link) && (self.files || lower == "createobject") {
            let path = Path { with: false, links: vec![link], span: self.span(at) };
            return Ok(self.node(Node::Path(path), at, end));
        }
        if let Some(why) = library_object_refusal(&link).filter(|_| lower == "createobject" && !is_var) {
            return Err(self.error_at(pair, why));
        }
        if FORBIDDEN.contains(&lower.as_str()) && !is_var {
            return Err(self.error_at(pair, refusal(&link.name)));
        }
        if self.declared.contains(&lower) && !is_var && self.proc_index(&link.name).is_none() {
            let why = "is a DLL's procedure (Declare … Lib): a macro cannot call into other programs";
            return Err(self.error_at(pair, format!("{} {why}", link.name)));
        }
        let Some(args) = &link.args else {
            // A name the project declares hides the library's constant of that name
            // ([MS-VBAL] 5.6.10: the module and project before referenced libraries).
            if let Some(kind) = constant(&lower).filter(|_| !is_var) {
                return Ok(Expr::new(kind, span));
            }
            if lower == "null" && !is_var {
                return Ok(self.node(Node::Null, at, end));
            }
            // Nodes of their own, never the tree's Missing: a call given `Empty` or `Nothing`
            // gave that argument ([MS-VBAL] 5.3.1.11), it did not leave it out.
            if lower == "empty" && !is_var {
                return Ok(self.node(Node::Empty, at, end));
            }
            if lower == "nothing" && !is_var {
                return Ok(self.node(Node::Nothing, at, end));
            }
            if is_var {
                if statement {
                    return Err(self.error_at(pair, format!("{}: a statement cannot be just a value", link.name)));
                }
                return Ok(Expr::new(ExprKind::Name(link.name.clone()), span));
            }
            if let Some(proc) = self.proc_index(&link.name) {
                return self.proc_call(pair, proc, Vec::new(), statement, end);
            }
            if self.is_object(&lower) {
                let path = Path { with: false, links: vec![link], span: self.span(at) };
                return Ok(self.node(Node::Path(path), at, end));
            }
            if statement {
                // `DoEvents` on its own line, as real macros yield in their long loops: a
                // library function whose answer no one needs.
                if lower == "doevents" {
                    if let Some(call) = self.bare_function(pair, &link)? {
                        return Ok(call);
                    }
                }
                // `Calculate` alone is Excel's global member, Application.Calculate.
                if lower == "calculate" {
                    let application = Link { name: "Application".into(), args: None, span: link.span };
                    let path = Path { with: false, links: vec![application, link], span: self.span(at) };
                    return Ok(self.node(Node::Path(path), at, end));
                }
                // "Beep statement": a tone through the computer's speaker, which changes nothing
                // a macro computes or writes.
                if lower == "beep" {
                    return Ok(self.node(Node::Empty, at, end));
                }
                return Err(self.error_at(pair, format!("no Sub named {}", link.name)));
            }
            if lower == "error" {
                return Ok(self.node(Node::Path(current_error_message(link)), at, end));
            }
            if let Some(call) = self.bare_function(pair, &link)? {
                return Ok(call);
            }
            let name = self.implicit_named(at, &link.name)?;
            return Ok(Expr::new(ExprKind::Name(name), span));
        };
        if let Some(proc) = self.proc_index(&link.name).filter(|_| !is_var || self.is_own_function(&link.name)) {
            let args = link.args.expect("arguments");
            return self.proc_call(pair, proc, args, statement, end);
        }
        // `a()`, an array variable with empty parentheses, is the whole array: how an argument
        // passes one (`Sort a()`, "Function statement": a parameter `arglist` of an array).
        if is_var && args.is_empty() {
            return Ok(Expr::new(ExprKind::Name(link.name.clone()), span));
        }
        if is_var {
            let index = args.iter().map(|a| a.value.clone()).collect();
            return Ok(self.node(Node::Element { var: link.name.clone(), index, span: self.span(at) }, at, end));
        }
        if lower == "ubound" || lower == "lbound" {
            return self.bound(pair, &link, lower == "ubound", end);
        }
        if let Some(what) = inspection(&lower).filter(|_| args.len() == 1 && args[0].name.is_none()) {
            let arg = args[0].value.clone();
            let at = start(pair);
            return Ok(self.node(Node::Inspect { what, arg, span: self.span(at) }, at, end));
        }
        // `Len(n)` of a variable: its declared type decides when the macro runs (`storage_size.rs`).
        if let Some(bytes) = storage_size_asked(&lower, args) {
            if let Some(call) = self.function_call(pair, &format!("{PREFIX}{lower}"), &link)? {
                let at = start(pair);
                let what = Inspect::Len { bytes };
                return Ok(self.node(Node::Inspect { what, arg: call, span: self.span(at) }, at, end));
            }
        }
        // `Left$(…)`: the `$` form, a String, where VBA has one apart (Null is error 94 there).
        if link.name.ends_with('$') {
            if let Some(call) = self.function_call(pair, &format!("{PREFIX}{lower}$"), &link)? {
                return Ok(call);
            }
        }
        if let Some(call) = self.function_call(pair, &format!("{PREFIX}{lower}"), &link)? {
            return Ok(call);
        }
        if self.is_object(&lower) {
            let path = Path { with: false, links: vec![link], span: self.span(at) };
            return Ok(self.node(Node::Path(path), at, end));
        }
        match self.function_call(pair, &link.name, &link)? {
            Some(call) => Ok(call),
            None => Err(self.error_at(pair, format!("no Function, Sub or sheet function named {}", link.name))),
        }
    }

    fn proc_call(&self, pair: &Pair<Rule>, proc: usize, args: Vec<Arg>, statement: bool, end: usize) -> Res<Expr> {
        let Signature { name, kind, params, required, param_array, .. } = &self.procs[proc];
        if *kind == ProcKind::Sub && !statement {
            return Err(self.error_at(pair, format!("Sub {name} has no value; call it as a statement")));
        }
        if *param_array {
            self.check_param_array_args(pair, name, params.len() - 1, &args)?;
        }
        let positional = args.iter().take_while(|a| a.name.is_none()).count();
        if args.len() > params.len() && !*param_array {
            return Err(self.error_at(pair, arity_message(name, *required, params.len(), args.len())));
        }
        for a in &args[positional..] {
            let Some(arg_name) = &a.name else {
                return Err(self.error_at(pair, "a positional argument cannot follow a named one"));
            };
            if !params.iter().any(|p| p.eq_ignore_ascii_case(arg_name)) {
                return Err(self.error_at(pair, format!("{name} has no parameter {arg_name}")));
            }
        }
        let given = |i: usize, p: &str| {
            args.get(i).is_some_and(|a| a.name.is_none() && a.value.kind != ExprKind::Missing)
                || args.iter().any(|a| a.name.as_deref().is_some_and(|n| n.eq_ignore_ascii_case(p)))
        };
        if let Some(missing) = params.iter().take(*required).enumerate().find(|(i, p)| !given(*i, p)) {
            return Err(self.error_at(pair, format!("{name}: argument {} is not optional", missing.1)));
        }
        self.check_by_ref_args(proc, &args)?;
        let at = start(pair);
        Ok(self.node(Node::Call { proc, args, span: self.span(at) }, at, end))
    }

    /// A call of a procedure with a ParamArray: its arguments by position only, none of those
    /// the ParamArray takes left out (this interpreter has no Missing item to give it).
    fn check_param_array_args(&self, pair: &Pair<Rule>, name: &str, fixed: usize, args: &[Arg]) -> Res<()> {
        if args.iter().any(|a| a.name.is_some()) {
            let why = "has a ParamArray: give its arguments by position (no name:=)";
            return Err(self.error_at(pair, format!("{name} {why}")));
        }
        if args.iter().skip(fixed).any(|a| a.value.kind == ExprKind::Missing) {
            let why = "an argument left out of its ParamArray is not supported; give each one";
            return Err(self.error_at(pair, format!("{name}: {why}")));
        }
        Ok(())
    }

    fn bound(&self, pair: &Pair<Rule>, link: &Link, upper: bool, end: usize) -> Res<Expr> {
        let args = link.args.as_deref().unwrap_or(&[]);
        let of = match args.first() {
            Some(a) if args.len() <= 2 && a.name.is_none() && a.value.kind != ExprKind::Missing => a.value.clone(),
            _ => return Err(self.error_at(pair, format!("{}(array, [dimension]) needs an array", link.name))),
        };
        let dim = args.get(1).map(|a| a.value.clone());
        let at = start(pair);
        Ok(self.node(Node::Bound { upper, of, dim, span: self.span(at) }, at, end))
    }
}

/// The variables (lower case) that every `Set` of the project's source sets to Excel's
/// WorksheetFunction object (`Set wsf = Application.WorksheetFunction`, `Set wf =
/// WorksheetFunction`, "Application.WorksheetFunction property": "Returns the
/// WorksheetFunction object"): `wsf.Trim(…)` calls the worksheet function as
/// `WorksheetFunction.Trim(…)` does. A variable also set to anything else is not one.
pub(super) fn sheet_function_aliases(src: &str) -> std::collections::HashSet<String> {
    let mut aliases = std::collections::HashSet::new();
    let mut others = std::collections::HashSet::new();
    let statements = src.lines().flat_map(|line| line.split(':'));
    for statement in statements {
        let Some((name, value)) = set_statement(statement) else { continue };
        let value: String = value.split_whitespace().collect::<String>().to_ascii_lowercase();
        let worksheet_function =
            matches!(value.as_str(), "worksheetfunction" | "application.worksheetfunction" | "excel.worksheetfunction");
        if worksheet_function { &mut aliases } else { &mut others }.insert(name);
    }
    aliases.retain(|name| !others.contains(name));
    aliases
}

/// `Set name = value` as written in one statement: the name in lower case and the value's
/// text; `None` for any other statement.
fn set_statement(statement: &str) -> Option<(String, &str)> {
    let statement = statement.trim_start();
    let rest = statement.get(..4).filter(|w| w.eq_ignore_ascii_case("set "))?;
    let (name, value) = statement[rest.len()..].split_once('=')?;
    let name = name.trim();
    if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return None;
    }
    Some((name.to_ascii_lowercase(), value.split('\'').next().unwrap_or(value)))
}

/// What a With block's object is, as far as the parser resolves a `.Member` in it itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum WithSubject {
    /// Excel's WorksheetFunction object: every member is a worksheet function.
    SheetFunctions,
    /// Application: its worksheet-function members resolve here, the others at run time.
    Application,
    /// Anything else: its members are found at run time.
    Other,
}

/// `CreateObject("Scripting.Dictionary")`, `CreateObject("System.Collections.ArrayList")`,
/// `CreateObject("VBScript.RegExp")`: the ProgIDs a macro may create (a literal).
fn created(link: &Link) -> Option<Made> {
    match link.args.as_deref() {
        Some([Arg { name: None, value }]) => match &value.kind {
            ExprKind::Text(id) => {
                super::collections::created_class(id).map(Made::Store).or_else(|| super::regexp::created(id))
            }
            _ => None,
        },
        _ => None,
    }
}

/// Why `CreateObject(progID)` of a library object ncsheet does not make is refused, by the
/// object's name rather than as a program: another of .NET's collections than the ArrayList
/// (`System.Collections.SortedList`, which macros borrow through COM).
fn library_object_refusal(link: &Link) -> Option<String> {
    let [Arg { name: None, value }] = link.args.as_deref()? else { return None };
    let ExprKind::Text(prog_id) = &value.kind else { return None };
    prog_id.to_ascii_lowercase().starts_with("system.collections.").then(|| {
        format!(
            "CreateObject(\"{prog_id}\"): .NET's collections are not in ncsheet (a macro loads no .NET \
             library); keep the items in a Collection, a Scripting.Dictionary or an array"
        )
    })
}

/// A worksheet function's name as a member of WorksheetFunction or Application spells it:
/// a dot of the function's name is an underscore there (`Floor_Precise` is FLOOR.PRECISE,
/// "WorksheetFunction.Floor_Precise method"), as no function name holds an underscore.
fn dotted(member: &str) -> String {
    member.replace('_', ".")
}

/// Whether a link before a path's last has an index list after its arguments (`d(k)(i).Name`,
/// `A(1)(2).Count`): what [`Build::chain`] reads, told from the pest pairs alone.
fn has_index_inside(pair: &Pair<Rule>) -> bool {
    let links: Vec<Pair<Rule>> = pair.clone().into_inner().filter(|p| p.as_rule() != Rule::with_dot).collect();
    links.split_last().is_some_and(|(_, before)| {
        before.iter().any(|link| link.clone().into_inner().any(|p| p.as_rule() == Rule::index_parens))
    })
}
