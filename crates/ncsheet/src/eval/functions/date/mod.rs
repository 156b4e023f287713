//! Dates and times: DATE, TIME and their parts, date arithmetic (EDATE, EOMONTH, DAYS,
//! DAYS360, DATEDIF, YEARFRAC), working days (NETWORKDAYS, WORKDAY and their .INTL forms),
//! weeks (WEEKDAY, WEEKNUM, ISOWEEKNUM), text (DATEVALUE, TIMEVALUE) and the clock (TODAY,
//! NOW). Serials and the calendar are `eval::dates`; every argument lifts over arrays.

use crate::eval::coerce::{to_bool, to_number, to_text};
use crate::eval::dates::{self, days_in_month, is_leap_year, serial_from_ymd, DateSystem, DateTime, LAST_SERIAL};
use crate::eval::functions::api::{
    for_each_value, in_locale, lift, lift_in_locale, lift_values, Ctx, FnSpec, Outside, Source,
};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use crate::eval::functions::math::basic::toolpak_number;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "DATE",
        3,
        3,
        date,
        "DATE(year, month, day)",
        "Serial number of a date; months and days beyond their range roll over",
    )
    .biff(65),
    FnSpec::value(
        "DATEDIF",
        3,
        3,
        datedif,
        "DATEDIF(start_date, end_date, unit)",
        "Whole years (\"Y\"), months (\"M\"), days (\"D\") or the rest (\"YM\", \"YD\", \"MD\") between two dates",
    )
    .biff(351),
    FnSpec::value(
        "DATEVALUE",
        1,
        1,
        datevalue,
        "DATEVALUE(date_text)",
        "Serial number of a date written as text (2024-01-10, 1/10/2024, 10-Jan-2024)",
    )
    .biff(140),
    FnSpec::value("DAY", 1, 1, day, "DAY(serial_number)", "Day of the month, 1 to 31").biff(67),
    FnSpec::value("DAYS", 2, 2, days, "DAYS(end_date, start_date)", "Days from start_date to end_date").future(),
    FnSpec::value(
        "DAYS360",
        2,
        3,
        days360,
        "DAYS360(start_date, end_date, [method])",
        "Days between two dates in a 360-day year; method TRUE is the European rule",
    )
    .biff(220),
    FnSpec::value(
        "EDATE",
        2,
        2,
        edate,
        "EDATE(start_date, months)",
        "The same day months later (or earlier), clamped to the month's last day",
    ),
    FnSpec::value(
        "EOMONTH",
        2,
        2,
        eomonth,
        "EOMONTH(start_date, months)",
        "Last day of the month months after (or before) start_date",
    ),
    FnSpec::value("HOUR", 1, 1, hour, "HOUR(serial_number)", "Hour of the time, 0 to 23").biff(71),
    FnSpec::value("ISOWEEKNUM", 1, 1, isoweeknum, "ISOWEEKNUM(date)", "ISO 8601 week number (weeks start on Monday)").future(),
    FnSpec::value("MINUTE", 1, 1, minute, "MINUTE(serial_number)", "Minute of the time, 0 to 59").biff(72),
    FnSpec::value("MONTH", 1, 1, month, "MONTH(serial_number)", "Month of the date, 1 to 12").biff(68),
    FnSpec::value(
        "NETWORKDAYS",
        2,
        3,
        networkdays,
        "NETWORKDAYS(start_date, end_date, [holidays])",
        "Working days (Monday to Friday, not holidays) from start_date to end_date inclusive",
    ),
    FnSpec::value(
        "NETWORKDAYS.INTL",
        2,
        4,
        networkdays_intl,
        "NETWORKDAYS.INTL(start_date, end_date, [weekend], [holidays])",
        "NETWORKDAYS with the weekend days chosen (1-7, 11-17 or a mask like \"0000011\")",
    ),
    FnSpec::value("NOW", 0, 0, now, "NOW()", "The current date and time (volatile)")
        .biff(74).volatile().reads(Outside::Clock),
    FnSpec::value("SECOND", 1, 1, second, "SECOND(serial_number)", "Second of the time, 0 to 59").biff(73),
    FnSpec::value(
        "TIME",
        3,
        3,
        time,
        "TIME(hour, minute, second)",
        "Time of day as a fraction of a day; beyond 24 hours it wraps",
    )
    .biff(66),
    FnSpec::value(
        "TIMEVALUE",
        1,
        1,
        timevalue,
        "TIMEVALUE(time_text)",
        "Time of day of a time written as text (13:30, 1:30 PM), as a fraction of a day",
    )
    .biff(141),
    FnSpec::value("TODAY", 0, 0, today, "TODAY()", "The current date (volatile)")
        .biff(221).volatile().reads(Outside::Clock),
    FnSpec::value(
        "WEEKDAY",
        1,
        2,
        weekday,
        "WEEKDAY(serial_number, [return_type])",
        "Day of the week: 1 (Sunday) to 7; return_type 2, 3, 11-17 count from other days",
    )
    .biff(70),
    FnSpec::value(
        "WEEKNUM",
        1,
        2,
        weeknum,
        "WEEKNUM(serial_number, [return_type])",
        "Week of the year, the week of January 1 being 1; return_type picks the first weekday (21: ISO)",
    ),
    FnSpec::value(
        "WORKDAY",
        2,
        3,
        workday,
        "WORKDAY(start_date, days, [holidays])",
        "The date days working days (Monday to Friday, not holidays) after start_date",
    ),
    FnSpec::value(
        "WORKDAY.INTL",
        2,
        4,
        workday_intl,
        "WORKDAY.INTL(start_date, days, [weekend], [holidays])",
        "WORKDAY with the weekend days chosen (1-7, 11-17 or a mask like \"0000011\")",
    ),
    FnSpec::value("YEAR", 1, 1, year, "YEAR(serial_number)", "Year of the date, 1900 to 9999").biff(69),
    FnSpec::value(
        "YEARFRAC",
        2,
        3,
        yearfrac,
        "YEARFRAC(start_date, end_date, [basis])",
        "Fraction of a year between two dates; basis 0 US 30/360, 1 actual, 2 actual/360, 3 actual/365, 4 European 30/360",
    ),
];

