//! The keyword arguments each study function takes: the field names of its options struct, read
//! from the struct's own `Deserialize` (the names serde accepts are exactly the keywords
//! [`crate::options`] lets through). The Python package's option walk
//! (`tests/python/test_option_walk.py`) probes every one of them.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde::de::{self, DeserializeOwned, Visitor};

/// A deserializer that only records the field list a struct asks for, then stops.
struct FieldNames(Option<&'static [&'static str]>);

impl<'de> de::Deserializer<'de> for &mut FieldNames {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not a struct"))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Self::Error> {
        self.0 = Some(fields);
        Err(de::Error::custom("fields recorded"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

/// The field names of the options struct `T`.
fn fields<T: DeserializeOwned>() -> Vec<&'static str> {
    let mut d = FieldNames(None);
    let _ = T::deserialize(&mut d);
    d.0.unwrap_or_default().to_vec()
}

/// The keyword arguments the native study function `function` takes (`trade`, `optimize_select`,
/// …), as its options struct names them.
#[pyfunction]
pub fn keywords(function: &str) -> PyResult<Vec<&'static str>> {
    use entrynav_studies as st;
    Ok(match function {
        "trade" | "trade_shard" => fields::<st::trade::TradeOptions>(),
        "tune" => fields::<st::tune::TuneStudyOptions>(),
        "observe" => fields::<st::observe::ObserveOptions>(),
        "deliver" => fields::<st::guidance::DeliverOptions>(),
        "simulate" => fields::<st::simulate::SimulateOptions>(),
        "optimize_ground" => fields::<st::design::GroundOptions>(),
        "optimize_select" => fields::<st::design::SelectOptions>(),
        "optimize_orbiters" => fields::<st::design::OrbiterOptions>(),
        "fmu_pack" => fields::<st::fmu_pack::PackOptions>(),
        other => {
            return Err(PyValueError::new_err(format!(
                "function = '{other}' is unknown: must be one of trade, trade_shard, tune, \
                 observe, deliver, simulate, optimize_ground, optimize_select, \
                 optimize_orbiters, fmu_pack"
            )));
        }
    })
}
