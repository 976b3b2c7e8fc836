//! Which of the five generic FMUs a table is for ([`Model`]): its identifier, description and
//! what it runs.

/// The five generic FMUs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// Entry dynamics, sensors and navigation filter (`MarsEntryNav`).
    Combined,
    /// The navigation filter alone, fed with measurements (`MarsEntryNavFilter`).
    Filter,
    /// Truth dynamics and sensors, producing the measurements (`MarsEntryTruth`).
    Truth,
    /// Entry guidance alone, fed with the navigation estimate and the accelerometer triad
    /// (`MarsEntryGuidance`): its output is the bank command.
    Guidance,
    /// Entry dynamics, sensors, navigation filter and guidance in one loop
    /// (`MarsEntryNavGuided`): guidance flies the filter's estimate, the truth flies its bank.
    Guided,
}

impl Model {
    /// All models.
    pub const ALL: [Model; 5] = [
        Model::Combined,
        Model::Filter,
        Model::Truth,
        Model::Guidance,
        Model::Guided,
    ];

    /// FMI model identifier (the shared library's file stem inside the `.fmu`).
    pub fn identifier(self) -> &'static str {
        match self {
            Model::Combined => "MarsEntryNav",
            Model::Filter => "MarsEntryNavFilter",
            Model::Truth => "MarsEntryTruth",
            Model::Guidance => "MarsEntryGuidance",
            Model::Guided => "MarsEntryNavGuided",
        }
    }

    /// One-line description.
    pub fn description(self) -> &'static str {
        match self {
            Model::Combined => {
                "Mars entry dynamics, sensors and navigation filter (entrynav), driven by a bank-angle command and beacon availability"
            }
            Model::Filter => {
                "Mars entry navigation filter (entrynav) alone, fed with accelerometer, air-data and radio measurements and their validity flags"
            }
            Model::Truth => {
                "Mars entry truth dynamics and sensors (entrynav): true trajectory and noisy measurements with validity flags"
            }
            Model::Guidance => {
                "Mars entry guidance (entrynav, the scenario's [guidance]): bank command through the rate and acceleration limits, from the navigation estimate and the accelerometer triad"
            }
            Model::Guided => {
                "Mars entry dynamics, sensors, navigation filter and guidance in one loop (entrynav, the scenario's [guidance]): guidance flies the filter's estimate, the truth flies the bank through the rate and acceleration limits, until the deployment trigger"
            }
        }
    }

    /// Whether this model runs the truth.
    pub fn has_truth(self) -> bool {
        matches!(self, Model::Combined | Model::Truth | Model::Guided)
    }

    /// Whether this model runs a filter.
    pub fn has_filter(self) -> bool {
        matches!(self, Model::Combined | Model::Filter | Model::Guided)
    }

    /// Whether the truth, the filter and their judgement run together (no measurement
    /// variables: the filter is fed inside).
    pub fn is_closed(self) -> bool {
        matches!(self, Model::Combined | Model::Guided)
    }

    /// The generic model with identifier `id`.
    pub fn from_identifier(id: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| m.identifier() == id)
    }
}
