//! Securities, the Analysis ToolPak set: coupon schedules (COUPPCD COUPNCD COUPNUM COUPDAYS
//! COUPDAYBS COUPDAYSNC), accrued interest (ACCRINT ACCRINTM), discounted and at-maturity
//! securities (DISC INTRATE RECEIVED PRICEDISC YIELDDISC PRICEMAT YIELDMAT) and coupon bonds
//! (PRICE YIELD DURATION MDURATION), also with an odd first or last period (ODDFPRICE
//! ODDFYIELD ODDLPRICE ODDLYIELD), and the French depreciation of an asset bought mid-period
//! (AMORLINC AMORDEGRC). Days are counted by the basis argument as YEARFRAC
//! reads it: 0 US 30/360, 1 actual/actual, 2 actual/360, 3 actual/365, 4 European 30/360.
//! Coupon dates step back from maturity (ACCRINT: from the first interest date) by 12 /
//! frequency months, on the month's last day when the anchor is one (Mayle's Standard
//! Securities Calculation Methods, the rules Excel follows).

use crate::eval::coerce::to_bool;
use crate::eval::dates::{days_in_month, serial_from_ymd, ymd_from_serial, DateSystem, DateTime, LAST_SERIAL};
use crate::eval::functions::api::{check, finite, scalar_numbers, Ctx, FnSpec, Scalars};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::math::basic::toolpak_number;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "COUPPCD",
        3,
        4,
        couppcd,
        "COUPPCD(settlement, maturity, frequency, [basis])",
        "Coupon date before settlement",
    ),
    FnSpec::value(
        "COUPNCD",
        3,
        4,
        coupncd,
        "COUPNCD(settlement, maturity, frequency, [basis])",
        "Coupon date after settlement",
    ),
    FnSpec::value(
        "COUPNUM",
        3,
        4,
        coupnum,
        "COUPNUM(settlement, maturity, frequency, [basis])",
        "Coupons payable from settlement to maturity",
    ),
    FnSpec::value(
        "COUPDAYS",
        3,
        4,
        coupdays,
        "COUPDAYS(settlement, maturity, frequency, [basis])",
        "Days in the coupon period holding settlement",
    ),
    FnSpec::value(
        "COUPDAYBS",
        3,
        4,
        coupdaybs,
        "COUPDAYBS(settlement, maturity, frequency, [basis])",
        "Days from the period's start to settlement",
    ),
    FnSpec::value(
        "COUPDAYSNC",
        3,
        4,
        coupdaysnc,
        "COUPDAYSNC(settlement, maturity, frequency, [basis])",
        "Days from settlement to the next coupon",
    ),
    FnSpec::value(
        "ACCRINT",
        6,
        8,
        accrint,
        "ACCRINT(issue, first_interest, settlement, rate, par, frequency, [basis], [calc_method])",
        "Accrued interest of a security paying periodic interest",
    ),
    FnSpec::value(
        "ACCRINTM",
        4,
        5,
        accrintm,
        "ACCRINTM(issue, settlement, rate, par, [basis])",
        "Accrued interest of a security paying interest at maturity",
    ),
    FnSpec::value(
        "DISC",
        4,
        5,
        disc,
        "DISC(settlement, maturity, pr, redemption, [basis])",
        "Discount rate of a security",
    ),
    FnSpec::value(
        "INTRATE",
        4,
        5,
        intrate,
        "INTRATE(settlement, maturity, investment, redemption, [basis])",
        "Interest rate of a fully invested security",
    ),
    FnSpec::value(
        "RECEIVED",
        4,
        5,
        received,
        "RECEIVED(settlement, maturity, investment, discount, [basis])",
        "Amount received at maturity of a fully invested security",
    ),
    FnSpec::value(
        "PRICEDISC",
        4,
        5,
        pricedisc,
        "PRICEDISC(settlement, maturity, discount, redemption, [basis])",
        "Price per 100 face value of a discounted security",
    ),
    FnSpec::value(
        "YIELDDISC",
        4,
        5,
        yielddisc,
        "YIELDDISC(settlement, maturity, pr, redemption, [basis])",
        "Annual yield of a discounted security",
    ),
    FnSpec::value(
        "PRICEMAT",
        5,
        6,
        pricemat,
        "PRICEMAT(settlement, maturity, issue, rate, yld, [basis])",
        "Price per 100 face value of a security paying interest at maturity",
    ),
    FnSpec::value(
        "YIELDMAT",
        5,
        6,
        yieldmat,
        "YIELDMAT(settlement, maturity, issue, rate, pr, [basis])",
        "Annual yield of a security paying interest at maturity",
    ),
    FnSpec::value(
        "PRICE",
        6,
        7,
        price,
        "PRICE(settlement, maturity, rate, yld, redemption, frequency, [basis])",
        "Price per 100 face value of a security paying periodic interest",
    ),
    FnSpec::value(
        "YIELD",
        6,
        7,
        yield_,
        "YIELD(settlement, maturity, rate, pr, redemption, frequency, [basis])",
        "Yield of a security paying periodic interest",
    ),
    FnSpec::value(
        "DURATION",
        5,
        6,
        duration,
        "DURATION(settlement, maturity, coupon, yld, frequency, [basis])",
        "Macaulay duration in years of a security paying periodic interest",
    ),
    FnSpec::value(
        "MDURATION",
        5,
        6,
        mduration,
        "MDURATION(settlement, maturity, coupon, yld, frequency, [basis])",
        "Modified duration in years of a security paying periodic interest",
    ),
    FnSpec::value(
        "AMORLINC",
        6,
        7,
        amorlinc,
        "AMORLINC(cost, date_purchased, first_period, salvage, period, rate, [basis])",
        "French straight-line depreciation of period (the first prorated)",
    ),
    FnSpec::value(
        "AMORDEGRC",
        6,
        7,
        amordegrc,
        "AMORDEGRC(cost, date_purchased, first_period, salvage, period, rate, [basis])",
        "French declining depreciation of period, by a coefficient of the asset's life",
    ),
    FnSpec::value(
        "ODDFPRICE",
        8,
        9,
        oddfprice,
        "ODDFPRICE(settlement, maturity, issue, first_coupon, rate, yld, redemption, frequency, [basis])",
        "Price per 100 face value of a security with an odd first period",
    ),
    FnSpec::value(
        "ODDFYIELD",
        8,
        9,
        oddfyield,
        "ODDFYIELD(settlement, maturity, issue, first_coupon, rate, pr, redemption, frequency, [basis])",
        "Yield of a security with an odd first period",
    ),
    FnSpec::value(
        "ODDLPRICE",
        7,
        8,
        oddlprice,
        "ODDLPRICE(settlement, maturity, last_interest, rate, yld, redemption, frequency, [basis])",
        "Price per 100 face value of a security with an odd last period",
    ),
    FnSpec::value(
        "ODDLYIELD",
        7,
        8,
        oddlyield,
        "ODDLYIELD(settlement, maturity, last_interest, rate, pr, redemption, frequency, [basis])",
        "Yield of a security with an odd last period",
    ),
];

