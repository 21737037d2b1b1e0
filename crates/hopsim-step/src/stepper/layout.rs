//! Where each unknown and each right-hand side of a step sits: the contact LCP of
//! docs/physics.md §4.3 (with the joint stops of §7.2), its frictionless fallback (§4.5), and
//! the rows solved with the mass matrix's factor. Every function that writes or reads one
//! of them goes through [`Layout`], so the offsets are written down once.

/// The sizes of one step's problem: `k` closed contacts and `l` closed joint stops.
///
/// The frictional LCP has `3k + l` rows, in blocks
///
/// | rows | unknown `z` | `w` |
/// |---|---|---|
/// | [`Layout::normal`] `c` | `Λ_N` | `ξ_N` |
/// | [`Layout::sliding`] `c` | `Λ_R = Λ_T + μΛ_N` | `ξ_R = ξ_T + ξ_L` |
/// | [`Layout::cone`] `c` | `ξ_L / s` | `s Λ_L` (`s`: the cone rows' scale) |
/// | [`Layout::limit`] `r` | `Λ_J` | `ξ_J` |
///
/// The frictionless fallback keeps the normal rows and the stops: `k + l` rows
/// ([`Layout::fallback_limit`]). The rows solved with `M`'s factor are `h Δt + impulses`,
/// then `w_N` and `w_T` of each contact, then `w_J` of each stop
/// ([`Layout::solved_normal`], …), `1 + 2k + l` rows of length `n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// Closed contacts `k` (terrain and body–body).
    pub contacts: usize,
    /// Closed joint stops `l`.
    pub limits: usize,
}

impl Layout {
    /// Rows of the frictional LCP: `3k + l`.
    #[inline(always)]
    pub fn size(&self) -> usize {
        3 * self.contacts + self.limits
    }

    /// Contact `c`'s normal row: `ξ_N ⟂ Λ_N`.
    #[inline(always)]
    pub fn normal(&self, c: usize) -> usize {
        c
    }

    /// Contact `c`'s sliding row: `ξ_R ⟂ Λ_R`.
    #[inline(always)]
    pub fn sliding(&self, c: usize) -> usize {
        self.contacts + c
    }

    /// Contact `c`'s friction-cone row: `s Λ_L ⟂ ξ_L / s`.
    #[inline(always)]
    pub fn cone(&self, c: usize) -> usize {
        2 * self.contacts + c
    }

    /// Stop `r`'s row: `ξ_J ⟂ Λ_J`.
    #[inline(always)]
    pub fn limit(&self, r: usize) -> usize {
        3 * self.contacts + r
    }

    /// Rows of the frictionless fallback: `k + l`.
    #[inline(always)]
    pub fn fallback_size(&self) -> usize {
        self.contacts + self.limits
    }

    /// Stop `r`'s row in the frictionless fallback (after the `k` normal rows).
    #[inline(always)]
    pub fn fallback_limit(&self, r: usize) -> usize {
        self.contacts + r
    }

    /// Rows solved with `M`'s factor: `1 + 2k + l`.
    #[inline(always)]
    pub fn solved_rows(&self) -> usize {
        1 + 2 * self.contacts + self.limits
    }

    /// The solved row of contact `c`'s `w_N` (`G w_N` after the solve).
    #[inline(always)]
    pub fn solved_normal(&self, c: usize) -> usize {
        1 + c
    }

    /// The solved row of contact `c`'s `w_T`.
    #[inline(always)]
    pub fn solved_tangent(&self, c: usize) -> usize {
        1 + self.contacts + c
    }

    /// The solved row of stop `r`'s `w_J`.
    #[inline(always)]
    pub fn solved_limit(&self, r: usize) -> usize {
        1 + 2 * self.contacts + r
    }
}

/// Index of entry `(row, col)` of a column-major matrix with leading dimension `ld`.
#[inline(always)]
pub(crate) fn at(ld: usize, row: usize, col: usize) -> usize {
    col * ld + row
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blocks_tile_each_problem_without_gaps_or_overlaps() {
        for contacts in 0..5 {
            for limits in 0..4 {
                let l = Layout { contacts, limits };
                let mut lcp: Vec<usize> = (0..contacts)
                    .flat_map(|c| [l.normal(c), l.sliding(c), l.cone(c)])
                    .chain((0..limits).map(|r| l.limit(r)))
                    .collect();
                lcp.sort_unstable();
                assert_eq!(lcp, (0..l.size()).collect::<Vec<_>>());
                let mut fallback: Vec<usize> = (0..contacts)
                    .map(|c| l.normal(c))
                    .chain((0..limits).map(|r| l.fallback_limit(r)))
                    .collect();
                fallback.sort_unstable();
                assert_eq!(fallback, (0..l.fallback_size()).collect::<Vec<_>>());
                let mut solved: Vec<usize> = std::iter::once(0)
                    .chain((0..contacts).flat_map(|c| [l.solved_normal(c), l.solved_tangent(c)]))
                    .chain((0..limits).map(|r| l.solved_limit(r)))
                    .collect();
                solved.sort_unstable();
                assert_eq!(solved, (0..l.solved_rows()).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn entries_are_column_major() {
        assert_eq!(at(7, 2, 3), 23);
        assert_eq!(at(7, 0, 0), 0);
    }
}
