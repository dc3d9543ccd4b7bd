//! A log's decimal numbers read as `f64`, the value and the grammar those
//! of the standard library's `str::parse::<f64>` bit for bit (an optional
//! sign; digits with an optional point and exponent, or `inf`, `infinity`,
//! `nan` in any case), the value correctly rounded, a tie to even.
//!
//! Written here rather than called because the standard reader carries a
//! 10 KB table of powers of five (Lemire's fast path) that no compressor
//! shrinks: most of the logs module's size margin (docs/BENCHMARKS.md,
//! `wasm-size`). A log's numbers take Clinger's exact path (1990: at most
//! 2^53 as digits, a power of ten up to 10^22, one correctly rounded
//! operation); any other number is divided out exactly in big integers.

/// 10^0 ..= 10^22, each exact in an `f64`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];
/// Significant digits kept; those after only say whether the value is past
/// what was kept. Every halfway point between two `f64`s has at most 767
/// significant digits, so that a value truncated past them rounds as the
/// whole would.
const KEPT_DIGITS: usize = 800;

/// `token` as `str::parse::<f64>` reads it, or `None` where it refuses.
pub(super) fn parse_f64(token: &[u8]) -> Option<f64> {
    let (negative, body) = match token.first() {
        Some(b'-') => (true, &token[1..]),
        Some(b'+') => (false, &token[1..]),
        _ => (false, token),
    };
    let value = match body.first()? {
        b'i' | b'I' | b'n' | b'N' => special(body)?,
        _ => decimal(body)?,
    };
    Some(if negative { -value } else { value })
}

/// `inf`, `infinity` or `nan`, in any case.
fn special(body: &[u8]) -> Option<f64> {
    let word = |w: &str| body.eq_ignore_ascii_case(w.as_bytes());
    if word("inf") || word("infinity") {
        Some(f64::INFINITY)
    } else if word("nan") {
        Some(f64::NAN)
    } else {
        None
    }
}

/// Digits, an optional point and digits (at least one digit in all), an
/// optional exponent: the value, rounded. A number of at most 19
/// significant digits is read in one pass without allocating (a log holds
/// millions); any other goes to [`long_decimal`].
fn decimal(body: &[u8]) -> Option<f64> {
    let (mut m, mut significant, mut fraction, mut seen) = (0u64, 0u32, 0i64, false);
    let mut i = 0;
    let mut after_point = false;
    while let Some(&b) = body.get(i) {
        match b {
            b'0'..=b'9' => {
                seen = true;
                fraction += i64::from(after_point);
                if significant > 0 || b != b'0' {
                    significant += 1;
                    m = m.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
                }
            }
            b'.' if !after_point => after_point = true,
            _ => break,
        }
        i += 1;
    }
    let mut exponent = 0i64;
    if seen && significant <= 19 && i < body.len() && (body[i] | 0x20) == b'e' {
        let (negative, digits) = match body.get(i + 1) {
            Some(b'-') => (true, &body[i + 2..]),
            Some(b'+') => (false, &body[i + 2..]),
            _ => (false, &body[i + 1..]),
        };
        if digits.is_empty() || digits.len() > 4 || !digits.iter().all(u8::is_ascii_digit) {
            return long_decimal(body);
        }
        exponent = digits.iter().fold(0, |e, &d| e * 10 + i64::from(d - b'0'));
        if negative {
            exponent = -exponent;
        }
        i = body.len();
    }
    let e10 = exponent - fraction;
    if !seen || i < body.len() || significant > 19 || m > 1 << 53 || !(-22..=22).contains(&e10) {
        return long_decimal(body);
    }
    let m = m as f64;
    Some(if e10 >= 0 {
        m * POW10[e10 as usize]
    } else {
        m / POW10[(-e10) as usize]
    })
}