// ---- calendar days ------------------------------------------------------------------------

/// A day of Excel's calendar: its serial and its parts (ordered by serial).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Day {
    serial: i64,
    year: i64,
    month: u32,
    day: u32,
    /// The workbook's date system, which the serial counts in.
    dates: DateSystem,
}

impl Day {
    fn from_serial(serial: i64, dates: DateSystem) -> Day {
        let (year, month, day) = ymd_from_serial(dates, serial);
        Day { serial, year, month, day, dates }
    }

    fn from_ymd(year: i64, month: u32, day: u32, dates: DateSystem) -> Day {
        Day { serial: serial_from_ymd(dates, year, i64::from(month), i64::from(day)), year, month, day, dates }
    }

    fn is_month_end(self) -> bool {
        self.day == days_in_month(self.year, self.month)
    }

    fn is_february_end(self) -> bool {
        self.month == 2 && self.is_month_end()
    }

    /// `months` later (earlier when negative): the day kept where the month has it, else the
    /// month's last day; always the last day when `month_end`.
    fn add_months(self, months: i64, month_end: bool) -> Day {
        let index = self.year * 12 + i64::from(self.month) - 1 + months;
        let (year, month) = (index.div_euclid(12), (index.rem_euclid(12) + 1) as u32);
        let last = days_in_month(year, month);
        Day::from_ymd(year, month, if month_end { last } else { self.day.min(last) }, self.dates)
    }

    fn days_to(self, later: Day) -> f64 {
        (later.serial - self.serial) as f64
    }
}

/// 30/360 days from `a` to `b` once the day numbers are adjusted to `d1` and `d2`.
fn days_360(a: Day, b: Day, d1: u32, d2: u32) -> f64 {
    ((b.year - a.year) * 360 + (i64::from(b.month) - i64::from(a.month)) * 30 + i64::from(d2) - i64::from(d1)) as f64
}

/// US (NASD) 30/360: a 31st or February's last day starts as the 30th; the end moves to the
/// 30th when it is a 31st after a start of 30 or 31, or February's end after February's end.
/// `both` moves the end to the 30th regardless of the start (the rule Excel uses for the
/// length of a whole coupon period).
fn us_360(a: Day, b: Day, both: bool) -> f64 {
    let (mut d1, mut d2) = (a.day, b.day);
    if b.is_february_end() && (a.is_february_end() || both) {
        d2 = 30;
    }
    if d2 == 31 && (d1 >= 30 || both) {
        d2 = 30;
    }
    if d1 == 31 || a.is_february_end() {
        d1 = 30;
    }
    days_360(a, b, d1, d2)
}

/// European 30/360: a 31st counts as the 30th at either end.
fn euro_360(a: Day, b: Day) -> f64 {
    days_360(a, b, a.day.min(30), b.day.min(30))
}

/// The day-count basis argument (YEARFRAC's).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Basis {
    Us30360,
    Actual,
    Actual360,
    Actual365,
    Euro30360,
}

impl Basis {
    /// Days from `a` to `b` as the basis counts them.
    fn days(self, a: Day, b: Day) -> f64 {
        match self {
            Basis::Us30360 => us_360(a, b, false),
            Basis::Euro30360 => euro_360(a, b),
            _ => a.days_to(b),
        }
    }

    /// The year's length for a span from `a` to `b`.
    fn year_days(self, a: Day, b: Day) -> f64 {
        match self {
            Basis::Actual => crate::eval::functions::date::actual_year_length(&date_time(a), &date_time(b), a.dates),
            Basis::Actual365 => 365.0,
            _ => 360.0,
        }
    }

    fn year_fraction(self, a: Day, b: Day) -> f64 {
        self.days(a, b) / self.year_days(a, b)
    }

