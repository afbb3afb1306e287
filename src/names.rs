//! Names: suggestions for misspelt ones.

/// The candidate closest to `name` by edit distance, if it is close enough
/// to be a plausible misspelling (at most a third of its characters, plus one).
///
/// ```
/// assert_eq!(bcifs::suggest("edg", ["edge", "vertex"]), Some("edge".into()));
/// assert_eq!(bcifs::suggest("zzzzzz", ["edge", "vertex"]), None);
/// ```
pub fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let limit = (name.chars().count() / 3).max(1) + 1;
    candidates
        .into_iter()
        .map(|c| (strsim::levenshtein(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names() {
        assert_eq!(suggest("T1", ["T0", "b1", "x"]), Some("T0".into()));
        assert_eq!(suggest("edg", ["edge", "vertex"]), Some("edge".into()));
        assert_eq!(suggest("zzzzzz", ["edge", "vertex"]), None);
    }
}
