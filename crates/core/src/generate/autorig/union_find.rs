//! Union-find forests over indices, shared by the passes that group cells or parts.

/// The representative of `p` in a union-find forest.
pub(super) fn find(into: &mut [usize], mut p: usize) -> usize {
    while into[p] != p {
        into[p] = into[into[p]];
        p = into[p];
    }
    p
}