// ---- arguments ----------------------------------------------------------------------------

/// A date-time argument as a serial: numbers, date text, booleans and blanks as arithmetic
/// reads them; `#NUM!` before serial 0 or after 9999-12-31.
fn serial(v: &Value, dates: DateSystem) -> XlResult<f64> {
    let n = to_number(v, dates)?;
    if (0.0..(LAST_SERIAL + 1) as f64).contains(&n) {
        Ok(n)
    } else {
        Err(XlError::Num)
    }
}

/// [`lift`] for functions whose every argument is a date, a time or a number: text reads as
/// the workbook's locale reads it (`YEAR("12.03.2025")` is 2025 in de-DE), as arithmetic does.
fn lift_dates(ctx: &mut Ctx, args: &[Expr], f: &dyn Fn(&[Value]) -> XlResult<Value>) -> XlResult<Value> {
    lift_in_locale(ctx, args, &|_| true, f)
}

/// A date argument split into calendar parts (time rounded to the second, as Excel does).
/// A time that rounds up past 9999-12-31's last second is `#NUM!`, as the next day is: that
/// day is no date ("YEAR function": 1900 to 9999; `YEAR(2958465.9999999)` was 10000).
fn date_time(v: &Value, dates: DateSystem) -> XlResult<DateTime> {
    let split = DateTime::from_serial(dates, serial(v, dates)?, 0);
    if split.serial > LAST_SERIAL {
        return Err(XlError::Num);
    }
    Ok(split)
}

/// A date argument of an Analysis ToolPak function (EDATE, EOMONTH, WORKDAY, NETWORKDAYS,
/// YEARFRAC): booleans are `#VALUE!` there.
fn toolpak_date(v: &Value, dates: DateSystem) -> XlResult<DateTime> {
    toolpak_number(v, dates)?;
    date_time(v, dates)
}

/// A count argument (months, days, a type): truncated toward zero as Excel does.
fn whole(v: &Value, dates: DateSystem) -> XlResult<i64> {
    let n = to_number(v, dates)?.trunc();
    if n.abs() < 1e15 {
        Ok(n as i64)
    } else {
        Err(XlError::Num)
    }
}

/// An optional argument: `None` when omitted or left empty (`WEEKDAY(A1,)`).
fn given(args: &[Expr], i: usize) -> bool {
    args.get(i).is_some_and(|e| e.kind != ExprKind::Missing)
}

/// A computed date as a value: `#NUM!` outside Excel's days.
fn date_result(serial: i64) -> XlResult<Value> {
    if (0..=LAST_SERIAL).contains(&serial) {
        Ok(Value::Number(serial as f64))
    } else {
        Err(XlError::Num)
    }
}

// ---- dates and times ----------------------------------------------------------------------

/// DATE: years 0–1899 are read as 1900–3799 (DATE(24,1,1) is 1924). The year the months
/// roll into must be 1900–9999 before the days roll on: DATE(9999,13,-1) is `#NUM!` in Excel
/// although 9999-12-30 exists.
fn date(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let (y, m, d) = (whole(&v[0], dates)?, whole(&v[1], dates)?, whole(&v[2], dates)?);
        let y = if (0..1900).contains(&y) { y + 1900 } else { y };
        let rolled_year = (y * 12 + m - 1).div_euclid(12);
        if !(1900..10_000).contains(&rolled_year) {
            return Err(XlError::Num);
        }
        date_result(serial_from_ymd(dates, y, m, d))
    })
}

