//! Scene-text edits that must take effect (shared by the test crates through `#[path]`).

/// `text.edit(from, to)` is `text.replace(from, to)` that panics when `from` does not occur:
/// an edit that silently does nothing (the example changed) would test the unedited scene and
/// could pass for the wrong reason.
pub trait Edit {
    fn edit(&self, from: &str, to: &str) -> String;
}

impl Edit for str {
    #[track_caller]
    fn edit(&self, from: &str, to: &str) -> String {
        assert!(self.contains(from), "test bug: the text to edit has no {from:?}:\n{self}");
        self.replace(from, to)
    }
}
