//! Least-squares regression on one or several variables: LINEST and TREND, and their
//! exponential forms LOGEST and GROWTH (the same fit on ln y). The fit is an SVD solve through
//! nalgebra; the statistics are LINEST's five rows as Excel lays them out.

use std::rc::Rc;

use nalgebra::{DMatrix, DVector};

use crate::eval::functions::api::{block, bool_or, given, ArgSet, Ctx, FnSpec};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "GROWTH",
        1,
        4,
        growth,
        "GROWTH(known_ys, [known_xs], [new_xs], [const])",
        "Values on the exponential curve fitted to the known points",
    )
    .biff(52)
    .array_args(ArgSet::except(3)),
    FnSpec::value(
        "LINEST",
        1,
        4,
        linest,
        "LINEST(known_ys, [known_xs], [const], [stats])",
        "Least-squares line (or plane) coefficients, with regression statistics on request",
    )
    .biff(49)
    .array_args(ArgSet::only(0).and(ArgSet::only(1))),
    FnSpec::value(
        "LOGEST",
        1,
        4,
        logest,
        "LOGEST(known_ys, [known_xs], [const], [stats])",
        "Exponential curve y = b·m^x fitted by least squares, with statistics on request",
    )
    .biff(51)
    .array_args(ArgSet::only(0).and(ArgSet::only(1))),
    FnSpec::value(
        "TREND",
        1,
        4,
        trend,
        "TREND(known_ys, [known_xs], [new_xs], [const])",
        "Values on the least-squares line (or plane) through the known points",
    )
    .biff(50)
    .array_args(ArgSet::except(3)),
];

/// The known points: one row per observation, one column per variable.
struct Data {
    y: Vec<f64>,
    x: DMatrix<f64>,
    /// The variables run across columns of the sheet (known ys in a column) rather than rows.
    by_columns: bool,
}

/// The fitted coefficients, the variables' first, then the constant.
struct Fit {
    coef: Vec<f64>,
    constant: f64,
}

/// Every item as a number; anything else is `#VALUE!` (an error is itself).
pub(crate) fn all_numbers(a: &Array) -> XlResult<Vec<f64>> {
    a.data
        .iter()
        .map(|v| match v {
            Value::Number(n) => Ok(*n),
            Value::Error(e) => Err(*e),
            _ => Err(XlError::Value),
        })
        .collect()
}

