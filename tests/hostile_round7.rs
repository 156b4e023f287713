//! Hostile input (issue 30), a seventh round of variants (session 20): each test is a class
//! the round reached that the earlier fixes did not cover. Values come from outside our code:
//! arithmetic worked by hand.

mod common;

use ncsheet::eval::{Value, XlError};

/// MINVERSE and MDETERM of a matrix the array limit allows but whose LU decomposition is
/// billions of steps (n³): `MINVERSE(RANDARRAY(3000,3000))` ran past 30 s and 4,096 × 4,096
/// would take minutes. Past 10^9 steps (n > 1000) they are `#NUM!` before any work, with the
/// limit in the cell's note; at the limit they still compute: the identity matrix is its own
/// inverse and its determinant is 1, whatever its size (by hand).
#[test]
fn matrix_inverses_past_the_work_limit_are_num_with_a_note() {
    for formula in ["=SUM(MINVERSE(MUNIT(1001)))", "=MDETERM(MUNIT(1001))"] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Num), "{formula}");
        assert!(notes.iter().any(|n| n.contains("1001 × 1001 matrix") && n.contains("1e9")), "{formula}: {notes:?}");
    }
    assert_eq!(common::sheet::eval_a1("=SUM(MINVERSE(MUNIT(1000)))").0, Value::Number(1000.0));
    assert_eq!(common::sheet::eval_a1("=MDETERM(MUNIT(1000))").0, Value::Number(1.0));
}

/// MMULT of matrices the array limit allows but whose product is tens of billions of
/// multiply-adds (rows × inner size × columns): two 4,096 × 4,096 matrices took 13 s and a
/// cell of three such products ran past 30 s. Past 4·10^9 it is `#NUM!` before any work, the
/// limit in the cell's note: 4,000 × 251 by 251 × 4,000 is 4,016,000,000 (by hand).
#[test]
fn matrix_products_past_the_work_limit_are_num_with_a_note() {
    let formula = "=SUM(MMULT(SEQUENCE(4000,251,0,0),SEQUENCE(251,4000,0,0)))";
    let (value, notes, _) = common::sheet::eval_a1(formula);
    assert_eq!(value, Value::Error(XlError::Num), "{formula}");
    assert!(notes.iter().any(|n| n.contains("4016000000 multiply-adds") && n.contains("4e9")), "{notes:?}");
    // Inside the limit it computes: a row of 251 ones by a column of 251 twos is 502.
    assert_eq!(common::sheet::eval_a1("=MMULT(SEQUENCE(1,251,1,0),SEQUENCE(251,1,2,0))").0, Value::Number(502.0));
}

/// Operators and lifted functions over arrays of long texts make small items (TRUE, a
/// position) but read each pair of texts whole: 100 × 4,000 texts of 30,000 characters
/// compared took 53 s, FIND of them 119 s, SEARCH of 100,000 needles in one 32,000-character
/// text 77 s. The texts read for one array count against 512 MiB (2^29 bytes): 100 × 200
/// pairs of 30,001–30,003 characters read 1.2·10^9 bytes, 20,000 FINDs in a 32,000-character
/// text 6.4·10^8 (by hand) — `#NUM!` with the note; ten by ten texts of a thousand
/// characters compare as ever (the ten equal pairs, by hand).
#[test]
fn texts_read_for_one_array_count_against_their_limit() {
    for formula in [
        "=SUM(--(REPT(\"a\",30000)&SEQUENCE(100)>REPT(\"a\",30000)&SEQUENCE(1,200)))",
        "=ROWS(FIND(SEQUENCE(20000)&\"\",REPT(\"a\",32000)))",
    ] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Num), "{formula}");
        assert!(notes.iter().any(|n| n.contains("read more than 512 MiB of text")), "{formula}: {notes:?}");
    }
    let within = "=SUM(--(REPT(\"a\",1000)&SEQUENCE(10)=REPT(\"a\",1000)&SEQUENCE(1,10)))";
    assert_eq!(common::sheet::eval_a1(within).0, Value::Number(10.0));
}

