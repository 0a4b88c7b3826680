//! `problem` (`src/problem/`): the lines of dotted keys in a problem file's text
//! (`source.rs`) and a count's range check (`limits.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/problem/source.rs`.
mod source {
    use cwsynth::problem::source::SourceMap;

    #[test]
    fn finds_lines_of_nested_and_inline_keys() {
        let text = "name = \"x\"\n\n[mechanism]\ncrank_radius = \"35 mm\"\n[design]\nangle = { min = 0, max = 3 }\n";
        let m = SourceMap::new(text);
        assert_eq!(m.line_of("name"), Some(1));
        assert_eq!(m.line_of("mechanism.crank_radius"), Some(4));
        assert_eq!(m.line_of("design.angle.max"), Some(6));
        // Absent key: its parent's line.
        assert_eq!(m.line_of("mechanism.rod_length"), Some(3));
        let off = text.find("35 mm").unwrap();
        assert_eq!(m.key_at(off), Some("mechanism.crank_radius"));
    }

    #[test]
    fn a_text_toml_edit_rejects_is_indexed_by_lines() {
        // serde reads u64::MAX; toml_edit does not: the error still gets its line.
        let text = "name = \"x\"\n[accuracy]\n# n\nrms_samples = 18446744073709551615\n[[paper]]\nkey = \"a\"\n[[paper]]\nkey = \"b\"\n";
        let m = SourceMap::new(text);
        assert_eq!(m.line_of("accuracy.rms_samples"), Some(4));
        assert_eq!(m.line_of("paper[1].key"), Some(8));
        assert_eq!(m.line_of("accuracy.scan_samples"), Some(2));
    }
}

/// The former unit tests of `src/problem/limits.rs`.
mod limits {
    use cwsynth::problem::limits::{c, check, Count};

    #[test]
    fn check_names_the_key_and_range() {
        const T: &[Count] = &[c("accuracy.rms_samples", 16, 100_000)];
        let e = check(T, "accuracy.rms_samples", u64::MAX.into()).unwrap_err();
        assert_eq!(e.field, "accuracy.rms_samples");
        assert!(e.message.contains("16 to 100000"), "{}", e.message);
    }
}
