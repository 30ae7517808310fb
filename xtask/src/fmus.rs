//! `cargo xtask fmus`: build the release cdylibs and package one `.fmu` per FMU crate.
use crate::doc_page;
use crate::fmu_zip::{self, Entry};
use crate::platform::{FmiVersion, Platform};
use crate::ssp;
use crate::workspace::{self, Workspace};
use anyhow::{bail, Context, Result};
use fmu_metadata::{Fmi, FmuCrate};
use model_description::ModelDescription;
use std::path::{Path, PathBuf};

/// The binary of an FMU crate that prints its generated modelDescription.xml for `version`:
/// `<crate>_model_description` (FMI 2.0) and `<crate>_model_description_fmi3`, named after
/// the crate because binaries of one name in several packages collide in `target/`. A
/// binary, not an example: an example would build the crate's dev-dependencies (the test
/// kit, bindgen, criterion) only to print a file.
fn description_binary(fmu: &FmuCrate, version: Fmi) -> String {
    let stem = fmu.package.replace('-', "_");
    match version {
        Fmi::V2 => format!("{stem}_model_description"),
        Fmi::V3 => format!("{stem}_model_description_fmi3"),
    }
}

/// The FMU crates of the workspace, from their `[package.metadata.fmu]` tables, each
/// checked against what its `src/lib.rs` exports and which description binaries it has:
/// what is promised, exported and described must be the same before anything is packaged.
fn fmu_crates(ws: &Workspace) -> Result<Vec<FmuCrate>> {
    let fmus = fmu_metadata::workspace_fmus(&ws.root).map_err(anyhow::Error::msg)?;
    let mut problems = Vec::new();
    for fmu in &fmus {
        let lib_rs = ws.root.join(&fmu.dir).join("src").join("lib.rs");
        let source = std::fs::read_to_string(&lib_rs)
            .with_context(|| format!("cannot read {}", lib_rs.display()))?;
        let exports = fmu_metadata::exports_in_source(&source)
            .map_err(|e| anyhow::anyhow!("{}: {e}", lib_rs.display()))?;
        problems.extend(fmu_metadata::check_exports(fmu, &exports));
        for version in Fmi::ALL {
            let binary = binary_path(ws, fmu, version);
            match (fmu.ships(version), binary.is_file()) {
                (true, false) => problems.push(format!(
                    "{}: the metadata ships {version} but {} is missing",
                    fmu.model_identifier,
                    binary.display()
                )),
                (false, true) if fmu.offer(version).is_none() => problems.push(format!(
                    "{}: {} exists but the metadata offers no {version}",
                    fmu.model_identifier,
                    binary.display()
                )),
                _ => {}
            }
        }
    }
    if !problems.is_empty() {
        bail!(
            "the FMU crates disagree with their [package.metadata.fmu]:\n  {}",
            problems.join("\n  ")
        );
    }
    if fmus.is_empty() {
        bail!("no workspace member has a [package.metadata.fmu] table: nothing to package");
    }
    Ok(fmus)
}

fn binary_path(ws: &Workspace, fmu: &FmuCrate, version: Fmi) -> PathBuf {
    ws.root
        .join(&fmu.dir)
        .join("src")
        .join("bin")
        .join(format!("{}.rs", description_binary(fmu, version)))
}

/// Build and package every FMU of the metadata tables, for the host, then the SSP
/// of the paper scenario that holds two of them; returns the written files.
pub fn package_all(ws: &Workspace) -> Result<Vec<PathBuf>> {
    package_for(ws, &[])
}

/// As [`package_all`], building the dev-profile `packages` (the demo's harness) alongside
/// the description binaries, in the same cargo invocation.
pub fn package_all_with(ws: &Workspace, packages: &[&str]) -> Result<Vec<PathBuf>> {
    let fmus = fmu_crates(ws)?;
    let build = build_host(ws, &fmus, Describers::Build(packages))?;
    package(ws, &fmus, &[build], &ws.fmu_dir())
}

/// Where a build for one platform puts its libraries.
struct Build {
    platform: Platform,
    release_dir: PathBuf,
    /// The `strip` that knows the platform's object format (the host's for the host).
    strip: String,
}

