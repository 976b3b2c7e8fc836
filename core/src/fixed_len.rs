//! Fixed-length arrays read from scenario and network files, exactly: `[x, y, z]` with 2 or 4
//! numbers is an error naming the length, never cut or padded. (serde's own `[f64; N]` stops
//! reading after N elements outside a tagged enum, so `velocity_mps = [1, 2, 3, 4]` would
//! silently become `[1, 2, 3]`.)
//!
//! Use as `#[serde(with = "crate::fixed_len::array")]` on a `[f64; N]` field and
//! `#[serde(default, with = "crate::fixed_len::option_array")]` on an `Option<[f64; N]>`.

use serde::de::{Error, Expected};
use std::fmt;

/// "exactly N numbers", for the error message.
struct Exactly(usize);

impl Expected for Exactly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "exactly {} numbers", self.0)
    }
}

fn exactly<E: Error, const N: usize>(v: Vec<f64>) -> Result<[f64; N], E> {
    <[f64; N]>::try_from(v.as_slice()).map_err(|_| E::invalid_length(v.len(), &Exactly(N)))
}

/// A `[f64; N]` field.
pub mod array {
    use super::exactly;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Read exactly `N` numbers.
    pub fn deserialize<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<[f64; N], D::Error> {
        exactly(Vec::<f64>::deserialize(d)?)
    }

    /// Write the numbers.
    pub fn serialize<S: Serializer, const N: usize>(v: &[f64; N], s: S) -> Result<S::Ok, S::Error> {
        v.as_slice().serialize(s)
    }
}

/// An `Option<[f64; N]>` field.
pub mod option_array {
    use super::exactly;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Read exactly `N` numbers when present.
    pub fn deserialize<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<[f64; N]>, D::Error> {
        Option::<Vec<f64>>::deserialize(d)?.map(exactly).transpose()
    }

    /// Write the numbers when present.
    pub fn serialize<S: Serializer, const N: usize>(
        v: &Option<[f64; N]>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        v.as_ref().map(|a| a.as_slice()).serialize(s)
    }
}

#[cfg(test)]
mod tests {
    #[derive(Debug, serde::Deserialize, serde::Serialize, PartialEq)]
    struct S {
        #[serde(with = "super::array")]
        v: [f64; 3],
        #[serde(default, with = "super::option_array")]
        o: Option<[f64; 2]>,
    }

    #[test]
    fn exactly_n_numbers_are_read_and_written_and_any_other_count_is_refused() {
        let s: S = toml::from_str("v = [1.0, 2.0, 3.0]\no = [4.0, 5.0]").unwrap();
        assert_eq!((s.v, s.o), ([1.0, 2.0, 3.0], Some([4.0, 5.0])));
        assert_eq!(
            toml::from_str::<S>(&toml::to_string(&s).unwrap()).unwrap(),
            s
        );
        let none: S = toml::from_str("v = [1.0, 2.0, 3.0]").unwrap();
        assert_eq!(none.o, None);
        for bad in [
            "v = [1.0, 2.0, 3.0, 4.0]",
            "v = [1.0, 2.0]",
            "v = [1.0, 2.0, 3.0]\no = [1.0]",
        ] {
            let err = toml::from_str::<S>(bad).unwrap_err().to_string();
            assert!(
                err.contains("invalid length") && err.contains("exactly"),
                "{err}"
            );
        }
    }
}
