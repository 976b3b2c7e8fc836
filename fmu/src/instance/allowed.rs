//! The allowed-state table of the FMI 2.0 co-simulation interface: one entry per fmi2 function,
//! giving the phases in which a master may call it (FMI 2.0.x §4.2.4, "State Machine of Calling
//! Sequence from Master to Slave"; the Reference-FMUs keep the same table as `MASK_fmi2*`).
//!
//! This FMU has five of the standard's co-simulation states ([`Phase`]): steps are synchronous,
//! so *stepInProgress* never occurs, and a failed step or replay moves to *error* instead of
//! *stepFailed*/*stepCanceled*. Each entry is the standard's row restricted to these five states
//! (the test at the end walks every row). *start/end* and *fatal* have no instance to ask, so
//! `fmi2Instantiate` (allowed only in *start/end*) and `fmi2CancelStep` (only in
//! *stepInProgress*) are allowed in no phase.

use crate::state::Phase::{self, *};

/// A set of [`Phase`]s.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Phases(u8);

impl Phases {
    /// No phase.
    pub const NONE: Phases = Phases(0);
    /// Every phase of an instance.
    pub const EVERY: Phases = Phases::of(&Phase::ALL);

    /// The set of `phases`.
    pub const fn of(phases: &[Phase]) -> Phases {
        let mut bits = 0;
        let mut i = 0;
        while i < phases.len() {
            bits |= 1 << phases[i].code();
            i += 1;
        }
        Phases(bits)
    }

    /// Whether `p` is in the set.
    pub const fn contains(self, p: Phase) -> bool {
        self.0 & (1 << p.code()) != 0
    }

    /// The phases of the set, in [`Phase::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = Phase> {
        Phase::ALL.into_iter().filter(move |p| self.contains(*p))
    }
}

impl std::fmt::Debug for Phases {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_set().entries(self.iter()).finish()
    }
}

/// fmi2Get*, fmi2GetDirectionalDerivative: from initialisation on.
const READ: Phases = Phases::of(&[InitializationMode, StepComplete, Terminated, Error]);
/// fmi2Set*, fmi2SetRealInputDerivatives: until and between steps.
const WRITE: Phases = Phases::of(&[Instantiated, InitializationMode, StepComplete]);
/// fmi2Get*Status: after a step (stepInProgress and stepFailed never occur here).
const QUERY: Phases = Phases::of(&[StepComplete, Terminated]);

macro_rules! table {
    ($($f:ident => $allowed:expr,)*) => {
        /// An operation of the instance, named after the fmi2 function of the co-simulation
        /// interface that performs it (the 34 the FMU exports). An FMI 3.0 function is checked
        /// as the operation it maps to (`ffi::fmi3::MAPPED`), so one table serves both interfaces.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Operation {
            $(
                #[doc = concat!("`fmi2", stringify!($f), "`.")]
                $f,
            )*
        }

        impl Operation {
            /// Every function, in the order of the standard's table.
            pub const ALL: &[Operation] = &[$(Operation::$f,)*];

            /// Its C name.
            pub const fn name(self) -> &'static str {
                match self {
                    $(Operation::$f => concat!("fmi2", stringify!($f)),)*
                }
            }

            /// The phases in which it may be called: the table's entry.
            pub const fn allowed(self) -> Phases {
                match self {
                    $(Operation::$f => $allowed,)*
                }
            }
        }
    };
}

table! {
    GetTypesPlatform => Phases::EVERY,
    GetVersion => Phases::EVERY,
    SetDebugLogging => Phases::EVERY,
    Instantiate => Phases::NONE,
    FreeInstance => Phases::EVERY,
    SetupExperiment => Phases::of(&[Instantiated]),
    EnterInitializationMode => Phases::of(&[Instantiated]),
    ExitInitializationMode => Phases::of(&[InitializationMode]),
    Terminate => Phases::of(&[StepComplete]),
    Reset => Phases::EVERY,
    GetReal => READ,
    GetInteger => READ,
    GetBoolean => READ,
    GetString => READ,
    SetReal => WRITE,
    SetInteger => WRITE,
    SetBoolean => WRITE,
    SetString => WRITE,
    GetFMUstate => Phases::EVERY,
    SetFMUstate => Phases::EVERY,
    FreeFMUstate => Phases::EVERY,
    SerializedFMUstateSize => Phases::EVERY,
    SerializeFMUstate => Phases::EVERY,
    DeSerializeFMUstate => Phases::EVERY,
    GetDirectionalDerivative => READ,
    SetRealInputDerivatives => WRITE,
    GetRealOutputDerivatives => Phases::of(&[StepComplete, Terminated, Error]),
    DoStep => Phases::of(&[StepComplete]),
    CancelStep => Phases::NONE,
    GetStatus => QUERY,
    GetRealStatus => QUERY,
    GetIntegerStatus => QUERY,
    GetBooleanStatus => QUERY,
    GetStringStatus => QUERY,
}