    /// The length (E) of the coupon period from `pcd` to `ncd`.
    fn period_days(self, pcd: Day, ncd: Day, frequency: f64) -> f64 {
        match self {
            Basis::Actual => pcd.days_to(ncd),
            Basis::Actual365 => 365.0 / frequency,
            _ => 360.0 / frequency,
        }
    }
}

fn date_time(d: Day) -> DateTime {
    DateTime::from_serial(d.dates, d.serial as f64, 0)
}

// ---- arguments ----------------------------------------------------------------------------

/// A date argument: truncated to the day; #NUM! outside Excel's days, #VALUE! for a boolean
/// (these are Analysis ToolPak functions).
fn date_arg(a: Scalars, i: usize) -> XlResult<Day> {
    let n = toolpak_number(a.value(i), a.1)?.trunc();
    check((0.0..=LAST_SERIAL as f64).contains(&n), XlError::Num)?;
    Ok(Day::from_serial(n as i64, a.1))
}

fn number_arg(a: Scalars, i: usize) -> XlResult<f64> {
    toolpak_number(a.value(i), a.1)
}

/// The optional basis argument at `i`: 0–4 after truncation, else #NUM!.
fn basis_arg(a: Scalars, i: usize) -> XlResult<Basis> {
    let b = if a.given(i) { toolpak_number(a.value(i), a.1)?.trunc() } else { 0.0 };
    Ok(match b as i64 {
        _ if !(0.0..=4.0).contains(&b) => return Err(XlError::Num),
        0 => Basis::Us30360,
        1 => Basis::Actual,
        2 => Basis::Actual360,
        3 => Basis::Actual365,
        _ => Basis::Euro30360,
    })
}

/// Coupons per year: 1, 2 or 4 after truncation, else #NUM!.
fn frequency_arg(a: Scalars, i: usize) -> XlResult<f64> {
    let f = toolpak_number(a.value(i), a.1)?.trunc();
    check(f == 1.0 || f == 2.0 || f == 4.0, XlError::Num)?;
    Ok(f)
}

/// Settlement and maturity (arguments 0 and 1): settlement strictly first.
fn settlement_maturity(a: Scalars) -> XlResult<(Day, Day)> {
    let (settlement, maturity) = (date_arg(a, 0)?, date_arg(a, 1)?);
    check(settlement < maturity, XlError::Num)?;
    Ok((settlement, maturity))
}

// ---- coupon schedules ---------------------------------------------------------------------

/// The coupon period holding a settlement day of a bond maturing on a given day.
struct Coupons {
    /// The coupon date on or before settlement.
    pcd: Day,
    /// The coupon date after settlement.
    ncd: Day,
    /// Coupons from `ncd` to maturity, both counted.
    count: f64,
    frequency: f64,
}

impl Coupons {
    fn new(settlement: Day, maturity: Day, frequency: f64) -> XlResult<Coupons> {
        let step = 12 / frequency as i64;
        let month_end = maturity.is_month_end();
        let (mut ncd, mut pcd, mut periods) = (maturity, maturity, 0.0);
        while pcd > settlement {
            ncd = pcd;
            pcd = pcd.add_months(-step, month_end);
            periods += 1.0;
        }
        check(pcd.serial >= 0, XlError::Num)?;
        Ok(Coupons { pcd, ncd, count: periods, frequency })
    }

    /// From the function's first arguments: settlement, maturity, frequency at `f`, basis
    /// after it.
    fn of_args(a: Scalars, f: usize) -> XlResult<(Coupons, Day, Basis)> {
        let (settlement, maturity) = settlement_maturity(a)?;
        let (frequency, basis) = (frequency_arg(a, f)?, basis_arg(a, f + 1)?);
        Ok((Coupons::new(settlement, maturity, frequency)?, settlement, basis))
    }

    /// E: the days of the coupon period.
    fn days(&self, basis: Basis) -> f64 {
        basis.period_days(self.pcd, self.ncd, self.frequency)
    }

    /// A: the days from the period's start to settlement.
    fn days_before(&self, settlement: Day, basis: Basis) -> f64 {
        basis.days(self.pcd, settlement)
    }

    /// DSC: the days from settlement to the next coupon.
    fn days_after(&self, settlement: Day, basis: Basis) -> f64 {
        match basis {
            Basis::Us30360 => us_360(self.pcd, self.ncd, true) - us_360(self.pcd, settlement, false),
            Basis::Euro30360 => euro_360(settlement, self.ncd),
            _ => settlement.days_to(self.ncd),
        }
    }
}

fn coupon_fn(ctx: &mut Ctx, args: &[Expr], f: fn(&Coupons, Day, Basis) -> f64) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (coupons, settlement, basis) = Coupons::of_args(a, 2)?;
        finite(f(&coupons, settlement, basis))
    })
}

fn couppcd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, _, _| c.pcd.serial as f64)
}

fn coupncd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, _, _| c.ncd.serial as f64)
}

fn coupnum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, _, _| c.count)
}

fn coupdays(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, _, basis| c.days(basis))
}

fn coupdaybs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, settlement, basis| c.days_before(settlement, basis))
}

fn coupdaysnc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    coupon_fn(ctx, args, |c, settlement, basis| c.days_after(settlement, basis))
}

// ---- accrued interest ---------------------------------------------------------------------

