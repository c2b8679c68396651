//! A byte cursor that reads ASCII tokens or little-endian binary numbers, with line numbers
//! for error messages. Counts read from a file are checked against the bytes left, so that a
//! corrupt count gives an error rather than a huge allocation.

use crate::error::MeshError;
use crate::excerpt::excerpt;

pub(crate) struct Cursor<'a> {
    pub b: &'a [u8],
    pub pos: usize,
    pub path: &'a str,
    pub binary: bool,
    pub size_t: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(b: &'a [u8], path: &'a str) -> Self {
        Cursor {
            b,
            pos: 0,
            path,
            binary: false,
            size_t: 8,
        }
    }

    pub fn line(&self) -> usize {
        1 + self.b[..self.pos.min(self.b.len())]
            .iter()
            .filter(|&&c| c == b'\n')
            .count()
    }

    pub fn err(&self, msg: impl Into<String>) -> MeshError {
        MeshError::Parse {
            path: self.path.to_string(),
            line: self.line(),
            message: msg.into(),
        }
    }

    pub fn at_end(&mut self) -> bool {
        self.skip_ws();
        self.pos >= self.b.len()
    }

    pub fn skip_ws(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next whitespace-delimited ASCII token.
    pub fn token(&mut self) -> Result<&'a str, MeshError> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.err("unexpected end of file (truncated?)"));
        }
        std::str::from_utf8(&self.b[start..self.pos])
            .map_err(|_| self.err("invalid bytes where text was expected"))
    }

    /// The rest of the next non-empty line, consuming its newline (section headers, names).
    pub fn line_text(&mut self) -> Result<&'a str, MeshError> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.b.len() && self.b[self.pos] != b'\n' {
            self.pos += 1;
        }
        let s = std::str::from_utf8(&self.b[start..self.pos])
            .map_err(|_| self.err("invalid bytes where a text line was expected"))?;
        if self.pos < self.b.len() {
            self.pos += 1;
        }
        Ok(s.trim_end_matches('\r'))
    }

    fn bytes(&mut self, n: usize, what: &str) -> Result<&'a [u8], MeshError> {
        if self.pos + n > self.b.len() {
            return Err(self.err(format!("file ends inside the binary {what} (truncated?)")));
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn parse<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, MeshError> {
        let t = self.token()?;
        t.parse()
            .map_err(|_| self.err(format!("expected {what}, found \"{}\"", excerpt(t))))
    }

    /// A Gmsh `int` (4 bytes in binary).
    pub fn int(&mut self) -> Result<i64, MeshError> {
        if self.binary {
            let s = self.bytes(4, "integer")?;
            Ok(i32::from_le_bytes([s[0], s[1], s[2], s[3]]) as i64)
        } else {
            self.parse("an integer")
        }
    }

    /// A Gmsh `size_t` (8 or 4 bytes in binary).
    pub fn size(&mut self) -> Result<u64, MeshError> {
        if self.binary {
            let n = self.size_t;
            let s = self.bytes(n, "size")?;
            let mut a = [0u8; 8];
            a[..n].copy_from_slice(s);
            Ok(u64::from_le_bytes(a))
        } else {
            self.parse("a non-negative integer")
        }
    }

    /// A Gmsh `double`.
    pub fn double(&mut self) -> Result<f64, MeshError> {
        if self.binary {
            let s = self.bytes(8, "real number")?;
            let mut a = [0u8; 8];
            a.copy_from_slice(s);
            Ok(f64::from_le_bytes(a))
        } else {
            self.parse("a real number")
        }
    }

    /// A count of items, each at least `min_bytes` long, checked against the bytes left.
    pub fn count(&mut self, min_bytes: usize, what: &str) -> Result<usize, MeshError> {
        let n = self.size()?;
        let left = (self.b.len() - self.pos.min(self.b.len())) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left {
            return Err(self.err(format!(
                "{what} count {n} is larger than the rest of the file (truncated or corrupt)"
            )));
        }
        Ok(n as usize)
    }

    /// Expects the section end marker `end` (e.g. `$EndNodes`).
    pub fn expect(&mut self, end: &str) -> Result<(), MeshError> {
        let t = self.line_text()?;
        if t.trim() != end {
            return Err(self.err(format!(
                "expected {end}, found \"{}\" (truncated or inconsistent counts)",
                excerpt(t)
            )));
        }
        Ok(())
    }

    /// Skips an unknown section up to and including its `$End...` line.
    pub fn skip_section(&mut self, name: &str) -> Result<(), MeshError> {
        let end = format!("$End{}", &name[1..]);
        let needle = end.as_bytes();
        while self.pos + needle.len() <= self.b.len() {
            if &self.b[self.pos..self.pos + needle.len()] == needle {
                self.pos += needle.len();
                return Ok(());
            }
            self.pos += 1;
        }
        Err(self.err(format!("section {name} has no {end} (truncated?)")))
    }
}