fn year(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(date_time(&v[0], dates)?.year as f64)))
}

fn month(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(f64::from(date_time(&v[0], dates)?.month))))
}

fn day(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(f64::from(date_time(&v[0], dates)?.day))))
}

fn hour(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(f64::from(date_time(&v[0], dates)?.hour))))
}

fn minute(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(f64::from(date_time(&v[0], dates)?.minute))))
}

fn second(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(f64::from(date_time(&v[0], dates)?.second))))
}

/// TIME: each part truncated, each at most 32767; a negative total is `#NUM!`; whole days
/// are dropped (TIME(25,0,0) is 1:00).
fn time(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let (h, m, s) = (whole(&v[0], dates)?, whole(&v[1], dates)?, whole(&v[2], dates)?);
        if h.max(m).max(s) > 32_767 {
            return Err(XlError::Num);
        }
        let seconds = h * 3600 + m * 60 + s;
        if seconds < 0 {
            return Err(XlError::Num);
        }
        // The whole days dropped from the quotient in doubles, as Excel does: its stored value
        // of TIME(23,120,0) is 4.1666666666666741E-2 (IronCalc's corpus, DATE_TIME.xlsx), not
        // the 1/24 that dropping whole seconds first would give.
        let days = seconds as f64 / 86_400.0;
        Ok(Value::Number(days - days.floor()))
    })
}

fn now(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(ctx.env.now()))
}

fn today(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(ctx.env.now().floor()))
}

/// The date and time written in a text argument (numbers are `#VALUE!`: these read text).
fn date_text(v: &Value, locale: crate::eval::Locale, dates: DateSystem) -> XlResult<dates::DateText> {
    match v {
        // In the user's locale: `12.03.2025` is 12 March in et-EE.
        Value::Text(t) => locale.read_date_text(t.trim(), dates).ok_or(XlError::Value),
        Value::Error(e) => Err(*e),
        _ => Err(XlError::Value),
    }
}

/// DATEVALUE: the date's serial; a time in the text is dropped; text without a date is `#VALUE!`.
fn datevalue(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    lift(ctx, args, &|v| {
        let date = date_text(&v[0], locale, dates)?.date.ok_or(XlError::Value)?;
        Ok(Value::Number(date as f64))
    })
}

/// TIMEVALUE: the time of day (24:00 is 0); text with only a date is 0.
fn timevalue(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    lift(ctx, args, &|v| {
        let t = date_text(&v[0], locale, dates)?.time.unwrap_or(0.0);
        Ok(Value::Number(t - t.floor()))
    })
}

// ---- date arithmetic ----------------------------------------------------------------------

/// The day of the month `months` after `start`'s, clamped to that month's length (`last_day`:
/// the month's last day instead).
fn add_months(start: &DateTime, months: i64, last_day: bool, dates: DateSystem) -> XlResult<Value> {
    // A month count past the calendar's ten thousand years (EDATE(1,1E+300)) is #NUM!, never
    // an overflow.
    let total = (start.year * 12 + i64::from(start.month) - 1).checked_add(months).ok_or(XlError::Num)?;
    let (y, m) = (total.div_euclid(12), (total.rem_euclid(12) + 1) as u32);
    if !(1900..10_000).contains(&y) {
        return Err(XlError::Num);
    }
    let length = days_in_month(y, m);
    let d = if last_day { length } else { start.day.min(length) };
    date_result(serial_from_ymd(dates, y, i64::from(m), i64::from(d)))
}

fn edate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let start = toolpak_date(&v[0], dates)?;
        add_months(&start, toolpak_number(&v[1], dates)?.trunc() as i64, false, dates)
    })
}

fn eomonth(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let start = toolpak_date(&v[0], dates)?;
        add_months(&start, toolpak_number(&v[1], dates)?.trunc() as i64, true, dates)
    })
}

/// DAYS: whole days between the dates, the times dropped.
fn days(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let (end, start) = (serial(&v[0], dates)?.trunc(), serial(&v[1], dates)?.trunc());
        Ok(Value::Number(end - start))
    })
}

/// DAYS360: each month 30 days. US (NASD) rule: a start on its month's last day is the 30th;
/// an end on the 31st is the 30th when the start is the 30th or later, else the 1st of the next
/// month. European rule (method TRUE): every 31st is the 30th.
fn days360(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let (start, end) = (date_time(&v[0], dates)?, date_time(&v[1], dates)?);
        let european = match v.get(2) {
            Some(m) => to_bool(m)?,
            None => false,
        };
        let (mut d1, mut d2, mut m2) = (start.day, end.day, end.month);
        if european {
            d1 = d1.min(30);
            d2 = d2.min(30);
        } else {
            if d1 == days_in_month(start.year, start.month) {
                d1 = 30;
            }
            if d2 == 31 && d1 < 30 {
                (d2, m2) = (1, m2 + 1);
            } else if d2 == 31 {
                d2 = 30;
            }
        }
        Ok(Value::Number(thirty_360(start.year, start.month, d1, end.year, m2, d2) as f64))
    })
}

