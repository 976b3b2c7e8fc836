//! FMU state snapshots and their byte format.
//!
//! A snapshot is a *replay log*: the parameters and inputs, the experiment set-up, the phase, and
//! every successful `fmi2DoStep` so far with the inputs it used. Restoring rebuilds the engine and
//! replays the steps; because the engine is deterministic this reproduces the rest of the run bit
//! for bit.
//!
//! Byte format (little-endian), version [`FORMAT_VERSION`]:
//! `b"ENAVFMUS"`, `u32` version, `u64` total length, `u8` model, `u32`+bytes GUID, `u8` phase,
//! `f64` start time, `u8`+`f64` stop time, `u32` count + tagged values (tag 0 none, 1 real `f64`,
//! 2 integer `i32`, 3 boolean `u8`, 4 string `u32`+UTF-8), `u32` inputs per step, `u64` step count
//! and per step `f64` t, `f64` h and the tagged input values, then an FNV-1a 64 checksum of
//! everything before it. Every length is checked against the remaining bytes before use.

use crate::vars::{Model, Value, fnv1a64};
use thiserror::Error;

/// Why serialized FMU-state bytes cannot be restored.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum StateError {
    /// Not written by this FMU.
    #[error("not an entrynav FMU state (bad magic bytes)")]
    BadMagic,
    /// Another format version.
    #[error(
        "FMU state format version {0} is not supported (this FMU reads version {FORMAT_VERSION})"
    )]
    Version(u32),
    /// The header's length is not the buffer's.
    #[error("FMU state length mismatch: header says {header} bytes, got {actual}")]
    Length {
        /// Length in the header.
        header: u64,
        /// Bytes given.
        actual: usize,
    },
    /// The checksum does not match.
    #[error("FMU state checksum mismatch (corrupted bytes)")]
    Checksum,
    /// The bytes end early.
    #[error("FMU state is truncated")]
    Truncated,
    /// Bytes left after the last field.
    #[error("FMU state has {0} trailing bytes")]
    Trailing(usize),
    /// An unknown value tag.
    #[error("FMU state has an unknown value tag {0}")]
    ValueTag(u8),
    /// A field that cannot be valid.
    #[error("FMU state {0}")]
    Corrupt(&'static str),
}

/// Magic bytes.
pub const MAGIC: &[u8; 8] = b"ENAVFMUS";
/// Format version.
pub const FORMAT_VERSION: u32 = 1;

/// Where the instance was in the FMI state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate / fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// Ready for fmi2DoStep.
    StepComplete,
    /// After fmi2Terminate.
    Terminated,
    /// After an error that needs fmi2Reset, fmi2SetFMUstate or fmi2FreeInstance.
    Error,
}

impl Phase {
    fn code(self) -> u8 {
        match self {
            Phase::Instantiated => 0,
            Phase::InitializationMode => 1,
            Phase::StepComplete => 2,
            Phase::Terminated => 3,
            Phase::Error => 4,
        }
    }

    fn from_code(c: u8) -> Option<Phase> {
        Some(match c {
            0 => Phase::Instantiated,
            1 => Phase::InitializationMode,
            2 => Phase::StepComplete,
            3 => Phase::Terminated,
            4 => Phase::Error,
            _ => return None,
        })
    }
}

/// One successful doStep.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Communication point.
    pub t: f64,
    /// Step size.
    pub h: f64,
    /// Values of the input variables used, in table order.
    pub inputs: Vec<Value>,
}

/// A saved FMU state.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Model.
    pub model: Model,
    /// GUID of the model's table when saved.
    pub guid: String,
    /// Phase.
    pub phase: Phase,
    /// Experiment start time.
    pub start_time: f64,
    /// Experiment stop time, if defined.
    pub stop_time: Option<f64>,
    /// Current value of every variable that has one stored (parameters, inputs), in table order.
    pub values: Vec<Option<Value>>,
    /// Steps so far.
    pub steps: Vec<StepRecord>,
}

fn put_value(out: &mut Vec<u8>, v: Option<&Value>) {
    match v {
        None => out.push(0),
        Some(Value::Real(x)) => {
            out.push(1);
            out.extend_from_slice(&x.to_le_bytes());
        }
        Some(Value::Integer(x)) => {
            out.push(2);
            out.extend_from_slice(&x.to_le_bytes());
        }
        Some(Value::Boolean(x)) => {
            out.push(3);
            out.push(*x as u8);
        }
        Some(Value::String(s)) => {
            out.push(4);
            out.extend_from_slice(&(s.len() as u32).to_le_bytes());
            out.extend_from_slice(s.as_bytes());
        }
    }
}

