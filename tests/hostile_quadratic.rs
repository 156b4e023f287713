//! Hostile input (issue 30): functions given an array of many keys or criteria over many
//! items (`MATCH(SEQUENCE(100000), items, 0)`, `COUNTIF(range, SEQUENCE(100000))`,
//! `FREQUENCY(SEQUENCE(2^20), SEQUENCE(2^20))`) compared every key with every item: 18 s to
//! hours. They now index the items once per call. Untimed: the large cases are sizes the
//! old code would take hours over, and inside MAP the LAMBDA work budget counts what a
//! lookup looked at. Expected values are Excel's documented rules worked out by hand, and
//! sums known by construction.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// A1:A10 the items, B1:B10 = 10, 20, …, 100 beside them.
///
/// A1 "Apple", A2 5, A3 "banana", A4 TRUE, A5 (empty), A6 "APPLE", A7 5, A8 "5", A9 3,
/// A10 #N/A.
fn items() -> Workbook {
    let mut wb = Workbook::with_sheet();
    let column = ["Apple", "5", "banana", "TRUE", "", "APPLE", "5", "'5", "3", "=NA()"];
    for (i, input) in column.iter().enumerate() {
        if !input.is_empty() {
            set(&mut wb, &format!("A{}", i + 1), input);
        }
        set(&mut wb, &format!("B{}", i + 1), &(10 * (i + 1)).to_string());
    }
    wb
}

/// The formula's result as text, set in `cell` (its items joined with commas).
fn shown(wb: &mut Workbook, cell: &str, formula: &str) -> Value {
    set(wb, cell, &format!("=TEXTJOIN(\",\",FALSE,{formula})"));
    get(wb, cell)
}

/// Each formula's result shown in `column`, one row each from row 1, against its text.
fn assert_all_shown(wb: &mut Workbook, column: char, cases: &[(String, &str)]) {
    for (i, (formula, expected)) in cases.iter().enumerate() {
        assert_eq!(shown(wb, &format!("{column}{}", i + 1), formula), t(expected), "{formula}");
    }
}

/// Each formula set in column A, one row each from row 1, against its number.
fn assert_numbers_in_column_a(wb: &mut Workbook, cases: &[(String, f64)]) {
    for (i, (formula, expected)) in cases.iter().enumerate() {
        let cell = format!("A{}", i + 1);
        set(wb, &cell, formula);
        assert_eq!(get(wb, &cell), n(*expected), "{formula}");
    }
}

fn t(s: &str) -> Value {
    Value::text(s)
}

/// Types each input into its cell.
fn set_cells(wb: &mut Workbook, cells: &[(&str, &str)]) {
    for (cell, input) in cells {
        set(wb, cell, input);
    }
}

/// The notes the workbook has on `cell`.
fn notes_at(wb: &Workbook, cell: &str) -> Vec<String> {
    let at = parse_cell(cell).unwrap();
    wb.problems().into_iter().filter(|p| p.pos == at).map(|p| p.message()).collect()
}

#[test]
fn lookups_of_many_keys_find_what_one_key_at_a_time_finds() {
    let mut wb = items();
    // Ten keys: exact matches ignore case, text "5" is not 5, wildcards match patterns.
    let keys = r#"{"apple";5;"BANANA";TRUE;"5";3;7;"b*";FALSE;"ban?na"}"#;
    assert_eq!(shown(&mut wb, "E1", &format!("IFERROR(MATCH({keys},A1:A10,0),\"na\")")), t("1,2,3,4,8,9,na,3,na,3"));
    // Last to first; mode 0 has no wildcards.
    assert_eq!(
        shown(&mut wb, "E2", &format!("IFERROR(XMATCH({keys},A1:A10,0,-1),\"na\")")),
        t("6,7,3,4,8,9,na,na,na,na")
    );
    assert_eq!(shown(&mut wb, "E3", &format!("IFERROR(XMATCH({keys},A1:A10,2),\"na\")")), t("1,2,3,4,8,9,na,3,na,3"));
    let table_keys = r#"{"APPLE";5;"5";TRUE;3;"ban*";7;"b?nana"}"#;
    let row = "10,20,80,40,90,30,na,30";
    assert_eq!(shown(&mut wb, "E4", &format!("IFERROR(VLOOKUP({table_keys},A1:B10,2,FALSE),\"na\")")), t(row));
    assert_eq!(
        shown(&mut wb, "E5", &format!("IFERROR(HLOOKUP({table_keys},TRANSPOSE(A1:B10),2,FALSE),\"na\")")),
        t(row)
    );

    // XLOOKUP: keys in D1:D8, D2 empty (an empty key finds the first, or last, empty item).
    for (i, key) in ["banana", "", "5", "x", "TRUE", "'5", "3", "Apple"].iter().enumerate() {
        if !key.is_empty() {
            set(&mut wb, &format!("D{}", i + 1), key);
        }
    }
    assert_eq!(shown(&mut wb, "E6", "XLOOKUP(D1:D8,A1:A10,B1:B10,\"none\")"), t("30,50,20,none,40,80,90,10"));
    assert_eq!(shown(&mut wb, "E7", "XLOOKUP(D1:D8,A1:A10,B1:B10,\"none\",0,-1)"), t("30,50,70,none,40,80,90,60"));
}