impl Operation {
    /// The fmi2Get function of values of type `ty`.
    pub const fn getter(ty: crate::vars::Type) -> Operation {
        use crate::vars::Type;
        match ty {
            Type::Real => Operation::GetReal,
            Type::Integer => Operation::GetInteger,
            Type::Boolean => Operation::GetBoolean,
            Type::String => Operation::GetString,
        }
    }

    /// The fmi2Set function of values of type `ty`.
    pub const fn setter(ty: crate::vars::Type) -> Operation {
        use crate::vars::Type;
        match ty {
            Type::Real => Operation::SetReal,
            Type::Integer => Operation::SetInteger,
            Type::Boolean => Operation::SetBoolean,
            Type::String => Operation::SetString,
        }
    }
}

impl std::fmt::Display for Operation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The standard's co-simulation state table (FMI 2.0.4 §4.2.4), transcribed row by row: one
    /// mark per state, in the columns *start/end*, *instantiated*, *initialization mode*,
    /// *stepComplete*, *stepInProgress*, *stepFailed*, *stepCanceled*, *terminated*, *error*,
    /// *fatal*; `x` allowed (with or without a footnote), `.` not.
    const STANDARD: [(&str, &str); 34] = [
        ("fmi2GetTypesPlatform", "xxxxxxxxxx"),
        ("fmi2GetVersion", "xxxxxxxxxx"),
        ("fmi2SetDebugLogging", ".xxxxxxxx."),
        ("fmi2Instantiate", "x........."),
        ("fmi2FreeInstance", ".xxx.xxxx."),
        ("fmi2SetupExperiment", ".x........"),
        ("fmi2EnterInitializationMode", ".x........"),
        ("fmi2ExitInitializationMode", "..x......."),
        ("fmi2Terminate", "...x.x...."),
        ("fmi2Reset", ".xxx.xxxx."),
        ("fmi2GetReal", "..xx.xxxx."),
        ("fmi2GetInteger", "..xx.xxxx."),
        ("fmi2GetBoolean", "..xx.xxxx."),
        ("fmi2GetString", "..xx.xxxx."),
        ("fmi2SetReal", ".xxx......"),
        ("fmi2SetInteger", ".xxx......"),
        ("fmi2SetBoolean", ".xxx......"),
        ("fmi2SetString", ".xxx......"),
        ("fmi2GetFMUstate", ".xxx.xxxx."),
        ("fmi2SetFMUstate", ".xxx.xxxx."),
        ("fmi2FreeFMUstate", ".xxx.xxxx."),
        ("fmi2SerializedFMUstateSize", ".xxx.xxxx."),
        ("fmi2SerializeFMUstate", ".xxx.xxxx."),
        ("fmi2DeSerializeFMUstate", ".xxx.xxxx."),
        ("fmi2GetDirectionalDerivative", "..xx.xxxx."),
        ("fmi2SetRealInputDerivatives", ".xxx......"),
        ("fmi2GetRealOutputDerivatives", "...x.xxxx."),
        ("fmi2DoStep", "...x......"),
        ("fmi2CancelStep", "....x....."),
        ("fmi2GetStatus", "...xxx.x.."),
        ("fmi2GetRealStatus", "...xxx.x.."),
        ("fmi2GetIntegerStatus", "...xxx.x.."),
        ("fmi2GetBooleanStatus", "...xxx.x.."),
        ("fmi2GetStringStatus", "...xxx.x.."),
    ];

    /// The standard's column of each phase of this FMU.
    fn column(p: Phase) -> usize {
        match p {
            Instantiated => 1,
            InitializationMode => 2,
            StepComplete => 3,
            Terminated => 7,
            Error => 8,
        }
    }

    #[test]
    fn every_entry_is_the_standards_row_on_the_phases_of_this_fmu() {
        assert_eq!(Operation::ALL.len(), STANDARD.len());
        for (f, (name, row)) in Operation::ALL.iter().zip(STANDARD) {
            assert_eq!(f.name(), name, "the table is not in the standard's order");
            let row = row.as_bytes();
            assert_eq!(row.len(), 10, "{name}: a row has one mark per state");
            for p in Phase::ALL {
                assert_eq!(
                    f.allowed().contains(p),
                    row[column(p)] == b'x',
                    "{name} in {p:?}"
                );
            }
        }
    }

    #[test]
    fn the_shorthand_sets_hold_what_they_say() {
        assert_eq!(Phases::EVERY.iter().collect::<Vec<_>>(), Phase::ALL);
        assert_eq!(Phases::NONE.iter().count(), 0);
        assert_eq!(
            Phases::of(&[Error, Instantiated])
                .iter()
                .collect::<Vec<_>>(),
            [Instantiated, Error]
        );
    }
}