/// FIND and SEARCH of a needle without wildcards search in linear time (a needle compared
/// at each place was text × needle steps: 16,000 characters in 32,767 took 0.3 s a call), and
/// SEARCH folds a text searched by many needles once. The answers, by hand: the only "b" of
/// 32,000 "a" and a "b" ends the first match of 16,000 "a" and a "b" at 32,001 − 16,000 =
/// 16,001; case is ignored by SEARCH only; a character past U+FFFF counts two (Excel counts
/// UTF-16 units), and the start counts units too.
#[test]
fn find_and_search_of_long_needles_answer_by_position() {
    let cases = [
        ("=FIND(REPT(\"a\",16000)&\"b\",REPT(\"a\",32000)&\"b\")", Value::Number(16001.0)),
        ("=SEARCH(REPT(\"A\",16000)&\"B\",REPT(\"a\",32000)&\"b\")", Value::Number(16001.0)),
        ("=FIND(REPT(\"A\",16000)&\"B\",REPT(\"a\",32000)&\"b\")", Value::Error(XlError::Value)),
        ("=SEARCH(\"É\",\"aé\u{1F600}É\")", Value::Number(2.0)),
        ("=SEARCH(\"É\",\"aé\u{1F600}É\",3)", Value::Number(5.0)),
        ("=FIND(\"É\",\"aé\u{1F600}É\")", Value::Number(5.0)),
        ("=SEARCH(\"~?\",\"ab?c\")", Value::Number(3.0)),
        // Wildcards: the part before the first `*` sought as text (no `?` in it), the rest once
        // after it; 16,000 "a" and `*b` first fit at 1 and the one "b" ends the text.
        ("=SEARCH(REPT(\"A\",16000)&\"*B\",REPT(\"a\",32000)&\"b\")", Value::Number(1.0)),
        ("=SEARCH(REPT(\"A\",16000)&\"*C\",REPT(\"a\",32000)&\"b\")", Value::Error(XlError::Value)),
        ("=SEARCH(\"É*X\",\"aé\u{1F600}Éx\")", Value::Number(2.0)),
        ("=SEARCH(\"b?d*\",\"ABCD\")", Value::Number(2.0)),
        ("=SEARCH(\"b?d*\",\"ÀBCD\")", Value::Number(2.0)),
        ("=FIND(\"\",\"abc\",4)", Value::Number(4.0)),
        ("=FIND(\"\",\"abc\",5)", Value::Error(XlError::Value)),
        // 20,000 needles in one text of 32,000 characters: read, 6.4·10^8 bytes, past the limit.
        ("=ROWS(SEARCH(SEQUENCE(20000)&\"\",REPT(\"a\",32000)))", Value::Error(XlError::Num)),
    ];
    for (formula, expected) in cases {
        assert_eq!(common::sheet::eval_a1(formula).0, expected, "{formula}");
    }
}

/// TEXTSPLIT, TEXTBEFORE and TEXTAFTER seek each distinct delimiter through the text once:
/// trying each of a thousand delimiters of 16,000 characters at each place of a 32,000-character
/// text ran past 30 s. What the searches read (the text once per delimiter, and the
/// delimiters) counts against the limit of 512 MiB (2^29) that an array's texts read have:
/// 20,000 delimiters through 32,000 characters read 6.4·10^8 (by hand), `#NUM!` with the note.
/// At each place the longest delimiter that starts there cuts (";;" before ";").
#[test]
fn text_split_reads_the_text_once_per_delimiter() {
    let none_found = "=COUNTA(TEXTSPLIT(REPT(\"a\",32000),REPT(\"a\",16000)&SEQUENCE(1,1000)))";
    assert_eq!(common::sheet::eval_a1(none_found).0, Value::Number(1.0));
    let cuts = "=TEXTJOIN(\"|\",,TEXTSPLIT(\"a,b;;c;d\",{\",\",\";\",\";;\"}))";
    assert_eq!(common::sheet::eval_a1(cuts).0, Value::text("a|b|c|d"));
    let ignoring_case = "=TEXTAFTER(\"aXbxc\",\"x\",-1,1)";
    assert_eq!(common::sheet::eval_a1(ignoring_case).0, Value::text("c"));
    for formula in [
        "=ROWS(TEXTSPLIT(REPT(\"a\",32000),\"b\"&SEQUENCE(20000)))",
        // Each of two texts read by 10,000 delimiters: 3.2·10^8, then 6.4·10^8 in all.
        "=ROWS(TEXTBEFORE(REPT(\"a\",32000)&SEQUENCE(2),\"b\"&SEQUENCE(1,10000)))",
    ] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Num), "{formula}");
        assert!(notes.iter().any(|n| n.contains("read more than 512 MiB of text")), "{formula}: {notes:?}");
    }
}

/// A whole column compared with a long text reads as many texts as its stored cells, and
/// counts them as other arrays do: 20,000 rows against 30,000 characters read 6·10^8 bytes,
/// past 512 MiB (by hand) — `#NUM!` with the note, where nothing was counted on this path.
#[test]
fn whole_columns_count_the_texts_they_read() {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    common::sheet::set(&mut wb, "B20000", "1");
    common::sheet::set(&mut wb, "A1", "=SUM(--(B:B=REPT(\"x\",30000)))");
    common::sheet::set(&mut wb, "A2", "=SUM(--(B:B=REPT(\"x\",3000)))");
    assert_eq!(common::sheet::get(&wb, "A1"), Value::Error(XlError::Num));
    let notes: Vec<String> = wb.problems().into_iter().map(|p| p.render()).collect();
    assert!(notes.iter().any(|n| n.contains("read more than 512 MiB of text")), "{notes:?}");
    assert_eq!(common::sheet::get(&wb, "A2"), Value::Number(0.0));
}
