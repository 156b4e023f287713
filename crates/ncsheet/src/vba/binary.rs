//! Binary and Random files: `Open … For Binary|Random As #n [Len = n]`, `Put #n, [rec], data`,
//! `Get #n, [rec], var`, `Seek #n, pos`, and `Seek(n)`, `Loc(n)`, `EOF(n)`, `LOF(n)` of them, in
//! the sandbox of `files.rs` (the same names, the same written files, all or nothing).
//!
//! The bytes are VBA's ("Put statement" and "Get statement" in the Office VBA reference,
//! [MS-VBAL] 5.4.5.11 and 5.4.5.7): little-endian, Byte 1 byte, Boolean and Integer 2, Long
//! and Single 4, Double, Date, Currency (scaled by 10,000) and LongLong 8; a String in a
//! Binary file its characters only, in a Random file after a 2-byte length; a Variant after
//! the 2-byte VarType of what it holds (a String then with its 2-byte length). Positions
//! count from 1: bytes in a Binary file, records of `Len` bytes (128 by default) in a Random
//! one, each record padded to its length.

use std::rc::Rc;

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::functions::vba::vba_text;
use crate::eval::Value;
use crate::formula::ast::{Expr, ExprKind};

use super::ast::{Span, Target, Ty};
use super::interp::{Interp, Run};
use super::typing::Declared;
use super::value::{VArray, Var};

/// VBA's errors of record files ("Trappable errors").
const BAD_RECORD_LENGTH: (u32, &str) = (59, "Bad record length");
const BAD_RECORD_NUMBER: (u32, &str) = (63, "Bad record number");

/// A Random file's record length without `Len =` ("Open statement": 128 bytes).
const DEFAULT_RECORD: usize = 128;

/// An open Binary or Random file.
#[derive(Debug)]
pub(super) struct Channel {
    pub name: String,
    place: Place,
    /// The 0-based byte the next Put or Get without a record number starts at.
    at: usize,
    /// The record length (Random) or 1 (Binary): positions count in these.
    record: usize,
    random: bool,
    /// The last byte (Binary) or record (Random) read or written, for `Loc`; 0 before any.
    last: usize,
    /// The last Get could not read a whole item (`EOF`).
    past_end: bool,
}

/// Where an open file's bytes are: a file of the run's written files, or a listed input,
/// which is read only.
#[derive(Debug)]
enum Place {
    Written(usize),
    Input(Rc<[u8]>),
}

impl Interp<'_, '_> {
    /// `Open name For Binary|Random As #n [Len = len]`: the file of the output folder (made
    /// empty when new), or a listed input, read only.
    pub(super) fn open_record_file(
        &self,
        name: String,
        n: i64,
        random: bool,
        len: Option<&Expr>,
        span: Span,
    ) -> Run<()> {
        let record = match (random, len) {
            (false, _) => 1,
            (true, None) => DEFAULT_RECORD,
            (true, Some(e)) => match self.index(e, "the record length (Len =)")? {
                n @ 1..=32767 => n as usize,
                n => return Err(self.file_error(span, BAD_RECORD_LENGTH, format!("Open … Len = {n}"))),
            },
        };
        let input = self.access().inputs.iter().find(|(i, _)| i.eq_ignore_ascii_case(&name)).map(|(_, b)| b.clone());
        let place = match input {
            Some(bytes) => Place::Input(bytes),
            None => Place::Written(self.open_for_writing("Open", &name, true, span)?),
        };
        let channel = Channel { name, place, at: 0, record, random, last: 0, past_end: false };
        self.files.borrow_mut().records.insert(n, channel);
        Ok(())
    }

