//! The declared type of an expression as VBA's static semantics give it ([MS-VBAL] 5.6.9.3,
//! "Arithmetic Operators"), and the Overflow (run-time error 6) it implies: `+`, `-`, `*`,
//! `\` and `Mod` on two Integer operands compute in Integer, on Long operands in Long, so
//! `200 * 200` fails although a Long or a Variant would hold 40000 (Office VBA reference,
//! "Overflow (Error 6)": `x = 2000 * 365` is an overflow, `CLng(2000) * 365` is not). An
//! operand that is a Variant makes the operation a Variant's, which VBA widens instead of
//! failing: the value is exact already (kept as a double), and the type each operation's
//! result widened to is noted where it is computed, for the operations around it.

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::format::number_format::general;
use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind, UnaryOp};

use super::ast::{Inspect, Node, Ty, DATE_VAR_TYPE, LONG_LONG_END};
use super::interp::{Fault, Interp};

mod decimal;
pub(in crate::vba) use decimal::{Dec, KeptDecimals};

/// An expression's declared type, as far as the interpreter tells types apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Declared {
    Byte,
    Boolean,
    Integer,
    Long,
    LongLong,
    Single,
    Double,
    Currency,
    Decimal,
    Date,
    String,
    /// A Variant, an object, or a type the interpreter does not follow: no static type.
    Variant,
}

/// Which type [`Interp::typed_within`] follows: the declared (static) type, where a Variant
/// is a Variant and its operations are checked for no overflow, or the type the value is held
/// with, where a Variant counts as the type of what it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Typing {
    Declared,
    Held,
}

/// How deep into an expression its type is followed: as deep as the parser lets a formula or
/// a macro's expression nest, so every operation of a long chain is typed (and checked for
/// overflow); each is typed once a statement ([`TypesKnown`]), the chain's cost linear. The
/// bound keeps the walk off the native stack's end should a deeper tree come by another road.
const MAX_DEPTH: u32 = crate::formula::limits::MAX_TREE_DEPTH;

/// The types [`Interp::typed_within`] worked out for the operations of the statement running.
/// Each operation's type is asked by the one enclosing it (for its overflow check, its held
/// type), and working it out walks the operands below: asked afresh each time, a chain
/// `1 + 1 + … + 1` of n terms walked n²/2 nodes (10,000 runs of a 1,400-term chain took
/// 24 s). Kept for one statement, so that each operation is typed once: a statement a call
/// runs in between starts afresh, since what it assigns may change a Variant's held type.
#[derive(Default)]
pub(super) struct TypesKnown {
    /// The statement ([`Interp::steps_run`]) the types are of.
    step: std::cell::Cell<u64>,
    /// By the operation's address and span, and the typing followed: keys of our own making,
    /// hashed by the fast hasher (SipHash was a fifth of a loop's time).
    types: std::cell::RefCell<crate::workbook::FxMap<(usize, u32, u32, Typing), Declared>>,
}

impl Declared {
    /// The declared type of a variable, an array's items or a Function's result.
    pub(super) fn of_ty(ty: Option<&Ty>) -> Declared {
        match ty {
            Some(Ty::Whole(2)) => Declared::Integer,
            Some(Ty::Whole(3)) => Declared::Long,
            Some(Ty::Whole(17)) => Declared::Byte,
            Some(Ty::Whole(_)) => Declared::LongLong,
            Some(Ty::Number(4)) => Declared::Single,
            Some(Ty::Number(6)) => Declared::Currency,
            Some(Ty::Number(14)) => Declared::Decimal,
            Some(Ty::Number(DATE_VAR_TYPE)) => Declared::Date,
            Some(Ty::Number(_)) => Declared::Double,
            Some(Ty::String | Ty::FixedString(_)) => Declared::String,
            Some(Ty::Boolean) => Declared::Boolean,
            Some(Ty::Variant | Ty::Object | Ty::Record(_)) | None => Declared::Variant,
        }
    }

