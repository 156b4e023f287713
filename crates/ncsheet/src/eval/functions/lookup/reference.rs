//! Reference and information functions that need facts about the workbook: ADDRESS, SHEET,
//! SHEETS, FORMULATEXT, ISFORMULA, GETPIVOTDATA (the file's pivot tables), and SUBTOTAL and AGGREGATE, which skip cells that are
//! themselves subtotals (through `Env::is_subtotal`) so that totals of subtotals do not count
//! twice. Rows a filter hid are left out by every code, rows hidden by hand by 101–111
//! (`Env::row_hidden`, from the file's `<row hidden="1">`).

use std::sync::LazyLock;

use crate::eval::coerce::to_text;
use crate::eval::functions::api::{
    bool_or, find, number, number_or, ArgSet, Ctx, FnSpec, Operand, Outside, RowHidden, MANY,
};
use crate::eval::value::{too_many_items, too_many_items_note, Array, Value, XlError, XlResult};
use crate::formula::address::{column_name, Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{Expr, ExprKind, FnId, SheetId};
use crate::formula::print::quote_sheet_name;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("ADDRESS", 2, 5, address, "ADDRESS(row, column, [abs_num], [a1], [sheet_text])", "A cell address as text (abs_num 1 $A$1, 2 A$1, 3 $A1, 4 A1)")
        .biff(219),
    FnSpec::value("AGGREGATE", 3, MANY, aggregate, "AGGREGATE(function_num, options, ref1, [ref2], ...)", "SUBTOTAL's functions and more (14 LARGE … 19 QUARTILE.EXC), optionally skipping errors").future().range_args(ArgSet::from(2)),
    FnSpec::value("CELL", 1, 2, cell, "CELL(info_type, [reference])", "Facts about a cell: \"address\", \"col\", \"row\", \"contents\", \"type\" (b blank, l text, v value)")
        .biff(125).range_args(ArgSet::only(1)),
    FnSpec::reference("TRIMRANGE", 1, 3, trimrange, "TRIMRANGE(range, [trim_rows], [trim_cols])", "The range without its blank outer rows and columns (0 none, 1 leading, 2 trailing, 3 both: the default)").future().dynamic().range_args(ArgSet::only(0)),
    FnSpec::value("INFO", 1, 1, info, "INFO(type_text)", "About the environment: \"numfile\", \"recalc\", \"system\" … as Excel 365 on Windows")
        .biff(244).reads(Outside::Host).volatile(),
    FnSpec::value("FORMULATEXT", 1, 1, formulatext, "FORMULATEXT(reference)", "The formula of a cell as text; #N/A when it holds none").future().range_args(ArgSet::only(0)),
    FnSpec::value("GETPIVOTDATA", 2, MANY, getpivotdata, "GETPIVOTDATA(data_field, pivot_table, [field1, item1], ...)", "A value a pivot table of the file shows: the data field's summary of the records holding the items")
        .biff(358).range_args(ArgSet::only(1)),
    FnSpec::value("HYPERLINK", 1, 2, hyperlink, "HYPERLINK(link_location, [friendly_name])", "The text a link shows: friendly_name, or the location (ncsheet opens no links)")
        .biff(359),
    FnSpec::value("ISFORMULA", 1, 1, isformula, "ISFORMULA(reference)", "Whether a cell holds a formula").future().range_args(ArgSet::only(0)),
    FnSpec::value("SHEET", 0, 1, sheet, "SHEET([value])", "The number of a sheet (of a reference or a sheet name; this one by default)").future().range_args(ArgSet::only(0)),
    FnSpec::value("SHEETS", 0, 1, sheets, "SHEETS([reference])", "How many sheets (in a reference; the workbook's by default)").future().range_args(ArgSet::only(0)),
    FnSpec::value("SUBTOTAL", 2, MANY, subtotal, "SUBTOTAL(function_num, ref1, [ref2], ...)", "1 AVERAGE 2 COUNT 3 COUNTA 4 MAX 5 MIN 6 PRODUCT 7 STDEV 8 STDEVP 9 SUM 10 VAR 11 VARP, skipping other subtotals")
        .biff(344).range_args(ArgSet::from(1)),
];

