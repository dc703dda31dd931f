//! Compressed rows (ground floor): data laid out row after row, row `r`
//! between `offsets[r]` and `offsets[r + 1]` (the bonds of each owner, the
//! columns of each point), split into one mutable slice per row so that
//! threads fill the rows without sharing memory.

/// Splits `data` into consecutive mutable chunks at `offsets` (length n + 1, starting at 0).
pub fn split_at_offsets<'a, T>(mut data: &'a mut [T], offsets: &[usize]) -> Vec<&'a mut [T]> {
    let mut chunks = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = data.split_at_mut(w[1] - w[0]);
        chunks.push(head);
        data = tail;
    }
    chunks
}
