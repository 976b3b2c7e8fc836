//! The GUID of a table: a hash of its layout version and of every variable, and the date every
//! description of the layout carries.

use super::var::{Value, Var};

/// Version of the table layout and the meaning of its variables (part of the GUID).
/// 2: `bank_angle` also drives the filter's onboard models (MarsEntryNav) and is an input of
/// MarsEntryNavFilter.
/// 3: `allow_external_files`; Enumeration types for `nav_status` and `truth_stop` (with Integer
/// twins `nav_status_code`, `truth_stop_code`); estimate outputs `discrete`; dimensionless units;
/// no input feeds through (`dependencies`).
/// 4: no output is NaN: undefined values (NIS before the first update, NEES without truth, the
/// density estimate of a filter without one, the truth of a state without truth counterpart)
/// read 0.
pub const TABLE_VERSION: u32 = 4;
/// `generationDateAndTime` of every description of [`TABLE_VERSION`]: the description is a pure
/// function of the table, so it carries the table's date and is reproducible byte for byte.
pub const TABLE_DATE: &str = "2026-12-04T00:00:00Z";

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A GUID from a hash of `identifier`, the table version, `extra` (the embedded scenario of a
/// specific FMU) and every variable's reference, name, type, Enumeration type, causality,
/// variability, unit and start value.
pub(crate) fn table_guid(identifier: &str, extra: &str, vars: &[Var]) -> String {
    let mut text = format!("{identifier}|{TABLE_VERSION}|{extra}\n");
    for v in vars {
        let declared = v
            .declared
            .map(|e| {
                let items: Vec<&str> = e.items.iter().map(|i| i.0).collect();
                format!("{}={}", e.name, items.join(","))
            })
            .unwrap_or_default();
        text.push_str(&format!(
            "{}|{}|{}|{}|{}|{}|{}|{}\n",
            v.vr,
            v.name,
            v.ty.xml(),
            declared,
            v.causality.xml(),
            v.variability.xml(),
            v.unit.unwrap_or(""),
            v.start.as_ref().map(Value::xml).unwrap_or_default()
        ));
    }
    let a = fnv1a64(text.as_bytes(), 0);
    let b = fnv1a64(text.as_bytes(), 0x5bd1_e995);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        (a >> 32) as u32,
        (a >> 16) as u16,
        a as u16,
        (b >> 48) as u16,
        b & 0xffff_ffff_ffff
    )
}
