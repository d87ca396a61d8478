//! Reading RON text into a [`Scene`], with errors that say where and which field.

use serde::Deserialize;

use crate::error::SceneError;
use crate::format::Scene;

impl Scene {
    /// Reads a scene from RON text; errors carry the line and column, the path of the field
    /// being read (e.g. `fluid.blocks[0].max`) and the offending text.
    pub fn from_ron(text: &str) -> Result<Self, SceneError> {
        scene(text)
    }
}

/// Longest excerpt of the offending text quoted in an error.
const MAX_EXCERPT: usize = 40;

/// Parses `text`; a failure becomes one line: position, field path, ron's reason and the text
/// found there.
pub(crate) fn scene(text: &str) -> Result<Scene, SceneError> {
    if text.trim().is_empty() {
        return Err(SceneError::Parse(
            "the file is empty; a scene is `Scene(name: ..., dimension: ..., dx: ..., ...)`".into(),
        ));
    }
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let mut deserializer = ron::Deserializer::from_str_with_options(text, &options)
        .map_err(|error| spanned(text, &error, ""))?;
    let mut track = serde_path_to_error::Track::new();
    let scene = Scene::deserialize(serde_path_to_error::Deserializer::new(
        &mut deserializer,
        &mut track,
    ))
    .map_err(|error| {
        let path = track.path().to_string();
        spanned(text, &deserializer.span_error(error), &path)
    })?;
    deserializer
        .end()
        .map_err(|error| spanned(text, &deserializer.span_error(error), ""))?;
    Ok(scene)
}

/// `line:column: field `path`: reason, found `excerpt``, on one line.
fn spanned(text: &str, error: &ron::error::SpannedError, path: &str) -> SceneError {
    let start = &error.span.start;
    let mut message = format!("line {}, column {}: ", start.line, start.col);
    // serde_path_to_error writes `?` for a path it could not follow and `.` for the root.
    if !path.is_empty() && path != "." && path != "?" {
        message.push_str(&format!("field `{path}`: "));
    } else if let Some(field) = offset(text, start).and_then(|end| last_field(text, end)) {
        message.push_str(&format!("after field `{field}`: "));
    }
    message.push_str(&one_line(&error.code.to_string()));
    if let ron::Error::NoSuchStructField { found, .. } = &error.code
        && WCSPH_ONLY.contains(&found.as_str())
        && !path.contains("Wcsph")
    {
        message.push_str(&format!(
            " (`{found}` is an option of the `Wcsph` solver only)"
        ));
    }
    if let Some(found) = excerpt(text, &error.span) {
        message.push_str(&format!(", found `{found}`"));
    }
    SceneError::Parse(message)
}

/// Terms that only WCSPH has: another solver's block that names one is told so.
const WCSPH_ONLY: [&str; 4] = ["sps", "surface_tension", "equation_of_state", "diffusion"];

/// The text of `span` (or, for an empty span, the token at its start), shortened to one line.
fn excerpt(text: &str, span: &ron::error::Span) -> Option<String> {
    let offset = |position: &ron::error::Position| offset(text, position);
    let mut start = offset(&span.start)?;
    // ron points at the digits of a negative number.
    if text[..start].ends_with('-') {
        start -= 1;
    }
    let end = offset(&span.end).filter(|&end| end > start);
    let spanned = end.map_or("", |end| text[start..end].trim());
    let token = if spanned.is_empty() {
        // An empty or blank span: the token that follows it.
        let rest = text[start..].trim_start();
        let length = rest
            .find(|c: char| c.is_whitespace() || matches!(c, ',' | ')' | ']' | '('))
            .unwrap_or(rest.len());
        &rest[..length]
    } else {
        spanned
    };
    let token = one_line(token.trim());
    if token.is_empty() {
        return None;
    }
    Some(match token.char_indices().nth(MAX_EXCERPT) {
        Some((at, _)) => format!("{}…", &token[..at]),
        None => token,
    })
}

/// The byte offset of a ron line:column (1-based, columns counting characters) in `text`.
fn offset(text: &str, position: &ron::error::Position) -> Option<usize> {
    let line = text
        .split_inclusive('\n')
        .nth(position.line.checked_sub(1)?)?;
    let before: usize = text
        .split_inclusive('\n')
        .take(position.line - 1)
        .map(str::len)
        .sum();
    let within = line
        .char_indices()
        .nth(position.col.checked_sub(1)?)
        .map_or(line.len(), |(at, _)| at);
    Some(before + within)
}

/// The last `identifier:` before `end` in `text`: the field whose value was being read when
/// ron stopped outside any value (e.g. at `2.5` of an integer field), outside comments.
fn last_field(text: &str, end: usize) -> Option<&str> {
    let before = text.get(..end)?;
    let mut found = None;
    for line in before.lines() {
        let code = line.split("//").next().unwrap_or("");
        let bytes = code.as_bytes();
        for (colon, _) in code.match_indices(':') {
            let name_end = code[..colon].trim_end().len();
            // Walk back over ASCII identifier characters only, so that the slice below
            // always starts on a character boundary (the fuzzer found one that did not).
            let name_start = code[..name_end]
                .char_indices()
                .rev()
                .take_while(|(_, c)| c.is_ascii_alphanumeric() || *c == '_')
                .last()
                .map_or(name_end, |(at, _)| at);
            if name_start < name_end && !bytes[name_start].is_ascii_digit() {
                found = Some(&code[name_start..name_end]);
            }
        }
    }
    found
}

/// `text` with line breaks replaced by spaces.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn last_field_skips_comments_and_copes_with_multibyte_text() {
        let whole = |text: &'static str| last_field(text, text.len());
        assert_eq!(whole("a: 1,\n b: 2 // c: 3\n"), Some("b"));
        assert_eq!(whole("x: 1, \u{4b08}layers: 2"), Some("layers"));
        assert_eq!(whole("\u{4b08}: 1"), None);
        assert_eq!(whole("9a: 1"), None);
    }

    /// The input on which the fuzzer found the panic (a slice inside a multi-byte character).
    #[test]
    fn fuzz_finding_multibyte_before_colon_is_an_error_not_a_panic() {
        let text = include_str!(
            "../../../fuzz/regressions/crash-86ca34701ee8c9c791656980319ceda07d751e3f"
        );
        assert!(scene(text).is_err());
    }
}
