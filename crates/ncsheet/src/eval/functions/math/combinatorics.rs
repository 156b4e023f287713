//! Counting and number theory (COMBIN, PERMUT, GCD, LCM, MULTINOMIAL, FACTDOUBLE, ISEVEN,
//! ISODD), sums over paired arrays (SUMX2MY2 …, SERIESSUM) and the matrix functions
//! (MMULT, MINVERSE, MDETERM, MUNIT, TRANSPOSE) through nalgebra.

use std::rc::Rc;

use nalgebra::DMatrix;

use crate::eval::coerce::{parse_number, parse_plain_number, to_number};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{
    block, check, finite, for_each_value, power, scalar, ArgSet, Ctx, FnSpec, Operand, Scalars, Source, MANY,
};
use crate::eval::value::{Array, Value, XlError, XlResult, MAX_ARRAY_ITEMS};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("COMBIN", 2, 2, combin, "COMBIN(number, number_chosen)", "Combinations without repetition").biff(276),
    FnSpec::value("COMBINA", 2, 2, combina, "COMBINA(number, number_chosen)", "Combinations with repetition").future(),
    FnSpec::value("PERMUT", 2, 2, permut, "PERMUT(number, number_chosen)", "Ordered selections without repetition")
        .biff(299),
    FnSpec::value(
        "PERMUTATIONA",
        2,
        2,
        permutationa,
        "PERMUTATIONA(number, number_chosen)",
        "Ordered selections with repetition: number^number_chosen",
    )
    .future(),
    FnSpec::value("GCD", 1, MANY, gcd, "GCD(number1, …)", "Greatest common divisor of whole numbers")
        .range_args(ArgSet::ALL),
    FnSpec::value("LCM", 1, MANY, lcm, "LCM(number1, …)", "Least common multiple of whole numbers")
        .range_args(ArgSet::ALL),
    FnSpec::value("MULTINOMIAL", 1, MANY, multinomial, "MULTINOMIAL(number1, …)", "(Σ numbers)! / Π numbers!")
        .range_args(ArgSet::ALL),
    FnSpec::value("FACTDOUBLE", 1, 1, factdouble, "FACTDOUBLE(number)", "Double factorial n·(n-2)·(n-4)…"),
    FnSpec::value("ISEVEN", 1, 1, iseven, "ISEVEN(number)", "TRUE when the integer part is even"),
    FnSpec::value("ISODD", 1, 1, isodd, "ISODD(number)", "TRUE when the integer part is odd"),
    FnSpec::value("SERIESSUM", 4, 4, seriessum, "SERIESSUM(x, n, m, coefficients)", "Σ coefficient_i · x^(n + i·m)")
        .array_args(ArgSet::only(3)),
    FnSpec::value("SUMX2MY2", 2, 2, sumx2my2, "SUMX2MY2(array_x, array_y)", "Σ (x² - y²) over pairs of numbers")
        .biff(304)
        .array_args(ArgSet::ALL),
    FnSpec::value("SUMX2PY2", 2, 2, sumx2py2, "SUMX2PY2(array_x, array_y)", "Σ (x² + y²) over pairs of numbers")
        .biff(305)
        .array_args(ArgSet::ALL),
    FnSpec::value("SUMXMY2", 2, 2, sumxmy2, "SUMXMY2(array_x, array_y)", "Σ (x - y)² over pairs of numbers")
        .biff(303)
        .array_args(ArgSet::ALL),
    FnSpec::value("MMULT", 2, 2, mmult, "MMULT(array1, array2)", "Matrix product").biff(165).array_args(ArgSet::ALL),
    FnSpec::value("MINVERSE", 1, 1, minverse, "MINVERSE(array)", "Inverse of a square matrix; #NUM! when singular")
        .biff(164)
        .array_args(ArgSet::ALL),
    FnSpec::value("MDETERM", 1, 1, mdeterm, "MDETERM(array)", "Determinant of a square matrix")
        .biff(163)
        .array_args(ArgSet::ALL),
    FnSpec::value("MUNIT", 1, 1, munit, "MUNIT(dimension)", "The identity matrix of that size").future(),
    FnSpec::value("TRANSPOSE", 1, 1, transpose, "TRANSPOSE(array)", "Rows become columns")
        .biff(83)
        .array_args(ArgSet::ALL),
];

/// A count argument: truncated, at least 0.
fn count(a: Scalars, i: usize) -> XlResult<f64> {
    let n = a.num(i)?.trunc();
    check(n >= 0.0, XlError::Num)?;
    Ok(n)
}

/// n! / (n-k)! / k! as a product of ratios, rounded to the whole number it is.
fn binomial(n: f64, k: f64) -> f64 {
    let k = k.min(n - k);
    let mut r: f64 = 1.0;
    let mut i = 0.0;
    // The product only grows (k ≤ n/2): once infinite it stays so, and stopping there keeps
    // COMBIN(1E+15,5E+14) from counting to 5E+14.
    while i < k && r.is_finite() {
        r = r * (n - i) / (i + 1.0);
        i += 1.0;
    }
    r.round()
}