fn address(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let row = number(ctx, &args[0])?.trunc();
    let col = number(ctx, &args[1])?.trunc();
    let abs = number_or(ctx, args, 2, 1.0)?.trunc();
    let a1 = bool_or(ctx, args, 3, true)?;
    let sheet = match args.get(4) {
        Some(e) if e.kind != ExprKind::Missing => Some(to_text(&ctx.eval(e))?),
        _ => None,
    };
    if row < 1.0 || row > f64::from(MAX_ROWS) || col < 1.0 || col > f64::from(MAX_COLS) || !(1.0..=4.0).contains(&abs) {
        return Err(XlError::Value);
    }
    let (row_abs, col_abs) = (abs == 1.0 || abs == 2.0, abs == 1.0 || abs == 3.0);
    let (row, col) = (row as u32, col as u32);
    let cell = if a1 {
        let dollar = |abs: bool| if abs { "$" } else { "" };
        format!("{}{}{}{row}", dollar(col_abs), column_name(col - 1), dollar(row_abs))
    } else {
        let part =
            |letter: char, n: u32, abs: bool| if abs { format!("{letter}{n}") } else { format!("{letter}[{n}]") };
        format!("{}{}", part('R', row, row_abs), part('C', col, col_abs))
    };
    Ok(Value::text(match sheet {
        Some(s) if s.is_empty() => format!("!{cell}"),
        Some(s) => format!("{}!{cell}", quote_sheet_name(&s)),
        None => cell,
    }))
}

/// The one cell a reference argument names (its first cell for a range); `#N/A` for a value.
fn referenced_cell(ctx: &mut Ctx, e: &Expr) -> XlResult<(crate::formula::ast::SheetId, crate::formula::address::Pos)> {
    match ctx.reference_only(e) {
        Operand::Ref(sheet, rect) => Ok((sheet, rect.first)),
        Operand::Value(Value::Error(err)) => Err(err),
        Operand::Value(_) => Err(XlError::NA),
        Operand::Areas(_) => Err(XlError::Value),
    }
}

/// CELL: what a cell's reference and value say. The formatting types (format, color,
/// parentheses, prefix, protect, width) and filename are not modelled: `#N/A` with a note.
fn cell(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let info = match ctx.eval(&args[0]).unwrap_single() {
        Value::Text(t) => english_info_type(&t, ctx.env.excel_language()),
        Value::Error(e) => return Err(e),
        _ => return Err(XlError::Value),
    };
    let (sheet, pos) = match args.get(1) {
        Some(e) if e.kind != ExprKind::Missing => match ctx.reference_only(e) {
            Operand::Ref(sheet, rect) => (sheet, rect.first),
            Operand::Value(Value::Error(err)) => return Err(err),
            Operand::Value(_) | Operand::Areas(_) => return Err(XlError::Value),
        },
        _ => (ctx.sheet, ctx.at),
    };
    match info.as_str() {
        "address" => {
            let address = format!("${}${}", column_name(pos.col), pos.row + 1);
            Ok(Value::text(match ctx.env.sheet_name(sheet) {
                Some(name) if sheet != ctx.sheet => format!("{}!{address}", quote_sheet_name(&name)),
                _ => address,
            }))
        }
        "col" => Ok(Value::Number(f64::from(pos.col) + 1.0)),
        "row" => Ok(Value::Number(f64::from(pos.row) + 1.0)),
        "contents" => match ctx.env.value(sheet, pos) {
            Value::Blank => Ok(Value::Number(0.0)),
            Value::Error(e) => Err(e),
            v => Ok(v),
        },
        "type" => Ok(Value::text(match ctx.env.value(sheet, pos) {
            Value::Blank => "b",
            Value::Text(_) => "l",
            _ => "v",
        })),
        // Excel: "Column width of the cell, rounded off to an integer"; 8.43 when not set.
        "width" => Ok(Value::Number(ctx.env.column_width(sheet, pos.col).unwrap_or(8.43).round())),
        "color" | "filename" | "format" | "parentheses" | "prefix" | "protect" => {
            Err(ctx.explain(XlError::NA, format!("CELL(\"{info}\") reads formatting ncsheet does not keep")))
        }
        _ => Err(XlError::Value),
    }
}

