//! "Did you mean ...?" for unknown keys and names.

/// Levenshtein distance between two short strings.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The candidate closest to `word`, if it is close enough to be a plausible typo.
pub fn closest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (edit_distance(word, c), c))
        .min_by_key(|&(d, _)| d)
        .filter(|&(d, c)| d <= (c.len().max(word.len()) / 2).max(2))
        .map(|(_, c)| c)
}

/// Adds a suggestion to serde's "unknown field `x`, expected one of `a`, `b`" (and the same for
/// unknown variants), leaving any other message as it is.
pub(crate) fn with_suggestion(message: &str) -> String {
    for kind in ["unknown field `", "unknown variant `"] {
        let Some(start) = message.find(kind) else {
            continue;
        };
        let rest = &message[start + kind.len()..];
        let Some(end) = rest.find('`') else {
            continue;
        };
        let word = &rest[..end];
        let expected = &rest[end + 1..];
        let candidates: Vec<&str> = expected
            .split('`')
            .skip(1)
            .step_by(2)
            .filter(|s| !s.is_empty())
            .collect();
        if let Some(best) = closest(word, candidates.iter().copied()) {
            let line_end = message[start..]
                .find('\n')
                .map_or(message.len(), |i| start + i);
            return format!(
                "{} (did you mean `{best}`?){}",
                &message[..line_end],
                &message[line_end..]
            );
        }
    }
    message.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_is_levenshtein() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("density", "density"), 0);
    }

    #[test]
    fn suggests_the_closest_field() {
        let m = "unknown field `densty`, expected one of `name`, `density`, `youngs_modulus`";
        assert!(with_suggestion(m).contains("did you mean `density`?"));
        let m = "unknown field `zzzzzzzzzz`, expected `dir`";
        assert!(!with_suggestion(m).contains("did you mean"));
    }
}
