//! [`unpack`]: one of our `.fmu` files opened (extracted and checked against this build, see
//! `entrynav-fmu-archive`) and its library loaded ([`Unpacked`]).

use crate::api::Api;
use crate::error::Result;
use entrynav_fmu_archive::{Archive, open};
use std::path::Path;
use std::sync::Arc;

/// An opened FMU and its loaded library.
pub struct Unpacked {
    /// The extracted and checked archive (its folder is removed on drop).
    pub archive: Archive,
    /// The library's fmi2 functions (it exports the fmi3 ones too: [`crate::Api3::load`]).
    pub api: Arc<Api>,
}

impl std::ops::Deref for Unpacked {
    type Target = Archive;

    fn deref(&self) -> &Archive {
        &self.archive
    }
}

/// Open `file` (see [`entrynav_fmu_archive::open`]) and load its library's fmi2 functions.
pub fn unpack(file: &Path) -> Result<Unpacked> {
    let archive = open(file)?;
    let api = Arc::new(Api::load(&archive.library)?);
    Ok(Unpacked { archive, api })
}