/// ACCRINT: par × rate / frequency × the coupon periods accrued from issue to settlement,
/// each period's share counted by the basis. The periods are anchored on the first interest
/// date. With calc_method FALSE the whole periods before the first interest date are left
/// out (only the issue's stub and the settlement's period count).
fn accrint(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (issue, first, settlement) = (date_arg(a, 0)?, date_arg(a, 1)?, date_arg(a, 2)?);
        let (rate, par, frequency, basis) =
            (number_arg(a, 3)?, number_arg(a, 4)?, frequency_arg(a, 5)?, basis_arg(a, 6)?);
        let from_issue = if a.given(7) { to_bool(a.value(7))? } else { true };
        check(rate > 0.0 && par > 0.0 && issue < settlement, XlError::Num)?;
        finite(par * rate / frequency * accrued_periods(issue, first, settlement, frequency, basis, from_issue))
    })
}

/// The coupon periods (whole and partial) ACCRINT accrues.
fn accrued_periods(issue: Day, first: Day, settlement: Day, frequency: f64, basis: Basis, from_issue: bool) -> f64 {
    let step = 12 / frequency as i64;
    let month_end = first.is_month_end();
    let regular_start = first.add_months(-step, month_end);
    // The coupon date the settlement's period starts on: past the first interest date the
    // schedule runs on to the last date before settlement.
    let mut start = regular_start;
    if settlement > first && from_issue {
        start = first;
        let mut next = first.add_months(step, month_end);
        while next < settlement {
            start = next;
            next = next.add_months(step, month_end);
        }
    }
    let normal = match basis {
        Basis::Actual => regular_start.days_to(first),
        _ => basis.period_days(regular_start, first, frequency),
    };
    let mut periods = basis.days(issue.max(start), settlement) / normal;
    // Back from there to the issue: whole periods, then the issue's stub.
    let mut end = start;
    while end > issue {
        let begin = end.add_months(-step, month_end);
        if begin >= issue {
            periods += if from_issue { 1.0 } else { 0.0 };
        } else {
            periods += stub_days(issue, end, basis) / stub_length(begin, end, frequency, basis);
        }
        end = begin;
    }
    periods
}

/// The days of the issue's stub period, from the issue to the period's end.
fn stub_days(issue: Day, end: Day, basis: Basis) -> f64 {
    basis.days(issue, end)
}

/// The length of the period holding the issue.
fn stub_length(begin: Day, end: Day, frequency: f64, basis: Basis) -> f64 {
    match basis {
        Basis::Us30360 => us_360(begin, end, true),
        Basis::Actual360 => us_360(begin, end, false),
        Basis::Actual365 => 365.0 / frequency,
        Basis::Actual => begin.days_to(end),
        Basis::Euro30360 => euro_360(begin, end),
    }
}

/// ACCRINTM: par × rate × the year fraction from issue to settlement.
fn accrintm(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (issue, settlement) = (date_arg(a, 0)?, date_arg(a, 1)?);
        let (rate, par, basis) = (number_arg(a, 2)?, number_arg(a, 3)?, basis_arg(a, 4)?);
        check(rate > 0.0 && par > 0.0 && issue < settlement, XlError::Num)?;
        finite(par * rate * basis.year_fraction(issue, settlement))
    })
}

// ---- discounted and at-maturity securities ------------------------------------------------

/// The common frame of DISC, INTRATE, RECEIVED, PRICEDISC and YIELDDISC: settlement before
/// maturity, two positive amounts, the year fraction between the dates.
fn discounted(ctx: &mut Ctx, args: &[Expr], f: fn(x: f64, y: f64, years: f64) -> f64) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (settlement, maturity) = settlement_maturity(a)?;
        let (x, y, basis) = (number_arg(a, 2)?, number_arg(a, 3)?, basis_arg(a, 4)?);
        check(x > 0.0 && y > 0.0, XlError::Num)?;
        finite(f(x, y, basis.year_fraction(settlement, maturity)))
    })
}

fn disc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    discounted(ctx, args, |pr, redemption, years| (redemption - pr) / redemption / years)
}

fn intrate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    discounted(ctx, args, |investment, redemption, years| (redemption - investment) / investment / years)
}

fn received(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    discounted(ctx, args, |investment, discount, years| investment / (1.0 - discount * years))
}

fn pricedisc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    discounted(ctx, args, |discount, redemption, years| redemption * (1.0 - discount * years))
}

fn yielddisc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    discounted(ctx, args, |pr, redemption, years| (redemption / pr - 1.0) / years)
}

/// The year fractions of a security paying interest at maturity: issue to maturity, issue
/// to settlement, settlement to maturity, all over the year of settlement to maturity.
fn at_maturity_years(a: Scalars) -> XlResult<(f64, f64, f64)> {
    let (settlement, maturity) = settlement_maturity(a)?;
    let (issue, basis) = (date_arg(a, 2)?, basis_arg(a, 5)?);
    check(issue <= settlement, XlError::Num)?;
    let year = basis.year_days(settlement, maturity);
    Ok((
        basis.days(issue, maturity) / year,
        basis.days(issue, settlement) / year,
        basis.days(settlement, maturity) / year,
    ))
}

fn pricemat(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (issue_to_maturity, issue_to_settlement, settlement_to_maturity) = at_maturity_years(a)?;
        let (rate, yld) = (number_arg(a, 3)?, number_arg(a, 4)?);
        check(rate >= 0.0 && yld >= 0.0, XlError::Num)?;
        finite(
            (100.0 + issue_to_maturity * rate * 100.0) / (1.0 + settlement_to_maturity * yld)
                - issue_to_settlement * rate * 100.0,
        )
    })
}

