//! Algebraic loops: a cycle of connections in which every FMU passes its input straight to the
//! output that feeds the next connection. A fixed-step master without an iteration cannot
//! solve one, and the result of running it anyway depends on the exchange order, so the
//! system is refused, naming the cycle.
//!
//! Which output depends on which input is read from the model description's
//! `ModelStructure/Outputs`; FMI 2.0 says an output without a `dependencies` attribute (or not
//! listed at all) depends on every input. Such an *implicit* dependency is only a worst case
//! (pythonfmu and many exporters write no `dependencies` at all), so a loop is refused only
//! when every hop in it is declared; a loop that needs an implicit hop is reported as a
//! warning and the exchange order breaks it, as in every fixed-step master.
use model_description::{Causality, ModelDescription};
use std::collections::{HashMap, HashSet};

/// Inputs each output depends on, by name; `None` = every input.
#[derive(Debug, Clone, Default)]
pub struct Feedthrough {
    outputs: HashMap<String, Option<HashSet<String>>>,
}

impl Feedthrough {
    pub fn from_description(description: &ModelDescription) -> Self {
        let variables = &description.model_variables.variables;
        let name_at = |index: u32| {
            (index as usize)
                .checked_sub(1)
                .and_then(|i| variables.get(i))
        };
        let mut outputs = HashMap::new();
        let listed = description
            .model_structure
            .outputs
            .as_ref()
            .map(|list| list.unknowns.as_slice())
            .unwrap_or_default();
        for unknown in listed {
            let Some(output) = name_at(unknown.index) else {
                continue;
            };
            let inputs = unknown.dependencies.as_ref().map(|list| {
                list.split_whitespace()
                    .filter_map(|index| index.parse().ok().and_then(name_at))
                    .filter(|v| v.causality_or_default() == Causality::Input)
                    .map(|v| v.name.clone())
                    .collect()
            });
            outputs.insert(output.name.clone(), inputs);
        }
        Self { outputs }
    }

    /// Whether `output` may change when `input` changes within one communication point;
    /// with `declared_only`, an output without a `dependencies` list counts as independent.
    pub fn depends(&self, output: &str, input: &str, declared_only: bool) -> bool {
        match self.outputs.get(output) {
            Some(Some(inputs)) => inputs.contains(input),
            Some(None) | None => !declared_only,
        }
    }
}

/// A scalar connection between `instance.variable` ends, with its instances split out.
#[derive(Debug, Clone)]
pub struct Edge<'a> {
    pub from_instance: &'a str,
    pub from_variable: &'a str,
    pub to_instance: &'a str,
    pub to_variable: &'a str,
}

/// The first algebraic loop found, as the connections it runs through, in order; `feedthrough`
/// gives each instance's dependencies (see [`Feedthrough::depends`] for `declared_only`).
pub fn find_loop<'a>(
    edges: &[Edge<'a>],
    feedthrough: &dyn Fn(&str) -> Option<&'a Feedthrough>,
    declared_only: bool,
) -> Option<Vec<usize>> {
    // Connection j follows connection i when j leaves the instance i enters, from an output
    // that depends on the input i sets.
    let next: Vec<Vec<usize>> = edges
        .iter()
        .map(|into| {
            edges
                .iter()
                .enumerate()
                .filter(|(_, out)| out.from_instance == into.to_instance)
                .filter(|(_, out)| {
                    feedthrough(into.to_instance).is_none_or(|f| {
                        f.depends(out.from_variable, into.to_variable, declared_only)
                    })
                })
                .map(|(j, _)| j)
                .collect()
        })
        .collect();
    // Depth-first search with an explicit stack; a back edge to a connection on the current
    // path closes a cycle.
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        OnPath,
        Done,
    }
    let mut mark = vec![Mark::New; edges.len()];
    for root in 0..edges.len() {
        if mark[root] != Mark::New {
            continue;
        }
        let mut path = vec![root];
        let mut cursor = vec![0usize];
        mark[root] = Mark::OnPath;
        while let Some(&node) = path.last() {
            let k = cursor.last_mut().expect("one cursor per path entry");
            if let Some(&child) = next[node].get(*k) {
                *k += 1;
                match mark[child] {
                    Mark::OnPath => {
                        let start = path.iter().position(|&n| n == child).expect("on path");
                        return Some(path[start..].to_vec());
                    }
                    Mark::New => {
                        mark[child] = Mark::OnPath;
                        path.push(child);
                        cursor.push(0);
                    }
                    Mark::Done => {}
                }
            } else {
                mark[node] = Mark::Done;
                path.pop();
                cursor.pop();
            }
        }
    }
    None
}