/// The `strip` of binutils for a foreign rustup target, by the GNU triple Debian names its
/// cross binutils with; the host's `strip` for the host.
fn strip_for(platform: &Platform, host: &Platform) -> String {
    if platform == host {
        return "strip".into();
    }
    crate::cross::TARGETS
        .iter()
        .find(|t| t.triple == platform.triple)
        .map_or_else(|| "(none)".into(), |t| t.strip.into())
}

/// Prints the folders a platform's binaries go to.
fn announce(platform: &Platform) -> Result<()> {
    let fmi3 = platform.folder(FmiVersion::V3)?;
    let fmi2 = platform
        .folder(FmiVersion::V2)
        .map_or_else(|_| "(none)".to_owned(), |f| format!("binaries/{f}"));
    println!(
        "xtask fmus: {} -> {fmi2} (FMI 2.0), binaries/{fmi3} (FMI 3.0)",
        platform.triple
    );
    Ok(())
}

/// Where the host build gets the description binaries from.
#[derive(Clone, Copy)]
pub enum Describers<'a> {
    /// Build them, with these further dev-profile packages in the same invocation.
    Build(&'a [&'a str]),
    /// `cargo test --workspace --no-run` has just built them with the features the tests
    /// resolve; a build of the FMU crates alone would resolve other features of their
    /// shared dependencies and compile those a second time.
    FromTestBuild,
}

/// The host build of today's `cargo xtask fmus`, with rustup's (the invoking) cargo: the
/// release libraries and, at the same time, the description binaries (see
/// [`build_describers`]).
fn build_host(ws: &Workspace, fmus: &[FmuCrate], describers: Describers) -> Result<Build> {
    let platform = Platform::host()?;
    announce(&platform)?;
    let mut libs = ws.cargo();
    libs.args(["build", "--release", "--lib"]);
    for fmu in fmus {
        libs.args(["-p", &fmu.package]);
    }
    // Two cargo processes at once (they lock different profile folders): each has serial
    // stretches (the LTO links, the crate chain up to the harness) that the other fills.
    libs.env("CARGO_TERM_PROGRESS_WHEN", "never");
    let started = libs
        .spawn()
        .with_context(|| format!("could not start {}", workspace::describe(&libs)))?;
    let described = match describers {
        Describers::Build(also_dev) => build_describers(ws, fmus, also_dev),
        Describers::FromTestBuild => {
            // A crate without integration tests has no binaries in the test build.
            let missing: Vec<FmuCrate> = fmus
                .iter()
                .filter(|fmu| {
                    Fmi::ALL.iter().any(|&version| {
                        fmu.ships(version) && !describer_path(ws, fmu, version).is_file()
                    })
                })
                .cloned()
                .collect();
            if missing.is_empty() && crate::references::generator_path(ws).is_file() {
                Ok(())
            } else {
                build_describers(ws, &missing, &[])
            }
        }
    };
    let built = workspace::wait(started, &libs);
    described.and(built)?;
    Ok(Build {
        strip: strip_for(&platform, &platform),
        platform,
        release_dir: ws.target_dir.join("release"),
    })
}

/// `cargo xtask fmus --all-platforms`: the host build, then aarch64 Linux and x86_64 Windows
/// with Debian's toolchain ([`crate::cross`]), packaged into FMUs that carry all three under
/// `target/fmu`, where the host-only FMUs go too: the FMUs every test loads are the ones a
/// release ships (FMI 2.0 has no aarch64 Linux folder: those FMUs carry two).
pub fn package_all_platforms(ws: &Workspace, describers: Describers) -> Result<Vec<PathBuf>> {
    let (packages, architectures) = crate::system_packages::for_all_platforms();
    crate::system_packages::ensure_with_architectures(&packages, architectures)?;
    let fmus = fmu_crates(ws)?;
    let names: Vec<&str> = fmus.iter().map(|f| f.package.as_str()).collect();
    let mut builds = Vec::new();
    let mut timings = Vec::new();
    let started = std::time::Instant::now();
    builds.push(build_host(ws, &fmus, describers)?);
    timings.push((builds[0].platform.triple.clone(), started.elapsed()));
    let host = Platform::host()?;
    for target in &crate::cross::TARGETS {
        let started = std::time::Instant::now();
        let platform = Platform::from_triple(target.triple)?;
        announce(&platform)?;
        let release_dir = crate::cross::build(ws, target, &names)?;
        builds.push(Build {
            strip: strip_for(&platform, &host),
            platform,
            release_dir,
        });
        timings.push((target.triple.to_owned(), started.elapsed()));
    }
    for (triple, took) in &timings {
        println!("xtask fmus: built {triple} in {:.1} s", took.as_secs_f64());
    }
    package(ws, &fmus, &builds, &ws.fmu_dir())
}

