//! The refusal of document type and entity declarations, run on the bytes before any XML
//! parser sees them.
//!
//! FMI model descriptions and SSP descriptions declare no DTD. An internal DTD is what lets a
//! file define entities, and the parsers expand them on reference: ten nested entities of ten
//! references each make a few hundred bytes expand to gigabytes. Refusing the declarations
//! outright means no expansion ever starts, whatever a parser's own limits are.
use crate::Error;

/// Refuses `bytes` if they hold a markup declaration (`<!DOCTYPE`, `<!ENTITY`, `<!ELEMENT`,
/// ...) outside comments and CDATA sections. UTF-8 and the single-byte encodings are read as
/// bytes, UTF-16 (with or without its byte order mark) by code unit: markup delimiters are
/// ASCII in all of them.
pub fn refuse_declarations(bytes: &[u8]) -> Result<(), Error> {
    let text = markup_bytes(bytes);
    let mut at = 0;
    let mut line = 1u64;
    while at < text.len() {
        let rest = &text[at..];
        let skip_to = |end: &[u8], from: usize| {
            find(&rest[from..], end).map(|position| from + position + end.len())
        };
        let skipped = if rest.starts_with(b"<!--") {
            skip_to(b"-->", 4)
        } else if rest.starts_with(b"<![CDATA[") {
            skip_to(b"]]>", 9)
        } else if rest.starts_with(b"<?") {
            skip_to(b"?>", 2)
        } else if rest.starts_with(b"<!") {
            let keyword: String = rest[2..]
                .iter()
                .take_while(|byte| byte.is_ascii_alphabetic())
                .take(16)
                .map(|&byte| char::from(byte))
                .collect();
            return Err(Error::Declaration { line, keyword });
        } else {
            Some(1)
        };
        // An unterminated comment or section is the parser's to report.
        let Some(length) = skipped else {
            return Ok(());
        };
        line += rest[..length].iter().filter(|&&byte| byte == b'\n').count() as u64;
        at += length;
    }
    Ok(())
}

/// The text as one byte per character: ASCII as itself, anything else as 0x80.
fn markup_bytes(bytes: &[u8]) -> std::borrow::Cow<'_, [u8]> {
    let utf16 = match bytes {
        [0xFF, 0xFE, ..] => Some((2, u16::from_le_bytes as fn([u8; 2]) -> u16)),
        [0xFE, 0xFF, ..] => Some((2, u16::from_be_bytes as fn([u8; 2]) -> u16)),
        [b'<', 0, ..] => Some((0, u16::from_le_bytes as fn([u8; 2]) -> u16)),
        [0, b'<', ..] => Some((0, u16::from_be_bytes as fn([u8; 2]) -> u16)),
        _ => None,
    };
    match utf16 {
        None => std::borrow::Cow::Borrowed(bytes),
        Some((skip, decode)) => bytes[skip..]
            .chunks_exact(2)
            .map(|pair| match decode([pair[0], pair[1]]) {
                unit @ 0..0x80 => unit as u8,
                _ => 0x80,
            })
            .collect(),
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack
        .windows(needle.len())
        .position(|window| window == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(text: &[u8]) -> Option<(u64, String)> {
        match refuse_declarations(text) {
            Ok(()) => None,
            Err(Error::Declaration { line, keyword }) => Some((line, keyword)),
            Err(other) => panic!("unexpected {other}"),
        }
    }

    #[test]
    fn a_doctype_is_refused_with_its_line() {
        let text = b"<?xml version=\"1.0\"?>\n<!DOCTYPE x [\n<!ENTITY a \"b\">]>\n<x a=\"&a;\"/>";
        assert_eq!(refused(text), Some((2, "DOCTYPE".to_owned())));
    }

    #[test]
    fn an_entity_declaration_anywhere_is_refused() {
        assert_eq!(
            refused(b"<x>\n\n<!ENTITY a \"b\"></x>"),
            Some((3, "ENTITY".to_owned()))
        );
    }

    #[test]
    fn comments_cdata_and_instructions_may_mention_declarations() {
        let text = b"<?xml version=\"1.0\"?><!-- <!DOCTYPE x> --><?pi <!ENTITY ?>\
                     <x><![CDATA[<!DOCTYPE html>]]></x>";
        assert_eq!(refused(text), None);
    }

    #[test]
    fn utf16_is_read_by_code_unit() {
        for big_endian in [false, true] {
            let text = "\u{feff}<!DOCTYPE x><x/>";
            let bytes: Vec<u8> = text
                .encode_utf16()
                .flat_map(|unit| {
                    if big_endian {
                        unit.to_be_bytes()
                    } else {
                        unit.to_le_bytes()
                    }
                })
                .collect();
            assert_eq!(refused(&bytes), Some((1, "DOCTYPE".to_owned())));
            assert_eq!(refused(&bytes[2..]), Some((1, "DOCTYPE".to_owned())));
        }
    }
}