/// `a.y -> b.u ~> b.z -> a.v ~> a.y`: `->` a connection, `~>` an output that depends on the
/// input before it.
pub fn describe(edges: &[Edge], cycle: &[usize]) -> String {
    let mut text = String::new();
    for &i in cycle {
        let e = &edges[i];
        text.push_str(&format!(
            "{}.{} -> {}.{} ~> ",
            e.from_instance, e.from_variable, e.to_instance, e.to_variable
        ));
    }
    let first = &edges[cycle[0]];
    text.push_str(&format!("{}.{}", first.from_instance, first.from_variable));
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge<'a>(from: &'a str, to: &'a str) -> Edge<'a> {
        let (fi, fv) = from.split_once('.').unwrap();
        let (ti, tv) = to.split_once('.').unwrap();
        Edge {
            from_instance: fi,
            from_variable: fv,
            to_instance: ti,
            to_variable: tv,
        }
    }

    fn only(pairs: &[(&str, &[&str])]) -> Feedthrough {
        Feedthrough {
            outputs: pairs
                .iter()
                .map(|(o, inputs)| {
                    (
                        o.to_string(),
                        Some(inputs.iter().map(|i| i.to_string()).collect()),
                    )
                })
                .collect(),
        }
    }

    #[test]
    fn a_loop_through_two_feedthrough_units_is_found_and_named() {
        let edges = [edge("a.y", "b.u"), edge("b.z", "a.v")];
        let all = Feedthrough::default();
        let cycle = find_loop(&edges, &|_| Some(&all), false).expect("a loop");
        let text = describe(&edges, &cycle);
        assert!(
            text == "a.y -> b.u ~> b.z -> a.v ~> a.y" || text == "b.z -> a.v ~> a.y -> b.u ~> b.z",
            "{text}"
        );
    }

    #[test]
    fn an_output_independent_of_its_inputs_breaks_the_loop() {
        let edges = [edge("plant.r", "gnc.r"), edge("gnc.f", "plant.f")];
        let plant = only(&[("r", &[])]);
        let gnc = only(&[("f", &["r"])]);
        let lookup = |instance: &str| Some(if instance == "plant" { &plant } else { &gnc });
        assert!(find_loop(&edges, &lookup, false).is_none());
        // The same wiring with a plant that declares direct feedthrough is a loop.
        let feedthrough_plant = only(&[("r", &["f"])]);
        let lookup = |instance: &str| {
            Some(if instance == "plant" {
                &feedthrough_plant
            } else {
                &gnc
            })
        };
        assert!(find_loop(&edges, &lookup, true).is_some());
    }

    #[test]
    fn a_unit_wired_to_itself_is_a_loop_only_through_a_dependency() {
        let edges = [edge("gnc.f", "gnc.m")];
        let depends = only(&[("f", &["m"])]);
        assert_eq!(find_loop(&edges, &|_| Some(&depends), true), Some(vec![0]));
        let independent = only(&[("f", &["r"])]);
        assert_eq!(find_loop(&edges, &|_| Some(&independent), false), None);
    }

    #[test]
    fn an_implicit_dependency_makes_a_loop_possible_but_not_declared() {
        // A plant that lists no dependencies (pythonfmu writes none) beside a feedthrough
        // controller: a loop in the worst case, none that is declared.
        let edges = [edge("plant.r", "gnc.r"), edge("gnc.f", "plant.f")];
        let silent_plant = Feedthrough::default();
        let gnc = only(&[("f", &["r"])]);
        let lookup = |instance: &str| {
            Some(if instance == "plant" {
                &silent_plant
            } else {
                &gnc
            })
        };
        assert!(find_loop(&edges, &lookup, false).is_some());
        assert!(find_loop(&edges, &lookup, true).is_none());
    }
}
