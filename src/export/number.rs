//! Coordinates as text, shared by every text format (OBJ, OFF): the
//! shortest text that reads back to the same `f64`, or a number of
//! significant digits.

/// Appends `x` as the shortest text that reads back to the same `f64`,
/// or with `digits` significant digits: `x` rounded to the nearest decimal
/// of that many digits, whose shortest text has at most that many.
#[inline]
pub(crate) fn push_f64(line: &mut Vec<u8>, buf: &mut ryu::Buffer, x: f64, digits: Option<u32>) {
    let x = match digits {
        Some(n) if x != 0.0 && x.is_finite() => {
            if push_digits(line, x, n) {
                return;
            }
            round_significant(x, n)
        }
        _ => x,
    };
    // Whole numbers as integers (a conversion, not a call to trunc).
    let whole = x as i64;
    if whole as f64 == x && x.abs() < 1e15 {
        let mut ib = itoa::Buffer::new();
        line.extend_from_slice(ib.format(whole).as_bytes());
    } else {
        line.extend_from_slice(buf.format(x).as_bytes());
    }
}

/// The decimal exponent of `a > 0`: `floor(log10(a))`, from the binary one
/// corrected by a comparison each way (no call into libm).
fn decimal_exponent(a: f64) -> i32 {
    let mut e = ((a.to_bits() >> 52) as i32 - 1023) * 30103 / 100_000;
    let ten = |k: i32| if (0..23).contains(&k) { POW10[k as usize] } else { 10f64.powi(k) };
    if a < ten(e) {
        e -= 1;
    }
    if a >= ten(e + 1) {
        e += 1;
    }
    e
}

/// Appends `x` with `n` significant digits in positional notation
/// (trailing zeros dropped), formatting the rounded integer of digits
/// directly; `false` (nothing written) when `x` needs an exponent
/// (below 1e-5 or at least 1e15 in magnitude, or more digits than a
/// power-of-ten table holds).
#[inline]
fn push_digits(line: &mut Vec<u8>, x: f64, n: u32) -> bool {
    let a = x.abs();
    if !(1e-5..1e15).contains(&a) {
        return false;
    }
    let mut shift = n as i32 - 1 - decimal_exponent(a);
    if (-14..0).contains(&shift) {
        // A whole number of more than `n` digits: its first `n`, then zeros.
        let m = (a / POW10[-shift as usize] + 0.5) as u64;
        if x < 0.0 {
            line.push(b'-');
        }
        line.extend_from_slice(itoa::Buffer::new().format(m).as_bytes());
        line.extend(std::iter::repeat_n(b'0', -shift as usize));
        return true;
    }
    if !(0..=22).contains(&shift) {
        return false;
    }
    let mut m = (a * POW10[shift as usize] + 0.5) as u64;
    while shift > 0 && m.is_multiple_of(10) {
        m /= 10;
        shift -= 1;
    }
    if x < 0.0 && m > 0 {
        line.push(b'-');
    }
    let mut ib = itoa::Buffer::new();
    let text = ib.format(m).as_bytes();
    let shift = shift as usize;
    if shift == 0 {
        line.extend_from_slice(text);
    } else if text.len() > shift {
        let point = text.len() - shift;
        line.extend_from_slice(&text[..point]);
        line.push(b'.');
        line.extend_from_slice(&text[point..]);
    } else {
        line.extend_from_slice(b"0.");
        line.extend(std::iter::repeat_n(b'0', shift - text.len()));
        line.extend_from_slice(text);
    }
    true
}

/// Exact powers of ten.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// `x` rounded to `n` significant digits: the nearest `f64` to that decimal
/// (an integer of at most 17 digits divided or multiplied by an exact
/// power of ten, one correctly rounded operation), without calls into libm.
fn round_significant(x: f64, n: u32) -> f64 {
    let e = decimal_exponent(x.abs());
    let shift = n as i32 - 1 - e;
    // Half away from zero, through an integer (below 10^17 < 2^63).
    let round = |y: f64| (y + 0.5f64.copysign(y)) as i64 as f64;
    if (0..=22).contains(&shift) {
        round(x * POW10[shift as usize]) / POW10[shift as usize]
    } else if (-22..0).contains(&shift) {
        round(x / POW10[-shift as usize]) * POW10[-shift as usize]
    } else {
        // Beyond exact powers of ten: the text of `n` digits read back.
        format!("{:.*e}", (n - 1) as usize, x).parse().unwrap_or(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(x: f64, digits: Option<u32>) -> String {
        let mut line = Vec::new();
        push_f64(&mut line, &mut ryu::Buffer::new(), x, digits);
        String::from_utf8(line).unwrap()
    }

    #[test]
    fn significant_digits() {
        for (x, n, expected) in [
            (3.434_921_7, 6, "3.43492"),
            (-0.424_263_9, 6, "-0.424264"),
            (0.000_123_456_78, 4, "0.0001235"),
            (123_456_789.0, 6, "123457000"),
            (9.999_999_6, 6, "10"),
            (2.5, 6, "2.5"),
            (-1.0, 3, "-1"),
            (0.0, 3, "0"),
            (1e-9, 3, "1e-9"),
            (6.02214076e23, 4, "6.022e23"),
        ] {
            assert_eq!(text(x, Some(n)), expected, "{x} to {n} digits");
        }
        // Shortest round trip by default.
        assert_eq!(text(0.1 + 0.2, None), "0.30000000000000004");
    }

    /// Random values over 40 decades: `n` digits at most, and within half a
    /// unit of the `n`-th digit of the value (relative 5·10^−n, plus rounding).
    #[test]
    fn significant_digits_read_back_close() {
        let mut state = 0x1234_5678_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..20_000 {
            let mantissa = (next() >> 11) as f64 / (1u64 << 53) as f64 + 0.1;
            let x = mantissa * 10f64.powi((next() % 40) as i32 - 20) * if next() % 2 == 0 { 1.0 } else { -1.0 };
            let n = (next() % 15 + 1) as u32;
            let t = text(x, Some(n));
            let back: f64 = t.parse().unwrap();
            let tol = 5.0 * 10f64.powi(-(n as i32)) * x.abs() * 1.000_001;
            assert!((back - x).abs() <= tol, "{x} to {n} digits: {t}");
            let digits = t.split('e').next().unwrap().trim_start_matches(['-', '0', '.']).replace('.', "");
            assert!(digits.trim_end_matches('0').len() <= n as usize, "{x} to {n} digits: {t}");
        }
    }
}
