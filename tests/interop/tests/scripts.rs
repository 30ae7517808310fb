//! Every Python script of tests/interop/python is run by some test of this crate.
use interop_tests::workspace_root;

#[test]
fn every_python_script_is_used_by_a_test() {
    let python_dir = workspace_root().join("tests/interop/python");
    let tests_dir = workspace_root().join("tests/interop/tests");
    let mut sources = String::new();
    for entry in std::fs::read_dir(&tests_dir).unwrap() {
        sources += &std::fs::read_to_string(entry.unwrap().path()).unwrap();
    }
    let mut unused = Vec::new();
    for entry in std::fs::read_dir(&python_dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        // results.py is a module the masters import, not a script.
        if name.ends_with(".py") && name != "results.py" && !sources.contains(&name) {
            unused.push(name);
        }
    }
    assert!(unused.is_empty(), "scripts no test runs: {unused:?}");
}
