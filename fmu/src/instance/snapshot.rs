//! FMU states of an instance: a snapshot is a replay log, restored by rebuilding the engine and
//! replaying the steps (see [`crate::state`]).

use super::allowed::Operation;
use super::machine::Instance;
use super::status::Status;
use crate::limits::MAX_STATE_BYTES;
use crate::state::{Phase::*, Snapshot};
use crate::vars::Value;

impl Instance {
    /// fmi2GetFMUstate.
    pub fn get_state(&self) -> Result<Snapshot, Status> {
        self.check(Operation::GetFMUstate)?;
        if let Some(t) = self.log_full_at {
            return Err(self.error(&format!(
                "fmi2GetFMUstate: the replay log of this run outgrew the {MAX_STATE_BYTES} bytes an FMU state may have at t = {t}; no FMU state can be taken until fmi2Reset or fmi2SetFMUstate"
            )));
        }
        Ok(Snapshot {
            model: self.model,
            guid: self.spec.guid().to_string(),
            phase: self.phase,
            start_time: self.start_time,
            stop_time: self.stop_time,
            values: self.values.clone(),
            steps: self.steps.clone(),
        })
    }

    /// Check a snapshot fits this instance (model, GUID, table).
    pub fn check_snapshot(&self, func: Operation, s: &Snapshot) -> Result<(), Status> {
        if s.model != self.model || s.guid != self.spec.guid() {
            return Err(self.error(&format!(
                "{func}: the FMU state belongs to {} {}, not to this {} instance ({})",
                s.model.identifier(),
                s.guid,
                self.spec.identifier(),
                self.spec.guid()
            )));
        }
        let types_ok = s.values.len() == self.vars.len()
            && s.values.iter().zip(&self.vars).all(|(v, var)| match v {
                None => !var.settable(),
                Some(v) => var.settable() && v.ty() == var.ty,
            })
            && s.steps.iter().all(|st| {
                st.inputs.len() == self.inputs.len()
                    && st
                        .inputs
                        .iter()
                        .zip(&self.inputs)
                        .all(|(v, &i)| v.ty() == self.vars[i].ty)
            });
        if !types_ok {
            return Err(self.error(&format!(
                "{func}: the FMU state's values do not match the variables of {}",
                self.model.identifier()
            )));
        }
        Ok(())
    }

    /// fmi2SetFMUstate: rebuild and replay.
    pub fn set_state(&mut self, s: &Snapshot) -> Status {
        if let Err(st) = self.check(Operation::SetFMUstate) {
            return st;
        }
        if let Err(st) = self.check_snapshot(Operation::SetFMUstate, s) {
            return st;
        }
        self.engine = None;
        self.steps.clear();
        self.log_full_at = None;
        self.flown_bank = None;
        self.start_time = s.start_time;
        self.stop_time = s.stop_time;
        self.values = s.values.clone();
        self.phase = s.phase;
        let needs_engine = matches!(s.phase, StepComplete | Terminated) || !s.steps.is_empty();
        if needs_engine {
            if let Err(e) = self.ensure_engine() {
                self.phase = Error;
                return self.error(&format!("fmi2SetFMUstate: cannot rebuild the engine: {e}"));
            }
            let current: Vec<Option<Value>> = self.values.clone();
            for st in s.steps.iter() {
                for (&i, v) in self.inputs.iter().zip(st.inputs.iter()) {
                    self.values[i] = Some(v.clone());
                }
                let checked = self
                    .check_step_work(st.t, st.h)
                    .map_err(super::engine::InstanceError::from)
                    .and_then(|()| self.step_engine(st.t, st.h));
                if let Err(e) = checked {
                    self.phase = Error;
                    self.values = current;
                    return self.error(&format!(
                        "fmi2SetFMUstate: replay failed at t = {}: {e}",
                        st.t
                    ));
                }
                self.steps.push(st.clone());
            }
            self.values = current;
        }
        self.info(&format!(
            "FMU state restored ({} steps replayed)",
            s.steps.len()
        ));
        Status::Ok
    }
}