/// The description binaries in the dev profile: they only print XML, so optimising and
/// LTO-linking ten of them would cost as much as the libraries themselves, and unoptimised
/// they share their artifacts with `cargo test`. `also_dev` packages are built in the same
/// invocation, so that the features of shared dependencies are resolved once. cosim's
/// `fmu_reference`, which writes the FMUs' references, is built with them.
fn build_describers(ws: &Workspace, fmus: &[FmuCrate], also_dev: &[&str]) -> Result<()> {
    let mut build = ws.cargo();
    build.args(["build", "--bins"]);
    for package in fmus
        .iter()
        .map(|f| f.package.as_str())
        .chain(also_dev.iter().copied())
    {
        build.args(["-p", package]);
    }
    build.args(["-p", "cosim"]);
    build.env("CARGO_TERM_PROGRESS_WHEN", "never");
    workspace::run(&mut build)
}

/// Where cargo puts the description binary of `fmu` for `version`.
fn describer_path(ws: &Workspace, fmu: &FmuCrate, version: Fmi) -> PathBuf {
    ws.target_dir
        .join("debug")
        .join(description_binary(fmu, version))
}

/// The model description `fmu`'s binary (built by [`build_describers`]) prints for
/// `version`.
fn describe(ws: &Workspace, fmu: &FmuCrate, version: Fmi) -> Result<String> {
    describe_with(ws, fmu, version, &[])
}

/// What `fmu`'s description binary for `version` prints when given `args`.
fn describe_with(ws: &Workspace, fmu: &FmuCrate, version: Fmi, args: &[&str]) -> Result<String> {
    let binary = describer_path(ws, fmu, version);
    let mut command = std::process::Command::new(&binary);
    command.args(args);
    // generationDateAndTime: the commit's time, so that a commit packages the same bytes on
    // every machine (kept when the caller set SOURCE_DATE_EPOCH itself; none outside git).
    if std::env::var_os("SOURCE_DATE_EPOCH").is_none() {
        if let Some(seconds) = commit_time(ws) {
            command.env("SOURCE_DATE_EPOCH", seconds);
        }
    }
    workspace::output(&mut command)
}

/// The Unix time of HEAD's commit, if the workspace is a git checkout.
fn commit_time(ws: &Workspace) -> Option<String> {
    let output = std::process::Command::new("git")
        .args(["log", "-1", "--format=%ct"])
        .current_dir(&ws.root)
        .output()
        .ok()?;
    let text = String::from_utf8(output.stdout).ok()?;
    let seconds = text.trim();
    (output.status.success() && seconds.parse::<i64>().is_ok()).then(|| seconds.to_owned())
}

/// Builds the release cdylibs for each target triple (the host when none is given).
fn build_all(ws: &Workspace, fmus: &[FmuCrate], triples: &[String]) -> Result<Vec<Build>> {
    let mut problems = Vec::new();
    let mut builds = Vec::new();
    let host = Platform::host()?;
    if triples.is_empty() {
        return Ok(vec![build_host(ws, fmus, Describers::Build(&[]))?]);
    }
    for triple in triples {
        match Platform::from_triple(triple) {
            Ok(platform) => builds.push(Build {
                release_dir: ws.target_dir.join(triple).join("release"),
                strip: strip_for(&platform, &host),
                platform,
            }),
            Err(error) => problems.push(format!("--target {triple}: {error:#}")),
        }
    }
    if !builds.is_empty()
        && builds
            .iter()
            .all(|b| b.platform.folder(FmiVersion::V2).is_err())
    {
        problems.push(
            "no target has an FMI 2.0 binaries folder: the FMI 2.0 FMUs would be empty".into(),
        );
    }
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    // The descriptions are printed on the host whatever the targets.
    build_describers(ws, fmus, &[])?;
    for target in &builds {
        announce(&target.platform)?;
        let mut build = ws.cargo();
        build.args(["build", "--release", "--lib"]);
        build.args(["--target", &target.platform.triple]);
        for fmu in fmus {
            build.args(["-p", &fmu.package]);
        }
        workspace::run(&mut build).with_context(|| {
            format!(
                "building for {} (is its standard library installed? \
                 `rustup target add {0}`)",
                target.platform.triple
            )
        })?;
    }
    Ok(builds)
}

