//! [`StepLog`]: the replay log of a run (its [`StepRecord`]s), shared in chunks between an
//! instance and its snapshots.

use crate::vars::Value;
use std::sync::Arc;

/// One successful doStep.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Communication point.
    pub t: f64,
    /// Step size.
    pub h: f64,
    /// Values of the input variables used, in table order (shared with the previous step when
    /// they did not change).
    pub inputs: Arc<[Value]>,
}

/// Steps per shared chunk of a [`StepLog`].
const CHUNK: usize = 4096;

/// Bytes a value takes in the byte format.
fn value_bytes(v: &Value) -> usize {
    match v {
        Value::Real(_) => 9,
        Value::Integer(_) => 5,
        Value::Boolean(_) => 2,
        Value::String(s) => 5 + s.len(),
    }
}

/// The successful steps of a run, in order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepLog {
    chunks: Vec<Arc<[StepRecord]>>,
    tail: Vec<StepRecord>,
    bytes: usize,
}

impl StepLog {
    /// Number of steps.
    pub fn len(&self) -> usize {
        self.chunks.len() * CHUNK + self.tail.len()
    }

    /// Whether there is no step.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes the steps take in the byte format.
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// The last step.
    pub fn last(&self) -> Option<&StepRecord> {
        self.tail
            .last()
            .or_else(|| self.chunks.last().and_then(|c| c.last()))
    }

    /// The steps in order.
    pub fn iter(&self) -> impl Iterator<Item = &StepRecord> {
        self.chunks.iter().flat_map(|c| c.iter()).chain(&self.tail)
    }

    /// Bytes `r` would add to the byte format after the current last step.
    pub fn cost(&self, r: &StepRecord) -> usize {
        let shared = self
            .last()
            .is_some_and(|l| Arc::ptr_eq(&l.inputs, &r.inputs));
        17 + if shared {
            0
        } else {
            r.inputs.iter().map(value_bytes).sum()
        }
    }

    /// Append a step.
    pub fn push(&mut self, r: StepRecord) {
        self.bytes += self.cost(&r);
        self.tail.push(r);
        if self.tail.len() == CHUNK {
            self.chunks.push(Arc::from(std::mem::take(&mut self.tail)));
        }
    }

    /// Remove every step.
    pub fn clear(&mut self) {
        *self = StepLog::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_shares_full_chunks_between_clones() {
        let inputs: Arc<[Value]> = Arc::from(vec![Value::Real(1.0)]);
        let mut log = StepLog::default();
        for k in 0..(2 * CHUNK + 3) {
            let t = k as f64;
            log.push(StepRecord {
                t,
                h: 1.0,
                inputs: Arc::clone(&inputs),
            });
        }
        let copy = log.clone();
        assert!(Arc::ptr_eq(&copy.chunks[1], &log.chunks[1]));
        assert_eq!(copy.len(), 2 * CHUNK + 3);
        assert_eq!(
            copy.iter().nth(CHUNK + 5).map(|r| r.t),
            Some((CHUNK + 5) as f64)
        );
        assert_eq!(log.bytes(), 17 * (2 * CHUNK + 3) + 9);
    }
}