    /// `EOF`, `LOF`, `Loc` and `Seek` of an open Binary or Random file; `None` when file `n`
    /// is no such file.
    pub(super) fn record_file_query(&self, what: &str, n: i64) -> Option<Value> {
        let files = self.files.borrow();
        let c = files.records.get(&n)?;
        let length = match &c.place {
            Place::Written(i) => files.written[*i].1.len(),
            Place::Input(bytes) => bytes.len(),
        };
        Some(match what {
            "eof" => Value::Bool(c.past_end),
            "lof" => Value::Number(length as f64),
            "loc" => Value::Number(c.last as f64),
            // The next byte or record ("Seek function").
            _ => Value::Number((c.at / c.record + 1) as f64),
        })
    }

    /// Where a Put or Get starts: record `record` (1-based; a byte in a Binary file), or the
    /// current position.
    fn record_start(&self, n: i64, record: Option<&Expr>, span: Span) -> Run<usize> {
        let position = match record {
            Some(e) => Some(self.index(e, "the record number")?),
            None => None,
        };
        let files = self.files.borrow();
        let c = files.records.get(&n).ok_or_else(|| self.not_a_record_file(n, span))?;
        match position {
            None => Ok(c.at),
            Some(p) if p >= 1 => Ok((p as usize - 1).saturating_mul(c.record)),
            Some(p) => Err(self.file_error(span, BAD_RECORD_NUMBER, format!("record {p} of \"{}\"", c.name))),
        }
    }

    fn not_a_record_file(&self, n: i64, span: Span) -> super::interp::Fault {
        let open = self.files.borrow().is_numbered(n);
        let why = if open { "open for Input, Output or Append, not Binary or Random" } else { "not open" };
        let code = if open { (54, "Bad file mode") } else { (52, "Bad file name or number") };
        self.file_error(span, code, format!("file #{n} is {why}"))
    }

    /// `Put #n, [record], data`.
    pub(super) fn put_record(&self, number: &Expr, record: Option<&Expr>, data: &Expr, span: Span) -> Run<()> {
        let n = self.file_no(number)?;
        let start = self.record_start(n, record, span)?;
        let random = self.files.borrow().records.get(&n).is_some_and(|c| c.random);
        let bytes = match self.var_of(data, false)? {
            Var::Value(value) => {
                let declared = self.declared_type(data);
                let date = self.as_date(data, &value).is_some();
                // A fixed-length String is its characters alone, in a Random file too.
                let fixed = matches!(&data.kind, ExprKind::Name(name)
                    if matches!(self.with_slot(name, |s| s.ty.clone()).flatten(), Some(Ty::FixedString(_))));
                match self.variant_number_type(declared, data, &value) {
                    Some(held) => held_variant_bytes(held, &value),
                    None => put_bytes(declared, &value, date, random && !fixed),
                }
            }
            whole @ (Var::Array(_) | Var::Record(..)) => {
                let (ty, fixed) = match &data.kind {
                    ExprKind::Name(name) => self.with_slot(name, |s| (s.ty.clone(), s.fixed)).unwrap_or_default(),
                    _ => (None, false),
                };
                self.composite_bytes(&whole, ty.as_ref(), random, false, fixed)
            }
            Var::Obj(_) => Err(Unput::Ours("an object is not written to a file (Put # writes values)".into())),
        };
        let bytes = bytes.map_err(|why| match why {
            Unput::Vba(m) => self.fault_at(span, format!("Put #{n}: {m}")),
            Unput::Ours(m) => self.unsupported(span, format!("Put #{n}: {m}")),
        })?;
        self.charge(bytes.len() as u64, span)?;
        let mut files = self.files.borrow_mut();
        let super::files::Files { records, written, .. } = &mut *files;
        let c = records.get_mut(&n).expect("checked by record_start");
        if c.random && bytes.len() > c.record {
            let what = format!("Put #{n}: {} bytes in a record of {} (Len =)", bytes.len(), c.record);
            return Err(self.file_error(span, BAD_RECORD_LENGTH, what));
        }
        let Place::Written(i) = c.place else {
            let what = format!("Put #{n}: \"{}\" is an input (--in-file), which a run never writes", c.name);
            return Err(self.file_error(span, (75, "Path/File access error"), what));
        };
        let file = &mut written[i].1;
        // A record is written whole: what it does not fill is zeros in a new file's part.
        let end = start + bytes.len().max(c.record);
        if file.len() < end {
            file.resize(end, 0);
        }
        file[start..start + bytes.len()].copy_from_slice(&bytes);
        c.at = start + if c.random { c.record } else { bytes.len() };
        c.last = if c.random { start / c.record + 1 } else { start + bytes.len() };
        Ok(())
    }

