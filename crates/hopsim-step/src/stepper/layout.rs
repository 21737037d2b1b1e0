//! Where each unknown and each right-hand side of a step sits: the contact LCP of
//! docs/physics.md §4.3 (with the joint stops of §7.2 and the joints' dry friction of §7.5),
//! its frictionless fallback (§4.5), and
//! the rows solved with the mass matrix's factor. Every function that writes or reads one
//! of them goes through [`Layout`], so the offsets are written down once.

/// The sizes of one step's problem: `k` closed contacts, `l` closed joint stops and `f`
/// joints with dry friction.
///
/// The frictional LCP has `3k + l + 2f` rows, in blocks
///
/// | rows | unknown `z` | `w` |
/// |---|---|---|
/// | [`Layout::normal`] `c` | `Λ_N` | `ξ_N` |
/// | [`Layout::sliding`] `c` | `Λ_R = Λ_T + μΛ_N` | `ξ_R = ξ_T + ξ_L` |
/// | [`Layout::cone`] `c` | `ξ_L / s` | `s Λ_L` (`s`: the cone rows' scale) |
/// | [`Layout::limit`] `r` | `Λ_J` | `ξ_J` |
/// | [`Layout::joint_sliding`] `j` | `Λ_F + β` | `ξ_F + ξ_D` |
/// | [`Layout::joint_cone`] `j` | `ξ_D / s` | `s (β − Λ_F)` |
///
/// (`β`: the joint's bound on its friction percussion `Λ_F`.) The frictionless fallback
/// keeps the normal rows and the stops: `k + l` rows ([`Layout::fallback_limit`]). The rows
/// solved with `M`'s factor are `h Δt + impulses`, then `w_N` and `w_T` of each contact,
/// then `w_J` of each stop, then `w_F` of each joint with dry friction
/// ([`Layout::solved_normal`], …), `1 + 2k + l + f` rows of length `n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// Closed contacts `k` (terrain and body–body).
    pub contacts: usize,
    /// Closed joint stops `l`.
    pub limits: usize,
    /// Joints with dry friction `f`.
    pub frictions: usize,
}

impl Layout {
    /// Rows of the frictional LCP: `3k + l + 2f`.
    #[inline(always)]
    pub fn size(&self) -> usize {
        3 * self.contacts + self.limits + 2 * self.frictions
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

    /// Joint `j`'s dry-friction row: `ξ_F + ξ_D ⟂ Λ_F + β`.
    #[inline(always)]
    pub fn joint_sliding(&self, j: usize) -> usize {
        3 * self.contacts + self.limits + j
    }

    /// Joint `j`'s friction-bound row: `s (β − Λ_F) ⟂ ξ_D / s`.
    #[inline(always)]
    pub fn joint_cone(&self, j: usize) -> usize {
        3 * self.contacts + self.limits + self.frictions + j
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

    /// Rows solved with `M`'s factor: `1 + 2k + l + f`.
    #[inline(always)]
    pub fn solved_rows(&self) -> usize {
        1 + 2 * self.contacts + self.limits + self.frictions
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

    /// The solved row of joint `j`'s `w_F`.
    #[inline(always)]
    pub fn solved_friction(&self, j: usize) -> usize {
        1 + 2 * self.contacts + self.limits + j
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
            for (limits, frictions) in (0..4).flat_map(|l| (0..3).map(move |f| (l, f))) {
                let l = Layout {
                    contacts,
                    limits,
                    frictions,
                };
                let mut lcp: Vec<usize> = (0..contacts)
                    .flat_map(|c| [l.normal(c), l.sliding(c), l.cone(c)])
                    .chain((0..limits).map(|r| l.limit(r)))
                    .chain((0..frictions).flat_map(|j| [l.joint_sliding(j), l.joint_cone(j)]))
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
                    .chain((0..frictions).map(|j| l.solved_friction(j)))
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