fn combin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let (n, k) = (count(a, 0)?, count(a, 1)?);
        check(k <= n, XlError::Num)?;
        finite(binomial(n, k))
    })
}

fn combina(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let (n, k) = (count(a, 0)?, count(a, 1)?);
        check(n >= k || n > 0.0 || k == 0.0, XlError::Num)?;
        if n == 0.0 {
            return Ok(Value::Number(f64::from(k == 0.0)));
        }
        finite(binomial(n + k - 1.0, k))
    })
}

fn permut(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let (n, k) = (count(a, 0)?, count(a, 1)?);
        check(k <= n, XlError::Num)?;
        let mut r: f64 = 1.0;
        let mut i = 0.0;
        // Every factor is at least 1: once infinite the product stays so.
        while i < k && r.is_finite() {
            r *= n - i;
            i += 1.0;
        }
        finite(r)
    })
}

fn permutationa(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| finite(count(a, 0)?.powf(count(a, 1)?)))
}

/// The arguments' numbers as GCD, LCM and MULTINOMIAL read them: text anywhere is read as
/// a number (or is #VALUE!), booleans are #VALUE!, blank cells of a range are skipped but a
/// blank argument is #VALUE!.
fn strict_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let dates = ctx.dates();
    // An empty argument slot is Excel's #N/A here.
    check(args.iter().all(|a| a.kind != ExprKind::Missing), XlError::NA)?;
    let mut out = Vec::new();
    for_each_value(ctx, args, &mut |v, source| {
        match (v, source) {
            (Value::Blank, Source::Collection) => {}
            (Value::Blank | Value::Bool(_), _) => return Err(XlError::Value),
            (Value::Text(t), _) => out.push(parse_plain_number(t.trim()).ok_or(XlError::Value)?),
            (v, _) => out.push(to_number(v, dates)?),
        }
        Ok(())
    })?;
    Ok(out)
}

/// A text GCD or LCM reads as a number: a number, or date text ("2024-01-10").
fn text_number(t: &str, dates: DateSystem) -> XlResult<f64> {
    parse_plain_number(t.trim()).or_else(|| parse_number(t, dates)).ok_or(XlError::Value)
}

/// The arguments' numbers as GCD and LCM read them (Excel's stored results): text anywhere
/// is read as a number or date; booleans are #VALUE!; a blank single cell is skipped but a
/// range of several cells with a blank among them counts a 0; no number at all is #VALUE!.
fn divisor_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let dates = ctx.dates();
    // An empty argument slot is Excel's #N/A here.
    check(args.iter().all(|a| a.kind != ExprKind::Missing), XlError::NA)?;
    let read = |v: &Value| match v {
        Value::Bool(_) => Err(XlError::Value),
        Value::Text(t) => text_number(t, dates),
        v => to_number(v, dates),
    };
    let mut out = Vec::new();
    for a in args {
        match ctx.operand(a) {
            Operand::Ref(sheet, rect) => {
                let mut seen = 0u64;
                let mut outcome = Ok(());
                ctx.env.for_each_value(sheet, rect, &mut |_, v| {
                    if v.is_blank() || outcome.is_err() {
                        return;
                    }
                    seen += 1;
                    outcome = read(v).map(|n| out.push(n));
                });
                outcome?;
                if !rect.is_cell() && seen < u64::from(rect.rows()) * u64::from(rect.cols()) {
                    out.push(0.0);
                }
            }
            Operand::Value(Value::Array(arr)) => {
                for v in &arr.data {
                    out.push(read(v)?);
                }
            }
            Operand::Value(Value::Blank) | Operand::Areas(_) => return Err(XlError::Value),
            Operand::Value(v) => out.push(read(&v)?),
        }
    }
    check(!out.is_empty(), XlError::Value)?;
    Ok(out)
}

/// The arguments' numbers as whole numbers 0 ≤ n < 2^53.
fn whole_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let ns = divisor_numbers(ctx, args)?;
    ns.iter()
        .map(|&n| {
            check((0.0..9007199254740992.0).contains(&n), XlError::Num)?;
            Ok(n.trunc())
        })
        .collect()
}

fn gcd_of(mut a: f64, mut b: f64) -> f64 {
    while b != 0.0 && b.is_finite() {
        (a, b) = (b, a % b);
    }
    a
}

fn gcd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(whole_numbers(ctx, args)?.into_iter().fold(0.0, gcd_of)))
}