    /// The type a Variant's number is held as, where it is not a Double or a Date (`v = 5`
    /// holds an Integer): Put writes that type's VarType and bytes ("Put statement": "a
    /// Variant of a numeric type" is 2 bytes of its VarType, then the variable). `None` for
    /// any other value or declared type.
    fn variant_number_type(&self, declared: Declared, data: &Expr, value: &Value) -> Option<Declared> {
        if declared != Declared::Variant || !matches!(value, Value::Number(_)) {
            return None;
        }
        match self.value_type(data, value) {
            held @ (Declared::Byte
            | Declared::Integer
            | Declared::Long
            | Declared::LongLong
            | Declared::Single
            | Declared::Currency) => Some(held),
            _ => None,
        }
    }

    /// `Get #n, [record], var`: reads what the variable's declared type says (a Variant
    /// what its VarType says); past the end the missing bytes read as zeros and `EOF` is True.
    pub(super) fn get_record(&self, number: &Expr, record: Option<&Expr>, target: &Target, span: Span) -> Run<()> {
        let n = self.file_no(number)?;
        let start = self.record_start(n, record, span)?;
        let (name, index) = match target {
            Target::Var(name) => (name, None),
            Target::Element(name, index) => (name, Some(index)),
            Target::Node(_) => return Err(self.fault_at(span, "Get # reads into a variable or an array's item")),
        };
        let ty = self.with_slot(name, |s| s.ty.clone()).flatten();
        if index.is_none() {
            if let Some(shape @ (Var::Array(_) | Var::Record(..))) = self.lookup(name) {
                let fixed = self.with_slot(name, |s| s.fixed).unwrap_or_default();
                return self.get_composite(n, start, name, (&shape, fixed), ty.as_ref(), span);
            }
        }
        let declared = Declared::of_ty(ty.as_ref());
        // A String in a Binary file is read for as many characters as the variable holds.
        let current = match index {
            None => self.lookup(name),
            Some(index) => self.array_item(name, index, span).ok(),
        };
        let held = match current {
            Some(Var::Value(Value::Text(t))) => t.chars().count(),
            _ => 0,
        };
        let fixed = matches!(ty, Some(Ty::FixedString(_)));
        let ((value, date), read) = self
            .read_at(n, start, |reader, random| reader.item(declared, random && !fixed, held))
            .map_err(|m| self.fault_at(span, m))?;
        match index {
            None => {
                self.set_var(name, Var::Value(value), span)?;
                let holds = match (date, declared) {
                    (true, _) => Declared::Date,
                    (false, Declared::Variant) => self.variant_number_type_at(n, start),
                    _ => Declared::Variant,
                };
                self.with_slot(name, |s| s.set_holds(holds));
            }
            Some(index) => self.set_element(name, index, value, date, span)?,
        }
        self.moved_past(n, start, read);
        Ok(())
    }

    /// The type of the number a Variant read at `start` of file `n` holds, by the VarType Put
    /// wrote first (`Variant` where it is a Double or no number).
    fn variant_number_type_at(&self, n: i64, start: usize) -> Declared {
        let code = self.read_at(n, start, |reader, _| Ok(u16::from_le_bytes(reader.take()))).map_or(0, |(c, _)| c);
        match var_type_declared(code) {
            Some(
                held @ (Declared::Byte
                | Declared::Integer
                | Declared::Long
                | Declared::LongLong
                | Declared::Single
                | Declared::Currency),
            ) => held,
            _ => Declared::Variant,
        }
    }

