//! How bytes found in an input are shown in error messages: escaped, so that a binary or
//! malformed file never garbles a terminal.

/// Shows bytes as text with non-printable bytes escaped, for error messages.
pub(crate) fn escape(bytes: &[u8]) -> String {
    let s: String = bytes
        .iter()
        .flat_map(|&b| std::ascii::escape_default(b))
        .map(char::from)
        .collect();
    if bytes.is_empty() {
        "end of file".to_owned()
    } else {
        format!("`{s}`")
    }
}

/// Shows text as it is, with control characters (NUL, escape, line ends, …) and invalid UTF-8
/// escaped and at most `max` bytes of it (then `…`), for error messages about text lines.
pub(crate) fn escape_text(bytes: &[u8], max: usize) -> String {
    let shown = &bytes[..bytes.len().min(max)];
    let mut s = String::with_capacity(shown.len() + 3);
    for chunk in shown.utf8_chunks() {
        for c in chunk.valid().chars() {
            if c.is_ascii_control() {
                s.extend(std::ascii::escape_default(c as u8).map(char::from));
            } else if c.is_control() {
                s.extend(c.escape_default());
            } else {
                s.push(c);
            }
        }
        for &b in chunk.invalid() {
            s.extend(std::ascii::escape_default(b).map(char::from));
        }
    }
    if bytes.len() > max {
        s.push('…');
    }
    s
}
