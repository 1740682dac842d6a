//! Comments cite the repository's own docs and decisions, never a
//! tracker's "issue N": a clone has no tracker, so such a comment points
//! nowhere. The rule, on the text of every line of Rust: the part after
//! `//` (line and doc comments) and every line of a `/* .. */` block must
//! not hold the word `issue` or `issues` followed by a number (`issue 8`,
//! `issues 18 and 20`, `issue #3`, any case).

/// The 1-based lines of `text` whose comment cites an issue number,
/// also where the word ends one comment line and the number starts the
/// next.
pub fn issue_citations(text: &str) -> Vec<usize> {
    let comments = comment_lines(text);
    let mut found = Vec::new();
    for (k, (n, comment)) in comments.iter().enumerate() {
        let next = comments
            .get(k + 1)
            .filter(|(m, _)| *m == n + 1)
            .map(|(_, c)| c.trim_start_matches(['/', '!', '*', ' ']));
        let joined = next.map_or_else(|| comment.to_string(), |c| format!("{comment} {c}"));
        if cites_an_issue(comment) || (ends_with_the_word(comment) && cites_an_issue(&joined)) {
            found.push(*n);
        }
    }
    found
}

/// Whether `comment` ends with `issue` or `issues`.
fn ends_with_the_word(comment: &str) -> bool {
    let lower = comment.trim_end().to_ascii_lowercase();
    lower.ends_with("issue") || lower.ends_with("issues")
}

/// The comment part of every line that has one: (1-based line, text).
fn comment_lines(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut in_block = false;
    for (n, line) in text.lines().enumerate() {
        let comment = if in_block {
            Some(line)
        } else {
            line.find("//")
                .map(|i| &line[i..])
                .or_else(|| line.find("/*").map(|i| &line[i..]))
        };
        if line.contains("/*") {
            in_block = !line.contains("*/");
        } else if in_block && line.contains("*/") {
            in_block = false;
        }
        if let Some(c) = comment {
            out.push((n + 1, c));
        }
    }
    out
}

/// Whether `text` holds `issue` or `issues` (any case) followed by a
/// number, with at most a `#` and spaces between.
pub fn cites_an_issue(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    lower.match_indices("issue").any(|(i, m)| {
        let before_ok = !lower[..i].ends_with(|c: char| c.is_ascii_alphanumeric());
        let rest = lower[i + m.len()..]
            .strip_prefix('s')
            .unwrap_or(&lower[i + m.len()..]);
        let rest = rest.trim_start_matches([' ', '#']);
        before_ok && rest.starts_with(|c: char| c.is_ascii_digit())
    })
}

#[test]
fn an_issue_number_in_a_comment_is_found() {
    let src = "//! Soak test (issue 8): many clients.\nfn f() {} // issues 18 and 20\n\
               /// Issue #3, point 6.\nconst A: u8 = 1;\n/* see\n   issue 12 */\n";
    assert_eq!(issue_citations(src), [1, 2, 3, 6]);
    let wrapped = "//! the API named in issue\n//! 7: a raw offset\n";
    assert_eq!(issue_citations(wrapped), [1]);
}

#[test]
fn other_uses_of_the_word_are_left_alone() {
    let src = "// an issue of the wire: 3 bytes\nlet s = \"issue 8\";\n// tissue 5\n\
               // decision 120 (docs/decisions.md)\n";
    assert_eq!(issue_citations(src), Vec::<usize>::new());
}