impl Snapshot {
    /// Serialize.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&0u64.to_le_bytes()); // total length, patched below
        out.push(
            Model::ALL
                .iter()
                .position(|m| *m == self.model)
                .unwrap_or(0) as u8,
        );
        out.extend_from_slice(&(self.guid.len() as u32).to_le_bytes());
        out.extend_from_slice(self.guid.as_bytes());
        out.push(self.phase.code());
        out.extend_from_slice(&self.start_time.to_le_bytes());
        out.push(self.stop_time.is_some() as u8);
        out.extend_from_slice(&self.stop_time.unwrap_or(0.0).to_le_bytes());
        out.extend_from_slice(&(self.values.len() as u32).to_le_bytes());
        for v in &self.values {
            put_value(&mut out, v.as_ref());
        }
        let per_step = self.steps.first().map(|s| s.inputs.len()).unwrap_or(0);
        out.extend_from_slice(&(per_step as u32).to_le_bytes());
        out.extend_from_slice(&(self.steps.len() as u64).to_le_bytes());
        for s in &self.steps {
            out.extend_from_slice(&s.t.to_le_bytes());
            out.extend_from_slice(&s.h.to_le_bytes());
            for v in &s.inputs {
                put_value(&mut out, Some(v));
            }
        }
        let total = (out.len() + 8) as u64;
        out[12..20].copy_from_slice(&total.to_le_bytes());
        let sum = fnv1a64(&out, 0);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Parse and check a serialized state.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, StateError> {
        let mut r = Reader { b: bytes, pos: 0 };
        if r.take(8)? != MAGIC {
            return Err(StateError::BadMagic);
        }
        let version = r.u32()?;
        if version != FORMAT_VERSION {
            return Err(StateError::Version(version));
        }
        let total = r.u64()?;
        if total != bytes.len() as u64 {
            return Err(StateError::Length {
                header: total,
                actual: bytes.len(),
            });
        }
        let body = &bytes[..bytes.len() - 8];
        let mut tail = [0u8; 8];
        tail.copy_from_slice(&bytes[bytes.len() - 8..]);
        if fnv1a64(body, 0) != u64::from_le_bytes(tail) {
            return Err(StateError::Checksum);
        }
        let mut r = Reader {
            b: body,
            pos: r.pos,
        };
        let model = *Model::ALL
            .get(r.u8()? as usize)
            .ok_or(StateError::Corrupt("names an unknown model"))?;
        let n = r.u32()? as usize;
        let guid = String::from_utf8(r.take(n)?.to_vec())
            .map_err(|_| StateError::Corrupt("has a GUID that is not UTF-8"))?;
        let phase = Phase::from_code(r.u8()?).ok_or(StateError::Corrupt("has an unknown phase"))?;
        let start_time = r.f64()?;
        let has_stop = r.u8()? != 0;
        let stop = r.f64()?;
        let nv = r.u32()? as usize;
        if nv > r.remaining() {
            return Err(StateError::Corrupt(
                "has a value count that exceeds its length",
            ));
        }
        let mut values = Vec::with_capacity(nv);
        for _ in 0..nv {
            values.push(r.value()?);
        }
        let per_step = r.u32()? as usize;
        let ns = r.u64()?;
        if ns > (r.remaining() / 16) as u64 {
            return Err(StateError::Corrupt(
                "has a step count that exceeds its length",
            ));
        }
        let mut steps = Vec::with_capacity(ns as usize);
        for _ in 0..ns {
            let t = r.f64()?;
            let h = r.f64()?;
            let mut inputs = Vec::with_capacity(per_step.min(r.remaining()));
            for _ in 0..per_step {
                inputs.push(
                    r.value()?
                        .ok_or(StateError::Corrupt("has a step input without a value"))?,
                );
            }
            steps.push(StepRecord { t, h, inputs });
        }
        if r.remaining() != 0 {
            return Err(StateError::Trailing(r.remaining()));
        }
        Ok(Snapshot {
            model,
            guid,
            phase,
            start_time,
            stop_time: has_stop.then_some(stop),
            values,
            steps,
        })
    }
}

struct Reader<'a> {
    b: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn remaining(&self) -> usize {
        self.b.len() - self.pos
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], StateError> {
        if n > self.remaining() {
            return Err(StateError::Truncated);
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn array<const K: usize>(&mut self) -> Result<[u8; K], StateError> {
        let mut a = [0u8; K];
        a.copy_from_slice(self.take(K)?);
        Ok(a)
    }

    fn u8(&mut self) -> Result<u8, StateError> {
        Ok(self.take(1)?[0])
    }

    fn u32(&mut self) -> Result<u32, StateError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    fn u64(&mut self) -> Result<u64, StateError> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    fn f64(&mut self) -> Result<f64, StateError> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    fn value(&mut self) -> Result<Option<Value>, StateError> {
        Ok(match self.u8()? {
            0 => None,
            1 => Some(Value::Real(self.f64()?)),
            2 => Some(Value::Integer(i32::from_le_bytes(self.array()?))),
            3 => Some(Value::Boolean(self.u8()? != 0)),
            4 => {
                let n = self.u32()? as usize;
                let s = String::from_utf8(self.take(n)?.to_vec())
                    .map_err(|_| StateError::Corrupt("has a string that is not UTF-8"))?;
                Some(Value::String(s))
            }
            t => return Err(StateError::ValueTag(t)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Snapshot {
        Snapshot {
            model: Model::Filter,
            guid: "{abc}".into(),
            phase: Phase::StepComplete,
            start_time: 0.0,
            stop_time: Some(300.0),
            values: vec![
                Some(Value::String("four-beacon-fusion".into())),
                Some(Value::Integer(-3)),
                None,
                Some(Value::Boolean(true)),
                Some(Value::Real(f64::NAN)),
            ],
            steps: vec![
                StepRecord {
                    t: 0.0,
                    h: 1.0,
                    inputs: vec![Value::Real(0.5), Value::Boolean(false)],
                },
                StepRecord {
                    t: 1.0,
                    h: 0.25,
                    inputs: vec![Value::Real(-0.5), Value::Boolean(true)],
                },
            ],
        }
    }

    #[test]
    fn round_trip_and_every_corruption_rejected() {
        let s = sample();
        let bytes = s.to_bytes();
        let back = Snapshot::from_bytes(&bytes).unwrap();
        assert_eq!(back.to_bytes(), bytes);
        assert_eq!(back.steps, s.steps);
        for n in 0..bytes.len() {
            assert!(
                Snapshot::from_bytes(&bytes[..n]).is_err(),
                "truncated to {n}"
            );
        }
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x40;
            assert!(Snapshot::from_bytes(&b).is_err(), "byte {i} flipped");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(Snapshot::from_bytes(&longer).is_err());
    }
}