/// CELL's info types that an Excel of a language other than English reads in that language
/// too, as MS-OI29500 2.1.896 lists them: these English types, then each language's
/// translations in their order. (The document's table of the other types, row, type, width
/// and the rest, is not here: ncsheet reads those in English only.)
const CELL_INFO_TRANSLATED: [&str; 6] = ["address", "col", "color", "contents", "filename", "format"];
const CELL_INFO_TRANSLATIONS: &[(&str, [&str; 6])] = &[
    ("cs", ["adresa", "sloupec", "barva", "obsah", "názevsouboru", "formát"]),
    ("da", ["adresse", "kolonne", "farve", "indhold", "filnavn", "format"]),
    ("de", ["adresse", "spalte", "farbe", "inhalt", "dateiname", "format"]),
    ("es", ["direccion", "columna", "color", "contenido", "nombrearchivo", "formato"]),
    ("fi", ["osoite", "sarake", "väri", "sisältö", "tiedostonnimi", "muoto"]),
    ("fr", ["adresse", "colonne", "couleur", "contenu", "nomfichier", "format"]),
    ("hu", ["cím", "oszlop", "szín", "tartalom", "filenév", "forma"]),
    ("it", ["indirizzo", "col", "colore", "contenuto", "nomefile", "formato"]),
    ("nb", ["adresse", "kol", "farge", "innhold", "filnavn", "format"]),
    ("nl", ["adres", "kolom", "kleur", "inhoud", "bestandsnaam", "notatie"]),
    ("pl", ["adres", "kolumna", "kolor", "zawartość", "nazwa_pliku", "format"]),
    ("pt-BR", ["endereço", "col", "cor", "conteúdo", "nome.arquivo", "formato"]),
    ("pt-PT", ["endereço", "col", "cor", "conteúdo", "nome.ficheiro", "formato"]),
];

/// CELL's info type in English, lowercased: as given, or translated from `language`, the
/// language of the Excel that saved the workbook, when it is one of that language's types.
fn english_info_type(info: &str, language: Option<&str>) -> String {
    let lower = info.to_lowercase();
    let translations = language.and_then(|language| CELL_INFO_TRANSLATIONS.iter().find(|(tag, _)| *tag == language));
    match translations.and_then(|(_, types)| types.iter().position(|local| *local == lower)) {
        Some(i) => CELL_INFO_TRANSLATED[i].to_string(),
        None => lower,
    }
}

fn trimrange(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    match trimmed(ctx, args) {
        Ok((sheet, rect)) => Operand::Ref(sheet, rect),
        Err(e) => Operand::Value(Value::Error(e)),
    }
}