#[test]
fn many_keys_not_found_take_the_next_smaller_or_larger_item() {
    let mut wb = items();
    // Next smaller: 4 → 3 (A9); 6 → 5, the first of A2 and A7; nothing below 2; "c" →
    // "banana"; "a" → "5" (digits sort before letters); 5 and TRUE are found themselves.
    let keys = r#"{4;6;2;"c";"a";TRUE;5;3.5}"#;
    assert_eq!(
        shown(&mut wb, "E1", &format!("XLOOKUP({keys},A1:A10,B1:B10,\"none\",-1)")),
        t("90,20,none,30,80,40,20,90")
    );
    // Next larger, searching last to first: among equal items the last (A7 for 5, A6 for
    // "apple").
    let keys = r#"{4;2;1;"apple";"b";"a";5;3.5}"#;
    assert_eq!(
        shown(&mut wb, "E2", &format!("XLOOKUP({keys},A1:A10,B1:B10,\"none\",1,-1)")),
        t("70,90,90,60,30,60,70,70")
    );
    assert_eq!(
        shown(&mut wb, "E3", &format!("XLOOKUP({keys},A1:A10,B1:B10,\"none\",1)")),
        t("20,90,90,10,30,10,20,20")
    );
}

#[test]
fn many_criteria_count_and_sum_what_each_criterion_finds() {
    let mut wb = items();
    // Excel: "" counts empty cells and empty text, "=" empty cells only, "<>" the rest;
    // 5 and "5" count 5 and the text "5"; errors are matched by their name.
    let criteria = r##"{"apple";5;"5";TRUE;"";"=";"<>";"b*";">4";"#N/A";"=apple";"=5"}"##;
    let cases = [
        (format!("COUNTIF(A1:A10,{criteria})"), "2,3,3,1,1,1,9,1,2,1,2,3"),
        (format!("SUMIF(A1:A10,{criteria},B1:B10)"), "70,170,170,40,50,50,500,30,90,100,70,170"),
        // Rows 6 to 10 only (B > 50): A6 "APPLE", A7 5, A8 "5", A9 3, A10 #N/A.
        (format!("COUNTIFS(A1:A10,{criteria},B1:B10,\">50\")"), "1,2,2,0,0,0,5,0,1,1,1,2"),
        (
            format!("IFERROR(AVERAGEIFS(B1:B10,A1:A10,{criteria},B1:B10,\">50\"),\"d\")"),
            "60,75,75,d,d,d,80,d,70,100,60,75",
        ),
        (format!("MAXIFS(B1:B10,A1:A10,{criteria})"), "60,80,80,40,50,50,100,30,70,100,60,80"),
        (format!("MINIFS(B1:B10,A1:A10,{criteria})"), "10,20,20,40,50,50,10,30,20,100,10,20"),
        (format!("SUMIFS(B1:B10,B1:B10,\"<=70\",A1:A10,{criteria})"), "70,90,90,40,50,50,230,30,90,0,70,90"),
        // A whole column: the cells past the sheet's used area are empty too.
        (format!("COUNTIF(A:A,{criteria})"), "2,3,3,1,1048567,1048567,9,1,2,1,2,3"),
    ];
    assert_all_shown(&mut wb, 'E', &cases);
    // Comparisons match values of their own kind only: ">a" the texts after "a" ("5" sorts
    // before letters), "<TRUE" no boolean here, ">#N/A" nothing; "<>5" all but the numbers 5.
    let comparisons = r##"{">4";"<4";">=5";"<=5";">a";"<b";">=TRUE";"<TRUE";">#N/A";"<>5";">=apple";"<5"}"##;
    let cases = [
        (format!("COUNTIF(A1:A10,{comparisons})"), "2,1,2,3,3,3,1,0,0,8,3,1"),
        (format!("COUNTIF(A:A,{comparisons})"), "2,1,2,3,3,3,1,0,0,1048574,3,1"),
        (format!("COUNTIFS(A1:A10,{comparisons},B1:B10,\">50\")"), "1,1,1,2,1,2,0,0,0,4,1,1"),
        // Summed beside them (B = 10 … 100): ">a" A1, A3 and A6; "<b" A1, A6 and the text "5".
        (format!("SUMIF(A1:A10,{comparisons},B1:B10)"), "90,90,90,180,100,150,40,0,0,460,100,90"),
        (format!("SUMIFS(B1:B10,A1:A10,{comparisons},B1:B10,\"<=70\")"), "90,0,90,90,100,70,40,0,0,190,100,0"),
        // Numbers with fractions are added in row order, as one criterion at a time adds them.
        (format!("SUMIF(A1:A10,{comparisons},B1:B10/10+0.1)"), "9.2,9.1,9.2,18.3,10.3,15.3,4.1,0,0,46.8,10.3,9.1"),
    ];
    assert_all_shown(&mut wb, 'F', &cases);
    // Two criteria arrays paired item by item (A with B): each pair names the cells where
    // both hold. The text "5" is 5 to the criterion 5; "" is the empty A5; "b*" a pattern.
    let first = r##"{"apple";"apple";5;5;"5";TRUE;"";"banana";3;"#N/A";"b*"}"##;
    let second = "{10;60;20;70;80;40;50;10;90;100;30}";
    let cases = [
        (format!("COUNTIFS(A1:A10,{first},B1:B10,{second})"), "1,1,1,1,1,1,1,0,1,1,1"),
        (format!("COUNTIFS(A1:A10,{first},B1:B10,{second},B1:B10,\">50\")"), "0,1,0,1,1,0,0,0,1,1,0"),
        (format!("SUMIFS(B1:B10,A1:A10,{first},B1:B10,{second})"), "10,60,20,70,80,40,50,0,90,100,30"),
        (format!("COUNTIFS(A:A,{first},B:B,{second})"), "1,1,1,1,1,1,1,0,1,1,1"),
    ];
    assert_all_shown(&mut wb, 'H', &cases);
    // "<>" matches what "=" does not, except that "<>5" keeps the text "5" (Excel's
    // COUNTIF.xlsx in the corpus); "<>" alone counts every cell that is not empty.
    let unequal = r##"{"<>apple";"<>5";"<>TRUE";"<>";"<>#N/A";"<>3";"<>x";"<>BANANA"}"##;
    let cases = [
        (format!("COUNTIF(A1:A10,{unequal})"), "8,8,9,9,9,9,10,9"),
        (format!("COUNTIF(A:A,{unequal})"), "1048574,1048574,1048575,9,1048575,1048575,1048576,1048575"),
        (format!("COUNTIFS(A1:A10,{unequal},B1:B10,\">50\")"), "4,4,5,5,4,4,5,5"),
        (format!("SUMIF(A1:A10,{unequal},B1:B10)"), "480,460,510,500,450,460,550,520"),
    ];
    assert_all_shown(&mut wb, 'G', &cases);
}