/// Days between two dates whose days were already adjusted to a 30-day month.
fn thirty_360(y1: i64, m1: u32, d1: u32, y2: i64, m2: u32, d2: u32) -> i64 {
    (y2 - y1) * 360 + (i64::from(m2) - i64::from(m1)) * 30 + i64::from(d2) - i64::from(d1)
}

/// DATEDIF, with Excel's arithmetic for the remainders: "MD" counts from the start's day in
/// the month before the end (DATE's rollover included, so Jan 31 to Mar 1 gives -2, as in
/// Excel), "YD" from the start's month and day in the end's year or the year before.
fn datedif(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    // The dates read in the locale; the unit is text.
    lift_in_locale(ctx, args, &|i| i < 2, &|v| {
        let (start, end) = (date_time(&v[0], dates)?, date_time(&v[1], dates)?);
        let unit = match &v[2] {
            Value::Error(e) => return Err(*e),
            other => to_text(other)?.to_ascii_uppercase(),
        };
        if start.serial > end.serial {
            return Err(XlError::Num);
        }
        let months = (end.year - start.year) * 12 + i64::from(end.month)
            - i64::from(start.month)
            - i64::from(end.day < start.day);
        let (d1, d2) = (i64::from(start.day), i64::from(end.day));
        let n = match unit.as_str() {
            "D" => end.serial - start.serial,
            "M" => months,
            "Y" => months / 12,
            "YM" => months % 12,
            "MD" if d2 >= d1 => d2 - d1,
            "MD" => end.serial - serial_from_ymd(dates, end.year, i64::from(end.month) - 1, d1),
            "YD" => {
                let same_year = (end.month, end.day) >= (start.month, start.day);
                let y = if same_year { end.year } else { end.year - 1 };
                end.serial - serial_from_ymd(dates, y, i64::from(start.month), d1)
            }
            _ => return Err(XlError::Num),
        };
        Ok(Value::Number(n as f64))
    })
}

/// YEARFRAC: the dates in either order; basis 0 (US 30/360), 1 (actual days over the actual
/// year length), 2 (actual/360), 3 (actual/365), 4 (European 30/360).
fn yearfrac(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let (mut a, mut b) = (toolpak_date(&v[0], dates)?, toolpak_date(&v[1], dates)?);
        let basis = match v.get(2) {
            Some(basis) => toolpak_number(basis, dates)?.trunc(),
            None => 0.0,
        };
        if a.serial > b.serial {
            std::mem::swap(&mut a, &mut b);
        }
        let actual = (b.serial - a.serial) as f64;
        let fraction = match basis as i64 {
            0 => us_30_360(&a, &b) as f64 / 360.0,
            1 => actual / actual_year_length(&a, &b, dates),
            2 => actual / 360.0,
            3 => actual / 365.0,
            4 => thirty_360(a.year, a.month, a.day.min(30), b.year, b.month, b.day.min(30)) as f64 / 360.0,
            _ => return Err(XlError::Num),
        };
        Ok(Value::Number(fraction))
    })
}

/// YEARFRAC's US 30/360 day count, which treats the end of February apart from DAYS360's.
fn us_30_360(a: &DateTime, b: &DateTime) -> i64 {
    let last_of_feb = |t: &DateTime| t.month == 2 && t.day == days_in_month(t.year, 2);
    let (mut d1, mut d2) = (a.day, b.day);
    if d1 == 31 && d2 == 31 {
        (d1, d2) = (30, 30);
    } else if d1 == 31 {
        d1 = 30;
    } else if d1 == 30 && d2 == 31 {
        d2 = 30;
    } else if last_of_feb(a) && last_of_feb(b) {
        (d1, d2) = (30, 30);
    } else if last_of_feb(a) {
        d1 = 30;
    }
    thirty_360(a.year, a.month, d1, b.year, b.month, d2)
}

/// Basis 1's year length: within a year (up to the same day a year on), 366 when the span
/// touches a February 29 and 365 otherwise; over longer spans the mean length of the years
/// from the first to the last.
pub(crate) fn actual_year_length(a: &DateTime, b: &DateTime, dates: DateSystem) -> f64 {
    let within_a_year = a.year == b.year || (a.year + 1 == b.year && (a.month, a.day) >= (b.month, b.day));
    if within_a_year {
        let leap_day_inside = [a.year, b.year]
            .iter()
            .any(|&y| is_leap_year(y) && (a.serial..=b.serial).contains(&serial_from_ymd(dates, y, 2, 29)));
        let leap = (a.year == b.year && is_leap_year(a.year)) || leap_day_inside;
        return if leap { 366.0 } else { 365.0 };
    }
    let years = b.year - a.year + 1;
    let days = serial_from_ymd(dates, b.year + 1, 1, 1) - serial_from_ymd(dates, a.year, 1, 1);
    days as f64 / years as f64
}