/// TRIMRANGE's reference: the bounding box of the non-blank cells, cut on the sides the
/// trim arguments name.
fn trimmed(ctx: &mut Ctx, args: &[Expr]) -> XlResult<(crate::formula::ast::SheetId, Rect)> {
    let (sheet, rect) = match ctx.reference_only(&args[0]) {
        Operand::Ref(sheet, rect) => (sheet, rect),
        Operand::Value(Value::Error(e)) => return Err(e),
        Operand::Value(_) | Operand::Areas(_) => return Err(XlError::Value),
    };
    let rows = number_or(ctx, args, 1, 3.0)?.trunc();
    let cols = number_or(ctx, args, 2, 3.0)?.trunc();
    if !(0.0..=3.0).contains(&rows) || !(0.0..=3.0).contains(&cols) {
        return Err(XlError::Value);
    }
    let mut used: Option<Rect> = None;
    let clipped = ctx.clip_to_used(sheet, rect);
    ctx.env.for_each_value(sheet, clipped, &mut |pos, v| {
        if !v.is_blank() {
            used = Some(used.map_or(Rect::cell(pos), |u| {
                Rect::new(
                    Pos::new(u.first.row.min(pos.row), u.first.col.min(pos.col)),
                    Pos::new(u.last.row.max(pos.row), u.last.col.max(pos.col)),
                )
            }));
        }
    });
    // An empty range trims to its first cell.
    let used = used.unwrap_or(Rect::cell(rect.first));
    let (rows, cols) = (rows as u8, cols as u8);
    let first = Pos::new(
        if rows & 1 == 1 { used.first.row } else { rect.first.row },
        if cols & 1 == 1 { used.first.col } else { rect.first.col },
    );
    let last = Pos::new(
        if rows & 2 == 2 { used.last.row } else { rect.last.row },
        if cols & 2 == 2 { used.last.col } else { rect.last.col },
    );
    Ok((sheet, Rect::new(first, last)))
}

/// INFO: the workbook's facts as they are (numfile, recalc) and the host's as Excel 365 on
/// Windows gives them with a window at rest (docs/functions.md), so that a workbook computes
/// the same on every machine. "directory" is a folder of the user's machine, which a value
/// must not depend on: `#N/A` with a note, as the memory queries Excel dropped.
fn info(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let kind = match ctx.eval(&args[0]).unwrap_single() {
        Value::Text(t) => t.to_ascii_lowercase(),
        Value::Error(e) => return Err(e),
        _ => return Err(XlError::Value),
    };
    match kind.as_str() {
        "numfile" => Ok(Value::Number(ctx.env.sheet_count() as f64)),
        "recalc" => Ok(Value::text("Automatic")),
        // The top-left cell of a window not scrolled, in Lotus 1-2-3's "$A:" form.
        "origin" => Ok(Value::text("$A:$A$1")),
        "osversion" => Ok(Value::text("Windows (64-bit) NT 10.00")),
        // Application.Version of Excel 2016 to 365.
        "release" => Ok(Value::text("16.0")),
        "system" => Ok(Value::text("pcdos")),
        "directory" => {
            Err(ctx
                .explain(XlError::NA, "INFO(\"directory\") is a folder of Excel's host, which ncsheet does not give"))
        }
        "memavail" | "memused" | "totmem" => Err(XlError::NA),
        _ => Err(XlError::Value),
    }
}

#[cfg(test)]
mod info_tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::{Value, XlError};

    /// Microsoft's INFO page: "system" is "pcdos" on Windows; "origin" is the top-left visible
    /// cell as "$A:" and its absolute reference; "memavail", "memused" and "totmem" are no
    /// longer supported and give #N/A. Excel 2016 to 365 report release "16.0" and, on
    /// Windows 10 and 11, osversion "Windows (64-bit) NT 10.00".
    #[test]
    fn info_answers_as_excel_365_on_windows() {
        let env = MapEnv::with(&[]);
        assert_eq!(env.eval("=INFO(\"system\")"), Value::text("pcdos"));
        assert_eq!(env.eval("=INFO(\"SYSTEM\")"), Value::text("pcdos"));
        assert_eq!(env.eval("=INFO(\"origin\")"), Value::text("$A:$A$1"));
        assert_eq!(env.eval("=INFO(\"release\")"), Value::text("16.0"));
        assert_eq!(env.eval("=INFO(\"osversion\")"), Value::text("Windows (64-bit) NT 10.00"));
        assert_eq!(env.eval("=INFO(\"recalc\")"), Value::text("Automatic"));
        assert_eq!(env.eval("=INFO(\"numfile\")"), Value::Number(1.0));
        for dropped in ["memavail", "memused", "totmem", "directory"] {
            assert_eq!(env.eval(&format!("=INFO(\"{dropped}\")")), Value::Error(XlError::NA), "{dropped}");
        }
        assert_eq!(env.eval("=INFO(\"colour\")"), Value::Error(XlError::Value));
    }
}

