//! The binary encoding of a checkpoint's state: little-endian fixed-width numbers, lengths as
//! `u64` before sequences, no padding. [`Pack`] writes a value into an [`Enc`] and reads it
//! back from a [`Dec`], which refuses to read past its end (a truncated checkpoint is an
//! error, never a panic) and names what it was reading.

/// The bytes being written.
#[derive(Debug, Default)]
pub struct Enc {
    /// The encoded bytes so far.
    pub buf: Vec<u8>,
}

impl Enc {
    /// An empty encoder with room for `n` bytes.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            buf: Vec::with_capacity(n),
        }
    }

    /// Appends `v`.
    pub fn put<T: Pack>(&mut self, v: &T) {
        v.pack(self);
    }

    /// Appends a text (as a [`String`] is written).
    pub fn text(&mut self, s: &str) {
        s.len().pack(self);
        self.buf.extend_from_slice(s.as_bytes());
    }

    /// Appends raw bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        self.buf.extend_from_slice(b);
    }

    /// Opens a section named `name`: its name and a length written when the closure returns,
    /// so that a reader can check it is where it expects and that a section was read whole.
    pub fn section(&mut self, name: &str, body: impl FnOnce(&mut Enc)) {
        self.text(name);
        let at = self.buf.len();
        self.buf.extend_from_slice(&0u64.to_le_bytes());
        body(self);
        let len = (self.buf.len() - at - 8) as u64;
        self.buf[at..at + 8].copy_from_slice(&len.to_le_bytes());
    }
}

/// Why a checkpoint's state cannot be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError(pub String);

impl std::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Reads bytes written by an [`Enc`].
#[derive(Debug)]
pub struct Dec<'a> {
    buf: &'a [u8],
    pos: usize,
    /// The section being read (for messages).
    section: String,
    /// Where the section being read ends.
    section_end: usize,
}

impl<'a> Dec<'a> {
    /// A reader over `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        Self {
            buf,
            pos: 0,
            section: String::new(),
            section_end: buf.len(),
        }
    }

    /// Reads a `T`.
    pub fn get<T: Pack>(&mut self) -> Result<T, DecodeError> {
        T::unpack(self)
    }

    /// The next `n` raw bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        if self.buf.len() - self.pos < n {
            return Err(self.error(format!(
                "ends {} bytes early",
                n - (self.buf.len() - self.pos)
            )));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// Passes over the rest of the section being read (a reader that does not need it).
    pub fn skip_rest(&mut self) {
        self.pos = self.section_end.max(self.pos);
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.buf.len() - self.pos
    }

    /// An error at the current place.
    pub fn error(&self, what: impl std::fmt::Display) -> DecodeError {
        if self.section.is_empty() {
            DecodeError(format!("{what}"))
        } else {
            DecodeError(format!("section `{}`: {what}", self.section))
        }
    }

    /// Reads the section `name` written by [`Enc::section`] with `body`, which must read it
    /// whole.
    pub fn section<T>(
        &mut self,
        name: &str,
        body: impl FnOnce(&mut Dec<'a>) -> Result<T, DecodeError>,
    ) -> Result<T, DecodeError> {
        let found: String = self.get()?;
        if found != name {
            return Err(self.error(format!("expected section `{name}`, found `{found}`")));
        }
        let len = self.get::<u64>()? as usize;
        let outer = std::mem::replace(&mut self.section, name.to_string());
        let start = self.pos;
        if self.remaining() < len {
            return Err(self.error(format!("ends {} bytes early", len - self.remaining())));
        }
        let outer_end = std::mem::replace(&mut self.section_end, start + len);
        let v = body(self)?;
        self.section_end = outer_end;
        if self.pos - start != len {
            return Err(self.error(format!(
                "read {} of its {len} bytes (the checkpoint was written by another build?)",
                self.pos - start
            )));
        }
        self.section = outer;
        Ok(v)
    }

    /// Reads a `Vec<T>` that must have `n` elements (what the scene's model has).
    pub fn vec_of_len<T: Pack>(&mut self, n: usize, what: &str) -> Result<Vec<T>, DecodeError> {
        let v: Vec<T> = self.get()?;
        if v.len() != n {
            return Err(self.error(format!(
                "{what}: {} values where the scene has {n}",
                v.len()
            )));
        }
        Ok(v)
    }

    /// Reads a `Vec<T>` into `out`, which must have as many elements.
    pub fn fill<T: Pack>(&mut self, out: &mut [T], what: &str) -> Result<(), DecodeError> {
        let n = self.get::<u64>()? as usize;
        if n != out.len() {
            return Err(self.error(format!(
                "{what}: {n} values where the scene has {}",
                out.len()
            )));
        }
        for o in out.iter_mut() {
            *o = T::unpack(self)?;
        }
        Ok(())
    }
}

/// A value a checkpoint can hold.
pub trait Pack: Sized {
    /// Appends the value.
    fn pack(&self, e: &mut Enc);
    /// Reads a value.
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError>;
}

