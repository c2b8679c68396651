//! Short excerpts of input text for error messages: a message quotes at most a few dozen
//! characters of any token of a file, however long the token is, so that a malformed
//! 200 MB file gives a one-line error, not a 200 MB one.
//!
//! - [`excerpt`]: one value (a token, a line, a name) as the reader found it, cut to
//!   [`EXCERPT_CHARS`] characters with its length appended.
//! - [`shorten`]: a whole message (for text formed by a library such as serde, which quotes
//!   values whole): every run of non-space characters longer than twice [`EXCERPT_CHARS`] is cut as by
//!   [`excerpt`], and a message still longer than [`MESSAGE_CHARS`] keeps its beginning and its
//!   end (where serde puts the list of valid names) around an elision mark.

use std::borrow::Cow;

/// The most characters of one input value an error message quotes.
pub const EXCERPT_CHARS: usize = 60;

/// The most characters of an error message after [`shorten`] (plus the elision mark).
pub const MESSAGE_CHARS: usize = 1000;

/// `s` when it has at most [`EXCERPT_CHARS`] characters; otherwise its first
/// [`EXCERPT_CHARS`] characters, an ellipsis and the length of the whole (`abc... (20000000
/// bytes)`).
pub fn excerpt(s: &str) -> Cow<'_, str> {
    match s.char_indices().nth(EXCERPT_CHARS) {
        None => Cow::Borrowed(s),
        Some((cut, _)) => Cow::Owned(format!("{}... ({} bytes)", &s[..cut], s.len())),
    }
}

/// `msg` with every run of non-whitespace characters longer than twice [`EXCERPT_CHARS`]
/// replaced by its [`excerpt`] (so that the excerpts of a message already formed with
/// [`excerpt`] are left alone) (the run's trailing punctuation such as a closing quote is kept), and cut to
/// [`MESSAGE_CHARS`] characters (its first two thirds and last third) when still longer.
/// Short messages come back unchanged and unallocated.
pub fn shorten(msg: &str) -> Cow<'_, str> {
    shorten_to(msg, MESSAGE_CHARS)
}

/// [`shorten`] with a limit of `max_chars` characters in place of [`MESSAGE_CHARS`].
pub fn shorten_to(msg: &str, max_chars: usize) -> Cow<'_, str> {
    let long_run = msg
        .split(char::is_whitespace)
        .any(|w| w.chars().nth(2 * EXCERPT_CHARS).is_some());
    let mut out: Cow<'_, str> = if long_run {
        let mut s = String::with_capacity(MESSAGE_CHARS);
        let mut rest = msg;
        while !rest.is_empty() {
            let ws = rest
                .find(|c: char| !c.is_whitespace())
                .unwrap_or(rest.len());
            s.push_str(&rest[..ws]);
            rest = &rest[ws..];
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            let word = &rest[..end];
            if word.chars().nth(2 * EXCERPT_CHARS).is_some() {
                // keep up to 3 closing characters (quotes, brackets, commas) after the cut
                let tail_start = word
                    .char_indices()
                    .rev()
                    .take(3)
                    .take_while(|(_, c)| !c.is_alphanumeric())
                    .last()
                    .map_or(word.len(), |(i, _)| i);
                s.push_str(&excerpt(&word[..tail_start]));
                s.push_str(&word[tail_start..]);
            } else {
                s.push_str(word);
            }
            rest = &rest[end..];
        }
        Cow::Owned(s)
    } else {
        Cow::Borrowed(msg)
    };
    let n = out.chars().count();
    if n > max_chars {
        let head_chars = 2 * max_chars / 3;
        let tail_chars = max_chars - head_chars;
        let head_end = out
            .char_indices()
            .nth(head_chars)
            .map_or(out.len(), |x| x.0);
        let tail_start = out
            .char_indices()
            .nth(n - tail_chars)
            .map_or(out.len(), |x| x.0);
        out = Cow::Owned(format!(
            "{} [... {} characters left out ...] {}",
            &out[..head_end],
            n - head_chars - tail_chars,
            &out[tail_start..]
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_text_is_unchanged() {
        assert!(matches!(excerpt("abc"), Cow::Borrowed("abc")));
        let m = "unknown variant `rk9`, expected one of `pc4`, `omf32`";
        assert!(matches!(shorten(m), Cow::Borrowed(_)));
    }

    #[test]
    fn a_long_token_is_cut_with_its_length() {
        let t = "x".repeat(1_000_000);
        let e = excerpt(&t);
        assert!(e.len() < 100, "{e}");
        assert!(e.ends_with("... (1000000 bytes)"), "{e}");
        // multi-byte characters are never split
        let u = "é".repeat(100);
        assert!(excerpt(&u).starts_with(&"é".repeat(EXCERPT_CHARS)));
    }

    #[test]
    fn a_message_keeps_its_words_and_valid_names() {
        let m = format!(
            "unknown variant `{}`, expected one of `pc4`, `omf32`",
            "y".repeat(5_000_000)
        );
        let s = shorten(&m);
        assert!(s.len() < 200, "{s}");
        assert!(s.starts_with("unknown variant `yyyy"), "{s}");
        assert!(s.contains("(5000001 bytes)`,"), "{s}");
        assert!(s.ends_with("expected one of `pc4`, `omf32`"), "{s}");
        // an excerpt inside a message is not cut again
        let once = format!("found \"{}\"", excerpt(&"q".repeat(1000)));
        assert_eq!(shorten(&once), once);
    }

    #[test]
    fn a_long_message_of_short_words_keeps_head_and_tail() {
        let m = format!("start {} end", "ab ".repeat(100_000));
        let s = shorten(&m);
        assert!(s.chars().count() < MESSAGE_CHARS + 60, "{}", s.len());
        assert!(s.starts_with("start ab") && s.ends_with("ab  end"), "{s}");
        assert!(s.contains("characters left out"));
    }
}
