//! Pivot tables (`xl/pivotTables/pivotTableN.xml`, named from a worksheet's relationships)
//! with their caches (`xl/pivotCache/pivotCacheDefinitionN.xml` and its records), for
//! GETPIVOTDATA. A pivot table's values are its cache's records summarised per data field
//! (`<dataField subtotal>`: sum by default); GETPIVOTDATA asks for the summary of the records
//! whose fields hold the given items. As Excel's, it answers only what the table shows: a
//! field on no axis of the table, an item hidden or absent, or a combination without records
//! is `#REF!`.

use crate::eval::dates::DateSystem;
use crate::eval::Value;
use crate::formula::address::{parse_rect, Pos, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::{PivotTables, Workbook};

use super::xml::{for_each_tag, unescape};

/// A pivot table: where it is, its fields and its cache's records.
#[derive(Debug)]
pub struct Pivot {
    sheet: SheetId,
    location: Rect,
    /// The cache's fields, in the records' order.
    fields: Vec<Field>,
    data_fields: Vec<DataField>,
    /// Each record's value per field.
    records: Vec<Vec<Value>>,
}

#[derive(Debug, Default)]
struct Field {
    name: String,
    /// The cache's shared items, which records name by index (`<x v="1"/>`).
    shared: Vec<Value>,
    /// On a row, column or page axis of the table (GETPIVOTDATA may name it).
    on_axis: bool,
    /// Shared items the table hides (`<item x="3" h="1"/>`): their records count nowhere.
    hidden: Vec<usize>,
    /// The one shared item a page field (report filter) selects.
    selected: Option<usize>,
    /// The table's items in its order (`<item x>`), which a page field's `item` indexes.
    items: Vec<usize>,
}

#[derive(Debug)]
struct DataField {
    name: String,
    field: usize,
    subtotal: String,
}

/// The parts of one pivot table, as read from the package.
pub struct PivotParts<'a> {
    pub sheet: SheetId,
    pub table: &'a [u8],
    pub definition: &'a [u8],
    pub records: &'a [u8],
    pub date_1904: bool,
}

/// Reads a pivot table with its cache; `None` when its location cannot be read.
pub fn parse_pivot(parts: &PivotParts) -> Option<Pivot> {
    let location = Rect::cell(Pos::new(0, 0));
    let mut pivot =
        Pivot { sheet: parts.sheet, location, fields: Vec::new(), data_fields: Vec::new(), records: Vec::new() };
    read_definition(parts.definition, &mut pivot, parts.date_1904);
    read_table(parts.table, &mut pivot)?;
    read_records(parts.records, &mut pivot, parts.date_1904);
    Some(pivot)
}

/// The cache's fields and their shared items.
fn read_definition(xml: &[u8], pivot: &mut Pivot, date_1904: bool) {
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"cacheField" => {
            pivot.fields.push(Field { name: tag.attr("name").map(unescape).unwrap_or_default(), ..Field::default() })
        }
        b"s" | b"n" | b"b" | b"e" | b"d" | b"m" => {
            if let Some(field) = pivot.fields.last_mut() {
                field.shared.push(item_value(tag.name, tag.attr("v"), date_1904));
            }
        }
        _ => {}
    });
}

/// The table's location, axes, hidden items, page selections and data fields.
fn read_table(xml: &[u8], pivot: &mut Pivot) -> Option<()> {
    let mut location = None;
    let mut field: Option<usize> = None;
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"location" => location = tag.attr("ref").and_then(|r| parse_rect(&unescape(r))),
        b"pivotField" => {
            let index = field.map_or(0, |f| f + 1);
            field = Some(index);
            if let Some(f) = pivot.fields.get_mut(index) {
                f.on_axis = tag.attr("axis").is_some();
            }
        }
        b"item" => {
            let Some(f) = field.and_then(|i| pivot.fields.get_mut(i)) else { return };
            let Some(x) = tag.parsed::<usize>("x") else { return };
            f.items.push(x);
            if tag.attr("h").is_some_and(|h| h == b"1" || h == b"true") {
                f.hidden.push(x);
            }
        }
        b"pageField" => {
            let (Some(fld), Some(item)) = (tag.parsed::<usize>("fld"), tag.parsed::<usize>("item")) else { return };
            if let Some(f) = pivot.fields.get_mut(fld) {
                f.selected = f.items.get(item).copied();
            }
        }
        b"dataField" => {
            let Some(fld) = tag.parsed::<usize>("fld") else { return };
            let name = tag.attr("name").map(unescape).unwrap_or_default();
            let subtotal = tag.attr("subtotal").map(unescape).unwrap_or_else(|| "sum".into());
            pivot.data_fields.push(DataField { name, field: fld, subtotal });
        }
        _ => {}
    });
    pivot.location = location?;
    Some(())
}

