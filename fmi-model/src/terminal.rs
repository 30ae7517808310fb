//! Terminals: named groups of a model's variables that a tool connects to another model's
//! group in one step (FMI 3.0 `terminalsAndIcons/terminalsAndIcons.xml`). A terminal names
//! each member by a `member` name that matches across models and by the declared variable
//! that carries it here; members are matched by name (`plug`, `bus`), so two models that
//! call a signal differently still connect.
use crate::declaration::{Causality, Declaration};
use crate::model::Model;
use std::collections::HashSet;

/// How a tool matches the members of two connected terminals (FMI 3.0, `matchingRule`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MatchingRule {
    /// Every member of this terminal must find its match.
    Plug,
    /// Members that find no match are left unconnected.
    Bus,
}

impl MatchingRule {
    pub fn name(self) -> &'static str {
        match self {
            MatchingRule::Plug => "plug",
            MatchingRule::Bus => "bus",
        }
    }
}

/// One member: its name across models and the declared variable that carries it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Member {
    pub member: &'static str,
    pub variable: &'static str,
}

/// A group of variables connected as one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Terminal {
    pub name: &'static str,
    pub matching_rule: MatchingRule,
    /// What the group is, in reverse domain notation, the same in every model that has one.
    pub kind: &'static str,
    pub description: &'static str,
    pub members: &'static [Member],
}

/// A member whose name is its variable's name, the usual case in the lander's FMUs.
pub const fn same(variable: &'static str) -> Member {
    Member {
        member: variable,
        variable,
    }
}

/// Members whose names are their variables' names.
pub const fn same_names<const N: usize>(names: [&'static str; N]) -> [Member; N] {
    let mut members = [same(""); N];
    let mut i = 0;
    while i < N {
        members[i] = same(names[i]);
        i += 1;
    }
    members
}

/// Checks `M`'s terminals against its declarations: every member is a declared input or
/// output (FMI 3.0 restricts signal members to inputs, outputs and parameters; a group that
/// is connected is one of the first two), all members of a terminal share one causality,
/// member and terminal names are unique. `Ok` or every problem found.
pub fn check_terminals<M: Model>() -> Result<(), Vec<String>> {
    let declarations = M::declarations();
    let mut problems = Vec::new();
    let mut terminal_names = HashSet::new();
    for terminal in M::terminals() {
        let mut problem =
            |text: String| problems.push(format!("terminal {}: {text}", terminal.name));
        if !terminal_names.insert(terminal.name) {
            problem("declared twice".into());
        }
        if terminal.members.is_empty() {
            problem("has no members".into());
        }
        let mut member_names = HashSet::new();
        let mut causalities = HashSet::new();
        for member in terminal.members {
            if !member_names.insert(member.member) {
                problem(format!("member {} named twice", member.member));
            }
            match declarations.iter().find(|d| d.name == member.variable) {
                None => problem(format!(
                    "member {} names {}, which is not a declared variable",
                    member.member, member.variable
                )),
                Some(Declaration {
                    causality: causality @ (Causality::Input | Causality::Output),
                    ..
                }) => {
                    causalities.insert(*causality);
                }
                Some(d) => problem(format!(
                    "member {} names {}, a {:?} variable: members are inputs or outputs",
                    member.member, d.name, d.causality
                )),
            }
        }
        if causalities.len() > 1 {
            problem("mixes inputs and outputs: a terminal flows one way".into());
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems)
    }
}
