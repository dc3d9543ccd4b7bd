//! CDR, the serialisation of ROS 2 messages (OMG CDR version 1, as
//! `rmw` writes it): a 4-byte encapsulation header whose second byte
//! names the byte order (`0x00` big-endian, `0x01` little-endian), then
//! the fields in order, each primitive aligned to its own size counted
//! from the end of the header (an `f64` to 8 bytes); a string is a `u32`
//! length counting its closing NUL, then the bytes; a sequence a `u32`
//! count, then the elements.

/// Reads one message's fields; every error names the field.
pub struct Cdr<'a> {
    body: &'a [u8],
    at: usize,
    little: bool,
}

/// Why a message could not be read: the field and the reason.
pub type CdrError = String;

impl<'a> Cdr<'a> {
    /// A reader of `data`, its encapsulation header checked.
    pub fn new(data: &'a [u8]) -> Result<Self, CdrError> {
        if data.len() < 4 {
            return Err(format!(
                "{} bytes, too short for CDR's 4-byte encapsulation header",
                data.len()
            ));
        }
        let little = match (data[0], data[1]) {
            (0, 0) => false,
            (0, 1) => true,
            (a, b) => {
                return Err(format!(
                    "encapsulation {a:#04x} {b:#04x} is not plain CDR (0x00 0x00 big-endian or 0x00 0x01 little-endian)"
                ))
            }
        };
        Ok(Self {
            body: &data[4..],
            at: 0,
            little,
        })
    }

    fn take(&mut self, field: &str, n: usize, align: usize) -> Result<&'a [u8], CdrError> {
        let start = self.at.div_ceil(align) * align;
        if start > self.body.len() || n > self.body.len() - start {
            return Err(format!(
                "{field}: {n} bytes at byte {} of the message, past its end ({} bytes)",
                start + 4,
                self.body.len() + 4
            ));
        }
        self.at = start + n;
        Ok(&self.body[start..start + n])
    }

    fn array<const N: usize>(&mut self, field: &str) -> Result<[u8; N], CdrError> {
        let mut a: [u8; N] = self.take(field, N, N)?.try_into().unwrap_or([0; N]);
        if !self.little {
            a.reverse();
        }
        Ok(a)
    }

    pub fn u32(&mut self, field: &str) -> Result<u32, CdrError> {
        Ok(u32::from_le_bytes(self.array(field)?))
    }

    pub fn i32(&mut self, field: &str) -> Result<i32, CdrError> {
        Ok(i32::from_le_bytes(self.array(field)?))
    }

    pub fn f32(&mut self, field: &str) -> Result<f32, CdrError> {
        Ok(f32::from_le_bytes(self.array(field)?))
    }

    pub fn f64(&mut self, field: &str) -> Result<f64, CdrError> {
        Ok(f64::from_le_bytes(self.array(field)?))
    }

    /// A string (its closing NUL dropped).
    pub fn string(&mut self, field: &str) -> Result<&'a str, CdrError> {
        let n = self.u32(field)? as usize;
        let bytes = self.take(field, n, 1)?;
        let text = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        std::str::from_utf8(text).map_err(|_| format!("{field}: not UTF-8 text"))
    }

    /// A sequence's count, checked against the bytes left (`size` bytes
    /// an element at least) and against `most`.
    pub fn count(&mut self, field: &str, size: usize, most: usize) -> Result<usize, CdrError> {
        let n = self.u32(field)? as usize;
        if n > most {
            return Err(format!(
                "{field}: {n} elements, more than the {most} it may have"
            ));
        }
        let left = self.body.len() - self.at;
        if n.saturating_mul(size) > left {
            return Err(format!(
                "{field}: {n} elements of {size} bytes, past the message's end ({left} bytes left)"
            ));
        }
        Ok(n)
    }

    /// `n` `f64`s (a covariance).
    pub fn skip_f64s(&mut self, field: &str, n: usize) -> Result<(), CdrError> {
        for _ in 0..n {
            self.f64(field)?;
        }
        Ok(())
    }
}
