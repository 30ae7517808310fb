//! The FMI 3.0 FMUs in the `fmi` crate's FMI 3.0 importer (rust-fmi 0.8): its own schema
//! reader and its own bindings to the official FMI 3.0 headers load, initialize and step
//! them, read the array outputs, and run the plant as Model Exchange.
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation, Common, Fmi3Model, Fmi3Res, GetSet, ModelExchange};
use fmi::traits::FmiImport;
use system_tests::{fmi3_fmu_path, fmi3_fmus};

fn import(model_identifier: &str) -> Fmi3Import {
    fmi::import::from_path(fmi3_fmu_path(model_identifier)).unwrap_or_else(|e| {
        panic!("the fmi crate cannot import the FMI 3.0 {model_identifier}: {e}");
    })
}

/// A value reference by name, from the fmi crate's reading of the XML.
fn vr(import: &Fmi3Import, name: &str) -> u32 {
    import
        .model_description()
        .model_variables
        .iter_abstract()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference()
}

#[test]
fn every_fmi3_fmu_loads_initializes_and_steps_in_the_fmi3_importer() {
    for fmu in fmi3_fmus() {
        let import = import(&fmu);
        let mut instance = import
            .instantiate_cs("fmi-crate", false, false, false, false, &[])
            .unwrap();
        assert_eq!(instance.get_version(), "3.0");
        instance.enter_initialization_mode(None, 0.0, None).unwrap();
        instance.exit_initialization_mode().unwrap();
        let h = 0.01;
        for i in 0..20 {
            let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
            let status = instance.do_step(
                f64::from(i) * h,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            );
            assert!(
                matches!(status, Ok(Fmi3Res::OK)),
                "{fmu} step {i}: {status:?}"
            );
            assert!(!terminate && !early);
            assert!((last - f64::from(i + 1) * h).abs() < 1e-12);
        }
        instance.terminate().unwrap();
    }
}

#[test]
fn the_plant_falls_as_an_array_output_says_in_co_simulation_and_model_exchange() {
    let import = import("LanderPlant");
    let r_nue = vr(&import, "r_nue");
    let g = 1.62;
    // Co-Simulation: 1 s of free fall, r_nue read as one 3-element array
    let mut cs = import
        .instantiate_cs("cs", false, false, false, false, &[])
        .unwrap();
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    for i in 0..10 {
        let (mut e, mut t, mut r, mut last) = (false, false, false, 0.0);
        cs.do_step(
            f64::from(i) * 0.1,
            0.1,
            true,
            &mut e,
            &mut t,
            &mut r,
            &mut last,
        )
        .unwrap();
    }
    let mut position = [f64::NAN; 3];
    cs.get_float64(&[r_nue], &mut position).unwrap();
    assert!(
        (position[1] - (800.0 - 0.5 * g)).abs() < 1e-9,
        "{position:?}"
    );
    assert_eq!((position[0], position[2]), (0.0, 0.0));

    // Model Exchange: the importer sees 18 states and 2 event indicators, and the
    // derivative of the altitude state is the velocity, of the vertical velocity -g.
    let mut me = import.instantiate_me("me", false, false).unwrap();
    me.enter_initialization_mode(None, 0.0, None).unwrap();
    me.exit_initialization_mode().unwrap();
    assert_eq!(me.get_number_of_continuous_states().unwrap(), 18);
    assert_eq!(me.get_number_of_event_indicators().unwrap(), 2);
    me.enter_continuous_time_mode().unwrap();
    let mut dx = [f64::NAN; 18];
    me.get_continuous_state_derivatives(&mut dx).unwrap();
    assert_eq!((dx[1], dx[4]), (0.0, -g));
    let mut z = [f64::NAN; 2];
    me.get_event_indicators(&mut z).unwrap();
    assert_eq!(
        z,
        [800.0, 300.0],
        "altitude and propellant above the dry mass"
    );
}
