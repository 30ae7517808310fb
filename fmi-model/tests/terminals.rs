//! Terminals are checked against the declarations: a member must be a declared input or
//! output, one terminal flows one way, names are unique.
use fmi_model::{
    check_declarations, decl, same, Declaration, Experiment, Log, MatchingRule, Member, Model,
    ModelError, StepEnd, Terminal,
};
use serde::{Deserialize, Serialize};

const fn terminal(name: &'static str, members: &'static [Member]) -> Terminal {
    Terminal {
        name,
        matching_rule: MatchingRule::Plug,
        kind: "_test",
        description: "",
        members,
    }
}

macro_rules! model {
    ($name:ident, $terminals:expr) => {
        #[derive(Debug, Clone, Default, Serialize, Deserialize)]
        struct $name {
            u: f64,
            y: f64,
            k: f64,
        }
        impl Model for $name {
            const MODEL_IDENTIFIER: &'static str = "Wired";
            const MODEL_NAME: &'static str = "Wired";
            const VERSION: &'static str = "0";
            const DESCRIPTION: &'static str = "";
            const DEFAULT_EXPERIMENT: Experiment = Experiment {
                start_time: 0.0,
                stop_time: 1.0,
                step_size: 0.1,
                tolerance: None,
            };
            fn declarations() -> &'static [Declaration<Self>] {
                static TABLE: [Declaration<$name>; 3] = [
                    decl!(1, input u: u, "m", "in"),
                    decl!(2, output y: y, "m", "out"),
                    decl!(3, parameter k: k, "1", "gain"),
                ];
                &TABLE
            }
            fn terminals() -> &'static [Terminal] {
                const TERMINALS: &[Terminal] = $terminals;
                TERMINALS
            }
            fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
                Ok(())
            }
            fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
                Ok(StepEnd::Complete)
            }
        }
    };
}

model!(
    Good,
    &[
        terminal("in", &[same("u")]),
        terminal(
            "out",
            &[Member {
                member: "signal",
                variable: "y"
            }]
        )
    ]
);
model!(
    Bad,
    &[
        terminal("a", &[same("nowhere"), same("k")]),
        terminal("b", &[same("u"), same("y")]),
        terminal(
            "b",
            &[
                same("u"),
                Member {
                    member: "u",
                    variable: "u"
                }
            ]
        ),
    ]
);

#[test]
fn terminals_of_declared_inputs_or_outputs_pass() {
    assert_eq!(check_declarations::<Good>(), Ok(()));
}

#[test]
fn every_wrong_member_is_named() {
    let problems = check_declarations::<Bad>().unwrap_err();
    for expected in [
        "terminal a: member nowhere names nowhere, which is not a declared variable",
        "terminal a: member k names k, a Parameter variable: members are inputs or outputs",
        "terminal b: mixes inputs and outputs: a terminal flows one way",
        "terminal b: declared twice",
        "terminal b: member u named twice",
    ] {
        assert!(
            problems.iter().any(|p| p == expected),
            "missing {expected:?} in {problems:#?}"
        );
    }
}
