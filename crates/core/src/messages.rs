//! Small helpers that format parts of error messages.

/// The first `max` indices, comma-separated, with "…" when there are more.
pub fn list_first(indices: &[usize], max: usize) -> String {
    let mut listed = indices
        .iter()
        .take(max)
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    if indices.len() > max {
        listed.push_str(", …");
    }
    listed
}

#[cfg(test)]
mod tests {
    #[test]
    fn lists_are_cut_with_an_ellipsis() {
        assert_eq!(super::list_first(&[1, 2, 3], 5), "1, 2, 3");
        assert_eq!(super::list_first(&[1, 2, 3], 2), "1, 2, …");
    }
}