/// As [`package_all`], with the binaries of every target triple in each FMU
/// (`cargo xtask fmus --target T1 --target T2`).
pub fn package_for(ws: &Workspace, triples: &[String]) -> Result<Vec<PathBuf>> {
    let fmus = fmu_crates(ws)?;
    let builds = build_all(ws, &fmus, triples)?;
    package(ws, &fmus, &builds, &ws.fmu_dir())
}

/// Packages every FMU of `fmus` with the libraries of `builds` into `out_dir` (FMI 3.0 in
/// `out_dir/fmi3`), and the SSP packages of the paper scenario beside them.
fn package(
    ws: &Workspace,
    fmus: &[FmuCrate],
    builds: &[Build],
    out_dir: &Path,
) -> Result<Vec<PathBuf>> {
    let out_dir = out_dir.to_path_buf();
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;

    let mut written = Vec::new();
    let mut packaged: Vec<(String, Vec<PathBuf>)> = Vec::new();
    for fmu in fmus {
        let mut files = Vec::new();
        for version in Fmi::ALL {
            match fmu.offer(version) {
                None => continue,
                Some(offer) if offer.awaiting_export => {
                    println!(
                        "xtask fmus: {}: {version} awaits its export (awaiting-export in \
                         {}/Cargo.toml): not packaged",
                        fmu.model_identifier,
                        fmu.dir.display()
                    );
                    continue;
                }
                Some(_) => {}
            }
            let path = match version {
                Fmi::V2 => package_one(ws, fmu, builds, &out_dir)?,
                Fmi::V3 => package_one_fmi3(ws, fmu, builds, &out_dir.join("fmi3"))?,
            };
            println!("xtask fmus: wrote {}", path.display());
            files.push(path.clone());
            written.push(path);
        }
        if !files.is_empty() {
            packaged.push((fmu.model_identifier.clone(), files));
        }
    }
    // The references are runs of the FMUs: only where they have a binary for this machine.
    let host = Platform::host()?;
    if builds.iter().any(|b| b.platform == host) {
        crate::references::add(ws, &packaged)?;
    } else {
        println!(
            "xtask fmus: no binary for this machine ({}): the FMUs carry no references",
            host.triple
        );
    }
    for package in ssp::package(ws, &out_dir)? {
        println!("xtask fmus: wrote {}", package.display());
        written.push(package);
    }
    Ok(written)
}

fn package_one(
    ws: &Workspace,
    fmu: &FmuCrate,
    builds: &[Build],
    out_dir: &Path,
) -> Result<PathBuf> {
    let xml = describe(ws, fmu, Fmi::V2)?;
    let description = ModelDescription::from_xml(&xml).with_context(|| {
        format!(
            "{} printed a modelDescription.xml that does not parse",
            fmu.package
        )
    })?;
    if let Err(problems) = description.validate() {
        bail!(
            "the model description of {} is invalid:\n  {}",
            fmu.package,
            problems.join("\n  ")
        );
    }
    let identifier = model_identifier(&description)
        .with_context(|| format!("in the model description of {}", fmu.package))?;
    check_described(
        fmu,
        Fmi::V2,
        identifier,
        description.model_exchange.is_some(),
    )?;

    let mut entries = vec![
        Entry::file(
            "documentation/index.html",
            doc_page::render(&description).into_bytes(),
        ),
        Entry::file("modelDescription.xml", xml.into_bytes()),
    ];
    entries.extend(binaries(fmu, builds, out_dir, identifier, FmiVersion::V2)?);
    let fmu_path = out_dir.join(format!("{identifier}.fmu"));
    fmu_zip::write(&fmu_path, entries)?;
    Ok(fmu_path)
}

/// The description `version` printed must name the metadata's `model-identifier` and
/// declare Model Exchange exactly when the metadata offers it.
fn check_described(
    fmu: &FmuCrate,
    version: Fmi,
    identifier: &str,
    declares_model_exchange: bool,
) -> Result<()> {
    if identifier != fmu.model_identifier {
        bail!(
            "the {version} description of {} names modelIdentifier {identifier:?}, its \
             [package.metadata.fmu] {:?}",
            fmu.package,
            fmu.model_identifier
        );
    }
    let offered = fmu.ships_model_exchange(version);
    if declares_model_exchange != offered {
        bail!(
            "the {version} description of {} ({}) {} <ModelExchange>, but its \
             [package.metadata.fmu] {} model-exchange",
            fmu.package,
            description_binary(fmu, version),
            if declares_model_exchange {
                "declares"
            } else {
                "lacks"
            },
            if offered { "lists" } else { "does not list" }
        );
    }
    Ok(())
}