    /// VBA's name of the type (`TypeName`).
    pub(super) fn name(self) -> &'static str {
        match self {
            Declared::Byte => "Byte",
            Declared::Boolean => "Boolean",
            Declared::Integer => "Integer",
            Declared::Long => "Long",
            Declared::LongLong => "LongLong",
            Declared::Single => "Single",
            Declared::Double => "Double",
            Declared::Currency => "Currency",
            Declared::Decimal => "Decimal",
            Declared::Date => "Date",
            Declared::String => "String",
            Declared::Variant => "Variant",
        }
    }

    /// VarType's number for a value of this type ("VarType function": vbInteger 2 …
    /// vbLongLong 20); `None` for a Variant, which answers what it holds.
    pub(super) fn var_type(self) -> Option<f64> {
        Some(match self {
            Declared::Integer => 2.0,
            Declared::Long => 3.0,
            Declared::Single => 4.0,
            Declared::Double => 5.0,
            Declared::Currency => 6.0,
            Declared::Date => 7.0,
            Declared::String => 8.0,
            Declared::Boolean => 11.0,
            Declared::Decimal => 14.0,
            Declared::Byte => 17.0,
            Declared::LongLong => 20.0,
            Declared::Variant => return None,
        })
    }

    /// The variable type that answers as this type (`TypeName`, `VarType`); `None` for a Variant.
    pub(super) fn ty(self) -> Option<Ty> {
        Some(match self {
            Declared::Byte => Ty::Whole(17),
            Declared::Integer => Ty::Whole(2),
            Declared::Long => Ty::Whole(3),
            Declared::LongLong => Ty::Whole(20),
            Declared::Single => Ty::Number(4),
            Declared::Double => Ty::Number(5),
            Declared::Currency => Ty::Number(6),
            Declared::Decimal => Ty::Number(14),
            Declared::Date => Ty::Number(DATE_VAR_TYPE),
            Declared::String => Ty::String,
            Declared::Boolean => Ty::Boolean,
            Declared::Variant => return None,
        })
    }

    /// The type a Variant holds the number `n` with when an operation of this type gave it
    /// ("Variant data type": "if an arithmetic operation is performed on a Variant containing
    /// a Byte, an Integer, a Long, or a Single, and the result exceeds the normal range for the
    /// original data type, the result is promoted within the Variant to the next larger data
    /// type. A Byte is promoted to an Integer, an Integer is promoted to a Long, and a Long and
    /// a Single are promoted to a Double").
    fn widened_for(self, n: f64) -> Declared {
        let mut ty = self;
        loop {
            let next = match ty {
                Declared::Byte => Declared::Integer,
                Declared::Integer => Declared::Long,
                Declared::Long | Declared::Single => Declared::Double,
                other => return other,
            };
            let fits = match ty.range() {
                Some((low, high, _)) => (low..=high).contains(&n),
                None => n.abs() <= f32::MAX as f64 || !n.is_finite(),
            };
            if fits {
                return ty;
            }
            ty = next;
        }
    }

    /// The range of an integral type and its name; `None` for any other type.
    fn range(self) -> Option<(f64, f64, &'static str)> {
        Some(match self {
            Declared::Byte => (0.0, 255.0, "a Byte (0 to 255)"),
            Declared::Integer => (-32768.0, 32767.0, "an Integer (-32,768 to 32,767)"),
            Declared::Long => (-2147483648.0, 2147483647.0, "a Long (-2,147,483,648 to 2,147,483,647)"),
            // The largest double below 2^63: 2^63 itself is one past the top.
            Declared::LongLong => (-LONG_LONG_END, LONG_LONG_END - 1024.0, "a LongLong (-2^63 to 2^63 - 1)"),
            _ => return None,
        })
    }

    /// Byte 0, Boolean and Integer 1, Long 2, LongLong 3: the integral types in the order
    /// the operator table widens to; `None` for the others.
    fn integral_rank(self) -> Option<u8> {
        match self {
            Declared::Byte => Some(0),
            Declared::Boolean | Declared::Integer => Some(1),
            Declared::Long => Some(2),
            Declared::LongLong => Some(3),
            _ => None,
        }
    }

    fn of_rank(rank: u8) -> Declared {
        match rank {
            0 => Declared::Byte,
            1 => Declared::Integer,
            2 => Declared::Long,
            _ => Declared::LongLong,
        }
    }
}

/// The declared type of `+`, `-` and (but for [`product_type`]'s exceptions) `*` on operands
/// of these types ([MS-VBAL] 5.6.9.3's table): two integral types give the wider (Byte and
/// Byte a Byte, Boolean counts as Integer), a Variant a Variant; a Currency with any other a
/// Currency, a Single with a Single, Byte, Boolean or Integer a Single; anything else a Double.
fn sum_type(a: Declared, b: Declared) -> Declared {
    if a == Declared::Variant || b == Declared::Variant {
        return Declared::Variant;
    }
    match (a.integral_rank(), b.integral_rank()) {
        (Some(x), Some(y)) => Declared::of_rank(x.max(y)),
        _ if a == Declared::Decimal || b == Declared::Decimal => Declared::Decimal,
        _ if a == Declared::Currency || b == Declared::Currency => Declared::Currency,
        _ => single_or_double(a, b),
    }
}

/// A Single where both operands are a Single or one narrower than a Long ([MS-VBAL]
/// 5.6.9.3: a Single with a Long or a LongLong is a Double, as with a Double); else a Double.
fn single_or_double(a: Declared, b: Declared) -> Declared {
    let fits_single =
        |t: Declared| matches!(t, Declared::Single | Declared::Byte | Declared::Boolean | Declared::Integer);
    if (a == Declared::Single || b == Declared::Single) && fits_single(a) && fits_single(b) {
        Declared::Single
    } else {
        Declared::Double
    }
}

/// The declared type of `*` ([MS-VBAL] "* Operator", under 5.6.9.3): the standard table of
/// 5.6.9.3 as for `+`, except that a Currency with a Single, a Double or a String is a Double
/// (the product is not rounded to a Currency's four places: `c * 0.03125` of the Currency 1
/// is 0.03125), and a Date with any number a Double.
fn product_type(a: Declared, b: Declared) -> Declared {
    let floating = |t: Declared| matches!(t, Declared::Single | Declared::Double | Declared::String);
    match (a, b) {
        (Declared::Variant, _) | (_, Declared::Variant) => Declared::Variant,
        (Declared::Date, _) | (_, Declared::Date) => Declared::Double,
        (Declared::Currency, other) | (other, Declared::Currency) if floating(other) => Declared::Double,
        _ => sum_type(a, b),
    }
}

/// The declared type of `+` and `-` with a Date operand ([MS-VBAL] 5.6.9.3.3 and 5.6.9.3.4):
/// a Date plus or minus a number is a Date (`d + 1` is the next day), a Date minus a Date a
/// Double (the days between); `None` when neither operand is a Date, or one is a Variant.
fn date_sum_type(op: BinOp, a: Declared, b: Declared) -> Option<Declared> {
    let numeric = |t: Declared| t != Declared::Variant && t != Declared::String;
    match (a, b) {
        (Declared::Date, Declared::Date) if op == BinOp::Sub => Some(Declared::Double),
        (Declared::Date, other) | (other, Declared::Date) if numeric(other) => Some(Declared::Date),
        _ => None,
    }
}

/// The declared type of `\` and `Mod` ([MS-VBAL] 5.6.9.3.6 and 5.6.9.3.7): as for `+` on
/// integral operands; otherwise the operands are made Longs (LongLong beside a LongLong).
fn whole_division_type(a: Declared, b: Declared) -> Declared {
    match (a.integral_rank(), b.integral_rank()) {
        (Some(x), Some(y)) => Declared::of_rank(x.max(y)),
        _ if a == Declared::LongLong || b == Declared::LongLong => Declared::LongLong,
        _ => Declared::Long,
    }
}

