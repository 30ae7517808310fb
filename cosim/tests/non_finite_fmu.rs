//! The FMU of tests/fixtures/non_finite_fmu.c, compiled on the spot: outputs that stop being
//! numbers while every call returns fmi2OK. Shared with the command line's tests
//! (harness/tests/import), which run it through `harness run`.

use std::path::PathBuf;
use std::process::Command;
use tempfile::TempDir;

/// Variables in the order of the fixture's value references, which the ModelStructure's
/// indices (1-based) count.
const DESCRIPTION: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="NonFinite" guid="{non-finite}">
  <CoSimulation modelIdentifier="NonFinite"/>
  <ModelVariables>
    <ScalarVariable name="y" valueReference="0" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="z" valueReference="1" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="v[1]" valueReference="2" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="v[2]" valueReference="3" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="k" valueReference="4" causality="calculatedParameter"
        variability="fixed" initial="calculated"><Real/></ScalarVariable>
    <ScalarVariable name="u" valueReference="5" causality="input"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="t_bad" valueReference="6" causality="parameter" variability="fixed"
        initial="exact"><Real start="0.45"/></ScalarVariable>
    <ScalarVariable name="echo" valueReference="7" causality="output"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs>
      <Unknown index="1" dependencies=""/>
      <Unknown index="2" dependencies=""/>
      <Unknown index="3" dependencies=""/>
      <Unknown index="4" dependencies=""/>
      <Unknown index="8" dependencies="6"/>
    </Outputs>
  </ModelStructure>
</fmiModelDescription>
"#;

/// The fixture compiled with `defines` into an unpacked FMU directory.
pub struct NonFiniteFmu {
    pub dir: PathBuf,
    _temp: TempDir,
}

impl NonFiniteFmu {
    pub fn build(defines: &[&str]) -> Self {
        let temp = TempDir::new().expect("temporary directory");
        let dir = temp.path().join("NonFinite");
        let binaries = dir.join("binaries").join("linux64");
        std::fs::create_dir_all(&binaries).expect("create binaries/linux64");
        std::fs::write(dir.join("modelDescription.xml"), DESCRIPTION).expect("write description");
        // From the workspace root, not this crate's: the harness's tests include this file too.
        let root = crate::common::workspace_root();
        let source = root.join("cosim/tests/fixtures/non_finite_fmu.c");
        // The FMI 2.0 types every C fixture shares live beside the importer's stub FMU.
        let types = root.join("fmi-import/tests/fixtures");
        let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
        let output = Command::new(&compiler)
            .args([
                "-shared", "-fPIC", "-std=c99", "-Wall", "-Wextra", "-Werror", "-o",
            ])
            .arg(binaries.join("NonFinite.so"))
            .arg("-I")
            .arg(&types)
            .arg(&source)
            .args(defines)
            .arg("-lm")
            .output()
            .unwrap_or_else(|error| panic!("cannot run the C compiler `{compiler}`: {error}"));
        assert!(
            output.status.success(),
            "compiling {} failed:\n{}",
            source.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        Self { dir, _temp: temp }
    }
}