    /// Reads with `read` (given the reader and whether the file is Random) from file `n`'s
    /// bytes at `start`; returns what it read and the reader, for [`Interp::moved_past`].
    fn read_at<T>(
        &self,
        n: i64,
        start: usize,
        read: impl FnOnce(&mut Reader, bool) -> Result<T, String>,
    ) -> Result<(T, (usize, bool)), String> {
        let files = self.files.borrow();
        let c = files.records.get(&n).expect("checked by record_start");
        let bytes: &[u8] = match &c.place {
            Place::Written(i) => &files.written[*i].1,
            Place::Input(bytes) => bytes,
        };
        let mut reader = Reader { bytes, at: start, past_end: false };
        let value = read(&mut reader, c.random)?;
        Ok((value, (reader.at - start, reader.past_end)))
    }

    /// After a Get of `read` bytes (and whether it ran past the end) at `start`: the next
    /// position, `Loc` and `EOF` of file `n`.
    fn moved_past(&self, n: i64, start: usize, (read, past_end): (usize, bool)) {
        let mut files = self.files.borrow_mut();
        let c = files.records.get_mut(&n).expect("checked by record_start");
        c.at = start + if c.random { c.record } else { read };
        c.last = if c.random { start / c.record + 1 } else { start + read };
        c.past_end = past_end;
    }

    /// The bytes `Put` writes for a Type value or an array ("Put statement"): a Type's members
    /// one after the other in their declared order, without padding, a String member after
    /// its 2-byte length even in a Binary file ("Put writes variable-length strings that are
    /// not elements of user-defined types without the 2-byte length descriptor"); an array's
    /// items in order, without a descriptor in a Binary file ("For any array other than an
    /// array in a user-defined type, Put writes only the data"). In a Random file VBA writes
    /// a descriptor before a dynamic array, whose content its reference does not give: such
    /// a Put is refused; a fixed-size array (`fixed`: a variable Dim gave its bounds) is its
    /// data alone there too ("If the variable being written is a fixed-size array, Put writes
    /// only the data. No descriptor is written to disk"). A two-dimensional array goes in VBA's memory order, the first index
    /// varying fastest ([`file_order`]).
    fn composite_bytes(
        &self,
        var: &Var,
        ty: Option<&Ty>,
        random: bool,
        member: bool,
        fixed: bool,
    ) -> Result<Vec<u8>, Unput> {
        match var {
            Var::Value(v) => match Declared::of_ty(ty) {
                // A fixed-length String field is its characters alone ("Put statement").
                _ if matches!(ty, Some(Ty::FixedString(_))) => string_bytes(v, false),
                Declared::String if member => string_bytes(v, true),
                declared => put_bytes(declared, v, false, random),
            },
            Var::Record(t, fields) => {
                let mut out = Vec::new();
                for (field, (_, field_ty)) in fields.iter().zip(&self.module.types[*t].fields) {
                    out.extend(self.composite_bytes(field, Some(field_ty), random, true, false)?);
                }
                Ok(out)
            }
            Var::Array(a) => {
                whole_array_layout(a, random && !fixed).map_err(Unput::Ours)?;
                let mut out = Vec::new();
                for k in file_order(a) {
                    let item = a.item(k);
                    match &item {
                        Var::Value(v) if matches!(Declared::of_ty(ty), Declared::Variant) => {
                            out.extend(variant_bytes(v, a.holds_date(k))?)
                        }
                        _ => out.extend(self.composite_bytes(&item, ty, random, member, false)?),
                    }
                }
                Ok(out)
            }
            Var::Obj(_) => Err(Unput::Ours("an object is not written to a file (Put # writes values)".into())),
        }
    }

