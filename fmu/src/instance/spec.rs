//! The model an `fmi2Instantiate` call gets: from the library's binding (see [`crate::binding`])
//! and the GUID the importer passes.

use super::scenario::load_resource_scenario;
use super::status::InstantiateError;
use crate::binding::Binding;
use crate::vars::{Model, ModelSpec};
use entrynav::estimation::nav::FilterKind;
use std::sync::Arc;

/// The model `guid` names for a library bound to `binding` (`None`: unbound, any of the three
/// generic models); a specific FMU's scenario is loaded from the resources folder at
/// `resource_location` and must still be the one it was packed with.
pub fn resolve_spec(
    binding: Option<&Binding>,
    guid: &str,
    resource_location: Option<&str>,
) -> Result<Arc<ModelSpec>, InstantiateError> {
    let Some(b) = binding else {
        return generic_spec(guid);
    };
    if guid != b.guid {
        let other = Model::from_guid(guid)
            .filter(|m| m.identifier() != b.identifier)
            .map(|m| {
                format!(
                    "; '{guid}' is the GUID of {m}, whose library is binaries/linux64/{m}.so in {m}.fmu",
                    m = m.identifier()
                )
            })
            .unwrap_or_default();
        return Err(InstantiateError::Guid {
            given: guid.to_string(),
            expected: format!(
                "this library ({}.so) was packed for {} and accepts only its GUID {}{other}",
                b.identifier, b.identifier, b.guid
            ),
        });
    }
    let embedded = |reason: String| InstantiateError::Embedded {
        identifier: b.identifier.clone(),
        reason,
    };
    let spec = match &b.scenario {
        None => ModelSpec::generic(b.base),
        Some((file, filter)) => {
            let dir = resource_location
                .ok_or(crate::uri::UriError::Missing)
                .and_then(crate::uri::resource_dir)
                .map_err(|e| embedded(e.to_string()))?;
            let scenario =
                load_resource_scenario(&dir, file).map_err(|e| embedded(e.to_string()))?;
            let kind = FilterKind::parse(filter).map_err(|e| embedded(e.to_string()))?;
            let toml = scenario.config.to_toml_string();
            ModelSpec::for_scenario(scenario, file, &toml, kind)
                .map_err(|e| embedded(e.to_string()))?
        }
    };
    if spec.identifier() != b.identifier || spec.guid() != b.guid {
        return Err(embedded(format!(
            "this library generates {} with GUID {}, not the packed {} {} (resources/ changed, or a library of another version)",
            spec.identifier(),
            spec.guid(),
            b.identifier,
            b.guid
        )));
    }
    Ok(Arc::new(spec))
}

/// The model a GUID names when no binding restricts it: one of the generic models.
pub fn generic_spec(guid: &str) -> Result<Arc<ModelSpec>, InstantiateError> {
    match Model::from_guid(guid) {
        Some(m) => Ok(Arc::new(ModelSpec::generic(m))),
        None => Err(InstantiateError::Guid {
            given: guid.to_string(),
            expected: format!(
                "this library serves {}",
                Model::ALL
                    .map(|m| format!("{} {}", m.identifier(), crate::vars::guid_of(m)))
                    .join(", ")
            ),
        }),
    }
}
