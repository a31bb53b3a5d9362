//! Did-you-mean suggestions, shared by every stage.
//!
//! A candidate is suggested when its normalized Damerau–Levenshtein similarity to the name is at
//! least [`THRESHOLD`], or when one contains the other. At most three candidates are returned,
//! the most similar first, ties broken alphabetically so that the output is deterministic.

/// The smallest similarity (0…1) for a candidate to be suggested.
pub const THRESHOLD: f64 = 0.6;

/// The longest name (in characters) that gets suggestions; a longer name, or a candidate
/// longer than this, is not compared (the comparison costs the product of the two lengths).
pub const MAX_NAME_CHARS: usize = 64;

/// The candidates closest to `name`, best first (at most three). A name or candidate longer
/// than [`MAX_NAME_CHARS`] gets or gives none.
pub fn closest<'a, I>(name: &str, candidates: I) -> Vec<String>
where
    I: IntoIterator<Item = &'a str>,
{
    if name.chars().count() > MAX_NAME_CHARS {
        return Vec::new();
    }
    let lower = name.to_lowercase();
    let mut scored: Vec<(f64, String)> = candidates
        .into_iter()
        .filter(|c| !c.is_empty() && *c != name && c.chars().count() <= MAX_NAME_CHARS)
        .filter_map(|c| {
            let cl = c.to_lowercase();
            let mut score = strsim::normalized_damerau_levenshtein(&lower, &cl);
            if lower.len() >= 3 && (cl.contains(&lower) || lower.contains(&cl)) && cl.len() >= 3 {
                score = score.max(THRESHOLD);
            }
            (score >= THRESHOLD).then(|| (score, c.to_string()))
        })
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then_with(|| a.1.cmp(&b.1)));
    scored.dedup_by(|a, b| a.1 == b.1);
    scored.into_iter().take(3).map(|(_, c)| c).collect()
}

/// A help sentence such as "did you mean `sofa-0`?" or "did you mean `a` or `b`?".
pub fn did_you_mean(candidates: &[String]) -> Option<String> {
    match candidates {
        [] => None,
        [one] => Some(format!("did you mean `{one}`?")),
        [rest @ .., last] => {
            let rest: Vec<String> = rest.iter().map(|c| format!("`{c}`")).collect();
            Some(format!("did you mean {} or `{last}`?", rest.join(", ")))
        }
    }
}

/// One fix per candidate: replace the text at `span` with it (an editor's "did you mean"
/// code actions).
pub fn replacements(span: crate::source::Span, candidates: &[String]) -> Vec<super::Fix> {
    candidates
        .iter()
        .map(|c| super::Fix { title: format!("replace with `{c}`"), span, replacement: c.clone() })
        .collect()
}

/// One fix per candidate for a string literal at `span` (quotes included): replace it with
/// the candidate in quotes.
pub fn quoted_replacements(span: crate::source::Span, candidates: &[String]) -> Vec<super::Fix> {
    candidates
        .iter()
        .map(|c| super::Fix {
            title: format!("replace with \"{c}\""),
            span,
            replacement: format!("\"{}\"", crate::parse::escape(c)),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_near_names_only() {
        let names = ["sofa-0", "coffee_table-0", "tv_stand-0"];
        assert_eq!(closest("sofa-1", names), vec!["sofa-0".to_string()]);
        assert!(closest("wardrobe", names).is_empty());
        let long = "sofa-".repeat(4000);
        assert!(closest(&long, [long.as_str(), "sofa-0"]).is_empty());
        assert_eq!(
            did_you_mean(&["a".into(), "b".into()]).as_deref(),
            Some("did you mean `a` or `b`?")
        );
    }
}