#[cfg(test)]
mod aggregate_tests {
    use crate::eval::testing::{err, n, MapEnv};
    use crate::eval::XlError;

    fn column() -> MapEnv {
        // 5, #N/A, 1, 9, 3, 7 in A1:A6.
        let a = [n(5.0), err(XlError::NA), n(1.0), n(9.0), n(3.0), n(7.0)];
        let cells: Vec<(String, _)> = a.iter().enumerate().map(|(i, v)| (format!("A{}", i + 1), v.clone())).collect();
        let cells: Vec<(&str, _)> = cells.iter().map(|(c, v)| (c.as_str(), v.clone())).collect();
        MapEnv::with(&cells)
    }

    /// The array form (14–19): the function of the same name over the values left, k after.
    /// Option 6 leaves out errors; 4 keeps them, and the error is the result.
    #[test]
    fn the_array_form_is_large_small_percentile_and_quartile_without_errors() {
        let env = column();
        // Without the error: 1, 3, 5, 7, 9.
        assert_eq!(env.eval("=AGGREGATE(14,6,A1:A6,2)"), n(7.0));
        assert_eq!(env.eval("=AGGREGATE(15,6,A1:A6,2)"), n(3.0));
        assert_eq!(env.eval("=AGGREGATE(16,6,A1:A6,0.25)"), n(3.0));
        assert_eq!(env.eval("=AGGREGATE(17,6,A1:A6,1)"), n(3.0));
        // PERCENTILE.EXC at 0.25 of 5 values: rank 1.5, halfway from 1 to 3.
        assert_eq!(env.eval("=AGGREGATE(18,6,A1:A6,0.25)"), n(2.0));
        assert_eq!(env.eval("=AGGREGATE(19,6,A1:A6,1)"), n(2.0));
        assert_eq!(env.eval("=AGGREGATE(14,4,A1:A6,1)"), err(XlError::NA));
        assert_eq!(env.eval("=AGGREGATE(14,6,A1:A6,6)"), err(XlError::Num));
        // "If a second ref argument is required but not provided, AGGREGATE returns #VALUE!".
        assert_eq!(env.eval("=AGGREGATE(15,6,A1:A6)"), err(XlError::Value));
    }

    /// A computed array: the errors it makes are left out (the usual conditional LARGE),
    /// and a whole column's blanks count as what the calculation makes of them.
    #[test]
    fn the_array_form_takes_a_computed_array_whole() {
        let env = column();
        assert_eq!(env.eval("=AGGREGATE(14,6,A1:A6/(A1:A6>4),1)"), n(9.0));
        assert_eq!(env.eval("=AGGREGATE(15,6,A1:A6/(A1:A6>4),1)"), n(5.0));
        assert_eq!(env.eval("=AGGREGATE(15,6,A1:A6*2,3)"), n(10.0));
        // A:A*1 is 1,048,576 items, the blanks 0: the smallest is 0, as SMALL says.
        assert_eq!(env.eval("=SMALL(IFERROR(A:A*1,\"\"),1)"), n(0.0));
        assert_eq!(env.eval("=AGGREGATE(15,6,A:A*1,1)"), n(0.0));
        assert_eq!(env.eval("=AGGREGATE(16,6,A:A*1,0.5)"), n(0.0));
        assert_eq!(env.eval("=AGGREGATE(14,6,A:A-10,1)"), n(-1.0));
    }

