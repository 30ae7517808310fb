//! The keys a `#[derive(Deserialize)]` struct accepts, as serde itself lists them: what a
//! test compares the scenario documentation with, so that the two cannot drift apart.
use serde::de::{self, Deserialize, Deserializer, Visitor};

/// The field names (after `rename`) of the struct `T` deserializes as; empty for a type that
/// is not a struct.
pub fn of<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
    let mut fields = None;
    // The capturing deserializer always fails: only the names it was shown are wanted.
    let _ = T::deserialize(Capture(&mut fields));
    fields.unwrap_or(&[])
}

struct Capture<'a>(&'a mut Option<&'static [&'static str]>);

impl<'de> Deserializer<'de> for Capture<'_> {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not a struct"))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Self::Error> {
        *self.0 = Some(fields);
        Err(de::Error::custom("fields captured"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

#[cfg(test)]
mod tests {
    #[derive(serde::Deserialize)]
    #[allow(dead_code)]
    struct Sample {
        a: f64,
        #[serde(rename = "instance")]
        instances: Vec<String>,
    }

    #[test]
    fn a_struct_lists_its_keys_as_written_in_toml() {
        assert_eq!(super::of::<Sample>(), ["a", "instance"]);
        assert!(super::of::<f64>().is_empty());
    }
}