/// Keys SEQUENCE(k) reversed over the items SEQUENCE(k): key j is found at position j, so
/// that the positions sum to k(k + 1)/2. A million keys over a million items were half a
/// million million comparisons (100,000 of each took 18–21 s).
#[test]
fn a_million_keys_over_a_million_items_are_found_by_index() {
    let k = 1_u64 << 20;
    let triangle = (k * (k + 1) / 2) as f64;
    let keys = format!("SEQUENCE({k},1,{k},-1)");
    let mut wb = Workbook::with_sheet();
    let cases = [
        (format!("=SUM(MATCH({keys},SEQUENCE({k}),0))"), triangle),
        (format!("=SUM(XLOOKUP({keys},SEQUENCE({k}),SEQUENCE({k})*2))"), 2.0 * triangle),
        (format!("=SUM(XLOOKUP({keys}+0.5,SEQUENCE({k}),SEQUENCE({k}),,-1))"), triangle),
        (format!("=COUNT(VLOOKUP({keys},HSTACK(SEQUENCE({k}),SEQUENCE({k})),2,FALSE))"), k as f64),
        // Each criterion matches one cell; SUMIF adds it.
        (format!("=SUM(COUNTIF(SEQUENCE({k}),{keys}))"), k as f64),
        (format!("=SUM(SUMIF(SEQUENCE({k}),{keys}))"), triangle),
        // "<=j" counts 1 … j.
        (format!("=SUM(COUNTIF(SEQUENCE({k}),\"<=\"&{keys}))"), triangle),
    ];
    assert_numbers_in_column_a(&mut wb, &cases);
}

/// FREQUENCY of 2^20 data in 2^20 bins (given in descending order): datum j falls in bin j,
/// one each, and none past the largest bin. Each datum tried the bins one by one: 2^39
/// comparisons.
#[test]
fn frequency_of_a_million_data_in_a_million_bins_searches_its_bins() {
    let k = 1_u64 << 20;
    let formula = format!(
        "=LET(f,FREQUENCY(SEQUENCE({k}),SEQUENCE({k},1,{k},-1)),TEXTJOIN(\",\",,ROWS(f),SUM(f),MIN(TAKE(f,{k})),TAKE(f,-1)))"
    );
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", &formula);
    assert_eq!(get(&wb, "A1"), t(&format!("{},{k},1,0", k + 1)));
    // Equal bins: the first of them holds the data (Excel: FREQUENCY({1;2;2;3},{2;2}) is
    // {3;0;1}).
    set(&mut wb, "A2", "=TEXTJOIN(\",\",,FREQUENCY({1;2;2;3},{2;2}))");
    assert_eq!(get(&wb, "A2"), t("3,0,1"));
}