    /// Functions 1–13 take references ("invalid types: actual data, arrays" in Excel's
    /// WorksheetFunction.Aggregate reference).
    #[test]
    fn the_reference_form_refuses_arrays_and_values() {
        let env = column();
        assert_eq!(env.eval("=AGGREGATE(4,6,A1:A6)"), n(9.0));
        assert_eq!(env.eval("=AGGREGATE(9,6,A1:A6,A3)"), n(26.0));
        assert_eq!(env.eval("=AGGREGATE(9,6,A1:A6*2)"), err(XlError::Value));
        assert_eq!(env.eval("=AGGREGATE(9,6,5)"), err(XlError::Value));
    }
}

fn formulatext(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (sheet, pos) = referenced_cell(ctx, &args[0])?;
    ctx.env.formula_text(sheet, pos).map(Value::text).ok_or(XlError::NA)
}

fn isformula(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (sheet, pos) = match ctx.reference_only(&args[0]) {
        Operand::Ref(sheet, rect) => (sheet, rect.first),
        Operand::Value(Value::Error(e)) => return Err(e),
        Operand::Value(_) | Operand::Areas(_) => return Err(XlError::Value),
    };
    Ok(Value::Bool(ctx.env.formula_text(sheet, pos).is_some()))
}

/// GETPIVOTDATA: what the pivot table holding the referenced cell shows, through
/// `Env::pivot_data` (the file's pivot cache); `#REF!` with a note where it shows nothing.
fn getpivotdata(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data_field = to_text(&ctx.eval(&args[0]).unwrap_single())?;
    let (sheet, at) = match ctx.reference_only(&args[1]) {
        Operand::Ref(sheet, rect) => (sheet, rect.first),
        Operand::Value(Value::Error(e)) => return Err(e),
        Operand::Value(_) | Operand::Areas(_) => {
            return Err(ctx.explain(XlError::Ref, "GETPIVOTDATA's second argument must be a cell of a pivot table"))
        }
    };
    if !args.len().is_multiple_of(2) {
        return Err(ctx.explain(XlError::Ref, "GETPIVOTDATA takes its fields and items in pairs"));
    }
    let mut pairs = Vec::with_capacity(args.len() / 2 - 1);
    for pair in args[2..].chunks(2) {
        let field = to_text(&ctx.eval(&pair[0]).unwrap_single())?;
        let item = match ctx.eval(&pair[1]).unwrap_single() {
            Value::Error(e) => return Err(e),
            item => item,
        };
        pairs.push((field.to_string(), item));
    }
    match ctx.env.pivot_data(sheet, at, &data_field, &pairs) {
        Ok(value) => Ok(value),
        Err(why) => Err(ctx.explain(XlError::Ref, why)),
    }
}

fn hyperlink(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let shown = match args.get(1) {
        Some(e) if e.kind != ExprKind::Missing => ctx.eval(e),
        _ => ctx.eval(&args[0]),
    };
    match shown.unwrap_single() {
        Value::Blank => Ok(Value::Number(0.0)),
        v => Ok(v),
    }
}

/// SHEET: the sheet's number among the tabs, counted from 1 (a moved sheet's new place).
fn sheet(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let Some(e) = args.first().filter(|e| e.kind != ExprKind::Missing) else {
        return Ok(tab_number(ctx, ctx.sheet));
    };
    match ctx.reference_only(e) {
        Operand::Ref(sheet, _) => Ok(tab_number(ctx, sheet)),
        Operand::Value(Value::Text(name)) => ctx.env.sheet_id(&name).map(|s| tab_number(ctx, s)).ok_or(XlError::NA),
        Operand::Value(Value::Error(e)) => Err(e),
        Operand::Value(_) => Err(XlError::NA),
        Operand::Areas(areas) => Ok(tab_number(ctx, areas[0].0)),
    }
}