/// The declared type of `x op y` for operands of the types `x` and `y` ([MS-VBAL] 5.6.9.3);
/// `Variant` for an operator that is no arithmetic one.
pub(super) fn binary_type(op: BinOp, x: Declared, y: Declared) -> Declared {
    let variant = x == Declared::Variant || y == Declared::Variant;
    match op {
        BinOp::Add | BinOp::Sub => date_sum_type(op, x, y).unwrap_or_else(|| sum_type(x, y)),
        BinOp::Mul => product_type(x, y),
        BinOp::IntDiv | BinOp::Mod if !variant => whole_division_type(x, y),
        // [MS-VBAL] 5.6.9.3.5: `/` of a Single keeps a Single as `*` does; `^` is a Double.
        // A Currency's quotient is a Double ("/ operator": "usually a Double"; a Currency is
        // none of its exceptions), not rounded to four places; a Decimal's is a Decimal ("/
        // operator": "Division involves a Decimal and any other data type: A Decimal").
        BinOp::Div if !variant && (x == Declared::Decimal || y == Declared::Decimal) => Declared::Decimal,
        BinOp::Div if !variant => single_or_double(x, y),
        BinOp::Pow if !variant => Declared::Double,
        BinOp::And | BinOp::Or | BinOp::Xor | BinOp::Eqv | BinOp::Imp if !variant => logical_type(x, y),
        // [MS-VBAL] 5.6.9.5 (relational operators): the result is a Boolean, unless an operand
        // is a Variant that may be Null (then Null), so `(1 = 1) + 1` adds a Boolean and an
        // Integer, an Integer.
        BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge if !variant => Declared::Boolean,
        _ => Declared::Variant,
    }
}

/// The declared type of a binary logical operator, `And`, `Or`, `Xor`, `Eqv` or `Imp`
/// ([MS-VBAL] 5.6.9.8's table): two Bytes a Byte, two Booleans a Boolean, Bytes, Booleans
/// and Integers together an Integer, a LongLong beside a LongLong, anything else a Long.
fn logical_type(x: Declared, y: Declared) -> Declared {
    let small = |t: Declared| matches!(t, Declared::Byte | Declared::Boolean | Declared::Integer);
    match (x, y) {
        (Declared::Byte, Declared::Byte) => Declared::Byte,
        (Declared::Boolean, Declared::Boolean) => Declared::Boolean,
        _ if small(x) && small(y) => Declared::Integer,
        _ if x == Declared::LongLong || y == Declared::LongLong => Declared::LongLong,
        _ => Declared::Long,
    }
}

/// The declared type of `Not x` for an operand of the type `x` ([MS-VBAL] 5.6.9.8.1, "Not
/// Operator"): a Byte, Boolean, Integer, Long or LongLong keeps its type (`Not CByte(5)` is
/// the Byte 250), a Variant stays a Variant, and anything else (a Single, Double, Currency,
/// Date or String) is let-coerced to a Long first, so its `Not` is a Long.
fn not_type(x: Declared) -> Declared {
    match x {
        Declared::Byte
        | Declared::Boolean
        | Declared::Integer
        | Declared::Long
        | Declared::LongLong
        | Declared::Variant => x,
        _ => Declared::Long,
    }
}

/// The type a Variant holds the number `n` with that an expression of type `ty` gave: a
/// whole-number type widened past its range, a number of no numeric type a Double.
fn held_number(ty: Declared, n: f64) -> Declared {
    match ty {
        Declared::Double | Declared::Currency | Declared::Decimal | Declared::Date => ty,
        Declared::String | Declared::Boolean | Declared::Variant => Declared::Double,
        ty => ty.widened_for(n),
    }
}

/// The type a Variant holds `n`, the sum of numbers held as `a` and `b`, with (a For
/// counter's next value): as `+` of those types gives it ([MS-VBAL] 5.6.9.3.3).
pub(super) fn sum_held(a: Declared, b: Declared, n: f64) -> Declared {
    held_number(date_sum_type(BinOp::Add, a, b).unwrap_or_else(|| sum_type(a, b)), n)
}

/// A Single's value as VBA shows it: its seven significant digits ("Single data type";
/// CStr, Str and Print show no more: `CSng(1 / 3)` is 0.3333333).
pub(super) fn single_shown(n: f64) -> f64 {
    format!("{n:.6e}").parse().unwrap_or(n)
}

/// Whether `source` may hold a Single, a Currency or a Decimal (it names the types, their
/// conversions, Rnd, or has a `!` or `@` type character): only then is each operation's
/// result checked for them, so that a module of Doubles computes as fast as before.
pub(super) fn names_single_or_currency(source: &str) -> bool {
    let names = |word: &[u8]| source.as_bytes().windows(word.len()).any(|w| w.eq_ignore_ascii_case(word));
    source.contains(['!', '@'])
        || [&b"single"[..], b"currency", b"csng", b"ccur", b"rnd", b"cdec", b"decimal"].into_iter().any(names)
}

/// The Currency `n` stands for written as a decimal without trailing zeros: the shortest
/// text that gives the double back, its places past the fourth rounded half to even (a
/// Currency's ten-thousandths). Read from that text, not from `n * 10000`, which a double past
/// 2^53 ten-thousandths no longer gives exactly (123456789012345.5 would become
/// 123456789012345.4976). `None` past the type's range.
fn currency_digits(n: f64) -> Option<String> {
    if !n.is_finite() || n.abs() >= 922_337_203_685_477.6 {
        return None;
    }
    let text = format!("{}", n.abs());
    let (whole, fraction) = text.split_once('.').unwrap_or((&text, ""));
    let places = format!("{fraction:0<4}");
    let (kept, rest) = places.split_at(4);
    let mut scaled: i128 = format!("{whole}{kept}").parse().ok()?;
    let rest: Vec<u8> = rest.bytes().map(|b| b - b'0').collect();
    let above_half = rest.first().is_some_and(|&d| d > 5 || (d == 5 && rest[1..].iter().any(|&d| d > 0)));
    let tie = rest.first() == Some(&5) && rest[1..].iter().all(|&d| d == 0);
    if above_half || (tie && scaled % 2 == 1) {
        scaled += 1;
    }
    let sign = if n < 0.0 && scaled != 0 { "-" } else { "" };
    let places = format!("{:04}", scaled % 10_000);
    let places = places.trim_end_matches('0');
    let whole = scaled / 10_000;
    Some(if places.is_empty() { format!("{sign}{whole}") } else { format!("{sign}{whole}.{places}") })
}