fn lcm(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let ns = whole_numbers(ctx, args)?;
    if ns.is_empty() || ns.contains(&0.0) {
        return Ok(Value::Number(0.0));
    }
    // Past 2^53 the result is #NUM!: stop there, before an infinite one makes Euclid's loop
    // endless.
    let mut lcm = 1.0;
    for n in ns {
        lcm = lcm / gcd_of(lcm, n) * n;
        check(lcm < 9007199254740992.0, XlError::Num)?;
    }
    Ok(Value::Number(lcm))
}

fn multinomial(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let ns = strict_numbers(ctx, args)?;
    let mut total = 0.0;
    let mut r = 1.0;
    for n in ns {
        check(n >= 0.0, XlError::Num)?;
        let n = n.trunc();
        // (total + n)! / (total! n!) = C(total + n, n)
        total += n;
        r *= binomial(total, n);
    }
    finite(r)
}

fn factdouble(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = a.num(0)?.trunc();
        check(n >= -1.0, XlError::Num)?;
        let mut r: f64 = 1.0;
        let mut k = n;
        while k > 1.0 && r.is_finite() {
            r *= k;
            k -= 2.0;
        }
        finite(r)
    })
}

/// The integer part of a number argument; text and booleans are #VALUE! (Analysis ToolPak).
fn parity(ctx: &mut Ctx, args: &[Expr], odd: bool) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = match a.value(0) {
            Value::Bool(_) => return Err(XlError::Value),
            _ => a.num(0)?.trunc(),
        };
        Ok(Value::Bool((n % 2.0 != 0.0) == odd))
    })
}

fn iseven(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    parity(ctx, args, false)
}

fn isodd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    parity(ctx, args, true)
}

/// A number argument; a boolean is #VALUE! (Analysis ToolPak).
fn toolpak_number(ctx: &mut Ctx, e: &Expr) -> XlResult<f64> {
    let dates = ctx.dates();
    match ctx.eval(e) {
        Value::Bool(_) => Err(XlError::Value),
        v => to_number(&v, dates),
    }
}

fn seriessum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let x = toolpak_number(ctx, &args[0])?;
    let n = toolpak_number(ctx, &args[1])?;
    let m = toolpak_number(ctx, &args[2])?;
    let coefficients = block(ctx, &args[3])?;
    let mut sum = 0.0;
    for (i, c) in coefficients.data.iter().enumerate() {
        let c = match c {
            Value::Number(c) => *c,
            Value::Error(e) => return Err(*e),
            _ => return Err(XlError::Value),
        };
        sum += c * power(x, n + i as f64 * m)?;
    }
    finite(sum)
}

/// Σ f(x, y) over the positions where both arrays hold numbers; #N/A when their sizes differ.
fn sum_pairs(ctx: &mut Ctx, args: &[Expr], f: fn(f64, f64) -> f64) -> XlResult<Value> {
    let x = block(ctx, &args[0])?;
    let y = block(ctx, &args[1])?;
    check(x.data.len() == y.data.len(), XlError::NA)?;
    let mut sum = 0.0;
    for (a, b) in x.data.iter().zip(&y.data) {
        match (a, b) {
            (Value::Error(e), _) | (_, Value::Error(e)) => return Err(*e),
            (Value::Number(a), Value::Number(b)) => sum += f(*a, *b),
            _ => {}
        }
    }
    finite(sum)
}

fn sumx2my2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    sum_pairs(ctx, args, |x, y| x * x - y * y)
}

fn sumx2py2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    sum_pairs(ctx, args, |x, y| x * x + y * y)
}

fn sumxmy2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    sum_pairs(ctx, args, |x, y| (x - y) * (x - y))
}

/// An argument as a matrix of numbers: any other item is #VALUE!.
/// More items than this in a matrix argument or result is refused (#NUM!) rather than
/// allocated, as SEQUENCE refuses a larger array: a whole column times a whole row would be
/// seventeen billion.
const MAX_MATRIX_ITEMS: usize = 16_777_216;

/// A matrix argument, whole: a whole row or column (`1:1+1`, a spill of one) counts every
/// item of its tail as Excel reads every cell.
fn matrix(ctx: &mut Ctx, e: &Expr) -> XlResult<DMatrix<f64>> {
    let a = block(ctx, e)?;
    let (rows, cols) = a.whole_size();
    if rows * cols > MAX_MATRIX_ITEMS {
        return Err(ctx.explain(XlError::Num, format!("a matrix of {rows} × {cols} items is too large")));
    }
    let mut items = Vec::with_capacity(rows * cols);
    for r in 0..rows {
        for c in 0..cols {
            match a.whole_get(r, c).expect("within the whole size") {
                Value::Number(n) => items.push(*n),
                Value::Error(e) => return Err(*e),
                _ => return Err(XlError::Value),
            }
        }
    }
    Ok(DMatrix::from_row_slice(rows, cols, &items))
}

