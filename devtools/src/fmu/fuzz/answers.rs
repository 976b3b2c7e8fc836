//! The check of every answer: its status against what the model expects, and every message the
//! instance logged for it (non-empty, in the version's terms, disclosing no host file).

use super::fuzzer::{Fuzzer, Version};
use super::model::{Expect, Sim};
use anyhow::{Result, ensure};
use entrynav_fmi_host::{FmiInstance, Message};

impl<V: Version> Fuzzer<V> {
    /// Check a call's status against `expect`, and the messages it logged: an error comes with a
    /// logged reason, anything else with no error logged.
    pub(super) fn expect(
        &mut self,
        s: &V::Instance,
        op: &str,
        sim: &Sim,
        expect: Expect,
        status: i32,
    ) -> Result<()> {
        self.stats.calls += 1;
        self.stats.statuses[status.clamp(0, 4) as usize] += 1;
        let msgs = s.take_messages();
        ensure!(
            expect.accepts(status),
            "{op} in state {:?} (t = {}) answered {status}, expected {expect:?}; log: {msgs:?}",
            sim.st,
            sim.time
        );
        self.messages(op, &msgs)?;
        ensure!(
            status != 3 || msgs.iter().any(|m| m.status == 3),
            "{op} answered {}Error without logging a reason",
            <V::Instance as FmiInstance>::PREFIX
        );
        ensure!(
            status >= 3 || msgs.iter().all(|m| m.status < 3),
            "{op} answered {status} but logged an error: {msgs:?}"
        );
        match expect {
            Expect::Refused => self.stats.refused += 1,
            Expect::Fails => self.stats.failed += 1,
            _ => {}
        }
        Ok(())
    }

    /// Every message non-empty, with a status and a category, in the version's terms (no name
    /// of the other version; every name of this one it uses exists) and disclosing no host file.
    pub(super) fn messages(&mut self, op: &str, msgs: &[Message]) -> Result<()> {
        let prefix = <V::Instance as FmiInstance>::PREFIX;
        for Message {
            status,
            category,
            text: m,
        } in msgs
        {
            ensure!(!m.trim().is_empty(), "{op}: an empty log message");
            ensure!(
                (0..=4).contains(status) && !category.trim().is_empty(),
                "{op}: status {status}, category '{category}': {m}"
            );
            ensure!(
                !m.to_ascii_lowercase().contains(V::OTHER_PREFIX),
                "{op}: a log message in the terms of another FMI version: {m}"
            );
            ensure!(
                !m.contains("root:x:"),
                "{op}: a log message discloses a host file: {m}"
            );
            for (i, _) in m.match_indices(prefix) {
                let name: String = m[i..]
                    .chars()
                    .take_while(char::is_ascii_alphanumeric)
                    .collect();
                ensure!(
                    self.names.contains(name.as_str()),
                    "{op}: a log message names {name}, which is no {prefix} function or type: {m}"
                );
            }
            self.stats.messages += 1;
        }
        Ok(())
    }
}
