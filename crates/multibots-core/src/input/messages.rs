//! Parser messages in the user's words: serde's, TOML's and JSON's errors turned into one
//! line that names the field and the value as the user wrote them (docs/limits.md,
//! docs/scenario-format.md), with no Rust type in it.

/// One line for a TOML file that does not fit its schema: the field's path, or the line for
/// a syntax error, then the first line of the parser's message.
pub(crate) fn toml_message(text: &str, e: serde_path_to_error::Error<toml::de::Error>) -> String {
    // The path holds the user's keys, which may be anything (a control character, 10 MB).
    let path = crate::error::shown(&e.path().to_string());
    let inner = e.into_inner();
    let msg = inner.message().lines().next().unwrap_or_default().trim();
    if !path.is_empty() && path != "." {
        return plain(&path, msg, None);
    }
    match inner.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let line = text[..start].matches('\n').count() + 1;
            // A number TOML cannot hold comes without a path: its line names the key and value.
            let src = text.lines().nth(line - 1).unwrap_or_default();
            match src.split_once('=').filter(|_| msg == "number too large to fit in target type") {
                Some((key, value)) => {
                    let value = value.split_once('#').map_or(value, |(v, _)| v);
                    plain(&format!("line {line}: {}", crate::error::shown(key.trim())), msg, Some(value))
                }
                None => plain(&format!("line {line}"), msg, None),
            }
        }
        None => plain("", msg, None),
    }
}

/// One line for a JSON text that does not fit its schema (what the Python API sends): the
/// field's path and the value in the user's words, without the JSON position (the user
/// wrote a dictionary or a flag, not this text).
pub(crate) fn json_message(e: &serde_path_to_error::Error<serde_json::Error>) -> String {
    let path = crate::error::shown(&e.path().to_string());
    let text = e.inner().to_string();
    let text = text.lines().next().unwrap_or_default();
    let text = text.rfind(" at line ").map_or(text, |k| &text[..k]).trim();
    plain(&path, text, None)
}

/// A message of serde (or of the TOML and JSON parsers) in the words of docs/limits.md and
/// docs/scenario-format.md: `FIELD = VALUE: expected a whole number from 0 to 4294967295`
/// rather than `invalid type: floating point `2e9`, expected u32`. `written`: the value's
/// text as the user wrote it, where the parser gave no path (a number TOML cannot hold).
pub(crate) fn plain(path: &str, message: &str, written: Option<&str>) -> String {
    let mut path = if path == "." { "" } else { path };
    if let Some(name) = message.strip_prefix("unknown field `").and_then(|m| m.split_once('`')).map(|m| m.0) {
        // The path ends with the unknown name itself: the table it is in says where.
        path = path.strip_suffix(name).map_or(path, |p| p.strip_suffix('.').unwrap_or(p));
    }
    match plain_parts(message, written) {
        (Some(value), reason) if !path.is_empty() => format!("{path} = {value}: {reason}"),
        (_, reason) if !path.is_empty() => format!("{path}: {reason}"),
        (_, reason) => reason,
    }
}