// ---- weeks --------------------------------------------------------------------------------

/// WEEKDAY: return_type 1 (Sunday 1 … Saturday 7), 2 (Monday 1 … Sunday 7), 3 (Monday 0 …
/// Sunday 6), 11–17 (Monday … Sunday is 1).
fn weekday(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let dow = i64::from(date_time(&v[0], dates)?.weekday);
        let kind = if v.len() > 1 { whole(&v[1], dates)? } else { 1 };
        let n = match kind {
            1 => dow + 1,
            2 => (dow + 6) % 7 + 1,
            3 => (dow + 6) % 7,
            11..=17 => (dow - (kind - 10)).rem_euclid(7) + 1,
            _ => return Err(XlError::Num),
        };
        Ok(Value::Number(n as f64))
    })
}

/// WEEKNUM: the week holding January 1 is week 1 and weeks start on the return_type's day: 1
/// or 17 Sunday, 2 or 11 Monday, 12–16 Tuesday to Saturday; 21 is the ISO week.
fn weeknum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| {
        let t = date_time(&v[0], dates)?;
        let kind = if v.len() > 1 { whole(&v[1], dates)? } else { 1 };
        let first_day = match kind {
            1 | 17 => 0,
            2 | 11 => 1,
            12..=16 => kind - 10,
            21 => return Ok(Value::Number(iso_week(t.serial, dates) as f64)),
            _ => return Err(XlError::Num),
        };
        let jan1 = serial_from_ymd(dates, t.year, 1, 1);
        let lead = (i64::from(dates::weekday(dates, jan1)) - first_day).rem_euclid(7);
        Ok(Value::Number(((t.serial - jan1 + lead) / 7 + 1) as f64))
    })
}

fn isoweeknum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_dates(ctx, args, &|v| Ok(Value::Number(iso_week(date_time(&v[0], dates)?.serial, dates) as f64)))
}

/// ISO 8601 week: the week (Monday to Sunday) whose Thursday is in the year; week 1 holds the
/// year's first Thursday.
fn iso_week(serial: i64, dates: DateSystem) -> i64 {
    let from_monday = (i64::from(dates::weekday(dates, serial)) + 6) % 7;
    let thursday = serial - from_monday + 3;
    // Thursdays before serial 1 belong to 1899 (Excel's calendar has no days there).
    let year = if thursday < 1 { 1899 } else { dates::ymd_from_serial(dates, thursday).0 };
    (thursday - serial_from_ymd(dates, year, 1, 1)) / 7 + 1
}

// ---- working days -------------------------------------------------------------------------

/// Which days of the week (0 = Sunday) are weekend days.
type Weekend = [bool; 7];

const SATURDAY_SUNDAY: Weekend = [true, false, false, false, false, false, true];

/// The .INTL functions' weekend argument: 1–7 a pair of days (1 Saturday and Sunday, 2 Sunday
/// and Monday, … 7 Friday and Saturday), 11–17 one day (11 Sunday … 17 Saturday), or seven
/// `0`/`1` characters from Monday; every day a weekend day is `#VALUE!`.
fn weekend(v: &Value, dates: DateSystem) -> XlResult<Weekend> {
    let mut days = [false; 7];
    match v {
        Value::Blank => return Ok(SATURDAY_SUNDAY),
        Value::Text(mask) => {
            if mask.len() != 7 || !mask.bytes().all(|b| b == b'0' || b == b'1') {
                return Err(XlError::Value);
            }
            for (i, b) in mask.bytes().enumerate() {
                days[(i + 1) % 7] = b == b'1';
            }
        }
        other => match whole(other, dates)? {
            n @ 1..=7 => {
                let first = (n - 2).rem_euclid(7) as usize;
                days[first] = true;
                days[(first + 1) % 7] = true;
            }
            n @ 11..=17 => days[(n - 11) as usize] = true,
            _ => return Err(XlError::Num),
        },
    }
    if days.iter().all(|&d| d) {
        return Err(XlError::Value);
    }
    Ok(days)
}