    /// `Get #n, [record], var` into a whole Type variable or array: read as
    /// [`Interp::composite_bytes`] writes it, in the shape the variable has.
    fn get_composite(
        &self,
        n: i64,
        start: usize,
        name: &std::rc::Rc<str>,
        (shape, fixed): (&Var, bool),
        ty: Option<&Ty>,
        span: Span,
    ) -> Run<()> {
        let (var, read) = self
            .read_at(n, start, |reader, random| self.read_composite(reader, (shape, fixed), ty, random, false))
            .map_err(|m| self.fault_at(span, format!("Get #{n}: {m}")))?;
        self.with_slot(name, |s| s.replace(var));
        self.moved_past(n, start, read);
        Ok(())
    }

    /// A Type value or an array of `shape`'s form read from `reader`.
    fn read_composite(
        &self,
        reader: &mut Reader,
        (shape, fixed): (&Var, bool),
        ty: Option<&Ty>,
        random: bool,
        member: bool,
    ) -> Result<Var, String> {
        match shape {
            Var::Value(v) => {
                let held = match v {
                    Value::Text(t) => t.chars().count(),
                    _ => 0,
                };
                let counted = (random || member) && !matches!(ty, Some(Ty::FixedString(_)));
                let (value, _) = reader.item(Declared::of_ty(ty), counted, held)?;
                Ok(Var::Value(value))
            }
            Var::Record(t, fields) => {
                let mut read = Vec::with_capacity(fields.len());
                for (field, (_, field_ty)) in fields.iter().zip(&self.module.types[*t].fields) {
                    read.push(self.read_composite(reader, (field, false), Some(field_ty), random, true)?);
                }
                Ok(Var::Record(*t, read))
            }
            Var::Array(a) => {
                whole_array_layout(a, random && !fixed)?;
                if let Some(records) = &a.records {
                    // An array of a Type: each item read as a Type value, in the file's order.
                    let mut read = records.as_ref().clone();
                    for k in file_order(a) {
                        read[k] = self.read_composite(reader, (&records[k], false), ty, random, member)?;
                    }
                    return Ok(Var::Array(VArray { records: Some(Rc::new(read)), ..a.clone() }));
                }
                let mut items = a.data.as_ref().clone();
                let mut dates = Vec::new();
                for k in file_order(a) {
                    let (value, date) = match Declared::of_ty(ty) {
                        Declared::Variant => reader.variant()?,
                        _ => match self.read_composite(reader, (&a.item(k), false), ty, random, member)? {
                            Var::Value(v) => (v, false),
                            _ => return Err("an array of objects or Type values is not read here".into()),
                        },
                    };
                    items.data[k] = value;
                    dates.push((k, date));
                }
                let mut array = a.clone();
                array.data = std::rc::Rc::new(items);
                for (k, date) in dates {
                    array.mark_date(k, date);
                }
                Ok(Var::Array(array))
            }
            Var::Obj(_) => Err("an object is not read from a file".into()),
        }
    }

    /// `Seek #n, position`: the byte (Binary) or record (Random) the next Put or Get uses.
    pub(super) fn seek_record(&self, number: &Expr, position: &Expr, span: Span) -> Run<()> {
        let n = self.file_no(number)?;
        let start = self.record_start(n, Some(position), span)?;
        if let Some(c) = self.files.borrow_mut().records.get_mut(&n) {
            c.at = start;
        }
        Ok(())
    }
}

/// The row-major positions of `a`'s items in the order a file holds them: VBA lays an array
/// out with its first index varying fastest (column-major: `a(1, 1), a(2, 1), …, a(1, 2)`),
/// which is why `ReDim Preserve` may change only the last dimension ("ReDim statement").
fn file_order(a: &super::value::VArray) -> impl Iterator<Item = usize> {
    a.memory_order().into_iter()
}

/// Whether Put and Get take array `a` whole: in a Binary file, no objects.
fn whole_array_layout(a: &super::value::VArray, random: bool) -> Result<(), String> {
    if random {
        return Err("a whole dynamic array in a Random file comes after a descriptor VBA's reference does not lay \
                    out; Put and Get its items, or use a Binary file or a fixed-size array"
            .into());
    }
    if a.objects.as_ref().is_some_and(|o| !o.is_empty()) {
        return Err("an array holding objects is not written to a file".into());
    }
    Ok(())
}

