//! Hand-written samples in the layouts of other tools' exporters (see each file's comment).
//! Every asserted value was read off the sample by hand. All four samples, and this crate's
//! rewrite of each, pass fmpy 0.3.32's XSD validation and `validate_model_description`
//! (checked by hand; the fmpy checks of the built FMUs live in the workspace tests).
use std::path::PathBuf;

use model_description::*;

fn sample(name: &str) -> ModelDescription {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/samples")
        .join(name);
    ModelDescription::from_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn real_start(md: &ModelDescription, name: &str) -> Option<f64> {
    match md.variable(name)?.start()? {
        StartValue::Real(value) => Some(value),
        other => panic!("{name}: not a Real start: {other:?}"),
    }
}

#[test]
fn reference_fmus_bouncing_ball() {
    // GIVEN a Reference-FMUs style file with ME and CS, SourceFiles and declared types
    let md = sample("reference_fmus_bouncing_ball.xml");

    // THEN the header and both interfaces are read, the SourceFiles children skipped
    assert_eq!(md.fmi_version, "2.0");
    assert_eq!(md.model_name, "BouncingBall");
    assert_eq!(md.guid, "{4e1c2f0a-5b8d-4c3e-9a71-0d6e2b9f1c33}");
    assert_eq!(md.number_of_event_indicators, Some(1));
    assert_eq!(
        md.model_exchange.as_ref().unwrap().model_identifier,
        "BouncingBall"
    );
    assert_eq!(md.co_simulation_identifier(), Some("BouncingBall"));
    let cs = md.co_simulation().unwrap();
    assert_eq!(cs.can_handle_variable_communication_step_size, Some(true));
    assert_eq!(cs.can_get_and_set_fmu_state, Some(true));
    assert_eq!(cs.can_interpolate_inputs, None);

    // AND units, declared types, categories and the default experiment
    let acceleration = md.unit("m/s2").unwrap().base_unit.clone().unwrap();
    assert_eq!(
        (acceleration.m, acceleration.s, acceleration.kg),
        (Some(1), Some(-2), None)
    );
    assert_eq!(md.type_definitions.as_ref().unwrap().simple_types.len(), 3);
    assert_eq!(
        md.log_categories.as_ref().unwrap().categories[1].name,
        "logStatusError"
    );
    let experiment = md.default_experiment.as_ref().unwrap();
    assert_eq!(
        (experiment.stop_time, experiment.step_size),
        (Some(3.0), Some(0.01))
    );
    assert_eq!(experiment.tolerance, None);

    // AND the eight variables in order, with the declared type's unit resolved
    assert_eq!(md.model_variables.variables.len(), 8);
    assert_eq!(md.index_of("der(v)"), Some(5));
    let h = md.variable("h").unwrap();
    assert_eq!(h.kind(), Some(VariableKind::Real));
    assert_eq!(h.description.as_deref(), Some("Position of the ball"));
    assert_eq!(md.unit_of(h), Some("m"));
    assert_eq!(
        md.variable("der(h)")
            .unwrap()
            .real
            .as_ref()
            .unwrap()
            .derivative,
        Some(2)
    );
    assert_eq!(real_start(&md, "g"), Some(-9.81));
    let e = md.variable("e").unwrap();
    assert_eq!(e.variability_or_default(), Variability::Tunable);
    assert_eq!(e.real.as_ref().unwrap().min, Some(0.5));
    let v_min = md.variable("v_min").unwrap();
    assert_eq!(v_min.causality_or_default(), Causality::Local);
    assert_eq!(v_min.initial_or_default(), Some(Initial::Exact));
    assert_eq!(
        md.variable("time").unwrap().causality,
        Some(Causality::Independent)
    );
    assert_eq!(
        md.outputs().map(|v| v.name.as_str()).collect::<Vec<_>>(),
        ["h", "v"]
    );
    assert_eq!(md.parameters().count(), 2);

    // AND the model structure
    let derivatives = &md.model_structure.derivatives.as_ref().unwrap().unknowns;
    assert_eq!(
        derivatives.iter().map(|u| u.index).collect::<Vec<_>>(),
        [3, 5]
    );
    assert_eq!(derivatives[0].dependencies, None);
    assert_eq!(md.validate(), Ok(()));
}

#[test]
fn openmodelica_heated_mass() {
    // GIVEN an OpenModelica style file: comments, a processing instruction, vendor annotations,
    // variable annotations, and 0/1 booleans
    let md = sample("openmodelica_heated_mass.xml");

    assert_eq!(md.model_name, "HeatedMass");
    assert_eq!(
        md.generation_tool.as_deref(),
        Some("OpenModelica Compiler OMCompiler v1.22.1")
    );
    let cs = md.co_simulation().unwrap();
    assert_eq!(
        cs.needs_execution_tool,
        Some(false),
        "\"0\" is xs:boolean false"
    );
    assert_eq!(
        cs.can_handle_variable_communication_step_size,
        Some(true),
        "\"1\""
    );
    assert_eq!(cs.can_run_asynchronuously, Some(false), "spaces around '='");
    assert_eq!(cs.max_output_derivative_order, Some(1));
    assert_eq!(md.log_categories.as_ref().unwrap().categories.len(), 11);
    assert_eq!(
        md.default_experiment.as_ref().unwrap().tolerance,
        Some(1e-6)
    );
    let watt = md.unit("W").unwrap().base_unit.clone().unwrap();
    assert_eq!((watt.kg, watt.m, watt.s), (Some(1), Some(2), Some(-3)));

    assert_eq!(md.model_variables.variables.len(), 8);
    let t = md.variable("T").unwrap();
    assert_eq!(t.real.as_ref().unwrap().nominal, Some(300.0));
    assert_eq!(t.initial, Some(Initial::Exact));
    let p = md.variable("P_heater").unwrap();
    assert_eq!(p.causality_or_default(), Causality::Input);
    assert_eq!(p.real.as_ref().unwrap().max, Some(1e60));
    assert_eq!(p.initial_or_default(), None, "inputs have no initial");
    assert_eq!(md.inputs().count(), 2);
    assert_eq!(
        md.variable("heaterOn").unwrap().start(),
        Some(StartValue::Boolean(false))
    );
    assert_eq!(
        md.variable("solverSubSteps").unwrap().start(),
        Some(StartValue::Integer(4))
    );
    assert_eq!(
        md.variable("label").unwrap().start(),
        Some(StartValue::String("heater \"A\" <main> & co".to_owned()))
    );
    // Value references are per type: Real, Boolean, Integer and String all use 0.
    assert_eq!(
        md.variables_with_reference(VariableKind::Real, 0)
            .map(|v| v.name.as_str())
            .collect::<Vec<_>>(),
        ["T"]
    );
    assert_eq!(
        md.variables_with_reference(VariableKind::Boolean, 0)
            .count(),
        1
    );

    let derivative = &md.model_structure.derivatives.as_ref().unwrap().unknowns[0];
    assert_eq!(derivative.index, 2);
    assert_eq!(derivative.dependencies.as_deref(), Some("1 3 5 6"));
    assert_eq!(
        md.model_structure
            .initial_unknowns
            .as_ref()
            .unwrap()
            .unknowns
            .len(),
        2
    );
    assert_eq!(md.validate(), Ok(()));
}

#[test]
fn dymola_thermal_sensor() {
    // GIVEN a Dymola style file: one attribute per line, display units, SIunits types,
    // an enumeration type and aliases
    let md = sample("dymola_thermal_sensor.xml");

    assert_eq!(md.model_name, "ThermalSensor");
    assert_eq!(md.model_exchange, None);
    assert_eq!(
        md.co_simulation().unwrap().provides_directional_derivative,
        Some(true)
    );

    let kelvin = md.unit("K").unwrap();
    assert_eq!(kelvin.display_units.len(), 2);
    assert_eq!(kelvin.display_units[0].name, "degC");
    assert_eq!(kelvin.display_units[0].offset, Some(-273.15));
    assert_eq!(kelvin.display_units[0].factor, None);
    assert_eq!(kelvin.display_units[1].factor, Some(1.8));
    assert_eq!(md.unit("rad").unwrap().base_unit, Some(BaseUnit::default()));

    let init = md.simple_type("Modelica.Blocks.Types.Init").unwrap();
    let items = &init.enumeration.as_ref().unwrap().items;
    assert_eq!(
        items
            .iter()
            .map(|i| (i.name.as_str(), i.value))
            .collect::<Vec<_>>(),
        [
            ("NoInit", 1),
            ("SteadyState", 2),
            ("InitialState", 3),
            ("InitialOutput", 4)
        ]
    );
    let temperature = md.simple_type("Modelica.SIunits.Temperature").unwrap();
    assert_eq!(temperature.real.as_ref().unwrap().min, Some(0.0));

    let init_type = md.variable("sensor.initType").unwrap();
    assert_eq!(init_type.kind(), Some(VariableKind::Enumeration));
    assert_eq!(
        init_type.declared_type(),
        Some("Modelica.Blocks.Types.Init")
    );
    assert_eq!(init_type.start(), Some(StartValue::Enumeration(3)));
    assert_eq!(real_start(&md, "sensor.T_sensor"), Some(2.5));
    assert_eq!(
        md.variable("sensor.T_sensor")
            .unwrap()
            .real
            .as_ref()
            .unwrap()
            .min,
        Some(0.001)
    );

    // mass.T and mass.port.T are one Real; the enumeration and the Integer share the
    // Integer value-reference space.
    let names = |kind, vr| {
        md.variables_with_reference(kind, vr)
            .map(|v| v.name.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(
        names(VariableKind::Real, 33_554_432),
        ["mass.T", "mass.port.T"]
    );
    assert_eq!(
        names(VariableKind::Integer, 100_663_296),
        ["sensor.initType", "sensor.initCode"]
    );
    assert_eq!(names(VariableKind::Enumeration, 100_663_296).len(), 2);

    let sensor_t = md.variable("sensor.T").unwrap();
    assert_eq!(md.unit_of(sensor_t), Some("K"));
    assert_eq!(
        sensor_t.real.as_ref().unwrap().display_unit.as_deref(),
        Some("degF")
    );
    assert_eq!(
        md.variable("mass.T").unwrap().causality_or_default(),
        Causality::Local
    );
    assert_eq!(
        md.variable("der(mass.T)").unwrap().initial_or_default(),
        Some(Initial::Calculated)
    );
    let initial_unknowns = &md
        .model_structure
        .initial_unknowns
        .as_ref()
        .unwrap()
        .unknowns;
    assert_eq!(
        initial_unknowns.iter().map(|u| u.index).collect::<Vec<_>>(),
        [3, 5, 8]
    );
    assert_eq!(md.validate(), Ok(()));
}

#[test]
fn pythonfmu_slave() {
    // GIVEN a pythonfmu style file: no encoding declared, tabs, no units or types
    let md = sample("pythonfmu_slave.xml");

    assert_eq!(md.guid, "2f1b8c4e-9d3a-4f6b-b0e7-5a1c3d9e8f70");
    assert_eq!(md.author.as_deref(), Some("md"));
    assert_eq!(md.variable_naming_convention.as_deref(), Some("structured"));
    assert_eq!(md.co_simulation().unwrap().needs_execution_tool, Some(true));
    assert_eq!(md.unit_definitions, None);
    assert_eq!(md.type_definitions, None);

    let kinds: Vec<_> = md.variables().map(|v| v.kind().unwrap()).collect();
    assert_eq!(
        kinds,
        [
            VariableKind::Real,
            VariableKind::Real,
            VariableKind::Integer,
            VariableKind::Boolean,
            VariableKind::String
        ]
    );
    assert_eq!(
        md.variable("realIn").unwrap().start(),
        Some(StartValue::Real(22.0))
    );
    assert_eq!(
        md.variable("intOut").unwrap().start(),
        Some(StartValue::Integer(-3))
    );
    assert_eq!(
        md.variable("boolOut").unwrap().start(),
        Some(StartValue::Boolean(false))
    );
    assert_eq!(
        md.variable("stringOut").unwrap().start(),
        Some(StartValue::String(String::new()))
    );
    assert_eq!(md.outputs().count(), 4);
    assert_eq!(md.model_structure.initial_unknowns, None);
    assert_eq!(md.validate(), Ok(()));
}

#[test]
fn every_sample_survives_a_write_read_cycle() {
    for name in [
        "reference_fmus_bouncing_ball.xml",
        "openmodelica_heated_mass.xml",
        "dymola_thermal_sensor.xml",
        "pythonfmu_slave.xml",
    ] {
        let read = sample(name);
        let written = read.to_xml().unwrap();
        let back = ModelDescription::from_xml(&written).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back, read, "{name}");
    }
}