/// RANK.AVG of 2^20 ones among 2^20 ones: each ties with all of them, rank (1 + 2^20)/2.
/// Each rank counted its ties one by one: 2^40 steps.
#[test]
fn ranks_among_a_million_equal_numbers_search_their_ties() {
    let k = 1_u64 << 20;
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", &format!("=SUM(RANK.AVG(SEQUENCE({k},1,1,0),SEQUENCE({k},1,1,0)))"));
    assert_eq!(get(&wb, "A1"), n((k * (k + 1) / 2) as f64));
    // Ties among others: 3 is third of {5;4;3;3;1} (RANK.EQ), 3.5 on average.
    set(&mut wb, "A2", "=TEXTJOIN(\",\",,RANK.EQ({3;5;1},{5;4;3;3;1}),RANK.AVG(3,{5;4;3;3;1}))");
    assert_eq!(get(&wb, "A2"), t("3,1,5,3.5"));
}

/// A LAMBDA work budget (`Settings::lambda_work`) of 2^22 items, checked at each call of
/// MAP's LAMBDA: a lookup of 10,000 keys counts the index it builds and one item per key,
/// well within; scanning for each key would count 50 million items and stop at the limit.
#[test]
fn many_keys_inside_a_lambda_count_the_index_not_a_scan_per_key() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(1 << 22);
    let k = 10_000_u64;
    let triangle = (k * (k + 1) / 2) as f64;
    let keys = format!("SEQUENCE({k},1,{k},-1)");
    // Two calls: the work of the first is weighed when the second starts.
    let inside = |body: String| format!("=SUM(MAP({{1;2}},LAMBDA(x,SUM({body}))))/2");
    let cases = [
        (inside(format!("MATCH({keys},SEQUENCE({k}),0)")), triangle),
        (inside(format!("XMATCH({keys},SEQUENCE({k}))")), triangle),
        (inside(format!("XLOOKUP({keys},SEQUENCE({k}),SEQUENCE({k}))")), triangle),
        (inside(format!("XLOOKUP({keys}-0.5,SEQUENCE({k}),SEQUENCE({k}),,1)")), triangle),
        (inside(format!("VLOOKUP({keys},HSTACK(SEQUENCE({k}),SEQUENCE({k})),2,FALSE)")), triangle),
        (inside(format!("HLOOKUP(TRANSPOSE({keys}),SEQUENCE(2,{k}),1,FALSE)")), triangle),
        (inside(format!("COUNTIF(SEQUENCE({k}),{keys})")), k as f64),
        (inside(format!("COUNTIF(SEQUENCE({k}),\">\"&{keys})")), (k * (k - 1) / 2) as f64),
        (inside(format!("SUMIFS(SEQUENCE({k}),SEQUENCE({k}),{keys})")), triangle),
        // "<=j" sums 1 … j, j(j + 1)/2; over all j, k(k + 1)(k + 2)/6.
        (inside(format!("SUMIF(SEQUENCE({k}),\"<=\"&{keys},SEQUENCE({k}))")), (k * (k + 1) * (k + 2) / 6) as f64),
        // Two criteria arrays paired item by item: (j, 2j) names one cell.
        (inside(format!("COUNTIFS(SEQUENCE({k}),{keys},SEQUENCE({k})*2,{keys}*2)")), k as f64),
        (inside(format!("SUMIFS(SEQUENCE({k}),SEQUENCE({k}),{keys},SEQUENCE({k})*2,{keys}*2)")), triangle),
        // The mean of 2j … 2k is j + k.
        (inside(format!("AVERAGEIF(SEQUENCE({k}),\">=\"&{keys},SEQUENCE({k})*2)")), (k * (k + 1) / 2 + k * k) as f64),
    ];
    assert_numbers_in_column_a(&mut wb, &cases);
    // "<>j" counts the cells less those equal to j, by the index: k − 1 each.
    set(&mut wb, "B1", &inside(format!("COUNTIF(SEQUENCE({k}),\"<>\"&{keys})")));
    assert_eq!(get(&wb, "B1"), n((k * (k - 1)) as f64));
    // 10,000 criteria equal to all 10,000 cells count them from the index, not cell by
    // cell (10^8 items of work, past the budget).
    set(&mut wb, "B2", &inside(format!("COUNTIF(SEQUENCE({k},1,1,0),SEQUENCE({k},1,1,0))")));
    assert_eq!(get(&wb, "B2"), n((k * k) as f64));
    set(&mut wb, "B3", &inside(format!("COUNTIF(SEQUENCE({k},1,1,0),\"<>\"&SEQUENCE({k},1,1,0))")));
    assert_eq!(get(&wb, "B3"), n(0.0));
    // A criterion no index answers (a pattern) is tested cell by cell, and counted so:
    // 10,000 criteria over 10,000 cells pass the budget.
    set(&mut wb, "B4", &inside(format!("COUNTIF(SEQUENCE({k}),\"*\"&{keys})")));
    assert_eq!(get(&wb, "B4"), Value::Error(ncsheet::eval::XlError::Num));
    let notes = notes_at(&wb, "B4");
    assert!(notes.iter().any(|m| m.contains("items of work")), "{notes:?}");
}