fn yieldmat(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (issue_to_maturity, issue_to_settlement, settlement_to_maturity) = at_maturity_years(a)?;
        let (rate, pr) = (number_arg(a, 3)?, number_arg(a, 4)?);
        check(rate >= 0.0 && pr > 0.0, XlError::Num)?;
        let paid = pr / 100.0 + issue_to_settlement * rate;
        finite((1.0 + issue_to_maturity * rate - paid) / paid / settlement_to_maturity)
    })
}

// ---- coupon bonds -------------------------------------------------------------------------

/// A bond between settlement and maturity, as PRICE, YIELD and DURATION see it.
struct Bond {
    /// Coupons left (N).
    count: f64,
    /// The settlement period's days (E), the accrued days (A).
    period: f64,
    accrued: f64,
    frequency: f64,
}

impl Bond {
    fn of_args(a: Scalars, f: usize) -> XlResult<Bond> {
        let (coupons, settlement, basis) = Coupons::of_args(a, f)?;
        let (period, accrued) = (coupons.days(basis), coupons.days_before(settlement, basis));
        Ok(Bond { count: coupons.count, period, accrued, frequency: coupons.frequency })
    }

    /// The fraction of the settlement's period still to run (DSC / E).
    fn to_next(&self) -> f64 {
        (self.period - self.accrued) / self.period
    }

    /// The clean price per 100 face value at annual yield `yld`.
    fn price(&self, rate: f64, yld: f64, redemption: f64) -> f64 {
        let coupon = 100.0 * rate / self.frequency;
        let accrued = coupon * self.accrued / self.period;
        let to_next = self.to_next();
        if self.count <= 1.0 {
            return (redemption + coupon) / (1.0 + to_next * yld / self.frequency) - accrued;
        }
        let v = 1.0 + yld / self.frequency;
        let coupons: f64 = (0..self.count as i64).map(|k| coupon / v.powf(k as f64 + to_next)).sum();
        redemption / v.powf(self.count - 1.0 + to_next) + coupons - accrued
    }

    /// The yield at which the clean price is `pr`: in closed form with one coupon left, else
    /// by Newton's method from the coupon rate.
    fn yield_at(&self, rate: f64, pr: f64, redemption: f64) -> XlResult<f64> {
        if self.count <= 1.0 {
            let accrued = self.accrued / self.period * rate / self.frequency;
            let paid = pr / 100.0 + accrued;
            let gain = redemption / 100.0 + rate / self.frequency - paid;
            return Ok(gain / paid * self.frequency / self.to_next());
        }
        solve_yield(|y| self.price(rate, y, redemption), pr, rate, self.frequency)
    }

    /// The Macaulay duration in years at annual yield `yld`.
    fn duration(&self, coupon: f64, yld: f64) -> f64 {
        let to_next = self.to_next();
        let v = 1.0 + yld / self.frequency;
        let payment = coupon * 100.0 / self.frequency;
        let (mut weighted, mut present) = (0.0, 0.0);
        for k in 0..self.count as i64 {
            let t = k as f64 + to_next;
            weighted += t * payment / v.powf(t);
            present += payment / v.powf(t);
        }
        let last = self.count - 1.0 + to_next;
        weighted += last * 100.0 / v.powf(last);
        present += 100.0 / v.powf(last);
        weighted / present / self.frequency
    }
}

fn price(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = Bond::of_args(a, 5)?;
        let (rate, yld, redemption) = (number_arg(a, 2)?, number_arg(a, 3)?, number_arg(a, 4)?);
        check(rate >= 0.0 && yld >= 0.0 && redemption > 0.0, XlError::Num)?;
        finite(bond.price(rate, yld, redemption))
    })
}

fn yield_(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = Bond::of_args(a, 5)?;
        let (rate, pr, redemption) = (number_arg(a, 2)?, number_arg(a, 3)?, number_arg(a, 4)?);
        check(rate >= 0.0 && pr > 0.0 && redemption > 0.0, XlError::Num)?;
        finite(bond.yield_at(rate, pr, redemption)?)
    })
}

fn duration_args(a: Scalars) -> XlResult<(Bond, f64, f64)> {
    let bond = Bond::of_args(a, 4)?;
    let (coupon, yld) = (number_arg(a, 2)?, number_arg(a, 3)?);
    check(coupon >= 0.0 && yld >= 0.0, XlError::Num)?;
    Ok((bond, coupon, yld))
}

fn duration(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (bond, coupon, yld) = duration_args(a)?;
        finite(bond.duration(coupon, yld))
    })
}

fn mduration(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (bond, coupon, yld) = duration_args(a)?;
        finite(bond.duration(coupon, yld) / (1.0 + yld / bond.frequency))
    })
}

/// The yield at which `price` is `pr`: Newton's method from `guess` (at least 5 %), with a
/// numeric slope; #NUM! when it does not settle or leaves the yields (−frequency, ∞).
fn solve_yield(price: impl Fn(f64) -> f64, pr: f64, guess: f64, frequency: f64) -> XlResult<f64> {
    let f = |y: f64| price(y) - pr;
    let mut y = guess.max(0.05);
    for _ in 0..100 {
        let h = 1e-6 * y.abs().max(1e-3);
        let slope = (f(y + h) - f(y - h)) / (2.0 * h);
        check(slope.is_finite() && slope != 0.0, XlError::Num)?;
        let step = f(y) / slope;
        y -= step;
        check(y.is_finite() && y > -frequency, XlError::Num)?;
        if step.abs() < 1e-13 * y.abs().max(1e-3) {
            return Ok(y);
        }
    }
    Err(XlError::Num)
}