/// `x op y` on Currencies: 64-bit integers of ten-thousandths ("Currency data type"), each
/// operand made one (four places, halves to even), the product's extra places rounded off
/// half to even; `None` past the type's range or for an operator that is no `+ - *`.
fn currency_result(op: BinOp, x: f64, y: f64) -> Option<f64> {
    // An operand past a Currency's range is Overflow itself; within it, two operands' sum
    // and product fit an i128 (an `as i128` of 1E+300 saturates, and its product overflowed).
    let scaled = |v: f64| i64::try_from((v * 10_000.0).round_ties_even() as i128).ok().map(i128::from);
    let (a, b) = (scaled(x)?, scaled(y)?);
    let r = match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => {
            let (q, rem) = (a * b / 10_000, a * b % 10_000);
            let away = rem.abs() * 2 > 10_000 || (rem.abs() * 2 == 10_000 && q % 2 != 0);
            q + if away { (a * b).signum() } else { 0 }
        }
        _ => return None,
    };
    i64::try_from(r).ok().map(|r| r as f64 / 10_000.0)
}

/// The type of a number literal from its text ([MS-VBAL] 3.3.2): a type character says it
/// (`%` Integer, `&` Long, `^` LongLong, `!` Single, `#` Double, `@` Currency); a whole
/// decimal number is an Integer if it fits, else a Long if it fits, else a Double; a number
/// with a point or an exponent is a Double; `&H…` and `&O…` are Integers or Longs; `#…#` a Date.
fn literal_type(text: &str, value: f64) -> Declared {
    let text = text.trim();
    let whole = |n: f64| {
        if n.abs() <= 32767.0 {
            Declared::Integer
        } else if n.abs() <= 2147483647.0 {
            Declared::Long
        } else {
            Declared::Double
        }
    };
    if text.starts_with('#') {
        return Declared::Date;
    }
    if let Some(radix) = text.strip_prefix('&') {
        return match radix.chars().last() {
            Some('&') => Declared::Long,
            Some('%') => Declared::Integer,
            Some('^') => Declared::LongLong,
            // A hex or octal literal of up to 16 bits is an Integer read as two's complement
            // ([MS-VBAL] 3.3.2, number tokens): `&HFFFF` is -1 and `&H8000` the Integer
            // -32768 (its value was right, its type a Long by the value's magnitude).
            _ if radix_digits_fit_16_bits(radix) => Declared::Integer,
            _ => Declared::Long,
        };
    }
    let digits = text.trim_start_matches(['-', '+']);
    match digits.chars().last() {
        Some('%') => Declared::Integer,
        Some('&') => Declared::Long,
        Some('^') => Declared::LongLong,
        Some('!') => Declared::Single,
        Some('#') => Declared::Double,
        Some('@') => Declared::Currency,
        _ if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) => whole(value),
        _ => Declared::Double,
    }
}

/// Whether the digits of a hex or octal literal (`HFFFF`, `o177777`, after its `&`) make an
/// unsigned number of at most 16 bits, whatever leading zeros they have.
fn radix_digits_fit_16_bits(radix: &str) -> bool {
    let (base, digits) = match radix.chars().next() {
        Some('h' | 'H') => (16, &radix[1..]),
        Some('o' | 'O') => (8, &radix[1..]),
        _ => (8, radix),
    };
    u64::from_str_radix(digits, base).is_ok_and(|n| n <= 0xFFFF)
}

/// The type of the number a VBA function gives in a Variant, where the language reference
/// names it ("InStr function": "Variant (Long)"; "StrComp function": "Variant (Integer)";
/// "Rnd function": "a Single"); `None` for the rest.
fn held_function_type(name: &str) -> Option<Declared> {
    match name {
        "VBA.INSTR" | "VBA.INSTRREV" => Some(Declared::Long),
        "VBA.STRCOMP" => Some(Declared::Integer),
        // "Weekday function", "Year function", "Month function", "Day function", "Hour
        // function", "Minute function", "Second function": each "Returns a Variant (Integer)".
        "VBA.WEEKDAY" | "VBA.YEAR" | "VBA.MONTH" | "VBA.DAY" | "VBA.HOUR" | "VBA.MINUTE" | "VBA.SECOND" => {
            Some(Declared::Integer)
        }
        "VBA.RND" => Some(Declared::Single),
        _ => None,
    }
}

