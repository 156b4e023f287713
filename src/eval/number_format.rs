//! Numbers as Excel turns them into text: 15 significant digits, no trailing zeros.

/// Excel's "General" text of a number, as `=A1&""` produces it: 15 significant digits,
/// positional notation for moderate magnitudes, `1.5E+20` style otherwise.
pub fn general(n: f64) -> String {
    if n == 0.0 || !n.is_finite() {
        return "0".to_string();
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

/// The decimal digits of |n| rounded to `precision` significant digits, trailing zeros
/// removed, and the decimal exponent of the first digit.
pub fn significant_digits(n: f64, precision: usize) -> (String, i32) {
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
pub fn round15(n: f64) -> f64 {
    if n == 0.0 || !n.is_finite() {
        return n;
    }
    format!("{n:.14e}").parse().unwrap_or(n)
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
    }
}
