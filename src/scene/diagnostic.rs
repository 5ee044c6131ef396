//! Locating and explaining scene mistakes: byte offsets to line/column, TOML and serde errors
//! rewritten as `Error::Scene` with a message and a hint, typed readers for leaf values, and
//! "did you mean" suggestions (Levenshtein edit distance).
use super::raw::TABLE_KEYS;
use crate::error::{Error, Location, Result};
use std::ops::Range;
use std::path::Path;
use toml::{Spanned, Value};

/// The text of a scene and the name it is reported under.
pub(super) struct Source<'a> {
    pub file: &'a Path,
    pub text: &'a str,
}

impl<'a> Source<'a> {
    /// 1-based line and column (in characters) of a byte offset; offsets past the end or inside
    /// a character are clamped.
    pub fn location(&self, offset: usize) -> Location {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &self.text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        Location {
            file: self.file.to_path_buf(),
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
        }
    }

    /// The value as written in the file (`1e9`, not `1000000000`).
    pub fn written<'v>(&'v self, v: &Spanned<Value>) -> &'v str {
        self.text.get(v.span()).unwrap_or("").trim()
    }

    pub fn error(&self, span: &Range<usize>, message: impl Into<String>, hint: impl Into<String>) -> Error {
        Error::Scene { location: self.location(span.start), message: message.into(), hint: hint.into() }
    }

    /// The span of the `occurrence`-th (0-based) header `[name]` (or `[[name]]` when `array`),
    /// found by scanning line starts. `None` for tables written inline or with dotted keys.
    pub fn table_header(&self, name: &str, array: bool, occurrence: usize) -> Option<Range<usize>> {
        self.table_header_within(name, array, occurrence, 0..self.text.len())
    }

    /// [`Source::table_header`] counting only the headers that start inside `within` (the
    /// text of one `[[body]]`: its `[body.mesh]`, its second `[[body.traction]]`...).
    pub fn table_header_within(
        &self,
        name: &str,
        array: bool,
        occurrence: usize,
        within: Range<usize>,
    ) -> Option<Range<usize>> {
        let mut seen = 0;
        let mut start = 0;
        for line in self.text.split_inclusive('\n') {
            let here = start;
            start += line.len();
            if !within.contains(&here) {
                continue;
            }
            let trimmed = line.trim_start();
            let indent = line.len() - trimmed.len();
            let body = match array {
                true => trimmed.strip_prefix("[[").and_then(|r| r.split_once("]]")).map(|(b, _)| b),
                false => match trimmed.starts_with("[[") {
                    true => None,
                    false => trimmed.strip_prefix('[').and_then(|r| r.split_once(']')).map(|(b, _)| b),
                },
            };
            let Some(body) = body else { continue };
            let header: String = body.split('.').map(|p| p.trim().trim_matches('"')).collect::<Vec<_>>().join(".");
            if header == name {
                if seen == occurrence {
                    let end = here + line.trim_end().len();
                    return Some(here + indent..end);
                }
                seen += 1;
            }
        }
        None
    }

    /// Rewrite a TOML syntax error or a serde structure error (unknown key, wrong type).
    pub fn toml_error(&self, e: &toml::de::Error) -> Error {
        let span = e.span().unwrap_or(0..0);
        let raw = e.message().trim();
        let one_line = raw.split('\n').map(str::trim).filter(|s| !s.is_empty()).collect::<Vec<_>>().join(": ");

        if let Some(rest) = raw.strip_prefix("unknown field ") {
            // serde: "unknown field `k`, expected one of `a`, `b`" / "expected `a` or `b`"
            let names = backticked(rest);
            if let Some((unknown, allowed)) = names.split_first() {
                return self.unknown_key(&span, unknown, allowed);
            }
        }
        if let Some(rest) = raw.strip_prefix("unexpected keys in table: ") {
            // toml_edit's own check: "unexpected keys in table: k1, k2, available keys: a, b"
            if let Some((unknown, allowed)) = rest.split_once(", available keys: ") {
                let unknown = unknown.split(", ").next().unwrap_or(unknown).to_string();
                let allowed: Vec<String> = allowed.split(", ").map(str::to_string).collect();
                return self.unknown_key(&span, &unknown, &allowed);
            }
        }
        let wrong_type = match (raw.strip_prefix("invalid type: "), raw.strip_prefix("invalid length ")) {
            (Some(rest), _) => Some(
                rest.replacen(", expected ", ", but expected ", 1)
                    .replace("expected a sequence", "expected an array of tables ([[name]] headers)"),
            ),
            (None, Some(rest)) => rest.split_once(", expected ").map(|(n, expected)| {
                let plural = if n == "1" { "" } else { "s" };
                format!("an array of {n} table{plural}, but expected {expected}")
            }),
            (None, None) => None,
        };
        if let Some(found) = wrong_type {
            let message = match self.key_before(span.start) {
                Some(key) => format!("wrong type for `{key}`: found {found}"),
                None => format!("wrong type: found {found}"),
            };
            return self.error(
                &span,
                message,
                "tables are written [name], repeatable tables [[name]] (traction, dirichlet); \
                 see docs/scene-format.md for the type of each key",
            );
        }
        if raw.starts_with("duplicate key") {
            return self.error(&span, one_line, "a key may appear only once per table: remove the repeated one");
        }
        self.error(
            &span,
            format!("TOML syntax error: {one_line}"),
            "fix the syntax here: strings need double quotes, arrays brackets [a, b], tables a header \
             line [name] (see https://toml.io)",
        )
    }

    fn unknown_key(&self, span: &Range<usize>, unknown: &str, allowed: &[String]) -> Error {
        let table = TABLE_KEYS
            .iter()
            .find(|(_, keys)| keys.len() == allowed.len() && keys.iter().all(|k| allowed.iter().any(|a| a == k)))
            .map(|(name, _)| *name);
        let message = match table {
            Some("the top level") => format!("unknown table or key `{unknown}` at the top level"),
            Some(t) => format!("unknown key `{unknown}` in {t}"),
            None => format!("unknown key `{unknown}`"),
        };
        let allowed_refs: Vec<&str> = allowed.iter().map(String::as_str).collect();
        let list = allowed_refs.join(", ");
        let hint = match closest(unknown, &allowed_refs) {
            Some(guess) => format!("did you mean `{guess}`? Allowed here: {list}"),
            None => format!("allowed here: {list}"),
        };
        self.error(span, message, hint)
    }

    /// The bare key written just before `offset` on its line (`key = <offset>`), if any.
    fn key_before(&self, offset: usize) -> Option<String> {
        let before = self.text.get(..offset)?;
        let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
        let lhs = line.trim_end().strip_suffix('=')?.trim();
        let key = lhs.rsplit(['.', ' ', '{', ',']).next()?.trim_matches('"');
        (!key.is_empty()).then(|| key.to_string())
    }

    // ---- typed readers for leaf values -------------------------------------------------------

    pub fn number(&self, v: &Spanned<Value>, key: &str) -> Result<f64> {
        let x = match v.get_ref() {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            other => {
                return Err(self.error(
                    &v.span(),
                    format!("`{key}` must be a number, found {}", describe(other)),
                    format!("write a number without quotes, e.g. `{key} = 1.5`"),
                ))
            }
        };
        if !x.is_finite() {
            return Err(self.error(
                &v.span(),
                format!("`{key}` must be a finite number, found {}", self.written(v)),
                format!("write a finite number, e.g. `{key} = 1.5` (nan and inf are not allowed)"),
            ));
        }
        Ok(x)
    }

    pub fn positive(&self, v: &Spanned<Value>, key: &str, what: &str) -> Result<f64> {
        let x = self.number(v, key)?;
        if x <= 0.0 {
            return Err(self.error(
                &v.span(),
                format!("`{key}` must be positive, found {}", self.written(v)),
                format!("give {what} greater than 0"),
            ));
        }
        Ok(x)
    }

    pub fn vector(&self, v: &Spanned<Value>, key: &str) -> Result<[f64; 2]> {
        let wrong = |found: String| {
            self.error(
                &v.span(),
                format!("`{key}` must be an array of two numbers [x, y], found {found}"),
                format!("write two numbers in brackets, e.g. `{key} = [0.0, 1.0]`"),
            )
        };
        let Value::Array(items) = v.get_ref() else {
            return Err(wrong(describe(v.get_ref())));
        };
        if items.len() != 2 {
            return Err(wrong(describe(v.get_ref())));
        }
        let mut out = [0.0; 2];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = match item {
                Value::Float(x) => *x,
                Value::Integer(i) => *i as f64,
                other => return Err(wrong(format!("{} inside the array", describe(other)))),
            };
            if !slot.is_finite() {
                return Err(self.error(
                    &v.span(),
                    format!("`{key}` must hold finite numbers, found {}", self.written(v)),
                    format!("write finite numbers, e.g. `{key} = [0.0, 1.0]` (nan and inf are not allowed)"),
                ));
            }
        }
        Ok(out)
    }

    /// A whole number `>= 1` (an iteration count...).
    pub fn positive_integer(&self, v: &Spanned<Value>, key: &str) -> Result<usize> {
        match v.get_ref() {
            Value::Integer(i) if *i >= 1 => usize::try_from(*i).map_err(|_| {
                self.error(&v.span(), format!("`{key}` is too large: {i}"), format!("give a smaller `{key}`"))
            }),
            Value::Integer(i) => Err(self.error(
                &v.span(),
                format!("`{key}` must be at least 1, found {i}"),
                format!("give a positive whole number, e.g. `{key} = 200`"),
            )),
            other => Err(self.error(
                &v.span(),
                format!("`{key}` must be a whole number, found {}", describe(other)),
                format!("write a positive whole number without a decimal point, e.g. `{key} = 200`"),
            )),
        }
    }

    /// An array of points `[[x0, y0], [x1, y1], ...]` (any length, checked by the caller).
    pub fn points(&self, v: &Spanned<Value>, key: &str) -> Result<Vec<[f64; 2]>> {
        let example = format!("`{key} = [[-1.0, 0.0], [0.0, -0.1], [1.0, 0.0]]`");
        let Value::Array(items) = v.get_ref() else {
            return Err(self.error(
                &v.span(),
                format!("`{key}` must be an array of points [x, y], found {}", describe(v.get_ref())),
                format!("write the points in brackets, e.g. {example}"),
            ));
        };
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let pair = match item {
                Value::Array(xy) if xy.len() == 2 => {
                    let number = |x: &Value| match x {
                        Value::Float(x) => Some(*x),
                        Value::Integer(i) => Some(*i as f64),
                        _ => None,
                    };
                    number(&xy[0]).zip(number(&xy[1])).map(|(x, y)| [x, y])
                }
                _ => None,
            };
            let Some(p) = pair else {
                return Err(self.error(
                    &v.span(),
                    format!("`{key}[{i}]` must be a point [x, y] of two numbers, found {}", describe(item)),
                    format!("write each point as two numbers in brackets, e.g. {example}"),
                ));
            };
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(self.error(
                    &v.span(),
                    format!("`{key}[{i}]` must hold finite numbers, found {item}"),
                    "write finite numbers (nan and inf are not allowed)",
                ));
            }
            out.push(p);
        }
        Ok(out)
    }

    pub fn string<'v>(&self, v: &'v Spanned<Value>, key: &str) -> Result<&'v str> {
        match v.get_ref() {
            Value::String(s) => Ok(s),
            other => Err(self.error(
                &v.span(),
                format!("`{key}` must be a string, found {}", describe(other)),
                format!("write text in double quotes, e.g. `{key} = \"...\"`"),
            )),
        }
    }

    pub fn nonempty_string<'v>(&self, v: &'v Spanned<Value>, key: &str) -> Result<&'v str> {
        let s = self.string(v, key)?;
        if s.trim().is_empty() {
            return Err(self.error(&v.span(), format!("`{key}` is empty"), format!("give a value for `{key}`")));
        }
        Ok(s)
    }

    /// One of `choices`, with a did-you-mean on a near miss.
    pub fn choice(&self, v: &Spanned<Value>, key: &str, choices: &[&'static str]) -> Result<&'static str> {
        let quoted: Vec<String> = choices.iter().map(|c| format!("\"{c}\"")).collect();
        let list = quoted.join(", ");
        let s = match v.get_ref() {
            Value::String(s) => s,
            other => {
                return Err(self.error(
                    &v.span(),
                    format!("`{key}` must be one of {list}, found {}", describe(other)),
                    format!("write the name in double quotes, e.g. `{key} = \"{}\"`", choices[0]),
                ))
            }
        };
        if let Some(c) = choices.iter().find(|c| **c == s) {
            return Ok(c);
        }
        let hint = match closest(s, choices) {
            Some(guess) => format!("did you mean \"{guess}\"? The choices are {list}"),
            None => format!("the choices are {list}"),
        };
        Err(self.error(&v.span(), format!("unknown {key} \"{s}\""), hint))
    }
}

/// The `...` quoted names in a serde message, in order.
fn backticked(s: &str) -> Vec<String> {
    s.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

/// A short description of a value for messages: `the string "steel"`, `the integer 3`...
pub(super) fn describe(v: &Value) -> String {
    let shown = |s: String| match s.chars().count() > 40 {
        true => format!("{}...", s.chars().take(40).collect::<String>()),
        false => s,
    };
    match v {
        Value::String(s) => format!("the string {}", shown(format!("{s:?}"))),
        Value::Integer(i) => format!("the integer {i}"),
        Value::Float(x) => format!("the number {x}"),
        Value::Boolean(b) => format!("the boolean {b}"),
        Value::Datetime(d) => format!("the date-time {d}"),
        Value::Array(a) => {
            format!("an array of {} item{} {}", a.len(), if a.len() == 1 { "" } else { "s" }, shown(v.to_string()))
        }
        Value::Table(_) => "a table".to_string(),
    }
}

/// The candidate closest to `word` if it is a plausible typo: edit distance at most 2, and at
/// most a third of the longer word.
pub(super) fn closest<'c>(word: &str, candidates: &[&'c str]) -> Option<&'c str> {
    let word = word.to_lowercase();
    candidates
        .iter()
        .map(|c| (edit_distance(&word, c), *c))
        .filter(|(d, c)| *d <= 2 && 3 * d <= word.chars().count().max(c.chars().count()))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// Edit distance counting insertions, deletions, substitutions and swaps of two adjacent
