//! Notes: what a run has to say besides its numbers (a route that changed, a
//! point removed, an answer at the round-off floor), in the order they arose.
//! Every layer pushes into the one sink it is handed; the drivers hand the
//! notes to their observer, and the command line prints them on stderr. The
//! library itself prints nothing.

/// The sink of a run's notes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Notes(Vec<String>);

impl Notes {
    /// Adds a note (its text says whether it is a `note:` or a `warning:`).
    pub fn push(&mut self, note: impl Into<String>) {
        self.0.push(note.into());
    }

    /// The notes pushed since the last call, in order.
    pub fn take(&mut self) -> Vec<String> {
        std::mem::take(&mut self.0)
    }
}