/// The records, each value resolved through the shared items.
fn read_records(xml: &[u8], pivot: &mut Pivot, date_1904: bool) {
    let fields = &pivot.fields;
    let records = &mut pivot.records;
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"r" => records.push(Vec::with_capacity(fields.len())),
        b"x" => {
            let Some(record) = records.last_mut() else { return };
            let shared = fields.get(record.len()).and_then(|f| f.shared.get(tag.parsed::<usize>("v")?));
            record.push(shared.cloned().unwrap_or(Value::Blank));
        }
        b"s" | b"n" | b"b" | b"e" | b"d" | b"m" => {
            if let Some(record) = records.last_mut() {
                record.push(item_value(tag.name, tag.attr("v"), date_1904));
            }
        }
        _ => {}
    });
}

/// A cache item (`<s v="East"/>`, `<n v="3"/>`, `<d v="2024-01-31T00:00:00"/>`, `<m/>`).
fn item_value(kind: &[u8], v: Option<&[u8]>, date_1904: bool) -> Value {
    let text = v.map(unescape).unwrap_or_default();
    match kind {
        b"s" => Value::text(text.as_str()),
        b"n" => text.trim().parse().map(Value::Number).unwrap_or(Value::Blank),
        b"b" => Value::Bool(text == "1" || text.eq_ignore_ascii_case("true")),
        b"e" => text.trim().parse().map(Value::Error).unwrap_or(Value::Blank),
        b"d" => date_serial(&text, date_1904).map_or(Value::text(text.as_str()), Value::Number),
        _ => Value::Blank,
    }
}

/// `2024-01-31T06:00:00` as a date serial, read as a date cell's text is.
fn date_serial(text: &str, date_1904: bool) -> Option<f64> {
    super::sheet_xml::iso_date_serial(text.trim(), DateSystem::from_1904_flag(date_1904))
}

impl Pivot {
    /// GETPIVOTDATA's answer: the data field's summary of the records holding every item of
    /// `pairs`; `Err` says why there is none (`#REF!`).
    fn value(&self, data_field: &str, pairs: &[(String, Value)]) -> Result<Value, String> {
        let data =
            self.data_field(data_field).ok_or_else(|| format!("the pivot table has no data field \"{data_field}\""))?;
        let mut wanted = Vec::with_capacity(pairs.len());
        for (name, item) in pairs {
            let index = self.fields.iter().position(|f| f.name.trim().eq_ignore_ascii_case(name.trim()));
            let Some(index) = index.filter(|&i| self.fields[i].on_axis) else {
                return Err(format!("the pivot table shows no field \"{name}\""));
            };
            wanted.push((index, item));
        }
        let mut values = Vec::new();
        let mut matched_item = vec![false; wanted.len()];
        for record in self.records.iter().filter(|r| self.shown(r)) {
            let mut all = true;
            for (k, &(field, item)) in wanted.iter().enumerate() {
                let hit = record.get(field).is_some_and(|v| same_item(v, item));
                matched_item[k] |= hit;
                all &= hit;
            }
            if all {
                values.push(record.get(data.field).cloned().unwrap_or(Value::Blank));
            }
        }
        if let Some(k) = matched_item.iter().position(|m| !m) {
            let (name, item) = &pairs[k];
            return Err(format!("the pivot table shows no item {} of \"{name}\"", shown(item)));
        }
        if values.is_empty() {
            return Err("the pivot table shows no value for these items".into());
        }
        summarise(&data.subtotal, &values)
    }

    /// The data field named as the table names it ("Sum of Score") or by its source field.
    fn data_field(&self, name: &str) -> Option<&DataField> {
        let name = name.trim();
        let source = |d: &DataField| self.fields.get(d.field).map_or("", |f| f.name.as_str());
        (self.data_fields.iter().find(|d| d.name.trim().eq_ignore_ascii_case(name)))
            .or_else(|| self.data_fields.iter().find(|d| source(d).trim().eq_ignore_ascii_case(name)))
    }

