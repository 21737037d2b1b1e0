//! The pivoting core of Lemke's method with the lexicographic minimum-ratio test
//! (Murty, "Linear Complementarity, Linear and Nonlinear Programming", ch. 2).
//!
//! The tableau of `w − M z − d z0 = q` is column-major in one flat buffer of `2n + 2`
//! columns: `[rhs | w_1..w_n (= B⁻¹) | z_1..z_n | z0]`, each padded with zero rows to
//! [`leading_dim`]`(n)` entries so the column updates run in whole SIMD vectors (groups
//! of four rows, and a last pair when `n mod 4` is 1 or 2, see [`active_len`]). The `w`
//! block is `B⁻¹` at every step, which is what the lexicographic test compares. A pivot
//! updates only the right-hand side and the `n + 1` non-basic columns (kept in a list).
//! The column of a basic variable is the unit vector of its row and is not stored: the
//! buffer holds stale values there, the lexicographic tie-break reads the basis instead,
//! and a variable's unit column is written when it leaves the basis.
//! Everything here is `#[inline(always)]` so that `primary.rs` can specialise it for each
//! small `n` (fixed trip counts) and instruction set.

use crate::certificate::MatRef;

/// Entries of the entering column at most `PIV_TOL · max(1, max_i |col_i|)` cannot pivot.
const PIV_TOL: f64 = 1e-12;
/// Ratios within `TIE_TOL · max(1, |θ|)` of the minimum count as ties (scaled problem).
/// Contact LCPs have structural ties at non-zero ratios (friction components vanishing
/// together with the normal impulse) whose computed ratios differ by round-off amplified
/// through the pivots; tighter values (1e-12 and below) let that noise break the ties
/// and send Lemke's path to spurious ray terminations.
const TIE_TOL: f64 = 1e-9;

/// Largest `n` whose entering column is copied to the stack during a pivot.
pub(crate) const MAX_FIXED: usize = 12;

/// Column stride of the tableau for problem size `n`: `n` rounded up to a multiple of 4.
pub(crate) const fn leading_dim(n: usize) -> usize {
    (n + 3) & !3
}

/// How one Lemke run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ending {
    /// `z0` left the basis: a complementary basis (still to be certified).
    Complementary,
    /// The entering column has no positive entry: a secondary ray.
    Ray,
    PivotLimit,
    /// A non-finite tableau entry.
    Breakdown,
}

/// Exact power-of-two factors between the original and the internal problem.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scales {
    /// Internal `q = q·q_inv` (internal `M = M·m_inv`).
    pub q_inv: f64,
    /// Original `z = z_int·z`, `w = w_int·w`.
    pub z: f64,
    pub w: f64,
}

impl Scales {
    /// From the internal factors `q_inv`, `m_inv` (powers of two, so the products below
    /// are exact).
    pub fn new(q_inv: f64, m_inv: f64, q_pow: f64) -> Self {
        Scales {
            q_inv,
            z: m_inv * q_pow,
            w: q_pow,
        }
    }
}

/// One-hot row masks of one group of four, as constants (loading one never waits on a
/// store): the marked lane is the one with the sign bit set.
const ONE_HOT: [[f64; 4]; 4] = [
    [-1.0, 0.0, 0.0, 0.0],
    [0.0, -1.0, 0.0, 0.0],
    [0.0, 0.0, -1.0, 0.0],
    [0.0, 0.0, 0.0, -1.0],
];

/// Whether `h` marks its row in a mask made by [`set_hot`]: a test of the sign bit alone,
/// which a vector blend reads directly (no compare per column).
#[inline(always)]
fn marked(h: f64) -> bool {
    (h.to_bits() as i64) < 0
}

/// Rows of a column that the vector code reads and writes for size `n`: `n` rounded up to
/// an even number. A column is worked on in groups of four rows and, when `n mod 4` is 1
/// or 2, a last pair: the two padding rows of such a column are never touched (on a
/// 128-bit vector unit a four-row operation costs two, so the pair halves the last
/// group's work). Rows from `n` to `active_len(n)` are computed from zero padding like the
/// others (zero unless a pivot was not finite) and enter no test; rows past it are stale
/// and never read.
#[inline(always)]
pub(crate) const fn active_len(n: usize) -> usize {
    (n + 1) & !1
}

/// Runs `$body` once per group of the first `$len` (even) rows of a column: with `$w = 4`
/// for each whole group of four, then with `$w = 2` for a last pair if `$len mod 4 = 2`;
/// `$i` is the group's first row. (`$w` is a constant, so each group is one vector
/// operation: 256 bits, or 128 for the pair.)
macro_rules! for_groups {
    ($len:expr, |$i:ident, $w:ident| $body:block) => {{
        let len: usize = $len;
        debug_assert!(len % 2 == 0);
        for g in 0..len / 4 {
            let $i = 4 * g;
            const $w: usize = 4;
            $body
        }
        if len % 4 != 0 {
            let $i = len - 2;
            const $w: usize = 2;
            $body
        }
    }};
}

/// The values a column held before a pivot update, one group at a time (see
/// [`update_column`]).
trait OldColumn {
    /// Rows `i..i + W`; `stored` is what the buffer holds there.
    fn group<const W: usize>(&self, i: usize, stored: &[f64]) -> [f64; W];
}

/// The column as stored.
struct Stored;

impl OldColumn for Stored {
    #[inline(always)]
    fn group<const W: usize>(&self, _: usize, stored: &[f64]) -> [f64; W] {
        std::array::from_fn(|k| stored[k])
    }
}

/// A unit vector's column outside the pivot row: zeros (the buffer is not read).
struct Zeros;