/// The criteria session 16 left to a scan per criterion, under the same budget of 2^22
/// items: MINIFS/MAXIFS with arrays of comparisons or of `"<>"&keys`, SUMIF with `<>`, and
/// three criteria arrays paired item by item. Scanned, 10,000 criteria over 10,000 cells
/// count 10^8 items (past the budget: `#NUM!`); indexed, a sort or a tally and a look-up or
/// two per criterion.
#[test]
fn comparisons_unequals_and_three_paired_arrays_inside_a_lambda_are_indexed() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(1 << 22);
    let k = 10_000_u64;
    let triangle = (k * (k + 1) / 2) as f64;
    let keys = format!("SEQUENCE({k},1,{k},-1)");
    let inside = |body: String| format!("=SUM(MAP({{1;2}},LAMBDA(x,SUM({body}))))/2");
    let cells = format!("SEQUENCE({k})");
    let cases = [
        // The largest below j is j − 1 (none, so 0, below 1): the sum of 0 … k − 1.
        (inside(format!("MAXIFS({cells},{cells},\"<\"&{keys})")), (k * (k - 1) / 2) as f64),
        // The smallest from j up is j.
        (inside(format!("MINIFS({cells},{cells},\">=\"&{keys})")), triangle),
        // Beside the cells (10 × their number) the largest up to j is 10j.
        (inside(format!("MAXIFS({cells}*10,{cells},\"<=\"&{keys})")), 10.0 * triangle),
        // All but j: the sum of 1 … k less j, over every j: k·k(k + 1)/2 − k(k + 1)/2.
        (inside(format!("SUMIF({cells},\"<>\"&{keys},{cells})")), (k - 1) as f64 * triangle),
        // All but j: the largest is k, or k − 1 leaving k out; the smallest 1, or 2.
        (inside(format!("MAXIFS({cells},{cells},\"<>\"&{keys})")), (k * k - 1) as f64),
        (inside(format!("MINIFS({cells},{cells},\"<>\"&{keys})")), (k + 1) as f64),
        // (j, 2j, 3j) names one cell.
        (inside(format!("COUNTIFS({cells},{keys},{cells}*2,{keys}*2,{cells}*3,{keys}*3)")), k as f64),
        (inside(format!("SUMIFS({cells},{cells},{keys},{cells}*2,{keys}*2,{cells}*3,{keys}*3)")), triangle),
    ];
    assert_numbers_in_column_a(&mut wb, &cases);
}

/// Excel's rules for MAXIFS/MINIFS over criteria arrays of comparisons and `<>`, worked
/// out by hand on the ten items: comparisons match their own kind only, "<>5" keeps the
/// text "5", and an error beside a matching cell is the result.
#[test]
fn extremes_over_many_comparisons_and_unequals_follow_excel() {
    let mut wb = items();
    let comparisons = r##"{">4";"<4";">=5";"<=5";">a";"<b";">=TRUE";"<TRUE";">#N/A";"<>5";">=apple";"<5"}"##;
    // B = 10 … 100 beside A1 … A10; B10 (beside #N/A) is matched only by "<>5".
    let cases = [
        (format!("MAXIFS(B1:B10,A1:A10,{comparisons})"), "70,90,70,90,60,80,40,0,0,100,60,90"),
        (format!("MINIFS(B1:B10,A1:A10,{comparisons})"), "20,90,20,20,10,10,40,0,0,10,10,90"),
        (format!("MAXIFS(B1:B10,A1:A10,{comparisons},B1:B10,\"<=60\")"), "20,0,20,20,60,60,40,0,0,60,60,0"),
    ];
    assert_all_shown(&mut wb, 'E', &cases);
    // With an error beside a cell a criterion matches, that error is the result.
    set(&mut wb, "B9", "=1/0");
    let unequal = r##"{"<>apple";"<>5";"<>TRUE";"<>";"<>#N/A";"<>3";"<>x";"<>BANANA"}"##;
    let cases = [
        (format!("IFERROR(MAXIFS(B1:B10,A1:A10,{unequal}),\"e\")"), "e,e,e,e,e,100,e,e"),
        (format!("IFERROR(MINIFS(B1:B10,A1:A10,{unequal},A1:A10,\"<>3\"),\"e\")"), "20,10,10,10,10,10,10,10"),
    ];
    assert_all_shown(&mut wb, 'F', &cases);
}

