//! Colour names of the candidate legends → candidate index. The model answers with a colour
//! name; the candidate's vector is looked up by index, never matched as a string (the
//! reference compared printed vectors and split `"Dark Gray"` at the blank, so its sixth
//! candidate could never be chosen).

/// Normal form of a colour name: lower case, letters and digits only, `grey` spelled `gray`,
/// anything in parentheses dropped (`"Red (X axis)"` → `"red"`).
#[must_use]
pub fn normalise_colour(name: &str) -> String {
    let head = name.split('(').next().unwrap_or(name);
    head.chars()
        .filter(char::is_ascii_alphanumeric)
        .collect::<String>()
        .to_ascii_lowercase()
        .replace("grey", "gray")
}

/// Index of `answer` in `legend` (compared in normal form), if it names one of its colours.
#[must_use]
pub fn colour_index(answer: &str, legend: &[&str]) -> Option<usize> {
    let wanted = normalise_colour(answer);
    if wanted.is_empty() {
        return None;
    }
    legend
        .iter()
        .position(|name| normalise_colour(name) == wanted)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_whatever_the_case_blanks_and_grey_spelling() {
        let legend = ["Yellow", "Dark Gray", "Red"];
        assert_eq!(colour_index("dark gray", &legend), Some(1));
        assert_eq!(colour_index("Dark Grey", &legend), Some(1));
        assert_eq!(colour_index(" DARK-GRAY ", &legend), Some(1));
        assert_eq!(colour_index("Red (X-axis)", &legend), Some(2));
        assert_eq!(colour_index("dark", &legend), None);
        assert_eq!(colour_index("", &legend), None);
        assert_eq!(colour_index("Teal", &legend), None);
    }
}