impl OldColumn for Zeros {
    #[inline(always)]
    fn group<const W: usize>(&self, _: usize, _: &[f64]) -> [f64; W] {
        [0.0; W]
    }
}

/// The column `s·src`, zero padded (computed, not stored first).
struct Scaled<'a> {
    s: f64,
    src: &'a [f64],
}

impl OldColumn for Scaled<'_> {
    #[inline(always)]
    fn group<const W: usize>(&self, i: usize, _: &[f64]) -> [f64; W] {
        map_group(self.src, i, |_, v| self.s * v)
    }
}

/// Which row is the pivot row, for [`update_column`].
trait Hot: Copy {
    /// Whether rows `i..i + W` are the pivot row.
    fn lanes<const W: usize>(self, i: usize) -> [bool; W];
    /// The same, for the first `len` rows only (the lanes then need no bounds check).
    fn cut(self, len: usize) -> Self;
}

/// The pivot row by its index (small `n`: the compare of a constant row-index vector with
/// `r` stays in registers, no mask goes through memory).
#[derive(Clone, Copy)]
struct HotRow(usize);

impl Hot for HotRow {
    #[inline(always)]
    fn lanes<const W: usize>(self, i: usize) -> [bool; W] {
        std::array::from_fn(|k| i + k == self.0)
    }
    #[inline(always)]
    fn cut(self, _: usize) -> Self {
        self
    }
}

/// The pivot row by a one-hot mask made by [`set_hot`] (large `n`: a loop of unknown trip
/// count reads the mask instead of comparing indices).
#[derive(Clone, Copy)]
struct HotMask<'a>(&'a [f64]);

impl Hot for HotMask<'_> {
    #[inline(always)]
    fn lanes<const W: usize>(self, i: usize) -> [bool; W] {
        let h = &self.0[i..i + W];
        std::array::from_fn(|k| marked(h[k]))
    }
    #[inline(always)]
    fn cut(self, len: usize) -> Self {
        HotMask(&self.0[..len])
    }
}

/// Pivot update of one column: `x ← x − f·y` except `x_r ← f` where `hot` (a one-hot
/// row mask, see [`set_hot`]) is marked, all in whole-group vector stores (see
/// [`for_groups`]; `x` is cut to [`active_len`]). (A scalar store into a column that the
/// next pivot reads back with vector loads stalls store-to-load forwarding.) Takes
/// `yn = −y` and adds `f·yn`, which is exactly `x − f·y` and compiles to one add per
/// vector. The old values come from `old`.
#[inline(always)]
fn update_column(x: &mut [f64], f: f64, yn: &[f64], hot: impl Hot, old: impl OldColumn) {
    let len = x.len();
    let (yn, hot) = (&yn[..len], hot.cut(len));
    for_groups!(len, |i, W| {
        let xc = &mut x[i..i + W];
        let yc = &yn[i..i + W];
        let xo: [f64; W] = old.group(i, xc);
        let hk: [bool; W] = hot.lanes(i);
        let mut v = [0.0; W];
        for k in 0..W {
            let e = xo[k] + f * yc[k];
            v[k] = if hk[k] { f } else { e };
        }
        xc.copy_from_slice(&v);
    });
}

/// [`update_column`] of the stored column `x`, with `f = x_r / p`.
#[inline(always)]
fn eliminate(x: &mut [f64], f: f64, yn: &[f64], hot: impl Hot) {
    update_column(x, f, yn, hot, Stored);
}

/// [`update_column`] of a column that was the unit vector `e_r` (not stored), so
/// `f = 1/p`: written without reading `x`.
#[inline(always)]
fn eliminate_unit(x: &mut [f64], inv: f64, yn: &[f64], hot: impl Hot) {
    update_column(x, inv, yn, hot, Zeros);
}

/// [`eliminate`] of the stored column `x` with `f = x_r · inv`, on `yn.len()` rows.
#[inline(always)]
fn eliminate_row(x: &mut [f64], r: usize, inv: f64, yn: &[f64], hot: impl Hot) {
    let x = &mut x[..yn.len()];
    let f = x[r] * inv;
    eliminate(x, f, yn, hot);
}

/// Column `c` of the tableau `tab` (`2n + 2` columns of stride `ld`), its first `la`
/// rows; `c` is the right-hand side or `1 +` a variable `< 2n + 1`, so always in range.
#[inline(always)]
fn column_mut(tab: &mut [f64], ld: usize, la: usize, c: usize) -> &mut [f64] {
    debug_assert!((c + 1) * ld <= tab.len() && la <= ld);
    // SAFETY: the callers pass `c ≤ 2n + 1` with `tab.len() = (2n + 2)·ld` and `la ≤ ld`
    // (checked in debug builds above): no bounds check per column update.
    unsafe { tab.get_unchecked_mut(c * ld..c * ld + la) }
}

/// [`update_column`] of the column `s·src` (zero padded) as if it had been stored first:
/// bit-identical, without the round trip through memory.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn eliminate_loaded(
    x: &mut [f64],
    s: f64,
    src: &[f64],
    r: usize,
    inv: f64,
    yn: &[f64],
    hot: impl Hot,
) {
    let f = (s * src[r]) * inv;
    update_column(x, f, yn, hot, Scaled { s, src });
}

/// `x ← −y` on the first `x.len()` (even) rows, in whole-group vector stores (see
/// [`eliminate`]).
#[inline(always)]
fn negate_into(x: &mut [f64], y: &[f64]) {
    let len = x.len();
    let y = &y[..len];
    for_groups!(len, |i, W| {
        let v: [f64; W] = std::array::from_fn(|k| -y[i + k]);
        x[i..i + W].copy_from_slice(&v);
    });
}