    /// Whether a record counts in the table: none of its items hidden, the page fields' items selected.
    fn shown(&self, record: &[Value]) -> bool {
        self.fields.iter().zip(record).all(|(f, v)| {
            let index = || f.shared.iter().position(|s| s == v);
            (f.hidden.is_empty() || index().is_none_or(|i| !f.hidden.contains(&i)))
                && f.selected.is_none_or(|s| index() == Some(s))
        })
    }
}

/// Whether a record's value is the item GETPIVOTDATA names: numbers by value, else by the
/// text shown, ignoring case.
fn same_item(value: &Value, item: &Value) -> bool {
    match (value, item) {
        (Value::Number(a), Value::Number(b)) => a == b,
        (a, b) => shown(a).eq_ignore_ascii_case(&shown(b)),
    }
}

fn shown(v: &Value) -> String {
    match v {
        Value::Text(t) => t.to_string(),
        Value::Number(n) => crate::formula::print::number_literal(*n),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
        Value::Error(e) => e.to_string(),
        _ => "(blank)".into(),
    }
}

/// The data field's summary (`<dataField subtotal>`) of the values of the matching records.
fn summarise(subtotal: &str, values: &[Value]) -> Result<Value, String> {
    if let Some(e) = values.iter().find_map(|v| if let Value::Error(e) = v { Some(*e) } else { None }) {
        return Ok(Value::Error(e));
    }
    let numbers: Vec<f64> =
        values.iter().filter_map(|v| if let Value::Number(n) = v { Some(*n) } else { None }).collect();
    let n = numbers.len() as f64;
    let mean = numbers.iter().sum::<f64>() / n;
    let squares = numbers.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>();
    let result = match subtotal {
        "sum" => numbers.iter().sum(),
        "count" => values.iter().filter(|v| !v.is_blank()).count() as f64,
        "countNums" => n,
        "average" if n > 0.0 => mean,
        // Without numbers Excel shows 0.
        "max" if n > 0.0 => numbers.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        "min" if n > 0.0 => numbers.iter().copied().fold(f64::INFINITY, f64::min),
        "max" | "min" => 0.0,
        "product" => numbers.iter().product(),
        "stdDev" if n > 1.0 => (squares / (n - 1.0)).sqrt(),
        "stdDevp" if n > 0.0 => (squares / n).sqrt(),
        "var" if n > 1.0 => squares / (n - 1.0),
        "varp" if n > 0.0 => squares / n,
        "average" | "stdDev" | "stdDevp" | "var" | "varp" => {
            return Ok(Value::Error(crate::eval::XlError::Div0));
        }
        other => return Err(format!("the data field's summary \"{other}\" is not one ncsheet computes")),
    };
    Ok(Value::Number(result))
}

/// The file's pivot tables, installed in the workbook for GETPIVOTDATA.
pub struct FilePivots(pub Vec<Pivot>);

impl PivotTables for FilePivots {
    fn value(&self, sheet: SheetId, at: Pos, data_field: &str, pairs: &[(String, Value)]) -> Result<Value, String> {
        let pivot = self.0.iter().find(|p| p.sheet == sheet && p.location.contains(at));
        pivot.ok_or_else(|| "the reference is in no pivot table".to_string())?.value(data_field, pairs)
    }
}