// ---- odd first and last periods -----------------------------------------------------------

/// Days from `a` to `b` by the basis, never negative.
fn days_at_least_0(basis: Basis, a: Day, b: Day) -> f64 {
    basis.days(a, b).max(0.0)
}

/// A bond with an odd first period: the arguments of ODDFPRICE and ODDFYIELD but the
/// sixth (the yield or the price).
struct OddFirst {
    settlement: Day,
    maturity: Day,
    issue: Day,
    first: Day,
    rate: f64,
    redemption: f64,
    frequency: f64,
    basis: Basis,
}

impl OddFirst {
    /// Excel's order of the dates: issue < settlement < first coupon < maturity.
    fn of_args(a: Scalars) -> XlResult<OddFirst> {
        let (settlement, maturity) = settlement_maturity(a)?;
        let (issue, first) = (date_arg(a, 2)?, date_arg(a, 3)?);
        let (rate, redemption) = (number_arg(a, 4)?, number_arg(a, 6)?);
        let (frequency, basis) = (frequency_arg(a, 7)?, basis_arg(a, 8)?);
        check(issue < settlement && settlement < first && first < maturity, XlError::Num)?;
        check(rate >= 0.0 && redemption > 0.0, XlError::Num)?;
        Ok(OddFirst { settlement, maturity, issue, first, rate, redemption, frequency, basis })
    }

    /// The clean price at annual yield `yld` (Mayle's formulas for a short or a long odd
    /// first period).
    fn price(&self, yld: f64) -> XlResult<f64> {
        let (basis, m) = (self.basis, self.frequency);
        let around = Coupons::new(self.settlement, self.first, m)?;
        let e = around.days(basis);
        let coupon = 100.0 * self.rate / m;
        let x = 1.0 + yld / m;
        let issue_to_first = days_at_least_0(basis, self.issue, self.first);
        if issue_to_first < e {
            let n = Coupons::new(self.settlement, self.maturity, m)?.count;
            let y = days_at_least_0(basis, self.settlement, self.first) / e;
            let accrued = days_at_least_0(basis, self.issue, self.settlement) / e;
            let later: f64 = (2..=n as i64).map(|k| coupon / x.powf(k as f64 - 1.0 + y)).sum();
            return Ok(self.redemption / x.powf(n - 1.0 + y) + coupon * issue_to_first / e / x.powf(y) + later
                - accrued * coupon);
        }
        let (first_coupon, accrued) = self.long_first_period(e)?;
        let to_next = match basis {
            Basis::Actual360 | Basis::Actual365 => days_at_least_0(basis, self.settlement, around.ncd),
            _ => e - basis.days(around.pcd, self.settlement),
        };
        let y = to_next / e;
        let nq = self.whole_periods_to_first();
        let n = Coupons::new(self.first, self.maturity, m)?.count;
        let later: f64 = (1..=n as i64).map(|k| coupon / x.powf(k as f64 + nq + y)).sum();
        Ok(self.redemption / x.powf(y + nq + n) + coupon * first_coupon / x.powf(nq + y) + later - coupon * accrued)
    }

    /// A long odd first period split into quasi-coupon periods back from the first coupon:
    /// the first coupon and the interest accrued at settlement, in regular coupons.
    fn long_first_period(&self, e: f64) -> XlResult<(f64, f64)> {
        let basis = self.basis;
        let step = 12 / self.frequency as i64;
        let periods = Coupons::new(self.issue, self.first, self.frequency)?.count as i64;
        let (mut late, mut coupon, mut accrued) = (self.first, 0.0, 0.0);
        for index in (1..=periods).rev() {
            let early = late.add_months(-step, false);
            let length = if basis == Basis::Actual { days_at_least_0(basis, early, late) } else { e };
            let counted = if index > 1 { length } else { days_at_least_0(basis, self.issue, late) };
            let held = days_at_least_0(basis, self.issue.max(early), self.settlement.min(late));
            coupon += counted / length;
            accrued += held / length;
            late = early;
        }
        Ok((coupon, accrued))
    }

    /// The whole quasi-coupon periods from settlement to the first coupon.
    fn whole_periods_to_first(&self) -> f64 {
        let step = 12 / self.frequency as i64;
        let first = self.first;
        let mut month_end = first.is_month_end();
        if !month_end && first.month != 2 && first.day > 28 {
            month_end = self.settlement.is_month_end();
        }
        let start = self.settlement.add_months(0, month_end);
        let mut periods = if self.settlement < start { 1.0 } else { 0.0 };
        let mut date = start.add_months(step, month_end);
        while date < first {
            periods += 1.0;
            date = date.add_months(step, month_end);
        }
        periods
    }
}

fn oddfprice(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = OddFirst::of_args(a)?;
        let yld = number_arg(a, 5)?;
        check(yld >= 0.0, XlError::Num)?;
        finite(bond.price(yld)?)
    })
}

fn oddfyield(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = OddFirst::of_args(a)?;
        let pr = number_arg(a, 5)?;
        check(pr > 0.0, XlError::Num)?;
        bond.price(bond.rate)?;
        let yld = solve_yield(|y| bond.price(y).unwrap_or(f64::NAN), pr, bond.rate, bond.frequency)?;
        finite(yld)
    })
}

/// A bond with an odd last period, summed over the quasi-coupon periods from the last
/// interest date to maturity: the last coupon, the interest accrued at settlement and the
/// time from settlement to maturity, each in regular coupon periods.
struct OddLast {
    coupon: f64,
    accrued: f64,
    remaining: f64,
    rate: f64,
    redemption: f64,
    frequency: f64,
}