/// The one-hot mask of row `r` (see [`marked`]) on the first `x.len()` (even) rows, in
/// whole-group vector stores.
#[inline(always)]
fn set_hot(x: &mut [f64], r: usize) {
    let (gr, hot) = (r / 4, &ONE_HOT[r % 4]);
    for_groups!(x.len(), |i, W| {
        x[i..i + W].copy_from_slice(if i / 4 == gr { &hot[..W] } else { &[0.0; W] });
    });
}

/// `x ← f·src` on the first `src.len()` entries and zero on the rest of `x` (of even
/// length), in whole-group vector stores (see [`eliminate`]).
#[inline(always)]
pub(crate) fn set_padded(x: &mut [f64], f: f64, src: &[f64]) {
    for_groups!(x.len(), |i, W| {
        let v: [f64; W] = map_group(src, i, |_, s| f * s);
        x[i..i + W].copy_from_slice(&v);
    });
}

/// `x ← x − f·src` on the first `src.len()` entries and zero on the rest of `x` (of even
/// length), in whole-group vector stores (see [`eliminate`]).
#[inline(always)]
pub(crate) fn sub_scaled_padded(x: &mut [f64], f: f64, src: &[f64]) {
    for_groups!(x.len(), |i, W| {
        let xc = &mut x[i..i + W];
        let v: [f64; W] = map_group(src, i, |k, s| xc[k] - f * s);
        xc.copy_from_slice(&v);
    });
}

/// `[h(k, src[i + k])]` for `k < W`, zero past the end of `src`: whole groups without a
/// test per entry (the padded tail of a dynamic size would pay one).
#[inline(always)]
fn map_group<const W: usize>(
    src: &[f64],
    i: usize,
    mut h: impl FnMut(usize, f64) -> f64,
) -> [f64; W] {
    let mut v = [0.0; W];
    if i + W <= src.len() {
        let s = &src[i..i + W];
        for k in 0..W {
            v[k] = h(k, s[k]);
        }
    } else {
        for (k, vk) in v.iter_mut().enumerate() {
            *vk = if i + k < src.len() {
                h(k, src[i + k])
            } else {
                0.0
            };
        }
    }
    v
}

/// `1 / pow2_floor(x)`, exactly, without a division.
#[inline(always)]
pub(crate) fn inv_pow2_floor(x: f64) -> f64 {
    let e = (x.to_bits() >> 52) & 0x7ff;
    match e {
        0 | 0x7ff => 1.0,
        0x7fe => f64::from_bits(1 << 51), // 2^-1023, subnormal
        _ => f64::from_bits((0x7fe - e) << 52),
    }
}

/// The largest power of two `≤ x` (1 for zero, subnormal or non-finite `x`).
#[inline(always)]
pub(crate) fn pow2_floor(x: f64) -> f64 {
    let p = f64::from_bits(x.to_bits() & 0x7ff0_0000_0000_0000);
    if p == 0.0 || !p.is_finite() {
        1.0
    } else {
        p
    }
}

/// A `Vec<f64>` whose exposed part starts on a 64-byte boundary, so SIMD column updates
/// touch whole cache lines (the allocator only guarantees 16 bytes).
#[derive(Debug, Default)]
pub(crate) struct Aligned {
    data: Vec<f64>,
    off: usize,
}

impl Aligned {
    /// Makes at least `len` entries available (never shrinks).
    pub fn reserve(&mut self, len: usize) {
        if self.data.len() < len + 7 {
            self.data.resize(len + 7, 0.0);
        }
        self.off = (self.data.as_ptr() as usize / 8).wrapping_neg() % 8;
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.data[self.off..]
    }

    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.data[self.off..]
    }
}

impl Clone for Aligned {
    fn clone(&self) -> Self {
        let mut copy = Aligned::default();
        let len = self.data.len().saturating_sub(7);
        copy.reserve(len);
        copy.as_mut_slice()[..len].copy_from_slice(&self.as_slice()[..len]);
        copy
    }
}

/// Reusable buffers of the pivoting core, grown by [`Work::reserve`].
#[derive(Debug, Clone, Default)]
pub(crate) struct Work {
    /// `ld·(2n + 2)`, column-major.
    tab: Aligned,
    /// `n`: the basic variable of each row (`0..n` w, `n..2n` z, `2n` z0).
    basis: Vec<usize>,
    /// `n + 1`: the non-basic variables.
    nonbasic: Vec<usize>,
    /// `2n + 1`: position of each non-basic variable in `nonbasic`.
    nb_pos: Vec<usize>,
    /// `ld`: copy of the entering column.
    col: Vec<f64>,
    /// `ld`: the pivot row's one-hot mask (large `n`).
    hot: Vec<f64>,
    /// `n`: ratio-test scratch.
    ties: Vec<usize>,
    /// `n`: the covering vector of the next run.
    cover: Vec<f64>,
    /// `ld`: absolute row sums of `M`.
    row_sum: Vec<f64>,
    /// `ld`: `M z + q` scratch of the certificate.
    mz: Vec<f64>,
}

/// Disjoint views of the buffers of [`Work`] for problem size `n`, passed to the core
/// functions as separate slices (separate `&mut` arguments cannot alias, so the compiler
/// keeps values in registers and vectorises; fields reached through one struct could).
pub(crate) struct Parts<'a> {
    pub tab: &'a mut [f64],
    pub basis: &'a mut [usize],
    pub nonbasic: &'a mut [usize],
    pub nb_pos: &'a mut [usize],
    pub col: &'a mut [f64],
    pub hot: &'a mut [f64],
    pub ties: &'a mut [usize],
    pub cover: &'a mut [f64],
    pub row_sum: &'a mut [f64],
    pub mz: &'a mut [f64],
}

