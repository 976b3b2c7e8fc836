//! The instance's messages (written in FMI 2.0 terms) in FMI 3.0 terms.

/// FMI 2.0 names in the instance's messages and their FMI 3.0 counterparts (longest first where
/// one is a prefix of another); every other `fmi2X` becomes `fmi3X`.
const RENAMED: [(&str, &str); 19] = [
    ("fmi2Instantiate", "fmi3InstantiateCoSimulation"),
    ("fmi2SetupExperiment", "fmi3EnterInitializationMode"),
    ("fmi2GetReal", "fmi3GetFloat64"),
    ("fmi2SetReal", "fmi3SetFloat64"),
    ("fmi2GetInteger", "fmi3GetInt32"),
    ("fmi2SetInteger", "fmi3SetInt32"),
    ("fmi2GetFMUstate", "fmi3GetFMUState"),
    ("fmi2SetFMUstate", "fmi3SetFMUState"),
    ("fmi2FreeFMUstate", "fmi3FreeFMUState"),
    ("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize"),
    ("fmi2SerializeFMUstate", "fmi3SerializeFMUState"),
    ("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState"),
    ("fmi2Component", "fmi3Instance"),
    ("FMUstate", "FMUState"),
    ("binaries/linux64/", "binaries/x86_64-linux/"),
    ("fmuResourceLocation", "resourcePath"),
    ("GUID", "instantiation token"),
    ("StepComplete", "StepMode"),
    ("FMI 2.0", "FMI"),
];

/// A message of the instance (written in FMI 2.0 terms) in FMI 3.0 terms.
pub fn in_fmi3_terms(msg: &str) -> String {
    let mut s = msg.to_string();
    for (from, to) in RENAMED {
        if s.contains(from) {
            s = s.replace(from, to);
        }
    }
    s.replace("fmi2", "fmi3")
}