/// The declared type of a VBA function's result, by its row of the function table.
fn function_type(name: &str) -> Declared {
    match name {
        "VBA.CINT" | "VBA.ASC" | "VBA.ASCW" | "VBA.SGN" | "VBA.VARTYPE" | "VBA.DATEPART" => Declared::Integer,
        "VBA.CLNG" | "VBA.LEN" | "VBA.LENB" | "VBA.DATEDIFF" => Declared::Long,
        "VBA.CLNGLNG" => Declared::LongLong,
        "VBA.CBYTE" => Declared::Byte,
        "VBA.CSNG" => Declared::Single,
        "VBA.CCUR" => Declared::Currency,
        "VBA.CDEC" => Declared::Decimal,
        "VBA.CDBL" | "VBA.VAL" | "VBA.TIMER" | "VBA.ATN" | "VBA.COS" | "VBA.SIN" | "VBA.TAN" | "VBA.EXP"
        | "VBA.LOG" | "VBA.SQR" => Declared::Double,
        "VBA.CSTR" | "VBA.WEEKDAYNAME" | "VBA.MONTHNAME" => Declared::String,
        "VBA.CBOOL" | "VBA.ISNUMERIC" | "VBA.ISEMPTY" | "VBA.ISERROR" | "VBA.ISARRAY" => Declared::Boolean,
        "VBA.CDATE" | "VBA.CVDATE" | "VBA.DATESERIAL" | "VBA.TIMESERIAL" | "VBA.DATEVALUE" | "VBA.TIMEVALUE"
        | "VBA.DATE" | "VBA.TIME" | "VBA.NOW" | "VBA.DATEADD" | "NOW" => Declared::Date,
        _ => Declared::Variant,
    }
}

impl Interp<'_, '_> {
    /// The declared type of an expression ([MS-VBAL] 5.6: each expression has one).
    pub(super) fn declared_type(&self, e: &Expr) -> Declared {
        self.typed_within(e, 0, Typing::Declared)
    }

    /// The type of the value `v` that `e` gave, as a Variant holds it (`TypeName`, `VarType`,
    /// a Variant assigned it): the declared type, where a Variant operand counts as what it
    /// holds ([MS-VBAL] 5.6.9.3's "effective value type"), a whole number widened past its
    /// type's range ([`Declared::widened_for`]); a number of no known type is a Double.
    /// Each operation inside widened where it was computed ([`Interp::note_widening`]).
    pub(super) fn value_type(&self, e: &Expr, v: &Value) -> Declared {
        match v {
            Value::Number(n) => held_number(self.typed_within(e, 0, Typing::Held), *n),
            Value::Text(_) => Declared::String,
            Value::Bool(_) => Declared::Boolean,
            _ => Declared::Variant,
        }
    }

    fn typed_within(&self, e: &Expr, depth: u32, typing: Typing) -> Declared {
        if depth > MAX_DEPTH {
            return Declared::Variant;
        }
        super::count(&super::NODES_TYPED, 1);
        let operand = |e: &Expr| match (self.typed_within(e, depth + 1, typing), typing) {
            // An operand of no known type holding a number: a Double (a cell's value).
            (Declared::Variant, Typing::Held) => Declared::Double,
            (ty, _) => ty,
        };
        match &e.kind {
            ExprKind::Number(n) => literal_type(self.source_between(e.span.start, e.span.end), *n),
            ExprKind::Text(_) => Declared::String,
            ExprKind::Bool(_) => Declared::Boolean,
            ExprKind::Paren(inner) => self.known_type(e, typing, || self.typed_within(inner, depth + 1, typing)),
            ExprKind::Name(name) => self.with_slot(name, |s| s.typed(typing)).unwrap_or(Declared::Variant),
            ExprKind::Unary(op @ (UnaryOp::Neg | UnaryOp::Plus), inner) => {
                match (op, self.widened_if_held(typing, inner)) {
                    (UnaryOp::Neg, Some(ty)) => ty,
                    _ => self.known_type(e, typing, || match operand(inner) {
                        Declared::Boolean => Declared::Integer,
                        other => other,
                    }),
                }
            }
            ExprKind::Unary(UnaryOp::Not, inner) => self.known_type(e, typing, || not_type(operand(inner))),
            ExprKind::Binary(BinOp::Concat, ..) => Declared::String,
            // The widening an operation's last result noted comes first: it is noted after
            // the operation's type is known, within the statement.
            ExprKind::Binary(op, a, b) => self
                .widened_if_held(typing, a)
                .unwrap_or_else(|| self.known_type(e, typing, || binary_type(*op, operand(a), operand(b)))),
            ExprKind::Call(id, args) => match (crate::eval::functions::spec(*id).name, args.first()) {
                // "Abs function", "Int, Fix functions": the result has the argument's type;
                // Round's too ("VB & VBA in a Nutshell", Round: "Return Value: The same data
                // type as expression"), so the Round of a Currency is a Currency.
                ("VBA.ABS" | "VBA.INT" | "VBA.FIX" | "VBA.ROUND", Some(arg)) if typing == Typing::Held => {
                    match operand(arg) {
                        Declared::String | Declared::Boolean => Declared::Double,
                        ty => ty,
                    }
                }
                // "IIf function": a Variant holding the chosen branch's value, as the
                // interpreter noted it past 2^53 (`longlong.rs`).
                // "Type conversion functions": CVar's Variant holds its argument as it was.
                ("VBA.CVAR", Some(arg)) if typing == Typing::Held => self.typed_within(arg, depth + 1, typing),
                ("VBA.IIF", _) if typing == Typing::Held => self
                    .iif_chosen(args)
                    .or_else(|| self.last_iif_branch(args))
                    .map_or(Declared::Variant, |b| self.typed_within(b, depth + 1, typing)),
                (name, _) if typing == Typing::Held => held_function_type(name).unwrap_or_else(|| function_type(name)),
                (name, _) => function_type(name),
            },
            ExprKind::Host(id) => self.node_type(*id, typing),
            // `Empty` in arithmetic is an Integer 0 ([MS-VBAL] 5.6.9.3's effective value type).
            ExprKind::Missing if typing == Typing::Held => Declared::Integer,
            _ => Declared::Variant,
        }
    }

