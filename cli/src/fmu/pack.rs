//! `entrynav fmu pack`: the three `.fmu` archives (model description, shared library,
//! documentation) from the FMU crate's cdylib.

#![allow(non_snake_case)]

use super::*;

pub(super) fn default_lib() -> Result<PathBuf> {
    let exe = std::env::current_exe()?;
    let dir = exe.parent().context("executable has no folder")?;
    Ok(dir.join("libmars_entry_nav.so"))
}

pub(super) fn pack(out: &Path, lib: Option<&Path>) -> Result<()> {
    let lib = match lib {
        Some(l) => l.to_path_buf(),
        None => default_lib()?,
    };
    let so = std::fs::read(&lib).with_context(|| {
        format!(
            "cannot read the FMU library {} (build it with `cargo build --release -p entrynav-fmu`, or pass --lib)",
            lib.display()
        )
    })?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    for m in Model::ALL {
        let path = out.join(format!("{}.fmu", m.identifier()));
        let file = std::fs::File::create(&path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        let mut zip = zip::ZipWriter::new(file);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .unix_permissions(0o644);
        zip.start_file("modelDescription.xml", opts)?;
        zip.write_all(model_description(m).as_bytes())?;
        zip.add_directory("binaries/", opts)?;
        zip.add_directory("binaries/linux64/", opts)?;
        zip.start_file(
            format!("binaries/linux64/{}.so", m.identifier()),
            opts.unix_permissions(0o755),
        )?;
        zip.write_all(&so)?;
        zip.add_directory("resources/", opts)?;
        for name in BUILTIN_NAMES {
            zip.start_file(format!("resources/{name}.toml"), opts)?;
            zip.write_all(builtin_toml(name).unwrap_or_default().as_bytes())?;
        }
        zip.add_directory("documentation/", opts)?;
        zip.start_file("documentation/index.html", opts)?;
        zip.write_all(documentation(m).as_bytes())?;
        zip.finish()?;
        println!("{}  {}  {}", path.display(), m.identifier(), guid_of(m));
    }
    Ok(())
}

pub(super) fn documentation(m: Model) -> String {
    let rows: String = variables(m)
        .iter()
        .map(|v| {
            format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                v.vr,
                v.name,
                v.causality.xml(),
                v.ty.xml(),
                v.unit.unwrap_or(""),
                v.description.replace('&', "&amp;").replace('<', "&lt;")
            )
        })
        .collect();
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{id}</title></head><body>\n<h1>{id}</h1>\n<p>{d}</p>\n<p>Scenario files in resources/ may be named by the <code>scenario</code> parameter.</p>\n<table border=\"1\"><tr><th>vr</th><th>name</th><th>causality</th><th>type</th><th>unit</th><th>description</th></tr>\n{rows}</table></body></html>\n",
        id = m.identifier(),
        d = m.description()
    )
}