/// [`decimal`] for any number: its significant digits kept (up to
/// [`KEPT_DIGITS`]), then read exactly.
fn long_decimal(body: &[u8]) -> Option<f64> {
    let mut digits: Vec<u8> = Vec::new();
    let (mut truncated, mut seen, mut point_shift) = (false, false, 0i64);
    let mut i = 0;
    let mut after_point = false;
    while i < body.len() {
        match body[i] {
            d @ b'0'..=b'9' => {
                seen = true;
                if after_point {
                    point_shift -= 1;
                }
                if digits.is_empty() && d == b'0' {
                    // A leading zero: no significant digit.
                } else if digits.len() < KEPT_DIGITS {
                    digits.push(d - b'0');
                } else {
                    truncated |= d != b'0';
                    point_shift += 1;
                }
            }
            b'.' if !after_point => after_point = true,
            _ => break,
        }
        i += 1;
    }
    if !seen {
        return None;
    }
    let mut exponent = 0i64;
    if i < body.len() {
        if body[i] != b'e' && body[i] != b'E' {
            return None;
        }
        i += 1;
        let negative = match body.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        if i == body.len() {
            return None;
        }
        for &b in &body[i..] {
            if !b.is_ascii_digit() {
                return None;
            }
            // Saturated: past this every value is 0 or infinite anyway.
            exponent = (exponent * 10 + i64::from(b - b'0')).min(1 << 40);
        }
        if negative {
            exponent = -exponent;
        }
    }
    // Trailing zeros of the digits kept move into the exponent.
    while digits.last() == Some(&0) {
        digits.pop();
        point_shift += 1;
    }
    if digits.is_empty() {
        return Some(0.0);
    }
    let e10 = exponent + point_shift;
    if !truncated && digits.len() <= 19 {
        let m = digits.iter().fold(0u64, |m, &d| m * 10 + u64::from(d));
        if m <= 1 << 53 && (-22..=22).contains(&e10) {
            let m = m as f64;
            return Some(if e10 >= 0 {
                m * POW10[e10 as usize]
            } else {
                m / POW10[(-e10) as usize]
            });
        }
    }
    // The leading digit's decade: 10^lead <= value < 10^(lead + 1).
    let lead = digits.len() as i64 - 1 + e10;
    if lead > 308 {
        return Some(f64::INFINITY);
    }
    if lead < -324 {
        return Some(0.0);
    }
    Some(exact(&digits, e10, truncated))
}

/// `digits · 10^e10` (plus a little more when `truncated`), rounded: the
/// quotient of two big integers taken to 64–66 bits, the remainder a
/// sticky bit.
fn exact(digits: &[u8], e10: i64, truncated: bool) -> f64 {
    let mut n = Big::from_digits(digits);
    let mut s = Big(vec![1]);
    if e10 >= 0 {
        n.mul_pow10(e10 as u32);
    } else {
        s.mul_pow10((-e10) as u32);
    }
    // value = n / s; scaled by 2^k so that the quotient has 65 or 66 bits.
    let k = 65 - (n.bits() as i64 - s.bits() as i64);
    if k >= 0 {
        n.shl(k as u32);
    } else {
        s.shl((-k) as u32);
    }
    let mut q = 0u128;
    for b in (0..67).rev() {
        let mut t = s.clone();
        t.shl(b);
        if n.cmp(&t) != std::cmp::Ordering::Less {
            n.sub(&t);
            q |= 1 << b;
        }
    }
    round(q, -k, truncated || !n.is_zero())
}

/// `q · 2^p`, plus a little more when `sticky`, rounded to an `f64` (to
/// nearest, a tie to even; subnormals and overflow as IEEE 754 has them).
fn round(q: u128, p: i64, sticky: bool) -> f64 {
    let bits = 128 - i64::from(q.leading_zeros());
    // The lowest bit kept: 53 bits, or down to 2^-1074.
    let low = (bits - 1 + p - 52).max(-1074);
    let drop = (low - p) as u32;
    let (mut mantissa, rest) = (q >> drop, q & ((1u128 << drop) - 1));
    let half = 1u128 << (drop - 1);
    if rest > half || (rest == half && (sticky || mantissa & 1 == 1)) {
        mantissa += 1;
    }
    let mut low = low;
    if mantissa == 1 << 53 {
        mantissa >>= 1;
        low += 1;
    }
    if mantissa < 1 << 52 {
        // Subnormal (low is -1074).
        return f64::from_bits(mantissa as u64);
    }
    let biased = low + 1075;
    if biased >= 2047 {
        return f64::INFINITY;
    }
    f64::from_bits(((biased as u64) << 52) | (mantissa as u64 & ((1 << 52) - 1)))
}

/// A natural number in base-2^32 limbs, least significant first.
#[derive(Clone)]
struct Big(Vec<u32>);

impl Big {
    fn from_digits(digits: &[u8]) -> Self {
        let mut b = Big(Vec::new());
        for chunk in digits.chunks(9) {
            let (mut scale, mut value) = (1u32, 0u32);
            for &d in chunk {
                scale *= 10;
                value = value * 10 + u32::from(d);
            }
            b.mul_add(scale, value);
        }
        b
    }

    fn mul_add(&mut self, m: u32, a: u32) {
        let mut carry = u64::from(a);
        for limb in self.0.iter_mut() {
            let v = u64::from(*limb) * u64::from(m) + carry;
            *limb = v as u32;
            carry = v >> 32;
        }
        if carry > 0 {
            self.0.push(carry as u32);
        }
    }

    fn mul_pow10(&mut self, mut e: u32) {
        while e > 0 {
            let step = e.min(9);
            self.mul_add(10u32.pow(step), 0);
            e -= step;
        }
    }

