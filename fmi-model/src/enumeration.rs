//! Enumerations come from Rust enums: the enum implements [`Enumeration`] once, and every
//! layer reads its items (names, values, descriptions) from there.

/// One item of an enumeration type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EnumItem {
    pub name: &'static str,
    pub value: i32,
    pub description: &'static str,
}

/// An enumeration type as a layer writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EnumType {
    /// Type name in the model description, e.g. `ControlLaw`.
    pub name: &'static str,
    pub description: &'static str,
    pub items: &'static [EnumItem],
}

impl EnumType {
    pub fn item(&self, value: i32) -> Option<&EnumItem> {
        self.items.iter().find(|i| i.value == value)
    }

    /// `"1 coupled, 2 decoupled, 3 reduced"`: the values for a description.
    pub fn listing(&self) -> String {
        let items: Vec<String> = self
            .items
            .iter()
            .map(|i| format!("{} {}", i.value, i.name))
            .collect();
        items.join(", ")
    }

    pub fn min(&self) -> Option<i32> {
        self.items.iter().map(|i| i.value).min()
    }

    pub fn max(&self) -> Option<i32> {
        self.items.iter().map(|i| i.value).max()
    }
}

/// A Rust enum exchanged as an FMI enumeration.
pub trait Enumeration: Copy + Sized + 'static {
    const TYPE: &'static EnumType;

    /// The FMI value of `self`.
    fn value(self) -> i32;

    /// The enum of an FMI value, `None` if it is no item.
    fn from_value(value: i32) -> Option<Self>;
}

/// What a field holding an enumeration can be: the Rust enum itself, or its raw `i32` value
/// (for a model that validates the value later and names it in its error).
pub trait EnumValue<E: Enumeration> {
    fn to_value(&self) -> i32;
    /// Called by the layer only with a value that is an item of `E::TYPE`.
    fn set_value(&mut self, value: i32);
}

impl<E: Enumeration> EnumValue<E> for E {
    fn to_value(&self) -> i32 {
        self.value()
    }

    fn set_value(&mut self, value: i32) {
        if let Some(e) = E::from_value(value) {
            *self = e;
        }
    }
}

impl<E: Enumeration> EnumValue<E> for i32 {
    fn to_value(&self) -> i32 {
        *self
    }

    fn set_value(&mut self, value: i32) {
        *self = value;
    }
}

/// Implements [`Enumeration`] for a fieldless Rust enum with explicit discriminants, its
/// items written once:
///
/// ```text
/// fmi_model::enumeration! {
///     ControlLaw = "ControlLaw", "Attitude control law" {
///         Coupled: "coupled", "classical quaternion PD on q_ref";
///         Decoupled: "decoupled", "decoupled thrust-axis control (the paper)";
///     }
/// }
/// ```
/// The FMI value of an item is the enum's discriminant.
#[macro_export]
macro_rules! enumeration {
    ($enum:ty = $type_name:literal, $description:literal {
        $($variant:ident : $name:literal, $item_description:literal;)+
    }) => {
        impl $crate::Enumeration for $enum {
            const TYPE: &'static $crate::EnumType = &$crate::EnumType {
                name: $type_name,
                description: $description,
                items: &[$($crate::EnumItem {
                    name: $name,
                    value: <$enum>::$variant as i32,
                    description: $item_description,
                },)+],
            };

            fn value(self) -> i32 {
                self as i32
            }

            fn from_value(value: i32) -> Option<Self> {
                [$(<$enum>::$variant,)+].into_iter().find(|item| *item as i32 == value)
            }
        }
    };
}
