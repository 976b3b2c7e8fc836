//! Our FMI host, a developer tool: opens one of our `.fmu` files, loads its shared library with
//! libloading and drives an instance through the FMI 2.0 functions ([`Slave`]) or the FMI 3.0
//! functions ([`Slave3`]), both behind one interface ([`FmiInstance`]: initialisation, steps,
//! values by value reference, FMU states, termination, reset, the log). `entrynav-dev fmu check`
//! compares a slave with the in-process [`Instance`](entrynav_fmu::instance::Instance) bit for
//! bit; `entrynav-dev fmu fuzz` drives random call sequences through either interface.
//!
//! It is a crate of its own so that neither the FMU library (`entrynav-fmu`, the cdylib shipped
//! in every `.fmu`) nor the `entrynav` command carries a library loader: libloading lives here
//! and only the developer crate (`entrynav-devtools`) depends on it. Opening and checking an
//! archive without loading it is `entrynav-fmu-archive`'s, which `entrynav fmu pack` uses too.
//!
//! Modules: [`api`] (the fmi2 functions of a loaded library and the logger the host passes),
//! [`api3`] (the fmi3 functions and the FMI 3.0 log callback), `instance` (the shared
//! interface), `slave` and `slave3` (one instance of each version), `outputs` (reading all
//! outputs of a slave or of an in-process instance the same way), `unpack` (an archive with its
//! library loaded) and `error`.
#![warn(missing_docs)]

pub mod api;
pub mod api3;
mod error;
mod instance;
mod outputs;
mod slave;
mod slave3;
mod unpack;

pub use api::{Api, Callbacks, Comp, HostLogger, Log};
pub use api3::{Api3, Inst3, Log3, Logger3, State3, host_logger3};
pub use entrynav_fmu_archive::{Archive, ArchiveError, file_uri};
pub use error::HostError;
pub use instance::{FmiInstance, FmuState, Message, StepAnswer};
pub use outputs::{OutputGroups, in_process_get_all, output_groups};
pub use slave::Slave;
pub use slave3::{Instantiate3, Slave3};
pub use unpack::{Unpacked, unpack};