/// `binaries/<folder>/<identifier>.<ext>` for every build that has a folder in `version`;
/// a platform FMI 2.0 has no folder for is left out of the FMI 2.0 FMU with a note.
fn binaries(
    fmu: &FmuCrate,
    builds: &[Build],
    scratch_dir: &Path,
    identifier: &str,
    version: FmiVersion,
) -> Result<Vec<Entry>> {
    let mut entries = Vec::new();
    for build in builds {
        let folder = match build.platform.folder(version) {
            Ok(folder) => folder,
            Err(error) => {
                println!("xtask fmus: {identifier}: {error:#}");
                continue;
            }
        };
        let library = build
            .release_dir
            .join(build.platform.cargo_library_file(&fmu.lib_name));
        // The host's strip does not know a foreign object format: each has its own.
        let binary = stripped_library(&build.strip, &library, scratch_dir, identifier)?;
        let file = build.platform.fmu_binary_file(identifier);
        entries.push(Entry::executable(
            format!("binaries/{folder}/{file}"),
            binary,
        ));
    }
    Ok(entries)
}

/// The FMI 3.0 FMU of a crate (the same library: it exports the `fmi3*` functions beside the
/// `fmi2*` ones).
fn package_one_fmi3(
    ws: &Workspace,
    fmu: &FmuCrate,
    builds: &[Build],
    out_dir: &Path,
) -> Result<PathBuf> {
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let xml = describe(ws, fmu, Fmi::V3)?;
    let identifier = fmi3_model_identifier(&xml)
        .with_context(|| format!("in the FMI 3.0 model description of {}", fmu.package))?;
    check_described(fmu, Fmi::V3, &identifier, xml.contains("<ModelExchange"))?;
    // The page lists the variables of the one declaration, read from the FMI 2.0 description.
    let fmi2 = ModelDescription::from_xml(&describe(ws, fmu, Fmi::V2)?).with_context(|| {
        format!(
            "{} printed an FMI 2.0 model description that does not parse",
            fmu.package
        )
    })?;
    let facts = doc_page::Fmi3Facts {
        instantiation_token: xml_attribute(&xml, "instantiationToken")
            .with_context(|| format!("in the FMI 3.0 model description of {}", fmu.package))?,
        generation_tool: xml_attribute(&xml, "generationTool").ok(),
    };
    let mut entries = vec![
        Entry::file(
            "documentation/index.html",
            doc_page::render_fmi3(&fmi2, &facts).into_bytes(),
        ),
        Entry::file("modelDescription.xml", xml.clone().into_bytes()),
    ];
    entries.extend(terminals_and_icons(ws, fmu)?);
    entries.extend(binaries(fmu, builds, out_dir, &identifier, FmiVersion::V3)?);
    let fmu_path = out_dir.join(format!("{identifier}.fmu"));
    fmu_zip::write(&fmu_path, entries)?;
    Ok(fmu_path)
}

/// `terminalsAndIcons/`: the file the crate's terminals and icon extent make, and the icon
/// the crate keeps at `terminalsAndIcons/icon.png`, if it has one.
fn terminals_and_icons(ws: &Workspace, fmu: &FmuCrate) -> Result<Vec<Entry>> {
    let xml = describe_with(ws, fmu, Fmi::V3, &["terminals-and-icons"])?;
    if !xml.contains("<fmiTerminalsAndIcons") {
        bail!(
            "{}'s FMI 3.0 description binary printed no terminalsAndIcons.xml",
            fmu.package
        );
    }
    let mut entries = vec![Entry::file(
        "terminalsAndIcons/terminalsAndIcons.xml",
        xml.into_bytes(),
    )];
    let icon = ws.root.join(&fmu.dir).join("terminalsAndIcons/icon.png");
    if icon.exists() {
        let bytes =
            std::fs::read(&icon).with_context(|| format!("cannot read {}", icon.display()))?;
        entries.push(Entry::file("terminalsAndIcons/icon.png", bytes));
    }
    Ok(entries)
}