macro_rules! numbers {
    ($($t:ty),*) => {$(
        impl Pack for $t {
            fn pack(&self, e: &mut Enc) {
                e.buf.extend_from_slice(&self.to_le_bytes());
            }
            fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
                let b = d.take(std::mem::size_of::<$t>())?;
                Ok(<$t>::from_le_bytes(b.try_into().expect("length taken")))
            }
        }
    )*};
}
numbers!(f64, f32, u64, u32, u16, u8, i64, i32);

impl Pack for usize {
    fn pack(&self, e: &mut Enc) {
        (*self as u64).pack(e);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let v = u64::unpack(d)?;
        usize::try_from(v).map_err(|_| d.error(format!("count {v} too large")))
    }
}

impl Pack for bool {
    fn pack(&self, e: &mut Enc) {
        e.buf.push(u8::from(*self));
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        match u8::unpack(d)? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(d.error(format!("{b} is not a flag"))),
        }
    }
}

impl<T: Pack> Pack for Vec<T> {
    fn pack(&self, e: &mut Enc) {
        self.as_slice().pack_slice(e);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let n = usize::unpack(d)?;
        // a length beyond the bytes left is a damaged file, not a reason to allocate
        if n > d.remaining() {
            return Err(d.error(format!(
                "a sequence of {n} values in {} bytes",
                d.remaining()
            )));
        }
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(T::unpack(d)?);
        }
        Ok(v)
    }
}

/// Slices are written as `Vec`s.
pub trait PackSlice {
    /// Appends the length and the elements.
    fn pack_slice(&self, e: &mut Enc);
}

impl<T: Pack> PackSlice for [T] {
    fn pack_slice(&self, e: &mut Enc) {
        self.len().pack(e);
        for x in self {
            x.pack(e);
        }
    }
}

impl<T: Pack, const N: usize> Pack for [T; N] {
    fn pack(&self, e: &mut Enc) {
        for x in self {
            x.pack(e);
        }
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let mut v = Vec::with_capacity(N);
        for _ in 0..N {
            v.push(T::unpack(d)?);
        }
        Ok(v.try_into().ok().expect("N elements"))
    }
}

impl<T: Pack> Pack for Option<T> {
    fn pack(&self, e: &mut Enc) {
        match self {
            None => e.buf.push(0),
            Some(v) => {
                e.buf.push(1);
                v.pack(e);
            }
        }
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(if bool::unpack(d)? {
            Some(T::unpack(d)?)
        } else {
            None
        })
    }
}

impl Pack for String {
    fn pack(&self, e: &mut Enc) {
        e.text(self);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let n = usize::unpack(d)?;
        let b = d.take(n)?;
        String::from_utf8(b.to_vec()).map_err(|_| d.error("text that is not UTF-8"))
    }
}

impl<A: Pack, B: Pack> Pack for (A, B) {
    fn pack(&self, e: &mut Enc) {
        self.0.pack(e);
        self.1.pack(e);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok((A::unpack(d)?, B::unpack(d)?))
    }
}

impl<A: Pack, B: Pack, C: Pack> Pack for (A, B, C) {
    fn pack(&self, e: &mut Enc) {
        self.0.pack(e);
        self.1.pack(e);
        self.2.pack(e);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok((A::unpack(d)?, B::unpack(d)?, C::unpack(d)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_come_back_bit_for_bit_and_a_short_buffer_is_an_error() {
        let mut e = Enc::default();
        let xs = vec![[1.5f64, -0.0], [f64::MIN_POSITIVE, 1e300]];
        e.section("a", |e| {
            e.put(&xs);
            e.put(&Some(7u32));
            e.put(&"text".to_string());
            e.put(&true);
        });
        let mut d = Dec::new(&e.buf);
        let (ys, o, s, b) = d
            .section("a", |d| {
                Ok((
                    d.get::<Vec<[f64; 2]>>()?,
                    d.get::<Option<u32>>()?,
                    d.get::<String>()?,
                    d.get::<bool>()?,
                ))
            })
            .unwrap();
        assert_eq!(ys[0][1].to_bits(), (-0.0f64).to_bits());
        assert_eq!((ys, o, s.as_str(), b), (xs, Some(7), "text", true));
        for cut in 0..e.buf.len() {
            let mut d = Dec::new(&e.buf[..cut]);
            assert!(d.section("a", |d| d.get::<Vec<[f64; 2]>>()).is_err());
        }
    }

    #[test]
    fn a_section_read_in_part_or_under_another_name_is_an_error() {
        let mut e = Enc::default();
        e.section("a", |e| e.put(&[1u64, 2]));
        let err = Dec::new(&e.buf)
            .section("a", |d| d.get::<u64>())
            .unwrap_err();
        assert!(err.0.contains("read 8 of its 16 bytes"), "{err}");
        let err = Dec::new(&e.buf)
            .section("b", |d| d.get::<u64>())
            .unwrap_err();
        assert!(err.0.contains("expected section `b`"), "{err}");
    }
}
