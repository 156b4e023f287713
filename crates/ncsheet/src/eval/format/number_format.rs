//! Numbers as Excel turns them into text: 15 significant digits, no trailing zeros.

use std::cmp::Ordering;

/// Excel's "General" text of a number, as `=A1&""` produces it: 15 significant digits,
/// positional notation for moderate magnitudes, `1.5E+20` style otherwise.
pub fn general(n: f64) -> String {
    if n == 0.0 || !n.is_finite() {
        return "0".to_string();
    }
    // A whole number below 10^15 is its own 15 digits, written out (SEQUENCE's items, row
    // numbers): its integer's text, without the digit search below.
    if n.fract() == 0.0 && n.abs() < 1e15 {
        return (n as i64).to_string();
    }
    let (digits, exp) = significant_digits(n, 15);
    let negative = n < 0.0;
    let body = if (-10..15).contains(&exp) { positional(&digits, exp) } else { scientific(&digits, exp) };
    if negative {
        format!("-{body}")
    } else {
        body
    }
}

/// A number as VBA turns it into text (CStr, Str, `&`, Print, a String variable): C's
/// `%.{precision}G`, which is what OLE Automation's VarBstrFromR8 (precision 15, a Double)
/// and VarBstrFromR4 (7, a Single) write. Positional from 1E-04 up to 10^precision, `1.5E-07`
/// and `1E+15` outside, where Excel's General writes `0.00000015` (down to 1E-10).
pub fn vba_general(n: f64, precision: usize) -> String {
    if n == 0.0 || !n.is_finite() {
        return "0".to_string();
    }
    let (digits, exp) = significant_digits(n, precision);
    let body = if (-4..precision as i32).contains(&exp) { positional(&digits, exp) } else { scientific(&digits, exp) };
    if n < 0.0 {
        format!("-{body}")
    } else {
        body
    }
}

/// A number as a cell with the number format `code` shows it: General (15 significant
/// digits) without one, or when the code is one ncsheet cannot apply. A date format shows it
/// as a serial of `dates`, the workbook's date system.
pub fn shown(n: f64, code: Option<&str>, dates: crate::eval::dates::DateSystem) -> String {
    let parsed = code.and_then(|c| crate::eval::functions::NumberFormat::parse(c).ok());
    shown_by(parsed.as_ref(), n, dates)
}

/// The number formats a call that shows many cells (an export, a table) has read: each
/// distinct code parsed once, where parsing it for every cell took 44 % of an export of
/// 200,000 cells under one four-section code. Owned by that call, never by the process.
///
/// Only codes of at most [`MAX_CACHED_CODE_LEN`] characters are kept, and at most
/// [`MAX_CACHED_CODES`] of them: a workbook whose every cell has a code of its own (or a
/// hostile code of a million placeholders) is shown as without the cache, one parse a cell,
/// and the cache never grows past a few hundred kilobytes.
#[derive(Default)]
pub struct ShownFormats {
    parsed: std::collections::HashMap<Box<str>, Option<crate::eval::functions::NumberFormat>>,
}

/// The longest code kept parsed: Excel's own limit on a number format code's length.
pub const MAX_CACHED_CODE_LEN: usize = 255;

/// The most codes kept parsed (Excel keeps 200 to 250 custom number formats a workbook).
pub const MAX_CACHED_CODES: usize = 1024;

impl ShownFormats {
    /// [`shown`], the code parsed the first time it is seen.
    pub fn shown(&mut self, n: f64, code: Option<&str>, dates: crate::eval::dates::DateSystem) -> String {
        let Some(code) = code else { return general(n) };
        if let Some(parsed) = self.parsed.get(code) {
            return shown_by(parsed.as_ref(), n, dates);
        }
        let parsed = crate::eval::functions::NumberFormat::parse(code).ok();
        let text = shown_by(parsed.as_ref(), n, dates);
        if code.len() <= MAX_CACHED_CODE_LEN && self.parsed.len() < MAX_CACHED_CODES {
            self.parsed.insert(code.into(), parsed);
        }
        text
    }
}

/// A number under a parsed code, General when the code could not be read or applied.
fn shown_by(
    format: Option<&crate::eval::functions::NumberFormat>,
    n: f64,
    dates: crate::eval::dates::DateSystem,
) -> String {
    format.and_then(|f| f.format_number(n, dates).ok()).unwrap_or_else(|| general(n))
}