fn read_data(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Data> {
    let ys = block(ctx, &args[0])?;
    let y = all_numbers(&ys)?;
    let n = y.len();
    if given(args, 1).is_none() {
        let x = DMatrix::from_fn(n, 1, |i, _| (i + 1) as f64);
        return Ok(Data { y, x, by_columns: true });
    }
    let xs = block(ctx, &args[1])?;
    let xv = all_numbers(&xs)?;
    if ys.cols == 1 && xs.rows == n && ys.rows > 1 {
        // Known ys in a column: each column of known xs is a variable.
        let x = DMatrix::from_fn(n, xs.cols, |i, j| xv[i * xs.cols + j]);
        return Ok(Data { y, x, by_columns: true });
    }
    if ys.rows == 1 && xs.cols == n && ys.cols > 1 {
        let x = DMatrix::from_fn(n, xs.rows, |i, j| xv[j * xs.cols + i]);
        return Ok(Data { y, x, by_columns: false });
    }
    if xv.len() == n {
        return Ok(Data { y, x: DMatrix::from_fn(n, 1, |i, _| xv[i]), by_columns: true });
    }
    Err(XlError::Ref)
}

/// The design matrix: the variables, and a column of ones for the constant.
fn design(x: &DMatrix<f64>, with_constant: bool) -> DMatrix<f64> {
    let k = x.ncols();
    DMatrix::from_fn(x.nrows(), k + usize::from(with_constant), |i, j| if j < k { x[(i, j)] } else { 1.0 })
}

/// The most work one fit may take: rows × columns × the smaller of the two, the SVD's
/// count of multiply-adds (a million rows by a few variables is 10^7; 1,000 rows by 5,000
/// variables, 5·10^9, ran for minutes).
const MAX_FIT_WORK: f64 = 1e9;

fn fit(ctx: &mut Ctx, data: &Data, with_constant: bool) -> XlResult<Fit> {
    let a = design(&data.x, with_constant);
    if a.nrows() == 0 {
        return Err(XlError::Value);
    }
    let (m, n) = (a.nrows() as f64, a.ncols() as f64);
    if m * n * m.min(n) > MAX_FIT_WORK {
        return Err(ctx.explain(
            XlError::Num,
            format!(
                "a fit of {m} rows by {n} variables is more work than ncsheet's limit of {MAX_FIT_WORK:e} \
                 (rows × variables × the smaller of the two)"
            ),
        ));
    }
    // A fit inside MAP's LAMBDA makes no array to count: its work is counted.
    ctx.charge((m * n * m.min(n)) as usize);
    let b = DVector::from_column_slice(&data.y);
    let solution = a.svd(true, true).solve(&b, 1e-13).map_err(|_| XlError::Num)?;
    let k = data.x.ncols();
    let constant = if with_constant { solution[k] } else { 0.0 };
    Ok(Fit { coef: solution.iter().take(k).copied().collect(), constant })
}

fn predict(fit: &Fit, point: &[f64]) -> f64 {
    fit.constant + fit.coef.iter().zip(point).map(|(m, x)| m * x).sum::<f64>()
}

/// ln of each y, `#NUM!` for one not positive (LOGEST, GROWTH).
fn log_data(mut data: Data) -> XlResult<Data> {
    for y in &mut data.y {
        if *y <= 0.0 {
            return Err(XlError::Num);
        }
        *y = y.ln();
    }
    Ok(data)
}

fn linest(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data = read_data(ctx, args)?;
    estimate(ctx, args, data, false)
}

fn logest(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data = log_data(read_data(ctx, args)?)?;
    estimate(ctx, args, data, true)
}

fn estimate(ctx: &mut Ctx, args: &[Expr], data: Data, exponential: bool) -> XlResult<Value> {
    let with_constant = bool_or(ctx, args, 2, true)?;
    let stats = bool_or(ctx, args, 3, false)?;
    let f = fit(ctx, &data, with_constant)?;
    let shown = |v: f64| if exponential { v.exp() } else { v };
    // Excel lists the coefficients last variable first, then the constant.
    let mut first_row: Vec<Value> = f.coef.iter().rev().map(|&m| Value::Number(shown(m))).collect();
    first_row.push(Value::Number(shown(f.constant)));
    if !stats {
        return Ok(Value::Array(Rc::new(Array::row(first_row))));
    }
    let rows = statistics(&data, &f, with_constant)?;
    let cols = first_row.len();
    let mut out = first_row;
    for row in rows {
        let len = row.len();
        out.extend(row);
        out.extend(std::iter::repeat_n(Value::Error(XlError::NA), cols - len));
    }
    Ok(Value::Array(Rc::new(Array::new(5, cols, out))))
}

/// LINEST's rows 2 to 5: standard errors; r² and the standard error of y; F and the degrees
/// of freedom; the regression and residual sums of squares.
fn statistics(data: &Data, f: &Fit, with_constant: bool) -> XlResult<Vec<Vec<Value>>> {
    let n = data.y.len();
    let k = data.x.ncols();
    let df = n as f64 - k as f64 - if with_constant { 1.0 } else { 0.0 };
    let ss_resid: f64 =
        (0..n).map(|i| data.y[i] - predict(f, &data.x.row(i).iter().copied().collect::<Vec<_>>())).map(|r| r * r).sum();
    let mean = data.y.iter().sum::<f64>() / n as f64;
    let ss_total: f64 = if with_constant {
        data.y.iter().map(|y| (y - mean) * (y - mean)).sum()
    } else {
        data.y.iter().map(|y| y * y).sum()
    };
    let ss_reg = ss_total - ss_resid;
    let num = |v: f64| if v.is_finite() { Value::Number(v) } else { Value::Error(XlError::Num) };
    let (se_y, f_stat) = if df > 0.0 {
        (num((ss_resid / df).sqrt()), num((ss_reg / k as f64) / (ss_resid / df)))
    } else {
        (Value::Error(XlError::Num), Value::Error(XlError::Num))
    };
    let a = design(&data.x, with_constant);
    let inverse = (a.transpose() * &a).try_inverse().ok_or(XlError::Num)?;
    let sigma2 = if df > 0.0 { ss_resid / df } else { f64::NAN };
    let se = |j: usize| num((inverse[(j, j)] * sigma2).sqrt());
    let mut errors: Vec<Value> = (0..k).rev().map(se).collect();
    errors.push(if with_constant { se(k) } else { Value::Error(XlError::NA) });
    Ok(vec![
        errors,
        vec![num(ss_reg / ss_total), se_y],
        vec![f_stat, Value::Number(df)],
        vec![Value::Number(ss_reg), Value::Number(ss_resid)],
    ])
}

fn trend(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data = read_data(ctx, args)?;
    project(ctx, args, data, false)
}

fn growth(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data = log_data(read_data(ctx, args)?)?;
    project(ctx, args, data, true)
}

/// The fitted values at the new xs (the known xs by default), in the new xs' shape.
fn project(ctx: &mut Ctx, args: &[Expr], data: Data, exponential: bool) -> XlResult<Value> {
    let with_constant = bool_or(ctx, args, 3, true)?;
    let f = fit(ctx, &data, with_constant)?;
    let k = data.x.ncols();
    let shown = |v: f64| Value::Number(if exponential { v.exp() } else { v });
    let new = if given(args, 2).is_some() {
        block(ctx, &args[2])?
    } else if given(args, 1).is_some() {
        block(ctx, &args[1])?
    } else {
        let ys = block(ctx, &args[0])?;
        let data = (1..=ys.data.len()).map(|i| Value::Number(i as f64)).collect();
        Rc::new(Array::new(ys.rows, ys.cols, data))
    };
    let xs = all_numbers(&new)?;
    if k == 1 {
        let data = xs.iter().map(|&x| shown(predict(&f, &[x]))).collect();
        return Ok(Value::Array(Rc::new(Array::new(new.rows, new.cols, data))));
    }
    // Several variables: each row (or column) of the new xs is one point.
    if data.by_columns {
        if new.cols != k {
            return Err(XlError::Ref);
        }
        let out = (0..new.rows).map(|i| shown(predict(&f, &xs[i * k..(i + 1) * k]))).collect();
        Ok(Value::Array(Rc::new(Array::column(out))))
    } else {
        if new.rows != k {
            return Err(XlError::Ref);
        }
        let out = (0..new.cols)
            .map(|j| shown(predict(&f, &(0..k).map(|i| xs[i * new.cols + j]).collect::<Vec<_>>())))
            .collect();
        Ok(Value::Array(Rc::new(Array::row(out))))
    }
}