impl Work {
    /// The buffers cut to size `n` (after [`Work::reserve`]).
    #[inline(always)]
    pub fn parts(&mut self, n: usize) -> Parts<'_> {
        let ld = leading_dim(n);
        Parts {
            tab: &mut self.tab.as_mut_slice()[..ld * (2 * n + 2)],
            basis: &mut self.basis[..n],
            nonbasic: &mut self.nonbasic[..n + 1],
            nb_pos: &mut self.nb_pos[..2 * n + 1],
            col: &mut self.col[..ld],
            hot: &mut self.hot[..ld],
            ties: &mut self.ties[..n],
            cover: &mut self.cover[..n],
            row_sum: &mut self.row_sum[..ld],
            mz: &mut self.mz[..ld],
        }
    }

    pub fn reserve(&mut self, n: usize) {
        let ld = leading_dim(n);
        self.tab.reserve(ld * (2 * n + 2));
        self.basis.resize(n, 0);
        self.nonbasic.resize(n + 1, 0);
        self.nb_pos.resize(2 * n + 1, 0);
        self.col.resize(ld, 0.0);
        self.hot.resize(ld, 0.0);
        self.ties.resize(n, 0);
        self.cover.resize(n, 0.0);
        self.row_sum.resize(ld, 0.0);
        self.mz.resize(ld, 0.0);
    }
}

/// `‖M‖_∞`, read in place; a non-finite result means `M` has a non-finite entry (or row
/// sums overflow). `row_sum` is scratch of length `ld`, used only when `n > MAX_FIXED`.
#[inline(always)]
pub(crate) fn matrix_norm(n: usize, m: MatRef<'_>, row_sum: &mut [f64]) -> f64 {
    let ld = leading_dim(n);
    // Small n: accumulate on the stack (registers).
    let mut local = [0.0; leading_dim(MAX_FIXED)];
    let row_sum = if n <= MAX_FIXED {
        &mut local[..ld]
    } else {
        &mut row_sum[..ld]
    };
    row_sum.fill(0.0);
    let la = active_len(n);
    for j in 0..n {
        add_abs_column(&mut row_sum[..la], &m.col(j)[..n]);
    }
    norm_of_row_sums(row_sum)
}

/// `row_sum ← row_sum + |col|` entrywise (`row_sum` of even length, padded, `col` not),
/// in whole groups (see [`for_groups`]).
#[inline(always)]
pub(crate) fn add_abs_column(row_sum: &mut [f64], col: &[f64]) {
    for_groups!(row_sum.len(), |i, W| {
        let sc = &mut row_sum[i..i + W];
        let v: [f64; W] = map_group(col, i, |k, c| sc[k] + c.abs());
        sc.copy_from_slice(&v);
    });
}

/// `‖M‖_∞` from the absolute row sums of `M` (padded with zeros to a multiple of 4):
/// infinite if one of them is not finite or their sum overflows (then see
/// `primary::checked_norm`).
#[inline(always)]
pub(crate) fn norm_of_row_sums(row_sum: &[f64]) -> f64 {
    // Four lanes: independent chains. The sum exposes NaN and ∞ (max skips NaN).
    let (mut max4, mut sum4) = ([0.0_f64; 4], [0.0; 4]);
    for s4 in row_sum.chunks_exact(4) {
        for k in 0..4 {
            max4[k] = lane_max(max4[k], s4[k]);
            sum4[k] += s4[k];
        }
    }
    // (The lanes hold no NaN: plain comparisons.)
    let max2 = [lane_max(max4[0], max4[1]), lane_max(max4[2], max4[3])];
    let m_norm = lane_max(max2[0], max2[1]);
    if ((sum4[0] + sum4[1]) + (sum4[2] + sum4[3])).is_finite() {
        m_norm
    } else {
        f64::INFINITY
    }
}

