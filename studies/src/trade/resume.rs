//! The `resume` block of a partial trade summary: its checksum, written beside it, and reading
//! it back for `trade --resume`, refused unless the two match.

use crate::error::{StudyError, StudyResult};
use entrynav::sim::ShardResult;
use serde_json::Value;

/// The checksum of a `resume` block: `fnv1a64:` and 16 hex digits of FNV-1a 64 over the block's
/// compact JSON, which round-trips exactly (floats are written in their shortest exact form and
/// read back exactly, serde_json's `float_roundtrip`). It catches a hand-edited, corrupt or
/// pasted-in block; it is not a signature against a deliberate forger.
pub fn resume_checksum(block: &ShardResult) -> String {
    let text = serde_json::to_vec(block).unwrap_or_default();
    format!(
        "fnv1a64:{:016x}",
        entrynav::sim::monte_carlo::shard::fnv1a64(text)
    )
}

/// The block sums stored in the partial summary `text`, refused unless they match the
/// `resume_checksum` written beside them (an edited or corrupt block would otherwise move the
/// resumed statistics silently). Messages say what is wrong, without naming the file (the
/// caller adds it).
pub fn read_resume(text: &str) -> StudyResult<ShardResult> {
    let refuse = |m: String| StudyError::Refused(m);
    let mut v: Value = serde_json::from_str(text).map_err(|e| refuse(format!("not JSON: {e}")))?;
    let block = v.get_mut("resume").map(Value::take).ok_or_else(|| {
        refuse("no `resume` block: not the summary of an interrupted trade".into())
    })?;
    let stored = v
        .get("resume_checksum")
        .and_then(Value::as_str)
        .map(str::to_owned);
    let block: ShardResult = serde_json::from_value(block)
        .map_err(|e| refuse(format!("corrupt `resume` block: {e}")))?;
    let Some(stored) = stored else {
        return Err(refuse(
            "the `resume` block has no `resume_checksum` (written by an older entrynav, or \
             edited); run the study again"
                .into(),
        ));
    };
    let actual = resume_checksum(&block);
    if stored != actual {
        return Err(refuse(format!(
            "the `resume` block does not match its checksum (resume_checksum {stored}, block \
             {actual}): it was edited, corrupted or copied from another file; refusing to \
             continue from it"
        )));
    }
    Ok(block)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_is_not_a_partial_summary_is_refused_saying_why() {
        let e = read_resume("{").unwrap_err().to_string();
        assert!(e.starts_with("not JSON"), "{e}");
        let e = read_resume("{\"complete\": true}").unwrap_err().to_string();
        assert!(e.starts_with("no `resume` block"), "{e}");
    }
}
