//! The committed `modelDescription/*.xml` files (FMI 2.0), `modelDescription/fmi3/*.xml` (FMI
//! 3.0, scalars only: `fmu pack --fmi 3`) and `modelDescription/fmi3-arrays/*.xml` (FMI 3.0 with
//! the filter's arrays: `fmu pack --fmi 3 --arrays`) are exactly what the variable table generates.
//! Regenerate them with `ENTRYNAV_BLESS=1 cargo test -p entrynav-fmu --test model_description`.

use entrynav_fmu::xml::{committed_file_name, model_description};
use entrynav_fmu::{Arrays, Model, ModelSpec, description3_of, guid_of};
use std::path::PathBuf;

#[test]
fn committed_model_descriptions_do_not_drift() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../modelDescription");
    let bless = std::env::var_os("ENTRYNAV_BLESS").is_some();
    std::fs::create_dir_all(dir.join("fmi3")).unwrap();
    std::fs::create_dir_all(dir.join("fmi3-arrays")).unwrap();
    let both = Model::ALL.into_iter().flat_map(|m| {
        [
            (dir.join(committed_file_name(m)), m, model_description(m)),
            (
                dir.join("fmi3").join(committed_file_name(m)),
                m,
                description3_of(&ModelSpec::generic(m), Arrays::Omitted),
            ),
            (
                dir.join("fmi3-arrays").join(committed_file_name(m)),
                m,
                description3_of(&ModelSpec::generic(m), Arrays::Declared),
            ),
        ]
    });
    for (path, m, generated) in both {
        assert!(generated.contains(&format!("=\"{}\"", guid_of(m))));
        assert!(generated.contains(&format!("modelIdentifier=\"{}\"", m.identifier())));
        if bless {
            std::fs::write(&path, &generated).unwrap();
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == generated,
            "{} drifted from the variable table; regenerate with ENTRYNAV_BLESS=1 cargo test -p entrynav-fmu --test model_description",
            path.display()
        );
    }
}