/// The holidays argument: dates from a range, an array or a value, sorted, each once. Blank
/// cells are skipped; text and booleans in a range are `#VALUE!`.
fn holidays(ctx: &mut Ctx, args: &[Expr], i: usize) -> XlResult<Vec<i64>> {
    let (dates, locale) = (ctx.dates(), ctx.locale());
    let mut out = Vec::new();
    if !given(args, i) {
        return Ok(out);
    }
    for_each_value(ctx, &args[i..=i], &mut |v, source| {
        let day = match (v, source) {
            (Value::Number(_), _) => serial(v, dates)?.trunc() as i64,
            // Typed date text, read in the locale (`"13.03.2025"` in de-DE).
            (Value::Text(_), Source::Direct) => {
                serial(&locale.numbers_for_arithmetic(v.clone(), dates), dates)?.trunc() as i64
            }
            (Value::Error(e), _) => return Err(*e),
            _ => return Err(XlError::Value),
        };
        out.push(day);
        Ok(())
    })?;
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// A working-day calendar: the weekend days and the holidays (sorted).
struct Workdays<'a> {
    weekend: Weekend,
    holidays: &'a [i64],
    /// The workbook's date system, which weekdays are counted in.
    dates: DateSystem,
}

impl Workdays<'_> {
    fn is_workday(&self, serial: i64) -> bool {
        !self.weekend[dates::weekday(self.dates, serial) as usize] && self.holidays.binary_search(&serial).is_err()
    }

    /// The holidays from `lo` to `hi` inclusive, found by binary search: scanning the whole
    /// list for every week stepped made WORKDAY quadratic in the holidays.
    fn holidays_in(&self, lo: i64, hi: i64) -> &[i64] {
        let from = self.holidays.partition_point(|&h| h < lo);
        let to = self.holidays.partition_point(|&h| h <= hi);
        &self.holidays[from..to.max(from)]
    }

    fn any_holiday_in(&self, lo: i64, hi: i64) -> bool {
        !self.holidays_in(lo, hi).is_empty()
    }

    fn per_week(&self) -> i64 {
        self.weekend.iter().filter(|&&w| !w).count() as i64
    }

    /// Working days from `start` to `end` inclusive; negative when `end` is before `start`.
    fn between(&self, start: i64, end: i64) -> i64 {
        let (lo, hi) = (start.min(end), start.max(end));
        let weeks = (hi - lo + 1) / 7;
        let rest =
            (lo + weeks * 7..=hi).filter(|&d| !self.weekend[dates::weekday(self.dates, d) as usize]).count() as i64;
        let holidays =
            self.holidays_in(lo, hi).iter().filter(|&&h| !self.weekend[dates::weekday(self.dates, h) as usize]).count()
                as i64;
        let n = weeks * self.per_week() + rest - holidays;
        if start > end {
            -n
        } else {
            n
        }
    }

    /// The working day `count` working days after `start` (before, when negative): whole weeks
    /// at a time where no holiday falls, day by day elsewhere.
    fn advance(&self, start: i64, count: i64) -> XlResult<i64> {
        let step = count.signum();
        let (mut day, mut left) = (start, count.abs());
        while left > 0 {
            if !(0..=LAST_SERIAL).contains(&day) {
                return Err(XlError::Num);
            }
            let week_ahead = if step > 0 { day + 1..=day + 7 } else { day - 7..=day - 1 };
            let holiday_ahead = self.any_holiday_in(*week_ahead.start(), *week_ahead.end());
            if left > self.per_week() && !holiday_ahead {
                day += 7 * step;
                left -= self.per_week();
                continue;
            }
            day += step;
            if self.is_workday(day) {
                left -= 1;
            }
        }
        Ok(day)
    }
}

/// The arguments of a working-day function: its lifted dates and counts (the first two), the
/// weekend (`weekend_at`, for the .INTL forms) and the holidays (`holidays_at`).
fn workdays_call(
    ctx: &mut Ctx,
    args: &[Expr],
    weekend_at: Option<usize>,
    holidays_at: usize,
    f: &dyn Fn(&Workdays, &Value, &Value) -> XlResult<Value>,
) -> XlResult<Value> {
    let dates = ctx.dates();
    let holidays = holidays(ctx, args, holidays_at)?;
    let weekend_value = match weekend_at {
        Some(i) if given(args, i) => ctx.eval(&args[i]),
        _ => Value::Blank,
    };
    // The start (and end) date and the count read in the locale; the weekend mask is text.
    let (first, second) = (ctx.eval(&args[0]), ctx.eval(&args[1]));
    let values = [in_locale(ctx, first), in_locale(ctx, second), weekend_value];
    lift_values(&values, &|v| {
        let calendar = Workdays { weekend: weekend(&v[2], dates)?, holidays: &holidays, dates };
        f(&calendar, &v[0], &v[1])
    })
}

fn networkdays_of(calendar: &Workdays, start: &Value, end: &Value) -> XlResult<Value> {
    let dates = calendar.dates;
    let (start, end) = (toolpak_date(start, dates)?.serial, toolpak_date(end, dates)?.serial);
    Ok(Value::Number(calendar.between(start, end) as f64))
}