impl OddLast {
    /// Excel's order of the dates: last interest < settlement < maturity.
    fn of_args(a: Scalars) -> XlResult<OddLast> {
        let (settlement, maturity) = settlement_maturity(a)?;
        let last = date_arg(a, 2)?;
        let (rate, redemption) = (number_arg(a, 3)?, number_arg(a, 5)?);
        let (frequency, basis) = (frequency_arg(a, 6)?, basis_arg(a, 7)?);
        check(last < settlement, XlError::Num)?;
        check(rate >= 0.0 && redemption > 0.0, XlError::Num)?;
        // The regular periods' lengths: basis 0 counts a whole period with both ends moved.
        let length = |a: Day, b: Day| match basis {
            Basis::Us30360 => us_360(a, b, true).max(0.0),
            _ => days_at_least_0(basis, a, b),
        };
        let step = 12 / frequency as i64;
        let periods = Coupons::new(last, maturity, frequency)?.count as i64;
        let (mut early, mut coupon, mut accrued, mut remaining) = (last, 0.0, 0.0, 0.0);
        for index in 1..=periods {
            let late = early.add_months(step, false);
            let normal = length(early, late);
            let counted = if index < periods { normal } else { length(early, maturity) };
            let held = if late < settlement {
                counted
            } else if early < settlement {
                days_at_least_0(basis, early, settlement)
            } else {
                0.0
            };
            let left = days_at_least_0(basis, settlement.max(early), maturity.min(late));
            coupon += counted / normal;
            accrued += held / normal;
            remaining += left / normal;
            early = late;
        }
        Ok(OddLast { coupon, accrued, remaining, rate, redemption, frequency })
    }

    /// The coupon per regular period and what is repaid at maturity with it.
    fn at_maturity(&self) -> (f64, f64) {
        let x = 100.0 * self.rate / self.frequency;
        (x, self.coupon * x + self.redemption)
    }
}

fn oddlprice(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = OddLast::of_args(a)?;
        let yld = number_arg(a, 4)?;
        check(yld >= 0.0, XlError::Num)?;
        let (x, repaid) = bond.at_maturity();
        finite(repaid / (bond.remaining * yld / bond.frequency + 1.0) - bond.accrued * x)
    })
}

fn oddlyield(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let bond = OddLast::of_args(a)?;
        let pr = number_arg(a, 4)?;
        check(pr > 0.0, XlError::Num)?;
        let (x, repaid) = bond.at_maturity();
        let paid = bond.accrued * x + pr;
        finite((repaid - paid) / paid * bond.frequency / bond.remaining)
    })
}

// ---- French depreciation ------------------------------------------------------------------

/// The arguments of AMORLINC and AMORDEGRC: cost, the first period's share of a year, salvage,
/// the period (whole) and the rate. Purchase after the first period's end, a rate not above
/// 0 or a salvage above the cost are #NUM!.
fn amortization_args(a: Scalars) -> XlResult<(f64, f64, f64, f64, f64)> {
    let (cost, purchased, first_end) = (number_arg(a, 0)?, date_arg(a, 1)?, date_arg(a, 2)?);
    let (salvage, period, rate, basis) = (number_arg(a, 3)?, number_arg(a, 4)?, number_arg(a, 5)?, basis_arg(a, 6)?);
    check(purchased <= first_end && rate > 0.0 && salvage <= cost && period >= 0.0, XlError::Num)?;
    check(cost >= 0.0 && salvage >= 0.0, XlError::Num)?;
    Ok((cost, basis.year_fraction(purchased, first_end), salvage, period.trunc(), rate))
}

fn amorlinc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (cost, first_share, salvage, period, rate) = amortization_args(a)?;
        let full = cost * rate;
        let first = first_share * full;
        let full_periods = ((cost - salvage - first) / full).trunc().max(0.0);
        finite(if period == 0.0 {
            first
        } else if period <= full_periods {
            full
        } else if period == full_periods + 1.0 {
            cost - salvage - full * full_periods - first
        } else {
            0.0
        })
    })
}

