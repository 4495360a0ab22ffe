//! The XML MuJoCo's parser (TinyXML2) accepts and a strict one refuses, made strict: a comment
//! holding `--` (MyoSuite's `<!-- a -- b -->`) and attributes with no space between them
//! (`name="a"type="box"`). Lines and the other characters stay where they were.

use std::borrow::Cow;

/// `text` with what only TinyXML2 accepts mended: `--` inside a comment becomes `- `, and a space
/// goes between an attribute's closing quote and the next attribute's name.
pub fn mend(text: &str) -> Cow<'_, str> {
    let mut changed = false;
    let mut out = String::with_capacity(text.len() + 16);
    let mut rest = text;
    while let Some(lt) = rest.find('<') {
        out.push_str(&rest[..lt]);
        rest = &rest[lt..];
        if let Some(body) = rest.strip_prefix("<!--") {
            let end = body.find("-->").map_or(body.len(), |e| e);
            out.push_str("<!--");
            changed |= body[..end].contains("--");
            out.push_str(&body[..end].replace("--", "- "));
            rest = &body[end..];
            continue;
        }
        if rest.starts_with("<!") || rest.starts_with("<?") {
            let end = rest.find('>').map_or(rest.len(), |e| e + 1);
            out.push_str(&rest[..end]);
            rest = &rest[end..];
            continue;
        }
        // a tag: copy to its '>', quoted values whole, a space after a value that a name follows
        let mut quote = None;
        let mut end = rest.len();
        let mut chars = rest.char_indices().peekable();
        while let Some((i, c)) = chars.next() {
            out.push(c);
            match quote {
                Some(q) if c == q => {
                    quote = None;
                    if chars.peek().is_some_and(|&(_, n)| n.is_alphabetic() || n == '_') {
                        out.push(' ');
                        changed = true;
                    }
                }
                Some(_) => {}
                None if c == '"' || c == '\'' => quote = Some(c),
                None if c == '>' => {
                    end = i + 1;
                    break;
                }
                None => {}
            }
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    if changed { Cow::Owned(out) } else { Cow::Borrowed(text) }
}

#[cfg(test)]
mod tests {
    use super::mend;

    #[test]
    fn mends_what_tinyxml_accepts_and_leaves_the_rest() {
        let text = "<mujoco>\n<!-- a -- b -->\n<geom name=\"a\"type=\"box\" size='1'rgba=\"1 1 1 1\"/>\n<text>\"quoted\"word</text></mujoco>";
        let mended = mend(text);
        assert_eq!(mended, "<mujoco>\n<!-- a -  b -->\n<geom name=\"a\" type=\"box\" size='1' rgba=\"1 1 1 1\"/>\n<text>\"quoted\"word</text></mujoco>");
        assert!(roxmltree::Document::parse(&mended).is_ok());
        let clean = "<mujoco><geom name=\"a\" type=\"box\"/></mujoco>";
        assert!(matches!(mend(clean), std::borrow::Cow::Borrowed(_)));
    }
}
