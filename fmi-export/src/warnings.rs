//! A model's warnings as a master's user reads them: each kind once, with the time it first
//! came, and at termination how often it came.
//!
//! A model that finds the same fault at every sample (a quaternion of norm 2, a zero mass)
//! says so at every sample, tens of thousands of times a flight: the first line is the one
//! that helps, the rest bury it and every other message. Two warnings are of one kind when
//! they differ only in their numbers (a time, a norm, a mass), so that no model needs to
//! know it is being summarised.

/// Distinct kinds remembered; beyond this many a new kind is logged every time (a model
/// whose every warning is new has nothing to summarise, and the memory stays bounded).
const MAX_KINDS: usize = 64;

/// One kind of warning: the first message as it was logged, when it came, and how often.
#[derive(Debug, Clone, PartialEq)]
pub struct Repeated {
    pub shape: String,
    pub first_message: String,
    pub first_time: f64,
    pub last_time: f64,
    pub count: u64,
}

/// The warnings of one run (from instantiation or reset to termination).
#[derive(Debug, Clone, Default)]
pub struct WarningTally {
    kinds: Vec<Repeated>,
}

impl WarningTally {
    /// Counts `message`, given at `time_s`; `true` when it is the first of its kind (to be
    /// logged), `false` for a repeat (counted only).
    pub fn first_of_its_kind(&mut self, message: &str, time_s: f64) -> bool {
        let shape = shape(message);
        if let Some(kind) = self.kinds.iter_mut().find(|k| k.shape == shape) {
            kind.count += 1;
            kind.last_time = time_s;
            return false;
        }
        if self.kinds.len() < MAX_KINDS {
            self.kinds.push(Repeated {
                shape,
                first_message: message.to_string(),
                first_time: time_s,
                last_time: time_s,
                count: 1,
            });
        }
        true
    }

    /// The kinds that came more than once, in the order they first came.
    pub fn repeated(&self) -> impl Iterator<Item = &Repeated> {
        self.kinds.iter().filter(|k| k.count > 1)
    }

    pub fn clear(&mut self) {
        self.kinds.clear();
    }
}

/// `message` with every number replaced by `#`: the kind of a warning.
pub fn shape(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let chars: Vec<char> = message.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let starts_number = c.is_ascii_digit()
            || (matches!(c, '-' | '+' | '.')
                && chars.get(i + 1).is_some_and(|n| n.is_ascii_digit())
                && (i == 0 || !chars[i - 1].is_alphanumeric()));
        if !starts_number {
            out.push(c);
            i += 1;
            continue;
        }
        i += 1;
        while i < chars.len() {
            let c = chars[i];
            let exponent = matches!(c, 'e' | 'E')
                && chars.get(i + 1).is_some_and(|n| {
                    n.is_ascii_digit()
                        || (matches!(n, '-' | '+')
                            && chars.get(i + 2).is_some_and(|d| d.is_ascii_digit()))
                });
            let sign_of_exponent = matches!(c, '-' | '+') && matches!(chars[i - 1], 'e' | 'E');
            // A full stop that ends a sentence after a number is not part of it.
            let decimal_point = c == '.' && chars.get(i + 1).is_some_and(|n| n.is_ascii_digit());
            if c.is_ascii_digit() || exponent || sign_of_exponent || decimal_point {
                i += 1;
            } else {
                break;
            }
        }
        out.push('#');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_masked_words_are_kept() {
        assert_eq!(
            shape("t = 12.34 s: q_body_to_nue has norm 2e0, not 1; used normalised."),
            "t = # s: q_body_to_nue has norm #, not #; used normalised."
        );
        assert_eq!(shape("mass = -1.5e-3 kg at t=7"), "mass = # kg at t=#");
        // Digits inside a name belong to the name's kind too, which keeps r_nue[1] and
        // r_nue[2] one kind: a warning about each element is the same advice.
        assert_eq!(shape("r_nue[2] is 3"), "r_nue[#] is #");
        assert_eq!(shape("a2b"), "a#b");
    }

    #[test]
    fn a_repeat_is_counted_not_logged_and_kinds_stay_apart() {
        let mut tally = WarningTally::default();
        assert!(tally.first_of_its_kind("t = 0 s: norm 2", 0.0));
        assert!(!tally.first_of_its_kind("t = 0.01 s: norm 2.5", 0.01));
        assert!(tally.first_of_its_kind("t = 0.02 s: mass = 0 kg", 0.02));
        assert!(!tally.first_of_its_kind("t = 0.03 s: norm 3", 0.03));
        let repeated: Vec<_> = tally.repeated().collect();
        assert_eq!(repeated.len(), 1);
        assert_eq!(repeated[0].count, 3);
        assert_eq!(repeated[0].first_message, "t = 0 s: norm 2");
        assert_eq!((repeated[0].first_time, repeated[0].last_time), (0.0, 0.03));
        tally.clear();
        assert!(tally.first_of_its_kind("t = 1 s: norm 2", 1.0));
    }

    #[test]
    fn memory_is_bounded_and_new_kinds_beyond_it_are_logged() {
        let mut tally = WarningTally::default();
        let words =
            |k: usize| format!("kind {}", char::from(b'a' + (k % 26) as u8)).repeat(k / 26 + 1);
        for k in 0..MAX_KINDS + 10 {
            assert!(tally.first_of_its_kind(&words(k), 0.0), "{k}");
        }
        assert_eq!(tally.kinds.len(), MAX_KINDS);
    }
}