/// The decimal digits of |n| rounded to `precision` significant digits, trailing zeros
/// removed, and the decimal exponent of the first digit.
pub fn significant_digits(n: f64, precision: usize) -> (String, i32) {
    // The shortest digits that read back as `n` are its rounding to `precision` digits when
    // they are no more than that: `n` lies within half a unit of its last place (2^-53 of it)
    // of them, far inside half a step of a 15-digit grid (not so for a subnormal, whose last
    // place is coarser: those take the exact path). Found by the shortest-digits
    // algorithm (Grisu), where the exact rounding below runs big-number arithmetic (Dragon)
    // for most numbers: `SEQUENCE(1048576,16)&"x"` spent 70 % of its time here.
    if precision <= 15 && n.is_normal() {
        let shortest = format!("{:e}", n.abs());
        let (mantissa, exp) = shortest.split_once('e').expect("exponent form");
        if mantissa.len() <= precision + 1 {
            let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
            if digits.len() <= precision {
                return (digits, exp.parse().expect("integer exponent"));
            }
        }
    }
    let sci = format!("{:.*e}", precision - 1, n.abs());
    let (mantissa, exp) = sci.split_once('e').expect("exponent form");
    let exp: i32 = exp.parse().expect("integer exponent");
    let mut digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    while digits.len() > 1 && digits.ends_with('0') {
        digits.pop();
    }
    (digits, exp)
}

/// Rounds to 15 significant digits, the precision Excel keeps when it shows or compares.
///
/// The result is the double nearest to the 15-digit decimal nearest to `n` (a tie goes to
/// the even digit): exactly what printing `n` with `{:.14e}` and parsing it back gives, but
/// without the text for magnitudes from 10^-8 to 10^37 (ROUND calls this twice per cell).
/// Other magnitudes go through the text.
pub fn round15(n: f64) -> f64 {
    if n == 0.0 || !n.is_finite() {
        return n;
    }
    match round15_in_integers(n.abs()) {
        Some(r) => r.copysign(n),
        None => round15_by_text(n),
    }
}

/// The 15 significant digits by printing and parsing back: the definition, used outside the
/// range [`round15_in_integers`] covers.
///
/// The doubles above 1.797693134862315E+308 round up to 1.79769313486232E+308, past the
/// largest double: they are kept as they are, the nearest double to their 15 digits, where
/// the infinity the text parses to made ROUNDDOWN and TRUNC of them return them unrounded.
fn round15_by_text(n: f64) -> f64 {
    match format!("{n:.14e}").parse::<f64>() {
        Ok(r) if r.is_finite() => r,
        _ => n,
    }
}

/// Powers of ten that are exact doubles (10^22 is the last).
const POW10_F64: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// `10^k` for `k <= 22`, as integers.
const POW10_INT: [u128; 23] = {
    let mut t = [1u128; 23];
    let mut k = 1;
    while k < 23 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
};

const FIFTEEN_DIGITS: std::ops::Range<u128> = POW10_INT[14]..POW10_INT[15];

/// [`round15`] of a positive `a`, or `None` outside the range it handles.
///
/// With `a = m·2^q` exactly and `e` its decimal exponent, the 15 digits are the integer
/// nearest to `a / 10^(e-14)`, which is computed exactly in 128-bit integers. The digits
/// times `10^(e-14)` is then one multiplication or division of two exact doubles (the
/// digits are below 2^53 and the power of ten at most 10^22), which IEEE arithmetic rounds
/// correctly, as the parser does: the same double as the text round trip.
fn round15_in_integers(a: f64) -> Option<f64> {
    let bits = a.to_bits();
    let biased_exp = (bits >> 52) as i32;
    if biased_exp == 0 {
        return None; // subnormal
    }
    let m = (bits & ((1 << 52) - 1)) | (1 << 52);
    let q = biased_exp - 1075;
    // a lies in [2^(q+52), 2^(q+53)), so its decimal exponent is this or one more; the
    // exponents handled are -8 to 36 (powers of ten up to 10^22 either way).
    let mut e = ((f64::from(q + 52) * std::f64::consts::LOG10_2).floor() as i32).clamp(-8, 36);
    for _ in 0..3 {
        let (int, rest) = scaled_by_pow10(m, q, 14 - e)?;
        if int >= FIFTEEN_DIGITS.end {
            e += 1;
        } else if int < FIFTEEN_DIGITS.start {
            e -= 1;
        } else {
            let round_up = rest == Ordering::Greater || (rest == Ordering::Equal && int % 2 == 1);
            // At most 10^15 (999…9 rounded up), so exact as a double; converted from 64 bits,
            // one instruction where a 128-bit integer takes a library call.
            let digits = (int as u64 + u64::from(round_up)) as f64;
            return Some(if e <= 14 {
                digits / POW10_F64[(14 - e) as usize]
            } else {
                digits * POW10_F64[(e - 14) as usize]
            });
        }
    }
    None
}

