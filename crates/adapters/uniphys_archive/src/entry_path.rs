//! Entry names as safe relative paths: what is unpacked stays inside the asset's folder.

/// Components at most in an entry's path.
const MAX_DEPTH: usize = 32;
/// Bytes at most in one component (the usual file-system limit).
const MAX_COMPONENT_BYTES: usize = 255;

/// The components of entry `name` (`/`-separated; empty and `.` components dropped), or why it
/// is refused: an absolute path, a `..` component, a backslash or drive letter (a Windows path
/// that may mean something else on another system), a control character, too deep or too long.
///
/// # Errors
/// The reason, for the submitter.
pub fn safe_components(name: &str) -> Result<Vec<String>, String> {
    if name.starts_with('/') {
        return Err("an absolute path; entries must be relative to the archive".into());
    }
    if name.contains('\\') {
        return Err("a backslash in the path; use / between folders".into());
    }
    if name.chars().any(char::is_control) {
        return Err("a control character in the path".into());
    }
    let components: Vec<String> = name
        .split('/')
        .filter(|c| !c.is_empty() && *c != ".")
        .map(str::to_owned)
        .collect();
    if components.is_empty() {
        return Err("an empty path".into());
    }
    if components.iter().any(|c| c == "..") {
        return Err("a .. component, which leads out of the asset's folder".into());
    }
    if components[0].len() == 2 && components[0].ends_with(':') {
        return Err("a drive letter; entries must be relative to the archive".into());
    }
    if components.len() > MAX_DEPTH {
        return Err(format!("more than {MAX_DEPTH} folders deep"));
    }
    if components.iter().any(|c| c.len() > MAX_COMPONENT_BYTES) {
        return Err(format!("a name longer than {MAX_COMPONENT_BYTES} bytes"));
    }
    Ok(components)
}

#[cfg(test)]
mod tests {
    use super::safe_components;

    #[test]
    fn relative_paths_pass_and_escapes_are_refused() {
        assert_eq!(
            safe_components("./45213/textured_objs/a.obj").expect("safe"),
            ["45213", "textured_objs", "a.obj"]
        );
        assert_eq!(safe_components("a//b/").expect("safe"), ["a", "b"]);
        for (bad, why) in [
            ("/etc/passwd", "absolute"),
            ("a/../../b", ".."),
            ("..", ".."),
            ("a\\b.obj", "backslash"),
            ("C:/x.obj", "drive"),
            ("a\u{0}b", "control"),
            ("./", "empty"),
        ] {
            let reason = safe_components(bad).expect_err(bad);
            assert!(reason.contains(why), "{bad}: {reason}");
        }
        assert!(safe_components(&"a/".repeat(40)).is_err());
        assert!(safe_components(&"a".repeat(300)).is_err());
    }
}
