//! Which model a packed shared library serves: the *binding*.
//!
//! One build of the library serves every model, but each `.fmu` must accept only its own model's
//! GUID. The library therefore carries a fixed block of data, [`BINDING`], which `entrynav fmu
//! pack` fills in each packed copy ([`patch`]) with the model identifier, the GUID and, for a
//! scenario-specific FMU, the embedded scenario's file name and default filter. At
//! `fmi2Instantiate` the library reads its block: a bound library accepts only the bound GUID;
//! the unbound library of a plain `cargo build` (never shipped) serves the five generic models,
//! which is how the in-process tests and `entrynav fmu run` use it.
//!
//! The block is immutable data (read with a volatile load, so the compiler cannot assume its
//! initial contents); patching it changes no code and keeps the library's layout.

use crate::vars::Model;
use thiserror::Error;

/// Bytes of binding data the block can hold.
pub const BINDING_CAPACITY: usize = 496;

/// The binding block as laid out in the library: 16 magic bytes, the data length (little-endian
/// `u32`, 0 when unbound) and the data (`key=value` lines).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct BindingBlock {
    /// The magic bytes `entrynav:bind:v1`.
    pub magic: [u8; 16],
    /// Length of `data` in use.
    pub len: [u8; 4],
    /// `key=value\n` lines.
    pub data: [u8; BINDING_CAPACITY],
}

/// The library's binding block (unbound until `entrynav fmu pack` patches a copy).
#[used]
pub static BINDING: BindingBlock = BindingBlock {
    magic: *b"entrynav:bind:v1",
    len: [0; 4],
    data: [0; BINDING_CAPACITY],
};

/// The magic bytes, kept reversed in code so that only [`BINDING`] holds them in order and a
/// library has exactly one copy to find.
fn magic() -> [u8; 16] {
    let mut m = *b"1v:dnib:vanyrtne";
    m.reverse();
    m
}

/// Why a binding cannot be read or written.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BindingError {
    /// No binding block in the library.
    #[error("the library has no binding block (not an entrynav FMU library)")]
    NoBlock,
    /// More than one block.
    #[error("the library has {0} binding blocks; expected exactly one")]
    Blocks(usize),
    /// The data does not fit the block.
    #[error("the binding is {0} bytes; the block holds {BINDING_CAPACITY}")]
    TooLong(usize),
    /// The block's data is not a binding.
    #[error("the binding block is corrupt: {0}")]
    Corrupt(&'static str),
}

/// What a packed library serves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Binding {
    /// Model identifier (the library's file stem in its `.fmu`).
    pub identifier: String,
    /// The generic model, or the base of a specific one.
    pub base: Model,
    /// The only GUID it accepts.
    pub guid: String,
    /// A specific FMU's embedded scenario file in `resources/`, and its default filter.
    pub scenario: Option<(String, String)>,
}

impl Binding {
    /// The block's data.
    pub fn encode(&self) -> Vec<u8> {
        let mut s = format!(
            "model={}\nbase={}\nguid={}\n",
            self.identifier,
            self.base.identifier(),
            self.guid
        );
        if let Some((file, filter)) = &self.scenario {
            s.push_str(&format!("scenario={file}\nfilter={filter}\n"));
        }
        s.into_bytes()
    }

    /// Read a block's length and data: `None` when unbound.
    pub fn decode(len: [u8; 4], data: &[u8]) -> Result<Option<Binding>, BindingError> {
        let n = u32::from_le_bytes(len) as usize;
        if n == 0 {
            return Ok(None);
        }
        let bytes = data
            .get(..n)
            .ok_or(BindingError::Corrupt("length past the block"))?;
        let text = std::str::from_utf8(bytes).map_err(|_| BindingError::Corrupt("not UTF-8"))?;
        let field = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
                .map(str::to_string)
        };
        let identifier = field("model").ok_or(BindingError::Corrupt("no model"))?;
        let base = field("base")
            .and_then(|b| Model::from_identifier(&b))
            .ok_or(BindingError::Corrupt("no known base model"))?;
        let guid = field("guid").ok_or(BindingError::Corrupt("no GUID"))?;
        let scenario = match (field("scenario"), field("filter")) {
            (Some(s), Some(f)) => Some((s, f)),
            (None, None) => None,
            _ => return Err(BindingError::Corrupt("a scenario without a filter")),
        };
        Ok(Some(Binding {
            identifier,
            base,
            guid,
            scenario,
        }))
    }
}

/// Offsets of the binding blocks in a library's bytes.
fn blocks(so: &[u8]) -> Vec<usize> {
    let m = magic();
    so.windows(m.len())
        .enumerate()
        .filter(|(_, w)| *w == m)
        .map(|(i, _)| i)
        .collect()
}

fn the_block(so: &[u8]) -> Result<usize, BindingError> {
    match blocks(so).as_slice() {
        [] => Err(BindingError::NoBlock),
        [one] if one + std::mem::size_of::<BindingBlock>() <= so.len() => Ok(*one),
        [_] => Err(BindingError::Corrupt("the block is cut off")),
        many => Err(BindingError::Blocks(many.len())),
    }
}

/// A copy of the library `so` bound to `b`.
pub fn patch(so: &[u8], b: &Binding) -> Result<Vec<u8>, BindingError> {
    let at = the_block(so)?;
    let data = b.encode();
    if data.len() > BINDING_CAPACITY {
        return Err(BindingError::TooLong(data.len()));
    }
    let mut out = so.to_vec();
    let len_at = at + 16;
    out[len_at..len_at + 4].copy_from_slice(&(data.len() as u32).to_le_bytes());
    let data_at = len_at + 4;
    out[data_at..data_at + BINDING_CAPACITY].fill(0);
    out[data_at..data_at + data.len()].copy_from_slice(&data);
    Ok(out)
}

/// The binding of the library bytes `so` (`None`: unbound).
pub fn read_library(so: &[u8]) -> Result<Option<Binding>, BindingError> {
    let at = the_block(so)?;
    let mut len = [0u8; 4];
    len.copy_from_slice(&so[at + 16..at + 20]);
    Binding::decode(len, &so[at + 20..at + 20 + BINDING_CAPACITY])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patch_and_read_round_trip() {
        let mut lib = vec![7u8; 100];
        lib.extend_from_slice(&magic());
        lib.extend_from_slice(&[0u8; 4 + BINDING_CAPACITY]);
        lib.extend_from_slice(&[9u8; 50]);
        assert_eq!(read_library(&lib), Ok(None));
        let b = Binding {
            identifier: "MarsEntryNav_msl_airdata".into(),
            base: Model::Combined,
            guid: "{1234}".into(),
            scenario: Some(("msl-airdata.toml".into(), "ukf".into())),
        };
        let bound = patch(&lib, &b).unwrap();
        assert_eq!(bound.len(), lib.len());
        assert_eq!(read_library(&bound), Ok(Some(b.clone())));
        let again = patch(
            &bound,
            &Binding {
                scenario: None,
                ..b.clone()
            },
        )
        .unwrap();
        assert_eq!(read_library(&again).unwrap().unwrap().scenario, None);
        assert_eq!(read_library(&lib[..90]), Err(BindingError::NoBlock));
        let mut two = lib.clone();
        two.extend_from_slice(&lib);
        assert_eq!(patch(&two, &b), Err(BindingError::Blocks(2)));
        assert_eq!(BINDING.magic, magic());
    }
}
