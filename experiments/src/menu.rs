//! A menu: a closed set of named choices (the codings, the neuron models, the precisions),
//! declared once as an enum that implements [`Menu`]. Its text form — the key a user types on
//! the command line or in Python, and the name in file names and reports — comes from
//! [`Menu::key`]; [`menu_text!`](crate::menu_text) gives the enum `FromStr` and `Display` from it,
//! so a parser (clap in the `neurotac` command, PyO3 in the Python package) never re-declares
//! the list.

use std::fmt;

/// A closed set of named choices.
pub trait Menu: Copy + PartialEq + 'static {
    /// What is chosen, for error messages (`"coding"`, `"neuron model"`).
    const WHAT: &'static str;
    /// Every choice, in the order menus and reports list them.
    const ALL: &'static [Self];
    /// The choice's key: lower case, what a user types (`"spatiotemporal"`, `"lif"`).
    fn key(self) -> &'static str;
}

/// A key that names no choice of a [`Menu`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} '{given}' (expected one of: {expected})")]
pub struct UnknownChoice {
    /// What was being chosen.
    pub what: &'static str,
    /// The key given.
    pub given: String,
    /// The menu's keys, comma-separated.
    pub expected: String,
}

/// The choice of `T` whose key is `key` (exact, lower case).
pub fn choose<T: Menu>(key: &str) -> Result<T, UnknownChoice> {
    T::ALL
        .iter()
        .copied()
        .find(|c| c.key() == key)
        .ok_or_else(|| UnknownChoice {
            what: T::WHAT,
            given: key.to_owned(),
            expected: keys::<T>().join(", "),
        })
}

/// The keys of `T`'s choices, in menu order.
pub fn keys<T: Menu>() -> Vec<&'static str> {
    T::ALL.iter().map(|c| c.key()).collect()
}

/// Writes a choice as its key.
pub fn write_key<T: Menu>(choice: T, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    f.write_str(choice.key())
}

/// Implements `FromStr` (through [`choose`]) and `Display` (the key) for a [`Menu`] type.
#[macro_export]
macro_rules! menu_text {
    ($menu:ty) => {
        impl ::std::str::FromStr for $menu {
            type Err = $crate::menu::UnknownChoice;
            fn from_str(key: &str) -> Result<Self, Self::Err> {
                $crate::menu::choose(key)
            }
        }
        impl ::std::fmt::Display for $menu {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                $crate::menu::write_key(*self, f)
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coding::CodingName;

    #[test]
    fn every_key_parses_back_to_its_choice_and_an_unknown_one_names_the_menu() {
        for &c in CodingName::ALL {
            assert_eq!(c.to_string().parse::<CodingName>(), Ok(c));
        }
        let e = "spatio".parse::<CodingName>().unwrap_err();
        let keys: Vec<&str> = CodingName::ALL.iter().map(|c| c.key()).collect();
        assert_eq!(
            e.to_string(),
            format!(
                "unknown coding 'spatio' (expected one of: {})",
                keys.join(", ")
            )
        );
        assert!(keys.starts_with(&["intensive", "spatial", "temporal", "spatiotemporal"]));
    }
}