/// `m·2^q·10^k` split into its integer part and how the fraction compares with one half;
/// `None` when `|k|` is over 22 or a term would not fit in 128 bits.
fn scaled_by_pow10(m: u64, q: i32, k: i32) -> Option<(u128, Ordering)> {
    let pow = *POW10_INT.get(k.unsigned_abs() as usize)?;
    let (mut num, mut den) = if k >= 0 { (u128::from(m) * pow, 1) } else { (u128::from(m), pow) };
    let shift = q.unsigned_abs();
    if q >= 0 {
        num = shifted_left(num, shift)?;
    } else if k >= 0 && shift < 128 {
        // The usual case (|a| below 2^52, at least 1e-8): a division by a power of two.
        let rest = num & ((1 << shift) - 1);
        return Some((num >> shift, rest.cmp(&(1 << (shift - 1)))));
    } else {
        den = shifted_left(den, shift)?;
    }
    let rest = num % den;
    Some((num / den, rest.cmp(&(den - rest))))
}

/// `x·2^shift`, or `None` when it would not fit.
fn shifted_left(x: u128, shift: u32) -> Option<u128> {
    (shift < x.leading_zeros()).then(|| x << shift)
}

fn positional(digits: &str, exp: i32) -> String {
    if exp < 0 {
        return format!("0.{}{digits}", "0".repeat((-exp - 1) as usize));
    }
    let int_len = exp as usize + 1;
    if digits.len() <= int_len {
        format!("{digits}{}", "0".repeat(int_len - digits.len()))
    } else {
        format!("{}.{}", &digits[..int_len], &digits[int_len..])
    }
}