/// Criteria no index answers (patterns, here) are tested cell by cell: 2^16 patterns over
/// 2^16 cells would be 2^32 tests (minutes; the old code also read each pattern again for
/// every cell). A call past 10^9 such tests stops before testing any, with a note.
#[test]
fn many_patterns_over_many_cells_stop_at_the_scan_limit() {
    let mut wb = Workbook::with_sheet();
    let k = 1 << 16;
    for (cell, formula) in [
        ("A1", format!("=COUNTIF(SEQUENCE({k}),\"*\"&SEQUENCE({k}))")),
        ("A2", format!("=SUMIF(SEQUENCE({k}),\"?\"&SEQUENCE({k}),SEQUENCE({k}))")),
    ] {
        set(&mut wb, cell, &formula);
        assert_eq!(get(&wb, cell), Value::Error(ncsheet::eval::XlError::Num), "{formula}");
        let notes = notes_at(&wb, cell);
        assert!(notes.iter().any(|m| m.contains("4294967296 cells one by one")), "{notes:?}");
    }
    // Below the limit patterns match as before: "*1" the texts ending in 1, "1?" the
    // two-character texts starting with 1, "~*" a star itself.
    set(
        &mut wb,
        "B1",
        "=TEXTJOIN(\",\",,COUNTIF(TEXT(SEQUENCE(20),\"0\"),{\"*1\";\"1?\";\"~*\";\"*\";\"?\";\"2*\";\"*0\";\"<>1*\"}))",
    );
    assert_eq!(get(&wb, "B1"), t("2,10,0,20,9,2,2,9"));
}

/// A D-function inside MAP's LAMBDA counted the records it tested against the LAMBDA work
/// budget only after testing them: one call tested as many as its own limit (10^9) allows,
/// past the budget, and gave its value. Under a budget of 2^22 items, 3,000 pattern rows
/// over 3,000 records (9 million tests) now stop before testing with `#NUM!` and the
/// budget's note; 1,000 over 1,000 (a million) fit, and each record "pj" is met by its own
/// row "*j*": DCOUNTA counts all 1,000.
#[test]
fn database_functions_inside_a_lambda_weigh_their_tests_against_the_budget_first() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(1 << 22);
    let call = |k: u64| {
        let texts = format!("VSTACK(\"n\",\"p\"&SEQUENCE({k}))");
        let patterns = format!("VSTACK(\"n\",\"*\"&SEQUENCE({k})&\"*\")");
        format!("=SUM(MAP({{1}},LAMBDA(x,DCOUNTA({texts},1,{patterns}))))")
    };
    set(&mut wb, "A1", &call(1_000));
    assert_eq!(get(&wb, "A1"), n(1_000.0));
    set(&mut wb, "A2", &call(3_000));
    assert_eq!(get(&wb, "A2"), Value::Error(ncsheet::eval::XlError::Num));
    let notes = notes_at(&wb, "A2");
    assert!(notes.iter().any(|m| m.contains("items of work")), "{notes:?}");
}

/// A database's criteria range of many rows: each row was tested against every record
/// (2^17 rows × 2^17 records, 2^34 tests, hours). A row with an equality (`=x`, a
/// number, TRUE) now tests only the records filed under its value, a row with a text
/// prefix only the texts that begin with it; other rows still test every record, and past
/// 10^9 such tests the call stops before testing any.
#[test]
fn database_functions_with_many_criteria_rows_look_equalities_up() {
    let mut wb = Workbook::with_sheet();
    let k: u64 = 1 << 17;
    // Row j of the criteria names the record j: each record once, the sum k(k + 1)/2.
    let db = format!("VSTACK(\"n\",SEQUENCE({k}))");
    set(&mut wb, "A1", &format!("=DSUM({db},\"n\",{db})"));
    assert_eq!(get(&wb, "A1"), n((k * (k + 1) / 2) as f64));
    set(&mut wb, "A2", &format!("=DCOUNT({db},,VSTACK(\"n\",\"=\"&SEQUENCE({k},1,2,2)))"));
    assert_eq!(get(&wb, "A2"), n((k / 2) as f64));
    // Text with no operator is a prefix: "p7" names p7, p70 … p79, p700 …; each record
    // is named by its own row at least.
    let texts = format!("VSTACK(\"n\",\"p\"&SEQUENCE({k}))");
    set(&mut wb, "A4", &format!("=DCOUNTA({texts},1,{texts})"));
    assert_eq!(get(&wb, "A4"), n(k as f64));
    // A pattern with letters at neither end tests every record.
    let patterns = format!("VSTACK(\"n\",\"*\"&SEQUENCE({k})&\"*\")");
    set(&mut wb, "A3", &format!("=DSUM({db},\"n\",{patterns})"));
    assert_eq!(get(&wb, "A3"), Value::Error(ncsheet::eval::XlError::Num));
    let notes = notes_at(&wb, "A3");
    assert!(notes.iter().any(|m| m.contains("records one by one")), "{notes:?}");

    // Excel's rules on a small database (A5:B11): "=bolt" is the whole text, any case;
    // "bol" with no operator is a prefix; a row's conditions must all hold.
    let cells = [
        ("A5", "Part"),
        ("B5", "Qty"),
        ("A6", "bolt"),
        ("B6", "5"),
        ("A7", "Bolt"),
        ("B7", "7"),
        ("A8", "12"),
        ("B8", "1"),
        ("A9", "washer"),
        ("B9", "2"),
        ("A10", "nut"),
        ("B10", "3"),
        ("A11", "TRUE"),
        ("B11", "4"),
        ("A12", "bolts"),
        ("B12", "6"),
        ("D5", "Part"),
        ("E5", "Qty"),
        ("D6", "'=bolt"),
        ("D7", "12"),
        ("D8", "'=nut"),
        ("E8", ">3"),
        ("D9", "TRUE"),
    ];
    set_cells(&mut wb, &cells);
    let sums = "=TEXTJOIN(\",\",,DSUM(A5:B12,\"Qty\",D5:E9),DCOUNTA(A5:B12,1,D5:E9),DSUM(A5:B12,2,D5:E10))";
    set(&mut wb, "G1", sums);
    // Rows 6 (bolt), 7 (Bolt), 8 (12) and 11 (TRUE): 5 + 7 + 1 + 4. With the prefix "bol"
    // below, bolts (6) too.
    set(&mut wb, "D10", "bol");
    assert_eq!(get(&wb, "G1"), t("17,4,23"));
}

