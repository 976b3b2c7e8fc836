//! The byte format of a [`Snapshot`] (see [`super`]).

use super::log::{StepLog, StepRecord};
use super::{FORMAT_VERSION, MAGIC, Phase, Snapshot, StateError};
use crate::limits::MAX_STATE_BYTES;
use crate::vars::{Model, Value, fnv1a64};
use std::sync::Arc;

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
        let per_step = self
            .steps
            .iter()
            .next()
            .map(|s| s.inputs.len())
            .unwrap_or(0);
        out.extend_from_slice(&(per_step as u32).to_le_bytes());
        out.extend_from_slice(&(self.steps.len() as u64).to_le_bytes());
        let mut previous: Option<&Arc<[Value]>> = None;
        for s in self.steps.iter() {
            out.extend_from_slice(&s.t.to_le_bytes());
            out.extend_from_slice(&s.h.to_le_bytes());
            if previous.is_some_and(|p| Arc::ptr_eq(p, &s.inputs)) {
                out.push(0);
            } else {
                out.push(1);
                for v in s.inputs.iter() {
                    put_value(&mut out, Some(v));
                }
            }
            previous = Some(&s.inputs);
        }
        let total = (out.len() + 8) as u64;
        out[12..20].copy_from_slice(&total.to_le_bytes());
        let sum = fnv1a64(&out, 0);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Parse and check a serialized state.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, StateError> {
        if bytes.len() > MAX_STATE_BYTES {
            return Err(StateError::TooLarge(bytes.len()));
        }
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
        if ns > (r.remaining() / 17) as u64 {
            return Err(StateError::Corrupt(
                "has a step count that exceeds its length",
            ));
        }
        let mut steps = StepLog::default();
        let mut previous: Option<Arc<[Value]>> = None;
        for _ in 0..ns {
            let t = r.f64()?;
            let h = r.f64()?;
            let inputs = match (r.u8()?, &previous) {
                (0, Some(p)) => Arc::clone(p),
                (0, None) => {
                    return Err(StateError::Corrupt(
                        "has a first step that refers to previous inputs",
                    ));
                }
                (1, _) => {
                    let mut inputs = Vec::with_capacity(per_step.min(r.remaining()));
                    for _ in 0..per_step {
                        inputs.push(
                            r.value()?
                                .ok_or(StateError::Corrupt("has a step input without a value"))?,
                        );
                    }
                    Arc::from(inputs)
                }
                _ => return Err(StateError::Corrupt("has an unknown step-input flag")),
            };
            previous = Some(Arc::clone(&inputs));
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
            steps: {
                let a: Arc<[Value]> = Arc::from(vec![Value::Real(0.5), Value::Boolean(false)]);
                let b: Arc<[Value]> = Arc::from(vec![Value::Real(-0.5), Value::Boolean(true)]);
                let mut log = StepLog::default();
                for (t, h, inputs) in [(0.0, 1.0, &a), (1.0, 0.25, &b), (1.25, 0.25, &b)] {
                    log.push(StepRecord {
                        t,
                        h,
                        inputs: Arc::clone(inputs),
                    });
                }
                log
            },
        }
    }

    #[test]
    fn round_trip_and_every_corruption_rejected() {
        let s = sample();
        let bytes = s.to_bytes();
        let back = Snapshot::from_bytes(&bytes).unwrap();
        assert_eq!(back.to_bytes(), bytes);
        assert_eq!(back.steps, s.steps);
        // The third step shares the second's inputs, in memory and in the bytes.
        let steps: Vec<_> = back.steps.iter().collect();
        assert!(Arc::ptr_eq(&steps[1].inputs, &steps[2].inputs));
        assert_eq!(s.steps.bytes(), 17 * 3 + 2 * (9 + 2));
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
        let huge = vec![0u8; MAX_STATE_BYTES + 1];
        assert_eq!(
            Snapshot::from_bytes(&huge),
            Err(StateError::TooLarge(MAX_STATE_BYTES + 1))
        );
    }
}