/// AMORDEGRC: the rate times a coefficient of the life 1 / rate (1.5 from 3 years, 2 from 5,
/// 2.5 over 6), each period's depreciation rounded to a whole amount; the period before
/// the salvage is reached takes half the value left, later ones nothing. Lives strictly
/// between 0 and 3 years other than 1 and 2, or between 4 and 5, are #NUM! as in Excel.
fn amordegrc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (mut cost, first_share, salvage, period, rate) = amortization_args(a)?;
        let life = 1.0 / rate;
        let odd_life = |lo: f64, hi: f64| life > lo && life < hi;
        check(!(odd_life(0.0, 1.0) || odd_life(1.0, 2.0) || odd_life(2.0, 3.0) || odd_life(4.0, 5.0)), XlError::Num)?;
        let coefficient = match life {
            l if l < 3.0 => 1.0,
            l if l < 5.0 => 1.5,
            l if l <= 6.0 => 2.0,
            _ => 2.5,
        };
        let rate = rate * coefficient;
        let mut depreciation = (first_share * rate * cost).round();
        cost -= depreciation;
        let mut left = cost - salvage;
        let mut n = 0.0;
        while n < period {
            depreciation = (rate * cost).round();
            if depreciation == 0.0 {
                // Nothing more is ever taken: this and every later period is 0.
                return Ok(Value::Number(0.0));
            }
            left -= depreciation;
            if left < 0.0 {
                return Ok(Value::Number(if period - n <= 1.0 { (cost * 0.5).round() } else { 0.0 }));
            }
            cost -= depreciation;
            n += 1.0;
        }
        finite(depreciation)
    })
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::value::{Value, XlError};

    /// `(formula, value)`: the values LibreOffice Calc 7 computes for these formulas (Excel's
    /// corpus has none of these functions; its cached values for the others are checked in
    /// `tests/excel_corpus_financial.rs`), to a relative 1e-9, LibreOffice's written digits.
    /// Not over a year at basis 1: there LibreOffice takes the settlement year's length
    /// where Excel (YEARFRAC, DISC in the corpus, DURATION's documented example) averages
    /// the years spanned.
    fn check(cases: &[(&str, f64)]) {
        check_to(cases, 1e-9);
    }

    fn check_to(cases: &[(&str, f64)], tolerance: f64) {
        let env = MapEnv::with(&[]);
        for (formula, want) in cases {
            match env.eval(formula) {
                Value::Number(got) => {
                    assert!((got - want).abs() <= tolerance * want.abs().max(1.0), "{formula}: {got}, oracle {want}")
                }
                other => panic!("{formula}: {other:?}, oracle {want}"),
            }
        }
    }

    /// The examples of Microsoft's documentation of DURATION and MDURATION (basis 1 over
    /// thirty and eight years), to the digits it prints.
    #[test]
    fn durations_as_excel_documents() {
        check_to(
            &[
                ("=DURATION(DATE(2018,7,1),DATE(2048,1,1),0.08,0.09,2,1)", 10.9191453),
                ("=MDURATION(DATE(2008,1,1),DATE(2016,1,1),0.08,0.09,2,1)", 5.73567),
            ],
            1e-6,
        );
    }

    #[test]
    fn discounted_and_at_maturity_securities_as_libreoffice() {
        check(&[
            ("=PRICEDISC(DATE(2008,2,16),DATE(2008,3,1),0.0525,100,2)", 99.7958333333333),
            ("=YIELDDISC(DATE(2008,2,16),DATE(2008,3,1),99.795,100,2)", 0.0528225719868601),
            ("=YIELDDISC(DATE(2008,2,16),DATE(2010,3,1),90,100,0)", 0.054421768707483),
            ("=PRICEMAT(DATE(2008,2,15),DATE(2008,4,13),DATE(2007,11,11),0.061,0.061,0)", 99.984498875557),
            ("=PRICEMAT(DATE(2008,2,15),DATE(2008,4,13),DATE(2008,2,15),0.061,0.061,0)", 100.0),
            ("=YIELDMAT(DATE(2008,3,15),DATE(2008,11,3),DATE(2007,11,8),0.0625,100.0123,0)", 0.0609543336915386),
            ("=RECEIVED(DATE(2008,2,15),DATE(2008,5,15),1000000,0.0575,2)", 1014584.6544071),
        ]);
    }

    #[test]
    fn durations_as_libreoffice() {
        check(&[
            ("=DURATION(DATE(2018,7,1),DATE(2025,3,15),0.05,0.04,4,0)", 5.7597629567678),
            ("=DURATION(DATE(2018,7,1),DATE(2019,3,15),0.05,0.04,1,3)", 0.704109589041096),
            ("=MDURATION(DATE(2008,1,1),DATE(2016,5,31),0.06,0.05,4,4)", 6.62048690229541),
        ]);
    }

    #[test]
    fn french_depreciation_as_libreoffice() {
        let bought = "2400,DATE(2008,8,19),DATE(2008,12,31),300";
        check(&[
            (&format!("=AMORLINC({bought},0,0.15,1)"), 131.803278688525),
            (&format!("=AMORLINC({bought},1,0.15,1)"), 360.0),
            (&format!("=AMORLINC({bought},3,0.15,3)"), 360.0),
            (&format!("=AMORLINC({bought},7,0.15,1)"), 0.0),
            (&format!("=AMORLINC({bought},8,0.15,0)"), 0.0),
            (&format!("=AMORDEGRC({bought},0,0.15,1)"), 330.0),
            (&format!("=AMORDEGRC({bought},1,0.15,1)"), 776.0),
            (&format!("=AMORDEGRC({bought},4,0.15,1)"), 190.0),
            (&format!("=AMORDEGRC({bought},5,0.15,1)"), 158.0),
            (&format!("=AMORDEGRC({bought},2,0.3,0)"), 496.0),
            (&format!("=AMORDEGRC({bought},2,0.5,4)"), 491.0),
        ]);
    }

    #[test]
    fn bad_arguments_are_num_errors() {
        let env = MapEnv::with(&[]);
        for formula in [
            "=DURATION(DATE(2018,7,1),DATE(2048,1,1),-0.08,0.09,2,1)",
            "=PRICEDISC(DATE(2009,2,16),DATE(2008,3,1),0.0525,100,2)",
            "=COUPNUM(DATE(2008,2,16),DATE(2009,3,1),3)",
            "=YIELDMAT(DATE(2008,3,15),DATE(2008,11,3),DATE(2008,11,8),0.0625,100,0)",
            "=AMORLINC(2400,DATE(2009,8,19),DATE(2008,12,31),300,1,0.15,1)",
        ] {
            assert_eq!(env.eval(formula), Value::Error(XlError::Num), "{formula}");
        }
    }
}