    fn shl(&mut self, bits: u32) {
        let (words, bits) = ((bits / 32) as usize, bits % 32);
        if bits > 0 {
            let mut carry = 0u32;
            for limb in self.0.iter_mut() {
                let v = (*limb << bits) | carry;
                carry = *limb >> (32 - bits);
                *limb = v;
            }
            if carry > 0 {
                self.0.push(carry);
            }
        }
        self.0.splice(0..0, std::iter::repeat_n(0, words));
    }

    fn trimmed(&self) -> &[u32] {
        let n = self.0.iter().rposition(|&l| l != 0).map_or(0, |i| i + 1);
        &self.0[..n]
    }

    fn bits(&self) -> u32 {
        let t = self.trimmed();
        t.last()
            .map_or(0, |&top| 32 * t.len() as u32 - top.leading_zeros())
    }

    fn is_zero(&self) -> bool {
        self.trimmed().is_empty()
    }

    fn cmp(&self, other: &Big) -> std::cmp::Ordering {
        let (a, b) = (self.trimmed(), other.trimmed());
        a.len()
            .cmp(&b.len())
            .then_with(|| a.iter().rev().cmp(b.iter().rev()))
    }

    /// `self -= other` (`other <= self`).
    fn sub(&mut self, other: &Big) {
        let mut borrow = 0i64;
        for (i, limb) in self.0.iter_mut().enumerate() {
            let v = i64::from(*limb) - i64::from(other.0.get(i).copied().unwrap_or(0)) - borrow;
            *limb = v.rem_euclid(1 << 32) as u32;
            borrow = i64::from(v < 0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::parse_f64;

    fn check(text: &str) {
        let ours = parse_f64(text.as_bytes());
        let std = text.parse::<f64>().ok();
        match (ours, std) {
            (Some(a), Some(b)) => assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{text:?}: {a:e} against {b:e}"
            ),
            _ => assert_eq!(
                ours.is_some(),
                std.is_some(),
                "{text:?}: {ours:?} against {std:?}"
            ),
        }
    }

    #[test]
    fn reads_what_the_standard_reader_reads() {
        for t in [
            "0",
            "-0",
            "+0",
            "0.0",
            "1",
            "-1.5",
            "12.345",
            ".5",
            "5.",
            "1.e5",
            ".e5",
            ".",
            "",
            "+",
            "-",
            "e5",
            "1e",
            "1e+",
            "1e-",
            "1e+5",
            "1E-5",
            "1e5x",
            " 1",
            "1 ",
            "1_0",
            "0x10",
            "inf",
            "-Infinity",
            "NaN",
            "nan",
            "infin",
            "infinityx",
            "in",
            "1..2",
            "1.2.3",
            "0.1",
            "0.2",
            "0.3",
            "9007199254740993",
            "9007199254740992.5",
            "1e22",
            "1e23",
            "123456789012345678901234567890",
            "2.2250738585072011e-308",
            "2.2250738585072014e-308",
            "4.9406564584124654e-324",
            "2.4703282292062327e-324",
            "2.4703282292062328e-324",
            "1.7976931348623157e308",
            "1.7976931348623158e308",
            "1.7976931348623159e308",
            "1e309",
            "1e-400",
            "1e99999999999999999999",
            "1e-99999999999999999999",
            "0e999999",
            "00000.000e5",
            "0.000000000000000000000000000001234",
            "179769313486231580793728971405301e276",
            "8.98846567431158e307",
            "5e-324",
            "3e-324",
            "7.2057594037927933e16",
            "-123.456e-7",
        ] {
            check(t);
        }
        // A halfway point with a digit far past the kept ones.
        let long = format!("9007199254740993{}1", "0".repeat(900));
        check(&long);
        check(&format!("9007199254740993{}", "0".repeat(900)));
        check(&format!("0.{}1e30", "0".repeat(850)));
    }

    #[test]
    fn agrees_over_many_numbers_and_non_numbers() {
        // A fixed-seed walk (xorshift): every f64's shortest and long
        // forms, and strings of number-like bytes.
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        const BYTES: &[u8] = b"0123456789.eE+-0011995";
        for _ in 0..6_000 {
            let x = f64::from_bits(next());
            check(&x.to_string());
            check(&format!("{x:e}"));
            check(&format!("{:.25e}", x));
            let y = (next() % 100_000_000) as f64 / 10f64.powi((next() % 12) as i32);
            check(&y.to_string());
            check(&format!("{y:.9}"));
            let len = (next() % 12) as usize;
            let t: String = (0..len)
                .map(|_| BYTES[(next() % BYTES.len() as u64) as usize] as char)
                .collect();
            check(&t);
        }
    }
}
