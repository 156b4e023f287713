//! `Range.TextToColumns` ("Range.TextToColumns method"): each cell of a one-column range is
//! split at its delimiters (`Tab`, `Semicolon`, `Comma`, `Space`, `Other` with `OtherChar`),
//! a field between text qualifiers (`"a,b"` under xlTextQualifierDoubleQuote, the default)
//! kept whole without its quotes, and the fields are typed into the row from `Destination`
//! (the range itself by default) as a user types them: `12` a number, `x` a text. With
//! `ConsecutiveDelimiter:=True` delimiters in a row make one. Fixed widths (`xlFixedWidth`)
//! and `FieldInfo` (a format per column) are refused by name.

use crate::eval::{Array, Ctx, Operand, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS};
use crate::formula::ast::SheetId;

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;

/// XlTextParsingType: xlDelimited 1, xlFixedWidth 2.
const XL_FIXED_WIDTH: f64 = 2.0;
/// XlTextQualifier: xlTextQualifierDoubleQuote 1, xlTextQualifierSingleQuote 2,
/// xlTextQualifierNone -4142.
const XL_QUALIFIER_SINGLE: f64 = 2.0;
const XL_QUALIFIER_NONE: f64 = -4142.0;

/// How the text of a cell is cut into fields.
struct Splitting {
    delimiters: Vec<char>,
    qualifier: Option<char>,
    consecutive: bool,
}

/// The fields of `text`: cut at every delimiter outside a qualified part, a qualified part's
/// doubled qualifier one character (`"say ""hi"""`), runs of delimiters one cut when
/// `consecutive`.
fn fields(text: &str, how: &Splitting) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    let mut last_was_delimiter = false;
    while let Some(c) = chars.next() {
        if Some(c) == how.qualifier {
            if quoted && chars.peek() == Some(&c) {
                field.push(c);
                chars.next();
            } else {
                quoted = !quoted;
            }
            last_was_delimiter = false;
            continue;
        }
        if !quoted && how.delimiters.contains(&c) {
            if !(how.consecutive && last_was_delimiter) {
                out.push(std::mem::take(&mut field));
            }
            last_was_delimiter = true;
            continue;
        }
        last_was_delimiter = false;
        field.push(c);
    }
    out.push(field);
    out
}

/// Whether `FieldInfo:=Array(Array(1, 1), Array(2, 1))` gives every column xlGeneralFormat
/// (1), what the macro recorder writes for a plain split: then it changes nothing.
fn all_general(info: &Value) -> bool {
    let general = |pair: &Value| match pair {
        Value::Array(p) => matches!(p.data.get(1), Some(Value::Number(n)) if *n == 1.0),
        _ => false,
    };
    match info {
        Value::Array(a) => a.data.iter().all(general),
        _ => false,
    }
}

impl Interp<'_, '_> {
    pub(super) fn text_to_columns(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        if rect.cols() != 1 {
            let why = "TextToColumns method of Range class failed: Text to Columns converts one column at a time";
            return Err(self.error_1004(link.span, why.into()));
        }
        if let Some(e) = argument(link, 1, "datatype") {
            if self.parameter_number(ctx, e, "DataType", link)? == XL_FIXED_WIDTH {
                return Err(self.unsupported(
                    link.span,
                    "TextToColumns DataType:=xlFixedWidth: ncsheet splits at delimiters only",
                ));
            }
        }
        if let Some(e) = argument(link, 10, "fieldinfo") {
            let v = ctx.eval(e).unwrap_single();
            self.take_pending()?;
            if !all_general(&v) {
                let why = "TextToColumns FieldInfo: ncsheet types every column as General (xlGeneralFormat, 1); \
                           a column read as text, as a date or skipped is not done";
                return Err(self.unsupported(link.span, why));
            }
        }
        let how = self.splitting(ctx, link)?;
        let (dest_sheet, dest) = match argument(link, 0, "destination") {
            None => (sheet, rect.first),
            Some(e) => match ctx.operand(e) {
                Operand::Ref(s, r) => (s, r.first),
                _ => return Err(self.fault_at(link.span, "TextToColumns: Destination is a Range")),
            },
        };
        self.take_pending()?;
        let rect = ctx.clip_to_used(sheet, rect);
        let texts: Vec<(u32, String)> = (rect.first.row..=rect.last.row)
            .map(|row| (row - rect.first.row, self.shown_text(ctx, sheet, Pos::new(row, rect.first.col))))
            .collect();
        for (offset, text) in texts {
            if text.is_empty() {
                continue;
            }
            let parts = fields(&text, &how);
            let row = dest.row + offset;
            let last = dest.col as usize + parts.len() - 1;
            if last >= MAX_COLS as usize {
                return Err(self.error_1004(link.span, "TextToColumns: the fields would run off the sheet".into()));
            }
            let cells = Rect::new(Pos::new(row, dest.col), Pos::new(row, last as u32));
            let items: Vec<Value> = parts.into_iter().map(Value::text).collect();
            self.write_range(dest_sheet, cells, &Value::from(Array::new(1, items.len(), items)))?;
        }
        Ok(Obj::Value(Value::Blank))
    }