/// Why `Put` wrote nothing: VBA's own error (a type mismatch, an overflow), which `On Error`
/// traps, or ncsheet's refusal of what VBA would write (a character outside Windows-1252, a
/// layout VBA's reference does not give), which it does not: a trapped one left the file
/// without the record and the macro going on as if it were there.
enum Unput {
    Vba(String),
    Ours(String),
}

impl From<String> for Unput {
    fn from(m: String) -> Self {
        Unput::Vba(m)
    }
}

/// The bytes `Put` writes for `v` of the declared type `declared`: a Variant's with its
/// VarType first; `date`: the value is a Date (a Variant's VarType 7).
fn put_bytes(declared: Declared, v: &Value, date: bool, random: bool) -> Result<Vec<u8>, Unput> {
    let number = || to_number(v, DateSystem::From1900).map_err(|e| format!("{e} is not a number (type mismatch)"));
    let whole = |low: f64, high: f64, ty: &str| -> Result<i64, String> {
        let n = number()?.round_ties_even();
        match (low..=high).contains(&n) {
            true => Ok(n as i64),
            false => Err(format!("{n} does not fit in {ty}: overflow (run-time error 6)")),
        }
    };
    Ok(match declared {
        Declared::Byte => vec![whole(0.0, 255.0, "a Byte")? as u8],
        Declared::Boolean => {
            (if crate::eval::coerce::to_bool(v).map_err(|e| e.to_string())? { -1i16 } else { 0 }).to_le_bytes().to_vec()
        }
        Declared::Integer => (whole(-32768.0, 32767.0, "an Integer")? as i16).to_le_bytes().to_vec(),
        Declared::Long => (whole(-2147483648.0, 2147483647.0, "a Long")? as i32).to_le_bytes().to_vec(),
        Declared::LongLong => {
            whole(-super::ast::LONG_LONG_END, super::ast::LONG_LONG_END - 1024.0, "a LongLong")?.to_le_bytes().to_vec()
        }
        Declared::Single => (number()? as f32).to_le_bytes().to_vec(),
        Declared::Double | Declared::Date => number()?.to_le_bytes().to_vec(),
        Declared::Currency => ((number()? * 10000.0).round() as i64).to_le_bytes().to_vec(),
        Declared::Decimal => return Err(Unput::Ours("a Decimal is not written here".into())),
        Declared::String => string_bytes(v, random)?,
        Declared::Variant => variant_bytes(v, date)?,
    })
}

/// A Variant holding a number of the type `held`: its VarType in 2 bytes, then the number
/// as that type's bytes.
fn held_variant_bytes(held: Declared, v: &Value) -> Result<Vec<u8>, Unput> {
    let var_type = held.var_type().expect("a numeric type has a VarType") as u16;
    Ok([var_type.to_le_bytes().to_vec(), put_bytes(held, v, false, false)?].concat())
}

/// A String's bytes in Windows-1252: in a Random file (or a Variant) after its 2-byte length.
fn string_bytes(v: &Value, counted: bool) -> Result<Vec<u8>, Unput> {
    let text = vba_text(v).map_err(|e| format!("{e} is not a text (type mismatch)"))?;
    let bytes = super::files::ansi_bytes(&text).map_err(Unput::Ours)?;
    if !counted {
        return Ok(bytes);
    }
    let len = u16::try_from(bytes.len()).map_err(|_| Unput::Ours("a String longer than 65,535 characters".into()))?;
    Ok([len.to_le_bytes().to_vec(), bytes].concat())
}

