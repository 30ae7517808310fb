//! "Did you mean" for misspelt instance, variable and connector names.

/// The candidate closest to `wrong`, if it is close enough to be a plausible typo: at most a
/// third of the name's characters edited (at least one, at most three).
pub fn closest<'a>(wrong: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let allowed = (wrong.chars().count() / 3).clamp(1, 3);
    candidates
        .into_iter()
        .filter(|candidate| *candidate != wrong)
        .map(|candidate| (strsim::damerau_levenshtein(wrong, candidate), candidate))
        .filter(|&(distance, _)| distance <= allowed)
        .min_by_key(|&(distance, candidate)| (distance, candidate))
        .map(|(_, candidate)| candidate)
}

/// `" (did you mean 'x'?)"`, or nothing.
pub fn hint<'a>(wrong: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(wrong, candidates)
        .map(|name| format!(" (did you mean '{name}'?)"))
        .unwrap_or_default()
}

/// The names a user may write for the variables of a model: each scalar name and, for the
/// elements of an array (`r_nue[1]`), the array's name (`r_nue`).
pub fn variable_names(description: &model_description::ModelDescription) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for variable in description.variables() {
        names.push(&variable.name);
        if let Some((base, _)) = variable.name.split_once('[') {
            if !names.contains(&base) {
                names.push(base);
            }
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transposition_or_one_extra_letter_is_suggested() {
        let names = ["r_nue", "v_nue", "phi_cmd", "phi_cmd_time"];
        assert_eq!(closest("r_neu", names), Some("r_nue"));
        assert_eq!(closest("phi_cmdd", names), Some("phi_cmd"));
        assert_eq!(hint("phi_cmdd", names), " (did you mean 'phi_cmd'?)");
    }

    #[test]
    fn an_unrelated_name_gets_no_suggestion() {
        assert_eq!(closest("altitude", ["r_nue", "v_nue"]), None);
        assert_eq!(hint("x", ["r_nue"]), "");
    }
}
