//! Splitting names into lower-case tokens and matching them against keyword lists.

/// Splits `text` into lower-case alphanumeric tokens, also at camelCase boundaries
/// (`DoorHandle_01` -> `door`, `handle`, `01`).
pub fn tokens(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    let mut prev_lower = false;
    for ch in text.chars() {
        if ch.is_ascii_alphanumeric() {
            if ch.is_ascii_uppercase() && prev_lower && !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
            prev_lower = ch.is_ascii_lowercase();
            current.push(ch.to_ascii_lowercase());
        } else {
            prev_lower = false;
            if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// Whether a token matches a keyword: exactly for keywords of up to 3 letters, as a prefix for
/// longer ones (`wooden` matches `wood`, `handles` matches `handle`).
pub fn token_matches(token: &str, keyword: &str) -> bool {
    if keyword.len() <= 3 {
        token == keyword
    } else {
        token.starts_with(keyword)
    }
}

/// The first keyword (in list order) that any token matches.
pub fn first_match<'k>(tokens: &[String], keywords: &[&'k str]) -> Option<&'k str> {
    keywords
        .iter()
        .copied()
        .find(|k| tokens.iter().any(|t| token_matches(t, k)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_split_on_punctuation_and_camel_case() {
        assert_eq!(tokens("DoorHandle_01"), ["door", "handle", "01"]);
        assert_eq!(tokens("wood-oak.002"), ["wood", "oak", "002"]);
        assert!(tokens("  ").is_empty());
    }

    #[test]
    fn short_keywords_match_exactly_and_long_ones_by_prefix() {
        assert!(token_matches("wooden", "wood"));
        assert!(!token_matches("absolute", "abs"));
        assert!(token_matches("abs", "abs"));
        let t = tokens("Metal_Steel");
        assert_eq!(first_match(&t, &["wood", "steel"]), Some("steel"));
    }
}