fn tab_number(ctx: &Ctx, sheet: SheetId) -> Value {
    Value::Number(ctx.env.tab_position(sheet) as f64 + 1.0)
}

fn sheets(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let Some(e) = args.first().filter(|e| e.kind != ExprKind::Missing) else {
        return Ok(Value::Number(ctx.env.sheet_count() as f64));
    };
    match ctx.reference_only(e) {
        Operand::Ref(..) | Operand::Areas(_) => Ok(Value::Number(1.0)),
        Operand::Value(Value::Error(e)) => Err(e),
        Operand::Value(_) => Err(XlError::Value),
    }
}

// ---- SUBTOTAL and AGGREGATE -----------------------------------------------------------------

/// SUBTOTAL's functions 1 to 11, and AGGREGATE's 12 to 19, by registry name.
const AGGREGATES: [&str; 19] = [
    "AVERAGE",
    "COUNT",
    "COUNTA",
    "MAX",
    "MIN",
    "PRODUCT",
    "STDEV.S",
    "STDEV.P",
    "SUM",
    "VAR.S",
    "VAR.P",
    "MEDIAN",
    "MODE.SNGL",
    "LARGE",
    "SMALL",
    "PERCENTILE.INC",
    "QUARTILE.INC",
    "PERCENTILE.EXC",
    "QUARTILE.EXC",
];

static AGGREGATE_IDS: LazyLock<Vec<FnId>> =
    LazyLock::new(|| AGGREGATES.iter().map(|n| find(n).expect("aggregate functions are registered")).collect());

/// Which cells of its ranges an aggregate leaves out.
#[derive(Clone, Copy)]
struct Skip {
    /// Cells holding a SUBTOTAL or AGGREGATE.
    subtotals: bool,
    /// Rows hidden by hand (rows a filter hides are always left out).
    hidden: bool,
    errors: bool,
}

impl Skip {
    fn row(self, hidden: Option<RowHidden>) -> bool {
        match hidden {
            Some(RowHidden::Filtered) => true,
            Some(RowHidden::Manually) => self.hidden,
            None => false,
        }
    }
}

/// The references and values of the arguments with the cells `skip` names taken out, as
/// one array argument.
///
/// A computed array (`A1:A9*(B1:B9>0)`) has no rows to hide or subtotal cells: only its
/// errors can be left out, as Excel's AGGREGATE documents. A whole column's array counts
/// every item, its tail included (`AGGREGATE(15,6,A:A*1,1)` is 0 when A has blanks).
/// `values_allowed` false: an argument that is no reference is `#VALUE!` (AGGREGATE's
/// reference form, functions 1–13, takes "no actual data, no arrays").
fn without_subtotals(ctx: &mut Ctx, args: &[Expr], skip: Skip, values_allowed: bool) -> XlResult<Vec<Value>> {
    let mut out = Vec::new();
    for a in args {
        match ctx.operand(a) {
            Operand::Ref(sheet, rect) => kept_values(ctx, sheet, rect, skip, &mut out),
            Operand::Areas(areas) => {
                for &(sheet, rect) in areas.iter() {
                    kept_values(ctx, sheet, rect, skip, &mut out);
                }
            }
            Operand::Value(_) if !values_allowed => return Err(XlError::Value),
            Operand::Value(Value::Array(arr)) => array_items(ctx, &arr, skip, &mut out)?,
            Operand::Value(v) => out.push(v),
        }
    }
    Ok(out)
}

/// Every item of a computed array, the tail's too, but the errors `skip` leaves out.
fn array_items(ctx: &mut Ctx, arr: &Array, skip: Skip, out: &mut Vec<Value>) -> XlResult<()> {
    let kept = |v: &Value| !(skip.errors && matches!(v, Value::Error(_)));
    out.extend(arr.data.iter().filter(|v| kept(v)).cloned());
    if let Some(tail) = &arr.tail {
        if too_many_items(tail.rows, tail.cols) {
            return Err(ctx.explain(XlError::Num, too_many_items_note(tail.rows, tail.cols)));
        }
        if kept(&tail.fill) {
            let count = tail.rows * tail.cols - arr.rows * arr.cols;
            out.extend(std::iter::repeat_n(tail.fill.clone(), count));
        }
    }
    Ok(())
}