/// A database's criteria rows of patterns (`=*7`, `=?7`, `p*7`): each row tested every
/// record (2^17 rows × 2^17 records, past the 10^9 limit: `#NUM!`). A pattern now tests only
/// the texts that begin with its first letters or those that end with its last, the fewer.
#[test]
fn database_patterns_test_only_the_texts_that_begin_or_end_as_they_do() {
    let mut wb = Workbook::with_sheet();
    let k: u64 = 1 << 17;
    // Record j is the text "p" & j. "*j" names it (and longer texts ending in j), "?j" and
    // "p*j" name it too: every record meets some row.
    let texts = format!("VSTACK(\"n\",\"p\"&SEQUENCE({k}))");
    for (cell, rows) in [("A1", "\"=*\""), ("A2", "\"=?\""), ("A3", "\"=p*\"")] {
        set(&mut wb, cell, &format!("=DCOUNTA({texts},1,VSTACK(\"n\",{rows}&SEQUENCE({k})))"));
        assert_eq!(get(&wb, cell), n(k as f64), "{rows}");
    }
    // Excel's rules on a small database: a pattern with "=" is the whole text, any case;
    // without, a prefix (a star is added); "~*" is a star itself.
    let cells = [
        ("C1", "Part"),
        ("D1", "Qty"),
        ("C2", "bolt"),
        ("D2", "5"),
        ("C3", "Bolt"),
        ("D3", "7"),
        ("C4", "12"),
        ("D4", "1"),
        ("C5", "washer"),
        ("D5", "2"),
        ("C6", "nut"),
        ("D6", "3"),
        ("C7", "TRUE"),
        ("D7", "4"),
        ("C8", "bolts"),
        ("D8", "6"),
    ];
    set_cells(&mut wb, &cells);
    let criteria = [
        ("\"=*olt\"", "12"),
        ("\"=?ut\"", "3"),
        ("\"=*t\"", "15"),
        ("\"b?lt\"", "18"),
        ("\"=B?LT\"", "12"),
        ("\"=w*r\"", "2"),
        ("\"=*s\"", "6"),
        ("\"=~*\"", "0"),
        ("\"=*olt\",\"=n?t\"", "15"),
    ];
    for (i, (rows, expected)) in criteria.iter().enumerate() {
        let cell = format!("F{}", i + 1);
        set(&mut wb, &cell, &format!("=TEXT(DSUM(C1:D8,\"Qty\",VSTACK(\"Part\",{rows})),\"0\")"));
        assert_eq!(get(&wb, &cell), t(expected), "{rows}");
    }
}

/// The shapes session 17 still tested cell by cell, under a LAMBDA work budget of 2^22
/// items (10,000 criteria over 10,000 cells scanned count 10^8: `#NUM!`): COUNTIFS with a
/// comparison array beside a criterion that holds in some cells only, and five criteria
/// arrays paired item by item. Sums worked by hand.
#[test]
fn comparisons_beside_a_partial_criterion_and_five_paired_arrays_inside_a_lambda_are_indexed() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(1 << 22);
    let k = 10_000_u64;
    let triangle = (k * (k + 1) / 2) as f64;
    let keys = format!("SEQUENCE({k},1,{k},-1)");
    let inside = |body: String| format!("=SUM(MAP({{1;2}},LAMBDA(x,SUM({body}))))/2");
    let cells = format!("SEQUENCE({k})");
    let paired: String = (1..=5).map(|m| format!(",{cells}*{m},{keys}*{m}")).collect();
    let cases = [
        // The odd numbers up to j: (j + 1) div 2; over j = 1 … 10,000 (k = 2m), m(m + 1).
        (inside(format!("COUNTIFS({cells},\"<=\"&{keys},MOD({cells},2),1)")), (5_000 * 5_001) as f64),
        // Above j but 5,000: k − j, less one while j < 5,000; k(k − 1)/2 − 4,999.
        (inside(format!("COUNTIFS({cells},\">\"&{keys},{cells},\"<>5000\")")), (k * (k - 1) / 2 - 4_999) as f64),
        // (j, 2j, 3j, 4j, 5j) names one cell.
        (inside(format!("COUNTIFS({})", &paired[1..])), k as f64),
        (inside(format!("SUMIFS({cells}{paired})")), triangle),
    ];
    assert_numbers_in_column_a(&mut wb, &cases);
}

