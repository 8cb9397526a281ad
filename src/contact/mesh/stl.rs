//! STL files: binary (80-byte header, a facet count, 50 bytes a facet) or ASCII (`solid`,
//! `facet normal`, `outer loop`, three `vertex`, `endloop`, `endfacet`, `endsolid`). A file is
//! binary when its size is exactly `84 + 50·count`, whatever its first bytes say (binary
//! headers often begin with `solid` too); otherwise it must be ASCII. Stored facet normals are
//! ignored (the vertex order defines the orientation).

use super::{Facets, MeshError};
use crate::math::Real;

/// The facets of an STL file.
pub(crate) fn parse(bytes: &[u8], file: &str) -> Result<Facets, MeshError> {
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if count.checked_mul(50).and_then(|n| n.checked_add(84)) == Some(bytes.len()) {
            return binary(bytes, count, file);
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|_| {
        MeshError::new(
            file,
            None,
            None,
            format!(
                "neither a binary STL ({} bytes is not 84 + 50 × the facet count in bytes 80..84) nor ASCII text",
                bytes.len()
            ),
        )
    })?;
    ascii(text, file)
}

fn binary(bytes: &[u8], count: usize, file: &str) -> Result<Facets, MeshError> {
    let mut triangles = Vec::with_capacity(count);
    for facet in 0..count {
        let base = 84 + 50 * facet;
        let float = |k: usize| {
            let at = base + 12 + 4 * k; // after the stored normal
            f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as Real
        };
        let mut triangle = [[0.0; 3]; 3];
        for (v, vertex) in triangle.iter_mut().enumerate() {
            for (c, value) in vertex.iter_mut().enumerate() {
                *value = float(3 * v + c);
            }
        }
        if triangle.iter().flatten().any(|x| !x.is_finite()) {
            return Err(MeshError::new(
                file,
                None,
                None,
                format!(
                    "binary facet {} (byte {base}): a vertex coordinate is not finite",
                    facet + 1
                ),
            ));
        }
        triangles.push(triangle);
    }
    Ok(Facets {
        lines: vec![None; triangles.len()],
        triangles,
    })
}

/// The words of a text, each with its 1-based line and column.
struct Words<'a> {
    words: Vec<(u64, u64, &'a str)>,
    next: usize,
    file: &'a str,
    end: (u64, u64),
}

impl<'a> Words<'a> {
    fn new(text: &'a str, file: &'a str) -> Words<'a> {
        let mut words = Vec::new();
        let mut lines = 0;
        for (index, line) in text.lines().enumerate() {
            lines = index as u64 + 1;
            words.extend(super::words(line).into_iter().map(|(c, w)| (lines, c, w)));
        }
        Words {
            words,
            next: 0,
            file,
            end: (lines.max(1), 1),
        }
    }

    fn peek(&self) -> Option<&'a str> {
        self.words.get(self.next).map(|w| w.2)
    }

    fn error_here(&self, message: String) -> MeshError {
        let (line, column) = self.words.get(self.next).map_or(self.end, |w| (w.0, w.1));
        MeshError::new(self.file, Some(line), Some(column), message)
    }

    /// The next word, which must be `keyword` (case-insensitive); returns its line.
    fn expect(&mut self, keyword: &str) -> Result<u64, MeshError> {
        match self.words.get(self.next) {
            Some(&(line, _, word)) if word.eq_ignore_ascii_case(keyword) => {
                self.next += 1;
                Ok(line)
            }
            Some(&(_, _, word)) => {
                Err(self.error_here(format!("expected `{keyword}`, found `{word}`")))
            }
            None => {
                Err(self.error_here(format!("expected `{keyword}`, found the end of the file")))
            }
        }
    }

    fn number(&mut self) -> Result<Real, MeshError> {
        let Some(&(_, _, word)) = self.words.get(self.next) else {
            return Err(self.error_here("expected a number, found the end of the file".into()));
        };
        match word.parse::<Real>() {
            Ok(x) if x.is_finite() => {
                self.next += 1;
                Ok(x)
            }
            _ => Err(self.error_here(format!("expected a finite number, found `{word}`"))),
        }
    }

    /// Skips the rest of the line `line` (a solid's name).
    fn skip_line(&mut self, line: u64) {
        while self.words.get(self.next).is_some_and(|w| w.0 == line) {
            self.next += 1;
        }
    }
}

fn ascii(text: &str, file: &str) -> Result<Facets, MeshError> {
    let mut words = Words::new(text, file);
    let (mut triangles, mut lines) = (Vec::new(), Vec::new());
    let line = words.expect("solid")?;
    words.skip_line(line);
    loop {
        match words.peek().map(str::to_ascii_lowercase).as_deref() {
            Some("facet") => {
                let line = words.expect("facet")?;
                words.expect("normal")?;
                for _ in 0..3 {
                    words.number()?;
                }
                words.expect("outer")?;
                words.expect("loop")?;
                let mut triangle = [[0.0; 3]; 3];
                for vertex in &mut triangle {
                    words.expect("vertex")?;
                    for value in vertex.iter_mut() {
                        *value = words.number()?;
                    }
                }
                words.expect("endloop")?;
                words.expect("endfacet")?;
                triangles.push(triangle);
                lines.push(Some(line));
            }
            Some("endsolid") => {
                let line = words.expect("endsolid")?;
                words.skip_line(line);
                match words.peek() {
                    None => break,
                    Some(w) if w.eq_ignore_ascii_case("solid") => {
                        let line = words.expect("solid")?;
                        words.skip_line(line);
                    }
                    Some(w) => {
                        return Err(words.error_here(format!(
                            "expected `solid` or the end of the file after `endsolid`, found `{w}`"
                        )));
                    }
                }
            }
            Some(_) => {
                let found = words.peek().unwrap_or_default();
                return Err(
                    words.error_here(format!("expected `facet` or `endsolid`, found `{found}`"))
                );
            }
            None => {
                return Err(
                    words.error_here("expected `endsolid`, found the end of the file".into())
                );
            }
        }
    }
    if triangles.is_empty() {
        return Err(MeshError::new(file, None, None, "no facets".into()));
    }
    Ok(Facets { triangles, lines })
}