/// [`plain`] in parts: the value, when the message has one, and what is wrong with it.
pub(crate) fn plain_parts(message: &str, written: Option<&str>) -> (Option<String>, String) {
    // Parsed whole: the value it quotes may be long (it is shortened once found) and may itself
    // hold ", expected " (what serde expected never does: the last one is serde's).
    if let Some(rest) = message.strip_prefix("invalid type: ").or_else(|| message.strip_prefix("invalid value: ")) {
        if let Some((got, expected)) = rest.rsplit_once(", expected ") {
            let (value, float) = unexpected(got);
            let mut want = crate::error::inert(&expected_words(expected));
            if float && want.starts_with("a whole number") {
                want.push_str(", written without a decimal point or exponent");
            }
            return match value {
                Ok(v) => (Some(crate::error::shown(&v)), format!("expected {want}")),
                Err(kind) => (None, format!("expected {want}, not {kind}")),
            };
        }
    }
    let message = crate::error::inert(message);
    let strip = |s: &str| s.replace('`', "");
    if let Some(rest) = message.strip_prefix("unknown variant ") {
        let (name, expected) = rest.split_once(", expected ").unwrap_or((rest, "no value"));
        let (name, expected) = (strip(name), strip(expected));
        let hint = crate::error::did_you_mean(&name, names_in(&expected)).map_or(String::new(), |n| format!(" (did you mean \"{n}\"?)"));
        return (Some(format!("\"{name}\"")), format!("expected {expected}{hint}"));
    }
    if let Some(rest) = message.strip_prefix("unknown field ") {
        let (name, known) = rest.split_once(", expected ").unwrap_or((rest, ""));
        let known = strip(known.strip_prefix("one of ").unwrap_or(known)).replace(" or ", ", ");
        let hint = crate::error::did_you_mean(&strip(name), names_in(&known)).map_or(String::new(), |n| format!("did you mean `{n}`? "));
        let known = if known.is_empty() { String::new() } else { format!(" ({hint}known: {known})") };
        return (None, format!("unknown field {name}{known}"));
    }
    let value = written.map(|w| crate::error::shown(w.trim()));
    let reason = match message.as_str() {
        "number too large to fit in target type" => format!("too large (TOML whole numbers are at most {})", i64::MAX),
        "number out of range" => "a number out of range (at most ±1.8e308)".into(),
        "wanted string or table" => "expected text in quotes".into(),
        "recursion limit exceeded" => format!("nested deeper than {} levels (docs/limits.md)", crate::input::limits::MAX_NESTING),
        _ => return (None, message),
    };
    (value, reason)
}

/// The names of a list such as "a, b, c" or "one of a, b or c".
fn names_in(list: &str) -> Vec<String> {
    let list = list.strip_prefix("one of ").unwrap_or(list).replace(" or ", ", ");
    list.split(", ").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()
}

/// The value serde found, as the user would write it (`Ok`), or what kind of thing it is
/// when it has no short form (`Err`: "a list", "a table"); and whether it is a float.
fn unexpected(got: &str) -> (Result<String, &'static str>, bool) {
    let quoted = |s: &str| s.split_once('`').and_then(|(_, r)| r.rsplit_once('`')).map(|(v, _)| v.to_string());
    if let Some(rest) = got.strip_prefix("floating point ") {
        let text = quoted(rest).unwrap_or_default();
        let shown = match text.parse::<f64>() {
            Ok(v) if v.is_finite() && v.fract() == 0.0 && v.abs() < 1e16 => format!("{v:.1}"),
            Ok(v) => crate::error::number(v),
            Err(_) => text,
        };
        return (Ok(shown), true);
    }
    if let Some(rest) = got.strip_prefix("integer ").or_else(|| got.strip_prefix("boolean ")) {
        return (Ok(quoted(rest).unwrap_or_default()), false);
    }
    if let Some(rest) = got.strip_prefix("string ") {
        return (Ok(rest.to_string()), false);
    }
    match got {
        "sequence" => (Err("a list"), false),
        "map" => (Err("a table"), false),
        "null" | "unit value" | "Option value" => (Ok("null".into()), false),
        _ => (Ok(got.to_string()), false),
    }
}

/// What serde expected, in the user's words.
fn expected_words(expected: &str) -> String {
    let whole = |low: &str, high: String| format!("a whole number from {low} to {high}");
    match expected {
        "u8" => whole("0", u8::MAX.to_string()),
        "u16" => whole("0", u16::MAX.to_string()),
        "u32" => whole("0", u32::MAX.to_string()),
        "u64" | "usize" => whole("0", i64::MAX.to_string()),
        "i32" | "i64" | "isize" => "a whole number".into(),
        "f32" | "f64" => "a number".into(),
        "a string" | "a character" => "text in quotes".into(),
        "a boolean" => "true or false".into(),
        e if e.starts_with("a sequence") || e.starts_with("a tuple") => "a list".into(),
        e if e.starts_with("struct ") || e.starts_with("a map") => "a table".into(),
        e => match e.strip_prefix("an array of length ") {
            Some(n) => format!("a list of {n} values"),
            None => e.replace('`', ""),
        },
    }
}