fn to_value(m: &DMatrix<f64>) -> XlResult<Value> {
    let mut data = Vec::with_capacity(m.len());
    for r in 0..m.nrows() {
        for c in 0..m.ncols() {
            let x = m[(r, c)];
            check(x.is_finite(), XlError::Num)?;
            data.push(Value::Number(x));
        }
    }
    Ok(Value::Array(Rc::new(Array::new(m.nrows(), m.ncols(), data))))
}

fn mmult(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = matrix(ctx, &args[0])?;
    let b = matrix(ctx, &args[1])?;
    check(a.ncols() == b.nrows(), XlError::Value)?;
    if a.nrows() * b.ncols() > MAX_MATRIX_ITEMS {
        return Err(ctx.explain(XlError::Num, format!("a product of {} × {} items is too large", a.nrows(), b.ncols())));
    }
    let work = a.nrows().saturating_mul(a.ncols()).saturating_mul(b.ncols());
    if work > MAX_MMULT_WORK {
        let note = format!(
            "a product of {} × {} by {} × {} items is {work} multiply-adds, more than ncsheet's limit of {:e} for MMULT",
            a.nrows(),
            a.ncols(),
            b.nrows(),
            b.ncols(),
            MAX_MMULT_WORK as f64
        );
        return Err(ctx.explain(XlError::Num, note));
    }
    // Its multiply-adds, for a product inside MAP's LAMBDA (the result counts far fewer).
    ctx.charge(work);
    to_value(&(a * b))
}

/// The most multiply-adds one MMULT may take (rows × inner size × columns): 4·10^9, about a
/// second (two 1,587 × 1,587 matrices). The array limit allows 4,096 × 4,096 by 4,096 × 4,096,
/// 6.9·10^10, which took 13 s, and a cell of three such products ran past 30 s.
const MAX_MMULT_WORK: usize = 4_000_000_000;

/// The most work one LU decomposition (MINVERSE, MDETERM) may take: n³ steps, 10^9 (a
/// 1,000 × 1,000 matrix, under a second). The array limit allows 4,096 × 4,096, and 3,000 × 3,000
/// ran past 30 s.
const MAX_LU_WORK: usize = 1_000_000_000;

fn square(ctx: &mut Ctx, e: &Expr) -> XlResult<DMatrix<f64>> {
    let m = matrix(ctx, e)?;
    check(m.is_square(), XlError::Value)?;
    let n = m.nrows();
    let work = n.saturating_mul(n).saturating_mul(n);
    if work > MAX_LU_WORK {
        let note = format!(
            "a {n} × {n} matrix is more work than ncsheet's limit of {:e} for MINVERSE and MDETERM (n³ steps)",
            MAX_LU_WORK as f64
        );
        return Err(ctx.explain(XlError::Num, note));
    }
    // MINVERSE's and MDETERM's LU decomposition, about n^3 steps, inside MAP's LAMBDA.
    ctx.charge(work);
    Ok(m)
}

fn minverse(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = square(ctx, &args[0])?;
    // A zero determinant (as LU finds it) is a singular matrix: #NUM! as in Excel.
    let lu = m.lu();
    check(lu.determinant() != 0.0, XlError::Num)?;
    to_value(&lu.try_inverse().ok_or(XlError::Num)?)
}

fn mdeterm(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    finite(square(ctx, &args[0])?.lu().determinant())
}

fn munit(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // The lifted body cannot reach `ctx`: a size past the array limit is kept, and the note
    // docs/limits.md promises is given through `Ctx::room_for` after it.
    let too_large = std::cell::Cell::new(None);
    let unit = scalar(ctx, args, &|a| {
        let n = a.num(0)?.trunc();
        check((1.0..=1_048_576.0).contains(&n), XlError::Value)?;
        if n * n > MAX_ARRAY_ITEMS as f64 {
            too_large.set(Some(n as usize));
            return Err(XlError::Num);
        }
        to_value(&DMatrix::identity(n as usize, n as usize))
    });
    if let Some(n) = too_large.get() {
        ctx.room_for(n, n)?;
    }
    unit
}

/// Rows become columns; a tail (the rest of a whole row or column, one value) turns with
/// them, so `TRANSPOSE(1:1+1)` is a whole column held in memory as the row was.
fn transpose(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    // A blank cell reads as 0, as in Excel's result.
    let item = |v: &Value| match v {
        Value::Blank => Value::Number(0.0),
        v => v.clone(),
    };
    let mut data = Vec::with_capacity(a.data.len());
    for c in 0..a.cols {
        for r in 0..a.rows {
            data.push(item(a.get(r, c)));
        }
    }
    let turned = Array::new(a.cols, a.rows, data);
    let turned = match &a.tail {
        Some(t) => turned.with_tail(t.cols, t.rows, item(&t.fill)),
        None => turned,
    };
    Ok(Value::Array(Rc::new(turned)))
}