/// The values of one range that `skip` keeps, pushed onto `out`.
fn kept_values(ctx: &Ctx, sheet: crate::formula::ast::SheetId, rect: Rect, skip: Skip, out: &mut Vec<Value>) {
    let rect = ctx.clip_to_used(sheet, rect);
    let env = ctx.env;
    env.for_each_value(sheet, rect, &mut |pos, v| {
        let left_out = skip.subtotals && env.is_subtotal(sheet, pos)
            || skip.errors && matches!(v, Value::Error(_))
            || skip.row(env.row_hidden(sheet, pos.row));
        if !left_out {
            out.push(v.clone());
        }
    });
}

/// Calls the aggregate `code` (1-based) on `values` as one array, plus `extra` arguments.
fn call_on(ctx: &mut Ctx, code: usize, values: Vec<Value>, extra: &[Expr]) -> Value {
    use std::rc::Rc;
    let n = values.len();
    let array = if n == 0 { Value::Blank } else { Value::Array(Rc::new(Array::column(values))) };
    // The values travel as a LET-bound name, so the function reads them as it reads a range.
    let name: Rc<str> = Rc::from("_xlagg_values");
    let span = extra.first().map_or(Default::default(), |e: &Expr| e.span);
    let mut call_args = vec![Expr { kind: ExprKind::Name(name.clone()), span }];
    call_args.extend(extra.iter().cloned());
    let id = AGGREGATE_IDS[code - 1];
    ctx.with_local(name, array, |ctx| ctx.call(id, &call_args))
}

fn subtotal(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let code = number(ctx, &args[0])?.trunc();
    let (code, hidden) = match code {
        c if (1.0..=11.0).contains(&c) => (c as usize, false),
        c if (101.0..=111.0).contains(&c) => (c as usize - 100, true),
        _ => return Err(XlError::Value),
    };
    let values = without_subtotals(ctx, &args[1..], Skip { subtotals: true, hidden, errors: false }, true)?;
    first_error_unless_counting(code, &values)?;
    Ok(call_on(ctx, code, values, &[]))
}

fn aggregate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let code = number(ctx, &args[0])?.trunc();
    let options = number(ctx, &args[1])?.trunc();
    if !(1.0..=19.0).contains(&code) || !(0.0..=7.0).contains(&options) {
        return Err(XlError::Value);
    }
    let code = code as usize;
    // Options 0–3 leave out nested subtotals, 1, 3, 5 and 7 hidden rows, 2, 3, 6 and 7 errors.
    let options = options as u8;
    let skip = Skip { subtotals: options <= 3, hidden: options % 2 == 1, errors: matches!(options, 2 | 3 | 6 | 7) };
    let (refs, extra) = if code >= 14 {
        if args.len() != 4 {
            return Err(XlError::Value);
        }
        (&args[2..3], &args[3..])
    } else {
        (&args[2..], &args[..0])
    };
    let values = without_subtotals(ctx, refs, skip, code >= 14)?;
    first_error_unless_counting(code, &values)?;
    Ok(call_on(ctx, code, values, extra))
}

/// An error in the range is the result, except for COUNT (2), which skips errors as COUNT
/// does, and COUNTA (3), which counts them: Excel's SUBTOTAL(2,…) and SUBTOTAL(3,…) over a
/// range holding #DIV/0! are numbers.
fn first_error_unless_counting(code: usize, values: &[Value]) -> XlResult<()> {
    match values.iter().find_map(Value::as_error) {
        Some(e) if !matches!(code, 2 | 3) => Err(e),
        _ => Ok(()),
    }
}