fn workday_of(calendar: &Workdays, start: &Value, days: &Value) -> XlResult<Value> {
    let dates = calendar.dates;
    let start = toolpak_date(start, dates)?.serial;
    let count = toolpak_number(days, dates)?.trunc();
    if count.abs() > LAST_SERIAL as f64 {
        return Err(XlError::Num);
    }
    date_result(calendar.advance(start, count as i64)?)
}

fn networkdays(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    workdays_call(ctx, args, None, 2, &networkdays_of)
}

fn networkdays_intl(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    workdays_call(ctx, args, Some(2), 3, &networkdays_of)
}

fn workday(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    workdays_call(ctx, args, None, 2, &workday_of)
}

fn workday_intl(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    workdays_call(ctx, args, Some(2), 3, &workday_of)
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::testing::{err, n};
    use crate::eval::value::{Value, XlError};

    /// Values from Microsoft's documentation of each function and from hand counting on a
    /// calendar.
    fn check(cases: &[(&str, Value)]) {
        let env = MapEnv::with(&[("A1", n(45301.0)), ("A2", Value::Bool(true)), ("A3", Value::text("2"))]);
        for (formula, want) in cases {
            assert_eq!(&env.eval(formula), want, "{formula}");
        }
    }

    #[test]
    fn date_builds_serials_with_rollover() {
        check(&[
            ("=DATE(2024,1,10)", n(45301.0)),
            ("=DATE(2008,14,2)", n(39846.0)),
            ("=DATE(2008,1,35)", n(39482.0)),
            ("=DATE(2008,-3,2)", n(39327.0)),
            ("=DATE(108,1,2)", n(39449.0)),
            ("=DATE(1900,2,29)", n(60.0)),
            ("=DATE(1900,3,0)", n(60.0)),
            ("=DATE(1900,1,0)", n(0.0)),
            ("=DATE(1900,1,-1)", err(XlError::Num)),
            ("=DATE(10000,1,1)", err(XlError::Num)),
            ("=DATE(9999,13,-1)", err(XlError::Num)),
            ("=DATE(2024.9,1.9,10.9)", n(45301.0)),
            ("=DATE(\"x\",1,1)", err(XlError::Value)),
        ]);
    }

    #[test]
    fn parts_of_dates_and_times() {
        check(&[
            ("=YEAR(A1)", n(2024.0)),
            ("=MONTH(A1)", n(1.0)),
            ("=DAY(A1)", n(10.0)),
            ("=DAY(60)", n(29.0)),
            ("=DAY(0)", n(0.0)),
            ("=YEAR(\"2024-01-10\")", n(2024.0)),
            ("=YEAR(-1)", err(XlError::Num)),
            ("=YEAR(2958466)", err(XlError::Num)),
            ("=HOUR(0.75)", n(18.0)),
            ("=MINUTE(\"13:45\")", n(45.0)),
            ("=SECOND(TIME(1,2,3))", n(3.0)),
            ("=HOUR(0.99999999)", n(0.0)),
            ("=TIME(12,0,0)", n(0.5)),
            // 25/24 - 1 in doubles, as Excel computes it (TIME(23,120,0) in the corpus).
            ("=TIME(25,0,0)", n(25.0 / 24.0 - 1.0)),
            ("=TIME(0,-1,0)", err(XlError::Num)),
            ("=TIME(32768,0,0)", err(XlError::Num)),
        ]);
    }

    #[test]
    fn dates_and_times_from_text() {
        check(&[
            ("=DATEVALUE(\"1/10/2024\")", n(45301.0)),
            ("=DATEVALUE(\"10-Jan-2024 18:00\")", n(45301.0)),
            ("=DATEVALUE(\" 2024-01-10 \")", n(45301.0)),
            ("=DATEVALUE(45301)", err(XlError::Value)),
            ("=DATEVALUE(\"2023-02-29\")", err(XlError::Value)),
            ("=TIMEVALUE(\"6:00 PM\")", n(0.75)),
            ("=TIMEVALUE(\"24:00\")", n(0.0)),
            ("=TIMEVALUE(\"2024-01-10\")", n(0.0)),
        ]);
    }

    #[test]
    fn month_arithmetic_clamps_to_the_months_end() {
        check(&[
            ("=EDATE(DATE(2024,1,31),1)", n(45351.0)),
            ("=EDATE(DATE(2024,3,31),-1.9)", n(45351.0)),
            ("=EOMONTH(DATE(2024,1,10),1)", n(45351.0)),
            ("=EOMONTH(DATE(2024,1,10),-1)", n(45291.0)),
            ("=EDATE(A1,A2)", err(XlError::Value)),
            ("=EDATE(A1,A3)", n(45361.0)),
            ("=EOMONTH(DATE(1900,3,1),-3)", err(XlError::Num)),
        ]);
    }

    #[test]
    fn day_counts() {
        check(&[
            ("=DAYS(\"2024-03-01\",\"2024-02-01\")", n(29.0)),
            ("=DAYS(A1,A2)", n(45300.0)),
            ("=DAYS360(DATE(2024,1,31),DATE(2024,3,31))", n(60.0)),
            ("=DAYS360(DATE(2024,1,30),DATE(2024,3,31))", n(60.0)),
            ("=DAYS360(DATE(2024,1,29),DATE(2024,3,31))", n(62.0)),
            ("=DAYS360(DATE(2024,2,29),DATE(2024,3,31))", n(30.0)),
            ("=DAYS360(DATE(2024,1,29),DATE(2024,3,31),TRUE)", n(61.0)),
            ("=DATEDIF(DATE(2001,1,1),DATE(2003,1,1),\"Y\")", n(2.0)),
            ("=DATEDIF(DATE(2001,6,1),DATE(2002,8,15),\"D\")", n(440.0)),
            ("=DATEDIF(DATE(2001,6,1),DATE(2002,8,15),\"YD\")", n(75.0)),
            ("=DATEDIF(DATE(2001,6,1),DATE(2002,8,15),\"ym\")", n(2.0)),
            ("=DATEDIF(DATE(2001,6,20),DATE(2002,8,15),\"MD\")", n(26.0)),
            ("=DATEDIF(DATE(2015,1,31),DATE(2015,3,1),\"MD\")", n(-2.0)),
            ("=DATEDIF(DATE(2003,1,1),DATE(2001,1,1),\"Y\")", err(XlError::Num)),
            ("=DATEDIF(A1,A1,\"W\")", err(XlError::Num)),
        ]);
    }

    #[test]
    fn yearfrac_bases() {
        // Microsoft's example: 2012-01-01 to 2012-07-30.
        check(&[
            ("=YEARFRAC(DATE(2012,1,1),DATE(2012,7,30))", n(209.0 / 360.0)),
            ("=YEARFRAC(DATE(2012,1,1),DATE(2012,7,30),1)", n(211.0 / 366.0)),
            ("=YEARFRAC(DATE(2012,1,1),DATE(2012,7,30),3)", n(211.0 / 365.0)),
            ("=YEARFRAC(DATE(2012,7,30),DATE(2012,1,1),2)", n(211.0 / 360.0)),
            ("=YEARFRAC(DATE(2012,1,1),DATE(2012,7,30),5)", err(XlError::Num)),
        ]);
    }

    #[test]
    fn weeks() {
        // 2024-01-10 is a Wednesday, in ISO week 2.
        check(&[
            ("=WEEKDAY(A1)", n(4.0)),
            ("=WEEKDAY(A1,2)", n(3.0)),
            ("=WEEKDAY(A1,3)", n(2.0)),
            ("=WEEKDAY(A1,13)", n(1.0)),
            ("=WEEKDAY(A1,17)", n(4.0)),
            ("=WEEKDAY(A1,4)", err(XlError::Num)),
            ("=WEEKNUM(A1)", n(2.0)),
            ("=WEEKNUM(DATE(2024,1,6))", n(1.0)),
            ("=WEEKNUM(DATE(2024,1,7))", n(2.0)),
            ("=WEEKNUM(DATE(2024,1,7),2)", n(1.0)),
            ("=WEEKNUM(DATE(2021,1,1),21)", n(53.0)),
            ("=ISOWEEKNUM(A1)", n(2.0)),
            ("=ISOWEEKNUM(DATE(2024,12,30))", n(1.0)),
        ]);
    }

    #[test]
    fn working_days() {
        // January 2024: the 1st a Monday, 23 weekdays.
        check(&[
            ("=NETWORKDAYS(DATE(2024,1,1),DATE(2024,1,31))", n(23.0)),
            ("=NETWORKDAYS(DATE(2024,1,31),DATE(2024,1,1))", n(-23.0)),
            ("=NETWORKDAYS(DATE(2024,1,1),DATE(2024,1,31),{45292,45293,45294})", n(20.0)),
            ("=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),11)", n(27.0)),
            ("=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"0000000\")", n(31.0)),
            ("=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"1111111\")", err(XlError::Value)),
            ("=WORKDAY(DATE(2024,1,5),1)", n(45299.0)),
            ("=WORKDAY(DATE(2024,1,8),-1)", n(45296.0)),
            ("=WORKDAY(DATE(2024,1,1),22)", n(45322.0)),
            ("=WORKDAY(DATE(2024,1,1),22,DATE(2024,1,31))", n(45323.0)),
            ("=WORKDAY(DATE(2024,1,6),0)", n(45297.0)),
            ("=WORKDAY.INTL(DATE(2024,1,5),1,7)", n(45298.0)),
        ]);
    }
}
