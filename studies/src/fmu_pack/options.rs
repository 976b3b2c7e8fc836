//! The options of the FMU packer ([`super::pack`]), validated for both front ends (the CLI's
//! `fmu pack` flags and Python's `fmu_pack` keywords).

use crate::error::{StudyError, StudyResult};
use crate::options::check_count;
use entrynav_fmu::Arrays;

/// The options of the packer (the output folder and the library are arguments of their own).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PackOptions {
    /// Default filter of the scenario-specific FMU (default: dcifaif if it fits the scenario,
    /// else the first filter that does).
    pub filter: Option<String>,
    /// Also write SSP 1.0 packages of the generic FMUs (FMI 2.0 only).
    pub ssp: bool,
    /// FMI version of the packed FMUs: 2 (`<id>.fmu`) or 3 (`<id>-fmi3.fmu`).
    pub fmi: u8,
    /// FMI 3.0 only: also declare the arrays `est_x`, `est_sigma` and `est_covariance`, sized by
    /// the structural parameter `n_state_slots`. Off by default: OMSimulator 3.0 cannot load an
    /// FMU with a structural parameter (see [`entrynav_fmu::Arrays`]).
    pub arrays: bool,
    /// Ship the library with its symbols and debug information (by default it is stripped with
    /// binutils' `strip --strip-all`).
    pub keep_symbols: bool,
}

impl Default for PackOptions {
    fn default() -> Self {
        PackOptions {
            filter: None,
            ssp: false,
            fmi: 2,
            arrays: false,
            keep_symbols: false,
        }
    }
}

impl PackOptions {
    /// Refuse an FMI version other than 2 or 3, arrays in FMI 2.0 and SSP packages of FMI 3.0
    /// FMUs.
    pub fn validate(&self) -> StudyResult<()> {
        check_count("fmi", self.fmi as usize, 2, 3)?;
        if self.arrays && self.fmi != 3 {
            return Err(StudyError::Refused(format!(
                "arrays = true needs fmi = 3 (fmi = {}): FMI 2.0 has no array variables (its FMUs carry est_x_i and est_sigma_i as scalars)",
                self.fmi
            )));
        }
        if let Some(f) = &self.filter {
            crate::options::filter("filter", f)?;
        }
        if self.ssp && self.fmi == 3 {
            return Err(StudyError::Refused(super::ssp::SSP_FMI3_REFUSAL.into()));
        }
        Ok(())
    }

    /// The FMI 3.0 description's arrays these options ask for.
    pub fn fmi3_arrays(&self) -> Arrays {
        if self.arrays {
            Arrays::Declared
        } else {
            Arrays::Omitted
        }
    }
}