/// A Variant's bytes: its VarType in 2 bytes, then its value (a String with its length).
fn variant_bytes(v: &Value, date: bool) -> Result<Vec<u8>, Unput> {
    let (var_type, body): (u16, Vec<u8>) = match v {
        Value::Blank => (0, Vec::new()),
        Value::Null => (1, Vec::new()),
        Value::Number(n) => (if date { 7 } else { 5 }, n.to_le_bytes().to_vec()),
        Value::Text(_) => (8, string_bytes(v, true)?),
        Value::Bool(b) => (11, (if *b { -1i16 } else { 0 }).to_le_bytes().to_vec()),
        // An Error Variant holds VBA's SCODE of the error number (CVErr's).
        Value::Error(e) => {
            let number = super::files::error_number(*e).unwrap_or(2015);
            (10, (0x800A_0000u32 + number).to_le_bytes().to_vec())
        }
        Value::Array(_) | Value::Lambda(_) => {
            return Err(Unput::Ours("an array in a Variant is not written (Put a typed array's items)".into()))
        }
    };
    Ok([var_type.to_le_bytes().to_vec(), body].concat())
}

/// Reads items from a file's bytes; what lies past the end reads as zeros.
struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
    past_end: bool,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        for (k, b) in out.iter_mut().enumerate() {
            match self.bytes.get(self.at + k) {
                Some(&byte) => *b = byte,
                None => self.past_end = true,
            }
        }
        self.at += N;
        out
    }

    fn text(&mut self, len: usize) -> Value {
        let end = self.at + len;
        if end > self.bytes.len() {
            self.past_end = true;
        }
        let bytes = &self.bytes[self.at.min(self.bytes.len())..end.min(self.bytes.len())];
        self.at = end;
        Value::Text(super::files::ansi_text(bytes))
    }

    /// An item of the declared type; `random`: a String has its length before it; `held`:
    /// the characters a String variable holds (a Binary file's String reads as many).
    /// Returns the value and whether it is a Date.
    fn item(&mut self, declared: Declared, random: bool, held: usize) -> Result<(Value, bool), String> {
        let number = Value::Number;
        Ok(match declared {
            Declared::Byte => (number(f64::from(self.take::<1>()[0])), false),
            Declared::Boolean => (Value::Bool(i16::from_le_bytes(self.take()) != 0), false),
            Declared::Integer => (number(f64::from(i16::from_le_bytes(self.take()))), false),
            Declared::Long => (number(f64::from(i32::from_le_bytes(self.take()))), false),
            Declared::LongLong => (number(i64::from_le_bytes(self.take()) as f64), false),
            Declared::Single => (number(f64::from(f32::from_le_bytes(self.take()))), false),
            Declared::Double => (number(f64::from_le_bytes(self.take())), false),
            Declared::Date => (number(f64::from_le_bytes(self.take())), true),
            Declared::Currency => (number(i64::from_le_bytes(self.take()) as f64 / 10000.0), false),
            Declared::Decimal => return Err("Get #: a Decimal is not read here".into()),
            Declared::String if random => {
                let len = u16::from_le_bytes(self.take());
                (self.text(usize::from(len)), false)
            }
            Declared::String => (self.text(held), false),
            Declared::Variant => self.variant()?,
        })
    }

    /// A Variant: its 2-byte VarType, then the value of that type.
    fn variant(&mut self) -> Result<(Value, bool), String> {
        let var_type = u16::from_le_bytes(self.take());
        let declared = match var_type {
            0 => return Ok((Value::Blank, false)),
            1 => return Ok((Value::Null, false)),
            other => var_type_declared(other)
                .ok_or_else(|| format!("Get #: a Variant of VarType {other} is not read here"))?,
        };
        self.item(declared, true, 0)
    }
}

/// The type of a Variant's value by its VarType ("VarType function": vbInteger 2 …
/// vbLongLong 20), for the types a file holds; `None` for the rest.
fn var_type_declared(var_type: u16) -> Option<Declared> {
    Some(match var_type {
        2 => Declared::Integer,
        3 => Declared::Long,
        4 => Declared::Single,
        5 => Declared::Double,
        6 => Declared::Currency,
        7 => Declared::Date,
        8 => Declared::String,
        11 => Declared::Boolean,
        17 => Declared::Byte,
        20 => Declared::LongLong,
        _ => return None,
    })
}