/// characters as one edit each (optimal string alignment: Damerau, CACM 7(3), 1964), by characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    // d[i][j] = distance between a[..i] and b[..j]
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let substitution = d[i - 1][j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut best = substitution.min(d[i - 1][j] + 1).min(d[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_counts_single_edits() {
        assert_eq!(edit_distance("radius", "radius"), 0);
        assert_eq!(edit_distance("radus", "radius"), 1);
        assert_eq!(edit_distance("raidus", "radius"), 1);
        assert_eq!(edit_distance("rigth", "right"), 1);
        assert_eq!(edit_distance("abc", "ca"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn location_counts_lines_and_characters() {
        let src = Source { file: Path::new("s.toml"), text: "a = 1\nb = \"é\"x\n" };
        let l = src.location(0);
        assert_eq!((l.line, l.column), (1, 1));
        let l = src.location(6);
        assert_eq!((l.line, l.column), (2, 1));
        // "é" is two bytes but one column
        let l = src.location(src.text.find('x').unwrap());
        assert_eq!((l.line, l.column), (2, 8));
        let l = src.location(1000);
        assert_eq!((l.line, l.column), (3, 1));
    }

    #[test]
    fn headers_are_found_in_order() {
        let text = "[mesh]\n  [[traction]] # first\nx=1\n[[ traction ]]\n[mesh.refine]\n";
        let src = Source { file: Path::new("s.toml"), text };
        assert_eq!(src.table_header("mesh", false, 0), Some(0..6));
        assert_eq!(src.table_header("traction", true, 0).map(|r| src.location(r.start).line), Some(2));
        assert_eq!(src.table_header("traction", true, 1).map(|r| src.location(r.start).line), Some(4));
        assert_eq!(src.table_header("traction", true, 2), None);
        assert_eq!(src.table_header("traction", false, 0), None);
        assert_eq!(src.table_header("mesh.refine", false, 0).map(|r| src.location(r.start).line), Some(5));
    }
}