/// `b` if it exceeds `a`, else `a` (so a NaN `b` is skipped).
#[inline(always)]
fn lane_max(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// Loads the right-hand side `q·q_inv` and the basis `w` of the tableau
/// `[q·q_inv | I | −M·m_inv | −d]` (`d = work.cover`); returns
/// `m_inv = 1 / pow2_floor(m_norm)`. The columns of `I` stay implicit (basic), those of
/// `−M·m_inv` are written by the first pivot ([`pivot_loop`]), that of `−d` never (`z0`
/// enters at once and stays basic until it leaves, which ends the run).
#[inline(always)]
pub(crate) fn load(n: usize, t: &mut Parts<'_>, q: &[f64], q_inv: f64, m_norm: f64) -> f64 {
    set_padded(&mut t.tab[..active_len(n)], q_inv, &q[..n]);
    for (i, b) in t.basis[..n].iter_mut().enumerate() {
        *b = i;
    }
    for (k, v) in t.nonbasic[..n + 1].iter_mut().enumerate() {
        *v = n + k;
    }
    for (v, p) in t.nb_pos[..2 * n + 1].iter_mut().enumerate() {
        *p = if v < n { usize::MAX } else { v - n };
    }
    inv_pow2_floor(m_norm)
}

/// Lemke's pivoting on the tableau set up by [`load`] (`M`, `m_inv` give the columns of
/// `z`, written by the first pivot); returns how it ended and the pivot count. The basic
/// values are left in column 0 of `work.tab`, their variables in `work.basis`.
#[inline(always)]
pub(crate) fn pivot_loop(
    n: usize,
    t: &mut Parts<'_>,
    m: MatRef<'_>,
    m_inv: f64,
    max_pivots: usize,
) -> (Ending, usize) {
    pivot_loop_slices(
        n, t.tab, t.basis, t.nonbasic, t.nb_pos, t.col, t.hot, t.ties, t.cover, m, m_inv,
        max_pivots,
    )
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn pivot_loop_slices(
    n: usize,
    tab: &mut [f64],
    basis: &mut [usize],
    nonbasic: &mut [usize],
    nb_pos: &mut [usize],
    col: &mut [f64],
    hot: &mut [f64],
    ties: &mut [usize],
    cover: &[f64],
    m: MatRef<'_>,
    m_inv: f64,
    max_pivots: usize,
) -> (Ending, usize) {
    let (ld, la) = (leading_dim(n), active_len(n));
    let z0 = 2 * n;
    let tab = &mut tab[..ld * (2 * n + 2)];
    let basis = &mut basis[..n];
    let nonbasic = &mut nonbasic[..n + 1];
    let nb_pos = &mut nb_pos[..2 * n + 1];
    // Small n: the entering column lives on the stack, where it cannot alias the tableau.
    let mut local = [0.0; leading_dim(MAX_FIXED)];
    let col = if n <= MAX_FIXED {
        &mut local[..ld]
    } else {
        &mut col[..ld]
    };
    let ties = &mut ties[..n];
    let cover = &cover[..n];
    if max_pivots == 0 {
        return (Ending::PivotLimit, 0);
    }

    // z0 enters; the row lexicographically minimising (q_i, e_i)/d_i leaves.
    let lex = Lex {
        ld,
        tab,
        basis,
        nb_pos,
    };
    let Some(r) = lex_min_ratio(n, lex, cover, 0.0, false, usize::MAX, ties) else {
        return (Ending::Breakdown, 0);
    };
    set_padded(&mut col[..la], 1.0, cover); // −(−d)
    let load_z = Some((m, m_inv));
    pivot(
        hot, n, ld, tab, basis, nonbasic, nb_pos, col, -cover[r], r, z0, load_z,
    );
    let z0_row = r;
    let mut leaving = r; // w_r
    let mut pivots = 1;

    loop {
        // The complement of the variable that just left enters.
        let entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        if pivots >= max_pivots {
            return (Ending::PivotLimit, pivots);
        }
        let c = 1 + entering;
        // The ratio test reads the entering column in place: a fresh vector copy read back
        // element by element would stall store-to-load forwarding.
        let entering_col = &tab[c * ld..c * ld + la];
        // Four independent running maxima (a single chain is latency-bound). A NaN entry
        // is skipped here, never eligible in the ratio test, and caught by the finiteness
        // checks on the pivot row and the extracted solution.
        let mut max4 = [1.0_f64; 4];
        for_groups!(la, |i, W| {
            for k in 0..W {
                let a = entering_col[i + k].abs();
                max4[k] = if a > max4[k] { a } else { max4[k] };
            }
        });
        // (The lanes hold no NaN: plain comparisons.)
        let col_max = lane_max(lane_max(max4[0], max4[1]), lane_max(max4[2], max4[3]));
        let tol = PIV_TOL * col_max;
        let lex = Lex {
            ld,
            tab,
            basis,
            nb_pos,
        };
        let ratio = lex_min_ratio(n, lex, entering_col, tol, true, z0_row, ties);
        let Some(r) = ratio else {
            return (Ending::Ray, pivots);
        };
        let p = entering_col[r];
        negate_into(&mut col[..la], entering_col);
        leaving = basis[r];
        pivot(
            hot, n, ld, tab, basis, nonbasic, nb_pos, col, p, r, entering, None,
        );
        pivots += 1;
        if !tab[r].is_finite() {
            return (Ending::Breakdown, pivots);
        }
        if r == z0_row {
            return (Ending::Complementary, pivots);
        }
    }
}

/// Writes the basic values (unscaled) into `z`, `w` (zeros elsewhere); false if one is
/// not finite.
#[inline(always)]
pub(crate) fn extract(
    n: usize,
    t: &Parts<'_>,
    scales: &Scales,
    z: &mut [f64],
    w: &mut [f64],
) -> bool {
    let (z, w) = (&mut z[..n], &mut w[..n]);
    z.fill(0.0);
    w.fill(0.0);
    // The unscaled values: a finite tableau entry can still overflow when unscaled. (A sum
    // that overflows with finite values only sends the basis to the refinement.)
    let mut sum = 0.0;
    for (&x, &v) in t.tab[..n].iter().zip(&t.basis[..n]) {
        if v < n {
            w[v] = x * scales.w;
            sum += w[v];
        } else if v < 2 * n {
            z[v - n] = x * scales.z;
            sum += z[v - n];
        }
    }
    sum.is_finite()
}

/// What the lexicographic ratio test reads: the tableau (column stride `ld`; the
/// right-hand side and `B⁻¹`) and the basis.
#[derive(Clone, Copy)]
struct Lex<'a> {
    ld: usize,
    tab: &'a [f64],
    basis: &'a [usize],
    nb_pos: &'a [usize],
}

/// Lexicographic minimum-ratio test: among rows with `col_i > tol`, the row minimising
/// `(rhs_i, B⁻¹_{i·}) / col_i` lexicographically. `prefer` (z0's row) wins a tie of the
/// first component, which ends the run. `clamp` reads round-off negative right-hand sides
/// as zero. `None`: no eligible row (the entering column is a ray).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn lex_min_ratio(
    n: usize,
    lex: Lex<'_>,
    col: &[f64],
    tol: f64,
    clamp: bool,
    prefer: usize,
    ties: &mut [usize],
) -> Option<usize> {
    let rhs = &lex.tab[..n];
    let col = &col[..n];
    // (`0 > r`, not `r ≤ 0`: one max instruction. It keeps a −0, which every use below
    // treats as +0: products with it compare alike, and `num` enters `cut` only through
    // `num + slack` and `|num|`.)
    let rhs_at = |r: f64| if clamp && 0.0 > r { 0.0 } else { r };
    // Minimum ratio num/den by cross-multiplication (no division per row); (1, 0) is +∞,
    // beaten by any eligible row.
    let mut best = usize::MAX;
    let (mut num, mut den) = (1.0, 0.0);
    for (i, (&r, &c)) in rhs.iter().zip(col).enumerate() {
        let r = rhs_at(r);
        if c > tol && r * den < num * c {
            best = i;
            num = r;
            den = c;
        }
    }
    if best == usize::MAX {
        return None;
    }
    // Row i ties when r_i/c_i ≤ θ + TIE_TOL·max(1, |θ|) with θ = num/den, i.e. (times
    // c_i·den > 0) r_i·den ≤ (num + slack)·c_i.
    // (`den > tol ≥ 0` is not NaN: a plain comparison.)
    let slack = TIE_TOL * lane_max(den, num.abs());
    let cut = num + slack;
    if prefer < n && col[prefer] > tol && rhs_at(rhs[prefer]) * den <= cut * col[prefer] {
        return Some(prefer);
    }
    let mut count = 0;
    for (i, (&r, &c)) in rhs.iter().zip(col).enumerate() {
        if c > tol && rhs_at(r) * den <= cut * c {
            ties[count] = i;
            count += 1;
        }
    }
    if count <= 1 {
        return Some(best);
    }
    let Lex {
        ld,
        tab,
        basis,
        nb_pos,
    } = lex;
    Some(break_ties(
        n,
        ld,
        tab,
        basis,
        nb_pos,
        col,
        &mut ties[..count],
    ))
}