    /// The delimiters, qualifier and ConsecutiveDelimiter the arguments name.
    fn splitting(&self, ctx: &mut Ctx, link: &Link) -> Run<Splitting> {
        let mut delimiters = Vec::new();
        for (position, name, c) in [(4, "tab", '\t'), (5, "semicolon", ';'), (6, "comma", ','), (7, "space", ' ')] {
            if self.parameter_flag(ctx, link, position, name)? {
                delimiters.push(c);
            }
        }
        if self.parameter_flag(ctx, link, 8, "other")? {
            let Some(e) = argument(link, 9, "otherchar") else {
                return Err(self.fault_at(link.span, "TextToColumns Other:=True needs OtherChar"));
            };
            let v = ctx.eval(e).unwrap_single();
            self.take_pending()?;
            // "OtherChar": "the first character of the string is used".
            match crate::eval::coerce::to_text(&v).ok().and_then(|t| t.chars().next()) {
                Some(c) => delimiters.push(c),
                None => return Err(self.fault_at(link.span, "TextToColumns: OtherChar is empty")),
            }
        }
        let qualifier = match argument(link, 2, "textqualifier") {
            None => Some('"'),
            Some(e) => match self.parameter_number(ctx, e, "TextQualifier", link)? {
                XL_QUALIFIER_NONE => None,
                XL_QUALIFIER_SINGLE => Some('\''),
                _ => Some('"'),
            },
        };
        let consecutive = self.parameter_flag(ctx, link, 3, "consecutivedelimiter")?;
        Ok(Splitting { delimiters, qualifier, consecutive })
    }

    fn parameter_flag(&self, ctx: &mut Ctx, link: &Link, position: usize, name: &str) -> Run<bool> {
        let Some(e) = argument(link, position, name) else { return Ok(false) };
        let v = ctx.eval(e).unwrap_single();
        self.take_pending()?;
        crate::eval::coerce::to_bool(&v)
            .map_err(|_| self.fault_at(link.span, format!("TextToColumns: {name} is True or False")))
    }

    fn parameter_number(&self, ctx: &mut Ctx, e: &crate::formula::ast::Expr, what: &str, link: &Link) -> Run<f64> {
        let v = ctx.eval(e).unwrap_single();
        self.take_pending()?;
        self.number_of(&v, &format!("TextToColumns's {what}")).map_err(|m| self.fault_at(link.span, m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_cut_at_delimiters_outside_qualifiers() {
        let comma = Splitting { delimiters: vec![','], qualifier: Some('"'), consecutive: false };
        assert_eq!(fields("a,\"b,c\",,d", &comma), ["a", "b,c", "", "d"]);
        assert_eq!(fields("\"say \"\"hi\"\"\"", &comma), ["say \"hi\""]);
        let spaces = Splitting { delimiters: vec![' '], qualifier: None, consecutive: true };
        assert_eq!(fields("G01  X10   Y5", &spaces), ["G01", "X10", "Y5"]);
    }
}