/// Installs the pivot tables read from a file.
pub fn install(wb: &mut Workbook, pivots: Vec<Pivot>) {
    if !pivots.is_empty() {
        wb.set_pivot_tables(std::rc::Rc::new(FilePivots(pivots)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The parts of Apache POI's 54436.xlsx (Excel 2010), trimmed: scores 1–5 in two categories.
    const TABLE: &[u8] = br#"<pivotTableDefinition name="PivotTable2" cacheId="30"><location ref="A8:B11" firstHeaderRow="1" firstDataRow="1" firstDataCol="1"/><pivotFields count="3"><pivotField axis="axisRow" showAll="0"><items count="3"><item x="0"/><item x="1"/><item t="default"/></items></pivotField><pivotField showAll="0"/><pivotField dataField="1" showAll="0"/></pivotFields><rowFields count="1"><field x="0"/></rowFields><dataFields count="1"><dataField name="Sum of Score" fld="2" baseField="0" baseItem="0"/></dataFields></pivotTableDefinition>"#;
    const DEFINITION: &[u8] = br#"<pivotCacheDefinition recordCount="5"><cacheFields count="3"><cacheField name="Category" numFmtId="0"><sharedItems count="2"><s v="Category 1"/><s v="Category 2"/></sharedItems></cacheField><cacheField name="Question" numFmtId="0"><sharedItems/></cacheField><cacheField name="Score" numFmtId="0"><sharedItems containsNumber="1" minValue="1" maxValue="5"/></cacheField></cacheFields></pivotCacheDefinition>"#;
    const RECORDS: &[u8] = br#"<pivotCacheRecords count="5"><r><x v="0"/><s v="Question 1"/><n v="1"/></r><r><x v="0"/><s v="Question 2"/><n v="2"/></r><r><x v="1"/><s v="Question 3"/><n v="3"/></r><r><x v="1"/><s v="Question 4"/><n v="4"/></r><r><x v="1"/><s v="Question 5"/><n v="5"/></r></pivotCacheRecords>"#;

    fn pivot(table: &[u8]) -> FilePivots {
        let parts = PivotParts { sheet: 0, table, definition: DEFINITION, records: RECORDS, date_1904: false };
        FilePivots(vec![parse_pivot(&parts).expect("a pivot table")])
    }

    fn pairs(items: &[(&str, Value)]) -> Vec<(String, Value)> {
        items.iter().map(|(f, v)| (f.to_string(), v.clone())).collect()
    }

    #[test]
    fn the_data_fields_sum_per_item_and_in_all_as_the_table_shows_them() {
        let p = pivot(TABLE);
        let at = Pos::new(7, 0);
        // The values the table shows: B9 3, B10 12, B11 (grand total) 15.
        assert_eq!(
            p.value(0, at, "Sum of Score", &pairs(&[("Category", Value::text("Category 1"))])),
            Ok(Value::Number(3.0))
        );
        assert_eq!(
            p.value(0, Pos::new(10, 1), "score", &pairs(&[("category", Value::text("CATEGORY 2"))])),
            Ok(Value::Number(12.0))
        );
        assert_eq!(p.value(0, at, "Sum of Score", &[]), Ok(Value::Number(15.0)));
    }

    #[test]
    fn what_the_table_does_not_show_is_refused() {
        let p = pivot(TABLE);
        let at = Pos::new(7, 0);
        let refused = |data: &str, items: &[(&str, Value)], at: Pos| p.value(0, at, data, &pairs(items)).is_err();
        assert!(refused("Sum of Score", &[], Pos::new(0, 0)), "a cell outside the table");
        assert!(refused("Sum of Points", &[], at), "no such data field");
        assert!(refused("Sum of Score", &[("Question", Value::text("Question 1"))], at), "a field on no axis");
        assert!(refused("Sum of Score", &[("Category", Value::text("Category 3"))], at), "no such item");
        // An item the table hides counts nowhere, the grand total included.
        let hidden = String::from_utf8_lossy(TABLE).replace(r#"<item x="1"/>"#, r#"<item x="1" h="1"/>"#);
        let p = pivot(hidden.as_bytes());
        assert!(p.value(0, at, "Sum of Score", &pairs(&[("Category", Value::text("Category 2"))])).is_err());
        assert_eq!(p.value(0, at, "Sum of Score", &[]), Ok(Value::Number(3.0)));
    }

    #[test]
    fn a_data_field_summarises_as_its_subtotal_says() {
        let with = |subtotal: &str| {
            let table =
                String::from_utf8_lossy(TABLE).replace(r#"fld="2" "#, &format!(r#"fld="2" subtotal="{subtotal}" "#));
            pivot(table.as_bytes()).value(
                0,
                Pos::new(7, 0),
                "Sum of Score",
                &pairs(&[("Category", Value::text("Category 2"))]),
            )
        };
        // Scores 3, 4, 5.
        assert_eq!(with("count"), Ok(Value::Number(3.0)));
        assert_eq!(with("average"), Ok(Value::Number(4.0)));
        assert_eq!(with("max"), Ok(Value::Number(5.0)));
        assert_eq!(with("min"), Ok(Value::Number(3.0)));
        assert_eq!(with("product"), Ok(Value::Number(60.0)));
        assert_eq!(with("var"), Ok(Value::Number(1.0)));
        assert_eq!(with("varp"), Ok(Value::Number(2.0 / 3.0)));
    }
}