/// The first value of attribute `name` in `xml`.
fn xml_attribute(xml: &str, name: &str) -> Result<String> {
    xml.split(&format!(" {name}=\""))
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .map(str::to_owned)
        .with_context(|| format!("no {name} attribute"))
}

/// The `modelIdentifier` of an FMI 3.0 description: every interface element must name the
/// same one (one library serves them all), and it must be a C identifier.
fn fmi3_model_identifier(xml: &str) -> Result<String> {
    if !xml.contains("fmiVersion=\"3.0\"") {
        bail!("not an FMI 3.0 model description (no fmiVersion=\"3.0\")");
    }
    let mut found: Vec<&str> = xml
        .split("modelIdentifier=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect();
    found.dedup();
    match found.as_slice() {
        [] => bail!("no modelIdentifier"),
        [id] => {
            check_identifier(id)?;
            Ok((*id).to_owned())
        }
        more => bail!("the interfaces name different modelIdentifiers: {more:?}"),
    }
}

fn check_identifier(id: &str) -> Result<()> {
    let valid = !id.is_empty()
        && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !id.starts_with(|c: char| c.is_ascii_digit());
    if !valid {
        bail!("modelIdentifier {id:?} is not a valid C identifier");
    }
    Ok(())
}

/// The co-simulation `modelIdentifier`, checked to be usable as a file name.
fn model_identifier(description: &ModelDescription) -> Result<&str> {
    let cs = description
        .co_simulation
        .as_ref()
        .context("no <CoSimulation> element")?;
    let id = cs.model_identifier.as_str();
    check_identifier(id)?;
    Ok(id)
}

/// The shared library's bytes, without its static symbol table when `strip` (the program
/// that knows the library's format) is available. Stripping leaves `.dynsym` (the exported
/// fmi2* functions) and a DLL's export table untouched.
fn stripped_library(
    strip: &str,
    library: &Path,
    scratch_dir: &Path,
    identifier: &str,
) -> Result<Vec<u8>> {
    if !library.is_file() {
        bail!("{} was not built", library.display());
    }
    let source = if workspace::on_path(strip) {
        let stripped = scratch_dir.join(format!(".{identifier}.stripped.so"));
        workspace::run(
            std::process::Command::new(strip)
                .arg("--strip-unneeded")
                .arg("-o")
                .arg(&stripped)
                .arg(library),
        )?;
        stripped
    } else {
        println!(
            "xtask fmus: `{strip}` not found, packaging the unstripped {}",
            library.display()
        );
        library.to_path_buf()
    };
    let bytes =
        std::fs::read(&source).with_context(|| format!("cannot read {}", source.display()))?;
    if source != library {
        std::fs::remove_file(&source)?;
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_description::CoSimulation;

    fn with_identifier(id: &str) -> ModelDescription {
        ModelDescription {
            co_simulation: Some(CoSimulation {
                model_identifier: id.to_owned(),
                ..Default::default()
            }),
            ..Default::default()
        }
    }

    #[test]
    fn model_identifier_is_read_from_co_simulation() {
        assert_eq!(
            model_identifier(&with_identifier("LanderGnc")).unwrap(),
            "LanderGnc"
        );
    }

    #[test]
    fn model_identifier_that_is_no_c_identifier_is_refused() {
        for bad in ["", "1abc", "a-b", "../x", "a b"] {
            assert!(model_identifier(&with_identifier(bad)).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn fmi3_identifier_is_the_one_every_interface_names() {
        let both = r#"<fmiModelDescription fmiVersion="3.0" modelName="M">
            <ModelExchange modelIdentifier="LanderPlant"/>
            <CoSimulation modelIdentifier="LanderPlant"/></fmiModelDescription>"#;
        assert_eq!(fmi3_model_identifier(both).unwrap(), "LanderPlant");
        let clash = both.replacen("LanderPlant", "Other", 1);
        assert!(fmi3_model_identifier(&clash).is_err());
        let fmi2 = both.replace("3.0", "2.0");
        assert!(fmi3_model_identifier(&fmi2).is_err());
        let bad = both.replace("LanderPlant", "1x");
        assert!(fmi3_model_identifier(&bad).is_err());
    }

    #[test]
    fn model_exchange_only_description_is_refused() {
        assert!(model_identifier(&ModelDescription::default()).is_err());
    }
}