/// Lexicographic tie-break on the rows of `B⁻¹` (the w-columns), column by column; the
/// rows of `B⁻¹` are independent, so one row remains (up to round-off). The column of a
/// basic `w_k` is the unit vector of its row (not stored).
#[cold]
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn break_ties(
    n: usize,
    ld: usize,
    tab: &[f64],
    basis: &[usize],
    nb_pos: &[usize],
    col: &[f64],
    ties: &mut [usize],
) -> usize {
    let mut count = ties.len();
    for k in 0..n {
        if nb_pos[k] == usize::MAX {
            // `w_k` is basic: column `k` of B⁻¹ is `e_row` (not stored), so every ratio is 0
            // but `1/col_row` if its row ties; the minimum is 0 and the cut `TIE_TOL`.
            if let Some(t) = ties[..count].iter().position(|&i| basis[i] == k) {
                if 1.0 / col[ties[t]] > TIE_TOL {
                    ties.copy_within(t + 1..count, t);
                    count -= 1;
                }
            }
        } else {
            let bk = &tab[(1 + k) * ld..(2 + k) * ld];
            let vmin = ties[..count]
                .iter()
                .fold(f64::INFINITY, |a, &i| a.min(bk[i] / col[i]));
            let cut = vmin + TIE_TOL * vmin.abs().max(1.0);
            let mut kept = 0;
            for t in 0..count {
                let i = ties[t];
                if bk[i] / col[i] <= cut {
                    ties[kept] = i;
                    kept += 1;
                }
            }
            count = kept.max(1);
        }
        if count == 1 {
            break;
        }
    }
    ties[0]
}

/// Pivots on row `r` with `entering` (its column negated in `col`, `p = −col[r]`): the row's
/// basic variable leaves. Updates the right-hand side and the non-basic columns; the
/// leaving variable's column, the unit vector `e_r` it stood for (not stored), is written
/// directly; the entering column becomes implicit (basic).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn pivot(
    hot_buf: &mut [f64],
    n: usize,
    ld: usize,
    tab: &mut [f64],
    basis: &mut [usize],
    nonbasic: &mut [usize],
    nb_pos: &mut [usize],
    col: &[f64],
    p: f64,
    r: usize,
    entering: usize,
    load_z: Option<(MatRef<'_>, f64)>,
) {
    let leaving = basis[r];
    basis[r] = entering;
    let slot = nb_pos[entering];
    nonbasic[slot] = leaving;
    nb_pos[leaving] = slot;
    nb_pos[entering] = usize::MAX;

    let la = active_len(n);
    let col = &col[..la];
    let inv = 1.0 / p;
    let tab = &mut tab[..ld * (2 * n + 2)];
    let nonbasic = &nonbasic[..];
    if n <= MAX_FIXED {
        pivot_updates(
            n,
            ld,
            tab,
            nonbasic,
            slot,
            leaving,
            col,
            r,
            inv,
            load_z,
            HotRow(r),
        );
    } else {
        let hot = &mut hot_buf[..la];
        set_hot(hot, r);
        let hot = &*hot;
        let hot = HotMask(hot);
        pivot_updates(
            n, ld, tab, nonbasic, slot, leaving, col, r, inv, load_z, hot,
        );
    }
}