    /// The branch the last IIf call chose, when `args` are that call's ("IIf function": the
    /// Variant it returns holds that branch's value as it was, `IIf(True, 1, 2.5)` an Integer).
    fn last_iif_branch<'e>(&self, args: &'e [Expr]) -> Option<&'e Expr> {
        let condition = args.first()?;
        let (address, start, index) = self.iif_branch.get();
        let same = address == condition as *const Expr as usize && start == condition.span.start as usize;
        if same {
            args.get(index)
        } else {
            None
        }
    }

    /// The type of the operation `e` ([`TypesKnown`]): the one worked out before in this
    /// statement, or `work_out`'s, kept.
    fn known_type(&self, e: &Expr, typing: Typing, work_out: impl FnOnce() -> Declared) -> Declared {
        let known = &self.types_known;
        let step = self.steps_run();
        if known.step.get() != step {
            known.step.set(step);
            known.types.borrow_mut().clear();
        }
        // The span too: an expression cloned for a moment (an index list) may be dropped and
        // another put at its address in the same statement, never with the same span.
        let key = (e as *const Expr as usize, e.span.start, e.span.end, typing);
        if let Some(&ty) = known.types.borrow().get(&key) {
            return ty;
        }
        let ty = work_out();
        // `work_out` may have run a statement (it does not today, but a step changed means
        // the types kept are of another statement): keep it only for this one.
        if known.step.get() == step {
            known.types.borrow_mut().insert(key, ty);
        }
        ty
    }

    /// The day count of `v` when `e`, which gave it, is of the declared type Date: what
    /// Debug.Print, Print #, Write #, MsgBox and `&` show as a date ([MS-VBAL] 5.5.1.2.4,
    /// a Date let-coerced to String).
    pub(super) fn as_date(&self, e: &Expr, v: &Value) -> Option<f64> {
        match v {
            Value::Number(n) if self.declared_type(e) == Declared::Date => Some(*n),
            _ => None,
        }
    }

    fn node_type(&self, id: u32, typing: Typing) -> Declared {
        // A call, an item of an array, a Collection or a Dictionary that gave a Date (or,
        // for the held type, a number of a type, as a Variant Function's Integer).
        match self.node_types.borrow().get(&id) {
            Some(&ty) if ty == Declared::Date || typing == Typing::Held => return ty,
            _ => {}
        }
        match &self.module.nodes[id as usize] {
            Node::Call { proc, .. } => Declared::of_ty(self.module.procs[*proc].ty.as_ref()),
            // An item of a typed array (a Collection's or a Range's is a Variant).
            Node::Element { var, .. } => {
                match self.with_slot(var, |s| (matches!(s.var(), super::value::Var::Array(_)), s.ty.clone())) {
                    Some((true, ty)) => Declared::of_ty(ty.as_ref()),
                    _ => Declared::Variant,
                }
            }
            Node::Bound { .. } => Declared::Long,
            Node::Path(path) => self.field_type(path).unwrap_or(Declared::Variant),
            // `Empty` in arithmetic is an Integer 0 ([MS-VBAL] 5.6.9.3's effective value type).
            Node::Empty if typing == Typing::Held => Declared::Integer,
            Node::Inspect { what: Inspect::VarType, .. } => Declared::Integer,
            Node::Inspect { what: Inspect::Len { .. }, .. } => Declared::Long,
            Node::Is { .. }
            | Node::TypeOf { .. }
            | Node::Inspect { what: Inspect::IsMissing | Inspect::IsDate | Inspect::IsEmpty, .. } => Declared::Boolean,
            _ => Declared::Variant,
        }
    }

    /// The declared type of a field of a variable of a user-defined Type (`p.n`, `a(1).pos.x`):
    /// the field's own ([MS-VBAL] 5.2.3.3, a Type's element keeps its declared type), so
    /// `TypeName(p.n)` of an Integer field is "Integer". `None` for any other path.
    fn field_type(&self, path: &super::ast::Path) -> Option<Declared> {
        let (first, fields) = path.links.split_first().filter(|_| !path.with)?;
        let Some(Ty::Record(mut record)) = self.with_slot(&first.name, |s| s.ty.clone()).flatten() else {
            return None;
        };
        let mut ty = Ty::Record(record);
        for link in fields {
            let def = &self.module.types[record];
            let at = def.field(&link.name)?;
            // A field's array needs its index, a plain field none.
            if link.args.is_some() != def.bounds[at].is_some() {
                return None;
            }
            ty = def.fields[at].1.clone();
            if let Ty::Record(inner) = ty {
                record = inner;
            }
        }
        (!matches!(ty, Ty::Record(_)) && !fields.is_empty()).then(|| Declared::of_ty(Some(&ty)))
    }

    /// Overflow (run-time error 6) of `-operand`, which gave `result`: the negation has the
    /// operand's declared type ([MS-VBAL] 5.6.9.3.1, unary `-`), and the most negative
    /// Integer or Long has no positive of its type (`-x` for the Integer -32,768).
    pub(super) fn negation_overflow(&self, operand: &Expr, result: &Value) -> Option<Fault> {
        let Value::Number(n) = *result else { return None };
        if (-255.0..=255.0).contains(&n) || n.fract() != 0.0 {
            return None;
        }
        let declared = self.declared_type(operand);
        if declared == Declared::Variant {
            let ty = match self.held_operand(operand) {
                Declared::Boolean => Declared::Integer,
                other => other,
            };
            self.note_widening(operand, ty, n);
            return None;
        }
        let (low, high, holds) = declared.range()?;
        if (low..=high).contains(&n) {
            return None;
        }
        let shown = self.quoted_source(operand.span.start, operand.span.end, "the operand");
        Some(self.overflow_fault(
            self.expr_span(operand),
            format!("-{shown} overflows: its type makes it {holds}, which cannot hold {}", general(n)),
        ))
    }

    /// The bits of the whole-number type the value `v` of `e` is held with: 16 for a Byte,
    /// Boolean or Integer, 32 for a Long; `None` for any other type.
    pub(super) fn integer_bits(&self, e: &Expr, v: &Value) -> Option<u32> {
        match self.value_type(e, v) {
            Declared::Byte | Declared::Boolean | Declared::Integer => Some(16),
            Declared::Long => Some(32),
            _ => None,
        }
    }

    /// `Not operand`, which gave `result`, in the operand's type: a Byte's `Not` flips its
    /// eight bits ([MS-VBAL] 5.6.9.8.1: `Not` of a Byte is a Byte, so `Not CByte(5)` is 250,
    /// where the Long the evaluator computes in gives -6).
    pub(super) fn not_in_its_type(&self, operand: &Expr, result: Value) -> Value {
        match result {
            Value::Number(n) if self.held_operand(operand) == Declared::Byte => {
                Value::Number(f64::from(n as i64 as u8))
            }
            other => other,
        }
    }

    /// The type a Variant holds the value of the operand `e` with (a number of no known
    /// type is a Double).
    pub(super) fn held_operand(&self, e: &Expr) -> Declared {
        match self.typed_within(e, 1, Typing::Held) {
            Declared::Variant => Declared::Double,
            ty => ty,
        }
    }

    /// For the held type, the type the operation whose first operand is `first` gave its last
    /// result in, where that result widened past the type its operands' types give it.
    pub(super) fn widened_if_held(&self, typing: Typing, first: &Expr) -> Option<Declared> {
        if typing == Typing::Declared {
            return None;
        }
        let widened = self.widened.borrow();
        if widened.is_empty() {
            return None;
        }
        widened.get(&(first as *const Expr as usize)).copied()
    }

    /// Notes the type a Variant holds `n` with, which the operation whose first operand is
    /// `first` gave in the type `ty` its operands' held types make ("Variant data type": a
    /// Byte, Integer, Long or Single result past its type's range "is promoted within the
    /// Variant to the next larger data type"), so that an enclosing operation takes the
    /// widened type: `x * x - 30000` of the Integer 200 is the Long 10000, as the Long 40000
    /// less an Integer. Each operation's result widens where it is computed, not the whole
    /// expression's at its end.
    fn note_widening(&self, first: &Expr, ty: Declared, n: f64) {
        let held = held_number(ty, n);
        if held != ty && matches!(ty, Declared::Byte | Declared::Integer | Declared::Long | Declared::Single) {
            self.widened.borrow_mut().insert(first as *const Expr as usize, held);
        }
    }

    /// Forgets what the operation whose first operand is `first` gave before: it is being
    /// computed again ([`Interp::note_widening`]).
    pub(super) fn forget_widening(&self, first: &Expr) {
        if !self.widened.borrow().is_empty() {
            self.widened.borrow_mut().remove(&(first as *const Expr as usize));
        }
    }

    /// The number `v`, the value of `e`, shows as when it is held as a Single: its seven
    /// significant digits; `None` for any other value.
    pub(super) fn as_single(&self, e: &Expr, v: &Value) -> Option<f64> {
        match v {
            Value::Number(n) if self.narrow_numbers && self.value_type(e, v) == Declared::Single => {
                Some(single_shown(*n))
            }
            _ => None,
        }
    }

    /// The text the number `v`, the value of `e`, is let-coerced to for a String ([MS-VBAL]
    /// 5.5.1.2.4, Let-coercion to String), where its type writes it otherwise than a Double's
    /// fifteen digits: a Date its date text, a LongLong, Decimal or Currency its every digit,
    /// a Single its seven significant digits (`t = CSng(1 / 3)` into a String is "0.3333333");
    /// `None` for a Double and any other value. Library functions' String arguments take the
    /// same text (`eval::functions::vba::held_text`).
    pub(super) fn let_text(&self, e: &Expr, v: &Value) -> Option<String> {
        if !matches!(v, Value::Number(_)) {
            return None;
        }
        if let Some(day) = self.as_date(e, v) {
            return Some(super::value::date_text(day));
        }
        (self.long_long_text(e, v))
            .or_else(|| self.as_single(e, v).map(|n| crate::eval::functions::vba::vba_number_shown(n, true)))
    }

    /// [`Interp::let_text`] of the number `n` an argument gave, known by the type it holds
    /// (`held`, [MS-VBAL] 5.3.1.11) rather than by its expression: a Date, a Single or a
    /// Currency passed to a String parameter ByVal.
    pub(super) fn held_type_text(&self, held: Declared, n: f64) -> Option<String> {
        match held {
            Declared::Date => Some(super::value::date_text(n)),
            Declared::Single if self.narrow_numbers => {
                Some(crate::eval::functions::vba::vba_number_shown(single_shown(n), true))
            }
            Declared::Currency if self.narrow_numbers => currency_digits(n),
            _ => None,
        }
    }

    /// The digits of the Currency `v`, the value of `e`: its integer of ten-thousandths
    /// ("Currency data type") written as a decimal, `[-]whole[.places]`; `None` for any other
    /// value, and past a Currency's range.
    pub(super) fn currency_text(&self, e: &Expr, v: &Value) -> Option<String> {
        match v {
            Value::Number(n) if self.narrow_numbers && self.value_type(e, v) == Declared::Currency => {
                currency_digits(*n)
            }
            _ => None,
        }
    }

    /// `a & b` with a Single operand: its seven digits' text ([MS-VBAL] 5.6.9.4, `&`
    /// let-coerces each operand to String). `None` when neither is a Single.
    pub(super) fn concat_singles(&self, (a, b): (&Expr, &Expr), (x, y): (&Value, &Value)) -> Option<Value> {
        let (sx, sy) = (self.as_single(a, x), self.as_single(b, y));
        if sx.is_none() && sy.is_none() {
            return None;
        }
        let text = |single: Option<f64>, v: &Value| match (single, v) {
            (Some(n), _) => Some(crate::eval::functions::vba::vba_number_shown(n, true).into()),
            (None, Value::Null) => Some("".into()),
            (None, v) => crate::eval::functions::vba::vba_text(v).ok(),
        };
        Some(Value::text(format!("{}{}", text(sx, x)?, text(sy, y)?)))
    }

    /// `result`, the value of `a op b`, computed in its type where that is a Single (rounded
    /// to a 32-bit float, "Single data type"), a Currency (a scaled 64-bit integer,
    /// "Currency data type") or a Decimal (exact decimals, `typing/decimal.rs`) ([MS-VBAL] 5.6.9.3:
    /// the operation's value type is its result's);
    /// Overflow (run-time error 6) past the type's range, where a Variant's Single widens to
    /// a Double instead.
    pub(super) fn in_its_type(
        &self,
        op: BinOp,
        (a, b): (&Expr, &Expr),
        values: (&Value, &Value),
        result: Value,
    ) -> Result<Value, Fault> {
        let Value::Number(n) = result else { return Ok(result) };
        if !self.narrow_numbers || !matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div) {
            return Ok(result);
        }
        let held = self
            .widened_if_held(Typing::Held, a)
            .unwrap_or_else(|| binary_type(op, self.held_operand(a), self.held_operand(b)));
        let past = |holds: &str| {
            let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
            Err(self.overflow_fault(self.expr_span(a), format!("{shown} overflows: its result is past {holds}")))
        };
        match held {
            Declared::Single => match n as f32 {
                r if r.is_finite() || !n.is_finite() => Ok(Value::Number(f64::from(r))),
                // A Variant's Single widened to a Double ([`Interp::note_widening`]).
                _ if binary_type(op, self.declared_type(a), self.declared_type(b)) == Declared::Variant => Ok(result),
                _ => past("a Single (±3.402823E38)"),
            },
            Declared::Currency => {
                let number = |v: &Value| to_number(v, DateSystem::From1900).unwrap_or(0.0);
                match currency_result(op, number(values.0), number(values.1)) {
                    Some(r) => Ok(Value::Number(r)),
                    None if op == BinOp::Div => Ok(result),
                    None => past("a Currency (±922,337,203,685,477.5807)"),
                }
            }
            // The decimals' exact result (`typing/decimal.rs`), not the doubles'.
            Declared::Decimal => {
                let number = |v: &Value| to_number(v, DateSystem::From1900).unwrap_or(0.0);
                self.decimal_result(op, (a, b), (number(values.0), number(values.1)))
            }
            _ => Ok(result),
        }
    }

    /// VBA's Overflow (run-time error 6), with how to avoid it.
    pub(super) fn overflow_fault(&self, span: super::ast::Span, what: String) -> Fault {
        let mut fault = self.fault_at(
            span,
            crate::eval::functions::vba::errors::message(
                6,
                format_args!("{what} ([MS-VBAL] 5.6.9.3); make an operand wider, as CLng(x) or CDbl(x)"),
            ),
        );
        fault.code = 6;
        fault
    }

    /// Overflow (run-time error 6) of a Date sum `a op b` that gave `n` past the days a Date
    /// holds ("Date data type": 1 January 100 to 31 December 9999; `d + 1` of 12/31/9999).
    /// Only `+` and `-` give a Date: a Date times, over or to the power of a number is a
    /// Double ([MS-VBAL] "* Operator", 5.6.9.3.5), so `Now * 86400` is no Overflow. The
    /// operator and the range are checked before the operands' types, which cost a walk of
    /// both operands, so that `i = i + 1` pays nothing for them.
    fn date_overflow(&self, op: BinOp, (a, b): (&Expr, &Expr), n: f64) -> Option<Fault> {
        if !matches!(op, BinOp::Add | BinOp::Sub) || crate::eval::dates::VBA_DATE_RANGE.contains(&n) {
            return None;
        }
        if date_sum_type(op, self.held_operand(a), self.held_operand(b)) != Some(Declared::Date) {
            return None;
        }
        let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
        Some(self.overflow_fault(
            self.expr_span(a),
            format!("{shown} overflows: a Date holds 1/1/100 to 12/31/9999, not {}", general(n)),
        ))
    }

    /// Overflow (run-time error 6) of `a op b`, whose operands had `values` and which gave
    /// `result`, when its declared type is integral and the result (or, for `\` and `Mod`,
    /// an operand made whole) is past that type's range.
    pub(super) fn overflow(
        &self,
        op: BinOp,
        (a, b): (&Expr, &Expr),
        values: (&Value, &Value),
        result: &Value,
    ) -> Option<Fault> {
        let Value::Number(n) = *result else { return None };
        if let Some(fault) = self.date_overflow(op, (a, b), n) {
            return Some(fault);
        }
        let (ty, checked) = match op {
            BinOp::Add | BinOp::Sub | BinOp::Mul => {
                // Nothing fits every integral type, and a fraction is no integral result.
                if (0.0..=255.0).contains(&n) || n.fract() != 0.0 {
                    return None;
                }
                let ty = sum_type(self.declared_type(a), self.declared_type(b));
                if ty == Declared::Variant {
                    self.note_widening(a, binary_type(op, self.held_operand(a), self.held_operand(b)), n);
                    return None;
                }
                (ty, vec![n])
            }
            BinOp::IntDiv | BinOp::Mod => {
                let number = |v: &Value| to_number(v, DateSystem::From1900).ok().map(f64::round_ties_even);
                let (x, y) = (number(values.0)?, number(values.1)?);
                if [x, y, n].iter().all(|v| (0.0..=255.0).contains(v)) {
                    return None;
                }
                let (da, db) = (self.declared_type(a), self.declared_type(b));
                if da == Declared::Variant || db == Declared::Variant {
                    self.note_widening(a, binary_type(op, self.held_operand(a), self.held_operand(b)), n);
                    return None;
                }
                (whole_division_type(da, db), vec![x, y, n])
            }
            _ => return None,
        };
        let (low, high, holds) = ty.range()?;
        let past = checked.into_iter().find(|v| !(low..=high).contains(v))?;
        let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
        Some(self.overflow_fault(
            self.expr_span(a),
            format!("{shown} overflows: its operands' types make it {holds}, which cannot hold {}", general(past)),
        ))
    }
}