/// A database's criteria rows of one common value each look up every record they name:
/// those records are tested once a row, and count toward the 10^9 limit (2^15 rows of
/// `=1` over 2^15 records of 1 are 2^30 tests; they were not counted and ran). Inside a
/// LAMBDA they count toward its budget: 2^12 rows over 2^12 records, 2^24, pass 2^22.
#[test]
fn database_rows_of_a_common_value_count_the_records_they_test() {
    let mut wb = Workbook::with_sheet();
    let k = 1 << 15;
    let ones = format!("VSTACK(\"n\",SEQUENCE({k},1,1,0))");
    let texts = format!("VSTACK(\"n\",\"p\"&SEQUENCE({k}))");
    for (cell, formula) in [
        ("A1", format!("=DCOUNT({ones},,{ones})")),
        ("A2", format!("=DCOUNT({ones},,VSTACK(\"n\",IF(SEQUENCE({k}),\"=1\")))")),
        // "p" with no operator is a prefix every record begins with.
        ("A3", format!("=DCOUNTA({texts},1,VSTACK(\"n\",IF(SEQUENCE({k}),\"p\")))")),
    ] {
        set(&mut wb, cell, &formula);
        assert_eq!(get(&wb, cell), Value::Error(ncsheet::eval::XlError::Num), "{formula}");
        let notes = notes_at(&wb, cell);
        assert!(notes.iter().any(|m| m.contains("1073741824 records one by one")), "{notes:?}");
    }
    // Below the limit they count as before: each record meets some row.
    set(&mut wb, "B1", "=DCOUNT(VSTACK(\"n\",SEQUENCE(100,1,1,0)),,VSTACK(\"n\",SEQUENCE(100,1,1,0)))");
    assert_eq!(get(&wb, "B1"), n(100.0));

    wb.settings_mut().lambda_work = Some(1 << 22);
    let k = 1 << 12;
    let ones = format!("VSTACK(\"n\",SEQUENCE({k},1,1,0))");
    set(&mut wb, "C1", &format!("=SUM(MAP({{1;2}},LAMBDA(x,DCOUNT({ones},,{ones}))))"));
    assert_eq!(get(&wb, "C1"), Value::Error(ncsheet::eval::XlError::Num));
    let notes = notes_at(&wb, "C1");
    assert!(notes.iter().any(|m| m.contains("items of work")), "{notes:?}");
}

/// Paired criteria arrays whose item mixes an equality with a comparison were tested cell
/// by cell (10,000 items over 10,000 cells, past a LAMBDA budget of 2^22); the cells the
/// equality names are now the only ones tested. Key j (mod 1,000) names the ten cells
/// i ≡ j; those up to j are j, j − 1,000, … above 0: ⌈j/1,000⌉ of them, 1,000 × (1 + … +
/// 10) = 55,000 over all j, and their sum 192,527,500 (worked in Python by enumeration).
#[test]
fn paired_items_of_an_equality_and_a_comparison_inside_a_lambda_test_the_cells_it_names() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(1 << 22);
    let k = 10_000_u64;
    let keys = format!("SEQUENCE({k},1,{k},-1)");
    let inside = |body: String| format!("=SUM(MAP({{1;2}},LAMBDA(x,SUM({body}))))/2");
    let cells = format!("SEQUENCE({k})");
    let criteria = format!("MOD({cells},1000),MOD({keys},1000),{cells},\"<=\"&{keys}");
    let cases = [
        (inside(format!("COUNTIFS({criteria})")), 55_000.0),
        (inside(format!("SUMIFS({cells},{criteria})")), 192_527_500.0),
    ];
    assert_numbers_in_column_a(&mut wb, &cases);
}

/// A workbook of many defined names: each definition and each lookup read every name before
/// it, so reading 20,000 took 49 s (debug build) and 300,000 would take hours. Name nm_i is
/// `Sheet1!$A$1*i` and A1 is 2, so nm_i is 2i (by hand); a name defined again moves to the
/// end and the names after it move up, and a sheet's own name hides the workbook's, as in
/// Excel (names are not case-sensitive: Excel's "Define and use names in formulas").
#[test]
fn a_workbook_of_many_defined_names_reads_and_looks_them_up_in_time_proportional_to_them() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    let count = 300_000;
    for i in 0..count {
        wb.define_name_deferred(&format!("nm_{i}"), &format!("=Sheet1!$A$1*{i}"), None).unwrap();
    }
    wb.define_name_deferred("NM_5", "=Sheet1!$A$1*1000", None).unwrap();
    wb.define_name_deferred("nm_7", "=Sheet1!$A$1*-1", Some(0)).unwrap();
    set(&mut wb, "B1", &format!("=nm_{}+Nm_5+nm_7+nm_8", count - 1));
    // 2·299,999 + 2·1,000 (nm_5 redefined) − 2 (the sheet's nm_7) + 2·8.
    assert_eq!(get(&wb, "B1"), n(599_998.0 + 2_000.0 - 2.0 + 16.0));
    assert_eq!(wb.names().len(), count + 1);
}