/// The column updates of [`pivot`]: the right-hand side, the non-basic columns (those of z
/// computed from `M` at the first pivot) and the leaving variable's column.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn pivot_updates(
    n: usize,
    ld: usize,
    tab: &mut [f64],
    nonbasic: &[usize],
    slot: usize,
    leaving: usize,
    col: &[f64],
    r: usize,
    inv: f64,
    load_z: Option<(MatRef<'_>, f64)>,
    hot: impl Hot,
) {
    let la = active_len(n);
    eliminate_row(&mut tab[..la], r, inv, col, hot);
    match load_z {
        // First pivot (z0 enters, nonbasic = [z_1..z_n, w_r]): the columns of z, −M·m_inv,
        // are computed from M and updated in one pass instead of loaded, then updated.
        Some((m, m_inv)) => {
            for (j, &v) in nonbasic[..slot].iter().enumerate() {
                debug_assert_eq!(v, n + j);
                let c = 1 + v;
                let src = &m.col(j)[..n];
                eliminate_loaded(&mut tab[c * ld..c * ld + la], -m_inv, src, r, inv, col, hot);
            }
        }
        None => {
            for &v in &nonbasic[..slot] {
                eliminate_row(column_mut(tab, ld, la, 1 + v), r, inv, col, hot);
            }
            for &v in &nonbasic[slot + 1..] {
                eliminate_row(column_mut(tab, ld, la, 1 + v), r, inv, col, hot);
            }
        }
    }
    let c = 1 + leaving;
    eliminate_unit(&mut tab[c * ld..c * ld + la], inv, col, hot);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `pow2_floor` is the largest power of two not above `|x|` (1 for zero, subnormal and
    /// non-finite `x`), and `inv_pow2_floor` its exact reciprocal, over the whole range.
    #[test]
    fn powers_of_two_below_a_number_and_their_reciprocals() {
        for (x, p) in [
            (1.0, 1.0),
            (3.0, 2.0),
            (0.75, 0.5),
            (1e-300, 2f64.powi(-997)),
            (f64::MIN_POSITIVE, f64::MIN_POSITIVE),
            (f64::MAX, 2f64.powi(1023)),
            (-6.0, 4.0),
        ] {
            assert_eq!(pow2_floor(x), p, "{x:e}");
            assert_eq!(inv_pow2_floor(x) * p.abs(), 1.0, "{x:e}");
        }
        // 2^1023 has a subnormal reciprocal.
        assert_eq!(inv_pow2_floor(1.5e308), 2f64.powi(-1023));
        for x in [0.0, 5e-324, 1e-310, f64::INFINITY, f64::NAN] {
            assert_eq!((pow2_floor(x), inv_pow2_floor(x)), (1.0, 1.0), "{x:e}");
        }
    }

    /// The exposed part of an [`Aligned`] starts on a 64-byte boundary and holds what was
    /// reserved, also in a clone.
    #[test]
    fn aligned_buffers_start_on_a_cache_line() {
        let mut a = Aligned::default();
        for len in [1, 5, 8, 100, 3, 1000] {
            a.reserve(len);
            assert!(a.as_slice().len() >= len);
            assert_eq!(a.as_slice().as_ptr() as usize % 64, 0, "len {len}");
            assert_eq!(a.as_mut_slice().as_ptr() as usize % 64, 0);
        }
        a.as_mut_slice()[..3].copy_from_slice(&[1.0, 2.0, 3.0]);
        let b = a.clone();
        assert_eq!(b.as_slice()[..3], [1.0, 2.0, 3.0]);
        assert_eq!(b.as_slice().as_ptr() as usize % 64, 0);
        assert!(b.as_slice().len() >= 1000);
    }

    /// `‖M‖_∞` is the largest row sum, in whichever lane it sits; a non-finite row sum,
    /// or row sums whose total overflows, give +∞ (the caller's sign of a bad matrix).
    #[test]
    fn the_norm_of_row_sums_is_their_maximum_or_infinite() {
        let mut sums = [0.0; 12];
        for top in 0..12 {
            for (i, s) in sums.iter_mut().enumerate() {
                *s = 1.0 + 0.25 * i as f64 * (i != top) as u8 as f64 / 12.0;
            }
            sums[top] = 7.5;
            assert_eq!(norm_of_row_sums(&sums), 7.5, "largest in row {top}");
        }
        for bad in [f64::INFINITY, f64::NAN] {
            for at in 0..8 {
                let mut sums = [1.0; 8];
                sums[at] = bad;
                assert_eq!(norm_of_row_sums(&sums), f64::INFINITY, "{bad} in row {at}");
            }
        }
        // Finite row sums whose total overflows: in one lane, in two lanes of one pair,
        // in the two pairs.
        let big = 1e308;
        for sums in [
            [big, 0.0, 0.0, 0.0, big, 0.0, 0.0, 0.0],
            [big, big, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [big, 0.0, big, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, big, 0.0, big, 0.0, 0.0, 0.0, 0.0],
        ] {
            assert_eq!(norm_of_row_sums(&sums), f64::INFINITY, "{sums:?}");
        }
        // Large lanes whose products would overflow but whose total does not.
        let sums = [1e200, 0.0, 1e200, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(norm_of_row_sums(&sums), 1e200);
        assert_eq!(norm_of_row_sums(&[0.0; 4]), 0.0);
    }

    /// `load` writes the scaled right-hand side and the starting basis (every `w` basic,
    /// every `z` and `z0` non-basic, in order), and returns the reciprocal power of two of
    /// the norm.
    #[test]
    fn load_sets_the_starting_tableau() {
        for n in [1, 2, 3, 5, 8, 13] {
            let mut work = Work::default();
            work.reserve(n);
            let mut t = work.parts(n);
            t.basis.fill(usize::MAX);
            t.nonbasic.fill(usize::MAX);
            t.nb_pos.fill(7);
            let q: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
            assert_eq!(load(n, &mut t, &q, 0.25, 12.0), 0.125);
            for (i, q) in q.iter().enumerate() {
                assert_eq!(t.tab[i], 0.25 * q);
                assert_eq!(t.basis[i], i);
                assert_eq!(t.nb_pos[i], usize::MAX, "w_{i} is basic");
            }
            for k in 0..=n {
                assert_eq!(t.nonbasic[k], n + k);
                assert_eq!(t.nb_pos[n + k], k);
            }
        }
    }

    /// `extract` unscales the basic values into `w` and `z` by their own factors, leaves
    /// the non-basic ones (and `z0`) at zero, and flags values that overflow when unscaled
    /// or whose total does.
    #[test]
    fn extract_unscales_the_basic_values_and_flags_overflow() {
        let n = 3;
        let mut work = Work::default();
        work.reserve(n);
        let t = work.parts(n);
        // Row 0: z_2; row 1: w_0; row 2: z0 (its value belongs to neither).
        t.basis.copy_from_slice(&[n + 2, 0, 2 * n]);
        t.tab[..n].copy_from_slice(&[3.0, 5.0, 7.0]);
        let scales = Scales::new(1.0, 0.5, 4.0);
        let (mut z, mut w) = ([9.0; 3], [9.0; 3]);
        assert!(extract(n, &t, &scales, &mut z, &mut w));
        assert_eq!(z, [0.0, 0.0, 3.0 * 0.5 * 4.0]);
        assert_eq!(w, [5.0 * 4.0, 0.0, 0.0]);
        // Finite in the tableau, infinite unscaled.
        t.tab[..n].copy_from_slice(&[3.0, 1e308, 7.0]);
        assert!(!extract(n, &t, &scales, &mut z, &mut w));
        // Each finite, their total not.
        let unit = Scales::new(1.0, 1.0, 1.0);
        t.basis.copy_from_slice(&[n, 1, 0]);
        t.tab[..n].copy_from_slice(&[1e308, 1e308, 1.0]);
        assert!(!extract(n, &t, &unit, &mut z, &mut w));
        assert_eq!((z[0], w[1], w[0]), (1e308, 1e308, 1.0));
    }

    /// The ratio test on the starting tableau (`B⁻¹ = I`): the row of the smallest ratio
    /// `rhs_i / col_i` among entries above the pivot tolerance; a ratio a hair above the
    /// minimum is no tie, also where the ratios are tiny; an exact tie goes to the preferred
    /// row (z0's) if it is among them, else to the lexicographic rule, which on `B⁻¹ = I`
    /// keeps the row whose basic `w` has the largest index; with `clamp`, negative
    /// right-hand sides count as zero (so they tie).
    #[test]
    fn the_ratio_test_takes_the_smallest_ratio_and_breaks_exact_ties() {
        let n = 3;
        let ld = leading_dim(n);
        let mut work = Work::default();
        work.reserve(n);
        let mut t = work.parts(n);
        load(n, &mut t, &[0.0; 3], 1.0, 1.0);
        let mut ties = [0; 3];
        let mut test = |rhs: [f64; 3], col: [f64; 3], tol: f64, clamp: bool, prefer: usize| {
            t.tab[..n].copy_from_slice(&rhs);
            let lex = Lex {
                ld,
                tab: t.tab,
                basis: t.basis,
                nb_pos: t.nb_pos,
            };
            lex_min_ratio(n, lex, &col, tol, clamp, prefer, &mut ties)
        };
        let mut ratio = |rhs, col, tol| test(rhs, col, tol, false, usize::MAX);
        // Ratios 1, 1 + 1e-3, 2: row 0.
        assert_eq!(ratio([1.0, 1.001, 4.0], [1.0, 1.0, 2.0], 0.0), Some(0));
        assert_eq!(ratio([1.001, 1.0, 4.0], [1.0, 1.0, 2.0], 0.0), Some(1));
        // Ratios 1, 2, 5 from entries of 1e-12: no tie (the tie tolerance scales with them).
        assert_eq!(
            ratio([1e-12, 2e-12, 5.0], [1e-12, 1e-12, 1.0], 0.0),
            Some(0)
        );
        // An entry equal to the tolerance cannot pivot, one above it can.
        assert_eq!(ratio([0.0, 1.0, 2.0], [0.5, 1.0, 1.0], 0.5), Some(1));
        assert_eq!(ratio([0.0, 1.0, 1.0], [0.5, 0.5, 0.5], 0.5), None);
        assert_eq!(ratio([0.0, 1.0, 1.0], [0.6, 0.5, 0.5], 0.5), Some(0));
        // Exact ties at ratio 1: the lexicographic rule drops rows 0, then 1.
        assert_eq!(ratio([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], 0.0), Some(2));
        assert_eq!(ratio([1.0, 2.0, 5.0], [1.0, 2.0, 3.0], 0.0), Some(1));
        // A row at the tolerance is no tie either, nor a preferred row there.
        assert_eq!(ratio([0.0, 0.0, 1.0], [1.0, 0.5, 1.0], 0.5), Some(0));
        assert_eq!(
            test([1.0, 0.0, 2.0], [1.0, 0.5, 1.0], 0.5, false, 1),
            Some(0)
        );
        // The preferred row wins a tie it is in, and only then.
        assert_eq!(
            test([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], 0.0, false, 1),
            Some(1)
        );
        assert_eq!(
            test([1.0, 2.5, 3.0], [1.0, 2.0, 3.0], 0.0, false, 1),
            Some(2)
        );
        // Negative right-hand sides: the smallest ratio, or, clamped, a tie at zero.
        assert_eq!(
            test([-1.0, -0.5, 1.0], [1.0, 1.0, 1.0], 0.0, false, usize::MAX),
            Some(0)
        );
        assert_eq!(
            test([-1.0, -0.5, 1.0], [1.0, 1.0, 1.0], 0.0, true, usize::MAX),
            Some(1)
        );
    }
}