fn scientific(digits: &str, exp: i32) -> String {
    let mantissa = if digits.len() > 1 { format!("{}.{}", &digits[..1], &digits[1..]) } else { digits.to_string() };
    let sign = if exp < 0 { '-' } else { '+' };
    format!("{mantissa}E{sign}{:02}", exp.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fifteen_significant_digits_as_excel_shows_them() {
        // Values as Excel displays them in a General cell / converts with &"".
        assert_eq!(general(0.1 + 0.2), "0.3");
        assert_eq!(general(1.0 / 3.0), "0.333333333333333");
        assert_eq!(general(2.0 / 3.0), "0.666666666666667");
        assert_eq!(general(123456789012345.0), "123456789012345");
        assert_eq!(general(1e20), "1E+20");
        assert_eq!(general(-44.262741699796952), "-44.262741699797");
        assert_eq!(general(1.5e-11), "1.5E-11");
        assert_eq!(general(100.0), "100");
        assert_eq!(general(-42.0), "-42");
        assert_eq!(general(999999999999999.0), "999999999999999");
        assert_eq!(general(1e15), "1E+15");
    }

    /// The shortest digits where they are few enough, the exact rounding otherwise: both give
    /// what printing with `precision` significant digits and dropping trailing zeros gives
    /// (C's `%.15e`, the definition), for numbers of every magnitude and digit count.
    #[test]
    fn significant_digits_are_the_rounding_to_the_precision() {
        let exact = |n: f64, precision: usize| {
            let sci = format!("{:.*e}", precision - 1, n.abs());
            let (mantissa, exp) = sci.split_once('e').unwrap();
            let digits = mantissa.replace('.', "");
            (digits.trim_end_matches('0').to_string(), exp.parse::<i32>().unwrap())
        };
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for i in 0..200_000u64 {
            // Integers, short decimals, thirds, and doubles of random bits.
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let n = match i % 4 {
                0 => (x % 10_000_000_000_000_000) as f64,
                1 => (x % 1_000_000) as f64 / 1000.0,
                2 => (x % 1000) as f64 / 3.0,
                _ => f64::from_bits(x >> 2),
            };
            for precision in [7, 15] {
                let (digits, exp) = exact(n, precision);
                let digits = if digits.is_empty() { "0".to_string() } else { digits };
                assert_eq!(significant_digits(n, precision), (digits, exp), "{n:e} to {precision} digits");
            }
        }
    }

    /// C's printf `%.15G` and `%.7G` (the values Python's `'%.15G' % x` prints), the
    /// format OLE Automation's VarBstrFromR8 and VarBstrFromR4 use.
    #[test]
    fn vba_text_of_numbers_is_printf_g() {
        assert_eq!(vba_general(1.5e-7, 15), "1.5E-07");
        assert_eq!(vba_general(-1.5e-7, 15), "-1.5E-07");
        assert_eq!(vba_general(1e-5, 15), "1E-05");
        assert_eq!(vba_general(0.0001, 15), "0.0001");
        assert_eq!(vba_general(1e14, 15), "100000000000000");
        assert_eq!(vba_general(1e15, 15), "1E+15");
        assert_eq!(vba_general(123456789012345678.0, 15), "1.23456789012346E+17");
        assert_eq!(vba_general(1.5e300, 15), "1.5E+300");
        assert_eq!(vba_general(12345678.0, 7), "1.234568E+07");
        assert_eq!(vba_general(1234567.0, 7), "1234567");
    }

    /// The cache of an export keeps at most `MAX_CACHED_CODES` codes, none longer than
    /// `MAX_CACHED_CODE_LEN`: 200,000 cells each with a code of its own, or one code of a
    /// million placeholders, cost one parse a cell (as without it) and no more memory.
    #[test]
    fn the_codes_kept_parsed_are_bounded_in_number_and_length() {
        let mut formats = ShownFormats::default();
        for i in 0..MAX_CACHED_CODES + 500 {
            assert_eq!(formats.shown(2.5, Some(&format!("0.0\" mm{i}\"")), DATES), format!("2.5 mm{i}"));
        }
        assert_eq!(formats.parsed.len(), MAX_CACHED_CODES);
        let mut formats = ShownFormats::default();
        let long = format!("0.{}", "0".repeat(MAX_CACHED_CODE_LEN));
        assert_eq!(formats.shown(0.5, Some(&long), DATES), format!("0.5{}", "0".repeat(MAX_CACHED_CODE_LEN - 1)));
        assert!(formats.parsed.is_empty());
        // A code that cannot be read is kept as such, and shows General.
        assert_eq!(formats.shown(1.5, Some("[Foo]0"), DATES), "1.5");
        assert_eq!(formats.shown(2.5, Some("[Foo]0"), DATES), "2.5");
        assert_eq!(formats.parsed.len(), 1);
    }

    const DATES: crate::eval::dates::DateSystem = crate::eval::dates::DateSystem::From1900;

    /// The definition `round15` must agree with bit for bit: the original text round trip,
    /// a double whose 15 digits pass the largest one kept as it is.
    fn round15_reference(n: f64) -> f64 {
        if n == 0.0 || !n.is_finite() {
            return n;
        }
        Some(format!("{n:.14e}").parse::<f64>().unwrap_or(n)).filter(|r| r.is_finite()).unwrap_or(n)
    }

    fn assert_same_as_reference(n: f64) {
        let (fast, text) = (round15(n), round15_reference(n));
        assert_eq!(fast.to_bits(), text.to_bits(), "round15({n:e}) = {fast:e}, the text round trip gives {text:e}");
    }

    #[test]
    fn fifteen_significant_digits_as_excel_keeps_them() {
        // Excel shows and compares these on 15 significant digits.
        assert_eq!(round15(0.1 + 0.2), 0.3);
        assert_eq!(round15(1.0 / 3.0 * 3.0), 1.0);
        assert_eq!(round15(1.0 - 0.9), 0.1);
        assert_eq!(round15(0.1 * 3.0), 0.3);
        assert_eq!(round15(2.0 / 3.0), 0.666666666666667);
        assert_eq!(round15(-2.0 / 3.0), -0.666666666666667);
        assert_eq!(round15(1.0 / 3.0), 0.333333333333333);
        assert_eq!(round15(-44.262741699796952), -44.262741699797);
        assert_eq!(round15(123456789012345678.0), 123456789012346000.0);
        assert_eq!(round15(1e15 + 0.3), 1e15);
        assert_eq!(round15(2.675), 2.675);
        assert_eq!(round15(1.5e-11), 1.5e-11);
        assert_eq!(round15(1e300 / 3.0), 3.33333333333333e299);
        // 999999999999999.9 has 16 digits: rounding carries into a 16th place.
        assert_eq!(round15(999999999999999.9), 1e15);
        // Halves of the 15th digit go to the even digit (exact binary values, so true ties).
        assert_eq!(round15(123456789012345.5), 123456789012346.0);
        assert_eq!(round15(123456789012344.5), 123456789012344.0);
        assert_eq!(round15(1000000000000005.0), 1000000000000000.0);
        assert_eq!(round15(1000000000000015.0), 1000000000000020.0);
        for n in [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(round15(n).to_bits(), n.to_bits());
        }
        assert!(round15(f64::NAN).is_nan());
    }

    #[test]
    fn round15_agrees_with_the_text_round_trip_at_the_edges() {
        let mut edges = vec![
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::from_bits(1),
            f64::from_bits((1 << 52) - 1),
            f64::EPSILON,
            2f64.powi(52),
            2f64.powi(53),
            2f64.powi(53) - 1.0,
            2f64.powi(127),
            2f64.powi(-75),
            0.5,
            1.0,
        ];
        // Around every power of ten and the ends of the integer range.
        for p in -325..=308 {
            let ten: f64 = format!("1e{p}").parse().unwrap();
            for step in -4i64..=4 {
                edges.push(f64::from_bits((ten.to_bits() as i64 + step).max(0) as u64));
            }
        }
        for n in edges {
            assert_same_as_reference(n);
            assert_same_as_reference(-n);
        }
    }

    #[test]
    fn round15_needs_no_text_for_moderate_magnitudes() {
        for n in [
            1.0000001e-8,
            1.1e-8,
            1e-7,
            0.1 + 0.2,
            2.675,
            1.0,
            123456.789,
            999999999999999.9,
            1e15,
            4.5e15,
            1e20,
            9.9e36,
            9.999999e36,
        ] {
            assert!(round15_in_integers(n).is_some(), "{n:e}");
        }
    }

    /// A double from a sign, a binary exponent and 52 mantissa bits (normal numbers only).
    fn normal(negative: bool, exp: i32, mantissa: u64) -> f64 {
        let bits = (u64::from(negative) << 63) | (((exp + 1023) as u64) << 52) | (mantissa & ((1 << 52) - 1));
        f64::from_bits(bits)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]

        #[test]
        fn round15_agrees_for_any_bits(bits: u64) {
            assert_same_as_reference(f64::from_bits(bits));
        }

        #[test]
        fn round15_agrees_across_the_integer_range(negative: bool, exp in -40i32..130, mantissa: u64) {
            assert_same_as_reference(normal(negative, exp, mantissa));
        }

        #[test]
        fn round15_agrees_on_subnormals(mantissa in 1u64..(1 << 52)) {
            assert_same_as_reference(f64::from_bits(mantissa));
        }

        #[test]
        fn round15_agrees_on_decimals(k in -10_000_000i64..10_000_000, d in 0i32..=25) {
            let k = k as f64;
            assert_same_as_reference(k / 1000.0);
            assert_same_as_reference(k / 10f64.powi(d));
            assert_same_as_reference(k * 10f64.powi(d));
        }

        #[test]
        fn round15_agrees_on_sums_and_products_of_decimals(
            a in -100_000i64..100_000, b in -100_000i64..100_000, da in 0i32..8, db in 0i32..8,
        ) {
            let (x, y) = (a as f64 / 10f64.powi(da), b as f64 / 10f64.powi(db));
            for n in [x + y, x - y, x * y, x / y, (x + y) * 3.0, x * 0.1 + y * 0.2] {
                assert_same_as_reference(n);
            }
        }

        #[test]
        fn round15_agrees_around_1e15(x in -1e6f64..1e6, ulps in -1000i64..1000) {
            assert_same_as_reference(1e15 + x);
            assert_same_as_reference(1e15 - x.abs());
            assert_same_as_reference(f64::from_bits((1e15f64.to_bits() as i64 + ulps) as u64));
            assert_same_as_reference(f64::from_bits((1e14f64.to_bits() as i64 + ulps) as u64));
        }

        /// Halfway between two 15-digit decimals, and the doubles next to it.
        #[test]
        fn round15_agrees_near_ties(digits in 100_000_000_000_000u64..1_000_000_000_000_000, exp in -30i32..45, ulps in -2i64..=2) {
            let tie: f64 = format!("{digits}5e{exp}").parse().unwrap();
            assert_same_as_reference(f64::from_bits((tie.to_bits() as i64 + ulps) as u64));
        }
    }
}
